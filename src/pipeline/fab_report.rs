//! What a fabrication run tells the maker: the figures of its jobs, `report.json`'s sheet
//! section, the summary printed by `fab` and on the PDF, and the PDF itself.

use super::fab_options::{FabOptions, TILE_OVERLAP_MM};
use super::report_json::{MediaReport, PlotterReport, SheetReport, TwoSidedReport, UnscoredCrease};
use crate::fab::{Media, Sheet, ShortFolds, Toolpath};
use crate::machine::{Machine, Protocol};
use std::collections::BTreeMap;

/// One fabrication run's results, as the report and the summary describe them.
pub(super) struct Run<'a> {
    pub machine: &'a Machine,
    pub options: &'a FabOptions,
    pub sheet: &'a Sheet,
    /// The machine's margin (the layout may have kept a registration band inside it).
    pub margin: f64,
    /// The sheet was larger than the media and is tiled over PDF pages.
    pub tiled: bool,
    /// The front job, then the back job if any.
    pub jobs: Vec<&'a Toolpath>,
    /// The cutter's job files written (none for a laser or a tiled sheet).
    pub jobs_written: &'a [(String, Vec<u8>)],
    /// A two-sided job's steps for the maker, else empty.
    pub steps: &'a [String],
    /// Sheet lines of folds too short to score, and what the profile gave them.
    pub unscored: &'a [usize],
    pub short_folds: ShortFolds,
    pub isometry_error: f64,
}

/// Lengths and times of a run's jobs.
pub(super) struct Figures<'a> {
    line_length: BTreeMap<&'a str, f64>,
    cut_length: BTreeMap<&'a str, f64>,
    travel: f64,
    job_bytes: usize,
    motion: f64,
    transfer: f64,
    /// What plotting takes: the motion, or the transfer over the serial line if slower.
    estimate: f64,
}

impl<'a> Run<'a> {
    /// Cut and scored lengths, pen-up travel, and the time the machine takes.
    pub fn figures(&self) -> Figures<'a> {
        let mut line_length: BTreeMap<&str, f64> = BTreeMap::new();
        for l in &self.sheet.lines {
            *line_length.entry(l.kind.name()).or_default() += l.length();
        }
        let mut cut_length: BTreeMap<&str, f64> = BTreeMap::new();
        let mut motion = 0.0;
        let mut travel = 0.0;
        for job in &self.jobs {
            for (k, len) in job.cut_length() {
                *cut_length.entry(k.name()).or_default() += len;
                motion += len / self.machine.speed(k);
            }
            travel += job.travel();
        }
        motion += travel / self.machine.pen_up_speed_mm_s;
        let job_bytes: usize = self.jobs_written.iter().map(|(_, b)| b.len()).sum();
        let transfer = self
            .machine
            .serial_line()
            .map_or(0.0, |l| job_bytes as f64 / l.bytes_per_second());
        Figures {
            line_length,
            cut_length,
            travel,
            job_bytes,
            motion,
            transfer,
            estimate: motion.max(transfer),
        }
    }

    /// `report.json`'s `sheet` section.
    pub fn sheet_report(&self, f: &Figures) -> SheetReport {
        let (machine, sheet, media) = (self.machine, self.sheet, &self.sheet.media);
        let marks = |centres: [crate::mesh::Vec2; 3]| centres.map(|p| [p.x, p.y]);
        let names = |m: &BTreeMap<&str, f64>| m.iter().map(|(k, v)| (k.to_string(), *v)).collect();
        SheetReport {
            machine: machine.name.clone(),
            material: machine.material.clone(),
            // What `crease plot` needs to stream this job to the machine it was made for.
            plotter: machine
                .serial_line()
                .filter(|_| !self.jobs_written.is_empty())
                .map(|l| PlotterReport {
                    protocol: machine.protocol,
                    connection: machine.connection,
                    baud: l.baud,
                    flow_control: l.flow_control,
                    buffer_bytes: l.buffer_bytes,
                }),
            media: MediaReport {
                name: media.name.clone(),
                width_mm: media.width,
                height_mm: media.height,
            },
            size_mm: sheet.size,
            scale: sheet.scale,
            rotation_deg: sheet.rotation.to_degrees(),
            line_length_mm: names(&f.line_length),
            cut_length_mm: names(&f.cut_length),
            strokes: self.jobs.iter().map(|j| j.strokes.len()).sum(),
            pen_up_travel_mm: f.travel,
            job_files: Some(self.jobs_written.iter().map(|(n, _)| n.clone()).collect()),
            job_bytes: f.job_bytes,
            estimated_plot_time_s: f.estimate,
            motion_time_s: f.motion,
            transfer_time_s: f.transfer,
            isometry_max_relative_error: self.isometry_error,
            mountains_from_back: self.options.mountains_from_back,
            // How the two sides register: the crosses each job cuts first, and what to do.
            two_sided: (!self.steps.is_empty()).then(|| TwoSidedReport {
                front_marks_mm: marks(crate::fab::registration::front_centres(media, self.margin)),
                back_marks_mm: marks(crate::fab::registration::back_centres(media, self.margin)),
                steps: self.steps.to_vec(),
            }),
            tiled: self.tiled,
            // Folds with no room for a dash (shorter than the clearance the junctions at
            // their ends need), and what the profile's `short_folds` gave them: with
            // "nothing" the maker has to score these by hand.
            unscored_creases: self
                .unscored
                .iter()
                .map(|&i| {
                    let l = &sheet.lines[i];
                    UnscoredCrease {
                        given: self.short_folds.name().to_string(),
                        kind: l.kind.name().to_string(),
                        length_mm: l.length(),
                        from_mm: [l.a.x, l.a.y],
                        to_mm: [l.b.x, l.b.y],
                    }
                })
                .collect(),
        }
    }

    /// The summary's line on the cutter job: its size and time, or why there is none.
    pub fn job_line(&self, f: &Figures) -> String {
        let cut_mm: f64 = f.cut_length.values().sum();
        if self.tiled {
            return format!(
                "cut {cut_mm:.0} mm; tiled over pages to print and cut by hand, so no cutter job"
            );
        }
        let (travel_mm, seconds) = (f.travel, f.estimate);
        if self.jobs_written.is_empty() {
            let (files, software) = match self.machine.protocol {
                Protocol::Svg => ("sheet.svg", "the cutter's design software"),
                Protocol::Dxf | Protocol::Hpgl | Protocol::Gpgl => {
                    ("sheet.dxf or sheet.svg", "the laser's software")
                }
            };
            let software = self.machine.software.as_deref().unwrap_or(software);
            return format!(
                "cut {cut_mm:.0} mm, pen-up travel {travel_mm:.0} mm, about {seconds:.0} s of motion; no cutter job: {files} goes to {software}"
            );
        }
        let names: Vec<&str> = self.jobs_written.iter().map(|(n, _)| n.as_str()).collect();
        format!(
            "cut {cut_mm:.0} mm, pen-up travel {travel_mm:.0} mm, {} bytes in {}, about {seconds:.0} s to plot",
            f.job_bytes,
            names.join(" and ")
        )
    }

    /// The note naming folds too short to score, if there are any, and what they got.
    pub fn unscored_warning(&self) -> Option<String> {
        if self.unscored.is_empty() {
            return None;
        }
        let lines = &self.sheet.lines;
        let lengths: Vec<String> = self
            .unscored
            .iter()
            .map(|&i| format!("{} {:.1} mm", lines[i].kind.name(), lines[i].length()))
            .collect();
        let what = match self.short_folds {
            ShortFolds::Nothing => "crease by hand".to_string(),
            other => format!("given {} (the profile's short_folds)", other.name()),
        };
        Some(format!(
            "{} fold(s) too short to score, {what}: {} (report.json has their ends)",
            self.unscored.len(),
            lengths.join(", ")
        ))
    }

    /// The lines under the PDF's title: machine, media and size, the job, and the notes.
    pub fn summary(
        &self,
        verdict: &crate::fab::Verdict,
        job_line: &str,
        warnings: &[String],
    ) -> Vec<String> {
        let (sheet, media) = (self.sheet, &self.sheet.media);
        let mut summary = vec![
            format!(
                "{} on {} ({:.0} x {:.0} mm), pattern {:.1} x {:.1} mm at scale {:.3}; verification {}",
                self.machine.name,
                media.name,
                media.width,
                media.height,
                sheet.size[0],
                sheet.size[1],
                sheet.scale,
                match verdict {
                    crate::fab::Verdict::Pass => "passed".to_string(),
                    other => format!("{} (forced)", other.word()),
                }
            ),
            job_line.to_string(),
        ];
        if !self.steps.is_empty() {
            summary.push(
                "two-sided: the front job first, then turn the sheet over left to right; page 2 says how".into(),
            );
        }
        summary.extend(warnings.iter().cloned());
        summary
    }

    /// How the template of a sheet that fits its media is tiled for a home printer
    /// ([`crate::output::pdf::home_tiles`]): not for a two-sided job, whose template is
    /// its page of steps. The paper, the tiles' margin and the pages.
    pub fn home_tiles(&self) -> Option<(Media, f64, usize)> {
        (!self.tiled && self.steps.is_empty())
            .then(|| crate::output::pdf::home_tiles(self.sheet))
            .flatten()
    }

    /// The printable template: tiled over `page`s (or over A4 or Letter when the media is
    /// no paper a home printer takes, [`crate::output::pdf::home_paper_for`]); else the
    /// page to fold by (and for a two-sided job the page of steps), then the front job as
    /// it is cut.
    pub fn pdf(
        &self,
        page: &Media,
        title: &str,
        summary: &[String],
        guide: Option<&crate::output::pdf::FoldingGuide>,
    ) -> Vec<u8> {
        let sheet = self.sheet;
        let template = crate::output::pdf::Template {
            title,
            summary,
            flat: !self.options.hide_flat,
            guide,
        };
        let tiles = if self.tiled {
            Some((page.clone(), sheet.margin))
        } else {
            self.home_tiles().map(|(paper, margin, _)| (paper, margin))
        };
        if let Some((page, margin)) = tiles {
            crate::output::pdf::to_bytes_tiled(sheet, &page, margin, TILE_OVERLAP_MM, &template)
        } else if !self.steps.is_empty() {
            let marks = crate::fab::registration::front_centres(&sheet.media, self.margin);
            crate::output::pdf::to_bytes_two_sided(
                sheet,
                &template,
                &marks,
                self.steps,
                self.jobs.first().copied(),
            )
        } else {
            crate::output::pdf::to_bytes(sheet, &template, self.jobs.first().copied())
        }
    }
}

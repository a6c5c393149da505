//! Fabrication: verify → unfold → lay out → score → route → SVG, PDF, HP-GL, report.

use super::fab_options::{FabOptions, TILE_OVERLAP_MM};
use super::fab_report::Run;
use super::tube::TubeStrip;
use crate::fab::{Advice, FabOption};
use crate::geometry::unfold::{crease_pattern_of, PatternFrom};
use crate::mesh::Mesh;
use std::collections::BTreeMap;

/// Everything a fabrication run produced, ready to write.
pub struct FabOutput {
    /// File name and bytes, in writing order.
    pub files: Files,
    /// The report written as report.json.
    pub report: super::FabReport,
    /// The summary's line on the cutter job (as on the PDF): its size and time, or why
    /// there is none.
    pub job_line: String,
    /// What the maker must do by hand (as on the PDF), e.g. folds too short to score.
    pub warnings: Vec<String>,
    /// How the template is printed when its media is no paper a home printer takes (a
    /// cutting mat): over A4 or Letter pages ([`crate::output::pdf::home_paper_for`]).
    pub template_note: Option<String>,
    /// Whether sheet.pdf ends with the folding guide, or why not; none when the design
    /// has no 3D form or the guide was turned off.
    pub guide_note: Option<String>,
    /// For a two-sided job, what the maker does in order: which job first, how to turn
    /// the sheet, how to check the registration (as on the PDF's second page).
    pub steps: Vec<String>,
    /// What the maker does in the machine's own software (the profile's `software` and
    /// `steps`), if the profile says.
    pub next_steps: Option<NextSteps>,
    /// The verification report.
    pub verification: crate::fab::Report,
    /// The placed sheet.
    pub sheet: crate::fab::Sheet,
    /// The front job's toolpath.
    pub toolpath: crate::fab::Toolpath,
    /// The mirrored back job, if asked for.
    pub back: Option<crate::fab::Toolpath>,
    /// Largest relative edge-length difference between the sheet and the 3D design.
    pub isometry_error: f64,
}

/// The steps a machine's profile gives for its own software.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NextSteps {
    /// The software the files go to.
    pub software: String,
    /// What to do there, in order.
    pub steps: Vec<String>,
}

/// Files of a run, name and bytes, in writing order.
pub type Files = Vec<(String, Vec<u8>)>;

/// Why fabrication stopped: the design fails verification, does not fit, overlaps itself.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Rejected(pub Advice);

/// Verify → unfold → lay out → score → route → SVG, PDF, HP-GL and a report (§ the
/// fabrication half of the brief). Nothing is written here; see [`crate::io::write_all_atomic`].
pub fn fabricate(
    mesh: &Mesh,
    machine: &crate::machine::Machine,
    options: &FabOptions,
) -> Result<FabOutput, FabError> {
    use crate::fab::{verify, Tolerances};
    let verification = verify(mesh, None, Tolerances::default());
    fabricate_verified(mesh, verification, machine, options)
}

/// [`fabricate`] with the design's verification already done (it depends on the design
/// alone, so one report serves runs on several machines or media).
pub fn fabricate_verified(
    mesh: &Mesh,
    verification: crate::fab::Report,
    machine: &crate::machine::Machine,
    options: &FabOptions,
) -> Result<FabOutput, FabError> {
    use crate::fab::{score_lines, Media};
    let sizing = sizing_of(options)?;
    if !verification.pass() && !options.force {
        let verdict = verification.verdict();
        let what = if matches!(verdict, crate::fab::Verdict::Undecided { .. }) {
            "verification could not decide the design"
        } else {
            "the design fails verification"
        };
        return Err(FabError::Rejected(Rejected(
            Advice::text(format!("{what} (use "))
                .option(FabOption::Force)
                .then(format!(" to cut it anyway):\n{verification}")),
        )));
    }
    // A tube is made from the strip it is cut open to, with a glue tab (issue 31).
    let tube = tube_of(mesh, options)?;
    let mesh = tube.as_ref().map_or(mesh, |t| &t.strip.sheet);
    let (flat, isometry_error) = flatten(mesh)?;
    let page = match &options.media {
        Some(m) => m.clone(),
        None => Media::parse(&machine.media).map_err(FabError::input)?,
    };
    let margin = options.margin.unwrap_or(machine.margin_mm);
    let print = print_layout(machine, options)?;
    let placing = Placing {
        print: print.as_ref(),
        page: &page,
        margin,
        sizing,
        options,
    };
    let (sheet, tiled) = sheet_of(mesh, &flat, tube.as_ref(), &placing)?;
    // After the layout, whose refusal (media too small) is cheap: on a face of thousands
    // of corners this check is the slow part.
    crate::geometry::unfold::check_overlap(mesh.faces(), &flat)
        .map_err(|e| FabError::rejected(e.to_string()))?;
    let seam = tube.as_ref().map(|t| t.report(&sheet.vertices));
    check_cuttable(&sheet, machine)?;
    let settings = machine.score_settings();
    let (strokes, unscored) = score_lines(&sheet, &settings);
    check_stroke_count(strokes.len())?;
    let tools = machine.hpgl_settings().tools;
    // Two-sided jobs register by crosses, unless tiled (no machine takes the sheet).
    let registered = options.mountains_from_back && !tiled;
    let (toolpath, back) = sides(strokes, &sheet.media, margin, &tools, options, registered);
    // A tiled sheet is larger than the media: a cutter cannot take it, only pages print.
    let jobs_written = if tiled {
        Vec::new()
    } else {
        let frame = print.as_ref().and_then(|p| p.frame.as_ref());
        cutter_jobs(machine, &toolpath, back.as_ref(), frame)?
    };
    let steps = two_sided_steps(registered, &jobs_written);
    let mut files = sheet_files(&toolpath, back.as_ref(), &jobs_written, svg_layers(machine));
    if print.as_ref().map(|p| p.family) == Some(crate::fab::print_and_cut::MarkFamily::Cricut) {
        // Design Space's print-then-cut file: the image to print with the cut and scores.
        files[0].1 = crate::output::svg::print_then_cut_to_string(
            &toolpath,
            &sheet,
            mesh.faces(),
            options.print_fill,
        )
        .into_bytes();
    }
    files.extend(pattern_files(mesh, &sheet)?);
    let run = Run {
        machine,
        options,
        sheet: &sheet,
        margin,
        tiled,
        jobs: std::iter::once(&toolpath).chain(back.as_ref()).collect(),
        jobs_written: &jobs_written,
        steps: &steps,
        unscored: &unscored,
        short_folds: settings.short_folds,
        isometry_error,
    };
    let (pictures, mut previews) = preview_files(mesh, &toolpath)?;
    files.extend(pictures);
    let motion = super::guide::run_motion(mesh, options)?;
    files.extend(super::guide::motion_png(&motion, options, &mut previews)?);
    let guide = motion
        .motion
        .as_ref()
        .filter(|_| motion.guide)
        .map(super::guide::folding_guide);
    let figures = run.figures();
    let next_steps = next_steps_of(print.as_ref(), machine, &jobs_written);
    let hinge = hinge_of(mesh, &sheet, machine, tiled)?;
    if let Some(gaps) = &hinge {
        files.extend(panel_files(gaps, &sheet.media));
    }
    let report = super::FabReport {
        verification: verification.to_json(),
        sheet: run.sheet_report(&figures),
        previews,
        next_steps: next_steps.clone(),
        print_and_cut: print
            .as_ref()
            .map(crate::fab::print_and_cut::PrintLayout::report),
        hinge: hinge.as_ref().map(|g| hinge_report(g, mesh)),
        seam,
    };
    let job_line = run.job_line(&figures);
    let mut warnings: Vec<String> = run.unscored_warning().into_iter().collect();
    warnings.extend(hinge.as_ref().and_then(too_far_warning));
    warnings.extend(material_unused_warning(machine));
    let mut summary = run.summary(&verification.verdict(), &job_line, &warnings);
    if let Some(seam) = &report.seam {
        summary.push(format!(
            "a tube: fold the glue tab under along its valley and glue the seam's {} numbered edges beside it onto the edges numbered alike across the sheet (report.json, seam)",
            seam.pairs.len()
        ));
    }
    let title = if mesh.title.is_empty() {
        "crease pattern"
    } else {
        mesh.title.as_str()
    };
    // A print-and-cut page is the printer's own page, never tiled.
    let template_note = print
        .is_none()
        .then(|| run.home_tiles())
        .flatten()
        .map(|(paper, _, pages)| {
            format!(
                "sheet.pdf: {} is no paper a home printer takes, so the template is printed at 100% over {pages} {} pages to tape together ({TILE_OVERLAP_MM} mm overlap, registration marks)",
                sheet.media.name, paper.name
            )
        });
    summary.extend(template_note.clone());
    summary.extend(motion.guide_line.clone());
    let pdf = match &print {
        Some(p) => print_pdf(p, mesh, &sheet, &toolpath, title, options, guide.as_ref()),
        None => run.pdf(&page, title, &summary, guide.as_ref()),
    };
    files.push(("sheet.pdf".to_string(), pdf));
    files.push(("report.json".to_string(), report.to_text().into_bytes()));
    Ok(FabOutput {
        files,
        report,
        job_line,
        warnings,
        template_note,
        guide_note: motion.guide_line,
        steps,
        next_steps,
        verification,
        sheet,
        toolpath,
        back,
        isometry_error,
    })
}

/// A tube's strip with its glue tab `--tab` wide (range-checked here), `None` for a sheet.
fn tube_of(mesh: &Mesh, options: &FabOptions) -> Result<Option<TubeStrip>, FabError> {
    let tab_mm = crate::limits::LENGTH
        .check(
            "tab",
            options.tab.unwrap_or(super::fab_options::GLUE_TAB_MM),
        )
        .map_err(|e| FabError::Input(Advice::out_of_range(FabOption::Tab, &e)))?;
    let strip = super::tube::tube_strip(mesh, tab_mm).map_err(FabError::rejected)?;
    // A tab asked for on a sheet would be silently dropped: say so instead.
    if strip.is_none() && options.tab.is_some() {
        return Err(FabError::Input(
            Advice::text("")
                .option(FabOption::Tab)
                .then(": the design is a sheet, not a tube, so it has no seam to glue; leave ")
                .option(FabOption::Tab)
                .then(" out"),
        ));
    }
    Ok(strip)
}

/// Where a sheet goes: a print-and-cut frame, else the media within the margin.
struct Placing<'a> {
    print: Option<&'a crate::fab::print_and_cut::PrintLayout>,
    page: &'a crate::fab::Media,
    margin: f64,
    sizing: crate::fab::Sizing,
    options: &'a FabOptions,
}

/// The design's lines laid out as `at` says (a tube's strip with its glue tab and seam
/// numbers), and whether the sheet is tiled over pages.
fn sheet_of(
    mesh: &Mesh,
    flat: &[crate::mesh::Vec2],
    tube: Option<&TubeStrip>,
    at: &Placing,
) -> Result<(crate::fab::Sheet, bool), FabError> {
    let mut lines = crate::fab::crease_lines(mesh, flat);
    // The layout places the points it is given: the tab's corners reach past the strip,
    // and a curved outline bulges past the vertices it runs through (its cubics' control
    // points hold it).
    let mut extent = flat.to_vec();
    extent.extend(
        lines
            .iter()
            .filter(|l| l.kind == crate::fab::LineKind::Cut)
            .filter_map(|l| l.curve.as_ref())
            .flat_map(|c| c.pieces().iter().flat_map(|p| [p.c1, p.c2])),
    );
    if let Some(t) = tube {
        let (tab, with) = t.tab(flat, lines).map_err(FabError::rejected)?;
        lines = with;
        extent.extend(tab.outline);
    }
    let (mut sheet, tiled) = match at.print {
        Some(p) => (
            p.place(&extent, &lines, at.sizing)
                .map_err(FabError::rejected)?,
            false,
        ),
        None => lay_out(&extent, &lines, at.page, at.margin, at.sizing, at.options)?,
    };
    sheet.vertices.truncate(flat.len());
    if let Some(t) = tube {
        sheet.labels = t.labels(&sheet.vertices, sheet.scale, &sheet.lines);
    }
    Ok((sheet, tiled))
}

/// The sheet would need `count` strokes: more than a job may have is refused, saying
/// what to change.
fn check_stroke_count(count: usize) -> Result<(), FabError> {
    if crate::limits::STROKES
        .check_count("strokes", count as u64)
        .is_err()
    {
        return Err(FabError::Input(
            Advice::text(format!(
                "the sheet would need {} strokes, more than {} a job may have: use a smaller ",
                crate::limits::short(count as f64),
                crate::limits::STROKES.max
            ))
            .option(FabOption::Width)
            .then(" or ")
            .option(FabOption::Media)
            .then(", or a longer dash in the machine's profile"),
        ));
    }
    Ok(())
}

/// A machine driven by its design software (Cricut) takes sheet.svg as its job, layered
/// by operation; the others get a layer per line kind.
fn svg_layers(machine: &crate::machine::Machine) -> crate::output::svg::Layers {
    if machine.protocol == crate::machine::Protocol::Svg {
        crate::output::svg::Layers::ByOperation
    } else {
        crate::output::svg::Layers::ByKind
    }
}

/// The hinge gaps of a material that takes them ([`crate::fab::hinge`]); none on a tiled
/// sheet, which no machine cuts.
fn hinge_of(
    mesh: &Mesh,
    sheet: &crate::fab::Sheet,
    machine: &crate::machine::Machine,
    tiled: bool,
) -> Result<Option<crate::fab::hinge::HingeGaps>, FabError> {
    match machine.hinge_thickness_mm {
        Some(h) if !tiled => crate::fab::hinge::hinge_gaps(mesh, sheet, h)
            .map(Some)
            .map_err(FabError::rejected),
        _ => Ok(None),
    }
}

/// The print-and-cut sheet.pdf: the page to print with the family's marks and caption,
/// then the page as cut.
fn print_pdf(
    print: &crate::fab::print_and_cut::PrintLayout,
    mesh: &Mesh,
    sheet: &crate::fab::Sheet,
    toolpath: &crate::fab::Toolpath,
    title: &str,
    options: &FabOptions,
    guide: Option<&crate::output::pdf::FoldingGuide>,
) -> Vec<u8> {
    let page = crate::output::pdf::PrintPage {
        frame: print.frame.as_ref(),
        faces: mesh.faces(),
        fill: options.print_fill,
        caption: print.family.caption(),
        guide,
    };
    crate::output::pdf::to_bytes_print(sheet, title, &page, toolpath)
}

/// The settings of the profile's material the machine does not take from crease (a
/// Cricut's pressure), to be set in its own software.
fn material_unused_warning(machine: &crate::machine::Machine) -> Option<String> {
    let material = machine.material.as_ref()?;
    let unused = &machine.material_unused;
    let list = match unused.split_last()? {
        (last, []) => last.clone(),
        (last, rest) => format!("{} or {last}", rest.join(", ")),
    };
    Some(format!(
        "{} takes no {list} from {material}: set {} in its own software",
        machine.name,
        if unused.len() == 1 { "it" } else { "them" }
    ))
}

/// What the maker does next in the machine's software (the profile's `steps`), or for a
/// print-and-cut run the marks' family's steps.
fn next_steps_of(
    print: Option<&crate::fab::print_and_cut::PrintLayout>,
    machine: &crate::machine::Machine,
    jobs_written: &[(String, Vec<u8>)],
) -> Option<NextSteps> {
    match print {
        Some(p) => Some(NextSteps {
            software: p.family.software().to_string(),
            steps: p.family.steps(jobs_written),
        }),
        None => (!machine.steps.is_empty()).then(|| NextSteps {
            software: machine
                .software
                .clone()
                .unwrap_or_else(|| machine.name.clone()),
            steps: machine.steps.clone(),
        }),
    }
}

/// `panels.svg` and `panels.dxf`: every panel's outline, set back from its folds, as a
/// cut on the sheet's media (the panels go back on the membrane where they were cut).
fn panel_files(gaps: &crate::fab::hinge::HingeGaps, media: &crate::fab::Media) -> Files {
    use crate::fab::{LineKind, Stroke, Toolpath};
    let strokes = gaps
        .panels
        .iter()
        .enumerate()
        .flat_map(|(n, p)| {
            let k = p.outline.len();
            (0..k).map(move |i| Stroke {
                kind: LineKind::Cut,
                from: p.outline[i],
                to: p.outline[(i + 1) % k],
                line: n,
                bend: None,
            })
        })
        .collect();
    let path = Toolpath {
        media: media.clone(),
        strokes,
    };
    vec![
        (
            "panels.svg".to_string(),
            crate::output::svg::sheet_to_string(&path, crate::output::svg::Layers::ByKind)
                .into_bytes(),
        ),
        (
            "panels.dxf".to_string(),
            crate::output::dxf::to_string(&path).into_bytes(),
        ),
    ]
}

/// report.json's `hinge`: the formula, the thickness, each fold's angle and gap, the
/// panels, and the valleys folded too far for a gap.
fn hinge_report(
    gaps: &crate::fab::hinge::HingeGaps,
    mesh: &Mesh,
) -> super::report_json::HingeReport {
    use super::report_json::{HingeFold, HingeReport};
    HingeReport {
        formula: "gap = 2 * thickness * tan(fold / 2) at every valley (panels on the front, membrane under them); mountains take none".to_string(),
        thickness_mm: gaps.thickness,
        largest_gap_fold_deg: crate::fab::hinge::MAX_GAP_FOLD.to_degrees(),
        panels: gaps.panels.len(),
        folds: gaps
            .folds
            .iter()
            .map(|&(e, rho, g)| HingeFold {
                edge: e,
                vertices: mesh.edges()[e].vertices,
                fold_deg: rho.to_degrees(),
                gap_mm: g,
            })
            .collect(),
        too_far: gaps.too_far.clone(),
    }
}

/// The warning for valleys folded past the largest fold a gap is laid out for.
fn too_far_warning(gaps: &crate::fab::hinge::HingeGaps) -> Option<String> {
    (!gaps.too_far.is_empty()).then(|| {
        format!(
            "{} valley(s) fold past {:.0}°, beyond what a hinge gap in {} mm sheet allows without a gap over four times the thickness: they got that gap; fold them on a second hinge or use thinner sheet (report.json: hinge.too_far)",
            gaps.too_far.len(),
            crate::fab::hinge::MAX_GAP_FOLD.to_degrees(),
            gaps.thickness
        )
    })
}

/// A sheet the machine can cut: at least [`MIN_STEPS_ACROSS`] of its steps across, else
/// every stroke would round to a point or nothing on the job.
fn check_cuttable(
    sheet: &crate::fab::Sheet,
    machine: &crate::machine::Machine,
) -> Result<(), FabError> {
    let across = sheet.size[0].max(sheet.size[1]);
    let step = 1.0 / machine.units_per_mm;
    // NaN (a degenerate sheet) is refused too.
    if across.is_nan() || across < MIN_STEPS_ACROSS * step {
        return Err(FabError::Input(
            Advice::text(format!(
                "the design is {} mm across, under {MIN_STEPS_ACROSS} of the machine's {} mm steps: nothing on it could be cut; scale it with ",
                crate::limits::short(across),
                crate::limits::short(step)
            ))
            .option(FabOption::Width)
            .then(" or ")
            .option(FabOption::Fit),
        ));
    }
    Ok(())
}

/// The fewest machine steps a design may span and still be cut.
const MIN_STEPS_ACROSS: f64 = 20.0;

/// How the options size the sheet; a width too small to cut, or both `--fit` and
/// `--width`, is refused.
fn sizing_of(options: &FabOptions) -> Result<crate::fab::Sizing, FabError> {
    use crate::fab::Sizing;
    if let Some(w) = options.width {
        // Below the range's 5 mm every stroke is shorter than a blade's dash.
        crate::limits::SHEET_WIDTH
            .check("width", w)
            .map_err(|e| FabError::Input(Advice::out_of_range(FabOption::Width, &e)))?;
    }
    match (options.fit, options.width) {
        (true, Some(_)) => Err(FabError::Input(
            Advice::text("")
                .option(FabOption::Fit)
                .then(" and ")
                .option(FabOption::Width)
                .then(" both size the sheet: give one"),
        )),
        (true, None) => Ok(Sizing::Fit),
        (false, Some(w)) => Ok(Sizing::Width(w)),
        (false, None) => Ok(Sizing::Natural),
    }
}

/// The design's flat state (unfolded if it has a 3D form) and the largest relative
/// edge-length difference between it and the design; a sheet that overlaps itself is
/// refused.
fn flatten(mesh: &Mesh) -> Result<(Vec<crate::mesh::Vec2>, f64), FabError> {
    // The sheet must fold into exactly the 3D form that was verified.
    let flat = crease_pattern_of(mesh, PatternFrom::Form)
        .map_err(|e| FabError::rejected(e.to_string()))?
        .into_owned();
    let isometry_error = crate::geometry::unfold::isometry_error(mesh, &flat);
    Ok((flat, isometry_error))
}

/// The sheet placed on `media` within `margin` (and, two-sided, the registration band
/// inside it), or tiled on a virtual sheet when it does not fit and `--tile` asks for it;
/// `true` when tiled.
fn lay_out(
    flat: &[crate::mesh::Vec2],
    lines: &[crate::fab::CreaseLine],
    media: &crate::fab::Media,
    margin: f64,
    sizing: crate::fab::Sizing,
    options: &FabOptions,
) -> Result<(crate::fab::Sheet, bool), FabError> {
    use crate::fab::{layout, LayoutError};
    // A two-sided job keeps a band inside the margin for its registration crosses.
    let band = if options.mountains_from_back {
        crate::fab::registration::MARK_BAND_MM
    } else {
        0.0
    };
    match layout(flat, lines, media, margin + band, sizing) {
        Ok(s) => Ok((s, false)),
        // Turned for the fewest pages, on a virtual sheet just large enough; the PDF is
        // tiled.
        Err(LayoutError::TooLarge { .. }) if options.tile => {
            // Each page keeps a band for its label, scale bar and legend.
            let margin = margin.max(crate::output::pdf::TILE_MARGIN_MM);
            crate::fab::layout::layout_tiled(flat, lines, media, margin, TILE_OVERLAP_MM, sizing)
                .map(|s| (s, true))
                .map_err(FabError::Layout)
        }
        Err(e @ LayoutError::TooLarge { .. }) => {
            let why = if band > 0.0 {
                format!(" (a two-sided job keeps {band} mm more inside the margin for its registration crosses)")
            } else {
                String::new()
            };
            Err(FabError::Rejected(Rejected(e.advice().then(why))))
        }
        Err(e) => Err(FabError::Layout(e)),
    }
}

/// Where a print-and-cut run lays the sheet out, if `--print-and-cut` asks for one: the
/// machine's marks on the media asked for (default a4 for Silhouette, letter for Cricut).
/// A machine that finds no marks, or a run also two-sided or tiled, is refused.
fn print_layout(
    machine: &crate::machine::Machine,
    options: &FabOptions,
) -> Result<Option<crate::fab::print_and_cut::PrintLayout>, FabError> {
    use crate::fab::print_and_cut::{MarkFamily, PrintLayout};
    if !options.print_and_cut {
        return Ok(None);
    }
    let family = machine.print_and_cut.ok_or_else(|| {
        FabError::Input(
            Advice::text(format!(
                "{} finds no print-and-cut marks (its profile has no print_and_cut key): use ",
                machine.name
            ))
            .option(FabOption::Machine)
            .then(" silhouette-cameo or cricut-maker"),
        )
    })?;
    if options.mountains_from_back || options.tile {
        return Err(FabError::Input(
            Advice::text("")
                .option(FabOption::PrintAndCut)
                .then(" cuts one printed side in one piece: leave out ")
                .option(FabOption::MountainsFromBack)
                .then(" and ")
                .option(FabOption::Tile),
        ));
    }
    let page = match &options.media {
        Some(m) => m.clone(),
        None => crate::fab::Media::parse(match family {
            MarkFamily::Silhouette => "a4",
            MarkFamily::Cricut => "letter",
        })
        .map_err(FabError::input)?,
    };
    PrintLayout::new(family, &page)
        .map(Some)
        .map_err(FabError::input)
}

/// A two-sided job's steps for the maker (see [`crate::fab::registration::steps`]),
/// naming the cutter's files, or for a laser its SVG and DXF; nothing for one side.
fn two_sided_steps(two_sided: bool, jobs_written: &[(String, Vec<u8>)]) -> Vec<String> {
    if !two_sided {
        return Vec::new();
    }
    let (front, back) = match jobs_written {
        [f, b] => (f.0.as_str(), b.0.as_str()),
        _ => (
            "sheet.svg (or sheet.dxf)",
            "sheet-back.svg (or sheet-back.dxf)",
        ),
    };
    crate::fab::registration::steps(front, back)
}

/// The jobs as files: sheet.svg, the cutter's job, sheet.dxf, then the back job's.
fn sheet_files(
    front: &crate::fab::Toolpath,
    back: Option<&crate::fab::Toolpath>,
    jobs_written: &[(String, Vec<u8>)],
    layers: crate::output::svg::Layers,
) -> Files {
    use crate::output::{dxf, svg};
    let mut files = vec![(
        "sheet.svg".to_string(),
        svg::sheet_to_string(front, layers).into_bytes(),
    )];
    files.extend(jobs_written.iter().take(1).cloned());
    files.push(("sheet.dxf".to_string(), dxf::to_string(front).into_bytes()));
    files.extend(jobs_written.iter().skip(1).cloned());
    if let Some(b) = back {
        files.push((
            "sheet-back.svg".to_string(),
            svg::sheet_to_string(b, layers).into_bytes(),
        ));
        files.push(("sheet-back.dxf".to_string(), dxf::to_string(b).into_bytes()));
    }
    files
}

/// `sheet.png` (the front job as it is cut), `design.png` (the 3D form) and
/// `design-side.png` (the form from its side, level with it), and what the
/// report says of them: scale and stroke width, and the view of the form.
fn preview_files(
    mesh: &Mesh,
    front: &crate::fab::Toolpath,
) -> Result<(Files, super::PreviewsReport), FabError> {
    use crate::output::png;
    let sheet = png::sheet(front).map_err(FabError::input)?;
    let design = png::design(mesh).map_err(FabError::input)?;
    let side = png::design_side(mesh).map_err(FabError::input)?;
    let camera = png::DesignCamera::framing(mesh.positions());
    let side_view = png::design_side_view(mesh);
    let side_camera = png::DesignCamera::framing_from(mesh.positions(), side_view);
    let scale = png::sheet_px_per_mm(front);
    let view = png::design_view();
    let report = super::PreviewsReport {
        sheet: super::SheetPreview {
            px_per_mm: scale,
            stroke_px: png::sheet_stroke_px(scale),
        },
        design: super::DesignPreview {
            size_px: png::DESIGN_SIZE_PX,
            view: [view.x, view.y, view.z],
            px_per_mm: camera.px_per_mm,
        },
        design_side: super::DesignPreview {
            size_px: png::DESIGN_SIZE_PX,
            view: [side_view.x, side_view.y, side_view.z],
            px_per_mm: side_camera.px_per_mm,
        },
        motion: None,
        guide: None,
    };
    Ok((
        vec![
            ("sheet.png".to_string(), sheet),
            ("design.png".to_string(), design),
            ("design-side.png".to_string(), side),
        ],
        report,
    ))
}

/// The crease pattern as laid out on the sheet, as SVG and as FOLD (with the layer order
/// of a flat-folding pattern).
fn pattern_files(mesh: &Mesh, sheet: &crate::fab::Sheet) -> Result<Files, FabError> {
    let mut placed = mesh.clone();
    placed.set_crease_pattern(sheet.vertices.clone());
    let cp = crate::io::to_string(&placed, crate::io::Format::Svg).map_err(FabError::input)?;
    let orders = layer_order_of(mesh, &placed);
    Ok(vec![
        ("crease-pattern.svg".to_string(), cp.into_bytes()),
        (
            "crease-pattern.fold".to_string(),
            crate::io::fold::to_string_with_orders(&placed, orders.as_deref()).into_bytes(),
        ),
    ])
}

/// Why fabrication failed: bad input (exit 2) or a design that cannot be made as asked
/// (exit 1).
#[derive(Debug, thiserror::Error)]
pub enum FabError {
    /// Bad option or profile.
    #[error("{0}")]
    Input(Advice),
    /// An option outside its range ([`crate::limits`]).
    #[error(transparent)]
    Range(#[from] crate::limits::OutOfRange),
    /// Options the layout cannot meet (a bad margin, a tiling that does not fit).
    #[error(transparent)]
    Layout(crate::fab::LayoutError),
    /// The design was refused.
    #[error(transparent)]
    Rejected(#[from] Rejected),
}

impl FabError {
    /// Bad input in words (`Input`).
    pub fn input(words: impl Into<Advice>) -> FabError {
        FabError::Input(words.into())
    }

    /// A design refused in words (`Rejected`).
    pub fn rejected(words: impl Into<Advice>) -> FabError {
        FabError::Rejected(Rejected(words.into()))
    }

    /// The message with each option named by `name`: the face's word for it (a flag,
    /// a control on the page).
    pub fn naming(&self, name: &dyn Fn(FabOption) -> String) -> String {
        match self {
            FabError::Input(advice) | FabError::Rejected(Rejected(advice)) => advice.naming(name),
            FabError::Layout(e) => e.advice().naming(name),
            FabError::Range(e) => e.to_string(),
        }
    }

    /// Bad input (exit 2, the studio's 400) rather than a design refused (exit 1).
    pub fn is_input(&self) -> bool {
        !matches!(self, FabError::Rejected(_))
    }
}

/// The layer order FOLD tools expect beside a crease pattern that folds flat (every crease
/// ±180° and no 3D form): `faceOrders` of the laid-out faces, or nothing.
fn layer_order_of(design: &Mesh, placed: &Mesh) -> Option<Vec<[i64; 3]>> {
    if design.has_3d() || crate::fab::layers::partial_crease(design).is_some() {
        return None;
    }
    match crate::fab::layer_order(placed) {
        Ok(crate::fab::LayerOrder::Found(orders)) => Some(orders),
        _ => None,
    }
}

/// The front job and, for a two-sided run, the mirrored back job. Two-sided: the front
/// scores the valleys, the back the mountains and then the outline, so the piece stays in
/// the sheet until both sides are scored; each job starts with the registration crosses
/// ([`crate::fab::registration`]) when `registered`.
fn sides(
    strokes: Vec<crate::fab::Stroke>,
    media: &crate::fab::Media,
    margin: f64,
    tools: &BTreeMap<crate::fab::LineKind, crate::fab::ToolSetting>,
    options: &FabOptions,
    registered: bool,
) -> (crate::fab::Toolpath, Option<crate::fab::Toolpath>) {
    use crate::fab::{registration, route_with, LineKind, Toolpath};
    let (front, back): (Vec<_>, Vec<_>) = strokes.into_iter().partition(|s| {
        !(options.mountains_from_back && matches!(s.kind, LineKind::Mountain | LineKind::Cut))
    });
    let marks = |centres: [crate::mesh::Vec2; 3]| {
        if registered {
            registration::cross_strokes(&centres)
        } else {
            Vec::new()
        }
    };
    let mut front_strokes = marks(registration::front_centres(media, margin));
    front_strokes.extend(route_with(&front, tools, options.route));
    let front = Toolpath {
        media: media.clone(),
        strokes: front_strokes,
    };
    let back = options.mountains_from_back.then(|| {
        let mirrored: Vec<_> = back
            .iter()
            .map(|s| s.mapped(|p| registration::mirrored(media.width, p)))
            .collect();
        let mut strokes = marks(registration::back_centres(media, margin));
        strokes.extend(route_with(&mirrored, tools, options.route));
        Toolpath {
            media: media.clone(),
            strokes,
        }
    });
    (front, back)
}

/// The cutter's own job (sheet.hpgl or sheet.gpgl, and its `-back` twin for a two-sided
/// job) in the machine's protocol; nothing for a laser, which takes sheet.dxf or sheet.svg.
fn cutter_jobs(
    machine: &crate::machine::Machine,
    front: &crate::fab::Toolpath,
    back: Option<&crate::fab::Toolpath>,
    marks: Option<&crate::fab::print_and_cut::MarkFrame>,
) -> Result<Files, FabError> {
    let mut gpgl = machine.gpgl_settings();
    gpgl.registration = marks.map(|m| crate::output::gpgl::Registration {
        origin: m.origin,
        size: m.size,
    });
    let mut files = Vec::new();
    for (side, path) in [("sheet", Some(front)), ("sheet-back", back)] {
        let (Some(path), Some(name)) = (path, machine.job_file(side)) else {
            continue;
        };
        let text = match machine.protocol {
            crate::machine::Protocol::Gpgl => crate::output::gpgl::to_string(path, &gpgl),
            _ => crate::output::hpgl::to_string(path, &machine.hpgl_settings()),
        }
        .map_err(FabError::input)?;
        files.push((name, text.into_bytes()));
    }
    Ok(files)
}

/// Every file a fabrication run can write, and the journals `plot` keeps beside the jobs.
pub const OUTPUT_FILES: [&str; 21] = [
    "sheet.svg",
    "panels.svg",
    "panels.dxf",
    "sheet.png",
    "design.png",
    "design-side.png",
    "sheet.hpgl",
    "sheet.gpgl",
    "sheet.dxf",
    "sheet-back.hpgl",
    "sheet-back.gpgl",
    "sheet-back.svg",
    "sheet-back.dxf",
    "crease-pattern.svg",
    "crease-pattern.fold",
    "sheet.pdf",
    "report.json",
    "sheet.hpgl.journal",
    "sheet-back.hpgl.journal",
    "sheet.gpgl.journal",
    "sheet-back.gpgl.journal",
];

/// Files an earlier run left in `dir` that this run's `written` files do not replace (a
/// back job the new run has none of, with its journal; a sheet.hpgl when the machine now
/// takes sheet.gpgl): removed once
/// the new files are in, so the folder holds one run, never a mix of two.
pub fn remove_stale_outputs(dir: &std::path::Path, written: &[(String, Vec<u8>)]) -> Vec<String> {
    let mut removed = Vec::new();
    for name in OUTPUT_FILES {
        // A journal stays while its job is written again: for the same bytes it still
        // resumes, for others its hash tells `plot` it is not theirs.
        let owner = name.strip_suffix(".journal").unwrap_or(name);
        let fresh = written.iter().any(|(n, _)| n == owner);
        if !fresh && dir.join(name).is_file() && std::fs::remove_file(dir.join(name)).is_ok() {
            removed.push(name.to_string());
        }
    }
    removed
}

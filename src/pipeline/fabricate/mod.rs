//! Fabrication: verify → unfold → lay out → score → route → SVG, PDF, HP-GL, report.

use super::fab_options::{FabOptions, TILE_OVERLAP_MM};
use super::fab_report::Run;
use crate::fab::{Advice, FabOption};
use crate::mesh::Mesh;

mod hinge;
mod jobs;
mod layout;

use hinge::{hinge_of, hinge_report, panel_files, too_far_warning};
use jobs::{cut_sheet, job_files};
use layout::{lay_out_sheet, sizing_of, tube_of, Laid};

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
///
/// A crease pattern with unassigned creases is made with the sides a layer order gives
/// them (as `convert --assign` and `fold --flat` write them; a note in the verification
/// says so): its verdict is that assigned pattern's, so its creases are scored as the
/// mountains and valleys it was judged with. Where no sides are found it is made as
/// drawn, and its verdict (FAIL or UNDECIDED) refuses it unless `--force`.
pub fn fabricate(
    mesh: &Mesh,
    machine: &crate::machine::Machine,
    options: &FabOptions,
) -> Result<FabOutput, FabError> {
    use crate::fab::{verify, verify_searched, Budget, SideSearch, Tolerances};
    let (tol, budget) = (Tolerances::default(), Budget::default());
    let Some(search) = crate::fab::assign_sides(mesh, &budget) else {
        return fabricate_verified(mesh, verify(mesh, None, tol), machine, options);
    };
    // Judged as `verify` judges it, from the search already run; made with the sides
    // found, or as drawn where none were.
    let verification = verify_searched(mesh, &search, None, tol, &budget);
    let made = match &search {
        SideSearch::Found { mesh: assigned, .. } => assigned.as_ref(),
        SideSearch::NoOrder { .. } | SideSearch::Stopped(_) => mesh,
    };
    fabricate_verified(made, verification, machine, options)
}

/// [`fabricate`] with the design's verification already done (it depends on the design
/// alone, so one report serves runs on several machines or media).
pub fn fabricate_verified(
    mesh: &Mesh,
    verification: crate::fab::Report,
    machine: &crate::machine::Machine,
    options: &FabOptions,
) -> Result<FabOutput, FabError> {
    let sizing = sizing_of(options)?;
    refuse_unless_passed(&verification, options)?;
    // A tube is made from the strip it is cut open to, with a glue tab (issue 31).
    let tube = tube_of(mesh, options)?;
    let mesh = tube.as_ref().map_or(mesh, |t| &t.strip.sheet);
    let laid = lay_out_sheet(mesh, tube.as_ref(), machine, options, sizing)?;
    let cut = cut_sheet(&laid, machine, options)?;
    let mut files = job_files(mesh, &laid, &cut, machine, options)?;
    let run = Run {
        machine,
        options,
        sheet: &laid.sheet,
        margin: laid.margin,
        tiled: laid.tiled,
        jobs: std::iter::once(&cut.front)
            .chain(cut.back.as_ref())
            .collect(),
        jobs_written: &cut.jobs_written,
        steps: &cut.steps,
        unscored: &cut.unscored,
        short_folds: cut.short_folds,
        isometry_error: laid.isometry_error,
    };
    let (pictures, mut previews) = preview_files(mesh, &cut.front)?;
    files.extend(pictures);
    let motion = super::guide::run_motion(mesh, options)?;
    files.extend(super::guide::motion_png(&motion, options, &mut previews)?);
    let guide = motion
        .motion
        .as_ref()
        .filter(|_| motion.guide)
        .map(super::guide::folding_guide);
    let figures = run.figures();
    let next_steps = next_steps_of(laid.print.as_ref(), machine, &cut.jobs_written);
    let hinge = hinge_of(mesh, &laid.sheet, machine, laid.tiled)?;
    if let Some(gaps) = &hinge {
        files.extend(panel_files(gaps, &laid.sheet.media));
    }
    let report = super::FabReport {
        verification: verification.to_json(),
        sheet: run.sheet_report(&figures),
        previews,
        next_steps: next_steps.clone(),
        print_and_cut: laid
            .print
            .as_ref()
            .map(crate::fab::print_and_cut::PrintLayout::report),
        hinge: hinge.as_ref().map(|g| hinge_report(g, mesh)),
        seam: laid.seam.clone(),
    };
    let job_line = run.job_line(&figures);
    let mut warnings: Vec<String> = run.unscored_warning().into_iter().collect();
    warnings.extend(hinge.as_ref().and_then(too_far_warning));
    warnings.extend(material_unused_warning(machine));
    let template_note = template_note_of(&run, laid.print.is_some());
    let mut summary = run.summary(&verification.verdict(), &job_line, &warnings);
    summary.extend(report.seam.as_ref().map(seam_line));
    summary.extend(template_note.clone());
    summary.extend(motion.guide_line.clone());
    let pdf = sheet_pdf(mesh, &laid, &cut.front, &run, &summary, guide.as_ref());
    files.push(("sheet.pdf".to_string(), pdf));
    files.push(("report.json".to_string(), report.to_text().into_bytes()));
    Ok(FabOutput {
        files,
        report,
        job_line,
        warnings,
        template_note,
        guide_note: motion.guide_line,
        steps: cut.steps,
        next_steps,
        verification,
        sheet: laid.sheet,
        toolpath: cut.front,
        back: cut.back,
        isometry_error: laid.isometry_error,
    })
}

/// Refuses a design whose verdict is not PASS unless `--force`, naming what to do.
fn refuse_unless_passed(
    verification: &crate::fab::Report,
    options: &FabOptions,
) -> Result<(), FabError> {
    if verification.pass() || options.force {
        return Ok(());
    }
    let what = if matches!(
        verification.verdict(),
        crate::fab::Verdict::Undecided { .. }
    ) {
        "verification could not decide the design"
    } else {
        "the design fails verification"
    };
    Err(FabError::Rejected(Rejected(
        Advice::text(format!("{what} (use "))
            .option(FabOption::Force)
            .then(format!(" to cut it anyway):\n{verification}")),
    )))
}

/// How the template is printed when its media is no paper a home printer takes; a
/// print-and-cut page is the printer's own page, never tiled.
fn template_note_of(run: &Run, print_and_cut: bool) -> Option<String> {
    if print_and_cut {
        return None;
    }
    run.home_tiles().map(|(paper, _, pages)| {
        format!(
            "sheet.pdf: {} is no paper a home printer takes, so the template is printed at 100% over {pages} {} pages to tape together ({TILE_OVERLAP_MM} mm overlap, registration marks)",
            run.sheet.media.name, paper.name
        )
    })
}

/// What the maker does with a tube's seam, under the PDF's title.
fn seam_line(seam: &crate::pipeline::report_json::SeamReport) -> String {
    format!(
        "a tube: fold the glue tab under along its valley and glue the seam's {} numbered edges beside it onto the edges numbered alike across the sheet (report.json, seam)",
        seam.pairs.len()
    )
}

/// sheet.pdf, titled by the design: for print-and-cut, the page to print with the
/// family's marks and caption, then the page as cut; else the template ([`Run::pdf`])
/// under `summary`.
fn sheet_pdf(
    mesh: &Mesh,
    laid: &Laid,
    front: &crate::fab::Toolpath,
    run: &Run,
    summary: &[String],
    guide: Option<&crate::output::pdf::FoldingGuide>,
) -> Vec<u8> {
    let title = if mesh.title.is_empty() {
        "crease pattern"
    } else {
        mesh.title.as_str()
    };
    let Some(print) = &laid.print else {
        return run.pdf(&laid.page, title, summary, guide);
    };
    let page = crate::output::pdf::PrintPage {
        frame: print.frame.as_ref(),
        faces: mesh.faces(),
        fill: run.options.print_fill,
        caption: print.family.caption(),
        guide,
    };
    crate::output::pdf::to_bytes_print(&laid.sheet, title, &page, front)
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

//! Whole jobs that chain the stages (solver → fab), shared by the CLI and the tests so
//! both run exactly the same thing: folding a pattern, and running a design script.

use crate::constraints::{tracked_fold_angle, ConstraintSet, Reference};
use crate::fab::{unfold, UnfoldError};
use crate::mesh::{Assignment, Mesh, Vec3};
use crate::solver::{
    fold_toward, run_stage, DragReport, FoldReport, Mode, Options, Script, Solver, SolverError,
    Stage, Stats,
};
use std::collections::BTreeMap;
use std::path::Path;

/// Why a job failed. `is_input_error` separates bad arguments (exit 2) from solves that
/// did not work out (exit 1).
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// A bad argument or script entry.
    #[error("{0}")]
    Input(String),
    /// The solver failed.
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// The result could not be unfolded.
    #[error(transparent)]
    Unfold(#[from] UnfoldError),
}

impl PipelineError {
    /// Bad input rather than a failed solve.
    pub fn is_input_error(&self) -> bool {
        matches!(
            self,
            PipelineError::Input(_)
                | PipelineError::Solver(
                    SolverError::UnknownVertex { .. } | SolverError::NotADisk { .. }
                )
        )
    }
}

/// A design job: a mesh and what to do to it.
#[derive(Clone, Debug)]
pub struct DesignJob {
    /// The starting mesh.
    pub mesh: Mesh,
    /// Design or simulation (§5).
    pub mode: Mode,
    /// Conditions in design mode; default from the assignment.
    pub conditions: Option<ConstraintSet>,
    /// Twist allowance for flat creases.
    pub alpha: Option<f64>,
    /// Fixed vertices; default the face nearest the middle.
    pub fixed: Option<Vec<usize>>,
    /// Drag falloff radius (mm).
    pub radius: Option<f64>,
    /// Fold toward this fraction of the targets first.
    pub fold: Option<f64>,
    /// The drags.
    pub stages: Vec<Stage>,
    /// Solver settings.
    pub options: Options,
}

/// What a design job produced.
#[derive(Clone, Debug)]
pub struct DesignOutcome {
    /// The result: 3D form, crease pattern, fold angles.
    pub mesh: Mesh,
    /// Solver counters of the drag phase.
    pub stats: Stats,
    /// Per stage, how close the dragged vertices came.
    pub drags: Vec<DragReport>,
    /// The folding phase, if any.
    pub fold: Option<FoldReport>,
}

impl DesignJob {
    /// A job with defaults around a mesh.
    pub fn new(mesh: Mesh) -> DesignJob {
        DesignJob {
            mesh,
            mode: Mode::Design,
            conditions: None,
            alpha: None,
            fixed: None,
            radius: None,
            fold: None,
            stages: Vec::new(),
            options: Options::default(),
        }
    }

    /// A job from a script; its `base` is read relative to `script_dir` unless `mesh` is
    /// given.
    pub fn from_script(
        script: &Script,
        script_dir: &Path,
        mesh: Option<Mesh>,
    ) -> Result<DesignJob, PipelineError> {
        let mesh = match (mesh, &script.base) {
            (Some(m), _) => m,
            (None, Some(base)) => crate::io::read(&script_dir.join(base))
                .map_err(|e| PipelineError::Input(e.to_string()))?,
            (None, None) => {
                return Err(PipelineError::Input(
                    "the script names no base pattern and none was given".into(),
                ))
            }
        };
        let mut job = DesignJob::new(mesh);
        job.mode = match script.mode.as_deref() {
            None | Some("design") => Mode::Design,
            Some("simulation") => Mode::Simulation,
            Some(other) => {
                return Err(PipelineError::Input(format!(
                    "unknown mode \"{other}\" (design or simulation)"
                )))
            }
        };
        job.conditions = script
            .conditions
            .as_ref()
            .map(|c| ConstraintSet::parse(&c.join(",")))
            .transpose()
            .map_err(PipelineError::Input)?;
        job.alpha = script.alpha;
        job.fixed = script.fix.clone();
        job.radius = script.radius;
        job.fold = script.fold;
        job.stages = script.stage.clone();
        Ok(job)
    }
}

/// Progress callback: phase name, steps done, steps planned.
pub type Progress<'a> = &'a mut dyn FnMut(&str, usize, usize);

/// Runs a design job: optional folding, then the drags, then the unfolded crease pattern
/// (design mode changes lengths, so the pattern is laid out anew from the 3D form).
pub fn run_design(job: DesignJob, progress: Progress) -> Result<DesignOutcome, PipelineError> {
    let DesignJob {
        mut mesh,
        mode,
        conditions,
        alpha,
        fixed,
        radius,
        fold,
        stages,
        options,
    } = job;
    if let Some(a) = alpha {
        if !(0.0..1.0).contains(&a) {
            return Err(PipelineError::Input(format!(
                "alpha must be in [0, 1) (got {a})"
            )));
        }
        for e in mesh.edges_mut() {
            if e.target == 0.0 && matches!(e.assignment, Assignment::Flat | Assignment::Join) {
                e.alpha = a;
            }
        }
    }
    let dragged: Vec<usize> = stages
        .iter()
        .flat_map(|s| s.moves.iter().map(|m| m.vertex))
        .collect();
    let fixed = fixed.unwrap_or_else(|| Solver::default_fixed(&mesh, &dragged));
    let mut fold_report = None;
    if let Some(amount) = fold {
        if !(0.0..=1.0).contains(&amount) {
            return Err(PipelineError::Input(format!(
                "fold amount must be in [0, 1] (got {amount})"
            )));
        }
        // Folding shrinks the sheet; only a face in the middle is held for it.
        let centre = Solver::default_fixed(&mesh, &[]);
        let mut solver = Solver::new(mesh, Mode::folding_set(), &centre, options.clone())?;
        let report = fold_toward(&mut solver, amount, 4000, &mut |k| {
            progress("fold", k, 4000)
        })?;
        mesh = solver.into_mesh();
        fold_report = Some(report);
    }
    let mut stats = Stats::default();
    let mut drags = Vec::new();
    if !stages.is_empty() {
        check_targets(&mesh, &stages, &fixed, mode)?;
        let set = match mode {
            Mode::Simulation => Mode::simulation_set(),
            Mode::Design => {
                conditions.unwrap_or_else(|| ConstraintSet::default_for(&Reference::new(&mesh)))
            }
        };
        let mut solver = Solver::new(mesh, set, &fixed, options)?;
        solver.correct()?;
        let (lo, hi) = solver.mesh().bounding_box();
        let radius = radius.unwrap_or(0.25 * (hi - lo).norm());
        if !(radius.is_finite() && radius > 0.0) {
            return Err(PipelineError::Input(format!(
                "radius must be a positive length (got {radius})"
            )));
        }
        let total: usize = stages.iter().map(|s| s.steps).sum();
        let mut done = 0;
        for stage in &stages {
            drags.push(run_stage(&mut solver, stage, radius, &mut || {
                done += 1;
                progress("drag", done, total)
            })?);
        }
        // Saved designs are unfolded for cutting; polishing the residual from the solver's
        // working 1e-8 to 1e-12 makes that unfolding isometric to well under 1e-9.
        solver.polish(1e-12);
        stats = solver.stats.clone();
        mesh = solver.into_mesh();
    }
    record_fold_angles(&mut mesh);
    if mode == Mode::Design && !stages.is_empty() {
        let flat = unfold(&mesh)?;
        mesh.set_flat(flat);
    }
    Ok(DesignOutcome {
        mesh,
        stats,
        drags,
        fold: fold_report,
    })
}

/// Targets must be numbers and within reach: in simulation mode no farther from a fixed
/// vertex than the paper's extent; in design mode within ten times the design's size.
fn check_targets(
    mesh: &Mesh,
    stages: &[Stage],
    fixed: &[usize],
    mode: Mode,
) -> Result<(), PipelineError> {
    let (lo, hi) = mesh.bounding_box();
    let size = (hi - lo).norm();
    let paper = match mesh.flat() {
        Some(f) => {
            let (mut a, mut b) = (f[0], f[0]);
            for p in f {
                a = a.inf(p);
                b = b.sup(p);
            }
            (b - a).norm()
        }
        None => size,
    };
    for stage in stages {
        if stage.steps == 0 {
            return Err(PipelineError::Input(
                "a drag needs at least one step".into(),
            ));
        }
        for m in &stage.moves {
            if m.vertex >= mesh.vertex_count() {
                return Err(SolverError::UnknownVertex {
                    vertex: m.vertex,
                    count: mesh.vertex_count(),
                }
                .into());
            }
            if fixed.contains(&m.vertex) {
                return Err(PipelineError::Input(format!(
                    "vertex {} is both fixed and dragged",
                    m.vertex
                )));
            }
            let t = Vec3::new(m.to[0], m.to[1], m.to[2]);
            if !t.iter().all(|c| c.is_finite()) {
                return Err(PipelineError::Input(format!(
                    "target of vertex {} is not a finite point",
                    m.vertex
                )));
            }
            let reach = match mode {
                Mode::Simulation => paper,
                Mode::Design => 10.0 * size,
            };
            for &f in fixed {
                let d = (t - mesh.positions()[f]).norm();
                if d > reach {
                    return Err(PipelineError::Input(format!(
                        "target of vertex {} is unreachable: {d:.1} mm from fixed vertex {f}, but the paper spans only {reach:.1} mm",
                        m.vertex
                    )));
                }
            }
        }
    }
    Ok(())
}

/// Stores each crease's fold angle in the 3D form as its `fold_angle` (FOLD's
/// `edges_foldAngle` on output), on the branch its target implies near ±π.
pub fn record_fold_angles(mesh: &mut Mesh) {
    let reference = Reference::new(mesh);
    let angles: Vec<Option<f64>> = (0..mesh.edges().len())
        .map(|e| tracked_fold_angle(mesh, &reference, mesh.positions(), e).map(|(r, _)| r))
        .collect();
    let has_3d = mesh.has_3d();
    for (e, rho) in mesh.edges_mut().iter_mut().zip(angles) {
        if let (Some(r), true) = (rho, has_3d) {
            e.fold_angle = r;
        }
    }
}

/// Options of a fabrication run.
#[derive(Clone, Debug, Default)]
pub struct FabOptions {
    /// Media; default the machine's.
    pub media: Option<crate::fab::Media>,
    /// Scale the pattern to this width (mm).
    pub width: Option<f64>,
    /// Fabricate even if verification fails.
    pub force: bool,
    /// Score mountains from the back: a second, mirrored job.
    pub mountains_from_back: bool,
    /// When the pattern does not fit the media, split the PDF over pages instead of
    /// refusing (no cutter job is written then).
    pub tile: bool,
}

/// Overlap between tiled PDF pages (mm).
pub const TILE_OVERLAP_MM: f64 = 10.0;

/// Everything a fabrication run produced, ready to write.
pub struct FabOutput {
    /// File name and bytes, in writing order.
    pub files: Vec<(String, Vec<u8>)>,
    /// The report written as report.json.
    pub report: serde_json::Value,
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

/// Why fabrication stopped: the design fails verification, does not fit, overlaps itself.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Rejected(pub String);

/// Verify → unfold → lay out → score → route → SVG, PDF, HP-GL and a report (§ the
/// fabrication half of the brief). Nothing is written here; see [`crate::io::write_all_atomic`].
pub fn fabricate(
    mesh: &Mesh,
    machine: &crate::plotter::Machine,
    options: &FabOptions,
) -> Result<FabOutput, FabError> {
    use crate::fab::{
        check_overlap, crease_lines, layout, route, score, verify, LayoutError, LineKind, Media,
        Tolerances, Toolpath,
    };
    let verification = verify(mesh, None, Tolerances::default());
    if !verification.pass() && !options.force {
        return Err(FabError::Rejected(Rejected(format!(
            "the design fails verification (use --force to cut it anyway):\n{verification}"
        ))));
    }
    let flat = if mesh.has_3d() {
        unfold(mesh).map_err(|e| FabError::Rejected(Rejected(e.to_string())))?
    } else {
        mesh.flat()
            .map(<[_]>::to_vec)
            .unwrap_or_else(|| mesh.positions().iter().map(|p| p.xy()).collect())
    };
    let isometry_error = mesh
        .edges()
        .iter()
        .map(|e| {
            let [a, b] = e.vertices;
            let l3 = (mesh.positions()[a] - mesh.positions()[b]).norm();
            ((flat[a] - flat[b]).norm() - l3).abs() / l3
        })
        .fold(0.0, f64::max);
    check_overlap(mesh.faces(), &flat).map_err(|e| FabError::Rejected(Rejected(e.to_string())))?;
    let media = match &options.media {
        Some(m) => m.clone(),
        None => Media::parse(&machine.media).map_err(FabError::Input)?,
    };
    let lines = crease_lines(mesh, &flat);
    let mut tiled = false;
    let sheet = match layout(&flat, &lines, &media, machine.margin_mm, options.width) {
        Ok(s) => s,
        Err(LayoutError::TooLarge { need_w, need_h, .. }) if options.tile => {
            // Lay it out on a virtual sheet just large enough; the PDF is tiled below.
            tiled = true;
            let big = Media {
                name: format!("{need_w:.0}x{need_h:.0}mm (tiled over {})", media.name),
                width: need_w + 1e-6,
                height: need_h + 1e-6,
            };
            layout(&flat, &lines, &big, machine.margin_mm, options.width)
                .map_err(|e| FabError::Input(e.to_string()))?
        }
        Err(e @ LayoutError::TooLarge { .. }) => {
            return Err(FabError::Rejected(Rejected(e.to_string())))
        }
        Err(LayoutError::Bad(m)) => return Err(FabError::Input(m)),
    };
    let page = media.clone();
    let media = sheet.media.clone();
    let strokes = score(&sheet, &machine.score_settings());
    let (front, back): (Vec<_>, Vec<_>) = strokes
        .into_iter()
        .partition(|s| !(options.mountains_from_back && s.kind == LineKind::Mountain));
    let toolpath = Toolpath {
        media: media.clone(),
        strokes: route(&front),
    };
    let back = options.mountains_from_back.then(|| {
        // Seen from the back the sheet is mirrored left to right.
        let mirrored: Vec<_> = back
            .iter()
            .map(|s| crate::fab::Stroke {
                from: crate::mesh::Vec2::new(media.width - s.from.x, s.from.y),
                to: crate::mesh::Vec2::new(media.width - s.to.x, s.to.y),
                ..*s
            })
            .collect();
        Toolpath {
            media: media.clone(),
            strokes: route(&mirrored),
        }
    });
    let hpgl_settings = machine.hpgl_settings();
    let hpgl =
        crate::output::hpgl::to_string(&toolpath, &hpgl_settings).map_err(FabError::Input)?;
    let mut files = vec![
        (
            "sheet.svg".to_string(),
            crate::output::svg::sheet_to_string(&toolpath).into_bytes(),
        ),
        ("sheet.hpgl".to_string(), hpgl.clone().into_bytes()),
    ];
    let mut back_bytes = 0;
    if let Some(b) = &back {
        let text = crate::output::hpgl::to_string(b, &hpgl_settings).map_err(FabError::Input)?;
        back_bytes = text.len();
        files.push(("sheet-back.hpgl".to_string(), text.into_bytes()));
        files.push((
            "sheet-back.svg".to_string(),
            crate::output::svg::sheet_to_string(b).into_bytes(),
        ));
    }
    let mut placed = mesh.clone();
    placed.set_flat(sheet.vertices.clone());
    let cp = crate::io::to_string(&placed, crate::io::Format::Svg).map_err(FabError::Input)?;
    files.push(("crease-pattern.svg".to_string(), cp.into_bytes()));

    // Figures for the report.
    let mut line_length: BTreeMap<&str, f64> = BTreeMap::new();
    for l in &sheet.lines {
        *line_length.entry(l.kind.name()).or_default() += l.length();
    }
    let jobs: Vec<&Toolpath> = std::iter::once(&toolpath).chain(back.as_ref()).collect();
    let mut cut_length: BTreeMap<&str, f64> = BTreeMap::new();
    let mut motion = 0.0;
    let mut travel = 0.0;
    for job in &jobs {
        for (k, len) in job.cut_length() {
            *cut_length.entry(k.name()).or_default() += len;
            motion += len / machine.speed(k);
        }
        travel += job.travel();
    }
    motion += travel / machine.pen_up_speed_mm_s;
    let bytes = hpgl.len() + back_bytes;
    let transfer = bytes as f64 * 10.0 / machine.baud as f64;
    let estimate = motion.max(transfer);
    let sheet_json = serde_json::json!({
        "machine": machine.name,
        "media": {"name": media.name, "width_mm": media.width, "height_mm": media.height},
        "size_mm": sheet.size,
        "scale": sheet.scale,
        "rotation_deg": sheet.rotation.to_degrees(),
        "line_length_mm": line_length,
        "cut_length_mm": cut_length,
        "strokes": jobs.iter().map(|j| j.strokes.len()).sum::<usize>(),
        "pen_up_travel_mm": travel,
        "hpgl_bytes": bytes,
        "estimated_plot_time_s": estimate,
        "motion_time_s": motion,
        "transfer_time_s": transfer,
        "isometry_max_relative_error": isometry_error,
        "mountains_from_back": options.mountains_from_back,
        "tiled": tiled,
    });
    let report = serde_json::json!({"verification": verification.to_json(), "sheet": sheet_json});
    let title = if mesh.title.is_empty() {
        "crease pattern".to_string()
    } else {
        mesh.title.clone()
    };
    let summary =
        vec![
            format!(
            "{} on {} ({:.0} x {:.0} mm), pattern {:.1} x {:.1} mm at scale {:.3}; verification {}",
            machine.name,
            media.name,
            media.width,
            media.height,
            sheet.size[0],
            sheet.size[1],
            sheet.scale,
            if verification.pass() { "passed" } else { "FAILED (forced)" }
        ),
            format!(
                "cut {:.0} mm, pen-up travel {:.0} mm, {} bytes of HP-GL, about {:.0} s to plot",
                cut_length.values().sum::<f64>(),
                travel,
                bytes,
                estimate
            ),
        ];
    let pdf = if tiled {
        crate::output::pdf::to_bytes_tiled(
            &sheet,
            &page,
            machine.margin_mm,
            TILE_OVERLAP_MM,
            &title,
            &summary,
        )
    } else {
        crate::output::pdf::to_bytes(&sheet, &title, &summary)
    };
    if tiled {
        // A cutter cannot take a sheet larger than its media: only the printable files.
        files.retain(|(name, _)| !name.ends_with(".hpgl"));
    }
    files.push(("sheet.pdf".to_string(), pdf));
    files.push((
        "report.json".to_string(),
        (serde_json::to_string_pretty(&report).expect("json") + "\n").into_bytes(),
    ));
    Ok(FabOutput {
        files,
        report,
        verification,
        sheet,
        toolpath,
        back,
        isometry_error,
    })
}

/// Why fabrication failed: bad input (exit 2) or a design that cannot be made as asked
/// (exit 1).
#[derive(Debug, thiserror::Error)]
pub enum FabError {
    /// Bad option or profile.
    #[error("{0}")]
    Input(String),
    /// The design was refused.
    #[error(transparent)]
    Rejected(#[from] Rejected),
}

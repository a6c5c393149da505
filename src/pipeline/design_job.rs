//! The design job: a pattern folded toward its targets, dragged, fitted to a surface or
//! run from a script ([`DesignJob`], [`run_design`]), and what a finished design keeps
//! (its crease pattern, its fold angles, its sheet's size).

use super::fit;
use super::fit::{FitReport, FitStage};
use super::script::{Script, ScriptFit};
use super::step_order::lost_layer_order;
use super::{PipelineError, Progress};

use crate::constraints::{tracked_fold_angle, ConstraintSet, Family, Reference};
use crate::geometry::unfold::{crease_pattern_of, PatternFrom};
use crate::mesh::{Assignment, Mesh, Vec3};
use crate::solver::{
    fold_toward, run_stage, DragReport, FoldReport, Mode, Options, Solver, SolverError, Stage,
    Stats,
};
use std::path::Path;

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
    /// Fixed vertices of the drags; default the face farthest from the dragged vertices.
    pub fixed: Option<Vec<usize>>,
    /// Fixed vertices of the fold; default the face nearest the middle.
    pub fold_fixed: Option<Vec<usize>>,
    /// Drag falloff radius (mm).
    pub radius: Option<f64>,
    /// Fold toward this fraction of the targets first.
    pub fold: Option<f64>,
    /// Remesh (§4): collapse edges shorter than this fraction of the mean edge.
    pub remesh: Option<f64>,
    /// The drags.
    pub stages: Vec<Stage>,
    /// A fit to a target surface after the drags.
    pub fit: Option<FitStage>,
    /// Solver settings.
    pub options: Options,
    /// When a drag step cannot be corrected, keep the last state that held every
    /// condition (the stage stops there, [`DragReport::stalled`]; later stages and the
    /// fit are not run) instead of failing with nothing.
    pub keep_partial: bool,
    /// In design mode, hold the outline of the crease pattern as well: its angles (eq. 2)
    /// and the lengths of its straight runs (eq. 3), added to whatever conditions are
    /// chosen. Design mode frees lengths, and a drag otherwise redraws the outline (a
    /// 6 × 10 Miura-ori's four corners pulled into an arch: 130 × 173 mm flat became
    /// 155 × 177 mm with a ragged edge).
    pub keep_outline: bool,
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
    /// The fit, if any: how close the design came to its target.
    pub fit: Option<FitReport>,
    /// The crease pattern's size before and after, when design mode changed it.
    pub resized: Option<SheetResize>,
}

/// A change of the crease pattern's width or height (mm) past which a design job says
/// the sheet changed size: design mode frees lengths, and a maker cuts the sheet.
pub const SHEET_RESIZE_MM: f64 = 0.5;

/// The crease pattern's width and height (mm) before and after a design job that changed
/// either by more than [`SHEET_RESIZE_MM`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheetResize {
    /// Width and height before.
    pub before: crate::mesh::Vec2,
    /// Width and height after.
    pub after: crate::mesh::Vec2,
}

impl SheetResize {
    /// The change from `before` (a design's crease-pattern size) to `after`'s, when past
    /// [`SHEET_RESIZE_MM`].
    fn between(before: Option<crate::mesh::Vec2>, after: &Mesh) -> Option<SheetResize> {
        let (before, after) = (before?, after.crease_pattern_size()?);
        ((before - after).abs().max() > SHEET_RESIZE_MM).then_some(SheetResize { before, after })
    }
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
            fold_fixed: None,
            radius: None,
            fold: None,
            remesh: None,
            stages: Vec::new(),
            fit: None,
            options: Options::default(),
            keep_partial: false,
            keep_outline: false,
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
            (None, Some(base)) => crate::io::read(&script_dir.join(base))?,
            (None, None) => {
                return Err(PipelineError::Input(
                    "the script names no base pattern and none was given".into(),
                ))
            }
        };
        let mut job = DesignJob::new(mesh);
        if let Some(mode) = script.mode.as_deref() {
            job.mode = Mode::parse(mode).map_err(PipelineError::Input)?;
        }
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
        job.remesh = script.remesh;
        job.stages = script.stage.clone();
        if let Some(f) = &script.fit {
            job.fit = Some(fit_from_script(f, script_dir)?);
        }
        Ok(job)
    }
}

/// Runs a design job: optional folding, then the drags, then the unfolded crease pattern
/// (design mode changes lengths, so the pattern is laid out anew from the 3D form).
pub fn run_design(job: DesignJob, progress: Progress) -> Result<DesignOutcome, PipelineError> {
    let DesignJob {
        mut mesh,
        mode,
        conditions,
        alpha,
        fixed,
        fold_fixed,
        radius,
        fold,
        remesh,
        stages,
        fit,
        options,
        keep_partial,
        keep_outline,
    } = job;
    if let Some(a) = alpha {
        set_alpha(&mut mesh, a)?;
    }
    let size_before = mesh.crease_pattern_size();
    let dragged: Vec<usize> = stages
        .iter()
        .flat_map(|s| s.moves.iter().map(|m| m.vertex))
        .collect();
    check_options(&mesh, remesh, [&fixed, &fold_fixed])?;
    if let Some(f) = &fit {
        check_fit(f)?;
    }
    let moves = !stages.is_empty() || fit.is_some();
    // Folding shrinks the sheet: unless told otherwise, a face in the middle is held.
    let fold_anchor = fold_fixed.unwrap_or_else(|| Solver::default_fixed(&mesh, &[]));
    let pins = fixed.clone();
    let fixed = fixed.unwrap_or_else(|| Solver::default_fixed(&mesh, &dragged));
    let fold_report;
    (mesh, fold_report) = first_fold(mesh, fold, moves, &fold_anchor, &options, progress)?;
    let mut set = mode.conditions(conditions.as_ref(), &mesh);
    if keep_outline && mode == Mode::Design {
        for f in [Family::BoundaryAngle, Family::BoundaryLength] {
            if !set.families.contains(&f) {
                set.families.push(f);
            }
        }
    }
    let mut stats = Stats::default();
    let mut drags = Vec::new();
    if !stages.is_empty() {
        check_targets(&mesh, &stages, &fixed, mode)?;
        let mut solver = Solver::new(mesh, set.clone(), &fixed, options.clone())?;
        drags = drag_phase(&mut solver, &stages, radius, remesh, keep_partial, progress)?;
        stats = solver.stats.clone();
        mesh = solver.into_mesh();
    }
    let stalled = drags.iter().any(|d| d.stalled);
    let mut fit_phase = None;
    if let Some(stage) = fit.as_ref().filter(|_| !stalled) {
        let (fitted, phase, fit_stats) =
            fit::fit_phase(mesh, stage, pins.as_deref(), &set, &options, progress)?;
        add_stats(&mut stats, &fit_stats);
        (mesh, fit_phase) = (fitted, Some(phase));
    }
    finish_design(&mut mesh, mode == Mode::Design && moves)?;
    let fit_report = fit_phase
        .zip(fit.as_ref())
        .map(|(phase, stage)| fit::report(phase, &mesh, &stage.target, &set, &stats));
    Ok(DesignOutcome {
        resized: SheetResize::between(size_before, &mesh),
        mesh,
        stats,
        drags,
        fold: fold_report,
        fit: fit_report,
    })
}

impl DesignOutcome {
    /// The stage that stopped at a step Newton could not correct (a job with
    /// [`DesignJob::keep_partial`]): the design is the last state that held every
    /// condition, short of what was asked.
    pub fn stalled(&self) -> Option<(usize, &DragReport)> {
        self.drags.iter().enumerate().find(|(_, d)| d.stalled)
    }
}

/// Adds a later phase's solver counters to the job's.
fn add_stats(total: &mut Stats, more: &Stats) {
    total.steps += more.steps;
    total.newton_iterations += more.newton_iterations;
    total.halvings += more.halvings;
    total.worst_residual = total.worst_residual.max(more.worst_residual);
    total.factorisations += more.factorisations;
    total.restarted_predictions += more.restarted_predictions;
    total.one_solve_steps += more.one_solve_steps;
    total.solves += more.solves;
}

/// A fit's step count and goal within their ranges.
fn check_fit(stage: &FitStage) -> Result<(), PipelineError> {
    crate::limits::STEPS.check_count("--steps", stage.options.max_steps as u64)?;
    if let Some(g) = stage.options.goal {
        crate::limits::FIT_GOAL.check("--within", g)?;
    }
    if let Some(r) = stage.options.remesh {
        crate::limits::REMESH.check("--remesh", r)?;
    }
    Ok(())
}

/// A script's `[fit]` as a stage, its target read relative to `script_dir`.
fn fit_from_script(f: &ScriptFit, script_dir: &Path) -> Result<FitStage, PipelineError> {
    let path = script_dir.join(&f.target);
    let target = crate::io::read_target(&path)?;
    let mut options = crate::fit::FitOptions::default();
    if let Some(s) = &f.surface {
        options.surface = crate::fit::SurfaceChoice::parse(s).map_err(PipelineError::Input)?;
    }
    if let Some(n) = f.steps {
        options.max_steps = n;
    }
    options.goal = f.within;
    Ok(FitStage {
        target: std::sync::Arc::new(target),
        target_name: f.target.display().to_string(),
        align: f.align.unwrap_or(true),
        options,
    })
}

/// A remesh threshold in (0, 1) and fixed vertices that exist.
fn check_options(
    mesh: &Mesh,
    remesh: Option<f64>,
    fixed: [&Option<Vec<usize>>; 2],
) -> Result<(), PipelineError> {
    if let Some(r) = remesh {
        crate::limits::REMESH.check("remesh", r)?;
    }
    let n = mesh.vertex_count();
    for list in fixed {
        if let Some(&bad) = list.iter().flatten().find(|&&v| v >= n) {
            return Err(SolverError::UnknownVertex {
                vertex: bad,
                count: n,
            }
            .into());
        }
    }
    Ok(())
}

/// Folds `mesh` in simulation mode toward `amount` of its targets (§5), holding the face
/// nearest the middle, polished and with every crease's fold angle recorded: what
/// `crease fold --amount` and the studio's Fold both do, so a fold in the studio behaves
/// as the command on the saved design.
pub fn fold_mesh(
    mesh: Mesh,
    amount: f64,
    progress: Progress,
) -> Result<(Mesh, FoldReport), PipelineError> {
    crate::limits::FRACTION.check("fold amount", amount)?;
    let anchor = Solver::default_fixed(&mesh, &[]);
    let (mut mesh, report) =
        fold_phase(mesh, amount, &anchor, &Options::default(), "fold", progress)?;
    record_fold_angles(&mut mesh);
    Ok((mesh, report))
}

/// Folds `mesh` in simulation mode toward `amount` of its targets, holding `anchor`, and
/// polishes the result: a saved state is unfolded for cutting, isometric to ~1e-12.
/// The job's fold before any drag: to `fold` when asked, else out of the plane when
/// the design starts flat and is about to move (a flat sheet has no direction to fold
/// in), else none.
fn first_fold(
    mesh: Mesh,
    fold: Option<f64>,
    moves: bool,
    anchor: &[usize],
    options: &Options,
    progress: Progress,
) -> Result<(Mesh, Option<FoldReport>), PipelineError> {
    let (amount, phase) = match fold {
        Some(amount) => {
            crate::limits::FRACTION.check("fold amount", amount)?;
            (amount, "fold")
        }
        None if moves && is_flat_start(&mesh) => (LEAVE_FLAT_AMOUNT, "leave flat"),
        None => return Ok((mesh, None)),
    };
    let (folded, report) = fold_phase(mesh, amount, anchor, options, phase, progress)?;
    Ok((folded, Some(report)))
}

fn fold_phase(
    mesh: Mesh,
    amount: f64,
    anchor: &[usize],
    options: &Options,
    phase: &str,
    progress: Progress,
) -> Result<(Mesh, FoldReport), PipelineError> {
    let mut solver = Solver::new(mesh, Mode::folding_set(), anchor, options.clone())?;
    let report = fold_toward(&mut solver, amount, 4000, &mut |k| progress(phase, k, 4000))?;
    solver.polish(crate::tolerance::SAVED_RESIDUAL);
    Ok((solver.into_mesh(), report))
}

/// The drags of a job, stage by stage (§3, §5), from a state corrected onto the
/// conditions; the result polished from the solver's working 1e-8 to 1e-12, so that the
/// design's unfolding is isometric to well under 1e-9.
fn drag_phase(
    solver: &mut Solver,
    stages: &[Stage],
    radius: Option<f64>,
    remesh: Option<f64>,
    keep_partial: bool,
    progress: Progress,
) -> Result<Vec<DragReport>, PipelineError> {
    solver.correct()?;
    let radius = radius.unwrap_or_else(|| crate::solver::default_radius(solver.mesh().positions()));
    crate::limits::RADIUS.check("--radius", radius)?;
    let total: usize = stages.iter().map(|s| s.steps).sum();
    let mut done = 0;
    let mut drags = Vec::new();
    let keep_order = solver.conditions().families.contains(&Family::LayerOrder);
    let mut check = |s: &Solver| keep_order.then(|| lost_layer_order(s)).flatten();
    for stage in stages {
        drags.push(run_stage(
            solver,
            stage,
            radius,
            remesh,
            &mut check,
            keep_partial,
            &mut || {
                done += 1;
                progress("drag", done, total)
            },
        )?);
        if drags.last().is_some_and(|d| d.stalled) {
            break;
        }
    }
    solver.polish(crate::tolerance::SAVED_RESIDUAL);
    Ok(drags)
}

/// The fold, as a fraction of each crease's target, a drag from the flat sheet starts
/// from. The flat state is a singular point (see `solver::fold`): every crease's
/// fold-angle range (§2.4) is at its end there and the constraints' second-order terms
/// forbid most first-order motions, so a drag from it does not converge. 5% (9° on a ±180°
/// crease) is enough to pick the assignment's own branch and small enough to leave the
/// design's shape to the drag.
pub const LEAVE_FLAT_AMOUNT: f64 = 0.05;

/// A mesh lying in its flat state with creases that should fold: every crease with a
/// target has fold angle below 1e-6 rad in the 3D form.
pub fn is_flat_start(mesh: &Mesh) -> bool {
    let reference = Reference::new(mesh);
    let mut creases = (0..mesh.edges().len())
        .filter(|&e| mesh.edges()[e].target != 0.0)
        .peekable();
    creases.peek().is_some()
        && creases.all(|e| {
            tracked_fold_angle(mesh, &reference, mesh.positions(), e)
                .is_none_or(|(rho, _)| rho.abs() < crate::tolerance::VERIFIED_RESIDUAL)
        })
}

/// Gives every untwisted facet line (target 0, flat or join) the twist allowance α of
/// §2.4, which must lie in [0, 1).
pub fn set_alpha(mesh: &mut Mesh, alpha: f64) -> Result<(), PipelineError> {
    crate::limits::ALPHA.check("alpha", alpha)?;
    for e in mesh.edges_mut() {
        if e.target == 0.0 && matches!(e.assignment, Assignment::Flat | Assignment::Join) {
            e.alpha = alpha;
        }
    }
    Ok(())
}

/// Makes a solved mesh the file `deform` writes: each crease's fold angle recorded and,
/// when lengths changed (`relaid`: design mode moved it), the crease pattern unfolded
/// anew from the 3D form.
pub fn finish_design(mesh: &mut Mesh, relaid: bool) -> Result<(), PipelineError> {
    record_fold_angles(mesh);
    // A tube has no crease pattern of its own: its strip is unfolded when it is written
    // or cut (`geometry::unfold::sheet_of`).
    if relaid && !mesh.is_tube() {
        let pattern = crease_pattern_of(mesh, PatternFrom::Form)?.into_owned();
        mesh.set_crease_pattern(pattern);
    }
    Ok(())
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
    let paper = match mesh.crease_pattern() {
        Some(f) => {
            let (a, b) = crate::mesh::bounds(f);
            (b - a).norm()
        }
        None => size,
    };
    let total: usize = stages
        .iter()
        .map(|s| s.steps)
        .fold(0, usize::saturating_add);
    crate::limits::STEPS.check_count("steps in all", total as u64)?;
    for stage in stages {
        crate::limits::STEPS.check_count("steps", stage.steps as u64)?;
        for (k, m) in stage.moves.iter().enumerate() {
            if stage.moves[..k].iter().any(|o| o.vertex == m.vertex) {
                return Err(PipelineError::Input(format!(
                    "vertex {} is dragged twice in one stage: give it one target",
                    m.vertex
                )));
            }
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
                Mode::Design => crate::limits::DRAG_REACH_IN_SIZES * size,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Vec2;

    #[test]
    fn a_sheet_resize_is_reported_past_its_threshold_and_not_below() {
        let mut mesh = crate::io::fold::parse(include_str!("../../patterns/bird-base.fold"))
            .expect("a bundled pattern parses");
        let size = mesh.crease_pattern_size().unwrap();
        let stretched = |by: f64| {
            let pattern: Vec<Vec2> = mesh
                .crease_pattern()
                .unwrap()
                .iter()
                .map(|p| Vec2::new(p.x + by * p.x / size.x, p.y))
                .collect();
            pattern
        };
        let (under, over) = (
            stretched(0.9 * SHEET_RESIZE_MM),
            stretched(1.1 * SHEET_RESIZE_MM),
        );
        mesh.set_crease_pattern(under);
        assert_eq!(SheetResize::between(Some(size), &mesh), None);
        mesh.set_crease_pattern(over);
        let resize = SheetResize::between(Some(size), &mesh).expect("past the threshold");
        assert_eq!(resize.before, size);
        assert!((resize.after.x - size.x - 1.1 * SHEET_RESIZE_MM).abs() < 1e-9);
        assert_eq!(SheetResize::between(None, &mesh), None);
    }
}

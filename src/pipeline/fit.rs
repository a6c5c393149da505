//! The fit of a design to a target surface as a job (`crease fit`, a script's `[fit]`,
//! the studio's Fit button): placement, the pull (see [`crate::fit`]), and the report the
//! maker reads (`OUT.fit.json`), with every figure measured on the design as written.

use super::PipelineError;
use crate::constraints::{ConstraintSet, Family, Reference};
use crate::fit::{measure, place, FitOptions, Fitter, Placement, Stop, SurfaceChoice};
use crate::mesh::{Mesh, Vec3};
use crate::solver::{Resistance, Solver};
use crate::surface::TriSurface;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// What a design job fits its design to, and how.
#[derive(Clone, Debug)]
pub struct FitStage {
    /// The target surface (mm), never moved.
    pub target: Arc<TriSurface>,
    /// The target's name for the report (its file).
    pub target_name: String,
    /// Place the design on the target rigidly first (and hold no anchor while pulling).
    pub align: bool,
    /// Steps, goal, surface points, remeshing.
    pub options: FitOptions,
}

/// `OUT.fit.json`: how close the fit came and what stopped it. Written and read through
/// this one type.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FitReport {
    /// The target surface's file.
    pub target: String,
    /// How the surface points were chosen ("mid" or "all").
    pub surface: String,
    /// The measured points: each is the mean of its group's vertices (ids of the
    /// written design); every vertex is in at least one group.
    pub surface_groups: Vec<Vec<usize>>,
    /// Distances of the written design's surface points to the target.
    pub distance: Distances,
    /// The same after the rigid placement, before any pull.
    pub placed: Distances,
    /// Each chosen condition's largest residual on the written design.
    pub conditions: Vec<ConditionResidual>,
    /// Pairs of faces of the written design passing through each other.
    pub self_intersections: usize,
    /// Accepted steps.
    pub steps: usize,
    /// Steps that failed and were retried smaller.
    pub failed_steps: usize,
    /// Why the last step the layer-order check refused was undone (`layer-order` among
    /// the conditions), if one was.
    #[serde(default)]
    pub held_back: Option<String>,
    /// Newton iterations in all.
    pub newton_iterations: usize,
    /// Wall time of the fit (s).
    pub seconds: f64,
    /// "converged", "stalled", "step limit" or "blocked".
    pub stopped: String,
    /// Stopped at the step limit while the largest distance was still falling
    /// ([`crate::fit::largest_still_falling`]): more steps bring it nearer.
    #[serde(default)]
    pub still_improving: bool,
    /// The step after which the pull stalled short of the goal and Gauss–Newton steps
    /// took over ([`crate::fit::gauss_newton`]; an index into `history`), if they did.
    #[serde(default)]
    pub gauss_newton_from: Option<usize>,
    /// When the goal was not met and the fit was no longer improving: the condition
    /// refusing most of what the target still asks for.
    pub blocked_by: Option<BlockedBy>,
    /// The rigid placement applied before the pull: x ↦ R x + t (rows of R, t in mm).
    pub placement: PlacementRecord,
    /// (RMS, largest) distance in mm after each step, the placed state first.
    pub history: Vec<[f64; 2]>,
}

/// Distances of the surface points to the target.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Distances {
    /// The largest: the one-sided Hausdorff distance from the points to the target (mm).
    pub hausdorff_mm: f64,
    /// Root mean square (mm).
    pub rms_mm: f64,
    /// The bounding-box diagonal of the design measured (mm).
    pub diagonal_mm: f64,
    /// `hausdorff_mm` over the diagonal.
    pub hausdorff_relative: f64,
    /// `rms_mm` over the diagonal.
    pub rms_relative: f64,
    /// The goal for `hausdorff_mm` (mm).
    pub goal_mm: f64,
    /// Whether the goal is met.
    pub met: bool,
    /// The group farthest from the target.
    pub worst_group: usize,
}

/// One condition's largest residual.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConditionResidual {
    /// The condition family.
    pub name: String,
    /// Largest |residual| (radians, or relative for lengths).
    pub largest_residual: f64,
}

/// What held the fit back.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BlockedBy {
    /// The condition refusing the most motion.
    pub condition: String,
    /// Where it refuses most.
    pub element: String,
    /// The share of the remaining wish it and the others refuse (0–1).
    pub refused_share: f64,
    /// Each condition's refused motion (mm), largest first.
    pub by_condition: Vec<(String, f64)>,
}

/// A rigid placement in the report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlacementRecord {
    /// Whether a placement was searched for (`--no-align`: false, identity).
    pub aligned: bool,
    /// Rows of the rotation.
    pub rotation: [[f64; 3]; 3],
    /// The translation (mm).
    pub translation: [f64; 3],
}

impl FitReport {
    /// Why the fitted design is not written unless the user insists: it passes through
    /// itself (paper cannot), naming how many pairs of faces cross. `None` when it may be.
    pub fn refusal(&self) -> Option<String> {
        (self.self_intersections > 0).then(|| {
            format!(
                "the fitted design passes through itself ({} pairs of faces cross)",
                self.self_intersections
            )
        })
    }

    /// One paragraph for the terminal.
    pub fn summary(&self) -> String {
        let d = &self.distance;
        let mut s = format!(
            "fit: {} after {} steps ({:.1} s): largest distance {:.3} mm ({:.2}% of the {:.0} mm diagonal; goal {:.3} mm {}), RMS {:.3} mm; placed at {:.3} mm",
            self.stopped,
            self.steps,
            self.seconds,
            d.hausdorff_mm,
            100.0 * d.hausdorff_relative,
            d.diagonal_mm,
            d.goal_mm,
            if d.met { "met" } else { "NOT met" },
            d.rms_mm,
            self.placed.hausdorff_mm,
        );
        let worst = self
            .conditions
            .iter()
            .max_by(|a, b| a.largest_residual.total_cmp(&b.largest_residual));
        if let Some(c) = worst {
            s += &format!(
                "\nconditions held: largest residual {:.1e} ({})",
                c.largest_residual, c.name
            );
        }
        if self.self_intersections > 0 {
            s += &format!(
                "\nwarning: {} pairs of faces pass through each other",
                self.self_intersections
            );
        }
        if let Some(why) = &self.held_back {
            s += &format!("\nheld back: a step was undone because {why}");
        }
        if let Some(k) = self.gauss_newton_from {
            if let Some([_, largest]) = self.history.get(k) {
                s += &format!(
                    "\nthe pull stalled at {largest:.3} mm after step {k}; Gauss–Newton steps went on from there"
                );
            }
        }
        if let (true, Some(last)) = (self.still_improving, self.history.last()) {
            let window = (self.history.len() - 1).min(crate::fit::STALL_WINDOW);
            s += &format!(
                "\nstill improving at the step limit: the largest distance fell from {:.3} to {:.3} mm over the last {window} steps; raise --steps (it is {}) to go on",
                self.history[self.history.len() - 1 - window][1],
                last[1],
                self.steps,
            );
        }
        if let Some(b) = &self.blocked_by {
            s += &format!(
                "\nblocked by {} at {} ({:.0}% of the remaining pull is refused by the conditions)",
                b.condition,
                b.element,
                100.0 * b.refused_share
            );
        }
        s
    }
}

/// What the pull left for the report, before the design is finished.
pub(super) struct FitPhase {
    stage_target: String,
    surface: SurfaceChoice,
    placement: Placement,
    aligned: bool,
    placed: (f64, f64),
    history: Vec<(f64, f64)>,
    failures: usize,
    /// Why the last step the layer-order check refused was undone.
    held_back: Option<String>,
    gauss_newton_from: Option<usize>,
    stop: Stop,
    resistance: Option<Resistance>,
    goal: Option<f64>,
    seconds: f64,
}

/// The fit of a job: `mesh` placed on the target (when asked) and pulled onto it under
/// `set`, holding `pins` (placed on the target, the design holds no anchor unless pinned:
/// rigid motions stay in the null space and the placement keeps refining while it bends;
/// without the placement, the face nearest the middle). Returns the fitted mesh, what
/// the report needs and the fit's own solver counters.
pub(super) fn fit_phase(
    mesh: Mesh,
    stage: &FitStage,
    pins: Option<&[usize]>,
    set: &ConstraintSet,
    options: &crate::solver::Options,
    progress: super::Progress,
) -> Result<(Mesh, FitPhase, crate::solver::Stats), PipelineError> {
    let (placed, placement) = placed(mesh, stage);
    let anchor = match (pins, stage.align) {
        (Some(p), _) => p.to_vec(),
        (None, true) => Vec::new(),
        (None, false) => Solver::default_fixed(&placed, &[]),
    };
    let fit_options = crate::fit::solver_options(options);
    let mut solver = Solver::new(placed, set.clone(), &anchor, fit_options)?;
    solver.correct()?;
    let phase = pull(&mut solver, stage, placement, progress)?;
    let stats = solver.stats.clone();
    Ok((solver.into_mesh(), phase, stats))
}

/// Places `mesh` on the target (when asked), and returns it with the placement.
fn placed(mesh: Mesh, stage: &FitStage) -> (Mesh, Placement) {
    if !stage.align {
        return (mesh, Placement::identity());
    }
    let mut mesh = mesh;
    let groups = crate::fit::surface_groups(&mesh, stage.options.surface);
    let m = measure(mesh.positions(), &groups, &stage.target);
    let x = mesh.positions();
    let front = crate::geometry::vector_area(x, mesh.faces());
    let (lo, hi) = mesh.bounding_box();
    let (placement, _) = place(&m.points, front, &stage.target, (hi - lo).norm());
    let moved: Vec<Vec3> = x.iter().map(|&p| placement.apply(p)).collect();
    mesh.set_positions(moved);
    (mesh, placement)
}

/// The pull (see [`crate::fit`]) on a solver already corrected onto its conditions;
/// leaves the solver on the best state reached, polished.
fn pull(
    solver: &mut Solver,
    stage: &FitStage,
    placement: Placement,
    progress: super::Progress,
) -> Result<FitPhase, PipelineError> {
    let started = std::time::Instant::now();
    let mut fitter = Fitter::new(solver, stage.target.clone(), stage.options.clone());
    let placed = fitter.history[0];
    let max = stage.options.max_steps;
    let keep_order = solver.conditions().families.contains(&Family::LayerOrder);
    let mut check = super::step_order::lost_layer_order;
    let check = keep_order.then_some(&mut check);
    let stop = fitter.run(solver, check, &mut |k, _| progress("fit", k, max))?;
    progress("fit", max, max);
    fitter.settle_on_best(solver);
    let resistance = match stop {
        Stop::Converged => None,
        _ => fitter.resistance(solver)?,
    };
    solver.polish(crate::tolerance::SAVED_RESIDUAL);
    Ok(FitPhase {
        stage_target: stage.target_name.clone(),
        surface: stage.options.surface,
        placement,
        aligned: stage.align,
        placed,
        history: fitter.history.clone(),
        failures: fitter.failures,
        held_back: fitter.held_back.clone(),
        gauss_newton_from: fitter.gauss_newton_from,
        stop,
        resistance,
        goal: stage.options.goal,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// The report on the finished design `mesh` (its positions as written).
pub(super) fn report(
    phase: FitPhase,
    mesh: &Mesh,
    target: &TriSurface,
    set: &ConstraintSet,
    stats: &crate::solver::Stats,
) -> FitReport {
    let groups = crate::fit::surface_groups(mesh, phase.surface);
    let m = measure(mesh.positions(), &groups, target);
    let (lo, hi) = mesh.bounding_box();
    let diagonal = (hi - lo).norm();
    let goal = phase
        .goal
        .unwrap_or(crate::fit::DEFAULT_GOAL_FRACTION * diagonal);
    let distances = |largest: f64, rms: f64, worst: usize| Distances {
        hausdorff_mm: largest,
        rms_mm: rms,
        diagonal_mm: diagonal,
        hausdorff_relative: largest / diagonal,
        rms_relative: rms / diagonal,
        goal_mm: goal,
        met: largest <= goal,
        worst_group: worst,
    };
    let rows = set.evaluate_values(mesh, &Reference::new(mesh), mesh.positions());
    let conditions = set
        .families
        .iter()
        .map(|&f| ConditionResidual {
            name: f.name().to_string(),
            largest_residual: rows
                .residuals
                .iter()
                .zip(&rows.labels)
                .filter(|(_, l)| l.0 == f)
                .fold(0.0, |a, (r, _)| a.max(r.abs())),
        })
        .collect();
    let met = m.largest <= goal;
    let stopped = match (phase.stop, met) {
        (Stop::Converged | Stop::Stalled, true) => Stop::Converged,
        (Stop::Converged, false) => Stop::Stalled,
        (s, _) => s,
    };
    let improving =
        !met && phase.stop == Stop::StepLimit && crate::fit::largest_still_falling(&phase.history);
    let r = phase.placement.rotation;
    FitReport {
        target: phase.stage_target,
        surface: phase.surface.name().to_string(),
        distance: distances(m.largest, m.rms, m.worst),
        placed: distances(phase.placed.1, phase.placed.0, 0),
        surface_groups: groups,
        conditions,
        self_intersections: crate::fab::self_intersections(mesh).len(),
        steps: stats.steps,
        failed_steps: phase.failures,
        held_back: phase.held_back,
        newton_iterations: stats.newton_iterations,
        seconds: phase.seconds,
        stopped: stopped.name().to_string(),
        still_improving: improving,
        gauss_newton_from: phase.gauss_newton_from,
        blocked_by: phase
            .resistance
            .filter(|_| !met && !improving)
            .map(|r| BlockedBy {
                condition: r.family.name().to_string(),
                element: r.element.to_string(),
                refused_share: r.refused,
                by_condition: r
                    .by_family
                    .iter()
                    .map(|(f, v)| (f.name().to_string(), *v))
                    .collect(),
            }),
        placement: PlacementRecord {
            aligned: phase.aligned,
            rotation: [0, 1, 2].map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]),
            translation: phase.placement.translation.into(),
        },
        history: phase.history.iter().map(|&(a, b)| [a, b]).collect(),
    }
}

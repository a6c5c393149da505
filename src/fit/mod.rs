//! Fitting a design to a target surface (`crease fit`): the paper's design method (§3,
//! §5) with the wished motion dx₀ taken from a shape instead of a mouse.
//!
//! Each step measures the design's surface points ([`groups`]: a facet's mean, or a
//! vertex) against the target, asks every vertex to cover the mean of its groups' gaps
//! to their nearest target points (capped at a fraction of the mean edge, so the Euler
//! step stays small), and hands that wish to the solver: it is projected into the null
//! space of the chosen conditions (eq. 10) and corrected by Newton, so every condition
//! holds at every step exactly as in a drag. Without an anchor the rigid motions are
//! in that null space too, so the placement keeps refining while the design bends.
//! When these steps stall short of the goal, the fit goes on with Gauss–Newton steps on
//! the same energy, in the same null space ([`gauss_newton`]): where the conditions let
//! only a little of the pull through, gradient steps creep, and a Gauss–Newton step
//! takes the whole way along those directions at once.
//! The fit stops when the distance stops improving, and names the condition that
//! refuses most of what the target still asks for ([`crate::solver::Resistance`]).

pub mod align;
mod fitter;
pub mod gauss_newton;
pub mod groups;

pub use align::{kabsch, place, Placement};
pub use fitter::Fitter;
pub use groups::{surface_groups, SurfaceChoice};

use crate::mesh::Vec3;
use crate::surface::TriSurface;

/// Steps a fit takes at most unless told otherwise.
pub const DEFAULT_STEPS: usize = 400;

/// The distance goal unless told otherwise: this fraction of the fitted design's
/// bounding-box diagonal (one-sided Hausdorff distance of the surface points).
pub const DEFAULT_GOAL_FRACTION: f64 = 0.01;

/// The largest wish a step gives any vertex, as a fraction of the mean edge: small
/// enough for Newton to return to the conditions from the Euler step.
const STEP_CAP_EDGES: f64 = 0.5;

/// The weight of the preference for the starting edge lengths in each step's wish, as
/// a spring constant per unit of length change: an edge off its length by δ asks its
/// ends to close a fifth of δ, against the target's pull of the whole gap.
const KEEP_LENGTHS: f64 = 0.2;

/// The same for the distances between neighbouring surface points: weaker, since
/// taking a doubly curved target needs the mid-surface to change its lengths a little.
const KEEP_SIZE: f64 = 0.05;

/// The softness at which a settled fit stops loosening (three quarterings).
const MIN_SOFTNESS: f64 = 1.0 / 64.0;

/// Steps over which a fit must improve its distance by `STALL_IMPROVEMENT` to go on.
pub const STALL_WINDOW: usize = 15;

/// The relative improvement of the RMS and largest distance over [`STALL_WINDOW`]
/// steps below which the fit has stopped improving.
const STALL_IMPROVEMENT: f64 = 0.005;

/// The smallest step cap Newton's effort alone may shrink the cap to, as a fraction of
/// the largest (failed steps shrink it further).
const MIN_CAP_FRACTION: f64 = 0.05;

/// Times the solver halves a fit's step before the step fails: the fit then shrinks the
/// next step itself, so a step the conditions refuse costs three corrections, not seven.
pub const FIT_HALVINGS: usize = 2;

/// The solver settings of a fit, from the job's: steps halved [`FIT_HALVINGS`] times
/// before they fail, and no predicted corrections. The predictor extrapolates the
/// corrections of the last steps, which suits a drag's steady pull; a fit's wish turns
/// from step to step as the design settles onto the target, so predictions miss and
/// restart: on the 5k-vertex benchmark the fit took 10.8 s with them and 5.8–6.7 s
/// without (the designs below 4,096 faces never predict, so they are unchanged).
pub fn solver_options(job: &crate::solver::Options) -> crate::solver::Options {
    crate::solver::Options {
        max_halvings: FIT_HALVINGS,
        predict: Some(false),
        ..job.clone()
    }
}

/// Failed steps in a row (each already halved by the solver) that end a fit
/// as blocked.
const MAX_CONSECUTIVE_FAILURES: usize = 4;

/// A fit whose largest distance falls to this fraction of its goal has converged: what
/// is left is far below anything paper shows (a tenth of 1% of the diagonal by default).
const CONVERGED_FRACTION: f64 = 0.1;

/// How the surface points stand against the target.
#[derive(Clone, Debug, PartialEq)]
pub struct Measure {
    /// Each group's point (the mean of its vertices).
    pub points: Vec<Vec3>,
    /// Each point's nearest target point.
    pub nearest: Vec<Vec3>,
    /// Largest distance: the one-sided Hausdorff distance from the points to the target.
    pub largest: f64,
    /// The group with the largest distance.
    pub worst: usize,
    /// Root mean square of the distances.
    pub rms: f64,
}

/// The mean of a group's vertices.
fn group_point(x: &[Vec3], group: &[usize]) -> Vec3 {
    group.iter().map(|&v| x[v]).sum::<Vec3>() / group.len() as f64
}

/// Pairs of groups (g < h) that share a vertex or hold the two ends of an edge.
fn neighbouring_groups(mesh: &crate::mesh::Mesh, groups: &[Vec<usize>]) -> Vec<(usize, usize)> {
    let mut of_vertex: Vec<Vec<usize>> = vec![Vec::new(); mesh.vertex_count()];
    for (g, members) in groups.iter().enumerate() {
        members.iter().for_each(|&v| of_vertex[v].push(g));
    }
    let mut pairs = std::collections::BTreeSet::new();
    let mut add = |a: &[usize], b: &[usize]| {
        for &g in a {
            for &h in b {
                if g != h {
                    pairs.insert((g.min(h), g.max(h)));
                }
            }
        }
    };
    for list in &of_vertex {
        add(list, list);
    }
    for e in mesh.edges() {
        add(&of_vertex[e.vertices[0]], &of_vertex[e.vertices[1]]);
    }
    pairs.into_iter().collect()
}

/// The surface points of `groups` at `x` and their distances to `target`.
pub fn measure(x: &[Vec3], groups: &[Vec<usize>], target: &TriSurface) -> Measure {
    let points: Vec<Vec3> = groups.iter().map(|g| group_point(x, g)).collect();
    let mut nearest = Vec::with_capacity(points.len());
    let (mut largest, mut worst, mut sum) = (0.0f64, 0, 0.0);
    for (k, &p) in points.iter().enumerate() {
        let c = target.closest(p);
        if c.distance > largest {
            (largest, worst) = (c.distance, k);
        }
        sum += c.distance * c.distance;
        nearest.push(c.point);
    }
    Measure {
        rms: (sum / points.len().max(1) as f64).sqrt(),
        points,
        nearest,
        largest,
        worst,
    }
}

/// Whether a fit's distances, (RMS, largest) after each step, still improve: either
/// fell by `STALL_IMPROVEMENT` over the last [`STALL_WINDOW`] steps.
fn still_improving(history: &[(f64, f64)]) -> bool {
    let Some(&(rms0, max0)) = history
        .len()
        .checked_sub(1 + STALL_WINDOW)
        .map(|i| &history[i])
    else {
        return true;
    };
    let &(rms, largest) = history.last().expect("the window's start is in it");
    let improved = |before: f64, now: f64| now < before * (1.0 - STALL_IMPROVEMENT);
    improved(rms0, rms) || improved(max0, largest)
}

/// Whether the largest distance, the one the goal is set on, still fell by
/// `STALL_IMPROVEMENT` over the last [`STALL_WINDOW`] steps of `history` ((RMS,
/// largest) after each step): a fit stopped at its step limit so wants more steps,
/// where one that no longer comes nearer is held by the conditions.
pub fn largest_still_falling(history: &[(f64, f64)]) -> bool {
    let Some(first) = history.len().checked_sub(1 + STALL_WINDOW) else {
        return history.len() > 1 && history[history.len() - 1].1 < history[0].1;
    };
    history[history.len() - 1].1 < history[first].1 * (1.0 - STALL_IMPROVEMENT)
}

/// Why a fit stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// The distance stopped improving with the goal met.
    Converged,
    /// The distance stopped improving short of the goal.
    Stalled,
    /// The step limit came first.
    StepLimit,
    /// Steps kept failing however small: the conditions hold the design where it is.
    Blocked,
}

impl Stop {
    /// The word in reports.
    pub fn name(self) -> &'static str {
        match self {
            Stop::Converged => "converged",
            Stop::Stalled => "stalled",
            Stop::StepLimit => "step limit",
            Stop::Blocked => "blocked",
        }
    }
}

/// Settings of a fit.
#[derive(Clone, Debug)]
pub struct FitOptions {
    /// Which points represent the surface.
    pub surface: SurfaceChoice,
    /// Steps at most.
    pub max_steps: usize,
    /// The distance goal in mm; `None`: [`DEFAULT_GOAL_FRACTION`] of the diagonal.
    pub goal: Option<f64>,
    /// Collapse edges shorter than this fraction of the mean edge (§4).
    pub remesh: Option<f64>,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            surface: SurfaceChoice::Mid,
            max_steps: DEFAULT_STEPS,
            goal: None,
            remesh: None,
        }
    }
}

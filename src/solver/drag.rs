//! Dragging (§5): Euler integration of a user's drag. Each step asks the dragged vertices
//! to cover an equal share of their remaining way, spreads that wish smoothly to nearby
//! vertices (a surface, not a single point, is being pulled), projects it into the null
//! space, and corrects.

use super::{Solver, SolverError};
use crate::mesh::Vec3;
use serde::Deserialize;

/// One vertex pulled toward a target.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Move {
    /// The vertex.
    pub vertex: usize,
    /// Where it should go (mm).
    pub to: [f64; 3],
}

/// Moves made together over a number of steps.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Stage {
    /// Euler steps for this stage.
    pub steps: usize,
    /// The vertices pulled and their targets.
    pub moves: Vec<Move>,
}

/// What a drag did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DragReport {
    /// For each move of each stage: distance to target before and after (mm).
    pub distances: Vec<(usize, f64, f64)>,
    /// Edges collapsed during the stage.
    pub collapses: usize,
    /// Flat creases flipped during the stage.
    pub flips: usize,
    /// Why the stage stopped before its last step: a step that, even halved
    /// [`KEEP_HALVINGS`] times, would lose what the caller keeps (the layer order), or
    /// (when the caller keeps a partial drag) a step that could not be corrected.
    pub refused: Option<String>,
    /// The stage stopped at a step Newton could not correct, even halved (see
    /// [`run_stage`]'s `keep_partial`): the state is the last step's, which held every
    /// condition.
    pub stalled: bool,
}

/// Halvings of a drag step the caller's check refuses before the stage stops there.
pub const KEEP_HALVINGS: usize = 4;

/// A check on each drag step the conditions' rows cannot express (the layer order of the
/// flat-folded state): `None` to keep the step, else why it is refused.
pub type StepCheck<'a> = &'a mut dyn FnMut(&Solver) -> Option<String>;

/// Adds to `wish` the motion of pulling vertex `v` by `share`, spread to the surface
/// around it with the Gaussian weight exp(−|x_u − x_v|² / r²): a surface, not a single
/// point, is being pulled, and the null-space projection (eq. 10) then keeps what the
/// conditions allow.
pub fn pull(x: &[Vec3], v: usize, share: Vec3, radius: f64, wish: &mut [Vec3]) {
    let centre = x[v];
    for (u, d) in wish.iter_mut().enumerate() {
        let w = (-(x[u] - centre).norm_squared() / (radius * radius)).exp();
        *d += share * w;
    }
}

/// The falloff radius of a drag unless one is given: a quarter of the diagonal of the
/// positions' bounding box (`deform`, scripts and the studio alike).
pub fn default_radius(x: &[Vec3]) -> f64 {
    let (lo, hi) = crate::mesh::bounds(x);
    0.25 * (hi - lo).norm()
}

/// The mean edge length at `x`.
pub fn mean_edge(mesh: &crate::mesh::Mesh, x: &[Vec3]) -> f64 {
    let e = mesh.edges();
    e.iter()
        .map(|e| (x[e.vertices[1]] - x[e.vertices[0]]).norm())
        .sum::<f64>()
        / e.len().max(1) as f64
}

/// Longest pull of one step of a pointer drag, in mean edge lengths: past about half an
/// edge an Euler step leaves Newton's basin, so an interactive drag is integrated in
/// short steps toward wherever the pointer is.
pub const POINTER_STEP_CAP: f64 = 0.1;

/// How near the pointer a dragged vertex counts as arrived, in mean edge lengths; within
/// a step of the pointer, a step that brings it less than this nearer counts as held.
pub const ARRIVED_EDGES: f64 = 1e-3;

/// What one step of a pointer drag did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PointerStep {
    /// The vertex moved; it may go on.
    Moved,
    /// The vertex is where the pointer is (within [`ARRIVED_EDGES`] of the mean edge).
    Arrived,
    /// The step was taken but the vertex barely moved toward the pointer (or, within a
    /// step of it, came less than [`ARRIVED_EDGES`] of the mean edge nearer): the
    /// conditions hold it there.
    Held,
}

/// One Euler step of an interactive drag (§5): vertex `v` pulled a bounded share
/// ([`POINTER_STEP_CAP`]) of its way to `target`, spread over the surface within
/// [`default_radius`], projected into the null space (eq. 10) and corrected. The studio
/// calls it while the pointer is held, and [`pointer_release`] when it is let go; a
/// scripted stage is [`run_stage`].
///
/// Where the solver predicts its corrections ([`Solver::predicts`]: by default on
/// meshes of [`super::PREDICTOR_FACES`] faces and more) the step is a
/// [`Solver::live_step`], corrected to what a screen shows: there a step's time is its
/// solves and refactorisations, and the studio's 10k-vertex Miura-ori follows the
/// pointer at 14–17 steps a second instead of 6–8. Smaller meshes step at full
/// precision, fast enough as they are (60 a second at 256 vertices, the pointer's rate).
pub fn pointer_step(
    solver: &mut Solver,
    v: usize,
    target: Vec3,
) -> Result<PointerStep, SolverError> {
    let x = solver.positions();
    let gap = target - x[v];
    let mean = mean_edge(solver.mesh(), x);
    if gap.norm() < ARRIVED_EDGES * mean {
        return Ok(PointerStep::Arrived);
    }
    let share = if gap.norm() > POINTER_STEP_CAP * mean {
        gap * (POINTER_STEP_CAP * mean / gap.norm())
    } else {
        gap
    };
    let mut wish = vec![Vec3::zeros(); x.len()];
    pull(x, v, share, default_radius(x), &mut wish);
    let before = x[v];
    // A live step's chord policy is the predicting solver's; the two go together.
    if solver.predicts() {
        solver.live_step(&wish)?;
    } else {
        solver.step(&wish)?;
    }
    let progress = (solver.positions()[v] - before).dot(&share) / share.norm();
    // Held when the conditions pass almost none of the pull; or when, within one step's
    // reach of the pointer, a step brings the vertex less than the arrival distance
    // nearer: it is creeping toward the pointer by ever smaller steps as the conditions
    // pass ever less of the pull (a layer-order drag of the waterbomb closed its last
    // 0.1 mm at 0.001 mm a step and never reported itself settled).
    let creeping = gap.norm() <= POINTER_STEP_CAP * mean && progress < ARRIVED_EDGES * mean;
    Ok(if progress < 1e-3 * share.norm() || creeping {
        PointerStep::Held
    } else {
        PointerStep::Moved
    })
}

/// Ends an interactive drag: the positions its live steps left (see [`pointer_step`])
/// corrected to the solver's own tolerance, as every other step leaves them. False when
/// that correction fails; the positions then stay as the last step left them.
pub fn pointer_release(solver: &mut Solver) -> bool {
    solver.polish(solver.tolerance())
}

/// Runs one stage. `progress` is called after every accepted step. A step `check`
/// refuses is undone and tried at half the length, [`KEEP_HALVINGS`] times, before the
/// stage stops with the reason ([`DragReport::refused`]).
///
/// A step whose correction fails even halved (the solver's own halvings) ends the run
/// with the error, or with `keep_partial` ends the stage there ([`DragReport::stalled`]):
/// the solver keeps the last state that held every condition, which the caller may keep.
#[allow(clippy::too_many_arguments)] // the stage, its settings and the caller's hooks
pub fn run_stage(
    solver: &mut Solver,
    stage: &Stage,
    radius: f64,
    remesh: Option<f64>,
    check: StepCheck,
    keep_partial: bool,
    progress: &mut dyn FnMut(),
) -> Result<DragReport, SolverError> {
    let mut stage = stage.clone();
    let (mut collapses, mut flips) = (0, 0);
    let n = solver.positions().len();
    for m in &stage.moves {
        if m.vertex >= n {
            return Err(SolverError::UnknownVertex {
                vertex: m.vertex,
                count: n,
            });
        }
    }
    let target = |m: &Move| Vec3::new(m.to[0], m.to[1], m.to[2]);
    let before: Vec<f64> = stage
        .moves
        .iter()
        .map(|m| (target(m) - solver.positions()[m.vertex]).norm())
        .collect();
    let mut refused = None;
    let mut stalled = false;
    for k in 0..stage.steps {
        let n = solver.positions().len();
        let x = solver.positions().to_vec();
        let mut dx0 = vec![Vec3::zeros(); n];
        for m in &stage.moves {
            let share = (target(m) - x[m.vertex]) / (stage.steps - k) as f64;
            pull(&x, m.vertex, share, radius, &mut dx0);
        }
        if let StepEnd::Refused { why, uncorrected } =
            checked_step(solver, dx0, check, keep_partial)?
        {
            refused = Some(format!("step {} of {}: {why}", k + 1, stage.steps));
            stalled = uncorrected;
            break;
        }
        if let Some(threshold) = remesh {
            let dragged: Vec<usize> = stage.moves.iter().map(|m| m.vertex).collect();
            let outcome = solver.remesh(&dragged, threshold);
            collapses += outcome.collapses;
            flips += outcome.flips;
            if let Some(map) = outcome.renumbered {
                for m in &mut stage.moves {
                    m.vertex = map[m.vertex];
                }
            }
        }
        progress();
    }
    let distances = stage
        .moves
        .iter()
        .zip(before)
        .map(|(m, b)| {
            (
                m.vertex,
                b,
                (target(m) - solver.positions()[m.vertex]).norm(),
            )
        })
        .collect();
    Ok(DragReport {
        distances,
        collapses,
        flips,
        refused,
        stalled,
    })
}

/// How one step of a stage ended.
enum StepEnd {
    /// Taken, every condition and the check held.
    Taken,
    /// Not taken (the positions are as before it): `why`, and whether it was the solver
    /// that could not correct it (rather than the check refusing it at every length).
    Refused { why: String, uncorrected: bool },
}

/// One step of `dx0` held to `check`: a step the check refuses is undone and tried at half
/// the length, [`KEEP_HALVINGS`] times; with `keep_partial`, a step the solver cannot
/// correct ends the stage instead of failing it.
fn checked_step(
    solver: &mut Solver,
    mut dx0: Vec<Vec3>,
    check: &mut dyn FnMut(&Solver) -> Option<String>,
    keep_partial: bool,
) -> Result<StepEnd, SolverError> {
    let x = solver.positions().to_vec();
    let mut halvings = 0;
    loop {
        match solver.step(&dx0) {
            Ok(_) => {}
            Err(e @ SolverError::NotConverged { .. }) if keep_partial => {
                return Ok(StepEnd::Refused {
                    why: e.to_string(),
                    uncorrected: true,
                })
            }
            Err(e) => return Err(e),
        }
        let Some(why) = check(solver) else {
            return Ok(StepEnd::Taken);
        };
        solver.restore(x.clone());
        if halvings == KEEP_HALVINGS {
            return Ok(StepEnd::Refused {
                why,
                uncorrected: false,
            });
        }
        halvings += 1;
        for d in &mut dx0 {
            *d *= 0.5;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::{ConstraintSet, Reference};
    use crate::generate::{generate, Params, PatternKind};
    use crate::solver::{Mode, Options};

    fn miura_solver(set: Option<ConstraintSet>) -> (Solver, usize) {
        let mesh = generate(&Params::defaults(PatternKind::Miura)).unwrap();
        let set = set.unwrap_or_else(|| ConstraintSet::default_for(&Reference::new(&mesh)));
        let fixed = Solver::default_fixed(&mesh, &[40]);
        (
            Solver::new(mesh, set, &fixed, Options::default()).unwrap(),
            40,
        )
    }

    #[test]
    fn a_pointer_drag_arrives_where_it_may_and_is_held_where_the_paper_cannot_go() {
        // Design mode: lifting the middle 5 mm is allowed; steps of at most a tenth of an
        // edge get there and then report arrival.
        let (mut solver, v) = miura_solver(None);
        let target = solver.positions()[v] + Vec3::new(0.0, 0.0, 5.0);
        let mut steps = 0;
        while pointer_step(&mut solver, v, target).unwrap() != PointerStep::Arrived {
            steps += 1;
            assert!(steps < 500, "the drag arrives");
        }
        let mean = mean_edge(solver.mesh(), solver.positions());
        assert!((solver.positions()[v] - target).norm() < 1e-3 * mean);
        assert!(
            steps as f64 >= 5.0 / (POINTER_STEP_CAP * mean),
            "{steps} steps"
        );
        // Simulation mode keeps every length: pulling a vertex 500 mm away is held.
        let (mut solver, v) = miura_solver(Some(Mode::simulation_set()));
        let far = solver.positions()[v] + Vec3::new(0.0, 0.0, 500.0);
        let mut outcome = PointerStep::Moved;
        for _ in 0..400 {
            outcome = match pointer_step(&mut solver, v, far) {
                Ok(s) => s,
                Err(_) => PointerStep::Held,
            };
            if outcome != PointerStep::Moved {
                break;
            }
        }
        assert_eq!(outcome, PointerStep::Held);
    }
}

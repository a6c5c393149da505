//! Folding a pattern in simulation mode: every folded crease is driven toward a fraction of
//! its target angle while the panels stay rigid. This gives the 3D states of patterns
//! without a closed form (waterbomb, Resch).
//!
//! The flat state is a singular point: every out-of-plane motion keeps lengths to first
//! order, so projecting a drive into the null space (eq. 10) mostly yields motions that
//! second-order terms forbid, and Newton undoes them. Folding therefore follows a
//! continuation of weighted least-squares problems (lengths stiff, fold goals soft,
//! Levenberg–Marquardt steps), which leaves the singular point along the assignment's own
//! mode, and ends with the exact Newton projection onto the constraints.

use super::{NormalSolver, Solver, SolverError};
use crate::constraints::{tracked_fold_angle, Element, Family};
use crate::geometry::fold_angle_gradient;
use sprs::TriMat;

/// Where folding stopped.
#[derive(Clone, Debug, PartialEq)]
pub struct FoldReport {
    /// Continuation steps taken.
    pub steps: usize,
    /// Largest |ρ − amount·target| over the folded creases at the end (radians).
    pub error: f64,
    /// Mean ρ / target over the folded creases at the end.
    pub mean_fraction: f64,
    /// The most a crease is folded against its mountain or valley sign at the end
    /// (radians): 0 unless the sign ranges had to be left out near the flat state, and
    /// then at most [`WRONG_WAY_NEAR_FLAT_RADIANS`].
    pub wrong_way: f64,
}

/// How far a crease may end folded against its sign near the flat state (radians, 0.6°):
/// creased paper flexes that far the other way and springs back, and the folding goals
/// there are a few degrees.
pub const WRONG_WAY_NEAR_FLAT_RADIANS: f64 = 0.01;

/// Weight of a fold goal against a relative length error of 1.
const GOAL_WEIGHT: f64 = 0.003;
/// Continuation steps from the current fold to the goal.
const STEPS: usize = 60;
/// Levenberg–Marquardt iterations per continuation step.
const INNER: usize = 6;

/// Folds toward `amount` × every crease's target (0 flat, 1 fully folded): the creases
/// reach `amount` of their targets on average (mean ρ / target, the meaning `generate
/// --fold` shares), each as near its own share as the rigid panels allow. The solver's
/// conditions (rigid panels, untwisted facets) hold exactly at the end.
pub fn fold_toward(
    solver: &mut Solver,
    amount: f64,
    max_steps: usize,
    progress: &mut dyn FnMut(usize),
) -> Result<FoldReport, SolverError> {
    let mesh = solver.mesh().clone();
    let creases: Vec<usize> = (0..mesh.edges().len())
        .filter(|&e| mesh.edges()[e].target != 0.0)
        .collect();
    let steps = STEPS.min(max_steps.max(1));
    let start: Vec<f64> = creases
        .iter()
        .map(|&e| solver.reference().previous_fold[e])
        .collect();
    let mut run = Continuation {
        mesh,
        creases,
        start,
        normal: NormalSolver::default(),
    };
    for k in 1..=steps {
        run.relax(solver, k as f64 / steps as f64, amount)?;
        solver.stats.steps += 1;
        progress(k);
    }
    // Least squares over every crease lands near, not on, the asked mean when the panels
    // couple the creases (a Miura-ori has one folding motion): shift the goal by the miss.
    let mut goal = amount;
    for _ in 0..MEAN_ROUNDS {
        let miss = amount - mean_fraction(solver);
        if miss.abs() < 1e-6 || run.creases.is_empty() {
            break;
        }
        goal = (goal + miss).clamp(0.0, 1.0);
        run.relax(solver, 1.0, goal)?;
    }
    // The soft solution is close; make the rigid conditions exact. Redundant rows (a
    // closed tuck's panels) slow Newton to linear convergence, so it gets more room here.
    // Away from the flat state the mountain/valley ranges no longer chatter, so the end
    // state honours them too (no crease turns the wrong way or folds through itself).
    let newton = solver.options.max_newton;
    solver.options.max_newton = newton.max(60);
    let folding = std::mem::replace(&mut solver.set, super::Mode::simulation_set());
    let mut corrected = solver.correct();
    let mut wrong_way = 0.0;
    if corrected.is_err() {
        // Near the flat state a crease's sign range still sits on its bound and makes
        // Newton's active set chatter (the bent Miura-ori's path diverged so a twentieth
        // of the way). Correct without the sign ranges, and keep that state when no
        // crease turns the wrong way by more than paper flexes back from unharmed.
        solver.set = folding.clone();
        if solver.correct().is_ok() {
            solver.set = super::Mode::simulation_set();
            let residual = solver.residual();
            if residual <= WRONG_WAY_NEAR_FLAT_RADIANS {
                wrong_way = residual;
                corrected = Ok(0);
            }
        }
    }
    solver.options.max_newton = newton;
    solver.set = folding;
    solver.forget_last_step();
    corrected?;
    let worst = run
        .creases
        .iter()
        .map(|&e| (solver.reference.previous_fold[e] - amount * run.mesh.edges()[e].target).abs())
        .fold(0.0, f64::max);
    Ok(FoldReport {
        steps,
        wrong_way,
        error: worst,
        mean_fraction: mean_fraction(solver),
    })
}

/// Rounds that shift the soft goal until the mean fraction is `amount`.
const MEAN_ROUNDS: usize = 8;

/// The folded creases, where they started, and the normal equations reused between
/// Levenberg–Marquardt iterations.
struct Continuation {
    mesh: crate::mesh::Mesh,
    creases: Vec<usize>,
    start: Vec<f64>,
    normal: NormalSolver,
}

/// Mean ρ / target over the creases with a target at the solver's state: how far along
/// its fold the sheet is, the `amount` [`fold_toward`] aims at (0 with no such crease).
pub fn mean_fraction(solver: &Solver) -> f64 {
    let edges = solver.mesh().edges();
    let (sum, count) = edges
        .iter()
        .enumerate()
        .filter(|(_, edge)| edge.target != 0.0)
        .fold((0.0, 0usize), |(sum, count), (e, edge)| {
            (
                sum + solver.reference.previous_fold[e] / edge.target,
                count + 1,
            )
        });
    sum / count.max(1) as f64
}

impl Continuation {
    /// Levenberg–Marquardt iterations toward the goals at continuation parameter `s`:
    /// each crease at start + s · (amount · target − start), lengths stiff.
    fn relax(&mut self, solver: &mut Solver, s: f64, amount: f64) -> Result<(), SolverError> {
        let mesh = &self.mesh;
        for _ in 0..INNER {
            let x = solver.x.clone();
            let mut rows = solver.set.evaluate(mesh, &solver.reference, &x);
            for (i, &e) in self.creases.iter().enumerate() {
                let Some((rho, [a, b, c, d])) = tracked_fold_angle(mesh, &solver.reference, &x, e)
                else {
                    continue;
                };
                let t = mesh.edges()[e].target;
                let goal = self.start[i] + s * (amount * t - self.start[i]);
                let grad = fold_angle_gradient(&x, a, b, c, d);
                let row = rows.push(
                    Family::FoldAngleRange,
                    Element::Edge(e),
                    GOAL_WEIGHT * (rho - goal),
                );
                for (v, g) in [a, b, c, d].into_iter().zip(grad) {
                    rows.add_gradient(row, v, g, GOAL_WEIGHT);
                }
                // A crease turning the wrong way, or past its target (a loose flap swinging
                // through its neighbour), is as stiff as a stretched panel (§2.4).
                let signed = rho * t.signum();
                let excess = if signed < 0.0 {
                    signed
                } else {
                    (signed - t.abs()).max(0.0)
                };
                if excess != 0.0 {
                    let row = rows.push(Family::FoldAngleRange, Element::Edge(e), excess);
                    for (v, g) in [a, b, c, d].into_iter().zip(grad) {
                        rows.add_gradient(row, v, g, t.signum());
                    }
                }
            }
            // Normal equations in the free variables: factorising Jᵀ as "J" gives JᵀJ + λI.
            let mut t = TriMat::new((solver.free, rows.residuals.len()));
            for &(r, col, v) in &rows.triplets {
                if let Some(c) = solver.columns[col] {
                    t.add_triplet(c, r, v);
                }
            }
            self.normal.factorise(t.to_csr())?;
            // dx = −(JᵀJ)⁻¹ Jᵀ r
            let jt_r = self.normal.apply(&rows.residuals);
            let dx: Vec<f64> = self.normal.solve(&jt_r).into_iter().map(|v| -v).collect();
            let mut next = solver.x.clone();
            solver.add_free(&mut next, &dx, 1.0);
            solver.x = next;
            solver.reference.track_folds(mesh, &solver.x);
            if dx.iter().fold(0.0f64, |m, v| m.max(v.abs())) < 1e-10 {
                break;
            }
        }
        Ok(())
    }
}

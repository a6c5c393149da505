//! The freeform solver (paper §3, §5): moves a mesh only inside the null space of the
//! constraint Jacobian (eq. 9–10), then removes the drift of nonlinear and inequality
//! conditions with Newton–Raphson steps, and tracks every fold angle's branch.

mod correct;
mod drag;
mod error;
mod fold;
mod linear;
mod mode;
mod ordering;
mod predict;
mod remesh;
mod resist;

pub use drag::{
    default_radius, mean_edge, pointer_release, pointer_step, pull, run_stage, DragReport, Move,
    PointerStep, Stage, StepCheck, ARRIVED_EDGES, KEEP_HALVINGS, POINTER_STEP_CAP,
};
pub use error::{Blocker, LinearError, SolverError};
pub use fold::{fold_toward, mean_fraction, FoldReport, WRONG_WAY_NEAR_FLAT_RADIANS};
pub use linear::{NormalSolver, Shift};
pub use mode::Mode;
pub use remesh::{collapse_edge, flip_edge, Change, Refusal, RemeshOutcome};
pub use resist::Resistance;

use crate::constraints::{ConstraintSet, Family, Reference, Rows};
use crate::mesh::{Mesh, Vec3};
use predict::Predictor;

/// Steps a factorisation of J Jᵀ may serve projections before it is recomputed.
pub const MAX_FACTOR_AGE: usize = 16;

/// [`MAX_FACTOR_AGE`] when [`Options::predict`] is on: the predicted correction learns
/// the drift a stale projection lets through, so a factor serves longer. On the 10k
/// Miura drag, 16 → 48 steps took a step from 43 to 37 ms; longer measured no faster.
pub const PREDICTED_FACTOR_AGE: usize = 48;

/// Meshes with at least this many faces predict each step's Newton correction (see
/// [`Options::predict`]) unless told otherwise. Below it steps are as they were when the
/// designs in `patterns/` were recorded, so those rebuild byte for byte; above it the
/// Newton iterations the predictor saves are where a step's time goes.
pub const PREDICTOR_FACES: usize = 4096;

/// Solver settings.
#[derive(Clone, Debug)]
pub struct Options {
    /// Residual tolerance (radians / relative length).
    pub tolerance: f64,
    /// Newton iterations per step.
    pub max_newton: usize,
    /// Times a step is halved when its correction fails.
    pub max_halvings: usize,
    /// Whether Newton starts each full step from the Euler step plus a correction
    /// predicted from the steps before (see `predict.rs`): the line through the last two
    /// corrections, or the last one alone. On a 10k-vertex Miura drag the Newton
    /// iterations per step fall from 1.74 to 0.70, and since the prediction includes
    /// the projection's part, the projection needs no solve of its own (see
    /// [`Solver::step`]). The converged state still meets `tolerance`; the path differs
    /// by the tangential part of the prediction, and a factor serves
    /// [`PREDICTED_FACTOR_AGE`] steps. `None`: on for meshes of at least
    /// [`PREDICTOR_FACES`] faces.
    pub predict: Option<bool>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            tolerance: crate::tolerance::SOLVER_RESIDUAL,
            max_newton: 20,
            max_halvings: 6,
            predict: None,
        }
    }
}

/// Counters for reports and benchmarks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Newton iterations over all steps.
    pub newton_iterations: usize,
    /// Steps that had to be halved.
    pub halvings: usize,
    /// Largest residual left after a step.
    pub worst_residual: f64,
    /// Numeric factorisations of J Jᵀ (the dominant cost of a step).
    pub factorisations: usize,
    /// Full steps whose extrapolated correction left a residual the stale factor could
    /// not remove, so Newton started again from the last correction alone.
    pub restarted_predictions: usize,
    /// Steps whose projection and correction shared their solves (see [`Solver::step`]).
    pub one_solve_steps: usize,
    /// Solves with the factor of J Jᵀ (projections and Newton iterations): after the
    /// factorisations, what a step's time goes to on a large mesh.
    pub solves: usize,
}

/// The unknowns: column `3·v + k` of the Jacobian maps to a free variable unless vertex
/// `v` is fixed. Returns the map and the number of free variables.
fn free_columns(fixed: &[bool]) -> (Vec<Option<usize>>, usize) {
    let mut columns = vec![None; 3 * fixed.len()];
    let mut free = 0;
    for v in (0..fixed.len()).filter(|&v| !fixed[v]) {
        for k in 0..3 {
            columns[3 * v + k] = Some(free);
            free += 1;
        }
    }
    (columns, free)
}

/// Which condition each row of a Jacobian is.
type Labels = Vec<(Family, crate::constraints::Element)>;

/// A mesh being deformed under a set of conditions.
pub struct Solver {
    mesh: Mesh,
    reference: Reference,
    set: ConstraintSet,
    x: Vec<Vec3>,
    fixed: Vec<bool>,
    columns: Vec<Option<usize>>,
    free: usize,
    linear: NormalSolver,
    /// Rows of the Jacobian currently factorised, so Newton can reuse the factor while
    /// the active set stays (a chord iteration) instead of refactorising.
    factored: Labels,
    /// Steps since the factor was computed; a projection reuses a factor at most
    /// [`MAX_FACTOR_AGE`] (or [`PREDICTED_FACTOR_AGE`]) steps old (the Newton correction
    /// removes what a slightly stale projection lets through).
    factor_age: usize,
    /// The active rows' labels at the positions they were evaluated at: the last
    /// accepted step ends with that evaluation, and the next projection needs no other.
    last_labels: Option<(Vec<Vec3>, Labels)>,
    /// The fold angles the evaluation that accepted the last correction computed, there:
    /// the next branch reference, taken instead of computed again.
    accepted_folds: Option<crate::constraints::FoldAngles>,
    /// The last full steps' Newton corrections, when [`Options::predict`] is on.
    predictor: Predictor,
    /// The settings, with [`Options::predict`] decided for this mesh.
    options: Options,
    /// Whether the step under way is a [`Solver::live_step`].
    live: bool,
    /// Work done so far.
    pub stats: Stats,
}

impl Solver {
    /// Prepares a solve. `fixed` vertices never move, which removes rigid motions.
    pub fn new(
        mesh: Mesh,
        set: ConstraintSet,
        fixed: &[usize],
        options: Options,
    ) -> Result<Solver, SolverError> {
        let n = mesh.vertex_count();
        let summary = mesh.shape();
        if !(summary.is_disk || summary.is_tube) {
            return Err(SolverError::NotADisk {
                components: summary.components,
                holes: summary.holes,
            });
        }
        let mut is_fixed = vec![false; n];
        for &v in fixed {
            *is_fixed.get_mut(v).ok_or(SolverError::UnknownVertex {
                vertex: v,
                count: n,
            })? = true;
        }
        let (columns, free) = free_columns(&is_fixed);
        let reference = Reference::for_conditions(&mesh, &set);
        let mut options = options;
        options
            .predict
            .get_or_insert(mesh.faces().len() >= PREDICTOR_FACES);
        Ok(Solver {
            x: mesh.positions().to_vec(),
            mesh,
            reference,
            set,
            fixed: is_fixed,
            columns,
            free,
            linear: NormalSolver::default(),
            factored: Vec::new(),
            factor_age: 0,
            last_labels: None,
            accepted_folds: None,
            predictor: Predictor::default(),
            options,
            live: false,
            stats: Stats::default(),
        })
    }

    /// A default anchor: one face held still, which removes the rigid motions (§3).
    /// Without drags it is the face nearest the middle of the mesh. With drags it is the
    /// face farthest from every dragged vertex (largest distance from its centroid to the
    /// nearest one; ties go to the face nearer the middle): a face beside a dragged vertex
    /// holds the paper the user is pulling, and the vertex cannot follow the pointer.
    /// Holding a vertex holds its coincidence group (§6.4), so group partners of dragged
    /// vertices are avoided too.
    pub fn default_fixed(mesh: &Mesh, avoid: &[usize]) -> Vec<usize> {
        let (lo, hi) = mesh.bounding_box();
        let centre = (lo + hi) / 2.0;
        let x = mesh.positions();
        let mut avoid = avoid.to_vec();
        for g in &mesh.coincident {
            if g.iter().any(|v| avoid.contains(v)) {
                avoid.extend(g);
            }
        }
        let centroid = |f: &[usize; 3]| f.iter().map(|&v| x[v]).sum::<Vec3>() / 3.0;
        // Larger is better: (distance to the nearest dragged vertex, closeness to the middle).
        let score = |f: &[usize; 3]| {
            let c = centroid(f);
            let away = avoid
                .iter()
                .map(|&v| (x[v] - c).norm())
                .fold(f64::INFINITY, f64::min);
            (
                if avoid.is_empty() { 0.0 } else { away },
                -(c - centre).norm(),
            )
        };
        mesh.faces()
            .iter()
            .filter(|f| f.iter().all(|v| !avoid.contains(v)))
            .map(|f| (score(f), f))
            .fold(
                None::<((f64, f64), &[usize; 3])>,
                |best, (s, f)| match best {
                    Some((b, _)) if b.0 > s.0 || (b.0 == s.0 && b.1 >= s.1) => best,
                    _ => Some((s, f)),
                },
            )
            .map(|(_, f)| f.to_vec())
            .unwrap_or_default()
    }

    /// The vertices held while `dragged` is pulled by a user who pins as they go (the
    /// studio): the pins, plus the [`default_fixed`](Solver::default_fixed) face while
    /// fewer than three are pinned (fewer cannot hold the rigid motions), never the
    /// dragged vertex itself. A command line's `--fix` is held exactly as given instead.
    pub fn anchor_with_pins(
        mesh: &Mesh,
        pins: &std::collections::BTreeSet<usize>,
        dragged: usize,
    ) -> Vec<usize> {
        let mut anchor = pins.clone();
        if anchor.len() < 3 {
            anchor.extend(Self::default_fixed(mesh, &[dragged]));
        }
        anchor.remove(&dragged);
        anchor.into_iter().collect()
    }

    /// The mesh being solved (positions as of the last accepted step are in [`Solver::positions`]).
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Current positions.
    pub fn positions(&self) -> &[Vec3] {
        &self.x
    }

    /// Whether full steps start from a predicted correction ([`Options::predict`], as
    /// decided for this mesh: by default, meshes of [`PREDICTOR_FACES`] faces and more).
    pub fn predicts(&self) -> bool {
        self.options.predict == Some(true)
    }

    /// The residual each step is corrected to ([`Options::tolerance`]).
    pub fn tolerance(&self) -> f64 {
        self.options.tolerance
    }

    /// The conditions being held.
    pub fn conditions(&self) -> &ConstraintSet {
        &self.set
    }

    /// The reference state (for fold-angle branches).
    pub fn reference(&self) -> &Reference {
        &self.reference
    }

    /// Whether a vertex is held still.
    pub fn is_fixed(&self, v: usize) -> bool {
        self.fixed[v]
    }

    /// Puts the positions back to `x`, a state of the same mesh this solver accepted
    /// before (a fit's best): the factor, the active set and the predicted corrections of
    /// the steps since no longer apply, and the fold angles' branches follow.
    pub fn restore(&mut self, x: Vec<Vec3>) {
        assert_eq!(x.len(), self.x.len(), "a state of the same mesh");
        self.x = x;
        self.forget_last_step();
        self.factored.clear();
        self.accepted_folds = None;
        self.reference.track_folds(&self.mesh, &self.x);
    }

    /// The mesh with the solved positions.
    pub fn into_mesh(mut self) -> Mesh {
        self.mesh.set_positions(self.x);
        self.mesh
    }

    /// Rows at `x` that constrain motion: every equality row and the active inequalities.
    /// With `values_only` the Jacobian is left out (enough while the factor is reused).
    fn active_rows(&self, x: &[Vec3], values_only: bool) -> Rows {
        self.active_rows_holding(x, values_only, None)
    }

    /// [`Solver::active_rows`] with the `held` inequality rows kept (see
    /// [`crate::constraints::HeldRows`]).
    fn active_rows_holding(
        &self,
        x: &[Vec3],
        values_only: bool,
        held: Option<(std::sync::Arc<crate::constraints::HeldRows>, f64)>,
    ) -> Rows {
        self.set
            .evaluate_holding(&self.mesh, &self.reference, x, values_only, held)
    }

    /// Factorises J Jᵀ at `rows`. The corrections recorded so far lie in the old factor's
    /// row space and are forgotten: predicted through the new one, their tangential part
    /// would move the sheet (on the 10k Miura drag, 22 µm off the dragged corner's path
    /// in 192 steps; 0.15 µm when forgotten).
    fn factorise(&mut self, rows: &Rows) -> Result<(), SolverError> {
        self.predictor.forget();
        let columns = &self.columns;
        let shift = if rows.labels.iter().any(|l| l.0 == Family::LayerOrder) {
            Shift::EachRow
        } else {
            Shift::Largest
        };
        self.linear
            .factorise_shifted(rows.jacobian_mapped(self.free, |c| columns[c]), shift)?;
        self.factored.clone_from(&rows.labels);
        self.factor_age = 0;
        self.stats.factorisations += 1;
        Ok(())
    }

    fn to_free(&self, d: &[Vec3]) -> Vec<f64> {
        let mut out = vec![0.0; self.free];
        for (v, dv) in d.iter().enumerate() {
            for k in 0..3 {
                if let Some(c) = self.columns[3 * v + k] {
                    out[c] = dv[k];
                }
            }
        }
        out
    }

    fn add_free(&self, x: &mut [Vec3], d: &[f64], scale: f64) {
        for (v, xv) in x.iter_mut().enumerate() {
            for k in 0..3 {
                if let Some(c) = self.columns[3 * v + k] {
                    xv[k] += scale * d[c];
                }
            }
        }
    }

    /// Drops what the last accepted steps left for the next one (the active set and the
    /// corrections): after the mesh or the set of conditions changes, neither applies.
    fn forget_last_step(&mut self) {
        self.last_labels = None;
        self.predictor.forget();
    }

    /// Moves the branch reference to the accepted positions, with the fold angles the
    /// accepting evaluation computed when it computed them.
    fn track_folds_accepted(&mut self) {
        match self.accepted_folds.take() {
            Some(folds) => self.reference.adopt_folds(&folds),
            None => self.reference.track_folds(&self.mesh, &self.x),
        }
    }

    /// The row with the largest |residual| at `x`: after a failed step, evaluated where
    /// the smallest (most halved) step landed before Newton's correction, it names the
    /// condition that the motion could not keep.
    pub fn blocker_at(&self, x: &[Vec3]) -> Option<Blocker> {
        let rows = self.set.evaluate(&self.mesh, &self.reference, x);
        rows.residuals
            .iter()
            .zip(&rows.labels)
            .filter(|(r, _)| r.is_finite())
            .max_by(|a, b| a.0.abs().total_cmp(&b.0.abs()))
            .map(|(r, &(family, element))| Blocker {
                family,
                element,
                residual: r.abs(),
            })
    }

    /// Largest |residual| of the conditions at the current positions.
    pub fn residual(&self) -> f64 {
        self.set
            .evaluate(&self.mesh, &self.reference, &self.x)
            .residuals
            .iter()
            .fold(0.0, |a, r| a.max(r.abs()))
    }

    /// Eq. (10) at the current positions: the valid motion nearest to `dx0` (per vertex;
    /// fixed vertices' entries are ignored).
    pub fn null_space_step(&mut self, dx0: &[Vec3]) -> Result<Vec<Vec3>, SolverError> {
        self.project(dx0, false)
    }

    /// Eq. (10) again at the same positions: through the factor the last projection or
    /// step made while the active rows stay (a fresh one otherwise). An iterative solve
    /// that applies the projector many times within one step pays one factorisation.
    pub fn null_space_step_reusing(&mut self, dx0: &[Vec3]) -> Result<Vec<Vec3>, SolverError> {
        self.project(dx0, true)
    }

    /// Makes sure the factor of J Jᵀ fits the active rows at the current positions: a
    /// fresh one, or with `allow_stale` one up to [`MAX_FACTOR_AGE`] (or
    /// [`PREDICTED_FACTOR_AGE`]) steps old while the active set stays.
    fn refresh_factor(&mut self, allow_stale: bool) -> Result<(), SolverError> {
        // A reused factor needs only the row labels, to see the active set is the same;
        // after an accepted step the correction has just evaluated them here.
        let max_age = if self.predicts() {
            PREDICTED_FACTOR_AGE
        } else {
            MAX_FACTOR_AGE
        };
        let may_reuse = allow_stale && self.factor_age < max_age;
        let same_rows = may_reuse
            && match &self.last_labels {
                Some((x, labels)) if *x == self.x => *labels == self.factored,
                _ => self.active_rows(&self.x, true).labels == self.factored,
            };
        if !same_rows {
            let rows = self.active_rows(&self.x, false);
            self.factorise(&rows)?;
        }
        Ok(())
    }

    /// Eq. (10) through the factor as it stands.
    fn project_factored(&mut self, dx0: &[Vec3]) -> Vec<Vec3> {
        self.stats.solves += 1;
        let dx = self.linear.project(&self.to_free(dx0));
        let mut out = vec![Vec3::zeros(); self.x.len()];
        self.add_free(&mut out, &dx, 1.0);
        out
    }

    fn project(&mut self, dx0: &[Vec3], allow_stale: bool) -> Result<Vec<Vec3>, SolverError> {
        self.refresh_factor(allow_stale)?;
        Ok(self.project_factored(dx0))
    }

    /// Accepts the corrected positions `x` of a step. `wished` is where a full predicted
    /// step started (the positions plus the unprojected `dx0`): `x − wished` is the
    /// correction the next steps predict from, kept only while the factor it was made
    /// through serves (see [`Solver::factorise`]). Returns the motion.
    fn accept(&mut self, x: Vec<Vec3>, wished: Option<&[Vec3]>, newton: (usize, f64)) -> Vec<Vec3> {
        let moved: Vec<Vec3> = x.iter().zip(&self.x).map(|(a, b)| a - b).collect();
        match wished {
            Some(w) => self
                .predictor
                .record(x.iter().zip(w).map(|(a, b)| a - b).collect()),
            None => self.predictor.forget(),
        }
        self.x = x;
        self.track_folds_accepted();
        self.stats.steps += 1;
        self.stats.newton_iterations += newton.0;
        // Inactive inequality rows are 0, so the active rows' max is the residual.
        self.stats.worst_residual = self.stats.worst_residual.max(newton.1);
        moved
    }

    /// [`Solver::step`] solved to what a screen shows, for a drag the user is steering:
    /// corrected to [`LIVE_RESIDUAL`](crate::tolerance::LIVE_RESIDUAL) (or the solver's
    /// tolerance if looser), every solve with a single-precision copy of the factor (see
    /// [`NormalSolver::set_single_precision`]). A state reached this way is brought back
    /// to the solver's tolerance by [`Solver::polish`] when the drag ends.
    pub fn live_step(&mut self, dx0: &[Vec3]) -> Result<Vec<Vec3>, SolverError> {
        let tolerance = self.options.tolerance;
        self.options.tolerance = tolerance.max(crate::tolerance::LIVE_RESIDUAL);
        self.linear.set_single_precision(true);
        self.live = true;
        let motion = self.step(dx0);
        self.live = false;
        self.linear.set_single_precision(false);
        self.options.tolerance = tolerance;
        motion
    }

    /// One Euler step (§3): project `dx0` into the null space, move, correct. A step
    /// whose correction fails is halved and retried; positions only change when a step
    /// is accepted. Returns the motion applied.
    ///
    /// With [`Options::predict`] on and a correction to predict from, projection and
    /// correction share one solve: Newton's minimum-norm step J⁺F from x + dx₀ removes
    /// the part of dx₀ outside the null space (J dx₀, to first order in F) together with
    /// the drift, so Newton starts from x + dx₀ plus the predicted correction and no
    /// separate projection is solved. The motion kept along the null space is dx₀'s, as
    /// eq. (10) keeps it, plus the prediction's tangential part; the predicted correction
    /// lies in the row space of the factor it was made through, which is why predictions
    /// are dropped when the factor is renewed.
    pub fn step(&mut self, dx0: &[Vec3]) -> Result<Vec<Vec3>, SolverError> {
        self.refresh_factor(true)?;
        self.factor_age += 1;
        let predict = self.predicts();
        let factorisations = self.stats.factorisations;
        // The unprojected Euler step, where a predicted step starts and its correction is
        // measured from; unused (so not built) without the predictor.
        let wished = predict.then(|| {
            let mut w = self.x.clone();
            self.add_free(&mut w, &self.to_free(dx0), 1.0);
            w
        });
        if let Some(wished) = wished
            .as_deref()
            .filter(|_| self.predictor.last().is_some())
        {
            let mut x = wished.to_vec();
            if let Ok(newton) = self.correct_predicted(wished, &mut x) {
                self.stats.one_solve_steps += 1;
                let same_factor = self.stats.factorisations == factorisations;
                return Ok(self.accept(x, Some(wished).filter(|_| same_factor), newton));
            }
        }
        let dx = self.project_factored(dx0);
        let mut scale = 1.0;
        let mut failure = (f64::NAN, 0);
        let mut euler = Vec::new();
        for _ in 0..=self.options.max_halvings {
            let mut x = self.x.clone();
            for (xv, d) in x.iter_mut().zip(&dx) {
                *xv += d * scale;
            }
            // The Euler step, kept for the blocker report.
            euler.clone_from(&x);
            match self.correct_from(&mut x, true) {
                Ok(newton) => {
                    let full = scale == 1.0 && self.stats.factorisations == factorisations;
                    return Ok(self.accept(x, wished.as_deref().filter(|_| full), newton));
                }
                Err(f) => {
                    failure = f;
                    scale *= 0.5;
                    self.stats.halvings += 1;
                }
            }
        }
        Err(SolverError::NotConverged {
            step: self.stats.steps + 1,
            residual: failure.0,
            iterations: failure.1,
            tolerance: self.options.tolerance,
            blocker: self.blocker_at(&euler),
        })
    }
}

#[cfg(test)]
mod anchor_tests {
    use super::*;
    use std::collections::BTreeSet;

    #[test]
    fn pins_are_topped_up_with_the_far_face_until_three_and_never_hold_the_dragged_vertex() {
        let mesh = crate::io::fold::parse(include_str!("../../patterns/bird-base.fold"))
            .expect("a bundled pattern parses");
        let dragged = 0;
        let mut face = Solver::default_fixed(&mesh, &[dragged]);
        face.sort_unstable();
        assert_eq!(face.len(), 3);
        let none = BTreeSet::new();
        assert_eq!(Solver::anchor_with_pins(&mesh, &none, dragged), face);
        // Three pins hold the rigid motions: they are the anchor, exactly.
        let three: BTreeSet<usize> = [1, 2, 3].into();
        assert_eq!(Solver::anchor_with_pins(&mesh, &three, dragged), [1, 2, 3]);
        // One pin is topped up; a pinned vertex that is dragged is let go.
        let one: BTreeSet<usize> = [dragged].into();
        let anchor = Solver::anchor_with_pins(&mesh, &one, dragged);
        assert!(!anchor.contains(&dragged));
        assert_eq!(anchor, face);
    }
}

//! The fit under way: each step's wish from the distances and the preferences, the
//! Gauss–Newton steps once the pull stalls, and the rules that stop it.

use super::{
    gauss_newton, group_point, measure, neighbouring_groups, still_improving, surface_groups,
    FitOptions, Measure, Stop, CONVERGED_FRACTION, DEFAULT_GOAL_FRACTION, KEEP_LENGTHS, KEEP_SIZE,
    MAX_CONSECUTIVE_FAILURES, MIN_CAP_FRACTION, MIN_SOFTNESS, STALL_WINDOW, STEP_CAP_EDGES,
};
use crate::mesh::Vec3;
use crate::solver::{Resistance, Solver, SolverError};
use crate::surface::TriSurface;
use std::sync::Arc;

/// A fit under way: the solver, the target and what the steps so far achieved. The CLI
/// runs it to the end ([`Fitter::run`]); the studio steps it on its session thread.
pub struct Fitter {
    target: Arc<TriSurface>,
    options: FitOptions,
    groups: Vec<Vec<usize>>,
    /// How many groups each vertex is in.
    memberships: Vec<f64>,
    /// The positions the last step ended at and their distances: the next step starts
    /// from them unless the solver has moved since (a drag in the studio).
    last: Option<(Vec<Vec3>, Measure)>,
    /// The factor on the preference for the starting lengths: 1 at first, quartered
    /// each time the fit settles, down to [`MIN_SOFTNESS`] (a continuation: the
    /// preference shapes the path, the target decides where it ends).
    softness: f64,
    /// The step at which the softness last changed (stalls are judged after it).
    settled_at: usize,
    /// Each edge's length when the fit started (or the mesh last changed).
    rest: Vec<f64>,
    /// Pairs of neighbouring groups and the distance of their points then: the
    /// mid-surface's own lengths, which a Miura-ori's folding (a mechanism that keeps
    /// every edge) changes.
    neighbours: Vec<(usize, usize, f64)>,
    /// The largest wish of one step (mm), shrunk when a step fails.
    cap: f64,
    /// Distances after each step (RMS, largest), the start first.
    pub history: Vec<(f64, f64)>,
    /// Steps that failed and were retried smaller.
    pub failures: usize,
    /// Failures since the last accepted step.
    consecutive_failures: usize,
    /// The best state since the mesh last changed: (largest distance, positions).
    best: Option<(f64, Vec<Vec3>)>,
    stop: Option<Stop>,
    /// Why the last step a check refused was undone ([`Fitter::step_checked`]).
    pub held_back: Option<String>,
    /// The accepted step after which the pull stalled short of the goal and Gauss–Newton
    /// steps took over (an index into `history`), if they did.
    pub gauss_newton_from: Option<usize>,
    /// Gauss–Newton steps undone because they did not lower the energy: they count
    /// against the step limit as the solver counts them among its steps.
    undone: usize,
    /// The damping of Gauss–Newton steps, once the pull has stalled short of the goal.
    gauss_newton: Option<f64>,
}

impl Fitter {
    /// Prepares a fit of the solver's design onto `target`.
    pub fn new(solver: &Solver, target: Arc<TriSurface>, options: FitOptions) -> Fitter {
        let mut fitter = Fitter {
            target,
            options,
            groups: Vec::new(),
            memberships: Vec::new(),
            last: None,
            softness: 1.0,
            settled_at: 0,
            rest: Vec::new(),
            neighbours: Vec::new(),
            cap: 0.0,
            history: Vec::new(),
            failures: 0,
            consecutive_failures: 0,
            best: None,
            stop: None,
            held_back: None,
            gauss_newton_from: None,
            undone: 0,
            gauss_newton: None,
        };
        fitter.regroup(solver);
        let m = fitter.measure(solver);
        fitter.history.push((m.rms, m.largest));
        fitter
    }

    /// Groups and the step cap for the solver's mesh as it is (after remeshing, or when
    /// the studio resumes a fit on a solver built anew after a drag).
    pub fn regroup(&mut self, solver: &Solver) {
        let mesh = solver.mesh();
        self.groups = surface_groups(mesh, self.options.surface);
        self.memberships = vec![0.0; mesh.vertex_count()];
        for &v in self.groups.iter().flatten() {
            self.memberships[v] += 1.0;
        }
        let x = solver.positions();
        self.rest = mesh
            .edges()
            .iter()
            .map(|e| (x[e.vertices[0]] - x[e.vertices[1]]).norm())
            .collect();
        self.neighbours = neighbouring_groups(mesh, &self.groups)
            .into_iter()
            .map(|(g, h)| {
                let (p, q) = (
                    group_point(x, &self.groups[g]),
                    group_point(x, &self.groups[h]),
                );
                (g, h, (p - q).norm())
            })
            .collect();
        let mean_edge = self.rest.iter().sum::<f64>() / self.rest.len().max(1) as f64;
        self.cap = STEP_CAP_EDGES * mean_edge;
        self.best = None;
    }

    /// The surface groups (vertex ids of the solver's current mesh).
    pub fn groups(&self) -> &[Vec<usize>] {
        &self.groups
    }

    /// The target.
    pub fn target(&self) -> &TriSurface {
        &self.target
    }

    /// Why the fit stopped, once it has.
    pub fn stopped(&self) -> Option<Stop> {
        self.stop
    }

    /// The solver's surface points against the target.
    pub fn measure(&self, solver: &Solver) -> Measure {
        measure(solver.positions(), &self.groups, &self.target)
    }

    /// The distance goal at the solver's current size.
    pub fn goal(&self, solver: &Solver) -> f64 {
        self.options.goal.unwrap_or_else(|| {
            let (lo, hi) = crate::mesh::bounds(solver.positions());
            DEFAULT_GOAL_FRACTION * (hi - lo).norm()
        })
    }

    /// What the target asks of each vertex: the mean of its groups' gaps to their
    /// nearest target points.
    fn pull(&self, m: &Measure, vertices: usize) -> Vec<Vec3> {
        let mut dx0 = vec![Vec3::zeros(); vertices];
        for (g, (p, q)) in self.groups.iter().zip(m.points.iter().zip(&m.nearest)) {
            for &v in g {
                dx0[v] += (q - p) / self.memberships[v];
            }
        }
        dx0
    }

    /// The wish of a step: the target's pull plus a soft preference ([`KEEP_LENGTHS`]) for
    /// the lengths the fit started from — every edge's, and the distance between
    /// neighbouring surface points — the whole scaled so no vertex is asked to move more
    /// than the cap. Design mode lets lengths change freely: without the first, a vertex
    /// the pull does not hold (a boundary corner, measured only through its facet's mean)
    /// drifts with every correction and cells distort; without the second, a Miura-ori
    /// on a dome folds itself smaller (pulling points toward a sphere's centre contracts
    /// the sheet, and its folding keeps every edge). The preference keeps the design's
    /// cells and size wherever the target does not ask otherwise.
    fn wish(&self, m: &Measure, x: &[Vec3], edges: &[crate::mesh::Edge]) -> Vec<Vec3> {
        let mut dx0 = self.pull(m, x.len());
        // Half of `weight` × the length change, asked of each end of a stretched pair.
        let spring = |d: Vec3, rest: f64, weight: f64| {
            let l = d.norm();
            (l > 0.0).then(|| d * (self.softness * weight * 0.5 * (rest - l) / l))
        };
        for (e, &rest) in edges.iter().zip(&self.rest) {
            let [a, b] = e.vertices;
            if let Some(f) = spring(x[a] - x[b], rest, KEEP_LENGTHS) {
                dx0[a] += f;
                dx0[b] -= f;
            }
        }
        for &(g, h, rest) in &self.neighbours {
            if let Some(f) = spring(m.points[g] - m.points[h], rest, KEEP_SIZE) {
                for &v in &self.groups[g] {
                    dx0[v] += f / self.memberships[v];
                }
                for &v in &self.groups[h] {
                    dx0[v] -= f / self.memberships[v];
                }
            }
        }
        self.capped(dx0)
    }

    /// `dx0` scaled so no vertex is asked to move more than the cap.
    fn capped(&self, mut dx0: Vec<Vec3>) -> Vec<Vec3> {
        let longest = dx0.iter().map(|d| d.norm()).fold(0.0, f64::max);
        if longest > self.cap {
            let s = self.cap / longest;
            dx0.iter_mut().for_each(|d| *d *= s);
        }
        dx0
    }

    /// One step of the fit; returns the distances after it. After the fit has stopped
    /// (see [`Fitter::stopped`]) it does nothing.
    pub fn step(&mut self, solver: &mut Solver) -> Result<Measure, SolverError> {
        let m = match self.last.take() {
            // The distances the last step ended with, if the solver is still there.
            Some((at, m)) if at == solver.positions() => m,
            _ => self.measure(solver),
        };
        if self.stop.is_some() {
            return Ok(m);
        }
        let dx0 = match self.gauss_newton {
            Some(damping) => self.gauss_newton_wish(solver, &m, damping)?,
            None => self.wish(&m, solver.positions(), solver.mesh().edges()),
        };
        let newton_before = solver.stats.newton_iterations;
        // Where a Gauss–Newton step starts and the energy there, should it be undone.
        let before = self
            .gauss_newton
            .map(|_| (solver.positions().to_vec(), self.energy(solver, &m)));
        match solver.step(&dx0) {
            Ok(_) => {
                self.consecutive_failures = 0;
                // Newton's effort says whether the step was about right: a correction
                // that needed many iterations (inequalities switching on and off, a
                // sharply curved constraint surface) asks for shorter steps.
                match solver.stats.newton_iterations - newton_before {
                    0..=3 => self.cap *= 1.25,
                    4..=9 => {}
                    _ => self.cap = (0.8 * self.cap).max(MIN_CAP_FRACTION * self.max_cap(solver)),
                }
            }
            Err(SolverError::NotConverged { .. }) => {
                // The solver has already halved this step (twice, see [`FIT_HALVINGS`]):
                // the next try starts below where it gave up, and a few failures in a row
                // end the fit.
                self.failures += 1;
                self.consecutive_failures += 1;
                self.cap /= 8.0;
                if self.consecutive_failures >= MAX_CONSECUTIVE_FAILURES {
                    self.stop = Some(Stop::Blocked);
                }
                return Ok(m);
            }
            Err(e) => return Err(e),
        }
        if self.undone_by_damping(solver, before, &m) {
            return Ok(m);
        }
        if let Some(threshold) = self.options.remesh {
            let outcome = solver.remesh(&[], threshold);
            if outcome.renumbered.is_some() || outcome.collapses + outcome.flips > 0 {
                self.regroup(solver);
            }
        }
        self.cap = self.cap.min(self.max_cap(solver));
        let after = self.measure(solver);
        self.history.push((after.rms, after.largest));
        self.keep_best(solver, &after);
        self.judge(solver, &after);
        self.last = Some((solver.positions().to_vec(), after.clone()));
        Ok(after)
    }

    /// The preferences at their current softness, as the Gauss–Newton steps weigh them.
    fn preferences(&self) -> gauss_newton::Preferences<'_> {
        gauss_newton::Preferences {
            rest: &self.rest,
            neighbours: &self.neighbours,
            lengths: self.softness * KEEP_LENGTHS,
            size: self.softness * KEEP_SIZE,
        }
    }

    /// The fit's energy at the solver's positions, `m` measured there (the Gauss–Newton
    /// steps' objective, [`gauss_newton::energy`]).
    fn energy(&self, solver: &Solver, m: &Measure) -> f64 {
        gauss_newton::energy(solver, &self.groups, m, &self.target, &self.preferences())
    }

    /// The wish of a Gauss–Newton step ([`gauss_newton::motion`]), scaled so no vertex is
    /// asked to move more than the cap.
    fn gauss_newton_wish(
        &self,
        solver: &mut Solver,
        m: &Measure,
        damping: f64,
    ) -> Result<Vec<Vec3>, SolverError> {
        let keep = self.preferences();
        let dx = gauss_newton::motion(solver, &self.groups, m, &self.target, &keep, damping)?;
        Ok(self.capped(dx))
    }

    /// In the Gauss–Newton phase (`before` holds where the step started, where `m` was
    /// measured, and the energy there), undoes a step that did not lower the fit's energy
    /// and damps the next one more; a step that did lowers the damping. Ends the fit when
    /// the damping has grown past [`gauss_newton::MAX_DAMPING`]. Whether the step was
    /// undone.
    fn undone_by_damping(
        &mut self,
        solver: &mut Solver,
        before: Option<(Vec<Vec3>, f64)>,
        m: &Measure,
    ) -> bool {
        let (Some(damping), Some((before, was))) = (self.gauss_newton, before) else {
            return false;
        };
        let better = self.energy(solver, &self.measure(solver)) < was;
        let damping = gauss_newton::next_damping(damping, better);
        self.gauss_newton = Some(damping);
        if better {
            return false;
        }
        solver.restore(before);
        self.undone += 1;
        if self.out_of_steps(self.history.len() - 1) {
            self.stop = Some(Stop::StepLimit);
        } else if damping > gauss_newton::MAX_DAMPING {
            self.stop = Some(self.no_longer_improving(solver, m));
        }
        self.last = Some((solver.positions().to_vec(), m.clone()));
        true
    }

    /// The cap never grows past [`STEP_CAP_EDGES`] of the mean edge.
    fn max_cap(&self, solver: &Solver) -> f64 {
        STEP_CAP_EDGES * crate::solver::mean_edge(solver.mesh(), solver.positions())
    }

    /// Remembers the state with the smallest largest distance seen since the mesh last
    /// changed its vertices.
    fn keep_best(&mut self, solver: &Solver, m: &Measure) {
        if self.best.as_ref().is_none_or(|(b, _)| m.largest < *b) {
            self.best = Some((m.largest, solver.positions().to_vec()));
        }
    }

    /// Puts the solver back on the best state the fit reached, when the last steps made
    /// it worse (a target out of reach can leave the design swinging).
    pub fn settle_on_best(&mut self, solver: &mut Solver) {
        let now = self.measure(solver).largest;
        if let Some((best, x)) = self.best.take() {
            if best < now && x.len() == solver.positions().len() {
                solver.restore(x);
            }
        }
    }

    /// Stops on a stall or the step limit.
    fn judge(&mut self, solver: &Solver, m: &Measure) {
        let steps = self.history.len() - 1;
        if m.largest <= CONVERGED_FRACTION * self.goal(solver) {
            self.stop = Some(Stop::Converged);
            return;
        }
        if steps >= self.settled_at + STALL_WINDOW && !still_improving(&self.history) {
            if self.softness > MIN_SOFTNESS {
                // The preference for the starting lengths has done its work: the design
                // is as near the target as it lets it come. Loosen it and go on.
                self.softness *= 0.25;
                self.settled_at = steps;
            } else if self.gauss_newton.is_none() && m.largest > self.goal(solver) {
                // The pull has stalled short of the goal: what the conditions let through
                // may still lead there, too weakly for gradient steps to follow.
                self.gauss_newton = Some(gauss_newton::INITIAL_DAMPING);
                self.gauss_newton_from = Some(steps);
                self.settled_at = steps;
            } else {
                self.stop = Some(self.no_longer_improving(solver, m));
                return;
            }
        }
        if self.out_of_steps(steps) {
            self.stop = Some(Stop::StepLimit);
        }
    }

    /// Why a fit that no longer comes nearer stops: converged with the goal met at `m`,
    /// stalled short of it.
    fn no_longer_improving(&self, solver: &Solver, m: &Measure) -> Stop {
        if m.largest <= self.goal(solver) {
            Stop::Converged
        } else {
            Stop::Stalled
        }
    }

    /// Whether `accepted` steps, with the Gauss–Newton steps undone (the solver counts
    /// them among its steps too), have used the step budget.
    fn out_of_steps(&self, accepted: usize) -> bool {
        accepted + self.undone >= self.options.max_steps
    }

    /// Steps until the fit stops; `progress` sees each step's distances.
    /// One step held to `check` (as a drag's [`crate::solver::StepCheck`]: the layer order,
    /// with `layer-order` among the conditions): a step it refuses is undone — the
    /// positions, the best state and the history as before it — and counts as a failed
    /// step, so the next is shorter and a run of them ends the fit as blocked. Without a
    /// check it is [`Fitter::step`], with nothing kept to undo.
    pub fn step_checked<F: FnMut(&Solver) -> Option<String> + ?Sized>(
        &mut self,
        solver: &mut Solver,
        check: Option<&mut F>,
    ) -> Result<Measure, SolverError> {
        let Some(check) = check else {
            return self.step(solver);
        };
        let before = solver.positions().to_vec();
        let (best, history, cap) = (self.best.clone(), self.history.len(), self.cap);
        let m = self.step(solver)?;
        // Unmoved (a failed or final step) or remeshed (nothing to go back to): kept.
        if solver.positions() == before.as_slice() || solver.positions().len() != before.len() {
            return Ok(m);
        }
        let Some(why) = check(solver) else {
            return Ok(m);
        };
        solver.restore(before);
        self.best = best;
        self.history.truncate(history);
        self.last = None;
        self.held_back = Some(why);
        self.failures += 1;
        self.consecutive_failures += 1;
        self.cap = cap / 8.0;
        self.stop =
            (self.consecutive_failures >= MAX_CONSECUTIVE_FAILURES).then_some(Stop::Blocked);
        Ok(self.measure(solver))
    }

    /// Steps ([`Fitter::step_checked`] with `check`) until the fit stops.
    pub fn run<F: FnMut(&Solver) -> Option<String> + ?Sized>(
        &mut self,
        solver: &mut Solver,
        mut check: Option<&mut F>,
        progress: &mut dyn FnMut(usize, &Measure),
    ) -> Result<Stop, SolverError> {
        let mut k = 0;
        while self.stop.is_none() {
            let m = self.step_checked(solver, check.as_deref_mut())?;
            k += 1;
            progress(k, &m);
        }
        Ok(self.stop.expect("the loop ran to a stop"))
    }

    /// What refuses the motion the target still asks for, at the solver's state.
    pub fn resistance(&self, solver: &mut Solver) -> Result<Option<Resistance>, SolverError> {
        let m = self.measure(solver);
        let dx0 = self.pull(&m, solver.positions().len());
        solver.resisting(&dx0)
    }
}

//! Newton–Raphson correction (§3): brings positions back onto the conditions after an
//! Euler step, reusing a stale factor of J Jᵀ while it converges (a chord iteration), and
//! starting from a predicted correction on large meshes.

use super::{Solver, SolverError};
use crate::mesh::Vec3;

/// Chord iterations a live step ([`Solver::live_step`]) may still need at its chord's
/// rate for the chord to be kept: a refactorisation of J Jᵀ on the 10k-vertex Miura-ori
/// costs as much as a dozen chord iterations, and live steps stop at a residual the
/// chord reaches in a few. Over 200 steps of a pointer drag there, 1 → 3 took the
/// refactorisations from 26 to 19 (with the stalled chord refactorised in place).
const LIVE_CHORD_LEFT: i32 = 3;

/// The slowest rate (residual ratio per iteration) at which a live step's chord is kept.
const LIVE_CHORD_RATE: f64 = 0.7;

impl Solver {
    /// Newton–Raphson on F(x) = 0 with the inequality penalties of §3, from `x`.
    /// While the active rows are those last factorised and the residual falls fast, the
    /// factor is reused (a chord iteration: the Jacobian barely changes over one small
    /// step); otherwise J is refactorised where we are, unless `may_refactor` is false
    /// and the rows are still those factorised, when the correction gives up instead.
    /// Returns the iterations used and the final residual, or the residual that remained
    /// and the iterations spent.
    pub(super) fn correct_from(
        &mut self,
        x: &mut [Vec3],
        may_refactor: bool,
    ) -> Result<(usize, f64), (f64, usize)> {
        let tol = self.options.tolerance;
        let mut last = f64::INFINITY;
        let mut fresh = false;
        for it in 0..=self.options.max_newton {
            let rows = self.active_rows(x, true);
            let r = rows.residuals.iter().fold(0.0, |a: f64, v| a.max(v.abs()));
            if r <= tol {
                self.accepted_folds = rows.fold_angles;
                self.last_labels = Some((x.to_vec(), rows.labels));
                return Ok((it, r));
            }
            if it == self.options.max_newton || !r.is_finite() {
                return Err((r, it));
            }
            // A diverging iteration will not come back.
            if r > 10.0 * last && it > 2 {
                return Err((r, it));
            }
            // On a large mesh (predicting), a chord that converges slowly is still kept
            // when one more iteration at its rate ends the correction (a live step's:
            // [`LIVE_CHORD_LEFT`] more, while it converges at all): restarting or
            // refactorising costs more than that iteration.
            let rate = r / last;
            let finishing = self.predicts()
                && if self.live {
                    rate < LIVE_CHORD_RATE && r * rate.powi(LIVE_CHORD_LEFT) < tol
                } else {
                    r * rate < tol
                };
            let reuse = !fresh && rows.labels == self.factored && (r < 0.25 * last || finishing);
            let reuse = reuse || (it == 0 && rows.labels == self.factored);
            last = r;
            // Giving up is for a factor that still fits but converges slowly; rows that
            // changed need a new factor whatever the starting point.
            if !reuse && !may_refactor && rows.labels == self.factored {
                return Err((r, it));
            }
            if !reuse {
                if self.factorise(&self.active_rows(x, false)).is_err() {
                    return Err((r, it));
                }
                fresh = true;
            } else {
                fresh = false;
            }
            self.stats.solves += 1;
            let dx = self.linear.newton_step(&rows.residuals);
            self.add_free(x, &dx, 1.0);
        }
        unreachable!("the loop returns")
    }

    /// Tightens the residual of the current positions to `tolerance` (e.g. 1e-12 before a
    /// design is saved, so its unfolding is isometric to ~1e-12). Newton converges
    /// quadratically here, so this costs one or two iterations; on failure nothing moves.
    pub fn polish(&mut self, tolerance: f64) -> bool {
        let saved = self.options.tolerance;
        self.options.tolerance = tolerance;
        let ok = self.correct().is_ok();
        self.options.tolerance = saved;
        ok
    }

    /// Brings the current positions back onto the constraints (used after loading a
    /// design that is slightly off). Errors say what residual remained.
    pub fn correct(&mut self) -> Result<usize, SolverError> {
        let mut x = self.x.clone();
        match self.correct_from(&mut x, true) {
            Ok((it, _)) => {
                self.x = x;
                self.track_folds_accepted();
                self.stats.newton_iterations += it;
                Ok(it)
            }
            Err((residual, iterations)) => Err(SolverError::NotConverged {
                step: self.stats.steps,
                residual,
                iterations,
                tolerance: self.options.tolerance,
                blocker: self.blocker_at(&self.x),
            }),
        }
    }

    /// Newton from `wished` (the positions plus the unprojected wish, see
    /// [`Solver::step`]) plus a predicted correction, into `x`. First from the line
    /// through the last two corrections, on the factor as it stands: that prediction
    /// removes what a chord removes easily, and what it leaves is the part a stale factor
    /// corrects slowly (on the 100k Miura, 2.4e-8 → 1.5e-8 an iteration), which would
    /// cost a refactorisation. So should the chord stall (and not be one iteration from
    /// done), Newton starts again from the last correction alone, refactorising only if
    /// that fails too.
    pub(super) fn correct_predicted(
        &mut self,
        wished: &[Vec3],
        x: &mut [Vec3],
    ) -> Result<(usize, f64), (f64, usize)> {
        let mut spent = 0;
        if let Some(c) = self.predictor.extrapolated() {
            for (xv, cv) in x.iter_mut().zip(&c) {
                *xv += cv;
            }
            // A live step refactorises where its chord stalled: from there one fresh
            // iteration ends it, where a restart would cost a few chord iterations first
            // (over 200 steps of the 10k drag: 16 restarts, 57 more Newton iterations).
            match self.correct_from(x, self.live) {
                Ok(done) => return Ok(done),
                Err((_, it)) => spent = it,
            }
            self.stats.restarted_predictions += 1;
            x.copy_from_slice(wished);
        }
        if let Some(c) = self.predictor.last() {
            for (xv, cv) in x.iter_mut().zip(c) {
                *xv += cv;
            }
        }
        self.correct_from(x, true)
            .map(|(it, r)| (it + spent, r))
            .map_err(|(r, it)| (r, it + spent))
    }
}

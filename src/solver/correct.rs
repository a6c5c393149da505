//! Newton–Raphson correction (§3): brings positions back onto the conditions after an
//! Euler step, reusing a stale factor of J Jᵀ while it converges (a chord iteration), and
//! starting from a predicted correction on large meshes.

use super::{Solver, SolverError};
use crate::constraints::{HeldRows, Rows};
use crate::mesh::Vec3;
use std::sync::Arc;

/// Chord iterations a live step ([`Solver::live_step`]) may still need at its chord's
/// rate for the chord to be kept: a refactorisation of J Jᵀ on the 10k-vertex Miura-ori
/// costs as much as a dozen chord iterations, and live steps stop at a residual the
/// chord reaches in a few. Over 200 steps of a pointer drag there, 1 → 3 took the
/// refactorisations from 26 to 19 (with the stalled chord refactorised in place).
const LIVE_CHORD_LEFT: i32 = 3;

/// A Newton iteration that leaves more than this share of the residual is slow: the
/// correction then holds the inequality rows it has met (see
/// [`crate::constraints::HeldRows`]), where one that converges fast keeps to the rows
/// active at each iterate.
const SLOW_RATE: f64 = 0.25;

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
        // Inequality rows active at any iteration since a slow one stay in (see `HeldRows`).
        let mut held: Option<Arc<HeldRows>> = None;
        for it in 0..=self.options.max_newton {
            // Held rows satisfied by more than the last violation are let go.
            let holding = held.clone().map(|h| (h, last));
            let rows = self.active_rows_holding(x, true, holding.clone());
            let r = rows.largest_violation();
            if r <= tol {
                let mut rows = rows;
                self.accepted_folds = rows.fold_angles.take();
                self.last_labels = Some((x.to_vec(), active_labels(rows)));
                return Ok((it, r));
            }
            // Newton converges fast or not at all unless rows take turns: holding starts
            // at the first slow iteration, and goes on once started.
            if held.is_some() || (it > 0 && r > SLOW_RATE * last) {
                held = grow_held(held, &rows);
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
                // The same rows as `rows`: held by the set and band they were read with.
                if self
                    .factorise(&self.active_rows_holding(x, false, holding))
                    .is_err()
                {
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

/// `held` with the inequality rows active in `rows` added (the same set, not copied, when
/// none is new).
fn grow_held(held: Option<Arc<HeldRows>>, rows: &Rows) -> Option<Arc<HeldRows>> {
    let active = || {
        (0..rows.residuals.len())
            .filter(|&i| rows.inequality[i] && rows.residuals[i] > 0.0)
            .map(|i| rows.keys[i])
    };
    let known = held.as_deref();
    if active().all(|k| known.is_some_and(|h| h.contains(&k))) {
        return held;
    }
    let mut grown = known.cloned().unwrap_or_default();
    grown.extend(active());
    Some(Arc::new(grown))
}

/// The labels of the rows an evaluation without held rows would have: a held row below
/// its bound is left out, so that the next step's projection does not keep the motion
/// inside it.
fn active_labels(rows: Rows) -> super::Labels {
    if rows.held.is_none() {
        return rows.labels;
    }
    rows.labels
        .into_iter()
        .zip(rows.inequality.iter().zip(&rows.residuals))
        .filter(|(_, (&ineq, &r))| !ineq || r > 0.0)
        .map(|(l, _)| l)
        .collect()
}

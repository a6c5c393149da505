//! The Newton correction predicted from the steps before ([`super::Options::predict`]).
//!
//! Over one small step the drift the correction removes (the manifold's curvature, and
//! what a stale factor's projection lets through) is second order in the step and changes
//! smoothly from step to step. The last correction c₁ predicts the next to first order;
//! the line through the last two, 2c₁ − c₂, to second order, which on a 10k-vertex Miura
//! drag lands within the tolerance on about half the steps, so those need no Newton
//! iteration at all.

use crate::mesh::Vec3;

/// The corrections of the last full steps, newest first.
#[derive(Default)]
pub(super) struct Predictor {
    last: Option<Vec<Vec3>>,
    older: Option<Vec<Vec3>>,
}

impl Predictor {
    /// Forgets every correction: after a halved step, a remesh or a change of the set of
    /// conditions, they no longer describe the next step.
    pub fn forget(&mut self) {
        self.last = None;
        self.older = None;
    }

    /// Records the correction a full step needed (accepted positions minus its Euler step).
    pub fn record(&mut self, correction: Vec<Vec3>) {
        self.older = self.last.replace(correction);
    }

    /// The first-order prediction c₁, if a full step came before.
    pub fn last(&self) -> Option<&[Vec3]> {
        self.last.as_deref()
    }

    /// The second-order prediction 2c₁ − c₂, if two full steps came before.
    pub fn extrapolated(&self) -> Option<Vec<Vec3>> {
        let (last, older) = (self.last.as_ref()?, self.older.as_ref()?);
        Some(
            last.iter()
                .zip(older)
                .map(|(c1, c2)| 2.0 * c1 - c2)
                .collect(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extrapolation_continues_a_correction_that_changes_linearly() {
        let c = |k: f64| vec![Vec3::new(1.0 + 0.5 * k, -2.0 * k, 0.25), Vec3::new(k, k, k)];
        let mut p = Predictor::default();
        assert!(p.last().is_none() && p.extrapolated().is_none());
        p.record(c(0.0));
        assert_eq!(p.last(), Some(&c(0.0)[..]));
        assert!(p.extrapolated().is_none(), "one correction gives no line");
        p.record(c(1.0));
        assert_eq!(p.extrapolated(), Some(c(2.0)));
        p.record(c(2.0));
        assert_eq!(p.extrapolated(), Some(c(3.0)));
        assert_eq!(p.last(), Some(&c(2.0)[..]));
        p.forget();
        assert!(p.last().is_none() && p.extrapolated().is_none());
    }
}

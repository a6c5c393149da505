//! The layer order a drag step keeps: a step of a scripted drag, a fit or the studio's
//! pointer is held to the flat-folded layer order of its crease pattern when
//! `layer-order` is among the conditions.

use crate::geometry::unfold::{crease_pattern_of, PatternFrom};
use crate::solver::Solver;
use std::borrow::Cow;

/// Time one step's layer-order check may take before the step is let through undecided.
pub const STEP_ORDER_TIME: std::time::Duration = std::time::Duration::from_secs(5);

/// Why the solver's state has lost its layer order (`layer-order` among the conditions),
/// for a scripted drag: lost, or not confirmed within [`STEP_ORDER_TIME`] and the default
/// cap (a step is kept only when its order is known: proving that none exists can take
/// the search far longer than finding one). `None` while it keeps one.
pub(super) fn lost_layer_order(solver: &Solver) -> Option<String> {
    match layer_order_of_step(solver, STEP_ORDER_TIME) {
        StepOrder::Kept => None,
        StepOrder::Lost(why) | StepOrder::Undecided(why) => Some(why),
    }
}

/// What a drag step did to the layer order of its flat-folded crease pattern.
#[derive(Clone, Debug, PartialEq)]
pub enum StepOrder {
    /// It still has one.
    Kept,
    /// It has none, or no longer folds flat: why.
    Lost(String),
    /// Not decided within the time given: why.
    Undecided(String),
}

/// The layer order of the solver's state (`layer-order` among the conditions): its
/// crease pattern, unfolded afresh (a design-mode step changes it), folded flat, judged
/// within `time` and the default cap. Scripted drags (`drag_phase`) and the studio's
/// pointer drags both hold their steps to it.
pub fn layer_order_of_step(solver: &Solver, time: std::time::Duration) -> StepOrder {
    use crate::fab::{budget::Budget, layer_conflict, LayerError};
    let mut now = solver.mesh().clone();
    now.set_positions(solver.positions().to_vec());
    if now.is_tube() {
        // Not judged on a tube yet: its strip folded flat is not the tube folded flat.
        return StepOrder::Undecided(
            "the layer order of a tube is not judged yet (take layer-order out of the conditions)"
                .into(),
        );
    }
    // A design-mode step changes lengths: the pattern is the step's form unfolded.
    let Ok(pattern) = crease_pattern_of(&now, PatternFrom::Form).map(Cow::into_owned) else {
        return StepOrder::Kept;
    };
    now.set_crease_pattern(pattern);
    let budget = Budget {
        deadline: Some((std::time::Instant::now() + time, time)),
        ..Budget::default()
    };
    match layer_conflict(&now, &budget) {
        Ok(Some(c)) => StepOrder::Lost(format!("the layer order would be lost: {c}")),
        Ok(None) => StepOrder::Kept,
        Err(e @ LayerError::Open { .. }) => {
            StepOrder::Lost(format!("the crease pattern would stop folding flat: {e}"))
        }
        Err(e) => StepOrder::Undecided(format!("its layer order could not be confirmed: {e}")),
    }
}

//! What the solver preserves: design or simulation (§5), and the conditions each uses.

use crate::constraints::{ConstraintSet, Family};

/// What the solver preserves (§5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// The chosen conditions; lengths are free, so the crease pattern changes.
    Design,
    /// Every edge keeps its length: how the designed paper behaves.
    Simulation,
}

impl Mode {
    /// Parses "design" or "simulation".
    pub fn parse(name: &str) -> Result<Mode, String> {
        match name {
            "design" => Ok(Mode::Design),
            "simulation" => Ok(Mode::Simulation),
            other => Err(format!("unknown mode \"{other}\" (design or simulation)")),
        }
    }

    /// "design" or "simulation": the name [`Mode::parse`] reads.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Design => "design",
            Mode::Simulation => "simulation",
        }
    }

    /// The conditions of simulation mode: rigid panels (edge lengths) within their
    /// fold-angle and twist ranges.
    pub fn simulation_set() -> ConstraintSet {
        ConstraintSet {
            families: vec![
                Family::EdgeLength,
                Family::FoldAngleRange,
                Family::TwistRange,
            ],
        }
    }

    /// Folding from the flat state: rigid panels and untwisted facets. The mountain and
    /// valley sign ranges sit exactly on their bound there and would make Newton's active
    /// set chatter; the fold drive itself pulls each crease the right way.
    pub fn folding_set() -> ConstraintSet {
        ConstraintSet {
            families: vec![Family::EdgeLength, Family::TwistRange],
        }
    }
}

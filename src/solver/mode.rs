//! What the solver preserves: design or simulation (§5), and the conditions each uses.

use crate::constraints::{ConstraintSet, Family, Reference};
use crate::mesh::Mesh;

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

    /// The conditions in force (§5), decided here for every face: simulation mode's own
    /// set, or in design mode the families `chosen` (when any are), else what `mesh`'s
    /// assignment calls for ([`ConstraintSet::default_for`]).
    pub fn conditions(self, chosen: Option<&ConstraintSet>, mesh: &Mesh) -> ConstraintSet {
        match (self, chosen) {
            (Mode::Simulation, _) => Mode::simulation_set(),
            (Mode::Design, Some(set)) if !set.families.is_empty() => set.clone(),
            (Mode::Design, _) => ConstraintSet::default_for(&Reference::new(mesh)),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_conditions_in_force_follow_the_mode_then_the_choice_then_the_assignment() {
        let mesh = crate::io::fold::parse(include_str!("../../patterns/bird-base.fold"))
            .expect("a bundled pattern parses");
        let own = ConstraintSet::default_for(&Reference::new(&mesh));
        let chosen = ConstraintSet {
            families: vec![Family::Developability],
        };
        assert_ne!(own, chosen);
        let none = ConstraintSet { families: vec![] };
        for choice in [None, Some(&chosen), Some(&none)] {
            assert_eq!(
                Mode::Simulation.conditions(choice, &mesh),
                Mode::simulation_set()
            );
        }
        assert_eq!(Mode::Design.conditions(Some(&chosen), &mesh), chosen);
        assert_eq!(Mode::Design.conditions(None, &mesh), own);
        assert_eq!(Mode::Design.conditions(Some(&none), &mesh), own);
    }
}

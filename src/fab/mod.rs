//! Fabrication: verify a design before anything is cut (later: unfold, lay out, score).

pub mod verify;

pub use verify::{verify, FamilyReport, Report, Tolerances};

//! Fabrication: verify a design before anything is cut, unfold it (later: lay out, score).

pub mod unfold;
pub mod verify;

pub use unfold::{unfold, UnfoldError};
pub use verify::{verify, FamilyReport, Report, Tolerances};

//! Plotters and cutters: machine profiles (`machines/*.toml`); later, serial streaming.

pub mod machine;

pub use machine::{Machine, MachineError};

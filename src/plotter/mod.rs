//! Plotters and cutters: machine profiles (`machines/*.toml`), streaming a job over a serial
//! port with flow control, progress and resume, and an emulated plotter on a pty.

pub mod emulator;
mod journal;
pub mod machine;
pub mod stream;

pub use emulator::{Emulator, EmulatorConfig, EmulatorState, Flow};
pub use machine::{Machine, MachineError};
pub use stream::{stream, FlowMode, Journal, Progress, StreamError, StreamOptions, StreamReport};

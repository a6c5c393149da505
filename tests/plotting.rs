//! Plotting: streaming jobs to the emulator over pseudo-terminals, flow control, resuming.
//! One test crate per concept, each module a former crate of its own: compiled and
//! linked once (see tests/run).

mod common;

#[path = "plotting/plot.rs"]
mod plot;
#[path = "plotting/plot_resume.rs"]
mod plot_resume;

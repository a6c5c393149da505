//! The command line: every command's options and errors, hostile input, and a seeded fuzz;
//! and the scratch folders all the test crates write in.
//! One test crate per concept, each module a former crate of its own: compiled and
//! linked once (see tests/run).

mod common;

#[path = "cli/commands.rs"]
mod commands;
#[path = "cli/docs.rs"]
mod docs;
#[path = "cli/fuzz.rs"]
mod fuzz;
#[path = "cli/hostile.rs"]
mod hostile;
#[path = "cli/scratch.rs"]
mod scratch;

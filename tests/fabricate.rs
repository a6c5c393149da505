//! Fabrication: verification at the sheet, scoring and clearance, the files each machine
//! gets read back by readers crease did not write, layouts, print-and-cut and two-sided jobs.
//! One test crate per concept, each module a former crate of its own: compiled and
//! linked once (see tests/run).

mod common;

#[path = "fabricate/fab.rs"]
mod fab;
#[path = "fabricate/machines.rs"]
mod machines;
#[path = "fabricate/print_and_cut.rs"]
mod print_and_cut;
#[path = "fabricate/scoring.rs"]
mod scoring;
#[path = "fabricate/sheet_files.rs"]
mod sheet_files;
#[path = "fabricate/sheet_layout.rs"]
mod sheet_layout;
#[path = "fabricate/tubes.rs"]
mod tubes;
#[path = "fabricate/two_sided.rs"]
mod two_sided;

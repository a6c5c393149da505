//! Helpers shared by the integration tests (each test crate, one per concept, includes
//! this with `mod common;` and its modules `use crate::common;`).

#[allow(dead_code)] // only the fabrication tests use it
pub mod fabbing;
#[allow(dead_code)] // only the command line's hostile-input tests use it
pub mod hostile_inputs;
pub mod js;
#[allow(dead_code)] // only the layer tests use it
pub mod order_check;
#[allow(dead_code)] // only the plotting tests use it
pub mod plotting;
pub mod scratch;

#[allow(unused_imports)] // not every test crate makes folders
pub use scratch::{Scratch, ScratchFile};

use std::process::Command;

/// Runs the `crease` binary with `args`: exit status (−1 if killed), stdout, stderr.
#[allow(dead_code)] // the plotting tests drive the library, not the binary
pub fn run_crease(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_crease"))
        .args(args)
        .output()
        .expect("the crease binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Writes `content` to `name` in a scratch folder of its own for `suite`, removed with
/// the returned guard (kept when the test fails).
#[allow(dead_code)] // not every test crate that includes this module writes files
pub fn scratch_file(suite: &str, name: &str, content: &str) -> ScratchFile {
    ScratchFile::new(suite, name, content)
}

/// The library's one seeded stream (xorshift64), for the fuzzing and noise tests.
#[allow(unused_imports)] // only the fuzzing and noise tests draw from it
pub use crease::random::Rng;

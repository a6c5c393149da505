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

/// Writes `content` to `name` in this process's scratch folder for `suite`, so test
/// files of different suites and runs never share a path.
#[allow(dead_code)] // not every test crate that includes this module writes files
pub fn scratch_file(suite: &str, name: &str, content: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("crease-{suite}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, content).unwrap();
    p
}

/// The library's one seeded stream (xorshift64), for the fuzzing and noise tests.
#[allow(unused_imports)] // only the fuzzing and noise tests draw from it
pub use crease::random::Rng;

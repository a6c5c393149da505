//! Helpers shared by the integration tests (each test file is its own crate and includes
//! this with `mod common;`).

use std::process::Command;

/// Runs the `crease` binary with `args`: exit status (−1 if killed), stdout, stderr.
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

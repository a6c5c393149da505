#![allow(dead_code)] // each test crate uses its own part of these helpers
//! Readers crease did not write, run under node from `tests/js` (installed there by
//! `bash tests/run`): the Khronos glTF validator, Rabbit Ear.

use std::path::Path;

/// Runs the script `script` of tests/js on `file` and parses the JSON it prints.
pub fn node(script: &str, file: &Path) -> serde_json::Value {
    let out = std::process::Command::new("node")
        .arg(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("tests/js")
                .join(script),
        )
        .arg(file)
        .output()
        .expect("node runs (tests/run installs it and tests/js's packages)");
    assert!(
        out.status.success(),
        "{script}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

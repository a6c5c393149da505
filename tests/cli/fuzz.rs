//! Seeded mutations of the bundled patterns and the anchor files in every format crease
//! reads: import, verification and export must never panic, whatever the bytes. A sample
//! also goes through the real binary: exit 0, 1 or 2 only, and nothing written on failure.
//! `CREASE_FUZZ_CASES=5000 cargo test --release --test cli fuzz` runs a longer campaign.

use crate::common;

use common::{run_crease, Rng};
use crease::io::{self, Format};
use std::path::{Path, PathBuf};

/// Tokens that break parsers: numbers at the edges, structure, other formats' syntax.
const TOKENS: &[&str] = &[
    "-1",
    "0",
    "1e308",
    "-1e308",
    "NaN",
    "inf",
    "1e-320",
    "99999999",
    "null",
    "[]",
    "{}",
    "[",
    "]",
    "{",
    "}",
    ",",
    "\"",
    ")(",
    "<",
    ">",
    "</svg>",
    "<g transform=\")(\">",
    "e",
    ".",
    "-",
    "\n",
    "M",
    "A 1e6 1e6 0 1 1",
    "2",
    "#e 0 0 3 0",
    "f 1/1",
    "v 1 2",
];

/// Numbers that stay valid syntax in every format but stress the geometry: indices out of
/// range, degenerate and huge coordinates, sign flips.
const NUMBERS: &[&str] = &[
    "-1", "0", "1e308", "-1e308", "1e-320", "99999999", "2", "0.5", "-0.0", "1e6", "3", "-7.25",
];

fn mutate(seed: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut b = seed.to_vec();
    for _ in 0..1 + rng.below(2) {
        let at = rng.below(b.len() + 1);
        // Mostly numbers (they reach the geometry), sometimes structure (the parsers).
        let choice = match rng.below(10) {
            0..=4 => 3,
            5 | 6 => 1,
            7 => 2,
            8 => 0,
            _ => 4,
        };
        match choice {
            0 if !b.is_empty() => {
                let end = (at + 1 + rng.below(16)).min(b.len());
                b.drain(at.min(end)..end);
            }
            1 => {
                let t = TOKENS[rng.below(TOKENS.len())].as_bytes();
                b.splice(at..at, t.iter().copied());
            }
            2 if at < b.len() => b[at] = (rng.next_u64() & 0xff) as u8,
            3 if !b.is_empty() => {
                // Replace a digit run with a token (numbers are where geometry lives).
                let start = (at..b.len()).find(|&i| b[i].is_ascii_digit());
                if let Some(s) = start {
                    let e = (s..b.len())
                        .find(|&i| !b[i].is_ascii_digit() && b[i] != b'.')
                        .unwrap_or(b.len());
                    let t = NUMBERS[rng.below(NUMBERS.len())].as_bytes();
                    b.splice(s..e, t.iter().copied());
                }
            }
            _ => b.truncate(at),
        }
    }
    b
}

fn seeds() -> Vec<(PathBuf, Vec<u8>)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let anchors = root.join("tests/data");
    let mut out = Vec::new();
    let mut add = |p: PathBuf| {
        let bytes = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        out.push((p, bytes));
    };
    for name in [
        "simple",
        "vertex",
        "squaretwist",
        "box",
        "cube-cp",
        "cube-folded",
        "diagonal-folded",
    ] {
        add(anchors.join(format!("fold/{name}.fold")));
    }
    for name in [
        "simpleVertex",
        "wavy_pleats",
        "waterbombBase",
        "birdBase",
        "singlesquaretwist",
    ] {
        add(anchors.join(format!("origamisimulator/{name}.svg")));
    }
    add(root.join("patterns/miura.fold"));
    // The other formats from bundled designs, as crease writes them.
    let miura = io::read(&root.join("patterns/miura-bent.fold")).unwrap();
    for (ext, format) in [
        ("cp", Format::Cp),
        ("obj", Format::Obj),
        ("svg", Format::Svg),
    ] {
        let text = io::to_string(&miura, format).unwrap();
        out.push((
            PathBuf::from(format!("miura-bent.{ext}")),
            text.into_bytes(),
        ));
    }
    out
}

fn cases_per_seed() -> usize {
    std::env::var("CREASE_FUZZ_CASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(60)
}

#[test]
fn mutated_files_never_panic_on_import_verify_or_export() {
    let seeds = seeds();
    let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
    let mut imported = 0;
    let mut tried = 0;
    for (path, bytes) in &seeds {
        for case in 0..cases_per_seed() {
            let mutated = mutate(bytes, &mut rng);
            let name = path.clone();
            let run = std::panic::catch_unwind(|| {
                let Ok(file) = io::read_bytes(&name, mutated.clone()) else {
                    return false;
                };
                let report = crease::fab::verify(&file.mesh, None, Default::default());
                let _ = report.pass();
                for format in [Format::Fold, Format::Cp, Format::Svg, Format::Obj] {
                    let _ = io::to_string(&file.mesh, format);
                }
                true
            });
            tried += 1;
            match run {
                Ok(ok) => imported += ok as usize,
                Err(_) => {
                    let keep = std::env::temp_dir().join(format!(
                        "crease-fuzz-{}-{case}.{}",
                        path.file_stem().unwrap().to_string_lossy(),
                        path.extension().unwrap().to_string_lossy()
                    ));
                    std::fs::write(&keep, &mutated).unwrap();
                    panic!(
                        "{} case {case} panicked; input kept at {}",
                        path.display(),
                        keep.display()
                    );
                }
            }
        }
    }
    // The mutations must reach past the parsers, or the test checks little.
    assert!(
        imported * 10 > tried,
        "only {imported} of {tried} mutations imported"
    );
}

#[test]
fn mutated_files_through_the_binary_exit_0_1_or_2_and_write_all_or_nothing() {
    let seeds = seeds();
    let mut rng = Rng::new(0x2545_f491_4f6c_dd1d);
    let dir = common::Scratch::new("fuzz-bin");
    for (k, (path, bytes)) in seeds.iter().enumerate() {
        for case in 0..3 {
            let input = dir.join(format!(
                "in-{k}-{case}.{}",
                path.extension().unwrap().to_string_lossy()
            ));
            std::fs::write(&input, mutate(bytes, &mut rng)).unwrap();
            let output = dir.join(format!("out-{k}-{case}.fold"));
            let (code, _, err) =
                run_crease(&["convert", input.to_str().unwrap(), output.to_str().unwrap()]);
            assert!(
                [0, 1, 2].contains(&code),
                "{}: exit {code}: {err}",
                input.display()
            );
            assert!(!err.contains("panicked"), "{}: {err}", input.display());
            if code == 0 {
                io::read(&output).expect("what convert writes reads back");
            } else {
                assert!(!output.exists(), "{}: a failed run wrote", input.display());
                assert_eq!(err.trim_end().lines().count(), 1, "{err}");
            }
            let out = dir.join(format!("fab-{k}-{case}"));
            let (code, _, err) = run_crease(&[
                "fab",
                input.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ]);
            assert!(
                [0, 1, 2].contains(&code),
                "{}: fab exit {code}: {err}",
                input.display()
            );
            if code != 0 {
                assert!(!out.exists(), "{}: a failed fab wrote", input.display());
            }
        }
    }
}

//! Bad input through the real binary: exit status 2, one line naming the file and the
//! cause, never a panic, and no output file left behind.

use crate::common;

use common::run_crease;
use std::path::Path;

fn scratch(name: &str, content: &str) -> common::ScratchFile {
    common::scratch_file("cli", name, content)
}

fn assert_bad_input(path: &Path, cause: &str) {
    let out = path.with_file_name(format!(
        "{}-out.fold",
        path.file_name().unwrap().to_string_lossy()
    ));
    for args in [
        vec!["info", path.to_str().unwrap()],
        vec!["convert", path.to_str().unwrap(), out.to_str().unwrap()],
    ] {
        let (code, _, err) = run_crease(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
        assert!(
            err.contains(path.file_name().unwrap().to_str().unwrap()),
            "names the file: {err}"
        );
        assert!(err.to_lowercase().contains(cause), "says '{cause}': {err}");
        assert!(!out.exists(), "no output written for bad input");
    }
}

#[test]
fn malformed_json() {
    assert_bad_input(
        &scratch("broken.fold", "{\"vertices_coords\": [[0,0],"),
        "json",
    );
}

#[test]
fn index_out_of_range() {
    let fold = r#"{"vertices_coords": [[0,0],[1,0],[0,1]], "faces_vertices": [[0,1,7]],
                   "edges_vertices": [[0,1],[1,2],[2,0]]}"#;
    assert_bad_input(&scratch("range.fold", fold), "vertex 7");
}

#[test]
fn bad_coincidence_groups() {
    let fold = |groups: &str| {
        format!(
            r#"{{"vertices_coords": [[0,0],[1,0],[0,1]], "faces_vertices": [[0,1,2]],
                 "crease:coincidentVertices": {groups}}}"#
        )
    };
    assert_bad_input(&scratch("group-range.fold", &fold("[[0, 9]]")), "vertex 9");
    assert_bad_input(&scratch("group-one.fold", &fold("[[1]]")), "two or more");
    assert_bad_input(
        &scratch("group-twice.fold", &fold("[[0, 1], [1, 2]]")),
        "twice",
    );
}

#[test]
fn non_manifold_mesh() {
    // Three triangles on one edge (0–1).
    let fold = r#"{"vertices_coords": [[0,0,0],[1,0,0],[0,1,0],[0,-1,0],[0,0,1]],
                   "faces_vertices": [[0,1,2],[1,0,3],[0,1,4]]}"#;
    assert_bad_input(&scratch("fin.fold", fold), "non-manifold");
}

#[test]
fn unknown_svg_stroke_colour() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
        <rect x="0" y="0" width="10" height="10" stroke="#000"/>
        <line x1="0" y1="0" x2="10" y2="10" stroke="#123456"/></svg>"##;
    assert_bad_input(&scratch("colour.svg", svg), "#123456");
}

#[test]
fn empty_files() {
    assert_bad_input(&scratch("empty.fold", ""), "empty");
    assert_bad_input(&scratch("empty.svg", ""), "empty");
    assert_bad_input(&scratch("empty.cp", ""), "no crease");
}

#[test]
fn malformed_cp_line() {
    assert_bad_input(&scratch("bad.cp", "1 0 0 1 1\n2 0 0 x 1\n"), "line 2");
}

#[test]
fn missing_file_and_unknown_extension() {
    let (code, _, err) = run_crease(&["info", "/nonexistent/design.fold"]);
    assert_eq!(code, 2);
    assert!(err.contains("/nonexistent/design.fold"));
    assert_bad_input(&scratch("design.stl", "solid x"), "unknown file type");
}

#[test]
fn info_prints_counts() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura.fold");
    let (code, out, _) = run_crease(&["info", p.to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(out.contains("vertices:     81"), "{out}");
    assert!(
        out.contains("3D folded form: yes, crease pattern: yes"),
        "{out}"
    );
}

/// Command lines that named missing vertices, impossible thresholds or malformed lists
/// used to panic or be accepted; each is now exit 2 with one line naming the cause, and
/// nothing is written.
#[test]
fn bad_vertex_lists_thresholds_and_condition_lists_exit_2_with_one_line() {
    let miura = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura.fold");
    let m = miura.to_str().unwrap();
    let folder = common::Scratch::new("cli-bad");
    let out = folder.join("cli-bad.fold");
    let o = out.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![
                "deform",
                m,
                "--drag",
                "40=+0,+0,+5",
                "--fix",
                "99999",
                "-o",
                o,
            ],
            "99999",
        ),
        (
            vec!["fold", m, "--amount", "0.3", "--fix", "99999", "-o", o],
            "99999",
        ),
        (
            vec![
                "deform",
                m,
                "--drag",
                "40=+0,+0,+5",
                "--remesh",
                "1.5",
                "-o",
                o,
            ],
            "remesh",
        ),
        (
            vec!["verify", m, "--conditions", "developability,,convexity"],
            "empty entry",
        ),
        (
            vec!["verify", m, "--conditions", "developability,developability"],
            "twice",
        ),
        // The layer search's time and memory, on each command that searches.
        (vec!["verify", m, "--budget", "0"], "--budget"),
        (vec!["verify", m, "--memory", "NaN"], "--memory"),
        (vec!["verify", m, "--memory", "1"], "from 10 to 200000 MB"),
        (
            vec!["fold", m, "--flat", "--memory", "1e9", "-o", o],
            "--memory",
        ),
        (
            vec!["convert", m, o, "--assign", "--budget", "-3"],
            "--budget",
        ),
    ];
    for (args, cause) in cases {
        let (code, _, err) = run_crease(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(cause), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} wrote {o}");
    }
}

#[test]
fn fix_takes_commas_like_drag_and_a_fold_holds_what_is_fixed() {
    let miura = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/plane.fold");
    let folder = common::Scratch::new("cli-fix");
    let out = folder.join("cli-fix.fold");
    let (code, _, err) = run_crease(&[
        "deform",
        miura.to_str().unwrap(),
        "--drag",
        "80=+0,+0,+10",
        "--fix",
        "0,1,9",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let before = crease::io::read(&miura).unwrap();
    let after = crease::io::read(&out).unwrap();
    for v in [0, 1, 9] {
        assert_eq!(
            after.positions()[v],
            before.positions()[v],
            "vertex {v} is held"
        );
    }
}

#[test]
fn machines_are_listed_and_found_in_the_working_folder() {
    let (code, list, _) = run_crease(&["machines"]);
    assert_eq!(code, 0);
    for name in ["generic-hpgl", "hp7475a", "roland-cutter"] {
        assert!(list.lines().any(|l| l.starts_with(name)), "{list}");
    }
    assert!(!list.contains("Cargo"), "only profiles are listed: {list}");
    // A profile beside the user's design is found by name.
    let dir = common::Scratch::new("cli-machine");
    let profile = Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/generic-hpgl.toml");
    std::fs::copy(profile, dir.join("my-cutter.toml")).unwrap();
    let design = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura-bent.fold");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_crease"))
        .current_dir(&dir)
        .args([
            "fab",
            design.to_str().unwrap(),
            "--machine",
            "my-cutter",
            "--out",
            "job",
        ])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("job/sheet.hpgl").is_file());
}

#[test]
fn coordinates_beyond_any_sheet_are_refused() {
    let simple = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fold/simple.fold"),
    )
    .unwrap();
    assert!(simple.contains("[0,1,0]"));
    let far = simple.replacen("[0,1,0]", "[0,2e6,0]", 1);
    assert_bad_input(&scratch("coordinate-far.fold", &far), "within 1 km");
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 100 100">
<line x1="0" y1="0" x2="1e12" y2="0" stroke="#000"/><line x1="1e12" y1="0" x2="0" y2="100" stroke="#000"/>
<line x1="0" y1="100" x2="0" y2="0" stroke="#000"/></svg>"##;
    assert_bad_input(&scratch("coordinate-far.svg", svg), "within 1 km");
}

#[test]
fn svg_roots_that_scale_nothing_and_cut_short_files_are_refused() {
    let body = r##"<line x1="0" y1="0" x2="100" y2="0" stroke="#000"/><line x1="100" y1="0" x2="100" y2="100" stroke="#000"/><line x1="100" y1="100" x2="0" y2="0" stroke="#000"/>"##;
    let svg = |width: &str| {
        format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="100mm" viewBox="0 0 100 100">{body}</svg>"#
        )
    };
    assert_bad_input(
        &scratch("root-negative.svg", &svg("-100mm")),
        "positive length",
    );
    assert_bad_input(&scratch("root-zero.svg", &svg("0mm")), "positive length");
    assert_bad_input(&scratch("root-nan.svg", &svg("NaN")), "not a length");
    assert_bad_input(
        &scratch("root-furlongs.svg", &svg("100furlongs")),
        "not a length",
    );
    let unclosed = svg("100mm").replace("</svg>", "");
    assert_bad_input(&scratch("root-unclosed.svg", &unclosed), "cut short");
    let colour = svg("100mm").replacen("#000", "#0\n00", 1);
    assert_bad_input(&scratch("root-colour-newline.svg", &colour), "#0\\n00");
    // A percentage is relative to a page: stated, and read as px.
    let (code, info, err) = run_crease(&[
        "info",
        scratch("root-percent.svg", &svg("100%")).to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("100%"), "{err}");
    assert!(info.contains("26.458"), "{info}");
}

#[test]
fn a_3d_only_design_converts_to_svg_as_its_unfolding() {
    let simple = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fold/simple.fold");
    let folder = common::Scratch::new("cli-3d");
    let out = folder.join("cli-3d.svg");
    let (code, _, err) = run_crease(&["convert", simple.to_str().unwrap(), out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("simple.fold"),
        "the note names the input: {err}"
    );
    let design = crease::io::read(&simple).unwrap();
    let cp = crease::io::read(&out).unwrap();
    // Isometric: the written crease pattern has the 3D form's edge lengths (the SVG
    // numbers its vertices anew, so lengths are compared as sorted lists).
    let flat = cp.crease_pattern().unwrap();
    let sorted = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v
    };
    let l3 = sorted(
        design
            .edges()
            .iter()
            .map(|e| (design.positions()[e.vertices[0]] - design.positions()[e.vertices[1]]).norm())
            .collect(),
    );
    let l2 = sorted(
        cp.edges()
            .iter()
            .map(|e| (flat[e.vertices[0]] - flat[e.vertices[1]]).norm())
            .collect(),
    );
    assert_eq!(l3.len(), l2.len());
    for (a, b) in l3.iter().zip(&l2) {
        assert!((a - b).abs() < 1e-3 * a, "{l3:?} vs {l2:?}");
    }
}

#[test]
fn a_shape_drawn_four_thousand_times_imports_as_one() {
    let square = r##"<rect x="0" y="0" width="100" height="100" stroke="#000" fill="none"/>"##;
    let svg = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 100 100">{}<line x1="0" y1="0" x2="100" y2="100" stroke="#f00"/><line x1="0" y1="0" x2="100" y2="100" stroke="#ff0"/></svg>"##,
        square.repeat(4000)
    );
    let path = scratch("square-4000-times.svg", &svg);
    let mesh = crease::io::read(&path).unwrap();
    assert_eq!(mesh.vertex_count(), 4);
    assert_eq!(mesh.faces().len(), 2);
    let count =
        |a: crease::mesh::Assignment| mesh.edges().iter().filter(|e| e.assignment == a).count();
    assert_eq!(count(crease::mesh::Assignment::Boundary), 4);
    // The diagonal drawn as mountain and as facet line: the mountain wins.
    assert_eq!(count(crease::mesh::Assignment::Mountain), 1);
    assert_eq!(mesh.edges().len(), 5);
}

#[test]
fn a_fold_that_gets_nowhere_fails_and_writes_nothing() {
    let plane = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/plane.fold");
    let folder = common::Scratch::new("cli-nowhere");
    let out = folder.join("cli-nowhere.fold");
    let (code, _, err) = run_crease(&[
        "fold",
        plane.to_str().unwrap(),
        "--amount",
        "0.5",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("got nowhere") && err.contains("nothing was written"),
        "{err}"
    );
    assert!(!out.exists());
    // Asking for nothing and getting it is fine.
    let miura = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura.fold");
    let (code, _, err) = run_crease(&[
        "fold",
        miura.to_str().unwrap(),
        "--amount",
        "0",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
}

/// The option blocks of `crease SUB --help`: (long name, its whole description).
fn option_help(sub: &str) -> Vec<(String, String)> {
    let (code, out, err) = run_crease(&[sub, "--help"]);
    assert_eq!(code, 0, "{err}");
    let mut blocks: Vec<(String, String)> = Vec::new();
    for line in out.lines() {
        let t = line.trim_start();
        let starts = t.starts_with("--") || (t.starts_with('-') && t.get(2..4) == Some(", "));
        if starts && line.starts_with("  ") {
            let long = t
                .split_whitespace()
                .find(|w| w.starts_with("--"))
                .unwrap()
                .trim_end_matches(',')
                .to_string();
            blocks.push((long, t.to_string()));
        } else if let Some(last) = blocks.last_mut() {
            last.1.push(' ');
            last.1.push_str(t);
        }
    }
    blocks
}

#[test]
fn every_option_that_takes_a_value_says_its_default_and_conditions_are_all_listed() {
    // Options whose value is the job itself have no default to state.
    let no_default = [
        "generate --output",
        "fold --output",
        "fold --amount",
        "deform --output",
        "deform --drag",
        "deform --script",
        "plot --port",
        "emulate --link",
        "emulate --fail-after",
        "emulate --reconnect-after",
    ];
    for sub in [
        "generate", "info", "verify", "fold", "deform", "fab", "plot", "emulate", "convert",
        "studio",
    ] {
        for (long, text) in option_help(sub) {
            let takes_value = text
                .split_whitespace()
                .nth(1)
                .is_some_and(|w| w.starts_with('<'))
                || text.contains(&format!("{long} <"))
                || text.contains(&format!("{long} [<"));
            if !takes_value || no_default.contains(&format!("{sub} {long}").as_str()) {
                continue;
            }
            assert!(
                text.to_lowercase().contains("default"),
                "crease {sub} {long} does not say its default: {text}"
            );
        }
    }
    for sub in ["verify", "deform"] {
        let conditions = option_help(sub)
            .into_iter()
            .find(|(l, _)| l == "--conditions")
            .unwrap()
            .1;
        for family in crease::constraints::Family::ALL {
            assert!(
                conditions.contains(family.name()),
                "crease {sub} --conditions does not list {}",
                family.name()
            );
        }
    }
}

#[test]
fn arcs_of_a_kilometre_radius_import_as_few_points_or_are_refused_by_name() {
    let svg = |arc: &str| {
        format!(
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="200mm" height="200mm" viewBox="0 0 200 200">
<path d="M 0 0 L 200 0 L 200 200 L 0 200 Z" stroke="#000000" fill="none"/>
<path d="M 0 100 {arc}" stroke="#ff0000" fill="none"/></svg>"##
        )
    };
    // A gentle arc across the sheet: its sagitta (5 µm) is below the flattening tolerance,
    // so it stays one straight crease, not 10,000 points.
    let gentle = scratch("arc-gentle.svg", &svg("A 1000000 1000000 0 0 1 200 100"));
    let (code, out, err) = run_crease(&["info", gentle.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("vertices:     6 "), "{out}");
    // The large-arc branch of the same circle runs two kilometres out: refused, by name.
    let huge = scratch("arc-huge.svg", &svg("A 1000000 1000000 0 1 1 200 100"));
    let (code, _, err) = run_crease(&["info", huge.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("arc-huge.svg") && err.contains("1 km"),
        "{err}"
    );
}

#[test]
fn a_converted_file_gets_the_verdict_of_its_original() {
    // An SVG's coordinates are rounded; verification allows for it. Written as FOLD the
    // numbers are exact, so the FOLD records the rounding (crease:coordinatePrecision)
    // and keeps the allowance: simpleVertex.svg passed while its FOLD failed.
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/origamisimulator");
    for name in [
        "simpleVertex",
        "singlesquaretwist",
        "waterbombBase",
        "miura-ori",
        "hypar",
    ] {
        let svg = data.join(format!("{name}.svg"));
        let folder = common::Scratch::new("verdict");
        let fold = folder.join(format!("{name}.fold"));
        let (code, _, err) =
            run_crease(&["convert", svg.to_str().unwrap(), fold.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
        let original = run_crease(&["verify", svg.to_str().unwrap()]).0;
        let converted = run_crease(&["verify", fold.to_str().unwrap()]).0;
        assert_eq!(original, converted, "{name}: the SVG and its FOLD disagree");
        let text = std::fs::read_to_string(&fold).unwrap();
        let rounded = crease::io::read(&svg).unwrap().coordinate_precision > 0.0;
        assert_eq!(
            text.contains("crease:coordinatePrecision"),
            rounded,
            "{name}"
        );
    }
    // A recorded rounding past half a millimetre would excuse anything: refused.
    let folder = common::Scratch::new("precision");
    let bad = folder.join("precision.fold");
    std::fs::write(
        &bad,
        r#"{"vertices_coords": [[0,0],[10,0],[0,10]], "faces_vertices": [[0,1,2]], "crease:coordinatePrecision": 1e308}"#,
    )
    .unwrap();
    let (code, _, err) = run_crease(&["verify", bad.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("crease:coordinatePrecision"), "{err}");
}

/// A command typed without one of its required arguments says which, on one line, with
/// the command's usage and its help: the list clap prints under "the following required
/// arguments were not provided:" was once cut off, leaving the heading and nothing else.
#[test]
fn a_missing_argument_is_named_with_the_usage_of_its_command() {
    let pattern = scratch(
        "missing-args.fold",
        include_str!("../data/fold/simple.fold"),
    );
    let p = pattern.to_str().unwrap();
    for (args, missing, help) in [
        (
            vec!["generate", "miura"],
            "--output <OUTPUT>",
            "crease generate --help",
        ),
        (vec!["fab"], "<DESIGN>", "crease fab --help"),
        (
            vec!["fit", p, "-o", "z.fold"],
            "--to <TO>",
            "crease fit --help",
        ),
        (
            vec!["deform", p, "--drag", "0=+0,+0,+1"],
            "--output <OUTPUT>",
            "crease deform --help",
        ),
        (
            vec!["plot", "job.hpgl"],
            "--port <PORT>",
            "crease plot --help",
        ),
        (vec!["emulate"], "--link <PATH>", "crease emulate --help"),
        // fold needs one of two: both are named.
        (
            vec!["fold", p, "-o", "q.fold"],
            "<--amount <AMOUNT>|--flat>",
            "crease fold --help",
        ),
    ] {
        let (code, _, err) = run_crease(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
        assert!(err.contains("were not provided: "), "{args:?}: {err}");
        assert!(err.contains(missing), "{args:?} names {missing}: {err}");
        assert!(
            err.contains("usage: crease "),
            "{args:?} gives the usage: {err}"
        );
        assert!(err.contains(help), "{args:?} points at `{help}`: {err}");
    }
    assert!(!std::path::Path::new("z.fold").exists() && !std::path::Path::new("q.fold").exists());
}

/// A flag whose value is optional (`--count`, `--remesh`) or repeated (`--fix`) reads
/// the file typed after it as its value; the one line says so and what to do, points
/// at the command's help, and nothing is written. A value that is neither a file nor named like one keeps clap's
/// message alone.
#[test]
fn a_file_read_as_a_flags_value_gets_a_tip() {
    let pattern = scratch("value-tip.fold", include_str!("../data/fold/simple.fold"));
    let p = pattern.to_str().unwrap();
    for (args, value, flag) in [
        (vec!["verify", "--count", p], p, "--count"),
        (
            vec!["fold", "--fix", "3", "design.fold", "-o", "q.fold"],
            "design.fold",
            "--fix",
        ),
        (
            vec![
                "deform",
                "--remesh",
                p,
                "--drag",
                "0=+0,+0,+1",
                "-o",
                "q.fold",
            ],
            p,
            "--remesh",
        ),
    ] {
        let (code, _, err) = run_crease(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
        assert!(
            err.contains(&format!("'{value}' was read as {flag}'s value"))
                && err.contains(&format!("give it before {flag}")),
            "{args:?}: {err}"
        );
        // clap prints no usage here; the help named is still the command's.
        let help = format!("see `crease {} --help`", args[0]);
        assert!(err.contains(&help), "{args:?} points at {help}: {err}");
    }
    let (code, _, err) = run_crease(&["verify", "--count", "many", p]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("'many'") && !err.contains("tip:"), "{err}");
    assert!(!std::path::Path::new("q.fold").exists());
}

/// A mistyped flag keeps clap's suggestion on the one line.
#[test]
fn a_mistyped_flag_gets_a_did_you_mean() {
    let (code, _, err) = run_crease(&["fab", "x.fold", "--mahcine", "cameo"]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(
        err.contains("'--mahcine'") && err.contains("'--machine'"),
        "{err}"
    );
}

/// A negative number after a flag is its value, checked against its range, not an
/// unknown flag.
#[test]
fn a_negative_value_is_range_checked_not_taken_for_a_flag() {
    let pattern = scratch("negative.fold", include_str!("../data/fold/simple.fold"));
    let (code, _, err) = run_crease(&["fab", pattern.to_str().unwrap(), "--width", "-3"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--width = -3") && err.contains("from 5 to 50000 mm"),
        "{err}"
    );
}

/// `fab` names its output folder as every other command names its output (`-o`,
/// `--output`), and still takes `--out`.
#[test]
fn fab_takes_dash_o_and_output_like_the_other_commands() {
    let pattern = scratch("fab-o.fold", include_str!("../data/fold/simple.fold"));
    for flag in ["-o", "--output", "--out"] {
        let dir = common::Scratch::new(&format!("fab-o-{}", flag.trim_start_matches('-')));
        let (code, _, err) = run_crease(&[
            "fab",
            pattern.to_str().unwrap(),
            flag,
            dir.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{flag}: {err}");
        assert!(
            dir.join("sheet.svg").exists(),
            "{flag}: no sheet.svg in {}",
            dir.display()
        );
    }
    let help = option_help("fab");
    assert!(
        help.iter()
            .any(|(long, text)| long == "--output" && text.starts_with("-o, --output")),
        "{help:?}"
    );
}

/// `fab` says the pattern's size on its media (Cricut's steps send the maker to it), and
/// refuses `--tab` on a sheet instead of dropping it without a word.
#[test]
fn fab_prints_the_sheet_size_and_refuses_a_tab_on_a_sheet() {
    let pattern = format!("{}/patterns/miura.fold", env!("CARGO_MANIFEST_DIR"));
    let dir = common::Scratch::new("fab-size");
    let (code, _, err) = run_crease(&[
        "fab",
        &pattern,
        "--material",
        "heavy-card-300gsm",
        "--width",
        "150",
        "-o",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    let size = &report["sheet"]["size_mm"];
    assert!((size[0].as_f64().unwrap() - 150.0).abs() < 0.05, "{size}");
    let said = format!(
        "the pattern is 150.0 × {:.1} mm on a4 (210 × 297 mm, Heavy card 300 g/m²)",
        size[1].as_f64().unwrap()
    );
    assert!(err.contains(&said), "{said} not in {err}");
    let refused = dir.join("tab");
    let (code, _, err) = run_crease(&[
        "fab",
        &pattern,
        "--tab",
        "5",
        "-o",
        refused.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("--tab: the design is a sheet, not a tube"),
        "{err}"
    );
    assert!(!refused.exists());
}

/// Issue 47, item 2: the pull that stopped at step 75 of 120 with a twist allowance
/// (two smoothness rows took turns in Newton's correction) reaches its target, and the
/// design verifies and cuts.
#[test]
fn the_concentric_bowl_takes_a_20_mm_pull_with_a_twist_allowance_verifies_and_cuts() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bowl = root.join("patterns/concentric.fold");
    let dir = common::Scratch::new("cli-bowl");
    let out = dir.join("bowl.fold");
    let (code, _, err) = run_crease(&[
        "deform",
        bowl.to_str().unwrap(),
        "--drag",
        "80=+0,+0,+20",
        "--steps",
        "120",
        "--alpha",
        "0.1",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let start = crease::io::read(&bowl).unwrap().positions()[80];
    let end = crease::io::read(&out).unwrap().positions()[80];
    let target = start + crease::mesh::Vec3::new(0.0, 0.0, 20.0);
    assert!((end - target).norm() < 0.1, "{end:?} for {target:?}");
    let (code, _, err) = run_crease(&["verify", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let sheet = dir.join("sheet");
    let (code, _, err) = run_crease(&[
        "fab",
        out.to_str().unwrap(),
        "--media",
        "a3",
        "-o",
        sheet.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let job = std::fs::read_to_string(sheet.join("sheet.hpgl")).unwrap();
    assert!(job.matches("PD").count() > 20, "{job}");
}

/// Issue 47, item 2: a drag that cannot finish (the arc with rigid strips, whose
/// smoothness bound leaves no room at the last step) says what to try without repeating
/// what was given and writes nothing; with --keep-partial it writes the last state that
/// held every condition, names the step and still exits 1.
#[test]
fn a_drag_that_cannot_finish_keeps_its_last_good_state_only_when_asked() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let arc = root.join("patterns/arc.fold");
    let folder = common::Scratch::new("cli-partial");
    let out = folder.join("cli-partial.fold");
    let conditions = "developability,fold-angle-range,twist-range,boundary-angle,smoothness";
    let args = |partial: bool| {
        let mut a = vec![
            "deform",
            arc.to_str().unwrap(),
            "--drag",
            "80=83.48,121.6,40",
            "--steps",
            "60",
            "--fix",
            "40,31,49",
            "--alpha",
            "0",
            "--conditions",
            conditions,
            "-o",
            out.to_str().unwrap(),
        ];
        if partial {
            a.push("--keep-partial");
        }
        a
    };
    let (code, _, err) = run_crease(&args(false));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("nothing was written"), "{err}");
    let hint = err.lines().find(|l| l.starts_with("hint:")).expect(&err);
    assert!(hint.contains("--keep-partial"), "{hint}");
    assert!(hint.contains("more steps than --steps 60"), "{hint}");
    assert!(
        !hint.contains("--alpha") && !hint.contains("--fix"),
        "{hint}"
    );
    assert!(!out.exists());

    let (code, _, err) = run_crease(&args(true));
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("stage 1 did not finish (step 60 of 60")
            && err.contains("holds the last state that held every condition"),
        "{err}"
    );
    let (code, _, err) = run_crease(&["verify", out.to_str().unwrap(), "--conditions", conditions]);
    assert_eq!(code, 0, "{err}");
    // It went most of the way: the corner rose 20 mm or more of its 40.
    let z = crease::io::read(&out).unwrap().positions()[80].z;
    assert!(z > 20.0, "{z}");
}

/// Issue 47, item 4: a fit cut short while it still comes nearer says to raise --steps
/// and blames no condition; a fit whose design passes through itself writes nothing
/// unless --force.
#[test]
fn fit_tells_a_step_limit_from_a_block_and_writes_no_design_through_itself_unforced() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = common::Scratch::new("cli-fit");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let (code, _, err) = run_crease(&["surface", "saddle", "-o", &path("saddle.obj")]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = run_crease(&["generate", "waterbomb", "-o", &path("waterbomb.fold")]);
    assert_eq!(code, 0, "{err}");

    let (code, _, err) = run_crease(&[
        "fit",
        &path("waterbomb.fold"),
        "--to",
        &path("saddle.obj"),
        "--steps",
        "20",
        "-o",
        &path("short.fold"),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("fit: step limit after 20 steps"), "{err}");
    assert!(err.contains("still improving at the step limit"), "{err}");
    assert!(err.contains("raise --steps"), "{err}");
    assert!(!err.contains("blocked by"), "{err}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path("short.fit.json")).unwrap()).unwrap();
    assert_eq!(report["still_improving"], true, "{report}");
    assert!(report["blocked_by"].is_null());

    // The folded waterbomb pulled onto the saddle for 140 steps ends with faces through
    // each other.
    let folded = root.join("patterns/waterbomb-folded.fold");
    let fit = |force: bool| {
        let mut args = vec![
            "fit".to_string(),
            folded.to_str().unwrap().to_string(),
            "--to".into(),
            path("saddle.obj"),
            "--steps".into(),
            "140".into(),
            "-o".into(),
            path("through.fold"),
        ];
        if force {
            args.push("--force".into());
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        run_crease(&args)
    };
    let (code, _, err) = fit(false);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("passes through itself") && err.contains("nothing was written"),
        "{err}"
    );
    assert!(!dir.join("through.fold").exists());
    assert!(!dir.join("through.fit.json").exists());
    let (_, _, err) = fit(true);
    assert!(err.contains("pass through each other"), "{err}");
    let written = crease::io::read(&dir.join("through.fold")).unwrap();
    assert!(!crease::fab::self_intersections(&written).is_empty());
}

/// Issue 47, item 9: every command's --help is laid out alike, each option's help on its
/// own line beside it (`emulate` had clap's next-line layout, its long value names
/// pushing every help under its option).
#[test]
fn every_help_puts_each_option_beside_its_help() {
    let (_, top, _) = run_crease(&["--help"]);
    let commands: Vec<&str> = top
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(commands.len() >= 14, "{commands:?}");
    for sub in commands {
        let (code, help, err) = run_crease(&[sub, "--help"]);
        assert_eq!(code, 0, "{sub}: {err}");
        let options = help
            .lines()
            .skip_while(|l| !l.starts_with("Options:"))
            .take_while(|l| !l.is_empty());
        for line in options.filter(|l| l.trim_start().starts_with('-')) {
            let spec_and_help = line.trim_start();
            let beside = spec_and_help
                .split_once("  ")
                .is_some_and(|(_, h)| !h.trim().is_empty());
            assert!(
                beside,
                "crease {sub} --help: \"{line}\" has its help on the next line"
            );
        }
    }
}

/// Issue 47, item 3: the recipes `deform --help` gives are run as printed: each verifies,
/// and with --keep-outline the arch keeps its sheet within 1% of its size, where the same
/// corner drag without it grows the sheet and says so, naming --keep-outline.
#[test]
fn the_deform_help_recipes_run_as_printed_and_keep_their_outline() {
    let dir = common::Scratch::new("cli-recipes");
    let at = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let (code, _, err) = run_crease(&[
        "generate",
        "miura",
        "--nx",
        "6",
        "--ny",
        "10",
        "--fold",
        "0.5",
        "-o",
        &at("m.fold"),
    ]);
    assert_eq!(code, 0, "{err}");
    let (_, help, _) = run_crease(&["deform", "--help"]);
    // Each recipe's command: its first line and the continuation lines under it.
    let mut recipes: Vec<(String, String)> = Vec::new();
    for line in help.lines().skip_while(|l| !l.starts_with("Recipes")) {
        let t = line.trim_start();
        if let Some((name, command)) = t
            .split_once(':')
            .filter(|(_, c)| c.trim_start().starts_with("crease deform"))
        {
            recipes.push((name.to_string(), command.trim().to_string()));
        } else if line.starts_with("          --") {
            if let Some(last) = recipes.last_mut() {
                last.1 += &format!(" {t}");
            }
        }
    }
    let names: Vec<&str> = recipes.iter().map(|r| r.0.as_str()).collect();
    assert!(
        names.contains(&"arch") && names.contains(&"twist"),
        "{names:?}: {help}"
    );
    let flat = |path: &str| {
        let m = crease::io::read(std::path::Path::new(path)).unwrap();
        let (lo, hi) = crease::mesh::bounds(m.crease_pattern().unwrap());
        hi - lo
    };
    let start = flat(&at("m.fold"));
    // A recipe as printed, less the words in `leave_out`, its files in the scratch folder.
    let run_recipe = |command: &str, leave_out: &str| {
        let args: Vec<String> = command
            .split_whitespace()
            .skip(1)
            .filter(|w| *w != leave_out)
            .map(|w| {
                if w.ends_with(".fold") {
                    at(w)
                } else {
                    w.to_string()
                }
            })
            .collect();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        run_crease(&args)
    };
    for (name, command) in &recipes {
        let (code, _, err) = run_recipe(command, "");
        assert_eq!(code, 0, "{name}: {command}: {err}");
        assert!(!err.contains("--keep-outline holds"), "{name}: {err}");
        let out = at(&format!("{name}.fold"));
        let (code, _, verified) = run_crease(&["verify", &out]);
        assert_eq!(code, 0, "{name}: {verified}");
        let size = flat(&out);
        assert!(
            (size.x / start.x - 1.0).abs() < 0.025 && (size.y / start.y - 1.0).abs() < 0.025,
            "{name}: {size:?} from {start:?}"
        );
    }
    // The arch's drag without --keep-outline grows the sheet, and deform says so.
    let arch = &recipes.iter().find(|r| r.0 == "arch").unwrap().1;
    let (code, _, err) = run_recipe(arch, "--keep-outline");
    assert_eq!(code, 0, "{err}");
    let grown = flat(&at("arch.fold"));
    assert!(grown.x > 1.1 * start.x, "{grown:?} from {start:?}");
    assert!(
        err.contains("where it was") && err.contains("--keep-outline holds"),
        "{err}"
    );
}

#[test]
fn an_unknown_pattern_is_refused_naming_every_pattern_there_is() {
    // One refusal for the command line and the studio (PatternKind::parse).
    let folder = common::Scratch::new("unknown-pattern");
    let out = folder.join("unknown-pattern.fold");
    let (code, _, err) = run_crease(&["generate", "origami", "-o", out.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("unknown pattern \"origami\""), "{err}");
    for kind in crease::generate::PatternKind::ALL {
        assert!(err.contains(kind.name()), "{}: {err}", kind.name());
    }
    assert!(!out.exists());
}

#[test]
fn every_option_a_fab_message_names_is_a_flag_of_fab() {
    // The library keeps the options in its messages; the command line names each
    // `--word` (cli::fab::flag), so each must be one of fab's flags.
    let (code, help, err) = run_crease(&["fab", "--help"]);
    assert_eq!(code, 0, "{err}");
    for option in crease::fab::FabOption::ALL {
        let flag = format!("--{} ", option.word());
        let flag_with_value = format!("--{} <", option.word());
        assert!(
            help.contains(&flag) || help.contains(&flag_with_value),
            "{flag} is not in `crease fab --help`:\n{help}"
        );
    }
    // And a message names them so: a width out of range, by its flag.
    let (code, _, err) = run_crease(&[
        "fab",
        "patterns/miura.fold",
        "--width",
        "1e9",
        "--out",
        "/nonexistent/never",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--width = 1e9: "), "{err}");
}

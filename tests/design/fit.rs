//! `crease fit`: a Miura-ori pulled onto a dome and a saddle through the binary, its
//! report checked against distances computed here by brute force over every target
//! triangle, the result verified, free of self-intersection and fabricated; a target out
//! of reach ends with exit 1 and a named blocker; bad targets are refused.

use crate::common;

use common::run_crease;
use crease::mesh::{Vec2, Vec3};
use crease::pipeline::FitReport;
use std::path::Path;

/// The path `name` in a scratch folder of its own, removed with the guard.
fn scratch(name: &str) -> common::ScratchFile {
    common::ScratchFile::at("fit", name)
}

/// The scratch file `name`, written by `crease <args> -o` it (a `generate` or `surface`
/// command), which must succeed.
fn made(name: &str, args: &[&str]) -> common::ScratchFile {
    let path = scratch(name);
    let mut all = args.to_vec();
    all.extend(["-o", path.to_str().unwrap()]);
    let (code, _, err) = run_crease(&all);
    assert_eq!(code, 0, "{}: {err}", args.join(" "));
    path
}

/// The 12 × 12 Miura-ori of the acceptance, through the binary.
fn miura_12() -> (common::ScratchFile, f64) {
    let path = made(
        "miura12.fold",
        &["generate", "miura", "--nx", "12", "--ny", "12"],
    );
    let mesh = crease::io::read(&path).unwrap();
    let (lo, hi) = mesh.bounding_box();
    let span = (hi.x - lo.x).max(hi.y - lo.y);
    (path, span)
}

/// Distance from `p` to triangle `abc`, computed independently of the library: the
/// foot of the perpendicular when it falls inside (by signed areas), else the nearest
/// of the three sides (each a clamped projection).
fn distance_to_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let n = (b - a).cross(&(c - a));
    let foot = p - n * ((p - a).dot(&n) / n.norm_squared());
    let inside = [(a, b), (b, c), (c, a)]
        .iter()
        .all(|&(u, v)| (v - u).cross(&(foot - u)).dot(&n) >= 0.0);
    if inside {
        return (p - foot).norm();
    }
    [(a, b), (b, c), (c, a)]
        .iter()
        .map(|&(u, v)| {
            let t = ((p - u).dot(&(v - u)) / (v - u).norm_squared()).clamp(0.0, 1.0);
            (p - (u + (v - u) * t)).norm()
        })
        .fold(f64::INFINITY, f64::min)
}

/// A target OBJ read back by a reader written here: `v` and `f` lines.
fn read_obj(path: &Path) -> (Vec<Vec3>, Vec<[usize; 3]>) {
    let text = std::fs::read_to_string(path).unwrap();
    let (mut v, mut f) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first() {
            Some(&"v") => v.push(Vec3::new(
                w[1].parse().unwrap(),
                w[2].parse().unwrap(),
                w[3].parse().unwrap(),
            )),
            Some(&"f") => f.push([0, 1, 2].map(|k| w[k + 1].parse::<usize>().unwrap() - 1)),
            _ => {}
        }
    }
    (v, f)
}

/// Fits `pattern` to `target` through the binary; the exit code, the report, the design.
fn fit(
    pattern: &Path,
    target: &Path,
    name: &str,
    extra: &[&str],
) -> (i32, FitReport, common::ScratchFile, String) {
    let out = scratch(&format!("{name}.fold"));
    let mut args = vec![
        "fit",
        pattern.to_str().unwrap(),
        "--to",
        target.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    let (code, _, err) = run_crease(&args);
    // The report is written beside the design.
    let report_text = std::fs::read_to_string(out.with_file_name(format!("{name}.fit.json")))
        .unwrap_or_else(|e| panic!("no report ({e}): {err}"));
    let report: FitReport = serde_json::from_str(&report_text).unwrap();
    (code, report, out, err)
}

/// The report's distances against brute force: every surface point (its group's mean in
/// the written design) against every target triangle.
fn check_distances_by_brute_force(report: &FitReport, design: &Path, target: &Path) {
    let mesh = crease::io::read(design).unwrap();
    let x = mesh.positions();
    let mut seen = vec![false; x.len()];
    for g in &report.surface_groups {
        g.iter().for_each(|&v| seen[v] = true);
    }
    assert!(seen.iter().all(|&s| s), "every vertex is in a group");
    let (tv, tf) = read_obj(target);
    let distances: Vec<f64> = report
        .surface_groups
        .iter()
        .map(|g| {
            let p = g.iter().map(|&v| x[v]).sum::<Vec3>() / g.len() as f64;
            tf.iter()
                .map(|t| distance_to_triangle(p, tv[t[0]], tv[t[1]], tv[t[2]]))
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let largest = distances.iter().cloned().fold(0.0, f64::max);
    let rms = (distances.iter().map(|d| d * d).sum::<f64>() / distances.len() as f64).sqrt();
    // The FOLD file keeps 17 significant digits: the same figures to 1e-9 mm.
    assert!(
        (largest - report.distance.hausdorff_mm).abs() < 1e-9,
        "{largest} vs {}",
        report.distance.hausdorff_mm
    );
    assert!(
        (rms - report.distance.rms_mm).abs() < 1e-9,
        "{rms} vs {}",
        report.distance.rms_mm
    );
    let (lo, hi) = mesh.bounding_box();
    let diagonal = (hi - lo).norm();
    assert!((diagonal - report.distance.diagonal_mm).abs() < 1e-9);
}

/// Every condition of the fitted design `name` holds to 1e-9.
fn check_conditions_held(report: &FitReport, name: &str) {
    for c in &report.conditions {
        assert!(
            c.largest_residual < 1e-9,
            "{name}: {} {}",
            c.name,
            c.largest_residual
        );
    }
}

/// A fitted design passes `verify` with the fit's conditions, has no face through
/// another, and `fab` cuts it.
fn check_design_is_made(report: &FitReport, design: &Path, name: &str) {
    let names: Vec<&str> = report.conditions.iter().map(|c| c.name.as_str()).collect();
    let (code, out, err) = run_crease(&[
        "verify",
        design.to_str().unwrap(),
        "--conditions",
        &names.join(","),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let mesh = crease::io::read(design).unwrap();
    assert!(crease::fab::self_intersections(&mesh).is_empty());
    assert_eq!(report.self_intersections, 0);
    let dir = scratch(&format!("{name}-fab"));
    let (code, _, err) = run_crease(&[
        "fab",
        design.to_str().unwrap(),
        "--media",
        "a3",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::metadata(dir.join("sheet.hpgl")).unwrap().len() > 100);
    // The crease pattern written is the 3D form unfolded: every edge its length.
    let flat: &[Vec2] = mesh.crease_pattern().unwrap();
    for e in mesh.edges() {
        let [a, b] = e.vertices;
        let l3 = (mesh.positions()[a] - mesh.positions()[b]).norm();
        assert!(((flat[a] - flat[b]).norm() - l3).abs() < 1e-6 * l3);
    }
}

#[test]
fn a_miura_ori_fits_a_dome_and_a_saddle_within_a_percent_of_its_diagonal() {
    let (miura, span) = miura_12();
    let radius = 1.5 * span;
    let target_span = 1.6 * span;
    let (radius_text, span_text) = (radius.to_string(), target_span.to_string());
    let cap = made(
        "cap.obj",
        &[
            "surface",
            "cap",
            "--radius",
            &radius_text,
            "--span",
            &span_text,
        ],
    );
    // A saddle of the same curvature at its middle: z = d (x² − y²)/(S/2)², 2d/(S/2)² = 1/R.
    let depth = (target_span / 2.0).powi(2) / (2.0 * radius);
    let saddle = made(
        "saddle.obj",
        &[
            "surface",
            "saddle",
            "--depth",
            &depth.to_string(),
            "--span",
            &span_text,
        ],
    );
    for (target, name) in [(&cap, "dome"), (&saddle, "saddle")] {
        let (code, report, design, err) = fit(&miura, target, name, &[]);
        assert_eq!(code, 0, "{name}: {err}");
        assert!(report.distance.met);
        assert!(
            report.distance.hausdorff_relative <= 0.01,
            "{name}: {}",
            report.distance.hausdorff_relative
        );
        // Pulled: much closer than the rigid placement alone.
        assert!(report.distance.hausdorff_mm < 0.5 * report.placed.hausdorff_mm);
        check_distances_by_brute_force(&report, &design, target);
        check_design_is_made(&report, &design, name);
        check_conditions_held(&report, name);
    }
}

/// Issue 47: the generated waterbomb onto `crease surface saddle`, every option its
/// default. Its gradient pull stalls 5.5 mm away (the conditions let only a few percent
/// of it through); the Gauss–Newton steps that follow reach the goal within the default
/// step budget (0.99 mm of a 2.02 mm goal), and the design verifies and cuts.
#[test]
fn a_waterbomb_fits_the_default_saddle_with_default_options() {
    let waterbomb = made("waterbomb.fold", &["generate", "waterbomb"]);
    let saddle = made("default-saddle.obj", &["surface", "saddle"]);
    let (code, report, design, err) = fit(&waterbomb, &saddle, "waterbomb-saddle", &[]);
    assert_eq!(code, 0, "{err}");
    assert!(report.distance.met, "{err}");
    assert!(report.distance.hausdorff_relative <= 0.01, "{err}");
    assert_eq!(report.stopped, "converged", "{err}");
    assert!(report.steps <= crease::fit::DEFAULT_STEPS, "{err}");
    assert!(report.blocked_by.is_none() && !report.still_improving);
    // The pull alone stalled more than twice the goal away; the Gauss–Newton steps
    // brought it within the goal, and the summary says where they took over.
    let from = report.gauss_newton_from.expect("the pull stalled first");
    let stalled_at = report.history[from][1];
    assert!(stalled_at > 2.0 * report.distance.goal_mm, "{stalled_at}");
    assert!(
        report.distance.hausdorff_mm < 0.5 * report.distance.goal_mm,
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "the pull stalled at {stalled_at:.3} mm after step {from}"
        )),
        "{err}"
    );
    check_distances_by_brute_force(&report, &design, &saddle);
    check_design_is_made(&report, &design, "waterbomb-saddle");
    check_conditions_held(&report, "waterbomb-saddle");
}

#[test]
fn a_target_out_of_reach_ends_with_exit_1_the_best_design_and_what_blocked_it() {
    // A Yoshimura asked for negative curvature: its vault bends one way only.
    let yoshimura = made("yoshimura.fold", &["generate", "yoshimura"]);
    let saddle = made(
        "steep-saddle.obj",
        &["surface", "saddle", "--depth", "60", "--span", "300"],
    );
    // At 150 steps it still comes nearer (more steps are what it needs, and it says so);
    // by 400 it no longer does, and the conditions are blamed.
    let (code, report, _, err) = fit(&yoshimura, &saddle, "unreachable", &["--steps", "150"]);
    assert_eq!(code, 1, "{err}");
    assert!(
        report.still_improving && report.blocked_by.is_none(),
        "{err}"
    );
    assert!(
        err.contains("raise --steps") && !err.contains("blocked by"),
        "{err}"
    );
    let (code, report, design, err) = fit(&yoshimura, &saddle, "unreachable", &["--steps", "400"]);
    assert_eq!(code, 1, "{err}");
    assert!(!report.distance.met);
    assert!(!report.still_improving, "{err}");
    assert!(report.steps <= 400);
    assert!(["stalled", "step limit", "blocked"].contains(&report.stopped.as_str()));
    let blocked = report
        .blocked_by
        .as_ref()
        .expect("the report names a blocker");
    assert!(crease::constraints::Family::from_name(&blocked.condition).is_some());
    assert!(
        err.contains(&format!("blocked by {}", blocked.condition)),
        "{err}"
    );
    // The best design is written, and it holds every condition to the solver's tolerance.
    assert!(crease::io::read(&design).is_ok());
    for c in &report.conditions {
        assert!(
            c.largest_residual <= 1e-8,
            "{} {}",
            c.name,
            c.largest_residual
        );
    }
    // Best kept: no state it passed through was closer than the one written.
    let best = report
        .history
        .iter()
        .map(|h| h[1])
        .fold(f64::INFINITY, f64::min);
    assert!(report.distance.hausdorff_mm <= best * (1.0 + 1e-3) + 1e-6);
}

#[test]
fn bad_targets_exit_2_with_one_line_naming_the_file_and_write_nothing() {
    let miura = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/miura.fold");
    let write = |name: &str, bytes: &[u8]| {
        let p = scratch(name);
        std::fs::write(&p, bytes).unwrap();
        p
    };
    let quad = write(
        "quad.obj",
        b"v 0 0 0\nv 100 0 0\nv 100 100 0\nv 0 100 0\nf 1 2 3 4\n",
    );
    let empty = write("empty.obj", b"# nothing\n");
    let nan = write("nan.obj", b"v 0 0 0\nv 100 0 nan\nv 0 100 0\nf 1 2 3\n");
    let km = write(
        "km.obj",
        b"v 0 0 0\nv 1000000 0 0\nv 0 1000000 0\nf 1 2 3\n",
    );
    let mut truncated = vec![0u8; 80];
    truncated.extend(1000u32.to_le_bytes());
    truncated.extend([0u8; 120]);
    let stl = write("truncated.stl", &truncated);
    let garbage = write(
        "garbage.stl",
        b"solid x\n facet normal 0 0 1\n outer loop\n vertex 1 2\n",
    );
    let dir = scratch("a-directory.obj");
    std::fs::create_dir_all(&dir).unwrap();
    let text = write("target.txt", b"v 0 0 0\n");
    for (target, cause) in [
        (&quad, "corners"),
        (&empty, "no triangles"),
        (&nan, "not a number"),
        (&km, "extent"),
        (&stl, "1000 triangles"),
        (&garbage, "STL"),
        (&dir, "directory"),
        (&text, "unknown target type"),
    ] {
        let out = scratch("never.fold");
        let (code, _, err) = run_crease(&[
            "fit",
            miura.to_str().unwrap(),
            "--to",
            target.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{}: {err}", target.display());
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(target.to_str().unwrap()), "{err}");
        assert!(err.contains(cause), "{cause}: {err}");
        assert!(!out.exists() && !out.with_file_name("never.fit.json").exists());
    }
    // Absurd options too.
    let cap = made("cap-for-options.obj", &["surface", "cap"]);
    for (flag, value, cause) in [
        ("--steps", "0", "--steps"),
        ("--within=-1", "", "--within"),
        ("--surface", "both", "--surface"),
    ] {
        let out = scratch("never.fold");
        let mut args = vec![
            "fit",
            miura.to_str().unwrap(),
            "--to",
            cap.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            flag,
        ];
        if !value.is_empty() {
            args.push(value);
        }
        let (code, _, err) = run_crease(&args);
        assert_eq!(code, 2, "{flag} {value}: {err}");
        assert!(err.contains(cause), "{err}");
        assert!(!out.exists());
    }
}

#[test]
fn stl_targets_read_as_their_obj_twins_ascii_and_binary() {
    // The same cap written as OBJ and binary STL, and an ASCII STL written here: the fit
    // reads each to the same triangles (STL keeps single precision).
    let cap = [
        "surface",
        "cap",
        "--radius",
        "200",
        "--span",
        "150",
        "--resolution",
        "6",
    ];
    let (obj, stl) = (made("twin.obj", &cap), made("twin.stl", &cap));
    let a = crease::io::read_target(&obj).unwrap();
    let b = crease::io::read_target(&stl).unwrap();
    assert_eq!(a.triangles().len(), b.triangles().len());
    let mut ascii = String::from("solid twin\n");
    for t in a.triangles() {
        ascii += " facet normal 0 0 1\n  outer loop\n";
        for &v in t {
            let p = a.vertices()[v];
            ascii += &format!("   vertex {} {} {}\n", p.x, p.y, p.z);
        }
        ascii += "  endloop\n endfacet\n";
    }
    ascii += "endsolid twin\n";
    let text = scratch("twin-ascii.stl");
    std::fs::write(&text, ascii).unwrap();
    let c = crease::io::read_target(&text).unwrap();
    // Both STL readings are single precision: within 1e-4 mm of the OBJ's coordinates.
    for (s, tolerance) in [(&b, 1e-4), (&c, 1e-4)] {
        assert_eq!(s.triangles().len(), a.triangles().len());
        for (ta, ts) in a.triangles().iter().zip(s.triangles()) {
            for k in 0..3 {
                let d = (a.vertices()[ta[k]] - s.vertices()[ts[k]]).norm();
                assert!(d < tolerance, "{d}");
            }
        }
    }
}

#[test]
fn the_bundled_targets_are_what_crease_surface_writes() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/targets");
    for (name, args) in [
        ("dome.obj", ["cap", "--radius", "230"]),
        ("saddle.obj", ["saddle", "--depth", "40"]),
    ] {
        let out = scratch(name);
        let mut all = vec!["surface"];
        all.extend(args);
        all.extend([
            "--span",
            "240",
            "--resolution",
            "32",
            "-o",
            out.to_str().unwrap(),
        ]);
        let (code, _, err) = run_crease(&all);
        assert_eq!(code, 0, "{err}");
        let same = std::fs::read(&out).unwrap() == std::fs::read(dir.join(name)).unwrap();
        assert!(
            same,
            "patterns/targets/{name} is stale: rebuild it as its script says"
        );
    }
}

/// Issue 29: with `layer-order` among the conditions the fit holds the flat-folded
/// state's contacts as rows. The 15% waterbomb pulled onto the dome loses its order
/// without the condition (faces overlapping by millimetres); with it the fit ends on a
/// design that keeps an order, and still comes closer to the dome than where it was
/// placed (every step used to be undone by the step check alone: it stayed put).
#[test]
fn a_fit_with_layer_order_among_its_conditions_keeps_the_order() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let design = root.join("patterns/waterbomb-folded.fold");
    let dome = root.join("patterns/targets/dome.obj");
    let plain = "developability,flat-foldability,angular-inequality,fold-angle-range,twist-range";
    let layer_order_of = |out: &Path| {
        let (code, stdout, _) = run_crease(&[
            "verify",
            out.to_str().unwrap(),
            "--conditions",
            "layer-order",
            "--json",
        ]);
        let v: serde_json::Value = serde_json::from_str(stdout.lines().next().unwrap()).unwrap();
        (
            code,
            v["families"]["layer-order"]["violations"].as_u64().unwrap(),
        )
    };
    let run = |conditions: &str, name: &str| {
        let out = scratch(name);
        let (_, stdout, err) = run_crease(&[
            "fit",
            design.to_str().unwrap(),
            "--to",
            dome.to_str().unwrap(),
            "--steps",
            "10",
            "--conditions",
            conditions,
            "-o",
            out.to_str().unwrap(),
        ]);
        (out, stdout + &err)
    };
    let (free, _) = run(plain, "order-free.fold");
    assert_eq!(
        layer_order_of(&free),
        (1, 1),
        "the unguarded fit loses the order"
    );
    let (kept, said) = run(&format!("{plain},layer-order"), "order-kept.fold");
    assert_eq!(layer_order_of(&kept), (0, 0), "{said}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(kept.with_extension("fit.json")).unwrap())
            .unwrap();
    let rms = |k: &str| report[k]["rms_mm"].as_f64().unwrap();
    assert!(
        rms("distance") < 0.8 * rms("placed"),
        "RMS {} mm from {} mm placed: {said}",
        rms("distance"),
        rms("placed")
    );
}

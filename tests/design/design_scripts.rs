//! Designs from scripts and the commands that make them: the designs in `patterns/`
//! rebuild from their scripts, verify, and differ from the regular patterns; `fold` gives
//! rigid states; `deform` refuses bad arguments and reaches relative targets; `info`
//! lists vertices.

use crate::common;

use crease::constraints::{ConstraintSet, Family, Reference};
use crease::fab::{verify, Tolerances};
use crease::generate::{generate, Params, PatternKind};
use crease::mesh::{Mesh, Vec3};
use crease::pipeline::Script;
use crease::pipeline::{run_design, DesignJob};
use crease::solver::{Options, Solver};
use nalgebra::Matrix3;
use std::f64::consts::PI;
use std::path::Path;

fn patterns_dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/patterns"))
}

fn run_script(name: &str, keep_stages: bool) -> Mesh {
    let path = patterns_dir().join(format!("{name}.toml"));
    let script = Script::parse(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let mut job = DesignJob::from_script(&script, patterns_dir(), None).unwrap();
    if !keep_stages {
        job.stages.clear();
        job.fit = None;
    }
    run_design(job, &mut |_, _, _| {}).unwrap().mesh
}

/// RMS distance after the best rigid alignment (Kabsch): how far a shape is from another
/// beyond moving it around.
fn aligned_rms(a: &[Vec3], b: &[Vec3]) -> f64 {
    let n = a.len() as f64;
    let (ca, cb) = (a.iter().sum::<Vec3>() / n, b.iter().sum::<Vec3>() / n);
    let mut h = Matrix3::zeros();
    for (p, q) in a.iter().zip(b) {
        h += (p - ca) * (q - cb).transpose();
    }
    let svd = h.svd(true, true);
    let (u, vt) = (svd.u.unwrap(), svd.v_t.unwrap());
    let mut r = vt.transpose() * u.transpose();
    if r.determinant() < 0.0 {
        let mut v = vt.transpose();
        v.column_mut(2).neg_mut();
        r = v * u.transpose();
    }
    (a.iter()
        .zip(b)
        .map(|(p, q)| (r * (p - ca) - (q - cb)).norm_squared())
        .sum::<f64>()
        / n)
        .sqrt()
}

#[test]
fn designs_rebuild_from_their_scripts_verify_and_differ_from_the_regular_pattern() {
    for name in [
        "miura-bent",
        "waterbomb-curved",
        "yoshimura-shell",
        "plane-crumpled",
        "resch-dome",
        "miura-dome",
        "miura-saddle",
        "resch-cap",
        "arc-pulled",
    ] {
        let rebuilt = run_script(name, true);
        let regular = run_script(name, false);
        let committed = crease::io::read(&patterns_dir().join(format!("{name}.fold"))).unwrap();
        for (p, q) in rebuilt.positions().iter().zip(committed.positions()) {
            assert!(
                (p - q).norm() < 1e-6,
                "{name}.fold is stale: rebuild it from {name}.toml"
            );
        }
        let script = Script::parse(
            &std::fs::read_to_string(patterns_dir().join(format!("{name}.toml"))).unwrap(),
        )
        .unwrap();
        let set = script
            .conditions
            .map(|c| ConstraintSet::parse(&c.join(",")).unwrap());
        let report = verify(&committed, set.as_ref(), Tolerances::default());
        assert!(report.pass(), "{name}: {report}");
        // Visibly not the regular pattern: at least 3 mm RMS apart after the best rigid fit.
        let rms = aligned_rms(committed.positions(), regular.positions());
        assert!(
            rms > 3.0,
            "{name} is only {rms:.2} mm RMS from the regular pattern"
        );
        // And its crease pattern is that of the 3D form (unfolded isometrically).
        let flat = committed.crease_pattern().unwrap();
        for e in committed.edges() {
            let [a, b] = e.vertices;
            let l3 = (committed.positions()[a] - committed.positions()[b]).norm();
            let l2 = (flat[a] - flat[b]).norm();
            assert!(
                (l3 - l2).abs() / l3 < 1e-6,
                "{name}: edge {a}–{b} {l3} vs {l2}"
            );
        }
    }
}

#[test]
fn bad_deform_arguments_exit_2_and_write_nothing() {
    let bin = env!("CARGO_BIN_EXE_crease");
    let miura = patterns_dir().join("miura.fold");
    let kiri =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/origamisimulator/honeycombKiri.svg");
    let folder = common::Scratch::new("deform");
    let out = folder.join("deform.fold");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                miura.display().to_string(),
                "--drag".into(),
                "999=0,0,0".into(),
            ],
            "does not exist",
        ),
        (
            vec![
                miura.display().to_string(),
                "--drag".into(),
                "0=0,0,5000".into(),
                "--mode".into(),
                "simulation".into(),
            ],
            "unreachable",
        ),
        (
            vec![
                kiri.display().to_string(),
                "--drag".into(),
                "0=0,0,5".into(),
            ],
            "disk",
        ),
        (
            vec![
                miura.display().to_string(),
                "--drag".into(),
                "0=0,zero,5".into(),
            ],
            "V=X,Y,Z",
        ),
    ];
    for (args, says) in cases {
        let o = std::process::Command::new(bin)
            .arg("deform")
            .args(&args)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!out.exists());
    }
}

#[test]
fn folding_gives_a_rigid_state_with_every_crease_turned_its_own_way() {
    // Waterbomb is flat-foldable; Resch is not (tiles turn by π/2, tuck spokes by π/3).
    for (name, amount, conditions) in [
        (
            "waterbomb-folded",
            0.15,
            "edge-length,fold-angle-range,developability,flat-foldability",
        ),
        (
            "resch-folded",
            0.6,
            "edge-length,fold-angle-range,developability",
        ),
    ] {
        let folded = run_script(name, true);
        let committed = crease::io::read(&patterns_dir().join(format!("{name}.fold"))).unwrap();
        for (p, q) in folded.positions().iter().zip(committed.positions()) {
            assert!((p - q).norm() < 1e-6, "{name}.fold is stale");
        }
        // Rigid panels: every edge keeps its crease-pattern length; creases fold the right
        // way and no further than flat (§2.4).
        let set = ConstraintSet::parse(conditions).unwrap();
        let report = verify(&committed, Some(&set), Tolerances::default());
        assert!(report.pass(), "{name}: {report}");
        let fractions: Vec<f64> = committed
            .edges()
            .iter()
            .filter(|e| e.assignment.is_folded())
            .map(|e| e.fold_angle / e.target)
            .collect();
        let mean = fractions.iter().sum::<f64>() / fractions.len() as f64;
        assert!(
            (mean - amount).abs() < 0.01,
            "{name}: mean fold fraction {mean}"
        );
        assert!(
            fractions.iter().all(|&f| f > 0.0),
            "{name}: a crease turned the wrong way"
        );
        assert!(
            committed
                .edges()
                .iter()
                .all(|e| e.fold_angle.abs() <= PI + 1e-9),
            "{name}: a crease folded through itself"
        );
    }
}

#[test]
fn a_closed_resch_bends_with_its_tucks_closed_and_every_condition_held() {
    // Fully folded, every tile edge sits at its target π/2; bending the tiled surface turns
    // some further, which §2.4's range [0, π] allows (a range capped at the target did not
    // let the first step converge).
    let mut p = Params::defaults(PatternKind::Resch);
    p.nx = 4;
    p.ny = 4;
    p.fold = Some(1.0);
    let m = generate(&p).unwrap();
    let set = ConstraintSet::default_for(&Reference::new(&m));
    assert!(set.families.contains(&Family::Coincidence));
    let top: Vec<usize> = (0..m.vertex_count())
        .filter(|&v| m.positions()[v].z.abs() < 1e-9)
        .collect();
    let centre = m.positions().iter().sum::<Vec3>() / m.vertex_count() as f64;
    let middle = *top
        .iter()
        .min_by(|&&a, &&b| {
            let d = |v: usize| (m.positions()[v] - centre).xy().norm();
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    // Held: the face farthest from the middle (its corner of the sheet).
    let fixed = m
        .faces()
        .iter()
        .max_by(|a, b| {
            let d = |f: &[usize; 3]| (m.positions()[f[0]] - m.positions()[middle]).norm();
            d(a).total_cmp(&d(b))
        })
        .unwrap()
        .to_vec();
    let mut s = Solver::new(m.clone(), set, &fixed, Options::default()).unwrap();
    let target = m.positions()[middle] + Vec3::new(0.0, 0.0, 8.0);
    let steps = 20;
    for k in 0..steps {
        // A smooth bump around the middle, as a drag with falloff moves it.
        let step = (target - s.positions()[middle]) / (steps - k) as f64;
        let dx0: Vec<Vec3> = s
            .positions()
            .iter()
            .map(|x| {
                let r = (x - s.positions()[middle]).norm() / 30.0;
                step * (1.0 - r * r).max(0.0).powi(2)
            })
            .collect();
        s.step(&dx0).unwrap();
        assert!(s.residual() <= 1e-8, "step {k}: residual {}", s.residual());
        let x = s.positions();
        for g in &m.coincident {
            for &v in g {
                assert!(
                    (x[v] - x[g[0]]).norm() < 1e-6,
                    "step {k}: tuck {g:?} opened"
                );
            }
        }
    }
    let miss = (s.positions()[middle] - target).norm();
    assert!(miss < 4.0, "the middle is {miss} mm from its target");
    let report = verify(&s.into_mesh(), None, Tolerances::default());
    assert!(report.pass(), "{report}");
}

/// The studio's promise on the command line: with the default anchor (away from the dragged
/// vertex) a relative drag of the middle of the Miura-ori brings the vertex to its target.
#[test]
fn a_relative_drag_with_the_default_anchor_reaches_its_target() {
    let folder = common::Scratch::new("rel");
    let out = folder.join("rel.fold");
    let miura = patterns_dir().join("miura.fold");
    let (code, _, err) = common::run_crease(&[
        "deform",
        miura.to_str().unwrap(),
        "--drag",
        "40=+0,+0,+15",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let start = crease::io::read(&miura).unwrap().positions()[40];
    let end = crease::io::read(&out).unwrap().positions()[40];
    let target = start + crease::mesh::Vec3::new(0.0, 0.0, 15.0);
    assert!(
        (end - target).norm() < 1.5,
        "vertex 40 ends {:.2} mm from its target",
        (end - target).norm()
    );
    // The report line says the same.
    let line = err
        .lines()
        .find(|l| l.starts_with("vertex 40:"))
        .expect("a distance line");
    let reported: f64 = line
        .split_whitespace()
        .nth(2)
        .and_then(|d| d.parse().ok())
        .unwrap();
    assert!((reported - (end - target).norm()).abs() < 0.01, "{line}");
}

#[test]
fn info_lists_vertex_ids_with_their_positions() {
    let miura = patterns_dir().join("miura.fold");
    let (code, table, _) = common::run_crease(&["info", miura.to_str().unwrap(), "--vertices"]);
    assert_eq!(code, 0);
    let mesh = crease::io::read(&miura).unwrap();
    let rows: Vec<&str> = table
        .lines()
        .skip_while(|l| !l.trim_start().starts_with("vertex"))
        .skip(1)
        .collect();
    assert_eq!(rows.len(), mesh.vertex_count());
    for (v, row) in rows.iter().enumerate() {
        let cols: Vec<&str> = row.split_whitespace().collect();
        assert_eq!(cols[0].parse::<usize>().unwrap(), v);
        let z: f64 = cols[3].parse().unwrap();
        assert!((z - mesh.positions()[v].z).abs() < 1e-3, "{row}");
        let place = *cols.last().unwrap();
        assert_eq!(place == "interior", mesh.is_interior(v), "{row}");
    }
}

#[test]
fn a_fold_amount_means_the_same_in_generate_and_in_fold() {
    // "t" is the mean fraction ρ/target over the creases, whether the closed form gives the
    // state (generate --fold t) or the solver folds the flat sheet (fold --amount t). The
    // Miura-ori has one rigid-folding mode, so both must land on the same state.
    use crease::geometry::fold_angles;
    use crease::solver::{fold_toward, Mode};
    let t = 0.4;
    let mean_fraction = |m: &crease::mesh::Mesh| {
        let rho = fold_angles(m);
        let folded: Vec<f64> = m
            .edges()
            .iter()
            .zip(&rho)
            .filter(|(e, _)| e.target != 0.0)
            .map(|(e, r)| r / e.target)
            .collect();
        (folded.iter().sum::<f64>() / folded.len() as f64, folded)
    };
    let mut p = Params::defaults(PatternKind::Miura);
    p.fold = Some(t);
    let closed = generate(&p).unwrap();
    let (closed_mean, closed_fractions) = mean_fraction(&closed);
    assert!(
        (closed_mean - t).abs() < 1e-9,
        "generate: mean {closed_mean}"
    );
    p.fold = None;
    let flat = generate(&p).unwrap();
    let fixed = Solver::default_fixed(&flat, &[]);
    let mut solver = Solver::new(flat, Mode::folding_set(), &fixed, Options::default()).unwrap();
    let report = fold_toward(&mut solver, t, 4000, &mut |_| {}).unwrap();
    let (solved_mean, solved_fractions) = mean_fraction(&solver.into_mesh());
    assert!((solved_mean - t).abs() < 1e-3, "fold: mean {solved_mean}");
    assert!((report.mean_fraction - t).abs() < 1e-3, "{report:?}");
    for (a, b) in closed_fractions.iter().zip(&solved_fractions) {
        assert!((a - b).abs() < 1e-3, "crease fractions {a} and {b} differ");
    }
}

#[test]
fn a_fold_that_closes_the_sheet_through_itself_is_refused_unless_forced() {
    let bin = env!("CARGO_BIN_EXE_crease");
    let waterbomb = patterns_dir().join("waterbomb.fold");
    let folder = common::Scratch::new("fold-through");
    let out = folder.join("fold-through.fold");
    let fold = |amount: &str, force: bool| {
        let mut cmd = std::process::Command::new(bin);
        cmd.args([
            "fold",
            waterbomb.to_str().unwrap(),
            "--amount",
            amount,
            "-o",
        ])
        .arg(&out);
        if force {
            cmd.arg("--force");
        }
        cmd.output().unwrap()
    };
    // At 30% the waterbomb's rows roll into each other.
    let r = fold("0.3", false);
    assert_eq!(r.status.code(), Some(1));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        err.contains("passes through itself") && err.contains("--force"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
    let r = fold("0.3", true);
    assert_eq!(r.status.code(), Some(0));
    let forced = crease::io::read(&out).unwrap();
    assert!(!crease::fab::self_intersections(&forced).is_empty());
    // At 15% it folds clear, and the state verifies.
    let r = fold("0.15", false);
    assert_eq!(
        r.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let clear = crease::io::read(&out).unwrap();
    assert!(crease::fab::self_intersections(&clear).is_empty());
    assert!(verify(&clear, None, Tolerances::default()).pass());
}

/// Issue 30's acceptance: the scripted drag of a curved crease keeps the crease smooth
/// with the smoothness family on (second differences of its turning at most 0.5° per
/// segment, in the crease pattern and in space), the rulings uncrossed and every
/// condition held; the same drag without the family is measured, and is jagged (the
/// paper's Fig. 12).
#[test]
fn a_curved_crease_dragged_with_smoothness_stays_smooth_and_without_it_goes_jagged() {
    use crease::constraints::{crease_chains, largest_second_differences, MAX_SECOND_DIFFERENCE};
    let path = patterns_dir().join("arc-pulled.toml");
    let script = Script::parse(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let smooth = {
        let job = DesignJob::from_script(&script, patterns_dir(), None).unwrap();
        run_design(job, &mut |_, _, _| {}).unwrap().mesh
    };
    let rough = {
        let mut job = DesignJob::from_script(&script, patterns_dir(), None).unwrap();
        let set = job.conditions.as_mut().unwrap();
        set.families.retain(|&f| f != Family::Smoothness);
        assert_eq!(set.families.len(), 4);
        run_design(job, &mut |_, _, _| {}).unwrap().mesh
    };
    let start = crease::io::read(&patterns_dir().join("arc.fold")).unwrap();
    let chains = crease_chains(&start);
    assert_eq!(chains.len(), 1);
    let (pattern, space) = largest_second_differences(&smooth, &chains, smooth.positions());
    let (rough_pattern, rough_space) =
        largest_second_differences(&rough, &chains, rough.positions());
    eprintln!(
        "largest second difference of turning: with smoothness {:.3}° (pattern), {:.3}° \
         (space); without {:.1}°, {:.1}°",
        pattern.to_degrees(),
        space.to_degrees(),
        rough_pattern.to_degrees(),
        rough_space.to_degrees()
    );
    let bound = MAX_SECOND_DIFFERENCE + 1e-9;
    assert!(pattern <= bound && space <= bound, "{pattern} {space}");
    // Without the family the drag is the paper's jagged one: ten times the bound.
    assert!(rough_pattern.max(rough_space) > 10.0 * MAX_SECOND_DIFFERENCE);
    // Both moved the crease: the smooth design is not the start left where it was.
    let moved = smooth.positions()[80] - start.positions()[80];
    assert!(moved.z > 20.0, "{moved:?}");
    // Every condition of the script holds to 1e-9, smoothness among them.
    let set = ConstraintSet::parse(&script.conditions.clone().unwrap().join(",")).unwrap();
    let report = verify(&smooth, Some(&set), Tolerances::exactly(1e-9));
    assert!(report.pass(), "{report}");
    // No ruling crosses another: unfolded, every face keeps the turning sense it had in
    // the starting crease pattern (crossing rulings fold a face over).
    let flat = crease::geometry::unfold::unfold(&smooth).unwrap();
    let start_flat = start.crease_pattern().unwrap();
    let orient =
        |p: &[crease::mesh::Vec2], f: [usize; 3]| (p[f[1]] - p[f[0]]).perp(&(p[f[2]] - p[f[0]]));
    for &f in smooth.faces() {
        assert!(
            orient(&flat, f) * orient(start_flat, f) > 0.0,
            "face {f:?} folded over"
        );
    }
}

//! Constraint Jacobians against central finite differences, and `crease verify` on
//! bundled patterns, anchor crease patterns and a broken Miura-ori.

use crate::common;

use common::run_crease;
use crease::constraints::{ConstraintSet, Family, Reference};
use crease::generate::{generate, Params, PatternKind};
use crease::mesh::{Mesh, Vec3};

/// The library's seeded stream, drawn in [-1, 1) for a perturbation.
struct Perturbation(crease::random::Rng);
impl Perturbation {
    fn new(seed: u64) -> Perturbation {
        Perturbation(crease::random::Rng::new(seed))
    }
    fn next(&mut self) -> f64 {
        self.0.range(-1.0, 1.0)
    }
}

fn perturbed(kind: PatternKind, fold: Option<f64>, seed: u64) -> (Mesh, Vec<Vec3>) {
    let mut p = Params::defaults(kind);
    p.nx = 4;
    p.ny = 4;
    p.fold = fold;
    let m = generate(&p).unwrap();
    let mut rng = Perturbation::new(seed);
    // Lift out of the plane and jitter, so fold angles and all inequalities are generic.
    let x: Vec<Vec3> = m
        .positions()
        .iter()
        .map(|q| q + Vec3::new(rng.next(), rng.next(), 3.0 * rng.next()) * 0.8)
        .collect();
    (m, x)
}

/// Every family whose rows are smooth at generic points; inequality rows are checked
/// where active (their max(g, 0) has a kink only at g = 0). Returns how many Jacobian
/// entries were compared with a finite difference.
fn check_family(kind: PatternKind, fold: Option<f64>, family: Family) -> usize {
    (1..=3)
        .map(|seed| {
            let (m, x) = perturbed(kind, fold, seed);
            check_jacobian(&m, &x, family, &format!("{kind:?} seed {seed}"))
        })
        .sum()
}

/// Compares `family`'s Jacobian at `x` with central differences; the number of entries
/// compared (none when the family has no rows here).
fn check_jacobian(m: &Mesh, x: &[Vec3], family: Family, what: &str) -> usize {
    let mut reference = Reference::new(m);
    if family == Family::LayerOrder {
        // The contacts of the generated (unjittered) state, held at the jittered one.
        reference.hold_contacts(m);
    }
    let set = ConstraintSet {
        families: vec![family],
    };
    let rows = set.evaluate(m, &reference, x);
    if rows.residuals.is_empty() {
        return 0;
    }
    let jac = rows.jacobian(m.vertex_count()).to_dense();
    let h = 1e-6;
    let mut worst: f64 = 0.0;
    let mut compared = 0;
    let scale = jac.iter().fold(0.0f64, |a, &b| a.max(b.abs())).max(1e-12);
    for v in 0..m.vertex_count() {
        for k in 0..3 {
            let mut xp = x.to_vec();
            let mut xm = x.to_vec();
            xp[v][k] += h;
            xm[v][k] -= h;
            let rp = set.evaluate(m, &reference, &xp).residuals;
            let rm = set.evaluate(m, &reference, &xm).residuals;
            for r in 0..rows.residuals.len() {
                // Skip rows sitting on an inequality's kink.
                if (rp[r] == 0.0) != (rm[r] == 0.0) {
                    continue;
                }
                let fd = (rp[r] - rm[r]) / (2.0 * h);
                worst = worst.max((fd - jac[[r, 3 * v + k]]).abs() / scale);
                compared += 1;
            }
        }
    }
    assert!(
        worst < 1e-6,
        "{what} {family:?}: relative Jacobian error {worst:e}"
    );
    compared
}

#[test]
fn jacobians_match_finite_differences() {
    let cases = [
        (PatternKind::Miura, Some(0.4)),
        // Nearly flat: the perturbation turns some creases the wrong way.
        (PatternKind::Miura, Some(0.05)),
        (PatternKind::Waterbomb, None),
        (PatternKind::Resch, None),
        // Coincidence groups: the tucks' corners, jittered apart.
        (PatternKind::Resch, Some(1.0)),
        (PatternKind::Plane, Some(0.3)),
        // A curved crease: the smoothness rows, jittered well past their bound.
        (PatternKind::Arc, Some(0.5)),
        // Sinusoidal creases: the space turning signed through inflections.
        (PatternKind::Pleat, Some(0.5)),
        // Tubes: the seam's vertices are interior, their fans closing across it.
        (PatternKind::WaterbombTube, None),
        (PatternKind::Kresling, Some(0.5)),
    ];
    let mut compared = vec![0; Family::ALL.len()];
    for (kind, fold) in cases {
        for (i, family) in Family::ALL.into_iter().enumerate() {
            compared[i] += check_family(kind, fold, family);
        }
    }
    // A family with no rows on any case would have passed unchecked.
    for (family, n) in Family::ALL.into_iter().zip(&compared) {
        assert!(*n > 0, "{family:?}: no Jacobian entry was compared");
    }
}

/// One degree-4 vertex, creases at 0°, 40°, 140°, 280° (sectors 40, 100, 140, 80:
/// Kawasaki holds), assigned M, M, M, V: the 40° sector between the first two mountains
/// is smaller than both its neighbours, which eq. (6) forbids, and smaller than the one
/// after the valley, which eq. (7) forbids.
fn bad_vertex() -> Mesh {
    use crease::mesh::{Assignment, Edge, MeshParts, Vec2};
    let mut flat = vec![Vec2::zeros()];
    for deg in [0.0f64, 40.0, 140.0, 280.0] {
        let (s, c) = deg.to_radians().sin_cos();
        flat.push(Vec2::new(10.0 * c, 10.0 * s));
    }
    let faces = vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]];
    let kinds = [
        Assignment::Mountain,
        Assignment::Mountain,
        Assignment::Mountain,
        Assignment::Valley,
    ];
    let edges = (1..=4).map(|i| Edge::new(0, i, kinds[i - 1])).collect();
    Mesh::new(MeshParts {
        positions: None,
        flat: Some(flat),
        faces,
        edges,
    })
    .unwrap()
}

#[test]
fn angular_inequalities_catch_a_bad_assignment_and_have_exact_gradients() {
    let m = bad_vertex();
    let reference = Reference::new(&m);
    let rows = ConstraintSet {
        families: vec![Family::AngularInequality],
    }
    .evaluate(&m, &reference, m.positions());
    let worst = rows.residuals.iter().cloned().fold(0.0, f64::max);
    // Pair (c0, c1): min(80°, 100°) − 40° by eq. (6), 80° − 40° by eq. (7); pair
    // (c1, c2), followed by the valley: 140° − 100° by eq. (8). All 40°.
    assert!(
        (worst - 40f64.to_radians()).abs() < 1e-12,
        "residual {worst}"
    );
    assert_eq!(rows.residuals.iter().filter(|&&r| r > 0.0).count(), 3);
    // Kawasaki alone is satisfied: the inequalities add information.
    let kawasaki = ConstraintSet {
        families: vec![Family::FlatFoldability],
    }
    .evaluate(&m, &reference, m.positions());
    assert!(kawasaki.residuals[0].abs() < 1e-12);
    let mut rng = Perturbation::new(7);
    let x: Vec<Vec3> = m
        .positions()
        .iter()
        .map(|q| q + Vec3::new(rng.next(), rng.next(), rng.next()) * 0.5)
        .collect();
    let compared = check_jacobian(&m, &x, Family::AngularInequality, "bad vertex");
    assert!(
        compared > 0,
        "the bad vertex's inequality rows were compared"
    );
}

#[test]
fn fold_angle_ranges_are_active_under_the_test_perturbation() {
    // Otherwise the finite-difference test would prove nothing for them.
    let (m, x) = perturbed(PatternKind::Miura, Some(0.05), 1);
    let reference = Reference::new(&m);
    for family in [Family::FoldAngleRange, Family::TwistRange] {
        let rows = ConstraintSet {
            families: vec![family],
        }
        .evaluate(&m, &reference, &x);
        assert!(
            rows.residuals.iter().any(|&r| r.abs() > 0.0),
            "{family:?} never active"
        );
    }
}

#[test]
fn evaluation_on_two_cores_gives_the_same_rows_bit_for_bit() {
    // Large enough (4,608 faces) that the conditions are evaluated on every core.
    let mut p = Params::defaults(PatternKind::Miura);
    (p.nx, p.ny, p.fold) = (48, 48, Some(0.3));
    let m = generate(&p).unwrap();
    assert!(m.faces().len() >= 4096);
    let mut rng = Perturbation::new(7);
    let x: Vec<Vec3> = m
        .positions()
        .iter()
        .map(|q| q + Vec3::new(rng.next(), rng.next(), rng.next()) * 0.05)
        .collect();
    let reference = Reference::new(&m);
    let set = ConstraintSet {
        families: Family::ALL.to_vec(),
    };
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            (
                set.evaluate(&m, &reference, &x),
                set.evaluate_active(&m, &reference, &x, false),
            )
        })
    };
    let (one, two) = (on(1), on(2));
    for (a, b) in [(&one.0, &two.0), (&one.1, &two.1)] {
        assert!(a.residuals.iter().any(|&r| r > 0.0) && a.triplets.len() > 10_000);
        assert_eq!(a.labels, b.labels);
        let bits = |r: &[f64]| r.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a.residuals), bits(&b.residuals));
        let entries = |t: &[(usize, usize, f64)]| {
            t.iter()
                .map(|&(r, c, v)| (r, c, v.to_bits()))
                .collect::<Vec<_>>()
        };
        assert_eq!(entries(&a.triplets), entries(&b.triplets));
    }
}

#[test]
fn the_fold_angles_an_evaluation_hands_on_are_those_tracking_computes() {
    // The solver moves the branch reference with the fold angles the accepting
    // evaluation computed instead of computing them again; they must be the same numbers,
    // on the boundary (left alone) as inside.
    let (m, x) = perturbed(PatternKind::Miura, Some(0.05), 3);
    let reference = Reference::new(&m);
    let rows = ConstraintSet::default_for(&reference).evaluate_active(&m, &reference, &x, true);
    let folds = rows
        .fold_angles
        .expect("the default conditions read fold angles");
    let (mut tracked, mut adopted) = (reference.clone(), reference.clone());
    tracked.track_folds(&m, &x);
    adopted.adopt_folds(&folds);
    let bits = |r: &Reference| {
        r.previous_fold
            .iter()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&tracked), bits(&adopted));
    assert_ne!(bits(&tracked), bits(&reference), "nothing moved");
    let boundary = (0..m.edges().len()).find(|&e| folds.get(e).is_none());
    assert!(boundary.is_some(), "a sheet has boundary edges");
}

/// The binary's exit status and everything it printed (stdout, then stderr).
fn crease_all(args: &[&str]) -> (i32, String) {
    let (code, out, err) = run_crease(args);
    (code, out + &err)
}

#[test]
fn verify_passes_bundled_patterns_and_flat_foldable_anchors() {
    let root = env!("CARGO_MANIFEST_DIR");
    let mut files: Vec<String> = PatternKind::ALL
        .iter()
        .map(|k| format!("{root}/patterns/{}.fold", k.name()))
        .collect();
    for a in [
        "miura-ori.svg",
        "waterbomb.svg",
        "birdBase.svg",
        "singlesquaretwist.svg",
        "BoxPleatPyramid.fold",
    ] {
        files.push(format!("{root}/tests/data/origamisimulator/{a}"));
    }
    for f in files {
        let (code, out) = crease_all(&["verify", &f, "--json"]);
        assert_eq!(code, 0, "{f}: {out}");
        let v: serde_json::Value = serde_json::from_str(out.lines().next().unwrap()).unwrap();
        assert_eq!(v["pass"], true);
        if ["/arc.fold", "/concentric.fold", "/pleat.fold"]
            .iter()
            .any(|n| f.ends_with(n))
        {
            // A curved crease never folds flat: Kawasaki is not asked of it; its
            // smoothness is, and holds.
            assert!(v["families"]["flat-foldability"].is_null(), "{f}");
            assert_eq!(v["families"]["smoothness"]["violations"], 0, "{f}");
            assert!(
                v["families"]["smoothness"]["rows"].as_u64().unwrap() > 0,
                "{f}"
            );
        } else if !f.contains("plane") && !f.contains("resch") {
            assert!(
                v["families"]["flat-foldability"]["violations"] == 0,
                "{f} checked for flat-foldability"
            );
        }
    }
}

#[test]
fn a_miura_with_one_vertex_moved_fails_and_names_it() {
    // The bundled folded Miura-ori; one interior vertex of its 3D form moves 0.1 mm.
    let mut m = generate(&Params::defaults(PatternKind::Miura)).unwrap();
    let v = (0..m.vertex_count())
        .filter(|&v| m.is_interior(v))
        .nth(20)
        .unwrap();
    let mut x = m.positions().to_vec();
    x[v].z += 0.1;
    m.set_positions(x);
    let dir = common::Scratch::new("verify");
    let path = dir.join("moved.fold");
    crease::io::write(&m, &path).unwrap();
    let (code, out) = crease_all(&["verify", path.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains(&format!("vertex {v}")),
        "names vertex {v}: {out}"
    );
    assert!(out.contains("FAIL"), "{out}");
}

#[test]
fn verify_rejects_bad_input_with_status_2() {
    let (code, out) = crease_all(&["verify", "/nonexistent.fold"]);
    assert_eq!(code, 2, "{out}");
    let root = env!("CARGO_MANIFEST_DIR");
    let (code, out) = crease_all(&[
        "verify",
        &format!("{root}/patterns/miura.fold"),
        "--conditions",
        "kawasaki",
    ]);
    assert_eq!(code, 2);
    assert!(out.contains("unknown condition"), "{out}");
}

/// The smoothness family (issue 30) on a curved crease: the generator's chords of a
/// circle pass (their turning is constant), the jittered crease fails in the crease
/// pattern and in space, and the family is a curved-crease pattern's default only.
#[test]
fn smoothness_passes_a_circle_fails_a_jittered_crease_and_is_on_for_curved_creases() {
    let (m, x) = perturbed(PatternKind::Arc, Some(0.5), 1);
    let reference = Reference::new(&m);
    assert!(reference.curved_creases);
    assert_eq!(reference.chains.len(), 1, "{:?}", reference.chains);
    // nx = 4 chords: five vertices, three turns, one second difference, two rows.
    assert_eq!(reference.chains[0].vertices.len(), 5);
    let set = ConstraintSet {
        families: vec![Family::Smoothness],
    };
    let at_rest = set.evaluate(&m, &reference, m.positions());
    assert_eq!(at_rest.residuals.len(), 2);
    assert!(
        at_rest.residuals.iter().all(|&r| r == 0.0),
        "{:?}",
        at_rest.residuals
    );
    let jittered = set.evaluate(&m, &reference, &x);
    assert!(
        jittered.residuals.iter().all(|&r| r > 0.0),
        "both rows active: {:?}",
        jittered.residuals
    );
    assert!(check_jacobian(&m, &x, Family::Smoothness, "jittered arc") > 0);
    assert!(ConstraintSet::default_for(&reference)
        .families
        .contains(&Family::Smoothness));
    for kind in [
        PatternKind::Miura,
        PatternKind::Waterbomb,
        PatternKind::Curved,
    ] {
        let m = generate(&Params::defaults(kind)).unwrap();
        let r = Reference::new(&m);
        assert!(
            !ConstraintSet::default_for(&r)
                .families
                .contains(&Family::Smoothness),
            "{kind:?}"
        );
    }
}

/// The layer-order rows hold the flat-folded state's contacts: they are found on the
/// crease pattern, vanish at the folded 3D form of the same pattern (the folded image
/// depends only on the triangles' shapes, which folding keeps), and have exact
/// Jacobians away from it.
#[test]
fn layer_contact_rows_vanish_on_isometric_forms_and_have_exact_jacobians() {
    for (kind, fold) in [(PatternKind::Waterbomb, 0.3), (PatternKind::Miura, 0.5)] {
        let mut p = Params::defaults(kind);
        p.nx = 4;
        p.ny = 4;
        // Folded by the solver (the waterbomb has no closed form).
        let flat = generate(&p).unwrap();
        let (m, _) = crease::pipeline::fold_mesh(flat, fold, &mut |_, _, _| {}).unwrap();
        let mut reference = Reference::new(&m);
        reference.hold_contacts(&m);
        let set = ConstraintSet {
            families: vec![Family::LayerOrder],
        };
        let rows = set.evaluate(&m, &reference, m.positions());
        assert!(
            !reference.contacts.is_empty(),
            "{kind:?} folds flat with no contacts"
        );
        let worst = rows.residuals.iter().fold(0.0f64, |a, r| a.max(r.abs()));
        assert!(
            worst < 1e-9,
            "{kind:?}: contact residual {worst:e} on its own folded form"
        );
        for seed in 1..=2 {
            let (_, x) = perturbed(kind, None, seed);
            let what = format!("{kind:?} seed {seed}");
            assert!(
                check_jacobian(&m, &x, Family::LayerOrder, &what) > 0,
                "{what}"
            );
        }
    }
}

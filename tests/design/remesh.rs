//! Mesh modification (§4): the collapse rules checked against an independent count, a
//! scripted collapse in `patterns/`, and long random drags that never break the mesh.

use crease::constraints::{ConstraintSet, Reference};
use crease::fab::{verify, Tolerances};
use crease::generate::{generate, Params, PatternKind};
use crease::mesh::Mesh;
use crease::solver::{collapse_edge, Options, Refusal, Solver};
use std::collections::{BTreeSet, HashMap};
use std::f64::consts::PI;
use std::path::Path;

/// A Miura-ori half folded. (At the default 0.3 one collapse, edge 70, jumps too far for
/// Newton to restore Kawasaki; the remesher then undoes it, as in the long random drags
/// below.)
fn miura() -> Mesh {
    let mut p = Params::defaults(PatternKind::Miura);
    p.fold = Some(0.5);
    generate(&p).unwrap()
}

/// Target sums, neighbour sets and merged crease counts, from the raw edge list.
fn expected_verdict(m: &Mesh, e: usize) -> Option<bool> {
    let [u, v] = m.edges()[e].vertices;
    let interior = |w: usize| m.is_interior(w);
    if !interior(u) || !interior(v) || (m.edges()[e].target.abs() - PI).abs() > 1e-9 {
        return None; // not a candidate at all
    }
    let mut sum: HashMap<usize, f64> = HashMap::new();
    let mut nbr: HashMap<usize, BTreeSet<usize>> = HashMap::new();
    for ed in m.edges() {
        let [a, b] = ed.vertices;
        *sum.entry(a).or_default() += ed.target;
        *sum.entry(b).or_default() += ed.target;
        nbr.entry(a).or_default().insert(b);
        nbr.entry(b).or_default().insert(a);
    }
    let two_pi = |s: f64| ((s.abs()) - 2.0 * PI).abs() < 1e-9;
    let t = m.edges()[e].target;
    let merged = sum[&u] + sum[&v] - 2.0 * t;
    let mut at_w: HashMap<usize, f64> = HashMap::new();
    for ed in m.edges() {
        for (end, other) in [
            (ed.vertices[0], ed.vertices[1]),
            (ed.vertices[1], ed.vertices[0]),
        ] {
            if (end == u || end == v) && other != u && other != v {
                *at_w.entry(other).or_default() += ed.target;
            }
        }
    }
    let creases = at_w.values().filter(|t| t.abs() > 1e-9).count();
    Some(two_pi(sum[&u]) && two_pi(sum[&v]) && two_pi(merged) && creases >= 4)
}

#[test]
fn collapses_follow_maekawa_and_the_four_crease_rule() {
    let m = miura();
    let (mut allowed, mut maekawa, mut few) = (0, 0, 0);
    for e in 0..m.edges().len() {
        let Some(expect_ok) = expected_verdict(&m, e) else {
            continue;
        };
        match collapse_edge(&m, m.positions(), e, &[]) {
            Ok(change) => {
                assert!(expect_ok, "edge {e} collapsed against the rules");
                allowed += 1;
                // Every interior vertex of the result: target sum ±2π (Maekawa) …
                let c = &change.mesh;
                for v in (0..c.vertex_count()).filter(|&v| c.is_interior(v)) {
                    let s: f64 = c.topology().fans[v]
                        .spokes
                        .iter()
                        .map(|&s| c.edges()[s].target)
                        .sum();
                    assert!(
                        (s.abs() - 2.0 * PI).abs() < 1e-9,
                        "edge {e}: vertex {v} sum {s}"
                    );
                }
                // … and Kawasaki once the solver restores the conditions.
                let set = ConstraintSet::parse("developability,flat-foldability").unwrap();
                let fixed = Solver::default_fixed(c, &[]);
                let mut solver =
                    Solver::new(c.clone(), set.clone(), &fixed, Options::default()).unwrap();
                solver
                    .correct()
                    .unwrap_or_else(|err| panic!("edge {e}: {err}"));
                // Only these two are restored: nothing keeps the panels from swinging
                // through each other, which verify's self-intersection check may report.
                let report = verify(&solver.into_mesh(), Some(&set), Tolerances::default());
                for f in &set.families {
                    let family = report.families.iter().find(|r| r.name == f.name()).unwrap();
                    assert!(family.pass(), "edge {e}: {report}");
                }
            }
            Err(Refusal::Maekawa(_)) => {
                assert!(!expect_ok);
                maekawa += 1;
            }
            Err(Refusal::TooFewCreases(n)) => {
                assert!(!expect_ok && n < 4);
                few += 1;
            }
            Err(Refusal::LinkCondition(_)) => {}
            Err(other) => panic!("edge {e}: unexpected refusal {other}"),
        }
    }
    // In a regular Miura-ori every ±π crease joins vertices the rules allow to merge.
    assert!(
        allowed > 0,
        "allowed {allowed}, Maekawa refusals {maekawa}, too few {few}"
    );
}

#[test]
fn a_collapse_that_would_break_maekawa_is_refused() {
    let mut m = miura();
    // A mountain between two +2π vertices (case 1 of §4) …
    let sum = |m: &Mesh, w: usize| -> f64 {
        m.topology().fans[w]
            .spokes
            .iter()
            .map(|&s| m.edges()[s].target)
            .sum()
    };
    let e = (0..m.edges().len())
        .find(|&e| {
            let [u, v] = m.edges()[e].vertices;
            expected_verdict(&m, e) == Some(true)
                && m.edges()[e].target > 0.0
                && (sum(&m, u) - 2.0 * PI).abs() < 1e-9
                && (sum(&m, v) - 2.0 * PI).abs() < 1e-9
        })
        .unwrap();
    let [u, v] = m.edges()[e].vertices;
    assert!((sum(&m, u) - 2.0 * PI).abs() < 1e-9 && (sum(&m, v) - 2.0 * PI).abs() < 1e-9);
    // … turned into a valley, with one other valley at each end turned into a mountain so
    // both ends still sum to +2π: merging now gives 2π + 2π + 2π = 6π.
    let other_valley = |m: &Mesh, w: usize| {
        m.topology().fans[w]
            .spokes
            .iter()
            .copied()
            .find(|&s| s != e && m.edges()[s].target < 0.0)
            .unwrap()
    };
    let (su, sv) = (other_valley(&m, u), other_valley(&m, v));
    assert_ne!(su, sv);
    for (edge, target) in [(e, -PI), (su, PI), (sv, PI)] {
        let ed = &mut m.edges_mut()[edge];
        ed.target = target;
        ed.assignment = if target > 0.0 {
            crease::mesh::Assignment::Mountain
        } else {
            crease::mesh::Assignment::Valley
        };
    }
    assert!((sum(&m, u) - 2.0 * PI).abs() < 1e-9 && (sum(&m, v) - 2.0 * PI).abs() < 1e-9);
    match collapse_edge(&m, m.positions(), e, &[]) {
        Err(Refusal::Maekawa(s)) => assert!((s - 6.0 * PI).abs() < 1e-9, "{s}"),
        other => panic!("expected a Maekawa refusal, got {other:?}"),
    }
}

#[test]
fn locked_and_protected_topology_is_kept() {
    let mut m = miura();
    let e = (0..m.edges().len())
        .find(|&e| expected_verdict(&m, e) == Some(true))
        .unwrap();
    let [u, _] = m.edges()[e].vertices;
    assert_eq!(
        collapse_edge(&m, m.positions(), e, &[u]).unwrap_err(),
        Refusal::Protected(u)
    );
    m.lock_topology = true;
    assert_eq!(
        collapse_edge(&m, m.positions(), e, &[]).unwrap_err(),
        Refusal::Locked
    );
}

#[test]
fn the_scripted_collapse_has_fewer_vertices_and_verifies() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns");
    let script = crease::pipeline::Script::parse(
        &std::fs::read_to_string(dir.join("miura-collapse.toml")).unwrap(),
    )
    .unwrap();
    let job = crease::pipeline::DesignJob::from_script(&script, &dir, None).unwrap();
    let start = job.mesh.vertex_count();
    let outcome = crease::pipeline::run_design(job, &mut |_, _, _| {}).unwrap();
    let collapses: usize = outcome.drags.iter().map(|d| d.collapses).sum();
    assert!(collapses > 0);
    assert!(outcome.mesh.vertex_count() < start);
    let committed = crease::io::read(&dir.join("miura-collapse.fold")).unwrap();
    assert_eq!(committed.vertex_count(), outcome.mesh.vertex_count());
    for (p, q) in committed.positions().iter().zip(outcome.mesh.positions()) {
        assert!((p - q).norm() < 1e-6, "miura-collapse.fold is stale");
    }
    let report = verify(&committed, None, Tolerances::default());
    assert!(report.pass(), "{report}");
}

#[test]
fn long_random_drags_with_remeshing_never_break_the_mesh() {
    let mut total_changes = 0;
    for seed in 1u64..=3 {
        let m = miura();
        let set = ConstraintSet::default_for(&Reference::new(&m));
        let fixed = Solver::default_fixed(&m, &[]);
        let mut solver = Solver::new(m, set, &fixed, Options::default()).unwrap();
        let mut rng = crease::random::Rng::new(seed);
        let mut rand = || rng.uniform();
        let mut changes = 0;
        // Episodes: pull a random vertex toward a random neighbour, so edges degenerate.
        for _ in 0..25 {
            let n = solver.positions().len();
            let v = ((rand() * n as f64) as usize).min(n - 1);
            if solver.is_fixed(v) {
                continue;
            }
            let spokes = solver.mesh().topology().fans[v].spokes.clone();
            let pick = ((rand() * spokes.len() as f64) as usize).min(spokes.len() - 1);
            let u = solver.mesh().edges()[spokes[pick]].other(v);
            for _ in 0..8 {
                let n = solver.positions().len();
                if v >= n || u >= n {
                    break;
                }
                let mut dx0 = vec![crease::mesh::Vec3::zeros(); n];
                dx0[v] = (solver.positions()[u] - solver.positions()[v]) * 0.3;
                // A failed step is allowed (the drag stops); a broken mesh is not.
                if solver.step(&dx0).is_err() {
                    break;
                }
                let outcome = solver.remesh(&[], 0.35);
                changes += outcome.collapses + outcome.flips;
                let mesh = solver.mesh().clone();
                let rebuilt = Mesh::new(mesh.clone().into_parts());
                assert!(rebuilt.is_ok(), "seed {seed}: {:?}", rebuilt.err());
                let t = mesh.shape();
                assert!(t.is_disk, "seed {seed}: {t:?}");
                if outcome.renumbered.is_some() {
                    break; // indices moved; start a new episode
                }
            }
        }
        total_changes += changes;
    }
    // The drags must actually exercise remeshing for this to mean anything.
    assert!(total_changes > 0, "no collapse or flip happened");
}

#[test]
fn only_unfolded_untwisting_creases_are_flipped() {
    use crease::solver::flip_edge;
    let mut m = miura();
    let fold = (0..m.edges().len())
        .find(|&e| {
            m.edges()[e].assignment.is_folded()
                && m.topology().edge_faces[e].iter().all(Option::is_some)
        })
        .unwrap();
    assert_eq!(
        flip_edge(&m, m.positions(), fold).unwrap_err(),
        Refusal::NotFlippable(fold)
    );
    let flat = (0..m.edges().len())
        .find(|&e| m.edges()[e].assignment == crease::mesh::Assignment::Flat)
        .unwrap();
    m.edges_mut()[flat].alpha = 0.1;
    assert_eq!(
        flip_edge(&m, m.positions(), flat).unwrap_err(),
        Refusal::NotFlippable(flat)
    );
    // With α = 0, the Miura's diagonals are already the better ones: flipping would make
    // worse triangles, so it is refused too.
    m.edges_mut()[flat].alpha = 0.0;
    assert_eq!(
        flip_edge(&m, m.positions(), flat).unwrap_err(),
        Refusal::NotFlippable(flat)
    );
}

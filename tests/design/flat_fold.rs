//! The flat-folded state (x-ray): isometric images of every face, one image per vertex
//! exactly when the pattern folds flat (Kawasaki at ρ = ±π), and a refusal for patterns
//! whose creases aim at partial folds.

use crease::fab::{flat_folded, NotFlatFoldable};
use crease::generate::{generate, Params, PatternKind};
use crease::mesh::{Mesh, Vec2};

fn flat(kind: PatternKind) -> Mesh {
    let mut p = Params::defaults(kind);
    p.fold = None;
    generate(&p).unwrap()
}

fn check_isometric(mesh: &Mesh, triangles: &[[Vec2; 3]]) {
    let cp = mesh.crease_pattern().unwrap();
    for (f, tri) in mesh.faces().iter().zip(triangles) {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            let before = (cp[a] - cp[b]).norm();
            let after = (tri[k] - tri[(k + 1) % 3]).norm();
            assert!((before - after).abs() < 1e-9 * before, "face {f:?}");
        }
    }
}

#[test]
fn flat_foldable_patterns_close_up_with_every_face_isometric() {
    for kind in [
        PatternKind::Miura,
        PatternKind::Waterbomb,
        PatternKind::Yoshimura,
        PatternKind::Plane,
    ] {
        let mesh = flat(kind);
        let state = flat_folded(&mesh, None).unwrap();
        assert!(
            state.mismatch < 1e-9,
            "{}: images of vertex {:?} disagree by {}",
            kind.name(),
            state.worst_vertex,
            state.mismatch
        );
        check_isometric(&mesh, &state.triangles);
        // Across a ±π crease the paper turns over; across a flat line it does not.
        let topo = mesh.topology();
        for (e, edge) in mesh.edges().iter().enumerate() {
            if let [Some(f), Some(g)] = topo.edge_faces[e] {
                let turned = state.motions[f].flips() != state.motions[g].flips();
                let folded = edge.target.abs() > 3.0;
                assert_eq!(turned, folded, "{}: edge {e}", kind.name());
            }
        }
        // The plain sheet has no folds: its flat-folded state is the sheet itself.
        if kind == PatternKind::Plane {
            let cp = mesh.crease_pattern().unwrap();
            for (f, tri) in mesh.faces().iter().zip(&state.triangles) {
                for k in 0..3 {
                    assert!((tri[k] - cp[f[k]]).norm() < 1e-9);
                }
            }
        }
    }
}

#[test]
fn a_pattern_that_breaks_kawasaki_does_not_close_and_the_vertex_is_named() {
    let mesh = flat(PatternKind::Miura);
    let mut cp = mesh.crease_pattern().unwrap().to_vec();
    // Move one interior vertex 1 mm: its sector angles no longer alternate to zero.
    cp[40] += Vec2::new(1.0, 0.3);
    let state = flat_folded(&mesh, Some(&cp)).unwrap();
    assert!(state.mismatch > 0.1, "mismatch {}", state.mismatch);
    let worst = state.worst_vertex.unwrap();
    let neighbours: Vec<usize> = mesh.topology().fans[40]
        .spokes
        .iter()
        .map(|&e| mesh.edges()[e].other(40))
        .collect();
    assert!(
        worst == 40 || neighbours.contains(&worst),
        "worst vertex {worst} is near the moved vertex"
    );
}

#[test]
fn partial_targets_have_no_flat_folded_state() {
    let mesh = flat(PatternKind::Resch);
    match flat_folded(&mesh, None) {
        Err(NotFlatFoldable::PartialTarget { degrees, .. }) => {
            assert!((degrees.abs() - 180.0).abs() > 1.0)
        }
        other => panic!("expected a partial target, got {other:?}"),
    }
}

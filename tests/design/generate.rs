//! The generated starting patterns against invariants computed here from raw coordinates,
//! independently of crease's geometry code: developability (angle sums), Kawasaki and
//! Maekawa in the crease pattern, and isometry between the 3D and flat frames.

use crease::generate::{generate, Params, PatternKind};
use crease::mesh::{edge_key, Assignment, Mesh, Vec3};
use std::collections::HashMap;
use std::f64::consts::PI;

fn angle3(a: [f64; 3], b: [f64; 3]) -> f64 {
    let cross = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let c = (cross[0].powi(2) + cross[1].powi(2) + cross[2].powi(2)).sqrt();
    c.atan2(a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
}

fn sub(p: &Mesh, i: usize, j: usize) -> [f64; 3] {
    let (a, b) = (p.positions()[i], p.positions()[j]);
    [a.x - b.x, a.y - b.y, a.z - b.z]
}

/// Interior vertices: every edge at them has two faces (counted from the face list).
fn interior_vertices(m: &Mesh) -> Vec<usize> {
    let mut count: HashMap<(usize, usize), usize> = HashMap::new();
    for f in m.faces() {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            *count.entry(edge_key(a, b)).or_default() += 1;
        }
    }
    let mut on_boundary = vec![false; m.vertex_count()];
    for (&(a, b), &n) in &count {
        if n == 1 {
            on_boundary[a] = true;
            on_boundary[b] = true;
        }
    }
    (0..m.vertex_count()).filter(|&v| !on_boundary[v]).collect()
}

fn closed_form_kinds() -> Vec<PatternKind> {
    PatternKind::ALL
        .into_iter()
        // Tubes have no flat state: tests/design/tubes.rs checks theirs.
        .filter(|k| k.has_closed_form_3d() && !k.is_tube())
        .collect()
}

#[test]
fn folded_states_are_developable_at_every_interior_vertex() {
    for kind in closed_form_kinds() {
        for fold in [0.0, 0.1, 0.37, 0.5, 0.9, 1.0] {
            let mut p = Params::defaults(kind);
            p.fold = Some(fold);
            let m = generate(&p).unwrap();
            let mut sums = vec![0.0; m.vertex_count()];
            for f in m.faces() {
                for k in 0..3 {
                    let (v, a, b) = (f[k], f[(k + 1) % 3], f[(k + 2) % 3]);
                    sums[v] += angle3(sub(&m, a, v), sub(&m, b, v));
                }
            }
            let interior = interior_vertices(&m);
            assert!(interior.len() > 10, "{kind:?} has interior vertices");
            for v in interior {
                let g = 2.0 * PI - sums[v];
                assert!(
                    g.abs() < 1e-12,
                    "{kind:?} fold {fold}: vertex {v} has Gauss area {g:e}"
                );
            }
        }
    }
}

#[test]
fn folded_states_are_isometric_to_the_crease_pattern() {
    for kind in closed_form_kinds() {
        for fold in [0.2, 0.5, 0.8] {
            let mut p = Params::defaults(kind);
            p.fold = Some(fold);
            let m = generate(&p).unwrap();
            let flat = m.crease_pattern().unwrap();
            let mut worst: f64 = 0.0;
            for e in m.edges() {
                let [a, b] = e.vertices;
                let d3 = sub(&m, a, b);
                let l3 = (d3[0].powi(2) + d3[1].powi(2) + d3[2].powi(2)).sqrt();
                let l2 = ((flat[a].x - flat[b].x).powi(2) + (flat[a].y - flat[b].y).powi(2)).sqrt();
                worst = worst.max((l3 - l2).abs() / l2);
            }
            assert!(
                worst < 1e-12,
                "{kind:?} fold {fold}: relative edge-length error {worst:e}"
            );
            // And it really is folded, not the flat sheet again.
            let (lo, hi) = m.bounding_box();
            assert!(
                hi.z - lo.z > 1.0,
                "{kind:?} fold {fold} is not lifted out of the plane"
            );
        }
    }
}

/// Kawasaki (alternating sector sum π) and Maekawa (|M − V| = 2) over the folded creases,
/// with the creases sorted by angle around each vertex in the crease pattern.
#[test]
fn flat_foldable_patterns_satisfy_kawasaki_and_maekawa() {
    for kind in [
        PatternKind::Miura,
        PatternKind::Waterbomb,
        PatternKind::Yoshimura,
    ] {
        let mut p = Params::defaults(kind);
        p.fold = None;
        let m = generate(&p).unwrap();
        let flat = m.crease_pattern().unwrap();
        let mut creases: Vec<Vec<(f64, Assignment)>> = vec![Vec::new(); m.vertex_count()];
        for e in m.edges() {
            if !matches!(e.assignment, Assignment::Mountain | Assignment::Valley) {
                continue;
            }
            let [a, b] = e.vertices;
            let d = flat[b] - flat[a];
            creases[a].push((d.y.atan2(d.x), e.assignment));
            creases[b].push(((-d.y).atan2(-d.x), e.assignment));
        }
        let interior = interior_vertices(&m);
        assert!(!interior.is_empty());
        for v in interior {
            let mut c = creases[v].clone();
            c.sort_by(|x, y| x.0.total_cmp(&y.0));
            let n = c.len();
            assert!(
                n >= 4 && n.is_multiple_of(2),
                "{kind:?} vertex {v} has {n} creases"
            );
            let mut alternating = 0.0;
            for i in 0..n {
                let mut sector = c[(i + 1) % n].0 - c[i].0;
                if sector <= 0.0 {
                    sector += 2.0 * PI;
                }
                if i % 2 == 0 {
                    alternating += sector;
                }
            }
            assert!(
                (alternating - PI).abs() < 1e-12,
                "{kind:?} vertex {v}: Kawasaki sum {alternating}"
            );
            let mountains = c.iter().filter(|x| x.1 == Assignment::Mountain).count() as i64;
            assert_eq!(
                (2 * mountains - n as i64).abs(),
                2,
                "{kind:?} vertex {v}: Maekawa"
            );
        }
    }
}

#[test]
fn resch_fully_folded_is_isometric_with_tiles_on_top_and_three_corners_per_vertex() {
    let mut p = Params::defaults(PatternKind::Resch);
    p.fold = Some(1.0);
    let m = generate(&p).unwrap();
    assert!(m.lock_topology);
    let (x, flat) = (m.positions(), m.crease_pattern().unwrap());
    let l = p.size;
    for e in m.edges() {
        let [a, b] = e.vertices;
        let (l3, l2) = ((x[a] - x[b]).norm(), (flat[a] - flat[b]).norm());
        assert!((l3 - l2).abs() < 1e-12 * l, "edge {a}-{b}: {l3} vs {l2}");
    }
    // Tiles: the faces lying on the top plane; everything else hangs behind it.
    let top = |v: usize| x[v].z.abs() < 1e-12 * l;
    let tiles: Vec<&[usize; 3]> = m
        .faces()
        .iter()
        .filter(|f| f.iter().all(|&v| top(v)))
        .collect();
    assert!(!tiles.is_empty());
    for f in m.faces() {
        if !f.iter().all(|&v| top(v)) {
            assert!(
                f.iter().all(|&v| x[v].z < 1e-12 * l),
                "face {f:?} pokes through the tiles"
            );
        }
    }
    for f in &tiles {
        for k in 0..3 {
            let side = (x[f[k]] - x[f[(k + 1) % 3]]).norm();
            assert!((side - l).abs() < 1e-12 * l, "tile side {side}");
        }
    }
    // Every folded vertex on top gathers at most three paper corners, one tuck's; inner
    // ones exactly three (§6.4).
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for v in (0..x.len()).filter(|&v| top(v)) {
        match groups
            .iter_mut()
            .find(|g| (x[g[0]] - x[v]).norm() < 1e-9 * l)
        {
            Some(g) => g.push(v),
            None => groups.push(vec![v]),
        }
    }
    for g in &groups {
        assert!(g.len() <= 3, "{g:?}");
        for (i, &a) in g.iter().enumerate() {
            for &b in &g[i + 1..] {
                assert!(((flat[a] - flat[b]).norm() - l).abs() < 1e-9 * l, "{g:?}");
            }
        }
        if g.iter().all(|&v| m.is_interior(v)) {
            assert_eq!(g.len(), 3, "{g:?}");
        }
    }
    // Targets: tile edges turn the surface down by π/2 (mountain), spokes π/3, and the fins'
    // and tucks' halves close flat onto each other (valley π).
    let mut kinds: HashMap<(Assignment, i64), usize> = HashMap::new();
    for e in m.edges().iter().filter(|e| e.assignment.is_folded()) {
        *kinds
            .entry((e.assignment, (e.target.to_degrees()).round() as i64))
            .or_default() += 1;
    }
    let keys: Vec<_> = kinds.keys().copied().collect();
    for k in keys {
        assert!(
            [
                (Assignment::Mountain, 90),
                (Assignment::Mountain, 60),
                (Assignment::Valley, -180)
            ]
            .contains(&k),
            "unexpected crease kind {k:?}"
        );
    }
    assert_eq!(kinds.len(), 3);
}

#[test]
fn bad_parameters_are_refused_with_a_reason() {
    let mut p = Params::defaults(PatternKind::Miura);
    p.angle_deg = 95.0;
    assert!(generate(&p).unwrap_err().to_string().contains("angle"));
    let mut p = Params::defaults(PatternKind::Waterbomb);
    p.fold = Some(0.5);
    assert!(generate(&p).unwrap_err().to_string().contains("solver"));
    // Resch's closed form is the fully folded state only.
    let mut p = Params::defaults(PatternKind::Resch);
    p.fold = Some(0.5);
    assert!(generate(&p).unwrap_err().to_string().contains("--fold 1"));
    let mut p = Params::defaults(PatternKind::Plane);
    p.fold = Some(1.5);
    assert!(generate(&p).is_err());
}

#[test]
fn the_arc_is_the_mirror_construction_to_1e_9() {
    // `generate arc`: inside its crease every vertex lies on one circular cone about the
    // z axis with its apex at the origin, at its flat distance from the apex, generators
    // turned by the step that keeps their flat angle; outside, on that cone reflected
    // through the crease's plane. β is read off
    // one vertex; every other vertex is checked against the closed form with it, to 1e-9
    // mm. Each chord of the crease folds by the same angle, quads stay planar (their
    // diagonals at 0) and the design verifies.
    for fold in [0.2, 0.5, 1.0] {
        let mut p = Params::defaults(PatternKind::Arc);
        p.fold = Some(fold);
        let m = generate(&p).unwrap();
        let flat = m.crease_pattern().unwrap().to_vec();
        let crease = flat.iter().map(|q| q.norm()).fold(0.0, f64::max) - (p.ny / 2) as f64 * p.size;
        let x = m.positions();
        // β from a vertex inside the crease: z = r cos β.
        let inner = (0..x.len())
            .find(|&v| flat[v].norm() < crease - 1.0)
            .unwrap();
        let beta = (x[inner].z / flat[inner].norm()).acos();
        let (s, c) = beta.sin_cos();
        // Neighbouring generators keep their flat angle: cos² β + sin² β cos Δψ = cos Δφ.
        let dphi = PI / 2.0 / p.nx as f64;
        let dpsi = ((dphi.cos() - c * c) / (s * s)).acos();
        for v in 0..x.len() {
            let r = flat[v].norm();
            let phi = flat[v].y.atan2(flat[v].x);
            let psi = phi / dphi * dpsi;
            let z = if r > crease + 1e-9 {
                2.0 * crease - r
            } else {
                r
            } * c;
            let want = [r * s * psi.cos(), r * s * psi.sin(), z];
            let got = [x[v].x, x[v].y, x[v].z];
            let err = (0..3).map(|k| (want[k] - got[k]).abs()).fold(0.0, f64::max);
            assert!(
                err < 1e-9,
                "fold {fold}: vertex {v} is {err:e} mm off the cone"
            );
        }
        let angles = crease::geometry::fold_angles(&m);
        let chords: Vec<f64> = m
            .edges()
            .iter()
            .zip(&angles)
            .filter(|(e, _)| matches!(e.assignment, Assignment::Mountain | Assignment::Valley))
            .map(|(_, &a)| a)
            .collect();
        assert_eq!(chords.len(), p.nx);
        assert!(chords.iter().all(|a| (a - chords[0]).abs() < 1e-9));
        for (e, a) in m.edges().iter().zip(&angles) {
            if e.assignment == Assignment::Flat {
                assert!(a.abs() < 1e-9, "fold {fold}: a flat crease folds {a:e}");
            }
        }
        assert!(
            crease::fab::verify(&m, None, Default::default()).pass(),
            "fold {fold}"
        );
    }
}

#[test]
fn concentric_rings_are_the_mirror_construction_repeated_to_1e_9() {
    // `generate concentric`: every ring between two creases is a cone about the z axis;
    // along a generator the height is cos β times a zigzag in r whose slope flips at each
    // crease, w(r) = r + 2 Σ_k (−1)^k (r − c_k) over the creases c_1 < c_2 < … below r
    // (an independent form of the generator's). Every vertex matches it to 1e-9 mm, every
    // edge keeps its flat length, every chord of one ring folds by the same angle, rings
    // alternate mountain and valley with the same magnitude, and the design verifies
    // (smoothness among its default conditions).
    for fold in [0.3, 0.8] {
        let mut p = Params::defaults(PatternKind::Concentric);
        p.fold = Some(fold);
        let m = generate(&p).unwrap();
        let flat = m.crease_pattern().unwrap().to_vec();
        let x = m.positions();
        let inner = flat.iter().map(|q| q.norm()).fold(f64::INFINITY, f64::min);
        let creases: Vec<f64> = (1..p.ny).map(|j| inner + j as f64 * p.size).collect();
        let w = |r: f64| {
            r + creases
                .iter()
                .enumerate()
                .filter(|(_, &c)| c < r - 1e-9)
                .map(|(k, &c)| 2.0 * if k % 2 == 0 { -1.0 } else { 1.0 } * (r - c))
                .sum::<f64>()
        };
        let first = (0..x.len())
            .find(|&v| flat[v].norm() < inner + 1e-9)
            .unwrap();
        let beta = (x[first].z / w(inner)).acos();
        let (s, c) = beta.sin_cos();
        let dphi = PI / 2.0 / p.nx as f64;
        let dpsi = ((dphi.cos() - c * c) / (s * s)).acos();
        for v in 0..x.len() {
            let r = flat[v].norm();
            let psi = flat[v].y.atan2(flat[v].x) / dphi * dpsi;
            let want = Vec3::new(r * s * psi.cos(), r * s * psi.sin(), w(r) * c);
            let err = (want - x[v]).norm();
            assert!(err < 1e-9, "fold {fold}: vertex {v} is {err:e} mm off");
        }
        for e in m.edges() {
            let [a, b] = e.vertices;
            let (l3, l2) = ((x[a] - x[b]).norm(), (flat[a] - flat[b]).norm());
            assert!(
                (l3 - l2).abs() < 1e-9,
                "fold {fold}: edge {a}-{b} {l3} vs {l2}"
            );
        }
        let angles = crease::geometry::fold_angles(&m);
        for (ring, &radius) in creases.iter().enumerate() {
            let chords: Vec<(f64, Assignment)> = m
                .edges()
                .iter()
                .zip(&angles)
                .filter(|(e, _)| {
                    e.vertices
                        .iter()
                        .all(|&v| (flat[v].norm() - radius).abs() < 1e-9)
                })
                .map(|(e, &a)| (a, e.assignment))
                .collect();
            assert_eq!(chords.len(), p.nx, "ring {ring}");
            let (first_angle, first_kind) = chords[0];
            assert!(chords
                .iter()
                .all(|&(a, k)| (a - first_angle).abs() < 1e-9 && k == first_kind));
            let want = if ring % 2 == 0 { 1.0 } else { -1.0 };
            let inner_ring = angles[m
                .edges()
                .iter()
                .position(|e| {
                    e.vertices
                        .iter()
                        .all(|&v| (flat[v].norm() - creases[0]).abs() < 1e-9)
                })
                .unwrap()];
            assert!(
                (first_angle - want * inner_ring).abs() < 1e-9,
                "fold {fold}: ring {ring} folds {first_angle}, the first {inner_ring}"
            );
        }
        let report = crease::fab::verify(&m, None, Default::default());
        assert!(report.pass(), "fold {fold}: {report}");
        assert!(report
            .families
            .iter()
            .any(|f| f.name == "smoothness" && f.rows > 0));
    }
}

#[test]
fn the_pleat_is_a_ruled_strip_reflected_crease_by_crease_to_1e_9() {
    // `generate pleat`: the creases are v = A sin(k u) + j · pitch in the crease pattern
    // (A a quarter cell, one wave across); folded, every edge keeps its flat length, the
    // strips between rulings stay planar (their diagonals at 0), the paper before the
    // first crease lies on a cylinder along y (y equals the pattern's v), each crease's
    // chords fold alike in sign, neighbouring creases fold oppositely, and the design
    // verifies with its smoothness rows.
    for fold in [0.3, 0.8] {
        let mut p = Params::defaults(PatternKind::Pleat);
        p.fold = Some(fold);
        let m = generate(&p).unwrap();
        let flat = m.crease_pattern().unwrap().to_vec();
        let x = m.positions();
        let (amplitude, k) = (p.size / 4.0, 2.0 * PI / (p.nx as f64 * p.size));
        let crease_of = |q: crease::mesh::Vec2| {
            (1..p.ny)
                .find(|&j| (q.y - (amplitude * (k * q.x).sin() + j as f64 * p.size)).abs() < 1e-9)
        };
        for e in m.edges() {
            let [a, b] = e.vertices;
            let (l3, l2) = ((x[a] - x[b]).norm(), (flat[a] - flat[b]).norm());
            assert!(
                (l3 - l2).abs() < 1e-9,
                "fold {fold}: edge {a}-{b} {l3} vs {l2}"
            );
        }
        for v in 0..x.len() {
            let below_first = flat[v].y < amplitude * (k * flat[v].x).sin() + p.size + 1e-9;
            if below_first {
                assert!(
                    (x[v].y - flat[v].y).abs() < 1e-9,
                    "vertex {v} off the cylinder"
                );
            }
        }
        let angles = crease::geometry::fold_angles(&m);
        let mut sign_of_crease = vec![0.0f64; p.ny];
        for (e, &a) in m.edges().iter().zip(&angles) {
            match e.assignment {
                Assignment::Flat => {
                    assert!(a.abs() < 1e-9, "fold {fold}: a flat crease folds {a:e}")
                }
                Assignment::Mountain | Assignment::Valley => {
                    let [u, w] = e.vertices;
                    let j = crease_of(flat[u]).expect("a chord lies on a crease");
                    assert_eq!(crease_of(flat[w]), Some(j));
                    assert!(a.abs() > 1e-3);
                    if sign_of_crease[j] == 0.0 {
                        sign_of_crease[j] = a.signum();
                    }
                    assert_eq!(a.signum(), sign_of_crease[j], "fold {fold}: crease {j}");
                }
                _ => {}
            }
        }
        for j in 1..p.ny - 1 {
            assert_eq!(
                sign_of_crease[j],
                -sign_of_crease[j + 1],
                "creases {j} and {}",
                j + 1
            );
        }
        let report = crease::fab::verify(&m, None, Default::default());
        assert!(report.pass(), "fold {fold}: {report}");
        assert!(report
            .families
            .iter()
            .any(|f| f.name == "smoothness" && f.rows > 0));
    }
}

#[test]
fn fold_files_name_the_edges_of_each_curved_crease_and_read_back_unchanged() {
    // FOLD has no curved edges: the chords stay edges, and `crease:curves` lists, per
    // curved crease, its edges in order along it. Written from the mesh each time, so a
    // file read and written again is the same bytes (the field is not carried twice).
    for kind in [
        PatternKind::Arc,
        PatternKind::Concentric,
        PatternKind::Miura,
    ] {
        let params = Params::defaults(kind);
        let mesh = generate(&params).unwrap();
        let text = crease::io::fold::to_string(&mesh);
        let json: serde_json::Value = serde_json::from_str(&text).unwrap();
        let listed = json
            .get("crease:curves")
            .map(|c| c.as_array().unwrap().clone());
        // One arc; a circle between every two of the `ny` strips; no curve in a Miura-ori.
        let expected = match kind {
            PatternKind::Arc => 1,
            PatternKind::Concentric => params.ny - 1,
            _ => 0,
        };
        assert_eq!(listed.as_ref().map_or(0, Vec::len), expected, "{kind:?}");
        let ends: Vec<[usize; 2]> = serde_json::from_value(json["edges_vertices"].clone()).unwrap();
        let letters: Vec<String> =
            serde_json::from_value(json["edges_assignment"].clone()).unwrap();
        for curve in listed.into_iter().flatten() {
            let edges: Vec<usize> = serde_json::from_value(curve).unwrap();
            assert!(edges.len() >= 2);
            // One fold type, each edge sharing a vertex with the next.
            assert!(edges.iter().all(|&e| letters[e] == letters[edges[0]]));
            assert!(matches!(letters[edges[0]].as_str(), "M" | "V"));
            for w in edges.windows(2) {
                let (a, b) = (ends[w[0]], ends[w[1]]);
                assert!(
                    a.iter().any(|v| b.contains(v)),
                    "{kind:?}: {a:?} then {b:?}"
                );
            }
        }
        let file = crate::common::scratch_file("generate-curves", &format!("{kind:?}.fold"), &text);
        let again = crease::io::fold::to_string(&crease::io::read(&file).unwrap());
        assert_eq!(again, text, "{kind:?}");
    }
}

//! Tubes (issue 31, paper §7): generated closed, verified like any design, written as the
//! strip they are made from with `crease:seam`, read back closed.

use crate::common::{run_crease, scratch_file};
use crease::generate::{generate, Params, PatternKind};
use crease::mesh::{Mesh, Vec3};
use std::f64::consts::PI;

const TUBES: [PatternKind; 3] = [
    PatternKind::WaterbombTube,
    PatternKind::YoshimuraTube,
    PatternKind::Kresling,
];

fn tube(kind: PatternKind) -> Mesh {
    generate(&Params {
        nx: 8,
        ny: 6,
        ..Params::defaults(kind)
    })
    .unwrap()
}

/// Sum of the 3D sector angles at `v` (computed here from the faces, not by the crate).
fn angle_sum(m: &Mesh, v: usize) -> f64 {
    let x = m.positions();
    m.faces()
        .iter()
        .filter_map(|f| {
            let k = f.iter().position(|&c| c == v)?;
            let (a, b) = (x[f[(k + 1) % 3]] - x[v], x[f[(k + 2) % 3]] - x[v]);
            Some(a.cross(&b).norm().atan2(a.dot(&b)))
        })
        .sum()
}

fn seam_vertices(m: &Mesh) -> Vec<usize> {
    let mut v: Vec<usize> = m.seam.iter().flatten().copied().collect();
    v.sort_unstable();
    v.dedup();
    v
}

#[test]
fn generated_tubes_are_cylinders_that_pass_verification() {
    for kind in TUBES {
        let name = kind.name();
        let path = scratch_file("tubes", &format!("{name}.fold"), "");
        let p = path.to_str().unwrap();
        let (code, _, err) = run_crease(&["generate", name, "--nx", "8", "--ny", "6", "-o", p]);
        assert_eq!(code, 0, "{name}: {err}");
        let (code, info, _) = run_crease(&["info", p]);
        assert_eq!(code, 0);
        assert!(
            info.contains("cylinder") && info.contains("χ = 0"),
            "{name}: {info}"
        );
        let (code, out, err) = run_crease(&["verify", p, "--json"]);
        assert_eq!(code, 0, "{name}: {out}{err}");
        let v: serde_json::Value = serde_json::from_str(out.lines().next().unwrap()).unwrap();
        assert_eq!(v["pass"], true, "{name}");
        assert_eq!(
            v["families"]["self-intersection"]["violations"], 0,
            "{name}"
        );
        assert_eq!(v["families"]["flat-foldability"]["violations"], 0, "{name}");
        // The seam's vertices are interior vertices of the tube read back from the file,
        // and developable there: their sector angles close to 2π.
        let m = crease::io::read(&path).unwrap();
        assert!(m.is_tube(), "{name}");
        let seam = seam_vertices(&m);
        assert_eq!(seam.len(), 7, "{name}: one vertex a ring");
        let mut inner = 0;
        for v in seam {
            if m.is_interior(v) {
                inner += 1;
                let residual = (angle_sum(&m, v) - 2.0 * PI).abs();
                assert!(residual <= 1e-10, "{name}: seam vertex {v}: {residual:e}");
            }
        }
        assert_eq!(inner, 5, "{name}: the seam's vertices between the rims");
    }
}

#[test]
fn a_tube_is_written_as_its_strip_and_read_back_closed() {
    for kind in TUBES {
        let m = tube(kind);
        let text = crease::io::fold::to_string(&m);
        let json: serde_json::Value = serde_json::from_str(&text).unwrap();
        let coords = |v: &serde_json::Value| -> Vec<Vec<f64>> {
            serde_json::from_value(v["vertices_coords"].clone()).unwrap()
        };
        let folded = coords(&json);
        let flat = coords(&json["file_frames"][0]);
        assert_eq!(json["file_frames"][0]["frame_classes"][0], "creasePattern");
        // The strip: the tube's 56 vertices and a second copy of the seam's 7.
        assert_eq!(folded.len(), 63, "{kind:?}");
        let seam = json["crease:seam"].as_array().unwrap();
        assert_eq!(seam.len(), 6);
        // Every seam vertex's two copies lie together in 3D and one translation apart in
        // the strip, the width of the tube's unrolled rings.
        let mut shift: Option<[f64; 2]> = None;
        for entry in seam {
            for k in 0..2 {
                let (a, b) = (
                    entry[0][k].as_u64().unwrap() as usize,
                    entry[1][k].as_u64().unwrap() as usize,
                );
                let gap: f64 = (0..3)
                    .map(|i| (folded[a][i] - folded[b][i]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                assert!(gap <= 1e-9, "{kind:?}: {a}, {b} are {gap} mm apart");
                let t = [flat[b][0] - flat[a][0], flat[b][1] - flat[a][1]];
                let s = *shift.get_or_insert(t);
                assert!(
                    (s[0] - t[0]).abs() < 1e-9 && (s[1] - t[1]).abs() < 1e-9,
                    "{kind:?}: {t:?} against {s:?}"
                );
            }
        }
        let s = shift.unwrap();
        let width = (s[0] * s[0] + s[1] * s[1]).sqrt();
        assert!((width - 8.0 * 20.0).abs() < 1e-9, "{kind:?}: {width}");
        // The strip's edges keep their 3D lengths.
        let edges: Vec<[usize; 2]> =
            serde_json::from_value(json["edges_vertices"].clone()).unwrap();
        for [a, b] in edges {
            let l3: f64 = (0..3)
                .map(|i| (folded[a][i] - folded[b][i]).powi(2))
                .sum::<f64>()
                .sqrt();
            let l2 = ((flat[a][0] - flat[b][0]).powi(2) + (flat[a][1] - flat[b][1]).powi(2)).sqrt();
            assert!((l3 - l2).abs() < 1e-9, "{kind:?}: edge {a}-{b}");
        }
        let back = crease::io::fold::parse(&text).unwrap();
        assert!(back.is_tube());
        assert_eq!(back.faces(), m.faces(), "{kind:?}");
        assert_eq!(back.seam, m.seam, "{kind:?}");
        for (p, q) in back.positions().iter().zip(m.positions()) {
            assert!((p - q).norm() < 1e-12);
        }
        let letters = |m: &Mesh| -> Vec<&str> {
            m.edges()
                .iter()
                .map(|e| e.assignment.fold_letter())
                .collect()
        };
        assert_eq!(letters(&back), letters(&m), "{kind:?}");
    }
}

#[test]
fn tubes_close_in_their_rings_and_kresling_folds_with_its_amount() {
    // Rings of nx equal sides: every ring polygon regular, each side the cell size.
    for kind in TUBES {
        let m = tube(kind);
        let x = m.positions();
        for ring in 0..7 {
            for i in 0..8 {
                let (a, b) = (x[ring * 8 + i], x[ring * 8 + (i + 1) % 8]);
                assert!(((a - b).norm() - 20.0).abs() < 1e-9, "{kind:?}");
                assert!((a.z - b.z).abs() < 1e-12);
            }
        }
    }
    // Developable at every interior vertex, at every Kresling fold amount.
    let mut states: Vec<Mesh> = TUBES.iter().map(|&k| tube(k)).collect();
    for fold in [0.0, 0.3, 0.9] {
        states.push(
            generate(&Params {
                fold: Some(fold),
                ..Params::defaults(PatternKind::Kresling)
            })
            .unwrap(),
        );
    }
    for m in &states {
        for v in (0..m.vertex_count()).filter(|&v| m.is_interior(v)) {
            let g = angle_sum(m, v) - 2.0 * PI;
            assert!(g.abs() < 1e-12, "{}: vertex {v}: {g:e}", m.title);
        }
    }
    // Kresling's rings come closer as its fold amount grows.
    let height = |fold: f64| {
        let m = generate(&Params {
            fold: Some(fold),
            ..Params::defaults(PatternKind::Kresling)
        })
        .unwrap();
        let z: Vec<f64> = m.positions().iter().map(|p: &Vec3| p.z).collect();
        z.iter().cloned().fold(f64::MIN, f64::max) - z.iter().cloned().fold(f64::MAX, f64::min)
    };
    assert!(height(0.2) > height(0.5) && height(0.5) > height(0.8));
    assert!((height(0.5) - 8.0 * 10.0).abs() < 1e-9);
}

#[test]
fn absurd_tube_requests_are_refused_saying_why() {
    let out = scratch_file("tubes", "refused.fold", "");
    let o = out.to_str().unwrap();
    for (args, says) in [
        (vec!["yoshimura-tube", "--fold", "0.3"], "one state"),
        (
            vec!["waterbomb-tube", "--crease-pattern"],
            "no crease pattern",
        ),
        // `--flat`, the flag's old name, is read as --crease-pattern.
        (vec!["waterbomb-tube", "--flat"], "drop --crease-pattern"),
        (vec!["kresling", "--nx", "2"], "at least 3 cells round"),
        (vec!["kresling", "--fold", "0.95"], "at most 0.9"),
    ] {
        let mut full = vec!["generate"];
        full.extend(&args);
        full.extend(["-o", o]);
        let (code, _, err) = run_crease(&full);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
    // A seam that does not join its copies is refused naming the field.
    let m = tube(PatternKind::YoshimuraTube);
    let mut json: serde_json::Value =
        serde_json::from_str(&crease::io::fold::to_string(&m)).unwrap();
    // Join the first seam vertex to the ring's far side instead of its copy.
    json["crease:seam"][0][1][0] = serde_json::json!(4);
    let e = crease::io::fold::parse(&json.to_string())
        .expect_err("a bad seam is refused")
        .to_string();
    assert!(e.contains("crease:seam"), "{e}");
}

/// The end ring's plane normal (best fit through the ring's vertices, by the smallest
/// eigenvector of their scatter), pointing up the tube.
fn ring_normal(m: &Mesh, ring: std::ops::Range<usize>) -> Vec3 {
    let x = m.positions();
    let n = ring.len() as f64;
    let c = ring.clone().map(|v| x[v]).sum::<Vec3>() / n;
    let mut scatter = nalgebra::Matrix3::zeros();
    for v in ring {
        scatter += (x[v] - c) * (x[v] - c).transpose();
    }
    let eig = scatter.symmetric_eigen();
    let k = eig.eigenvalues.imin();
    let normal: Vec3 = eig.eigenvectors.column(k).into();
    if normal.z < 0.0 {
        -normal
    } else {
        normal
    }
}

#[test]
fn the_bent_tube_rebuilds_from_its_script_closed_and_bent_30_degrees() {
    use crease::pipeline::Script;
    use crease::pipeline::{run_design, DesignJob};
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns");
    let text = std::fs::read_to_string(dir.join("waterbomb-tube-bent.toml")).unwrap();
    let script = Script::parse(&text).unwrap();
    let job = DesignJob::from_script(&script, &dir, None).unwrap();
    let bent = run_design(job, &mut |_, _, _| {}).unwrap().mesh;
    let committed = crease::io::read(&dir.join("waterbomb-tube-bent.fold")).unwrap();
    for (p, q) in bent.positions().iter().zip(committed.positions()) {
        assert!((p - q).norm() < 1e-6, "waterbomb-tube-bent.fold is stale");
    }
    // Still the tube it started as, with its seam, and bent: the end rings' planes at
    // least 30° apart.
    let regular = tube_of_defaults();
    assert!(bent.is_tube());
    assert_eq!(bent.seam, regular.seam);
    let turn = ring_normal(&bent, 0..8)
        .angle(&ring_normal(&bent, 64..72))
        .to_degrees();
    assert!(
        (30.0..40.0).contains(&turn),
        "the end rings are {turn}° apart"
    );
    assert!(ring_normal(&regular, 0..8).angle(&ring_normal(&regular, 64..72)) < 1e-9);
    // Every condition of its script holds, seam vertices included.
    let set = script
        .conditions
        .map(|c| crease::constraints::ConstraintSet::parse(&c.join(",")).unwrap());
    let report = crease::fab::verify(&bent, set.as_ref(), crease::fab::Tolerances::default());
    assert!(report.pass(), "{report}");
    for v in seam_vertices(&bent)
        .into_iter()
        .filter(|&v| bent.is_interior(v))
    {
        assert!(
            (angle_sum(&bent, v) - 2.0 * PI).abs() <= 1e-10,
            "seam vertex {v}"
        );
    }
    // Written as its strip, the seam's two sides lie together in 3D.
    let json: serde_json::Value =
        serde_json::from_str(&crease::io::fold::to_string(&bent)).unwrap();
    let x: Vec<Vec<f64>> = serde_json::from_value(json["vertices_coords"].clone()).unwrap();
    let pairs = json["crease:seam"].as_array().unwrap();
    assert_eq!(pairs.len(), 8);
    for pair in pairs {
        for k in 0..2 {
            let (a, b) = (
                pair[0][k].as_u64().unwrap() as usize,
                pair[1][k].as_u64().unwrap() as usize,
            );
            let gap = (0..3)
                .map(|i| (x[a][i] - x[b][i]).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(gap <= 1e-9, "seam copies {a}, {b} are {gap} mm apart");
        }
    }
}

fn tube_of_defaults() -> Mesh {
    generate(&Params::defaults(PatternKind::WaterbombTube)).unwrap()
}

#[test]
fn the_vase_flares_from_its_script_and_its_strip_becomes_a_fan() {
    use crease::pipeline::Script;
    use crease::pipeline::{run_design, DesignJob};
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns");
    let text = std::fs::read_to_string(dir.join("waterbomb-tube-vase.toml")).unwrap();
    let script = Script::parse(&text).unwrap();
    let job = DesignJob::from_script(&script, &dir, None).unwrap();
    let vase = run_design(job, &mut |_, _, _| {}).unwrap().mesh;
    let committed = crease::io::read(&dir.join("waterbomb-tube-vase.fold")).unwrap();
    for (p, q) in vase.positions().iter().zip(committed.positions()) {
        assert!((p - q).norm() < 1e-6, "waterbomb-tube-vase.fold is stale");
    }
    assert!(vase.is_tube());
    let report = crease::fab::verify(&vase, None, crease::fab::Tolerances::default());
    assert!(report.pass(), "{report}");
    // The mouth at least a quarter wider than the foot.
    let radius = |ring: std::ops::Range<usize>| {
        let x = vase.positions();
        let c = ring.clone().map(|v| x[v]).sum::<Vec3>() / ring.len() as f64;
        ring.map(|v| (x[v] - c).xy().norm()).sum::<f64>() / 8.0
    };
    let (foot, mouth) = (radius(0..8), radius(64..72));
    assert!(
        mouth > 1.25 * foot,
        "foot {foot:.2} mm, mouth {mouth:.2} mm"
    );
    // Its strip: the seam's copies no longer one translation apart, but one rotation
    // (a fan), the same for every pair.
    let json: serde_json::Value =
        serde_json::from_str(&crease::io::fold::to_string(&vase)).unwrap();
    let flat: Vec<Vec<f64>> =
        serde_json::from_value(json["file_frames"][0]["vertices_coords"].clone()).unwrap();
    let at = |v: &serde_json::Value| {
        let v = v.as_u64().unwrap() as usize;
        nalgebra::Vector2::new(flat[v][0], flat[v][1])
    };
    let pairs = json["crease:seam"].as_array().unwrap();
    let turn = |pair: &serde_json::Value| {
        let (a, b) = (at(&pair[0][0]), at(&pair[0][1]));
        let (c, d) = (at(&pair[1][0]), at(&pair[1][1]));
        (b - a).perp(&(d - c)).atan2((b - a).dot(&(d - c)))
    };
    let first = turn(&pairs[0]);
    assert!(first.abs() > 0.1, "the strip still closes by a translation");
    for pair in pairs {
        assert!(
            (turn(pair) - first).abs() < 1e-9,
            "one rotation for every pair"
        );
    }
}

/// A square tube of side 20 and height 10 (two rings of four corners, each side split by a
/// flat diagonal), its corner `i` (the edge from ring vertex `i` up) a crease of the
/// given assignment (none: a flat line).
fn square_tube(corners: [Option<crease::mesh::Assignment>; 4]) -> Mesh {
    use crease::mesh::{Assignment, Edge, MeshParts};
    let square = [(0.0, 0.0), (20.0, 0.0), (20.0, 20.0), (0.0, 20.0)];
    let positions: Vec<Vec3> = [0.0, 10.0]
        .iter()
        .flat_map(|&z| square.iter().map(move |&(x, y)| Vec3::new(x, y, z)))
        .collect();
    let mut faces = Vec::new();
    let mut edges = Vec::new();
    for (i, corner) in corners.into_iter().enumerate() {
        let j = (i + 1) % 4;
        faces.push([i, j, j + 4]);
        faces.push([i, j + 4, i + 4]);
        edges.push(Edge::new(i, j + 4, Assignment::Flat));
        edges.push(Edge::new(i, j, Assignment::Boundary));
        edges.push(Edge::new(i + 4, j + 4, Assignment::Boundary));
        edges.push(Edge::new(i, i + 4, corner.unwrap_or(Assignment::Flat)));
    }
    Mesh::new(MeshParts {
        positions: Some(positions),
        flat: None,
        faces,
        edges,
    })
    .unwrap()
}

#[test]
fn a_tube_folds_flat_only_where_its_creases_close_round_it_and_stack() {
    use crease::fab::{flat_folded, layer_order, LayerOrder};
    use crease::mesh::Assignment::{Mountain as M, Valley as V};
    // Two opposite corners folded the same way flatten the tube into two layers: closed
    // round the tube, with an order (either way round: outside out, or turned inside out).
    for side in [M, V] {
        let tube = square_tube([Some(side), None, Some(side), None]);
        assert!(tube.is_tube() && tube.crease_pattern().is_none());
        let folded = flat_folded(&tube, None).unwrap();
        assert!(
            folded.layers_close() && !folded.open_seam,
            "{side:?}: {}",
            folded.mismatch
        );
        // Every face lands on the 40 × 10 rectangle the flattened tube covers (half its
        // 80 mm round).
        let images = folded.vertex_images(tube.faces(), tube.vertex_count());
        let width = |axis: usize| {
            let xs = images.iter().map(|p| p[axis]);
            xs.clone().fold(f64::MIN, f64::max) - xs.fold(f64::MAX, f64::min)
        };
        let mut sides = [width(0), width(1)];
        sides.sort_by(f64::total_cmp);
        assert!(
            (sides[0] - 10.0).abs() < 1e-9 && (sides[1] - 40.0).abs() < 1e-9,
            "{sides:?}"
        );
        assert!(
            matches!(layer_order(&tube), Ok(LayerOrder::Found(_))),
            "{side:?}: {:?}",
            layer_order(&tube)
        );
    }
    // One mountain and one valley: closed round the tube, but each fold puts the other
    // layer on its own side, so no order exists.
    let mixed = square_tube([Some(M), None, Some(V), None]);
    assert!(flat_folded(&mixed, None).unwrap().layers_close());
    assert!(matches!(layer_order(&mixed), Ok(LayerOrder::Conflict(_))));
    // Four corners folded the same way close round the square too (each side lands on
    // the last), but a loop wound twice round cannot stack: the last hinge would have to
    // pass through the first.
    let coiled = square_tube([Some(M); 4]);
    assert!(flat_folded(&coiled, None).unwrap().layers_close());
    assert!(matches!(layer_order(&coiled), Ok(LayerOrder::Conflict(_))));
    // Two neighbouring corners folded: every vertex is on a rim (nothing to fail on its
    // own), but folded flat the tube's two ends land 40 mm apart — no flat state at all.
    let open = square_tube([Some(M), Some(M), None, None]);
    let folded = flat_folded(&open, None).unwrap();
    assert!(folded.open_seam, "{}", folded.mismatch);
    assert!((folded.mismatch - 40.0).abs() < 1e-9, "{}", folded.mismatch);
    let report = crease::fab::verify(&open, None, Default::default());
    let row = report
        .families
        .iter()
        .find(|f| f.name == "layer-order")
        .unwrap();
    assert_eq!(row.violations, 1, "{report}");
    assert!(
        !row.gating,
        "a 3D tube's flat state is reported, not gating: {report}"
    );
    assert!(
        report
            .notes
            .iter()
            .any(|n| n.contains("the tube does not close")),
        "{report}"
    );
}

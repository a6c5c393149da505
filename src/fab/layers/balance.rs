//! The flat-folded state with a drawing's noise spread over the whole pattern instead of
//! compounded along one walk.
//!
//! [`super::super::flat_folded`] carries each face to the folded state by the reflections
//! met on a breadth-first walk from a root face. Where the pattern is drawn exactly, every
//! walk gives the same images. Where it is drawn with noise (vertices a few hundredths of
//! a millimetre off, as patterns drawn in ORIPA-like tools are), each vertex misses
//! Kawasaki's sums by a little, the walk's reflections turn each face by the sum of the
//! misses along its path, and faces far from the root land tenths of a millimetre from
//! where their neighbours across an edge the walk did not cross put them: corners meant
//! to meet are split, and edges meant to lie on one line cross, by more than the drawing's
//! own precision.
//!
//! So the images are balanced by least squares, as a surveyor adjusts a traverse:
//! 1. *Turns.* Each face's linear part `L_f` (a rotation, or a reflection for faces
//!    folded over) is turned by an angle `c_f`. Across an edge between faces `f` and `g`,
//!    the walk's rule predicts `L_g` from `L_f` (the same, or reflected across the
//!    crease's folded line) as `M_e`; the turn `δ_e` that remains, `L_g = R(δ_e) M_e`, is
//!    zero on the walk's own edges and the compounded misses elsewhere. Turning `f` by
//!    `c_f` turns its prediction by `c_f` too (a reflection conjugated by a rotation is
//!    the reflection across the turned line), so the remaining turn is
//!    `δ_e + c_g − c_f`: linear in `c`, and minimised over every edge at once.
//! 2. *Places.* Every vertex gets one folded position `y_v` (the walk gives it one per
//!    face), chosen so that each face's sides are as near as they can be to its
//!    turned crease-pattern sides: `Σ_f Σ_{ab ∈ f} |y_b − y_a − L_f (x_b − x_a)|²`.
//!
//! A pattern drawn exactly has `δ = 0` and its walk's images already fit every side, so
//! it is left where it was (to rounding); the walk's root face keeps its turn and its
//! first corner the walk's place for it (the mean of its faces' images, which drawn
//! exactly are one), so the balanced state sits where the walk put it. A file of
//! several pieces of paper is left as the walk left it: the walk folds only the root's.

use super::super::flat_fold::{FlatFolded, PlaneMotion};
use crate::constraints::mirrored_edges;
use crate::mesh::{Mesh, Vec2};

/// `folded` (the walk's flat-folded state of `mesh`) with its faces' turns and its
/// vertices' places balanced by least squares (see the module's comment). A tube, whose
/// walk runs over its strip and not its own vertices, a file of several pieces, or a
/// pattern whose linear algebra fails, is returned as it was.
///
/// # Performance
/// Three least-squares solves by conjugate gradients (the turns over the faces' adjacency,
/// the places' x and y over the vertices'): O(faces) in memory, and O(faces) a step for
/// at most [`MAX_ITERATIONS`] steps.
pub(super) fn balanced(mesh: &Mesh, folded: FlatFolded) -> FlatFolded {
    let (Some(cp), Ok(reflects)) = (mesh.crease_pattern(), mirrored_edges(mesh)) else {
        return folded;
    };
    // The walk carries only the root's piece of paper; others keep their crease-pattern
    // place, which no balance would make a folded state.
    if mesh.is_tube()
        || mesh.topology().components != 1
        || folded.motions.len() != mesh.faces().len()
    {
        return folded;
    }
    let Some(turns) = balanced_turns(mesh, cp, &reflects, &folded.motions, folded.root) else {
        return folded;
    };
    let linear: Vec<[[f64; 2]; 2]> = folded
        .motions
        .iter()
        .zip(&turns)
        .map(|(m, &c)| turned(c, m.linear))
        .collect();
    let Some(places) = balanced_places(mesh, cp, &folded, &linear) else {
        return folded;
    };
    let triangles = mesh.faces().iter().map(|f| f.map(|v| places[v])).collect();
    FlatFolded {
        triangles,
        ..folded
    }
}

/// Per face, the turn `c_f` (radians) that best closes the walk's predictions across
/// every edge (step 1 of the module's comment), the walk's `root` face held; `None` when
/// the solve fails.
fn balanced_turns(
    mesh: &Mesh,
    cp: &[Vec2],
    reflects: &[bool],
    motions: &[PlaneMotion],
    root: usize,
) -> Option<Vec<f64>> {
    let topo = mesh.topology();
    let mut rows = Vec::new();
    for (e, faces) in topo.edge_faces.iter().enumerate() {
        let [Some(f), Some(g)] = *faces else {
            continue;
        };
        let [a, b] = mesh.edges()[e].vertices;
        let predicted = motions[f].across(cp[a], cp[b], reflects[e]);
        let delta = turn_between(predicted.linear, motions[g].linear);
        rows.push(([(g, 1.0), (f, -1.0)], -delta));
    }
    least_squares(motions.len(), &rows, &[root])
}

/// Per vertex, its one folded position (step 2 of the module's comment), with every
/// face's linear part `linear`; `None` when the solve fails.
fn balanced_places(
    mesh: &Mesh,
    cp: &[Vec2],
    folded: &FlatFolded,
    linear: &[[[f64; 2]; 2]],
) -> Option<Vec<Vec2>> {
    let n = mesh.vertex_count();
    // Where the walk put each vertex, averaged over its faces: the balanced places are
    // found as corrections to these, so a held vertex stays at its walk's place.
    let mut start = vec![(Vec2::zeros(), 0usize); n];
    for (face, tri) in mesh.faces().iter().zip(&folded.triangles) {
        for (&v, q) in face.iter().zip(tri) {
            start[v].0 += q;
            start[v].1 += 1;
        }
    }
    let start: Vec<Vec2> = start
        .into_iter()
        .map(|(sum, k)| sum / k.max(1) as f64)
        .collect();
    let mut sides = Vec::new();
    for (face, l) in mesh.faces().iter().zip(linear) {
        for k in 0..3 {
            let (a, b) = (face[k], face[(k + 1) % 3]);
            let d = cp[b] - cp[a];
            let want = Vec2::new(l[0][0] * d.x + l[0][1] * d.y, l[1][0] * d.x + l[1][1] * d.y);
            sides.push(([(b, 1.0), (a, -1.0)], want - (start[b] - start[a])));
        }
    }
    let held = [mesh.faces()[folded.root][0]];
    let rows = |axis: usize| -> Vec<([(usize, f64); 2], f64)> {
        sides.iter().map(|&(cols, r)| (cols, r[axis])).collect()
    };
    let dx = least_squares(n, &rows(0), &held)?;
    let dy = least_squares(n, &rows(1), &held)?;
    Some(
        start
            .iter()
            .zip(dx.iter().zip(&dy))
            .map(|(p, (&x, &y))| p + Vec2::new(x, y))
            .collect(),
    )
}

/// The `x` minimising `Σ (Σ_k w_k x_{i_k} − r)²` over `rows` (two terms each), with the
/// unknowns in `held` kept at zero (each is one more row `x_i = 0`): the normal equations
/// AᵀA x = Aᵀ r solved by conjugate gradients with Jacobi's preconditioner. AᵀA is a
/// graph Laplacian (plus the held rows), well suited to it; the solver's sparse Cholesky
/// is a stage of its own the verification half does not call on. The iterate at
/// [`MAX_ITERATIONS`] is kept if the tolerance is not met: each lowers the residual's
/// energy, so it is nearer the balance than the walk, which is where it starts.
fn least_squares(
    unknowns: usize,
    rows: &[([(usize, f64); 2], f64)],
    held: &[usize],
) -> Option<Vec<f64>> {
    let normal = |x: &[f64]| {
        let mut out = vec![0.0; unknowns];
        for (terms, _) in rows {
            let ax: f64 = terms.iter().map(|&(i, w)| w * x[i]).sum();
            for &(i, w) in terms {
                out[i] += w * ax;
            }
        }
        for &i in held {
            out[i] += x[i];
        }
        out
    };
    let mut diagonal = vec![0.0; unknowns];
    let mut rhs = vec![0.0; unknowns];
    for (terms, r) in rows {
        for &(i, w) in terms {
            diagonal[i] += w * w;
            rhs[i] += w * r;
        }
    }
    for &i in held {
        diagonal[i] += 1.0;
    }
    // An unknown in no row (a vertex no face holds) stays where it is.
    let inverse: Vec<f64> = diagonal
        .iter()
        .map(|&d| if d > 0.0 { 1.0 / d } else { 0.0 })
        .collect();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let tolerance = TOLERANCE * dot(&rhs, &rhs).sqrt().max(f64::MIN_POSITIVE);
    let mut x = vec![0.0; unknowns];
    let mut residual = rhs;
    let mut z: Vec<f64> = residual.iter().zip(&inverse).map(|(r, m)| r * m).collect();
    let mut direction = z.clone();
    let mut rz = dot(&residual, &z);
    for _ in 0..MAX_ITERATIONS {
        if dot(&residual, &residual).sqrt() <= tolerance {
            break;
        }
        let q = normal(&direction);
        let curvature = dot(&direction, &q);
        if curvature <= 0.0 {
            break;
        }
        let step = rz / curvature;
        for ((xi, ri), (di, qi)) in x
            .iter_mut()
            .zip(&mut residual)
            .zip(direction.iter().zip(&q))
        {
            *xi += step * di;
            *ri -= step * qi;
        }
        for ((zi, ri), m) in z.iter_mut().zip(&residual).zip(&inverse) {
            *zi = ri * m;
        }
        let next = dot(&residual, &z);
        let beta = next / rz;
        rz = next;
        for (di, zi) in direction.iter_mut().zip(&z) {
            *di = zi + beta * *di;
        }
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The residual, relative to the right-hand side, at which the conjugate gradients stop:
/// the balanced places then move by well under a micron from the least-squares ones.
const TOLERANCE: f64 = 1e-10;

/// The most conjugate-gradient iterations one balance takes: a pattern's graph of tens
/// of thousands of vertices converges in a few hundred.
const MAX_ITERATIONS: usize = 2000;

/// The angle (radians, in (−π, π]) of the rotation that takes `from` to `to`, two
/// orthogonal 2 × 2 matrices of one determinant: `to = R(angle) · from`.
fn turn_between(from: [[f64; 2]; 2], to: [[f64; 2]; 2]) -> f64 {
    // to · fromᵀ is the rotation R(angle).
    let cos = to[0][0] * from[0][0] + to[0][1] * from[0][1];
    let sin = to[1][0] * from[0][0] + to[1][1] * from[0][1];
    sin.atan2(cos)
}

/// `R(angle) · linear`.
fn turned(angle: f64, linear: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let (s, c) = angle.sin_cos();
    [
        [
            c * linear[0][0] - s * linear[1][0],
            c * linear[0][1] - s * linear[1][1],
        ],
        [
            s * linear[0][0] + c * linear[1][0],
            s * linear[0][1] + c * linear[1][1],
        ],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fab::flat_folded;

    /// A grid pattern of Daniel Brown's (Flat-Folder's examples) on a 100 mm square,
    /// every vertex moved by up to `noise` mm in x and y, as FOLD.
    fn grid_fold(noise: f64, seed: u64) -> serde_json::Value {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/flat-folder/grids/263_brown_4x4_D2.fold"
        );
        let mut fold: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let mut rng = crate::random::Rng::new(seed);
        for v in fold["vertices_coords"].as_array_mut().unwrap() {
            for c in v.as_array_mut().unwrap() {
                *c = (c.as_f64().unwrap() * 100.0 + rng.range(-noise, noise)).into();
            }
        }
        fold
    }

    /// [`grid_fold`] read.
    fn grid(noise: f64, seed: u64) -> Mesh {
        crate::io::fold::parse(&grid_fold(noise, seed).to_string()).unwrap()
    }

    /// Of the vertices that fold onto one point in the exact pattern's folded state
    /// (`exact`, one image per vertex), the farthest apart of their corners in
    /// `triangles` (the faces of `mesh`): how far corners meant to meet miss. Vertices,
    /// not faces, are matched: noise may triangulate a pattern's faces another way.
    fn worst_miss(exact: &[Vec2], mesh: &Mesh, triangles: &[[Vec2; 3]]) -> f64 {
        let corners: Vec<(Vec2, Vec2)> = mesh
            .faces()
            .iter()
            .zip(triangles)
            .flat_map(|(face, tri)| (0..3).map(move |k| (exact[face[k]], tri[k])))
            .collect();
        let mut worst = 0.0f64;
        for (i, &(p, a)) in corners.iter().enumerate() {
            for &(q, b) in &corners[i + 1..] {
                if (p - q).norm() < 1e-9 {
                    worst = worst.max((a - b).norm());
                }
            }
        }
        worst
    }

    /// Drawn exactly, the walk's images already fit every side: balancing leaves them.
    #[test]
    fn an_exact_pattern_is_left_where_the_walk_put_it() {
        let mesh = grid(0.0, 1);
        let walk = flat_folded(&mesh, None).unwrap();
        let balanced = balanced(&mesh, walk.clone());
        for (a, b) in walk.triangles.iter().zip(&balanced.triangles) {
            for k in 0..3 {
                assert!(
                    (a[k] - b[k]).norm() < 1e-9,
                    "{:?} moved to {:?}",
                    a[k],
                    b[k]
                );
            }
        }
    }

    /// Two pieces of paper in one file: the walk folds only the root's, so the balance
    /// leaves the state as the walk left it, noise or not.
    #[test]
    fn a_file_of_two_pieces_is_left_as_the_walk_left_it() {
        // The grid's file holds only its coordinates, edges, assignments and faces.
        let twice = |mut fold: serde_json::Value| -> Mesh {
            let n = fold["vertices_coords"].as_array().unwrap().len() as u64;
            for key in [
                "vertices_coords",
                "edges_vertices",
                "faces_vertices",
                "edges_assignment",
            ] {
                let copy: Vec<serde_json::Value> = fold[key]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|row| match key {
                        "edges_assignment" => row.clone(),
                        "vertices_coords" => {
                            let p: Vec<f64> = row
                                .as_array()
                                .unwrap()
                                .iter()
                                .map(|c| c.as_f64().unwrap())
                                .collect();
                            vec![p[0] + 300.0, p[1]].into()
                        }
                        _ => row
                            .as_array()
                            .unwrap()
                            .iter()
                            .map(|v| v.as_u64().unwrap() + n)
                            .collect::<Vec<_>>()
                            .into(),
                    })
                    .collect();
                fold[key].as_array_mut().unwrap().extend(copy);
            }
            crate::io::fold::parse(&fold.to_string()).unwrap()
        };
        for mesh in [twice(grid_fold(0.0, 1)), twice(grid_fold(0.01, 6))] {
            assert_eq!(mesh.shape().components, 2);
            let walk = flat_folded(&mesh, None).unwrap();
            assert!(
                balanced(&mesh, walk.clone()).triangles == walk.triangles,
                "the balance moved the faces of a file of two pieces"
            );
        }
    }

    /// Drawn with 0.01 mm of noise on a pattern whose shortest creases are 4-6 mm, the
    /// walk compounds the noise until corners meant to meet miss by tenths of a
    /// millimetre; balanced, they miss by a few times the noise, and every face keeps its
    /// sides' lengths to within that order too.
    #[test]
    fn noise_is_spread_instead_of_compounded() {
        let exact_mesh = grid(0.0, 1);
        let exact = flat_folded(&exact_mesh, None)
            .unwrap()
            .vertex_images(exact_mesh.faces(), exact_mesh.vertex_count());
        let mut worst = (0.0f64, 0.0f64);
        for seed in 2..14 {
            let mesh = grid(0.01, seed);
            let walk = flat_folded(&mesh, None).unwrap();
            let walk_miss = worst_miss(&exact, &mesh, &walk.triangles);
            let balanced = balanced(&mesh, walk);
            let miss = worst_miss(&exact, &mesh, &balanced.triangles);
            // Measured: 0.04-0.10 mm balanced, 0.09-0.36 mm walked.
            assert!(
                miss < 0.12 && miss <= walk_miss + 1e-9,
                "seed {seed}: corners meant to meet miss by {miss} mm balanced, {walk_miss} mm walked"
            );
            worst = (worst.0.max(walk_miss), worst.1.max(miss));
            let cp = mesh.crease_pattern().unwrap();
            for (face, tri) in mesh.faces().iter().zip(&balanced.triangles) {
                for k in 0..3 {
                    let side = (tri[(k + 1) % 3] - tri[k]).norm();
                    let drawn = (cp[face[(k + 1) % 3]] - cp[face[k]]).norm();
                    assert!(
                        (side - drawn).abs() < 0.05,
                        "seed {seed}: a side of {drawn} mm balanced to {side} mm"
                    );
                }
            }
        }
        assert!(
            worst.0 > 3.0 * worst.1,
            "walked {} mm, balanced {} mm",
            worst.0,
            worst.1
        );
    }

    /// Three unknowns tied in a triangle, x₁ − x₀ = x₂ − x₁ = x₂ − x₀ = 1, with x₀ held:
    /// the normal equations 2x₁ − x₂ = 0 and 2x₂ − x₁ = 2 give x₁ = 2/3, x₂ = 4/3.
    #[test]
    fn least_squares_meets_the_closed_form() {
        let rows = [
            ([(1, 1.0), (0, -1.0)], 1.0),
            ([(2, 1.0), (1, -1.0)], 1.0),
            ([(2, 1.0), (0, -1.0)], 1.0),
        ];
        let x = least_squares(3, &rows, &[0]).unwrap();
        for (got, want) in x.iter().zip([0.0, 2.0 / 3.0, 4.0 / 3.0]) {
            assert!((got - want).abs() < 1e-9, "{x:?}");
        }
    }

    /// The turn between two orthogonal matrices of one determinant, against the closed
    /// form, for rotations and for reflections.
    #[test]
    fn turn_between_recovers_the_turn_applied() {
        let rotation = |a: f64| [[a.cos(), -a.sin()], [a.sin(), a.cos()]];
        let mirror = |a: f64| [[a.cos(), a.sin()], [a.sin(), -a.cos()]];
        for from in [rotation(0.3), mirror(1.1)] {
            for angle in [0.0, 0.25, -2.0, 3.0] {
                let got = turn_between(from, turned(angle, from));
                assert!((got - angle).abs() < 1e-12, "{got} for {angle}");
            }
        }
    }
}

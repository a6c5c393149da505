//! The layer order as rows (§2.3): where the crease pattern folded flat has two vertices
//! on one point, or a vertex on another face's edge, those contacts stay contacts.
//!
//! A freeform variation keeps Kawasaki's condition (eq. 5) at every vertex, yet its
//! flat-folded state can lose its layer order: in a regular tessellation folded flat,
//! lines meet edge to edge, and a generic variation makes them cross, a flap's edge
//! entering a pocket it must lie outside. Holding the contacts of the starting state
//! keeps the flat-folded state's arrangement, and so its layer order, while the drag
//! moves in what the other conditions and these rows leave free.
//!
//! The flat-folded image is built from the 3D positions alone: each triangle keeps its
//! 3D shape, laid edge to edge along a breadth-first walk of the faces, mirrored across
//! every crease that folds flat (target an odd multiple of π). Its derivative is carried
//! along the walk (forward mode), so the rows' Jacobian is exact.

use super::context::mirrored_edges;
use super::{Element, Family, Reference, Rows};
use crate::mesh::{Mesh, Vec2, Vec3};
use nalgebra::{Matrix2, Matrix2x3};
use std::collections::VecDeque;

/// Meshes with more faces than this get no contact rows: the images' derivatives grow
/// with the walk's depth (about √faces vertices each), and a large design's layer order
/// is checked on each step instead (`crate::solver::run_stage`).
pub const MAX_CONTACT_FACES: usize = 4096;

/// A contact of the flat-folded state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Contact {
    /// Two vertices fold onto one point: `vertex` stays on `on`.
    Vertices {
        /// The vertex held.
        vertex: usize,
        /// The vertex it stays on (the first of its group).
        on: usize,
    },
    /// A vertex folds onto the line of collinear edges' images and stays on the line
    /// through two other vertices of it.
    OnLine {
        /// The vertex.
        vertex: usize,
        /// The two vertices the line runs through.
        through: [usize; 2],
    },
}

/// How a folded image moves with the 3D positions: `(u, ∂w/∂x_u)` for each vertex u it
/// depends on, by vertex.
type SparseGradient = Vec<(usize, Matrix2x3<f64>)>;

/// Where each vertex lands when the surface is folded flat, and how that moves with the
/// 3D positions.
struct FoldedImages {
    image: Vec<Vec2>,
    grad: Vec<SparseGradient>,
}

/// The quarter turn J: J·(x, y) = (−y, x).
fn quarter_turn() -> Matrix2<f64> {
    Matrix2::new(0.0, -1.0, 1.0, 0.0)
}

/// `Σ coefficient · gradient` over sparse gradients, summed by vertex.
fn combine(
    parts: &[(&Matrix2<f64>, &SparseGradient)],
    local: &[(usize, Matrix2x3<f64>)],
) -> SparseGradient {
    let mut out: SparseGradient = Vec::new();
    for (m, g) in parts {
        out.extend(g.iter().map(|(u, d)| (*u, *m * d)));
    }
    out.extend_from_slice(local);
    out.sort_unstable_by_key(|e| e.0);
    let mut merged: SparseGradient = Vec::with_capacity(out.len());
    for (u, d) in out {
        match merged.last_mut() {
            Some((w, acc)) if *w == u => *acc += d,
            _ => merged.push((u, d)),
        }
    }
    merged
}

/// Places `c` beside the placed edge `a → b` as the 3D triangle (a, b, c) lies:
/// w_c = w_a + s·E + σ·h·J·E with E = w_b − w_a, s and h the foot and height of c over
/// the edge in units of |ab|, σ = +1 for the left side.
fn place(
    x: &[Vec3],
    images: &mut FoldedImages,
    [a, b, c]: [usize; 3],
    sigma: f64,
    with_gradient: bool,
) {
    let (p, q) = (x[b] - x[a], x[c] - x[a]);
    // A collapsed edge (zero length) places its apex on it rather than at NaN.
    let l2 = p.norm_squared().max(f64::MIN_POSITIVE);
    let s = q.dot(&p) / l2;
    let n = p.cross(&q);
    let h = n.norm() / l2;
    let e = images.image[b] - images.image[a];
    let j = quarter_turn();
    images.image[c] = images.image[a] + s * e + sigma * h * (j * e);
    if !with_gradient {
        return;
    }
    // ∂s/∂p, ∂s/∂q and ∂h/∂p, ∂h/∂q (p = x_b − x_a, q = x_c − x_a).
    let ds_dp = q / l2 - 2.0 * s * p / l2;
    let ds_dq = p / l2;
    let unit_n = if n.norm() > 0.0 {
        n / n.norm()
    } else {
        Vec3::zeros()
    };
    let dh_dp = q.cross(&unit_n) / l2 - 2.0 * h * p / l2;
    let dh_dq = unit_n.cross(&p) / l2;
    let je = j * e;
    let outer = |dir: Vec2, g: Vec3| dir * g.transpose();
    let by_p = outer(e, ds_dp) + outer(sigma * je, dh_dp);
    let by_q = outer(e, ds_dq) + outer(sigma * je, dh_dq);
    let along_a = Matrix2::identity() * (1.0 - s) - j * (sigma * h);
    let along_b = Matrix2::identity() * s + j * (sigma * h);
    let grad = combine(
        &[(&along_a, &images.grad[a]), (&along_b, &images.grad[b])],
        &[(a, -(by_p + by_q)), (b, by_p), (c, by_q)],
    );
    images.grad[c] = grad;
}

/// The flat-folded image of `mesh` at 3D positions `x` (disks only; `None` when a crease
/// aims at a partial fold). Every triangle keeps its shape; the walk starts at face 0.
fn folded_images(mesh: &Mesh, x: &[Vec3], with_gradient: bool) -> Option<FoldedImages> {
    let mirrored = mirrored_edges(mesh).ok()?;
    let faces = mesh.faces();
    let topo = mesh.topology();
    let n = mesh.vertex_count();
    let mut images = FoldedImages {
        image: vec![Vec2::zeros(); n],
        grad: vec![Vec::new(); n],
    };
    let mut placed = vec![false; n];
    let mut orientation: Vec<Option<f64>> = vec![None; faces.len()];
    let first = faces.first()?;
    // The root's first edge lies along +x from the origin.
    let [a, b, c] = *first;
    let p = x[b] - x[a];
    images.image[b] = Vec2::new(p.norm(), 0.0);
    if with_gradient {
        let along = Matrix2x3::from_rows(&[(p / p.norm()).transpose(), Vec3::zeros().transpose()]);
        images.grad[b] = combine(&[], &[(a, -along), (b, along)]);
    }
    place(x, &mut images, [a, b, c], 1.0, with_gradient);
    placed[a] = true;
    placed[b] = true;
    placed[c] = true;
    orientation[0] = Some(1.0);
    let mut queue = VecDeque::from([0usize]);
    while let Some(f) = queue.pop_front() {
        let of = orientation[f].expect("queued faces are oriented");
        for &e in &topo.face_edges[f] {
            for g in topo.edge_faces[e].iter().flatten().copied() {
                if orientation[g].is_some() {
                    continue;
                }
                let og = if mirrored[e] { -of } else { of };
                orientation[g] = Some(og);
                queue.push_back(g);
                let [ea, eb] = mesh.edges()[e].vertices;
                let face = faces[g];
                let k = (0..3)
                    .find(|&k| face[k] != ea && face[k] != eb)
                    .expect("a face has a corner off each of its edges");
                let apex = face[k];
                if placed[apex] {
                    continue;
                }
                // (face[k+1], face[k+2]) runs along the face's winding: apex on its left.
                let (from, to) = (face[(k + 1) % 3], face[(k + 2) % 3]);
                place(x, &mut images, [from, to, apex], og, with_gradient);
                placed[apex] = true;
            }
        }
    }
    Some(images)
}

/// The contacts of the flat-folded state of `mesh` at its positions (flat or folded):
/// vertices within `tolerance` mm of one another (each held on the first of its group)
/// and vertices within it of another edge's image (held on the line of the collinear
/// edges through it). Empty on tubes, on meshes past [`MAX_CONTACT_FACES`] and where a
/// crease aims at a partial fold.
pub fn flat_contacts(mesh: &Mesh, positions: &[Vec3], tolerance: f64) -> Vec<Contact> {
    if mesh.is_tube() || mesh.faces().len() > MAX_CONTACT_FACES {
        return Vec::new();
    }
    let Some(images) = folded_images(mesh, positions, false) else {
        return Vec::new();
    };
    let w = &images.image;
    let mean = mesh
        .edges()
        .iter()
        .map(|e| (w[e.vertices[1]] - w[e.vertices[0]]).norm())
        .sum::<f64>()
        / mesh.edges().len().max(1) as f64;
    let grid = ImageGrid::new(w, 2.0 * mean.max(tolerance));
    let (point_of, mut contacts) = shared_points(w, &grid, tolerance);
    contacts.extend(shared_lines(mesh, w, &grid, &point_of, tolerance));
    contacts
}

/// Vertex images bucketed in square cells, for neighbours within a reach.
struct ImageGrid {
    cell: f64,
    buckets: std::collections::HashMap<(i64, i64), Vec<usize>>,
}

impl ImageGrid {
    fn new(images: &[Vec2], cell: f64) -> ImageGrid {
        let mut grid = ImageGrid {
            cell,
            buckets: Default::default(),
        };
        for (v, &p) in images.iter().enumerate() {
            grid.buckets.entry(grid.key(p)).or_default().push(v);
        }
        grid
    }

    fn key(&self, p: Vec2) -> (i64, i64) {
        (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
        )
    }

    /// Vertices in the cells within `reach` of `p` (a superset of those within reach),
    /// in a fixed order.
    fn near(&self, p: Vec2, reach: f64) -> Vec<usize> {
        let (lo, hi) = (
            self.key(p - Vec2::repeat(reach)),
            self.key(p + Vec2::repeat(reach)),
        );
        let mut out = Vec::new();
        for i in lo.0..=hi.0 {
            for j in lo.1..=hi.1 {
                out.extend(self.buckets.get(&(i, j)).into_iter().flatten().copied());
            }
        }
        out
    }
}

/// Vertices folded onto one point: each vertex's point (the first vertex there), and a
/// contact holding every other vertex on it.
fn shared_points(w: &[Vec2], grid: &ImageGrid, tolerance: f64) -> (Vec<usize>, Vec<Contact>) {
    let mut contacts = Vec::new();
    let mut point_of: Vec<usize> = (0..w.len()).collect();
    for v in 0..w.len() {
        let first = grid
            .near(w[v], tolerance)
            .into_iter()
            .filter(|&u| u < v && (w[u] - w[v]).norm() <= tolerance)
            .map(|u| point_of[u])
            .min();
        if let Some(on) = first {
            point_of[v] = on;
            contacts.push(Contact::Vertices { vertex: v, on });
        }
    }
    (point_of, contacts)
}

/// Points folded onto lines: each edge's image with the points on it; collinear edges
/// sharing a point lie on one line, and every point of a line but its two farthest apart
/// is held on the line through those (one row each, where a row per vertex and edge
/// touching would repeat the same condition many times: 2,204 rows for 158 on the 8 × 8
/// waterbomb).
fn shared_lines(
    mesh: &Mesh,
    w: &[Vec2],
    grid: &ImageGrid,
    point_of: &[usize],
    tolerance: f64,
) -> Vec<Contact> {
    let edges = mesh.edges();
    let on_edge = points_on_edges(mesh, w, grid, point_of, tolerance);
    let mut edges_at: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for (e, points) in on_edge.iter().enumerate() {
        for &p in points {
            edges_at.entry(p).or_default().push(e);
        }
    }
    let collinear = |e: usize, f: usize| {
        let [a, b] = edges[e].vertices;
        let d = w[b] - w[a];
        let len = d.norm();
        len > tolerance
            && edges[f]
                .vertices
                .iter()
                .all(|&v| d.perp(&(w[v] - w[a])).abs() / len <= tolerance)
    };
    let mut line_of = crate::mesh::UnionFind::new(edges.len());
    for at in edges_at.values() {
        for (i, &e) in at.iter().enumerate() {
            for &f in &at[i + 1..] {
                if collinear(e, f) {
                    line_of.union(e, f);
                }
            }
        }
    }
    let mut lines: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for (e, points) in on_edge.iter().enumerate() {
        if points.len() >= 2 {
            lines.entry(line_of.find(e)).or_default().extend(points);
        }
    }
    let mut contacts = Vec::new();
    for (first, mut points) in lines {
        points.sort_unstable();
        points.dedup();
        if points.len() < 3 {
            continue;
        }
        // The line through its two points farthest apart along it.
        let [a, b] = edges[first].vertices;
        let along = |p: &&usize| (w[**p] - w[a]).dot(&(w[b] - w[a]));
        let lo = *points
            .iter()
            .min_by(|p, q| along(p).total_cmp(&along(q)))
            .expect("three");
        let hi = *points
            .iter()
            .max_by(|p, q| along(p).total_cmp(&along(q)))
            .expect("three");
        contacts.extend(
            points
                .iter()
                .filter(|&&p| p != lo && p != hi)
                .map(|&vertex| Contact::OnLine {
                    vertex,
                    through: [lo, hi],
                }),
        );
    }
    contacts
}

/// The points on each edge's image (its ends' and every vertex folded within
/// `tolerance` of it), sorted and each once.
fn points_on_edges(
    mesh: &Mesh,
    w: &[Vec2],
    grid: &ImageGrid,
    point_of: &[usize],
    tolerance: f64,
) -> Vec<Vec<usize>> {
    let on_edge = |edge: &crate::mesh::Edge| {
        let [a, b] = edge.vertices;
        let (wa, wb) = (w[a], w[b]);
        let length = (wb - wa).norm();
        let mut points = vec![point_of[a], point_of[b]];
        if point_of[a] != point_of[b] {
            for v in grid.near((wa + wb) / 2.0, length / 2.0 + tolerance) {
                let t = (w[v] - wa).dot(&(wb - wa)) / (length * length);
                let off = (wb - wa).perp(&(w[v] - wa)).abs() / length;
                if (0.0..=1.0).contains(&t) && off <= tolerance {
                    points.push(point_of[v]);
                }
            }
        }
        points.sort_unstable();
        points.dedup();
        points
    };
    mesh.edges().iter().map(on_edge).collect()
}

/// §2.3 as rows: every contact of the starting flat-folded state
/// ([`Reference::contacts`]) stays one at `x`. Two vertices: (w_v − w_on)/ℓ̄ per axis; a
/// vertex on an edge: its signed distance from the edge's line, (E × (w_v − w_a))/(|E| ℓ̄).
pub fn layer_contacts(mesh: &Mesh, reference: &Reference, x: &[Vec3], rows: &mut Rows) {
    if reference.contacts.is_empty() {
        return;
    }
    let Some(images) = folded_images(mesh, x, !rows.values_only) else {
        return;
    };
    let scale = reference.mean_length;
    let w = &images.image;
    let add = |rows: &mut Rows, row: usize, v: usize, coefficient: nalgebra::RowVector2<f64>| {
        if rows.values_only {
            return;
        }
        for (u, d) in &images.grad[v] {
            rows.add_gradient(row, *u, (coefficient * d).transpose(), 1.0 / scale);
        }
    };
    for &contact in &reference.contacts {
        match contact {
            Contact::Vertices { vertex, on } => {
                let d = w[vertex] - w[on];
                for axis in 0..2 {
                    let row =
                        rows.push(Family::LayerOrder, Element::Vertex(vertex), d[axis] / scale);
                    let mut unit = nalgebra::RowVector2::zeros();
                    unit[axis] = 1.0;
                    add(rows, row, vertex, unit);
                    add(rows, row, on, -unit);
                }
            }
            Contact::OnLine {
                vertex,
                through: [a, b],
            } => {
                let e = w[b] - w[a];
                let r = w[vertex] - w[a];
                let len = e.norm();
                let distance = e.perp(&r) / len;
                let row = rows.push(
                    Family::LayerOrder,
                    Element::Vertex(vertex),
                    distance / scale,
                );
                // ∂(E × R)/∂R = (−E_y, E_x); ∂(E × R)/∂E = (R_y, −R_x); ∂|E|/∂E = E/|E|.
                let by_r = nalgebra::RowVector2::new(-e.y, e.x) / len;
                let by_e = nalgebra::RowVector2::new(r.y, -r.x) / len
                    - e.transpose() * (distance / (len * len));
                add(rows, row, vertex, by_r);
                add(rows, row, b, by_e);
                add(rows, row, a, -by_e - by_r);
            }
        }
    }
}

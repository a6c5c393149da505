//! Angle conditions: developability (1), boundary angles (2), convexity (4),
//! flat-foldability (5), angular inequalities (6)–(8) and fold-angle ranges (§2.4).

use super::context::flips;
use super::{Element, Family, Reference, Rows};
use crate::geometry::{
    face_normal, fold_angle_between, fold_angle_gradient, sector_angle, sector_angle_gradient,
    track_branch,
};
use crate::mesh::{Mesh, Vec3};
use rayon::prelude::*;
use std::f64::consts::PI;

/// Every sector angle of the mesh at one set of positions, computed once per evaluation:
/// developability, flat-foldability and the angular inequalities all sum the same
/// corners, and `atan2` dominated evaluation when each recomputed them.
/// (Caching their gradients as well measured slower: the table outgrows the cache.)
pub struct Corners<'a> {
    x: &'a [Vec3],
    angle: Vec<[f64; 3]>,
}

impl<'a> Corners<'a> {
    /// The sector angles of every face at `x`.
    pub fn new(mesh: &Mesh, x: &'a [Vec3], parallel: bool) -> Corners<'a> {
        let angle = per_face(mesh, parallel, |f| [0, 1, 2].map(|k| sector_angle(x, f, k)));
        Corners { x, angle }
    }

    /// The sector angle of `face` at its corner `v`.
    pub fn angle_at(&self, mesh: &Mesh, v: usize, face: usize) -> f64 {
        self.angle[face][corner(mesh, v, face)]
    }

    /// The positions the angles were computed at.
    pub fn positions(&self) -> &'a [Vec3] {
        self.x
    }
}

/// Every face's unit normal at one set of positions, computed once per evaluation: a face
/// borders three edges, and the fold-angle rows used to compute it once for each.
pub struct FaceNormals(Vec<Vec3>);

impl FaceNormals {
    /// The normals of every face at `x`.
    pub fn new(mesh: &Mesh, x: &[Vec3], parallel: bool) -> FaceNormals {
        FaceNormals(per_face(mesh, parallel, |f| face_normal(x, f)))
    }
}

/// The tracked fold angle (§2) of every edge at some positions, NaN on the boundary:
/// computed once per evaluation for the families that read them, and kept by the solver
/// as the next branch reference (`Reference::adopt_folds`) when those positions are
/// accepted.
#[derive(Clone, Debug)]
pub struct FoldAngles(pub Vec<f64>);

impl FoldAngles {
    /// Every edge's fold angle at `x` on the branch `reference` tracks.
    pub fn new(
        mesh: &Mesh,
        reference: &Reference,
        normals: &FaceNormals,
        x: &[Vec3],
        parallel: bool,
    ) -> FoldAngles {
        FoldAngles(per_index(mesh.edges().len(), parallel, |e| {
            tracked_fold_angle_of(mesh, reference, normals, x, e).unwrap_or(f64::NAN)
        }))
    }

    /// Edge `e`'s fold angle; `None` on the boundary.
    pub fn get(&self, e: usize) -> Option<f64> {
        Some(self.0[e]).filter(|rho| !rho.is_nan())
    }
}

/// `value` of every face, in face order, on every core when `parallel`.
fn per_face<T: Send>(
    mesh: &Mesh,
    parallel: bool,
    value: impl Fn([usize; 3]) -> T + Sync,
) -> Vec<T> {
    per_index(mesh.faces().len(), parallel, |f| value(mesh.faces()[f]))
}

/// `value(i)` for i in 0..count, in order, on every core when `parallel`.
fn per_index<T: Send>(count: usize, parallel: bool, value: impl Fn(usize) -> T + Sync) -> Vec<T> {
    if parallel {
        (0..count).into_par_iter().map(&value).collect()
    } else {
        (0..count).map(value).collect()
    }
}

/// Vertex `v`'s corner index in `face`.
fn corner(mesh: &Mesh, v: usize, face: usize) -> usize {
    mesh.faces()[face]
        .iter()
        .position(|&x| x == v)
        .expect("fan face holds its vertex")
}

/// Σ wᵢ θᵢ over the given fan faces of `v`.
fn weighted_sum(
    mesh: &Mesh,
    c: &Corners,
    v: usize,
    faces: impl IntoIterator<Item = (usize, f64)>,
) -> f64 {
    faces
        .into_iter()
        .map(|(face, w)| w * c.angle[face][corner(mesh, v, face)])
        .sum()
}

/// Adds the gradient of Σ wᵢ θᵢ over the given fan faces of `v` to `row`.
fn add_weighted_gradient(
    mesh: &Mesh,
    c: &Corners,
    v: usize,
    faces: impl IntoIterator<Item = (usize, f64)>,
    row: usize,
    rows: &mut Rows,
) {
    if rows.values_only {
        return;
    }
    for (face, w) in faces {
        let f = mesh.faces()[face];
        let g = sector_angle_gradient(c.x, f, corner(mesh, v, face));
        for (j, gj) in g.iter().enumerate() {
            rows.add_gradient(row, f[j], *gj, w);
        }
    }
}

/// The faces of `v`'s fan, each with weight `w`.
fn fan(mesh: &Mesh, v: usize, w: f64) -> impl Iterator<Item = (usize, f64)> + '_ {
    mesh.topology().fans[v].faces.iter().map(move |&f| (f, w))
}

fn angle_sum(mesh: &Mesh, c: &Corners, v: usize) -> f64 {
    weighted_sum(mesh, c, v, fan(mesh, v, 1.0))
}

/// Eq. (1): G = 2π − Σθ at every interior vertex.
pub fn developability(mesh: &Mesh, c: &Corners, rows: &mut Rows) {
    for v in (0..mesh.vertex_count()).filter(|&v| mesh.is_interior(v)) {
        let g = 2.0 * PI - angle_sum(mesh, c, v);
        let row = rows.push(Family::Developability, Element::Vertex(v), g);
        add_weighted_gradient(mesh, c, v, fan(mesh, v, -1.0), row, rows);
    }
}

/// Eq. (2): Σθ − Σθ⁰ at every boundary vertex.
pub fn boundary_angle(mesh: &Mesh, reference: &Reference, c: &Corners, rows: &mut Rows) {
    for v in (0..mesh.vertex_count()).filter(|&v| !mesh.is_interior(v)) {
        let r = angle_sum(mesh, c, v) - reference.angle_sum[v];
        let row = rows.push(Family::BoundaryAngle, Element::Vertex(v), r);
        add_weighted_gradient(mesh, c, v, fan(mesh, v, 1.0), row, rows);
    }
}

/// Eq. (4): max(Σθ − π, 0) at every boundary vertex.
pub fn convexity(mesh: &Mesh, c: &Corners, rows: &mut Rows) {
    for v in (0..mesh.vertex_count()).filter(|&v| !mesh.is_interior(v)) {
        let g = angle_sum(mesh, c, v) - PI;
        if let Some(row) = rows.push_inequality(Family::Convexity, Element::Vertex(v), g) {
            add_weighted_gradient(mesh, c, v, fan(mesh, v, 1.0), row, rows);
        }
    }
}

/// Eq. (5): F = Σ σθ at every vertex where σ is defined.
pub fn flat_foldability(mesh: &Mesh, reference: &Reference, c: &Corners, rows: &mut Rows) {
    for (v, sigma) in reference.sigma.iter().enumerate() {
        let Some(sigma) = sigma else { continue };
        let faces = || {
            mesh.topology().fans[v]
                .faces
                .iter()
                .copied()
                .zip(sigma.iter().copied())
        };
        let value = weighted_sum(mesh, c, v, faces());
        let row = rows.push(Family::FlatFoldability, Element::Vertex(v), value);
        add_weighted_gradient(mesh, c, v, faces(), row, rows);
    }
}

/// Eq. (6)–(8) at every vertex with σ: for consecutive folded creases of equal direction,
/// the sector between them is not smaller than its neighbours as the equations say.
pub fn angular_inequality(mesh: &Mesh, reference: &Reference, c: &Corners, rows: &mut Rows) {
    // Reused for every vertex: this runs at every Newton iteration.
    let mut creases: Vec<usize> = Vec::new();
    let mut sums: Vec<f64> = Vec::new();
    for (v, sigma) in reference.sigma.iter().enumerate() {
        if sigma.is_none() {
            continue;
        }
        let fan = &mesh.topology().fans[v];
        // Folded creases in counter-clockwise order and the fan faces between each and the next.
        creases.clear();
        creases
            .extend((0..fan.spokes.len()).filter(|&i| flips(mesh.edges()[fan.spokes[i]].target)));
        let creases = &creases;
        let n = creases.len();
        if n < 4 {
            continue;
        }
        let m = fan.faces.len();
        let sector_faces = |i: usize| {
            let (from, to) = (creases[i % n], creases[(i + 1) % n]);
            let len = (to + m - from) % m;
            (0..len).map(move |k| fan.faces[(from + k) % m])
        };
        let direction = |i: usize| mesh.edges()[fan.spokes[creases[i % n]]].target.signum();
        // Each sector is one side of up to three conditions: summed once.
        sums.clear();
        sums.extend((0..n).map(|i| weighted_sum(mesh, c, v, sector_faces(i).map(|f| (f, 1.0)))));
        let sector = |i: usize| sums[i];
        for i in 0..n {
            if direction(i) != direction(i + 1) {
                continue;
            }
            let (prev, next) = ((i + n - 1) % n, (i + 1) % n);
            let (s, sp, sn) = (sector(i), sector(prev), sector(next));
            let element =
                |eq: u8| Element::Sector(v, fan.spokes[creases[i]], fan.spokes[creases[next]], eq);
            // Each bound: its equation, its value and the sector it sums.
            let smaller = if sp <= sn { (sp, prev) } else { (sn, next) };
            let conditions = [
                Some((6, smaller)),
                (direction(prev) != direction(i)).then_some((7, (sp, prev))),
                (direction(i + 2) != direction(i + 1)).then_some((8, (sn, next))),
            ];
            for (eq, (bound, bound_sector)) in conditions.into_iter().flatten() {
                let element = element(eq);
                let g = bound - s;
                if let Some(row) = rows.push_inequality(Family::AngularInequality, element, g) {
                    let w = sector_faces(bound_sector)
                        .map(|f| (f, 1.0))
                        .chain(sector_faces(i).map(|f| (f, -1.0)));
                    add_weighted_gradient(mesh, c, v, w, row, rows);
                }
            }
        }
    }
}

/// The fold angle of edge `e` on its tracked branch, with its gradient's vertices.
pub fn tracked_fold_angle(
    mesh: &Mesh,
    reference: &Reference,
    x: &[Vec3],
    e: usize,
) -> Option<(f64, [usize; 4])> {
    let [l, r] = mesh.topology().edge_faces[e];
    let normal = |f: Option<usize>| Some(face_normal(x, mesh.faces()[f?]));
    let rho = tracked_angle(mesh, reference, x, e, normal(l)?, normal(r)?);
    Some((rho, hinge(mesh, e)))
}

/// [`tracked_fold_angle`] with every face normal computed beforehand; `None` on the
/// boundary.
fn tracked_fold_angle_of(
    mesh: &Mesh,
    reference: &Reference,
    normals: &FaceNormals,
    x: &[Vec3],
    e: usize,
) -> Option<f64> {
    let [l, r] = mesh.topology().edge_faces[e];
    let rho = tracked_angle(mesh, reference, x, e, normals.0[l?], normals.0[r?]);
    Some(rho)
}

fn tracked_angle(
    mesh: &Mesh,
    reference: &Reference,
    x: &[Vec3],
    e: usize,
    n1: Vec3,
    n2: Vec3,
) -> f64 {
    let raw = fold_angle_between(x, n1, n2, mesh.edges()[e].vertices);
    track_branch(raw, reference.previous_fold[e])
}

/// The vertices a fold angle depends on: the edge's ends, then the third corner of its
/// left and right faces (an interior edge).
fn hinge(mesh: &Mesh, e: usize) -> [usize; 4] {
    let [a, b] = mesh.edges()[e].vertices;
    let third = |f: Option<usize>| {
        *mesh.faces()[f.expect("interior edge")]
            .iter()
            .find(|&&v| v != a && v != b)
            .expect("triangle")
    };
    let [l, r] = mesh.topology().edge_faces[e];
    [a, b, third(l), third(r)]
}

/// §2.4 (1–2): a mountain keeps 0 ≤ ρ ≤ π, a valley −π ≤ ρ ≤ 0, whatever its target
/// (Resch's tile edges aim at π/2 but a curved design turns some further); merged creases
/// of §4 with targets ±2π may turn up to their target. Unassigned creases and the boundary
/// are free; target-0 creases are [`twist_range`]'s.
pub fn fold_angle_range(mesh: &Mesh, folds: &FoldAngles, x: &[Vec3], rows: &mut Rows) {
    for (e, edge) in mesh.edges().iter().enumerate() {
        if edge.assignment == crate::mesh::Assignment::Unassigned || edge.target == 0.0 {
            continue;
        }
        let Some(rho) = folds.get(e) else {
            continue;
        };
        let t = edge.target;
        let limit = t.abs().max(PI);
        // Signed so that g ≤ 0 inside the range; `dir` is ∂g/∂ρ.
        let (g, dir) = if t > 0.0 {
            if rho < 0.0 {
                (-rho, -1.0)
            } else {
                (rho - limit, 1.0)
            }
        } else if rho > 0.0 {
            (rho, 1.0)
        } else {
            (-rho - limit, -1.0)
        };
        let row = rows.push_inequality(Family::FoldAngleRange, Element::Edge(e), g);
        if let Some(row) = row.filter(|_| !rows.values_only) {
            let [a, b, k, l] = hinge(mesh, e);
            let grad = fold_angle_gradient(x, a, b, k, l);
            for (v, gv) in [a, b, k, l].into_iter().zip(grad) {
                rows.add_gradient(row, v, gv, dir);
            }
        }
    }
}

/// §2.4 (3): a target-0 crease (not unassigned) keeps |ρ| ≤ απ. With α = 0 the facet may
/// not twist at all, which is the equality ρ = 0: a smooth row, so the solver does not
/// chatter on the kink of |ρ| at the flat state where every design starts.
pub fn twist_range(mesh: &Mesh, folds: &FoldAngles, x: &[Vec3], rows: &mut Rows) {
    for (e, edge) in mesh.edges().iter().enumerate() {
        if edge.assignment == crate::mesh::Assignment::Unassigned || edge.target != 0.0 {
            continue;
        }
        let Some(rho) = folds.get(e) else {
            continue;
        };
        let grad = |rows: &mut Rows, row: usize, dir: f64| {
            if rows.values_only {
                return;
            }
            let [a, b, k, l] = hinge(mesh, e);
            let g = fold_angle_gradient(x, a, b, k, l);
            for (v, gv) in [a, b, k, l].into_iter().zip(g) {
                rows.add_gradient(row, v, gv, dir);
            }
        };
        if edge.alpha == 0.0 {
            let row = rows.push_row(Family::TwistRange, Element::Edge(e), rho, false);
            grad(rows, row, 1.0);
        } else {
            let g = rho.abs() - edge.alpha * PI;
            if let Some(row) = rows.push_inequality(Family::TwistRange, Element::Edge(e), g) {
                grad(rows, row, rho.signum());
            }
        }
    }
}

/// Fold tracking lives beside the fold angles it reads, so `context` (which defines
/// [`Reference`]) need not import this file.
impl Reference {
    /// Moves the branch reference to the fold angles at `x` (call after each accepted step,
    /// §2: "the previous rotation angle value of each edge is stored for each frame").
    pub fn track_folds(&mut self, mesh: &Mesh, x: &[Vec3]) {
        let parallel = super::evaluate_in_parallel(mesh);
        let normals = FaceNormals::new(mesh, x, parallel);
        let folds = FoldAngles::new(mesh, self, &normals, x, parallel);
        self.adopt_folds(&folds);
    }

    /// [`Reference::track_folds`] with the fold angles an evaluation at the accepted
    /// positions already computed (the same numbers, not computed twice).
    pub fn adopt_folds(&mut self, folds: &FoldAngles) {
        for (e, previous) in self.previous_fold.iter_mut().enumerate() {
            if let Some(rho) = folds.get(e) {
                *previous = rho;
            }
        }
    }
}

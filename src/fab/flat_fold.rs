//! The flat-folded state: every ±π crease folded completely, so the paper lies in its
//! plane again with layers on top of each other (the "x-ray" of ORIPA and Origami
//! Simulator). Each face is carried there by a rigid motion of the plane: walk the faces
//! breadth first from a root face and, crossing a crease whose target is ±π, reflect across
//! that crease's line in the folded image; crossing any other edge keeps the motion.
//!
//! Around a vertex the walk composes one reflection per ±π crease, so the faces close up
//! only where Kawasaki's alternating sum vanishes (eq. 5 at ρ = ±π);
//! [`FlatFolded::mismatch`] measures the worst gap and names its vertex, which makes a
//! pattern that does not fold flat visible.
//!
//! A tube (paper §7) has no one crease pattern: its strip is folded flat instead, and the
//! seam's two sides must meet again in the folded image, as a crease's two faces do. Going
//! round the tube composes the reflections of every crease the loop crosses; only where
//! that composition is the identity does the tube close up flat, which no vertex's own
//! condition implies.

use crate::constraints::mirrored_edges;
use crate::mesh::{Mesh, UnionFind, Vec2};
use std::collections::{HashMap, VecDeque};
use std::f64::consts::PI;

/// A rigid motion of the plane `p ↦ R p + t`, with `R` a rotation or a reflection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneMotion {
    /// The linear part, rows `[[a, b], [c, d]]`.
    pub linear: [[f64; 2]; 2],
    /// The translation.
    pub shift: Vec2,
}

impl PlaneMotion {
    /// The identity.
    pub const IDENTITY: PlaneMotion = PlaneMotion {
        linear: [[1.0, 0.0], [0.0, 1.0]],
        shift: Vec2::new(0.0, 0.0),
    };

    /// Applies the motion to a point.
    pub fn apply(&self, p: Vec2) -> Vec2 {
        let [[a, b], [c, d]] = self.linear;
        Vec2::new(a * p.x + b * p.y, c * p.x + d * p.y) + self.shift
    }

    /// True when the motion turns the paper over (determinant −1): the face shows its back.
    pub fn flips(&self) -> bool {
        let [[a, b], [c, d]] = self.linear;
        a * d - b * c < 0.0
    }

    /// The reflection across the line through `p` and `q`.
    pub fn reflection(p: Vec2, q: Vec2) -> PlaneMotion {
        let u = (q - p).normalize();
        // R = 2uuᵀ − I; t = p − R p keeps the line fixed.
        let linear = [
            [2.0 * u.x * u.x - 1.0, 2.0 * u.x * u.y],
            [2.0 * u.x * u.y, 2.0 * u.y * u.y - 1.0],
        ];
        let m = PlaneMotion {
            linear,
            shift: Vec2::zeros(),
        };
        PlaneMotion {
            linear,
            shift: p - m.apply(p),
        }
    }

    /// The motion of the face across the crease-pattern edge `a`–`b` from a face this
    /// motion carries: reflected across the edge's folded image when the edge folds flat
    /// (`folds`), the same motion when it does not. The walk's one rule, which the layer
    /// solver's balance also predicts by.
    pub fn across(&self, a: Vec2, b: Vec2, folds: bool) -> PlaneMotion {
        if folds {
            PlaneMotion::reflection(self.apply(a), self.apply(b)).after(self)
        } else {
            *self
        }
    }

    /// `self ∘ other`: first `other`, then `self`.
    pub fn after(&self, other: &PlaneMotion) -> PlaneMotion {
        let [[a, b], [c, d]] = self.linear;
        let [[e, f], [g, h]] = other.linear;
        PlaneMotion {
            linear: [
                [a * e + b * g, a * f + b * h],
                [c * e + d * g, c * f + d * h],
            ],
            shift: self.apply(other.shift),
        }
    }
}

/// The flat-folded state of a crease pattern.
#[derive(Clone, Debug, PartialEq)]
pub struct FlatFolded {
    /// The face the walk started from; it keeps its crease-pattern position.
    pub root: usize,
    /// Per face, the motion from the crease pattern to the folded state.
    pub motions: Vec<PlaneMotion>,
    /// Per face, its three corners in the folded state.
    pub triangles: Vec<[Vec2; 3]>,
    /// The largest gap (mm) the faces around one interior vertex leave when folded flat
    /// (see `worst_closure`): zero, up to rounding, exactly when every vertex folds flat.
    pub mismatch: f64,
    /// The vertex with that gap.
    pub worst_vertex: Option<usize>,
    /// Whether that gap is where a tube's seam fails to meet itself (the faces close up
    /// round every vertex of the strip, not round the tube): a proof that it does not
    /// fold flat, not a drawing's noise.
    pub open_seam: bool,
    /// Per face, whether its front (its normal) faces +z once folded.
    pub front_up: Vec<bool>,
    /// The gap (mm) below which the faces count as closing up ([`closure_tolerance`]).
    pub tolerance: f64,
}

/// The gap (mm) below which the faces of a flat-folded state close up around their
/// vertices, for the crease pattern `flat` from a file rounded to `precision` mm
/// ([`crate::tolerance::closure_mm`] of its diagonal). Verification and the studio's
/// x-ray judge closure by this one figure, so the pane and the verdict agree.
pub fn closure_tolerance(flat: &[Vec2], precision: f64) -> f64 {
    let (lo, hi) = crate::mesh::bounds(flat);
    crate::tolerance::closure_mm((hi - lo).norm(), precision)
}

impl FlatFolded {
    /// Where each vertex of `faces` lands: in the folded image of the last face listed
    /// that holds it (where the layers close up, every face holding it agrees).
    pub fn vertex_images(&self, faces: &[[usize; 3]], vertices: usize) -> Vec<Vec2> {
        let mut images = vec![Vec2::zeros(); vertices];
        for (face, tri) in faces.iter().zip(&self.triangles) {
            for (&v, &q) in face.iter().zip(tri) {
                images[v] = q;
            }
        }
        images
    }

    /// Whether the layers close up around every vertex (and a tube round its seam),
    /// within [`FlatFolded::tolerance`]: the one test of closure that verification, the
    /// layer solver and the studio's x-ray apply, so their verdicts agree.
    pub fn layers_close(&self) -> bool {
        self.mismatch <= self.tolerance
    }

    /// The folded state with corners that lie within `scale` of each other moved to
    /// their mean, as Flat-Folder merges folded points within its epsilon. A drawing's
    /// noise, compounded along the reflections, leaves corners meant to coincide a
    /// little apart and edges meant to lie on one line a little crossed; at the drawing's
    /// precision they are one point again, so faces meant to touch do not overlap in
    /// slivers. `scale` must be below the pattern's features (the drawing precision is
    /// at most an eighth of the shortest crease).
    pub fn snapped(mut self, scale: f64) -> FlatFolded {
        if scale <= 0.0 {
            return self;
        }
        let corners: Vec<Vec2> = self.triangles.iter().flatten().copied().collect();
        let labels = cluster_labels(&corners, scale);
        let mut sums = vec![(Vec2::zeros(), 0usize); corners.len()];
        for (p, &l) in corners.iter().zip(&labels) {
            sums[l].0 += p;
            sums[l].1 += 1;
        }
        for (k, &l) in labels.iter().enumerate() {
            let (sum, n) = sums[l];
            self.triangles[k / 3][k % 3] = sum / n as f64;
        }
        self
    }
}

/// Why a pattern has no flat-folded state.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NotFlatFoldable {
    /// No crease pattern is known (a 3D-only file that was never unfolded).
    #[error("the design has no crease pattern")]
    NoCreasePattern,
    /// A tube that cannot be cut open and unrolled into its strip.
    #[error("the tube cannot be unrolled into its strip to fold flat: {0}")]
    NoStrip(String),
    /// A crease aims at a partial fold, so the folded-flat state is not what the pattern
    /// describes.
    #[error("crease {edge} targets {degrees:.0}°, not ±180°: this pattern does not fold flat")]
    PartialTarget {
        /// The edge.
        edge: usize,
        /// Its target, degrees (paper sign: mountain positive).
        degrees: f64,
    },
}

/// The flat-folded state of `mesh`'s crease pattern (`flat` overrides the stored pattern,
/// e.g. one freshly unfolded from a design being varied), or of a tube's strip with its
/// seam checked to close ([`FlatFolded::open_seam`]). Fails when a crease targets a
/// partial fold.
///
/// # Performance
/// O(faces): one breadth-first walk (a tube's unrolling first is O(faces) too).
pub fn flat_folded(mesh: &Mesh, flat: Option<&[Vec2]>) -> Result<FlatFolded, NotFlatFoldable> {
    let cp = flat.or_else(|| mesh.crease_pattern());
    if cp.is_none() && !mesh.is_tube() {
        return Err(NotFlatFoldable::NoCreasePattern);
    }
    let reflects = mirrored_edges(mesh).map_err(|edge| NotFlatFoldable::PartialTarget {
        edge,
        degrees: mesh.edges()[edge].target.to_degrees(),
    })?;
    let Some(cp) = cp else {
        return tube_folded(mesh, &reflects);
    };
    let faces = mesh.faces();
    let topo = mesh.topology();
    let centre = cp.iter().sum::<Vec2>() / cp.len().max(1) as f64;
    let centroid = |f: &[usize; 3]| (cp[f[0]] + cp[f[1]] + cp[f[2]]) / 3.0;
    let root = (0..faces.len())
        .min_by(|&a, &b| {
            (centroid(&faces[a]) - centre)
                .norm()
                .total_cmp(&(centroid(&faces[b]) - centre).norm())
        })
        .unwrap_or(0);
    let mut motions: Vec<Option<PlaneMotion>> = vec![None; faces.len()];
    motions[root] = Some(PlaneMotion::IDENTITY);
    let mut queue = VecDeque::from([root]);
    while let Some(f) = queue.pop_front() {
        let mf = motions[f].expect("queued faces have a motion");
        for &e in &topo.face_edges[f] {
            for g in topo.edge_faces[e].iter().flatten().copied() {
                if motions[g].is_some() {
                    continue;
                }
                let [a, b] = mesh.edges()[e].vertices;
                motions[g] = Some(mf.across(cp[a], cp[b], reflects[e]));
                queue.push_back(g);
            }
        }
    }
    // Faces of other pieces of paper (none on a disk) keep their crease-pattern place.
    let motions: Vec<PlaneMotion> = motions
        .into_iter()
        .map(|m| m.unwrap_or(PlaneMotion::IDENTITY))
        .collect();
    let triangles: Vec<[Vec2; 3]> = faces
        .iter()
        .zip(&motions)
        .map(|(f, m)| f.map(|v| m.apply(cp[v])))
        .collect();
    let (mismatch, worst_vertex) = worst_closure(mesh, cp, &reflects);
    let front_up = faces
        .iter()
        .zip(&motions)
        .map(|(f, m)| {
            let counter_clockwise = (cp[f[1]] - cp[f[0]]).perp(&(cp[f[2]] - cp[f[0]])) > 0.0;
            counter_clockwise != m.flips()
        })
        .collect();
    Ok(FlatFolded {
        root,
        motions,
        triangles,
        mismatch,
        worst_vertex,
        open_seam: false,
        front_up,
        tolerance: closure_tolerance(cp, mesh.coordinate_precision),
    })
}

/// A tube's flat-folded state: its strip folded flat (faces keep their numbers and corner
/// order, so the strip's images are the tube's), with each seam edge's two faces checked
/// to meet again — the walk over the strip never crosses the seam, so nothing else
/// joins them. `reflects` is the tube's [`mirrored_edges`].
fn tube_folded(tube: &Mesh, reflects: &[bool]) -> Result<FlatFolded, NotFlatFoldable> {
    let strip = crate::geometry::unfold::unfold_tube(tube)
        .map_err(|e| NotFlatFoldable::NoStrip(e.to_string()))?;
    let mut folded = flat_folded(&strip.sheet, None)?;
    folded.worst_vertex = folded.worst_vertex.map(|v| strip.origin[v]);
    let (gap, vertex) = worst_edge_gap(tube, &folded.triangles, reflects, &strip.edges);
    if gap > folded.mismatch {
        folded.mismatch = gap;
        folded.worst_vertex = vertex;
        // Rounding leaves the seam a little open as it leaves any vertex: only a gap
        // past the closure tolerance is the tube's own.
        folded.open_seam = gap > folded.tolerance;
    }
    Ok(folded)
}

/// Of `edges` (interior edges of `mesh`), the widest gap (mm) between an edge's two faces
/// in the folded image `triangles`, and a vertex of that edge: its ends should land on
/// the same points, and the faces on one side of it when it is folded (`reflects`), on
/// both sides when not. A face on the wrong side is as far off as its far corner is from
/// its mirror image.
fn worst_edge_gap(
    mesh: &Mesh,
    triangles: &[[Vec2; 3]],
    reflects: &[bool],
    edges: &[usize],
) -> (f64, Option<usize>) {
    let faces = mesh.faces();
    let topo = mesh.topology();
    let corner = |f: usize, v: usize| {
        let k = faces[f].iter().position(|&w| w == v);
        triangles[f][k.expect("an edge's face holds its ends")]
    };
    let apex = |f: usize, [u, v]: [usize; 2]| {
        let k = faces[f].iter().position(|&w| w != u && w != v);
        triangles[f][k.expect("a triangle has a third corner")]
    };
    let mut worst = (0.0, None);
    for &e in edges {
        let edge = &mesh.edges()[e];
        let [Some(f), Some(g)] = topo.edge_faces[e] else {
            continue;
        };
        let [u, v] = edge.vertices;
        let (p, q) = (corner(f, u), corner(f, v));
        let ends = (corner(g, u) - p).norm().max((corner(g, v) - q).norm());
        let along = (q - p).normalize();
        let (side_f, side_g) = (
            along.perp(&(apex(f, edge.vertices) - p)),
            along.perp(&(apex(g, edge.vertices) - p)),
        );
        let same_side = side_f * side_g > 0.0;
        let turned = if same_side == reflects[e] {
            0.0
        } else {
            2.0 * side_g.abs()
        };
        let gap = ends.max(turned);
        if gap > worst.0 {
            worst = (gap, Some(u));
        }
    }
    worst
}

/// The largest failure of the faces around one interior vertex to close up when folded
/// flat, in mm, and that vertex. Going once around the vertex composes one reflection per
/// folded crease: an even number leaves a rotation by Σ σ_i θ_i (σ flipping at each folded
/// crease), which must vanish (Kawasaki, eq. 5 at ρ = ±π); an odd number leaves a
/// reflection, which never closes (counted as a half turn). The angle is turned into a
/// length at the vertex's shortest crease, the gap the x-ray shows there.
fn worst_closure(mesh: &Mesh, cp: &[Vec2], reflects: &[bool]) -> (f64, Option<usize>) {
    let topo = mesh.topology();
    let mut worst = (0.0, None);
    for (v, fan) in topo.fans.iter().enumerate() {
        if fan.boundary || fan.spokes.is_empty() {
            continue;
        }
        let k = fan.spokes.len();
        let arm = |i: usize| cp[mesh.edges()[fan.spokes[i % k]].other(v)] - cp[v];
        let (mut sum, mut sign, mut folds) = (0.0, 1.0, 0);
        for i in 0..k {
            let (a, b) = (arm(i), arm(i + 1));
            sum += sign * a.perp(&b).atan2(a.dot(&b)).abs();
            if reflects[fan.spokes[(i + 1) % k]] {
                sign = -sign;
                folds += 1;
            }
        }
        let turn = if folds % 2 == 1 {
            PI
        } else {
            let r = sum.rem_euclid(2.0 * PI);
            r.min(2.0 * PI - r)
        };
        let shortest = (0..k).map(|i| arm(i).norm()).fold(f64::INFINITY, f64::min);
        let gap = turn * shortest;
        if gap > worst.0 {
            worst = (gap, Some(v));
        }
    }
    worst
}

/// Each point's group when points within `scale` of each other (in x and y) are one:
/// grid cells of that size, joined where their points' boxes come that near. Folded
/// states stack many corners on one point, so cells, not points, are compared. Labels
/// are indices below `points.len()`.
pub(super) fn cluster_labels(points: &[Vec2], scale: f64) -> Vec<usize> {
    let key = |p: &Vec2| ((p.x / scale).floor() as i64, (p.y / scale).floor() as i64);
    let mut boxes: HashMap<(i64, i64), (Vec2, Vec2)> = HashMap::new();
    for p in points {
        boxes
            .entry(key(p))
            .and_modify(|(lo, hi)| {
                *lo = lo.inf(p);
                *hi = hi.sup(p);
            })
            .or_insert((*p, *p));
    }
    let cells: Vec<((i64, i64), (Vec2, Vec2))> = boxes.into_iter().collect();
    let index: HashMap<(i64, i64), usize> = cells
        .iter()
        .enumerate()
        .map(|(i, (k, _))| (*k, i))
        .collect();
    let mut groups = UnionFind::new(cells.len());
    for (i, ((cx, cy), (lo, hi))) in cells.iter().enumerate() {
        for (dx, dy) in [(1, -1), (1, 0), (1, 1), (0, 1)] {
            let Some(&j) = index.get(&(cx + dx, cy + dy)) else {
                continue;
            };
            let (olo, ohi) = cells[j].1;
            let gap_x = (olo.x - hi.x).max(lo.x - ohi.x);
            let gap_y = (olo.y - hi.y).max(lo.y - ohi.y);
            if gap_x.max(gap_y) <= scale {
                groups.union(i, j);
            }
        }
    }
    points.iter().map(|p| groups.find(index[&key(p)])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reflection_fixes_its_line_and_squares_to_the_identity() {
        let (p, q) = (Vec2::new(1.0, 2.0), Vec2::new(4.0, -1.0));
        let r = PlaneMotion::reflection(p, q);
        assert!((r.apply(p) - p).norm() < 1e-12);
        assert!((r.apply(q) - q).norm() < 1e-12);
        assert!(r.flips());
        let twice = r.after(&r);
        let z = Vec2::new(-3.0, 7.5);
        assert!((twice.apply(z) - z).norm() < 1e-12);
        assert!(!twice.flips());
        // A point off the line lands at the same distance on the other side.
        let m = r.apply(z);
        let u = (q - p).normalize();
        let side = |w: Vec2| u.perp(&(w - p));
        assert!((side(m) + side(z)).abs() < 1e-12);
    }
}

//! Sector angles θ and fold angles ρ of a triangle mesh (paper §2–3), and their gradients
//! (eq. 12–18). Free functions over position slices so the solver can call them on any
//! configuration without building a mesh.

mod gradients;
mod plane;
pub mod unfold;

pub use gradients::{fold_angle_gradient, sector_angle_gradient};
pub use plane::{out_of_plane, principal_frame};

use crate::mesh::{Mesh, Topology, Vec2, Vec3};
use std::f64::consts::PI;

/// The angle at corner `k` of triangle `face` (θ in eq. 1), radians in [0, π].
pub fn sector_angle(positions: &[Vec3], face: [usize; 3], k: usize) -> f64 {
    let p = positions[face[k]];
    let a = positions[face[(k + 1) % 3]] - p;
    let b = positions[face[(k + 2) % 3]] - p;
    a.cross(&b).norm().atan2(a.dot(&b))
}

/// Unit normal of a counter-clockwise triangle (`n_ijk` in eq. 12–18).
pub fn face_normal(positions: &[Vec3], face: [usize; 3]) -> Vec3 {
    let [i, j, k] = face;
    (positions[j] - positions[i])
        .cross(&(positions[k] - positions[i]))
        .normalize()
}

/// The vector area of a surface: the sum of its faces' areas along their normals. It
/// points to the front of a surface that is roughly flat; its length is the area of the
/// surface's projection across it.
pub fn vector_area(positions: &[Vec3], faces: &[[usize; 3]]) -> Vec3 {
    let x = positions;
    faces
        .iter()
        .map(|f| (x[f[1]] - x[f[0]]).cross(&(x[f[2]] - x[f[0]])))
        .sum::<Vec3>()
        * 0.5
}

/// Fold angle ρ of edge `e` (paper §2.4: |ρ| = π − dihedral angle; mountain positive),
/// in (−π, π]. Zero for boundary edges.
pub fn fold_angle(
    positions: &[Vec3],
    faces: &[[usize; 3]],
    topology: &Topology,
    e: usize,
    ends: [usize; 2],
) -> f64 {
    let [left, right] = topology.edge_faces[e];
    let (Some(l), Some(r)) = (left, right) else {
        return 0.0;
    };
    let n1 = face_normal(positions, faces[l]);
    let n2 = face_normal(positions, faces[r]);
    fold_angle_between(positions, n1, n2, ends)
}

/// Fold angle ρ of the edge `ends` between faces of unit normals `n1` (left) and `n2`
/// (right): the signed angle from `n1` to `n2` about the edge. Split from [`fold_angle`]
/// so an evaluation can compute each face's normal once for all three of its edges.
pub fn fold_angle_between(positions: &[Vec3], n1: Vec3, n2: Vec3, ends: [usize; 2]) -> f64 {
    let axis = (positions[ends[1]] - positions[ends[0]]).normalize();
    n1.cross(&n2).dot(&axis).atan2(n1.dot(&n2))
}

/// The fold angle on the branch closest to `previous` (paper §2: the stored angle of the
/// last frame picks the plausible candidate, so a crease folded past ±π keeps its sign).
pub fn track_branch(raw: f64, previous: f64) -> f64 {
    let gap = previous - raw;
    // Nearly every angle is on its last branch; `round` is a library call without
    // SSE4.1 and took 5% of an evaluation. The signed zero is what `round` gives there.
    let turns = if gap.abs() < 3.0 {
        0.0f64.copysign(gap)
    } else {
        (gap / (2.0 * PI)).round()
    };
    raw + turns * 2.0 * PI
}

/// Fold angles of every edge of a mesh at its current positions.
pub fn fold_angles(mesh: &Mesh) -> Vec<f64> {
    mesh.edges()
        .iter()
        .enumerate()
        .map(|(e, edge)| {
            fold_angle(
                mesh.positions(),
                mesh.faces(),
                mesh.topology(),
                e,
                edge.vertices,
            )
        })
        .collect()
}

/// The sector angles around vertex `v`, in fan order (counter-clockwise from the front).
pub fn sector_angles(mesh: &Mesh, v: usize) -> Vec<f64> {
    mesh.topology().fans[v]
        .faces
        .iter()
        .map(|&f| {
            let face = mesh.faces()[f];
            let k = face.iter().position(|&x| x == v).expect("fan face holds v");
            sector_angle(mesh.positions(), face, k)
        })
        .collect()
}

/// The part of segment `a`–`b` inside the rectangle `(lo, hi)` (Liang–Barsky), if any.
pub fn clip_segment(a: Vec2, b: Vec2, (lo, hi): (Vec2, Vec2)) -> Option<(Vec2, Vec2)> {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x - lo.x),
        (d.x, hi.x - a.x),
        (-d.y, a.y - lo.y),
        (d.y, hi.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    (t0 <= t1).then(|| (a + d * t0, a + d * t1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn track_branch_picks_the_branch_nearest_the_previous_angle() {
        let reference =
            |raw: f64, previous: f64| raw + ((previous - raw) / (2.0 * PI)).round() * 2.0 * PI;
        let mut values = vec![0.0, -0.0, 2.999_999, -2.999_999, 3.0, -3.0, PI, -PI];
        values.extend((-400..=400).map(|k| k as f64 * 0.0173));
        for &raw in &values {
            for &previous in &values {
                let (got, want) = (track_branch(raw, previous), reference(raw, previous));
                assert_eq!(
                    got.to_bits(),
                    want.to_bits(),
                    "raw {raw}, previous {previous}"
                );
                assert!((got - previous).abs() <= PI + 1e-12);
            }
        }
        // Folded past π, a crease keeps its side.
        assert!((track_branch(-3.1, 3.1) - (2.0 * PI - 3.1)).abs() < 1e-15);
    }
}

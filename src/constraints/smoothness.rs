//! Smoothness of curved creases (issue 30). The paper approximates a curved crease by a
//! chain of straight creases between planar-quad strips and found the result "can easily
//! become jagged … because of the excess degrees of freedom" (§6.6, Fig. 12); it names
//! more constraints as its first future work (§7). These are such constraints, in the
//! paper's inequality form `g ≤ 0` (§3): along each crease chain the turning angle varies
//! smoothly, in the crease pattern and in space.
//!
//! At a vertex v of a chain u → v → w:
//! - the crease pattern's turning angle is τ = π − L, L the sum of the sector angles on
//!   the chain's left (intrinsic: the developed plane's geodesic turning, read from the
//!   same sector angles as eq. 1);
//! - the folded curve's turning angle in space is κ = π − ∠(u, v, w) (its discrete
//!   curvature times the segment length), signed within each three turns compared by the
//!   side their binormals t_in × t_out take against the sharpest one's: a curve through an
//!   inflection turns smoothly through κ = 0, where the angle's size has a kink. (The
//!   curvature *vector*'s second difference would not do: it rotates with the tangent, so
//!   a circle's coarse chords would fail it.)
//!
//! Each row is `|Δ²| − B ≤ 0`, Δ² the second difference of τ (or κ) over three consecutive
//! chain vertices and B = [`MAX_SECOND_DIFFERENCE`]: a circle's chords (τ constant) and any
//! smooth curve finely divided pass; a zigzag does not.

use super::angles::Corners;
use super::chains::{left_faces, CreaseChain};
use super::{Element, Family, Reference, Rows};
use crate::geometry::sector_angle_gradient;
use crate::mesh::{Mesh, Vec3};
use std::f64::consts::PI;

/// The largest second difference of turning angle along a chain, per segment (radians):
/// half a degree, the bound issue 30's acceptance sets.
pub const MAX_SECOND_DIFFERENCE: f64 = 0.5 * PI / 180.0;

/// τ = π − L at a turn (see the module's notes), from the evaluation's sector angles.
fn pattern_turn(mesh: &Mesh, c: &Corners, turn: [usize; 3]) -> f64 {
    let v = turn[1];
    let left: f64 = left_faces(mesh, turn)
        .into_iter()
        .map(|f| c.angle_at(mesh, v, f))
        .sum();
    PI - left
}

/// Adds `scale · ∇τ` of a turn to `row`.
fn add_pattern_turn_gradient(
    mesh: &Mesh,
    c: &Corners,
    turn: [usize; 3],
    scale: f64,
    row: usize,
    rows: &mut Rows,
) {
    let v = turn[1];
    for f in left_faces(mesh, turn) {
        let face = mesh.faces()[f];
        let k = face.iter().position(|&x| x == v).expect("fan face holds v");
        let g = sector_angle_gradient(c.positions(), face, k);
        for (j, gj) in g.iter().enumerate() {
            rows.add_gradient(row, face[j], *gj, -scale);
        }
    }
}

/// κ = π − ∠(u, v, w) in space, with its gradient with respect to u, v, w (the corner
/// angle's, eq. 12–14, negated) and the binormal t_in × t_out that signs it. A straight
/// run (κ = 0) has no defined gradient: it is left zero there.
fn space_turn(x: &[Vec3], [u, v, w]: [usize; 3]) -> (f64, [Vec3; 3], Vec3) {
    let (a, b) = (x[u] - x[v], x[w] - x[v]);
    let cross = a.cross(&b);
    let corner = cross.norm().atan2(a.dot(&b));
    let kappa = PI - corner;
    // t_in × t_out = (−a) × b / (|a||b|): the side the curve turns to.
    let binormal = -cross / (a.norm() * b.norm());
    if cross.norm() <= 1e-12 * a.norm() * b.norm() {
        return (kappa, [Vec3::zeros(); 3], binormal);
    }
    let n = cross.normalize();
    let ga = -n.cross(&a) / a.norm_squared();
    let gb = n.cross(&b) / b.norm_squared();
    (kappa, [-ga, ga + gb, -gb], binormal)
}

/// Three consecutive turns in space, each signed by the side its binormal takes against
/// the sharpest turn's (see the module's notes): the values and their signs.
fn signed_space_turns(x: &[Vec3], triple: [[usize; 3]; 3]) -> [(f64, [Vec3; 3], f64); 3] {
    let turns = triple.map(|t| space_turn(x, t));
    // Against the sharpest turn's binormal: the others' sides are told apart from it
    // (a sum would vanish at a symmetric inflection, where the two sides cancel).
    let reference = turns.iter().map(|t| t.2).fold(Vec3::zeros(), |best, b| {
        if b.norm() > best.norm() {
            b
        } else {
            best
        }
    });
    turns.map(|(kappa, gradient, binormal)| {
        let sign = if binormal.dot(&reference) < 0.0 {
            -1.0
        } else {
            1.0
        };
        (sign * kappa, gradient, sign)
    })
}

/// The smoothness rows: for every chain and every three consecutive turns, the second
/// difference of τ (crease pattern) and of the signed κ (space), each as `|Δ²| − B ≤ 0`.
pub fn smoothness(mesh: &Mesh, reference: &Reference, c: &Corners, x: &[Vec3], rows: &mut Rows) {
    for chain in &reference.chains {
        for triple in chain.second_differences() {
            let weights = [1.0, -2.0, 1.0];
            let element = Element::Vertex(triple[1][1]);
            // In the crease pattern.
            let d2: f64 = (0..3)
                .map(|i| weights[i] * pattern_turn(mesh, c, triple[i]))
                .sum();
            let g = d2.abs() - MAX_SECOND_DIFFERENCE;
            if let Some(row) = rows.push_inequality(Family::Smoothness, element, g) {
                for i in 0..3 {
                    let scale = weights[i] * d2.signum();
                    add_pattern_turn_gradient(mesh, c, triple[i], scale, row, rows);
                }
            }
            // In space.
            let turns = signed_space_turns(x, triple);
            let d2: f64 = (0..3).map(|i| weights[i] * turns[i].0).sum();
            let g = d2.abs() - MAX_SECOND_DIFFERENCE;
            if let Some(row) = rows.push_inequality(Family::Smoothness, element, g) {
                for i in 0..3 {
                    let scale = weights[i] * turns[i].2 * d2.signum();
                    for (j, &vertex) in triple[i].iter().enumerate() {
                        rows.add_gradient(row, vertex, turns[i].1[j], scale);
                    }
                }
            }
        }
    }
}

/// The largest |second difference| of turning angle over every chain, in the crease
/// pattern and in space (radians): what the acceptance measures and docs/guide.md reports.
pub fn largest_second_differences(mesh: &Mesh, chains: &[CreaseChain], x: &[Vec3]) -> (f64, f64) {
    let c = Corners::new(mesh, x, false);
    let (mut pattern, mut space) = (0.0f64, 0.0f64);
    for chain in chains {
        for triple in chain.second_differences() {
            let tau = triple.map(|t| pattern_turn(mesh, &c, t));
            let kappa = signed_space_turns(x, triple).map(|t| t.0);
            pattern = pattern.max((tau[0] - 2.0 * tau[1] + tau[2]).abs());
            space = space.max((kappa[0] - 2.0 * kappa[1] + kappa[2]).abs());
        }
    }
    (pattern, space)
}

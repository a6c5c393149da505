//! One curved crease folded exactly, by the mirror construction (paper §6.6 and its future
//! work, §7; Mitani's reflected developables).
//!
//! The sheet is an annular sector: polar coordinates (r, φ) about an apex, φ across a
//! quarter turn, r across `ny` strips of width `size`, and the crease is the circular arc
//! r = R at its middle. Folded, the sheet inside the arc is a polyhedral cone: the flat
//! fan of generators φ_i, Δφ apart, bent equally at each, so every generator lies on a
//! circular cone with its apex at the origin and half-angle β about the z axis,
//!
//! ```text
//!     X(r, φ_i) = r · (sin β cos ψ_i, sin β sin ψ_i, cos β),    ψ_i = (φ_i / Δφ) · Δψ,
//!     cos Δψ = (cos Δφ − cos² β) / sin² β,
//! ```
//!
//! the azimuth step Δψ chosen so that neighbouring generators keep their flat angle Δφ
//! (every strip between them is a rigid flat piece; on the smooth cone ψ = φ / sin β,
//! the limit as Δφ → 0). The sheet outside the arc is the same cone reflected through the
//! plane z = R cos β of the crease circle, z ↦ 2R cos β − z. Reflection is an isometry,
//! so both sides develop back onto the sector and every chord of the crease folds by the
//! same angle (π − 2β in the smooth limit). The mesh runs along the cones' generators
//! (the rulings): every quad between two generators of one cone lies in a plane through
//! its apex, so quads are exactly planar, their diagonals and the arcs across a strip are
//! flat creases (target 0, twist α from the parameters, 0 by default), the generators
//! bend freely (unassigned) and the arc's chords are the fold.

use super::{assign_by_fold, lattice::build, parameter_for_fraction, GenerateError, Params};
use crate::mesh::{Assignment, Mesh, Vec2, Vec3};
use std::f64::consts::PI;

/// The flat sector's angle: a quarter turn.
const SECTOR: f64 = PI / 2.0;

/// The smallest sin β the closed form goes to: the folded sector then wraps 95% of the
/// way round its cone (ψ = φ / sin β), so it never overlaps itself.
const SMALLEST_SIN_BETA: f64 = SECTOR / (2.0 * PI) / 0.95;

/// The arc's chords' target fold, as a fraction of π (fold amount 1 reaches it): a curved
/// crease cannot fold flat (its cones would wrap round without end), and the closed
/// form's tightest cone folds the chords past 0.8 · π.
pub const ARC_TARGET: f64 = 0.8;

/// Half-angle β of the inner cone at closed-form parameter `u` (0 flat, 1 the tightest).
fn beta_at(u: f64) -> f64 {
    let tightest = SMALLEST_SIN_BETA.asin();
    PI / 2.0 - u * (PI / 2.0 - tightest)
}

/// The azimuth step Δψ between generators `dphi` apart in the flat, on a cone of
/// half-angle β: the angle between unit generators, cos² β + sin² β cos Δψ, is cos Δφ.
pub fn azimuth_step(dphi: f64, beta: f64) -> f64 {
    let (s, c) = beta.sin_cos();
    ((dphi.cos() - c * c) / (s * s)).clamp(-1.0, 1.0).acos()
}

/// A point of the folded sheet: flat polar (r, φ) with φ = k·Δφ on the cone of
/// half-angle β (azimuth ψ = k·Δψ), reflected through each crease's plane in turn, the
/// creases at radii `creases` (ascending). Reflecting through the horizontal plane of
/// a crease circle keeps x and y and turns the height's slope along a generator, so the
/// height is cos β times a zigzag in r whose slope flips (±1) at every crease: each
/// ring between two creases is a cone about the z axis with its own apex, generators
/// still unit speed in r.
pub fn folded_point(r: f64, phi: f64, dphi: f64, creases: &[f64], beta: f64) -> Vec3 {
    let (s, c) = beta.sin_cos();
    let psi = phi / dphi * azimuth_step(dphi, beta);
    Vec3::new(r * s * psi.cos(), r * s * psi.sin(), zigzag(r, creases) * c)
}

/// The height along a generator, in units of cos β: r up to the first crease, then
/// slope −1, +1, … after each crease it passes.
fn zigzag(r: f64, creases: &[f64]) -> f64 {
    let (mut height, mut at, mut slope) = (0.0, 0.0, 1.0);
    for &k in creases.iter().filter(|&&k| k < r) {
        height += slope * (k - at);
        at = k;
        slope = -slope;
    }
    height + slope * (r - at)
}

/// The arc pattern: `nx` chords along the crease, `ny` strips across (an even number,
/// half inside the crease), `size` mm apart, folded by the fold amount.
pub fn arc(p: &Params) -> Result<Mesh, GenerateError> {
    let bad = |m: String| GenerateError::BadParameter(m);
    if !p.ny.is_multiple_of(2) || p.ny < 2 {
        return Err(bad(format!(
            "ny {}: an arc takes an even number of strips, half on each side of its crease",
            p.ny
        )));
    }
    let half = p.ny / 2;
    // Chords about `size` long along the crease.
    let crease = p.nx as f64 * p.size / SECTOR;
    if half as f64 * p.size >= crease {
        return Err(bad(format!(
            "ny {} × size {}: the inner strips would pass the arc's centre ({:.1} mm from the crease); use more chords (nx) or fewer strips (ny)",
            p.ny, p.size, crease
        )));
    }
    rings(p, crease - half as f64 * p.size, &[crease])
}

/// Concentric creases: `ny` strips `size` mm wide round an annular sector whose inner
/// edge has `nx` chords about `size` long, every circle between two strips a crease,
/// mountains and valleys alternating — the mirror construction repeated, each ring
/// reflected through the plane of the crease before it.
pub fn concentric(p: &Params) -> Result<Mesh, GenerateError> {
    if p.ny < 3 {
        return Err(GenerateError::BadParameter(format!(
            "ny {}: concentric creases take at least three strips (two creases)",
            p.ny
        )));
    }
    let inner = p.nx as f64 * p.size / SECTOR;
    let creases: Vec<f64> = (1..p.ny).map(|j| inner + j as f64 * p.size).collect();
    rings(p, inner, &creases)
}

/// An annular sector from radius `inner` outward, `p.ny` strips of `p.size`, `p.nx`
/// generators' gaps across a quarter turn, folded along the circles `creases`.
fn rings(p: &Params, inner: f64, creases: &[f64]) -> Result<Mesh, GenerateError> {
    let (n, rows) = (p.nx, p.ny);
    let radius = |j: usize| inner + j as f64 * p.size;
    let angle = |i: usize| -SECTOR / 2.0 + i as f64 * SECTOR / n as f64;
    let idx = |i: usize, j: usize| j * (n + 1) + i;
    let mut polar = Vec::new();
    for j in 0..=rows {
        for i in 0..=n {
            polar.push((radius(j), angle(i)));
        }
    }
    let flat: Vec<Vec2> = polar
        .iter()
        .map(|&(r, phi)| Vec2::new(r * phi.cos(), r * phi.sin()))
        .collect();
    let mut faces = Vec::new();
    for j in 0..rows {
        for i in 0..n {
            // Counter-clockwise: out along a generator, across, back in.
            let (a, b, c, d) = (idx(i, j), idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j));
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    let dphi = SECTOR / n as f64;
    let creases = creases.to_vec();
    let on_creases = creases.clone();
    let folded_at = move |u: f64| -> Result<Vec<Vec3>, GenerateError> {
        let beta = beta_at(u);
        Ok(polar
            .iter()
            .map(|&(r, phi)| folded_point(r, phi, dphi, &creases, beta))
            .collect())
    };
    let on_crease = |a: Vec2, b: Vec2| {
        on_creases
            .iter()
            .any(|&k| (a.norm() - k).abs() < 1e-9 * k && (b.norm() - k).abs() < 1e-9 * k)
    };
    let along_generator = |a: Vec2, b: Vec2| a.perp(&b).abs() < 1e-9 * a.norm() * b.norm();
    let lattice = (flat, faces);
    curved_crease_mesh(lattice, p, on_crease, along_generator, &folded_at)
}

/// A curved-crease pattern from its lattice (points and faces of the flat sheet): the
/// edges `on_crease` tells are the chords of its creases and fold (mountain or valley,
/// read off the closed form at its middle, targeted at [`ARC_TARGET`] of π, since a curved
/// crease is not held to Kawasaki's flat-foldability); the other edges `ruling` tells are
/// the rulings of the developable between the creases and bend freely (unassigned, target
/// 0); everything else across a strip is a flat crease of twist α. Folded by `folded_at`
/// (closed-form parameter 0 flat, 1 the furthest) to the fold amount. Shared by the arc,
/// the concentric rings and the pleat.
pub(super) fn curved_crease_mesh(
    (flat, faces): (Vec<Vec2>, Vec<[usize; 3]>),
    p: &Params,
    on_crease: impl Fn(Vec2, Vec2) -> bool,
    ruling: impl Fn(Vec2, Vec2) -> bool,
    folded_at: &impl Fn(f64) -> Result<Vec<Vec3>, GenerateError>,
) -> Result<Mesh, GenerateError> {
    let points = flat.clone();
    let mut parts = build(
        flat,
        faces,
        |a, b| {
            if on_crease(a, b) {
                Assignment::Unassigned
            } else {
                Assignment::Flat
            }
        },
        p.alpha,
    );
    let rulings: Vec<bool> = parts
        .edges
        .iter()
        .map(|e| {
            let [a, b] = e.vertices.map(|v| points[v]);
            e.assignment == Assignment::Flat && ruling(a, b)
        })
        .collect();
    // Only the chords are unassigned here, so only they take a fold's sign.
    assign_by_fold(&mut parts, folded_at(0.5)?)?;
    for (e, ruling) in parts.edges.iter_mut().zip(rulings) {
        if ruling {
            e.assignment = Assignment::Unassigned;
            e.target = 0.0;
            e.fold_angle = 0.0;
        } else if matches!(e.assignment, Assignment::Mountain | Assignment::Valley) {
            e.target = e.target.signum() * ARC_TARGET * PI;
            e.fold_angle = e.target;
        }
    }
    let mut mesh = Mesh::new(parts)?;
    if let Some(t) = p.fold {
        let u = parameter_for_fraction(&mut mesh, t, folded_at)?;
        mesh.set_positions(folded_at(u)?);
    }
    Ok(mesh)
}

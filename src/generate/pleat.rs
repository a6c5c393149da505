//! A curved pleat: parallel sinusoidal creases, mountains and valleys alternating, folded
//! exactly by reflecting a ruled strip again and again (issue 30; the mirror construction
//! of curved folding, as in [`super::arc`], on a cylinder instead of a cone).
//!
//! The crease pattern has coordinates (u, v): the creases are v = A sin(k u) + V_j, j =
//! 1 … P, V_j = j · pitch, one wave across the sheet. Folded, the sheet before the first
//! crease is a *polygonal cylinder*: its rulings run along y, its cross-section is the
//! polygon γ_i = (x_i, z_i) in the xz plane with
//!
//! ```text
//!     z_i = t A sin(k u_i),   x_{i+1} = x_i + √(h² − (z_{i+1} − z_i)²),
//! ```
//!
//! every side h long, so the strip between rulings u_i and u_{i+1} develops exactly onto
//! the crease pattern's. Crease j is where that cylinder meets the plane
//! P_j: z = t (y − V_j) (at ruling i, y = A sin(k u_i) + V_j — the crease pattern's
//! curve whatever t is). The sheet past crease j is the sheet before it reflected through
//! P_j as already placed, so the ring of paper between creases q and q + 1 is the cylinder
//! moved by R_1 R_2 … R_q (reflections in the planes P_1 … P_q): each reflection is an
//! isometry, R_j fixes crease j, so the pieces meet along the creases and the whole
//! develops onto the crease pattern. t = 0 is the flat sheet; the fold grows with t.
//! Between two rulings a piece of one cylinder is a planar trapezoid (parallel rulings),
//! so its diagonal is a flat crease; the rulings bend freely and the crease chords fold.

use super::arc::curved_crease_mesh;
use super::{GenerateError, Params};
use crate::mesh::{Mesh, Vec2, Vec3};
use std::f64::consts::PI;

/// Rulings per cell along the wave: the creases turn smoothly enough between them for
/// the smoothness conditions (second differences of turning well under 0.5°).
const RULINGS_PER_CELL: usize = 4;

/// The largest t the closed form goes to, as a fraction of the t at which a side of the
/// cross-section would stand vertical (t A k h = h, where the polygon stops).
const LARGEST_T_FRACTION: f64 = 0.7;

/// The pleat: `nx` cells across (one wave), `ny` strips between `ny − 1` creases, `size`
/// mm cells; amplitude a quarter of a cell.
pub fn pleat(p: &Params) -> Result<Mesh, GenerateError> {
    if p.ny < 2 {
        return Err(GenerateError::BadParameter(format!(
            "ny {}: a pleat takes at least two strips (one crease)",
            p.ny
        )));
    }
    let n = p.nx * RULINGS_PER_CELL;
    let h = p.size / RULINGS_PER_CELL as f64;
    let width = n as f64 * h;
    let (amplitude, pitch) = (p.size / 4.0, p.size);
    let k = 2.0 * PI / width;
    let creases = p.ny - 1;
    let rows = creases + 2;
    let wave = move |i: usize| amplitude * (k * i as f64 * h).sin();
    // Row 0 is the sheet's lower edge, rows 1 … P the creases, row P + 1 the upper edge.
    let v_of = move |i: usize, r: usize| match r {
        0 => 0.0,
        r if r <= creases => wave(i) + r as f64 * pitch,
        _ => (creases + 1) as f64 * pitch,
    };
    let idx = |i: usize, r: usize| r * (n + 1) + i;
    let mut flat = Vec::new();
    for r in 0..rows {
        for i in 0..=n {
            flat.push(Vec2::new(i as f64 * h, v_of(i, r)));
        }
    }
    let mut faces = Vec::new();
    for r in 0..rows - 1 {
        for i in 0..n {
            let (a, b, c, d) = (idx(i, r), idx(i + 1, r), idx(i + 1, r + 1), idx(i, r + 1));
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    let largest_t = LARGEST_T_FRACTION / (amplitude * k);
    let folded_at = move |u: f64| -> Result<Vec<Vec3>, GenerateError> {
        let t = u * largest_t;
        let section = cross_section(n, h, |i| t * wave(i));
        let mut x = Vec::with_capacity((n + 1) * rows);
        for r in 0..rows {
            // The ring below row r: a crease row lies on both sides' images alike.
            let ring = r.saturating_sub(1).min(creases);
            for (i, &(sx, sz)) in section.iter().enumerate() {
                let mut point = Vec3::new(sx, v_of(i, r), sz);
                for j in (1..=ring).rev() {
                    point = reflect(point, t, j as f64 * pitch);
                }
                x.push(point);
            }
        }
        Ok(x)
    };
    let crease_row = |q: Vec2| {
        let i = (q.x / h).round() as usize;
        (1..=creases).find(|&r| (q.y - v_of(i, r)).abs() < 1e-9 * pitch)
    };
    let on_crease = |a: Vec2, b: Vec2| matches!((crease_row(a), crease_row(b)), (Some(x), Some(y)) if x == y && a.x != b.x);
    let ruling = |a: Vec2, b: Vec2| (a.x - b.x).abs() < 1e-12 * width;
    curved_crease_mesh((flat, faces), p, on_crease, ruling, &folded_at)
}

/// The cross-section polygon: corners at heights `z(i)`, every side `h` long.
fn cross_section(n: usize, h: f64, z: impl Fn(usize) -> f64) -> Vec<(f64, f64)> {
    let mut corners = vec![(0.0, z(0))];
    for i in 1..=n {
        let (x, zi) = (corners[i - 1].0, z(i));
        let rise = zi - corners[i - 1].1;
        corners.push((x + (h * h - rise * rise).max(0.0).sqrt(), zi));
    }
    corners
}

/// Reflection through the plane z = t (y − offset).
fn reflect(p: Vec3, t: f64, offset: f64) -> Vec3 {
    let normal = Vec3::new(0.0, -t, 1.0) / (1.0 + t * t).sqrt();
    let distance = normal.dot(&p) - normal.dot(&Vec3::new(0.0, offset, 0.0));
    p - normal * (2.0 * distance)
}

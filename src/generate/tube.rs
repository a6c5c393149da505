//! Closed tubes (paper §7, and its §6.1 waterbomb as the stent-graft pattern): a strip of
//! `nx` cells round and `ny` rows along, closed into a cylinder whose joined vertices are
//! single vertices, with its seam (the path of edges the strip is cut open along) recorded.
//!
//! Every tube here is a stack of rings: row `j`'s `nx` vertices form a regular polygon of
//! circumradius `R` (its side is the cell width `a`, so `a = 2R sin(π/nx)`), turned by an
//! angle `ψ_j` about the axis and lifted to height `z_j`. Each triangle joins two vertices
//! of one ring to one of the next, so a pattern is isometric to its strip exactly when the
//! diagonals between rings keep their flat lengths; the heights (Yoshimura, waterbomb) or
//! the strip's shear (Kresling) are chosen so they do.

use super::lattice::face_edges;
use super::{assign_by_fold_with_twist, GenerateError, Params, PatternKind};
use crate::mesh::{edge_key, Assignment, Mesh, MeshParts, Vec3};
use std::f64::consts::PI;

/// Kresling's twist between rings as a fraction of the angle a cell spans (`2π/nx`).
const KRESLING_TWIST: f64 = 0.25;
/// Kresling's largest fold amount: past it the strip's rows thin towards nothing.
pub const KRESLING_MAX_FOLD: f64 = 0.9;

/// The rings of one tube: the strip's rows and the closed form.
struct Rings {
    nx: usize,
    ny: usize,
    /// Cell width (mm): a ring polygon's side.
    width: f64,
    /// Each row's offset along the strip (mm, unwrapped: may exceed the width).
    offset: Vec<f64>,
    /// Each ring's turn about the axis (radians).
    turn: Vec<f64>,
    /// Each ring's height (mm).
    height: Vec<f64>,
}

impl Rings {
    fn radius(&self) -> f64 {
        self.width / (2.0 * (PI / self.nx as f64).sin())
    }

    fn index(&self, i: isize, j: usize) -> usize {
        j * self.nx + i.rem_euclid(self.nx as isize) as usize
    }

    /// Whole cells row `j + 1` is shifted left of row `j` (m) and the remaining shift (d).
    fn step(&self, j: usize) -> (isize, f64) {
        let delta = self.offset[j + 1] - self.offset[j];
        let m = (delta / self.width).floor();
        (m as isize, delta - m * self.width)
    }

    /// Counter-clockwise triangles (seen from outside) between each ring and the next.
    fn faces(&self) -> Vec<[usize; 3]> {
        let mut faces = Vec::with_capacity(2 * self.nx * self.ny);
        for j in 0..self.ny {
            let (m, _) = self.step(j);
            for i in 0..self.nx as isize {
                let up = self.index(i - m, j + 1);
                faces.push([self.index(i, j), self.index(i + 1, j), up]);
                faces.push([self.index(i + 1, j), self.index(i + 1 - m, j + 1), up]);
            }
        }
        faces
    }

    fn positions(&self) -> Vec<Vec3> {
        let r = self.radius();
        let mut out = Vec::with_capacity(self.nx * (self.ny + 1));
        for j in 0..=self.ny {
            for i in 0..self.nx {
                let theta = 2.0 * PI * i as f64 / self.nx as f64 + self.turn[j];
                out.push(Vec3::new(r * theta.cos(), r * theta.sin(), self.height[j]));
            }
        }
        out
    }

    /// The seam: from vertex 0 of the first ring, to each next ring by the diagonal that
    /// keeps the seam nearest its start along the strip, so the strip's ends stay square.
    fn seam(&self) -> Vec<[usize; 2]> {
        let (mut i, mut x) = (0isize, 0.0);
        let mut seam = Vec::with_capacity(self.ny);
        for j in 0..self.ny {
            let (m, d) = self.step(j);
            // Up-right by d to (i − m), or up-left by a − d to (i − m − 1).
            let (next, nx) = if (x + d).abs() <= (x + d - self.width).abs() {
                (i - m, x + d)
            } else {
                (i - m - 1, x + d - self.width)
            };
            let (a, b) = edge_key(self.index(i, j), self.index(next, j + 1));
            seam.push([a, b]);
            (i, x) = (next, nx);
        }
        seam
    }
}

/// Generates `waterbomb-tube`, `yoshimura-tube` or `kresling` closed.
pub fn tube(p: &Params) -> Result<Mesh, GenerateError> {
    let bad = |m: String| Err(GenerateError::BadParameter(m));
    if p.nx < 3 {
        return bad(format!(
            "a tube needs at least 3 cells round (nx = {}); fewer cannot close",
            p.nx
        ));
    }
    let a = p.size;
    let rings = match p.kind {
        PatternKind::WaterbombTube | PatternKind::YoshimuraTube => alternating_rings(p)?,
        PatternKind::Kresling => {
            let Some(t) = p.fold else {
                return bad(
                    "kresling is generated at a fold amount: the state its strip is made to close in (give --fold, e.g. 0.5)".into(),
                );
            };
            if t > KRESLING_MAX_FOLD {
                return bad(format!(
                    "kresling's fold amount must be at most {KRESLING_MAX_FOLD} (got {t}): past it the strip's rows thin towards nothing"
                ));
            }
            kresling(p.nx, p.ny, a, t)
        }
        _ => unreachable!("tube() is called for tubes only"),
    };
    let mut faces = rings.faces();
    if p.kind == PatternKind::WaterbombTube {
        // Seen from inside, the rings' sides are the waterbomb's mountains and the
        // diagonals its valleys (2 M + 4 V at every vertex), as in `generate waterbomb`.
        for f in &mut faces {
            f.swap(1, 2);
        }
    }
    let positions = rings.positions();
    let mut parts = MeshParts {
        positions: Some(positions.clone()),
        flat: None,
        edges: face_edges(&faces, |_, _| Assignment::Unassigned, p.alpha),
        faces,
    };
    // Mountain, valley or flat from the sign of each crease's fold in the closed form.
    assign_by_fold_with_twist(&mut parts, positions, p.alpha)?;
    let mut mesh = Mesh::new(parts)?;
    mesh.seam = rings.seam();
    Ok(mesh)
}

/// Waterbomb and Yoshimura tubes: alternate rows shifted half a cell, each ring a regular
/// polygon, the rings spaced so each diagonal keeps its flat length. They close in one
/// state, so a fold amount is refused.
fn alternating_rings(p: &Params) -> Result<Rings, GenerateError> {
    let bad = |m: String| Err(GenerateError::BadParameter(m));
    let a = p.size;
    if let Some(f) = p.fold {
        return bad(format!(
                "{} closes in one state (rings of {} equal sides), so it takes no fold amount (got {f}); fold it further with `crease fold` or `crease deform`",
                p.kind.name(),
                p.nx
            ));
    }
    // Rows of the strip: waterbomb right isosceles (height a/2), Yoshimura
    // equilateral (height a·√3/2); alternate rows shifted by half a cell.
    let row = if p.kind == PatternKind::WaterbombTube {
        a / 2.0
    } else {
        a * 3f64.sqrt() / 2.0
    };
    let offset: Vec<f64> = (0..=p.ny).map(|j| (j % 2) as f64 * a / 2.0).collect();
    let turn: Vec<f64> = offset
        .iter()
        .map(|o| 2.0 * PI * o / (p.nx as f64 * a))
        .collect();
    // A diagonal spans half a cell round: its chord is 2R sin(π / 2nx); the rings'
    // spacing makes up the rest of its flat length √((a/2)² + row²).
    let r = a / (2.0 * (PI / p.nx as f64).sin());
    let chord = 2.0 * r * (PI / (2.0 * p.nx as f64)).sin();
    let rise2 = a * a / 4.0 + row * row - chord * chord;
    if rise2 <= 0.0 {
        return bad(format!(
            "{} with {} cells round cannot close",
            p.kind.name(),
            p.nx
        ));
    }
    let height = (0..=p.ny).map(|j| j as f64 * rise2.sqrt()).collect();
    Ok(Rings {
        nx: p.nx,
        ny: p.ny,
        width: a,
        offset,
        turn,
        height,
    })
}

/// Kresling at fold amount `t`: rings `(1 − t)·a` apart, each turned a quarter cell
/// (`KRESLING_TWIST`) past the last. Its strip is the parallelogram lattice whose two
/// diagonals `b`, `c` have the ring-to-ring lengths: `b² = s² + h²`, `c² = (a − s)² + h²`,
/// so the shear `s = (a² + b² − c²) / 2a` and the row height `h = √(b² − s²)`.
fn kresling(nx: usize, ny: usize, a: f64, t: f64) -> Rings {
    let n = nx as f64;
    let r = a / (2.0 * (PI / n).sin());
    let phi = KRESLING_TWIST * 2.0 * PI / n;
    let rise = (1.0 - t) * a;
    let b2 = (2.0 * r * (phi / 2.0).sin()).powi(2) + rise * rise;
    let c2 = (2.0 * r * (PI / n - phi / 2.0).sin()).powi(2) + rise * rise;
    let s = (a * a + b2 - c2) / (2.0 * a);
    Rings {
        nx,
        ny,
        width: a,
        offset: (0..=ny).map(|j| j as f64 * s).collect(),
        turn: (0..=ny).map(|j| j as f64 * phi).collect(),
        height: (0..=ny).map(|j| j as f64 * rise).collect(),
    }
}

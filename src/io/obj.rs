//! Freeform Origami's OBJ (as Origami Simulator writes it): `v` 3D positions, `vt` the
//! crease pattern scaled to [0, 1] by its longer side, `f a/a b/b c/c`, and one
//! `#e i j TYPE 0` line per edge (TYPE 0 border, 1 flat, 2 valley, 3 mountain).

use super::FileCause;
use crate::mesh::{Assignment, Edge, Mesh, MeshParts, Vec2, Vec3};
use std::fmt::Write as _;

/// Writes `mesh` as Freeform Origami OBJ (the crease pattern as `vt`, scaled to [0, 1]).
pub fn to_string(mesh: &Mesh) -> String {
    let mut out = String::from("# crease: Freeform Origami OBJ\n");
    for p in mesh.positions() {
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
    }
    if let Some(flat) = mesh.crease_pattern() {
        let (lo, hi) = crate::mesh::bounds(flat);
        let side = (hi - lo).max().max(f64::MIN_POSITIVE);
        for p in flat {
            let q = (p - lo) / side;
            let _ = writeln!(out, "vt {} {}", q.x, q.y);
        }
    }
    for f in mesh.faces() {
        let _ = writeln!(
            out,
            "f {0}/{0} {1}/{1} {2}/{2}",
            f[0] + 1,
            f[1] + 1,
            f[2] + 1
        );
    }
    for e in mesh.edges() {
        let kind = match e.assignment {
            Assignment::Boundary | Assignment::Cut => 0,
            Assignment::Valley => 2,
            Assignment::Mountain => 3,
            _ => 1,
        };
        let _ = writeln!(
            out,
            "#e {} {} {kind} 0",
            e.vertices[0] + 1,
            e.vertices[1] + 1
        );
    }
    out
}

/// Reads Freeform Origami OBJ; the crease pattern (`vt`) is scaled back to millimetres.
pub fn parse(text: &str) -> Result<Mesh, FileCause> {
    let mut positions = Vec::new();
    let mut uv = Vec::new();
    let mut faces = Vec::new();
    let mut edges = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let bad = || {
            format!(
                "line {}: cannot read \"{}\"",
                i + 1,
                crate::limits::short_text(line.trim())
            )
        };
        let nums = |k: usize| -> Result<Vec<f64>, String> {
            f.get(1..=k)
                .ok_or_else(bad)?
                .iter()
                .map(|s| s.parse::<f64>().map_err(|_| bad()))
                .collect()
        };
        let index = |s: &str| -> Result<usize, String> {
            let v: usize = s
                .split('/')
                .next()
                .unwrap_or("")
                .parse()
                .map_err(|_| bad())?;
            v.checked_sub(1).ok_or_else(bad)
        };
        match f.first().copied() {
            Some("v") => {
                let v = nums(3)?;
                positions.push(Vec3::new(v[0], v[1], v[2]));
            }
            Some("vt") => {
                let v = nums(2)?;
                uv.push(Vec2::new(v[0], v[1]));
            }
            Some("f") => {
                if f.len() != 4 {
                    return Err(format!("line {}: only triangles are supported", i + 1).into());
                }
                faces.push([index(f[1])?, index(f[2])?, index(f[3])?]);
            }
            Some("#e") => {
                if f.len() < 4 {
                    return Err(bad().into());
                }
                let assignment = match f[3] {
                    "0" => Assignment::Boundary,
                    "1" => Assignment::Flat,
                    "2" => Assignment::Valley,
                    "3" => Assignment::Mountain,
                    _ => return Err(bad().into()),
                };
                edges.push(Edge::new(index(f[1])?, index(f[2])?, assignment));
            }
            _ => {}
        }
    }
    if positions.is_empty() {
        return Err("no vertices (\"v\" lines)".into());
    }
    let flat = (uv.len() == positions.len()).then(|| crease_pattern_in_mm(&uv, &positions, &faces));
    let mut mesh = Mesh::new(MeshParts {
        positions: Some(positions),
        flat,
        faces,
        edges,
    })
    .map_err(|e| e.to_string())?;
    mesh.coordinate_precision = super::rounding_of(&mesh, super::decimal_quantum(text));
    Ok(mesh)
}

/// `vt` is normalised; millimetres come back by matching its total edge length to the 3D
/// form's, which an isometric unfolding preserves.
fn crease_pattern_in_mm(uv: &[Vec2], positions: &[Vec3], faces: &[[usize; 3]]) -> Vec<Vec2> {
    let (mut l3, mut l2) = (0.0, 0.0);
    for f in faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            if a < positions.len() && b < positions.len() {
                l3 += (positions[a] - positions[b]).norm();
                l2 += (uv[a] - uv[b]).norm();
            }
        }
    }
    let s = if l2 > 0.0 { l3 / l2 } else { 1.0 };
    uv.iter().map(|p| p * s).collect()
}

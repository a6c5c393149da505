//! Target surfaces a design is fitted onto (`crease fit`): a triangle mesh in millimetres
//! that never moves, with the nearest-point query the fit pulls toward
//! ([`closest`]) and a few shapes a maker asks for by name ([`shapes`]).

pub mod closest;
pub mod shapes;

pub use closest::{closest_on_triangle, Closest, ClosestPointTree};

use crate::limits::{self, OutOfRange};
use crate::mesh::Vec3;

/// Why a set of triangles is no target.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SurfaceError {
    /// No triangle at all, or none with an area.
    #[error("it has no triangles{0}")]
    Empty(&'static str),
    /// A coordinate is NaN or infinite.
    #[error("vertex {0} has a coordinate that is not a number")]
    NotFinite(usize),
    /// A triangle names a vertex that is not there.
    #[error("triangle {triangle} names vertex {vertex}, but there are {count}")]
    BadIndex {
        /// The triangle.
        triangle: usize,
        /// The vertex it names.
        vertex: usize,
        /// Vertices in the file.
        count: usize,
    },
    /// Too large, too small or too many triangles.
    #[error(transparent)]
    Range(#[from] OutOfRange),
}

/// A triangle mesh in millimetres with its nearest-point hierarchy.
#[derive(Clone, Debug)]
pub struct TriSurface {
    vertices: Vec<Vec3>,
    triangles: Vec<[usize; 3]>,
    tree: ClosestPointTree,
}

impl TriSurface {
    /// Checks and indexes a surface: every coordinate a number, every index in range,
    /// its extent and triangle count within [`limits::TARGET_EXTENT`] and
    /// [`limits::TARGET_TRIANGLES`]. Triangles without area are left out (they hold no
    /// nearest point a neighbour does not).
    pub fn new(
        vertices: Vec<Vec3>,
        triangles: Vec<[usize; 3]>,
    ) -> Result<TriSurface, SurfaceError> {
        if triangles.is_empty() {
            return Err(SurfaceError::Empty(""));
        }
        limits::TARGET_TRIANGLES.check_count("triangles", triangles.len() as u64)?;
        if let Some(v) = vertices
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(SurfaceError::NotFinite(v));
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&v) = tri.iter().find(|&&v| v >= vertices.len()) {
                return Err(SurfaceError::BadIndex {
                    triangle: t,
                    vertex: v,
                    count: vertices.len(),
                });
            }
        }
        let (lo, hi) = crate::mesh::bounds(&vertices);
        limits::TARGET_EXTENT.check("its extent", (hi - lo).norm())?;
        let scale = (hi - lo).norm();
        // Coincident copies are kept once: the hierarchy cannot prune between triangles
        // with one box, so 400k copies of one triangle took a minute of fitting. Corners
        // are compared on a grid of 1e-9 of the extent, far below any fit's goal.
        let grid = 1e-9 * scale;
        let mut seen = std::collections::HashSet::new();
        let triangles: Vec<[usize; 3]> = triangles
            .into_iter()
            .filter(|t| {
                let [a, b, c] = t.map(|v| vertices[v]);
                (b - a).cross(&(c - a)).norm() > 1e-12 * scale * scale
            })
            .filter(|t| {
                let mut corners = t.map(|v| ((vertices[v] - lo) / grid).map(|x| x.round() as i64));
                corners.sort_by_key(|p| (p.x, p.y, p.z));
                seen.insert(corners.map(|p| [p.x, p.y, p.z]))
            })
            .collect();
        if triangles.is_empty() {
            return Err(SurfaceError::Empty(" with an area"));
        }
        let tree = ClosestPointTree::build(&vertices, &triangles);
        Ok(TriSurface {
            vertices,
            triangles,
            tree,
        })
    }

    /// The vertices (mm).
    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices
    }

    /// The triangles with an area.
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// The surface's nearest point to `p`.
    pub fn closest(&self, p: Vec3) -> Closest {
        self.tree
            .closest(&self.vertices, &self.triangles, p)
            .expect("a surface has triangles")
    }

    /// Unit normal of triangle `t` (by its corners' order).
    pub fn normal(&self, t: usize) -> Vec3 {
        let [a, b, c] = self.triangles[t].map(|v| self.vertices[v]);
        (b - a).cross(&(c - a)).normalize()
    }

    /// The smallest box around the vertices.
    pub fn bounding_box(&self) -> (Vec3, Vec3) {
        crate::mesh::bounds(&self.vertices)
    }

    /// The area-weighted mean of the triangles' centroids and the total area.
    pub fn centroid(&self) -> (Vec3, f64) {
        let mut sum = Vec3::zeros();
        let mut area = 0.0;
        for t in &self.triangles {
            let [a, b, c] = t.map(|v| self.vertices[v]);
            let w = (b - a).cross(&(c - a)).norm() / 2.0;
            sum += (a + b + c) / 3.0 * w;
            area += w;
        }
        (sum / area, area)
    }

    /// The surface placed as a person turns it: `offset` mm along its normals, turned by
    /// `turn_degrees` about x, then y, then z (each about the fixed axes), shifted by
    /// `shift` ([`TriSurface::moved`]).
    pub fn placed(&self, offset: f64, turn_degrees: [f64; 3], shift: Vec3) -> TriSurface {
        use nalgebra::Rotation3;
        let r = turn_degrees.map(f64::to_radians);
        let rotation = Rotation3::from_axis_angle(&Vec3::z_axis(), r[2])
            * Rotation3::from_axis_angle(&Vec3::y_axis(), r[1])
            * Rotation3::from_axis_angle(&Vec3::x_axis(), r[0]);
        self.moved(offset, rotation.matrix(), shift)
    }

    /// The surface moved: each vertex first `offset` mm along its normal (the area-weighted
    /// mean of its triangles'), then turned by `rotation` about the area centroid and
    /// shifted by `shift`. The studio places a loaded target with it.
    pub fn moved(&self, offset: f64, rotation: &nalgebra::Matrix3<f64>, shift: Vec3) -> TriSurface {
        let mut normals = vec![Vec3::zeros(); self.vertices.len()];
        for t in &self.triangles {
            let [a, b, c] = t.map(|v| self.vertices[v]);
            let n = (b - a).cross(&(c - a));
            t.iter().for_each(|&v| normals[v] += n);
        }
        let (centre, _) = self.centroid();
        let vertices: Vec<Vec3> = self
            .vertices
            .iter()
            .zip(&normals)
            .map(|(p, n)| {
                let p = p + n.try_normalize(0.0).unwrap_or_else(Vec3::zeros) * offset;
                rotation * (p - centre) + centre + shift
            })
            .collect();
        let tree = ClosestPointTree::build(&vertices, &self.triangles);
        TriSurface {
            vertices,
            triangles: self.triangles.clone(),
            tree,
        }
    }

    /// Wavefront OBJ text: `v x y z` lines, then `f a b c` (1-based).
    pub fn to_obj(&self, comment: &str) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        for line in comment.lines() {
            let _ = writeln!(s, "# {line}");
        }
        for v in &self.vertices {
            let _ = writeln!(s, "v {} {} {}", v.x, v.y, v.z);
        }
        for t in &self.triangles {
            let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::{TriSurface, Vec3};

    #[test]
    fn a_placed_surface_turns_about_x_then_y_then_z_around_its_centroid() {
        // A flat square centred on the origin. Corner (1, 0, 0): 90° about x keeps it,
        // 90° about y sends it to (0, 0, -1), 90° about z leaves it there. Corner
        // (0, 1, 0): about x to (0, 0, 1), about y to (1, 0, 0), about z to (0, 1, 0).
        // The shift moves every vertex by itself.
        let square = TriSurface::new(
            vec![
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(-1.0, 0.0, 0.0),
                Vec3::new(0.0, -1.0, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap();
        let shift = Vec3::new(5.0, -2.0, 7.0);
        let placed = square.placed(0.0, [90.0, 90.0, 90.0], shift);
        let expect = [Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 1.0, 0.0)];
        for (v, want) in expect.iter().enumerate() {
            let got = placed.vertices()[v] - shift;
            assert!((got - want).norm() < 1e-12, "vertex {v}: {got:?}");
        }
        // Lengths are kept: a placement is rigid.
        let side = |s: &TriSurface| (s.vertices()[0] - s.vertices()[1]).norm();
        assert!((side(&placed) - side(&square)).abs() < 1e-12);
    }
}

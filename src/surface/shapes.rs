//! Target shapes a maker asks for by name (`crease surface`): a spherical cap (a dome),
//! a hyperbolic paraboloid (a saddle) and a circular cylinder (a vault), each a square
//! patch of `span` × `span` mm seen from above, its apex or centre at the origin, sampled
//! on a grid of `resolution` × `resolution` squares of two triangles.

use super::{SurfaceError, TriSurface};
use crate::limits::{self, OutOfRange};
use crate::mesh::Vec3;

/// A named shape and its dimensions (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// z = √(R² − x² − y²) − R: a sphere of radius R, apex at the origin, bulging up (+z).
    Cap {
        /// The sphere's radius.
        radius: f64,
    },
    /// z = depth · (x² − y²) / (span/2)²: rises by `depth` at the middles of two opposite
    /// sides and falls by it at the other two.
    Saddle {
        /// Height at the middle of a side.
        depth: f64,
    },
    /// z = √(R² − x²) − R: a cylinder of radius R along y.
    Cylinder {
        /// The cylinder's radius.
        radius: f64,
    },
}

impl Shape {
    /// The names `crease surface` takes.
    pub const NAMES: [&'static str; 3] = ["cap", "saddle", "cylinder"];

    /// Height above the tangent plane at (x, y).
    fn height(&self, x: f64, y: f64, span: f64) -> f64 {
        match *self {
            Shape::Cap { radius } => (radius * radius - x * x - y * y).sqrt() - radius,
            Shape::Saddle { depth } => depth * (x * x - y * y) / (span * span / 4.0),
            Shape::Cylinder { radius } => (radius * radius - x * x).sqrt() - radius,
        }
    }

    /// The shape sampled over a `span`-wide square. The sphere and the cylinder must
    /// reach over it: `span` at most √2 R (cap) or 2 R (cylinder), less 1%.
    pub fn surface(&self, span: f64, resolution: usize) -> Result<TriSurface, ShapeError> {
        limits::PATTERN_EXTENT.check("--span", span)?;
        limits::SURFACE_RESOLUTION.check_count("--resolution", resolution as u64)?;
        match *self {
            Shape::Cap { radius } | Shape::Cylinder { radius } => {
                limits::RADIUS.check("--radius", radius)?;
                let reach = match self {
                    Shape::Cap { .. } => std::f64::consts::SQRT_2 * radius,
                    _ => 2.0 * radius,
                };
                if span > 0.99 * reach {
                    return Err(ShapeError::TooWide { span, reach });
                }
            }
            Shape::Saddle { depth } => {
                limits::PATTERN_EXTENT.check("--depth", depth.abs())?;
            }
        }
        let n = resolution;
        let mut vertices = Vec::with_capacity((n + 1) * (n + 1));
        for j in 0..=n {
            for i in 0..=n {
                let x = span * (i as f64 / n as f64 - 0.5);
                let y = span * (j as f64 / n as f64 - 0.5);
                vertices.push(Vec3::new(x, y, self.height(x, y, span)));
            }
        }
        let mut triangles = Vec::with_capacity(2 * n * n);
        for j in 0..n {
            for i in 0..n {
                let v = j * (n + 1) + i;
                triangles.push([v, v + 1, v + n + 2]);
                triangles.push([v, v + n + 2, v + n + 1]);
            }
        }
        Ok(TriSurface::new(vertices, triangles)?)
    }
}

/// A shape that cannot be made with the dimensions given.
#[derive(Debug, thiserror::Error)]
pub enum ShapeError {
    /// A dimension out of its range.
    #[error(transparent)]
    Range(#[from] OutOfRange),
    /// The square does not fit on the sphere or cylinder.
    #[error("--span = {}: a square this wide does not fit on the shape (at most {} mm for this radius)", limits::short(*.span), limits::short(0.99 * *.reach))]
    TooWide {
        /// The span asked for.
        span: f64,
        /// The widest square the shape holds.
        reach: f64,
    },
    /// The sampled surface is no target (cannot happen within the ranges; kept typed).
    #[error(transparent)]
    Surface(#[from] SurfaceError),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_sample_of_a_cap_lies_on_its_sphere_and_of_a_saddle_on_its_paraboloid() {
        let r = 300.0;
        let cap = Shape::Cap { radius: r }.surface(400.0, 20).unwrap();
        let centre = Vec3::new(0.0, 0.0, -r);
        for v in cap.vertices() {
            assert!(((v - centre).norm() - r).abs() < 1e-9);
        }
        let saddle = Shape::Saddle { depth: 30.0 }.surface(200.0, 20).unwrap();
        for v in saddle.vertices() {
            assert!((v.z - 30.0 * (v.x * v.x - v.y * v.y) / 10_000.0).abs() < 1e-9);
        }
        assert_eq!(saddle.triangles().len(), 800);
    }

    #[test]
    fn a_square_wider_than_the_sphere_holds_is_refused() {
        let e = Shape::Cap { radius: 100.0 }
            .surface(150.0, 10)
            .unwrap_err()
            .to_string();
        assert!(e.contains("does not fit"), "{e}");
        assert!(Shape::Cylinder { radius: 1e308 }
            .surface(100.0, 10)
            .is_err());
    }
}

//! A rigid placement of a design on its target, before any folding changes: paper does not
//! stretch, so only a rotation and a translation (no scaling). Candidates match the
//! design's principal frame to the target's at the point of the target nearest its
//! centroid, both ways up and at four quarter turns; each is refined by iterative
//! closest points (ICP: pair every surface point with its nearest target point, move by
//! the least-squares rigid motion of Kabsch's method, repeat), and the one with the
//! smallest RMS distance wins.

use crate::geometry::principal_frame;
use crate::mesh::Vec3;
use crate::surface::TriSurface;
use nalgebra::Matrix3;

/// A rigid motion x ↦ R x + t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The rotation R (orthonormal, determinant +1).
    pub rotation: Matrix3<f64>,
    /// The translation t (mm).
    pub translation: Vec3,
}

impl Placement {
    /// No motion.
    pub fn identity() -> Placement {
        Placement {
            rotation: Matrix3::identity(),
            translation: Vec3::zeros(),
        }
    }

    /// R p + t.
    pub fn apply(&self, p: Vec3) -> Vec3 {
        self.rotation * p + self.translation
    }

    /// This motion after `first`.
    pub fn after(&self, first: &Placement) -> Placement {
        Placement {
            rotation: self.rotation * first.rotation,
            translation: self.rotation * first.translation + self.translation,
        }
    }
}

/// The rigid motion taking `from` nearest to `to` in least squares (Kabsch's method: the
/// SVD of the cross-covariance, with the reflection removed).
pub fn kabsch(from: &[Vec3], to: &[Vec3]) -> Placement {
    let n = from.len().max(1) as f64;
    let cf = from.iter().sum::<Vec3>() / n;
    let ct = to.iter().sum::<Vec3>() / n;
    let mut h = Matrix3::zeros();
    for (p, q) in from.iter().zip(to) {
        h += (p - cf) * (q - ct).transpose();
    }
    let svd = h.svd(true, true);
    let (u, vt) = (svd.u.expect("asked for"), svd.v_t.expect("asked for"));
    let mut d = Matrix3::identity();
    if (vt.transpose() * u.transpose()).determinant() < 0.0 {
        d[(2, 2)] = -1.0;
    }
    let rotation = vt.transpose() * d * u.transpose();
    Placement {
        rotation,
        translation: ct - rotation * cf,
    }
}

/// The RMS distance of `points` from `surface`, and their nearest points there.
pub fn rms_to(points: &[Vec3], surface: &TriSurface) -> (f64, Vec<Vec3>) {
    let nearest: Vec<Vec3> = points.iter().map(|&p| surface.closest(p).point).collect();
    let sum: f64 = points
        .iter()
        .zip(&nearest)
        .map(|(p, q)| (p - q).norm_squared())
        .sum();
    ((sum / points.len().max(1) as f64).sqrt(), nearest)
}

/// Iterative closest points from `start`: at most `iterations` rounds, stopping when the
/// RMS distance improves by less than a millionth of `scale`. Returns the placement and
/// its RMS distance.
pub fn icp(
    points: &[Vec3],
    surface: &TriSurface,
    start: Placement,
    iterations: usize,
    scale: f64,
) -> (Placement, f64) {
    let mut placement = start;
    let moved = |p: &Placement| points.iter().map(|&x| p.apply(x)).collect::<Vec<_>>();
    let mut current = moved(&placement);
    let (mut rms, mut nearest) = rms_to(&current, surface);
    for _ in 0..iterations {
        let step = kabsch(&current, &nearest);
        let next = step.after(&placement);
        let candidate = moved(&next);
        let (next_rms, next_nearest) = rms_to(&candidate, surface);
        if next_rms >= rms - 1e-6 * scale {
            if next_rms < rms {
                (placement, rms) = (next, next_rms);
            }
            break;
        }
        (placement, current, rms, nearest) = (next, candidate, next_rms, next_nearest);
    }
    (placement, rms)
}

/// The best rigid placement of the surface `points` on `surface` (see the module's doc).
/// `front` is the design's front side (its mean face normal): the first candidates
/// turn it along the target's normal, and a candidate only wins against an earlier one
/// by a clear margin, so a symmetric case keeps the design's front facing the target's.
pub fn place(points: &[Vec3], front: Vec3, surface: &TriSurface, scale: f64) -> (Placement, f64) {
    let (mut design, c) = principal_frame(points.iter().copied());
    if design.column(2).dot(&front) < 0.0 {
        design.column_mut(2).neg_mut();
        design.column_mut(1).neg_mut();
    }
    let (target_centre, _) = surface.centroid();
    let anchor = surface.closest(target_centre);
    let normal = surface.normal(anchor.triangle);
    let (target_frame, _) = principal_frame(surface.vertices().iter().copied());
    // The target's widest direction, in its tangent plane at the anchor.
    let mut u = target_frame.column(0).into_owned();
    u -= normal * normal.dot(&u);
    if u.norm() < 1e-6 {
        u = normal.cross(&Vec3::x());
        if u.norm() < 1e-6 {
            u = normal.cross(&Vec3::y());
        }
    }
    let u = u.normalize();
    let mut best: Option<(Placement, f64)> = None;
    for up in [1.0, -1.0] {
        let t3 = normal * up;
        for quarter in 0..4 {
            let angle = quarter as f64 * std::f64::consts::FRAC_PI_2;
            let t1 = u * angle.cos() + t3.cross(&u) * angle.sin();
            let t2 = t3.cross(&t1);
            let target = Matrix3::from_columns(&[t1, t2, t3]);
            let rotation = target * design.transpose();
            let start = Placement {
                rotation,
                translation: anchor.point - rotation * c,
            };
            let (placed, rms) = icp(points, surface, start, 40, scale);
            if best.is_none_or(|(_, b)| rms < b - 1e-3 * scale) {
                best = Some((placed, rms));
            }
        }
    }
    best.expect("eight candidates tried")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::shapes::Shape;

    #[test]
    fn kabsch_recovers_a_rigid_motion_exactly() {
        let points: Vec<Vec3> = (0..20)
            .map(|k| {
                let t = k as f64;
                Vec3::new(t.sin() * 10.0, (1.3 * t).cos() * 7.0, t * 0.5)
            })
            .collect();
        let motion = Placement {
            rotation: *nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 2.0).matrix(),
            translation: Vec3::new(5.0, -2.0, 40.0),
        };
        let moved: Vec<Vec3> = points.iter().map(|&p| motion.apply(p)).collect();
        let found = kabsch(&points, &moved);
        assert!((found.rotation - motion.rotation).norm() < 1e-12);
        assert!((found.translation - motion.translation).norm() < 1e-10);
    }

    #[test]
    fn a_cap_sampled_off_its_place_is_put_back_on_its_sphere() {
        let r = 200.0;
        let cap = Shape::Cap { radius: r }.surface(250.0, 40).unwrap();
        // Points of a smaller patch of the same sphere, turned and moved away.
        let patch: Vec<Vec3> = Shape::Cap { radius: r }
            .surface(100.0, 8)
            .unwrap()
            .vertices()
            .to_vec();
        let motion = Placement {
            rotation: *nalgebra::Rotation3::from_euler_angles(0.4, 0.2, 0.9).matrix(),
            translation: Vec3::new(30.0, -80.0, 120.0),
        };
        let moved: Vec<Vec3> = patch.iter().map(|&p| motion.apply(p)).collect();
        let front = motion.rotation * Vec3::z();
        let (placement, rms) = place(&moved, front, &cap, 250.0);
        // The target's flat triangles lie up to their sagitta, (6.25 mm)² / 8R = 0.024 mm,
        // inside the sphere the points were sampled on.
        assert!(rms < 0.03, "{rms}");
        let centre = Vec3::new(0.0, 0.0, -r);
        for p in &moved {
            let q = placement.apply(*p);
            assert!(((q - centre).norm() - r).abs() < 0.05);
        }
    }
}

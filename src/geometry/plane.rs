//! The principal axes of a point set and its least-squares plane: how far a panel, a
//! folded form or a fit's surface points are from lying flat, and which way they spread.

use crate::mesh::Vec3;
use nalgebra::{Matrix3, SymmetricEigen};

/// The centroid of `points` and the eigenvectors of their covariance, largest spread
/// first, as the columns of a right-handed frame: the third column is the normal of their
/// least-squares plane.
pub fn principal_frame<I>(points: I) -> (Matrix3<f64>, Vec3)
where
    I: IntoIterator<Item = Vec3>,
    I::IntoIter: Clone,
{
    let points = points.into_iter();
    let n = points.clone().count().max(1) as f64;
    let centroid = points.clone().sum::<Vec3>() / n;
    let mut covariance = Matrix3::zeros();
    for p in points {
        let d = p - centroid;
        covariance += d * d.transpose();
    }
    let eigen = SymmetricEigen::new(covariance);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
    let mut frame =
        Matrix3::from_columns(&order.map(|k| eigen.eigenvectors.column(k).into_owned()));
    if frame.determinant() < 0.0 {
        frame.column_mut(1).neg_mut();
    }
    (frame, centroid)
}

/// The largest distance of `points` from their least-squares plane (through their
/// centroid, normal to the covariance's least eigenvector), mm.
pub fn out_of_plane<I>(points: I) -> f64
where
    I: IntoIterator<Item = Vec3>,
    I::IntoIter: Clone,
{
    let points = points.into_iter();
    let (frame, centroid) = principal_frame(points.clone());
    let normal: Vec3 = frame.column(2).into_owned();
    points
        .map(|p| (p - centroid).dot(&normal).abs())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_on_a_turned_plane_lie_in_it_and_one_lifted_point_is_measured() {
        // A symmetric grid, wider along x (±50) than y (±20): its principal axes are
        // exactly the plane's x, y and normal.
        let turn = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1);
        let shift = Vec3::new(12.0, -4.0, 30.0);
        let grid = (-5..=5).flat_map(|i| (-2..=2).map(move |j| (i, j)));
        let mut points: Vec<Vec3> = grid
            .map(|(i, j)| turn * Vec3::new(10.0 * f64::from(i), 10.0 * f64::from(j), 0.0) + shift)
            .collect();
        assert!(out_of_plane(points.iter().copied()) < 1e-9);
        let (frame, centroid) = principal_frame(points.iter().copied());
        assert!(frame.determinant() > 0.0, "a right-handed frame");
        // The widest spread is along the plane's x (±50 against ±20), its normal z.
        assert!((frame.column(0).dot(&(turn * Vec3::x())).abs() - 1.0).abs() < 1e-9);
        assert!((frame.column(2).dot(&(turn * Vec3::z())).abs() - 1.0).abs() < 1e-9);
        assert!((centroid - shift).norm() < 1e-12);
        // Four points at ±h about the plane, in a square: the plane lies between them.
        let h = 0.5;
        points = [
            (-1.0, -1.0, h),
            (1.0, -1.0, -h),
            (1.0, 1.0, h),
            (-1.0, 1.0, -h),
        ]
        .map(|(x, y, z)| turn * Vec3::new(10.0 * x, 10.0 * y, z) + shift)
        .to_vec();
        assert!((out_of_plane(points.iter().copied()) - h).abs() < 1e-9);
    }
}

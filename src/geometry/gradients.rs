//! Analytic gradients of sector and fold angles (paper eq. 12–18).

use super::face_normal;
use crate::mesh::Vec3;

/// Gradient of the angle at corner `k` of triangle `face` with respect to the triangle's
/// three vertices, in face order (eq. 12–14): moving an arm's end perpendicular to the arm
/// opens the angle at rate 1/length.
pub fn sector_angle_gradient(positions: &[Vec3], face: [usize; 3], k: usize) -> [Vec3; 3] {
    let p = positions[face[k]];
    let u = positions[face[(k + 1) % 3]] - p;
    let w = positions[face[(k + 2) % 3]] - p;
    let n = u.cross(&w).normalize();
    let gu = -n.cross(&u) / u.norm_squared();
    let gw = n.cross(&w) / w.norm_squared();
    let mut g = [Vec3::zeros(); 3];
    g[k] = -(gu + gw);
    g[(k + 1) % 3] = gu;
    g[(k + 2) % 3] = gw;
    g
}

/// Gradient of the fold angle ρ of edge `a → b` with respect to `[a, b, k, l]`, where
/// triangle `(a, b, k)` is counter-clockwise on the left of the edge and `(b, a, l)` on its
/// right (eq. 15–18). The wing tips move along their face normals at rate 1/h; the edge's
/// ends take the rest so the gradient is blind to rigid motions, split by where each tip
/// projects onto the edge (the cotangent weights of eq. 17–18).
pub fn fold_angle_gradient(
    positions: &[Vec3],
    a: usize,
    b: usize,
    k: usize,
    l: usize,
) -> [Vec3; 4] {
    let (xa, xb) = (positions[a], positions[b]);
    let e = xb - xa;
    let len2 = e.norm_squared();
    let n1 = face_normal(positions, [a, b, k]);
    let n2 = face_normal(positions, [b, a, l]);
    let height = |x: Vec3| e.cross(&(x - xa)).norm() / len2.sqrt();
    let gk = -n1 / height(positions[k]);
    let gl = -n2 / height(positions[l]);
    let sk = (positions[k] - xa).dot(&e) / len2;
    let sl = (positions[l] - xa).dot(&e) / len2;
    [
        -gk * (1.0 - sk) - gl * (1.0 - sl),
        -gk * sk - gl * sl,
        gk,
        gl,
    ]
}

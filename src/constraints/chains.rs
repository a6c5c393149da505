//! What the smoothness conditions need of crease chains (found by
//! [`crate::mesh::crease_chains`], once per design in [`super::Reference`]): the triples
//! of turns whose second difference is bounded, the faces on a chain's left, and whether
//! a pattern has curved creases at all.

use crate::geometry::sector_angle;
pub use crate::mesh::{crease_chains, CreaseChain};
use crate::mesh::{Mesh, Vec3};
use std::f64::consts::PI;

impl CreaseChain {
    /// Consecutive triples of [`CreaseChain::turns`] whose second difference is taken.
    pub(super) fn second_differences(&self) -> Vec<[[usize; 3]; 3]> {
        let t = self.turns();
        let n = t.len();
        if self.closed && n >= 3 {
            (0..n)
                .map(|i| [t[(i + n - 1) % n], t[i], t[(i + 1) % n]])
                .collect()
        } else {
            t.windows(3).map(|w| [w[0], w[1], w[2]]).collect()
        }
    }
}

/// The faces of `v`'s fan on the left of a chain arriving from `u` and leaving to `w`:
/// counter-clockwise from the spoke to w up to the spoke to u.
pub(super) fn left_faces(mesh: &Mesh, [u, v, w]: [usize; 3]) -> Vec<usize> {
    let fan = &mesh.topology().fans[v];
    let n = fan.spokes.len();
    let spoke_to = |x: usize| {
        fan.spokes
            .iter()
            .position(|&e| mesh.edges()[e].vertices.contains(&x))
            .expect("a chain's neighbour is joined to it by a crease")
    };
    let (from, to) = (spoke_to(w), spoke_to(u));
    let count = (to + n - from) % n;
    (0..count).map(|i| fan.faces[(from + i) % n]).collect()
}

/// Whether some chain of `mesh` long enough to have a second difference turns in its
/// crease pattern (a curved crease, drawn as chords), judged on `flat`, the reference
/// positions: such patterns get the smoothness family by default.
pub fn has_curved_crease(mesh: &Mesh, chains: &[CreaseChain], flat: &[Vec3]) -> bool {
    // A chain of fewer than three turns has no second difference to bound.
    let bounded = chains.iter().filter(|c| !c.second_differences().is_empty());
    bounded.flat_map(CreaseChain::turns).any(|turn| {
        let v = turn[1];
        let left: f64 = left_faces(mesh, turn)
            .into_iter()
            .map(|f| {
                let face = mesh.faces()[f];
                let k = face.iter().position(|&x| x == v).expect("fan face holds v");
                sector_angle(flat, face, k)
            })
            .sum();
        (PI - left).abs() > 1e-6
    })
}

/// Whether `mesh` has a curved crease (`has_curved_crease` over its own chains, judged
/// on its crease pattern, or its 3D form when it has none): its unassigned edges are then
/// the rulings of the developable surface between the creases.
pub fn has_curved_creases(mesh: &Mesh) -> bool {
    let reference: Vec<Vec3> = match mesh.crease_pattern() {
        Some(f) => f.iter().map(|p| Vec3::new(p.x, p.y, 0.0)).collect(),
        None => mesh.positions().to_vec(),
    };
    has_curved_crease(mesh, &crease_chains(mesh), &reference)
}

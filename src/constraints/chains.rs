//! Crease chains: curved creases as they are drawn, straight creases joined end to end
//! through vertices where exactly two creases meet (issue 30). What the smoothness
//! conditions walk along; found once per design ([`super::Reference`]).

use crate::geometry::sector_angle;
use crate::mesh::{Mesh, Vec3};
use std::f64::consts::PI;

/// One crease chain: creases (mountain or valley) joined end to end through interior
/// vertices where exactly two creases meet, which is how a curved crease is drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct CreaseChain {
    /// Its vertices in order (a closed chain does not repeat its first).
    pub vertices: Vec<usize>,
    /// Whether it closes on itself (a circle drawn inside the sheet).
    pub closed: bool,
}

impl CreaseChain {
    /// The chain's vertices at which it turns, each with the one before and after:
    /// every vertex of a closed chain, the inner ones of an open chain.
    pub fn turns(&self) -> Vec<[usize; 3]> {
        let v = &self.vertices;
        let n = v.len();
        if self.closed {
            (0..n)
                .map(|i| [v[(i + n - 1) % n], v[i], v[(i + 1) % n]])
                .collect()
        } else {
            v.windows(3).map(|w| [w[0], w[1], w[2]]).collect()
        }
    }

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

/// The creases of `mesh` joined into chains: maximal runs of mountain and valley edges
/// through interior vertices with exactly two of them. Chains of one edge are left out
/// (nothing turns there).
pub fn crease_chains(mesh: &Mesh) -> Vec<CreaseChain> {
    let topo = mesh.topology();
    let folded = |e: usize| mesh.edges()[e].assignment.is_folded();
    // Per vertex, its folded spokes; a vertex passes a chain on when it is interior and
    // has exactly two.
    let creases_at: Vec<Vec<usize>> = topo
        .fans
        .iter()
        .map(|fan| fan.spokes.iter().copied().filter(|&e| folded(e)).collect())
        .collect();
    let passes = |v: usize| !topo.fans[v].boundary && creases_at[v].len() == 2;
    let other_end = |e: usize, v: usize| {
        let [a, b] = mesh.edges()[e].vertices;
        if a == v {
            b
        } else {
            a
        }
    };
    let mut used = vec![false; mesh.edges().len()];
    let mut chains = Vec::new();
    // Walks from `start` along crease `e` while the vertices pass the chain on.
    let walk = |start: usize, first: usize, used: &mut Vec<bool>| {
        let mut vertices = vec![start];
        let (mut v, mut e) = (start, first);
        loop {
            used[e] = true;
            v = other_end(e, v);
            if v == start {
                return CreaseChain {
                    vertices,
                    closed: true,
                };
            }
            vertices.push(v);
            if !passes(v) {
                break;
            }
            let [a, b] = [creases_at[v][0], creases_at[v][1]];
            e = if a == e { b } else { a };
            if used[e] {
                break;
            }
        }
        CreaseChain {
            vertices,
            closed: false,
        }
    };
    // Open chains from their ends, then what is left: closed loops.
    for v in (0..mesh.vertex_count()).filter(|&v| !passes(v)) {
        for &e in &creases_at[v] {
            if !used[e] {
                chains.push(walk(v, e, &mut used));
            }
        }
    }
    for v in (0..mesh.vertex_count()).filter(|&v| passes(v)) {
        let e = creases_at[v][0];
        if !used[e] {
            chains.push(walk(v, e, &mut used));
        }
    }
    chains.retain(|c| c.vertices.len() >= 3);
    chains
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

/// Whether `mesh` has a curved crease ([`has_curved_crease`] over its own chains, judged
/// on its crease pattern, or its 3D form when it has none): its unassigned edges are then
/// the rulings of the developable surface between the creases.
pub fn has_curved_creases(mesh: &Mesh) -> bool {
    let reference: Vec<Vec3> = match mesh.flat() {
        Some(f) => f.iter().map(|p| Vec3::new(p.x, p.y, 0.0)).collect(),
        None => mesh.positions().to_vec(),
    };
    has_curved_crease(mesh, &crease_chains(mesh), &reference)
}

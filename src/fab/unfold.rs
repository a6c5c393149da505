//! Isometric unfolding of a developable 3D design to its crease pattern: triangles are laid
//! out across a spanning tree of the faces, each placed from its 3D edge lengths on the far
//! side of the edge it shares with its parent, so orientation is kept; the result is then
//! turned and moved onto the previous crease pattern when one is known.

use crate::mesh::{Mesh, Vec2};
use std::collections::VecDeque;

/// Why a design cannot be unfolded.
#[derive(Debug, thiserror::Error)]
pub enum UnfoldError {
    /// Some faces are not reachable from the first across shared edges.
    #[error("the design has {0} separate pieces; unfold them one at a time")]
    Disconnected(usize),
}

/// The flat layout of `mesh`'s 3D form, aligned to its current crease pattern if any.
pub fn unfold(mesh: &Mesh) -> Result<Vec<Vec2>, UnfoldError> {
    let x = mesh.positions();
    let faces = mesh.faces();
    let topo = mesh.topology();
    let n = x.len();
    let mut placed: Vec<Option<Vec2>> = vec![None; n];
    let mut done = vec![false; faces.len()];
    // Seed: the first face, laid along the x axis.
    let [a, b, c] = faces[0];
    let (lab, lac, lbc) = (
        (x[b] - x[a]).norm(),
        (x[c] - x[a]).norm(),
        (x[c] - x[b]).norm(),
    );
    placed[a] = Some(Vec2::zeros());
    placed[b] = Some(Vec2::new(lab, 0.0));
    placed[c] = Some(apex(Vec2::zeros(), Vec2::new(lab, 0.0), lac, lbc));
    done[0] = true;
    let mut queue = VecDeque::from([0usize]);
    let mut reached = 1;
    while let Some(f) = queue.pop_front() {
        for &e in &topo.face_edges[f] {
            for g in topo.edge_faces[e].iter().flatten().copied() {
                if done[g] {
                    continue;
                }
                done[g] = true;
                reached += 1;
                queue.push_back(g);
                // g = (p, q, r) counter-clockwise; p, q on the shared edge are placed.
                let fg = faces[g];
                let k = (0..3)
                    .find(|&k| {
                        placed[fg[k]].is_some() && placed[fg[(k + 1) % 3]].is_some() && {
                            let [u, v] = mesh.edges()[e].vertices;
                            let (s, t) = (fg[k], fg[(k + 1) % 3]);
                            (s == u && t == v) || (s == v && t == u)
                        }
                    })
                    .expect("shared edge is placed");
                let (p, q, r) = (fg[k], fg[(k + 1) % 3], fg[(k + 2) % 3]);
                if placed[r].is_none() {
                    let (pp, pq) = (placed[p].unwrap(), placed[q].unwrap());
                    placed[r] = Some(apex(pp, pq, (x[r] - x[p]).norm(), (x[r] - x[q]).norm()));
                }
            }
        }
    }
    if reached < faces.len() {
        return Err(UnfoldError::Disconnected(topo.components));
    }
    let mut flat: Vec<Vec2> = placed
        .into_iter()
        .map(|p| p.expect("every vertex is on a face"))
        .collect();
    if let Some(old) = mesh.flat() {
        align(&mut flat, old);
    }
    Ok(flat)
}

/// The third corner of a counter-clockwise triangle on base p→q with sides |pr|, |qr|.
fn apex(p: Vec2, q: Vec2, pr: f64, qr: f64) -> Vec2 {
    let base = q - p;
    let d = base.norm();
    let along = (pr * pr - qr * qr + d * d) / (2.0 * d);
    let up = (pr * pr - along * along).max(0.0).sqrt();
    let u = base / d;
    p + u * along + Vec2::new(-u.y, u.x) * up
}

/// Rotates and translates `flat` onto `target` in the least-squares sense (2D Procrustes).
fn align(flat: &mut [Vec2], target: &[Vec2]) {
    let n = flat.len() as f64;
    let ca = flat.iter().sum::<Vec2>() / n;
    let cb = target.iter().sum::<Vec2>() / n;
    let (mut s, mut c) = (0.0, 0.0);
    for (p, q) in flat.iter().zip(target) {
        let (u, v) = (p - ca, q - cb);
        c += u.dot(&v);
        s += u.perp(&v);
    }
    let angle = s.atan2(c);
    let (sn, cs) = angle.sin_cos();
    for p in flat.iter_mut() {
        let u = *p - ca;
        *p = cb + Vec2::new(cs * u.x - sn * u.y, sn * u.x + cs * u.y);
    }
}

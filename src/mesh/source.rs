//! What a source file had that crease does not model, carried with the mesh so that
//! converting a file loses nothing (FOLD metadata, polygon faces, `faceOrders`, …): an
//! opaque attachment the format's reader makes and its writer reads; the mesh's own
//! fingerprint, to tell whether the file's per-element fields still describe it; and the
//! polygons its synthetic edges join.

use super::{Mesh, Vec2, Vec3};
use std::any::Any;
use std::sync::Arc;

/// What a source file had beyond the mesh, kept with it so that converting a file loses
/// nothing, and opaque to the mesh: the format that read the file attaches its own record
/// (FOLD's is `io::fold::SourceRecord`) and reads it back when writing; the mesh only
/// carries it along (a clone shares it).
#[derive(Clone)]
pub struct SourceAttachment(Arc<dyn Any + Send + Sync>);

impl SourceAttachment {
    /// Attaches a format's record.
    pub fn new<T: Any + Send + Sync>(record: T) -> Self {
        SourceAttachment(Arc::new(record))
    }

    /// The record, if it is a `T` (a file read by another format has another record).
    pub fn get<T: Any>(&self) -> Option<&T> {
        self.0.downcast_ref()
    }
}

impl std::fmt::Debug for SourceAttachment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SourceAttachment(..)")
    }
}

/// Faces and positions of a mesh at one moment.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Fingerprint {
    faces: Vec<[usize; 3]>,
    positions: Vec<Vec3>,
    flat: Option<Vec<Vec2>>,
}

impl Fingerprint {
    /// The mesh's faces and positions now.
    pub fn of(mesh: &Mesh) -> Fingerprint {
        Fingerprint {
            faces: mesh.faces().to_vec(),
            positions: mesh.positions().to_vec(),
            flat: mesh.crease_pattern().map(<[Vec2]>::to_vec),
        }
    }
}

/// Groups of faces joined across synthetic edges (added by crease to triangulate a
/// source polygon) that still lie flat (|fold angle| ≤ `flat_tolerance(e)` radians), each
/// as a polygon: its boundary walked once around, in the faces' winding. A group whose
/// boundary is not one simple loop stays as its triangles. Groups are ordered by their
/// first face, so a file's polygons come back in the file's order.
pub fn polygon_faces(
    mesh: &Mesh,
    fold: &[f64],
    flat_tolerance: impl Fn(usize) -> f64,
) -> Vec<(Vec<usize>, Vec<usize>)> {
    let topo = mesh.topology();
    let n = mesh.faces().len();
    let mut sets = super::UnionFind::new(n);
    for (e, edge) in mesh.edges().iter().enumerate() {
        if !edge.synthetic || fold[e].abs() > flat_tolerance(e) {
            continue;
        }
        if let [Some(a), Some(b)] = topo.edge_faces[e] {
            sets.union(a, b);
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut slot = vec![usize::MAX; n];
    for f in 0..n {
        let r = sets.find(f);
        if slot[r] == usize::MAX {
            slot[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[slot[r]].push(f);
    }
    let mut out = Vec::new();
    for group in groups {
        if group.len() == 1 {
            out.push((mesh.faces()[group[0]].to_vec(), group));
            continue;
        }
        // Half-edges of the group whose twin is not in the group: the boundary.
        let inside = |f: usize| group.contains(&f);
        let mut next = std::collections::HashMap::new();
        let mut half_edges = 0;
        for &f in &group {
            let t = mesh.faces()[f];
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let e = topo.edge_between(a, b).expect("face edges exist");
                let shared = topo.edge_faces[e]
                    .iter()
                    .flatten()
                    .filter(|&&g| inside(g))
                    .count();
                if shared < 2 {
                    next.insert(a, b);
                    half_edges += 1;
                }
            }
        }
        let start = *next.keys().min().expect("a group has a boundary");
        let mut polygon = vec![start];
        let mut at = next[&start];
        while at != start && polygon.len() <= next.len() {
            polygon.push(at);
            at = next[&at];
        }
        if half_edges == next.len() && polygon.len() == next.len() && at == start {
            out.push((polygon, group));
        } else {
            for f in group {
                out.push((mesh.faces()[f].to_vec(), vec![f]));
            }
        }
    }
    out
}

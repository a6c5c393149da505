//! What a source file had that crease does not model, kept with the mesh so that
//! converting a file loses nothing (FOLD metadata, polygon faces, `faceOrders`, …).

use super::{Mesh, Vec2, Vec3};
use serde_json::Value;

/// The parts of a source file carried through unchanged.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct SourceRecord {
    /// The file's faces as it listed them (polygons), before triangulation.
    pub polygons: Vec<Vec<usize>>,
    /// Descriptive fields that stay true whatever happens to the geometry (`file_author`,
    /// `file_description`, `frame_description`, …), by name.
    pub metadata: Vec<(String, Value)>,
    /// Fields indexed by vertex, edge or face, or derived from the geometry (`faceOrders`,
    /// `vertices_flatUnfoldCoords`, …): written back only while the mesh is unchanged.
    pub extras: Vec<(String, Value)>,
    /// The frame unit exactly as given (`None` when the file gave none).
    pub unit: Option<String>,
    /// The file's own `vertices_coords`, `frame_classes` and `frame_attributes`, written
    /// back verbatim while the mesh is unchanged (a flat pattern some tools store in the
    /// xz-plane as "3D" keeps its axes).
    pub frame: Vec<(String, Value)>,
    /// The mesh as imported, to tell whether `extras` still describe it.
    pub imported: Fingerprint,
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
            flat: mesh.flat().map(<[Vec2]>::to_vec),
        }
    }
}

impl SourceRecord {
    /// Whether the per-element `extras` still describe `mesh`: same faces, same positions.
    pub fn describes(&self, mesh: &Mesh) -> bool {
        self.imported == Fingerprint::of(mesh)
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

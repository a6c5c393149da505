//! What a FOLD file has beyond the mesh crease builds from it, read so that writing it
//! back loses nothing: its fields, its coordinates' text, its vertex numbers.

use crate::mesh::{Fingerprint, Mesh, MeshParts, Vec2};
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

impl SourceRecord {
    /// Whether the per-element `extras` still describe `mesh`: same faces, same positions.
    pub fn describes(&self, mesh: &Mesh) -> bool {
        self.imported == Fingerprint::of(mesh)
    }

    /// The FOLD record attached to `mesh`, if it was read from a FOLD file.
    pub fn of(mesh: &Mesh) -> Option<&SourceRecord> {
        mesh.source.as_ref().and_then(|s| s.get::<SourceRecord>())
    }
}

/// The text of every `vertices_coords` array in a FOLD file (a file's rounding shows in
/// its coordinates; fold angles and metadata are written with other precisions). Only a
/// key whose value is an array counts, and each byte is scanned once: a file of many
/// `{"vertices_coords": 0}` before the real array took a copy of that array per key
/// (1.7 GB from 777 kB); the result is never longer than the file.
pub(super) fn coordinate_arrays(text: &str) -> String {
    let mut out = String::new();
    let mut scanned = 0;
    for (at, key) in text.match_indices("\"vertices_coords\"") {
        if at < scanned {
            continue;
        }
        let rest = &text[at + key.len()..];
        let after_colon = rest.trim_start().strip_prefix(':').map(str::trim_start);
        let Some(array) = after_colon.filter(|r| r.starts_with('[')) else {
            continue;
        };
        let start = text.len() - array.len();
        let mut depth = 0;
        let mut end = text.len();
        for (k, c) in array.char_indices() {
            match c {
                '[' => depth += 1,
                ']' => depth -= 1,
                _ => {}
            }
            if depth == 0 {
                end = start + k + 1;
                break;
            }
        }
        out.push_str(&text[start..end]);
        out.push(' ');
        scanned = end;
    }
    out
}

/// Gives the vertices of a mesh rebuilt from a file's edges (an edges-only FOLD) the
/// file's own numbers: FOLD identifies vertices by index, so a vertex found at a file
/// vertex's position takes its index, and points the rebuild added (crossings) follow.
pub(super) fn keep_file_numbering(mut parts: MeshParts, file: &[Vec2]) -> MeshParts {
    let Some(points) = parts.flat.take() else {
        return parts;
    };
    let key = |p: &Vec2| (p.x.to_bits(), p.y.to_bits());
    let by_position: std::collections::HashMap<_, usize> =
        file.iter().enumerate().map(|(i, p)| (key(p), i)).collect();
    let mut next = file.len();
    let mut taken = vec![false; file.len()];
    let map: Vec<usize> = points
        .iter()
        .map(|p| match by_position.get(&key(p)) {
            Some(&i) if !taken[i] => {
                taken[i] = true;
                i
            }
            _ => {
                next += 1;
                next - 1
            }
        })
        .collect();
    // File vertices no edge uses do not exist in the rebuilt mesh: close the gaps.
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by_key(|&k| map[k]);
    let mut compact = vec![0; points.len()];
    for (new, &k) in order.iter().enumerate() {
        compact[k] = new;
    }
    let mut flat = vec![Vec2::zeros(); points.len()];
    for (k, p) in points.into_iter().enumerate() {
        flat[compact[k]] = p;
    }
    for f in &mut parts.faces {
        *f = f.map(|v| compact[v]);
    }
    for e in &mut parts.edges {
        e.vertices = e.vertices.map(|v| compact[v]);
    }
    parts.flat = Some(flat);
    parts
}

/// Top-level fields crease reads itself; everything else is carried through.
const MODELLED: [&str; 19] = [
    "file_spec",
    "file_creator",
    "file_classes",
    "file_frames",
    "frame_title",
    "frame_classes",
    "frame_attributes",
    "frame_unit",
    "vertices_coords",
    "edges_vertices",
    "edges_assignment",
    "edges_foldAngle",
    "faces_vertices",
    "crease:targetAngle",
    "crease:alpha",
    "crease:lockTopology",
    "crease:coincidentVertices",
    "crease:coordinatePrecision",
    "crease:curves",
];

/// The top-level fields a source record keeps (those crease does not model, and frame
/// 0's coordinates, classes and attributes), in the order of their names as a JSON
/// object holds them, the last of a repeated name winning. The modelled fields — the bulk
/// of a large file — are skipped without being parsed into a tree.
struct Unmodelled(Vec<(String, serde_json::Value)>);

impl<'de> serde::Deserialize<'de> for Unmodelled {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Fields;
        impl<'de> serde::de::Visitor<'de> for Fields {
            type Value = Unmodelled;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a FOLD object")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<Unmodelled, A::Error> {
                let mut kept = std::collections::BTreeMap::new();
                while let Some(name) = map.next_key::<String>()? {
                    let wanted = matches!(
                        name.as_str(),
                        "vertices_coords" | "frame_classes" | "frame_attributes"
                    ) || !MODELLED.contains(&name.as_str());
                    if wanted {
                        kept.insert(name, map.next_value::<serde_json::Value>()?);
                    } else {
                        map.next_value::<serde::de::IgnoredAny>()?;
                    }
                }
                Ok(Unmodelled(kept.into_iter().collect()))
            }
        }
        d.deserialize_map(Fields)
    }
}

/// What the file has beyond the mesh: its polygons, its descriptive `file_*`/`frame_*`
/// fields, its other fields (kept while the geometry is unchanged) and its unit.
pub(super) fn source_record(
    text: &str,
    mesh: &Mesh,
    polygons: Vec<Vec<usize>>,
    unit: Option<String>,
) -> SourceRecord {
    let mut record = SourceRecord {
        polygons,
        unit,
        imported: Fingerprint::of(mesh),
        ..Default::default()
    };
    if let Ok(Unmodelled(fields)) = serde_json::from_str(text) {
        for (name, value) in fields {
            if matches!(
                name.as_str(),
                "vertices_coords" | "frame_classes" | "frame_attributes"
            ) {
                record.frame.push((name, value));
                continue;
            }
            if MODELLED.contains(&name.as_str()) {
                continue;
            }
            if name.starts_with("file_") || name.starts_with("frame_") {
                record.metadata.push((name, value));
            } else {
                record.extras.push((name, value));
            }
        }
    }
    // Vertices renumbered on import (cut lines split, unused vertices dropped): the file's
    // per-vertex fields and coordinates no longer line up with the mesh.
    let listed = record
        .frame
        .iter()
        .find(|(n, _)| n == "vertices_coords")
        .and_then(|(_, v)| v.as_array().map(Vec::len));
    if listed != Some(mesh.vertex_count()) {
        record.frame.clear();
        record.extras.clear();
    }
    record
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coordinate_arrays_take_each_array_once_and_skip_keys_that_are_not_arrays() {
        let real = "[[0.5,1],[2,3.25]]";
        let mut text = String::from("{\"x\": [");
        for _ in 0..1000 {
            text.push_str("{\"vertices_coords\": 0},");
        }
        text.push_str(&format!(
            "1], \"vertices_coords\" : {real}, \"f\": [{{\"vertices_coords\":[[7]]}}]}}"
        ));
        let arrays = coordinate_arrays(&text);
        assert_eq!(arrays, format!("{real} [[7]] "));
        assert!(arrays.len() <= text.len());
    }
}

//! FOLD 1.1 (JSON). Frame 0 holds the 3D folded form (or, as other tools write it, the
//! crease pattern, the folded form in a later frame: the last one is read); a
//! `creasePattern` frame holds the flat positions of the same vertices. Angles on disk are FOLD's: degrees, valley
//! positive. This module is the one place where they are converted to the paper's radians.

use super::planar::{mesh_from_segments, Segment};
use super::FileCause;
use crate::mesh::{
    split_along_cuts, triangulate_polygon, Assignment, Edge, Mesh, MeshParts, SourceAttachment,
    TriangulationBudget, Vec2, Vec3,
};
use serde::Deserialize;
use source::{coordinate_arrays, keep_file_numbering, source_record};

mod seam;
mod source;
mod write;
pub use source::SourceRecord;
pub use write::{
    motion_to_string, to_string, to_string_crease_pattern_first, to_string_with_orders,
};

/// FOLD degrees (valley positive) to paper radians (mountain positive).
pub fn angle_from_fold(degrees: f64) -> f64 {
    -degrees.to_radians()
}

/// Paper radians (mountain positive) to FOLD degrees (valley positive).
pub fn angle_to_fold(radians: f64) -> f64 {
    let d = -radians.to_degrees();
    if d == 0.0 {
        0.0 // never write -0
    } else {
        d
    }
}

#[derive(Deserialize, Default, Clone)]
struct Frame {
    frame_title: Option<String>,
    frame_classes: Option<Vec<String>>,
    frame_unit: Option<String>,
    frame_inherit: Option<bool>,
    frame_parent: Option<usize>,
    vertices_coords: Option<Vec<Vec<f64>>>,
    edges_vertices: Option<Vec<[usize; 2]>>,
    edges_assignment: Option<Vec<String>>,
    #[serde(rename = "edges_foldAngle")]
    edges_fold_angle: Option<Vec<Option<f64>>>,
    faces_vertices: Option<Vec<Vec<usize>>>,
    #[serde(rename = "crease:targetAngle")]
    target_angle: Option<Vec<Option<f64>>>,
    #[serde(rename = "crease:alpha")]
    alpha: Option<Vec<f64>>,
    #[serde(rename = "crease:lockTopology")]
    lock_topology: Option<bool>,
    #[serde(rename = "crease:coordinatePrecision")]
    coordinate_precision: Option<f64>,
    #[serde(rename = "crease:coincidentVertices")]
    coincident: Option<Vec<Vec<usize>>>,
    #[serde(
        rename = "faceOrders",
        default,
        deserialize_with = "bounded_face_orders"
    )]
    face_orders: Option<Vec<serde_json::Value>>,
    #[serde(rename = "crease:seam")]
    seam: Option<Vec<seam::SeamEntry>>,
}

impl Frame {
    fn inherit_from(&mut self, parent: &Frame) {
        macro_rules! take {
            ($($f:ident),*) => { $( if self.$f.is_none() { self.$f = parent.$f.clone(); } )* };
        }
        take!(
            frame_unit,
            vertices_coords,
            edges_vertices,
            edges_assignment,
            edges_fold_angle,
            faces_vertices,
            target_angle,
            alpha
        );
    }

    fn has_class(&self, class: &str) -> bool {
        self.frame_classes
            .as_ref()
            .is_some_and(|c| c.iter().any(|x| x == class))
    }
}

/// The file's own fields beyond frame 0's. Read in a pass of its own over the text, as
/// frame 0 is: `#[serde(flatten)]` would first buffer the whole file as an untyped tree
/// (460 MB for a 25 MB file of 90k vertices), where two typed passes skip what they do
/// not model without building anything.
#[derive(Deserialize)]
struct FileFields {
    file_title: Option<String>,
    file_frames: Option<Vec<Frame>>,
}

pub(crate) fn unit_scale(unit: Option<&str>) -> Result<f64, String> {
    Ok(match unit.unwrap_or("unit") {
        "unit" | "mm" => 1.0,
        "cm" => 10.0,
        "m" => 1000.0,
        "in" => 25.4,
        "pt" => 25.4 / 72.0,
        "um" => 1e-3,
        "nm" => 1e-6,
        other => {
            return Err(format!(
                "unknown frame_unit \"{}\"",
                crate::limits::short_text(other)
            ))
        }
    })
}

/// Coordinates of a frame as 3D points in mm.
fn coords(frame: &Frame) -> Result<Vec<Vec3>, String> {
    let scale = unit_scale(frame.frame_unit.as_deref())?;
    let raw = frame.vertices_coords.as_ref().ok_or("no vertices_coords")?;
    raw.iter()
        .enumerate()
        .map(|(i, c)| {
            if c.len() < 2 || c.len() > 3 {
                return Err(format!(
                    "vertex {i} has {} coordinates (expected 2 or 3)",
                    c.len()
                ));
            }
            if c.len() != raw[0].len() {
                return Err(format!(
                    "vertex {i} has {} coordinates but vertex 0 has {}: a frame is 2D or 3D throughout",
                    c.len(),
                    raw[0].len()
                ));
            }
            Ok(Vec3::new(c[0], c[1], c.get(2).copied().unwrap_or(0.0)) * scale)
        })
        .collect()
}

/// The flat layout of a planar frame, keeping the given faces counter-clockwise when they
/// all agree; `None` if the frame is not planar or its faces overlap (a flat-folded form).
fn planar_layout(points: &[Vec3], faces: &[Vec<usize>]) -> Option<Vec<Vec2>> {
    let (lo, hi) = crate::mesh::bounds(points);
    let extent = hi - lo;
    let tol = 1e-9 * extent.norm().max(f64::MIN_POSITIVE);
    // Prefer an exact axis-aligned plane: coordinates are copied, not recomputed.
    let axis = (0..3).rev().find(|&k| extent[k] <= tol)?;
    let (i, j) = match axis {
        2 => (0, 1),
        1 => (0, 2),
        _ => (1, 2),
    };
    let mut flat: Vec<Vec2> = points.iter().map(|p| Vec2::new(p[i], p[j])).collect();
    let signs: Vec<f64> = faces
        .iter()
        .filter(|f| f.len() >= 3 && f.iter().all(|&v| v < flat.len()))
        .map(|f| {
            (0..f.len())
                .map(|k| flat[f[k]].perp(&flat[f[(k + 1) % f.len()]]))
                .sum::<f64>()
        })
        .collect();
    let positive = signs.iter().filter(|&&s| s > 0.0).count();
    let negative = signs.iter().filter(|&&s| s < 0.0).count();
    if positive > 0 && negative > 0 {
        return None;
    }
    if negative > 0 {
        for p in &mut flat {
            p.y = -p.y;
        }
    }
    Some(flat)
}

/// Parses FOLD text into a mesh. Errors are causes without the file name.
pub fn parse(text: &str) -> Result<Mesh, FileCause> {
    parse_noting(text, &mut Vec::new())
}

/// [`parse`], adding to `notes` what reading changed (faces rebuilt from the edges).
pub fn parse_noting(text: &str, notes: &mut Vec<String>) -> Result<Mesh, FileCause> {
    if text.trim().is_empty() {
        return Err("the file is empty".into());
    }
    let frame: Frame = serde_json::from_str(text).map_err(FileCause::Json)?;
    let file: FileFields = serde_json::from_str(text).map_err(FileCause::Json)?;
    let file_title = file.file_title;
    let frames = frames_of(frame, file.file_frames.unwrap_or_default())?;
    let top = &frames[0];
    let face_lists = top.faces_vertices.clone().unwrap_or_default();
    check_face_orders(top.face_orders.as_deref(), face_lists.len())?;
    let (flat, folded) = layouts(&frames, &face_lists)?;
    let n = flat
        .as_ref()
        .map(|f| f.len())
        .or(folded.as_ref().map(|f| f.len()))
        .ok_or("no vertices_coords in any frame")?;
    let edges = read_edges(top, n)?;
    check_face_sides(&face_lists, &edges, n)?;
    let title = top.frame_title.clone().or(file_title).unwrap_or_default();
    let (mut parts, rebuilt) = mesh_parts(&face_lists, edges, flat, folded, n)?;
    if let Some(why) = &rebuilt {
        notes.push(format!(
            "faces_vertices: {why}; the faces were rebuilt from the edges (vertex numbers kept where the edges meet)"
        ));
    }
    // Faces rebuilt from the edges are written back as found, not as the file listed them.
    let face_lists = if rebuilt.is_some() {
        Vec::new()
    } else {
        face_lists
    };
    let mut tube_seam = None;
    if let Some(entries) = top.seam.as_deref() {
        let (tube, seam) = seam::close(parts, entries)?;
        (parts, tube_seam) = (tube, Some(seam));
    }
    split_along_cuts(&mut parts);
    let mut mesh = Mesh::new(parts)?;
    // The file's own rounding, or the rounding of the file it was converted from as
    // recorded (`crease:coordinatePrecision`, in the frame's unit), whichever is coarser.
    let scale = unit_scale(top.frame_unit.as_deref())?;
    let recorded = match top.coordinate_precision {
        Some(p) => {
            crate::limits::COORDINATE_PRECISION.check("crease:coordinatePrecision", p * scale)?
        }
        None => 0.0,
    };
    let quantum = super::decimal_quantum(&coordinate_arrays(text)) * scale;
    mesh.coordinate_precision = super::rounding_of(&mesh, quantum).max(recorded);
    mesh.title = title;
    mesh.lock_topology = top.lock_topology.unwrap_or(false);
    let groups = top.coincident.clone().unwrap_or_default();
    if !groups.is_empty() && face_lists.is_empty() {
        // Faces are rebuilt from the segments then, renumbering the vertices.
        return Err("crease:coincidentVertices needs faces_vertices".into());
    }
    mesh.coincident = read_groups(groups, n)?;
    if let Some(seam) = tube_seam {
        if !mesh.is_tube() {
            return Err("crease:seam does not close the strip into a tube".into());
        }
        mesh.seam = seam;
        mesh.seam_edges()?;
        // The file describes the strip; the tube is written back from its own geometry.
        return Ok(mesh);
    }
    mesh.source = Some(SourceAttachment::new(source_record(
        text,
        &mesh,
        face_lists,
        top.frame_unit.clone(),
    )));
    Ok(mesh)
}

/// Every side of every listed face must be a listed edge, when the file lists edges:
/// the crease a side stands for, and its assignment, come from `edges_vertices` and
/// `edges_assignment`, so a side missing there means the two lists disagree (an edge
/// shuffled or dropped), and reading on would quietly make that crease flat. (An edge
/// that bounds no face is refused by the mesh; an edge marked B between two faces is a
/// cut, the rule for slits.)
fn check_face_sides(faces: &[Vec<usize>], edges: &[Edge], n: usize) -> Result<(), String> {
    if edges.is_empty() {
        return Ok(());
    }
    let listed: std::collections::HashSet<(usize, usize)> = edges
        .iter()
        .map(|e| {
            let [a, b] = e.vertices;
            (a.min(b), a.max(b))
        })
        .collect();
    for (f, face) in faces.iter().enumerate() {
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            // A vertex out of range is reported as such when the faces are read.
            if a < n && b < n && !listed.contains(&(a.min(b), a.max(b))) {
                return Err(format!(
                    "face {f}'s side {a}–{b} is not in edges_vertices: the faces and edges disagree \
                     (every side of a face must be listed as an edge, with its assignment)"
                ));
            }
        }
    }
    Ok(())
}

/// `faceOrders` read entry by entry, refused past [`crate::limits::MAX_FACE_ORDERS`]
/// before the next is held (10⁷ entries took 1.7 GB as a list of JSON values).
fn bounded_face_orders<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Option<Vec<serde_json::Value>>, D::Error> {
    struct Orders;
    impl<'de> serde::de::Visitor<'de> for Orders {
        type Value = Option<Vec<serde_json::Value>>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a list of [f, g, s] triples")
        }
        fn visit_unit<E>(self) -> Result<Self::Value, E> {
            Ok(None)
        }
        fn visit_seq<A: serde::de::SeqAccess<'de>>(
            self,
            mut seq: A,
        ) -> Result<Self::Value, A::Error> {
            let cap = crate::limits::MAX_FACE_ORDERS;
            let mut orders = Vec::new();
            while let Some(order) = seq.next_element::<serde_json::Value>()? {
                if orders.len() == cap {
                    return Err(serde::de::Error::custom(format!(
                        "faceOrders has more than {cap} entries, more than crease reads"
                    )));
                }
                orders.push(order);
            }
            Ok(Some(orders))
        }
    }
    d.deserialize_any(Orders)
}

/// FOLD `faceOrders`: triples `[f, g, s]` of two different listed faces and s ∈ {−1, 0,
/// +1}. They are copied through on writing, so a bad one is refused here.
fn check_face_orders(orders: Option<&[serde_json::Value]>, faces: usize) -> Result<(), String> {
    for (k, order) in orders.unwrap_or_default().iter().enumerate() {
        let triple = order.as_array().filter(|t| t.len() == 3);
        let ints: Option<Vec<i64>> = triple.and_then(|t| t.iter().map(|x| x.as_i64()).collect());
        let shown: String = order.to_string().chars().take(40).collect();
        let bad = |why: String| Err(format!("faceOrders[{k}] = {shown}: {why}"));
        let Some([f, g, s]) = ints.as_deref().map(|v| [v[0], v[1], v[2]]) else {
            return bad("not three whole numbers [f, g, s]".into());
        };
        for face in [f, g] {
            if face < 0 || face as usize >= faces {
                return bad(format!(
                    "face {face} is not one of the file's {faces} faces"
                ));
            }
        }
        if f == g || !(-1..=1).contains(&s) {
            return bad("needs two different faces and s of -1, 0 or 1".into());
        }
    }
    Ok(())
}

/// The file's frames, frame 0 (the file's own) first, each inheriting what it says from
/// its parent.
fn frames_of(frame: Frame, file_frames: Vec<Frame>) -> Result<Vec<Frame>, String> {
    let mut frames = vec![frame];
    for (k, f) in file_frames.into_iter().enumerate() {
        if f.frame_inherit == Some(true) {
            let parent = f.frame_parent.unwrap_or(0);
            if parent >= frames.len() {
                return Err(format!(
                    "frame {} inherits from missing frame {parent}",
                    k + 1
                ));
            }
        }
        frames.push(f);
    }
    Ok(frames)
}

/// The frame a frame inherits from, if it does (always an earlier one: checked by
/// [`frames_of`], so walking up ends).
fn parent_of(frames: &[Frame], k: usize) -> Option<usize> {
    let f = &frames[k];
    (k > 0 && f.frame_inherit == Some(true)).then(|| f.frame_parent.unwrap_or(0))
}

/// Whether frame `k`, with what it inherits, has vertex coordinates.
fn has_coords(frames: &[Frame], k: usize) -> bool {
    let mut at = Some(k);
    while let Some(i) = at {
        if frames[i].vertices_coords.is_some() {
            return true;
        }
        at = parent_of(frames, i);
    }
    false
}

/// Frame `k` with what it inherits filled in. Frames are resolved only when used, and a
/// field is copied at most once: a file of thousands of inheriting frames over a large
/// one cost a copy of it per frame (2 GB from 462 kB).
fn resolved(frames: &[Frame], k: usize) -> Frame {
    let mut frame = frames[k].clone();
    let mut at = parent_of(frames, k);
    while let Some(i) = at {
        frame.inherit_from(&frames[i]);
        at = parent_of(frames, i);
    }
    frame
}

/// A file's crease pattern (flat, in the plane) and folded form, each if it has one.
type Layouts = (Option<Vec<Vec2>>, Option<Vec<Vec3>>);

/// The crease pattern and the folded form the frames hold.
fn layouts(frames: &[Frame], face_lists: &[Vec<usize>]) -> Result<Layouts, String> {
    let with_coords = |k: &usize| has_coords(frames, *k);
    let cp_frame = (0..frames.len())
        .filter(with_coords)
        .find(|&k| frames[k].has_class("creasePattern"))
        .map(|k| resolved(frames, k));
    // The last folded frame with coordinates of its own: a design (crease's own order,
    // or the crease pattern first as other tools want) has one, and a motion (`crease
    // animate`, ORIPA's folded states) ends at its folded form. A folded frame that only
    // inherits its coordinates says nothing new; the first such is read when no frame
    // has its own.
    let folded = |k: &usize| !frames[*k].has_class("creasePattern");
    let folded_frame = (0..frames.len())
        .filter(|&k| frames[k].vertices_coords.is_some())
        .rfind(folded)
        .or_else(|| (0..frames.len()).filter(with_coords).find(folded))
        .map(|k| resolved(frames, k));
    let mut flat: Option<Vec<Vec2>> = None;
    let mut folded: Option<Vec<Vec3>> = None;
    if let Some(f) = &cp_frame {
        let p = coords(f)?;
        match planar_layout(&p, face_lists) {
            Some(layout) => flat = Some(layout),
            None => folded = Some(p),
        }
    }
    if let Some(f) = &folded_frame {
        let p = coords(f)?;
        // A "folded form" lying flat without overlaps is a crease pattern (cube-cp.fold,
        // Origami Simulator's exports); one with overlapping faces is flat-folded.
        match (flat.is_none(), planar_layout(&p, face_lists)) {
            (true, Some(layout)) => flat = Some(layout),
            _ => folded = Some(p),
        }
    }
    Ok((flat, folded))
}

/// Faces triangulated from `faces_vertices`, or, for an edges-only file, found from the
/// crease pattern's segments (keeping the file's vertex numbers). A crease pattern whose
/// listed faces cannot be triangulated (a face running along itself, as drawing tools
/// write where edges overlap) has its faces found from the edges too, as Flat-Folder
/// does: the second value says why.
fn mesh_parts(
    face_lists: &[Vec<usize>],
    edges: Vec<Edge>,
    flat: Option<Vec<Vec2>>,
    folded: Option<Vec<Vec3>>,
    n: usize,
) -> Result<(MeshParts, Option<String>), String> {
    if face_lists.is_empty() {
        let flat = flat.ok_or("edges-only FOLD files need a flat crease pattern to find faces")?;
        return Ok((faces_from_edges(&edges, &flat)?, None));
    }
    let mut faces = Vec::with_capacity(face_lists.len());
    let mut budget = TriangulationBudget::default();
    for (i, poly) in face_lists.iter().enumerate() {
        // Past the budget the file is refused, not rebuilt from its edges: that would
        // clip the same face again.
        budget
            .charge(poly.len())
            .map_err(|why| format!("face {i}: {why}"))?;
        if let Some(&v) = poly.iter().find(|&&v| v >= n) {
            return Err(format!(
                "face {i} refers to vertex {v}, but there are only {n} vertices"
            ));
        }
        if let Err(why) = triangulate_face(i, poly, flat.as_deref(), folded.as_deref(), &mut faces)
        {
            return match (&flat, &folded) {
                (Some(f), None) => Ok((faces_from_edges(&edges, f)?, Some(why))),
                _ => Err(why),
            };
        }
    }
    let parts = MeshParts {
        positions: folded,
        flat,
        faces,
        edges,
    };
    Ok((parts, None))
}

/// The faces of the planar arrangement of a crease pattern's edges.
fn faces_from_edges(edges: &[Edge], flat: &[Vec2]) -> Result<MeshParts, String> {
    let segments: Vec<Segment> = edges
        .iter()
        .map(|e| Segment {
            a: flat[e.vertices[0]],
            b: flat[e.vertices[1]],
            assignment: e.assignment,
            fold_angle: e.fold_angle,
        })
        .collect();
    Ok(keep_file_numbering(mesh_from_segments(&segments)?.0, flat))
}

/// `crease:coincidentVertices`: disjoint groups of at least two existing vertices.
fn read_groups(groups: Vec<Vec<usize>>, n: usize) -> Result<Vec<Vec<usize>>, String> {
    let mut seen = vec![false; n];
    for (i, g) in groups.iter().enumerate() {
        if g.len() < 2 {
            return Err(format!(
                "crease:coincidentVertices group {i} has {} vertex; a group needs two or more",
                g.len()
            ));
        }
        for &v in g {
            if v >= n {
                return Err(format!(
                    "crease:coincidentVertices group {i} refers to vertex {v}, but there are only {n} vertices"
                ));
            }
            if std::mem::replace(&mut seen[v], true) {
                return Err(format!(
                    "crease:coincidentVertices lists vertex {v} twice (group {i})"
                ));
            }
        }
    }
    Ok(groups)
}

fn read_edges(frame: &Frame, n: usize) -> Result<Vec<Edge>, String> {
    let ev = frame.edges_vertices.clone().unwrap_or_default();
    let m = ev.len();
    let check_len = |name: &str, len: Option<usize>| match len {
        Some(l) if l != m => Err(format!("{name} has {l} entries but edges_vertices has {m}")),
        _ => Ok(()),
    };
    check_len(
        "edges_assignment",
        frame.edges_assignment.as_ref().map(Vec::len),
    )?;
    check_len(
        "edges_foldAngle",
        frame.edges_fold_angle.as_ref().map(Vec::len),
    )?;
    check_len(
        "crease:targetAngle",
        frame.target_angle.as_ref().map(Vec::len),
    )?;
    check_len("crease:alpha", frame.alpha.as_ref().map(Vec::len))?;
    let mut edges = Vec::with_capacity(m);
    for (i, &[a, b]) in ev.iter().enumerate() {
        if let Some(&v) = [a, b].iter().find(|&&v| v >= n) {
            return Err(format!(
                "edge {i} refers to vertex {v}, but there are only {n} vertices"
            ));
        }
        let fold = frame
            .edges_fold_angle
            .as_ref()
            .and_then(|f| f[i])
            .map(angle_from_fold);
        let assignment = match frame.edges_assignment.as_ref() {
            Some(list) => Assignment::from_fold(&list[i]).ok_or_else(|| {
                format!(
                    "edge {i} has unknown assignment \"{}\"",
                    crate::limits::short_text(&list[i])
                )
            })?,
            None => match fold {
                Some(r) if r > 0.0 => Assignment::Mountain,
                Some(r) if r < 0.0 => Assignment::Valley,
                _ => Assignment::Unassigned,
            },
        };
        let mut e = Edge::new(a, b, assignment);
        if let Some(r) = fold {
            e.fold_angle = r;
        }
        if let Some(t) = frame.target_angle.as_ref().and_then(|t| t[i]) {
            e.target = angle_from_fold(t);
        }
        if let Some(al) = frame.alpha.as_ref() {
            e.alpha = al[i];
        }
        edges.push(e);
    }
    Ok(edges)
}

/// Splits a polygon face into triangles with flat creases, in the crease pattern when
/// known, else in the polygon's own plane.
fn triangulate_face(
    index: usize,
    poly: &[usize],
    flat: Option<&[Vec2]>,
    folded: Option<&[Vec3]>,
    out: &mut Vec<[usize; 3]>,
) -> Result<(), String> {
    if poly.len() < 3 {
        return Err(format!("face {index} has {} vertices", poly.len()));
    }
    if poly.len() == 3 {
        out.push([poly[0], poly[1], poly[2]]);
        return Ok(());
    }
    let corners: Vec<Vec2> = match (flat, folded) {
        (Some(f), _) => poly.iter().map(|&v| f[v]).collect(),
        (None, Some(p)) => {
            let pts: Vec<Vec3> = poly.iter().map(|&v| p[v]).collect();
            // Newell's normal, then any orthonormal basis of its plane.
            let mut normal = Vec3::zeros();
            for k in 0..pts.len() {
                normal += pts[k].cross(&pts[(k + 1) % pts.len()]);
            }
            let normal = normal
                .try_normalize(0.0)
                .ok_or(format!("face {index} is degenerate"))?;
            let helper = if normal.x.abs() < 0.9 {
                Vec3::x()
            } else {
                Vec3::y()
            };
            let u = normal.cross(&helper).normalize();
            let w = normal.cross(&u);
            pts.iter()
                .map(|q| Vec2::new(q.dot(&u), q.dot(&w)))
                .collect()
        }
        (None, None) => unreachable!("positions were checked"),
    };
    let tris = triangulate_polygon(&corners, 0.0).ok_or_else(|| {
        format!("face {index} cannot be triangulated (degenerate or self-intersecting)")
    })?;
    // Keep the file's winding: ear clipping returns counter-clockwise triangles.
    let ccw = (0..corners.len())
        .map(|k| corners[k].perp(&corners[(k + 1) % corners.len()]))
        .sum::<f64>()
        > 0.0;
    for t in tris {
        let t = [poly[t[0]], poly[t[1]], poly[t[2]]];
        out.push(if ccw { t } else { [t[0], t[2], t[1]] });
    }
    Ok(())
}

//! glTF 2.0 of a folding motion (issue 49): the sheet's triangles twice, front and back
//! of the paper each in its own colour (one-sided materials, the back wound the other
//! way), the creases as lines in their colours, and the motion as morph targets.
//!
//! Why morph targets and not a node per rigid panel: a path may bend its panels (the
//! square twist does), which node transforms cannot show; morph targets carry any
//! motion, and every viewer that plays glTF animation (Blender, three.js, model-viewer)
//! plays them. Frame k > 0 is target k − 1, the displacement from frame 0; the animation
//! weights one target at each key time and interpolates linearly between two keys, which
//! is the straight blend of the two frames' positions.
//!
//! Positions are single-precision millimetres about the sheet's centre (the mesh node's
//! translation holds the centre in double precision), under a root node that turns
//! crease's z-up millimetres into glTF's y-up metres. No normals are written: glTF
//! clients compute flat normals, which is what folded paper has.

use crate::fab::LineKind;
use crate::mesh::{Mesh, Vec3};
use nalgebra::{UnitQuaternion, Vector3};
use serde_json::{json, Value};

/// Seconds between two frames of the animation.
pub const SECONDS_PER_FRAME: f64 = 1.0 / 15.0;

/// The front of the paper (sRGB), the colour of the previews' paper.
pub const FRONT_RGB: [u8; 3] = [241, 231, 208];
/// The back of the paper (sRGB): a light blue, so the sides tell apart as a flap turns.
pub const BACK_RGB: [u8; 3] = [176, 202, 226];

/// A motion to write: the sheet's faces and edges, and its positions frame by frame.
pub struct MotionFrames<'a> {
    /// The sheet (faces, edges and their kinds; its positions are not read).
    pub sheet: &'a Mesh,
    /// Every vertex's position in each frame (mm); frame 0 is the base.
    pub frames: &'a [Vec<Vec3>],
}

/// The motion as a binary glTF (`.glb`).
pub fn glb(motion: &MotionFrames) -> Result<Vec<u8>, String> {
    let (document, bin) = build(motion, None)?;
    let mut json = serde_json::to_vec(&document).map_err(|e| e.to_string())?;
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let total =
        u32::try_from(total).map_err(|_| "the motion is larger than a .glb holds (4 GB)")?;
    let mut out = Vec::with_capacity(total as usize);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    Ok(out)
}

/// The motion as a `.gltf` document whose buffer is the file `bin_name` beside it, and
/// that buffer's bytes.
pub fn gltf(motion: &MotionFrames, bin_name: &str) -> Result<(String, Vec<u8>), String> {
    let (document, bin) = build(motion, Some(bin_name))?;
    let text = serde_json::to_string_pretty(&document).map_err(|e| e.to_string())?;
    Ok((text, bin))
}

/// The binary buffer and the accessors and views over it, as they are added.
#[derive(Default)]
struct Buffer {
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

/// glTF's component types and buffer-view targets.
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

impl Buffer {
    /// A view over `bytes`, aligned to 4, with an optional target; its index.
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        let mut view = json!({
            "buffer": 0,
            "byteOffset": self.bytes.len(),
            "byteLength": bytes.len(),
        });
        if let Some(t) = target {
            view["target"] = json!(t);
        }
        self.bytes.extend_from_slice(bytes);
        self.views.push(view);
        self.views.len() - 1
    }

    /// A VEC3 float accessor over `points` with its bounds (glTF requires them for
    /// positions and their targets); its index.
    fn vec3(&mut self, points: &[[f32; 3]]) -> usize {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        let mut bytes = Vec::with_capacity(points.len() * 12);
        for p in points {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
                bytes.extend_from_slice(&p[k].to_le_bytes());
            }
        }
        let view = self.view(&bytes, Some(ARRAY_BUFFER));
        self.accessor(json!({
            "bufferView": view,
            "componentType": FLOAT,
            "count": points.len(),
            "type": "VEC3",
            "min": lo,
            "max": hi,
        }))
    }

    /// An index accessor; its index.
    fn indices(&mut self, indices: &[u32]) -> usize {
        let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(ELEMENT_ARRAY_BUFFER));
        self.accessor(json!({
            "bufferView": view,
            "componentType": UNSIGNED_INT,
            "count": indices.len(),
            "type": "SCALAR",
        }))
    }

    /// A float accessor for animation data (`times` with its bounds); its index.
    fn floats(&mut self, values: &[f32], bounds: bool) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, None);
        let mut accessor = json!({
            "bufferView": view,
            "componentType": FLOAT,
            "count": values.len(),
            "type": "SCALAR",
        });
        if bounds {
            let lo = values.iter().copied().fold(f32::INFINITY, f32::min);
            let hi = values.iter().copied().fold(f32::NEG_INFINITY, f32::max);
            accessor["min"] = json!([lo]);
            accessor["max"] = json!([hi]);
        }
        self.accessor(accessor)
    }

    fn accessor(&mut self, accessor: Value) -> usize {
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }
}

/// A material of one flat colour, one-sided (`double_sided` for lines).
fn material(name: &str, rgb: [u8; 3], double_sided: bool) -> Value {
    let linear = rgb.map(|c| srgb_to_linear(f64::from(c) / 255.0));
    json!({
        "name": name,
        "pbrMetallicRoughness": {
            "baseColorFactor": [linear[0], linear[1], linear[2], 1.0],
            "metallicFactor": 0.0,
            "roughnessFactor": 0.9,
        },
        "doubleSided": double_sided,
    })
}

/// glTF's colour factors are linear; the colours crease names are sRGB.
fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The document and its binary buffer (named `uri` when it is a file beside it).
fn build(motion: &MotionFrames, uri: Option<&str>) -> Result<(Value, Vec<u8>), String> {
    let sheet = motion.sheet;
    let frames = motion.frames;
    if frames.is_empty() {
        return Err("a motion needs at least one frame".into());
    }
    let n = sheet.vertex_count();
    if frames.iter().any(|f| f.len() != n) {
        return Err("every frame must place every vertex of the sheet".into());
    }
    let centre = centre_of(frames);
    let mut buffer = Buffer::default();
    let (position, targets) = positions_and_targets(&mut buffer, frames, centre);
    let (primitives, materials) = sheet_primitives(&mut buffer, sheet, position, &targets);
    let animations: Vec<Value> = weight_animation(&mut buffer, frames.len(), targets.len())
        .into_iter()
        .collect();

    let mut mesh = json!({ "name": "sheet", "primitives": primitives });
    if !targets.is_empty() {
        mesh["weights"] = json!(vec![0.0; targets.len()]);
    }
    let (camera, camera_node) = default_camera(frames, centre);
    let mut buffer_entry = json!({ "byteLength": buffer.bytes.len() });
    if let Some(uri) = uri {
        buffer_entry["uri"] = json!(uri);
    }
    let title = if sheet.title.is_empty() {
        "crease folding motion".to_string()
    } else {
        sheet.title.clone()
    };
    let document = json!({
        "asset": { "version": "2.0", "generator": "crease" },
        "scene": 0,
        "scenes": [{ "name": title, "nodes": [0, 2] }],
        "nodes": [
            {
                "name": "z-up millimetres to y-up metres",
                // −90° about x takes z to y; 1 mm is 0.001 m.
                "rotation": [-std::f64::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f64::consts::FRAC_1_SQRT_2],
                "scale": [0.001, 0.001, 0.001],
                "children": [1],
            },
            {
                "name": "sheet",
                "mesh": 0,
                "translation": [centre.x, centre.y, centre.z],
            },
            camera_node,
        ],
        "meshes": [mesh],
        "materials": materials,
        "cameras": [camera],
        "animations": animations,
        "accessors": buffer.accessors,
        "bufferViews": buffer.views,
        "buffers": [buffer_entry],
    });
    Ok((document, buffer.bytes))
}

/// Frame 0's positions about `centre` (single precision) and, for each later frame, its
/// displacement from frame 0 as a morph target; the positions' accessor and the targets.
fn positions_and_targets(
    buffer: &mut Buffer,
    frames: &[Vec<Vec3>],
    centre: Vec3,
) -> (usize, Vec<Value>) {
    let relative = |p: &Vec3| -> [f32; 3] {
        let d = p - centre;
        [d.x as f32, d.y as f32, d.z as f32]
    };
    let base: Vec<[f32; 3]> = frames[0].iter().map(relative).collect();
    let position = buffer.vec3(&base);
    let targets = frames[1..]
        .iter()
        .map(|frame| {
            let delta: Vec<[f32; 3]> = frame
                .iter()
                .zip(&base)
                .map(|(p, b)| {
                    let r = relative(p);
                    [r[0] - b[0], r[1] - b[1], r[2] - b[2]]
                })
                .collect();
            json!({ "POSITION": buffer.vec3(&delta) })
        })
        .collect();
    (position, targets)
}

/// The paper's two sides (triangles wound both ways) and its mountain, valley and outline
/// lines, each a primitive with its material; the primitives and the materials.
fn sheet_primitives(
    buffer: &mut Buffer,
    sheet: &Mesh,
    position: usize,
    targets: &[Value],
) -> (Vec<Value>, Vec<Value>) {
    let faces = sheet.faces();
    let front: Vec<u32> = faces
        .iter()
        .flat_map(|&[a, b, c]| [a, b, c])
        .map(|v| v as u32)
        .collect();
    let back: Vec<u32> = faces
        .iter()
        .flat_map(|&[a, b, c]| [a, c, b])
        .map(|v| v as u32)
        .collect();
    let kinds = LineKind::of_mesh(sheet);
    let lines = |kind: LineKind| -> Vec<u32> {
        sheet
            .edges()
            .iter()
            .zip(&kinds)
            .filter(|(_, &k)| k == kind)
            .flat_map(|(e, _)| e.vertices)
            .map(|v| v as u32)
            .collect()
    };
    let mut materials = vec![
        material("paper front", FRONT_RGB, false),
        material("paper back", BACK_RGB, false),
    ];
    let mut primitives = vec![
        primitive(position, buffer.indices(&front), 0, 4, targets),
        primitive(position, buffer.indices(&back), 1, 4, targets),
    ];
    for (name, kind) in [
        ("mountain", LineKind::Mountain),
        ("valley", LineKind::Valley),
        ("outline", LineKind::Cut),
    ] {
        let indices = lines(kind);
        if indices.is_empty() {
            continue;
        }
        materials.push(material(name, super::colour::rgb(kind), true));
        let accessor = buffer.indices(&indices);
        primitives.push(primitive(
            position,
            accessor,
            materials.len() - 1,
            1,
            targets,
        ));
    }
    (primitives, materials)
}

/// The animation of the sheet's morph weights over `keys` frames: one key per frame, at
/// key k only target k − 1 weighs (none at key 0). None without targets.
fn weight_animation(buffer: &mut Buffer, keys: usize, targets: usize) -> Option<Value> {
    if targets == 0 {
        return None;
    }
    let times: Vec<f32> = (0..keys)
        .map(|k| (k as f64 * SECONDS_PER_FRAME) as f32)
        .collect();
    let mut weights = vec![0f32; keys * targets];
    for k in 1..keys {
        weights[k * targets + (k - 1)] = 1.0;
    }
    let input = buffer.floats(&times, true);
    let output = buffer.floats(&weights, false);
    Some(json!({
        "name": "fold from flat",
        "samplers": [{ "input": input, "output": output, "interpolation": "LINEAR" }],
        "channels": [{ "sampler": 0, "target": { "node": 1, "path": "weights" } }],
    }))
}

/// A primitive over the shared positions and targets.
fn primitive(
    position: usize,
    indices: usize,
    material: usize,
    mode: u32,
    targets: &[Value],
) -> Value {
    let mut p = json!({
        "attributes": { "POSITION": position },
        "indices": indices,
        "material": material,
        "mode": mode,
    });
    if !targets.is_empty() {
        p["targets"] = json!(targets);
    }
    p
}

/// The middle of the box round every frame (mm).
fn centre_of(frames: &[Vec<Vec3>]) -> Vec3 {
    let mut lo = Vec3::repeat(f64::INFINITY);
    let mut hi = Vec3::repeat(f64::NEG_INFINITY);
    for p in frames.iter().flatten() {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    if lo.x.is_finite() {
        (lo + hi) / 2.0
    } else {
        Vec3::zeros()
    }
}

/// A perspective camera seeing every frame from the previews' direction
/// ([`super::png::design_view`]), in glTF's y-up metres.
fn default_camera(frames: &[Vec<Vec3>], centre: Vec3) -> (Value, Value) {
    let radius = frames
        .iter()
        .flatten()
        .map(|p| (p - centre).norm())
        .fold(0.0, f64::max)
        .max(1.0);
    let yfov: f64 = 0.6;
    let distance = radius / (yfov / 2.0).sin() * 1.1;
    let to_world = |p: Vec3| Vector3::new(p.x, p.z, -p.y) * 0.001;
    let target = to_world(centre);
    let eye = to_world(centre + super::png::design_view() * distance);
    // A camera looks down its −z: its +z points from the target to the eye.
    let rotation = UnitQuaternion::face_towards(&(eye - target), &Vector3::y());
    let q = rotation.coords;
    let camera = json!({
        "name": "view",
        "type": "perspective",
        "perspective": {
            "yfov": yfov,
            "aspectRatio": 4.0 / 3.0,
            "znear": (distance - radius).max(radius * 0.01) * 0.001 * 0.5,
            "zfar": (distance + radius) * 0.001 * 2.0,
        },
    });
    let node = json!({
        "name": "view",
        "camera": 0,
        "translation": [eye.x, eye.y, eye.z],
        "rotation": [q.x, q.y, q.z, q.w],
    });
    (camera, node)
}

//! Target surfaces for `crease fit`, in millimetres: Wavefront OBJ (read by `tobj`) and
//! STL, ASCII or binary (read by `stl_io`). Only triangles are taken: a target with
//! polygons is refused rather than triangulated by guesswork, since the fit measures its
//! distances to exactly these triangles. Writing is OBJ or binary STL.

use super::FileError;
use crate::limits;
use crate::mesh::Vec3;
use crate::surface::TriSurface;
use std::path::Path;

/// Reads a target surface, the format chosen by the extension (`.obj`, `.stl`).
pub fn read_target(path: &Path) -> Result<TriSurface, FileError> {
    let bytes = super::read_file_bytes(path, limits::MAX_FILE_BYTES)?;
    read_target_bytes(path, &bytes)
}

/// A target surface from a file's bytes (the studio's upload), the format chosen by the
/// extension of `name`.
pub fn read_target_bytes(name: &Path, bytes: &[u8]) -> Result<TriSurface, FileError> {
    let bad = |cause: String| FileError::new(name, cause);
    let ext = super::extension_of(name);
    let (vertices, triangles) = match ext.as_str() {
        "obj" => parse_obj(bytes).map_err(bad)?,
        "stl" => parse_stl(bytes).map_err(bad)?,
        "" => return Err(bad("has no extension: name a target .obj or .stl".into())),
        other => {
            return Err(bad(format!(
                "unknown target type \".{other}\": a target is a triangle mesh, .obj or .stl"
            )))
        }
    };
    TriSurface::new(vertices, triangles).map_err(|e| bad(e.to_string()))
}

/// Vertices and triangles of an OBJ file, every object merged; faces must be triangles.
fn parse_obj(bytes: &[u8]) -> Result<(Vec<Vec3>, Vec<[usize; 3]>), String> {
    check_obj_counts(bytes)?;
    let options = tobj::LoadOptions {
        triangulate: false,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = std::io::BufReader::new(bytes);
    // Materials are never read: nothing in a target opens another file.
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| format!("not a readable OBJ file: {}", brief(&e.to_string())))?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for model in &models {
        let m = &model.mesh;
        if let Some(k) = m.face_arities.iter().position(|&a| a != 3) {
            return Err(format!(
                "face {} of object \"{}\" has {} corners: a target must be triangles (triangulate it first)",
                k + 1,
                crate::limits::short_text(&model.name),
                m.face_arities[k]
            ));
        }
        let base = vertices.len();
        vertices.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        triangles.extend(m.indices.chunks_exact(3).map(|t| {
            [
                base + t[0] as usize,
                base + t[1] as usize,
                base + t[2] as usize,
            ]
        }));
    }
    Ok((vertices, triangles))
}

/// Refuses an OBJ whose counts pass the target limits before `tobj` builds anything:
/// it keeps several words per corner, so 10⁷ faces `f 1 1 1` (80 MB) took gigabytes
/// before the triangle count could be checked. One pass over the bytes, nothing kept.
fn check_obj_counts(bytes: &[u8]) -> Result<(), String> {
    let (mut vertices, mut faces, mut corners) = (0u64, 0u64, 0u64);
    for line in bytes.split(|&b| b == b'\n') {
        let line = line.trim_ascii_start();
        let mut words = line
            .split(|b| b.is_ascii_whitespace())
            .filter(|w| !w.is_empty());
        match words.next() {
            Some(b"v") => vertices += 1,
            Some(b"f") => {
                faces += 1;
                corners += words.count() as u64;
            }
            _ => {}
        }
    }
    let most = limits::TARGET_TRIANGLES.max as u64;
    // No face at all is left to the surface's own check ("it has no triangles").
    if faces > 0 {
        limits::TARGET_TRIANGLES
            .check_count("its face count", faces)
            .map_err(|e| e.to_string())?;
    }
    if corners > 3 * most || vertices > 3 * most {
        return Err(format!(
            "{vertices} vertices and {corners} face corners are more than a target of {most} triangles needs (at most {} each)",
            3 * most
        ));
    }
    Ok(())
}

/// Vertices and triangles of an STL file, ASCII or binary.
fn parse_stl(bytes: &[u8]) -> Result<(Vec<Vec3>, Vec<[usize; 3]>), String> {
    // A binary file's header states its triangle count: refuse an absurd one before
    // reading, and a file shorter than it says.
    if !bytes.starts_with(b"solid") && bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        limits::TARGET_TRIANGLES
            .check_count("its triangle count", count)
            .map_err(|e| e.to_string())?;
        if (bytes.len() as u64) < 84 + 50 * count {
            return Err(format!(
                "a binary STL of {count} triangles needs {} bytes, the file has {}",
                84 + 50 * count,
                bytes.len()
            ));
        }
    }
    let mut cursor = std::io::Cursor::new(bytes);
    let mesh = stl_io::read_stl(&mut cursor)
        .map_err(|e| format!("not a readable STL file: {}", brief(&e.to_string())))?;
    let vertices = mesh
        .vertices
        .iter()
        .map(|v| Vec3::new(v[0] as f64, v[1] as f64, v[2] as f64))
        .collect();
    let triangles = mesh.faces.iter().map(|f| f.vertices).collect();
    Ok((vertices, triangles))
}

/// A reader's message cut to one short line: it may quote a line of the file.
fn brief(message: &str) -> String {
    let line = message.lines().next().unwrap_or_default();
    match line.char_indices().nth(100) {
        Some((cut, _)) => format!("{}…", &line[..cut]),
        None => line.to_string(),
    }
}

/// Writes a target surface as OBJ or binary STL, by the extension, atomically.
pub fn write_target(surface: &TriSurface, path: &Path, comment: &str) -> Result<(), FileError> {
    let ext = super::extension_of(path);
    let bytes = match ext.as_str() {
        "obj" => surface.to_obj(comment).into_bytes(),
        "stl" => {
            let x = surface.vertices();
            let triangles: Vec<stl_io::Triangle> = surface
                .triangles()
                .iter()
                .map(|&t| {
                    let [a, b, c] = t.map(|v| x[v]);
                    let n = (b - a).cross(&(c - a)).normalize();
                    let f = |p: Vec3| stl_io::Vertex::new([p.x as f32, p.y as f32, p.z as f32]);
                    stl_io::Triangle {
                        normal: stl_io::Normal::new([n.x as f32, n.y as f32, n.z as f32]),
                        vertices: [f(a), f(b), f(c)],
                    }
                })
                .collect();
            let mut out = Vec::new();
            stl_io::write_stl(&mut out, triangles.iter()).map_err(|e| FileError::new(path, e))?;
            out
        }
        _ => {
            return Err(FileError::new(
                path,
                "a target surface is written as .obj or .stl",
            ))
        }
    };
    super::write_atomic(path, &bytes)
}

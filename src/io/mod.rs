//! Pattern files in and out: FOLD, ORIPA `.cp`, Origami Simulator SVG, Freeform Origami OBJ.
//! Every error names the file and the cause; every write goes to a temporary file first and
//! is renamed into place, so a failed run never leaves half a file behind.

mod cp;
pub mod fold;
mod obj;
mod opx;
pub mod planar;
mod svg_path;
mod svg_read;
mod svg_transform;
mod svg_write;
mod target;

pub use target::{read_target, read_target_bytes, write_target};

use crate::mesh::Mesh;
use std::path::{Path, PathBuf};

/// A file that could not be read or written, and why.
#[derive(Debug, thiserror::Error)]
#[error("{}: {cause}", path.display())]
pub struct FileError {
    /// The file.
    pub path: PathBuf,
    /// What is wrong with it.
    #[source]
    pub cause: FileCause,
}

/// Why a file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum FileCause {
    /// The system refused (no such file, no permission, disk full).
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// What it holds is not what its format allows; the message says where and why.
    #[error("{0}")]
    Content(String),
    /// FOLD text that is not JSON of FOLD's shape.
    #[error("not valid FOLD JSON: {0}")]
    Json(#[source] serde_json::Error),
    /// A value outside its range ([`crate::limits`]).
    #[error(transparent)]
    Range(#[from] crate::limits::OutOfRange),
    /// What it describes is not a valid mesh.
    #[error(transparent)]
    Mesh(#[from] crate::mesh::MeshError),
    /// A tube's seam that does not join the strip's ends.
    #[error(transparent)]
    Seam(#[from] crate::mesh::SeamError),
}

impl From<String> for FileCause {
    fn from(message: String) -> Self {
        FileCause::Content(message)
    }
}

impl From<&str> for FileCause {
    fn from(message: &str) -> Self {
        FileCause::Content(message.to_string())
    }
}

impl FileError {
    /// An error about `path`: a message about its content, the system's `io::Error`, or
    /// any other [`FileCause`].
    pub fn new(path: &Path, cause: impl Into<FileCause>) -> Self {
        FileError {
            path: path.to_path_buf(),
            cause: cause.into(),
        }
    }
}

/// Pattern file formats, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// FOLD 1.1 JSON (`.fold`).
    Fold,
    /// ORIPA crease pattern (`.cp`).
    Cp,
    /// Origami Simulator SVG crease pattern (`.svg`).
    Svg,
    /// ORIPA's own document (`.opx`), read only.
    Opx,
    /// Freeform Origami OBJ (`.obj`).
    Obj,
}

/// A path's extension in lower case ("" when it has none): the one reading of a file
/// name's format for every reader and writer.
pub fn extension_of(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default()
}

impl Format {
    /// The format for a path's extension.
    pub fn from_path(path: &Path) -> Result<Format, FileError> {
        let ext = extension_of(path);
        match ext.as_str() {
            "fold" | "json" => Ok(Format::Fold),
            "cp" => Ok(Format::Cp),
            "svg" => Ok(Format::Svg),
            "opx" => Ok(Format::Opx),
            "obj" => Ok(Format::Obj),
            "" => Err(FileError::new(
                path,
                "the file name has no extension to tell its format: name it .fold, .cp, .opx, .svg or .obj",
            )),
            _ => Err(FileError::new(
                path,
                format!("unknown file type \".{ext}\" (expected .fold, .cp, .opx, .svg or .obj)"),
            )),
        }
    }
}

/// A mesh read from a file, with notes on what import changed (dropped lines, holes).
#[derive(Debug)]
pub struct Imported {
    /// The mesh.
    pub mesh: Mesh,
    /// Human-readable notes for the user.
    pub notes: Vec<String>,
}

/// The decimals of every number with a decimal point in `text`, each with its count of
/// significant digits: `12.50` gives (2, 4); an all-zero fraction (`20.0`) counts as 0
/// decimals.
fn number_decimals(text: &str) -> Vec<(i32, usize)> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'.' && i + 1 < bytes.len() && bytes[i + 1].is_ascii_digit() {
            let mut int_start = i;
            while int_start > 0 && bytes[int_start - 1].is_ascii_digit() {
                int_start -= 1;
            }
            let mut j = i + 1;
            while j < bytes.len() && bytes[j].is_ascii_digit() {
                j += 1;
            }
            let mut decimals = (j - i - 1) as i32;
            if j + 1 < bytes.len() && (bytes[j] == b'e' || bytes[j] == b'E') {
                let exp: String = text[j + 1..]
                    .chars()
                    .take_while(|c| c.is_ascii_digit() || *c == '-' || *c == '+')
                    .collect();
                decimals -= exp.parse::<i32>().unwrap_or(0);
            }
            if bytes[i + 1..j].iter().all(|&b| b == b'0') {
                decimals = 0;
            }
            let digits: String = text[int_start..j]
                .chars()
                .filter(char::is_ascii_digit)
                .collect();
            let significant = digits.trim_start_matches('0').len();
            out.push((decimals, significant));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// `quantum` (a file's inferred rounding, [`decimal_quantum`], mm) as `mesh`'s rounding
/// when it is fine beside the drawing, else zero: ±0.05 on a unit grid written 0.2, 0.4,
/// … is a quarter of its shortest crease, so those are exact values on a coarse grid, not
/// measurements rounded to it (taken as rounding, it made every overlap thinner than a
/// tenth of the sheet a contact).
pub(crate) fn rounding_of(mesh: &Mesh, quantum: f64) -> f64 {
    if quantum <= 0.0 {
        return 0.0;
    }
    let length = |a: usize, b: usize| match mesh.crease_pattern() {
        Some(f) => (f[b] - f[a]).norm(),
        None => (mesh.positions()[b] - mesh.positions()[a]).norm(),
    };
    let shortest = mesh
        .edges()
        .iter()
        .map(|e| length(e.vertices[0], e.vertices[1]))
        .filter(|&l| l > 0.0)
        .fold(f64::INFINITY, f64::min);
    if quantum > crate::tolerance::ROUNDING_OF_SHORTEST_EDGE * shortest {
        0.0
    } else {
        quantum
    }
}

/// The rounding a drawing program applied to its coordinates: half the decimal step it
/// rounded to (Illustrator writes 3 decimals: ±0.0005), in the file's units, or zero for
/// full precision. Inferred from what the numbers of `text` show, never from how short
/// one of them happens to be:
/// - a number with 15 or more significant digits is a double written in full, so the file
///   keeps doubles (a shortest-decimal writer writes `20.8` for 20.8 and `17.320508075688775`
///   for √300): full precision;
/// - numbers whose fraction is all zeros (`20.0`) are integers and say nothing;
/// - otherwise the finest count of decimals d is the rounding only if enough numbers use
///   it (at least 3, and 5% of all numbers): one hand-edited `20.8` among integers is an
///   exact value, not a file rounded to 0.1.
pub fn decimal_quantum(text: &str) -> f64 {
    let numbers = number_decimals(text);
    if numbers.iter().any(|&(_, sig)| sig >= 15) {
        return 0.0;
    }
    let all = numbers.len() + integer_count(text);
    let fractional: Vec<i32> = numbers
        .iter()
        .filter(|&&(d, _)| d > 0)
        .map(|&(d, _)| d)
        .collect();
    let Some(&finest) = fractional.iter().max() else {
        return 0.0;
    };
    let at_finest = fractional.iter().filter(|&&d| d == finest).count();
    if at_finest >= 3 && at_finest * 20 >= all {
        0.5 * 10f64.powi(-finest)
    } else {
        0.0
    }
}

/// Numbers without a decimal point in `text` (runs of digits not next to a `.`, a letter
/// or an exponent).
fn integer_count(text: &str) -> usize {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '.' || c == '-' || c == '+'))
        .filter(|w| {
            let w = w.trim_start_matches(['-', '+']);
            !w.is_empty() && w.bytes().all(|b| b.is_ascii_digit())
        })
        .count()
}

/// A TOML error on one line: where it is (line, and the key with its table, as
/// `gpgl.axis_order`, or the table header the error sits on) and what is wrong, instead of
/// the parser's multi-line snippet.
pub fn toml_error(text: &str, e: &toml::de::Error) -> String {
    let message = e.message().replace('\n', " ");
    let Some(span) = e.span() else {
        return message;
    };
    let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
    let lines: Vec<&str> = text.lines().collect();
    let header = |l: &str| {
        let l = l.trim();
        l.starts_with('[').then(|| {
            let name = l.trim_start_matches('[');
            name.split(']').next().unwrap_or(name).trim().to_string()
        })
    };
    let this = lines.get(line - 1).copied().unwrap_or("");
    let table = lines[..(line - 1).min(lines.len())]
        .iter()
        .rev()
        .find_map(|l| header(l));
    let place = match (header(this), this.split_once('='), table) {
        (Some(h), _, _) => format!(" (table [{h}])"),
        (None, Some((k, _)), Some(t)) => format!(" (key {t}.{})", k.trim()),
        (None, Some((k, _)), None) => format!(" (key {})", k.trim()),
        (None, None, _) => String::new(),
    };
    format!("line {line}{place}: {message}")
}

/// The bytes of the regular file at `path` (a symbolic link is followed), at most
/// `limit` of them. A FIFO, a device or a directory is refused by its type before
/// anything is read, and the cap counts bytes as they are read, so neither a pipe that
/// never ends nor a file that grows can make a read unbounded.
pub fn read_file_bytes(path: &Path, limit: u64) -> Result<Vec<u8>, FileError> {
    use std::io::Read;
    let meta = regular_file(path)?;
    let file = std::fs::File::open(path).map_err(|e| FileError::new(path, e))?;
    let mut bytes = Vec::with_capacity(meta.len().min(limit) as usize);
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| FileError::new(path, e))?;
    if bytes.len() as u64 > limit {
        return Err(FileError::new(
            path,
            format!("is larger than the {} MB crease reads", limit >> 20),
        ));
    }
    Ok(bytes)
}

/// The text of the regular file at `path`, read as [`read_file_bytes`] does, within
/// [`crate::limits::MAX_FILE_BYTES`].
pub fn read_file_text(path: &Path) -> Result<String, FileError> {
    let bytes = read_file_bytes(path, crate::limits::MAX_FILE_BYTES)?;
    String::from_utf8(bytes).map_err(|_| FileError::new(path, "the file is not UTF-8 text"))
}

/// [`read_file_text`] for readers whose errors carry the system's `io::Error` (machine
/// and material profiles): the same bounds and refusals, a refusal that is not the
/// system's given as `InvalidData` with its message.
pub fn read_text_as_io(path: &Path) -> std::io::Result<String> {
    read_file_text(path).map_err(|e| match e.cause {
        FileCause::Io(io) => io,
        other => std::io::Error::new(std::io::ErrorKind::InvalidData, other.to_string()),
    })
}

/// The metadata of `path`, refusing what is not a regular file (a directory, a FIFO, a
/// socket, a device) by what it is.
fn regular_file(path: &Path) -> Result<std::fs::Metadata, FileError> {
    let meta = std::fs::metadata(path).map_err(|e| FileError::new(path, e))?;
    if !meta.is_file() {
        let kind = if meta.is_dir() {
            "a directory"
        } else {
            "not a regular file (a FIFO, socket or device)"
        };
        return Err(FileError::new(
            path,
            format!("is {kind}: give crease a file on disk"),
        ));
    }
    Ok(meta)
}

/// Reads a pattern file of any supported format.
pub fn read(path: &Path) -> Result<Mesh, FileError> {
    read_with_notes(path).map(|i| i.mesh)
}

/// Reads a pattern file and reports what import changed.
pub fn read_with_notes(path: &Path) -> Result<Imported, FileError> {
    // A folder is named as one, not as a file name without an extension.
    regular_file(path)?;
    Format::from_path(path)?;
    let bytes = read_file_bytes(path, crate::limits::MAX_FILE_BYTES)?;
    read_bytes(path, bytes)
}

/// Reads a pattern from bytes already in memory (an upload to the studio); `path` names
/// it in errors and chooses the format by its extension.
pub fn read_bytes(path: &Path, bytes: Vec<u8>) -> Result<Imported, FileError> {
    let format = Format::from_path(path)?;
    let text =
        String::from_utf8(bytes).map_err(|_| FileError::new(path, "the file is not UTF-8 text"))?;
    let err = |cause: FileCause| FileError::new(path, cause);
    let mut notes = Vec::new();
    let mesh = match format {
        Format::Fold => fold::parse_noting(&text, &mut notes).map_err(err)?,
        Format::Cp => cp::parse(&text, &mut notes).map_err(err)?,
        Format::Svg => svg_read::parse(&text, &mut notes).map_err(err)?,
        Format::Opx => opx::parse(&text, &mut notes).map_err(err)?,
        Format::Obj => obj::parse(&text).map_err(err)?,
    };
    Ok(Imported { mesh, notes })
}

/// Serialises a mesh in a format.
pub fn to_string(mesh: &Mesh, format: Format) -> Result<String, String> {
    match format {
        Format::Fold => Ok(fold::to_string(mesh)),
        Format::Cp => cp::to_string(mesh),
        Format::Svg => svg_write::to_string(mesh),
        Format::Opx => Err(
            "writing ORIPA's .opx is not supported: write .cp, which ORIPA opens as well".into(),
        ),
        Format::Obj => Ok(obj::to_string(mesh)),
    }
}

/// Writes a mesh to a file, the format chosen by extension.
pub fn write(mesh: &Mesh, path: &Path) -> Result<(), FileError> {
    let format = Format::from_path(path)?;
    let text = to_string(mesh, format).map_err(|c| FileError::new(path, c))?;
    write_atomic(path, text.as_bytes())
}

/// Writes several files into `dir` as one step: every file goes to a temporary name first,
/// and only when all are written are they renamed into place. A failure removes the
/// temporary files, so a run never leaves a partial set behind.
pub fn write_all_atomic(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<(), FileError> {
    std::fs::create_dir_all(dir).map_err(|e| FileError::new(dir, e))?;
    let temp = |name: &str| dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let mut written = Vec::new();
    for (name, bytes) in files {
        let t = temp(name);
        if let Err(e) = std::fs::write(&t, bytes) {
            let _ = std::fs::remove_file(&t);
            for w in &written {
                let _ = std::fs::remove_file(w);
            }
            return Err(FileError::new(&dir.join(name), e));
        }
        written.push(t);
    }
    // Every destination is checked before the first rename: a folder (or anything but a
    // file) in the way would otherwise stop the set half renamed in.
    let blocked = files
        .iter()
        .map(|(name, _)| dir.join(name))
        .find(|d| std::fs::symlink_metadata(d).is_ok_and(|m| !m.file_type().is_file()));
    if let Some(d) = blocked {
        for w in &written {
            let _ = std::fs::remove_file(w);
        }
        return Err(FileError::new(
            &d,
            "something other than a file is in the way; move it and run again (nothing was written)",
        ));
    }
    for ((name, _), t) in files.iter().zip(&written) {
        std::fs::rename(t, dir.join(name)).map_err(|e| FileError::new(&dir.join(name), e))?;
    }
    Ok(())
}

/// Writes bytes to `path` through a temporary file in the same folder and a rename, so
/// readers never see a partial file. Creates missing parent folders.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), FileError> {
    let err = |e: std::io::Error| FileError::new(path, e);
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(err)?;
    }
    let mut tmp_name = path.file_name().unwrap_or_default().to_os_string();
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    let result = std::fs::write(&tmp, bytes).and_then(|_| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(err)
}

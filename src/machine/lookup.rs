//! Finding data files by name: machine profiles and materials are both `NAME.toml` in a
//! list of folders, or a path given outright.

use std::path::{Path, PathBuf};

/// The file `name_or_path` names: itself when it looks like a path (ends in `.toml` or
/// holds a `/`), else `NAME.toml` in the first of `dirs` that has it. `None` if no such
/// file exists.
pub(super) fn find_toml(name_or_path: &str, dirs: &[PathBuf]) -> Option<PathBuf> {
    let as_path = Path::new(name_or_path);
    if as_path.extension().is_some_and(|e| e == "toml") || name_or_path.contains('/') {
        return Some(as_path.to_path_buf()).filter(|p| p.is_file());
    }
    dirs.iter()
        .map(|d| d.join(format!("{name_or_path}.toml")))
        .find(|p| p.is_file())
}

/// Names (file stems) of the `.toml` files in `dirs`, sorted, each once.
pub(super) fn toml_names<'a>(dirs: impl IntoIterator<Item = &'a PathBuf>) -> Vec<String> {
    let mut known: Vec<String> = dirs
        .into_iter()
        .filter_map(|d| std::fs::read_dir(d).ok())
        .flatten()
        .flatten()
        .filter_map(|e| {
            let p = e.path();
            if p.extension()? != "toml" {
                return None;
            }
            Some(p.file_stem()?.to_string_lossy().into_owned())
        })
        .collect();
    known.sort();
    known.dedup();
    known
}

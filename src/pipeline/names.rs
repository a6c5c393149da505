//! What the files crease writes are called, and where they go when no one says: one rule
//! each, for both faces (the command line writes them, the studio offers them as
//! downloads).

use std::path::{Path, PathBuf};

/// A design's title or a file's name made a file stem: the name without its folder and
/// extension, every character but ASCII letters, digits, `-` and `_` turned into `-`
/// (a download's name reaches the user's file system), "design" when nothing is left.
pub fn file_stem(name: &str) -> String {
    let stem = Path::new(name)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let clean: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect();
    if clean.is_empty() {
        "design".into()
    } else {
        clean
    }
}

/// The file a design titled `title` is saved as: `STEM.fold`.
pub fn design_file(title: &str) -> String {
    format!("{}.fold", file_stem(title))
}

/// The file the folding motion of a design titled `title` is exported as:
/// `STEM-motion.FORMAT` (`format` an extension `MotionFormat::of` reads).
pub fn motion_file(title: &str, format: &str) -> String {
    format!("{}-motion.{format}", file_stem(title))
}

/// Where the report of a fit written to `output` goes: `OUT.fit.json` beside it.
pub fn fit_report_path(output: &Path) -> PathBuf {
    output.with_extension("fit.json")
}

/// Where `fab` writes the sheet's files of `design` when no folder is given:
/// `out/STEM`, in the folder the command runs in (`out/` is git-ignored).
pub fn fab_folder(design: &Path) -> PathBuf {
    PathBuf::from("out").join(design.file_stem().unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_keep_what_a_file_system_takes_and_nothing_else() {
        assert_eq!(file_stem("miura-bent.fold"), "miura-bent");
        assert_eq!(file_stem("../../etc/pass wd.fold"), "pass-wd");
        assert_eq!(file_stem("été.svg"), "-t-");
        assert_eq!(file_stem(""), "design");
        assert_eq!(design_file("a b.fold"), "a-b.fold");
        assert_eq!(
            motion_file("waterbomb 8x8", "glb"),
            "waterbomb-8x8-motion.glb"
        );
        assert_eq!(
            fit_report_path(Path::new("dir/dome.fold")),
            Path::new("dir/dome.fit.json")
        );
        assert_eq!(
            fab_folder(Path::new("patterns/miura.fold")),
            Path::new("out/miura")
        );
    }
}

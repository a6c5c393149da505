//! Scratch folders for the tests: one per test (or per case), removed when it is done.
//!
//! The tests once made their folders by hand under the system's temporary folder and
//! never removed them, so every run of the suite left some 120 MB there (2.4 GB after
//! twenty runs on the development machine). A [`Scratch`] is removed when it is dropped
//! on a test that passed; on a test that fails it is kept and named on stderr, so what
//! the test wrote can still be read.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A scratch folder of its own: `crease-NAME-PID-N` under the system's temporary
/// folder, made empty, removed on drop unless the thread is panicking. It derefs to
/// its path, so `dir.join(..)`, `&dir` and `dir.display()` read as for a `PathBuf`.
pub struct Scratch(PathBuf);

impl Scratch {
    /// A new, empty folder. `name` says which test it serves; the process id and a
    /// counter keep tests that run at once, in this process or another, apart.
    pub fn new(name: &str) -> Scratch {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("crease-{name}-{}-{n}", std::process::id()));
        // A folder of that name is left from an earlier process of the same id.
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir)
            .unwrap_or_else(|e| panic!("cannot make the scratch folder {}: {e}", dir.display()));
        Scratch(dir)
    }

    /// Writes `content` to `name` in the folder and returns its path.
    #[allow(dead_code)] // not every test crate writes files this way
    pub fn file(&self, name: &str, content: impl AsRef<[u8]>) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, content)
            .unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
        path
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<OsStr> for Scratch {
    fn as_ref(&self) -> &OsStr {
        self.0.as_os_str()
    }
}

impl std::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("kept {} (the test failed)", self.0.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// A file in a scratch folder of its own (see [`Scratch`]): the folder goes with it.
/// It derefs to the file's path.
#[allow(dead_code)] // not every test crate writes lone files
pub struct ScratchFile {
    path: PathBuf,
    _dir: Scratch,
}

#[allow(dead_code)]
impl ScratchFile {
    /// Writes `content` to `name` in a new scratch folder for `suite`.
    pub fn new(suite: &str, name: &str, content: impl AsRef<[u8]>) -> ScratchFile {
        let dir = Scratch::new(suite);
        ScratchFile {
            path: dir.file(name, content),
            _dir: dir,
        }
    }

    /// The path `name` in a new scratch folder for `suite`, nothing written there (an
    /// output the test expects, or a file or folder it makes itself).
    pub fn at(suite: &str, name: &str) -> ScratchFile {
        let dir = Scratch::new(suite);
        ScratchFile {
            path: dir.join(name),
            _dir: dir,
        }
    }
}

impl std::ops::Deref for ScratchFile {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for ScratchFile {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

impl std::fmt::Debug for ScratchFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.path.fmt(f)
    }
}

impl AsRef<OsStr> for ScratchFile {
    fn as_ref(&self) -> &OsStr {
        self.path.as_os_str()
    }
}

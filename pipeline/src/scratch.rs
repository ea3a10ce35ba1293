//! Scratch files for the unit tests: a fresh temporary directory per call, removed when the
//! value is dropped (`tempfile`), so that test runs leave nothing behind in the system's
//! temporary directory.

use std::path::{Path, PathBuf};

/// A path in a temporary directory of its own, which lives as long as this value.
pub struct Scratch {
    _dir: tempfile::TempDir,
    path: PathBuf,
}

impl Scratch {
    /// A fresh, empty directory.
    pub fn dir() -> Scratch {
        let dir = tempfile::Builder::new()
            .prefix("bumpsim-test-")
            .tempdir()
            .expect("a temporary directory");
        let path = dir.path().to_path_buf();
        Scratch { _dir: dir, path }
    }

    /// The path `name` in a fresh, empty directory (nothing is created at it).
    pub fn file(name: &str) -> Scratch {
        let d = Scratch::dir();
        Scratch {
            path: d.path.join(name),
            _dir: d._dir,
        }
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

//! Shared by the fuzz targets: a scratch file per process for the inputs that the
//! pipeline reads from a path.

use std::path::PathBuf;

/// A file `name` in this process's scratch directory (created once), holding `bytes`.
pub fn scratch_file(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bumpsim-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("create the scratch directory");
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write the scratch file");
    path
}

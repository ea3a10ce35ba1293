//! All-or-nothing output writing: nothing already written is left half-written.
//!
//! Every file is written to a temporary file in its target directory (a hidden
//! `.<name>.<pid>.<n>.tmp`) and renamed into place, so a reader sees either the old file or
//! the whole new one. An [`OutputSet`] first writes every temporary file of the set and only
//! then renames them all; if any write fails, the temporary files already written are removed
//! and no target is touched. Directories that `commit` creates are removed again when it
//! fails, so a failed run leaves no stray parent directory either.

use rayon::prelude::*;
use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Files to write into one directory, kept in memory until [`OutputSet::commit`].
#[derive(Debug, Clone)]
pub struct OutputSet {
    dir: PathBuf,
    /// `(file name, bytes)` in the order first added.
    files: Vec<(String, Vec<u8>)>,
}

impl OutputSet {
    /// An empty set of files for `dir` (created by `commit` if missing).
    pub fn new(dir: &Path) -> Self {
        OutputSet {
            dir: dir.to_path_buf(),
            files: Vec::new(),
        }
    }

    /// The target directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The file names added so far, in order.
    pub fn names(&self) -> Vec<&str> {
        self.files.iter().map(|(n, _)| n.as_str()).collect()
    }

    /// Add a file. `name` is a plain file name in the directory (checked by `commit`);
    /// adding a name again replaces its bytes and keeps its place.
    pub fn add(&mut self, name: &str, bytes: Vec<u8>) {
        match self.files.iter_mut().find(|(n, _)| n == name) {
            Some(f) => f.1 = bytes,
            None => self.files.push((name.to_string(), bytes)),
        }
    }

    /// Add an image encoded as PNG.
    pub fn add_png(&mut self, name: &str, img: &image::RgbImage) -> Result<(), String> {
        self.add_pngs(&[(name, img)])
    }

    /// [`Self::add_png`] of several images, encoded concurrently (rayon) and added in the
    /// order given. On an error nothing is added.
    pub fn add_pngs(&mut self, imgs: &[(&str, &image::RgbImage)]) -> Result<(), String> {
        let encoded: Vec<Vec<u8>> = imgs
            .par_iter()
            .map(|(name, img)| {
                encode_png(img).map_err(|e| format!("cannot encode {name} as PNG: {e}"))
            })
            .collect::<Result<_, _>>()?;
        for ((name, _), bytes) in imgs.iter().zip(encoded) {
            self.add(name, bytes);
        }
        Ok(())
    }

    /// Write every file: create the directory if missing, write each file to a temporary
    /// file next to its target, then rename them all into place. On an error no target has
    /// been touched (unless a rename itself fails, after every write succeeded: then the
    /// files renamed so far are complete new files and the rest keep their old contents),
    /// no temporary file is left, the directories created are removed, and the message
    /// names the path. Returns the paths written, in the order added.
    pub fn commit(self) -> Result<Vec<PathBuf>, String> {
        for (name, _) in &self.files {
            check_name(name)?;
        }
        let mut created = Vec::new();
        let result = self.write(&mut created);
        if result.is_err() {
            // innermost first; `remove_dir` only removes empty directories
            for d in created.iter().rev() {
                let _ = fs::remove_dir(d);
            }
        }
        result
    }

    /// [`OutputSet::commit`] after the names are checked; records the directories it
    /// creates in `created`, outermost first.
    fn write(&self, created: &mut Vec<PathBuf>) -> Result<Vec<PathBuf>, String> {
        create_dirs(&self.dir, created)
            .map_err(|e| format!("cannot create output directory {}: {e}", self.dir.display()))?;
        if !self.dir.is_dir() {
            return Err(format!(
                "output directory {} is not a directory",
                self.dir.display()
            ));
        }
        let targets: Vec<PathBuf> = self.files.iter().map(|(n, _)| self.dir.join(n)).collect();
        for t in &targets {
            if t.is_dir() {
                return Err(format!("cannot write {}: it is a directory", t.display()));
            }
        }
        // the temporary files are written (and synced) concurrently: their syncs wait on the
        // disk, not the processor; on an error every temporary file written is removed and
        // the first failure in file order is reported
        let written: Vec<io::Result<PathBuf>> = self
            .files
            .par_iter()
            .map(|(name, bytes)| write_temp(&self.dir, name, bytes))
            .collect();
        if let Some(k) = written.iter().position(Result::is_err) {
            let ok: Vec<PathBuf> = written.iter().flatten().cloned().collect();
            remove_all(&ok);
            let e = written[k].as_ref().expect_err("a failed write");
            return Err(format!("cannot write {}: {e}", targets[k].display()));
        }
        let temps: Vec<PathBuf> = written.into_iter().flatten().collect();
        for (k, (temp, target)) in temps.iter().zip(&targets).enumerate() {
            if let Err(e) = fs::rename(temp, target) {
                remove_all(&temps[k..]);
                return Err(format!(
                    "cannot move {} into place as {}: {e} ({k} of {} files were written)",
                    temp.display(),
                    target.display(),
                    targets.len()
                ));
            }
        }
        sync_dir(&self.dir);
        Ok(targets)
    }
}

/// Create `dir` and its missing parents like `create_dir_all`, recording each directory
/// created, outermost first (a directory that appears meanwhile is not recorded).
fn create_dirs(dir: &Path, created: &mut Vec<PathBuf>) -> io::Result<()> {
    let mut missing = Vec::new();
    let mut d = dir;
    while !d.as_os_str().is_empty() && fs::symlink_metadata(d).is_err() {
        missing.push(d.to_path_buf());
        match d.parent() {
            Some(p) => d = p,
            None => break,
        }
    }
    for m in missing.into_iter().rev() {
        match fs::create_dir(&m) {
            Ok(()) => created.push(m),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

/// Write one file atomically: to a temporary file in the same directory, then renamed over
/// `path`. The directory must exist. On an error nothing is left behind and the message
/// names `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| format!("cannot write {}: expected a file path", path.display()))?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if path.is_dir() {
        return Err(format!(
            "cannot write {}: it is a directory",
            path.display()
        ));
    }
    let temp = write_temp(dir, name, bytes)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    if let Err(e) = fs::rename(&temp, path) {
        let _ = fs::remove_file(&temp);
        return Err(format!("cannot write {}: {e}", path.display()));
    }
    sync_dir(dir);
    Ok(())
}

/// PNG bytes of an RGB image.
pub fn encode_png(img: &image::RgbImage) -> Result<Vec<u8>, image::ImageError> {
    let mut buf = io::Cursor::new(Vec::new());
    img.write_to(&mut buf, image::ImageFormat::Png)?;
    Ok(buf.into_inner())
}

/// A name must be a plain file name: not empty, not `.` or `..`, no separator, no NUL.
fn check_name(name: &str) -> Result<(), String> {
    if name.is_empty() || name == "." || name == ".." || name.contains(['/', '\\', '\0']) {
        return Err(format!(
            "invalid output file name {name:?}: expected a plain file name"
        ));
    }
    Ok(())
}

static TEMP_SEQ: AtomicU64 = AtomicU64::new(0);

/// Write `bytes` to a new temporary file in `dir` for target `name`; the partial file is
/// removed on error.
fn write_temp(dir: &Path, name: &str, bytes: &[u8]) -> io::Result<PathBuf> {
    let seq = TEMP_SEQ.fetch_add(1, Ordering::Relaxed);
    let temp = dir.join(format!(".{name}.{}.{seq}.tmp", std::process::id()));
    let mut f = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp)?;
    let written = f.write_all(bytes).and_then(|_| f.sync_all());
    drop(f);
    match written {
        Ok(()) => Ok(temp),
        Err(e) => {
            let _ = fs::remove_file(&temp);
            Err(e)
        }
    }
}

fn remove_all(paths: &[PathBuf]) {
    for p in paths {
        let _ = fs::remove_file(p);
    }
}

/// Best effort: make the renames durable (not supported everywhere, so errors are ignored).
fn sync_dir(dir: &Path) {
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh, empty scratch directory for one test (removed when dropped).
    fn scratch() -> crate::scratch::Scratch {
        crate::scratch::Scratch::dir()
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn commit_writes_every_file_and_creates_the_directory() {
        let root = scratch();
        let dir = root.join("a").join("b");
        let mut img = image::RgbImage::new(3, 2);
        img.put_pixel(2, 1, image::Rgb([10, 20, 30]));
        let mut set = OutputSet::new(&dir);
        set.add("report.json", b"{\"x\": 1}\n".to_vec());
        set.add_png("image.png", &img).unwrap();
        set.add("notes.txt", b"first".to_vec());
        set.add("notes.txt", b"second".to_vec()); // replaces, keeps its place
        assert_eq!(set.names(), vec!["report.json", "image.png", "notes.txt"]);
        let paths = set.commit().unwrap();
        assert_eq!(
            paths,
            vec![
                dir.join("report.json"),
                dir.join("image.png"),
                dir.join("notes.txt")
            ]
        );
        assert_eq!(listing(&dir), vec!["image.png", "notes.txt", "report.json"]);
        assert_eq!(fs::read(dir.join("report.json")).unwrap(), b"{\"x\": 1}\n");
        assert_eq!(fs::read(dir.join("notes.txt")).unwrap(), b"second");
        let back = image::load_from_memory(&fs::read(dir.join("image.png")).unwrap())
            .unwrap()
            .to_rgb8();
        assert_eq!(back, img);

        // a second commit replaces the files whole
        let mut set = OutputSet::new(&dir);
        set.add("notes.txt", b"third".to_vec());
        set.commit().unwrap();
        assert_eq!(fs::read(dir.join("notes.txt")).unwrap(), b"third");
        assert_eq!(listing(&dir), vec!["image.png", "notes.txt", "report.json"]);
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn a_directory_that_is_a_file_fails_and_writes_nothing() {
        let root = scratch();
        let blocker = root.join("out");
        fs::write(&blocker, b"keep").unwrap();
        for dir in [blocker.clone(), blocker.join("sub")] {
            let mut set = OutputSet::new(&dir);
            set.add("a.txt", b"a".to_vec());
            set.add("b.txt", b"b".to_vec());
            let err = set.commit().unwrap_err();
            assert!(err.contains(&dir.display().to_string()), "{err}");
        }
        assert_eq!(listing(&root), vec!["out"]);
        assert_eq!(fs::read(&blocker).unwrap(), b"keep");
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn a_failed_write_removes_the_files_already_written() {
        let root = scratch();
        fs::write(root.join("first.txt"), b"old").unwrap();
        let long = "x".repeat(300); // too long a file name: its temp file cannot be created
        let mut set = OutputSet::new(&root);
        set.add("first.txt", b"new".to_vec());
        set.add("second.txt", b"2".to_vec());
        set.add(&long, b"3".to_vec());
        let err = set.commit().unwrap_err();
        assert!(err.starts_with("cannot write "), "{err}");
        assert!(
            err.contains(&root.join(&long).display().to_string()),
            "{err}"
        );
        // the old file is untouched and no temporary file is left
        assert_eq!(listing(&root), vec!["first.txt"]);
        assert_eq!(fs::read(root.join("first.txt")).unwrap(), b"old");
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn a_failed_commit_removes_the_directories_it_created() {
        let root = scratch();
        fs::create_dir(root.join("kept")).unwrap();
        // a name too long for the file system: `a/` and `a/b/` are created, then removed
        let long = root.join("a").join("b").join("x".repeat(300));
        let mut set = OutputSet::new(&long);
        set.add("report.json", b"{}".to_vec());
        let err = set.commit().unwrap_err();
        assert!(err.contains("cannot create output directory"), "{err}");
        assert_eq!(listing(&root), vec!["kept"]);
        // a write that fails inside a created directory: the directory goes too
        let dir = root.join("c").join("d");
        let mut set = OutputSet::new(&dir);
        set.add("ok.txt", b"ok".to_vec());
        set.add(&"y".repeat(300), b"x".to_vec());
        assert!(set.commit().is_err());
        assert_eq!(listing(&root), vec!["kept"]);
        // an existing directory is never removed, even empty
        let mut set = OutputSet::new(&root.join("kept"));
        set.add(&"z".repeat(300), b"x".to_vec());
        assert!(set.commit().is_err());
        assert_eq!(listing(&root), vec!["kept"]);
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn a_target_that_is_a_directory_fails_before_writing() {
        let root = scratch();
        fs::create_dir(root.join("b.txt")).unwrap();
        let mut set = OutputSet::new(&root);
        set.add("a.txt", b"a".to_vec());
        set.add("b.txt", b"b".to_vec());
        let err = set.commit().unwrap_err();
        assert_eq!(
            err,
            format!(
                "cannot write {}: it is a directory",
                root.join("b.txt").display()
            )
        );
        assert_eq!(listing(&root), vec!["b.txt"]);
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn bad_names_are_rejected_before_writing() {
        let root = scratch();
        for bad in ["", ".", "..", "../x", "a/b", "a\\b", "nul\0"] {
            let mut set = OutputSet::new(&root);
            set.add("ok.txt", b"ok".to_vec());
            set.add(bad, b"x".to_vec());
            let err = set.commit().unwrap_err();
            assert!(err.starts_with("invalid output file name"), "{err}");
        }
        assert!(listing(&root).is_empty());
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn write_atomic_writes_and_replaces_whole_files() {
        let root = scratch();
        let p = root.join("trace.vcd");
        write_atomic(&p, b"one").unwrap();
        write_atomic(&p, b"two, longer").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"two, longer");
        assert_eq!(listing(&root), vec!["trace.vcd"]);

        let missing = root.join("no").join("such").join("t.txt");
        let err = write_atomic(&missing, b"x").unwrap_err();
        assert!(err.contains(&missing.display().to_string()), "{err}");
        let err = write_atomic(&root, b"x").unwrap_err();
        assert!(err.contains("it is a directory"), "{err}");
        assert!(write_atomic(Path::new("/"), b"x").is_err());
        assert_eq!(listing(&root), vec!["trace.vcd"]);
        fs::remove_dir_all(&root).unwrap();
    }
}

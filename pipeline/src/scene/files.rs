//! Reading the files a scene names (OBJ and PLY meshes, PNG images) with bounds: a regular file (a
//! directory is "is a directory", a missing file "no such file"), at most a size limit, and
//! for PNG images the dimensions read from the header and checked before anything is decoded.

use std::hash::{Hash, Hasher};
use std::io::Read;
use std::path::Path;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use super::SceneError;

/// Largest OBJ file read, in bytes (256 MiB: about 5 million triangles; the bunny is 101 KB).
pub const MAX_OBJ_BYTES: u64 = 256 << 20;

/// Largest PLY file read, in bytes (256 MiB: about 16 million triangles in binary with float
/// coordinates, 5 million in ASCII; the 871 K-face Stanford dragon is 32 MB in binary).
pub const MAX_PLY_BYTES: u64 = 256 << 20;

/// Largest PNG file read, in bytes (256 MiB).
pub const MAX_PNG_BYTES: u64 = 256 << 20;

/// Largest side of an input image (bump maps, colour textures, environment maps), in pixels:
/// 4096, the largest texture side of the units.
pub const MAX_PNG_SIDE: u32 = 4096;

/// Why `path` is not a regular file we can open: "is a directory", "no such file", ...
fn not_a_file(path: &Path, what: &str) -> Option<String> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Some(format!(
            "could not read {what}: it is a directory (expected a {what} file)"
        )),
        Ok(_) => None,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            Some(format!("could not read {what}: no such file"))
        }
        Err(e) => Some(format!("could not read {what}: {e}")),
    }
}

/// What [`recorded`] has seen on this thread: the digests of the paths and bytes read.
struct Record {
    hashers: [std::collections::hash_map::DefaultHasher; 2],
}

thread_local! {
    static RECORD: std::cell::RefCell<Option<Record>> = const { std::cell::RefCell::new(None) };
}

/// Recordings in progress on any thread.
static RECORDING: AtomicUsize = AtomicUsize::new(0);
/// Files read by a thread that was not recording while some recording was in progress.
static MISSED: AtomicU64 = AtomicU64::new(0);

/// `f()` and a digest of every file it read (paths and bytes, in order): what a result
/// built from files depends on beyond its config (`crate::memo`). None if `f` read a file
/// on another thread (or a recording is already running on this one), since such reads
/// cannot be told apart from another recording's.
pub fn recorded<T>(f: impl FnOnce() -> T) -> (T, Option<[u64; 2]>) {
    if RECORD.with(|r| r.borrow().is_some()) {
        return (f(), None);
    }
    /// Ends the recording however `f` returns (a panic included).
    struct Guard;
    impl Drop for Guard {
        fn drop(&mut self) {
            RECORD.with(|r| r.borrow_mut().take());
            RECORDING.fetch_sub(1, Ordering::SeqCst);
        }
    }
    let missed = MISSED.load(Ordering::SeqCst);
    RECORDING.fetch_add(1, Ordering::SeqCst);
    RECORD.with(|r| {
        *r.borrow_mut() = Some(Record {
            hashers: std::array::from_fn(|pass| {
                let mut h = std::collections::hash_map::DefaultHasher::new();
                (pass as u64).hash(&mut h);
                h
            }),
        })
    });
    let guard = Guard;
    let out = f();
    let record = RECORD.with(|r| r.borrow_mut().take());
    drop(guard);
    let clean = MISSED.load(Ordering::SeqCst) == missed;
    let digest = record
        .filter(|_| clean)
        .map(|r| r.hashers.map(|h| h.finish()));
    (out, digest)
}

/// Account for the bytes of `path` in this thread's recording.
fn note(path: &Path, bytes: &[u8]) {
    let recorded = RECORD.with(|r| match r.borrow_mut().as_mut() {
        Some(rec) => {
            for h in &mut rec.hashers {
                path.hash(h);
                bytes.hash(h);
            }
            true
        }
        None => false,
    });
    if !recorded && RECORDING.load(Ordering::SeqCst) > 0 {
        MISSED.fetch_add(1, Ordering::SeqCst);
    }
}

/// The bytes of `path`, at most `max` of them; `what` names the kind of file ("OBJ") in
/// the messages, which are file errors naming the path.
pub fn read_bounded(path: &Path, max: u64, what: &str) -> Result<Vec<u8>, SceneError> {
    let bytes = read_bounded_unrecorded(path, max, what)?;
    note(path, &bytes);
    Ok(bytes)
}

fn read_bounded_unrecorded(path: &Path, max: u64, what: &str) -> Result<Vec<u8>, SceneError> {
    let fail = |m: String| SceneError::file(path.display(), m);
    if let Some(m) = not_a_file(path, what) {
        return Err(fail(m));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(max + 1).read_to_end(&mut bytes))
        .map_err(|e| fail(format!("could not read {what}: {e}")))?;
    if bytes.len() as u64 > max {
        return Err(fail(format!(
            "could not read {what}: the file is larger than {} MiB (expected at most {max} \
             bytes)",
            max >> 20
        )));
    }
    Ok(bytes)
}

/// Width and height from the IHDR chunk right after the PNG signature, if the file starts so.
fn ihdr_size(bytes: &[u8]) -> Option<(u32, u32)> {
    const SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";
    if bytes.len() < 24 || &bytes[..8] != SIGNATURE || &bytes[12..16] != b"IHDR" {
        return None;
    }
    let be =
        |at: usize| u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    Some((be(16), be(20)))
}

/// Read a PNG image: a regular file of at most [`MAX_PNG_BYTES`], whose header gives sides of
/// 1 to `max_side` pixels (checked before the image is decoded, so an 8192 x 8192 file is
/// refused without allocating its pixels). Errors are file errors naming the path; their
/// messages start with `could not read PNG`, `could not decode PNG` or `the PNG image is`.
pub fn read_png(path: &Path, max_side: u32) -> Result<image::DynamicImage, SceneError> {
    let fail = |m: String| SceneError::file(path.display(), m);
    let bytes = read_bounded(path, MAX_PNG_BYTES, "PNG")?;
    let reader =
        || image::ImageReader::with_format(std::io::Cursor::new(&bytes), image::ImageFormat::Png);
    // the sides from the IHDR chunk, which a PNG file must start with (the decoder's own
    // header read also wants the chunks up to the image data)
    let (w, h) = match ihdr_size(&bytes) {
        Some(wh) => wh,
        None => reader()
            .into_dimensions()
            .map_err(|e| fail(format!("could not decode PNG: {e}")))?,
    };
    if w == 0 || h == 0 || w > max_side || h > max_side {
        return Err(fail(format!(
            "the PNG image is {w} x {h} pixels: expected 1 to {max_side} pixels a side \
             (checked before decoding)"
        )));
    }
    let mut r = reader();
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(max_side);
    limits.max_image_height = Some(max_side);
    // 16-bit RGBA at the largest side, and a margin for the decoder
    limits.max_alloc = Some(u64::from(max_side) * u64::from(max_side) * 8 * 2);
    r.limits(limits);
    r.decode()
        .map_err(|e| fail(format!("could not decode PNG: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `name` in a fresh, empty directory (removed when dropped).
    fn temp(name: &str) -> crate::scratch::Scratch {
        crate::scratch::Scratch::file(name)
    }

    /// The digest of a recording: the same for the same bytes, apart for one changed byte,
    /// none when a file is read on another thread meanwhile or when recordings nest.
    #[test]
    fn recordings_digest_the_files_read_and_only_on_their_thread() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("mesh.obj");
        let read = || read_bounded(&path, 1 << 20, "OBJ").unwrap();
        // Another test of this process reading a file meanwhile also spoils a recording (it
        // cannot be told apart from a read of this one on another thread): retry until clean.
        let clean = |f: &dyn Fn()| {
            (0..100)
                .find_map(|_| recorded(f).1)
                .expect("a recording without reads elsewhere")
        };
        std::fs::write(&path, b"v 0 0 0\n").unwrap();
        assert_eq!(recorded(read).0, b"v 0 0 0\n");
        let a = clean(&|| drop(read()));
        assert_eq!(clean(&|| drop(read())), a);
        assert_ne!(clean(&|| ()), a, "no file read");
        std::fs::write(&path, b"v 0 0 1\n").unwrap();
        let b = clean(&|| drop(read()));
        assert_ne!(a, b);
        // a file read on another thread while recording cannot be attributed
        let (_, c) = recorded(|| {
            read();
            std::thread::scope(|s| {
                s.spawn(read);
            });
        });
        assert_eq!(c, None);
        assert_eq!(recorded(|| recorded(read).1).0, None, "nested");
        assert_eq!(clean(&|| drop(read())), b, "the state is left clean");
    }

    #[test]
    fn directories_and_missing_files_are_named() {
        let dir = temp("a-dir");
        std::fs::create_dir_all(&dir).unwrap();
        let e = read_bounded(&dir, 10, "OBJ").unwrap_err().to_string();
        assert!(e.contains("is a directory"), "{e}");
        let e = read_png(&dir, 16).unwrap_err().to_string();
        assert!(e.contains("is a directory"), "{e}");
        let e = read_png(&temp("nope.png"), 16).unwrap_err().to_string();
        assert!(e.contains("no such file"), "{e}");
    }

    #[test]
    fn a_file_over_the_limit_is_refused() {
        let p = temp("big.obj");
        std::fs::write(&p, vec![b'#'; 100]).unwrap();
        assert!(read_bounded(&p, 100, "OBJ").is_ok());
        let e = read_bounded(&p, 99, "OBJ").unwrap_err().to_string();
        assert!(e.contains("larger than"), "{e}");
    }

    #[test]
    fn png_dimensions_are_checked_before_decoding() {
        // a valid 8 x 4 PNG refused at a limit of 6 a side; its pixels fit otherwise
        let p = temp("small.png");
        image::RgbImage::new(8, 4).save(&p).unwrap();
        assert_eq!(read_png(&p, 8).unwrap().width(), 8);
        let e = read_png(&p, 6).unwrap_err().to_string();
        assert!(e.contains("8 x 4 pixels") && e.contains("1 to 6"), "{e}");
    }
}

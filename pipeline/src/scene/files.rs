//! Reading the files a scene names (OBJ and PLY meshes, PNG images) with bounds: a regular file (a
//! directory is "is a directory", a missing file "no such file"), at most a size limit, and
//! for PNG images the dimensions read from the header and checked before anything is decoded.

use std::io::Read;
use std::path::Path;

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

/// The bytes of `path`, at most `max` of them; `what` names the kind of file ("OBJ") in
/// the messages, which are file errors naming the path.
pub fn read_bounded(path: &Path, max: u64, what: &str) -> Result<Vec<u8>, SceneError> {
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

    fn temp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("bumpsim-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
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

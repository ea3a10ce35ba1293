//! What the NV2A hardware checks share: the captured frames in the repository.
#![allow(dead_code)]

use std::path::PathBuf;

/// Frame size of every capture (the A8R8G8B8 back buffer).
pub const W: u32 = 640;
pub const H: u32 = 480;

/// The frame `name` of `suite` (`Combiner`, `Pixel_shader`, `Bump_map`) as RGBA; a missing or
/// unreadable file fails the test (the frames are part of the repository, not optional).
pub fn frame(suite: &str, name: &str) -> image::RgbaImage {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/nv2a/golden")
        .join(suite)
        .join(format!("{name}.png"));
    let img = image::open(&p)
        .unwrap_or_else(|e| {
            panic!(
                "the NV2A frame {} is missing or unreadable: {e}",
                p.display()
            )
        })
        .to_rgba8();
    assert_eq!(img.dimensions(), (W, H), "{}", p.display());
    img
}

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

/// The ROP's blend the combiner frames found: SRC_ALPHA, ONE_MINUS_SRC_ALPHA on all four
/// channels, rounded to nearest.
pub fn blend(s: [u8; 4], d: [u8; 4]) -> [u8; 4] {
    let a = s[3] as u32;
    std::array::from_fn(|c| {
        let t = s[c] as u32 * a + d[c] as u32 * (255 - a);
        ((2 * t + 255) / 510) as u8
    })
}

/// Whether (x, y) lies in a text cell the host prints: `(row, col, characters)` of
/// `pb_printat` / `pb_print`, 10 x 16 px cells at x = 20 + 10 col, y = 25 + 25 row.
pub fn in_text(cells: &[(u32, u32, u32)], x: u32, y: u32) -> bool {
    cells.iter().any(|&(r, c, n)| {
        let (x0, y0) = (20 + 10 * c, 25 + 25 * r);
        x >= x0 && x < x0 + 10 * n && y >= y0 && y < y0 + 16
    })
}

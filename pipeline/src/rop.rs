//! The frame buffer write (ROP): the depth test and the colour write of the fragments that
//! leave the pipe, in the order they leave it.
//!
//! The test is LESS against a buffer cleared to the largest code, on the fragment's quantised
//! window depth. With the rasterizer's early test ([`crate::raster::DepthTest::Early`]) every
//! arriving fragment is nearer than all earlier ones at its pixel, so this test passes them
//! all and the frame is the same as without it; with the late test (an engine that may kill)
//! it is the only depth test, and a killed fragment neither writes colour nor depth.

use crate::metrics::Rgb64;
use crate::raster::{scan::depth_max, Fragment};
use bumpsim_hw::Word;

/// The frame buffer after the ROP has taken `outputs` (by fragment; `None` = killed).
pub struct Framebuffer {
    pub image: Rgb64,
    /// Pixels written.
    pub mask: Vec<bool>,
    /// Live fragments that reached the depth test (each reads depth).
    pub tested: u64,
    /// Fragments that passed it (each writes colour and depth).
    pub written: u64,
}

/// The frame buffer after writing `outputs` of `frags` for a `depth_bits`-bit depth buffer.
/// Colours are clamped to [0, 1].
pub fn write(
    w: u32,
    h: u32,
    depth_bits: u32,
    frags: &[Fragment],
    outputs: &[Option<Word>],
) -> Framebuffer {
    let mut img = Rgb64::new(w, h);
    let mut mask = vec![false; (w as usize) * (h as usize)];
    let mut depth = vec![depth_max(depth_bits); mask.len()];
    let (mut tested, mut written) = (0, 0);
    for (f, o) in frags.iter().zip(outputs) {
        let Some(o) = o else { continue };
        tested += 1;
        let i = (f.y as usize) * (w as usize) + f.x as usize;
        if f.depth >= depth[i] {
            continue;
        }
        written += 1;
        depth[i] = f.depth;
        img.px[i] = [0, 1, 2].map(|c| o.lanes[c].x.clamp(0.0, 1.0));
        mask[i] = true;
    }
    Framebuffer {
        image: img,
        mask,
        tested,
        written,
    }
}

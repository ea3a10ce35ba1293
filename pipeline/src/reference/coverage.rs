//! Step 1's visibility: the fragment that wins each pixel, taken from the rasterizer's
//! fragments (the engine's own, so the reference does not rasterise the frame again).

use crate::raster::{scan, DepthBuffer, Fragment, RasterConfig};

/// The winning fragment of each pixel: the last fragment at the pixel that passes the
/// rasterizer's early depth test (LESS against a buffer cleared to the largest code of
/// `depth_bits`), in rasterization order.
///
/// The fragments may come from a rasterizer with the early test
/// ([`crate::raster::DepthTest::Early`]: each already passed it, so each passes again and the
/// last at a pixel wins) or with the late one ([`crate::raster::DepthTest::Late`]: every
/// covered sample, in the same order and with the same depths, so replaying the test keeps
/// exactly the fragments the early test would have emitted). Both give the same winners.
#[derive(Debug, Clone, PartialEq)]
pub struct Coverage {
    pub width: u32,
    pub height: u32,
    /// Per pixel, row-major: the index of the winning fragment, [`Coverage::NONE`] where no
    /// fragment covers the pixel.
    winner: Vec<u32>,
}

impl Coverage {
    /// No fragment covers the pixel.
    pub const NONE: u32 = u32::MAX;

    /// The winners of `frags` (in rasterization order, rasterised with `raster`) on a
    /// `width` x `height` image. Fragments outside the image are ignored. A frame holds far
    /// fewer than `u32::MAX` fragments (the run's memory estimate bounds it), so indices fit
    /// 32 bits.
    pub fn of_fragments(
        frags: &[Fragment],
        width: u32,
        height: u32,
        raster: &RasterConfig,
    ) -> Coverage {
        let n = width as usize * height as usize;
        let mut winner = vec![Self::NONE; n];
        // the rasterizer's own test ([`crate::raster::rasterize_with`])
        let clear = scan::depth_max(raster.depth_bits.clamp(16, 32));
        let mut zbuf = DepthBuffer::new(width, height, clear);
        for (k, f) in frags.iter().enumerate() {
            if zbuf.test_and_set(f.x, f.y, f.depth) {
                winner[f.y as usize * width as usize + f.x as usize] = k as u32;
            }
        }
        Coverage {
            width,
            height,
            winner,
        }
    }

    /// The winners of row `y` (fragment indices, [`Coverage::NONE`] where none).
    pub fn row(&self, y: u32) -> &[u32] {
        let w = self.width as usize;
        &self.winner[y as usize * w..(y as usize + 1) * w]
    }
}

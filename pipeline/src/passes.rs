//! Rendering passes and their cost: cycles, geometry and framebuffer traffic per pass.
//!
//! Most engines render a frame in one pass. Tarini et al. 1999 §7 blends a base colour with
//! the quantized normal map's shade in framebuffer passes: equation (1) takes three passes
//! (base colour; `dst = dst alpha`; `dst = src (1 - dst) + dst`), equation (2) two (base
//! colour; `dst = src (1 - dst) + dst alpha`), colour as a material attribute one. The cycle
//! simulator streams every fragment through the engine once; this module charges each pass:
//!
//! * **cycles**: a pass re-sends the geometry and re-rasterizes every triangle, so it takes the
//!   simulated fragment-stream cycles of the frame (`cycles.total - cycles.frame`: setup,
//!   scan and one fragment per clock); per-frame work (palette builds) is charged once;
//! * **geometry**: `triangles x bits_per_triangle` per pass;
//! * **framebuffer**: the first pass reads depth for every live fragment (the depth test;
//!   killed fragments are dropped before it) and writes colour and depth for every one that
//!   passes (all of them when the rasterizer tested depth early); a blend pass reads and writes colour and reads depth (the
//!   `GL_EQUAL` test of a re-drawn surface; no depth write).

use serde::Serialize;

use bumpsim_hw::units::BlendEquation;

/// One pass.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Pass {
    pub name: String,
    pub cycles: u64,
    pub geometry_bits: u64,
    pub fb_read_bits: u64,
    pub fb_write_bits: u64,
}

/// All passes of a frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Passes {
    pub passes: Vec<Pass>,
    /// Frame work plus every pass's cycles.
    pub total_cycles: u64,
    /// Framebuffer bits read and written over all passes.
    pub fb_bits: u64,
    /// Geometry bits over all passes.
    pub geometry_bits: u64,
}

/// What the passes are charged with.
#[derive(Debug, Clone, Copy)]
pub struct Frame {
    /// Per-frame work, cycles.
    pub frame_cycles: u64,
    /// One traversal of every triangle and fragment, cycles.
    pub stream_cycles: u64,
    pub triangles: u64,
    /// Live fragments at the depth test (killed ones are dropped before it).
    pub fragments: u64,
    /// Fragments that passed the depth test (all of them with the rasterizer's early test).
    pub written: u64,
    pub bits_per_triangle: u64,
    /// Bits of the colour written per pixel.
    pub color_bits: u64,
    pub depth_bits: u64,
}

/// The passes of a frame with `blend` (`None`: one pass).
pub fn passes(f: Frame, blend: Option<BlendEquation>) -> Passes {
    let pass = |name: &str, read: u64, write: u64| Pass {
        name: name.to_string(),
        cycles: f.stream_cycles,
        geometry_bits: f.triangles * f.bits_per_triangle,
        fb_read_bits: read,
        fb_write_bits: write,
    };
    let first = |name: &str| {
        pass(
            name,
            f.fragments * f.depth_bits,
            f.written * (f.color_bits + f.depth_bits),
        )
    };
    let blend_pass = |name: &str| {
        pass(
            name,
            f.fragments * (f.color_bits + f.depth_bits),
            f.fragments * f.color_bits,
        )
    };
    let list = match blend {
        None => vec![first("shade")],
        Some(BlendEquation::Approx) => vec![
            first("base colour"),
            blend_pass("eq. (2): dst = src (1 - dst) + dst alpha"),
        ],
        Some(BlendEquation::Exact) => vec![
            first("base colour"),
            blend_pass("eq. (1): dst = dst alpha"),
            blend_pass("eq. (1): dst = src (1 - dst) + dst"),
        ],
    };
    Passes {
        total_cycles: f.frame_cycles + list.iter().map(|p| p.cycles).sum::<u64>(),
        fb_bits: list.iter().map(|p| p.fb_read_bits + p.fb_write_bits).sum(),
        geometry_bits: list.iter().map(|p| p.geometry_bits).sum(),
        passes: list,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> Frame {
        Frame {
            frame_cycles: 512,
            stream_cycles: 10_000,
            triangles: 100,
            fragments: 9_000,
            written: 9_000,
            bits_per_triangle: 480,
            color_bits: 24,
            depth_bits: 24,
        }
    }

    #[test]
    fn one_two_and_three_passes() {
        let one = passes(frame(), None);
        assert_eq!(one.passes.len(), 1);
        assert_eq!(one.total_cycles, 10_512);
        // write colour + depth, read depth
        assert_eq!(one.fb_bits, 9_000 * (24 + 48));
        let two = passes(frame(), Some(BlendEquation::Approx));
        assert_eq!(two.total_cycles, 512 + 20_000);
        // the blend pass reads colour and depth and writes colour: 72 bits a fragment
        assert_eq!(two.fb_bits, 9_000 * (72 + 72));
        assert_eq!(two.geometry_bits, 2 * 100 * 480);
        let three = passes(frame(), Some(BlendEquation::Exact));
        assert_eq!(three.passes.len(), 3);
        assert_eq!(three.total_cycles, 512 + 30_000);
        assert_eq!(three.fb_bits, 9_000 * (72 + 2 * 72));
        // late depth test: 9,000 live fragments read depth, 6,000 pass and write
        let late = passes(
            Frame {
                written: 6_000,
                ..frame()
            },
            None,
        );
        assert_eq!(late.fb_bits, 9_000 * 24 + 6_000 * 48);
    }
}

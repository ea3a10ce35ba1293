//! Rendering passes and their cost: cycles, geometry and framebuffer traffic per pass.
//!
//! Most engines render a frame in one pass. A config's `engine.passes` adds passes after the
//! first (Tarini et al. 1999 §7 blends a base colour with the quantized normal map's shade in
//! framebuffer passes: equation (1) takes three, base colour, `dst = dst alpha` and
//! `dst = src (1 - dst) + dst`; equation (2) two, base colour and
//! `dst = src (1 - dst) + dst alpha`). Every pass goes through the ROP with its own state
//! (`rop.rs`, `hw/src/units/rop.rs`), and this module charges each pass from what its
//! fragments did there:
//!
//! * **cycles**: a pass re-sends the geometry and re-rasterizes every triangle, so it takes the
//!   simulated fragment-stream cycles of the frame (`cycles.total - cycles.frame`: setup,
//!   scan and one fragment per clock); per-frame work (palette builds) is charged once;
//! * **geometry**: `triangles x bits_per_triangle` per pass;
//! * **framebuffer**: depth read for every live fragment that passed the alpha test; for every
//!   one that passed the depth test, colour read when the pass blends, colour written, and
//!   depth written when the pass writes depth.

use serde::Serialize;

use crate::rop::PassCounts;

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

/// What every pass is charged with.
#[derive(Debug, Clone, Copy)]
pub struct Frame {
    /// Per-frame work, cycles.
    pub frame_cycles: u64,
    /// One traversal of every triangle and fragment, cycles.
    pub stream_cycles: u64,
    pub triangles: u64,
    pub bits_per_triangle: u64,
    /// Bits of the colour written per pixel.
    pub color_bits: u64,
    pub depth_bits: u64,
}

/// One pass as the ROP ran it.
#[derive(Debug, Clone)]
pub struct PassRun {
    pub name: String,
    pub counts: PassCounts,
    /// Whether the ROP blended (read the destination colour).
    pub blends: bool,
    pub depth_write: bool,
}

/// The passes of a frame, in order.
pub fn passes(f: Frame, runs: &[PassRun]) -> Passes {
    let list: Vec<Pass> = runs
        .iter()
        .map(|r| {
            let c = r.counts;
            let color_read = if r.blends { f.color_bits } else { 0 };
            let depth_write = if r.depth_write { f.depth_bits } else { 0 };
            Pass {
                name: r.name.clone(),
                cycles: f.stream_cycles,
                geometry_bits: f.triangles * f.bits_per_triangle,
                fb_read_bits: c.depth_tested * f.depth_bits + c.written * color_read,
                fb_write_bits: c.written * (f.color_bits + depth_write),
            }
        })
        .collect();
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
            bits_per_triangle: 480,
            color_bits: 24,
            depth_bits: 24,
        }
    }

    fn run(name: &str, depth_tested: u64, written: u64, blends: bool) -> PassRun {
        PassRun {
            name: name.into(),
            counts: PassCounts {
                tested: depth_tested,
                depth_tested,
                written,
            },
            blends,
            depth_write: !blends,
        }
    }

    #[test]
    fn one_two_and_three_passes() {
        let one = passes(frame(), &[run("shade", 9_000, 9_000, false)]);
        assert_eq!(one.passes.len(), 1);
        assert_eq!(one.total_cycles, 10_512);
        // write colour + depth, read depth
        assert_eq!(one.fb_bits, 9_000 * (24 + 48));
        // a blend pass over the surface (depth Equal, no depth write): 8,000 of the 9,000
        // fragments are the surface's and blend: read depth for all, colour for those, write
        // their colour
        let blend = run("blend", 9_000, 8_000, true);
        let two = passes(frame(), &[run("base", 9_000, 9_000, false), blend.clone()]);
        assert_eq!(two.total_cycles, 512 + 20_000);
        assert_eq!(
            two.fb_bits,
            9_000 * (24 + 48) + 9_000 * 24 + 8_000 * (24 + 24)
        );
        assert_eq!(two.geometry_bits, 2 * 100 * 480);
        let three = passes(
            frame(),
            &[run("base", 9_000, 9_000, false), blend.clone(), blend],
        );
        assert_eq!(three.passes.len(), 3);
        assert_eq!(three.total_cycles, 512 + 30_000);
        // late depth test: 9,000 live fragments read depth, 6,000 pass and write
        let late = passes(frame(), &[run("shade", 9_000, 6_000, false)]);
        assert_eq!(late.fb_bits, 9_000 * 24 + 6_000 * 48);
    }
}

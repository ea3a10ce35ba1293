//! The frame buffer write: the ROP unit (`hw/src/units/rop.rs`: alpha test, depth test,
//! blending, the colour write in the framebuffer's format) driven over the fragments that
//! leave the pipe, in the order they leave it (their rasterization order: the pipe is in
//! order).
//!
//! The depth test (default LESS against a buffer cleared to the largest code) reads the
//! fragment's quantised window depth. With the rasterizer's early test
//! ([`crate::raster::DepthTest::Early`]) every arriving fragment is nearer than all earlier
//! ones at its pixel, so a LESS test passes them all and the frame is the same as without it;
//! with the late test (an engine that may kill, or a ROP whose depth function is not LESS, or
//! one that tests alpha) it is the only depth test, and a killed fragment neither writes colour
//! nor depth.

use crate::metrics::Rgb64;
use crate::raster::Fragment;
use crate::sim::Outputs;
use bumpsim_hw::units::rop::Outcome;
use bumpsim_hw::units::Rop;
use bumpsim_hw::Mode;

/// What the ROP reads of a fragment: its pixel, depth code and triangle (16 bytes; a
/// [`Fragment`] is 40, its barycentrics read only by the paths before the ROP).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RopFragment {
    pub x: u32,
    pub y: u32,
    pub depth: u32,
    pub tri: u32,
}

impl From<&Fragment> for RopFragment {
    fn from(f: &Fragment) -> Self {
        RopFragment {
            x: f.x,
            y: f.y,
            depth: f.depth,
            tri: f.tri,
        }
    }
}

/// A fragment as the ROP reads it: [`Fragment`] or [`RopFragment`].
pub trait AsRopFragment {
    fn rop_fragment(&self) -> RopFragment;
}

impl AsRopFragment for Fragment {
    #[inline]
    fn rop_fragment(&self) -> RopFragment {
        self.into()
    }
}

impl AsRopFragment for RopFragment {
    #[inline]
    fn rop_fragment(&self) -> RopFragment {
        *self
    }
}

/// What one pass's fragments did at the ROP.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PassCounts {
    /// Live fragments that reached the ROP's tests.
    pub tested: u64,
    /// Fragments that passed the alpha test (each reads depth).
    pub depth_tested: u64,
    /// Fragments that passed both tests (each writes colour, and depth if the pass writes it;
    /// a blending pass reads their colour first).
    pub written: u64,
}

/// The frame buffer after the ROP has taken `outputs` (by fragment; `None` = killed).
pub struct Framebuffer {
    /// The colour that reached each pixel (clamped to [0, 1], blended in f64): what the
    /// error measures compare, before the framebuffer's rounding.
    pub image: Rgb64,
    /// The framebuffer as 8-bit RGB: the stored codes (rescaled when the framebuffer is not 8
    /// bits per channel).
    pub rgb8: image::RgbImage,
    /// Pixels written.
    pub mask: Vec<bool>,
    /// The triangle of the last fragment written at each pixel
    /// ([`crate::edges::NO_TRIANGLE`] where none was): what the edge measure reads.
    pub tri: Vec<u32>,
    /// Each pass's counts, in order (one for a one-pass frame).
    pub passes: Vec<PassCounts>,
}

/// The frame buffer of a `w` x `h` image after `rop` has written `outputs` of `frags` in
/// `mode`: a one-pass frame.
pub fn write(
    rop: &Rop,
    mode: Mode,
    w: u32,
    h: u32,
    frags: &[impl AsRopFragment],
    outputs: &Outputs,
) -> Framebuffer {
    write_passes(&[(rop, outputs)], mode, w, h, frags)
}

/// The frame buffer of a `w` x `h` image after every pass of `passes` (the ROP state of the
/// pass and its outputs, by fragment of `frags`) has written, in order, in `mode`. Every pass
/// streams the same fragments; colour codes and depth carry from one pass to the next.
pub fn write_passes(
    passes: &[(&Rop, &Outputs)],
    mode: Mode,
    w: u32,
    h: u32,
    frags: &[impl AsRopFragment],
) -> Framebuffer {
    write_passes_observed(passes, mode, w, h, frags, |_| {})
}

/// What the ROP read for one fragment: the pass, the fragment's colour word and depth code,
/// and the pixel it landed on as the framebuffer held it (the datapath's inputs,
/// `bumpsim_hw::units::RopDatapath`).
#[derive(Debug, Clone, Copy)]
pub struct RopInput {
    pub pass: usize,
    pub color: bumpsim_hw::Word,
    pub depth: u32,
    pub dst: bumpsim_hw::units::rop::Pixel,
    pub dst_depth: u32,
}

/// [`write_passes`], calling `observe` with every fragment's [`RopInput`] before the ROP
/// takes it.
pub fn write_passes_observed(
    passes: &[(&Rop, &Outputs)],
    mode: Mode,
    w: u32,
    h: u32,
    frags: &[impl AsRopFragment],
    mut observe: impl FnMut(RopInput),
) -> Framebuffer {
    let rop = passes[0].0;
    let mut fb = rop.clear(w, h);
    let mut tri = vec![crate::edges::NO_TRIANGLE; w as usize * h as usize];
    let mut counts = Vec::with_capacity(passes.len());
    for (pass, &(rop, outputs)) in passes.iter().enumerate() {
        let mut n = PassCounts::default();
        for (k, f) in frags.iter().enumerate().take(outputs.len()) {
            let Some(o) = outputs.word(k) else { continue };
            let f = f.rop_fragment();
            n.tested += 1;
            let i = (f.y as usize) * (w as usize) + f.x as usize;
            observe(RopInput {
                pass,
                color: o,
                depth: f.depth,
                dst: fb.pixel(i),
                dst_depth: fb.depth[i],
            });
            match rop.write(&mut fb, mode, i, f.depth, &o) {
                Outcome::AlphaFailed => {}
                Outcome::DepthFailed => n.depth_tested += 1,
                Outcome::Written => {
                    n.depth_tested += 1;
                    n.written += 1;
                    tri[i] = f.tri;
                }
            }
        }
        counts.push(n);
    }
    let one = (1i64 << rop.params().color_bits) - 1;
    let to8 = |c: u16| ((2 * i64::from(c) * 255 + one) / (2 * one)) as u8;
    let mut rgb8 = image::RgbImage::new(w, h);
    for (p, code) in rgb8.pixels_mut().zip(&fb.code) {
        p.0 = code.map(to8);
    }
    // the values are the image as they are (the codes are in rgb8): nothing is copied
    let px = fb.x;
    Framebuffer {
        image: Rgb64 {
            width: w,
            height: h,
            px,
        },
        rgb8,
        mask: fb.written,
        tri,
        passes: counts,
    }
}

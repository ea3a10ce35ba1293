//! A config's animation (`frames`, [`crate::config::frames`]): every frame rendered as a run of
//! its own, one after another, and the report of frame 0 extended with a row per frame: the
//! frame's cycles and its per-frame work (the palette builds and table loads the hardware pays
//! again each frame), its fragments and texture traffic, the texture bits the host uploads
//! again (the textures whose words changed from the frame before: a light-dependent map), its
//! error against the reference, and
//! the temporal flicker of the bit-accurate image against the frame before; and over all frames,
//! the ringing of the bit-accurate path against the exact-mode path ([`Ringing`]).

use crate::config::{frames, InputError, Loaded};
use crate::run::{self, RunResult};
use image::RgbImage;
use serde::Serialize;

/// The animation section of a report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnimationReport {
    /// Frames, frame 0 included.
    pub frames: u32,
    /// Cycles of all frames.
    pub total_cycles: u64,
    /// Per-frame work (cycles before the first triangle) of all frames.
    pub frame_work_cycles: u64,
    /// Texture bits uploaded over all frames ([`FrameRow::upload_bits`]).
    pub upload_bits: u64,
    /// The largest flicker between two successive frames.
    pub max_flicker_lsb: f64,
    /// Temporal ringing of the bit-accurate path against the exact-mode path (the same
    /// program in f64), over every pair of successive frames ([`Ringing`]).
    pub ringing: Ringing,
    pub per_frame: Vec<FrameRow>,
}

/// How much more the bit-accurate image changes from frame to frame than the exact-mode one
/// (8-bit codes of the framebuffers), pooled over every pair of successive frames and every
/// channel of the samples lit (non-zero) in any of the four images of the pair: the engine's
/// own quantization moving with the scene, apart from the algorithm's error against the
/// reference. All 0 for a single frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ringing {
    /// Mean `|ΔI_bit - ΔI_exact|`, `ΔI` the change from the frame before.
    pub mean_lsb: f64,
    /// Share of the samples where `|ΔI_bit - ΔI_exact|` reaches 4 codes (0 to 1).
    pub share_4lsb: f64,
    /// The bit-accurate image's own mean `|ΔI_bit|` over the same samples.
    pub change_lsb: f64,
    /// The samples counted (channels, over all pairs).
    pub samples: u64,
}

/// The sums of [`Ringing`] over pairs of frames.
#[derive(Default)]
struct RingingSum {
    diff: u64,
    big: u64,
    own: u64,
    n: u64,
}

impl RingingSum {
    /// Add the pair `a` (bit-accurate, exact) then `b`.
    fn add(&mut self, a: [&RgbImage; 2], b: [&RgbImage; 2]) {
        let [a0, r0] = a;
        let [a1, r1] = b;
        let pixels = a0
            .pixels()
            .zip(a1.pixels())
            .zip(r0.pixels().zip(r1.pixels()));
        for ((p0, p1), (q0, q1)) in pixels {
            for c in 0..3 {
                if p0[c] == 0 && p1[c] == 0 && q0[c] == 0 && q1[c] == 0 {
                    continue;
                }
                let db = i32::from(p1[c]) - i32::from(p0[c]);
                let dr = i32::from(q1[c]) - i32::from(q0[c]);
                let x = (db - dr).unsigned_abs();
                self.diff += u64::from(x);
                self.own += u64::from(db.unsigned_abs());
                self.big += u64::from(x >= 4);
                self.n += 1;
            }
        }
    }

    fn report(&self) -> Ringing {
        let per = |x: u64| {
            if self.n == 0 {
                0.0
            } else {
                x as f64 / self.n as f64
            }
        };
        Ringing {
            mean_lsb: per(self.diff),
            share_4lsb: per(self.big),
            change_lsb: per(self.own),
            samples: self.n,
        }
    }
}

/// One frame of an animation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrameRow {
    pub frame: u32,
    /// The frame's overrides (none for frame 0).
    pub sets: Vec<String>,
    pub cycles: u64,
    /// Cycles of per-frame work (`cycles.frame`).
    pub frame_work: u64,
    pub fragments: u64,
    pub killed: u64,
    /// Texel bits read in the frame, all textures.
    pub texture_bits: u64,
    /// Bits of the textures the host uploads before the frame: every texture whose stored
    /// words differ from the frame before's (a light-dependent map rebuilt for the moved
    /// light; a new texture); 0 for frame 0, whose textures are resident.
    pub upload_bits: u64,
    /// Bit-accurate image against the float reference.
    pub total_psnr_db: f64,
    pub total_max_lsb: f64,
    /// Mean over the pixels covered in this frame and the one before, and over channels, of
    /// how much the bit-accurate image's error against the reference changed, in 8-bit codes:
    /// `|(image_k - reference_k) - (image_k-1 - reference_k-1)|`. 0 when the hardware follows
    /// the reference's change exactly; error that moves with the light (a quantized normal
    /// jumping to another palette entry) shows here. Absent for frame 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flicker_lsb: Option<f64>,
}

/// A rendered animation: frame 0's run (with the animation section in its report) and the
/// bit-accurate images of the later frames.
pub struct Animation {
    pub first: RunResult,
    pub images: Vec<RgbImage>,
}

/// Render every frame of `l` (frame 0 only when it has no `frames`).
/// The engine is built once, for frame 0; before every later frame it takes that frame's
/// inputs ([`crate::engine::Engine::begin_frame`]), as the hardware does.
pub fn run(l: &Loaded) -> Result<Animation, InputError> {
    let (mut first, mut engine) = run::run_frame(l, None, None)?;
    if l.config.frames.is_empty() {
        return Ok(Animation {
            first,
            images: Vec::new(),
        });
    }
    let mut rows = vec![row(0, &[], &first, None, None)];
    let mut images = Vec::new();
    let mut prev: Option<RunResult> = None;
    let mut ringing = RingingSum::default();
    for k in 1..=l.config.frames.len() {
        let (r, next) =
            run::run_frame(&frames::frame(l, k)?, None, Some(engine)).map_err(|e| InputError {
                field: format!("frames[{}] (frame {k}): {}", k - 1, e.field),
                ..e
            })?;
        engine = next;
        let before = prev.as_ref().unwrap_or(&first);
        ringing.add([&before.image, &before.exact], [&r.image, &r.exact]);
        rows.push(row(
            k,
            &l.config.frames[k - 1],
            &r,
            Some(before),
            Some(flicker(before, &r)),
        ));
        images.push(r.image.clone());
        prev = Some(r);
    }
    first.report.animation = Some(AnimationReport {
        frames: rows.len() as u32,
        total_cycles: rows.iter().map(|r| r.cycles).fold(0, u64::saturating_add),
        frame_work_cycles: rows
            .iter()
            .map(|r| r.frame_work)
            .fold(0, u64::saturating_add),
        upload_bits: rows
            .iter()
            .map(|r| r.upload_bits)
            .fold(0, u64::saturating_add),
        max_flicker_lsb: rows
            .iter()
            .filter_map(|r| r.flicker_lsb)
            .fold(0.0, f64::max),
        ringing: ringing.report(),
        per_frame: rows,
    });
    Ok(Animation { first, images })
}

/// The stored bits of `b`'s textures that `a` does not hold with the same words.
fn upload_bits(a: &RunResult, b: &RunResult) -> u64 {
    b.textures
        .iter()
        .filter(|(name, t)| {
            !a.textures
                .iter()
                .any(|(n, u)| n == name && (std::sync::Arc::ptr_eq(t, u) || t.same_contents(u)))
        })
        .map(|(_, t)| t.stored_bits())
        .fold(0, u64::saturating_add)
}

fn row(
    k: usize,
    sets: &[String],
    r: &RunResult,
    prev: Option<&RunResult>,
    flicker_lsb: Option<f64>,
) -> FrameRow {
    let rep = &r.report;
    FrameRow {
        frame: k as u32,
        sets: sets.to_vec(),
        cycles: rep.cycles.total,
        frame_work: rep.cycles.frame,
        fragments: rep.cycles.fragments,
        killed: rep.cycles.killed,
        texture_bits: rep
            .bandwidth
            .texture_memory
            .values()
            .map(|t| t.bits_per_frame)
            .fold(0, u64::saturating_add),
        upload_bits: prev.map_or(0, |p| upload_bits(p, r)),
        total_psnr_db: rep.error.total.psnr_db,
        total_max_lsb: rep.error.total.max_abs_lsb,
        flicker_lsb,
    }
}

/// [`FrameRow::flicker_lsb`] of `b` after `a`.
fn flicker(a: &RunResult, b: &RunResult) -> f64 {
    flicker_of(
        [&a.image, &a.reference],
        &a.mask,
        [&b.image, &b.reference],
        &b.mask,
    )
}

/// The flicker of frames given as (image, reference) and mask, of one size (frames change
/// inputs, not the image).
fn flicker_of(a: [&RgbImage; 2], ma: &[bool], b: [&RgbImage; 2], mb: &[bool]) -> f64 {
    let err = |[img, rf]: [&RgbImage; 2], i: usize, c: usize| {
        let (x, y) = ((i as u32) % img.width(), (i as u32) / img.width());
        i32::from(img.get_pixel(x, y).0[c]) - i32::from(rf.get_pixel(x, y).0[c])
    };
    let (mut sum, mut n) = (0u64, 0u64);
    let both = ma
        .iter()
        .zip(mb)
        .enumerate()
        .filter(|(_, (p, q))| **p && **q);
    for (i, _) in both {
        for c in 0..3 {
            sum += u64::from(err(b, i, c).abs_diff(err(a, i, c)));
            n += 1;
        }
    }
    if n == 0 {
        0.0
    } else {
        sum as f64 / n as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Rgb;

    fn img(v: [u8; 4]) -> RgbImage {
        RgbImage::from_fn(2, 2, |x, y| Rgb([v[(2 * y + x) as usize]; 3]))
    }

    #[test]
    fn flicker_is_the_mean_change_of_the_error_over_pixels_covered_in_both() {
        // pixel 0: error 0 -> 0 (the image follows the reference's change); pixel 1: error
        // +2 -> -1 (3 codes); pixel 2 uncovered in the second frame; pixel 3: 5 -> 5.
        // (0 + 3 + 0) x 3 channels over 9 = 1
        let (a, ra) = (img([10, 12, 50, 9]), img([10, 10, 40, 4]));
        let (b, rb) = (img([20, 12, 0, 9]), img([20, 13, 0, 4]));
        let (all, three) = ([true; 4], [true, true, false, true]);
        assert_eq!(flicker_of([&a, &ra], &all, [&b, &rb], &three), 1.0);
        assert_eq!(flicker_of([&a, &ra], &all, [&a, &ra], &all), 0.0);
        // nothing covered in both: no flicker
        assert_eq!(flicker_of([&a, &ra], &all, [&b, &rb], &[false; 4]), 0.0);
    }

    #[test]
    fn ringing_is_the_change_of_the_bit_accurate_image_beyond_the_exact_ones() {
        // 4 pixels x 3 channels; pixel 3 black in all four images: not counted.
        // pixel 0: bit 10 -> 14 (+4), exact 10 -> 10 (0): 4, a big one, own 4
        // pixel 1: bit 12 -> 11 (-1), exact 12 -> 13 (+1): 2, own 1
        // pixel 2: bit 0 -> 0, exact 0 -> 5 (lit in one image): 5, big, own 0
        let (a, ea) = (img([10, 12, 0, 0]), img([10, 12, 0, 0]));
        let (b, eb) = (img([14, 11, 0, 0]), img([10, 13, 5, 0]));
        let mut s = RingingSum::default();
        s.add([&a, &ea], [&b, &eb]);
        let r = s.report();
        assert_eq!(r.samples, 9);
        assert_eq!(r.mean_lsb, 33.0 / 9.0);
        assert_eq!(r.share_4lsb, 6.0 / 9.0);
        assert_eq!(r.change_lsb, 15.0 / 9.0);
        // a frame against itself: no ringing, no change
        let mut z = RingingSum::default();
        z.add([&a, &ea], [&a, &ea]);
        assert_eq!((z.report().mean_lsb, z.report().change_lsb), (0.0, 0.0));
        assert_eq!(RingingSum::default().report().samples, 0);
    }
}

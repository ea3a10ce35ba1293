//! The raster operations unit (ROP): depth test, alpha test, framebuffer blending and the
//! colour write in the framebuffer's format, for the fragments that leave the pipe.
//!
//! Unlike the other units the ROP has state, the framebuffer, and its result depends on the
//! order of the fragments, so it is not a [`crate::unit::Unit`] (whose evaluation is a pure
//! function of one fragment's inputs): the simulator drives [`Rop::write`] in the order the
//! fragments leave the last stage (which is their rasterization order: the pipe is in order).
//! The operations and their order are OpenGL 1.2's per-fragment operations (§4.1: alpha test,
//! depth test, blending) and Direct3D's, which NV20-class parts implement:
//!
//! 1. **Alpha test** (`alpha_test: (func, reference)`): the fragment's alpha rounded to 8 bits
//!    (as NV2A does: `../shared/nv2a/README.md`) compared with an 8-bit reference; a fragment
//!    that fails is dropped before the depth test.
//! 2. **Depth test** (`depth`): the fragment's window depth code against the buffer's; a pass
//!    writes depth (unless `depth_write` is off).
//! 3. **Blending** (`blend: (src, dst)`): `c = src_factor * src + dst_factor * dst`, clamped to 1.
//! 4. **Colour write** in the framebuffer format, unsigned `color_bits` per channel
//!    (`c / (2^bits - 1)`).
//!
//! Bit-accurate mode converts the incoming colour into framebuffer codes by rounding the exact
//! value half up (`floor(x (2^b - 1) + 1/2)`, clamped), blends on the codes (8-bit factor
//! codes, products exact, one rounding to nearest of the sum divided by `2^b - 1`) and stores
//! codes. Exact mode keeps f64 colours without rounding. In both modes the unit also keeps the
//! colour value that reached it (clamped to [0, 1], blended in f64 with the destination as the
//! framebuffer holds it: its codes in bit-accurate mode, so that a blend pass reads back what
//! an earlier pass stored): the measure of the engine's error before the framebuffer's last
//! rounding.

use crate::format::{Codec, Encoding};
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, Word};
use serde::{Deserialize, Serialize};

/// A comparison of the alpha and depth tests: `incoming FUNC stored` (GL's names).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Compare {
    Never,
    #[default]
    Less,
    Equal,
    LEqual,
    Greater,
    NotEqual,
    GEqual,
    Always,
}

impl Compare {
    #[inline]
    pub fn test<T: PartialOrd>(self, a: T, b: T) -> bool {
        match self {
            Compare::Never => false,
            Compare::Less => a < b,
            Compare::Equal => a == b,
            Compare::LEqual => a <= b,
            Compare::Greater => a > b,
            Compare::NotEqual => a != b,
            Compare::GEqual => a >= b,
            Compare::Always => true,
        }
    }
}

/// A blend factor (GL 1.2 table 4.1 without the destination alpha ones: the framebuffer holds
/// RGB).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Factor {
    Zero,
    One,
    SrcColor,
    OneMinusSrcColor,
    DstColor,
    OneMinusDstColor,
    SrcAlpha,
    OneMinusSrcAlpha,
}

impl Factor {
    /// The factor for channel values `s`, `d` and source alpha `a`, all in [0, `one`].
    #[inline]
    fn of<T: Copy + std::ops::Sub<Output = T>>(self, s: T, d: T, a: T, zero: T, one: T) -> T {
        match self {
            Factor::Zero => zero,
            Factor::One => one,
            Factor::SrcColor => s,
            Factor::OneMinusSrcColor => one - s,
            Factor::DstColor => d,
            Factor::OneMinusDstColor => one - d,
            Factor::SrcAlpha => a,
            Factor::OneMinusSrcAlpha => one - a,
        }
    }
    fn reads_alpha(self) -> bool {
        matches!(self, Factor::SrcAlpha | Factor::OneMinusSrcAlpha)
    }
}

/// The ROP's configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RopParams {
    /// Depth test (default `Less`; `Always` turns it off).
    #[serde(default)]
    pub depth: Compare,
    /// Whether a fragment that passes writes its depth (default yes).
    #[serde(default = "yes")]
    pub depth_write: bool,
    /// Alpha test: the function and the 8-bit reference (default none).
    #[serde(default)]
    pub alpha_test: Option<(Compare, u8)>,
    /// Blending: the source and destination factors (default none: replace).
    #[serde(default)]
    pub blend: Option<(Factor, Factor)>,
    /// Bits per framebuffer channel, 1 to 16 (default 8).
    #[serde(default = "eight")]
    pub color_bits: u32,
}

fn yes() -> bool {
    true
}
fn eight() -> u32 {
    8
}

impl Default for RopParams {
    fn default() -> Self {
        RopParams {
            depth: Compare::Less,
            depth_write: true,
            alpha_test: None,
            blend: None,
            color_bits: 8,
        }
    }
}

impl RopParams {
    /// Whether the defaults are in use (an engine without a `rop` field).
    pub fn is_default(&self) -> bool {
        *self == RopParams::default()
    }
    /// Whether the unit reads the fragment's alpha.
    pub fn reads_alpha(&self) -> bool {
        self.alpha_test.is_some()
            || self
                .blend
                .is_some_and(|(s, d)| s.reads_alpha() || d.reads_alpha())
    }
}

/// One framebuffer pixel: the stored codes, and the colour value that reached it (see the
/// module documentation).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Pixel {
    pub code: [i64; 3],
    pub x: [f64; 3],
}

/// The framebuffer: colour and depth per pixel. The two halves of each [`Pixel`] are kept
/// apart, the codes in 16 bits (`color_bits` is at most 16), so a caller can take either
/// whole: 30 bytes of colour per pixel instead of 48.
#[derive(Debug, Clone)]
pub struct Framebuffer {
    pub width: u32,
    pub height: u32,
    /// The stored codes ([`Pixel::code`]).
    pub code: Vec<[u16; 3]>,
    /// The colour values that reached the pixels ([`Pixel::x`]).
    pub x: Vec<[f64; 3]>,
    pub depth: Vec<u32>,
    /// Pixels written at least once.
    pub written: Vec<bool>,
}

impl Framebuffer {
    /// Pixel `i`.
    pub fn pixel(&self, i: usize) -> Pixel {
        Pixel {
            code: self.code[i].map(i64::from),
            x: self.x[i],
        }
    }

    /// Set pixel `i` (codes from 0 to `2^16 - 1`).
    pub fn set_pixel(&mut self, i: usize, p: Pixel) {
        self.code[i] = p.code.map(|c| c as u16);
        self.x[i] = p.x;
    }
}

/// What happened to one fragment at the ROP.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Dropped by the alpha test (reads no depth).
    AlphaFailed,
    /// Failed the depth test (read depth).
    DepthFailed,
    /// Written (read depth, wrote colour and depth; read colour if blending).
    Written,
}

/// The ROP. See the module documentation.
#[derive(Debug, Clone)]
pub struct Rop {
    params: RopParams,
    color: Encoding,
    alpha: Option<Encoding>,
    depth_bits: u32,
}

/// `floor(num / den + 1/2)` for `den > 0`, as the hardware's round-half-up. In 64-bit
/// arithmetic when the operands fit (the usual case, and several times faster than the
/// 128-bit division), the same quotient either way.
#[inline]
fn div_round(num: i128, den: i128) -> i128 {
    let small = i64::try_from(num).ok().zip(i64::try_from(den).ok());
    if let Some((n, d)) = small {
        let t = n.checked_mul(2).and_then(|t| t.checked_add(d));
        if let Some((t, d2)) = t.zip(d.checked_mul(2)) {
            return i128::from(t.div_euclid(d2));
        }
    }
    (2 * num + den).div_euclid(2 * den)
}

/// The exact rational value of a raw word: `(numerator, denominator)`.
#[inline]
fn rational(enc: &Encoding, raw: i64) -> (i128, i128) {
    let n = enc.format.width as u32;
    let r = raw as i128;
    match enc.codec {
        Codec::Fixed => (r, 1i128 << enc.format.frac),
        Codec::UnitUnsigned => (r, (1i128 << n) - 1),
        Codec::UnitSigned => (r, 1i128 << (n - 1)),
        Codec::UnitSymmetric => (2 * r + 1, (1i128 << n) - 1),
    }
}

impl Rop {
    /// A ROP for colours of encoding `color`, alpha of encoding `alpha` (if the engine gives
    /// one) and a `depth_bits`-bit depth buffer. Errors name the field.
    pub fn new(
        params: RopParams,
        color: Encoding,
        alpha: Option<Encoding>,
        depth_bits: u32,
    ) -> Result<Self, String> {
        if !(1..=16).contains(&params.color_bits) {
            return Err(format!(
                "rop.color_bits {}: expected 1 to 16",
                params.color_bits
            ));
        }
        if params.reads_alpha() && alpha.is_none() {
            return Err("rop: the alpha test or an alpha blend factor reads alpha: expected an engine output of 4 lanes (RGBA)".into());
        }
        Ok(Rop {
            params,
            color,
            alpha,
            depth_bits: depth_bits.clamp(1, 32),
        })
    }

    pub fn params(&self) -> &RopParams {
        &self.params
    }
    /// The encoding of the incoming colour.
    pub fn color(&self) -> Encoding {
        self.color
    }
    /// The encoding of the incoming alpha, if the unit reads it.
    pub fn alpha(&self) -> Option<Encoding> {
        self.alpha
    }
    /// Bits of a depth code.
    pub fn depth_bits(&self) -> u32 {
        self.depth_bits
    }

    /// The largest framebuffer code.
    pub fn one(&self) -> i64 {
        (1i64 << self.params.color_bits) - 1
    }

    /// A cleared framebuffer: colour 0, depth the largest code.
    pub fn clear(&self, width: u32, height: u32) -> Framebuffer {
        let n = (width as usize) * (height as usize);
        Framebuffer {
            width,
            height,
            code: vec![[0; 3]; n],
            x: vec![[0.0; 3]; n],
            depth: vec![(u64::MAX >> (64 - self.depth_bits)) as u32; n],
            written: vec![false; n],
        }
    }

    /// The framebuffer code of lane `l` of `w` (rounded half up, clamped).
    #[inline]
    fn code_of(&self, enc: &Encoding, w: &Word, l: usize) -> i64 {
        let (num, den) = rational(enc, w.lanes[l].raw);
        div_round(num * self.one() as i128, den).clamp(0, self.one() as i128) as i64
    }

    /// The 8-bit alpha code of the fragment.
    #[inline]
    fn alpha_code(&self, w: &Word, mode: Mode) -> i64 {
        let enc = self.alpha.expect("checked in new");
        match mode {
            Mode::BitAccurate => {
                let (num, den) = rational(&enc, w.lanes[3].raw);
                div_round(num * 255, den).clamp(0, 255) as i64
            }
            Mode::Exact => (w.lanes[3].x.clamp(0.0, 1.0) * 255.0 + 0.5).floor() as i64,
        }
    }

    /// Write one fragment of colour `c` (3 or 4 lanes of the colour encoding; lane 3 alpha)
    /// at pixel index `i` with depth code `depth`, in `mode`.
    pub fn write(
        &self,
        fb: &mut Framebuffer,
        mode: Mode,
        i: usize,
        depth: u32,
        c: &Word,
    ) -> Outcome {
        let (outcome, px) = self.resolve(mode, depth, c, &fb.pixel(i), fb.depth[i]);
        if outcome == Outcome::Written {
            if self.params.depth_write {
                fb.depth[i] = depth;
            }
            fb.set_pixel(i, px);
            fb.written[i] = true;
        }
        outcome
    }

    /// What the unit does with one fragment of colour `c` and depth code `depth` on a pixel
    /// holding `dst` at depth `dst_depth`, in `mode`: the outcome and the pixel it writes
    /// (`dst` unchanged unless written). A pure function: [`Rop::write`] applies it to the
    /// framebuffer, [`crate::units::RopDatapath`] is it as a unit (its Verilog,
    /// co-simulation and synthesis).
    pub fn resolve(
        &self,
        mode: Mode,
        depth: u32,
        c: &Word,
        dst: &Pixel,
        dst_depth: u32,
    ) -> (Outcome, Pixel) {
        if let Some((func, reference)) = self.params.alpha_test {
            if !func.test(self.alpha_code(c, mode), i64::from(reference)) {
                return (Outcome::AlphaFailed, *dst);
            }
        }
        if !self.params.depth.test(depth, dst_depth) {
            return (Outcome::DepthFailed, *dst);
        }
        let x: [f64; 3] = std::array::from_fn(|l| c.lanes[l].x.clamp(0.0, 1.0));
        let (mut px, one) = (Pixel::default(), self.one());
        match self.params.blend {
            None => {
                px.x = x;
                px.code = match mode {
                    Mode::BitAccurate => std::array::from_fn(|l| self.code_of(&self.color, c, l)),
                    Mode::Exact => x.map(|v| (v * one as f64 + 0.5).floor() as i64),
                };
            }
            Some((fs, fd)) => {
                let a = if self.alpha.is_some() {
                    c.lanes[3].x.clamp(0.0, 1.0)
                } else {
                    1.0
                };
                // the destination as the framebuffer holds it: its codes in bit-accurate mode
                // (a blend pass reads back what an earlier pass stored), its value in exact mode
                let d_of = |l: usize| match mode {
                    Mode::BitAccurate => dst.code[l] as f64 / one as f64,
                    Mode::Exact => dst.x[l],
                };
                px.x = std::array::from_fn(|l| {
                    let (s, d) = (x[l], d_of(l));
                    (fs.of(s, d, a, 0.0, 1.0) * s + fd.of(s, d, a, 0.0, 1.0) * d).min(1.0)
                });
                match mode {
                    Mode::Exact => px.code = px.x.map(|v| (v * one as f64 + 0.5).floor() as i64),
                    Mode::BitAccurate => {
                        // the source in framebuffer codes, alpha in 8 bits scaled to them
                        let a = if self.alpha.is_some() {
                            let a8 = self.alpha_code(c, mode) as i128;
                            div_round(a8 * one as i128, 255) as i64
                        } else {
                            one
                        };
                        for l in 0..3 {
                            let (s, d) = (self.code_of(&self.color, c, l), dst.code[l]);
                            let sum = fs.of(s, d, a, 0, one) as i128 * s as i128
                                + fd.of(s, d, a, 0, one) as i128 * d as i128;
                            px.code[l] = div_round(sum, one as i128).min(one as i128) as i64;
                        }
                    }
                }
            }
        }
        (Outcome::Written, px)
    }

    /// Gate estimate, item for item the datapath of its Verilog (`rtl::rop`): the colour
    /// conversion per channel ([`conversion`]), the depth test (a magnitude comparator and an
    /// equality, the function's three bits ANDed and ORed), the alpha conversion and test, the
    /// blender (per channel two 8-way factor selects, two `b x b` products, their sum, the
    /// round-half-up divide by `2^b - 1`, the clamp; alpha scaled to the framebuffer's codes),
    /// the write select (new codes or the stored ones), the host registers holding the pass's
    /// state, the output registers and the sequencer. The framebuffer's read registers are the
    /// memory's, outside the unit (as the texture memories'). yosys: `docs/gates.md`.
    pub fn gates(&self, t: &CostTable) -> GateBudget {
        let p = &self.params;
        let b = p.color_bits;
        let one = self.one() as i128;
        let zb = self.depth_bits;
        let mut g = GateBudget::new();
        let conv = conversion(t, &self.color, b);
        if conv > 0.0 {
            g.add(
                format!("colour conversion {} -> {b}", self.color.width()),
                3,
                conv,
            );
        }
        let mut state = 1; // depth write
        if p.depth != Compare::Always && p.depth != Compare::Never {
            g.add(format!("depth test {zb}"), 1, test_gates(t, zb));
            state += 3;
        }
        let alpha = self.alpha.filter(|_| p.reads_alpha());
        if let Some(a) = alpha {
            let conv = conversion(t, &a, 8);
            if conv > 0.0 {
                g.add(format!("alpha conversion {} -> 8", a.width()), 1, conv);
            }
        }
        if p.alpha_test.is_some() {
            g.add("alpha test 8", 1, test_gates(t, 8));
            state += 11;
        }
        if p.blend.is_some() {
            if alpha.is_some() && b != 8 {
                g.add(
                    format!("alpha scale 8 -> {b}"),
                    1,
                    t.shift_add(8, one as u128) + t.div_round(0, 255 * one, 255),
                );
            }
            // the complements of s, d and alpha are NOTs; 8-way selects of b bits (6 inputs
            // without alpha: its two are the constants 2^b - 1 and 0)
            let ways = if alpha.is_some() { 8 } else { 6 };
            g.add(
                format!("factor select {b}"),
                6,
                t.mux(b, ways) + t.inv * b as f64,
            );
            g.add(format!("blend multiplier {b}x{b}"), 6, t.multiplier(b, b));
            g.add(format!("blend adder {}", 2 * b + 1), 3, t.adder(2 * b + 1));
            g.add(
                format!("divide by {one}"),
                3,
                t.div_round(0, 2 * one * one, one) + t.clamp(b),
            );
            state += 6;
        }
        // the stored codes are kept when a test can fail
        if p.depth != Compare::Always || p.alpha_test.is_some() {
            g.add(format!("write select {}", 3 * b), 1, t.mux(3 * b, 2));
        }
        // named without the count, so that the union of several passes' budgets
        // (`Engine::rop_gates`) keeps the largest
        g.add("state registers", state, t.register(1));
        g.add(
            format!("output registers {}", 3 * b + 2),
            1,
            t.register(3 * b + 2),
        );
        g.add("sequencer", 1, t.sequencer(1));
        g
    }
}

/// A test of `n`-bit operands: a magnitude comparator, an equality (an XOR a bit and the AND
/// tree) and the function's select (three ANDs and the OR).
fn test_gates(t: &CostTable, n: u32) -> f64 {
    t.comparator(n) + t.xor2 * n as f64 + t.and2 * (n - 1) as f64 + 5.0 * t.and2
}

/// The range of the numerator `num` of a word of `enc` (the raw word, or `2 raw + 1` for
/// symmetric codes) and the denominator `den` of its exact value `num / den`.
pub fn conversion_terms(enc: &Encoding) -> ((i128, i128), i128) {
    let n = enc.width();
    let (lo, hi) = (enc.format.min_raw() as i128, enc.format.max_raw() as i128);
    match enc.codec {
        Codec::Fixed => ((lo, hi), 1i128 << enc.format.frac),
        Codec::UnitUnsigned => ((lo, hi), (1i128 << n) - 1),
        Codec::UnitSigned => ((lo, hi), 1i128 << (n - 1)),
        Codec::UnitSymmetric => ((2 * lo + 1, 2 * hi + 1), (1i128 << n) - 1),
    }
}

/// Gates of the conversion of a word of `enc` into a `bits`-bit code, `clamp(round(num
/// (2^bits - 1) / den), 0, 2^bits - 1)` ([`conversion_terms`], `rtl::rop::code`): none for a
/// unit code of that width (the code itself); else the rounding's constant adds, the clamps
/// its range needs and the constant multiplies, which synthesis merges into one constant
/// multiply of the narrow word ([`CostTable::scaled_div`]).
pub fn conversion(t: &CostTable, enc: &Encoding, bits: u32) -> f64 {
    if enc.codec == Codec::UnitUnsigned && enc.width() == bits {
        return 0.0;
    }
    let one = (1i128 << bits) - 1;
    let ((lo, hi), den) = conversion_terms(enc);
    let w = crate::arith::bit_length(lo.unsigned_abs().max(hi.unsigned_abs())) + 1;
    let q = |x: i128| (2 * x * one + den).div_euclid(2 * den);
    let clamps = u32::from(q(lo) < 0) + u32::from(q(hi) > one);
    let clamp = t.clamp(bits) * clamps as f64;
    if one % den == 0 {
        // the division cancels (a symmetric code into its own width: `2 raw + 1`)
        return t.shift_add(w, (one / den) as u128) + clamp;
    }
    t.scaled_div(lo, hi, one, den) + clamp
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::Format;

    fn word(enc: &Encoding, mode: Mode, xs: &[f64]) -> Word {
        Word::for_mode(mode, enc, xs)
    }

    #[test]
    fn div_round_fast_path_is_the_128_bit_quotient() {
        let wide = |n: i128, d: i128| (2 * n + d).div_euclid(2 * d);
        // every small pair, signs included, and the edges of the 64-bit range
        for n in -300i128..=300 {
            for d in 1i128..=40 {
                assert_eq!(div_round(n, d), wide(n, d), "{n} / {d}");
            }
        }
        let edge = [
            i64::MIN as i128,
            i64::MIN as i128 + 1,
            -(1 << 62),
            (1 << 62) - 1,
        ];
        let edge = edge
            .into_iter()
            .chain([1 << 62, i64::MAX as i128, 1 << 80, -(1 << 80)]);
        for n in edge {
            for d in [
                1i128,
                3,
                255,
                (1 << 62) - 1,
                1 << 62,
                i64::MAX as i128,
                1 << 70,
            ] {
                assert_eq!(div_round(n, d), wide(n, d), "{n} / {d}");
            }
        }
    }

    #[test]
    fn the_colour_write_rounds_half_up_like_the_png_writer_for_every_10_bit_code() {
        let enc = Encoding::fixed(Format::u(10, 9)); // [0, 2)
        let rop = Rop::new(RopParams::default(), enc, None, 16).unwrap();
        let mut fb = rop.clear(1, 1);
        for raw in 0..1024 {
            let w = Word::from_raw(&enc, &[raw, raw, raw]);
            fb.depth[0] = u32::MAX;
            assert_eq!(
                rop.write(&mut fb, Mode::BitAccurate, 0, 5, &w),
                Outcome::Written
            );
            let x = enc.decode(raw).clamp(0.0, 1.0);
            assert_eq!(
                fb.pixel(0).code[0],
                (x * 255.0 + 0.5).floor() as i64,
                "raw {raw}"
            );
            assert_eq!(fb.pixel(0).x[0], x);
        }
    }

    #[test]
    fn every_test_function_at_every_8_bit_reference_and_alpha() {
        let enc = Encoding::texel(Codec::UnitUnsigned, false, 8);
        for func in [
            Compare::Never,
            Compare::Less,
            Compare::Equal,
            Compare::LEqual,
            Compare::Greater,
            Compare::NotEqual,
            Compare::GEqual,
            Compare::Always,
        ] {
            for reference in 0..=255u8 {
                let params = RopParams {
                    alpha_test: Some((func, reference)),
                    depth: Compare::Always,
                    ..RopParams::default()
                };
                let rop = Rop::new(params, enc, Some(enc), 16).unwrap();
                let mut fb = rop.clear(1, 1);
                for a in 0..=255i64 {
                    for mode in [Mode::BitAccurate, Mode::Exact] {
                        let w = match mode {
                            Mode::BitAccurate => Word::from_raw(&enc, &[0, 0, 0, a]),
                            Mode::Exact => {
                                Word::from_exact(&enc, &[0.0, 0.0, 0.0, a as f64 / 255.0])
                            }
                        };
                        let pass = rop.write(&mut fb, mode, 0, 0, &w) == Outcome::Written;
                        assert_eq!(
                            pass,
                            func.test(a, i64::from(reference)),
                            "{func:?} {reference} {a}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn depth_functions_and_depth_write() {
        let enc = Encoding::texel(Codec::UnitUnsigned, false, 8);
        let w = Word::from_raw(&enc, &[10, 20, 30]);
        let rop = Rop::new(RopParams::default(), enc, None, 8).unwrap();
        let mut fb = rop.clear(1, 1);
        assert_eq!(fb.depth[0], 255);
        assert_eq!(
            rop.write(&mut fb, Mode::BitAccurate, 0, 100, &w),
            Outcome::Written
        );
        assert_eq!(
            rop.write(&mut fb, Mode::BitAccurate, 0, 100, &w),
            Outcome::DepthFailed
        );
        assert_eq!(
            rop.write(&mut fb, Mode::BitAccurate, 0, 99, &w),
            Outcome::Written
        );
        assert_eq!((fb.depth[0], fb.pixel(0).code), (99, [10, 20, 30]));
        let keep = RopParams {
            depth: Compare::LEqual,
            depth_write: false,
            ..RopParams::default()
        };
        let rop = Rop::new(keep, enc, None, 8).unwrap();
        let mut fb = rop.clear(1, 1);
        assert_eq!(
            rop.write(&mut fb, Mode::BitAccurate, 0, 255, &w),
            Outcome::Written
        );
        assert_eq!(fb.depth[0], 255);
    }

    #[test]
    fn src_alpha_blending_rounds_to_nearest_on_8_bit_codes() {
        let enc = Encoding::texel(Codec::UnitUnsigned, false, 8);
        let params = RopParams {
            depth: Compare::Always,
            blend: Some((Factor::SrcAlpha, Factor::OneMinusSrcAlpha)),
            ..RopParams::default()
        };
        let rop = Rop::new(params, enc, Some(enc), 16).unwrap();
        // every source, destination and alpha code of a coarse grid against the exact rational
        for s in (0..=255i64).step_by(5) {
            for d in (0..=255i64).step_by(7) {
                for a in (0..=255i64).step_by(3) {
                    let mut fb = rop.clear(1, 1);
                    fb.code[0] = [d as u16; 3];
                    let w = Word::from_raw(&enc, &[s, s, s, a]);
                    rop.write(&mut fb, Mode::BitAccurate, 0, 0, &w);
                    let want = ((s * a + d * (255 - a)) as f64 / 255.0 + 0.5).floor() as i64;
                    assert_eq!(fb.pixel(0).code[0], want, "s {s} d {d} a {a}");
                }
            }
        }
        // additive blending saturates
        let add = RopParams {
            blend: Some((Factor::One, Factor::One)),
            depth: Compare::Always,
            ..RopParams::default()
        };
        let rop = Rop::new(add, enc, None, 16).unwrap();
        let mut fb = rop.clear(1, 1);
        for mode in [Mode::BitAccurate, Mode::Exact] {
            fb.set_pixel(0, Pixel::default());
            for _ in 0..3 {
                rop.write(&mut fb, mode, 0, 0, &word(&enc, mode, &[0.4, 0.2, 0.0]));
            }
            assert_eq!(fb.pixel(0).code, [255, 153, 0], "{mode:?}");
            assert!((fb.pixel(0).x[1] - 0.6).abs() < 1e-12);
        }
    }

    #[test]
    fn bad_parameters_are_rejected() {
        let enc = Encoding::texel(Codec::UnitUnsigned, false, 8);
        let alpha = RopParams {
            alpha_test: Some((Compare::Greater, 0)),
            ..RopParams::default()
        };
        assert!(Rop::new(alpha, enc, None, 16)
            .unwrap_err()
            .contains("4 lanes"));
        let bits = RopParams {
            color_bits: 0,
            ..RopParams::default()
        };
        assert!(Rop::new(bits, enc, None, 16)
            .unwrap_err()
            .contains("color_bits"));
        let g = Rop::new(RopParams::default(), enc, None, 24)
            .unwrap()
            .gates(&CostTable::default());
        assert!(g.total() > 0.0);
    }
}

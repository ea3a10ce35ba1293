//! The sampler: the one texel addressing and filtering datapath of the engine, used by every
//! unit that reads a [`Texture`] (texel fetches, the emboss filter, the quantized-normal
//! index fetch, texture-shader stages).
//!
//! * Addressing: from a fixed-point texture coordinate to a texel index and filter weight on
//!   one axis ([`texel_axis`]), and what happens to an index outside the texture
//!   ([`Address`]). Texture sizes are powers of two, so the texel address is a shift of the
//!   coordinate (an arithmetic shift: negative coordinates floor, as the hardware's
//!   two's-complement shifter does).
//! * Filtering ([`Sampler`]): nearest or bilinear, the bilinear weights truncated to
//!   `weight_bits` bits of the coordinate's fraction, exact products and one cast of the
//!   filtered value into the output encoding (the filtered vector is not renormalised, as in
//!   the hardware of the period). Exact mode reads the unquantized texels with exact weights.
//! * Mip selection: [`Texture::nearest_level`].
//! * Cube maps: the face and face coordinates of a direction ([`cube_face`],
//!   [`cube_face_bits`]), OpenGL 1.3 §3.8.6.

use crate::arith::{Acc, Reader, Writer};
use crate::format::Encoding;
use crate::texture::{Level, Texture};
use crate::unit::MAX_LANES;

/// What happens to a texel address outside the texture, per axis (OpenGL's texture wrap
/// modes: REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, Default)]
pub enum Address {
    /// The texture repeats: texel `i mod n`.
    #[default]
    Wrap,
    /// The edge texel repeats: texel `clamp(i, 0, n - 1)`; a coordinate of exactly 1 reads
    /// the last texel (as lookup tables indexed by a dot product need).
    Clamp,
    /// The texture repeats mirrored every other period.
    Mirror,
}

impl Address {
    /// Texel index along an axis of `n` texels.
    #[inline]
    pub fn apply(self, i: i64, n: i64) -> i64 {
        // a power-of-two side (every texture's) takes the remainder as a mask, as the
        // hardware does: the same index as `rem_euclid` without a division
        let rem = |i: i64, n: i64| {
            if n > 0 && n & (n - 1) == 0 {
                i & (n - 1)
            } else {
                i.rem_euclid(n)
            }
        };
        match self {
            Address::Wrap => rem(i, n),
            Address::Clamp => i.clamp(0, n - 1),
            Address::Mirror => {
                let m = rem(i, 2 * n);
                if m >= n {
                    2 * n - 1 - m
                } else {
                    m
                }
            }
        }
    }
}

/// Texel position along one axis of `2^log` texels for a coordinate `raw` with `frac`
/// fraction bits (`frac >= log`, and `frac > log` when `centered`): `s = c * size - 1/2` when `centered` (bilinear filtering: the
/// taps around the sample point), `c * size` otherwise (nearest, or a filter over whole texels);
/// returns (integer part, fraction raw with `frac - log` bits).
#[inline]
pub fn texel_axis(raw: i64, frac: u32, log: u32, centered: bool) -> (i64, i64) {
    let f = frac - log; // fraction bits left after multiplying by 2^log
    let mut s = raw as i128;
    if centered {
        s -= 1i128 << (f - 1);
    }
    ((s >> f) as i64, (s & ((1i128 << f) - 1)) as i64)
}

/// Texel filter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, Default)]
pub enum Filter {
    Nearest,
    #[default]
    Bilinear,
}

/// A texture sampler: filter, weight width and address modes. See the module documentation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sampler {
    filter: Filter,
    weight_bits: u32,
    address: [Address; 2],
}

impl Sampler {
    /// `weight_bits` 1 to 16 (bilinear weights); wrap addressing on both axes.
    pub fn new(filter: Filter, weight_bits: u32) -> Result<Self, String> {
        if !(1..=16).contains(&weight_bits) {
            return Err(format!("weight_bits {weight_bits}: expected 1 to 16"));
        }
        Ok(Sampler {
            filter,
            weight_bits,
            address: [Address::Wrap; 2],
        })
    }
    /// Address modes along s and t.
    pub fn with_address(mut self, s: Address, t: Address) -> Self {
        self.address = [s, t];
        self
    }
    pub fn filter(&self) -> Filter {
        self.filter
    }
    pub fn weight_bits(&self) -> u32 {
        self.weight_bits
    }
    pub fn address(&self) -> [Address; 2] {
        self.address
    }
    /// Texels read per sample.
    pub fn taps(&self) -> u32 {
        match self.filter {
            Filter::Nearest => 1,
            Filter::Bilinear => 4,
        }
    }
    /// Check that coordinates of encoding `coord` address every texel of `tex` (at least
    /// `log2 side + 1` fraction bits, for the bilinear half-texel offset).
    pub fn check(&self, tex: &Texture, coord: &Encoding) -> Result<(), String> {
        let l = tex.level_at(0);
        let (log_w, log_h) = l.logs();
        if (coord.format.frac as u32) < log_w.max(log_h) + 1 {
            return Err(format!(
                "texture coordinate format {} has too few fraction bits for a {}x{} texture: expected at least {}",
                coord.format,
                l.width(),
                l.height(),
                log_w.max(log_h) + 1
            ));
        }
        Ok(())
    }

    /// Memory index of texel (i, j) of `face` of level `l`, after addressing.
    #[inline]
    pub fn index(&self, l: &Level, face: usize, i: i64, j: i64) -> usize {
        l.index(face, i, j, self.address)
    }

    /// The filtered texel at real coordinates (s, t) of `face` of level `level` (exact mode).
    pub fn sample_exact(
        &self,
        tex: &Texture,
        level: usize,
        face: usize,
        s: f64,
        t: f64,
    ) -> [f64; MAX_LANES] {
        let l = tex.level_at(level);
        let (w, h) = (l.width() as f64, l.height() as f64);
        let get = |i: i64, j: i64| *l.value(self.index(l, face, i, j));
        match self.filter {
            Filter::Nearest => get((s * w).floor() as i64, (t * h).floor() as i64),
            Filter::Bilinear => {
                let (su, sv) = (s * w - 0.5, t * h - 0.5);
                let (i, j) = (su.floor(), sv.floor());
                let (fu, fv) = (su - i, sv - j);
                let (i, j) = (i as i64, j as i64);
                let (t00, t10, t01, t11) =
                    (get(i, j), get(i + 1, j), get(i, j + 1), get(i + 1, j + 1));
                std::array::from_fn(|k| {
                    let top = t00[k] + (t10[k] - t00[k]) * fu;
                    let bot = t01[k] + (t11[k] - t01[k]) * fu;
                    top + (bot - top) * fv
                })
            }
        }
    }

    /// The casts of [`Sampler::sample_bits`] from texels of encoding `texel` into `out`,
    /// planned once (a unit that always reads one texel format into one port keeps its plan).
    pub fn plan(&self, texel: &Encoding, out: &Encoding) -> SamplePlan {
        let read = Reader::new(texel);
        let wb = self.weight_bits;
        SamplePlan {
            texel: *texel,
            out: *out,
            nearest: read.map(|r| (r, Writer::new(r.frac, out))),
            bilinear: read
                .filter(|r| r.bits + 2 * wb <= 62)
                .map(|r| (r, Writer::new(r.frac + 2 * wb, out))),
        }
    }

    /// The filtered texel at raw coordinates (s, t) with `frac` fraction bits, as raw words of
    /// the output encoding of `plan` (made by [`Sampler::plan`] for this texture's texel
    /// encoding; bit-accurate mode). Lanes beyond the texture's are 0.
    #[allow(clippy::too_many_arguments)]
    pub fn sample_bits(
        &self,
        tex: &Texture,
        level: usize,
        face: usize,
        s: i64,
        t: i64,
        frac: u32,
        plan: &SamplePlan,
    ) -> [i64; MAX_LANES] {
        debug_assert_eq!(
            plan.texel,
            *tex.texel(),
            "a plan for another texel encoding"
        );
        let l = tex.level_at(level);
        let (log_w, log_h) = l.logs();
        let centered = self.filter == Filter::Bilinear;
        let (i, fu) = texel_axis(s, frac, log_w, centered);
        let (j, fv) = texel_axis(t, frac, log_h, centered);
        let (texel, out) = (&plan.texel, &plan.out);
        let lanes = tex.lanes() as usize;
        let mut res = [0i64; MAX_LANES];
        match self.filter {
            Filter::Nearest => {
                let code = l.code(self.index(l, face, i, j));
                for (r, &c) in res.iter_mut().zip(code).take(lanes) {
                    *r = match &plan.nearest {
                        Some((read, write)) => write.write(read.read(c)),
                        None => Acc::from_code(c, texel).to_code(out),
                    };
                }
            }
            Filter::Bilinear => {
                // weights truncated to weight_bits of the coordinate fraction
                let wb = self.weight_bits;
                let trunc = |f: i64, bits: u32| {
                    if bits >= wb {
                        f >> (bits - wb)
                    } else {
                        f << (wb - bits)
                    }
                };
                let (wu, wv) = (trunc(fu, frac - log_w), trunc(fv, frac - log_h));
                let taps = [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)]
                    .map(|(a, b)| l.code(self.index(l, face, a, b)));
                res = bilinear(
                    taps,
                    texel,
                    lanes,
                    [wu, wv],
                    wb,
                    out,
                    plan.bilinear.as_ref(),
                );
            }
        }
        res
    }
}

/// The casts of one texel encoding into one output encoding ([`Sampler::plan`]): the texel's
/// [`Reader`] and the [`Writer`] of a nearest texel and of a bilinear sum, where they fit in
/// `i64`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SamplePlan {
    texel: Encoding,
    out: Encoding,
    nearest: Option<(Reader, Writer)>,
    bilinear: Option<(Reader, Writer)>,
}

/// The bilinear filter of four taps' codes (t00, t10, t01, t11) of encoding `texel`, with
/// weights `w = [wu, wv]` of `wb` bits, cast into `out`: the exact `a (1 - w) + b w` along u,
/// then along v. With `narrow` (the texel's [`Reader`], its readings and two weights within
/// 62 bits, and the [`Writer`] of the sum into `out`) the same integers are summed in `i64`
/// instead of `i128`.
fn bilinear(
    taps: [&[i64; MAX_LANES]; 4],
    texel: &Encoding,
    lanes: usize,
    w: [i64; 2],
    wb: u32,
    out: &Encoding,
    narrow: Option<&(Reader, Writer)>,
) -> [i64; MAX_LANES] {
    let mut res = [0i64; MAX_LANES];
    if let Some((r, write)) = narrow {
        let full = 1i64 << wb;
        let lerp = |a: i64, b: i64, w: i64| a * (full - w) + b * w;
        for (lane, o) in res.iter_mut().enumerate().take(lanes) {
            let c = |k: usize| r.read(taps[k][lane]);
            let top = lerp(c(0), c(1), w[0]);
            let bot = lerp(c(2), c(3), w[0]);
            *o = write.write(lerp(top, bot, w[1]));
        }
        return res;
    }
    let one = Acc::new(1, 0);
    let (wu, wv) = (Acc::new(w[0] as i128, wb), Acc::new(w[1] as i128, wb));
    let lerp = |a: Acc, b: Acc, w: Acc| a.mul(one.sub(w)).add(b.mul(w));
    for (lane, o) in res.iter_mut().enumerate().take(lanes) {
        let c = |k: usize| Acc::from_code(taps[k][lane], texel);
        let top = lerp(c(0), c(1), wu);
        let bot = lerp(c(2), c(3), wu);
        *o = lerp(top, bot, wv).to_code(out);
    }
    res
}

/// The major axis of a cube-map direction: (face, sc, tc, ma) by OpenGL 1.3 table 3.19, faces
/// +X, -X, +Y, -Y, +Z, -Z = 0..5. Ties go to x before y before z (the spec leaves them open).
#[inline]
fn major<T: Copy + PartialOrd + std::ops::Neg<Output = T>>(
    d: [T; 3],
    abs: impl Fn(T) -> T,
    zero: T,
) -> (usize, T, T, T) {
    let [x, y, z] = d;
    let (ax, ay, az) = (abs(x), abs(y), abs(z));
    if ax >= ay && ax >= az {
        if x >= zero {
            (0, -z, -y, ax)
        } else {
            (1, z, -y, ax)
        }
    } else if ay >= az {
        if y >= zero {
            (2, x, z, ay)
        } else {
            (3, x, -z, ay)
        }
    } else if z >= zero {
        (4, x, -y, az)
    } else {
        (5, -x, -y, az)
    }
}

/// Face and coordinates `s = (sc / |ma| + 1) / 2`, `t = (tc / |ma| + 1) / 2` of direction
/// `d` (exact mode). A zero direction reads the centre of face +X.
pub fn cube_face(d: [f64; 3]) -> (usize, f64, f64) {
    let (f, sc, tc, ma) = major(d, f64::abs, 0.0);
    if ma == 0.0 {
        return (0, 0.5, 0.5);
    }
    (f, (sc / ma + 1.0) * 0.5, (tc / ma + 1.0) * 0.5)
}

/// [`cube_face`] on raw direction words of one format (bit-accurate mode): the face from
/// comparisons of magnitudes, and `s`, `t` as raw words with `frac` fraction bits from one
/// divider, `round((sc + |ma|) 2^frac / (2 |ma|))` (correctly rounded, half up; the
/// projection's divider is modelled exact at the output width).
pub fn cube_face_bits(d: [i64; 3], frac: u32) -> (usize, i64, i64) {
    let (f, sc, tc, ma) = major(d, i64::abs, 0);
    if ma == 0 {
        return (0, 1 << frac.saturating_sub(1), 1 << frac.saturating_sub(1));
    }
    let div = |c: i64| {
        let ma = ma as i128;
        ((((c as i128 + ma) << frac) + ma) / (2 * ma)) as i64
    };
    (f, div(sc), div(tc))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Codec, Format};
    use proptest::prelude::*;

    /// Texel and output encodings of the project's texels (8- and 16-bit unit codes, fixed
    /// point, HILO16) and the widest each path takes.
    fn encodings() -> Vec<Encoding> {
        vec![
            Encoding::texel(Codec::UnitUnsigned, false, 8),
            Encoding::texel(Codec::UnitSigned, true, 8),
            Encoding::texel(Codec::UnitSymmetric, true, 8),
            Encoding::texel(Codec::UnitUnsigned, false, 16),
            Encoding::texel(Codec::UnitSigned, true, 16),
            Encoding::texel(Codec::UnitSymmetric, true, 16),
            Encoding::fixed(Format::s(10, 8)),
            Encoding::fixed(Format::u(16, 12)),
            Encoding::fixed(Format::s(32, 16)),
        ]
    }

    proptest! {
        #[test]
        fn bilinear_in_i64_is_the_i128_filter(
            t in 0usize..9, o in 0usize..9, wb in 1u32..=16,
            codes in prop::array::uniform4(prop::array::uniform4(any::<i64>())),
            w in prop::array::uniform2(any::<u32>()),
        ) {
            let (texel, out) = (encodings()[t], encodings()[o]);
            let f = texel.format;
            let span = (f.max_raw() - f.min_raw()) as u64 + 1;
            let codes = codes.map(|c| c.map(|x| f.min_raw() + (x as u64 % span) as i64));
            let w = w.map(|x| i64::from(x) % ((1i64 << wb) + 1));
            let taps = [&codes[0], &codes[1], &codes[2], &codes[3]];
            let narrow = Reader::new(&texel)
                .filter(|r| r.bits + 2 * wb <= 62)
                .map(|r| (r, Writer::new(r.frac + 2 * wb, &out)));
            prop_assume!(narrow.is_some());
            prop_assert_eq!(
                bilinear(taps, &texel, 4, w, wb, &out, narrow.as_ref()),
                bilinear(taps, &texel, 4, w, wb, &out, None)
            );
        }
    }

    #[test]
    fn bilinear_in_i64_matches_for_every_4_bit_tap_pair_and_weight() {
        // exhaustive at 4-bit texels: every code of two taps (the other two at the ends of
        // the range) and every weight of 4 bits, each codec
        for (codec, signed) in [
            (Codec::UnitUnsigned, false),
            (Codec::UnitSigned, true),
            (Codec::UnitSymmetric, true),
        ] {
            let texel = Encoding::texel(codec, signed, 4);
            let out = Encoding::texel(codec, signed, 8);
            let (lo, hi) = (texel.format.min_raw(), texel.format.max_raw());
            let narrow = Reader::new(&texel).map(|r| (r, Writer::new(r.frac + 8, &out)));
            assert!(narrow.is_some());
            for a in lo..=hi {
                for b in lo..=hi {
                    let codes = [[a, b, lo, hi], [b, a, hi, lo], [lo; 4], [hi; 4]];
                    let taps = [&codes[0], &codes[1], &codes[2], &codes[3]];
                    for wu in 0..=16 {
                        for wv in [0, 1, 7, 8, 15, 16] {
                            assert_eq!(
                                bilinear(taps, &texel, 4, [wu, wv], 4, &out, narrow.as_ref()),
                                bilinear(taps, &texel, 4, [wu, wv], 4, &out, None),
                                "{codec:?} {a} {b} {wu} {wv}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn address_modes_fold_every_index_of_three_periods() {
        for n in [1i64, 2, 3, 4, 5, 8, 4096] {
            for i in -3 * n..3 * n {
                let w = Address::Wrap.apply(i, n);
                assert_eq!(w, ((i % n) + n) % n);
                assert_eq!(Address::Clamp.apply(i, n), i.max(0).min(n - 1));
                // mirrored repeat: 0 1 .. n-1 n-1 .. 1 0 0 1 ..
                let period = i.div_euclid(n);
                let m = Address::Mirror.apply(i, n);
                assert_eq!(
                    m,
                    if period % 2 == 0 { w } else { n - 1 - w },
                    "n {n} i {i}"
                );
            }
        }
    }

    #[test]
    fn cube_faces_follow_the_gl_table_and_the_divider_rounds_to_nearest() {
        // each face's centre and its (s, t) orientation: +X at (1, y, z) has s = (-z + 1) / 2
        let cases = [
            ([1.0, 0.0, -0.5], 0, 0.75, 0.5),
            ([-1.0, 0.5, 0.0], 1, 0.5, 0.25),
            ([0.25, 1.0, 0.5], 2, 0.625, 0.75),
            ([0.25, -1.0, 0.5], 3, 0.625, 0.25),
            ([0.5, 0.0, 1.0], 4, 0.75, 0.5),
            ([0.5, 0.5, -1.0], 5, 0.25, 0.25),
        ];
        for (d, f, s, t) in cases {
            assert_eq!(cube_face(d), (f, s, t), "{d:?}");
        }
        assert_eq!(cube_face([0.0; 3]), (0, 0.5, 0.5));
        // raw directions with 8 fraction bits, s and t with 12: every direction of a small
        // grid agrees with the exact face and within half an output step
        for x in -6i64..=6 {
            for y in -6i64..=6 {
                for z in -6i64..=6 {
                    let d = [x * 37, y * 41, z * 43];
                    let (fe, se, te) = cube_face(d.map(|v| v as f64 / 256.0));
                    let (fb, sb, tb) = cube_face_bits(d, 12);
                    assert_eq!(fb, fe, "{d:?}");
                    for (b, e) in [(sb, se), (tb, te)] {
                        assert!((b as f64 / 4096.0 - e).abs() <= 0.5 / 4096.0, "{d:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_axis_floors_negative_coordinates_and_keeps_the_fraction() {
        // 4 fraction bits, 2 texels (log 1): one texel = 8 raw steps
        for raw in -40i64..40 {
            let (i, f) = texel_axis(raw, 4, 1, false);
            assert_eq!((i, f), (raw.div_euclid(8), raw.rem_euclid(8)), "raw {raw}");
            let (i, f) = texel_axis(raw, 4, 1, true);
            assert_eq!(
                (i, f),
                ((raw - 4).div_euclid(8), (raw - 4).rem_euclid(8)),
                "raw {raw}"
            );
        }
    }
}

//! The dot-product input mappings (NV_texture_shader 3.8.13, "Dot product mappings";
//! NV2A `NV097_SET_DOT_RGBMAPPING`): from the previous stage's texel to the vector N that a
//! dot-product stage multiplies with its (s, t, r).
//!
//! Both modes read the texel as channel codes: an 8-bit channel as its code `x` in 0..=255
//! (a signed texel's code is its two's-complement byte), a 16-bit HI or LO as its code `c`
//! in 0..=65535 (the two lanes of a 16-bit texture, or `A<<8|R` and `G<<8|B` of an 8-bit
//! RGBA texel). Exact mode takes the real code (`255 v`, `128 v`, ... of the possibly
//! filtered value `v`) and evaluates the formula in f64; bit-accurate mode takes the integer
//! code and rounds the formula once to `frac` fraction bits (halves up). The hemisphere
//! `z = sqrt(max(0, 1 - hi^2 - lo^2))` is, in bit-accurate mode, the integer square root
//! (floor) of `max(0, 2^(2 frac) - HI^2 - LO^2)` of the rounded HI and LO words.
//! Texels of other widths are read by value: `v` (ZERO_TO_ONE and two's complement) or
//! `2v - 1` (the D3D and GL expansions).

use super::program::DotMapping;
use crate::arith::Acc;
use crate::format::{Codec, Encoding, Quant};

/// round-half-up(p / d), d > 0.
pub(crate) fn div_round(p: i128, d: i128) -> i128 {
    (2 * p + d).div_euclid(2 * d)
}

/// Integer square root (floor) of v >= 0.
pub(crate) fn isqrt(v: i128) -> i128 {
    if v <= 0 {
        return 0;
    }
    let mut x = (v as f64).sqrt() as i128;
    while x * x > v {
        x -= 1;
    }
    while (x + 1) * (x + 1) <= v {
        x += 1;
    }
    x
}

/// The 8-bit mapping of channel code `x` (real in exact mode).
pub fn map8_exact(m: DotMapping, x: f64) -> f64 {
    match m {
        DotMapping::Minus1To1D3d => (x - 128.0) / 127.0,
        DotMapping::Minus1To1Gl => (2.0 * x + 1.0) / 255.0 - 1.0,
        DotMapping::Minus1To1 => {
            let sx = if x >= 127.5 { x - 256.0 } else { x };
            sx / 127.0
        }
        _ => x / 255.0,
    }
}

/// The 8-bit mapping of channel code `x` as a word with `frac` fraction bits.
pub fn map8_bits(m: DotMapping, x: i64, frac: u32) -> i64 {
    let x = (x & 0xff) as i128;
    let one = 1i128 << frac;
    (match m {
        DotMapping::Minus1To1D3d => div_round((x - 128) * one, 127),
        DotMapping::Minus1To1Gl => div_round((2 * x - 254) * one, 255),
        DotMapping::Minus1To1 => {
            let sx = if x >= 128 { x - 256 } else { x };
            div_round(sx * one, 127)
        }
        _ => div_round(x * one, 255),
    }) as i64
}

/// A 16-bit HI or LO code by the mapping's convention (exact mode, real code).
pub fn map16_exact(m: DotMapping, c: f64) -> f64 {
    match m {
        DotMapping::HiloHemisphereD3d => (c - 32768.0) / 32767.0,
        DotMapping::HiloHemisphereGl => (2.0 * c + 1.0) / 65535.0 - 1.0,
        DotMapping::HiloHemisphere => {
            let sc = if c >= 32767.5 { c - 65536.0 } else { c };
            sc / 32767.0
        }
        _ => c / 65535.0,
    }
}

/// A 16-bit HI or LO code as a word with `frac` fraction bits.
pub fn map16_bits(m: DotMapping, c: i64, frac: u32) -> i64 {
    let c = (c & 0xffff) as i128;
    let one = 1i128 << frac;
    (match m {
        DotMapping::HiloHemisphereD3d => div_round((c - 32768) * one, 32767),
        DotMapping::HiloHemisphereGl => div_round((2 * c - 65534) * one, 65535),
        DotMapping::HiloHemisphere => {
            let sc = if c >= 32768 { c - 65536 } else { c };
            div_round(sc * one, 32767)
        }
        _ => div_round(c * one, 65535),
    }) as i64
}

/// The HILO vector (hi, lo, z) (exact mode).
pub fn hilo_exact(m: DotMapping, hi: f64, lo: f64) -> [f64; 3] {
    let (h, l) = (map16_exact(m, hi), map16_exact(m, lo));
    let z = if m == DotMapping::Hilo1 {
        1.0
    } else {
        (1.0 - h * h - l * l).max(0.0).sqrt()
    };
    [h, l, z]
}

/// The HILO vector as words with `frac` fraction bits.
pub fn hilo_bits(m: DotMapping, hi: i64, lo: i64, frac: u32) -> [i64; 3] {
    let (h, l) = (map16_bits(m, hi, frac), map16_bits(m, lo, frac));
    let z = if m == DotMapping::Hilo1 {
        1i64 << frac
    } else {
        let r = (1i128 << (2 * frac)) - (h as i128).pow(2) - (l as i128).pow(2);
        isqrt(r) as i64
    };
    [h, l, z]
}

/// The real code of a texel lane of encoding `enc` holding value `v` (exact mode): the
/// unsigned code `(2^n - 1) v`, or the two's-complement code of a signed lane, taken
/// modulo `2^n`. A `UnitSigned` lane's code `2^(n-1) v` saturates to
/// `[-2^(n-1), 2^(n-1) - 1]` as the texel's encoder does, so that an unquantized 1.0 (the
/// z of a flat face-space normal) reads as the largest positive code, never as the
/// negative code `2^(n-1)` that the sign test of the mappings would take it for.
pub(crate) fn real_code(v: f64, enc: &Encoding) -> f64 {
    let n = enc.width() as i32;
    let m = (1u64 << n) as f64;
    let c = match enc.codec {
        Codec::UnitUnsigned => v * (m - 1.0),
        Codec::UnitSigned => (v * m / 2.0).clamp(-m / 2.0, m / 2.0 - 1.0),
        Codec::UnitSymmetric => (v * (m - 1.0) - 1.0) / 2.0,
        Codec::Fixed => v * 2f64.powi(enc.format.frac as i32),
    };
    if c < 0.0 {
        c + m
    } else {
        c
    }
}

/// N from a texel of `lanes` lanes (exact mode: `xs` are the lane values).
pub fn vector_exact(m: DotMapping, xs: &[f64; 4], enc: &Encoding, lanes: u8) -> [f64; 3] {
    let w = enc.width();
    if m.is_hilo() {
        let (hi, lo) = if lanes == 2 && w == 16 {
            (real_code(xs[0], enc), real_code(xs[1], enc))
        } else {
            let c = |k: usize| real_code(xs[k], enc);
            (256.0 * c(3) + c(0), 256.0 * c(1) + c(2))
        };
        return hilo_exact(m, hi, lo);
    }
    std::array::from_fn(|k| {
        if w == 8 {
            map8_exact(m, real_code(xs[k], enc))
        } else {
            match m {
                DotMapping::Minus1To1D3d | DotMapping::Minus1To1Gl => 2.0 * xs[k] - 1.0,
                _ => xs[k],
            }
        }
    })
}

/// N from a texel as words with `frac` fraction bits (bit-accurate mode: `raws` are the
/// lane codes).
pub fn vector_bits(
    m: DotMapping,
    raws: &[i64; 4],
    enc: &Encoding,
    lanes: u8,
    frac: u32,
) -> [i64; 3] {
    let w = enc.width();
    if m.is_hilo() {
        let (hi, lo) = if lanes == 2 && w == 16 {
            (raws[0] & 0xffff, raws[1] & 0xffff)
        } else {
            let c = |k: usize| raws[k] & 0xff;
            ((c(3) << 8) | c(0), (c(1) << 8) | c(2))
        };
        return hilo_bits(m, hi, lo, frac);
    }
    std::array::from_fn(|k| {
        if w == 8 {
            map8_bits(m, raws[k], frac)
        } else {
            let v = Acc::from_code(raws[k], enc);
            let v = match m {
                DotMapping::Minus1To1D3d | DotMapping::Minus1To1Gl => {
                    v.scale(2).sub(Acc::new(1, 0))
                }
                _ => v,
            };
            crate::format::shift_round(v.raw, v.frac.saturating_sub(frac), Quant::Rnd) as i64
                * if v.frac < frac {
                    1 << (frac - v.frac)
                } else {
                    1
                }
        }
    })
}

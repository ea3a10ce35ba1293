//! The exact oracle shared by `format_exhaustive.rs` and `format_props.rs`: integer
//! arithmetic only, with the rounding and overflow rules of the Algorithmic C datatypes
//! reference (`ac_fixed`):
//!
//! * AC_TRN: toward minus infinity; AC_TRN_ZERO: toward zero;
//! * AC_RND: nearest, ties toward plus infinity; AC_RND_ZERO: ties toward zero;
//!   AC_RND_INF: ties away from zero; AC_RND_MIN_INF: ties toward minus infinity;
//!   AC_RND_CONV: ties to even; AC_RND_CONV_ODD: ties to odd;
//! * AC_WRAP: two's complement, modulo 2^W; AC_SAT: clamp to MIN or MAX; AC_SAT_ZERO: zero
//!   on overflow; AC_SAT_SYM: for signed formats, on overflow *or when the result is MIN*, the
//!   closest of -MAX or MAX (unsigned formats: as AC_SAT).

#![allow(dead_code)] // each test crate uses its own part

use bumpsim_hw::format::{Codec, Encoding, Overflow, Quant};
use std::cmp::Ordering;

pub const QUANTS: [Quant; 8] = Quant::ALL;
/// The modes that round to nearest: all but the truncating `Trn` and `TrnZero`.
pub const NEAREST: &[Quant] = QUANTS.split_at(2).1;

pub const OVERFLOWS: [Overflow; 4] = Overflow::ALL;

/// `num / den` (den > 0) rounded to an integer by `q`, computed exactly.
pub fn round_div(num: i128, den: i128, q: Quant) -> i128 {
    assert!(den > 0);
    let lo = num.div_euclid(den); // floor
    let r = num.rem_euclid(den); // num = lo * den + r, 0 <= r < den
    if r == 0 {
        return lo;
    }
    let hi = lo + 1; // the exact value lies strictly between lo and hi
    let (toward_zero, away_from_zero) = if num < 0 { (hi, lo) } else { (lo, hi) };
    let even = if lo.rem_euclid(2) == 0 { lo } else { hi };
    let odd = if lo.rem_euclid(2) == 1 { lo } else { hi };
    match q {
        Quant::Trn => lo,
        Quant::TrnZero => toward_zero,
        _ => match (2 * r).cmp(&den) {
            Ordering::Less => lo,
            Ordering::Greater => hi,
            Ordering::Equal => match q {
                Quant::Rnd => hi,
                Quant::RndZero => toward_zero,
                Quant::RndInf => away_from_zero,
                Quant::RndMinInf => lo,
                Quant::RndConv => even,
                Quant::RndConvOdd => odd,
                Quant::Trn | Quant::TrnZero => unreachable!(),
            },
        },
    }
}

/// Smallest and largest raw word of a `width`-bit word.
pub fn range(signed: bool, width: u32) -> (i128, i128) {
    if signed {
        (-(1i128 << (width - 1)), (1i128 << (width - 1)) - 1)
    } else {
        (0, (1i128 << width) - 1)
    }
}

/// An integer at the target scale, which may lie beyond i128.
#[derive(Debug, Clone, Copy)]
pub enum Wide {
    Exact(i128),
    /// Out of the i128 range: its sign and its low 128 bits.
    Huge {
        negative: bool,
        low: u128,
    },
}

impl From<i128> for Wide {
    fn from(v: i128) -> Self {
        Wide::Exact(v)
    }
}

/// An integer (at the target scale) put into a `width`-bit word by the overflow mode.
pub fn overflow_oracle(signed: bool, width: u32, v: impl Into<Wide>, o: Overflow) -> i64 {
    let (min, max) = range(signed, width);
    let wrap = |bits: u128| {
        // keep the low `width` bits, then sign-extend from bit width-1
        let bits = bits & ((1u128 << width) - 1);
        if signed && (bits >> (width - 1)) & 1 == 1 {
            bits as i128 - (1i128 << width)
        } else {
            bits as i128
        }
    };
    let r = match v.into() {
        Wide::Exact(v) => match o {
            Overflow::Wrap => wrap(v as u128),
            Overflow::Sat => v.clamp(min, max),
            Overflow::SatZero => {
                if v > max || v < min {
                    0
                } else {
                    v
                }
            }
            Overflow::SatSym => {
                if !signed {
                    v.clamp(min, max)
                } else if v > max {
                    max
                } else if v <= min {
                    -max // MIN itself becomes -MAX too
                } else {
                    v
                }
            }
        },
        Wide::Huge { negative, low } => match o {
            Overflow::Wrap => wrap(low),
            Overflow::Sat => {
                if negative {
                    min
                } else {
                    max
                }
            }
            Overflow::SatZero => 0,
            Overflow::SatSym => {
                if !negative {
                    max
                } else if signed {
                    -max
                } else {
                    0
                }
            }
        },
    };
    r as i64
}

/// A validated texel encoding of `n` bits with the given modes.
pub fn texel(codec: Codec, n: u32, q: Quant, o: Overflow) -> Encoding {
    let mut e = Encoding::texel(codec, codec != Codec::UnitUnsigned, n as u8);
    e.quant = q;
    e.overflow = o;
    e.validate().unwrap();
    e
}

/// The three unit texel codecs of `n` bits (UnitSigned, UnitSymmetric, UnitUnsigned), rounding
/// and saturating, after checking the endpoints every width shares: UnitSigned -2^(n-1) is
/// exactly -1.0 and 1.0 saturates to the top code; UnitSymmetric has +-1.0 at the extremes;
/// UnitUnsigned has 0.0 at 0 and 1.0 at all-ones.
pub fn texel_endpoints(n: u32) -> (Encoding, Encoding, Encoding) {
    let half = 1i64 << (n - 1);
    let all = (1i64 << n) - 1;
    let s = texel(Codec::UnitSigned, n, Quant::Rnd, Overflow::Sat);
    assert_eq!(s.decode(-half), -1.0);
    assert_eq!(s.encode(-1.0), -half);
    assert_eq!(s.encode(1.0), half - 1); // saturates
    let y = texel(Codec::UnitSymmetric, n, Quant::Rnd, Overflow::Sat);
    assert_eq!(y.decode(half - 1), 1.0);
    assert_eq!(y.decode(-half), -1.0);
    assert_eq!(y.encode(1.0), half - 1);
    assert_eq!(y.encode(-1.0), -half);
    let u = texel(Codec::UnitUnsigned, n, Quant::Rnd, Overflow::Sat);
    assert_eq!(u.decode(all), 1.0);
    assert_eq!(u.encode(1.0), all);
    assert_eq!(u.encode(0.0), 0);
    (s, y, u)
}

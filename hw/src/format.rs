//! Run-time fixed-point number formats, named as Algorithmic C `ac_fixed` and SystemC
//! `sc_fixed` name them.
//!
//! A [`Format`] is `ac_fixed<W, I, S>`: `width` = W total bits, `frac` fraction bits
//! (so I = W - frac integer bits, the sign bit included when signed). A raw word `r`
//! stands for `r / 2^frac`. Widths run from 1 to 32 bits; full-precision products and sums
//! are carried in `i128` and cast back with a [`Quant`] and an [`Overflow`] mode, exactly as
//! `ac_fixed` assignment does.
//!
//! Texel conventions (see `docs/formats.md` and `shared/facts/hardware-facts.md`) are a
//! [`Codec`] on top of a format: unsigned n-bit `c / (2^n - 1)`, signed n-bit with
//! `-2^(n-1) = -1.0` (i.e. `c / 2^(n-1)`), and the symmetric signed mapping
//! `(2c + 1) / (2^n - 1)`.

use serde::{Deserialize, Serialize};
use std::fmt;

mod batch;

/// Largest word width a port or register may have.
pub const MAX_WIDTH: u8 = 32;

/// Quantization (rounding) modes, with the `ac_fixed` / `sc_fixed` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
pub enum Quant {
    /// AC_TRN / SC_TRN: truncate toward minus infinity (drop the low bits).
    #[default]
    Trn,
    /// AC_TRN_ZERO / SC_TRN_ZERO: truncate toward zero.
    TrnZero,
    /// AC_RND / SC_RND: round to nearest, halves toward plus infinity ("round half up").
    Rnd,
    /// AC_RND_ZERO / SC_RND_ZERO: round to nearest, halves toward zero.
    RndZero,
    /// AC_RND_INF / SC_RND_INF: round to nearest, halves away from zero.
    RndInf,
    /// AC_RND_MIN_INF / SC_RND_MIN_INF: round to nearest, halves toward minus infinity.
    RndMinInf,
    /// AC_RND_CONV / SC_RND_CONV: round to nearest, halves to even ("convergent").
    RndConv,
    /// AC_RND_CONV_ODD: round to nearest, halves to odd.
    RndConvOdd,
}

/// Overflow modes, with the `ac_fixed` / `sc_fixed` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
pub enum Overflow {
    /// AC_WRAP / SC_WRAP: keep the low `width` bits (two's complement wrap-around).
    Wrap,
    /// AC_SAT / SC_SAT: clamp to the largest or smallest representable value.
    #[default]
    Sat,
    /// AC_SAT_ZERO / SC_SAT_ZERO: an overflowing value becomes zero.
    SatZero,
    /// AC_SAT_SYM / SC_SAT_SYM: clamp symmetrically, to `-max` rather than `min`. As in
    /// `ac_fixed`, a signed result equal to `min` also becomes `-max`, so `min` is never
    /// produced (SystemC's SC_SAT_SYM only acts on overflow).
    SatSym,
}

impl Quant {
    /// Every mode, in declaration order (the truncating `Trn`, `TrnZero` first).
    pub const ALL: [Quant; 8] = [
        Quant::Trn,
        Quant::TrnZero,
        Quant::Rnd,
        Quant::RndZero,
        Quant::RndInf,
        Quant::RndMinInf,
        Quant::RndConv,
        Quant::RndConvOdd,
    ];
}

impl Overflow {
    /// Every mode, in declaration order.
    pub const ALL: [Overflow; 4] = [
        Overflow::Wrap,
        Overflow::Sat,
        Overflow::SatZero,
        Overflow::SatSym,
    ];
}

/// How a raw word maps to a real number at a memory or port interface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
pub enum Codec {
    /// `raw / 2^frac`: the plain fixed-point reading of the format.
    #[default]
    Fixed,
    /// Unsigned n-bit texel, `c / (2^n - 1)`: 0 is 0.0 and all-ones is 1.0.
    UnitUnsigned,
    /// Signed n-bit texel, `c / 2^(n-1)`: `-2^(n-1)` is -1.0, `2^(n-1)-1` is just below 1.0
    /// (NVIDIA's choice: 8-bit 127 = 0.99218).
    UnitSigned,
    /// Signed n-bit texel, `(2c + 1) / (2^n - 1)`: symmetric, no exact zero (OpenGL packed).
    UnitSymmetric,
}

/// A fixed-point format: `ac_fixed<width, width - frac, signed>`. Deserialisation checks the
/// width (1 to 32) and the fraction bits (0 to width), so a config cannot hold a bad format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "FormatSpec")]
pub struct Format {
    pub signed: bool,
    pub width: u8,
    pub frac: u8,
}

/// The unchecked form of a [`Format`] as written in a config.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FormatSpec {
    signed: bool,
    width: u32,
    frac: u32,
}

impl TryFrom<FormatSpec> for Format {
    type Error = FormatError;
    fn try_from(s: FormatSpec) -> Result<Self, FormatError> {
        Format::new(s.signed, s.width, s.frac)
    }
}

/// A reason a format cannot be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FormatError {
    #[error("width {0} is out of range: expected 1 to 32 bits")]
    Width(u32),
    #[error("fraction bits {frac} exceed the width {width}: expected 0 to {width}")]
    Frac { width: u32, frac: u32 },
}

impl Format {
    /// A checked format: width 1..=32, fraction bits 0..=width.
    pub fn new(signed: bool, width: u32, frac: u32) -> Result<Self, FormatError> {
        if width == 0 || width > MAX_WIDTH as u32 {
            return Err(FormatError::Width(width));
        }
        if frac > width {
            return Err(FormatError::Frac { width, frac });
        }
        Ok(Format {
            signed,
            width: width as u8,
            frac: frac as u8,
        })
    }
    /// Unsigned format. Panics on a bad width: for formats fixed in code, not user input.
    pub const fn u(width: u8, frac: u8) -> Self {
        assert!(width >= 1 && width <= MAX_WIDTH && frac <= width);
        Format {
            signed: false,
            width,
            frac,
        }
    }
    /// Signed format. Panics on a bad width: for formats fixed in code, not user input.
    pub const fn s(width: u8, frac: u8) -> Self {
        assert!(width >= 1 && width <= MAX_WIDTH && frac <= width);
        Format {
            signed: true,
            width,
            frac,
        }
    }
    /// Re-check a format that came from deserialisation.
    pub fn validate(&self) -> Result<(), FormatError> {
        Format::new(self.signed, self.width as u32, self.frac as u32).map(|_| ())
    }
    /// Smallest raw word.
    pub fn min_raw(&self) -> i64 {
        if self.signed {
            -(1i64 << (self.width - 1))
        } else {
            0
        }
    }
    /// Largest raw word.
    pub fn max_raw(&self) -> i64 {
        if self.signed {
            (1i64 << (self.width - 1)) - 1
        } else {
            ((1u64 << self.width) - 1) as i64
        }
    }
    /// One least significant bit as a real number.
    #[inline]
    pub fn lsb(&self) -> f64 {
        pow2(-(self.frac as i32))
    }
    /// Real value of a raw word in the plain fixed-point reading.
    #[inline]
    pub fn to_f64(&self, raw: i64) -> f64 {
        raw as f64 * self.lsb()
    }
    /// Raw word for a real number, with the given rounding and overflow modes.
    /// NaN becomes 0; infinities saturate (or wrap to 0 in `Wrap` mode).
    #[inline]
    pub fn from_f64(&self, x: f64, q: Quant, o: Overflow) -> i64 {
        let scaled = x * self.frac_scale();
        // The common case, in i64 and without branching on the remainder's class: |scaled|
        // below 2^62 (NaN fails the test). The same words as the general path below
        // (`from_f64_wide`; `format_exhaustive::fast_path_is_the_general_path` checks it exhaustively
        // for small formats, `format_props` for wide ones).
        if scaled.abs() < 4.0e18 {
            let t = scaled as i64; // toward zero
            let fl = t - ((t as f64) > scaled) as i64;
            let rem = scaled - fl as f64; // exact, in [0, 1)
            let r = fl + round_up(fl, rem, q) as i64;
            let sym_min = o == Overflow::SatSym && self.signed && r == self.min_raw();
            if r >= self.min_raw() && r <= self.max_raw() && !sym_min {
                return r;
            }
            return self.overflow(r as i128, o);
        }
        self.from_f64_wide(x, q, o)
    }
    /// [`Format::from_f64`] for any value, in i128 (NaN, infinities, huge values).
    #[doc(hidden)]
    pub fn from_f64_wide(&self, x: f64, q: Quant, o: Overflow) -> i64 {
        if x.is_nan() {
            return 0;
        }
        let scaled = x * self.frac_scale();
        // Beyond +-2^100 every mode overflows; clamp so the integer conversion is exact.
        let limit = 2f64.powi(100);
        let scaled = scaled.clamp(-limit, limit);
        // floor through i64 where that is exact (the common case: `f64::floor` and
        // f64 -> i128 are library calls on the baseline x86-64 target)
        let (fl, base) = if scaled.abs() < 4.0e18 {
            let t = scaled as i64; // toward zero
            let t = if (t as f64) > scaled { t - 1 } else { t };
            (t as f64, t as i128)
        } else {
            let fl = scaled.floor();
            (fl, fl as i128)
        };
        let rem = scaled - fl; // exact: both are dyadic with the same exponent range
        let rounded = round_with_remainder(base, rem_class(rem), q);
        self.overflow(rounded, o)
    }
    #[inline]
    fn frac_scale(&self) -> f64 {
        pow2(self.frac as i32)
    }
    /// Cast a raw value that has `from_frac` fraction bits into this format.
    #[inline]
    pub fn cast(&self, raw: i128, from_frac: u32, q: Quant, o: Overflow) -> i64 {
        // The common case in i64 (a 128-bit shift, compare and add cost about twice as much):
        // a value within 62 bits, moved by fewer than 62 bits, truncated or rounded half up.
        // The same words as the general path (`format_props::cast_fast_path_is_the_general_path`).
        if let Ok(r) = i64::try_from(raw) {
            if let Some(v) = self.cast_small(r, from_frac, q, o) {
                return v;
            }
        }
        self.cast_wide(raw, from_frac, q, o)
    }
    /// [`Format::cast`] in i64 where that is exact: `None` outside its common case.
    #[inline]
    fn cast_small(&self, raw: i64, from_frac: u32, q: Quant, o: Overflow) -> Option<i64> {
        const LIMIT: i64 = 1 << 62;
        if !(-LIMIT..LIMIT).contains(&raw) {
            return None;
        }
        let to = self.frac as u32;
        let v = if from_frac <= to {
            let up = to - from_frac;
            let v = raw.checked_shl(up).filter(|v| up < 62 && v >> up == raw)?;
            if !(-LIMIT..LIMIT).contains(&v) {
                return None;
            }
            v
        } else {
            let by = from_frac - to;
            match q {
                _ if by >= 62 => return None,
                Quant::Trn => raw >> by,
                // |raw| < 2^62: the sum stays within i64
                Quant::Rnd => (raw + (1i64 << (by - 1))) >> by,
                _ => return None,
            }
        };
        let (lo, hi) = (self.min_raw(), self.max_raw());
        let sym_min = o == Overflow::SatSym && self.signed && v == lo;
        if v >= lo && v <= hi && !sym_min {
            return Some(v);
        }
        Some(self.overflow(v as i128, o))
    }
    /// [`Format::cast`] for any value, in i128.
    #[doc(hidden)]
    pub fn cast_wide(&self, raw: i128, from_frac: u32, q: Quant, o: Overflow) -> i64 {
        let to = self.frac as u32;
        let v = if from_frac <= to {
            let up = to - from_frac;
            match o {
                // Keeps the low 128 bits, all that wrapping to `width` bits needs.
                Overflow::Wrap => raw << up,
                // Beyond i128 every format overflows: keep the side.
                _ => raw.saturating_mul(1i128 << up),
            }
        } else {
            shift_round(raw, from_frac - to, q)
        };
        self.overflow(v, o)
    }
    /// Apply the overflow mode to an integer already at this format's scale.
    #[inline]
    pub fn overflow(&self, v: i128, o: Overflow) -> i64 {
        let (lo, hi) = (self.min_raw() as i128, self.max_raw() as i128);
        let sym_min = o == Overflow::SatSym && self.signed && v == lo; // ac_fixed: MIN -> -MAX
        if v >= lo && v <= hi && !sym_min {
            return v as i64;
        }
        match o {
            Overflow::Wrap => {
                let m = 1i128 << self.width;
                let mut w = v.rem_euclid(m);
                if self.signed && w > hi {
                    w -= m;
                }
                w as i64
            }
            Overflow::Sat => v.clamp(lo, hi) as i64,
            Overflow::SatZero => 0,
            Overflow::SatSym => {
                let lo_sym = if self.signed { -hi } else { lo };
                v.clamp(lo_sym, hi) as i64
            }
        }
    }
    /// Whether a raw word is representable.
    pub fn contains(&self, raw: i64) -> bool {
        raw >= self.min_raw() && raw <= self.max_raw()
    }
    /// Bits as an unsigned pattern (two's complement in `width` bits), for traces.
    pub fn bits(&self, raw: i64) -> u64 {
        (raw as u64) & (u64::MAX >> (64 - self.width as u32))
    }
    /// Number of hex digits needed to print a word of this width.
    pub fn hex_digits(&self) -> usize {
        (self.width as usize).div_ceil(4)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = if self.signed { 's' } else { 'u' };
        write!(f, "{s}{}.{}", self.width - self.frac, self.frac)
    }
}

/// Where the discarded low part of a value lies relative to one half LSB.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Rem {
    Zero,
    BelowHalf,
    Half,
    AboveHalf,
}

fn rem_class(rem: f64) -> Rem {
    if rem == 0.0 {
        Rem::Zero
    } else if rem < 0.5 {
        Rem::BelowHalf
    } else if rem == 0.5 {
        Rem::Half
    } else {
        Rem::AboveHalf
    }
}

/// Whether `floor + rem` (`floor` the floor of the exact value, `rem` in [0, 1)) rounds up
/// to `floor + 1` under `q`: [`round_with_remainder`] as one boolean expression per mode.
#[inline]
fn round_up(floor: i64, rem: f64, q: Quant) -> bool {
    let negative = floor < 0;
    let above = rem > 0.5;
    let half = rem == 0.5;
    match q {
        Quant::Trn => false,
        Quant::TrnZero => negative & (rem != 0.0),
        Quant::Rnd => rem >= 0.5,
        Quant::RndZero => above | (half & negative),
        Quant::RndInf => above | (half & !negative),
        Quant::RndMinInf => above,
        Quant::RndConv => above | (half & (floor & 1 == 1)),
        Quant::RndConvOdd => above | (half & (floor & 1 == 0)),
    }
}

/// `a / b` (`b > 0`) rounded to an integer by `q`, exactly: the floor and the remainder's
/// class against one half, as [`Format::from_f64`] rounds a real.
pub fn round_rational(a: i128, b: i128, q: Quant) -> i128 {
    debug_assert!(b > 0);
    let (fl, r) = (a.div_euclid(b), a.rem_euclid(b));
    let rem = match (2 * r).cmp(&b) {
        _ if r == 0 => Rem::Zero,
        std::cmp::Ordering::Less => Rem::BelowHalf,
        std::cmp::Ordering::Equal => Rem::Half,
        std::cmp::Ordering::Greater => Rem::AboveHalf,
    };
    round_with_remainder(fl, rem, q)
}

/// Round `floor + rem` (with `floor` the floor of the exact value) to an integer.
fn round_with_remainder(floor: i128, rem: Rem, q: Quant) -> i128 {
    if rem == Rem::Zero {
        return floor;
    }
    let negative = floor < 0; // the exact value lies in (floor, floor + 1)
    match q {
        Quant::Trn => floor,
        Quant::TrnZero => {
            if negative {
                floor + 1
            } else {
                floor
            }
        }
        _ => match rem {
            Rem::BelowHalf => floor,
            Rem::AboveHalf => floor + 1,
            Rem::Half => {
                let up = match q {
                    Quant::Rnd => true,
                    Quant::RndZero => negative,
                    Quant::RndInf => !negative,
                    Quant::RndMinInf => false,
                    Quant::RndConv => floor & 1 == 1,
                    Quant::RndConvOdd => floor & 1 == 0,
                    Quant::Trn | Quant::TrnZero => unreachable!(),
                };
                floor + up as i128
            }
            Rem::Zero => floor,
        },
    }
}

/// `2^k` for `k` in -1022..=1023, exactly (built from its bits: no libm call).
#[inline]
pub fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((1023 + k) as u64) << 52)
}

/// Shift `v` right by `by` bits, rounding the discarded bits by `q`.
#[inline]
pub fn shift_round(v: i128, by: u32, q: Quant) -> i128 {
    if by == 0 {
        return v;
    }
    if by >= 128 {
        // |v| <= 2^127 <= 2^(by-1): the value lies in [-1/2, 1/2).
        return match v.signum() {
            0 => 0,
            1 => round_with_remainder(0, Rem::BelowHalf, q),
            _ => {
                let rem = if by == 128 && v == i128::MIN {
                    Rem::Half
                } else {
                    Rem::AboveHalf
                };
                round_with_remainder(-1, rem, q)
            }
        };
    }
    // the two common modes directly (the same results as the general path below)
    match q {
        Quant::Trn => return v >> by,
        Quant::Rnd => {
            if let Some(s) = v.checked_add(1i128 << (by - 1)) {
                return s >> by;
            }
        }
        _ => {}
    }
    let floor = v >> by;
    let low = v - (floor << by); // 0 <= low < 2^by
    let half = 1i128 << (by - 1);
    let rem = if low == 0 {
        Rem::Zero
    } else if low < half {
        Rem::BelowHalf
    } else if low == half {
        Rem::Half
    } else {
        Rem::AboveHalf
    };
    round_with_remainder(floor, rem, q)
}

/// A number format at a port or memory interface: a fixed-point format, the codec that reads
/// it, and the modes used when a real number is written into it.
///
/// In a config: `(format: (signed: true, width: 10, frac: 8), codec: Fixed, quant: Rnd,
/// overflow: Sat)`; `codec`, `quant` and `overflow` may be left out (Fixed, Rnd, Sat).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "EncodingSpec")]
pub struct Encoding {
    pub format: Format,
    pub codec: Codec,
    pub quant: Quant,
    pub overflow: Overflow,
}

/// The unchecked form of an [`Encoding`] as written in a config.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EncodingSpec {
    format: Format,
    #[serde(default)]
    codec: Codec,
    #[serde(default = "round_half_up")]
    quant: Quant,
    #[serde(default)]
    overflow: Overflow,
}

fn round_half_up() -> Quant {
    Quant::Rnd
}

impl TryFrom<EncodingSpec> for Encoding {
    type Error = String;
    fn try_from(s: EncodingSpec) -> Result<Self, String> {
        let e = Encoding {
            format: s.format,
            codec: s.codec,
            quant: s.quant,
            overflow: s.overflow,
        };
        e.validate().map(|_| e)
    }
}

impl Encoding {
    /// Plain fixed point with round-half-up and saturation: the datapath default.
    pub const fn fixed(format: Format) -> Self {
        Encoding {
            format,
            codec: Codec::Fixed,
            quant: Quant::Rnd,
            overflow: Overflow::Sat,
        }
    }
    /// A texel component with one of the unit codecs, rounded to nearest and saturated.
    pub const fn texel(codec: Codec, signed: bool, width: u8) -> Self {
        let frac = match codec {
            Codec::UnitSigned => width - 1,
            _ => 0,
        };
        Encoding {
            format: Format {
                signed,
                width,
                frac,
            },
            codec,
            quant: Quant::Rnd,
            overflow: Overflow::Sat,
        }
    }
    pub fn width(&self) -> u32 {
        self.format.width as u32
    }
    /// Check that the codec suits the format (unit codecs fix the signedness).
    pub fn validate(&self) -> Result<(), String> {
        self.format.validate().map_err(|e| e.to_string())?;
        match self.codec {
            Codec::UnitUnsigned if self.format.signed => {
                Err("codec UnitUnsigned needs an unsigned format".into())
            }
            Codec::UnitSigned | Codec::UnitSymmetric if !self.format.signed => {
                Err(format!("codec {:?} needs a signed format", self.codec))
            }
            Codec::UnitSymmetric | Codec::UnitSigned if self.format.width < 2 => {
                Err("signed unit codecs need at least 2 bits".into())
            }
            _ => Ok(()),
        }
    }
    /// Real value of a raw word.
    #[inline]
    pub fn decode(&self, raw: i64) -> f64 {
        let n = self.format.width as i32;
        match self.codec {
            Codec::Fixed => self.format.to_f64(raw),
            Codec::UnitUnsigned => raw as f64 / ((1u64 << n) - 1) as f64,
            Codec::UnitSigned => raw as f64 / (1u64 << (n - 1)) as f64,
            Codec::UnitSymmetric => (2 * raw + 1) as f64 / ((1u64 << n) - 1) as f64,
        }
    }
    /// Raw word for a real number (rounded by `quant`, clamped or wrapped by `overflow`).
    #[inline]
    pub fn encode(&self, x: f64) -> i64 {
        let n = self.format.width as i32;
        let f = &self.format;
        let int = Format {
            signed: f.signed,
            width: f.width,
            frac: 0,
        };
        match self.codec {
            Codec::Fixed => f.from_f64(x, self.quant, self.overflow),
            Codec::UnitUnsigned => {
                int.from_f64(x * ((1u64 << n) - 1) as f64, self.quant, self.overflow)
            }
            Codec::UnitSigned => {
                int.from_f64(x * (1u64 << (n - 1)) as f64, self.quant, self.overflow)
            }
            Codec::UnitSymmetric => {
                // c = (x (2^n - 1) - 1) / 2; the division by two is exact in f64.
                let c = (x * ((1u64 << n) - 1) as f64 - 1.0) * 0.5;
                int.from_f64(c, self.quant, self.overflow)
            }
        }
    }
    /// Largest decoding error of a value inside the representable range: half a step when
    /// rounding to nearest, a whole step when truncating.
    pub fn max_error(&self) -> f64 {
        let n = self.format.width as i32;
        let step = match self.codec {
            Codec::Fixed => self.format.lsb(),
            Codec::UnitUnsigned => 1.0 / ((1u64 << n) - 1) as f64,
            Codec::UnitSigned => 1.0 / (1u64 << (n - 1)) as f64,
            Codec::UnitSymmetric => 2.0 / ((1u64 << n) - 1) as f64,
        };
        match self.quant {
            Quant::Trn | Quant::TrnZero => step,
            _ => step / 2.0,
        }
    }
}

impl fmt::Display for Encoding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.codec {
            Codec::Fixed => write!(f, "{}", self.format),
            c => write!(f, "{:?}{}", c, self.format.width),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_texel_conventions_match_the_facts() {
        let e = Encoding::texel(Codec::UnitSigned, true, 8);
        assert_eq!(e.decode(-128), -1.0);
        assert!((e.decode(127) - 0.99218).abs() < 1e-5);
        let e16 = Encoding::texel(Codec::UnitSigned, true, 16);
        assert!((e16.decode(32767) - 0.99996).abs() < 1e-5);
        let sym = Encoding::texel(Codec::UnitSymmetric, true, 8);
        assert_eq!(sym.decode(127), 1.0);
        assert_eq!(sym.decode(-128), -1.0);
        assert_eq!(sym.encode(1.0), 127);
        assert_eq!(sym.encode(-1.0), -128);
        let u = Encoding::texel(Codec::UnitUnsigned, false, 8);
        assert_eq!(u.decode(255), 1.0);
        assert_eq!(u.encode(0.5), 128); // 127.5 rounds half up
    }

    #[test]
    fn rounding_modes_on_halves() {
        let f = Format::s(8, 1); // steps of 0.5 at raw level; test from_frac 2
        let cases = [
            (Quant::Trn, [1, -2]),
            (Quant::TrnZero, [1, -1]),
            (Quant::Rnd, [2, -1]),
            (Quant::RndZero, [1, -1]),
            (Quant::RndInf, [2, -2]),
            (Quant::RndMinInf, [1, -2]),
            (Quant::RndConv, [2, -2]),
            (Quant::RndConvOdd, [1, -1]),
        ];
        for (q, [pos, neg]) in cases {
            // raw 3 with 2 frac bits = 0.75 -> in frac 1: 1.5 LSB => halves
            assert_eq!(f.cast(3, 2, q, Overflow::Sat), pos, "{q:?} +1.5");
            assert_eq!(f.cast(-3, 2, q, Overflow::Sat), neg, "{q:?} -1.5");
        }
    }

    #[test]
    fn overflow_modes() {
        let f = Format::s(4, 0);
        assert_eq!(f.overflow(9, Overflow::Wrap), -7);
        assert_eq!(f.overflow(9, Overflow::Sat), 7);
        assert_eq!(f.overflow(-9, Overflow::Sat), -8);
        assert_eq!(f.overflow(-9, Overflow::SatSym), -7);
        assert_eq!(f.overflow(9, Overflow::SatZero), 0);
        let u = Format::u(4, 0);
        assert_eq!(u.overflow(17, Overflow::Wrap), 1);
        assert_eq!(u.overflow(-1, Overflow::Wrap), 15);
        assert_eq!(u.overflow(-1, Overflow::Sat), 0);
    }

    #[test]
    fn bad_formats_are_rejected() {
        assert_eq!(Format::new(true, 0, 0), Err(FormatError::Width(0)));
        assert_eq!(Format::new(true, 33, 0), Err(FormatError::Width(33)));
        assert_eq!(
            Format::new(true, 8, 9),
            Err(FormatError::Frac { width: 8, frac: 9 })
        );
        assert!(Format::new(false, 32, 32).is_ok());
    }
}

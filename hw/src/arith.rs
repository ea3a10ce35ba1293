//! Full-precision fixed-point intermediates shared by every unit's bit-accurate datapath.
//!
//! An [`Acc`] is a raw integer with a number of fraction bits, held in `i128` so that sums of
//! products of 32-bit words are exact. Units read port words into `Acc`s, compute exactly,
//! and cast the result into an output [`Encoding`] once, with that encoding's quantization and
//! overflow modes: the behaviour of an `ac_fixed` datapath whose intermediate types are wide
//! enough. Where a unit narrows an intermediate on purpose (a LUT index, a filter weight) it
//! says so.

use crate::format::{shift_round, Codec, Encoding, Format, Quant};

mod writer;
pub use writer::Writer;

/// An exact intermediate value `raw / 2^frac`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Acc {
    pub raw: i128,
    pub frac: u32,
}

/// How a datapath reads the codes of one encoding in `i64`: [`Acc::from_code`] is affine in
/// the code for every codec, `raw = code m + c` with `frac` fraction bits, so a port's reader
/// is found once and a code is read without a match on its codec. Only for encodings whose
/// readings fit in `bits` <= 62 bits (sign included).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Reader {
    pub m: i64,
    pub c: i64,
    pub frac: u32,
    /// Bits (sign included) that bound `|code m + c|` ([`Acc::code_bits`]).
    pub bits: u32,
}

impl Reader {
    /// The reader of `enc`, if its readings fit in 62 bits.
    pub fn new(enc: &Encoding) -> Option<Reader> {
        let bits = Acc::code_bits(enc);
        if bits > 62 {
            return None;
        }
        let n = enc.format.width as u32;
        let (m, c, frac) = match enc.codec {
            Codec::Fixed => (1, 0, enc.format.frac as u32),
            Codec::UnitSigned => (1, 0, n - 1),
            Codec::UnitUnsigned => ((1i64 << n) + 1, 0, 2 * n),
            Codec::UnitSymmetric => (2 * ((1i64 << n) + 1), (1i64 << n) + 1, 2 * n),
        };
        Some(Reader { m, c, frac, bits })
    }
    /// [`Acc::from_code`]'s `raw` of `code`.
    #[inline]
    pub fn read(&self, code: i64) -> i64 {
        code * self.m + self.c
    }
}

// Named methods rather than operator traits: a datapath reads as the hardware's steps.
#[allow(clippy::should_implement_trait)]
impl Acc {
    pub const ZERO: Acc = Acc { raw: 0, frac: 0 };

    pub fn new(raw: i128, frac: u32) -> Acc {
        Acc { raw, frac }
    }

    /// Read a port word into the datapath.
    ///
    /// Fixed and `UnitSigned` codes are dyadic and read exactly. The `c / (2^n - 1)` codecs are
    /// read the way texture hardware expands them, by bit replication to 2n bits:
    /// `c / (2^n - 1) ~ c (2^n + 1) / 2^2n`, an error below `2^-2n`.
    #[inline]
    pub fn from_code(raw: i64, enc: &Encoding) -> Acc {
        let n = enc.format.width as u32;
        let raw = raw as i128;
        match enc.codec {
            Codec::Fixed => Acc::new(raw, enc.format.frac as u32),
            Codec::UnitSigned => Acc::new(raw, n - 1),
            Codec::UnitUnsigned => Acc::new(raw * ((1i128 << n) + 1), 2 * n),
            Codec::UnitSymmetric => Acc::new((2 * raw + 1) * ((1i128 << n) + 1), 2 * n),
        }
    }

    /// Bits (sign included) that bound the magnitude of [`Acc::from_code`]'s `raw` for any
    /// code of `enc`: where sums of products stay below 2^63, a datapath may take them in
    /// `i64`, with the same result.
    pub fn code_bits(enc: &Encoding) -> u32 {
        let n = enc.format.width as u32;
        match enc.codec {
            Codec::Fixed | Codec::UnitSigned => n + 1,
            Codec::UnitUnsigned | Codec::UnitSymmetric => 2 * n + 3,
        }
    }

    /// Exact product.
    #[inline]
    pub fn mul(self, o: Acc) -> Acc {
        Acc::new(self.raw * o.raw, self.frac + o.frac)
    }

    /// Exact sum (aligned to the larger number of fraction bits).
    #[inline]
    pub fn add(self, o: Acc) -> Acc {
        let f = self.frac.max(o.frac);
        Acc::new((self.raw << (f - self.frac)) + (o.raw << (f - o.frac)), f)
    }

    pub fn sub(self, o: Acc) -> Acc {
        self.add(o.neg())
    }

    pub fn neg(self) -> Acc {
        Acc::new(-self.raw, self.frac)
    }

    /// Multiply by an integer constant.
    pub fn scale(self, k: i128) -> Acc {
        Acc::new(self.raw * k, self.frac)
    }

    /// Multiply by `2^-k` (a wire shift: exact).
    pub fn shr(self, k: u32) -> Acc {
        Acc::new(self.raw, self.frac + k)
    }

    /// Clamp into `[lo, hi]` (given as values at any scale).
    pub fn clamp(self, lo: Acc, hi: Acc) -> Acc {
        if self.lt(lo) {
            lo
        } else if hi.lt(self) {
            hi
        } else {
            self
        }
    }

    /// Exact comparison.
    pub fn lt(self, o: Acc) -> bool {
        let f = self.frac.max(o.frac);
        (self.raw << (f - self.frac)) < (o.raw << (f - o.frac))
    }

    /// The real value (for tests and traces; rounding only beyond 53 bits).
    pub fn to_f64(self) -> f64 {
        if self.frac <= 1022 {
            self.raw as f64 * crate::format::pow2(-(self.frac as i32))
        } else {
            self.raw as f64 * (-(self.frac as f64)).exp2()
        }
    }

    /// Round to an integer with mode `q`.
    pub fn round_int(self, q: Quant) -> i128 {
        shift_round(self.raw, self.frac, q)
    }

    /// Cast into a port encoding with its quantization and overflow modes.
    #[inline]
    pub fn to_code(self, enc: &Encoding) -> i64 {
        let n = enc.format.width as u32;
        let int = Format {
            signed: enc.format.signed,
            width: enc.format.width,
            frac: 0,
        };
        let (q, o) = (enc.quant, enc.overflow);
        match enc.codec {
            Codec::Fixed => enc.format.cast(self.raw, self.frac, q, o),
            // c = x 2^(n-1): with fewer than n - 1 fraction bits the value is an exact
            // multiple of the code's step, so it shifts left
            Codec::UnitSigned if self.frac + 1 >= n => int.cast(self.raw, self.frac + 1 - n, q, o),
            Codec::UnitSigned => {
                let up = (n - 1 - self.frac).min(126);
                let v = self.raw.checked_shl(up).filter(|v| v >> up == self.raw);
                let sat = if self.raw < 0 {
                    i128::MIN / 2
                } else {
                    i128::MAX / 2
                };
                int.cast(v.unwrap_or(sat), 0, q, o)
            }
            // c = x (2^n - 1)
            Codec::UnitUnsigned => int.cast(self.raw * ((1i128 << n) - 1), self.frac, q, o),
            // c = (x (2^n - 1) - 1) / 2
            Codec::UnitSymmetric => {
                let v = self.raw * ((1i128 << n) - 1) - (1i128 << self.frac);
                int.cast(v, self.frac + 1, q, o)
            }
        }
    }
}

/// [`Acc::to_code`] of the exact rational `num / den` (`den > 0`): the code the encoding's
/// rounding gives the real value, without an intermediate rounding (the rescale of a
/// non-dyadic factor such as `255 / 31`). Equal to `Acc::new(num, f).to_code(enc)` when `den
/// = 2^f` (`tests::rational_code_is_to_code_on_dyadic_values`).
pub fn rational_code(num: i128, den: i128, enc: &Encoding) -> i64 {
    let n = enc.format.width as u32;
    let (q, o) = (enc.quant, enc.overflow);
    let int = Format {
        signed: enc.format.signed,
        width: enc.format.width,
        frac: 0,
    };
    // the code's real value as a / b
    let (a, b, fmt) = match enc.codec {
        Codec::Fixed => (num << enc.format.frac, den, &enc.format),
        Codec::UnitSigned => (num << (n - 1), den, &int),
        Codec::UnitUnsigned => (num * ((1i128 << n) - 1), den, &int),
        Codec::UnitSymmetric => (num * ((1i128 << n) - 1) - den, 2 * den, &int),
    };
    fmt.overflow(crate::format::round_rational(a, b, q), o)
}

/// The canonical signed-digit form of `k`: `(shift, +1 or -1)` terms, fewest nonzero (the
/// shifts and adds of a constant multiplication, `rtl::fixed` and
/// `CostTable::constant_multiplier`).
pub fn csd(mut k: u128) -> Vec<(u32, i8)> {
    let mut d = Vec::new();
    let mut i = 0;
    while k != 0 {
        if k & 1 == 1 {
            if k & 3 == 3 {
                d.push((i, -1));
                k += 1;
            } else {
                d.push((i, 1));
                k -= 1;
            }
        }
        k >>= 1;
        i += 1;
    }
    d
}

/// The reciprocal of the odd `o > 1` for dividends in `[0, u_max]`: `(M, s)` with
/// `floor(u M / 2^s) = floor(u / o)` for every such `u` (the smallest `s`, or among the next
/// eight the `M` with the fewest signed digits). The division by a constant of the generated
/// Verilog (`rtl::divide`) and its price (`CostTable::div_round`).
pub fn reciprocal(o: i128, u_max: i128) -> (i128, u32) {
    let exact = |s: u32| -> Option<i128> {
        let p = 1i128 << s;
        let m = (p + o - 1) / o;
        let e = m * o - p;
        (u_max.checked_mul(e)? < p).then_some(m)
    };
    let first = (1..100)
        .find(|&s| exact(s).is_some())
        .expect("a reciprocal within 100 bits");
    (first..first + 8)
        .filter_map(|s| exact(s).map(|m| (m, s)))
        .min_by_key(|&(m, s)| (csd(m as u128).len(), s))
        .unwrap()
}

/// Greatest common divisor (`gcd(a, 0) = a`).
pub fn gcd(a: u128, b: u128) -> u128 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// Smallest number of bits that holds `v` unsigned (0 for 0).
pub fn bit_length(v: u128) -> u32 {
    128 - v.leading_zeros()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Codec, Encoding, Format};

    /// On dyadic values the rational cast is `to_code`, for every codec, rounding and
    /// overflow mode over a grid of raw words at several fraction counts.
    #[test]
    fn rational_code_is_to_code_on_dyadic_values() {
        use crate::format::Overflow;
        let encs = [
            Encoding::fixed(Format::s(9, 3)),
            Encoding::fixed(Format::u(7, 5)),
            Encoding::texel(Codec::UnitSigned, true, 6),
            Encoding::texel(Codec::UnitUnsigned, false, 5),
            Encoding::texel(Codec::UnitSymmetric, true, 6),
        ];
        for base in encs {
            for q in Quant::ALL {
                for o in Overflow::ALL {
                    let mut enc = base;
                    enc.quant = q;
                    enc.overflow = o;
                    for frac in 0..8u32 {
                        for raw in -700i128..=700 {
                            assert_eq!(
                                rational_code(raw, 1 << frac, &enc),
                                Acc::new(raw, frac).to_code(&enc),
                                "{enc:?} {raw} / 2^{frac}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn rational_code_rounds_the_exact_quotient() {
        // 255 v / 31 into s12.4: truncated, and to nearest (no ties: 31 is odd)
        let mut enc = Encoding::fixed(Format::s(16, 4));
        for v in -93i128..=93 {
            enc.quant = Quant::Trn;
            assert_eq!(
                rational_code(255 * v, 31, &enc) as i128,
                (255 * 16 * v).div_euclid(31)
            );
            enc.quant = Quant::Rnd;
            assert_eq!(
                rational_code(255 * v, 31, &enc) as i128,
                (2 * 255 * 16 * v + 31).div_euclid(62)
            );
        }
        // a tie: 3 / 2 into integers, every mode
        let mut int = Encoding::fixed(Format::s(8, 0));
        for (q, want) in [
            (Quant::Rnd, 2),
            (Quant::RndZero, 1),
            (Quant::RndConv, 2),
            (Quant::RndConvOdd, 1),
            (Quant::Trn, 1),
        ] {
            int.quant = q;
            assert_eq!(rational_code(3, 2, &int), want, "{q:?}");
        }
    }

    #[test]
    fn unit_signed_casts_of_values_with_few_fraction_bits_shift_up() {
        // an integer (no fraction bits) into an 8-bit UnitSigned code: c = x 128
        let enc = Encoding::texel(Codec::UnitSigned, true, 8);
        assert_eq!(Acc::new(-1, 0).to_code(&enc), -128);
        assert_eq!(Acc::new(1, 0).to_code(&enc), 127, "saturates");
        assert_eq!(Acc::new(0, 0).to_code(&enc), 0);
        // a quarter with 2 fraction bits: 32
        assert_eq!(Acc::new(1, 2).to_code(&enc), 32);
        assert_eq!(Acc::new(-3, 2).to_code(&enc), -96);
        // huge values saturate instead of wrapping
        assert_eq!(Acc::new(i128::MAX / 4, 0).to_code(&enc), 127);
        assert_eq!(Acc::new(i128::MIN / 4, 0).to_code(&enc), -128);
    }

    #[test]
    fn a_reader_reads_every_code_as_from_code_does() {
        for (codec, signed, widths) in [
            (Codec::UnitUnsigned, false, [1u8, 8, 12, 16, 29]),
            (Codec::UnitSigned, true, [2, 8, 12, 16, 32]),
            (Codec::UnitSymmetric, true, [1, 8, 12, 16, 29]),
        ] {
            for n in widths {
                let enc = Encoding::texel(codec, signed, n);
                let r = Reader::new(&enc).expect("fits");
                let f = enc.format;
                let step = ((f.max_raw() - f.min_raw()) / 4099).max(1);
                let codes = (f.min_raw()..=f.max_raw()).step_by(step as usize);
                for c in codes.chain([f.min_raw(), f.max_raw()]) {
                    let a = Acc::from_code(c, &enc);
                    assert_eq!(
                        (r.read(c) as i128, r.frac),
                        (a.raw, a.frac),
                        "{codec:?}{n} {c}"
                    );
                    assert!(
                        a.raw.unsigned_abs() < 1u128 << (r.bits - 1),
                        "{codec:?}{n} {c}"
                    );
                }
            }
        }
        for (w, fr) in [(10u8, 8u8), (16, 12), (32, 16), (32, 0)] {
            let enc = Encoding::fixed(Format::s(w, fr));
            let r = Reader::new(&enc).expect("fits");
            for c in [enc.format.min_raw(), -1, 0, 1, enc.format.max_raw()] {
                let a = Acc::from_code(c, &enc);
                assert_eq!((r.read(c) as i128, r.frac), (a.raw, a.frac));
            }
        }
        // readings beyond 62 bits have no reader: the datapaths keep i128
        assert!(Reader::new(&Encoding::texel(Codec::UnitUnsigned, false, 30)).is_none());
        assert!(Reader::new(&Encoding::texel(Codec::UnitSymmetric, true, 32)).is_none());
    }

    #[test]
    fn codes_read_and_write_back_exactly_for_every_8_bit_code() {
        for (codec, signed) in [
            (Codec::UnitUnsigned, false),
            (Codec::UnitSigned, true),
            (Codec::UnitSymmetric, true),
        ] {
            let enc = Encoding::texel(codec, signed, 8);
            let f = enc.format;
            for c in f.min_raw()..=f.max_raw() {
                let a = Acc::from_code(c, &enc);
                assert!(
                    (a.to_f64() - enc.decode(c)).abs() <= 2f64.powi(-16),
                    "{codec:?} {c}"
                );
                assert_eq!(a.to_code(&enc), c, "{codec:?} {c}");
            }
        }
    }

    #[test]
    fn products_and_sums_are_exact() {
        let a = Acc::new(3, 2); // 0.75
        let b = Acc::new(-5, 3); // -0.625
        assert_eq!(a.mul(b).to_f64(), -0.46875);
        assert_eq!(a.add(b).to_f64(), 0.125);
        assert_eq!(a.sub(b).to_f64(), 1.375);
        let out = Encoding::fixed(Format::s(8, 4));
        assert_eq!(a.mul(b).to_code(&out), -7); // -0.46875 * 16 = -7.5 -> Rnd -> -7
    }
}

//! [`Writer`]: the output side of a datapath, the cast of its sum into a port's codes planned
//! once per port, as [`super::Reader`] is the input side.

use super::Acc;
use crate::format::{Codec, Encoding, Overflow, Quant};

/// How a datapath writes a sum with `from_frac` fraction bits into the codes of one encoding,
/// in `i64`: [`Acc::to_code`] with its codec, shifts, rounding and overflow resolved when the
/// unit is built rather than at every cast. Every codec's cast is
/// `round((v m + c) 2^up / 2^down)` followed by the overflow mode; the common case (a rounding
/// toward minus infinity or half up, a sum within the bound that keeps that arithmetic in
/// 62 bits, a result in range or saturated) is computed in `i64`, and every other value goes
/// through [`Acc::to_code`], so [`Writer::write`] is `Acc::new(v, from_frac).to_code(enc)` for
/// every `v` (`tests::the_writer_is_to_code`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Writer {
    enc: Encoding,
    from_frac: u32,
    /// The common case applies: the rounding is `Trn` or `Rnd` and the shifts are below 62.
    fast: bool,
    m: i64,
    c: i64,
    up: u32,
    down: u32,
    /// Added before the right shift: half an output step for `Rnd`, 0 for `Trn`.
    half: i64,
    /// `|v| <= bound` keeps `(v m + c) 2^up + half` within 62 bits.
    bound: i64,
    /// Results returned as they are (for `SatSym`, the signed minimum is excluded).
    lo: i64,
    hi: i64,
    /// Out-of-range results clamp to `[lo, hi]` in the common case (`Sat`).
    sat: bool,
}

impl Writer {
    /// The writer of sums with `from_frac` fraction bits into `enc`.
    pub fn new(from_frac: u32, enc: &Encoding) -> Writer {
        let n = enc.format.width as u32;
        // (m, c, target fraction bits): the code is round((v m + c) / 2^(from_frac + extra - to))
        let (m, c, extra, to) = match enc.codec {
            Codec::Fixed => (1i128, 0i128, 0, enc.format.frac as u32),
            Codec::UnitSigned => (1, 0, 0, n - 1),
            Codec::UnitUnsigned => ((1i128 << n.min(100)) - 1, 0, 0, 0),
            Codec::UnitSymmetric => (
                (1i128 << n.min(100)) - 1,
                -(1i128 << from_frac.min(100)),
                1,
                0,
            ),
        };
        let from = from_frac + extra;
        let (up, down) = (to.saturating_sub(from), from.saturating_sub(to));
        let (lo, hi) = (enc.format.min_raw(), enc.format.max_raw());
        let lo = if enc.overflow == Overflow::SatSym && enc.format.signed {
            lo + 1
        } else {
            lo
        };
        let rounds = matches!(enc.quant, Quant::Trn | Quant::Rnd);
        let fast = rounds && up < 62 && down < 62 && n <= 60 && from_frac <= 60 && m < 1 << 61;
        let (bound, half) = if fast {
            let room = (1i128 << 61 >> up) - c.abs() - 1;
            let half = if enc.quant == Quant::Rnd && down > 0 {
                1i64 << (down - 1)
            } else {
                0
            };
            ((room / m).max(-1) as i64, half)
        } else {
            (-1, 0)
        };
        Writer {
            enc: *enc,
            from_frac,
            fast: fast && bound >= 0,
            m: m.min(i64::MAX as i128) as i64,
            c: c.max(i64::MIN as i128) as i64,
            up,
            down,
            half,
            bound,
            lo,
            hi,
            sat: enc.overflow == Overflow::Sat,
        }
    }

    /// The encoding written.
    pub fn encoding(&self) -> &Encoding {
        &self.enc
    }

    /// Fraction bits of the sums written.
    pub fn from_frac(&self) -> u32 {
        self.from_frac
    }

    /// The code of the sum `v / 2^from_frac`: `Acc::new(v, from_frac).to_code(enc)`.
    #[inline]
    pub fn write(&self, v: i64) -> i64 {
        if self.fast && v.unsigned_abs() <= self.bound as u64 {
            let r = (((v * self.m + self.c) << self.up) + self.half) >> self.down;
            if r >= self.lo && r <= self.hi {
                return r;
            }
            if self.sat {
                return r.clamp(self.lo, self.hi);
            }
        }
        Acc::new(v as i128, self.from_frac).to_code(&self.enc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::Format;

    /// Every encoding of each codec, sign, rounding and overflow mode up to `max_width` bits
    /// (fixed formats with every fraction from 0 to the width).
    fn encodings(max_width: u8) -> Vec<Encoding> {
        let mut v = Vec::new();
        for width in 1..=max_width {
            for signed in [false, true] {
                for codec in [
                    Codec::Fixed,
                    Codec::UnitUnsigned,
                    Codec::UnitSigned,
                    Codec::UnitSymmetric,
                ] {
                    let fracs = if codec == Codec::Fixed {
                        0..=width
                    } else {
                        0..=0
                    };
                    for frac in fracs {
                        for quant in Quant::ALL {
                            for overflow in Overflow::ALL {
                                let format = Format {
                                    signed,
                                    width,
                                    frac,
                                };
                                v.push(Encoding {
                                    format,
                                    codec,
                                    quant,
                                    overflow,
                                });
                            }
                        }
                    }
                }
            }
        }
        v
    }

    #[test]
    fn the_writer_is_to_code() {
        // every encoding to 6 bits, every sum fraction to 14 bits, every sum in [-260, 260]
        let mut checks = 0u64;
        for enc in encodings(6) {
            for from_frac in 0..=14 {
                let w = Writer::new(from_frac, &enc);
                for v in -260..=260i64 {
                    let want = Acc::new(v as i128, from_frac).to_code(&enc);
                    assert_eq!(w.write(v), want, "{enc:?} from_frac {from_frac} v {v}");
                    checks += 1;
                }
            }
        }
        assert!(checks > 20_000_000, "{checks}");
    }

    #[test]
    fn the_writer_is_to_code_on_wide_sums_and_formats() {
        // random sums of every magnitude (and the ends of i64) into formats to 62 bits
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for _ in 0..200_000 {
            let r = next();
            let width = 1 + (r % 62) as u8;
            let enc = Encoding {
                format: Format {
                    signed: r >> 8 & 1 == 1,
                    width,
                    frac: ((r >> 9) % (width as u64 + 1)) as u8,
                },
                codec: [
                    Codec::Fixed,
                    Codec::UnitUnsigned,
                    Codec::UnitSigned,
                    Codec::UnitSymmetric,
                ][(r >> 16) as usize % 4],
                quant: Quant::ALL[(r >> 20) as usize % 8],
                overflow: Overflow::ALL[(r >> 24) as usize % 4],
            };
            let from_frac = ((r >> 28) % 64) as u32;
            let w = Writer::new(from_frac, &enc);
            let mag = next() % 64;
            let v = match next() % 8 {
                0 => i64::MIN,
                1 => i64::MAX,
                2 => w.bound,
                3 => -w.bound,
                _ => (next() as i64) >> mag,
            };
            let want = Acc::new(v as i128, from_frac).to_code(&enc);
            assert_eq!(w.write(v), want, "{enc:?} from_frac {from_frac} v {v}");
        }
    }
}

//! [`Format::from_f64`] over a slice of values: the attribute interpolator rounds one lane of
//! a batch of fragments at a time. The same words as one call per value, without a call, a
//! conversion through the integer unit or a branch per value: the floor by the
//! `1.5 * 2^52` addition (exact below `2^51`), the remainder's class by the rounding mode
//! chosen once per slice, and the values outside that common case (huge, NaN, overflowing)
//! sent to [`Format::from_f64`] afterwards.

use super::{round_up, Format, Overflow, Quant};

/// `1.5 * 2^52`: added to a real `s` with `|s| < 2^51`, the sum lies in `[2^52, 2^53)`, where
/// the doubles are the integers, so it rounds `s` to an integer (ties to even) exactly.
const MAGIC: f64 = 6_755_399_441_055_744.0;
/// The common case's bound on the scaled value.
const LIMIT: f64 = 2_251_799_813_685_248.0;

impl Format {
    /// `out[k] = self.from_f64(xs[k], q, o)` for every `k` of the shorter slice.
    pub fn from_f64_slice(&self, xs: &[f64], q: Quant, o: Overflow, out: &mut [i64]) {
        // one loop per rounding mode, so that the mode is not tested per value
        macro_rules! with {
            ($q:expr) => {
                self.slice_with(xs, q, o, out, |fl, rem| round_up(fl, rem, $q))
            };
        }
        match q {
            Quant::Trn => with!(Quant::Trn),
            Quant::TrnZero => with!(Quant::TrnZero),
            Quant::Rnd => with!(Quant::Rnd),
            Quant::RndZero => with!(Quant::RndZero),
            Quant::RndInf => with!(Quant::RndInf),
            Quant::RndMinInf => with!(Quant::RndMinInf),
            Quant::RndConv => with!(Quant::RndConv),
            Quant::RndConvOdd => with!(Quant::RndConvOdd),
        }
    }

    #[inline(always)]
    fn slice_with(
        &self,
        xs: &[f64],
        q: Quant,
        o: Overflow,
        out: &mut [i64],
        up: impl Fn(i64, f64) -> bool,
    ) {
        let scale = self.frac_scale();
        let hi = self.max_raw();
        // SAT_SYM never gives a signed format's minimum: it is left to `from_f64`
        let lo = self.min_raw() + (o == Overflow::SatSym && self.signed) as i64;
        // the range test in f64 (exact: the words are integers below 2^51 in magnitude, and
        // SSE2 has no 64-bit integer comparison)
        let (lo_f, hi_f) = (lo as f64, hi as f64);
        let common = |s: f64, v: f64| (s.abs() < LIMIT) & (v >= lo_f) & (v <= hi_f);
        let mut all = true;
        for (r, &x) in out.iter_mut().zip(xs) {
            let s = x * scale;
            // outside the common case the arithmetic runs on 0 and the value is redone below
            let c = if s.abs() < LIMIT { s } else { 0.0 };
            let n = (c + MAGIC) - MAGIC;
            let fl = n - ((n > c) as u8 as f64);
            let rem = c - fl; // exact, in [0, 1)
            let fi = (fl + MAGIC).to_bits() as i64 - MAGIC.to_bits() as i64;
            let up = up(fi, rem);
            all &= common(s, fl + up as u8 as f64);
            *r = fi + up as i64;
        }
        if !all {
            for (r, &x) in out.iter_mut().zip(xs) {
                if !common(x * scale, *r as f64) {
                    *r = self.from_f64(x, q, o);
                }
            }
        }
    }
}

//! Property tests of `bumpsim_hw::format` for widths 13 to 32 bits (widths up to 12 are
//! checked exhaustively in `format_exhaustive.rs`), and cross-checks against the `fixed`
//! crate as an independent implementation.
//!
//! The oracle is shared with `format_exhaustive.rs` (`common/mod.rs`: exact integer
//! arithmetic, modes as the `ac_fixed` reference defines them), here extended to divisors
//! beyond `i128` with a sticky bit, and to products beyond `i128` by keeping the sign and
//! the low 128 bits.
//!
//! What the `fixed` crate documents, and so what it is compared with:
//! * `from_num` / `saturating_from_num` / `wrapping_from_num` / `checked_from_num` from a
//!   float "rounds to the nearest, with ties rounding to even": our `Quant::RndConv` with
//!   `Overflow::Sat` / `Overflow::Wrap`;
//! * conversion from another fixed-point number: "any extra fractional bits are discarded,
//!   which rounds towards -inf": our `cast` with `Quant::Trn`;
//! * `wide_mul` "returns a wider type to retain all precision": the exact `i128` product;
//! * `round_ties_even`, `round` (ties away from zero), `floor`, `round_to_zero`: `RndConv`,
//!   `RndInf`, `Trn` and `TrnZero` casts to zero fraction bits.
//!
//! The docs do not say how `*` (`wrapping_mul`, `saturating_mul`) rounds; its implementation
//! shifts the double-width product right, which is truncation toward -inf, so it is compared
//! with `Quant::Trn`, and with the documented route `wide_mul` + `from_num`.

mod common;

use bumpsim_hw::format::{shift_round, Codec, Encoding, Format, Overflow, Quant};
use common::{
    overflow_oracle, range, round_div, texel, texel_endpoints, Wide, NEAREST, OVERFLOWS, QUANTS,
};
use fixed::types::{I16F16, I1F15, I4F12, I8F8, U0F16, U16F16, U8F8};
use proptest::prelude::*;
use proptest::test_runner::Config;

/// Cases per property: each case checks every quantization and overflow mode, and the whole
/// file runs in well under a second at opt-level 1.
const CASES: u32 = 10_000;

fn cfg(cases: u32) -> Config {
    // No regression files are written into the source tree.
    Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    }
}

// ------------------------------------------------------------------------------------------
// The oracle.
// ------------------------------------------------------------------------------------------

/// `v / 2^by` rounded by `q`, for any `by` (2^by may not fit in an i128).
///
/// For large shifts the low `j` bits are first replaced by one sticky bit: with
/// `v' = floor(v / 2^j)` and `s = (v mod 2^j != 0)`, `(2 v' + s) / 2^(by - j + 1)` has the same
/// floor and the same position relative to the half as `v / 2^by`.
fn round_shift(v: i128, by: u32, q: Quant) -> i128 {
    if by <= 120 {
        return round_div(v, 1i128 << by, q);
    }
    let j = by - 62;
    let (floor_j, sticky) = if j <= 127 {
        let f = v >> j;
        (f, v.wrapping_sub(f.wrapping_shl(j)) != 0)
    } else {
        (v >> 127, v != 0) // |v| <= 2^127 < 2^j: the floor is 0 or -1
    };
    round_div(2 * floor_j + sticky as i128, 1i128 << 63, q)
}

/// `v * 2^s`, exactly or as its sign and low bits.
fn shl_wide(v: i128, s: u32) -> Wide {
    if s < 127 {
        if let Some(p) = v.checked_mul(1i128 << s) {
            return Wide::Exact(p);
        }
    } else if v == 0 {
        return Wide::Exact(0);
    }
    let low = if s >= 128 { 0 } else { (v as u128) << s };
    Wide::Huge {
        negative: v < 0,
        low,
    }
}

fn expected_cast(f: Format, raw: i128, from_frac: u32, q: Quant, o: Overflow) -> i64 {
    let to = f.frac as u32;
    let v = if from_frac >= to {
        Wide::Exact(round_shift(raw, from_frac - to, q))
    } else {
        shl_wide(raw, to - from_frac)
    };
    overflow_oracle(f.signed, f.width as u32, v, o)
}

/// Finite `x` times 2^frac rounded by `q`, exactly: x = ±m 2^e, so x 2^frac = ±m 2^(e + frac).
fn scaled_round(f: Format, x: f64, q: Quant) -> Wide {
    assert!(x.is_finite());
    let bits = x.to_bits();
    let exp_field = ((bits >> 52) & 0x7ff) as i32;
    let frac_field = (bits & ((1u64 << 52) - 1)) as i128;
    let (m, e) = if exp_field == 0 {
        (frac_field, -1074) // subnormal or zero
    } else {
        (frac_field | (1i128 << 52), exp_field - 1075)
    };
    let m = if x.is_sign_negative() { -m } else { m };
    let s = e + f.frac as i32;
    if s >= 0 {
        shl_wide(m, s as u32)
    } else {
        Wide::Exact(round_shift(m, (-s) as u32, q))
    }
}

/// Exact expected `from_f64` result; NaN is 0 and infinities overflow, as documented.
fn expected_from_f64(f: Format, x: f64, q: Quant, o: Overflow) -> i64 {
    let v = if x.is_nan() {
        Wide::Exact(0)
    } else if x.is_infinite() {
        Wide::Huge {
            negative: x < 0.0,
            low: 0,
        }
    } else {
        scaled_round(f, x, q)
    };
    overflow_oracle(f.signed, f.width as u32, v, o)
}

/// Whether `x` rounded by `q` fits `f` without overflow.
fn fits(f: Format, x: f64, q: Quant) -> bool {
    let (min, max) = range(f.signed, f.width as u32);
    matches!(scaled_round(f, x, q), Wide::Exact(v) if v >= min && v <= max)
}

#[test]
fn wide_oracle_hand_computed() {
    // 2^127 would not fit: -1 / 2^200 is just below zero.
    assert_eq!(round_shift(-1, 200, Quant::Trn), -1);
    assert_eq!(round_shift(-1, 200, Quant::TrnZero), 0);
    assert_eq!(round_shift(-1, 200, Quant::Rnd), 0);
    assert_eq!(round_shift(1, 200, Quant::RndInf), 0);
    assert_eq!(round_shift(i128::MIN, 127, Quant::TrnZero), -1); // exactly -1
    assert_eq!(round_shift(i128::MIN, 128, Quant::Rnd), 0); // exactly -0.5
    assert_eq!(round_shift(i128::MIN, 128, Quant::RndInf), -1);
    assert_eq!(round_shift(i128::MIN, 128, Quant::RndConv), 0);
    assert_eq!(round_shift((1 << 126) + 1, 127, Quant::Rnd), 1); // just above 0.5
    assert_eq!(round_shift(1 << 126, 127, Quant::RndZero), 0); // exactly 0.5
    assert_eq!(round_shift(3 << 120, 121, Quant::RndConv), 2); // 1.5
    assert_eq!(round_shift(-(3 << 120), 121, Quant::RndConvOdd), -1);
    for by in 0..=120 {
        for q in QUANTS {
            assert_eq!(round_shift(5 << by, by, q), 5);
        }
    }
    let f = Format::s(16, 8);
    assert_eq!(
        expected_from_f64(f, -1.5 / 256.0, Quant::Rnd, Overflow::Sat),
        -1
    );
    assert_eq!(expected_from_f64(f, 1e300, Quant::Rnd, Overflow::Wrap), 0);
    assert_eq!(
        expected_from_f64(f, 1e-300, Quant::RndInf, Overflow::Sat),
        0
    );
    assert_eq!(expected_from_f64(f, -1e-300, Quant::Trn, Overflow::Sat), -1);
    assert_eq!(
        expected_cast(f, i128::MAX, 0, Quant::Trn, Overflow::Sat),
        32767
    );
    assert_eq!(
        expected_cast(f, i128::MIN, 0, Quant::Trn, Overflow::Wrap),
        0
    );
}

// ------------------------------------------------------------------------------------------
// Strategies.
// ------------------------------------------------------------------------------------------

fn q_and_o() -> impl Iterator<Item = (Quant, Overflow)> {
    QUANTS
        .into_iter()
        .flat_map(|q| OVERFLOWS.into_iter().map(move |o| (q, o)))
}

/// A format of 13 to 32 bits; the fraction is often 0, 1, width/2 or width.
fn wide_format() -> impl Strategy<Value = Format> {
    (any::<bool>(), 13u32..=32)
        .prop_flat_map(|(s, w)| {
            let fr = prop_oneof![Just(0), Just(1), Just(w / 2), Just(w), 0..=w];
            (Just(s), Just(w), fr)
        })
        .prop_map(|(s, w, fr)| Format::new(s, w, fr).unwrap())
}

/// A target-scale integer in or near the range of `f`: around either end, around zero, or
/// anywhere within two ranges.
fn near_range(f: Format) -> BoxedStrategy<i128> {
    let (min, max) = range(f.signed, f.width as u32);
    let span = 1i128 << f.width;
    prop_oneof![
        (-40i128..=40).prop_map(move |d| min + d),
        (-40i128..=40).prop_map(move |d| max + d),
        -40i128..=40,
        (min - span)..=(max + span),
    ]
    .boxed()
}

/// A source word for a cast into `f` from `from_frac` fraction bits: near the range (with a
/// random low part, or exactly a tie), or anything at all.
fn source_raw(f: Format, from_frac: u32) -> BoxedStrategy<i128> {
    let d = from_frac as i32 - f.frac as i32;
    let near = near_range(f);
    if d > 0 {
        let unit = 1i128 << d;
        prop_oneof![
            4 => (near.clone(), 0..unit).prop_map(move |(t, low)| t * unit + low),
            2 => near.prop_map(move |t| t * unit + unit / 2), // exactly half an LSB
            1 => any::<i128>(),
            1 => any::<i64>().prop_map(|v| v as i128),
        ]
        .boxed()
    } else {
        prop_oneof![
            4 => near.prop_map(move |t| t >> -d),
            1 => any::<i128>(),
            1 => any::<i64>().prop_map(|v| v as i128),
        ]
        .boxed()
    }
}

/// A finite or non-finite f64: exact dyadic points near the range (with eighth-LSB
/// offsets, so midpoints and quarter points are hit), random values of any magnitude, or
/// any bit pattern.
fn f64_for(f: Format) -> BoxedStrategy<f64> {
    let scale = (-(f.frac as f64 + 3.0)).exp2();
    prop_oneof![
        4 => (near_range(f), 0i128..8).prop_map(move |(k, t)| (8 * k + t) as f64 * scale),
        2 => (any::<i64>(), -120i32..=60).prop_map(|(m, e)| (m >> 11) as f64 * (e as f64).exp2()),
        1 => any::<u64>().prop_map(f64::from_bits),
    ]
    .boxed()
}

// ------------------------------------------------------------------------------------------
// Oracle properties, widths 13..=32.
// ------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(cfg(CASES))]

    #[test]
    fn cast_matches_oracle(
        (f, from_frac, raw) in (wide_format(), 0u32..=62)
            .prop_flat_map(|(f, ff)| (Just(f), Just(ff), source_raw(f, ff)))
    ) {
        for (q, o) in q_and_o() {
            let want = expected_cast(f, raw, from_frac, q, o);
            prop_assert_eq!(f.cast(raw, from_frac, q, o), want,
                "{} cast({}, from_frac {}, {:?}, {:?})", f, raw, from_frac, q, o);
        }
    }

    /// `Format::cast`'s i64 fast path gives the general (i128) path's words, small formats
    /// included.
    #[test]
    fn cast_fast_path_is_the_general_path(
        (f, from_frac, raw) in ((1u32..=32, any::<bool>()).prop_flat_map(|(w, s)| {
            (0..=w).prop_map(move |fr| Format::new(s, w, fr).unwrap())
        }), 0u32..=62)
            .prop_flat_map(|(f, ff)| (Just(f), Just(ff), source_raw(f, ff)))
    ) {
        for (q, o) in q_and_o() {
            prop_assert_eq!(f.cast(raw, from_frac, q, o), f.cast_wide(raw, from_frac, q, o),
                "{} cast({}, from_frac {}, {:?}, {:?})", f, raw, from_frac, q, o);
        }
    }

    #[test]
    fn overflow_matches_oracle(
        (f, v) in wide_format().prop_flat_map(|f| (Just(f), prop_oneof![
            3 => near_range(f),
            1 => any::<i128>(),
        ]))
    ) {
        for o in OVERFLOWS {
            let want = overflow_oracle(f.signed, f.width as u32, Wide::Exact(v), o);
            prop_assert_eq!(f.overflow(v, o), want, "{} overflow({}, {:?})", f, v, o);
        }
    }

    #[test]
    fn from_f64_matches_oracle(
        (f, x) in wide_format().prop_flat_map(|f| (Just(f), f64_for(f)))
    ) {
        for (q, o) in q_and_o() {
            let want = expected_from_f64(f, x, q, o);
            prop_assert_eq!(f.from_f64(x, q, o), want, "{} from_f64({:e}) {:?} {:?}", f, x, q, o);
        }
    }

    #[test]
    fn shift_round_matches_oracle(
        v in prop_oneof![any::<i128>(), any::<i64>().prop_map(|v| v as i128), -5i128..=5,
                         Just(i128::MIN), Just(i128::MAX), Just(i128::MIN + 1)],
        by in prop_oneof![0u32..=64, 64u32..=140, 120u32..=300],
    ) {
        for q in QUANTS {
            prop_assert_eq!(shift_round(v, by, q), round_shift(v, by, q), "{} >> {} {:?}", v, by, q);
        }
    }

    #[test]
    fn shift_round_ties(k in any::<i64>(), by in 1u32..=64) {
        // k + 1/2 exactly
        let v = ((k as i128) << by) + (1i128 << (by - 1));
        let k = k as i128;
        let want = [(Quant::Trn, k), (Quant::TrnZero, if k < 0 { k + 1 } else { k }),
            (Quant::Rnd, k + 1), (Quant::RndZero, if k < 0 { k + 1 } else { k }),
            (Quant::RndInf, if k < 0 { k } else { k + 1 }), (Quant::RndMinInf, k),
            (Quant::RndConv, if k % 2 == 0 { k } else { k + 1 }),
            (Quant::RndConvOdd, if k % 2 == 0 { k + 1 } else { k })];
        for (q, w) in want {
            prop_assert_eq!(shift_round(v, by, q), w, "{} + 1/2, {:?}", k, q);
        }
    }
}

#[test]
fn shift_round_beyond_i128_hand_computed() {
    // v / 2^by with 2^by beyond i128: the exact value lies in [-1/2, 1/2).
    for by in [128u32, 129, 200, u32::MAX] {
        assert_eq!(shift_round(-1, by, Quant::Trn), -1);
        assert_eq!(shift_round(-1, by, Quant::TrnZero), 0);
        assert_eq!(
            shift_round(-1, by, Quant::Rnd),
            0,
            "-tiny rounds to 0 (by {by})"
        );
        assert_eq!(shift_round(-1, by, Quant::RndMinInf), 0);
        assert_eq!(shift_round(1, by, Quant::RndInf), 0);
        assert_eq!(shift_round(0, by, Quant::Trn), 0);
    }
    assert_eq!(shift_round(i128::MIN, 128, Quant::Rnd), 0); // exactly -1/2
    assert_eq!(shift_round(i128::MIN, 128, Quant::RndInf), -1);
    assert_eq!(shift_round(i128::MIN, 128, Quant::RndMinInf), -1);
    // by = 127: the value lies in [-1, 1) and can be at or above one half.
    assert_eq!(shift_round(i128::MIN, 127, Quant::TrnZero), -1); // exactly -1
    assert_eq!(shift_round((1 << 126) + 1, 127, Quant::Rnd), 1);
    assert_eq!(shift_round(1 << 126, 127, Quant::RndZero), 0);
    assert_eq!(shift_round(-1, 127, Quant::Rnd), 0);
    assert_eq!(shift_round(-(1 << 126) - 1, 127, Quant::Rnd), -1);
}

#[test]
fn cast_of_huge_source_words() {
    // A source word that overflows i128 when brought up to the target scale still saturates
    // the right way (and wraps to its low bits).
    let f = Format::s(32, 16);
    for (raw, sat) in [
        (1i128 << 120, i32::MAX as i64),
        (-(1i128 << 120), i32::MIN as i64),
    ] {
        assert_eq!(f.cast(raw, 0, Quant::Trn, Overflow::Sat), sat);
        assert_eq!(f.cast(raw, 0, Quant::Trn, Overflow::SatZero), 0);
        assert_eq!(f.cast(raw, 0, Quant::Trn, Overflow::Wrap), 0);
    }
    assert_eq!(
        f.cast(i128::MAX, 8, Quant::Trn, Overflow::Sat),
        i32::MAX as i64
    );
    assert_eq!(f.cast(i128::MAX, 8, Quant::Trn, Overflow::Wrap), -256); // 0xffff_ff00
    assert_eq!(
        f.cast(i128::MIN, 8, Quant::Rnd, Overflow::SatSym),
        -(i32::MAX as i64)
    );
}

// ------------------------------------------------------------------------------------------
// Encodings, widths 13..=32.
// ------------------------------------------------------------------------------------------

fn unit_codec() -> impl Strategy<Value = Codec> {
    prop::sample::select(vec![
        Codec::UnitUnsigned,
        Codec::UnitSigned,
        Codec::UnitSymmetric,
    ])
}

proptest! {
    #![proptest_config(cfg(CASES))]

    #[test]
    fn texel_round_trip((codec, n, c) in (unit_codec(), 13u32..=32).prop_flat_map(|(codec, n)| {
        let (min, max) = range(codec != Codec::UnitUnsigned, n);
        (Just(codec), Just(n), prop_oneof![(min..=max), min..=min + 3, max - 3..=max])
    })) {
        let c = c as i64;
        for &q in NEAREST {
            let e = texel(codec, n, q, Overflow::Sat);
            let x = e.decode(c);
            prop_assert_eq!(e.encode(x), c, "{} {:?} encode(decode({}))", e, q, c);
            prop_assert_eq!(e.decode(e.encode(x)), x);
        }
        // UnitSigned decodes exactly, so truncation gives the code back too.
        if codec == Codec::UnitSigned {
            for q in [Quant::Trn, Quant::TrnZero] {
                let e = texel(codec, n, q, Overflow::Sat);
                prop_assert_eq!(e.encode(e.decode(c)), c);
            }
        }
    }

    /// Exact encode oracle on the grid x = k / 2^g, g = 51 - n, where x (2^n - 1) is exact
    /// in f64.
    #[test]
    fn texel_encode_matches_oracle((codec, n, k) in (unit_codec(), 13u32..=32).prop_flat_map(|(codec, n)| {
        let g = 51 - n;
        let kmax = (5i128 << g) / 4;
        (Just(codec), Just(n), -kmax..=kmax)
    })) {
        let g = 51 - n;
        let m = (1i128 << n) - 1;
        let (num, den) = match codec {
            Codec::UnitUnsigned => (k * m, 1i128 << g),
            Codec::UnitSigned => (k << (n - 1), 1i128 << g),
            _ => (k * m - (1i128 << g), 1i128 << (g + 1)),
        };
        let x = k as f64 * (-(g as f64)).exp2();
        let signed = codec != Codec::UnitUnsigned;
        for (q, o) in q_and_o() {
            let e = texel(codec, n, q, o);
            let want = overflow_oracle(signed, n, Wide::Exact(round_div(num, den, q)), o);
            prop_assert_eq!(e.encode(x), want, "{} {:?} {:?} encode({})", e, q, o, x);
            // Inside the range, the error bound holds.
            let (min, max) = range(signed, n);
            if o == Overflow::Sat && x >= e.decode(min as i64) && x <= e.decode(max as i64) {
                let err = (e.decode(want) - x).abs();
                prop_assert!(err <= e.max_error() * (1.0 + 1e-9), "{} {:?} {}: {}", e, q, x, err);
            }
        }
    }

    #[test]
    fn texel_monotone((codec, n, a, b) in (unit_codec(), 13u32..=32, -1.3f64..1.3, -1.3f64..1.3)) {
        let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
        for q in QUANTS {
            for o in [Overflow::Sat, Overflow::SatSym] {
                let e = texel(codec, n, q, o);
                prop_assert!(e.encode(lo) <= e.encode(hi), "{} {:?} {:?} {} {}", e, q, o, lo, hi);
            }
        }
    }

    #[test]
    fn fixed_codec_round_trip((f, c) in wide_format().prop_flat_map(|f| {
        (Just(f), f.min_raw()..=f.max_raw())
    })) {
        for q in QUANTS {
            let mut e = Encoding::fixed(f);
            e.quant = q;
            prop_assert_eq!(e.encode(e.decode(c)), c, "{} {:?}", f, q);
        }
    }
}

#[test]
fn texel_endpoints_wide() {
    for n in 13..=32u32 {
        texel_endpoints(n);
    }
}

// ------------------------------------------------------------------------------------------
// The `fixed` crate as an independent oracle.
// ------------------------------------------------------------------------------------------

/// Floats for a fixed type: dyadic points with eighth-LSB offsets near its range, and
/// arbitrary finite values.
fn finite_f64_for(f: Format) -> BoxedStrategy<f64> {
    let scale = (-(f.frac as f64 + 3.0)).exp2();
    prop_oneof![
        4 => (near_range(f), 0i128..8).prop_map(move |(k, t)| (8 * k + t) as f64 * scale),
        2 => (any::<i64>(), -120i32..=60).prop_map(|(m, e)| (m >> 11) as f64 * (e as f64).exp2()),
        1 => any::<u64>().prop_map(f64::from_bits).prop_filter("finite", |x| x.is_finite()),
    ]
    .boxed()
}

macro_rules! fixed_from_num {
    ($name:ident, $T:ty, $fmt:expr) => {
        proptest! {
            #![proptest_config(cfg(CASES))]
            #[test]
            fn $name(x in finite_f64_for($fmt)) {
                let f: Format = $fmt;
                let ours_sat = f.from_f64(x, Quant::RndConv, Overflow::Sat);
                let ours_wrap = f.from_f64(x, Quant::RndConv, Overflow::Wrap);
                prop_assert_eq!(<$T>::saturating_from_num(x).to_bits() as i64, ours_sat,
                    "saturating_from_num({:e})", x);
                prop_assert_eq!(<$T>::wrapping_from_num(x).to_bits() as i64, ours_wrap,
                    "wrapping_from_num({:e})", x);
                // checked_from_num is Some exactly when the rounded value fits.
                let in_range = fits(f, x, Quant::RndConv);
                prop_assert_eq!(<$T>::checked_from_num(x).map(|v| v.to_bits() as i64),
                    in_range.then_some(ours_sat), "checked_from_num({:e})", x);
            }
        }
    };
}

fixed_from_num!(fixed_from_num_i8f8, I8F8, Format::s(16, 8));
fixed_from_num!(fixed_from_num_u8f8, U8F8, Format::u(16, 8));
fixed_from_num!(fixed_from_num_i4f12, I4F12, Format::s(16, 12));
fixed_from_num!(fixed_from_num_i1f15, I1F15, Format::s(16, 15));
fixed_from_num!(fixed_from_num_u0f16, U0F16, Format::u(16, 16));
fixed_from_num!(fixed_from_num_i16f16, I16F16, Format::s(32, 16));
fixed_from_num!(fixed_from_num_u16f16, U16F16, Format::u(32, 16));

#[test]
fn fixed_from_num_infinities_saturate() {
    let f = Format::s(16, 8);
    assert_eq!(
        I8F8::saturating_from_num(f64::INFINITY).to_bits() as i64,
        f.from_f64(f64::INFINITY, Quant::RndConv, Overflow::Sat)
    );
    assert_eq!(
        I8F8::saturating_from_num(f64::NEG_INFINITY).to_bits() as i64,
        f.from_f64(f64::NEG_INFINITY, Quant::RndConv, Overflow::Sat)
    );
    // A worked tie: 1.5 LSB and 2.5 LSB of I8F8 go to the even neighbour.
    assert_eq!(I8F8::from_num(1.5 / 256.0).to_bits(), 2);
    assert_eq!(I8F8::from_num(2.5 / 256.0).to_bits(), 2);
    assert_eq!(I8F8::from_num(-1.5 / 256.0).to_bits(), -2);
    assert_eq!(f.from_f64(-1.5 / 256.0, Quant::RndConv, Overflow::Sat), -2);
}

/// The 16-bit UnitSigned texel codec is I1F15; UnitUnsigned is not U0F16 (it
/// divides by 2^16 - 1), but the Fixed codec of u0.16 is.
#[test]
fn texel_codecs_against_fixed_types() {
    let s16 = {
        let mut e = Encoding::texel(Codec::UnitSigned, true, 16);
        e.quant = Quant::RndConv;
        e
    };
    let mut u16 = Encoding::fixed(Format::u(16, 16));
    u16.quant = Quant::RndConv;
    let mut runner = proptest::test_runner::TestRunner::new(cfg(CASES));
    runner
        .run(&(-1.5f64..1.5), |x| {
            prop_assert_eq!(
                s16.encode(x),
                I1F15::saturating_from_num(x).to_bits() as i64
            );
            prop_assert_eq!(
                s16.decode(s16.encode(x)),
                I1F15::saturating_from_num(x).to_num::<f64>()
            );
            prop_assert_eq!(
                u16.encode(x),
                U0F16::saturating_from_num(x).to_bits() as i64
            );
            Ok(())
        })
        .unwrap();
}

macro_rules! fixed_mul {
    ($name:ident, $T:ty, $Bits:ty, $fmt:expr) => {
        proptest! {
            #![proptest_config(cfg(CASES))]
            #[test]
            fn $name(
                a in prop_oneof![any::<$Bits>(), Just(<$Bits>::MIN), Just(<$Bits>::MAX), (-300i32..300).prop_map(|v| v as $Bits)],
                b in prop_oneof![any::<$Bits>(), Just(<$Bits>::MIN), Just(<$Bits>::MAX), (-300i32..300).prop_map(|v| v as $Bits)],
            ) {
                let f: Format = $fmt;
                let (x, y) = (<$T>::from_bits(a), <$T>::from_bits(b));
                let prod = a as i128 * b as i128; // 2 * frac fraction bits
                let from = 2 * f.frac as u32;
                prop_assert_eq!(x.wrapping_mul(y).to_bits() as i64, f.cast(prod, from, Quant::Trn, Overflow::Wrap));
                prop_assert_eq!(x.saturating_mul(y).to_bits() as i64, f.cast(prod, from, Quant::Trn, Overflow::Sat));
                // Documented route: the full product, then a fixed-to-fixed conversion, which
                // discards the extra fraction bits (toward -inf).
                let wide = x.wide_mul(y);
                prop_assert_eq!(wide.to_bits() as i128, prod);
                prop_assert_eq!(<$T>::wrapping_from_num(wide).to_bits() as i64, f.cast(prod, from, Quant::Trn, Overflow::Wrap));
                prop_assert_eq!(<$T>::saturating_from_num(wide).to_bits() as i64, f.cast(prod, from, Quant::Trn, Overflow::Sat));
            }
        }
    };
}

fixed_mul!(fixed_mul_i8f8, I8F8, i16, Format::s(16, 8));
fixed_mul!(fixed_mul_u8f8, U8F8, u16, Format::u(16, 8));
fixed_mul!(fixed_mul_i4f12, I4F12, i16, Format::s(16, 12));
fixed_mul!(fixed_mul_i16f16, I16F16, i32, Format::s(32, 16));
fixed_mul!(fixed_mul_u16f16, U16F16, u32, Format::u(32, 16));

proptest! {
    #![proptest_config(cfg(CASES))]

    /// Fixed-to-fixed conversions that drop fraction bits (documented: toward -inf).
    #[test]
    fn fixed_narrowing_conversions(a in any::<i32>(), u in any::<u32>()) {
        let x = I16F16::from_bits(a);
        let s16_8 = Format::s(16, 8);
        prop_assert_eq!(I8F8::wrapping_from_num(x).to_bits() as i64, s16_8.cast(a as i128, 16, Quant::Trn, Overflow::Wrap));
        prop_assert_eq!(I8F8::saturating_from_num(x).to_bits() as i64, s16_8.cast(a as i128, 16, Quant::Trn, Overflow::Sat));
        let s16_12 = Format::s(16, 12);
        prop_assert_eq!(I4F12::wrapping_from_num(x).to_bits() as i64, s16_12.cast(a as i128, 16, Quant::Trn, Overflow::Wrap));
        prop_assert_eq!(I4F12::saturating_from_num(x).to_bits() as i64, s16_12.cast(a as i128, 16, Quant::Trn, Overflow::Sat));
        let u16_8 = Format::u(16, 8);
        prop_assert_eq!(U8F8::wrapping_from_num(x).to_bits() as i64, u16_8.cast(a as i128, 16, Quant::Trn, Overflow::Wrap));
        prop_assert_eq!(U8F8::saturating_from_num(x).to_bits() as i64, u16_8.cast(a as i128, 16, Quant::Trn, Overflow::Sat));
        let y = U16F16::from_bits(u);
        prop_assert_eq!(I8F8::wrapping_from_num(y).to_bits() as i64, s16_8.cast(u as i128, 16, Quant::Trn, Overflow::Wrap));
        prop_assert_eq!(I8F8::saturating_from_num(y).to_bits() as i64, s16_8.cast(u as i128, 16, Quant::Trn, Overflow::Sat));
        // Widening (more fraction bits): exact.
        let z = I8F8::from_bits(a as i16);
        prop_assert_eq!(I16F16::from_num(z).to_bits() as i64, Format::s(32, 16).cast(a as i16 as i128, 8, Quant::Rnd, Overflow::Sat));
    }

    /// Rounding to an integer: round_ties_even = RndConv, round = RndInf (ties away from
    /// zero), floor = Trn, round_to_zero = TrnZero.
    #[test]
    fn fixed_round_to_integer(a in prop_oneof![any::<i32>(), (-40i32..40).prop_map(|k| k << 15), (i32::MAX - 99_999)..=i32::MAX, i32::MIN..=(i32::MIN + 99_999)]) {
        let x = I16F16::from_bits(a);
        let int = Format::s(16, 0);
        let raw = a as i128;
        let cases = [
            (x.wrapping_round_ties_even(), Quant::RndConv),
            (x.wrapping_round(), Quant::RndInf),
            (x.wrapping_floor(), Quant::Trn),
            (x.round_to_zero(), Quant::TrnZero),
        ];
        for (r, q) in cases {
            prop_assert_eq!(r.frac().to_bits(), 0);
            prop_assert_eq!((r.to_bits() >> 16) as i64, int.cast(raw, 16, q, Overflow::Wrap), "{} {:?}", x, q);
        }
    }
}

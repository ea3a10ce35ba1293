//! Exhaustive checks of `bumpsim_hw::format` for every width from 1 to 12 bits.
//!
//! Every result is compared with an exact oracle (`common/mod.rs`) written with integer
//! arithmetic only (an `i128` numerator over a power-of-two or small denominator), whose
//! rounding and overflow rules are taken from the Algorithmic C datatypes reference
//! (`ac_fixed`).
//!
//! Widths above 12 bits are covered by random inputs in `format_props.rs`.

mod common;

use bumpsim_hw::format::{shift_round, Codec, Encoding, Format, Overflow, Quant};
use common::{overflow_oracle, range, round_div, texel, texel_endpoints, OVERFLOWS, QUANTS};

// ------------------------------------------------------------------------------------------
// Helpers.
// ------------------------------------------------------------------------------------------

/// The fraction counts tried for a width: 0, 1, width/2 and width (deduplicated).
fn fracs(width: u32) -> Vec<u32> {
    let mut v = vec![0, 1.min(width), width / 2, width];
    v.sort_unstable();
    v.dedup();
    v
}

/// All formats of 1 to 12 bits, signed and unsigned, with the fractions of [`fracs`].
fn small_formats() -> Vec<Format> {
    let mut out = Vec::new();
    for signed in [false, true] {
        for w in 1..=12u32 {
            for fr in fracs(w) {
                out.push(Format::new(signed, w, fr).unwrap());
            }
        }
    }
    out
}

/// Extra LSBs beyond the representable range on each side: the whole range again (two
/// wrap-arounds) for narrow words, 256 LSBs for wide ones.
fn margin(width: u32) -> i128 {
    (1i128 << width).min(256)
}

/// Values far outside every small format, for wrap-around and saturation.
const FAR: [i128; 12] = [
    1 << 40,
    (1 << 40) + 5,
    -(1 << 40),
    -(1 << 40) - 3,
    (1 << 62) - 1,
    -(1 << 62),
    i64::MAX as i128,
    i64::MIN as i128,
    (1 << 100) + 12345,
    -(1 << 100) - 12345,
    i128::MAX >> 8,
    i128::MIN >> 8,
];

// ------------------------------------------------------------------------------------------
// The oracle itself, on hand-computed values (so a wrong oracle cannot hide a wrong cast).
// ------------------------------------------------------------------------------------------

#[test]
fn oracle_agrees_with_hand_computed_values() {
    // -1.5 LSB and +1.5 LSB, and 2.5 / -2.5 (for the ties-to-even / odd modes).
    let table: [(Quant, [i128; 4]); 8] = [
        (Quant::Trn, [-2, 1, 2, -3]),
        (Quant::TrnZero, [-1, 1, 2, -2]),
        (Quant::Rnd, [-1, 2, 3, -2]),
        (Quant::RndZero, [-1, 1, 2, -2]),
        (Quant::RndInf, [-2, 2, 3, -3]),
        (Quant::RndMinInf, [-2, 1, 2, -3]),
        (Quant::RndConv, [-2, 2, 2, -2]),
        (Quant::RndConvOdd, [-1, 1, 3, -3]),
    ];
    for (q, [m15, p15, p25, m25]) in table {
        assert_eq!(round_div(-3, 2, q), m15, "{q:?} -1.5");
        assert_eq!(round_div(3, 2, q), p15, "{q:?} +1.5");
        assert_eq!(round_div(5, 2, q), p25, "{q:?} +2.5");
        assert_eq!(round_div(-5, 2, q), m25, "{q:?} -2.5");
        // not a tie: -1.25 and 1.75
        let nearest = !matches!(q, Quant::Trn | Quant::TrnZero);
        assert_eq!(
            round_div(-5, 4, q),
            if nearest || q == Quant::TrnZero {
                -1
            } else {
                -2
            }
        );
        assert_eq!(round_div(7, 4, q), if nearest { 2 } else { 1 });
    }
    assert_eq!(overflow_oracle(true, 4, 9, Overflow::Wrap), -7);
    assert_eq!(overflow_oracle(true, 4, -8, Overflow::SatSym), -7);
    assert_eq!(overflow_oracle(true, 4, -8, Overflow::Sat), -8);
    assert_eq!(overflow_oracle(false, 4, -1, Overflow::Wrap), 15);
    assert_eq!(overflow_oracle(false, 4, -1, Overflow::SatSym), 0);
    assert_eq!(overflow_oracle(true, 1, -1, Overflow::SatSym), 0);
    assert_eq!(overflow_oracle(true, 1, 1, Overflow::Wrap), -1);
}

// ------------------------------------------------------------------------------------------
// Format::overflow and shift_round.
// ------------------------------------------------------------------------------------------

#[test]
fn overflow_every_value_every_mode() {
    let mut checked = 0u64;
    for signed in [false, true] {
        for w in 1..=12u32 {
            let f = Format::new(signed, w, 0).unwrap();
            let (min, max) = range(signed, w);
            let m = 1i128 << w;
            let values = (min - 2 * m..=max + 2 * m).chain(FAR);
            for v in values {
                for o in OVERFLOWS {
                    let want = overflow_oracle(signed, w, v, o);
                    assert_eq!(f.overflow(v, o), want, "{f} overflow({v}, {o:?})");
                    checked += 1;
                }
            }
        }
    }
    println!("overflow: {checked} comparisons");
    assert!(checked > 200_000);
}

#[test]
fn shift_round_small_shifts() {
    for by in 0..=10u32 {
        for v in -3000i128..=3000 {
            for q in QUANTS {
                assert_eq!(
                    shift_round(v, by, q),
                    round_div(v, 1 << by, q),
                    "{v} >> {by} {q:?}"
                );
            }
        }
    }
}

// ------------------------------------------------------------------------------------------
// Format::cast from a source with more (or fewer) fraction bits.
// ------------------------------------------------------------------------------------------

/// Every source word whose value lies within the margin around the target range, for source
/// fraction counts frac-2 ..= frac+3.
fn cast_exhaustive(signed: bool) -> u64 {
    let mut checked = 0u64;
    for f in small_formats().into_iter().filter(|f| f.signed == signed) {
        let w = f.width as u32;
        let (min, max) = range(signed, w);
        let (lo, hi) = (min - margin(w), max + margin(w));
        for d in -2i32..=3 {
            let from_frac = f.frac as i32 + d;
            if from_frac < 0 {
                continue;
            }
            let from_frac = from_frac as u32;
            let (src_lo, src_hi) = if d >= 0 {
                ((lo << d) - ((1 << d) - 1), (hi << d) + ((1 << d) - 1))
            } else {
                (lo >> -d, hi >> -d)
            };
            // Both signs of source words: an unsigned source is just the non-negative part.
            let raws = (src_lo..=src_hi).chain(FAR);
            for raw in raws {
                for q in QUANTS {
                    let rounded = if d >= 0 {
                        round_div(raw, 1 << d, q)
                    } else {
                        raw * (1 << -d)
                    };
                    for o in OVERFLOWS {
                        let want = overflow_oracle(signed, w, rounded, o);
                        let got = f.cast(raw, from_frac, q, o);
                        if got != want {
                            panic!(
                                "{f} (ac_fixed<{w},{},{signed}>) cast({raw}, from_frac {from_frac}, \
                                 {q:?}, {o:?}) = {got}, expected {want}",
                                w as i32 - f.frac as i32
                            );
                        }
                        checked += 1;
                    }
                }
            }
        }
    }
    checked
}

#[test]
fn cast_unsigned_formats_match_oracle() {
    let n = cast_exhaustive(false);
    println!("cast, unsigned targets: {n} comparisons");
    assert!(n > 1_000_000);
}

#[test]
fn cast_signed_formats_match_oracle() {
    let n = cast_exhaustive(true);
    println!("cast, signed targets: {n} comparisons");
    assert!(n > 1_000_000);
}

#[test]
fn cast_hand_computed_cases() {
    // -1.5 LSB into s8.0 from 1 extra fraction bit, every mode (the docs' worked example).
    let f = Format::s(8, 0);
    let cases = [
        (Quant::Trn, -2),
        (Quant::TrnZero, -1),
        (Quant::Rnd, -1),
        (Quant::RndZero, -1),
        (Quant::RndInf, -2),
        (Quant::RndMinInf, -2),
        (Quant::RndConv, -2),
        (Quant::RndConvOdd, -1),
    ];
    for (q, want) in cases {
        assert_eq!(f.cast(-3, 1, q, Overflow::Sat), want, "{q:?}");
    }
    // Overflow of u4.0 / s4.0 with a value of 18.75 and -9.
    let u = Format::u(4, 0);
    assert_eq!(u.cast(75, 2, Quant::Rnd, Overflow::Wrap), 3); // 19 mod 16
    assert_eq!(u.cast(75, 2, Quant::Trn, Overflow::Wrap), 2); // 18 mod 16
    assert_eq!(u.cast(75, 2, Quant::Rnd, Overflow::Sat), 15);
    assert_eq!(u.cast(75, 2, Quant::Rnd, Overflow::SatZero), 0);
    let s = Format::s(4, 0);
    assert_eq!(s.cast(-9, 0, Quant::Trn, Overflow::Wrap), 7);
    assert_eq!(s.cast(-9, 0, Quant::Trn, Overflow::Sat), -8);
    assert_eq!(s.cast(-9, 0, Quant::Trn, Overflow::SatSym), -7);
    // AC_SAT_SYM: a result that is exactly MIN also becomes -MAX.
    assert_eq!(s.cast(-8, 0, Quant::Trn, Overflow::SatSym), -7);
    assert_eq!(s.cast(-17, 1, Quant::Rnd, Overflow::SatSym), -7); // -8.5 -> -8 -> -7
    assert_eq!(s.cast(-17, 1, Quant::Rnd, Overflow::Sat), -8);
    // 1-bit signed: MIN = -1, MAX = 0, so the symmetric range is {0}.
    assert_eq!(Format::s(1, 0).cast(-1, 0, Quant::Trn, Overflow::SatSym), 0);
}

// ------------------------------------------------------------------------------------------
// Format::from_f64 on exact dyadic inputs.
// ------------------------------------------------------------------------------------------

#[test]
fn from_f64_points_midpoints_and_quarters() {
    let mut checked = 0u64;
    for f in small_formats() {
        let w = f.width as u32;
        let fr = f.frac as i32;
        let (min, max) = range(f.signed, w);
        // x = n / 2^(frac+2): t = 0 is a representable value (or an integer multiple of the
        // LSB outside the range), t = 2 a midpoint, t = 1 and 3 quarter points.
        for k in (min - margin(w))..=(max + margin(w)) {
            for t in 0..4i128 {
                let n = 4 * k + t;
                let x = n as f64 * (-(fr + 2) as f64).exp2(); // exact
                for q in QUANTS {
                    let rounded = round_div(n, 4, q);
                    for o in OVERFLOWS {
                        let want = overflow_oracle(f.signed, w, rounded, o);
                        let got = f.from_f64(x, q, o);
                        if got != want {
                            panic!("{f} from_f64({x}) {q:?} {o:?} = {got}, expected {want}");
                        }
                        checked += 1;
                    }
                }
            }
        }
        // Powers of two far beyond the range, both signs, and tiny values near zero.
        for e in -60i32..=90 {
            for sign in [1i128, -1] {
                let x = sign as f64 * (e as f64).exp2();
                for q in QUANTS {
                    let s = e + fr; // x * 2^frac = sign * 2^s
                    let rounded = if s >= 0 {
                        sign << s
                    } else {
                        round_div(sign, 1 << -s, q)
                    };
                    for o in OVERFLOWS {
                        let want = overflow_oracle(f.signed, w, rounded, o);
                        assert_eq!(f.from_f64(x, q, o), want, "{f} from_f64({x}) {q:?} {o:?}");
                    }
                }
            }
        }
        // Non-finite and signed zero, as documented: NaN -> 0, infinities saturate (0 in Wrap).
        for q in QUANTS {
            for o in OVERFLOWS {
                assert_eq!(f.from_f64(f64::NAN, q, o), 0);
                assert_eq!(f.from_f64(-0.0, q, o), 0);
                let (pos, neg) = match o {
                    Overflow::Wrap | Overflow::SatZero => (0, 0),
                    Overflow::Sat => (max as i64, min as i64),
                    Overflow::SatSym => (max as i64, if f.signed { -max as i64 } else { 0 }),
                };
                assert_eq!(f.from_f64(f64::INFINITY, q, o), pos, "{f} +inf {o:?}");
                assert_eq!(f.from_f64(f64::NEG_INFINITY, q, o), neg, "{f} -inf {o:?}");
            }
        }
    }
    println!("from_f64: {checked} comparisons on the quarter-LSB grid");
    assert!(checked > 1_000_000);
}

// ------------------------------------------------------------------------------------------
// Encoding: texel codecs, widths 2..=12.
// ------------------------------------------------------------------------------------------

/// Exact expected code for x = k / 2^g, from the codec definitions:
/// UnitUnsigned c = x (2^n - 1); UnitSigned c = x 2^(n-1); UnitSymmetric c = (x (2^n-1) - 1) / 2.
fn expected_texel_code(codec: Codec, n: u32, k: i128, g: u32, q: Quant, o: Overflow) -> i64 {
    let m = (1i128 << n) - 1;
    let (num, den) = match codec {
        Codec::UnitUnsigned => (k * m, 1i128 << g),
        Codec::UnitSigned => (k << (n - 1), 1i128 << g),
        Codec::UnitSymmetric => (k * m - (1i128 << g), 1i128 << (g + 1)),
        Codec::Fixed => unreachable!(),
    };
    let signed = codec != Codec::UnitUnsigned;
    overflow_oracle(signed, n, round_div(num, den, q), o)
}

/// The exact value of code c as a fraction num / den.
fn texel_value(codec: Codec, n: u32, c: i128) -> (i128, i128) {
    let m = (1i128 << n) - 1;
    match codec {
        Codec::UnitUnsigned => (c, m),
        Codec::UnitSigned => (c, 1i128 << (n - 1)),
        Codec::UnitSymmetric => (2 * c + 1, m),
        Codec::Fixed => unreachable!(),
    }
}

const UNIT_CODECS: [Codec; 3] = [Codec::UnitUnsigned, Codec::UnitSigned, Codec::UnitSymmetric];

#[test]
fn texel_round_trip_every_code() {
    for n in 2..=12u32 {
        for codec in UNIT_CODECS {
            let (min, max) = range(codec != Codec::UnitUnsigned, n);
            // Every mode gives the code back exactly. For the truncating modes and the
            // c / (2^n - 1) codecs this rests on f64 rounding: decode(c) may lie just below the
            // real c / (2^n - 1), but decode(c) * (2^n - 1) rounds back to exactly c for every
            // code of 2 to 12 bits (checked here; wider words are only checked for rounding to
            // nearest, in format_props.rs).
            for q in QUANTS {
                let e = texel(codec, n, q, Overflow::Sat);
                for c in min..=max {
                    let c = c as i64;
                    let x = e.decode(c);
                    assert_eq!(e.encode(x), c, "{e} {q:?} encode(decode({c}) = {x})");
                    assert_eq!(e.decode(e.encode(x)), x);
                }
            }
        }
    }
}

#[test]
fn texel_decode_is_exact_and_strictly_increasing() {
    for n in 2..=12u32 {
        for codec in UNIT_CODECS {
            let e = texel(codec, n, Quant::Rnd, Overflow::Sat);
            let (min, max) = range(codec != Codec::UnitUnsigned, n);
            let mut prev = f64::NEG_INFINITY;
            for c in min..=max {
                let (num, den) = texel_value(codec, n, c);
                let x = e.decode(c as i64);
                assert_eq!(x, num as f64 / den as f64, "{e} decode({c})");
                assert!(x > prev, "{e} decode not increasing at {c}");
                prev = x;
            }
        }
    }
}

#[test]
fn texel_documented_endpoints() {
    for n in 2..=12u32 {
        let half = 1i64 << (n - 1);
        let all = (1i64 << n) - 1;
        // The endpoints every width shares, then the ones checked only up to 12 bits.
        let (s, y, u) = texel_endpoints(n);
        // UnitSigned (NVIDIA): -2^(n-1) is exactly -1.0, the top code is 1 - 2^-(n-1).
        assert_eq!(s.decode(0), 0.0);
        assert_eq!(s.decode(half - 1), 1.0 - (-(n as f64 - 1.0)).exp2());
        assert_eq!(s.encode(0.0), 0);
        assert_eq!(s.encode(-7.0), -half);
        // UnitSymmetric (OpenGL (2c+1)/(2^n-1)): +-1.0 at the extremes, no code is zero.
        assert_eq!(y.decode(0), 1.0 / all as f64);
        assert_eq!(y.decode(-1), -1.0 / all as f64);
        for c in -half..half {
            assert_ne!(y.decode(c), 0.0);
            assert_eq!(y.decode(c), -y.decode(-1 - c), "symmetry at {c}");
        }
        // UnitUnsigned: 0 and all-ones are 0.0 and 1.0.
        assert_eq!(u.decode(0), 0.0);
        assert_eq!(u.encode(-0.25), 0);
        assert_eq!(u.encode(3.0), all);
        // Half steps of the documented formulas.
        assert_eq!(u.max_error(), 0.5 / all as f64);
        assert_eq!(s.max_error(), 0.5 / half as f64);
        assert_eq!(y.max_error(), 1.0 / all as f64);
        assert_eq!(
            texel(Codec::UnitUnsigned, n, Quant::Trn, Overflow::Sat).max_error(),
            1.0 / all as f64
        );
    }
}

/// Exact encode oracle, monotonicity and the error bound on the grid x = k / 2^(n+3),
/// x in [-1.25, 1.25].
#[test]
fn texel_encode_on_fine_grid() {
    let mut checked = 0u64;
    for n in 2..=12u32 {
        let g = n + 3;
        let kmax = (5i128 << g) / 4;
        for codec in UNIT_CODECS {
            let signed = codec != Codec::UnitUnsigned;
            let (min, max) = range(signed, n);
            let (lo_num, lo_den) = texel_value(codec, n, min);
            let (hi_num, hi_den) = texel_value(codec, n, max);
            for q in QUANTS {
                for o in OVERFLOWS {
                    let e = texel(codec, n, q, o);
                    let monotone = matches!(o, Overflow::Sat | Overflow::SatSym);
                    let bound = e.max_error();
                    let truncating = matches!(q, Quant::Trn | Quant::TrnZero);
                    let mut prev = i64::MIN;
                    for k in -kmax..=kmax {
                        let x = k as f64 / (1u64 << g) as f64; // exact
                        let c = e.encode(x);
                        let want = expected_texel_code(codec, n, k, g, q, o);
                        if c != want {
                            panic!("{e} {q:?} {o:?} encode({x}) = {c}, expected {want}");
                        }
                        checked += 1;
                        if monotone {
                            assert!(c >= prev, "{e} {q:?} {o:?} not monotone at {x}");
                            prev = c;
                        }
                        // Inside [decode(min), decode(max)] the error is at most half a step
                        // (a whole step when truncating); checked exactly and in f64.
                        let inside = k * lo_den >= lo_num << g && k * hi_den <= hi_num << g;
                        if inside && o != Overflow::SatSym {
                            let (num, den) = texel_value(codec, n, c as i128);
                            // |num/den - k/2^g| <= step (/ 2), step = 2/den for UnitSymmetric
                            let err = (num * (1i128 << g) - k * den).abs(); // * 1/(den 2^g)
                            let step = (if codec == Codec::UnitSymmetric { 2 } else { 1 }) << g;
                            let limit = if truncating { step } else { step / 2 };
                            assert!(err <= limit, "{e} {q:?} encode({x}) = {c}: too far");
                            if truncating {
                                assert!(err < limit, "{e} {q:?} truncation error must be < 1 step");
                            }
                            let fe = (e.decode(c) - x).abs();
                            assert!(fe <= bound * (1.0 + 1e-12), "{e} {q:?} {x}: {fe} > {bound}");
                        }
                    }
                }
            }
        }
    }
    println!("texel encode: {checked} comparisons on the grid");
    assert!(checked > 1_000_000);
}

#[test]
fn fixed_codec_round_trip_and_grid() {
    for f in small_formats() {
        for q in QUANTS {
            let mut e = Encoding::fixed(f);
            e.quant = q;
            e.overflow = Overflow::Sat;
            for c in f.min_raw()..=f.max_raw() {
                let x = e.decode(c);
                assert_eq!(x, c as f64 * (-(f.frac as f64)).exp2());
                assert_eq!(e.encode(x), c, "{f} {q:?} round trip {c}");
            }
            // Quarter-LSB grid: matches from_f64 and stays within max_error inside the range.
            let (min, max) = (f.min_raw() as i128, f.max_raw() as i128);
            for n in 4 * min..=4 * max {
                let x = n as f64 * (-(f.frac as f64 + 2.0)).exp2();
                let c = e.encode(x);
                assert_eq!(
                    c as i128,
                    round_div(n, 4, q).clamp(min, max),
                    "{f} {q:?} {x}"
                );
                assert!((e.decode(c) - x).abs() <= e.max_error(), "{f} {q:?} {x}");
            }
        }
    }
}

#[test]
fn encoding_validation() {
    for n in 2..=12u8 {
        for codec in UNIT_CODECS {
            assert!(Encoding::texel(codec, codec != Codec::UnitUnsigned, n)
                .validate()
                .is_ok());
            assert!(Encoding::texel(codec, codec == Codec::UnitUnsigned, n)
                .validate()
                .is_err());
        }
    }
    assert!(Encoding::texel(Codec::UnitSigned, true, 1)
        .validate()
        .is_err());
    assert!(Encoding::texel(Codec::UnitSymmetric, true, 1)
        .validate()
        .is_err());
}

/// `from_f64`'s i64 path against the general i128 one: every format up to 12 bits, at
/// every half LSB and the doubles either side of it, across and beyond the range, and
/// at pseudo-random values of every width.
#[test]
fn fast_path_is_the_general_path() {
    let mut checked = 0u64;
    let mut check = |f: &Format, x: f64| {
        for q in QUANTS {
            for o in OVERFLOWS {
                assert_eq!(
                    f.from_f64(x, q, o),
                    f.from_f64_wide(x, q, o),
                    "{f} from_f64({x:e}) {q:?} {o:?}"
                );
                checked += 1;
            }
        }
    };
    for width in 1..=12u32 {
        for frac in 0..=width {
            for signed in [false, true] {
                let f = Format::new(signed, width, frac).unwrap();
                for x in half_lsb_grid(&f) {
                    check(&f, x);
                }
            }
        }
    }
    let mut next = xorshift();
    for _ in 0..200_000 {
        let state = next();
        let f = random_format(state);
        // magnitudes from 2^-40 to 2^70 of the LSB, either sign
        let e = ((state >> 20) % 110) as i32 - 40;
        let m = (state >> 32) as f64 / 4_294_967_296.0;
        let sign = if state >> 63 == 1 { -1.0 } else { 1.0 };
        check(&f, sign * m * bumpsim_hw::format::pow2(e) * f.lsb());
    }
    for x in [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        -0.0,
        4.0e18,
        -4.0e18,
    ] {
        check(&Format::s(16, 8), x);
    }
    assert!(checked > 10_000_000, "{checked}");
}

/// `from_f64_slice` against one `from_f64` per value: every format up to 12 bits, at every
/// half LSB and the doubles either side of it, across and beyond the range (slices that mix
/// the common case with overflowing values), pseudo-random values of every width and
/// magnitude around the common case's 2^51 bound, and NaN and infinities among ordinary values.
#[test]
fn slice_is_from_f64_per_value() {
    let mut checked = 0u64;
    let mut check = |f: &Format, xs: &[f64]| {
        for q in QUANTS {
            for o in OVERFLOWS {
                let mut out = vec![i64::MIN; xs.len()];
                f.from_f64_slice(xs, q, o, &mut out);
                for (&x, &r) in xs.iter().zip(&out) {
                    assert_eq!(r, f.from_f64(x, q, o), "{f} from_f64({x:e}) {q:?} {o:?}");
                }
                checked += xs.len() as u64;
            }
        }
    };
    for width in 1..=12u32 {
        for frac in 0..=width {
            for signed in [false, true] {
                let f = Format::new(signed, width, frac).unwrap();
                let xs = half_lsb_grid(&f);
                check(&f, &xs);
                // slices within the range only (no value redone): the first quarter of them
                // lies below an unsigned format's range, so take the middle
                let mid = xs.len() / 2;
                check(&f, &xs[mid..mid + 3 * (1usize << width)]);
            }
        }
    }
    let mut next = xorshift();
    for _ in 0..20_000 {
        let s = next();
        let f = random_format(s);
        let xs: Vec<f64> = (0..16)
            .map(|_| {
                let s = next();
                // magnitudes from 2^-40 to 2^70 of the LSB, and 2^50 to 2^52 (the bound)
                let e = if s & 1 == 0 {
                    ((s >> 20) % 110) as i32 - 40
                } else {
                    50 + ((s >> 20) % 3) as i32
                };
                let m = (s >> 32) as f64 / 4_294_967_296.0;
                let sign = if s >> 63 == 1 { -1.0 } else { 1.0 };
                sign * m * bumpsim_hw::format::pow2(e) * f.lsb()
            })
            .collect();
        check(&f, &xs);
    }
    let f = Format::s(16, 8);
    check(
        &f,
        &[
            1.5,
            f64::NAN,
            -0.0,
            f64::INFINITY,
            2.0,
            f64::NEG_INFINITY,
            4.0e18,
            -4.0e18,
            0.25,
        ],
    );
    check(
        &f,
        &[
            (1u64 << 43) as f64,
            -((1u64 << 43) as f64),
            2251799813685247.0 / 256.0,
        ],
    );
    assert!(checked > 5_000_000, "{checked}");
}

/// Every half LSB of `f` across its range and two LSBs beyond, and the doubles either side of
/// each: where the rounding modes and the overflow modes decide.
fn half_lsb_grid(f: &Format) -> Vec<f64> {
    let half = f.lsb() / 2.0;
    let span = (1i64 << (f.width + 1)) + 4;
    (-span..=span)
        .flat_map(|k| {
            let x = k as f64 * half;
            [x, x.next_up(), x.next_down()]
        })
        .collect()
}

/// A xorshift64 stream from a fixed seed.
fn xorshift() -> impl FnMut() -> u64 {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    }
}

/// A format of 1 to 32 bits drawn from the random word `s` (its low 17 bits).
fn random_format(s: u64) -> Format {
    let width = 1 + (s % 32) as u32;
    let frac = ((s >> 8) % (width as u64 + 1)) as u32;
    Format::new(s >> 16 & 1 == 1, width, frac).unwrap()
}

//! The casts of the datapath as Verilog: [`crate::format::shift_round`] in every [`Quant`]
//! mode, [`crate::format::Format::overflow`] in every [`Overflow`] mode, and
//! [`crate::arith::Acc::to_code`] into every codec; [`clamp_code`] fuses a clamp with the cast
//! that follows it.

use super::fixed::{align_wire, clamp, constant, floor_shr, make, plain, scale, sub, Fx};
use super::verilog::{lit, Module};
use crate::arith::Acc;
use crate::format::{Codec, Encoding, Format, Overflow, Quant};

/// A fused clamp and cast: `to_code(clamp(a, lo, hi), enc)` with the comparisons on `a`'s own
/// word (its factors kept) and the limits' codes as constants, so the mux is as wide as the
/// code. Exactly [`crate::arith::Acc::clamp`] then [`crate::arith::Acc::to_code`].
pub fn clamp_code(
    m: &mut Module,
    a: &Fx,
    lo: Option<(i128, u32)>,
    hi: Option<(i128, u32)>,
    enc: &Encoding,
) -> String {
    let a = align_wire(m, a, a.frac);
    let f = a.fac.iter().fold(1i128, |k, &n| k * ((1i128 << n) + 1));
    // x = r F / 2^fa against B = braw / 2^bf: r F 2^bf vs braw 2^fa
    let ratio = |(braw, bf): (i128, u32)| -> (i128, i128) {
        let (n, d) = (braw << a.frac, f << bf);
        (n.div_euclid(d), -((-n).div_euclid(d))) // (floor, ceil)
    };
    let lo_t = lo.map(|l| (ratio(l).1, l)).filter(|(t, _)| *t > a.lo);
    let hi_t = hi.map(|h| (ratio(h).0, h)).filter(|(t, _)| *t < a.hi);
    let mut inner = a.clone();
    if let Some((t, _)) = lo_t {
        inner.lo = inner.lo.max(t);
    }
    if let Some((t, _)) = hi_t {
        inner.hi = inner.hi.min(t);
    }
    if inner.lo > inner.hi {
        // every value is clamped: a constant code
        let (_, b) = lo_t.or(hi_t).unwrap();
        let c = Acc::new(b.0, b.1).to_code(enc);
        return m.uwire("code", enc.width(), &code_lit(enc, c));
    }
    let mut e = to_code(m, &inner, enc);
    let x = &a.name;
    if let Some((t, b)) = hi_t {
        let c = code_lit(enc, Acc::new(b.0, b.1).to_code(enc));
        e = format!("({x} > {}) ? {c} : {e}", lit(t));
    }
    if let Some((t, b)) = lo_t {
        let c = code_lit(enc, Acc::new(b.0, b.1).to_code(enc));
        e = format!("({x} < {}) ? {c} : ({e})", lit(t));
    }
    m.uwire("code", enc.width(), &e)
}

fn code_lit(enc: &Encoding, c: i64) -> String {
    let w = enc.width();
    format!("{w}'d{}", enc.format.bits(c))
}

/// [`crate::format::shift_round`]: `a` (an integer at scale `2^-by`) shifted right by `by`,
/// rounded by `q`. The result has 0 fraction bits.
pub fn shift_round(m: &mut Module, a: &Fx, by: u32, q: Quant) -> Fx {
    if by == 0 {
        return a.clone().at_frac(0);
    }
    let a = &plain(m, a);
    let a = &align_wire(m, a, a.frac);
    let x = &a.name;
    let w = a.width();
    let half = 1i128 << (by - 1);
    let (flo, fhi) = (floor_shr(a.lo, by), floor_shr(a.hi, by));
    if q == Quant::Trn {
        return make(m, "trn", flo, fhi, 0, &format!("{x} >>> {by}"));
    }
    if q == Quant::Rnd {
        let (lo, hi) = (floor_shr(a.lo + half, by), floor_shr(a.hi + half, by));
        let s = make(
            m,
            "rh",
            a.lo + half,
            a.hi + half,
            0,
            &format!("{x} + {}", lit(half)),
        );
        return make(m, "rnd", lo, hi, 0, &format!("{} >>> {by}", s.name));
    }
    let floor = make(m, "flr", flo, fhi, 0, &format!("{x} >>> {by}"));
    let low = m.uwire("low", by, &format!("{x}[{}:0]", by - 1));
    let nz = m.uwire("nz", 1, &format!("|{low}"));
    let neg = m.uwire("neg", 1, &format!("{x}[{}]", w - 1));
    let is_half = m.uwire("hf", 1, &format!("{low} == {by}'d{half}"));
    let above = m.uwire("ab", 1, &format!("{low} > {by}'d{half}"));
    let up = match q {
        Quant::TrnZero => format!("{neg} & {nz}"),
        Quant::RndZero => format!("{above} | ({is_half} & {neg})"),
        Quant::RndInf => format!("{above} | ({is_half} & ~{neg})"),
        Quant::RndMinInf => above.clone(),
        Quant::RndConv => format!("{above} | ({is_half} & {}[0])", floor.name),
        Quant::RndConvOdd => format!("{above} | ({is_half} & ~{}[0])", floor.name),
        Quant::Trn | Quant::Rnd => unreachable!(),
    };
    let up = m.uwire("up", 1, &up);
    make(
        m,
        "rq",
        flo,
        fhi + 1,
        0,
        &format!("{} + $signed({{1'b0, {up}}})", floor.name),
    )
}

/// [`crate::arith::rational_code`]: the integer wire `num` over the constant `den > 0` cast
/// into `enc` with one rounding (the code's value as `a / b`, [`super::divide::round_div`])
/// and the overflow. Returns the code's bits.
pub fn rational_code(m: &mut Module, num: &Fx, den: i128, enc: &Encoding) -> String {
    let n = enc.format.width as u32;
    let int = Format {
        signed: enc.format.signed,
        width: enc.format.width,
        frac: 0,
    };
    let (a, b, fmt) = match enc.codec {
        Codec::Fixed => (scale(m, num, 1i128 << enc.format.frac), den, enc.format),
        Codec::UnitSigned => (scale(m, num, 1i128 << (n - 1)), den, int),
        Codec::UnitUnsigned => (scale(m, num, (1i128 << n) - 1), den, int),
        Codec::UnitSymmetric => {
            let t = scale(m, num, (1i128 << n) - 1);
            (sub(m, &t, &constant(den, 0)), 2 * den, int)
        }
    };
    let r = super::divide::round_div(m, &a, b, enc.quant);
    overflow(m, &r, &fmt, enc.overflow)
}

/// [`crate::format::Format::overflow`] of an integer wire into `fmt`; returns the code's
/// `fmt.width` bits (an unsigned vector).
pub fn overflow(m: &mut Module, v: &Fx, fmt: &Format, o: Overflow) -> String {
    let w = fmt.width as u32;
    let (lo, hi) = (fmt.min_raw() as i128, fmt.max_raw() as i128);
    let v = &plain(m, v);
    let v = &align_wire(m, v, v.frac);
    let x = &v.name;
    let sym = o == Overflow::SatSym && fmt.signed;
    let lo_eff = if sym { -hi } else { lo };
    let fits = v.lo >= lo_eff && v.hi <= hi;
    let sat = if fits || o == Overflow::Wrap {
        v.clone()
    } else {
        match o {
            Overflow::Sat | Overflow::SatSym => clamp(m, v, Some((lo_eff, 0)), Some((hi, 0))),
            Overflow::SatZero => {
                let out_of = format!("({x} < {}) || ({x} > {})", lit(lo), lit(hi));
                make(
                    m,
                    "sz",
                    v.lo.max(lo).min(0),
                    v.hi.min(hi).max(0),
                    0,
                    &format!("({out_of}) ? {} : {x}", lit(0)),
                )
            }
            Overflow::Wrap => unreachable!(),
        }
    };
    // the low `w` bits (wrap is this selection alone); widen first if the wire is narrower
    let sw = sat.width();
    if sw >= w {
        m.uwire("code", w, &format!("{}[{}:0]", sat.name, w - 1))
    } else {
        m.uwire(
            "code",
            w,
            &format!(
                "{{{{{}{{{}[{}]}}}}, {}}}",
                w - sw,
                sat.name,
                sw - 1,
                sat.name
            ),
        )
    }
}

/// [`crate::format::Format::cast`] of `a` (at `a.frac` fraction bits) into `fmt`.
fn cast_into(m: &mut Module, a: &Fx, fmt: &Format, q: Quant, o: Overflow) -> String {
    let a = &plain(m, a);
    let to = fmt.frac as u32;
    let v = if a.frac <= to {
        let up = to - a.frac;
        if up == 0 {
            a.clone().at_frac(0)
        } else {
            make(
                m,
                "up",
                a.lo << up,
                a.hi << up,
                0,
                &format!("{} <<< {up}", a.name),
            )
        }
    } else {
        shift_round(m, a, a.frac - to, q)
    };
    overflow(m, &v, fmt, o)
}

/// [`crate::arith::Acc::to_code`]: the cast into a port encoding with its quantization and
/// overflow modes. Returns the code's bits.
pub fn to_code(m: &mut Module, a: &Fx, enc: &Encoding) -> String {
    if !matches!(enc.codec, Codec::UnitUnsigned | Codec::UnitSymmetric) {
        let a = &plain(m, a);
        return to_code_plain(m, a, enc);
    }
    to_code_plain(m, a, enc)
}

fn to_code_plain(m: &mut Module, a: &Fx, enc: &Encoding) -> String {
    let n = enc.format.width as u32;
    let int = Format {
        signed: enc.format.signed,
        width: enc.format.width,
        frac: 0,
    };
    let (q, o) = (enc.quant, enc.overflow);
    match enc.codec {
        Codec::Fixed => cast_into(m, a, &enc.format, q, o),
        Codec::UnitSigned if a.frac + 1 >= n => {
            let r = a.clone().at_frac(a.frac + 1 - n);
            cast_into(m, &r, &int, q, o)
        }
        Codec::UnitSigned => {
            let up = n - 1 - a.frac;
            let v = make(
                m,
                "up",
                a.lo << up,
                a.hi << up,
                0,
                &format!("{} <<< {up}", a.name),
            );
            cast_into(m, &v, &int, q, o)
        }
        Codec::UnitUnsigned => {
            let v = scale(m, a, (1i128 << n) - 1);
            cast_into(m, &v, &int, q, o)
        }
        // c = (x (2^n - 1) - 1) / 2: raw (2^n - 1) - 2^frac, read with frac + 1 bits
        Codec::UnitSymmetric => {
            let s = scale(m, a, (1i128 << n) - 1);
            let v = sub(m, &s, &constant(1i128 << a.frac, a.frac)).at_frac(a.frac + 1);
            cast_into(m, &v, &int, q, o)
        }
    }
}

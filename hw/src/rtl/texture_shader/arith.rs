//! The texture shader's arithmetic beyond [`crate::rtl::fixed`]: the projective divide
//! (`FixedArith::div`), the dot-product mappings ([`crate::units::texture_shader::mapping::
//! vector_bits`]) and the HILO hemisphere's integer square root.

use super::super::divide::div_round;
use super::super::fixed::{from_code, make, raw_word, scale, shift_round, square, sub, Fx};
use super::super::verilog::{signed_bits, Module};
use crate::format::{Encoding, Format, Overflow, Quant};
use crate::units::texture_shader::DotMapping;

/// `a / b` of two coordinate raw words (`f` fraction bits, signed `w` bits) as the model's
/// `FixedArith::div`: `p = a 2^f`, the signs moved into `p`, `floor((2 p + |b|) / (2 |b|))`
/// (round half up), 0 when `b` is 0. Returns the exact quotient (0 fraction bits, the raw
/// word before the overflow into the coordinate format; under a saturating `ov` a quotient
/// beyond `2^w` is returned as `+-2^w`, which saturates alike). One unsigned divider of the
/// magnitudes; the floor of a negative quotient is `-ceil(|N| / D)`.
pub(super) fn divide(m: &mut Module, a: &str, b: &str, fmt: &Format, ov: Overflow) -> Fx {
    let w = fmt.width as u32;
    let f = fmt.frac as u32;
    // |p| <= 2^(w - 1 + f); N = 2 p' + |b|: |N| <= 2^(w + f) + 2^(w - 1)
    let nw = w + f + 2;
    let neg = m.uwire("qneg", 1, &format!("{b}[{}]", w - 1));
    let dmag = m.uwire("qd", w, &format!("{neg} ? (~{b} + {w}'d1) : {b}"));
    let pn = m.swire(
        "qp",
        nw,
        &format!("{neg} ? -($signed({a}) <<< {f}) : ($signed({a}) <<< {f})"),
    );
    let n = m.swire(
        "qn",
        nw,
        &format!("({pn} <<< 1) + $signed({{{}'d0, {dmag}}})", nw - w),
    );
    let d2 = m.uwire("qd2", w + 1, &format!("{{{dmag}, 1'b0}}"));
    let zero = m.uwire("qz", 1, &format!("{b} == {w}'d0"));
    let sat = matches!(ov, Overflow::Sat | Overflow::SatSym);
    // wrapping: |q| <= 2^(w - 1 + f) + 1
    let hi = (1i128 << (w - 1 + f)) + 1;
    floor_quotient(m, &n, nw, (&d2, w + 1), &zero, sat.then_some(w), hi)
}

/// `floor(N / D)` of a signed `N` (the wire `n`, `nw` bits) by an unsigned `D` (`d2`, `db`
/// bits, `db < nw`), 0 when `zero` (`D = 0`); the floor of a negative quotient is
/// `-ceil(|N| / D)`. `sat_bits = Some(k)`: the quotient saturates beyond `k` bits (a
/// quotient of `2^k` or more is returned as `+-2^k` whatever its low bits, so only the low
/// `k` quotient bits are divided and the high part of the numerator is compared with `D`
/// once: below it, it is the first partial remainder); `None`: every quotient bit, the
/// quotient's magnitude at most `wrap_hi`.
pub(super) fn floor_quotient(
    m: &mut Module,
    n: &str,
    nw: u32,
    (d2, db): (&str, u32),
    zero: &str,
    sat_bits: Option<u32>,
    wrap_hi: i128,
) -> Fx {
    let dd = m.uwire("qdd", nw, &format!("{{{}'d0, {d2}}}", nw - db));
    let nabs = m.uwire("qna", nw, &format!("{n}[{}] ? -{n} : {n}", nw - 1));
    let num = m.uwire(
        "qnum",
        nw,
        &format!("{n}[{}] ? ({nabs} + {dd} - {nw}'d1) : {nabs}", nw - 1),
    );
    let sgn = format!("{n}[{}]", nw - 1);
    if let Some(k) = sat_bits.filter(|&k| k < nw) {
        let top = m.uwire("qhi", nw - k, &format!("{num}[{}:{k}]", nw - 1));
        let ovf = m.uwire("qovf", 1, &format!("{top} >= {d2}"));
        let r0 = if nw - k >= db {
            m.uwire("qr", db, &format!("{top}[{}:0]", db - 1))
        } else {
            m.uwire("qr", db, &format!("{{{}'d0, {top}}}", db - (nw - k)))
        };
        let qa = restoring(m, &num, k, d2, db, r0);
        let hi = 1i128 << k;
        let qw = signed_bits(-hi, hi);
        let q = m.swire(
            "qs",
            qw,
            &format!(
                "{zero} ? {qw}'sd0 : {ovf} ? ({sgn} ? -{qw}'sd{hi} : {qw}'sd{hi}) : \
                 ({sgn} ? -$signed({{1'b0, {qa}}}) : $signed({{1'b0, {qa}}}))"
            ),
        );
        return Fx {
            name: q,
            lo: -hi,
            hi,
            frac: 0,
            fac: Vec::new(),
        };
    }
    let r0 = m.uwire("qr", db, &format!("{db}'d0"));
    let qa = restoring(m, &num, nw, d2, db, r0);
    let hi = wrap_hi;
    let qw = signed_bits(-hi, hi);
    let q = m.swire(
        "qs",
        qw,
        &format!(
            "{zero} ? {qw}'sd0 : ({sgn} ? -$signed({{1'b0, {qa}}}) : $signed({{1'b0, {qa}}}))"
        ),
    );
    Fx {
        name: q,
        lo: -hi,
        hi,
        frac: 0,
        fac: Vec::new(),
    }
}

/// The unsigned quotient of the low `nb` bits of `num` by `d` (`db` bits), the partial
/// remainder starting at `r0` (`< d`): `floor((r0 2^nb + num[nb-1:0]) / d)` mod `2^nb`, as a
/// restoring array: per
/// quotient bit, from the top, the partial remainder shifted in one numerator bit, compared
/// with `d` and reduced (one `db + 1`-bit subtractor and a mux), so that each step is as
/// wide as the divisor, not as the numerator. `d = 0` gives all ones (the caller masks it).
pub(super) fn restoring(
    m: &mut Module,
    num: &str,
    nb: u32,
    d: &str,
    db: u32,
    r0: String,
) -> String {
    let mut r = r0;
    let mut q = Vec::new();
    for i in (0..nb).rev() {
        let sh = m.uwire("qsh", db + 1, &format!("{{{r}, {num}[{i}]}}"));
        let df = m.uwire("qdf", db + 2, &format!("{{1'b0, {sh}}} - {{2'b0, {d}}}"));
        let ge = m.uwire("qge", 1, &format!("~{df}[{}]", db + 1));
        q.push(ge.clone());
        r = m.uwire(
            "qr",
            db,
            &format!("{ge} ? {df}[{}:0] : {sh}[{}:0]", db - 1, db - 1),
        );
    }
    m.uwire("qa", nb, &format!("{{{}}}", q.join(", ")))
}

/// An `n`-bit vector of the low bits of a lane code `bits` of `w` bits (sign- or
/// zero-extended when `w < n`): the model's `raw & (2^n - 1)`.
fn low_bits(m: &mut Module, bits: &str, w: u32, signed: bool, n: u32) -> String {
    let e = if w >= n {
        format!("{bits}[{}:0]", n - 1)
    } else if signed {
        format!("{{{{{}{{{bits}[{}]}}}}, {bits}}}", n - w, w - 1)
    } else {
        format!("{{{}'d0, {bits}}}", n - w)
    };
    m.uwire("lb", n, &e)
}

/// `div_round(x 2^frac, d)` of an integer wire `x`, as `mapping::div_round`.
fn scaled_div(m: &mut Module, x: &Fx, frac: u32, d: i128) -> Fx {
    let p = scale(m, x, 1i128 << frac);
    div_round(m, &p, d)
}

/// How a dot mapping reads an `n`-bit code `c` (`mapping::map8_bits`, `map16_bits`).
#[derive(Clone, Copy)]
enum Reading {
    /// `(c - 2^(n-1)) / (2^(n-1) - 1)` (the D3D mappings).
    Offset,
    /// `(2c - (2^n - 2)) / (2^n - 1)` (the GL mappings).
    Doubled,
    /// two's complement `c / (2^(n-1) - 1)`.
    Signed,
    /// `c / (2^n - 1)`.
    Unsigned,
}

/// `map8_bits`: an 8-bit channel code (unsigned 8-bit vector).
fn map8(m: &mut Module, mp: DotMapping, x: &str, frac: u32) -> Fx {
    let r = match mp {
        DotMapping::Minus1To1D3d => Reading::Offset,
        DotMapping::Minus1To1Gl => Reading::Doubled,
        DotMapping::Minus1To1 => Reading::Signed,
        _ => Reading::Unsigned,
    };
    map_code(m, r, x, 8, frac)
}

/// `map16_bits`: a 16-bit HI or LO code (unsigned 16-bit vector).
fn map16(m: &mut Module, mp: DotMapping, c: &str, frac: u32) -> Fx {
    let r = match mp {
        DotMapping::HiloHemisphereD3d => Reading::Offset,
        DotMapping::HiloHemisphereGl => Reading::Doubled,
        DotMapping::HiloHemisphere => Reading::Signed,
        _ => Reading::Unsigned,
    };
    map_code(m, r, c, 16, frac)
}

/// The `n`-bit code `x` read as `r` says, at `frac` fraction bits (rounded half up).
fn map_code(m: &mut Module, r: Reading, x: &str, n: u8, frac: u32) -> Fx {
    let (half, top) = (1i128 << (n - 1), (1i128 << n) - 1);
    let name = format!("m{n}");
    match r {
        Reading::Offset => {
            let u = raw_word(m, x, &Format::u(n, 0));
            let c = make(
                m,
                &name,
                u.lo - half,
                u.hi - half,
                0,
                &format!("{} - {}'sd{half}", u.name, n + 1),
            );
            scaled_div(m, &c, frac, half - 1)
        }
        Reading::Doubled => {
            let u = raw_word(m, x, &Format::u(n, 0));
            let c = make(
                m,
                &name,
                2 * u.lo - (top - 1),
                2 * u.hi - (top - 1),
                0,
                &format!("({} <<< 1) - {}'sd{}", u.name, n + 2, top - 1),
            );
            scaled_div(m, &c, frac, top)
        }
        Reading::Signed => {
            let sx = raw_word(m, x, &Format::s(n, 0));
            scaled_div(m, &sx, frac, half - 1)
        }
        Reading::Unsigned => {
            let u = raw_word(m, x, &Format::u(n, 0));
            scaled_div(m, &u, frac, top)
        }
    }
}

/// The floor of the square root of `v` (an integer wire; 0 when `v <= 0`): the digit-by-digit
/// method, one bit of the root per step (a subtractor of the partial remainder).
pub(super) fn isqrt(m: &mut Module, v: &Fx) -> Fx {
    let hi = v.hi.max(0);
    let root_hi = crate::units::texture_shader::mapping::isqrt(hi);
    let mut bits = 128 - (hi as u128).leading_zeros();
    bits += bits & 1;
    let bits = bits.max(2);
    let n = bits / 2;
    let x = m.uwire(
        "sq",
        bits,
        &format!("({0} < 0) ? {bits}'d0 : {0}[{1}:0]", v.name, bits - 1),
    );
    let (rw, tw) = (n + 4, n + 2);
    let mut rem = m.uwire("sqm", rw, &format!("{rw}'d0"));
    let mut root = m.uwire("sqo", n, &format!("{n}'d0"));
    for i in (0..n).rev() {
        let r2 = m.uwire(
            "sqr",
            rw,
            &format!("{{{rem}[{}:0], {x}[{}:{}]}}", rw - 3, 2 * i + 1, 2 * i),
        );
        let tr = m.uwire("sqt", tw, &format!("{{{root}, 2'b01}}"));
        let ge = m.uwire("sqg", 1, &format!("{r2} >= {{1'b0, {tr}}}"));
        rem = m.uwire("sqm", rw, &format!("{ge} ? ({r2} - {{1'b0, {tr}}}) : {r2}"));
        root = if n == 1 {
            m.uwire("sqo", 1, &ge)
        } else {
            m.uwire("sqo", n, &format!("{{{root}[{}:0], {ge}}}", n - 2))
        };
    }
    let name = m.swire("root", n + 1, &format!("$signed({{1'b0, {root}}})"));
    Fx {
        name,
        lo: 0,
        hi: root_hi,
        frac: 0,
        fac: Vec::new(),
    }
}

/// A HILO hemisphere's `z = isqrt(2^(2 frac) - h^2 - l^2)` in a submodule of its own
/// (`sub`: its name, and the list its text is added to): the two squares and the root are
/// most of a hemisphere dot product's logic, and ABC maps a module at a time, so that the
/// stage's other logic does not share its run (the whole in one module did not finish in
/// 25 minutes at `dot_frac` 16).
fn hemisphere(m: &mut Module, h: &Fx, l: &Fx, frac: u32, sub: (&str, &mut Vec<String>)) -> Fx {
    let (name, subs) = sub;
    let mut hm = Module::new(name);
    let port = |hm: &mut Module, p: &str, x: &Fx| {
        let w = x.width();
        hm.input(p, w);
        make(hm, p, x.lo, x.hi, 0, &format!("$signed({p})"))
    };
    let hx = port(&mut hm, "h", h);
    let lx = port(&mut hm, "l", l);
    let h2 = square(&mut hm, &hx);
    let l2 = square(&mut hm, &lx);
    let one = 1i128 << (2 * frac);
    let r = make(
        &mut hm,
        "zr",
        one - h2.hi - l2.hi,
        one - h2.lo - l2.lo,
        0,
        &format!(
            "{} - {} - {}",
            super::super::verilog::lit(one),
            h2.name,
            l2.name
        ),
    );
    let z = isqrt(&mut hm, &r);
    let zw = z.width();
    hm.output_wire("y", zw, &z.name);
    subs.push(hm.text());
    let net = m.net("hz", zw);
    m.stmt(format!(
        "{name} {net}_i (.h({}), .l({}), .y({net}));",
        h.name, l.name
    ));
    Fx {
        name: m.swire("z", zw, &format!("$signed({net})")),
        ..z
    }
}

/// The mapped vector N (three integer wires at `frac` fraction bits) of the previous
/// stage's texel `codes` (4 lane code wires of encoding `enc`, `lanes` of them from the
/// texture), as `vector_bits`; a HILO hemisphere's z in the submodule `hemi` ([`hemisphere`]).
pub(super) fn vector(
    m: &mut Module,
    mp: DotMapping,
    codes: &[String],
    enc: &Encoding,
    lanes: u8,
    frac: u32,
    hemi: (&str, &mut Vec<String>),
) -> [Fx; 3] {
    let w = enc.width();
    let signed = enc.format.signed;
    if mp.is_hilo() {
        let (hi, lo) = if lanes == 2 && w == 16 {
            (codes[0].clone(), codes[1].clone())
        } else {
            let mut c = |k: usize| low_bits(m, &codes[k], w, signed, 8);
            let (c0, c1, c2, c3) = (c(0), c(1), c(2), c(3));
            (
                m.uwire("hi", 16, &format!("{{{c3}, {c0}}}")),
                m.uwire("lo", 16, &format!("{{{c1}, {c2}}}")),
            )
        };
        let h = map16(m, mp, &hi, frac);
        let l = map16(m, mp, &lo, frac);
        let z = if mp == DotMapping::Hilo1 {
            let one = 1i128 << frac;
            make(m, "z", one, one, 0, &super::super::verilog::lit(one))
        } else {
            hemisphere(m, &h, &l, frac, hemi)
        };
        return [h, l, z];
    }
    std::array::from_fn(|k| {
        if w == 8 {
            let x = low_bits(m, &codes[k], w, signed, 8);
            map8(m, mp, &x, frac)
        } else {
            let v = from_code(m, &codes[k], enc);
            let v = match mp {
                DotMapping::Minus1To1D3d | DotMapping::Minus1To1Gl => {
                    let two = scale(m, &v, 2);
                    sub(m, &two, &super::super::fixed::constant(1, 0))
                }
                _ => v,
            };
            if v.frac > frac {
                shift_round(m, &v, v.frac - frac, Quant::Rnd)
            } else {
                let p = scale(m, &v, 1i128 << (frac - v.frac));
                p.at_frac(0)
            }
        }
    })
}

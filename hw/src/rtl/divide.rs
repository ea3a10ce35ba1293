//! Division by a constant as Verilog: `floor(x / d)` and round-half-up `x / d` of an integer
//! wire, for a constant `d > 0` (the register combiners' products read back in units of
//! `255 * 2^f`, the `c / (2^n - 1)` port codes).
//!
//! `d = 2^t o` with `o` odd: the power of two is an arithmetic shift; `o` is a multiplication
//! by the reciprocal `M = ceil(2^s / o)` and a shift by `s` (shifts and adds, `arith::csd`),
//! of the value offset by a multiple of `o` into `[0, U]`. With `e = M o - 2^s`, `u M / 2^s =
//! u / o + u e / (o 2^s)`, so the floor is `floor(u / o)` for every `u <= U` exactly when
//! `U e < 2^s` (the fraction of `u / o` is at most `(o - 1) / o`). The generator takes the
//! smallest such `s` and, among the next eight, the `M` with the fewest signed digits.

use super::fixed::{align_wire, make, plain, scale, Fx};
use super::verilog::lit;
use super::verilog::signed_bits;
use crate::arith::reciprocal;
use crate::format::Quant;

/// `floor(x / d)` for the integer wire `x` (0 fraction bits) and a constant `d > 0`.
pub fn floor_div(m: &mut super::verilog::Module, x: &Fx, d: i128) -> Fx {
    assert!(d > 0 && x.frac == 0);
    let x = plain(m, x);
    let t = d.trailing_zeros();
    let o = d >> t;
    let x = if t == 0 {
        x
    } else {
        make(
            m,
            "dsh",
            x.lo >> t,
            x.hi >> t,
            0,
            &format!("{} >>> {t}", x.name),
        )
    };
    if o == 1 {
        return x;
    }
    let (lo, hi) = (x.lo.div_euclid(o), x.hi.div_euclid(o));
    if lo == hi {
        return make(m, "dq", lo, hi, 0, &lit(lo));
    }
    // offset into [0, U]: u = x + k o
    let k = if x.lo < 0 { (-x.lo + o - 1) / o } else { 0 };
    let u = if k == 0 {
        x
    } else {
        make(
            m,
            "du",
            x.lo + k * o,
            x.hi + k * o,
            0,
            &format!("{} + {}", x.name, lit(k * o)),
        )
    };
    let (mm, s) = reciprocal(o, u.hi);
    let p = scale(m, &u, mm);
    let q = make(
        m,
        "dq",
        u.lo / o,
        u.hi / o,
        0,
        &format!("{} >>> {s}", p.name),
    );
    if k == 0 {
        q
    } else {
        make(m, "dq", lo, hi, 0, &format!("{} - {}", q.name, lit(k)))
    }
}

/// Round-half-up `x / d`: `floor((2 x + d) / (2 d))`.
pub fn div_round(m: &mut super::verilog::Module, x: &Fx, d: i128) -> Fx {
    let x = plain(m, x);
    let n = make(
        m,
        "dn",
        2 * x.lo + d,
        2 * x.hi + d,
        0,
        &format!("({} <<< 1) + {}", x.name, lit(d)),
    );
    floor_div(m, &n, 2 * d)
}

/// `x / d` for the integer wire `x` and a constant `d > 0`, rounded by `q` exactly
/// ([`crate::format::round_rational`]): the floor, and for the modes that need it the
/// remainder `x - d floor(x / d)` against zero and `d / 2`.
pub fn round_div(m: &mut super::verilog::Module, x: &Fx, d: i128, q: Quant) -> Fx {
    match q {
        Quant::Trn => return floor_div(m, x, d),
        Quant::Rnd => return div_round(m, x, d),
        _ => {}
    }
    let x = plain(m, x);
    let x = align_wire(m, &x, 0);
    let fl = floor_div(m, &x, d);
    let fl = align_wire(m, &fl, 0);
    let qd = scale(m, &fl, d);
    let rb = signed_bits(0, 2 * d);
    let r = m.swire("rem", rb, &format!("{} - {}", x.name, qd.name));
    let nz = m.uwire("nz", 1, &format!("{r} != {}", lit(0)));
    let half = m.uwire("hf", 1, &format!("({r} <<< 1) == {}", lit(d)));
    let above = m.uwire("ab", 1, &format!("({r} <<< 1) > {}", lit(d)));
    let neg = m.uwire("neg", 1, &format!("{} < {}", x.name, lit(0)));
    let f = &fl.name;
    let up = match q {
        Quant::TrnZero => format!("{neg} & {nz}"),
        Quant::RndZero => format!("{above} | ({half} & {neg})"),
        Quant::RndInf => format!("{above} | ({half} & ~{neg})"),
        Quant::RndMinInf => above.clone(),
        Quant::RndConv => format!("{above} | ({half} & {f}[0])"),
        Quant::RndConvOdd => format!("{above} | ({half} & ~{f}[0])"),
        Quant::Trn | Quant::Rnd => unreachable!(),
    };
    let up = m.uwire("up", 1, &up);
    make(
        m,
        "rq",
        fl.lo,
        fl.hi + 1,
        0,
        &format!("{f} + $signed({{1'b0, {up}}})"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reciprocal_of_255_is_exact_over_its_whole_range() {
        for u_max in [255i128, 1 << 12, 200_000, 1 << 20] {
            let (mm, s) = reciprocal(255, u_max);
            for u in 0..=u_max {
                assert_eq!((u * mm) >> s, u / 255, "u {u} of {u_max}: M {mm}, s {s}");
            }
        }
    }

    #[test]
    fn reciprocals_of_small_odd_divisors_are_exact() {
        for o in (3..=129i128).step_by(2) {
            let u_max = 1 << 14;
            let (mm, s) = reciprocal(o, u_max);
            for u in 0..=u_max {
                assert_eq!((u * mm) >> s, u / o, "o {o}, u {u}");
            }
        }
    }
}

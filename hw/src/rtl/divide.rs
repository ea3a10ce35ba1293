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

use super::fixed::{make, plain, scale, Fx};
use super::verilog::lit;
use crate::arith::reciprocal;

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

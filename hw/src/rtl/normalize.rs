//! Verilog of the normalisation unit ([`crate::units::Normalize`]): three squarers and the
//! exact sum `s = x^2 + y^2 + z^2`, a leading-one detector that picks the even shift `k` and
//! the table index of the mantissa `m = s 4^k` in `[1/4, 1)`, the reciprocal-square-root ROM
//! (`Rsqrt`'s own entries), three multipliers by the entry, a barrel shifter by `2^k` and the
//! cast into the output encoding; the zero vector gives zero (the table is not read).
//!
//! The detector is a priority chain over the possible lengths of `s`: for each it yields the
//! shift and the index exactly as `Rsqrt::lookup` computes them, so every case of the model
//! has its wire. The product times `2^k` is the product shifted left by `k - k0` at a fixed
//! binary point (`k0` the smallest shift), the exact value of the model's `scale` / `shr`.
//!
//! Clocking: one datapath edge, `start` to the output registers (RTL latency 1, inputs held
//! until `done`); the model's latency of 4 and its pipeline registers stand for a pipelined
//! version of the same logic.

use super::fixed::{from_code, make, mul, plain, sum, to_code, with_fac};
use super::{Plan, RtlUnit, Shell};
use crate::arith::bit_length;
use crate::unit::Unit;
use crate::units::Normalize;

/// Verilog of a built [`Normalize`] (its table is read from the unit).
pub fn rtl(u: &Normalize, top: &str) -> RtlUnit {
    let rs = u.rsqrt();
    let (tb, vb) = (rs.index_bits(), rs.value_bits());
    let mut sh = Shell::new(top, Plan::single());
    let ins = u.inputs().to_vec();
    let enc = ins[0].enc;
    let out = u.outputs()[0].enc;
    let v = sh.port(0, &ins[0], false);
    let outs = sh.output(0, &u.outputs()[0]);
    let comp = sh.comp.clone();
    let c: Vec<_> = v.iter().map(|x| from_code(&mut sh.m, x, &enc)).collect();
    let m = &mut sh.m;
    m.comment("squared length, exact");
    let sq: Vec<_> = c.iter().map(|x| mul(m, x, x)).collect();
    let s = sum(m, &[&sq[0], &sq[1], &sq[2]]);
    let s = plain(m, &s);
    // the possible lengths of s.raw (s >= 0): 1 ..= len_max
    let len_max = bit_length(s.hi.max(0) as u128) as i64;
    let f = s.frac as i64;
    let k_of = |len: i64| {
        let e = len - f;
        -(e.div_euclid(2) + e.rem_euclid(2))
    };
    let (k_lo, k_hi) = (1..=len_max.max(1))
        .map(k_of)
        .fold((i64::MAX, i64::MIN), |(a, b), k| (a.min(k), b.max(k)));
    m.comment("leading-one detector: shift k and table index per length of s");
    let span = (k_hi - k_lo).max(0) as u32;
    let kb = super::verilog::unsigned_bits(span as u128);
    let (mut k_expr, mut idx_expr) = (format!("{kb}'d0"), format!("{tb}'d0"));
    for len in 1..=len_max {
        let k = k_of(len);
        let mbits = f - 2 * k;
        let shifted = if mbits >= tb as i64 {
            format!("({} >>> {})", s.name, mbits - tb as i64)
        } else {
            format!("({} <<< {})", s.name, tb as i64 - mbits)
        };
        let idx = m.uwire("idx", tb, &shifted);
        let bit = format!("{}[{}]", s.name, len - 1);
        k_expr = format!("{bit} ? {kb}'d{} : ({k_expr})", k - k_lo);
        idx_expr = format!("{bit} ? {idx} : ({idx_expr})");
    }
    let kk = m.uwire("kk", kb, &k_expr);
    let idx = m.uwire("idx", tb, &idx_expr);
    let zero = m.uwire("zero", 1, &format!("{} == 0", s.name));
    let _ = m;
    let rom = sh.rom(&format!("{top}_rsqrt"), rs.table(), vb, &idx);
    let m = &mut sh.m;
    let (rlo, rhi) = rs
        .table()
        .iter()
        .fold((i128::MAX, i128::MIN), |(a, b), &x| {
            (a.min(x as i128), b.max(x as i128))
        });
    let r = make(
        m,
        "r",
        rlo,
        rhi,
        vb - 2,
        &format!("$signed({{1'b0, {rom}}})"),
    );
    for (l, x) in c.iter().enumerate() {
        m.comment(&format!("lane {l}: x r 2^k"));
        let p = mul(m, x, &r);
        // p 2^k = (p << (k - base)) / 2^(frac - base), base <= frac so the point stays put
        let base = k_lo.min(p.frac as i64);
        let up = (k_hi - base).max(0) as u32;
        let by = k_lo - base; // the shift at k = k_lo
        let lo = (p.lo << by).min(p.lo << up);
        let hi = (p.hi << by).max(p.hi << up);
        let expr = format!("{} <<< ({kk} + {by})", p.name);
        let q = make(m, "sc", lo, hi, (p.frac as i64 - base) as u32, &expr);
        let q = with_fac(q, p.fac.clone());
        let code = to_code(m, &q, &out);
        let w = out.width();
        m.stmt(format!(
            "always @(posedge clk) if ({comp}) {} <= {zero} ? {w}'d0 : {code};",
            outs[l]
        ));
    }
    sh.finish()
}

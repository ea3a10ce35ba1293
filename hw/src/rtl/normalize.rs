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
//! Clocking: the model's four stages (squares, detector, table, products and casts), every
//! stage register loaded on every edge, the inputs held until `done`: RTL latency 4.

use super::fixed::{from_code, make, mul, plain, register, square, sum, to_code, with_fac, Fx};
use super::verilog::Module;
use super::{Plan, RtlUnit, Shell};
use crate::arith::bit_length;
use crate::unit::Unit;
use crate::units::normalize::Rsqrt;
use crate::units::Normalize;

/// The leading-one detector of [`crate::units::normalize::Rsqrt::lookup`] on the plain,
/// non-negative `s`: the shift `k = kk + k_lo` (`kk` unsigned, `kb` bits, up to `k_hi - k_lo`),
/// the table index (`tb` bits) and the zero detect.
pub(crate) struct Detect {
    pub zero: String,
    pub kk: String,
    pub kb: u32,
    pub k_lo: i64,
    pub k_hi: i64,
    pub idx: String,
}

pub(crate) fn detect(m: &mut Module, s: &Fx, tb: u32) -> Detect {
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
    Detect {
        kk: m.uwire("kk", kb, &k_expr),
        idx: m.uwire("idx", tb, &idx_expr),
        zero: m.uwire("zero", 1, &format!("{} == 0", s.name)),
        kb,
        k_lo,
        k_hi,
    }
}

/// The table entry at `idx` (a ROM `rom` of `rs`'s entries) as a value with `value_bits - 2`
/// fraction bits.
pub(crate) fn table_value(sh: &mut Shell, rs: &Rsqrt, idx: &str, rom: &str) -> Fx {
    let vb = rs.value_bits();
    let y = sh.rom(rom, rs.table(), vb, idx);
    let (rlo, rhi) = rs
        .table()
        .iter()
        .fold((i128::MAX, i128::MIN), |(a, b), &x| {
            (a.min(x as i128), b.max(x as i128))
        });
    make(
        &mut sh.m,
        "r",
        rlo,
        rhi,
        vb - 2,
        &format!("$signed({{1'b0, {y}}})"),
    )
}

/// `p 2^k` for `k = kk + k_lo` in `[k_lo, k_hi]`: `p` shifted left by `kk` at a fixed binary
/// point (the exact value of the model's `shift_pow2`).
pub(crate) fn times_pow2(m: &mut Module, p: &Fx, kk: &str, k_lo: i64, k_hi: i64) -> Fx {
    // p 2^k = (p << (k - base)) / 2^(frac - base), base <= frac so the point stays put
    let base = k_lo.min(p.frac as i64);
    let up = (k_hi - base).max(0) as u32;
    let by = k_lo - base; // the shift at k = k_lo
    let lo = (p.lo << by).min(p.lo << up);
    let hi = (p.hi << by).max(p.hi << up);
    let expr = format!("{} <<< ({kk} + {by})", p.name);
    let q = make(m, "sc", lo, hi, (p.frac as i64 - base) as u32, &expr);
    with_fac(q, p.fac.clone())
}

/// Verilog of a built [`Normalize`] (its table is read from the unit), pipelined as the
/// model's latency of 4: (1) the squares and their sum; (2) the leading-one detector; (3) the
/// table; (4) the products, the shift and the casts into the output registers. The vector is
/// carried through the stages; every stage register is loaded on every edge.
pub fn rtl(u: &Normalize, top: &str) -> RtlUnit {
    let rs = u.rsqrt();
    let tb = rs.index_bits();
    let mut sh = Shell::new(top, Plan::pipeline(4));
    let ins = u.inputs().to_vec();
    let enc = ins[0].enc;
    let out = u.outputs()[0].enc;
    let v = sh.port(0, &ins[0], false);
    let outs = sh.output(0, &u.outputs()[0]);
    let fin = sh.fin.clone();
    let c: Vec<_> = v.iter().map(|x| from_code(&mut sh.m, x, &enc)).collect();
    let m = &mut sh.m;
    m.comment("stage 1: squared length, exact");
    let sq: Vec<_> = c.iter().map(|x| square(m, x)).collect();
    let s = sum(m, &[&sq[0], &sq[1], &sq[2]]);
    let s = plain(m, &s);
    let s1 = stage(m, "s1", &s);
    let c1 = stage_all(m, "v1", &c);
    m.comment("stage 2: the detector");
    let d = detect(m, &s1, tb);
    let d2 = stage_detect(m, "d2", &d, tb);
    let c2 = stage_all(m, "v2", &c1);
    m.comment("stage 3: the table");
    let r = table_value(&mut sh, rs, &d2.idx, &format!("{top}_rsqrt"));
    let m = &mut sh.m;
    let r3 = stage(m, "r3", &r);
    let c3 = stage_all(m, "v3", &c2);
    let kk3 = stage_bits(m, "kk3", d2.kb, &d2.kk);
    let zero3 = stage_bits(m, "zero3", 1, &d2.zero);
    for (l, x) in c3.iter().enumerate() {
        m.comment(&format!("stage 4, lane {l}: x r 2^k"));
        let p = mul(m, x, &r3);
        let q = times_pow2(m, &p, &kk3, d2.k_lo, d2.k_hi);
        let code = to_code(m, &q, &out);
        let w = out.width();
        m.stmt(format!(
            "always @(posedge clk) if ({fin}) {} <= {zero3} ? {w}'d0 : {code};",
            outs[l]
        ));
    }
    sh.finish()
}

/// A stage register, loaded on every edge.
pub(crate) fn stage(m: &mut Module, name: &str, x: &Fx) -> Fx {
    register(m, name, "1'b1", x, x.lo, x.hi)
}

/// Stage registers `{name}_{i}` for every value of `xs`.
pub(crate) fn stage_all(m: &mut Module, name: &str, xs: &[Fx]) -> Vec<Fx> {
    xs.iter()
        .enumerate()
        .map(|(i, x)| stage(m, &format!("{name}_{i}"), x))
        .collect()
}

/// An unsigned stage register of `w` bits loaded with `expr` on every edge.
pub(crate) fn stage_bits(m: &mut Module, name: &str, w: u32, expr: &str) -> String {
    m.reg(name, w);
    m.stmt(format!("always @(posedge clk) {name} <= {expr};"));
    name.to_string()
}

/// The detector's outputs registered.
pub(crate) fn stage_detect(m: &mut Module, name: &str, d: &Detect, tb: u32) -> Detect {
    Detect {
        zero: stage_bits(m, &format!("{name}_zero"), 1, &d.zero),
        kk: stage_bits(m, &format!("{name}_kk"), d.kb, &d.kk),
        idx: stage_bits(m, &format!("{name}_idx"), tb, &d.idx),
        ..*d
    }
}

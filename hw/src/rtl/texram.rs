//! Verilog of Texram's per-pixel frame ([`crate::units::TexramFrame`], Ernst et al. 1998
//! §3.1: `e1 = m x N / |m x N|`, `e2 = N x e1`; outputs `u = -(n x e1)`, `v = e1`, or in the
//! scaled form `v = |N_i| e1`), pipelined as the model's six stages:
//!
//! 1. `c = m x n` (exact);
//! 2. `c . c` (and, scaled, `N_i . N_i`);
//! 3. the leading-one detector and the table index (`normalize::detect`; scaled, a
//!    second detector for `N_i . N_i`);
//! 4. the reciprocal-square-root ROM (the model's entries; scaled, a second copy for the
//!    second read of the clock), `n x c` alongside;
//! 5. the scaling multipliers `(n x c) r`, `c r` (scaled: `c (N_i . N_i) r_n r`);
//! 6. the shift by `2^k` (`2^(k + k_n)`), the negation of `u`, the casts into the output
//!    registers; `c = 0` gives zero axes (the table is not read).
//!
//! Every stage register is loaded on every edge (the inputs are held from `start` to `done`),
//! so the RTL latency is the model's 6.

use super::fixed::{from_code, mul, plain, scale, square, sub, sum, to_code, Fx};
use super::normalize::{
    detect, stage, stage_all, stage_bits, stage_detect, table_value, times_pow2,
};
use super::verilog::Module;
use super::{Plan, RtlUnit, Shell};
use crate::unit::Unit;
use crate::units::{TexramForm, TexramFrame};

/// `a x b` exactly, as `perturb::cross_acc`.
fn cross(m: &mut Module, a: &[Fx], b: &[Fx]) -> Vec<Fx> {
    let t = |m: &mut Module, i: usize, j: usize| {
        let p = mul(m, &a[i], &b[j]);
        let q = mul(m, &a[j], &b[i]);
        sub(m, &p, &q)
    };
    vec![t(m, 1, 2), t(m, 2, 0), t(m, 0, 1)]
}

/// `a . a` exactly, the plain value.
fn length2(m: &mut Module, a: &[Fx]) -> Fx {
    let sq: Vec<Fx> = a.iter().map(|x| square(m, x)).collect();
    let s = sum(m, &sq.iter().collect::<Vec<_>>());
    plain(m, &s)
}

/// The Verilog of a built [`TexramFrame`] (its form, table and encodings are the parameters).
pub fn rtl(u: &TexramFrame, top: &str) -> RtlUnit {
    let rs = u.rsqrt();
    let tb = rs.index_bits();
    let scaled = u.form() == TexramForm::Scaled;
    let mut sh = Shell::new(top, Plan::pipeline(6));
    let ins = u.inputs().to_vec();
    let out = u.outputs()[0].enc;
    let nw = sh.port(0, &ins[0], false);
    let mw = sh.port(1, &ins[1], false);
    let uo = sh.output(0, &u.outputs()[0]);
    let vo = sh.output(1, &u.outputs()[1]);
    let fin = sh.fin.clone();
    let m = &mut sh.m;
    let n: Vec<Fx> = nw.iter().map(|x| from_code(m, x, &ins[0].enc)).collect();
    let mv: Vec<Fx> = mw.iter().map(|x| from_code(m, x, &ins[1].enc)).collect();
    m.comment("stage 1: c = m x n");
    let c = cross(m, &mv, &n);
    let c1 = stage_all(m, "c1", &c);
    let n1 = stage_all(m, "n1", &n);
    m.comment("stage 2: c . c");
    let s = length2(m, &c1);
    let s2 = stage(m, "s2", &s);
    let c2 = stage_all(m, "c2", &c1);
    let n2 = stage_all(m, "n2", &n1);
    let l2 = scaled.then(|| {
        let l = length2(m, &n1);
        stage(m, "l2", &l)
    });
    m.comment("stage 3: leading-one detectors");
    let d = detect(m, &s2, tb);
    let d3 = stage_detect(m, "d3", &d, tb);
    let c3 = stage_all(m, "c3", &c2);
    let n3 = stage_all(m, "n3", &n2);
    let ln3 = l2.as_ref().map(|l| {
        let dl = detect(m, l, tb);
        (stage_detect(m, "dl3", &dl, tb), stage(m, "l3", l))
    });
    m.comment("stage 4: the table, n x c");
    let r = table_value(&mut sh, rs, &d3.idx, &format!("{top}_rsqrt"));
    let rn = ln3
        .as_ref()
        .map(|(dl, _)| table_value(&mut sh, rs, &dl.idx, &format!("{top}_rsqrt")));
    let m = &mut sh.m;
    let r4 = stage(m, "r4", &r);
    let p = cross(m, &n3, &c3);
    let p4 = stage_all(m, "p4", &p);
    let c4 = stage_all(m, "c4", &c3);
    let zero4 = stage_bits(m, "zero4", 1, &d3.zero);
    let kk4 = stage_bits(m, "kk4", d3.kb, &d3.kk);
    let scaled4 = ln3.as_ref().zip(rn.as_ref()).map(|((dl, l3), rn)| {
        (
            stage(m, "rn4", rn),
            stage(m, "l4", l3),
            stage_bits(m, "kn4", dl.kb, &dl.kk),
        )
    });
    m.comment("stage 5: the scaling multipliers");
    let pu: Vec<Fx> = p4.iter().map(|x| mul(m, x, &r4)).collect();
    let pu5 = stage_all(m, "pu5", &pu);
    let g = scaled4.as_ref().map(|(rn4, l4, _)| {
        let nl = mul(m, l4, rn4);
        mul(m, &nl, &r4)
    });
    let pv: Vec<Fx> = c4
        .iter()
        .map(|x| mul(m, x, g.as_ref().unwrap_or(&r4)))
        .collect();
    let pv5 = stage_all(m, "pv5", &pv);
    let zero5 = stage_bits(m, "zero5", 1, &zero4);
    let kk5 = stage_bits(m, "kk5", d3.kb, &kk4);
    let kn5 = scaled4
        .as_ref()
        .map(|(_, _, kn4)| stage_bits(m, "kn5", ln3.as_ref().unwrap().0.kb, kn4));
    m.comment("stage 6: shifts, casts, outputs");
    let w = out.width();
    for (l, o) in uo.iter().enumerate() {
        let q = times_pow2(m, &pu5[l], &kk5, d3.k_lo, d3.k_hi);
        let neg = scale(m, &q, -1);
        let code = to_code(m, &neg, &out);
        m.stmt(format!(
            "always @(posedge clk) if ({fin}) {o} <= {zero5} ? {w}'d0 : {code};"
        ));
    }
    let (kv, lo, hi) = match (&kn5, &ln3) {
        (Some(kn5), Some((dl, _))) => (
            format!("{kk5} + {kn5}"),
            d3.k_lo + dl.k_lo,
            d3.k_hi + dl.k_hi,
        ),
        _ => (kk5.clone(), d3.k_lo, d3.k_hi),
    };
    for (l, o) in vo.iter().enumerate() {
        let q = times_pow2(m, &pv5[l], &kv, lo, hi);
        let code = to_code(m, &q, &out);
        m.stmt(format!(
            "always @(posedge clk) if ({fin}) {o} <= {zero5} ? {w}'d0 : {code};"
        ));
    }
    sh.finish()
}

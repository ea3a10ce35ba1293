//! Verilog of VISA+'s quaternion frame ([`crate::units::QuatFrame`], Ernst et al. 1998 §3.2,
//! last paragraph): the first two columns of the rotation of the interpolated `q`, divided by
//! `|q|^2 = (r 2^k)^2` from Normalize's reciprocal-square-root table, optionally combined with
//! the 2x2 matrix `m`; pipelined as the model's six stages:
//!
//! 1. the four squares (folded, `fixed::square`) and six products of `q`'s lanes;
//! 2. `s = q . q` and the matrix entries;
//! 3. the leading-one detector of `s`, the `m` combination (or the negation) alongside;
//! 4. the table and `r^2`;
//! 5. the column scaling products;
//! 6. the shift by `2^2k`, the casts into the output registers; `q = 0` gives zero axes.
//!
//! Every stage register is loaded on every edge (the inputs are held from `start` to `done`),
//! so the RTL latency is the model's 6.

use super::fixed::{add, from_code, mul, plain, scale, square, sub, sum, to_code, Fx};
use super::normalize::{
    detect, stage, stage_all, stage_bits, stage_detect, table_value, times_pow2,
};
use super::{Plan, RtlUnit, Shell};
use crate::unit::Unit;
use crate::units::QuatFrame;

/// The Verilog of a built [`QuatFrame`] (its table, `m` input and encodings are the
/// parameters).
pub fn rtl(u: &QuatFrame, top: &str) -> RtlUnit {
    let rs = u.rsqrt();
    let tb = rs.index_bits();
    let mut sh = Shell::new(top, Plan::pipeline(6));
    let ins = u.inputs().to_vec();
    let out = u.outputs()[0].enc;
    let qw = sh.port(0, &ins[0], false);
    let mw = ins.get(1).map(|p| sh.port(1, p, false));
    let uo = sh.output(0, &u.outputs()[0]);
    let vo = sh.output(1, &u.outputs()[1]);
    let fin = sh.fin.clone();
    let m = &mut sh.m;
    let q: Vec<Fx> = qw.iter().map(|x| from_code(m, x, &ins[0].enc)).collect();
    let (x, y, z, w) = (&q[0], &q[1], &q[2], &q[3]);
    m.comment("stage 1: squares and products of q");
    let sq: Vec<Fx> = [x, y, z, w].iter().map(|v| square(m, v)).collect();
    let pr: Vec<Fx> = [(x, y), (w, z), (x, z), (w, y), (y, z), (w, x)]
        .iter()
        .map(|(a, b)| mul(m, a, b))
        .collect();
    let sq1 = stage_all(m, "sq1", &sq);
    let p1 = stage_all(m, "p1", &pr);
    m.comment("stage 2: |q|^2 and the matrix entries");
    let (xx, yy, zz, ww) = (&sq1[0], &sq1[1], &sq1[2], &sq1[3]);
    let (xy, wz, xz, wy, yz, wx) = (&p1[0], &p1[1], &p1[2], &p1[3], &p1[4], &p1[5]);
    let s = sum(m, &[xx, yy, zz, ww]);
    let s = plain(m, &s);
    let dwz = sub(m, ww, zz);
    let dxy = sub(m, xx, yy);
    let two = |m: &mut super::verilog::Module, a: Fx| scale(m, &a, 2);
    let e = [
        add(m, &dwz, &dxy),
        {
            let t = add(m, xy, wz);
            two(m, t)
        },
        {
            let t = sub(m, xz, wy);
            two(m, t)
        },
        {
            let t = sub(m, xy, wz);
            two(m, t)
        },
        sub(m, &dwz, &dxy),
        {
            let t = add(m, yz, wx);
            two(m, t)
        },
    ];
    let s2 = stage(m, "s2", &s);
    let e2 = stage_all(m, "e2", &e);
    m.comment("stage 3: the detector; the m combination");
    let d = detect(m, &s2, tb);
    let d3 = stage_detect(m, "d3", &d, tb);
    let (a0, a1) = (&e2[0..3], &e2[3..6]);
    let (pu, pv): (Vec<Fx>, Vec<Fx>) = match &mw {
        Some(mw) => {
            let mv: Vec<Fx> = mw.iter().map(|c| from_code(m, c, &ins[1].enc)).collect();
            let comb = |m: &mut super::verilog::Module, ka: &Fx, kb: &Fx| -> Vec<Fx> {
                (0..3)
                    .map(|j| {
                        let p = mul(m, ka, &a0[j]);
                        let r = mul(m, kb, &a1[j]);
                        add(m, &p, &r)
                    })
                    .collect()
            };
            (comb(m, &mv[0], &mv[2]), comb(m, &mv[1], &mv[3]))
        }
        None => (
            a0.iter().map(|a| scale(m, a, -1)).collect(),
            a1.iter().map(|a| scale(m, a, -1)).collect(),
        ),
    };
    let pu3 = stage_all(m, "pu3", &pu);
    let pv3 = stage_all(m, "pv3", &pv);
    m.comment("stage 4: the table and r^2");
    let r = table_value(&mut sh, rs, &d3.idx, &format!("{top}_rsqrt"));
    let m = &mut sh.m;
    let rr = square(m, &r);
    let rr4 = stage(m, "rr4", &rr);
    let pu4 = stage_all(m, "pu4", &pu3);
    let pv4 = stage_all(m, "pv4", &pv3);
    let zero4 = stage_bits(m, "zero4", 1, &d3.zero);
    let kk4 = stage_bits(m, "kk4", d3.kb, &d3.kk);
    m.comment("stage 5: the column scaling");
    let su: Vec<Fx> = pu4.iter().map(|a| mul(m, a, &rr4)).collect();
    let sv: Vec<Fx> = pv4.iter().map(|a| mul(m, a, &rr4)).collect();
    let su5 = stage_all(m, "su5", &su);
    let sv5 = stage_all(m, "sv5", &sv);
    let zero5 = stage_bits(m, "zero5", 1, &zero4);
    let kk5 = stage_bits(m, "kk5", d3.kb, &kk4);
    m.comment("stage 6: the shift by 2^2k, casts, outputs");
    let k2 = format!("{{{kk5}, 1'b0}}");
    let wo = out.width();
    for (outs, vals) in [(&uo, &su5), (&vo, &sv5)] {
        for (o, a) in outs.iter().zip(vals.iter()) {
            let q = times_pow2(m, a, &k2, 2 * d3.k_lo, 2 * d3.k_hi);
            let code = to_code(m, &q, &out);
            m.stmt(format!(
                "always @(posedge clk) if ({fin}) {o} <= {zero5} ? {wo}'d0 : {code};"
            ));
        }
    }
    sh.finish()
}

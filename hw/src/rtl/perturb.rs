//! Verilog of the normal-perturbation unit ([`crate::units::Perturb`], Ernst et al. 1998
//! §3.2 `N' = N + A V`, §3.5, §3.1): per lane `n_j = base_j + d0 u_j + d1 v_j`, six exact
//! products, two exact sums per lane and the cast into the output encoding.
//!
//! Clocking as the model's latency of 2 and as its gate budget: edge 1 (`start`) loads the six
//! products and the base lanes into the product register, edge 2 adds and casts them into the
//! output registers. The inputs are read at `start` only.

use super::fixed::{align_wire, from_code, mul, register, sum, to_code, Fx};
use super::{Plan, RtlUnit, Shell};
use crate::format::Codec;
use crate::unit::Unit;
use crate::units::Perturb;

/// The Verilog of a built [`Perturb`] (its port encodings are the generator's parameters).
pub fn rtl(u: &Perturb, top: &str) -> RtlUnit {
    let plan = Plan {
        capture: false,
        interval: 1,
        finish: true,
    };
    let mut sh = Shell::new(top, plan);
    let ins = u.inputs().to_vec();
    let ports: Vec<Vec<String>> = (0..4).map(|i| sh.port(i, &ins[i], false)).collect();
    let out_enc = u.outputs()[0].enc;
    let outs = sh.output(0, &u.outputs()[0]);
    let (comp, fin) = (sh.comp.clone(), sh.fin.clone());
    let m = &mut sh.m;
    let read = |m: &mut super::verilog::Module, p: usize, l: usize| {
        from_code(m, &ports[p][l], &ins[p].enc)
    };
    let d: Vec<Fx> = (0..2).map(|l| read(m, 3, l)).collect();
    for (j, o) in outs.iter().enumerate() {
        m.comment(&format!("lane {j}: product register"));
        let b = read(m, 0, j);
        let uj = read(m, 1, j);
        let vj = read(m, 2, j);
        let pu = mul(m, &d[0], &uj);
        let pv = mul(m, &d[1], &vj);
        let rb = register(m, &format!("p_base_{j}"), &comp, &b, b.lo, b.hi);
        let ru = register(m, &format!("p_du_{j}"), &comp, &pu, pu.lo, pu.hi);
        let rv = register(m, &format!("p_dv_{j}"), &comp, &pv, pv.lo, pv.hi);
        m.comment(&format!("lane {j}: sum and cast"));
        let mut s = sum(m, &[&rb, &ru, &rv]);
        // the model's cast widens a UnitSigned output's fraction first (value unchanged)
        let n = out_enc.width();
        if out_enc.codec == Codec::UnitSigned && s.frac + 1 < n {
            s = align_wire(m, &s, n - 1);
        }
        let code = to_code(m, &s, &out_enc);
        m.stmt(format!("always @(posedge clk) if ({fin}) {o} <= {code};"));
    }
    sh.finish()
}

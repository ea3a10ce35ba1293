//! Verilog of the light combiner ([`crate::units::Shade`]): `parallel` multiply-add datapaths
//! over the lights, the per-light coefficients `kd (*) Lc_i`, `ks (*) Lc_i` and the ambient
//! `ka` in host-loaded registers (quantized as the model quantizes them) with a select mux per
//! datapath, an exact accumulator per channel, and the final sum with `C_src` and the ambient
//! term cast once into the output encoding.
//!
//! Clocking: edges 1 to `interval` accumulate (the `d`, `s`, `base` and `src` inputs held
//! until `done`), edge `interval + 1` writes the output registers.

use super::fixed::{from_code, gate, mul, register, sum, sum_in_range, to_code, Fx};
use super::{Plan, RtlUnit, Shell};
use crate::format::Encoding;
use crate::unit::Unit;
use crate::units::{Shade, ShadeInputs, ShadeParams};

/// The parameters of [`Shade::new`]; builds both the unit and its Verilog.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadeRtl {
    pub intensity: Encoding,
    pub has: ShadeInputs,
    pub params: ShadeParams,
    pub coef: Encoding,
    pub parallel: u32,
    pub out: Encoding,
}

impl ShadeRtl {
    pub fn unit(&self) -> Shade {
        Shade::new(
            self.intensity,
            self.has,
            self.params.clone(),
            self.coef,
            self.parallel,
            self.out,
        )
    }

    pub fn rtl(&self, top: &str) -> RtlUnit {
        let u = self.unit();
        let pr = &self.params;
        let k = pr.light_colors.len();
        let p = (self.parallel as usize).clamp(1, k.max(1));
        let iv = u.interval();
        let plan = Plan {
            capture: false,
            interval: iv,
            finish: true,
        };
        let mut sh = Shell::new(top, plan);
        let ins = u.inputs().to_vec();
        let pidx = |n: &str| crate::unit::port_index(&ins, n);
        let d: Vec<String> = (0..k)
            .map(|i| sh.port(i, &ins[i], false)[0].clone())
            .collect();
        let s: Vec<String> = match self.has.specular {
            Some(_) => (0..k)
                .map(|i| sh.port(k + i, &ins[k + i], false)[0].clone())
                .collect(),
            None => Vec::new(),
        };
        let base = pidx("base").map(|i| sh.port(i, &ins[i], false));
        let src = pidx("src").map(|i| sh.port(i, &ins[i], false));
        let out = sh.output(0, &u.outputs()[0]);
        // host registers, quantized as Shade::new quantizes them
        let coef = self.coef;
        let code = |x: f64| coef.encode(x);
        let ka: Vec<String> = (0..3)
            .map(|c| sh.config_reg(&format!("ka[{c}]"), &coef, code(pr.ambient[c])))
            .collect();
        let kd: Vec<Vec<String>> = (0..k)
            .map(|i| {
                (0..3)
                    .map(|c| {
                        let v = code(pr.diffuse[c] * pr.light_colors[i][c]);
                        sh.config_reg(&format!("kd*Lc{i}[{c}]"), &coef, v)
                    })
                    .collect()
            })
            .collect();
        let ks: Vec<Vec<String>> = match self.has.specular {
            Some(_) => (0..k)
                .map(|i| {
                    (0..3)
                        .map(|c| {
                            let v = code(pr.specular[c] * pr.light_colors[i][c]);
                            sh.config_reg(&format!("ks*Lc{i}[{c}]"), &coef, v)
                        })
                        .collect()
                })
                .collect(),
            None => Vec::new(),
        };
        let (t, tb, comp, fin) = (sh.t.clone(), sh.t_bits, sh.comp.clone(), sh.fin.clone());
        let m = &mut sh.m;
        let ie = self.intensity;
        let wc = coef.width();
        let bv: Vec<Option<Fx>> = (0..3)
            .map(|c| {
                let e = self.has.base?;
                Some(from_code(m, &base.as_ref()?[c], &e))
            })
            .collect();
        // per channel, the terms each datapath adds this clock
        let mut cycle: Vec<Vec<Fx>> = vec![Vec::new(); 3];
        for j in 0..p {
            m.comment(&format!("datapath {j}"));
            let slots: Vec<usize> = (0..iv as usize).map(|c| c * p + j).collect();
            let items: Vec<usize> = slots.iter().map(|&i| i.min(k - 1)).collect();
            let pick = |m: &mut super::verilog::Module, v: &[String], w: u32| {
                let names: Vec<String> = items.iter().map(|&i| v[i].clone()).collect();
                m.select_bits(&t, &names, w)
            };
            let dj = pick(m, &d, ie.width());
            let dv = from_code(m, &dj, &ie);
            let sv = match self.has.specular {
                Some(se) => {
                    let sj = pick(m, &s, se.width());
                    Some(from_code(m, &sj, &se))
                }
                None => None,
            };
            // a slot past the last light adds nothing
            let valid = if slots.iter().any(|&i| i >= k) {
                let last = (k - 1 - j) / p;
                Some(m.uwire("valid", 1, &format!("{t} <= {tb}'d{last}")))
            } else {
                None
            };
            for c in 0..3 {
                let kdc: Vec<String> = kd.iter().map(|v| v[c].clone()).collect();
                let kdj = pick(m, &kdc, wc);
                let kdv = from_code(m, &kdj, &coef);
                let bd = match &bv[c] {
                    Some(b) => mul(m, b, &dv),
                    None => dv.clone(),
                };
                let mut term = mul(m, &kdv, &bd);
                if let Some(sv) = &sv {
                    let ksc: Vec<String> = ks.iter().map(|v| v[c].clone()).collect();
                    let ksj = pick(m, &ksc, wc);
                    let ksv = from_code(m, &ksj, &coef);
                    let st = mul(m, &ksv, sv);
                    term = sum(m, &[&term, &st]);
                }
                if let Some(v) = &valid {
                    term = gate(m, v, &term);
                }
                cycle[c].push(term);
            }
        }
        for (c, terms) in cycle.iter().enumerate() {
            m.comment(&format!("channel {c}: accumulator, ambient, source, cast"));
            let refs: Vec<&Fx> = terms.iter().collect();
            let per = sum(m, &refs);
            let n = iv as i128;
            let (lo, hi) = (per.lo.min(0) * n, per.hi.max(0) * n);
            let acc_name = format!("acc_{c}");
            let acc = Fx {
                name: acc_name.clone(),
                lo,
                hi,
                frac: per.frac,
                fac: per.fac.clone(),
            };
            let prev = m.swire(
                "accin",
                acc.width(),
                &format!("({t} == {tb}'d0) ? 0 : {acc_name}"),
            );
            let prev = Fx {
                name: prev,
                ..acc.clone()
            };
            let next = sum_in_range(m, &[&prev, &per], lo, hi);
            let acc = register(m, &acc_name, &comp, &next, lo, hi);
            let kav = from_code(m, &ka[c], &coef);
            let amb = match &bv[c] {
                Some(b) => mul(m, &kav, b),
                None => kav,
            };
            let mut parts = vec![acc, amb];
            if let (Some(src), Some(e)) = (&src, self.has.src) {
                parts.push(from_code(m, &src[c], &e));
            }
            let refs: Vec<&Fx> = parts.iter().collect();
            let v = sum(m, &refs);
            let code = to_code(m, &v, &self.out);
            m.stmt(format!(
                "always @(posedge clk) if ({fin}) {} <= {code};",
                out[c]
            ));
        }
        sh.finish()
    }
}

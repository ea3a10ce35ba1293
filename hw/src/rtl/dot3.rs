//! Verilog of the dot-product unit ([`crate::units::Dot3`]): `parallel` datapaths of three
//! multipliers and a 3-input adder, the clamp and the cast into the output encoding; the
//! `k` products over `ceil(k / parallel)` clocks with an operand mux per datapath.
//!
//! Clocking as the model's latency (`interval + 1`): edge 1 loads the `a` input register,
//! edges 2 to `interval + 1` evaluate `parallel` dot products each into the result registers.
//! The `b` inputs are read through the operand mux and must be held until `done`.

use super::fixed::{clamp_code, from_code, mul, sum, to_code};
use super::{Plan, RtlUnit, Shell};
use crate::format::Encoding;
use crate::unit::Unit;
use crate::units::{Clamp, Dot3};

/// The parameters of [`Dot3::new`]; builds both the unit and its Verilog.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dot3Rtl {
    pub a: Encoding,
    pub b: Encoding,
    pub k: u32,
    pub parallel: u32,
    pub clamp: Clamp,
    pub out: Encoding,
}

impl Dot3Rtl {
    pub fn unit(&self) -> Dot3 {
        Dot3::new(self.a, self.b, self.k, self.parallel, self.clamp, self.out)
    }

    pub fn rtl(&self, top: &str) -> RtlUnit {
        let u = self.unit();
        let k = self.k.max(1) as usize;
        let p = self.parallel.clamp(1, k as u32) as usize;
        let iv = u.interval();
        let plan = Plan {
            capture: true,
            interval: iv,
            finish: false,
        };
        let mut sh = Shell::new(top, plan);
        let ins = u.inputs().to_vec();
        let a = sh.port(0, &ins[0], true);
        let b: Vec<Vec<String>> = (0..k).map(|i| sh.port(1 + i, &ins[1 + i], false)).collect();
        let outs: Vec<Vec<String>> = u
            .outputs()
            .iter()
            .enumerate()
            .map(|(i, o)| sh.output(i, o))
            .collect();
        let (t, tb, comp) = (sh.t.clone(), sh.t_bits, sh.comp.clone());
        let m = &mut sh.m;
        let ea = self.a;
        let wb = self.b.width();
        let av: Vec<_> = a.iter().map(|x| from_code(m, x, &ea)).collect();
        for j in 0..p {
            m.comment(&format!("datapath {j}"));
            // the products this datapath evaluates, one per clock
            let items: Vec<usize> = (0..iv as usize)
                .map(|c| c * p + j)
                .filter(|&i| i < k)
                .collect();
            let prods: Vec<_> = (0..3)
                .map(|l| {
                    let names: Vec<String> = items.iter().map(|&i| b[i][l].clone()).collect();
                    let bits = m.select_bits(&t, &names, wb);
                    let bv = from_code(m, &bits, &self.b);
                    mul(m, &av[l], &bv)
                })
                .collect();
            let s = sum(m, &[&prods[0], &prods[1], &prods[2]]);
            let one = Some((1i128 << s.frac, s.frac));
            let zero = Some((0, 0));
            let code = match self.clamp {
                Clamp::Unit => clamp_code(m, &s, zero, one, &self.out),
                Clamp::Positive => clamp_code(m, &s, zero, None, &self.out),
                Clamp::None => to_code(m, &s, &self.out),
            };
            for (c, &i) in items.iter().enumerate() {
                m.stmt(format!(
                    "always @(posedge clk) if ({comp} && {t} == {tb}'d{c}) {} <= {code};",
                    outs[i][0]
                ));
            }
        }
        sh.finish()
    }
}

//! Verilog of the texture stage ([`crate::units::Modulate`], Ernst et al. 1998 §5.1: the
//! texture applied after the blend, `c * t` per channel): three multipliers, each followed by
//! the clamp to `[0, 1]` and the cast into the output encoding, fused ([`clamp_code`]).
//!
//! Clocking: one datapath edge, `start` to the output registers (RTL latency 1). The inputs
//! are read directly and must be held until `done`. The model's latency of 2 stands for a
//! multiplier with a pipeline register; the gate model prices no input registers, and none
//! are generated.

use super::fixed::{clamp_code, from_code, mul};
use super::{Plan, RtlUnit, Shell};
use crate::format::Encoding;
use crate::unit::Unit;
use crate::units::Modulate;

/// The parameters of [`Modulate::new`]; builds both the unit and its Verilog.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModulateRtl {
    pub c: Encoding,
    pub t: Encoding,
    pub out: Encoding,
}

impl ModulateRtl {
    pub fn unit(&self) -> Modulate {
        Modulate::new(self.c, self.t, self.out)
    }

    pub fn rtl(&self, top: &str) -> RtlUnit {
        let u = self.unit();
        let mut sh = Shell::new(top, Plan::single());
        let ins = u.inputs().to_vec();
        let c = sh.port(0, &ins[0], false);
        let t = sh.port(1, &ins[1], false);
        let outs = sh.output(0, &u.outputs()[0]);
        let comp = sh.comp.clone();
        let m = &mut sh.m;
        for l in 0..3 {
            m.comment(&format!("channel {l}"));
            let cv = from_code(m, &c[l], &self.c);
            let tv = from_code(m, &t[l], &self.t);
            let p = mul(m, &cv, &tv);
            let code = clamp_code(m, &p, Some((0, 0)), Some((1, 0)), &self.out);
            m.stmt(format!(
                "always @(posedge clk) if ({comp}) {} <= {code};",
                outs[l]
            ));
        }
        sh.finish()
    }
}

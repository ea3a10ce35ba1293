//! Verilog of the framebuffer blend ([`crate::units::FbBlend`], Tarini et al. 1999 §7): per
//! channel the passes of equation (1) or (2) as the model fuses them, each framebuffer word a
//! clamp to `[0, 1]` and a cast into the framebuffer encoding ([`clamp_code`]), read back
//! with the encoding's replication:
//!
//! * pass 1: `r_o` = the base colour as a framebuffer word;
//! * equation (1): `d` = the word of `r_o alpha`, then `(1 - d) r_i + d`;
//! * equation (2): `(1 - r_o) r_i + r_o alpha`.
//!
//! Two multipliers a channel either way, as the gate model prices them. Clocking: one edge
//! from `start` into the output registers (RTL latency 1); the model's latency of 2 stands
//! for a pipelined multiplier, which neither the RTL nor the gate model has (as Modulate).

use super::fixed::{add, clamp_code, constant, from_code, mul, sub};
use super::verilog::Module;
use super::{Plan, RtlUnit, Shell};
use crate::format::Encoding;
use crate::unit::Unit;
use crate::units::{BlendEquation, FbBlend};

/// A value as a framebuffer word and read back: the word's bits and the value it holds.
fn word(m: &mut Module, x: &super::fixed::Fx, fb: &Encoding) -> super::fixed::Fx {
    let code = clamp_code(m, x, Some((0, 0)), Some((1, 0)), fb);
    from_code(m, &code, fb)
}

/// The Verilog of a built [`FbBlend`].
pub fn rtl(u: &FbBlend, top: &str) -> RtlUnit {
    let mut sh = Shell::new(top, Plan::single());
    let ins = u.inputs().to_vec();
    let (be, ee) = (ins[0].enc, ins[1].enc);
    let fb = u.outputs()[0].enc;
    let base = sh.port(0, &ins[0], false);
    let entry = sh.port(1, &ins[1], false);
    let outs = sh.output(0, &u.outputs()[0]);
    let comp = sh.comp.clone();
    let m = &mut sh.m;
    let one = constant(1, 0);
    let alpha = from_code(m, &entry[3], &ee);
    for (c, o) in outs.iter().enumerate() {
        m.comment(&format!("channel {c}"));
        let b = from_code(m, &base[c], &be);
        let ro = word(m, &b, &fb);
        let ri = from_code(m, &entry[c], &ee);
        let v = match u.equation() {
            BlendEquation::Exact => {
                let p = mul(m, &ro, &alpha);
                let d = word(m, &p, &fb);
                let inv = sub(m, &one, &d);
                let q = mul(m, &inv, &ri);
                add(m, &q, &d)
            }
            BlendEquation::Approx => {
                let inv = sub(m, &one, &ro);
                let q = mul(m, &inv, &ri);
                let p = mul(m, &ro, &alpha);
                add(m, &q, &p)
            }
        };
        let code = clamp_code(m, &v, Some((0, 0)), Some((1, 0)), &fb);
        m.stmt(format!("always @(posedge clk) if ({comp}) {o} <= {code};"));
    }
    sh.finish()
}

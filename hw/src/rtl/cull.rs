//! Verilog of the fragment cull unit ([`crate::units::CullFragment`], NV_texture_shader
//! CULL_FRAGMENT, "Conditional fragment culling"): per lane the sign bit of the raw word
//! against the lane's host-loaded mode bit (1 = `Less`), a failure where they differ, and
//! `live` the NOR of the failures. An unsigned lane is never negative (its sign is 0).
//!
//! Clocking: one edge from `start` into the `live` register, as the model's latency of 1.

use super::{Plan, RtlUnit, Shell};
use crate::format::{Encoding, Format};
use crate::unit::Unit;
use crate::units::{CullFragment, CullTest};

/// The Verilog of a built [`CullFragment`].
pub fn rtl(u: &CullFragment, top: &str) -> RtlUnit {
    let mut sh = Shell::new(top, Plan::single());
    let v = u.inputs()[0].clone();
    let lanes = sh.port(0, &v, false);
    let live = sh.output(0, &u.outputs()[0])[0].clone();
    let bit = Encoding::fixed(Format::u(1, 0));
    let modes: Vec<String> = u
        .tests()
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let less = *t == CullTest::Less;
            sh.config_reg(
                &format!("lane {i} test (1 = Less, 0 = Gequal)"),
                &bit,
                i64::from(less),
            )
        })
        .collect();
    let comp = sh.comp.clone();
    let m = &mut sh.m;
    let w = v.enc.width();
    let fails: Vec<String> = lanes
        .iter()
        .zip(&modes)
        .map(|(l, md)| {
            let sign = if v.enc.format.signed {
                format!("{l}[{}]", w - 1)
            } else {
                "1'b0".to_string()
            };
            m.uwire("fail", 1, &format!("{sign} ^ {md}"))
        })
        .collect();
    m.stmt(format!(
        "always @(posedge clk) if ({comp}) {live} <= ~({});",
        fails.join(" | ")
    ));
    sh.finish()
}

//! Verilog of the quantized normal maps unit ([`crate::units::QuantizedFetch`], Tarini et al.
//! §3-5): the per-frame builder ([`super::palette_builder`]) writing the colour table, and per
//! fragment the nearest read of the index texture ([`super::fetch`]) and the colour-table read.
//!
//! * Per frame: the `frame` pulse runs the builder; `frame_done` rises when the last entry is
//!   written ([`super::RtlUnit::frame`] clocks).
//! * Per fragment: the index word is the fetch's nearest texel (the index texture a memory,
//!   outside the budget), registered (the LUT's index register), the colour table read (one
//!   clock), and the entry registered into `c` (RGBA); `color` is a copy of its RGB lanes
//!   (wires, as the model's second port). The index texture holds no index beyond the table
//!   (the unit checks it when it is built), so the LUT's range compare is not built.
//!
//! Clocking: the fetch's code is valid while `step = L` (its memory latency); the index
//! register is written on edge `L + 1`, the table word arrives after edge `L + 2`, the outputs
//! on edge `L + 3`: the model's latency (fetch `L + 1`, LUT 2). Index mipmaps (§5.2) have no
//! generator yet.

use super::palette_builder::builder;
use super::verilog::unsigned_bits;
use super::{fetch, Plan, RtlUnit, Shell};
use crate::unit::Unit;
use crate::units::QuantizedFetch;

/// The Verilog of a built [`QuantizedFetch`] (its index texture, builder and LUT are the
/// parameters).
pub fn rtl(u: &QuantizedFetch, top: &str) -> Result<RtlUnit, String> {
    if u.levels() > 1 {
        return Err("index mipmaps: the generator reads level 0 only (no generator yet)".into());
    }
    let f = u.index_fetch();
    let lat = fetch::plan(f).interval;
    let plan = Plan {
        capture: false,
        interval: lat + 2,
        finish: true,
    };
    let mut sh = Shell::new(top, plan);
    let uv = sh.port(0, &u.inputs()[0].clone(), false);
    let c = sh.output(0, &u.outputs()[0].clone());
    sh.output_wires(1, &u.outputs()[1].clone(), &c[..3]);
    let code = fetch::datapath(&mut sh, f, &uv, "indices")?.remove(0);
    let bits = f.outputs()[0].enc.width();
    let writes = builder(&mut sh, u.builder(), bits)?;
    let sb = unsigned_bits(plan.latency() as u128);
    let m = &mut sh.m;
    m.comment("the colour table's index register");
    let idx = m.reg("idx", bits);
    m.stmt(format!(
        "always @(posedge clk) if (step == {sb}'d{lat}) {idx} <= {code};"
    ));
    let n = u.builder().entries();
    let entry = u.outputs()[0].enc.width();
    let data = sh
        .ram(
            "colours",
            n,
            4 * entry,
            &[(idx.clone(), bits)],
            1,
            (&writes.we, &writes.addr, &writes.data),
        )
        .remove(0);
    let fin = sh.fin.clone();
    for (l, o) in c.iter().enumerate() {
        let word = format!(
            "{data}[{}:{}]",
            (l as u32 + 1) * entry - 1,
            l as u32 * entry
        );
        sh.m.stmt(format!("always @(posedge clk) if ({fin}) {o} <= {word};"));
    }
    let r = sh.finish();
    debug_assert_eq!(r.frame, Some(writes.cycles));
    Ok(r)
}

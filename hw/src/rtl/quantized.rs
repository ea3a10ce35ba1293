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
//! on edge `L + 3`: the model's latency (fetch `L + 1`, LUT 2).
//! * Index mipmaps (§5.2): with a `lod` port the level `clamp(floor(lod + 1/2), 0, levels -
//!   1)` is read nearest (GL's `NEAREST_MIPMAP_NEAREST`, the model's
//!   [`crate::texture::Texture::nearest_level`]): per level the sampler's nearest address in
//!   the level, the level's offset and base address selected and added, the levels one after
//!   the other in the index memory (`mip_fetch`).

use super::fixed::{clamp, from_code, overflow, raw_word, shift_round, to_code};
use super::palette_builder::builder;
use super::verilog::unsigned_bits;
use super::{fetch, Plan, RtlUnit, Shell};
use crate::format::{Codec, Encoding, Format, Overflow, Quant};
use crate::unit::Unit;
use crate::units::QuantizedFetch;

/// The Verilog of a built [`QuantizedFetch`] (its index texture, builder and LUT are the
/// parameters).
pub fn rtl(u: &QuantizedFetch, top: &str) -> Result<RtlUnit, String> {
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
    let code = if u.levels() > 1 {
        let lod = sh.port(1, &u.inputs()[1].clone(), false);
        mip_fetch(&mut sh, u, &uv, &lod[0])?
    } else {
        fetch::datapath(&mut sh, f, &uv, "indices")?.remove(0)
    };
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

/// The nearest read of the index texture's mip level `clamp(floor(lod + 1/2), 0, levels -
/// 1)` ([`crate::texture::Texture::nearest_level`], GL's `NEAREST_MIPMAP_NEAREST`; Tarini
/// §5.2): per level the texel address of its `2^log_w x 2^log_h` texels (the sampler's nearest
/// addressing, [`fetch::axis`]), the level's offset and base address selected by the level
/// and added; the levels stored one after the other in one memory. Returns the index code,
/// valid while `step` is the memory's latency (as [`fetch::datapath`]).
fn mip_fetch(
    sh: &mut Shell,
    u: &QuantizedFetch,
    uv: &[String],
    lod: &str,
) -> Result<String, String> {
    let f = u.index_fetch();
    let tex = f.texture();
    let levels = tex.levels();
    let lod_enc = u.inputs()[1].enc;
    if lod_enc.codec != Codec::Fixed {
        return Err(format!(
            "index mipmaps: a LOD of codec {:?}: the generator reads a fixed-point LOD",
            lod_enc.codec
        ));
    }
    let uv_enc = u.inputs()[0].enc;
    let frac = uv_enc.format.frac as u32;
    let [am_s, am_t] = f.sampler().address();
    let texel: Encoding = *tex.texel();
    let wt = texel.width();
    let out_enc = f.outputs()[0].enc;
    // the levels one after the other: base addresses and the words
    let mut bases = Vec::new();
    let mut words: Vec<u128> = Vec::new();
    for l in 0..levels {
        let level = tex.level_at(l);
        bases.push(words.len() as u128);
        let n = (level.width() * level.height()) as usize;
        words.extend((0..n).map(|k| texel.format.bits(level.code(k)[0]) as u128));
    }
    let abits = unsigned_bits(words.len().saturating_sub(1) as u128).max(1);
    let lb = unsigned_bits(levels as u128 - 1);
    let m = &mut sh.m;
    m.comment("the mip level: floor(lod + 1/2), clamped to the levels");
    let lf = lod_enc.format.frac as u32;
    let lx = raw_word(m, lod, &lod_enc.format).at_frac(lf);
    let r = shift_round(m, &lx, lf, Quant::Rnd);
    let c = clamp(m, &r, Some((0, 0)), Some((levels as i128 - 1, 0)));
    let level = overflow(m, &c, &Format::u(lb as u8, 0), Overflow::Wrap);
    m.comment("per level the texel's address in the level");
    let rs = raw_word(m, &uv[0], &uv_enc.format);
    let rt = raw_word(m, &uv[1], &uv_enc.format);
    let mut offsets = Vec::new();
    for l in 0..levels {
        let (log_w, log_h) = tex.level_at(l).logs();
        if frac < log_w.max(log_h) {
            return Err(format!(
                "index mipmaps: level {l} of 2^{log_w} x 2^{log_h} texels from a coordinate of \
                 {frac} fraction bits"
            ));
        }
        let ax_s = fetch::axis(m, &rs, frac, log_w, false, am_s);
        let ax_t = fetch::axis(m, &rt, frac, log_h, false, am_t);
        let parts: Vec<String> = [&ax_t.addr[0], &ax_s.addr[0]]
            .into_iter()
            .flatten()
            .cloned()
            .collect();
        let w = log_w + log_h;
        offsets.push(if parts.is_empty() {
            format!("{abits}'d0")
        } else if w < abits {
            m.uwire(
                "moff",
                abits,
                &format!("{{{}'d0, {}}}", abits - w, parts.join(", ")),
            )
        } else {
            m.uwire("moff", abits, &format!("{{{}}}", parts.join(", ")))
        });
    }
    let off = m.select_bits(&level, &offsets, abits);
    let base_words: Vec<String> = bases.iter().map(|b| format!("{abits}'d{b}")).collect();
    let base = m.select_bits(&level, &base_words, abits);
    let addr = m.uwire("maddr", abits, &format!("{off} + {base}"));
    let lat = f.mem_latency();
    let data = sh
        .memory("indices", words, wt, &[(addr, abits)], lat)
        .remove(0);
    let m = &mut sh.m;
    let x = from_code(m, &data, &texel);
    Ok(to_code(m, &x, &out_enc))
}

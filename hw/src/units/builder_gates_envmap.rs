//! The gate list of the palette builder's `EnvMap` table (every material `EnvMap`), priced
//! as `rtl::palette_envmap` builds it after the builder's slot issue and dot product: per
//! material four slots (`V`, then the eye frame's axes, vector registers the host loads) and
//! three reflection constants `V.a`; the normal read and the dot product; `N.V` registered,
//! `2 (N.V)(N.a) - V.a` and the three `R.a` registers; the exact `q = R_x^2 + R_y^2 + (R_z +
//! 1)^2`, Normalize's leading-one detector, mantissa shifter and reciprocal-square-root ROM;
//! per material and axis the product `R_a rho`, its shift by `2^k`, `1 +`, the scale by the
//! image's side, the clamp, and the texel address `j w + i` (the environment images lie in the
//! engine's texture memory: [`PaletteBuilder::frame_reads`]); the stage registers.

use super::builder_gates::{bits, corners, dot_product, fac_value, issue, raw_range};
use super::builder_gates::{normals_and_vectors, reading_facs, sbits};
use super::palette_builder::{LightingFn, PaletteBuilder};
use crate::arith::bit_length;
use crate::gates::{CostTable, GateBudget};

/// The builder's gates for a table of `EnvMap` materials; `None` when another function
/// shares the table (the generator refuses it).
pub(crate) fn envmap(b: &PaletteBuilder, t: &CostTable) -> Option<GateBudget> {
    let rs = b.sphere()?;
    let mut images = Vec::new();
    for (_, f) in b.materials() {
        match f {
            LightingFn::EnvMap {
                image,
                width,
                height,
                ..
            } => images.push((image.len() as u64, *width, *height)),
            _ => return None,
        }
    }
    let f = *b.formats();
    let (wn, wv, we) = (f.normal.width(), f.vector.width(), f.entry.width());
    let n = b.entries() as u64;
    let mats = images.len() as u32;
    let slots = 4 * mats;
    let (eb, fb) = (bits(n as u128 - 1), bits(slots as u128 - 1));
    let (nr, vr) = (raw_range(&f.normal), raw_range(&f.vector));
    let dn = corners(nr, vr);
    let dot = (3 * dn.0, 3 * dn.1);
    let kv = corners(vr, vr);
    let kw = sbits(3 * kv.0, 3 * kv.1);
    let regs = 3 * slots + 3 * mats;
    let mut g = GateBudget::new();
    normals_and_vectors(&mut g, t, b, slots);
    g.add(
        format!("slot reflection constant registers {kw}"),
        3 * mats,
        t.register(kw),
    );
    issue(&mut g, t, regs, eb, fb);
    if mats > 1 {
        // the material of the next entry (issue) and of the entry in stage 4
        g.add(
            format!("material compare {eb}"),
            3 * (mats - 1),
            t.comparator(eb),
        );
        g.add(format!("first slot mux {fb}"), 1, t.mux(fb, mats));
        g.add(
            format!("reflection constant select {kw}"),
            1,
            t.mux(kw, 3 * mats),
        );
        g.add(format!("texel select {}", 3 * we), 1, t.mux(3 * we, mats));
    }
    dot_product(&mut g, t, wn, wv, slots);
    // R.a = 2 (N.V)(N.a) - V.a: the constant lines up below the product's fraction
    let wdot = sbits(dot.0, dot.1);
    g.add(format!("N.V register {wdot}"), 1, t.register(wdot));
    g.add(
        format!("reflection multiplier {wdot}x{wdot}"),
        1,
        t.multiplier(wdot, wdot),
    );
    let (fnr, facn) = reading_facs(&f.normal);
    let (fvr, _) = reading_facs(&f.vector);
    let below = 2 * (fnr + fvr) - 1 - 2 * fvr;
    let k = fac_value(&[facn.clone(), facn].concat()) as i128;
    let p = corners(dot, dot);
    let (rlo, rhi) = (
        p.0.checked_mul(k)? - ((3 * kv.1) << below),
        p.1.checked_mul(k)? - ((3 * kv.0) << below),
    );
    let wfull = sbits(rlo, rhi);
    g.add(
        format!("reflection subtractor {}", wfull - below),
        1,
        t.adder(kw) + t.half_adder * (wfull - below).saturating_sub(kw) as f64,
    );
    // R.a's word: s2.r_frac, the dropped bits wires, the saturation a clamp
    let rf = f.sphere.r_frac;
    let wr = rf + 2;
    g.add(format!("R saturation {wfull}"), 1, t.clamp(wfull));
    g.add(format!("R registers {wr}"), 3, t.register(wr));
    // q: three squarers (R_z + 1 a bit wider), the sum
    g.add("R_z + 1 3", 1, t.constant_add(3));
    g.add(
        format!("squarer {wr}"),
        3,
        t.squarer(wr + 1) + t.adder(2 * wr),
    );
    let wq = 2 * wr + 2;
    g.add(format!("q adder {wq}"), 2, t.adder(wq));
    let levels = bit_length(wq as u128);
    rs.lookup_gates(&mut g, t, "sphere ", wq, levels);
    let (tb, vb) = (rs.index_bits(), rs.value_bits());
    let kb = bit_length(wq as u128 / 2 + 1);
    // per material and axis: R_a rho, the shift by 2^k, 1 +, x n, the floor's clamp; the
    // texel address j w + i
    for (img, w, h) in &images {
        for n in [w, h] {
            let cb = bits(*n as u128 - 1);
            g.add(
                format!("sphere multiplier {wr}x{vb}"),
                1,
                t.multiplier(wr, vb),
            );
            g.add(
                format!("sphere shifter {}x{kb}", wr + vb),
                1,
                t.mux(wr + vb, 2) * kb as f64,
            );
            g.add(format!("sphere 1 + {}", 2), 1, t.constant_add(2));
            g.add(
                format!("sphere scale x{n} {}", cb + 2),
                1,
                t.shift_add(cb + 2, *n as u128),
            );
            g.add(format!("sphere clamp {cb}"), 1, t.clamp(cb));
        }
        let ia = bits(*img as u128 - 1);
        g.add(
            format!("texel address x{w} {ia}"),
            1,
            t.shift_add(ia, *w as u128) + t.adder(ia),
        );
    }
    // stage registers: valid, entry (four stages), the material; the detector's flag, shift
    // and index; R_x and R_y twice; the table word and the shift
    let stages = 4 + 4 * eb + bits(mats as u128 - 1) + (1 + kb + tb) + 4 * wr + vb + kb;
    g.add(
        format!("stage registers {stages}"),
        1,
        t.dff * stages as f64,
    );
    Some(g)
}

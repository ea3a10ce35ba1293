//! The gate list of the palette builder's one-pipeline datapath for the functions with a
//! Verilog generator (Lambert, Specular, the split form; a `Table` power generator):
//! priced as `rtl::palette_builder` builds it (`docs/units/palette_builder.md`).
//!
//! Per slot (one dot product per clock; `cycles_per_entry` slots per material) the host
//! loads the vector and one coefficient per lane (the exact product of two entry words), per
//! material the ambient words. The pipeline: the slot sequencer (entry and slot counters, the
//! material of the next entry by the interval bounds), the vector select, three `normal x
//! vector` multipliers and the sum, the clamp and the cast into the intensity word (its
//! register), the power tables' index rounding (one table per distinct table), per lane the
//! coefficient select, one `coefficient x value` multiplier, the products of both kinds
//! brought to one reading where a lane has both, one accumulator, and after the entry's last
//! slot the factors the ambient word does not share applied, the ambient added and the cast
//! into the entry word. Pipeline registers between the stages.

use super::palette_builder::{LightingFn, PaletteBuilder};
use super::specgen::SpecGen;
use crate::format::{Codec, Encoding};
use crate::gates::{CostTable, GateBudget};

fn bits(hi: u128) -> u32 {
    (128 - hi.leading_zeros()).max(1)
}

/// `(fraction bits, replication factor)` of a word of `e` read into the datapath.
fn reading(e: &Encoding) -> (u32, u128) {
    let n = e.width();
    match e.codec {
        Codec::Fixed => (e.format.frac as u32, 1),
        Codec::UnitSigned => (n - 1, 1),
        Codec::UnitUnsigned | Codec::UnitSymmetric => (2 * n, (1u128 << n) + 1),
    }
}

/// Per lane: whether diffuse and specular slots add to it, the most slots of one material
/// that do, and whether a material has an ambient word in it.
#[derive(Default, Clone, Copy)]
struct Lane {
    diffuse: bool,
    specular: bool,
    most: u32,
    ambient: bool,
}

/// The builder's gates when every material has a generator; `None` otherwise.
pub(crate) fn pipelined(b: &PaletteBuilder, t: &CostTable) -> Option<GateBudget> {
    if b.entries_per_clock() != 1 {
        return None;
    }
    let f = *b.formats();
    let (wn, wv, wi, we) = (
        f.normal.width(),
        f.vector.width(),
        f.intensity.width(),
        f.entry.width(),
    );
    let n = b.entries() as u64;
    let mut lanes = [Lane::default(); 4];
    let (mut slots, mut coefs, mut ambients, mut split) = (0u32, 0u32, 0u32, false);
    let mut tables: Vec<&[i64]> = Vec::new();
    for ((_, func), gen) in b.materials().iter().zip(b.generators()) {
        if let Some(g) = gen {
            if !matches!(g.spec(), SpecGen::Table { .. }) {
                return None;
            }
            if !tables.contains(&g.table()) {
                tables.push(g.table());
            }
        }
        // (lights, diffuse lanes, specular lanes, ambient lanes)
        let (l, dl, sl, al): (u32, &[usize], &[usize], &[usize]) = match func {
            LightingFn::Lambert { lights, .. } => {
                (lights.len() as u32, &[0, 1, 2], &[], &[0, 1, 2])
            }
            LightingFn::Specular { lights, .. } => {
                (lights.len() as u32, &[0, 1, 2], &[0, 1, 2], &[0, 1, 2])
            }
            LightingFn::SpecularSplit { lights, .. } => {
                split = true;
                (lights.len() as u32, &[3], &[0, 1, 2], &[3])
            }
            _ => return None,
        };
        let kinds = 1 + u32::from(!sl.is_empty());
        slots += (kinds * l).max(1);
        coefs += l * (dl.len() + sl.len()) as u32;
        ambients += al.len() as u32;
        for (j, lane) in lanes.iter_mut().enumerate() {
            let (d, s) = (dl.contains(&j) && l > 0, sl.contains(&j) && l > 0);
            lane.diffuse |= d;
            lane.specular |= s;
            lane.most = lane.most.max(l * (u32::from(d) + u32::from(s)));
            lane.ambient |= al.contains(&j);
        }
    }
    let mats = b.materials().len() as u32;
    let (eb, fb) = (bits(n as u128 - 1), bits(slots as u128 - 1));
    let value_bits = match f.power {
        SpecGen::Table { value_bits, .. } => value_bits,
        _ => 1,
    };
    // a coefficient: the product of two entry words' readings
    let emax = match f.entry.codec {
        Codec::UnitSymmetric => 2 * f.entry.format.max_raw() as u128 + 1,
        _ => f.entry.format.max_raw().max(0) as u128,
    };
    let cw = bits(emax * emax);
    let regs = 3 * slots + coefs + ambients;
    let ab = bits(regs.saturating_sub(1) as u128);
    let mut g = GateBudget::new();
    g.add_memory(
        format!("normal table {n}x{} (loadable)", 3 * wn),
        1,
        t.table(n, 3 * wn),
    );
    g.add(
        format!("slot vector registers 3x{wv}"),
        slots,
        t.register(3 * wv),
    );
    g.add(
        format!("slot coefficient registers {cw}"),
        coefs,
        t.register(cw),
    );
    g.add(format!("ambient registers {we}"), ambients, t.register(we));
    g.add(
        format!("register address decode {ab}"),
        regs,
        t.and2 * ab as f64,
    );
    // issue: busy, entry and slot counters, the next entry's material and its first slot
    g.add(
        format!("slot sequencer {}", 1 + eb + fb),
        1,
        t.register(1 + eb + fb) + t.half_adder * (eb + fb) as f64,
    );
    if mats > 1 {
        g.add(
            format!("material compare {eb}"),
            2 * (mats - 1),
            t.comparator(eb),
        );
        g.add(format!("first slot mux {fb}"), 1, t.mux(fb, mats));
        g.add(format!("ambient mux {we}"), 4, t.mux(we, mats));
    }
    g.add(
        format!("pipeline registers {}", 3 + 3 * eb + 2 * fb + wi),
        1,
        t.register(3 + 3 * eb + 2 * fb + wi),
    );
    g.add(format!("vector select 3x{wv}"), 1, t.mux(3 * wv, slots));
    let wd = wn + wv + 2;
    g.add(format!("dot multiplier {wn}x{wv}"), 3, t.multiplier(wn, wv));
    g.add(format!("dot adder {wd}"), 2, t.adder(wd));
    let (fi, ri) = reading(&f.intensity);
    g.add(format!("intensity clamp {wi}"), 1, t.clamp(wi));
    // the clamped dot product (fraction bits of both words) cast into the intensity word
    let k_int = ri.max(1) * ((1u128 << wi) - 1);
    let dot_frac = f.normal.format.frac as u32 + f.vector.format.frac as u32;
    g.add(
        format!("intensity cast x{k_int} {}", dot_frac + 1),
        1,
        t.shift_add(dot_frac + 1, k_int),
    );
    let spec_any = lanes.iter().any(|l| l.specular);
    if spec_any {
        if let Some(gen) = b.generators().iter().flatten().next() {
            let mut part = gen.gates(t);
            part.items.retain(|i| !i.memory);
            g.add_part("", 1, part);
        }
        for (k, tab) in tables.iter().enumerate() {
            g.add_memory(
                format!("power table {k} {}x{value_bits} (loadable)", tab.len()),
                1,
                t.table(tab.len() as u64, value_bits),
            );
        }
        if tables.len() > 1 {
            g.add(
                format!("power table select {value_bits}"),
                1,
                t.mux(value_bits, tables.len() as u32),
            );
        }
    }
    let xw = if spec_any { wi.max(value_bits) } else { wi };
    if spec_any && lanes.iter().any(|l| l.diffuse) {
        g.add(format!("intensity or power select {xw}"), 1, t.mux(xw, 2));
    }
    let (fe, re) = reading(&f.entry);
    let pe = Encoding::texel(Codec::UnitUnsigned, false, value_bits.clamp(1, 16) as u8);
    let (fp, rp) = reading(&pe);
    let pw = cw + xw; // a lane product
    for (j, l) in lanes.iter().enumerate().take(if split { 4 } else { 3 }) {
        if !(l.diffuse || l.specular) {
            continue;
        }
        g.add(
            format!("lane {j} coefficient select {cw}"),
            1,
            t.mux(cw, slots),
        );
        g.add(
            format!("lane {j} multiplier {cw}x{xw}"),
            1,
            t.multiplier(cw, xw),
        );
        // the accumulated reading: the product's raw integer with its factors pending
        let (mut width, mut pending) = (pw, re * re);
        if l.diffuse && l.specular {
            let top = fi.max(fp);
            let (kd, ks) = (ri << (top - fi), rp << (top - fp));
            g.add(
                format!("lane {j} diffuse reading x{kd} {pw}"),
                1,
                t.shift_add(pw, kd),
            );
            g.add(
                format!("lane {j} power reading x{ks} {pw}"),
                1,
                t.shift_add(pw, ks),
            );
            width = pw + bits(kd.max(ks));
            g.add(
                format!("lane {j} reading select {width}"),
                1,
                t.mux(width, 2),
            );
        } else {
            pending *= if l.diffuse { ri } else { rp };
        }
        let aw = width + bits(l.most.max(1) as u128 - 1) + 1;
        g.add(
            format!("lane {j} accumulator {aw}"),
            1,
            t.adder(aw) + t.register(aw) + t.and2 * aw as f64,
        );
        let k_cast = ((1u128 << we) - 1) * if l.ambient { re } else { pending };
        let mut cw_in = aw;
        if l.ambient {
            // the factors the ambient word does not share, then its sum
            let strip = pending / re;
            g.add(
                format!("lane {j} accumulator reading x{strip} {aw}"),
                1,
                t.shift_add(aw, strip),
            );
            cw_in = aw + bits(strip);
            // the ambient word sits above the accumulator's fraction: an adder over its bits
            // and a carry chain above them
            let acc_frac = 2 * fe
                + if l.diffuse && l.specular {
                    fi.max(fp)
                } else if l.diffuse {
                    fi
                } else {
                    fp
                };
            let over = cw_in.saturating_sub(acc_frac - fe);
            let wa = (we + 1).min(over);
            g.add(
                format!("lane {j} ambient adder {wa}"),
                1,
                t.adder(wa) + t.half_adder * over.saturating_sub(wa) as f64,
            );
        }
        g.add(
            format!("lane {j} entry cast x{k_cast} {cw_in}"),
            1,
            t.shift_add(cw_in, k_cast),
        );
        g.add(format!("lane {j} entry clamp {we}"), 1, t.clamp(we));
    }
    Some(g)
}

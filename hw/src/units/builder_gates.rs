//! The gate list of the palette builder's one-pipeline datapath for the functions with a
//! Verilog generator (Lambert, Specular, the split form, Cartoon, DoubledAnglePhong, Chrome;
//! a `Table` power generator): priced as `rtl::palette_builder` builds it
//! (`docs/units/palette_builder.md`).
//!
//! Per slot (one dot product per clock; `cycles_per_entry` slots per material) the host
//! loads the vector and one coefficient per lane (the exact product of two entry words;
//! chrome's `sky - ground`, one word's width and a sign), a reflection slot its constant
//! (`L.V`, `V.up`), per material the ambient words (chrome's ground), per cartoon material
//! its band words. The pipeline: the slot sequencer (entry and slot counters, the material of
//! the next entry by the interval bounds), the vector select, three `normal x vector`
//! multipliers and the sum, the clamp and the cast into the intensity word (its register),
//! the other intensity sources and their select (the cartoon sum, its clamp and cast; the
//! reflection: the previous dot product's register, `dot x dot`, the constant's subtractor;
//! chrome's offset, clamp and cast; doubled-angle Phong's `R.V` clamp and register, the
//! folded squarer, the offset, clamp and cast), the power tables' index rounding (one table
//! per distinct table), per lane the coefficient select, one `coefficient x value`
//! multiplier, the products of the lane's classes brought to one reading where it has
//! several, one accumulator, and after the entry's last slot the factors the ambient word
//! does not share applied, the ambient added and the cast into the entry word; cartoon's band
//! index (`x bands` by its digits, the clamp), its register and the band word selects.
//! Pipeline registers between the stages.

use super::palette_builder::{LightingFn, PaletteBuilder};
use super::specgen::SpecGen;
use crate::format::{Codec, Encoding};
use crate::gates::{CostTable, GateBudget, TableRole};

pub(crate) fn bits(hi: u128) -> u32 {
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

/// `(fraction bits, factor n's)` of a word of `e` read into the datapath: the factors
/// `2^n + 1` of its bit replication.
pub(crate) fn reading_facs(e: &Encoding) -> (u32, Vec<u32>) {
    let n = e.width();
    match e.codec {
        Codec::Fixed => (e.format.frac as u32, Vec::new()),
        Codec::UnitSigned => (n - 1, Vec::new()),
        Codec::UnitUnsigned | Codec::UnitSymmetric => (2 * n, vec![n]),
    }
}

/// The product of the factors `2^n + 1`.
pub(crate) fn fac_value(f: &[u32]) -> u128 {
    f.iter().map(|&n| (1u128 << n) + 1).product()
}

/// The range of the raw integers a word of `e` is read as (`2c + 1` for symmetric codes).
pub(crate) fn raw_range(e: &Encoding) -> (i128, i128) {
    let f = e.format;
    match e.codec {
        Codec::UnitSymmetric => (2 * f.min_raw() as i128 + 1, 2 * f.max_raw() as i128 + 1),
        _ => (f.min_raw() as i128, f.max_raw() as i128),
    }
}

pub(crate) fn corners(a: (i128, i128), b: (i128, i128)) -> (i128, i128) {
    let c = [a.0 * b.0, a.0 * b.1, a.1 * b.0, a.1 * b.1];
    (*c.iter().min().unwrap(), *c.iter().max().unwrap())
}

/// Bits of a signed word holding `[lo, hi]`.
pub(crate) fn sbits(lo: i128, hi: i128) -> u32 {
    crate::rtl::verilog::signed_bits(lo, hi)
}

/// The classes of lane term: a coefficient of two entry words or one (chrome's `sky -
/// ground`), times an intensity or a power word.
const PD: usize = 0;
const PS: usize = 1;
const WD: usize = 2;

/// Per lane: which classes of term add to it, the most slots of one material that do, and
/// whether a material has an ambient word in it.
#[derive(Default, Clone, Copy)]
struct Lane {
    class: [bool; 3],
    most: u32,
    ambient: bool,
}

/// The normal table (memory) and the slots' vector registers (`vec_slots` of them).
pub(crate) fn normals_and_vectors(
    g: &mut GateBudget,
    t: &CostTable,
    b: &PaletteBuilder,
    vec_slots: u32,
) {
    let f = b.formats();
    let (n, wn, wv) = (b.entries(), f.normal.width(), f.vector.width());
    g.add_memory(
        format!("normal table {n}x{} (loadable)", 3 * wn),
        1,
        t.for_table(TableRole::Normals)
            .table_of(&b.normal_words(), 3 * wn),
    );
    g.add(
        format!("slot vector registers 3x{wv}"),
        vec_slots,
        t.register(3 * wv),
    );
}

/// The host registers' address decode (`regs` registers) and the slot sequencer: busy, the
/// entry (`eb` bits) and slot (`fb` bits) counters.
pub(crate) fn issue(g: &mut GateBudget, t: &CostTable, regs: u32, eb: u32, fb: u32) {
    let ab = bits(regs.saturating_sub(1) as u128);
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
}

/// The slot's vector select (`slots` vectors of `3 x wv` bits) and the dot product `N .
/// vector`: three multipliers and the exact sum.
pub(crate) fn dot_product(g: &mut GateBudget, t: &CostTable, wn: u32, wv: u32, slots: u32) {
    g.add(format!("vector select 3x{wv}"), 1, t.mux(3 * wv, slots));
    let wd = wn + wv + 2;
    g.add(format!("dot multiplier {wn}x{wv}"), 3, t.multiplier(wn, wv));
    g.add(format!("dot adder {wd}"), 2, t.adder(wd));
}

/// The builder's gates when every material has a generator; `None` otherwise.
pub(crate) fn pipelined(b: &PaletteBuilder, t: &CostTable) -> Option<GateBudget> {
    if b.entries_per_clock() != 1 {
        return None;
    }
    if b.materials()
        .iter()
        .any(|(_, f)| matches!(f, LightingFn::EnvMap { .. }))
    {
        return super::builder_gates_envmap::envmap(b, t);
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
    let (mut slots, mut vec_slots, mut coefs, mut ambients, mut split) =
        (0u32, 0u32, 0u32, 0u32, false);
    // chrome's coefficient words, reflection constants, band words
    let (mut words, mut konsts, mut band_words) = (0u32, 0u32, 0u32);
    let (mut chrome, mut doubled, mut zero) = (false, false, false);
    let mut cartoon_lights: Option<u32> = None;
    let mut band_counts: Vec<u32> = Vec::new();
    let mut cartoon_mats = 0u32;
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
        // (lights, diffuse lanes, specular lanes, ambient lanes) of the product classes
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
            LightingFn::DoubledAnglePhong { .. } => {
                // N.L, N.V (R.V, the doubled angle, the power word), an idle slot
                doubled = true;
                slots += 3;
                vec_slots += 2;
                konsts += 1;
                coefs += 6;
                ambients += 3;
                for lane in lanes.iter_mut().take(3) {
                    lane.class[PD] = true;
                    lane.class[PS] = true;
                    lane.most = lane.most.max(2);
                    lane.ambient = true;
                }
                continue;
            }
            LightingFn::Chrome { .. } => {
                // N.V, N.up (R.up, t): the lane adds (sky - ground) t to the ground word
                chrome = true;
                slots += 2;
                vec_slots += 2;
                konsts += 1;
                words += 3;
                ambients += 3;
                for lane in lanes.iter_mut().take(3) {
                    lane.class[WD] = true;
                    lane.most = lane.most.max(1);
                    lane.ambient = true;
                }
                continue;
            }
            LightingFn::Cartoon { bands, lights, .. } => {
                // one slot per light into the cartoon sum, the band slot; the entry is a
                // band word
                let l = lights.len() as u32;
                slots += l + 1;
                vec_slots += l;
                band_words += 3 * bands;
                cartoon_mats += 1;
                zero |= l == 0;
                if l > 0 {
                    cartoon_lights = Some(cartoon_lights.unwrap_or(0).max(l));
                }
                if !band_counts.contains(bands) {
                    band_counts.push(*bands);
                }
                continue;
            }
            LightingFn::EnvMap { .. } => return None, // priced above
        };
        let kinds = 1 + u32::from(!sl.is_empty());
        slots += (kinds * l).max(1);
        vec_slots += kinds * l;
        coefs += l * (dl.len() + sl.len()) as u32;
        ambients += al.len() as u32;
        for (j, lane) in lanes.iter_mut().enumerate() {
            let (d, s) = (dl.contains(&j) && l > 0, sl.contains(&j) && l > 0);
            lane.class[PD] |= d;
            lane.class[PS] |= s;
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
    let (er_lo, er_hi) = raw_range(&f.entry);
    let ww = sbits(er_lo - er_hi, er_hi - er_lo);
    // the dot product's exact range, a reflection constant's
    let (nr, vr) = (raw_range(&f.normal), raw_range(&f.vector));
    let dn = corners(nr, vr);
    let dot = (3 * dn.0, 3 * dn.1);
    let kv = corners(vr, vr);
    let kw = sbits(3 * kv.0, 3 * kv.1);
    let regs = 3 * vec_slots + coefs + words + konsts + ambients + band_words;
    let mut g = GateBudget::new();
    normals_and_vectors(&mut g, t, b, vec_slots);
    if coefs > 0 {
        g.add(
            format!("slot coefficient registers {cw}"),
            coefs,
            t.register(cw),
        );
    }
    if words > 0 {
        g.add(
            format!("slot sky - ground registers {ww}"),
            words,
            t.register(ww),
        );
    }
    if konsts > 0 {
        g.add(
            format!("slot reflection constant registers {kw}"),
            konsts,
            t.register(kw),
        );
    }
    if ambients > 0 {
        g.add(format!("ambient registers {we}"), ambients, t.register(we));
    }
    if band_words > 0 {
        g.add(format!("band registers {we}"), band_words, t.register(we));
    }
    issue(&mut g, t, regs, eb, fb);
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
    dot_product(&mut g, t, wn, wv, slots);
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
    // the other sources of the intensity word: a clamp into [0, 1] (a compare of the
    // word against the upper limit, the code mux) and the cast of the fraction
    let k_code = (1u128 << wi) - 1;
    let mut sources = 0u32;
    let (fnr, facn) = reading_facs(&f.normal);
    let (fvr, facv) = reading_facs(&f.vector);
    let dfrac = fnr + fvr;
    let dfac = fac_value(&[facn.clone(), facv.clone()].concat());
    if chrome || doubled {
        // the previous slot's dot product, its product with this slot's, less the constant
        let wdot = sbits(dot.0, dot.1);
        g.add(
            format!("reflection register {wdot}"),
            1,
            t.dff * wdot as f64,
        );
        g.add(
            format!("reflection multiplier {wdot}x{wdot}"),
            1,
            t.multiplier(wdot, wdot),
        );
        let p = corners(dot, dot);
        let wp = sbits(p.0, p.1);
        // the constant lines up below the product's fraction: its bits and the carry above
        let below = 2 * dfrac - 1 - 2 * fvr;
        let mut kfac = 1;
        if dfac > 1 {
            // the factors the constant does not share, applied to the product
            kfac = fac_value(&[facn.clone(), facn.clone()].concat());
            g.add(
                format!("reflection reading x{kfac} {wp}"),
                1,
                t.shift_add(wp, kfac),
            );
        }
        let k = kfac as i128;
        // R = 2 (N.a)(N.b) - a.b: the product's raw word read with one fraction bit less
        let (rlo, rhi) = (
            p.0.checked_mul(k)? - ((3 * kv.1) << below),
            p.1.checked_mul(k)? - ((3 * kv.0) << below),
        );
        if rhi > 1 << 62 {
            return None; // the generator refuses: R.V's square overflows 128 bits
        }
        let wr = sbits(rlo, rhi);
        g.add(
            format!("reflection subtractor {}", wr - below),
            1,
            t.adder(kw) + t.half_adder * (wr - below).saturating_sub(kw) as f64,
        );
        if konsts > 1 {
            g.add(
                format!("reflection constant select {kw}"),
                1,
                t.mux(kw, konsts),
            );
        }
        let rfrac = 2 * dfrac - 1;
        if chrome {
            // t = (1 + R.up) / 2: a carry chain over the integer bits, clamp and cast
            let one = 1i128 << rfrac;
            let wt = sbits(rlo + one, rhi + one);
            let int = wt.saturating_sub(rfrac);
            g.add(format!("chrome offset {int}"), 1, t.constant_add(int));
            g.add(format!("chrome clamp {wt}"), 1, t.clamp(wt) + t.clamp(wi));
            g.add(
                format!("chrome cast x{k_code} {}", rfrac + 2),
                1,
                t.shift_add(rfrac + 2, k_code),
            );
            sources += 1;
        }
        if doubled {
            // R.V clamped to [0, 1] and registered, its square (as wide as the fraction),
            // 2 x^2 - 1 (a borrow chain over the top bits), the clamp at 0 and the cast
            let wq = rfrac + 1;
            g.add(format!("doubled-angle R.V clamp {wr}"), 1, t.clamp(wr));
            g.add(
                format!("doubled-angle R.V register {wq}"),
                1,
                t.dff * wq as f64,
            );
            // the folded array (each product u_i u_j once) and the diagonal u_i at 2i, a row
            // of its own: one adder over the square's bits
            g.add(
                format!("doubled-angle squarer {wq}"),
                1,
                t.squarer(wq) + t.adder(2 * wq),
            );
            let sfrac = 2 * rfrac - 1;
            g.add("doubled-angle offset 2", 1, t.constant_add(2));
            g.add(format!("doubled-angle clamp {wi}"), 1, t.clamp(wi));
            g.add(
                format!("doubled-angle cast x{k_code} {}", sfrac + 1),
                1,
                t.shift_add(sfrac + 1, k_code),
            );
            sources += 1;
        }
    }
    if let Some(l) = cartoon_lights {
        // the sum of the clamped dot products, its clamp and cast
        let wc = dfrac + 1 + bits(l as u128);
        g.add(
            format!("cartoon sum {wc}"),
            1,
            t.adder(wc) + t.register(wc) + t.and2 * wc as f64,
        );
        if l > 1 {
            g.add(format!("cartoon clamp {wc}"), 1, t.clamp(wc) + t.clamp(wi));
        }
        g.add(
            format!("cartoon cast x{k_code} {}", dfrac + 1),
            1,
            t.shift_add(dfrac + 1, k_code),
        );
        sources += 1;
    }
    if zero {
        sources += 1;
    }
    if sources > 0 {
        g.add(
            format!("intensity source select {wi}"),
            1,
            t.mux(wi, sources + 1),
        );
    }
    let spec_any = lanes.iter().any(|l| l.class[PS]);
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
                t.for_table(TableRole::Power).table_of(tab, value_bits),
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
    if spec_any && lanes.iter().any(|l| l.class[PD] || l.class[WD]) {
        g.add(format!("intensity or power select {xw}"), 1, t.mux(xw, 2));
    }
    if let Some(&most) = band_counts.iter().max() {
        // stage 2: floor(bands k), clamped; stage 3: the band word per lane
        let kb = bits(most as u128 - 1);
        for &bands in &band_counts {
            let kx = ri.max(1) * bands as u128;
            g.add(
                format!("band index x{kx} {wi}"),
                1,
                t.shift_add(wi, kx) + t.clamp(kb),
            );
        }
        if band_counts.len() > 1 {
            g.add(
                format!("band index select {kb}"),
                1,
                t.mux(kb, band_counts.len() as u32),
            );
        }
        g.add(format!("band register {kb}"), 1, t.dff * kb as f64);
        g.add(
            format!("band select {we}"),
            3 * cartoon_mats,
            t.mux(we, most),
        );
        if cartoon_mats > 1 {
            g.add(format!("band material select {we}"), 3, t.mux(we, mats));
        }
        if cartoon_mats < mats {
            g.add(format!("band or colour select {we}"), 3, t.mux(we, 2));
        }
    }
    let (fe, re) = reading(&f.entry);
    let pe = Encoding::texel(Codec::UnitUnsigned, false, value_bits.clamp(1, 16) as u8);
    let (fp, rp) = reading(&pe);
    for (j, l) in lanes.iter().enumerate().take(if split { 4 } else { 3 }) {
        if !l.class.iter().any(|&c| c) {
            continue;
        }
        // the classes in the lane: (coefficient width, fraction, pending factor)
        let classes: Vec<(u32, u32, u128)> = [
            (PD, cw, 2 * fe + fi, re * re * ri),
            (PS, cw, 2 * fe + fp, re * re * rp),
            (WD, ww, fe + fi, re * ri),
        ]
        .into_iter()
        .filter(|c| l.class[c.0])
        .map(|c| (c.1, c.2, c.3))
        .collect();
        let lw = classes.iter().map(|c| c.0).max().unwrap();
        let lxw = xw;
        g.add(
            format!("lane {j} coefficient select {lw}"),
            1,
            t.mux(lw, slots),
        );
        g.add(
            format!("lane {j} multiplier {lw}x{lxw}"),
            1,
            t.multiplier(lw, lxw),
        );
        let pw = lw + lxw; // a lane product
                           // the accumulated reading: the product's raw integer with its factors pending
        let (mut width, mut pending, acc_frac) = (pw, classes[0].2, classes[0].1);
        let acc_frac = if classes.len() > 1 {
            // each class brought to the common reading: the factors not common to all, and
            // the alignment to the finest fraction
            let top = classes.iter().map(|c| c.1).max().unwrap();
            let common = classes
                .iter()
                .fold(classes[0].2, |a, c| crate::arith::gcd(a, c.2));
            let mut kmax = 1;
            for (c, &(_, fr, fac)) in classes.iter().enumerate() {
                let k = (fac / common) << (top - fr);
                let name = ["diffuse", "power", "sky - ground"][[PD, PS, WD]
                    .iter()
                    .copied()
                    .filter(|&x| l.class[x])
                    .nth(c)
                    .unwrap()];
                g.add(
                    format!("lane {j} {name} reading x{k} {pw}"),
                    1,
                    t.shift_add(pw, k),
                );
                kmax = kmax.max(k);
            }
            width = pw + bits(kmax);
            g.add(
                format!("lane {j} reading select {width}"),
                1,
                t.mux(width, classes.len() as u32),
            );
            pending = common;
            top
        } else {
            acc_frac
        };
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

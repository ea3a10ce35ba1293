//! Texel fetch and filter unit: a 2D texture of 1 to 4 lane texels (a normal map, a height
//! map, a colour texture) read at the fragment's texture coordinate with nearest or bilinear
//! filtering and wrap, clamp-to-edge or mirrored-repeat addressing ([`Address`]), at signed
//! or unsigned coordinates (a dependent lookup reads coordinates that an earlier unit computed,
//! such as two dot products in [-1, 1]).
//!
//! Models the normal-map lookup of the SGI engine (Gouraud bump paper §3.4: "a perturbed
//! normal vector field is needed as a bump-normal map (three component texture map)") and the
//! filtered bump-map read of Ernst et al. §5.3 ("Due to the full texture filtering capability
//! of bump maps, smoothly interpolated bump-vectors are used").
//!
//! Texture sizes are powers of two, so the texel address is a shift of the fixed-point
//! coordinate. Bilinear filtering uses `weight_bits`-bit weights truncated from the
//! coordinate's fraction, and exact products; the filtered value is cast once into the output
//! encoding. The filtered vector is *not* renormalised (as in the hardware of the period).
//! Memory: `ports` texels are read per clock, so a bilinear fetch takes `ceil(4 / ports)`
//! clocks. Exact mode reads the unquantized texels with exact weights.

use crate::columns::{Column, ColumnIn};
use crate::format::{Codec, Encoding};
use crate::gates::{CostTable, GateBudget, TableRole};
pub use crate::sampler::{Address, Filter};
use crate::sampler::{SamplePlan, Sampler};
pub use crate::texture::Texels;
use crate::texture::Texture;
use crate::unit::{Mode, PortSpec, TextureRead, Unit, Word};
use std::sync::Arc;

pub struct TexFetch {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    sampler: Sampler,
    ports: u32,
    mem_latency: u32,
    tex: Arc<Texture>,
    /// The sampler's casts from the texture's texels into `t`.
    plan: SamplePlan,
}

impl TexFetch {
    /// Read level 0 of the 2D texture `tex` of the engine's texture memory through `sampler`
    /// at coordinates of encoding `uv`; `ports` texels per clock, `mem_latency` clocks of
    /// memory latency; the filtered texel cast into `out`. If the texture is stored as palette
    /// indices ([`Texture::with_palette`], Ernst et al. §6: "The memory requirements for the
    /// bump maps can be minimized by using palletized bumps. With eight bit addressing a table
    /// lookup (bump) texture, up to 256 surface orientations can be modeled."), the unit adds
    /// the palette RAM (entries x texel bits, loaded once per frame) to its gates and its
    /// per-frame cycles; filtering happens after the palette lookup (one lookup per tap).
    /// Errors name the parameter and what was expected.
    pub fn new(
        uv: Encoding,
        tex: Arc<Texture>,
        sampler: Sampler,
        ports: u32,
        mem_latency: u32,
        out: Encoding,
    ) -> Result<Self, String> {
        if !(1..=4).contains(&ports) {
            return Err(format!("ports {ports}: expected 1 to 4"));
        }
        if tex.shape() != crate::texture::Shape::Flat {
            return Err(format!(
                "texture {}: a cube map: expected a 2D texture",
                tex.name()
            ));
        }
        sampler.check(&tex, &uv)?;
        Ok(TexFetch {
            inputs: vec![PortSpec::new("uv", 2, uv)],
            outputs: vec![PortSpec::new("t", tex.lanes(), out)],
            sampler,
            ports,
            mem_latency: mem_latency.max(1),
            plan: sampler.plan(tex.texel(), &out),
            tex,
        })
    }

    /// Clocks of memory latency.
    pub fn mem_latency(&self) -> u32 {
        self.mem_latency
    }

    /// The texture read.
    pub fn texture(&self) -> &Arc<Texture> {
        &self.tex
    }

    /// The sampler (filter, weight width, address modes).
    pub fn sampler(&self) -> &Sampler {
        &self.sampler
    }

    /// Texels read per clock.
    pub fn ports(&self) -> u32 {
        self.ports
    }

    /// The filtered texel of mip level `level` at the coordinate `uv`, in `mode`.
    pub fn sample(&self, mode: Mode, level: usize, uv: &Word) -> Word {
        let out = self.outputs[0].enc;
        let lanes = self.tex.lanes() as usize;
        match mode {
            Mode::Exact => {
                let (s, t) = (uv.lanes[0].x, uv.lanes[1].x);
                let v = self.sampler.sample_exact(&self.tex, level, 0, s, t);
                Word::from_exact(&out, &v[..lanes])
            }
            Mode::BitAccurate => {
                let frac = self.inputs[0].enc.format.frac as u32;
                let (s, t) = (uv.lanes[0].raw, uv.lanes[1].raw);
                let res = self
                    .sampler
                    .sample_bits(&self.tex, level, 0, s, t, frac, &self.plan);
                Word::from_raw(&out, &res[..lanes])
            }
        }
    }
}

impl Unit for TexFetch {
    fn kind(&self) -> &'static str {
        "tex_fetch"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        self.mem_latency
            .saturating_add(self.interval())
            .saturating_add(u32::from(self.sampler.filter() == Filter::Bilinear))
    }
    fn interval(&self) -> u32 {
        self.sampler.taps().div_ceil(self.ports)
    }
    fn textures(&self) -> Vec<TextureRead> {
        vec![TextureRead {
            texture: self.tex.clone(),
            taps: self.sampler.taps(),
        }]
    }
    fn upload(&mut self, old: &Arc<Texture>, new: &Arc<Texture>) {
        if Arc::ptr_eq(&self.tex, old) {
            self.plan = self.sampler.plan(new.texel(), &self.outputs[0].enc);
            self.tex = new.clone();
        }
    }
    fn frame_cycles(&self) -> u64 {
        self.tex.palette().map_or(0, u64::from)
    }
    /// Priced as `rtl::fetch` builds it (`docs/gates.md`): per axis the half-texel offset and
    /// the neighbour's incrementer on the index bits the address mode needs, the clamp or
    /// mirror logic, the port address muxes; per lane three lerps `a + (b - a) w` whose
    /// weights carry only the coordinate's fraction bits below the texel (`min(weight_bits,
    /// frac - log2 size)`: the truncated weight's other bits are zero); the cast; the weight,
    /// tap and output registers. The texel memory is outside the budget.
    fn gates(&self, t: &CostTable) -> GateBudget {
        let uv = self.inputs[0].enc;
        let texel = self.tex.texel();
        let wt = texel.width();
        let lanes = self.tex.lanes() as u32;
        let out = self.outputs[0].enc;
        let wo = out.width();
        let taps = self.sampler.taps();
        let mut g = GateBudget::new();
        let ax = address_gates(
            &mut g,
            t,
            &uv,
            self.tex.level_at(0).logs(),
            &self.sampler,
            1,
        );
        let eff = [ax[0].1, ax[1].1];
        let (log_w, log_h) = self.tex.level_at(0).logs();
        let ab = (log_w + log_h).max(1);
        let groups = self.interval();
        if groups > 1 {
            g.add(
                format!("port address mux {groups}:1 x{ab}"),
                self.ports.min(taps),
                t.mux(ab, groups),
            );
            g.add(
                format!("tap register {}", wt * lanes),
                taps,
                t.register(wt * lanes),
            );
        }
        filter_gates(&mut g, t, texel, lanes, &out, &self.sampler, eff);
        g.add(
            format!("output register {}", wo * lanes),
            1,
            t.register(wo * lanes),
        );
        g.add("sequencer", 1, t.sequencer(self.latency()));
        if let Some(n) = self.tex.palette() {
            // by its contents where the texture knows them (`cost.tables = Rom`), else by size
            let ge = match self.tex.palette_words() {
                Some(words) => t
                    .for_table(TableRole::BumpPalette)
                    .table_of(words, wt * lanes),
                None => t
                    .for_table(TableRole::BumpPalette)
                    .table(n as u64, wt * lanes),
            };
            g.add_memory(
                format!("bump palette {n}x{} (loadable)", wt * lanes),
                self.ports,
                ge,
            );
        }
        g
    }
    fn eval_columns(&self, n: usize, ins: &[ColumnIn<'_>], outs: &mut [&mut Column]) -> bool {
        let frac = self.inputs[0].enc.format.frac as u32;
        let [s, t, ..] = ins[0].lanes;
        let lanes = self.tex.lanes() as usize;
        let o = &mut outs[0];
        for k in 0..n {
            let res = self
                .sampler
                .sample_bits(&self.tex, 0, 0, s[k], t[k], frac, &self.plan);
            for (o, r) in o.iter_mut().zip(res).take(lanes) {
                o[k] = r;
            }
        }
        true
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        outs[0] = self.sample(mode, 0, &ins[0]);
    }
}

/// The texel addressing of a level of `2^log_w x 2^log_h` texels read at coordinates `uv`
/// by `sampler` (the half-texel offset, the neighbour incrementer, clamp or mirror logic per
/// axis, each item `count` times), added to `g`. Returns per axis the index bits the address
/// reads (0 for a one-texel axis) and the weight bits (`weight_bits`, or fewer where the
/// coordinate has fewer fraction bits below the texel).
/// Shared with the texture shaders' configured price.
pub(crate) fn address_gates(
    g: &mut GateBudget,
    t: &CostTable,
    uv: &Encoding,
    (log_w, log_h): (u32, u32),
    sampler: &Sampler,
    count: u32,
) -> [(u32, u32); 2] {
    let frac = uv.format.frac as u32;
    let bilinear = sampler.filter() == Filter::Bilinear;
    let mut eff = [(0u32, 0u32); 2];
    for (a, (name, log)) in [("s", log_w), ("t", log_h)].into_iter().enumerate() {
        let f = frac - log;
        eff[a].1 = sampler.weight_bits().min(f);
        if log == 0 {
            continue;
        }
        let mode = sampler.address()[a];
        // the index's range (and its neighbour's) from the coordinate's
        let half = if bilinear { 1i64 << (f - 1) } else { 0 };
        let lo = (uv.format.min_raw() - half) >> f;
        let hi = ((uv.format.max_raw() - half) >> f) + i64::from(bilinear);
        let span = crate::rtl::verilog::signed_bits(lo as i128, hi as i128);
        // index bits the address needs: the low log (wrap), one more (mirror), all (clamp)
        let ib = match mode {
            Address::Wrap => log,
            Address::Mirror => log + 1,
            Address::Clamp => span.max(log + 1),
        };
        eff[a].0 = ib;
        let idx = (1 + u32::from(bilinear)) * count;
        if bilinear {
            g.add(
                format!("{name} half-texel offset {}", ib + 1),
                count,
                t.half_adder * (ib + 1) as f64,
            );
            g.add(
                format!("{name} neighbour incrementer {ib}"),
                count,
                t.half_adder * ib as f64,
            );
        }
        let n = 1i64 << log;
        match mode {
            Address::Wrap => {}
            // logic only where the index can leave the texture (the RTL tracks the range)
            Address::Clamp if lo >= 0 && hi < n => {}
            Address::Clamp => {
                g.add(
                    format!("{name} clamp {log} of {ib}"),
                    idx,
                    t.clamp(log) + t.and2 * (ib - log) as f64,
                );
            }
            Address::Mirror => {
                g.add(format!("{name} mirror {log}"), idx, t.xor2 * log as f64);
            }
        }
    }
    eff
}

/// The filter of `lanes` texels of encoding `texel` (two lerps in u, one in v per lane at the
/// weight bits `eff` when bilinear) and the cast into `out`, added to `g`. Shared with the
/// texture shaders' configured price.
pub(crate) fn filter_gates(
    g: &mut GateBudget,
    t: &CostTable,
    texel: &Encoding,
    lanes: u32,
    out: &Encoding,
    sampler: &Sampler,
    eff: [u32; 2],
) {
    let wt = texel.width();
    let wo = out.width();
    let bilinear = sampler.filter() == Filter::Bilinear;
    // the filtered value's width before the cast
    let mut vw = wt;
    if bilinear {
        let [eu, ev] = eff;
        // u: two lerps on the (wt + 1)-bit texel differences; the adds touch only the
        // bits above the product's fraction
        g.add(
            format!("u lerp subtractor {}", wt + 1),
            2 * lanes,
            t.adder(wt + 1),
        );
        g.add(
            format!("u lerp multiplier {}x{eu}", wt + 1),
            2 * lanes,
            t.multiplier(wt + 1, eu),
        );
        g.add(
            format!("u lerp adder {}", wt + 1),
            2 * lanes,
            t.adder(wt + 1),
        );
        let wu = wt + eu + 1;
        // (bot - top fits wu bits: both are convex combinations of texels, 2^eu apart)
        g.add(format!("v lerp subtractor {wu}"), lanes, t.adder(wu));
        g.add(
            format!("v lerp multiplier {wu}x{ev}"),
            lanes,
            t.multiplier(wu, ev),
        );
        g.add(format!("v lerp adder {wu}"), lanes, t.adder(wu));
        g.add(
            format!("weight register {}", eu + ev),
            1,
            t.register(eu + ev),
        );
        vw = wu + ev;
    }
    // the cast: the texel read's factor 2^n + 1 and a unit output's 2^m - 1 folded into
    // one constant whose signed digits are the shifts and adds (u8 into u8: 2^16 - 1, one
    // subtractor), the rounding riding on them for a unit output; the saturation where the
    // texel range exceeds the output's
    if bilinear || out != texel {
        let unit = |e: &Encoding| matches!(e.codec, Codec::UnitUnsigned | Codec::UnitSymmetric);
        let mut k = 1u128;
        if unit(texel) {
            k *= (1u128 << wt) + 1;
        }
        if unit(out) {
            k *= (1u128 << wo) - 1;
        }
        if k > 1 {
            g.add(format!("cast x{k} {vw}"), lanes, t.shift_add(vw, k));
        }
        let (tl, th) = (
            texel.decode(texel.format.min_raw()),
            texel.decode(texel.format.max_raw()),
        );
        let (ol, oh) = (
            out.decode(out.format.min_raw()),
            out.decode(out.format.max_raw()),
        );
        let clamp = if tl >= ol && th <= oh {
            0.0
        } else {
            t.clamp(wo)
        };
        let round = if unit(out) {
            0.0
        } else {
            t.half_adder * wo as f64
        };
        if round + clamp > 0.0 {
            g.add(format!("rounding and clamp {wo}"), lanes, round + clamp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Codec, Format};

    /// A fetch of a new texture `tex` with address mode `a` on both axes.
    #[allow(clippy::too_many_arguments)]
    fn fetch_at(
        uv: Encoding,
        tex: Texels,
        texel: Encoding,
        filter: Filter,
        weight_bits: u32,
        ports: u32,
        mem_latency: u32,
        out: Encoding,
        a: Address,
    ) -> Result<TexFetch, String> {
        let tex = Arc::new(Texture::new("t", texel, tex)?);
        let sampler = Sampler::new(filter, weight_bits)?.with_address(a, a);
        TexFetch::new(uv, tex, sampler, ports, mem_latency, out)
    }

    fn ramp(w: u32, h: u32) -> Texels {
        let values = (0..h)
            .flat_map(|j| (0..w).map(move |i| [i as f64 / w as f64, j as f64 / h as f64, 0.5, 0.0]))
            .collect();
        Texels {
            width: w,
            height: h,
            lanes: 3,
            values,
        }
    }

    /// A palette whose words the texture holds is priced by its contents when tables are
    /// ROMs (`table_of`), by its size otherwise; one whose words are unknown, by its size.
    #[test]
    fn a_known_palette_is_priced_by_its_contents_as_a_rom() {
        let uv = Encoding::fixed(Format::u(16, 16));
        let texel = Encoding::texel(Codec::UnitUnsigned, false, 8);
        // a 4-entry palette of 3 lanes: entry k is (k/3, 0, 1)
        let table: Vec<[f64; 4]> = (0..4).map(|k| [k as f64 / 3.0, 0.0, 1.0, 0.0]).collect();
        let values = (0..16).map(|i| table[i % 4]).collect();
        let tex = Texels {
            width: 4,
            height: 4,
            lanes: 3,
            values,
        };
        let t = Texture::new("t", texel, tex).unwrap();
        let sampler = Sampler::new(Filter::Nearest, 8).unwrap();
        let fetch = |t: Texture| TexFetch::new(uv, Arc::new(t), sampler, 1, 0, texel).unwrap();
        let known = fetch(t.clone().with_palette_table(4, &table));
        let sized = fetch(t.with_palette(4));
        // lane l's code in bits 8l..8l+8: (code(k/3), 0, 255)
        let words: Vec<i64> = (0..4).map(|k| (85 * k) | (255 << 16)).collect();
        assert_eq!(known.tex.palette_words().unwrap(), &words[..]);
        let rom = CostTable {
            tables: crate::gates::MemoryKind::Rom,
            ..CostTable::default()
        };
        let sram = CostTable::default();
        assert_eq!(known.gates(&rom).memory(), rom.rom_of(&words, 24));
        assert_ne!(rom.rom_of(&words, 24), rom.table(4, 24));
        assert_eq!(sized.gates(&rom).memory(), rom.table(4, 24));
        assert_eq!(known.gates(&sram).memory(), sram.table(4, 24));
        assert_eq!(sized.gates(&sram).memory(), sram.table(4, 24));
    }

    #[test]
    fn bit_accurate_bilinear_matches_exact_within_the_format_bound() {
        let uv = Encoding::fixed(Format::u(16, 16));
        let texel = Encoding::texel(Codec::UnitSigned, true, 8);
        let out = Encoding::fixed(Format::s(12, 10));
        let f = fetch_at(
            uv,
            ramp(8, 4),
            texel,
            Filter::Bilinear,
            8,
            4,
            2,
            out,
            Address::Wrap,
        )
        .unwrap();
        let mut ob = [Word::default()];
        let mut oe = [Word::default()];
        for k in 0..2000 {
            let (u, v) = (
                (k * 37 % 1000) as f64 / 1000.0,
                (k * 91 % 1000) as f64 / 1000.0,
            );
            let w = Word::quantize(&uv, &[u, v]);
            f.eval(Mode::BitAccurate, &[w], &mut ob);
            f.eval(Mode::Exact, &[w], &mut oe);
            for l in 0..3 {
                // texel rounding (1/256) + weight truncation (2^-8 of a texel step, away from the
                // wrap seam where the step is large) + output rounding
                let step = if l == 2 { 0.0 } else { 1.0 };
                let bound = texel.max_error() + step * 2f64.powi(-8) + out.max_error();
                let d = (ob[0].lanes[l].x - oe[0].lanes[l].x).abs();
                assert!(d <= bound + 1e-12, "k {k} lane {l}: {d} > {bound}");
            }
        }
    }

    #[test]
    fn signed_coordinates_match_exact_in_every_address_mode() {
        let uv = Encoding::fixed(Format::s(16, 12));
        let texel = Encoding::texel(Codec::UnitSigned, true, 8);
        let out = Encoding::fixed(Format::s(12, 10));
        for a in [Address::Wrap, Address::Clamp, Address::Mirror] {
            for filter in [Filter::Nearest, Filter::Bilinear] {
                let f = fetch_at(uv, ramp(8, 4), texel, filter, 8, 4, 2, out, a).unwrap();
                let (mut ob, mut oe) = ([Word::default()], [Word::default()]);
                for k in 0..1500 {
                    let (u, v) = (
                        (k * 37 % 3000) as f64 / 1000.0 - 1.5,
                        (k * 91 % 3000) as f64 / 1000.0 - 1.5,
                    );
                    // on the grid of the coordinate format, so both modes read one position
                    let w = Word::quantize(&uv, &[u, v]);
                    f.eval(Mode::BitAccurate, &[w], &mut ob);
                    f.eval(Mode::Exact, &[w], &mut oe);
                    for l in 0..3 {
                        let step = if l == 2 || filter == Filter::Nearest {
                            0.0
                        } else {
                            1.0
                        };
                        let bound = texel.max_error() + step * 2f64.powi(-8) + out.max_error();
                        let d = (ob[0].lanes[l].x - oe[0].lanes[l].x).abs();
                        assert!(d <= bound + 1e-12, "{a:?} {filter:?} k {k} lane {l}: {d}");
                    }
                }
            }
        }
        // clamp: u = 1 reads the last column and u = -0.3 the first; wrap: u = 1 reads the first
        let near = |a: Address, u: f64| {
            let f = fetch_at(uv, ramp(8, 4), texel, Filter::Nearest, 8, 1, 1, out, a).unwrap();
            let mut o = [Word::default()];
            f.eval(Mode::BitAccurate, &[Word::quantize(&uv, &[u, 0.1])], &mut o);
            o[0].lanes[0].x
        };
        assert!((near(Address::Clamp, 1.0) - 0.875).abs() < 0.01);
        assert!(near(Address::Clamp, -0.3).abs() < 0.01);
        assert!(near(Address::Wrap, 1.0).abs() < 0.01);
        assert!((near(Address::Mirror, -0.01) - 0.0).abs() < 0.01);
        assert!((near(Address::Mirror, 1.01) - 0.875).abs() < 0.01);
    }

    #[test]
    fn nearest_reads_the_texel_under_the_coordinate() {
        let uv = Encoding::fixed(Format::u(12, 12));
        let texel = Encoding::fixed(Format::s(10, 8));
        let out = texel;
        let f = fetch_at(
            uv,
            ramp(8, 4),
            texel,
            Filter::Nearest,
            8,
            1,
            3,
            out,
            Address::Wrap,
        )
        .unwrap();
        assert_eq!((f.interval(), f.latency()), (1, 4));
        let mut o = [Word::default()];
        // u = 0.40 -> texel 3 (0.375), v = 0.9 -> row 3 (0.75)
        f.eval(
            Mode::BitAccurate,
            &[Word::quantize(&uv, &[0.40, 0.90])],
            &mut o,
        );
        assert_eq!(o[0].raws::<3>(), [96, 192, 128]);
        assert_eq!(f.textures()[0].texture.bits_per_texel(), 30);
    }

    #[test]
    fn the_budget_prices_the_weight_bits_that_are_not_zero_and_the_cast_by_overlap() {
        let t = CostTable::default();
        // x 257 of 17 bits: the copies overlap over 9 bits; x (2^16 - 1) of 13 bits: not at all
        let fa = t.full_adder;
        assert!((t.shift_add(17, 257) - (9.0 * fa + 8.0 * t.half_adder)).abs() < 1e-9);
        assert!((t.shift_add(13, 65535) - 13.0 * t.half_adder).abs() < 1e-9);
        assert_eq!(t.shift_add(13, 1), 0.0);
        // u4.12 on 8 x 4 texels: 9 and 10 fraction bits below the texel, weights of 8 bits
        // carry all 8; on a 256 x 256 texture only 4 of a u4.12 coordinate's bits remain
        let uv = Encoding::fixed(Format::u(16, 12));
        let texel = Encoding::texel(Codec::UnitSigned, true, 8);
        let out = Encoding::fixed(Format::s(12, 10));
        let what = |w: u32, h: u32| {
            let f = fetch_at(
                uv,
                ramp(w, h),
                texel,
                Filter::Bilinear,
                8,
                4,
                2,
                out,
                Address::Wrap,
            );
            let g = f.unwrap().gates(&t);
            g.items.iter().map(|i| i.what.clone()).collect::<Vec<_>>()
        };
        assert!(what(8, 4).contains(&"u lerp multiplier 9x8".to_string()));
        assert!(what(256, 256).contains(&"u lerp multiplier 9x4".to_string()));
        assert!(what(256, 256).contains(&"weight register 8".to_string()));
    }

    #[test]
    fn bad_parameters_are_rejected() {
        let uv = Encoding::fixed(Format::u(16, 16));
        let t = Encoding::fixed(Format::s(8, 6));
        assert!(fetch_at(
            uv,
            ramp(6, 4),
            t,
            Filter::Nearest,
            8,
            1,
            1,
            t,
            Address::Wrap
        )
        .err()
        .unwrap()
        .contains("power of two"));
        let uv_short = Encoding::fixed(Format::u(4, 3));
        assert!(fetch_at(
            uv_short,
            ramp(8, 4),
            t,
            Filter::Nearest,
            8,
            1,
            1,
            t,
            Address::Wrap
        )
        .err()
        .unwrap()
        .contains("fraction bits"));
        assert!(fetch_at(
            uv,
            ramp(8, 4),
            t,
            Filter::Bilinear,
            0,
            1,
            1,
            t,
            Address::Wrap
        )
        .is_err());
    }
}

//! Quantized normal maps fetch: the index texture, its nearest fetch and the paletted
//! lookup of the per-frame colour table, as one unit.
//!
//! Tarini, Cignoni, Rocchini, Scopigno, "Real Time, Accurate, Multi-Featured Rendering of Bump
//! Mapped Surfaces", §3–5: the normal map is stored as an index texture into a table `N` of
//! `s_N` normals; per frame the builder ([`PaletteBuilder`]) shades `N` into the colour table
//! `C` (§5.1) which is loaded into the paletted-texture lookup ([`PaletteLut`]); per fragment
//! the index texel under the coordinate is read (nearest: indices cannot be filtered, §5.2) and
//! translated into an RGBA colour.
//!
//! * Port `uv`: 2 lanes (the wired encoding). Outputs `c`: 4 lanes RGBA of the entry encoding,
//!   and `color`: its first 3 lanes (RGB) for the frame buffer.
//! * The index texture is a [`Texture`] of 1-lane texels holding the index value in an
//!   unsigned integer `Fixed` word of `index_bits` bits, with its mip levels, read by a
//!   [`TexFetch`] with nearest filtering and 1 port.
//! * Latency: the fetch's latency plus the LUT's 2; interval 1.
//! * [`Unit::frame_cycles`] = builder [`PaletteBuilder::cycles_per_frame`] + LUT load
//!   (`ceil(entries / load_width)`); neither depends on the texture size.
//! * [`Unit::gates`] = builder + LUT + the index fetch's address logic, as `rtl::quantized`
//!   builds them: the index goes straight into the LUT's index register (no fetch output
//!   register) and, the texture holding no index beyond the table, the LUT has no range
//!   compare.
//! * [`Unit::textures`]: the index texture, `index_bits` per texel, one read per fragment.
//! * Exact mode reads the builder's f64 table; bit-accurate mode the builder's words.

use crate::format::{Encoding, Format};
use crate::frame::FrameInputs;
use crate::gates::{CostTable, GateBudget};
use crate::sampler::{Filter, Sampler};
use crate::texture::{Texels, Texture};
use crate::unit::{Mode, PortSpec, TextureRead, Unit, Word};
use crate::units::fetch::TexFetch;
use crate::units::palette_builder::PaletteBuilder;
use crate::units::palette_lut::{PaletteLut, MAX_INDEX_BITS};
use std::sync::Arc;

pub struct QuantizedFetch {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    fetch: TexFetch,
    /// The LUT loaded with the exact table (exact mode) and with the words (bit-accurate).
    lut_exact: PaletteLut,
    lut_bits: PaletteLut,
    builder: PaletteBuilder,
    index_bits: u32,
}

impl QuantizedFetch {
    /// `name`: the index texture's name in the texture memory; `uv`: the coordinate
    /// encoding; `width` x `height` `indices` (row-major, row 0 at v in
    /// [0, 1/height)) into the builder's table; `index_bits` 8 to
    /// [`MAX_INDEX_BITS`] (the table must fit);
    /// `load_width`: LUT entries written per clock; `mem_latency`: clocks of the index read.
    /// Errors name the parameter and what was expected.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        name: &str,
        uv: Encoding,
        width: u32,
        height: u32,
        indices: &[u32],
        index_bits: u32,
        builder: PaletteBuilder,
        load_width: u32,
        mem_latency: u32,
    ) -> Result<Self, String> {
        if !(8..=MAX_INDEX_BITS).contains(&index_bits) {
            return Err(format!(
                "index_bits {index_bits}: expected 8 to {MAX_INDEX_BITS}"
            ));
        }
        let n = builder.entries();
        if n > 1usize << index_bits {
            return Err(format!(
                "table of {n} entries: expected at most 2^{index_bits} = {} for index_bits {index_bits}",
                1usize << index_bits
            ));
        }
        if let Some(i) = indices.iter().find(|&&i| i as usize >= n) {
            return Err(format!("index {i} out of range for a table of {n} entries"));
        }
        let idx = Encoding::fixed(Format::u(index_bits as u8, 0));
        let tex = Texels {
            width,
            height,
            lanes: 1,
            values: indices.iter().map(|&i| [i as f64, 0.0, 0.0, 0.0]).collect(),
        };
        let tex = Arc::new(Texture::new(name, idx, tex)?);
        let nearest = Sampler::new(Filter::Nearest, 8)?;
        let fetch = TexFetch::new(uv, tex, nearest, 1, mem_latency, idx)?;
        let entry = builder.formats().entry;
        let lut_exact = PaletteLut::new(idx, entry, builder.build_exact(), load_width)?;
        let mut lut_bits = PaletteLut::new(idx, entry, vec![[0.0; 4]; n], load_width)?;
        lut_bits.load(builder.build(Mode::BitAccurate))?;
        Ok(QuantizedFetch {
            inputs: vec![PortSpec::new("uv", 2, uv)],
            outputs: vec![
                PortSpec::new("c", 4, entry),
                PortSpec::new("color", 3, entry),
            ],
            fetch,
            lut_exact,
            lut_bits,
            builder,
            index_bits,
        })
    }

    /// Add index mipmap levels 1.. (`(width, height, indices)` each, coarsest last, built by
    /// the host: Tarini §5.2) and a 1-lane `lod` input of encoding `lod`. Per fragment the
    /// level `clamp(floor(lod + 1/2), 0, levels)` is fetched nearest (GL's
    /// `NEAREST_MIPMAP_NEAREST`); level 0 is the texture given to [`QuantizedFetch::new`].
    pub fn with_mipmaps(
        mut self,
        lod: Encoding,
        levels: Vec<(u32, u32, Vec<u32>)>,
    ) -> Result<Self, String> {
        lod.validate()?;
        let n = self.builder.entries();
        let idx = Encoding::fixed(Format::u(self.index_bits as u8, 0));
        let mut mips = Vec::new();
        for (k, (w, h, indices)) in levels.into_iter().enumerate() {
            if let Some(i) = indices.iter().find(|&&i| i as usize >= n) {
                return Err(format!(
                    "mip level {}: index {i} out of range for a table of {n} entries",
                    k + 1
                ));
            }
            mips.push(Texels {
                width: w,
                height: h,
                lanes: 1,
                values: indices.iter().map(|&i| [i as f64, 0.0, 0.0, 0.0]).collect(),
            });
        }
        let tex = Arc::new(Texture::clone(self.fetch.texture()).with_mips(mips)?);
        let uv = self.inputs[0].enc;
        let nearest = Sampler::new(Filter::Nearest, 8)?;
        self.fetch = TexFetch::new(uv, tex, nearest, 1, self.fetch.mem_latency(), idx)?;
        self.inputs.push(PortSpec::new("lod", 1, lod));
        Ok(self)
    }

    /// Mip levels including level 0.
    pub fn levels(&self) -> usize {
        self.fetch.texture().levels()
    }

    /// The index texture's nearest fetch.
    pub fn index_fetch(&self) -> &TexFetch {
        &self.fetch
    }
    pub fn builder(&self) -> &PaletteBuilder {
        &self.builder
    }
    /// The LUT as loaded for `mode`.
    pub fn lut(&self, mode: Mode) -> &PaletteLut {
        match mode {
            Mode::Exact => &self.lut_exact,
            Mode::BitAccurate => &self.lut_bits,
        }
    }
}

impl Unit for QuantizedFetch {
    fn kind(&self) -> &'static str {
        "quantized_fetch"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        self.fetch.latency() + self.lut_bits.latency()
    }
    fn interval(&self) -> u32 {
        1
    }
    fn textures(&self) -> Vec<TextureRead> {
        self.fetch.textures()
    }
    fn frame_reads(&self) -> Vec<crate::unit::FrameRead> {
        self.builder.frame_reads()
    }
    fn upload(&mut self, old: &Arc<Texture>, new: &Arc<Texture>) {
        self.fetch.upload(old, new);
    }
    /// The builder takes the frame ([`PaletteBuilder::begin_frame`]) and the LUT is loaded
    /// with the table it builds, in both modes.
    fn begin_frame(&mut self, f: &FrameInputs) -> Result<(), String> {
        self.builder.begin_frame(f)?;
        self.lut_exact.set_values(self.builder.build_exact())?;
        self.lut_bits.load(self.builder.build(Mode::BitAccurate))
    }
    fn frame_cycles(&self) -> u64 {
        self.builder.cycles_per_frame() + self.lut_bits.frame_cycles()
    }
    /// The builder's clocks first (no writes), then the LUT load: entry `k` written at
    /// clock `builder + k / load_width`, as the `c` (RGBA) and `color` (RGB) words.
    fn frame_writes(&self) -> Vec<(u64, u64, Vec<Word>)> {
        let start = self.builder.cycles_per_frame();
        let per_clock = self.lut_bits.load_width() as u64;
        let enc = self.builder.formats().entry;
        self.lut_bits
            .table()
            .codes
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let rgba = Word::from_raw(&enc, c);
                let rgb = Word::from_raw(&enc, &c[..3]);
                (start + k as u64 / per_clock, k as u64, vec![rgba, rgb])
            })
            .collect()
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let mut g = GateBudget::new();
        // the index word goes straight into the LUT's index register: the fetch has no
        // output register of its own (`rtl::quantized`)
        let mut fetch = self.fetch.gates(t);
        fetch
            .items
            .retain(|i| !i.what.starts_with("output register"));
        // no index of the texture reaches beyond the table (checked in `new`): no range compare
        let mut lut = self.lut_bits.gates(t);
        lut.items.retain(|i| {
            !i.what.starts_with("index range compare") && !i.what.starts_with("output gating")
        });
        for (who, part) in [
            ("builder", self.builder.gates(t)),
            ("lut", lut),
            ("index fetch", fetch),
        ] {
            g.add_part(&format!("{who}: "), 1, part);
        }
        if let Some(lod) = self.inputs.get(1) {
            // as `rtl::quantized` builds it: the LOD rounded to an integer (a carry chain over
            // its integer bits) and clamped to the levels; per level the texel's offset in the
            // level (the coordinates' top bits: the index texture wraps), selected by the
            // level bit by bit; the level's base address (constants, a decode of the level)
            // added to it
            let tex = self.fetch.texture();
            let levels = self.levels() as u32;
            let lf = lod.enc.format.frac as u32;
            let wr = lod.enc.width().saturating_sub(lf) + 1;
            g.add(
                format!("mip level round and clamp {wr}"),
                1,
                t.constant_add(wr) + t.clamp(wr),
            );
            let bits: Vec<u32> = (0..levels as usize)
                .map(|l| {
                    let (w, h) = tex.level_at(l).logs();
                    w + h
                })
                .collect();
            let texels: u64 = (0..levels as usize)
                .map(|l| {
                    let lv = tex.level_at(l);
                    lv.width() as u64 * lv.height() as u64
                })
                .sum();
            let abits = (64 - texels.saturating_sub(1).leading_zeros()).max(1);
            let select: f64 = (0..abits)
                .map(|k| t.mux(1, bits.iter().filter(|&&b| b > k).count() as u32))
                .sum();
            g.add(format!("mip offset select {abits}"), 1, select);
            let lb = 32 - (levels - 1).leading_zeros();
            g.add(format!("mip base select {abits}"), 1, t.decoder(levels, lb));
            g.add(format!("mip base adder {abits}"), 1, t.adder(abits));
        }
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let level = match ins.get(1) {
            Some(lod) if self.levels() > 1 => {
                let x = match mode {
                    Mode::Exact => lod.lanes[0].x,
                    Mode::BitAccurate => self.inputs[1].enc.decode(lod.lanes[0].raw),
                };
                self.fetch.texture().nearest_level(x)
            }
            _ => 0,
        };
        let i = [self.fetch.sample(mode, level, &ins[0])];
        let mut c = [Word::default()];
        match mode {
            Mode::Exact => self.lut_exact.eval(mode, &i, &mut c),
            Mode::BitAccurate => self.lut_bits.eval(mode, &i, &mut c),
        }
        let mut rgb = c[0];
        rgb.lanes[3] = Default::default();
        outs[0] = c[0];
        outs[1] = rgb;
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::format::Codec;
    use crate::units::palette_builder::{BuilderFormats, LightingFn};
    use crate::units::specgen::SpecGen;

    fn formats() -> BuilderFormats {
        BuilderFormats {
            normal: Encoding::fixed(Format::s(12, 10)),
            vector: Encoding::fixed(Format::s(12, 10)),
            intensity: Encoding::texel(Codec::UnitUnsigned, false, 10),
            power: SpecGen::Table {
                index_bits: 10,
                value_bits: 12,
            },
            entry: Encoding::texel(Codec::UnitUnsigned, false, 8),
            sphere: Default::default(),
        }
    }
    /// `n` normals spread over the upper hemisphere (a golden-angle spiral).
    pub(crate) fn normals(n: usize) -> Vec<[f64; 3]> {
        (0..n)
            .map(|k| {
                let a = k as f64 * 2.399963;
                let z = 1.0 - (k as f64 + 0.5) / n as f64;
                let r = (1.0 - z * z).sqrt();
                [r * a.cos(), r * a.sin(), z]
            })
            .collect()
    }
    fn specular() -> LightingFn {
        LightingFn::Specular {
            ambient: [0.1; 3],
            diffuse: [0.6, 0.5, 0.4],
            specular: [0.3; 3],
            shininess: 16.0,
            view: [0.0, 0.2, 1.0],
            lights: vec![([0.4, 0.5, 1.0], [1.0; 3])],
        }
    }
    fn unit(n: usize, size: u32, bits: u32, load: u32) -> QuantizedFetch {
        let b = PaletteBuilder::single(normals(n), specular(), formats(), 1).unwrap();
        let idx: Vec<u32> = (0..size * size).map(|k| k * 7 % n as u32).collect();
        let uv = Encoding::fixed(Format::u(16, 12));
        QuantizedFetch::new("indices", uv, size, size, &idx, bits, b, load, 3).unwrap()
    }

    #[test]
    fn quantized_fetch_mipmaps_pick_the_rounded_level() {
        // 4x4 level 0 of index 0, 2x2 level 1 of index 1, 1x1 level 2 of index 2
        let b = PaletteBuilder::single(normals(8), specular(), formats(), 1).unwrap();
        let uv = Encoding::fixed(Format::u(16, 12));
        let lod = Encoding::fixed(Format::u(8, 4));
        let mut u = QuantizedFetch::new("indices", uv, 4, 4, &[0; 16], 8, b, 1, 3)
            .unwrap()
            .with_mipmaps(lod, vec![(2, 2, vec![1; 4]), (1, 1, vec![2])])
            .unwrap();
        assert_eq!((u.levels(), u.inputs().len()), (3, 2));
        let codes = u.builder().build(Mode::BitAccurate).codes;
        let at = |u: &mut QuantizedFetch, mode: Mode, l: f64| {
            let ins = [
                Word::quantize(&uv, &[0.3, 0.6]),
                Word::for_mode(mode, &lod, &[l]),
            ];
            let mut o = [Word::default(); 2];
            u.eval(mode, &ins, &mut o);
            let c = o[0].raws::<4>();
            codes.iter().position(|e| *e == c).unwrap()
        };
        for (l, want) in [
            (0.0, 0),
            (0.4375, 0),
            (0.5, 1),
            (1.4375, 1),
            (1.5, 2),
            (9.0, 2),
        ] {
            assert_eq!(at(&mut u, Mode::BitAccurate, l), want, "lod {l}");
        }
        // exact mode rounds the exact LOD: 0.49 stays on level 0
        let exact = u.lut(Mode::Exact).table().values.clone();
        let ins = [
            Word::quantize(&uv, &[0.3, 0.6]),
            Word::for_mode(Mode::Exact, &lod, &[0.49]),
        ];
        let mut o = [Word::default(); 2];
        u.eval(Mode::Exact, &ins, &mut o);
        assert_eq!(o[0].xs::<4>(), exact[0]);
        // an index outside the table is refused
        let b = PaletteBuilder::single(normals(8), specular(), formats(), 1).unwrap();
        let err = QuantizedFetch::new("indices", uv, 4, 4, &[0; 16], 8, b, 1, 3)
            .unwrap()
            .with_mipmaps(lod, vec![(2, 2, vec![8; 4])])
            .err()
            .unwrap();
        assert!(
            err.contains("mip level 1") && err.contains("index 8"),
            "{err}"
        );
        // the level select costs gates
        let plain = unit(8, 4, 8, 1).gates(&CostTable::default()).total();
        assert!(u.gates(&CostTable::default()).total() > plain);
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn quantized_fetch_exact_and_bit_accurate_agree_within_the_entry_bound() {
        let u = unit(256, 16, 8, 1);
        let uv = Encoding::fixed(Format::u(16, 12));
        let exact = u.builder().build_exact();
        let words = u.builder().build(Mode::BitAccurate);
        // the builder's derived bound for Blinn-Phong with one light (as in the
        // palette_builder tests); the fetch and the LUT add nothing
        let f = formats();
        let (en, ev) = (f.normal.max_error(), f.vector.max_error());
        let edot = 3f64.sqrt() * (en + ev) + 3.0 * en * ev;
        let ei = f.intensity.max_error() + (-2.0 * f.intensity.width() as f64).exp2();
        let ecoef = f.entry.max_error() + (-2.0 * f.entry.width() as f64).exp2();
        let term = |dx: f64| ecoef + dx + ecoef * dx;
        let gen = crate::units::SpecularGenerator::new(f.power, 16.0, f.intensity).unwrap();
        let epow = gen.error_bound() + 16.0 * (edot + f.intensity.max_error());
        let bound = ecoef + term(term(edot + ei)) + term(term(epow)) + f.entry.max_error();
        let mut worst: f64 = 0.0;
        for k in 0..1000u32 {
            let (s, t) = (
                (k * 37 % 1000) as f64 / 1000.0,
                (k * 91 % 1000) as f64 / 1000.0,
            );
            let w = Word::quantize(&uv, &[s, t]);
            let (mut e, mut b) = ([Word::default(); 2], [Word::default(); 2]);
            u.eval(Mode::Exact, &[w], &mut e);
            u.eval(Mode::BitAccurate, &[w], &mut b);
            let (i, j) = ((w.lanes[0].x * 16.0) as u32, (w.lanes[1].x * 16.0) as u32);
            let index = ((j * 16 + i) * 7 % 256) as usize;
            for l in 0..4 {
                assert_eq!(e[0].lanes[l].x, exact[index][l]);
                assert_eq!(b[0].lanes[l].raw, words.codes[index][l]);
                let d = (e[0].lanes[l].x - b[0].lanes[l].x).abs();
                worst = worst.max(d);
                assert!(d <= bound, "{k} {l}: {d} > {bound}");
            }
            for l in 0..3 {
                assert_eq!(b[1].lanes[l], b[0].lanes[l]);
                assert_eq!(e[1].lanes[l], e[0].lanes[l]);
            }
            assert_eq!(b[0].lanes[3].raw, 255);
        }
        println!("worst {worst:.5} bound {bound:.5}");
    }

    #[test]
    fn quantized_fetch_frame_cycles_are_builder_plus_load_and_ignore_texture_size() {
        for (n, bits, load) in [(256usize, 8u32, 1u32), (2048, 11, 4), (16, 8, 2)] {
            let u = unit(n, 32, bits, load);
            let b = PaletteBuilder::single(normals(n), specular(), formats(), 1).unwrap();
            // specular, one light: 2 cycles per entry
            assert_eq!(b.cycles_per_frame(), 2 * n as u64);
            assert_eq!(
                u.frame_cycles(),
                b.cycles_per_frame() + (n as u64).div_ceil(load as u64)
            );
            assert_eq!(u.frame_cycles(), unit(n, 128, bits, load).frame_cycles());
            assert_eq!(u.textures()[0].texture.bits_per_texel(), bits);
            // builder + LUT without its range compare + the fetch without its output register
            let t = CostTable::default();
            let part = |g: GateBudget, gone: &[&str]| -> f64 {
                g.items
                    .iter()
                    .filter(|i| !gone.iter().any(|w| i.what.starts_with(w)))
                    .map(|i| i.ge)
                    .sum()
            };
            let lut = part(
                u.lut(Mode::BitAccurate).gates(&t),
                &["index range compare", "output gating"],
            );
            let fetch = part(u.index_fetch().gates(&t), &["output register"]);
            let want = b.gates(&t).total() + lut + fetch;
            assert!((u.gates(&t).total() - want).abs() < 1e-6, "{n}");
            assert!(fetch > 0.0 && lut < u.lut(Mode::BitAccurate).gates(&t).total() + 1e-9);
        }
    }

    #[test]
    fn quantized_fetch_rejects_bad_parameters() {
        let uv = Encoding::fixed(Format::u(16, 12));
        let b = || PaletteBuilder::single(normals(300), specular(), formats(), 1).unwrap();
        assert!(QuantizedFetch::new("indices", uv, 4, 4, &[0; 16], 8, b(), 1, 1).is_err());
        assert!(QuantizedFetch::new("indices", uv, 4, 4, &[0; 16], 17, b(), 1, 1).is_err());
        assert!(QuantizedFetch::new("indices", uv, 4, 4, &[0; 16], 16, b(), 1, 1).is_ok());
        assert!(QuantizedFetch::new("indices", uv, 4, 4, &[300; 16], 9, b(), 1, 1).is_err());
        assert!(QuantizedFetch::new("indices", uv, 4, 4, &[299; 16], 9, b(), 1, 1).is_ok());
    }
}

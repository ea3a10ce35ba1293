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

use crate::arith::Acc;
use crate::format::Encoding;
use crate::gates::{CostTable, GateBudget};
use crate::sampler::texel_axis;
pub use crate::sampler::Address;
use crate::unit::{Mode, PortSpec, Unit, Word, MAX_LANES};

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, Default)]
pub enum Filter {
    Nearest,
    #[default]
    Bilinear,
}

/// Texture contents: `width * height` texels of `lanes` real values each, row-major, row 0
/// at v in [0, 1/height).
#[derive(Debug, Clone)]
pub struct Texels {
    pub width: u32,
    pub height: u32,
    pub lanes: u8,
    pub values: Vec<[f64; MAX_LANES]>,
}

pub struct TexFetch {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    texel: Encoding,
    filter: Filter,
    weight_bits: u32,
    ports: u32,
    mem_latency: u32,
    tex: Texels,
    codes: Vec<[i64; MAX_LANES]>,
    log_w: u32,
    log_h: u32,
    palette: Option<u32>,
    address: [Address; 2],
}

impl TexFetch {
    /// Address modes along u and v (default wrap on both).
    pub fn with_address(mut self, u: Address, v: Address) -> Self {
        self.address = [u, v];
        self
    }

    /// Store the texture as indices into a palette of `entries` texels (Ernst et al. §6:
    /// "The memory requirements for the bump maps can be minimized by using palletized bumps.
    /// With eight bit addressing a table lookup (bump) texture, up to 256 surface orientations
    /// can be modeled."). The texels given to [`TexFetch::new`] must already be palette
    /// entries; the unit then counts `ceil(log2 entries)` bits per stored texel and adds the
    /// palette RAM (entries x lanes x texel bits, loaded once per frame) to its gates and its
    /// per-frame cycles. Filtering happens after the palette lookup (one lookup per tap).
    pub fn with_palette(mut self, entries: u32) -> Self {
        self.palette = Some(entries.max(1));
        self
    }

    /// Errors name the parameter and what was expected.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        uv: Encoding,
        tex: Texels,
        texel: Encoding,
        filter: Filter,
        weight_bits: u32,
        ports: u32,
        mem_latency: u32,
        out: Encoding,
    ) -> Result<Self, String> {
        for (name, v) in [("width", tex.width), ("height", tex.height)] {
            if !v.is_power_of_two() || v > 1 << 14 {
                return Err(format!(
                    "texture {name} {v}: expected a power of two from 1 to 16384"
                ));
            }
        }
        if !(1..=16).contains(&weight_bits) {
            return Err(format!("weight_bits {weight_bits}: expected 1 to 16"));
        }
        if !(1..=4).contains(&ports) {
            return Err(format!("ports {ports}: expected 1 to 4"));
        }
        if tex.values.len() != (tex.width * tex.height) as usize {
            return Err("texel count does not match the texture size".into());
        }
        let log_w = tex.width.trailing_zeros();
        let log_h = tex.height.trailing_zeros();
        if (uv.format.frac as u32) < log_w.max(log_h) + 1 {
            return Err(format!(
                "texture coordinate format {} has too few fraction bits for a {}x{} texture: expected at least {}",
                uv.format, tex.width, tex.height, log_w.max(log_h) + 1
            ));
        }
        let lanes = tex.lanes;
        let codes = tex
            .values
            .iter()
            .map(|t| {
                std::array::from_fn(|l| {
                    if l < lanes as usize {
                        texel.encode(t[l])
                    } else {
                        0
                    }
                })
            })
            .collect();
        Ok(TexFetch {
            inputs: vec![PortSpec::new("uv", 2, uv)],
            outputs: vec![PortSpec::new("t", lanes, out)],
            texel,
            filter,
            weight_bits,
            ports,
            mem_latency: mem_latency.max(1),
            tex,
            codes,
            log_w,
            log_h,
            palette: None,
            address: [Address::Wrap; 2],
        })
    }

    fn taps(&self) -> u32 {
        match self.filter {
            Filter::Nearest => 1,
            Filter::Bilinear => 4,
        }
    }

    /// Index of texel (i, j) after addressing.
    fn texel_index(&self, i: i64, j: i64) -> usize {
        let (w, h) = (self.tex.width as i64, self.tex.height as i64);
        (self.address[1].apply(j, h) * w + self.address[0].apply(i, w)) as usize
    }

    fn axis(&self, raw: i64, frac: u32, log: u32) -> (i64, i64) {
        texel_axis(raw, frac, log, self.filter == Filter::Bilinear)
    }

    fn eval_exact(&self, u: f64, v: f64) -> [f64; MAX_LANES] {
        let (w, h) = (self.tex.width as f64, self.tex.height as f64);
        let get = |i: i64, j: i64| self.tex.values[self.texel_index(i, j)];
        match self.filter {
            Filter::Nearest => get((u * w).floor() as i64, (v * h).floor() as i64),
            Filter::Bilinear => {
                let (su, sv) = (u * w - 0.5, v * h - 0.5);
                let (i, j) = (su.floor(), sv.floor());
                let (fu, fv) = (su - i, sv - j);
                let (i, j) = (i as i64, j as i64);
                let (t00, t10, t01, t11) =
                    (get(i, j), get(i + 1, j), get(i, j + 1), get(i + 1, j + 1));
                std::array::from_fn(|l| {
                    let top = t00[l] + (t10[l] - t00[l]) * fu;
                    let bot = t01[l] + (t11[l] - t01[l]) * fu;
                    top + (bot - top) * fv
                })
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
        self.mem_latency + self.interval() + u32::from(self.filter == Filter::Bilinear)
    }
    fn interval(&self) -> u32 {
        self.taps().div_ceil(self.ports)
    }
    fn texel_bits(&self) -> Option<u32> {
        Some(match self.palette {
            Some(n) => n.next_power_of_two().trailing_zeros().max(1),
            None => self.tex.lanes as u32 * self.texel.width(),
        })
    }
    fn frame_cycles(&self) -> u64 {
        self.palette.map_or(0, u64::from)
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let wc = self.inputs[0].enc.width();
        let wt = self.texel.width();
        let wb = self.weight_bits;
        let lanes = self.tex.lanes as u32;
        let wo = self.outputs[0].enc.width();
        let mut g = GateBudget::new();
        g.add(format!("address adder {wc}"), 2 * self.ports, t.adder(wc));
        if self.filter == Filter::Bilinear {
            // three lerps per lane, a + (b - a) w: two along u on (wt + 1)-bit differences,
            // one along v on the exact (wt + wb + 1)-bit results of the first two
            g.add(
                format!("u lerp multiplier {}x{wb}", wt + 1),
                2 * lanes,
                t.multiplier(wt + 1, wb),
            );
            g.add(
                format!("v lerp multiplier {}x{wb}", wt + wb + 1),
                lanes,
                t.multiplier(wt + wb + 1, wb),
            );
            g.add(
                format!("u lerp adders {}", wt + wb + 1),
                4 * lanes,
                t.adder(wt + wb + 1),
            );
            g.add(
                format!("v lerp adders {}", wt + 2 * wb + 1),
                2 * lanes,
                t.adder(wt + 2 * wb + 1),
            );
            g.add(format!("weight register {}", 2 * wb), 1, t.register(2 * wb));
        }
        if self.interval() > 1 {
            g.add(
                format!("tap register {}", wt * lanes),
                self.taps(),
                t.register(wt * lanes),
            );
        }
        g.add(
            format!("output register {}", wo * lanes),
            1,
            t.register(wo * lanes),
        );
        if let Some(n) = self.palette {
            g.add(
                format!("bump palette {n}x{} (loadable)", wt * lanes),
                self.ports,
                t.sram(n as u64, wt * lanes),
            );
        }
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.outputs[0].enc;
        let lanes = self.tex.lanes as usize;
        let uv = &ins[0];
        match mode {
            Mode::Exact => {
                let v = self.eval_exact(uv.lanes[0].x, uv.lanes[1].x);
                outs[0] = Word::from_exact(&out, &v[..lanes]);
            }
            Mode::BitAccurate => {
                let frac = self.inputs[0].enc.format.frac as u32;
                let (i, fu) = self.axis(uv.lanes[0].raw, frac, self.log_w);
                let (j, fv) = self.axis(uv.lanes[1].raw, frac, self.log_h);
                let code = |t: usize, l: usize| Acc::from_code(self.codes[t][l], &self.texel);
                let mut res = [0i64; MAX_LANES];
                match self.filter {
                    Filter::Nearest => {
                        let t = self.texel_index(i, j);
                        for (l, r) in res.iter_mut().enumerate().take(lanes) {
                            *r = code(t, l).to_code(&out);
                        }
                    }
                    Filter::Bilinear => {
                        // weights truncated to weight_bits of the coordinate fraction
                        let fu_bits = frac - self.log_w;
                        let fv_bits = frac - self.log_h;
                        let wb = self.weight_bits;
                        let trunc = |f: i64, bits: u32| {
                            if bits >= wb {
                                f >> (bits - wb)
                            } else {
                                f << (wb - bits)
                            }
                        };
                        let (wu, wv) = (
                            Acc::new(trunc(fu, fu_bits) as i128, wb),
                            Acc::new(trunc(fv, fv_bits) as i128, wb),
                        );
                        let one = Acc::new(1, 0);
                        let [t00, t10, t01, t11] = [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)]
                            .map(|(a, b)| self.texel_index(a, b));
                        for (l, r) in res.iter_mut().enumerate().take(lanes) {
                            let lerp = |a: Acc, b: Acc, w: Acc| a.mul(one.sub(w)).add(b.mul(w));
                            let top = lerp(code(t00, l), code(t10, l), wu);
                            let bot = lerp(code(t01, l), code(t11, l), wu);
                            *r = lerp(top, bot, wv).to_code(&out);
                        }
                    }
                }
                outs[0] = Word::from_raw(&out, &res[..lanes]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Codec, Format};

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

    #[test]
    fn bit_accurate_bilinear_matches_exact_within_the_format_bound() {
        let uv = Encoding::fixed(Format::u(16, 16));
        let texel = Encoding::texel(Codec::UnitSigned, true, 8);
        let out = Encoding::fixed(Format::s(12, 10));
        let f = TexFetch::new(uv, ramp(8, 4), texel, Filter::Bilinear, 8, 4, 2, out).unwrap();
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
                let f = TexFetch::new(uv, ramp(8, 4), texel, filter, 8, 4, 2, out)
                    .unwrap()
                    .with_address(a, a);
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
            let f = TexFetch::new(uv, ramp(8, 4), texel, Filter::Nearest, 8, 1, 1, out)
                .unwrap()
                .with_address(a, a);
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
        let f = TexFetch::new(uv, ramp(8, 4), texel, Filter::Nearest, 8, 1, 3, out).unwrap();
        assert_eq!((f.interval(), f.latency()), (1, 4));
        let mut o = [Word::default()];
        // u = 0.40 -> texel 3 (0.375), v = 0.9 -> row 3 (0.75)
        f.eval(
            Mode::BitAccurate,
            &[Word::quantize(&uv, &[0.40, 0.90])],
            &mut o,
        );
        assert_eq!(o[0].raws::<3>(), [96, 192, 128]);
        assert_eq!(f.texel_bits(), Some(30));
    }

    #[test]
    fn bad_parameters_are_rejected() {
        let uv = Encoding::fixed(Format::u(16, 16));
        let t = Encoding::fixed(Format::s(8, 6));
        assert!(
            TexFetch::new(uv, ramp(6, 4), t, Filter::Nearest, 8, 1, 1, t)
                .err()
                .unwrap()
                .contains("power of two")
        );
        let uv_short = Encoding::fixed(Format::u(4, 3));
        assert!(
            TexFetch::new(uv_short, ramp(8, 4), t, Filter::Nearest, 8, 1, 1, t)
                .err()
                .unwrap()
                .contains("fraction bits")
        );
        assert!(TexFetch::new(uv, ramp(8, 4), t, Filter::Bilinear, 0, 1, 1, t).is_err());
    }
}

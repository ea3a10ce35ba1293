//! Emboss filter unit: Schlag's 3x3 gradient masks over a height texture.
//!
//! Lingard (1995), "An Example: Embossing", after Schlag, Graphics Gems IV VIII.1: the height
//! image `i(u, v)` is a surface `P = [u v i]` with normal `[-i_u, -i_v, 1]`; the derivatives are
//! estimated by the 3x3 masks `i_u = [-1 0 1]` (each of three rows) and `i_v` (three columns,
//! `+1` on the `+v` side), and the masks' response (6a for a ramp `i = a u`) is compensated by
//! the constant `N_z = 6 * 255 / w`, `w` the width of the bevel. The unit outputs the
//! unnormalised normal `(-i_u, -i_v, N_z)` in texel intensity units (0..255 scale); a
//! [`crate::units::normalize::Normalize`] and a dot product finish Lambert's
//! `N . L / (|N| |L|)`.
//!
//! The nine texels are read `ports` per clock from the texture memory (nearest texel under the
//! coordinate, wrap addressing), so the initiation interval is `ceil(9 / ports)`. The mask
//! sums are exact integers (two 4-input adder trees); `N_z` is a constant register quantized
//! to the output format.

use crate::format::{Encoding, Format};
use crate::gates::{CostTable, GateBudget};
use crate::sampler::{texel_axis, Filter, Sampler};
use crate::texture::{Shape, Texture};
use crate::unit::{Mode, PortSpec, TextureRead, Unit, Word};
use std::sync::Arc;

pub struct EmbossFilter {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    tex: Arc<Texture>,
    sampler: Sampler,
    nz: f64,
    ports: u32,
    mem_latency: u32,
}

impl EmbossFilter {
    /// `tex`: the height map, one lane of heights in [0, 1] (1 = white) stored in an unsigned
    /// intensity format (usually 8 bits, `UnitUnsigned`); level 0 is read.
    pub fn new(
        uv: Encoding,
        tex: Arc<Texture>,
        bevel_w: f64,
        ports: u32,
        mem_latency: u32,
        out: Encoding,
    ) -> Result<Self, String> {
        if tex.lanes() != 1 || tex.shape() != Shape::Flat {
            return Err(format!(
                "height map {}: expected a 2D texture of one lane",
                tex.name()
            ));
        }
        if !(bevel_w.is_finite() && bevel_w > 0.0) {
            return Err(format!(
                "bevel width w {bevel_w}: expected a finite number above 0"
            ));
        }
        if !(1..=9).contains(&ports) {
            return Err(format!("ports {ports}: expected 1 to 9"));
        }
        let l = tex.level_at(0);
        let (log_w, log_h) = l.logs();
        if (uv.format.frac as u32) < log_w.max(log_h) {
            return Err(format!(
                "texture coordinate format {} has too few fraction bits for a {}x{} map",
                uv.format,
                l.width(),
                l.height()
            ));
        }
        Ok(EmbossFilter {
            inputs: vec![PortSpec::new("uv", 2, uv)],
            outputs: vec![PortSpec::new("n", 3, out)],
            tex,
            sampler: Sampler::new(Filter::Nearest, 1)?,
            nz: 6.0 * 255.0 / bevel_w,
            ports,
            mem_latency: mem_latency.max(1),
        })
    }

    /// Mask responses over the 3x3 neighbourhood of texel (i, j) for a texel reader `t` of
    /// memory indices.
    fn masks<T: Copy + std::ops::Add<Output = T> + std::ops::Sub<Output = T>>(
        &self,
        i: i64,
        j: i64,
        t: impl Fn(usize) -> T,
    ) -> (T, T) {
        let l = self.tex.level_at(0);
        let g = |a: i64, b: i64| t(self.sampler.index(l, 0, i + a, j + b));
        let iu = (g(1, -1) - g(-1, -1)) + (g(1, 0) - g(-1, 0)) + (g(1, 1) - g(-1, 1));
        let iv = (g(-1, 1) - g(-1, -1)) + (g(0, 1) - g(0, -1)) + (g(1, 1) - g(1, -1));
        (iu, iv)
    }
}

impl Unit for EmbossFilter {
    fn kind(&self) -> &'static str {
        "emboss_filter"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        self.mem_latency + self.interval() + 1
    }
    fn interval(&self) -> u32 {
        9u32.div_ceil(self.ports)
    }
    fn textures(&self) -> Vec<TextureRead> {
        vec![TextureRead {
            texture: self.tex.clone(),
            taps: 9,
        }]
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let wc = self.inputs[0].enc.width();
        let wt = self.tex.texel().width();
        let wo = self.outputs[0].enc.width();
        let mut g = GateBudget::new();
        g.add(format!("address adder {wc}"), 2 * self.ports, t.adder(wc));
        g.add(format!("tap register {wt}"), 9, t.register(wt));
        // each mask: three differences and two sums, growing to wt + 3 bits
        g.add(format!("mask adder {}", wt + 3), 10, t.adder(wt + 3));
        g.add(format!("N_z constant register {wo}"), 1, t.register(wo));
        g.add(format!("output register {}", 3 * wo), 1, t.register(3 * wo));
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.outputs[0].enc;
        let uv = &ins[0];
        match mode {
            Mode::Exact => {
                let l = self.tex.level_at(0);
                let i = (uv.lanes[0].x * l.width() as f64).floor() as i64;
                let j = (uv.lanes[1].x * l.height() as f64).floor() as i64;
                let (iu, iv) = self.masks(i, j, |k| l.value(k)[0] * 255.0);
                outs[0] = Word::from_exact(&out, &[-iu, -iv, self.nz]);
            }
            Mode::BitAccurate => {
                let frac = self.inputs[0].enc.format.frac as u32;
                let l = self.tex.level_at(0);
                let (log_w, log_h) = l.logs();
                let i = texel_axis(uv.lanes[0].raw, frac, log_w, false).0;
                let j = texel_axis(uv.lanes[1].raw, frac, log_h, false).0;
                // intensities as stored codes, read on the 0..255 scale of an 8-bit texel
                let scale = 255.0 / self.tex.texel().format.max_raw() as f64;
                let (iu, iv) = self.masks(i, j, |k| l.code(k)[0]);
                let f = Format {
                    signed: true,
                    width: 32,
                    frac: 0,
                };
                let enc = Encoding::fixed(f);
                let nz = out.encode(self.nz);
                let to = |v: i64| out.encode(enc.decode(v) * scale);
                outs[0] = Word::from_raw(&out, &[to(-iu), to(-iv), nz]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::Codec;
    use crate::texture::Texels;

    #[test]
    fn a_ramp_gives_six_a_and_the_bevel_constant() {
        // i = a u with a = 4 intensity levels per texel along u, constant along v
        let (w, h) = (16u32, 8u32);
        let heights: Vec<f64> = (0..h)
            .flat_map(|_| (0..w).map(|i| (40 + 4 * i) as f64 / 255.0))
            .collect();
        let uv = Encoding::fixed(Format::u(16, 16));
        let texel = Encoding::texel(Codec::UnitUnsigned, false, 8);
        let out = Encoding::fixed(Format::s(16, 4));
        let values = heights.iter().map(|&x| [x, 0.0, 0.0, 0.0]).collect();
        let tex = Texels {
            width: w,
            height: h,
            lanes: 1,
            values,
        };
        let tex = Arc::new(Texture::new("heights", texel, tex).unwrap());
        let u = EmbossFilter::new(uv, tex, 6.0, 3, 2, out).unwrap();
        assert_eq!(u.interval(), 3);
        let mut o = [Word::default()];
        for mode in [Mode::Exact, Mode::BitAccurate] {
            u.eval(mode, &[Word::quantize(&uv, &[0.5 + 0.01, 0.3])], &mut o);
            let x: [f64; 3] = o[0].xs();
            assert!((x[0] - -24.0).abs() < 1e-9, "{mode:?} {x:?}"); // -6a
            assert!(x[1].abs() < 1e-9);
            assert!((x[2] - 255.0).abs() < 1e-9); // 6*255/6
        }
    }
}

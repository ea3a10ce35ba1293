//! The per-fragment noise generator of NDF-based bump map synthesis in software (Kautz et
//! al. 2001 §5.1: "We then evaluate a noise function for that surface — a fractal noise
//! function such as Perlin turbulence should be used. We adjust the number of used octaves
//! depending on the distance d, the closer the more octaves we use. Whenever a new octave is
//! added, it should be blended in smoothly ... The noise function has to be evaluated twice
//! (with different settings) to get two different random numbers (r1, r2)").
//!
//! In: `uv` (2 lanes, unsigned, wrapped to [0, 1)), `lod` (1 lane: the level of detail, e.g.
//! the per-triangle `Lod` attribute). Out: `r` (2 lanes: the indices `(r1, r2)` in [0, 1],
//! ready to read the lookup table `L`). The octave count is `clamp(octaves - lod, 0,
//! octaves)`, fractional: the last octave is weighted by the fraction.
//!
//! **Exact mode**: f64 ([`Turbulence::exact`]), `r = clamp(1/2 + n scale, 0, 1)`.
//! **Bit-accurate mode**: `uv` raw words, the octave count to 8 fraction bits (truncated),
//! [`Turbulence::bits_blend`] with `frac` fraction bits, `scale` quantized to 16 fraction
//! bits, `1/2 + n scale` exact, then clamped and cast once into `r`'s encoding.

use super::ndf_noise::{Turbulence, MAX_OCTAVES};
use crate::arith::Acc;
use crate::format::Encoding;
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};

/// Fraction bits of the index scale.
const SCALE_FRAC: u32 = 16;

/// See the module documentation.
pub struct TurbulenceIndex {
    turbulence: Turbulence,
    octaves: u32,
    scale: f64,
    scale_raw: i64,
    frac: u32,
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
}

impl TurbulenceIndex {
    /// `octaves` (1 to 12) of `turbulence`, index `1/2 + n scale`; `frac` (4 to 24) fraction
    /// bits of the noise datapath; `uv`, `lod` the encodings of the wires in, `out` of `r`
    /// (unsigned).
    pub fn new(
        turbulence: Turbulence,
        octaves: u32,
        scale: f64,
        frac: u32,
        uv: Encoding,
        lod: Encoding,
        out: Encoding,
    ) -> Result<Self, String> {
        if !(1..=MAX_OCTAVES).contains(&octaves) {
            return Err(format!("octaves {octaves}: expected 1 to {MAX_OCTAVES}"));
        }
        if !(4..=24).contains(&frac) {
            return Err(format!("frac {frac}: expected 4 to 24 fraction bits"));
        }
        if uv.format.signed || out.format.signed {
            return Err(format!(
                "uv {uv}, out {out}: expected unsigned encodings (wrapped coordinates, indices in [0, 1])"
            ));
        }
        if !(scale.is_finite() && scale > 0.0 && scale < 1e6) {
            return Err(format!(
                "scale {scale}: expected a positive number below 1e6"
            ));
        }
        Ok(TurbulenceIndex {
            turbulence,
            octaves,
            scale,
            scale_raw: (scale * f64::from(1u32 << SCALE_FRAC)).round() as i64,
            frac,
            inputs: vec![PortSpec::new("uv", 2, uv), PortSpec::new("lod", 1, lod)],
            outputs: vec![PortSpec::new("r", 2, out)],
        })
    }

    /// The octave count at level of detail `lod`, exact.
    fn octaves_at(&self, lod: f64) -> f64 {
        (f64::from(self.octaves) - lod).clamp(0.0, f64::from(self.octaves))
    }
}

impl Unit for TurbulenceIndex {
    fn kind(&self) -> &'static str {
        "ndf_turbulence"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    /// One clock per octave (the octaves are pipelined), 3 more for the lattice hash, the
    /// index scale and the clamp.
    fn latency(&self) -> u32 {
        self.octaves + 3
    }
    fn interval(&self) -> u32 {
        1
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let f = self.frac;
        let n = 2 * self.octaves; // two random numbers, one datapath per octave each
        let mut g = GateBudget::new();
        g.add_rom(
            "permutation ROM 256 x 8 (4 corners x 3 lookups)",
            n * 12,
            t.rom(256, 8),
        );
        g.add(
            format!("fade polynomial multipliers {f}x{f}"),
            n * 2 * 4,
            t.multiplier(f, f),
        );
        g.add(
            format!("lerp multipliers {f}x{f}"),
            n * 3,
            t.multiplier(f, f),
        );
        g.add(
            format!("corner dot adders {}", f + 2),
            n * 4,
            t.adder(f + 2),
        );
        g.add(
            format!("octave weight multiplier {f}x9"),
            n,
            t.multiplier(f, 9),
        );
        g.add(format!("octave sum adder {}", f + 12), n, t.adder(f + 12));
        g.add(
            format!("index scale multiplier {}x{SCALE_FRAC}", f + 2),
            2,
            t.multiplier(f + 2, SCALE_FRAC),
        );
        g.add(format!("clamp {}", f + 2), 2, t.clamp(f + 2));
        g.add(
            format!("pipeline registers {}", 4 * f),
            n,
            t.register(4 * f),
        );
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.outputs[0].enc;
        outs[0] = match mode {
            Mode::Exact => {
                let (u, v) = (ins[0].lanes[0].x, ins[0].lanes[1].x);
                let oct = self.octaves_at(ins[1].lanes[0].x);
                let r: [f64; 2] = std::array::from_fn(|w| {
                    (0.5 + self.turbulence.exact(w, u, v, oct) * self.scale).clamp(0.0, 1.0)
                });
                Word::from_exact(&out, &r)
            }
            Mode::BitAccurate => {
                let uv_enc = self.inputs[0].enc;
                let uf = uv_enc.format.frac as u32;
                let lod = Acc::from_code(ins[1].lanes[0].raw, &self.inputs[1].enc);
                // the octave count to 8 fraction bits, truncated toward -inf
                let lod_q = if lod.frac >= 8 {
                    lod.raw >> (lod.frac - 8)
                } else {
                    lod.raw << (8 - lod.frac)
                };
                let oq = (i128::from(self.octaves) * 256 - lod_q)
                    .clamp(0, i128::from(self.octaves) * 256);
                let (ur, vr) = (ins[0].lanes[0].raw, ins[0].lanes[1].raw);
                let r: [i64; 2] = std::array::from_fn(|w| {
                    let n = self
                        .turbulence
                        .bits_blend(w, ur, vr, uf, oq as i64, self.frac);
                    Acc::new(n as i128, self.frac)
                        .mul(Acc::new(self.scale_raw as i128, SCALE_FRAC))
                        .add(Acc::new(1, 1))
                        .clamp(Acc::ZERO, Acc::new(1, 0))
                        .to_code(&out)
                });
                Word::from_raw(&out, &r)
            }
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Codec, Format};
    use proptest::prelude::*;

    fn unit(frac: u32) -> TurbulenceIndex {
        TurbulenceIndex::new(
            Turbulence::new(8, 3),
            4,
            0.6,
            frac,
            Encoding::fixed(Format::u(16, 16)),
            Encoding::fixed(Format::u(8, 4)),
            Encoding::texel(Codec::UnitUnsigned, false, 16),
        )
        .unwrap()
    }

    fn eval(u: &TurbulenceIndex, mode: Mode, uv: [f64; 2], lod: f64) -> [f64; 2] {
        let ins = [
            Word::from_exact(&u.inputs[0].enc, &uv),
            Word::from_exact(&u.inputs[1].enc, &[lod]),
        ];
        let ins: Vec<Word> = ins
            .iter()
            .zip(&u.inputs)
            .map(|(w, p)| Word::from_raw(&p.enc, &w.raws::<4>()[..p.lanes as usize]))
            .collect();
        let mut outs = vec![Word::default()];
        u.eval(mode, &ins, &mut outs);
        [outs[0].lanes[0].x, outs[0].lanes[1].x]
    }

    /// Exhaustive over a 64 x 64 grid of coordinates and every LOD code of 0..4 at 4
    /// fraction bits (the coordinate and LOD words exact in both modes), 8 noise fraction
    /// bits: bit-accurate within 2 LSB of the noise per octave, scaled, plus one index LSB.
    #[test]
    fn exact_and_bits_agree_small_width() {
        let u = unit(8);
        let bound = 4.0 * 2.0 / 256.0 * 0.6 + 2.0 / 65535.0;
        for i in 0..64 {
            for j in 0..64 {
                for l in 0..=64 {
                    let uv = [f64::from(i) / 64.0, f64::from(j) / 64.0];
                    let lod = f64::from(l) / 16.0;
                    let e = eval(&u, Mode::Exact, uv, lod);
                    let b = eval(&u, Mode::BitAccurate, uv, lod);
                    for k in 0..2 {
                        assert!((e[k] - b[k]).abs() <= bound, "{uv:?} {lod}: {e:?} {b:?}");
                    }
                }
            }
        }
    }

    proptest! {
        #[test]
        fn exact_and_bits_agree_wide(u0 in 0u32..65536, v0 in 0u32..65536, l in 0u32..80) {
            let u = unit(16);
            let uv = [f64::from(u0) / 65536.0, f64::from(v0) / 65536.0];
            let lod = f64::from(l) / 16.0;
            let e = eval(&u, Mode::Exact, uv, lod);
            let b = eval(&u, Mode::BitAccurate, uv, lod);
            let bound = 4.0 * 4.0 / 65536.0 * 0.6 + 2.0 / 65535.0;
            for k in 0..2 {
                prop_assert!((e[k] - b[k]).abs() <= bound, "{:?} {}: {:?} {:?}", uv, lod, e, b);
            }
        }
    }
}

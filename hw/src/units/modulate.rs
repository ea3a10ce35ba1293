//! Texture modulate stage: `c_out = c (*) t` per channel (OpenGL's MODULATE texture
//! environment).
//!
//! The texture stage of a Gouraud rasterizer, Ernst et al. 1998 §5.1: "A rendering pipeline
//! for a Gouraud rasterizer usually gets the interpolated Gouraud color and blends the texture
//! color thereafter. Thus, the pipeline ordering is ColorDDA - Texture - Blend"; Gouraud bump
//! mapping re-orders it into DiffuseBlend - Texture - SpecularBlend, because "blending the
//! diffuse and specular color together after the texture pass has no effect on black texture
//! color due to the multiplication (see Figure 3)" — a black texel gives black, whatever the
//! Gouraud colour.
//!
//! Ports: `c` (3 lanes, the fragment colour) and `t` (3 lanes, the texel) in; `c` (3 lanes)
//! out. Three multipliers in one clock; interval 1, latency 2 (the multiply, then the clamp
//! and output register). Exact mode: `clamp(c t, 0, 1)` in f64 (OpenGL clamps colours after
//! each texture environment). Bit-accurate mode: the product exact in [`Acc`], clamped to
//! [0, 1] and cast once into the output encoding.

use crate::arith::Acc;
use crate::format::{Codec, Encoding};
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};

pub struct Modulate {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
}

impl Modulate {
    /// `c` and `t` are the encodings of the wires into the unit.
    pub fn new(c: Encoding, t: Encoding, out: Encoding) -> Self {
        Modulate {
            inputs: vec![PortSpec::new("c", 3, c), PortSpec::new("t", 3, t)],
            outputs: vec![PortSpec::new("c", 3, out)],
        }
    }
}

impl Unit for Modulate {
    fn kind(&self) -> &'static str {
        "modulate"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        2
    }
    fn interval(&self) -> u32 {
        1
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let wc = self.inputs[0].enc.width();
        let wt = self.inputs[1].enc.width();
        let wo = self.outputs[0].enc.width();
        let mut g = GateBudget::new();
        g.add(format!("multiplier {wc}x{wt}"), 3, t.multiplier(wc, wt));
        // Each `c / (2^n - 1)` read (a factor 2^n + 1) and a cast into such a code (a factor
        // 2^n - 1) is one shift-and-add of the product: the exact cast folds them into one
        // constant (u8 x u8 into u8: (2^8 + 1)(2^16 - 1), three adders; `rtl::modulate`).
        let reps = [
            &self.inputs[0].enc,
            &self.inputs[1].enc,
            &self.outputs[0].enc,
        ]
        .iter()
        .filter(|e| matches!(e.codec, Codec::UnitUnsigned | Codec::UnitSymmetric))
        .count() as u32;
        if reps > 0 {
            let wp = wc + wt;
            g.add(format!("cast shift-and-add {wp}"), 3 * reps, t.adder(wp));
        }
        // the clamp to [0, 1] is logic only where a product can leave it (the generated
        // Verilog tracks the range and drops it otherwise, `rtl::modulate`)
        let in_unit = |e: &Encoding| {
            e.decode(e.format.min_raw()) >= 0.0 && e.decode(e.format.max_raw()) <= 1.0
        };
        let clamp = if in_unit(&self.inputs[0].enc) && in_unit(&self.inputs[1].enc) {
            0.0
        } else {
            t.clamp(wo)
        };
        g.add(
            format!("rounding and clamp {wo}"),
            3,
            t.half_adder * wo as f64 + clamp,
        );
        g.add(format!("output register {}", 3 * wo), 1, t.register(3 * wo));
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.outputs[0].enc;
        let (c, t) = (&ins[0], &ins[1]);
        outs[0] = match mode {
            Mode::Exact => {
                let v: [f64; 3] =
                    std::array::from_fn(|i| (c.lanes[i].x * t.lanes[i].x).clamp(0.0, 1.0));
                Word::from_exact(&out, &v)
            }
            Mode::BitAccurate => {
                let (ce, te) = (&self.inputs[0].enc, &self.inputs[1].enc);
                let v: [i64; 3] = std::array::from_fn(|i| {
                    Acc::from_code(c.lanes[i].raw, ce)
                        .mul(Acc::from_code(t.lanes[i].raw, te))
                        .clamp(Acc::ZERO, Acc::new(1, 0))
                        .to_code(&out)
                });
                Word::from_raw(&out, &v)
            }
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::Format;

    fn u8e() -> Encoding {
        Encoding::texel(Codec::UnitUnsigned, false, 8)
    }

    fn run(m: &mut Modulate, mode: Mode, c: Word, t: Word) -> Word {
        let mut o = [Word::default()];
        m.eval(mode, &[c, t], &mut o);
        o[0]
    }

    #[test]
    fn hand_values() {
        let f = Encoding::fixed(Format::u(9, 8));
        let mut m = Modulate::new(f, f, f);
        assert_eq!((m.interval(), m.latency()), (1, 2));
        let c = Word::quantize(&f, &[0.5, 0.75, 1.0]);
        let t = Word::quantize(&f, &[0.5, 0.25, 0.625]);
        // 0.25, 0.1875, 0.625: exact in u1.8
        assert_eq!(
            run(&mut m, Mode::BitAccurate, c, t).raws::<3>(),
            [64, 48, 160]
        );
        assert_eq!(
            run(&mut m, Mode::Exact, c, t).xs::<3>(),
            [0.25, 0.1875, 0.625]
        );
        // 8-bit colours: 200 * 100 / 255 = 78.43 -> 78; 255 * 37 / 255 = 37; 128 * 128 / 255
        // = 64.25 -> 64
        let e = u8e();
        let mut m8 = Modulate::new(e, e, e);
        let c = Word::from_raw(&e, &[200, 255, 128]);
        let t = Word::from_raw(&e, &[100, 37, 128]);
        assert_eq!(
            run(&mut m8, Mode::BitAccurate, c, t).raws::<3>(),
            [78, 37, 64]
        );
        // white is the identity, for every 8-bit code
        for code in 0..=255 {
            let c = Word::from_raw(&e, &[code, code, code]);
            let w = Word::from_raw(&e, &[255, 255, 255]);
            assert_eq!(run(&mut m8, Mode::BitAccurate, c, w).raws::<3>(), [code; 3]);
        }
        // products above 1 are clamped (wide fixed-point inputs)
        let wide = Encoding::fixed(Format::u(10, 8));
        let mut mw = Modulate::new(wide, wide, f);
        let two = Word::quantize(&wide, &[2.0, 1.5, 0.5]);
        assert_eq!(
            run(&mut mw, Mode::BitAccurate, two, two).raws::<3>(),
            [256, 256, 64]
        );
        assert_eq!(
            run(&mut mw, Mode::Exact, two, two).xs::<3>(),
            [1.0, 1.0, 0.25]
        );
    }

    #[test]
    fn black_texel_gives_black() {
        // Ernst Fig. 3: whatever was blended before the texture pass, a black texel wins
        let e = u8e();
        let mut m = Modulate::new(e, e, e);
        let black = Word::from_raw(&e, &[0, 0, 0]);
        for code in [0, 1, 77, 254, 255] {
            let c = Word::from_raw(&e, &[code, 255, 128]);
            assert_eq!(run(&mut m, Mode::BitAccurate, c, black).raws::<3>(), [0; 3]);
            assert_eq!(run(&mut m, Mode::Exact, c, black).xs::<3>(), [0.0; 3]);
        }
    }

    #[test]
    fn bit_accurate_is_within_half_an_output_step_of_exact() {
        let e = u8e();
        let mut m = Modulate::new(e, e, e);
        for a in (0..=255).step_by(3) {
            for b in 0..=255 {
                let c = Word::from_raw(&e, &[a, b, 255 - a]);
                let t = Word::from_raw(&e, &[b, a, b]);
                let bits = run(&mut m, Mode::BitAccurate, c, t).xs::<3>();
                let exact = run(&mut m, Mode::Exact, c, t).xs::<3>();
                for l in 0..3 {
                    // the 8-bit reads by bit replication are off by < 2^-16 each
                    let bound = e.max_error() + 2.0 * 2f64.powi(-16);
                    assert!((bits[l] - exact[l]).abs() <= bound, "{a} {b} lane {l}");
                }
            }
        }
    }

    #[test]
    fn gates_are_three_multipliers_and_a_clamp() {
        let t = CostTable::default();
        let e = u8e();
        let g = Modulate::new(e, e, e).gates(&t);
        assert!((g.items[0].ge - 3.0 * t.multiplier(8, 8)).abs() < 1e-9);
        let wide = Encoding::texel(Codec::UnitUnsigned, false, 10);
        assert!(Modulate::new(wide, wide, e).gates(&t).total() > g.total());
    }
}

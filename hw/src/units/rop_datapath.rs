//! The ROP's datapath as a unit: [`Rop::resolve`], a pure function of one fragment and the
//! pixel it lands on, with the framebuffer read and write outside it (as the texture
//! memories are outside the fetch units). This is what the ROP's Verilog implements
//! (`rtl::rop`), what co-simulation replays and what synthesis prices; the simulator drives
//! [`Rop::write`], the same function applied to the framebuffer.
//!
//! Ports: `c` the fragment's colour (RGB, or RGBA when the ROP reads alpha, in the engine
//! output's encoding), `z` its depth code, `dc` the pixel's three stored codes and `dz` its
//! depth code (unsigned integers of `color_bits` and `depth_bits` bits). Outputs: `wc` (the
//! colour is written: both tests passed), `wz` (the depth is written: `wc` and the pass
//! writes depth) and `oc`, the codes written (the stored codes when `wc` is 0).
//!
//! Exact mode reads `dc` as stored codes too and gives `oc` as the unrounded colour in code
//! units (`x (2^b - 1)`), so that the exact-vs-bit-accurate bound is in codes.

use super::rop::{Outcome, Pixel, Rop};
use crate::format::{Encoding, Format};
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};

/// The ROP's datapath. See the module documentation.
#[derive(Debug, Clone)]
pub struct RopDatapath {
    rop: Rop,
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
}

impl RopDatapath {
    /// The datapath of `rop`.
    pub fn new(rop: &Rop) -> Self {
        let lanes = if rop.alpha().is_some() { 4 } else { 3 };
        let depth = Encoding::fixed(Format::u(rop.depth_bits() as u8, 0));
        let code = Encoding::fixed(Format::u(rop.params().color_bits as u8, 0));
        let bit = Encoding::fixed(Format::u(1, 0));
        RopDatapath {
            rop: rop.clone(),
            inputs: vec![
                PortSpec::new("c", lanes, rop.color()),
                PortSpec::new("z", 1, depth),
                PortSpec::new("dc", 3, code),
                PortSpec::new("dz", 1, depth),
            ],
            outputs: vec![
                PortSpec::new("wc", 1, bit),
                PortSpec::new("wz", 1, bit),
                PortSpec::new("oc", 3, code),
            ],
        }
    }

    pub fn rop(&self) -> &Rop {
        &self.rop
    }
}

impl Unit for RopDatapath {
    fn kind(&self) -> &'static str {
        "rop"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        1
    }
    fn interval(&self) -> u32 {
        1
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        self.rop.gates(t)
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let int = |w: &Word, l: usize| match mode {
            Mode::BitAccurate => w.lanes[l].raw,
            Mode::Exact => w.lanes[l].x.round() as i64,
        };
        let one = self.rop.one();
        let code: [i64; 3] = std::array::from_fn(|l| int(&ins[2], l));
        let dst = Pixel {
            code,
            x: code.map(|c| c as f64 / one as f64),
        };
        let (z, dz) = (int(&ins[1], 0) as u32, int(&ins[3], 0) as u32);
        let (outcome, px) = self.rop.resolve(mode, z, &ins[0], &dst, dz);
        let written = outcome == Outcome::Written;
        let bit = self.outputs[0].enc;
        outs[0] = Word::from_raw(&bit, &[i64::from(written)]);
        outs[1] = Word::from_raw(&bit, &[i64::from(written && self.rop.params().depth_write)]);
        let enc = self.outputs[2].enc;
        outs[2] = match mode {
            Mode::BitAccurate => Word::from_raw(&enc, &px.code),
            Mode::Exact => Word::from_exact(&enc, &px.x.map(|v| v * one as f64)),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::Codec;
    use crate::units::rop::{Compare, Factor, RopParams};

    /// The unit is [`Rop::write`] on a one-pixel framebuffer, for every outcome.
    #[test]
    fn the_datapath_is_the_framebuffer_write() {
        let enc = Encoding::texel(Codec::UnitUnsigned, false, 8);
        let params = RopParams {
            depth: Compare::LEqual,
            alpha_test: Some((Compare::Greater, 40)),
            blend: Some((Factor::OneMinusDstColor, Factor::SrcAlpha)),
            ..RopParams::default()
        };
        let rop = Rop::new(params, enc, Some(enc), 12).unwrap();
        let u = RopDatapath::new(&rop);
        let mut outs = vec![Word::default(); 3];
        let mut seen = [0usize; 3];
        for k in 0..4000i64 {
            let c = Word::from_raw(&enc, &[k % 256, k * 7 % 256, k * 13 % 256, k * 3 % 256]);
            let (z, dz) = ((k * 37 % 4096) as u32, (k * 91 % 4096) as u32);
            let dc = [k * 5 % 256, k * 11 % 256, k * 17 % 256];
            let mut fb = rop.clear(1, 1);
            fb.code[0] = dc.map(|v| v as u16);
            fb.depth[0] = dz;
            let outcome = rop.write(&mut fb, Mode::BitAccurate, 0, z, &c);
            seen[outcome as usize] += 1;
            let code = u.outputs()[2].enc;
            let depth = u.inputs()[1].enc;
            let ins = [
                c,
                Word::from_raw(&depth, &[i64::from(z)]),
                Word::from_raw(&code, &dc),
                Word::from_raw(&depth, &[i64::from(dz)]),
            ];
            u.eval(Mode::BitAccurate, &ins, &mut outs);
            let written = outcome == Outcome::Written;
            assert_eq!(outs[0].lanes[0].raw, i64::from(written), "{k}");
            assert_eq!(outs[1].lanes[0].raw, i64::from(written), "{k}");
            assert_eq!(outs[2].raws::<3>(), fb.pixel(0).code, "{k}");
            assert_eq!(fb.depth[0], if written { z } else { dz }, "{k}");
        }
        assert!(seen.iter().all(|&n| n > 500), "{seen:?}");
    }
}

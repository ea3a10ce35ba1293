//! Fragment cull unit: the CULL_FRAGMENT program of NV20 texture shaders (NV_texture_shader,
//! "Conditional fragment culling"), also what a user clip plane does per fragment.
//!
//! Each lane `v[i]` of the input (the stage's interpolated s, t, r, q, or a plane distance) is
//! compared with zero by its test: `Gequal` passes when `v >= 0`, `Less` when `v < 0`. If any
//! test fails, the fragment is killed: it goes on down the pipe with its live bit cleared and
//! the ROP does not write it (`crate::stage::Token::live`). The spec compares the coordinates
//! themselves, without dividing by q.
//!
//! Ports: `v` (1 to 4 lanes) in; `live` (1 lane, one bit: 1 = survives) out, so that traces
//! show the decision. Bit-accurate mode reads the sign bit of the raw word (for every
//! encoding of the project, a negative raw word is a negative value, the symmetric texel codec
//! included); exact mode compares the real value. Latency 1, interval 1.

use crate::format::{Encoding, Format};
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};

/// The comparison of one lane with zero (the CULL_MODES_NV state of one coordinate).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum CullTest {
    /// Passes when the lane is >= 0 (GL_GEQUAL).
    Gequal,
    /// Passes when the lane is < 0 (GL_LESS).
    Less,
}

pub struct CullFragment {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    tests: Vec<CullTest>,
}

impl CullFragment {
    /// One test per lane of `v`, 1 to 4 of them.
    pub fn new(v: Encoding, tests: &[CullTest]) -> Result<Self, String> {
        if !(1..=4).contains(&tests.len()) {
            return Err(format!(
                "tests: {} given: expected 1 to 4, one per lane of v",
                tests.len()
            ));
        }
        Ok(CullFragment {
            inputs: vec![PortSpec::new("v", tests.len() as u8, v)],
            outputs: vec![PortSpec::new("live", 1, Encoding::fixed(Format::u(1, 0)))],
            tests: tests.to_vec(),
        })
    }

    /// The test of each lane.
    pub fn tests(&self) -> &[CullTest] {
        &self.tests
    }

    fn passes(&self, mode: Mode, v: &Word) -> bool {
        self.tests.iter().zip(&v.lanes).all(|(t, s)| {
            let negative = match mode {
                Mode::Exact => s.x < 0.0,
                Mode::BitAccurate => s.raw < 0,
            };
            negative == (*t == CullTest::Less)
        })
    }
}

impl Unit for CullFragment {
    fn kind(&self) -> &'static str {
        "cull_fragment"
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
        let n = self.tests.len() as u32;
        let mut g = GateBudget::new();
        // the sign bit against the lane's mode bit, then a NOR of the failures (`rtl::cull`);
        // the mode bits are host-loaded registers and `live` is loaded per fragment (each a
        // flip-flop with a load enable), and a one-step sequencer
        g.add("sign test (XOR with the mode bit)", n, t.xor2);
        g.add(
            "kill OR tree",
            n.saturating_sub(1),
            t.and2 + t.inv, // OR2 ~ NAND2 of inverted inputs
        );
        g.add("mode register", n, t.register(1));
        g.add("live register", 1, t.register(1));
        g.add("sequencer", 1, t.sequencer(1));
        g
    }
    fn can_kill(&self) -> bool {
        true
    }
    fn live(&self, _: Mode, _: &[Word], outs: &[Word]) -> bool {
        outs[0].lanes[0].raw != 0
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let live = self.passes(mode, &ins[0]);
        let enc = self.outputs[0].enc;
        outs[0] = Word::from_raw(&enc, &[i64::from(live)]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_sign_pattern_of_four_lanes_against_every_test_pattern() {
        let enc = Encoding::fixed(Format::s(4, 2));
        for pattern in 0..16u32 {
            let tests: Vec<CullTest> = (0..4)
                .map(|i| {
                    if pattern >> i & 1 == 1 {
                        CullTest::Less
                    } else {
                        CullTest::Gequal
                    }
                })
                .collect();
            let u = CullFragment::new(enc, &tests).unwrap();
            // every input word: 4 lanes of 4 bits (2^16 words)
            for bits in 0..1u32 << 16 {
                let raws: Vec<i64> = (0..4)
                    .map(|i| {
                        ((bits >> (4 * i)) & 15) as i64
                            - if (bits >> (4 * i)) & 8 != 0 { 16 } else { 0 }
                    })
                    .collect();
                let w = Word::from_raw(&enc, &raws);
                let want = (0..4).all(|i| (raws[i] < 0) == (tests[i] == CullTest::Less));
                let mut o = [Word::default()];
                for mode in [Mode::BitAccurate, Mode::Exact] {
                    u.eval(mode, &[w], &mut o);
                    assert_eq!(o[0].lanes[0].raw, i64::from(want));
                    assert_eq!(u.live(mode, &[w], &o), want);
                }
            }
        }
    }

    #[test]
    fn zero_passes_gequal_and_fails_less() {
        let enc = Encoding::fixed(Format::s(8, 6));
        let mut o = [Word::default()];
        let zero = Word::from_raw(&enc, &[0]);
        let ge = CullFragment::new(enc, &[CullTest::Gequal]).unwrap();
        ge.eval(Mode::BitAccurate, &[zero], &mut o);
        assert_eq!(o[0].lanes[0].raw, 1);
        let lt = CullFragment::new(enc, &[CullTest::Less]).unwrap();
        lt.eval(Mode::BitAccurate, &[zero], &mut o);
        assert_eq!(o[0].lanes[0].raw, 0);
        assert!(CullFragment::new(enc, &[]).is_err());
        assert!(CullFragment::new(enc, &[CullTest::Less; 5]).is_err());
    }
}

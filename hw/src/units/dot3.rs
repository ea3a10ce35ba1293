//! Dot-product unit: `d_i = clamp(a . b_i)` for k vectors `b_i` against one vector `a`.
//!
//! Models the per-fragment dot products of the SGI tangent-space engine (Gouraud bump paper
//! §3.4: `N'_TS . L_TS` and `N'_TS . H_TS`, evaluated in the rasterizer after the normal texel
//! fetch) and the diffuse blend of Ernst et al. §4.2 (`fd_i = B_i . L`). One datapath of three
//! multipliers and a 3-input adder evaluates one dot product per clock; with `parallel`
//! datapaths the k products take `ceil(k / parallel)` clocks, which is the unit's initiation
//! interval ("n lights in n clock cycles", §4.2).
//!
//! Bit-accurate mode: the products and their sum are exact (`(wa + wb + 2)`-bit adder), then
//! clamped and cast once into the output encoding with its rounding and overflow modes.

use crate::arith::{Acc, Reader, Writer};
use crate::columns::{Column, ColumnIn};
use crate::format::Encoding;
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};

/// Result clamping of a dot-product unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, Default)]
pub enum Clamp {
    /// `max(0, min(1, a.b))`: lighting intensities.
    #[default]
    Unit,
    /// `max(0, a.b)`.
    Positive,
    /// No clamp (the output encoding's overflow mode still applies).
    None,
}

pub struct Dot3 {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    parallel: u32,
    clamp: Clamp,
    /// The datapath in `i64`, when a sum of three products fits in 62 bits.
    narrow: Option<Narrow>,
}

/// The readers of `a` and `b`, the clamp's 1 at the sum's scale and the writer of the
/// clamped sum, for the `i64` datapath.
#[derive(Clone, Copy)]
struct Narrow {
    a: Reader,
    b: Reader,
    one: i64,
    out: Writer,
}

impl Dot3 {
    /// `a` and `b` are the encodings of the incoming vectors; `k` the number of `b` vectors.
    pub fn new(
        a: Encoding,
        b: Encoding,
        k: u32,
        parallel: u32,
        clamp: Clamp,
        out: Encoding,
    ) -> Self {
        let mut inputs = vec![PortSpec::new("a", 3, a)];
        inputs.extend((0..k).map(|i| PortSpec::new(&format!("b{i}"), 3, b)));
        let outputs = (0..k)
            .map(|i| PortSpec::new(&format!("d{i}"), 1, out))
            .collect();
        let narrow = Reader::new(&a)
            .zip(Reader::new(&b))
            .filter(|(ra, rb)| ra.bits + rb.bits + 2 <= 62)
            .map(|(a, b)| {
                let frac = a.frac + b.frac;
                Narrow {
                    a,
                    b,
                    // a sum below 2^62 is below 1 when 1 is 2^62 or more
                    one: if frac < 63 { 1i64 << frac } else { i64::MAX },
                    out: Writer::new(frac, &out),
                }
            });
        Dot3 {
            inputs,
            outputs,
            parallel: parallel.clamp(1, k.max(1)),
            clamp,
            narrow,
        }
    }

    fn k(&self) -> u32 {
        self.outputs.len() as u32
    }

    fn clamp_f64(&self, x: f64) -> f64 {
        match self.clamp {
            Clamp::Unit => x.clamp(0.0, 1.0),
            Clamp::Positive => x.max(0.0),
            Clamp::None => x,
        }
    }
}

impl Unit for Dot3 {
    fn kind(&self) -> &'static str {
        "dot3"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        self.interval() + 1
    }
    fn interval(&self) -> u32 {
        self.k().div_ceil(self.parallel).max(1)
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let wa = self.inputs[0].enc.width();
        let wb = self.inputs.get(1).map_or(wa, |p| p.enc.width());
        let wo = self.outputs.first().map_or(0, |p| p.enc.width());
        let p = self.parallel;
        let mut g = GateBudget::new();
        g.add(format!("multiplier {wa}x{wb}"), 3 * p, t.multiplier(wa, wb));
        g.add(
            format!("adder {}", wa + wb + 2),
            2 * p,
            t.adder(wa + wb + 2),
        );
        g.add(format!("clamp {wo}"), p, t.clamp(wo));
        if self.interval() > 1 {
            g.add(
                format!("operand mux {}:1 x{}", self.interval(), 3 * wb),
                p,
                t.mux(3 * wb, self.interval()),
            );
            g.add("sequencer counter 4", 1, t.register(4) + t.adder(4));
        }
        g.add(format!("input register {}", 3 * wa), 1, t.register(3 * wa));
        g.add(format!("result register {wo}"), self.k(), t.register(wo));
        g
    }
    fn eval_columns(&self, n: usize, ins: &[ColumnIn<'_>], outs: &mut [&mut Column]) -> bool {
        // the narrow datapath of `eval`, a column at a time
        let Some(nw) = self.narrow.as_ref() else {
            return false;
        };
        let a = &ins[0].lanes;
        for (o, b) in outs.iter_mut().zip(&ins[1..]) {
            let b = &b.lanes;
            for (k, o) in o[0][..n].iter_mut().enumerate() {
                let p = |j: usize| nw.a.read(a[j][k]) * nw.b.read(b[j][k]);
                let s = p(0) + p(1) + p(2);
                let s = match self.clamp {
                    Clamp::Unit => s.clamp(0, nw.one),
                    Clamp::Positive => s.max(0),
                    Clamp::None => s,
                };
                *o = nw.out.write(s);
            }
        }
        true
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let a = &ins[0];
        let out = self.outputs[0].enc;
        for (i, o) in outs.iter_mut().enumerate() {
            let b = &ins[1 + i];
            match mode {
                Mode::Exact => {
                    let d: f64 = (0..3).map(|j| a.lanes[j].x * b.lanes[j].x).sum();
                    *o = Word::from_exact(&out, &[self.clamp_f64(d)]);
                }
                Mode::BitAccurate if self.narrow.is_some() => {
                    let n = self.narrow.as_ref().expect("checked");
                    // the same exact sum and clamp in i64 (three products of one scale)
                    let p = |j: usize| n.a.read(a.lanes[j].raw) * n.b.read(b.lanes[j].raw);
                    let s = p(0) + p(1) + p(2);
                    let s = match self.clamp {
                        Clamp::Unit => s.clamp(0, n.one),
                        Clamp::Positive => s.max(0),
                        Clamp::None => s,
                    };
                    *o = Word::from_raw(&out, &[n.out.write(s)]);
                }
                Mode::BitAccurate => {
                    let (ea, eb) = (&self.inputs[0].enc, &self.inputs[1 + i].enc);
                    let rd = |w: &Word, j: usize, e: &Encoding| Acc::from_code(w.lanes[j].raw, e);
                    let s = (0..3).fold(Acc::ZERO, |s, j| s.add(rd(a, j, ea).mul(rd(b, j, eb))));
                    let s = match self.clamp {
                        Clamp::Unit => s.clamp(Acc::ZERO, Acc::new(1, 0)),
                        Clamp::Positive => {
                            if s.lt(Acc::ZERO) {
                                Acc::ZERO
                            } else {
                                s
                            }
                        }
                        Clamp::None => s,
                    };
                    *o = Word::from_raw(&out, &[s.to_code(&out)]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Codec, Format};

    fn word(mode: Mode, enc: &Encoding, v: [f64; 3]) -> Word {
        Word::for_mode(mode, enc, &v)
    }

    #[test]
    fn the_i64_sum_is_the_i128_sum_for_every_5_bit_pair_of_each_codec() {
        // every pair of codes on lane 0 (lanes 1, 2 at the ends of the range), 5-bit operands
        // of each codec into outputs of each clamp: the narrow and the wide datapath agree
        let codecs = [
            Encoding::texel(Codec::UnitUnsigned, false, 5),
            Encoding::texel(Codec::UnitSigned, true, 5),
            Encoding::texel(Codec::UnitSymmetric, true, 5),
            Encoding::fixed(Format::s(5, 3)),
        ];
        let out = Encoding::fixed(Format::s(14, 11));
        for ea in codecs {
            for eb in codecs {
                for clamp in [Clamp::Unit, Clamp::Positive, Clamp::None] {
                    let fast = Dot3::new(ea, eb, 1, 1, clamp, out);
                    assert!(fast.narrow.is_some());
                    let wide = Dot3 {
                        narrow: None,
                        ..Dot3::new(ea, eb, 1, 1, clamp, out)
                    };
                    let (fa, fb) = (ea.format, eb.format);
                    for x in fa.min_raw()..=fa.max_raw() {
                        for y in fb.min_raw()..=fb.max_raw() {
                            let a = Word::from_raw(&ea, &[x, fa.min_raw(), fa.max_raw()]);
                            let b = Word::from_raw(&eb, &[y, fb.max_raw(), fb.max_raw()]);
                            let (mut o1, mut o2) = ([Word::default()], [Word::default()]);
                            fast.eval(Mode::BitAccurate, &[a, b], &mut o1);
                            wide.eval(Mode::BitAccurate, &[a, b], &mut o2);
                            assert_eq!(o1, o2, "{ea} {eb} {clamp:?} {x} {y}");
                        }
                    }
                }
            }
        }
        // 32-bit unit codes read in 67 bits: the wide datapath
        let e32 = Encoding::texel(Codec::UnitUnsigned, false, 32);
        assert!(Dot3::new(e32, e32, 1, 1, Clamp::Unit, out).narrow.is_none());
    }

    #[test]
    fn exhaustive_4_bit_operands_match_the_exact_dot_within_half_an_output_lsb() {
        // a and b in s1.3 (4 bits): every combination of (a.x, b.x) with the other lanes fixed.
        let ein = Encoding::fixed(Format::s(4, 3));
        let out = Encoding::fixed(Format::u(12, 10));
        let u = Dot3::new(ein, ein, 1, 1, Clamp::Unit, out);
        let mut o = [Word::default()];
        for ax in -8..8 {
            for bx in -8..8 {
                for ay in [-8, 0, 7] {
                    let a = Word::from_raw(&ein, &[ax, ay, 4]);
                    let b = Word::from_raw(&ein, &[bx, 5, 4]);
                    u.eval(Mode::BitAccurate, &[a, b], &mut o);
                    let exact = (a.lanes[0].x * b.lanes[0].x + a.lanes[1].x * b.lanes[1].x + 0.25)
                        .clamp(0.0, 1.0);
                    let got = o[0].lanes[0].x;
                    assert!(
                        (got - exact).abs() <= out.max_error() + 1e-12,
                        "{ax} {bx} {ay}: {got} vs {exact}"
                    );
                    u.eval(Mode::Exact, &[a, b], &mut o);
                    assert_eq!(o[0].lanes[0].x, exact);
                }
            }
        }
    }

    #[test]
    fn hand_computed_values_and_interval() {
        let n = Encoding::texel(Codec::UnitSigned, true, 8);
        let out = Encoding::fixed(Format::u(9, 8));
        let u = Dot3::new(n, n, 4, 2, Clamp::Unit, out);
        assert_eq!(u.interval(), 2);
        assert_eq!(u.latency(), 3);
        let mode = Mode::BitAccurate;
        let a = word(mode, &n, [0.0, 0.0, 0.5]);
        let ins = [
            a,
            word(mode, &n, [0.0, 0.0, 0.5]),
            word(mode, &n, [0.5, 0.0, -0.5]),
            word(mode, &n, [0.0, 0.5, 0.25]),
            word(mode, &n, [-0.5, 0.5, 0.75]),
        ];
        let mut o = [Word::default(); 4];
        u.eval(mode, &ins, &mut o);
        // 0.25 -> 64/256; -0.25 clamps to 0; 0.125 -> 32; 0.375 -> 96
        assert_eq!(o.map(|w| w.lanes[0].raw), [64, 0, 32, 96]);
        assert!(u.gates(&CostTable::default()).total() > 0.0);
    }
}

//! Per-pixel normal perturbation: `n = base + d0 u + d1 v`.
//!
//! The last step of every engine of Ernst et al. 1998 §3 that perturbs an interpolated normal
//! by a bump map's offsets `(d0, d1)` along two axes:
//!
//! * VISA+ (§3.2): "`N' = N + A . V`, where V is the perturbation vector `V = [Δu Δv]^T`",
//!   `A = [u v]` the alignment matrix's columns (per triangle, or from the interpolated
//!   quaternion: [`super::QuatFrame`]);
//! * Harmony (§3.5): the interpolated per-vertex axes `-Pv x N` and `-N x Pu`, Blinn's
//!   `N' = N + Fu (N x Pv) + Fv (Pu x N)` of §2 with the axes interpolated over the triangle;
//! * Texram (§3.1): the per-pixel frame `e1`, `e2` of [`super::TexramFrame`].
//!
//! Six multipliers and, per lane, two adders; the products and sums are exact and each lane is
//! cast once into the output encoding (so for on-grid inputs the result is the exact value
//! rounded by the output's quantization mode, or saturated by its overflow mode). Exact mode
//! evaluates the same sum in f64. Latency 2 (products; sums and cast), interval 1.

use crate::arith::Acc;
use crate::format::{Codec, Encoding};
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};

/// The largest raw magnitude (`2^MAX_BITS`) an exact intermediate may reach: `i128` holds it
/// with room for a sign and a carry.
pub(crate) const MAX_BITS: u32 = 126;

/// A bound on an exact intermediate of a datapath: `|raw| <= 2^bits` at `frac` fraction bits.
/// Units build the spans of their datapaths in `new` and refuse widths whose intermediates
/// would not fit the `i128` of [`Acc`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Span {
    pub bits: u32,
    pub frac: u32,
}

impl Span {
    /// The span of a port word read by [`Acc::from_code`] (unit codecs replicate to 2n bits).
    pub(crate) fn of(enc: &Encoding) -> Span {
        let w = enc.width();
        match enc.codec {
            Codec::Fixed => Span {
                bits: if enc.format.signed { w - 1 } else { w },
                frac: enc.format.frac as u32,
            },
            Codec::UnitSigned => Span {
                bits: w - 1,
                frac: w - 1,
            },
            Codec::UnitUnsigned | Codec::UnitSymmetric => Span {
                bits: 2 * w,
                frac: 2 * w,
            },
        }
    }
    /// The span of an exact product.
    pub(crate) fn mul(self, o: Span) -> Span {
        Span {
            bits: self.bits + o.bits,
            frac: self.frac + o.frac,
        }
    }
    /// The span of an exact sum or difference (aligned as [`Acc::add`] aligns).
    pub(crate) fn add(self, o: Span) -> Span {
        let f = self.frac.max(o.frac);
        Span {
            bits: (self.bits + f - self.frac).max(o.bits + f - o.frac) + 1,
            frac: f,
        }
    }
    /// The span of a two-term cross-product component `a_i b_j - a_j b_i`.
    pub(crate) fn cross(self, o: Span) -> Span {
        let p = self.mul(o);
        p.add(p)
    }
    /// An error unless the span fits.
    pub(crate) fn check(self, what: &str) -> Result<Span, String> {
        if self.bits > MAX_BITS || self.frac > MAX_BITS {
            Err(format!(
                "{what} needs {} bits at {} fraction bits, more than the {MAX_BITS} bits of \
                 the exact intermediate: narrow the input formats or value_bits",
                self.bits, self.frac
            ))
        } else {
            Ok(self)
        }
    }
    /// Check the cast of a value of this span, shifted by `2^k` for `k` in `k_range`
    /// (`(0, 0)` when there is no shift), into `out` by [`cast`].
    pub(crate) fn check_cast(
        self,
        what: &str,
        k_range: (i64, i64),
        out: &Encoding,
    ) -> Result<(), String> {
        let (kmin, kmax) = k_range;
        // shift_pow2: fraction bits go first, then the raw word grows
        let mut frac_min = self.frac as i64 - kmax;
        let mut bits = self.bits as i64;
        if frac_min < 0 {
            bits -= frac_min;
            frac_min = 0;
        }
        let frac_max = self.frac as i64 - kmin;
        let n = out.width() as i64;
        let bits = match out.codec {
            Codec::Fixed => bits,
            Codec::UnitSigned => bits + (n - 1 - frac_min).max(0),
            Codec::UnitUnsigned => bits + n,
            Codec::UnitSymmetric => (bits + n).max(frac_max) + 1,
        };
        let span = Span {
            bits: bits.max(0) as u32,
            frac: frac_max.max(0) as u32,
        };
        span.check(&format!("{what} cast into {out}")).map(|_| ())
    }
}

/// Cast an exact result into an output encoding ([`Acc::to_code`]), first widening the
/// fraction of a value with fewer fraction bits than a `UnitSigned` output reads (the value
/// is unchanged).
pub(crate) fn cast(a: Acc, out: &Encoding) -> i64 {
    let n = out.width();
    let a = if out.codec == Codec::UnitSigned && a.frac + 1 < n {
        Acc::new(a.raw << (n - 1 - a.frac), n - 1)
    } else {
        a
    };
    a.to_code(out)
}

/// `a x b` exactly.
pub(crate) fn cross_acc(a: [Acc; 3], b: [Acc; 3]) -> [Acc; 3] {
    [
        a[1].mul(b[2]).sub(a[2].mul(b[1])),
        a[2].mul(b[0]).sub(a[0].mul(b[2])),
        a[0].mul(b[1]).sub(a[1].mul(b[0])),
    ]
}

/// `a x b` in f64.
pub(crate) fn cross_f64(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The lanes of a port word read into the datapath.
pub(crate) fn accs<const N: usize>(w: &Word, enc: &Encoding) -> [Acc; N] {
    std::array::from_fn(|i| Acc::from_code(w.lanes[i].raw, enc))
}

/// `n = base + d0 u + d1 v` (Ernst et al. 1998 §3.2 `N' = N + A V`, §3.5, §3.1). Inputs
/// `base`, `u`, `v` (3 lanes each), `d` (2 lanes: the bump map's offsets); output `n`
/// (3 lanes). See the module documentation.
pub struct Perturb {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
}

impl Perturb {
    /// The encodings of the base normal, the two axes, the offsets and the output.
    pub fn new(
        base: Encoding,
        axis_u: Encoding,
        axis_v: Encoding,
        offsets: Encoding,
        out: Encoding,
    ) -> Result<Self, String> {
        let d = Span::of(&offsets);
        let sum = Span::of(&base)
            .add(d.mul(Span::of(&axis_u)))
            .add(d.mul(Span::of(&axis_v)))
            .check("perturb: base + d0 u + d1 v")?;
        sum.check_cast("perturb: n", (0, 0), &out)?;
        Ok(Perturb {
            inputs: vec![
                PortSpec::new("base", 3, base),
                PortSpec::new("u", 3, axis_u),
                PortSpec::new("v", 3, axis_v),
                PortSpec::new("d", 2, offsets),
            ],
            outputs: vec![PortSpec::new("n", 3, out)],
        })
    }
}

impl Unit for Perturb {
    fn kind(&self) -> &'static str {
        "perturb"
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
        let [wb, wu, wv, wd] = [0, 1, 2, 3].map(|i| self.inputs[i].enc.width());
        let wo = self.outputs[0].enc.width();
        let aw = (wd + wu.max(wv)).max(wb) + 2;
        let mut g = GateBudget::new();
        g.add(format!("multiplier {wd}x{wu}"), 3, t.multiplier(wd, wu));
        g.add(format!("multiplier {wd}x{wv}"), 3, t.multiplier(wd, wv));
        g.add(format!("adder {aw}"), 6, t.adder(aw));
        g.add(format!("output saturation {wo}"), 3, t.clamp(wo));
        let pipe = 3 * (wd + wu) + 3 * (wd + wv) + 3 * wb;
        g.add(format!("product register {pipe}"), 1, t.register(pipe));
        g.add(format!("output register {}", 3 * wo), 1, t.register(3 * wo));
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.outputs[0].enc;
        let (base, u, v, d) = (&ins[0], &ins[1], &ins[2], &ins[3]);
        match mode {
            Mode::Exact => {
                let [d0, d1] = d.xs::<2>();
                let (b, u, v) = (base.xs::<3>(), u.xs::<3>(), v.xs::<3>());
                let n: [f64; 3] = std::array::from_fn(|j| b[j] + d0 * u[j] + d1 * v[j]);
                outs[0] = Word::from_exact(&out, &n);
            }
            Mode::BitAccurate => {
                let b = accs::<3>(base, &self.inputs[0].enc);
                let u = accs::<3>(u, &self.inputs[1].enc);
                let v = accs::<3>(v, &self.inputs[2].enc);
                let [d0, d1] = accs::<2>(d, &self.inputs[3].enc);
                let n: [i64; 3] =
                    std::array::from_fn(|j| cast(b[j].add(d0.mul(u[j])).add(d1.mul(v[j])), &out));
                outs[0] = Word::from_raw(&out, &n);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Format, Overflow, Quant};
    use proptest::prelude::*;

    fn eval(u: &Perturb, mode: Mode, ins: &[Word; 4]) -> Word {
        let mut o = [Word::default()];
        u.eval(mode, ins, &mut o);
        o[0]
    }

    fn exact_sum(ins: &[Word; 4]) -> [f64; 3] {
        let [d0, d1] = ins[3].xs::<2>();
        let (b, u, v) = (ins[0].xs::<3>(), ins[1].xs::<3>(), ins[2].xs::<3>());
        std::array::from_fn(|j| b[j] + d0 * u[j] + d1 * v[j])
    }

    #[test]
    fn exact_mode_is_the_f64_sum() {
        let e = Encoding::fixed(Format::s(12, 8));
        let u = Perturb::new(e, e, e, e, e).unwrap();
        let ins = [
            Word::from_exact(&e, &[0.1, -0.2, 0.9]),
            Word::from_exact(&e, &[-1.0, 0.0, 0.0]),
            Word::from_exact(&e, &[0.0, -0.7, 0.3]),
            Word::from_exact(&e, &[0.25, -0.5]),
        ];
        let n = eval(&u, Mode::Exact, &ins);
        let want = [0.1 - 0.25, -0.2 + 0.35, 0.9 - 0.15];
        for (g, w) in n.xs::<3>().iter().zip(want) {
            assert!((g - w).abs() < 1e-15, "{g} vs {w}");
        }
        assert_eq!(n.raws::<3>(), want.map(|x| e.encode(x)));
    }

    /// Every per-lane combination of 4-bit codes: lane j of the output depends on
    /// `(base_j, u_j, v_j, d0, d1)` only, so 16^5 evaluations with the three lanes carrying
    /// rotated copies of the five codes cover all of them. The exact value is exact in f64
    /// here, so the bound is the output rounding itself: the bit-accurate word must equal
    /// `out.encode(exact)` (round to nearest, or saturate) for every input, and the error is
    /// at most half an output LSB where the sum is in range.
    #[test]
    fn exhaustive_4_bit_lanes_equal_the_rounded_exact_sum() {
        let s13 = Encoding::fixed(Format::s(4, 3)); // [-1, 0.875]
        let s22 = Encoding::fixed(Format::s(4, 2)); // [-2, 1.75]
        let u22 = Encoding::fixed(Format::u(4, 2)); // [0, 3.75]
        let sym = Encoding::texel(Codec::UnitSymmetric, true, 4);
        for (out, exact_out) in [
            (Encoding::fixed(Format::s(10, 6)), true), // every sum's grid: no rounding
            (Encoding::fixed(Format::s(6, 2)), false), // rounds; saturates beyond [-8, 7.75]
            (
                Encoding {
                    quant: Quant::Trn,
                    overflow: Overflow::Wrap,
                    ..Encoding::fixed(Format::s(6, 3))
                },
                false,
            ),
        ] {
            for (eb, eu, ev, ed) in [(s13, s13, s13, s13), (u22, s22, s13, s22)] {
                let u = Perturb::new(eb, eu, ev, ed, out).unwrap();
                let codes = |e: &Encoding| e.format.min_raw()..=e.format.max_raw();
                let mut worst: f64 = 0.0;
                let max = out.decode(out.format.max_raw());
                for d0 in codes(&ed) {
                    for d1 in codes(&ed) {
                        for b in codes(&eb) {
                            for a in codes(&eu) {
                                for c in codes(&ev) {
                                    let rot = |x: i64, e: &Encoding| {
                                        let n = e.format.max_raw() - e.format.min_raw() + 1;
                                        let m = e.format.min_raw();
                                        [x, m + (x - m + 5) % n, m + (x - m + 11) % n]
                                    };
                                    let ins = [
                                        Word::from_raw(&eb, &rot(b, &eb)),
                                        Word::from_raw(&eu, &rot(a, &eu)),
                                        Word::from_raw(&ev, &rot(c, &ev)),
                                        Word::from_raw(&ed, &[d0, d1]),
                                    ];
                                    let got = eval(&u, Mode::BitAccurate, &ins);
                                    let exact = exact_sum(&ins);
                                    assert_eq!(got.raws::<3>(), exact.map(|x| out.encode(x)));
                                    for (g, x) in got.xs::<3>().iter().zip(exact) {
                                        if x.abs() <= max {
                                            worst = worst.max((g - x).abs());
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
                println!("perturb 4-bit lanes exhaustive into {out}: worst {worst}");
                if exact_out {
                    assert_eq!(worst, 0.0, "s4.6 holds every sum on its grid");
                } else {
                    assert!(worst <= out.max_error() && worst > 0.0, "{worst}");
                }
            }
        }
        // integer inputs (no fraction bits) into a UnitSigned output: the cast widens the
        // fraction first; sums of -1 and 0 are representable, the rest saturate
        let int = Encoding::fixed(Format::s(4, 0));
        let out = Encoding::texel(Codec::UnitSigned, true, 8);
        let u = Perturb::new(int, int, int, int, out).unwrap();
        let ins = [
            Word::from_raw(&int, &[-1, 0, 3]),
            Word::from_raw(&int, &[0, 0, 1]),
            Word::from_raw(&int, &[0, 0, 1]),
            Word::from_raw(&int, &[2, -1]),
        ];
        assert_eq!(
            eval(&u, Mode::BitAccurate, &ins).raws::<3>(),
            [-128, 0, 127]
        );
        // a unit codec on the axes (bit replication) and a UnitSigned output
        let out = Encoding::texel(Codec::UnitSigned, true, 8);
        let u = Perturb::new(s13, sym, sym, s13, out).unwrap();
        let mut worst: f64 = 0.0;
        for d0 in -8..8 {
            for d1 in -8..8 {
                for a in -8..8 {
                    let ins = [
                        Word::from_raw(&s13, &[0, 2, 5]),
                        Word::from_raw(&sym, &[a, -a - 1, 3]),
                        Word::from_raw(&sym, &[-4, a, a / 2]),
                        Word::from_raw(&s13, &[d0, d1]),
                    ];
                    let got = eval(&u, Mode::BitAccurate, &ins);
                    for (g, x) in got.xs::<3>().iter().zip(exact_sum(&ins)) {
                        if x.abs() < 0.99 {
                            worst = worst.max((g - x).abs());
                        }
                    }
                }
            }
        }
        println!("perturb UnitSymmetric axes into UnitSigned 8: worst {worst}");
        // half an output LSB, plus the replication's relative 2^-8 on |d u + d v| <= 2
        assert!(worst <= out.max_error() + 2.0 * 2f64.powi(-8), "{worst}");
    }

    #[test]
    fn widths_beyond_the_exact_intermediate_are_refused() {
        let w = Encoding::texel(Codec::UnitSymmetric, true, 32);
        let err = Perturb::new(w, w, w, w, w).err().unwrap();
        assert!(err.contains("more than the 126 bits"), "{err}");
        let e = Encoding::fixed(Format::s(32, 30));
        assert!(Perturb::new(e, e, e, e, e).is_ok());
    }

    #[test]
    fn gates_are_itemised_and_positive() {
        // the configs: s2.8 base, axes and offsets, s4.8 out
        let e = Encoding::fixed(Format::s(10, 8));
        let u = Perturb::new(e, e, e, e, Encoding::fixed(Format::s(12, 8))).unwrap();
        let g = u.gates(&CostTable::default());
        for i in &g.items {
            println!("perturb gates: {:>10.1}  {}", i.ge, i.what);
        }
        println!("perturb gates at s2.8 -> s4.8: {:.1}", g.total());
        assert!(g.total() > 0.0);
        assert!(g.items.iter().any(|i| i.what == "multiplier 10x10"));
        assert_eq!((u.latency(), u.interval()), (2, 1));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        /// Wide widths: 16-bit lanes keep every sum within f64's 53 bits, so the exact value
        /// is exact and the bit-accurate word must still equal `out.encode(exact)`; the error
        /// is at most half an output LSB.
        #[test]
        fn wide_widths_equal_the_rounded_exact_sum(
            fb in 0u8..=15, fu in 0u8..=15, fd in 0u8..=15, fo in 4u8..=20,
            raws in proptest::collection::vec(-32768i64..32768, 11),
        ) {
            let eb = Encoding::fixed(Format::s(16, fb));
            let eu = Encoding::fixed(Format::s(16, fu));
            let ed = Encoding::fixed(Format::s(16, fd));
            let out = Encoding::fixed(Format::s(24, fo));
            let u = Perturb::new(eb, eu, eu, ed, out).unwrap();
            let ins = [
                Word::from_raw(&eb, &raws[0..3]),
                Word::from_raw(&eu, &raws[3..6]),
                Word::from_raw(&eu, &raws[6..9]),
                Word::from_raw(&ed, &raws[9..11]),
            ];
            let got = eval(&u, Mode::BitAccurate, &ins);
            let exact = exact_sum(&ins);
            prop_assert_eq!(got.raws::<3>(), exact.map(|x| out.encode(x)));
            let max = out.format.max_raw() as f64 * out.format.lsb();
            for (g, x) in got.xs::<3>().iter().zip(exact) {
                if x.abs() < max {
                    prop_assert!((g - x).abs() <= out.max_error());
                }
            }
        }
    }
}

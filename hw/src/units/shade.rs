//! Light combiner: sums per-light diffuse and specular intensities into a colour.
//!
//! `C = C_src + ka (*) base + sum_i Lc_i (*) (kd (*) base d_i + ks s_i)`, clamped by the output
//! encoding. This is the blending equation of Ernst et al. 1998 §4.2,
//! `C_new = C_src + sum_i (fd_i + fs_i) k_i L_i` (with `k_i = 1`, their sample implementation),
//! extended with the material's diffuse and specular colours and an optional base colour
//! (a texel) so that the same unit finishes the SGI tangent-space engine (§3.4) and the
//! emboss shader (Lingard: "the shading result can be used for a grey scale image or applied
//! against another texture image").
//!
//! Lights are accumulated over `ceil(k / parallel)` clocks by `parallel` multiply-add
//! datapaths ("n light sources are blended in n clock cycles, avoiding n times the hardware").
//! The per-light products `kd (*) Lc_i` and `ks (*) Lc_i` are held in registers loaded by the
//! host once per frame, quantized to the coefficient encoding. The sum is exact and cast once
//! into the output encoding.

use crate::arith::{Acc, Reader, Writer};
use crate::columns::{Column, ColumnIn};
use crate::format::{Codec, Encoding};
use crate::frame::FrameInputs;
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};

/// Constant inputs of the combiner, in f64 (quantized by the unit in bit-accurate mode).
#[derive(Debug, Clone, PartialEq)]
pub struct ShadeParams {
    pub ambient: [f64; 3],
    pub diffuse: [f64; 3],
    pub specular: [f64; 3],
    pub light_colors: Vec<[f64; 3]>,
}

/// Which optional inputs the combiner has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShadeInputs {
    /// Encoding of the specular intensities `s_i`, when the unit has them.
    pub specular: Option<Encoding>,
    /// A 3-lane base colour (texel); white when absent.
    pub base: Option<Encoding>,
    /// A 3-lane source colour added unchanged (the Gouraud colour `C_src`).
    pub src: Option<Encoding>,
}

pub struct Shade {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    params: ShadeParams,
    has: ShadeInputs,
    coef: Encoding,
    parallel: u32,
    /// Quantized coefficients: ka, then kd*Lc_i and ks*Lc_i per light.
    ka: [Acc; 3],
    kdl: Vec<[Acc; 3]>,
    ksl: Vec<[Acc; 3]>,
    /// Input indices of the optional `base` and `src` ports (found once, not per fragment).
    base_port: Option<usize>,
    src_port: Option<usize>,
    /// The bit-accurate sum in `i64`, where every term fits ([`Fast`]).
    fast: Option<Fast>,
}

/// Shade's exact sum in `i64`: the same terms as the `Acc` datapath, each read by its port's
/// [`Reader`] and shifted to the sum's fraction bits, where the whole sum is known to stay
/// below 2^62 (so it equals the `i128` sum).
struct Fast {
    d: Reader,
    s: Option<Reader>,
    base: Option<Reader>,
    src: Option<Reader>,
    ka: [i64; 3],
    kdl: Vec<[i64; 3]>,
    ksl: Vec<[i64; 3]>,
    /// Left shifts of the src, ambient, diffuse and specular terms to `frac`.
    shift: [u32; 4],
    /// The writer of the sum, which has `frac` fraction bits, into the output encoding.
    out: Writer,
}

impl Fast {
    fn new(
        intensity: &Encoding,
        has: &ShadeInputs,
        coef: &Encoding,
        k: usize,
        out: &Encoding,
    ) -> Option<Fast> {
        let (d, kc) = (Reader::new(intensity)?, Reader::new(coef)?);
        let opt = |e: &Option<Encoding>| {
            e.as_ref()
                .map(Reader::new)
                .map_or(Some(None), |r| r.map(Some))
        };
        let (s, base, src) = (opt(&has.specular)?, opt(&has.base)?, opt(&has.src)?);
        // (fraction bits, magnitude bits) of each term; base 1 is (0, 1)
        let (bf, bb) = base.map_or((0, 1), |r| (r.frac, r.bits));
        let terms = [
            src.map(|r| (r.frac, r.bits)),
            Some((kc.frac + bf, kc.bits + bb)),
            (k > 0).then_some((kc.frac + bf + d.frac, kc.bits + bb + d.bits)),
            s.filter(|_| k > 0)
                .map(|r| (kc.frac + r.frac, kc.bits + r.bits)),
        ];
        let frac = terms.iter().flatten().map(|t| t.0).max()?;
        let count = 2 + 2 * k as u32; // terms summed, at most
        let widest = terms.iter().flatten().map(|t| t.1 + frac - t.0).max()?;
        if widest + (32 - count.leading_zeros()) > 62 {
            return None;
        }
        let shift = terms.map(|t| t.map_or(0, |t| frac - t.0));
        Some(Fast {
            d,
            s,
            base,
            src,
            ka: [0; 3],
            kdl: Vec::new(),
            ksl: Vec::new(),
            shift,
            out: Writer::new(frac, out),
        })
    }
}

impl Shade {
    /// `intensity` is the encoding of the diffuse inputs `d_i`.
    pub fn new(
        intensity: Encoding,
        has: ShadeInputs,
        params: ShadeParams,
        coef: Encoding,
        parallel: u32,
        out: Encoding,
    ) -> Self {
        let k = params.light_colors.len() as u32;
        let mut inputs: Vec<PortSpec> = (0..k)
            .map(|i| PortSpec::new(&format!("d{i}"), 1, intensity))
            .collect();
        if let Some(e) = has.specular {
            inputs.extend((0..k).map(|i| PortSpec::new(&format!("s{i}"), 1, e)));
        }
        if let Some(e) = has.base {
            inputs.push(PortSpec::new("base", 3, e));
        }
        if let Some(e) = has.src {
            inputs.push(PortSpec::new("src", 3, e));
        }
        let q = |x: f64| Acc::from_code(coef.encode(x), &coef);
        let ka = params.ambient.map(q);
        let kdl: Vec<[Acc; 3]> = params
            .light_colors
            .iter()
            .map(|lc| std::array::from_fn(|c| q(params.diffuse[c] * lc[c])))
            .collect();
        let ksl: Vec<[Acc; 3]> = params
            .light_colors
            .iter()
            .map(|lc| std::array::from_fn(|c| q(params.specular[c] * lc[c])))
            .collect();
        let base_port = crate::unit::port_index(&inputs, "base");
        let src_port = crate::unit::port_index(&inputs, "src");
        let fast = Fast::new(&intensity, &has, &coef, k as usize, &out).map(|f| {
            let raw = |a: &[Acc; 3]| a.map(|a| a.raw as i64);
            Fast {
                ka: raw(&ka),
                kdl: kdl.iter().map(raw).collect(),
                ksl: ksl.iter().map(raw).collect(),
                ..f
            }
        });
        Shade {
            fast,
            base_port,
            src_port,
            inputs,
            outputs: vec![PortSpec::new("color", 3, out)],
            params,
            has,
            coef,
            parallel: parallel.clamp(1, k.max(1)),
            ka,
            kdl,
            ksl,
        }
    }

    fn k(&self) -> usize {
        self.params.light_colors.len()
    }
}

impl ShadeParams {
    /// The frame's registers: material 0's coefficients and the bump lights' colours.
    pub fn from_frame(f: &FrameInputs) -> Result<ShadeParams, String> {
        let m = f.material(0)?;
        Ok(ShadeParams {
            ambient: m.ambient,
            diffuse: m.diffuse,
            specular: m.specular,
            light_colors: f.lights.iter().map(|l| l.color).collect(),
        })
    }
}

impl Shade {
    /// The integer datapath's three channel sums, before the output cast, of the inputs whose
    /// raw words `raw(port, lane)` gives: the sums light by light (integer sums in any order).
    #[inline(always)]
    fn fast_sums(&self, f: &Fast, raw: impl Fn(usize, usize) -> i64) -> [i64; 3] {
        let k = self.k();
        let [s_src, s_ka, s_kd, s_ks] = f.shift;
        let read = |p: Option<usize>, r: Option<Reader>, c: usize| {
            p.zip(r).map(|(p, r)| r.read(raw(p, c)))
        };
        let b: [i64; 3] = std::array::from_fn(|c| read(self.base_port, f.base, c).unwrap_or(1));
        let mut v: [i64; 3] = std::array::from_fn(|c| {
            (read(self.src_port, f.src, c).unwrap_or(0) << s_src) + ((f.ka[c] * b[c]) << s_ka)
        });
        for i in 0..k {
            let d = f.d.read(raw(i, 0));
            for ((v, kd), b) in v.iter_mut().zip(f.kdl[i]).zip(b) {
                *v += (kd * b * d) << s_kd;
            }
            let spec = self.has.specular.and(f.s);
            if let Some(s) = spec.map(|r| r.read(raw(k + i, 0))) {
                for (v, ks) in v.iter_mut().zip(f.ksl[i]) {
                    *v += (ks * s) << s_ks;
                }
            }
        }
        v
    }
}

impl Unit for Shade {
    fn kind(&self) -> &'static str {
        "shade"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        self.interval() + 2
    }
    /// Reloads `ka`, `kd Lc_i` and `ks Lc_i` ([`ShadeParams::from_frame`]).
    fn begin_frame(&mut self, f: &FrameInputs) -> Result<(), String> {
        f.expect_lights(self.k(), "the light combiner")?;
        *self = Shade::new(
            self.inputs[0].enc,
            self.has,
            ShadeParams::from_frame(f)?,
            self.coef,
            self.parallel,
            self.outputs[0].enc,
        );
        Ok(())
    }
    fn interval(&self) -> u32 {
        (self.k() as u32).div_ceil(self.parallel).max(1)
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let ie = self.inputs.first().map_or(self.coef, |p| p.enc);
        let wi = ie.width();
        let wb = self.has.base.map_or(0, |e| e.width());
        let wc = self.coef.width();
        let out = self.outputs[0].enc;
        let wo = out.width();
        // The bit-accurate datapath keeps every product exact, so the adders and the
        // accumulator are priced at the width of the exact sum (`exact_sum_bits`: the
        // products' code bits, aligned to the finest fraction, with the bit replication of
        // `c / (2^n - 1)` reads) plus the growth of k + 2 terms.
        let wd = if wb > 0 { wi + wb } else { wi };
        let ws = self.has.specular.map_or(0, |e| e.width());
        let growth = 32 - (self.k() as u32 + 2).leading_zeros();
        let mut diffuse = vec![self.coef, ie];
        diffuse.extend(self.has.base);
        let mut terms = vec![Term::of(&diffuse)];
        if let Some(se) = self.has.specular {
            terms.push(Term::of(&[self.coef, se]));
        }
        let acc = exact_sum_bits(&terms) + growth;
        let p = self.parallel;
        let mut g = GateBudget::new();
        if wb > 0 {
            g.add(
                format!("base x intensity multiplier {wi}x{wb}"),
                3 * p,
                t.multiplier(wi, wb),
            );
            g.add(
                format!("ambient multiplier {wb}x{wc}"),
                3,
                t.multiplier(wb, wc),
            );
        }
        g.add(
            format!("diffuse coefficient multiplier {wd}x{wc}"),
            3 * p,
            t.multiplier(wd, wc),
        );
        if self.has.specular.is_some() {
            g.add(
                format!("specular coefficient multiplier {ws}x{wc}"),
                3 * p,
                t.multiplier(ws, wc),
            );
            // a product read with more bit replications than the other is aligned to it by
            // a shift and add per extra replication
            for (name, term) in ["diffuse", "specular"].iter().zip(&terms) {
                let extra = term.reps.len() - common_reps(&terms).len();
                if extra > 0 {
                    g.add(
                        format!("{name} replication adder {}", term.bits),
                        3 * p * extra as u32,
                        t.adder(term.bits),
                    );
                }
            }
            g.add(format!("adder {acc}"), 3 * p, t.adder(acc));
        }
        g.add(format!("accumulator adder {acc}"), 3 * p, t.adder(acc));
        g.add(format!("accumulator register {acc}"), 3, t.register(acc));
        // the ambient code lands on the accumulator's top bits (its fraction is coarser)
        let wamb = wc + wb + growth + 1;
        g.add(format!("ambient adder {wamb}"), 3, t.adder(wamb));
        if self.has.src.is_some() {
            g.add(format!("source colour adder {acc}"), 3, t.adder(acc));
        }
        // the exact cast: the sum's common factor prod (2^n + 1) of its replicated reads and,
        // for the unit codecs, x (2^n - 1), folded into one constant whose signed digits are
        // the shifts and adds (8-bit codes: 2^16 - 1, one subtractor; 12-bit coefficients into
        // 8 bits: 2^20 - 2^12 + 2^8 - 1, three); the rounding rides on them
        let unit_out = matches!(out.codec, Codec::UnitUnsigned | Codec::UnitSymmetric);
        let mut factors: Vec<u128> = common_reps(&terms)
            .iter()
            .map(|&n| (1u128 << n) + 1)
            .collect();
        if unit_out {
            factors.push((1u128 << wo) - 1);
        }
        // (three 32-bit codes overflow the folded constant: then each factor apart, one
        // adder each, an upper bound)
        let (k, cast) = match factors.iter().try_fold(1u128, |k, &f| k.checked_mul(f)) {
            Some(k) => (k.to_string(), t.constant_multiplier(acc, k)),
            None => (
                factors
                    .iter()
                    .map(u128::to_string)
                    .collect::<Vec<_>>()
                    .join("x"),
                factors.len() as f64 * t.adder(acc),
            ),
        };
        if cast > 0.0 {
            g.add(format!("output cast x{k} and rounding {acc}"), 3, cast);
        }
        if !unit_out {
            g.add(format!("output rounding {wo}"), 3, t.half_adder * wo as f64);
        }
        g.add(format!("output clamp {wo}"), 3, t.clamp(wo));
        g.add(format!("output register {}", 3 * wo), 1, t.register(3 * wo));
        let per_light = 3 * (1 + self.has.specular.is_some() as u32);
        let coefs = 3 + self.k() as u32 * per_light;
        g.add(
            format!("coefficient registers {coefs}x{wc}"),
            1,
            t.register(coefs * wc),
        );
        if self.interval() > 1 {
            g.add(
                format!("light mux {}:1 x{}", self.interval(), 2 * wi),
                p,
                t.mux(2 * wi, self.interval()),
            );
            g.add(
                format!(
                    "coefficient select mux {}:1 x{}",
                    self.interval(),
                    per_light * wc
                ),
                p,
                t.mux(per_light * wc, self.interval()),
            );
        }
        g
    }
    fn eval_columns(&self, n: usize, ins: &[ColumnIn<'_>], outs: &mut [&mut Column]) -> bool {
        let Some(f) = self.fast.as_ref() else {
            return false;
        };
        let o = &mut outs[0];
        for k in 0..n {
            let v = self.fast_sums(f, |p, l| ins[p].lanes[l][k]);
            for (o, v) in o.iter_mut().zip(v) {
                o[k] = f.out.write(v);
            }
        }
        true
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.outputs[0].enc;
        let k = self.k();
        let spec = |i: usize| self.has.specular.map(|_| &ins[k + i]);
        let base = self.base_port.map(|i| &ins[i]);
        let src = self.src_port.map(|i| &ins[i]);
        match mode {
            Mode::Exact => {
                let p = &self.params;
                let c: [f64; 3] = std::array::from_fn(|c| {
                    let b = base.map_or(1.0, |w| w.lanes[c].x);
                    let mut v = src.map_or(0.0, |w| w.lanes[c].x) + p.ambient[c] * b;
                    for (i, lc) in p.light_colors.iter().enumerate() {
                        let s = spec(i).map_or(0.0, |w| w.lanes[0].x);
                        v += lc[c] * (p.diffuse[c] * b * ins[i].lanes[0].x + p.specular[c] * s);
                    }
                    v
                });
                outs[0] = Word::from_exact(&out, &c);
            }
            Mode::BitAccurate if self.fast.is_some() => {
                let f = self.fast.as_ref().expect("checked");
                let v = self.fast_sums(f, |p, l| ins[p].lanes[l].raw);
                outs[0] = Word::from_raw(&out, &v.map(|v| f.out.write(v)));
            }
            Mode::BitAccurate => {
                let rd = |w: &Word, l: usize, e: &Encoding| Acc::from_code(w.lanes[l].raw, e);
                let ie = self.inputs.first().map_or(self.coef, |p| p.enc);
                let codes: [i64; 3] = std::array::from_fn(|c| {
                    let b = base.map_or(Acc::new(1, 0), |w| rd(w, c, &self.has.base.unwrap()));
                    let mut v = src.map_or(Acc::ZERO, |w| rd(w, c, &self.has.src.unwrap()));
                    v = v.add(self.ka[c].mul(b));
                    for (i, d) in ins.iter().enumerate().take(k) {
                        v = v.add(self.kdl[i][c].mul(b.mul(rd(d, 0, &ie))));
                        if let (Some(s), Some(se)) = (spec(i), &self.has.specular) {
                            v = v.add(self.ksl[i][c].mul(rd(s, 0, se)));
                        }
                    }
                    v.to_code(&out)
                });
                outs[0] = Word::from_raw(&out, &codes);
            }
        }
    }
}

/// One product of the combiner's sum, for its gate estimate: the code bits of its operands,
/// its fraction bits as [`Acc`] reads them, and the widths of the operands read by bit
/// replication (`c (2^n + 1)` for the `c / (2^n - 1)` codecs).
struct Term {
    bits: u32,
    frac: u32,
    reps: Vec<u32>,
}

impl Term {
    fn of(operands: &[Encoding]) -> Term {
        let mut t = Term {
            bits: 0,
            frac: 0,
            reps: Vec::new(),
        };
        for e in operands {
            let n = e.width();
            t.bits += n;
            t.frac += match e.codec {
                Codec::Fixed => e.format.frac as u32,
                Codec::UnitSigned => n - 1,
                Codec::UnitUnsigned | Codec::UnitSymmetric => {
                    t.reps.push(n);
                    2 * n
                }
            };
        }
        t.reps.sort_unstable();
        t
    }
}

/// `a` without the elements of `b` (multisets).
fn minus(a: &[u32], b: &[u32]) -> Vec<u32> {
    let mut rest = b.to_vec();
    a.iter()
        .copied()
        .filter(|x| match rest.iter().position(|y| y == x) {
            Some(i) => {
                rest.remove(i);
                false
            }
            None => true,
        })
        .collect()
}

/// The replications every term shares (kept as a common factor of the sum).
fn common_reps(terms: &[Term]) -> Vec<u32> {
    let mut c = terms[0].reps.clone();
    for t in &terms[1..] {
        c = minus(&c, &minus(&c, &t.reps));
    }
    c
}

/// Bits of the exact sum of the terms: each aligned to the finest fraction, with its
/// replications beyond the common ones applied (`n + 1` bits each).
fn exact_sum_bits(terms: &[Term]) -> u32 {
    let f = terms.iter().map(|t| t.frac).max().unwrap_or(0);
    let c = common_reps(terms);
    terms
        .iter()
        .map(|t| {
            let extra: u32 = minus(&t.reps, &c).iter().map(|n| n + 1).sum();
            t.bits + extra + (f - t.frac)
        })
        .max()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Codec, Format};

    fn unit(parallel: u32) -> Shade {
        let i = Encoding::fixed(Format::u(9, 8));
        let params = ShadeParams {
            ambient: [0.1, 0.1, 0.1],
            diffuse: [0.8, 0.6, 0.4],
            specular: [0.5, 0.5, 0.5],
            light_colors: vec![[1.0, 1.0, 1.0], [0.5, 0.0, 0.5]],
        };
        let has = ShadeInputs {
            specular: Some(i),
            base: None,
            src: None,
        };
        let out = Encoding::texel(Codec::UnitUnsigned, false, 8);
        Shade::new(
            i,
            has,
            params,
            Encoding::texel(Codec::UnitUnsigned, false, 8),
            parallel,
            out,
        )
    }

    /// Port encodings the tests draw from: unit codes of 4 to 16 bits, fixed point.
    fn encoding(k: usize) -> Encoding {
        [
            Encoding::texel(Codec::UnitUnsigned, false, 8),
            Encoding::texel(Codec::UnitUnsigned, false, 12),
            Encoding::texel(Codec::UnitSigned, true, 8),
            Encoding::texel(Codec::UnitSymmetric, true, 8),
            Encoding::texel(Codec::UnitUnsigned, false, 16),
            Encoding::fixed(Format::u(9, 8)),
            Encoding::fixed(Format::s(10, 8)),
            Encoding::texel(Codec::UnitUnsigned, false, 4),
        ][k % 8]
    }

    proptest::proptest! {
        #[test]
        fn the_i64_sum_is_the_i128_sum(
            lights in 0usize..4,
            pick in proptest::array::uniform6(0usize..8),
            present in proptest::array::uniform3(proptest::bool::ANY),
            colors in proptest::array::uniform12(0.0f64..1.0),
            codes in proptest::collection::vec(proptest::num::i64::ANY, 24),
        ) {
            let [ei, es, eb, ec, ecoef, eo] = pick.map(encoding);
            let has = ShadeInputs {
                specular: present[0].then_some(es),
                base: present[1].then_some(eb),
                src: present[2].then_some(ec),
            };
            let params = ShadeParams {
                ambient: [colors[0], colors[1], colors[2]],
                diffuse: [colors[3], colors[4], colors[5]],
                specular: [colors[6], colors[7], colors[8]],
                light_colors: (0..lights).map(|l| [colors[9 + l % 3], colors[9], colors[11 - l % 3]]).collect(),
            };
            let fast = Shade::new(ei, has, params.clone(), ecoef, 1, eo);
            proptest::prop_assume!(fast.fast.is_some());
            let wide = Shade {
                fast: None,
                ..Shade::new(ei, has, params, ecoef, 1, eo)
            };
            // every input word from the drawn codes, folded into its port's range
            let ins: Vec<Word> = fast
                .inputs
                .iter()
                .enumerate()
                .map(|(p, port)| {
                    let f = port.enc.format;
                    let span = (f.max_raw() - f.min_raw()) as u64 + 1;
                    let raws: Vec<i64> = (0..3)
                        .map(|l| f.min_raw() + (codes[(3 * p + l) % 24] as u64 % span) as i64)
                        .collect();
                    Word::from_raw(&port.enc, &raws)
                })
                .collect();
            let (mut o1, mut o2) = ([Word::default()], [Word::default()]);
            fast.eval(Mode::BitAccurate, &ins, &mut o1);
            wide.eval(Mode::BitAccurate, &ins, &mut o2);
            proptest::prop_assert_eq!(o1, o2);
        }
    }

    #[test]
    fn wide_coefficients_keep_the_i128_sum() {
        // 32-bit unit-code coefficients read in 67 bits: no i64 path
        let i = Encoding::fixed(Format::u(9, 8));
        let has = ShadeInputs {
            specular: Some(i),
            base: None,
            src: None,
        };
        let params = unit(1).params;
        let coef = Encoding::texel(Codec::UnitUnsigned, false, 32);
        assert!(Shade::new(i, has, params.clone(), coef, 1, coef)
            .fast
            .is_none());
        assert!(Shade::new(
            i,
            has,
            params,
            Encoding::texel(Codec::UnitUnsigned, false, 8),
            1,
            coef
        )
        .fast
        .is_some());
        assert!(
            unit(1).fast.is_some(),
            "the bundled widths take the i64 path"
        );
    }

    #[test]
    fn the_cast_is_priced_by_the_digits_of_its_folded_constant() {
        let t = CostTable::default();
        let cast = |coef: Encoding, ie: Encoding, base: Option<Encoding>, out: Encoding| {
            let params = ShadeParams {
                ambient: [0.1; 3],
                diffuse: [0.8; 3],
                specular: [0.0; 3],
                light_colors: vec![[1.0; 3]],
            };
            let has = ShadeInputs {
                specular: None,
                base,
                src: None,
            };
            let g = Shade::new(ie, has, params, coef, 1, out).gates(&t);
            g.items
                .iter()
                .find(|i| i.what.starts_with("output cast"))
                .map(|i| (i.what.clone(), i.ge))
        };
        let fx = Encoding::fixed(Format::u(9, 8));
        let u = |n| Encoding::texel(Codec::UnitUnsigned, false, n);
        // 8-bit coefficients: (2^8 + 1)(2^8 - 1) = 2^16 - 1, one subtractor a channel
        let (what, ge) = cast(u(8), fx, None, u(8)).unwrap();
        assert!(what.starts_with("output cast x65535 "), "{what}");
        let acc: u32 = what.rsplit(' ').next().unwrap().parse().unwrap();
        assert!((ge - 3.0 * t.adder(acc)).abs() < 1e-9);
        // 12-bit: (2^12 + 1)(2^8 - 1) = 2^20 - 2^12 + 2^8 - 1, three adders
        let (what, ge) = cast(u(12), fx, None, u(8)).unwrap();
        let acc: u32 = what.rsplit(' ').next().unwrap().parse().unwrap();
        assert!((ge - 9.0 * t.adder(acc)).abs() < 1e-9, "{what}");
        // three 32-bit replicated reads into a 32-bit code overflow the folded constant
        // (131 bits): priced a factor at a time (four adders a channel), no overflow
        let (what, ge) = cast(u(32), u(32), Some(u(32)), u(32)).unwrap();
        let acc: u32 = what.rsplit(' ').next().unwrap().parse().unwrap();
        assert!((ge - 12.0 * t.adder(acc)).abs() < 1e-9, "{what}");
    }

    #[test]
    fn two_lights_hand_computed() {
        let u = unit(1);
        assert_eq!((u.interval(), u.latency()), (2, 4));
        let e = Encoding::fixed(Format::u(9, 8));
        let w = |x: f64| Word::quantize(&e, &[x]);
        let ins = [w(0.5), w(0.25), w(0.125), w(0.0)];
        let mut o = [Word::default()];
        u.eval(Mode::Exact, &ins, &mut o);
        // r = 0.1 + 1*(0.8*0.5 + 0.5*0.125) + 0.5*(0.8*0.25) = 0.6625
        // g = 0.1 + (0.6*0.5 + 0.0625) + 0 = 0.4625
        // b = 0.1 + (0.4*0.5 + 0.0625) + 0.5*(0.4*0.25) = 0.4125
        let x: [f64; 3] = o[0].xs();
        for (a, b) in x.iter().zip([0.6625, 0.4625, 0.4125]) {
            assert!((a - b).abs() < 1e-12);
        }
        u.eval(Mode::BitAccurate, &ins, &mut o);
        // coefficients rounded to 8 bits (bit-replicated on read), sum cast to 8 bits
        // b: 26/255 + 0.4*0.5 + 128/255*0.125 + 51/255*0.25 = 0.4147 -> 105.75 -> 106
        assert_eq!(o[0].raws::<3>(), [169, 118, 106]);
        assert_eq!(unit(2).interval(), 1);
        assert!(
            unit(2).gates(&CostTable::default()).total()
                > unit(1).gates(&CostTable::default()).total()
        );
    }
}

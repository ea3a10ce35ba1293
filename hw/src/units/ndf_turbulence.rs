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
use crate::rtl::ndf_turbulence::LATENCY;
use crate::rtl::verilog::{signed_bits, unsigned_bits};
use crate::unit::{Mode, PortSpec, Unit, Word};

/// Fraction bits of the index scale.
pub const SCALE_FRAC: u32 = 16;

/// Where octave `k`'s lattice position comes from in the coordinate word (one axis): the
/// low `ubits` bits `r` of the raw word (the coordinate wrapped to `[0, 1)`) times the
/// period, `P = r period`; the cell index is `P >> uv_frac` (in `[0, period)`) and the
/// position in the cell, at the datapath's `frac` bits, is `P[uv_frac - 1 : low] 2^(frac -
/// fb)`: `fb = uv_frac - low` bits that are not always zero (the coordinate's bits below
/// the period's trailing zeros, or below the datapath's fraction bits, are not in it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lattice {
    pub period: u64,
    pub ubits: u32,
    pub low: u32,
    pub fb: u32,
}

impl Lattice {
    /// Bits of the cell index (0 for a one-cell period).
    pub fn index_bits(&self) -> u32 {
        if self.period <= 1 {
            0
        } else {
            64 - (self.period - 1).leading_zeros()
        }
    }
}

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

    pub fn turbulence(&self) -> &Turbulence {
        &self.turbulence
    }
    pub fn octaves(&self) -> u32 {
        self.octaves
    }
    /// Fraction bits of the noise datapath.
    pub fn frac(&self) -> u32 {
        self.frac
    }
    /// The index scale as a code with [`SCALE_FRAC`] fraction bits.
    pub fn scale_raw(&self) -> i64 {
        self.scale_raw
    }
    /// Bits of the index scale's register: [`SCALE_FRAC`], more for a scale of 1 or more.
    pub fn scale_bits(&self) -> u32 {
        (64 - (self.scale_raw as u64).leading_zeros()).max(SCALE_FRAC)
    }

    /// Octave `k`'s lattice geometry on one axis (both axes have the same).
    pub fn lattice(&self, k: u32) -> Lattice {
        let uv = self.inputs[0].enc.format;
        let uf = uv.frac as u32;
        let period = u64::from(self.turbulence.frequency) << k;
        let s = period.trailing_zeros();
        let low = s.max(uf.saturating_sub(self.frac)).min(uf);
        Lattice {
            period,
            ubits: (uv.width as u32).min(uf),
            low,
            fb: uf - low,
        }
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
        // the netlist of `rtl::ndf_turbulence` (docs/units/ndf.md, "Gates"), its widths
        // from the same exact ranges
        let f = self.frac;
        let o = self.octaves;
        let mut g = GateBudget::new();
        let sbits = |lo: i128, hi: i128| signed_bits(lo, hi);
        let (fade_hi, mut nsum) = (1i128 << f, (0i128, 0i128));
        let lod = self.inputs[1].enc;
        let wb = Acc::from_code(0, &lod).frac.min(8);
        for k in 0..o {
            let l = self.lattice(k);
            let (fb, xb) = (l.fb, l.index_bits());
            if xb > 0 {
                if l.period.is_power_of_two() {
                    g.add(
                        format!("octave {k}: neighbour cell incrementer {xb}"),
                        2,
                        t.half_adder * f64::from(xb),
                    );
                } else {
                    g.add(
                        format!(
                            "octave {k}: coordinate x {} ({} bits), cell wrap",
                            l.period, l.ubits
                        ),
                        2,
                        t.constant_multiplier(l.ubits, u128::from(l.period))
                            + t.constant_add(xb)
                            + t.comparator(xb)
                            + t.mux(xb, 2),
                    );
                }
            }
            // the position's two corner offsets fx and fx - 1 (a sign bit), on fb bits
            let p = (1i128 << fb) - 1;
            let (d0, d1) = ((0, p), (-(1i128 << fb), -1));
            if fb > 0 {
                // the fade, per axis (shared by the two noises)
                let q = 2 * fb + 4;
                g.add(format!("octave {k}: fade squarer {fb}"), 2, t.squarer(fb));
                g.add(
                    format!("octave {k}: fade t^2 t {}x{fb}", 2 * fb),
                    2,
                    t.multiplier(2 * fb, fb),
                );
                g.add(
                    format!("octave {k}: fade 6 t^2 - 15 t + 10 ({q} bits)"),
                    2,
                    t.shift_add(2 * fb, 6) + t.shift_add(fb, 15) + t.adder(q) + t.constant_add(4),
                );
                g.add(
                    format!("octave {k}: fade t^3 q {}x{q}", 3 * fb),
                    2,
                    t.multiplier(3 * fb, q),
                );
                if 5 * fb > f {
                    g.add(
                        format!("octave {k}: fade rounding {}", f + 1),
                        2,
                        t.constant_add(f + 1),
                    );
                }
                g.add(
                    format!(
                        "octave {k}: fade and position stage registers {}",
                        f + 2 + fb
                    ),
                    2,
                    t.dff * f64::from(f + 2 + fb),
                );
            }
            // per noise: the hash, the corner dots, the lerps, the weighted term
            if xb > 0 {
                let yb = xb.min(8);
                g.add(
                    format!("octave {k}: hash adder P[i] + j (8 bits, j {yb})"),
                    2 * 4,
                    t.adder(yb) + t.half_adder * f64::from(8 - yb),
                );
            }
            g.add(
                format!("octave {k}: gradient index stage register 4"),
                2 * 4,
                t.dff * 4.0,
            );
            // g . (dx, dy): per term a conditional negation of dx (an incrementer) and a
            // select, and the sum
            let term = |d: (i128, i128)| {
                let mag = d.0.unsigned_abs().max(d.1.unsigned_abs()) as i128;
                (-mag, mag)
            };
            let dot = |a: (i128, i128), b: (i128, i128)| {
                let (ta, tb) = (term(a), term(b));
                (ta.0 + tb.0, ta.1 + tb.1)
            };
            let dots = [dot(d0, d0), dot(d1, d0), dot(d0, d1), dot(d1, d1)];
            for (c, d) in dots.iter().enumerate() {
                let (wx, wy) = (
                    sbits(term([d0, d1][c % 2]).0, term([d0, d1][c % 2]).1),
                    sbits(term([d0, d1][c / 2]).0, term([d0, d1][c / 2]).1),
                );
                g.add(
                    format!(
                        "octave {k}: corner {c} dot ({wx} + {wy} -> {})",
                        sbits(d.0, d.1)
                    ),
                    2,
                    (t.constant_add(wx) + t.inv * f64::from(wx) + t.mux(wx, 3))
                        + (t.constant_add(wy) + t.inv * f64::from(wy) + t.mux(wy, 3))
                        + t.adder(sbits(d.0, d.1)),
                );
            }
            // lerp p + round(t (q - p)) at f bits, t in [0, 2^f]; the result between p and q
            let tw = unsigned_bits(fade_hi as u128);
            let mut lerp = |what: &str, p: (i128, i128), q: (i128, i128), sh: u32| {
                let d = (q.0 - p.1, q.1 - p.0);
                let dw = sbits(d.0, d.1);
                let (plo, phi) = (p.0 << sh, p.1 << sh);
                g.add(
                    format!(
                        "octave {k}: {what} lerp: q - p {dw}, t (q - p) {tw}x{}, round, p + r",
                        dw - 1
                    ),
                    2,
                    t.adder(dw)
                        + t.multiplier(tw, dw - 1)
                        + t.adder(tw)
                        + t.constant_add(f.min(tw))
                        + t.adder(sbits(plo.min(q.0 << sh), phi.max(q.1 << sh))),
                );
                (plo.min(q.0 << sh), phi.max(q.1 << sh))
            };
            let sh = f - fb;
            let r0 = lerp("x", dots[0], dots[1], sh);
            let r1 = lerp("x", dots[2], dots[3], sh);
            let n = lerp("y", r0, r1, 0);
            let nw = sbits(n.0, n.1);
            // w_k's low bits are zero below the LOD's fraction bits (a multiple of 2^(8 - F)):
            // its non-zero bits and the 256 flag are the array's rows, the sign row an adder
            g.add(
                format!("octave {k}: weighted term n x w {nw}x{}", wb + 1),
                2,
                t.multiplier(nw, wb + 1) + t.adder(nw),
            );
            let s = o - 1 - k;
            nsum = (nsum.0 + ((n.0 * 256) << s), nsum.1 + ((n.1 * 256) << s));
            g.add(
                format!("octave {k}: weight clamp(256 (octaves - k) - lod, 0, 256)"),
                1,
                t.adder(12) + t.clamp(9),
            );
        }
        // the octave sum, rounded to f bits
        let sw = sbits(nsum.0, nsum.1);
        g.add(format!("octave sum adder {sw}"), 2 * (o - 1), t.adder(sw));
        let by = 8 + o - 1;
        let n = (nsum.0 >> by, (nsum.1 >> by) + 1);
        let nw = sbits(n.0, n.1);
        g.add(format!("octave sum rounding {nw}"), 2, t.constant_add(nw));
        g.add(
            format!("noise stage register {nw}"),
            2,
            t.dff * f64::from(nw),
        );
        let lw = self.inputs[1].enc.width();
        g.add(format!("LOD stage register {lw}"), 1, t.dff * f64::from(lw));
        // the index
        let sb = self.scale_bits();
        g.add(
            format!("index scale multiplier {}x{sb}", nw - 1),
            2,
            t.multiplier(nw - 1, sb) + t.adder(sb),
        );
        let wo = self.outputs[0].enc.width();
        g.add(
            format!("1/2 + n scale, clamp to [0, 1] and cast into {wo} bits"),
            2,
            t.constant_add(wo + 2) + t.clamp(wo),
        );
        g.add(format!("index output register {wo}"), 2, t.register(wo));
        g.add(format!("index scale register {sb}"), 1, t.register(sb));
        g.add("sequencer", 1, t.sequencer(LATENCY + 1));
        // the tables, one set per random number (r1, r2), each priced by its noise's own
        // permutation (`CostTable::rom_of`)
        for which in 0..2 {
            let perm: Vec<i64> = self
                .turbulence
                .noise(which)
                .perm()
                .iter()
                .map(|&p| i64::from(p))
                .collect();
            let r = ["r1", "r2"][which];
            for k in 0..o {
                let l = self.lattice(k);
                let n = l.period.min(256);
                if l.index_bits() > 0 && n < 256 {
                    g.add_rom(
                        format!("{r} octave {k}: permutation ROM {n} x 8 (P[i], i < {n})"),
                        2,
                        t.rom_of(&perm[..n as usize], 8),
                    );
                }
            }
            let full = (0..o)
                .map(|k| {
                    let l = self.lattice(k);
                    if l.index_bits() == 0 || l.period < 256 {
                        4
                    } else {
                        6
                    }
                })
                .sum::<u32>();
            g.add_rom(
                format!("{r} permutation ROM 256 x 8"),
                full,
                t.rom_of(&perm, 8),
            );
            let grad: Vec<i64> = perm.iter().map(|p| p & 15).collect();
            g.add_rom(
                format!("{r} gradient index ROM 256 x 4 (P[b] & 15)"),
                4 * o,
                t.rom_of(&grad, 4),
            );
        }
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

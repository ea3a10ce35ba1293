//! The combiner datapath, written once over a number type ([`Path`]) and run three ways:
//! [`FixedPath`] (bit-accurate: integers in the register format), [`ExactPath`] (f64, no
//! quantization) and [`BoundPath`] (interval arithmetic on |exact| and |bit - exact|, which
//! gives the documented bound between the two modes).
//!
//! Register format of the bit-accurate path: signed `width`-bit words `r` read as
//! `r / S` with `S = 255 * 2^(width - 9)`, so that 1.0 is 255 at the default 9 bits (the
//! GeForce 256 convention, `shared/facts/hardware-facts.md`) and every 8-bit colour code `k`
//! is the register word `k * 2^(width - 9)` exactly. One half (bias, half-bias mappings, mux
//! threshold) is `ceil(S / 2)`: 128/255 at 9 bits.

use super::program::*;
use crate::arith::Acc;
use crate::format::{Codec, Encoding, Quant};
use crate::unit::Sample;

/// The arithmetic of one evaluation mode. `V` is one component value.
pub(crate) trait Path {
    type V: Copy;
    fn zero(&self) -> Self::V;
    /// A port lane read into a register (clamped to [-1, 1]).
    fn port(&self, s: &Sample, enc: &Encoding) -> Self::V;
    /// An 8-bit constant code `k`, value k/255.
    fn code(&self, k: u8) -> Self::V;
    /// A general-combiner input mapping.
    fn map(&self, x: Self::V, m: Mapping) -> Self::V;
    /// `sum_i a_i b_i`, rounded once into the register's precision (not clamped).
    fn dot(&self, terms: &[(Self::V, Self::V)]) -> Self::V;
    fn add(&self, a: Self::V, b: Self::V) -> Self::V;
    /// Output scale and bias, then the clamp to [-1, 1].
    fn out(&self, x: Self::V, op: OutputOp) -> Self::V;
    /// The mux: `cd` when spare0's alpha passes the test, else `ab`.
    fn select(&self, alpha: Self::V, sel: MuxSelect, ab: Self::V, cd: Self::V) -> Self::V;
    /// Final-combiner mapping: max(0, x), or 1 - min(max(x, 0), 1) inverted.
    fn fin_map(&self, x: Self::V, invert: bool) -> Self::V;
    /// min(max(x, 0), 1).
    fn clamp01(&self, x: Self::V) -> Self::V;
    /// `a*b + (1-a)*c`, rounded once.
    fn lerp(&self, a: Self::V, b: Self::V, c: Self::V) -> Self::V;
}

/// Bit-accurate arithmetic in the register format.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FixedPath {
    /// 1.0 as a register word: 255 * 2^f.
    pub s: i64,
    /// 1/2 as a register word: ceil(s / 2).
    pub half: i64,
    /// Extra fraction bits beyond 9-bit: width - 9.
    pub f: u32,
}

impl FixedPath {
    pub fn new(width: u32) -> FixedPath {
        let f = width - 9;
        let s = 255i64 << f;
        FixedPath {
            s,
            half: (s + 1) >> 1,
            f,
        }
    }
    fn clamp(&self, x: i64) -> i64 {
        x.clamp(-self.s, self.s)
    }
    /// round-half-up(p / d), d > 0.
    fn div_round(p: i128, d: i128) -> i128 {
        (2 * p + d).div_euclid(2 * d)
    }
    /// The 8-bit code of spare0's alpha as the mux sees it: round-half-up(r / 2^f).
    pub fn code8(&self, x: i64) -> i64 {
        if self.f == 0 {
            x
        } else {
            (x + (1 << (self.f - 1))) >> self.f
        }
    }
    /// An output word (clamped to [0, 1]) as an 8-bit code.
    pub fn code_of(&self, x: i64) -> i64 {
        self.code8(x.clamp(0, self.s)).clamp(0, 255)
    }
}

impl Path for FixedPath {
    type V = i64;
    fn zero(&self) -> i64 {
        0
    }
    fn port(&self, s: &Sample, enc: &Encoding) -> i64 {
        // round-half-up(x S): exactly, for the c / (2^n - 1) codecs too
        let n = enc.width();
        let (r, sc) = (s.raw as i128, self.s as i128);
        let v = match enc.codec {
            Codec::UnitUnsigned => Self::div_round(r * sc, (1i128 << n) - 1),
            Codec::UnitSymmetric => Self::div_round((2 * r + 1) * sc, (1i128 << n) - 1),
            _ => Acc::from_code(s.raw, enc).scale(sc).round_int(Quant::Rnd),
        };
        v.clamp(-sc, sc) as i64
    }
    fn code(&self, k: u8) -> i64 {
        (k as i64) << self.f
    }
    fn map(&self, x: i64, m: Mapping) -> i64 {
        let (s, h) = (self.s, self.half);
        let pos = x.max(0);
        match m {
            Mapping::UnsignedIdentity => pos,
            Mapping::UnsignedInvert => s - x.clamp(0, s),
            Mapping::ExpandNormal => 2 * pos - s,
            Mapping::ExpandNegate => s - 2 * pos,
            Mapping::HalfBiasNormal => pos - h,
            Mapping::HalfBiasNegate => h - pos,
            Mapping::SignedIdentity => x,
            Mapping::SignedNegate => -x,
        }
    }
    fn dot(&self, terms: &[(i64, i64)]) -> i64 {
        let p: i128 = terms.iter().map(|&(a, b)| a as i128 * b as i128).sum();
        Self::div_round(p, self.s as i128) as i64
    }
    fn add(&self, a: i64, b: i64) -> i64 {
        a + b
    }
    fn out(&self, x: i64, op: OutputOp) -> i64 {
        let (bias, shift) = op.parts();
        let v = if bias { x - self.half } else { x };
        let v = match shift {
            -1 => (v + 1) >> 1, // halves round up (CombinerOps: 255/2 -> 128)
            k => v << k,
        };
        self.clamp(v)
    }
    fn select(&self, alpha: i64, sel: MuxSelect, ab: i64, cd: i64) -> i64 {
        let pass = match sel {
            MuxSelect::Msb => alpha >= self.half,
            MuxSelect::Lsb => self.code8(alpha) & 1 == 1,
        };
        if pass {
            cd
        } else {
            ab
        }
    }
    fn fin_map(&self, x: i64, invert: bool) -> i64 {
        if invert {
            self.s - x.clamp(0, self.s)
        } else {
            x.max(0)
        }
    }
    fn clamp01(&self, x: i64) -> i64 {
        x.clamp(0, self.s)
    }
    fn lerp(&self, a: i64, b: i64, c: i64) -> i64 {
        let p = a as i128 * b as i128 + (self.s - a) as i128 * c as i128;
        Self::div_round(p, self.s as i128) as i64
    }
}

/// The algorithm in f64: 1.0 is 1.0, one half is 0.5, nothing is rounded.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ExactPath;

impl Path for ExactPath {
    type V = f64;
    fn zero(&self) -> f64 {
        0.0
    }
    fn port(&self, s: &Sample, _: &Encoding) -> f64 {
        s.x.clamp(-1.0, 1.0)
    }
    fn code(&self, k: u8) -> f64 {
        k as f64 / 255.0
    }
    fn map(&self, x: f64, m: Mapping) -> f64 {
        let pos = x.max(0.0);
        match m {
            Mapping::UnsignedIdentity => pos,
            Mapping::UnsignedInvert => 1.0 - x.clamp(0.0, 1.0),
            Mapping::ExpandNormal => 2.0 * pos - 1.0,
            Mapping::ExpandNegate => 1.0 - 2.0 * pos,
            Mapping::HalfBiasNormal => pos - 0.5,
            Mapping::HalfBiasNegate => 0.5 - pos,
            Mapping::SignedIdentity => x,
            Mapping::SignedNegate => -x,
        }
    }
    fn dot(&self, terms: &[(f64, f64)]) -> f64 {
        terms.iter().map(|&(a, b)| a * b).sum()
    }
    fn add(&self, a: f64, b: f64) -> f64 {
        a + b
    }
    fn out(&self, x: f64, op: OutputOp) -> f64 {
        let (bias, shift) = op.parts();
        let v = if bias { x - 0.5 } else { x };
        let v = match shift {
            -1 => v * 0.5,
            k => v * (1 << k) as f64,
        };
        v.clamp(-1.0, 1.0)
    }
    fn select(&self, alpha: f64, sel: MuxSelect, ab: f64, cd: f64) -> f64 {
        let pass = match sel {
            MuxSelect::Msb => alpha >= 0.5,
            // the LSB of the nearest 8-bit code (round half up)
            MuxSelect::Lsb => ((alpha * 255.0 + 0.5).floor() as i64) & 1 == 1,
        };
        if pass {
            cd
        } else {
            ab
        }
    }
    fn fin_map(&self, x: f64, invert: bool) -> f64 {
        if invert {
            1.0 - x.clamp(0.0, 1.0)
        } else {
            x.max(0.0)
        }
    }
    fn clamp01(&self, x: f64) -> f64 {
        x.clamp(0.0, 1.0)
    }
    fn lerp(&self, a: f64, b: f64, c: f64) -> f64 {
        a * b + (1.0 - a) * c
    }
}

/// A bound on one component: `mag >= |exact value|`, `err >= |bit-accurate - exact|`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bound {
    pub mag: f64,
    pub err: f64,
}

/// Propagates [`Bound`]s through the program: the bound between the two modes.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BoundPath {
    /// One register LSB, 1/S.
    pub ulp: f64,
    /// |ceil(S/2)/S - 1/2|: the bit-accurate half's distance from 0.5.
    pub half_err: f64,
}

impl BoundPath {
    pub fn new(width: u32) -> BoundPath {
        let p = FixedPath::new(width);
        BoundPath {
            ulp: 1.0 / p.s as f64,
            half_err: (p.half as f64 / p.s as f64 - 0.5).abs(),
        }
    }
}

fn b(mag: f64, err: f64) -> Bound {
    Bound { mag, err }
}

impl Path for BoundPath {
    type V = Bound;
    fn zero(&self) -> Bound {
        Bound { mag: 0.0, err: 0.0 }
    }
    fn port(&self, s: &Sample, enc: &Encoding) -> Bound {
        // 8-bit unsigned colours read exactly (k/255 is a register word); others round once
        let exact = enc.codec == Codec::UnitUnsigned && enc.width() == 8;
        let _ = s;
        b(1.0, if exact { 0.0 } else { 0.5 * self.ulp })
    }
    fn code(&self, k: u8) -> Bound {
        b(k as f64 / 255.0, 0.0)
    }
    fn map(&self, x: Bound, m: Mapping) -> Bound {
        match m {
            Mapping::UnsignedIdentity | Mapping::SignedIdentity | Mapping::SignedNegate => x,
            Mapping::UnsignedInvert => b(1.0, x.err),
            Mapping::ExpandNormal | Mapping::ExpandNegate => b(1.0, 2.0 * x.err),
            Mapping::HalfBiasNormal | Mapping::HalfBiasNegate => {
                b(x.mag.max(0.5), x.err + self.half_err)
            }
        }
    }
    fn dot(&self, terms: &[(Bound, Bound)]) -> Bound {
        let mag = terms.iter().map(|(a, c)| a.mag * c.mag).sum();
        let err: f64 = terms
            .iter()
            .map(|(a, c)| a.err * c.mag + c.err * a.mag + a.err * c.err)
            .sum();
        // a product with a factor that is 0 in both modes is 0: nothing to round
        let rounds = terms.iter().any(|(a, c)| a.mag > 0.0 && c.mag > 0.0);
        b(mag, err + if rounds { 0.5 * self.ulp } else { 0.0 })
    }
    fn add(&self, x: Bound, y: Bound) -> Bound {
        b(x.mag + y.mag, x.err + y.err)
    }
    fn out(&self, x: Bound, op: OutputOp) -> Bound {
        let (bias, shift) = op.parts();
        let (m, e) = if bias {
            (x.mag + 0.5, x.err + self.half_err)
        } else {
            (x.mag, x.err)
        };
        let (m, e) = match shift {
            -1 => (m * 0.5, e * 0.5 + 0.5 * self.ulp),
            k => (m * (1 << k) as f64, e * (1 << k) as f64),
        };
        // the clamp to [-1, 1] is 1-Lipschitz, and two values in [-1, 1] differ by <= 2
        b(m.min(1.0), e.min(2.0))
    }
    fn select(&self, alpha: Bound, _: MuxSelect, ab: Bound, cd: Bound) -> Bound {
        let mag = ab.mag.max(cd.mag);
        if alpha.err == 0.0 {
            // both modes see the same register word: the same choice
            b(mag, ab.err.max(cd.err))
        } else {
            b(mag, ab.err.max(cd.err).max(ab.mag + cd.mag))
        }
    }
    fn fin_map(&self, x: Bound, invert: bool) -> Bound {
        if invert {
            b(1.0, x.err)
        } else {
            x
        }
    }
    fn clamp01(&self, x: Bound) -> Bound {
        b(x.mag.min(1.0), x.err.min(1.0))
    }
    fn lerp(&self, a: Bound, x: Bound, y: Bound) -> Bound {
        if a.mag == 0.0 {
            return y; // A is 0 in both modes: the lerp is C, exactly
        }
        let one_a = 1.0 + a.mag;
        let mag = a.mag * x.mag + one_a * y.mag;
        let err = a.err * (x.mag + y.mag)
            + x.err * a.mag
            + y.err * one_a
            + a.err * (x.err + y.err)
            + 0.5 * self.ulp;
        b(mag, err)
    }
}

/// One register file: 12 registers of RGBA.
type Regs<V> = [[V; 4]; REGISTERS];

/// The values of variable `i` of an RGB portion (3 lanes) or an alpha portion (1 lane).
fn fetch<P: Path>(p: &P, regs: &Regs<P::V>, i: &Input, lanes: usize) -> [P::V; 3] {
    let r = &regs[i.source.index().unwrap_or(0)];
    let v = |lane: usize| p.map(r[lane], i.mapping);
    match (lanes, i.usage) {
        (3, Usage::Rgb) => [v(0), v(1), v(2)],
        (3, _) => [v(3); 3],
        (_, Usage::Blue) => [v(2); 3],
        _ => [v(3); 3],
    }
}

/// (AB, CD, sum-or-mux), each after the output op: `lanes` components.
fn portion<P: Path>(
    p: &P,
    regs: &Regs<P::V>,
    q: &Portion,
    lanes: usize,
    sel: MuxSelect,
) -> [[P::V; 3]; 3] {
    let [a, bb, c, d] = [&q.a, &q.b, &q.c, &q.d].map(|i| fetch(p, regs, i, lanes));
    let prod = |x: &[P::V; 3], y: &[P::V; 3], dot: bool| -> [P::V; 3] {
        if dot {
            let t = p.dot(&[(x[0], y[0]), (x[1], y[1]), (x[2], y[2])]);
            [t; 3]
        } else {
            std::array::from_fn(|l| p.dot(&[(x[l], y[l])]))
        }
    };
    let ab = prod(&a, &bb, q.ab_dot);
    let cd = prod(&c, &d, q.cd_dot);
    let alpha = regs[10][3]; // spare0 alpha at the stage's input
    let sum: [P::V; 3] = std::array::from_fn(|l| {
        if q.mux {
            p.select(alpha, sel, ab[l], cd[l])
        } else {
            p.add(ab[l], cd[l])
        }
    });
    [ab, cd, sum].map(|v| v.map(|x| p.out(x, q.op)))
}

/// The value of a final-combiner variable (3 lanes; G uses lane 0 of its own fetch).
fn fin_fetch<P: Path>(
    p: &P,
    regs: &Regs<P::V>,
    i: &FinalInput,
    sum: &[P::V; 3],
    ef: &[P::V; 3],
) -> [P::V; 3] {
    let raw: [P::V; 3] = match i.source {
        Source::Spare0PlusSecondary => *sum,
        Source::EfProduct => *ef,
        s => {
            let r = &regs[s.index().unwrap_or(0)];
            match i.usage {
                Usage::Rgb => [r[0], r[1], r[2]],
                Usage::Alpha => [r[3]; 3],
                Usage::Blue => [r[2]; 3],
            }
        }
    };
    raw.map(|x| p.fin_map(x, i.invert))
}

/// Run the program on one fragment's inputs (primary, secondary, fog, texture 0..3 as
/// register values): the final RGBA, clamped to [0, 1].
pub(crate) fn run<P: Path>(p: &P, prog: &Program, inputs: &[[P::V; 4]; 7]) -> [P::V; 4] {
    let z = p.zero();
    let mut regs: Regs<P::V> = [[z; 4]; REGISTERS];
    for (k, v) in inputs.iter().enumerate() {
        regs[3 + k] = *v; // fog, primary, secondary, tex0..3 (indices 3..=9)
    }
    regs[10][3] = regs[6][3]; // spare0 alpha = texture 0 alpha (spec, initial values)
    for st in &prog.stages {
        regs[1] = st.c0.map(|k| p.code(k));
        regs[2] = st.c1.map(|k| p.code(k));
        let rgb = portion(p, &regs, &st.rgb, 3, prog.mux_select);
        let alpha = portion(p, &regs, &st.alpha, 1, prog.mux_select);
        let mut next = regs;
        let dests = |q: &Portion| [q.ab_out, q.cd_out, q.sum_out];
        for (o, dst) in dests(&st.rgb).iter().enumerate() {
            if let Some(r) = dst.and_then(|r| r.index()) {
                next[r][..3].copy_from_slice(&rgb[o]);
            }
        }
        for (o, dst) in dests(&st.alpha).iter().enumerate() {
            if let Some(r) = dst.and_then(|r| r.index()) {
                next[r][3] = alpha[o][0];
            }
        }
        for (o, on) in [(0, st.ab_blue_to_alpha), (1, st.cd_blue_to_alpha)] {
            if let (true, Some(r)) = (on, dests(&st.rgb)[o].and_then(|r| r.index())) {
                next[r][3] = rgb[o][2];
            }
        }
        regs = next;
    }
    let fc = &prog.final_combiner;
    regs[1] = fc.c0.map(|k| p.code(k));
    regs[2] = fc.c1.map(|k| p.code(k));
    let sum: [P::V; 3] = std::array::from_fn(|l| {
        let r0 = p.fin_map(regs[10][l], fc.sum_invert_spare0);
        let v1 = p.fin_map(regs[5][l], fc.sum_invert_secondary);
        let s = p.add(p.clamp01(r0), p.clamp01(v1));
        if fc.sum_clamp {
            p.clamp01(s)
        } else {
            s
        }
    });
    let none = [z; 3];
    let e = fin_fetch(p, &regs, &fc.e, &none, &none);
    let f = fin_fetch(p, &regs, &fc.f, &none, &none);
    let ef: [P::V; 3] = std::array::from_fn(|l| p.dot(&[(e[l], f[l])]));
    let [a, bb, c, d] = [&fc.a, &fc.b, &fc.c, &fc.d].map(|i| fin_fetch(p, &regs, i, &sum, &ef));
    let g = fin_fetch(p, &regs, &fc.g, &none, &none)[0];
    let rgb: [P::V; 3] = std::array::from_fn(|l| p.clamp01(p.add(p.lerp(a[l], bb[l], c[l]), d[l])));
    [rgb[0], rgb[1], rgb[2], p.clamp01(g)]
}

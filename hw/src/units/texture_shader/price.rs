//! The price of the configured datapath ([`Datapath::Configured`]): each stage has the
//! hardware of its own program only, item by item, as the Verilog generator builds it
//! (`rtl::texture_shader`, `docs/rtl.md` "The texture shaders"): the projective divider per
//! TEXTURE_2D stage, the mapping, the products and the cast per dot product, the matrix
//! constants per offset stage, the luminance scale, the colour converter per PASS_THROUGH
//! lane, and the fetch (addressing per mip level, filter, cast) per texture. Texture memory is
//! not counted (as for [`crate::units::TexFetch`]); the registers are the coordinate and
//! result registers of a unit that holds one fragment at a time.
//!
//! The widths are the exact ones of the bit-accurate mode (`eval.rs`, `FixedArith`): every
//! intermediate is as wide as its range, which [`Rg`] tracks as the generator's wires do.

use super::{Compiled, DotMapping, Program, ShaderParams, TextureShader};
use crate::arith::bit_length;
use crate::format::{Codec, Encoding, Format, Overflow};
use crate::gates::{CostTable, GateBudget};
use crate::rtl::verilog::signed_bits;
use crate::sampler::Filter;
use crate::unit::Unit;
use crate::units::fetch::{address_gates, filter_gates};
use serde::{Deserialize, Serialize};

/// What the gate budget prices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum Datapath {
    /// Every stage has the datapath of every program (the NV2A's stages: any stage may run
    /// any program); the default.
    #[default]
    Programmable,
    /// Each stage has the datapath of its configured program only, as the generated Verilog
    /// (what synthesis confirms, `hw/tests/rtl_synth.rs`).
    Configured,
}

/// An exact integer range `[lo, hi]` at `frac` fraction bits, as the generator's wires.
#[derive(Debug, Clone, Copy)]
pub(super) struct Rg {
    pub(super) lo: i128,
    pub(super) hi: i128,
    pub(super) frac: u32,
}

impl Rg {
    pub(super) fn of(f: &Format) -> Rg {
        Rg {
            lo: f.min_raw() as i128,
            hi: f.max_raw() as i128,
            frac: f.frac as u32,
        }
    }
    pub(super) fn width(&self) -> u32 {
        signed_bits(self.lo, self.hi)
    }
    /// Bits of the magnitude (the unsigned part of a product's array).
    fn mag(&self) -> u32 {
        if self.lo >= 0 {
            bit_length(self.hi as u128)
        } else {
            self.width() - 1
        }
    }
}

/// An exact product's array and sign rows (`rtl::fixed::mul`).
pub(super) fn mul(t: &CostTable, a: Rg, b: Rg) -> (f64, Rg) {
    let c = [a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi];
    let r = Rg {
        lo: *c.iter().min().unwrap_or(&0),
        hi: *c.iter().max().unwrap_or(&0),
        frac: a.frac + b.frac,
    };
    let (na, nb) = (a.mag(), b.mag());
    let mut ge = t.multiplier(na.max(1), nb.max(1));
    // a sign row is an AND row and an adder into the product
    if a.lo < 0 {
        ge += t.and2 * nb as f64 + t.adder(nb + 1);
    }
    if b.lo < 0 {
        ge += t.and2 * na as f64 + t.adder(na + 1);
    }
    (ge, r)
}

/// The exact sum of terms aligned to the largest fraction.
pub(super) fn sum(t: &CostTable, terms: &[Rg]) -> (f64, Rg) {
    let f = terms.iter().map(|r| r.frac).max().unwrap_or(0);
    let (mut lo, mut hi) = (0i128, 0i128);
    for r in terms {
        lo += r.lo << (f - r.frac);
        hi += r.hi << (f - r.frac);
    }
    let s = Rg { lo, hi, frac: f };
    (t.adder(s.width()) * terms.len().saturating_sub(1) as f64, s)
}

/// Round half up by `by` bits and saturate into `out` (the cast of a coordinate, a dot
/// product or an offset): an incrementer on the bits above the rounding position and the
/// clamp of the output's width when the range exceeds it.
pub(super) fn cast_fixed(t: &CostTable, x: Rg, out: &Encoding) -> f64 {
    let of = out.format.frac as u32;
    let by = x.frac.saturating_sub(of);
    let w = x.width();
    let round = if by > 0 {
        t.constant_add(w.saturating_sub(by) + 1)
    } else {
        0.0
    };
    let (lo, hi) = (x.lo >> by, (x.hi + (1 << by >> 1)) >> by);
    let clamp = if lo < out.format.min_raw() as i128 || hi > out.format.max_raw() as i128 {
        match out.overflow {
            Overflow::Wrap => 0.0,
            _ => t.clamp(out.width()) + t.comparator(signed_bits(lo, hi)),
        }
    } else {
        0.0
    };
    round + clamp
}

/// The range of a lane code read by its codec, and the price of the reading (the symmetric
/// codec's `2c + 1` is a wire; a unit unsigned code's `2^n + 1` stays a pending factor).
pub(super) fn read_code(enc: &Encoding) -> (Rg, u128) {
    let n = enc.format.width as u32;
    let r = Rg::of(&enc.format);
    match enc.codec {
        Codec::Fixed => (r, 1),
        Codec::UnitSigned => (Rg { frac: n - 1, ..r }, 1),
        Codec::UnitUnsigned => (Rg { frac: 2 * n, ..r }, (1 << n) + 1),
        Codec::UnitSymmetric => (
            Rg {
                lo: 2 * r.lo + 1,
                hi: 2 * r.hi + 1,
                frac: 2 * n,
            },
            (1 << n) + 1,
        ),
    }
}

/// A conditional negate of `n` bits (`s ? -x : x`): an inverter and a half adder a bit and
/// the select.
fn negate(t: &CostTable, n: u32) -> f64 {
    (t.inv + t.half_adder) * n as f64 + t.mux(n, 2)
}

/// One `s/q` divider (`rtl::texture_shader::arith::divide`): the restoring array (per
/// quotient bit a subtractor and the restoring select, as wide as the partial remainder can
/// be) and the sign logic around it. Calibrated on the divider alone (the `_div` module,
/// yosys, s12.6 to s32.16, saturating and wrapping: 0.98-1.06, docs/gates.md): saturating,
/// every step is as wide as the divisor (the partial remainder starts at the numerator's
/// top bits, which synthesis cannot bound below the divisor); wrapping, it starts at 0 and
/// grows a bit a step. The sign logic synthesises to about the divisor's magnitude and one
/// numerator-wide adder (the rounding numerator `2p + |q|`, its magnitude and the signed
/// quotient fold together).
pub(super) fn divider(t: &CostTable, coord: &Encoding) -> f64 {
    let w = coord.format.width as u32;
    let f = coord.format.frac as u32;
    let nw = w + f + 2;
    let db = w + 1;
    let sat = !matches!(coord.overflow, Overflow::Wrap);
    // saturating: the low w quotient bits only, from the numerator's top (full width);
    // wrapping: every numerator bit, from 0
    let steps = if sat { (w, true) } else { (nw, false) };
    negate(t, w) + t.adder(nw) + restoring(t, steps, db)
}

/// The steps of a restoring division by a `db`-bit divisor: per quotient bit a subtractor and
/// the restoring select, as wide as the partial remainder can be (`(steps, full)`: `full`,
/// every step at the divisor's width plus one; else growing a bit a step from 0).
pub(super) fn restoring(t: &CostTable, (steps, full): (u32, bool), db: u32) -> f64 {
    let mut r = if full { db } else { 0 };
    let mut ge = 0.0;
    for _ in 0..steps {
        let wk = (r + 1).min(db + 1);
        ge += t.adder(wk) + t.mux(wk, 2);
        r = wk;
    }
    ge
}

/// One lane of the PASS_THROUGH colour converter into `out`: the clamp to [0, 1] (the sign
/// bit and a compare with a constant) and the converter (`convert_frac`) or the cast.
pub(super) fn pass_lane(t: &CostTable, p: &ShaderParams, out: &Encoding) -> f64 {
    let n = out.width();
    let cw = p.coord.width();
    let f = p.coord.format.frac as u32;
    t.clamp(f + 1)
        + t.and2 * cw as f64
        + match p.convert_frac {
            Some(k) => t.constant_add(k + 1) + t.shift_add(k + 1, (1 << n) - 1),
            None => cast_fixed(t, Rg::of(&Format::u(f as u8 + 1, f as u8)), out),
        }
}

/// The mapped N of a dot product (`arith::vector`): per component the code read and divided
/// by its constant (`div_round`, a reciprocal multiply), or for the HILO hemispheres the two
/// 16-bit codes, their squares and the integer square root. Returns the price and the
/// range of one component.
pub(super) fn mapping(t: &CostTable, mp: DotMapping, enc: &Encoding, df: u32) -> (f64, Rg) {
    // `div_round(c 2^df, d)`: the reciprocal multiply acts on the code's bits (the df low
    // bits of `c 2^df` are zeros and the rounding's constants, which synthesis folds), plus
    // the carry of those constants across the df bits (yosys: the dot cases 1.03-1.10 when
    // priced on the shifted word, 0.97-1.035 so)
    let scaled = |lo: i128, hi: i128, d: i128| {
        let ge = t.div_round(lo, hi, d) + t.constant_add(df);
        let (lo, hi) = (lo << df, hi << df);
        let q = (
            (2 * lo + d).div_euclid(2 * d),
            (2 * hi + d).div_euclid(2 * d),
        );
        (
            ge,
            Rg {
                lo: q.0,
                hi: q.1,
                frac: df,
            },
        )
    };
    // how an n-bit code reads (the D3D offset, the GL doubling, two's complement, unsigned)
    let code = |n: u32, offset: bool, gl: bool, signed: bool| {
        let (half, top) = (1i128 << (n - 1), (1i128 << n) - 1);
        if offset {
            let (p, r) = scaled(-half, half - 1, half - 1);
            (p + t.constant_add(n + 1), r)
        } else if gl {
            let (p, r) = scaled(-(top - 1), top - 1, top);
            (p + t.constant_add(n + 2), r)
        } else if signed {
            scaled(-half, half - 1, half - 1)
        } else {
            scaled(0, top, top)
        }
    };
    use DotMapping::*;
    if mp.is_hilo() {
        let (pc, r) = code(
            16,
            mp == HiloHemisphereD3d,
            mp == HiloHemisphereGl,
            mp == HiloHemisphere,
        );
        let mut ge = 2.0 * pc;
        if mp != Hilo1 {
            ge += hemisphere_z(t, r, df);
        }
        return (ge, r);
    }
    let w = enc.width();
    if w == 8 {
        let (p, r) = code(8, mp == Minus1To1D3d, mp == Minus1To1Gl, mp == Minus1To1);
        return (3.0 * p, r);
    }
    // other widths read by value and shifted to `df` fraction bits
    let (r, k) = read_code(enc);
    let mut ge = 0.0;
    let mut v = r;
    if k > 1 {
        ge += t.shift_add(r.width(), k);
        v = Rg {
            lo: r.lo * k as i128,
            hi: r.hi * k as i128,
            ..r
        };
    }
    if matches!(mp, Minus1To1D3d | Minus1To1Gl) {
        ge += t.adder(v.width() + 1);
        v = Rg {
            lo: 2 * v.lo - (1 << v.frac),
            hi: 2 * v.hi - (1 << v.frac),
            ..v
        };
    }
    if v.frac > df {
        ge += t.constant_add(v.width() - (v.frac - df) + 1);
        let by = v.frac - df;
        v = Rg {
            lo: v.lo >> by,
            hi: (v.hi + (1 << (by - 1))) >> by,
            frac: df,
        };
    }
    (3.0 * ge, v)
}

/// The HILO hemisphere's z from the two mapped codes of range `r`: two squares
/// (`fixed::square`, a folded array and the sign row), `1 - h^2 - l^2`, the root digit by
/// digit (a subtractor and a select per root bit, as wide as the partial remainder can be).
pub(super) fn hemisphere_z(t: &CostTable, r: Rg, df: u32) -> f64 {
    let n = r.mag();
    let mut ge = 2.0 * (t.squarer(n) + if r.lo < 0 { t.adder(n + 1) } else { 0.0 });
    ge += 2.0 * t.adder(2 * n + 2);
    let bits = (2 * df + 2).next_multiple_of(2);
    let half = bits / 2;
    for i in 0..half {
        let wk = (i + 3).min(half + 3);
        ge += t.adder(wk) + t.mux(wk, 2);
    }
    ge
}

/// The reflection of `eval.rs`: `N.N` (three squares), `N.E`, per component
/// `2 N_k (N.E) - E_k (N.N)` and its rounded division by `N.N` into the coordinate format
/// (`rtl::texture_shader::cube::reflect`), N and E words of the coordinate encoding (E the
/// constants `eye` of DOT_PRODUCT_CONST_EYE_REFLECT_CUBE_MAP, whose products are shifts and
/// adds).
pub(super) fn reflection(t: &CostTable, coord: &Encoding, eye: Option<[i128; 3]>) -> GateBudget {
    let c = Rg::of(&coord.format);
    let mut g = GateBudget::new();
    let w = c.width();
    // a square: the folded array of the magnitude and the sign row
    let sq = t.squarer(c.mag()) + t.adder(c.mag() + 1);
    let nn = Rg {
        lo: 0,
        hi: 3 * (c.lo * c.lo).max(c.hi * c.hi),
        frac: 2 * c.frac,
    };
    let (_, prod) = mul(t, c, c);
    let ne = Rg {
        lo: 3 * prod.lo,
        hi: 3 * prod.hi,
        frac: prod.frac,
    };
    let by_eye = |t: &CostTable, x: Rg, k: usize| match eye {
        Some(e) => t.constant_multiplier(x.width(), e[k].unsigned_abs()),
        None => mul(t, c, x).0,
    };
    let ne_products: f64 = (0..3).map(|k| by_eye(t, c, k)).sum();
    g.add(
        format!(
            "reflection: N.N (3 squares {w}) and N.E (3 products), sums {}",
            ne.width()
        ),
        1,
        3.0 * sq + ne_products + 2.0 * (t.adder(nn.width()) + t.adder(ne.width())),
    );
    let (p1, a) = mul(t, c, ne);
    let b = Rg {
        lo: c.lo.min(-c.hi) * nn.hi,
        hi: c.hi.max(-c.lo) * nn.hi,
        frac: c.frac + nn.frac,
    };
    let (_, num) = sum(t, &[a, a, b]);
    let nb = num.width() + 1;
    let db = bit_length(nn.hi as u128) + 1;
    for k in 0..3 {
        g.add(
            format!(
                "reflection {k}: 2 N (N.E) - E (N.N) ({w}x{}, the difference {} and 2 num + N.N)",
                ne.width(),
                num.width()
            ),
            1,
            p1 + by_eye(t, nn, k) + t.adder(num.width()) + t.adder(nb),
        );
    }
    // the quotient saturates into the coordinate (w steps at the divisor's width, the
    // numerator's top bits compared with the divisor once) or wraps (every numerator bit);
    // the numerator's magnitude and rounding, the signed quotient; -E when N = 0
    let steps = if !matches!(coord.overflow, Overflow::Wrap) {
        (w, true)
    } else {
        (nb, false)
    };
    g.add(
        format!("reflection: divider {nb} / {db}, the signs and the zero select"),
        3,
        negate(t, nb)
            + t.adder(nb)
            + t.comparator(nb.saturating_sub(w))
            + restoring(t, steps, db)
            + 2.0 * negate(t, w + 1)
            + t.mux(w, 2),
    );
    g
}

/// The cube-face select and projection of a direction of coordinate words of range `c`
/// (`rtl::texture_shader::cube::face`): the three magnitudes, the major-axis comparators,
/// the selects of `sc`, `tc`, `ma` by the face (of 4, 3 and 3 distinct values: `-z, z, x, -x`;
/// `-y, z, -z`; the three magnitudes), and per face coordinate the numerator
/// `(sc + ma) 2^f + ma` and an `f + 1`-step restoring division by `2 ma`.
pub(super) fn cube_face(t: &CostTable, c: Rg) -> f64 {
    let w = c.width() + 1;
    let f = c.frac;
    3.0 * negate(t, w)
        + 3.0 * t.comparator(w)
        + t.mux(w, 4)
        + 2.0 * t.mux(w, 3)
        + 2.0 * (2.0 * t.adder(w + 1) + restoring(t, (f + 1, true), w) + t.mux(f + 2, 2))
}

/// One dot product of a stage: N mapped from the previous stage's texel, three products
/// with `(s, t, r)`, their sum and the cast into the coordinate format.
/// `shared`: the mapping is the one an earlier stage applies to the same texel (synthesis
/// keeps one copy of identical logic, as a designer would).
fn dot(
    g: &mut GateBudget,
    t: &CostTable,
    p: &ShaderParams,
    (mp, shared): (DotMapping, bool),
    prev: &Compiled,
) {
    let df = p.dot_frac;
    let (pm, n) = mapping(t, mp, &prev.out_enc, df);
    if !shared {
        g.add(format!("dot mapping {mp:?} ({} bits)", n.width()), 1, pm);
    }
    let c = Rg::of(&p.coord.format);
    let (pp, prod) = mul(t, c, n);
    // HILO_1's z is the constant 1: its product is a shift
    let products = if mp == DotMapping::Hilo1 { 2 } else { 3 };
    g.add(
        format!("dot products {}x{}", c.width(), n.width()),
        products,
        pp,
    );
    let (ps, s) = sum(t, &[prod, prod, prod]);
    g.add(format!("dot sum {}", s.width()), 1, ps);
    g.add("dot cast", 1, cast_fixed(t, s, &p.coord));
}

/// The offset `s + a1 ds + a3 dt`, `t + a2 ds + a4 dt` (matrix entries as shifts and adds)
/// and the casts into the coordinate format.
fn offset(g: &mut GateBudget, t: &CostTable, p: &ShaderParams, st: &Compiled, prev: &Compiled) {
    let pe = prev.out_enc;
    let (d, k) = if st.offset.twos_complement && !pe.format.signed {
        let nb = pe.format.width;
        (
            Rg {
                frac: nb as u32 - 1,
                ..Rg::of(&Format::s(nb, 0))
            },
            1,
        )
    } else {
        read_code(&pe)
    };
    let of = p.offset_frac;
    let c = Rg::of(&p.coord.format);
    for (axis, ks) in [("s", [0usize, 2]), ("t", [1, 3])] {
        let mut terms = vec![c];
        for &kk in &ks {
            let r = st.matrix_raw[kk] as i128;
            if r == 0 {
                continue;
            }
            let m = r * k as i128;
            g.add(
                format!("{axis} offset: x a{} ({m}) on {}", kk + 1, d.width()),
                1,
                t.constant_multiplier(d.width(), m.unsigned_abs()),
            );
            let (a, b) = (d.lo * m, d.hi * m);
            terms.push(Rg {
                lo: a.min(b),
                hi: a.max(b),
                frac: d.frac + of,
            });
        }
        let (ps, s) = sum(t, &terms);
        g.add(format!("{axis} offset sum {}", s.width()), 1, ps);
        g.add(format!("{axis} offset cast"), 1, cast_fixed(t, s, &p.coord));
    }
}

/// OFFSET_TEXTURE_2D_SCALE's luminance: `l = scale mag + bias` (constants), clamped, times
/// each RGB lane and cast (or the NV2A's integer quotient, a constant division per lane).
fn luminance(g: &mut GateBudget, t: &CostTable, p: &ShaderParams, st: &Compiled, mag: &Encoding) {
    let enc = st.out_enc;
    let (m, k) = read_code(mag);
    let sk = st.scale_raw[0].unsigned_abs() as u128 * k;
    g.add(
        format!("luminance scale x{sk} on {}", m.width()),
        1,
        t.constant_multiplier(m.width(), sk.max(1)),
    );
    let lw = m.width() + bit_length(sk) + 1;
    g.add(
        format!("luminance bias and clamp {lw}"),
        1,
        t.constant_add(lw) + t.clamp(p.offset_frac + 2),
    );
    let unit = |e: &Encoding| e.codec == Codec::UnitUnsigned && !e.format.signed;
    let (c, _) = read_code(&enc);
    let lum = Rg {
        lo: 0,
        hi: 1i128 << (p.offset_frac + 1),
        frac: p.offset_frac,
    };
    let (pm, prod) = mul(t, c, lum);
    g.add(
        format!("luminance product {}x{}", c.width(), lum.width()),
        3,
        pm,
    );
    if st.offset.luminance_unclamped && unit(mag) && unit(&enc) {
        let top = (1i128 << enc.width()) - 1;
        let den = ((1i128 << mag.width()) - 1) << p.offset_frac;
        g.add(
            "luminance quotient (a constant divider)",
            3,
            t.div_round(0, prod.hi, top * den),
        );
        if p.convert_frac.is_some() {
            g.add(
                "luminance converter",
                3,
                t.constant_add(prod.width()) + t.shift_add(prod.width(), top as u128),
            );
        }
    } else {
        let kk = if unit(&enc) {
            ((1u128 << enc.width()) + 1) * ((1u128 << enc.width()) - 1)
        } else {
            1
        };
        g.add(
            format!("luminance cast x{kk}"),
            3,
            t.shift_add(prod.width(), kk) + t.constant_add(prod.width()) + t.clamp(enc.width()),
        );
    }
}

/// The price of `u`'s configured datapath (see the module documentation).
pub(super) fn configured(u: &TextureShader, t: &CostTable) -> GateBudget {
    let p = u.params();
    let cw = p.coord.width();
    let c = Rg::of(&p.coord.format);
    let mut g = GateBudget::new();
    let progs = u.programs();
    let mut registers = 0u32;
    let mut mapped: Vec<(usize, DotMapping)> = Vec::new();
    for (i, st) in u.stages.iter().enumerate() {
        let prog = progs[i];
        let name = prog.name();
        let mut s = GateBudget::new();
        if let (Some(mp), Some(k)) = (prog.mapping(), prog.prev()) {
            let shared = mapped.contains(&(k, mp));
            mapped.push((k, mp));
            dot(&mut s, t, p, (mp, shared), &u.stages[k]);
            if matches!(
                prog,
                Program::DotProduct { .. } | Program::DotProductDiffuseCube { .. }
            ) {
                registers += cw;
            }
        }
        match prog {
            Program::Texture2d => {
                // one divider module, two instances (s/q, t/q)
                s.add(format!("projective divider {cw}"), 2, divider(t, &p.coord));
            }
            Program::DependentAr { prev } | Program::DependentGb { prev } => {
                let (r, k) = read_code(&u.stages[prev].out_enc);
                let x = Rg {
                    lo: r.lo * k as i128,
                    hi: r.hi * k as i128,
                    ..r
                };
                let rep = if k > 1 {
                    t.shift_add(r.width(), k)
                } else {
                    0.0
                };
                s.add(
                    "dependent read: the code into a coordinate",
                    2,
                    rep + cast_fixed(t, x, &p.coord),
                );
            }
            Program::OffsetTexture2d { prev, .. } | Program::OffsetTexture2dScale { prev, .. } => {
                offset(&mut s, t, p, st, &u.stages[prev]);
                if let Program::OffsetTexture2dScale { prev, .. } = prog {
                    luminance(&mut s, t, p, st, &u.stages[prev].out_enc);
                }
            }
            Program::PassThrough => {
                let n = st.out_enc.width();
                s.add(
                    format!("colour converter into {n} bits"),
                    4,
                    pass_lane(t, p, &st.out_enc),
                );
                registers += 4 * n;
            }
            Program::DotProductDepthReplace { .. } => {
                s.add(format!("depth divider {cw}"), 1, divider(t, &p.coord));
                registers += cw;
            }
            Program::TextureCube
            | Program::DotProductTextureCube { .. }
            | Program::DotProductDiffuseCube { .. } => {
                s.add("cube face: select and projection", 1, cube_face(t, c));
            }
            Program::DotProductReflectCube { .. }
            | Program::DotProductConstEyeReflectCube { .. } => {
                let eye = match prog {
                    Program::DotProductConstEyeReflectCube { eye, .. } => {
                        Some(eye.map(|x| p.coord.encode(x) as i128))
                    }
                    _ => None,
                };
                s.add_part("", 1, reflection(t, &p.coord, eye));
                s.add("cube face: select and projection", 1, cube_face(t, c));
            }
            Program::CullFragment { .. } => {
                s.add(
                    "cull test: 4 sign bits and the OR",
                    1,
                    4.0 * (t.inv + t.and2),
                );
                registers += 1;
            }
            _ => {}
        }
        if let (Some(tex), Some(_)) = (&st.spec.texture, prog.texture_kind()) {
            let levels = if matches!(prog, Program::Texture2d) && p.lod.is_some() {
                tex.levels() as u32
            } else {
                1
            };
            let sampler = &st.spec.sampler;
            // a cube face's coordinates: [0, 1] at the coordinate's fraction bits, and the face
            let cube = prog.texture_kind() == Some(true);
            let f = p.coord.format.frac;
            let scoord = if cube {
                registers += 3;
                Encoding::fixed(Format::s(f + 2, f))
            } else {
                p.coord
            };
            let sw = scoord.width();
            let mut ax = [(0, 0); 2];
            // the coordinate bits the addresses and weights read (the others are not kept)
            let mut kept = [0u32; 2];
            for l in 0..levels {
                ax = address_gates(
                    &mut s,
                    t,
                    &scoord,
                    tex.level_at(l as usize).logs(),
                    sampler,
                    1,
                );
                let (lw, lh) = tex.level_at(l as usize).logs();
                for (a, log) in [lw, lh].into_iter().enumerate() {
                    let bits = if sampler.filter() == Filter::Bilinear {
                        ax[a].0 + ax[a].1
                    } else {
                        ax[a].0.max(log)
                    };
                    kept[a] = kept[a].max(bits.min(sw));
                }
            }
            let eff = [ax[0].1, ax[1].1];
            if levels > 1 {
                let taps = sampler.taps();
                let words: u64 = (0..levels as usize)
                    .map(|l| {
                        let (a, b) = tex.level_at(l).logs();
                        1u64 << (a + b)
                    })
                    .sum();
                let ab = bit_length(u128::from(words - 1)).max(1);
                let lw = p.lod.map_or(0, |e| e.width());
                s.add(
                    format!("mip level: lod rounding {lw} and clamp to {levels} levels"),
                    1,
                    t.constant_add(lw) + t.clamp(bit_length(u128::from(levels - 1))),
                );
                s.add(
                    format!(
                        "mip level select of each tap's offset {levels}:1 x{ab} and the base adder"
                    ),
                    taps,
                    t.mux(ab, levels) + t.adder(ab),
                );
                if sampler.filter() == Filter::Bilinear {
                    s.add(
                        format!("mip level select of the weights {levels}:1"),
                        2,
                        t.mux(sampler.weight_bits(), levels),
                    );
                }
            }
            filter_gates(
                &mut s,
                t,
                tex.texel(),
                tex.lanes() as u32,
                &st.out_enc,
                sampler,
                eff,
            );
            registers += kept[0] + kept[1] + tex.lanes() as u32 * st.out_enc.width();
        }
        if !s.items.is_empty() {
            g.add_part(&format!("stage {i} {name}: "), 1, s);
        }
    }
    g.add(
        format!("coordinate, dot and result registers {registers}"),
        1,
        t.register(registers),
    );
    g.add("sequencer", 1, t.sequencer(u.latency()));
    g
}

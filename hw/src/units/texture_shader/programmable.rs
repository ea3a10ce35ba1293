//! The price of the programmable part ([`Datapath::Programmable`], the default): every stage
//! has the datapath of every program, since any stage may run any of them (the NV2A's four
//! stages). Built from the configured price's items (`price.rs`), which synthesis calibrates
//! (`docs/gates.md` "The texture shaders"), at the widths the part must take whatever it
//! runs:
//!
//! * the projective divider pair per stage (the calibrated restoring divider);
//! * the dot mapping: the four 8-bit readings side by side for three components and the four
//!   HILO readings for two with one hemisphere z (squares and root), their selects; the three
//!   products on the widest mapped range, their sum and cast;
//! * the offset with the matrix in registers (four true multipliers of the 9-bit reading of
//!   an 8-bit code, signed or not, by an `offset_frac + 2`-bit entry), the luminance scale
//!   with its scale, bias and clamp, and three RGB products;
//! * the PASS_THROUGH converter's four lanes;
//! * the fetch of the largest texture (4096 x 4096, bilinear, clamp and mirror addressing),
//!   the filter of the wider of four 8-bit and two 16-bit lanes;
//! * the cube face per stage and one reflection per part (`2 N (N.E) - E (N.N)` over `N.N`,
//!   as `eval.rs` computes it): the items of the configured cube-map programs, whose Verilog
//!   synthesis confirms;
//! * program selection, stage state and result registers, the sequencer.
//!
//! The figure therefore moves with the calibrated items; what synthesis confirms is the
//! configured datapath (`Unit::generated_gates`).

use super::price::{
    cast_fixed, cube_face, divider, hemisphere_z, mapping, mul, pass_lane, reflection, sum, Rg,
};
use super::{DotMapping, TextureShader};
use crate::format::{Codec, Encoding, Format};
use crate::gates::{CostTable, GateBudget};
use crate::sampler::{Address, Filter, Sampler};
use crate::unit::Unit;
use crate::units::fetch::{address_gates, filter_gates};

/// The largest texture a stage reads, log2 of its side (the NV2A's 4096).
const MAX_TEXTURE_LOG: u32 = 12;

/// The readings `mappings` of a code side by side (each its own constant datapath; a
/// hemisphere reading's z counted once, by `z`): their summed price and the union of their
/// ranges.
fn readings(t: &CostTable, mappings: &[DotMapping], df: u32, z: bool) -> (f64, Rg) {
    let u8 = Encoding::texel(Codec::UnitUnsigned, false, 8);
    let mut ge = 0.0;
    let mut u = Rg {
        lo: 0,
        hi: 0,
        frac: df,
    };
    let mut zmax: f64 = 0.0;
    for &mp in mappings {
        let (g, r) = mapping(t, mp, &u8, df);
        ge += g;
        if mp.is_hilo() && mp != DotMapping::Hilo1 {
            let zr = hemisphere_z(t, r, df);
            ge -= zr;
            zmax = zmax.max(zr);
        }
        u = Rg {
            lo: u.lo.min(r.lo),
            hi: u.hi.max(r.hi),
            frac: df,
        };
    }
    (ge + if z { zmax } else { 0.0 }, u)
}

/// The price of the programmable part (see the module documentation).
pub(super) fn programmable(u: &TextureShader, t: &CostTable) -> GateBudget {
    let p = u.params();
    let n = u.stages.len() as u32;
    let w = p.coord.width();
    let (df, of) = (p.dot_frac, p.offset_frac);
    let c = Rg::of(&p.coord.format);
    let mut g = GateBudget::new();
    g.add(
        format!("coordinate registers 4 x {w} x{n} stages"),
        n,
        t.register(4 * w),
    );
    g.add(
        format!("projective divider {w} (s/q, t/q) x{n}"),
        2 * n,
        divider(t, &p.coord),
    );
    // the dot mapping: 8-bit codes (three components) and HILO codes (two and the z)
    use DotMapping::*;
    let (m8, r8) = readings(
        t,
        &[ZeroToOne, Minus1To1D3d, Minus1To1Gl, Minus1To1],
        df,
        false,
    );
    g.add(
        format!("dot mapping: 8-bit codes, the 4 readings x3 and their select x{n}"),
        n,
        m8 + 3.0 * t.mux(r8.width(), 4),
    );
    let hilo = [Hilo1, HiloHemisphereD3d, HiloHemisphereGl, HiloHemisphere];
    let (mh, rh) = readings(t, &hilo, df, true);
    g.add(
        format!(
            "dot mapping: HILO codes, the 4 readings x2, the hemisphere's z and their select x{n}"
        ),
        n,
        mh + 3.0 * t.mux(rh.width(), 4),
    );
    let nr = Rg {
        lo: r8.lo.min(rh.lo),
        hi: r8.hi.max(rh.hi),
        frac: df,
    };
    g.add(
        format!("dot mapping select 8-bit / HILO {} x3 x{n}", nr.width()),
        3 * n,
        t.mux(nr.width(), 2),
    );
    let (pp, prod) = mul(t, c, nr);
    g.add(
        format!("dot products {}x{} x3 x{n}", c.width(), nr.width()),
        3 * n,
        pp,
    );
    let (ps, s) = sum(t, &[prod, prod, prod]);
    g.add(
        format!("dot sum {} and cast x{n}", s.width()),
        n,
        ps + cast_fixed(t, s, &p.coord),
    );
    // the offset: an 8-bit code read signed or not (9 bits), the matrix in registers
    let d = Rg {
        lo: -256,
        hi: 255,
        frac: 8,
    };
    let m = Rg::of(&Format::s(of as u8 + 2, of as u8));
    let (pm, dm) = mul(t, d, m);
    g.add(
        format!(
            "offset matrix multipliers {}x{} (DS, DT x 2x2) x{n}",
            d.width(),
            m.width()
        ),
        4 * n,
        pm,
    );
    let (po, os) = sum(t, &[c, dm, dm]);
    g.add(
        format!("offset sums {} and casts (s, t) x{n}", os.width()),
        2 * n,
        po + cast_fixed(t, os, &p.coord),
    );
    // the luminance: scale x magnitude + bias, clamped, times each RGB lane, cast
    let mag = Rg {
        lo: 0,
        hi: 255,
        frac: 8,
    };
    let (pl, l) = mul(t, mag, m);
    let (pb, lb) = sum(t, &[l, m]);
    let lum = Rg {
        lo: 0,
        hi: 1i128 << (of + 1),
        frac: of,
    };
    let (prgb, rgb) = mul(t, mag, lum);
    let kk = ((1u128 << 8) + 1) * ((1u128 << 8) - 1);
    g.add(
        format!("luminance scale, bias and clamp {} x{n}", lb.width()),
        n,
        pl + pb + t.clamp(of + 2),
    );
    g.add(
        format!(
            "luminance RGB products {}x{} and casts x3 x{n}",
            mag.width(),
            lum.width()
        ),
        3 * n,
        prgb + t.shift_add(rgb.width(), kk) + t.constant_add(rgb.width()) + t.clamp(8),
    );
    g.add(
        format!(
            "colour converter: 4 lanes into {} bits x{n}",
            p.pass_through.width()
        ),
        4 * n,
        pass_lane(t, p, &p.pass_through),
    );
    g.add(
        format!("cube face: magnitudes, major axis, selects and the two projections x{n}"),
        n,
        cube_face(t, c),
    );
    g.add_part("", 1, reflection(t, &p.coord, None));
    if let Some(l) = p.lod {
        let lw = l.width();
        g.add(
            format!(
                "mip level select: lod rounding adder {lw}, clamp to the level count, level base address adder 24 and per-level shift mux x{n}"
            ),
            n,
            t.adder(lw) + t.clamp(lw) + t.adder(24) + t.mux(w, 4),
        );
    }
    fetch(&mut g, t, p.coord, n);
    g.add(
        format!(
            "program / input select muxes (16 programs, {} lanes) x{n}",
            4 * w
        ),
        n,
        t.mux(4 * w, 16),
    );
    g.add(
        format!("stage state: program, mapping, cull modes, matrix 4 x {}, scale, bias, eye 3 x {w} = {} bits x{n}", of + 2, 16 + 6 * (of + 2) + 3 * w),
        n,
        t.register(16 + 6 * (of + 2) + 3 * w),
    );
    g.add(
        format!("result registers 4 x 16 + dot {w} x{n} (pipeline)"),
        n,
        t.register(64 + w),
    );
    g.add("sequencer", 1, t.sequencer(u.latency()));
    g
}

/// A stage's fetch of any texture: the addressing of the largest (bilinear, clamp, the mirror
/// logic beside it), the index and weight bits selected by the texture's size, and the
/// filter of the wider texel (four 8-bit or two 16-bit lanes).
fn fetch(g: &mut GateBudget, t: &CostTable, coord: Encoding, n: u32) {
    // a bilinear tap needs a fraction bit below the texel
    let log = MAX_TEXTURE_LOG.min((coord.format.frac as u32).saturating_sub(1));
    let bilinear = |a| {
        Sampler::new(Filter::Bilinear, 8)
            .map(|s| s.with_address(a, a))
            .ok()
    };
    let (Some(clamp), Some(mirror)) = (bilinear(Address::Clamp), bilinear(Address::Mirror)) else {
        return;
    };
    let mut a = GateBudget::new();
    let eff = address_gates(&mut a, t, &coord, (log, log), &clamp, 1);
    let mut mi = GateBudget::new();
    address_gates(&mut mi, t, &coord, (log, log), &mirror, 1);
    for it in mi.items.iter().filter(|i| i.what.contains("mirror")) {
        a.add(it.what.clone(), 1, it.ge);
    }
    a.add(
        format!(
            "index and weight select by the texture's size {}:1",
            log + 1
        ),
        2,
        t.mux(eff[0].0 + eff[0].1, log + 1),
    );
    let rgba = Encoding::texel(Codec::UnitUnsigned, false, 8);
    let hilo = Encoding::texel(Codec::UnitSigned, true, 16);
    // the weights of a small texture (the largest leaves fewer fraction bits below a texel)
    let weights = [clamp.weight_bits(); 2];
    let mut f8 = GateBudget::new();
    filter_gates(&mut f8, t, &rgba, 4, &rgba, &clamp, weights);
    let mut f16 = GateBudget::new();
    filter_gates(&mut f16, t, &hilo, 2, &hilo, &clamp, weights);
    let f = if f8.total() >= f16.total() { f8 } else { f16 };
    g.add_part(&format!("fetch x{n}: "), n, a);
    g.add_part(&format!("filter x{n}: "), n, f);
}

//! Verilog of the colour-table builder's `EnvMap` function (Tarini et al. §5.1 item 3: the
//! entry is the environment texel the reflected view ray meets; the model is
//! [`crate::units::palette_builder`]'s `EnvMap`, an OpenGL sphere map in the viewer's eye
//! frame), after the builder's slot issue, normal read and dot product
//! ([`super::palette_builder`]).
//!
//! * Slots (the model's four clocks per entry): `N.V`, registered; then per axis `a` of the
//!   eye frame (`x`, `y`, `z`: vector registers the host loads) `N.a`, forming `R.a = 2 (N.V)
//!   (N.a) - V.a` (`V.a` a host constant, the exact product of two vector readings), each
//!   cast into its word (`SphereAddress::r_encoding`: s2.`r_frac`, truncated, saturated) and
//!   registered.
//! * Stage 2 (the clock after the `z` slot): `q = R_x^2 + R_y^2 + (R_z + 1)^2` exact and the
//!   leading-one detector of Normalize's reciprocal square root ([`super::normalize::detect`]);
//!   stage 3: the table (a ROM of the model's own entries); stage 4: per axis `floor(n (1 +
//!   R_a rho 2^k) / 2)` clamped to `0..n` and the texel address `j w + i`, into the
//!   environment image (a memory the host loads, one per material, a black box in synthesis);
//!   stage 5: the texel's RGB words and alpha `1` into the colour table. `q = 0` needs no
//!   zero detect: it has `R_x = R_y = 0`, so the product is 0 whatever the table gives, the
//!   model's `floor(n / 2)`.
//!
//! A table of `EnvMap` materials only: its entries are written two clocks later than the
//! other functions' (`T + 6` clocks per frame for `T` slots).

use super::fixed::{add, clamp, constant, from_code, mul, overflow, plain, register, scale};
use super::fixed::{shift_round, to_code};
use super::fixed::{square, sum, Fx};
use super::normalize::{detect, stage, stage_bits, stage_detect, table_value, times_pow2};
use super::palette_builder::{any_eq, material_of, reflection, write_port, Slot, Writes};
use super::verilog::{unsigned_bits, Module};
use super::Shell;
use crate::format::{Format, Overflow, Quant};
use crate::units::palette_builder::LightingFn;
use crate::units::PaletteBuilder;

/// Stage 1 of the builder as the env path reads it.
pub(crate) struct Stage1<'a> {
    /// The slot's dot product `N . vector`.
    pub dot: &'a Fx,
    /// The slot's host constant `V.a`.
    pub konst: &'a Fx,
    /// Slot, entry and valid registers of stage 1.
    pub f1: &'a str,
    pub e1: &'a str,
    pub v1: &'a str,
    pub fb: u32,
    pub eb: u32,
}

/// The env path from stage 1 to the colour table's write port; `frame` and `done` are the
/// shell's frame pulse and done register, `cycles` its clocks per frame.
pub(crate) fn finish(
    sh: &mut Shell,
    b: &PaletteBuilder,
    slots: &[Slot],
    s1: Stage1,
    (frame, done, cycles): (&str, &str, u32),
    addr_bits: u32,
) -> Result<Writes, String> {
    let rs = b
        .sphere()
        .ok_or("EnvMap: the builder has no sphere-map table")?
        .clone();
    let (fb, eb) = (s1.fb, s1.eb);
    let f = *b.formats();
    let m = &mut sh.m;
    let flag = |m: &mut Module, a: u8| {
        let e = any_eq(
            s1.f1,
            fb,
            slots
                .iter()
                .enumerate()
                .filter(|(_, x)| x.env == Some(a))
                .map(|(i, _)| i),
        );
        m.uwire("env_slot", 1, &format!("{} && ({e})", s1.v1))
    };
    m.comment("EnvMap: N.V registered; R.a = 2 (N.V)(N.a) - V.a per axis of the eye frame");
    let is_v = flag(m, 0);
    let nv = register(m, "env_nv", &is_v, s1.dot, s1.dot.lo, s1.dot.hi);
    let r = reflection(m, &nv, s1.dot, s1.konst);
    // R.a's word: s2.r_frac, truncated and saturated
    let re = f.sphere.r_encoding();
    let code = to_code(m, &r, &re);
    let r = from_code(m, &code, &re);
    let axes: Vec<Fx> = (1..=3u8)
        .map(|a| {
            let en = flag(m, a);
            register(m, &format!("env_r{a}"), &en, &r, r.lo, r.hi)
        })
        .collect();
    let z_slot = flag(m, 3);
    let v2 = stage_bits(m, "env_v2", 1, &format!("{z_slot} && !rst"));
    let e2 = stage_bits(m, "env_e2", eb, s1.e1);
    m.comment("EnvMap stage 2: q = R_x^2 + R_y^2 + (R_z + 1)^2 and the detector");
    let z1 = add(m, &axes[2], &constant(1, 0));
    let sq: Vec<Fx> = [&axes[0], &axes[1], &z1]
        .iter()
        .map(|x| square(m, x))
        .collect();
    let q = sum(m, &[&sq[0], &sq[1], &sq[2]]);
    let q = plain(m, &q);
    let tb = rs.index_bits();
    let d = detect(m, &q, tb);
    let d3 = stage_detect(m, "env_d3", &d, tb);
    let rx3 = stage(m, "env_rx3", &axes[0]);
    let ry3 = stage(m, "env_ry3", &axes[1]);
    let v3 = stage_bits(m, "env_v3", 1, &format!("{v2} && !rst"));
    let e3 = stage_bits(m, "env_e3", eb, &e2);
    m.comment("EnvMap stage 3: the reciprocal-square-root table");
    let rom = format!("{}_sphere_rsqrt", sh.m.name);
    let rho = table_value(sh, &rs, &d3.idx, &rom);
    let m = &mut sh.m;
    let rho4 = stage(m, "env_rho4", &rho);
    let kk4 = stage_bits(m, "env_kk4", d3.kb, &d3.kk);
    let rx4 = stage(m, "env_rx4", &rx3);
    let ry4 = stage(m, "env_ry4", &ry3);
    let v4 = stage_bits(m, "env_v4", 1, &format!("{v3} && !rst"));
    let e4 = stage_bits(m, "env_e4", eb, &e3);
    m.comment("EnvMap stage 4: the texel address, floor(n (1 + R_a rho 2^k) / 2) per axis");
    let mat4 = material_of(m, b, &e4, eb);
    let we = f.entry.width();
    let mut texels = Vec::new();
    for (k, (_, func)) in b.materials().iter().enumerate() {
        let m = &mut sh.m;
        let LightingFn::EnvMap {
            image,
            width,
            height,
            ..
        } = func
        else {
            return Err(format!("material {k}: expected EnvMap"));
        };
        let mut coord = |c: &Fx, n: u32| {
            let p = mul(m, c, &rho4);
            let t = times_pow2(m, &p, &kk4, d.k_lo, d.k_hi);
            let u = add(m, &constant(1, 0), &t);
            let us = scale(m, &u, n as i128);
            let half = Fx {
                frac: us.frac + 1,
                ..us
            };
            let fl = shift_round(m, &half, half.frac, Quant::Trn);
            let cl = clamp(m, &fl, Some((0, 0)), Some((n as i128 - 1, 0)));
            let bits = unsigned_bits(n.saturating_sub(1) as u128);
            overflow(m, &cl, &Format::u(bits as u8, 0), Overflow::Wrap)
        };
        let i = coord(&rx4, *width);
        let j = coord(&ry4, *height);
        let ab = unsigned_bits((*width as u128 * *height as u128).saturating_sub(1));
        let addr = m.uwire("env_addr", ab, &format!("{j} * {ab}'d{width} + {i}"));
        let words: Vec<u128> = image
            .iter()
            .map(|t| {
                (0..3).fold(0u128, |acc, l| {
                    let c = f.entry.encode(t[l]);
                    acc | (f.entry.format.bits(c) as u128) << (l as u32 * we)
                })
            })
            .collect();
        let data = sh.memory(&format!("env{k}"), words, 3 * we, &[(addr, ab)], 1);
        texels.push(data[0].clone());
    }
    let m = &mut sh.m;
    m.comment("EnvMap stage 5: the texel and alpha 1 into the colour table");
    let mat5 = stage_bits(
        m,
        "env_m5",
        unsigned_bits(texels.len().saturating_sub(1) as u128),
        &mat4,
    );
    let v5 = stage_bits(m, "env_v5", 1, &format!("{v4} && !rst"));
    let e5 = stage_bits(m, "env_e5", eb, &e4);
    let texel = m.select_bits(&mat5, &texels, 3 * we);
    let one = f.entry.format.bits(f.entry.encode(1.0));
    let data = m.uwire("env_entry", 4 * we, &format!("{{{we}'d{one}, {texel}}}"));
    Ok(write_port(
        m,
        (v5, e5, eb),
        data,
        addr_bits,
        (frame, done, cycles),
        b.entries(),
    ))
}

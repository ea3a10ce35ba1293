//! Verilog of the texel fetch and filter unit ([`crate::units::TexFetch`], the SGI engine's
//! normal-map read, Gouraud bump paper §3.4; Ernst et al. §5.3's filtered bump map): the
//! sampler's addressing ([`crate::sampler::texel_axis`], [`crate::sampler::Address`]), the
//! texel reads through `ports` memory ports, and nearest or bilinear filtering with the
//! model's truncated weights, exact lerps and one cast ([`crate::sampler::Sampler::sample_bits`]).
//!
//! * Addressing per axis of `2^log` texels at a coordinate of `F` fraction bits: `s' = s -
//!   2^(F - log - 1)` when bilinear (the half-texel offset), integer part `s' >>> (F - log)`
//!   (the arithmetic shift floors negative coordinates), fraction `s'[F - log - 1 : 0]`
//!   truncated or padded to `weight_bits`. The neighbour is the integer part plus one. Wrap
//!   keeps the low `log` bits, clamp saturates to `[0, 2^log - 1]`, mirror reads the low `log
//!   + 1` bits and inverts the low `log` when bit `log` is set. The address is `{j, i}`.
//! * The texel store is a memory module ([`super::Memory`]): `ports` read ports, the word
//!   `mem_latency` clocks after its address, lanes packed from bit 0. For co-simulation it is a
//!   behavioural model loaded with the level-0 codes (palette textures hold the looked-up
//!   codes: the palette RAM is priced as memory, `docs/rtl.md`); synthesis treats it as a
//!   black box, so the unit's figure is its logic, as the gate model prices it.
//! * The lerps are `a + (b - a) w`, one multiplier each; exactly the model's `a (1 - w) + b
//!   w`. The filtered value is cast once into the output encoding.
//!
//! Clocking: tap group `g` (taps `g P .. g P + P - 1` of `00, 10, 01, 11`) is addressed in
//! the cycle before edge `g + 1` and arrives after edge `g + L`. Nearest, and bilinear with
//! one group (4 ports): the cast or the filter writes the output registers on edge `L + 1`.
//! Bilinear with `I > 1` groups: each group is loaded into the tap registers on edge `g + L
//! + 1` and the filter writes the output on edge `L + I + 1`, the model's latency. The weights
//! are registered at `start`.

use super::fixed::{add, clamp, constant, from_code, make, mul, raw_word, register, sub, Fx};
use super::verilog::Module;
use super::{Plan, RtlUnit, Shell};
use crate::format::{Encoding, Format};
use crate::sampler::{Address, Filter};
use crate::unit::Unit;
use crate::units::TexFetch;

/// One axis: the tap indices' address bits (`[own, next]`, `log` bits each; `None` for a
/// one-texel axis) and the fraction bits that remain after the texel index.
pub(crate) struct Axis {
    pub(crate) addr: [Option<String>; 2],
    pub(crate) frac: Option<(String, u32)>,
}

/// One axis of `2^log` texels of the coordinate `raw` at `frac` fraction bits
/// ([`crate::sampler::texel_axis`], the address mode applied).
pub(crate) fn axis(
    m: &mut Module,
    raw: &Fx,
    frac: u32,
    log: u32,
    centered: bool,
    mode: Address,
) -> Axis {
    let f = frac - log;
    let s = if centered {
        sub(m, raw, &constant(1i128 << (f - 1), 0))
    } else {
        raw.clone()
    };
    let fr = (f > 0).then(|| (m.uwire("fr", f, &format!("{}[{}:0]", s.name, f - 1)), f));
    let i = make(
        m,
        "ti",
        s.lo >> f,
        s.hi >> f,
        0,
        &format!("{} >>> {f}", s.name),
    );
    let next = add(m, &i, &constant(1, 0));
    let addr = [i, next].map(|x| (log > 0).then(|| address(m, &x, log, mode)));
    Axis { addr, frac: fr }
}

/// The `log` address bits of texel index `x` after addressing.
fn address(m: &mut Module, x: &Fx, log: u32, mode: Address) -> String {
    let n = 1i128 << log;
    match mode {
        Address::Wrap => m.uwire("wrap", log, &format!("{}[{}:0]", x.name, log - 1)),
        Address::Clamp => {
            let c = clamp(m, x, Some((0, 0)), Some((n - 1, 0)));
            m.uwire("clmp", log, &format!("{}[{}:0]", c.name, log - 1))
        }
        Address::Mirror => {
            let x = super::fixed::align_wire(m, x, 0);
            let r = m.uwire("per", log + 1, &format!("{}[{log}:0]", x.name));
            m.uwire(
                "mirr",
                log,
                &format!("{r}[{log}] ? ~{r}[{}:0] : {r}[{}:0]", log - 1, log - 1),
            )
        }
    }
}

/// The `wb`-bit weight from an axis fraction of `f` bits (the model's truncation).
pub(crate) fn weight(m: &mut Module, fr: &Option<(String, u32)>, wb: u32) -> String {
    match fr {
        None => m.uwire("wt", wb, &format!("{wb}'d0")),
        Some((name, f)) if *f >= wb => m.uwire("wt", wb, &format!("{name}[{}:{}]", f - 1, f - wb)),
        Some((name, f)) => m.uwire("wt", wb, &format!("{{{name}, {}'d0}}", wb - f)),
    }
}

/// The Verilog of a built [`TexFetch`] (its ports, sampler and texture are the parameters).
pub fn rtl(u: &TexFetch, top: &str) -> Result<RtlUnit, String> {
    let mut sh = Shell::new(top, plan(u));
    let uv = u.inputs()[0].clone();
    let coords = sh.port(0, &uv, false);
    let outs = sh.output(0, &u.outputs()[0]);
    let codes = datapath(&mut sh, u, &coords, "texels")?;
    let fin = sh.fin.clone();
    for (o, code) in outs.iter().zip(&codes) {
        sh.m.stmt(format!("always @(posedge clk) if ({fin}) {o} <= {code};"));
    }
    Ok(sh.finish())
}

/// The fetch's own clocking: the memory's latency, the tap groups, one edge into the outputs.
pub(crate) fn plan(u: &TexFetch) -> Plan {
    let groups = u.interval();
    let lat = u.mem_latency();
    Plan {
        capture: false,
        interval: if groups > 1 { lat + groups } else { lat },
        finish: true,
    }
}

/// The fetch between the coordinate words `coords` (held from `start`) and the output codes
/// in `sh`, the texel store a memory named `mem`: returns one code wire per output lane, valid
/// while `step` is [`plan`]'s interval (the cycle before the fetch's own output edge).
pub(crate) fn datapath(
    sh: &mut Shell,
    u: &TexFetch,
    coords: &[String],
    mem: &str,
) -> Result<Vec<String>, String> {
    let tex = u.texture();
    let level = tex.level_at(0);
    let (log_w, log_h) = level.logs();
    let sampler = u.sampler();
    let bilinear = sampler.filter() == Filter::Bilinear;
    let (taps, ports) = (sampler.taps(), u.ports());
    let groups = u.interval();
    let lat = u.mem_latency();
    let uv = u.inputs()[0].clone();
    let frac = uv.enc.format.frac as u32;
    let (texel, wt, lanes) = texel_word(tex)?;
    let out_enc = u.outputs()[0].enc;
    let t = sh.t.clone();
    let sb = super::verilog::unsigned_bits(sh.plan.latency() as u128);
    let [am_s, am_t] = sampler.address();
    let m = &mut sh.m;
    m.comment("addressing");
    let rs = raw_word(m, &coords[0], &uv.enc.format);
    let rt = raw_word(m, &coords[1], &uv.enc.format);
    let ax_s = axis(m, &rs, frac, log_w, bilinear, am_s);
    let ax_t = axis(m, &rt, frac, log_h, bilinear, am_t);
    let abits = (log_w + log_h).max(1);
    let tap_offsets: &[(usize, usize)] = if bilinear {
        &[(0, 0), (1, 0), (0, 1), (1, 1)]
    } else {
        &[(0, 0)]
    };
    let tap_addr: Vec<String> = tap_offsets
        .iter()
        .map(|&(di, dj)| {
            let parts: Vec<String> = [&ax_t.addr[dj], &ax_s.addr[di]]
                .into_iter()
                .flatten()
                .cloned()
                .collect();
            if parts.is_empty() {
                m.uwire("addr", 1, "1'b0")
            } else {
                m.uwire("addr", abits, &format!("{{{}}}", parts.join(", ")))
            }
        })
        .collect();
    // port p reads tap g P + p in group g
    let port_addr: Vec<(String, u32)> = (0..ports.min(taps) as usize)
        .map(|p| {
            let names: Vec<String> = (0..groups as usize)
                .map(|g| g * ports as usize + p)
                .filter(|&k| k < taps as usize)
                .map(|k| tap_addr[k].clone())
                .collect();
            (m.select_bits(&t, &names, abits), abits)
        })
        .collect();
    let wb = sampler.weight_bits();
    let weights = bilinear.then(|| {
        m.comment("weights, registered at start");
        let w = [weight(m, &ax_s.frac, wb), weight(m, &ax_t.frac, wb)];
        let w = w.map(|x| raw_word(m, &x, &Format::u(wb as u8, 0)));
        let hi = (1i128 << wb) - 1;
        [("w_u", &w[0]), ("w_v", &w[1])].map(|(n, x)| register(m, n, "start", x, 0, hi).at_frac(wb))
    });
    let word = (wt as usize * lanes) as u32;
    let words: Vec<u128> = (0..(level.width() * level.height()) as usize)
        .map(|k| {
            let c = level.code(k);
            (0..lanes).fold(0u128, |acc, l| {
                acc | (texel.format.bits(c[l]) as u128) << (l as u32 * wt)
            })
        })
        .collect();
    let data = sh.memory(mem, words, word, &port_addr, lat);
    let m = &mut sh.m;
    // the tap words: registered per group when the reads take several clocks
    let tap_word: Vec<String> = (0..taps as usize)
        .map(|k| {
            let (g, p) = (k / ports as usize, k % ports as usize);
            if groups > 1 {
                let r = m.reg(&format!("tap_{k}"), word);
                m.stmt(format!(
                    "always @(posedge clk) if (step == {sb}'d{}) {r} <= {};",
                    g as u32 + lat,
                    data[p]
                ));
                r
            } else {
                data[p].clone()
            }
        })
        .collect();
    let lanes = u.outputs()[0].lanes as usize;
    let codes = filter(
        m,
        &tap_word,
        lanes,
        &texel,
        weights.as_ref(),
        &out_enc,
        "lane",
    );
    Ok(codes)
}

/// Each lane of the tap words (`taps[k]`: tap `k` of `00, 10, 01, 11`, lanes packed from bit 0
/// at the texel's width) read by the texel's codec, filtered (nearest: tap 0; bilinear: the
/// lerps `a + (b - a) w` with the weights `[w_u, w_v]`, exactly the model's) and cast once into
/// `out`: the texel fetch's filter, shared with the texture shaders' stages. `what` starts each
/// lane's comment.
/// A texture's texel encoding, its width and its lanes, checked to fit the memory's words
/// (all lanes of a texel in one word of at most 128 bits).
pub(crate) fn texel_word(tex: &crate::texture::Texture) -> Result<(Encoding, u32, usize), String> {
    let lanes = tex.lanes() as usize;
    let texel: Encoding = *tex.texel();
    let wt = texel.width();
    match wt as usize * lanes > 128 {
        true => Err(format!(
            "texel words of {} bits: expected at most 128",
            wt as usize * lanes
        )),
        false => Ok((texel, wt, lanes)),
    }
}

pub(crate) fn filter(
    m: &mut Module,
    taps: &[String],
    lanes: usize,
    texel: &Encoding,
    weights: Option<&[Fx; 2]>,
    out: &Encoding,
    what: &str,
) -> Vec<String> {
    let wt = texel.width();
    let mut codes = Vec::new();
    for l in 0..lanes {
        m.comment(&format!("{what} {l}"));
        let read = |m: &mut Module, k: usize| {
            let bits = m.uwire(
                "tx",
                wt,
                &format!("{}[{}:{}]", taps[k], (l as u32 + 1) * wt - 1, l as u32 * wt),
            );
            from_code(m, &bits, texel)
        };
        let v = match weights {
            None => read(m, 0),
            Some([wu, wv]) => {
                let lerp = |m: &mut Module, a: &Fx, b: &Fx, w: &Fx| {
                    let d = sub(m, b, a);
                    let p = mul(m, &d, w);
                    add(m, a, &p)
                };
                let (t00, t10, t01, t11) = (read(m, 0), read(m, 1), read(m, 2), read(m, 3));
                let top = lerp(m, &t00, &t10, wu);
                let bot = lerp(m, &t01, &t11, wu);
                lerp(m, &top, &bot, wv)
            }
        };
        codes.push(super::fixed::to_code(m, &v, out));
    }
    codes
}

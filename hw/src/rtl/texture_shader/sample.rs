//! The texel fetch of one texture-shader stage: the sampler's addressing per mip level
//! ([`crate::rtl::fetch::axis`]), one read port per tap through the stage's texture memory,
//! nearest or bilinear filtering with the model's truncated weights
//! ([`crate::sampler::Sampler::sample_bits`]) and the cast into the stage's result encoding.
//!
//! Every level of the stage's texture that the program can read is stored in one memory, the
//! levels one after the other (level `l` from address `base_l`); the level select (from the
//! `lod` input, TEXTURE_2D only) picks each tap's offset in the level, the base and, when
//! bilinear, the weights.

use super::super::fetch::{axis, filter, weight};
use super::super::fixed::raw_word;
use super::super::verilog::unsigned_bits;
use super::super::Shell;
use crate::format::{Encoding, Format};
use crate::sampler::{Filter, Sampler};
use crate::texture::Texture;

/// One stage's texture read.
pub(super) struct Fetch<'a> {
    pub tex: &'a Texture,
    pub sampler: &'a Sampler,
    /// Levels stored (1: level 0 only).
    pub levels: usize,
    /// Faces stored (6: a cube map's level 0, face-major, read with a face select).
    pub faces: usize,
    /// The coordinate encoding (its fraction bits address the texels).
    pub coord: Encoding,
    /// The stage's result encoding.
    pub out: Encoding,
}

/// The texel words of the first `faces` faces of level `l`, lanes packed from bit 0.
fn level_words(tex: &Texture, l: usize, faces: usize) -> Vec<u128> {
    let level = tex.level_at(l);
    let texel = tex.texel();
    let wt = texel.width();
    let lanes = tex.lanes() as usize;
    (0..faces * (level.width() * level.height()) as usize)
        .map(|k| {
            let c = level.code(k);
            (0..lanes).fold(0u128, |acc, ln| {
                acc | (texel.format.bits(c[ln]) as u128) << (ln as u32 * wt)
            })
        })
        .collect()
}

/// The fetch of `f` at the coordinate words `s`, `t` (coordinate raw words, stable from the
/// clock before the memory's read edge until the result is registered) from level `level`
/// (a wire, `None`: level 0) and face `face` (a 3-bit wire of a cube map, `f.faces` 6: the
/// face's texels from `face 2^(log_w + log_h)`). The memory is `{top}_{mem}`, one port per
/// tap, one clock.
/// Returns one code wire per texture lane (in `f.out`), valid after the read edge.
pub(super) fn fetch(
    sh: &mut Shell,
    f: &Fetch,
    s: &str,
    t: &str,
    level: Option<&str>,
    face: Option<&str>,
    mem: &str,
) -> Result<Vec<String>, String> {
    let tex = f.tex;
    let sampler = f.sampler;
    let bilinear = sampler.filter() == Filter::Bilinear;
    let frac = f.coord.format.frac as u32;
    let (texel, wt, lanes) = crate::rtl::fetch::texel_word(tex)?;
    let word = wt * lanes as u32;
    let mut bases = Vec::new();
    let mut words: Vec<u128> = Vec::new();
    for l in 0..f.levels {
        let (log_w, log_h) = tex.level_at(l).logs();
        let need = if bilinear { 1 } else { 0 };
        if frac < log_w.max(log_h) + need {
            return Err(format!(
                "level {l} of 2^{log_w} x 2^{log_h} texels from a coordinate of {frac} fraction bits"
            ));
        }
        bases.push(words.len() as u128);
        words.extend(level_words(tex, l, f.faces));
    }
    let abits = unsigned_bits(words.len().saturating_sub(1) as u128).max(1);
    let [am_s, am_t] = sampler.address();
    let wb = sampler.weight_bits();
    let taps: &[(usize, usize)] = if bilinear {
        &[(0, 0), (1, 0), (0, 1), (1, 1)]
    } else {
        &[(0, 0)]
    };
    let m = &mut sh.m;
    m.comment("texel addressing per level");
    let rs = raw_word(m, s, &f.coord.format);
    let rt = raw_word(m, t, &f.coord.format);
    // per level: the tap offsets in the level and the weights
    let mut offs: Vec<Vec<String>> = vec![Vec::new(); taps.len()];
    let mut wts: [Vec<String>; 2] = [Vec::new(), Vec::new()];
    for l in 0..f.levels {
        let (log_w, log_h) = tex.level_at(l).logs();
        let ax_s = axis(m, &rs, frac, log_w, bilinear, am_s);
        let ax_t = axis(m, &rt, frac, log_h, bilinear, am_t);
        let w = log_w + log_h;
        for (k, &(di, dj)) in taps.iter().enumerate() {
            let parts: Vec<String> = [&ax_t.addr[dj], &ax_s.addr[di]]
                .into_iter()
                .flatten()
                .cloned()
                .collect();
            offs[k].push(if parts.is_empty() {
                m.uwire("toff", abits, &format!("{abits}'d0"))
            } else if w < abits {
                m.uwire(
                    "toff",
                    abits,
                    &format!("{{{}'d0, {}}}", abits - w, parts.join(", ")),
                )
            } else {
                m.uwire("toff", abits, &format!("{{{}}}", parts.join(", ")))
            });
        }
        if bilinear {
            wts[0].push(weight(m, &ax_s.frac, wb));
            wts[1].push(weight(m, &ax_t.frac, wb));
        }
    }
    let lsel = level.unwrap_or("1'b0");
    let base_words: Vec<String> = bases.iter().map(|b| format!("{abits}'d{b}")).collect();
    let base = if f.levels > 1 {
        Some(m.select_bits(lsel, &base_words, abits))
    } else {
        None
    };
    // a cube face's texels from face 2^(log_w + log_h) (level 0 only)
    let (lw, lh) = tex.level_at(0).logs();
    let fbase = match (face, f.faces > 1) {
        (Some(fc), true) if lw + lh > 0 => Some(format!("{{{fc}, {}'d0}}", lw + lh)),
        (Some(fc), true) => Some(fc.to_string()),
        _ => None,
    };
    let addrs: Vec<(String, u32)> = offs
        .iter()
        .map(|o| {
            let off = m.select_bits(lsel, o, abits);
            let a = match (&base, &fbase) {
                (Some(b), _) => m.uwire("taddr", abits, &format!("{off} + {b}")),
                (None, Some(b)) => m.uwire("taddr", abits, &format!("{off} | {b}")),
                (None, None) => off,
            };
            (a, abits)
        })
        .collect();
    let weights = bilinear.then(|| {
        [0, 1].map(|a| {
            let w = m.select_bits(lsel, &wts[a], wb);
            raw_word(m, &w, &Format::u(wb as u8, 0)).at_frac(wb)
        })
    });
    let data = sh.memory(mem, words, word, &addrs, 1);
    let m = &mut sh.m;
    Ok(filter(
        m,
        &data,
        lanes,
        &texel,
        weights.as_ref(),
        &f.out,
        "filter, lane",
    ))
}

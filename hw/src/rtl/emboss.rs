//! Verilog of the emboss filter ([`crate::units::EmbossFilter`], Lingard 1995 after Schlag,
//! Graphics Gems IV VIII.1): the nearest texel under the coordinate with wrap addressing
//! ([`crate::sampler::texel_axis`], [`crate::sampler::Sampler::index`]), its 3x3 neighbourhood
//! read `ports` texels per clock through the texture memory, the two mask sums as exact
//! integers, the cast of `(-i_u, -i_v)` into the output encoding and `N_z` from a host-loaded
//! register.
//!
//! * Addressing per axis of `2^log` texels at a coordinate of `F` fraction bits: the texel
//!   index is `s >>> (F - log)` (floor), and wrap keeps its low `log` bits, so only those are
//!   built: the index bits, a `log`-bit incrementer and decrementer for the neighbours (wrap
//!   by their width). The address is `{j, i}`; a one-texel axis has no bits.
//! * Tap `k` of [`TAPS`] (row by row) is read by port `k % P` in clock `k / P` (`P` =
//!   `ports`). Each port's address is `{j, i}`, each part a mux by the clock over the offsets
//!   the port's taps take on that axis, none where it is the same in every clock, and one mux
//!   per distinct sequence, shared by the ports that read it
//!   ([`crate::units::emboss::address_muxes`]): with 3 ports, port `p` reads column `p - 1`
//!   and the three share one `j` mux.
//! * The centre tap is read (the model's nine reads, its interval) but is in neither mask, so
//!   it has no tap register.
//! * The texel store is a memory module ([`super::Memory`]): the level-0 codes, the word
//!   `mem_latency` clocks after its address; a `$readmemh` model for co-simulation and a black
//!   box in synthesis, outside the unit's budget (as the gate model has it, and as the fetch's).
//! * The masks on the tap registers: `-i_u = sum_b (h[i-1, j+b] - h[i+1, j+b])` and `-i_v =
//!   sum_a (h[i+a, j-1] - h[i+a, j+1])` (the negation folded into the operand order), three
//!   subtractors and a three-input sum each, at their exact widths; the codes' rescale to the
//!   0..255 scale by the integer `255 / max_code` (shifts and adds; none for 8-bit texels);
//!   one cast into the output encoding ([`super::fixed::to_code`]), as the model's
//!   [`crate::units::emboss::cast`]. A texel format whose largest code does not divide 255 has
//!   the rational rescale `255 s / max_code` rounded once ([`super::cast::rational_code`]: the
//!   floor by the reciprocal of `max_code`, the remainder against zero and a half where the
//!   rounding mode needs them, the overflow).
//! * `N_z` is a host-loaded register (`cfg` address 0) holding the model's code
//!   ([`EmbossFilter::nz_code`]): the bevel width is a parameter of the image, not of the
//!   netlist.
//!
//! Clocking: group `g` (taps `g P .. g P + P - 1`) is addressed in the cycle before edge `g +
//! 1` and loaded into its tap registers on edge `g + L + 1`; the masks and the cast write the
//! output registers on edge `L + I + 1`, the model's latency (`I = ceil(9 / P)`).

use super::cast::rational_code;
use super::fixed::{raw_word, scale, sub, sum, to_code, Fx};
use super::verilog::{unsigned_bits, Module};
use super::{Plan, RtlUnit, Shell};
use crate::unit::Unit;
use crate::units::emboss::{port_offsets, EmbossFilter, TAPS};

/// The clocking: `I` tap groups after the memory's latency, one edge into the outputs.
pub(crate) fn plan(u: &EmbossFilter) -> Plan {
    Plan {
        capture: false,
        interval: u.mem_latency() + u.interval(),
        finish: true,
    }
}

/// The value of clock `g` of `vals` (one per group, `sel` the clock): one wire where every
/// clock takes the same value, else a mux over the distinct values (the last one the default).
fn select(m: &mut Module, sel: &str, vals: &[String], w: u32) -> String {
    let mut distinct: Vec<&String> = Vec::new();
    for v in vals {
        if !distinct.contains(&v) {
            distinct.push(v);
        }
    }
    let mut e = distinct.last().unwrap().to_string();
    if distinct.len() == 1 {
        return e;
    }
    for d in distinct.iter().rev().skip(1) {
        let cond: Vec<String> = vals
            .iter()
            .enumerate()
            .filter(|(_, v)| v == d)
            .map(|(g, _)| format!("({sel} == {g})"))
            .collect();
        e = format!("({}) ? {d} : ({e})", cond.join(" || "));
    }
    m.uwire("amux", w, &e)
}

/// The Verilog of a built [`EmbossFilter`].
pub fn rtl(u: &EmbossFilter, top: &str) -> Result<RtlUnit, String> {
    let tex = u.texture();
    let texel = *tex.texel();
    let k = u.code_scale();
    let mut sh = Shell::new(top, plan(u));
    let uv = u.inputs()[0].clone();
    let out = u.outputs()[0].clone();
    let coords = sh.port(0, &uv, false);
    let outs = sh.output(0, &out);
    let nz = sh.config_reg("N_z (code of 6 * 255 / w)", &out.enc, u.nz_code());
    let level = tex.level_at(0);
    let (log_w, log_h) = level.logs();
    let frac = uv.enc.format.frac as u32;
    let (ports, lat) = (u.ports() as usize, u.mem_latency());
    let wt = texel.width();
    let t = sh.t.clone();
    let sb = unsigned_bits(sh.plan.latency() as u128);
    let m = &mut sh.m;
    m.comment("addressing: the index's low bits and its neighbours, wrapped by their width");
    // per axis the address bits of offsets -1, 0, +1 (none for a one-texel axis)
    let axes: Vec<Option<[String; 3]>> = [(0usize, log_w), (1, log_h)]
        .into_iter()
        .map(|(a, log)| {
            (log > 0).then(|| {
                let raw = raw_word(m, &coords[a], &uv.enc.format);
                let ix = m.uwire("ix", log, &format!("{} >>> {}", raw.name, frac - log));
                let dec = m.uwire("ixm", log, &format!("{ix} - {log}'d1"));
                let inc = m.uwire("ixp", log, &format!("{ix} + {log}'d1"));
                [dec, ix, inc]
            })
        })
        .collect();
    let bits = |a: usize, off: i64| axes[a].as_ref().map(|x| x[(off + 1) as usize].clone());
    let logs = [log_w, log_h];
    m.comment("port addresses: port p reads tap g P + p in clock g; one mux per sequence");
    let mut muxes: Vec<(usize, Vec<i64>, String)> = Vec::new();
    let mut part = |m: &mut Module, a: usize, seq: &[i64]| -> Option<String> {
        let first = bits(a, seq[0])?;
        if seq.iter().all(|&o| o == seq[0]) {
            return Some(first);
        }
        if let Some((_, _, w)) = muxes.iter().find(|(b, s, _)| *b == a && s == seq) {
            return Some(w.clone());
        }
        let vals: Vec<String> = seq.iter().map(|&o| bits(a, o).unwrap()).collect();
        let w = select(m, &t, &vals, logs[a]);
        muxes.push((a, seq.to_vec(), w.clone()));
        Some(w)
    };
    let abits = (log_w + log_h).max(1);
    let port_addr: Vec<(String, u32)> = (0..ports.min(9))
        .map(|p| {
            let [si, sj] = port_offsets(ports as u32, p as u32);
            let i = part(m, 0, &si);
            let j = part(m, 1, &sj);
            let parts: Vec<String> = [j, i].into_iter().flatten().collect();
            let addr = if parts.is_empty() {
                m.uwire("addr", 1, "1'b0")
            } else {
                m.uwire("addr", abits, &format!("{{{}}}", parts.join(", ")))
            };
            (addr, abits)
        })
        .collect();
    debug_assert_eq!(
        muxes.len(),
        crate::units::emboss::address_muxes(ports as u32)
            .iter()
            .filter(|(a, _, _)| logs[*a] > 0)
            .count()
    );
    let words: Vec<u128> = (0..(level.width() * level.height()) as usize)
        .map(|k| texel.format.bits(level.code(k)[0]) as u128)
        .collect();
    let data = sh.memory("heights", words, wt, &port_addr, lat);
    let m = &mut sh.m;
    m.comment("tap registers: group g on edge g + L + 1 (the centre is read but in neither mask)");
    let taps: Vec<Option<Fx>> = (0..9)
        .map(|k| {
            if TAPS[k] == (0, 0) {
                return None;
            }
            let (g, p) = (k / ports, k % ports);
            let r = m.reg(&format!("tap_{k}"), wt);
            m.stmt(format!(
                "always @(posedge clk) if (step == {sb}'d{}) {r} <= {};",
                g as u32 + lat,
                data[p]
            ));
            Some(raw_word(m, &r, &texel.format))
        })
        .collect();
    let tap = |a: i64, b: i64| {
        let k = TAPS.iter().position(|&x| x == (a, b)).unwrap();
        taps[k].clone().expect("a tap of the masks")
    };
    m.comment("the masks: -i_u and -i_v as exact integers");
    let mut codes = Vec::new();
    for lane in 0..2 {
        let diffs: Vec<Fx> = (-1..=1)
            .map(|x| {
                let (lo, hi) = if lane == 0 {
                    (tap(-1, x), tap(1, x))
                } else {
                    (tap(x, -1), tap(x, 1))
                };
                sub(m, &lo, &hi)
            })
            .collect();
        let s = sum(m, &diffs.iter().collect::<Vec<_>>());
        codes.push(match k {
            Some(1) => to_code(m, &s, &out.enc),
            Some(k) => {
                let s = scale(m, &s, k);
                to_code(m, &s, &out.enc)
            }
            // 255 s / max_code, one rounding
            None => {
                let s = scale(m, &s, 255);
                rational_code(m, &s, texel.format.max_raw() as i128, &out.enc)
            }
        });
    }
    codes.push(nz);
    let fin = sh.fin.clone();
    for (o, c) in outs.iter().zip(&codes) {
        sh.m.stmt(format!("always @(posedge clk) if ({fin}) {o} <= {c};"));
    }
    Ok(sh.finish())
}

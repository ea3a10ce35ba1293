//! Emboss filter unit: Schlag's 3x3 gradient masks over a height texture.
//!
//! Lingard (1995), "An Example: Embossing", after Schlag, Graphics Gems IV VIII.1: the height
//! image `i(u, v)` is a surface `P = [u v i]` with normal `[-i_u, -i_v, 1]`; the derivatives are
//! estimated by the 3x3 masks `i_u = [-1 0 1]` (each of three rows) and `i_v` (three columns,
//! `+1` on the `+v` side), and the masks' response (6a for a ramp `i = a u`) is compensated by
//! the constant `N_z = 6 * 255 / w`, `w` the width of the bevel. The unit outputs the
//! unnormalised normal `(-i_u, -i_v, N_z)` in texel intensity units (0..255 scale); a
//! [`crate::units::normalize::Normalize`] and a dot product finish Lambert's
//! `N . L / (|N| |L|)`.
//!
//! The nine texels are read `ports` per clock from the texture memory (nearest texel under the
//! coordinate, wrap addressing), so the initiation interval is `ceil(9 / ports)`. The mask
//! sums are exact integers (per mask three differences and a three-input sum); `N_z` is a
//! host-loaded register holding its code in the output encoding.
//!
//! Bit-accurate mode computes in integers, as the hardware ([`crate::rtl::emboss`]): the masks
//! on the stored codes, the rescale to the 0..255 scale by the integer `255 / max_code` (1 for
//! 8-bit unsigned texels) and one cast ([`Acc::to_code`]) into the output encoding. Where the
//! largest code does not divide 255 (a 5-, 6-, 7-, 10-bit texel, ...) the rescale `255 v /
//! max_code` is an exact rational rounded once by the output's mode
//! ([`crate::arith::rational_code`]; until 2026-12-07 an f64 formula that rounded twice and
//! missed the exact code on some words, `the_rescale_of_a_5_bit_texel_is_the_exact_rational`).

use crate::arith::Acc;
use crate::format::{Codec, Encoding, Format, Overflow, Quant};
use crate::gates::{CostTable, GateBudget};
use crate::sampler::{texel_axis, Filter, Sampler};
use crate::texture::{Shape, Texture};
use crate::unit::{Mode, PortSpec, TextureRead, Unit, Word};
use std::sync::Arc;

pub struct EmbossFilter {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    tex: Arc<Texture>,
    sampler: Sampler,
    nz: f64,
    /// `N_z`'s code in the output encoding: the contents of its register.
    nz_code: i64,
    /// `255 / max_code` of the texel format when it is an integer (the exact rescale of a
    /// mask sum of codes to the 0..255 scale), else `None` (the rational rescale, [`cast`]).
    code_scale: Option<i128>,
    ports: u32,
    mem_latency: u32,
}

/// The nine taps' offsets `(a, b)` (texel `(i + a, j + b)`) in reading order, row by row:
/// tap `k` is read by port `k % ports` in clock `k / ports` (with 3 ports, one row a clock).
pub const TAPS: [(i64, i64); 9] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (0, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// The offsets read by port `p` of `ports`, one per clock it reads in: `[a offsets (i axis), b
/// offsets (j axis)]` ([`TAPS`]).
pub fn port_offsets(ports: u32, p: u32) -> [Vec<i64>; 2] {
    let taps: Vec<(i64, i64)> = (p..9)
        .step_by(ports as usize)
        .map(|k| TAPS[k as usize])
        .collect();
    [
        taps.iter().map(|t| t.0).collect(),
        taps.iter().map(|t| t.1).collect(),
    ]
}

/// The port address muxes of `ports` read ports: per axis (0 = i, 1 = j) each distinct
/// sequence of offsets over the clocks ([`port_offsets`]) that takes more than one value, with
/// its number of distinct offsets (the mux's inputs). Ports with the same sequence share one
/// mux; a port whose offset is the same in every clock has none.
pub fn address_muxes(ports: u32) -> Vec<(usize, Vec<i64>, u32)> {
    let mut v: Vec<(usize, Vec<i64>, u32)> = Vec::new();
    for p in 0..ports.min(9) {
        for (a, seq) in port_offsets(ports, p).into_iter().enumerate() {
            let mut d = seq.clone();
            d.sort_unstable();
            d.dedup();
            if d.len() > 1 && !v.iter().any(|(b, s, _)| *b == a && *s == seq) {
                v.push((a, seq, d.len() as u32));
            }
        }
    }
    v
}

/// The integer factor `255 / max_code` of a texel format, if `max_code` divides 255 (unsigned
/// widths 1, 2, 4, 8; signed 2, 3, 5, 9).
pub fn code_scale(texel: &Format) -> Option<i128> {
    let m = texel.max_raw() as i128;
    (m > 0 && 255 % m == 0).then(|| 255 / m)
}

/// A mask sum `v` of texel codes (at `texel`'s code scale) on the 0..255 intensity scale,
/// cast into `out`: exactly `v k` (`k = 255 / max_code`, [`code_scale`]) with one
/// [`Acc::to_code`]; without an integer `k`, the exact rational `255 v / max_code` with one
/// rounding ([`crate::arith::rational_code`]).
pub fn cast(v: i64, texel: &Format, out: &Encoding) -> i64 {
    match code_scale(texel) {
        Some(k) => Acc::new(v as i128, 0).scale(k).to_code(out),
        None => crate::arith::rational_code(255 * v as i128, texel.max_raw() as i128, out),
    }
}

/// Gates of the rational rescale of one mask sum `s` in `[-span, span]` (`rtl::cast::
/// rational_code`): `255 s` times the codec's factor over `max_code`, one merged constant
/// multiply of `s` ([`CostTable::scaled_div`]), for the
/// rounding modes other than truncation and half-up the remainder (the floor times `max_code`
/// and a subtractor) with its compares against zero and a half and the increment, and the
/// saturation where the code can overflow.
fn rational_gates(t: &CostTable, span: i128, max_code: i128, out: &Encoding) -> GateBudget {
    let mut g = GateBudget::new();
    let bits = |r: i128| crate::rtl::verilog::signed_bits(-r, r);
    let n = out.format.width as u32;
    let (factor, den) = match out.codec {
        Codec::Fixed => (1i128 << out.format.frac, max_code),
        Codec::UnitSigned => (1i128 << (n - 1), max_code),
        Codec::UnitUnsigned => ((1i128 << n) - 1, max_code),
        Codec::UnitSymmetric => ((1i128 << n) - 1, 2 * max_code),
    };
    // `255 s`, the codec's factor and the reciprocal: one constant multiply of `s`
    let a = span * 255 * factor;
    let q = a.div_euclid(den) + 1;
    g.add(
        format!("divide by {den} {}", bits(a)),
        1,
        t.scaled_div(-span, span, 255 * factor, den),
    );
    if !matches!(out.quant, Quant::Trn | Quant::Rnd) {
        let rb = bits(2 * den);
        g.add(
            format!("remainder {rb}"),
            1,
            t.shift_add(bits(q), den as u128) + t.adder(rb),
        );
        g.add(
            format!("remainder compares {rb}"),
            1,
            2.0 * t.comparator(rb) + t.and2 * rb as f64,
        );
        g.add(
            format!("rounding increment {}", bits(q)),
            1,
            t.half_adder * bits(q) as f64,
        );
    }
    let fits = [-q, q].iter().all(|&v| out.format.contains(v as i64));
    if !fits && out.overflow != Overflow::Wrap {
        g.add(format!("cast saturation {n}"), 1, t.clamp(n));
    }
    g
}

impl EmbossFilter {
    /// `tex`: the height map, one lane of heights in [0, 1] (1 = white) stored in an unsigned
    /// intensity format (usually 8 bits, `UnitUnsigned`); level 0 is read.
    pub fn new(
        uv: Encoding,
        tex: Arc<Texture>,
        bevel_w: f64,
        ports: u32,
        mem_latency: u32,
        out: Encoding,
    ) -> Result<Self, String> {
        if tex.lanes() != 1 || tex.shape() != Shape::Flat {
            return Err(format!(
                "height map {}: expected a 2D texture of one lane",
                tex.name()
            ));
        }
        if !(bevel_w.is_finite() && bevel_w > 0.0) {
            return Err(format!(
                "bevel width w {bevel_w}: expected a finite number above 0"
            ));
        }
        if !(1..=9).contains(&ports) {
            return Err(format!("ports {ports}: expected 1 to 9"));
        }
        let l = tex.level_at(0);
        let (log_w, log_h) = l.logs();
        if (uv.format.frac as u32) < log_w.max(log_h) {
            return Err(format!(
                "texture coordinate format {} has too few fraction bits for a {}x{} map",
                uv.format,
                l.width(),
                l.height()
            ));
        }
        let nz = 6.0 * 255.0 / bevel_w;
        let code_scale = code_scale(&tex.texel().format);
        Ok(EmbossFilter {
            inputs: vec![PortSpec::new("uv", 2, uv)],
            outputs: vec![PortSpec::new("n", 3, out)],
            tex,
            sampler: Sampler::new(Filter::Nearest, 1)?,
            nz,
            nz_code: out.encode(nz),
            code_scale,
            ports,
            mem_latency: mem_latency.max(1),
        })
    }

    /// The height map (level 0 is read).
    pub fn texture(&self) -> &Arc<Texture> {
        &self.tex
    }
    /// The sampler: nearest, wrap on both axes ([`Sampler::index`]).
    pub fn sampler(&self) -> &Sampler {
        &self.sampler
    }
    /// Texels read per clock.
    pub fn ports(&self) -> u32 {
        self.ports
    }
    /// Clocks from a texel's address to its word.
    pub fn mem_latency(&self) -> u32 {
        self.mem_latency
    }
    /// `N_z`'s code in the output encoding (its register's contents).
    pub fn nz_code(&self) -> i64 {
        self.nz_code
    }
    /// `255 / max_code` of the texel format when it is an integer ([`code_scale`]).
    pub fn code_scale(&self) -> Option<i128> {
        self.code_scale
    }

    /// The bits of an output code of `-i_u` (or `-i_v`) that are distinct functions of the
    /// mask sum: neither constant nor a copy of another bit, over every sum of codes whose
    /// differences span `span` (the whole code where the sums are too many to list).
    fn code_bits(&self, span: i128) -> u32 {
        let out = self.outputs[0].enc;
        let wo = out.width();
        if span > 1 << 12 {
            return wo;
        }
        let texel = self.tex.texel().format;
        let codes: Vec<u64> = (-3 * span..=3 * span)
            .map(|v| out.format.bits(cast(v as i64, &texel, &out)))
            .collect();
        let mut columns: Vec<Vec<bool>> = (0..wo)
            .map(|b| codes.iter().map(|c| c >> b & 1 == 1).collect::<Vec<bool>>())
            .filter(|c| c.iter().any(|&x| x) && !c.iter().all(|&x| x))
            .collect();
        columns.sort();
        columns.dedup();
        columns.len() as u32
    }

    /// Mask responses over the 3x3 neighbourhood of texel (i, j) for a texel reader `t` of
    /// memory indices.
    fn masks<T: Copy + std::ops::Add<Output = T> + std::ops::Sub<Output = T>>(
        &self,
        i: i64,
        j: i64,
        t: impl Fn(usize) -> T,
    ) -> (T, T) {
        let l = self.tex.level_at(0);
        let g = |a: i64, b: i64| t(self.sampler.index(l, 0, i + a, j + b));
        let iu = (g(1, -1) - g(-1, -1)) + (g(1, 0) - g(-1, 0)) + (g(1, 1) - g(-1, 1));
        let iv = (g(-1, 1) - g(-1, -1)) + (g(0, 1) - g(0, -1)) + (g(1, 1) - g(1, -1));
        (iu, iv)
    }
}

impl Unit for EmbossFilter {
    fn kind(&self) -> &'static str {
        "emboss_filter"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        self.mem_latency + self.interval() + 1
    }
    fn interval(&self) -> u32 {
        9u32.div_ceil(self.ports)
    }
    fn textures(&self) -> Vec<TextureRead> {
        vec![TextureRead {
            texture: self.tex.clone(),
            taps: 9,
        }]
    }
    fn upload(&mut self, old: &Arc<Texture>, new: &Arc<Texture>) {
        if Arc::ptr_eq(&self.tex, old) {
            self.tex = new.clone();
        }
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        // the netlist of `rtl::emboss` (docs/units/emboss_filter.md, "Gates")
        let texel = self.tex.texel().format;
        let wt = texel.width as u32;
        let out = self.outputs[0].enc;
        let wo = out.width();
        let logs = {
            let (w, h) = self.tex.level_at(0).logs();
            [w, h]
        };
        let mut g = GateBudget::new();
        // addressing: the index's low bits, a neighbour incrementer and decrementer per axis
        for (name, log) in ["s", "t"].into_iter().zip(logs) {
            if log > 0 {
                g.add(
                    format!("{name} neighbour incrementer and decrementer {log}"),
                    2,
                    t.half_adder * log as f64,
                );
            }
        }
        for (a, seq, n) in address_muxes(self.ports) {
            if logs[a] > 0 {
                g.add(
                    format!(
                        "{} port address mux {n}:1 x{} (offsets {seq:?})",
                        ["s", "t"][a],
                        logs[a]
                    ),
                    1,
                    t.mux(logs[a], n),
                );
            }
        }
        // the eight taps of the masks (the centre is read but in neither)
        g.add(format!("tap register {wt}"), 8, t.register(wt));
        // per mask three differences of codes (a wt-bit subtractor whose borrow is the sign
        // for unsigned codes; sign-extended signed codes) and a three-input sum at its widths;
        // a wrapping cast keeps only the low bits of the sums, and so do the adders
        let span = (texel.max_raw() - texel.min_raw()) as i128;
        let k = self.code_scale.unwrap_or(1);
        let keep = match (out.overflow, out.codec) {
            (Overflow::Wrap, Codec::Fixed) => wo - out.format.frac as u32,
            (Overflow::Wrap, Codec::UnitSigned) => 1,
            _ => u32::MAX,
        };
        let bits = |r: i128| crate::rtl::verilog::signed_bits(-r, r).min(keep);
        let ws = (if texel.signed { wt + 1 } else { wt }).min(keep);
        g.add(format!("mask subtractor {ws}"), 6, t.adder(ws));
        g.add(
            format!("mask adder {}", bits(2 * span)),
            2,
            t.adder(bits(2 * span)),
        );
        g.add(
            format!("mask adder {}", bits(3 * span)),
            2,
            t.adder(bits(3 * span)),
        );
        if self.code_scale.is_none() {
            g.add_part(
                "",
                2,
                rational_gates(t, 3 * span, texel.max_raw() as i128, &out),
            );
        }
        // the cast: the rescale by 255 / max_code and a unit code's 2^n - 1, each as shifts
        // and adds; the rounding of a symmetric code; the saturation where the sums can exceed
        // the output (of the rational rescale: its own, above)
        let (lo, hi) = (-3 * span * k, 3 * span * k);
        let vb = bits(hi);
        if k > 1 {
            g.add(
                format!("rescale x{k} {}", bits(3 * span)),
                2,
                t.shift_add(bits(3 * span), k as u128),
            );
        }
        let dyadic = self.code_scale.is_some();
        if dyadic && matches!(out.codec, Codec::UnitUnsigned | Codec::UnitSymmetric) {
            let f = (1u128 << wo) - 1;
            g.add(format!("cast x{f} {vb}"), 2, t.shift_add(vb, f));
        }
        if dyadic && out.codec == Codec::UnitSymmetric {
            g.add(format!("cast rounding {wo}"), 2, t.half_adder * wo as f64);
        }
        let wrap = Encoding {
            overflow: Overflow::Wrap,
            ..out
        };
        let fits = [lo, hi]
            .iter()
            .all(|&v| Acc::new(v, 0).to_code(&out) == Acc::new(v, 0).to_code(&wrap));
        if dyadic && !fits && out.overflow != Overflow::Wrap {
            g.add(format!("cast saturation {wo}"), 2, t.clamp(wo));
        }
        g.add(
            format!("N_z register {wo} (host-loaded)"),
            1,
            t.register(wo),
        );
        // the output registers of -i_u and -i_v: one flip-flop per distinct function of the
        // sums among the code's bits (a constant bit, e.g. the zero bits below a fixed-point
        // code's integer, or a copy of another, e.g. the sign, is a wire)
        let wl = self.code_bits(span);
        g.add(
            format!("output register {wl} + {wl} + {wo}"),
            1,
            t.register(2 * wl + wo),
        );
        g.add("sequencer", 1, t.sequencer(self.latency()));
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.outputs[0].enc;
        let uv = &ins[0];
        match mode {
            Mode::Exact => {
                let l = self.tex.level_at(0);
                let i = (uv.lanes[0].x * l.width() as f64).floor() as i64;
                let j = (uv.lanes[1].x * l.height() as f64).floor() as i64;
                let (iu, iv) = self.masks(i, j, |k| l.value(k)[0] * 255.0);
                outs[0] = Word::from_exact(&out, &[-iu, -iv, self.nz]);
            }
            Mode::BitAccurate => {
                let frac = self.inputs[0].enc.format.frac as u32;
                let l = self.tex.level_at(0);
                let (log_w, log_h) = l.logs();
                let i = texel_axis(uv.lanes[0].raw, frac, log_w, false).0;
                let j = texel_axis(uv.lanes[1].raw, frac, log_h, false).0;
                // intensities as stored codes, exact integer mask sums, rescaled to the 0..255
                // scale of an 8-bit texel in the one cast
                let (iu, iv) = self.masks(i, j, |k| l.code(k)[0]);
                let texel = &self.tex.texel().format;
                let to = |v: i64| cast(v, texel, &out);
                outs[0] = Word::from_raw(&out, &[to(-iu), to(-iv), self.nz_code]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::{Codec, Overflow, Quant};
    use crate::texture::Texels;

    #[test]
    fn a_ramp_gives_six_a_and_the_bevel_constant() {
        // i = a u with a = 4 intensity levels per texel along u, constant along v
        let (w, h) = (16u32, 8u32);
        let heights: Vec<f64> = (0..h)
            .flat_map(|_| (0..w).map(|i| (40 + 4 * i) as f64 / 255.0))
            .collect();
        let uv = Encoding::fixed(Format::u(16, 16));
        let texel = Encoding::texel(Codec::UnitUnsigned, false, 8);
        let out = Encoding::fixed(Format::s(16, 4));
        let values = heights.iter().map(|&x| [x, 0.0, 0.0, 0.0]).collect();
        let tex = Texels {
            width: w,
            height: h,
            lanes: 1,
            values,
        };
        let tex = Arc::new(Texture::new("heights", texel, tex).unwrap());
        let u = EmbossFilter::new(uv, tex, 6.0, 3, 2, out).unwrap();
        assert_eq!(u.interval(), 3);
        let mut o = [Word::default()];
        for mode in [Mode::Exact, Mode::BitAccurate] {
            u.eval(mode, &[Word::quantize(&uv, &[0.5 + 0.01, 0.3])], &mut o);
            let x: [f64; 3] = o[0].xs();
            assert!((x[0] - -24.0).abs() < 1e-9, "{mode:?} {x:?}"); // -6a
            assert!(x[1].abs() < 1e-9);
            assert!((x[2] - 255.0).abs() < 1e-9); // 6*255/6
        }
    }

    const QUANTS: [Quant; 8] = Quant::ALL;
    const OVERFLOWS: [Overflow; 4] = Overflow::ALL;

    /// The bit-accurate cast before it was written in integers: the mask sum read as an s32.0
    /// word, times `255 / max_code` in f64, encoded into `out`.
    fn former(v: i64, texel: &Format, out: &Encoding) -> i64 {
        let scale = 255.0 / texel.max_raw() as f64;
        let enc = Encoding::fixed(Format::s(32, 0));
        out.encode(enc.decode(v) * scale)
    }

    /// Every output encoding of widths 1 to 10, 16, 24 and 32 (every fraction of a fixed
    /// format, every codec, quantization and overflow mode).
    fn outputs() -> Vec<Encoding> {
        let mut v = Vec::new();
        for w in (1u8..=10).chain([16, 24, 32]) {
            let mut formats = Vec::new();
            for signed in [false, true] {
                for f in 0..=w {
                    formats.push(Encoding::fixed(if signed {
                        Format::s(w, f)
                    } else {
                        Format::u(w, f)
                    }));
                }
            }
            formats.push(Encoding::texel(Codec::UnitUnsigned, false, w));
            if w >= 2 {
                formats.push(Encoding::texel(Codec::UnitSigned, true, w));
                formats.push(Encoding::texel(Codec::UnitSymmetric, true, w));
            }
            for e in formats {
                for q in QUANTS {
                    for o in OVERFLOWS {
                        v.push(Encoding {
                            quant: q,
                            overflow: o,
                            ..e
                        });
                    }
                }
            }
        }
        v
    }

    #[test]
    fn the_integer_cast_is_the_former_f64_formula_on_every_word() {
        // every texel format whose largest code divides 255, every mask sum of its codes
        let texels = [
            Format::u(1, 0),
            Format::u(2, 0),
            Format::u(4, 0),
            Format::u(8, 0),
            Format::u(8, 8),
            Format::s(2, 0),
            Format::s(3, 0),
            Format::s(5, 0),
            Format::s(9, 0),
        ];
        let outs = outputs();
        let mut words = 0u64;
        for t in &texels {
            let k = code_scale(t).expect("an integer rescale");
            assert_eq!(k * t.max_raw() as i128, 255);
            let span = t.max_raw() - t.min_raw();
            for out in &outs {
                for v in -3 * span..=3 * span {
                    assert_eq!(cast(v, t, out), former(v, t, out), "{t} {out:?} {v}");
                    words += 1;
                }
            }
        }
        assert!(words > 40_000_000, "{words}");
        // the other widths have no integer rescale and keep the formula
        for t in [
            Format::u(5, 0),
            Format::u(10, 0),
            Format::s(8, 0),
            Format::u(16, 0),
        ] {
            assert_eq!(code_scale(&t), None, "{t}");
            let out = Encoding::fixed(Format::s(16, 4));
            for v in [-3 * t.max_raw(), -7, 0, 1, 3 * t.max_raw()] {
                assert_eq!(cast(v, &t, &out), former(v, &t, &out));
            }
        }
    }

    #[test]
    fn the_rescale_of_a_5_bit_texel_is_the_exact_rational() {
        // 255 v / 31 truncated into s12.4: the former f64 formula (`out.encode(v * 255 / 31)`)
        // missed the exact floor on some words; the cast is the exact rational
        let t = Format::u(5, 0);
        let mut out = Encoding::fixed(Format::s(16, 4));
        out.quant = Quant::Trn;
        let mut f64_differs = 0;
        for v in -93i64..=93 {
            let exact = (255 * 16 * v as i128).div_euclid(31) as i64;
            assert_eq!(cast(v, &t, &out), exact, "{v}");
            f64_differs += usize::from(out.encode(v as f64 * (255.0 / 31.0)) != exact);
        }
        assert!(f64_differs > 0);
    }

    #[test]
    fn the_port_schedule_reads_every_tap_once_and_shares_its_muxes() {
        for ports in 1..=9u32 {
            let mut read: Vec<(i64, i64)> = (0..ports)
                .flat_map(|p| {
                    let [a, b] = port_offsets(ports, p);
                    a.into_iter().zip(b).collect::<Vec<_>>()
                })
                .collect();
            assert_eq!(read.len(), 9);
            read.sort_unstable();
            let mut all = TAPS.to_vec();
            all.sort_unstable();
            assert_eq!(read, all, "{ports} ports");
        }
        // a row a clock: the three ports share one j mux over the rows, the columns are fixed
        assert_eq!(address_muxes(3), vec![(1, vec![-1, 0, 1], 3)]);
        assert!(address_muxes(9).is_empty());
        // one port walks the whole neighbourhood: a 3:1 mux on each axis
        let one = address_muxes(1);
        assert_eq!(one.len(), 2);
        assert!(one.iter().all(|m| m.2 == 3));
    }

    /// A `w x h` map of pseudo-random codes of `texel`.
    fn random_map(w: u32, h: u32, texel: Encoding, seed: u64) -> Arc<Texture> {
        let mut x = seed;
        let f = texel.format;
        let values = (0..w * h)
            .map(|_| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let c = f.min_raw() + ((x >> 33) % (f.max_raw() - f.min_raw() + 1) as u64) as i64;
                [texel.decode(c), 0.0, 0.0, 0.0]
            })
            .collect();
        let t = Texels {
            width: w,
            height: h,
            lanes: 1,
            values,
        };
        Arc::new(Texture::new("heights", texel, t).unwrap())
    }

    #[test]
    fn bit_accurate_words_are_the_former_formula_at_every_texel() {
        // the former eval, written out: masks on the codes, the f64 cast, N_z encoded
        for (texel, out) in [
            (
                Encoding::texel(Codec::UnitUnsigned, false, 8),
                Encoding::fixed(Format::s(16, 4)),
            ),
            (
                Encoding::texel(Codec::UnitUnsigned, false, 4),
                Encoding::texel(Codec::UnitSigned, true, 10),
            ),
            (
                Encoding::fixed(Format::s(9, 0)),
                Encoding::texel(Codec::UnitSymmetric, true, 12),
            ),
            (
                Encoding::texel(Codec::UnitUnsigned, false, 6),
                Encoding::fixed(Format::s(12, 2)),
            ),
        ] {
            let (w, h) = (16u32, 8u32);
            let tex = random_map(w, h, texel, 7 + texel.width() as u64);
            let uv = Encoding::fixed(Format::s(12, 8));
            let u = EmbossFilter::new(uv, tex.clone(), 3.7, 3, 2, out).unwrap();
            let l = tex.level_at(0);
            let mut o = [Word::default()];
            for raw_u in (uv.format.min_raw()..=uv.format.max_raw()).step_by(7) {
                let raw_v = (raw_u * 13 + 5).rem_euclid(1 << 12) - (1 << 11);
                u.eval(
                    Mode::BitAccurate,
                    &[Word::from_raw(&uv, &[raw_u, raw_v])],
                    &mut o,
                );
                let i = texel_axis(raw_u, 8, 4, false).0;
                let j = texel_axis(raw_v, 8, 3, false).0;
                let g = |a: i64, b: i64| l.code(u.sampler.index(l, 0, i + a, j + b))[0];
                let iu: i64 = (-1..=1).map(|b| g(1, b) - g(-1, b)).sum();
                let iv: i64 = (-1..=1).map(|a| g(a, 1) - g(a, -1)).sum();
                let want = [
                    former(-iu, &texel.format, &out),
                    former(-iv, &texel.format, &out),
                    out.encode(6.0 * 255.0 / 3.7),
                ];
                let got: Vec<i64> = o[0].lanes[..3].iter().map(|s| s.raw).collect();
                assert_eq!(got, want, "{texel:?} {raw_u} {raw_v}");
            }
        }
    }
}

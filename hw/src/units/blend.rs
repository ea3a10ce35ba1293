//! Bump blend unit: the diffuse and specular blending units of Gouraud bump mapping.
//!
//! Ernst, Rüsseler, Schulz, Wittig 1998, §4.2 and Fig. 1: the blending unit "combines the
//! Gouraud color with the lighting result given by the bump map normal B, the light direction
//! L and the half-vector H":
//!
//! `C_new = C_src + sum_i (fd_i + fs_i) k_i L_i`, with `fd_i = B . L_i` and
//! `fs_i = (B . H_i)^n`,
//!
//! for the lights that react on the bump map. The paper's pipeline (§5.1) splits it into a
//! diffuse unit before the texture stage and a specular unit after it
//! (*DiffuseBlend - Texture - SpecularBlend*), so one configurable unit serves both:
//! [`BlendKind::Diffuse`] adds only `fd_i`, [`BlendKind::Specular`] only `fs_i`,
//! [`BlendKind::Both`] the whole sum (the Texture-then-blend ordering of the paper's Fig. 3).
//!
//! **Bump state.** Light directions and half vectors are either bump-state registers loaded
//! once per frame ([`VecSource::State`]: parallel light and parallel viewer, §4.1 "the
//! half-vector and the light direction can be stored in the bump state") or arrive on an input
//! port per fragment ([`VecSource::Port`]: "transferred to the rasterizer with the triangle
//! data", or interpolated as §6 suggests; the pipeline decides). The light colours are state
//! registers holding `k_i L_i`, premultiplied by the host: in the paper's sample implementation
//! `k_i` "has no effect" (1.0), and a constant spot / attenuation factor folds into the colour
//! register; a per-fragment `k_i` (spot cut-off) would need a port and a multiplier, which is
//! not modelled. The power table for the shininess is loaded "similar to a color LUT"
//! ([`SpecularGenerator`], `specgen.rs`).
//!
//! **Ports.** Inputs, in this order: `c` (3 lanes, the Gouraud colour `C_src`), `b` (3 lanes,
//! the bump normal), `l0..l{n-1}` (3 lanes each, only for `l_source == Port` and a kind with a
//! diffuse term), `h0..h{n-1}` (3 lanes each, only for `h_source == Port` and a kind with a
//! specular term), `enable` (1 lane, only for the [`Selective`] modes that read it). Output:
//! `c` (3 lanes). Input encodings are those of the wires (the constructor asks for each).
//!
//! **Selective blending.** "Both blending units can selectively be turned off to reduce the
//! artifacts described in section 5.4 according to the color information given in the
//! interpolated Gouraud color fragment C_src." The Gouraud-colour switch is the `enable` input
//! (the pipeline derives it from the Gouraud colour; 0 passes `C_src` through, any other word
//! blends). §5.4.2's remedy, "adding only the bump blending effect which has a perturbed
//! normal stored in the bump map and leaving the fragments that contain unperturbed normals
//! untouched", is [`Selective::Unperturbed`]: `C_src` passes through when every lane of `B` is
//! within one code of the unperturbed `[0, 0, 1]` as the `b` encoding stores it. Exact mode
//! applies the same test to the real values (within one step of the stored `[0, 0, 1]`).
//!
//! **Timing.** "n light sources are blended in n clock cycles, avoiding n times the hardware":
//! one datapath loops over the lights, accumulating, then adds `C_src`; interval =
//! `ceil(lights / parallel)`, latency = interval + 2 (the intensity register and the final
//! add / clamp). `parallel` datapaths trade gates for speed. Per frame the host loads the power
//! table (one entry per clock) and the bump-state registers, one register word per clock: 3
//! colour words per light, plus 3 per state light vector and 3 per state half vector.
//!
//! **Arithmetic.** Exact mode: f64, dot products clamped to [0, 1], `powf`, the colour clamped
//! to [0, 1] (OpenGL's colour clamp after each fragment stage). Bit-accurate mode: state
//! values quantized to their register encodings (`state` for vectors, `color` for `k_i L_i`);
//! products and sums exact in [`Acc`]; each dot product clamped to [0, 1] and cast into the
//! intensity register encoding `dot` (the hardware's intermediate register), which feeds both
//! the specular generator and the colour multiplier; the sum `C_src + acc` clamped to [0, 1]
//! and cast once into `out`.
//!
//! **Widths taken as the paper's** ([`BumpBlendParams::paper`]; the paper states no widths,
//! only that the budget depends on "the accuracy of all relevant input fields (B, H, n and
//! color) and the fidelity of the specular intensity generator"): B 8-bit signed components
//! (`UnitSigned` 8, a 3 x 8-bit normal texel), L and H 10-bit signed (`UnitSigned` 10),
//! colours 8 bits (`UnitUnsigned` 8 for `C_src`, the light colour registers and the output),
//! the intensity register 8 bits (`UnitUnsigned` 8, so it indexes the table directly), a 256 x
//! 8 power table (a colour LUT's size), two lights ("usually two to four"). A Diffuse unit
//! plus a Specular unit at these widths cost about 15,700 GE (6,267 + 9,398; tests), inside
//! the paper's "10,000 to 25,000 gate equivalents" (14,300 GE with one light, 18,100 with
//! four). The power table is the largest single item (3,072 GE), then the three B x L
//! multipliers of each dot product (1,470 GE) and the three colour multipliers (1,150 GE).

use crate::arith::{bit_length, Acc};
use crate::format::{Codec, Encoding, Format};
use crate::frame::FrameInputs;
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};
use crate::units::specgen::{SpecGen, SpecularGenerator};

/// Which terms a blend unit adds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum BlendKind {
    /// `C_src + sum_i fd_i k_i L_i`: the diffuse blend before the texture stage.
    Diffuse,
    /// `C_src + sum_i fs_i k_i L_i`: the specular blend after the texture stage.
    Specular,
    /// Both terms in one unit.
    Both,
}

impl BlendKind {
    pub fn diffuse(self) -> bool {
        matches!(self, BlendKind::Diffuse | BlendKind::Both)
    }
    pub fn specular(self) -> bool {
        matches!(self, BlendKind::Specular | BlendKind::Both)
    }
}

/// Where a light or half vector comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum VecSource {
    /// A bump-state register, loaded once per frame.
    #[default]
    State,
    /// An input port, per fragment (per triangle or interpolated: the pipeline decides).
    Port,
}

/// When the unit passes `C_src` through instead of blending.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Selective {
    /// Always blend.
    #[default]
    Off,
    /// Skip fragments whose bump normal is the unperturbed `[0, 0, 1]` (within one code of
    /// the `b` encoding): §5.4.2.
    Unperturbed,
    /// Skip fragments whose `enable` input is 0 (the Gouraud-colour switch of §4.2).
    Enable,
    /// Skip when either of the above says so.
    UnperturbedAndEnable,
}

impl Selective {
    fn unperturbed(self) -> bool {
        matches!(
            self,
            Selective::Unperturbed | Selective::UnperturbedAndEnable
        )
    }
    fn enable(self) -> bool {
        matches!(self, Selective::Enable | Selective::UnperturbedAndEnable)
    }
}

fn one() -> f64 {
    1.0
}

/// One light's bump state.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LightState {
    /// Light colour `L_i`, each channel in [0, 1].
    pub color: [f64; 3],
    /// Light direction in bump space (used when `l_source == State`).
    pub l: [f64; 3],
    /// Half vector in bump space (used when `h_source == State`).
    pub h: [f64; 3],
    /// Spot / attenuation factor `k_i` (>= 0; 1.0 = off, the paper's sample implementation),
    /// premultiplied into the colour register.
    #[serde(default = "one")]
    pub k: f64,
}

impl LightState {
    /// The bump state of the frame's lights for a unit of `kind`: each light's direction and
    /// half vector, and its colour weighted by the material term the unit adds (material 0's
    /// diffuse for `Diffuse`, its specular for `Specular`; `Both` adds both terms with one
    /// register, so it takes the plain light colour: kd = ks = 1, the paper's equation), as
    /// the host loads the registers each frame.
    pub fn from_frame(kind: BlendKind, f: &FrameInputs) -> Result<Vec<LightState>, String> {
        let m = f.material(0)?;
        let w = match kind {
            BlendKind::Diffuse => m.diffuse,
            BlendKind::Specular => m.specular,
            BlendKind::Both => [1.0; 3],
        };
        Ok(f.lights
            .iter()
            .map(|l| LightState {
                color: std::array::from_fn(|c| l.color[c] * w[c]),
                l: l.dir,
                h: l.half,
                k: 1.0,
            })
            .collect())
    }
}

/// Parameters of a bump blend unit. See the module documentation.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BumpBlendParams {
    pub kind: BlendKind,
    pub lights: Vec<LightState>,
    pub l_source: VecSource,
    pub h_source: VecSource,
    /// Specular intensity generator (unused by `Diffuse`).
    pub spec: SpecGen,
    pub shininess: f64,
    /// Bump-state register format of the L and H vectors.
    pub state: Encoding,
    /// Register format of the light colours `k_i L_i`.
    pub color: Encoding,
    /// The intensity register: each clamped dot product is cast into it.
    pub dot: Encoding,
    /// The blended colour.
    pub out: Encoding,
    pub selective: Selective,
    /// Datapaths (each blends one light per clock).
    pub parallel: u32,
}

impl BumpBlendParams {
    /// The widths taken as the paper's (module documentation), with state vectors, no
    /// selective blending, shininess 16 and one datapath.
    pub fn paper(kind: BlendKind, lights: Vec<LightState>) -> Self {
        BumpBlendParams {
            kind,
            lights,
            l_source: VecSource::State,
            h_source: VecSource::State,
            spec: SpecGen::Table {
                index_bits: 8,
                value_bits: 8,
            },
            shininess: 16.0,
            state: Encoding::texel(Codec::UnitSigned, true, 10),
            color: Encoding::texel(Codec::UnitUnsigned, false, 8),
            dot: Encoding::texel(Codec::UnitUnsigned, false, 8),
            out: Encoding::texel(Codec::UnitUnsigned, false, 8),
            selective: Selective::Off,
            parallel: 1,
        }
    }

    fn l_ports(&self) -> bool {
        self.kind.diffuse() && self.l_source == VecSource::Port
    }
    fn h_ports(&self) -> bool {
        self.kind.specular() && self.h_source == VecSource::Port
    }

    /// Names of the input ports the unit will have, in order, for wiring before it is built.
    pub fn input_names(&self) -> Vec<String> {
        let n = self.lights.len();
        let mut v = vec!["c".to_string(), "b".to_string()];
        if self.l_ports() {
            v.extend((0..n).map(|i| format!("l{i}")));
        }
        if self.h_ports() {
            v.extend((0..n).map(|i| format!("h{i}")));
        }
        if self.selective.enable() {
            v.push("enable".into());
        }
        v
    }
}

/// Encoding the pipeline would give the `enable` input: one unsigned bit.
pub const ENABLE_ENCODING: Encoding = Encoding::fixed(Format::u(1, 0));

/// Largest word width the unit accepts on any port or register (keeps every exact
/// intermediate inside `i128`).
const MAX_BITS: u32 = 24;

pub struct BumpBlend {
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    p: BumpBlendParams,
    gen: Option<SpecularGenerator>,
    parallel: u32,
    /// Port indices.
    il: Option<usize>,
    ih: Option<usize>,
    ie: Option<usize>,
    /// Quantized state registers (bit-accurate mode).
    lq: Vec<[Acc; 3]>,
    hq: Vec<[Acc; 3]>,
    kc: Vec<[Acc; 3]>,
    /// The shininess is the frame's material's ([`BumpBlend::following_material`]).
    follows_material: bool,
}

fn check_enc(what: &str, e: &Encoding) -> Result<(), String> {
    e.validate().map_err(|m| format!("{what}: {m}"))?;
    if e.width() > MAX_BITS {
        return Err(format!(
            "{what}: width {} is out of range: expected 1 to {MAX_BITS} bits",
            e.width()
        ));
    }
    Ok(())
}

fn dot3(a: &[Acc; 3], b: &[Acc; 3]) -> Acc {
    a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]))
}

/// Value step between neighbouring codes of an encoding (all codecs are linear).
fn step(e: &Encoding) -> f64 {
    e.decode(1) - e.decode(0)
}

impl BumpBlend {
    /// Build the unit. `wire(name)` gives the encoding of the signal wired to input `name`
    /// (see [`BumpBlendParams::input_names`]). Errors name the parameter and what was expected.
    pub fn new(
        params: BumpBlendParams,
        wire: impl Fn(&str) -> Option<Encoding>,
    ) -> Result<Self, String> {
        let p = params;
        let n = p.lights.len();
        if !(1..=8).contains(&n) {
            return Err(format!("lights: {n} lights, expected 1 to 8"));
        }
        for (what, e) in [
            ("state", &p.state),
            ("color", &p.color),
            ("dot", &p.dot),
            ("out", &p.out),
        ] {
            check_enc(what, e)?;
        }
        for (i, l) in p.lights.iter().enumerate() {
            if !l.color.iter().all(|c| (0.0..=1.0).contains(c)) {
                return Err(format!(
                    "lights[{i}].color {:?}: expected channels in [0, 1]",
                    l.color
                ));
            }
            if !(l.k.is_finite() && l.k >= 0.0) {
                return Err(format!("lights[{i}].k {}: expected a number >= 0", l.k));
            }
            if !l.l.iter().chain(&l.h).all(|v| v.is_finite()) {
                return Err(format!("lights[{i}]: vectors must be finite"));
            }
        }
        let gen = if p.kind.specular() {
            Some(SpecularGenerator::new(p.spec, p.shininess, p.dot)?)
        } else {
            None
        };
        let mut inputs = Vec::new();
        for name in p.input_names() {
            let e = wire(&name).ok_or_else(|| format!("input {name:?} is not wired"))?;
            check_enc(&format!("input {name:?}"), &e)?;
            let lanes = if name == "enable" { 1 } else { 3 };
            inputs.push(PortSpec::new(&name, lanes, e));
        }
        let idx = |name: &str| crate::unit::port_index(&inputs, name);
        let (il, ih, ie) = (idx("l0"), idx("h0"), idx("enable"));
        let q = |e: &Encoding, v: [f64; 3]| v.map(|x| Acc::from_code(e.encode(x), e));
        let lq = p.lights.iter().map(|l| q(&p.state, l.l)).collect();
        let hq = p.lights.iter().map(|l| q(&p.state, l.h)).collect();
        let kc = p
            .lights
            .iter()
            .map(|l| q(&p.color, l.color.map(|c| c * l.k)))
            .collect();
        Ok(BumpBlend {
            outputs: vec![PortSpec::new("c", 3, p.out)],
            inputs,
            parallel: p.parallel.clamp(1, n as u32),
            gen,
            il,
            ih,
            ie,
            lq,
            hq,
            kc,
            p,
            follows_material: false,
        })
    }

    pub fn params(&self) -> &BumpBlendParams {
        &self.p
    }

    /// A unit whose shininess is the frame's material's ([`Unit::begin_frame`]); otherwise
    /// the parameters' shininess is kept in every frame.
    pub fn following_material(mut self) -> Self {
        self.follows_material = true;
        self
    }

    /// The specular generator (kinds with a specular term).
    pub fn generator(&self) -> Option<&SpecularGenerator> {
        self.gen.as_ref()
    }

    fn n(&self) -> usize {
        self.p.lights.len()
    }

    /// Whether the fragment passes `C_src` through.
    fn skip(&self, mode: Mode, ins: &[Word]) -> bool {
        let sel = self.p.selective;
        if sel.enable() {
            let e = ins[self.ie.unwrap()].lanes[0];
            let on = match mode {
                Mode::Exact => e.x >= 0.5,
                Mode::BitAccurate => e.raw != 0,
            };
            if !on {
                return true;
            }
        }
        if sel.unperturbed() {
            let be = &self.inputs[1].enc;
            let b = &ins[1];
            let target = [0.0, 0.0, 1.0].map(|t| be.encode(t));
            let flat = (0..3).all(|j| match mode {
                Mode::Exact => (b.lanes[j].x - be.decode(target[j])).abs() <= step(be),
                Mode::BitAccurate => (b.lanes[j].raw - target[j]).abs() <= 1,
            });
            if flat {
                return true;
            }
        }
        false
    }

    fn eval_exact(&self, ins: &[Word]) -> [f64; 3] {
        let c: [f64; 3] = ins[0].xs();
        if self.skip(Mode::Exact, ins) {
            return c.map(|v| v.clamp(0.0, 1.0));
        }
        let b: [f64; 3] = ins[1].xs();
        let dot = |v: [f64; 3]| (0..3).map(|j| b[j] * v[j]).sum::<f64>().clamp(0.0, 1.0);
        let mut acc = [0.0; 3];
        for (i, light) in self.p.lights.iter().enumerate() {
            let mut f = 0.0;
            if self.p.kind.diffuse() {
                let l = self.il.map_or(light.l, |k| ins[k + i].xs());
                f += dot(l);
            }
            if let Some(g) = &self.gen {
                let h = self.ih.map_or(light.h, |k| ins[k + i].xs());
                f += g.exact(dot(h));
            }
            for (a, col) in acc.iter_mut().zip(light.color) {
                *a += f * light.k * col;
            }
        }
        std::array::from_fn(|ch| (c[ch] + acc[ch]).clamp(0.0, 1.0))
    }

    fn eval_bits(&self, ins: &[Word]) -> [i64; 3] {
        let ce = self.inputs[0].enc;
        let out = &self.p.out;
        let c = ins[0];
        let one = Acc::new(1, 0);
        let finish = |ch: usize, acc: Acc| {
            Acc::from_code(c.lanes[ch].raw, &ce)
                .add(acc)
                .clamp(Acc::ZERO, one)
                .to_code(out)
        };
        if self.skip(Mode::BitAccurate, ins) {
            return std::array::from_fn(|ch| {
                let raw = c.lanes[ch].raw;
                if ce == *out && (0.0..=1.0).contains(&ce.decode(raw)) {
                    raw // the same word, untouched
                } else {
                    finish(ch, Acc::ZERO)
                }
            });
        }
        let read = |w: &Word, e: &Encoding| -> [Acc; 3] {
            std::array::from_fn(|j| Acc::from_code(w.lanes[j].raw, e))
        };
        let b = read(&ins[1], &self.inputs[1].enc);
        let de = &self.p.dot;
        // the intensity register: clamp, cast into `dot`
        let intensity = |v: &[Acc; 3]| dot3(&b, v).clamp(Acc::ZERO, one).to_code(de);
        let mut acc = [Acc::ZERO; 3];
        for i in 0..self.n() {
            let mut f = Acc::ZERO;
            if self.p.kind.diffuse() {
                let d = match self.il {
                    Some(k) => intensity(&read(&ins[k + i], &self.inputs[k + i].enc)),
                    None => intensity(&self.lq[i]),
                };
                f = f.add(Acc::from_code(d, de));
            }
            if let Some(g) = &self.gen {
                let d = match self.ih {
                    Some(k) => intensity(&read(&ins[k + i], &self.inputs[k + i].enc)),
                    None => intensity(&self.hq[i]),
                };
                f = f.add(g.bits(d));
            }
            for (a, k) in acc.iter_mut().zip(self.kc[i]) {
                *a = a.add(f.mul(k));
            }
        }
        std::array::from_fn(|ch| finish(ch, acc[ch]))
    }
}

/// Whether words of `e` are read by bit replication (`c / (2^n - 1)` codecs): their exact
/// products and casts need the shift-and-add of `2^n + 1` or `2^n - 1` (gate estimate).
fn replicated(e: &Encoding) -> bool {
    matches!(e.codec, Codec::UnitUnsigned | Codec::UnitSymmetric)
}

impl Unit for BumpBlend {
    fn kind(&self) -> &'static str {
        "bump_blend"
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
    fn interval(&self) -> u32 {
        (self.n() as u32).div_ceil(self.parallel).max(1)
    }
    /// Reloads the bump-state and colour registers ([`LightState::from_frame`]) and, when the
    /// unit follows the material, the power generator's shininess.
    fn begin_frame(&mut self, f: &FrameInputs) -> Result<(), String> {
        f.expect_lights(self.n(), "the bump blend unit")?;
        let mut p = self.p.clone();
        p.lights = LightState::from_frame(p.kind, f)?;
        if self.follows_material {
            p.shininess = f.material(0)?.shininess;
        }
        let ins = &self.inputs;
        let wire = |n: &str| ins.iter().find(|p| p.name == n).map(|p| p.enc);
        let follows = self.follows_material;
        *self = BumpBlend::new(p, wire)?;
        self.follows_material = follows;
        Ok(())
    }
    fn frame_cycles(&self) -> u64 {
        let table = self.gen.as_ref().map_or(0, |g| g.load_cycles());
        let words_per_light = 3
            + 3 * (self.p.kind.diffuse() && self.il.is_none()) as u64
            + 3 * (self.p.kind.specular() && self.ih.is_none()) as u64;
        table + words_per_light * self.n() as u64
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let p = self.parallel;
        let n = self.n() as u32;
        let iv = self.interval();
        let wc_src = self.inputs[0].enc.width();
        let wb = self.inputs[1].enc.width();
        let ws = self.p.state.width();
        let wl = self.il.map_or(ws, |k| self.inputs[k].enc.width());
        let wh = self.ih.map_or(ws, |k| self.inputs[k].enc.width());
        let wd = self.p.dot.width();
        let dot_enc = self.p.dot;
        let wk = self.p.color.width();
        let wo = self.p.out.width();
        let mut g = GateBudget::new();
        // dot-product datapaths: 3 multipliers, a 3-input adder, clamp and rounding into the
        // intensity register
        let mut dot = |name: &str, wv: u32| {
            g.add(
                format!("{name} dot multiplier {wb}x{wv}"),
                3 * p,
                t.multiplier(wb, wv),
            );
            g.add(
                format!("{name} dot adder {}", wb + wv + 2),
                2 * p,
                t.adder(wb + wv + 2),
            );
            g.add(
                format!("{name} intensity clamp and rounding {wd}"),
                p,
                t.clamp(wd) + t.half_adder * wd as f64,
            );
            // the exact cast into a `c / (2^n - 1)` code multiplies by 2^n - 1: a subtractor
            // over the exact dot product
            if replicated(&dot_enc) {
                g.add(
                    format!("{name} intensity cast x(2^{wd}-1) {}", wb + wv + 2),
                    p,
                    t.adder(wb + wv + 2),
                );
            }
            g.add(format!("{name} intensity register {wd}"), p, t.register(wd));
        };
        if self.p.kind.diffuse() {
            dot("B.L", wl);
        }
        let mut wf = wd;
        if let Some(gen) = &self.gen {
            dot("B.H", wh);
            g.add_part("specular generator: ", p, gen.gates(t));
            wf = gen.out_bits();
            if self.p.kind.diffuse() {
                wf = wf.max(wd) + 1;
                g.add(format!("fd + fs adder {wf}"), p, t.adder(wf));
            }
        }
        // colour multiply-accumulate: intensity x (k_i L_i) per channel, exact sums
        let wa = wf + wk + bit_length((n - 1) as u128) + 1;
        g.add(
            format!("colour multiplier {wf}x{wk}"),
            3 * p,
            t.multiplier(wf, wk),
        );
        g.add(format!("accumulator adder {wa}"), 3 * p, t.adder(wa));
        g.add(format!("accumulator register {wa}"), 3, t.register(wa));
        // the products of two `c / (2^n - 1)` reads carry two bit replications, C_src one:
        // a shift and add per replication they differ by aligns them
        let f_reps = match &self.gen {
            Some(_) => 1, // the power table's words are UnitUnsigned
            None => replicated(&self.p.dot) as i32,
        };
        let extra = (f_reps + replicated(&self.p.color) as i32
            - replicated(&self.inputs[0].enc) as i32)
            .unsigned_abs();
        g.add(
            format!("C_src replication adder {wa}"),
            3 * extra,
            t.adder(wa),
        );
        g.add(format!("C_src adder {wa}"), 3, t.adder(wa));
        if replicated(&self.p.out) {
            g.add(format!("output cast x(2^{wo}-1) {wa}"), 3, t.adder(wa));
        }
        g.add(format!("output clamp {wo}"), 3, t.clamp(wo));
        g.add(format!("output register {}", 3 * wo), 1, t.register(3 * wo));
        // bump-state registers
        let per_light = 3 * wk
            + if self.p.kind.diffuse() && self.il.is_none() {
                3 * wl
            } else {
                0
            }
            + if self.p.kind.specular() && self.ih.is_none() {
                3 * wh
            } else {
                0
            };
        g.add(
            format!("bump-state registers {n}x{per_light}"),
            1,
            t.register(n * per_light),
        );
        // fragment inputs held while the lights are looped over
        let port_bits: u32 = self.inputs.iter().map(|s| s.bits()).sum();
        g.add(
            format!("input registers {port_bits}"),
            1,
            t.register(port_bits),
        );
        if iv > 1 {
            let port_vec = 3 * (self.il.map_or(0, |_| wl) + self.ih.map_or(0, |_| wh));
            g.add(
                format!("light select mux {iv}:1 x{}", per_light + port_vec),
                p,
                t.mux(per_light + port_vec, iv),
            );
            let cb = bit_length(iv as u128);
            g.add(
                format!("light counter {cb}"),
                1,
                t.register(cb) + t.half_adder * cb as f64,
            );
        }
        if self.p.selective != Selective::Off {
            if self.p.selective.unperturbed() {
                g.add(
                    format!("unperturbed normal detector 3x{wb}"),
                    3,
                    t.comparator(wb),
                );
            }
            g.add(
                format!("pass-through mux {}", 3 * wo.max(wc_src)),
                1,
                t.mux(3 * wo.max(wc_src), 2),
            );
        }
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = self.p.out;
        outs[0] = match mode {
            Mode::Exact => Word::from_exact(&out, &self.eval_exact(ins)),
            Mode::BitAccurate => Word::from_raw(&out, &self.eval_bits(ins)),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn unit_u(w: u8) -> Encoding {
        Encoding::texel(Codec::UnitUnsigned, false, w)
    }
    fn unit_s(w: u8) -> Encoding {
        Encoding::texel(Codec::UnitSigned, true, w)
    }
    fn light(color: [f64; 3], l: [f64; 3], h: [f64; 3], k: f64) -> LightState {
        LightState { color, l, h, k }
    }
    /// Wires: `c` and `enable` as given, `b` in `b`, every vector port in `v`.
    fn wires(c: Encoding, b: Encoding, v: Encoding) -> impl Fn(&str) -> Option<Encoding> {
        move |name: &str| match name {
            "c" => Some(c),
            "b" => Some(b),
            "enable" => Some(ENABLE_ENCODING),
            _ if name.starts_with('l') || name.starts_with('h') => Some(v),
            _ => None,
        }
    }
    fn paper_unit(kind: BlendKind, lights: Vec<LightState>) -> BumpBlend {
        let p = BumpBlendParams::paper(kind, lights);
        BumpBlend::new(p, wires(unit_u(8), unit_s(8), unit_s(10))).unwrap()
    }
    fn run(u: &mut BumpBlend, mode: Mode, ins: &[Word]) -> Word {
        let mut o = [Word::default()];
        u.eval(mode, ins, &mut o);
        o[0]
    }
    /// Input words for `u` from real values (quantized into the port encodings).
    fn words(u: &BumpBlend, vals: &[&[f64]]) -> Vec<Word> {
        u.inputs()
            .iter()
            .zip(vals)
            .map(|(p, v)| Word::quantize(&p.enc, v))
            .collect()
    }

    #[test]
    fn one_light_diffuse_hand_computed() {
        let v = Encoding::fixed(Format::s(10, 8));
        let c = Encoding::fixed(Format::u(9, 8));
        let mut p = BumpBlendParams::paper(
            BlendKind::Diffuse,
            vec![light([1.0, 0.5, 0.25], [0.5, 0.25, 0.5], [0.0; 3], 1.0)],
        );
        (p.state, p.color, p.dot, p.out) = (v, c, c, c);
        let mut u = BumpBlend::new(p, wires(c, v, v)).unwrap();
        assert_eq!(u.input_names(), ["c", "b"]);
        let ins = words(&u, &[&[0.125, 0.25, 0.0], &[0.5, 0.0, 0.75]]);
        // B.L = 0.25 + 0.375 = 0.625; C = C_src + 0.625 (1, 0.5, 0.25)
        let want = [0.75, 0.5625, 0.15625];
        assert_eq!(
            run(&mut u, Mode::BitAccurate, &ins).raws::<3>(),
            [192, 144, 40]
        );
        assert_eq!(run(&mut u, Mode::Exact, &ins).xs::<3>(), want);
        assert!(u.generator().is_none());
        // one light: one clock, the table is not loaded, 3 colour + 3 L words
        assert_eq!((u.interval(), u.latency(), u.frame_cycles()), (1, 3, 6));
    }

    impl BumpBlend {
        fn input_names(&self) -> Vec<String> {
            self.inputs.iter().map(|p| p.name.clone()).collect()
        }
    }

    #[test]
    fn two_lights_both_terms_hand_computed() {
        let v = Encoding::fixed(Format::s(10, 8));
        let c = Encoding::fixed(Format::u(9, 8));
        let lights = vec![
            // B.L = 0.625, B.H = 0.5 -> 0.0625: f = 0.6875
            light([1.0, 0.5, 0.25], [0.5, 0.25, 0.5], [1.0, 0.0, 0.0], 1.0),
            // B.L = -0.5 -> 0, B.H = 0.75 -> 0.31640625 = 81/256; k L = (0.25, 0.25, 0)
            light([0.5, 0.5, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], 0.5),
        ];
        let mut p = BumpBlendParams::paper(BlendKind::Both, lights);
        (p.state, p.color, p.dot) = (v, c, c);
        p.spec = SpecGen::Squaring { width: 8 };
        p.shininess = 4.0;
        p.out = Encoding::fixed(Format::u(12, 10));
        let mut u = BumpBlend::new(p.clone(), wires(c, v, v)).unwrap();
        let ins = words(&u, &[&[0.0, 0.0, 0.125], &[0.5, 0.0, 0.75]]);
        // r = 0.6875 + 81/256 * 0.25; g = 0.6875 * 0.5 + 81/1024; b = 0.125 + 0.6875 * 0.25
        let want = [0.7666015625, 0.4228515625, 0.296875];
        assert_eq!(
            run(&mut u, Mode::BitAccurate, &ins).raws::<3>(),
            [785, 433, 304]
        );
        assert_eq!(run(&mut u, Mode::Exact, &ins).xs::<3>(), want);
        // into 8-bit colour: 195.48, 107.83, 75.70
        p.out = unit_u(8);
        let mut u8 = BumpBlend::new(p, wires(c, v, v)).unwrap();
        assert_eq!(
            run(&mut u8, Mode::BitAccurate, &ins).raws::<3>(),
            [195, 108, 76]
        );
        // two lights on one datapath: two clocks; squaring loads nothing, 2 x 9 state words
        assert_eq!((u.interval(), u.latency(), u.frame_cycles()), (2, 4, 18));
    }

    #[test]
    fn vectors_on_ports_give_the_same_result_as_state() {
        let v = Encoding::fixed(Format::s(10, 8));
        let c = Encoding::fixed(Format::u(9, 8));
        let lights = vec![light(
            [1.0, 0.5, 0.25],
            [0.5, 0.25, 0.5],
            [1.0, 0.0, 0.0],
            1.0,
        )];
        let mut p = BumpBlendParams::paper(BlendKind::Both, lights);
        (p.state, p.color, p.dot) = (v, c, c);
        p.spec = SpecGen::Squaring { width: 8 };
        p.shininess = 4.0;
        let mut s = BumpBlend::new(p.clone(), wires(c, v, v)).unwrap();
        (p.l_source, p.h_source) = (VecSource::Port, VecSource::Port);
        assert_eq!(p.input_names(), ["c", "b", "l0", "h0"]);
        let mut q = BumpBlend::new(p, wires(c, v, v)).unwrap();
        let cb: [&[f64]; 2] = [&[0.0, 0.0, 0.125], &[0.5, 0.0, 0.75]];
        let ins_s = words(&s, &cb);
        let ins_q = words(&q, &[cb[0], cb[1], &[0.5, 0.25, 0.5], &[1.0, 0.0, 0.0]]);
        for mode in [Mode::Exact, Mode::BitAccurate] {
            assert_eq!(run(&mut s, mode, &ins_s), run(&mut q, mode, &ins_q));
        }
        // only the colour words are loaded per frame now
        assert_eq!(q.frame_cycles(), 3);
    }

    #[test]
    fn interval_is_lights_over_datapaths_and_latency_two_more() {
        let ls = vec![light([1.0; 3], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], 1.0); 3];
        for (parallel, interval) in [(1, 3), (2, 2), (3, 1), (9, 1)] {
            let mut p = BumpBlendParams::paper(BlendKind::Specular, ls.clone());
            p.parallel = parallel;
            let u = BumpBlend::new(p, wires(unit_u(8), unit_s(8), unit_s(10))).unwrap();
            assert_eq!((u.interval(), u.latency()), (interval, interval + 2));
            // the 256-entry table plus 3 colour and 3 H words per light
            assert_eq!(u.frame_cycles(), 256 + 3 * 6);
        }
        for n in 1..=4 {
            let u = paper_unit(BlendKind::Diffuse, ls[..1].repeat(n));
            assert_eq!(u.interval(), n as u32);
        }
    }

    #[test]
    fn selective_modes_pass_c_src_through() {
        let ls = vec![light([1.0; 3], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], 1.0)];
        let mut p = BumpBlendParams::paper(BlendKind::Both, ls);
        p.selective = Selective::UnperturbedAndEnable;
        let mut u = BumpBlend::new(p.clone(), wires(unit_u(8), unit_s(8), unit_s(10))).unwrap();
        assert_eq!(u.input_names(), ["c", "b", "enable"]);
        let (ce, be) = (unit_u(8), unit_s(8));
        let c = Word::from_raw(&ce, &[17, 99, 200]);
        let cases = [
            // (B codes, enable, passes)
            ([0, 0, 127], 1, true), // unperturbed [0, 0, 1] as UnitSigned 8 stores it
            ([1, -1, 126], 1, true), // within one code
            ([2, 0, 127], 1, false), // perturbed
            ([0, 0, 125], 1, false), // perturbed
            ([40, -30, 100], 0, true), // switched off by the Gouraud colour
            ([40, -30, 100], 1, false),
        ];
        for (b, en, passes) in cases {
            let ins = [
                c,
                Word::from_raw(&be, &b),
                Word::from_raw(&ENABLE_ENCODING, &[en]),
            ];
            let bits = run(&mut u, Mode::BitAccurate, &ins);
            let exact = run(&mut u, Mode::Exact, &ins);
            assert_eq!(bits.raws::<3>() == [17, 99, 200], passes, "{b:?} {en}");
            assert_eq!(exact.xs::<3>() == c.xs::<3>(), passes, "{b:?} {en}");
        }
        // Off blends everything; Enable alone ignores B
        p.selective = Selective::Enable;
        let mut e = BumpBlend::new(p.clone(), wires(ce, be, unit_s(10))).unwrap();
        let flat = Word::from_raw(&be, &[0, 0, 127]);
        let on = Word::from_raw(&ENABLE_ENCODING, &[1]);
        assert_ne!(
            run(&mut e, Mode::BitAccurate, &[c, flat, on]).raws::<3>(),
            [17, 99, 200]
        );
        p.selective = Selective::Off;
        let mut o = BumpBlend::new(p, wires(ce, be, unit_s(10))).unwrap();
        assert_eq!(o.inputs().len(), 2);
        assert_ne!(
            run(&mut o, Mode::BitAccurate, &[c, flat]).raws::<3>(),
            [17, 99, 200]
        );
    }

    #[test]
    fn k_scales_the_light() {
        let v = Encoding::fixed(Format::s(10, 8));
        let c = Encoding::fixed(Format::u(12, 10));
        let build = |k: f64| {
            let ls = vec![light([1.0, 0.5, 0.25], [0.5, 0.25, 0.5], [0.0; 3], k)];
            let mut p = BumpBlendParams::paper(BlendKind::Diffuse, ls);
            (p.state, p.color, p.dot, p.out) = (v, c, c, c);
            BumpBlend::new(p, wires(c, v, v)).unwrap()
        };
        let src = [0.125, 0.25, 0.0];
        for mode in [Mode::Exact, Mode::BitAccurate] {
            let mut out = Vec::new();
            for k in [0.0, 0.5, 1.0] {
                let mut u = build(k);
                let ins = words(&u, &[&src, &[0.5, 0.0, 0.75]]);
                out.push(run(&mut u, mode, &ins).xs::<3>());
            }
            for ch in 0..3 {
                // k = 0 leaves C_src; the contribution at k = 1/2 is half that at k = 1
                assert_eq!(out[0][ch], src[ch]);
                assert_eq!(out[1][ch] - src[ch], 0.5 * (out[2][ch] - src[ch]));
            }
            assert_eq!(out[2], [0.75, 0.5625, 0.15625]);
        }
    }

    fn read_err(e: &Encoding) -> f64 {
        match e.codec {
            Codec::Fixed | Codec::UnitSigned => 0.0,
            _ => (-2.0 * e.width() as f64).exp2(),
        }
    }
    fn q_err(e: &Encoding, x: f64) -> f64 {
        (e.decode(e.encode(x)) - x).abs() + read_err(e)
    }

    /// The bound on |bit-accurate - exact| per channel implied by the formats, for inputs
    /// `ins` (the same words in both modes):
    /// * a light or half vector from state differs by `e_v` per lane (its register rounding),
    ///   so the dot product by `sum_j |B_j| e_v` (+ the read error of B);
    /// * the intensity register adds its rounding `e_d` (+ read error);
    /// * `fs`: the generator's own bound at the intensity word, plus `n |dq - d|`;
    /// * colour: `f_err k L + (f + f_err) e_c`, summed over lights;
    /// * the final cast adds half an output step, the read of C_src its read error.
    fn bound(u: &BumpBlend, ins: &[Word]) -> [f64; 3] {
        let p = u.params();
        let b: [f64; 3] = ins[1].xs();
        let rb = read_err(&u.inputs()[1].enc);
        let ed = p.dot.max_error() + read_err(&p.dot);
        let mut acc = [0.0; 3];
        for (i, l) in p.lights.iter().enumerate() {
            let vec_err = |v: [f64; 3], port: Option<usize>| -> (f64, f64) {
                let (v, ev) = match port {
                    Some(k) => {
                        let x: [f64; 3] = ins[k + i].xs();
                        (x, read_err(&u.inputs()[k + i].enc))
                    }
                    None => (v, v.iter().map(|&x| q_err(&p.state, x)).fold(0.0, f64::max)),
                };
                let d: f64 = (0..3).map(|j| b[j] * v[j]).sum::<f64>().clamp(0.0, 1.0);
                let e: f64 = (0..3)
                    .map(|j| b[j].abs() * ev + (v[j].abs() + ev) * rb)
                    .sum();
                (d, e + ed)
            };
            let (mut f, mut fe) = (0.0, 0.0);
            if p.kind.diffuse() {
                let (d, e) = vec_err(l.l, u.il);
                f += d;
                fe += e;
            }
            if let Some(g) = u.generator() {
                let (d, e) = vec_err(l.h, u.ih);
                f += g.exact(d);
                fe += g.error_bound() + g.shininess().max(1.0) * e;
            }
            for (a, col) in acc.iter_mut().zip(l.color) {
                let kc = l.k * col;
                *a += fe * kc + (f + fe) * q_err(&p.color, kc);
            }
        }
        acc.map(|a| a + p.out.max_error() + read_err(&u.inputs()[0].enc) + 1e-12)
    }

    /// A small deterministic generator for sweeps.
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn unit_vec(&mut self, z_min: f64) -> [f64; 3] {
            loop {
                let v = [0, 1, 2].map(|_| 2.0 * self.next() - 1.0);
                let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                if n > 0.1 && v[2] / n >= z_min {
                    return v.map(|x| x / n);
                }
            }
        }
    }

    fn check_agreement(u: &mut BumpBlend, ins: &[Word]) -> Result<(), String> {
        let bits = run(u, Mode::BitAccurate, ins).xs::<3>();
        let exact = run(u, Mode::Exact, ins).xs::<3>();
        let bnd = bound(u, ins);
        for ch in 0..3 {
            let d = (bits[ch] - exact[ch]).abs();
            if d > bnd[ch] {
                return Err(format!("channel {ch}: {d} > {}", bnd[ch]));
            }
        }
        Ok(())
    }

    #[test]
    fn paper_widths_agree_with_exact_within_the_format_bound() {
        let mut r = Lcg(7);
        let mut worst = [0.0f64; 3];
        for kind in [BlendKind::Diffuse, BlendKind::Specular, BlendKind::Both] {
            for _ in 0..300 {
                let lights = (0..2)
                    .map(|_| {
                        let col = [r.next(), r.next(), r.next()];
                        let k = 0.5 + 0.5 * r.next();
                        light(col, r.unit_vec(-0.5), r.unit_vec(0.0), k)
                    })
                    .collect();
                let mut u = paper_unit(kind, lights);
                for _ in 0..10 {
                    let c = [r.next() * 0.5, r.next() * 0.5, r.next() * 0.5];
                    let ins = words(&u, &[&c, &r.unit_vec(0.3)]);
                    check_agreement(&mut u, &ins).unwrap();
                    let bits = run(&mut u, Mode::BitAccurate, &ins).xs::<3>();
                    let exact = run(&mut u, Mode::Exact, &ins).xs::<3>();
                    let w = &mut worst[kind as usize];
                    *w = (0..3)
                        .map(|ch| (bits[ch] - exact[ch]).abs())
                        .fold(*w, f64::max);
                }
            }
        }
        // measured: the diffuse blend within a few 8-bit steps, specular (n = 16) more
        println!("worst |bits - exact| (Diffuse, Specular, Both): {worst:?}");
        assert!(worst[0] < 4.0 / 255.0, "{worst:?}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(192))]
        #[test]
        fn wide_widths_agree_with_exact_within_the_format_bound(
            wb in 8u32..=24, wv in 8u32..=24, wk in 8u32..=24, wd in 8u32..=20,
            kind in 0usize..3, gen in 0usize..3, k_exp in 1u32..=5,
            ports in any::<(bool, bool)>(), seed in any::<u64>(),
        ) {
            let kind = [BlendKind::Diffuse, BlendKind::Specular, BlendKind::Both][kind];
            let mut r = Lcg(seed);
            let lights = (0..2)
                .map(|_| {
                    let col = [r.next(), r.next(), r.next()];
                    light(col, r.unit_vec(-0.5), r.unit_vec(0.0), 1.0)
                })
                .collect();
            let mut p = BumpBlendParams::paper(kind, lights);
            p.state = unit_s(wv as u8);
            p.color = unit_u(wk as u8);
            p.out = unit_u(wk as u8);
            p.dot = unit_u(wd as u8);
            p.shininess = (1u32 << k_exp) as f64;
            p.spec = match gen {
                0 => SpecGen::Table {
                    index_bits: wd.min(12),
                    value_bits: 12,
                },
                1 => SpecGen::TableLerp {
                    index_bits: 6,
                    value_bits: 12,
                    frac_bits: 8,
                },
                _ => SpecGen::Squaring { width: wd + 2 },
            };
            if ports.0 {
                p.l_source = VecSource::Port;
            }
            if ports.1 {
                p.h_source = VecSource::Port;
            }
            let w = wires(unit_u(wk as u8), unit_s(wb as u8), unit_s(wv as u8));
            let mut u = BumpBlend::new(p, w).unwrap();
            let names = u.input_names();
            for _ in 0..8 {
                let vals: Vec<Vec<f64>> = names
                    .iter()
                    .map(|n| match n.as_str() {
                        "c" => vec![r.next() * 0.5, r.next() * 0.5, r.next() * 0.5],
                        "b" => r.unit_vec(0.3).to_vec(),
                        _ => r.unit_vec(-0.3).to_vec(),
                    })
                    .collect();
                let refs: Vec<&[f64]> = vals.iter().map(|v| v.as_slice()).collect();
                let ins = words(&u, &refs);
                let res = check_agreement(&mut u, &ins);
                prop_assert!(res.is_ok(), "{:?}", res);
            }
        }
    }

    fn two_lights() -> Vec<LightState> {
        vec![light([1.0; 3], [0.0, 0.6, 0.8], [0.0, 0.0, 1.0], 1.0); 2]
    }

    /// Diffuse + Specular pair (the paper's split pipeline) with B, L/H, colour widths and
    /// the power table's index bits.
    fn pair_ge(wb: u8, wv: u8, wc: u8, index_bits: u32) -> (f64, f64) {
        let t = CostTable::default();
        let ge = |kind| {
            let mut p = BumpBlendParams::paper(kind, two_lights());
            p.state = unit_s(wv);
            p.color = unit_u(wc);
            p.out = unit_u(wc);
            p.spec = SpecGen::Table {
                index_bits,
                value_bits: 8,
            };
            let u = BumpBlend::new(p, wires(unit_u(wc), unit_s(wb), unit_s(wv))).unwrap();
            u.gates(&t).total()
        };
        (ge(BlendKind::Diffuse), ge(BlendKind::Specular))
    }

    #[test]
    fn paper_widths_cost_10k_to_25k_gates_for_diffuse_plus_specular() {
        let t = CostTable::default();
        for kind in [BlendKind::Diffuse, BlendKind::Specular] {
            let u = paper_unit(kind, two_lights());
            let g = u.gates(&t);
            println!("{kind:?}: {:.0} GE", g.total());
            for i in &g.items {
                println!("  {:>8.1}  {}", i.ge, i.what);
            }
        }
        let (d, s) = pair_ge(8, 10, 8, 8);
        println!("Diffuse {d:.0} + Specular {s:.0} = {:.0} GE", d + s);
        assert!((10_000.0..=25_000.0).contains(&(d + s)), "{}", d + s);
        // and still inside for one to four lights
        for n in [1, 4] {
            let ls = two_lights()[..1].repeat(n);
            let total: f64 = [BlendKind::Diffuse, BlendKind::Specular]
                .map(|k| paper_unit(k, ls.clone()).gates(&t).total())
                .iter()
                .sum();
            println!("{n} lights: {total:.0} GE");
            assert!((10_000.0..=25_000.0).contains(&total), "{n}: {total}");
        }
    }

    #[test]
    fn gates_grow_with_every_width_and_the_table() {
        let total = |wb, wv, wc, tb| {
            let (d, s) = pair_ge(wb, wv, wc, tb);
            d + s
        };
        let series = [
            ("B width", [6u8, 8, 10, 12].map(|w| total(w, 10, 8, 8))),
            ("L/H width", [8u8, 10, 12, 16].map(|w| total(8, w, 8, 8))),
            ("colour width", [6u8, 8, 10, 12].map(|w| total(8, 10, w, 8))),
            (
                "table index bits",
                [6u32, 7, 8, 9].map(|b| total(8, 10, 8, b)),
            ),
        ];
        for (name, s) in series {
            println!("{name}: {s:.0?}");
            assert!(s.windows(2).all(|w| w[0] < w[1]), "{name}: {s:?}");
        }
        // parallel datapaths cost gates and save clocks
        let ls = two_lights();
        let mut p = BumpBlendParams::paper(BlendKind::Both, ls);
        let one = BumpBlend::new(p.clone(), wires(unit_u(8), unit_s(8), unit_s(10))).unwrap();
        p.parallel = 2;
        let two = BumpBlend::new(p, wires(unit_u(8), unit_s(8), unit_s(10))).unwrap();
        let t = CostTable::default();
        assert!(two.gates(&t).total() > one.gates(&t).total());
        assert_eq!((one.interval(), two.interval()), (2, 1));
    }

    #[test]
    fn bad_parameters_are_rejected() {
        let w = || wires(unit_u(8), unit_s(8), unit_s(10));
        let err = |p: BumpBlendParams| BumpBlend::new(p, w()).err().unwrap();
        let ls = two_lights();
        assert!(err(BumpBlendParams::paper(BlendKind::Both, vec![])).contains("lights"));
        let mut p = BumpBlendParams::paper(BlendKind::Specular, ls.clone());
        p.spec = SpecGen::Squaring { width: 8 };
        p.shininess = 10.0;
        assert!(err(p).contains("power of two"));
        let mut p = BumpBlendParams::paper(BlendKind::Diffuse, ls.clone());
        p.spec = SpecGen::Squaring { width: 8 };
        p.shininess = 10.0; // no specular term: the generator is not built
        assert!(BumpBlend::new(p, w()).is_ok());
        let mut p = BumpBlendParams::paper(BlendKind::Diffuse, ls.clone());
        p.lights[1].color[0] = 1.5;
        assert!(err(p).contains("lights[1].color"));
        let mut p = BumpBlendParams::paper(BlendKind::Diffuse, ls.clone());
        p.lights[0].k = -1.0;
        assert!(err(p).contains("lights[0].k"));
        let mut p = BumpBlendParams::paper(BlendKind::Diffuse, ls.clone());
        p.dot = Encoding::fixed(Format::u(32, 30));
        assert!(err(p).contains("dot: width 32"));
        let mut p = BumpBlendParams::paper(BlendKind::Diffuse, ls);
        p.l_source = VecSource::Port;
        let e = BumpBlend::new(p, |n: &str| (n != "l1").then(|| unit_s(8)))
            .err()
            .unwrap();
        assert_eq!(e, "input \"l1\" is not wired");
    }
}

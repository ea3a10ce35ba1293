//! NV20 / NV2A register combiners (NV_register_combiners, section 2.14 "Register Combiners
//! Application"; NV2A registers `NV097_SET_COMBINER_*`): up to 8 general combiner stages and
//! the final combiner, per fragment.
//!
//! Each general stage (spec 2.14.2-2.14.5) has an RGB and an alpha portion. A portion picks
//! four variables A, B, C, D from the register file (ZERO, CONSTANT_COLOR0/1 of the stage,
//! FOG, PRIMARY_COLOR, SECONDARY_COLOR, TEXTURE0-3, SPARE0, SPARE1), each with a component
//! usage (RGB / ALPHA in the RGB portion, ALPHA / BLUE in the alpha portion) and one of the
//! eight input mappings (table NV_register_combiners.2). It computes `AB = A*B` (or the dot
//! product `A.B`, broadcast to R, G and B), `CD = C*D` (or `C.D`) and `AB + CD` (or the mux:
//! `CD` when spare0 alpha passes the mux test, else `AB`), applies the output scale and bias
//! (table .4) with the clamp to [-1, 1] to each, and writes them to up to three registers.
//! Every stage reads the register file as it was before the stage (writes take effect after
//! it, the `Independence` frame shows this). NV2A's blue-to-alpha flags copy the blue of the
//! RGB AB / CD output into the alpha of its destination.
//!
//! The final combiner (spec 2.14.6) computes `RGB = min(A*B + (1-A)*C + D, 1)` and
//! `alpha = G` with UNSIGNED_IDENTITY or UNSIGNED_INVERT inputs, where A to D may also read
//! `E*F` and `spare0 + secondary` (each summand clamped to [0, 1], optionally inverted, and
//! the sum clamped to 1 only with the clamp flag: the `Flags` frame's "Uncapped" quad is
//! 0.5 * (1 + 1) = 254/255).
//!
//! **Number format.** The spec leaves the precision out. The bit-accurate datapath holds
//! every register as a signed `width`-bit word `r` read as `r / S`, `S = 255 * 2^(width-9)`:
//! at the default 9 bits 1.0 is 255 and -1.0 is -255 (the GeForce 256 format), and an 8-bit
//! colour code `k` is the word `k` exactly. One half is `ceil(S/2)` (128/255 at 9 bits).
//! Products and dot products are exact, then rounded once to the nearest word (halves up);
//! the shift right rounds halves up; every output is clamped to [-S, S]. The final RGBA is
//! rounded to 8-bit codes (at 9 bits it already is one). Which of these the NV2A frames settle
//! and which they leave open is in `docs/units/register-combiners.md`.
//!
//! **Exact mode** runs the same program in f64: 1/2 is 0.5, nothing is rounded. The constants
//! are 8-bit codes in both modes (the registers hold codes: that is an input, not a rounding
//! of the datapath). [`Combiner::mode_error_bound`] propagates a bound on
//! |bit-accurate - exact| through the program.
//!
//! Ports: `primary`, `secondary`, `fog`, `tex0`..`tex3` in (4 lanes each, any encoding; read
//! into the register format rounded to nearest and clamped to [-1, 1]); `rgba` out (4 lanes,
//! 8-bit unsigned). Latency: one clock per general stage of the part plus two for the final
//! combiner; interval 1 (every stage is its own pipeline stage).

mod datapath;
mod program;
#[cfg(test)]
mod tests;

pub use program::{
    FinalCombiner, FinalInput, GeneralStage, Input, Mapping, MuxSelect, OutputOp, Portion, Program,
    Source, Usage,
};

use crate::format::{Codec, Encoding};
use crate::gates::{CostTable, GateBudget};
use crate::unit::{Mode, PortSpec, Unit, Word};
use datapath::{run, BoundPath, ExactPath, FixedPath, Path};

/// The default register width: 9-bit signed, 255 = 1.0 (see the module documentation).
pub const DEFAULT_WIDTH: u32 = 9;
/// The widest register the model takes.
pub const MAX_WIDTH: u32 = 24;
/// General combiner stages of the NV2A (and of the GeForce3).
pub const NV2A_STAGES: usize = 8;
/// Largest number of general stages a part may have.
pub const MAX_STAGES: usize = 16;

/// The input ports, in order.
pub const INPUT_PORTS: [&str; 7] = [
    "primary",
    "secondary",
    "fog",
    "tex0",
    "tex1",
    "tex2",
    "tex3",
];

/// The part: register width, number of general stages, and the encodings of the inputs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CombinerParams {
    /// Register width in bits, 9 to 24.
    pub width: u32,
    /// General combiner stages the part has (1 to 16; the NV2A has 8).
    pub stages: usize,
    /// Encodings of the input ports, in the order of [`INPUT_PORTS`].
    pub inputs: [Encoding; 7],
}

impl Default for CombinerParams {
    fn default() -> Self {
        CombinerParams {
            width: DEFAULT_WIDTH,
            stages: NV2A_STAGES,
            inputs: [Encoding::texel(Codec::UnitUnsigned, false, 8); 7],
        }
    }
}

/// The register-combiner unit. See the module documentation.
pub struct Combiner {
    params: CombinerParams,
    program: Program,
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
    /// For each of [`INPUT_PORTS`], its index among the unit's inputs (`None`: not a port of
    /// this unit; the register reads 0).
    port_of: [Option<usize>; 7],
}

impl Combiner {
    /// A combiner part running `program`. Every field is checked; the error names it and
    /// says what was expected.
    pub fn new(params: CombinerParams, program: Program) -> Result<Combiner, String> {
        if !(DEFAULT_WIDTH..=MAX_WIDTH).contains(&params.width) {
            return Err(format!(
                "width: {} given: expected {DEFAULT_WIDTH} to {MAX_WIDTH} bits (1.0 is \
                 255 * 2^(width - 9), so 8-bit colours need at least 9)",
                params.width
            ));
        }
        if !(1..=MAX_STAGES).contains(&params.stages) {
            return Err(format!(
                "stages: {} given: expected 1 to {MAX_STAGES} general combiners in the part",
                params.stages
            ));
        }
        for (name, e) in INPUT_PORTS.iter().zip(&params.inputs) {
            e.validate().map_err(|m| format!("inputs.{name}: {m}"))?;
        }
        program.validate(params.stages)?;
        let inputs = INPUT_PORTS
            .iter()
            .zip(&params.inputs)
            .map(|(n, e)| PortSpec::new(n, 4, *e))
            .collect();
        let outputs = vec![PortSpec::new("rgba", 4, Self::output_encoding())];
        Ok(Combiner {
            params,
            program,
            inputs,
            outputs,
            port_of: std::array::from_fn(Some),
        })
    }

    /// Keep only the input ports `ports` (name and lanes, 1 to 4, in any order), as an engine
    /// wires them: a register without a port reads 0, and the lanes a port lacks read 0 (a
    /// 3-lane vector in `primary` gives primary alpha 0). Errors name the port.
    pub fn with_ports(mut self, ports: &[(&str, u8)]) -> Result<Combiner, String> {
        let mut inputs = Vec::new();
        let mut port_of = [None; 7];
        for &(name, lanes) in ports {
            let k = INPUT_PORTS.iter().position(|p| *p == name).ok_or_else(|| {
                format!("input {name:?}: expected one of {}", INPUT_PORTS.join(", "))
            })?;
            if !(1..=4).contains(&lanes) {
                return Err(format!("input {name}: {lanes} lanes: expected 1 to 4"));
            }
            if port_of[k].is_some() {
                return Err(format!("input {name}: given twice"));
            }
            port_of[k] = Some(inputs.len());
            inputs.push(PortSpec::new(name, lanes, self.params.inputs[k]));
        }
        self.inputs = inputs;
        self.port_of = port_of;
        Ok(self)
    }

    /// The encoding of the `rgba` output: 8-bit unsigned, 255 = 1.0.
    pub fn output_encoding() -> Encoding {
        Encoding::texel(Codec::UnitUnsigned, false, 8)
    }

    pub fn params(&self) -> &CombinerParams {
        &self.params
    }

    pub fn program(&self) -> &Program {
        &self.program
    }

    /// A bound on |bit-accurate - exact| of each output component (R, G, B, A) as a real
    /// number, for any inputs, propagated through the program: each product or dot product
    /// adds half a register LSB to the operands' propagated errors, the half-bias mappings
    /// and the output bias add |ceil(S/2)/S - 1/2| (0.5/255 at 9 bits), scales multiply, the
    /// shift right adds half an LSB; a mux whose spare0 alpha is not exact in both modes may
    /// choose differently, and then the bound covers both choices. 8-bit unsigned inputs are
    /// read exactly; other encodings add half an LSB.
    pub fn mode_error_bound(&self) -> [f64; 4] {
        let p = BoundPath::new(self.params.width);
        let ins = self.register_inputs(&p, None);
        let r = run(&p, &self.program, &ins);
        let out_round = if self.params.width > DEFAULT_WIDTH {
            0.5 / 255.0
        } else {
            0.0
        };
        r.map(|v| v.err.min(1.0) + out_round)
    }

    /// The final combiner's datapath as `rtl::combiner` builds it (two pipeline stages):
    /// the `spare0 + secondary` sum, the variables A to G (register selects, the usage
    /// select, `max(0, x)` and the invert), `E * F`, the stage registers, then per colour lane
    /// `A B + (1 - A) C` read back by `/ S`, `+ D`, and the clamps and codes. Widths are the
    /// exact ranges the Verilog's wires have: a mapped variable is in `[0, S]`, `w - 1` bits.
    fn final_gates(&self, t: &CostTable, g: &mut GateBudget) {
        let w = self.params.width;
        let f = w - DEFAULT_WIDTH;
        let s = 255i128 << f;
        let v = w - 1; // [0, S]; A to D are in [0, 2 S] (spare0 + secondary unclamped), w bits
        let bits = |x: i128| crate::arith::bit_length(x.unsigned_abs());
        // the registers that are not a constant 0 after the general stages: the final
        // combiner's two constants, the 8 the stages write, FOG if it has a port
        let regs = 2 + 8 + u32::from(self.port_of[2].is_some());
        g.add(
            format!("final register reads x{w} of {regs} (E, F: 3 lanes + alpha; G: blue, alpha; A-D: alpha)"),
            14,
            t.mux(w, regs + 1),
        );
        g.add(
            format!(
                "final register reads x{} of {} (A-D x 3 lanes: + spare0 + secondary, E F)",
                w + 1,
                regs + 2
            ),
            12,
            t.mux(w + 1, regs + 3),
        );
        g.add(
            format!(
                "final register codes decoded (A-G, {} lines each)",
                regs + 2
            ),
            7,
            t.decoder(regs + 2, 4),
        );
        g.add(
            format!("final usage select 2:1 x{w} (A-F x 3 lanes, G)"),
            19,
            t.mux(w, 2),
        );
        // S - x on [0, S] with the invert flag: the bits' complement (an XOR with the flag)
        // when S = 2^v - 1, else a subtractor and a select
        let invert = if f == 0 {
            t.xor2 * f64::from(v)
        } else {
            t.adder(v) + t.mux(v, 2)
        };
        g.add(
            format!("final max(0, x) and invert {v} bits (spare0, secondary, E, F x 3 lanes, G)"),
            13,
            t.and2 * f64::from(v) + invert,
        );
        g.add(
            format!("final max(0, x), clamp to S and invert {w} bits (A-D x 3 lanes)"),
            12,
            t.and2 * f64::from(w) + t.clamp(v) + invert,
        );
        g.add(
            format!("spare0 + secondary: adder {w}, clamp to S, select"),
            3,
            t.adder(w) + t.clamp(v) + t.mux(w, 2),
        );
        g.add(format!("E*F multiplier {v}x{v}"), 3, t.multiplier(v, v));
        g.add("E*F / S (reciprocal multiply)", 3, t.div_round(0, s * s, s));
        g.add(
            format!(
                "final stage registers: A-D x 3 lanes x {w} bits, G {v} bits, loaded every edge"
            ),
            1,
            t.dff * f64::from(12 * w + v),
        );
        if f > 0 {
            g.add(format!("1 - A subtractor {w}"), 3, t.adder(w));
        }
        g.add(format!("A*B multiplier {w}x{w}"), 3, t.multiplier(w, w));
        g.add(
            format!("(1-A)*C multiplier {v}x{w} and the sign row {w}"),
            3,
            t.multiplier(v, w) + t.adder(w),
        );
        let (lo, hi) = (-2 * s * s, 6 * s * s);
        g.add(
            format!("A B + (1 - A) C adder {}", bits(hi) + 1),
            3,
            t.adder(bits(hi) + 1),
        );
        g.add(
            "A B + (1 - A) C / S (reciprocal multiply)",
            3,
            t.div_round(lo, hi, s),
        );
        g.add(
            format!("+ D adder {}", bits(8 * s) + 1),
            3,
            t.adder(bits(8 * s) + 1),
        );
        g.add(
            format!("colour clamp to [0, S], {v} bits"),
            3,
            t.clamp(v) + t.and2 * f64::from(v),
        );
        if f > 0 {
            g.add(format!("rounding to 8 bits (adder {v})"), 4, t.adder(v));
        }
    }

    /// The port words as register values, in register order (fog, primary, secondary,
    /// tex0..3).
    fn register_inputs<P: Path>(&self, p: &P, ins: Option<&[Word]>) -> [[P::V; 4]; 7] {
        // register order -> port index
        const PORT_OF: [usize; 7] = [2, 0, 1, 3, 4, 5, 6];
        std::array::from_fn(|k| {
            let port = PORT_OF[k];
            let enc = &self.params.inputs[port];
            let lanes = self.port_of[port].map_or(0, |i| self.inputs[i].lanes as usize);
            let w = match (ins, self.port_of[port]) {
                (Some(w), Some(i)) => w[i],
                _ => Word::default(),
            };
            // a lane the port lacks reads 0 (not the reading of code 0: 1/255 in UnitSymmetric)
            std::array::from_fn(|l| {
                if l < lanes {
                    p.port(&w.lanes[l], enc)
                } else {
                    p.zero()
                }
            })
        })
    }
}

impl Unit for Combiner {
    fn kind(&self) -> &'static str {
        "register_combiners"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        self.params.stages as u32 + 2
    }
    fn interval(&self) -> u32 {
        1
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        let w = self.params.width;
        let n = self.params.stages as u32;
        let mut g = GateBudget::new();
        // one general stage, RGB (3 lanes) and alpha (1 lane) portions; x n stages
        let vars = 4 * (3 + 1); // variable lanes per stage
                                // the register reads: per stage RGB 4 variables x (3 lanes + the alpha pick), alpha
                                // 4 x (blue + alpha); a register that reads a constant 0 (ZERO; FOG and the ports
                                // without a port; SPARE0 and SPARE1 before the first stage writes them) is no input
        let ports = |ks: &[usize]| ks.iter().filter(|&&k| self.port_of[k].is_some()).count() as u32;
        let fog = ports(&[2]);
        let first = 2 + fog + ports(&[0, 1, 3, 4, 5, 6]);
        let later = 2 + fog + 8;
        // 24 reads of `v` inputs, 8 codes (one ICW register field per variable) decoded
        let reads = |v: u32| 24.0 * t.mux(w, v + 1) + 8.0 * t.decoder(v, 4);
        g.add(
            format!("operand select x{w} of {first} registers, 24 reads (stage 0)"),
            1,
            reads(first),
        );
        g.add(
            format!(
                "operand select x{w} of {later} registers, 24 reads x{} stages",
                n - 1
            ),
            n - 1,
            reads(later),
        );
        g.add(
            format!("component-usage mux 2:1 x{w} x{n}"),
            vars * n,
            t.mux(w, 2),
        );
        g.add(
            format!("input mapping (clamp {w}, adder {}, 8:1 mux) x{n}", w + 1),
            vars * n,
            t.clamp(w) + t.adder(w + 1) + t.mux(w + 1, 8),
        );
        g.add(
            format!(
                "signed multiplier {w}x{w}: {v}x{v}, the two sign rows and the corner into the \
                 top {w} bits (RGB 6, alpha 2) x{n}",
                v = w - 1
            ),
            8 * n,
            t.multiplier(w - 1, w - 1) + 3.0 * t.adder(w),
        );
        g.add(
            format!("dot-product adders {} (2 dots x 2) x{n}", 2 * w + 2),
            4 * n,
            t.adder(2 * w + 2),
        );
        // each product read back in register units, round-half-up `/ S` as the Verilog
        // divides (`rtl::divide`): a lane product in [-S^2, S^2], the dot product's first lane
        // (the sum of three) in [-3 S^2, 3 S^2]; RGB AB and CD (3 lanes each), alpha AB, CD
        let s = 255i128 << (w - DEFAULT_WIDTH);
        g.add(
            format!("product rounding / (255 2^f) as a reciprocal multiply (6 products) x{n}"),
            6 * n,
            t.div_round(-s * s, s * s, s),
        );
        g.add(
            format!("dot-product rounding / (255 2^f) (RGB AB, CD) x{n}"),
            2 * n,
            t.div_round(-3 * s * s, 3 * s * s, s),
        );
        g.add(
            format!("AB + CD adder {} x4 x{n}", w + 2),
            4 * n,
            t.adder(w + 2),
        );
        g.add(
            format!("sum / mux select 2:1 x{} x4 x{n}", w + 2),
            4 * n,
            t.mux(w + 2, 2),
        );
        g.add(
            format!(
                "output scale / bias (adder {}, 4:1 shift mux, clamp {w}) x12 x{n}",
                w + 2
            ),
            12 * n,
            t.adder(w + 2) + t.mux(w + 3, 4) + t.clamp(w),
        );
        g.add(
            format!("blue-to-alpha mux 2:1 x{w} x2 x{n}"),
            2 * n,
            t.mux(w, 2),
        );
        g.add(
            format!("register write-back x{w}: 3 writes a colour lane, 5 an alpha lane (8 registers) x{n}"),
            n,
            24.0 * t.mux(w, 4) + 8.0 * t.mux(w, 6),
        );
        g.add(
            format!("write-back destination compares (8 registers x 6 fields) x{n}"),
            n,
            48.0 * t.decoder(1, 4),
        );
        g.add(
            format!(
                "pipeline registers: {} registers x 4 lanes x {w} bits, loaded every edge x{n}",
                8 + fog
            ),
            n,
            t.dff * f64::from(4 * (8 + fog) * w),
        );
        g.add(
            format!("stage state: 8 ICW bytes, 2 OCW of 20 bits, 2 RGBA factors = 168 bits x{n}"),
            n,
            t.register(168),
        );
        self.final_gates(t, &mut g);
        g.add(
            "final state: 7 variables of 6 bits, 3 flags, 2 RGBA factors = 109 bits",
            1,
            t.register(109),
        );
        g.add("output register 32", 1, t.register(32));
        g
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        let out = Self::output_encoding();
        match mode {
            Mode::Exact => {
                let p = ExactPath;
                let r = run(&p, &self.program, &self.register_inputs(&p, Some(ins)));
                outs[0] = Word::from_exact(&out, &r);
            }
            Mode::BitAccurate => {
                let p = FixedPath::new(self.params.width);
                let r = run(&p, &self.program, &self.register_inputs(&p, Some(ins)));
                outs[0] = Word::from_raw(&out, &r.map(|v| p.code_of(v)));
            }
        }
    }
}

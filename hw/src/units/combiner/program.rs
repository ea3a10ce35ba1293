//! The combiner program: what the NV_register_combiners state (and the NV2A registers
//! `NV097_SET_COMBINER_COLOR_ICW/OCW`, `_ALPHA_ICW/OCW`, `_FACTOR0/1`, `_SPECULAR_FOG_CW0/1`,
//! `_COMBINER_CONTROL`) hold, as plain data, and its checks.
//!
//! Names follow the extension spec (section 2.14 "Register Combiners Application" of
//! NV_register_combiners): registers (table NV_register_combiners.1), input mappings (table .2
//! ), component usage, the general combiner's AB / CD / sum outputs with scale and bias
//! (table .4), and the final combiner's variables A to G with the special inputs
//! `E_TIMES_F` and `SPARE0_PLUS_SECONDARY_COLOR`.

use serde::{Deserialize, Serialize};

/// A combiner register (NV_register_combiners table .1; the NV2A source codes 0 to 15 in
/// brackets). `Spare0PlusSecondary` and `EfProduct` exist only as final-combiner inputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub enum Source {
    /// ZERO (0): reads as 0 in every component.
    #[default]
    Zero,
    /// CONSTANT_COLOR0 (1): the stage's (or the final combiner's) constant 0.
    Constant0,
    /// CONSTANT_COLOR1 (2).
    Constant1,
    /// FOG (3): fog colour in RGB, fog factor in alpha.
    Fog,
    /// PRIMARY_COLOR (4): the interpolated diffuse colour.
    Primary,
    /// SECONDARY_COLOR (5): the interpolated specular colour.
    Secondary,
    /// TEXTURE0..3 (8 to 11): the texture-shader stage results.
    Texture0,
    Texture1,
    Texture2,
    Texture3,
    /// SPARE0 (12, NV2A "R0"): alpha initialised to texture 0's alpha, RGB to 0.
    Spare0,
    /// SPARE1 (13, NV2A "R1"): initialised to 0.
    Spare1,
    /// SPARE0_PLUS_SECONDARY_COLOR (14): final combiner only.
    Spare0PlusSecondary,
    /// E_TIMES_F (15): final combiner only.
    EfProduct,
}

impl Source {
    /// Index into the register file (0 to 11), `None` for the two final-combiner specials.
    pub(crate) fn index(self) -> Option<usize> {
        use Source::*;
        Some(match self {
            Zero => 0,
            Constant0 => 1,
            Constant1 => 2,
            Fog => 3,
            Primary => 4,
            Secondary => 5,
            Texture0 => 6,
            Texture1 => 7,
            Texture2 => 8,
            Texture3 => 9,
            Spare0 => 10,
            Spare1 => 11,
            Spare0PlusSecondary | EfProduct => return None,
        })
    }
    /// Whether a general combiner may write it (spec: DISCARD, the spares, the colours and
    /// the textures; not ZERO, the constants or FOG).
    pub fn writable(self) -> bool {
        use Source::*;
        matches!(
            self,
            Primary | Secondary | Texture0 | Texture1 | Texture2 | Texture3 | Spare0 | Spare1
        )
    }
}

/// Number of registers of the register file (ZERO to SPARE1).
pub(crate) const REGISTERS: usize = 12;

/// Input mapping of a general-combiner variable (spec table NV_register_combiners.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub enum Mapping {
    /// max(0, e)
    #[default]
    UnsignedIdentity,
    /// 1 - min(max(e, 0), 1)
    UnsignedInvert,
    /// 2 max(0, e) - 1
    ExpandNormal,
    /// -2 max(0, e) + 1
    ExpandNegate,
    /// max(0, e) - 1/2
    HalfBiasNormal,
    /// -max(0, e) + 1/2
    HalfBiasNegate,
    /// e
    SignedIdentity,
    /// -e
    SignedNegate,
}

impl Mapping {
    pub const ALL: [Mapping; 8] = [
        Mapping::UnsignedIdentity,
        Mapping::UnsignedInvert,
        Mapping::ExpandNormal,
        Mapping::ExpandNegate,
        Mapping::HalfBiasNormal,
        Mapping::HalfBiasNegate,
        Mapping::SignedIdentity,
        Mapping::SignedNegate,
    ];
}

/// Component usage of a variable (spec: RGB or ALPHA in an RGB portion, ALPHA or BLUE in an
/// alpha portion; NV2A's one "alpha" bit per variable selects between the two).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub enum Usage {
    Rgb,
    #[default]
    Alpha,
    Blue,
}

/// One variable (A, B, C or D) of a general combiner portion. In a config every field may be
/// left out: an omitted variable reads ZERO (usage ALPHA, UNSIGNED_IDENTITY), valid in both
/// portions; the same holds for omitted portions, stages' flags and constants (0) and
/// final-combiner inputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Input {
    pub source: Source,
    pub usage: Usage,
    pub mapping: Mapping,
}

impl Input {
    pub const fn new(source: Source, usage: Usage, mapping: Mapping) -> Input {
        Input {
            source,
            usage,
            mapping,
        }
    }
    /// ZERO, UNSIGNED_IDENTITY: 0 (RGB usage; valid in an RGB portion).
    pub const fn zero() -> Input {
        Input::new(Source::Zero, Usage::Rgb, Mapping::UnsignedIdentity)
    }
    /// ZERO, UNSIGNED_INVERT: 1 (RGB usage).
    pub const fn one() -> Input {
        Input::new(Source::Zero, Usage::Rgb, Mapping::UnsignedInvert)
    }
    /// ZERO in an alpha portion (BLUE usage).
    pub const fn zero_alpha() -> Input {
        Input::new(Source::Zero, Usage::Blue, Mapping::UnsignedIdentity)
    }
    /// 1 in an alpha portion.
    pub const fn one_alpha() -> Input {
        Input::new(Source::Zero, Usage::Blue, Mapping::UnsignedInvert)
    }
    /// `source` with the given usage, UNSIGNED_IDENTITY.
    pub const fn of(source: Source, usage: Usage) -> Input {
        Input::new(source, usage, Mapping::UnsignedIdentity)
    }
}

/// Output scale and bias of a general combiner portion (spec table NV_register_combiners.4;
/// NV2A OCW bits 15-17: 0 identity, 1 bias, 2 shift left 1, 3 shift left 1 with bias,
/// 4 shift left 2, 5 shift left 2 with bias, 6 shift right 1). SCALE_BY_ONE_HALF with
/// BIAS_BY_NEGATIVE_ONE_HALF is an error in the spec and has no variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub enum OutputOp {
    /// x
    #[default]
    Identity,
    /// x - 1/2
    Bias,
    /// 2 x
    ShiftLeft1,
    /// 2 (x - 1/2)
    ShiftLeft1Bias,
    /// 4 x
    ShiftLeft2,
    /// 4 (x - 1/2)
    ShiftLeft2Bias,
    /// x / 2
    ShiftRight1,
}

impl OutputOp {
    pub const ALL: [OutputOp; 7] = [
        OutputOp::Identity,
        OutputOp::Bias,
        OutputOp::ShiftLeft1,
        OutputOp::ShiftLeft1Bias,
        OutputOp::ShiftLeft2,
        OutputOp::ShiftLeft2Bias,
        OutputOp::ShiftRight1,
    ];
    /// (bias applied, left shift; -1 for the right shift)
    pub(crate) fn parts(self) -> (bool, i32) {
        match self {
            OutputOp::Identity => (false, 0),
            OutputOp::Bias => (true, 0),
            OutputOp::ShiftLeft1 => (false, 1),
            OutputOp::ShiftLeft1Bias => (true, 1),
            OutputOp::ShiftLeft2 => (false, 2),
            OutputOp::ShiftLeft2Bias => (true, 2),
            OutputOp::ShiftRight1 => (false, -1),
        }
    }
}

/// One portion (RGB or alpha) of a general combiner: `AB = A*B` or `A.B`, `CD = C*D` or
/// `C.D`, and `AB + CD` or the mux; each of the three written, after the output op, to its
/// register or discarded (`None`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Portion {
    pub a: Input,
    pub b: Input,
    pub c: Input,
    pub d: Input,
    /// AB is the dot product A.B (RGB portion only), broadcast to R, G and B.
    pub ab_dot: bool,
    /// CD is the dot product C.D (RGB portion only).
    pub cd_dot: bool,
    /// The third output is the mux (spare0 alpha selects CD or AB) instead of AB + CD.
    pub mux: bool,
    pub op: OutputOp,
    pub ab_out: Option<Source>,
    pub cd_out: Option<Source>,
    pub sum_out: Option<Source>,
}

impl Portion {
    /// All variables zero, every output discarded: a portion that does nothing. `alpha`
    /// picks the component usage valid for an alpha portion.
    pub const fn nop(alpha: bool) -> Portion {
        let z = if alpha {
            Input::zero_alpha()
        } else {
            Input::zero()
        };
        Portion {
            a: z,
            b: z,
            c: z,
            d: z,
            ab_dot: false,
            cd_dot: false,
            mux: false,
            op: OutputOp::Identity,
            ab_out: None,
            cd_out: None,
            sum_out: None,
        }
    }
}

/// One general combiner stage: its RGB and alpha portions, the NV2A "blue to alpha" flags
/// (OCW bits 19 and 18: the blue of the RGB portion's AB (CD) output is also written to the
/// alpha of the AB (CD) destination, as Direct3D's dp3 replicates into alpha), and the
/// stage's two constants as the 8-bit codes `NV097_SET_COMBINER_FACTOR0/1` hold (RGBA).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct GeneralStage {
    pub rgb: Portion,
    pub alpha: Portion,
    pub ab_blue_to_alpha: bool,
    pub cd_blue_to_alpha: bool,
    pub c0: [u8; 4],
    pub c1: [u8; 4],
}

impl GeneralStage {
    /// A stage that does nothing, with zero constants.
    pub const fn nop() -> GeneralStage {
        GeneralStage {
            rgb: Portion::nop(false),
            alpha: Portion::nop(true),
            ab_blue_to_alpha: false,
            cd_blue_to_alpha: false,
            c0: [0; 4],
            c1: [0; 4],
        }
    }
}

/// One final-combiner variable: its register, component usage and UNSIGNED_INVERT flag
/// (the final combiner only has UNSIGNED_IDENTITY and UNSIGNED_INVERT).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct FinalInput {
    pub source: Source,
    pub usage: Usage,
    pub invert: bool,
}

impl FinalInput {
    pub const fn new(source: Source, usage: Usage, invert: bool) -> FinalInput {
        FinalInput {
            source,
            usage,
            invert,
        }
    }
    /// 0 (ZERO, RGB usage).
    pub const fn zero() -> FinalInput {
        FinalInput::new(Source::Zero, Usage::Rgb, false)
    }
    /// 1 (ZERO inverted).
    pub const fn one() -> FinalInput {
        FinalInput::new(Source::Zero, Usage::Rgb, true)
    }
}

/// The final combiner: `RGB = min(A*B + (1-A)*C + D, 1)`, `alpha = G`, with `E*F` and
/// `spare0 + secondary` as extra inputs of A to D, and NV2A's flags on that sum
/// (`NV097_SET_COMBINER_SPECULAR_FOG_CW1`: invert R0, invert V1, clamp), and its own two
/// constants (`NV097_SET_SPECULAR_FOG_FACTOR`, RGBA codes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct FinalCombiner {
    pub a: FinalInput,
    pub b: FinalInput,
    pub c: FinalInput,
    pub d: FinalInput,
    pub e: FinalInput,
    pub f: FinalInput,
    /// G: alpha or blue usage.
    pub g: FinalInput,
    /// The sum adds 1 - spare0 instead of spare0.
    pub sum_invert_spare0: bool,
    /// The sum adds 1 - secondary instead of secondary.
    pub sum_invert_secondary: bool,
    /// COLOR_SUM_CLAMP: the sum is clamped to 1.
    pub sum_clamp: bool,
    pub c0: [u8; 4],
    pub c1: [u8; 4],
}

impl FinalCombiner {
    /// `RGB = D`, `alpha = G`: the most common final combiner.
    pub const fn just(d: FinalInput, g: FinalInput) -> FinalCombiner {
        FinalCombiner {
            a: FinalInput::zero(),
            b: FinalInput::zero(),
            c: FinalInput::zero(),
            d,
            e: FinalInput::zero(),
            f: FinalInput::zero(),
            g,
            sum_invert_spare0: false,
            sum_invert_secondary: false,
            sum_clamp: false,
            c0: [0; 4],
            c1: [0; 4],
        }
    }
}

/// What the mux of a general combiner tests (NV2A `NV097_SET_COMBINER_CONTROL_MUX_SELECT`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub enum MuxSelect {
    /// The least significant bit of spare0's 8-bit alpha code (NV2A's reset value).
    #[default]
    Lsb,
    /// The most significant bit: spare0 alpha >= 1/2 (the extension spec's test).
    Msb,
}

/// A whole combiner program: 1 to the part's number of general stages, then the final
/// combiner.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Program {
    pub stages: Vec<GeneralStage>,
    #[serde(default)]
    pub final_combiner: FinalCombiner,
    #[serde(default)]
    pub mux_select: MuxSelect,
}

fn check_input(at: &str, i: &Input, alpha: bool) -> Result<(), String> {
    if i.source.index().is_none() {
        return Err(format!(
            "{at}.source: {:?} is a final-combiner input: expected a register from Zero to Spare1",
            i.source
        ));
    }
    let ok = if alpha {
        matches!(i.usage, Usage::Alpha | Usage::Blue)
    } else {
        matches!(i.usage, Usage::Rgb | Usage::Alpha)
    };
    if !ok {
        let want = if alpha {
            "Alpha or Blue"
        } else {
            "Rgb or Alpha"
        };
        let p = if alpha { "an alpha" } else { "an RGB" };
        return Err(format!(
            "{at}.usage: {:?} is not allowed in {p} portion: expected {want}",
            i.usage
        ));
    }
    Ok(())
}

fn check_portion(at: &str, p: &Portion, alpha: bool) -> Result<(), String> {
    for (n, i) in [("a", &p.a), ("b", &p.b), ("c", &p.c), ("d", &p.d)] {
        check_input(&format!("{at}.{n}"), i, alpha)?;
    }
    if alpha && (p.ab_dot || p.cd_dot) {
        let f = if p.ab_dot { "ab_dot" } else { "cd_dot" };
        return Err(format!(
            "{at}.{f}: dot products exist only in the RGB portion: expected false"
        ));
    }
    let outs = [
        ("ab_out", p.ab_out),
        ("cd_out", p.cd_out),
        ("sum_out", p.sum_out),
    ];
    for (k, (n, o)) in outs.iter().enumerate() {
        if let Some(r) = o {
            if !r.writable() {
                return Err(format!(
                    "{at}.{n}: {r:?} cannot be written: expected None (discard), Primary, \
                     Secondary, Texture0 to Texture3, Spare0 or Spare1"
                ));
            }
            if let Some((m, _)) = outs[..k].iter().find(|(_, q)| *q == Some(*r)) {
                return Err(format!(
                    "{at}.{n}: {r:?} is also {m}: expected distinct registers for the outputs \
                     of one portion"
                ));
            }
        }
    }
    Ok(())
}

fn check_final_input(at: &str, i: &FinalInput, special_ok: bool, g: bool) -> Result<(), String> {
    let special = i.source.index().is_none();
    if special && !special_ok {
        return Err(format!(
            "{at}.source: {:?} is only an input of A, B, C and D: expected a register from \
             Zero to Spare1",
            i.source
        ));
    }
    if g {
        if !matches!(i.usage, Usage::Alpha | Usage::Blue) {
            return Err(format!(
                "{at}.usage: {:?} is not allowed for G: expected Alpha or Blue",
                i.usage
            ));
        }
    } else if special && i.usage != Usage::Rgb {
        return Err(format!(
            "{at}.usage: {:?} of {:?}: expected Rgb (the special inputs have no alpha)",
            i.usage, i.source
        ));
    } else if i.usage == Usage::Blue {
        return Err(format!(
            "{at}.usage: Blue is not allowed for A to F: expected Rgb or Alpha"
        ));
    }
    Ok(())
}

impl Program {
    /// Check the program against the spec's rules and the part's `max_stages`. The error
    /// names the field and what was expected.
    pub fn validate(&self, max_stages: usize) -> Result<(), String> {
        let n = self.stages.len();
        if n == 0 || n > max_stages {
            return Err(format!(
                "stages: {n} given: expected 1 to {max_stages} general combiners"
            ));
        }
        for (k, s) in self.stages.iter().enumerate() {
            check_portion(&format!("stages[{k}].rgb"), &s.rgb, false)?;
            check_portion(&format!("stages[{k}].alpha"), &s.alpha, true)?;
        }
        let f = &self.final_combiner;
        for (n, i) in [("a", &f.a), ("b", &f.b), ("c", &f.c), ("d", &f.d)] {
            check_final_input(&format!("final_combiner.{n}"), i, true, false)?;
        }
        for (n, i) in [("e", &f.e), ("f", &f.f)] {
            check_final_input(&format!("final_combiner.{n}"), i, false, false)?;
        }
        check_final_input("final_combiner.g", &f.g, false, true)?;
        Ok(())
    }
}

//! NV20 / NV2A texture shaders (NV_texture_shader, section 3.8.13 "Texture Shaders"; NV2A
//! registers `NV097_SET_SHADER_STAGE_PROGRAM`, `_SHADER_OTHER_STAGE_INPUT`,
//! `_DOT_RGBMAPPING`, `_SHADER_CLIP_PLANE_MODE`, `_TEXTURE_SET_BUMP_ENV_*`): one program per
//! stage, 4 stages by default (the GeForce3 / NV2A count; the count is a parameter).
//!
//! Programs (`program.rs`): NONE, TEXTURE_2D (projective: s/q, t/q), TEXTURE_CUBE_MAP,
//! PASS_THROUGH, CULL_FRAGMENT, OFFSET_TEXTURE_2D and _SCALE (the D3D6 BUMPENVMAP and
//! BUMPENVMAPLUMINANCE), DEPENDENT_AR / _GB, DOT_PRODUCT, DOT_PRODUCT_TEXTURE_2D,
//! DOT_PRODUCT_TEXTURE_CUBE_MAP, DOT_PRODUCT_REFLECT_CUBE_MAP, DOT_PRODUCT_CONST_EYE_REFLECT_
//! CUBE_MAP, DOT_PRODUCT_DIFFUSE_CUBE_MAP and DOT_PRODUCT_DEPTH_REPLACE. The stage rules
//! (`rules.rs`, spec "Texture Shader Consistency") are checked at construction: a broken rule
//! is an error naming the stage and the rule, or, with [`OnBroken::AsNone`], the stage runs
//! NONE as the hardware does and [`TextureShader::broken`] reports it. Dot-product mappings
//! (`mapping.rs`): the NV2A's eight (ZERO_TO_ONE, MINUS1_TO_1_D3D, _GL, two's complement,
//! HILO_1 and the three HILO hemispheres).
//!
//! Textures are the engine's shared [`Texture`]s behind `Arc`, read only through each
//! stage's [`Sampler`]; a stage's result is its texel in the texture's own encoding (missing
//! lanes: RGB 0, alpha 1), so a combiner reads 8-bit codes exactly.
//!
//! **Bit-accurate mode.** Texture coordinates are raw words of the coordinate encoding
//! ([`ShaderParams::coord`], default s16.16); the projective divide, the dot products (the
//! mapped N has [`ShaderParams::dot_frac`] fraction bits, default 16), the offset (matrix,
//! scale and bias with [`ShaderParams::offset_frac`] fraction bits, default 8), the reflection
//! and the depth divide are computed exactly and rounded once into the coordinate format
//! (halves up, saturated). PASS_THROUGH writes [`ShaderParams::pass_through`] (default 8-bit
//! unsigned through the colour converter [`ShaderParams::convert_frac`]: truncated to 12
//! fraction bits and read as the top of its step, the `Passthru` frame). **Exact mode**: the same programs in f64 (the
//! matrix and the eye unquantized).
//!
//! Ports: in `coord0`..`coord{n-1}` (s, t, r, q per stage) and, with [`ShaderParams::lod`],
//! `lod` (the level of detail of the TEXTURE_2D stages' mip levels); out `tex0`..`tex{n-1}` (4 lanes,
//! each in its stage's result encoding, [`TextureShader::result_encoding`]) and `depth` (1
//! lane, coordinate encoding: DOT_PRODUCT_DEPTH_REPLACE's z, else 0). CULL_FRAGMENT kills
//! through [`Unit::live`]. Latency: one clock per stage plus 3 (texel fetch and filter);
//! interval 1.

mod eval;
pub mod mapping;
mod price;
mod program;
mod programmable;
mod rules;
#[cfg(test)]
mod tests;

pub use price::Datapath;
pub use program::{DotMapping, Offset, Program};

use crate::format::{Codec, Encoding, Format, Quant};
use crate::gates::{CostTable, GateBudget};
use crate::sampler::{Filter, SamplePlan, Sampler};
use crate::texture::Texture;
use crate::unit::{Mode, PortSpec, TextureRead, Unit, Word};
use eval::{run, ExactArith, FixedArith};
use std::sync::Arc;

/// Stages of the GeForce3 / NV2A.
pub const NV2A_STAGES: usize = 4;
/// Largest number of stages a part may have.
pub const MAX_STAGES: usize = 8;

/// What a broken stage rule does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OnBroken {
    /// Construction fails, naming the stage and the rule.
    #[default]
    Reject,
    /// The stage runs NONE (the hardware's behaviour) and is listed by
    /// [`TextureShader::broken`].
    AsNone,
}

/// The part: stage count and number formats.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShaderParams {
    /// Stages of the part (1 to 8; 4 on the NV2A).
    pub stages: usize,
    /// Encoding of the texture coordinates (fixed point, signed, 8 to 32 bits).
    pub coord: Encoding,
    /// Fraction bits of the mapped dot-product vector N (1 to 24).
    pub dot_frac: u32,
    /// Fraction bits of the offset matrix and of the luminance scale and bias (1 to 16).
    pub offset_frac: u32,
    /// Encoding of the PASS_THROUGH colour.
    pub pass_through: Encoding,
    /// The converter of the colours the unit computes (PASS_THROUGH's coordinates and the
    /// BUMPENVMAPLUMINANCE product) into n-bit unsigned codes. `Some(k)` (1 to 24; the
    /// NV2A's 12): the value `x`, clamped to [0, 1], truncated to `k` fraction bits and read
    /// as the top of its step, `c = ((floor(x 2^k) + 1) (2^n - 1)) >> k` (the `Passthru` and
    /// `BumpEnvMapLuminance` frames: every pixel). `None`: PASS_THROUGH rounds the coordinate
    /// into `pass_through` by its quantization, the luminance product is floored.
    pub convert_frac: Option<u32>,
    pub on_broken: OnBroken,
    /// The encoding of the level-of-detail input `lod` (1 lane, fixed point), if the part
    /// selects mip levels: a TEXTURE_2D stage whose texture has mip levels reads level
    /// `clamp(floor(lod + 1/2), 0, levels - 1)` (GL's NEAREST_MIPMAP_NEAREST); every other
    /// stage, and every stage without `lod`, reads level 0. The GeForce3 computes the LOD per
    /// pixel from the coordinates' derivatives; here it comes from the engine (a per-triangle
    /// or interpolated per-vertex attribute), and the dependent lookups read level 0 (their
    /// tables have one).
    pub lod: Option<Encoding>,
    /// What the gate budget prices: the programmable part (every stage has every program's
    /// datapath, the default) or the configured programs' datapaths only (`price.rs`).
    pub datapath: Datapath,
}

impl Default for ShaderParams {
    fn default() -> Self {
        ShaderParams {
            stages: NV2A_STAGES,
            coord: Encoding::fixed(Format::s(32, 16)),
            dot_frac: 16,
            offset_frac: 8,
            pass_through: Encoding {
                quant: Quant::Trn,
                ..Encoding::texel(Codec::UnitUnsigned, false, 8)
            },
            convert_frac: Some(12),
            on_broken: OnBroken::Reject,
            lod: None,
            datapath: Datapath::Programmable,
        }
    }
}

/// One stage: its program, its texture (shared memory) and its sampler.
#[derive(Debug, Clone)]
pub struct StageSpec {
    pub program: Program,
    pub texture: Option<Arc<Texture>>,
    pub sampler: Sampler,
}

impl StageSpec {
    /// A stage running `program` on `texture` (bilinear, 8-bit weights, wrap).
    pub fn new(program: Program, texture: Option<Arc<Texture>>) -> StageSpec {
        StageSpec {
            program,
            texture,
            sampler: Sampler::new(Filter::Bilinear, 8).expect("8 weight bits are valid"),
        }
    }
    pub fn none() -> StageSpec {
        StageSpec::new(Program::None, None)
    }
    pub fn with_sampler(mut self, s: Sampler) -> StageSpec {
        self.sampler = s;
        self
    }
}

/// A stage as built: the spec, its result encoding and lanes, quantized constants, the
/// broken rule if any.
#[derive(Debug, Clone)]
pub(crate) struct Compiled {
    pub spec: StageSpec,
    pub out_enc: Encoding,
    pub lanes: u8,
    pub offset: Offset,
    pub matrix_raw: [i64; 4],
    pub scale_raw: [i64; 2],
    pub broken: Option<String>,
    /// The sampler's casts from the stage's texture into `out_enc`, if it has a texture.
    pub plan: Option<SamplePlan>,
}

/// The texture-shader unit. See the module documentation.
pub struct TextureShader {
    params: ShaderParams,
    pub(crate) stages: Vec<Compiled>,
    inputs: Vec<PortSpec>,
    outputs: Vec<PortSpec>,
}

fn u8_enc() -> Encoding {
    Encoding::texel(Codec::UnitUnsigned, false, 8)
}

impl TextureShader {
    /// A part running `stages` (at most `params.stages`; the rest run NONE). Every field is
    /// checked; errors name it and say what was expected.
    pub fn new(params: ShaderParams, stages: Vec<StageSpec>) -> Result<TextureShader, String> {
        if !(1..=MAX_STAGES).contains(&params.stages) {
            return Err(format!(
                "stages: {} given: expected 1 to {MAX_STAGES} texture-shader stages",
                params.stages
            ));
        }
        if stages.len() > params.stages {
            return Err(format!(
                "programs: {} stages given: the part has {}",
                stages.len(),
                params.stages
            ));
        }
        let c = params.coord;
        c.validate().map_err(|m| format!("coord: {m}"))?;
        if c.codec != Codec::Fixed || !c.format.signed || c.width() < 8 {
            return Err(format!(
                "coord: {c}: expected a signed fixed-point encoding of 8 to 32 bits"
            ));
        }
        if !(1..=24).contains(&params.dot_frac) {
            return Err(format!(
                "dot_frac: {} given: expected 1 to 24 fraction bits",
                params.dot_frac
            ));
        }
        if !(1..=16).contains(&params.offset_frac) {
            return Err(format!(
                "offset_frac: {} given: expected 1 to 16 fraction bits",
                params.offset_frac
            ));
        }
        params
            .pass_through
            .validate()
            .map_err(|m| format!("pass_through: {m}"))?;
        if let Some(k) = params.convert_frac {
            if !(1..=24).contains(&k) {
                return Err(format!("convert_frac: {k}: expected 1 to 24 fraction bits"));
            }
            let e = params.pass_through;
            if e.codec != Codec::UnitUnsigned || e.format.signed || e.width() > 16 {
                return Err(format!(
                    "convert_frac: needs an unsigned unit pass_through code of at most 16 bits, not {e}"
                ));
            }
        }
        if let Some(l) = params.lod {
            l.validate().map_err(|m| format!("lod: {m}"))?;
            if l.codec != Codec::Fixed || l.width() > 32 {
                return Err(format!(
                    "lod: {l}: expected a fixed-point level of detail of at most 32 bits"
                ));
            }
        }
        let mut specs = stages;
        specs.resize_with(params.stages, StageSpec::none);
        let broken = rules::check(&specs);
        if params.on_broken == OnBroken::Reject {
            if let Some((i, m)) = broken
                .iter()
                .enumerate()
                .find_map(|(i, b)| b.as_ref().map(|m| (i, m)))
            {
                return Err(format!("stage {i}: {m}"));
            }
        }
        let of = params.offset_frac;
        let mut compiled = Vec::with_capacity(specs.len());
        for (i, (spec, broken)) in specs.into_iter().zip(broken).enumerate() {
            if let Some(t) = &spec.texture {
                spec.sampler
                    .check(t, &c)
                    .map_err(|m| format!("stage {i}: {m}"))?;
            }
            let (out_enc, lanes) = match (&spec.program, &spec.texture) {
                (Program::PassThrough, _) => (params.pass_through, 4),
                (p, Some(t)) if p.texture_kind().is_some() => (*t.texel(), t.lanes()),
                _ => (u8_enc(), 4),
            };
            let offset = match spec.program {
                Program::OffsetTexture2d { offset, .. }
                | Program::OffsetTexture2dScale { offset, .. } => offset,
                _ => Offset::default(),
            };
            let q = |what: String, x: f64| -> Result<i64, String> {
                if !x.is_finite() || x.abs() > 1024.0 {
                    return Err(format!(
                        "stage {i}: {what} = {x}: expected a finite value in [-1024, 1024]"
                    ));
                }
                Ok((x * (1u64 << of) as f64).round() as i64)
            };
            let mut matrix_raw = [0; 4];
            for (k, m) in matrix_raw.iter_mut().enumerate() {
                *m = q(format!("offset.matrix[{k}]"), offset.matrix[k])?;
            }
            let scale_raw = [
                q("offset.scale".into(), offset.scale)?,
                q("offset.bias".into(), offset.bias)?,
            ];
            if let Program::DotProductConstEyeReflectCube { eye, .. } = spec.program {
                if eye.iter().any(|e| !e.is_finite()) {
                    return Err(format!("stage {i}: eye {eye:?}: expected finite values"));
                }
            }
            let plan = spec
                .texture
                .as_ref()
                .map(|t| spec.sampler.plan(t.texel(), &out_enc));
            compiled.push(Compiled {
                plan,
                spec,
                out_enc,
                lanes,
                offset,
                matrix_raw,
                scale_raw,
                broken,
            });
        }
        let n = compiled.len();
        let mut inputs: Vec<PortSpec> = (0..n)
            .map(|i| PortSpec::new(&format!("coord{i}"), 4, c))
            .collect();
        if let Some(l) = params.lod {
            inputs.push(PortSpec::new("lod", 1, l));
        }
        let mut outputs: Vec<PortSpec> = compiled
            .iter()
            .enumerate()
            .map(|(i, s)| PortSpec::new(&format!("tex{i}"), 4, s.out_enc))
            .collect();
        outputs.push(PortSpec::new("depth", 1, c));
        Ok(TextureShader {
            params,
            stages: compiled,
            inputs,
            outputs,
        })
    }

    pub fn params(&self) -> &ShaderParams {
        &self.params
    }
    /// The program each stage runs: its configured one, or NONE where a rule is broken
    /// (what the price of the configured datapath and the Verilog generator build).
    pub fn programs(&self) -> Vec<Program> {
        self.stages
            .iter()
            .map(|s| match s.broken {
                Some(_) => Program::None,
                None => s.spec.program,
            })
            .collect()
    }
    /// The stages whose rule is broken (they run NONE): (stage, the rule).
    pub fn broken(&self) -> Vec<(usize, String)> {
        self.stages
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.broken.clone().map(|m| (i, m)))
            .collect()
    }
    /// The encoding of stage `i`'s result port.
    pub fn result_encoding(&self, i: usize) -> Option<Encoding> {
        self.stages.get(i).map(|s| s.out_enc)
    }
    /// Whether a program kills fragments.
    fn culls(&self) -> bool {
        self.stages
            .iter()
            .any(|s| s.broken.is_none() && matches!(s.spec.program, Program::CullFragment { .. }))
    }
    fn eval_any(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) -> bool {
        let c = &self.params.coord;
        let n = self.stages.len();
        let (results, live, depth) = match mode {
            Mode::Exact => {
                let f = run(&ExactArith, self, ins);
                let d = Word::from_exact(c, &[f.depth.unwrap_or(0.0)]);
                (f.results, f.live, d)
            }
            Mode::BitAccurate => {
                let a = FixedArith {
                    coord: *c,
                    dot_frac: self.params.dot_frac,
                    offset_frac: self.params.offset_frac,
                    lod_frac: self.params.lod.map_or(0, |l| l.format.frac as u32),
                    convert_frac: self.params.convert_frac,
                };
                let f = run(&a, self, ins);
                (
                    f.results,
                    f.live,
                    Word::from_raw(c, &[f.depth.unwrap_or(0)]),
                )
            }
        };
        if outs.len() > n {
            outs[..n].copy_from_slice(&results);
            outs[n] = depth;
        }
        live
    }
}

impl Unit for TextureShader {
    fn kind(&self) -> &'static str {
        "texture_shader"
    }
    fn inputs(&self) -> &[PortSpec] {
        &self.inputs
    }
    fn outputs(&self) -> &[PortSpec] {
        &self.outputs
    }
    fn latency(&self) -> u32 {
        self.stages.len() as u32 + 3
    }
    fn interval(&self) -> u32 {
        1
    }
    fn textures(&self) -> Vec<TextureRead> {
        self.stages
            .iter()
            .filter(|s| s.spec.program.texture_kind().is_some())
            .filter_map(|s| {
                s.spec.texture.clone().map(|texture| TextureRead {
                    texture,
                    taps: s.spec.sampler.taps(),
                })
            })
            .collect()
    }
    fn upload(&mut self, old: &Arc<Texture>, new: &Arc<Texture>) {
        for s in &mut self.stages {
            if s.spec.texture.as_ref().is_some_and(|t| Arc::ptr_eq(t, old)) {
                s.plan = Some(s.spec.sampler.plan(new.texel(), &s.out_enc));
                s.spec.texture = Some(new.clone());
            }
        }
    }
    fn can_kill(&self) -> bool {
        self.culls()
    }
    fn live(&self, mode: Mode, ins: &[Word], _outs: &[Word]) -> bool {
        if !self.culls() {
            return true;
        }
        let mut scratch = vec![Word::default(); self.outputs.len()];
        self.eval_any(mode, ins, &mut scratch)
    }
    fn gates(&self, t: &CostTable) -> GateBudget {
        match self.params.datapath {
            Datapath::Programmable => programmable::programmable(self, t),
            Datapath::Configured => price::configured(self, t),
        }
    }
    fn generated_gates(&self, t: &CostTable) -> Option<GateBudget> {
        (self.params.datapath == Datapath::Programmable).then(|| price::configured(self, t))
    }
    fn eval(&self, mode: Mode, ins: &[Word], outs: &mut [Word]) {
        self.eval_any(mode, ins, outs);
    }
}

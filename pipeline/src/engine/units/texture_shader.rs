//! NV20 / NV2A texture shaders as a config unit (`hw/src/units/texture_shader/`,
//! `docs/units/texture-shader.md`).

use super::ports::input;
use super::textures::{cube_faces, key, mip_levels, texels, TextureSource};
use super::{recipe, BuildCtx, Spec};
use bumpsim_hw::units::texture_shader::{
    Datapath, OnBroken, Program, ShaderParams, StageSpec, TextureShader, MAX_STAGES,
};
use bumpsim_hw::units::{Address, Filter};
use bumpsim_hw::{Encoding, PortSpec, Sampler, Texture, Unit};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// NV20 / NV2A texture shaders: one `program` per stage (NV_texture_shader table 3.A, the
/// `Program` names of `hw/src/units/texture_shader/program.rs`), each stage `i` reading its
/// texture coordinates `(s, t, r, q)` from input `coord{i}` (4 lanes; every stage the same
/// signed fixed-point encoding, which is the part's coordinate format) and writing its texel
/// to output `tex{i}` (4 lanes in the texture's encoding; `depth` for DEPENDENT_DEPTH_REPLACE).
/// The part has as many stages as `programs` (1 to 8; the NV2A's 4: give NONE stages to
/// model it whole). `on_broken`: a program that breaks a stage rule is a config error
/// (`Reject`, the default) or runs NONE as the hardware does (`AsNone`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureShaderSpec {
    pub programs: Vec<StageConfig>,
    /// Fraction bits of the mapped dot-product vector (1 to 24; 16 by default).
    #[serde(default = "dot_frac")]
    pub dot_frac: u32,
    /// Fraction bits of the offset matrix, luminance scale and bias (1 to 16; 8 by default).
    #[serde(default = "offset_frac")]
    pub offset_frac: u32,
    #[serde(default)]
    pub on_broken: Broken,
    /// The colour converter of PASS_THROUGH and of the NV2A luminance product
    /// (`luminance_unclamped`): `Some(k)` truncates the value to `k` fraction bits (1 to 24)
    /// and reads it as the top of its step, `c = ((floor(x 2^k) + 1) 255) >> k`, as the NV2A
    /// does at `Some(12)` (the default, left out of the serialised config); `None` rounds
    /// (PASS_THROUGH by its encoding) or floors (the luminance product).
    #[serde(default = "convert_frac", skip_serializing_if = "is_nv2a_converter")]
    pub convert_frac: Option<u32>,
    /// Mip-level selection: the unit reads a level of detail from input `lod` (1 lane, fixed
    /// point, e.g. the `Lod` or `VertexLod` attribute), and a TEXTURE_2D stage whose texture
    /// has mip levels (`NdfNoise(mips: true)`) reads the level GL's NEAREST_MIPMAP_NEAREST
    /// selects. `false` (the default): every stage reads level 0. (Left out of the
    /// serialised config when `false`.)
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub lod: bool,
    /// What the unit's gate budget prices: `Programmable` (the default: every stage has the
    /// datapath of every program, as the NV2A's) or `Configured` (each stage the datapath of
    /// its program only, as the generated Verilog that synthesis confirms; docs/gates.md).
    /// (Left out of the serialised config when `Programmable`.)
    #[serde(default, skip_serializing_if = "is_programmable")]
    pub datapath: Datapath,
}

fn is_programmable(d: &Datapath) -> bool {
    *d == Datapath::Programmable
}

/// What a broken stage rule does (`hw` [`OnBroken`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Broken {
    #[default]
    Reject,
    AsNone,
}

/// One stage: its program and, for the programs that read one, its texture.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StageConfig {
    pub program: Program,
    #[serde(default)]
    pub texture: Option<StageTexture>,
}

/// A stage's texture: a source of the engine's texture memory stored in `texel` words, and
/// the stage's sampler.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StageTexture {
    pub source: TextureSource,
    pub texel: Encoding,
    #[serde(default)]
    pub filter: Filter,
    #[serde(default = "weight_bits")]
    pub weight_bits: u32,
    #[serde(default)]
    pub address: Address,
    /// The texel type the application uploads (OpenGL's `type` of `glTexImage2D`), when it
    /// is not `texel` itself: bit-accurate mode reads the `texel` codes of values first
    /// rounded to `upload` (e.g. GL_BYTE, `(format: (signed: true, width: 8, frac: 0),
    /// codec: UnitSymmetric)`, into a SIGNED_HILO16 `texel`: Wang et al. Fig. 2a). `None`
    /// (the default): the values are encoded as `texel` directly.
    /// (Left out of the serialised config when `None`, so that the hash of a config
    /// without it is what it was before the field existed.)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub upload: Option<Encoding>,
}

fn dot_frac() -> u32 {
    16
}
fn offset_frac() -> u32 {
    8
}
fn convert_frac() -> Option<u32> {
    ShaderParams::default().convert_frac
}
fn is_nv2a_converter(k: &Option<u32>) -> bool {
    *k == convert_frac()
}
fn weight_bits() -> u32 {
    8
}

/// A stage's texture, named `name`: a cube map's six faces, or the source's texels with
/// their mip levels, through the upload's conversion when it has one.
fn stage_texture(t: &StageTexture, ctx: &BuildCtx, name: &str) -> Result<Texture, String> {
    if t.source.is_cube() {
        return Texture::cube(name, t.texel, cube_faces(&t.source, ctx)?);
    }
    let mut tex = Texture::new(name, t.texel, texels(&t.source, ctx)?)?;
    let mips = mip_levels(&t.source, ctx)?;
    if !mips.is_empty() {
        tex = tex.with_mips(mips)?;
    }
    match &t.upload {
        Some(u) => tex.with_upload(u),
        None => Ok(tex),
    }
}

impl Spec for TextureShaderSpec {
    fn input_names(&self, _: &BuildCtx) -> Vec<String> {
        let mut names: Vec<String> = (0..self.programs.len())
            .map(|i| format!("coord{i}"))
            .collect();
        if self.lod {
            names.push("lod".into());
        }
        names
    }

    fn build(
        &self,
        ins: &BTreeMap<String, PortSpec>,
        ctx: &BuildCtx,
    ) -> Result<Box<dyn Unit>, String> {
        let n = self.programs.len();
        if !(1..=MAX_STAGES).contains(&n) {
            return Err(format!(
                "programs: {n} stages given: expected 1 to {MAX_STAGES}"
            ));
        }
        let coord = input(ins, "coord0")?.enc;
        for i in 1..n {
            let e = input(ins, &format!("coord{i}"))?.enc;
            if e != coord {
                return Err(format!(
                    "coord{i}: {e}: expected the encoding of coord0, {coord} (the part has one coordinate format)"
                ));
            }
        }
        let mut stages = Vec::with_capacity(n);
        for (i, s) in self.programs.iter().enumerate() {
            let Some(t) = &s.texture else {
                stages.push(StageSpec::new(s.program, None));
                continue;
            };
            let mut memory_key = key(&t.source, &t.texel, None);
            if let Some(u) = &t.upload {
                memory_key += &format!(" upload {u:?}");
            }
            let tex = ctx
                .memory
                .get_or_build(&memory_key, &format!("{}.tex{i}", ctx.unit), |name| {
                    stage_texture(t, ctx, name)
                })
                .map_err(|m| format!("programs[{i}].texture: {m}"))?;
            if t.source.per_frame() {
                let t = t.clone();
                let build = move |ctx: &BuildCtx, name: &str| stage_texture(&t, ctx, name);
                ctx.memory.each_frame(&tex, recipe(build));
            }
            let sampler = Sampler::new(t.filter, t.weight_bits)
                .map_err(|m| format!("programs[{i}].texture.weight_bits: {m}"))?
                .with_address(t.address, t.address);
            stages.push(StageSpec::new(s.program, Some(tex)).with_sampler(sampler));
        }
        let lod = if self.lod {
            let l = input(ins, "lod")?;
            if l.lanes != 1 {
                return Err(format!(
                    "lod: {} lanes wired: expected 1 (a level of detail)",
                    l.lanes
                ));
            }
            Some(l.enc)
        } else {
            None
        };
        let params = ShaderParams {
            lod,
            stages: n,
            coord,
            dot_frac: self.dot_frac,
            offset_frac: self.offset_frac,
            convert_frac: self.convert_frac,
            datapath: self.datapath,
            on_broken: match self.on_broken {
                Broken::Reject => OnBroken::Reject,
                Broken::AsNone => OnBroken::AsNone,
            },
            ..ShaderParams::default()
        };
        Ok(Box::new(TextureShader::new(params, stages)?))
    }
}

//! Texture-shader programs as data, and the stage rules of NV_texture_shader.
//!
//! Names follow the extension spec (NV_texture_shader, section 3.8.13 "Texture Shaders": the
//! shader operations of table 3.A, the dot-product mappings of `RGBA_UNSIGNED_DOT_PRODUCT_
//! MAPPING_NV`, the cull modes of `CULL_MODES_NV`, the offset matrix `OFFSET_TEXTURE_2D_
//! MATRIX_NV` with `OFFSET_TEXTURE_2D_SCALE_NV` / `_BIAS_NV`, and the stage consistency rules
//! of "Texture Shader Consistency") and the NV2A's registers (`NV097_SET_SHADER_STAGE_PROGRAM`,
//! `NV097_SET_SHADER_OTHER_STAGE_INPUT`, `NV097_SET_DOT_RGBMAPPING`,
//! `NV097_SET_SHADER_CLIP_PLANE_MODE`, `NV097_SET_TEXTURE_SET_BUMP_ENV_MAT/SCALE/OFFSET`).

use serde::{Deserialize, Serialize};

/// How a dot-product stage reads the previous stage's texel as a vector (NV2A
/// `NV097_SET_DOT_RGBMAPPING`, 3 bits per stage, codes in brackets; `shared/nv2a/README.md`).
/// The 8-bit mappings act on each 8-bit channel code `x` of R, G, B; the HILO mappings on
/// 16-bit codes `hi`, `lo` (the two lanes of a 16-bit HILO texture, or `A<<8|R`, `G<<8|B` of
/// an 8-bit RGBA texel).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub enum DotMapping {
    /// \[0\] x / 255 (NV_texture_shader UNSIGNED_IDENTITY_NV).
    #[default]
    ZeroToOne,
    /// \[1\] (x - 128) / 127 (Direct3D's signed reading).
    Minus1To1D3d,
    /// \[2\] (2x + 1) / 255 - 1 (OpenGL's EXPAND of a packed signed value).
    Minus1To1Gl,
    /// \[3\] x read as two's complement, / 127.
    Minus1To1,
    /// \[4\] (hi / 65535, lo / 65535, 1).
    Hilo1,
    /// \[5\] hi, lo by (c - 32768) / 32767, z = sqrt(max(0, 1 - hi^2 - lo^2)).
    HiloHemisphereD3d,
    /// \[6\] hi, lo by (2c + 1) / 65535 - 1, z as above.
    HiloHemisphereGl,
    /// \[7\] hi, lo two's complement / 32767, z as above (SIGNED_HILO of NV_texture_shader).
    HiloHemisphere,
}

impl DotMapping {
    pub const ALL: [DotMapping; 8] = [
        DotMapping::ZeroToOne,
        DotMapping::Minus1To1D3d,
        DotMapping::Minus1To1Gl,
        DotMapping::Minus1To1,
        DotMapping::Hilo1,
        DotMapping::HiloHemisphereD3d,
        DotMapping::HiloHemisphereGl,
        DotMapping::HiloHemisphere,
    ];
    /// Whether the mapping reads 16-bit HI and LO codes.
    pub fn is_hilo(self) -> bool {
        matches!(
            self,
            DotMapping::Hilo1
                | DotMapping::HiloHemisphereD3d
                | DotMapping::HiloHemisphereGl
                | DotMapping::HiloHemisphere
        )
    }
    /// The NV2A register code (0 to 7).
    pub fn code(self) -> u32 {
        DotMapping::ALL.iter().position(|m| *m == self).unwrap_or(0) as u32
    }
}

/// The D3D6 / NV_texture_shader offset state of an OFFSET_TEXTURE_2D stage: the 2x2 matrix
/// `(a1, a2, a3, a4)` with `s' = s + a1 ds + a3 dt`, `t' = t + a2 ds + a4 dt`, and for the
/// _SCALE program the luminance `clamp(scale * mag + bias, 0, 1)` that multiplies RGB. The
/// lanes of the previous stage's texel that hold `ds`, `dt` and `mag` (the DSDT8_MAG8 order
/// is 0, 1, 2; the NV2A's BUMPENVMAP on A8R8G8B8 reads B and G, lanes 2 and 1).
///
/// `twos_complement`: the NV2A reading (`docs/units/texture-shader.md`, hypothesis 17): the
/// n-bit codes of the `ds`, `dt` lanes are read as two's complement, `c / 2^(n-1)` with
/// `c >= 2^(n-1)` negative, whatever the texture's signedness, so an unsigned A8R8G8B8 or
/// G8B8 map offsets in both directions. A signed texture reads as it is. Off (the default),
/// the lanes are read in the texture's own encoding (NV_texture_shader's DSDT formats).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Offset {
    pub matrix: [f64; 4],
    pub scale: f64,
    pub bias: f64,
    pub lanes: [usize; 3],
    #[serde(default)]
    pub twos_complement: bool,
    /// The _SCALE program's luminance clamped at 0 only, not at 1: the NV2A reading
    /// (`docs/units/texture-shader.md`, hypothesis 20, frame `BumpEnvMapLuminance`: a clamp
    /// at 1 reproduces 53.4 % of its pixels, none 96.9 %); the RGB product saturates at the
    /// texel's largest code. Off (the default), `clamp(scale mag + bias, 0, 1)` as
    /// NV_texture_shader specifies.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub luminance_unclamped: bool,
}

impl Default for Offset {
    fn default() -> Self {
        Offset {
            matrix: [1.0, 0.0, 0.0, 1.0],
            scale: 1.0,
            bias: 0.0,
            lanes: [0, 1, 2],
            twos_complement: false,
            luminance_unclamped: false,
        }
    }
}

/// One stage's shader operation (NV_texture_shader table 3.A). `prev` is the previous
/// texture input stage (`PREVIOUS_TEXTURE_INPUT_NV`, NV2A `SHADER_OTHER_STAGE_INPUT`): an
/// earlier stage whose texel the program reads.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub enum Program {
    /// NONE: result (0, 0, 0, 0).
    #[default]
    None,
    /// TEXTURE_2D: the stage's 2D texture at (s/q, t/q).
    Texture2d,
    /// TEXTURE_CUBE_MAP: the stage's cube map in direction (s, t, r).
    TextureCube,
    /// PASS_THROUGH: (s, t, r, q) clamped to [0, 1] as the colour.
    PassThrough,
    /// CULL_FRAGMENT: the fragment is discarded unless every coordinate passes its test
    /// (`true`: GEQUAL, the coordinate is >= 0; `false`: LESS, it is < 0). Result 0.
    CullFragment { gequal: [bool; 4] },
    /// OFFSET_TEXTURE_2D: the 2D texture at (s, t) offset by the matrix times (ds, dt).
    OffsetTexture2d { prev: usize, offset: Offset },
    /// OFFSET_TEXTURE_2D_SCALE: as above, RGB scaled by clamp(scale mag + bias, 0, 1).
    OffsetTexture2dScale { prev: usize, offset: Offset },
    /// DEPENDENT_AR_TEXTURE_2D: the 2D texture at (alpha, red) of the previous texel.
    DependentAr { prev: usize },
    /// DEPENDENT_GB_TEXTURE_2D: the 2D texture at (green, blue) of the previous texel.
    DependentGb { prev: usize },
    /// DOT_PRODUCT: (s, t, r) . mapped previous texel; result (0, 0, 0, 0).
    DotProduct { prev: usize, mapping: DotMapping },
    /// DOT_PRODUCT_TEXTURE_2D: the 2D texture at (previous stage's dot, this dot).
    DotProductTexture2d { prev: usize, mapping: DotMapping },
    /// DOT_PRODUCT_TEXTURE_CUBE_MAP: the cube map at the three dots of this stage and the
    /// two before it.
    DotProductTextureCube { prev: usize, mapping: DotMapping },
    /// DOT_PRODUCT_REFLECT_CUBE_MAP: the cube map at R = 2 N (N.E) / (N.N) - E, N the three
    /// dots, E the q coordinates of the three stages.
    DotProductReflectCube { prev: usize, mapping: DotMapping },
    /// DOT_PRODUCT_CONST_EYE_REFLECT_CUBE_MAP: as above with a constant eye vector.
    DotProductConstEyeReflectCube {
        prev: usize,
        mapping: DotMapping,
        eye: [f64; 3],
    },
    /// DOT_PRODUCT_DIFFUSE_CUBE_MAP (the middle stage of a reflect group): the cube map at N.
    DotProductDiffuseCube { prev: usize, mapping: DotMapping },
    /// DOT_PRODUCT_DEPTH_REPLACE: depth = previous stage's dot / this dot; result 0.
    DotProductDepthReplace { prev: usize, mapping: DotMapping },
}

/// What a stage's result is, for the consistency rules of later stages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Result_ {
    /// No texel (NONE, CULL_FRAGMENT, DOT_PRODUCT, DEPTH_REPLACE, an inconsistent stage).
    Invalid,
    /// A texel of a texture (its format decides what may read it).
    Texel,
    /// The PASS_THROUGH colour (unsigned RGBA).
    Colour,
}

impl Program {
    /// The spec name of the operation.
    pub fn name(&self) -> &'static str {
        match self {
            Program::None => "NONE",
            Program::Texture2d => "TEXTURE_2D",
            Program::TextureCube => "TEXTURE_CUBE_MAP",
            Program::PassThrough => "PASS_THROUGH",
            Program::CullFragment { .. } => "CULL_FRAGMENT",
            Program::OffsetTexture2d { .. } => "OFFSET_TEXTURE_2D",
            Program::OffsetTexture2dScale { .. } => "OFFSET_TEXTURE_2D_SCALE",
            Program::DependentAr { .. } => "DEPENDENT_AR_TEXTURE_2D",
            Program::DependentGb { .. } => "DEPENDENT_GB_TEXTURE_2D",
            Program::DotProduct { .. } => "DOT_PRODUCT",
            Program::DotProductTexture2d { .. } => "DOT_PRODUCT_TEXTURE_2D",
            Program::DotProductTextureCube { .. } => "DOT_PRODUCT_TEXTURE_CUBE_MAP",
            Program::DotProductReflectCube { .. } => "DOT_PRODUCT_REFLECT_CUBE_MAP",
            Program::DotProductConstEyeReflectCube { .. } => {
                "DOT_PRODUCT_CONST_EYE_REFLECT_CUBE_MAP"
            }
            Program::DotProductDiffuseCube { .. } => "DOT_PRODUCT_DIFFUSE_CUBE_MAP",
            Program::DotProductDepthReplace { .. } => "DOT_PRODUCT_DEPTH_REPLACE",
        }
    }
    /// The previous texture input stage, if the program reads one.
    pub fn prev(&self) -> Option<usize> {
        use Program::*;
        match *self {
            OffsetTexture2d { prev, .. }
            | OffsetTexture2dScale { prev, .. }
            | DependentAr { prev }
            | DependentGb { prev }
            | DotProduct { prev, .. }
            | DotProductTexture2d { prev, .. }
            | DotProductTextureCube { prev, .. }
            | DotProductReflectCube { prev, .. }
            | DotProductConstEyeReflectCube { prev, .. }
            | DotProductDiffuseCube { prev, .. }
            | DotProductDepthReplace { prev, .. } => Some(prev),
            _ => Option::None,
        }
    }
    /// The dot mapping, for the dot-product programs.
    pub fn mapping(&self) -> Option<DotMapping> {
        use Program::*;
        match *self {
            DotProduct { mapping, .. }
            | DotProductTexture2d { mapping, .. }
            | DotProductTextureCube { mapping, .. }
            | DotProductReflectCube { mapping, .. }
            | DotProductConstEyeReflectCube { mapping, .. }
            | DotProductDiffuseCube { mapping, .. }
            | DotProductDepthReplace { mapping, .. } => Some(mapping),
            _ => Option::None,
        }
    }
    /// Whether the stage computes a dot product.
    pub fn is_dot(&self) -> bool {
        self.mapping().is_some()
    }
    /// Whether the program reads the stage's 2D texture (`Some(false)`), its cube map
    /// (`Some(true)`) or none.
    pub fn texture_kind(&self) -> Option<bool> {
        use Program::*;
        match self {
            Texture2d
            | OffsetTexture2d { .. }
            | OffsetTexture2dScale { .. }
            | DependentAr { .. }
            | DependentGb { .. }
            | DotProductTexture2d { .. } => Some(false),
            TextureCube
            | DotProductTextureCube { .. }
            | DotProductReflectCube { .. }
            | DotProductConstEyeReflectCube { .. }
            | DotProductDiffuseCube { .. } => Some(true),
            _ => Option::None,
        }
    }
    /// What the stage's result is when it is consistent.
    pub fn result(&self) -> Result_ {
        match self {
            Program::PassThrough => Result_::Colour,
            p if p.texture_kind().is_some() => Result_::Texel,
            _ => Result_::Invalid,
        }
    }
}

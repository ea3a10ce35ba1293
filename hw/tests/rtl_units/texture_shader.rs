//! Texture-shader units for the RTL tests (`bumpsim_hw::rtl::texture_shader`): one case per
//! program family at the bundled configs' formats and variants of the other parameters.

use super::{fixed, uu, Case};
use bumpsim_hw::rtl;
use bumpsim_hw::units::texture_shader::{
    Datapath, DotMapping, Offset, OnBroken, Program, ShaderParams, StageSpec, TextureShader,
};
use bumpsim_hw::units::{Address, Filter, Texels};
use bumpsim_hw::{Codec, Encoding, Overflow, Quant, Sampler, Texture};
use std::sync::Arc;

/// Pseudo-random texels of `w x h` in the range of `texel` (deterministic from `seed`).
fn texels(seed: u64, w: u32, h: u32, lanes: u8, texel: &Encoding) -> Texels {
    let (lo, hi) = (
        texel.decode(texel.format.min_raw()),
        texel.decode(texel.format.max_raw()),
    );
    let mut x = 0x9e37_79b9_7f4a_7c15u64 ^ seed.wrapping_mul(0x1000_0001);
    let values = (0..w * h)
        .map(|_| {
            std::array::from_fn(|_| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                lo + (hi - lo) * ((x >> 11) as f64 / (1u64 << 53) as f64)
            })
        })
        .collect();
    Texels {
        width: w,
        height: h,
        lanes,
        values,
    }
}

fn tex(seed: u64, (w, h, lanes): (u32, u32, u8), texel: Encoding) -> Option<Arc<Texture>> {
    let t = texels(seed, w, h, lanes, &texel);
    Some(Arc::new(
        Texture::new(&format!("t{seed}"), texel, t).unwrap(),
    ))
}

/// A texture of `levels` mip levels from `w x h` down (each side halved, at least 1).
fn mip_tex(seed: u64, (w, h, lanes): (u32, u32, u8), levels: u32, texel: Encoding) -> Arc<Texture> {
    let t = texels(seed, w, h, lanes, &texel);
    let mips = (1..levels)
        .map(|k| {
            texels(
                seed + k as u64,
                (w >> k).max(1),
                (h >> k).max(1),
                lanes,
                &texel,
            )
        })
        .collect();
    Arc::new(
        Texture::new(&format!("m{seed}"), texel, t)
            .unwrap()
            .with_mips(mips)
            .unwrap(),
    )
}

fn stage(
    program: Program,
    texture: Option<Arc<Texture>>,
    (filter, address): (Filter, Address),
) -> StageSpec {
    StageSpec::new(program, texture).with_sampler(
        Sampler::new(filter, 8)
            .unwrap()
            .with_address(address, address),
    )
}

fn s8() -> Encoding {
    Encoding::texel(Codec::UnitSigned, true, 8)
}

const BW: (Filter, Address) = (Filter::Bilinear, Address::Wrap);
const BC: (Filter, Address) = (Filter::Bilinear, Address::Clamp);
const NC: (Filter, Address) = (Filter::Nearest, Address::Clamp);
const NM: (Filter, Address) = (Filter::Nearest, Address::Mirror);
const BM: (Filter, Address) = (Filter::Bilinear, Address::Mirror);

fn case(name: &'static str, params: ShaderParams, stages: Vec<StageSpec>) -> Case {
    let u = TextureShader::new(params, stages).unwrap();
    let r = rtl::texture_shader::rtl(&u, name).unwrap();
    Case::new(name, u, r)
}

fn offset(matrix: [f64; 4], scale: f64, bias: f64, lanes: [usize; 3]) -> Offset {
    Offset {
        matrix,
        scale,
        bias,
        lanes,
        ..Offset::default()
    }
}

/// One case per program family (and the mappings of the bundled configs and their
/// neighbours).
pub fn cases() -> Vec<Case> {
    cases_with(ShaderParams::default)
}

/// The cases at s16.8 coordinates where they take the default (s32.16): the same programs
/// with an 18-step divider instead of a 34-step one, so that yosys maps each in seconds
/// (the calibration band of `rtl_synth.rs`).
pub fn narrow() -> Vec<Case> {
    cases_with(|| ShaderParams {
        coord: fixed(true, 16, 8),
        datapath: Datapath::Configured,
        ..ShaderParams::default()
    })
}

/// The narrow cases whose synthesis takes under a minute each (the suite's band,
/// `rtl_synth.rs`); the others are checked by the ignored `texture_shaders_slow_cases`
/// (`ts_depth_replace` among them since session 30, for the suite's time: its divider is the
/// projective one that the TEXTURE_2D cases synthesise).
pub const FAST: [&str; 10] = [
    "ts_cube",
    "ts_tex2d_narrow",
    "ts_tex2d_pass",
    "ts_dependent",
    "ts_dot_rgb8",
    "ts_dot_hilo1_wide",
    "ts_offset",
    "ts_offset_scale",
    "ts_offset_nv2a",
    "ts_offset_nv2a_floor",
];

fn cases_with(d: impl Fn() -> ShaderParams + Copy) -> Vec<Case> {
    let u8e = uu(8);
    vec![
        // projective TEXTURE_2D (bilinear, wrap) beside PASS_THROUGH and NONE
        case(
            "ts_tex2d_pass",
            d(),
            vec![
                stage(Program::Texture2d, tex(1, (16, 8, 4), u8e), BW),
                stage(Program::PassThrough, None, BW),
                StageSpec::none(),
            ],
        ),
        // narrow wrapping coordinates (the full divider), a 1-lane 4-bit texture (mirror, nearest), PASS_THROUGH cast
        // without the converter into a 6-bit code
        case(
            "ts_tex2d_narrow",
            ShaderParams {
                stages: 2,
                coord: Encoding {
                    overflow: Overflow::Wrap,
                    ..fixed(true, 12, 8)
                },
                convert_frac: None,
                pass_through: Encoding {
                    quant: Quant::Rnd,
                    ..uu(6)
                },
                ..d()
            },
            vec![
                stage(Program::Texture2d, tex(2, (32, 4, 1), uu(4)), NM),
                stage(Program::PassThrough, None, BW),
            ],
        ),
        // mip levels from the lod input (bilinear clamp, 5 levels of a 32 x 8 texture) and a
        // second TEXTURE_2D stage without mips
        case(
            "ts_tex2d_mip",
            ShaderParams {
                lod: Some(fixed(true, 6, 2)),
                ..d()
            },
            vec![
                stage(Program::Texture2d, Some(mip_tex(3, (32, 8, 3), 6, u8e)), BC),
                stage(Program::Texture2d, Some(mip_tex(4, (8, 8, 4), 4, u8e)), NM),
            ],
        ),
        // DEPENDENT_AR and _GB reading one texel (the NDF path's lookups)
        case(
            "ts_dependent",
            d(),
            vec![
                stage(Program::Texture2d, tex(5, (8, 8, 4), u8e), NC),
                stage(
                    Program::DependentAr { prev: 0 },
                    tex(6, (16, 16, 3), u8e),
                    BM,
                ),
                stage(
                    Program::DependentGb { prev: 0 },
                    tex(7, (32, 16, 2), uu(6)),
                    NC,
                ),
            ],
        ),
        // wang-bunny-rgb8: signed 8-bit normals, MINUS1_TO_1, dot_frac 8
        case(
            "ts_dot_rgb8",
            ShaderParams { dot_frac: 8, ..d() },
            vec![
                stage(Program::Texture2d, tex(8, (16, 16, 3), s8()), BW),
                stage(
                    Program::DotProduct {
                        prev: 0,
                        mapping: DotMapping::Minus1To1,
                    },
                    None,
                    BW,
                ),
                stage(
                    Program::DotProductTexture2d {
                        prev: 0,
                        mapping: DotMapping::Minus1To1,
                    },
                    tex(9, (32, 32, 3), u8e),
                    BC,
                ),
            ],
        ),
        // the NDF hardware path: TEXTURE_2D, DEPENDENT_GB, DOT_PRODUCT and
        // DOT_PRODUCT_TEXTURE_2D with MINUS1_TO_1_GL
        case(
            "ts_dot_ndf",
            d(),
            vec![
                stage(Program::Texture2d, tex(10, (16, 16, 3), u8e), BW),
                stage(
                    Program::DependentGb { prev: 0 },
                    tex(11, (16, 16, 3), u8e),
                    NC,
                ),
                stage(
                    Program::DotProduct {
                        prev: 1,
                        mapping: DotMapping::Minus1To1Gl,
                    },
                    None,
                    BW,
                ),
                stage(
                    Program::DotProductTexture2d {
                        prev: 1,
                        mapping: DotMapping::Minus1To1Gl,
                    },
                    tex(12, (16, 16, 4), u8e),
                    BC,
                ),
            ],
        ),
        // ZERO_TO_ONE and MINUS1_TO_1_D3D on RGBA8, dot_frac 12
        case(
            "ts_dot_d3d",
            ShaderParams {
                dot_frac: 12,
                ..d()
            },
            vec![
                stage(Program::Texture2d, tex(13, (8, 8, 4), u8e), BW),
                stage(
                    Program::DotProduct {
                        prev: 0,
                        mapping: DotMapping::ZeroToOne,
                    },
                    None,
                    BW,
                ),
                stage(
                    Program::DotProductTexture2d {
                        prev: 0,
                        mapping: DotMapping::Minus1To1D3d,
                    },
                    tex(14, (16, 16, 3), u8e),
                    NM,
                ),
            ],
        ),
        // wang-bunny-hilo: a 16-bit signed HILO texture, the SIGNED_HILO hemisphere
        case(
            "ts_dot_hilo",
            d(),
            vec![
                stage(
                    Program::Texture2d,
                    tex(
                        15,
                        (16, 16, 2),
                        Encoding::texel(Codec::UnitSigned, true, 16),
                    ),
                    BW,
                ),
                stage(
                    Program::DotProduct {
                        prev: 0,
                        mapping: DotMapping::HiloHemisphere,
                    },
                    None,
                    BW,
                ),
                stage(
                    Program::DotProductTexture2d {
                        prev: 0,
                        mapping: DotMapping::HiloHemisphere,
                    },
                    tex(16, (32, 32, 3), u8e),
                    BC,
                ),
            ],
        ),
        // HILO from an RGBA8 texel: the D3D and GL hemispheres, dot_frac 10
        case(
            "ts_dot_hilo8",
            ShaderParams {
                dot_frac: 10,
                ..d()
            },
            vec![
                stage(Program::Texture2d, tex(17, (8, 8, 4), u8e), BW),
                stage(
                    Program::DotProduct {
                        prev: 0,
                        mapping: DotMapping::HiloHemisphereD3d,
                    },
                    None,
                    BW,
                ),
                stage(
                    Program::DotProductTexture2d {
                        prev: 0,
                        mapping: DotMapping::HiloHemisphereGl,
                    },
                    tex(18, (16, 16, 4), u8e),
                    BW,
                ),
            ],
        ),
        // HILO_1 of a signed RGBA8 texel, 16-bit HILO with unsigned HI / LO (HILO_1) and
        // texels of 12 bits read by value (MINUS1_TO_1_GL), 3 lanes
        case(
            "ts_dot_hilo1_wide",
            d(),
            vec![
                stage(Program::Texture2d, tex(19, (8, 8, 4), s8()), NC),
                stage(
                    Program::DotProduct {
                        prev: 0,
                        mapping: DotMapping::Hilo1,
                    },
                    None,
                    BW,
                ),
                stage(
                    Program::DotProductTexture2d {
                        prev: 0,
                        mapping: DotMapping::Hilo1,
                    },
                    tex(20, (16, 16, 1), u8e),
                    BC,
                ),
                stage(Program::Texture2d, tex(21, (8, 8, 3), uu(12)), BW),
            ],
        ),
        case(
            "ts_dot_wide",
            ShaderParams {
                dot_frac: 14,
                ..d()
            },
            vec![
                stage(Program::Texture2d, tex(22, (8, 8, 3), uu(12)), BW),
                stage(
                    Program::DotProduct {
                        prev: 0,
                        mapping: DotMapping::Minus1To1Gl,
                    },
                    None,
                    BW,
                ),
                stage(
                    Program::DotProductTexture2d {
                        prev: 0,
                        mapping: DotMapping::ZeroToOne,
                    },
                    tex(23, (16, 16, 3), u8e),
                    BC,
                ),
                stage(
                    Program::Texture2d,
                    tex(
                        24,
                        (4, 4, 4),
                        Encoding::texel(Codec::UnitSymmetric, true, 6),
                    ),
                    BW,
                ),
            ],
        ),
        // d3d6-embm-quad: a DSDT (signed 8-bit) map, OFFSET_TEXTURE_2D with a full matrix
        case(
            "ts_offset",
            d(),
            vec![
                stage(Program::Texture2d, tex(25, (16, 16, 2), s8()), BW),
                stage(
                    Program::OffsetTexture2d {
                        prev: 0,
                        offset: offset([0.75, -0.25, 0.5, -1.0], 1.0, 0.0, [0, 1, 2]),
                    },
                    tex(26, (32, 32, 3), u8e),
                    BC,
                ),
            ],
        ),
        // d3d6-embm-luminance-quad: OFFSET_TEXTURE_2D_SCALE, the clamped luminance
        case(
            "ts_offset_scale",
            ShaderParams {
                offset_frac: 6,
                ..d()
            },
            vec![
                stage(Program::Texture2d, tex(27, (16, 16, 3), s8()), BW),
                stage(
                    Program::OffsetTexture2dScale {
                        prev: 0,
                        offset: offset([-0.5, 0.0, 0.0, -0.5], 0.6, 0.4, [0, 1, 2]),
                    },
                    tex(28, (32, 32, 4), u8e),
                    BW,
                ),
            ],
        ),
        // the NV2A reading: an unsigned RGBA map read as two's complement (lanes B, G,
        // R), the luminance unclamped at 1, through the colour converter
        case(
            "ts_offset_nv2a",
            d(),
            vec![
                stage(Program::Texture2d, tex(29, (16, 16, 4), u8e), NC),
                stage(
                    Program::OffsetTexture2dScale {
                        prev: 0,
                        offset: Offset {
                            twos_complement: true,
                            luminance_unclamped: true,
                            ..offset([0.25, 0.5, -0.125, 1.0], 1.5, -0.25, [2, 1, 0])
                        },
                    },
                    tex(30, (16, 16, 3), u8e),
                    BW,
                ),
            ],
        ),
        // the same without the converter (the floored product), a 6-bit texel
        case(
            "ts_offset_nv2a_floor",
            ShaderParams {
                convert_frac: None,
                offset_frac: 10,
                ..d()
            },
            vec![
                stage(Program::Texture2d, tex(31, (8, 8, 4), u8e), NC),
                stage(
                    Program::OffsetTexture2dScale {
                        prev: 0,
                        offset: Offset {
                            twos_complement: true,
                            luminance_unclamped: true,
                            ..offset([1.0, 0.0, 0.0, 1.0], 2.25, 0.125, [2, 1, 3])
                        },
                    },
                    tex(32, (16, 16, 4), uu(6)),
                    NC,
                ),
            ],
        ),
        // a broken stage (a dependent read in stage 0) runs NONE
        case(
            "ts_broken_as_none",
            ShaderParams {
                on_broken: OnBroken::AsNone,
                ..d()
            },
            vec![
                stage(
                    Program::DependentGb { prev: 0 },
                    tex(33, (4, 4, 3), u8e),
                    NC,
                ),
                stage(Program::Texture2d, tex(34, (4, 4, 3), u8e), BW),
            ],
        ),
        // TEXTURE_CUBE_MAP at the inputs' direction (s, t, r), bilinear, clamped in a face
        case(
            "ts_cube",
            d(),
            vec![stage(Program::TextureCube, cube_map(60, 8), BC)],
        ),
        // DOT_PRODUCT_TEXTURE_CUBE_MAP: the three dots of an RGBA8 normal as the direction
        case("ts_dot_cube", d(), dot_cube(None)),
        // DOT_PRODUCT_REFLECT_CUBE_MAP: the eye from the three stages' q
        case("ts_reflect_cube", d(), dot_cube(Some(None))),
        // DOT_PRODUCT_CONST_EYE_REFLECT_CUBE_MAP, nearest, wrapping in a face
        case(
            "ts_reflect_cube_const_eye",
            d(),
            dot_cube(Some(Some([0.25, -0.5, 0.75]))),
        ),
        // DOT_PRODUCT_DIFFUSE_CUBE_MAP before a reflection: its lookup at the three dots
        case("ts_diffuse_reflect_cube", d(), {
            let mut st = dot_cube(Some(None));
            st[2] = stage(
                Program::DotProductDiffuseCube {
                    prev: 0,
                    mapping: DotMapping::Minus1To1Gl,
                },
                cube_map(80, 4),
                (Filter::Nearest, Address::Clamp),
            );
            st
        }),
        // DOT_PRODUCT_DEPTH_REPLACE: the depth output, the previous dot over this one
        case(
            "ts_depth_replace",
            d(),
            vec![
                stage(Program::Texture2d, tex(72, (8, 8, 4), uu(8)), BW),
                stage(
                    Program::DotProduct {
                        prev: 0,
                        mapping: DotMapping::Minus1To1,
                    },
                    None,
                    BW,
                ),
                stage(
                    Program::DotProductDepthReplace {
                        prev: 0,
                        mapping: DotMapping::Minus1To1,
                    },
                    None,
                    BW,
                ),
            ],
        ),
    ]
}

/// A cube map of `n x n` pseudo-random RGB faces.
fn cube_map(seed: u64, n: u32) -> Option<Arc<Texture>> {
    let f = (0..6).map(|k| texels(seed + k, n, n, 3, &uu(8))).collect();
    Some(Arc::new(Texture::cube("cube", uu(8), f).unwrap()))
}

/// A normal map, two DOT_PRODUCT stages and a cube-map stage reading the three dots:
/// DOT_PRODUCT_TEXTURE_CUBE_MAP (`reflect` None), DOT_PRODUCT_REFLECT_CUBE_MAP
/// (`Some(None)`) or its constant-eye form.
fn dot_cube(reflect: Option<Option<[f64; 3]>>) -> Vec<StageSpec> {
    let mapping = DotMapping::Minus1To1Gl;
    let dot = Program::DotProduct { prev: 0, mapping };
    let (last, look) = match reflect {
        None => (Program::DotProductTextureCube { prev: 0, mapping }, BC),
        Some(None) => (Program::DotProductReflectCube { prev: 0, mapping }, BC),
        Some(Some(eye)) => (
            Program::DotProductConstEyeReflectCube {
                prev: 0,
                mapping,
                eye,
            },
            (Filter::Nearest, Address::Wrap),
        ),
    };
    vec![
        stage(Program::Texture2d, tex(70, (8, 8, 4), uu(8)), BW),
        stage(dot, None, BW),
        stage(dot, None, BW),
        stage(last, cube_map(71, 4), look),
    ]
}

/// CULL_FRAGMENT in two stages (every mode) and a PASS_THROUGH stage; `live` is checked by
/// the test as an extra output lane.
pub fn cull() -> Case {
    case(
        "ts_cull",
        ShaderParams::default(),
        vec![
            stage(
                Program::CullFragment {
                    gequal: [true, false, true, true],
                },
                None,
                BW,
            ),
            stage(Program::PassThrough, None, BW),
            stage(
                Program::CullFragment {
                    gequal: [true, true, false, true],
                },
                None,
                BW,
            ),
        ],
    )
}

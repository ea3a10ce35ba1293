use super::mapping::*;
use super::*;
use crate::sampler::{Address, Filter, Sampler};
use crate::texture::Texels;
use crate::unit::Sample;
use proptest::prelude::*;

const U8: Encoding = Encoding::texel(Codec::UnitUnsigned, false, 8);
const S8: Encoding = Encoding::texel(Codec::UnitSigned, true, 8);

fn coord_enc() -> Encoding {
    ShaderParams::default().coord
}

fn tex2d(
    name: &str,
    enc: Encoding,
    w: u32,
    h: u32,
    f: impl Fn(u32, u32) -> [f64; 4],
) -> Arc<Texture> {
    let values = (0..w * h).map(|k| f(k % w, k / w)).collect();
    Arc::new(
        Texture::new(
            name,
            enc,
            Texels {
                width: w,
                height: h,
                lanes: 4,
                values,
            },
        )
        .unwrap(),
    )
}

fn cube(name: &str) -> Arc<Texture> {
    let faces = (0..6)
        .map(|f| Texels {
            width: 4,
            height: 4,
            lanes: 4,
            values: (0..16)
                .map(|k| {
                    [
                        f as f64 / 5.0,
                        (k % 4) as f64 / 3.0,
                        (k / 4) as f64 / 3.0,
                        1.0,
                    ]
                })
                .collect(),
        })
        .collect();
    Arc::new(Texture::cube(name, U8, faces).unwrap())
}

fn coords(mode: Mode, cs: &[[f64; 4]]) -> Vec<Word> {
    cs.iter()
        .map(|c| Word::for_mode(mode, &coord_enc(), c))
        .collect()
}

fn eval(u: &TextureShader, mode: Mode, ins: &[Word]) -> Vec<Word> {
    let mut o = vec![Word::default(); u.outputs().len()];
    u.eval(mode, ins, &mut o);
    o
}

fn nearest() -> Sampler {
    Sampler::new(Filter::Nearest, 8).unwrap()
}

#[test]
fn every_8_bit_code_maps_by_the_nv2a_formulas_in_both_modes() {
    for m in [
        DotMapping::ZeroToOne,
        DotMapping::Minus1To1D3d,
        DotMapping::Minus1To1Gl,
        DotMapping::Minus1To1,
    ] {
        for x in 0..=255i64 {
            let want = match m {
                DotMapping::ZeroToOne => x as f64 / 255.0,
                DotMapping::Minus1To1D3d => (x as f64 - 128.0) / 127.0,
                DotMapping::Minus1To1Gl => (2 * x + 1) as f64 / 255.0 - 1.0,
                _ => (x as i8) as f64 / 127.0,
            };
            let e = map8_exact(m, x as f64);
            assert!((e - want).abs() < 1e-12, "{m:?} {x}");
            for frac in [8u32, 9, 12, 16, 24] {
                let b = map8_bits(m, x, frac) as f64 / (1u64 << frac) as f64;
                assert!(
                    (b - want).abs() <= 0.5 / (1u64 << frac) as f64 + 1e-15,
                    "{m:?} {x} frac {frac}: {b} vs {want}"
                );
            }
        }
    }
    // landmarks: D3D 128 -> 0, 255 -> 1, 1 -> -1; GL 0 -> -1 + 1/255; two's complement 127 -> 1
    assert_eq!(map8_bits(DotMapping::Minus1To1D3d, 128, 16), 0);
    assert_eq!(map8_bits(DotMapping::Minus1To1D3d, 255, 16), 65536);
    assert_eq!(map8_bits(DotMapping::Minus1To1D3d, 1, 16), -65536);
    assert_eq!(map8_bits(DotMapping::Minus1To1, 127, 16), 65536);
    assert_eq!(map8_bits(DotMapping::Minus1To1, 0x81, 16), -65536);
}

#[test]
fn every_16_bit_hi_code_maps_and_the_hemisphere_z_is_the_floor_root() {
    for m in [
        DotMapping::Hilo1,
        DotMapping::HiloHemisphereD3d,
        DotMapping::HiloHemisphereGl,
        DotMapping::HiloHemisphere,
    ] {
        for c in (0..=65535i64).step_by(7).chain([0, 32767, 32768, 65535]) {
            let want = match m {
                DotMapping::Hilo1 => c as f64 / 65535.0,
                DotMapping::HiloHemisphereD3d => (c as f64 - 32768.0) / 32767.0,
                DotMapping::HiloHemisphereGl => (2 * c + 1) as f64 / 65535.0 - 1.0,
                _ => (c as i16) as f64 / 32767.0,
            };
            assert!((map16_exact(m, c as f64) - want).abs() < 1e-12);
            let b = map16_bits(m, c, 16) as f64 / 65536.0;
            assert!((b - want).abs() <= 0.5 / 65536.0 + 1e-15, "{m:?} {c}");
        }
        for (hi, lo) in [(0i64, 0i64), (0x4000, 0x2000), (0xc000, 0x8001), (32767, 0)] {
            let e = hilo_exact(m, hi as f64, lo as f64);
            let b = hilo_bits(m, hi, lo, 16).map(|v| v as f64 / 65536.0);
            for k in 0..3 {
                // z: the floor root of the rounded words, within 2^-16 plus the error
                // the rounding of hi, lo carries into sqrt (at most 2^-8 near z = 0)
                let bound = if k == 2 { 1.0 / 256.0 } else { 0.5 / 65536.0 };
                assert!((e[k] - b[k]).abs() <= bound + 1e-12, "{m:?} {hi} {lo} {k}");
            }
        }
    }
    assert_eq!(hilo_bits(DotMapping::Hilo1, 5, 7, 12)[2], 4096);
    assert_eq!(isqrt(99), 9);
    assert_eq!(isqrt(100), 10);
}

#[test]
fn a_signed_lane_reads_the_same_vector_in_both_modes_up_to_full_scale() {
    // Exact mode reads a signed lane's value as its real code; bit-accurate mode reads the
    // encoder's code. On every code and at +-1.0 (which the encoder saturates to the largest
    // code) the two agree; before the saturation, exact mode read 1.0 as the code 2^(n-1),
    // i.e. as -1.
    let s16 = Encoding::texel(Codec::UnitSigned, true, 16);
    for (enc, m, lanes) in [
        (S8, DotMapping::Minus1To1, 4u8),
        (s16, DotMapping::HiloHemisphere, 2u8),
    ] {
        let n = enc.width() as i32;
        let half = 1i64 << (n - 1);
        let values = (-half..half)
            .step_by(if n == 8 { 1 } else { 37 })
            .map(|c| c as f64 / half as f64)
            .chain([1.0, -1.0, 0.99999, -0.99999]);
        for v in values {
            let xs = [v, 0.0, 0.0, 0.0];
            let e = vector_exact(m, &xs, &enc, lanes);
            let raws = xs.map(|x| enc.encode(x));
            let b = vector_bits(m, &raws, &enc, lanes, 16).map(|w| w as f64 / 65536.0);
            // the real code and the rounded code differ by at most half a code
            let bound = 0.5 / (half - 1) as f64 + 0.5 / 65536.0 + 1e-12;
            assert!(
                (e[0] - b[0]).abs() <= bound,
                "{m:?} {v}: {} vs {}",
                e[0],
                b[0]
            );
            assert!(
                b[0] == 0.0 || e[0].signum() == b[0].signum(),
                "{m:?} {v}: sign"
            );
        }
        let one = vector_exact(m, &[1.0, -1.0, 0.0, 0.0], &enc, lanes);
        assert!((one[0] - 1.0).abs() < 1e-12, "{m:?}: 1.0 reads {}", one[0]);
        assert!(one[1] < -1.0 + 1e-12, "{m:?}: -1.0 reads {}", one[1]);
    }
}

#[test]
fn pass_through_and_texture_2d_read_the_coordinates_and_texels() {
    let t = tex2d("grad", U8, 4, 4, |x, y| {
        [x as f64 / 3.0, y as f64 / 3.0, 0.0, 1.0]
    });
    let u = TextureShader::new(
        ShaderParams::default(),
        vec![
            StageSpec::new(Program::PassThrough, None),
            StageSpec::new(Program::Texture2d, Some(t)).with_sampler(nearest()),
        ],
    )
    .unwrap();
    for mode in [Mode::Exact, Mode::BitAccurate] {
        // texel (2, 1) at (s, t) = (0.6, 0.3) with q = 1; projective: (1.2, 0.6) / 2
        let ins = coords(
            mode,
            &[
                [0.5, -0.25, 1.5, 0.25],
                [1.2, 0.6, 0.0, 2.0],
                [0.0; 4],
                [0.0; 4],
            ],
        );
        let o = eval(&u, mode, &ins);
        assert_eq!(o[0].raws::<4>(), [127, 0, 255, 63], "{mode:?}"); // truncated codes
        assert_eq!(o[1].raws::<4>(), [170, 85, 0, 255], "{mode:?}");
        assert!(u.live(mode, &ins, &o));
    }
    assert!(!u.can_kill());
}

/// The colour converter at every s16.16 coordinate word of [0, 1] (65,537 words): the code is
/// constant on each 2^-12 step of the coordinate, it is `floor((v + 2^-12) 255)` at the
/// step's foot `v` (the top of the step read exactly, dyadic in f64), within one code of
/// exact mode's, and monotone; without the converter it is `floor(v 255)`. The `Passthru`
/// frame settles the NV2A's 12 bits (hypothesis 5).
#[test]
fn the_colour_converter_reads_the_top_of_each_twelve_bit_step() {
    let part = |convert_frac| {
        let p = ShaderParams {
            convert_frac,
            ..ShaderParams::default()
        };
        TextureShader::new(p, vec![StageSpec::new(Program::PassThrough, None)]).unwrap()
    };
    let (nv2a, plain) = (part(Some(12)), part(None));
    let enc = ShaderParams::default().coord;
    let code = |u: &TextureShader, raw: i64| {
        let w = Word::from_raw(&enc, &[raw, 0, 0, 0]);
        eval(u, Mode::BitAccurate, &[w; 4])[0].lanes[0].raw
    };
    let mut last = 0;
    for raw in 0..=65536i64 {
        let v = raw as f64 / 65536.0;
        let foot = (raw >> 4) as f64 / 4096.0;
        let c = code(&nv2a, raw);
        assert_eq!(
            c,
            (((foot + 1.0 / 4096.0) * 255.0).floor() as i64).min(255),
            "{raw}"
        );
        assert!(
            c >= last && (c as f64 / 255.0 - v).abs() <= 1.0 / 255.0,
            "{raw}: {c}"
        );
        assert_eq!(code(&plain, raw), (v * 255.0).floor() as i64, "{raw}");
        last = c;
    }
    assert_eq!((code(&nv2a, 0), code(&nv2a, 65536), last), (0, 255, 255));
    let bad = ShaderParams {
        convert_frac: Some(25),
        ..ShaderParams::default()
    };
    match TextureShader::new(bad, vec![]) {
        Err(e) => assert!(e.contains("convert_frac: 25"), "{e}"),
        Ok(_) => panic!("convert_frac 25 accepted"),
    }
}

/// With a `lod` input a TEXTURE_2D stage reads the mip level `clamp(floor(lod + 1/2), 0,
/// levels - 1)`, the same in both modes at every code of a 4.4 level of detail (each level of
/// the 8x8 chain holds its level number); a DEPENDENT_GB stage reads level 0.
#[test]
fn texture_2d_reads_the_mip_level_the_lod_selects() {
    let lod = Encoding::fixed(Format::u(8, 4));
    let level = |k: u32| Texels {
        width: 8 >> k,
        height: 8 >> k,
        lanes: 4,
        values: vec![[f64::from(k) / 3.0, 0.5, 0.25, 1.0]; (64 >> (2 * k)) as usize],
    };
    let chain = |name: &str| {
        Arc::new(
            Texture::new(name, U8, level(0))
                .unwrap()
                .with_mips((1..4).map(level).collect())
                .unwrap(),
        )
    };
    let u = TextureShader::new(
        ShaderParams {
            lod: Some(lod),
            ..ShaderParams::default()
        },
        vec![
            StageSpec::new(Program::Texture2d, Some(chain("noise"))).with_sampler(nearest()),
            StageSpec::new(Program::DependentGb { prev: 0 }, Some(chain("l")))
                .with_sampler(nearest()),
        ],
    )
    .unwrap();
    assert_eq!(u.inputs().len(), 5);
    assert_eq!(u.inputs()[4].name, "lod");
    for code in 0..256i64 {
        let x = code as f64 / 16.0;
        let want = ((x + 0.5).floor() as i64).clamp(0, 3);
        for mode in [Mode::Exact, Mode::BitAccurate] {
            let mut ins = coords(mode, &[[0.3, 0.6, 0.0, 1.0]; 4]);
            ins.push(Word::for_mode(mode, &lod, &[x]));
            let o = eval(&u, mode, &ins);
            assert_eq!(
                o[0].raws::<4>()[0],
                (want * 255 + 1) / 3,
                "lod {x} {mode:?}"
            );
            assert_eq!(o[1].raws::<4>()[0], 0, "dependent stage, lod {x} {mode:?}");
        }
    }
    let bad = ShaderParams {
        lod: Some(S8),
        ..ShaderParams::default()
    };
    let e = TextureShader::new(bad, vec![]).err().unwrap();
    assert!(e.starts_with("lod:"), "{e}");
}

#[test]
fn cull_fragment_kills_by_the_sign_of_each_coordinate() {
    for gequal in [[true; 4], [false, true, false, true]] {
        let u = TextureShader::new(
            ShaderParams::default(),
            vec![StageSpec::new(Program::CullFragment { gequal }, None)],
        )
        .unwrap();
        assert!(u.can_kill());
        for c in [
            [0.0, 1.0, 2.0, 0.0],
            [-0.5, 1.0, -1.0, 3.0],
            [0.1, -0.1, 0.0, 0.0],
        ] {
            let want = (0..4).all(|k| (c[k] >= 0.0) == gequal[k]);
            for mode in [Mode::Exact, Mode::BitAccurate] {
                let ins = coords(mode, &[c, [0.0; 4], [0.0; 4], [0.0; 4]]);
                let o = eval(&u, mode, &ins);
                assert_eq!(u.live(mode, &ins, &o), want, "{gequal:?} {c:?} {mode:?}");
            }
        }
    }
}

#[test]
fn offset_dependent_and_dot_programs_agree_between_modes() {
    let dsdt = tex2d("dsdt", S8, 4, 4, |x, y| {
        [x as f64 / 8.0 - 0.25, y as f64 / 8.0, 0.5, 0.0]
    });
    let env = tex2d("env", U8, 16, 16, |x, y| {
        [x as f64 / 15.0, y as f64 / 15.0, 0.5, 1.0]
    });
    let normals = tex2d("n", U8, 4, 4, |x, y| {
        [x as f64 / 3.0, y as f64 / 3.0, 0.9, 0.8]
    });
    let offset = Offset {
        matrix: [0.5, 0.25, -0.25, 0.75],
        scale: 0.5,
        bias: 0.25,
        lanes: [0, 1, 2],
        twos_complement: false,
        luminance_unclamped: false,
    };
    let programs: Vec<Vec<StageSpec>> = vec![
        vec![
            StageSpec::new(Program::Texture2d, Some(dsdt.clone())).with_sampler(nearest()),
            StageSpec::new(
                Program::OffsetTexture2dScale { prev: 0, offset },
                Some(env.clone()),
            )
            .with_sampler(nearest()),
        ],
        vec![
            StageSpec::new(Program::Texture2d, Some(normals.clone())).with_sampler(nearest()),
            StageSpec::new(Program::DependentGb { prev: 0 }, Some(env.clone()))
                .with_sampler(nearest()),
        ],
        vec![
            StageSpec::new(Program::Texture2d, Some(normals.clone())).with_sampler(nearest()),
            StageSpec::new(
                Program::DotProduct {
                    prev: 0,
                    mapping: DotMapping::Minus1To1D3d,
                },
                None,
            ),
            StageSpec::new(
                Program::DotProductTexture2d {
                    prev: 0,
                    mapping: DotMapping::Minus1To1D3d,
                },
                Some(env.clone()),
            )
            .with_sampler(nearest()),
        ],
        vec![
            StageSpec::new(Program::Texture2d, Some(normals.clone())).with_sampler(nearest()),
            StageSpec::new(
                Program::DotProduct {
                    prev: 0,
                    mapping: DotMapping::Minus1To1Gl,
                },
                None,
            ),
            StageSpec::new(
                Program::DotProductDiffuseCube {
                    prev: 0,
                    mapping: DotMapping::Minus1To1Gl,
                },
                Some(cube("d")),
            )
            .with_sampler(nearest()),
            StageSpec::new(
                Program::DotProductReflectCube {
                    prev: 0,
                    mapping: DotMapping::Minus1To1Gl,
                },
                Some(cube("s")),
            )
            .with_sampler(nearest()),
        ],
    ];
    for (k, p) in programs.into_iter().enumerate() {
        let u = TextureShader::new(ShaderParams::default(), p).unwrap();
        assert!(u.broken().is_empty());
        let c = [
            [0.3, 0.6, 0.0, 1.0],
            [0.41, 0.27, 0.5, 0.3],
            [0.2, 0.35, 0.6, -0.7],
            [0.15, 0.5, 0.3, 0.4],
        ];
        let e = eval(&u, Mode::Exact, &coords(Mode::Exact, &c));
        let b = eval(&u, Mode::BitAccurate, &coords(Mode::BitAccurate, &c));
        for s in 0..4 {
            for l in 0..4 {
                // away from texel edges the two modes read the same texel: within one code
                assert!(
                    (e[s].lanes[l].x - b[s].lanes[l].x).abs() <= 1.0 / 255.0 + 1e-9,
                    "program {k} stage {s} lane {l}: {e:?} vs {b:?}"
                );
            }
        }
    }
}

#[test]
fn broken_rules_are_errors_or_run_as_none() {
    let t2 = tex2d("t", U8, 4, 4, |_, _| [0.5; 4]);
    let dot = |prev| Program::DotProduct {
        prev,
        mapping: DotMapping::ZeroToOne,
    };
    let cases: Vec<(Vec<StageSpec>, &str)> = vec![
        (vec![StageSpec::new(dot(0), None)], "not allowed in stage 0"),
        (
            vec![StageSpec::new(Program::Texture2d, None)],
            "needs a texture",
        ),
        (
            vec![StageSpec::new(Program::TextureCube, Some(t2.clone()))],
            "reads a cube map",
        ),
        (
            vec![StageSpec::new(Program::Texture2d, Some(cube("c")))],
            "reads a 2D texture",
        ),
        (
            vec![StageSpec::none(), StageSpec::new(dot(0), None)],
            "result is invalid",
        ),
        (
            vec![
                StageSpec::new(Program::Texture2d, Some(t2.clone())),
                StageSpec::new(dot(1), None),
            ],
            "expected an earlier stage",
        ),
        (
            vec![
                StageSpec::new(Program::Texture2d, Some(t2.clone())),
                StageSpec::new(
                    Program::DotProductTexture2d {
                        prev: 0,
                        mapping: DotMapping::ZeroToOne,
                    },
                    Some(t2.clone()),
                ),
            ],
            "needs 2 stages",
        ),
        (
            vec![
                StageSpec::new(Program::Texture2d, Some(t2.clone())),
                StageSpec::new(
                    Program::OffsetTexture2d {
                        prev: 0,
                        offset: Offset::default(),
                    },
                    Some(t2.clone()),
                ),
            ],
            "signed DS, DT",
        ),
        (
            vec![
                StageSpec::new(Program::Texture2d, Some(t2.clone())),
                StageSpec::new(dot(0), None),
                StageSpec::new(
                    Program::DotProductDiffuseCube {
                        prev: 0,
                        mapping: DotMapping::ZeroToOne,
                    },
                    Some(cube("c")),
                ),
            ],
            "DOT_PRODUCT_REFLECT_CUBE_MAP",
        ),
    ];
    for (stages, rule) in cases {
        let e = TextureShader::new(ShaderParams::default(), stages.clone())
            .err()
            .unwrap_or_default();
        assert!(e.contains(rule), "{e} lacks {rule}");
        assert!(e.starts_with("stage "), "{e}");
        let lax = ShaderParams {
            on_broken: OnBroken::AsNone,
            ..ShaderParams::default()
        };
        let u = TextureShader::new(lax, stages).unwrap();
        let b = u.broken();
        assert!(!b.is_empty() && b[0].1.contains(rule), "{b:?}");
        // a broken stage produces 0
        let o = eval(
            &u,
            Mode::BitAccurate,
            &coords(Mode::BitAccurate, &[[0.5; 4]; 4]),
        );
        assert_eq!(o[b[0].0].raws::<4>(), [0; 4]);
    }
    // a dependent of a broken stage is broken too
    let lax = ShaderParams {
        on_broken: OnBroken::AsNone,
        ..ShaderParams::default()
    };
    let u = TextureShader::new(
        lax,
        vec![
            StageSpec::new(Program::Texture2d, None),
            StageSpec::new(dot(0), None),
        ],
    )
    .unwrap();
    assert_eq!(u.broken().len(), 2);
}

#[test]
fn bad_parameters_are_errors_naming_the_field() {
    let p = ShaderParams::default();
    let bad = [
        (ShaderParams { stages: 0, ..p }, "stages"),
        (ShaderParams { stages: 9, ..p }, "stages"),
        (ShaderParams { dot_frac: 0, ..p }, "dot_frac"),
        (ShaderParams { dot_frac: 25, ..p }, "dot_frac"),
        (
            ShaderParams {
                offset_frac: 17,
                ..p
            },
            "offset_frac",
        ),
        (
            ShaderParams {
                coord: Encoding::fixed(Format::u(16, 8)),
                ..p
            },
            "coord",
        ),
    ];
    for (q, field) in bad {
        let e = TextureShader::new(q, vec![]).err().unwrap_or_default();
        assert!(e.starts_with(field), "{e}");
    }
    let five = vec![StageSpec::none(); 5];
    assert!(TextureShader::new(p, five.clone())
        .err()
        .unwrap_or_default()
        .contains("the part has 4"));
    let u = TextureShader::new(ShaderParams { stages: 5, ..p }, five).unwrap();
    assert_eq!((u.inputs().len(), u.outputs().len()), (5, 6));
    let nan = Offset {
        matrix: [f64::NAN, 0.0, 0.0, 1.0],
        ..Offset::default()
    };
    let s8 = tex2d("s", S8, 4, 4, |_, _| [0.0; 4]);
    let e = TextureShader::new(
        p,
        vec![
            StageSpec::new(Program::Texture2d, Some(s8.clone())),
            StageSpec::new(
                Program::OffsetTexture2d {
                    prev: 0,
                    offset: nan,
                },
                Some(s8),
            ),
        ],
    )
    .err()
    .unwrap_or_default();
    assert!(e.contains("offset.matrix[0]"), "{e}");
}

fn rnd_word(mode: Mode, c: [f64; 4]) -> Word {
    Word::for_mode(mode, &coord_enc(), &c)
}

proptest! {
    /// Dot products of interpolated coordinates with mapped 8-bit texels: bit-accurate within
    /// |s|+|t|+|r| times half an N step plus half a coordinate step of exact (coordinates
    /// are the same words in both modes).
    #[test]
    fn dot_products_agree_within_the_rounding_bound(
        x in 0u8..=255, y in 0u8..=255, z in 0u8..=255,
        s in -4.0f64..4.0, t in -4.0f64..4.0, r in -4.0f64..4.0,
        m in 0usize..8, frac in 8u32..=16,
    ) {
        let mapping = DotMapping::ALL[m];
        let texel = Word::from_raw(&U8, &[x as i64, y as i64, z as i64, 255]);
        let cw = rnd_word(Mode::BitAccurate, [s, t, r, 1.0]);
        let c = cw.xs::<3>();
        let ne = vector_exact(mapping, &texel.xs::<4>(), &U8, 4);
        let nb = vector_bits(mapping, &texel.raws::<4>(), &U8, 4, frac);
        let e: f64 = (0..3).map(|k| c[k] * ne[k]).sum();
        let b: f64 = (0..3).map(|k| c[k] * nb[k] as f64 / (1u64 << frac) as f64).sum();
        let step = 1.0 / (1u64 << frac) as f64;
        // z of a hemisphere mapping: the floor root, within 2^-frac / 2 + sqrt(2^-frac)
        let zb = if mapping.is_hilo() && mapping != DotMapping::Hilo1 { step.sqrt() * 2.0 } else { 0.5 * step };
        let bound = (c[0].abs() + c[1].abs()) * 0.5 * step + c[2].abs() * zb + 1e-9;
        prop_assert!((e - b).abs() <= bound, "{mapping:?}: {e} vs {b} (bound {bound})");
    }

    /// PASS_THROUGH: the bit-accurate colour is the truncated code of the coordinate word
    /// (s16.16): within one code plus one coordinate step of exact mode's.
    #[test]
    fn pass_through_is_within_one_code(s in -0.5f64..1.5, t in 0.0f64..1.0, r in 0.0f64..1.0, q in 0.0f64..1.0) {
        let u = TextureShader::new(ShaderParams::default(), vec![StageSpec::new(Program::PassThrough, None)]).unwrap();
        let e = eval(&u, Mode::Exact, &[rnd_word(Mode::Exact, [s, t, r, q]); 4]);
        let b = eval(&u, Mode::BitAccurate, &[rnd_word(Mode::BitAccurate, [s, t, r, q]); 4]);
        for l in 0..4 {
            prop_assert!((e[0].lanes[l].x - b[0].lanes[l].x).abs() <= 1.0 / 255.0 + 1.0 / 65536.0, "{:?} {:?}", e[0], b[0]);
        }
    }
}

#[test]
fn the_default_part_has_an_itemised_budget_and_shares_its_textures() {
    let t = tex2d("t", U8, 8, 8, |_, _| [0.5; 4]);
    let u = TextureShader::new(
        ShaderParams::default(),
        vec![
            StageSpec::new(Program::Texture2d, Some(t.clone())),
            StageSpec::new(Program::DependentAr { prev: 0 }, Some(t.clone())).with_sampler(
                Sampler::new(Filter::Bilinear, 8)
                    .unwrap()
                    .with_address(Address::Clamp, Address::Clamp),
            ),
        ],
    )
    .unwrap();
    let g = u.gates(&CostTable::default());
    for i in &g.items {
        println!("{:>10.0}  {}", i.ge, i.what);
    }
    println!("{:>10.0}  total", g.total());
    assert!(
        g.total() > 10_000.0 && g.total() < 1_000_000.0,
        "{}",
        g.total()
    );
    let reads = u.textures();
    assert_eq!(reads.len(), 2);
    assert!(Arc::ptr_eq(&reads[0].texture, &reads[1].texture));
    assert_eq!((u.latency(), u.interval()), (7, 1));
    let _ = Sample::default();
}

/// The NV2A's two's-complement reading of BUMPENVMAP offset lanes, every 8-bit code: an
/// unsigned code c is (c - 256 if c >= 128) / 128 in both modes, 0x7F just below 1 and 0x80
/// exactly -1 (hypothesis 17 of the unit page); a signed code reads as its encoding does.
#[test]
fn offset_lanes_read_as_twos_complement_at_every_code() {
    use super::eval::{twos_complement_bits, twos_complement_exact};
    for c in 0..256i64 {
        let want = if c >= 128 { c - 256 } else { c } as f64 / 128.0;
        assert_eq!(
            twos_complement_bits(c, &U8).to_f64(),
            want,
            "bits, code {c}"
        );
        let x = twos_complement_exact(c as f64 / 255.0, &U8);
        assert!((x - want).abs() < 1e-12, "exact, code {c}: {x} vs {want}");
        let s = if c >= 128 { c - 256 } else { c };
        assert_eq!(twos_complement_bits(s, &S8).to_f64(), s as f64 / 128.0);
        assert_eq!(
            twos_complement_exact(s as f64 / 128.0, &S8),
            s as f64 / 128.0
        );
    }
    assert_eq!(twos_complement_bits(0x7f, &U8).to_f64(), 127.0 / 128.0);
    assert_eq!(twos_complement_bits(0x80, &U8).to_f64(), -1.0);
}

/// The configured price (`price.rs`): each stage the datapath of its own program. A NONE part
/// is its sequencer only; a TEXTURE_2D stage adds its two dividers and its fetch; two dot
/// products of one texel with one mapping keep one mapping; HILO_1's constant z needs two
/// products, not three; the configured part is far below the programmable one.
#[test]
fn the_configured_price_has_each_stages_program_only() {
    let t = tex2d("t", U8, 8, 8, |_, _| [0.5; 4]);
    let cfg = ShaderParams {
        datapath: Datapath::Configured,
        ..ShaderParams::default()
    };
    let part = |stages: Vec<StageSpec>| TextureShader::new(cfg, stages).unwrap();
    let ct = CostTable::default();
    let items = |u: &TextureShader, what: &str| {
        u.gates(&ct)
            .items
            .iter()
            .filter(|i| i.what.contains(what))
            .count()
    };
    let none = part(vec![StageSpec::none()]);
    let g = none.gates(&ct);
    assert_eq!(g.items.len(), 1, "{:?}", g.items);
    assert!(g.items[0].what.starts_with("sequencer"));
    let tex = part(vec![StageSpec::new(Program::Texture2d, Some(t.clone()))]);
    assert_eq!(items(&tex, "projective divider"), 1);
    assert!(tex
        .gates(&ct)
        .items
        .iter()
        .any(|i| i.what.contains("u lerp")));
    let dots = |mapping| {
        part(vec![
            StageSpec::new(Program::Texture2d, Some(t.clone())),
            StageSpec::new(Program::DotProduct { prev: 0, mapping }, None),
            StageSpec::new(
                Program::DotProductTexture2d { prev: 0, mapping },
                Some(t.clone()),
            ),
        ])
    };
    let d = dots(DotMapping::Minus1To1Gl);
    assert_eq!(items(&d, "dot mapping"), 1);
    assert_eq!(items(&d, "dot products"), 2);
    let find = |u: &TextureShader, what: &str| {
        u.gates(&ct)
            .items
            .iter()
            .find(|i| i.what.contains(what))
            .map(|i| i.ge)
            .unwrap()
    };
    let (three, two) = (
        find(&d, "dot products"),
        find(&dots(DotMapping::Hilo1), "dot products"),
    );
    // the same 32 x 18 array (MINUS1_TO_1_GL's N and HILO_1's in [-1, 1] at 16 fraction
    // bits): the counts differ
    assert!(two < three, "{two} vs {three}");
    let mut programmable = d.params;
    programmable.datapath = Datapath::Programmable;
    let p = TextureShader::new(
        programmable,
        d.stages.iter().map(|s| s.spec.clone()).collect(),
    )
    .unwrap();
    let (c, pr) = (d.gates(&ct).total(), p.gates(&ct).total());
    assert!(c < pr / 4.0, "configured {c} vs programmable {pr}");
}

/// The programmable price of a part of NONE stages.
fn programmable_part(params: ShaderParams) -> GateBudget {
    let stages = vec![StageSpec::none(); params.stages];
    match TextureShader::new(params, stages) {
        Ok(u) => u.gates(&CostTable::default()),
        Err(e) => panic!("{e}"),
    }
}

/// The programmable price (`programmable.rs`) is built from the configured price's items:
/// per stage it holds at least what any configured program needs. For each program alone in
/// the stages of a part, every configured item kind (dividers, mapping, products,
/// offset, filter) is at most the programmable part's item of that kind; the divider is the
/// same calibrated divider, two per stage.
#[test]
fn the_programmable_price_covers_each_configured_program() {
    let t8 = tex2d("t", U8, 64, 64, |_, _| [0.5; 4]);
    let s8 = tex2d("s", S8, 64, 64, |_, _| [0.1; 4]);
    let hilo = Arc::new(
        Texture::new(
            "h",
            Encoding::texel(Codec::UnitSigned, true, 16),
            Texels {
                width: 64,
                height: 64,
                lanes: 2,
                values: vec![[0.1, -0.2, 0.0, 0.0]; 64 * 64],
            },
        )
        .unwrap(),
    );
    let ct = CostTable::default();
    let kind = |u: &TextureShader, what: &str| -> f64 {
        u.gates(&ct)
            .items
            .iter()
            .filter(|i| i.what.contains(what))
            .map(|i| i.ge)
            .sum()
    };
    // a texel, a dot product and a dot-product lookup of it
    let dots = |tex: &Arc<Texture>, mapping| {
        vec![
            StageSpec::new(Program::Texture2d, Some(tex.clone())),
            StageSpec::new(Program::DotProduct { prev: 0, mapping }, None),
            StageSpec::new(
                Program::DotProductTexture2d { prev: 0, mapping },
                Some(t8.clone()),
            ),
        ]
    };
    let mut parts: Vec<(&str, Vec<StageSpec>)> = vec![
        (
            "tex2d",
            vec![
                StageSpec::new(Program::Texture2d, Some(t8.clone())),
                StageSpec::new(Program::Texture2d, Some(t8.clone())),
            ],
        ),
        ("dot", dots(&t8, DotMapping::Minus1To1Gl)),
        ("hilo", dots(&hilo, DotMapping::HiloHemisphere)),
        (
            "offset",
            vec![
                StageSpec::new(Program::Texture2d, Some(s8.clone())),
                StageSpec::new(
                    Program::OffsetTexture2d {
                        prev: 0,
                        offset: Offset {
                            matrix: [0.5, -0.25, 0.75, -1.0],
                            ..Offset::default()
                        },
                    },
                    Some(t8.clone()),
                ),
            ],
        ),
    ];
    let mapping = DotMapping::Minus1To1Gl;
    parts.push((
        "reflect",
        vec![
            StageSpec::new(Program::Texture2d, Some(t8.clone())),
            StageSpec::new(Program::DotProduct { prev: 0, mapping }, None),
            StageSpec::new(Program::DotProduct { prev: 0, mapping }, None),
            StageSpec::new(
                Program::DotProductReflectCube { prev: 0, mapping },
                Some(cube("c")),
            ),
        ],
    ));
    for (name, stages) in parts {
        let with = |datapath| {
            let params = ShaderParams {
                stages: stages.len(),
                datapath,
                ..ShaderParams::default()
            };
            TextureShader::new(params, stages.clone()).unwrap()
        };
        let (c, p) = (with(Datapath::Configured), with(Datapath::Programmable));
        for what in [
            "projective divider",
            "dot mapping",
            "dot products",
            "offset",
            "lerp multiplier",
            "reflection",
            "cube face",
        ] {
            let (kc, kp) = (kind(&c, what), kind(&p, what));
            assert!(
                kc <= kp,
                "{name}: {what}: configured {kc} > programmable {kp}"
            );
        }
        assert!(c.gates(&ct).total() < p.gates(&ct).total(), "{name}");
    }
    // every coordinate format prices (a coordinate with fewer fraction bits than the largest
    // texture's side addresses a smaller one)
    for (w, f) in [
        (8u8, 0u8),
        (8, 1),
        (12, 6),
        (16, 10),
        (16, 16),
        (32, 31),
        (32, 32),
    ] {
        let params = ShaderParams {
            coord: Encoding::fixed(Format::s(w, f)),
            ..ShaderParams::default()
        };
        let g = programmable_part(params);
        assert!(g.total().is_finite() && g.total() > 0.0, "s{w}.{f}");
    }
    // the same divider: two per stage in the programmable part
    let tex = TextureShader::new(
        ShaderParams {
            stages: 1,
            datapath: Datapath::Configured,
            ..ShaderParams::default()
        },
        vec![StageSpec::new(Program::Texture2d, Some(t8))],
    )
    .unwrap();
    let one = kind(&tex, "projective divider");
    let p = TextureShader::new(
        ShaderParams {
            stages: 1,
            ..ShaderParams::default()
        },
        vec![StageSpec::none()],
    )
    .unwrap();
    assert_eq!(kind(&p, "projective divider"), one);
}

//! Texture-shader programs as config units, end to end: Direct3D 6 environment-mapped bump
//! mapping (`configs/d3d6-embm-quad.ron`, Ernst et al. 1998 §3.3), with luminance
//! (`configs/d3d6-embm-luminance-quad.ron`) and the checks of the `TextureShader` spec.

mod common;

use bumpsim_pipeline::report::Report;
use common::*;

#[test]
fn bump_env_map_follows_the_reference_where_its_one_matrix_fits_the_surface() {
    // measured at the bundled 256 x 256 (algorithm PSNR dB; the test runs 128 x 128): the
    // quad facing the viewer 31.4, without bumps 48.8 (what the lighting map and the
    // near-parallel viewer cost), the same bricks on a sphere 27.7: one offset matrix per
    // draw is right only where the surface's (T, B) is the view's (x, y)
    let quad = config_report("d3d6-embm-quad", &SMALL);
    let mut flat = SMALL.to_vec();
    flat.push("scene.bump=Flat");
    let flat = config_report("d3d6-embm-quad", &flat);
    let mut sphere = SMALL.to_vec();
    sphere.push("scene.mesh=Sphere(radius: 1.0, slices: 64, stacks: 32, uv_repeat: (4.0, 2.0))");
    let sphere = config_report("d3d6-embm-quad", &sphere);
    let a = |r: &Report| r.error.algorithm.psnr_db;
    assert!(a(&quad) > 29.0, "{}", a(&quad));
    assert!(a(&flat) > a(&quad) + 10.0, "{} {}", a(&flat), a(&quad));
    assert!(a(&sphere) < a(&quad) - 2.0, "{} {}", a(&sphere), a(&quad));
    // the bit-accurate offsets and lighting map add little (8-bit texels, s16.16 coordinates)
    assert!(quad.error.quantization.psnr_db > 50.0, "{:?}", quad.error);
    // the matrix that the derivation gives beats its sign flips
    let flipped = config_report(
        "d3d6-embm-quad",
        &[
            SMALL[0],
            SMALL[1],
            "engine.units.shader.unit.programs[1].program.offset.matrix=(0.5, 0.0, 0.0, 0.5)",
        ],
    );
    assert!(a(&flipped) < a(&quad) - 5.0, "{} {}", a(&flipped), a(&quad));
    // two textures in one unit are two textures of the memory, each named after its stage
    let names: Vec<&String> = quad.bandwidth.texture_memory.keys().collect();
    assert_eq!(names, ["shader.tex0", "shader.tex1"]);
}

#[test]
fn bump_env_map_luminance_darkens_the_grooves_and_nothing_else() {
    let plain = config_run("d3d6-embm-quad", &SMALL).image;
    let lum = config_run("d3d6-embm-luminance-quad", &SMALL).image;
    // the same offsets, RGB times l = 0.6 h + 0.4 <= 1: never brighter, as dark as 0.4x
    let (mut sum_p, mut sum_l, mut same, mut darkest) = (0u64, 0u64, 0u64, 1.0f64);
    for (p, l) in plain.pixels().zip(lum.pixels()) {
        for c in 0..3 {
            let (a, b) = (p.0[c], l.0[c]);
            assert!(b <= a, "a channel got brighter: {a} -> {b}");
            sum_p += u64::from(a);
            sum_l += u64::from(b);
            if a >= 64 {
                darkest = darkest.min(f64::from(b) / f64::from(a));
            }
        }
        same += u64::from((0..3).all(|c| p.0[c] - l.0[c] <= 1));
    }
    let ratio = sum_l as f64 / sum_p as f64;
    // measured at 128 x 128: 0.82 of the light overall, 0.40 at the darkest (h = 0)
    assert!((0.7..0.95).contains(&ratio), "{ratio}");
    assert!((0.38..0.45).contains(&darkest), "{darkest}");
    println!("luminance: ratio {ratio:.3}, darkest {darkest:.3}, within 1 code {same}");
    // the brick tops (h = 1, read as 127/128: l = 0.995) and the background keep their colour
    assert!(same > 128 * 128 / 2, "{same}");
    // scale + bias = 1: the NV2A's unclamped luminance changes nothing; with bias 0.8 it
    // brightens past the plain map where scale h + bias > 1
    let path = "engine.units.shader.unit.programs[1].program.offset";
    let unclamped = format!("{path}.luminance_unclamped=true");
    let nv2a = config_run(
        "d3d6-embm-luminance-quad",
        &[SMALL[0], SMALL[1], &unclamped],
    )
    .image;
    assert_eq!(nv2a, lum);
    let bias = format!("{path}.bias=0.8");
    let bright = config_run(
        "d3d6-embm-luminance-quad",
        &[SMALL[0], SMALL[1], &unclamped, &bias],
    )
    .image;
    let clamped = config_run("d3d6-embm-luminance-quad", &[SMALL[0], SMALL[1], &bias]).image;
    let brighter = |x: &image::RgbImage| {
        plain
            .pixels()
            .zip(x.pixels())
            .filter(|(p, q)| (0..3).any(|c| q.0[c] > p.0[c]))
            .count()
    };
    assert_eq!(brighter(&clamped), 0);
    assert!(brighter(&bright) > 1000, "{}", brighter(&bright));
}

#[test]
fn texture_shader_programs_are_checked_with_the_stage_and_the_rule() {
    // stage 1 reads itself: a broken consistency rule, named with its stage
    let e = config_error(
        "d3d6-embm-quad",
        &["engine.units.shader.unit.programs[1].program.prev=1"],
    );
    assert!(e.contains("stage 1"), "{e}");
    // every stage of a part has one coordinate format
    let e = config_error(
        "d3d6-embm-quad",
        &["engine.attributes[1].enc=(format: (signed: true, width: 24, frac: 12))"],
    );
    assert!(e.contains("coord1") && e.contains("coord0"), "{e}");
    // fixed-point texels are not a texture-shader format
    let e = config_error(
        "d3d6-embm-quad",
        &["engine.units.shader.unit.programs[0].texture.texel=(format: (signed: true, width: 8, frac: 6))"],
    );
    assert!(e.contains("stage 0") && e.contains("unit codec"), "{e}");
    // more than 8 stages
    let nine = format!(
        "engine.units.shader.unit.programs=[{}]",
        ["(program: None)"; 9].join(", ")
    );
    let e = config_error("d3d6-embm-quad", &[&nine]);
    assert!(e.contains("programs"), "{e}");
    // unknown keys inside a program's fields are errors
    let e = config_error(
        "d3d6-embm-quad",
        &["engine.units.shader.unit.programs[1].program.offset.skew=1.0"],
    );
    assert!(e.contains("skew"), "{e}");
}

#[test]
fn reflect_cube_map_lights_the_bumps_through_the_world_normal_and_the_eye() {
    // measured at 128 x 128 (algorithm PSNR dB): 32.6 with the bricks, 43.5 without bumps
    // (what the cube maps' Phong lobe for Blinn-Phong and their sampling cost), 28.3 when the
    // reflection takes a constant eye (the camera's direction) instead of each vertex's: the
    // local viewer is worth 4 dB here
    let r = config_report("nv20-reflect-cube", &SMALL);
    let a = |r: &Report| r.error.algorithm.psnr_db;
    assert!(a(&r) > 31.5, "{}", a(&r));
    let mut flat = SMALL.to_vec();
    flat.push("scene.bump=Flat");
    let flat = config_report("nv20-reflect-cube", &flat);
    assert!(
        a(&flat) > 42.0 && a(&flat) > a(&r) + 9.0,
        "{} {}",
        a(&flat),
        a(&r)
    );
    let program = "engine.units.shader.unit.programs[3].program";
    let const_eye = format!(
        "{program}=DotProductConstEyeReflectCube(prev: 0, mapping: Minus1To1, eye: (0.0, 0.24, 0.97))"
    );
    let distant = config_report("nv20-reflect-cube", &[SMALL[0], SMALL[1], &const_eye]);
    assert!(a(&distant) < a(&r) - 3.0, "{} {}", a(&distant), a(&r));
    // s16.12 coordinates and 8-bit texels: the bit-accurate path is near the exact one
    // (51.9 dB, at most 9.8 codes)
    assert!(
        r.error.quantization.psnr_db > 50.0,
        "{:?}",
        r.error.quantization
    );
    assert!(
        r.error.quantization.max_abs_lsb < 12.0,
        "{:?}",
        r.error.quantization
    );
    // a wrapping address takes a direction on a face's edge (s = 1 exactly in bit-accurate
    // mode) to the far side of the face: 25 codes where clamping has 10
    let wrap = config_report(
        "nv20-reflect-cube",
        &[
            SMALL[0],
            SMALL[1],
            "engine.units.shader.unit.programs[3].texture.address=Wrap",
        ],
    );
    assert!(
        wrap.error.quantization.max_abs_lsb > 20.0,
        "{:?}",
        wrap.error.quantization
    );
    // three textures of the memory: the normal map and two cube maps of six faces
    let names: Vec<&String> = r.bandwidth.texture_memory.keys().collect();
    assert_eq!(names, ["shader.tex0", "shader.tex2", "shader.tex3"]);
}

#[test]
fn cube_sources_and_frame_rows_are_checked() {
    let e = config_error("nv20-reflect-cube", &["engine.attributes[1].source.row=3"]);
    assert!(
        e.contains("engine.attributes[1].source.row: TangentRow row 3: expected 0, 1 or 2"),
        "{e}"
    );
    let e = config_error(
        "nv20-reflect-cube",
        &["engine.units.shader.unit.programs[3].texture.source.size=1024"],
    );
    assert!(
        e.contains("size 1024: expected a power of two from 1 to 512 (a cube map's face)"),
        "{e}"
    );
    let e = config_error(
        "sgi-teapot",
        &["engine.units.fetch.unit.source=CubeLighting(size: 8, light: 0, term: Diffuse)"],
    );
    assert!(
        e.contains("a cube map: expected it bound to a texture-shader stage"),
        "{e}"
    );
    let e = config_error(
        "nv20-reflect-cube",
        &["engine.units.shader.unit.programs[2].texture.source.light=1"],
    );
    assert!(e.contains("light 1: the scene has 1 lights"), "{e}");
}

#[test]
fn the_cube_maps_phong_exponent_a_quarter_of_the_shininess_stands_in_for_blinn_phong() {
    // the sphere without bumps (only the lobe and the cube sampling differ from the reference):
    // measured at 128 x 128, algorithm PSNR 26.0 dB at exponent 4, 43.5 at 8 (shininess 32 /
    // 4, the default), 30.2 at 16; the best of a finer scan 45.7 at 8.5
    let psnr = |e: Option<f64>| {
        let mut sets = vec![SMALL[0], SMALL[1], "scene.bump=Flat"];
        let s = e.map(|e| {
            format!(
                "engine.units.shader.unit.programs[3].texture.source=CubeLighting(size: 256, light: 0, term: Specular, exponent: Some({e:?}))"
            )
        });
        if let Some(s) = &s {
            sets.push(s);
        }
        config_report("nv20-reflect-cube", &sets)
            .error
            .algorithm
            .psnr_db
    };
    let (default, quarter) = (psnr(None), psnr(Some(8.0)));
    assert_eq!(default, quarter);
    let (half, double) = (psnr(Some(4.0)), psnr(Some(16.0)));
    assert!(
        quarter > half + 10.0 && quarter > double + 10.0,
        "{half} {quarter} {double}"
    );
    let e = config_error(
        "nv20-reflect-cube",
        &["engine.units.shader.unit.programs[3].texture.source.exponent=Some(0.0)"],
    );
    assert!(
        e.contains("exponent 0: expected a number above 0, at most 10000"),
        "{e}"
    );
}

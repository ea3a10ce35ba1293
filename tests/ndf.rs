//! NDF-based bump map synthesis (Kautz et al. 2001, issue 15): the generated normals follow
//! the NDF (C17), the hardware path's 4-stage program runs and follows the reference, the
//! anisotropic variant is rejected on a 4-stage part with the reason, and bad input is a
//! config error naming the field and the rule.

mod common;

use bumpsim_pipeline::ndf::statistics;
use bumpsim_pipeline::ndf::tables::{binned, fit, histogram};
use bumpsim_pipeline::ndf::{Distribution, NdfSpec, NdfSurface, SynthesisSpec};
use common::*;
use std::path::Path;

fn spec(ndf: NdfSpec) -> SynthesisSpec {
    SynthesisSpec {
        ndf,
        normals: Distribution::Ndf,
        octaves: 4,
        frequency: 16,
        seed: 1,
        map_size: 64,
    }
}

/// Chi-square per degree of freedom and KL divergence (nats) of the normals generated over a
/// grid of 256² texture coordinates against the target NDF integrated over 16² bins of the
/// hemispherical map; `table`: through the lookup table `L` of that size (nearest entry, as
/// the hardware path reads it), else the exact inverse CDFs (the report's `synthesis`
/// figures, `ndf::statistics`).
fn c17(surf: &NdfSurface, table: Option<u32>) -> (f64, f64) {
    let f = statistics::normals_fit(surf, table);
    (f.chi2_dof, f.kl)
}

/// C17: the generated normals follow the NDF for Blinn-Phong, Beckmann and Ward's
/// anisotropic Gaussian, through the exact inverse CDFs and through L at 64 and 256 entries a
/// side; normals distributed uniformly (Fig. 4 right) do not. Measured (256² normals, 16²
/// bins): KL 0.005 to 0.009 nats with the NDF, 10 to 70 uniform; the chi-square per degree
/// of freedom is 8 to 15 with the NDF, not 1, because neighbouring normals of a noise texture
/// are correlated, not independent draws (the tables fed independent numbers give 0.8:
/// `inverse_cdfs_sample_the_map`; `docs/studies/ndf-synthesis.md`).
#[test]
fn generated_normals_follow_the_ndf() {
    let ndfs = [
        NdfSpec::BlinnPhong { exponent: 20.0 },
        NdfSpec::Beckmann { roughness: 0.3 },
        NdfSpec::Ward {
            alpha_x: 0.15,
            alpha_y: 0.5,
        },
    ];
    for ndf in ndfs {
        let s = spec(ndf.clone());
        let mut u = s.clone();
        u.normals = Distribution::Uniform;
        let (surf, usurf) = (build(&s), build(&u));
        let (uchi, ukl) = c17(&usurf, None);
        println!("{ndf:?} uniform: chi2/dof {uchi:.1} KL {ukl:.4}");
        for table in [None, Some(64), Some(256)] {
            let (chi, kl) = c17(&surf, table);
            println!("{ndf:?} table {table:?}: chi2/dof {chi:.2} KL {kl:.5}");
            assert!(kl < 0.02, "{ndf:?} {table:?}: KL {kl}");
            assert!(
                kl * 100.0 < ukl,
                "{ndf:?} {table:?}: KL {kl} vs uniform {ukl}"
            );
            assert!(
                chi * 1000.0 < uchi,
                "{ndf:?} {table:?}: chi2 {chi} vs uniform {uchi}"
            );
        }
    }
}

fn build(s: &SynthesisSpec) -> NdfSurface {
    s.build(Path::new(".")).expect("valid spec")
}

/// The tables alone, fed independent uniform numbers instead of noise, are a sampler of the
/// NDF's map: chi-square per degree of freedom about 1.
#[test]
fn inverse_cdfs_sample_the_map() {
    let s = spec(NdfSpec::Beckmann { roughness: 0.4 });
    let surf = build(&s);
    let mut state = 0x1234_5678_9abc_def0u64;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let normals: Vec<_> = (0..200_000)
        .map(|_| {
            let (a, b) = (next(), next());
            surf.tables.sample(a, b)
        })
        .collect();
    let bins = 16;
    let h = histogram(bins, normals.into_iter());
    // the sampler's own density: the 64 x 64 map, piecewise constant
    let (chi, kl) = fit(&h, &binned(&surf.ndf.map(64, Distribution::Ndf), 64, bins));
    println!("iid: chi2/dof {chi:.3} KL {kl:.6}");
    assert!(chi < 1.5 && kl < 0.002, "chi2/dof {chi} KL {kl}");
}

/// The 4-stage program follows the float reference of the same synthesised surface (at the
/// bundled 256 x 256: algorithm 43.3 dB, quantization 43.2 dB); with the index quantization
/// of the noise texels at 16 bits instead of 8 the quantization error falls.
#[test]
fn hardware_path_follows_the_reference() {
    let r = config_report("ndf-sphere-hw", &SMALL);
    println!("{:?}", r.error);
    assert!(r.error.algorithm.psnr_db > 38.0, "{:?}", r.error);
    assert!(r.error.quantization.psnr_db > 38.0, "{:?}", r.error);
    let mut wide = SMALL.to_vec();
    wide.push(
        "engine.units.shader.unit.programs[0].texture.texel=(format: (signed: false, width: 16, frac: 0), codec: UnitUnsigned)",
    );
    let w = config_report("ndf-sphere-hw", &wide);
    println!("16-bit indices: {:?}", w.error);
    assert!(
        w.error.quantization.psnr_db > r.error.quantization.psnr_db,
        "{:?} vs {:?}",
        w.error,
        r.error
    );
}

/// C16: an anisotropic NDF on the 4-stage program is a config error that says why (exit 2 from
/// the CLI); the 5-stage variant runs.
#[test]
fn anisotropic_ndf_needs_a_fifth_stage() {
    let set = "scene.bump=Ndf(ndf: Ward(alpha_x: 0.1, alpha_y: 0.4), octaves: 4, frequency: 8)";
    let e = config_error("ndf-sphere-hw", &[SMALL[0], SMALL[1], set]);
    assert!(
        e.contains("programs[3].texture") && e.contains("anisotropic") && e.contains("four stages"),
        "{e}"
    );
    let cfg = config("ndf-sphere-hw");
    let o = bumpsim(&["check", cfg.to_str().unwrap(), "--set", set]);
    o.expect_code(2, "anisotropic NDF on 4 stages");
    assert!(o.stderr.contains("anisotropic"), "{}", o.stderr);
    let r = config_report("ndf-teapot-aniso-hw5", &SMALL);
    assert!(r.error.quantization.psnr_db > 30.0, "{:?}", r.error);
    // the reference's microfacet tangent follows the surface's u, as the engines' does (with
    // world x instead, 25.8 dB at 256 x 256)
    println!("5 stages: {:?}", r.error);
    assert!(r.error.algorithm.psnr_db > 34.0, "{:?}", r.error);
}

/// The far level (no octaves left: the flat surface) shaded with the far NDF keeps the bump
/// levels' mean shading, where the plain NDF (§5.1: "we just shade the surface with the NDF")
/// is 1.8 times as bright at the highlight's centre: the mean of a patch of 256² texture
/// coordinates at 4 octaves against the flat surface, Beckmann 0.35.
#[test]
fn far_level_keeps_the_bump_levels_shading() {
    let s = SynthesisSpec {
        frequency: 8,
        map_size: 128,
        ..spec(NdfSpec::Beckmann { roughness: 0.35 })
    };
    let surf = build(&s);
    for deg in [0.0f64, 10.0, 20.0, 30.0] {
        let t = deg.to_radians();
        let near = surf.patch_shading(0, 256, t);
        let far = surf.far_shading(t);
        // the flat level with the plain NDF
        let plain = surf.patch_shading(4, 1, t);
        println!("{deg}°: bumps {near:.4}, far NDF {far:.4}, plain NDF {plain:.4}");
        assert!(
            (far - near).abs() < 0.08 * near,
            "{deg}°: far {far} vs bumps {near}"
        );
        if deg == 0.0 {
            assert!(plain > 1.6 * near, "plain {plain} vs bumps {near}");
        }
    }
}

/// The software path (§5.1): per-fragment turbulence (octaves by LOD), L and its tangent, H
/// projected, the anisotropic NDF; bit-accurate against exact mode 39.3 dB at 256 x 256.
#[test]
fn software_path_runs_in_both_modes() {
    let r = config_report("ndf-teapot-aniso-sw", &SMALL);
    assert!(r.error.quantization.psnr_db > 33.0, "{:?}", r.error);
    assert!(
        r.gates.per_unit.contains_key("noise"),
        "{:?}",
        r.gates.per_unit.keys()
    );
}

/// Bad input names the field and the rule.
#[test]
fn bad_input_is_a_config_error() {
    let cases: [(&str, &str); 6] = [
        (
            "scene.bump=Ndf(ndf: BlinnPhong(exponent: 20.0), octaves: 0, frequency: 8)",
            "bump.Ndf.octaves",
        ),
        (
            "scene.bump=Ndf(ndf: BlinnPhong(exponent: 20.0), octaves: 13, frequency: 8)",
            "bump.Ndf.octaves",
        ),
        (
            "scene.bump=Ndf(ndf: BlinnPhong(exponent: 20.0), octaves: 4, frequency: 8, map_size: 100)",
            "bump.Ndf.map_size",
        ),
        (
            "scene.bump=Ndf(ndf: Beckmann(roughness: -1.0), octaves: 4, frequency: 8)",
            "roughness",
        ),
        (
            "engine.units.shader.unit.programs[1].texture.source=NdfLookup(size: 100, entry: Rgb8)",
            "power of two",
        ),
        (
            "engine.units.shader.unit.programs[1].texture.source=NdfLookup(size: 2048, entry: Rgb8)",
            "NDF table",
        ),
    ];
    for (set, want) in cases {
        let e = config_error("ndf-sphere-hw", &[SMALL[0], SMALL[1], set]);
        assert!(e.contains(want), "{set}: {e}");
    }
    // the software path's noise unit
    let e = config_error(
        "ndf-teapot-aniso-sw",
        &[SMALL[0], SMALL[1], "engine.units.noise.unit.frac=30"],
    );
    assert!(e.contains("frac 30") && e.contains("4 to 24"), "{e}");
    let e = config_error(
        "ndf-teapot-aniso-sw",
        &[
            SMALL[0],
            SMALL[1],
            "engine.units.noise.unit.out=(format: (signed: true, width: 16, frac: 14))",
        ],
    );
    assert!(e.contains("unsigned"), "{e}");
    // unknown keys
    let e = config_error(
        "ndf-sphere-hw",
        &["scene.bump=Ndf(ndf: BlinnPhong(exponent: 20.0), octaves: 4, frequency: 8, bogus: 1)"],
    );
    assert!(e.contains("bogus"), "{e}");
    // NDF images: not a square power of two, all zero
    let dir = std::env::temp_dir().join(format!("bumpsim-ndf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = |name: &str, w: u32, h: u32, v: u8| {
        let p = dir.join(name);
        image::GrayImage::from_pixel(w, h, image::Luma([v]))
            .save(&p)
            .unwrap();
        p
    };
    for (p, want) in [
        (png("oblong.png", 32, 16, 200), "square power of two"),
        (png("zero.png", 32, 32, 0), "not a density"),
    ] {
        let set = format!(
            "scene.bump=Ndf(ndf: Png(path: {:?}), octaves: 4, frequency: 8)",
            p.display().to_string()
        );
        let e = config_error("ndf-sphere-hw", &[SMALL[0], SMALL[1], &set]);
        assert!(
            e.contains("bump.Ndf.ndf.Png.path") && e.contains(want),
            "{e}"
        );
    }
    // a valid PNG NDF (uniform over the disk) builds and runs when declared isotropic
    let p = png("flat.png", 32, 32, 255);
    let set = format!(
        "scene.bump=Ndf(ndf: Png(path: {:?}, isotropic: true), octaves: 4, frequency: 8)",
        p.display().to_string()
    );
    config_report("ndf-sphere-hw", &[SMALL[0], SMALL[1], &set]);
    std::fs::remove_dir_all(&dir).ok();
}

/// A bundled config's bit-accurate image with `--set` overrides.
fn image(stem: &str, sets: &[&str]) -> image::RgbImage {
    config_run(stem, sets).image
}

/// Per-fragment mip levels (§5.2.2's mipmapped noise, `ndf-sphere-hw-mip`): with a level of
/// detail of 0 everywhere the whole chain renders what level 0 alone renders, byte for byte;
/// with the interpolated per-vertex LOD every pixel is the pixel one of the per-draw levels
/// renders (NEAREST_MIPMAP_NEAREST picks one level per fragment), and more than one level
/// shows.
#[test]
fn noise_mip_level_is_selected_per_fragment() {
    let zero = image(
        "ndf-sphere-hw-mip",
        &[
            SMALL[0],
            SMALL[1],
            "engine.attributes[2].source=VertexLod(size: 1)",
        ],
    );
    assert!(zero == image("ndf-sphere-hw", &SMALL), "lod 0: level 0");
    let mip = image("ndf-sphere-hw-mip", &SMALL);
    let levels: Vec<image::RgbImage> = (0..=4)
        .map(|k| {
            let set = format!(
                "engine.units.shader.unit.programs[0].texture.source=NdfNoise(size: 256, level: {k})"
            );
            image("ndf-sphere-hw", &[SMALL[0], SMALL[1], &set])
        })
        .collect();
    // the lod input: wired, and one lane
    let e = config_error(
        "ndf-sphere-hw-mip",
        &[
            r#"engine.units.shader.inputs={"coord0": "uvq", "coord1": "uvq", "coord2": "cat(h0, uvq.q)", "coord3": "uvq.pppp"}"#,
        ],
    );
    assert!(e.contains("\"lod\"") && e.contains("not wired"), "{e}");
    let e = config_error(
        "ndf-sphere-hw-mip",
        &[r#"engine.units.shader.inputs.lod="uvq.st""#],
    );
    assert!(
        e.contains("lod: 2 lanes") && e.contains("expected 1"),
        "{e}"
    );
    let mut used = [0usize; 5];
    for (x, y, p) in mip.enumerate_pixels() {
        let k = levels.iter().position(|l| l.get_pixel(x, y) == p);
        let k = k.unwrap_or_else(|| panic!("pixel ({x}, {y}) {p:?} is no level's"));
        used[k] += 1;
    }
    println!("pixels first matching level 0..4: {used:?}");
    assert!(used.iter().filter(|&&n| n > 100).count() >= 2, "{used:?}");
}

/// The report's `synthesis` section (`reference.synthesis`): the patch shading per level at
/// a 30° half-way vector is the study's (Beckmann 0.35, 8 cells: the closed form 0.1170,
/// levels 0 to 4 0.1865 0.1865 0.1858 0.1809 0.1117, the far NDF 0.1813), the fits are those
/// of the tables (through the exact inverse CDFs and through the engine's 256² `L`, 16² bins),
/// the section is absent without the option, and the option needs an NDF scene and a tilt
/// from 0 to 90 degrees.
#[test]
fn the_report_measures_the_synthesis_tables() {
    let small = ["scene.width=32", "scene.height=32"];
    let with = [
        small[0],
        small[1],
        "reference.synthesis=Some((tilt_deg: 30.0))",
    ];
    let r = config_report("ndf-sphere-hw", &with);
    let y = r.synthesis.expect("the section");
    let near = |a: f64, b: f64| (a - b).abs() < 5e-5;
    assert!(near(y.closed_form, 0.1170), "{}", y.closed_form);
    let want = [0.1865, 0.1865, 0.1858, 0.1809, 0.1117];
    assert_eq!(y.levels.len(), 5);
    for (k, (&got, want)) in y.levels.iter().zip(want).enumerate() {
        assert!(near(got, want), "level {k}: {got} vs {want}");
    }
    assert!(near(y.far, 0.1813), "{}", y.far);
    let l = y.lookup.expect("the engine reads L");
    assert_eq!((y.side, y.bins, l.side), (256, 16, 256));
    // the fits: small and the uniform counter-example far off (the same sweep as the study's
    // C17, docs/studies/sweeps/kautz-fit.ron)
    assert!(y.exact.kl < 0.03 && l.kl < 0.03, "{:?} {l:?}", y.exact);
    let u = config_report(
        "ndf-sphere-hw",
        &[with[0], with[1], with[2], "scene.bump.normals=Uniform"],
    )
    .synthesis
    .unwrap();
    assert!(
        u.exact.kl > 100.0 * y.exact.kl,
        "{:?} vs {:?}",
        u.exact,
        y.exact
    );
    assert!(config_report("ndf-sphere-hw", &small).synthesis.is_none());
    let e = config_error(
        "sgi-teapot",
        &["reference.synthesis=Some((tilt_deg: 30.0))"],
    );
    assert!(
        e.contains("reference.synthesis") && e.contains("bump: Ndf"),
        "{e}"
    );
    let e = config_error(
        "ndf-sphere-hw",
        &["reference.synthesis=Some((tilt_deg: 91.0))"],
    );
    assert!(
        e.contains("reference.synthesis.tilt_deg") && e.contains("0 to 90"),
        "{e}"
    );
}

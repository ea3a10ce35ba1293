//! The per-pixel perturbation engines of Ernst et al. 1998 §3 (Texram, VISA+, VISA+ with
//! quaternions, Harmony) and their shared Phong datapath, end to end on the bundled configs:
//! error against the reference both ways, what each asks of the geometry engine, and the edge
//! discontinuity of §3.2 on the folded strip of `configs/visa-fold.ron`.

mod common;

use bumpsim_pipeline::config::{self, Loaded};
use bumpsim_pipeline::report::Report;
use bumpsim_pipeline::run;
use common::*;

fn load(stem: &str, sets: &[String]) -> Loaded {
    config::load(&config(stem), sets).unwrap_or_else(|e| panic!("{stem}: {e}"))
}

fn report(stem: &str, sets: &[String]) -> Report {
    run::run(&load(stem, sets), None)
        .unwrap_or_else(|e| panic!("{stem}: {e}"))
        .report
}

fn small() -> Vec<String> {
    vec!["scene.width=128".into(), "scene.height=128".into()]
}

/// The study scene of `configs/visa-fold.ron` as one `--set scene=...` override, at
/// `angle_deg`, 128 x 128.
fn fold_scene(angle_deg: f64) -> Vec<String> {
    let l = load("visa-fold", &[]);
    let scene = ron::to_string(&l.config.scene).expect("the scene serialises");
    let mut sets = vec![format!("scene={scene}")];
    sets.push(format!("scene.mesh.angle_deg={angle_deg}"));
    sets.extend(small());
    sets
}

#[test]
fn every_perturbation_engine_follows_the_reference_in_both_modes() {
    // measured at 128 x 128 (PSNR dB, algorithm / quantization): the bump engines share the
    // texture and the lighting widths, so they land within a fraction of a dB of each other
    for (stem, algorithm, quantization) in [
        ("phong-teapot", 45.0, 40.0),
        ("visa-teapot", 31.0, 39.0),
        ("visa-quat-teapot", 31.0, 39.0),
        ("harmony-teapot", 31.0, 39.0),
        ("texram-teapot", 31.0, 39.0),
        ("texram-teapot-scaled", 31.0, 39.0),
    ] {
        let r = report(stem, &small());
        let e = &r.error;
        assert!(
            e.algorithm.psnr_db > algorithm && e.quantization.psnr_db > quantization,
            "{stem}: algorithm {:.2} dB, quantization {:.2} dB",
            e.algorithm.psnr_db,
            e.quantization.psnr_db
        );
    }
}

#[test]
fn the_geometry_engine_sends_what_each_engine_needs() {
    // bits per triangle: uv (2 x 16) and four 3 x 10-bit light vectors per vertex for all;
    // then N (Phong, VISA+, Texram), the alignment matrix's two 3 x 10-bit columns once per
    // triangle (VISA+), the main direction per vertex (Texram), a 4 x 10-bit quaternion per
    // vertex (VISA+ with quaternions), three axes per vertex (Harmony)
    let bits = |stem: &str| {
        report(stem, &small())
            .bandwidth
            .bump_extra_bits_per_triangle
    };
    let lights = 3 * 4 * 30;
    assert_eq!(bits("phong-teapot"), lights + 3 * 30);
    assert_eq!(bits("visa-teapot"), lights + 3 * 30 + 2 * 30);
    assert_eq!(bits("texram-teapot"), lights + 2 * 3 * 30);
    assert_eq!(bits("visa-quat-teapot"), lights + 3 * 30 + 3 * 40);
    assert_eq!(bits("harmony-teapot"), lights + 3 * 3 * 30);
}

#[test]
fn visa_plus_steps_at_a_folded_edge_and_its_quaternion_variant_does_not() {
    // exact mode against the reference (the algorithm's own discontinuity): the worst single
    // edge's mean error step beyond the interior's. Measured at 128 x 128: VISA+ 0.6 LSB at
    // 10 degrees, 1.6 at 30, 2.4 at 60; the continuous frames stay below 0.2 LSB.
    let seam = |stem: &str, angle: f64| report(stem, &fold_scene(angle)).edges.algorithm;
    let flat = seam("visa-teapot", 0.0);
    assert!(
        flat.worst_seam_lsb < 0.1,
        "a flat strip has no seam: {flat:?}"
    );
    let mut last = flat.worst_seam_lsb;
    for angle in [15.0, 30.0, 60.0] {
        let visa = seam("visa-teapot", angle);
        assert!(
            visa.worst_seam_lsb > last + 0.2,
            "VISA+ at {angle}: {visa:?} (below {last})"
        );
        last = visa.worst_seam_lsb;
        for stem in ["visa-quat-teapot", "harmony-teapot", "texram-teapot"] {
            let s = seam(stem, angle);
            assert!(
                s.worst_seam_lsb < 0.25 * visa.worst_seam_lsb,
                "{stem} at {angle}: {s:?} against VISA+ {visa:?}"
            );
        }
    }
    assert!(last > 1.5, "VISA+ at 60 degrees: {last}");
}

#[test]
fn quaternions_interpolate_around_a_low_polygon_sphere() {
    // the vertex frames of a sphere turn by 360 degrees around its axis, so neighbouring
    // vertex quaternions fall in opposite hemispheres somewhere: triangle setup must flip
    // them, or the interpolated rotation passes near zero. Measured at 128 x 128 on a
    // 12 x 8 sphere (algorithm PSNR dB): quaternions 41.81, Harmony 41.93, Texram 41.84,
    // VISA+ 39.76 (its alignment matrix is per triangle).
    let mut sets = small();
    sets.push(
        "scene.mesh=Sphere(radius: 1.0, slices: 12, stacks: 8, uv_repeat: (2.0, 1.0))".into(),
    );
    let psnr = |stem: &str| report(stem, &sets).error.algorithm.psnr_db;
    let (quat, harmony, texram, visa) = (
        psnr("visa-quat-teapot"),
        psnr("harmony-teapot"),
        psnr("texram-teapot"),
        psnr("visa-teapot"),
    );
    assert!((quat - harmony).abs() < 0.5, "{quat} {harmony}");
    assert!((quat - texram).abs() < 0.5, "{quat} {texram}");
    assert!(visa < quat - 1.0, "{visa} {quat}");
}

#[test]
fn unit_fields_out_of_range_are_errors_naming_the_field() {
    for (stem, set, field) in [
        (
            "texram-teapot",
            "engine.units.frame.unit.table_bits=40",
            "engine.units[2].unit.table_bits",
        ),
        (
            "visa-quat-teapot",
            "engine.units.qframe.unit.table_bits=1",
            "engine.units[2].unit.table_bits",
        ),
        (
            "visa-teapot",
            "scene.mesh=Fold(angle_deg: 200.0, size: 1.0, columns: 1, uv_repeat: (1.0, 1.0))",
            "mesh.Fold.angle_deg",
        ),
    ] {
        let e = config::load(&config(stem), &[set.to_string()])
            .and_then(|l| run::run(&l, None).map(|_| ()))
            .expect_err(set)
            .to_string();
        assert!(e.contains(field), "{stem} {set}: {e}");
    }
}

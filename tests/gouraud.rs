//! Gouraud bump mapping (Ernst, Rüsseler, Schulz, Wittig 1998): the paper's claims checked on
//! the bundled `configs/gouraud-*.ron` through the library (fast: small images).

use bumpsim_pipeline::config;
use bumpsim_pipeline::run::{run, RunResult};
use std::path::PathBuf;

fn cfg(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("configs")
        .join(format!("{name}.ron"))
}

fn run_cfg(name: &str, sets: &[&str]) -> RunResult {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let l = config::load(&cfg(name), &sets).unwrap_or_else(|e| panic!("{name}: {e}"));
    run(&l, None).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// §4.2: "three 16-bit words per triangle, or about less than 5% of a typical textured
/// Gouraud triangle data-set".
#[test]
fn quad_bandwidth_is_three_16_bit_words_under_5_percent() {
    let r = run_cfg("gouraud-quad-bandwidth", &[]);
    let b = &r.report.bandwidth;
    assert_eq!(b.baseline_bits_per_triangle, 1056);
    assert_eq!(b.bump_extra_bits_per_triangle, 48);
    assert!(
        (b.bump_extra_percent - 4.5).abs() < 0.05,
        "{}",
        b.bump_extra_percent
    );
    assert!(b.bump_extra_percent < 5.0);
}

/// §4.2: "the gate budget lies in the range from 10,000 to 25,000 gate equivalents".
#[test]
fn teapot_blend_units_cost_10k_to_25k_gates() {
    let r = run_cfg("gouraud-teapot", &[]);
    let blend: f64 = r
        .report
        .gates
        .per_unit
        .values()
        .filter(|u| u.kind == "bump_blend")
        .map(|u| u.total)
        .sum();
    assert!((10_000.0..=25_000.0).contains(&blend), "{blend} GE");
}

/// §4.2: "n light sources are blended in n clock cycles": two lights on one datapath.
#[test]
fn torus_two_lights_take_two_clocks_per_fragment() {
    let r = run_cfg("gouraud-torus-caps", &[]);
    let c = &r.report.cycles;
    assert!(c.per_fragment >= 2.0, "{}", c.per_fragment);
    for unit in ["diffuse", "specular"] {
        let busy = c.per_unit[unit].busy as f64;
        let ratio = busy / c.fragments as f64;
        assert!(
            (ratio - 2.0).abs() < 0.05,
            "{unit}: busy {busy}, ratio {ratio}"
        );
    }
    // two datapaths blend both lights in one clock
    let r2 = run_cfg(
        "gouraud-torus-caps",
        &[
            "engine.units.diffuse.unit.parallel=2",
            "engine.units.specular.unit.parallel=2",
        ],
    );
    assert!(r2.report.cycles.per_fragment < c.per_fragment);
}

/// §5.1, Figs. 2 and 3: the split order and the combined one differ on the black squares.
#[test]
fn split_and_combined_orders_differ_on_black_squares() {
    let split = run_cfg("gouraud-order-split", &[]);
    let comb = run_cfg("gouraud-order-combined", &[]);
    // the combined order is further from the reference (which modulates the diffuse term
    // by the texture, as the split order does)
    assert!(
        comb.report.error.total.rmse > 2.0 * split.report.error.total.rmse,
        "{} vs {}",
        comb.report.error.total.rmse,
        split.report.error.total.rmse
    );
    // on the black squares the split order leaves only the specular term, the combined one
    // adds the whole diffuse term: pixels dark in the split image but lit in the combined one
    let (w, h) = split.image.dimensions();
    let mut black_lit = 0;
    for y in 0..h {
        for x in 0..w {
            let s = split.image.get_pixel(x, y).0;
            let c = comb.image.get_pixel(x, y).0;
            let lum = |p: [u8; 3]| p.iter().map(|&v| v as u32).sum::<u32>();
            if lum(s) > 0 && lum(s) < 3 * 20 && lum(c) > lum(s) + 3 * 40 {
                black_lit += 1;
            }
        }
    }
    assert!(black_lit > 500, "{black_lit} pixels");
}

/// §5.4.2: selective blending leaves unperturbed texels to the Gouraud colour.
#[test]
fn selective_blending_fixes_the_faceting() {
    let art = run_cfg("gouraud-flat-artifact", &[]);
    let fix = run_cfg("gouraud-flat-fix", &["scene.bump=Flat"]);
    // with a flat map every texel is unperturbed: the fix is plain Gouraud shading, much
    // closer to the reference than the faceted blend
    assert!(fix.report.error.total.rmse < art.report.error.total.rmse);
}

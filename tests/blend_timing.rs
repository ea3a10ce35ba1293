//! Multi-light timing of the Gouraud bump blend units (Ernst et al. 1998 §4.2: "n light
//! sources are blended in n clock cycles"), on `tests/fixtures/gouraud-tiny.ron`: a 4x4 quad,
//! 16 fragments, diffuse and specular blend units with one datapath each.

mod common;

use common::*;

const LIGHTS: [&str; 4] = [
    "(kind: Directional(dir: (1.0, 1.0, 1.0)), color: (1.0, 1.0, 1.0))",
    "(kind: Directional(dir: (-1.0, 0.5, 1.0)), color: (0.6, 0.2, 0.6))",
    "(kind: Directional(dir: (0.0, -1.0, 1.0)), color: (0.2, 0.6, 0.2))",
    "(kind: Directional(dir: (0.5, 0.0, 1.0)), color: (0.3, 0.3, 0.3))",
];

fn tiny() -> std::path::PathBuf {
    root().join("tests/fixtures/gouraud-tiny.ron")
}

fn report(lights: usize, parallel: u32) -> serde_json::Value {
    let set_lights = format!("scene.lights=[{}]", LIGHTS[..lights].join(", "));
    let mut args: Vec<String> = vec![
        "report".into(),
        tiny().display().to_string(),
        "--json".into(),
        "--set".into(),
        set_lights,
    ];
    for unit in ["diffuse", "specular"] {
        args.push("--set".into());
        args.push(format!("engine.units.{unit}.unit.parallel={parallel}"));
    }
    let o = bumpsim(&args);
    o.expect_code(0, &format!("{args:?}"));
    json(&o.stdout)
}

#[test]
fn n_lights_take_n_clocks_per_fragment_on_one_datapath() {
    for n in 1..=4usize {
        let r = report(n, 1);
        assert_eq!(uint(&r, "cycles.fragments"), 16);
        for unit in ["diffuse", "specular"] {
            // each fragment holds the unit for n clocks; the last one stays in flight for the
            // two pipeline stages behind the accumulator (latency = interval + 2)
            let busy = uint(&r, &format!("cycles.per_unit.{unit}.busy"));
            assert_eq!(busy, 16 * n as u64 + 2, "{n} lights, {unit}");
            assert_eq!(
                uint(&r, &format!("cycles.per_unit.{unit}.stall")),
                0,
                "{n} lights, {unit}"
            );
        }
        // per frame: a 16-entry power table, 3 colour words per light in each unit, 3 L words
        // per light (diffuse), 3 H words per light (specular)
        assert_eq!(uint(&r, "cycles.frame"), 16 + 12 * n as u64, "{n} lights");
        if n > 1 {
            // the units before the blend units are held back by them
            assert!(
                uint(&r, "cycles.per_unit.bump.stall") > 0,
                "{n} lights: the fetch must stall"
            );
        }
    }
}

#[test]
fn two_datapaths_halve_the_interval_and_cost_gates() {
    let one = report(4, 1);
    let two = report(4, 2);
    for unit in ["diffuse", "specular"] {
        assert_eq!(
            uint(&two, &format!("cycles.per_unit.{unit}.busy")),
            16 * 2 + 2,
            "{unit}"
        );
        let gates = |r: &serde_json::Value| num(r, &format!("gates.per_unit.{unit}.total"));
        assert!(
            gates(&two) > gates(&one),
            "{unit}: a second datapath costs gates"
        );
    }
    assert!(uint(&two, "cycles.total") < uint(&one, "cycles.total"));
    // the images are the same: the datapaths change time, not values
    assert_eq!(at(&one, "error.total"), at(&two, "error.total"));
}

/// The stall pattern of a whole frame, cycle by cycle, with two lights.
#[test]
fn two_light_trace_snapshot() {
    let scratch = Scratch::new("blend-timing-trace");
    let out = scratch.join("trace.txt");
    let r = report(2, 1);
    let total = uint(&r, "cycles.total");
    let args: Vec<String> = vec![
        "trace".into(),
        tiny().display().to_string(),
        "--cycles".into(),
        format!("0..{total}"),
        "--format".into(),
        "text".into(),
        "--out".into(),
        out.display().to_string(),
    ];
    bumpsim(&args).expect_code(0, "trace of the tiny scene");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("stall"),
        "the fetch stalls behind the two-clock blend units"
    );
    insta::with_settings!({
        snapshot_path => concat!(env!("CARGO_MANIFEST_DIR"), "/traces"),
        prepend_module_to_snapshot => false,
    }, {
        insta::assert_snapshot!("trace-gouraud-tiny-2-lights", text);
    });
}

/// Bad Gouraud configs are rejected with exit code 2 and a message naming what was expected.
#[test]
fn bad_gouraud_configs_are_rejected() {
    let cases: [(&str, &[&str]); 5] = [
        ("scene.lights=[]", &["light", "expected"]),
        (
            "engine.units.specular.unit.spec=Table(index_bits: 17, value_bits: 8)",
            &["index_bits", "17"],
        ),
        ("scene.material.shininess=0", &["shininess", "above 0"]),
        ("scene.material.shininess=-4", &["shininess", "above 0"]),
        (
            "scene.lights=[(kind: Directional(dir: (1, 1, 1)), color: (1.5, 1, 1))]",
            &["color", "[0, 1]"],
        ),
    ];
    for (set, needles) in cases {
        expect_rejected(&tiny(), set, needles);
    }
}

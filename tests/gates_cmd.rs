//! `bumpsim gates CONFIG [--synth] [--json]`: the report's gate figures without a render, and
//! with `--synth` yosys's synthesis beside them. yosys is required for the synthesis test
//! (`.ci/install-yosys.sh`): it **fails** without it unless `BUMPSIM_SKIP_YOSYS=1` is set.

mod common;

use common::*;
use serde_json::Value;

fn skip_yosys() -> bool {
    std::env::var_os("BUMPSIM_SKIP_YOSYS").is_some_and(|v| !v.is_empty() && v != "0")
}

fn gates_json(cfg: &str, extra: &[&str]) -> Value {
    let path = config(cfg);
    let mut args = vec!["gates", path.to_str().unwrap(), "--json"];
    args.extend(extra);
    let o = bumpsim(&args);
    o.expect_code(0, "gates --json");
    json(&o.stdout)
}

#[test]
fn gates_are_the_reports_figures_without_a_render() {
    for cfg in ["sgi-teapot", "gouraud-teapot", "quantized-sphere"] {
        let path = config(cfg);
        let sets = ["--set", "scene.width=48", "--set", "scene.height=48"];
        let g = gates_json(cfg, &sets);
        let mut args = vec!["report", path.to_str().unwrap(), "--json"];
        args.extend(sets);
        let o = bumpsim(&args);
        o.expect_code(0, "report --json");
        let r = json(&o.stdout);
        assert_eq!(at(&g, "gates"), at(&r, "gates"), "{cfg}");
        assert_eq!(at(&g, "config_hash"), at(&r, "config_hash"), "{cfg}");
        assert_eq!(at(&g, "gates.estimate").as_str(), Some("model"), "{cfg}");
        assert!(num(&g, "gates.total") > 1000.0, "{cfg}");
    }
    // an override moves the figure as it moves the report's
    let wide = gates_json(
        "sgi-teapot",
        &["--set", r#"engine.units.spec.unit.index_bits=10"#],
    );
    let base = gates_json("sgi-teapot", &[]);
    assert!(
        num(&wide, "gates.per_unit.spec.total") > 3.5 * num(&base, "gates.per_unit.spec.total"),
        "a 4x power table"
    );
    // the text form names every unit and the total
    let path = config("emboss");
    let o = bumpsim(&["gates", path.to_str().unwrap()]);
    o.expect_code(0, "gates");
    for needle in [
        "dot",
        "emboss",
        "norm",
        "shade",
        "total",
        "model's estimate",
    ] {
        assert!(o.stdout.contains(needle), "{needle}: {}", o.stdout);
    }
    // bad input: exit 2 naming the file
    let o = bumpsim(&["gates", "configs/no-such-config.ron"]);
    o.expect_code(2, "missing config");
    assert!(o.stderr.contains("no-such-config.ron"), "{}", o.stderr);
}

/// A unit's own `tables` builds its tables as it says, the other units' as `cost.tables`
/// does (docs/gates.md, "Memory"): sgi-teapot's 256 x 8 power table (2,048 bits) as flip-flop
/// RAM (10.33 GE a bit) against SRAM (1.5), the texel fetch unchanged.
#[test]
fn a_units_tables_kind_overrides_the_configs() {
    let base = gates_json("sgi-teapot", &[]);
    let flop = gates_json(
        "sgi-teapot",
        &["--set", "engine.units.spec.tables=Some(FlopRam)"],
    );
    let mem = |g: &Value, u: &str| num(g, &format!("gates.per_unit.{u}.memory"));
    assert!(
        (mem(&base, "spec") - 2048.0 * 1.5).abs() < 0.01,
        "{}",
        mem(&base, "spec")
    );
    assert!(
        (mem(&flop, "spec") - 2048.0 * 10.33).abs() < 0.01,
        "{}",
        mem(&flop, "spec")
    );
    assert_eq!(
        at(&flop, "gates.per_unit.spec.tables").as_str(),
        Some("flip-flop RAM")
    );
    assert!(at(&base, "gates.per_unit.spec").get("tables").is_none());
    assert_eq!(at(&flop, "gates.tables").as_str(), Some("SRAM"));
    assert_eq!(
        at(&flop, "gates.per_unit.fetch"),
        at(&base, "gates.per_unit.fetch")
    );
    // the override is part of the config, so of its hash
    assert_ne!(at(&flop, "config_hash"), at(&base, "config_hash"));
    // a kind that does not exist is an error naming the field
    let path = config("sgi-teapot");
    let o = bumpsim(&[
        "gates",
        path.to_str().unwrap(),
        "--set",
        "engine.units.spec.tables=Some(Disk)",
    ]);
    o.expect_code(2, "an unknown memory kind");
    assert!(
        o.stderr.contains("tables") && o.stderr.contains("FlopRam"),
        "{}",
        o.stderr
    );
}

#[test]
fn each_table_of_a_unit_is_built_as_its_role_says() {
    let set = "engine.units.qnm.table_kinds={Colours: LatchRam, Power: FlopRam}";
    let g = gates_json("quantized-sphere", &["--set", set]);
    let u = at(&g, "gates.per_unit.qnm");
    let item = |what: &str| {
        let items = u["items"].as_array().expect("items");
        let i = items
            .iter()
            .find(|i| i["what"].as_str().is_some_and(|w| w.contains(what)))
            .unwrap_or_else(|| panic!("no item {what}: {items:?}"));
        assert_eq!(i["memory"], Value::Bool(true), "{i}");
        num(i, "ge")
    };
    // 256 colours of 4 x 8 bits in latches, 1024 x 12 power words in flip-flops, the
    // 256 x 36 normal table in SRAM as cost.tables says
    assert!((item("colour table 256x32") - 256.0 * 32.0 * 5.66).abs() < 0.01);
    assert!((item("power table 0 1024x12") - 1024.0 * 12.0 * 10.33).abs() < 0.01);
    assert!((item("normal table 256x36") - 256.0 * 36.0 * 1.5).abs() < 0.01);
    assert_eq!(
        at(&g, "gates.per_unit.qnm.table_kinds.colours").as_str(),
        Some("latch RAM")
    );
    assert_eq!(
        at(&g, "gates.per_unit.qnm.table_kinds.power").as_str(),
        Some("flip-flop RAM")
    );
    let base = gates_json("quantized-sphere", &[]);
    assert!(at(&base, "gates.per_unit.qnm").get("table_kinds").is_none());
    assert_ne!(at(&g, "config_hash"), at(&base, "config_hash"));
    // a role the unit has no table of is an error naming the field and the unit's roles
    let path = config("sgi-teapot");
    let o = bumpsim(&[
        "gates",
        path.to_str().unwrap(),
        "--set",
        "engine.units.spec.table_kinds={Colours: Rom}",
    ]);
    o.expect_code(2, "a role the unit has no table of");
    assert!(
        o.stderr.contains("engine.units[2].table_kinds")
            && o.stderr.contains("no colours table")
            && o.stderr.contains("Power"),
        "{}",
        o.stderr
    );
}

#[test]
fn synth_puts_yosys_beside_the_model_for_every_generated_unit() {
    if skip_yosys() {
        println!("gates --synth: skipped (BUMPSIM_SKIP_YOSYS is set)");
        return;
    }
    let g = gates_json("emboss", &["--synth"]);
    for unit in ["emboss", "dot", "shade", "norm"] {
        let s = at(&g, &format!("gates.per_unit.{unit}.synth"));
        let ge = num(s, "ge");
        let ratio = num(s, "logic_ratio");
        let model = num(&g, &format!("gates.per_unit.{unit}.total"));
        assert!(ge > 1000.0, "{unit}: {ge} GE");
        // the band of hw/tests/rtl_synth.rs, issue 13's +-10% (measured 0.935-1.032 here)
        assert!(
            (0.9..=1.1).contains(&ratio),
            "{unit}: model / yosys {ratio}"
        );
        // no loadable table; Normalize's reciprocal square root is a ROM, compared apart
        let rom: f64 = at(&g, &format!("gates.per_unit.{unit}.items"))
            .as_array()
            .unwrap()
            .iter()
            .filter(|i| i.get("rom").is_some_and(|r| r == true))
            .map(|i| num(i, "ge"))
            .sum();
        assert_eq!(rom > 0.0, unit == "norm", "{unit}: ROM items {rom}");
        assert!(
            (num(s, "logic_model_ge") - (model - rom)).abs() < 0.01,
            "{unit}: the logic is the model without its ROM"
        );
        assert!((num(s, "logic_model_ge") / num(s, "logic_synth_ge") - ratio).abs() < 1e-3);
    }
    // the ROP (one pass: its budget is the report's figure), in the same band (measured 1.025)
    let rop = at(&g, "gates.rop.synth.rop");
    assert!((num(rop, "model_ge") - num(&g, "gates.rop.total")).abs() < 0.01);
    assert!((0.9..=1.1).contains(&num(rop, "logic_ratio")), "rop: {rop}");
    // a unit without a generator (the builder's interpolated power table) is named with the
    // reason
    let g = gates_json(
        "quantized-sphere",
        &["--synth", "--set", common::LERP_POWER],
    );
    let why = at(&g, "gates.per_unit.qnm.synth.none");
    assert!(
        why.as_str()
            .is_some_and(|w| w.contains("not generated") && w.contains("TableLerp")),
        "qnm: {why}"
    );
    // an emboss filter of 6-bit heights has the rational rescale 255 s / 63 (the bricks'
    // s12.4 output, rounded to nearest): generated and synthesised
    let g = gates_json(
        "emboss",
        &[
            "--synth",
            "--set",
            "engine.units.emboss.unit.texel=(format:(signed:false,width:6,frac:0),codec:UnitUnsigned)",
        ],
    );
    let s = at(&g, "gates.per_unit.emboss.synth");
    let ratio = num(s, "logic_ratio");
    assert!(
        num(s, "ge") > 1000.0 && (0.8..=1.4).contains(&ratio),
        "emboss: {s}"
    );
}

/// A texture shader's budget prices the programmable part (every program in every stage) by
/// default; its Verilog is the configured programs' datapath, so `--synth` compares yosys with
/// the model of that (`generated_model_ge`), and with `datapath: Configured` the budget is
/// that model itself. `d3d6-embm-quad` at s16.10 coordinates (yosys about 10 s).
#[test]
fn synth_compares_a_texture_shader_with_its_configured_datapath() {
    if skip_yosys() {
        println!("gates --synth: skipped (BUMPSIM_SKIP_YOSYS is set)");
        return;
    }
    let narrow = "(format: (signed: true, width: 16, frac: 10))";
    let a0 = format!("engine.attributes[0].enc={narrow}");
    let a1 = format!("engine.attributes[1].enc={narrow}");
    let g = gates_json("d3d6-embm-quad", &["--synth", "--set", &a0, "--set", &a1]);
    let s = at(&g, "gates.per_unit.shader.synth");
    let programmable = num(&g, "gates.per_unit.shader.total");
    let configured = num(s, "generated_model_ge");
    assert!(
        configured < programmable / 5.0,
        "configured {configured} vs programmable {programmable}"
    );
    assert_eq!(num(s, "logic_model_ge"), configured);
    let ratio = num(s, "logic_ratio");
    // the band of hw/tests/rtl_synth.rs (measured 1.047)
    assert!((0.9..=1.1).contains(&ratio), "model / yosys {ratio}");
    let c = gates_json(
        "d3d6-embm-quad",
        &[
            "--synth",
            "--set",
            &a0,
            "--set",
            &a1,
            "--set",
            "engine.units.shader.unit.datapath=Configured",
        ],
    );
    let cs = at(&c, "gates.per_unit.shader.synth");
    assert_eq!(num(&c, "gates.per_unit.shader.total"), configured);
    assert!(cs.get("generated_model_ge").is_none(), "{cs}");
    assert_eq!(num(cs, "logic_ratio"), ratio);
}

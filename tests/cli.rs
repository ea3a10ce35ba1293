//! End-to-end tests of the `bumpsim` command line on the bundled configs: `check`, `render`,
//! `report` (table and JSON) and `--set` overrides.

mod common;

use common::*;
use serde_json::Value;
use std::path::Path;

/// The first `key: <integer>` after `after` in a config's text.
fn int_after(text: &str, after: &str, key: &str) -> u32 {
    let s = &text[text.find(after).unwrap_or_else(|| panic!("no {after:?}"))..];
    let s = &s[s
        .find(key)
        .unwrap_or_else(|| panic!("no {key:?} after {after:?}"))
        + key.len()..];
    let digits: String = s
        .trim_start()
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    digits.parse().unwrap()
}

fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let img = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
        .unwrap_or_else(|e| panic!("{} does not decode as PNG: {e}", path.display()));
    (img.width(), img.height())
}

const ERROR_KINDS: [&str; 3] = ["total", "algorithm", "quantization"];
const ERROR_STATS: [&str; 4] = ["psnr_db", "rmse", "max_abs_lsb", "mean_abs_lsb"];

/// Check every field the report must have, and the relations between them.
fn check_report(r: &Value, units: &[String], width: u32, height: u32, what: &str) {
    assert_eq!(
        at(r, "version").as_str(),
        Some(env!("CARGO_PKG_VERSION")),
        "{what}"
    );
    let hash = at(r, "config_hash")
        .as_str()
        .expect("config_hash is a string");
    assert_eq!(
        hash.len(),
        64,
        "{what}: config_hash {hash:?} is not a SHA-256 hex digest"
    );
    assert!(
        hash.chars().all(|c| c.is_ascii_hexdigit()),
        "{what}: {hash}"
    );
    assert_eq!(uint(r, "image.width"), u64::from(width), "{what}");
    assert_eq!(uint(r, "image.height"), u64::from(height), "{what}");

    let total = uint(r, "cycles.total");
    let frame = uint(r, "cycles.frame");
    assert!(
        total > frame,
        "{what}: cycles.total {total} <= cycles.frame {frame}"
    );
    let per_unit = at(r, "cycles.per_unit")
        .as_object()
        .expect("cycles.per_unit is an object");
    // every engine unit, plus the front end's setup and scan units
    for u in units.iter().map(String::as_str).chain(["setup", "scan"]) {
        let c = per_unit
            .get(u)
            .unwrap_or_else(|| panic!("{what}: cycles.per_unit has no {u:?}: {per_unit:?}"));
        let k = |f: &str| {
            c.get(f)
                .and_then(Value::as_u64)
                .unwrap_or_else(|| panic!("{what}: cycles.per_unit.{u}.{f} missing"))
        };
        let (busy, idle, stall) = (k("busy"), k("idle"), k("stall"));
        assert_eq!(
            busy + idle + stall,
            total - frame,
            "{what}: unit {u}: busy {busy} + idle {idle} + stall {stall} != total {total} - frame {frame}"
        );
    }
    for u in units {
        assert!(
            uint(r, &format!("cycles.per_unit.{u}.busy")) > 0,
            "{what}: unit {u} was never busy"
        );
    }

    let gates_total = num(r, "gates.total");
    assert!(gates_total > 0.0, "{what}");
    let gates = at(r, "gates.per_unit").as_object().expect("gates.per_unit");
    let mut names: Vec<&String> = gates.keys().collect();
    names.sort();
    let mut want: Vec<&String> = units.iter().collect();
    want.sort();
    assert_eq!(
        names, want,
        "{what}: gates.per_unit has exactly the engine units"
    );
    let mut sum = 0.0;
    for u in units {
        let g = num(r, &format!("gates.per_unit.{u}.total"));
        assert!(g > 0.0, "{what}: unit {u} has {g} gates");
        sum += g;
    }
    assert!(
        (sum - gates_total).abs() < 0.05,
        "{what}: gates.total {gates_total} != sum of units {sum}"
    );

    assert_eq!(
        uint(r, "bandwidth.baseline_bits_per_triangle"),
        1056,
        "{what}"
    );
    let bits = uint(r, "bandwidth.bits_per_triangle");
    assert!(bits > 0, "{what}");
    let texel = uint(r, "bandwidth.bits_per_texel");
    let textures = at(r, "bandwidth.texture_memory")
        .as_object()
        .expect("bandwidth.texture_memory")
        .len();
    assert_eq!(
        texel > 0,
        textures > 0,
        "{what}: bits per texel {texel} with {textures} textures"
    );

    for k in ERROR_KINDS {
        for s in ERROR_STATS {
            let x = num(r, &format!("error.{k}.{s}"));
            assert!(x.is_finite(), "{what}: error.{k}.{s} = {x}");
            if s != "psnr_db" {
                assert!(x >= 0.0, "{what}: error.{k}.{s} = {x}");
            }
        }
        assert!(
            num(r, &format!("error.{k}.mean_abs_lsb")) <= num(r, &format!("error.{k}.max_abs_lsb")),
            "{what}: error.{k}: mean above max"
        );
    }
}

/// `check`, `render`, `report --json` and `report` on one bundled config.
fn config_end_to_end(name: &str) {
    let cfg = config(name);
    let text = std::fs::read_to_string(&cfg).unwrap();
    let units = engine_units(&text);
    let width = int_after(&text, "scene:", "width:");
    let height = int_after(&text, "scene:", "height:");
    let scratch = Scratch::new(&format!("cli-{name}"));
    let what = format!("configs/{name}.ron");

    let o = bumpsim(&["check".as_ref(), cfg.as_os_str()]);
    o.expect_code(0, &format!("check {what}"));
    assert!(o.stdout.starts_with("ok: "), "{}", o.stdout);

    let out = scratch.join("out");
    let o = bumpsim(&[
        "render".as_ref(),
        cfg.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    o.expect_code(0, &format!("render {what}"));
    // an animation (`frames`) also writes each later frame's image
    let report = json(&std::fs::read_to_string(out.join("report.json")).unwrap());
    let frames = report
        .get("animation")
        .map_or(1, |_| uint(&report, "animation.frames"));
    let mut files: Vec<String> = (1..frames).map(|k| format!("frame-{k:03}.png")).collect();
    files.extend(["error.png", "image.png", "reference.png", "report.json"].map(String::from));
    files.sort();
    assert_eq!(
        listing(&out),
        files,
        "{what}: render writes exactly these files"
    );
    for png in ["image.png", "reference.png", "error.png"] {
        assert_eq!(png_size(&out.join(png)), (width, height), "{what}: {png}");
    }
    let report_text = std::fs::read_to_string(out.join("report.json")).unwrap();
    let report = json(&report_text);
    check_report(&report, &units, width, height, &what);
    let cfg_name = {
        let s = &text[text.find("name: \"").unwrap() + 7..];
        &s[..s.find('"').unwrap()]
    };
    assert_eq!(at(&report, "name").as_str(), Some(cfg_name), "{what}");
    // the table printed by render names every unit too
    for u in &units {
        assert!(
            o.stdout.contains(u.as_str()),
            "{what}: render output lacks {u}"
        );
    }

    let o = bumpsim(&["report".as_ref(), cfg.as_os_str(), "--json".as_ref()]);
    o.expect_code(0, &format!("report --json {what}"));
    assert_eq!(
        o.stdout, report_text,
        "{what}: report --json differs from report.json"
    );

    let o = bumpsim(&["report".as_ref(), cfg.as_os_str()]);
    o.expect_code(0, &format!("report {what}"));
    for u in &units {
        assert!(
            o.stdout
                .lines()
                .any(|l| l.split_whitespace().next() == Some(u.as_str())),
            "{what}: the report table has no line for unit {u}:\n{}",
            o.stdout
        );
    }
    assert!(
        o.stdout.contains(&format!("config {cfg_name}")),
        "{}",
        o.stdout
    );
    assert!(o
        .stdout
        .contains(&report["config_hash"].as_str().unwrap()[..16]));
}

/// Every config in `configs/` (whatever configs are added later).
#[test]
fn every_bundled_config_checks_renders_and_reports() {
    let names: Vec<String> = configs().iter().map(|p| stem(p)).collect();
    for name in ["sgi-teapot", "emboss"] {
        assert!(
            names.iter().any(|n| n == name),
            "configs/{name}.ron is missing"
        );
    }
    for name in &names {
        config_end_to_end(name);
    }
}

fn report_json(cfg: &Path, sets: &[&str]) -> Value {
    let mut args: Vec<String> = vec!["report".into(), cfg.display().to_string(), "--json".into()];
    for s in sets {
        args.push("--set".into());
        args.push(s.to_string());
    }
    let o = bumpsim(&args);
    o.expect_code(0, &format!("{args:?}"));
    json(&o.stdout)
}

#[test]
fn set_index_bits_changes_gates_error_and_hash() {
    let cfg = config("sgi-teapot");
    let base = report_json(&cfg, &[]);
    let small = report_json(&cfg, &["engine.units.spec.unit.index_bits=4"]);
    // the override addressed by index gives the same config
    let by_index = report_json(&cfg, &["engine.units[2].unit.PowerTable.index_bits=4"]);
    assert_eq!(
        small, by_index,
        "units.spec and units[2].PowerTable name the same field"
    );

    assert_ne!(base["config_hash"], small["config_hash"]);
    let g = |r: &Value, u: &str| num(r, &format!("gates.per_unit.{u}.total"));
    assert!(
        g(&small, "spec") < g(&base, "spec"),
        "a 16-entry power table ({}) should take fewer gates than a 256-entry one ({})",
        g(&small, "spec"),
        g(&base, "spec")
    );
    for u in ["fetch", "dot", "shade"] {
        assert_eq!(
            g(&small, u),
            g(&base, u),
            "unit {u} does not depend on spec.index_bits"
        );
    }
    assert!(num(&small, "gates.total") < num(&base, "gates.total"));

    let q = |r: &Value, s: &str| num(r, &format!("error.quantization.{s}"));
    assert!(
        q(&small, "rmse") > q(&base, "rmse"),
        "4 index bits: quantization rmse {} should exceed 8 bits' {}",
        q(&small, "rmse"),
        q(&base, "rmse")
    );
    assert!(q(&small, "psnr_db") < q(&base, "psnr_db"));
    assert!(q(&small, "max_abs_lsb") >= q(&base, "max_abs_lsb"));
    // the exact-mode (algorithm) error does not depend on table sizes
    assert_eq!(base["error"]["algorithm"], small["error"]["algorithm"]);
    // nor does the geometry, the packet or the timing of the pipe (same latency); the
    // image's mean lit level is the bit-accurate image's, so it moves with the table
    for k in [
        "width",
        "height",
        "covered_pixels",
        "coverage_mismatch",
        "lit_pixels",
    ] {
        assert_eq!(base["image"][k], small["image"][k], "image.{k}");
    }
    assert_ne!(
        base["image"]["mean_lit_level"],
        small["image"]["mean_lit_level"]
    );
    assert_eq!(base["bandwidth"], small["bandwidth"]);
}

#[test]
fn set_scene_width_renders_a_narrower_image() {
    let cfg = config("sgi-teapot");
    let scratch = Scratch::new("cli-set-width");
    let out = scratch.join("out");
    let o = bumpsim(&[
        "render".as_ref(),
        cfg.as_os_str(),
        "--set".as_ref(),
        "scene.width=64".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    o.expect_code(0, "render --set scene.width=64");
    for png in ["image.png", "reference.png", "error.png"] {
        assert_eq!(png_size(&out.join(png)), (64, 256), "{png}");
    }
    let r = json(&std::fs::read_to_string(out.join("report.json")).unwrap());
    assert_eq!(uint(&r, "image.width"), 64);
    assert_eq!(uint(&r, "image.height"), 256);
    let base_hash = {
        let o = bumpsim(&["check".as_ref(), cfg.as_os_str()]);
        o.expect_code(0, "check");
        o.stdout
            .split("hash ")
            .nth(1)
            .unwrap()
            .trim_end_matches([')', '\n'])
            .to_string()
    };
    assert!(!r["config_hash"].as_str().unwrap().starts_with(&base_hash));
    // a narrower viewport of the same scene covers fewer pixels and triangles' fragments
    let full = report_json(&cfg, &[]);
    assert!(uint(&r, "image.covered_pixels") < uint(&full, "image.covered_pixels"));
    assert!(uint(&r, "cycles.fragments") < uint(&full, "cycles.fragments"));
    assert_eq!(
        uint(&r, "cycles.triangles"),
        uint(&full, "cycles.triangles")
    );
}

#[test]
fn set_several_overrides_apply_in_order() {
    // the last of two overrides of one field wins; `check` applies overrides too
    let cfg = config("sgi-teapot");
    let o = bumpsim(&[
        "check".as_ref(),
        cfg.as_os_str(),
        "--set".as_ref(),
        "scene.width=0".as_ref(),
        "--set".as_ref(),
        "scene.width=32".as_ref(),
    ]);
    o.expect_code(0, "check with scene.width=0 then 32");
}

#[test]
fn render_timings_go_to_stderr_and_leave_the_outputs_alone() {
    let cfg = config("gouraud-quad-bandwidth");
    let scratch = Scratch::new("timings");
    let render = |tag: &str, extra: &[&str]| {
        let out = scratch.join(tag);
        let mut args: Vec<&std::ffi::OsStr> = vec![
            "render".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ];
        args.extend(extra.iter().map(std::ffi::OsStr::new));
        let o = bumpsim(&args);
        o.expect_code(0, tag);
        (o, std::fs::read(out.join("report.json")).unwrap())
    };
    let (plain, report_plain) = render("plain", &[]);
    let (timed, report_timed) = render("timed", &["--timings"]);
    assert_eq!(plain.stdout.replace("plain", "timed"), timed.stdout);
    assert_eq!(report_plain, report_timed);
    assert!(!plain.stderr.contains("phase wall times"));
    for phase in [
        "scene and assets",
        "simulation",
        "exact mode",
        "reference",
        "metrics",
        "writing",
        "total",
    ] {
        assert!(timed.stderr.contains(phase), "{phase}: {}", timed.stderr);
    }
}

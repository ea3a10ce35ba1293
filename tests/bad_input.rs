//! Bad configs, files and arguments: each exits with code 2, with a message on stderr that
//! names the file (or `--set`, `--cycles`) and the field or what was expected, and `render`
//! writes nothing.
//!
//! Bad configs are made by editing the text of a bundled config (`configs/sgi-teapot.ron` or
//! `configs/emboss.ron`) and written to a scratch directory with any files they refer to.

mod common;

use common::*;
use std::path::PathBuf;

/// A bad config in its own scratch directory.
struct Bad {
    scratch: Scratch,
    cfg: PathBuf,
    text: String,
}

/// Copy `configs/<base>.ron` with each `(from, to)` edit applied once (each `from` must
/// occur), plus `files` next to it.
fn bad(test: &str, base: &str, edits: &[(&str, &str)], files: &[(&str, &[u8])]) -> Bad {
    let scratch = Scratch::new(&format!("bad-{test}"));
    let mut text = std::fs::read_to_string(config(base)).unwrap();
    for (from, to) in edits {
        assert!(
            text.contains(from),
            "{test}: configs/{base}.ron no longer contains {from:?}; update the test"
        );
        text = text.replacen(from, to, 1);
    }
    let cfg = scratch.join(&format!("{test}.ron"));
    std::fs::write(&cfg, &text).unwrap();
    for (name, bytes) in files {
        std::fs::write(scratch.join(name), bytes).unwrap();
    }
    Bad { scratch, cfg, text }
}

/// 1-based line of the first occurrence of `needle` in `text`.
fn line_of(text: &str, needle: &str) -> usize {
    let at = text
        .find(needle)
        .unwrap_or_else(|| panic!("{needle:?} not in the config"));
    text[..at].matches('\n').count() + 1
}

/// `(line, column)` of the `<file>:L:C:` prefix of an error message, if it has one.
fn position(stderr: &str, file: &str) -> Option<(usize, usize)> {
    let rest = &stderr[stderr.find(file)? + file.len()..];
    let rest = rest.strip_prefix(':')?;
    let mut it = rest.splitn(3, ':');
    let l = it.next()?.parse().ok()?;
    let c = it.next()?.parse().ok()?;
    Some((l, c))
}

/// Run `render CONFIG --out DIR [extra]` where DIR does not exist yet, and `check CONFIG
/// [extra]`: both must exit 2 with the same message, render must not create DIR, and the
/// message must contain every needle. Returns the message.
fn fails(b: &Bad, extra: &[&str], needles: &[&str]) -> String {
    let out = b.scratch.join("out");
    assert!(!out.exists());
    let mut args: Vec<String> = vec!["render".into(), b.cfg.display().to_string()];
    args.extend(extra.iter().map(|s| s.to_string()));
    args.extend(["--out".to_string(), out.display().to_string()]);
    let o = bumpsim(&args);
    o.expect_code(2, &format!("{args:?}"));
    assert!(
        !out.exists(),
        "render created the output directory on an error: {:?}",
        std::fs::read_dir(&out).map(|d| d.count())
    );
    // nothing else was written next to the config either (no stray temporary files)
    let left: Vec<String> = listing(&b.scratch.path)
        .into_iter()
        .filter(|n| n.starts_with('.') || n == "out")
        .collect();
    assert!(left.is_empty(), "stray files: {left:?}");
    let msg = o.stderr.trim_end().to_string();
    assert!(msg.starts_with("error: "), "{msg}");
    assert_eq!(msg.lines().count(), 1, "one line of error: {msg}");
    assert!(
        o.stdout.is_empty(),
        "nothing on stdout on an error: {}",
        o.stdout
    );
    for n in needles {
        assert!(msg.contains(n), "the message lacks {n:?}:\n{msg}");
    }

    let mut args: Vec<String> = vec!["check".into(), b.cfg.display().to_string()];
    args.extend(extra.iter().map(|s| s.to_string()));
    let c = bumpsim(&args);
    c.expect_code(2, &format!("{args:?}"));
    assert_eq!(
        c.stderr.trim_end(),
        msg,
        "check and render report the same error"
    );
    msg
}

/// Like [`fails`] for a config error, also checking that the message starts with the config
/// path and, when `at` is given, the line of the first occurrence of `at`.
fn fails_at(b: &Bad, at: Option<&str>, needles: &[&str]) -> String {
    let msg = fails(b, &[], needles);
    let file = b.cfg.display().to_string();
    assert!(
        msg.starts_with(&format!("error: {file}")),
        "the message names the config first: {msg}"
    );
    if let Some(needle) = at {
        let line = line_of(&b.text, needle);
        let pos = position(&msg, &file).unwrap_or_else(|| panic!("no line:column in {msg}"));
        assert_eq!(
            pos.0, line,
            "expected line {line} (of {needle:?}), got {pos:?}: {msg}"
        );
        assert!(msg.contains(&format!(":{line}:")), "{msg}");
    }
    msg
}

/// One test per edited config that `check` and `render` reject ([`fails_at`]):
/// `name: (scratch name, base config, edits, Some(text whose line the message points at)
/// or None, needles);`.
macro_rules! config_errors {
    ($($name:ident: ($test:expr, $base:expr, $edits:expr, $at:expr, $needles:expr $(,)?);)*) => {
        $(
            #[test]
            fn $name() {
                let b = bad($test, $base, $edits, &[]);
                fails_at(&b, $at, $needles);
            }
        )*
    };
}

/// [`fails`] for an error about the file `name` next to the config: the message names its
/// path, and every needle.
fn file_fails(b: &Bad, name: &str, needles: &[&str]) {
    let path = b.scratch.join(name).display().to_string();
    let mut all = vec![path.as_str()];
    all.extend_from_slice(needles);
    fails(b, &[], &all);
}

// ---------------------------------------------------------------- unknown names and keys

config_errors! {
    unknown_unit_kind: ("unit-kind", "sgi-teapot", &[("Dot3(", "Dot4(")], Some("Dot4("),
        &["engine.units[1].unit", "Dot4", "expected one of", "Dot3"]);
    // inside a unit's variant (it used to be ignored, rendering as if it were absent)
    unknown_key_in_a_unit: ("unit-key", "sgi-teapot", &[("Dot3(count: 4,", "Dot3(count: 4, paralel: 2,")], Some("paralel"),
        &["engine.units[1].unit.Dot3.paralel", "paralel", "expected one of", "parallel"]);
    unknown_key_in_scene: ("scene-key", "sgi-teapot", &[("width: 256,", "width: 256, colour: 1,")], Some("colour: 1"),
        &["scene.colour", "colour", "expected one of", "width"]);
    unknown_top_level_key: ("top-key", "emboss", &[("name: \"emboss\",", "name: \"emboss\", frobnicate: true,")], Some("frobnicate"),
        &["frobnicate", "expected one of", "engine"]);
}

// ---------------------------------------------------------------- number formats

const L0_FORMAT: &str =
    "(name: \"l0\", source: LightDir(light: 0, frame: Tangent), enc: (format: (signed: true, width: 10, frac: 8))),";

config_errors! {
    format_width_zero: ("width0", "sgi-teapot", &[(L0_FORMAT, &L0_FORMAT.replace("width: 10, frac: 8", "width: 0, frac: 0"))], Some("width: 0,"),
        &["engine.attributes[1].enc.format", "width 0", "expected 1 to 32 bits"]);
    format_width_33: ("width33", "sgi-teapot", &[(L0_FORMAT, &L0_FORMAT.replace("width: 10, frac: 8", "width: 33, frac: 8"))], Some("width: 33,"),
        &["engine.attributes[1].enc.format", "width 33", "expected 1 to 32 bits"]);
    // in a unit's output format this time
    format_frac_above_width: ("frac", "emboss", &[("out: (format: (signed: true, width: 16, frac: 4)),", "out: (format: (signed: true, width: 16, frac: 17)),")], Some("frac: 17"),
        &["engine.units[0].unit", "fraction bits 17 exceed the width 16", "expected 0 to 16"]);
}

// ---------------------------------------------------------------- wiring

config_errors! {
    // fetch.t is s2.8, 10 bits per lane
    expected_port_width_mismatch: ("expect", "sgi-teapot", &[("\"b3\": \"h1\"},", "\"b3\": \"h1\"}, expect: {\"a\": 12},")], Some("name: \"dot\""),
        &["engine.units[1].expect.a", "port width mismatch", "12 bits", "fetch.t carries 10"]);
    input_wired_to_a_missing_signal: ("missing-signal", "sgi-teapot", &[("\"b3\": \"h1\"}", "\"b3\": \"h9\"}")], Some("name: \"dot\""),
        &["engine.units[1].inputs.b3", "no signal \"h9\"", "expected one of", "fetch.t"]);
    unwired_input_port: ("unwired", "sgi-teapot", &[(", \"b3\": \"h1\"}", "}")], Some("name: \"dot\""),
        &["engine.units[1].inputs", "\"b3\"", "not wired", "expected a signal"]);
    input_port_that_does_not_exist: ("no-port", "sgi-teapot", &[("\"b3\": \"h1\"}", "\"b3\": \"h1\", \"b4\": \"h1\"}")], Some("name: \"dot\""),
        &["engine.units[1].inputs", "no input port \"b4\"", "expected a, b0, b1, b2, b3"]);
}

// ---------------------------------------------------------------- wire expressions

config_errors! {
    wire_concatenation_of_a_missing_signal: ("cat-missing", "dependent-dot-lookup", &[("\"uv\": \"cat(dot.d0, dot.d1)\"", "\"uv\": \"cat(dot.d0, dot.d7)\"")], Some("name: \"light\""),
        &["engine.units[2].inputs.uv", "no signal \"dot.d7\"", "expected one of", "dot.d0"]);
    wire_concatenation_of_two_encodings: ("cat-encodings", "dependent-dot-lookup", &[("\"uv\": \"cat(dot.d0, dot.d1)\"", "\"uv\": \"cat(dot.d0, fetch.t.x)\"")], Some("name: \"light\""),
        &["engine.units[2].inputs.uv", "dot.d0 carries", "fetch.t.x carries", "expected one encoding"]);
    wire_concatenation_of_too_many_lanes: ("cat-lanes", "dependent-dot-lookup", &[("\"b1\": \"h0\"}", "\"b1\": \"cat(h0, l0)\"}")], Some("name: \"dot\""),
        &["engine.units[1].inputs.b1", "6 lanes", "expected at most 4"]);
    wire_concatenation_without_its_parenthesis: ("cat-paren", "dependent-dot-lookup", &[("\"uv\": \"cat(dot.d0, dot.d1)\"", "\"uv\": \"cat(dot.d0, dot.d1\"")], Some("name: \"light\""),
        &["engine.units[2].inputs.uv", "closing parenthesis"]);
    wire_swizzle_past_the_lanes: ("swizzle-lane", "cull-fragment", &[("\"v\": \"l0.z\"", "\"v\": \"uv.z\"")], Some("name: \"cull\""),
        &["engine.units[0].inputs.v", "lane 2 of uv, which carries 2 lanes"]);
    wire_swizzle_of_mixed_letter_sets: ("swizzle-set", "cull-fragment", &[("\"v\": \"l0.z\"", "\"v\": \"l0.xg\"")], Some("name: \"cull\""),
        &["engine.units[0].inputs.v", "not a swizzle", "xyzw, rgba or stpq"]);
    // the wired lanes must match the port: a 2-lane swizzle into a 1-test cull unit
    wire_swizzle_of_the_wrong_lane_count: ("swizzle-count", "cull-fragment", &[("\"v\": \"l0.z\"", "\"v\": \"l0.zy\"")], Some("name: \"cull\""),
        &["engine.units[0].inputs.v", "takes 1 lanes", "l0.zy carries 2"]);
    cull_unit_without_tests: ("cull-empty", "cull-fragment", &[("tests: [Gequal]", "tests: []")], Some("name: \"cull\""),
        &["engine.units[0].unit", "tests: 0 given", "expected 1 to 4"]);
    cull_unit_with_an_unknown_test: ("cull-test", "cull-fragment", &[("tests: [Gequal]", "tests: [Greater]")], Some("Greater"),
        &["engine.units[0].unit", "Greater", "Gequal", "Less"]);
    interpolator_weight_bits_out_of_range: ("interp-bits", "sgi-teapot", &[("output: \"shade.color\",", "output: \"shade.color\", interpolator: Fixed(weight_bits: 2),")], Some("interpolator:"),
        &["engine.interpolator.weight_bits", "weight_bits 2", "expected 4 to 30"]);
    texture_address_mode_unknown: ("address", "dependent-dot-lookup", &[("address: Clamp", "address: Border")], Some("Border"),
        &["engine.units[2].unit", "Border", "Wrap", "Clamp", "Mirror"]);
    lighting_table_of_a_missing_light: ("lighting-light", "dependent-dot-lookup", &[("LightingTable(size: 256, light: 0)", "LightingTable(size: 256, light: 3)")], Some("name: \"light\""),
        &["engine.units[2].unit", "light 3", "the scene has 1 lights"]);
}

#[test]
fn vector_inputs_of_different_formats() {
    // h0 (wired to dot.b1) gets a 12-bit format; dot.b0 (l0) stays 10 bits
    let from = "(name: \"h0\", source: HalfVec(light: 0, frame: Tangent), enc: (format: (signed: true, width: 10, frac: 8))),";
    let to = from.replace("width: 10, frac: 8", "width: 12, frac: 10");
    let b = bad("vector-mismatch", "sgi-teapot", &[(from, &to)], &[]);
    fails_at(
        &b,
        Some("name: \"dot\""),
        &[
            "engine.units[1].inputs.b1",
            "port width mismatch",
            "h0 carries",
            "12 bits",
            "must share a format",
        ],
    );
}

#[test]
fn wiring_cycle() {
    // norm reads dot, dot reads norm
    let b = bad(
        "cycle",
        "emboss",
        &[(
            "inputs: {\"v\": \"emboss.n\"},",
            "inputs: {\"v\": \"dot.d0\"},",
        )],
        &[],
    );
    let msg = fails_at(
        &b,
        Some("name: \"norm\""),
        &["engine.units", "cycle", "norm", "dot", "expected a DAG"],
    );
    assert!(
        !msg.contains("emboss,"),
        "emboss is not on the cycle: {msg}"
    );
}

// ---------------------------------------------------------------- files

const TEAPOT_MESH: &str = "Teapot(subdivisions: 8, uv_repeat: (2.0, 2.0))";

/// The teapot config with its mesh read from the OBJ file `name`, and `files` next to it.
fn obj_config(test: &str, name: &str, files: &[(&str, &[u8])]) -> Bad {
    let mesh = format!("Obj(path: \"{name}\", uv_repeat: (1.0, 1.0))");
    bad(test, "sgi-teapot", &[(TEAPOT_MESH, &mesh)], files)
}

/// The teapot config with `obj` as its mesh, `mesh.obj`.
fn mesh_obj(test: &str, obj: &[u8]) -> Bad {
    obj_config(test, "mesh.obj", &[("mesh.obj", obj)])
}

#[test]
fn missing_obj_file() {
    let b = obj_config("obj-missing", "nope.obj", &[]);
    file_fails(&b, "nope.obj", &["scene.mesh", "OBJ", "no such file"]);
}

#[test]
fn corrupt_obj_file() {
    let obj = [0xff, 0xfe, 0x00, 0x13, 0x80, 0x81, b'\n', 0xc3];
    let b = mesh_obj("obj-corrupt", &obj);
    file_fails(&b, "mesh.obj", &["scene.mesh", "could not load OBJ"]);
}

#[test]
fn obj_with_a_zero_area_triangle() {
    // triangle 0 is fine, triangle 1 has three collinear corners
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n\
               vt 0 0\nvt 1 0\nvt 0 1\n\
               f 1/1 2/2 3/3\nf 1/1 2/2 4/3\n";
    let b = mesh_obj("obj-degenerate", obj.as_bytes());
    let needles = ["scene.mesh", "triangle 1", "degenerate (zero area)"];
    file_fails(&b, "mesh.obj", &needles);
}

#[test]
fn obj_with_a_zero_uv_area_triangle() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.5\nf 1/1 2/1 3/1\n";
    let b = mesh_obj("obj-degenerate-uv", obj.as_bytes());
    let needles = ["scene.mesh", "triangle 0", "degenerate texture coordinates"];
    file_fails(&b, "mesh.obj", &needles);
}

const EMBOSS_BUMP: &str = "Bricks(rows: 8, cols: 4, mortar: 0.12, bevel: 0.1, depth: 0.01)";
const GARBAGE_PNG: &[u8] = b"\x89PNX\r\n\x1a\nthis is not a PNG image at all";

#[test]
fn missing_height_png() {
    let to = "HeightPng(path: \"nope.png\", depth: 0.1)";
    let b = bad("png-missing", "emboss", &[(EMBOSS_BUMP, to)], &[]);
    file_fails(&b, "nope.png", &["scene.bump", "could not read"]);
}

/// A bump map of `from` replaced by `to`, which reads `name`: a file that is not a PNG.
fn garbage_png_fails(test: &str, base: &str, from: &str, to: &str, name: &str) {
    let b = bad(test, base, &[(from, to)], &[(name, GARBAGE_PNG)]);
    file_fails(&b, name, &["scene.bump", "PNG"]);
}

#[test]
fn corrupt_height_png() {
    let to = "HeightPng(path: \"bumps.png\", depth: 0.1)";
    garbage_png_fails("png-corrupt", "emboss", EMBOSS_BUMP, to, "bumps.png");
}

#[test]
fn corrupt_normal_png() {
    let from = "MexicanHat(cells: 4, sigma: 0.18, depth: 0.012)";
    let to = "NormalPng(path: \"normals.png\")";
    garbage_png_fails("normal-png-corrupt", "sgi-teapot", from, to, "normals.png");
}

#[test]
fn config_file_that_does_not_exist() {
    let scratch = Scratch::new("bad-no-config");
    let cfg = scratch.join("nope.ron");
    let out = scratch.join("out");
    for cmd in ["render", "report", "check"] {
        let mut args = vec![cmd.to_string(), cfg.display().to_string()];
        if cmd == "render" {
            args.extend(["--out".to_string(), out.display().to_string()]);
        }
        let o = bumpsim(&args);
        o.expect_code(2, &format!("{args:?}"));
        assert!(
            o.stderr.contains(&cfg.display().to_string()),
            "{}",
            o.stderr
        );
        assert!(o.stderr.contains("cannot read the config"), "{}", o.stderr);
    }
    assert!(!out.exists());
}

// ---------------------------------------------------------------- lights and material

const LIGHT0_DIR: &str = "dir: (1.0, 1.0, 1.0)";

config_errors! {
    nan_light_direction: ("light-nan", "sgi-teapot", &[(LIGHT0_DIR, "dir: (NaN, 0.0, 1.0)")], None,
        &["scene.lights[0].kind.dir", "expected a finite non-zero direction", "NaN"]);
    zero_light_direction: ("light-zero", "sgi-teapot", &[(LIGHT0_DIR, "dir: (0.0, 0.0, 0.0)")], None,
        &["scene.lights[0].kind.dir", "expected a finite non-zero direction"]);
}

#[test]
fn light_colour_outside_unit_range() {
    for (k, c) in [(1, "1.2"), (0, "-0.1")] {
        let mut comps = ["0.6", "0.2", "0.6"];
        comps[k] = c;
        let to = format!("color: ({})", comps.join(", "));
        let b = bad(
            &format!("light-colour-{k}"),
            "sgi-teapot",
            &[("color: (0.6, 0.2, 0.6)", &to)],
            &[],
        );
        fails_at(
            &b,
            None,
            &[
                &format!("scene.lights[1].color[{k}]"),
                "expected a value in [0, 1]",
                &format!("found {c}"),
            ],
        );
    }
}

#[test]
fn shininess_zero_and_negative() {
    for (tag, v) in [("zero", "0.0"), ("negative", "-4.0")] {
        let b = bad(
            &format!("shininess-{tag}"),
            "sgi-teapot",
            &[("shininess: 32.0", &format!("shininess: {v}"))],
            &[],
        );
        fails_at(
            &b,
            None,
            &["scene.material.shininess", "expected a number above 0"],
        );
    }
}

/// The lines the errors above point at: the field in question, not a comment that happens
/// to contain the field's name (both configs' header comments mention "lights", "shininess"
/// and "rasterizer").
#[test]
fn scene_errors_point_at_the_field_not_a_comment() {
    let cases: [(&str, &str, &str, &str); 4] = [
        ("pos-light", LIGHT0_DIR, "dir: (NaN, 0.0, 1.0)", "lights: ["),
        (
            "pos-colour",
            "color: (0.6, 0.2, 0.6)",
            "color: (0.6, 1.5, 0.6)",
            "lights: [",
        ),
        (
            "pos-shininess",
            "shininess: 32.0",
            "shininess: 0.0",
            "shininess: 0.0",
        ),
        (
            "pos-raster",
            "setup_cycles: 8",
            "setup_cycles: 0",
            "setup_cycles: 0",
        ),
    ];
    for (test, from, to, field_line) in cases {
        let b = bad(test, "sgi-teapot", &[(from, to)], &[]);
        let msg = fails(&b, &[], &[]);
        let file = b.cfg.display().to_string();
        let (line, _) = position(&msg, &file).unwrap_or_else(|| panic!("no position: {msg}"));
        let src = b.text.lines().nth(line - 1).unwrap_or("");
        assert!(
            !src.trim_start().starts_with("//"),
            "{test}: the error points at a comment, line {line} {src:?}: {msg}"
        );
        // at the field's line, or (for a list) at the list's opening line or below it
        let want = line_of(&b.text, field_line);
        let edited = line_of(&b.text, to);
        assert!(
            line == want || line == edited,
            "{test}: expected line {want} or {edited}, got {line}: {msg}"
        );
    }
}

// ---------------------------------------------------------------- image size

config_errors! {
    image_width_zero: ("size0", "sgi-teapot", &[("width: 256,", "width: 0,")], Some("width: 0,"),
        &["scene.width", "image side 0", "expected 1 to 16384"]);
    image_height_16385: ("size16385", "emboss", &[("height: 256,", "height: 16385,")], Some("height: 16385,"),
        &["scene.height", "image side 16385", "expected 1 to 16384"]);
}

// ---------------------------------------------------------------- arguments

/// A `--set` error on an unmodified config.
fn set_fails(test: &str, set: &str, needles: &[&str]) -> String {
    let b = bad(test, "sgi-teapot", &[], &[]);
    let msg = fails(&b, &["--set", set], needles);
    assert!(
        msg.starts_with("error: --set: "),
        "the message names --set: {msg}"
    );
    msg
}

#[test]
fn set_nonexistent_path() {
    set_fails(
        "set-path",
        "scene.widthh=64",
        &[
            "scene.widthh",
            "no field \"widthh\"",
            "expected one of",
            "width",
        ],
    );
    set_fails(
        "set-path-unit",
        "engine.units.nope.unit.index_bits=4",
        &["engine.units.nope", "no field \"nope\"", "element name"],
    );
}

#[test]
fn set_value_of_the_wrong_type() {
    set_fails(
        "set-type",
        "scene.width=wide",
        &["scene.width", "invalid type", "expected u32"],
    );
    set_fails(
        "set-type-bool",
        "engine.units.spec.unit.index_bits=true",
        &["index_bits", "invalid type", "expected u32"],
    );
    set_fails(
        "set-range",
        "scene.width=0",
        &["scene.width", "image side 0", "expected 1 to 16384"],
    );
    set_fails(
        "set-no-equals",
        "scene.width",
        &["scene.width", "expected path.to.field=value"],
    );
}

/// Run `bumpsim args`: it must exit 2 with every needle on stderr.
fn exits_2(args: &[&str], needles: &[&str]) {
    let o = bumpsim(args);
    o.expect_code(2, &args.join(" "));
    for n in needles {
        assert!(o.stderr.contains(n), "stderr lacks {n:?}: {}", o.stderr);
    }
}

#[test]
fn trace_cycle_window_reversed() {
    let scratch = Scratch::new("bad-trace-window");
    let out = scratch.join("t.txt").display().to_string();
    let cfg = config("sgi-teapot").display().to_string();
    exits_2(
        &["trace", &cfg, "--cycles", "50..10", "--out", &out],
        &["--cycles", "\"50..10\"", "expected A..B with A < B"],
    );
    assert!(!std::path::Path::new(&out).exists());
    assert!(listing(&scratch.path).is_empty());
}

#[test]
fn render_out_onto_an_existing_file() {
    let b = bad("out-is-file", "emboss", &[], &[]);
    let blocker = b.scratch.join("blocker");
    std::fs::write(&blocker, b"keep").unwrap();
    let (cfg, path) = (b.cfg.display().to_string(), blocker.display().to_string());
    exits_2(&["render", &cfg, "--out", &path], &[&path, "--out"]);
    assert_eq!(std::fs::read(&blocker).unwrap(), b"keep");
    // no temporary files are left next to it
    assert_eq!(listing(&b.scratch.path), ["blocker", "out-is-file.ron"]);
}

#[test]
fn trace_out_into_a_missing_directory() {
    let scratch = Scratch::new("bad-trace-out");
    let out = scratch.join("no/such/dir/t.vcd").display().to_string();
    let cfg = config("emboss").display().to_string();
    let args = [
        "trace", &cfg, "--cycles", "10..20", "--format", "vcd", "--out", &out,
    ];
    exits_2(&args, &[&out]);
    assert!(listing(&scratch.path).is_empty());
}

/// Units take `parallel` datapaths; 0 datapaths is no hardware at all and should be rejected
/// like `ports: 0` ("ports 0: expected 1 to 4").
#[test]
fn zero_parallel_datapaths_are_rejected() {
    for (test, unit) in [
        ("par-dot", "dot"),
        ("par-spec", "spec"),
        ("par-shade", "shade"),
    ] {
        let b = bad(test, "sgi-teapot", &[], &[]);
        let set = format!("engine.units.{unit}.unit.parallel=0");
        fails(&b, &["--set", &set], &["parallel", "expected"]);
    }
}

/// With no lights, a `LightDir(light: 0, frame: Tangent)` attribute is reported as "the scene has 0 lights
/// (expected 0 to 0)": index 0 is just what it got, and no index is valid.
#[test]
fn light_index_message_with_no_lights() {
    let b = bad("no-lights", "emboss", &[], &[]);
    let msg = fails(
        &b,
        &["--set", "scene.lights=[]"],
        &["engine.attributes[1].source", "light index 0", "0 lights"],
    );
    assert!(!msg.contains("expected 0 to 0"), "{msg}");
}

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
    // a stale lighting map (docs/studies/embm-limits.md) must be built for a direction
    embm_map_built_for_no_direction: ("built-for", "d3d6-embm-quad",
        &[("SphereLighting(size: 256, light: 0),", "SphereLighting(size: 256, light: 0, built_for: Some((0.0, 0.0, 0.0))),")],
        None,
        &["engine.units[0].unit", "programs[1].texture", "built_for: (0, 0, 0)", "expected a finite, non-zero direction"]);
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
    // a unit's name names its files (`bumpsim rtl`, `gates --synth`): no path in it
    unit_name_with_a_path: ("unit-path", "sgi-teapot", &[("name: \"fetch\"", "name: \"/tmp/x\"")], Some("name: \"/tmp/x\""),
        &["engine.units[0].name", "\"/tmp/x\"", "expected a unique name of ASCII letters, digits, '_' and '-'"]);
    // the cycle report and traces name the scan converter, setup and ROP beside the units
    unit_name_of_the_back_end: ("unit-rop", "sgi-teapot", &[("name: \"spec\"", "name: \"rop\""), ("\"spec.y0\"", "\"rop.y0\""), ("\"spec.y1\"", "\"rop.y1\"")], Some("name: \"rop\""),
        &["engine.units[2].name", "\"rop\"", "front or back end", "reserved: setup, scan, rop"]);
    unit_name_of_the_front_end: ("unit-scan", "sgi-teapot", &[("name: \"fetch\"", "name: \"scan\""), ("\"fetch.t\"", "\"scan.t\"")], Some("name: \"scan\""),
        &["engine.units[0].name", "\"scan\"", "reserved: setup, scan, rop"]);
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

/// `bumpsim check CFG [extra]` must succeed (exit 0).
fn checks_ok(b: &Bad, extra: &[&str]) -> String {
    let mut args: Vec<String> = vec!["check".into(), b.cfg.display().to_string()];
    args.extend(extra.iter().map(|s| s.to_string()));
    let o = bumpsim(&args);
    o.expect_code(0, &format!("{args:?}"));
    o.stdout
}

#[test]
fn obj_with_a_zero_area_triangle_drops_it() {
    // triangle 0 is fine, triangle 1 has three collinear corners: dropped (docs/assets.md)
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n\
               vt 0 0\nvt 1 0\nvt 0 1\n\
               f 1/1 2/2 3/3\nf 1/1 2/2 4/3\n";
    let b = mesh_obj("obj-degenerate", obj.as_bytes());
    assert!(checks_ok(&b, &[]).contains("(1 triangles"));
    // only zero-area faces: an error that says so
    let b = mesh_obj(
        "obj-all-degenerate",
        b"v 0 0 0\nv 1 0 0\nv 2 0 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n",
    );
    file_fails(&b, "mesh.obj", &["scene.mesh", "non-zero area", "1 faces"]);
}

#[test]
fn obj_with_a_zero_uv_area_triangle_names_the_line() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.5\nf 1/1 2/1 3/1\n";
    let b = mesh_obj("obj-degenerate-uv", obj.as_bytes());
    let needles = ["scene.mesh", "line 5", "degenerate texture coordinates"];
    file_fails(&b, "mesh.obj", &needles);
}

/// A tetrahedron with texture coordinates, plus `extra` lines.
fn tetra(extra: &str) -> String {
    format!(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 5 5 5\n\
         vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n\
         f 1/1 3/3 2/2\nf 1/1 2/2 4/4\nf 1/1 4/4 3/3\nf 2/2 3/3 4/4\n{extra}"
    )
}

#[test]
fn obj_scan_defects_load_under_the_documented_rule() {
    // an exact duplicate face, a back-to-back copy, a zero-area face, an unreferenced vertex
    // (v 5 5 5): the first copy of a face is kept, the rest dropped
    let obj = tetra("f 1/1 3/3 2/2\nf 1/1 2/2 3/3\nf 1/1 1/1 2/2\n");
    let b = mesh_obj("obj-scan", obj.as_bytes());
    assert!(checks_ok(&b, &[]).contains("(4 triangles"));
    // a sheet of two back-to-back faces alone: one is kept, its normal defined
    let sheet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 2/2\n";
    let b = mesh_obj("obj-sheet", sheet.as_bytes());
    assert!(checks_ok(&b, &[]).contains("(1 triangles"));
    // the same with a generated atlas
    let b = bad(
        "obj-sheet-atlas",
        "sgi-teapot",
        &[(
            TEAPOT_MESH,
            "Obj(path: \"mesh.obj\", uv_repeat: (1.0, 1.0), atlas: true)",
        )],
        &[("mesh.obj", sheet.as_bytes())],
    );
    assert!(checks_ok(&b, &[]).contains("(1 triangles"));
}

#[test]
fn obj_vertex_whose_face_normals_cancel_gets_a_normal() {
    // vertex 5 is the tip of two faces folded onto each other (a zero-volume fin): their
    // area-weighted normals cancel; the documented fallback gives it one
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 2 0\n\
               vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvt 0.5 0.5\n\
               f 1/1 2/2 4/4\nf 1/1 4/4 3/3\nf 2/2 5/5 4/4\nf 3/3 5/5 4/4\n";
    let b = mesh_obj("obj-fold", obj.as_bytes());
    checks_ok(&b, &[]);
}

#[test]
fn obj_face_without_texture_coordinates_names_its_line() {
    let obj = tetra("f 1 2 3\n");
    let b = mesh_obj("obj-no-vt", obj.as_bytes());
    file_fails(
        &b,
        "mesh.obj",
        &["scene.mesh", "line 14", "without texture coordinates (vt)"],
    );
}

#[test]
fn obj_coordinate_beyond_f32_is_out_of_range_with_its_line() {
    let obj = tetra("").replace("v 5 5 5", "v 5 1e39 5");
    let b = mesh_obj("obj-big", obj.as_bytes());
    file_fails(
        &b,
        "mesh.obj",
        &["scene.mesh", "line 5", "1e39 is out of range", "f32"],
    );
}

#[test]
fn a_directory_as_a_mesh_or_image_is_named_a_directory() {
    let b = obj_config("obj-dir", "meshdir", &[]);
    std::fs::create_dir(b.scratch.join("meshdir")).unwrap();
    file_fails(&b, "meshdir", &["scene.mesh", "is a directory"]);
    let to = "HeightPng(path: \"pngdir\", depth: 0.1)";
    let b = bad("png-dir", "emboss", &[(EMBOSS_BUMP, to)], &[]);
    std::fs::create_dir(b.scratch.join("pngdir")).unwrap();
    file_fails(&b, "pngdir", &["scene.bump", "is a directory"]);
}

/// A PNG file with only a signature and an IHDR chunk of `w` x `h` 8-bit grey pixels: its
/// dimensions are read, nothing is decoded.
fn png_header(w: u32, h: u32) -> Vec<u8> {
    fn crc(bytes: &[u8]) -> u32 {
        let mut c = 0xffff_ffffu32;
        for &b in bytes {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 == 1 {
                    0xedb8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend(w.to_be_bytes());
    ihdr.extend(h.to_be_bytes());
    ihdr.extend([8, 0, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    png.extend(13u32.to_be_bytes());
    png.extend(&ihdr);
    png.extend(crc(&ihdr).to_be_bytes());
    png
}

#[test]
fn an_8192_png_is_refused_from_its_header() {
    let to = "HeightPng(path: \"big.png\", depth: 0.1)";
    let b = bad(
        "png-8192",
        "emboss",
        &[(EMBOSS_BUMP, to)],
        &[("big.png", &png_header(8192, 8192))],
    );
    file_fails(
        &b,
        "big.png",
        &[
            "scene.bump",
            "8192 x 8192 pixels",
            "expected 1 to 4096",
            "before decoding",
        ],
    );
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

// ---------------------------------------------------------------- strict schema (issue 10)

config_errors! {
    // unknown keys inside struct variants used to be ignored (exit 0, same hash)
    unknown_key_in_a_light_kind: ("light-kind-key", "sgi-teapot", &[(LIGHT0_DIR, "dir: (1.0, 1.0, 1.0), dirr: (0.0, 1.0, 0.0)")], Some("dirr:"),
        &["scene.lights[0].kind.Directional.dirr", "dirr", "expected", "dir"]);
    unknown_key_in_an_attribute_source: ("attr-source-key", "sgi-teapot", &[("LightDir(light: 0, frame: Tangent)", "LightDir(light: 0, frame: Tangent, per_triangel: true)")], Some("per_triangel"),
        &["engine.attributes[1].source.LightDir.per_triangel", "per_triangel", "per_triangle"]);
    unknown_key_in_a_bump_map: ("bump-key", "emboss", &[("mortar: 0.12,", "mortar: 0.12, mortr: 0.2,")], Some("mortr"),
        &["scene.bump.Bricks.mortr", "mortr", "mortar"]);
    unknown_key_in_a_material_model: ("shading-key", "quantized-cartoon", &[("Cartoon(bands: ", "Cartoon(band: 2, bands: ")], Some("band:"),
        &["Cartoon.band", "`band`", "bands"]);
}

/// The canonical RON of a config (one line, no struct names) and the byte offsets of every
/// `(` that opens named fields (a struct, or a struct variant `Name(field: ...`), with the
/// name it is known by: the variant's name, or the field's that holds the struct.
fn named_field_groups(canon: &str) -> Vec<(usize, String)> {
    let b = canon.as_bytes();
    let ident = |i: usize| {
        let mut j = i;
        while j < b.len() && (b[j].is_ascii_alphanumeric() || b[j] == b'_') {
            j += 1;
        }
        j
    };
    let (mut groups, mut in_str, mut i) = (Vec::new(), false, 0);
    while i < b.len() {
        match b[i] {
            b'\\' if in_str => i += 1,
            b'"' => in_str = !in_str,
            b'(' if !in_str => {
                let j = ident(i + 1);
                if j > i + 1 && b.get(j) == Some(&b':') {
                    // the name before the bracket, or the field name before `name:(`
                    let mut k = i;
                    while k > 0 && (b[k - 1].is_ascii_alphanumeric() || b[k - 1] == b'_') {
                        k -= 1;
                    }
                    let name = if k < i {
                        canon[k..i].to_string()
                    } else {
                        let end = canon[..i].trim_end_matches([':', '(']);
                        let s = end
                            .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                            .map_or(0, |p| p + 1);
                        format!("({})", &end[s..])
                    };
                    groups.push((i, name));
                }
            }
            _ => {}
        }
        i += 1;
    }
    groups
}

/// The schema walk: for every bundled config (and test fixture), every struct and struct
/// variant it contains gets a bogus key in turn (in the config's canonical RON), and parsing
/// must fail with a clean error that names the key. A struct or enum that forgets
/// `deny_unknown_fields` makes this test fail.
#[test]
fn every_struct_in_every_config_rejects_an_unknown_key() {
    use bumpsim_pipeline::config;
    let mut files = configs();
    files.extend(
        std::fs::read_dir(root().join("tests/fixtures"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "ron")),
    );
    let key = "zz_bogus_key";
    let (mut checked, mut accepted) = (0, Vec::new());
    let mut names = std::collections::BTreeSet::new();
    for path in &files {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).unwrap();
        let parsed = config::parse(&text, &file).unwrap_or_else(|e| panic!("{e}"));
        let canon = config::canonical(&parsed);
        // the canonical form is itself a config, with the same hash
        assert_eq!(config::parse(&canon, &file).unwrap(), parsed);
        let groups = named_field_groups(&canon);
        assert!(groups.len() >= 10, "{file}: only {} structs", groups.len());
        for (at, name) in groups {
            let mutated = format!("{}{key}: 0, {}", &canon[..=at], &canon[at + 1..]);
            names.insert(name.clone());
            checked += 1;
            match config::parse(&mutated, &file) {
                Ok(_) => accepted.push(format!("{file}: {name} at byte {at}")),
                Err(e) => {
                    assert!(
                        e.field.ends_with(key) && e.message.contains(key) && e.pos.is_some(),
                        "{file}: {name} at byte {at}: the error does not name the key: {e}"
                    );
                }
            }
        }
    }
    assert!(
        accepted.is_empty(),
        "{} structs ignore an unknown key (add #[serde(deny_unknown_fields)]):\n{}",
        accepted.len(),
        accepted.join("\n")
    );
    // the walk reaches the schema's structs and struct variants
    for n in [
        "(scene)",
        "(camera)",
        "Directional",
        "LightDir",
        "HalfVec",
        "Gouraud",
        "Bricks",
        "Teapot",
        "Dot3",
        "TexFetch",
        "(cost)",
        "(format)",
        "(raster)",
        "(material)",
    ] {
        assert!(names.contains(n), "no config has {n}: {names:?}");
    }
    assert!(checked > 1000, "only {checked} structs checked");
}

/// Types deserialized with derive but not read from a config (built by the engine from
/// config fields): exempt from the source check below.
const NOT_CONFIG_SYNTAX: &[&str] = &[
    "LightingFn",
    "BuilderFormats",
    "BumpBlendParams",
    "LightState",
];

/// The source check: every type in `pipeline/src` and `hw/src` that derives `Deserialize`
/// and has named fields (a braced struct, or an enum with a struct variant) says
/// `deny_unknown_fields`, so a new struct that no bundled config uses yet is caught too.
#[test]
fn every_deserialized_struct_in_the_source_denies_unknown_fields() {
    fn rust_files(dir: &std::path::Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                rust_files(&p, out);
            } else if p.extension().is_some_and(|e| e == "rs") {
                out.push(p);
            }
        }
    }
    let mut files = Vec::new();
    rust_files(&root().join("pipeline/src"), &mut files);
    rust_files(&root().join("hw/src"), &mut files);
    files.sort();
    let (mut missing, mut seen) = (Vec::new(), 0);
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let mut attrs = String::new();
        for (i, line) in lines.iter().enumerate() {
            let t = line.trim_start();
            if t.starts_with("#[") || (!attrs.is_empty() && !t.starts_with("///") && !is_item(t)) {
                attrs.push_str(t);
                continue;
            }
            if t.starts_with("///") || t.starts_with("//") {
                continue;
            }
            if !attrs.contains("Deserialize") || !is_item(t) {
                attrs.clear();
                continue;
            }
            let words: Vec<&str> = t
                .split(|c: char| !(c.is_alphanumeric() || c == '_'))
                .collect();
            let kind = if words.contains(&"struct") {
                "struct"
            } else {
                "enum"
            };
            let name = words
                .iter()
                .skip_while(|w| **w != kind)
                .nth(1)
                .copied()
                .unwrap_or("?");
            let indent = line.len() - t.len();
            let named = if kind == "struct" {
                t.trim_end().ends_with('{')
            } else {
                // a variant line `Name {` one level in, before the enum's closing brace
                lines[i + 1..]
                    .iter()
                    .take_while(|l| l.trim_end() != format!("{}}}", " ".repeat(indent)))
                    .any(|l| {
                        let v = l.trim();
                        l.len() - l.trim_start().len() == indent + 4
                            && v.ends_with('{')
                            && v.starts_with(|c: char| c.is_ascii_uppercase())
                    })
            };
            let converted = ["try_from", "from =", "transparent"]
                .iter()
                .any(|a| attrs.contains(a));
            if named {
                seen += 1;
                let exempt = NOT_CONFIG_SYNTAX.contains(&name);
                if !attrs.contains("deny_unknown_fields") && !converted && !exempt {
                    let rel = f.strip_prefix(root()).unwrap_or(f);
                    missing.push(format!("{}:{}: {kind} {name}", rel.display(), i + 1));
                }
            }
            attrs.clear();
        }
    }
    assert!(
        seen > 20,
        "only {seen} types found: is the check still reading the source?"
    );
    assert!(
        missing.is_empty(),
        "these types derive Deserialize with named fields but accept unknown keys (add \
         #[serde(deny_unknown_fields)]):\n{}",
        missing.join("\n")
    );
}

/// A line that starts a struct or enum item.
fn is_item(t: &str) -> bool {
    let t = t
        .strip_prefix("pub(crate) ")
        .or_else(|| t.strip_prefix("pub(super) "))
        .or_else(|| t.strip_prefix("pub "))
        .unwrap_or(t);
    t.starts_with("struct ") || t.starts_with("enum ")
}

// ---------------------------------------------------------------- gate-cost overrides

#[test]
fn gate_cost_overrides_must_be_finite_and_not_negative() {
    for (tag, price, shown) in [
        ("nan", "NaN", "price NaN"),
        ("inf", "inf", "price inf"),
        ("neg", "-2.5", "price -2.5"),
        ("big", "1e9", "price 1000000000"),
    ] {
        let to = format!("name: \"emboss\",\n    cost: (inv: 0.67, full_adder: {price}),");
        let b = bad(
            &format!("cost-{tag}"),
            "emboss",
            &[("name: \"emboss\",", &to)],
            &[],
        );
        fails_at(
            &b,
            Some("full_adder:"),
            &[
                "cost.full_adder",
                shown,
                "expected a finite number of gate equivalents from 0 to",
            ],
        );
    }
    // the same through --set (which takes no NaN at all)
    let b = bad("cost-set", "emboss", &[], &[]);
    fails(
        &b,
        &["--set", "cost.sram_bit=-1"],
        &[
            "with --set cost.sram_bit=-1",
            "cost.sram_bit",
            "price -1",
            "expected a finite number",
        ],
    );
    let msg = set_fails(
        "cost-set-nan",
        "cost.sram_bit=NaN",
        &["cost.sram_bit", "NaN"],
    );
    assert!(msg.contains("not allowed"), "{msg}");
    // the memory kind of the tables: one of four, and so are the new prices
    set_fails(
        "cost-tables",
        "cost.tables=Dram",
        &[
            "cost.tables",
            "unknown variant `Dram`",
            "`Sram`, `LatchRam`, `FlopRam`, `Rom`",
        ],
    );
    fails(
        &b,
        &["--set", "cost.flop_ram_bit=-2"],
        &[
            "with --set cost.flop_ram_bit=-2",
            "cost.flop_ram_bit",
            "price -2",
        ],
    );
}

#[test]
fn gate_cost_of_zero_is_accepted() {
    let b = bad(
        "cost-zero",
        "emboss",
        &[(
            "name: \"emboss\",",
            "name: \"emboss\", cost: (rom_bit: 0.0),",
        )],
        &[],
    );
    bumpsim(&["check".to_string(), b.cfg.display().to_string()]).expect_code(0, "rom_bit 0");
}

// ---------------------------------------------------------------- bounded input

#[test]
fn dev_zero_as_the_config_is_refused_after_16_mib() {
    let o = bumpsim(&["check", "/dev/zero"]);
    o.expect_code(2, "check /dev/zero");
    assert!(
        o.stderr.contains("/dev/zero") && o.stderr.contains("larger than 16 MiB"),
        "{}",
        o.stderr
    );
}

#[test]
fn an_oversized_config_file_is_refused() {
    let b = bad("huge", "emboss", &[], &[]);
    // a valid config padded with a comment past the limit
    let mut text = b.text.clone();
    text.push_str("\n// ");
    text.push_str(&"x".repeat(16 << 20));
    std::fs::write(&b.cfg, text).unwrap();
    fails(
        &b,
        &[],
        &["huge.ron", "cannot read the config", "larger than 16 MiB"],
    );
}

#[test]
fn a_directory_as_the_config_is_named_a_directory() {
    let scratch = Scratch::new("bad-config-dir");
    let dir = scratch.join("configs.ron");
    std::fs::create_dir(&dir).unwrap();
    for cmd in ["check", "report"] {
        let o = bumpsim(&[cmd, &dir.display().to_string()]);
        o.expect_code(2, cmd);
        assert!(
            o.stderr.contains(&dir.display().to_string())
                && o.stderr
                    .contains("cannot read the config: it is a directory"),
            "{}",
            o.stderr
        );
    }
}

#[test]
fn a_config_that_is_not_utf8_is_named_so() {
    let b = bad("not-utf8", "emboss", &[], &[]);
    let mut bytes = b.text.clone().into_bytes();
    bytes.insert(3, 0xff);
    std::fs::write(&b.cfg, bytes).unwrap();
    fails(&b, &[], &["not-utf8.ron", "not UTF-8", "offset 3"]);
}

#[test]
fn a_byte_order_mark_is_accepted_with_the_same_hash() {
    let b = bad("bom", "emboss", &[], &[]);
    let plain = bumpsim(&["check".to_string(), b.cfg.display().to_string()]);
    plain.expect_code(0, "without a BOM");
    std::fs::write(&b.cfg, format!("\u{feff}{}", b.text)).unwrap();
    let bom = bumpsim(&["check".to_string(), b.cfg.display().to_string()]);
    bom.expect_code(0, "with a BOM");
    assert_eq!(bom.stdout, plain.stdout, "same config, same hash");
}

#[test]
fn set_values_nest_a_bounded_depth() {
    for (tag, open, close) in [("sq", "[", "]"), ("par", "(", ")"), ("map", "{\"a\":", "}")] {
        let v = format!("{}1{}", open.repeat(20_000), close.repeat(20_000));
        let msg = set_fails(
            &format!("set-deep-{tag}"),
            &format!("scene.lights={v}"),
            &[
                "scene.lights",
                "nested more than 128 levels",
                "expected at most 128",
                "bytes)",
            ],
        );
        assert!(msg.len() < 400, "the value is abbreviated: {msg}");
    }
    // an unclosed one too
    set_fails(
        "set-deep-open",
        &format!("scene.lights={}", "[".repeat(20_000)),
        &["nested more than 128"],
    );
}

// ---------------------------------------------------------------- outputs

#[test]
fn a_failed_render_leaves_no_output_parent_behind() {
    let b = bad("stray-parent", "emboss", &[], &[]);
    let out = b.scratch.join("a").join("x".repeat(300));
    let (cfg, path) = (b.cfg.display().to_string(), out.display().to_string());
    exits_2(
        &["render", &cfg, "--out", &path],
        &["--out", "cannot create output directory"],
    );
    assert_eq!(
        listing(&b.scratch.path),
        ["stray-parent.ron"],
        "a/ was left behind"
    );
    // and a render that succeeds creates the parents
    let ok = b.scratch.join("a").join("b");
    bumpsim(&["render", &cfg, "--out", &ok.display().to_string()]).expect_code(0, "render");
    assert_eq!(
        listing(&ok),
        ["error.png", "image.png", "reference.png", "report.json"]
    );
}

// ---------------------------------------------------------------- messages

config_errors! {
    // it said "scene.?: Expected comma"
    fractional_image_width: ("width-frac", "sgi-teapot", &[("width: 256,", "width: 256.5,")], Some("width: 256.5"),
        &["scene.width", "expected an integer, found 256.5"]);
    exponent_image_width: ("width-exp", "sgi-teapot", &[("width: 256,", "width: 2.56e2,")], Some("width: 2.56e2"),
        &["scene.width", "expected an integer, found 2.56e2"]);
    fractional_unit_count: ("count-frac", "sgi-teapot", &[("Dot3(count: 4,", "Dot3(count: 4.0,")], Some("count: 4.0"),
        &["engine.units[1].unit.Dot3.count", "expected an integer, found 4.0"]);
    // a NaN no check looks at used to render (or reach --set as null): every number is finite
    nan_in_an_unchecked_field: ("mortar-nan", "emboss", &[("mortar: 0.12,", "mortar: NaN,")], Some("mortar: NaN"),
        &["scene.bump.Bricks.mortar", "expected a finite number, found NaN"]);
    overflowing_literal_is_infinite: ("depth-inf", "emboss", &[("depth: 0.01)", "depth: 1e400)")], Some("depth: 1e400"),
        &["scene.bump.Bricks.depth", "expected a finite number, found inf"]);
}

#[test]
fn nan_in_the_file_with_a_set_names_the_field_not_null() {
    let b = bad(
        "nan-set",
        "emboss",
        &[("mortar: 0.12,", "mortar: NaN,")],
        &[],
    );
    let msg = fails(
        &b,
        &["--set", "scene.width=64"],
        &[
            "scene.bump.Bricks.mortar",
            "expected a finite number, found NaN",
        ],
    );
    assert!(
        msg.starts_with(&format!("error: {}:", b.cfg.display())),
        "names the file: {msg}"
    );
    assert!(
        !msg.contains("null") && !msg.starts_with("error: --set"),
        "{msg}"
    );
    let line = line_of(&b.text, "mortar: NaN");
    assert_eq!(
        position(&msg, &b.cfg.display().to_string()).map(|p| p.0),
        Some(line),
        "{msg}"
    );
}

// ---------------------------------------------------------------- ranges that bound work

config_errors! {
    // 2^31 port names used to be allocated (51 GB) before the range check
    unit_count_of_2_pow_31: ("count-2-31", "sgi-teapot", &[("Dot3(count: 4,", "Dot3(count: 2147483648,")], Some("name: \"dot\""),
        &["engine.units[1].unit.count", "count 2147483648", "expected 1 to 8"]);
    // u32::MAX used to wrap the latency to fewer cycles than 4
    mem_latency_beyond_its_range: ("mem-latency", "sgi-teapot", &[("mem_latency: 4,", "mem_latency: 4294967295,")], Some("name: \"fetch\""),
        &["engine.units[0].unit.mem_latency", "expected 1 to 1024 cycles"]);
    mem_latency_2_pow_31: ("mem-latency-31", "emboss", &[("mem_latency: 4,", "mem_latency: 2147483648,")], None,
        &["mem_latency", "expected 1 to 1024 cycles"]);
    palette_beyond_its_range: ("palette-range", "sgi-teapot", &[("mem_latency: 4,", "mem_latency: 4, palette: 65537,")], Some("name: \"fetch\""),
        &["engine.units[0].unit.palette", "expected 2 to 65536"]);
    light_direction_whose_length_overflows: ("light-1e154", "sgi-teapot", &[("Directional(dir: (1.0, 1.0, 1.0))", "Directional(dir: (1e154, 1e154, 1e154))")], Some("lights:"),
        &["scene.lights[0].kind.dir", "out of range", "overflow"]);
    far_plane_that_overflows_the_projection: ("far-1e308", "sgi-teapot", &[("far: 30.0", "far: 1e308")], Some("camera:"),
        &["scene.camera.far", "out of range", "at most 1e12"]);
    eye_beyond_the_coordinate_range: ("eye-1e200", "sgi-teapot", &[("eye: (0.0, 3.5, 8.0)", "eye: (0.0, 3.5, 8e200)")], Some("camera:"),
        &["scene.camera.eye", "out of range"]);
    model_scale_beyond_its_range: ("scale-1e300", "sgi-teapot", &[("model: (translate: (-0.2, -1.2, 0.0))", "model: (translate: (-0.2, -1.2, 0.0), scale: 1e300)")], Some("model:"),
        &["scene.model.scale", "1e-12 < abs(scale) <= 1e12"]);
}

/// `bumpsim check CONFIG --set ...` of a bundled config exits 2 with every needle; with
/// `--force` it passes the estimate (check builds the scene and the engine).
fn over_budget(cfg: &str, sets: &[&str], needles: &[&str], forced_ok: bool) {
    let path = config(cfg).display().to_string();
    let mut args = vec!["check", path.as_str()];
    for s in sets {
        args.extend(["--set", s]);
    }
    let mut all = vec!["over the budget", "--force", "2-core, 24 GB"];
    all.extend_from_slice(needles);
    exits_2(&args, &all);
    if forced_ok {
        args.push("--force");
        bumpsim(&args).expect_code(0, &args.join(" "));
    }
}

#[test]
fn a_16384_square_image_is_over_the_estimate() {
    // aborted after 4.6 GB; --force runs `check` (no render)
    over_budget(
        "sgi-teapot",
        &["scene.width=16384", "scene.height=16384"],
        &["scene.width x scene.height", "GiB"],
        true,
    );
}

#[test]
fn uv_repeat_1e5_on_a_quantized_config_is_over_the_estimate() {
    over_budget(
        "quantized-sphere",
        &["scene.mesh.uv_repeat=[100000.0,100000.0]"],
        &["engine.units[0].unit.size^2", "uv area"],
        false,
    );
}

#[test]
fn palette_65536_on_a_4096_texture_is_over_the_estimate() {
    over_budget(
        "sgi-teapot",
        &[
            "engine.units.fetch.unit.source.size=4096",
            "engine.units.fetch.unit.palette=65536",
        ],
        &["engine.units[0].unit.palette = 65536"],
        false,
    );
}

#[test]
fn kmeans_16384_entries_300_iterations_is_over_the_estimate() {
    over_budget(
        "quantized-sphere",
        &[
            "engine.units.qnm.unit.index_bits=14",
            "engine.units.qnm.unit.s_n=16384",
            "engine.units.qnm.unit.quantizer=KMeans(start:MedianCut,max_iterations:300)",
        ],
        &["k-means", "s_n = 16384", "max_iterations = 300"],
        false,
    );
}

#[test]
fn force_does_not_go_past_a_hard_limit() {
    let cfg = config("sgi-teapot").display().to_string();
    exits_2(
        &[
            "check",
            &cfg,
            "--force",
            "--set",
            "engine.units.dot.unit.count=2147483648",
        ],
        &["engine.units[1].unit.count", "expected 1 to 8"],
    );
}

#[test]
fn trace_cycle_window_beyond_a_million_says_so() {
    let scratch = Scratch::new("bad-trace-window-long");
    let out = scratch.join("t.txt").display().to_string();
    let cfg = config("sgi-teapot").display().to_string();
    exits_2(
        &["trace", &cfg, "--cycles", "0..2000000", "--out", &out],
        &[
            "--cycles",
            "window of 2000000 cycles",
            "at most 1000000 cycles",
        ],
    );
    assert!(listing(&scratch.path).is_empty());
}

// Found by tests/config_mutation.rs (docs/fuzzing.md): an override without a path or without
// a value names the `--set` argument and what was expected.
#[test]
fn set_without_a_path_or_a_value() {
    set_fails(
        "set-empty-path",
        "=1",
        &["empty path", "expected path.to.field=value"],
    );
    set_fails(
        "set-no-value",
        "scene.width",
        &["\"scene.width\"", "expected path.to.field=value"],
    );
}

// Found by tests/config_mutation.rs: a finite but huge `uv_repeat` (1e39) is accepted by the
// mesh range (finite > 0) and refused by the estimate, which names the field, before any bake.
#[test]
fn huge_uv_repeat_is_refused_by_the_estimate() {
    let b = bad(
        "huge-uv-repeat",
        "quantized-plane-mipmap",
        &[("uv_repeat: (1.0, 1.0)", "uv_repeat: (1e39, 1.0)")],
        &[],
    );
    fails(&b, &[], &["uv_repeat", "over the budget", "--force"]);
}

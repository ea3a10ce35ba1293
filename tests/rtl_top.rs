//! `bumpsim rtl CONFIG --out DIR --cosim N`: the engine's top (`engine.v`, every generated
//! unit wired as the config wires it) co-simulated on N fragments of the rendered frame, the
//! attribute words the interpolator gave them in, the engine's output words out. iverilog is
//! required (`.ci/install-iverilog.sh`): the tests **fail** without it unless
//! `BUMPSIM_SKIP_IVERILOG=1` is set.

mod common;

use common::*;
use std::process::Command;

fn engine_line(stdout: &str) -> &str {
    stdout
        .lines()
        .find(|l| l.starts_with("engine "))
        .unwrap_or_else(|| panic!("no engine line in {stdout}"))
}

#[test]
fn the_engine_top_replays_the_frames_own_fragments() {
    // four units with host registers and a texture memory (sgi-teapot); a concatenation wire
    // `cat(dot.d0, dot.d1)` (dependent-dot-lookup); a swizzled output and 107 host registers
    // (nv20-combiner-bump); a unit with a frame phase (quantized-sn16); the cube-map
    // programs with a reflection and four concatenations (nv20-reflect-cube)
    // (the reflect group's iverilog run is the longest: 40 fragments)
    for (name, latency, regs, n) in [
        ("sgi-teapot", 13, 15, 150),
        ("dependent-dot-lookup", 12, 0, 150),
        ("nv20-combiner-bump", 15, 107, 150),
        ("quantized-sn16", 7, 9, 150),
        ("nv20-reflect-cube", 17, 107, 40),
    ] {
        let Some((_s, out, o)) = rtl_cosim(name, &n.to_string(), "top-replay") else {
            return;
        };
        let line = engine_line(&o.stdout);
        assert!(
            line.contains(&format!("latency {latency}  registers {regs}"))
                && line.contains(&format!("cosim {n} fragments of the frame, 0 mismatches")),
            "{name}: {line}"
        );
        let v = std::fs::read_to_string(out.join("engine.v")).unwrap();
        assert!(v.contains("module bumpsim_engine ("), "{name}");
        let regs_file = std::fs::read_to_string(out.join("engine.regs")).unwrap();
        assert_eq!(
            regs_file.lines().filter(|l| !l.starts_with('#')).count(),
            regs,
            "{name}"
        );
    }
}

#[test]
fn the_top_is_wired_as_the_config_wires_it() {
    let Some((_s, out, _)) = rtl_cosim("dependent-dot-lookup", "20", "top-wiring") else {
        return;
    };
    let v = std::fs::read_to_string(out.join("engine.v")).unwrap();
    // the lookup's (s, t) is the concatenation of the two 1-lane dot products
    assert!(
        v.contains(".uv_0(u_dot_d0)") && v.contains(".uv_1(u_dot_d1)"),
        "{v}"
    );
}

#[test]
fn a_wrong_expected_word_is_a_mismatch() {
    // the comparison is live: one flipped bit in the model's words is one mismatch
    let Some((_s, out, _)) = rtl_cosim("sgi-teapot", "40", "top-flip") else {
        return;
    };
    let dir = out.join("cosim").join("engine");
    let hex = std::fs::read_to_string(dir.join("out.hex")).unwrap();
    let mut lines: Vec<String> = hex.lines().map(str::to_string).collect();
    let w = u32::from_str_radix(&lines[7], 16).unwrap() ^ 1;
    lines[7] = format!("{w:08x}");
    std::fs::write(dir.join("out.hex"), lines.join("\n") + "\n").unwrap();
    let vvp = Command::new("vvp")
        .current_dir(&dir)
        .args(["-n", "tb.vvp"])
        .output()
        .expect("vvp runs");
    let text = String::from_utf8_lossy(&vvp.stdout);
    assert!(
        text.contains("RESULT vectors=40 mismatches=1 latency_errors=0"),
        "{text}"
    );
}

#[test]
fn a_unit_without_a_generator_leaves_no_top() {
    let s = Scratch::new("rtl-top-none");
    let out = s.join("rtl");
    // every bundled config's units have a generator: the builder's interpolated power table
    // has none
    let cfg = config("quantized-sphere");
    let (cfg, out_s) = (cfg.to_str().unwrap(), out.to_str().unwrap());
    let o = bumpsim(&["rtl", cfg, "--out", out_s, "--set", common::LERP_POWER]);
    o.expect_code(0, "rtl");
    assert!(
        o.stdout
            .contains("engine top not generated: 1 of 1 units have no generator"),
        "{}",
        o.stdout
    );
    assert!(!listing(&out).iter().any(|f| f == "engine.v"));
}

#[test]
fn a_texture_shader_engine_has_a_top() {
    // wang-bunny-hilo: TEXTURE_2D of a HILO map, DOT_PRODUCT, DOT_PRODUCT_TEXTURE_2D
    let Some((_s, out, o)) = rtl_cosim("wang-bunny-hilo", "150", "top-shader") else {
        return;
    };
    let line = engine_line(&o.stdout);
    assert!(
        line.contains("latency 7  registers 0")
            && line.contains("cosim 150 fragments of the frame, 0 mismatches"),
        "{line}"
    );
    assert!(
        o.stdout.contains("shader       texture_shader shader.v"),
        "{}",
        o.stdout
    );
    assert!(out.join("bumpsim_shader_tex0.hex").exists());
}

//! `bumpsim rtl CONFIG --out DIR [--cosim N]` on the units whose Verilog is generated from the
//! engine's own unit: the quantized normal maps unit (baked; the files, the frame phase) and
//! the register combiners (the program in host registers), each co-simulated with iverilog,
//! which is required (`.ci/install-iverilog.sh`): the tests **fail** without it unless
//! `BUMPSIM_SKIP_IVERILOG=1` is set.

mod common;

use common::*;

#[test]
fn the_quantized_unit_cosimulates_from_the_engines_own_unit() {
    let Some((_s, out, o)) = rtl_cosim("quantized-sn16", "400", "cmd") else {
        return;
    };
    // Lambert, one light: 16 slots and the 4-clock pipeline; the model adds the LUT load
    assert!(
        o.stdout.contains("frame 20 clocks (model 32)")
            && o.stdout.contains("cosim 400 vectors, 0 mismatches"),
        "{}",
        o.stdout
    );
    let files = listing(&out);
    for f in [
        "qnm.v",
        "qnm.regs",
        "bumpsim_qnm_indices.hex",
        "bumpsim_qnm_normals.hex",
    ] {
        assert!(files.iter().any(|x| x == f), "{f} not in {files:?}");
    }
    // the colour table is written by the builder: no contents file
    assert!(!files.iter().any(|x| x.contains("colours")), "{files:?}");
    let normals = std::fs::read_to_string(out.join("bumpsim_qnm_normals.hex")).unwrap();
    assert_eq!(normals.lines().count(), 16);
    let regs = std::fs::read_to_string(out.join("qnm.regs")).unwrap();
    // 3 vector words, 3 coefficients, 3 ambient words
    assert_eq!(
        regs.lines().filter(|l| !l.starts_with('#')).count(),
        9,
        "{regs}"
    );
}

#[test]
fn a_function_without_a_generator_is_named() {
    let s = Scratch::new("rtl-lerp");
    let out = s.join("rtl");
    let cfg = config("quantized-sphere");
    let (cfg, out) = (cfg.to_str().unwrap(), out.to_str().unwrap());
    let o = bumpsim(&["rtl", cfg, "--out", out, "--set", common::LERP_POWER]);
    o.expect_code(0, "rtl");
    assert!(
        o.stdout.contains(
            "not generated: material 0: power generator TableLerp { index_bits: 8, value_bits: \
             12, frac_bits: 4 }: the generator builds the Table form only"
        ),
        "{}",
        o.stdout
    );
}

#[test]
fn the_register_combiners_cosimulate_with_the_program_in_host_registers() {
    let Some((_s, out, o)) = rtl_cosim("nv20-combiner-bump", "300", "cmd") else {
        return;
    };
    // eight general stages and the two-stage final combiner
    let line = o
        .stdout
        .lines()
        .find(|l| l.starts_with("rc "))
        .unwrap_or_else(|| panic!("{}", o.stdout));
    assert!(
        line.contains("latency 10")
            && line.contains("registers 107")
            && line.contains("cosim 300 vectors, 0 mismatches"),
        "{line}"
    );
    let regs = std::fs::read_to_string(out.join("rc.regs")).unwrap();
    // the mux select; 8 stages x (2 portions x (4 ICW bytes + OCW) + c0, c1); the 7 final
    // variables, the flags and the final c0, c1
    assert_eq!(
        regs.lines().filter(|l| !l.starts_with('#')).count(),
        107,
        "{regs}"
    );
    assert!(regs.contains("stages[0].rgb.a (icw byte)"), "{regs}");
}

#[test]
fn the_emboss_filter_cosimulates_rebuilt_from_its_config() {
    let Some((_s, out, o)) = rtl_cosim("emboss", "300", "cmd") else {
        return;
    };
    // the unit rebuilt with the bricks' default bevel; 3 ports behind a 4-clock memory
    let line = o
        .stdout
        .lines()
        .find(|l| l.starts_with("emboss "))
        .unwrap_or_else(|| panic!("{}", o.stdout));
    assert!(
        line.contains("latency 8")
            && line.contains("registers 1")
            && line.contains("cosim 300 vectors, 0 mismatches"),
        "{line}"
    );
    let files = listing(&out);
    for f in ["emboss.v", "emboss.regs", "bumpsim_emboss_heights.hex"] {
        assert!(files.iter().any(|x| x == f), "{f} not in {files:?}");
    }
    let heights = std::fs::read_to_string(out.join("bumpsim_emboss_heights.hex")).unwrap();
    assert_eq!(heights.lines().count(), 256 * 256);
    // N_z = 6 * 255 / (0.01 * 256) = 597.66 in s12.4
    let regs = std::fs::read_to_string(out.join("emboss.regs")).unwrap();
    assert!(regs.contains("0 16 0x255b N_z"), "{regs}");
}

/// Every pass's ROP state as a module with its state in host registers: Tarini's eq. (2) as
/// passes, the base colour (depth Less, written) and the blend `(1 - dst) src + alpha dst`
/// with depth Equal and no depth write.
#[test]
fn every_pass_has_a_rop_module_cosimulated_with_its_state() {
    let Some((_s, out, o)) = rtl_cosim("quantized-bunny-wood-eq2", "300", "rop") else {
        return;
    };
    for (label, file) in [("rop ", "rop.v"), ("rop.1 ", "rop.1.v")] {
        let line = o
            .stdout
            .lines()
            .find(|l| l.starts_with(label))
            .unwrap_or_else(|| panic!("{label}: {}", o.stdout));
        // random vectors, and the fragments the ROP read in the rendered frame replayed
        assert!(
            line.contains(file)
                && line.contains("cosim 300 vectors, 0 mismatches")
                && line.contains("frame 300 fragments, 0 mismatches"),
            "{line}"
        );
    }
    // the blend pass: depth function Equal (2), no depth write, alpha read (4 colour lanes),
    // factors OneMinusDstColor (5) and SrcAlpha (6)
    let regs = std::fs::read_to_string(out.join("rop.1.regs")).unwrap();
    let values: Vec<&str> = regs
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split_whitespace().nth(2).unwrap())
        .collect();
    assert_eq!(values, ["0x2", "0x0", "0x5", "0x6"], "{regs}");
    let v = std::fs::read_to_string(out.join("rop.1.v")).unwrap();
    assert!(v.contains("input wire [7:0] c_3"), "alpha lane");
    let first = std::fs::read_to_string(out.join("rop.regs")).unwrap();
    assert_eq!(first.lines().filter(|l| !l.starts_with('#')).count(), 2);
}

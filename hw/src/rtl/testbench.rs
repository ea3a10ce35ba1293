//! Co-simulation: a Verilog testbench that loads a unit's host registers, replays input
//! vectors and compares every output word with the model's, run with iverilog.
//!
//! Files written by [`write`](fn@write) into a directory: `unit.v` (the generated unit), `tb.v`,
//! `in.hex` / `out.hex` (one 32-bit word per lane per vector, lanes in
//! [`RtlUnit::inputs`] / [`RtlUnit::outputs`] order), `cfg.hex` (the register words) and
//! the contents of the unit's texture memories ([`RtlUnit::memories`]).
//! A unit with per-frame work ([`RtlUnit::frame`]) gets one `frame` pulse after the registers
//! are loaded, and the vectors start when `frame_done` is high.
//! [`run_iverilog`] compiles with `iverilog -g2005` and runs `vvp`; the testbench prints
//! `RESULT vectors=N mismatches=M latency_errors=L` (and the first mismatches).

use super::RtlUnit;
use crate::unit::Word;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// What a co-simulation found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CosimReport {
    pub vectors: usize,
    pub mismatches: usize,
    /// Vectors whose `done` did not come exactly [`RtlUnit::latency`] clocks after `start`,
    /// plus one when a frame phase ([`RtlUnit::frame`]) took another number of clocks.
    pub latency_errors: usize,
    /// The testbench's lines about the first mismatches.
    pub first: Vec<String>,
}

fn hex_words<'a>(words: impl Iterator<Item = u64> + 'a) -> String {
    let mut s = String::new();
    for w in words {
        let _ = writeln!(s, "{w:08x}");
    }
    s
}

fn bits(w: u32) -> String {
    if w == 1 {
        String::new()
    } else {
        format!("[{}:0] ", w - 1)
    }
}

/// The testbench module `tb` for `u` and `n` vectors.
pub fn testbench(u: &RtlUnit, n: usize) -> String {
    let (ni, no, nc) = (u.inputs.len(), u.outputs.len(), u.config.len());
    let mut s = String::from("module tb;\n");
    s += "    reg clk = 0, rst = 1, start = 0;\n";
    let _ = writeln!(s, "    reg [31:0] vin [0:{}];", (n * ni).max(1) - 1);
    let _ = writeln!(s, "    reg [31:0] vout [0:{}];", (n * no).max(1) - 1);
    let mut conns = vec![
        ".clk(clk)".to_string(),
        ".rst(rst)".into(),
        ".start(start)".into(),
        ".done(done)".into(),
    ];
    if nc > 0 {
        let _ = writeln!(s, "    reg [31:0] cfg [0:{}];", nc - 1);
        let _ = writeln!(
            s,
            "    reg cfg_we = 0;\n    reg {}cfg_addr = 0;\n    reg {}cfg_data = 0;",
            bits(u.cfg_addr_bits()),
            bits(u.cfg_data_bits())
        );
        conns.extend(["cfg_we", "cfg_addr", "cfg_data"].map(|c| format!(".{c}({c})")));
    }
    if u.frame.is_some() {
        s += "    reg frame = 0;\n    wire frame_done;\n";
        conns.extend(["frame", "frame_done"].map(|c| format!(".{c}({c})")));
    }
    for l in &u.inputs {
        let _ = writeln!(s, "    reg {}i_{} = 0;", bits(l.enc.width()), l.name);
        conns.push(format!(".{0}(i_{0})", l.name));
    }
    for l in &u.outputs {
        let _ = writeln!(s, "    wire {}o_{};", bits(l.enc.width()), l.name);
        conns.push(format!(".{0}(o_{0})", l.name));
    }
    s += "    wire done;\n";
    let _ = writeln!(
        s,
        "    {} dut (\n        {}\n    );",
        u.top,
        conns.join(",\n        ")
    );
    s += "    always #5 clk = ~clk;\n";
    s += "    integer v, i, cycles, mismatches, lat_bad, bad;\n";
    s += "    initial begin\n";
    s += "        $readmemh(\"in.hex\", vin);\n        $readmemh(\"out.hex\", vout);\n";
    if nc > 0 {
        s += "        $readmemh(\"cfg.hex\", cfg);\n";
    }
    s += "        mismatches = 0; lat_bad = 0;\n";
    s += "        @(negedge clk); rst = 0;\n";
    if nc > 0 {
        let _ = writeln!(
            s,
            "        for (i = 0; i < {nc}; i = i + 1) begin\n            cfg_we = 1; cfg_addr = i; cfg_data = cfg[i];\n            @(negedge clk);\n        end\n        cfg_we = 0;"
        );
    }
    if let Some(f) = u.frame {
        // the per-frame phase: one pulse, then the clocks until frame_done
        let _ = writeln!(
            s,
            "        frame = 1;\n        @(negedge clk);\n        frame = 0;\n        cycles = 1;\n        \
             while (!frame_done && cycles < {}) begin\n            @(negedge clk);\n            \
             cycles = cycles + 1;\n        end\n        if (cycles != {f}) begin\n            \
             lat_bad = lat_bad + 1;\n            $display(\"FRAME %0d clocks, expected {f}\", cycles);\n        end",
            f as u64 * 2 + 1000
        );
    }
    let _ = writeln!(s, "        for (v = 0; v < {n}; v = v + 1) begin");
    for (k, l) in u.inputs.iter().enumerate() {
        let _ = writeln!(s, "            i_{} = vin[v * {ni} + {k}];", l.name);
    }
    s += "            start = 1;\n            @(negedge clk);\n            start = 0;\n            cycles = 1;\n";
    s += "            while (!done && cycles < 1000) begin\n                @(negedge clk);\n                cycles = cycles + 1;\n            end\n";
    let _ = writeln!(
        s,
        "            if (cycles != {}) lat_bad = lat_bad + 1;",
        u.latency
    );
    s += "            bad = 0;\n";
    for (k, l) in u.outputs.iter().enumerate() {
        let w = l.enc.width();
        let _ = writeln!(
            s,
            "            if (o_{0} !== vout[v * {no} + {k}][{1}:0]) begin\n                bad = 1;\n                if (mismatches < 5) $display(\"MISMATCH vector %0d lane {0}: rtl %h model %h\", v, o_{0}, vout[v * {no} + {k}][{1}:0]);\n            end",
            l.name,
            w - 1
        );
    }
    s += "            mismatches = mismatches + bad;\n        end\n";
    let _ = writeln!(
        s,
        "        $display(\"RESULT vectors=%0d mismatches=%0d latency_errors=%0d\", {n}, mismatches, lat_bad);\n        $finish;\n    end\nendmodule"
    );
    s
}

/// Write the unit, the testbench and the vectors into `dir`. `ins` and `outs` are the
/// model's words per vector (input ports, output ports).
pub fn write(
    dir: &Path,
    u: &RtlUnit,
    ins: &[Vec<Word>],
    outs: &[Vec<Word>],
) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    std::fs::write(dir.join("unit.v"), &u.verilog)?;
    std::fs::write(dir.join("tb.v"), testbench(u, ins.len()))?;
    let lanes = |ls: &[super::Lane], words: &[Vec<Word>]| {
        hex_words(words.iter().flat_map(move |w| {
            ls.iter()
                .map(move |l| l.enc.format.bits(w[l.port].lanes[l.lane].raw))
        }))
    };
    std::fs::write(dir.join("in.hex"), lanes(&u.inputs, ins))?;
    std::fs::write(dir.join("out.hex"), lanes(&u.outputs, outs))?;
    let cfg = hex_words(u.config.iter().map(|c| {
        let mask = if c.width >= 64 {
            u64::MAX
        } else {
            (1u64 << c.width) - 1
        };
        c.value as u64 & mask
    }));
    std::fs::write(dir.join("cfg.hex"), cfg)?;
    for mem in u.memories.iter().filter(|m| m.has_file()) {
        std::fs::write(dir.join(&mem.file), mem.hex())?;
    }
    Ok(())
}

/// The iverilog binary (`$IVERILOG` or `iverilog` on `PATH`) and `vvp` beside it.
pub fn iverilog_bin() -> (String, String) {
    let iv = std::env::var("IVERILOG").unwrap_or_else(|_| "iverilog".into());
    let vvp = match Path::new(&iv).parent() {
        Some(p) if !p.as_os_str().is_empty() => p.join("vvp").display().to_string(),
        _ => "vvp".into(),
    };
    (iv, vvp)
}

/// Compile and run the testbench in `dir` (written by [`write`](fn@write)).
pub fn run_iverilog(dir: &Path) -> Result<CosimReport, String> {
    let (iv, vvp) = iverilog_bin();
    let o = Command::new(&iv)
        .current_dir(dir)
        .args(["-g2005", "-Wall", "-o", "tb.vvp", "tb.v", "unit.v"])
        .output()
        .map_err(|e| format!("running {iv}: {e}"))?;
    if !o.status.success() {
        return Err(format!(
            "iverilog failed: {}",
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    let o = Command::new(&vvp)
        .current_dir(dir)
        .args(["-n", "tb.vvp"])
        .output()
        .map_err(|e| format!("running {vvp}: {e}"))?;
    let text = String::from_utf8_lossy(&o.stdout);
    let first = text
        .lines()
        .filter(|l| l.starts_with("MISMATCH"))
        .map(str::to_string)
        .collect();
    let line = text
        .lines()
        .find(|l| l.starts_with("RESULT"))
        .ok_or_else(|| format!("no RESULT line from vvp: {text}"))?;
    let field = |k: &str| -> Result<usize, String> {
        line.split_whitespace()
            .find_map(|f| f.strip_prefix(k).and_then(|v| v.strip_prefix('=')))
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| format!("bad RESULT line: {line}"))
    };
    Ok(CosimReport {
        vectors: field("vectors")?,
        mismatches: field("mismatches")?,
        latency_errors: field("latency_errors")?,
        first,
    })
}

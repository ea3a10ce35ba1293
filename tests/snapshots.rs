//! Snapshot tests (insta) of every bundled config, stored in `traces/`:
//!
//! * `trace-<config>.snap`: the text trace of all units over the first 30 cycles of the
//!   fragment phase (from `cycles.frame + raster.setup_cycles`, when the first triangle's
//!   setup is done and the scan converter can emit its first fragment);
//! * `report-<config>.snap`: the report JSON, as `bumpsim report --json` prints it.
//!
//! Update with `INSTA_UPDATE=always cargo test --test snapshots`, then review the diff.

mod common;

use common::*;
use std::path::Path;

const WINDOW: u64 = 30;

/// `raster.setup_cycles` of a config (8 when left out).
fn setup_cycles(text: &str) -> u64 {
    let Some(i) = text.find("setup_cycles:") else {
        return 8;
    };
    text[i + "setup_cycles:".len()..]
        .trim_start()
        .chars()
        .take_while(char::is_ascii_digit)
        .collect::<String>()
        .parse()
        .expect("setup_cycles is an integer")
}

fn report_text(cfg: &Path) -> String {
    let o = bumpsim(&["report".as_ref(), cfg.as_os_str(), "--json".as_ref()]);
    o.expect_code(0, &format!("report --json {}", cfg.display()));
    o.stdout
}

fn trace_text(cfg: &Path, from: u64, to: u64, scratch: &Scratch) -> String {
    let out = scratch.join("trace.txt");
    let o = bumpsim(&[
        "trace".as_ref(),
        cfg.as_os_str(),
        "--cycles".as_ref(),
        format!("{from}..{to}").as_ref(),
        "--format".as_ref(),
        "text".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    o.expect_code(0, &format!("trace {}", cfg.display()));
    std::fs::read_to_string(&out).unwrap()
}

macro_rules! in_traces_dir {
    ($($body:tt)*) => {
        insta::with_settings!({
            snapshot_path => concat!(env!("CARGO_MANIFEST_DIR"), "/traces"),
            prepend_module_to_snapshot => false,
        }, { $($body)* })
    };
}

#[test]
fn report_snapshots() {
    for cfg in configs() {
        let name = stem(&cfg);
        let text = report_text(&cfg);
        assert!(
            !text.contains("NaN") && !text.contains("null"),
            "{name}: {text}"
        );
        in_traces_dir! {
            insta::assert_snapshot!(format!("report-{name}"), text);
        }
    }
}

#[test]
fn trace_snapshots() {
    let scratch = Scratch::new("snapshots");
    for cfg in configs() {
        let name = stem(&cfg);
        let report = json(&report_text(&cfg));
        let config_text = std::fs::read_to_string(&cfg).unwrap();
        let from = uint(&report, "cycles.frame") + setup_cycles(&config_text);
        let text = trace_text(&cfg, from, from + WINDOW, &scratch);
        let units = engine_units(&config_text);
        // the engine's units between the scan converter and the ROP
        assert!(
            text.starts_with(&format!(
                "# bumpsim trace: {} units, cycles {from}..={}",
                units.len() + 2,
                from + WINDOW - 1
            )),
            "{name}: {text}"
        );
        in_traces_dir! {
            insta::assert_snapshot!(format!("trace-{name}"), text);
        }
    }
}

/// Tarini §5.1 per-frame work on a 16-entry table (`quantized-sn16`: Lambert, one light, one
/// entry per clock): 16 builder clocks, then the LUT load writes entry k at clock 16 + k.
#[test]
fn palette_build_trace_snapshot() {
    let scratch = Scratch::new("palette-build");
    let cfg = config("quantized-sn16");
    let report = json(&report_text(&cfg));
    assert_eq!(uint(&report, "cycles.frame"), 32);
    let text = trace_text(&cfg, 0, 34, &scratch);
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    // the unit's 34 clocks, and the scan converter's and the ROP's from the frame's end (32)
    assert_eq!(lines.len(), 34 + 2 * 2, "{text}");
    for (c, l) in lines.iter().enumerate().take(32) {
        assert!(l.contains("busy"), "cycle {c}: {l}");
        let write = format!("out#{} ", c.wrapping_sub(16));
        assert_eq!(c >= 16 && l.contains(&write), c >= 16, "cycle {c}: {l}");
    }
    in_traces_dir! {
        insta::assert_snapshot!("trace-palette-build-sn16", text);
    }
}

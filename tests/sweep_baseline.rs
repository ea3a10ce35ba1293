//! End-to-end tests of a sweep's `baseline` and `tables` (docs/sweep.md): every point compared
//! with its own baseline (the point with the baseline's overrides), one render per distinct
//! baseline, kept rows only with the same baseline on `--resume`, a baseline that does not
//! run as error rows; and `bumpsim table` giving the sweep's table files.

mod common;

use common::*;
use std::collections::BTreeMap;
use std::path::Path;

/// A quantized sphere at 48 or 64 pixels with a 32 x 32 map (at most 1024 distinct normals),
/// median cut at 16 or 1024 entries (1024: every normal kept), against the same engine with
/// `quantizer: Exact`.
fn sweep_file(dir: &Path, baseline: &str) -> std::path::PathBuf {
    let base = root().join("configs/quantized-sphere.ron");
    let file = dir.join("s.ron");
    std::fs::write(
        &file,
        format!(
            r#"(
    base: {:?},
    sets: ["engine.units.qnm.unit.size=32", "engine.units.qnm.unit.index_bits=10",
           "engine.units.qnm.unit.dither=false", "scene.height=48"],
    axes: [
        (path: "engine.units.qnm.unit.s_n", name: "s_n", values: List([16, 1024])),
        (path: "scene.width", name: "w", values: List([48, 64])),
    ],
    baseline: [{baseline}],
    tables: [(name: "t", columns: ["w", "s_n", "baseline_psnr_db", "baseline_max_lsb"],
              headings: ["width", "s_N", "PSNR dB", "max LSB"], filter: ["w=64"], digits: 1)],
)"#,
            base.display().to_string()
        ),
    )
    .unwrap();
    file
}

/// Every normal kept (1024 entries: the baseline sets the point's table size too).
const EXACT: &str = r#""engine.units.qnm.unit.quantizer=Exact", "engine.units.qnm.unit.s_n=1024""#;

fn rows(out: &Path) -> Vec<BTreeMap<String, String>> {
    let text = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            head.iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

/// `bumpsim sweep FILE --out OUT [extra]`: exit 0 and `summary` in its output.
fn run_sweep(file: &Path, out: &Path, extra: &[&str], summary: &str) -> Out {
    let mut args = vec![
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    let o = bumpsim(&args);
    o.expect_code(0, summary);
    assert!(o.stdout.contains(summary), "{}", o.stdout);
    o
}

fn num(r: &BTreeMap<String, String>, k: &str) -> f64 {
    r[k].parse().unwrap_or_else(|_| panic!("{k} = {:?}", r[k]))
}

#[test]
fn each_point_is_compared_with_its_own_baseline() {
    let s = Scratch::new("sweep-baseline");
    let file = sweep_file(&s.join(""), EXACT);
    let out = s.join("out");
    let o = run_sweep(&file, &out, &[], "4 of 4 points run, 0 with errors");
    let r = rows(&out);
    assert_eq!(r.len(), 4);
    for row in &r {
        assert_eq!(row["status"], "ok", "{row:?}");
        assert_eq!(row["baseline_hash"].len(), 64);
    }
    // one baseline per width: the points of one width share it, the widths do not
    assert_eq!(r[0]["baseline_hash"], r[2]["baseline_hash"]);
    assert_eq!(r[1]["baseline_hash"], r[3]["baseline_hash"]);
    assert_ne!(r[0]["baseline_hash"], r[1]["baseline_hash"]);
    // 1024 entries hold every normal of the 32 x 32 map: the image is the baseline's at both
    // widths (it would not be against a baseline of the other width)
    for row in &r[2..] {
        assert_eq!(num(row, "baseline_psnr_db"), 999.0, "{row:?}");
        assert_eq!(num(row, "baseline_max_lsb"), 0.0);
        assert_eq!(num(row, "baseline_banding"), 0.0);
        // while the f64 reference still sees the bake and the uv rounding
        assert!(num(row, "total_psnr_db") < 40.0, "{row:?}");
    }
    // 16 entries: the quantization's loss alone
    for row in &r[..2] {
        let p = num(row, "baseline_psnr_db");
        assert!((10.0..30.0).contains(&p), "{row:?}");
        assert!(num(row, "baseline_max_lsb") > 20.0);
    }
    // the table: the w=64 rows, one decimal
    let t = std::fs::read_to_string(out.join("t.md")).unwrap();
    let p16 = num(&r[1], "baseline_psnr_db");
    let max16 = num(&r[1], "baseline_max_lsb");
    assert_eq!(
        t,
        format!(
            "| width | s_N | PSNR dB | max LSB |\n|---|---|---|---|\n| 64 | 16 | {p16:.1} | \
             {max16:.1} |\n| 64 | 1024 | 999.0 | 0.0 |\n"
        )
    );
    assert!(o.stdout.contains("t.md: 2 rows"), "{}", o.stdout);
    // `bumpsim table` prints the same
    let csv = out.join("sweep.csv");
    let o = bumpsim(&[
        "table",
        csv.to_str().unwrap(),
        "--columns",
        "w,s_n,baseline_psnr_db,baseline_max_lsb",
        "--headings",
        "width,s_N,PSNR dB,max LSB",
        "--filter",
        "w=64",
        "--digits",
        "1",
    ]);
    o.expect_code(0, "bumpsim table");
    assert_eq!(o.stdout, t);
    let o = bumpsim(&["table", csv.to_str().unwrap(), "--columns", "w,nope"]);
    o.expect_code(2, "a missing column");
    assert!(
        o.stderr.contains("--columns") && o.stderr.contains("\"nope\""),
        "{}",
        o.stderr
    );

    // resume keeps the rows while the baseline is the same, reruns them when it changes
    run_sweep(&file, &out, &["--resume"], "resume: 4 points kept");
    let before = std::fs::read(out.join("sweep.csv")).unwrap();
    let file = sweep_file(
        &s.join(""),
        &format!(r#"{EXACT}, "engine.units.qnm.unit.entries_per_clock=2""#),
    );
    run_sweep(&file, &out, &["--resume"], "resume: 0 points kept");
    let r2 = rows(&out);
    assert_ne!(r2[0]["baseline_hash"], r[0]["baseline_hash"]);
    // the builder's parallelism changes the frame's cycles, not the image
    assert_eq!(r2[1]["baseline_psnr_db"], r[1]["baseline_psnr_db"]);
    assert_ne!(std::fs::read(out.join("sweep.csv")).unwrap(), before);
}

#[test]
fn a_baseline_that_does_not_run_makes_error_rows() {
    let s = Scratch::new("sweep-baseline-bad");
    // Exact with 16 entries cannot hold the map's normals: the baseline fails at every point
    let file = sweep_file(
        &s.join(""),
        &format!(r#"{EXACT}, "engine.units.qnm.unit.s_n=16""#),
    );
    let out = s.join("out");
    run_sweep(&file, &out, &[], "4 of 4 points run, 4 with errors");
    for row in rows(&out) {
        assert_eq!(row["status"], "error");
        assert!(
            row["error"].contains("baseline") && row["error"].contains("distinct"),
            "{row:?}"
        );
    }
    // a table naming a column the sweep does not have: exit 2 before any point runs
    let bad = s.join("bad.ron");
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace("\"baseline_max_lsb\"]", "\"no_such\"]");
    std::fs::write(&bad, text).unwrap();
    let out2 = s.join("out2");
    let o = bumpsim(&[
        "sweep",
        bad.to_str().unwrap(),
        "--out",
        out2.to_str().unwrap(),
    ]);
    o.expect_code(2, "a bad table");
    assert!(o.stderr.contains("tables[0].columns"), "{}", o.stderr);
    assert!(!out2.exists());
}

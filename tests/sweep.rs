//! End-to-end tests of `bumpsim sweep`: the example sweep's CSV and its numbers, the same
//! bytes at any thread count and from merged shards, error rows, bad sweep files and merges.

mod common;

use common::*;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

const EXAMPLE: &str = "configs/sweeps/sgi-teapot-index-bits.ron";

fn sweep(args: &[&str]) -> Out {
    bumpsim(&[&["sweep"], args].concat())
}

/// The CSV as a list of rows, each a map from column to field (no quoted fields expected).
fn csv_rows(path: &Path) -> Vec<BTreeMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), head.len(), "{l}");
            head.iter()
                .zip(f)
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect()
        })
        .collect()
}

fn f(row: &BTreeMap<String, String>, k: &str) -> f64 {
    row[k]
        .parse()
        .unwrap_or_else(|_| panic!("{k} = {:?} is not a number", row[k]))
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn example_sweep_rows_numbers_threads_and_shards() {
    let s = Scratch::new("sweep-example");
    let all = s.join("all");
    let o = sweep(&[EXAMPLE, "--out", all.to_str().unwrap(), "--threads", "2"]);
    o.expect_code(0, "sweep the example");
    assert!(
        o.stdout.contains("7 of 7 points run, 0 with errors"),
        "{}",
        o.stdout
    );
    let rows = csv_rows(&all.join("sweep.csv"));
    assert_eq!(rows.len(), 7);
    let bits: Vec<String> = rows.iter().map(|r| r["index_bits"].clone()).collect();
    assert_eq!(bits, ["4", "5", "6", "7", "8", "9", "10"]);
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r["index"], i.to_string());
        assert_eq!(r["status"], "ok", "{r:?}");
        assert_eq!(r["error"], "");
        assert_eq!(r["config_hash"].len(), 64);
    }
    // every point is the base config with its overrides: the 8-bit row is `report --set`
    let r8 = &rows[4];
    let o = bumpsim(&[
        "report",
        "configs/sgi-teapot.ron",
        "--json",
        "--set",
        "scene.width=96",
        "--set",
        "scene.height=96",
        "--set",
        "engine.units.spec.unit.index_bits=8",
    ]);
    o.expect_code(0, "report of the 8-bit point");
    let rep: Value = json(&o.stdout);
    assert_eq!(rep["config_hash"].as_str().unwrap(), r8["config_hash"]);
    assert_eq!(num(&rep, "gates.total"), f(r8, "gates_total"));
    assert_eq!(uint(&rep, "cycles.total") as f64, f(r8, "cycles"));
    assert_eq!(num(&rep, "error.total.psnr_db"), f(r8, "total_psnr_db"));
    assert_eq!(num(&rep, "artifacts.total.banding"), f(r8, "total_banding"));
    // one gates column per unit of the base config, in its order, summing to the total
    let units = ["fetch", "dot", "spec", "shade"];
    for u in units {
        let col = format!("gates.{u}");
        assert_eq!(
            num(&rep, &format!("gates.per_unit.{u}.total")),
            f(r8, &col),
            "{u}"
        );
    }
    let sum: f64 = units.iter().map(|u| f(r8, &format!("gates.{u}"))).sum();
    assert!((sum - f(r8, "gates_total")).abs() < 0.05, "{sum}");

    // the numbers (see docs/sweep.md)
    let col = |k: &str| rows.iter().map(|r| f(r, k)).collect::<Vec<f64>>();
    let gates = col("gates_total");
    let quant = col("quantization_psnr_db");
    let band = col("quantization_banding");
    let facet = col("quantization_faceting_lsb");
    let lowpass = col("quantization_lowpass_psnr_db");
    let round = |v: &[f64], d: i32| -> Vec<f64> {
        v.iter()
            .map(|x| (x * 10f64.powi(d)).round() / 10f64.powi(d))
            .collect()
    };
    assert_eq!(round(&gates, 0), GATES);
    assert_eq!(round(&quant, 2), QUANT_PSNR);
    assert_eq!(round(&band, 5), QUANT_BANDING);
    assert_eq!(round(&facet, 3), QUANT_FACETING);
    assert_eq!(round(&lowpass, 2), QUANT_LOWPASS_PSNR);
    // the table grows with its index; the error and the faceting of the highlight shrink up
    // to 8 bits (the 8-bit output then dominates)
    assert!(gates.windows(2).all(|w| w[0] < w[1]), "{gates:?}");
    assert!(quant[..5].windows(2).all(|w| w[0] < w[1]), "{quant:?}");
    assert!(facet[..5].windows(2).all(|w| w[0] > w[1]), "{facet:?}");
    assert!(lowpass[..5].windows(2).all(|w| w[0] < w[1]), "{lowpass:?}");
    // table loads take frame cycles: more entries, more cycles
    let cycles = col("cycles");
    assert!(cycles.windows(2).all(|w| w[0] < w[1]), "{cycles:?}");
    // the rest of the pipe does not depend on the table
    for k in ["fragments", "bits_per_triangle", "algorithm_psnr_db"] {
        let v = col(k);
        assert!(v.iter().all(|x| *x == v[0]), "{k}: {v:?}");
    }
    // JSON lines: the same rows
    let jl = std::fs::read_to_string(all.join("sweep.jsonl")).unwrap();
    let j: Vec<Value> = jl.lines().map(json).collect();
    assert_eq!(j.len(), 7);
    assert_eq!(j[3]["index_bits"], 7);
    assert_eq!(j[3]["gates_total"].as_f64().unwrap(), gates[3]);
    assert!(j[3]["error"].is_null());
    let summary = json(&std::fs::read_to_string(all.join("sweep.json")).unwrap());
    assert_eq!(summary["points"], 7);

    // shards at other thread counts, merged: the same bytes
    let (s0, s1) = (s.join("s0"), s.join("s1"));
    let o = sweep(&[
        EXAMPLE,
        "--out",
        s0.to_str().unwrap(),
        "--shard",
        "0/2",
        "--threads",
        "1",
    ]);
    o.expect_code(0, "shard 0/2");
    assert!(o.stdout.contains("4 of 7 points run"), "{}", o.stdout);
    let o = sweep(&[
        EXAMPLE,
        "--out",
        s1.to_str().unwrap(),
        "--shard",
        "1/2",
        "--threads",
        "3",
    ]);
    o.expect_code(0, "shard 1/2");
    let idx: Vec<String> = csv_rows(&s1.join("sweep.csv"))
        .iter()
        .map(|r| r["index"].clone())
        .collect();
    assert_eq!(idx, ["1", "3", "5"]);
    // a shard missing: refused
    let m = s.join("merged");
    let o = sweep(&[
        "--merge",
        s0.to_str().unwrap(),
        "--out",
        m.to_str().unwrap(),
    ]);
    o.expect_code(2, "merge of one of two shards");
    assert!(o.stderr.contains("4 of 7 points"), "{}", o.stderr);
    // a shard twice: refused
    let o = sweep(&[
        "--merge",
        s0.to_str().unwrap(),
        s0.to_str().unwrap(),
        "--out",
        m.to_str().unwrap(),
    ]);
    o.expect_code(2, "merge of a shard twice");
    // in any order, the two shards give the unsharded files
    let o = sweep(&[
        "--merge",
        s1.to_str().unwrap(),
        s0.to_str().unwrap(),
        "--out",
        m.to_str().unwrap(),
    ]);
    o.expect_code(0, "merge");
    for name in ["sweep.csv", "sweep.jsonl", "sweep.json"] {
        assert_eq!(
            read(&m.join(name)),
            read(&all.join(name)),
            "{name}: merged shards (1 and 3 threads) differ from the unsharded run (2 threads)"
        );
    }
}

/// The example's numbers, index bits 4..10 (a 96x96 teapot). Below 8 index bits the u9.8
/// dot has more fraction bits than the index: the index's second carry (`index carry`, a
/// half adder a bit, docs/gates.md) adds 3.33 GE per index bit.
const GATES: [f64; 7] = [
    18016.0, 18210.0, 18596.0, 19365.0, 20877.0, 23947.0, 30093.0,
];
/// `quantization_psnr_db`, 2 decimals.
const QUANT_PSNR: [f64; 7] = [25.95, 31.9, 36.76, 39.19, 42.81, 42.81, 42.8];
/// `quantization_banding`, 5 decimals: no contour at any width (the 3 to 6 steps of 2981
/// pixels that the measure counted before it required a group of 8 pixels were specks).
const QUANT_BANDING: [f64; 7] = [0.0; 7];
/// `quantization_faceting_lsb`, 3 decimals.
const QUANT_FACETING: [f64; 7] = [7.222, 3.846, 2.167, 1.501, 1.128, 1.128, 1.129];
/// `quantization_lowpass_psnr_db`, 2 decimals.
const QUANT_LOWPASS_PSNR: [f64; 7] = [30.41, 39.27, 42.65, 43.68, 49.77, 49.78, 49.71];

#[test]
fn a_rejected_point_is_an_error_row_and_the_sweep_goes_on() {
    let s = Scratch::new("sweep-bad-point");
    let file = s.join("bad.ron");
    let base = root().join("configs/sgi-teapot.ron");
    std::fs::write(
        &file,
        format!(
            r#"(
    base: {:?},
    sets: ["scene.width=32", "scene.height=32"],
    axes: [(path: "engine.units.spec.unit.index_bits", values: List([6, 0, 17])),
           (path: "scene.width", values: List([32]))],
    sampling: Product,
)"#,
            base.display().to_string()
        ),
    )
    .unwrap();
    let out = s.join("out");
    let o = sweep(&[file.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    o.expect_code(0, "a sweep with bad points");
    assert!(
        o.stdout.contains("3 of 3 points run, 2 with errors"),
        "{}",
        o.stdout
    );
    let text = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 4, "{text}");
    assert!(lines[1].starts_with("0,6,32,ok,,"), "{}", lines[1]);
    for (l, bad) in [(lines[2], "0"), (lines[3], "17")] {
        assert!(
            l.starts_with(&format!(
                "{},{bad},32,error,",
                if bad == "0" { 1 } else { 2 }
            )),
            "{l}"
        );
        assert!(l.contains("index_bits"), "the message names the field: {l}");
    }
    let j: Vec<Value> = std::fs::read_to_string(out.join("sweep.jsonl"))
        .unwrap()
        .lines()
        .map(json)
        .collect();
    assert_eq!(j[1]["status"], "error");
    assert!(j[1]["gates_total"].is_null());
    assert!(j[1]["error"].as_str().unwrap().contains("index_bits"));
    assert_eq!(
        json(&std::fs::read_to_string(out.join("sweep.json")).unwrap())["errors"],
        2
    );
}

#[test]
fn bad_sweep_files_and_arguments_exit_2() {
    let s = Scratch::new("sweep-bad-file");
    let out = s.join("out");
    let cases = [
        (
            "(base: \"../configs/sgi-teapot.ron\", axes: [])",
            "at least one axis",
        ),
        ("(base: \"x.ron\", axis: [])", "axis"),
        (
            "(base: \"x.ron\", axes: [(path: \"a\", values: Grid(\"a\", 1, 2))])",
            "numbers",
        ),
        // an axis named as a column the sweep writes anyway, or as another axis
        (
            "(base: \"x.ron\", axes: [(path: \"a\", name: \"cycles\", values: List([1]))])",
            "axes[0].name: \"cycles\": another column of the output has this name",
        ),
        (
            "(base: \"x.ron\", axes: [(path: \"a\", name: \"k\", values: List([1])), \
             (path: \"b\", name: \"k\", values: List([2]))])",
            "axes[0].name: \"k\": another column",
        ),
    ];
    for (text, needle) in cases {
        let file = s.join("s.ron");
        std::fs::write(&file, text).unwrap();
        let o = sweep(&[file.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        o.expect_code(2, text);
        assert!(o.stderr.contains(needle), "{text}: {}", o.stderr);
        assert!(!out.exists(), "nothing is written");
    }
    for shard in ["2/2", "x", "1/0"] {
        let o = sweep(&[EXAMPLE, "--out", out.to_str().unwrap(), "--shard", shard]);
        o.expect_code(2, shard);
        assert!(o.stderr.contains("--shard"), "{}", o.stderr);
    }
    let o = sweep(&[
        "--merge",
        s.join("nothing").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    o.expect_code(2, "merge of a missing directory");
    assert!(!out.exists());
}

#[test]
fn report_fields_are_columns_after_the_baseline() {
    let s = Scratch::new("sweep-report-fields");
    let file = s.join("fields.ron");
    let base = root().join("configs/quantized-vase-sn16.ron");
    std::fs::write(
        &file,
        format!(
            r#"(
    base: {:?},
    axes: [(path: "engine.units.qnm.unit.s_n", name: "s_n", values: List([16, 32]))],
    baseline: ["engine.units.qnm.unit.s_n=64"],
    report: ["cycles.frame", "cycles.per_fragment", "passes.passes", "passes.passes.0.name",
             "bandwidth.textures", "no.such.field"],
    tables: [(name: "t", columns: ["s_n", "report.cycles.frame", "report.passes.passes"])],
)"#,
            base.to_str().unwrap()
        ),
    )
    .unwrap();
    let out = s.join("out");
    let o = sweep(&[file.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    o.expect_code(0, "sweep with report fields");
    let head = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let head: Vec<&str> = head.lines().next().unwrap().split(',').collect();
    let k = head.iter().position(|c| *c == "baseline_hash").unwrap();
    assert_eq!(
        head[k + 1..k + 7],
        [
            "report.cycles.frame",
            "report.cycles.per_fragment",
            "report.passes.passes",
            "report.passes.passes.0.name",
            "report.bandwidth.textures",
            "report.no.such.field"
        ]
    );
    assert!(head[k + 7].starts_with("gates."), "{head:?}");
    let rows = csv_rows(&out.join("sweep.csv"));
    // point 0 is the config as it is: its fields are `bumpsim report --json`'s
    let o = bumpsim(&["report", base.to_str().unwrap(), "--json"]);
    o.expect_code(0, "report of the base");
    let rep: Value = json(&o.stdout);
    let r = &rows[0];
    assert_eq!(r["report.cycles.frame"], rep["cycles"]["frame"].to_string());
    assert_eq!(
        f(r, "report.cycles.per_fragment"),
        rep["cycles"]["per_fragment"].as_f64().unwrap()
    );
    // a list is its length, text as it is, an object or a missing field empty
    assert_eq!(r["report.passes.passes"], "1");
    assert_eq!(
        r["report.passes.passes.0.name"],
        rep["passes"]["passes"][0]["name"].as_str().unwrap()
    );
    assert_eq!(r["report.bandwidth.textures"], "");
    assert_eq!(r["report.no.such.field"], "");
    // the frame work is one table entry per cycle and then some: it doubles with s_N
    assert_eq!(
        2.0 * f(&rows[0], "report.cycles.frame"),
        f(&rows[1], "report.cycles.frame")
    );
    let t = std::fs::read_to_string(out.join("t.md")).unwrap();
    assert!(
        t.starts_with("| s_n | report.cycles.frame | report.passes.passes |"),
        "{t}"
    );
    assert!(
        t.contains(&format!("| 16 | {} | 1 |", rep["cycles"]["frame"])),
        "{t}"
    );
    // a table of a report field the file does not ask for is refused before any point runs
    let bad = s.join("bad.ron");
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace("\"report.passes.passes\"]", "\"report.cycles.total\"]");
    std::fs::write(&bad, text).unwrap();
    let o = sweep(&[
        bad.to_str().unwrap(),
        "--out",
        s.join("bad").to_str().unwrap(),
    ]);
    o.expect_code(2, "a table of an unknown report column");
    assert!(o.stderr.contains("report.cycles.total"), "{}", o.stderr);
}

#[test]
fn a_table_column_of_names_joined_by_plus_is_their_sum() {
    let s = Scratch::new("sweep-table-sum");
    let csv = s.join("sweep.csv");
    std::fs::write(
        &csv,
        "index,w,gates.diffuse,gates.specular,status\n0,6,7160.24,10302.64,ok\n1,8,7988,11131,ok\n2,10,,1,error\n",
    )
    .unwrap();
    let o = bumpsim(&[
        "table",
        csv.to_str().unwrap(),
        "--columns",
        "w,gates.diffuse+gates.specular,w + w",
        "--headings",
        "width,pair GE,twice",
        "--digits",
        "1",
    ]);
    o.expect_code(0, "bumpsim table of a sum");
    // a sum of integers is an integer, of any non-integer a number with the digits; an empty
    // or non-numeric term leaves the cell empty
    assert_eq!(
        o.stdout,
        "| width | pair GE | twice |\n|---|---|---|\n| 6 | 17462.9 | 12 |\n| 8 | 19119 | 16 |\n| 10 |  | 20 |\n"
    );
    // every term must be a column: in the command and in a sweep file, before any point runs
    let o = bumpsim(&["table", csv.to_str().unwrap(), "--columns", "w+nope"]);
    o.expect_code(2, "a sum of a missing column");
    assert!(o.stderr.contains("\"nope\""), "{}", o.stderr);
    let file = s.join("bad.ron");
    std::fs::write(
        &file,
        format!(
            r#"(base: {:?}, axes: [(path: "scene.width", values: List([8]))],
    tables: [(name: "t", columns: ["gates_total+gates_nope"])])"#,
            root().join("configs/sgi-teapot.ron").to_str().unwrap()
        ),
    )
    .unwrap();
    let out = s.join("out");
    let o = sweep(&[file.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    o.expect_code(2, "a table summing a missing column");
    assert!(
        o.stderr.contains("gates_nope") && !out.join("sweep.csv").exists(),
        "{}",
        o.stderr
    );
}

/// A sweep with a plot and a table, sharded: the shards draw neither (a shard's rows are
/// part of the front and of the table); `--merge` with the sweep file checks that the rows
/// are its own and draws both as the unsharded run does, byte for byte; a shard without a
/// point is no failure.
#[test]
fn merged_shards_draw_the_plots_and_tables_of_the_unsharded_run() {
    let s = Scratch::new("sweep-merge-draws");
    let file = s.join("drawn.ron");
    let base = root().join("configs/sgi-teapot.ron");
    std::fs::write(
        &file,
        format!(
            r#"(
    base: {:?},
    sets: ["scene.width=32", "scene.height=32"],
    axes: [(path: "engine.units.spec.unit.index_bits", name: "index_bits", values: Grid(4, 6, 3))],
    plots: [(x: "gates_total", y: "quantization_psnr_db", name: "front",
             pareto: ["gates_total:min", "quantization_psnr_db:max"])],
    tables: [(name: "bits", columns: ["index_bits", "gates_total"],
              headings: ["index bits", "gates"])],
)"#,
            base.display().to_string()
        ),
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let (all, s0, s1, s2) = (s.join("all"), s.join("s0"), s.join("s1"), s.join("s2"));
    sweep(&[f, "--out", all.to_str().unwrap()]).expect_code(0, "unsharded");
    for (d, k) in [(&s0, "0/4"), (&s1, "1/4"), (&s2, "2/4")] {
        let o = sweep(&[f, "--out", d.to_str().unwrap(), "--shard", k]);
        o.expect_code(0, k);
        assert!(
            o.stdout.contains("not drawn from a shard's rows"),
            "{}",
            o.stdout
        );
        assert!(!d.join("front.png").exists() && !d.join("bits.md").exists());
    }
    // shard 3/4 of 3 points holds none: its files hold no row, and it succeeds
    let s3 = s.join("s3");
    let o = sweep(&[f, "--out", s3.to_str().unwrap(), "--shard", "3/4"]);
    o.expect_code(0, "an empty shard");
    assert!(o.stdout.contains("0 of 3 points run"), "{}", o.stdout);
    let dirs = [&s0, &s1, &s2, &s3].map(|d| d.to_str().unwrap().to_string());
    let m = s.join("merged");
    let mut args = vec![f, "--merge"];
    args.extend(dirs.iter().map(|d| d.as_str()));
    args.extend(["--out", m.to_str().unwrap()]);
    sweep(&args).expect_code(0, "merge with the sweep file");
    for name in [
        "sweep.csv",
        "sweep.jsonl",
        "sweep.json",
        "front.png",
        "front.svg",
        "front.pareto.csv",
        "bits.md",
    ] {
        assert_eq!(read(&m.join(name)), read(&all.join(name)), "{name}");
    }
    // shards of another sweep (other sets, the same shape): refused, naming the difference
    let other = s.join("other.ron");
    std::fs::write(
        &other,
        std::fs::read_to_string(&file)
            .unwrap()
            .replace("Grid(4, 6, 3)", "Grid(5, 7, 3)"),
    )
    .unwrap();
    let m2 = s.join("merged-other");
    let mut args = vec![other.to_str().unwrap(), "--merge"];
    args.extend(dirs.iter().map(|d| d.as_str()));
    args.extend(["--out", m2.to_str().unwrap()]);
    let o = sweep(&args);
    o.expect_code(2, "merge against another sweep file");
    assert!(
        o.stderr.contains("--merge")
            && o.stderr
                .contains("point 0: the shards' index_bits is \"4\""),
        "{}",
        o.stderr
    );
    assert!(!m2.exists(), "nothing is written");
}

/// More points than one chunk of rows (`sweep::CHUNK`, 256): the rows stream to the files a
/// chunk at a time, in point order, the same bytes at any thread count and after a resume
/// that keeps every second row (the kept rows go in between the chunks' rows).
#[test]
fn rows_stream_in_point_order_across_chunks() {
    let s = Scratch::new("sweep-chunks");
    let file = s.join("many.ron");
    let base = root().join("tests/fixtures/gouraud-tiny.ron");
    std::fs::write(
        &file,
        format!(
            r#"(
    base: {:?},
    axes: [(path: "scene.material.shininess", name: "shininess", values: Grid(2.0, 64.0, 600))],
)"#,
            base.display().to_string()
        ),
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let (a, b) = (s.join("a"), s.join("b"));
    sweep(&[f, "--out", a.to_str().unwrap(), "--threads", "1"]).expect_code(0, "1 thread");
    sweep(&[f, "--out", b.to_str().unwrap(), "--threads", "3"]).expect_code(0, "3 threads");
    let rows = csv_rows(&a.join("sweep.csv"));
    assert_eq!(rows.len(), 600);
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(r["index"], k.to_string());
    }
    for name in ["sweep.csv", "sweep.jsonl", "sweep.json"] {
        assert_eq!(read(&a.join(name)), read(&b.join(name)), "{name}");
    }
    // no temporary file is left
    let left: Vec<String> = std::fs::read_dir(&a)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left.len(), 3, "{left:?}");
    // resume from the odd rows only: the even points run, the files are the same
    let jl = std::fs::read_to_string(b.join("sweep.jsonl")).unwrap();
    let odd: String = jl
        .lines()
        .skip(1)
        .step_by(2)
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(b.join("sweep.jsonl"), odd).unwrap();
    let o = sweep(&[
        f,
        "--out",
        b.to_str().unwrap(),
        "--resume",
        "--threads",
        "2",
    ]);
    o.expect_code(0, "resume");
    assert!(o.stdout.contains("300 points kept"), "{}", o.stdout);
    for name in ["sweep.csv", "sweep.jsonl", "sweep.json"] {
        assert_eq!(
            read(&a.join(name)),
            read(&b.join(name)),
            "{name} after resume"
        );
    }
}

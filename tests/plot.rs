//! End-to-end tests of `bumpsim plot` and of a sweep file's `plots`: PNG and SVG from a real
//! small sweep (the PNG decodes, the SVG names its axes, two runs give the same bytes), the
//! Pareto rows, error rows skipped and counted, bad input exits 2.

mod common;

use common::*;
use std::path::Path;

/// A 5-point sweep of the 32x32 teapot over the table's index bits; point 2 (0 bits) is
/// rejected, so it is an error row. `plots` is put into the file as given.
fn sweep_file(dir: &Path, plots: &str) -> String {
    let base = root().join("configs/sgi-teapot.ron");
    let file = dir.join("s.ron");
    std::fs::write(
        &file,
        format!(
            r#"(
    base: {:?},
    sets: ["scene.width=32", "scene.height=32"],
    axes: [(path: "engine.units.spec.unit.index_bits", name: "index_bits", values: List([4, 6, 0, 8, 10]))],
    plots: [{plots}],
)"#,
            base.display().to_string()
        ),
    )
    .unwrap();
    file.to_str().unwrap().to_string()
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The rows of a CSV without quoted fields, each split at commas (the header first).
fn rows(p: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(p)
        .unwrap()
        .lines()
        .map(|l| l.split(',').map(String::from).collect())
        .collect()
}

const PLOTS: &str = r#"(x: "gates_total", y: "quantization_psnr_db", kind: Scatter,
        pareto: ["gates_total:min", "quantization_psnr_db:max", "cycles:min"], name: "front"),
    (x: "index_bits", y: "quantization_banding", kind: Line)"#;

#[test]
fn plots_of_a_sweep_png_svg_pareto_and_the_same_bytes_twice() {
    let s = Scratch::new("plot");
    let file = sweep_file(&s.path, PLOTS);
    let d = s.join("out");
    let o = bumpsim(&["sweep", &file, "--out", d.to_str().unwrap()]);
    o.expect_code(0, "the sweep with plots");
    assert!(
        o.stdout.contains("5 of 5 points run, 1 with errors"),
        "{}",
        o.stdout
    );
    assert!(
        o.stdout.contains("front.{png,svg} and .pareto.csv")
            && o.stdout.contains("skipped 1 error rows"),
        "{}",
        o.stdout
    );
    for f in [
        "front.png",
        "front.svg",
        "front.pareto.csv",
        "quantization_banding-vs-index_bits.png",
        "quantization_banding-vs-index_bits.svg",
    ] {
        assert!(d.join(f).is_file(), "{f}: {:?}", listing(&d));
    }
    let csv = d.join("sweep.csv");

    // the CLI: PNG and SVG, each twice
    let mut bytes = Vec::new();
    for (k, name) in ["a.png", "b.png", "a.svg", "b.svg"].iter().enumerate() {
        let out = s.join(name);
        let o = bumpsim(&[
            "plot",
            csv.to_str().unwrap(),
            "--x",
            "gates_total",
            "--y",
            "quantization_psnr_db",
            "--pareto",
            "gates_total:min,quantization_psnr_db:max,cycles:min",
            "--out",
            out.to_str().unwrap(),
        ]);
        o.expect_code(0, name);
        assert!(
            o.stdout.contains("plotted 4 rows")
                && o.stdout
                    .contains("skipped 1 error rows, 0 rows with a non-numeric cell"),
            "{}",
            o.stdout
        );
        bytes.push(read(&out));
        if k % 2 == 1 {
            assert_eq!(bytes[k], bytes[k - 1], "{name}: two runs, other bytes");
        }
    }
    // the sweep's plot of the same request is the same file
    assert_eq!(bytes[0], read(&d.join("front.png")));
    assert_eq!(bytes[2], read(&d.join("front.svg")));
    let png = image::load_from_memory(&bytes[0]).expect("the PNG decodes");
    assert_eq!((png.width(), png.height()), (800, 600));
    // not blank: more than the background and one colour
    let rgb = png.to_rgb8();
    let mut colours: Vec<[u8; 3]> = rgb.pixels().map(|p| p.0).collect();
    colours.sort();
    colours.dedup();
    assert!(colours.len() > 10, "{} colours", colours.len());
    let svg = String::from_utf8(bytes[2].clone()).unwrap();
    assert!(svg.starts_with("<svg"), "{}", &svg[..100]);
    for label in ["gates_total", "quantization_psnr_db", "Pareto front"] {
        assert!(svg.contains(label), "the SVG names {label}");
    }

    // the front: the ok rows no other ok row dominates (on all three objectives)
    let all = rows(&csv);
    let col = |n: &str| all[0].iter().position(|h| h == n).unwrap();
    let (g, q, c, st) = (
        col("gates_total"),
        col("quantization_psnr_db"),
        col("cycles"),
        col("status"),
    );
    let ok: Vec<&Vec<String>> = all[1..].iter().filter(|r| r[st] == "ok").collect();
    let v = |r: &Vec<String>| -> [f64; 3] {
        [
            r[g].parse().unwrap(),
            -r[q].parse::<f64>().unwrap(),
            r[c].parse().unwrap(),
        ]
    };
    let dominated = |r: &Vec<String>| {
        ok.iter().any(|o| {
            let (a, b) = (v(o), v(r));
            a.iter().zip(&b).all(|(x, y)| x <= y) && a.iter().zip(&b).any(|(x, y)| x < y)
        })
    };
    let expect: Vec<String> = ok
        .iter()
        .filter(|r| !dominated(r))
        .map(|r| r[0].clone())
        .collect();
    let front = rows(&s.join("a.pareto.csv"));
    assert_eq!(front[0], all[0], "the header");
    let got: Vec<String> = front[1..].iter().map(|r| r[0].clone()).collect();
    assert_eq!(got, expect);
    assert!(!got.is_empty() && !got.contains(&"2".to_string()));
    assert_eq!(
        read(&s.join("a.pareto.csv")),
        read(&d.join("front.pareto.csv"))
    );
}

#[test]
fn bad_plot_input_exits_2_naming_file_column_and_expectation() {
    let s = Scratch::new("plot-bad");
    let file = sweep_file(&s.path, "");
    let d = s.join("out");
    bumpsim(&["sweep", &file, "--out", d.to_str().unwrap()]).expect_code(0, "the sweep");
    let csv = d.join("sweep.csv");
    let c = csv.to_str().unwrap();
    let png = s.join("p.png");
    let p = png.to_str().unwrap();
    std::fs::write(s.join("empty.csv"), "").unwrap();
    let empty = s.join("empty.csv");
    let cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        (
            vec![c, "--x", "nope", "--y", "cycles", "--out", p],
            vec!["sweep.csv", "nope", "no such column"],
        ),
        (
            vec![c, "--x", "config_hash", "--y", "cycles", "--out", p],
            vec!["sweep.csv", "config_hash", "expected numbers"],
        ),
        (
            vec![
                c,
                "--x",
                "cycles",
                "--y",
                "gates_total",
                "--pareto",
                "cycles:up",
                "--out",
                p,
            ],
            vec!["--pareto", "cycles:up", "expected min or max"],
        ),
        (
            vec![
                c,
                "--x",
                "cycles",
                "--y",
                "gates_total",
                "--pareto",
                "nope:min",
                "--out",
                p,
            ],
            vec!["sweep.csv", "nope", "no such column"],
        ),
        (
            vec![
                c,
                "--x",
                "cycles",
                "--y",
                "gates_total",
                "--out",
                "/nonexistent-dir/p.png",
            ],
            vec!["/nonexistent-dir/p.png", "cannot write"],
        ),
        (
            vec![c, "--x", "cycles", "--y", "gates_total", "--out", "p.jpg"],
            vec!["p.jpg", ".png or .svg"],
        ),
        (
            vec![
                empty.to_str().unwrap(),
                "--x",
                "cycles",
                "--y",
                "gates_total",
                "--out",
                p,
            ],
            vec!["empty.csv", "empty"],
        ),
    ];
    for (args, needles) in cases {
        let o = bumpsim(&[&["plot"], &args[..]].concat());
        o.expect_code(2, &args.join(" "));
        for n in needles {
            assert!(o.stderr.contains(n), "{args:?}: {n}: {}", o.stderr);
        }
        assert!(!png.exists(), "nothing is written");
    }
    // a sweep file's plots are checked before anything runs
    for (plots, needle) in [
        (r#"(x: "nope", y: "cycles")"#, "plots[0].x"),
        (
            r#"(x: "cycles", y: "cycles", pareto: ["cycles:up"])"#,
            "plots[0].pareto",
        ),
        (r#"(x: "cycles", y: "cycles", colour: "red")"#, "colour"),
    ] {
        let file = sweep_file(&s.path, plots);
        let out = s.join("never");
        let o = bumpsim(&["sweep", &file, "--out", out.to_str().unwrap()]);
        o.expect_code(2, plots);
        assert!(o.stderr.contains(needle), "{plots}: {}", o.stderr);
        assert!(!out.exists(), "nothing is run or written");
    }
}

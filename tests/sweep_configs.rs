//! End-to-end tests of a sweep over engines (the `@config` axis), axis labels and light
//! shares (`docs/sweep.md`): the three pipeline orders of Ernst et al. §5.1 at 64 x 64.

mod common;

use common::*;
use serde_json::Value;
use std::path::Path;

const ORDERS: [&str; 3] = [
    "gouraud-order-split",
    "gouraud-order-combined",
    "gouraud-order-multiplicative",
];

/// A sweep file over the three orders (absolute config paths), labelled, with the light
/// shares on black and white checker texels; `extra`: more fields of the file.
fn orders_sweep(extra: &str) -> String {
    let files: Vec<String> = ORDERS
        .iter()
        .map(|c| format!("{:?}", config(c).display().to_string()))
        .collect();
    format!(
        r#"(
    base: {base:?},
    sets: ["scene.width=64", "scene.height=64"],
    axes: [(path: "@config", name: "order", values: List([{files}]),
            labels: ["split", "additive", "multiplying"])],
    shares: [
        (name: "black", mask: ["engine.output=\"tex.t\""], colour: (0, 0, 0)),
        (name: "white", mask: ["engine.output=\"tex.t\""], colour: (255, 255, 255)),
    ],
    {extra}
)"#,
        base = config(ORDERS[0]).display().to_string(),
        files = files.join(", "),
    )
}

/// `bumpsim sweep FILE --out OUT`.
fn sweep(file: &Path, out: &Path) -> Out {
    bumpsim(&[
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
}

fn rows(dir: &Path) -> Vec<Value> {
    std::fs::read_to_string(dir.join("sweep.jsonl"))
        .unwrap()
        .lines()
        .map(json)
        .collect()
}

#[test]
fn a_config_axis_runs_each_engine_labels_its_rows_and_measures_light_shares() {
    let s = Scratch::new("sweep-configs");
    let file = s.join("orders.ron");
    std::fs::write(&file, orders_sweep("")).unwrap();
    let out = s.join("out");
    let o = sweep(&file, &out);
    o.expect_code(0, "the orders sweep");
    let r = rows(&out);
    assert_eq!(r.len(), 3);
    // the labels, not the file names, in the axis column
    let labels: Vec<&str> = r.iter().map(|x| x["order"].as_str().unwrap()).collect();
    assert_eq!(labels, ["split", "additive", "multiplying"]);
    for (row, c) in r.iter().zip(ORDERS) {
        assert_eq!(row["status"], "ok", "{row}");
        // each row is its config's run: the same hash and error as `bumpsim report`
        let rep = bumpsim(&[
            "report",
            config(c).to_str().unwrap(),
            "--set",
            "scene.width=64",
            "--set",
            "scene.height=64",
            "--json",
        ]);
        rep.expect_code(0, c);
        let rep = json(&rep.stdout);
        assert_eq!(row["config_hash"], rep["config_hash"], "{c}");
        assert_eq!(
            row["total_psnr_db"], rep["error"]["total"]["psnr_db"],
            "{c}"
        );
    }
    // gate columns: the union of the engines' units, empty where an engine lacks one
    assert!(r[0]["gates.diffuse"].as_f64().unwrap() > 0.0);
    assert!(r[1]["gates.diffuse"].is_null());
    assert!(r[1]["gates.blend"].as_f64().unwrap() > 0.0);
    assert!(r[0]["gates.blend"].is_null());
    // §5.1: the texture multiplying the combined blend leaves no light on black texels; the
    // split order keeps most of the highlight there; the additive order adds the diffuse
    // light on top of it; every order keeps the white texels' light
    let share = |k: usize, c: &str| r[k][format!("share.{c}")].as_f64().unwrap();
    assert_eq!(share(2, "black"), 0.0);
    assert!(
        (0.8..0.95).contains(&share(0, "black")),
        "{}",
        share(0, "black")
    );
    assert!(share(1, "black") > 2.0, "{}", share(1, "black"));
    for k in 0..3 {
        assert!(
            (0.95..1.05).contains(&share(k, "white")),
            "{}",
            share(k, "white")
        );
    }
    // a resumed run keeps every labelled row
    let o = bumpsim(&[
        "sweep",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--resume",
    ]);
    o.expect_code(0, "resume");
    let said = format!("{}{}", o.stdout, o.stderr);
    assert!(said.contains("3 points kept"), "{said}");
    assert!(said.contains("0 of 3 points run"), "{said}");
    // the rows as a cross table: the engines across
    let csv = out.join("sweep.csv");
    let o = bumpsim(&[
        "table",
        csv.to_str().unwrap(),
        "--columns",
        "status",
        "--pivot",
        "order=share.black",
        "--digits",
        "1",
    ]);
    o.expect_code(0, "table --pivot");
    let lines: Vec<&str> = o.stdout.lines().collect();
    assert_eq!(lines[0], "| status | split | additive | multiplying |");
    assert!(
        lines[2].starts_with("| ok | 0.") && lines[2].ends_with(" | 0.0 |"),
        "{}",
        o.stdout
    );
    let o = bumpsim(&[
        "table",
        csv.to_str().unwrap(),
        "--columns",
        "status",
        "--pivot",
        "order",
    ]);
    o.expect_code(2, "--pivot without a value");
    assert!(o.stderr.contains("--pivot"), "{}", o.stderr);
}

#[test]
fn bad_labels_config_axes_and_shares_are_rejected() {
    let s = Scratch::new("sweep-configs-bad");
    let out = s.join("out");
    let base = config(ORDERS[0]).display().to_string();
    let cases = [
        (
            format!(
                r#"(base: {base:?}, axes: [(path: "scene.width", values: List([64, 96]), labels: ["a"])])"#
            ),
            "axes[0].labels",
        ),
        (
            format!(
                r#"(base: {base:?}, axes: [(path: "scene.width", values: Grid(64, 96, 2), labels: ["a", "b"])])"#
            ),
            "axes[0].labels",
        ),
        (
            format!(r#"(base: {base:?}, axes: [(path: "@config", values: Grid(1, 2, 2))])"#),
            "config files",
        ),
        (
            format!(
                r#"(base: {base:?}, axes: [(path: "@config", also: ["x"], values: List(["a.ron"]))])"#
            ),
            "axes[0].also",
        ),
        (
            format!(
                r#"(base: {base:?}, axes: [(path: "scene.width", values: List([64]))],
                    shares: [(name: "a", mask: [], colour: (0, 0, 0)), (name: "a", mask: [], colour: (1, 1, 1))])"#
            ),
            "shares[1].name",
        ),
    ];
    for (text, needle) in cases {
        let file = s.join("s.ron");
        std::fs::write(&file, &text).unwrap();
        let o = sweep(&file, &out);
        o.expect_code(2, &text);
        assert!(o.stderr.contains(needle), "{text}: {}", o.stderr);
        assert!(!out.exists(), "nothing is written");
    }
    // a missing config and a mask that does not load are error rows that name the cause
    let text = format!(
        r#"(base: {base:?}, sets: ["scene.width=32", "scene.height=32"],
            axes: [(path: "@config", values: List(["no-such.ron", {base:?}]))],
            shares: [(name: "x", mask: ["engine.output=\"nope.c\""], colour: (0, 0, 0))])"#
    );
    let file = s.join("s.ron");
    std::fs::write(&file, &text).unwrap();
    let o = sweep(&file, &out);
    o.expect_code(0, "error rows");
    let r = rows(&out);
    assert_eq!(r[0]["status"], "error");
    assert!(
        r[0]["error"].as_str().unwrap().contains("no-such.ron"),
        "{}",
        r[0]
    );
    assert_eq!(r[1]["status"], "error");
    let e = r[1]["error"].as_str().unwrap();
    assert!(
        e.contains("mask of share \"x\"") && e.contains("nope"),
        "{e}"
    );
}

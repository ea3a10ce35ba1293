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

/// Run `bumpsim plot CSV --x x --y y --out OUT` (and `extra`), killed after 60 s: every input
/// must finish in bounded time (a range overflowing to infinity once spun for minutes).
fn plot_bounded(csv: &Path, out: &Path, extra: &[&str]) -> Out {
    use std::io::Read;
    use std::time::{Duration, Instant};
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_bumpsim"))
        .args(["plot", csv.to_str().unwrap(), "--x", "x", "--y", "y"])
        .args(extra)
        .args(["--out", out.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the bumpsim binary runs");
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if t0.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            child.wait().unwrap();
            panic!("{}: bumpsim plot still running after 60 s", csv.display());
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let (mut stdout, mut stderr) = (String::new(), String::new());
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut stdout)
        .unwrap();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    Out {
        code: status.code().unwrap_or(-1),
        stdout,
        stderr,
    }
}

/// Whether an SVG is well formed: tags nest and close, attributes are quoted, text and
/// attribute values hold no raw `<` and only the XML entities after `&`; one `svg` root.
fn well_formed(svg: &str) -> Result<(), String> {
    let entity = |s: &str| {
        ["&amp;", "&lt;", "&gt;", "&quot;", "&apos;"]
            .iter()
            .any(|e| s.starts_with(e))
    };
    let mut stack: Vec<&str> = Vec::new();
    let mut roots = 0;
    let mut rest = svg;
    while let Some(i) = rest.find('<') {
        let text = &rest[..i];
        for (k, _) in text.match_indices('&') {
            if !entity(&text[k..]) {
                return Err(format!("a raw & in text: {:?}", &text[k..]));
            }
        }
        let end = rest[i..].find('>').ok_or("a tag without its >")? + i;
        let tag = &rest[i + 1..end];
        rest = &rest[end + 1..];
        if tag.starts_with('?') || tag.starts_with('!') {
            continue;
        }
        if tag.contains('<') || tag.matches('"').count() & 1 == 1 {
            return Err(format!("a malformed tag: <{tag}>"));
        }
        for (k, _) in tag.match_indices('&') {
            if !entity(&tag[k..]) {
                return Err(format!("a raw & in <{tag}>"));
            }
        }
        if let Some(name) = tag.strip_prefix('/') {
            match stack.pop() {
                Some(open) if open == name.trim() => {}
                other => return Err(format!("</{name}> closes {other:?}")),
            }
            continue;
        }
        let name = tag
            .split(|c: char| c.is_whitespace() || c == '/')
            .next()
            .unwrap_or("");
        if name.is_empty() {
            return Err(format!("a tag without a name: <{tag}>"));
        }
        if stack.is_empty() {
            roots += 1;
        }
        if !tag.ends_with('/') {
            stack.push(name);
        }
    }
    if !rest.trim().is_empty() || !stack.is_empty() || roots != 1 {
        return Err(format!(
            "unclosed {stack:?}, {roots} roots, trailing {rest:?}"
        ));
    }
    Ok(())
}

/// The `aria-label`s of an SVG's text paths, in order.
fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<path aria-label=\"")
        .skip(1)
        .map(|s| s[..s.find('"').unwrap()].to_string())
        .collect()
}

/// Columns whose range overflows f64, holds non-finite cells, has no width, or no number:
/// each plot finishes (in milliseconds) with a sane PNG and SVG, or exits 2 naming the file,
/// the column and what was expected.
#[test]
fn extreme_and_degenerate_columns_plot_in_bounded_time_or_exit_2() {
    let s = Scratch::new("plot-extreme");
    let ok: &[(&str, &str, &[&str])] = &[
        // the reported hang: the y range overflows to infinity
        ("overflow", "1,1e308\n2,-1e308\n", &["-1e308", "0", "1e308"]),
        (
            "max",
            "1,1.7976931348623157e308\n2,-1.7976931348623157e308\n3,0\n",
            &["0"],
        ),
        // NaN, infinities and a number beyond f64 are skipped and counted
        (
            "non-finite",
            "1,NaN\n2,inf\n3,-inf\n4,1e999\n5,2\n6,4\n",
            &["2", "3", "4"],
        ),
        ("single", "3,5\n3,5\n3,5\n", &["5"]),
        ("zero", "0,0\n", &["0"]),
        ("narrow", "1,1e15\n2,1000000000000000.125\n", &[]),
        ("tiny", "1,5e-324\n2,1e-323\n", &[]),
        ("huge-x", "-1e300,1\n1e300,2\n", &["-1e300", "1e300"]),
    ];
    for (name, rows, labels) in ok {
        let csv = s.join(&format!("{name}.csv"));
        std::fs::write(&csv, format!("x,y\n{rows}")).unwrap();
        let png = s.join(&format!("{name}.png"));
        let t0 = std::time::Instant::now();
        let o = plot_bounded(&csv, &png, &[]);
        o.expect_code(0, name);
        assert!(t0.elapsed().as_secs() < 20, "{name}: {:?}", t0.elapsed());
        let img = image::open(&png).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((img.width(), img.height()), (800, 600), "{name}");
        let svg_path = s.join(&format!("{name}.svg"));
        plot_bounded(&csv, &svg_path, &["--kind", "line"]).expect_code(0, name);
        let svg = std::fs::read_to_string(&svg_path).unwrap();
        well_formed(&svg).unwrap_or_else(|e| panic!("{name}: {e}"));
        let texts = svg_texts(&svg);
        for l in *labels {
            assert!(texts.iter().any(|t| t == l), "{name}: {l:?} in {texts:?}");
        }
        // every tick label is a number, none of them "inf" or "NaN"
        for t in &texts[1..texts.len() - 2] {
            let v: f64 = t
                .parse()
                .unwrap_or_else(|_| panic!("{name}: tick {t:?} in {texts:?}"));
            assert!(v.is_finite(), "{name}: {t}");
        }
    }
    let o = plot_bounded(&s.join("non-finite.csv"), &s.join("n.png"), &[]);
    assert!(
        o.stdout
            .contains("plotted 2 rows; skipped 0 error rows, 4 rows with a non-numeric cell"),
        "{}",
        o.stdout
    );

    let bad: &[(&str, &str, &[&str])] = &[
        (
            "empty-y",
            "1,\n2,\n",
            &["empty-y.csv", "y", "every cell is empty"],
        ),
        (
            "all-nan",
            "1,NaN\n2,inf\n",
            &[
                "all-nan.csv",
                "y",
                "not a numeric column",
                "expected numbers",
            ],
        ),
        (
            "overflowing-cells",
            "1e400,1\n-1e400,2\n",
            &["overflowing-cells.csv", "x", "1e400", "expected numbers"],
        ),
    ];
    for (name, rows, needles) in bad {
        let csv = s.join(&format!("{name}.csv"));
        std::fs::write(&csv, format!("x,y\n{rows}")).unwrap();
        let png = s.join(&format!("{name}.png"));
        let o = plot_bounded(&csv, &png, &[]);
        o.expect_code(2, name);
        for n in *needles {
            assert!(o.stderr.contains(n), "{name}: {n}: {}", o.stderr);
        }
        assert!(!png.exists(), "{name}: nothing is written");
    }
}

/// The SVG draws every text as paths of the bundled font (no `<text>`, no font family for
/// the viewer to substitute), each path labelled with its text; it is well formed and the
/// same bytes every run. Tick labels read "18000", not "18000.0".
#[test]
fn the_svg_draws_its_text_as_font_paths_and_ticks_have_no_needless_decimals() {
    let s = Scratch::new("plot-svg");
    let csv = s.join("c.csv");
    std::fs::write(
        &csv,
        "x,y,status\n18000,1.5,ok\n19000,2.25,ok\n25000,3,ok\n20000,0,error\n",
    )
    .unwrap();
    let (a, b) = (s.join("a.svg"), s.join("b.svg"));
    plot_bounded(&csv, &a, &[]).expect_code(0, "a.svg");
    plot_bounded(&csv, &b, &[]).expect_code(0, "b.svg");
    assert_eq!(read(&a), read(&b), "two runs, other bytes");
    let svg = std::fs::read_to_string(&a).unwrap();
    well_formed(&svg).unwrap();
    assert!(!svg.contains("<text"), "no text element");
    assert!(!svg.contains("font-family"), "no font family");
    let texts = svg_texts(&svg);
    // the title, the ticks, the axes' names
    assert_eq!(texts[0], "y vs x");
    assert!(
        texts.ends_with(&["x".to_string(), "y".to_string()]),
        "{texts:?}"
    );
    let ticks = &texts[1..texts.len() - 2];
    for want in ["18000", "20000", "25000", "1.6", "2", "2.4", "3"] {
        assert!(ticks.iter().any(|t| t == want), "{want} in {ticks:?}");
    }
    assert!(
        ticks.iter().all(|t| !t.ends_with(".0") && !t.contains('e')),
        "{ticks:?}"
    );
    // each text is a filled outline: moves, lines and quadratic curves
    let d = &svg[svg.find("aria-label=\"y vs x\" d=\"").unwrap()..];
    let d = &d[d.find("d=\"").unwrap() + 3..];
    let d = &d[..d.find('"').unwrap()];
    assert!(
        d.starts_with('M') && d.contains('Q') && d.ends_with('Z'),
        "{d:.80}"
    );
}

/// A three-objective front's title is wider than the canvas at full size: it is wrapped
/// onto lines that each fit, and the PNG has no ink at its left and right edges.
#[test]
fn a_long_title_wraps_within_the_canvas() {
    use bumpsim_pipeline::plot::{draw, font};
    let title = "quantization_psnr_db vs gates_total (front of gates_total:min, \
                 quantization_psnr_db:max, cycles:min)";
    let f = font::font();
    assert!(
        f.width(title, 20.0) > 800.0,
        "wider than the canvas unwrapped"
    );
    let (lines, size) = draw::fit_title(title);
    let lines: Vec<&str> = lines.split('\n').collect();
    assert_eq!((lines.len(), size), (2, 20.0), "{lines:?}");
    for l in &lines {
        let w = f.width(l, size);
        assert!(w <= draw::TITLE_WIDTH && w > 300.0, "{l}: {w}");
    }

    let s = Scratch::new("plot-title");
    let csv = s.join("c.csv");
    std::fs::write(
        &csv,
        "gates_total,quantization_psnr_db,cycles\n100,30,5\n200,40,6\n150,20,4\n",
    )
    .unwrap();
    let png = s.join("front.png");
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
        png.to_str().unwrap(),
    ]);
    o.expect_code(0, "the front");
    let img = image::open(&png).unwrap().to_rgb8();
    let dark = |x: u32, y: u32| img.get_pixel(x, y).0.iter().all(|c| *c < 128);
    // the title's two lines: ink in the first 24 rows and in the 20 below them
    let ink = |y0: u32, y1: u32| (y0..y1).any(|y| (0..800).any(|x| dark(x, y)));
    assert!(ink(0, 28) && ink(28, 50), "two lines of title");
    for y in 0..60 {
        for x in (0..10).chain(790..800) {
            assert!(!dark(x, y), "ink at the edge ({x}, {y})");
        }
    }
    let svg = s.join("front.svg");
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
        svg.to_str().unwrap(),
    ]);
    o.expect_code(0, "the front's SVG");
    let texts = svg_texts(&std::fs::read_to_string(&svg).unwrap());
    assert_eq!(texts[0], lines.join(" "));
}

/// PSNR 999 dB (the cap of identical images) is left out of the axis' range: the ticks
/// span the other values, the capped points are drawn at the edge and counted.
#[test]
fn psnr_at_the_cap_is_drawn_at_the_edge_not_in_the_range() {
    let s = Scratch::new("plot-cap");
    let csv = s.join("c.csv");
    std::fs::write(
        &csv,
        "s_n,baseline_psnr_db\n16,14.9\n256,27.1\n4096,999\n4096,40.8\n16384,999\n",
    )
    .unwrap();
    let svg = s.join("p.svg");
    let o = bumpsim(&[
        "plot",
        csv.to_str().unwrap(),
        "--x",
        "s_n",
        "--y",
        "baseline_psnr_db",
        "--out",
        svg.to_str().unwrap(),
    ]);
    o.expect_code(0, "the capped plot");
    assert!(
        o.stdout.contains(
            "plotted 5 rows; skipped 0 error rows, 0 rows with a non-numeric cell; \
             2 at the PSNR cap (999 dB, identical images) drawn at the axis' edge"
        ),
        "{}",
        o.stdout
    );
    let texts = svg_texts(&std::fs::read_to_string(&svg).unwrap());
    let y_ticks: Vec<f64> = texts
        .iter()
        .filter_map(|t| t.parse::<f64>().ok())
        .filter(|v| *v < 1000.0)
        .collect();
    assert!(
        y_ticks.contains(&15.0) && y_ticks.contains(&40.0),
        "{texts:?}"
    );
    assert!(
        !texts
            .iter()
            .any(|t| t == "1000" || t == "999" || t == "500"),
        "the cap is out of the range: {texts:?}"
    );
    assert!(
        texts.iter().any(|t| t.contains("2 at the PSNR cap 999 dB")),
        "{texts:?}"
    );
    // not a PSNR column: 999 is a value like any other
    let csv2 = s.join("d.csv");
    std::fs::write(&csv2, "x,y\n1,10\n2,999\n").unwrap();
    let o = plot_bounded(&csv2, &s.join("d.svg"), &[]);
    o.expect_code(0, "no cap");
    assert!(!o.stdout.contains("PSNR cap"), "{}", o.stdout);
}

/// `--x-log` and `--y-range`: a log axis ticks the decades and skips (and counts) rows not
/// above 0; a given range is kept exactly and rows beyond it are drawn at its edge and
/// counted; bad ranges exit 2 naming the flag or the sweep file's field.
#[test]
fn log_axes_and_given_ranges() {
    let s = Scratch::new("plot-scale");
    let csv = s.join("c.csv");
    std::fs::write(&csv, "x,y\n0,5\n16,10\n256,20\n4096,30\n16384,80\n").unwrap();
    let svg = s.join("p.svg");
    let o = plot_bounded(&csv, &svg, &["--x-log", "--y-range", "0,40"]);
    o.expect_code(0, "log x, y range");
    assert!(
        o.stdout.contains(
            "plotted 4 rows; skipped 0 error rows, 0 rows with a non-numeric cell; skipped 1 \
             rows not above 0 on a log axis; 1 beyond an axis' range drawn at its edge"
        ),
        "{}",
        o.stdout
    );
    let texts = svg_texts(&std::fs::read_to_string(&svg).unwrap());
    for t in ["10", "100", "1000", "10000", "0", "40"] {
        assert!(texts.iter().any(|x| x == t), "{t}: {texts:?}");
    }
    assert!(!texts.iter().any(|x| x == "5000"), "{texts:?}");
    let bad: &[(&[&str], &str)] = &[
        (&["--x-range", "5,1"], "--x-range"),
        (&["--y-range", "1"], "--y-range"),
        (&["--y-log", "--y-range", "0,10"], "above 0"),
        (&["--x-range", "nan,1"], "finite"),
    ];
    for (args, needle) in bad {
        let o = plot_bounded(&csv, &s.join("bad.svg"), args);
        o.expect_code(2, needle);
        assert!(o.stderr.contains(needle), "{args:?}: {}", o.stderr);
        assert!(!s.join("bad.svg").exists());
    }
    // every row not above 0 on the log axis: nothing to plot, exit 2
    std::fs::write(&csv, "x,y\n1,0\n2,-1\n").unwrap();
    let o = plot_bounded(&csv, &svg, &["--y-log"]);
    o.expect_code(2, "no positive y");
    assert!(
        o.stderr.contains("2 not above 0 on a log axis"),
        "{}",
        o.stderr
    );
    // in a sweep file: checked before any point runs
    let file = sweep_file(
        &s.path,
        r#"(x: "index_bits", y: "cycles", x_scale: (range: Some((4.0, 2.0))))"#,
    );
    let o = bumpsim(&["sweep", &file, "--out", s.join("o").to_str().unwrap()]);
    o.expect_code(2, "bad x_scale");
    assert!(o.stderr.contains("plots[0].x_scale.range"), "{}", o.stderr);
    let file = sweep_file(
        &s.path,
        r#"(x: "index_bits", y: "cycles", y_scale: (log: true), name: "log")"#,
    );
    let o = bumpsim(&["sweep", &file, "--out", s.join("o2").to_str().unwrap()]);
    o.expect_code(0, "log y in a sweep");
    assert!(s.join("o2/log.png").exists() && s.join("o2/log.svg").exists());
}

//! The study pages are written from their sources by `bumpsim study` (`docs/studies.md`):
//! each committed page is what its source gives with its sweeps' committed rows, so no number
//! of a page is typed by hand (`tests/study_sweeps.rs` checks that the rows are current).

mod common;

use common::*;

/// The page sources, `docs/studies/*.src.md`, relative to the repository root.
fn sources() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(root().join("docs/studies"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".src.md"))
        .map(|n| format!("docs/studies/{n}"))
        .collect();
    v.sort();
    v
}

#[test]
fn every_page_is_what_its_source_gives() {
    let src = sources();
    assert!(!src.is_empty());
    let mut args = vec!["study".to_string()];
    args.extend(src.iter().cloned());
    args.extend(["--reuse".into(), "--check".into()]);
    let o = bumpsim(&args);
    o.expect_code(0, "bumpsim study --reuse --check");
}

/// Every study page has a source: a page with none would hold numbers typed by hand.
#[test]
fn every_study_page_has_a_source() {
    let src = sources();
    for e in std::fs::read_dir(root().join("docs/studies")).unwrap() {
        let n = e.unwrap().file_name().to_string_lossy().into_owned();
        if let Some(stem) = n.strip_suffix(".md").filter(|s| !s.ends_with(".src")) {
            let want = format!("docs/studies/{stem}.src.md");
            assert!(src.contains(&want), "docs/studies/{n} has no source {want}");
        }
    }
}

#[test]
fn a_stale_page_fails_the_check_and_a_bad_directive_names_its_line() {
    let s = Scratch::new("study-pages");
    let dir = s.join("docs");
    std::fs::create_dir_all(dir.join("sweeps")).unwrap();
    let base = root().join("configs/sgi-teapot.ron");
    let sweep = format!(
        "(base: {base:?}, \
                 sets: [\"scene.width=24\", \"scene.height=24\"], \
                 axes: [(path: \"engine.units.spec.unit.index_bits\", name: \"bits\", \
                 values: List([4, 6]))], \
                 tables: [(name: \"t\", columns: [\"bits\", \"gates_total\"])])"
    );
    std::fs::write(dir.join("sweeps/s.ron"), sweep).unwrap();
    let src = dir.join("p.src.md");
    std::fs::write(
        &src,
        "# P\n{{run sweeps/s.ron -> out/s}}\n\n{{table s t}}\n\nAt 6 bits: \
         {{value s gates_total bits=6 / gates_total bits=4 :3}}x the gates of 4 bits; \
         {{count s}} points.\n",
    )
    .unwrap();
    let p = src.to_str().unwrap();
    // a page never written is stale
    bumpsim(&["study", p, "--reuse", "--check"]).expect_code(2, "no rows yet");
    bumpsim(&["study", p]).expect_code(0, "the first run");
    let page = std::fs::read_to_string(dir.join("p.md")).unwrap();
    let csv = std::fs::read_to_string(dir.join("out/s/sweep.csv")).unwrap();
    let table = std::fs::read_to_string(dir.join("out/s/t.md")).unwrap();
    assert!(page.starts_with("<!-- generated from p.src.md"), "{page}");
    assert!(page.contains(table.trim_end()), "{page}");
    assert!(
        page.contains("# P\n\n| bits |"),
        "the run line is gone: {page}"
    );
    assert!(
        page.contains("x the gates of 4 bits; 2 points.\n"),
        "{page}"
    );
    assert_eq!(csv.lines().count(), 3);
    bumpsim(&["study", p, "--reuse", "--check"]).expect_code(0, "fresh");
    std::fs::write(dir.join("p.md"), page.replace("2 points", "3 points")).unwrap();
    let o = bumpsim(&["study", p, "--reuse", "--check"]);
    o.expect_code(1, "stale");
    assert!(o.stderr.contains("p.md"), "{}", o.stderr);
    // a bad directive: exit 2 naming the source and its line, the page untouched
    let before = std::fs::read_to_string(dir.join("p.md")).unwrap();
    std::fs::write(
        &src,
        "# P\n{{run sweeps/s.ron -> out/s}}\n\n{{value s nope bits=6}}\n",
    )
    .unwrap();
    let o = bumpsim(&["study", p, "--reuse"]);
    o.expect_code(2, "bad column");
    assert!(
        o.stderr.contains("p.src.md") && o.stderr.contains(":4"),
        "{}",
        o.stderr
    );
    assert!(o.stderr.contains("no column \"nope\""), "{}", o.stderr);
    assert_eq!(std::fs::read_to_string(dir.join("p.md")).unwrap(), before);
    // a NUL in the source (the expander's own marker) is refused, naming line and column
    std::fs::write(&src, "# P\n{{run sweeps/s.ron -> out/s}}\n\nab\u{0}c\n").unwrap();
    let o = bumpsim(&["study", p, "--reuse"]);
    o.expect_code(2, "NUL");
    assert!(
        o.stderr.contains("p.src.md") && o.stderr.contains(":4:3") && o.stderr.contains("NUL"),
        "{}",
        o.stderr
    );
    assert_eq!(std::fs::read_to_string(dir.join("p.md")).unwrap(), before);
    // pictures: rendered, cropped and zoomed; a crop outside the image is exit 2
    let cfg = root().join("configs/sgi-teapot.ron");
    let render = |opts: &str| {
        format!(
            "# P\n{{{{render {} set=scene.width=24 set=scene.height=24 -> pics/a.png \
             reference=pics/r.png quantization=pics/q.png gain=8 {opts}}}}}\n![](pics/a.png)\n",
            cfg.display()
        )
    };
    std::fs::write(&src, render("crop=4,2,8,6 zoom=3 mark=4,2,8,6")).unwrap();
    bumpsim(&["study", p]).expect_code(0, "render");
    for f in ["a", "r", "q"] {
        let img = image::open(dir.join(format!("pics/{f}.png"))).unwrap();
        assert_eq!((img.width(), img.height()), (24, 18), "{f}");
    }
    let page = std::fs::read_to_string(dir.join("p.md")).unwrap();
    assert!(page.ends_with("# P\n![](pics/a.png)\n"), "{page}");
    // with --reuse nothing is rendered
    std::fs::remove_file(dir.join("pics/a.png")).unwrap();
    bumpsim(&["study", p, "--reuse"]).expect_code(0, "reuse");
    assert!(!dir.join("pics/a.png").exists());
    std::fs::write(&src, render("crop=20,20,8,8")).unwrap();
    let o = bumpsim(&["study", p]);
    o.expect_code(2, "crop outside");
    assert!(o.stderr.contains("outside the 24x24 image"), "{}", o.stderr);
    assert!(!dir.join("pics/a.png").exists(), "nothing written");
    let o = bumpsim(&["study", s.join("docs/q.md").to_str().unwrap()]);
    o.expect_code(2, "not a source");
    assert!(o.stderr.contains("NAME.src.md"), "{}", o.stderr);
}

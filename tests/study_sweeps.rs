//! The studies' tables come from the sweep files of `docs/studies/sweeps/` (issue 11): each
//! sweep, run as `bumpsim sweep FILE --out DIR`, writes byte for byte the tables and rows
//! committed in its study directory, and the study page quotes every table verbatim.

mod common;

use common::*;

/// Each study sweep, the directory its page runs it into, and the page quoting it: the
/// `{{run sweeps/NAME.ron -> DIR}}` directives of the page sources (`docs/studies/*.src.md`,
/// docs/studies.md); [`DRAGON_SWEEPS`] must agree with them.
fn study_sweeps() -> Vec<(String, String, String)> {
    use bumpsim_pipeline::study::directive::{parse, Directive, Piece};
    let mut out: Vec<(String, String, String)> = Vec::new();
    let mut srcs: Vec<_> = std::fs::read_dir(root().join("docs/studies"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".src.md"))
        .collect();
    srcs.sort();
    for src in srcs {
        let page = src
            .file_name()
            .unwrap()
            .to_string_lossy()
            .replace(".src.md", ".md");
        let text = std::fs::read_to_string(&src).unwrap();
        for piece in parse(&text).unwrap_or_else(|e| panic!("{}: {e:?}", src.display())) {
            if let Piece::Directive(_, d) = piece {
                if let Directive::Run { file, out: dir } = *d {
                    let name = file
                        .strip_prefix("sweeps/")
                        .and_then(|f| f.strip_suffix(".ron"));
                    let name = name
                        .unwrap_or_else(|| panic!("{page}: run {file}: expected sweeps/NAME.ron"));
                    out.push((name.to_string(), dir, page.clone()));
                }
            }
        }
    }
    for (name, dir, page) in DRAGON_SWEEPS {
        match out.iter().find(|(n, _, _)| n == name) {
            Some((_, d, _)) => assert_eq!(d, dir, "{name}: the source and the list differ"),
            None => out.push((name.to_string(), dir.to_string(), page.to_string())),
        }
    }
    out
}

/// Whether a sweep bakes the Stanford dragon ([`DRAGON_SWEEPS`]).
fn dragon(name: &str) -> bool {
    DRAGON_SWEEPS.iter().any(|d| d.0 == name)
}

/// The sweeps that bake the Stanford dragon (871,306 faces): the mesh is not committed
/// (`tools/fetch-dragon.sh`, its licence) and their 78 points take about ten minutes in a
/// release build (hours in the suite's debug build), so the suite does not run them; `every_dragon_sweep_is_committed_and_quoted`
/// checks what it can without the mesh.
const DRAGON_SWEEPS: &[(&str, &str, &str)] = &[
    ("wang-views", "baking/views", "normal-map-baking.md"),
    ("wang-precision", "baking/precision", "normal-map-baking.md"),
    ("wang-faces", "baking/faces", "normal-map-baking.md"),
];

/// A dragon sweep parses, has the points its committed rows hold (each row's axis cells
/// those of the point of its index), and every table it writes is committed and quoted by
/// the page.
#[test]
fn every_dragon_sweep_is_committed_and_quoted() {
    use bumpsim_pipeline::sweep;
    let studies = root().join("docs/studies");
    for (name, dir, page) in study_sweeps().iter().filter(|s| dragon(&s.0)) {
        let s = sweep::load(&root().join(format!("docs/studies/sweeps/{name}.ron")))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let committed = studies.join(dir);
        let read = |f: &str| {
            std::fs::read_to_string(committed.join(f))
                .unwrap_or_else(|e| panic!("{name}: {f}: {e} (run the study)"))
        };
        let meta = json(&read("sweep.json"));
        let columns: Vec<String> = meta["columns"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_str().unwrap().to_string())
            .collect();
        let lines = read("sweep.jsonl");
        let rows: Vec<_> = lines
            .lines()
            .map(|l| {
                sweep::table::Row::from_json_line(l, &columns, s.file.axes.len())
                    .unwrap()
                    .unwrap_or_else(|| panic!("{name}: a row of other columns"))
            })
            .collect();
        assert_eq!(rows.len(), s.points.len(), "{name}: rows");
        for (row, p) in rows.iter().zip(&s.points) {
            assert_eq!(row.index, p.index, "{name}");
            assert_eq!(row.values, s.cells(p), "{name}: row {}", row.index);
        }
        let page = std::fs::read_to_string(studies.join(page)).unwrap();
        for t in &s.file.tables {
            let md = std::fs::read_to_string(committed.join(format!("{}.md", t.name)))
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(
                page.contains(md.trim_end()),
                "{name}: {}.md is not quoted",
                t.name
            );
        }
    }
}

#[test]
fn every_study_sweep_writes_the_committed_tables() {
    let studies = root().join("docs/studies");
    // every sweep file is listed here
    let mut files: Vec<String> = std::fs::read_dir(studies.join("sweeps"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    let mut listed: Vec<String> = study_sweeps()
        .iter()
        .map(|s| format!("{}.ron", s.0))
        .collect();
    listed.sort();
    assert_eq!(
        files, listed,
        "docs/studies/sweeps/ and the sweeps the pages run differ"
    );
    let s = Scratch::new("study-sweeps");
    for (name, dir, page) in study_sweeps().iter().filter(|s| !dragon(&s.0)) {
        // relative to the repository root (the tests' directory), as the study programs run
        // them: an error row's message names the configs by this path, not the checkout's
        let file = format!("docs/studies/sweeps/{name}.ron");
        let out = s.join(name);
        let o = bumpsim(&["sweep", &file, "--out", out.to_str().unwrap()]);
        // (a rejected point is an error row, compared with the committed one below)
        o.expect_code(0, name);
        let committed = studies.join(dir);
        let page = std::fs::read_to_string(studies.join(page)).unwrap();
        let mut tables = 0;
        for entry in std::fs::read_dir(&out).unwrap() {
            let path = entry.unwrap().path();
            let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
            if !["md", "csv"].contains(&ext) {
                continue;
            }
            let fresh = std::fs::read_to_string(&path).unwrap();
            let base = path.file_name().unwrap();
            let old = std::fs::read_to_string(committed.join(base)).unwrap_or_else(|e| {
                panic!(
                    "{}: {e} (regenerate the study)",
                    committed.join(base).display()
                )
            });
            assert!(
                fresh == old,
                "{name}: {base:?} differs from {dir}: regenerate the study"
            );
            if ext == "md" {
                tables += 1;
                assert!(
                    page.contains(fresh.trim_end()),
                    "{page:.0}{name}: {base:?} is not quoted"
                );
            }
        }
        assert!(tables > 0, "{name} writes no table");
    }
}

/// The perturbation sweeps copy the scene of `configs/visa-fold.ron` into a `scene=` set
/// (a sweep cannot take another config's scene): the copies must stay that scene (the prisms'
/// mesh apart, their axis).
#[test]
fn the_fold_sweeps_render_the_fold_configs_scene() {
    use bumpsim_pipeline::{config, sweep};
    let fold = config::load(&config("visa-fold"), &[])
        .unwrap()
        .config
        .scene;
    for name in [
        "perturb-fold",
        "perturb-finer",
        "perturb-shininess",
        "perturb-prisms",
    ] {
        let s = sweep::load(&root().join(format!("docs/studies/sweeps/{name}.ron"))).unwrap();
        for p in &s.points {
            let mut scene = config::load(&s.config_of(p), &s.file.sets)
                .unwrap_or_else(|e| panic!("{name}: {e}"))
                .config
                .scene;
            if name == "perturb-prisms" {
                scene.mesh = fold.mesh.clone();
            }
            assert_eq!(scene, fold, "{name}, point {}", p.index);
        }
    }
}

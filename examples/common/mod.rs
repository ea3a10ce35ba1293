//! What the study generators share: the repository root, a config's framebuffers in both
//! modes, and the sweeps of `docs/studies/sweeps/` run as `bumpsim sweep` runs them.

// each generator uses some of these
#![allow(dead_code)]

use bumpsim_hw::Mode;
use bumpsim_pipeline::config;
use bumpsim_pipeline::report::Gates;
use bumpsim_pipeline::rop::{self, Framebuffer};
use bumpsim_pipeline::run::{self, RunResult};
use bumpsim_pipeline::sweep::table::{Cell, Row};
use std::path::PathBuf;

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Bundled config `cfg` loaded with `--set` overrides `sets`.
pub fn load(cfg: &str, sets: &[String]) -> config::Loaded {
    let path = root().join("configs").join(format!("{cfg}.ron"));
    config::load(&path, sets).unwrap_or_else(|e| panic!("{cfg} {sets:?}: {e}"))
}

/// A full run of bundled config `cfg` with `--set` overrides `sets`.
pub fn go(cfg: &str, sets: &[String]) -> RunResult {
    run::run(&load(cfg, sets), None).unwrap_or_else(|e| panic!("{cfg} {sets:?}: {e}"))
}

/// The report's gate figures of bundled config `cfg` with `sets`, without rendering.
pub fn gates(cfg: &str, sets: &[String]) -> Gates {
    run::gates(&load(cfg, sets)).unwrap_or_else(|e| panic!("{cfg} {sets:?}: {e}"))
}

/// Map `f` over `items` on the machine's cores (results in item order).
pub fn par_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let n = std::thread::available_parallelism().map_or(1, |n| n.get());
    let next = std::sync::atomic::AtomicUsize::new(0);
    let out = std::sync::Mutex::new((0..items.len()).map(|_| None).collect::<Vec<_>>());
    std::thread::scope(|s| {
        for _ in 0..n {
            s.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                if i >= items.len() {
                    break;
                }
                let r = f(&items[i]);
                out.lock().unwrap()[i] = Some(r);
            });
        }
    });
    out.into_inner()
        .unwrap()
        .into_iter()
        .map(Option::unwrap)
        .collect()
}

/// Run every `(config, sets)` job on the machine's cores (results in job order).
pub fn go_all<S: AsRef<str> + Sync>(jobs: &[(S, Vec<String>)]) -> Vec<RunResult> {
    par_map(jobs, |(c, s)| go(c.as_ref(), s))
}

/// The framebuffers of bundled config `name` (with `--set` overrides `sets`) in bit-accurate
/// and exact mode, rendered without the reference.
pub fn framebuffers(name: &str, sets: &[String]) -> (Framebuffer, Framebuffer) {
    let path = root().join("configs").join(format!("{name}.ron"));
    let l = config::load(&path, sets).unwrap_or_else(|e| panic!("{name} {sets:?}: {e}"));
    let p = run::prepare(&l).unwrap_or_else(|e| panic!("{name}: {e}"));
    let (w, h) = (p.scene.width, p.scene.height);
    let bit = p.simulate_lanes(None);
    let exact = p.evaluate_exact();
    let frags = &p.raster.fragments;
    (
        rop::write(&p.engine.rop, Mode::BitAccurate, w, h, frags, &bit.outputs),
        rop::write(&p.engine.rop, Mode::Exact, w, h, frags, &exact),
    )
}

/// Run `docs/studies/sweeps/{name}.ron` into `docs/studies/{out}` exactly as `bumpsim sweep
/// FILE --out DIR` does (rows, plots, tables); the rows, and each table's Markdown by name.
/// Every point must succeed.
pub fn study_sweep(
    name: &str,
    out: &str,
) -> (
    bumpsim_pipeline::sweep::Table,
    std::collections::BTreeMap<String, String>,
) {
    let (t, md) = sweep_into(name, out);
    let bad: Vec<_> = t.rows.iter().filter(|r| !r.is_ok()).collect();
    assert!(bad.is_empty(), "{name}: points failed: {bad:?}");
    (t, md)
}

/// [`study_sweep`], error rows kept (a rejected config is a row).
fn sweep_into(
    name: &str,
    out: &str,
) -> (
    bumpsim_pipeline::sweep::Table,
    std::collections::BTreeMap<String, String>,
) {
    use bumpsim_pipeline::plot;
    use bumpsim_pipeline::sweep::{self, RunOptions};
    // relative to the repository root, so that a path in the rows (an error row's message)
    // does not name the checkout
    std::env::set_current_dir(root()).unwrap_or_else(|e| panic!("{e}"));
    let file = PathBuf::from(format!("docs/studies/sweeps/{name}.ron"));
    let s = sweep::load(&file).unwrap_or_else(|e| panic!("{e}"));
    let dir = PathBuf::from("docs/studies").join(out);
    sweep::run_into(&s, &dir, RunOptions::default(), false).unwrap_or_else(|e| panic!("{e}"));
    let table = s.read_table(&dir).unwrap_or_else(|e| panic!("{e}"));
    let csv = table.to_csv();
    plot::sweep_plots(&s.file.plots, &csv, &dir).unwrap_or_else(|e| panic!("{e}"));
    plot::table::sweep_tables(&s.file.tables, &csv, &dir).unwrap_or_else(|e| panic!("{e}"));
    let tables = s
        .file
        .tables
        .iter()
        .map(|t| {
            let md = std::fs::read_to_string(dir.join(format!("{}.md", t.name)))
                .unwrap_or_else(|e| panic!("{e}"));
            (t.name.clone(), md.trim_end().to_string())
        })
        .collect();
    (table, tables)
}

/// A study's sweep, run ([`study_sweep`]): its rows and tables, read by the prose.
pub struct Swept {
    /// The sweep file's stem under `docs/studies/sweeps/`.
    pub file: String,
    /// Its output directory under `docs/studies/`.
    pub out: String,
    pub t: bumpsim_pipeline::sweep::Table,
    pub md: std::collections::BTreeMap<String, String>,
}

impl Swept {
    /// Run `docs/studies/sweeps/{file}.ron` into `docs/studies/{out}/`; every point must
    /// succeed.
    pub fn run(file: &str, out: &str) -> Swept {
        let (t, md) = study_sweep(file, out);
        Swept {
            file: file.into(),
            out: out.into(),
            t,
            md,
        }
    }

    /// [`Swept::run`], error rows kept (a rejected config is a row: [`Swept::any_row`]).
    pub fn run_keeping_errors(file: &str, out: &str) -> Swept {
        let (t, md) = sweep_into(file, out);
        Swept {
            file: file.into(),
            out: out.into(),
            t,
            md,
        }
    }

    /// The first row, ok or not, that [`Swept::holds`] `conds`.
    pub fn any_row(&self, conds: &[(&str, &str)]) -> &Row {
        self.t
            .rows
            .iter()
            .find(|r| self.holds(r, conds))
            .unwrap_or_else(|| panic!("{}: no row {conds:?}", self.file))
    }

    /// The sweep file and the command that writes its tables, for the prose.
    pub fn cite(&self) -> String {
        let (f, o) = (&self.file, &self.out);
        format!(
            "`docs/studies/sweeps/{f}.ron` (`bumpsim sweep docs/studies/sweeps/{f}.ron --out \
             docs/studies/{o}`)"
        )
    }

    /// Table `name`, as the sweep wrote it.
    pub fn table(&self, name: &str) -> &str {
        self.md
            .get(name)
            .unwrap_or_else(|| panic!("{}: no table {name}", self.file))
    }

    /// The cell as the CSV writes it (text, numbers, booleans; empty for none).
    pub fn text(&self, r: &Row, c: &str) -> String {
        match self.t.cell(r, c) {
            Some(Cell::Text(s)) => s,
            Some(Cell::Int(i)) => i.to_string(),
            Some(Cell::Bool(b)) => b.to_string(),
            Some(Cell::Float(x)) => x.to_string(),
            _ => String::new(),
        }
    }

    /// The number in column `c` (NaN for none).
    pub fn n(&self, r: &Row, c: &str) -> f64 {
        self.t.number(r, c).unwrap_or(f64::NAN)
    }

    /// The ok rows.
    pub fn rows(&self) -> impl Iterator<Item = &Row> {
        self.t.rows.iter().filter(|r| r.is_ok())
    }

    /// Whether row `r`'s cells hold these texts: `v` exactly, or with a trailing `*` the
    /// text's start ("SphereCaps*"), with a leading `*` its end ("*`visa-teapot`").
    pub fn holds(&self, r: &Row, conds: &[(&str, &str)]) -> bool {
        conds.iter().all(|(c, v)| {
            let t = self.text(r, c);
            if let Some(p) = v.strip_suffix('*') {
                t.starts_with(p)
            } else if let Some(e) = v.strip_prefix('*') {
                t.ends_with(e)
            } else {
                t == *v
            }
        })
    }

    /// The first ok row that [`Swept::holds`] `conds`.
    pub fn row(&self, conds: &[(&str, &str)]) -> &Row {
        self.rows()
            .find(|r| self.holds(r, conds))
            .unwrap_or_else(|| panic!("{}: no row {conds:?}", self.file))
    }

    /// Column `c` of [`Swept::row`]`(conds)`.
    pub fn at(&self, conds: &[(&str, &str)], c: &str) -> f64 {
        self.n(self.row(conds), c)
    }
}

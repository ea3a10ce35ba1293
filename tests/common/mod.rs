//! Helpers shared by the end-to-end tests: run the `bumpsim` binary, scratch directories,
//! the bundled configs.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository root (the root package's manifest directory).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every bundled config `configs/*.ron`, sorted by file name.
pub fn configs() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("configs"))
        .expect("configs/ exists")
        .map(|e| e.expect("readable dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    v.sort();
    assert!(!v.is_empty(), "no configs found in configs/");
    v
}

/// The file stem of a config path (`sgi-teapot` for `configs/sgi-teapot.ron`).
pub fn stem(p: &Path) -> String {
    p.file_stem().unwrap().to_string_lossy().into_owned()
}

/// Path of a bundled config by stem.
pub fn config(stem: &str) -> PathBuf {
    root().join("configs").join(format!("{stem}.ron"))
}

/// What one run of the binary produced.
#[derive(Debug)]
pub struct Out {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

impl Out {
    /// Panic with the full output unless the exit code is `code`.
    pub fn expect_code(&self, code: i32, what: &str) -> &Self {
        assert_eq!(
            self.code, code,
            "{what}: expected exit code {code}, got {}\n--- stdout\n{}\n--- stderr\n{}",
            self.code, self.stdout, self.stderr
        );
        self
    }
}

/// Run `bumpsim` with `args` (and extra environment variables), from the repository root.
pub fn bumpsim_env<S: AsRef<std::ffi::OsStr>>(args: &[S], envs: &[(&str, &str)]) -> Out {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_bumpsim"));
    cmd.args(args).current_dir(root());
    for (k, v) in envs {
        cmd.env(k, v);
    }
    let o = cmd.output().expect("the bumpsim binary runs");
    Out {
        code: o.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
}

pub fn bumpsim<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Out {
    bumpsim_env(args, &[])
}

/// A scratch directory for one test, unique per test name and process; removed on drop.
pub struct Scratch {
    pub path: PathBuf,
}

impl Scratch {
    /// A fresh, empty directory.
    pub fn new(test: &str) -> Scratch {
        let path = std::env::temp_dir().join(format!("bumpsim-e2e-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).expect("create scratch dir");
        Scratch { path }
    }
    pub fn join(&self, p: &str) -> PathBuf {
        self.path.join(p)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.path);
    }
}

/// Sorted file names in a directory (hidden files included).
pub fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("read_dir {}: {e}", dir.display()))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Parse JSON text or panic with it.
pub fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap_or_else(|e| panic!("invalid JSON ({e}):\n{text}"))
}

/// The node at a dotted path of a JSON value, or panic naming the path.
pub fn at<'a>(v: &'a serde_json::Value, path: &str) -> &'a serde_json::Value {
    let mut node = v;
    for seg in path.split('.') {
        node = node
            .get(seg)
            .unwrap_or_else(|| panic!("report has no {path:?} (missing {seg:?})"));
    }
    node
}

pub fn num(v: &serde_json::Value, path: &str) -> f64 {
    at(v, path)
        .as_f64()
        .unwrap_or_else(|| panic!("{path} is not a number: {}", at(v, path)))
}

pub fn uint(v: &serde_json::Value, path: &str) -> u64 {
    at(v, path)
        .as_u64()
        .unwrap_or_else(|| panic!("{path} is not an unsigned integer: {}", at(v, path)))
}

/// Engine unit names of a config, in config order, read from its text (`name: "..."` inside
/// `units: [...]`).
pub fn engine_units(config_text: &str) -> Vec<String> {
    let start = config_text.find("units:").expect("config has units");
    let end = config_text[start..]
        .find("output:")
        .map_or(config_text.len(), |e| start + e);
    let body = &config_text[start..end];
    let mut names = Vec::new();
    let mut rest = body;
    while let Some(i) = rest.find("name: \"") {
        let s = &rest[i + 7..];
        let j = s.find('"').unwrap();
        names.push(s[..j].to_string());
        rest = &s[j..];
    }
    assert!(!names.is_empty(), "no unit names found");
    names
}

/// `bumpsim check cfg --set set` must exit 2 with every needle in its message; returns the
/// message.
pub fn expect_rejected(cfg: &Path, set: &str, needles: &[&str]) -> String {
    let args = [
        "check".to_string(),
        cfg.display().to_string(),
        "--set".into(),
        set.to_string(),
    ];
    let o = bumpsim(&args);
    o.expect_code(2, set);
    for n in needles {
        assert!(
            o.stderr.contains(n),
            "{} --set {set}: the message lacks {n:?}: {}",
            cfg.display(),
            o.stderr
        );
    }
    o.stderr.clone()
}

/// A bundled config run with `--set` overrides `sets` (through the library): images, report.
pub fn config_run(stem: &str, sets: &[&str]) -> bumpsim_pipeline::run::RunResult {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let l = bumpsim_pipeline::config::load(&config(stem), &sets)
        .unwrap_or_else(|e| panic!("{stem}: {e}"));
    bumpsim_pipeline::run::run(&l, None).unwrap_or_else(|e| panic!("{stem}: {e}"))
}

/// The report of [`config_run`].
pub fn config_report(stem: &str, sets: &[&str]) -> bumpsim_pipeline::report::Report {
    config_run(stem, sets).report
}

/// The error message of a bundled config that `sets` make invalid (loading or running).
pub fn config_error(stem: &str, sets: &[&str]) -> String {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    bumpsim_pipeline::config::load(&config(stem), &sets)
        .and_then(|l| bumpsim_pipeline::run::run(&l, None).map(|_| ()))
        .expect_err("the config is rejected")
        .to_string()
}

/// `--set` overrides for a 128 x 128 image (fast end-to-end runs).
pub const SMALL: [&str; 2] = ["scene.width=128", "scene.height=128"];

/// Whether the iverilog co-simulations are skipped explicitly (`BUMPSIM_SKIP_IVERILOG=1`);
/// otherwise a test that needs iverilog fails without it.
pub fn skip_iverilog() -> bool {
    std::env::var_os("BUMPSIM_SKIP_IVERILOG").is_some_and(|v| !v.is_empty() && v != "0")
}

/// `bumpsim rtl NAME --out DIR --cosim n` on a bundled config, into a scratch directory of its
/// own (`tag`: tests run in parallel) kept alive by the returned `Scratch`; `None` when
/// iverilog is skipped explicitly. The command must exit 0.
pub fn rtl_cosim(name: &str, n: &str, tag: &str) -> Option<(Scratch, PathBuf, Out)> {
    if skip_iverilog() {
        println!("rtl: skipped (BUMPSIM_SKIP_IVERILOG is set)");
        return None;
    }
    let s = Scratch::new(&format!("rtl-{tag}-{name}"));
    let out = s.join("rtl");
    let cfg = config(name);
    let o = bumpsim(&[
        "rtl",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--cosim",
        n,
    ]);
    o.expect_code(0, "rtl --cosim");
    Some((s, out, o))
}

/// A `--set` that gives the palette builder a power generator its Verilog does not build
/// (the interpolated table): a unit reported "not generated".
#[allow(dead_code)]
pub const LERP_POWER: &str =
    "engine.units.qnm.unit.datapath.power=TableLerp(index_bits: 8, value_bits: 12, frac_bits: 4)";

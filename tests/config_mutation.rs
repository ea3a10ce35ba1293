//! Mutated configs: every bundled config (`configs/*.ron`, `tests/fixtures/*.ron`) is mutated
//! token by token — tokens deleted, duplicated or replaced by another token of the file,
//! numbers set to extremes (0, -1, huge integers, 1e308, 1e400, NaN, inf, subnormals), unknown
//! keys inserted, the text cut short — and each mutant is loaded (parse + validation + the
//! budget estimate, `config::load_with`) and, when it loads and its estimate is not above the
//! original's, built as `bumpsim check` builds it (the scene and the engine; no rendering).
//! A few `--set` overrides with extreme values are applied to the bundled configs as well.
//!
//! Asserted for every mutant: no panic; an error names a field or a position; each load
//! within [`LOAD_LIMIT`] and each check within [`CHECK_LIMIT`] (debug build).
//!
//! The mutants are drawn from a fixed seed, so a run is repeatable. `BUMPSIM_MUTANTS=N` (per
//! config, default [`DEFAULT_MUTANTS`]) and `BUMPSIM_MUTATION_SEED=S` run more or other
//! mutants (`docs/fuzzing.md`). A failing mutant is written to the message whole, so that it
//! can become a test in `tests/bad_input.rs`.

mod common;

use bumpsim_pipeline::config::{self, limits, LoadOptions};
use common::*;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Mutants per config in the default run.
const DEFAULT_MUTANTS: usize = 40;
/// Longest accepted load of one mutant (parse, validation, estimate): a hang detector, far
/// above the measured maximum (79 ms on a loaded machine), so that a slow CI machine does not
/// make it flake.
const LOAD_LIMIT: Duration = Duration::from_secs(30);
/// Longest accepted check-level build of one mutant (scene + engine): a hang detector, far
/// above the measured maximum (12.5 s on a loaded machine).
const CHECK_LIMIT: Duration = Duration::from_secs(300);
/// Mutants per config built as by `check` in the default run (the builds bake textures and
/// cost much more than loads).
const DEFAULT_CHECKS: usize = 4;

/// splitmix64: a small deterministic generator (the suite has no RNG crate at the root).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Number,
    Ident,
    Str,
    Punct,
}

/// A token of RON text: byte range and kind (comments and white space are not tokens).
#[derive(Debug, Clone, Copy)]
struct Tok {
    start: usize,
    end: usize,
    kind: Kind,
}

fn tokens(text: &str) -> Vec<Tok> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let start = i;
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if b[i..].starts_with(b"//") {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if b[i..].starts_with(b"/*") {
            i += 2;
            while i < b.len() && !b[i..].starts_with(b"*/") {
                i += 1;
            }
            i = (i + 2).min(b.len());
            continue;
        }
        let kind = if c == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += if b[i] == b'\\' { 2 } else { 1 };
            }
            i = (i + 1).min(b.len());
            Kind::Str
        } else if c.is_ascii_digit() || (c == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            i += 1;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b"._+-".contains(&b[i])) {
                // a sign only right after an exponent
                if (b[i] == b'+' || b[i] == b'-') && !matches!(b[i - 1], b'e' | b'E') {
                    break;
                }
                i += 1;
            }
            Kind::Number
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            Kind::Ident
        } else {
            // one character (UTF-8 aware)
            i += text[i..].chars().next().map_or(1, char::len_utf8);
            Kind::Punct
        };
        out.push(Tok {
            start,
            end: i,
            kind,
        });
    }
    out
}

/// Extreme values for a number token.
const EXTREMES: &[&str] = &[
    "0",
    "-1",
    "1",
    "2",
    "-0.0",
    "0.5",
    "255",
    "256",
    "4096",
    "4097",
    "16384",
    "65535",
    "65536",
    "2147483647",
    "2147483648",
    "-2147483648",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "18446744073709551615",
    "18446744073709551616",
    "340282366920938463463374607431768211456",
    "1e12",
    "1e13",
    "1e38",
    "1e39",
    "1e154",
    "1e308",
    "-1e308",
    "1e400",
    "1e-320",
    "1e-400",
    "NaN",
    "inf",
    "-inf",
    "0x7fffffff",
    "1_000_000",
];

/// Junk to insert: unknown keys, brackets, stray characters.
const JUNK: &[&str] = &[
    "zzz: 1,",
    "unknown_key: \"x\",",
    "(",
    ")",
    "[",
    "]",
    ",",
    ":",
    "Some(",
    "None",
    "\"",
    "#",
    "\u{feff}",
    "\u{0}",
    "é",
    "r#\"raw\"#",
    "b\"bytes\"",
    "'c'",
    "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[",
];

/// One mutant of `text` with 1 to 3 edits, and a description of the edits.
fn mutate(text: &str, rng: &mut Rng) -> (String, String) {
    let mut s = text.to_string();
    let mut what = Vec::new();
    for _ in 0..1 + rng.below(3) {
        let toks = tokens(&s);
        if toks.is_empty() {
            break;
        }
        let t = *rng.pick(&toks);
        let numbers: Vec<&Tok> = toks.iter().filter(|t| t.kind == Kind::Number).collect();
        let (range, new) = match rng.below(10) {
            // delete
            0 => (t.start..t.end, String::new()),
            // duplicate
            1 => (t.start..t.end, format!("{0} {0}", &s[t.start..t.end])),
            // replace by another token of the file
            2 | 3 => {
                let o = rng.pick(&toks);
                (t.start..t.end, s[o.start..o.end].to_string())
            }
            // a number to an extreme (most edits: numbers are the most fields)
            4..=6 if !numbers.is_empty() => {
                let n = rng.pick(&numbers);
                (n.start..n.end, rng.pick(EXTREMES).to_string())
            }
            // an identifier to another identifier of the file
            7 if toks.iter().any(|t| t.kind == Kind::Ident) => {
                let ids: Vec<&Tok> = toks.iter().filter(|t| t.kind == Kind::Ident).collect();
                let a = rng.pick(&ids);
                let b = rng.pick(&ids);
                (a.start..a.end, s[b.start..b.end].to_string())
            }
            // cut the text short
            8 => (t.start..s.len(), String::new()),
            // insert junk (an unknown key after an opening parenthesis, or anywhere)
            _ => {
                let opens: Vec<&Tok> = toks.iter().filter(|t| &s[t.start..t.end] == "(").collect();
                let j = rng.pick(JUNK);
                let at = if j.ends_with(',') && !opens.is_empty() {
                    rng.pick(&opens).end
                } else {
                    t.start
                };
                (at..at, j.to_string())
            }
        };
        what.push(format!(
            "{:?} -> {new:?} at byte {}",
            &s[range.clone()],
            range.start
        ));
        s.replace_range(range, &new);
    }
    (s, what.join("; "))
}

/// What one mutant did.
#[derive(Debug, Default)]
struct Tally {
    mutants: usize,
    loaded: usize,
    rejected: usize,
    checked: usize,
    check_rejected: usize,
    skipped_check: usize,
    panics: Vec<String>,
    unnamed: Vec<String>,
    slow: Vec<String>,
    max_load: Duration,
    max_check: Duration,
}

impl Tally {
    fn add(&mut self, o: Tally) {
        self.mutants += o.mutants;
        self.loaded += o.loaded;
        self.rejected += o.rejected;
        self.checked += o.checked;
        self.check_rejected += o.check_rejected;
        self.skipped_check += o.skipped_check;
        self.panics.extend(o.panics);
        self.unnamed.extend(o.unnamed);
        self.slow.extend(o.slow);
        self.max_load = self.max_load.max(o.max_load);
        self.max_check = self.max_check.max(o.max_check);
    }
}

/// Whether an error names a field or a position: or, for the two errors that are about no
/// single field, the `--set` argument (its file is `--set`, its message quotes the argument)
/// or the estimate's largest term (the message names its fields).
fn names_something(e: &config::InputError) -> bool {
    !e.field.is_empty()
        || e.pos.is_some()
        || e.file == "--set"
        || e.message.contains("over the budget") && e.message.contains("the largest part is")
}

fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "(non-string panic)".into())
}

/// Load `path` with `sets` and, when it loads within `max_estimate` seconds of estimated
/// work, build its scene and engine; add the outcome to `t`. `what` describes the mutant.
fn try_mutant(
    t: &mut Tally,
    path: &Path,
    sets: &[String],
    max_estimate: f64,
    checks_left: &mut usize,
    what: &str,
) {
    t.mutants += 1;
    let start = Instant::now();
    let r = catch_unwind(AssertUnwindSafe(|| {
        config::load_with(path, sets, LoadOptions::default())
    }));
    let took = start.elapsed();
    t.max_load = t.max_load.max(took);
    if took > LOAD_LIMIT {
        t.slow.push(format!("load took {took:.1?}: {what}"));
    }
    let l = match r {
        Err(p) => {
            t.panics
                .push(format!("load panicked ({}): {what}", panic_text(&*p)));
            return;
        }
        Ok(Err(e)) => {
            t.rejected += 1;
            if !names_something(&e) {
                t.unnamed.push(format!("{e}: {what}"));
            }
            return;
        }
        Ok(Ok(l)) => l,
    };
    t.loaded += 1;
    if *checks_left == 0 || limits::estimate(&l.config).seconds() > max_estimate {
        t.skipped_check += 1;
        return;
    }
    *checks_left -= 1;
    let start = Instant::now();
    let r = catch_unwind(AssertUnwindSafe(|| {
        let scene = bumpsim_pipeline::run::build_scene(&l)?;
        bumpsim_pipeline::engine::build(&l, &scene).map(|_| ())
    }));
    let took = start.elapsed();
    t.max_check = t.max_check.max(took);
    if took > CHECK_LIMIT {
        t.slow.push(format!("check took {took:.1?}: {what}"));
    }
    match r {
        Err(p) => t
            .panics
            .push(format!("check panicked ({}): {what}", panic_text(&*p))),
        Ok(Err(e)) => {
            t.check_rejected += 1;
            if !names_something(&e) {
                t.unnamed.push(format!("{e}: {what}"));
            }
        }
        Ok(Ok(())) => t.checked += 1,
    }
}

/// `--set` overrides with extreme or malformed values on fields most configs have.
const SETS: &[&str] = &[
    "scene.width=0",
    "scene.width=4294967296",
    "scene.width=-1",
    "scene.height=1e400",
    "scene.width=\"wide\"",
    "raster.subpixel_bits=255",
    "raster.depth_bits=1e308",
    "sim.fifo_depth=18446744073709551616",
    "reference.samples=[[[[1]]]]",
    "scene.model.scale=0",
    "scene.model.scale=NaN",
    "scene.camera.near=-1",
    "scene.camera.far=1e308",
    "scene.lights[0].color=[2.0,0.0,0.0]",
    "scene.lights[0].color=[1e400,0.0,0.0]",
    "scene.lights=[]",
    "scene.lights[99].color=[0.0,0.0,0.0]",
    "scene.material.shininess=-5",
    "scene.mesh=None",
    "scene.bump=Flat",
    "engine.units=[]",
    "engine.attributes=[]",
    "engine.output=\"nope.color\"",
    "cost.full_adder=-1",
    "nonexistent.field=1",
    "scene..width=1",
    "=1",
    "scene.width",
    "scene.width==1",
    "scene.width=[",
    "scene.width={\"a\":1}",
];

fn sources() -> Vec<PathBuf> {
    let mut v = configs();
    let fixtures = root().join("tests/fixtures");
    if let Ok(d) = std::fs::read_dir(&fixtures) {
        let mut f: Vec<PathBuf> = d
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "ron"))
            .collect();
        f.sort();
        v.extend(f);
    }
    v
}

#[test]
fn mutated_configs_fail_cleanly() {
    let per_config: usize = env_or("BUMPSIM_MUTANTS", DEFAULT_MUTANTS);
    let checks: usize = env_or("BUMPSIM_MUTATION_CHECKS", DEFAULT_CHECKS);
    let seed: u64 = env_or("BUMPSIM_MUTATION_SEED", 0x6275_6d70);
    let scratch = Scratch::new("config-mutation");
    let start = Instant::now();
    let srcs = sources();
    let total = on_two_workers(
        &srcs,
        &scratch,
        Tally::add,
        |w, i, src, scratch, t: &mut Tally| {
            let text = std::fs::read_to_string(src).unwrap();
            let name = stem(src);
            let original = config::load(src, &[]).unwrap_or_else(|e| {
                panic!("the bundled config {} does not load: {e}", src.display())
            });
            // check-level work only for mutants that do not ask for more work
            // than the original (a mutant may legally ask for a 4096 bake)
            let max_estimate = limits::estimate(&original.config).seconds();
            let mut rng = Rng(seed ^ (i as u64).wrapping_mul(0x1000_0000_01b3));
            let path = scratch.join(format!("w{w}-{name}.ron"));
            let mut checks_left = checks;
            for k in 0..per_config {
                let (m, what) = mutate(&text, &mut rng);
                std::fs::write(&path, &m).unwrap();
                let what = format!("{name} mutant {k}: {what}");
                try_mutant(t, &path, &[], max_estimate, &mut checks_left, &what);
            }
            // overrides on the original
            std::fs::write(&path, &text).unwrap();
            for _ in 0..3 {
                let set = rng.pick(SETS).to_string();
                let what = format!("{name} --set {set}");
                try_mutant(t, &path, &[set], max_estimate, &mut checks_left, &what);
            }
        },
    );
    println!(
        "config_mutation: {} mutants of {} configs in {:.1?} (seed {seed}): {} rejected at \
         load, {} loaded ({} built as by check, {} rejected at check, {} not built: over the \
         number of checks or an estimate above the original's); {} panics, {} errors without a field or position, {} over the \
         time limits; slowest load {:.1?}, slowest check {:.1?}",
        total.mutants,
        srcs.len(),
        start.elapsed(),
        total.rejected,
        total.loaded,
        total.checked,
        total.check_rejected,
        total.skipped_check,
        total.panics.len(),
        total.unnamed.len(),
        total.slow.len(),
        total.max_load,
        total.max_check,
    );
    let bad: Vec<&String> = total
        .panics
        .iter()
        .chain(&total.unnamed)
        .chain(&total.slow)
        .collect();
    assert!(
        bad.is_empty(),
        "{} mutants failed:\n{}",
        bad.len(),
        bad.iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
}

#[test]
fn the_tokenizer_keeps_every_token_of_a_config() {
    let text = std::fs::read_to_string(config("sgi-teapot")).unwrap();
    let toks = tokens(&text);
    assert!(toks.len() > 50);
    // the tokens, re-joined, are the text without comments and white space
    let joined: String = toks.iter().map(|t| &text[t.start..t.end]).collect();
    assert!(joined.contains("scene:("), "{joined}");
    assert!(toks
        .iter()
        .any(|t| t.kind == Kind::Number && &text[t.start..t.end] == "256"));
}

/// How one run of the real CLI on a mutant ended.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Exit {
    Code(i32),
    /// killed by this signal (an abort is SIGABRT, 6; a stack overflow SIGSEGV, 11)
    Signal(i32),
    Timeout,
}

/// Run `bumpsim args` with the release binary this test was built with, its output to files
/// in `scratch`, killed after `limit`. Returns the exit and stderr.
fn run_cli(args: &[String], scratch: &Path, limit: Duration) -> (Exit, String) {
    let err_path = scratch.join("stderr");
    let err = std::fs::File::create(&err_path).unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_bumpsim"))
        .args(args)
        .current_dir(scratch)
        .env("RAYON_NUM_THREADS", "1")
        .stdout(std::process::Stdio::null())
        .stderr(err)
        .spawn()
        .expect("the bumpsim binary runs");
    let start = Instant::now();
    let exit = loop {
        if let Some(st) = child.try_wait().unwrap() {
            #[cfg(unix)]
            if let Some(sig) = std::os::unix::process::ExitStatusExt::signal(&st) {
                break Exit::Signal(sig);
            }
            break Exit::Code(st.code().unwrap_or(-1));
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break Exit::Timeout;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    (exit, std::fs::read_to_string(&err_path).unwrap_or_default())
}

/// Counts of the CLI run over the mutants.
#[derive(Debug, Default)]
struct CliTally {
    mutants: usize,
    checks: [usize; 3], // exit 0, exit 2, other exit codes
    renders: [usize; 3],
    signals: usize,
    timeouts: usize,
    failures: Vec<String>,
}

impl CliTally {
    /// Count one exit; anything but 0 or 2 with a message that names the file or `--set` is
    /// a failure (written out whole with the mutant).
    fn count(&mut self, render: bool, exit: Exit, stderr: &str, file: &str, what: &str) {
        let slot = if render {
            &mut self.renders
        } else {
            &mut self.checks
        };
        let bad = match exit {
            Exit::Code(0) => {
                slot[0] += 1;
                None
            }
            Exit::Code(2) => {
                slot[1] += 1;
                (!stderr.contains(file) && !stderr.contains("--set"))
                    .then(|| format!("exit 2 without the file's name ({})", stderr.trim()))
            }
            Exit::Code(c) => {
                slot[2] += 1;
                Some(format!("exit {c} ({})", stderr.trim()))
            }
            Exit::Signal(s) => {
                self.signals += 1;
                Some(format!("killed by signal {s} ({})", stderr.trim()))
            }
            Exit::Timeout => {
                self.timeouts += 1;
                Some("over the time limit".to_string())
            }
        };
        if let Some(b) = bad {
            let cmd = if render { "render" } else { "check" };
            self.failures.push(format!("{cmd}: {b}: {what}"));
        }
    }
    fn add(&mut self, o: CliTally) {
        self.mutants += o.mutants;
        for i in 0..3 {
            self.checks[i] += o.checks[i];
            self.renders[i] += o.renders[i];
        }
        self.signals += o.signals;
        self.timeouts += o.timeouts;
        self.failures.extend(o.failures);
    }
}

/// Run `each(worker, index, source, dir, tally)` for every source on two worker threads (a
/// shared counter hands the sources out), each worker with its own tally and its own
/// directory `scratch/w<worker>` (with the bundled configs' `assets/` linked in, which they
/// name relative to the config); the workers' tallies summed by `add`.
fn on_two_workers<T: Default + Send>(
    srcs: &[PathBuf],
    scratch: &Scratch,
    add: impl Fn(&mut T, T),
    each: impl Fn(usize, usize, &Path, &Path, &mut T) + Sync,
) -> T {
    let next = std::sync::atomic::AtomicUsize::new(0);
    std::thread::scope(|s| {
        let workers: Vec<_> = (0..2)
            .map(|w| {
                let (next, each) = (&next, &each);
                let dir = scratch.join(&format!("w{w}"));
                s.spawn(move || {
                    std::fs::create_dir_all(&dir).unwrap();
                    #[cfg(unix)]
                    std::os::unix::fs::symlink(root().join("configs/assets"), dir.join("assets"))
                        .unwrap();
                    let mut t = T::default();
                    loop {
                        let i = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                        let Some(src) = srcs.get(i) else { break };
                        each(w, i, src, &dir, &mut t);
                    }
                    t
                })
            })
            .collect();
        let mut total = T::default();
        for w in workers {
            add(&mut total, w.join().unwrap());
        }
        total
    })
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// The mutants through the real CLI, as a user meets them: `bumpsim check MUTANT` for every
/// mutant and `bumpsim render MUTANT --out DIR` for the first few of each config that check
/// and whose estimate is not above the original's. Exit codes, signals (aborts, stack
/// overflows) and time-outs are counted; anything but exit 0, or exit 2 naming the file, fails.
/// Not in the suite (a process per mutant): run against the release binary with
///
/// ```sh
/// BUMPSIM_MUTANTS=60 BUMPSIM_MUTATION_RENDERS=2 BUMPSIM_MUTATION_SEED=11 \
///     cargo test --release --test config_mutation -- --ignored --nocapture cli
/// ```
#[test]
#[ignore = "a process per mutant: run by hand against the release binary (docs/fuzzing.md)"]
fn cli_mutants_exit_0_or_2() {
    let per_config: usize = env_or("BUMPSIM_MUTANTS", 20);
    let renders: usize = env_or("BUMPSIM_MUTATION_RENDERS", 1);
    let seed: u64 = env_or("BUMPSIM_MUTATION_SEED", 0x6275_6d70);
    let limit = Duration::from_secs(env_or("BUMPSIM_MUTATION_TIMEOUT", 120));
    let scratch = Scratch::new("cli-mutation");
    let start = Instant::now();
    let srcs = sources();
    let total = on_two_workers(
        &srcs,
        &scratch,
        CliTally::add,
        |_, i, src, dir, t: &mut CliTally| {
            let text = std::fs::read_to_string(src).unwrap();
            let name = stem(src);
            let original = config::load(src, &[]).unwrap();
            let max_estimate = limits::estimate(&original.config).seconds();
            let mut rng = Rng(seed ^ (i as u64).wrapping_mul(0x1000_0000_01b3));
            let file = format!("m-{name}.ron");
            let path = dir.join(&file);
            let mut renders_left = renders;
            for k in 0..per_config + 3 {
                let (m, what, sets) = if k < per_config {
                    let (m, what) = mutate(&text, &mut rng);
                    (m, what, vec![])
                } else {
                    let set = rng.pick(SETS).to_string();
                    (text.clone(), format!("--set {set}"), vec![set])
                };
                std::fs::write(&path, &m).unwrap();
                let what = format!("{name} mutant {k}: {what}");
                t.mutants += 1;
                let mut args = vec!["check".to_string(), file.clone()];
                for s in &sets {
                    args.extend(["--set".to_string(), s.clone()]);
                }
                let (exit, err) = run_cli(&args, dir, limit);
                t.count(false, exit, &err, &file, &what);
                if exit != Exit::Code(0) || renders_left == 0 {
                    continue;
                }
                let small = config::load_with(&path, &sets, LoadOptions::default())
                    .is_ok_and(|l| limits::estimate(&l.config).seconds() <= max_estimate);
                if !small {
                    continue;
                }
                renders_left -= 1;
                let out = dir.join("out");
                let _ = std::fs::remove_dir_all(&out);
                args[0] = "render".into();
                args.extend(["--out".to_string(), "out".to_string()]);
                let (exit, err) = run_cli(&args, dir, limit);
                t.count(true, exit, &err, &file, &what);
                let _ = std::fs::remove_dir_all(&out);
            }
        },
    );
    println!(
        "cli_mutation: {} mutants of {} configs in {:.1?} (seed {seed}, {} s limit): check \
         exits 0/2/other {}/{}/{}, render exits 0/2/other {}/{}/{}, {} killed by a signal, {} \
         over the time limit",
        total.mutants,
        srcs.len(),
        start.elapsed(),
        limit.as_secs(),
        total.checks[0],
        total.checks[1],
        total.checks[2],
        total.renders[0],
        total.renders[1],
        total.renders[2],
        total.signals,
        total.timeouts,
    );
    assert!(
        total.failures.is_empty(),
        "{} mutants failed:\n{}",
        total.failures.len(),
        total.failures.join("\n")
    );
}

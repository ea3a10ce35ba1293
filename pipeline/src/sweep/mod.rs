//! `bumpsim sweep`: one base config, axes over `--set` paths, one report row per point.
//!
//! A sweep file (RON, `docs/sweep.md`) names the base config (relative to the sweep file),
//! fixed overrides applied to every point, the axes and how points are drawn from them:
//! the product of the axes' values (`Product`, the default; the last axis varies fastest), or
//! `Random(n, seed)` / `LatinHypercube(n, seed)` samples over the axes' ranges. Every point
//! is loaded and run on its own ([`crate::run::run`]), in parallel; rows come back in point
//! order, so the output does not depend on the thread count. A point whose config is
//! rejected (or whose run fails) gives a row with the error.

pub mod baseline;
pub mod journal;
pub mod resume;
pub mod share;
pub mod table;

use crate::config::{self, InputError, LoadOptions};
use rand_xoshiro::rand_core::{RngCore, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;
use serde::Deserialize;
use std::path::{Path, PathBuf};

pub use resume::{run_into, DirError, Outcome};
pub use table::{merge, Row, Table};

/// Most points one sweep may have.
pub const MAX_POINTS: usize = 1_000_000;

/// A sweep file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    /// The base config, relative to the sweep file.
    pub base: PathBuf,
    /// Overrides applied to every point before the axes' values (`path=value`).
    #[serde(default)]
    pub sets: Vec<String>,
    pub axes: Vec<Axis>,
    #[serde(default)]
    pub sampling: Sampling,
    /// Plots of the output written into the directory after the sweep (`docs/sweep.md`).
    #[serde(default)]
    pub plots: Vec<crate::plot::PlotSpec>,
    /// Overrides (after `sets`) of a baseline run: with any, every point's image is also
    /// compared with the baseline's (`baseline_*` columns, [`baseline`]); none (the
    /// default): no baseline.
    #[serde(default)]
    pub baseline: Vec<String>,
    /// Markdown tables of the output written into the directory after the sweep
    /// (`DIR/NAME.md`, [`crate::plot::table`]).
    #[serde(default)]
    pub tables: Vec<crate::plot::table::TableSpec>,
    /// More report fields as columns: each a dot path into the report's JSON (`bumpsim report
    /// --json`), e.g. `cycles.frame`, written as column `report.PATH` after the baseline's
    /// ([`report_cell`]).
    #[serde(default)]
    pub report: Vec<String>,
    /// Light kept on a class of pixels, as a share of the reference's light there: one
    /// `share.NAME` column each, after the report's ([`share`]).
    #[serde(default)]
    pub shares: Vec<share::Share>,
}

/// The path of an axis whose values are config files (relative to the sweep file): each
/// point runs its value's config instead of `base` (engines that differ in their units, not
/// in a field; `docs/sweep.md`).
pub const CONFIG_AXIS: &str = "@config";

/// The keys of report path `path`: dot-separated object keys and list indices, and a key
/// in brackets taken as written, dots included (`bandwidth.texture_memory[shader.tex0].bits`:
/// the texture `shader.tex0`). An unclosed or empty bracket, or an empty key, is an error.
pub fn report_keys(path: &str) -> Result<Vec<&str>, String> {
    let mut keys = Vec::new();
    let mut rest = path;
    // after a bracket a `.` or another bracket must follow
    let mut after_bracket = false;
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix('[') {
            let end = r
                .find(']')
                .ok_or_else(|| format!("{path:?}: a '[' without its ']'"))?;
            if end == 0 {
                return Err(format!("{path:?}: an empty key in brackets"));
            }
            keys.push(&r[..end]);
            rest = &r[end + 1..];
            after_bracket = true;
            continue;
        }
        if after_bracket {
            rest = rest
                .strip_prefix('.')
                .ok_or_else(|| format!("{path:?}: expected '.' or '[' after ']'"))?;
            after_bracket = false;
        } else if !keys.is_empty() {
            rest = rest
                .strip_prefix('.')
                .ok_or_else(|| format!("{path:?}: an empty key"))?;
        }
        let end = rest.find(['.', '[']).unwrap_or(rest.len());
        if end == 0 {
            return Err(format!("{path:?}: an empty key"));
        }
        keys.push(&rest[..end]);
        rest = &rest[end..];
    }
    if keys.is_empty() {
        return Err("an empty report path".into());
    }
    Ok(keys)
}

/// The cell of report field `path` ([`report_keys`]: object keys and list indices) in
/// `report`'s JSON: a number, text or boolean as it is, a list its length, anything else (an
/// object, null, a path the report does not have, a path that does not parse) empty.
pub fn report_cell(report: &serde_json::Value, path: &str) -> table::Cell {
    use table::Cell;
    let Ok(keys) = report_keys(path) else {
        return Cell::Empty;
    };
    let mut v = report;
    for key in keys {
        let next = match v {
            serde_json::Value::Object(m) => m.get(key),
            serde_json::Value::Array(a) => key.parse::<usize>().ok().and_then(|i| a.get(i)),
            _ => None,
        };
        match next {
            Some(n) => v = n,
            None => return Cell::Empty,
        }
    }
    match v {
        serde_json::Value::Bool(b) => Cell::Bool(*b),
        serde_json::Value::Number(n) => match n.as_i64() {
            Some(i) => Cell::Int(i),
            None => n.as_f64().map_or(Cell::Empty, Cell::Float),
        },
        serde_json::Value::String(t) => Cell::Text(t.clone()),
        serde_json::Value::Array(a) => Cell::Int(a.len() as i64),
        _ => Cell::Empty,
    }
}

/// One axis: a `--set` path and its values.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axis {
    /// Any `--set` path, e.g. `engine.units.spec.unit.index_bits`.
    pub path: String,
    /// Column name in the output (default: the path).
    #[serde(default)]
    pub name: String,
    pub values: Values,
    /// More `--set` paths that take the same value at every point (e.g. one flag of several
    /// attributes), set after `path`.
    #[serde(default)]
    pub also: Vec<String>,
    /// Labels of a `List`'s values, one per value: the axis' column holds the label instead
    /// of the value (e.g. `"2 lights"` for a list of lights). Empty (the default): the value.
    #[serde(default)]
    pub labels: Vec<String>,
    /// More `--set` paths that take their own value at the same position as the axis'
    /// value (a `List` axis only, its values distinct): a distance paired with the noise
    /// level it needs, where `also` sets one value and two axes would multiply.
    #[serde(default)]
    pub paired: Vec<Paired>,
}

/// A path whose values follow a `List` axis' value by position ([`Axis::paired`]).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Paired {
    /// Any `--set` path.
    pub path: String,
    /// One value per value of the axis.
    pub values: Vec<Scalar>,
}

impl Axis {
    /// The axis' column name.
    pub fn column(&self) -> String {
        if self.name.is_empty() {
            self.path.clone()
        } else {
            self.name.clone()
        }
    }

    /// The position of value `v` in the axis' `List` (the first, values with labels or
    /// pairs are distinct).
    fn position(&self, v: &Scalar) -> Option<usize> {
        match &self.values {
            Values::List(vals) => vals.iter().position(|x| x == v),
            Values::Grid(..) => None,
        }
    }

    /// The `path=value` overrides of value `v`: the axis' path and its `also` paths, then
    /// each paired path with its value at `v`'s position (on the config axis, whose value
    /// is a file, the paired paths only).
    fn sets(&self, v: &Scalar) -> Vec<String> {
        let text = v.to_ron();
        let mut sets: Vec<String> = std::iter::once(&self.path)
            .chain(&self.also)
            .filter(|_| self.path != CONFIG_AXIS)
            .map(|p| format!("{p}={text}"))
            .collect();
        if let Some(k) = self.position(v) {
            for p in &self.paired {
                if let Some(x) = p.values.get(k) {
                    sets.push(format!("{}={}", p.path, x.to_ron()));
                }
            }
        }
        sets
    }

    /// The axis' cell for value `v`: its label if it has labels, else the value.
    pub fn cell(&self, v: &Scalar) -> table::Cell {
        let label = self.position(v).and_then(|k| self.labels.get(k));
        label.map_or_else(|| table::Cell::of(v), |l| table::Cell::Text(l.clone()))
    }
}

/// An axis' values.
#[derive(Debug, Clone, Deserialize)]
pub enum Values {
    /// These values, in order.
    List(Vec<Scalar>),
    /// `steps` values evenly spaced from `from` to `to` (both included); integers when both
    /// ends are integers (rounded to nearest, repeats dropped), floats otherwise. As a
    /// sampled axis: the interval `[from, to]`.
    Grid(Scalar, Scalar, u32),
}

/// How the points are drawn.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
pub enum Sampling {
    /// Every combination of the axes' values; the last axis varies fastest.
    #[default]
    Product,
    /// `n` points, each axis drawn uniformly and independently (xoshiro256++ from `seed`).
    Random(u32, u64),
    /// `n` points of a Latin hypercube: each axis' range cut into `n` strata, one point in
    /// each, strata paired at random (xoshiro256++ from `seed`).
    LatinHypercube(u32, u64),
}

/// One value of an axis: what follows `path=` in a `--set`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum Scalar {
    Bool(bool),
    Int(i64),
    Float(f64),
    /// Passed to `--set` as written (RON: `"Nearest"` gives `filter=Nearest`).
    Text(String),
}

impl Scalar {
    /// The RON text of the value for `--set`.
    pub fn to_ron(&self) -> String {
        match self {
            Scalar::Bool(b) => b.to_string(),
            Scalar::Int(i) => i.to_string(),
            Scalar::Float(x) => format!("{x:?}"),
            Scalar::Text(s) => s.clone(),
        }
    }

    fn as_f64(&self) -> Option<f64> {
        match self {
            Scalar::Int(i) => Some(*i as f64),
            Scalar::Float(x) => Some(*x),
            _ => None,
        }
    }
}

/// One point of a sweep: its position in point order and a value per axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub index: usize,
    pub values: Vec<Scalar>,
}

/// A parsed sweep, ready to run.
#[derive(Debug, Clone)]
pub struct Sweep {
    pub file: SweepFile,
    /// The sweep file's path (for messages).
    pub path: PathBuf,
    /// The base config's path (resolved against the sweep file's directory).
    pub base: PathBuf,
    pub points: Vec<Point>,
    /// The base config's engine units (with the file's `sets`), in config order: one
    /// `gates.<unit>` column each. Empty if that config does not load (every point's error
    /// row says why).
    pub units: Vec<String>,
}

/// A shard: run the points whose index is `i` modulo `n` (0-based `i < n`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub i: usize,
    pub n: usize,
}

impl Shard {
    /// Parse `i/n`.
    pub fn parse(s: &str) -> Result<Shard, InputError> {
        let bad = || {
            InputError::new(
                "--shard",
                "",
                format!("{s:?}: expected i/n with 0 <= i < n, e.g. 0/4"),
            )
        };
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (i, n): (usize, usize) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if n == 0 || i >= n {
            return Err(bad());
        }
        Ok(Shard { i, n })
    }

    pub fn contains(&self, index: usize) -> bool {
        index % self.n == self.i
    }
}

/// Read and parse a sweep file and compute its points.
pub fn load(path: &Path) -> Result<Sweep, InputError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError::new(&name, "", format!("cannot read the sweep file: {e}")))?;
    let file: SweepFile = ron::from_str(&text).map_err(|e| {
        let mut err = InputError::new(&name, "", e.code.to_string());
        err.pos = Some((e.span.start.line, e.span.start.col));
        err
    })?;
    let points = points(&file).map_err(|(field, m)| InputError::new(&name, field, m))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let base = dir.join(&file.base);
    // the units of the base config and of every config of a config axis, in first-seen order
    let mut configs = vec![base.clone()];
    for a in file.axes.iter().filter(|a| a.path == CONFIG_AXIS) {
        if let Values::List(v) = &a.values {
            configs.extend(v.iter().map(|c| dir.join(c.to_ron())));
        }
    }
    let mut units: Vec<String> = Vec::new();
    for c in &configs {
        if let Ok(l) = config::load(c, &file.sets) {
            for u in &l.config.engine.units {
                if !units.contains(&u.name) {
                    units.push(u.name.clone());
                }
            }
        }
    }
    let sweep = Sweep {
        base,
        path: path.to_path_buf(),
        file,
        points,
        units,
    };
    sweep.check_columns()?;
    sweep.check_plots()?;
    share::check(&sweep.file.shares, &name)?;
    crate::plot::table::check_specs(&sweep.file.tables, &sweep.columns(), &name)?;
    Ok(sweep)
}

/// The values of a grid or list axis.
fn axis_values(a: &Values, field: &str) -> Result<Vec<Scalar>, (String, String)> {
    match a {
        Values::List(v) => {
            if v.is_empty() {
                return Err((field.into(), "List([]): expected at least one value".into()));
            }
            Ok(v.clone())
        }
        Values::Grid(from, to, steps) => {
            let (Some(f), Some(t)) = (from.as_f64(), to.as_f64()) else {
                return Err((
                    field.into(),
                    "Grid(from, to, steps): expected numbers from and to".into(),
                ));
            };
            if !f.is_finite() || !t.is_finite() {
                return Err((field.into(), "Grid: expected finite ends".into()));
            }
            if *steps == 0 || *steps as usize > MAX_POINTS {
                return Err((
                    field.into(),
                    format!("Grid(.., {steps}): expected 1 to {MAX_POINTS} steps"),
                ));
            }
            let at = |k: u32| {
                if *steps == 1 {
                    f
                } else {
                    f + (t - f) * k as f64 / (*steps - 1) as f64
                }
            };
            let ints = matches!((from, to), (Scalar::Int(_), Scalar::Int(_)));
            let mut out: Vec<Scalar> = Vec::new();
            for k in 0..*steps {
                let v = if ints {
                    Scalar::Int(at(k).round() as i64)
                } else {
                    Scalar::Float(at(k))
                };
                if out.last() != Some(&v) {
                    out.push(v);
                }
            }
            Ok(out)
        }
    }
}

/// A uniform `f64` in [0, 1) from 53 random bits.
fn uniform(rng: &mut Xoshiro256PlusPlus) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The value of a sampled axis at `u` in [0, 1): a list's element `floor(u * len)`, a
/// grid's `from + u (to - from)` (integers: `from + floor(u (to - from + 1))`).
fn sample_value(a: &Values, u: f64) -> Scalar {
    match a {
        Values::List(v) => v[((u * v.len() as f64) as usize).min(v.len() - 1)].clone(),
        Values::Grid(from, to, _) => match (from, to) {
            (Scalar::Int(f), Scalar::Int(t)) => {
                let (lo, hi) = ((*f).min(*t), (*f).max(*t));
                let span = (hi - lo + 1) as f64;
                Scalar::Int((lo + (u * span) as i64).min(hi))
            }
            _ => {
                let (f, t) = (from.as_f64().unwrap(), to.as_f64().unwrap());
                Scalar::Float(f + u * (t - f))
            }
        },
    }
}

/// The points of a sweep file, in point order.
pub fn points(file: &SweepFile) -> Result<Vec<Point>, (String, String)> {
    if file.axes.is_empty() {
        return Err(("axes".into(), "expected at least one axis".into()));
    }
    for (k, p) in file.report.iter().enumerate() {
        report_keys(p).map_err(|e| {
            (
                format!("report[{k}]"),
                format!("{e}: expected a report path (docs/sweep.md)"),
            )
        })?;
    }
    let mut per_axis = Vec::new();
    for (k, a) in file.axes.iter().enumerate() {
        if a.path.trim().is_empty() {
            return Err((format!("axes[{k}].path"), "expected a --set path".into()));
        }
        if a.also.iter().any(|p| p.trim().is_empty()) {
            return Err((format!("axes[{k}].also"), "expected --set paths".into()));
        }
        if !a.labels.is_empty() {
            let n = match &a.values {
                Values::List(v) => v.len(),
                Values::Grid(..) => 0,
            };
            if n != a.labels.len() {
                return Err((
                    format!("axes[{k}].labels"),
                    format!(
                        "{} labels: expected one per value of a List ({n} values)",
                        a.labels.len()
                    ),
                ));
            }
        }
        if !a.paired.is_empty() {
            let vals = match &a.values {
                Values::List(v) => v.as_slice(),
                Values::Grid(..) => &[],
            };
            if vals.is_empty() {
                return Err((
                    format!("axes[{k}].paired"),
                    "expected a List axis (paired values follow its values by position)".into(),
                ));
            }
            if (1..vals.len()).any(|i| vals[..i].contains(&vals[i])) {
                return Err((
                    format!("axes[{k}].values"),
                    "a repeated value: expected distinct values on an axis with paired paths"
                        .into(),
                ));
            }
            for (j, p) in a.paired.iter().enumerate() {
                if p.path.trim().is_empty() {
                    return Err((
                        format!("axes[{k}].paired[{j}].path"),
                        "expected a --set path".into(),
                    ));
                }
                if p.values.len() != vals.len() {
                    return Err((
                        format!("axes[{k}].paired[{j}].values"),
                        format!(
                            "{} values: expected one per value of the axis ({})",
                            p.values.len(),
                            vals.len()
                        ),
                    ));
                }
            }
        }
        if a.path == CONFIG_AXIS {
            if file.axes[..k].iter().any(|b| b.path == CONFIG_AXIS) {
                return Err((
                    format!("axes[{k}].path"),
                    format!("a second {CONFIG_AXIS} axis: expected at most one"),
                ));
            }
            if !a.also.is_empty() {
                return Err((
                    format!("axes[{k}].also"),
                    format!("expected none on the {CONFIG_AXIS} axis (its values are files)"),
                ));
            }
            let files = match &a.values {
                Values::List(v) => v
                    .iter()
                    .all(|x| matches!(x, Scalar::Text(t) if !t.trim().is_empty())),
                Values::Grid(..) => false,
            };
            if !files {
                return Err((
                    format!("axes[{k}].values"),
                    "expected List([\"config.ron\", ...]): config files, relative to the sweep \
                     file"
                        .into(),
                ));
            }
        }
        per_axis.push(axis_values(&a.values, &format!("axes[{k}].values"))?);
    }
    let points: Vec<Vec<Scalar>> = match file.sampling {
        Sampling::Product => {
            let mut n: usize = 1;
            for v in &per_axis {
                n = n.saturating_mul(v.len());
            }
            if n > MAX_POINTS {
                return Err((
                    "axes".into(),
                    format!("{n} points: a sweep has at most {MAX_POINTS}"),
                ));
            }
            (0..n)
                .map(|mut i| {
                    let mut vals = vec![Scalar::Int(0); per_axis.len()];
                    for (k, v) in per_axis.iter().enumerate().rev() {
                        vals[k] = v[i % v.len()].clone();
                        i /= v.len();
                    }
                    vals
                })
                .collect()
        }
        Sampling::Random(n, seed) | Sampling::LatinHypercube(n, seed) => {
            let n = n as usize;
            if n == 0 || n > MAX_POINTS {
                return Err((
                    "sampling".into(),
                    format!("{n} samples: expected 1 to {MAX_POINTS}"),
                ));
            }
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            let d = file.axes.len();
            // u[point][axis]
            let mut u = vec![vec![0.0; d]; n];
            if let Sampling::Random(..) = file.sampling {
                for row in u.iter_mut() {
                    for x in row.iter_mut() {
                        *x = uniform(&mut rng);
                    }
                }
            } else {
                for k in 0..d {
                    // Fisher-Yates permutation of the strata, then a jitter in each
                    let mut perm: Vec<usize> = (0..n).collect();
                    for i in (1..n).rev() {
                        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
                        perm.swap(i, j);
                    }
                    for (i, row) in u.iter_mut().enumerate() {
                        row[k] = (perm[i] as f64 + uniform(&mut rng)) / n as f64;
                    }
                }
            }
            u.iter()
                .map(|row| {
                    file.axes
                        .iter()
                        .zip(row)
                        .map(|(a, &x)| sample_value(&a.values, x))
                        .collect()
                })
                .collect()
        }
    };
    Ok(points
        .into_iter()
        .enumerate()
        .map(|(index, values)| Point { index, values })
        .collect())
}

/// How to run a sweep.
#[derive(Debug, Clone, Copy, Default)]
pub struct RunOptions {
    pub shard: Option<Shard>,
    /// Passed to every point's load (`--force`).
    pub force: bool,
    /// Worker threads (default: rayon's, `RAYON_NUM_THREADS` or one per core).
    pub threads: Option<usize>,
}

impl Sweep {
    /// The `--set` list of a point: the file's fixed overrides, then one per axis.
    pub fn sets(&self, p: &Point) -> Vec<String> {
        let mut sets = self.file.sets.clone();
        for (a, v) in self.file.axes.iter().zip(&p.values) {
            sets.extend(a.sets(v));
        }
        sets
    }

    /// The config point `p` runs: its value of the config axis (relative to the sweep
    /// file), or the base config.
    pub fn config_of(&self, p: &Point) -> PathBuf {
        let dir = self.path.parent().unwrap_or(Path::new("."));
        self.file
            .axes
            .iter()
            .zip(&p.values)
            .find(|(a, _)| a.path == CONFIG_AXIS)
            .map_or_else(|| self.base.clone(), |(_, v)| dir.join(v.to_ron()))
    }

    /// Point `p`'s axis cells (each value, or its label).
    pub fn cells(&self, p: &Point) -> Vec<table::Cell> {
        self.file
            .axes
            .iter()
            .zip(&p.values)
            .map(|(a, v)| a.cell(v))
            .collect()
    }

    /// Whether merged rows (`csv_text`, a merged `sweep.csv`) are this sweep's: its columns,
    /// one row per point, and each row's axis cells those of its point. The message names
    /// the first difference.
    pub fn check_merged(&self, csv_text: &str) -> Result<(), String> {
        let csv = crate::plot::csv::Csv::parse(csv_text)
            .map_err(|(l, m)| format!("the merged sweep.csv, line {l}: {m}"))?;
        let columns = self.columns();
        if csv.header != columns {
            return Err(format!(
                "the shards' columns are not this sweep file's: {} against {}",
                csv.header.join(","),
                columns.join(",")
            ));
        }
        if csv.rows.len() != self.points.len() {
            return Err(format!(
                "the shards hold a sweep of {} points, this sweep file has {}",
                csv.rows.len(),
                self.points.len()
            ));
        }
        for (row, p) in csv.rows.iter().zip(&self.points) {
            for (j, c) in self.cells(p).iter().enumerate() {
                let want = crate::plot::csv::Csv::parse(&format!("x\n{}\n", c.csv()))
                    .ok()
                    .and_then(|t| t.rows.into_iter().next())
                    .and_then(|r| r.into_iter().next())
                    .unwrap_or_default();
                if row.get(1 + j) != Some(&want) {
                    return Err(format!(
                        "point {}: the shards' {} is {:?}, this sweep file's {want:?}",
                        p.index,
                        columns[1 + j],
                        row.get(1 + j).map_or("", |s| s.as_str())
                    ));
                }
            }
        }
        Ok(())
    }

    /// The `--set` list of point `p`'s baseline, if the file has one: the point's sets,
    /// then the baseline's overrides.
    pub fn baseline_sets(&self, p: &Point) -> Option<Vec<String>> {
        let b = &self.file.baseline;
        (!b.is_empty()).then(|| self.sets(p).into_iter().chain(b.iter().cloned()).collect())
    }

    /// Run one point: its row (with the error of a rejected config or a failed run), its
    /// image compared with its baseline's if the sweep has one (`base`: the rendered
    /// baseline, or why it did not run, which makes the point's row an error).
    pub fn run_point(
        &self,
        p: &Point,
        force: bool,
        base: Option<Result<&baseline::Baseline, &str>>,
    ) -> Row {
        let sets = self.sets(p);
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let base = base.transpose().map_err(|e| {
                InputError::new(self.path.display().to_string(), "baseline", e.to_string())
            })?;
            let config = self.config_of(p);
            let l = config::load_with(&config, &sets, LoadOptions { force })?;
            // every frame of a config with `frames`, as `bumpsim report` runs it: the row is
            // frame 0's report with its `animation` section
            let r = crate::animation::run(&l)?.first;
            let mut extra = base.map(|b| b.cells(&r)).unwrap_or_default();
            if !self.file.report.is_empty() {
                let json = serde_json::to_value(&r.report).unwrap_or_default();
                extra.extend(self.file.report.iter().map(|p| report_cell(&json, p)));
            }
            extra.extend(share::cells(&self.file.shares, &config, &sets, force, &r)?);
            Ok::<_, InputError>(Row::ok(
                p.index,
                self.cells(p),
                &r.report,
                extra,
                &self.units,
            ))
        }));
        let after = self.extra_columns().len() + self.units.len();
        let error = |m: &str| Row::error(p.index, self.cells(p), m, after);
        match outcome {
            Ok(Ok(row)) => row,
            Ok(Err(e)) => error(&e.to_string()),
            Err(_) => error("internal error: the run panicked (a bug)"),
        }
    }

    /// The columns after the report columns: the baseline's, if the file has one, then
    /// `report.PATH` per field of the file's `report`.
    fn extra_columns(&self) -> Vec<String> {
        let mut c = match self.file.baseline.is_empty() {
            false => baseline::columns(),
            true => Vec::new(),
        };
        c.extend(self.file.report.iter().map(|p| format!("report.{p}")));
        c.extend(self.file.shares.iter().map(|s| format!("share.{}", s.name)));
        c
    }

    /// No two columns share a name: an axis named as another axis or as a column the sweep
    /// writes anyway (`index`, `cycles`, ...) would write a header twice and JSON lines
    /// with one key overwritten.
    fn check_columns(&self) -> Result<(), InputError> {
        let columns = self.columns();
        for (k, a) in self.file.axes.iter().enumerate() {
            let c = a.column();
            if columns.iter().filter(|x| **x == c).count() > 1 {
                let field = if a.name.is_empty() { "path" } else { "name" };
                return Err(InputError::new(
                    self.path.display().to_string(),
                    format!("axes[{k}].{field}"),
                    format!(
                        "{c:?}: another column of the output has this name; expected a name \
                         that is not index, another axis' or a report column's ({})",
                        columns.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The plots name columns of the output and objectives with a direction.
    fn check_plots(&self) -> Result<(), InputError> {
        let name = self.path.display().to_string();
        let columns = self.columns();
        let known = |k: usize, field: &str, c: &str| {
            if columns.iter().any(|x| x == c) {
                Ok(())
            } else {
                Err(InputError::new(
                    &name,
                    format!("plots[{k}].{field}"),
                    format!(
                        "{c:?}: no such column: expected index, an axis' name or a report \
                         column ({})",
                        columns.join(", ")
                    ),
                ))
            }
        };
        for (k, p) in self.file.plots.iter().enumerate() {
            known(k, "x", &p.x)?;
            known(k, "y", &p.y)?;
            for (scale, field) in [(p.x_scale, "x_scale"), (p.y_scale, "y_scale")] {
                scale
                    .check()
                    .map_err(|m| InputError::new(&name, format!("plots[{k}].{field}.range"), m))?;
            }
            let objectives = p
                .objectives()
                .map_err(|e| InputError::new(&name, format!("plots[{k}].pareto"), e))?;
            for o in objectives {
                known(k, "pareto", &o.column)?;
            }
        }
        Ok(())
    }

    /// The output's column names (`index`, the axes, the report columns).
    pub fn columns(&self) -> Vec<String> {
        self.table(Vec::new()).columns()
    }

    fn table(&self, rows: Vec<Row>) -> Table {
        Table {
            axes: self.file.axes.iter().map(Axis::column).collect(),
            extra: self.extra_columns(),
            units: self.units.clone(),
            points: self.points.len(),
            rows,
        }
    }

    /// Whether `opts` runs point `index` (its shard holds it).
    pub fn in_shard(&self, opts: &RunOptions, index: usize) -> bool {
        opts.shard.is_none_or(|s| s.contains(index))
    }

    /// Run `f` on `opts.threads` worker threads (default: rayon's pool).
    pub fn on_pool<T: Send>(
        &self,
        opts: &RunOptions,
        f: impl FnOnce() -> T + Send,
    ) -> Result<T, String> {
        match opts.threads {
            None => Ok(f()),
            Some(t) => Ok(rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .map_err(|e| e.to_string())?
                .install(f)),
        }
    }

    /// Run the sweep's points (those of `opts.shard`), in parallel; rows in point order.
    pub fn run(&self, opts: RunOptions) -> Result<Table, DirError> {
        self.run_with(opts, Vec::new(), None).map(|(t, _)| t)
    }

    /// [`Sweep::run`] past the rows `done` (of points of the shard, kept from an earlier
    /// run), appending each new row to `journal` as it finishes. The table holds both, in
    /// point order; the second value is the first journal write that failed (the sweep
    /// goes on without the journal). A sweep with a baseline renders the baselines of the
    /// points to run first, each distinct baseline config once
    /// ([`baseline::Baselines`]).
    pub fn run_with(
        &self,
        opts: RunOptions,
        done: Vec<Row>,
        journal: Option<&journal::Journal>,
    ) -> Result<(Table, Option<String>), DirError> {
        let mut rows = Vec::new();
        let failed = self.run_streamed(opts, done, journal, &mut |r| {
            rows.push(r);
            Ok(())
        })?;
        Ok((self.table(rows), failed))
    }

    /// [`Sweep::run_with`], each row handed to `emit` in point order instead of kept: the
    /// points run [`CHUNK`] at a time (in parallel within a chunk, chunks in point order),
    /// so the memory the rows take is that of one chunk, whatever the number of points.
    /// An `emit` error ends the sweep (an internal error naming it).
    pub fn run_streamed(
        &self,
        opts: RunOptions,
        done: Vec<Row>,
        journal: Option<&journal::Journal>,
        emit: &mut dyn FnMut(Row) -> Result<(), String>,
    ) -> Result<Option<String>, DirError> {
        let have: std::collections::HashSet<usize> = done.iter().map(|r| r.index).collect();
        let todo: Vec<&Point> = self
            .points
            .iter()
            .filter(|p| self.in_shard(&opts, p.index) && !have.contains(&p.index))
            .collect();
        let columns = self.columns();
        let bases = self
            .on_pool(&opts, || {
                baseline::Baselines::render(self, &todo, opts.force)
            })
            .map_err(DirError::Internal)?;
        let failed = std::sync::Mutex::new(None::<String>);
        let progress = crate::progress::bar(todo.len() as u64, "sweep");
        let mut done = done;
        done.sort_by_key(|r| r.index);
        let mut done = done.into_iter().peekable();
        for chunk in todo.chunks(CHUNK) {
            let work = || -> Vec<Row> {
                chunk
                    .par_iter()
                    .map(|p| {
                        let row = self.run_point(p, opts.force, bases.of(p.index));
                        if let Some(j) = journal {
                            if let Err(e) = j.append(&row.json_line(&columns)) {
                                let mut f = failed.lock().unwrap_or_else(|e| e.into_inner());
                                f.get_or_insert_with(|| format!("{}: {e}", j.path().display()));
                            }
                        }
                        progress.inc(1);
                        row
                    })
                    .collect()
            };
            // rows in point order: the points are, and the kept rows go in between
            for row in self.on_pool(&opts, work).map_err(DirError::Internal)? {
                while let Some(d) = done.next_if(|d| d.index < row.index) {
                    emit(d).map_err(DirError::Internal)?;
                }
                emit(row).map_err(DirError::Internal)?;
            }
        }
        for d in done {
            emit(d).map_err(DirError::Internal)?;
        }
        Ok(failed.into_inner().unwrap_or_else(|e| e.into_inner()))
    }

    /// The rows a run wrote into `dir` (its `sweep.jsonl`), as a table.
    pub fn read_table(&self, dir: &Path) -> Result<Table, InputError> {
        let rows = journal::read(
            &dir.join("sweep.jsonl"),
            &self.columns(),
            self.file.axes.len(),
            false,
        )?
        .into_iter()
        .filter_map(|e| e.row)
        .collect();
        Ok(self.table(rows))
    }
}

/// Points run together in [`Sweep::run_streamed`] (their rows are held until the chunk ends).
pub const CHUNK: usize = 256;

#[cfg(test)]
mod tests {
    use super::*;

    fn file(text: &str) -> SweepFile {
        ron::from_str(text).unwrap()
    }

    fn vals(f: &SweepFile) -> Vec<Vec<String>> {
        points(f)
            .unwrap()
            .iter()
            .map(|p| p.values.iter().map(Scalar::to_ron).collect())
            .collect()
    }

    #[test]
    fn grids_and_lists_form_a_product_last_axis_fastest() {
        let f = file(
            r#"(base: "x.ron", axes: [
                (path: "a", values: Grid(4, 6, 3)),
                (path: "b", values: List([0.5, "Nearest", true])),
            ])"#,
        );
        let v = vals(&f);
        assert_eq!(v.len(), 9);
        assert_eq!(v[0], ["4", "0.5"]);
        assert_eq!(v[1], ["4", "Nearest"]);
        assert_eq!(v[2], ["4", "true"]);
        assert_eq!(v[8], ["6", "true"]);
        let g = file(r#"(base: "x", axes: [(path: "a", values: Grid(0.0, 1.0, 5))])"#);
        assert_eq!(vals(&g), [["0.0"], ["0.25"], ["0.5"], ["0.75"], ["1.0"]]);
        // integer grids round and drop repeats
        let g = file(r#"(base: "x", axes: [(path: "a", values: Grid(1, 3, 5))])"#);
        assert_eq!(vals(&g), [["1"], ["2"], ["3"]]);
    }

    #[test]
    fn samples_are_seeded_and_latin_hypercube_strata_are_filled_once() {
        let text = |s: &str| {
            format!(
                r#"(base: "x", sampling: {s}, axes: [
                    (path: "a", values: Grid(0.0, 1.0, 2)),
                    (path: "b", values: Grid(0, 9, 2)),
                ])"#
            )
        };
        let a = vals(&file(&text("Random(20, 7)")));
        assert_eq!(a, vals(&file(&text("Random(20, 7)"))));
        assert_ne!(a, vals(&file(&text("Random(20, 8)"))));
        assert_eq!(a.len(), 20);
        let l = points(&file(&text("LatinHypercube(10, 3)"))).unwrap();
        let mut strata: Vec<usize> = l
            .iter()
            .map(|p| match p.values[0] {
                Scalar::Float(x) => (x * 10.0) as usize,
                _ => panic!(),
            })
            .collect();
        strata.sort();
        assert_eq!(strata, (0..10).collect::<Vec<_>>());
        // integer axis 0..=9 with 10 strata: every integer once
        let mut ints: Vec<i64> = l
            .iter()
            .map(|p| match p.values[1] {
                Scalar::Int(i) => i,
                _ => panic!(),
            })
            .collect();
        ints.sort();
        assert_eq!(ints, (0..10).collect::<Vec<_>>());
    }

    /// The sweep of file `f` (base `x`, no units), its points drawn.
    fn sweep_of(f: SweepFile) -> Sweep {
        Sweep {
            points: points(&f).unwrap(),
            file: f,
            path: "s.ron".into(),
            base: "x".into(),
            units: Vec::new(),
        }
    }

    #[test]
    fn paired_paths_follow_the_axis_value_by_position() {
        let f = file(
            r#"(base: "x", axes: [
            (path: "d", values: List([3.2, 6.4]), labels: ["near", "far"],
             paired: [(path: "lvl", values: [0, 1]), (path: "e", values: ["(0, 2)", "(0, 4)"])]),
            (path: "@config", values: List(["a.ron", "b.ron"]), paired: [(path: "z", values: [7, 8])]),
        ])"#,
        );
        let s = sweep_of(f);
        assert_eq!(s.points.len(), 4);
        assert_eq!(s.sets(&s.points[0]), ["d=3.2", "lvl=0", "e=(0, 2)", "z=7"]);
        assert_eq!(s.sets(&s.points[3]), ["d=6.4", "lvl=1", "e=(0, 4)", "z=8"]);
        assert_eq!(s.cells(&s.points[3])[0], table::Cell::Text("far".into()));
        let bad =
            |axis: &str| points(&file(&format!(r#"(base: "x", axes: [{axis}])"#))).unwrap_err();
        let e = bad(r#"(path: "d", values: List([1, 2]), paired: [(path: "l", values: [0])])"#);
        assert_eq!(e.0, "axes[0].paired[0].values");
        assert!(
            e.1.contains("1 values: expected one per value of the axis (2)"),
            "{}",
            e.1
        );
        let e = bad(r#"(path: "d", values: Grid(1, 2, 2), paired: [(path: "l", values: [0, 1])])"#);
        assert_eq!(e.0, "axes[0].paired");
        let e = bad(r#"(path: "d", values: List([1, 1]), paired: [(path: "l", values: [0, 1])])"#);
        assert_eq!(e.0, "axes[0].values");
        let e = bad(r#"(path: "d", values: List([1]), paired: [(path: " ", values: [0])])"#);
        assert_eq!(e.0, "axes[0].paired[0].path");
    }

    #[test]
    fn report_paths_take_bracketed_keys_with_dots() {
        assert_eq!(report_keys("a.b.0").unwrap(), ["a", "b", "0"]);
        assert_eq!(
            report_keys("bandwidth.texture_memory[shader.tex0].stored_bits").unwrap(),
            ["bandwidth", "texture_memory", "shader.tex0", "stored_bits"]
        );
        assert_eq!(report_keys("[x.y][2]").unwrap(), ["x.y", "2"]);
        for bad in ["", "a..b", ".a", "a.", "a[b", "a[]", "a[b]c"] {
            assert!(report_keys(bad).is_err(), "{bad:?}");
        }
        let json = serde_json::json!({"t": {"s.t0": {"bits": 24}, "l": [5, 6]}});
        assert_eq!(report_cell(&json, "t[s.t0].bits"), table::Cell::Int(24));
        assert_eq!(report_cell(&json, "t.l[1]"), table::Cell::Int(6));
        assert_eq!(report_cell(&json, "t.s.t0.bits"), table::Cell::Empty);
        let f =
            file(r#"(base: "x", axes: [(path: "a", values: List([1]))], report: ["ok", "a[b"])"#);
        let e = points(&f).unwrap_err();
        assert_eq!(e.0, "report[1]");
    }

    #[test]
    fn an_axis_sets_its_also_paths_to_the_same_value() {
        let f = file(
            r#"(base: "x", sets: ["s=0"], axes: [
            (path: "a", also: ["b", "c"], values: List([1, 2])),
            (path: "d", values: List([true])),
        ])"#,
        );
        let s = sweep_of(f);
        assert_eq!(s.sets(&s.points[1]), ["s=0", "a=2", "b=2", "c=2", "d=true"]);
        // the baseline: the point's sets, then its own
        assert_eq!(s.baseline_sets(&s.points[1]), None);
        let mut b = s.clone();
        b.file.baseline = vec!["a=0".into()];
        assert_eq!(
            b.baseline_sets(&b.points[0]).unwrap(),
            ["s=0", "a=1", "b=1", "c=1", "d=true", "a=0"]
        );
        let f = file(r#"(base: "x", axes: [(path: "a", also: [" "], values: List([1]))])"#);
        assert_eq!(points(&f).unwrap_err().0, "axes[0].also");
    }

    #[test]
    fn bad_sweeps_and_shards_are_rejected() {
        let f = file(r#"(base: "x", axes: [])"#);
        assert!(points(&f).is_err());
        let f = file(r#"(base: "x", axes: [(path: "a", values: Grid("a", 2, 3))])"#);
        assert!(points(&f).unwrap_err().1.contains("numbers"));
        let f = file(r#"(base: "x", axes: [(path: "a", values: List([]))])"#);
        assert!(points(&f).is_err());
        assert_eq!(Shard::parse("1/4").unwrap(), Shard { i: 1, n: 4 });
        for s in ["4/4", "1", "a/2", "0/0"] {
            assert!(Shard::parse(s).is_err(), "{s}");
        }
    }
}

//! A sweep's baseline (`baseline: [...]` in the sweep file): each point's config with the
//! baseline's overrides added after the point's own, rendered before the points, once per
//! distinct baseline config (points that differ only in what the baseline overrides share
//! one); every point's bit-accurate image is then compared with its baseline's bit-accurate
//! image, the same error and artifact figures as against the reference. This is the comparison that holds
//! everything but one factor fixed: e.g. a quantized normal map against the same engine with
//! every normal kept (`quantizer=Exact`), where the f64 reference would also count the bake
//! and the texture coordinates' rounding (issue 11, Tarini §4).

use super::table::{self, Cell};
use super::{Point, Sweep};
use crate::config::{self, InputError, LoadOptions};
use crate::metrics::{self, Rgb64};
use crate::run::RunResult;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The baseline's columns, after the report columns: its error and artifact figures and the
/// hash of its config (a resumed row is kept only with the same baseline).
pub fn columns() -> Vec<String> {
    let mut c: Vec<String> = table::ERRORS
        .iter()
        .chain(&table::ARTIFACTS)
        .map(|s| format!("baseline_{s}"))
        .collect();
    c.push("baseline_hash".into());
    c
}

/// The rendered baseline.
#[derive(Debug, Clone)]
pub struct Baseline {
    /// SHA-256 of the baseline's config.
    pub hash: String,
    image: Rgb64,
    mask: Vec<bool>,
}

impl Baseline {
    /// Load and render a baseline (`force` as for the points); the error says why it does
    /// not run.
    fn render(base: &Path, sets: &[String], force: bool) -> Result<Baseline, String> {
        let err = |e: InputError| format!("the baseline does not run: {e}");
        let l = config::load_with(base, sets, LoadOptions { force }).map_err(err)?;
        let r = crate::run::run(&l, None).map_err(err)?;
        Ok(Baseline {
            hash: l.hash.clone(),
            image: Rgb64::from_rgb8(&r.image),
            mask: r.mask,
        })
    }

    /// A point's baseline cells (its image against the baseline's), in [`columns`] order.
    pub fn cells(&self, r: &RunResult) -> Vec<Cell> {
        let img = Rgb64::from_rgb8(&r.image);
        let e = metrics::compare(&img, &r.mask, &self.image, &self.mask);
        let a = crate::artifacts::measure(&img, &r.mask, &self.image, &self.mask);
        let mut c: Vec<Cell> = table::errors(&e).into_iter().collect();
        c.extend(table::artifacts(&a));
        c.push(Cell::Text(self.hash.clone()));
        c
    }
}

/// The baselines of a sweep's points to run, each distinct one rendered once.
#[derive(Debug, Default)]
pub struct Baselines {
    /// Per point index, its baseline's config hash (or why it has none).
    of_point: BTreeMap<usize, Result<String, String>>,
    /// Per config hash, the render (or why it failed).
    renders: BTreeMap<String, Result<Baseline, String>>,
}

impl Baselines {
    /// Render the baselines of `points` (none if the sweep has no baseline), in parallel.
    pub fn render(sweep: &Sweep, points: &[&Point], force: bool) -> Baselines {
        if sweep.file.baseline.is_empty() {
            return Baselines::default();
        }
        type Hashed = (usize, (PathBuf, Vec<String>), Result<String, String>);
        let hashed: Vec<Hashed> = points
            .par_iter()
            .map(|p| {
                let (config, sets) = (
                    sweep.config_of(p),
                    sweep.baseline_sets(p).unwrap_or_default(),
                );
                let h = config::hash_with(&config, &sets)
                    .map_err(|e| format!("the baseline does not load: {e}"));
                (p.index, (config, sets), h)
            })
            .collect();
        let mut distinct: BTreeMap<&str, &(PathBuf, Vec<String>)> = BTreeMap::new();
        for (_, what, h) in &hashed {
            if let Ok(h) = h {
                distinct.entry(h).or_insert(what);
            }
        }
        let renders = distinct
            .into_par_iter()
            .map(|(h, (config, sets))| (h.to_string(), Baseline::render(config, sets, force)))
            .collect();
        Baselines {
            of_point: hashed.into_iter().map(|(i, _, h)| (i, h)).collect(),
            renders,
        }
    }

    /// Point `index`'s baseline: none without a baseline, else the render or why there is
    /// none.
    pub fn of(&self, index: usize) -> Option<Result<&Baseline, &str>> {
        let h = self.of_point.get(&index)?;
        Some(match h {
            Err(e) => Err(e.as_str()),
            Ok(h) => match self.renders.get(h) {
                Some(Ok(b)) => Ok(b),
                Some(Err(e)) => Err(e.as_str()),
                None => Err("the baseline was not rendered (a bug)"),
            },
        })
    }
}

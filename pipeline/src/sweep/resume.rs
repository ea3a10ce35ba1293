//! A sweep run into its output directory: each row journaled as its point finishes
//! ([`journal`](super::journal)), the final files written all or nothing at the end and the
//! journal removed; with `resume`, the rows of an earlier run (its journal and its
//! `sweep.jsonl`) are kept where they still match their point, and only the rest run.
//!
//! An earlier row is kept only if the sweep file still has its point (same `index`), the
//! point is in this run's shard, the row is `ok` and its `config_hash` is the hash of the
//! point's config as the sweep file now defines it (and, with a baseline, its `baseline_hash`
//! that of the baseline's config now). So an edited sweep reruns the points it changed (and
//! a row with other columns, or an error row, is run again).

use super::journal::{self, Journal, JOURNAL};
use super::{RunOptions, Sweep};
use crate::config::{self, InputError};
use crate::output::OutputSet;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Why a sweep into a directory failed: bad input (exit 2) or an internal error.
#[derive(Debug)]
pub enum DirError {
    Input(InputError),
    Internal(String),
}

impl std::fmt::Display for DirError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DirError::Input(e) => write!(f, "{e}"),
            DirError::Internal(e) => write!(f, "internal error: {e}"),
        }
    }
}

/// What a sweep into a directory did.
#[derive(Debug)]
pub struct Outcome {
    pub table: super::Table,
    /// Points run now.
    pub ran: usize,
    /// Rows kept from an earlier run.
    pub kept: usize,
    /// Points of this run with an earlier row of this sweep's columns that was not kept
    /// (their point changed, or the row was an error): run again. (Rows with other columns
    /// are dropped without being counted.)
    pub stale: usize,
    /// A journal was there and was replaced (a run without `resume`).
    pub replaced_journal: bool,
    /// The first failed journal write, if any (the sweep went on without it).
    pub journal_failure: Option<String>,
    /// The final files, in order.
    pub written: Vec<PathBuf>,
}

/// Run `sweep` into `out` (see the module doc).
pub fn run_into(
    sweep: &Sweep,
    out: &Path,
    opts: RunOptions,
    resume: bool,
) -> Result<Outcome, DirError> {
    let out_err =
        |e: String| DirError::Input(InputError::new(out.display().to_string(), "--out", e));
    std::fs::create_dir_all(out)
        .map_err(|e| out_err(format!("cannot create the output directory: {e}")))?;
    let journal_path = out.join(JOURNAL);
    let replaced_journal = !resume && journal_path.exists();
    let (kept, stale) = if resume {
        earlier_rows(sweep, out, &opts)?
    } else {
        (Vec::new(), 0)
    };
    let columns = sweep.columns();
    let lines: Vec<String> = kept.iter().map(|r| r.json_line(&columns)).collect();
    let journal = Journal::create(&journal_path, &lines)
        .map_err(|e| out_err(format!("cannot write {}: {e}", journal_path.display())))?;
    let n_kept = kept.len();
    let (table, journal_failure) = sweep.run_with(opts, kept, Some(&journal))?;
    drop(journal);
    let mut set = OutputSet::new(out);
    for (name, bytes) in table.files() {
        set.add(name, bytes);
    }
    let written = set.commit().map_err(out_err)?;
    let _ = std::fs::remove_file(&journal_path);
    Ok(Outcome {
        ran: table.rows.len() - n_kept,
        kept: n_kept,
        stale,
        replaced_journal,
        journal_failure,
        written,
        table,
    })
}

/// The rows of an earlier run in `out` that still match their point and are in the shard
/// (one per point, in point order), and the number of this run's points whose earlier row
/// was not kept.
fn earlier_rows(
    sweep: &Sweep,
    out: &Path,
    opts: &RunOptions,
) -> Result<(Vec<super::Row>, usize), DirError> {
    let columns = sweep.columns();
    let axes = sweep.file.axes.len();
    let mut found =
        journal::read(&out.join(JOURNAL), &columns, axes, true).map_err(DirError::Input)?;
    found.extend(
        journal::read(&out.join("sweep.jsonl"), &columns, axes, false).map_err(DirError::Input)?,
    );
    // the candidates, one per point of the shard: a row with the right columns and values
    let mut seen = std::collections::BTreeSet::new();
    let mut candidates = BTreeMap::new();
    for e in found {
        let Some(row) = e.row else { continue };
        let Some(p) = sweep.points.get(row.index) else {
            continue;
        };
        if !sweep.in_shard(opts, p.index) {
            continue;
        }
        seen.insert(p.index);
        let values = sweep.cells(p);
        if row.is_ok() && row.values == values && row.config_hash().is_some() {
            candidates.entry(p.index).or_insert(row);
        }
    }
    let rows: Vec<super::Row> = candidates.into_values().collect();
    // with a baseline, a row is kept only if it was compared with the point's baseline now
    let at = columns.iter().position(|c| c == "baseline_hash");
    let same_baseline = |r: &super::Row, p: &super::Point| match (sweep.baseline_sets(p), at) {
        (None, _) => true,
        (Some(sets), Some(at)) => config::hash_with(&sweep.config_of(p), &sets)
            .is_ok_and(|h| r.report.get(at - 1 - axes) == Some(&super::table::Cell::Text(h))),
        _ => false,
    };
    let check = || -> Vec<bool> {
        rows.par_iter()
            .map(|r| {
                let p = &sweep.points[r.index];
                same_baseline(r, p)
                    && config::hash_with(&sweep.config_of(p), &sweep.sets(p))
                        .is_ok_and(|h| Some(h.as_str()) == r.config_hash())
            })
            .collect()
    };
    let keep = sweep.on_pool(opts, check).map_err(DirError::Internal)?;
    let kept: Vec<super::Row> = rows
        .into_iter()
        .zip(keep)
        .filter_map(|(r, k)| k.then_some(r))
        .collect();
    let stale = seen.len() - kept.len();
    Ok((kept, stale))
}

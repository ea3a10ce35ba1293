//! A sweep run into its output directory: each row journaled as its point finishes
//! ([`super::journal`]), the final files written all or nothing at the end and the
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
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::io::Write;
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
    /// Points in the whole sweep (all shards).
    pub points: usize,
    /// Rows written (run now or kept).
    pub rows: usize,
    /// Of them, error rows.
    pub errors: usize,
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

/// The final files as the rows arrive: `sweep.csv` and `sweep.jsonl` written through to
/// temporary files beside them (so a sweep's memory does not grow with its rows), renamed
/// into place with `sweep.json` when the sweep ends, removed if it fails.
struct Stream {
    dir: PathBuf,
    csv: std::io::BufWriter<std::fs::File>,
    jsonl: std::io::BufWriter<std::fs::File>,
    columns: Vec<String>,
    indices: Vec<usize>,
    errors: usize,
}

const TMP_CSV: &str = ".sweep.csv.tmp";
const TMP_JSONL: &str = ".sweep.jsonl.tmp";
const TMP_JSON: &str = ".sweep.json.tmp";

impl Stream {
    fn create(dir: &Path, columns: Vec<String>) -> std::io::Result<Stream> {
        let open = |n: &str| std::fs::File::create(dir.join(n)).map(std::io::BufWriter::new);
        let mut csv = open(TMP_CSV)?;
        csv.write_all(super::table::csv_header(&columns).as_bytes())?;
        Ok(Stream {
            dir: dir.to_path_buf(),
            csv,
            jsonl: open(TMP_JSONL)?,
            columns,
            indices: Vec::new(),
            errors: 0,
        })
    }

    fn push(&mut self, r: &super::Row) -> std::io::Result<()> {
        self.csv.write_all(r.csv_line().as_bytes())?;
        self.jsonl
            .write_all(r.json_line(&self.columns).as_bytes())?;
        self.jsonl.write_all(b"\n")?;
        self.indices.push(r.index);
        self.errors += usize::from(!r.is_ok());
        Ok(())
    }

    /// Flush and sync the rows, write `sweep.json`, and rename the three into place.
    fn finish(mut self, points: usize) -> std::io::Result<Vec<PathBuf>> {
        let summary = super::table::summary(points, &self.columns, &self.indices, self.errors);
        std::fs::write(self.dir.join(TMP_JSON), summary)?;
        for w in [&mut self.csv, &mut self.jsonl] {
            w.flush()?;
            w.get_ref().sync_all()?;
        }
        let mut written = Vec::new();
        for (tmp, name) in [
            (TMP_CSV, "sweep.csv"),
            (TMP_JSONL, "sweep.jsonl"),
            (TMP_JSON, "sweep.json"),
        ] {
            std::fs::rename(self.dir.join(tmp), self.dir.join(name))?;
            written.push(self.dir.join(name));
        }
        Ok(written)
    }

    /// Remove the temporary files (a failed sweep).
    fn discard(dir: &Path) {
        for t in [TMP_CSV, TMP_JSONL, TMP_JSON] {
            let _ = std::fs::remove_file(dir.join(t));
        }
    }
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
    for name in ["sweep.csv", "sweep.jsonl", "sweep.json"] {
        if out.join(name).is_dir() {
            return Err(out_err(format!(
                "cannot write {}: it is a directory",
                out.join(name).display()
            )));
        }
    }
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
    let mut stream = Stream::create(out, columns)
        .map_err(|e| out_err(format!("cannot write in {}: {e}", out.display())))?;
    let mut write_failed = None;
    let run = sweep.run_streamed(opts, kept, Some(&journal), &mut |r| {
        stream.push(&r).map_err(|e| {
            let m = format!("cannot write the rows in {}: {e}", out.display());
            write_failed = Some(m.clone());
            m
        })
    });
    drop(journal);
    let (rows, errors) = (stream.indices.len(), stream.errors);
    let finished = match (run, write_failed) {
        (_, Some(m)) => Err(out_err(m)),
        (Err(e), None) => Err(e),
        (Ok(journal_failure), None) => stream
            .finish(sweep.points.len())
            .map(|w| (w, journal_failure))
            .map_err(|e| out_err(format!("cannot write the rows in {}: {e}", out.display()))),
    };
    let (written, journal_failure) = finished.inspect_err(|_| Stream::discard(out))?;
    let _ = std::fs::remove_file(&journal_path);
    Ok(Outcome {
        points: sweep.points.len(),
        rows,
        errors,
        ran: rows - n_kept,
        kept: n_kept,
        stale,
        replaced_journal,
        journal_failure,
        written,
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

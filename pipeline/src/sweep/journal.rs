//! The journal of a running sweep, `DIR/sweep.partial.jsonl`: each point's row (its JSON
//! line, as in `sweep.jsonl`) appended and flushed as the point finishes, in completion order,
//! so that a killed sweep leaves the rows it had. A last line without its line break (the
//! write a kill cut short) is ignored when the journal is read back.

use super::table::Row;
use crate::config::InputError;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The journal's file name in the output directory.
pub const JOURNAL: &str = "sweep.partial.jsonl";

/// An open journal, appended to by the worker threads.
pub struct Journal {
    path: PathBuf,
    file: Mutex<File>,
}

impl Journal {
    /// Start the journal at `path` with these lines (the rows kept from an earlier run),
    /// replacing any journal there.
    pub fn create(path: &Path, lines: &[String]) -> std::io::Result<Journal> {
        let mut text = String::new();
        for l in lines {
            text.push_str(l);
            text.push('\n');
        }
        crate::output::write_atomic(path, text.as_bytes()).map_err(std::io::Error::other)?;
        let file = OpenOptions::new().append(true).open(path)?;
        Ok(Journal {
            path: path.to_path_buf(),
            file: Mutex::new(file),
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Append one row's JSON line (one write of the whole line and its break, then a flush).
    pub fn append(&self, line: &str) -> std::io::Result<()> {
        let mut f = self.file.lock().unwrap_or_else(|e| e.into_inner());
        f.write_all(format!("{line}\n").as_bytes())?;
        f.flush()
    }
}

/// One row read back from a journal or a `sweep.jsonl`, with its 1-based line.
#[derive(Debug)]
pub struct Earlier {
    pub line: usize,
    /// `None`: a row of a sweep with other columns.
    pub row: Option<Row>,
    /// The line's text (kept to start the new journal with).
    pub text: String,
}

/// The rows of a journal or `sweep.jsonl` at `path` (none if it does not exist), for a table
/// with `columns` and `axes` axis columns. A last line without a line break is skipped only
/// when `torn_ok` (a journal); text that is no sweep row is an error naming the file and line.
pub fn read(
    path: &Path,
    columns: &[String],
    axes: usize,
    torn_ok: bool,
) -> Result<Vec<Earlier>, InputError> {
    let name = path.display().to_string();
    let text = match std::fs::read(path) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(InputError::new(&name, "", format!("cannot read: {e}"))),
    };
    let mut out = Vec::new();
    let mut rest = &text[..];
    let mut line = 0;
    while !rest.is_empty() {
        line += 1;
        let (l, complete) = match rest.iter().position(|&b| b == b'\n') {
            Some(k) => {
                let l = &rest[..k];
                rest = &rest[k + 1..];
                (l, true)
            }
            None => {
                let l = rest;
                rest = &[];
                (l, false)
            }
        };
        if !complete && torn_ok {
            break;
        }
        let bad = |m: String| {
            InputError::new(
                &name,
                "",
                format!("{m}: expected a sweep row (one JSON object a line, as in sweep.jsonl)"),
            )
            .at(Some((line, 1)))
        };
        let l = std::str::from_utf8(l).map_err(|_| bad("not UTF-8 text".into()))?;
        if l.trim().is_empty() {
            continue;
        }
        let row = Row::from_json_line(l, columns, axes).map_err(bad)?;
        out.push(Earlier {
            line,
            row,
            text: l.to_string(),
        });
    }
    Ok(out)
}

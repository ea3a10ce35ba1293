//! A sweep's rows: `sweep.csv` (one line per row: error messages have no line breaks),
//! `sweep.jsonl` (one JSON object per row, keys in column order), `sweep.json` (the number of
//! points and the rows' indices), and the merge of shards.

use super::Scalar;
use crate::artifacts::ArtifactStats;
use crate::metrics::ErrorStats;
use crate::report::Report;
use std::fmt::Write;
use std::path::Path;

/// One cell of a row.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    Empty,
    Int(i64),
    Float(f64),
    Bool(bool),
    Text(String),
}

impl Cell {
    pub(crate) fn of(s: &Scalar) -> Cell {
        match s {
            Scalar::Bool(b) => Cell::Bool(*b),
            Scalar::Int(i) => Cell::Int(*i),
            Scalar::Float(x) => Cell::Float(*x),
            Scalar::Text(t) => Cell::Text(t.clone()),
        }
    }

    /// The JSON text (shortest round-trip numbers; non-finite as null).
    fn json(&self) -> String {
        match self {
            Cell::Empty => "null".into(),
            Cell::Int(i) => i.to_string(),
            Cell::Float(x) if x.is_finite() => serde_json::to_string(x).unwrap(),
            Cell::Float(_) => "null".into(),
            Cell::Bool(b) => b.to_string(),
            Cell::Text(t) => serde_json::to_string(t).unwrap(),
        }
    }

    /// The CSV field (numbers as in JSON, text quoted when it needs to be).
    pub(crate) fn csv(&self) -> String {
        match self {
            Cell::Empty => String::new(),
            Cell::Text(t) => {
                if t.contains([',', '"', '\n', '\r']) {
                    format!("\"{}\"", t.replace('"', "\"\""))
                } else {
                    t.clone()
                }
            }
            Cell::Float(x) if !x.is_finite() => String::new(),
            c => c.json(),
        }
    }
}

/// The error figures of one comparison, in column order ([`errors`]).
pub(crate) const ERRORS: [&str; 3] = ["psnr_db", "max_lsb", "mean_lsb"];
/// The artifact figures of one comparison, in column order ([`artifacts`]).
pub(crate) const ARTIFACTS: [&str; 7] = [
    "banding",
    "blockiness",
    "faceting_lsb",
    "ringing_lsb",
    "lowpass_psnr_db",
    "half_ssim",
    "ms_ssim",
];
/// The animation's temporal figures (`animation.*`), empty for a single frame.
pub(crate) const TEMPORAL: [&str; 3] = [
    "max_flicker_lsb",
    "temporal_ringing_lsb",
    "temporal_ringing_share_4lsb",
];

/// The report columns after the axes, in order.
pub fn report_columns() -> Vec<String> {
    let mut c: Vec<String> = [
        "status",
        "error",
        "config_hash",
        "gates_total",
        "gates_memory",
        "bits_per_triangle",
        "bits_per_texel",
        "cycles",
        "fragments",
    ]
    .map(String::from)
    .to_vec();
    for k in ["total", "algorithm", "quantization"] {
        for s in ERRORS {
            c.push(format!("{k}_{s}"));
        }
    }
    for k in ["total", "quantization"] {
        for s in ARTIFACTS {
            c.push(format!("{k}_{s}"));
        }
    }
    for k in ["total", "algorithm", "quantization"] {
        for s in ["edge_excess_lsb", "edge_p99_lsb", "worst_seam_lsb"] {
            c.push(format!("{k}_{s}"));
        }
    }
    c.extend(TEMPORAL.map(String::from));
    c
}

/// One point's row: its index, axis values and the report columns.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub index: usize,
    pub values: Vec<Cell>,
    /// One cell per [`report_columns`], then one per [`Table::extra`] column, then one per
    /// unit of [`Table::units`].
    pub report: Vec<Cell>,
}

pub(crate) fn errors(e: &ErrorStats) -> [Cell; 3] {
    [
        Cell::Float(e.psnr_db),
        Cell::Float(e.max_abs_lsb),
        Cell::Float(e.mean_abs_lsb),
    ]
}

pub(crate) fn artifacts(a: &ArtifactStats) -> [Cell; 7] {
    [
        Cell::Float(a.banding),
        Cell::Float(a.blockiness),
        Cell::Float(a.faceting_lsb),
        Cell::Float(a.ringing_lsb),
        Cell::Float(a.lowpass_psnr_db),
        Cell::Float(a.half_ssim),
        Cell::Float(a.ms_ssim),
    ]
}

impl Row {
    /// The row of a run with report `r`; `extra`: the cells of the table's [`Table::extra`]
    /// columns; `units`: the table's [`Table::units`] (a unit the point's engine lacks is an
    /// empty cell).
    pub fn ok(
        index: usize,
        values: Vec<Cell>,
        r: &Report,
        extra: Vec<Cell>,
        units: &[String],
    ) -> Row {
        let mut c = vec![
            Cell::Text("ok".into()),
            Cell::Empty,
            Cell::Text(r.config_hash.clone()),
            Cell::Float(r.gates.total),
            Cell::Float(r.gates.memory),
            Cell::Int(r.bandwidth.bits_per_triangle as i64),
            Cell::Int(i64::from(r.bandwidth.bits_per_texel)),
            Cell::Int(r.cycles.total as i64),
            Cell::Int(r.cycles.fragments as i64),
        ];
        for e in [&r.error.total, &r.error.algorithm, &r.error.quantization] {
            c.extend(errors(e));
        }
        for a in [&r.artifacts.total, &r.artifacts.quantization] {
            c.extend(artifacts(a));
        }
        for e in [&r.edges.total, &r.edges.algorithm, &r.edges.quantization] {
            c.extend([
                Cell::Float(e.excess_lsb),
                Cell::Float(e.edge_p99_lsb),
                Cell::Float(e.worst_seam_lsb),
            ]);
        }
        match &r.animation {
            Some(a) => c.extend([
                Cell::Float(a.max_flicker_lsb),
                Cell::Float(a.ringing.mean_lsb),
                Cell::Float(a.ringing.share_4lsb),
            ]),
            None => c.extend([Cell::Empty, Cell::Empty, Cell::Empty]),
        }
        c.extend(extra);
        for u in units {
            c.push(
                r.gates
                    .per_unit
                    .get(u)
                    .map_or(Cell::Empty, |g| Cell::Float(g.total)),
            );
        }
        Row {
            index,
            values,
            report: c,
        }
    }

    /// The row of a point that failed with `message`, in a table of `after` columns after
    /// the report columns (extra and unit columns).
    pub fn error(index: usize, values: Vec<Cell>, message: &str, after: usize) -> Row {
        let one_line = message.split_whitespace().collect::<Vec<_>>().join(" ");
        let mut c = vec![Cell::Text("error".into()), Cell::Text(one_line)];
        c.resize(report_columns().len() + after, Cell::Empty);
        Row {
            index,
            values,
            report: c,
        }
    }

    pub fn is_ok(&self) -> bool {
        self.report[0] == Cell::Text("ok".into())
    }

    /// The row's `config_hash` (none in an error row).
    pub fn config_hash(&self) -> Option<&str> {
        match &self.report[2] {
            Cell::Text(h) => Some(h),
            _ => None,
        }
    }

    /// The row as one JSON object, keys `columns` (a [`Table::columns`]) in order, no line
    /// break.
    /// The row's CSV line (with its line break).
    pub fn csv_line(&self) -> String {
        let line: Vec<String> = self.cells().map(|c| c.csv()).collect();
        line.join(",") + "\n"
    }

    pub fn json_line(&self, columns: &[String]) -> String {
        let fields: Vec<String> = columns
            .iter()
            .zip(self.cells())
            .map(|(k, c)| format!("{}:{}", serde_json::to_string(k).unwrap(), c.json()))
            .collect();
        format!("{{{}}}", fields.join(","))
    }

    /// Read a row back from a [`Row::json_line`] of a table with `columns` and `axes` axis
    /// columns: `Ok(None)` for a row of another sweep's columns, an error for text that is
    /// no sweep row. Reads back the cells that wrote it (numbers round-trip exactly).
    pub fn from_json_line(
        line: &str,
        columns: &[String],
        axes: usize,
    ) -> Result<Option<Row>, String> {
        let v: serde_json::Value =
            serde_json::from_str(line).map_err(|e| format!("not JSON ({e})"))?;
        let obj = v.as_object().ok_or("a JSON value that is no object")?;
        let index = obj
            .get("index")
            .and_then(|i| i.as_u64())
            .ok_or("no integer \"index\"")?;
        match obj.get("config_hash") {
            Some(serde_json::Value::String(_) | serde_json::Value::Null) => {}
            _ => return Err("no \"config_hash\" (text or null)".into()),
        }
        if obj.len() != columns.len() || columns.iter().any(|c| !obj.contains_key(c)) {
            return Ok(None);
        }
        let mut cells = Vec::with_capacity(columns.len());
        for c in &columns[1..] {
            cells.push(match &obj[c] {
                serde_json::Value::Null => Cell::Empty,
                serde_json::Value::Bool(b) => Cell::Bool(*b),
                serde_json::Value::String(t) => Cell::Text(t.clone()),
                serde_json::Value::Number(n) => match n.as_i64() {
                    Some(i) => Cell::Int(i),
                    None => Cell::Float(
                        exact_number(line, c)
                            .ok_or_else(|| format!("{c}: {n} is not a 64-bit number"))?,
                    ),
                },
                _ => return Err(format!("{c}: an array or object, not a cell")),
            });
        }
        let report = cells.split_off(axes);
        Ok(Some(Row {
            index: index as usize,
            values: cells,
            report,
        }))
    }

    fn cells(&self) -> impl Iterator<Item = Cell> + '_ {
        std::iter::once(Cell::Int(self.index as i64))
            .chain(self.values.iter().cloned())
            .chain(self.report.iter().cloned())
    }
}

/// The number after `"key":` in a JSON line, read with Rust's exact decimal-to-`f64`
/// conversion (serde_json's default reading can be one unit in the last place off). The
/// first `"key":` is the key itself: inside a JSON string its quotes would be escaped.
fn exact_number(line: &str, key: &str) -> Option<f64> {
    let pat = format!("{}:", serde_json::to_string(key).ok()?);
    let rest = &line[line.find(&pat)? + pat.len()..];
    let end = rest.find([',', '}']).unwrap_or(rest.len());
    rest[..end].trim().parse().ok()
}

/// The rows of a sweep (or of one shard of it).
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The axes' column names.
    pub axes: Vec<String>,
    /// Columns after the report columns: the baseline's (`baseline.rs`), if any, then the
    /// sweep file's `report` fields (`report.PATH`).
    pub extra: Vec<String>,
    /// The base config's unit names: a `gates.<unit>` column each, after the report and
    /// extra columns.
    pub units: Vec<String>,
    /// Points in the whole sweep (all shards).
    pub points: usize,
    pub rows: Vec<Row>,
}

impl Table {
    /// All column names: `index`, the axes, the report columns, the extra columns,
    /// `gates.<unit>` per unit
    /// (unit names hold no `.`, so these collide with no other column).
    pub fn columns(&self) -> Vec<String> {
        std::iter::once("index".to_string())
            .chain(self.axes.iter().cloned())
            .chain(report_columns())
            .chain(self.extra.iter().cloned())
            .chain(self.units.iter().map(|u| format!("gates.{u}")))
            .collect()
    }

    /// The cell of `row` in `column` (none for a column the table does not have).
    pub fn cell(&self, row: &Row, column: &str) -> Option<Cell> {
        let k = self.columns().iter().position(|c| c == column)?;
        row.cells().nth(k)
    }

    /// The number in `row`'s `column` (none for an empty or text cell).
    pub fn number(&self, row: &Row, column: &str) -> Option<f64> {
        match self.cell(row, column)? {
            Cell::Int(i) => Some(i as f64),
            Cell::Float(x) => Some(x),
            _ => None,
        }
    }

    pub fn to_csv(&self) -> String {
        let mut s = csv_header(&self.columns());
        for r in &self.rows {
            s.push_str(&r.csv_line());
        }
        s
    }

    pub fn to_jsonl(&self) -> String {
        let cols = self.columns();
        let mut s = String::new();
        for r in &self.rows {
            let _ = writeln!(s, "{}", r.json_line(&cols));
        }
        s
    }

    /// `sweep.json`: the number of points, the columns and the rows' indices.
    pub fn summary(&self) -> String {
        let rows: Vec<usize> = self.rows.iter().map(|r| r.index).collect();
        let errors = self.rows.iter().filter(|r| !r.is_ok()).count();
        summary(self.points, &self.columns(), &rows, errors)
    }

    /// The output files: `sweep.csv`, `sweep.jsonl` and `sweep.json`.
    pub fn files(&self) -> Vec<(&'static str, Vec<u8>)> {
        vec![
            ("sweep.csv", self.to_csv().into_bytes()),
            ("sweep.jsonl", self.to_jsonl().into_bytes()),
            ("sweep.json", self.summary().into_bytes()),
        ]
    }
}

/// The CSV header line of a table with these columns (with its line break).
pub fn csv_header(columns: &[String]) -> String {
    let head: Vec<String> = columns
        .iter()
        .map(|c| Cell::Text(c.clone()).csv())
        .collect();
    head.join(",") + "\n"
}

/// `sweep.json`: the number of points, the columns, the rows' indices and the error rows.
pub fn summary(points: usize, columns: &[String], rows: &[usize], errors: usize) -> String {
    let v = serde_json::json!({
        "points": points,
        "columns": columns,
        "rows": rows,
        "errors": errors,
    });
    serde_json::to_string_pretty(&v).unwrap() + "\n"
}

/// The merged files of several shard directories (each with `sweep.csv`, `sweep.jsonl` and
/// `sweep.json`): the rows of all shards in point order, byte for byte those of the
/// unsharded run. Shards must share their columns and number of points, hold no point
/// twice, and together every point.
pub fn merge(dirs: &[&Path]) -> Result<Vec<(&'static str, Vec<u8>)>, String> {
    let mut header: Option<String> = None;
    let mut points: Option<u64> = None;
    let mut rows: Vec<(u64, String, String)> = Vec::new();
    for d in dirs {
        let read = |name: &str| {
            std::fs::read_to_string(d.join(name))
                .map_err(|e| format!("{}: {e}", d.join(name).display()))
        };
        let (csv, jsonl, summary) = (
            read("sweep.csv")?,
            read("sweep.jsonl")?,
            read("sweep.json")?,
        );
        let summary: serde_json::Value =
            serde_json::from_str(&summary).map_err(|e| format!("{}: {e}", d.display()))?;
        let n = summary["points"]
            .as_u64()
            .ok_or_else(|| format!("{}/sweep.json: no number of points", d.display()))?;
        if points.is_some_and(|p| p != n) {
            return Err(format!(
                "{}: a sweep of {n} points, the others have {}",
                d.display(),
                points.unwrap()
            ));
        }
        points = Some(n);
        let mut lines = csv.lines();
        let head = lines.next().unwrap_or("").to_string();
        if header.as_ref().is_some_and(|h| *h != head) {
            return Err(format!(
                "{}/sweep.csv: its columns differ from the first shard's",
                d.display()
            ));
        }
        header = Some(head);
        let jl: Vec<&str> = jsonl.lines().collect();
        let cl: Vec<&str> = lines.collect();
        if jl.len() != cl.len() {
            return Err(format!(
                "{}: sweep.csv has {} rows, sweep.jsonl {}",
                d.display(),
                cl.len(),
                jl.len()
            ));
        }
        for (c, j) in cl.into_iter().zip(jl) {
            let index: u64 = c
                .split(',')
                .next()
                .and_then(|i| i.parse().ok())
                .ok_or_else(|| format!("{}/sweep.csv: a row without an index", d.display()))?;
            rows.push((index, c.to_string(), j.to_string()));
        }
    }
    let (Some(header), Some(points)) = (header, points) else {
        return Err("no shard directories to merge".into());
    };
    rows.sort_by_key(|r| r.0);
    for w in rows.windows(2) {
        if w[0].0 == w[1].0 {
            return Err(format!("point {} is in two shards", w[0].0));
        }
    }
    let have: Vec<u64> = rows.iter().map(|r| r.0).collect();
    if have != (0..points).collect::<Vec<_>>() {
        let missing: Vec<String> = (0..points)
            .filter(|i| have.binary_search(i).is_err())
            .take(10)
            .map(|i| i.to_string())
            .collect();
        return Err(format!(
            "the shards hold {} of {points} points (missing: {}{})",
            rows.len(),
            missing.join(", "),
            if points as usize - rows.len() > 10 {
                ", ..."
            } else {
                ""
            }
        ));
    }
    let mut csv = header.clone() + "\n";
    let mut jsonl = String::new();
    for (_, c, j) in &rows {
        csv.push_str(c);
        csv.push('\n');
        jsonl.push_str(j);
        jsonl.push('\n');
    }
    let errors = rows
        .iter()
        .filter(|r| {
            serde_json::from_str::<serde_json::Value>(&r.2).is_ok_and(|v| v["status"] == "error")
        })
        .count();
    let columns: Vec<&str> = header.split(',').collect();
    let summary = serde_json::json!({
        "points": points,
        "columns": columns,
        "rows": have,
        "errors": errors,
    });
    Ok(vec![
        ("sweep.csv", csv.into_bytes()),
        ("sweep.jsonl", jsonl.into_bytes()),
        (
            "sweep.json",
            (serde_json::to_string_pretty(&summary).unwrap() + "\n").into_bytes(),
        ),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::Point;

    #[test]
    fn a_json_line_reads_back_to_the_same_cells() {
        let p = Point {
            index: 3,
            values: vec![
                Scalar::Int(7),
                Scalar::Float(0.1 + 0.2),
                Scalar::Text("a,\"b\"".into()),
            ],
        };
        let mut row = Row::error(
            p.index,
            p.values.iter().map(Cell::of).collect(),
            "bad\n  \"thing\"",
            2,
        );
        row.report[0] = Cell::Text("ok".into());
        row.report[2] = Cell::Text("ab12".into());
        row.report[3] = Cell::Float(19533.0);
        row.report[4] = Cell::Int(-5);
        row.report[5] = Cell::Float(1.0000000000000002e-300);
        row.report[6] = Cell::Bool(true);
        let n = row.report.len();
        row.report[n - 2] = Cell::Float(874.5);
        let t = Table {
            axes: vec!["a".into(), "b".into(), "c".into()],
            extra: Vec::new(),
            units: vec!["fetch".into(), "total".into()],
            points: 4,
            rows: vec![row.clone()],
        };
        let cols = t.columns();
        assert_eq!(cols[cols.len() - 2..], ["gates.fetch", "gates.total"]);
        let line = row.json_line(&cols);
        let back = Row::from_json_line(&line, &cols, 3).unwrap().unwrap();
        assert_eq!(back, row);
        assert_eq!(back.json_line(&cols), line);
        // other columns: not this sweep's row; no index: not a row at all
        assert_eq!(
            Row::from_json_line(&line, &cols[..cols.len() - 1], 3),
            Ok(None)
        );
        assert!(Row::from_json_line(r#"{"config_hash":null}"#, &cols, 3).is_err());
        assert!(Row::from_json_line("[1]", &cols, 3).is_err());
    }
}

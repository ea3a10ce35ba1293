//! `bumpsim plot CSV` and the `plots` of a sweep file (`docs/sweep.md`): two numeric columns
//! of a sweep's CSV as a scatter or a line, PNG or SVG, with the Pareto front of chosen
//! objectives ([`pareto`]) highlighted and its rows written beside the plot
//! (`NAME.pareto.csv`). Error rows (`status` = `error`) and rows with a non-numeric cell in a
//! column used are skipped and counted; PSNR values at the cap of identical images (999 dB)
//! are drawn at the axis' edge, outside its range. Drawing is in [`draw`] (axes and ticks in
//! [`axis`], text from the bundled font in [`font`]), reading the CSV in [`csv`].

pub mod axis;
pub mod csv;
pub mod draw;
pub mod font;
pub mod pareto;
pub mod table;

use crate::config::InputError;
use crate::output::write_atomic;
pub use axis::Scale;
use csv::Csv;
use draw::{Figure, Format};
use pareto::Objective;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Points alone, or joined in x order.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
pub enum Kind {
    #[default]
    Scatter,
    Line,
}

/// A plot asked for by a sweep file: `(x: "gates_total", y: "total_psnr_db", kind: Scatter,
/// pareto: ["gates_total:min", "total_psnr_db:max"], name: "gates-psnr")`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlotSpec {
    pub x: String,
    pub y: String,
    #[serde(default)]
    pub kind: Kind,
    /// Objectives `COLUMN:min` / `COLUMN:max` of the front (none: no front).
    #[serde(default)]
    pub pareto: Vec<String>,
    /// File names in the output directory: `NAME.png`, `NAME.svg` (default `Y-vs-X`).
    #[serde(default)]
    pub name: String,
    /// The axes' ranges and log scales: `x_scale: (range: Some((1.0, 100.0)), log: true)`
    /// (default: the data's range, linear).
    #[serde(default)]
    pub x_scale: Scale,
    #[serde(default)]
    pub y_scale: Scale,
}

impl PlotSpec {
    /// The file name stem: `name`, or `Y-vs-X`; characters other than letters, digits, `.`,
    /// `-` and `_` become `_`.
    pub fn stem(&self) -> String {
        let n = if self.name.is_empty() {
            format!("{}-vs-{}", self.y, self.x)
        } else {
            self.name.clone()
        };
        n.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || "._-".contains(c) {
                    c
                } else {
                    '_'
                }
            })
            .collect()
    }

    pub fn objectives(&self) -> Result<Vec<Objective>, String> {
        self.pareto.iter().map(|s| Objective::parse(s)).collect()
    }
}

/// What to plot from a CSV.
#[derive(Debug, Clone)]
pub struct Request {
    pub x: String,
    pub y: String,
    pub kind: Kind,
    pub objectives: Vec<Objective>,
    pub x_scale: Scale,
    pub y_scale: Scale,
}

/// A plot ready to draw.
#[derive(Debug, Clone)]
pub struct Plot {
    pub figure: Figure,
    /// The rows on the front, as CSV with the header (when objectives were given).
    pub pareto_csv: Option<String>,
    pub plotted: usize,
    pub on_front: usize,
    pub error_rows: usize,
    pub non_numeric: usize,
    /// Rows with a value not above 0 on a log axis (not drawn).
    pub non_positive: usize,
    /// Rows at the PSNR cap (999 dB) left out of an axis and drawn at its edge.
    pub capped: usize,
    /// Rows beyond an axis' given range, drawn at its edge.
    pub beyond: usize,
}

impl Plot {
    /// `plotted 7 rows (3 on the Pareto front); skipped 1 error row, 0 rows with a
    /// non-numeric cell` (and `; N at the PSNR cap ...` when some are).
    pub fn summary(&self) -> String {
        let front = if self.pareto_csv.is_some() {
            format!(" ({} on the Pareto front)", self.on_front)
        } else {
            String::new()
        };
        let capped = match self.capped {
            0 => String::new(),
            n => format!(
                "; {n} at the PSNR cap ({} dB, identical images) drawn at the axis' edge",
                crate::metrics::PSNR_CAP_DB
            ),
        };
        let mut more = String::new();
        if self.non_positive > 0 {
            more += &format!(
                "; skipped {} rows not above 0 on a log axis",
                self.non_positive
            );
        }
        if self.beyond > 0 {
            more += &format!("; {} beyond an axis' range drawn at its edge", self.beyond);
        }
        format!(
            "plotted {} rows{front}; skipped {} error rows, {} rows with a non-numeric \
             cell{capped}{more}",
            self.plotted, self.error_rows, self.non_numeric
        )
    }
}

fn csv_field(f: &str) -> String {
    if f.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", f.replace('"', "\"\""))
    } else {
        f.to_string()
    }
}

fn csv_line(fields: &[String]) -> String {
    fields
        .iter()
        .map(|f| csv_field(f))
        .collect::<Vec<_>>()
        .join(",")
        + "\n"
}

/// Read and parse a CSV file (errors name the file and line).
pub fn read_csv(path: &Path) -> Result<Csv, InputError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError::new(&name, "", format!("cannot read the CSV: {e}")))?;
    Csv::parse(&text).map_err(|(line, m)| InputError::new(&name, "", m).at(Some((line, 1))))
}

/// The cap of a PSNR column (`metrics::PSNR_CAP_DB`, the 999 dB of identical images), which
/// the plot leaves out of the axis' range and draws at its edge.
fn psnr_cap(column: &str) -> Option<f64> {
    column
        .to_ascii_lowercase()
        .contains("psnr")
        .then_some(crate::metrics::PSNR_CAP_DB)
}

/// Select the rows and columns of `req` from `csv` (named `name` in messages).
pub fn prepare(csv: &Csv, name: &str, req: &Request) -> Result<Plot, InputError> {
    let mut used: Vec<&str> = vec![&req.x, &req.y];
    for o in &req.objectives {
        if !used.contains(&o.column.as_str()) {
            used.push(&o.column);
        }
    }
    let cols: Vec<usize> = used
        .iter()
        .map(|c| {
            csv.column(c).ok_or_else(|| {
                InputError::new(
                    name,
                    *c,
                    format!(
                        "no such column: expected one of the header's ({})",
                        csv.header.join(", ")
                    ),
                )
            })
        })
        .collect::<Result<_, _>>()?;
    if csv.rows.is_empty() {
        return Err(InputError::new(
            name,
            "",
            "no rows: expected a header and at least one row",
        ));
    }
    let status = csv.column("status");
    let (mut error_rows, mut non_numeric) = (0, 0);
    let mut numeric_seen = vec![false; cols.len()];
    let mut first_text: Vec<Option<&str>> = vec![None; cols.len()];
    let mut kept: Vec<(usize, Vec<f64>)> = Vec::new();
    for (r, row) in csv.rows.iter().enumerate() {
        if status.is_some_and(|s| row[s] == "error") {
            error_rows += 1;
            continue;
        }
        let mut vals = Vec::with_capacity(cols.len());
        for (k, &c) in cols.iter().enumerate() {
            // NaN, infinities and numbers beyond f64 ("1e999") are not plotted
            match row[c].trim().parse::<f64>() {
                Ok(v) if v.is_finite() => {
                    numeric_seen[k] = true;
                    vals.push(v);
                }
                _ => {
                    let t = first_text[k].get_or_insert(&row[c]);
                    if t.trim().is_empty() {
                        *t = &row[c];
                    }
                }
            }
        }
        if vals.len() == cols.len() {
            kept.push((r, vals));
        } else {
            non_numeric += 1;
        }
    }
    if error_rows < csv.rows.len() {
        if let Some(k) = numeric_seen.iter().position(|s| !s) {
            let m = match first_text[k] {
                Some(t) if !t.trim().is_empty() => {
                    format!("not a numeric column (e.g. {t:?}): expected numbers")
                }
                _ => "every cell is empty: expected numbers".to_string(),
            };
            return Err(InputError::new(name, used[k], m));
        }
    }
    for (scale, field) in [(req.x_scale, "x_scale"), (req.y_scale, "y_scale")] {
        scale
            .check()
            .map_err(|m| InputError::new(name, format!("{field}.range"), m))?;
    }
    // a log axis has no place for 0 or below
    let before = kept.len();
    kept.retain(|(_, v)| (!req.x_scale.log || v[0] > 0.0) && (!req.y_scale.log || v[1] > 0.0));
    let non_positive = before - kept.len();
    if kept.is_empty() {
        return Err(InputError::new(
            name,
            "",
            format!(
                "no row to plot ({error_rows} error rows, {non_numeric} with a non-numeric \
                 cell, {non_positive} not above 0 on a log axis): expected rows with numbers \
                 in {}",
                used.join(", ")
            ),
        ));
    }
    let on: Vec<bool> = if req.objectives.is_empty() {
        vec![false; kept.len()]
    } else {
        let idx: Vec<usize> = req
            .objectives
            .iter()
            .map(|o| used.iter().position(|u| *u == o.column).unwrap())
            .collect();
        let obj: Vec<Vec<f64>> = kept
            .iter()
            .map(|(_, v)| idx.iter().map(|&i| v[i]).collect())
            .collect();
        let dirs: Vec<pareto::Direction> = req.objectives.iter().map(|o| o.direction).collect();
        pareto::front(&obj, &dirs)
    };
    let pareto_csv = (!req.objectives.is_empty()).then(|| {
        let mut s = csv_line(&csv.header);
        for ((r, _), f) in kept.iter().zip(&on) {
            if *f {
                s.push_str(&csv_line(&csv.rows[*r]));
            }
        }
        s
    });
    let mut title = format!("{} vs {}", req.y, req.x);
    if !req.objectives.is_empty() {
        let objs: Vec<String> = req
            .objectives
            .iter()
            .map(|o| {
                let d = match o.direction {
                    pareto::Direction::Min => "min",
                    pareto::Direction::Max => "max",
                };
                format!("{}:{d}", o.column)
            })
            .collect();
        title.push_str(&format!(" (front of {})", objs.join(", ")));
    }
    let figure = Figure {
        title,
        x_label: req.x.clone(),
        y_label: req.y.clone(),
        points: kept
            .iter()
            .zip(&on)
            .map(|((_, v), f)| (v[0], v[1], *f))
            .collect(),
        line: req.kind == Kind::Line,
        pareto: !req.objectives.is_empty(),
        x_cap: psnr_cap(&req.x),
        y_cap: psnr_cap(&req.y),
        x_scale: req.x_scale,
        y_scale: req.y_scale,
    };
    let (capped, beyond) = draw::edge_points(&figure);
    Ok(Plot {
        capped,
        beyond,
        non_positive,
        figure,
        on_front: on.iter().filter(|f| **f).count(),
        plotted: kept.len(),
        pareto_csv,
        error_rows,
        non_numeric,
    })
}

/// `FILE.pareto.csv` beside a plot `FILE.png` / `FILE.svg`.
pub fn pareto_path(out: &Path) -> PathBuf {
    out.with_extension("pareto.csv")
}

/// Draw `plot` into `out` (its extension gives the format) and write its front's rows to
/// [`pareto_path`]; the paths written.
pub fn write(plot: &Plot, out: &Path) -> Result<Vec<PathBuf>, InputError> {
    let out_err = |e: String| InputError::new(out.display().to_string(), "--out", e);
    let format = Format::of(out)
        .ok_or_else(|| out_err("expected a file name ending in .png or .svg".into()))?;
    let bytes = draw::render(&plot.figure, format).map_err(out_err)?;
    write_atomic(out, &bytes).map_err(out_err)?;
    let mut written = vec![out.to_path_buf()];
    if let Some(p) = &plot.pareto_csv {
        let path = pareto_path(out);
        write_atomic(&path, p.as_bytes()).map_err(out_err)?;
        written.push(path);
    }
    Ok(written)
}

/// A sweep's CSV text (of `DIR/sweep.csv`) parsed, and that file's name for messages.
pub fn sweep_csv(csv_text: &str, dir: &Path) -> Result<(Csv, String), InputError> {
    let name = dir.join("sweep.csv").display().to_string();
    let csv =
        Csv::parse(csv_text).map_err(|(l, m)| InputError::new(&name, "", m).at(Some((l, 1))))?;
    Ok((csv, name))
}

/// The plots of a sweep file, from its CSV text: `DIR/NAME.png` and `DIR/NAME.svg` each
/// (and `DIR/NAME.pareto.csv`); one summary line per plot.
pub fn sweep_plots(
    specs: &[PlotSpec],
    csv_text: &str,
    dir: &Path,
) -> Result<Vec<String>, InputError> {
    let (csv, name) = sweep_csv(csv_text, dir)?;
    let mut lines = Vec::new();
    for (k, s) in specs.iter().enumerate() {
        let req = Request {
            x: s.x.clone(),
            y: s.y.clone(),
            kind: s.kind,
            objectives: s
                .objectives()
                .map_err(|e| InputError::new(&name, format!("plots[{k}].pareto"), e))?,
            x_scale: s.x_scale,
            y_scale: s.y_scale,
        };
        let plot = prepare(&csv, &name, &req)?;
        let stem = s.stem();
        for ext in ["png", "svg"] {
            write(&plot, &dir.join(format!("{stem}.{ext}")))?;
        }
        lines.push(format!(
            "{}/{stem}.{{png,svg}}{}: {}",
            dir.display(),
            if plot.pareto_csv.is_some() {
                " and .pareto.csv"
            } else {
                ""
            },
            plot.summary()
        ));
    }
    Ok(lines)
}

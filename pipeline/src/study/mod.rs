//! `bumpsim study PAGE.src.md`: a study page written by hand around the numbers of its sweeps
//! (`docs/studies.md`). The source is Markdown with directives (`{{table ID NAME}}`,
//! `{{value ID EXPR COND...}}`, ... : [`directive`]); the page is the source with each
//! directive replaced by what it names, read from the sweeps' rows, so that a number in a
//! study is a cell of a sweep and the prose is the author's. `{{run}}` runs a sweep as
//! `bumpsim sweep` does; `{{render}}` writes a config's pictures. With `reuse`, the sweeps'
//! rows already in their directories are read instead and nothing is rendered: the page can
//! be checked against its committed sweeps quickly (`tests/study_pages.rs`).

pub mod directive;

use crate::config::{self, InputError};
use crate::output::{encode_png, write_atomic};
use crate::plot::csv::Csv;
use crate::run::{self, RunResult};
use crate::sweep::{self, RunOptions};
use directive::{Aggregate, Directive, Piece};
use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

/// Stands for a directive that writes nothing until its line is judged empty.
const SILENT: char = '\u{0}';

/// How a page is made.
#[derive(Debug, Clone, Copy, Default)]
pub struct Options {
    /// Read the sweeps' rows already written instead of running them; render nothing.
    pub reuse: bool,
    /// Worker threads of the sweeps (default: rayon's).
    pub threads: Option<usize>,
}

/// A sweep of the page: its file, its directory and rows, its tables by name.
struct Swept {
    file: PathBuf,
    out: PathBuf,
    csv: Csv,
    tables: BTreeMap<String, String>,
}

/// `dir/p` with `.` and `a/..` removed (lexically), so that the page names
/// `docs/studies/sweeps/x.ron`, not `docs/studies/./sweeps/x.ron`.
fn join(dir: &Path, p: &str) -> PathBuf {
    let joined = dir.join(p);
    let mut out: Vec<Component> = Vec::new();
    for c in joined.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out.iter().collect()
}

/// The page's path for source `src`: `NAME.src.md` -> `NAME.md`.
pub fn page_of(src: &Path) -> Result<PathBuf, InputError> {
    let name = src.file_name().and_then(|n| n.to_str()).unwrap_or("");
    match name.strip_suffix(".src.md") {
        Some(stem) if !stem.is_empty() => Ok(src.with_file_name(format!("{stem}.md"))),
        _ => Err(InputError::new(
            src.display().to_string(),
            "",
            "expected a page source named NAME.src.md (the page is NAME.md beside it)",
        )),
    }
}

/// The page of source file `src` (not written): its text and the pictures to write.
pub fn expand(src: &Path, opts: Options) -> Result<Expanded, InputError> {
    let name = src.display().to_string();
    let text = std::fs::read_to_string(src)
        .map_err(|e| InputError::new(&name, "", format!("cannot read: {e}")))?;
    // the expander marks the lines of directives that write nothing with NUL (`SILENT`): a
    // source holding one would lose it
    if let Some((l, line)) = text.lines().enumerate().find(|(_, l)| l.contains(SILENT)) {
        let col = line
            .find(SILENT)
            .map_or(1, |c| line[..c].chars().count() + 1);
        return Err(InputError::new(
            &name,
            "",
            "a NUL character: expected Markdown text (no control character NUL)".to_string(),
        )
        .at(Some((l + 1, col))));
    }
    let pieces =
        directive::parse(&text).map_err(|(l, m)| InputError::new(&name, "", m).at(Some((l, 1))))?;
    let dir = src.parent().unwrap_or(Path::new(""));
    let mut page = Page {
        dir: dir.to_path_buf(),
        opts,
        sweeps: BTreeMap::new(),
        runs: Vec::new(),
        pictures: Vec::new(),
    };
    let file_name = src.file_name().map(|n| n.to_string_lossy().to_string());
    let mut out = format!(
        "<!-- generated from {} by `bumpsim study`: edit that file, not this one -->\n",
        file_name.unwrap_or_default()
    );
    for p in &pieces {
        match p {
            Piece::Text(t) => out.push_str(t),
            Piece::Directive(line, d) => {
                let s = page
                    .directive(d)
                    .map_err(|m| InputError::new(&name, "", m).at(Some((*line, 1))))?;
                match s.is_empty() {
                    true => out.push(SILENT),
                    false => out.push_str(&s),
                }
            }
        }
    }
    // a line holding nothing but directives that write nothing is no line of the page
    let text: String = out
        .split_inclusive('\n')
        .filter(|l| !(l.contains(SILENT) && l.chars().all(|c| c == SILENT || c.is_whitespace())))
        .collect::<String>()
        .replace(SILENT, "");
    Ok(Expanded {
        text,
        pictures: page.pictures,
    })
}

/// A page made: its Markdown, and the pictures it renders (path, PNG bytes).
pub struct Expanded {
    pub text: String,
    pub pictures: Vec<(PathBuf, Vec<u8>)>,
}

impl Expanded {
    /// Write the pictures, then the page (each file whole: [`write_atomic`]).
    pub fn write(&self, page: &Path) -> Result<Vec<PathBuf>, InputError> {
        let mut written = Vec::new();
        let files = self
            .pictures
            .iter()
            .map(|(p, b)| (p.as_path(), b.as_slice()))
            .chain(std::iter::once((page, self.text.as_bytes())));
        for (p, bytes) in files {
            if let Some(d) = p.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(d).map_err(|e| {
                    InputError::new(d.display().to_string(), "", format!("cannot create: {e}"))
                })?;
            }
            write_atomic(p, bytes).map_err(|e| InputError::new(p.display().to_string(), "", e))?;
            written.push(p.to_path_buf());
        }
        Ok(written)
    }
}

struct Page {
    dir: PathBuf,
    opts: Options,
    sweeps: BTreeMap<String, Swept>,
    /// The configs rendered so far, with their `--set` lists.
    runs: Vec<((PathBuf, Vec<String>), RunResult)>,
    pictures: Vec<(PathBuf, Vec<u8>)>,
}

impl Page {
    fn directive(&mut self, d: &Directive) -> Result<String, String> {
        match d {
            Directive::Run { file, out } => self.run(file, out).map(|_| String::new()),
            Directive::Cite { id } => {
                let s = self.sweep(id)?;
                let (f, o) = (s.file.display(), s.out.display());
                Ok(format!("`{f}` (`bumpsim sweep {f} --out {o}`)"))
            }
            Directive::Table { id, name } => {
                let s = self.sweep(id)?;
                s.tables.get(name).cloned().ok_or_else(|| {
                    let names: Vec<&str> = s.tables.keys().map(String::as_str).collect();
                    format!(
                        "{id} has no table {name:?}: expected one of its file's tables ({})",
                        names.join(", ")
                    )
                })
            }
            Directive::Number {
                how,
                id,
                groups,
                digits,
            } => {
                let fmt = |x: f64| format_number(x, digits.unwrap_or(2));
                let mut acc = 0.0;
                for g in groups {
                    let vals = self.values(id, &g.expr, &g.conds)?;
                    let v = match how {
                        Aggregate::One => {
                            let first = fmt(vals[0]);
                            if vals.iter().any(|&v| fmt(v) != first) {
                                return Err(format!(
                                    "{} rows of {id} meet the conditions with different {}: \
                                     expected one (add a condition, or use min or max)",
                                    vals.len(),
                                    g.expr
                                ));
                            }
                            vals[0]
                        }
                        Aggregate::Min => vals.iter().copied().fold(f64::INFINITY, f64::min),
                        Aggregate::Max => vals.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                    };
                    acc = match g.op {
                        '-' => acc - v,
                        '*' => acc * v,
                        '/' => acc / v,
                        _ => acc + v,
                    };
                }
                Ok(fmt(acc))
            }
            Directive::Arg {
                max,
                id,
                expr,
                key,
                conds,
            } => {
                let s = self.sweep(id)?;
                let k = s
                    .csv
                    .column(key)
                    .ok_or_else(|| no_column(id, &s.csv, key))?;
                let mut best: Option<(f64, &Vec<String>)> = None;
                for r in rows(s, id, conds)? {
                    let v = eval(&s.csv, r, expr).map_err(|m| format!("{id}: {m}"))?;
                    let better = best.is_none_or(|(b, _)| if *max { v > b } else { v < b });
                    if better {
                        best = Some((v, r));
                    }
                }
                Ok(best.map(|(_, r)| r[k].clone()).unwrap_or_default())
            }
            Directive::Count { id, conds } => {
                let mut n = 0;
                for one in id.split(',') {
                    n += rows(self.sweep(one)?, one, conds).map_or(0, |r| r.len());
                }
                Ok(n.to_string())
            }
            Directive::Text {
                id,
                column,
                conds,
                from,
            } => {
                let s = self.sweep(id)?;
                let k = s
                    .csv
                    .column(column)
                    .ok_or_else(|| no_column(id, &s.csv, column))?;
                let texts: Vec<&str> = rows(s, id, conds)?.iter().map(|r| r[k].as_str()).collect();
                if texts.iter().any(|t| *t != texts[0]) {
                    return Err(format!(
                        "{} rows of {id} meet the conditions with different {column}: expected \
                         one (add a condition)",
                        texts.len()
                    ));
                }
                match from {
                    None => Ok(texts[0].to_string()),
                    Some(m) => texts[0]
                        .find(m.as_str())
                        .map(|at| texts[0][at..].to_string())
                        .ok_or_else(|| format!("{id}: {column} holds no {m:?}: {:?}", texts[0])),
                }
            }
            Directive::Render(r) => {
                if !self.opts.reuse {
                    self.pictures(r)?;
                }
                Ok(String::new())
            }
        }
    }

    /// The pictures of a render directive, added to the page's.
    fn pictures(&mut self, d: &directive::Render) -> Result<(), String> {
        let dir = self.dir.clone();
        let r = self.render(&d.config, &d.sets)?;
        let quantization = d.quantization.as_ref().map(|_| {
            let g = d.gain.unwrap_or(1.0);
            let mut q = r.image.clone();
            for (p, e) in q.pixels_mut().zip(r.exact.pixels()) {
                for c in 0..3 {
                    let diff = (p[c] as f64 - e[c] as f64).abs() * g;
                    p[c] = diff.min(255.0).round() as u8;
                }
            }
            q
        });
        let mut imgs = vec![(&d.image, &r.image)];
        imgs.extend(d.reference.iter().map(|p| (p, &r.reference)));
        imgs.extend(d.exact.iter().map(|p| (p, &r.exact)));
        imgs.extend(d.error.iter().map(|p| (p, &r.error)));
        let q = d.quantization.as_ref().zip(quantization.as_ref());
        imgs.extend(q);
        let mut out = Vec::new();
        let inside = |what: &str, [x, y, w, h]: [u32; 4], img: &image::RgbImage| match x
            .saturating_add(w)
            > img.width()
            || y.saturating_add(h) > img.height()
        {
            true => Err(format!(
                "{what} {x},{y},{w},{h}: outside the {}x{} image of {}",
                img.width(),
                img.height(),
                d.config
            )),
            false => Ok(()),
        };
        for (path, img) in imgs {
            let mut img = img.clone();
            if let Some(m @ [x, y, w, h]) = d.mark {
                inside("mark", m, &img)?;
                for t in 0..w.max(h) {
                    let red = image::Rgb([255, 0, 0]);
                    if t < w {
                        img.put_pixel(x + t, y, red);
                        img.put_pixel(x + t, y + h - 1, red);
                    }
                    if t < h {
                        img.put_pixel(x, y + t, red);
                        img.put_pixel(x + w - 1, y + t, red);
                    }
                }
            }
            if let Some(c @ [x, y, w, h]) = d.crop {
                inside("crop", c, &img)?;
                img = image::imageops::crop_imm(&img, x, y, w, h).to_image();
            }
            if let Some(k) = d.zoom {
                let (w, h) = (img.width() * k, img.height() * k);
                img = image::imageops::resize(&img, w, h, image::imageops::FilterType::Nearest);
            }
            let bytes = encode_png(&img).map_err(|e| format!("{path}: {e}"))?;
            out.push((join(&dir, path), bytes));
        }
        self.pictures.extend(out);
        Ok(())
    }

    /// `expr` of the rows meeting `conds` in the sweeps `id` (one, or several joined by
    /// commas: `ernst-gates-lh-width,ernst-power-table`); at least one row in all.
    fn values(&self, id: &str, expr: &str, conds: &[directive::Cond]) -> Result<Vec<f64>, String> {
        let ids: Vec<&str> = id.split(',').collect();
        let mut vals = Vec::new();
        let mut missing = None;
        for one in &ids {
            let s = self.sweep(one)?;
            match rows(s, one, conds) {
                Ok(rs) => {
                    for r in rs {
                        vals.push(eval(&s.csv, r, expr).map_err(|m| format!("{one}: {m}"))?);
                    }
                }
                Err(m) => missing = Some(m),
            }
        }
        match (vals.is_empty(), missing) {
            (true, Some(m)) if ids.len() == 1 => Err(m),
            (true, _) => Err(format!(
                "no row of {} meets the conditions",
                ids.join(" or ")
            )),
            (false, _) => Ok(vals),
        }
    }

    fn sweep(&self, id: &str) -> Result<&Swept, String> {
        self.sweeps.get(id).ok_or_else(|| {
            format!("no sweep {id:?}: expected a `{{{{run {id}.ron -> DIR}}}}` above it")
        })
    }

    /// Run (or with `reuse`, read) a sweep file into `out`, both relative to the source.
    fn run(&mut self, file: &str, out: &str) -> Result<(), String> {
        let path = join(&self.dir, file);
        let id = path
            .file_stem()
            .map(|s| s.to_string_lossy().to_string())
            .unwrap_or_default();
        if self.sweeps.contains_key(&id) {
            return Err(format!("sweep {id} run twice"));
        }
        let dir = join(&self.dir, out);
        let s = sweep::load(&path).map_err(|e| e.to_string())?;
        let csv_text = if self.opts.reuse {
            let p = dir.join("sweep.csv");
            std::fs::read_to_string(&p).map_err(|e| {
                format!(
                    "cannot read {}: {e} (run the page without reuse)",
                    p.display()
                )
            })?
        } else {
            let opts = RunOptions {
                threads: self.opts.threads,
                ..RunOptions::default()
            };
            sweep::run_into(&s, &dir, opts, false).map_err(|e| e.to_string())?;
            let csv = s.read_table(&dir).map_err(|e| e.to_string())?.to_csv();
            crate::plot::sweep_plots(&s.file.plots, &csv, &dir).map_err(|e| e.to_string())?;
            crate::plot::table::sweep_tables(&s.file.tables, &csv, &dir)
                .map_err(|e| e.to_string())?;
            csv
        };
        let (csv, name) = crate::plot::sweep_csv(&csv_text, &dir).map_err(|e| e.to_string())?;
        if self.opts.reuse {
            s.check_merged(&csv_text).map_err(|m| {
                format!("{name}: {m} (the sweep file changed: run the page without reuse)")
            })?;
        }
        let mut tables = BTreeMap::new();
        for (k, t) in s.file.tables.iter().enumerate() {
            let md = t
                .markdown(&csv, &name, &format!("tables[{k}]"))
                .map_err(|e| e.to_string())?;
            tables.insert(t.name.clone(), md.trim_end().to_string());
        }
        self.sweeps.insert(
            id,
            Swept {
                file: path,
                out: dir,
                csv,
                tables,
            },
        );
        Ok(())
    }

    /// The run of `config` (relative to the source) with `sets`, once per page.
    fn render(&mut self, config: &str, sets: &[String]) -> Result<&RunResult, String> {
        let key = (join(&self.dir, config), sets.to_vec());
        if let Some(k) = self.runs.iter().position(|(k, _)| *k == key) {
            return Ok(&self.runs[k].1);
        }
        let l = config::load(&key.0, sets).map_err(|e| e.to_string())?;
        let r = run::run(&l, None).map_err(|e| e.to_string())?;
        self.runs.push((key, r));
        Ok(&self.runs[self.runs.len() - 1].1)
    }
}

fn no_column(id: &str, csv: &Csv, c: &str) -> String {
    format!(
        "{id} has no column {c:?}: expected one of {}",
        csv.header.join(", ")
    )
}

/// The ok rows of a sweep meeting `conds` ([`directive::Cond`]); at least one.
fn rows<'a>(
    s: &'a Swept,
    id: &str,
    conds: &[directive::Cond],
) -> Result<Vec<&'a Vec<String>>, String> {
    let mut cs = Vec::new();
    for c in conds {
        let k = s.csv.column(&c.column);
        cs.push((k.ok_or_else(|| no_column(id, &s.csv, &c.column))?, c));
    }
    let status = s.csv.column("status");
    let by_status = cs.iter().any(|(k, _)| Some(*k) == status);
    let kept: Vec<&Vec<String>> = s
        .csv
        .rows
        .iter()
        .filter(|r| by_status || status.is_none_or(|k| r[k] == "ok"))
        .filter(|r| cs.iter().all(|(k, c)| c.holds(&r[*k])))
        .collect();
    match kept.is_empty() {
        true => {
            let shown: Vec<String> = conds
                .iter()
                .map(|c| format!("{}{}{}", c.column, op_text(c.op), c.value))
                .collect();
            Err(format!("no row of {id} meets {}", shown.join(" ")))
        }
        false => Ok(kept),
    }
}

fn op_text(op: directive::Cmp) -> &'static str {
    use directive::Cmp::*;
    match op {
        Eq => "=",
        Ne => "!=",
        Lt => "<",
        Le => "<=",
        Gt => ">",
        Ge => ">=",
    }
}

/// `EXPR` of a row: columns and numbers joined by `+`, `*` and `/` (the last two first).
fn eval(csv: &Csv, row: &[String], expr: &str) -> Result<f64, String> {
    let term = |t: &str| -> Result<f64, String> {
        if let Ok(x) = t.parse::<f64>() {
            return Ok(x);
        }
        let k = csv.column(t).ok_or_else(|| {
            format!(
                "{expr}: no column {t:?}: expected numbers and columns ({}) joined by +, * and /",
                csv.header.join(", ")
            )
        })?;
        row[k]
            .parse::<f64>()
            .map_err(|_| format!("{expr}: {t} is {:?} in a row: expected a number", row[k]))
    };
    let mut total = 0.0;
    for sum_term in expr.split('+') {
        let mut x = 1.0;
        let mut op = '*';
        let mut rest = sum_term;
        loop {
            let cut = rest.find(['*', '/']).unwrap_or(rest.len());
            let v = term(rest[..cut].trim())?;
            x = if op == '*' { x * v } else { x / v };
            if cut == rest.len() {
                break;
            }
            op = rest.as_bytes()[cut] as char;
            rest = &rest[cut + 1..];
        }
        total += x;
    }
    Ok(total)
}

/// `x` with `digits` decimals (no `-0`).
fn format_number(x: f64, digits: usize) -> String {
    let s = format!("{x:.digits$}");
    match s
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        true => s.trim_start_matches('-').to_string(),
        false => s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn swept() -> Swept {
        let csv = Csv::parse(
            "index,bits,status,psnr,gates.a,gates.b\n0,6,ok,20.5,100,50\n1,8,ok,30.25,200,60\n\
             2,10,error,,,\n3,12,ok,30.25,400,70\n",
        )
        .unwrap();
        Swept {
            file: "docs/studies/sweeps/s.ron".into(),
            out: "docs/studies/s".into(),
            csv,
            tables: BTreeMap::new(),
        }
    }

    fn page() -> Page {
        let mut p = Page {
            dir: PathBuf::new(),
            opts: Options::default(),
            sweeps: BTreeMap::new(),
            runs: Vec::new(),
            pictures: Vec::new(),
        };
        p.sweeps.insert("s".into(), swept());
        let mut t = swept();
        t.csv.rows[0][4] = "999".into();
        t.csv.rows[1][4] = "1".into();
        p.sweeps.insert("t".into(), t);
        p
    }

    fn go(src: &str) -> Result<String, String> {
        let mut p = page();
        let mut out = String::new();
        for piece in directive::parse(src).map_err(|e| e.1)? {
            match piece {
                Piece::Text(t) => out.push_str(&t),
                Piece::Directive(_, d) => out.push_str(&p.directive(&d)?),
            }
        }
        Ok(out)
    }

    #[test]
    fn numbers_come_from_the_rows_meeting_the_conditions() {
        assert_eq!(go("{{value s psnr bits=8}} dB").unwrap(), "30.25 dB");
        assert_eq!(go("{{value s psnr bits=6 :1}}").unwrap(), "20.5");
        assert_eq!(go("{{value s gates.a+gates.b bits=8 :0}}").unwrap(), "260");
        assert_eq!(
            go("{{value s gates.a/gates.b*3 bits=12 :3}}").unwrap(),
            "17.143"
        );
        assert_eq!(
            go("{{min s gates.a :0}}-{{max s gates.a :0}}").unwrap(),
            "100-400"
        );
        // the error row is left out unless asked for
        assert_eq!(go("{{count s}} {{count s status=error}}").unwrap(), "3 1");
        assert_eq!(
            go("{{argmax s psnr bits}} {{argmin s psnr bits}}").unwrap(),
            "8 6"
        );
        assert_eq!(go("{{value s psnr bits=1*}}").unwrap(), "30.25");
        // rows that agree on the value are one value
        assert_eq!(go("{{value s psnr bits=1* :0}}").unwrap(), "30");
        assert_eq!(
            go("{{text s status bits=10 status=error}}").unwrap(),
            "error"
        );
        assert_eq!(go("{{text s psnr bits=8 :from=.2}}").unwrap(), ".25");
        // two rows: a difference, a ratio
        assert_eq!(go("{{value s psnr bits=8 - psnr bits=6}}").unwrap(), "9.75");
        assert_eq!(
            go("{{value s gates.a bits=12 / gates.a bits=6 :1}}").unwrap(),
            "4.0"
        );
        assert_eq!(
            go("{{cite s}}").unwrap(),
            "`docs/studies/sweeps/s.ron` (`bumpsim sweep docs/studies/sweeps/s.ron --out \
             docs/studies/s`)"
        );
    }

    #[test]
    fn what_cannot_be_answered_is_an_error_naming_what_was_expected() {
        let e = |s: &str| go(s).unwrap_err();
        assert!(
            e("{{value s psnr}}").contains("different psnr"),
            "{}",
            e("{{value s psnr}}")
        );
        assert!(e("{{value s psnr bits=7}}").contains("no row of s meets bits=7"));
        assert_eq!(
            go("{{count s bits>=8}} {{count s bits!=8}}").unwrap(),
            "2 2"
        );
        assert_eq!(go("{{max s gates.a bits<12 :0}}").unwrap(), "200");
        assert!(e("{{value s nope bits=8}}").contains("no column \"nope\""));
        assert!(e("{{value s psnr nope=8}}").contains("no column \"nope\""));
        assert!(e("{{value u psnr}}").contains("no sweep \"u\""));
        assert!(e("{{max s,t psnr bits=7}}").contains("no row of s or t"));
        assert!(e("{{table s x}}").contains("has no table \"x\""));
        assert!(e("{{text s psnr bits=8 :from=x}}").contains("holds no \"x\""));
        assert!(e("{{text s psnr}}").contains("different psnr"));
        assert!(e("{{value s psnr status=error}}").contains("expected a number"));
    }

    #[test]
    fn paths_are_joined_lexically() {
        let p = join(Path::new("docs/studies"), "./sweeps/../gouraud/x.png");
        assert_eq!(p, PathBuf::from("docs/studies/gouraud/x.png"));
        assert_eq!(join(Path::new(""), "../c.ron"), PathBuf::from("../c.ron"));
        assert_eq!(format_number(-0.001, 2), "0.00");
        assert_eq!(
            page_of(Path::new("docs/a.src.md")).unwrap(),
            PathBuf::from("docs/a.md")
        );
        assert!(page_of(Path::new("docs/a.md")).is_err());
    }
}

//! `bumpsim table CSV` and the `tables` of a sweep file (`docs/sweep.md`): chosen columns of a
//! sweep's CSV as a Markdown table, the rows filtered by `COLUMN=VALUE` conditions, numbers
//! with a fixed number of decimals. The studies' tables are these (`docs/studies/sweeps/`),
//! so a number in a study is a cell of a sweep, not of a hand-written program.

use super::csv::Csv;
use crate::config::InputError;
use crate::output::write_atomic;
use serde::Deserialize;
use std::path::Path;

fn two() -> u32 {
    2
}

/// Most decimals of a number.
pub const MAX_DIGITS: u32 = 12;

/// A table asked for by a sweep file: `(name: "dither", columns: ["s_n", "dither",
/// "baseline_psnr_db"], headings: ["s_N", "dither", "PSNR dB"], filter: ["status=ok"],
/// digits: 2)`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableSpec {
    /// The file's stem in the output directory: `NAME.md`.
    pub name: String,
    pub columns: Vec<String>,
    /// One heading per column (default: the column names).
    #[serde(default)]
    pub headings: Vec<String>,
    /// `COLUMN=VALUE` conditions a row must meet (the CSV text of the cell), all of them.
    #[serde(default)]
    pub filter: Vec<String>,
    /// Decimals of a non-integer number (default 2).
    #[serde(default = "two")]
    pub digits: u32,
    /// Decimals for chosen columns instead of `digits`: `[(COLUMN, DIGITS), ...]`, each column
    /// one of `columns` or the pivot's `value` (e.g. KL divergences at 4 and chi-squares at 1
    /// in one table).
    #[serde(default)]
    pub column_digits: Vec<(String, u32)>,
    /// A cross table: one row per distinct combination of `columns` (in first-seen order),
    /// then one column per distinct value of `pivot.over`, holding `pivot.value` of the row
    /// with both (empty where there is none). E.g. engines as columns, angles as rows.
    #[serde(default)]
    pub pivot: Option<Pivot>,
}

/// A cross table's spread column and cell ([`TableSpec::pivot`]).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pivot {
    /// The column whose distinct values (the CSV text, in first-seen order) become columns.
    pub over: String,
    /// The cell shown (a column, or `A+B` as in `columns`).
    pub value: String,
    /// One heading per distinct value of `over`, in order (default: the values).
    #[serde(default)]
    pub headings: Vec<String>,
}

impl Default for TableSpec {
    fn default() -> Self {
        TableSpec {
            name: String::new(),
            columns: Vec::new(),
            headings: Vec::new(),
            filter: Vec::new(),
            digits: two(),
            column_digits: Vec::new(),
            pivot: None,
        }
    }
}

impl TableSpec {
    /// The decimals of column `c`: its `column_digits`, else `digits`.
    fn digits_of(&self, c: &str) -> usize {
        self.column_digits
            .iter()
            .find(|(n, _)| n == c)
            .map_or(self.digits, |(_, d)| *d) as usize
    }

    /// Check the spec against the CSV's header (`name`: the CSV in messages, `field`: where
    /// the spec is, e.g. `tables[0]` or `--columns`).
    fn check(&self, csv: &Csv, name: &str, field: &str) -> Result<Vec<Vec<usize>>, InputError> {
        // a sweep file's `tables[k].columns`, or the command's `--columns` (field "")
        let e = |f: &str, m: String| match field {
            "" => InputError::new(name, format!("--{}", &f[1..]), m),
            _ => InputError::new(name, format!("{field}{f}"), m),
        };
        if self.columns.is_empty() {
            return Err(e(".columns", "expected at least one column".into()));
        }
        if !self.headings.is_empty() && self.headings.len() != self.columns.len() {
            let m = format!(
                "{} headings for {} columns: expected one per column",
                self.headings.len(),
                self.columns.len()
            );
            return Err(e(".headings", m));
        }
        if self.digits > MAX_DIGITS {
            let m = format!("{}: expected 0 to {MAX_DIGITS}", self.digits);
            return Err(e(".digits", m));
        }
        for (c, d) in &self.column_digits {
            let shown =
                self.columns.contains(c) || self.pivot.as_ref().is_some_and(|p| p.value == *c);
            if !shown {
                let m = format!("{c:?}: expected one of the table's columns or its pivot value");
                return Err(e(".column_digits", m));
            }
            if *d > MAX_DIGITS {
                return Err(e(
                    ".column_digits",
                    format!("{c:?}: {d}: expected 0 to {MAX_DIGITS}"),
                ));
            }
        }
        for f in &self.filter {
            let (c, _) = f
                .split_once('=')
                .ok_or_else(|| e(".filter", format!("{f:?}: expected COLUMN=VALUE")))?;
            known(csv, c).map_err(|m| e(".filter", m))?;
        }
        if let Some(p) = &self.pivot {
            known(csv, &p.over).map_err(|m| e(".pivot.over", m))?;
            terms(csv, &p.value).map_err(|m| e(".pivot.value", m))?;
        }
        self.columns
            .iter()
            .map(|c| terms(csv, c).map_err(|m| e(".columns", m)))
            .collect()
    }

    /// The rows of `csv` that meet the filters.
    fn kept<'a>(&self, csv: &'a Csv) -> impl Iterator<Item = &'a Vec<String>> {
        let conds: Vec<(usize, String)> = self
            .filter
            .iter()
            .filter_map(|f| f.split_once('='))
            .filter_map(|(c, v)| Some((csv.column(c)?, v.to_string())))
            .collect();
        csv.rows
            .iter()
            .filter(move |r| conds.iter().all(|(c, v)| r[*c] == *v))
    }

    /// The cross table of [`TableSpec::pivot`] (checked: `cols` the key columns' terms).
    fn cross(
        &self,
        csv: &Csv,
        p: &Pivot,
        cols: &[Vec<usize>],
        name: &str,
        field: &str,
    ) -> Result<String, InputError> {
        let over = csv.column(&p.over).unwrap_or(0);
        let value = terms(csv, &p.value).unwrap_or_default();
        let cell = |r: &Vec<String>, c: &[usize], digits: usize| match c {
            [one] => number(&r[*one], digits),
            _ => number(&sum(c.iter().map(|&k| r[k].as_str())), digits),
        };
        let key_digits: Vec<usize> = self.columns.iter().map(|c| self.digits_of(c)).collect();
        let value_digits = self.digits_of(&p.value);
        let mut spread: Vec<&str> = Vec::new();
        let mut keys: Vec<Vec<String>> = Vec::new();
        let mut cells: std::collections::HashMap<(usize, usize), String> = Default::default();
        for r in self.kept(csv) {
            let key: Vec<String> = cols
                .iter()
                .zip(&key_digits)
                .map(|(c, &d)| cell(r, c, d))
                .collect();
            let ki = keys.iter().position(|k| *k == key).unwrap_or_else(|| {
                keys.push(key);
                keys.len() - 1
            });
            let si = spread
                .iter()
                .position(|v| *v == r[over])
                .unwrap_or_else(|| {
                    spread.push(&r[over]);
                    spread.len() - 1
                });
            cells
                .entry((ki, si))
                .or_insert_with(|| cell(r, &value, value_digits));
        }
        if !p.headings.is_empty() && p.headings.len() != spread.len() {
            let m = format!(
                "{} headings for {} values of {:?} ({}): expected one per value",
                p.headings.len(),
                spread.len(),
                p.over,
                spread.join(", ")
            );
            return Err(InputError::new(name, format!("{field}.pivot.headings"), m));
        }
        let mut heads: Vec<String> = match self.headings.is_empty() {
            true => self.columns.clone(),
            false => self.headings.clone(),
        };
        match p.headings.is_empty() {
            true => heads.extend(spread.iter().map(|v| v.replace('|', "\\|"))),
            false => heads.extend(p.headings.iter().cloned()),
        }
        let mut s = format!("| {} |\n", heads.join(" | "));
        s += &format!("|{}\n", "---|".repeat(heads.len()));
        for (ki, key) in keys.iter().enumerate() {
            let row: Vec<String> = (0..spread.len())
                .map(|si| cells.get(&(ki, si)).cloned().unwrap_or_default())
                .collect();
            s += &format!("| {} | {} |\n", key.join(" | "), row.join(" | "));
        }
        Ok(s)
    }

    /// The Markdown table of `csv`'s rows that meet the filters.
    pub fn markdown(&self, csv: &Csv, name: &str, field: &str) -> Result<String, InputError> {
        let cols = self.check(csv, name, field)?;
        if let Some(p) = &self.pivot {
            return self.cross(csv, p, &cols, name, field);
        }
        let heads = match self.headings.is_empty() {
            true => &self.columns,
            false => &self.headings,
        };
        let digits: Vec<usize> = self.columns.iter().map(|c| self.digits_of(c)).collect();
        let mut s = format!("| {} |\n", heads.join(" | "));
        s += &format!("|{}\n", "---|".repeat(cols.len()));
        for r in self.kept(csv) {
            let cells: Vec<String> = cols
                .iter()
                .zip(&digits)
                .map(|(c, &d)| match c[..] {
                    [one] => number(&r[one], d),
                    _ => number(&sum(c.iter().map(|&k| r[k].as_str())), d),
                })
                .collect();
            s += &format!("| {} |\n", cells.join(" | "));
        }
        Ok(s)
    }
}

/// The tables of a sweep file, from its CSV text: `DIR/NAME.md` each; one line per table.
pub fn sweep_tables(
    specs: &[TableSpec],
    csv_text: &str,
    dir: &Path,
) -> Result<Vec<String>, InputError> {
    let (csv, name) = super::sweep_csv(csv_text, dir)?;
    let mut lines = Vec::new();
    for (k, t) in specs.iter().enumerate() {
        let md = t.markdown(&csv, &name, &format!("tables[{k}]"))?;
        let out = dir.join(format!("{}.md", t.name));
        write_atomic(&out, md.as_bytes()).map_err(|e| {
            InputError::new(out.display().to_string(), "", format!("cannot write: {e}"))
        })?;
        let rows = md.lines().count() - 2;
        lines.push(format!("{}: {rows} rows", out.display()));
    }
    Ok(lines)
}

/// Check a sweep file's tables against its columns (before any point runs): the columns and
/// filters exist, the headings match, the names are file names.
pub fn check_specs(specs: &[TableSpec], columns: &[String], name: &str) -> Result<(), InputError> {
    let csv = Csv {
        header: columns.to_vec(),
        rows: Vec::new(),
    };
    let mut names = std::collections::BTreeSet::new();
    for (k, t) in specs.iter().enumerate() {
        let ok = !t.name.is_empty()
            && t.name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "._-".contains(c))
            && !t.name.starts_with('.');
        if !ok {
            let m = format!(
                "{:?}: expected a file stem of letters, digits, ., - and _",
                t.name
            );
            return Err(InputError::new(name, format!("tables[{k}].name"), m));
        }
        if !names.insert(&t.name) {
            let m = format!("{:?}: two tables of one name", t.name);
            return Err(InputError::new(name, format!("tables[{k}].name"), m));
        }
        t.check(&csv, name, &format!("tables[{k}]"))?;
    }
    Ok(())
}

fn known(csv: &Csv, c: &str) -> Result<usize, String> {
    csv.column(c).ok_or_else(|| {
        format!(
            "{c:?}: no such column: expected one of {}",
            csv.header.join(", ")
        )
    })
}

/// The CSV columns of table column `c`: the column of that name, or for `A+B+...` (no column
/// of that name) the columns summed.
fn terms(csv: &Csv, c: &str) -> Result<Vec<usize>, String> {
    match (csv.column(c), c.contains('+')) {
        (Some(k), _) => Ok(vec![k]),
        (None, true) => c.split('+').map(|t| known(csv, t.trim())).collect(),
        (None, false) => known(csv, c).map(|k| vec![k]),
    }
}

/// The sum of the cells (as CSV text: an integer if all are, empty if any is not a number).
fn sum<'a>(cells: impl Iterator<Item = &'a str>) -> String {
    let (mut int, mut x, mut all_int) = (0i64, 0.0f64, true);
    for c in cells {
        if let Ok(i) = c.parse::<i64>() {
            int = int.saturating_add(i);
            x += i as f64;
            continue;
        }
        match c.parse::<f64>() {
            Ok(v) if v.is_finite() && !c.eq_ignore_ascii_case("nan") => {
                x += v;
                all_int = false;
            }
            _ => return String::new(),
        }
    }
    match all_int {
        true => int.to_string(),
        false => format!("{x:?}"),
    }
}

/// A cell as written: integers and text unchanged, other numbers with `digits` decimals;
/// `|` escaped for Markdown.
fn number(cell: &str, digits: usize) -> String {
    if cell.parse::<i64>().is_ok() {
        return cell.to_string();
    }
    match cell.parse::<f64>() {
        Ok(x) if x.is_finite() && !cell.eq_ignore_ascii_case("nan") => format!("{x:.digits$}"),
        _ => cell.replace('|', "\\|"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv() -> Csv {
        Csv::parse("index,s_n,dither,psnr\n0,16,false,12.345\n1,16,true,11\n2,64,false,x|y\n")
            .unwrap()
    }

    #[test]
    fn a_table_of_chosen_columns_and_filtered_rows() {
        let t = TableSpec {
            name: "t".into(),
            columns: vec!["s_n".into(), "psnr".into()],
            headings: vec!["s_N".into(), "PSNR dB".into()],
            filter: vec!["dither=false".into()],
            digits: 1,
            ..Default::default()
        };
        assert_eq!(
            t.markdown(&csv(), "c.csv", "tables[0]").unwrap(),
            "| s_N | PSNR dB |\n|---|---|\n| 16 | 12.3 |\n| 64 | x\\|y |\n"
        );
        // a column's own decimals
        let t3 = TableSpec {
            column_digits: vec![("psnr".into(), 3)],
            ..t.clone()
        };
        assert_eq!(
            t3.markdown(&csv(), "c.csv", "tables[0]").unwrap(),
            "| s_N | PSNR dB |\n|---|---|\n| 16 | 12.345 |\n| 64 | x\\|y |\n"
        );
        for (c, d, want) in [
            ("nope", 1, "expected one of the table's columns"),
            ("psnr", 99, "expected 0 to"),
        ] {
            let bad = TableSpec {
                column_digits: vec![(c.into(), d)],
                ..t.clone()
            };
            let e = bad.markdown(&csv(), "c.csv", "tables[0]").unwrap_err();
            assert_eq!(e.field, "tables[0].column_digits");
            assert!(e.message.contains(want), "{e}");
        }
    }

    #[test]
    fn a_column_of_several_names_joined_by_plus_is_their_sum() {
        let c = Csv::parse("index,a,b,c\n0,1.25,2,3\n1,4,5,x\n2,6,7,8\n").unwrap();
        let t = TableSpec {
            name: "t".into(),
            columns: vec!["a+b".into(), "b + c".into(), "a+b+c".into()],
            digits: 1,
            ..Default::default()
        };
        assert_eq!(
            t.markdown(&c, "c.csv", "tables[0]").unwrap(),
            "| a+b | b + c | a+b+c |\n|---|---|---|\n| 3.2 | 5 | 6.2 |\n| 9 |  |  |\n| 13 | 15 | 21 |\n"
        );
        let bad = TableSpec {
            columns: vec!["a+nope".into()],
            ..Default::default()
        };
        let e = bad.markdown(&c, "c.csv", "tables[0]").unwrap_err();
        assert_eq!(e.field, "tables[0].columns", "{e}");
    }

    #[test]
    fn a_pivot_spreads_one_column_into_columns() {
        let c = Csv::parse(
            "index,angle,engine,seam\n0,15,visa,1.5\n1,15,sgi,0.25\n2,30,visa,3\n3,30,sgi,0.5\n4,45,visa,7\n",
        )
        .unwrap();
        let t = TableSpec {
            name: "t".into(),
            columns: vec!["angle".into()],
            headings: vec!["angle".into()],
            digits: 1,
            pivot: Some(Pivot {
                over: "engine".into(),
                value: "seam".into(),
                headings: vec!["VISA+".into(), "SGI".into()],
            }),
            ..Default::default()
        };
        assert_eq!(
            t.markdown(&c, "c.csv", "tables[0]").unwrap(),
            "| angle | VISA+ | SGI |\n|---|---|---|\n| 15 | 1.5 | 0.2 |\n| 30 | 3 | 0.5 |\n| 45 | 7 |  |\n"
        );
        let mut bad = t.clone();
        bad.pivot.as_mut().unwrap().headings.pop();
        let e = bad.markdown(&c, "c.csv", "tables[0]").unwrap_err();
        assert_eq!(e.field, "tables[0].pivot.headings", "{e}");
        let mut bad = t;
        bad.pivot.as_mut().unwrap().over = "nope".into();
        let e = bad.markdown(&c, "c.csv", "tables[0]").unwrap_err();
        assert_eq!(e.field, "tables[0].pivot.over", "{e}");
    }

    #[test]
    fn bad_tables_name_the_field() {
        let bad = |t: TableSpec, field: &str| {
            let e = t.markdown(&csv(), "c.csv", "tables[1]").unwrap_err();
            assert_eq!(e.field, field, "{e}");
        };
        let cols = |c: &[&str]| c.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        bad(TableSpec::default(), "tables[1].columns");
        bad(
            TableSpec {
                columns: cols(&["nope"]),
                ..Default::default()
            },
            "tables[1].columns",
        );
        bad(
            TableSpec {
                columns: cols(&["s_n"]),
                headings: cols(&["a", "b"]),
                ..Default::default()
            },
            "tables[1].headings",
        );
        bad(
            TableSpec {
                columns: cols(&["s_n"]),
                filter: cols(&["dither"]),
                ..Default::default()
            },
            "tables[1].filter",
        );
        bad(
            TableSpec {
                columns: cols(&["s_n"]),
                digits: 13,
                ..Default::default()
            },
            "tables[1].digits",
        );
    }
}

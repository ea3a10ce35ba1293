//! The directives of a study page's source (`docs/studies.md`): `{{WORD ARG ...}}` anywhere
//! in the Markdown, arguments separated by blanks, `"..."` an argument with blanks.

/// One directive, as written.
#[derive(Debug, Clone, PartialEq)]
pub enum Directive {
    /// `{{run SWEEP.ron -> DIR}}`: run a sweep file into DIR (its rows, plots and tables);
    /// the sweep is named by its file stem from then on. Writes nothing into the page.
    Run { file: String, out: String },
    /// `{{cite ID}}`: the sweep's file and the command that writes its directory.
    Cite { id: String },
    /// `{{table ID NAME}}`: the sweep file's table NAME, as `bumpsim sweep` writes it.
    Table { id: String, name: String },
    /// `{{value ID EXPR COND... [OP EXPR COND...]... [:D]}}` (and `min`, `max`, of one
    /// group): EXPR of the one row (the least, the greatest over the rows) meeting the
    /// conditions; groups joined by a lone `+`, `-`, `*` or `/`, left to right (a difference
    /// or a ratio of two rows).
    Number {
        how: Aggregate,
        id: String,
        groups: Vec<Group>,
        digits: Option<usize>,
    },
    /// `{{argmin ID EXPR KEY COND...}}` (and `argmax`): the text of column KEY in the row
    /// with the least (greatest) EXPR, the first such row on a tie.
    Arg {
        max: bool,
        id: String,
        expr: String,
        key: String,
        conds: Vec<Cond>,
    },
    /// `{{count ID COND...}}`: how many rows meet the conditions.
    Count { id: String, conds: Vec<Cond> },
    /// `{{text ID COL COND... [:from=MARK]}}`: the text of column COL in the rows meeting
    /// the conditions (they must agree), from the first MARK in it on (an error row's message
    /// without the config and overrides before it).
    Text {
        id: String,
        column: String,
        conds: Vec<Cond>,
        from: Option<String>,
    },
    /// `{{render CONFIG [set=PATH=VALUE]... -> IMAGE.png [OPTION]...}}`: render a config,
    /// write its image and the others asked for ([`Render`]). Writes nothing into the page.
    Render(Render),
}

/// A render's pictures.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Render {
    pub config: String,
    pub sets: Vec<String>,
    /// The engine's (bit-accurate) image.
    pub image: String,
    /// `reference=PNG`: the f64 reference's image.
    pub reference: Option<String>,
    /// `exact=PNG`: the exact mode's image.
    pub exact: Option<String>,
    /// `error=PNG`: the run's error image (as `bumpsim render` writes `error.png`).
    pub error: Option<String>,
    /// `quantization=PNG`: |bit-accurate - exact| per channel, times `gain`.
    pub quantization: Option<String>,
    /// `gain=G` (default 1) of the quantization picture.
    pub gain: Option<f64>,
    /// `crop=X,Y,W,H`: every picture cut to this window.
    pub crop: Option<[u32; 4]>,
    /// `zoom=K`: every picture (after the crop) K x K pixels a pixel.
    pub zoom: Option<u32>,
    /// `mark=X,Y,W,H`: a red 1-pixel frame drawn around this window (before the crop), to
    /// show where another picture's crop is.
    pub mark: Option<[u32; 4]>,
}

/// One operand of a number: `EXPR COND...`, and the operator joining it to the ones before
/// (`+` for the first).
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    pub op: char,
    pub expr: String,
    pub conds: Vec<Cond>,
}

/// Which row(s) a number comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Aggregate {
    One,
    Min,
    Max,
}

/// The pieces of a page: text, and directives with their 1-based line.
#[derive(Debug, Clone, PartialEq)]
pub enum Piece {
    Text(String),
    Directive(usize, Box<Directive>),
}

/// Split a source into text and directives; errors give the 1-based line.
pub fn parse(src: &str) -> Result<Vec<Piece>, (usize, String)> {
    let mut out = Vec::new();
    let mut rest = src;
    let mut line = 1;
    while let Some(k) = rest.find("{{") {
        out.push(Piece::Text(rest[..k].to_string()));
        line += rest[..k].matches('\n').count();
        let body = &rest[k + 2..];
        let Some(e) = body.find("}}") else {
            return Err((line, "`{{` without its closing `}}`".into()));
        };
        let inner = &body[..e];
        out.push(Piece::Directive(
            line,
            Box::new(directive(inner).map_err(|m| (line, m))?),
        ));
        line += inner.matches('\n').count();
        rest = &body[e + 2..];
    }
    if rest.contains("}}") {
        line += rest[..rest.find("}}").unwrap_or(0)].matches('\n').count();
        return Err((line, "`}}` without its opening `{{`".into()));
    }
    out.push(Piece::Text(rest.to_string()));
    Ok(out)
}

/// The arguments of a directive's body (blanks separate, `"..."` keeps them).
fn words(s: &str) -> Result<Vec<String>, String> {
    let mut out = Vec::new();
    let mut chars = s.chars().peekable();
    while let Some(&c) = chars.peek() {
        if c.is_whitespace() {
            chars.next();
            continue;
        }
        let mut w = String::new();
        while let Some(&c) = chars.peek() {
            if c.is_whitespace() {
                break;
            }
            chars.next();
            if c == '"' {
                loop {
                    match chars.next() {
                        Some('"') => break,
                        Some(c) => w.push(c),
                        None => return Err("a `\"` without its closing `\"`".into()),
                    }
                }
            } else {
                w.push(c);
            }
        }
        out.push(w);
    }
    Ok(out)
}

const FORMS: &str = "(COND: COL=VALUE, COL!=VALUE, COL<N, <=, >, >=) run SWEEP.ron -> DIR | cite ID | table ID NAME | value ID EXPR \
                     [COND]... [+|-|*|/ EXPR [COND]...]... [:DIGITS] | min|max ID[,ID]... \
                     EXPR [COND]... [:DIGITS] | argmin|argmax ID EXPR KEY [COND]... | \
                     count ID [COND]... | text ID COL [COND]... [:from=MARK] | render CONFIG [set=PATH=VALUE]... -> PNG \
                     [reference=|exact=|error=|quantization=PNG] [gain=G] [crop=X,Y,W,H] [zoom=K] \
                     [mark=X,Y,W,H]";

/// `:D` at the end of `w`, removed.
fn digits(w: &mut Vec<String>) -> Result<Option<usize>, String> {
    match w.last().and_then(|l| l.strip_prefix(':')) {
        None => Ok(None),
        Some(d) => {
            let n = d
                .parse::<usize>()
                .ok()
                .filter(|&n| n <= 12)
                .ok_or_else(|| format!("{:?}: expected :DIGITS, 0 to 12", w[w.len() - 1]))?;
            w.pop();
            Ok(Some(n))
        }
    }
}

/// A condition on a row: the column, the comparison, the value as written.
#[derive(Debug, Clone, PartialEq)]
pub struct Cond {
    pub column: String,
    pub op: Cmp,
    pub value: String,
}

/// How a cell is compared: `=` (the CSV text, `*` at either end a wildcard), `!=` (not
/// that), or as numbers, `<`, `<=`, `>`, `>=`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cmp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

impl Cond {
    /// `COL=VALUE`, `COL!=VALUE`, `COL<N`, `COL<=N`, `COL>N` or `COL>=N`.
    pub fn parse(c: &str) -> Result<Cond, String> {
        let bad =
            || format!("{c:?}: expected a condition COL=VALUE, COL!=VALUE or COL<N, <=, >, >=");
        let at = c.find(['=', '<', '>', '!']).ok_or_else(bad)?;
        let (column, rest) = c.split_at(at);
        let ops = [
            ("!=", Cmp::Ne),
            ("<=", Cmp::Le),
            (">=", Cmp::Ge),
            ("=", Cmp::Eq),
            ("<", Cmp::Lt),
            (">", Cmp::Gt),
        ];
        let (tok, op) = ops
            .iter()
            .find(|(t, _)| rest.starts_with(t))
            .ok_or_else(bad)?;
        let value = rest[tok.len()..].to_string();
        if column.is_empty() {
            return Err(bad());
        }
        if !matches!(op, Cmp::Eq | Cmp::Ne) && value.parse::<f64>().map_or(true, |x| !x.is_finite())
        {
            return Err(format!("{c:?}: expected a number after {tok}"));
        }
        Ok(Cond {
            column: column.to_string(),
            op: *op,
            value,
        })
    }

    /// Whether a cell (its CSV text) meets the condition.
    pub fn holds(&self, cell: &str) -> bool {
        let text = |v: &str| {
            if let Some(p) = v.strip_suffix('*') {
                cell.starts_with(p)
            } else if let Some(e) = v.strip_prefix('*') {
                cell.ends_with(e)
            } else {
                cell == v
            }
        };
        let num = |f: fn(f64, f64) -> bool| match (cell.parse::<f64>(), self.value.parse::<f64>()) {
            (Ok(a), Ok(b)) => f(a, b),
            _ => false,
        };
        match self.op {
            Cmp::Eq => text(&self.value),
            Cmp::Ne => !text(&self.value),
            Cmp::Lt => num(|a, b| a < b),
            Cmp::Le => num(|a, b| a <= b),
            Cmp::Gt => num(|a, b| a > b),
            Cmp::Ge => num(|a, b| a >= b),
        }
    }
}

/// The conditions among `w`.
fn conds(w: &[String]) -> Result<Vec<Cond>, String> {
    w.iter().map(|c| Cond::parse(c)).collect()
}

fn directive(body: &str) -> Result<Directive, String> {
    let mut w = words(body)?;
    let bad = |m: String| format!("{m}; a directive is one of: {FORMS}");
    if w.is_empty() {
        return Err(bad("an empty directive".into()));
    }
    let word = w.remove(0);
    let need = |n: usize, w: &[String]| match w.len() >= n {
        true => Ok(()),
        false => Err(bad(format!("`{word}` with {} arguments", w.len()))),
    };
    Ok(match word.as_str() {
        "run" => match &w[..] {
            [file, arrow, out] if arrow == "->" => Directive::Run {
                file: file.clone(),
                out: out.clone(),
            },
            _ => return Err(bad("expected `run SWEEP.ron -> DIR`".into())),
        },
        "cite" => match &w[..] {
            [id] => Directive::Cite { id: id.clone() },
            _ => return Err(bad("expected `cite ID`".into())),
        },
        "table" => match &w[..] {
            [id, name] => Directive::Table {
                id: id.clone(),
                name: name.clone(),
            },
            _ => return Err(bad("expected `table ID NAME`".into())),
        },
        "value" | "min" | "max" => {
            let d = digits(&mut w)?;
            need(2, &w)?;
            let mut groups = Vec::new();
            let mut op = '+';
            for part in w[1..].split(|t| ["+", "-", "*", "/"].contains(&t.as_str())) {
                let Some((expr, cs)) = part.split_first() else {
                    return Err(bad(format!(
                        "`{word}`: an operator without EXPR on each side"
                    )));
                };
                groups.push(Group {
                    op,
                    expr: expr.clone(),
                    conds: conds(cs)?,
                });
                let used: usize = groups.iter().map(|g| g.conds.len() + 2).sum();
                op = w.get(used).and_then(|t| t.chars().next()).unwrap_or('+');
            }
            let how = match word.as_str() {
                "value" => Aggregate::One,
                "min" => Aggregate::Min,
                _ => Aggregate::Max,
            };
            if how != Aggregate::One && groups.len() > 1 {
                return Err(bad(format!("`{word}` of one EXPR COND... (no operator)")));
            }
            Directive::Number {
                how,
                id: w[0].clone(),
                groups,
                digits: d,
            }
        }
        "argmin" | "argmax" => {
            need(3, &w)?;
            Directive::Arg {
                max: word == "argmax",
                id: w[0].clone(),
                expr: w[1].clone(),
                key: w[2].clone(),
                conds: conds(&w[3..])?,
            }
        }
        "count" => {
            need(1, &w)?;
            Directive::Count {
                id: w[0].clone(),
                conds: conds(&w[1..])?,
            }
        }
        "text" => {
            let from = match w.last().and_then(|l| l.strip_prefix(":from=")) {
                Some(m) if !m.is_empty() => Some(m.to_string()),
                Some(_) => return Err(bad("`:from=` without a mark".into())),
                None => None,
            };
            if from.is_some() {
                w.pop();
            }
            need(2, &w)?;
            Directive::Text {
                id: w[0].clone(),
                column: w[1].clone(),
                conds: conds(&w[2..])?,
                from,
            }
        }
        "render" => render(&w).map_err(bad)?,
        _ => return Err(bad(format!("unknown directive `{word}`"))),
    })
}

fn render(w: &[String]) -> Result<Directive, String> {
    let arrow = w
        .iter()
        .position(|a| a == "->")
        .ok_or("expected `render CONFIG [set=PATH=VALUE]... -> PNG ...`")?;
    let (Some(config), Some(image)) = (w.first(), w.get(arrow + 1)) else {
        return Err("expected `render CONFIG [set=PATH=VALUE]... -> PNG ...`".into());
    };
    let mut sets = Vec::new();
    for s in &w[1..arrow] {
        match s.strip_prefix("set=") {
            Some(v) => sets.push(v.to_string()),
            None => return Err(format!("{s:?}: expected set=PATH=VALUE before `->`")),
        }
    }
    let mut r = Render {
        config: config.clone(),
        sets,
        image: image.clone(),
        ..Render::default()
    };
    for o in &w[arrow + 2..] {
        match o.split_once('=') {
            Some(("reference", p)) => r.reference = Some(p.to_string()),
            Some(("exact", p)) => r.exact = Some(p.to_string()),
            Some(("error", p)) => r.error = Some(p.to_string()),
            Some(("quantization", p)) => r.quantization = Some(p.to_string()),
            Some(("gain", g)) => match g.parse::<f64>() {
                Ok(g) if g.is_finite() && g > 0.0 && g <= 1e6 => r.gain = Some(g),
                _ => return Err(format!("{o:?}: expected gain=G, above 0 and at most 1e6")),
            },
            Some(("zoom", k)) => match k.parse::<u32>() {
                Ok(k) if (1..=16).contains(&k) => r.zoom = Some(k),
                _ => return Err(format!("{o:?}: expected zoom=K, 1 to 16")),
            },
            Some((k @ ("crop" | "mark"), c)) => {
                let v: Vec<u32> = c.split(',').filter_map(|n| n.parse().ok()).collect();
                let window = match v[..] {
                    [x, y, w, h] if w > 0 && h > 0 => [x, y, w, h],
                    _ => return Err(format!("{o:?}: expected {k}=X,Y,W,H, W and H above 0")),
                };
                match k {
                    "crop" => r.crop = Some(window),
                    _ => r.mark = Some(window),
                }
            }
            _ => {
                return Err(format!(
                    "{o:?}: expected reference=, exact=, error=, quantization= (a PNG), \
                     gain=G, crop=X,Y,W,H, mark=X,Y,W,H or zoom=K after the image"
                ))
            }
        }
    }
    Ok(Directive::Render(r))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_and_directives_with_their_lines() {
        let p = parse("a\n{{table s t}} b\n\n{{value s x+y k=\"a b\" :3}}").unwrap();
        assert_eq!(p.len(), 5);
        assert_eq!(
            p[1],
            Piece::Directive(
                2,
                Box::new(Directive::Table {
                    id: "s".into(),
                    name: "t".into()
                })
            )
        );
        assert_eq!(
            p[3],
            Piece::Directive(
                4,
                Box::new(Directive::Number {
                    how: Aggregate::One,
                    id: "s".into(),
                    groups: vec![Group {
                        op: '+',
                        expr: "x+y".into(),
                        conds: vec![Cond::parse("k=a b").unwrap()],
                    }],
                    digits: Some(3)
                })
            )
        );
        assert_eq!(p[4], Piece::Text(String::new()));
    }

    #[test]
    fn render_options() {
        let p = parse("{{render ../c.ron set=a.b=3 -> x.png reference=r.png crop=1,2,3,4 zoom=4}}");
        let Ok(p) = p else { panic!("{p:?}") };
        assert_eq!(
            p[1],
            Piece::Directive(
                1,
                Box::new(Directive::Render(Render {
                    config: "../c.ron".into(),
                    sets: vec!["a.b=3".into()],
                    image: "x.png".into(),
                    reference: Some("r.png".into()),
                    crop: Some([1, 2, 3, 4]),
                    zoom: Some(4),
                    ..Render::default()
                }))
            )
        );
    }

    #[test]
    fn errors_name_the_line_and_what_was_expected() {
        let e = |s: &str| parse(s).unwrap_err();
        assert_eq!(e("a\nb {{table s}}").0, 2);
        assert!(e("a\nb {{table s}}").1.contains("expected `table ID NAME`"));
        assert!(e("{{frob}}").1.contains("unknown directive `frob`"));
        assert!(e("x\n\n{{value s").1.contains("without its closing"));
        assert_eq!(e("x\n\n{{value s").0, 3);
        assert!(e("x }} y").1.contains("without its opening"));
        assert!(e("{{value s x :99}}").1.contains("0 to 12"));
        assert!(e("{{value s x bad}}").1.contains("COL=VALUE"));
        assert!(e("{{value s x a<b}}").1.contains("a number after <"));
        assert!(e("{{value s x =3}}").1.contains("COL=VALUE"));
        assert!(e("{{render c.ron -> x.png crop=1,2,0,4}}")
            .1
            .contains("above 0"));
        assert!(e("{{render c.ron oops -> x.png}}")
            .1
            .contains("set=PATH=VALUE"));
        assert!(e("{{cite \"s}}").1.contains("closing"));
        assert!(e("{{}}").1.contains("empty"));
        assert!(e("{{value s x a=1 - }}").1.contains("operator without"));
        assert!(e("{{min s x a=1 - x a=2}}").1.contains("no operator"));
    }
}

#[cfg(test)]
mod cond_tests {
    use super::*;

    #[test]
    fn conditions_compare_text_or_numbers() {
        let c = |s: &str, cell: &str| Cond::parse(s).unwrap().holds(cell);
        assert!(c("a=x*", "xyz") && c("a=*z", "xyz") && !c("a=x", "xyz"));
        assert!(c("a!=x", "xyz") && !c("a!=x*", "xyz"));
        assert!(c("a>=15", "15") && c("a>=15", "20.5") && !c("a>=15", "10"));
        assert!(c("a<15", "-3") && !c("a<15", "15") && c("a<=15", "15"));
        assert!(c("a>1e3", "1001") && !c("a>1", "text") && !c("a>1", ""));
        assert_eq!(Cond::parse("b!=").unwrap().value, "");
        // the first operator splits: a value may hold more
        assert_eq!(Cond::parse("k=a=b").unwrap().value, "a=b");
    }
}

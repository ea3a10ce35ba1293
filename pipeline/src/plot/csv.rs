//! Reading a sweep's CSV (`sweep.csv`, `docs/sweep.md`): a header, then one line per row;
//! fields with commas or quotes are quoted, `""` a quote inside.

/// A CSV table: the header and the rows' fields.
#[derive(Debug, Clone, PartialEq)]
pub struct Csv {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

/// The fields of one line.
fn fields(line: &str) -> Result<Vec<String>, String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    let mut start = true;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (false, '"') if start => quoted = true,
            (true, '"') if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            (true, '"') => quoted = false,
            (false, ',') => {
                out.push(std::mem::take(&mut cur));
                start = true;
                continue;
            }
            (_, c) => cur.push(c),
        }
        start = false;
    }
    if quoted {
        return Err("a quoted field without its closing quote".into());
    }
    out.push(cur);
    Ok(out)
}

impl Csv {
    /// Parse CSV text; errors name the 1-based line.
    pub fn parse(text: &str) -> Result<Csv, (usize, String)> {
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let Some((_, head)) = lines.next() else {
            return Err((1, "empty: expected a header line and rows".into()));
        };
        let header = fields(head).map_err(|e| (1, e))?;
        let mut rows = Vec::new();
        for (k, l) in lines {
            let f = fields(l).map_err(|e| (k + 1, e))?;
            if f.len() != header.len() {
                return Err((
                    k + 1,
                    format!(
                        "{} fields: expected {} as in the header",
                        f.len(),
                        header.len()
                    ),
                ));
            }
            rows.push(f);
        }
        Ok(Csv { header, rows })
    }

    /// The position of a column.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoted_fields_and_bad_lines() {
        let c = Csv::parse("a,b,c\n1,\"x, \"\"y\"\"\",\n").unwrap();
        assert_eq!(c.rows[0], ["1", "x, \"y\"", ""]);
        assert_eq!(c.column("c"), Some(2));
        assert_eq!(Csv::parse("a,b\n1\n").unwrap_err().0, 2);
        assert!(Csv::parse("").is_err());
        assert!(Csv::parse("a\n\"x\n").is_err());
    }
}

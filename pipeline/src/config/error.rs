//! Errors about user input: configs, files, values. Each names the file, where it can the line
//! and column, the field, and what was expected. The command line exits with code 2 on them.

use std::fmt;

#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    /// The file the error is about (a config, a PNG, an OBJ), or `--set` for overrides.
    pub file: String,
    /// 1-based line and column, where known.
    pub pos: Option<(usize, usize)>,
    /// Dotted path of the field, e.g. `engine.units[2].unit.Dot3.out.format.width`.
    pub field: String,
    /// What was wrong and what was expected.
    pub message: String,
}

impl InputError {
    pub fn new(
        file: impl Into<String>,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        InputError {
            file: file.into(),
            pos: None,
            field: field.into(),
            message: message.into(),
        }
    }
    pub fn at(mut self, pos: Option<(usize, usize)>) -> Self {
        self.pos = pos;
        self
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some((l, c)) = self.pos {
            write!(f, ":{l}:{c}")?;
        }
        if !self.field.is_empty() {
            write!(f, ": {}", self.field)?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for InputError {}

/// 1-based line and column of the first occurrence of `needle` in `text` outside comments.
pub fn locate(text: &str, needle: &str) -> Option<(usize, usize)> {
    let at = mask_comments(text).find(needle)?;
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = at - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    Some((line, col))
}

/// `text` with RON comments (`// ...` and `/* ... */`, not inside strings) blanked out, so
/// positions stay the same.
fn mask_comments(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = b.to_vec();
    let (mut i, mut in_str) = (0, false);
    while i < b.len() {
        if in_str {
            if b[i] == b'\\' {
                i += 1;
            } else if b[i] == b'"' {
                in_str = false;
            }
            i += 1;
        } else if b[i] == b'"' {
            in_str = true;
            i += 1;
        } else if b[i..].starts_with(b"//") {
            while i < b.len() && b[i] != b'\n' {
                out[i] = b' ';
                i += 1;
            }
        } else if b[i..].starts_with(b"/*") {
            let end = text[i + 2..].find("*/").map_or(b.len(), |e| i + 2 + e + 2);
            for c in &mut out[i..end] {
                if *c != b'\n' {
                    *c = b' ';
                }
            }
            i = end;
        } else {
            i += 1;
        }
    }
    // only ASCII bytes were replaced, by ASCII spaces, at ASCII positions or inside comments
    String::from_utf8(out).unwrap_or_else(|_| text.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locate_finds_line_and_column() {
        assert_eq!(locate("a\nbc name: \"x\"\n", "name: \"x\""), Some((2, 4)));
        assert_eq!(locate("abc", "z"), None);
        assert_eq!(
            locate("// lights here\n  lights: [", "lights"),
            Some((2, 3))
        );
        assert_eq!(locate("/* a:\n b: */ a: 1", "a:"), Some((2, 8)));
        // a "//" inside a string is not a comment: the string stays searchable
        assert_eq!(locate("(s: \"// x:\", x: 1)", "x:"), Some((1, 9)));
        let e = InputError::new("c.ron", "scene.width", "expected 1 to 16384, found 0")
            .at(Some((3, 5)));
        assert_eq!(
            e.to_string(),
            "c.ron:3:5: scene.width: expected 1 to 16384, found 0"
        );
    }
}

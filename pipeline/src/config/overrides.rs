//! `--set path.to.field=value` overrides.
//!
//! The parsed config is turned into a JSON tree, each override replaces one node, and the tree
//! is parsed back (so every check that parsing does applies to overridden values too).
//! Path segments are field names; a list element is chosen by index (`units[2]` or `units.2`)
//! or by its `name` field (`units.dot`); an enum variant's fields can be reached without naming
//! the variant (`unit.index_bits` for `unit: PowerTable(index_bits: 8, ...)`). Values are RON:
//! numbers, `true`/`false`, strings, lists, and bare identifiers for unit enum variants
//! (`filter=Nearest`).

use super::{Config, InputError};
use serde_json::Value;

/// Apply overrides to a config.
pub fn apply(config: &Config, sets: &[String]) -> Result<Config, InputError> {
    let mut tree = serde_json::to_value(config).expect("a config serialises to JSON");
    for set in sets {
        let err = |field: &str, msg: String| InputError::new("--set", field, msg);
        let (path, value) = set
            .split_once('=')
            .ok_or_else(|| err("", format!("{set:?}: expected path.to.field=value")))?;
        let value = parse_value(value).map_err(|m| err(path, m))?;
        let segments = split_path(path);
        if segments.is_empty() {
            return Err(err(path, "empty path: expected path.to.field=value".into()));
        }
        let node = walk(&mut tree, &segments).map_err(|m| err(path, m))?;
        *node = value;
    }
    let result: Result<Config, _> = serde_path_to_error::deserialize(tree);
    result.map_err(|e| InputError::new("--set", e.path().to_string(), e.into_inner().to_string()))
}

fn split_path(path: &str) -> Vec<String> {
    path.replace('[', ".")
        .replace(']', "")
        .split('.')
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .collect()
}

fn parse_value(text: &str) -> Result<Value, String> {
    let t = text.trim();
    if !t.is_empty()
        && t.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && t.starts_with(|c: char| c.is_ascii_alphabetic())
        && t != "true"
        && t != "false"
    {
        return Ok(Value::String(t.to_string()));
    }
    ron::from_str::<Value>(t).map_err(|e| format!("value {t:?} is not a RON value: {e}"))
}

fn walk<'a>(mut node: &'a mut Value, segments: &[String]) -> Result<&'a mut Value, String> {
    for (depth, seg) in segments.iter().enumerate() {
        if step(node, seg).is_none() {
            let here = segments[..depth].join(".");
            let known = match &*node {
                Value::Object(m) => m.keys().cloned().collect::<Vec<_>>().join(", "),
                Value::Array(a) => format!("an index below {} or an element name", a.len()),
                _ => "nothing (a value, not a structure)".into(),
            };
            return Err(format!(
                "no field {seg:?} under {:?}: expected one of {known}",
                if here.is_empty() { "(top)" } else { &here }
            ));
        }
        node = step(node, seg).expect("checked above");
    }
    Ok(node)
}

fn step<'a>(node: &'a mut Value, seg: &str) -> Option<&'a mut Value> {
    match node {
        Value::Array(items) => {
            if let Ok(i) = seg.parse::<usize>() {
                return items.get_mut(i);
            }
            items
                .iter_mut()
                .find(|it| it.get("name").and_then(Value::as_str) == Some(seg))
        }
        Value::Object(map) => {
            if map.contains_key(seg) {
                return map.get_mut(seg);
            }
            // an externally tagged enum variant: {"Variant": {...}}
            if map.len() == 1 {
                let inner = map.values_mut().next()?;
                return step(inner, seg);
            }
            None
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_split_on_dots_and_brackets() {
        assert_eq!(
            split_path("engine.units[2].unit.index_bits"),
            ["engine", "units", "2", "unit", "index_bits"]
        );
    }

    #[test]
    fn values_parse_as_ron_or_identifiers() {
        assert_eq!(parse_value("12").unwrap(), Value::from(12));
        assert_eq!(parse_value("Nearest").unwrap(), Value::from("Nearest"));
        assert_eq!(parse_value("true").unwrap(), Value::from(true));
        assert_eq!(parse_value("[1, 2]").unwrap(), serde_json::json!([1, 2]));
        assert!(parse_value("(").is_err());
    }

    #[test]
    fn walk_finds_named_elements_and_enum_fields() {
        let mut v = serde_json::json!({"units": [{"name": "a", "unit": {"Pow": {"bits": 4}}}]});
        *walk(&mut v, &split_path("units.a.unit.bits")).unwrap() = Value::from(6);
        assert_eq!(v["units"][0]["unit"]["Pow"]["bits"], 6);
        let e = walk(&mut v, &split_path("units.b")).unwrap_err();
        assert!(e.contains("no field \"b\""), "{e}");
    }
}

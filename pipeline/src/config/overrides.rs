//! `--set path.to.field=value` overrides.
//!
//! The parsed config is turned into a JSON tree, each override replaces one node, and the tree
//! is parsed back (so every check that parsing does applies to overridden values too).
//! Path segments are field names; a list element is chosen by index (`units[2]` or `units.2`)
//! or by its `name` field (`units.dot`); an enum variant's fields can be reached without naming
//! the variant (`unit.index_bits` for `unit: PowerTable(index_bits: 8, ...)`). Values are RON,
//! enum variants included (`filter=Nearest`, `scene.bump=Bricks(rows: 8, ...)`,
//! `scene.lights=[(kind: Directional(dir: (1, 1, 1)), color: (1, 1, 1))]`). A value nests at
//! most [`MAX_DEPTH`] levels deep (a config needs about ten).

use super::{Config, InputError};
use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::Value;

/// Deepest nesting of values in an override value (a value inside `n` brackets is at level
/// `n + 1`), the limit RON sets on a config file.
pub const MAX_DEPTH: usize = 128;

/// Apply overrides to a config. Its numbers must be finite: the overrides go through a JSON
/// tree, which has no NaN or infinity.
pub fn apply(config: &Config, sets: &[String]) -> Result<Config, InputError> {
    if let Some((field, x)) = super::finite::first_non_finite(config) {
        return Err(InputError::new(
            "the config",
            field,
            format!("expected a finite number, found {x} (before the --set overrides)"),
        ));
    }
    apply_to(config, sets)
}

/// [`apply`] for any schema that goes through JSON (e.g. an NV2A frame, `crate::nv2a`): the
/// same paths, values and messages. A number that JSON cannot hold (NaN, infinity) comes back
/// as a type error at its field.
pub fn apply_to<T: Serialize + DeserializeOwned>(
    config: &T,
    sets: &[String],
) -> Result<T, InputError> {
    let mut tree = serde_json::to_value(config).expect("a config serialises to JSON");
    // the paths where `None` was set over a string (see below)
    let mut nones: Vec<Vec<String>> = Vec::new();
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
        if walk(&mut tree, &segments).is_err() {
            add_default_field::<T>(&mut tree, &segments);
        }
        if let Err(m) = walk(&mut tree, &segments) {
            return Err(err(path, schema_fields::<T>(&tree, &segments).unwrap_or(m)));
        }
        let node = walk(&mut tree, &segments).map_err(|m| err(path, m))?;
        // `None` over an enum variant (a string in the tree, e.g. `raster.cull`) is the
        // variant named None, not an absent option; unless the schema has no such variant
        // there (an `Option` of an enum, e.g. `mipmap: Some(NearestToAverage)`), see below
        *node = match (&*node, value) {
            (Value::String(_), Value::Null) => {
                nones.push(segments.clone());
                Value::String("None".into())
            }
            (_, v) => v,
        };
    }
    // the tree is copied for a second try only when a `None` may have to be read back
    let retry = (!nones.is_empty()).then(|| tree.clone());
    let e = match serde_path_to_error::deserialize::<_, T>(tree) {
        Ok(c) => return Ok(c),
        Err(e) => e,
    };
    // an Option of an enum: `None` is the absent option after all
    if let Some(mut tree) = retry {
        for segs in &nones {
            if let Ok(node) = walk(&mut tree, segs) {
                *node = Value::Null;
            }
        }
        if let Ok(c) = serde_path_to_error::deserialize::<_, T>(tree) {
            return Ok(c);
        }
    }
    Err(InputError::new(
        "--set",
        e.path().to_string(),
        e.into_inner().to_string(),
    ))
}

/// A field at its default may be left out of the config's tree (`skip_serializing_if`, so
/// that new fields keep old configs' hashes): add the last segment of `segments` under its
/// parent (inside the parent's enum variant, if it is one) when the schema accepts a field of
/// that name there. Otherwise leave the tree as it is, for [`walk`]'s error.
fn add_default_field<T: DeserializeOwned>(tree: &mut Value, segments: &[String]) {
    let Some((last, parent)) = segments.split_last() else {
        return;
    };
    // the schema knows the field if a value of no type it could take is rejected for another
    // reason than an unknown field (structures that ignore unknown keys accept it)
    let mut probe = tree.clone();
    let Some(m) = field_map(&mut probe, parent) else {
        return;
    };
    m.insert(last.clone(), serde_json::json!({ "\u{0}not a value": 0 }));
    let unknown = format!("unknown field `{last}`");
    let known = match serde_json::from_value::<T>(probe) {
        Err(e) => !e.to_string().contains(&unknown),
        Ok(_) => false,
    };
    if known {
        if let Some(m) = field_map(tree, parent) {
            m.insert(last.clone(), Value::Null);
        }
    }
}

/// The message for a path the tree does not hold, with every field the schema accepts where
/// the path leaves the tree (the tree leaves out fields at their default, so its own keys are
/// not all of them): serde's list of expected fields, when a structure is there.
fn schema_fields<T: DeserializeOwned>(tree: &Value, segments: &[String]) -> Option<String> {
    let mut probe = tree.clone();
    let depth = (1..=segments.len()).find(|&d| walk(&mut probe, &segments[..d]).is_err())?;
    let (parent, seg) = (&segments[..depth - 1], &segments[depth - 1]);
    field_map(&mut probe, parent)?.insert(seg.clone(), Value::Null);
    let e = serde_json::from_value::<T>(probe).err()?.to_string();
    let unknown = format!("unknown field `{seg}`, ");
    let at = e.find(&unknown)? + unknown.len();
    let expected = e[at..].split(" at line").next().unwrap_or_default();
    let here = parent.join(".");
    Some(format!(
        "no field {seg:?} under {:?}: {expected}",
        if here.is_empty() { "(top)" } else { &here }
    ))
}

/// The fields of the structure at `parent`: the object itself, or the fields of the enum
/// variant it holds (`{"Variant": {fields}}`).
fn field_map<'a>(
    tree: &'a mut Value,
    parent: &[String],
) -> Option<&'a mut serde_json::Map<String, Value>> {
    let node = walk(tree, parent).ok()?;
    let variant = matches!(&*node, Value::Object(m) if m.len() == 1
    && m.iter().next().is_some_and(|(k, v)| {
        k.starts_with(|c: char| c.is_ascii_uppercase()) && v.is_object()
    }));
    let node = if variant {
        node.as_object_mut()?.values_mut().next()?
    } else {
        node
    };
    node.as_object_mut()
}

fn split_path(path: &str) -> Vec<String> {
    path.replace('[', ".")
        .replace(']', "")
        .split('.')
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .collect()
}

/// An override value for a message: whole if short, otherwise its start and its length.
fn shown(text: &str) -> String {
    const SHOWN: usize = 60;
    if text.len() <= SHOWN {
        return format!("{text:?}");
    }
    let cut = (0..=SHOWN)
        .rev()
        .find(|&i| text.is_char_boundary(i))
        .unwrap_or(0);
    format!("{:?}... ({} bytes)", &text[..cut], text.len())
}

fn parse_value(text: &str) -> Result<Value, String> {
    let mut p = RonValue {
        s: text.as_bytes(),
        i: 0,
        depth: 0,
    };
    let v = p
        .value()
        .map_err(|m| format!("value {} is not a RON value: {m}", shown(text)))?;
    p.ws();
    if p.i != p.s.len() {
        return Err(format!(
            "value {} is not a RON value: unexpected text at byte {}",
            shown(text),
            p.i
        ));
    }
    Ok(v)
}

/// A small RON reader for override values that keeps enum variant names, in serde's externally
/// tagged form (what the JSON tree of a config holds): `Name` is `"Name"`, `Name(x)` is
/// `{"Name": x}`, `Name(a: 1)` is `{"Name": {"a": 1}}`, `(a: 1)` is `{"a": 1}`, `(1, 2)` and
/// `[1, 2]` are lists, `Some(x)` is `x` and `None` is `null`.
struct RonValue<'a> {
    s: &'a [u8],
    i: usize,
    /// Brackets open around the value being read.
    depth: usize,
}

impl RonValue<'_> {
    fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }
    fn peek(&mut self) -> Option<u8> {
        self.ws();
        self.s.get(self.i).copied()
    }
    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    fn ident(&mut self) -> String {
        let start = self.i;
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_')
        {
            self.i += 1;
        }
        String::from_utf8_lossy(&self.s[start..self.i]).into_owned()
    }
    /// A value; each bracket it opens counts toward [`MAX_DEPTH`].
    fn value(&mut self) -> Result<Value, String> {
        if self.depth >= MAX_DEPTH {
            return Err(format!(
                "nested more than {MAX_DEPTH} levels deep at byte {} (expected at most {MAX_DEPTH})",
                self.i
            ));
        }
        self.depth += 1;
        let v = self.value_inner();
        self.depth -= 1;
        v
    }
    fn value_inner(&mut self) -> Result<Value, String> {
        match self.peek().ok_or("unexpected end")? {
            b'"' => {
                let start = self.i;
                self.i += 1;
                while self.i < self.s.len() && self.s[self.i] != b'"' {
                    self.i += if self.s[self.i] == b'\\' { 2 } else { 1 };
                }
                self.i += 1;
                let lit = std::str::from_utf8(&self.s[start..self.i.min(self.s.len())])
                    .map_err(|e| e.to_string())?;
                serde_json::from_str(lit).map_err(|e| format!("bad string {lit}: {e}"))
            }
            b'[' => {
                self.i += 1;
                Ok(Value::Array(self.items(b']')?))
            }
            b'{' => {
                // a map (RON's `{"key": value}`, also the JSON form of the config tree)
                self.i += 1;
                let mut m = serde_json::Map::new();
                loop {
                    if self.eat(b'}') {
                        return Ok(Value::Object(m));
                    }
                    let k = match self.value()? {
                        Value::String(k) => k,
                        other => other.to_string(),
                    };
                    if !self.eat(b':') {
                        return Err(format!("expected ':' at byte {}", self.i));
                    }
                    let v = self.value()?;
                    m.insert(k, v);
                    if !self.eat(b',') && self.peek() != Some(b'}') {
                        return Err(format!("expected ',' or '}}' at byte {}", self.i));
                    }
                }
            }
            b'(' => {
                self.i += 1;
                self.group()
            }
            c if c.is_ascii_alphabetic() => {
                let name = self.ident();
                match name.as_str() {
                    "true" => return Ok(Value::Bool(true)),
                    "false" => return Ok(Value::Bool(false)),
                    "None" => return Ok(Value::Null),
                    "NaN" | "inf" => return Err(format!("{name} is not allowed in an override")),
                    _ => {}
                }
                if !self.eat(b'(') {
                    return Ok(Value::String(name));
                }
                let inner = self.group()?;
                if name == "Some" {
                    return Ok(inner);
                }
                let mut m = serde_json::Map::new();
                m.insert(name, inner);
                Ok(Value::Object(m))
            }
            _ => {
                let start = self.i;
                while self.i < self.s.len()
                    && (self.s[self.i].is_ascii_alphanumeric() || b"+-.".contains(&self.s[self.i]))
                {
                    self.i += 1;
                }
                let lit = std::str::from_utf8(&self.s[start..self.i]).map_err(|e| e.to_string())?;
                serde_json::from_str::<serde_json::Number>(lit)
                    .map(Value::Number)
                    .map_err(|_| format!("bad number {lit:?}"))
            }
        }
    }
    /// After `(`: named fields make an object, a single value is itself, several a list.
    fn group(&mut self) -> Result<Value, String> {
        let save = self.i;
        self.ws();
        let key = self.ident();
        if !key.is_empty() && self.eat(b':') {
            self.i = save;
            let mut m = serde_json::Map::new();
            loop {
                if self.eat(b')') {
                    return Ok(Value::Object(m));
                }
                self.ws();
                let k = self.ident();
                if k.is_empty() || !self.eat(b':') {
                    return Err(format!("expected a field name and ':' at byte {}", self.i));
                }
                let v = self.value()?;
                m.insert(k, v);
                if !self.eat(b',') && self.peek() != Some(b')') {
                    return Err(format!("expected ',' or ')' at byte {}", self.i));
                }
            }
        }
        self.i = save;
        let mut items = self.items(b')')?;
        Ok(if items.len() == 1 {
            items.pop().expect("one item")
        } else {
            Value::Array(items)
        })
    }
    fn items(&mut self, close: u8) -> Result<Vec<Value>, String> {
        let mut v = Vec::new();
        loop {
            if self.eat(close) {
                return Ok(v);
            }
            v.push(self.value()?);
            if !self.eat(b',') && self.peek() != Some(close) {
                return Err(format!(
                    "expected ',' or '{}' at byte {}",
                    close as char, self.i
                ));
            }
        }
    }
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

    /// The bundled config `configs/{name}`, parsed.
    fn bundled(name: &str) -> Config {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../configs")
            .join(name);
        super::super::parse(&std::fs::read_to_string(path).unwrap(), name).unwrap()
    }

    #[test]
    fn none_over_an_enum_variant_is_the_variant_named_none() {
        let c = bundled("cull-fragment.ron");
        assert_eq!(c.raster.cull, crate::raster::Cull::Back);
        let set = apply(&c, &["raster.cull=None".to_string()]).unwrap();
        assert_eq!(set.raster.cull, crate::raster::Cull::None);
        // but an Option of an enum without a None variant: the absent option
        let c = bundled("quantized-plane-mipmap.ron");
        let mip = |c: &Config| match &c.engine.units[0].unit {
            crate::engine::units::UnitSpec::QuantizedNormals(q) => q.mipmap,
            _ => panic!("the unit is qnm"),
        };
        assert!(mip(&c).is_some());
        let set = apply(&c, &["engine.units.qnm.unit.mipmap=None".to_string()]).unwrap();
        assert_eq!(mip(&set), None);
        // a wrong name is still the first error
        let e = apply(&c, &["engine.units.qnm.unit.mipmap=Nothing".to_string()]).unwrap_err();
        assert!(e.message.contains("Nothing"), "{e}");
    }

    #[test]
    fn fields_left_out_at_their_default_can_be_set() {
        let c = bundled("sgi-teapot.ron");
        let set = |s: &str| apply(&c, &[s.to_string()]);
        let fixed = set("engine.interpolator=Fixed(weight_bits: 12)").unwrap();
        assert_eq!(
            fixed.engine.interpolator,
            super::super::Interpolator::Fixed { weight_bits: 12 }
        );
        // inside an enum variant: TexFetch's address
        let clamp = set("engine.units.fetch.unit.address=Clamp").unwrap();
        assert_ne!(clamp.engine.units[0].unit, c.engine.units[0].unit);
        // a name the schema does not know is still an error naming what exists
        let e = set("engine.interpolatr=Exact").unwrap_err();
        assert!(e.to_string().contains("no field \"interpolatr\""), "{e}");
        let e = set("engine.units.fetch.unit.adress=Clamp").unwrap_err();
        assert!(e.to_string().contains("no field \"adress\""), "{e}");
    }

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
        let light =
            parse_value("[(kind: Directional(dir: (1.0, 0.5, 1.0)), color: (1, 1, 1))]").unwrap();
        assert_eq!(
            light,
            serde_json::json!([{"kind": {"Directional": {"dir": [1.0, 0.5, 1.0]}}, "color": [1, 1, 1]}])
        );
        assert_eq!(
            parse_value("Png(\"a.png\")").unwrap(),
            serde_json::json!({"Png": "a.png"})
        );
        assert_eq!(parse_value("Some(2.5)").unwrap(), serde_json::json!(2.5));
        assert_eq!(
            parse_value("(format: (signed: true, width: 8, frac: 7), codec: UnitSigned)").unwrap(),
            serde_json::json!({"format": {"signed": true, "width": 8, "frac": 7}, "codec": "UnitSigned"})
        );
        assert!(parse_value("(a: 1").is_err());
        assert_eq!(
            parse_value("{\"c\": \"g\", \"b\": [1]}").unwrap(),
            serde_json::json!({"c": "g", "b": [1]})
        );
    }

    #[test]
    fn values_nest_at_most_max_depth_levels() {
        let nested = |n: usize| format!("{}1{}", "[".repeat(n), "]".repeat(n));
        assert!(parse_value(&nested(MAX_DEPTH - 1)).is_ok());
        let e = parse_value(&nested(MAX_DEPTH)).unwrap_err();
        assert!(e.contains("nested more than 128 levels"), "{e}");
        // far deeper than the stack would take without the limit
        let e = parse_value(&"(".repeat(1_000_000)).unwrap_err();
        assert!(e.contains("nested more than"), "{e}");
        // the message shows the start of a long value, not all of it
        assert!(e.contains("... (1000000 bytes)") && e.len() < 300, "{e}");
    }

    #[test]
    fn a_misspelt_field_lists_the_fields_left_out_at_their_default_too() {
        let c = bundled("sgi-teapot.ron");
        let e = apply(&c, &["reference.highlight_lum=0.5".to_string()]).unwrap_err();
        let m = e.to_string();
        assert!(
            m.contains("no field \"highlight_lum\" under \"reference\""),
            "{m}"
        );
        for f in [
            "`perturbation`",
            "`samples`",
            "`highlight_luma`",
            "`synthesis`",
        ] {
            assert!(m.contains(f), "{f} in {m}");
        }
        // and a field at its default is set
        let set = apply(&c, &["reference.highlight_luma=0.5".to_string()]).unwrap();
        assert_eq!(set.reference.highlight_luma, Some(0.5));
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

//! Every number in a config is finite: [`first_non_finite`] finds a NaN or an infinity (RON
//! reads `NaN`, `inf`, and `1e400` as infinity) anywhere in a config, with the path of its
//! field in the form of the parse errors (`scene.bump.Bricks.depth`,
//! `scene.lights[0].kind.Directional.dir[0]`).
//!
//! It is a serializer that only looks at floats: the config's own `Serialize` walks every
//! field (those left out of the canonical form at their default excepted, which are finite
//! defaults), so no field can be forgotten.

use serde::ser::{self, Impossible, Serialize};
use std::fmt;

/// The path and value of the first NaN or infinite number in `value`, in field order.
pub fn first_non_finite<T: Serialize + ?Sized>(value: &T) -> Option<(String, f64)> {
    match value.serialize(Finder(String::new())) {
        Err(Stop::Found(path, x)) => Some((path, x)),
        _ => None,
    }
}

/// Why the walk stopped.
#[derive(Debug)]
enum Stop {
    Found(String, f64),
    Other(String),
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stop::Found(p, x) => write!(f, "{p}: {x}"),
            Stop::Other(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for Stop {}

impl ser::Error for Stop {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        Stop::Other(msg.to_string())
    }
}

fn field(path: &str, name: &str) -> String {
    if path.is_empty() {
        name.to_string()
    } else {
        format!("{path}.{name}")
    }
}

/// Walks a value at `self.0`, the path so far.
struct Finder(String);

/// The elements or fields of a compound value at `path`.
struct Compound {
    path: String,
    index: usize,
    key: String,
}

impl Compound {
    fn new(path: String) -> Self {
        Compound {
            path,
            index: 0,
            key: String::new(),
        }
    }
    fn element<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Stop> {
        let at = format!("{}[{}]", self.path, self.index);
        self.index += 1;
        v.serialize(Finder(at))
    }
    fn field<T: Serialize + ?Sized>(&mut self, name: &str, v: &T) -> Result<(), Stop> {
        v.serialize(Finder(field(&self.path, name)))
    }
}

macro_rules! plain {
    ($($method:ident($ty:ty);)*) => {$(
        fn $method(self, _: $ty) -> Result<(), Stop> {
            Ok(())
        }
    )*};
}

impl ser::Serializer for Finder {
    type Ok = ();
    type Error = Stop;
    type SerializeSeq = Compound;
    type SerializeTuple = Compound;
    type SerializeTupleStruct = Compound;
    type SerializeTupleVariant = Compound;
    type SerializeMap = Compound;
    type SerializeStruct = Compound;
    type SerializeStructVariant = Compound;

    plain! {
        serialize_bool(bool);
        serialize_i8(i8);
        serialize_i16(i16);
        serialize_i32(i32);
        serialize_i64(i64);
        serialize_i128(i128);
        serialize_u8(u8);
        serialize_u16(u16);
        serialize_u32(u32);
        serialize_u64(u64);
        serialize_u128(u128);
        serialize_char(char);
        serialize_str(&str);
        serialize_bytes(&[u8]);
        serialize_unit_struct(&'static str);
    }

    fn serialize_f32(self, x: f32) -> Result<(), Stop> {
        self.serialize_f64(f64::from(x))
    }
    fn serialize_f64(self, x: f64) -> Result<(), Stop> {
        if x.is_finite() {
            Ok(())
        } else {
            Err(Stop::Found(self.0, x))
        }
    }
    fn serialize_none(self) -> Result<(), Stop> {
        Ok(())
    }
    fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> Result<(), Stop> {
        v.serialize(self)
    }
    fn serialize_unit(self) -> Result<(), Stop> {
        Ok(())
    }
    fn serialize_unit_variant(self, _: &'static str, _: u32, _: &'static str) -> Result<(), Stop> {
        Ok(())
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        v: &T,
    ) -> Result<(), Stop> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        v: &T,
    ) -> Result<(), Stop> {
        v.serialize(Finder(field(&self.0, variant)))
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Compound, Stop> {
        Ok(Compound::new(self.0))
    }
    fn serialize_tuple(self, _: usize) -> Result<Compound, Stop> {
        Ok(Compound::new(self.0))
    }
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Compound, Stop> {
        Ok(Compound::new(self.0))
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        _: usize,
    ) -> Result<Compound, Stop> {
        Ok(Compound::new(field(&self.0, variant)))
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Compound, Stop> {
        Ok(Compound::new(self.0))
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Compound, Stop> {
        Ok(Compound::new(self.0))
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        _: usize,
    ) -> Result<Compound, Stop> {
        Ok(Compound::new(field(&self.0, variant)))
    }
}

impl ser::SerializeSeq for Compound {
    type Ok = ();
    type Error = Stop;
    fn serialize_element<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Stop> {
        self.element(v)
    }
    fn end(self) -> Result<(), Stop> {
        Ok(())
    }
}

impl ser::SerializeTuple for Compound {
    type Ok = ();
    type Error = Stop;
    fn serialize_element<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Stop> {
        self.element(v)
    }
    fn end(self) -> Result<(), Stop> {
        Ok(())
    }
}

impl ser::SerializeTupleStruct for Compound {
    type Ok = ();
    type Error = Stop;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Stop> {
        self.element(v)
    }
    fn end(self) -> Result<(), Stop> {
        Ok(())
    }
}

impl ser::SerializeTupleVariant for Compound {
    type Ok = ();
    type Error = Stop;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Stop> {
        self.element(v)
    }
    fn end(self) -> Result<(), Stop> {
        Ok(())
    }
}

impl ser::SerializeMap for Compound {
    type Ok = ();
    type Error = Stop;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, k: &T) -> Result<(), Stop> {
        // map keys of a config are strings; anything else is named `?`
        self.key = k.serialize(KeyName).unwrap_or_else(|_| "?".into());
        Ok(())
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Stop> {
        let key = std::mem::take(&mut self.key);
        self.field(&key, v)
    }
    fn end(self) -> Result<(), Stop> {
        Ok(())
    }
}

impl ser::SerializeStruct for Compound {
    type Ok = ();
    type Error = Stop;
    fn serialize_field<T: Serialize + ?Sized>(
        &mut self,
        name: &'static str,
        v: &T,
    ) -> Result<(), Stop> {
        self.field(name, v)
    }
    fn end(self) -> Result<(), Stop> {
        Ok(())
    }
}

impl ser::SerializeStructVariant for Compound {
    type Ok = ();
    type Error = Stop;
    fn serialize_field<T: Serialize + ?Sized>(
        &mut self,
        name: &'static str,
        v: &T,
    ) -> Result<(), Stop> {
        self.field(name, v)
    }
    fn end(self) -> Result<(), Stop> {
        Ok(())
    }
}

/// A map key as text: strings only.
struct KeyName;

macro_rules! not_a_key {
    ($($method:ident($($arg:ty),*) -> $out:ty;)*) => {$(
        fn $method(self, $(_: $arg),*) -> Result<$out, Stop> {
            Err(Stop::Other("not a string key".into()))
        }
    )*};
}

impl ser::Serializer for KeyName {
    type Ok = String;
    type Error = Stop;
    type SerializeSeq = Impossible<String, Stop>;
    type SerializeTuple = Impossible<String, Stop>;
    type SerializeTupleStruct = Impossible<String, Stop>;
    type SerializeTupleVariant = Impossible<String, Stop>;
    type SerializeMap = Impossible<String, Stop>;
    type SerializeStruct = Impossible<String, Stop>;
    type SerializeStructVariant = Impossible<String, Stop>;

    fn serialize_str(self, s: &str) -> Result<String, Stop> {
        Ok(s.to_string())
    }

    not_a_key! {
        serialize_bool(bool) -> String;
        serialize_i8(i8) -> String;
        serialize_i16(i16) -> String;
        serialize_i32(i32) -> String;
        serialize_i64(i64) -> String;
        serialize_u8(u8) -> String;
        serialize_u16(u16) -> String;
        serialize_u32(u32) -> String;
        serialize_u64(u64) -> String;
        serialize_f32(f32) -> String;
        serialize_f64(f64) -> String;
        serialize_char(char) -> String;
        serialize_bytes(&[u8]) -> String;
        serialize_none() -> String;
        serialize_unit() -> String;
        serialize_unit_struct(&'static str) -> String;
        serialize_unit_variant(&'static str, u32, &'static str) -> String;
        serialize_seq(Option<usize>) -> Self::SerializeSeq;
        serialize_tuple(usize) -> Self::SerializeTuple;
        serialize_tuple_struct(&'static str, usize) -> Self::SerializeTupleStruct;
        serialize_tuple_variant(&'static str, u32, &'static str, usize)
            -> Self::SerializeTupleVariant;
        serialize_map(Option<usize>) -> Self::SerializeMap;
        serialize_struct(&'static str, usize) -> Self::SerializeStruct;
        serialize_struct_variant(&'static str, u32, &'static str, usize)
            -> Self::SerializeStructVariant;
    }

    fn serialize_some<T: Serialize + ?Sized>(self, _: &T) -> Result<String, Stop> {
        Err(Stop::Other("not a string key".into()))
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        v: &T,
    ) -> Result<String, Stop> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<String, Stop> {
        Err(Stop::Other("not a string key".into()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[derive(serde::Serialize)]
    enum E {
        V { x: [f64; 2] },
        N(Option<f64>),
    }

    #[derive(serde::Serialize)]
    struct S {
        a: f64,
        list: Vec<E>,
        map: BTreeMap<String, f32>,
    }

    #[test]
    fn finds_the_first_non_finite_number_with_its_path() {
        let mut s = S {
            a: 1.0,
            list: vec![E::N(None), E::V { x: [0.0, 2.0] }],
            map: BTreeMap::from([("k".to_string(), 1.0)]),
        };
        assert_eq!(first_non_finite(&s), None);
        s.map.insert("k".into(), f32::INFINITY);
        assert_eq!(first_non_finite(&s), Some(("map.k".into(), f64::INFINITY)));
        s.list[1] = E::V {
            x: [0.0, f64::NEG_INFINITY],
        };
        assert_eq!(
            first_non_finite(&s),
            Some(("list[1].V.x[1]".into(), f64::NEG_INFINITY))
        );
        s.list[0] = E::N(Some(f64::NAN));
        let (path, x) = first_non_finite(&s).unwrap();
        assert!(path == "list[0].N" && x.is_nan(), "{path} {x}");
        s.a = f64::NAN;
        assert_eq!(first_non_finite(&s).unwrap().0, "a");
    }
}

//! A unit spec is a struct of its own (in its file) but is written in a config as a struct
//! variant of [`super::UnitSpec`]: `Dot3(count: 2, out: ...)`, not the newtype form
//! `Dot3((count: 2, out: ...))`. These adapters run the struct's derived `Serialize` and
//! `Deserialize` as that struct variant, so a format sees exactly the calls of a derived struct
//! variant (`serialize_struct_variant` and its fields; `struct_variant` after the tag): the RON
//! text, the canonical config and its hash, the `--set` JSON tree and the error messages are
//! those of the struct variant.

use serde::de::{self, VariantAccess, Visitor};
use serde::ser::{self, Impossible, Serialize, SerializeStruct, SerializeStructVariant};

const NOT_A_STRUCT: &str = "a unit spec is a struct";

/// Serializes a struct as variant `variant` (number `index`) of enum `name`.
pub(super) struct AsVariant<S> {
    pub ser: S,
    pub name: &'static str,
    pub index: u32,
    pub variant: &'static str,
}

/// The struct's fields, written as the variant's.
pub(super) struct Fields<V>(V);

impl<V: SerializeStructVariant> SerializeStruct for Fields<V> {
    type Ok = V::Ok;
    type Error = V::Error;
    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        value: &T,
    ) -> Result<(), V::Error> {
        self.0.serialize_field(key, value)
    }
    fn skip_field(&mut self, key: &'static str) -> Result<(), V::Error> {
        self.0.skip_field(key)
    }
    fn end(self) -> Result<V::Ok, V::Error> {
        self.0.end()
    }
}

/// Every shape but a struct is refused.
macro_rules! refuse {
    ($($method:ident($($arg:ty),*) -> $out:ty;)*) => {$(
        fn $method(self, $(_: $arg),*) -> Result<$out, S::Error> {
            Err(ser::Error::custom(NOT_A_STRUCT))
        }
    )*};
}

impl<S: ser::Serializer> ser::Serializer for AsVariant<S> {
    type Ok = S::Ok;
    type Error = S::Error;
    type SerializeStruct = Fields<S::SerializeStructVariant>;
    type SerializeSeq = Impossible<S::Ok, S::Error>;
    type SerializeTuple = Impossible<S::Ok, S::Error>;
    type SerializeTupleStruct = Impossible<S::Ok, S::Error>;
    type SerializeTupleVariant = Impossible<S::Ok, S::Error>;
    type SerializeMap = Impossible<S::Ok, S::Error>;
    type SerializeStructVariant = Impossible<S::Ok, S::Error>;

    fn serialize_struct(
        self,
        _: &'static str,
        len: usize,
    ) -> Result<Self::SerializeStruct, S::Error> {
        self.ser
            .serialize_struct_variant(self.name, self.index, self.variant, len)
            .map(Fields)
    }

    refuse! {
        serialize_bool(bool) -> S::Ok;
        serialize_i8(i8) -> S::Ok;
        serialize_i16(i16) -> S::Ok;
        serialize_i32(i32) -> S::Ok;
        serialize_i64(i64) -> S::Ok;
        serialize_u8(u8) -> S::Ok;
        serialize_u16(u16) -> S::Ok;
        serialize_u32(u32) -> S::Ok;
        serialize_u64(u64) -> S::Ok;
        serialize_f32(f32) -> S::Ok;
        serialize_f64(f64) -> S::Ok;
        serialize_char(char) -> S::Ok;
        serialize_str(&str) -> S::Ok;
        serialize_bytes(&[u8]) -> S::Ok;
        serialize_none() -> S::Ok;
        serialize_unit() -> S::Ok;
        serialize_unit_struct(&'static str) -> S::Ok;
        serialize_unit_variant(&'static str, u32, &'static str) -> S::Ok;
        serialize_seq(Option<usize>) -> Self::SerializeSeq;
        serialize_tuple(usize) -> Self::SerializeTuple;
        serialize_tuple_struct(&'static str, usize) -> Self::SerializeTupleStruct;
        serialize_tuple_variant(&'static str, u32, &'static str, usize)
            -> Self::SerializeTupleVariant;
        serialize_map(Option<usize>) -> Self::SerializeMap;
        serialize_struct_variant(&'static str, u32, &'static str, usize)
            -> Self::SerializeStructVariant;
    }

    fn serialize_some<T: ?Sized + Serialize>(self, _: &T) -> Result<S::Ok, S::Error> {
        Err(ser::Error::custom(NOT_A_STRUCT))
    }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: &T,
    ) -> Result<S::Ok, S::Error> {
        Err(ser::Error::custom(NOT_A_STRUCT))
    }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<S::Ok, S::Error> {
        Err(ser::Error::custom(NOT_A_STRUCT))
    }
}

/// Deserializes a struct from the struct variant whose tag was just read.
pub(super) struct FromVariant<A>(pub A);

impl<'de, A: VariantAccess<'de>> de::Deserializer<'de> for FromVariant<A> {
    type Error = A::Error;

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, A::Error> {
        self.0.struct_variant(fields, visitor)
    }

    fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, A::Error> {
        Err(de::Error::custom(NOT_A_STRUCT))
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
        ignored_any
    }
}

#[cfg(test)]
mod tests {
    use super::super::UnitSpec;

    const MODULATE: &str = "Modulate(out:(format:(signed:false,width:8,frac:0),codec:UnitUnsigned,quant:Rnd,overflow:Sat))";

    #[test]
    fn a_spec_is_written_as_a_struct_variant() {
        let spec: UnitSpec = ron::from_str(MODULATE).unwrap();
        assert!(matches!(spec, UnitSpec::Modulate(_)));
        assert_eq!(ron::to_string(&spec).unwrap(), MODULATE);
        let json = serde_json::to_value(&spec).unwrap();
        assert_eq!(json["Modulate"]["out"]["format"]["width"], 8);
        assert_eq!(serde_json::from_value::<UnitSpec>(json).unwrap(), spec);
    }

    #[test]
    fn the_newtype_form_and_unknown_tags_are_refused() {
        let newtype = MODULATE.replacen('(', "((", 1) + ")";
        assert!(ron::from_str::<UnitSpec>(&newtype).is_err());
        let e = ron::from_str::<UnitSpec>(&MODULATE.replacen("Modulate", "Modulat", 1))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`Modulat`") && e.contains("`EmbossFilter`"),
            "{e}"
        );
    }
}

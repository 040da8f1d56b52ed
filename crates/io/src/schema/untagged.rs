//! `Deserialize` of the scenario file's values that take several forms ([`Param`],
//! [`LayerRef`]). serde's `untagged` would try each form and, when a table has a misspelt
//! key, say only that no form matched; reading by the value's kind instead passes the
//! table's own error on, which names the key and the keys the table takes.

use super::{LayerRef, Param, VectorLayer, VectorParam};
use serde::Deserialize;
use serde::de::{self, Deserializer, MapAccess, Visitor};
use std::fmt;

struct ParamVisitor;

impl<'de> Visitor<'de> for ParamVisitor {
    type Value = Param;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number, a raster path or a table { vector, field, layer }")
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Param, E> {
        Ok(Param::Num(v))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Param, E> {
        Ok(Param::Num(v as f64))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Param, E> {
        Ok(Param::Num(v as f64))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Param, E> {
        Ok(Param::Path(v.to_owned()))
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Param, A::Error> {
        VectorParam::deserialize(de::value::MapAccessDeserializer::new(map)).map(Param::Vector)
    }
}

impl<'de> Deserialize<'de> for Param {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Param, D::Error> {
        d.deserialize_any(ParamVisitor)
    }
}

struct LayerVisitor;

impl<'de> Visitor<'de> for LayerVisitor {
    type Value = LayerRef;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a file path or a table { vector, layer }")
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<LayerRef, E> {
        Ok(LayerRef::Path(v.to_owned()))
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<LayerRef, A::Error> {
        VectorLayer::deserialize(de::value::MapAccessDeserializer::new(map)).map(LayerRef::Vector)
    }
}

impl<'de> Deserialize<'de> for LayerRef {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<LayerRef, D::Error> {
        d.deserialize_any(LayerVisitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    struct T {
        p: Param,
        l: Option<LayerRef>,
    }

    fn read(text: &str) -> Result<T, String> {
        toml::from_str(text).map_err(|e| e.to_string())
    }

    #[test]
    fn each_form_is_read() {
        let t = read("p = 2\nl = \"r.geojson\"").expect("ok");
        assert!(matches!(t.p, Param::Num(v) if v == 2.0));
        assert!(matches!(t.l, Some(LayerRef::Path(ref p)) if p == "r.geojson"));
        let t = read("p = 0.5\n").expect("ok");
        assert!(matches!(t.p, Param::Num(v) if v == 0.5));
        let t = read("p = \"rg.asc\"\nl = { vector = \"a.gpkg\", layer = \"x\" }").expect("ok");
        assert!(matches!(t.p, Param::Path(ref p) if p == "rg.asc"));
        assert!(
            matches!(t.l, Some(LayerRef::Vector(ref v)) if v.vector == "a.gpkg" && v.layer.as_deref() == Some("x"))
        );
        let t = read("p = { vector = \"s.shp\", field = \"rg\" }").expect("ok");
        assert!(matches!(t.p, Param::Vector(ref v) if v.field == "rg" && v.layer.is_none()));
    }

    #[test]
    fn a_misspelt_key_of_a_table_is_named() {
        let e = read("p = 1\nl = { vector = \"r.geojson\", layr = \"a\" }").unwrap_err();
        assert!(
            e.contains("unknown field `layr`") && e.contains("`layer`"),
            "{e}"
        );
        let e = read("p = { vector = \"s.shp\", feild = \"rg\" }").unwrap_err();
        assert!(
            e.contains("unknown field `feild`") && e.contains("`field`"),
            "{e}"
        );
        let e = read("p = true").unwrap_err();
        assert!(e.contains("a number, a raster path or a table"), "{e}");
    }
}

//! GeoJSON layers (RFC 7946) with the `geojson` crate. The CRS is the legacy `crs` member
//! (`{"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::2154"}}`) that GDAL
//! writes for any CRS but WGS 84; without it a file is in OGC:CRS84 (RFC 7946 §4).

use super::{Feature, Geometry, Layer, Value, VectorError, Xy, epsg_of_name};
use ::geojson::{GeoJson, GeometryValue, JsonObject, JsonValue, Position, feature::Id};
use rockfall_raster::Crs;
use std::path::Path;

/// A GeoJSON file's bytes → its one layer (named after the file stem).
pub fn parse_geojson(bytes: &[u8], path: &Path) -> Result<Layer, VectorError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|_| VectorError::file(path, "not UTF-8 text, so not GeoJSON"))?;
    let json: GeoJson = text
        .parse()
        .map_err(|e| VectorError::file(path, format!("not GeoJSON: {e}")))?;
    let name = (path.file_stem())
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let (features, members) = match json {
        GeoJson::FeatureCollection(fc) => (fc.features, fc.foreign_members),
        GeoJson::Feature(f) => (vec![f], None),
        GeoJson::Geometry(g) => (
            vec![::geojson::Feature {
                bbox: None,
                geometry: Some(g),
                id: None,
                properties: None,
                foreign_members: None,
            }],
            None,
        ),
    };
    let mut layer = Layer {
        path: path.to_path_buf(),
        name,
        crs: Some(crs_of(members.as_ref(), path)?),
        within: None,
        features: Vec::with_capacity(features.len()),
    };
    for (index, f) in features.into_iter().enumerate() {
        let id = match &f.id {
            Some(Id::Number(n)) => n.as_i64().unwrap_or(index as i64),
            _ => index as i64,
        };
        let geometry = match f.geometry {
            None => Geometry::Empty,
            Some(g) => geometry(&g.value).map_err(|m| VectorError::feature(&layer, id, m))?,
        };
        let attributes = f.properties.map(attributes).unwrap_or_default();
        layer.features.push(Feature {
            id,
            geometry,
            attributes,
        });
    }
    Ok(layer)
}

fn crs_of(members: Option<&JsonObject>, path: &Path) -> Result<Crs, VectorError> {
    let Some(crs) = members.and_then(|m| m.get("crs")) else {
        return Ok(Crs::from_epsg(4326));
    };
    let name = crs.pointer("/properties/name").and_then(JsonValue::as_str);
    match name.and_then(epsg_of_name) {
        Some(code) => Ok(Crs::from_epsg(code)),
        None => Err(VectorError::file(
            path,
            format!("the `crs` member {crs} names no EPSG code"),
        )),
    }
}

fn attributes(properties: JsonObject) -> Vec<(String, Value)> {
    (properties.into_iter())
        .map(|(k, v)| {
            let value = match v {
                JsonValue::Number(n) => n.as_f64().map(Value::Num).unwrap_or(Value::Null),
                JsonValue::String(s) => Value::Text(s),
                JsonValue::Bool(b) => Value::Num(f64::from(u8::from(b))),
                JsonValue::Null => Value::Null,
                other => Value::Text(other.to_string()),
            };
            (k, value)
        })
        .collect()
}

fn xy(p: &Position) -> Result<Xy, String> {
    match p.as_slice() {
        [x, y, ..] if x.is_finite() && y.is_finite() => Ok([*x, *y]),
        [_, _, ..] => Err("a coordinate is not a finite number".into()),
        _ => Err("a position with fewer than two coordinates".into()),
    }
}

fn line(ps: &[Position]) -> Result<Vec<Xy>, String> {
    ps.iter().map(xy).collect()
}

fn polygon(rings: &[Vec<Position>]) -> Result<Vec<Vec<Xy>>, String> {
    rings.iter().map(|r| line(r)).collect()
}

fn geometry(g: &GeometryValue) -> Result<Geometry, String> {
    Ok(match g {
        GeometryValue::Point { coordinates } => Geometry::Points(vec![xy(coordinates)?]),
        GeometryValue::MultiPoint { coordinates } => Geometry::Points(line(coordinates)?),
        GeometryValue::LineString { coordinates } => Geometry::Lines(vec![line(coordinates)?]),
        GeometryValue::MultiLineString { coordinates } => {
            Geometry::Lines((coordinates.iter().map(|l| line(l))).collect::<Result<_, _>>()?)
        }
        GeometryValue::Polygon { coordinates } => Geometry::Polygons(vec![polygon(coordinates)?]),
        GeometryValue::MultiPolygon { coordinates } => {
            Geometry::Polygons((coordinates.iter().map(|p| polygon(p))).collect::<Result<_, _>>()?)
        }
        GeometryValue::GeometryCollection { .. } => {
            return Err("a GeometryCollection: give one geometry type per feature".into());
        }
    })
}

//! ESRI Shapefiles with the `shapefile` crate: the `.shp` geometries, the `.dbf` attributes,
//! the CRS from the `.prj` (WKT; its EPSG code when it names one or its name is one we ship).

use super::{Feature, Geometry, Layer, Value, VectorError, Xy};
use rockfall_raster::Crs;
use shapefile::dbase::FieldValue;
use shapefile::{Point, PolygonRing, Shape};
use std::io::Cursor;
use std::path::Path;

/// A Shapefile's `.shp` and `.dbf` bytes and `.prj` text → its one layer (named after the
/// file stem). No `.prj`: the CRS is unknown.
pub fn parse_shapefile(
    shp: &[u8],
    dbf: &[u8],
    prj: Option<&str>,
    path: &Path,
) -> Result<Layer, VectorError> {
    let bad =
        |e: shapefile::Error| VectorError::file(path, format!("not a readable Shapefile: {e}"));
    let shapes = shapefile::ShapeReader::new(Cursor::new(shp)).map_err(bad)?;
    let records = shapefile::dbase::Reader::new(Cursor::new(dbf))
        .map_err(|e| VectorError::file(path, format!("the .dbf is not readable: {e}")))?;
    let mut reader = shapefile::Reader::new(shapes, records);
    let mut layer = Layer {
        path: path.to_path_buf(),
        name: (path.file_stem())
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        crs: prj.map(Crs::from_wkt),
        features: Vec::new(),
    };
    for (index, item) in reader.iter_shapes_and_records().enumerate() {
        let id = index as i64;
        let (shape, record) = item.map_err(|e| VectorError::feature(&layer, id, e.to_string()))?;
        let geometry = geometry(shape).map_err(|m| VectorError::feature(&layer, id, m))?;
        let attributes = record
            .into_iter()
            .map(|(name, v)| (name, value(v)))
            .collect();
        layer.features.push(Feature {
            id,
            geometry,
            attributes,
        });
    }
    Ok(layer)
}

fn value(v: FieldValue) -> Value {
    let num = |x: Option<f64>| x.map(Value::Num).unwrap_or(Value::Null);
    match v {
        FieldValue::Numeric(x) => num(x),
        FieldValue::Float(x) => num(x.map(f64::from)),
        FieldValue::Integer(i) => Value::Num(f64::from(i)),
        FieldValue::Double(x) | FieldValue::Currency(x) => Value::Num(x),
        FieldValue::Logical(b) => num(b.map(|b| f64::from(u8::from(b)))),
        FieldValue::Character(s) => s.map(Value::Text).unwrap_or(Value::Null),
        FieldValue::Memo(s) => Value::Text(s),
        other => Value::Text(format!("{other:?}")),
    }
}

fn finite(x: f64, y: f64) -> Result<Xy, String> {
    match x.is_finite() && y.is_finite() {
        true => Ok([x, y]),
        false => Err("a coordinate is not a finite number".into()),
    }
}

fn xys<P>(points: &[P], at: impl Fn(&P) -> (f64, f64)) -> Result<Vec<Xy>, String> {
    points.iter().map(at).map(|(x, y)| finite(x, y)).collect()
}

/// Rings of a Shapefile polygon grouped into polygons: each outer ring starts one, the inner
/// rings after it are its holes (the order ESRI's specification and GDAL's writer keep).
fn polygons<P>(
    rings: &[PolygonRing<P>],
    at: impl Fn(&P) -> (f64, f64) + Copy,
) -> Result<Geometry, String> {
    let mut out: Vec<Vec<Vec<Xy>>> = Vec::new();
    for ring in rings {
        match ring {
            PolygonRing::Outer(ps) => out.push(vec![xys(ps, at)?]),
            PolygonRing::Inner(ps) => match out.last_mut() {
                Some(p) => p.push(xys(ps, at)?),
                None => return Err("a hole before any outer ring".into()),
            },
        }
    }
    Ok(Geometry::Polygons(out))
}

fn geometry(shape: Shape) -> Result<Geometry, String> {
    let p2 = |p: &Point| (p.x, p.y);
    Ok(match shape {
        Shape::NullShape => Geometry::Empty,
        Shape::Point(p) => Geometry::Points(vec![finite(p.x, p.y)?]),
        Shape::PointM(p) => Geometry::Points(vec![finite(p.x, p.y)?]),
        Shape::PointZ(p) => Geometry::Points(vec![finite(p.x, p.y)?]),
        Shape::Multipoint(m) => Geometry::Points(xys(m.points(), p2)?),
        Shape::MultipointM(m) => Geometry::Points(xys(m.points(), |p| (p.x, p.y))?),
        Shape::MultipointZ(m) => Geometry::Points(xys(m.points(), |p| (p.x, p.y))?),
        Shape::Polyline(l) => {
            Geometry::Lines((l.parts().iter().map(|p| xys(p, p2))).collect::<Result<_, _>>()?)
        }
        Shape::PolylineM(l) => Geometry::Lines(
            (l.parts().iter().map(|p| xys(p, |q| (q.x, q.y)))).collect::<Result<_, _>>()?,
        ),
        Shape::PolylineZ(l) => Geometry::Lines(
            (l.parts().iter().map(|p| xys(p, |q| (q.x, q.y)))).collect::<Result<_, _>>()?,
        ),
        Shape::Polygon(p) => polygons(p.rings(), p2)?,
        Shape::PolygonM(p) => polygons(p.rings(), |q| (q.x, q.y))?,
        Shape::PolygonZ(p) => polygons(p.rings(), |q| (q.x, q.y))?,
        Shape::Multipatch(_) => return Err("a multipatch: give points, lines or polygons".into()),
    })
}

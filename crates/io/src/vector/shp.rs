//! ESRI Shapefiles with the `shapefile` crate: the `.shp` geometries, the `.dbf` attributes,
//! the CRS from the `.prj` (WKT; its EPSG code when it names one or its name is one we ship).

use super::{Feature, Geometry, Layer, Value, VectorError, Xy};
use rockfall_raster::Crs;
use shapefile::dbase::FieldValue;
use shapefile::{Point, PolygonRing, ReadableShape, Shape};
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
    let contents = records(shp)
        .map_err(|m| VectorError::file(path, format!("not a readable Shapefile: {m}")))?;
    let mut table = shapefile::dbase::Reader::new(Cursor::new(dbf))
        .map_err(|e| VectorError::file(path, format!("the .dbf is not readable: {e}")))?;
    // the crate hands a row over as a hash map: the header gives the fields' order
    let names: Vec<String> = (table.fields().iter())
        .map(|f| f.name().to_string())
        .collect();
    let mut rows = table.iter_records();
    let mut layer = Layer {
        path: path.to_path_buf(),
        name: (path.file_stem())
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        crs: prj.map(Crs::from_wkt),
        within: None,
        features: Vec::with_capacity(contents.len()),
    };
    for (index, content) in contents.into_iter().enumerate() {
        let id = index as i64;
        let fail = |layer: &Layer, m: String| VectorError::feature(layer, id, m);
        // the record's content alone: the crate cannot read past it
        let size =
            i32::try_from(content.len()).map_err(|_| fail(&layer, "record too long".into()))?;
        let shape = Shape::read_from(&mut Cursor::new(content), size)
            .map_err(|e| fail(&layer, e.to_string()))?;
        let mut record = match rows.next() {
            Some(r) => r.map_err(|e| fail(&layer, format!("its .dbf row: {e}")))?,
            None => return Err(fail(&layer, "no .dbf row for this shape".into())),
        };
        let geometry = geometry(shape).map_err(|m| fail(&layer, m))?;
        let attributes = (names.iter())
            .filter_map(|name| Some((name.clone(), value(record.remove(name)?))))
            .collect();
        layer.features.push(Feature {
            id,
            geometry,
            attributes,
        });
    }
    Ok(layer)
}

/// The `.shp` records' contents (ESRI Shapefile Technical Description, 1998: a 100-byte
/// header, then records of an 8-byte big-endian header and a content of `length` 16-bit
/// words), each checked to lie in the file and, for multi-part shapes, to hold the parts
/// and points it counts, with part starts rising within the points. The `shapefile` crate sizes its buffers from those counts and reads
/// records one after the other, so a few lying bytes would otherwise ask it for gigabytes
/// (found by fuzzing): it is given one checked record at a time.
fn records(shp: &[u8]) -> Result<Vec<&[u8]>, String> {
    let word = |at: usize, big: bool| {
        let b: [u8; 4] = shp.get(at..at + 4)?.try_into().ok()?;
        Some(if big {
            i32::from_be_bytes(b)
        } else {
            i32::from_le_bytes(b)
        })
    };
    if shp.len() < 100 || word(0, true) != Some(9994) {
        return Err("no Shapefile header (file code 9994)".into());
    }
    let mut out = Vec::new();
    let mut pos = 100;
    while pos + 8 <= shp.len() {
        let record = out.len() + 1;
        let count = |at: usize, big: bool| -> Result<usize, String> {
            usize::try_from(word(at, big).unwrap_or(-1))
                .map_err(|_| format!("record {record}: a length or count is missing or negative"))
        };
        let bytes = count(pos + 4, true)?.saturating_mul(2);
        let start = pos + 8;
        let content = (shp.get(start..start.saturating_add(bytes)))
            .ok_or_else(|| format!("record {record} runs past the end of the file"))?;
        let need = match word(start, false).unwrap_or(0) {
            // polyline, polygon (plain, Z, M): parts and points after the bounding box
            3 | 5 | 13 | 15 | 23 | 25 => (count(start + 36, false)?.saturating_mul(4))
                .saturating_add(count(start + 40, false)?.saturating_mul(16))
                .saturating_add(44),
            // multipatch: parts, their types, points
            31 => (count(start + 36, false)?.saturating_mul(8))
                .saturating_add(count(start + 40, false)?.saturating_mul(16))
                .saturating_add(44),
            // multipoint (plain, Z, M): points after the bounding box
            8 | 18 | 28 => (count(start + 36, false)?.saturating_mul(16)).saturating_add(40),
            _ => 0,
        };
        if need > bytes {
            return Err(format!(
                "record {record} declares more parts or points than its {bytes} bytes hold"
            ));
        }
        if matches!(word(start, false), Some(3 | 5 | 13 | 15 | 23 | 25 | 31)) {
            // each part starts at a point index: rising, and within the points
            let (parts, points) = (count(start + 36, false)?, count(start + 40, false)?);
            let mut last = 0;
            for k in 0..parts {
                let first = count(start + 44 + 4 * k, false)?;
                if first < last || first > points {
                    return Err(format!(
                        "record {record}: part {} starts at point {first} of {points}",
                        k + 1
                    ));
                }
                last = first;
            }
        }
        out.push(content);
        pos = start + bytes;
    }
    Ok(out)
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

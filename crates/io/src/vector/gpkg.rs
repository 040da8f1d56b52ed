//! GeoPackage layers (OGC 12-128r18) through SQLite (`rusqlite`, cargo feature `gpkg`): the
//! feature tables of `gpkg_geometry_columns`, their CRS from `gpkg_spatial_ref_sys`, their
//! geometry blobs decoded by [`super::wkb`].

use super::wkb::decode_gpkg_geometry;
use super::{Envelope, Feature, Geometry, Layer, Value, VectorError};
use rockfall_raster::Crs;
use rusqlite::types::ValueRef;
use rusqlite::{Connection, OpenFlags};
use std::path::Path;

/// Reads the layer `layer` (the only one when `None`) of a GeoPackage, read-only; with
/// `within`, through the layer's R-tree when it has one: the features whose stored box meets
/// `within` (the caller drops those whose exact box does not), in the table's order.
pub(super) fn read(
    path: &Path,
    layer: Option<&str>,
    within: Option<Envelope>,
) -> Result<Layer, VectorError> {
    let fail = |m: String| VectorError::file(path, m);
    let db = Connection::open_with_flags(path, OpenFlags::SQLITE_OPEN_READ_ONLY)
        .map_err(|e| fail(format!("not a readable GeoPackage: {e}")))?;
    let sql = |e: rusqlite::Error| fail(format!("not a readable GeoPackage: {e}"));
    let mut stmt = db
        .prepare(
            "SELECT table_name, column_name, srs_id FROM gpkg_geometry_columns ORDER BY table_name",
        )
        .map_err(sql)?;
    let layers: Vec<(String, String, i64)> = stmt
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))
        .map_err(sql)?
        .collect::<Result<_, _>>()
        .map_err(sql)?;
    let names = || {
        let n: Vec<String> = layers.iter().map(|l| format!("`{}`", l.0)).collect();
        n.join(", ")
    };
    let (table, column, srs_id) = match (layer, layers.as_slice()) {
        (_, []) => return Err(fail("the GeoPackage holds no feature layer".into())),
        (None, [one]) => one.clone(),
        (None, _) => {
            return Err(fail(format!(
                "{} layers ({}): name one with `layer = \"…\"`",
                layers.len(),
                names()
            )));
        }
        (Some(name), _) => match layers.iter().find(|l| l.0 == name) {
            Some(l) => l.clone(),
            None => return Err(fail(format!("no layer `{name}`; its layers: {}", names()))),
        },
    };
    let mut out = Layer {
        path: path.to_path_buf(),
        name: table.clone(),
        crs: crs(&db, srs_id).map_err(sql)?,
        features: Vec::new(),
        within: None,
    };
    let quoted = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
    let pk: Option<String> = db
        .prepare(&format!("PRAGMA table_info({})", quoted(&table)))
        .and_then(|mut s| {
            let cols: Vec<(String, i64)> = s
                .query_map([], |r| Ok((r.get(1)?, r.get(5)?)))?
                .collect::<Result<_, _>>()?;
            Ok(cols.into_iter().find(|c| c.1 == 1).map(|c| c.0))
        })
        .map_err(sql)?;
    let indexed = within.zip(pk.as_ref()).and_then(|(e, pk)| {
        let rtree = format!("rtree_{table}_{column}");
        // the index's boxes are rounded outward to f32: a superset of the exact test
        let query = format!(
            "SELECT * FROM {} WHERE {} IN (SELECT id FROM {} WHERE minx <= ?3 AND maxx >= ?1 AND miny <= ?4 AND maxy >= ?2) ORDER BY rowid",
            quoted(&table),
            quoted(pk),
            quoted(&rtree)
        );
        // no index table (or no R-tree module): the query does not prepare
        let stmt = db.prepare(&query).ok()?;
        Some((stmt, [e.x_min_m, e.y_min_m, e.x_max_m, e.y_max_m]))
    });
    // without an index (or SQLite's R-tree module), the whole table in its order
    let (mut stmt, bounds) = match indexed {
        Some((stmt, b)) => (stmt, Some(b)),
        None => (
            db.prepare(&format!("SELECT * FROM {}", quoted(&table)))
                .map_err(sql)?,
            None,
        ),
    };
    let columns: Vec<String> = stmt.column_names().map(String::from).collect();
    let mut rows = match &bounds {
        Some(b) => stmt.query(rusqlite::params_from_iter(b.iter())),
        None => stmt.query([]),
    }
    .map_err(sql)?;
    let mut index = 0i64;
    while let Some(row) = rows.next().map_err(sql)? {
        let mut id = index;
        let mut geometry = Geometry::Empty;
        let mut attributes = Vec::new();
        for (c, name) in columns.iter().enumerate() {
            let v = row.get_ref(c).map_err(sql)?;
            if Some(name) == pk.as_ref() {
                if let ValueRef::Integer(i) = v {
                    id = i;
                }
                continue;
            }
            if name.eq_ignore_ascii_case(&column) {
                if let ValueRef::Blob(b) = v {
                    geometry = decode_gpkg_geometry(b)
                        .map_err(|m| VectorError::feature(&out, id, m))?
                        .0;
                }
                continue;
            }
            let value = match v {
                ValueRef::Integer(i) => Value::Num(i as f64),
                ValueRef::Real(x) => Value::Num(x),
                ValueRef::Text(t) => Value::Text(String::from_utf8_lossy(t).into_owned()),
                ValueRef::Null | ValueRef::Blob(_) => Value::Null,
            };
            attributes.push((name.clone(), value));
        }
        out.features.push(Feature {
            id,
            geometry,
            attributes,
        });
        index += 1;
    }
    Ok(out)
}

/// The CRS of `srs_id`: its EPSG code when the organisation is EPSG, else its WKT;
/// `None` for GeoPackage's "undefined" systems (−1, 0).
fn crs(db: &Connection, srs_id: i64) -> Result<Option<Crs>, rusqlite::Error> {
    let mut stmt = db.prepare(
        "SELECT organization, organization_coordsys_id, definition FROM gpkg_spatial_ref_sys WHERE srs_id = ?1",
    )?;
    let mut rows = stmt.query([srs_id])?;
    let Some(row) = rows.next()? else {
        return Ok(None);
    };
    let org: String = row.get(0)?;
    let code: i64 = row.get(1)?;
    let wkt: String = row.get(2)?;
    Ok(
        match (org.eq_ignore_ascii_case("EPSG"), u32::try_from(code)) {
            (true, Ok(c)) if c > 0 => Some(Crs::from_epsg(c)),
            _ if srs_id <= 0 => None,
            _ => Some(Crs::from_wkt(&wkt)),
        },
    )
}

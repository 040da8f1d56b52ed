//! Writing one polygon layer as a GeoPackage (OGC 12-128r18, GeoPackage 1.3) through SQLite
//! (`rusqlite`, cargo feature `gpkg`): what [`super::write_gpkg_polygons`] does.
//!
//! The file holds the tables a feature GeoPackage requires and no more: the header's
//! `application_id` 'GPKG' and `user_version` 10300 (§1.1.1.1.1, Req. 2), the
//! `gpkg_spatial_ref_sys` table with its three required rows (§1.1.2.1.2, Req. 11: EPSG:4326,
//! −1 undefined Cartesian, 0 undefined geographic) and the layer's CRS, `gpkg_contents`
//! (§1.1.3, data type `features` and the layer's bounds), `gpkg_geometry_columns` (§2.1.5,
//! `MULTIPOLYGON`) and the feature table (§2.1.6: `fid INTEGER PRIMARY KEY AUTOINCREMENT`,
//! `geom MULTIPOLYGON`, the attribute columns), geometries as blobs of
//! [`super::wkb::encode_gpkg_multipolygon`]. No R-tree index (the extension of §F.3): a
//! hazard map's layer has a feature per level, so an index would never pay, and GDAL and
//! QGIS read the layer without it.
//!
//! Atomic, as every writer of the workspace (`rockfall_raster::atomic`): the database is
//! built in a temporary file beside the target, flushed, and renamed over it; on any error
//! the temporary is removed and an existing file left as it was.

use super::wkb::encode_gpkg_multipolygon;
use super::{FieldType, Polygon, Value, VectorError, Xy};
use rockfall_raster::Crs;
use rockfall_raster::crs::known;
use rusqlite::Connection;
use rusqlite::types::Value as Sql;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The SRS id of a CRS known only by its WKT (GDAL's first id for such systems).
const CUSTOM_SRS_ID: i32 = 100_000;

/// Writes the layer; see [`super::write_gpkg_polygons`].
pub(super) fn write(
    path: &Path,
    layer: &str,
    crs: Option<&Crs>,
    fields: &[(&str, FieldType)],
    features: &[(Vec<Polygon>, Vec<Value>)],
) -> Result<(), VectorError> {
    let fail = |feature: Option<i64>, message: String| VectorError {
        path: path.to_path_buf(),
        layer: Some(layer.to_string()),
        feature,
        message,
    };
    check_name(layer, "layer").map_err(|m| fail(None, m))?;
    let lower = |s: &str| s.to_ascii_lowercase();
    for (k, (name, _)) in fields.iter().enumerate() {
        check_name(name, "field").map_err(|m| fail(None, m))?;
        if ["fid", "geom"].contains(&lower(name).as_str()) {
            return Err(fail(
                None,
                format!("field `{name}` would be a column we write"),
            ));
        }
        if fields[..k].iter().any(|(n, _)| lower(n) == lower(name)) {
            return Err(fail(None, format!("field `{name}` twice (case ignored)")));
        }
    }
    let srs = Srs::of(crs);
    let mut rows = Vec::with_capacity(features.len());
    let mut bounds = Bounds::default();
    for (k, (polygons, values)) in features.iter().enumerate() {
        // the feature's fid: the AUTOINCREMENT key counts from 1 in an empty table
        let fid = k as i64 + 1;
        let fail = |m: String| fail(Some(fid), m);
        check_polygons(polygons).map_err(fail)?;
        polygons
            .iter()
            .flatten()
            .flatten()
            .for_each(|p| bounds.add(p));
        let blob = encode_gpkg_multipolygon(polygons, srs.id).map_err(fail)?;
        rows.push((blob, sql_values(fields, values).map_err(fail)?));
    }
    let tmp = temp_name(path);
    let _ = std::fs::remove_file(&tmp);
    let built = build(&tmp, layer, &srs, fields, &rows, &bounds)
        .map_err(|e| fail(None, format!("cannot write the GeoPackage: {e}")))
        .and_then(|()| {
            let synced = std::fs::File::open(&tmp).and_then(|f| f.sync_all());
            synced
                .and_then(|()| std::fs::rename(&tmp, path))
                .map_err(|e| fail(None, e.to_string()))
        });
    if built.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    built
}

/// A layer or field name: not empty, no control character, not in a reserved namespace.
fn check_name(name: &str, what: &str) -> Result<(), String> {
    let lower = name.to_ascii_lowercase();
    if name.is_empty() || name.chars().any(char::is_control) {
        return Err(format!(
            "{what} name {name:?} is empty or holds a control character"
        ));
    }
    match ["gpkg_", "sqlite_", "rtree_"]
        .iter()
        .find(|p| lower.starts_with(*p))
    {
        Some(p) => Err(format!(
            "{what} name `{name}` starts with the reserved `{p}`"
        )),
        None => Ok(()),
    }
}

/// Polygons of at least one closed ring each, rings of four points or more, coordinates
/// finite.
fn check_polygons(polygons: &[Polygon]) -> Result<(), String> {
    for (i, polygon) in polygons.iter().enumerate() {
        if polygon.is_empty() {
            return Err(format!("polygon {i} has no ring"));
        }
        for (r, ring) in polygon.iter().enumerate() {
            let at = format!("ring {r} of polygon {i}");
            if ring.len() < 4 {
                return Err(format!("{at} has {} points, fewer than 4", ring.len()));
            }
            if ring.first() != ring.last() {
                return Err(format!("{at} is not closed"));
            }
            if let Some(p) = ring
                .iter()
                .find(|p| !(p[0].is_finite() && p[1].is_finite()))
            {
                return Err(format!("{at} has the point ({}, {})", p[0], p[1]));
            }
        }
    }
    Ok(())
}

/// A feature's values as the columns' SQL values: integers whole and within 64 bits, reals
/// finite, text as text; null anywhere.
fn sql_values(fields: &[(&str, FieldType)], values: &[Value]) -> Result<Vec<Sql>, String> {
    if values.len() != fields.len() {
        let (n, m) = (values.len(), fields.len());
        return Err(format!("{n} values for {m} fields"));
    }
    let two_63 = 9_223_372_036_854_775_808.0;
    (fields.iter().zip(values))
        .map(|((name, kind), v)| match (kind, v) {
            (_, Value::Null) => Ok(Sql::Null),
            (FieldType::Integer, Value::Num(x)) if x.fract() == 0.0 && x.abs() < two_63 => {
                Ok(Sql::Integer(*x as i64))
            }
            (FieldType::Real, Value::Num(x)) if x.is_finite() => Ok(Sql::Real(*x)),
            (FieldType::Text, Value::Text(t)) => Ok(Sql::Text(t.clone())),
            (kind, v) => Err(format!("field `{name}` ({kind:?}) cannot hold {v:?}")),
        })
        .collect()
}

/// The `gpkg_spatial_ref_sys` row of the layer's CRS.
struct Srs {
    id: i32,
    /// (name, organization, definition) of a row to add; `None` for a required row.
    row: Option<(String, &'static str, String)>,
}

impl Srs {
    /// An EPSG code: its own id, with the shipped WKT when we have it (else the CRS's own,
    /// else `undefined`); only a WKT: [`CUSTOM_SRS_ID`]; neither: −1, undefined Cartesian.
    fn of(crs: Option<&Crs>) -> Srs {
        let Some(crs) = crs else {
            return Srs { id: -1, row: None };
        };
        let epsg = crs
            .epsg
            .and_then(|c| i32::try_from(c).ok())
            .filter(|&c| c > 0);
        match (epsg, &crs.wkt) {
            (Some(4326), _) => Srs {
                id: 4326,
                row: None,
            },
            (Some(code), wkt) => {
                let shipped = known(code as u32);
                let name = shipped
                    .map(|k| k.name.to_string())
                    .unwrap_or(crs.describe());
                let wkt = (shipped.map(|k| k.wkt.to_string()))
                    .or(wkt.clone())
                    .unwrap_or_else(|| "undefined".into());
                Srs {
                    id: code,
                    row: Some((name, "EPSG", wkt)),
                }
            }
            (None, Some(wkt)) => Srs {
                id: CUSTOM_SRS_ID,
                row: Some((crs.describe(), "NONE", wkt.clone())),
            },
            (None, None) => Srs { id: -1, row: None },
        }
    }
}

/// The layer's extent, m; empty until a point is added.
struct Bounds {
    lo: Xy,
    hi: Xy,
}

impl Default for Bounds {
    fn default() -> Self {
        Bounds {
            lo: [f64::INFINITY; 2],
            hi: [f64::NEG_INFINITY; 2],
        }
    }
}

impl Bounds {
    fn add(&mut self, p: &Xy) {
        self.lo = [self.lo[0].min(p[0]), self.lo[1].min(p[1])];
        self.hi = [self.hi[0].max(p[0]), self.hi[1].max(p[1])];
    }

    /// (min x, min y, max x, max y), or nulls for an empty layer.
    fn sql(&self) -> [Option<f64>; 4] {
        let some = self.lo[0] <= self.hi[0];
        [self.lo[0], self.lo[1], self.hi[0], self.hi[1]].map(|v| some.then_some(v))
    }
}

/// The table definitions of OGC 12-128r18 Annex C (as GDAL writes them) and the required
/// undefined systems.
const SCHEMA: &str = "
CREATE TABLE gpkg_spatial_ref_sys (srs_name TEXT NOT NULL, srs_id INTEGER NOT NULL PRIMARY KEY,
  organization TEXT NOT NULL, organization_coordsys_id INTEGER NOT NULL,
  definition TEXT NOT NULL, description TEXT);
CREATE TABLE gpkg_contents (table_name TEXT NOT NULL PRIMARY KEY, data_type TEXT NOT NULL,
  identifier TEXT UNIQUE, description TEXT DEFAULT '',
  last_change DATETIME NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ','now')),
  min_x DOUBLE, min_y DOUBLE, max_x DOUBLE, max_y DOUBLE, srs_id INTEGER,
  CONSTRAINT fk_gc_r_srs_id FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys(srs_id));
CREATE TABLE gpkg_geometry_columns (table_name TEXT NOT NULL, column_name TEXT NOT NULL,
  geometry_type_name TEXT NOT NULL, srs_id INTEGER NOT NULL, z TINYINT NOT NULL,
  m TINYINT NOT NULL,
  CONSTRAINT pk_geom_cols PRIMARY KEY (table_name, column_name),
  CONSTRAINT uk_gc_table_name UNIQUE (table_name),
  CONSTRAINT fk_gc_tn FOREIGN KEY (table_name) REFERENCES gpkg_contents(table_name),
  CONSTRAINT fk_gc_srs FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys (srs_id));
INSERT INTO gpkg_spatial_ref_sys VALUES
  ('Undefined Cartesian SRS', -1, 'NONE', -1, 'undefined',
   'undefined Cartesian coordinate reference system'),
  ('Undefined geographic SRS', 0, 'NONE', 0, 'undefined',
   'undefined geographic coordinate reference system');
";

/// The GeoPackage in `file`, in one transaction.
fn build(
    file: &Path,
    layer: &str,
    srs: &Srs,
    fields: &[(&str, FieldType)],
    rows: &[(Vec<u8>, Vec<Sql>)],
    bounds: &Bounds,
) -> Result<(), rusqlite::Error> {
    let mut db = Connection::open(file)?;
    // the file is ours alone until renamed: no journal to leave beside it
    db.pragma_update(None, "journal_mode", "MEMORY")?;
    db.pragma_update(None, "application_id", 0x4750_4B47)?;
    db.pragma_update(None, "user_version", 10300)?;
    db.pragma_update(None, "foreign_keys", true)?;
    let tx = db.transaction()?;
    tx.execute_batch(SCHEMA)?;
    let wgs84 = known(4326).map(|k| k.wkt).unwrap_or("undefined");
    let insert_srs = "INSERT INTO gpkg_spatial_ref_sys VALUES (?1, ?2, ?3, ?4, ?5, ?6)";
    tx.execute(
        insert_srs,
        (
            "WGS 84 geodetic",
            4326,
            "EPSG",
            4326,
            wgs84,
            "longitude/latitude coordinates in decimal degrees on the WGS 84 spheroid",
        ),
    )?;
    if let Some((name, org, wkt)) = &srs.row {
        tx.execute(insert_srs, (name, srs.id, org, srs.id, wkt, None::<String>))?;
    }
    let [min_x, min_y, max_x, max_y] = bounds.sql();
    tx.execute(
        "INSERT INTO gpkg_contents (table_name, data_type, identifier, min_x, min_y, max_x, max_y, srs_id) \
         VALUES (?1, 'features', ?1, ?2, ?3, ?4, ?5, ?6)",
        (layer, min_x, min_y, max_x, max_y, srs.id),
    )?;
    tx.execute(
        "INSERT INTO gpkg_geometry_columns VALUES (?1, 'geom', 'MULTIPOLYGON', ?2, 0, 0)",
        (layer, srs.id),
    )?;
    let quoted = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
    let sql_type = |t: &FieldType| match t {
        FieldType::Integer => "INTEGER",
        FieldType::Real => "REAL",
        FieldType::Text => "TEXT",
    };
    let columns: Vec<String> = (fields.iter())
        .map(|(n, t)| format!(", {} {}", quoted(n), sql_type(t)))
        .collect();
    tx.execute_batch(&format!(
        "CREATE TABLE {} (\"fid\" INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, \"geom\" MULTIPOLYGON{})",
        quoted(layer),
        columns.concat()
    ))?;
    let names: Vec<String> = fields
        .iter()
        .map(|(n, _)| format!(", {}", quoted(n)))
        .collect();
    let slots: Vec<String> = (0..fields.len()).map(|k| format!(", ?{}", k + 2)).collect();
    let mut insert = tx.prepare(&format!(
        "INSERT INTO {} (\"geom\"{}) VALUES (?1{})",
        quoted(layer),
        names.concat(),
        slots.concat()
    ))?;
    for (blob, values) in rows {
        insert.raw_bind_parameter(1, blob)?;
        for (k, v) in values.iter().enumerate() {
            insert.raw_bind_parameter(k + 2, v)?;
        }
        insert.raw_execute()?;
    }
    drop(insert);
    tx.commit()?;
    db.close().map_err(|(_, e)| e)
}

/// `dir/.name.tmp-PID-N` beside the target: hidden, on the same file system, unique per
/// process and call (as `rockfall_raster::atomic` names its temporaries).
fn temp_name(path: &Path) -> PathBuf {
    static CALLS: AtomicU64 = AtomicU64::new(0);
    let name = (path.file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out.gpkg".into());
    let n = CALLS.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.tmp-{}-{n}", std::process::id()))
}

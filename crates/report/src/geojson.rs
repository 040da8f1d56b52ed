//! The recorded trajectories as GeoJSON lines, for QGIS and every other GIS.
//!
//! One `LineString` feature per recorded rock, with `[x, y, z]` vertices in the run's map
//! coordinates (m). Vertices are thinned: a row is kept when it lies at least
//! [`vertex_spacing_m`] (half a cell) horizontally from the last kept one, and the first and
//! last rows and every tree impact are always kept. The CRS is named in the (pre-RFC 7946)
//! `crs` member as `urn:ogc:def:crs:EPSG::<code>`, which GDAL and QGIS read; coordinates
//! stay in the run's projected CRS rather than being reprojected to WGS 84. A CRS known only
//! by WKT cannot be named in GeoJSON: the member is then left out and the report says so.

use std::path::Path;

use rockfall_forest::Stem;
use rockfall_raster::Crs;
use rockfall_raster::atomic::{write_atomic, write_bytes_atomic};
use rockfall_results::{Event, TrajectoryRow};
use serde_json::{Value, json};
use std::io::Write;

use crate::ReportError;

/// Largest horizontal gap (m) between kept vertices that thinning may leave out: half a cell.
pub fn vertex_spacing_m(cell_size_m: f64) -> f64 {
    cell_size_m / 2.0
}

/// The rows of each recorded rock, in rock order (rows are sorted by rock id, then time).
pub fn by_rock(rows: &[TrajectoryRow]) -> Vec<&[TrajectoryRow]> {
    rows.chunk_by(|a, b| a.rock_id == b.rock_id).collect()
}

/// The rows of one rock kept as vertices (see the module docs).
pub fn thin(rows: &[TrajectoryRow], spacing_m: f64) -> Vec<&TrajectoryRow> {
    let mut kept: Vec<&TrajectoryRow> = Vec::new();
    for (i, r) in rows.iter().enumerate() {
        let last = i + 1 == rows.len();
        let far = kept
            .last()
            .is_none_or(|k| (r.x_m - k.x_m).hypot(r.y_m - k.y_m) >= spacing_m);
        if far || last || r.event == Event::Tree {
            kept.push(r);
        }
    }
    kept
}

/// `v` rounded to three decimals (mm for coordinates in m).
fn mm(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// Total kinetic energy of a row, kJ.
pub fn energy_kj(r: &TrajectoryRow) -> f64 {
    (r.e_trans_j + r.e_rot_j) / 1e3
}

/// The GeoJSON `FeatureCollection` of the recorded trajectories.
pub fn feature_collection(rows: &[TrajectoryRow], crs: Option<&Crs>, cell_size_m: f64) -> Value {
    collection(
        "trajectories",
        crs,
        trajectory_features(rows, cell_size_m).collect(),
    )
}

/// The features of [`feature_collection`], one rock at a time.
pub fn trajectory_features(
    rows: &[TrajectoryRow],
    cell_size_m: f64,
) -> impl Iterator<Item = Value> + '_ {
    let spacing = vertex_spacing_m(cell_size_m);
    by_rock(rows)
        .into_iter()
        .filter(|rock| rock.len() >= 2)
        .map(move |rock| {
            let coords: Vec<Value> = thin(rock, spacing)
                .into_iter()
                .map(|r| json!([mm(r.x_m), mm(r.y_m), mm(r.z_m)]))
                .collect();
            let speed = |r: &TrajectoryRow| {
                (r.vx_ms * r.vx_ms + r.vy_ms * r.vy_ms + r.vz_ms * r.vz_ms).sqrt()
            };
            let max = |f: &dyn Fn(&TrajectoryRow) -> f64| rock.iter().map(f).fold(0.0, f64::max);
            let (first, last) = (&rock[0], &rock[rock.len() - 1]);
            json!({
                "type": "Feature",
                "properties": {
                    "rock_id": first.rock_id,
                    "duration_s": mm(last.t_s - first.t_s),
                    "max_speed_ms": mm(max(&speed)),
                    "max_energy_kj": mm(max(&energy_kj)),
                    "tree_impacts": rock.iter().filter(|r| r.event == Event::Tree).count(),
                    "end_event": last.event.name(),
                    "vertices": coords.len(),
                },
                "geometry": {"type": "LineString", "coordinates": coords},
            })
        })
}

/// The stems as GeoJSON point features `[x, y]` with their DBH (cm), height (m) and species,
/// one stem at a time (written by [`write_feature_collection`]).
pub fn stem_features(stems: &[Stem]) -> impl Iterator<Item = Value> + '_ {
    stems.iter().map(|s| {
        json!({
            "type": "Feature",
            "properties": {
                "dbh_cm": mm(s.dbh_cm),
                "height_m": mm(s.height_m),
                "species": s.species.name(),
            },
            "geometry": {"type": "Point", "coordinates": [mm(s.x_m), mm(s.y_m)]},
        })
    })
}

/// The `crs` member naming the CRS's EPSG code, when it has one.
fn crs_member(crs: Option<&Crs>) -> Option<Value> {
    let code = crs.and_then(|c| c.epsg)?;
    let urn = format!("urn:ogc:def:crs:EPSG::{code}");
    Some(json!({"type": "name", "properties": {"name": urn}}))
}

/// A named `FeatureCollection` with the CRS member when the CRS has an EPSG code.
fn collection(name: &str, crs: Option<&Crs>, features: Vec<Value>) -> Value {
    let mut fc = json!({"type": "FeatureCollection", "name": name});
    if let Some(member) = crs_member(crs) {
        fc["crs"] = member;
    }
    fc["features"] = Value::Array(features);
    fc
}

/// Writes the `FeatureCollection` `name` of `features` to `path` atomically, one feature at a
/// time: the same bytes as [`write_geojson`] of the collection, without holding it (a
/// region's stems are millions of features).
pub fn write_feature_collection(
    path: &Path,
    name: &str,
    crs: Option<&Crs>,
    features: impl Iterator<Item = Value>,
) -> Result<(), ReportError> {
    let io = |e: std::io::Error| ReportError::Io {
        path: path.to_path_buf(),
        source: e,
    };
    write_atomic(path, |w| {
        // the members in serde_json's (sorted) order: crs, features, name, type
        w.write_all(b"{").map_err(io)?;
        if let Some(member) = crs_member(crs) {
            w.write_all(b"\"crs\":").map_err(io)?;
            serde_json::to_writer(&mut *w, &member).map_err(|e| io(e.into()))?;
            w.write_all(b",").map_err(io)?;
        }
        w.write_all(b"\"features\":[").map_err(io)?;
        for (i, f) in features.enumerate() {
            if i > 0 {
                w.write_all(b",").map_err(io)?;
            }
            serde_json::to_writer(&mut *w, &f).map_err(|e| io(e.into()))?;
        }
        w.write_all(b"],\"name\":").map_err(io)?;
        serde_json::to_writer(&mut *w, name).map_err(|e| io(e.into()))?;
        w.write_all(b",\"type\":\"FeatureCollection\"}\n")
            .map_err(io)
    })
}

/// Writes a GeoJSON value to `path` atomically (compact JSON).
pub fn write_geojson(path: &Path, fc: &Value) -> Result<(), ReportError> {
    let mut bytes = serde_json::to_vec(fc).map_err(|e| ReportError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e),
    })?;
    bytes.push(b'\n');
    write_bytes_atomic(path, &bytes).map_err(ReportError::from)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn row(rock_id: u64, t_s: f64, x_m: f64, event: Event) -> TrajectoryRow {
        TrajectoryRow {
            rock_id,
            t_s,
            x_m,
            y_m: 10.0,
            z_m: 100.0 - x_m,
            vx_ms: 3.0,
            vy_ms: 0.0,
            vz_ms: -4.0,
            wx_rads: 0.0,
            wy_rads: 0.0,
            wz_rads: 0.0,
            e_trans_j: 1000.0 * x_m,
            e_rot_j: 500.0,
            event,
        }
    }

    #[test]
    fn one_line_per_rock_thinned_with_its_ends_and_tree_impacts_kept() {
        let mut rows: Vec<TrajectoryRow> = (0..=20)
            .map(|i| row(3, f64::from(i) * 0.1, f64::from(i) * 0.25, Event::Flight))
            .collect();
        rows[7].event = Event::Tree;
        rows[20].event = Event::Stop;
        rows.push(row(4, 0.0, 0.0, Event::Flight));
        rows.push(row(4, 1.0, 9.0, Event::Stop));
        rows.push(row(5, 0.0, 0.0, Event::Stop)); // a single row is no line
        let fc = feature_collection(&rows, Some(&Crs::from_epsg(2056)), 2.0);
        let features = fc["features"].as_array().unwrap();
        assert_eq!(features.len(), 2);
        let coords = features[0]["geometry"]["coordinates"].as_array().unwrap();
        let xs: Vec<f64> = coords.iter().map(|c| c[0].as_f64().unwrap()).collect();
        // Spacing 1 m: every 4th row (0, 1, 2, …), plus the tree impact at 1.75 m.
        assert_eq!(xs, [0.0, 1.0, 1.75, 2.75, 3.75, 4.75, 5.0]);
        assert_eq!(coords[0].as_array().unwrap().len(), 3);
        let p = &features[0]["properties"];
        assert_eq!(p["rock_id"], 3);
        assert_eq!(p["tree_impacts"], 1);
        assert_eq!(p["end_event"], "stop");
        assert_eq!(p["max_speed_ms"], 5.0);
        assert_eq!(p["max_energy_kj"], 5.5);
        assert_eq!(p["duration_s"], 2.0);
        assert_eq!(
            fc["crs"]["properties"]["name"],
            "urn:ogc:def:crs:EPSG::2056"
        );
    }

    #[test]
    fn streaming_writes_the_bytes_of_the_whole_collection() {
        let rows: Vec<TrajectoryRow> = (0..=30)
            .map(|i: u32| {
                row(
                    u64::from(i / 10),
                    f64::from(i) * 0.1,
                    f64::from(i),
                    Event::Flight,
                )
            })
            .collect();
        let dir = tempfile::tempdir().unwrap();
        let crs = Crs::from_epsg(2056);
        let wkt_only = Crs::from_wkt("LOCAL_CS[\"x\"]");
        for (k, crs) in [Some(&crs), Some(&wkt_only), None].into_iter().enumerate() {
            let (whole, streamed) = (dir.path().join("a"), dir.path().join(format!("b{k}")));
            write_geojson(&whole, &feature_collection(&rows, crs, 2.0)).unwrap();
            let features = trajectory_features(&rows, 2.0);
            write_feature_collection(&streamed, "trajectories", crs, features).unwrap();
            assert_eq!(
                std::fs::read(&whole).unwrap(),
                std::fs::read(&streamed).unwrap()
            );
            // no feature at all
            write_geojson(&whole, &feature_collection(&[], crs, 2.0)).unwrap();
            let none = trajectory_features(&[], 2.0);
            write_feature_collection(&streamed, "trajectories", crs, none).unwrap();
            assert_eq!(
                std::fs::read(&whole).unwrap(),
                std::fs::read(&streamed).unwrap()
            );
        }
    }

    #[test]
    fn without_an_epsg_code_there_is_no_crs_member() {
        let rows = [
            row(0, 0.0, 0.0, Event::Flight),
            row(0, 1.0, 3.0, Event::Stop),
        ];
        let fc = feature_collection(&rows, Some(&Crs::from_wkt("LOCAL_CS[\"x\"]")), 2.0);
        assert!(fc.get("crs").is_none());
        assert_eq!(fc["features"].as_array().unwrap().len(), 1);
    }
}

//! GeoPackages we write (`rockfall_io::vector::write_gpkg_polygons`): read back by our own
//! reader and by SQLite (integrity, the required tables and rows, the blobs' areas), and by
//! GDAL's `ogrinfo` (layer, geometry type, count, fields, CRS, values; validity through
//! SpatiaLite's `ST_IsValid` where GDAL has it).
//!
//! The `ogrinfo` checks need gdal-bin; without it they print a notice and pass, except when
//! `CI` is set: then they fail.

#![cfg(feature = "gpkg")]
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_io::vector::wkb::decode_gpkg_geometry;
use rockfall_io::vector::{
    FieldType, Geometry, Value, Xy, polygonize, read_layer, write_gpkg_polygons,
};
use rockfall_raster::{Crs, GridGeometry};
use rusqlite::Connection;
use std::path::Path;
use std::process::Command;

type Features = Vec<(Vec<Vec<Vec<Xy>>>, Vec<Value>)>;

const FIELDS: [(&str, FieldType); 3] = [
    ("level", FieldType::Integer),
    ("area_m2", FieldType::Real),
    ("label", FieldType::Text),
];

/// 8 × 6 cells of 5 m in LV95: a frame of 1 with an island of 1 in its hole, diagonal cells
/// of 2, and 3 touching itself at a corner (its hole touches its exterior there).
fn zones() -> (Vec<u8>, GridGeometry) {
    let rows = [
        "11111020", "10001200", "10101033", "10001303", "11111333", "00000000",
    ];
    let values = rows
        .iter()
        .flat_map(|r| r.bytes().map(|b| b - b'0'))
        .collect();
    let grid = GridGeometry {
        ncols: 8,
        nrows: 6,
        x_min_m: 2_600_000.0,
        y_min_m: 1_200_000.0,
        cell_size_m: 5.0,
    };
    (values, grid)
}

/// One feature per level: its polygons, the level, its area and a label.
fn features(values: &[u8], grid: &GridGeometry) -> Features {
    (polygonize(values, grid).into_iter())
        .map(|(level, polygons)| {
            let cells = values.iter().filter(|&&v| v == level).count();
            let attributes = vec![
                Value::Num(f64::from(level)),
                Value::Num(cells as f64 * grid.cell_area_m2()),
                Value::Text(["low", "medium", "high"][usize::from(level) - 1].into()),
            ];
            (polygons, attributes)
        })
        .collect()
}

fn signed_area_m2(ring: &[Xy]) -> f64 {
    let o = ring[0];
    let twice: f64 = (ring.windows(2))
        .map(|w| (w[0][0] - o[0]) * (w[1][1] - o[1]) - (w[1][0] - o[0]) * (w[0][1] - o[1]))
        .sum();
    twice / 2.0
}

fn write_zones(path: &Path, crs: Option<&Crs>) -> Features {
    let (values, grid) = zones();
    let features = features(&values, &grid);
    write_gpkg_polygons(path, "hazard_zones", crs, &FIELDS, &features).unwrap();
    features
}

#[test]
fn our_reader_reads_back_what_we_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("hazard_zones.gpkg");
    let features = write_zones(&path, Some(&Crs::from_epsg(2056)));
    let layer = read_layer(&path, None).unwrap();
    assert_eq!(layer.name, "hazard_zones");
    assert_eq!(layer.crs.as_ref().and_then(|c| c.epsg), Some(2056));
    assert_eq!(layer.features.len(), 3);
    for (k, (f, (polygons, values))) in layer.features.iter().zip(&features).enumerate() {
        assert_eq!(f.id, k as i64 + 1);
        assert_eq!(f.geometry, Geometry::Polygons(polygons.clone()));
        for ((name, _), v) in FIELDS.iter().zip(values) {
            assert_eq!(f.attribute(name), Some(v), "{name}");
        }
    }
    // only what we wrote beside the file: no temporary, no journal
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn sqlite_finds_a_sound_geopackage_with_exact_areas() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("zones.gpkg");
    let features = write_zones(&path, Some(&Crs::from_epsg(2056)));
    let db = Connection::open(&path).unwrap();
    let one =
        |sql: &str| -> rusqlite::types::Value { db.query_row(sql, [], |r| r.get(0)).unwrap() };
    use rusqlite::types::Value as Sql;
    assert_eq!(one("PRAGMA integrity_check"), Sql::Text("ok".into()));
    assert_eq!(one("PRAGMA application_id"), Sql::Integer(0x4750_4B47));
    assert_eq!(one("PRAGMA user_version"), Sql::Integer(10300));
    let mut fk = db.prepare("PRAGMA foreign_key_check").unwrap();
    assert!(fk.query([]).unwrap().next().unwrap().is_none());
    let srs: Vec<(i64, String, i64)> = db
        .prepare("SELECT srs_id, organization, organization_coordsys_id FROM gpkg_spatial_ref_sys ORDER BY srs_id")
        .unwrap()
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    let expected = [
        (-1, "NONE", -1),
        (0, "NONE", 0),
        (2056, "EPSG", 2056),
        (4326, "EPSG", 4326),
    ];
    let expected: Vec<(i64, String, i64)> = expected
        .iter()
        .map(|(a, b, c)| (*a, b.to_string(), *c))
        .collect();
    assert_eq!(srs, expected);
    let wkt = one("SELECT definition FROM gpkg_spatial_ref_sys WHERE srs_id = 2056");
    assert!(matches!(wkt, Sql::Text(w) if w.starts_with("PROJCS[\"CH1903+ / LV95\"")));
    let contents = "SELECT data_type || ' ' || min_x || ' ' || min_y || ' ' || max_x || ' ' || max_y || ' ' || srs_id FROM gpkg_contents WHERE table_name = 'hazard_zones'";
    assert_eq!(
        one(contents),
        Sql::Text("features 2600000.0 1200005.0 2600040.0 1200030.0 2056".into())
    );
    let columns = "SELECT column_name || ' ' || geometry_type_name || ' ' || srs_id || z || m FROM gpkg_geometry_columns";
    assert_eq!(one(columns), Sql::Text("geom MULTIPOLYGON 205600".into()));
    let (values, grid) = zones();
    let mut stmt = db
        .prepare("SELECT fid, geom, level FROM hazard_zones ORDER BY fid")
        .unwrap();
    let mut rows = stmt.query([]).unwrap();
    let mut n = 0;
    while let Some(row) = rows.next().unwrap() {
        let (fid, blob, level): (i64, Vec<u8>, i64) = (
            row.get(0).unwrap(),
            row.get(1).unwrap(),
            row.get(2).unwrap(),
        );
        assert_eq!(&blob[..4], b"GP\0\x03", "little endian with an xy envelope");
        let (geometry, srs_id) = decode_gpkg_geometry(&blob).unwrap();
        assert_eq!(srs_id, 2056);
        let Geometry::Polygons(polygons) = geometry else {
            panic!("feature {fid}: {geometry:?}")
        };
        let area: f64 = polygons.iter().flatten().map(|r| signed_area_m2(r)).sum();
        let cells = values.iter().filter(|&&v| i64::from(v) == level).count();
        assert_eq!(area, cells as f64 * grid.cell_area_m2());
        assert_eq!(polygons, features[n].0);
        n += 1;
    }
    assert_eq!(n, 3);
}

/// `ogrinfo` and its arguments' output, `None` (with a notice) without gdal-bin.
fn ogrinfo(args: &[&str]) -> Option<String> {
    match Command::new("ogrinfo").args(args).output() {
        Ok(out) => {
            assert!(
                out.status.success(),
                "ogrinfo {args:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            Some(String::from_utf8_lossy(&out.stdout).into_owned())
        }
        Err(_) if std::env::var_os("CI").is_some() => {
            panic!("ogrinfo is not on PATH: gdal-bin must be installed in CI")
        }
        Err(_) => {
            eprintln!("notice: ogrinfo not found; GDAL's reading not checked (install gdal-bin)");
            None
        }
    }
}

#[test]
fn gdal_reads_the_layer_its_fields_crs_and_values() {
    let dir = tempfile::tempdir().unwrap();
    for (epsg, name) in [(2056, "CH1903+ / LV95"), (32632, "WGS 84 / UTM zone 32N")] {
        let path = dir.path().join(format!("zones_{epsg}.gpkg"));
        write_zones(&path, Some(&Crs::from_epsg(epsg)));
        let file = path.to_str().unwrap();
        let Some(summary) = ogrinfo(&["-al", "-so", file]) else {
            return;
        };
        for expected in [
            "Layer name: hazard_zones",
            "Geometry: Multi Polygon",
            "Feature Count: 3",
            "Extent: (2600000.000000, 1200005.000000) - (2600040.000000, 1200030.000000)",
            &format!("PROJCRS[\"{name}\""),
            &format!("ID[\"EPSG\",{epsg}]]"),
            "FID Column = fid",
            "Geometry Column = geom",
            "level: Integer64",
            "area_m2: Real",
            "label: String",
        ] {
            assert!(summary.contains(expected), "no `{expected}` in:\n{summary}");
        }
        let all = ogrinfo(&["-al", file]).unwrap();
        for expected in [
            "OGRFeature(hazard_zones):1",
            "level (Integer64) = 1",
            "area_m2 (Real) = 425",
            "label (String) = low",
            "OGRFeature(hazard_zones):3",
            "level (Integer64) = 3",
            "label (String) = high",
            "MULTIPOLYGON (((2600000 1200030,",
        ] {
            assert!(all.contains(expected), "no `{expected}` in:\n{all}");
        }
    }
}

/// Validity by GEOS through GDAL's SQLite dialect, where GDAL was built with SpatiaLite: the
/// crafted zones, and speckled blocks whose polygons touch themselves and each other at
/// corners everywhere (a MultiPolygon is valid only when its polygons do not overlap).
#[test]
fn gdal_finds_the_polygons_valid() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("zones.gpkg");
    write_zones(&path, Some(&Crs::from_epsg(2056)));
    let sql = "SELECT fid, ST_IsValid(geom) AS valid, ST_Area(geom) AS area FROM hazard_zones";
    let Some(out) = ogrinfo(&[
        "-q",
        "-dialect",
        "SQLite",
        "-sql",
        sql,
        path.to_str().unwrap(),
    ]) else {
        return;
    };
    if !out.contains("valid (Integer) =") {
        eprintln!("notice: GDAL has no SpatiaLite; validity not checked:\n{out}");
        return;
    }
    assert_eq!(out.matches("valid (Integer) = 1").count(), 3, "{out}");
    for area in [425, 50, 175] {
        assert!(out.contains(&format!("area (Real) = {area}")), "{out}");
    }
    let grid = GridGeometry {
        ncols: 90,
        nrows: 60,
        ..zones().1
    };
    let mut state = 7u64;
    let speckled: Vec<u8> = (0..grid.len())
        .map(|i| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let (row, col) = grid.row_col(i);
            match (state >> 33) % 9 {
                noise @ 0..3 => noise as u8,
                _ => ((row / 7 + col / 11) % 4) as u8,
            }
        })
        .collect();
    write_gpkg_polygons(
        &path,
        "hazard_zones",
        None,
        &FIELDS,
        &features(&speckled, &grid),
    )
    .unwrap();
    let out = ogrinfo(&[
        "-q",
        "-dialect",
        "SQLite",
        "-sql",
        sql,
        path.to_str().unwrap(),
    ])
    .unwrap();
    assert_eq!(out.matches("valid (Integer) = 1").count(), 3, "{out}");
}

#[test]
fn each_crs_is_recorded_as_gdal_and_our_reader_expect() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("zones.gpkg");
    let srs_rows = |path: &Path| -> Vec<(i64, String)> {
        let db = Connection::open(path).unwrap();
        let mut stmt = db
            .prepare("SELECT srs_id, organization FROM gpkg_spatial_ref_sys ORDER BY srs_id")
            .unwrap();
        let rows = stmt.query_map([], |r| Ok((r.get(0)?, r.get(1)?)));
        rows.unwrap().collect::<Result<_, _>>().unwrap()
    };
    let required = [(-1, "NONE"), (0, "NONE"), (4326, "EPSG")];
    let rows = |extra: &[(i64, &str)]| {
        let mut all: Vec<(i64, String)> = (required.iter().chain(extra))
            .map(|(id, org)| (*id, org.to_string()))
            .collect();
        all.sort();
        all
    };
    // none: GeoPackage's undefined Cartesian system
    write_zones(&path, None);
    assert_eq!(srs_rows(&path), rows(&[]));
    assert_eq!(read_layer(&path, None).unwrap().crs, None);
    // WGS 84: the required row, not a second one
    write_zones(&path, Some(&Crs::from_epsg(4326)));
    assert_eq!(srs_rows(&path), rows(&[]));
    assert_eq!(
        read_layer(&path, None).unwrap().crs,
        Some(Crs::from_epsg(4326))
    );
    // a WKT without an EPSG code: a system of our own, read back by its WKT
    let wkt = r#"PROJCS["My local grid",GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]],PROJECTION["Transverse_Mercator"],PARAMETER["latitude_of_origin",0],PARAMETER["central_meridian",10],PARAMETER["scale_factor",1],PARAMETER["false_easting",0],PARAMETER["false_northing",0],UNIT["metre",1]]"#;
    let own = Crs::from_wkt(wkt);
    assert_eq!(own.epsg, None);
    write_zones(&path, Some(&own));
    assert_eq!(srs_rows(&path), rows(&[(100_000, "NONE")]));
    assert_eq!(read_layer(&path, None).unwrap().crs, Some(own));
    if let Some(out) = ogrinfo(&["-al", "-so", path.to_str().unwrap()]) {
        assert!(out.contains("PROJCRS[\"My local grid\""), "{out}");
    }
    // an EPSG code we ship no WKT for: still its code, which GDAL resolves
    write_zones(&path, Some(&Crs::from_epsg(25831)));
    assert_eq!(srs_rows(&path), rows(&[(25831, "EPSG")]));
    let crs = read_layer(&path, None).unwrap().crs.unwrap();
    assert_eq!(crs.epsg, Some(25831));
    if let Some(out) = ogrinfo(&["-al", "-so", path.to_str().unwrap()]) {
        assert!(out.contains("ID[\"EPSG\",25831]]"), "{out}");
    }
}

#[test]
fn empty_geometries_and_empty_layers_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("empty.gpkg");
    let features: Features = vec![(vec![], vec![Value::Null, Value::Null, Value::Null])];
    write_gpkg_polygons(&path, "zones", None, &FIELDS, &features).unwrap();
    let layer = read_layer(&path, None).unwrap();
    assert_eq!(layer.features[0].geometry, Geometry::Empty);
    assert_eq!(layer.features[0].attribute("label"), Some(&Value::Null));
    write_gpkg_polygons(&path, "zones", None, &[], &[]).unwrap();
    assert!(read_layer(&path, None).unwrap().features.is_empty());
    if let Some(out) = ogrinfo(&["-al", "-so", path.to_str().unwrap()]) {
        assert!(out.contains("Feature Count: 0"), "{out}");
    }
}

#[test]
fn a_file_is_replaced_whole_or_left_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("zones.gpkg");
    std::fs::write(&path, b"an older file").unwrap();
    let features = write_zones(&path, None);
    assert_eq!(read_layer(&path, None).unwrap().features.len(), 3);
    let before = std::fs::read(&path).unwrap();
    // a bad feature after good ones: nothing written
    let mut bad = features.clone();
    bad[2].1[0] = Value::Num(2.5);
    let e = write_gpkg_polygons(&path, "hazard_zones", None, &FIELDS, &bad).unwrap_err();
    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "a temporary is left"
    );
    assert_eq!(e.feature, Some(3));
    // a folder that does not exist
    let nowhere = dir.path().join("no/such/folder/zones.gpkg");
    let e = write_gpkg_polygons(&nowhere, "zones", None, &FIELDS, &features).unwrap_err();
    assert_eq!(e.path, nowhere);
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn bad_names_values_and_rings_are_errors_naming_the_feature() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.gpkg");
    let (values, grid) = zones();
    let good = features(&values, &grid);
    let write = |layer: &str, fields: &[(&str, FieldType)], features: &Features| {
        let e = write_gpkg_polygons(&path, layer, None, fields, features).unwrap_err();
        assert!(!path.exists());
        (e.feature, e.to_string())
    };
    let one_field = |name| [(name, FieldType::Integer)];
    let level_only = |f: &Features| -> Features {
        f.iter()
            .map(|(p, v)| (p.clone(), vec![v[0].clone()]))
            .collect()
    };
    for (layer, field, wanted) in [
        ("", "level", "layer name \"\""),
        ("gpkg_zones", "level", "reserved `gpkg_`"),
        ("zones", "fid", "field `fid`"),
        ("zones", "GEOM", "field `GEOM`"),
        ("zones", "rtree_x", "reserved `rtree_`"),
        ("zo\nnes", "level", "control character"),
    ] {
        let (feature, message) = write(layer, &one_field(field), &level_only(&good));
        assert_eq!(feature, None);
        assert!(message.contains(wanted), "{message}");
    }
    let twice = [("level", FieldType::Integer), ("Level", FieldType::Real)];
    assert!(write("zones", &twice, &good).1.contains("twice"));
    type Spoil = fn(&mut Features);
    let cases: [(usize, Spoil, &str); 7] = [
        (1, |f| f[1].1.truncate(2), "2 values for 3 fields"),
        (
            0,
            |f| f[0].1[0] = Value::Text("1".into()),
            "cannot hold Text",
        ),
        (
            2,
            |f| f[2].1[1] = Value::Num(f64::NAN),
            "`area_m2` (Real) cannot hold Num(NaN)",
        ),
        (
            0,
            |f| f[0].1[2] = Value::Num(1.0),
            "`label` (Text) cannot hold",
        ),
        (
            1,
            |f| f[1].0[0][0].truncate(4),
            "ring 0 of polygon 0 is not closed",
        ),
        (
            2,
            |f| f[2].0[0][1][1][0] = f64::INFINITY,
            "ring 1 of polygon 0 has the point (inf",
        ),
        (0, |f| f[0].0[1].clear(), "polygon 1 has no ring"),
    ];
    for (index, spoil, wanted) in cases {
        let mut bad = good.clone();
        spoil(&mut bad);
        let (feature, message) = write("zones", &FIELDS, &bad);
        assert_eq!(feature, Some(index as i64 + 1), "{message}");
        assert!(message.contains(wanted), "{message}");
        assert!(message.contains("bad.gpkg, layer `zones`"), "{message}");
    }
    let short = vec![(vec![vec![vec![[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]]]], vec![])];
    assert!(
        write("zones", &[], &short)
            .1
            .contains("3 points, fewer than 4")
    );
}

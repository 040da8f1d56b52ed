//! Vector inputs on real files written by GDAL's ogr2ogr (`tests/data/vector/make.sh`): the
//! three formats read alike, and burnt onto a grid cell by cell as `gdal_rasterize` burns them.
//!
//! The comparisons with `gdal_rasterize` need gdal-bin; without it they print a notice and
//! pass, except when `CI` is set: then they fail.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_io::vector::inputs::{self, Frame, Outside};
use rockfall_io::vector::{Geometry, Layer, Value, burn, read_layer};
use rockfall_raster::{Crs, GridGeometry};
use std::path::{Path, PathBuf};
use std::process::Command;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/vector")
        .join(name)
}

/// The grid the fixtures are drawn on: 12 × 10 cells of 10 m, EPSG:2154.
fn frame() -> Frame {
    Frame {
        window: None,
        geometry: GridGeometry {
            ncols: 12,
            nrows: 10,
            x_min_m: 900_000.0,
            y_min_m: 6_400_000.0,
            cell_size_m: 10.0,
        },
        crs: Some(Crs::from_epsg(2154)),
    }
}

fn gdal_available() -> bool {
    match Command::new("gdal_rasterize").arg("--version").output() {
        Ok(out) if out.status.success() => true,
        _ if std::env::var_os("CI").is_some() => {
            panic!("gdal_rasterize is not on PATH: gdal-bin must be installed in CI")
        }
        _ => {
            eprintln!("notice: gdal_rasterize not found; comparison skipped (install gdal-bin)");
            false
        }
    }
}

/// `gdal_rasterize` of `layer` in `file` on [`frame`]'s grid, read back: one value per cell,
/// `None` where nothing was burnt.
fn gdal_burn(file: &str, layer: &str, how: &[&str]) -> Vec<Option<f64>> {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("burnt.tif");
    let mut args: Vec<&str> = vec![
        "-q",
        "-l",
        layer,
        "-te",
        "900000",
        "6400000",
        "900120",
        "6400100",
        "-tr",
        "10",
        "10",
        "-ot",
        "Float64",
        "-a_nodata",
        "-9999",
        "-init",
        "-9999",
    ];
    args.extend_from_slice(how);
    let src = data(file);
    let status = Command::new("gdal_rasterize")
        .args(&args)
        .arg(&src)
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success(), "gdal_rasterize {args:?} failed");
    let grid = rockfall_raster::geotiff::read(&out).unwrap();
    assert_eq!(*grid.geometry(), frame().geometry);
    (0..grid.geometry().len())
        .map(|i| grid.get_index(i))
        .collect()
}

fn cells_of(values: &[Option<f64>]) -> Vec<usize> {
    (values.iter().enumerate())
        .filter(|(_, v)| v.is_some())
        .map(|(i, _)| i)
        .collect()
}

#[test]
fn the_three_formats_read_alike() {
    let geojson = read_layer(&data("stands.geojson"), None).unwrap();
    let shp = read_layer(&data("stands.shp"), None).unwrap();
    let gpkg = read_layer(&data("site.gpkg"), Some("stands")).unwrap();
    for l in [&geojson, &shp, &gpkg] {
        assert_eq!(
            l.crs.as_ref().and_then(|c| c.epsg),
            Some(2154),
            "{}",
            l.path.display()
        );
        assert_eq!(l.features.len(), 3);
        let rg: Vec<Option<&Value>> = l.features.iter().map(|f| f.attribute("rg70")).collect();
        assert_eq!(
            rg,
            [
                Some(&Value::Num(0.25)),
                Some(&Value::Num(0.5)),
                Some(&Value::Num(1.0))
            ]
        );
        // the first polygon has its hole, the second is two polygons
        match (&l.features[0].geometry, &l.features[1].geometry) {
            (Geometry::Polygons(a), Geometry::Polygons(b)) => {
                assert_eq!((a.len(), a[0].len(), b.len()), (1, 2, 2));
            }
            other => panic!("{other:?}"),
        }
    }
    // every format burns the same cells
    let f = frame();
    let burn = |l: &Layer| inputs::field_grid(l, "rg70", &f, Outside::Nodata, "rg70_m").unwrap();
    assert_eq!(burn(&geojson), burn(&shp));
    assert_eq!(burn(&geojson), burn(&gpkg));
    let trees = read_layer(&data("site.gpkg"), Some("trees")).unwrap();
    let stems = inputs::stems(&trees, &f).unwrap();
    assert_eq!(stems.len(), 3);
    assert_eq!((stems[0].dbh_cm, stems[0].height_m), (32.5, 24.0));
    assert_eq!(stems[0].species, rockfall_forest::Species::PiceaAbies);
    assert_eq!(stems[2].height_m, 30.5);
    assert_eq!(
        inputs::stems(&read_layer(&data("trees.shp"), None).unwrap(), &f).unwrap(),
        stems
    );
}

#[test]
fn polygons_burn_by_cell_centre_as_gdal_rasterize_does() {
    if !gdal_available() {
        return;
    }
    let layer = read_layer(&data("stands.geojson"), None).unwrap();
    let (ours, covered) =
        inputs::field_grid(&layer, "rg70", &frame(), Outside::Nodata, "rg70_m").unwrap();
    let gdal = gdal_burn("stands.geojson", "stands", &["-a", "rg70"]);
    let ours: Vec<Option<f64>> = (0..gdal.len()).map(|i| ours.get_index(i)).collect();
    assert_eq!(ours, gdal, "cells differ from gdal_rasterize");
    // the fixture exercises a hole, a multipolygon, an overlap (the later feature wins) and
    // edges through cell centres
    assert!(covered > 20);
    assert!(gdal.contains(&Some(1.0)) && gdal.contains(&Some(0.25)));
    let release = read_layer(&data("release.shp"), None).unwrap();
    let cells = inputs::release_cells(&release, &frame()).unwrap();
    assert_eq!(
        cells,
        cells_of(&gdal_burn("release.geojson", "release", &["-burn", "1"]))
    );
}

#[test]
fn lines_burn_every_cell_they_touch_as_gdal_rasterize_at_does() {
    if !gdal_available() {
        return;
    }
    let layer = read_layer(&data("nets.geojson"), None).unwrap();
    let nets = inputs::net_lines(&layer, &frame()).unwrap();
    assert_eq!(nets.iter().map(|n| n.id).collect::<Vec<_>>(), [1, 2]);
    let mut ours: Vec<usize> = nets.iter().flat_map(|n| n.cells.clone()).collect();
    ours.sort_unstable();
    ours.dedup();
    let gdal = cells_of(&gdal_burn("nets.geojson", "nets", &["-at", "-burn", "1"]));
    assert_eq!(ours, gdal);
    let [number, energy, height] = inputs::net_grids(&nets, &frame()).unwrap();
    let c = nets[1].cells[0];
    assert_eq!(
        (
            number.get_index(c),
            energy.get_index(c),
            height.get_index(c)
        ),
        (Some(2.0), Some(3000.0), Some(6.0))
    );
}

#[test]
fn burning_rules_on_hand_made_shapes() {
    let g = GridGeometry {
        ncols: 4,
        nrows: 3,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 1.0,
    };
    // a square whose edges pass through the centres of columns 1 and 3 and rows 0 and 2: a
    // centre on its left edge is out, on its right, top or bottom edge in (what
    // gdal_rasterize 3.6 gives for this square in either ring orientation)
    let square = [[1.5, 0.5], [3.5, 0.5], [3.5, 2.5], [1.5, 2.5], [1.5, 0.5]];
    let cells = burn::polygon_cells(&g, &[&square]);
    assert_eq!(cells, [2, 3, 6, 7, 10, 11]);
    let mut reversed = square;
    reversed.reverse();
    assert_eq!(burn::polygon_cells(&g, &[&reversed]), cells);
    // a hole removes its cells
    let outer = [[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0], [0.0, 0.0]];
    let hole = [[1.2, 1.2], [1.8, 1.2], [1.8, 1.8], [1.2, 1.8], [1.2, 1.2]];
    let with_hole = burn::polygon_cells(&g, &[&outer, &hole]);
    assert_eq!(with_hole.len(), 11);
    assert!(!with_hole.contains(&5));
    // a diagonal line touches the cells it crosses, no more
    let line = burn::line_cells(&g, &[[0.2, 2.9], [2.9, 0.3]]);
    assert_eq!(line, [0, 1, 5, 6, 10]);
}

#[test]
fn bad_layers_are_errors_naming_file_layer_and_feature() {
    let f = frame();
    let stands = read_layer(&data("stands.geojson"), None).unwrap();
    let err = |e: rockfall_io::vector::VectorError| e.to_string();
    let e = err(inputs::field_grid(&stands, "rg20", &f, Outside::Nodata, "rg20_m").unwrap_err());
    assert!(
        e.contains("stands.geojson, layer `stands`, feature 0: no field `rg20`"),
        "{e}"
    );
    let e = err(inputs::field_grid(&stands, "label", &f, Outside::Nodata, "rg70_m").unwrap_err());
    assert!(
        e.contains("feature 0") && e.contains("`with hole`, not a number"),
        "{e}"
    );
    let e = err(inputs::field_grid(&stands, "rg70", &f, Outside::Error, "rock.d1_m").unwrap_err());
    assert!(
        e.contains("`rock.d1_m` has no default") && e.contains("cells lie outside"),
        "{e}"
    );
    let trees = read_layer(&data("trees.geojson"), None).unwrap();
    let e = err(inputs::release_cells(&trees, &f).unwrap_err());
    assert!(
        e.contains("trees.geojson, layer `trees`, feature 0: points where polygons"),
        "{e}"
    );
    let e = err(inputs::stems(&stands, &f).unwrap_err());
    assert!(e.contains("polygons where tree points"), "{e}");
    // far away: no overlap with the DEM
    let mut away = f.clone();
    away.geometry.x_min_m += 10_000.0;
    let e = err(
        inputs::release_cells(&read_layer(&data("release.geojson"), None).unwrap(), &away)
            .unwrap_err(),
    );
    assert!(e.contains("no feature covers a cell of the DEM"), "{e}");
    // another CRS
    let mut notes = Vec::new();
    let e = err(inputs::open(&data("stands_wgs84.geojson"), None, &f, &mut notes).unwrap_err());
    assert!(e.contains("EPSG:4326") && e.contains("EPSG:2154"), "{e}");
    // a GeoPackage of several layers needs the name; an unknown one is named with the others
    let e = err(read_layer(&data("site.gpkg"), None).unwrap_err());
    assert!(e.contains("4 layers") && e.contains("`trees`"), "{e}");
    let e = err(read_layer(&data("site.gpkg"), Some("roads")).unwrap_err());
    assert!(e.contains("no layer `roads`"), "{e}");
    // unreadable files and unknown formats
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes, needle) in [
        (
            "broken.geojson",
            &b"{\"type\": \"FeatureCollection\", \"features\": ["[..],
            "not GeoJSON",
        ),
        (
            "broken.gpkg",
            &b"SQLite format 3\0 but no more"[..],
            "not a readable GeoPackage",
        ),
        ("broken.shp", &b"\0\0\x27\x0a"[..], "no .dbf"),
        ("area.kml", &b"<kml/>"[..], "unknown vector format"),
    ] {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        let e = err(read_layer(&p, None).unwrap_err());
        assert!(e.contains(name) && e.contains(needle), "{e}");
    }
    let e = err(read_layer(&dir.path().join("none.geojson"), None).unwrap_err());
    assert!(e.contains("no such vector file"), "{e}");
}

/// Fuzzing found a polygon record whose part count asked the `shapefile` crate for 4 GB: the
/// counts are now checked against the record's bytes first. The fixture's .shp, with the
/// count of its first record's parts set to 2³⁰, is refused with a message.
#[test]
fn a_shapefile_record_declaring_huge_counts_is_refused_before_reading() {
    let shp = std::fs::read(data("stands.shp")).unwrap();
    let dbf = std::fs::read(data("stands.dbf")).unwrap();
    assert!(rockfall_io::vector::parse_shapefile(&shp, &dbf, None, Path::new("a.shp")).is_ok());
    let mut lying = shp.clone();
    // record 1: header at 100, content at 108, its part count at 108 + 36
    lying[144..148].copy_from_slice(&(1i32 << 30).to_le_bytes());
    let e = rockfall_io::vector::parse_shapefile(&lying, &dbf, None, Path::new("a.shp"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("a.shp") && e.contains("record 1 declares more parts"),
        "{e}"
    );
    // a part starting past the points: the crate would size that part from the difference
    let mut misplaced = shp.clone();
    misplaced[156..160].copy_from_slice(&(1i32 << 28).to_le_bytes());
    let e = rockfall_io::vector::parse_shapefile(&misplaced, &dbf, None, Path::new("a.shp"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("record 1: part 2 starts at point"), "{e}");
    let mut truncated = shp;
    truncated.truncate(130);
    let e = rockfall_io::vector::parse_shapefile(&truncated, &dbf, None, Path::new("a.shp"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("runs past the end"), "{e}");
}

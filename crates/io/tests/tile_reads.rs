//! What a tile reads of a polygon layer: the features whose bounding box meets its window, in
//! the layer's order, from any format; through a GeoPackage's R-tree where it has one; and a
//! tile's per-cell parameters burnt from them exactly as the whole region's. Of a tree list or
//! tree point layer: the stems in its window, in order, every row still checked.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_io::scenario_file::{read_scenario, read_scenario_tile};
use rockfall_io::trees::{TreeFormat, read_tree_list};
use rockfall_io::vector::inputs::{Frame, stems};
use rockfall_io::vector::{Envelope, Layer, parse_geojson, read_layer, read_layer_in};
use rockfall_raster::Window;
use rockfall_scenario::{ForestSpec, Scenario};
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/vector")
        .join(name)
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Envelope {
    Envelope {
        x_min_m: x0,
        y_min_m: y0,
        x_max_m: x1,
        y_max_m: y1,
    }
}

/// The stands of the fixtures (three polygons on the 12 × 10 grid of 10 m cells at
/// (900000, 6400000)): two in the south half, one strip along the north.
const SOUTH: (f64, f64, f64, f64) = (900_000.0, 6_400_000.0, 900_120.0, 6_400_050.0);
const EAST: (f64, f64, f64, f64) = (900_100.0, 6_400_000.0, 900_120.0, 6_400_100.0);
const AWAY: (f64, f64, f64, f64) = (800_000.0, 6_300_000.0, 800_100.0, 6_300_100.0);

/// The window of `ncols` × `nrows` cells from column `col0`, row `row0`.
const fn win(col0: usize, row0: usize, ncols: usize, nrows: usize) -> Window {
    Window {
        col0,
        row0,
        ncols,
        nrows,
    }
}

fn read(file: &str, layer: Option<&str>, r: (f64, f64, f64, f64)) -> Layer {
    read_layer_in(&data(file), layer, Some(rect(r.0, r.1, r.2, r.3))).unwrap()
}

#[test]
fn a_window_reads_the_features_that_meet_it_in_the_layers_order() {
    for (file, layer) in [
        ("site.gpkg", Some("stands")),
        ("stands.geojson", None),
        ("stands.shp", None),
    ] {
        let whole = read_layer(&data(file), layer).unwrap();
        assert_eq!(whole.features.len(), 3, "{file}");
        assert_eq!(whole.within, None);
        // attributes in the table's or the .dbf's field order (GeoJSON's by name)
        for f in whole
            .features
            .iter()
            .filter(|_| !file.ends_with(".geojson"))
        {
            let names: Vec<&str> = f.attributes.iter().map(|(n, _)| n.as_str()).collect();
            assert_eq!(names, ["rg70", "soil", "label"], "{file}");
        }
        for (r, expect) in [(SOUTH, vec![0, 2]), (EAST, vec![1]), (AWAY, vec![])] {
            let part = read(file, layer, r);
            let kept: Vec<_> = part.features.iter().collect();
            let want: Vec<_> = expect.iter().map(|&k| &whole.features[k]).collect();
            assert_eq!(kept, want, "{file} over {r:?}");
            assert_eq!(part.within, Some(rect(r.0, r.1, r.2, r.3)));
            assert_eq!((&part.name, &part.crs), (&whole.name, &whole.crs));
        }
    }
}

/// Copies the fixture GeoPackage into a temporary folder and runs `sql` on the copy.
#[cfg(feature = "gpkg")]
fn edited_gpkg(sql: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("site.gpkg");
    std::fs::copy(data("site.gpkg"), &path).unwrap();
    let db = rusqlite::Connection::open(&path).unwrap();
    db.execute_batch(sql).unwrap();
    (dir, path)
}

#[cfg(feature = "gpkg")]
#[test]
fn a_geopackage_window_is_read_through_its_rtree_or_without_one() {
    let east = Some(rect(EAST.0, EAST.1, EAST.2, EAST.3));
    let ids = |l: &Layer| l.features.iter().map(|f| f.id).collect::<Vec<_>>();
    // the index says the north strip (fid 2) lies far away: a read through the index misses
    // it, a read of the whole layer still has it
    let (_dir, moved) = edited_gpkg(
        "UPDATE rtree_stands_geom SET minx = 0, maxx = 1, miny = 0, maxy = 1 WHERE id = 2;",
    );
    assert_eq!(
        ids(&read_layer_in(&moved, Some("stands"), east).unwrap()),
        Vec::<i64>::new()
    );
    assert_eq!(
        ids(&read_layer(&moved, Some("stands")).unwrap()),
        vec![1, 2, 3]
    );
    // the index's boxes may be looser than the features' (f32, rounded outward): the exact
    // boxes decide
    let (_dir, loose) =
        edited_gpkg("UPDATE rtree_stands_geom SET minx = 0, maxx = 1e7, miny = 0, maxy = 1e7;");
    assert_eq!(
        ids(&read_layer_in(&loose, Some("stands"), east).unwrap()),
        vec![2]
    );
    let south = Some(rect(SOUTH.0, SOUTH.1, SOUTH.2, SOUTH.3));
    assert_eq!(
        ids(&read_layer_in(&loose, Some("stands"), south).unwrap()),
        vec![1, 3]
    );
    // the index's bounds are compared axis by axis: a box east of the window (x beyond its
    // x_max but below its y values) is not read
    let (_dir, east_of) =
        edited_gpkg("UPDATE rtree_stands_geom SET minx = 1000000, maxx = 1000001 WHERE id = 2;");
    assert_eq!(
        ids(&read_layer_in(&east_of, Some("stands"), east).unwrap()),
        Vec::<i64>::new()
    );
    // a primary key that is not the rowid, rows stored against the key's order: a window
    // keeps the whole read's order (which decides overlaps)
    let (_dir, reordered) = edited_gpkg(
        "CREATE TABLE s2(fid INT PRIMARY KEY NOT NULL, geom GEOMETRY, rg70 REAL, soil MEDIUMINT, label TEXT);
         INSERT INTO s2 SELECT fid, geom, rg70, soil, label FROM stands ORDER BY fid DESC;
         DROP TABLE stands; ALTER TABLE s2 RENAME TO stands;",
    );
    assert_eq!(
        ids(&read_layer(&reordered, Some("stands")).unwrap()),
        vec![3, 2, 1]
    );
    assert_eq!(
        ids(&read_layer_in(&reordered, Some("stands"), south).unwrap()),
        vec![3, 1]
    );
    // without the index the whole table is read and filtered
    let (_dir, bare) = edited_gpkg("DROP TABLE rtree_stands_geom;");
    assert_eq!(
        ids(&read_layer_in(&bare, Some("stands"), east).unwrap()),
        vec![2]
    );
    assert_eq!(
        ids(&read_layer_in(&bare, Some("stands"), south).unwrap()),
        vec![1, 3]
    );
}

/// A site of 40 × 30 cells of 10 m with a soil map of 12 × 10 squares of 3 × 3 cells (one
/// polygon each, in a GeoJSON layer), two of them overlapping others, released from a row.
fn squares_site() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let (x0, y0) = (600_000.0, 5_100_000.0);
    let mut dem = format!(
        "ncols 40\nnrows 30\nxllcorner {x0}\nyllcorner {y0}\ncellsize 10\nNODATA_value -9999\n"
    );
    for row in 0..30 {
        let z: Vec<String> = (0..40)
            .map(|c| format!("{}", 500.0 - 6.0 * row as f64 + 0.2 * c as f64))
            .collect();
        dem += &z.join(" ");
        dem.push('\n');
    }
    std::fs::write(dir.path().join("dem.asc"), dem).unwrap();
    let mut features = Vec::new();
    let mut square = |x: f64, y: f64, side: f64, soil: u32| {
        let ring = format!(
            "[[{x},{y}],[{},{y}],[{},{}],[{x},{}],[{x},{y}]]",
            x + side,
            x + side,
            y + side,
            y + side
        );
        features.push(format!(
            r#"{{"type":"Feature","properties":{{"soil":{soil}}},"geometry":{{"type":"Polygon","coordinates":[{ring}]}}}}"#
        ));
    };
    for j in 0..10 {
        for i in 0..12 {
            let (x, y) = (x0 + 5.0 + 33.0 * i as f64, y0 + 2.0 + 29.0 * j as f64);
            square(x, y, 30.0, 1 + ((i + 2 * j) % 6) as u32);
        }
    }
    // two later squares over earlier ones: the later wins
    square(x0 + 100.0, y0 + 100.0, 60.0, 7);
    square(x0 + 300.0, y0 + 200.0, 45.0, 4);
    let geojson = format!(
        r#"{{"type":"FeatureCollection","crs":{{"type":"name","properties":{{"name":"urn:ogc:def:crs:EPSG::2056"}}}},"features":[{}]}}"#,
        features.join(",")
    );
    std::fs::write(dir.path().join("soil.geojson"), geojson).unwrap();
    let scenario = dir.path().join("scenario.toml");
    std::fs::write(
        &scenario,
        r#"
[terrain]
dem = "dem.asc"
epsg = 2056
soiltype = { vector = "soil.geojson", field = "soil" }

[rock]
shape = "sphere"
diameter_m = 0.8

[[release.points]]
x_m = 600205.0
y_m = 5100255.0
"#,
    )
    .unwrap();
    (dir, scenario)
}

#[test]
fn a_tile_burns_its_window_from_the_features_that_meet_it_as_the_region_does() {
    let (_dir, scenario) = squares_site();
    let whole = read_scenario(&scenario).unwrap();
    let note = |s: &rockfall_scenario::Scenario| {
        (s.notes.iter())
            .find(|n| n.starts_with("vector soiltype"))
            .cloned()
            .unwrap()
    };
    assert!(
        note(&whole).contains(": 122 features (polygons)"),
        "{}",
        note(&whole)
    );
    let region = whole.terrain.surface.soil_type.as_grid().unwrap();
    for (col0, row0, ncols, nrows) in [(0, 0, 14, 9), (20, 12, 20, 18), (5, 20, 9, 10)] {
        let window = win(col0, row0, ncols, nrows);
        let core = window;
        let (tile, _) = read_scenario_tile(&scenario, core, window, None).unwrap();
        let n = note(&tile);
        let read: usize = (n.split(": ").nth(2).unwrap().split(' ').next().unwrap())
            .parse()
            .unwrap();
        let layer = read_layer(&scenario.with_file_name("soil.geojson"), None).unwrap();
        let within = Envelope::of_window(region.geometry(), &window);
        let meeting = (layer.features.iter())
            .filter(|f| Envelope::of_geometry(&f.geometry).is_some_and(|b| b.meets(&within)))
            .count();
        assert_eq!(read, meeting, "{n}");
        assert!(
            read < 122 / 2,
            "a window of {ncols} × {nrows} cells read {read} squares"
        );
        assert!(n.contains("features meeting the tile's window"), "{n}");
        let soil = tile.terrain.surface.soil_type.as_grid().unwrap();
        for row in row0..row0 + nrows {
            for col in col0..col0 + ncols {
                assert_eq!(soil.get(row, col), region.get(row, col), "({row}, {col})");
            }
        }
    }
}

/// A tile's window on the squares site: columns 12–26, rows 5–15 (x 600120–600270, y
/// 5100140–5100250).
const WINDOW: Window = win(12, 5, 15, 11);

fn stems_of(s: &Scenario) -> Vec<(f64, f64, f64)> {
    match &s.forest {
        Some(ForestSpec::Stems(st)) => st.iter().map(|t| (t.x_m, t.y_m, t.dbh_cm)).collect(),
        _ => panic!("no explicit stems"),
    }
}

/// 400 trees on a 20 × 20 lattice over the squares site (one every 20 m from (600010,
/// 5100010)), as a CSV, a Rockyfor3D tree file and a GeoJSON point layer.
fn with_trees(dir: &Path) -> Vec<(f64, f64, f64)> {
    let trees: Vec<(f64, f64, f64)> = (0..400)
        .map(|k| {
            let (i, j) = ((k % 20) as f64, (k / 20) as f64);
            (
                600_010.0 + 20.0 * i,
                5_100_010.0 + 14.5 * j,
                20.0 + (k % 7) as f64,
            )
        })
        .collect();
    let mut csv = String::from("# trees of the squares site\nx_m,y_m,dbh_cm\n");
    let mut txt = String::from("x y dbh\n");
    let mut points = Vec::new();
    for (x, y, d) in &trees {
        csv += &format!("{x},{y},{d}\n");
        txt += &format!("{x}\t{y}\t{d}\n");
        points.push(format!(
            r#"{{"type":"Feature","properties":{{"dbh_cm":{d}}},"geometry":{{"type":"Point","coordinates":[{x},{y}]}}}}"#
        ));
    }
    std::fs::write(dir.join("trees.csv"), csv).unwrap();
    std::fs::write(dir.join("treefile.txt"), txt).unwrap();
    let layer = format!(
        r#"{{"type":"FeatureCollection","crs":{{"type":"name","properties":{{"name":"urn:ogc:def:crs:EPSG::2056"}}}},"features":[{}]}}"#,
        points.join(",")
    );
    std::fs::write(dir.join("trees.geojson"), layer).unwrap();
    trees
}

#[test]
fn a_tile_holds_the_stems_of_its_window_from_a_list_or_a_layer() {
    let (dir, scenario) = squares_site();
    let trees = with_trees(dir.path());
    let text = std::fs::read_to_string(&scenario).unwrap();
    let window = WINDOW;
    // the window's rectangle: x 600120–600270, y 5100140–5100250 (rows from the north)
    let inside: Vec<_> = (trees.iter().copied())
        .filter(|t| {
            (600_120.0..=600_270.0).contains(&t.0) && (5_100_140.0..=5_100_250.0).contains(&t.1)
        })
        .collect();
    assert!(!inside.is_empty() && inside.len() < 100, "{}", inside.len());
    for forest in [
        "trees_csv = \"trees.csv\"",
        "treefile = \"treefile.txt\"",
        "trees = \"trees.geojson\"",
    ] {
        std::fs::write(&scenario, format!("{text}\n[forest]\n{forest}\n")).unwrap();
        let whole = read_scenario(&scenario).unwrap();
        assert_eq!(stems_of(&whole), trees, "{forest}");
        let (tile, _) = read_scenario_tile(&scenario, window, window, None).unwrap();
        assert_eq!(stems_of(&tile), inside, "{forest}");
        // a list counts all its trees; a point layer is read over the window only
        let said = tile.notes.iter().any(|n| {
            n.contains(&format!("400 trees, {} in the tile's window", inside.len()))
                || (n.contains(" features meeting the tile's window (points)")
                    && n.contains(&format!(", {} stems", inside.len())))
        });
        assert!(said, "{forest}: {:?}", tile.notes);
        // the scenario read whole and cut to the tile holds the same stems
        let mut cut = whole;
        cut.cut_to_tile(window, window).unwrap();
        assert_eq!(stems_of(&cut), inside, "{forest}");
        // a window without a tree is no error there
        let empty = win(0, 0, 1, 1);
        let (tile, _) = read_scenario_tile(&scenario, empty, empty, None).unwrap();
        assert_eq!(stems_of(&tile), Vec::new(), "{forest}");
    }
}

#[test]
fn a_tree_list_read_for_a_window_still_checks_every_row() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("trees.csv");
    std::fs::write(
        &path,
        "\u{feff}x_m,y_m,dbh_cm\n1,1,30\n\n# far away\n500,500,25\n2,2,40\n",
    )
    .unwrap();
    let near = |s: &rockfall_forest::Stem| s.x_m < 10.0;
    let (kept, all) = read_tree_list(&path, TreeFormat::Csv, near).unwrap();
    assert_eq!(all, 3);
    assert_eq!(
        kept.iter().map(|s| s.dbh_cm).collect::<Vec<_>>(),
        vec![30.0, 40.0]
    );
    // a bad row outside the window is still an error naming its line
    std::fs::write(&path, "x_m,y_m,dbh_cm\n1,1,30\n500,500,-25\n").unwrap();
    let e = read_tree_list(&path, TreeFormat::Csv, near)
        .unwrap_err()
        .to_string();
    assert!(e.contains("trees.csv") && e.contains("line 3"), "{e}");
    // a list without a tree, or a window without one
    std::fs::write(&path, "x y dbh\n# none\n").unwrap();
    let e = read_tree_list(&path, TreeFormat::Treefile, |_| true)
        .unwrap_err()
        .to_string();
    assert!(e.contains("holds no tree"), "{e}");
    std::fs::write(&path, "7 8 30\n9 9 35 1\n").unwrap();
    let (kept, all) = read_tree_list(&path, TreeFormat::Treefile, |_| false).unwrap();
    assert_eq!((kept.len(), all), (0, 2));
}

#[test]
fn a_multipoint_across_a_window_keeps_its_points_inside() {
    let g = rockfall_raster::GridGeometry {
        ncols: 10,
        nrows: 10,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 10.0,
    };
    let west_half = win(0, 0, 5, 10);
    let frame = Frame {
        geometry: g,
        crs: None,
        window: Some(west_half),
    };
    let text = r#"{"type":"FeatureCollection","features":[{"type":"Feature","properties":{"dbh_cm":30},"geometry":{"type":"MultiPoint","coordinates":[[10,10],[90,10],[50,95]]}}]}"#;
    let layer = parse_geojson(text.as_bytes(), Path::new("trees.geojson")).unwrap();
    let kept = stems(&layer, &frame).unwrap();
    assert_eq!(
        kept.iter().map(|s| (s.x_m, s.y_m)).collect::<Vec<_>>(),
        [(10.0, 10.0), (50.0, 95.0)]
    );
}

/// The squares site released from its squares, which also give `rg70_m`.
fn squares_release_site() -> (tempfile::TempDir, PathBuf) {
    let (dir, scenario) = squares_site();
    let text = std::fs::read_to_string(&scenario).unwrap();
    let text = text.replace(
        "[[release.points]]\nx_m = 600205.0\ny_m = 5100255.0\n",
        "[release]\ncells = \"soil.geojson\"\n",
    );
    let text = text.replace("soiltype = {", "rg70_m = {");
    assert!(
        text.contains("cells = \"soil.geojson\"") && text.contains("rg70_m"),
        "{text}"
    );
    std::fs::write(&scenario, text).unwrap();
    (dir, scenario)
}

#[test]
fn a_layer_for_a_key_and_the_release_numbers_the_regions_sources() {
    // the squares give both a per-cell key (read over the window) and the release (read
    // whole without a tile index: a tile's sources keep their numbers among the region's)
    let (_dir, scenario) = squares_release_site();
    let core = win(14, 7, 11, 7);
    let window = WINDOW;
    let mut whole = read_scenario(&scenario).unwrap();
    whole.cut_to_tile(core, window).unwrap();
    let (tile, _) = read_scenario_tile(&scenario, core, window, None).unwrap();
    same_sources(&whole, &tile);
}

/// Asserts two reads of one tile release the same (non-empty) source cells, numbered alike
/// among the same count of the region's.
fn same_sources(expected: &Scenario, tile: &Scenario) {
    assert!(!tile.release.cells.is_empty());
    assert_eq!(expected.release.cells, tile.release.cells);
    let (a, b) = (expected.tile.as_ref().unwrap(), tile.tile.as_ref().unwrap());
    assert_eq!(a.region_source_cells, b.region_source_cells);
    assert_eq!(a.ordinals, b.ordinals);
}

/// The note of `rockfall check` on a scenario's release layer.
fn release_note(s: &Scenario) -> String {
    (s.notes.iter())
        .find(|n| n.starts_with("vector release.cells"))
        .cloned()
        .unwrap()
}

#[test]
fn with_the_index_a_tile_reads_the_release_polygons_of_its_rows_only() {
    let (_dir, scenario) = squares_release_site();
    let layer = read_layer(&scenario.with_file_name("soil.geojson"), None).unwrap();
    let g = *read_scenario(&scenario).unwrap().terrain.dem.geometry();
    for (col0, row0, ncols, nrows) in [(14, 7, 11, 7), (0, 0, 14, 9), (20, 22, 20, 8)] {
        let core = win(col0, row0, ncols, nrows);
        let window = core.grown(2, 40, 30);
        let (whole, counts) = read_scenario_tile(&scenario, core, window, None).unwrap();
        assert!(
            release_note(&whole).contains(": 122 features (polygons)"),
            "{}",
            release_note(&whole)
        );
        let counts = Arc::new(counts.unwrap());
        let (tile, built) = read_scenario_tile(&scenario, core, window, Some(counts)).unwrap();
        assert!(built.is_none(), "the index's counts were used");
        same_sources(&whole, &tile);
        // the polygons meeting the core's rows from the grid's first column (its block)
        let rows = Envelope::of_window(&g, &win(0, row0, col0 + ncols, nrows));
        let meeting = (layer.features.iter())
            .filter(|f| Envelope::of_geometry(&f.geometry).is_some_and(|b| b.meets(&rows)))
            .count();
        let n = release_note(&tile);
        assert!(meeting < 122 / 2, "{meeting}");
        assert!(
            n.contains(&format!(": {meeting} features meeting the tile's window")),
            "{n}"
        );
    }
}

#[test]
fn counts_of_another_file_have_a_tile_read_its_release_whole() {
    let (dir, scenario) = squares_release_site();
    let core = win(14, 7, 11, 7);
    let (expected, counts) = read_scenario_tile(&scenario, core, WINDOW, None).unwrap();
    // the same squares under another name: their counts are of another file
    std::fs::copy(
        dir.path().join("soil.geojson"),
        dir.path().join("other.geojson"),
    )
    .unwrap();
    let text = std::fs::read_to_string(&scenario).unwrap();
    let other = dir.path().join("other.toml");
    std::fs::write(&other, text.replace("cells = \"soil", "cells = \"other")).unwrap();
    let (tile, built) = read_scenario_tile(&other, core, WINDOW, counts.map(Arc::new)).unwrap();
    assert!(built.is_some(), "counted again");
    assert!(release_note(&tile).contains(": 122 features (polygons)"));
    same_sources(&expected, &tile);
}

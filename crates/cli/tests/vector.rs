//! Scenario files with vector inputs, end to end through the binary: a site whose roughness
//! and soil come from polygons, whose release area, stems and nets are a polygon, a point and a
//! line layer (the fixtures ogr2ogr wrote in crates/io/tests/data/vector); `check` describes
//! each layer, `run` uses them, and every kind of bad layer exits 2 naming the file.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{bad_input, json, ok, rockfall, s};
use std::path::{Path, PathBuf};

const SCENARIO: &str = r#"
[terrain]
dem = "dem.asc"
epsg = 2154
rg70_m = { vector = "site.gpkg", layer = "stands", field = "rg70" }
soiltype = { vector = "stands.shp", field = "soil" }

[rock]
shape = "sphere"
diameter_m = 0.8

[release]
cells = "release.geojson"

[forest]
trees = { vector = "site.gpkg", layer = "trees" }

[nets]
lines = "nets.geojson"

[simulation]
rocks_per_cell = 4
"#;

/// Writes `dir/dem.asc`: `ncols × nrows` cells of 10 m with the lower-left corner at
/// (`xll`, `yll`), elevation `z(row, col)` with rows from the north.
fn write_dem(
    dir: &Path,
    (ncols, nrows): (usize, usize),
    (xll, yll): (u32, u32),
    z: impl Fn(usize, usize) -> f64,
) {
    let mut dem = format!(
        "ncols {ncols}\nnrows {nrows}\nxllcorner {xll}\nyllcorner {yll}\ncellsize 10\nNODATA_value -9999\n"
    );
    for row in 0..nrows {
        let line: Vec<String> = (0..ncols).map(|c| format!("{}", z(row, c))).collect();
        dem += &line.join(" ");
        dem.push('\n');
    }
    std::fs::write(dir.join("dem.asc"), dem).unwrap();
}

/// A site folder: a 12 × 10 DEM of 10 m cells falling to the south, the vector fixtures and
/// `scenario.toml` with `SCENARIO` edited by `edit`.
fn site(edit: impl Fn(String) -> String) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    write_dem(dir.path(), (12, 10), (900_000, 6_400_000), |row, c| {
        200.0 - 7.0 * row as f64 + 0.3 * c as f64
    });
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../io/tests/data/vector");
    for e in std::fs::read_dir(&data).unwrap() {
        let p = e.unwrap().path();
        if p.is_file() {
            std::fs::copy(&p, dir.path().join(p.file_name().unwrap())).unwrap();
        }
    }
    let scenario = dir.path().join("scenario.toml");
    std::fs::write(&scenario, edit(SCENARIO.to_string())).unwrap();
    (dir, scenario)
}

#[test]
fn check_describes_each_layer_and_run_uses_them() {
    let (dir, scenario) = site(|s| s);
    let out = ok(rockfall(&["check", s(&scenario)]));
    for needle in [
        "vector rg70:",
        "layer `stands`: 3 features (polygons)",
        "vector soiltype:",
        "vector release.cells:",
        "vector forest.trees:",
        "3 stems",
        "vector nets.lines:",
    ] {
        assert!(out.contains(needle), "{needle} missing from:\n{out}");
    }
    let run_dir = dir.path().join("out");
    ok(rockfall(&[
        "run",
        s(&scenario),
        "--out",
        s(&run_dir),
        "--threads",
        "1",
    ]));
    let summary = json(&run_dir.join("summary.json"));
    // the release polygon covers 7 cells (gdal_rasterize agrees: crates/io/tests/vector.rs)
    assert_eq!(summary["rocks"], 7 * 4);
}

#[test]
fn bad_layers_exit_2_naming_the_file() {
    let cases: [(&str, &str, &[&str]); 7] = [
        (
            "field = \"rg70\" }",
            "field = \"rg99\" }",
            &[
                "site.gpkg",
                "layer `stands`",
                "feature 1",
                "no field `rg99`",
            ],
        ),
        (
            "field = \"soil\"",
            "field = \"label\"",
            &["stands.shp", "feature 0", "not a number"],
        ),
        (
            "cells = \"release.geojson\"",
            "cells = \"trees.geojson\"",
            &["trees.geojson", "feature 0", "points where polygons"],
        ),
        (
            "field = \"soil\"",
            "field = \"soil\", colour = 1",
            &["scenario.toml", "soiltype"],
        ),
        (
            "stands.shp",
            "stands_wgs84.geojson",
            &["stands_wgs84.geojson", "EPSG:4326", "EPSG:2154"],
        ),
        (
            "layer = \"trees\"",
            "layer = \"roads\"",
            &["site.gpkg", "no layer `roads`", "`trees`"],
        ),
        (
            "lines = \"nets.geojson\"",
            "lines = \"nets.kml\"",
            &["nets.kml", "not a vector file"],
        ),
    ];
    for (from, to, needles) in cases {
        let (_dir, scenario) = site(|s| s.replacen(from, to, 1));
        bad_input(rockfall(&["check", s(&scenario)]), needles);
    }
    // a DEM elsewhere: no layer overlaps it
    let (dir, scenario) = site(|s| s);
    let dem = std::fs::read_to_string(dir.path().join("dem.asc")).unwrap();
    std::fs::write(
        dir.path().join("dem.asc"),
        dem.replace("xllcorner 900000", "xllcorner 950000"),
    )
    .unwrap();
    bad_input(
        rockfall(&["check", s(&scenario)]),
        &["no feature covers a cell of the DEM"],
    );
}

/// `rockfall.qgs` opens the run: every layer's file exists where the project says (relative
/// to it), every layer of the tree is defined, the CRS is the DEM's, the rasters carry the
/// renderer of their `.qml` and the DEM is drawn as a hillshade at the bottom.
#[test]
fn run_writes_a_qgis_project_whose_layers_all_exist() {
    let (dir, scenario) = site(|s| {
        s.replace(
            "rocks_per_cell = 4",
            "rocks_per_cell = 4\n[output]\ntrajectories = 3",
        )
    });
    let out = dir.path().join("out");
    ok(rockfall(&[
        "run",
        s(&scenario),
        "--out",
        s(&out),
        "--threads",
        "1",
    ]));
    let text = std::fs::read_to_string(out.join("rockfall.qgs")).unwrap();
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    let doc = roxmltree::Document::parse_with_options(&text, options).unwrap();
    let text_of = |node: roxmltree::Node, tag: &str| {
        node.children()
            .find(|n| n.has_tag_name(tag))
            .and_then(|n| n.text())
            .unwrap_or_default()
            .to_string()
    };
    let crs = doc
        .descendants()
        .find(|n| n.has_tag_name("projectCrs"))
        .unwrap();
    assert!(
        crs.descendants()
            .any(|n| n.has_tag_name("authid") && n.text() == Some("EPSG:2154"))
    );
    let layers: Vec<roxmltree::Node> = doc
        .descendants()
        .filter(|n| n.has_tag_name("maplayer"))
        .collect();
    let mut names = Vec::new();
    for l in &layers {
        let source = text_of(*l, "datasource");
        assert!(out.join(&source).is_file(), "{source} does not exist");
        names.push(text_of(*l, "layername"));
    }
    for name in [
        "Reach_probability",
        "E_95",
        "Ph_95",
        "Nr_passages",
        "trajectories",
        "stems",
        "Hillshade (DEM)",
    ] {
        assert!(
            names.iter().any(|n| n == name),
            "{name} missing from {names:?}"
        );
    }
    let ids: Vec<String> = layers.iter().map(|l| text_of(*l, "id")).collect();
    let tree: Vec<roxmltree::Node> = doc
        .descendants()
        .filter(|n| n.has_tag_name("layer-tree-layer"))
        .collect();
    assert_eq!(tree.len(), layers.len());
    for t in &tree {
        assert!(ids.iter().any(|id| Some(id.as_str()) == t.attribute("id")));
    }
    // the hillshade is the bottom of the tree; the E_95 layer has its style's ramp
    assert_eq!(
        tree.last().unwrap().attribute("name"),
        Some("Hillshade (DEM)")
    );
    let e95 = layers
        .iter()
        .find(|l| text_of(**l, "layername") == "E_95")
        .unwrap();
    let qml = std::fs::read_to_string(out.join("E_95.qml")).unwrap();
    let first_item = qml.lines().find(|l| l.contains("<item ")).unwrap().trim();
    let e95_xml = &text[e95.range()];
    assert!(
        e95_xml.contains(first_item),
        "E_95's renderer differs from E_95.qml"
    );
    // QGIS opens it in the scenario's CRS, the DEM (an ASCII grid without `.prj`) too
    common::qgis_opens(&out.join("rockfall.qgs"), 2154, true);
}

/// `[nets] screens = true`: every net line is also a screen, `net_<id>`, with the net's
/// capacity and height as its limits, read like any screen in `summary.json` and
/// `screen_crossings.csv`; `check` lists it.
#[test]
fn nets_as_screens_carry_the_nets_limits() {
    let (dir, scenario) = site(|s| {
        s.replace(
            "lines = \"nets.geojson\"",
            "lines = \"nets.geojson\"\nscreens = true",
        )
        .replace("rocks_per_cell = 4", "rocks_per_cell = 40")
            + "\n[output]\nscreen_crossings = true\n"
    });
    let listed = ok(rockfall(&["check", s(&scenario)]));
    for needle in [
        "net_1 (net 1, 1000 kJ, 4 m high)",
        "net_2 (net 2, 3000 kJ, 6 m high)",
    ] {
        assert!(listed.contains(needle), "{needle} missing from:\n{listed}");
    }
    let run_dir = dir.path().join("out");
    ok(rockfall(&["run", s(&scenario), "--out", s(&run_dir)]));
    let summary = json(&run_dir.join("summary.json"));
    let screens = summary["screens"].as_array().unwrap();
    let names: Vec<&str> = screens
        .iter()
        .map(|x| x["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["net_1", "net_2"]);
    assert_eq!(screens[0]["capacity_kj"], 1000.0);
    assert_eq!(screens[0]["height_m"], 4.0);
    assert_eq!(screens[1]["capacity_kj"], 3000.0);
    let crossings: u64 = screens
        .iter()
        .map(|x| x["crossings"].as_u64().unwrap())
        .sum();
    assert!(crossings > 0, "{summary}");
    let csv = std::fs::read_to_string(run_dir.join("screen_crossings.csv")).unwrap();
    assert_eq!(csv.lines().count() as u64, crossings + 1, "{csv}");
    assert!(
        csv.lines()
            .skip(1)
            .all(|l| l.contains(",net_1,") || l.contains(",net_2,"))
    );
    // every rock a net stopped was seen by its screen
    let stopped = summary["outcomes"]["net_stopped"].as_u64().unwrap();
    let rocks_seen: std::collections::BTreeSet<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert!(rocks_seen.len() as u64 >= stopped);
}

#[test]
fn tiles_burn_their_windows_of_each_layer_and_merge_into_the_single_run() {
    let (dir, scenario) = site(|s| s);
    let single = dir.path().join("single");
    let run = |extra: &[&str], out: &Path| {
        let mut args = vec!["run", s(&scenario), "--threads", "1", "--out", s(out)];
        args.extend(extra);
        ok(rockfall(&args))
    };
    run(&[], &single);
    // every tile in one process: the release layer's counts kept after the first tile
    let all = dir.path().join("all");
    run(&["--tiles", "4", "--halo-m", "40"], &all);
    common::same_outputs(&single, &all);
    // tiles as separate runs with an index file: the first burns the release layer over
    // the region and writes the counts, the others read and burn the polygons of their own
    // rows only
    let dirs = four_tiles(dir.path(), run);
    // a tile's layers were burnt over less than the grid (12 × 10 cells)
    let first = json(&dirs[0].join("tile.json"));
    assert_eq!(
        first["passes"][0]["window"],
        serde_json::json!([0, 0, 10, 9])
    );
    merge_as_single(dir.path(), &dirs, &single);
}

/// Runs tiles 1/4 to 4/4 (halo 40 m) as separate runs with `run` into `dir`/t1 … t4, with a
/// tile index file `dir`/region.index, which the first writes; their folders.
fn four_tiles(dir: &Path, run: impl Fn(&[&str], &Path) -> String) -> Vec<PathBuf> {
    let index = dir.join("region.index");
    let mut dirs = Vec::new();
    for i in 1..=4 {
        let d = dir.join(format!("t{i}"));
        let tile = format!("{i}/4");
        run(
            &["--tile", &tile, "--halo-m", "40", "--tile-index", s(&index)],
            &d,
        );
        dirs.push(d);
    }
    dirs
}

/// Merges the tiles' folders `dirs` into `dir`/merged and asserts it equals the run `single`.
fn merge_as_single(dir: &Path, dirs: &[PathBuf], single: &Path) {
    let merged = dir.join("merged");
    let mut args = vec!["merge"];
    args.extend(dirs.iter().map(|d| s(d)));
    args.extend(["--out", s(&merged)]);
    ok(rockfall(&args));
    common::same_outputs(single, &merged);
}

/// A 40 × 30 grid of 10 m cells at (600000, 5100000) falling to the south, its soil types
/// from a GeoPackage of 12 × 10 squares written by ogr2ogr (with its R-tree index), a tree
/// every 6 m × 7 m in a CSV, released from a band of cells in the north.
fn squares_site(dir: &Path) -> Option<PathBuf> {
    write_dem(dir, (40, 30), (600_000, 5_100_000), |row, c| {
        500.0 - 6.0 * row as f64 + 0.2 * c as f64
    });
    let polygon = |x: f64, y: f64, w: f64, h: f64, props: String| {
        format!(
            r#"{{"type":"Feature","properties":{{{props}}},"geometry":{{"type":"Polygon","coordinates":[[[{x},{y}],[{},{y}],[{},{}],[{x},{}],[{x},{y}]]]}}}}"#,
            x + w,
            x + w,
            y + h,
            y + h
        )
    };
    let collection = |features: Vec<String>| {
        format!(
            r#"{{"type":"FeatureCollection","crs":{{"type":"name","properties":{{"name":"urn:ogc:def:crs:EPSG::2056"}}}},"features":[{}]}}"#,
            features.join(",")
        )
    };
    let squares = (0..120)
        .map(|k| {
            let (i, j) = ((k % 12) as f64, (k / 12) as f64);
            let soil = format!(r#""soil":{}"#, 1 + (k * 5 % 6));
            polygon(
                600_005.0 + 33.0 * i,
                5_100_002.0 + 29.0 * j,
                30.0,
                30.0,
                soil,
            )
        })
        .collect();
    std::fs::write(dir.join("soil.geojson"), collection(squares)).unwrap();
    let band = polygon(600_020.0, 5_100_250.0, 360.0, 20.0, String::new());
    std::fs::write(dir.join("release.geojson"), collection(vec![band])).unwrap();
    let mut trees = String::from("x_m,y_m,dbh_cm\n");
    for k in 0..66 * 40 {
        let (i, j) = ((k % 66) as f64, (k / 66) as f64);
        trees += &format!(
            "{},{},{}\n",
            600_003.0 + 6.0 * i,
            5_100_004.0 + 7.0 * j,
            15 + k % 20
        );
    }
    std::fs::write(dir.join("trees.csv"), trees).unwrap();
    let made = std::process::Command::new("ogr2ogr")
        .args(["-f", "GPKG", "soil.gpkg", "soil.geojson", "-nln", "soil"])
        .current_dir(dir)
        .status();
    match made {
        Ok(s) if s.success() => {}
        _ if std::env::var_os("CI").is_some() => panic!("ogr2ogr (gdal-bin) is needed in CI"),
        _ => return None,
    }
    let scenario = dir.join("scenario.toml");
    let text = "[terrain]\ndem = \"dem.asc\"\nepsg = 2056\n\
                soiltype = { vector = \"soil.gpkg\", field = \"soil\" }\n\n\
                [rock]\nshape = \"sphere\"\ndiameter_m = 0.8\n\n\
                [release]\ncells = \"release.geojson\"\n\n[forest]\ntrees_csv = \"trees.csv\"\n\n\
                [simulation]\nrocks_per_cell = 3\n";
    std::fs::write(&scenario, text).unwrap();
    Some(scenario)
}

#[test]
fn tiles_read_a_soil_geopackage_and_trees_over_their_windows_and_merge_into_the_single_run() {
    let dir = tempfile::tempdir().unwrap();
    let Some(scenario) = squares_site(dir.path()) else {
        eprintln!("ogr2ogr not found: skipped");
        return;
    };
    let check = ok(rockfall(&["check", s(&scenario)]));
    assert!(
        check.contains("layer `soil`: 120 features (polygons)"),
        "{check}"
    );
    let run = |extra: &[&str], out: &Path| {
        let mut args = vec!["run", s(&scenario), "--threads", "1", "--out", s(out)];
        args.extend(extra);
        ok(rockfall(&args))
    };
    let single = dir.path().join("single");
    run(&[], &single);
    let dirs = four_tiles(dir.path(), run);
    // the first pass of a tile reads less than the grid (40 × 30 cells)
    let first = json(&dirs[0].join("tile.json"));
    let window = &first["passes"][0]["window"];
    assert!(window[2].as_u64().unwrap() < 40, "{window}");
    merge_as_single(dir.path(), &dirs, &single);
}

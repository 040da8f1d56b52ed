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

/// A site folder: a 12 × 10 DEM of 10 m cells falling to the south, the vector fixtures and
/// `scenario.toml` with `SCENARIO` edited by `edit`.
fn site(edit: impl Fn(String) -> String) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let mut dem = String::from(
        "ncols 12\nnrows 10\nxllcorner 900000\nyllcorner 6400000\ncellsize 10\nNODATA_value -9999\n",
    );
    for row in 0..10 {
        let z: Vec<String> = (0..12)
            .map(|c| format!("{}", 200.0 - 7.0 * row as f64 + 0.3 * c as f64))
            .collect();
        dem += &z.join(" ");
        dem.push('\n');
    }
    std::fs::write(dir.path().join("dem.asc"), dem).unwrap();
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

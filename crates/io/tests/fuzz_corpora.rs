//! Every input of the fuzz corpora (`fuzz/corpus/<target>/`) and every crash the fuzzers
//! found (`fuzz/regressions/<target>/`) through the parser its target feeds, on the stable
//! toolchain and in the ordinary test run: each must give a value or an error, never a panic.
//! The fuzz targets themselves (`fuzz/fuzz_targets/`) run under `cargo +nightly fuzz`.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use std::path::{Path, PathBuf};

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz")
}

/// The files of `fuzz/corpus/<target>` and `fuzz/regressions/<target>`; the corpus must not
/// be empty.
fn inputs(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files = Vec::new();
    for kind in ["corpus", "regressions"] {
        let dir = fuzz_dir().join(kind).join(target);
        let Ok(entries) = std::fs::read_dir(&dir) else {
            assert_ne!(kind, "corpus", "no fuzz corpus at {}", dir.display());
            continue;
        };
        for e in entries {
            let path = e.unwrap().path();
            files.push((path.clone(), std::fs::read(&path).unwrap()));
        }
    }
    files.sort();
    assert!(!files.is_empty(), "the fuzz corpus of {target} is empty");
    files
}

fn text(bytes: &[u8]) -> Option<&str> {
    std::str::from_utf8(bytes).ok()
}

#[test]
fn ascii_grid_corpus() {
    for (path, bytes) in inputs("ascii_grid") {
        if let Some(t) = text(&bytes) {
            let _ = rockfall_raster::ascii_grid::parse(t, &path);
        }
    }
}

#[test]
fn tree_list_corpora() {
    for (path, bytes) in inputs("tree_csv") {
        if let Some(t) = text(&bytes) {
            let _ = rockfall_io::trees::parse_tree_csv(t, &path);
        }
    }
    for (path, bytes) in inputs("treefile") {
        if let Some(t) = text(&bytes) {
            let _ = rockfall_io::trees::parse_treefile(t, &path);
        }
    }
}

#[test]
fn rock_shape_corpora() {
    for ext in ["ply", "stl", "obj"] {
        for (_, bytes) in inputs(ext) {
            let _ = rockfall_io::shape::parse_points(Path::new(&format!("rock.{ext}")), &bytes);
        }
    }
}

#[test]
fn scenario_corpus() {
    // the folder the scenario_toml target reads its scenarios in: a DEM, a release raster and
    // a tree list
    let dir = tempfile::tempdir().unwrap();
    let grid = |v: &dyn Fn(usize, usize) -> f64| {
        let mut s = String::from(
            "ncols 4\nnrows 4\nxllcorner 0\nyllcorner 0\ncellsize 10\nNODATA_value -9999\n",
        );
        for r in 0..4 {
            let row: Vec<String> = (0..4).map(|c| v(r, c).to_string()).collect();
            s += &row.join(" ");
            s.push('\n');
        }
        s
    };
    std::fs::write(
        dir.path().join("dem.asc"),
        grid(&|r, _| 100.0 - 10.0 * (3 - r) as f64),
    )
    .unwrap();
    std::fs::write(
        dir.path().join("release.asc"),
        grid(&|r, c| f64::from(u8::from(r == 0 && c == 1))),
    )
    .unwrap();
    std::fs::write(
        dir.path().join("trees.csv"),
        "x_m,y_m,dbh_cm\n15,15,30\n25,12,20\n",
    )
    .unwrap();
    let scenario = dir.path().join("scenario.toml");
    let mut read = 0;
    for (_, bytes) in inputs("scenario_toml") {
        if let Some(t) = text(&bytes) {
            read += usize::from(rockfall_io::scenario_file::parse_scenario(t, &scenario).is_ok());
        }
    }
    // the seed scenarios are valid: the folder above is the one the target builds
    assert!(read >= 3, "only {read} corpus scenarios read");
}

#[test]
fn geotiff_corpus() {
    let mut read = 0;
    for (path, bytes) in inputs("geotiff") {
        read += usize::from(rockfall_raster::geotiff::decode(&bytes, &path).is_ok());
    }
    // the seeds (GDAL's strip, tiled, LZW, PackBits and COG files, and ours) read
    assert!(read >= 8, "only {read} corpus GeoTIFFs read");
}

#[test]
fn vector_corpora() {
    let mut read = 0;
    for (path, bytes) in inputs("geojson") {
        read += usize::from(rockfall_io::vector::parse_geojson(&bytes, &path).is_ok());
    }
    for (_, bytes) in inputs("wkb") {
        read += usize::from(rockfall_io::vector::wkb::decode_gpkg_geometry(&bytes).is_ok());
        let _ = rockfall_io::vector::wkb::decode_wkb(&bytes);
    }
    for (path, bytes) in inputs("shapefile") {
        if bytes.len() >= 2 {
            let n = usize::from(u16::from_le_bytes([bytes[0], bytes[1]])).min(bytes.len() - 2);
            let (shp, dbf) = bytes[2..].split_at(n);
            read +=
                usize::from(rockfall_io::vector::parse_shapefile(shp, dbf, None, &path).is_ok());
        }
    }
    // the seeds: five GeoJSON layers, nine geometry blobs, four Shapefiles from ogr2ogr
    assert!(read >= 18, "only {read} vector corpus inputs read");
}

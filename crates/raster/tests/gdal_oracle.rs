//! GDAL as an oracle: files we write must read in GDAL with the right geometry, CRS and
//! nodata, and files GDAL writes from ours must read back identically.
//!
//! Needs `gdalinfo`/`gdal_translate` (Debian: gdal-bin). Without them the tests print a notice
//! and pass, except when `CI` is set: then they fail, so CI cannot silently skip the oracle.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use std::path::Path;
use std::process::Command;

use rockfall_raster::{
    Crs, Grid, GridGeometry, RasterError, SampleType, Window, ascii_grid, geotiff, read_grid_window,
};
use serde_json::Value;

mod common;
use common::Rule;

const X_MIN: f64 = 912345.5;
const Y_MAX: f64 = 6456789.0;
const CELL: f64 = 2.5;

fn gdal_available() -> bool {
    match Command::new("gdalinfo").arg("--version").output() {
        Ok(out) if out.status.success() => true,
        _ if std::env::var_os("CI").is_some() => {
            panic!(
                "gdalinfo is not on PATH: gdal-bin must be installed to run the GDAL oracle tests in CI"
            )
        }
        _ => {
            eprintln!(
                "notice: gdalinfo not found on PATH; GDAL oracle test skipped (install gdal-bin)"
            );
            false
        }
    }
}

/// 7 × 5 cells, EPSG:2154, four nodata cells.
fn lambert93_grid() -> Grid<f64> {
    let geometry = GridGeometry {
        ncols: 7,
        nrows: 5,
        x_min_m: X_MIN,
        y_min_m: Y_MAX - 5.0 * CELL,
        cell_size_m: CELL,
    };
    Grid::from_fn(geometry, |row, col| {
        ((row + 2 * col) % 6 != 5).then_some(1200.0 + 3.0 * row as f64 - 1.5 * col as f64)
    })
    .with_crs(Some(Crs::from_epsg(2154)))
}

fn run(program: &str, args: &[&str]) -> String {
    let out = Command::new(program).args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{program} {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn gdalinfo(path: &Path) -> Value {
    serde_json::from_str(&run("gdalinfo", &["-json", path.to_str().unwrap()])).unwrap()
}

/// Asserts geotransform, size and EPSG:2154 of a `gdalinfo -json` report.
fn assert_lambert93_geometry(info: &Value) {
    let gt: Vec<f64> = (info["geoTransform"].as_array().unwrap().iter())
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(gt, [X_MIN, CELL, 0.0, Y_MAX, 0.0, -CELL], "{info:#}");
    assert_eq!(info["size"], serde_json::json!([7, 5]));
    let wkt = info["coordinateSystem"]["wkt"].as_str().unwrap();
    assert!(wkt.trim_end().ends_with(r#"ID["EPSG",2154]]"#), "{wkt}");
}

#[test]
fn gdalinfo_reads_our_geotiff_geometry_epsg_and_nodata() {
    if !gdal_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for (sample, gdal_type) in [
        (SampleType::F32, "Float32"),
        (SampleType::F64, "Float64"),
        (SampleType::I32, "Int32"),
    ] {
        let path = dir.path().join(format!("dem-{gdal_type}.tif"));
        geotiff::write(&path, &lambert93_grid(), sample).unwrap();
        let info = gdalinfo(&path);
        assert_lambert93_geometry(&info);
        let band = &info["bands"][0];
        assert_eq!(band["type"], gdal_type, "{band:#}");
        assert_eq!(band["noDataValue"].as_f64(), Some(-9999.0), "{band:#}");
        assert_eq!(info["bands"].as_array().unwrap().len(), 1);
        assert_eq!(info["metadata"][""]["AREA_OR_POINT"], "Area");
    }
}

#[test]
fn gdal_translate_output_reads_back_identically() {
    if !gdal_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let grid = lambert93_grid();
    let ours = dir.path().join("ours.tif");
    // I32 so that GDAL's integer conversions below are exact.
    geotiff::write(&ours, &grid, SampleType::I32).unwrap();
    let expected = geotiff::read(&ours).unwrap();
    assert_eq!(expected.mask(), grid.mask());
    let variants: &[&[&str]] = &[
        &[],
        &["-ot", "Float32", "-co", "COMPRESS=LZW"],
        &[
            "-ot",
            "Float64",
            "-co",
            "TILED=YES",
            "-co",
            "BLOCKXSIZE=16",
            "-co",
            "BLOCKYSIZE=16",
        ],
        &[
            "-ot",
            "Int16",
            "-co",
            "COMPRESS=DEFLATE",
            "-co",
            "PREDICTOR=2",
        ],
        &["-ot", "Int16", "-mo", "AREA_OR_POINT=Point"],
        &["-co", "BIGTIFF=YES", "-co", "TILED=YES"],
    ];
    for (k, options) in variants.iter().enumerate() {
        let theirs = dir.path().join(format!("gdal-{k}.tif"));
        let mut args = vec!["-q", "-of", "GTiff"];
        args.extend_from_slice(options);
        args.extend([ours.to_str().unwrap(), theirs.to_str().unwrap()]);
        run("gdal_translate", &args);
        let back = geotiff::read(&theirs).unwrap_or_else(|e| panic!("{options:?}: {e}"));
        assert_eq!(back.geometry(), grid.geometry(), "{options:?}");
        assert_eq!(back.mask(), expected.mask(), "{options:?}");
        assert_eq!(back.values(), expected.values(), "{options:?}");
        assert_eq!(back.crs().and_then(|c| c.epsg), Some(2154), "{options:?}");
        assert_eq!(back.nodata_value(), Some(-9999.0), "{options:?}");
    }
    // Float32 through GDAL keeps the fractional values exactly.
    let (ours, theirs) = (
        dir.path().join("ours-f32.tif"),
        dir.path().join("gdal-f32.tif"),
    );
    geotiff::write(&ours, &grid, SampleType::F32).unwrap();
    run(
        "gdal_translate",
        &["-q", ours.to_str().unwrap(), theirs.to_str().unwrap()],
    );
    let mut expected = grid.clone();
    expected.set_nodata_value(Some(-9999.0));
    assert_eq!(geotiff::read(&theirs).unwrap(), expected);
    // GDAL puts the directory first: a file cut inside the pixel data must still be an error.
    let bytes = std::fs::read(dir.path().join("gdal-0.tif")).unwrap();
    let cut = dir.path().join("cut.tif");
    std::fs::write(&cut, &bytes[..bytes.len() - 10]).unwrap();
    let err = geotiff::read(&cut).unwrap_err();
    assert!(matches!(err, RasterError::Tiff { .. }), "{err}");
}

#[test]
fn gdalinfo_reads_our_ascii_grid_and_prj() {
    if !gdal_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dem.asc");
    ascii_grid::write(&path, &lambert93_grid()).unwrap();
    let info = gdalinfo(&path);
    assert_lambert93_geometry(&info);
    assert_eq!(info["bands"][0]["noDataValue"].as_f64(), Some(-9999.0));
}

/// The reader decodes strip by strip and tile by tile into place: many strips and tiles,
/// partial ones at the right and bottom edges, compressed, classic and BigTIFF, must all read
/// back as the grid.
#[test]
fn gdal_tiles_and_strips_of_every_shape_read_back_in_place() {
    if !gdal_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let geometry = GridGeometry {
        ncols: 37,
        nrows: 23,
        x_min_m: X_MIN,
        y_min_m: Y_MAX - 23.0 * CELL,
        cell_size_m: CELL,
    };
    let grid = Grid::from_fn(geometry, |row, col| {
        ((row * 7 + col * 3) % 11 != 4).then_some((row * 100 + col) as f64 * 0.25 - 3.0)
    })
    .with_crs(Some(Crs::from_epsg(2154)));
    let ours = dir.path().join("ours.tif");
    geotiff::write(&ours, &grid, SampleType::F64).unwrap();
    let mut expected = grid.clone();
    expected.set_nodata_value(Some(-9999.0));
    assert_eq!(geotiff::read(&ours).unwrap(), expected);
    let tiles = |x: &'static str, y: &'static str| {
        ["-co", "TILED=YES", "-co", x, "-co", y].map(str::to_owned)
    };
    let variants: Vec<Vec<String>> = vec![
        // 5 strips of 5 rows, the last of 3
        vec!["-co".into(), "BLOCKYSIZE=5".into()],
        ["-co", "BLOCKYSIZE=4", "-co", "COMPRESS=DEFLATE"]
            .map(str::to_owned)
            .to_vec(),
        // 3 × 2 tiles of 16 × 16, partial ones at the edges
        tiles("BLOCKXSIZE=16", "BLOCKYSIZE=16").to_vec(),
        [
            tiles("BLOCKXSIZE=32", "BLOCKYSIZE=16").to_vec(),
            vec!["-co".into(), "COMPRESS=PACKBITS".into()],
        ]
        .concat(),
        [
            tiles("BLOCKXSIZE=16", "BLOCKYSIZE=32").to_vec(),
            [
                "-co",
                "BIGTIFF=YES",
                "-co",
                "COMPRESS=DEFLATE",
                "-co",
                "PREDICTOR=3",
            ]
            .map(str::to_owned)
            .to_vec(),
        ]
        .concat(),
    ];
    for (k, options) in variants.iter().enumerate() {
        let theirs = dir.path().join(format!("gdal-{k}.tif"));
        let mut args = vec!["-q", "-of", "GTiff"];
        args.extend(options.iter().map(String::as_str));
        args.extend([ours.to_str().unwrap(), theirs.to_str().unwrap()]);
        run("gdal_translate", &args);
        let back = geotiff::read(&theirs).unwrap_or_else(|e| panic!("{options:?}: {e}"));
        assert_eq!(back, expected, "{options:?}");
        // windows across strip and tile edges, and at the grid's edges, read alone
        for w in [
            (3, 4, 20, 9),
            (15, 15, 3, 3),
            (0, 22, 37, 1),
            (36, 0, 1, 23),
            (17, 5, 20, 18),
        ] {
            let w = Window {
                col0: w.0,
                row0: w.1,
                ncols: w.2,
                nrows: w.3,
            };
            let part = read_grid_window(&theirs, &w).unwrap();
            assert_eq!(part, expected.window(&w).unwrap(), "{options:?} {w:?}");
        }
    }
}

/// GDAL's COG validator, as Debian's python3-gdal installs it (a dependency of gdal-bin).
const VALIDATOR: &str =
    "/usr/lib/python3/dist-packages/osgeo_utils/samples/validate_cloud_optimized_geotiff.py";

/// Runs GDAL's COG validator on `path` with the system Python (the one with the `osgeo`
/// bindings) and asserts that it passes without warnings. `false` when the validator is not
/// installed (a failure under `CI`).
fn assert_valid_cog(path: &Path) -> bool {
    if !Path::new(VALIDATOR).is_file() {
        assert!(
            std::env::var_os("CI").is_none(),
            "{VALIDATOR} is missing: python3-gdal must be installed to validate COGs in CI"
        );
        eprintln!("notice: {VALIDATOR} not found; COG validation skipped (install python3-gdal)");
        return false;
    }
    let out = Command::new("/usr/bin/python3")
        .args([VALIDATOR, path.to_str().unwrap()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}: {text}", path.display());
    assert!(
        text.contains("is a valid cloud optimized GeoTIFF"),
        "{text}"
    );
    assert!(!text.contains("warning"), "{text}");
    true
}

/// Every sample type and size class: tiles of 256, the overviews down to one tile, the type,
/// the nodata marker, Deflate with its predictor, and GDAL's COG layout — and the validator
/// passes without warnings.
#[test]
fn gdal_sees_valid_cogs() {
    if !gdal_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let shapes: [(usize, usize, &[[u64; 2]]); 4] = [
        (1, 1, &[]),
        (256, 256, &[]),
        (600, 520, &[[300, 260], [150, 130]]),
        (1100, 257, &[[550, 129], [275, 65], [138, 33]]),
    ];
    let types = [
        (SampleType::F32, "Float32", "3"),
        (SampleType::F64, "Float64", "3"),
        (SampleType::I32, "Int32", "2"),
    ];
    for (ncols, nrows, overviews) in shapes {
        for (sample, gdal_type, predictor) in types {
            let path = dir.path().join(format!("{ncols}x{nrows}-{gdal_type}.tif"));
            let grid = common::grid(ncols, nrows, |r, c| {
                (r * ncols + c != 0).then_some(((r * 7 + c * 3) % 100) as f64)
            });
            geotiff::write(&path, &grid, sample).unwrap();
            let info = gdalinfo(&path);
            let band = &info["bands"][0];
            let what = format!("{}: {band:#}", path.display());
            assert_eq!(band["block"], serde_json::json!([256, 256]), "{what}");
            assert_eq!(band["type"], gdal_type, "{what}");
            assert_eq!(band["noDataValue"].as_f64(), Some(-9999.0), "{what}");
            let sizes: Vec<Value> = overviews
                .iter()
                .map(|s| serde_json::json!({ "size": s }))
                .collect();
            assert_eq!(
                band["overviews"].as_array().cloned().unwrap_or_default(),
                sizes,
                "{what}"
            );
            let structure = &info["metadata"]["IMAGE_STRUCTURE"];
            assert_eq!(structure["COMPRESSION"], "DEFLATE", "{what}");
            assert_eq!(structure["PREDICTOR"], predictor, "{what}");
            assert_eq!(structure["LAYOUT"], "COG", "{what}");
            assert_valid_cog(&path);
            // GDAL's own COG driver, with our tile size, makes the same overview levels
            let theirs = path.with_extension("gdal.tif");
            let (from, to) = (path.to_str().unwrap(), theirs.to_str().unwrap());
            run(
                "gdal_translate",
                &["-q", "-of", "COG", "-co", "BLOCKSIZE=256", from, to],
            );
            assert_eq!(
                gdalinfo(&theirs)["bands"][0]["overviews"],
                band["overviews"],
                "{what}"
            );
        }
    }
}

/// The raw cells of `path` (overview `ovr` when given, 0 = the largest) as GDAL reads them:
/// `gdal_translate` to ENVI (raw samples, little-endian) and the bytes decoded here.
fn gdal_cells(path: &Path, ovr: Option<usize>, sample: SampleType) -> Vec<f64> {
    let out = path.with_extension(format!("ovr{}.img", ovr.map_or(-1, |k| k as i64)));
    let ovr = ovr.map(|k| k.to_string());
    let mut args = vec!["-q", "-of", "ENVI"];
    if let Some(k) = &ovr {
        args.extend(["-ovr", k]);
    }
    args.extend([path.to_str().unwrap(), out.to_str().unwrap()]);
    run("gdal_translate", &args);
    let bytes = std::fs::read(&out).unwrap();
    match sample {
        SampleType::F32 => (bytes.chunks_exact(4))
            .map(|b| f64::from(f32::from_le_bytes(b.try_into().unwrap())))
            .collect(),
        SampleType::F64 => (bytes.chunks_exact(8))
            .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
            .collect(),
        SampleType::I32 => (bytes.chunks_exact(4))
            .map(|b| f64::from(i32::from_le_bytes(b.try_into().unwrap())))
            .collect(),
    }
}

/// GDAL reads the full resolution as we wrote it, bit for bit, and the overviews as the
/// resampling rules give them from the grid, block by block: the mean of the valid cells for
/// floats (nodata where a block has none), the centre cell for integers.
#[test]
fn gdal_reads_our_cells_and_overviews_exactly() {
    if !gdal_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            common::grid(600, 520, common::ramp),
            SampleType::F32,
            Rule::MeanF32,
        ),
        (
            common::grid(600, 520, common::ramp),
            SampleType::F64,
            Rule::MeanF64,
        ),
        (
            common::grid(600, 520, common::counts),
            SampleType::I32,
            Rule::Centre,
        ),
    ];
    for (grid, sample, rule) in cases {
        let path = dir.path().join(format!("{sample:?}.tif"));
        geotiff::write(&path, &grid, sample).unwrap();
        let full: Vec<f64> = (grid.values().iter().zip(grid.mask()))
            .map(|(&v, &ok)| if ok { v } else { -9999.0 })
            .collect();
        assert!(gdal_cells(&path, None, sample) == full, "{sample:?}");
        for k in 1..=2 {
            let expected = common::expected_level(&grid, k, rule);
            let gdal = gdal_cells(&path, Some(k as usize - 1), sample);
            assert!(gdal == expected, "{sample:?} level {k}");
        }
    }
}

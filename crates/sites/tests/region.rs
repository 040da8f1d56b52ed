//! `alpine-region`: deterministic files, source cells and soil classes that follow the slope
//! of the DEM as written, and sizes checked.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_raster::read_grid;
use rockfall_sites::region::{self, CLIFF_DEG, RegionSpec, soil_type};

fn spec(cells: u64) -> RegionSpec {
    RegionSpec {
        cells,
        cell_size_m: 5.0,
        seed: 7,
    }
}

/// Horn's slope (degrees) of cell (row, col) of `z` (n × n, row 0 north), edges repeated:
/// what `gdaldem slope` computes.
fn horn(z: &[f64], n: usize, row: usize, col: usize, cell: f64) -> f64 {
    let at = |r: usize, c: usize| z[r.min(n - 1) * n + c.min(n - 1)];
    let (r0, c0) = (row.saturating_sub(1), col.saturating_sub(1));
    let (r2, c2) = (row + 1, col + 1);
    let dzdx = (at(r0, c2) + 2.0 * at(row, c2) + at(r2, c2))
        - (at(r0, c0) + 2.0 * at(row, c0) + at(r2, c0));
    let dzdy = (at(r2, c0) + 2.0 * at(r2, col) + at(r2, c2))
        - (at(r0, c0) + 2.0 * at(r0, col) + at(r0, c2));
    (dzdx / (8.0 * cell))
        .hypot(dzdy / (8.0 * cell))
        .atan()
        .to_degrees()
}

#[test]
fn a_region_is_the_same_for_a_seed_and_its_layers_follow_the_slope() {
    let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let files = region::write(a.path(), &spec(40_000)).unwrap();
    region::write(b.path(), &spec(40_000)).unwrap();
    assert_eq!(files.len(), 8);
    for f in &files {
        let name = f.file_name().unwrap();
        assert_eq!(
            std::fs::read(f).unwrap(),
            std::fs::read(b.path().join(name)).unwrap(),
            "{name:?}"
        );
    }
    let dem = read_grid(&a.path().join("dem.tif")).unwrap();
    let g = *dem.geometry();
    assert_eq!((g.ncols, g.nrows, g.cell_size_m), (200, 200, 5.0));
    assert_eq!(dem.crs().and_then(|c| c.epsg), Some(2056));
    let z: Vec<f64> = dem.values().to_vec();
    let release = read_grid(&a.path().join("release.tif")).unwrap();
    let soil = read_grid(&a.path().join("soiltype.tif")).unwrap();
    let rg10 = read_grid(&a.path().join("rg10.tif")).unwrap();
    let (mut sources, mut talus) = (0, 0);
    for row in 0..200 {
        for col in 0..200 {
            let s = horn(&z, 200, row, col, 5.0);
            let k = row * 200 + col;
            let src = release.values()[k] > 0.0;
            assert_eq!(src, s >= CLIFF_DEG, "({row}, {col}): slope {s}°");
            assert_eq!(soil.values()[k], f64::from(soil_type(s)));
            sources += usize::from(src);
            talus += usize::from(soil.values()[k] == 4.0 && (rg10.values()[k] - 0.3).abs() < 1e-6);
        }
    }
    // cliffs, talus and floors are all there
    assert!((200..20_000).contains(&sources), "{sources} source cells");
    assert!(talus > 1_000, "{talus}");
    // another seed, another relief
    let c = tempfile::tempdir().unwrap();
    region::write(
        c.path(),
        &RegionSpec {
            seed: 8,
            ..spec(40_000)
        },
    )
    .unwrap();
    assert_ne!(
        std::fs::read(a.path().join("dem.tif")).unwrap(),
        std::fs::read(c.path().join("dem.tif")).unwrap()
    );
}

#[test]
fn sizes_and_cell_sizes_out_of_range_are_refused() {
    let d = tempfile::tempdir().unwrap();
    for bad in [
        spec(9_999),
        spec(5_000_000_000),
        RegionSpec {
            cell_size_m: 0.5,
            ..spec(40_000)
        },
        RegionSpec {
            cell_size_m: f64::NAN,
            ..spec(40_000)
        },
    ] {
        let e = region::write(d.path(), &bad).unwrap_err();
        assert!(matches!(e, region::RegionError::Spec(_)), "{e}");
    }
    assert!(
        std::fs::read_dir(d.path()).unwrap().next().is_none(),
        "nothing written"
    );
}

//! Windows of a raster read alone equal the same cells of the whole raster, for our tiled
//! COGs (windows across tile edges, at the grid's edges, inside one tile) and ASCII grids;
//! a window outside the raster is refused naming it. (GDAL's strip and tile layouts:
//! `gdal_oracle.rs`.)

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_raster::{
    Crs, Grid, GridGeometry, RasterError, SampleType, Window, read_geometry, read_grid,
    read_grid_window, write_grid,
};

fn grid(ncols: usize, nrows: usize) -> Grid<f64> {
    let g = GridGeometry {
        ncols,
        nrows,
        x_min_m: 2_600_000.0,
        y_min_m: 1_100_000.0,
        cell_size_m: 2.0,
    };
    Grid::from_fn(g, |row, col| {
        ((row * 13 + col * 7) % 17 != 3).then_some((row * 1000 + col) as f64 * 0.5)
    })
    .with_crs(Some(Crs::from_epsg(2056)))
}

/// Windows of a 600 × 520 grid (tiles of 256): inside one tile, across tile corners, along
/// every edge, a single cell, a single row, the whole grid.
const WINDOWS: [Window; 8] = [
    Window {
        col0: 10,
        row0: 20,
        ncols: 30,
        nrows: 40,
    },
    Window {
        col0: 250,
        row0: 250,
        ncols: 20,
        nrows: 20,
    },
    Window {
        col0: 0,
        row0: 0,
        ncols: 600,
        nrows: 1,
    },
    Window {
        col0: 599,
        row0: 519,
        ncols: 1,
        nrows: 1,
    },
    Window {
        col0: 500,
        row0: 300,
        ncols: 100,
        nrows: 220,
    },
    Window {
        col0: 0,
        row0: 255,
        ncols: 257,
        nrows: 2,
    },
    Window {
        col0: 300,
        row0: 0,
        ncols: 1,
        nrows: 520,
    },
    Window {
        col0: 0,
        row0: 0,
        ncols: 600,
        nrows: 520,
    },
];

#[test]
fn a_window_of_a_cog_or_an_ascii_grid_is_those_cells_of_the_whole() {
    let dir = tempfile::tempdir().unwrap();
    let whole = grid(600, 520);
    for (name, sample) in [
        ("f32.tif", SampleType::F32),
        ("f64.tif", SampleType::F64),
        ("i32.tif", SampleType::I32),
        ("grid.asc", SampleType::F32),
    ] {
        let path = dir.path().join(name);
        write_grid(&path, &whole, sample).unwrap();
        let read = read_grid(&path).unwrap();
        let (g, crs) = read_geometry(&path).unwrap();
        assert_eq!(
            (g, crs.and_then(|c| c.epsg)),
            (*read.geometry(), Some(2056)),
            "{name}"
        );
        for w in WINDOWS {
            let part = read_grid_window(&path, &w).unwrap();
            let expected = read.window(&w).unwrap();
            assert!(part == expected, "{name} {w:?}: the window differs");
            // the window's corner is where its first cell lies in the whole grid
            let (x, y) = part.geometry().cell_center(0, 0);
            assert_eq!(
                read.geometry().cell_of(x, y),
                Some((w.row0, w.col0)),
                "{name}"
            );
        }
    }
}

#[test]
fn a_window_outside_the_raster_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dem.tif");
    write_grid(&path, &grid(40, 30), SampleType::F32).unwrap();
    for w in [
        Window {
            col0: 30,
            row0: 0,
            ncols: 11,
            nrows: 5,
        },
        Window {
            col0: 0,
            row0: 30,
            ncols: 1,
            nrows: 1,
        },
        Window {
            col0: 0,
            row0: 0,
            ncols: 0,
            nrows: 5,
        },
        Window {
            col0: usize::MAX,
            row0: 0,
            ncols: 2,
            nrows: 2,
        },
    ] {
        match read_grid_window(&path, &w) {
            Err(RasterError::Invalid { path: p, message }) => {
                assert_eq!(p, path);
                assert!(message.contains("outside its 40 × 30 cells"), "{message}");
            }
            other => panic!("{w:?}: {other:?}"),
        }
    }
}

#[test]
fn a_window_decodes_only_the_tiles_it_touches() {
    use tiff::decoder::Decoder;
    use tiff::tags::Tag;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dem.tif");
    write_grid(&path, &grid(600, 520), SampleType::F32).unwrap();
    let intact = read_grid(&path).unwrap();
    // the last tile of the full resolution (south-east corner) garbled
    let mut bytes = std::fs::read(&path).unwrap();
    let mut dec = Decoder::new(std::io::Cursor::new(&bytes)).unwrap();
    let offsets = dec.get_tag_u64_vec(Tag::TileOffsets).unwrap();
    let counts = dec.get_tag_u64_vec(Tag::TileByteCounts).unwrap();
    let (at, n) = (
        *offsets.last().unwrap() as usize,
        *counts.last().unwrap() as usize,
    );
    for b in &mut bytes[at..at + n] {
        *b = 0xff;
    }
    std::fs::write(&path, &bytes).unwrap();
    assert!(
        read_grid(&path).is_err(),
        "the whole file reads the garbled tile"
    );
    // a window of the north-west tiles never reads it
    let w = Window {
        col0: 0,
        row0: 0,
        ncols: 300,
        nrows: 300,
    };
    let part = read_grid_window(&path, &w).unwrap();
    assert!(part == intact.window(&w).unwrap(), "the window differs");
    // one that reaches into the garbled tile does read it
    let w = Window {
        col0: 590,
        row0: 515,
        ncols: 5,
        nrows: 5,
    };
    assert!(read_grid_window(&path, &w).is_err());
}

//! Writes one large synthetic raster through [`rockfall_raster::write_rows`], for timing the
//! GeoTIFF writer and measuring its memory: the cells are computed row by row (a [`Rows`]
//! view, no grid in memory), so the process's peak memory is the writer's.
//!
//! The raster is dense, a smooth field over a slope (`f32`/`f64`) with nodata west of a
//! diagonal, or counts falling off away from three paths (`i32`); with `sparse` it looks like
//! a result map of a regional run: values only along the three paths, nodata (floats) or 0
//! (counts) elsewhere.
//!
//! ```sh
//! cargo run --release -p rockfall-raster --example write_raster -- OUT.tif NCOLS NROWS [f32|f64|i32] [sparse]
//! /usr/bin/time -v target/release/examples/write_raster OUT.tif 4000 4000   # "Maximum resident set size"
//! ```
//!
//! Prints the seconds spent writing and the file's size. `bench/geotiff.sh` runs the sizes
//! of the memory benchmark.

use std::path::PathBuf;
use std::time::Instant;

use rockfall_raster::{Crs, GridGeometry, Rows, SampleType, write_rows};

/// A synthetic raster computed cell by cell.
struct Synthetic {
    geometry: GridGeometry,
    crs: Crs,
    counts: bool,
    sparse: bool,
}

impl Synthetic {
    /// Cell (row, col): `None` west of the diagonal for floats, else a value.
    fn cell(&self, row: usize, col: usize) -> Option<f64> {
        let (r, c) = (row as f64, col as f64);
        let n = self.geometry.ncols as f64;
        // three paths down the slope
        let d = (0..3)
            .map(|k| (c - (k as f64 + 0.5) * n / 3.0 - 0.02 * r).abs())
            .fold(f64::INFINITY, f64::min);
        if self.sparse && d > 20.0 {
            return self.counts.then_some(0.0);
        }
        if self.counts {
            // counts decaying away from the paths
            return Some((1000.0 * (-d / 40.0).exp()).floor());
        }
        if c < 0.1 * r {
            return None;
        }
        let h = (row.wrapping_mul(7919) ^ col.wrapping_mul(104_729)) % 1000;
        Some(2000.0 - 0.7 * r + 30.0 * (c / 97.0).sin() + h as f64 * 1e-3)
    }
}

impl Rows for Synthetic {
    fn geometry(&self) -> GridGeometry {
        self.geometry
    }

    fn crs(&self) -> Option<&Crs> {
        Some(&self.crs)
    }

    fn nodata_value(&self) -> Option<f64> {
        None
    }

    fn row(&self, row: usize, out: &mut [Option<f64>]) {
        for (col, o) in out.iter_mut().enumerate() {
            *o = self.cell(row, col);
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [out, ncols, nrows, rest @ ..] = args.as_slice() else {
        return Err("usage: write_raster OUT.tif NCOLS NROWS [f32|f64|i32] [sparse]".into());
    };
    let sample = match rest.first().map(String::as_str) {
        None | Some("f32") => SampleType::F32,
        Some("f64") => SampleType::F64,
        Some("i32") => SampleType::I32,
        Some(other) => return Err(format!("unknown sample type {other:?}").into()),
    };
    let raster = Synthetic {
        geometry: GridGeometry {
            ncols: ncols.parse()?,
            nrows: nrows.parse()?,
            x_min_m: 900_000.0,
            y_min_m: 6_400_000.0,
            cell_size_m: 2.0,
        },
        crs: Crs::from_epsg(2154),
        counts: sample == SampleType::I32,
        sparse: rest.get(1).map(String::as_str) == Some("sparse"),
    };
    let out = PathBuf::from(out);
    let start = Instant::now();
    write_rows(&out, &raster, sample)?;
    let seconds = start.elapsed().as_secs_f64();
    let bytes = std::fs::metadata(&out)?.len();
    println!(
        "{}: {ncols} × {nrows} {sample:?}{} written in {seconds:.2} s, {bytes} bytes",
        out.display(),
        if raster.sparse { " sparse" } else { "" }
    );
    Ok(())
}

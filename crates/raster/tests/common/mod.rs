//! Grids and the overview rules computed from their definition, for the GeoTIFF tests.

#![allow(dead_code)] // each test file uses a part

use rockfall_raster::{Crs, Grid, GridGeometry};

/// `ncols` × `nrows` cells of 2.5 m, Lambert-93; values from `value(row, col)`, nodata where
/// it gives `None`.
pub fn grid(ncols: usize, nrows: usize, value: impl Fn(usize, usize) -> Option<f64>) -> Grid<f64> {
    let g = GridGeometry {
        ncols,
        nrows,
        x_min_m: 912_000.5,
        y_min_m: 6_456_000.25,
        cell_size_m: 2.5,
    };
    Grid::from_fn(g, value).with_crs(Some(Crs::from_epsg(2154)))
}

/// A value exact in f32 (quarters), with a nodata cell every 7th and a pattern that changes
/// across tile edges.
pub fn quarters(r: usize, c: usize) -> Option<f64> {
    ((r * 3 + c) % 7 != 2).then(|| ((r * 31 + c * 17) % 1001) as f64 * 0.25 - 100.0)
}

/// A ramp that differs in every cell, with nodata on a diagonal pattern and a 4 × 4 nodata
/// square at (8, 8): a level-2 block without a valid cell.
pub fn ramp(r: usize, c: usize) -> Option<f64> {
    let hole = (8..12).contains(&r) && (8..12).contains(&c) || (r + 2 * c).is_multiple_of(11);
    (!hole).then(|| (r * 600 + c) as f64 * 0.5)
}

/// Counts without nodata.
pub fn counts(r: usize, c: usize) -> Option<f64> {
    Some(((r * 7 + c * 13) % 50) as f64)
}

/// An overview rule and the sample type its values are stored in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// The mean of the valid cells, stored as f32.
    MeanF32,
    /// The mean of the valid cells, stored as f64.
    MeanF64,
    /// The cell at the centre of the block.
    Centre,
}

/// Overview level `k` of `g`, row-major, computed from the definition block by block by
/// `rule`; −9999 for nodata.
pub fn expected_level(g: &Grid<f64>, k: u32, rule: Rule) -> Vec<f64> {
    let (n, m) = (g.geometry().ncols, g.geometry().nrows);
    let side = 1 << k;
    let (w, h) = (n.div_ceil(side), m.div_ceil(side));
    let block = |i: usize, len: usize| (i * side)..((i + 1) * side).min(len);
    let centre = |b: std::ops::Range<usize>| (b.start + b.end) / 2;
    let mut out = Vec::new();
    for i in 0..h {
        for j in 0..w {
            let (rows, cols) = (block(i, m), block(j, n));
            let cells: Vec<f64> = (rows.clone())
                .flat_map(|r| cols.clone().filter_map(move |c| g.get(r, c)))
                .collect();
            let mean = cells.iter().sum::<f64>() / cells.len() as f64;
            out.push(match rule {
                _ if rule != Rule::Centre && cells.is_empty() => -9999.0,
                Rule::MeanF32 => f64::from(mean as f32),
                Rule::MeanF64 => mean,
                Rule::Centre => g.get(centre(rows), centre(cols)).unwrap_or(-9999.0),
            });
        }
    }
    out
}

//! Writes a large synthetic site for memory measurements: `dem.tif` (a slope that flattens
//! into a plain, with deterministic noise) and `scenario.toml` (constant surface parameters,
//! two release points near the top of the slope, 1 000 rocks each), so that the rocks reach a
//! small part of a huge grid. With `asc` the DEM is written as `dem.asc` (ESRI ASCII grid);
//! with `rasters` the soil type and the three obstacle heights are rasters too (four classes
//! in bands across the slope), as in a Rockyfor3D folder.
//!
//! ```sh
//! cargo run --release -p rockfall-raster --example big_site -- OUT_DIR NCOLS NROWS [CELL_M] [tif|asc] [rasters]
//! /usr/bin/time -v rockfall run OUT_DIR/scenario.toml --out RUN_DIR   # "Maximum resident set size"
//! ```
//!
//! `bench/memory.sh` runs both sizes of the issue (4 000² and 10 000² cells at 2 m).

use std::path::PathBuf;

use rockfall_raster::{Crs, Grid, GridGeometry, SampleType, write_grid};

/// Height of the terrain at `d_m` metres south of the northern edge and `x_m` east of the
/// western edge: a 35° slope for 400 m, easing into a plain over the next 200 m, plus ±0.2 m
/// of hashed noise.
fn height_m(d_m: f64, x_m: f64, noise: u64) -> f64 {
    const TOP_M: f64 = 400.0;
    const EASE_M: f64 = 200.0;
    let tan = 0.7;
    let drop = if d_m < TOP_M {
        tan * d_m
    } else if d_m < TOP_M + EASE_M {
        let s = d_m - TOP_M;
        tan * (TOP_M + s - 0.5 * s * s / EASE_M)
    } else {
        tan * (TOP_M + 0.5 * EASE_M)
    };
    let h = noise.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let h = (h ^ (h >> 29)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let unit = (h >> 11) as f64 / (1u64 << 53) as f64;
    2000.0 - drop + 0.4 * (unit - 0.5) + 0.001 * x_m
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [out, ncols, nrows, rest @ ..] = args.as_slice() else {
        return Err("usage: big_site OUT_DIR NCOLS NROWS [CELL_M] [tif|asc] [rasters]".into());
    };
    let (out, ncols, nrows) = (PathBuf::from(out), ncols.parse()?, nrows.parse()?);
    let cell: f64 = rest.first().map_or(Ok(2.0), |c| c.parse())?;
    let dem = match rest.get(1).map(String::as_str) {
        None | Some("tif") => "dem.tif",
        Some("asc") => "dem.asc",
        Some(other) => return Err(format!("unknown DEM format {other:?}: tif or asc").into()),
    };
    let geometry = GridGeometry {
        ncols,
        nrows,
        x_min_m: 900_000.0,
        y_min_m: 6_400_000.0,
        cell_size_m: cell,
    };
    let rasters = rest.get(2).map(String::as_str) == Some("rasters");
    std::fs::create_dir_all(&out)?;
    let grid = Grid::from_fn(geometry, |row, col| {
        let d = (row as f64 + 0.5) * cell;
        let x = (col as f64 + 0.5) * cell;
        Some(height_m(d, x, (row * ncols + col) as u64))
    })
    .with_crs(Some(Crs::from_epsg(2154)));
    write_grid(&out.join(dem), &grid, SampleType::F32)?;
    drop(grid);
    // soil type 3 or 4 and obstacle heights in bands 400 m wide across the slope; without
    // `rasters`, the constants of the second band
    let band = |col: usize| (col as f64 * cell / 400.0) as usize % 4;
    let surface = [
        ("soiltype", [3.0, 4.0, 4.0, 3.0]),
        ("rg70", [0.1, 0.05, 0.0, 0.2]),
        ("rg20", [0.2, 0.1, 0.05, 0.3]),
        ("rg10", [0.3, 0.2, 0.1, 0.5]),
    ];
    let mut terrain = String::new();
    for (name, classes) in surface {
        let value = if rasters {
            let file = format!("{name}.tif");
            let grid = Grid::from_fn(geometry, |_, col| Some(classes[band(col)]))
                .with_crs(Some(Crs::from_epsg(2154)));
            write_grid(&out.join(&file), &grid, SampleType::F32)?;
            format!("\"{file}\"")
        } else {
            format!("{}", classes[1])
        };
        let key = if name == "soiltype" {
            name.to_string()
        } else {
            format!("{name}_m")
        };
        terrain.push_str(&format!("{key} = {value}\n"));
    }
    let x_mid = geometry.x_min_m + 0.5 * ncols as f64 * cell;
    let y_top = geometry.y_max_m() - 60.0;
    let scenario = format!(
        r#"name = "big-site-{ncols}x{nrows}"
engine = "lumped"
seed = 1

[terrain]
dem = "{dem}"
{terrain}
[rock]
shape = "sphere"
diameter_m = 0.8
density_kg_m3 = 2800

[simulation]
rocks_per_point = 1000

[release]
height_m = 1.0

[[release.points]]
x_m = {x1}
y_m = {y_top}

[[release.points]]
x_m = {x2}
y_m = {y_top}
"#,
        x1 = x_mid - 100.0,
        x2 = x_mid + 100.0,
    );
    std::fs::write(out.join("scenario.toml"), scenario)?;
    println!("{}: {ncols} × {nrows} cells of {cell} m", out.display());
    Ok(())
}

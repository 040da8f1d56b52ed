//! `alpine-region`: a procedural mountain region of any size, written as tiled,
//! Cloud-Optimised GeoTIFFs with a scenario file: the regional test site and benchmark.
//!
//! What it holds (every rule ours, see [`relief`] for the heights):
//!
//! - **The DEM** ([`Relief`]): ridges, valleys with floors, cliff bands with talus benches
//!   below them, square, `ncols = nrows = round(√cells)`, cells of `cell_size_m` (default
//!   [`DEFAULT_CELL_M`]), in Swiss LV95 (EPSG 2056) from (2 600 000, 1 100 000). Deterministic
//!   from the seed: the same seed and size give the same files.
//! - **Source cells** where the slope (Horn's 3 × 3 gradient, as GDAL's `gdaldem slope`)
//!   is at least [`CLIFF_DEG`]. The threshold follows Loye, Jaboyedoff & Pedrazzini (2009,
//!   NHESS 9, 1643–1653): a cell is a potential source where its slope is above the angle at
//!   which the slope distribution's "rock cliff" mode dominates the "steep slope" mode. On
//!   this relief the cliffs are built at 70–80° and the flanks at 25–45°, so the modes part
//!   near 45°, the value we take.
//! - **Soil type and roughness** by slope class: ≥ 45° bedrock (6), 30–45° talus (4), 15–30°
//!   scree (3), below 15° fine soil (2); rg70/rg20/rg10 per class in [`ROUGHNESS_M`].
//! - **Forest stands** on slopes of 10–42° (not the valley floors, not the cliffs) between
//!   800 m and the tree line at 1 900 m, where a slow forest field is positive (about half of
//!   those slopes): [`STEMS_PER_HA`] stems/ha, DBH 28 ± 10 cm.
//!
//! The DEM is held as `f32` while the files are written (4 bytes per cell: 4 GB at 10⁹
//! cells); every other raster is computed row by row from it as it is written.

pub mod relief;

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use rockfall_raster::{Crs, GridGeometry, Rows, SampleType};

pub use relief::Relief;

/// Cell size unless given, m.
pub const DEFAULT_CELL_M: f64 = 5.0;
/// Cells unless given.
pub const DEFAULT_CELLS: u64 = 1_000_000;
/// Fewest cells.
pub const MIN_CELLS: u64 = 10_000;
/// Most cells (the DEM is held as 4 bytes per cell while the files are written).
pub const MAX_CELLS: u64 = 4_000_000_000;
/// Slope at and above which a cell is a source cell, degrees (Loye et al. 2009; see the module
/// docs).
pub const CLIFF_DEG: f64 = 45.0;
/// Obstacle heights rg70, rg20, rg10 (m) of soil types 2, 3, 4 and 6 (ours: smooth fine soil,
/// scree, coarse talus, bare rock).
pub const ROUGHNESS_M: [(u8, [f64; 3]); 4] = [
    (2, [0.01, 0.02, 0.05]),
    (3, [0.03, 0.06, 0.12]),
    (4, [0.08, 0.15, 0.30]),
    (6, [0.0, 0.0, 0.0]),
];
/// Stems per hectare of the forest stands.
pub const STEMS_PER_HA: f64 = 350.0;
/// EPSG code and south-west corner of the region, m.
const EPSG: u32 = 2056;
const ORIGIN_M: (f64, f64) = (2_600_000.0, 1_100_000.0);

/// What to write.
#[derive(Debug, Clone, Copy)]
pub struct RegionSpec {
    /// Cells of the DEM (rounded to a square).
    pub cells: u64,
    /// Cell size, m.
    pub cell_size_m: f64,
    /// Seed of the relief.
    pub seed: u64,
}

/// Why a region could not be written.
#[derive(Debug, thiserror::Error)]
pub enum RegionError {
    /// The size or cell size is out of range.
    #[error("{0}")]
    Spec(String),
    /// A raster could not be written.
    #[error(transparent)]
    Raster(#[from] rockfall_raster::RasterError),
    /// A file could not be written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

/// The DEM of a region, held as `f32`, with its geometry.
struct Heights {
    geometry: GridGeometry,
    crs: Crs,
    z: Vec<f32>,
}

impl Heights {
    fn generate(spec: &RegionSpec) -> Heights {
        let side = (spec.cells as f64).sqrt().round() as usize;
        let h = spec.cell_size_m;
        let geometry = GridGeometry {
            ncols: side,
            nrows: side,
            x_min_m: ORIGIN_M.0,
            y_min_m: ORIGIN_M.1,
            cell_size_m: h,
        };
        let relief = Relief::new(spec.seed);
        let mut z = vec![0f32; side * side];
        z.par_chunks_mut(side).enumerate().for_each(|(row, out)| {
            for (col, v) in out.iter_mut().enumerate() {
                let (x, y) = relief_xy(&geometry, row, col);
                *v = relief.height_m(x, y) as f32;
            }
        });
        Heights {
            geometry,
            crs: Crs::from_epsg(EPSG),
            z,
        }
    }

    fn at(&self, row: usize, col: usize) -> f64 {
        let n = self.geometry.ncols;
        f64::from(self.z[row.min(self.geometry.nrows - 1) * n + col.min(n - 1)])
    }

    /// Slope of cell (row, col), degrees: Horn's (1981) 3 × 3 gradient, edges repeated.
    fn slope_deg(&self, row: usize, col: usize) -> f64 {
        let (r0, r2) = (row.saturating_sub(1), row + 1);
        let (c0, c2) = (col.saturating_sub(1), col + 1);
        let z = |r, c| self.at(r, c);
        let dzdx = ((z(r0, c2) + 2.0 * z(row, c2) + z(r2, c2))
            - (z(r0, c0) + 2.0 * z(row, c0) + z(r2, c0)))
            / (8.0 * self.geometry.cell_size_m);
        let dzdy = ((z(r2, c0) + 2.0 * z(r2, col) + z(r2, c2))
            - (z(r0, c0) + 2.0 * z(r0, col) + z(r0, c2)))
            / (8.0 * self.geometry.cell_size_m);
        dzdx.hypot(dzdy).atan().to_degrees()
    }
}

/// Relief coordinates (m from the region's south-west corner) of the centre of cell (row,
/// col): the relief does not depend on where the region is placed.
fn relief_xy(g: &GridGeometry, row: usize, col: usize) -> (f64, f64) {
    let h = g.cell_size_m;
    ((col as f64 + 0.5) * h, (g.nrows - row) as f64 * h - 0.5 * h)
}

/// Soil type (Rockyfor3D's classes) of a cell of slope `deg`.
pub fn soil_type(deg: f64) -> u8 {
    match deg {
        d if d >= CLIFF_DEG => 6,
        d if d >= 30.0 => 4,
        d if d >= 15.0 => 3,
        _ => 2,
    }
}

/// One raster of the region, computed row by row from the heights.
struct Layer<'a> {
    heights: &'a Heights,
    relief: Relief,
    value: fn(&Heights, Relief, usize, usize) -> f64,
}

impl Rows for Layer<'_> {
    fn geometry(&self) -> GridGeometry {
        self.heights.geometry
    }

    fn crs(&self) -> Option<&Crs> {
        Some(&self.heights.crs)
    }

    fn nodata_value(&self) -> Option<f64> {
        None
    }

    fn row(&self, row: usize, out: &mut [Option<f64>]) {
        for (col, o) in out.iter_mut().enumerate() {
            *o = Some((self.value)(self.heights, self.relief, row, col));
        }
    }
}

fn roughness(deg: f64, k: usize) -> f64 {
    let t = soil_type(deg);
    (ROUGHNESS_M.iter())
        .find(|r| r.0 == t)
        .map_or(0.0, |r| r.1[k])
}

/// Stems per hectare at cell (row, col).
fn stems(h: &Heights, relief: Relief, row: usize, col: usize) -> f64 {
    let z = h.at(row, col);
    let (x, y) = relief_xy(&h.geometry, row, col);
    let field = relief.forest(x, y);
    let slope = h.slope_deg(row, col);
    let forest = (800.0..1_900.0).contains(&z) && (10.0..42.0).contains(&slope) && field > 0.0;
    if forest { STEMS_PER_HA } else { 0.0 }
}

/// The rasters written: file name, sample type, value.
type LayerSpec = (
    &'static str,
    SampleType,
    fn(&Heights, Relief, usize, usize) -> f64,
);

const LAYERS: [LayerSpec; 7] = [
    ("dem.tif", SampleType::F32, |h, _, r, c| h.at(r, c)),
    ("release.tif", SampleType::I32, |h, _, r, c| {
        f64::from(u8::from(h.slope_deg(r, c) >= CLIFF_DEG))
    }),
    ("soiltype.tif", SampleType::I32, |h, _, r, c| {
        f64::from(soil_type(h.slope_deg(r, c)))
    }),
    ("rg70.tif", SampleType::F32, |h, _, r, c| {
        roughness(h.slope_deg(r, c), 0)
    }),
    ("rg20.tif", SampleType::F32, |h, _, r, c| {
        roughness(h.slope_deg(r, c), 1)
    }),
    ("rg10.tif", SampleType::F32, |h, _, r, c| {
        roughness(h.slope_deg(r, c), 2)
    }),
    ("stems_per_ha.tif", SampleType::F32, stems),
];

/// Checks `spec`: an error naming the option out of range.
pub fn check(spec: &RegionSpec) -> Result<(), RegionError> {
    if !(MIN_CELLS..=MAX_CELLS).contains(&spec.cells) {
        return Err(RegionError::Spec(format!(
            "--cells {}: give {MIN_CELLS} to {MAX_CELLS} cells",
            spec.cells
        )));
    }
    if !(spec.cell_size_m.is_finite() && (1.0..=25.0).contains(&spec.cell_size_m)) {
        return Err(RegionError::Spec(format!(
            "--cell-size-m {}: give 1 to 25 m",
            spec.cell_size_m
        )));
    }
    Ok(())
}

/// Writes the region into `out` (an existing folder): the rasters and `scenario.toml`.
/// Returns the files written.
pub fn write(out: &Path, spec: &RegionSpec) -> Result<Vec<PathBuf>, RegionError> {
    check(spec)?;
    let heights = Heights::generate(spec);
    let relief = Relief::new(spec.seed);
    let written: Vec<Result<PathBuf, RegionError>> = LAYERS
        .par_iter()
        .map(|&(name, sample, value)| {
            let path = out.join(name);
            let layer = Layer {
                heights: &heights,
                relief,
                value,
            };
            rockfall_raster::geotiff::write_rows(&path, &layer, sample)?;
            Ok(path)
        })
        .collect();
    let mut files = written.into_iter().collect::<Result<Vec<_>, _>>()?;
    let path = out.join("scenario.toml");
    std::fs::write(&path, scenario_toml(spec, &heights.geometry)).map_err(|source| {
        RegionError::Io {
            path: path.clone(),
            source,
        }
    })?;
    files.push(path);
    Ok(files)
}

/// The scenario file of a region.
fn scenario_toml(spec: &RegionSpec, g: &GridGeometry) -> String {
    format!(
        r#"# rockfall scenario "alpine-region", written by `rockfall site alpine-region`:
# a procedural mountain region of {ncols} × {nrows} cells of {cell} m (seed {seed}).
# Source cells: slope ≥ {cliff}° (Loye et al. 2009). Paths are relative to this file.

name = "alpine-region"
engine = "lumped"
seed = 1

[terrain]
dem = "dem.tif"
soiltype = "soiltype.tif"
rg70_m = "rg70.tif"
rg20_m = "rg20.tif"
rg10_m = "rg10.tif"

[rock]
shape = "sphere"
diameter_m = 1.0
density_kg_m3 = 2700.0

[release]
cells = "release.tif"          # cells > 0 are source cells
height_m = 0.5

[forest]
stems_per_ha = "stems_per_ha.tif"
dbh_mean_cm = 28.0
dbh_sd_cm = 10.0

[simulation]
rocks_per_cell = 10
"#,
        ncols = g.ncols,
        nrows = g.nrows,
        cell = spec.cell_size_m,
        seed = spec.seed,
        cliff = CLIFF_DEG,
    )
}

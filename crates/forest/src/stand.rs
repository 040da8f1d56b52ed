//! Stand expansion: from per-cell stand descriptions to explicit stems.
//!
//! Forest inventories and Rockyfor3D-style inputs describe forest per raster cell: stems per
//! hectare, mean and standard deviation of DBH, the conifer share and, sometimes, heights. The
//! rockfall engines need explicit stems, so each cell is expanded as follows.
//!
//! 1. **Count.** The expected number of stems is n = stems/ha × cell area / 10⁴ m². The cell
//!    gets ⌊n⌋ stems plus one more with probability n − ⌊n⌋. The count is unbiased (its mean
//!    is n), like a Poisson draw, but its variance is only frac(n)·(1 − frac(n)) ≤ ¼ instead
//!    of n: a stand described as 290 stems/ha really has close to 290 stems per hectare,
//!    rather than adding Poisson clumping on top of the (already random) positions.
//! 2. **Positions**: uniform over the cell.
//! 3. **DBH** from a normal truncated to [`StandOptions::dbh_min_cm`, `dbh_max_cm`], whose
//!    parent parameters are solved so that the *truncated* distribution has the cell's mean
//!    and sd (see [`crate::truncated_normal`]; solved once per distinct (mean, sd) pair).
//!    An sd of 0 gives every stem the mean. Requests no truncated normal can meet (sd too large
//!    for the lower bound, mean outside the bounds) fail with [`ForestError::InfeasibleDbh`].
//! 4. **Species**: [`Species::OtherConifer`] with probability conifer % / 100, else
//!    [`Species::OtherBroadleaf`].
//! 5. **Height**: when the cell gives (mean, sd), from N(mean, sd) truncated to above breast
//!    height (these are the parent parameters; the truncation removes a negligible share for
//!    real stands), independent of DBH. Otherwise from DBH by
//!    [`crate::allometry::height_from_dbh_m`].
//!
//! # Reproducibility
//!
//! Cell (row, col) draws from its own stream,
//! `rockfall_rng::stream(seed, Purpose::StandExpansion, &[row-major cell index])`, in a fixed
//! layout: one uniform for the count, then per stem five uniforms (x, y, DBH, species,
//! height — the height uniform is drawn even when the allometry is used). The stems of a cell
//! therefore depend only on the seed, the cell's index and its description: not on the other
//! cells, the order of expansion or the number of threads. Expanding a sub-region (cells
//! outside it returning `None`) reproduces exactly the stems of those cells.
//!
//! Stems are returned cell by cell in row-major order.
//!
//! ```
//! use rockfall_forest::{StandCell, StandOptions, expand_stands};
//! use rockfall_raster::GridGeometry;
//! let geometry = GridGeometry { ncols: 4, nrows: 4, x_min_m: 0.0, y_min_m: 0.0, cell_size_m: 25.0 };
//! let stand = StandCell {
//!     stems_per_ha: 290.0, dbh_mean_cm: 31.0, dbh_sd_cm: 21.0, conifer_percent: 75.0, height: None,
//! };
//! let stems = expand_stands(&geometry, |_, _| Some(stand), 42, &StandOptions::default())?;
//! assert!(stems.iter().all(|s| s.dbh_cm >= 5.0 && s.height_m > 1.3));
//! # Ok::<(), rockfall_forest::ForestError>(())
//! ```

use std::collections::HashMap;

use rand::RngExt;
use rockfall_raster::{GridGeometry, Window};
use rockfall_rng::{Purpose, stream};

use crate::allometry::height_from_dbh_m;
use crate::truncated_normal::TruncatedNormal;
use crate::{BREAST_HEIGHT_M, ForestError, Species, Stem};

/// Largest stem density accepted, stems/ha (10 stems per m²): a guard against unit mix-ups
/// that would otherwise try to allocate billions of stems.
pub const MAX_STEMS_PER_HA: f64 = 100_000.0;

/// Square metres per hectare.
const M2_PER_HA: f64 = 10_000.0;

/// The forest of one raster cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StandCell {
    /// Stem density, stems/ha (≥ 0, at most [`MAX_STEMS_PER_HA`]). A cell with 0 gets no
    /// stems and its other fields are not checked.
    pub stems_per_ha: f64,
    /// Mean DBH of the stems above the calliper threshold, cm (> 0).
    pub dbh_mean_cm: f64,
    /// Standard deviation of DBH, cm (≥ 0).
    pub dbh_sd_cm: f64,
    /// Share of conifers among the stems, % (0–100).
    pub conifer_percent: f64,
    /// Mean and standard deviation of tree height, m (mean > 1.3, sd ≥ 0); `None` to derive
    /// heights from DBH.
    pub height: Option<(f64, f64)>,
}

/// Settings of stand expansion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StandOptions {
    /// Smallest DBH generated, cm (the inventory's calliper threshold; default 5).
    pub dbh_min_cm: f64,
    /// Largest DBH generated, cm (default 250; may be `f64::INFINITY`).
    pub dbh_max_cm: f64,
}

impl Default for StandOptions {
    fn default() -> Self {
        StandOptions {
            dbh_min_cm: 5.0,
            dbh_max_cm: 250.0,
        }
    }
}

/// Expands the stands of a grid into stems (see the module docs). `cell(row, col)` describes
/// the forest of a cell (row 0 north), or `None` for no forest; `seed` is the run's master seed.
///
/// Fails on the first invalid cell (row-major order) with an error naming its row and column.
pub fn expand_stands(
    geometry: &GridGeometry,
    cell: impl Fn(usize, usize) -> Option<StandCell>,
    seed: u64,
    options: &StandOptions,
) -> Result<Vec<Stem>, ForestError> {
    expand_stands_in(geometry, &Window::whole(geometry), cell, seed, options)
}

/// [`expand_stands`] over the cells of `window` only: each cell's stems are those the whole
/// grid's expansion gives it (every cell draws from its own stream, keyed by its row-major
/// index on `geometry`), so a spatial tile of a region gets exactly the region's stems in
/// its window.
pub fn expand_stands_in(
    geometry: &GridGeometry,
    window: &Window,
    cell: impl Fn(usize, usize) -> Option<StandCell>,
    seed: u64,
    options: &StandOptions,
) -> Result<Vec<Stem>, ForestError> {
    check_options(options)?;
    check_geometry(geometry)?;
    let half = 0.5 * geometry.cell_size_m;
    let mut dbh_fits: HashMap<(u64, u64), TruncatedNormal> = HashMap::new();
    let mut stems = Vec::new();
    let rows = window.row0..(window.row0 + window.nrows).min(geometry.nrows);
    let cols = window.col0..(window.col0 + window.ncols).min(geometry.ncols);
    for row in rows {
        for col in cols.clone() {
            let Some(stand) = cell(row, col) else {
                continue;
            };
            if !check_stand(&stand, row, col)? {
                continue;
            }
            let key = (stand.dbh_mean_cm.to_bits(), stand.dbh_sd_cm.to_bits());
            let dbh = match dbh_fits.get(&key) {
                Some(fit) => *fit,
                None => {
                    let fit = fit_dbh(&stand, options, row, col)?;
                    dbh_fits.insert(key, fit);
                    fit
                }
            };
            let height = match stand.height {
                Some((mean, sd)) => Some(
                    TruncatedNormal::from_parent(mean, sd, BREAST_HEIGHT_M, f64::INFINITY)
                        .map_err(|_| invalid(row, col, "height mean", mean, HEIGHT_RULE))?,
                ),
                None => None,
            };

            let mut rng = stream(
                seed,
                Purpose::StandExpansion,
                &[geometry.index(row, col) as u64],
            );
            let expected = stand.stems_per_ha * geometry.cell_area_m2() / M2_PER_HA;
            let extra = rng.random::<f64>() < expected.fract();
            let count = expected.floor() as usize + usize::from(extra);
            let (cx, cy) = geometry.cell_center(row, col);
            let conifer_probability = stand.conifer_percent / 100.0;
            stems.reserve(count);
            for _ in 0..count {
                let x_m = cx + (2.0 * rng.random::<f64>() - 1.0) * half;
                let y_m = cy + (2.0 * rng.random::<f64>() - 1.0) * half;
                let dbh_cm = dbh.sample(&mut rng);
                let species = if rng.random::<f64>() < conifer_probability {
                    Species::OtherConifer
                } else {
                    Species::OtherBroadleaf
                };
                let u_height: f64 = rng.random();
                let height_m = match &height {
                    Some(distribution) => distribution.quantile(u_height),
                    None => height_from_dbh_m(dbh_cm),
                };
                stems.push(Stem {
                    x_m,
                    y_m,
                    dbh_cm,
                    // Keep strictly above breast height even at the truncation bound.
                    height_m: height_m.max(BREAST_HEIGHT_M.next_up()),
                    species,
                });
            }
        }
    }
    Ok(stems)
}

const HEIGHT_RULE: &str = "must be finite and above breast height (1.3 m)";

fn invalid(
    row: usize,
    col: usize,
    field: &'static str,
    value: f64,
    requirement: &'static str,
) -> ForestError {
    ForestError::InvalidStand {
        row,
        col,
        field,
        value,
        requirement,
    }
}

/// Checks a cell's values; `Ok(false)` when the cell has no stems (nothing else checked).
fn check_stand(stand: &StandCell, row: usize, col: usize) -> Result<bool, ForestError> {
    let n = stand.stems_per_ha;
    if !(n.is_finite() && (0.0..=MAX_STEMS_PER_HA).contains(&n)) {
        return Err(invalid(
            row,
            col,
            "stems_per_ha",
            n,
            "must be finite, ≥ 0 and ≤ 100000 stems/ha",
        ));
    }
    if n == 0.0 {
        return Ok(false);
    }
    let d = stand.dbh_mean_cm;
    if !(d.is_finite() && d > 0.0) {
        return Err(invalid(
            row,
            col,
            "dbh_mean_cm",
            d,
            "must be finite and > 0",
        ));
    }
    let s = stand.dbh_sd_cm;
    if !(s.is_finite() && s >= 0.0) {
        return Err(invalid(row, col, "dbh_sd_cm", s, "must be finite and ≥ 0"));
    }
    let c = stand.conifer_percent;
    if !(c.is_finite() && (0.0..=100.0).contains(&c)) {
        return Err(invalid(
            row,
            col,
            "conifer_percent",
            c,
            "must be between 0 and 100",
        ));
    }
    if let Some((mean, sd)) = stand.height {
        if !(mean.is_finite() && mean > BREAST_HEIGHT_M) {
            return Err(invalid(row, col, "height mean", mean, HEIGHT_RULE));
        }
        if !(sd.is_finite() && sd >= 0.0) {
            return Err(invalid(row, col, "height sd", sd, "must be finite and ≥ 0"));
        }
    }
    Ok(true)
}

fn fit_dbh(
    stand: &StandCell,
    options: &StandOptions,
    row: usize,
    col: usize,
) -> Result<TruncatedNormal, ForestError> {
    TruncatedNormal::fit(
        stand.dbh_mean_cm,
        stand.dbh_sd_cm,
        options.dbh_min_cm,
        options.dbh_max_cm,
    )
    .map_err(|cause| ForestError::InfeasibleDbh {
        row,
        col,
        mean_cm: stand.dbh_mean_cm,
        sd_cm: stand.dbh_sd_cm,
        min_cm: options.dbh_min_cm,
        max_cm: options.dbh_max_cm,
        cause,
    })
}

fn check_options(options: &StandOptions) -> Result<(), ForestError> {
    let (min, max) = (options.dbh_min_cm, options.dbh_max_cm);
    if min.is_finite() && min > 0.0 && max > min {
        Ok(())
    } else {
        Err(ForestError::InvalidDbhBounds {
            min_cm: min,
            max_cm: max,
        })
    }
}

fn check_geometry(g: &GridGeometry) -> Result<(), ForestError> {
    if g.x_min_m.is_finite()
        && g.y_min_m.is_finite()
        && g.cell_size_m.is_finite()
        && g.cell_size_m > 0.0
    {
        Ok(())
    } else {
        Err(ForestError::InvalidGeometry {
            x_min_m: g.x_min_m,
            y_min_m: g.y_min_m,
            cell_size_m: g.cell_size_m,
        })
    }
}

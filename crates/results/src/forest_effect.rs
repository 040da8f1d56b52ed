//! The protective effect of the forest: a run with the forest minus the same run without it.

use std::path::{Path, PathBuf};

use rockfall_raster::{Grid, SampleType};
use serde::{Deserialize, Serialize};

use crate::convergence::MIN_REACH_PCT;
use crate::results::{Kind, NODATA, RasterCells};
use crate::summary::finite;
use crate::write::{create_dir, write_json, write_raster};
use crate::{Results, ScreenSummary};

/// The forest's protective effect: the run with the forest minus the run without it (same
/// layout, seed and rocks). Negative values are a protective effect.
#[derive(Debug, Clone)]
pub struct ForestEffect {
    reach: Grid<f64>,
    e95: Grid<f64>,
    summary: ForestEffectSummary,
}

/// `forest_effect.json`: the forest's effect on a run's numbers, `None` (written `null`) where
/// undefined. Written with its keys sorted ([`crate::write_json`]).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ForestEffectSummary {
    /// Engine name (of the run with the forest).
    pub engine: String,
    /// Scenario name.
    pub scenario: String,
    /// Master seed.
    pub seed: u64,
    /// Version of rockfall that wrote it.
    pub version: String,
    /// Rocks simulated (written as numbers with a fraction, e.g. `10000.0`).
    pub rocks: Difference,
    /// `Forest_effect_Reach_probability`, percentage points, over cells reached in either run.
    pub reach_probability_pp: ReachDifferences,
    /// `Forest_effect_E_95`, kJ, over cells with data in either run.
    pub e_95_kj: CellDifferences,
    /// Both differences over one set of cells: those the run without the forest reached. The
    /// headline: unlike [`ForestEffectSummary::e_95_kj`], whose cells differ between the runs
    /// (the forest run reaches other cells, often near the source where energies are high),
    /// it compares like with like.
    #[serde(default)]
    pub on_cells_reached_without_forest: BareCells,
    /// Area reached by at least [`MIN_REACH_PCT`] of the rocks where `E_95` exceeds each of the
    /// run's energy thresholds (`[output] energy_thresholds_kj`), with and without the forest:
    /// the footprint a hazard map draws (`rockfall hazard`'s default reach rule).
    #[serde(default)]
    pub area_e_95_above: Vec<AreaAbove>,
    /// Share of rocks stopped inside the DEM.
    pub stopped_fraction: Difference,
    /// Share of rocks that left the DEM.
    pub left_dem_fraction: Difference,
    /// Median run-out, m.
    pub runout_p50_m: Difference,
    /// 95th percentile of the run-out, m.
    pub runout_p95_m: Difference,
    /// Longest run-out, m.
    pub runout_max_m: Difference,
    /// Mean over rocks of each rock's largest speed, m/s.
    pub max_velocity_mean_ms: Difference,
    /// Mean over rocks of each rock's largest jump height, m.
    pub max_jump_height_mean_m: Difference,
    /// Tree impacts per rock.
    pub tree_impacts_per_rock: Difference,
    /// The screens of the run with the forest, matched by name in the run without.
    pub screens: Vec<ScreenDifference>,
}

/// One number of the two runs and their difference (with − without).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Difference {
    /// In the run with the forest.
    pub with_forest: Option<f64>,
    /// In the run without it.
    pub without_forest: Option<f64>,
    /// `with_forest − without_forest` (`None` when either is).
    pub difference: Option<f64>,
}

impl Difference {
    /// `with` and `without` and their difference.
    fn of(with: Option<f64>, without: Option<f64>) -> Difference {
        let (a, b) = (finite(with), finite(without));
        Difference {
            with_forest: a,
            without_forest: b,
            difference: finite(a.zip(b).map(|(a, b)| a - b)),
        }
    }
}

/// What a difference raster holds over the cells described.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct CellDifferences {
    /// Cells described.
    pub cells: u64,
    /// Mean difference (the raster's unit).
    pub mean_difference: Option<f64>,
    /// Smallest difference.
    pub min_difference: Option<f64>,
    /// Largest difference.
    pub max_difference: Option<f64>,
    /// Cells where the forest lowered the value.
    pub cells_lowered: u64,
    /// Cells where the forest raised the value.
    pub cells_raised: u64,
}

/// [`CellDifferences`] of the reach probability, with the cells each run reached.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ReachDifferences {
    /// Over the cells reached in either run, percentage points.
    #[serde(flatten)]
    pub cells: CellDifferences,
    /// Cells reached with the forest.
    pub cells_reached_with_forest: u64,
    /// Cells reached without it.
    pub cells_reached_without_forest: u64,
}

/// The forest's effect over the cells the run without the forest reached: a cell the run with
/// the forest did not reach counts 0 % and 0 kJ there.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct BareCells {
    /// Reach probability, percentage points.
    pub reach_probability_pp: CellDifferences,
    /// `E_95`, kJ.
    pub e_95_kj: CellDifferences,
}

/// The area reached by at least [`MIN_REACH_PCT`] of the rocks where `E_95` exceeds one
/// energy, in each run.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct AreaAbove {
    /// The energy, kJ (strictly above it).
    pub energy_kj: f64,
    /// Area, m², {with, without, difference}.
    pub area_m2: Difference,
}

impl AreaAbove {
    /// The area with and without the forest, ha (`None` when either is undefined).
    pub fn hectares(&self) -> Option<(f64, f64)> {
        let a = self.area_m2;
        Some((a.with_forest? / 1e4, a.without_forest? / 1e4))
    }
}

/// The forest's effect at one screen.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ScreenDifference {
    /// Screen name.
    pub name: String,
    /// Share of rocks that crossed.
    pub passed_fraction: Difference,
    /// 95th percentile of the crossings' energy, kJ.
    pub energy_kj_p95: Difference,
    /// 95th percentile of the crossings' speed, m/s.
    pub velocity_ms_p95: Difference,
    /// 95th percentile of the crossings' jump height, m.
    pub jump_height_m_p95: Difference,
}

impl ScreenDifference {
    /// Screen `with` of the run with the forest against `without` (`None`: the run without
    /// the forest has no screen of that name).
    fn of(with: &ScreenSummary, without: Option<&ScreenSummary>) -> ScreenDifference {
        let d = |f: fn(&ScreenSummary) -> Option<f64>| Difference::of(f(with), without.and_then(f));
        ScreenDifference {
            name: with.name.clone(),
            passed_fraction: d(|s| s.passed_fraction),
            energy_kj_p95: d(|s| s.energy_kj.p95),
            velocity_ms_p95: d(|s| s.velocity_ms.p95),
            jump_height_m_p95: d(|s| s.jump_height_m.p95),
        }
    }
}

/// Mean, min, max and count of lowered / raised cells of the valid cells of a difference
/// raster, over the cells where `counted` holds.
fn describe(diff: &Grid<f64>, counted: impl Fn(usize) -> bool) -> CellDifferences {
    let (mut n, mut sum, mut lo, mut hi, mut lowered, mut raised) = (0u64, 0.0, None, None, 0, 0);
    for (i, &v) in diff.values().iter().enumerate() {
        if !diff.mask()[i] || !counted(i) {
            continue;
        }
        n += 1;
        sum += v;
        lo = Some(lo.map_or(v, |l: f64| l.min(v)));
        hi = Some(hi.map_or(v, |h: f64| h.max(v)));
        lowered += u64::from(v < 0.0);
        raised += u64::from(v > 0.0);
    }
    CellDifferences {
        cells: n,
        mean_difference: finite((n > 0).then(|| sum / n as f64)),
        min_difference: finite(lo),
        max_difference: finite(hi),
        cells_lowered: lowered,
        cells_raised: raised,
    }
}

impl ForestEffect {
    /// The effect of the forest: `with_forest` minus `without_forest`, cell by cell on the
    /// grid of `with_forest` (both runs must share the layout).
    ///
    /// `Forest_effect_Reach_probability` is in percentage points, defined everywhere (0 where
    /// neither run reached the cell). `Forest_effect_E_95` is in kJ, where a run that did not
    /// reach the cell counts as 0 kJ, and nodata where neither run reached it.
    pub fn new(with_forest: &Results, without_forest: &Results) -> ForestEffect {
        let geometry = with_forest.layout.geometry;
        let crs = with_forest.layout.crs.clone();
        // the runs' rasters are read cell by cell from their statistics: no grid of them
        let pair = |kind| (with_forest.rows(kind), without_forest.rows(kind));
        let (rw, ro) = pair(Kind::Reach);
        let (ew, eo) = pair(Kind::EnergyPercentile(95.0));
        let (pw, po) = pair(Kind::Passages);
        let reached = |g: &RasterCells<'_>, i| g.at(i).is_some_and(|v| v > 0.0);
        let reach = Grid::from_fn(geometry, |row, col| {
            let i = geometry.index(row, col);
            let v = |g: &RasterCells<'_>| g.at(i).unwrap_or(0.0);
            Some(v(&rw) - v(&ro))
        })
        .with_crs(crs.clone());
        let mut e95 = Grid::from_fn(geometry, |row, col| {
            let i = geometry.index(row, col);
            match (ew.at(i), eo.at(i)) {
                (None, None) => None,
                (a, b) => Some(a.unwrap_or(0.0) - b.unwrap_or(0.0)),
            }
        })
        .with_crs(crs);
        e95.set_nodata_value(Some(NODATA));

        let (sw, so) = (with_forest.summary(), without_forest.summary());
        let either = |i| reached(&pw, i) || reached(&po, i);
        let bare = |i| reached(&po, i);
        let cell_m2 = geometry.cell_size_m * geometry.cell_size_m;
        let area_above = |reach: &RasterCells<'_>, e95: &RasterCells<'_>, e: f64| {
            let n = (0..geometry.len()).filter(|&i| {
                reach.at(i).is_some_and(|r| r >= MIN_REACH_PCT) && e95.at(i).is_some_and(|v| v > e)
            });
            Some(n.count() as f64 * cell_m2)
        };
        let area_e_95_above = (with_forest.layout.energy_thresholds_kj.iter())
            .map(|&e| AreaAbove {
                energy_kj: e,
                area_m2: Difference::of(area_above(&rw, &ew, e), area_above(&ro, &eo, e)),
            })
            .collect();
        let count =
            |g: &RasterCells<'_>| (0..geometry.len()).filter(|&i| reached(g, i)).count() as u64;
        let d = |f: fn(&crate::Summary) -> Option<f64>| Difference::of(f(&sw), f(&so));
        let summary = ForestEffectSummary {
            engine: sw.engine.clone(),
            scenario: sw.scenario.clone(),
            seed: sw.seed,
            version: env!("CARGO_PKG_VERSION").to_string(),
            rocks: d(|s| Some(s.rocks as f64)),
            reach_probability_pp: ReachDifferences {
                cells: describe(&reach, either),
                cells_reached_with_forest: count(&pw),
                cells_reached_without_forest: count(&po),
            },
            e_95_kj: describe(&e95, |_| true),
            on_cells_reached_without_forest: BareCells {
                reach_probability_pp: describe(&reach, bare),
                e_95_kj: describe(&e95, bare),
            },
            area_e_95_above,
            stopped_fraction: d(|s| s.stopped_fraction),
            left_dem_fraction: d(|s| s.left_dem_fraction),
            runout_p50_m: d(|s| s.runout_m.p50),
            runout_p95_m: d(|s| s.runout_m.p95),
            runout_max_m: d(|s| s.runout_m.max),
            max_velocity_mean_ms: d(|s| s.max_velocity_ms.mean),
            max_jump_height_mean_m: d(|s| s.max_jump_height_m.mean),
            tree_impacts_per_rock: d(|s| s.tree_impacts_per_rock),
            screens: (sw.screens.iter())
                .map(|s| ScreenDifference::of(s, so.screens.iter().find(|o| o.name == s.name)))
                .collect(),
        };
        ForestEffect {
            reach,
            e95,
            summary,
        }
    }

    /// `forest_effect.json`: for the reach probability (percentage points, over cells reached
    /// in either run) and E_95 (kJ, over cells with data in either run) the mean, min and max
    /// difference and the number of cells lowered / raised by the forest; {with_forest,
    /// without_forest, difference} of stopped and left-DEM fractions, runout p50/p95/max (m),
    /// mean of the rocks' maximum speed (m/s) and jump height (m), tree impacts per rock, and
    /// per screen (matched by name) passed fraction and p95 of energy (kJ), speed (m/s) and
    /// jump height (m). `None` (`null`) where undefined.
    pub fn summary(&self) -> &ForestEffectSummary {
        &self.summary
    }

    /// [`ForestEffect::summary`] as a JSON value (keys sorted), as `forest_effect.json` holds
    /// it.
    pub fn summary_json(&self) -> serde_json::Value {
        // cannot fail: every map of the summary is keyed by strings
        serde_json::to_value(&self.summary).unwrap_or_default()
    }

    /// The difference rasters: `Forest_effect_Reach_probability` (percentage points) and
    /// `Forest_effect_E_95` (kJ), in that order.
    pub fn rasters(&self) -> [(&'static str, &Grid<f64>); 2] {
        [
            ("Forest_effect_Reach_probability", &self.reach),
            ("Forest_effect_E_95", &self.e95),
        ]
    }

    /// Writes `Forest_effect_Reach_probability` and `Forest_effect_E_95` as GeoTIFF (32-bit
    /// float; and `.asc` when `ascii`) and `forest_effect.json` into `out_dir` (created when
    /// missing), each atomically. Returns the paths written.
    pub fn write(&self, out_dir: &Path, ascii: bool) -> Result<Vec<PathBuf>, crate::ResultsError> {
        create_dir(out_dir)?;
        let mut written = Vec::new();
        for (name, grid) in self.rasters() {
            write_raster(out_dir, name, grid, SampleType::F32, ascii, &mut written)?;
        }
        let json = out_dir.join("forest_effect.json");
        write_json(&json, &self.summary)?;
        written.push(json);
        Ok(written)
    }
}

//! The protective effect of the forest: a run with the forest minus the same run without it.

use std::path::{Path, PathBuf};

use rockfall_raster::{Grid, SampleType};
use serde_json::{Value, json};

use crate::Results;
use crate::results::{Kind, NODATA};
use crate::summary::num;
use crate::write::{create_dir, write_json, write_raster};

/// The forest's protective effect: the run with the forest minus the run without it (same
/// layout, seed and rocks). Negative values are a protective effect.
#[derive(Debug, Clone)]
pub struct ForestEffect {
    reach: Grid<f64>,
    e95: Grid<f64>,
    summary: Value,
}

/// {with, without, difference} of two summary values at `path` (keys into nested objects).
fn compare(with: &Value, without: &Value, path: &[&str]) -> Value {
    let get = |v: &Value| path.iter().fold(v, |v, k| &v[*k]).as_f64();
    let (a, b) = (get(with), get(without));
    json!({
        "with_forest": num(a),
        "without_forest": num(b),
        "difference": num(a.zip(b).map(|(a, b)| a - b)),
    })
}

/// Mean, min, max and count of lowered / raised cells of the valid cells of a difference
/// raster, over the cells where `counted` holds.
fn describe(diff: &Grid<f64>, counted: impl Fn(usize) -> bool) -> Value {
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
    json!({
        "cells": n,
        "mean_difference": num((n > 0).then(|| sum / n as f64)),
        "min_difference": num(lo),
        "max_difference": num(hi),
        "cells_lowered": lowered,
        "cells_raised": raised,
    })
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
        let pair = |kind| (with_forest.grid(kind), without_forest.grid(kind));
        let (rw, ro) = pair(Kind::Reach);
        let (ew, eo) = pair(Kind::EnergyPercentile(95.0));
        let (pw, po) = pair(Kind::Passages);
        let reached = |g: &Grid<f64>, i| g.get_index(i).is_some_and(|v| v > 0.0);
        let reach = Grid::from_fn(geometry, |row, col| {
            let i = geometry.index(row, col);
            let v = |g: &Grid<f64>| g.get_index(i).unwrap_or(0.0);
            Some(v(&rw) - v(&ro))
        })
        .with_crs(crs.clone());
        let mut e95 = Grid::from_fn(geometry, |row, col| {
            let i = geometry.index(row, col);
            match (ew.get_index(i), eo.get_index(i)) {
                (None, None) => None,
                (a, b) => Some(a.unwrap_or(0.0) - b.unwrap_or(0.0)),
            }
        })
        .with_crs(crs);
        e95.set_nodata_value(Some(NODATA));

        let (sw, so) = (with_forest.summary_json(), without_forest.summary_json());
        let either = |i| reached(&pw, i) || reached(&po, i);
        let count = |g: &Grid<f64>| (0..geometry.len()).filter(|&i| reached(g, i)).count();
        let mut reach_stats = describe(&reach, either);
        reach_stats["cells_reached_with_forest"] = json!(count(&pw));
        reach_stats["cells_reached_without_forest"] = json!(count(&po));
        let screens: Vec<Value> = (sw["screens"].as_array().into_iter().flatten())
            .map(|s| {
                let name = s["name"].as_str().unwrap_or_default();
                let other = (so["screens"].as_array().into_iter().flatten())
                    .find(|o| o["name"].as_str() == Some(name))
                    .cloned()
                    .unwrap_or(Value::Null);
                json!({
                    "name": name,
                    "passed_fraction": compare(s, &other, &["passed_fraction"]),
                    "energy_kj_p95": compare(s, &other, &["energy_kj", "p95"]),
                    "velocity_ms_p95": compare(s, &other, &["velocity_ms", "p95"]),
                    "jump_height_m_p95": compare(s, &other, &["jump_height_m", "p95"]),
                })
            })
            .collect();
        let summary = json!({
            "engine": sw["engine"],
            "scenario": sw["scenario"],
            "seed": sw["seed"],
            "version": env!("CARGO_PKG_VERSION"),
            "rocks": compare(&sw, &so, &["rocks"]),
            "reach_probability_pp": reach_stats,
            "e_95_kj": describe(&e95, |_| true),
            "stopped_fraction": compare(&sw, &so, &["stopped_fraction"]),
            "left_dem_fraction": compare(&sw, &so, &["left_dem_fraction"]),
            "runout_p50_m": compare(&sw, &so, &["runout_m", "p50"]),
            "runout_p95_m": compare(&sw, &so, &["runout_m", "p95"]),
            "runout_max_m": compare(&sw, &so, &["runout_m", "max"]),
            "max_velocity_mean_ms": compare(&sw, &so, &["max_velocity_ms", "mean"]),
            "max_jump_height_mean_m": compare(&sw, &so, &["max_jump_height_m", "mean"]),
            "tree_impacts_per_rock": compare(&sw, &so, &["tree_impacts_per_rock"]),
            "screens": screens,
        });
        ForestEffect {
            reach,
            e95,
            summary,
        }
    }

    /// `forest_effect.json` as a JSON value: for the reach probability (percentage points,
    /// over cells reached in either run) and E_95 (kJ, over cells with data in either run)
    /// the mean, min and max difference and the number of cells lowered / raised by the
    /// forest; {with_forest, without_forest, difference} of stopped and left-DEM fractions,
    /// runout p50/p95/max (m), mean of the rocks' maximum speed (m/s) and jump height (m),
    /// tree impacts per rock, and per screen (matched by name) passed fraction and p95 of
    /// energy (kJ), speed (m/s) and jump height (m). `null` where undefined.
    pub fn summary_json(&self) -> Value {
        self.summary.clone()
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

//! What the study compares of one shape or class: run-out, lateral spread and outcomes.

use super::path::{FallLine, SlopeRun};
use crate::ensemble::{self, ClassEstimates, Estimate, RockMeasure};
use crate::stats::{quantile, sorted_finite};
use rockfall_results::Summary;
use serde::Serialize;
use serde_json::{Value, json};

/// What the study compares of one shape or class.
#[derive(Debug, Clone, PartialEq)]
pub struct SlopeStats {
    /// The shape or class.
    pub label: String,
    /// Rocks with a recorded path.
    pub rocks: usize,
    /// Run-out along the fall line: (mean, p50, p95, max), m.
    pub runout_m: [f64; 4],
    /// Final lateral offsets: (standard deviation, p5, p95, largest |offset|), m.
    pub lateral_end_m: [f64; 4],
    /// Largest |lateral offset| along each rock's path: (p50, p95, max), m.
    pub lateral_path_m: [f64; 3],
    /// Members (shapes) pooled, with the statistics' 95 % intervals over members and rocks.
    pub estimates: Option<ClassEstimates>,
    /// Shares of the rocks stopped, left the DEM, at the time limit, and tree impacts per
    /// rock, over the members' runs.
    pub outcomes: Outcomes,
}

/// How a class's rocks ended, over its members' runs.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Outcomes {
    /// Share of rocks at rest inside the DEM.
    pub stopped_fraction: Option<f64>,
    /// Share of rocks that left the DEM.
    pub left_dem_fraction: Option<f64>,
    /// Share of rocks stopped by the time limit.
    pub time_limit_fraction: Option<f64>,
    /// Tree impacts per rock.
    pub tree_impacts_per_rock: Option<f64>,
}

impl Outcomes {
    /// The rock-weighted means of `summaries`.
    fn of(summaries: &[&Summary]) -> Outcomes {
        let rocks: u64 = summaries.iter().map(|s| s.rocks).sum();
        let mean = |f: fn(&Summary) -> Option<f64>| {
            let parts: Option<Vec<f64>> = (summaries.iter())
                .map(|s| f(s).map(|v| v * s.rocks as f64))
                .collect();
            parts
                .filter(|_| rocks > 0)
                .map(|p| p.iter().sum::<f64>() / rocks as f64)
        };
        Outcomes {
            stopped_fraction: mean(|s| s.stopped_fraction),
            left_dem_fraction: mean(|s| s.left_dem_fraction),
            time_limit_fraction: mean(|s| s.time_limit_fraction),
            tree_impacts_per_rock: mean(|s| s.tree_impacts_per_rock),
        }
    }
}

impl SlopeStats {
    /// Reduces `run` in the directions of `line`, each path from its own first point.
    pub fn of(run: &SlopeRun, line: &FallLine) -> SlopeStats {
        Self::of_members(&run.label, &[run], line)
    }

    /// Reduces the runs of the members of a class, their rocks pooled.
    pub fn of_members(label: &str, runs: &[&SlopeRun], line: &FallLine) -> SlopeStats {
        let measures: Vec<Vec<RockMeasure>> = runs.iter().map(|r| rock_measures(r, line)).collect();
        let paths = || runs.iter().flat_map(|r| r.paths.iter());
        let along = sorted_finite(measures.iter().flatten().map(|m| m.runout_m));
        let across = sorted_finite(measures.iter().flatten().map(|m| m.lateral_m));
        let widest = sorted_finite(paths().filter_map(|p| {
            let from = *p.points.first()?;
            let off = p.points.iter().map(|q| line.offsets(from, *q).1.abs());
            Some(off.fold(0.0, f64::max))
        }));
        let q = |v: &[f64], p: f64| quantile(v, p);
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let mean_across = mean(&across);
        let var = across
            .iter()
            .map(|x| (x - mean_across).powi(2))
            .sum::<f64>()
            / (across.len() as f64 - 1.0);
        let summaries: Vec<&Summary> = runs.iter().map(|r| &r.summary).collect();
        SlopeStats {
            label: label.to_string(),
            rocks: paths().count(),
            runout_m: [
                mean(&along),
                q(&along, 0.5),
                q(&along, 0.95),
                q(&along, 1.0),
            ],
            lateral_end_m: [
                if across.len() > 1 {
                    var.sqrt()
                } else {
                    f64::NAN
                },
                q(&across, 0.05),
                q(&across, 0.95),
                q(&across, 0.0).abs().max(q(&across, 1.0).abs()),
            ],
            lateral_path_m: [q(&widest, 0.5), q(&widest, 0.95), q(&widest, 1.0)],
            estimates: ensemble::estimates(&measures),
            outcomes: Outcomes::of(&summaries),
        }
    }

    /// Width of the central 90 % of final lateral offsets, m.
    pub fn spread_width_m(&self) -> f64 {
        self.lateral_end_m[2] - self.lateral_end_m[1]
    }

    /// The study's JSON for this shape or class.
    pub fn json(&self) -> Value {
        let [mean, p50, p95, max] = self.runout_m;
        let [sd, p5, p95l, max_abs] = self.lateral_end_m;
        let [w50, w95, wmax] = self.lateral_path_m;
        let o = &self.outcomes;
        let e = self.estimates.as_ref();
        let ci = |f: fn(&ClassEstimates) -> Estimate| e.map(|e| f(e).ci95);
        let motion = e.map(|e| {
            let mut m = serde_json::Map::new();
            for (name, est) in rockfall_results::MOTION_NAMES.iter().zip(e.motion_share) {
                m.insert(
                    (*name).into(),
                    json!({"share": est.value, "ci95": est.ci95}),
                );
            }
            Value::Object(m)
        });
        json!({
            "shape": self.label,
            "members": e.map_or(1, |e| e.members),
            "rocks": self.rocks,
            "stopped_fraction": o.stopped_fraction,
            "left_dem_fraction": o.left_dem_fraction,
            "time_limit_fraction": o.time_limit_fraction,
            "tree_impacts_per_rock": o.tree_impacts_per_rock,
            "runout_m": {
                "mean": mean, "p50": p50, "p95": p95, "max": max,
                "mean_ci95": ci(|e| e.runout_mean_m), "p95_ci95": ci(|e| e.runout_p95_m),
            },
            "lateral_end_m": {
                "sd": sd, "p5": p5, "p95": p95l, "width_p5_p95": self.spread_width_m(),
                "max_abs": max_abs, "sd_ci95": ci(|e| e.lateral_sd_m),
                "width_ci95": ci(|e| e.spread_width_m),
            },
            "lateral_path_max_m": {"p50": w50, "p95": w95, "max": wmax},
            "motion": motion,
        })
    }
}

/// The run-out, final lateral offset and motion of each rock of `run`.
fn rock_measures(run: &SlopeRun, line: &FallLine) -> Vec<RockMeasure> {
    (run.paths.iter().enumerate())
        .filter_map(|(k, p)| {
            let (runout_m, lateral_m) = line.offsets(*p.points.first()?, *p.points.last()?);
            Some(RockMeasure {
                runout_m,
                lateral_m,
                motion_s: run.motion_s.get(k).copied().unwrap_or([0.0; 5]),
            })
        })
        .filter(|m| m.runout_m.is_finite() && m.lateral_m.is_finite())
        .collect()
}

/// The runs of `runs` grouped by label, in order of first appearance (the members of a class
/// are its runs of one label).
pub fn classes(runs: &[SlopeRun]) -> Vec<(String, Vec<&SlopeRun>)> {
    let mut out: Vec<(String, Vec<&SlopeRun>)> = Vec::new();
    for r in runs {
        match out.iter_mut().find(|(l, _)| *l == r.label) {
            Some((_, members)) => members.push(r),
            None => out.push((r.label.clone(), vec![r])),
        }
    }
    out
}

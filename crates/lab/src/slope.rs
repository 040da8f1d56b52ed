//! The forest-slope rock-shape study of seed 001 §3.4 (fig. 6): one slope, one run per rock
//! shape, compared by run-out and lateral spread.
//!
//! Each shape's run is an ordinary rigid-engine run whose trajectories are all recorded every
//! few hundredths of a second; this module reduces them. Distances are horizontal, measured
//! from each rock's own start along and across the fall line of the (first) release point —
//! the steepest descent of the DEM there:
//!
//! - **run-out**: how far along the fall line the rock ends up (m; the end point is where it
//!   stopped, left the DEM or was at the time limit);
//! - **lateral offset**: the signed distance across the fall line (m, positive to the left
//!   looking downhill); the *spread* of a shape is the standard deviation and the 5–95 %
//!   width of its rocks' final offsets, and its *reach* sideways the largest offset any point
//!   of a rock's path takes (per rock, then its 95th percentile and maximum over rocks).

use crate::LabError;
use crate::stats::{quantile, sorted_finite};
use rockfall_plot::{Axes, ColorScale, LinePanel, Polyline, colored_lines_panels};
use rockfall_results::{Results, Summary};
use serde::Serialize;
use serde_json::{Value, json};
use std::path::Path;

/// One rock's recorded path.
#[derive(Debug, Clone, PartialEq)]
pub struct RockPath {
    /// Plan-view positions (x, y) of the centre, m.
    pub points: Vec<[f64; 2]>,
    /// Total kinetic energy (translational + rotational) at each point, J.
    pub energy_j: Vec<f64>,
}

/// One shape's run on the slope.
#[derive(Debug, Clone)]
pub struct SlopeRun {
    /// The shape.
    pub label: String,
    /// The run's `summary.json`.
    pub summary: Summary,
    /// Every recorded rock's path, by rock number.
    pub paths: Vec<RockPath>,
}

impl SlopeRun {
    /// The paths of every rock recorded in `results` (all of them in a study run).
    pub fn new(label: &str, results: &Results) -> SlopeRun {
        let mut paths: Vec<RockPath> = Vec::new();
        let mut current = None;
        for row in results.trajectories() {
            if current != Some(row.rock_id) {
                current = Some(row.rock_id);
                paths.push(RockPath {
                    points: Vec::new(),
                    energy_j: Vec::new(),
                });
            }
            if let Some(p) = paths.last_mut() {
                p.points.push([row.x_m, row.y_m]);
                p.energy_j.push(row.e_trans_j + row.e_rot_j);
            }
        }
        SlopeRun {
            label: label.to_string(),
            summary: results.summary(),
            paths,
        }
    }
}

/// The fall-line frame of a release point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FallLine {
    /// Release point (x, y), m.
    pub origin_m: [f64; 2],
    /// Unit horizontal direction of steepest descent.
    pub downhill: [f64; 2],
}

impl FallLine {
    /// The frame at `origin_m` on a surface of gradient (`dzdx`, `dzdy`); `None` on flat
    /// ground.
    pub fn new(origin_m: [f64; 2], dzdx: f64, dzdy: f64) -> Option<FallLine> {
        let g = dzdx.hypot(dzdy);
        (g > 0.0 && g.is_finite()).then(|| FallLine {
            origin_m,
            downhill: [-dzdx / g, -dzdy / g],
        })
    }

    /// (along the fall line, across it to the left) of `p` from the origin, m.
    pub fn frame(&self, p: [f64; 2]) -> (f64, f64) {
        self.offsets(self.origin_m, p)
    }

    /// (along the fall line, across it to the left) of `p` from `from`, m.
    pub fn offsets(&self, from: [f64; 2], p: [f64; 2]) -> (f64, f64) {
        let (dx, dy) = (p[0] - from[0], p[1] - from[1]);
        let [ux, uy] = self.downhill;
        (dx * ux + dy * uy, ux * dy - uy * dx)
    }
}

/// What the study compares of one shape.
#[derive(Debug, Clone, PartialEq)]
pub struct SlopeStats {
    /// The shape.
    pub label: String,
    /// Rocks with a recorded path.
    pub rocks: usize,
    /// Run-out along the fall line: (mean, p50, p95, max), m.
    pub runout_m: [f64; 4],
    /// Final lateral offsets: (standard deviation, p5, p95, largest |offset|), m.
    pub lateral_end_m: [f64; 4],
    /// Largest |lateral offset| along each rock's path: (p50, p95, max), m.
    pub lateral_path_m: [f64; 3],
}

impl SlopeStats {
    /// Reduces `run` in the directions of `line`, each path from its own first point.
    pub fn of(run: &SlopeRun, line: &FallLine) -> SlopeStats {
        let ends: Vec<(f64, f64)> = (run.paths.iter())
            .filter_map(|p| Some(line.offsets(*p.points.first()?, *p.points.last()?)))
            .collect();
        let along = sorted_finite(ends.iter().map(|e| e.0));
        let across = sorted_finite(ends.iter().map(|e| e.1));
        let widest = sorted_finite(run.paths.iter().filter_map(|p| {
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
        SlopeStats {
            label: run.label.clone(),
            rocks: run.paths.len(),
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
        }
    }

    /// Width of the central 90 % of final lateral offsets, m.
    pub fn spread_width_m(&self) -> f64 {
        self.lateral_end_m[2] - self.lateral_end_m[1]
    }

    /// The study's JSON for this shape.
    pub fn json(&self, summary: &Summary) -> Value {
        let [mean, p50, p95, max] = self.runout_m;
        let [sd, p5, p95l, max_abs] = self.lateral_end_m;
        let [w50, w95, wmax] = self.lateral_path_m;
        json!({
            "shape": self.label,
            "rocks": self.rocks,
            "stopped_fraction": summary.stopped_fraction,
            "left_dem_fraction": summary.left_dem_fraction,
            "time_limit_fraction": summary.time_limit_fraction,
            "tree_impacts_per_rock": summary.tree_impacts_per_rock,
            "max_velocity_ms": summary.max_velocity_ms,
            "runout_m": {"mean": mean, "p50": p50, "p95": p95, "max": max},
            "lateral_end_m": {
                "sd": sd, "p5": p5, "p95": p95l, "width_p5_p95": self.spread_width_m(),
                "max_abs": max_abs,
            },
            "lateral_path_max_m": {"p50": w50, "p95": w95, "max": wmax},
        })
    }
}

/// The shape with the largest (`largest`) or smallest value of `key`.
fn pick(stats: &[SlopeStats], key: impl Fn(&SlopeStats) -> f64, largest: bool) -> Option<&str> {
    let better = |a: f64, b: f64| if largest { a > b } else { a < b };
    let mut best: Option<&SlopeStats> = None;
    for s in stats.iter().filter(|s| key(s).is_finite()) {
        if best.is_none_or(|b| better(key(s), key(b))) {
            best = Some(s);
        }
    }
    best.map(|s| s.label.as_str())
}

/// The comparison seed 001 draws from fig. 6 (`study.json` key `ranking`): which shape runs
/// out farthest (p95 run-out), spreads widest and least (5–95 % width of the final lateral
/// offsets); `None` when no shape has a finite value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ranking {
    /// The shape of the largest p95 run-out.
    pub farthest_runout_p95: Option<String>,
    /// The shape of the widest spread.
    pub widest_spread: Option<String>,
    /// The shape of the least spread.
    pub least_spread: Option<String>,
    /// What the paper found.
    pub paper: PaperRanking,
}

/// Seed 001's findings (§3.4, fig. 6), by shape.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PaperRanking {
    /// The shape that runs out farthest.
    pub farthest_runout: &'static str,
    /// The shape that spreads widest.
    pub widest_spread: &'static str,
    /// The shape that spreads least.
    pub least_spread: &'static str,
}

/// What seed 001 found.
pub const PAPER_RANKING: PaperRanking = PaperRanking {
    farthest_runout: "flat2.2",
    widest_spread: "flat2.2",
    least_spread: "long2.2",
};

/// The ranking of `stats` (see [`Ranking`]).
pub fn ranking(stats: &[SlopeStats]) -> Ranking {
    let shape =
        |key: fn(&SlopeStats) -> f64, largest| pick(stats, key, largest).map(str::to_string);
    Ranking {
        farthest_runout_p95: shape(|s| s.runout_m[2], true),
        widest_spread: shape(SlopeStats::spread_width_m, true),
        least_spread: shape(SlopeStats::spread_width_m, false),
        paper: PAPER_RANKING,
    }
}

/// A Markdown table of `stats`.
pub fn table(stats: &[SlopeStats], runs: &[SlopeRun]) -> String {
    let mut t = String::from(
        "| shape | rocks | stopped | left DEM | run-out mean | p50 | p95 | max | lateral sd \
         | 5–95 % width | path max-lateral p95 | max |\n\
         |---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n",
    );
    for (s, r) in stats.iter().zip(runs) {
        let pct = |f: Option<f64>| f.map_or("–".into(), |v| format!("{:.0} %", 100.0 * v));
        t += &format!(
            "| {} | {} | {} | {} | {:.1} m | {:.1} m | {:.1} m | {:.1} m | {:.1} m | {:.1} m | {:.1} m | {:.1} m |\n",
            s.label,
            s.rocks,
            pct(r.summary.stopped_fraction),
            pct(r.summary.left_dem_fraction),
            s.runout_m[0],
            s.runout_m[1],
            s.runout_m[2],
            s.runout_m[3],
            s.lateral_end_m[0],
            s.spread_width_m(),
            s.lateral_path_m[1],
            s.lateral_path_m[2],
        );
    }
    t
}

/// Lowest energy of the plan view's logarithmic colour scale, kJ (lower ones take its colour).
const LOG_FLOOR_KJ: f64 = 0.1;

/// Draws every path of `runs`, one panel per shape, coloured by total energy (kJ) on one
/// logarithmic scale for all, so that the slow rolling and the fast bouncing stretches both
/// show (cf. seed 001 fig. 6).
pub fn plan_view(path: &Path, runs: &[SlopeRun]) -> Result<(), LabError> {
    let top_kj = runs
        .iter()
        .flat_map(|r| r.paths.iter().flat_map(|p| p.energy_j.iter()))
        .fold(0.0_f64, |m, e| m.max(e / 1e3));
    let panels: Vec<LinePanel> = runs
        .iter()
        .map(|r| LinePanel {
            title: r.label.clone(),
            lines: (r.paths.iter())
                .map(|p| Polyline {
                    points: p.points.clone(),
                    values: p.energy_j.iter().map(|e| e / 1e3).collect(),
                })
                .collect(),
        })
        .collect();
    let axes = Axes {
        x_label: "x (m)".into(),
        y_label: "y (m)".into(),
        x_range: None,
        y_range: None,
    };
    let scale = ColorScale {
        label: "total kinetic energy (kJ, log scale)".into(),
        min: LOG_FLOOR_KJ,
        max: top_kj.max(10.0 * LOG_FLOOR_KJ),
        log: true,
        ramp: rockfall_plot::Ramp::Viridis,
    };
    let title = "Trajectories coloured by total energy (cf. seed 001 fig. 6)";
    colored_lines_panels(path, title, &axes, &scale, &panels)
        .map_err(|e| LabError::Plot(e.to_string()))
}

/// What [`write_study`] wrote.
#[derive(Debug, Clone)]
pub struct Study {
    /// The statistics per shape.
    pub stats: Vec<SlopeStats>,
    /// `study.md`'s text.
    pub markdown: String,
    /// The files written.
    pub files: Vec<std::path::PathBuf>,
}

/// Writes the study of `runs` into `out_dir`: `trajectories_plan.png`, `study.json` and
/// `study.md`.
pub fn write_study(out_dir: &Path, runs: &[SlopeRun], line: &FallLine) -> Result<Study, LabError> {
    let stats: Vec<SlopeStats> = runs.iter().map(|r| SlopeStats::of(r, line)).collect();
    let plan = out_dir.join("trajectories_plan.png");
    plan_view(&plan, runs)?;
    let json_path = out_dir.join("study.json");
    let shapes: Vec<Value> = stats
        .iter()
        .zip(runs)
        .map(|(s, r)| s.json(&r.summary))
        .collect();
    let rank = ranking(&stats);
    crate::output::write_json(
        &json_path,
        &json!({
            "experiment": "shape-study",
            "fall_line": {"origin_m": line.origin_m, "downhill": line.downhill},
            "shapes": shapes,
            "ranking": rank,
        }),
    )?;
    let md_path = out_dir.join("study.md");
    let name = |shape: &Option<String>| shape.as_deref().unwrap_or("–").to_string();
    let md = format!(
        "# Rock-shape study (seed 001 §3.4)\n\nRun-out along the fall line of the release and \
         lateral offset across it (horizontal m); spread = final lateral offsets, path \
         max-lateral = the farthest each rock strays sideways.\n\n{}\n\
         Farthest run-out (p95): **{}** (paper: {}). Widest spread (5–95 % width): **{}** \
         (paper: {}). Least spread: **{}** (paper: {}).\n",
        table(&stats, runs),
        name(&rank.farthest_runout_p95),
        rank.paper.farthest_runout,
        name(&rank.widest_spread),
        rank.paper.widest_spread,
        name(&rank.least_spread),
        rank.paper.least_spread,
    );
    rockfall_raster::atomic::write_bytes_atomic(&md_path, md.as_bytes()).map_err(LabError::from)?;
    Ok(Study {
        stats,
        markdown: md,
        files: vec![plan, json_path, md_path],
    })
}

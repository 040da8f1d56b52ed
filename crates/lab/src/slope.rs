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
use crate::ensemble::{self, ClassEstimates, Estimate, RockMeasure};
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

/// One shape's run on the slope (one member of its class).
#[derive(Debug, Clone)]
pub struct SlopeRun {
    /// The shape, or the class of an ensemble's member.
    pub label: String,
    /// The run's `summary.json`.
    pub summary: Summary,
    /// Every recorded rock's path, by rock number.
    pub paths: Vec<RockPath>,
    /// Every rock's time per mode of motion, s, by rock number (empty when the run kept no
    /// rock records).
    pub motion_s: Vec<[f64; 5]>,
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
            motion_s: (results.rock_records().iter())
                .map(|r| r.end.motion.as_array())
                .collect(),
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
    /// Whether each of the three (in that order) stands clear of every other shape: its 95 %
    /// interval does not overlap theirs (`None` without intervals). Where it does, another
    /// sample could rank the shapes otherwise.
    pub clear: [Option<bool>; 3],
    /// What the paper found.
    pub paper: PaperRanking,
}

/// Whether the shape `label` of `stats` stands clear above (`largest`) or below every other
/// shape in the interval `ci`; `None` when a shape has no interval.
fn clear(
    stats: &[SlopeStats],
    label: Option<&str>,
    ci: fn(&ClassEstimates) -> [f64; 2],
    largest: bool,
) -> Option<bool> {
    let label = label?;
    let ci_of = |s: &SlopeStats| s.estimates.as_ref().map(ci);
    let own = ci_of(stats.iter().find(|s| s.label == label)?)?;
    let mut others = stats.iter().filter(|s| s.label != label).peekable();
    others.peek()?;
    others
        .map(|s| {
            ci_of(s).map(|o| {
                if largest {
                    own[0] > o[1]
                } else {
                    own[1] < o[0]
                }
            })
        })
        .try_fold(true, |all, c| c.map(|c| all && c))
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
    let farthest_runout_p95 = shape(|s| s.runout_m[2], true);
    let widest_spread = shape(SlopeStats::spread_width_m, true);
    let least_spread = shape(SlopeStats::spread_width_m, false);
    let clear = [
        clear(
            stats,
            farthest_runout_p95.as_deref(),
            |e| e.runout_p95_m.ci95,
            true,
        ),
        clear(
            stats,
            widest_spread.as_deref(),
            |e| e.spread_width_m.ci95,
            true,
        ),
        clear(
            stats,
            least_spread.as_deref(),
            |e| e.spread_width_m.ci95,
            false,
        ),
    ];
    Ranking {
        farthest_runout_p95,
        widest_spread,
        least_spread,
        clear,
        paper: PAPER_RANKING,
    }
}

/// A Markdown table of `stats`: per shape or class its rocks' outcomes, run-out and spread,
/// each headline statistic with its 95 % interval, and the shares of time rolling and
/// sliding.
pub fn table(stats: &[SlopeStats]) -> String {
    let mut t = String::from(
        "| shape | members × rocks | stopped | left DEM | run-out mean [95 % CI] | p50 \
         | p95 [95 % CI] | max | lateral sd [95 % CI] | 5–95 % width [95 % CI] \
         | path max-lateral p95 | flight / rolling / sliding face / sliding edge / slow |\n\
         |---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n",
    );
    for s in stats {
        let pct = |f: Option<f64>| f.map_or("–".into(), |v| format!("{:.0} %", 100.0 * v));
        let e = s.estimates.as_ref();
        let with_ci = |v: f64, est: Option<Estimate>| match est {
            Some(est) => format!("{v:.1} [{:.1}, {:.1}] m", est.ci95[0], est.ci95[1]),
            None => format!("{v:.1} m"),
        };
        let members = e.map_or(1, |e| e.members);
        let motion = e.map_or("–".into(), |e| {
            let share = |k: usize| {
                let v = e.motion_share[k].value;
                if v.is_finite() {
                    format!("{:.0}", 100.0 * v)
                } else {
                    "–".into()
                }
            };
            format!(
                "{} / {} / {} / {} / {} %",
                share(0),
                share(1),
                share(2),
                share(3),
                share(4)
            )
        });
        t += &format!(
            "| {} | {} × {} | {} | {} | {} | {:.1} m | {} | {:.1} m | {} | {} | {:.1} m | {} |\n",
            s.label,
            members,
            s.rocks / members.max(1),
            pct(s.outcomes.stopped_fraction),
            pct(s.outcomes.left_dem_fraction),
            with_ci(s.runout_m[0], e.map(|e| e.runout_mean_m)),
            s.runout_m[1],
            with_ci(s.runout_m[2], e.map(|e| e.runout_p95_m)),
            s.runout_m[3],
            with_ci(s.lateral_end_m[0], e.map(|e| e.lateral_sd_m)),
            with_ci(s.spread_width_m(), e.map(|e| e.spread_width_m)),
            s.lateral_path_m[1],
            motion,
        );
    }
    t
}

/// Lowest energy of the plan view's logarithmic colour scale, kJ (lower ones take its colour).
const LOG_FLOOR_KJ: f64 = 0.1;

/// Draws every path of `runs`, one panel per shape or class (its members' paths together),
/// coloured by total energy (kJ) on one logarithmic scale for all, so that the slow rolling
/// and the fast bouncing stretches both show (cf. seed 001 fig. 6).
pub fn plan_view(path: &Path, runs: &[SlopeRun]) -> Result<(), LabError> {
    let top_kj = runs
        .iter()
        .flat_map(|r| r.paths.iter().flat_map(|p| p.energy_j.iter()))
        .fold(0.0_f64, |m, e| m.max(e / 1e3));
    let panels: Vec<LinePanel> = classes(runs)
        .into_iter()
        .map(|(label, members)| LinePanel {
            title: label,
            lines: (members.iter().flat_map(|r| r.paths.iter()))
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
    let stats: Vec<SlopeStats> = (classes(runs).iter())
        .map(|(label, members)| SlopeStats::of_members(label, members, line))
        .collect();
    let plan = out_dir.join("trajectories_plan.png");
    plan_view(&plan, runs)?;
    let json_path = out_dir.join("study.json");
    let shapes: Vec<Value> = stats.iter().map(SlopeStats::json).collect();
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
    let clear = |c: Option<bool>| match c {
        Some(true) => " (clear of the others' 95 % intervals)",
        Some(false) => " (its 95 % interval overlaps another's)",
        None => "",
    };
    let md = format!(
        "# Rock-shape study (seed 001 §3.4)\n\nRun-out along the fall line of the release and \
         lateral offset across it (horizontal m); spread = final lateral offsets, path \
         max-lateral = the farthest each rock strays sideways. A class of several members \
         (`rough-flat2.2*10`) pools their rocks; [95 % CI] are two-stage bootstrap intervals \
         over members and rocks. The last column is the share of the rocks' time in each mode \
         of motion (summary.json `motion`).\n\n{}\n\
         Farthest run-out (p95): **{}**{} (paper: {}). Widest spread (5–95 % width): **{}**{} \
         (paper: {}). Least spread: **{}**{} (paper: {}).\n",
        table(&stats),
        name(&rank.farthest_runout_p95),
        clear(rank.clear[0]),
        rank.paper.farthest_runout,
        name(&rank.widest_spread),
        clear(rank.clear[1]),
        rank.paper.widest_spread,
        name(&rank.least_spread),
        clear(rank.clear[2]),
        rank.paper.least_spread,
    );
    rockfall_raster::atomic::write_bytes_atomic(&md_path, md.as_bytes()).map_err(LabError::from)?;
    Ok(Study {
        stats,
        markdown: md,
        files: vec![plan, json_path, md_path],
    })
}

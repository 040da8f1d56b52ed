//! The study's files: the Markdown table, the plan view of the paths and `study.json`.

use super::path::{FallLine, SlopeRun};
use super::rank::ranking;
use super::shape_stats::{SlopeStats, classes};
use crate::LabError;
use crate::ensemble::Estimate;
use rockfall_plot::{Axes, ColorScale, LinePanel, Polyline, colored_lines_panels};
use serde_json::{Value, json};
use std::path::Path;

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

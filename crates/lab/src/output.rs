//! What `rockfall impact-lab` writes: `impacts.csv`, `summary.json` and the figures.

use crate::LabError;
use crate::figures::figures;
use crate::impact::Lab;
use crate::run::LabRun;
use crate::summary::{Labelled, Metrics, RegimeSummary, regimes_json};
use crate::table::write_impacts;
use rockfall_forest::impact_type::{FRONTAL_MAX, LATERAL_MAX};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// Writes a run's outputs into `out_dir` (created if needed); returns the files written.
pub fn write_lab(
    out_dir: &Path,
    shape: &str,
    lab: &Lab,
    run: &LabRun,
    seed: u64,
    samples: u64,
) -> Result<Vec<PathBuf>, LabError> {
    std::fs::create_dir_all(out_dir).map_err(|e| LabError::from((out_dir.to_path_buf(), e)))?;
    let csv = out_dir.join("impacts.csv");
    write_impacts(&csv, &run.impacts)?;
    let json_path = out_dir.join("summary.json");
    let summary = summary_json(shape, lab, run, seed, samples);
    write_json(&json_path, &summary)?;
    let runs = [Labelled {
        label: shape.to_string(),
        metrics: run.impacts.iter().map(Metrics::from).collect(),
    }];
    let mut files = vec![csv, json_path];
    files.extend(figures(out_dir, &runs)?);
    Ok(files)
}

/// Writes `value` as pretty JSON with a final newline (atomically).
pub fn write_json(path: &Path, value: &Value) -> Result<(), LabError> {
    rockfall_results::write_json(path, value).map_err(LabError::from)
}

/// `summary.json` of a run (see the README for the keys).
pub fn summary_json(shape: &str, lab: &Lab, run: &LabRun, seed: u64, samples: u64) -> Value {
    let s = lab.setup();
    let b = lab.body();
    let g = &b.geometry;
    let metrics: Vec<Metrics> = run.impacts.iter().map(Metrics::from).collect();
    let m = &run.misses;
    json!({
        "experiment": "impact-lab",
        "shape": shape,
        "rock": {
            "volume_m3": g.volume_m3,
            "density_kg_m3": b.density_kg_m3,
            "mass_kg": b.mass_kg,
            "vertices": g.vertices_m.len(),
            "axis_lengths_m": g.lengths_m,
            "aspect_ratio": g.aspect_ratio(),
            "class": g.class().name(),
            "principal_moments_kgm2": [b.inertia_kgm2.x, b.inertia_kgm2.y, b.inertia_kgm2.z],
            "circumradius_m": g.circumradius_m,
        },
        "stem": {"d0_m": s.stem_d0_m, "d1_m": s.stem_d1_m(), "h_m": s.stem_h_m},
        "contact": {"mu": s.mu, "eps_n": s.eps_n, "eps_t": s.eps_t},
        "setup": {
            "release_height_m": s.release_height_m,
            "min_axis_distance_m": s.min_axis_distance_m,
            "lattice_side_m": s.lattice_side_m,
            "lattice_points_per_side": s.lattice_points_per_side,
            "orientations_per_point": s.orientations_per_point,
            "speed_ms": [s.speed_ms.0, s.speed_ms.1],
            "spin_rads": [s.spin_rads.0, s.spin_rads.1],
            "theta_deg": [s.theta_deg.0, s.theta_deg.1],
            "chi_deg": [s.chi_deg.0, s.chi_deg.1],
            "dt_s": s.dt_s,
            "max_time_s": s.max_time_s,
        },
        "zeta_ct_thresholds": {"frontal_below": FRONTAL_MAX, "scratch_from": LATERAL_MAX},
        "seed": seed,
        "samples_requested": samples,
        "samples": run.impacts.len(),
        "candidates_total": s.candidates(),
        "candidates_tried": run.tried,
        "hit_rate": run.impacts.len() as f64 / run.tried.max(1) as f64,
        "misses": {
            "wide": m.wide, "ground": m.ground, "passed": m.passed,
            "time_limit": m.time_limit, "failed": m.failed,
        },
        "exhausted": run.exhausted,
        "threads": run.threads,
        "wall_time_s": run.wall_time_s,
        "regimes": regimes_json(&metrics),
        "all": RegimeSummary::of(&metrics, |_| true).json(metrics.len()),
    })
}

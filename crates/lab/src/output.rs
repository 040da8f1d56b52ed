//! What `rockfall impact-lab` writes: `impacts.csv`, `summary.json` and the figures.

use crate::figures::figures;
use crate::impact::Lab;
use crate::run::{LabRun, MissCounts};
use crate::summary::{Labelled, Metrics, RegimeReport, RegimeSummary, Regimes};
use crate::table::write_impacts;
use crate::{LabError, Regime};
use rockfall_forest::impact_type::{FRONTAL_MAX, LATERAL_MAX};
use rockfall_scenario::ContactParams;
use serde::{Deserialize, Serialize};
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
    let summary = LabSummary::new(shape, lab, run, seed, samples);
    write_json(&json_path, &summary)?;
    let runs = [Labelled {
        label: shape.to_string(),
        metrics: run.impacts.iter().map(Metrics::from).collect(),
    }];
    let mut files = vec![csv, json_path];
    files.extend(figures(out_dir, &runs)?);
    Ok(files)
}

/// Writes `value` as pretty JSON with a final newline, keys sorted (atomically).
pub fn write_json(path: &Path, value: &impl Serialize) -> Result<(), LabError> {
    rockfall_results::write_json(path, value).map_err(LabError::from)
}

/// `summary.json` of an impact-lab run (see docs/guide/engines.md for the keys): the rock, stem, contact
/// and setup, the sample drawn, and the impact metrics per regime and of all impacts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LabSummary {
    /// Always `impact-lab`.
    pub experiment: String,
    /// The rock shape (its name or file).
    pub shape: String,
    /// The rock.
    pub rock: LabRock,
    /// The stem.
    pub stem: LabStem,
    /// Rock–stem contact law.
    pub contact: ContactParams,
    /// How candidates are released.
    pub setup: LabRelease,
    /// Eccentricity ζ_CT bounds of the regimes.
    pub zeta_ct_thresholds: ZetaThresholds,
    /// Master seed.
    pub seed: u64,
    /// Impacts asked for.
    pub samples_requested: u64,
    /// Impacts sampled.
    pub samples: u64,
    /// Candidates of the setup.
    pub candidates_total: u64,
    /// Candidates tried until the sample was full.
    pub candidates_tried: u64,
    /// Impacts / candidates tried.
    pub hit_rate: f64,
    /// Candidates that missed, by reason.
    pub misses: MissCounts,
    /// Every candidate was tried and fewer impacts than asked for were found.
    pub exhausted: bool,
    /// Worker threads.
    pub threads: u64,
    /// Wall time, s.
    pub wall_time_s: f64,
    /// The metrics per regime.
    pub regimes: Regimes,
    /// The same impacts sorted into regimes by [`ALTERNATIVE_THRESHOLDS`] instead of thirds:
    /// how much the shares and losses depend on where the regimes are cut (ours: the papers
    /// name the regimes without numeric bounds). Absent in summaries written before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub regimes_alternative: Option<AlternativeRegimes>,
    /// The metrics of all impacts.
    pub all: RegimeReport,
}

/// The alternative regime bounds of `summary.json` `regimes_alternative`: frontal below 0.4,
/// scratch from 0.75.
pub const ALTERNATIVE_THRESHOLDS: ZetaThresholds = ZetaThresholds {
    frontal_below: 0.4,
    scratch_from: 0.75,
};

/// The impacts' regimes under other ζ_CT bounds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AlternativeRegimes {
    /// The bounds.
    pub zeta_ct_thresholds: ZetaThresholds,
    /// The metrics per regime under them.
    pub regimes: Regimes,
}

impl ZetaThresholds {
    /// The regime of eccentricity `zeta_ct` under these bounds (NaN: scratch, as
    /// [`Regime::of`]).
    pub fn regime(&self, zeta_ct: f64) -> Regime {
        Regime::with_bounds(zeta_ct, self.frontal_below, self.scratch_from)
    }
}

/// The rock of an impact-lab run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LabRock {
    /// Volume, m³.
    pub volume_m3: f64,
    /// Density, kg/m³.
    pub density_kg_m3: f64,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Vertices of its hull.
    pub vertices: u64,
    /// Extents along the principal axes, m.
    pub axis_lengths_m: [f64; 3],
    /// Aspect ratio (dimensionless).
    pub aspect_ratio: f64,
    /// Shape class (`cubic`, `flat`, `long`, …).
    pub class: String,
    /// Principal moments of inertia, kg·m².
    pub principal_moments_kgm2: [f64; 3],
    /// Radius of the smallest centred ball holding the rock, m.
    pub circumradius_m: f64,
}

/// The stem of an impact-lab run: a truncated cone.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LabStem {
    /// Diameter at the ground, m.
    pub d0_m: f64,
    /// Diameter at the top, m.
    pub d1_m: f64,
    /// Height, m.
    pub h_m: f64,
}

/// How the candidates of an impact-lab run are released (see [`crate::LabSetup`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LabRelease {
    /// Height of the rock centre above the plane, m.
    pub release_height_m: f64,
    /// Smallest horizontal distance between a release point and the stem axis, m.
    pub min_axis_distance_m: f64,
    /// Side of the square release lattice, m.
    pub lattice_side_m: f64,
    /// Lattice points per side.
    pub lattice_points_per_side: u32,
    /// Rocks released from each lattice point.
    pub orientations_per_point: u32,
    /// Release speed range, m/s.
    pub speed_ms: [f64; 2],
    /// Release spin range, rad/s.
    pub spin_rads: [f64; 2],
    /// Horizontal direction range θ, degrees.
    pub theta_deg: [f64; 2],
    /// Vertical direction range χ, degrees.
    pub chi_deg: [f64; 2],
    /// Time step, s.
    pub dt_s: f64,
    /// Longest simulated time of one candidate, s.
    pub max_time_s: f64,
}

/// The eccentricity bounds of the regimes (`rockfall_forest::impact_type`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ZetaThresholds {
    /// Frontal below this ζ_CT.
    pub frontal_below: f64,
    /// Scratch from this ζ_CT on.
    pub scratch_from: f64,
}

impl LabSummary {
    /// The summary of `run` of rocks of `shape` in `lab`, seeded with `seed`, `samples`
    /// impacts asked for.
    pub fn new(shape: &str, lab: &Lab, run: &LabRun, seed: u64, samples: u64) -> LabSummary {
        let s = lab.setup();
        let b = lab.body();
        let g = &b.geometry;
        let metrics: Vec<Metrics> = run.impacts.iter().map(Metrics::from).collect();
        let alternative: Vec<Metrics> = (run.impacts.iter().zip(&metrics))
            .map(|(i, m)| Metrics {
                regime: ALTERNATIVE_THRESHOLDS.regime(i.zeta_ct),
                ..*m
            })
            .collect();
        let pair = |(lo, hi): (f64, f64)| [lo, hi];
        LabSummary {
            experiment: "impact-lab".into(),
            shape: shape.into(),
            rock: LabRock {
                volume_m3: g.volume_m3,
                density_kg_m3: b.density_kg_m3,
                mass_kg: b.mass_kg,
                vertices: g.vertices_m.len() as u64,
                axis_lengths_m: g.lengths_m,
                aspect_ratio: g.aspect_ratio(),
                class: g.class().name().into(),
                principal_moments_kgm2: [b.inertia_kgm2.x, b.inertia_kgm2.y, b.inertia_kgm2.z],
                circumradius_m: g.circumradius_m,
            },
            stem: LabStem {
                d0_m: s.stem_d0_m,
                d1_m: s.stem_d1_m(),
                h_m: s.stem_h_m,
            },
            contact: ContactParams {
                mu: s.mu,
                eps_n: s.eps_n,
                eps_t: s.eps_t,
            },
            setup: LabRelease {
                release_height_m: s.release_height_m,
                min_axis_distance_m: s.min_axis_distance_m,
                lattice_side_m: s.lattice_side_m,
                lattice_points_per_side: s.lattice_points_per_side,
                orientations_per_point: s.orientations_per_point,
                speed_ms: pair(s.speed_ms),
                spin_rads: pair(s.spin_rads),
                theta_deg: pair(s.theta_deg),
                chi_deg: pair(s.chi_deg),
                dt_s: s.dt_s,
                max_time_s: s.max_time_s,
            },
            zeta_ct_thresholds: ZetaThresholds {
                frontal_below: FRONTAL_MAX,
                scratch_from: LATERAL_MAX,
            },
            seed,
            samples_requested: samples,
            samples: run.impacts.len() as u64,
            candidates_total: s.candidates(),
            candidates_tried: run.tried,
            hit_rate: run.impacts.len() as f64 / run.tried.max(1) as f64,
            misses: run.misses,
            exhausted: run.exhausted,
            threads: run.threads as u64,
            wall_time_s: run.wall_time_s,
            regimes: Regimes::of(&metrics),
            regimes_alternative: Some(AlternativeRegimes {
                zeta_ct_thresholds: ALTERNATIVE_THRESHOLDS,
                regimes: Regimes::of(&alternative),
            }),
            all: RegimeSummary::of(&metrics, |_| true).report(metrics.len()),
        }
    }
}

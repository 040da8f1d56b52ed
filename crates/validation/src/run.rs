//! `rockfall validate` end to end: the published-experiment runs, compared and written.
//!
//! Each Vaujany site runs as the experiments observed it (cut below the last observation,
//! `vaujany::build_observed`) on the lumped engine and is compared with every published case
//! of that site (table 2, the table 3 screens); forest-slope-40 runs seed 001's shape study
//! and checks its findings; then the sensitivity table ([`crate::sensitivity`]). Every run
//! goes through the driver (`rockfall_sim`) and is written as a run folder of its own.

use crate::figure::{FIG2_FILE, tree_impacts_figure};
use crate::shapes::{EOTA, ROUGH_CLASSES, SHAPES, ShapeStudies, rough_members, shape_case};
use crate::{CaseReport, Meta, ValidationError, fair, measure, published, write_reports};
use rockfall_lab::study::{ShapeStudy, StudyShape, run_shape_study};
use rockfall_report::ReportInput;
use rockfall_scenario::{LumpedSettings, MohMode, Scenario};
use rockfall_sim::{Observer, Overrides, Simulation};
use rockfall_sites::vaujany::{self, Site};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The runs `validate` knows, in the order it runs them.
pub const CASES: [&str; 6] = [
    "vaujany-site1",
    "vaujany-site2",
    "vaujany-crossval",
    "impact-lab",
    "forest-slope-40",
    "leine-ramp-40",
];

/// Rocks per Vaujany site as in seed 000 (§2.6) and per shape as in seed 001 (§3.4).
pub const ROCKS: (u64, u64) = (10_000, 500);
/// Rocks per Vaujany site and per shape of a quick validation.
pub const QUICK_ROCKS: (u64, u64) = (1000, 30);

/// What a validation runs.
#[derive(Debug, Clone)]
pub struct Validate {
    /// The runs, among [`CASES`], in running order.
    pub cases: Vec<&'static str>,
    /// Rocks per Vaujany site.
    pub site_rocks: u64,
    /// Rocks per shape of the shape study.
    pub shape_rocks: u64,
    /// Master seed of every run.
    pub seed: u64,
    /// Worker threads.
    pub threads: usize,
    /// The command line, for the reports.
    pub command: String,
}

impl Validate {
    /// The runs `names` asks for (none: all) in running order; an unknown name is an error.
    pub fn select(names: &[String]) -> Result<Vec<&'static str>, ValidationError> {
        if let Some(bad) = names.iter().find(|c| !CASES.contains(&c.as_str())) {
            return Err(ValidationError::UnknownCase(format!(
                "unknown case `{bad}` (known: {})",
                CASES.join(", ")
            )));
        }
        Ok(CASES
            .into_iter()
            .filter(|c| names.is_empty() || names.iter().any(|a| a == c))
            .collect())
    }
}

/// A validation's outcome: the compared cases, what was run, and the files written.
#[derive(Debug, Clone)]
pub struct Validation {
    /// Every case compared.
    pub cases: Vec<CaseReport>,
    /// Seed, threads, settings, figures, sensitivity table.
    pub meta: Meta,
    /// `validation.json`, `validation.md` and the figures.
    pub files: Vec<PathBuf>,
}

/// Runs `v` into `out` and writes `validation.json`, `validation.md` and the figures.
pub fn run_validation(
    v: &Validate,
    out: &Path,
    observer: &dyn Observer,
) -> Result<Validation, ValidationError> {
    let started = Instant::now();
    let mut cases = Vec::new();
    let mut meta = Meta {
        seed: v.seed,
        threads: v.threads,
        wall_time_s: 0.0,
        command: v.command.clone(),
        settings: Vec::new(),
        figures: Vec::new(),
        sensitivity: Vec::new(),
    };
    for &name in &v.cases {
        if name == crate::lab::NAME {
            // seed 001's 5000 impacts per shape by default: ten times the rocks of a shape
            let samples = 10 * v.shape_rocks;
            cases.push(crate::lab::lab_case(v, samples, out)?);
            meta.settings.push(format!(
                "rigid: impact laboratory of seed 001 §2, shapes {}, {samples} impacts each",
                crate::lab::SHAPES.join(", ")
            ));
            for (what, file) in [
                ("total energy loss", "energy_loss_total.png"),
                ("change of rotational speed Δω", "rotation_change.png"),
            ] {
                meta.figures.push((
                    format!("PDFs of the {what} per regime, flat2.2 (cf. seed 001 figs. 3–4)"),
                    format!("{name}/flat2.2/{file}"),
                ));
            }
        } else if name == crate::ramp::NAME {
            // the paper's 1 000 rocks by default: twice the rocks of a shape
            for law in [GroundLaw::Scarring, GroundLaw::Hard] {
                cases.push(crate::ramp::ramp_case(
                    v,
                    2 * v.shape_rocks,
                    law,
                    out,
                    observer,
                )?);
            }
            meta.settings.push(format!(
                "rigid: built-in {name}, 780 kg eota221 of 0.93 × 0.93 × 0.465 m, dt 2 ms, {} \
                 rocks, on the scarring ground (medium class) and on the hard ground of Leine \
                 et al. 2014",
                2 * v.shape_rocks
            ));
        } else if name == crate::crossval::NAME {
            cases.extend(crate::crossval::crossval_cases(v, observer)?);
            meta.settings.push(format!(
                "lumped: cross-validation, free factors {} calibrated on one Vaujany site ({} \
                 candidates of {} rocks, the site's release height and speed with them) and \
                 carried to the other",
                crate::crossval::free_factors()
                    .iter()
                    .map(|p| p.key.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                crate::crossval::BUDGET,
                crate::crossval::CALIBRATION_ROCKS.min(v.site_rocks)
            ));
        } else if name == "forest-slope-40" {
            for law in [GroundLaw::Scarring, GroundLaw::Hard] {
                cases.push(shape_study_case(name, law, v, out, observer)?);
            }
            meta.settings.push(format!(
                "rigid: built-in {name} on the scarring ground (medium class) and, in \
                 `{name}-hard`, on the hard ground of Leine et al. 2014; shapes {}; rough \
                 classes {} of {} members each; EOTA blocks {}",
                SHAPES.join(", "),
                ROUGH_CLASSES.join(", "),
                rough_members(v.shape_rocks),
                EOTA.join(", ")
            ));
            for (what, dir) in [
                ("seed 001's stand-in shapes", ""),
                ("rough classes", "rough/"),
                ("EOTA blocks", "eota/"),
            ] {
                meta.figures.push((
                    format!(
                        "Trajectories of {what} coloured by total energy (cf. seed 001 fig. 6)"
                    ),
                    format!("{name}/{dir}trajectories_plan.png"),
                ));
            }
        } else {
            let (site_cases, settings) = vaujany_cases(name, v, out, &mut meta, observer)?;
            cases.extend(site_cases);
            if !meta.settings.contains(&settings) {
                meta.settings.push(settings);
            }
        }
    }
    // the sensitivity table: a fifth of the rocks per run (at least 200)
    let rocks = (v.site_rocks / 5).max(200);
    meta.sensitivity =
        crate::sensitivity::sensitivity(&v.cases, rocks, v.seed, v.threads, observer)?;
    meta.wall_time_s = started.elapsed().as_secs_f64();
    let mut files = write_reports(out, &cases, &meta)?;
    files.extend(meta.figures.iter().map(|(_, f)| out.join(f)));
    Ok(Validation { cases, meta, files })
}

/// Runs a Vaujany site as the experiments observed it on the lumped engine, writes its
/// outputs in `out/<name>` and compares it with every published case of that site (table 2,
/// table 3 screens); the fig. 2 histogram for a forested site. Returns the cases and the
/// engine settings in a line.
fn vaujany_cases(
    name: &str,
    v: &Validate,
    out: &Path,
    meta: &mut Meta,
    observer: &dyn Observer,
) -> Result<(Vec<CaseReport>, String), ValidationError> {
    let site = match name {
        "vaujany-site1" => Site::One,
        _ => Site::Two,
    };
    let mut scenario: Scenario = vaujany::build_observed(site)?;
    scenario.output.rocks_csv = true;
    let overrides = Overrides {
        seed: Some(v.seed),
        rocks_per_cell: Some(v.site_rocks),
        threads: Some(v.threads),
        ..Overrides::default()
    };
    let sim = Simulation::new(scenario, &overrides)?;
    let (scenario, forest) = (sim.scenario(), sim.stems());
    let results = sim.run(true, name, observer)?;
    write_case_run(
        &out.join(name),
        &sim,
        &results,
        format!("built-in site {name}, cut where the experiments observed (rockfall validate)"),
        &v.command,
        observer,
    )?;
    let summary = results.summary();
    let records = results.rock_records();
    let site_published: Vec<_> = published().into_iter().filter(|p| p.site == name).collect();
    let site_rocks = site_published.iter().find_map(|p| p.observed_rocks);
    let mut cases = Vec::new();
    for p in &site_published {
        let simulated = match p.screen {
            None => measure::slope_quantities(&summary, records),
            Some(screen) => measure::screen_quantities(&summary, screen),
        };
        let mut case = CaseReport::compare(p, "lumped", results.rocks(), &simulated);
        if let Some(n) = site_rocks {
            let at = p
                .screen
                .map(|name| scenario.screens.iter().position(|s| s.name == name));
            let maxima = match at {
                None => fair::group_maxima(&results, None, n),
                Some(Some(i)) => fair::group_maxima(&results, Some(i), n),
                Some(None) => BTreeMap::new(), // a screen the site does not have
            };
            case.add_fair(&maxima, n);
        }
        if let Some(n) = p.observed_rocks
            && let Some((vmax, h)) = measure::per_rock_quantile_of_max(records, n)
        {
            case.notes.push(format!(
                "the maxima are over {} simulated rocks, the observed ones over {}; the largest \
                 of {} rocks is, in expectation, near the per-rock {:.0}th percentile: {vmax:.1} \
                 m/s and {h:.2} m here",
                results.rocks(),
                n,
                n,
                100.0 * (1.0 - 1.0 / (f64::from(n) + 1.0))
            ));
        }
        cases.push(case);
    }
    let trees = (site_published.iter())
        .flat_map(|p| &p.quantities)
        .find(|q| q.key == "tree_impacts_per_rock");
    if let (Some(q), Some(_)) = (trees, forest) {
        let counts = measure::tree_impact_counts(records);
        tree_impacts_figure(&out.join(FIG2_FILE), name, &counts, q.observed, q.rockyfor)?;
        meta.figures.push((
            format!("{name}: tree impacts per rock (cf. seed 000 fig. 2)"),
            FIG2_FILE.to_string(),
        ));
    }
    Ok((cases, lumped_settings(&scenario.lumped)))
}

/// The lumped engine's settings in a line.
fn lumped_settings(l: &LumpedSettings) -> String {
    let moh = match l.moh {
        MohMode::Draw => "drawn 70/20/10 %",
        MohMode::Mean => "the eq. 4 mean",
    };
    format!(
        "lumped: tangential rebound law {}, MOH {moh} per rebound, r_t ± {} %, slope lowered by \
         up to {}°, r_n / (1 + (v_n/{} m/s)²), roughness tilt × {}, lateral deviation ≤ {}°, \
         lift-off above {} × MOH, rolling friction max({} × tan φ_soil, MOH/R), stop below {} m/s",
        l.tangential.name(),
        100.0 * l.rt_variation,
        l.slope_reduction_max_deg,
        l.rn_velocity_scale_ms,
        l.roughness_tilt_factor,
        l.max_lateral_deviation_deg,
        l.lift_off_obstacle_factor,
        l.soil_friction_scale,
        l.stop_velocity_ms
    )
}

/// Runs seed 001's shape study on the built-in forest-slope-40 into `out/<name>` and checks
/// the paper's findings.
fn shape_study_case(
    name: &str,
    law: GroundLaw,
    v: &Validate,
    out: &Path,
    observer: &dyn Observer,
) -> Result<CaseReport, ValidationError> {
    let overrides = Overrides {
        seed: Some(v.seed),
        ..Overrides::default()
    };
    let mut scenario = rockfall_sites::build(name)?;
    scenario.contact = law.contact();
    let (base, forest) = Simulation::new(scenario, &overrides)?.into_parts();
    let name = &law.case_name(name);
    let study = |shapes: Vec<StudyShape>, rocks: u64, dir: PathBuf| {
        let study = ShapeStudy {
            shapes,
            rocks,
            interval_s: 0.05,
            threads: v.threads,
            input: "built-in site forest-slope-40 (rockfall shape-study)".into(),
            command: v.command.clone(),
        };
        run_shape_study(&base, &forest, &study, &dir, observer).map(|(s, _)| s.stats)
    };
    // the rough classes as ensembles: members of an equal share of the rocks
    let members = rough_members(v.shape_rocks);
    let dir = out.join(name);
    let studies = ShapeStudies {
        stand_ins: study(
            SHAPES.map(StudyShape::named).into(),
            v.shape_rocks,
            dir.clone(),
        )?,
        rough: study(
            ROUGH_CLASSES
                .map(|c| StudyShape::ensemble(c, members))
                .into(),
            (v.shape_rocks / members).max(1),
            dir.join("rough"),
        )?,
        eota: study(
            EOTA.map(StudyShape::named).into(),
            v.shape_rocks,
            dir.join("eota"),
        )?,
    };
    Ok(shape_case(name, law.describe(), &studies, v.shape_rocks))
}

/// The ground law a rigid case runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroundLaw {
    /// The scarring ground of Lu et al. 2019, `medium` class (the built-in sites' own).
    Scarring,
    /// The hard ground with the slippage friction of Leine et al. 2014 (the law before).
    Hard,
}

impl GroundLaw {
    /// Its contact settings (seed 001's stems with μ 0.1).
    pub fn contact(self) -> rockfall_scenario::ContactSettings {
        match self {
            GroundLaw::Scarring => rockfall_sites::forest_slope::scarring_contact(),
            GroundLaw::Hard => rockfall_sites::forest_slope::leine_2014_contact(),
        }
    }

    /// The case name for the site `site`: the site's own on the scarring ground, `<site>-hard`
    /// on the hard one.
    pub fn case_name(self, site: &str) -> String {
        match self {
            GroundLaw::Scarring => site.to_string(),
            GroundLaw::Hard => format!("{site}-hard"),
        }
    }

    /// In words, for the reports.
    pub fn describe(self) -> &'static str {
        match self {
            GroundLaw::Scarring => {
                "the scarring ground of Lu et al. 2019 (medium class: M_e 15 MN/m², C_s 1.5, \
                 C_f 1, ρ 1700 kg/m³, μ 0.55–2.0, β 185 s⁻¹, κ 3 m⁻¹)"
            }
            GroundLaw::Hard => {
                "the hard ground of Leine et al. 2014 (ε = 0, slippage friction μ 0.2–1.3, β \
                 20 s⁻¹, κ 0.7 m⁻¹), the law before the scarring ground"
            }
        }
    }
}

/// Writes the run of `sim` into `dir` as `rockfall run` writes a run (rasters, tables,
/// report, its forest's stems), telling `observer`; `input` says what was read.
pub(crate) fn write_case_run(
    dir: &Path,
    sim: &Simulation,
    results: &rockfall_results::Results,
    input: String,
    command: &str,
    observer: &dyn Observer,
) -> Result<(), ValidationError> {
    let report = ReportInput {
        scenario: sim.scenario(),
        results,
        stems: sim.stems().map_or(&[], |f| f.stems()),
        input,
        command: command.to_string(),
        files: Vec::new(),
        forest_effect: None,
        links: Vec::new(),
        label: String::new(),
    };
    let files = rockfall_report::write_run(dir, false, &report)?;
    observer.wrote(dir, &files);
    Ok(())
}

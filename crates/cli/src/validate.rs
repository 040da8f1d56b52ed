//! `rockfall validate`: the published-experiment cases run, compared and written.

use crate::Failure;
use crate::lab::{StudyFlags, print_files, run_shape_study};
use crate::simulate;
use anyhow::anyhow;
use rockfall_scenario::{LumpedSettings, MohMode, Scenario};
use rockfall_sites::vaujany::{self, Site};
use rockfall_validation::fair;
use rockfall_validation::figure::{FIG2_FILE, tree_impacts_figure};
use rockfall_validation::shapes::{SHAPES, shape_case};
use rockfall_validation::{CaseReport, Meta, measure, published, report, write_reports};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

/// The runs `validate` knows, in the order it runs them.
pub const CASES: [&str; 3] = ["vaujany-site1", "vaujany-site2", "forest-slope-40"];

/// Rocks per Vaujany site as in seed 000 (§2.6), per shape as in seed 001 (§3.4); and for
/// `--quick`.
const ROCKS: (u64, u64) = (10_000, 500);
const QUICK_ROCKS: (u64, u64) = (1000, 30);

/// The flags of `validate`.
pub struct ValidateFlags {
    /// Runs asked for (none: all).
    pub cases: Vec<String>,
    /// `--rocks`.
    pub rocks: Option<u64>,
    /// `--quick`.
    pub quick: bool,
    /// `--seed`.
    pub seed: Option<u64>,
    /// `--threads`.
    pub threads: Option<u64>,
}

impl ValidateFlags {
    /// The runs asked for, in running order; an unknown name is bad input.
    fn selected(&self) -> Result<Vec<&'static str>, Failure> {
        if let Some(bad) = self.cases.iter().find(|c| !CASES.contains(&c.as_str())) {
            return Err(Failure::BadInput(anyhow!(
                "unknown case `{bad}` (known: {})",
                CASES.join(", ")
            )));
        }
        let all = self.cases.is_empty();
        Ok(CASES
            .into_iter()
            .filter(|c| all || self.cases.iter().any(|a| a == c))
            .collect())
    }

    /// Rocks per Vaujany run and per shape.
    fn rocks(&self) -> (u64, u64) {
        match (self.rocks, self.quick) {
            (Some(n), _) => (n, n),
            (None, true) => QUICK_ROCKS,
            (None, false) => ROCKS,
        }
    }
}

/// `rockfall validate`.
pub fn validate(flags: &ValidateFlags, out: &Path) -> Result<(), Failure> {
    let selected = flags.selected()?;
    let (site_rocks, shape_rocks) = flags.rocks();
    let seed = flags.seed.unwrap_or(1);
    let threads = simulate::threads(flags.threads);
    let started = Instant::now();
    let mut cases = Vec::new();
    let mut meta = Meta {
        seed,
        threads,
        wall_time_s: 0.0,
        // lossy: a path that is not UTF-8 must not make the report panic
        command: std::iter::once("rockfall".to_string())
            .chain(
                std::env::args_os()
                    .skip(1)
                    .map(|a| a.to_string_lossy().into_owned()),
            )
            .collect::<Vec<_>>()
            .join(" "),
        settings: Vec::new(),
        figures: Vec::new(),
        sensitivity: Vec::new(),
    };
    for &name in &selected {
        if name == "forest-slope-40" {
            cases.push(shape_study_case(
                name,
                shape_rocks,
                seed,
                flags.threads,
                out,
            )?);
            meta.settings.push(format!(
                "rigid: built-in {name}, shapes {}, the scenario's contact laws",
                SHAPES.join(", ")
            ));
            meta.figures.push((
                "Trajectories per shape coloured by total energy (cf. seed 001 fig. 6)".into(),
                format!("{name}/trajectories_plan.png"),
            ));
        } else {
            let (site_cases, settings) =
                vaujany_cases(name, site_rocks, seed, threads, out, &mut meta)?;
            cases.extend(site_cases);
            if !meta.settings.contains(&settings) {
                meta.settings.push(settings);
            }
        }
    }
    // the sensitivity table: a fifth of the rocks per run (at least 200)
    meta.sensitivity =
        crate::sensitivity::sensitivity(&selected, (site_rocks / 5).max(200), seed, threads)?;
    meta.wall_time_s = started.elapsed().as_secs_f64();
    print!("{}", report::terminal(&cases));
    print!("{}", report::sensitivity_terminal(&meta.sensitivity));
    let mut files = write_reports(out, &cases, &meta).map_err(|e| Failure::Internal(e.into()))?;
    files.extend(meta.figures.iter().map(|(_, f)| out.join(f)));
    println!();
    print_files(out, &files);
    Ok(())
}

/// Runs a Vaujany site as the experiments observed it (cut below the last observation,
/// [`vaujany::build_observed`]) on the lumped engine, writes its outputs in `out/<name>` and
/// compares it with every published case of that site (table 2, table 3 screens); the fig. 2
/// histogram for a forested site. Returns the cases and the engine settings in a line.
fn vaujany_cases(
    name: &str,
    rocks: u64,
    seed: u64,
    threads: usize,
    out: &Path,
    meta: &mut Meta,
) -> Result<(Vec<CaseReport>, String), Failure> {
    let site = match name {
        "vaujany-site1" => Site::One,
        _ => Site::Two,
    };
    let mut scenario: Scenario =
        vaujany::build_observed(site).map_err(|e| Failure::Internal(e.into()))?;
    scenario.simulation.rocks_per_cell = rocks;
    scenario.seed = seed;
    scenario.output.rocks_csv = true;
    let forest = scenario
        .build_forest()
        .map_err(|e| Failure::Internal(e.into()))?;
    let forest = (!forest.is_empty()).then_some(&forest);
    let results = simulate::simulate(&scenario, forest, threads, name)?;
    let input =
        format!("built-in site {name}, cut where the experiments observed (rockfall validate)");
    simulate::write(
        &results,
        &out.join(name),
        false,
        &simulate::Context::new(&scenario, forest, input),
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
            && let Some((v, h)) = measure::per_rock_quantile_of_max(records, n)
        {
            case.notes.push(format!(
                "the maxima are over {} simulated rocks, the observed ones over {}; the largest \
                 of {} rocks is, in expectation, near the per-rock {:.0}th percentile: {v:.1} m/s \
                 and {h:.2} m here",
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
        tree_impacts_figure(&out.join(FIG2_FILE), name, &counts, q.observed, q.rockyfor)
            .map_err(|e| Failure::Internal(e.into()))?;
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
         lift-off above {} × MOH, stop below {} m/s",
        l.tangential.name(),
        100.0 * l.rt_variation,
        l.slope_reduction_max_deg,
        l.rn_velocity_scale_ms,
        l.roughness_tilt_factor,
        l.max_lateral_deviation_deg,
        l.lift_off_obstacle_factor,
        l.stop_velocity_ms
    )
}

/// Runs seed 001's shape study on the built-in forest-slope-40 into `out/<name>` and checks
/// the paper's findings.
fn shape_study_case(
    name: &str,
    rocks: u64,
    seed: u64,
    threads: Option<u64>,
    out: &Path,
) -> Result<CaseReport, Failure> {
    let flags = StudyFlags {
        input: None,
        shapes: SHAPES.iter().map(|s| s.to_string()).collect(),
        rocks,
        seed: Some(seed),
        interval_s: 0.05,
        threads,
    };
    let (study, runs) = run_shape_study(&flags, &out.join(name))?;
    let summaries: Vec<_> = runs.iter().map(|r| r.summary.clone()).collect();
    Ok(shape_case(name, &study.stats, &summaries, rocks))
}

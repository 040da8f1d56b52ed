//! `rockfall impact-lab` and `rockfall shape-study`: seed 001's experiments.

use crate::Failure;
use crate::simulate;
use anyhow::anyhow;
use rockfall_lab::study::{ShapeStudy, StudyShape, expand_shape, run_shape_study, shape_label};
use rockfall_lab::summary::{Labelled, Metrics, regime_table};
use rockfall_lab::{Lab, LabError, LabSetup, run_lab};
use rockfall_scenario::RockShape;
use rockfall_sim::{Overrides, Simulation};
use std::path::{Path, PathBuf};

/// The flags of `impact-lab` that shape the experiment.
pub struct LabFlags {
    /// `--shape`.
    pub shape: String,
    /// `--samples`.
    pub samples: u64,
    /// `--seed`.
    pub seed: u64,
    /// `--dbh-m`.
    pub d0_m: f64,
    /// `--mu`.
    pub mu: f64,
    /// `--eps-n`.
    pub eps_n: f64,
    /// `--eps-t`.
    pub eps_t: f64,
    /// `--dt-s`.
    pub dt_s: f64,
    /// `--threads`.
    pub threads: Option<u64>,
}

/// Bad flags and unreadable inputs are the user's; anything else is ours.
fn failure(e: LabError) -> Failure {
    Failure::of(e.is_bad_input(), e)
}

/// The rock shape `flag` (`--shape` or `--shapes`) names in `shape`, a file read into its points
/// (a path relative to the working directory); every problem is bad input.
fn parse_shape(flag: &str, shape: &str) -> Result<RockShape, Failure> {
    let parsed = RockShape::parse(shape).map_err(|e| Failure::BadInput(anyhow!("{flag}: {e}")))?;
    rockfall_io::shape::read_shape(parsed)
        .map_err(|e| Failure::BadInput(anyhow!("{flag} {shape}: {e}")))
}

/// `rockfall impact-lab` (simulating).
pub fn impact_lab(flags: &LabFlags, out: &Path) -> Result<(), Failure> {
    let setup = LabSetup {
        stem_d0_m: flags.d0_m,
        mu: flags.mu,
        eps_n: flags.eps_n,
        eps_t: flags.eps_t,
        dt_s: flags.dt_s,
        ..LabSetup::default()
    };
    let shape = parse_shape("--shape", &flags.shape)?;
    let lab = Lab::with_shape(setup, shape).map_err(|e| match e {
        LabError::Shape(e) => Failure::BadInput(anyhow!("--shape {}: {e}", flags.shape)),
        other => failure(other),
    })?;
    let label = shape_label(&flags.shape);
    let threads = simulate::threads(flags.threads);
    let bar = simulate::progress_bar(flags.samples, &format!("impact-lab {label}"), "impacts");
    let tick = |hits: u64| bar.set_position(hits);
    let run = run_lab(&lab, flags.seed, flags.samples, threads, &tick).map_err(failure)?;
    bar.finish_and_clear();
    let files = rockfall_lab::output::write_lab(out, &label, &lab, &run, flags.seed, flags.samples)
        .map_err(failure)?;
    println!(
        "impact-lab: {label}, {} impacts from {} candidates tried (hit rate {:.1} %) in {:.1} s \
         on {threads} threads",
        run.impacts.len(),
        run.tried,
        100.0 * run.impacts.len() as f64 / run.tried.max(1) as f64,
        run.wall_time_s
    );
    if run.exhausted {
        println!(
            "  every candidate was tried: only {} of the {} impacts asked for exist",
            run.impacts.len(),
            flags.samples
        );
    }
    let runs = [Labelled {
        label,
        metrics: run.impacts.iter().map(Metrics::from).collect(),
    }];
    print!("{}", regime_table(&runs));
    print_files(out, &files);
    Ok(())
}

/// `rockfall impact-lab --compare DIR…`.
pub fn compare(dirs: &[PathBuf], out: &Path) -> Result<(), Failure> {
    let (runs, files) = rockfall_lab::compare::compare(dirs, out).map_err(failure)?;
    print!("{}", regime_table(&runs));
    print_files(out, &files);
    Ok(())
}

pub fn print_files(out: &Path, files: &[PathBuf]) {
    println!("wrote {} files to {}:", files.len(), out.display());
    for f in files {
        println!("  {}", f.display());
    }
}

/// The flags of `shape-study`.
pub struct StudyFlags {
    /// The input, or `None` for the built-in forest-slope-40.
    pub input: Option<PathBuf>,
    /// `--shapes`.
    pub shapes: Vec<String>,
    /// `--rocks`.
    pub rocks: u64,
    /// `--seed`.
    pub seed: Option<u64>,
    /// `--interval-s`.
    pub interval_s: f64,
    /// `--threads`.
    pub threads: Option<u64>,
}

/// `rockfall shape-study`.
pub fn shape_study(flags: &StudyFlags, out: &Path) -> Result<(), Failure> {
    let overrides = Overrides {
        seed: flags.seed,
        ..Overrides::default()
    };
    let sim = match &flags.input {
        Some(input) => crate::commands::load_simulation(input, &overrides)?,
        None => {
            let site = rockfall_sites::build("forest-slope-40")
                .map_err(|e| Failure::Internal(e.into()))?;
            Simulation::new(site, &overrides).map_err(|e| Failure::Internal(e.into()))?
        }
    };
    let (base, forest) = sim.into_parts();
    let shapes = (flags.shapes.iter())
        .map(|item| {
            let (label, names) =
                expand_shape(item).map_err(|e| Failure::BadInput(anyhow!("--shapes: {e}")))?;
            let members = (names.into_iter())
                .map(|n| Ok((shape_label(&n), parse_shape("--shapes", &n)?)))
                .collect::<Result<Vec<_>, Failure>>()?;
            Ok(StudyShape { label, members })
        })
        .collect::<Result<Vec<_>, Failure>>()?;
    let study = ShapeStudy {
        shapes,
        rocks: flags.rocks,
        interval_s: flags.interval_s,
        threads: simulate::threads(flags.threads),
        input: flags.input.as_ref().map_or_else(
            || "built-in site forest-slope-40 (rockfall shape-study)".to_owned(),
            |p| p.display().to_string(),
        ),
        command: simulate::command_line(),
    };
    let console = simulate::Console::with_summaries();
    let (study, _) = run_shape_study(&base, &forest, &study, out, &console).map_err(failure)?;
    print!("{}", study.markdown);
    print_files(out, &study.files);
    Ok(())
}

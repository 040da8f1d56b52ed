//! `rockfall impact-lab` and `rockfall shape-study`: seed 001's experiments.

use crate::Failure;
use crate::simulate;
use anyhow::anyhow;
use rockfall_lab::slope::{FallLine, SlopeRun, Study, write_study};
use rockfall_lab::summary::{Labelled, Metrics, regime_table};
use rockfall_lab::{Lab, LabError, LabSetup, run_lab};
use rockfall_rigid::shape::body_from_spec;
use rockfall_scenario::{Engine, RockShape, RockSpec, Scenario};
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
    match e {
        LabError::Setup(_) | LabError::Shape(_) | LabError::Read { .. } => {
            Failure::BadInput(e.into())
        }
        // a missing input folder or an output folder we may not write to
        LabError::Io { ref source, .. }
            if matches!(
                source.kind(),
                std::io::ErrorKind::NotFound | std::io::ErrorKind::PermissionDenied
            ) =>
        {
            Failure::BadInput(e.into())
        }
        other => Failure::Internal(other.into()),
    }
}

/// The rock shape `flag` (`--shape` or `--shapes`) names in `shape`, a file read into its points
/// (a path relative to the working directory); every problem is bad input.
fn parse_shape(flag: &str, shape: &str) -> Result<RockShape, Failure> {
    let parsed = RockShape::parse(shape).map_err(|e| Failure::BadInput(anyhow!("{flag}: {e}")))?;
    rockfall_io::shape::read_shape(parsed)
        .map_err(|e| Failure::BadInput(anyhow!("{flag} {shape}: {e}")))
}

/// The rock of `shape` scaled to `volume_m3` at `density_kg_m3` (a file read into its points).
pub fn rock_spec(shape: &str, volume_m3: f64, density_kg_m3: f64) -> Result<RockSpec, Failure> {
    let parsed = parse_shape("--shape", shape)?;
    // block shapes start as a sphere of the volume's diameter; every shape is then rescaled
    let d_m = (6.0 * volume_m3 / std::f64::consts::PI).cbrt();
    Ok(RockSpec {
        shape: parsed,
        volume_m3: Some(volume_m3),
        ..RockSpec::sphere(d_m, density_kg_m3)
    })
}

/// A short name for a shape: its name, or a file's stem.
pub fn shape_label(shape: &str) -> String {
    match RockShape::parse(shape) {
        Ok(RockShape::File(p)) => p
            .file_stem()
            .map_or_else(|| shape.to_string(), |s| s.to_string_lossy().into()),
        _ => shape.to_ascii_lowercase(),
    }
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
    let spec = rock_spec(&flags.shape, setup.volume_m3, setup.density_kg_m3)?;
    let body = body_from_spec(&spec)
        .map_err(|e| Failure::BadInput(anyhow!("--shape {}: {e}", flags.shape)))?;
    let lab = Lab::new(setup, body).map_err(failure)?;
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
    let (study, _) = run_shape_study(flags, out)?;
    print!("{}", study.markdown);
    print_files(out, &study.files);
    Ok(())
}

/// Runs and writes the shape study of `flags` into `out`; returns it with its runs.
pub fn run_shape_study(flags: &StudyFlags, out: &Path) -> Result<(Study, Vec<SlopeRun>), Failure> {
    if !(flags.interval_s.is_finite() && flags.interval_s > 0.0) {
        return Err(Failure::BadInput(anyhow!(
            "--interval-s must be finite and > 0"
        )));
    }
    let (mut base, forest) = match &flags.input {
        Some(input) => {
            let overrides = rockfall_sim::Overrides {
                seed: flags.seed,
                ..Default::default()
            };
            crate::commands::load_simulation(input, &overrides)?.into_parts()
        }
        None => {
            let s = rockfall_sites::build("forest-slope-40")
                .map_err(|e| Failure::Internal(e.into()))?;
            let f = s.build_forest().map_err(|e| Failure::Internal(e.into()))?;
            (s, f)
        }
    };
    let input_name = flags.input.as_ref().map_or_else(
        || "built-in site forest-slope-40 (rockfall shape-study)".to_owned(),
        |p| p.display().to_string(),
    );
    base.engine = Engine::Rigid;
    base.seed = flags.seed.unwrap_or(base.seed);
    base.simulation.rocks_per_point = flags.rocks;
    base.simulation.rocks_per_cell = flags.rocks;
    base.output.trajectory_interval_s = flags.interval_s;
    base.output.trajectories = u64::MAX; // every rock's path
    let line = fall_line(&base)?;
    let scenarios = shape_scenarios(&base, &flags.shapes)?;
    let threads = simulate::threads(flags.threads);
    let forest = (!forest.is_empty()).then_some(&forest);
    let mut runs = Vec::new();
    for (label, sc) in &scenarios {
        let results = simulate::simulate(sc, forest, threads, label)?;
        simulate::print_summary(&format!("{label}:"), &results);
        let ctx = simulate::Context {
            label: format!("shape {label}"),
            ..simulate::Context::new(sc, forest, input_name.clone())
        };
        simulate::write(&results, &out.join(label), false, &ctx)?;
        runs.push(SlopeRun::new(label, &results));
    }
    let study = write_study(out, &runs, &line).map_err(failure)?;
    Ok((study, runs))
}

/// `base` once per shape of `shapes` (at `base`'s rock volume), labelled; every shape is
/// checked, and labels must differ (each names its output folder), before anything runs.
fn shape_scenarios(base: &Scenario, shapes: &[String]) -> Result<Vec<(String, Scenario)>, Failure> {
    if shapes.is_empty() {
        return Err(Failure::BadInput(anyhow!(
            "--shapes: give at least one shape"
        )));
    }
    let volume_m3 = match base.rock.volume_m3 {
        Some(v) => v,
        None => {
            body_from_spec(&base.rock)
                .map_err(|e| Failure::BadInput(anyhow!("rock: {e}")))?
                .geometry
                .volume_m3
        }
    };
    let mut out: Vec<(String, Scenario)> = Vec::new();
    for shape in shapes {
        let label = shape_label(shape);
        if out.iter().any(|(l, _)| *l == label) {
            return Err(Failure::BadInput(anyhow!(
                "--shapes: `{label}` twice (each shape's run goes to a folder of its name)"
            )));
        }
        let mut sc = base.clone();
        sc.rock.shape = parse_shape("--shapes", shape)?;
        sc.rock.volume_m3 = Some(volume_m3);
        body_from_spec(&sc.rock)
            .map_err(|e| Failure::BadInput(anyhow!("--shapes {shape}: {e}")))?;
        out.push((label, sc));
    }
    Ok(out)
}

/// The fall line at the first release of `s`.
fn fall_line(s: &Scenario) -> Result<FallLine, Failure> {
    let dem = &s.terrain.dem;
    let xy = match (s.release.points.first(), s.release.cells.first()) {
        (Some(p), _) => [p.x_m, p.y_m],
        (None, Some(&cell)) => {
            let g = dem.geometry();
            let (row, col) = g.row_col(cell);
            let (x, y) = g.cell_center(row, col);
            [x, y]
        }
        (None, None) => return Err(Failure::BadInput(anyhow!("the scenario releases no rocks"))),
    };
    dem.surface_at(xy[0], xy[1])
        .and_then(|p| FallLine::new(xy, p.dzdx, p.dzdy))
        .ok_or_else(|| {
            Failure::BadInput(anyhow!(
                "the ground at the release ({:.1}, {:.1}) is flat or off the DEM: no fall line",
                xy[0],
                xy[1]
            ))
        })
}

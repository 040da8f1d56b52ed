//! `rockfall hazard`: runs a hazard file's scenarios not yet run, then writes the hazard
//! zone map, its rasters, polygons, summary, report page and QGIS project.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::anyhow;
use rockfall_hazard::hazard_file::ScenarioEntry;
use rockfall_hazard::{HazardError, HazardMap, HazardSpec, Source};
use rockfall_raster::Grid;
use rockfall_sim::{Overrides, Simulation};

use crate::Failure;
use crate::simulate;

/// The flags of `rockfall hazard`.
pub struct HazardFlags {
    /// The hazard file.
    pub file: PathBuf,
    /// `--matrix`: a preset or a matrix file, replacing the file's.
    pub matrix: Option<String>,
    /// `--rocks-per-cell` for every scenario run.
    pub rocks_per_cell: Option<u64>,
    /// `--seed` for every scenario run.
    pub seed: Option<u64>,
    /// `--threads`.
    pub threads: Option<u64>,
    /// `--rerun`: run scenarios again even when their run folder is finished.
    pub rerun: bool,
}

/// The record beside a run the hazard command made, telling whether it can be reused.
const RUN_RECORD: &str = "hazard_run.json";

fn hazard_failure(e: HazardError) -> Failure {
    Failure::of(e.is_bad_input(), e)
}

/// Runs `rockfall hazard`.
pub fn hazard(flags: &HazardFlags, out: &Path) -> Result<(), Failure> {
    let start = Instant::now();
    let spec = rockfall_hazard::read_hazard_file(&flags.file, flags.matrix.as_deref())
        .map_err(hazard_failure)?;
    let overrides = Overrides {
        seed: flags.seed,
        rocks_per_cell: flags.rocks_per_cell,
        threads: flags.threads.map(|n| n as usize),
        ..Overrides::default()
    };
    // every scenario is read and checked before anything runs
    let mut sims = Vec::new();
    for (i, entry) in spec.scenarios.iter().enumerate() {
        sims.push(match &entry.source {
            Source::Run(_) => None,
            Source::Scenario(_) | Source::Site(_) => Some(prepare(&spec, i, entry, &overrides)?),
        });
    }
    let mut dirs = Vec::new();
    let mut dem: Option<(Grid<f64>, Option<PathBuf>)> = None;
    for (entry, sim) in spec.scenarios.iter().zip(sims) {
        match (&entry.source, sim) {
            (Source::Run(dir), _) => dirs.push(dir.clone()),
            (Source::Scenario(_) | Source::Site(_), Some(sim)) => {
                if dem.is_none() {
                    let s = sim.scenario();
                    let file = s.source_of("dem").map(Path::to_path_buf);
                    dem = Some((s.terrain.dem.shared_grid().as_ref().clone(), file));
                }
                dirs.push(run_scenario(out, entry, &sim, flags.rerun)?);
            }
            (_, None) => unreachable!("every scenario and site was prepared"),
        }
    }
    let refs: Vec<&Path> = dirs.iter().map(PathBuf::as_path).collect();
    let map = rockfall_hazard::build(&spec, &refs).map_err(hazard_failure)?;
    let relief = rockfall_hazard::Relief {
        dem: dem.as_ref().map(|(g, _)| g),
        file: dem.as_ref().and_then(|(_, f)| f.as_deref()),
    };
    let files = write_outputs(out, &spec, &map, relief, start)?;
    print_areas(&spec, &map, out, &files);
    Ok(())
}

/// Reads scenario entry `i` and applies the entry's block, rocks and the energy thresholds
/// the matrix needs; every problem is bad input naming the hazard file's key.
fn prepare(
    spec: &HazardSpec,
    i: usize,
    entry: &ScenarioEntry,
    overrides: &Overrides,
) -> Result<Simulation, Failure> {
    let key = |k: &str| format!("{}: scenario[{}].{k}", spec.path.display(), i + 1);
    let (mut scenario, path) = match &entry.source {
        Source::Scenario(path) if !path.exists() => {
            return Err(Failure::BadInput(anyhow!(
                "{}: {} not found",
                key("scenario"),
                path.display()
            )));
        }
        Source::Scenario(path) => (rockfall_io::load(path)?, path.clone()),
        Source::Site(name) => {
            let s = rockfall_sites::build(name).map_err(|e| match e {
                rockfall_sites::SiteError::Unknown(_) => {
                    Failure::BadInput(anyhow!("{}: {e}", key("site")))
                }
                other => Failure::Internal(other.into()),
            })?;
            (s, PathBuf::from(format!("built-in site {name}")))
        }
        Source::Run(_) => unreachable!("a run folder is not prepared"),
    };
    rockfall_hazard::adapt::set_block(&mut scenario, &entry.block)
        .map_err(|(k, m)| Failure::BadInput(anyhow!("{}: {m}", key(k))))?;
    rockfall_hazard::adapt::add_thresholds(&mut scenario, &spec.matrix);
    let mut o = overrides.clone();
    if o.rocks_per_cell.is_none() {
        o.rocks_per_cell = entry.rocks_per_cell;
    }
    Simulation::new(scenario, &o).map_err(|e| simulate::sim_failure(e, &path))
}

/// Runs scenario entry `entry` into `out/runs/<label>`, unless that folder already holds a
/// finished run of the same scenario (same fingerprint); returns the run folder.
fn run_scenario(
    out: &Path,
    entry: &ScenarioEntry,
    sim: &Simulation,
    rerun: bool,
) -> Result<PathBuf, Failure> {
    let dir = out
        .join("runs")
        .join(rockfall_hazard::outputs::file_label(&entry.label));
    let fingerprint = rockfall_sim::share::fingerprint(sim.scenario());
    let record = dir.join(RUN_RECORD);
    let finished = std::fs::read_to_string(&record)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| v["fingerprint"] == fingerprint.as_str())
        && dir.join("summary.json").is_file();
    if finished && !rerun {
        println!(
            "{}: reusing the finished run in {} (--rerun to run it again)",
            entry.label,
            dir.display()
        );
        return Ok(dir);
    }
    let scenario = sim.scenario();
    let what = match &entry.source {
        Source::Scenario(p) => p.display().to_string(),
        Source::Site(name) => format!("built-in site {name}"),
        Source::Run(p) => p.display().to_string(),
    };
    println!("{}: running {what}", entry.label);
    let results = simulate::simulate(sim, true, &entry.label)?;
    let ctx = simulate::Context::new(scenario, sim.stems(), what.clone());
    simulate::write(&results, &dir, scenario.output.ascii_rasters, &ctx)?;
    let text = serde_json::json!({
        "label": entry.label,
        "scenario": what,
        "fingerprint": fingerprint,
    });
    rockfall_raster::atomic::write_bytes_atomic(&record, format!("{text:#}\n").as_bytes())
        .map_err(|(p, e)| Failure::Internal(anyhow!("{}: {e}", p.display())))?;
    Ok(dir)
}

fn write_outputs(
    out: &Path,
    spec: &HazardSpec,
    map: &HazardMap,
    relief: rockfall_hazard::Relief<'_>,
    start: Instant,
) -> Result<Vec<PathBuf>, Failure> {
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::Internal(anyhow!("{}: {e}", out.display())))?;
    rockfall_hazard::write_all(out, spec, map, relief, start).map_err(hazard_failure)
}

fn print_areas(spec: &HazardSpec, map: &HazardMap, out: &Path, files: &[PathBuf]) {
    let areas = rockfall_hazard::outputs::areas(&map.classes, map.geometry.cell_area_m2());
    println!(
        "hazard zones ({} matrix, {} mode), {} m cells:",
        spec.matrix.name,
        match spec.mode {
            rockfall_hazard::Mode::Scenario => "scenario",
            rockfall_hazard::Mode::Frequency => "frequency",
        },
        map.geometry.cell_size_m
    );
    for l in areas.levels.iter().rev() {
        println!(
            "  {:<8} ({:<12}) {:>10.2} ha  {:>5.1} %",
            l.name, l.colour, l.area_ha, l.share_pct
        );
    }
    println!("wrote {} files into {}", files.len() + 1, out.display());
}

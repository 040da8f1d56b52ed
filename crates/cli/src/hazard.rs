//! `rockfall hazard`: runs a hazard file's scenarios not yet run, then writes the hazard
//! zone map, its rasters, polygons, summary, report page and QGIS project.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::anyhow;
use rockfall_hazard::runner::{Prepared, is_finished, prepare, record, run_dir};
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
    for i in 0..spec.scenarios.len() {
        sims.push(match prepare(&spec, i).map_err(hazard_failure)? {
            None => None,
            Some(p) => {
                let what = PathBuf::from(&p.what);
                let sim = Simulation::new(p.scenario.clone(), &overrides)
                    .map_err(|e| simulate::sim_failure(e, p.file.as_deref().unwrap_or(&what)))?;
                Some((p, sim))
            }
        });
    }
    let mut dirs = Vec::new();
    let mut relief: Option<(Grid<f64>, Option<PathBuf>)> = None;
    for (entry, prepared) in spec.scenarios.iter().zip(sims) {
        match (&entry.source, prepared) {
            (Source::Run(dir), _) => dirs.push(dir.clone()),
            (_, Some((p, sim))) => {
                if relief.is_none() {
                    let s = sim.scenario();
                    let file = s.source_of("dem").map(Path::to_path_buf);
                    relief = Some((s.terrain.dem.shared_grid().as_ref().clone(), file));
                }
                dirs.push(run_scenario(out, &entry.label, &p, &sim, flags.rerun)?);
            }
            (_, None) => return Err(Failure::Internal(anyhow!("{}: not prepared", entry.label))),
        }
    }
    let refs: Vec<&Path> = dirs.iter().map(PathBuf::as_path).collect();
    let map = rockfall_hazard::build(&spec, &refs).map_err(hazard_failure)?;
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::Internal(anyhow!("{}: {e}", out.display())))?;
    let relief = rockfall_hazard::Relief {
        dem: relief.as_ref().map(|(g, _)| g),
        file: relief.as_ref().and_then(|(_, f)| f.as_deref()),
    };
    let files =
        rockfall_hazard::write_all(out, &spec, &map, relief, start).map_err(hazard_failure)?;
    print_areas(&spec, &map, out, &files);
    Ok(())
}

/// Runs a prepared scenario into `out/runs/<label>`, unless that folder already holds a
/// finished run of the same scenario (same fingerprint); returns the run folder.
fn run_scenario(
    out: &Path,
    label: &str,
    p: &Prepared,
    sim: &Simulation,
    rerun: bool,
) -> Result<PathBuf, Failure> {
    let dir = run_dir(out, label);
    let fingerprint = rockfall_sim::share::fingerprint(sim.scenario());
    if is_finished(&dir, &fingerprint) && !rerun {
        println!(
            "{label}: reusing the finished run in {} (--rerun to run it again)",
            dir.display()
        );
        return Ok(dir);
    }
    println!("{label}: running {}", p.what);
    let what = PathBuf::from(&p.what);
    let input = p.file.as_deref().unwrap_or(&what);
    let results = simulate::simulate(sim, input, true, label)?;
    let scenario = sim.scenario();
    let ctx = simulate::Context::new(scenario, sim.stems(), p.what.clone());
    simulate::write(&results, &dir, scenario.output.ascii_rasters, &ctx)?;
    record(&dir, label, &p.what, &fingerprint).map_err(hazard_failure)?;
    Ok(dir)
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
    println!(
        "wrote {} files into {} (open {})",
        files.len(),
        out.display(),
        out.join("hazard.html").display()
    );
}

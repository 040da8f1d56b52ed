//! One function per subcommand.

use crate::Failure;
use crate::args::Command;
use crate::calibrate;
use crate::lab;
use crate::regional;
use crate::simulate;
use crate::validate;
use anyhow::anyhow;
use rockfall_scenario::{Engine, Overview};
use rockfall_sim::{Overrides, RunRecord, Simulation};
use std::path::{Path, PathBuf};

/// Runs a subcommand.
pub fn dispatch(command: Command) -> Result<(), Failure> {
    if let Some(out) = output_folder(&command) {
        check_output_folder(out)?;
    }
    match command {
        Command::Check { input } => check(&input),
        Command::Schema { markdown, out } => crate::schema::schema(markdown, out.as_deref()),
        Command::Site {
            name,
            out,
            list,
            cells,
            cell_size_m,
            seed,
        } => match (name, out) {
            (Some(name), Some(out)) if !list => {
                let region = RegionOptions {
                    cells,
                    cell_size_m,
                    seed,
                };
                site(&name, &out, region)
            }
            _ => {
                list_sites();
                Ok(())
            }
        },
        Command::Run {
            input,
            out,
            engine,
            rocks_per_cell,
            rocks_per_point,
            seed,
            threads,
            ascii,
            partition,
            until_stable,
            tile,
            tiles,
            tile_size_m,
            halo_m,
            tile_index,
            resume,
        } => {
            if let Some(dir) = resume {
                return regional::resume(&dir, threads, ascii);
            }
            let Some(input) = input else {
                return Err(Failure::BadInput(anyhow!(
                    "run: give an INPUT or --resume DIR"
                )));
            };
            let engine = match engine {
                None => None,
                Some(e) => Some(
                    e.parse()
                        .map_err(|e: String| Failure::BadInput(anyhow!("--engine: {e}")))?,
                ),
            };
            let overrides = Overrides {
                seed,
                rocks_per_cell,
                rocks_per_point,
                engine,
                threads: threads.map(|n| n as usize),
                until_stable_pct: until_stable,
            };
            let spec = |index, count| rockfall_sim::tile::TileSpec {
                index,
                count,
                size_m: tile_size_m,
                halo_m: halo_m.unwrap_or(rockfall_sim::tile::DEFAULT_HALO_M),
            };
            let index = crate::region_index::RegionIndex::new(tile_index);
            if let Some(t) = tile {
                let spec = spec(t.index, t.count);
                return crate::tiles::run(&input, &overrides, &spec, &index, &out);
            }
            if let Some(n) = tiles {
                if let Some(tol) = until_stable {
                    println!("until stable within {tol} %, over {n} tiles");
                }
                #[cfg(feature = "mpi")]
                if crate::mpi_run::launched() {
                    let spec = spec(1, n);
                    return crate::mpi_tiles::run(&input, &overrides, &spec, &index, &out, ascii);
                }
                return crate::tiles::run_all(&input, &overrides, &spec(1, n), &index, &out, ascii);
            }
            #[cfg(feature = "mpi")]
            if crate::mpi_run::launched() {
                if partition.is_some() || until_stable.is_some() {
                    return Err(Failure::BadInput(anyhow!(
                        "under mpirun the ranks are the partitions: run without --partition; \
                         --until-stable runs over tiles (--tiles N)"
                    )));
                }
                return crate::mpi_run::run(&input, &overrides, &out, ascii);
            }
            // every override before the forest is built: a stand map is expanded from the seed
            let sim = load_simulation(&input, &overrides)?;
            for n in sim.scenario().ignored_parameters() {
                println!("ignored by the {} engine: {n}", sim.scenario().engine);
            }
            let batched = sim.scenario().simulation.until_stable_pct.is_some();
            if let Some(tol) = sim.scenario().simulation.until_stable_pct {
                print_caps(tol, &sim.scenario().simulation);
            }
            if partition.is_some() || batched {
                let mut record = RunRecord::new(sim.scenario(), &regional::recorded_input(&input));
                if let Some(p) = partition {
                    record = record.with_partition(p);
                }
                let b = regional::Batched {
                    sim,
                    input: &input,
                    record,
                    saved: None,
                };
                return regional::run_batched(b, &out, ascii);
            }
            let scenario = sim.scenario();
            let ascii = ascii || scenario.output.ascii_rasters;
            let results = simulate::simulate(&sim, &input, true, "simulating")?;
            let ctx = simulate::Context::new(scenario, sim.stems(), input.display().to_string());
            simulate::write(&results, &out, ascii, &ctx)?;
            simulate::print_summary(&format!("{}:", scenario.name), &results);
            Ok(())
        }
        Command::Merge {
            dirs,
            out,
            stream: true,
            threads,
            ..
        } => regional::merge_streamed(&dirs, &out, threads),
        Command::Merge {
            dirs,
            out,
            input,
            ascii,
            ..
        } => regional::merge(&dirs, &out, input.as_deref(), ascii),
        Command::Demo { out } => simulate::demo(&out),
        Command::ImpactLab {
            shape,
            samples,
            seed,
            out,
            dbh_m,
            mu,
            eps_n,
            eps_t,
            dt_s,
            threads,
            compare,
        } => {
            if compare.is_empty() {
                let flags = lab::LabFlags {
                    shape,
                    samples,
                    seed,
                    d0_m: dbh_m,
                    mu,
                    eps_n,
                    eps_t,
                    dt_s,
                    threads,
                };
                lab::impact_lab(&flags, &out)
            } else {
                lab::compare(&compare, &out)
            }
        }
        Command::ShapeStudy {
            input,
            shapes,
            rocks,
            seed,
            interval_s,
            threads,
            out,
        } => {
            let flags = lab::StudyFlags {
                input,
                shapes,
                rocks,
                seed,
                interval_s,
                threads,
            };
            lab::shape_study(&flags, &out)
        }
        Command::Validate {
            cases,
            rocks,
            quick,
            seed,
            threads,
            out,
        } => {
            let flags = validate::ValidateFlags {
                cases,
                rocks,
                quick,
                seed,
                threads,
            };
            validate::validate(&flags, &out)
        }
        Command::Hazard {
            file,
            matrix,
            rocks_per_cell,
            seed,
            threads,
            rerun,
            out,
        } => {
            let flags = crate::hazard::HazardFlags {
                file,
                matrix,
                rocks_per_cell,
                seed,
                threads,
                rerun,
            };
            crate::hazard::hazard(&flags, &out)
        }
        Command::Calibrate {
            scenario,
            targets,
            budget,
            seed,
            threads,
            out,
        } => {
            let flags = calibrate::CalibrateFlags {
                scenario,
                targets,
                budget: budget as usize,
                seed,
                threads,
            };
            calibrate::calibrate(&flags, &out)
        }
    }
}

/// The output folder a command writes into (`site` checks its own).
fn output_folder(command: &Command) -> Option<&Path> {
    match command {
        Command::Demo { out }
        | Command::Run { out, .. }
        | Command::Merge { out, .. }
        | Command::ImpactLab { out, .. }
        | Command::ShapeStudy { out, .. }
        | Command::Validate { out, .. }
        | Command::Calibrate { out, .. }
        | Command::Hazard { out, .. } => Some(out),
        // `site` refuses any existing folder that is not empty, files included
        // `schema --out` names a file
        Command::Site { .. } | Command::Check { .. } | Command::Schema { .. } => None,
    }
}

/// An output folder that exists as something other than a folder is bad input (exit 2),
/// found before anything runs.
fn check_output_folder(out: &Path) -> Result<(), Failure> {
    if out.exists() && !out.is_dir() {
        return Err(Failure::BadInput(anyhow!(
            "{}: exists and is not a folder; --out names the folder the outputs go into",
            out.display()
        )));
    }
    Ok(())
}

/// Reads `input`, applies `overrides` and builds its forest (every problem is bad input):
/// the seed is applied *before* the forest is built, since a stand forest is expanded into
/// stems from it, so `--seed N` and `seed = N` in the file give the same run.
pub fn load_simulation(input: &Path, overrides: &Overrides) -> Result<Simulation, Failure> {
    let scenario = rockfall_io::load(input)?;
    Simulation::new(scenario, overrides).map_err(|e| simulate::sim_failure(e, input))
}

/// States the caps of a convergence run, and where a scenario named no number of rocks, that
/// the generous default stands in for it.
fn print_caps(tol_pct: f64, s: &rockfall_scenario::SimulationSettings) {
    let cap = rockfall_scenario::UNTIL_STABLE_DEFAULT_CAP;
    let note = if s.rocks_per_cell == cap || s.rocks_per_point == cap {
        format!(
            "; {cap} is the cap of a convergence run whose scenario names no number of rocks \
             (`--rocks-per-cell`, `--rocks-per-point` or `[simulation]` set one)"
        )
    } else {
        String::new()
    };
    println!(
        "until stable within {tol_pct} %: at most {} rocks per source cell and {} per release \
         point{note}",
        s.rocks_per_cell, s.rocks_per_point
    );
}

fn check(input: &Path) -> Result<(), Failure> {
    let sim = load_simulation(input, &Overrides::default())?;
    let scenario = sim.scenario();
    let hull = match scenario.engine {
        Engine::Rigid => Some(
            rockfall_sim::RigidRock::of(scenario).map_err(|e| simulate::sim_failure(e, input))?,
        ),
        Engine::Lumped => None,
    };
    // the engine launches every release (a z_m in the ground is refused) before `ok`
    let prepared = sim.prepare().map_err(|e| simulate::sim_failure(e, input))?;
    println!("{}: ok", input.display());
    print!("{}", Overview::new(scenario, sim.forest()));
    if let Some(hull) = hull {
        println!("{hull}");
    }
    if let Some((held, of)) = prepared.held_releases()
        && let Some(w) = rockfall_sim::held_warning("releases", held as u64, of as u64)
    {
        println!("{w}");
    }
    Ok(())
}

/// The options of `rockfall site` that only `alpine-region` takes.
struct RegionOptions {
    cells: Option<u64>,
    cell_size_m: Option<f64>,
    seed: Option<u64>,
}

fn site(name: &str, out: &Path, region: RegionOptions) -> Result<(), Failure> {
    // Never mix a site with files of another: stale rasters or tree files would be read back.
    if out.exists() {
        let empty = std::fs::read_dir(out).is_ok_and(|mut d| d.next().is_none());
        if !empty {
            return Err(Failure::BadInput(anyhow!(
                "{}: exists and is not an empty folder; choose a new output folder",
                out.display()
            )));
        }
    }
    let files = if name == rockfall_sites::REGION_SITE.0 {
        write_region(out, &region)?
    } else {
        let given = [
            region.cells.map(|_| "--cells"),
            region.cell_size_m.map(|_| "--cell-size-m"),
            region.seed.map(|_| "--seed"),
        ];
        if let Some(key) = given.into_iter().flatten().next() {
            return Err(Failure::BadInput(anyhow!(
                "{key} is an option of `alpine-region` only; `{name}` is a fixed site"
            )));
        }
        let scenario = rockfall_sites::build(name).map_err(|e| match e {
            rockfall_sites::SiteError::Unknown(_) => Failure::BadInput(e.into()),
            other => Failure::Internal(other.into()),
        })?;
        rockfall_io::write::write_scenario_dir(&scenario, out)
            .map_err(|e| Failure::Internal(e.into()))?
    };
    println!(
        "wrote site `{name}` to {} ({} files):",
        out.display(),
        files.len()
    );
    for f in &files {
        println!("  {}", f.display());
    }
    println!(
        "check it with `rockfall check {}`",
        out.join("scenario.toml").display()
    );
    Ok(())
}

fn list_sites() {
    println!("built-in sites:");
    for (name, what) in rockfall_sites::SITES
        .into_iter()
        .chain([rockfall_sites::REGION_SITE])
    {
        println!("  {name:<16} {what}");
    }
}

/// Writes `alpine-region` into `out`.
fn write_region(out: &Path, o: &RegionOptions) -> Result<Vec<PathBuf>, Failure> {
    use rockfall_sites::region::{self, RegionError, RegionSpec};
    let spec = RegionSpec {
        cells: o.cells.unwrap_or(region::DEFAULT_CELLS),
        cell_size_m: o.cell_size_m.unwrap_or(region::DEFAULT_CELL_M),
        seed: o.seed.unwrap_or(1),
    };
    let bad = |e: RegionError| Failure::BadInput(e.into());
    region::check(&spec).map_err(bad)?;
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::BadInput(anyhow!("{}: {e}", out.display())))?;
    region::write(out, &spec).map_err(|e| match e {
        RegionError::Spec(_) => Failure::BadInput(e.into()),
        other => Failure::Internal(other.into()),
    })
}

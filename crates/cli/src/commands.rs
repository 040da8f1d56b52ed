//! One function per subcommand.

use crate::Failure;
use crate::args::Command;
use crate::lab;
use crate::simulate;
use crate::validate;
use anyhow::anyhow;
use rockfall_scenario::{Engine, Summary};
use std::path::Path;

/// Runs a subcommand.
pub fn dispatch(command: Command) -> Result<(), Failure> {
    if let Some(out) = output_folder(&command) {
        check_output_folder(out)?;
    }
    match command {
        Command::Check { input } => check(&input),
        Command::Site { name, out, list } => match (name, out) {
            (Some(name), Some(out)) if !list => site(&name, &out),
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
        } => {
            // the seed first: a stand forest is expanded from it
            let (mut scenario, forest) = load_checked(&input, seed)?;
            if let Some(e) = engine {
                scenario.engine = e
                    .parse()
                    .map_err(|e: String| Failure::BadInput(anyhow!("--engine: {e}")))?;
            }
            if let Some(n) = rocks_per_cell {
                scenario.simulation.rocks_per_cell = n;
            }
            if let Some(n) = rocks_per_point {
                scenario.simulation.rocks_per_point = n;
            }
            let ascii = ascii || scenario.output.ascii_rasters;
            let threads = simulate::threads(threads);
            let forest = (!forest.is_empty()).then_some(&forest);
            let results = simulate::simulate(&scenario, forest, threads, "simulating")?;
            let ctx = simulate::Context::new(&scenario, forest, input.display().to_string());
            simulate::write(&results, &out, ascii, &ctx)?;
            simulate::print_summary(&format!("{}:", scenario.name), &results);
            Ok(())
        }
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
    }
}

/// The output folder a command writes into (`site` checks its own).
fn output_folder(command: &Command) -> Option<&Path> {
    match command {
        Command::Demo { out }
        | Command::Run { out, .. }
        | Command::ImpactLab { out, .. }
        | Command::ShapeStudy { out, .. }
        | Command::Validate { out, .. } => Some(out),
        // `site` refuses any existing folder that is not empty, files included
        Command::Site { .. } | Command::Check { .. } => None,
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

/// Reads and validates `input` and builds its forest (every problem is bad input); `seed` (a `--seed` flag) replaces the
/// scenario's seed *before* the forest is built, since a stand forest is expanded into stems
/// from it: `--seed N` and `seed = N` in the file give the same run.
pub fn load_checked(
    input: &Path,
    seed: Option<u64>,
) -> Result<(rockfall_scenario::Scenario, rockfall_forest::Forest), Failure> {
    let mut scenario = rockfall_io::load(input)?;
    if let Some(s) = seed {
        scenario.seed = s;
    }
    let forest = scenario
        .build_forest()
        .map_err(|e| Failure::BadInput(anyhow!("{}: {e}", forest_source(&scenario, input))))?;
    Ok((scenario, forest))
}

fn forest_source(s: &rockfall_scenario::Scenario, input: &Path) -> String {
    s.source_of("forest.trees")
        .or_else(|| s.source_of("nrtrees"))
        .unwrap_or(input)
        .display()
        .to_string()
}

fn check(input: &Path) -> Result<(), Failure> {
    let (scenario, forest) = load_checked(input, None)?;
    let hull = match scenario.engine {
        Engine::Rigid => Some(rigid_rock(&scenario)?),
        Engine::Lumped => None,
    };
    println!("{}: ok", input.display());
    print!("{}", Summary::new(&scenario, &forest));
    if let Some(hull) = hull {
        println!("{hull}");
    }
    Ok(())
}

/// The rigid engine's rock, described in a line; an unusable shape is bad input.
fn rigid_rock(scenario: &rockfall_scenario::Scenario) -> Result<String, Failure> {
    let body = rockfall_rigid::shape::body_from_spec(&scenario.rock).map_err(|e| {
        let at = scenario
            .source_of("rock.shape")
            .map_or(String::new(), |p| format!("{}: ", p.display()));
        Failure::BadInput(anyhow!("{at}rock: {e}"))
    })?;
    let g = &body.geometry;
    let [l1, l2, l3] = g.lengths_m;
    Ok(format!(
        "rigid rock: convex hull of {} vertices, {} faces; volume {:.4} m³, mass {:.1} kg; \
         principal moments {:.4}, {:.4}, {:.4} kg m²; axis lengths {l1:.3}, {l2:.3}, {l3:.3} m; \
         Π = {:.2} ({})",
        g.vertices_m.len(),
        g.triangles.len(),
        g.volume_m3,
        body.mass_kg,
        body.inertia_kgm2.x,
        body.inertia_kgm2.y,
        body.inertia_kgm2.z,
        g.aspect_ratio(),
        g.class().name()
    ))
}

fn site(name: &str, out: &Path) -> Result<(), Failure> {
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
    let scenario = rockfall_sites::build(name).map_err(|e| match e {
        rockfall_sites::SiteError::Unknown(_) => Failure::BadInput(e.into()),
        other => Failure::Internal(other.into()),
    })?;
    let files = rockfall_io::write::write_scenario_dir(&scenario, out)
        .map_err(|e| Failure::Internal(e.into()))?;
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
    for (name, what) in rockfall_sites::SITES {
        println!("  {name:<16} {what}");
    }
}

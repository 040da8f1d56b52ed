//! `rockfall run` and `rockfall demo`: prepare a scenario, simulate it with a progress bar,
//! write the results.

use crate::Failure;
use anyhow::anyhow;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rockfall_forest::Forest;
use rockfall_lumped::{LumpedModel, RunOptions};
use rockfall_report::ReportInput;
use rockfall_results::{
    ForestEffect, ForestEffectSummary, Layout, LegacySolver, LumpedParameters, Parameters, Results,
    RigidParameters, RunInfo, RunSize,
};
use rockfall_rigid::RigidModel;
use rockfall_scenario::{Engine, Scenario};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

/// Worker threads: the request, or every core.
pub fn threads(requested: Option<u64>) -> usize {
    requested.map_or_else(
        || std::thread::available_parallelism().map_or(1, |n| n.get()),
        |n| n as usize,
    )
}

/// Simulates `scenario` with `forest` (none: without trees) on `threads` workers.
pub fn simulate(
    scenario: &Scenario,
    forest: Option<&Forest>,
    threads: usize,
    label: &str,
) -> Result<Results, Failure> {
    let bad_input = |e: &dyn std::fmt::Display, keys: &[&str]| {
        let source = keys.iter().find_map(|k| scenario.source_of(k));
        let at = source.map_or(String::new(), |p| format!("{}: ", p.display()));
        Failure::BadInput(anyhow!("{at}{e}"))
    };
    let layout = Arc::new(Layout::of(scenario));
    let started = Instant::now();
    let (tally, parameters) = match scenario.engine {
        Engine::Lumped => {
            let model = LumpedModel::new(scenario, forest)
                .map_err(|e| bad_input(&e, &["rockdensity", "dem"]))?;
            let tally = with_progress(model.rocks(), threads, label, |opts| {
                model.run(layout.clone(), opts)
            })
            .map_err(|e| Failure::Internal(e.into()))?;
            (
                tally,
                Parameters::Lumped(lumped_parameters(scenario, &model)),
            )
        }
        Engine::Rigid => {
            let model = RigidModel::new(scenario, forest)
                .map_err(|e| bad_input(&e, &["rock.shape", "dem"]))?;
            let tally = with_progress(model.rocks(), threads, label, |opts| {
                model.run(layout.clone(), opts)
            })
            .map_err(|e| Failure::Internal(e.into()))?;
            (tally, Parameters::Rigid(rigid_parameters(scenario, &model)))
        }
    };
    let info = RunInfo {
        engine: scenario.engine.to_string(),
        scenario: scenario.name.clone(),
        seed: scenario.seed,
        threads,
        wall_time_s: started.elapsed().as_secs_f64(),
        parameters,
    };
    Ok(Results::new(&layout, tally, info))
}

/// Runs `run` with a progress bar over `rocks` rocks (shown on a terminal only).
fn with_progress<T>(
    rocks: u64,
    threads: usize,
    label: &str,
    run: impl FnOnce(&RunOptions<'_>) -> T,
) -> T {
    let bar = progress_bar(rocks, label, "rocks");
    let started = Instant::now();
    let done = AtomicU64::new(0);
    let warned = AtomicBool::new(false);
    let tick = |n: u64| {
        bar.inc(n);
        let so_far = done.fetch_add(n, Ordering::Relaxed) + n;
        if !warned.load(Ordering::Relaxed)
            && let Some(w) = long_run_warning(rocks, so_far, started.elapsed().as_secs_f64())
            && !warned.swap(true, Ordering::Relaxed)
        {
            // above the progress bar, or plainly on stderr without one
            bar.suspend(|| eprintln!("{label}: {w}"));
        }
    };
    let opts = RunOptions {
        threads,
        progress: Some(&tick),
    };
    let out = run(&opts);
    bar.finish_and_clear();
    out
}

/// Seconds of running after which the rate is trusted for an estimate.
const ESTIMATE_AFTER_S: f64 = 3.0;
/// A run estimated to take longer than this gets a warning, s.
const LONG_RUN_S: f64 = 3600.0;

/// The warning for a run of `rocks` rocks of which `done` took `elapsed_s`, once the rate has
/// been measured for [`ESTIMATE_AFTER_S`] and the whole run would take more than an hour:
/// the estimate, the rocks and the measured rate, so that the user can stop it.
pub fn long_run_warning(rocks: u64, done: u64, elapsed_s: f64) -> Option<String> {
    if elapsed_s < ESTIMATE_AFTER_S || done == 0 {
        return None;
    }
    let rate = done as f64 / elapsed_s;
    let total_s = rocks as f64 / rate;
    (total_s > LONG_RUN_S).then(|| {
        format!(
            "this run will take about {:.1} h: {rocks} rocks at the {rate:.0} rocks/s measured so \
             far; Ctrl-C stops it (fewer rocks: --rocks-per-cell, --rocks-per-point)",
            total_s / 3600.0
        )
    })
}

/// Engine parameters of a lumped run recorded in `summary.json`.
fn lumped_parameters(scenario: &Scenario, model: &LumpedModel<'_>) -> LumpedParameters {
    let first = model.sources().first();
    LumpedParameters {
        settings: scenario.lumped.clone(),
        size: RunSize::of(scenario, model.stems()),
        rock_mass_kg: first.map(|s| s.body.mass_kg),
        rock_radius_m: first.map(|s| s.body.radius_m),
        tree_energy_units: "seed 000 eq. 2 read as joules (DBH in cm)".into(),
    }
}

/// Engine parameters of a rigid run recorded in `summary.json`.
fn rigid_parameters(scenario: &Scenario, model: &RigidModel<'_>) -> RigidParameters {
    let b = model.body();
    let g = &b.geometry;
    RigidParameters {
        rock_shape: scenario.rock.shape.describe(),
        rock_vertices: g.vertices_m.len() as u64,
        rock_volume_m3: g.volume_m3,
        rock_mass_kg: b.mass_kg,
        rock_inertia_kgm2: [b.inertia_kgm2.x, b.inertia_kgm2.y, b.inertia_kgm2.z],
        rock_lengths_m: g.lengths_m,
        rock_aspect_ratio: g.aspect_ratio(),
        rock_class: g.class().name().into(),
        contact_ground: scenario.contact.ground,
        contact_tree: scenario.contact.tree,
        slippage: scenario.contact.slippage,
        dt_s: scenario.simulation.dt_s,
        size: RunSize::of(scenario, model.stems()),
        settings: scenario.rigid,
        solver: LegacySolver::from(&scenario.rigid),
    }
}

/// A progress bar over `total` `unit` (on a terminal only), prefixed with `label`.
pub fn progress_bar(total: u64, label: &str, unit: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
    let style = ProgressStyle::with_template(&format!(
        "{{prefix}} [{{bar:30}}] {{human_pos}}/{{human_len}} {unit}, {{per_sec}}, {{eta}} left"
    ))
    .map(|s| s.progress_chars("=> "))
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar.set_prefix(label.to_string());
    bar
}

/// What a run's report says beside its results.
pub struct Context<'a> {
    /// The scenario simulated.
    pub scenario: &'a Scenario,
    /// The forest simulated, if any.
    pub forest: Option<&'a Forest>,
    /// What was read: a file, a folder, a built-in site.
    pub input: String,
    /// Words added to the report's title ("with forest"); may be empty.
    pub label: String,
    /// Links to related reports: (label, path relative to the output folder).
    pub links: Vec<(String, String)>,
    /// The forest's effect, mapped in the report (the demo).
    pub forest_effect: Option<&'a ForestEffect>,
    /// Files already written into the output folder, listed in the report.
    pub files: Vec<PathBuf>,
}

impl<'a> Context<'a> {
    /// The context of a run of `scenario` with `forest`, read from `input`.
    pub fn new(scenario: &'a Scenario, forest: Option<&'a Forest>, input: String) -> Self {
        Context {
            scenario,
            forest,
            input,
            label: String::new(),
            links: Vec::new(),
            forest_effect: None,
            files: Vec::new(),
        }
    }
}

/// The command line, for reports.
pub fn command_line() -> String {
    std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Writes `results` into `out` with the report and GIS files, and prints where.
pub fn write(results: &Results, out: &Path, ascii: bool, ctx: &Context<'_>) -> Result<(), Failure> {
    let mut files = results
        .write(out, ascii)
        .map_err(|e| Failure::Internal(e.into()))?;
    let mut listed = ctx.files.clone();
    listed.extend(files.iter().cloned());
    let input = ReportInput {
        scenario: ctx.scenario,
        results,
        stems: ctx.forest.map_or(&[], |f| f.stems()),
        input: ctx.input.clone(),
        command: command_line(),
        files: listed,
        forest_effect: ctx.forest_effect,
        links: ctx.links.clone(),
        label: ctx.label.clone(),
    };
    let report = rockfall_report::write(out, &input).map_err(|e| Failure::Internal(e.into()))?;
    files.extend(report);
    println!(
        "wrote {} files to {} (open {})",
        files.len() + ctx.files.len(),
        out.display(),
        out.join("report.html").display()
    );
    Ok(())
}

/// `x` with two decimals, `–` when undefined.
fn two_decimals(x: Option<f64>) -> String {
    x.map_or("–".to_string(), |x| format!("{x:.2}"))
}

/// A fraction as a percentage with one decimal, `–` when undefined.
fn percent(x: Option<f64>) -> String {
    x.map_or("–".to_string(), |x| format!("{:.1} %", x * 100.0))
}

/// Prints the headline numbers of a run.
pub fn print_summary(title: &str, results: &Results) {
    let s = results.summary();
    let f = two_decimals;
    println!("{title}");
    println!(
        "  {} rocks in {:.2} s ({:.0} trajectories/s on {} threads)",
        s.rocks,
        s.wall_time_s.unwrap_or(0.0),
        s.trajectories_per_s.unwrap_or(0.0),
        s.threads
    );
    println!(
        "  stopped {}, left the DEM {}",
        percent(s.stopped_fraction),
        percent(s.left_dem_fraction)
    );
    let r = &s.runout_m;
    println!(
        "  run-out p50 {} m, p95 {} m, max {} m",
        f(r.p50),
        f(r.p95),
        f(r.max)
    );
    let (v, h) = (&s.max_velocity_ms, &s.max_jump_height_m);
    println!(
        "  max velocity mean {} m/s, max {} m/s; jump height mean {} m, max {} m",
        f(v.mean),
        f(v.max),
        f(h.mean),
        f(h.max)
    );
    println!("  tree impacts per rock {}", f(s.tree_impacts_per_rock));
    for sc in &s.screens {
        println!(
            "  screen {}: passed {}, v mean {} m/s, E p95 {} kJ, jump p95 {} m",
            sc.name,
            percent(sc.passed_fraction),
            f(sc.velocity_ms.mean),
            f(sc.energy_kj.p95),
            f(sc.jump_height_m.p95)
        );
    }
}

/// `rockfall demo`: vaujany-site2 with and without its forest.
pub fn demo(out: &Path) -> Result<(), Failure> {
    let scenario =
        rockfall_sites::build("vaujany-site2").map_err(|e| Failure::Internal(e.into()))?;
    let forest = scenario
        .build_forest()
        .map_err(|e| Failure::Internal(e.into()))?;
    let threads = threads(None);
    println!(
        "demo: {} — {} rocks from one source cell, {} stems",
        scenario.name,
        scenario.simulation.rocks_per_cell,
        forest.len()
    );
    let ascii = scenario.output.ascii_rasters;
    let with = simulate(&scenario, Some(&forest), threads, "with forest")?;
    let without = simulate(&scenario, None, threads, "without forest")?;
    let effect = ForestEffect::new(&with, &without);
    let effect_files = effect
        .write(out, ascii)
        .map_err(|e| Failure::Internal(e.into()))?;
    let input = format!("built-in site {} (rockfall demo)", scenario.name);
    let ctx = Context {
        label: "with forest".into(),
        links: vec![("Without forest".into(), "without_forest/report.html".into())],
        forest_effect: Some(&effect),
        files: effect_files,
        ..Context::new(&scenario, Some(&forest), input.clone())
    };
    write(&with, out, ascii, &ctx)?;
    let bare = out.join("without_forest");
    let ctx = Context {
        label: "without forest".into(),
        links: vec![("With forest".into(), "../report.html".into())],
        ..Context::new(&scenario, None, input)
    };
    write(&without, &bare, ascii, &ctx)?;
    print_summary("with forest:", &with);
    print_summary("without forest:", &without);
    print_effect(effect.summary());
    println!(
        "outputs: {} (with forest), {} (without), forest effect in {}",
        out.display(),
        bare.display(),
        out.join("forest_effect.json").display()
    );
    println!("report: {}", out.join("report.html").display());
    Ok(())
}

/// Prints the headline numbers of the forest's effect.
fn print_effect(e: &ForestEffectSummary) {
    println!("forest effect (with − without):");
    for (d, label) in [
        (&e.stopped_fraction, "stopped"),
        (&e.left_dem_fraction, "left the DEM"),
    ] {
        if let Some(d) = d.difference {
            println!("  {label}: {:+.1} percentage points", d * 100.0);
        }
    }
    if let Some(d) = e.runout_p95_m.difference {
        println!("  run-out p95: {d:+.1} m");
    }
    if let Some(d) = e.reach_probability_pp.cells.mean_difference {
        println!("  reach probability, mean over reached cells: {d:+.2} percentage points");
    }
    if let Some(d) = e.e_95_kj.mean_difference {
        println!("  E_95, mean over reached cells: {d:+.1} kJ");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_of_more_than_an_hour_is_announced_once_its_rate_is_known() {
        // 10¹⁴ rocks at 40 000 rocks/s: about 7·10⁵ h
        let w = long_run_warning(100_000_000_000_000, 120_000, 3.0).unwrap();
        assert!(w.contains("694444") && w.contains("40000 rocks/s"), "{w}");
        assert!(
            w.contains("100000000000000 rocks") && w.contains("Ctrl-C"),
            "{w}"
        );
        // not before the rate has been measured for 3 s, nor for a run of under an hour
        assert_eq!(long_run_warning(100_000_000_000_000, 1_000, 0.5), None);
        assert_eq!(long_run_warning(100_000_000, 120_000, 3.0), None);
        assert!(long_run_warning(200_000_000, 120_000, 3.0).is_some());
        assert_eq!(long_run_warning(10, 0, 10.0), None);
    }
}

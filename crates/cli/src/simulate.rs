//! `rockfall run` and `rockfall demo`: prepare a scenario, simulate it with a progress bar,
//! write the results.

use crate::Failure;
use anyhow::anyhow;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rockfall_forest::Forest;
use rockfall_report::ReportInput;
use rockfall_results::{ForestEffect, ForestEffectSummary, MIN_REACH_PCT, Results};
use rockfall_scenario::Scenario;
use rockfall_sim::{Observer, Overrides, SimError, Simulation};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

/// Worker threads: the request, or every core.
pub fn threads(requested: Option<u64>) -> usize {
    Overrides {
        threads: requested.map(|n| n as usize),
        ..Overrides::default()
    }
    .threads()
}

/// An error of the driver as the command line reports it: bad input names its file, or
/// `input` when the error names none.
pub fn sim_failure(e: SimError, input: &Path) -> Failure {
    match e.file() {
        None if e.is_bad_input() => Failure::BadInput(anyhow!("{}: {e}", input.display())),
        _ => Failure::of(e.is_bad_input(), e),
    }
}

/// Runs every rock of `sim`, read from `input`, with its forest or without, with a progress
/// bar labelled `label`; bad input that names no file of its own is `input`'s (a release
/// point's `z_m`).
pub fn simulate(
    sim: &Simulation,
    input: &Path,
    with_forest: bool,
    label: &str,
) -> Result<Results, Failure> {
    sim.run(with_forest, label, &Console::default())
        .map_err(|e| sim_failure(e, input))
}

/// What the terminal shows of runs: a progress bar per run (on a terminal only), a warning
/// when a run would take more than an hour, and, with `summaries`, each run's headline
/// numbers when it ends.
#[derive(Default)]
pub struct Console {
    /// Print each finished run's headline numbers.
    pub summaries: bool,
    run: Mutex<Option<ConsoleRun>>,
}

/// The run under way.
struct ConsoleRun {
    bar: ProgressBar,
    label: String,
    rocks: u64,
    started: Instant,
    done: AtomicU64,
    warned: AtomicBool,
}

impl Console {
    /// A console that also prints each finished run's headline numbers.
    pub fn with_summaries() -> Console {
        Console {
            summaries: true,
            ..Console::default()
        }
    }
}

impl Observer for Console {
    fn started(&self, label: &str, rocks: u64) {
        let run = ConsoleRun {
            bar: progress_bar(rocks, label, "rocks"),
            label: label.to_string(),
            rocks,
            started: Instant::now(),
            done: AtomicU64::new(0),
            warned: AtomicBool::new(false),
        };
        *self.run.lock().unwrap_or_else(|e| e.into_inner()) = Some(run);
    }

    fn advanced(&self, n: u64) {
        let guard = self.run.lock().unwrap_or_else(|e| e.into_inner());
        let Some(run) = guard.as_ref() else {
            return;
        };
        run.bar.inc(n);
        let so_far = run.done.fetch_add(n, Ordering::Relaxed) + n;
        if !run.warned.load(Ordering::Relaxed)
            && let Some(w) =
                long_run_warning(run.rocks, so_far, run.started.elapsed().as_secs_f64())
            && !run.warned.swap(true, Ordering::Relaxed)
        {
            // above the progress bar, or plainly on stderr without one
            run.bar.suspend(|| eprintln!("{}: {w}", run.label));
        }
    }

    fn ended(&self, _label: &str) {
        if let Some(run) = self.run.lock().unwrap_or_else(|e| e.into_inner()).take() {
            run.bar.finish_and_clear();
        }
    }

    fn finished(&self, label: &str, results: &Results) {
        if let Some(run) = self.run.lock().unwrap_or_else(|e| e.into_inner()).take() {
            run.bar.finish_and_clear();
        }
        if self.summaries {
            print_summary(&format!("{label}:"), results);
        }
    }

    fn wrote(&self, out: &Path, files: &[PathBuf]) {
        print_written(out, files);
    }
}

/// Says how many files went into `out` and which page to open.
fn print_written(out: &Path, files: &[PathBuf]) {
    println!(
        "wrote {} files to {} (open {})",
        files.len(),
        out.display(),
        out.join("report.html").display()
    );
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
    let input = ReportInput {
        scenario: ctx.scenario,
        results,
        stems: ctx.forest.map_or(&[], |f| f.stems()),
        input: ctx.input.clone(),
        command: command_line(),
        files: ctx.files.clone(),
        forest_effect: ctx.forest_effect,
        links: ctx.links.clone(),
        label: ctx.label.clone(),
    };
    let files =
        rockfall_report::write_run(out, ascii, &input).map_err(|e| Failure::Internal(e.into()))?;
    let mut listed = ctx.files.clone();
    listed.extend(files);
    print_written(out, &listed);
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
    let wall_s = s.wall_time_s.unwrap_or(0.0);
    let events_per_s = if wall_s > 0.0 {
        s.events as f64 / wall_s
    } else {
        0.0
    };
    println!(
        "  {} rocks in {wall_s:.2} s ({:.0} trajectories/s, {:.3} M events/s on {} threads; {} \
         events per rock)",
        s.rocks,
        s.trajectories_per_s.unwrap_or(0.0),
        events_per_s / 1e6,
        s.threads,
        s.events_per_rock.map_or("–".into(), |e| format!("{e:.0}"))
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
    if let Some(w) = rockfall_sim::held_warning("rocks", s.held_at_release, s.rocks) {
        println!("{w}");
    }
}

/// `rockfall demo`: vaujany-site2 with and without its forest.
pub fn demo(out: &Path) -> Result<(), Failure> {
    let site = rockfall_sites::build("vaujany-site2").map_err(|e| Failure::Internal(e.into()))?;
    let sim =
        Simulation::new(site, &Overrides::default()).map_err(|e| Failure::Internal(e.into()))?;
    let (scenario, forest) = (sim.scenario(), sim.forest());
    println!(
        "demo: {} — {} rocks from one source cell, {} stems",
        scenario.name,
        scenario.simulation.rocks_per_cell,
        forest.len()
    );
    let ascii = scenario.output.ascii_rasters;
    let site_name = PathBuf::from(format!("built-in site {}", scenario.name));
    let with = simulate(&sim, &site_name, true, "with forest")?;
    let without = simulate(&sim, &site_name, false, "without forest")?;
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
        ..Context::new(scenario, Some(forest), input.clone())
    };
    write(&with, out, ascii, &ctx)?;
    let bare = out.join("without_forest");
    let ctx = Context {
        label: "without forest".into(),
        links: vec![("With forest".into(), "../report.html".into())],
        ..Context::new(scenario, None, input)
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
    let bare = &e.on_cells_reached_without_forest;
    println!(
        "  on the {} cells reached without the forest (a cell the forest kept every rock from counts 0):",
        bare.e_95_kj.cells
    );
    if let Some(d) = bare.reach_probability_pp.mean_difference {
        println!("    reach probability, mean: {d:+.2} percentage points");
    }
    if let Some(d) = bare.e_95_kj.mean_difference {
        println!("    E_95, mean: {d:+.1} kJ");
    }
    for a in &e.area_e_95_above {
        if let Some((w, o)) = a.hectares() {
            let e_kj = a.energy_kj;
            println!(
                "  area reached by ≥ {MIN_REACH_PCT} % of rocks with E_95 > {e_kj} kJ: \
                 {w:.2} ha with, {o:.2} ha without"
            );
        }
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

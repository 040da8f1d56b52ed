//! Regional runs on the command line: `run --partition`, `run --until-stable`, `run
//! --resume` and `merge`. The batching, the merge and their checks are the driver's
//! (`rockfall_sim`); this module reads and writes the tally files and the run folders.

use crate::Failure;
use crate::commands::load_simulation;
use crate::simulate::{self, Console, Context};
use anyhow::anyhow;
use rockfall_results::{Results, RunInfo, SavedTally, TALLY_FILE, Tally, read_tally, write_tally};
use rockfall_sim::{Finished, Overrides, RunRecord, Simulation, share};
use std::path::{Path, PathBuf};

/// The file a batched run saves itself into after every batch, until it ends.
pub const CHECKPOINT_FILE: &str = "checkpoint.tally";

/// How a batched run is started: from scratch (its input and share) or from a checkpoint.
pub struct Batched<'a> {
    /// The simulation.
    pub sim: Simulation,
    /// What the input was called on the command line (for the report).
    pub input: &'a Path,
    /// Its record: which rocks, which batches.
    pub record: RunRecord,
    /// The tally and run saved so far, when continuing.
    pub saved: Option<(Tally, RunInfo)>,
}

/// The absolute path of `input` as a run records it.
pub fn recorded_input(input: &Path) -> String {
    std::path::absolute(input)
        .unwrap_or_else(|_| input.to_path_buf())
        .display()
        .to_string()
}

/// Runs a partition or a convergence run into `out`: saves `checkpoint.tally` after every
/// batch, then the exact tallies (`rockfall.tally`), then the run folder.
pub fn run_batched(b: Batched<'_>, out: &Path, ascii: bool) -> Result<(), Failure> {
    let internal = |e: std::io::Error, p: &Path| Failure::Internal(anyhow!("{}: {e}", p.display()));
    std::fs::create_dir_all(out).map_err(|e| internal(e, out))?;
    // An earlier run's complete tallies must not stand beside this run's checkpoint: a merge
    // would take them for this run's.
    let finished = out.join(TALLY_FILE);
    if b.saved.is_none() {
        remove_if_present(&finished).map_err(|e| internal(e, &finished))?;
    }
    let checkpoint = out.join(CHECKPOINT_FILE);
    let mut save = |t: &Tally, i: &RunInfo, r: &RunRecord| {
        write_tally(&checkpoint, t, i, r).map_err(|e| e.to_string())
    };
    let label = match &b.record.partition {
        Some(p) => format!("partition {p}"),
        None => "simulating".to_string(),
    };
    let console = Console::default();
    let f = b
        .sim
        .run_batches(b.record, b.saved, &label, &console, &mut save)
        .map_err(|e| simulate::sim_failure(e, b.input))?;
    write_run_folder(&b.sim, b.input, out, ascii, f)?;
    remove_if_present(&checkpoint).map_err(|e| internal(e, &checkpoint))
}

/// Writes a finished run into `out`: its exact tallies (`rockfall.tally`) first, then the
/// rasters, tables and report; prints its headline numbers.
pub fn write_run_folder(
    sim: &Simulation,
    input: &Path,
    out: &Path,
    ascii: bool,
    f: Finished,
) -> Result<(), Failure> {
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::Internal(anyhow!("{}: {e}", out.display())))?;
    let finished = out.join(TALLY_FILE);
    write_tally(&finished, &f.tally, &f.info, &f.record)
        .map_err(|e| Failure::Internal(e.into()))?;
    let Finished {
        tally,
        info,
        record,
        convergence,
    } = f;
    let layout = tally.layout().clone();
    let mut results = Results::new(&layout, tally, info);
    if let Some(c) = convergence {
        print_convergence(&c);
        results = results.with_convergence(c);
    }
    let scenario = sim.scenario();
    let ctx = Context {
        files: vec![finished],
        ..Context::new(scenario, sim.stems(), input.display().to_string())
    };
    let ascii = ascii || scenario.output.ascii_rasters;
    simulate::write(&results, out, ascii, &ctx)?;
    let title = match &record.partition {
        Some(p) => format!("{} (partition {p}):", scenario.name),
        None => format!("{}:", scenario.name),
    };
    simulate::print_summary(&title, &results);
    Ok(())
}

fn remove_if_present(path: &Path) -> std::io::Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(e),
        _ => Ok(()),
    }
}

fn print_convergence(c: &rockfall_results::ConvergenceSummary) {
    let change = match (c.max_change_pct, &c.metric) {
        (Some(m), Some(metric)) => format!("last change {m:.3} % ({metric})"),
        _ => "a single batch".to_string(),
    };
    let verdict = if c.cap_hit {
        "the cap on rocks was reached before the maps were stable"
    } else {
        "stable"
    };
    println!(
        "convergence: {verdict} at {} rocks ({} per source cell) after {} batches, {change}, \
         tolerance {} %",
        c.rocks, c.rocks_per_cell, c.batches, c.tolerance_pct
    );
}

/// The overrides that rebuild the scenario a record was run with.
fn overrides_of(r: &RunRecord, threads: Option<u64>) -> Result<Overrides, Failure> {
    let engine = r
        .engine
        .parse()
        .map_err(|e: String| Failure::BadInput(anyhow!(e)))?;
    Ok(Overrides {
        seed: Some(r.seed),
        rocks_per_cell: Some(r.rocks_per_cell),
        rocks_per_point: Some(r.rocks_per_point),
        engine: Some(engine),
        threads: threads.map(|n| n as usize),
        until_stable_pct: r.batch.until_stable_pct,
    })
}

/// Loads the input `record` names (or `input`, where it is now) with the record's settings,
/// and checks that it is still the input the run was made of.
fn reload(
    record: &RunRecord,
    input: Option<&Path>,
    threads: Option<u64>,
) -> Result<Simulation, Failure> {
    let path = input.map_or_else(|| PathBuf::from(&record.input), Path::to_path_buf);
    let sim = load_simulation(&path, &overrides_of(record, threads)?)?;
    let now = match record.fingerprint.starts_with("tiles-") {
        true => {
            let digest = rockfall_sim::share::input_digest(sim.scenario())
                .map_err(|e| Failure::BadInput(anyhow!("{}: {e}", path.display())))?;
            rockfall_sim::share::tile_fingerprint(sim.scenario(), digest)
        }
        false => rockfall_sim::share::fingerprint(sim.scenario()),
    };
    if now != record.fingerprint {
        return Err(Failure::BadInput(anyhow!(
            "{}: the input changed since the run started (scenario fingerprint {now}, the run \
             recorded {})",
            path.display(),
            record.fingerprint
        )));
    }
    Ok(sim)
}

/// `rockfall run --resume DIR`.
pub fn resume(dir: &Path, threads: Option<u64>, ascii: bool) -> Result<(), Failure> {
    let checkpoint = dir.join(CHECKPOINT_FILE);
    if !checkpoint.exists() {
        let why = if dir.join(TALLY_FILE).exists() {
            "the run in it is complete (rockfall.tally); nothing to continue"
        } else {
            "no checkpoint.tally: not the folder of a run with --partition or --until-stable"
        };
        return Err(Failure::BadInput(anyhow!("{}: {why}", dir.display())));
    }
    let saved: SavedTally<RunRecord> =
        read_tally(&checkpoint).map_err(|e| Failure::BadInput(e.into()))?;
    let sim = reload(&saved.run, None, threads)?;
    println!(
        "resuming {}: {} of its rocks done in {} batches",
        dir.display(),
        saved.tally.rocks(),
        saved.run.batch.batches
    );
    let input = PathBuf::from(&saved.run.input);
    let b = Batched {
        sim,
        input: &input,
        record: saved.run,
        saved: Some((saved.tally, saved.info)),
    };
    run_batched(b, dir, ascii)
}

/// The tally files of the run folders `dirs`, refusing `out` among them and folders without
/// a finished tally.
fn tally_files(dirs: &[PathBuf], out: &Path) -> Result<Vec<PathBuf>, Failure> {
    let same = |d: &Path| match (d.canonicalize(), out.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if let Some(d) = dirs.iter().find(|d| same(d)) {
        return Err(Failure::BadInput(anyhow!(
            "{}: --out is one of the folders merged; write the merge into a folder of its own",
            d.display()
        )));
    }
    let mut files = Vec::with_capacity(dirs.len());
    for d in dirs {
        let path = d.join(TALLY_FILE);
        if !path.exists() {
            let why = if d.join(CHECKPOINT_FILE).exists() {
                "its run did not finish (only checkpoint.tally); continue it with `rockfall run \
                 --resume` on it"
            } else {
                "no rockfall.tally: not the output folder of `rockfall run --partition` or \
                 `--tile`"
            };
            return Err(Failure::BadInput(anyhow!("{}: {why}", d.display())));
        }
        files.push(path);
    }
    Ok(files)
}

/// Warns when the tally files outweigh half the memory available (Linux's
/// `/proc/meminfo`): a merge in memory holds about as much as the files, twice while the
/// last is added.
fn warn_if_large(files: &[PathBuf]) {
    let bytes: u64 = (files.iter())
        .filter_map(|f| std::fs::metadata(f).ok())
        .map(|m| m.len())
        .sum();
    let available_kb = std::fs::read_to_string("/proc/meminfo").ok().and_then(|t| {
        let line = t.lines().find(|l| l.starts_with("MemAvailable:"))?;
        line.split_whitespace().nth(1)?.parse::<u64>().ok()
    });
    if let Some(kb) = available_kb.filter(|&kb| bytes / 1024 > kb / 2) {
        eprintln!(
            "warning: the tallies hold {:.1} GB and {:.1} GB of memory is available: a merge in \
             memory may not fit; `rockfall merge --stream` merges them in bounded memory",
            bytes as f64 / 1e9,
            kb as f64 * 1024.0 / 1e9
        );
    }
}

/// `rockfall merge DIR… --out OUT --stream`.
pub fn merge_streamed(dirs: &[PathBuf], out: &Path, threads: Option<u64>) -> Result<(), Failure> {
    use rockfall_sim::streamed::{self, StreamedMergeError};
    let files = tally_files(dirs, out)?;
    let threads = match threads {
        Some(n) => usize::try_from(n).unwrap_or(usize::MAX),
        None => std::thread::available_parallelism().map_or(1, usize::from),
    };
    // a tally unreadable or changed in a later reading is bad input too
    let failure = |e: StreamedMergeError| match e {
        StreamedMergeError::Write(rockfall_results::ResultsError::Tally(e)) => {
            Failure::BadInput(e.into())
        }
        StreamedMergeError::Write(e) => Failure::Internal(e.into()),
        e => Failure::BadInput(e.into()),
    };
    let start = std::time::Instant::now();
    let survey = streamed::survey(&files, threads).map_err(failure)?;
    println!(
        "read {} tallies of {} rocks in {:.1} s: {} cells in all",
        files.len(),
        survey.merged.record.rocks_total,
        start.elapsed().as_secs_f64(),
        survey.bounds.touched
    );
    let start = std::time::Instant::now();
    let written = streamed::write(survey, out, threads).map_err(failure)?;
    println!(
        "merged {} shares of {} rocks in {:.1} s, streaming their cells ({} readings, at most \
         {} tallies open at once)",
        dirs.len(),
        written.record.rocks_total,
        start.elapsed().as_secs_f64(),
        written.readings,
        written.most_open
    );
    println!(
        "wrote {} files to {} (rasters, summary.json, tables; no report)",
        written.files.len(),
        out.display()
    );
    simulate::print_summary(
        &format!("{} (merged):", written.record.scenario),
        &written.results,
    );
    Ok(())
}

/// `rockfall merge DIR… --out OUT`.
pub fn merge(
    dirs: &[PathBuf],
    out: &Path,
    input: Option<&Path>,
    ascii: bool,
) -> Result<(), Failure> {
    let files = tally_files(dirs, out)?;
    warn_if_large(&files);
    let mut parts = Vec::new();
    for path in files {
        let saved = read_tally::<RunRecord>(&path).map_err(|e| Failure::BadInput(e.into()))?;
        parts.push((path, saved));
    }
    let merged = share::merge(parts).map_err(|e| Failure::BadInput(e.into()))?;
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::Internal(anyhow!("{}: {e}", out.display())))?;
    let tally_path = out.join(TALLY_FILE);
    write_tally(&tally_path, &merged.tally, &merged.info, &merged.record)
        .map_err(|e| Failure::Internal(e.into()))?;
    let layout = merged.tally.layout().clone();
    let results = Results::new(&layout, merged.tally, merged.info);
    println!(
        "merged {} shares of {} rocks",
        dirs.len(),
        merged.record.rocks_total
    );
    match reload(&merged.record, input, None) {
        Ok(sim) => {
            let ctx = Context {
                files: vec![tally_path],
                ..Context::new(sim.scenario(), sim.stems(), merged.record.input.clone())
            };
            let ascii = ascii || sim.scenario().output.ascii_rasters;
            simulate::write(&results, out, ascii, &ctx)?;
        }
        Err(e) => {
            let files = results
                .write(out, ascii)
                .map_err(|e| Failure::Internal(e.into()))?;
            println!(
                "wrote {} files to {} without the report: its input could not be read ({}); \
                 give it with --input",
                files.len() + 1,
                out.display(),
                e.text()
            );
        }
    }
    simulate::print_summary(&format!("{} (merged):", merged.record.scenario), &results);
    Ok(())
}

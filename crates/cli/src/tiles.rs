//! `rockfall run --tile i/N`: one spatial tile of a region, into its exact tallies
//! (`rockfall.tally`) and `tile.json`, for `rockfall merge`. The tiling, halos and reruns
//! are the driver's (`rockfall_sim::tile`).

use crate::Failure;
use crate::simulate::{self, Console};
use anyhow::anyhow;
use rockfall_results::{SavedTally, TALLY_FILE, write_tally};
use rockfall_sim::reduce::{Part, combine};
use rockfall_sim::tile::{TilePass, TileRun, TileSpec, run_tile};
use rockfall_sim::{Finished, Observer, Overrides, RunRecord, SimError, share};

use serde::Serialize;
use std::path::Path;

/// What `tile.json` says about a tile's run.
#[derive(Serialize)]
struct TileReport<'a> {
    /// `i/N`.
    tile: String,
    /// Side of the square tiles, m, when given.
    tile_size_m: Option<f64>,
    /// The tile's own cells: [col0, row0, ncols, nrows] on the region's grid.
    core: [usize; 4],
    /// Rocks of the tile (those of its source cells and release points).
    rocks: u64,
    /// Rocks of the whole region's run.
    region_rocks: u64,
    /// Cells the tile's rocks reached.
    cells_reached: usize,
    /// Bytes of their per-cell statistics.
    cell_statistics_bytes: usize,
    /// Each pass: halo, window read, rocks simulated, rocks that left the trusted cells.
    passes: &'a [TilePass],
    /// Wall time of the passes, s.
    wall_time_s: f64,
}

/// Runs tile `spec` of the region `input` describes into `out`.
pub fn run(
    input: &Path,
    overrides: &Overrides,
    spec: &TileSpec,
    out: &Path,
) -> Result<(), Failure> {
    let (run, record) = simulate_tile(input, overrides, spec, &Console::default())?;
    let internal =
        |e: &dyn std::fmt::Display, p: &Path| Failure::Internal(anyhow!("{}: {e}", p.display()));
    std::fs::create_dir_all(out).map_err(|e| internal(&e, out))?;
    let tally_path = out.join(TALLY_FILE);
    write_tally(&tally_path, &run.tally, &run.info, &record)
        .map_err(|e| Failure::Internal(e.into()))?;
    let report = report(spec, &run);
    let json_path = out.join("tile.json");
    rockfall_results::write_json(&json_path, &report).map_err(|e| internal(&e, &json_path))?;
    print(&run.scenario.name, &report);
    println!(
        "wrote {} and tile.json to {}; merge every tile with `rockfall merge`",
        TALLY_FILE,
        out.display()
    );
    Ok(())
}

/// `--tiles N`: every tile of the region in turn, folded into one part as they finish, then
/// the region's run folder written from it.
pub fn run_all(
    input: &Path,
    overrides: &Overrides,
    spec: &TileSpec,
    out: &Path,
    ascii: bool,
) -> Result<(), Failure> {
    let console = Console::default();
    let mut acc: Option<Part> = None;
    for index in 1..=spec.count {
        let spec = TileSpec { index, ..*spec };
        let part = tile_part(input, overrides, &spec, &console)?;
        acc = Some(match acc {
            None => part,
            Some(a) => combine(a, part).map_err(|e| Failure::Internal(e.into()))?,
        });
    }
    let part = acc.ok_or_else(|| Failure::BadInput(anyhow!("--tiles: no tile")))?;
    write_region(input, overrides, part, out, ascii)
}

/// Tile `spec` run and printed, as a part of the region's run.
pub fn tile_part(
    input: &Path,
    overrides: &Overrides,
    spec: &TileSpec,
    observer: &dyn Observer,
) -> Result<Part, Failure> {
    let (run, record) = simulate_tile(input, overrides, spec, observer)?;
    print(&run.scenario.name, &report(spec, &run));
    let name = std::path::PathBuf::from(format!("tile {spec}"));
    let saved = SavedTally {
        layout: run.tally.layout().clone(),
        info: run.info,
        run: record,
        tally: run.tally,
    };
    Ok((name, saved))
}

/// The region's run folder from `part`, the fold of all its tiles (checked complete), with
/// the region's input read whole for the report.
pub fn write_region(
    input: &Path,
    overrides: &Overrides,
    part: Part,
    out: &Path,
    ascii: bool,
) -> Result<(), Failure> {
    let merged = share::merge(vec![part]).map_err(|e| Failure::Internal(e.into()))?;
    let sim = crate::commands::load_simulation(input, overrides)?;
    let finished = Finished {
        tally: merged.tally,
        info: merged.info,
        record: merged.record,
        convergence: None,
    };
    crate::regional::write_run_folder(&sim, input, out, ascii, finished)
}

/// Runs tile `spec`: its run and the record its tally file carries.
fn simulate_tile(
    input: &Path,
    overrides: &Overrides,
    spec: &TileSpec,
    observer: &dyn Observer,
) -> Result<(TileRun, RunRecord), Failure> {
    let region = rockfall_io::region_geometry(input)?;
    let failed = std::cell::RefCell::new(None);
    let load = |core, window| {
        rockfall_io::load_tile(input, core, window).map_err(|e| {
            let message = e.to_string();
            failed.replace(Some(e));
            SimError::Engine {
                file: None,
                message,
            }
        })
    };
    let run = run_tile(&region, spec, overrides, &load, observer).map_err(|e| {
        match failed.take() {
            // the input's own error, with its file and exit code
            Some(e) => Failure::from(e),
            None => simulate::sim_failure(e, input),
        }
    })?;
    // of the scenario as simulated (overrides applied), as `merge` computes it to reload it
    let fingerprint = share::tile_fingerprint(&run.scenario)
        .map_err(|e| Failure::BadInput(anyhow!("{}: {e}", input.display())))?;
    let record = RunRecord::of_tile(
        &run.scenario,
        &crate::regional::recorded_input(input),
        fingerprint,
        &run.rocks,
        run.region_rocks,
        spec,
    );
    Ok((run, record))
}

fn report<'a>(spec: &TileSpec, run: &'a TileRun) -> TileReport<'a> {
    let (bytes, cells) = run.tally.cell_memory();
    TileReport {
        tile: spec.to_string(),
        tile_size_m: spec.size_m,
        core: run.core,
        rocks: run.rocks.len(),
        region_rocks: run.region_rocks,
        cells_reached: cells,
        cell_statistics_bytes: bytes,
        passes: &run.passes,
        wall_time_s: run.passes.iter().map(|p| p.wall_time_s).sum(),
    }
}

fn print(name: &str, r: &TileReport<'_>) {
    let [c0, r0, nc, nr] = r.core;
    println!(
        "{name} (tile {}): {} of the region's {} rocks, from the {nc} × {nr} cells at column \
         {c0}, row {r0}; {} cells reached",
        r.tile, r.rocks, r.region_rocks, r.cells_reached
    );
    for (k, p) in r.passes.iter().enumerate() {
        let [_, _, wc, wr] = p.window;
        println!(
            "  pass {}: halo {} m ({wc} × {wr} cells read), {} rocks, {} left the tile{}, {:.1} s",
            k + 1,
            p.halo_m,
            p.rocks,
            p.left_tile,
            if p.left_tile > 0 {
                " (run again on a halo twice as wide)"
            } else {
                ""
            },
            p.wall_time_s
        );
    }
}

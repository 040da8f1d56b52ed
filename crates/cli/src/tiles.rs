//! `rockfall run --tile i/N`: one spatial tile of a region, into its exact tallies
//! (`rockfall.tally`) and `tile.json`, for `rockfall merge`. The tiling, halos and reruns
//! are the driver's (`rockfall_sim::tile`).

use crate::Failure;
use crate::simulate::{self, Console};
use anyhow::anyhow;
use rockfall_results::{TALLY_FILE, write_tally};
use rockfall_sim::tile::{TilePass, TileRun, TileSpec, run_tile};
use rockfall_sim::{Overrides, RunRecord, SimError, share};

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
    let console = Console::default();
    let run = run_tile(&region, spec, overrides, &load, &console).map_err(|e| {
        match failed.take() {
            // the input's own error, with its file and exit code
            Some(e) => Failure::from(e),
            None => simulate::sim_failure(e, input),
        }
    })?;
    // of the scenario as simulated (overrides applied), as `merge` computes it to reload it
    let fingerprint = share::tile_fingerprint(&run.scenario)
        .map_err(|e| Failure::BadInput(anyhow!("{}: {e}", input.display())))?;
    let internal =
        |e: &dyn std::fmt::Display, p: &Path| Failure::Internal(anyhow!("{}: {e}", p.display()));
    std::fs::create_dir_all(out).map_err(|e| internal(&e, out))?;
    let record = RunRecord::of_tile(
        &run.scenario,
        &crate::regional::recorded_input(input),
        fingerprint,
        &run.rocks,
        run.region_rocks,
        spec,
    );
    let tally_path = out.join(TALLY_FILE);
    write_tally(&tally_path, &run.tally, &run.info, &record)
        .map_err(|e| Failure::Internal(e.into()))?;
    let report = report(spec, &run);
    let json_path = out.join("tile.json");
    rockfall_results::write_json(&json_path, &report).map_err(|e| internal(&e, &json_path))?;
    print(&run.scenario.name, &report, out);
    Ok(())
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

fn print(name: &str, r: &TileReport<'_>, out: &Path) {
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
    println!(
        "wrote {} and tile.json to {}; merge every tile with `rockfall merge`",
        TALLY_FILE,
        out.display()
    );
}

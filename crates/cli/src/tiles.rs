//! `rockfall run --tile i/N`: one spatial tile of a region, into its exact tallies
//! (`rockfall.tally`) and `tile.json`, for `rockfall merge`. The tiling, halos and reruns
//! are the driver's (`rockfall_sim::tile`).

use crate::Failure;
use crate::simulate::{self, Console};
use anyhow::anyhow;
use rockfall_results::{SavedTally, TALLY_FILE, write_tally};
use rockfall_sim::converge::Convergence;
use rockfall_sim::reduce::{Part, accumulate, combine};
use rockfall_sim::tile::{SelectRocks, TilePass, TileRun, TileSpec, run_tile};
use rockfall_sim::{
    Finished, Observer, Overrides, RunRecord, SimError, batch_rocks, convergence_summary,
    per_release, share,
};

use crate::region_index::RegionIndex;
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
    /// Cells of the tile's core its rocks reached. Summed over the tiles: at most the
    /// region's cells reached (a cell reached only by other tiles' rocks is not counted),
    /// as the sum of `cells_reached` is at least it (the halos overlap).
    cells_reached_in_core: usize,
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
    index: &RegionIndex,
    out: &Path,
) -> Result<(), Failure> {
    let (run, record) = simulate_tile(input, overrides, spec, None, index, &Console::default())?;
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
/// the region's run folder written from it. A convergence run (`--until-stable`) does so
/// batch after batch, deciding on the region's merged maps after each.
pub fn run_all(
    input: &Path,
    overrides: &Overrides,
    spec: &TileSpec,
    index: &RegionIndex,
    out: &Path,
    ascii: bool,
) -> Result<(), Failure> {
    let console = Console::default();
    let mut run = TiledRun::default();
    let tiles: Vec<u64> = (1..=spec.count).collect();
    while let Some(range) = run.next_batch() {
        let batch = own_tiles(input, overrides, spec, &tiles, range, index, &console)?;
        let Some(batch) = batch else { break };
        if run.add(batch)? {
            break;
        }
    }
    run.write(input, overrides, out, ascii)
}

/// The tiles `tiles` of the region, each run on the rocks of indices `range` of its
/// releases (a batch of a convergence run; all its rocks otherwise), folded into one part.
/// `index` is the region's tile index: the release raster is scanned and the input files
/// hashed once per run (or not at all, with an index file).
pub fn own_tiles(
    input: &Path,
    overrides: &Overrides,
    spec: &TileSpec,
    tiles: &[u64],
    range: (u64, u64),
    index: &RegionIndex,
    observer: &dyn Observer,
) -> Result<Option<Part>, Failure> {
    let mut acc: Option<Part> = None;
    for &k in tiles {
        let spec = TileSpec { index: k, ..*spec };
        let part = tile_part(input, overrides, &spec, range, index, observer)?;
        acc = Some(match acc {
            None => part,
            Some(a) => combine(a, part).map_err(|e| Failure::Internal(e.into()))?,
        });
    }
    Ok(acc)
}

/// A region's run over tiles, batch after batch: the merged part so far and, for a
/// convergence run, where it stands.
#[derive(Default)]
pub struct TiledRun {
    part: Option<Part>,
    convergence: Option<Convergence>,
    over: bool,
}

impl TiledRun {
    /// The rock indices of every release in the next batch (the first: those of a
    /// convergence run's first batch, or all of a run without a tolerance); `None` when the
    /// run is over.
    pub fn next_batch(&self) -> Option<(u64, u64)> {
        match (&self.convergence, self.over) {
            (_, true) => None,
            (None, false) => Some((0, per_release(1))),
            (Some(c), false) => c.next(),
        }
    }

    /// Adds a batch (every tile's part of it, merged); true when the run is over.
    pub fn add(&mut self, batch: Part) -> Result<bool, Failure> {
        let internal = |e: rockfall_sim::MergeError| Failure::Internal(e.into());
        let Some(tol) = batch.1.run.batch.until_stable_pct else {
            // no tolerance: the tiles ran all their rocks
            self.part = Some(batch);
            self.over = true;
            return Ok(true);
        };
        if batch.1.tally.rocks() == 0 && self.part.is_some() {
            // every release at its cap
            self.over = true;
            return Ok(true);
        }
        let part = match self.part.take() {
            None => batch,
            Some(run) => accumulate(run, batch).map_err(internal)?,
        };
        let c = self
            .convergence
            .get_or_insert_with(|| Convergence::new(tol));
        c.batch_done(&part.1.tally);
        self.part = Some(part);
        self.over = c.next().is_none();
        Ok(self.over)
    }

    /// Writes the region's run folder into `out`, with the region's input read whole for
    /// the report.
    pub fn write(
        self,
        input: &Path,
        overrides: &Overrides,
        out: &Path,
        ascii: bool,
    ) -> Result<(), Failure> {
        let part = (self.part).ok_or_else(|| Failure::BadInput(anyhow!("--tiles: no tile")))?;
        let sim = crate::commands::load_simulation(input, overrides)?;
        let finished = match self.convergence {
            None => {
                let merged = share::merge(vec![part]).map_err(|e| Failure::Internal(e.into()))?;
                Finished {
                    tally: merged.tally,
                    info: merged.info,
                    record: merged.record,
                    convergence: None,
                }
            }
            Some(c) => {
                let (_, saved) = part;
                let mut record = saved.run;
                record.batch = c.state(record.rocks.clone());
                (record.partition, record.complete) = (None, true);
                let tol = record.batch.until_stable_pct.unwrap_or_default();
                let summary = convergence_summary(&record, &saved.tally, tol, &sim);
                Finished {
                    tally: saved.tally,
                    info: saved.info,
                    record,
                    convergence: Some(summary),
                }
            }
        };
        crate::regional::write_run_folder(&sim, input, out, ascii, finished)
    }
}

/// Tile `spec` run on the rocks of indices `range` of its releases when the scenario has a
/// tolerance (a batch), on all its rocks otherwise; printed, as a part of the region's run.
pub fn tile_part(
    input: &Path,
    overrides: &Overrides,
    spec: &TileSpec,
    range: (u64, u64),
    index: &RegionIndex,
    observer: &dyn Observer,
) -> Result<Part, Failure> {
    let select = |s: &rockfall_scenario::Scenario, r: &rockfall_sim::Releases| match s
        .simulation
        .until_stable_pct
    {
        Some(_) => batch_rocks(r, range.0, range.1),
        None => r.rock_set(),
    };
    let (run, record) = simulate_tile(input, overrides, spec, Some(&select), index, observer)?;
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

/// Runs tile `spec`: its run and the record its tally file carries.
fn simulate_tile(
    input: &Path,
    overrides: &Overrides,
    spec: &TileSpec,
    select: Option<&SelectRocks<'_>>,
    index: &RegionIndex,
    observer: &dyn Observer,
) -> Result<(TileRun, RunRecord), Failure> {
    let region = rockfall_io::region_geometry(input)?;
    let failed = std::cell::RefCell::new(None);
    let fail = |f: Failure| {
        let message = f.text();
        failed.replace(Some(f));
        SimError::Engine {
            file: None,
            message,
        }
    };
    let load = |core: rockfall_raster::Window, window| {
        let rows = core.row0..core.row0 + core.nrows;
        let counts = index.counts(rows).map_err(fail)?;
        let (s, scanned) =
            rockfall_io::load_tile(input, core, window, counts).map_err(|e| fail(e.into()))?;
        index.scanned(scanned);
        let tolerance = overrides.until_stable_pct.or(s.simulation.until_stable_pct);
        if select.is_none() && tolerance.is_some() {
            // one tile alone cannot tell when the region's maps are stable
            return Err(fail(Failure::BadInput(anyhow!(
                "{}: until_stable_pct: a convergence run decides on the region's maps; run \
                 every tile with --tiles N (also under mpirun), not --tile i/N",
                input.display()
            ))));
        }
        Ok(s)
    };
    let run = run_tile(&region, spec, overrides, &load, select, observer).map_err(|e| {
        match failed.take() {
            // the input's own error, with its file and exit code
            Some(f) => f,
            None => simulate::sim_failure(e, input),
        }
    })?;
    // of the scenario as simulated (overrides applied), as `merge` computes it to reload it
    let fingerprint = share::tile_fingerprint(&run.scenario, index.digest(&run.scenario)?);
    index.save();
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
        cells_reached_in_core: {
            let g = run.scenario.terrain.dem.geometry();
            let [c0, r0, nc, nr] = run.core;
            run.tally.cells_reached_where(|c| {
                let (row, col) = g.row_col(c);
                (c0..c0 + nc).contains(&col) && (r0..r0 + nr).contains(&row)
            })
        },
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

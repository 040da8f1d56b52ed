//! A merge of shares that streams their per-cell statistics instead of holding them: for
//! regions whose merged statistics do not fit in memory (`rockfall merge --stream`).
//!
//! Two readings of the tally files, after a check of their heads. The first ([`survey`])
//! reads each file whole, on
//! several threads, one file per thread at a time: it checks it (checksum, cells in order),
//! keeps what is per rock (statistics, trajectory rows, records), notes its first cell and
//! bounds on its counts ([`CellBounds`]), and drops its cells; the parts are then checked
//! and merged as [`share::merge`] does. The second ([`write`]) merges the files' cells in
//! cell order ([`CellMerge`]) straight into the rasters ([`Results::write_streamed`]); a
//! third reading precedes it only when the bounds leave a raster's sample type or nodata
//! marker open. Memory: the per-rock parts, one band of rows per raster, and the cells in
//! flight of the files open at once — those whose cells span the row being written. The
//! rasters' tiles are compressed on the threads asked for (the deflate of the tiles took
//! 56 % of the writing on one thread, `perf` on the 10⁸-cell region's merge).

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use rockfall_results::{
    CellBounds, CellMerge, MergeSource, Results, ResultsError, SavedTally, TallyFileError,
    TallyStream,
};

use crate::share::{self, MergeError, Merged, RunRecord};

/// What stops a streamed merge; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum StreamedMergeError {
    /// A tally file cannot be read, or changed between the readings.
    #[error(transparent)]
    Read(#[from] TallyFileError),
    /// The tallies are not the parts of one run.
    #[error(transparent)]
    Merge(#[from] MergeError),
    /// An output could not be written.
    #[error(transparent)]
    Write(#[from] ResultsError),
}

/// What the first reading found.
pub struct Survey {
    /// The merge of everything but the per-cell statistics.
    pub merged: Merged,
    /// Where each file's cells are, for the second reading.
    pub sources: Vec<MergeSource>,
    /// Bounds on the merged cells' counts.
    pub bounds: CellBounds,
}

/// One file's share of a [`Survey`].
type Surveyed = (SavedTally<RunRecord>, MergeSource, CellBounds);

/// Reads the tally files `paths` once each, on `threads` threads (see the module docs),
/// after checking from their heads alone (a few kilobytes each) that they are the parts of
/// one run: a missing or repeated tile is refused before hours of reading.
pub fn survey(paths: &[PathBuf], threads: usize) -> Result<Survey, StreamedMergeError> {
    let mut heads = Vec::with_capacity(paths.len());
    for path in paths {
        let (_, head) = TallyStream::open::<RunRecord>(path)?;
        heads.push((path.clone(), head));
    }
    share::merge(heads)?;
    let next = AtomicUsize::new(0);
    let slots: Vec<Mutex<Option<Result<Surveyed, TallyFileError>>>> =
        paths.iter().map(|_| Mutex::new(None)).collect();
    std::thread::scope(|s| {
        for _ in 0..threads.clamp(1, paths.len().max(1)) {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(path) = paths.get(i) else { break };
                    let read = read_one(path);
                    let failed = read.is_err();
                    *slots[i].lock().unwrap_or_else(|p| p.into_inner()) = Some(read);
                    if failed {
                        // the first error in file order is reported: stop taking files
                        next.fetch_add(paths.len(), Ordering::Relaxed);
                    }
                }
            });
        }
    });
    let mut parts = Vec::with_capacity(paths.len());
    let (mut sources, mut bounds) = (Vec::with_capacity(paths.len()), CellBounds::default());
    for (path, slot) in paths.iter().zip(slots) {
        let Some(read) = slot.into_inner().unwrap_or_else(|p| p.into_inner()) else {
            continue; // not read: an earlier file failed
        };
        let (saved, source, b) = read?;
        bounds.add(&b);
        sources.push(source);
        parts.push((path.clone(), saved));
    }
    let merged = share::merge(parts)?;
    Ok(Survey {
        merged,
        sources,
        bounds,
    })
}

fn read_one(path: &Path) -> Result<Surveyed, TallyFileError> {
    let (mut stream, mut saved) = TallyStream::open::<RunRecord>(path)?;
    let mut bounds = CellBounds::default();
    let mut first = None;
    while let Some(c) = stream.next_cell()? {
        first.get_or_insert(c.index());
        bounds.observe(&c);
    }
    let cells = stream.cells();
    let checksum = stream.finish(&mut saved.tally)?;
    let source = MergeSource {
        path: path.to_path_buf(),
        first_cell: first.unwrap_or(0),
        cells,
        checksum,
    };
    Ok((saved, source, bounds))
}

/// What a streamed merge wrote.
pub struct Written {
    /// The merged results, without per-cell statistics (their summary counts them).
    pub results: Results,
    /// The whole run's record.
    pub record: RunRecord,
    /// The files written.
    pub files: Vec<PathBuf>,
    /// How many readings of the files it took (2, or 3 when the bounds did not settle the
    /// rasters' types).
    pub readings: usize,
    /// Most files open at once in the last reading.
    pub most_open: usize,
}

/// Writes the merge of `survey` into `out` (see the module docs), the rasters' tiles
/// compressed on `threads` threads (the same bytes whatever their number).
pub fn write(survey: Survey, out: &Path, threads: usize) -> Result<Written, StreamedMergeError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build();
    match pool {
        Ok(pool) => pool.install(|| write_in(survey, out)),
        // no thread to be had: the calling thread alone
        Err(_) => write_in(survey, out),
    }
}

fn write_in(survey: Survey, out: &Path) -> Result<Written, StreamedMergeError> {
    let Survey {
        merged,
        sources,
        bounds,
    } = survey;
    let layout = merged.tally.layout().clone();
    let mut results = Results::new(&layout, merged.tally, merged.info);
    let (plan, readings) = match results.stream_plan(&bounds) {
        Some(plan) => (plan, 2),
        None => {
            let mut first = CellMerge::new(sources.clone());
            (results.stream_plan_exact(&mut first)?, 3)
        }
    };
    let mut cells = CellMerge::new(sources);
    let files = results.write_streamed(out, &plan, &mut cells)?;
    Ok(Written {
        results,
        record: merged.record,
        files,
        readings,
        most_open: cells.most_open(),
    })
}

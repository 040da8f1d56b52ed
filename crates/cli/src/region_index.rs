//! A region's tile index while its tiles run (`rockfall_io::tile_index`): computed by the
//! first tile that needs it and kept for every later tile of the process, and read from and
//! written to `--tile-index FILE` when given, so that tiles run as separate processes (a job
//! array) read it instead of the whole region.

use crate::Failure;
use anyhow::anyhow;
use rockfall_io::tile_index::{FileStamp, ReleaseCounts, TileIndex};
use rockfall_scenario::Scenario;
use std::cell::{Cell, RefCell};
use std::ops::Range;
use std::path::PathBuf;
use std::sync::Arc;

/// The digest of the input files and the files it was computed from.
type Inputs = (u64, Vec<(String, FileStamp)>);

/// A region's tile index: the release raster's or layer's counts and the input files' digest, each
/// once known; see the module.
#[derive(Default)]
pub struct RegionIndex {
    /// `--tile-index FILE`.
    file: Option<PathBuf>,
    /// Whether the file was read (or found missing).
    read: Cell<bool>,
    release: RefCell<Option<Arc<ReleaseCounts>>>,
    inputs: RefCell<Option<Inputs>>,
    /// Whether something was computed since the file was read or written.
    changed: Cell<bool>,
}

impl RegionIndex {
    /// The index of a run, kept in `file` when given.
    pub fn new(file: Option<PathBuf>) -> RegionIndex {
        RegionIndex {
            file,
            ..Default::default()
        }
    }

    /// The release's counts for a tile whose own cells are in rows `rows`, if known.
    /// The file is read at the first call, for `rows` only.
    pub fn counts(&self, rows: Range<usize>) -> Result<Option<Arc<ReleaseCounts>>, Failure> {
        if !self.read.replace(true)
            && let Some(file) = self.file.as_ref().filter(|f| f.exists())
        {
            let ix = TileIndex::read(file, Some(rows.clone()))?;
            *self.release.borrow_mut() = ix.release.map(Arc::new);
            *self.inputs.borrow_mut() = ix.inputs;
        }
        let held = self.release.borrow().clone();
        // counts read for another tile's rows: the file is read whole, once
        if let (Some(c), Some(file)) = (&held, &self.file)
            && !c.holds(rows)
        {
            let whole = TileIndex::read(file, None)?.release.map(Arc::new);
            *self.release.borrow_mut() = whole.clone();
            return Ok(whole);
        }
        Ok(held)
    }

    /// Keeps the counts of a release a tile read whole.
    pub fn scanned(&self, counts: Option<ReleaseCounts>) {
        if let Some(c) = counts {
            *self.release.borrow_mut() = Some(Arc::new(c));
            self.changed.set(true);
        }
    }

    /// The digest of the files `scenario` was read from
    /// (`rockfall_sim::share::input_digest`): the index's while every file has the stamp it
    /// had when hashed, computed again otherwise.
    pub fn digest(&self, scenario: &Scenario) -> Result<u64, Failure> {
        let same = |(_, files): &Inputs| {
            files.len() == scenario.sources.len()
                && (files.iter().zip(&scenario.sources)).all(|((k, s), (key, path))| {
                    k == key && FileStamp::of(path).is_ok_and(|now| now == *s)
                })
        };
        if let Some(held) = self.inputs.borrow().as_ref().filter(|i| same(i)) {
            return Ok(held.0);
        }
        let io = |e: std::io::Error| Failure::BadInput(anyhow!("{e}"));
        let stamps = (scenario.sources.iter())
            .map(|(k, p)| Ok((k.clone(), FileStamp::of(p).map_err(io)?)))
            .collect::<Result<Vec<_>, Failure>>()?;
        let digest = rockfall_sim::share::input_digest(scenario).map_err(io)?;
        *self.inputs.borrow_mut() = Some((digest, stamps));
        self.changed.set(true);
        Ok(digest)
    }

    /// Writes the index to its file, if it has one and something was computed since. A
    /// failure to write it is a warning: the tile's results do not depend on it.
    pub fn save(&self) {
        let Some(file) = &self.file else {
            return;
        };
        if !self.changed.replace(false) {
            return;
        }
        let mut release = self.release.borrow().as_deref().cloned();
        if let Some(c) = &release
            && !c.holds(0..c.nrows)
        {
            // counts read for one tile's rows: the file's whole counts are written back (none
            // if it is gone: the next tile counts them again)
            release = TileIndex::read(file, None).ok().and_then(|i| i.release);
        }
        let index = TileIndex {
            release,
            inputs: self.inputs.borrow().clone(),
        };
        if let Err(e) = index.write(file) {
            eprintln!(
                "warning: {}: cannot write the tile index ({e}); the tiles read the region \
                 whole instead",
                file.display()
            );
        }
    }
}

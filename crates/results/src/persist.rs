//! Tally files: a tally saved exactly, to be merged with others or continued later.
//!
//! A partition of a run (`rockfall run --partition i/N`), a batch of a convergence run and
//! every rank of an MPI run produce a [`Tally`]. Because every statistic of a tally is an
//! integer count, a fixed-point integer sum, an exact maximum or an integer histogram
//! ([`crate::hist`]), tallies of disjoint rock sets merge exactly; this module writes one
//! to bytes and back without losing a bit, so a merge of saved tallies is bit-identical to
//! the tally of one run over the union of their rocks.
//!
//! # Format (version [`TALLY_FORMAT`])
//!
//! - 8 bytes magic `RFTALLY` + NUL, `u32` format version (little-endian), the length of the
//!   header, the header as JSON: the [`Layout`] (grid, CRS, screens, percentiles, energy
//!   thresholds, trajectories kept, rock records kept), the [`RunInfo`] and the caller's
//!   description of the run (`run`: what the run was and which rocks it covers; see
//!   `rockfall-sim`).
//! - The body ([`crate::codec`]: integers as LEB128 varints, floats as their bit patterns):
//!   per-rock statistics, screens, speed profile, per-cell statistics sorted by cell (each
//!   cell as the gap from the one before), trajectory rows sorted by (rock, sequence), rock
//!   records sorted by rock, screen-crossing records sorted by (rock, sequence). Histograms
//!   are stored as their non-empty bins (each as the gap from the one before), a cell's
//!   source cells likewise. Format 7 took varints and gaps for the fixed-width integers of
//!   format 6: a third of the bytes on the regional tiles of `alpine-region`.
//! - A closing FNV-1a checksum (`u64`, little-endian) of everything before it, so that a
//!   truncated or damaged file is refused rather than merged.
//!
//! The file is the same whatever the thread count or merge order that produced the tally.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use rockfall_raster::{Crs, GridGeometry};
use rockfall_scenario::Screen;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::codec::{Dec, Enc, fnv1a};
use crate::tally_body::{body, read_body};
use crate::{Elevation, Layout, RunInfo, Tally};

/// Version of the tally file format this build reads and writes.
pub const TALLY_FORMAT: u32 = 7;

/// File name of a run folder's exact tallies.
pub const TALLY_FILE: &str = "rockfall.tally";

pub(crate) const MAGIC: &[u8; 8] = b"RFTALLY\0";

/// Why a tally file cannot be used. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum TallyFileError {
    /// The file cannot be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// Not a tally file at all.
    #[error("{path}: not a rockfall tally file")]
    NotATally {
        /// The file.
        path: PathBuf,
    },
    /// A tally file of another format version.
    #[error("{path}: tally file format {found}, this rockfall reads format {TALLY_FORMAT}")]
    Format {
        /// The file.
        path: PathBuf,
        /// Its format version.
        found: u32,
    },
    /// The bytes do not add up: a truncated, damaged or partially written file.
    #[error("{path}: damaged tally file ({what})")]
    Damaged {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        what: String,
    },
}

/// A tally read back, with what was saved beside it.
#[derive(Debug, Clone)]
pub struct SavedTally<M> {
    /// The layout the tally was made for.
    pub layout: Arc<Layout>,
    /// What the run was (engine, scenario, seed, threads, time, parameters).
    pub info: RunInfo,
    /// The caller's description of the run.
    pub run: M,
    /// The tally.
    pub tally: Tally,
}

/// The layout as the header stores it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(crate) struct LayoutRecord {
    ncols: usize,
    nrows: usize,
    x_min_m: f64,
    y_min_m: f64,
    cell_size_m: f64,
    epsg: Option<u32>,
    wkt: Option<String>,
    screens: Vec<ScreenRecord>,
    percentiles: Vec<f64>,
    energy_thresholds_kj: Vec<f64>,
    trajectories: u64,
    rock_ends: bool,
    screen_crossings: bool,
}

/// A screen as a tally file's header holds it.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct ScreenRecord {
    name: String,
    points_m: Vec<[f64; 2]>,
    capacity_kj: Option<f64>,
    height_m: Option<f64>,
    #[serde(default)]
    net: Option<u32>,
}

impl From<&Layout> for LayoutRecord {
    fn from(l: &Layout) -> Self {
        let g = &l.geometry;
        LayoutRecord {
            ncols: g.ncols,
            nrows: g.nrows,
            x_min_m: g.x_min_m,
            y_min_m: g.y_min_m,
            cell_size_m: g.cell_size_m,
            epsg: l.crs.as_ref().and_then(|c| c.epsg),
            wkt: l.crs.as_ref().and_then(|c| c.wkt.clone()),
            screens: (l.screens.iter())
                .map(|s| ScreenRecord {
                    name: s.name.clone(),
                    points_m: s.points_m.clone(),
                    capacity_kj: s.capacity_kj,
                    height_m: s.height_m,
                    net: s.net,
                })
                .collect(),
            percentiles: l.percentiles.clone(),
            energy_thresholds_kj: l.energy_thresholds_kj.clone(),
            trajectories: l.trajectories,
            rock_ends: l.rock_ends,
            screen_crossings: l.screen_crossings,
        }
    }
}

impl From<LayoutRecord> for Layout {
    fn from(r: LayoutRecord) -> Self {
        let crs = (r.epsg.is_some() || r.wkt.is_some()).then_some(Crs {
            epsg: r.epsg,
            wkt: r.wkt,
        });
        Layout {
            geometry: GridGeometry {
                ncols: r.ncols,
                nrows: r.nrows,
                x_min_m: r.x_min_m,
                y_min_m: r.y_min_m,
                cell_size_m: r.cell_size_m,
            },
            crs,
            screens: (r.screens.into_iter())
                .map(|s| Screen {
                    name: s.name,
                    points_m: s.points_m,
                    capacity_kj: s.capacity_kj,
                    height_m: s.height_m,
                    net: s.net,
                })
                .collect(),
            percentiles: r.percentiles,
            energy_thresholds_kj: r.energy_thresholds_kj,
            trajectories: r.trajectories,
            rock_ends: r.rock_ends,
            screen_crossings: r.screen_crossings,
            elevation: Elevation::default(),
            trusted: Default::default(),
        }
    }
}

#[derive(Serialize, Deserialize)]
pub(crate) struct Header<M> {
    pub(crate) layout: LayoutRecord,
    pub(crate) info: RunInfo,
    pub(crate) run: M,
}

/// `tally` (no rock in progress) with `info` and the caller's `run` description, as the bytes
/// of a tally file.
pub fn encode_tally<M: Serialize>(
    tally: &Tally,
    info: &RunInfo,
    run: &M,
) -> Result<Vec<u8>, serde_json::Error> {
    let mut e = Enc::default();
    encode_content(&mut e, tally, info, run)?;
    let sum = fnv1a(&e.buf);
    e.buf.extend_from_slice(&sum.to_le_bytes());
    Ok(e.buf)
}

/// Everything of a tally file but its checksum.
fn encode_content<M: Serialize>(
    e: &mut Enc,
    tally: &Tally,
    info: &RunInfo,
    run: &M,
) -> Result<(), serde_json::Error> {
    let header = serde_json::to_vec(&Header {
        layout: LayoutRecord::from(&**tally.layout()),
        info: info.clone(),
        run,
    })?;
    e.buf.extend_from_slice(MAGIC);
    e.u32(TALLY_FORMAT);
    e.len(header.len());
    e.buf.extend_from_slice(&header);
    body(e, tally);
    Ok(())
}

/// Reads the bytes of a tally file written by [`encode_tally`]; errors name `path`.
pub fn decode_tally<M: DeserializeOwned>(
    bytes: &[u8],
    path: &Path,
) -> Result<SavedTally<M>, TallyFileError> {
    let damaged = |what: String| TallyFileError::Damaged {
        path: path.to_path_buf(),
        what,
    };
    if bytes.len() < 12 || &bytes[..8] != MAGIC {
        return Err(TallyFileError::NotATally {
            path: path.to_path_buf(),
        });
    }
    let mut d = Dec::new(&bytes[8..]);
    let format = d.u32().map_err(|e| damaged(e.to_string()))?;
    if format != TALLY_FORMAT {
        return Err(TallyFileError::Format {
            path: path.to_path_buf(),
            found: format,
        });
    }
    if bytes.len() < 20 {
        return Err(damaged("too short".into()));
    }
    let (content, sum) = bytes.split_at(bytes.len() - 8);
    let mut sum_bytes = [0; 8];
    sum_bytes.copy_from_slice(sum);
    if fnv1a(content) != u64::from_le_bytes(sum_bytes) {
        return Err(damaged("checksum mismatch: truncated or altered".into()));
    }
    let mut d = Dec::new(&content[12..]);
    let n = d.len(1).map_err(|e| damaged(e.to_string()))?;
    let header = d.take(n).map_err(|e| damaged(e.to_string()))?;
    let header: Header<M> =
        serde_json::from_slice(header).map_err(|e| damaged(format!("header: {e}")))?;
    let layout = Arc::new(Layout::from(header.layout));
    let mut tally = Tally::new(layout.clone());
    read_body(&mut d, &mut tally).map_err(|e| damaged(e.to_string()))?;
    if d.remaining() != 0 {
        return Err(damaged(format!("{} bytes past the end", d.remaining())));
    }
    Ok(SavedTally {
        layout,
        info: header.info,
        run: header.run,
        tally,
    })
}

/// Writes a tally file atomically: a reader sees the old file or the whole new one, never
/// part of it, and a killed writer leaves no file under `path`. The bytes are those of
/// [`encode_tally`], streamed: at most about a megabyte of them is held at once.
pub fn write_tally<M: Serialize>(
    path: &Path,
    tally: &Tally,
    info: &RunInfo,
    run: &M,
) -> Result<(), crate::ResultsError> {
    let at = |e: std::io::Error| (path.to_path_buf(), e);
    rockfall_raster::atomic::write_atomic(path, |w| {
        // the encoder writes through its own handle of the (still empty) file
        let mut e = Enc::to_file(w.get_ref().try_clone().map_err(at)?);
        encode_content(&mut e, tally, info, run).map_err(|e| at(std::io::Error::other(e)))?;
        e.finish().map_err(at)
    })
    .map_err(|e: (std::path::PathBuf, std::io::Error)| crate::ResultsError::from(e))
}

/// Reads the tally file at `path`.
pub fn read_tally<M: DeserializeOwned>(path: &Path) -> Result<SavedTally<M>, TallyFileError> {
    let bytes = std::fs::read(path).map_err(|source| TallyFileError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode_tally(&bytes, path)
}

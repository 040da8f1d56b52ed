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
//! - 8 bytes magic `RFTALLY` + NUL, `u32` format version, `u64` length of the header, the
//!   header as JSON: the [`Layout`] (grid, CRS, screens, percentiles, energy thresholds,
//!   trajectories kept,
//!   rock records kept), the [`RunInfo`] and the caller's description of the run (`run`:
//!   what the run was and which rocks it covers; see `rockfall-sim`).
//! - The body, little-endian: per-rock statistics, screens, speed profile, per-cell
//!   statistics sorted by cell, trajectory rows sorted by (rock, sequence), rock records
//!   sorted by rock, screen-crossing records sorted by (rock, sequence). Histograms are
//!   stored as their non-empty bins. Floats are stored as their bit patterns.
//! - A closing `u64` FNV-1a checksum of everything before it, so that a truncated or
//!   damaged file is refused rather than merged.
//!
//! The file is the same whatever the thread count or merge order that produced the tally.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use rockfall_raster::{Crs, GridGeometry};
use rockfall_scenario::Screen;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::cells::{CellHists, CellStats};
use crate::codec::{Dec, DecodeError, Enc, fnv1a};
use crate::hist::Stat;
use crate::profile::SpeedHistogram;
use crate::{
    CrossingRecord, Elevation, Event, Layout, Motion, Outcome, RockEnd, RockRecord, RunInfo,
    ScreenCrossing, Tally, TrajectoryRow,
};

/// Version of the tally file format this build reads and writes.
pub const TALLY_FORMAT: u32 = 6;

/// File name of a run folder's exact tallies.
pub const TALLY_FILE: &str = "rockfall.tally";

const MAGIC: &[u8; 8] = b"RFTALLY\0";

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
struct LayoutRecord {
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
        }
    }
}

#[derive(Serialize, Deserialize)]
struct Header<M> {
    layout: LayoutRecord,
    info: RunInfo,
    run: M,
}

/// `tally` (no rock in progress) with `info` and the caller's `run` description, as the bytes
/// of a tally file.
pub fn encode_tally<M: Serialize>(
    tally: &Tally,
    info: &RunInfo,
    run: &M,
) -> Result<Vec<u8>, serde_json::Error> {
    let header = serde_json::to_vec(&Header {
        layout: LayoutRecord::from(&**tally.layout()),
        info: info.clone(),
        run,
    })?;
    let mut e = Enc::default();
    e.buf.extend_from_slice(MAGIC);
    e.u32(TALLY_FORMAT);
    e.len(header.len());
    e.buf.extend_from_slice(&header);
    body(&mut e, tally);
    let sum = fnv1a(&e.buf);
    e.u64(sum);
    Ok(e.buf)
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
/// part of it, and a killed writer leaves no file under `path`.
pub fn write_tally<M: Serialize>(
    path: &Path,
    tally: &Tally,
    info: &RunInfo,
    run: &M,
) -> Result<(), crate::ResultsError> {
    let bytes = encode_tally(tally, info, run)
        .map_err(|e| (path.to_path_buf(), std::io::Error::other(e)))?;
    rockfall_raster::atomic::write_bytes_atomic(path, &bytes).map_err(crate::ResultsError::from)
}

/// Reads the tally file at `path`.
pub fn read_tally<M: DeserializeOwned>(path: &Path) -> Result<SavedTally<M>, TallyFileError> {
    let bytes = std::fs::read(path).map_err(|source| TallyFileError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode_tally(&bytes, path)
}

fn stat(e: &mut Enc, s: &Stat) {
    e.u64(s.count);
    e.u128(s.sum);
    e.f64(s.max);
    e.sparse(&s.hist);
}

fn read_stat(d: &mut Dec<'_>, s: &mut Stat) -> Result<(), DecodeError> {
    s.count = d.u64()?;
    s.sum = d.u128()?;
    s.max = d.f64()?;
    d.sparse_into(&mut s.hist, Some)
}

fn body(e: &mut Enc, t: &Tally) {
    let r = &t.rock;
    for &n in &r.outcomes {
        e.u64(n);
    }
    for s in [&r.runout, &r.max_velocity, &r.max_jump, &r.time] {
        stat(e, s);
    }
    for n in [
        r.tree_impacts,
        r.stems_broken,
        r.rebounds,
        r.events,
        r.held_at_release,
    ] {
        e.u64(n);
    }
    for &n in &r.motion_us {
        e.u64(n);
    }
    e.len(t.screens.len());
    for s in &t.screens {
        e.u64(s.rocks);
        e.u64(s.over_capacity);
        e.u64(s.over_height);
        for st in [&s.velocity, &s.energy, &s.height] {
            stat(e, st);
        }
    }
    e.f64(t.profile.bin_m);
    e.len(t.profile.bins.len());
    for b in &t.profile.bins {
        e.sparse(&b.counts);
        e.f64(b.max_ms);
    }
    let mut cells: Vec<&CellStats> = t.cells.touched().iter().collect();
    cells.sort_unstable_by_key(|c| c.cell);
    e.len(cells.len());
    let thresholds = t.cells.thresholds().len();
    for c in cells {
        cell(e, c, thresholds);
    }
    let mut rows: Vec<_> = t.rows.iter().collect();
    rows.sort_unstable_by_key(|(rock, seq, _)| (*rock, *seq));
    e.len(rows.len());
    for (rock, seq, row) in rows {
        e.u64(*rock);
        e.u64(*seq);
        trajectory_row(e, row);
    }
    let mut records: Vec<_> = t.rock_records.iter().collect();
    records.sort_unstable_by_key(|r| r.rock_id);
    e.len(records.len());
    for r in records {
        rock_record(e, r);
    }
    let mut crossings: Vec<_> = t.crossing_records.iter().collect();
    crossings.sort_unstable_by_key(|c| (c.rock_id, c.seq));
    e.len(crossings.len());
    for c in crossings {
        crossing_record(e, c);
    }
}

fn crossing_record(e: &mut Enc, c: &CrossingRecord) {
    e.u64(c.rock_id);
    e.len(c.screen);
    e.u32(c.seq);
    let x = &c.crossing;
    for v in [
        x.velocity_ms,
        x.energy_j,
        x.jump_height_m,
        x.x_m,
        x.y_m,
        c.mass_kg,
    ] {
        e.f64(v);
    }
}

fn read_crossing_record(d: &mut Dec<'_>, screens: usize) -> Result<CrossingRecord, DecodeError> {
    let rock_id = d.u64()?;
    let at = d.pos();
    let screen = d.u64()? as usize;
    if screen >= screens {
        return Err(d.corrupt(at, format!("crossing of screen {screen} of {screens}")));
    }
    let seq = d.u32()?;
    let [velocity_ms, energy_j, jump_height_m, x_m, y_m, mass_kg] =
        [d.f64()?, d.f64()?, d.f64()?, d.f64()?, d.f64()?, d.f64()?];
    Ok(CrossingRecord {
        rock_id,
        screen,
        seq,
        crossing: ScreenCrossing {
            velocity_ms,
            energy_j,
            jump_height_m,
            x_m,
            y_m,
        },
        mass_kg,
    })
}

fn read_body(d: &mut Dec<'_>, t: &mut Tally) -> Result<(), DecodeError> {
    let r = &mut t.rock;
    for n in &mut r.outcomes {
        *n = d.u64()?;
    }
    for s in [
        &mut r.runout,
        &mut r.max_velocity,
        &mut r.max_jump,
        &mut r.time,
    ] {
        read_stat(d, s)?;
    }
    for n in [
        &mut r.tree_impacts,
        &mut r.stems_broken,
        &mut r.rebounds,
        &mut r.events,
        &mut r.held_at_release,
    ] {
        *n = d.u64()?;
    }
    for n in &mut r.motion_us {
        *n = d.u64()?;
    }
    let at = d.pos();
    let screens = d.len(1)?;
    if screens != t.screens.len() {
        return Err(DecodeError::Corrupt {
            offset: at,
            what: format!("{screens} screens, the layout has {}", t.screens.len()),
        });
    }
    for s in &mut t.screens {
        s.rocks = d.u64()?;
        s.over_capacity = d.u64()?;
        s.over_height = d.u64()?;
        for st in [&mut s.velocity, &mut s.energy, &mut s.height] {
            read_stat(d, st)?;
        }
    }
    let bin_m = d.f64()?;
    if bin_m.to_bits() != t.profile.bin_m.to_bits() {
        return Err(d.corrupt(d.pos(), format!("profile bins of {bin_m} m")));
    }
    let bins = d.len(16)?;
    t.profile.bins = Vec::with_capacity(bins);
    for _ in 0..bins {
        let mut h = SpeedHistogram::new();
        d.sparse_into(&mut h.counts, Some)?;
        h.max_ms = d.f64()?;
        t.profile.bins.push(h);
    }
    let n = d.len(8)?;
    let len = t.layout().geometry.len();
    let thresholds = t.cells.thresholds().len();
    let mut cells = Vec::with_capacity(n);
    for _ in 0..n {
        let c = read_cell(d, thresholds)?;
        if c.cell >= len {
            return Err(d.corrupt(d.pos(), format!("cell {} outside the grid", c.cell)));
        }
        cells.push(c);
    }
    t.cells.absorb(cells);
    let n = d.len(16)?;
    t.rows.reserve(n);
    for _ in 0..n {
        let (rock, seq) = (d.u64()?, d.u64()?);
        t.rows.push((rock, seq, read_trajectory_row(d)?));
    }
    let n = d.len(8)?;
    t.rock_records.reserve(n);
    for _ in 0..n {
        t.rock_records.push(read_rock_record(d)?);
    }
    let n = d.len(60)?;
    t.crossing_records.reserve(n);
    for _ in 0..n {
        let screens = t.screens.len();
        t.crossing_records.push(read_crossing_record(d, screens)?);
    }
    Ok(())
}

fn cell(e: &mut Enc, c: &CellStats, thresholds: usize) {
    e.len(c.cell);
    for n in [
        c.visits,
        c.reached,
        c.deposited,
        c.tree_impacts,
        c.stems_broken,
    ] {
        e.u64(n);
    }
    e.f64(c.tree_height_max_m);
    e.u128(c.energy_sum);
    e.u128(c.height_sum);
    e.u128(c.energy_sq_sum);
    e.u128(c.height_sq_sum);
    for v in [
        c.energy_max_j,
        c.height_max_m,
        c.velocity_max_ms,
        c.el_angle_max_deg,
    ] {
        e.f64(v);
    }
    match &c.hists {
        None => e.u8(0),
        Some(h) => {
            e.u8(1);
            e.sparse(&h.energy);
            e.sparse(&h.height);
            for &n in &h.above[..thresholds] {
                e.u64(n);
            }
        }
    }
    e.len(c.sources.len());
    for &s in &c.sources {
        e.u32(s);
    }
}

fn read_cell(d: &mut Dec<'_>, thresholds: usize) -> Result<CellStats, DecodeError> {
    let at = d.pos();
    let cell = usize::try_from(d.u64()?).map_err(|_| d.corrupt(at, "cell index".into()))?;
    let mut c = CellStats::new(cell);
    for n in [
        &mut c.visits,
        &mut c.reached,
        &mut c.deposited,
        &mut c.tree_impacts,
        &mut c.stems_broken,
    ] {
        *n = d.u64()?;
    }
    c.tree_height_max_m = d.f64()?;
    c.energy_sum = d.u128()?;
    c.height_sum = d.u128()?;
    c.energy_sq_sum = d.u128()?;
    c.height_sq_sum = d.u128()?;
    for v in [
        &mut c.energy_max_j,
        &mut c.height_max_m,
        &mut c.velocity_max_ms,
        &mut c.el_angle_max_deg,
    ] {
        *v = d.f64()?;
    }
    if d.u8()? == 1 {
        let mut h = CellHists::empty();
        let narrow = |c: u64| u32::try_from(c).ok();
        d.sparse_into(&mut h.energy, narrow)?;
        d.sparse_into(&mut h.height, narrow)?;
        for n in &mut h.above[..thresholds] {
            *n = d.u64()?;
        }
        c.hists = Some(h);
    }
    let n = d.len(4)?;
    c.sources = (0..n).map(|_| d.u32()).collect::<Result<_, _>>()?;
    if !c.sources.windows(2).all(|w| w[0] < w[1]) {
        return Err(d.corrupt(at, format!("sources of cell {cell} not ascending")));
    }
    Ok(c)
}

const EVENTS: [Event; 5] = [
    Event::Flight,
    Event::Impact,
    Event::Roll,
    Event::Tree,
    Event::Stop,
];

fn trajectory_row(e: &mut Enc, r: &TrajectoryRow) {
    e.u64(r.rock_id);
    for v in r.values() {
        e.f64(v);
    }
    e.u8(EVENTS.iter().position(|&k| k == r.event).unwrap_or(0) as u8);
}

fn read_trajectory_row(d: &mut Dec<'_>) -> Result<TrajectoryRow, DecodeError> {
    let rock_id = d.u64()?;
    let mut v = [0.0; 12];
    for x in &mut v {
        *x = d.f64()?;
    }
    let at = d.pos();
    let k = d.u8()?;
    let event = *(EVENTS.get(k as usize)).ok_or_else(|| d.corrupt(at, format!("event {k}")))?;
    Ok(TrajectoryRow::from_values(rock_id, v, event))
}

fn rock_record(e: &mut Enc, r: &RockRecord) {
    e.u64(r.rock_id);
    e.len(r.source_cell);
    for v in r.start_m {
        e.f64(v);
    }
    e.f64(r.volume_m3);
    e.f64(r.mass_kg);
    let end = &r.end;
    let (kind, cell) = match end.outcome {
        Outcome::Stopped { cell } => (0, cell),
        Outcome::NetStopped { cell } => (1, cell),
        Outcome::LeftDem => (2, 0),
        Outcome::TimeLimit => (3, 0),
        Outcome::Failed => (4, 0),
    };
    e.u8(kind);
    e.len(cell);
    for v in [
        end.x_m,
        end.y_m,
        end.runout_m,
        end.max_velocity_ms,
        end.max_jump_height_m,
        end.time_s,
    ] {
        e.f64(v);
    }
    for n in [end.tree_impacts, end.stems_broken, end.rebounds, end.events] {
        e.u32(n);
    }
    for t in end.motion.as_array() {
        e.f64(t);
    }
}

fn read_rock_record(d: &mut Dec<'_>) -> Result<RockRecord, DecodeError> {
    let rock_id = d.u64()?;
    let source_cell = d.u64()? as usize;
    let start_m = [d.f64()?, d.f64()?, d.f64()?];
    let (volume_m3, mass_kg) = (d.f64()?, d.f64()?);
    let at = d.pos();
    let kind = d.u8()?;
    let cell = d.u64()? as usize;
    let outcome = match kind {
        0 => Outcome::Stopped { cell },
        1 => Outcome::NetStopped { cell },
        2 => Outcome::LeftDem,
        3 => Outcome::TimeLimit,
        4 => Outcome::Failed,
        k => return Err(d.corrupt(at, format!("outcome {k}"))),
    };
    let [
        x_m,
        y_m,
        runout_m,
        max_velocity_ms,
        max_jump_height_m,
        time_s,
    ] = [d.f64()?, d.f64()?, d.f64()?, d.f64()?, d.f64()?, d.f64()?];
    let [tree_impacts, stems_broken, rebounds, events] = [d.u32()?, d.u32()?, d.u32()?, d.u32()?];
    let motion = Motion::from_array([d.f64()?, d.f64()?, d.f64()?, d.f64()?, d.f64()?]);
    Ok(RockRecord {
        rock_id,
        source_cell,
        start_m,
        volume_m3,
        mass_kg,
        end: RockEnd {
            outcome,
            x_m,
            y_m,
            runout_m,
            max_velocity_ms,
            max_jump_height_m,
            tree_impacts,
            stems_broken,
            rebounds,
            time_s,
            events,
            motion,
        },
    })
}

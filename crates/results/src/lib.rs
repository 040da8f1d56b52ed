//! What a run produces, shared by both engines.
//!
//! An engine simulates rocks one after another on each worker thread and reports what happens
//! to a per-worker [`Tally`]: a rock starts, visits cells, hits trees, crosses screens, ends.
//! Tallies hold bounded-memory statistics only (counts, fixed-point sums, maxima, fixed-bin
//! histograms), so memory does not grow with the number of rocks, and merging two tallies is
//! exact integer arithmetic: the merged result is bit-identical whatever the order of merging,
//! hence whatever the thread count.
//!
//! [`Results::new`] turns the merged tally into rasters (named as Rockyfor3D users know them),
//! `summary.json` (a [`Summary`], the engine's [`Parameters`] in it), `trajectories.csv` and,
//! on request ([`Layout::rock_ends`]), `rocks.csv` (one [`RockRecord`] per rock);
//! [`Results::write`] writes them atomically. [`ForestEffect`] compares a run with the forest
//! to the same run without it (`forest_effect.json`: a [`ForestEffectSummary`]).
//! [`Results::distribution`] and [`Results::speed_profile`] give what the report plots.
//! [`ScreenSet`] finds where a rock's plan-view path crosses the evaluation screens.
//!
//! # Statistics and their accuracy
//!
//! - Sums are of values quantised to integers (mJ for energies; µm, µm/s, µs for heights,
//!   speeds, distances and times) in `u128`; means are exact up to that quantisation.
//!   Values are cleaned first: NaN and negative → 0, above 10¹² → 10¹².
//! - Maxima are exact (`f64::max`).
//! - Percentiles come from log-spaced histograms with 32 bins per decade: energies
//!   1 J … 10¹⁰ J (320 bins), passing / jump heights and speeds 10⁻³ … 10³ m, m/s
//!   (192 bins), runouts and times 10⁻³ … 10⁵ m, s (256 bins), each with an underflow
//!   bin (below the range, 0 included) and an overflow bin. Inside a range a percentile is
//!   within [`PERCENTILE_RELATIVE_ERROR`] (10^(1/32) − 1 ≈ 7.46 %) of the exact
//!   nearest-rank value; below it within the lower bound (1 J, 1 mm) in absolute terms;
//!   percentiles are clamped to the exact maximum.
//!
//! # Memory
//!
//! Per tally: 1 KiB per block of 16 × 16 cells something happened in (and ≈ 0.016 byte per
//! grid cell for the directory of blocks), plus for every cell something happened in 176 bytes
//! of counters, sums and maxima (in pages of 4 096, never moved once full, the last growing by
//! doubling) and on the heap its energy and passing-height histograms packed (3 bytes per
//! visit for a cell visited a few times, else one byte per bin of the window it uses and
//! more only for the bins counting past 255), its source cells as runs of
//! neighbours (8 bytes for the last, 3–4 for each other) and, where rocks stopped, hit trees or passed above an energy
//! threshold, 80 bytes more: 0.31–0.42 kB per reached cell in every case measured
//! (`cell_statistics_bytes_per_reached_cell` of `summary.json`; docs/scale.md): vaujany-site2
//! with 10⁴–10⁶ rocks (cells of 10⁵ visits and more), `alpine-region` of 10⁶ cells with 1–100
//! rocks per source cell (cells reached from hundreds of source cells) and of 10⁷ cells. A run's workers
//! move their cells into one shared table every 65 536 cells ([`Tally::flush_cells`]), so
//! the threads do not multiply it. Per-screen and per-rock statistics are a few
//! kB in all; the speed profile ([`Results::speed_profile`]) 4 kB per distance bin of one
//! cell reached (at most 2000 bins, 8 MB). Only the recorded trajectories (rocks with `rock_id < Layout::trajectories`)
//! and, when [`Layout::rock_ends`] is set, the per-rock records (one [`RockRecord`], 120
//! bytes, per rock) grow with the number of rocks.

mod cells;
mod codec;
mod convergence;
mod distribution;
pub mod fair;
mod forest_effect;
mod hist;
mod packed;
mod parameters;
mod persist;
mod profile;
mod results;
mod screens;
mod source_set;
mod stream;
mod stream_write;
mod summary;
mod tally;
mod tally_body;
mod trajectory;
mod write;

pub use cells::MAX_ENERGY_THRESHOLDS;
pub use codec::{DecodeError, Fnv1a};
pub use convergence::{ConvergenceSummary, MIN_REACH_PCT, MapChange, MapSnapshot};
pub use distribution::{Bin, Distribution, Quantity};
pub use forest_effect::{
    AreaAbove, BareCells, CellDifferences, Difference, ForestEffect, ForestEffectSummary,
    ReachDifferences, ScreenDifference,
};
pub use hist::PERCENTILE_RELATIVE_ERROR;
pub use parameters::{LegacySolver, LumpedParameters, Parameters, RigidParameters, RunSize};
pub use persist::{
    SavedTally, TALLY_FILE, TALLY_FORMAT, TallyFileError, decode_tally, encode_tally, read_tally,
    write_tally,
};
pub use profile::ProfileBin;
pub use results::{RasterCells, Results, RunInfo, rocks_above_name};
pub use screens::ScreenSet;
pub use stream::{CellMerge, MergeSource, StreamCell, TallyStream};
pub use stream_write::{CellBounds, StreamPlan};
pub use summary::{MeanP95Max, MotionShares, Outcomes, Runout, ScreenSummary, Summary, TimeStats};
pub use tally::{SharedCells, Tally};
pub use trajectory::{Event, TrajectoryRow};
pub use write::{CROSSINGS_HEADER, ROCKS_HEADER, ResultsError, TRAJECTORY_HEADER, write_json};

use rockfall_raster::{Crs, Grid, GridGeometry};
use rockfall_scenario::{Scenario, Screen};
use std::sync::Arc;

/// What the tallies need to know about the run before it starts.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// The DEM's grid: every cell index below is row-major on it.
    pub geometry: GridGeometry,
    /// CRS written into the rasters.
    pub crs: Option<Crs>,
    /// Evaluation screens, in scenario order.
    pub screens: Vec<Screen>,
    /// Energy percentiles written as `E_<p>` rasters (e.g. 50, 90, 95, 98, 99); `E_95` and
    /// `Ph_95` are always written.
    pub percentiles: Vec<f64>,
    /// Energies, kJ, ascending (at most [`MAX_ENERGY_THRESHOLDS`]; more are ignored): each
    /// cell counts the distinct rocks that passed it with more kinetic energy than each,
    /// written as `Nr_rocks_above_<e>kJ` rasters, what the hazard frequency
    /// `λ(x, e) = f · N_pass(x, E > e) / N` needs (`rockfall hazard`, frequency mode).
    pub energy_thresholds_kj: Vec<f64>,
    /// Rocks with `rock_id < trajectories` have their trajectory recorded.
    pub trajectories: u64,
    /// Keep one [`RockRecord`] per rock (start, outcome, maxima) and write `rocks.csv`.
    /// Memory then grows with the number of rocks: one record (176 bytes) per rock.
    pub rock_ends: bool,
    /// Keep one record per screen crossing and write `screen_crossings.csv`
    /// (`[output] screen_crossings`). Memory then grows with the crossings: 72 bytes each.
    pub screen_crossings: bool,
    /// The DEM the energy-line angles (`EL_angles`) are measured on; without it (a layout
    /// read back from a tally file, whose cells already hold their angles) no new angle is
    /// recorded.
    pub elevation: Elevation,
    /// For a spatial tile of a region: the cells its rocks may visit. A rock that visits
    /// another ends as `left_tile`: nothing of it is tallied, and it is listed to be run
    /// again on a wider halo ([`crate::Tally::left_tile`]).
    pub trusted: TrustedCells,
}

/// The cells a tile's rocks may visit (see [`Layout::trusted`]); `None`: every cell. Not part
/// of a layout's identity (the tiles of one region merge) and never written into a tally
/// file.
#[derive(Clone, Copy, Default, Debug)]
pub struct TrustedCells(pub Option<rockfall_raster::Window>);

impl PartialEq for TrustedCells {
    fn eq(&self, _: &TrustedCells) -> bool {
        true
    }
}

/// The DEM heights a run's tallies read the energy-line angle from (`EL_angles`). Not part
/// of a layout's identity: two layouts differing only here are equal (the DEM is part of the
/// scenario fingerprint, checked separately), and it is never written into a tally file.
#[derive(Clone, Default)]
pub struct Elevation(pub Option<Arc<Grid<f64>>>);

impl Elevation {
    /// Height of the DEM at the centre of row-major `cell`, m; `None` without a DEM or at
    /// nodata.
    pub fn at(&self, cell: usize) -> Option<f64> {
        self.0.as_ref()?.get_index(cell)
    }
}

impl PartialEq for Elevation {
    fn eq(&self, _: &Elevation) -> bool {
        true
    }
}

impl std::fmt::Debug for Elevation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.is_some() {
            "Elevation(DEM)"
        } else {
            "Elevation(none)"
        })
    }
}

impl Layout {
    /// The layout of a run of `scenario`: the DEM's grid and CRS, its screens, energy
    /// percentiles, number of recorded trajectories and whether per-rock records are kept
    /// (`[output] rocks_csv`).
    pub fn of(scenario: &Scenario) -> Layout {
        let dem = &scenario.terrain.dem;
        Layout {
            geometry: *dem.geometry(),
            crs: dem.crs().cloned(),
            screens: scenario.screens.clone(),
            percentiles: scenario.output.percentiles.clone(),
            energy_thresholds_kj: scenario.output.energy_thresholds_kj.clone(),
            trajectories: scenario.output.trajectories,
            rock_ends: scenario.output.rocks_csv,
            screen_crossings: scenario.output.screen_crossings,
            elevation: Elevation(Some(dem.shared_grid().clone())),
            trusted: TrustedCells(scenario.tile.as_ref().map(|t| t.trusted)),
        }
    }
}

/// A rock leaves its release position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RockStart {
    /// Global rock number, 0-based, in release order (source cells, then points).
    pub rock_id: u64,
    /// Row-major index of the cell the rock is released from.
    pub source_cell: usize,
    /// Release position of the rock centre, m.
    pub x_m: f64,
    /// Release position, m.
    pub y_m: f64,
    /// Release position, m.
    pub z_m: f64,
    /// The rock's volume, m³ (its own when `[rock] volume_variation_percent` varies it).
    pub volume_m3: f64,
    /// The rock's mass, kg.
    pub mass_kg: f64,
}

/// One visit of a rock to a cell: the maxima over the time it spent in the cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellVisit {
    /// Largest kinetic energy (translational + rotational), J.
    pub energy_j: f64,
    /// Largest translational speed, m/s.
    pub velocity_ms: f64,
    /// Largest passing height: vertical height of the rock centre above the ground, m.
    pub passing_height_m: f64,
}

/// A rock crossing an evaluation screen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScreenCrossing {
    /// Translational speed at the crossing, m/s.
    pub velocity_ms: f64,
    /// Kinetic energy (translational + rotational) at the crossing, J.
    pub energy_j: f64,
    /// Vertical height of the rock centre above the ground at the crossing, m.
    pub jump_height_m: f64,
    /// Where the rock centre crossed the screen in plan view, m.
    pub x_m: f64,
    /// Where the rock centre crossed the screen in plan view, m.
    pub y_m: f64,
}

/// One crossing of a screen as `screen_crossings.csv` lists it (kept when
/// [`Layout::screen_crossings`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrossingRecord {
    /// The rock.
    pub rock_id: u64,
    /// Index of the screen in [`Layout::screens`].
    pub screen: usize,
    /// Sequence number of this crossing within the rock's crossings.
    pub seq: u32,
    /// The crossing.
    pub crossing: ScreenCrossing,
    /// The rock's mass, kg.
    pub mass_kg: f64,
}

/// How a rock's run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Came to rest inside the DEM, in this cell.
    Stopped {
        /// Row-major cell index.
        cell: usize,
    },
    /// Stopped by a net in this cell.
    NetStopped {
        /// Row-major cell index.
        cell: usize,
    },
    /// Left the DEM (or reached a nodata cell).
    LeftDem,
    /// Still moving at the scenario's `max_time_s`.
    TimeLimit,
    /// The engine gave up on this rock (non-finite or exploding state).
    Failed,
}

impl Outcome {
    /// Stable lowercase name, as in `rocks.csv` and the `outcomes` object of
    /// `summary.json`: `stopped`, `net_stopped`, `left_dem`, `time_limit` or `failed`.
    pub fn name(&self) -> &'static str {
        tally::OUTCOME_NAMES[tally::outcome_index(self)]
    }
}

/// A rock's run is over.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RockEnd {
    /// How it ended.
    pub outcome: Outcome,
    /// End position, m.
    pub x_m: f64,
    /// End position, m.
    pub y_m: f64,
    /// Horizontal distance from release to end point, m.
    pub runout_m: f64,
    /// Largest translational speed over the run, m/s.
    pub max_velocity_ms: f64,
    /// Largest vertical height of the rock centre above the ground, m.
    pub max_jump_height_m: f64,
    /// Tree impacts.
    pub tree_impacts: u32,
    /// Stems broken by this rock.
    pub stems_broken: u32,
    /// Ground rebounds.
    pub rebounds: u32,
    /// Simulated time, s.
    pub time_s: f64,
    /// Events the engine simulated for this rock: flight arcs and rolling steps (lumped),
    /// time steps (rigid). Their rate is the engine's cost per unit of path; trajectories/s
    /// also depend on how long the paths are.
    pub events: u32,
    /// How the rock moved, s (rigid engine; all zero for the lumped engine).
    pub motion: Motion,
}

/// The time a rigid rock spent in each mode of motion, s. Each time step is one mode, judged
/// after its contact impulses (the rule is ours: the papers name the modes without a
/// numerical test):
///
/// - **flight**: no ground contact;
/// - **slow**: ground contact with the centre slower than the stop speed (settling);
/// - **rolling**: ground contact where the contact points slip slower than half the centre's
///   speed — the hull turns over the ground more than it slides (on an edge or a vertex this is
///   the wheel-like rolling of flat rocks, Caviezel et al. 2021);
/// - **sliding on a face**: the contact points slip at half the centre's speed or more on three
///   or more contacts (a face on the ground);
/// - **sliding on an edge**: the same on one or two contacts (an edge or a vertex).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Motion {
    /// In flight, s.
    pub flight_s: f64,
    /// Rolling, s.
    pub rolling_s: f64,
    /// Sliding on a face, s.
    pub sliding_face_s: f64,
    /// Sliding on an edge or a vertex, s.
    pub sliding_edge_s: f64,
    /// In slow ground contact, s.
    pub slow_s: f64,
}

impl Motion {
    /// The times in the order of [`MOTION_NAMES`], s.
    pub fn as_array(&self) -> [f64; 5] {
        [
            self.flight_s,
            self.rolling_s,
            self.sliding_face_s,
            self.sliding_edge_s,
            self.slow_s,
        ]
    }

    /// The motion of times in the order of [`MOTION_NAMES`], s.
    pub fn from_array(t: [f64; 5]) -> Motion {
        Motion {
            flight_s: t[0],
            rolling_s: t[1],
            sliding_face_s: t[2],
            sliding_edge_s: t[3],
            slow_s: t[4],
        }
    }
}

/// Names of the modes of [`Motion`], as keys of `summary.json` `motion` and, with `_s`,
/// columns of `rocks.csv`.
pub const MOTION_NAMES: [&str; 5] = ["flight", "rolling", "sliding_face", "sliding_edge", "slow"];

/// One rock's run: where it started and how it ended (kept when `Layout::rock_ends`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RockRecord {
    /// Global rock number, 0-based, in release order (as [`RockStart::rock_id`]).
    pub rock_id: u64,
    /// Row-major index of the cell the rock was released from.
    pub source_cell: usize,
    /// Release position of the rock centre (x, y, z), m.
    pub start_m: [f64; 3],
    /// The rock's volume, m³.
    pub volume_m3: f64,
    /// The rock's mass, kg.
    pub mass_kg: f64,
    /// How and where the run ended: outcome, end position (m), runout (m), maximum speed
    /// (m/s) and jump height (m), tree impacts, stems broken, rebounds, simulated time (s).
    pub end: RockEnd,
}

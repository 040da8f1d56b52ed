//! The per-worker accumulator.

use std::sync::{Arc, Mutex};

use crate::cells::CellTable;
use crate::hist::{LENGTH_SCALE, LONG_AXIS, SHORT_AXIS, Stat};
use crate::profile::SpeedProfile;
use crate::screens::ScreenStats;
use crate::{
    CellVisit, CrossingRecord, Layout, Outcome, RockEnd, RockRecord, RockStart, ScreenCrossing,
    TrajectoryRow,
};

/// The rock being simulated.
#[derive(Debug, Clone, Copy)]
struct Current {
    rock_id: u64,
    /// `rock_id + 1`: what the per-cell and per-screen "last rock" markers hold.
    key: u64,
    source: u32,
    records: bool,
    /// Rows recorded for this rock so far.
    seq: u64,
    /// Screen crossings kept for this rock so far.
    crossings: u32,
    /// DEM height at the centre of the release cell, m (NaN without a DEM).
    source_z_m: f64,
    /// Where it started (for its [`RockRecord`]).
    start: RockStart,
    /// It visited a cell outside a tile's trusted cells ([`Layout::trusted`]).
    left_tile: bool,
}

/// An event of a tile's rock, kept until the rock ends without leaving the tile's trusted
/// cells ([`Layout::trusted`]) and then tallied in the order it came.
#[derive(Debug, Clone)]
enum Pending {
    Visit(usize, CellVisit),
    Tree(usize, f64, bool),
    Screen(usize, ScreenCrossing),
    Row(TrajectoryRow),
}

/// Per-rock statistics (over ended rocks).
#[derive(Debug, Clone)]
pub(crate) struct RockStats {
    /// Rocks per outcome: stopped, net_stopped, left_dem, time_limit, failed.
    pub(crate) outcomes: [u64; 5],
    /// Runout, m.
    pub(crate) runout: Stat,
    /// Each rock's largest speed, m/s.
    pub(crate) max_velocity: Stat,
    /// Each rock's largest jump height, m.
    pub(crate) max_jump: Stat,
    /// Simulated time, s.
    pub(crate) time: Stat,
    /// Sum of tree impacts.
    pub(crate) tree_impacts: u64,
    /// Sum of stems broken.
    pub(crate) stems_broken: u64,
    /// Sum of ground rebounds.
    pub(crate) rebounds: u64,
    /// Sum of the engine's events (see [`crate::RockEnd::events`]).
    pub(crate) events: u64,
    /// Rocks that came to rest in the cell they were released from (the ground held them).
    pub(crate) held_at_release: u64,
    /// Sum of the rocks' [`crate::Motion`] times, each rounded to whole microseconds (exact
    /// in any order of summation).
    pub(crate) motion_us: [u64; 5],
}

/// Names of the outcomes, in the order of [`RockStats::outcomes`] (see [`Outcome::name`]).
pub(crate) const OUTCOME_NAMES: [&str; 5] =
    ["stopped", "net_stopped", "left_dem", "time_limit", "failed"];

/// Index of an outcome in [`RockStats::outcomes`] and [`OUTCOME_NAMES`].
pub(crate) fn outcome_index(o: &Outcome) -> usize {
    match o {
        Outcome::Stopped { .. } => 0,
        Outcome::NetStopped { .. } => 1,
        Outcome::LeftDem => 2,
        Outcome::TimeLimit => 3,
        Outcome::Failed => 4,
    }
}

impl RockStats {
    fn new() -> RockStats {
        RockStats {
            outcomes: [0; 5],
            runout: Stat::new(&LONG_AXIS, LENGTH_SCALE),
            max_velocity: Stat::new(&SHORT_AXIS, LENGTH_SCALE),
            max_jump: Stat::new(&SHORT_AXIS, LENGTH_SCALE),
            time: Stat::new(&LONG_AXIS, LENGTH_SCALE),
            tree_impacts: 0,
            stems_broken: 0,
            rebounds: 0,
            events: 0,
            held_at_release: 0,
            motion_us: [0; 5],
        }
    }

    fn merge(&mut self, o: &RockStats) {
        for (a, b) in self.outcomes.iter_mut().zip(&o.outcomes) {
            *a += b;
        }
        self.runout.merge(&o.runout);
        self.max_velocity.merge(&o.max_velocity);
        self.max_jump.merge(&o.max_jump);
        self.time.merge(&o.time);
        self.tree_impacts += o.tree_impacts;
        self.stems_broken += o.stems_broken;
        self.rebounds += o.rebounds;
        self.events += o.events;
        self.held_at_release += o.held_at_release;
        for (a, b) in self.motion_us.iter_mut().zip(&o.motion_us) {
            *a += b;
        }
    }

    /// Rocks ended.
    pub(crate) fn rocks(&self) -> u64 {
        self.outcomes.iter().sum()
    }
}

/// Energy-line angle of a visit, degrees: the angle above the horizontal of the straight line
/// from the DEM surface at the centre of the rock's release cell (height `source_z_m`, m) to
/// the DEM surface at the centre of the visited cell (`cell_z_m`, m), `distance_m` (m)
/// apart in plan view — the "Fahrböschung" or energy-line angle of Heim (1932) and of the
/// cone method (Jaboyedoff & Labiouse 2011), which Rockyfor3D's `EL_angles` maps. `None`
/// within half a cell of the release point (the angle of a rock that has not left its cell
/// says nothing), without a DEM or at nodata.
fn energy_line_angle_deg(
    source_z_m: f64,
    cell_z_m: Option<f64>,
    distance_m: f64,
    cell_size_m: f64,
) -> Option<f64> {
    let drop_m = source_z_m - cell_z_m?;
    (drop_m.is_finite() && distance_m >= 0.5 * cell_size_m)
        .then(|| drop_m.atan2(distance_m).to_degrees())
}

/// What one worker thread accumulates: bounded-memory statistics of the rocks it simulated
/// (per cell, per screen, per rock), the recorded trajectory rows and, when
/// [`Layout::rock_ends`], one [`RockRecord`] per rock.
///
/// Use: for each rock, [`Tally::begin_rock`], then any number of [`Tally::cell_visit`],
/// [`Tally::tree_impact`], [`Tally::screen_crossing`] and [`Tally::record`], then
/// [`Tally::end_rock`]. Events outside `begin_rock … end_rock` are ignored (and assert in
/// debug builds); cell and screen indices out of range are ignored. A rock must be simulated
/// entirely by one tally. When all rocks are done, [`Tally::merge`] the tallies in any order:
/// the result is bit-identical.
///
/// Memory: per touched cell the statistics described in the crate documentation (≈ 0.35–0.5 kB
/// per visited cell) and 1 KiB per touched block of 16 × 16 cells, ≈ 0.016 byte per grid
/// cell, plus the recorded rows; nothing per rock unless [`Layout::rock_ends`], which keeps
/// one [`RockRecord`] per rock.
#[derive(Debug, Clone)]
pub struct Tally {
    layout: Arc<Layout>,
    current: Option<Current>,
    pub(crate) cells: CellTable,
    pub(crate) screens: Vec<ScreenStats>,
    pub(crate) rock: RockStats,
    /// Speeds of the cell visits by distance from release.
    pub(crate) profile: SpeedProfile,
    /// (rock id, sequence number within the rock, row) of recorded rocks.
    pub(crate) rows: Vec<(u64, u64, TrajectoryRow)>,
    /// One record per ended rock, in the order they ended (only when `layout.rock_ends`).
    pub(crate) rock_records: Vec<RockRecord>,
    /// One record per screen crossing (only when `layout.screen_crossings`).
    pub(crate) crossing_records: Vec<CrossingRecord>,
    /// A tile's current rock's events, until it ends (see [`Layout::trusted`]).
    pending: Vec<Pending>,
    /// True while the pending events are tallied.
    replaying: bool,
    /// The rocks that left a tile's trusted cells, in the order they ended.
    left_tile: Vec<u64>,
}

impl Tally {
    /// An empty tally for a run on `layout`.
    pub fn new(layout: Arc<Layout>) -> Tally {
        Tally {
            cells: CellTable::new(
                &layout.geometry,
                crate::cells::Thresholds::of_kj(&layout.energy_thresholds_kj),
            ),
            screens: layout.screens.iter().map(ScreenStats::new).collect(),
            rock: RockStats::new(),
            profile: SpeedProfile::new(&layout),
            current: None,
            rows: Vec::new(),
            rock_records: Vec::new(),
            crossing_records: Vec::new(),
            pending: Vec::new(),
            replaying: false,
            left_tile: Vec::new(),
            layout,
        }
    }

    /// True when the current event is to be kept until the rock ends (a tile's rock), and
    /// not yet tallied. Marks nothing.
    fn defers(&self) -> bool {
        self.layout.trusted.0.is_some() && !self.replaying
    }

    /// Keeps an event of a tile's rock until it ends; nothing once the rock has left.
    fn defer(&mut self, event: Pending) {
        if self.current.is_some_and(|c| !c.left_tile) {
            self.pending.push(event);
        }
    }

    /// The rocks that left a tile's trusted cells ([`Layout::trusted`]): nothing of them is
    /// in the tally, nor counted in [`Tally::rocks`]; a run on a wider halo simulates them.
    pub fn left_tile(&self) -> &[u64] {
        &self.left_tile
    }

    /// Takes the list of [`Tally::left_tile`], leaving it empty.
    pub fn take_left_tile(&mut self) -> Vec<u64> {
        std::mem::take(&mut self.left_tile)
    }

    /// The layout this tally was made for.
    pub fn layout(&self) -> &Arc<Layout> {
        &self.layout
    }

    /// A rock leaves its release position; the events that follow belong to it.
    pub fn begin_rock(&mut self, start: RockStart) {
        debug_assert!(self.current.is_none(), "begin_rock before end_rock");
        self.current = Some(Current {
            rock_id: start.rock_id,
            key: start.rock_id.wrapping_add(1),
            source: u32::try_from(start.source_cell).unwrap_or(u32::MAX),
            records: start.rock_id < self.layout.trajectories,
            seq: 0,
            crossings: 0,
            source_z_m: self
                .layout
                .elevation
                .at(start.source_cell)
                .unwrap_or(f64::NAN),
            start,
            left_tile: false,
        });
        self.pending.clear();
    }

    fn active(&self) -> Option<Current> {
        debug_assert!(
            self.current.is_some(),
            "event outside begin_rock … end_rock"
        );
        self.current
    }

    /// True when the current rock's trajectory is recorded (`rock_id < layout.trajectories`).
    pub fn records(&self) -> bool {
        self.current.is_some_and(|c| c.records)
    }

    /// Records one trajectory state of the current rock; a no-op unless [`Tally::records`].
    pub fn record(&mut self, row: TrajectoryRow) {
        if self.defers() {
            if self.records() {
                self.defer(Pending::Row(row));
            }
            return;
        }
        if let Some(c) = self.current.as_mut().filter(|c| c.records) {
            self.rows.push((c.rock_id, c.seq, row));
            c.seq += 1;
        }
    }

    /// The current rock visited `cell` (row-major index); `visit` holds its maxima while
    /// there. Report every cell the rock is in, the release and the final cell included.
    pub fn cell_visit(&mut self, cell: usize, visit: CellVisit) {
        if let (Some(trusted), false) = (self.layout.trusted.0, self.replaying) {
            let (row, col) = self.layout.geometry.row_col(cell);
            match trusted.contains(row, col) {
                true => self.defer(Pending::Visit(cell, visit)),
                false => {
                    if let Some(c) = self.current.as_mut() {
                        c.left_tile = true;
                    }
                }
            }
            return;
        }
        if let Some(c) = self.active() {
            let g = &self.layout.geometry;
            let (row, col) = g.row_col(cell);
            let (x, y) = g.cell_center(row, col);
            let (dx, dy) = (x - c.start.x_m, y - c.start.y_m);
            let distance_m = (dx * dx + dy * dy).sqrt();
            let angle = energy_line_angle_deg(
                c.source_z_m,
                self.layout.elevation.at(cell),
                distance_m,
                g.cell_size_m,
            );
            self.cells.visit(cell, c.key, c.source, &visit, angle);
            self.profile.add(distance_m, visit.velocity_ms);
        }
    }

    /// The current rock hit a tree standing in `cell` at `impact_height_m` above the ground
    /// (m); `stem_broken` when the stem broke.
    pub fn tree_impact(&mut self, cell: usize, impact_height_m: f64, stem_broken: bool) {
        if self.defers() {
            return self.defer(Pending::Tree(cell, impact_height_m, stem_broken));
        }
        if self.active().is_some() {
            self.cells.tree_impact(cell, impact_height_m, stem_broken);
        }
    }

    /// The current rock crossed screen number `screen` (index in `layout.screens`).
    pub fn screen_crossing(&mut self, screen: usize, crossing: ScreenCrossing) {
        if self.defers() {
            return self.defer(Pending::Screen(screen, crossing));
        }
        if let Some(c) = self.active()
            && let Some(s) = self.screens.get_mut(screen)
        {
            s.add(c.key, &crossing);
            if self.layout.screen_crossings {
                self.crossing_records.push(CrossingRecord {
                    rock_id: c.rock_id,
                    screen,
                    seq: c.crossings,
                    crossing,
                    mass_kg: c.start.mass_kg,
                });
                if let Some(cur) = self.current.as_mut() {
                    cur.crossings += 1;
                }
            }
        }
    }

    /// The current rock's run is over. With [`Layout::rock_ends`], its [`RockRecord`] is
    /// kept (release position from [`Tally::begin_rock`], `end` as given).
    pub fn end_rock(&mut self, end: RockEnd) {
        debug_assert!(self.current.is_some(), "end_rock without begin_rock");
        if self.layout.trusted.0.is_some() && !self.tally_pending() {
            return;
        }
        let current = self.current.take();
        if let (Some(c), Outcome::Stopped { cell }) = (&current, end.outcome)
            && c.start.source_cell == cell
        {
            self.rock.held_at_release += 1;
        }
        if let Some(c) = current
            && self.layout.rock_ends
        {
            let s = c.start;
            self.rock_records.push(RockRecord {
                rock_id: s.rock_id,
                source_cell: s.source_cell,
                start_m: [s.x_m, s.y_m, s.z_m],
                volume_m3: s.volume_m3,
                mass_kg: s.mass_kg,
                end,
            });
        }
        if let Outcome::Stopped { cell } | Outcome::NetStopped { cell } = end.outcome {
            self.cells.deposit(cell);
        }
        let r = &mut self.rock;
        r.outcomes[outcome_index(&end.outcome)] += 1;
        r.runout.add(end.runout_m);
        r.max_velocity.add(end.max_velocity_ms);
        r.max_jump.add(end.max_jump_height_m);
        r.time.add(end.time_s);
        r.tree_impacts += u64::from(end.tree_impacts);
        r.stems_broken += u64::from(end.stems_broken);
        r.rebounds += u64::from(end.rebounds);
        r.events += u64::from(end.events);
        for (a, t) in r.motion_us.iter_mut().zip(end.motion.as_array()) {
            *a += (t * 1e6).round() as u64;
        }
    }

    /// A tile's rock ends: its kept events are tallied, in the order they came, when it never
    /// left the tile's trusted cells (true); else they are dropped and the rock is listed in
    /// [`Tally::left_tile`] (false).
    fn tally_pending(&mut self) -> bool {
        let Some(c) = self.current else {
            return false;
        };
        let pending = std::mem::take(&mut self.pending);
        if c.left_tile {
            self.left_tile.push(c.rock_id);
            self.current = None;
            return false;
        }
        self.replaying = true;
        for event in &pending {
            match *event {
                Pending::Visit(cell, visit) => self.cell_visit(cell, visit),
                Pending::Tree(cell, h, broken) => self.tree_impact(cell, h, broken),
                Pending::Screen(k, crossing) => self.screen_crossing(k, crossing),
                Pending::Row(row) => self.record(row),
            }
        }
        self.replaying = false;
        // the buffer keeps its capacity for the next rock
        self.pending = pending;
        self.pending.clear();
        true
    }

    /// Adds everything `other` (a tally of the same layout, with no rock in progress)
    /// accumulated. Exact: any merge order gives bit-identical results.
    pub fn merge(&mut self, other: Tally) {
        self.cells.merge(other.cells);
        for (a, b) in self.screens.iter_mut().zip(&other.screens) {
            a.merge(b);
        }
        self.rock.merge(&other.rock);
        self.profile.merge(&other.profile);
        self.rows.extend(other.rows);
        self.rock_records.extend(other.rock_records);
        self.crossing_records.extend(other.crossing_records);
        self.left_tile.extend(other.left_tile);
    }

    /// Rocks ended so far.
    pub fn rocks(&self) -> u64 {
        self.rock.rocks()
    }

    /// An empty table of per-cell statistics that the workers of one run share (see
    /// [`Tally::flush_cells`]).
    pub fn shared_cells(&self) -> SharedCells {
        SharedCells(Mutex::new(CellTable::new(
            &self.layout.geometry,
            self.cells.thresholds(),
        )))
    }

    /// Moves this tally's per-cell statistics into `shared` (exactly: they add up as
    /// [`Tally::merge`] adds them) when they cover at least `min_cells` cells; call it between
    /// rocks. Workers that flush every so often hold only the cells of their last rocks, so a
    /// run's per-cell memory is one table, not one per worker thread.
    pub fn flush_cells(&mut self, shared: &SharedCells, min_cells: usize) {
        debug_assert!(self.current.is_none(), "flush_cells during a rock");
        if self.cells.len() >= min_cells.max(1) {
            let mut table = shared.0.lock().unwrap_or_else(|p| p.into_inner());
            self.cells.drain_into(&mut table);
        }
    }

    /// Adds the per-cell statistics gathered in `shared` to this tally's.
    pub fn absorb_cells(&mut self, shared: SharedCells) {
        let table = shared.0.into_inner().unwrap_or_else(|p| p.into_inner());
        if self.cells.len() == 0 {
            // the shared table is the whole: take it rather than copy it
            self.cells = table;
        } else {
            self.cells.merge(table);
        }
    }

    /// Bytes held by the per-cell statistics (see the crate's memory notes) and the number
    /// of cells they cover.
    pub fn cell_memory(&self) -> (usize, usize) {
        (self.cells.heap_bytes(), self.cells.len())
    }

    /// Cells reached (visited) whose row-major index `keep` accepts (e.g. those of a tile's
    /// core), as `summary.json`'s `cells_reached` counts them.
    pub fn cells_reached_where(&self, keep: impl Fn(usize) -> bool) -> usize {
        (self.cells.touched())
            .filter(|c| c.visits > 0 && keep(c.cell))
            .count()
    }
}

/// Per-cell statistics shared by the workers of one run: each worker moves its own into it
/// every so often ([`Tally::flush_cells`]) and the run's tally takes them at the end
/// ([`Tally::absorb_cells`]). Exact in any order of flushing.
#[derive(Debug)]
pub struct SharedCells(Mutex<CellTable>);

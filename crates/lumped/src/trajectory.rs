//! One rock from release to rest: an event-driven state machine over exact flight arcs and
//! rolling steps. Every arc or step is a [`Seg`] whose horizontal path is straight.
//!
//! The physics and the reporting live apart:
//! - [`crate::contact`]: flight, ground rebound, rolling and stopping;
//! - [`crate::obstacles`]: stems and nets met on a segment;
//! - [`crate::recorder`]: what a rock reports — the cells it crosses, screens, trajectory rows.

use crate::V3;
use crate::body::RockBody;
use crate::forestry::Trees;
use crate::ground::Ground;
use crate::memo::PointMemo;
use crate::segment::Seg;
use crate::vec3::V3Ext;
use rockfall_results::{CellVisit, Event, Outcome, RockEnd, RockStart, ScreenSet, Tally};
use rockfall_rng::Rng;
use rockfall_scenario::{LumpedSettings, StartHeight};

/// A rock still moving after this many events is given up as [`Outcome::Failed`] (a guard
/// against a defect, never reached on the built-in sites).
pub const MAX_EVENTS: u32 = 200_000;

/// Everything a rock moves through, shared read-only by all rocks.
pub struct World<'a> {
    /// Terrain, surface and nets.
    pub ground: &'a Ground,
    /// Stems, if any.
    pub trees: Option<&'a Trees<'a>>,
    /// Evaluation screens.
    pub screens: &'a ScreenSet,
    /// Engine settings.
    pub settings: &'a LumpedSettings,
    /// Largest simulated time per rock, s.
    pub max_time_s: f64,
}

/// A rock at release.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Launch {
    /// Global rock number.
    pub rock_id: u64,
    /// Row-major index of the release cell.
    pub source_cell: usize,
    /// Centre position, m.
    pub p: V3,
    /// Velocity, m/s.
    pub v: V3,
    /// Angular velocity (world frame), rad/s.
    pub w: V3,
    /// The rock.
    pub body: RockBody,
    /// The ground's elevation under the release position, m.
    pub ground_z_m: f64,
    /// How the release set the centre's height (what a rock of another volume keeps).
    pub start: StartHeight,
}

/// Reusable per-worker buffers.
#[derive(Debug, Default)]
pub struct Scratch {
    pub(crate) crossings: Vec<(usize, f64)>,
}

/// The state of the rock being simulated.
pub(crate) struct Rock<'w, 'a, 't> {
    pub(crate) world: &'w World<'a>,
    pub(crate) tally: &'t mut Tally,
    pub(crate) scratch: &'t mut Scratch,
    pub(crate) rng: &'t mut Rng,
    pub(crate) body: RockBody,
    pub(crate) rock_id: u64,
    pub(crate) recording: bool,
    pub(crate) start: V3,
    /// Centre position, m.
    pub(crate) p: V3,
    /// Velocity, m/s.
    pub(crate) v: V3,
    /// Angular velocity, rad/s.
    pub(crate) w: V3,
    /// Time since release, s.
    pub(crate) t: f64,
    pub(crate) rolling: bool,
    pub(crate) moved: bool,
    /// Whether the rock has touched the ground since its release: its rebound heights count
    /// from then on, not the drop from the release height.
    pub(crate) grounded: bool,
    /// The next rolling step may not take off (the last take-off landed at once).
    pub(crate) hold_ground: bool,
    pub(crate) visit: Option<(usize, CellVisit)>,
    pub(crate) last_rebound_cell: Option<usize>,
    pub(crate) last_stem: Option<usize>,
    /// The net whose cells the rock is in (see `Rock::net_entry`).
    pub(crate) net_passage: rockfall_engine::nets::NetPassage,
    pub(crate) max_v: f64,
    pub(crate) max_h: f64,
    pub(crate) impacts: u32,
    pub(crate) broken: u32,
    pub(crate) rebounds: u32,
    /// The ground at the last point asked about (rolling steps ask several times).
    pub(crate) memo: PointMemo,
}

/// Simulates one rock and reports it to `tally`.
pub fn simulate(
    world: &World<'_>,
    launch: &Launch,
    rng: &mut Rng,
    tally: &mut Tally,
    scratch: &mut Scratch,
) {
    tally.begin_rock(RockStart {
        rock_id: launch.rock_id,
        source_cell: launch.source_cell,
        x_m: launch.p.x,
        y_m: launch.p.y,
        z_m: launch.p.z,
        volume_m3: launch.body.volume_m3,
        mass_kg: launch.body.mass_kg,
    });
    let recording = tally.records();
    let mut rock = Rock {
        world,
        tally,
        scratch,
        rng,
        body: launch.body,
        rock_id: launch.rock_id,
        recording,
        start: launch.p,
        p: launch.p,
        v: launch.v,
        w: launch.w,
        t: 0.0,
        rolling: false,
        moved: false,
        grounded: false,
        hold_ground: false,
        visit: None,
        last_rebound_cell: None,
        last_stem: None,
        net_passage: rockfall_engine::nets::NetPassage::default(),
        max_v: 0.0,
        max_h: 0.0,
        impacts: 0,
        broken: 0,
        rebounds: 0,
        memo: PointMemo::default(),
    };
    rock.run();
}

impl Rock<'_, '_, '_> {
    fn run(&mut self) {
        self.settle_at_release();
        self.record(Event::Flight);
        let mut events = 0u32;
        let mut segments = 0u32;
        let outcome = loop {
            events += 1;
            if events > MAX_EVENTS || !(self.p.is_finite() && self.v.is_finite()) {
                break Outcome::Failed;
            }
            let remaining = self.world.max_time_s - self.t;
            if remaining <= 0.0 {
                break Outcome::TimeLimit;
            }
            segments += 1;
            let step = if self.rolling {
                self.roll()
            } else {
                self.fly(remaining)
            };
            if let Some(outcome) = step {
                break outcome;
            }
        };
        self.finish(outcome, segments);
    }

    /// Kinetic energy (translational at `v` plus the current rotation), J.
    pub(crate) fn energy_j(&self, v: V3) -> f64 {
        self.body.translational_energy_j(v) + self.body.rotational_energy_j(self.w)
    }

    pub(crate) fn current_cell(&self) -> Option<usize> {
        self.world.ground.cell_index(self.p.x, self.p.y)
    }

    /// Ends the rock with `outcome` after `events` segments (flight arcs, rolling steps).
    fn finish(&mut self, outcome: Outcome, events: u32) {
        self.flush_visit();
        if matches!(
            outcome,
            Outcome::Stopped { .. } | Outcome::NetStopped { .. }
        ) {
            self.v = V3::ZERO;
            self.w = V3::ZERO;
        }
        self.record(Event::Stop);
        let runout = (self.p.x - self.start.x).hypot(self.p.y - self.start.y);
        self.tally.end_rock(RockEnd {
            outcome,
            x_m: self.p.x,
            y_m: self.p.y,
            runout_m: runout,
            max_velocity_ms: self.max_v,
            max_jump_height_m: self.max_h,
            tree_impacts: self.impacts,
            stems_broken: self.broken,
            rebounds: self.rebounds,
            time_s: self.t,
            events,
            motion: Default::default(),
        });
    }

    /// Follows `seg` for its first `dur` s (or less, when a stem or a net cuts it): the
    /// cells, screens and trajectory rows it crosses are reported, and the rock moves to its
    /// end. Returns the time covered and what cut it.
    pub(crate) fn advance(&mut self, seg: &Seg, dur: f64) -> (f64, crate::segment::Cut) {
        let (tau, cut) = self.traverse(seg, dur);
        if matches!(seg, Seg::Flight { .. }) {
            self.record_arc(seg, tau);
        }
        self.p = seg.pos(tau);
        self.v = seg.vel(tau);
        self.t += tau;
        (tau, cut)
    }
}

/// Horizontal unit direction of `v`, `None` when it is (nearly) vertical.
#[inline]
pub(crate) fn horizontal_unit(v: V3) -> Option<(f64, f64)> {
    let h = v.horizontal_norm();
    (h > 1e-9).then(|| (v.x / h, v.y / h))
}

/// Angular velocity of rolling without slip with velocity `v` on ground of normal `n`.
#[inline]
pub(crate) fn rolling_spin(v: V3, n: V3, radius_m: f64) -> V3 {
    n.cross(v) * (1.0 / radius_m)
}

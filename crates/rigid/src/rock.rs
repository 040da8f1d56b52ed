//! One rock's run: release, time steps until it rests, leaves the DEM or runs out of time,
//! and what it reports to the tally on the way.
//!
//! **Release.** Orientation and height as [`crate::release`] sets them.
//!
//! **Rest.** A rock touching the ground whose centre moves slower than the stop speed and
//! whose hull points move slower than it by rotation (|ω|·circumradius) for the rest time in
//! a row has come to rest ([`StopRule`]).
//!
//! **Failure.** A non-finite state or a speed above [`StopRule::max_speed_ms`] ends the rock as
//! `Failed`; the run goes on.
//!
//! **What is reported.** Cell visits with their maxima of energy (translational +
//! rotational), speed and passing height (vertical height of the centre of mass above the
//! ground); screen crossings of the centre's path; a tree impact when a contact with a stem
//! begins (stems do not break: seed 001's stems are rigid); a rebound when a ground contact
//! begins after a step without one (on the scarring ground: when the rock enters the soft
//! layer); every time step of recorded trajectories.
//!
//! **Nets** act as the lumped engine's do ([`crate::nets`]).

use crate::ground::{Ground, Under};
use crate::math::{Quat, V3};
use crate::nets::NetTrack;
use crate::rotation::rotational_energy_j;
use crate::shape::RockBody;
use crate::stems::Stand;
use crate::step::{RockState, StepParams, StepReport, StepScratch, step};
use rockfall_engine::nets::NetMap;
use rockfall_results::{
    CellVisit, Event, Motion, Outcome, RockEnd, RockStart, ScreenCrossing, ScreenSet, Tally,
    TrajectoryRow,
};
use rockfall_rng::Rng;
use rockfall_scenario::StartHeight;

pub use crate::release::{random_orientation, release_centre_z_m};

/// When a rock is at rest, and when it has failed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StopRule {
    /// Stop speed, m/s (default 0.05): centre speed and |ω|·circumradius below it …
    pub stop_speed_ms: f64,
    /// … for this long in a row while touching the ground, s (default 0.5).
    pub rest_time_s: f64,
    /// A speed above this is a numerical failure, m/s (default 500).
    pub max_speed_ms: f64,
}

impl Default for StopRule {
    fn default() -> Self {
        StopRule {
            stop_speed_ms: 0.05,
            rest_time_s: 0.5,
            max_speed_ms: 500.0,
        }
    }
}

/// What every rock of a run shares.
pub struct World<'a> {
    /// The terrain.
    pub ground: &'a Ground,
    /// The trees, if any.
    pub stand: Option<&'a Stand<'a>>,
    /// Evaluation screens.
    pub screens: &'a ScreenSet,
    /// The nets' cells (empty without nets).
    pub nets: &'a NetMap,
    /// Step parameters.
    pub step: StepParams<'a>,
    /// Rest and failure.
    pub stop: StopRule,
    /// Longest simulated time, s.
    pub max_time_s: f64,
    /// Shortest time between two recorded trajectory rows, s (0: every step; the final row
    /// is always recorded).
    pub record_interval_s: f64,
}

/// One rock's start.
#[derive(Debug, Clone, Copy)]
pub struct Launch {
    /// Global rock number.
    pub rock_id: u64,
    /// Row-major index of the cell released from.
    pub source_cell: usize,
    /// Release point (x, y), m.
    pub xy_m: [f64; 2],
    /// How high the rock starts: a gap between the ground under its centre and its lowest
    /// hull vertex, or its centre's elevation.
    pub start: StartHeight,
    /// Initial velocity, m/s.
    pub velocity_ms: V3,
    /// Initial angular velocity, world frame, rad/s.
    pub angular_velocity_rads: V3,
    /// Orientation; `None` for a random one.
    pub orientation: Option<Quat>,
}

/// Per-rock bookkeeping.
struct Log<'t> {
    tally: &'t mut Tally,
    rock_id: u64,
    recording: bool,
    next_record_s: f64,
    visit: Option<(usize, CellVisit)>,
    max_v: f64,
    max_h: f64,
    impacts: u32,
    rebounds: u32,
    touching_ground: bool,
    /// Steps in each mode of motion, in the order of [`Motion::as_array`].
    motion_steps: [u32; 5],
    /// The centre's passage through the nets' cells.
    nets: NetTrack,
}

impl Log<'_> {
    fn observe(&mut self, cell: Option<usize>, e: f64, speed: f64, h: f64) {
        self.max_v = self.max_v.max(speed);
        self.max_h = self.max_h.max(h);
        match (&mut self.visit, cell) {
            (Some((c, v)), Some(cell)) if *c == cell => {
                v.energy_j = v.energy_j.max(e);
                v.velocity_ms = v.velocity_ms.max(speed);
                v.passing_height_m = v.passing_height_m.max(h);
            }
            _ => {
                self.flush();
                self.visit = cell.map(|c| {
                    (
                        c,
                        CellVisit {
                            energy_j: e,
                            velocity_ms: speed,
                            passing_height_m: h,
                        },
                    )
                });
            }
        }
    }

    fn flush(&mut self) {
        if let Some((cell, visit)) = self.visit.take() {
            self.tally.cell_visit(cell, visit);
        }
    }
}

/// Time off a stem after which touching it again is a new impact, s.
pub const IMPACT_SEPARATION_S: f64 = 0.05;

/// Simulates one rock into `tally`.
pub fn simulate(
    world: &World<'_>,
    body: &RockBody,
    launch: &Launch,
    rng: &mut Rng,
    tally: &mut Tally,
    scratch: &mut StepScratch,
) {
    let q = launch
        .orientation
        .unwrap_or_else(|| random_orientation(rng));
    let ground = world.ground;
    let z = release_centre_z_m(ground, body, q, launch.xy_m, launch.start);
    let start = V3::new(launch.xy_m[0], launch.xy_m[1], z.unwrap_or(f64::NAN));
    tally.begin_rock(RockStart {
        rock_id: launch.rock_id,
        source_cell: launch.source_cell,
        x_m: start.x,
        y_m: start.y,
        z_m: start.z,
        volume_m3: body.geometry.volume_m3,
        mass_kg: body.mass_kg,
    });
    let mut state = RockState {
        r_m: start,
        q,
        v_ms: launch.velocity_ms,
        w_body_rads: q.inverse() * launch.angular_velocity_rads,
    };
    scratch.reset();
    let recording = tally.records();
    let mut log = Log {
        tally,
        rock_id: launch.rock_id,
        recording,
        next_record_s: 0.0,
        visit: None,
        max_v: 0.0,
        max_h: 0.0,
        impacts: 0,
        rebounds: 0,
        touching_ground: false,
        motion_steps: [0; 5],
        nets: NetTrack::default(),
    };
    let (outcome, time_s) = if z.is_none() {
        (Outcome::Failed, 0.0)
    } else {
        run(world, body, &mut state, &mut log, scratch)
    };
    finish(world, body, &state, start, outcome, time_s, log);
}

/// Steps until the rock ends; returns how and the simulated time.
fn run(
    world: &World<'_>,
    body: &RockBody,
    state: &mut RockState,
    log: &mut Log<'_>,
    scratch: &mut StepScratch,
) -> (Outcome, f64) {
    let dt = world.step.dt_s;
    let steps = (world.max_time_s / dt).ceil() as u64;
    let lattice = world.ground.lattice();
    let mut rest_s = 0.0;
    let mut touching: Vec<(usize, f64)> = Vec::new();
    let ground_z = lattice.height_m(state.r_m.x, state.r_m.y);
    observe(world, body, state, log, 0.0, Event::Flight, ground_z);
    for k in 1..=steps {
        let t = k as f64 * dt;
        let before = state.r_m;
        let report = step(state, &world.step, world.ground, world.stand, scratch);
        if !state.is_finite() || state.v_ms.length() > world.stop.max_speed_ms {
            return (Outcome::Failed, t);
        }
        let Under::Surface(surface) = world.ground.under(state.r_m.x, state.r_m.y) else {
            return (Outcome::LeftDem, t);
        };
        // on the scarring ground the rock touches the ground while it is in the layer
        let on_ground = report.ground_contacts.max(report.soil_contacts);
        let mut event = if on_ground > 0 {
            Event::Roll
        } else {
            Event::Flight
        };
        if on_ground > 0 && !log.touching_ground {
            log.rebounds += 1;
            event = Event::Impact;
        }
        log.touching_ground = on_ground > 0;
        let mode = motion_mode(
            world.stop.stop_speed_ms,
            state.v_ms.length(),
            on_ground,
            report.slip_ms,
        );
        log.motion_steps[mode] += 1;
        if tree_impacts(world, scratch, t, &mut touching, log) {
            event = Event::Tree;
        }
        screens(world, body, before, state, log);
        if let Some(cell) = (log.nets).meet(world, body, state, surface.z_m, log.tally) {
            return (Outcome::NetStopped { cell }, t);
        }
        if at_rest(world, body, state, &report, &mut rest_s) {
            let cell = lattice.cell_index(state.r_m.x, state.r_m.y);
            return (
                cell.map_or(Outcome::LeftDem, |cell| Outcome::Stopped { cell }),
                t,
            );
        }
        if k == steps {
            break;
        }
        observe(world, body, state, log, t, event, Some(surface.z_m));
    }
    (Outcome::TimeLimit, steps as f64 * dt)
}

/// The mode of motion of a step, as an index into [`Motion::as_array`] (the rule is
/// [`Motion`]'s): flight, rolling, sliding on a face, sliding on an edge, slow; from the stop
/// speed and the centre's speed (m/s), the ground contacts and their mean slip (m/s).
fn motion_mode(stop_speed_ms: f64, speed_ms: f64, ground_contacts: usize, slip_ms: f64) -> usize {
    if ground_contacts == 0 {
        0
    } else if speed_ms < stop_speed_ms {
        4
    } else if slip_ms < ROLLING_SLIP_SHARE * speed_ms {
        1
    } else if ground_contacts >= 3 {
        2
    } else {
        3
    }
}

/// A step in ground contact is rolling when its contact points slip slower than this share
/// of the centre's speed (ours; see [`Motion`]).
pub const ROLLING_SLIP_SHARE: f64 = 0.5;

/// Counts the time the rock has been at rest; `true` once it has been for the rest time.
fn at_rest(
    world: &World<'_>,
    body: &RockBody,
    state: &RockState,
    report: &StepReport,
    rest_s: &mut f64,
) -> bool {
    let slow = world.stop.stop_speed_ms;
    if report.ground_contacts > 0
        && state.v_ms.length() < slow
        && state.w_body_rads.length() * body.geometry.circumradius_m < slow
    {
        *rest_s += world.step.dt_s;
        *rest_s >= world.stop.rest_time_s - 0.5 * world.step.dt_s
    } else {
        *rest_s = 0.0;
        false
    }
}

/// Reports the stems whose contact began in this step; `true` if there was one.
///
/// One impact runs from first touch until the rock has been off the stem for
/// [`IMPACT_SEPARATION_S`]: a rock grazing a stem flickers in and out of contact at the
/// scale of the time step, and that is still one impact.
fn tree_impacts(
    world: &World<'_>,
    scratch: &StepScratch,
    t_s: f64,
    touching: &mut Vec<(usize, f64)>,
    log: &mut Log<'_>,
) -> bool {
    let Some(stand) = world.stand else {
        return false;
    };
    let mut new = false;
    for c in scratch.stem_contacts() {
        if let Some(entry) = touching.iter_mut().find(|(k, _)| *k == c.stem) {
            entry.1 = t_s;
            continue;
        }
        touching.push((c.stem, t_s));
        new = true;
        log.impacts += 1;
        let base = stand.cone(c.stem).base_m;
        if let Some(cell) = world.ground.lattice().cell_index(base.x, base.y) {
            log.tally.tree_impact(cell, c.height_m.max(0.0), false);
        }
    }
    touching.retain(|(_, last)| t_s - last < IMPACT_SEPARATION_S);
    new
}

/// Kinetic energies (translational, rotational) of `state`, J.
pub(crate) fn energies_j(body: &RockBody, state: &RockState) -> (f64, f64) {
    (
        0.5 * body.mass_kg * state.v_ms.length_squared(),
        rotational_energy_j(state.w_body_rads, body.inertia_kgm2),
    )
}

/// Reports the crossings of the centre's path from `before` to the current position.
fn screens(world: &World<'_>, body: &RockBody, before: V3, state: &RockState, log: &mut Log<'_>) {
    if world.screens.is_empty() {
        return;
    }
    let after = state.r_m;
    let (e_t, e_r) = energies_j(body, state);
    let lattice = world.ground.lattice();
    let tally = &mut *log.tally;
    world
        .screens
        .for_each_crossing([before.x, before.y], [after.x, after.y], |k, s| {
            let p = before + s * (after - before);
            let zg = lattice.height_m(p.x, p.y).unwrap_or(p.z);
            tally.screen_crossing(
                k,
                ScreenCrossing {
                    velocity_ms: state.v_ms.length(),
                    energy_j: e_t + e_r,
                    jump_height_m: p.z - zg,
                    x_m: p.x,
                    y_m: p.y,
                },
            );
        });
}

/// Updates the maxima and the cell visit, and records a trajectory row; `ground_z_m` is the
/// ground height under the centre of mass (`None` off the DEM).
fn observe(
    world: &World<'_>,
    body: &RockBody,
    state: &RockState,
    log: &mut Log<'_>,
    t_s: f64,
    event: Event,
    ground_z_m: Option<f64>,
) {
    let lattice = world.ground.lattice();
    let r = state.r_m;
    let h = ground_z_m.map_or(0.0, |z| r.z - z);
    let (e_t, e_r) = energies_j(body, state);
    let speed = state.v_ms.length();
    log.observe(lattice.cell_index(r.x, r.y), e_t + e_r, speed, h);
    // rows fall due every `record_interval_s`, to within half a step
    let due = t_s + 0.5 * world.step.dt_s >= log.next_record_s;
    if log.recording && (due || event == Event::Stop) {
        log.next_record_s = t_s + world.record_interval_s;
        let w = state.w_world_rads();
        log.tally.record(TrajectoryRow {
            rock_id: log.rock_id,
            t_s,
            x_m: r.x,
            y_m: r.y,
            z_m: r.z,
            vx_ms: state.v_ms.x,
            vy_ms: state.v_ms.y,
            vz_ms: state.v_ms.z,
            wx_rads: w.x,
            wy_rads: w.y,
            wz_rads: w.z,
            e_trans_j: e_t,
            e_rot_j: e_r,
            event,
        });
    }
}

/// Ends the rock: the last cell visit, the final row and the rock's summary.
fn finish(
    world: &World<'_>,
    body: &RockBody,
    state: &RockState,
    start: V3,
    outcome: Outcome,
    time_s: f64,
    mut log: Log<'_>,
) {
    if outcome != Outcome::Failed && state.is_finite() {
        let ground_z = world.ground.lattice().height_m(state.r_m.x, state.r_m.y);
        observe(world, body, state, &mut log, time_s, Event::Stop, ground_z);
    }
    log.flush();
    let end = if state.is_finite() { state.r_m } else { start };
    log.tally.end_rock(RockEnd {
        outcome,
        x_m: end.x,
        y_m: end.y,
        runout_m: (end.x - start.x).hypot(end.y - start.y),
        max_velocity_ms: log.max_v,
        max_jump_height_m: log.max_h,
        tree_impacts: log.impacts,
        stems_broken: 0,
        rebounds: log.rebounds,
        time_s,
        // the steps taken: the time is a whole number of them
        events: (time_s / world.step.dt_s).round() as u32,
        motion: Motion::from_array(log.motion_steps.map(|n| f64::from(n) * world.step.dt_s)),
    });
}

#[cfg(test)]
mod tests {
    use super::motion_mode;

    /// The rule of `Motion`, case by case and at its edges: no contact is flight whatever the
    /// speed; contact below the stop speed is slow; slip under half the speed rolls; else
    /// three or more contacts slide on a face, one or two on an edge.
    #[test]
    fn each_step_gets_the_mode_of_the_rule() {
        let stop = 0.05;
        assert_eq!(motion_mode(stop, 10.0, 0, 0.0), 0);
        assert_eq!(motion_mode(stop, 0.0, 0, 0.0), 0);
        assert_eq!(motion_mode(stop, 0.04, 3, 0.04), 4);
        assert_eq!(motion_mode(stop, 10.0, 2, 4.99), 1);
        assert_eq!(motion_mode(stop, 10.0, 4, 4.99), 1);
        assert_eq!(motion_mode(stop, 10.0, 3, 5.0), 2);
        assert_eq!(motion_mode(stop, 10.0, 2, 5.0), 3);
        assert_eq!(motion_mode(stop, 10.0, 1, 9.0), 3);
    }
}

//! One rock from release to rest: an event-driven state machine over exact flight arcs and
//! rolling steps. Every arc or step is a *segment* whose horizontal path is straight; a
//! segment is checked against stems (the earliest impact truncates it), walked cell by cell
//! for the per-cell statistics and nets, and intersected with the evaluation screens.

use crate::body::RockBody;
use crate::direction::draw_direction;
use crate::forestry::Trees;
use crate::ground::SurfNormal;
use crate::ground::{FlightEnd, Ground};
use crate::rebound::{clearing_speed2, compose, hop, rebound};
use crate::roll::{
    ROLL_DT_MAX_S, ROLL_DT_MIN_S, RollInput, RollStep, roll_step, rolling_resistance,
};
use crate::trees::{ImpactType, draw_deviation_deg, eccentricity, impact_loss_j};
use crate::vec3::rotate_horizontal;
use crate::walk::Walk;
use crate::{G_MS2, V3};
use rand::RngExt;
use rockfall_results::{
    CellVisit, Event, Outcome, RockEnd, RockStart, ScreenCrossing, ScreenSet, Tally, TrajectoryRow,
};
use rockfall_rng::Rng;
use rockfall_scenario::LumpedSettings;

/// A rock still moving after this many events is given up as [`Outcome::Failed`] (a guard
/// against a defect, never reached on the built-in sites).
pub const MAX_EVENTS: u32 = 200_000;

/// Interval between the flight rows written for recorded trajectories, s.
const RECORD_DT_S: f64 = 0.05;

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
}

/// A piece of motion with a straight horizontal path, parameterised by time τ from its start.
#[derive(Debug, Clone, Copy)]
enum Seg {
    /// Free flight from `p0` with velocity `v0`.
    Flight { p0: V3, v0: V3 },
    /// A rolling step from `p0` to `p1` over `dur` s, velocity from `v0` to `v1`.
    Line {
        p0: V3,
        p1: V3,
        v0: V3,
        v1: V3,
        dur: f64,
    },
}

impl Seg {
    #[inline]
    fn pos(&self, tau: f64) -> V3 {
        match *self {
            Seg::Flight { p0, v0 } => p0 + v0 * tau + V3::new(0.0, 0.0, -0.5 * G_MS2 * tau * tau),
            Seg::Line { p0, p1, dur, .. } => p0 + (p1 - p0) * (tau / dur),
        }
    }

    #[inline]
    fn vel(&self, tau: f64) -> V3 {
        match *self {
            Seg::Flight { v0, .. } => v0 + V3::new(0.0, 0.0, -G_MS2 * tau),
            Seg::Line { v0, v1, dur, .. } => v0 + (v1 - v0) * (tau / dur),
        }
    }

    /// Horizontal velocity of the path (constant over the segment), m/s.
    #[inline]
    fn rate(&self) -> (f64, f64) {
        match *self {
            Seg::Flight { v0, .. } => (v0.x, v0.y),
            Seg::Line { p0, p1, dur, .. } => ((p1.x - p0.x) / dur, (p1.y - p0.y) / dur),
        }
    }
}

/// What cut a segment short.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cut {
    None,
    Tree(usize),
    Net(usize),
}

const EMPTY_VISIT: CellVisit = CellVisit {
    energy_j: 0.0,
    velocity_ms: 0.0,
    passing_height_m: 0.0,
};

/// Reusable per-worker buffers.
#[derive(Debug, Default)]
pub struct Scratch {
    crossings: Vec<(usize, f64)>,
}

/// The state of the rock being simulated.
struct Rock<'w, 'a, 't> {
    world: &'w World<'a>,
    tally: &'t mut Tally,
    scratch: &'t mut Scratch,
    rng: &'t mut Rng,
    body: RockBody,
    rock_id: u64,
    recording: bool,
    start: V3,
    p: V3,
    v: V3,
    w: V3,
    t: f64,
    rolling: bool,
    moved: bool,
    /// The next rolling step may not take off (the last take-off landed at once).
    hold_ground: bool,
    visit: Option<(usize, CellVisit)>,
    last_rebound_cell: Option<usize>,
    last_stem: Option<usize>,
    max_v: f64,
    max_h: f64,
    impacts: u32,
    broken: u32,
    rebounds: u32,
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
        hold_ground: false,
        visit: None,
        last_rebound_cell: None,
        last_stem: None,
        max_v: 0.0,
        max_h: 0.0,
        impacts: 0,
        broken: 0,
        rebounds: 0,
    };
    rock.run();
}

impl Rock<'_, '_, '_> {
    fn run(&mut self) {
        self.settle_at_release();
        self.record(Event::Flight);
        let mut events = 0u32;
        let outcome = loop {
            events += 1;
            if events > MAX_EVENTS || !(self.p.is_finite() && self.v.is_finite()) {
                break Outcome::Failed;
            }
            let remaining = self.world.max_time_s - self.t;
            if remaining <= 0.0 {
                break Outcome::TimeLimit;
            }
            let step = if self.rolling {
                self.roll()
            } else {
                self.fly(remaining)
            };
            if let Some(outcome) = step {
                break outcome;
            }
        };
        self.finish(outcome);
    }

    /// Starts rolling when released on the ground without lift-off speed.
    fn settle_at_release(&mut self) {
        let Some(s) = self.world.ground.surface(self.p.x, self.p.y) else {
            return;
        };
        let n = s.normal_v3();
        let gap = self.p.z - (s.z_m + self.body.radius_m);
        if gap <= 1e-9 && self.v.dot(n) <= 1e-9 {
            self.p.z = s.z_m + self.body.radius_m;
            self.start_rolling(n);
        }
        let zg = s.z_m;
        self.max_h = self.p.z - zg;
    }

    fn energy_j(&self, v: V3) -> f64 {
        self.body.translational_energy_j(v) + self.body.rotational_energy_j(self.w)
    }

    fn current_cell(&self) -> Option<usize> {
        self.world.ground.cell_index(self.p.x, self.p.y)
    }

    /// One flight arc (possibly cut by a stem or a net); `None` while the rock goes on.
    fn fly(&mut self, remaining: f64) -> Option<Outcome> {
        let r = self.body.radius_m;
        let end = self.world.ground.fly(self.p, self.v, r, remaining);
        let dur = match end {
            FlightEnd::Land { t_s } | FlightEnd::Exit { t_s } => t_s,
            FlightEnd::Timeout => remaining,
        };
        let seg = Seg::Flight {
            p0: self.p,
            v0: self.v,
        };
        let (tau, cut) = self.traverse(&seg, dur);
        self.record_arc(&seg, tau);
        self.p = seg.pos(tau);
        self.v = seg.vel(tau);
        self.t += tau;
        if tau > 0.0 {
            self.moved = true;
        }
        match cut {
            Cut::Tree(stem) => self.tree_impact(stem),
            Cut::Net(cell) => self.net(cell),
            Cut::None => match end {
                FlightEnd::Land { .. } if dur < 1e-6 => {
                    // touching down where it took off: the rock runs along the ground
                    let n = self.world.ground.surface(self.p.x, self.p.y)?.normal_v3();
                    self.start_rolling(n);
                    self.hold_ground = true;
                    None
                }
                FlightEnd::Land { .. } => self.rebound(),
                FlightEnd::Exit { .. } => Some(Outcome::LeftDem),
                FlightEnd::Timeout => Some(Outcome::TimeLimit),
            },
        }
    }

    /// One ground rebound; switches to rolling when the rock would barely lift off.
    fn rebound(&mut self) -> Option<Outcome> {
        let ground = self.world.ground;
        let Some(s) = ground.surface(self.p.x, self.p.y) else {
            return Some(Outcome::LeftDem);
        };
        let Some(cell) = ground.cell_index(self.p.x, self.p.y) else {
            return Some(Outcome::LeftDem);
        };
        self.p.z = s.z_m + self.body.radius_m;
        let n_true = s.normal_v3();
        let settings = self.world.settings;
        let reb = rebound(
            &self.body,
            self.v,
            self.w,
            n_true,
            ground.cell(cell),
            settings,
            self.rng,
        );
        let incoming = horizontal_unit(self.v);
        let along = horizontal_unit(reb.tangent).unwrap_or((1.0, 0.0));
        let (dir, vt) = if reb.vt_ms < 0.0 {
            ((-along.0, -along.1), -reb.vt_ms)
        } else if self.last_rebound_cell != Some(cell) {
            let max_dev = settings.max_lateral_deviation_deg.to_radians();
            let (x, y) = (self.p.x, self.p.y);
            let d = draw_direction(ground, cell, x, y, incoming, max_dev, self.rng);
            (d.unwrap_or(along), reb.vt_ms)
        } else {
            (incoming.unwrap_or(along), reb.vt_ms)
        };
        let k = self.body.rolling_factor();
        // small rebound: on ground too gentle to keep a rolling rock going it rolls (and
        // slows down); on steeper ground it bounces on over the obstacles
        let mu = rolling_resistance(ground.cell(cell).moh_mean_m, self.body.radius_m);
        let hopped = if holds_rolling_rock(n_true, mu) {
            let vn = reb.vn_ms;
            (vn * vn >= clearing_speed2(reb.moh_m, reb.normal.z)).then_some((vt, vn))
        } else {
            hop(vt, reb.vn_ms, reb.moh_m, reb.normal.z, k)
        };
        let (vt, vn) = hopped.unwrap_or((vt, reb.vn_ms));
        let (v, w) = compose(reb.normal, dir, vt, vn, self.body.radius_m);
        self.rebounds += 1;
        self.last_rebound_cell = Some(cell);
        self.v = v;
        self.w = w;
        if hopped.is_none() || vn <= 0.0 || v.dot(n_true) <= 0.0 {
            self.start_rolling(n_true);
        }
        self.record(Event::Impact);
        None
    }

    /// Puts the rock on the ground: velocity projected on the tangent plane, rolling spin.
    /// The rolling state never holds more kinetic energy than the rock had: a rebound on the
    /// flattened slope leaves it with some speed normal to that plane which, projected on the
    /// true tangent plane, would otherwise turn into rolling speed and spin.
    fn start_rolling(&mut self, n: V3) {
        self.rolling = true;
        let before_j = self.energy_j(self.v);
        self.v = self.v - n * self.v.dot(n);
        self.w = rolling_spin(self.v, n, self.body.radius_m);
        let after_j = self.energy_j(self.v);
        if after_j > before_j {
            let scale = (before_j / after_j).sqrt();
            self.v = self.v * scale;
            self.w = self.w * scale;
        }
    }

    /// One rolling step; `None` while the rock goes on.
    fn roll(&mut self) -> Option<Outcome> {
        let ground = self.world.ground;
        let Some(cell) = self.current_cell() else {
            return Some(Outcome::LeftDem);
        };
        let moh = ground.cell(cell).moh_mean_m;
        let mu = rolling_resistance(moh, self.body.radius_m);
        // on ground too steep to hold it, a rock fast enough to bounce over the cell's
        // obstacles does so: a rebound where it is
        if self.moved && moh > 0.0 {
            let n = ground
                .surface(self.p.x, self.p.y)
                .map_or(V3::UP, |s| s.normal_v3());
            if !holds_rolling_rock(n, mu) && self.v.norm2() >= clearing_speed2(moh, n.z) {
                self.rolling = false;
                return self.rebound();
            }
        }
        let stop = self.world.settings.stop_velocity_ms;
        let mut input = RollInput {
            mu_r: mu,
            stop_ms: stop,
            moved: self.moved,
            dt_cap_s: ROLL_DT_MAX_S,
            allow_fly: !std::mem::take(&mut self.hold_ground),
        };
        // a take-off is confirmed on ever shorter steps, so the rock rolls up to the break
        let step = loop {
            let step = roll_step(ground, &self.body, self.p, self.v, &input);
            if step != RollStep::Fly || input.dt_cap_s < ROLL_DT_MIN_S {
                break step;
            }
            input.dt_cap_s *= 0.25;
        };
        let (p1, v1, dt, stops) = match step {
            RollStep::Stuck => return Some(Outcome::Stopped { cell }),
            RollStep::Exit => return Some(Outcome::LeftDem),
            RollStep::Fly => {
                self.rolling = false;
                return None;
            }
            RollStep::Moved { p, v, dt_s } => (p, v, dt_s, false),
            RollStep::Stopped { p, dt_s } => (p, V3::ZERO, dt_s, true),
        };
        let seg = Seg::Line {
            p0: self.p,
            p1,
            v0: self.v,
            v1,
            dur: dt,
        };
        let (tau, cut) = self.traverse(&seg, dt);
        self.p = seg.pos(tau);
        self.v = seg.vel(tau);
        self.t += tau;
        self.moved = true;
        let surface = ground.surface(self.p.x, self.p.y);
        if let Some(s) = surface {
            // a step cut short lies on the chord: put the rock back on the ground
            self.p.z = s.z_m + self.body.radius_m;
        }
        let n = surface.map(|s| s.normal_v3());
        self.w = n.map_or(V3::ZERO, |n| rolling_spin(self.v, n, self.body.radius_m));
        match cut {
            Cut::Tree(stem) => return self.tree_impact(stem),
            Cut::Net(cell) => return self.net(cell),
            Cut::None => {}
        }
        self.record(Event::Roll);
        if stops {
            let cell = self.current_cell()?;
            return Some(Outcome::Stopped { cell });
        }
        None
    }

    /// The rock meets stem `stem` where it is now (seed 000 §2.4, eqs. 1–2, table 1).
    fn tree_impact(&mut self, stem: usize) -> Option<Outcome> {
        let trees = self.world.trees?;
        let s = trees.stem(stem);
        self.last_stem = Some(stem);
        let (dx, dy) = horizontal_unit(self.v)?;
        // signed lateral offset of the stem axis from the path (positive: stem on the left)
        let (cx, cy) = (s.x_m - self.p.x, s.y_m - self.p.y);
        let lateral = dx * cy - dy * cx;
        let x = eccentricity(lateral.abs(), self.body.radius_m, s.radius_m);
        let kind = ImpactType::of(x);
        let energy = self.energy_j(self.v);
        let (loss, broken) = impact_loss_j(energy, x, s.e_max_j);
        let keep = ((energy - loss).max(0.0) / energy).sqrt();
        let deviation = draw_deviation_deg(kind, self.rng).to_radians();
        let side = match kind {
            ImpactType::Frontal if self.rng.random::<bool>() => 1.0,
            ImpactType::Frontal => -1.0,
            _ if lateral > 0.0 => -1.0,
            _ => 1.0,
        };
        self.v = rotate_horizontal(self.v * keep, side * deviation);
        self.w = self.w * keep;
        if self.rolling {
            let n = self.world.ground.surface(self.p.x, self.p.y)?.normal_v3();
            self.start_rolling(n);
        }
        self.impacts += 1;
        self.broken += u32::from(broken);
        let height = self.p.z - s.base_z_m;
        self.tally.tree_impact(s.cell, height, broken);
        self.record(Event::Tree);
        if loss >= energy || self.v.norm() < self.world.settings.stop_velocity_ms {
            return Some(Outcome::Stopped {
                cell: self.current_cell()?,
            });
        }
        None
    }

    /// The rock reaches the nets of `cell` below their height: each net takes its energy
    /// from the rock or, if the rock has less, stops it.
    fn net(&mut self, cell: usize) -> Option<Outcome> {
        let c = *self.world.ground.cell(cell);
        for _ in 0..c.nets {
            let energy = self.energy_j(self.v);
            if energy <= c.net_energy_j {
                self.v = V3::ZERO;
                self.w = V3::ZERO;
                return Some(Outcome::NetStopped { cell });
            }
            let keep = ((energy - c.net_energy_j) / energy).sqrt();
            self.v = self.v * keep;
            self.w = self.w * keep;
        }
        None
    }

    /// Checks a segment against stems, walks its cells (statistics, nets) and screens;
    /// returns where it ends and why.
    fn traverse(&mut self, seg: &Seg, dur: f64) -> (f64, Cut) {
        let (mut end, mut cut) = (dur, Cut::None);
        if let Some((tau, stem)) = self.first_stem(seg, dur) {
            (end, cut) = (tau, Cut::Tree(stem));
        }
        if let Some(tau_net) = self.walk_cells(seg, end) {
            (end, cut) = tau_net;
        }
        self.screens(seg, end);
        (end, cut)
    }

    /// The earliest stem the rock touches over `[0, dur]`: its centre comes within
    /// R + DBH/2 of the stem axis while the rock's lowest point is below the stem's top.
    fn first_stem(&self, seg: &Seg, dur: f64) -> Option<(f64, usize)> {
        let trees = self.world.trees?;
        let r = self.body.radius_m;
        let (a0, a1) = (seg.pos(0.0), seg.pos(dur));
        let (dx, dy) = seg.rate();
        let qa = dx * dx + dy * dy;
        let mut best: Option<(f64, usize)> = None;
        trees
            .index()
            .for_each_near_segment((a0.x, a0.y), (a1.x, a1.y), r, |hit| {
                if Some(hit.index) == self.last_stem {
                    return;
                }
                let s = trees.stem(hit.index);
                let rho = r + s.radius_m;
                let (ex, ey) = (a0.x - s.x_m, a0.y - s.y_m);
                let qb = 2.0 * (dx * ex + dy * ey);
                let qc = ex * ex + ey * ey - rho * rho;
                let tau = if qc <= 0.0 {
                    if qb >= 0.0 {
                        return;
                    }
                    0.0
                } else {
                    let disc = qb * qb - 4.0 * qa * qc;
                    if qa == 0.0 || disc < 0.0 {
                        return;
                    }
                    (-qb - disc.sqrt()) / (2.0 * qa)
                };
                if !(0.0..=dur).contains(&tau) || seg.pos(tau).z - r >= s.top_z_m {
                    return;
                }
                if best.is_none_or(|(b, _)| tau < b) {
                    best = Some((tau, hit.index));
                }
            });
        best
    }

    /// Walks the cells the segment crosses up to `end`: per-cell visit maxima, and nets
    /// (returns the entry time into a cell whose nets catch the rock).
    fn walk_cells(&mut self, seg: &Seg, end: f64) -> Option<(f64, Cut)> {
        let ground = self.world.ground;
        let g = *ground.geometry();
        let p0 = seg.pos(0.0);
        let walk = Walk::new(
            (g.x_min_m, g.y_min_m),
            g.cell_size_m,
            (p0.x, p0.y),
            seg.rate(),
            end,
        );
        for piece in walk {
            let (i, j) = (piece.i, piece.j);
            if i < 0 || j < 0 || i >= g.ncols as i64 || j >= g.nrows as i64 {
                continue;
            }
            let cell = (g.nrows - 1 - j as usize) * g.ncols + i as usize;
            if self.visit.is_none_or(|(c, _)| c != cell) {
                self.flush_visit();
                self.visit = Some((cell, EMPTY_VISIT));
                let c = ground.cell(cell);
                if c.nets > 0 && piece.s_a > 0.0 {
                    let q = seg.pos(piece.s_a);
                    let zg = ground.height_m(q.x, q.y).unwrap_or(f64::NEG_INFINITY);
                    if q.z - zg < c.net_height_m {
                        self.sample(seg, piece.s_a);
                        return Some((piece.s_a, Cut::Net(cell)));
                    }
                }
            }
            self.sample(seg, 0.5 * (piece.s_a + piece.s_b));
            self.sample(seg, piece.s_b);
        }
        None
    }

    /// Folds the state at `tau` into the current visit and the rock's maxima.
    fn sample(&mut self, seg: &Seg, tau: f64) {
        let q = seg.pos(tau);
        let u = seg.vel(tau);
        let Some(zg) = self.world.ground.height_m(q.x, q.y) else {
            return;
        };
        let h = q.z - zg;
        let speed = u.norm();
        let e = self.energy_j(u);
        self.max_v = self.max_v.max(speed);
        self.max_h = self.max_h.max(h);
        if let Some((_, v)) = &mut self.visit {
            v.energy_j = v.energy_j.max(e);
            v.velocity_ms = v.velocity_ms.max(speed);
            v.passing_height_m = v.passing_height_m.max(h);
        }
    }

    fn flush_visit(&mut self) {
        if let Some((cell, visit)) = self.visit.take() {
            self.tally.cell_visit(cell, visit);
        }
    }

    /// Reports the screen crossings of the segment's horizontal path over `[0, end]`.
    fn screens(&mut self, seg: &Seg, end: f64) {
        let screens = self.world.screens;
        if screens.is_empty() || end <= 0.0 {
            return;
        }
        let (a, b) = (seg.pos(0.0), seg.pos(end));
        let buf = &mut self.scratch.crossings;
        buf.clear();
        screens.for_each_crossing([a.x, a.y], [b.x, b.y], |k, s| buf.push((k, s)));
        for i in 0..self.scratch.crossings.len() {
            let (k, s) = self.scratch.crossings[i];
            let tau = s * end;
            let (q, u) = (seg.pos(tau), seg.vel(tau));
            let zg = self.world.ground.height_m(q.x, q.y).unwrap_or(q.z);
            let crossing = ScreenCrossing {
                velocity_ms: u.norm(),
                energy_j: self.energy_j(u),
                jump_height_m: q.z - zg,
            };
            self.tally.screen_crossing(k, crossing);
        }
    }

    fn record(&mut self, event: Event) {
        if self.recording {
            let row = self.row(self.t, self.p, self.v, event);
            self.tally.record(row);
        }
    }

    /// Rows along a flight arc every [`RECORD_DT_S`] for recorded rocks.
    fn record_arc(&mut self, seg: &Seg, dur: f64) {
        if !self.recording {
            return;
        }
        let mut tau = RECORD_DT_S;
        while tau < dur {
            let row = self.row(self.t + tau, seg.pos(tau), seg.vel(tau), Event::Flight);
            self.tally.record(row);
            tau += RECORD_DT_S;
        }
    }

    fn row(&self, t: f64, p: V3, v: V3, event: Event) -> TrajectoryRow {
        TrajectoryRow {
            rock_id: self.rock_id,
            t_s: t,
            x_m: p.x,
            y_m: p.y,
            z_m: p.z,
            vx_ms: v.x,
            vy_ms: v.y,
            vz_ms: v.z,
            wx_rads: self.w.x,
            wy_rads: self.w.y,
            wz_rads: self.w.z,
            e_trans_j: self.body.translational_energy_j(v),
            e_rot_j: self.body.rotational_energy_j(self.w),
            event,
        }
    }

    fn finish(&mut self, outcome: Outcome) {
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
        });
    }
}

/// Whether rolling resistance `mu` holds a rock on ground of normal `n`: `tan θ ≤ μ_r`. There
/// a rock rolls and slows down; on steeper ground a rolling rock speeds up until the
/// obstacles throw it into short bounces (see [`crate::rebound::hop`]).
#[inline]
fn holds_rolling_rock(n: V3, mu: f64) -> bool {
    n.horizontal_norm() <= mu * n.z
}

/// Horizontal unit direction of `v`, `None` when it is (nearly) vertical.
#[inline]
fn horizontal_unit(v: V3) -> Option<(f64, f64)> {
    let h = v.horizontal_norm();
    (h > 1e-9).then(|| (v.x / h, v.y / h))
}

/// Angular velocity of rolling without slip with velocity `v` on ground of normal `n`.
#[inline]
fn rolling_spin(v: V3, n: V3, radius_m: f64) -> V3 {
    n.cross(v) * (1.0 / radius_m)
}

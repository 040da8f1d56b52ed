//! A rock and the ground: flight, rebound, rolling and stopping (seed 000 §2.3, §2.5).
//!
//! - **Flight** is an exact parabola until the centre reaches the offset surface
//!   ([`Ground::fly`](crate::ground::Ground::fly)).
//! - **Rebound** ([`crate::rebound`]): Pfeiffer & Bowen as adapted in seed 000, on the local
//!   surface lowered by 0–4° and tilted by the roughness ([`crate::rebound::roughness_tilt`]:
//!   towards the rock at every rebound, sideways only at the first one in a new cell), with
//!   r_n of the soil class scaled by the impact speed and r_t of eq. 3; the outgoing heading
//!   follows from the incoming motion and that surface, within 45° of the incoming heading
//!   (§2.3).
//! - **Rolling**: a rebound that cannot lift the rock over the obstacle it met
//!   ([`crate::rebound::lifts_off`], a rule of ours) puts it on the ground, where it rolls
//!   against the friction of the surface ([`crate::roll`]) until the ground falls away from
//!   it (a flight) or it stops. Rolling is "a sequence of short bounces" (model notes, after
//!   Dorren et al. 2004) whose direction changes only between cells (seed 000 §2.3): a rolling
//!   rock fast enough to clear the obstacles (`v² ≥ 2 g n_z MOH`) rebounds where it enters a
//!   new cell, and may fly off again (ours: which speed and how often are not published).
//! - **Stop**: below 0.1 m/s once it has moved (seed 000 §4), or where the friction holds it.
//!
//! The rock's centre is R from the ground along the surface normal: `R / n_z` above it
//! vertically ([`Ground::centre_z_m`](crate::ground::Ground::centre_z_m)).

use crate::V3;
use crate::ground::{FlightEnd, SurfNormal};
use crate::rebound::{clears_obstacles_speed2, compose, lifts_off, limit_heading, rebound};
use crate::roll::{
    ROLL_DT_MAX_S, ROLL_DT_MIN_S, RollInput, RollStep, friction_coefficient, roll_step,
};
use crate::segment::Seg;
use crate::trajectory::{Rock, horizontal_unit, rolling_spin};
use rockfall_results::{Event, Outcome};

impl Rock<'_, '_, '_> {
    /// Starts rolling when released on the ground without lift-off speed.
    pub(crate) fn settle_at_release(&mut self) {
        let Some(s) = self.world.ground.surface(self.p.x, self.p.y) else {
            return;
        };
        let n = s.normal_v3();
        let Some(rest_z) = self
            .world
            .ground
            .centre_z_m(self.p.x, self.p.y, self.body.radius_m)
        else {
            return;
        };
        if self.p.z - rest_z <= 1e-9 && self.v.dot(n) <= 1e-9 {
            self.p.z = rest_z;
            self.grounded = true;
            self.max_h = self.p.z - s.z_m;
            self.start_rolling(n);
        }
    }

    /// One flight arc (possibly cut by a stem or a net); `None` while the rock goes on.
    pub(crate) fn fly(&mut self, remaining: f64) -> Option<Outcome> {
        // a flight starts on or above the surface it lands on: a rock leaving the ground a
        // little below it (its resting height comes from the smoothed normal) is lifted to it
        let floor = self
            .world
            .ground
            .flight_floor_z_m(self.p.x, self.p.y, self.body.radius_m);
        if let Some(z) = floor.filter(|&z| z > self.p.z) {
            self.put_on_ground(z);
        }
        let end = self
            .world
            .ground
            .fly(self.p, self.v, self.body.radius_m, remaining);
        let dur = match end {
            FlightEnd::Land { t_s } | FlightEnd::Exit { t_s } => t_s,
            FlightEnd::Timeout => remaining,
        };
        let seg = Seg::Flight {
            p0: self.p,
            v0: self.v,
        };
        let (tau, cut) = self.advance(&seg, dur);
        if tau > 0.0 {
            self.moved = true;
        }
        if let Some(outcome) = self.obstacle(cut, seg.rate()) {
            return outcome;
        }
        match end {
            FlightEnd::Land { .. } if dur < 1e-6 => {
                // touching down where it took off: the rock runs along the ground
                let n = self.world.ground.surface(self.p.x, self.p.y)?.normal_v3();
                self.grounded = true;
                self.start_rolling(n);
                self.hold_ground = true;
                None
            }
            FlightEnd::Land { .. } => self.rebound(false),
            FlightEnd::Exit { .. } => Some(Outcome::LeftDem),
            FlightEnd::Timeout => Some(Outcome::TimeLimit),
        }
    }

    /// One ground rebound; puts the rock on the ground when it would not lift off. A rolling
    /// rock (`rolling`) meeting the obstacles of a new cell rebounds only if they throw it off
    /// the ground; otherwise it rolls on over them, against the friction that stands for them
    /// ([`crate::roll`]), and the rebound is not taken.
    fn rebound(&mut self, rolling: bool) -> Option<Outcome> {
        let ground = self.world.ground;
        let Some(s) = self.memo.surface(ground, self.p.x, self.p.y) else {
            return Some(Outcome::LeftDem);
        };
        let Some(cell) = ground.cell_index(self.p.x, self.p.y) else {
            return Some(Outcome::LeftDem);
        };
        let n_true = s.normal_v3();
        let r = self.body.radius_m;
        let rest_z = (self.memo.centre_z_m(ground, self.p.x, self.p.y, r)).unwrap_or(self.p.z);
        self.put_on_ground(rest_z);
        self.grounded = true;
        let settings = self.world.settings;
        let new_cell = self.last_rebound_cell != Some(cell);
        let params = ground.cell(cell);
        let reb = rebound(
            &self.body, self.v, self.w, n_true, params, settings, new_cell, self.rng,
        );
        let incoming = horizontal_unit(self.v);
        let (mut v, mut w) = compose(reb.normal, reb.tangent, reb.vt_ms, reb.vn_ms, r);
        if reb.vt_ms >= 0.0 {
            let max_dev = settings.max_lateral_deviation_deg.to_radians();
            (v, w) = limit_heading(v, w, incoming, max_dev);
        }
        self.last_rebound_cell = Some(cell);
        let (factor, stop_ms) = (settings.lift_off_obstacle_factor, settings.stop_velocity_ms);
        let flies = lifts_off(v.dot(n_true), reb.moh_m, n_true.z, factor, stop_ms);
        if rolling && !flies {
            self.rolling = true;
            return None;
        }
        self.rebounds += 1;
        self.v = v;
        self.w = w;
        if !flies {
            self.start_rolling(n_true);
        }
        self.record(Event::Impact);
        None
    }

    /// Moves the centre to height `z_m` (on the ground). Where that lifts it (the end of a
    /// rolling step cut short lies on the chord below the curved ground; a landing on the edge
    /// of a steeper patch), gravity's work is taken from the kinetic energy, so that putting
    /// the rock back on the ground never creates energy.
    fn put_on_ground(&mut self, z_m: f64) {
        let lift_j = self.body.mass_kg * crate::G_MS2 * (z_m - self.p.z);
        self.p.z = z_m;
        if lift_j > 0.0 {
            let e = self.energy_j(self.v);
            let keep = if e > lift_j {
                ((e - lift_j) / e).sqrt()
            } else {
                0.0
            };
            self.v *= keep;
            self.w *= keep;
        }
    }

    /// Puts the rock on the ground: velocity projected on the tangent plane, rolling spin.
    /// The rolling state never holds more kinetic energy than the rock had: a rebound on the
    /// lowered or tilted surface leaves it with some speed normal to that plane which,
    /// projected on the true tangent plane, would otherwise turn into rolling speed and spin.
    pub(crate) fn start_rolling(&mut self, n: V3) {
        self.rolling = true;
        let before_j = self.energy_j(self.v);
        self.v = self.v - n * self.v.dot(n);
        self.w = rolling_spin(self.v, n, self.body.radius_m);
        let after_j = self.energy_j(self.v);
        if after_j > before_j {
            let scale = (before_j / after_j).sqrt();
            self.v *= scale;
            self.w *= scale;
        }
    }

    /// One rolling step; `None` while the rock goes on.
    pub(crate) fn roll(&mut self) -> Option<Outcome> {
        let ground = self.world.ground;
        let Some(cell) = self.current_cell() else {
            return Some(Outcome::LeftDem);
        };
        let params = ground.cell(cell);
        let moh = params.moh_mean_m;
        let n = (self.memo.surface(ground, self.p.x, self.p.y)).map_or(V3::Z, |s| s.normal_v3());
        if self.moved
            && moh > 0.0
            && self.last_rebound_cell != Some(cell)
            && self.v.length_squared() >= clears_obstacles_speed2(moh, n.z)
        {
            // rolling as a sequence of short bounces: a rock fast enough to be thrown by the
            // obstacles meets them where it enters a cell (a rebound there, if they throw it)
            self.rolling = false;
            if let Some(outcome) = self.rebound(true) {
                return Some(outcome);
            }
            if !self.rolling {
                return None;
            }
        }
        let settings = self.world.settings;
        let mu = friction_coefficient(
            moh,
            self.body.radius_m,
            params.soil_mu,
            settings.soil_friction_scale,
        );
        let mut input = RollInput {
            mu_r: mu,
            stop_ms: settings.stop_velocity_ms,
            moved: self.moved,
            dt_cap_s: ROLL_DT_MAX_S,
            allow_fly: !std::mem::take(&mut self.hold_ground),
        };
        // a take-off is confirmed on ever shorter steps, so the rock rolls up to the break
        let step = loop {
            let step = roll_step(ground, &mut self.memo, &self.body, self.p, self.v, &input);
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
        let (_, cut) = self.advance(&seg, dt);
        self.moved = true;
        let surface = self.memo.surface(ground, self.p.x, self.p.y);
        let n = surface.map(|s| s.normal_v3());
        self.w = n.map_or(V3::ZERO, |n| rolling_spin(self.v, n, self.body.radius_m));
        let r = self.body.radius_m;
        if let Some(z) = self.memo.centre_z_m(ground, self.p.x, self.p.y, r) {
            // a step cut short lies on the chord: put the rock back on the ground
            self.put_on_ground(z);
        }
        if let Some(outcome) = self.obstacle(cut, seg.rate()) {
            return outcome;
        }
        self.record(Event::Roll);
        if stops {
            let cell = self.current_cell()?;
            return Some(Outcome::Stopped { cell });
        }
        None
    }
}

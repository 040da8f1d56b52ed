//! What a rock reports as it moves: the cells it crosses (per-cell statistics), the screens
//! it passes, its maxima and, for recorded rocks, its trajectory rows.

use crate::V3;
use crate::segment::{Cut, Seg};
use crate::trajectory::Rock;
use crate::walk::Walk;
use rockfall_results::{CellVisit, Event, ScreenCrossing, TrajectoryRow};

/// Interval between the flight rows written for recorded trajectories, s.
const RECORD_DT_S: f64 = 0.05;

const EMPTY_VISIT: CellVisit = CellVisit {
    energy_j: 0.0,
    velocity_ms: 0.0,
    passing_height_m: 0.0,
};

impl Rock<'_, '_, '_> {
    /// Checks a segment against stems, walks its cells (statistics, nets) and screens;
    /// returns where it ends and why.
    pub(crate) fn traverse(&mut self, seg: &Seg, dur: f64) -> (f64, Cut) {
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
            // a path starting exactly on a cell edge (after a net cut it) crosses the cell
            // behind the edge in zero length: that is no visit, nor an entry into the cell
            // ahead (which would be its second)
            if piece.s_b <= piece.s_a && piece.s_b < end {
                continue;
            }
            if self.visit.is_none_or(|(c, _)| c != cell) {
                let first = self.visit.is_none();
                self.flush_visit();
                self.visit = Some((cell, EMPTY_VISIT));
                let c = ground.cell(cell);
                // a net acts once per passage through its cells (ours: a rasterised line is
                // often two cells wide along a path), not on a rock released among them
                let new_passage = self.net_passage.enter(c.net_id, first);
                self.net_entry(seg, piece.s_a, c.net_id, new_passage);
                if new_passage {
                    let q = seg.pos(piece.s_a);
                    let zg = (self.memo.height_m(ground, q.x, q.y)).unwrap_or(f64::NEG_INFINITY);
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

    /// The rock enters a cell of net `net_id` (0: none) at `tau`; `new_passage` when it begins
    /// a passage through the net's cells ([`rockfall_engine::nets::NetPassage`]). The first
    /// cell of a passage through the cells of a net that has a screen (`[nets] screens`) counts
    /// as a crossing of that screen, at the entry point and before the net acts, whatever the
    /// rock's height.
    fn net_entry(&mut self, seg: &Seg, tau: f64, net_id: u32, new_passage: bool) {
        if !new_passage {
            return;
        }
        if let Some(k) = self.world.screens.net_screen(net_id) {
            let crossing = self.crossing_at(seg, tau);
            self.tally.screen_crossing(k, crossing);
        }
    }

    /// The rock as a screen sees it at `tau` of `seg`: speed, kinetic energy, height of its
    /// centre above the ground and plan position.
    fn crossing_at(&mut self, seg: &Seg, tau: f64) -> ScreenCrossing {
        let (q, u) = (seg.pos(tau), seg.vel(tau));
        let zg = (self.memo.height_m(self.world.ground, q.x, q.y)).unwrap_or(q.z);
        ScreenCrossing {
            velocity_ms: u.length(),
            energy_j: self.energy_j(u),
            jump_height_m: q.z - zg,
            x_m: q.x,
            y_m: q.y,
        }
    }

    /// Folds the state at `tau` into the current visit and the rock's maxima.
    fn sample(&mut self, seg: &Seg, tau: f64) {
        let q = seg.pos(tau);
        let u = seg.vel(tau);
        let Some(zg) = self.memo.height_m(self.world.ground, q.x, q.y) else {
            return;
        };
        let h = q.z - zg;
        let speed = u.length();
        let e = self.energy_j(u);
        self.max_v = self.max_v.max(speed);
        if self.grounded {
            self.max_h = self.max_h.max(h);
        }
        if let Some((_, v)) = &mut self.visit {
            v.energy_j = v.energy_j.max(e);
            v.velocity_ms = v.velocity_ms.max(speed);
            v.passing_height_m = v.passing_height_m.max(h);
        }
    }

    pub(crate) fn flush_visit(&mut self) {
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
            let crossing = self.crossing_at(seg, s * end);
            self.tally.screen_crossing(k, crossing);
        }
    }

    pub(crate) fn record(&mut self, event: Event) {
        if self.recording {
            let row = self.row(self.t, self.p, self.v, event);
            self.tally.record(row);
        }
    }

    /// Rows along a flight arc every [`RECORD_DT_S`] for recorded rocks.
    pub(crate) fn record_arc(&mut self, seg: &Seg, dur: f64) {
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
}

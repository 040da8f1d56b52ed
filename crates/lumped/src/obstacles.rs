//! What a rock meets on its way besides the ground: stems (seed 000 §2.4, eqs. 1–2, table 1)
//! and nets.

use crate::V3;
use crate::ground::SurfNormal;
use crate::segment::{Cut, Seg};
use crate::trajectory::Rock;
use crate::trees::{ImpactType, draw_deviation_deg, eccentricity, impact_loss_j};
use crate::vec3::rotate_horizontal;
use rand::RngExt;
use rockfall_engine::nets::{NetEffect, net_effect};
use rockfall_results::{Event, Outcome};

impl Rock<'_, '_, '_> {
    /// The rock meets stem `stem` where it is now, moving along the horizontal unit direction
    /// `path` (seed 000 §2.4, eqs. 1–2, table 1). The direction is the path's, so an impact
    /// found on a segment is never lost to a velocity that has turned vertical.
    pub(crate) fn tree_impact(&mut self, stem: usize, path: (f64, f64)) -> Option<Outcome> {
        let trees = self.world.trees?;
        let s = trees.stem(stem);
        self.last_stem = Some(stem);
        let (dx, dy) = path;
        // signed lateral offset of the stem axis from the path (positive: stem on the left)
        let (cx, cy) = (s.x_m - self.p.x, s.y_m - self.p.y);
        let lateral = dx * cy - dy * cx;
        let x = eccentricity(lateral.abs(), self.body.radius_m, s.radius_m);
        let kind = ImpactType::of(x);
        let energy = self.energy_j(self.v);
        let (loss, broken) = impact_loss_j(energy, x, s.e_max_j);
        let keep = if energy > 0.0 {
            ((energy - loss).max(0.0) / energy).sqrt()
        } else {
            0.0
        };
        let deviation = draw_deviation_deg(kind, self.rng).to_radians();
        let side = match kind {
            ImpactType::Frontal if self.rng.random::<bool>() => 1.0,
            ImpactType::Frontal => -1.0,
            _ if lateral > 0.0 => -1.0,
            _ => 1.0,
        };
        self.v = rotate_horizontal(self.v * keep, side * deviation);
        self.w *= keep;
        if self.rolling {
            let n = self.world.ground.surface(self.p.x, self.p.y)?.normal_v3();
            self.start_rolling(n);
        }
        self.impacts += 1;
        self.broken += u32::from(broken);
        let height = self.p.z - s.base_z_m;
        self.tally.tree_impact(s.cell, height, broken);
        self.record(Event::Tree);
        if loss >= energy || self.v.length() < self.world.settings.stop_velocity_ms {
            return Some(Outcome::Stopped {
                cell: self.current_cell()?,
            });
        }
        None
    }

    /// The rock reaches the net of `cell` below its height (Rockyfor3D's nets, Dorren 2016
    /// §2.3): the net takes its energy capacity from the rock or, if the rock has less, stops
    /// it. Speed and spin scale by √((E − E_net)/E), so the kinetic energy drops by E_net.
    pub(crate) fn net(&mut self, cell: usize) -> Option<Outcome> {
        let c = *self.world.ground.cell(cell);
        match net_effect(self.energy_j(self.v), c.net_energy_j) {
            NetEffect::Stopped => {
                self.v = V3::ZERO;
                self.w = V3::ZERO;
                Some(Outcome::NetStopped { cell })
            }
            NetEffect::Passed { keep } => {
                self.v *= keep;
                self.w *= keep;
                None
            }
        }
    }

    /// Acts on what cut a segment with horizontal rate `rate` short; `None` while the rock
    /// goes on.
    pub(crate) fn obstacle(&mut self, cut: Cut, rate: (f64, f64)) -> Option<Option<Outcome>> {
        match cut {
            Cut::None => None,
            Cut::Net(cell) => Some(self.net(cell)),
            Cut::Tree(stem) => {
                let h = rate.0.hypot(rate.1);
                let path = if h > 0.0 {
                    (rate.0 / h, rate.1 / h)
                } else {
                    (1.0, 0.0)
                };
                Some(self.tree_impact(stem, path))
            }
        }
    }

    pub(crate) fn first_stem(&self, seg: &Seg, dur: f64) -> Option<(f64, usize)> {
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
}

//! Nets as the rigid engine meets them, by the rule and the code of the lumped engine
//! ([`rockfall_engine::nets`]): when the centre enters a cell of a net on a new passage with
//! its centre below the net's height above the ground, a rock with no more kinetic energy
//! than the capacity stops in it (`net_stopped`), any other goes on with speed and spin scaled
//! so that its energy drops by the capacity. The first cell of a passage through a net that
//! has a screen counts as a crossing of that screen, whatever the rock's height.

use crate::math::V3;
use crate::rock::{World, energies_j};
use crate::shape::RockBody;
use crate::step::RockState;
use rockfall_engine::nets::{NetEffect, NetPassage, net_effect};
use rockfall_results::{ScreenCrossing, Tally};

/// A rock's passage through the nets' cells: the net it is in and the cell its centre was
/// last in.
#[derive(Debug, Default)]
pub(crate) struct NetTrack {
    passage: NetPassage,
    cell: Option<usize>,
}

impl NetTrack {
    /// The nets' rule ([`rockfall_engine::nets`]) when the centre has entered a new cell: a net
    /// screen crossing, and the net's effect on a rock below its height. Returns the cell of a
    /// net that stopped the rock; `ground_z_m` is the ground height under the centre.
    pub(crate) fn meet(
        &mut self,
        world: &World<'_>,
        body: &RockBody,
        state: &mut RockState,
        ground_z_m: f64,
        tally: &mut Tally,
    ) -> Option<usize> {
        if world.nets.is_empty() {
            return None;
        }
        let cell = world
            .ground
            .lattice()
            .cell_index(state.r_m.x, state.r_m.y)?;
        if self.cell == Some(cell) {
            return None;
        }
        let first = self.cell.is_none();
        self.cell = Some(cell);
        let net = world.nets.at(cell);
        if !self.passage.enter(net.map_or(0, |n| n.id), first) {
            return None;
        }
        let net = net?;
        let (e_t, e_r) = energies_j(body, state);
        let height_m = state.r_m.z - ground_z_m;
        if let Some(k) = world.screens.net_screen(net.id) {
            tally.screen_crossing(
                k,
                ScreenCrossing {
                    velocity_ms: state.v_ms.length(),
                    energy_j: e_t + e_r,
                    jump_height_m: height_m,
                    x_m: state.r_m.x,
                    y_m: state.r_m.y,
                },
            );
        }
        if height_m >= net.height_m {
            return None;
        }
        match net_effect(e_t + e_r, net.energy_j) {
            NetEffect::Stopped => {
                state.v_ms = V3::ZERO;
                state.w_body_rads = V3::ZERO;
                Some(cell)
            }
            NetEffect::Passed { keep } => {
                slow_by(state, keep);
                None
            }
        }
    }
}

/// Scales the rock's speed and spin by `keep`: its kinetic energy, translational and
/// rotational, by keep² (a net's `NetEffect::Passed`).
fn slow_by(state: &mut RockState, keep: f64) {
    state.v_ms *= keep;
    state.w_body_rads *= keep;
}

#[cfg(test)]
mod tests {
    use super::slow_by;
    use crate::rock::energies_j;
    use crate::shape::{RockBody, RockGeometry, box_points};
    use crate::step::RockState;
    use crate::{Quat, V3};

    /// A spinning rock of 400 kJ passing a net of 300 kJ keeps 100 kJ, of its motion and of
    /// its spin alike.
    #[test]
    fn a_net_takes_its_capacity_from_motion_and_spin() {
        let geom = RockGeometry::from_points(&box_points([0.6, 0.8, 1.0])).unwrap();
        let body = RockBody::new(geom, 2700.0).unwrap();
        let mut s = RockState {
            r_m: V3::ZERO,
            q: Quat::IDENTITY,
            v_ms: V3::new(3.0, -4.0, 1.0),
            w_body_rads: V3::new(2.0, -7.0, 5.0),
        };
        let (t0, r0) = energies_j(&body, &s);
        let e0 = t0 + r0;
        let rockfall_engine::nets::NetEffect::Passed { keep } =
            rockfall_engine::nets::net_effect(e0, 0.75 * e0)
        else {
            panic!("passes")
        };
        slow_by(&mut s, keep);
        let (t1, r1) = energies_j(&body, &s);
        assert!((t1 - 0.25 * t0).abs() < 1e-9 * e0 && (r1 - 0.25 * r0).abs() < 1e-9 * e0);
    }
}

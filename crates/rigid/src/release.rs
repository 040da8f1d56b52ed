//! How a rock starts: its orientation and the height of its centre.
//!
//! The rock takes its orientation from the release (or a uniformly random one, Shoemake
//! 1992, from its own random stream) and its centre the height the release gives
//! ([`StartHeight`], one definition for both engines): its lowest hull vertex the release's
//! gap `height_m` above the ground under its centre — raised until no hull vertex is below
//! the ground under it when the gap would leave the rock partly in the ground (a small gap
//! on a slope) — or the centre at `z_m` ([`release_centre_z_m`]).

use crate::ground::Ground;
use crate::math::Quat;
use crate::shape::RockBody;
use rand::RngExt;
use rockfall_rng::Rng;
use rockfall_scenario::StartHeight;

/// A uniformly random rotation (Shoemake 1992, "Uniform random rotations", Graphics Gems
/// III): from three uniform numbers u1, u2, u3 in [0, 1).
pub fn random_orientation(rng: &mut Rng) -> Quat {
    let (u1, u2, u3): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
    let tau = std::f64::consts::TAU;
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    Quat::from_xyzw(
        a * (tau * u2).sin(),
        a * (tau * u2).cos(),
        b * (tau * u3).sin(),
        b * (tau * u3).cos(),
    )
    .normalize()
}

/// How far the rock reaches below its centre of mass in orientation `q`, m: the centre's
/// height over its lowest hull vertex.
pub fn extent_below_m(body: &RockBody, q: Quat) -> f64 {
    (body.geometry.vertices_m.iter())
        .map(|v| -(q * *v).z)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// How far the rock reaches below its centre of mass in the orientation that takes it
/// farthest down, m: its largest distance from the centre to a hull vertex.
pub fn circumradius_m(body: &RockBody) -> f64 {
    (body.geometry.vertices_m.iter())
        .map(|v| v.length())
        .fold(0.0, f64::max)
}

/// The lowest height of the centre of mass at which no hull vertex of the rock, at (x, y) in
/// orientation `q`, is below the ground under that vertex, m: the rock resting on the
/// ground at its highest point under the hull. Vertices off the DEM have no ground to
/// rest on and are left out (−∞ when every vertex is off it).
pub fn resting_centre_z_m(ground: &Ground, body: &RockBody, q: Quat, xy: [f64; 2]) -> f64 {
    let mut z = f64::NEG_INFINITY;
    for v in &body.geometry.vertices_m {
        let w = q * *v;
        if let Some(h) = ground.lattice().height_m(xy[0] + w.x, xy[1] + w.y) {
            z = z.max(h - w.z);
        }
    }
    z
}

/// Height of the centre of mass at release, m, with the rock at (x, y) in orientation `q`:
/// [`StartHeight::centre_z_m`] with the ground under the centre and [`extent_below_m`]; for a
/// gap, raised to [`resting_centre_z_m`] when that is higher — a rock that the gap under its
/// centre would leave partly in the ground (a small gap on a slope) starts resting on it.
/// `None` when (x, y) is off the DEM.
pub fn release_centre_z_m(
    ground: &Ground,
    body: &RockBody,
    q: Quat,
    xy: [f64; 2],
    start: StartHeight,
) -> Option<f64> {
    let ground_z_m = ground.lattice().height_m(xy[0], xy[1])?;
    let z = start.centre_z_m(ground_z_m, extent_below_m(body, q));
    Some(match start {
        StartHeight::Gap { .. } => z.max(resting_centre_z_m(ground, body, q, xy)),
        StartHeight::CentreZ { .. } => z,
    })
}

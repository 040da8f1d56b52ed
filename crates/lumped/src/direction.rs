//! The fall direction: multiple-fall-direction on the DEM (seed 000 §2.3).
//!
//! Seed 000 only says that at every step the fall direction can be towards any of the
//! downslope cells (the exact procedure being in Dorren et al. 2004), that trajectories
//! therefore diverge instead of converging like water-flow routing, that a rebound cannot turn
//! the rock by more than 45° laterally, and that the direction changes only between two cells.
//! What we implement:
//!
//! 1. A new direction is drawn only at the first ground rebound in a cell other than the cell
//!    of the previous rebound; rebounds within the same cell keep the incoming horizontal
//!    direction (tree impacts deviate the rock anywhere, see [`crate::trees`]).
//! 2. Candidates are the (up to eight) neighbours of the rebound cell lower than it. Each
//!    candidate's direction is the horizontal direction from the rock's rebound point to the
//!    neighbour's centre, so directions vary continuously with where in the cell the rock
//!    lands rather than snapping to eight compass points.
//! 3. One candidate is drawn with probability proportional to the tangent of the slope
//!    towards it, `(z_cell − z_neighbour) / distance` — the weights of the multiple-flow-
//!    direction method of Quinn et al. (1991) without contour-length factors — among the
//!    candidates within the allowed deviation of the incoming direction; when none lies
//!    within it, among all candidates, and the result is turned back to the limit.
//! 4. With no lower neighbour (a pit or a flat) the incoming direction is kept.

use crate::ground::Ground;
use rand::RngExt;
use rockfall_rng::Rng;

/// Draws the horizontal unit direction after a rebound at (x, y) in cell `cell`, given the
/// incoming horizontal direction `incoming` (unit, or `None` for a vertical arrival) and the
/// largest lateral deviation `max_dev_rad`.
pub fn draw_direction(
    ground: &Ground,
    cell: usize,
    x_m: f64,
    y_m: f64,
    incoming: Option<(f64, f64)>,
    max_dev_rad: f64,
    rng: &mut Rng,
) -> Option<(f64, f64)> {
    let z = ground.cell_z(cell);
    let h = ground.cell_size_m();
    // (angle, weight, within the allowed deviation)
    let mut cand = [(0.0f64, 0.0f64, false); 8];
    let mut n = 0;
    let base = incoming.map(|(dx, dy)| dy.atan2(dx));
    for (k, dc, dr) in ground.neighbours(cell) {
        let drop = z - ground.cell_z(k);
        if drop <= 0.0 {
            continue;
        }
        let tan = drop / (h * ((dc * dc + dr * dr) as f64).sqrt());
        let (cx, cy) = ground.cell_center(k);
        let angle = (cy - y_m).atan2(cx - x_m);
        let ok = base.is_none_or(|b| wrap(angle - b).abs() <= max_dev_rad);
        cand[n] = (angle, tan, ok);
        n += 1;
    }
    let cand = &cand[..n];
    if cand.is_empty() {
        return incoming;
    }
    let any_ok = cand.iter().any(|c| c.2);
    let pool = |c: &&(f64, f64, bool)| !any_ok || c.2;
    let total: f64 = cand.iter().filter(pool).map(|c| c.1).sum();
    let mut u = rng.random::<f64>() * total;
    let mut chosen = cand[0].0;
    for c in cand.iter().filter(pool) {
        chosen = c.0;
        if u < c.1 {
            break;
        }
        u -= c.1;
    }
    let angle = match base {
        Some(b) => b + wrap(chosen - b).clamp(-max_dev_rad, max_dev_rad),
        None => chosen,
    };
    Some((angle.cos(), angle.sin()))
}

/// An angle wrapped to (−π, π].
#[inline]
pub fn wrap(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let r = a.rem_euclid(TAU);
    if r > PI { r - TAU } else { r }
}

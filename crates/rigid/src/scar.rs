//! The scarring ground of RAMMS::ROCKFALL (Lu et al. 2019, "Modelling rockfall impact with
//! scarring in compactable soils", *Landslides* 16:2353–2367, eqs. 9–14).
//!
//! The ground is a soft, compactable scarring layer Σ over a hard rebound plane Λ, both below
//! the DEM surface. One impact runs in three phases:
//!
//! 1. **scarring**: the rock enters Σ (a hull vertex below the DEM surface). At that moment the
//!    depth of Λ is fixed by eq. 11, `d_max = 0.1·M^(1/3)·M_e^(−0.4)·|V⊥|^0.8` (M in kg, M_e in
//!    kN/m², V⊥ the vertical speed of the rock's centre just before it touches, m/s; the slope
//!    at the impact point is not taken into account, as in the paper). While any part of the
//!    rock is in Σ, the scar drag of eq. 9, `F_d = ½·C_d·ρ_Σ·A_Γ·|V|²` with `C_d = C_f + C_s`
//!    (eq. 12), acts at the centre of mass against the velocity; A_Γ is the frontal area of
//!    the immersed part, its projection onto the plane perpendicular to the rock's velocity
//!    (fig. 3 caption);
//! 2. **sliding**: the rock's hull meets Λ, the DEM surface lowered by d_max, as a hard contact
//!    (the scenario's ε_N, ε_T; 0 by default, as in Leine et al. 2014) with the slippage
//!    friction `μ(s) = μ_min + (2/π)(μ_max − μ_min)·atan(κ s)` (eq. 13). s grows by the centre's
//!    speed while a contact with Λ carries force (Leine et al. 2014 eq. 47) and decays by
//!    `ṡ = −β s` otherwise (eq. 14), also after the rock leaves Σ;
//! 3. **rebounding**: the rock leaves Λ and, drag still acting, Σ. The impact ends when no
//!    hull vertex is below the DEM surface; the next entry is a new impact with its own d_max.
//!
//! **Our choices, where the paper is silent** (docs/rigid-ground.md lists them with their
//! sensitivity):
//!
//! - eq. 9 writes the drag with the penetration rate |ζ̇| of the vertical drop it was derived
//!   on; with the frontal area perpendicular to the velocity (fig. 3) and the drag persisting
//!   while the rock slides and rebounds (phases 2 and 3), we take the centre's speed |V|;
//! - the immersed part is the hull cut by the DEM surface, linearly along each edge
//!   ([`crate::immersion`]); exact where the DEM is a plane under the rock;
//! - the drag is integrated implicitly over a step, `V_E = V_B / (1 + k|V_B|Δt)` with
//!   `k = ½ C_d ρ_Σ A_Γ / M`: the exact solution of `dV/dt = −k|V|V` at constant A_Γ. It never
//!   reverses the velocity and never adds energy, at any step;
//! - the ground class of an impact is that of the cell under the centre when it begins.

use crate::ground::Ground;
use crate::math::V3;
use rockfall_raster::{Field, GridGeometry};
use rockfall_scenario::{ScarringGround, ScarringSettings};

/// Depth of the rebound plane below the DEM surface, m (Lu et al. 2019 eq. 11): for a rock of
/// `mass_kg` entering soil of strength `me_mn_m2` (MN/m², converted to the kN/m² of the
/// equation) with vertical speed `v_perp_ms`.
pub fn rebound_depth_m(mass_kg: f64, me_mn_m2: f64, v_perp_ms: f64) -> f64 {
    let me_kn_m2 = me_mn_m2 * 1e3;
    0.1 * mass_kg.cbrt() * me_kn_m2.powf(-0.4) * v_perp_ms.abs().powf(0.8)
}

/// The velocity after a step `dt_s` of scar drag (eq. 9) with rate `k_per_m` = ½ C_d ρ_Σ A_Γ / M
/// (1/m): `v / (1 + k|v|Δt)`, the exact solution of `dv/dt = −k|v|v` (ours, see the module
/// docs). Its length never exceeds |v|.
pub fn after_drag(v_ms: V3, k_per_m: f64, dt_s: f64) -> V3 {
    v_ms / (1.0 + k_per_m * v_ms.length() * dt_s)
}

/// The rate k = ½ C_d ρ_Σ A_Γ / M of eq. 9, 1/m, for `ground`, frontal area `area_m2` and
/// `mass_kg`.
pub fn drag_rate_per_m(ground: &ScarringGround, area_m2: f64, mass_kg: f64) -> f64 {
    0.5 * ground.drag_coefficient() * ground.rho_kg_m3 * area_m2 / mass_kg
}

/// The scar a rock is in: its rebound plane's depth and the ground class of the impact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scar {
    /// Depth d_max of the rebound plane below the DEM surface, fixed at impact, m.
    pub depth_m: f64,
    /// The ground of the impact.
    pub ground: ScarringGround,
}

/// The ground classes of a run, per cell.
#[derive(Debug, Clone)]
pub struct ScarMap {
    /// The ground where no map is given.
    default: ScarringGround,
    /// Parameters by class number.
    by_id: Vec<Option<ScarringGround>>,
    /// Class number per cell (row-major), when a map is given.
    cells: Option<Vec<u8>>,
}

impl ScarMap {
    /// The map of `settings` with the per-cell class numbers of `map` on `grid` (none: the
    /// default class everywhere); `Err` names the first class number without a class.
    pub fn new(
        settings: &ScarringSettings,
        map: Option<&Field>,
        grid: &GridGeometry,
    ) -> Result<ScarMap, u8> {
        let mut by_id = vec![None; 256];
        for c in &settings.classes {
            by_id[usize::from(c.id)] = Some(c.params);
        }
        let cells = match map {
            None => None,
            Some(f) => {
                let mut cells = Vec::with_capacity(grid.ncols * grid.nrows);
                for row in 0..grid.nrows {
                    for col in 0..grid.ncols {
                        // nodata and out-of-range cells were refused by the scenario's checks;
                        // 0 stands for "the default class"
                        let id = f.at(row, col).map_or(0, |v| v as u8);
                        if id != 0 && by_id[usize::from(id)].is_none() {
                            return Err(id);
                        }
                        cells.push(id);
                    }
                }
                Some(cells)
            }
        };
        Ok(ScarMap {
            default: settings.default.params,
            by_id,
            cells,
        })
    }

    /// The ground of the cell under (x, y) (the default class off the grid).
    pub fn at(&self, ground: &Ground, x_m: f64, y_m: f64) -> ScarringGround {
        let id = match (&self.cells, ground.lattice().cell_index(x_m, y_m)) {
            (Some(cells), Some(i)) => cells[i],
            _ => 0,
        };
        self.by_id[usize::from(id)].unwrap_or(self.default)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Eq. 11 at Lu et al. 2019's trajectory set: 780 kg, 15 MN/m², 10.74 m/s (impact 2 of
    /// their table 2) gives 0.1·780^(1/3)·15000^(−0.4)·10.74^0.8 = 0.131 m; the depth scales as
    /// M^(1/3) and V^0.8 and falls with M_e^0.4.
    #[test]
    fn rebound_depth_follows_eq_11() {
        let d = rebound_depth_m(780.0, 15.0, 10.74);
        let want = 0.1 * 780f64.cbrt() * 15000f64.powf(-0.4) * 10.74f64.powf(0.8);
        assert!((d - want).abs() < 1e-15 && (d - 0.1313).abs() < 5e-4, "{d}");
        assert!((rebound_depth_m(8.0 * 780.0, 15.0, 10.74) / d - 2.0).abs() < 1e-12);
        assert!((rebound_depth_m(780.0, 15.0, -2.0 * 10.74) / d - 2f64.powf(0.8)).abs() < 1e-12);
        assert!((rebound_depth_m(780.0, 30.0, 10.74) / d - 2f64.powf(-0.4)).abs() < 1e-12);
        assert_eq!(rebound_depth_m(780.0, 15.0, 0.0), 0.0);
    }

    /// The drag step never speeds up, never reverses, and matches dv/dt = −k v² in closed
    /// form: v(t) = v0 / (1 + k v0 t), whatever the number of steps.
    #[test]
    fn drag_is_the_exact_quadratic_decay() {
        let v0 = V3::new(3.0, -4.0, 0.0);
        let k = 0.7;
        let one = after_drag(v0, k, 0.5);
        let mut many = v0;
        for _ in 0..500 {
            many = after_drag(many, k, 0.001);
        }
        let want = 5.0 / (1.0 + k * 5.0 * 0.5);
        assert!((one.length() - want).abs() < 1e-12);
        assert!((many.length() - want).abs() < 1e-9, "{}", many.length());
        assert!((one.normalize() - v0.normalize()).length() < 1e-12);
        assert_eq!(after_drag(v0, 0.0, 1.0), v0);
    }
}

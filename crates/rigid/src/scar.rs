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
//! - the immersed part is the hull cut by the DEM surface: the hull vertices below it and the
//!   points where the hull's edges cross it (linear along each edge), projected and wrapped in
//!   their convex hull; exact where the DEM is a plane under the rock;
//! - the drag is integrated implicitly over a step, `V_E = V_B / (1 + k|V_B|Δt)` with
//!   `k = ½ C_d ρ_Σ A_Γ / M`: the exact solution of `dV/dt = −k|V|V` at constant A_Γ. It never
//!   reverses the velocity and never adds energy, at any step;
//! - the ground class of an impact is that of the cell under the centre when it begins.

use crate::ground::{Ground, GroundContact};
use crate::math::{M3, V3, tangent_basis};
use crate::shape::RockGeometry;
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

/// Buffers of the immersion analysis, reused from step to step.
#[derive(Debug, Default, Clone)]
pub struct ImmersionScratch {
    /// Per hull vertex: its world position and how far it is below the DEM surface
    /// (vertically, m; negative above, −∞ off the DEM).
    vertices: Vec<(V3, f64, V3)>,
    /// Immersed points projected onto the plane across the velocity.
    projected: Vec<[f64; 2]>,
    /// Convex hull of the projected points.
    hull: Vec<[f64; 2]>,
}

impl ImmersionScratch {
    /// How far the deepest hull vertex of the last analysis is below the DEM surface, m
    /// (≤ 0 when none is).
    pub fn deepest_m(&self) -> f64 {
        self.vertices
            .iter()
            .map(|v| v.1)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// Analyses the rock `geom` with centre `c` and rotation `rot` against the DEM surface:
/// fills `scratch` and returns how deep its deepest vertex is below the surface, m (≤ 0:
/// not immersed).
pub fn immersion(
    ground: &Ground,
    geom: &RockGeometry,
    c: V3,
    rot: &M3,
    scratch: &mut ImmersionScratch,
) -> f64 {
    scratch.vertices.clear();
    for v in &geom.vertices_m {
        let p = c + *rot * *v;
        let entry = match ground.lattice().surface(p.x, p.y) {
            Some(s) => (p, s.z_m - p.z, V3::from_array(s.normal())),
            None => (p, f64::NEG_INFINITY, V3::Z),
        };
        scratch.vertices.push(entry);
    }
    scratch.deepest_m()
}

/// Contacts of the analysed rock with the rebound plane at `depth_m` below the DEM surface:
/// every hull vertex at least that deep, with the gap `(d − below)·n_z` along the surface
/// normal, and the DEM nodes lowered by `depth_m` inside the hull.
pub fn plane_contacts(
    ground: &Ground,
    geom: &RockGeometry,
    c: V3,
    rot: &M3,
    depth_m: f64,
    scratch: &ImmersionScratch,
    out: &mut Vec<GroundContact>,
) {
    for (k, &(p, below, n)) in scratch.vertices.iter().enumerate() {
        if below >= depth_m {
            out.push(GroundContact {
                point_m: p,
                normal: n,
                gap_m: (depth_m - below) * n.z,
                key: k as u64,
            });
        }
    }
    ground.node_contacts_below(geom, c, rot, depth_m, out);
}

/// Frontal area A_Γ of the immersed part of the analysed rock across `direction` (a unit
/// vector), m²; 0 when nothing is immersed.
pub fn frontal_area_m2(geom: &RockGeometry, direction: V3, scratch: &mut ImmersionScratch) -> f64 {
    let (t1, t2) = tangent_basis(direction);
    let ImmersionScratch {
        vertices,
        projected,
        hull,
    } = scratch;
    projected.clear();
    let project = |p: V3| [t1.dot(p), t2.dot(p)];
    for &(p, below, _) in vertices.iter() {
        if below > 0.0 {
            projected.push(project(p));
        }
    }
    if projected.is_empty() {
        return 0.0;
    }
    for &[i, j] in &geom.edges {
        let (a, b) = (vertices[i as usize], vertices[j as usize]);
        if (a.1 > 0.0) != (b.1 > 0.0) && a.1.is_finite() && b.1.is_finite() {
            let t = a.1 / (a.1 - b.1);
            projected.push(project(a.0 + (b.0 - a.0) * t));
        }
    }
    convex_area_m2(projected, hull)
}

/// Area of the convex hull of `points` (Andrew's monotone chain), m²; `hull` is a buffer.
fn convex_area_m2(points: &mut [[f64; 2]], hull: &mut Vec<[f64; 2]>) -> f64 {
    if points.len() < 3 {
        return 0.0;
    }
    points.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    hull.clear();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &[f64; 2]>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    let n = hull.len();
    let twice: f64 = (0..n)
        .map(|i| {
            let (a, b) = (hull[i], hull[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    0.5 * twice.abs()
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

    #[test]
    fn convex_area_of_a_square_with_inner_points() {
        let mut pts = vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [0.5, 0.5],
            [2.0, 3.0],
            [0.0, 3.0],
            [1.0, 3.0],
            [1.0, 1.0],
        ];
        let mut hull = Vec::new();
        assert!((convex_area_m2(&mut pts, &mut hull) - 6.0).abs() < 1e-12);
        assert_eq!(
            convex_area_m2(&mut [[0.0, 0.0], [1.0, 1.0]], &mut hull),
            0.0
        );
    }
}

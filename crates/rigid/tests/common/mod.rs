//! Builders shared by the rigid-engine physics tests: terrains made of exactly
//! representable surfaces, hand-built bodies, step parameters, energies and a stepping loop.

#![allow(dead_code)] // each test file uses part of it
#![allow(clippy::unwrap_used)]

use rockfall_raster::{Grid, GridGeometry};
use rockfall_rigid::ground::Ground;
use rockfall_rigid::rotation::rotational_energy_j;
use rockfall_rigid::shape::{RockBody, RockGeometry, box_points};
use rockfall_rigid::solver::SolverSettings;
use rockfall_rigid::stems::Stand;
use rockfall_rigid::step::{RockState, StepParams, StepReport, StepScratch, step};
use rockfall_rigid::{G_MS2, Quat, V3};
use rockfall_scenario::ContactParams;
use rockfall_terrain::{Dem, Lattice};

/// The engine's default time step, s.
pub const DT_S: f64 = 1e-3;

/// Density of the test rocks, kg/m³ (seed 001 table 1).
pub const RHO: f64 = 2700.0;

/// A grid of `ncols × nrows` cells of `cell_m` with its south-west corner at (x_min, y_min).
pub fn geometry(
    ncols: usize,
    nrows: usize,
    cell_m: f64,
    (x_min_m, y_min_m): (f64, f64),
) -> GridGeometry {
    GridGeometry {
        ncols,
        nrows,
        x_min_m,
        y_min_m,
        cell_size_m: cell_m,
    }
}

/// A DEM grid holding `f(x, y)` at every cell centre.
pub fn dem_grid(geometry: GridGeometry, f: impl Fn(f64, f64) -> f64) -> Grid<f64> {
    Grid::from_fn(geometry, |row, col| {
        let (x, y) = geometry.cell_center(row, col);
        Some(f(x, y))
    })
}

/// The ground of the DEM holding `f(x, y)` at the cell centres.
pub fn ground_from(geometry: GridGeometry, f: impl Fn(f64, f64) -> f64) -> Ground {
    let dem = Dem::new(dem_grid(geometry, f)).unwrap();
    Ground::new(Lattice::new(&dem))
}

/// A square grid of cells of `cell_m` covering at least [−half, half]² with a node (cell
/// centre) at the origin.
pub fn square(half_m: f64, cell_m: f64) -> GridGeometry {
    let n = (half_m / cell_m).ceil() as usize;
    let cells = 2 * n + 1;
    let corner = -(n as f64 + 0.5) * cell_m;
    geometry(cells, cells, cell_m, (corner, corner))
}

/// The inclined plane `z = −tanθ·y` (downhill towards +y) over [−half, half]²: bilinear
/// interpolation of an affine function is exact, so the DEM surface is the plane itself.
pub fn incline(theta_deg: f64, half_m: f64) -> Ground {
    let t = theta_deg.to_radians().tan();
    ground_from(square(half_m, 1.0), move |_, y| -t * y)
}

/// Flat ground at z = 0 over [−half, half]².
pub fn flat(half_m: f64) -> Ground {
    ground_from(square(half_m, 1.0), |_, _| 0.0)
}

/// Upward unit normal of the plane `z = −tanθ·y`.
pub fn incline_normal(theta_deg: f64) -> V3 {
    let th = theta_deg.to_radians();
    V3::new(0.0, th.sin(), th.cos())
}

/// Unit vector down the slope of `z = −tanθ·y`.
pub fn downhill(theta_deg: f64) -> V3 {
    let th = theta_deg.to_radians();
    V3::new(0.0, th.cos(), -th.sin())
}

/// The homogeneous rock of the hull of `points` at density [`RHO`].
pub fn body_of(points: &[V3]) -> RockBody {
    RockBody::new(RockGeometry::from_points(points).unwrap(), RHO).unwrap()
}

/// A box with edges `dims_m` along x, y, z.
pub fn box_body(dims_m: [f64; 3]) -> RockBody {
    body_of(&box_points(dims_m))
}

/// The orientation (body frame K → world) that puts the hull where its input points were: the
/// principal frame of a box or a sphere is not unique, so "identity" is the input frame.
pub fn input_pose(body: &RockBody) -> Quat {
    body.geometry.to_body.inverse()
}

/// A contact law.
pub fn law(mu: f64, eps_n: f64, eps_t: f64) -> ContactParams {
    ContactParams { mu, eps_n, eps_t }
}

/// Step parameters at Δt = 1 ms, standard gravity, the ground law `ground`, the stem law of
/// seed 001 (μ 0.6, ε = 0), no damping, no slippage, the default solver.
pub fn params(body: &RockBody, ground: ContactParams) -> StepParams<'_> {
    StepParams {
        body,
        dt_s: DT_S,
        gravity_ms2: V3::new(0.0, 0.0, -G_MS2),
        ground,
        tree: law(0.6, 0.0, 0.0),
        slippage: None,
        scar: None,
        linear_damping_per_s: 0.0,
        angular_damping_per_s: 0.0,
        solver: SolverSettings::default(),
    }
}

/// A rock at rest at `r_m` in orientation `q`.
pub fn at_rest(r_m: V3, q: Quat) -> RockState {
    RockState {
        r_m,
        q,
        v_ms: V3::ZERO,
        w_body_rads: V3::ZERO,
    }
}

/// Hull vertices of the rock in `state`, world frame.
pub fn vertices(body: &RockBody, state: &RockState) -> Vec<V3> {
    body.geometry
        .vertices_m
        .iter()
        .map(|&v| state.r_m + state.q * v)
        .collect()
}

/// Smallest `f(vertex)` over the hull vertices in world coordinates.
pub fn min_over_vertices(body: &RockBody, state: &RockState, f: impl Fn(V3) -> f64) -> f64 {
    vertices(body, state)
        .into_iter()
        .map(f)
        .fold(f64::INFINITY, f64::min)
}

/// Height of the lowest hull vertex, m.
pub fn lowest_z(body: &RockBody, state: &RockState) -> f64 {
    min_over_vertices(body, state, |p| p.z)
}

/// Centre of mass that sets the hull (orientation `q`) on the plane through `origin` with unit
/// normal `n`, lifted by `gap_m` along n: the lowest vertex along n touches the plane.
pub fn resting_on_plane(body: &RockBody, q: Quat, origin: V3, n: V3, gap_m: f64) -> V3 {
    let lowest = body
        .geometry
        .vertices_m
        .iter()
        .map(|&v| n.dot(q * v))
        .fold(f64::INFINITY, f64::min);
    origin + n * (gap_m - lowest)
}

/// Translational kinetic energy ½ m v², J.
pub fn translational_j(body: &RockBody, s: &RockState) -> f64 {
    0.5 * body.mass_kg * s.v_ms.length_squared()
}

/// Kinetic energy ½ m v² + ½ ΩᵀΘΩ, J.
pub fn kinetic_j(body: &RockBody, s: &RockState) -> f64 {
    translational_j(body, s) + rotational_energy_j(s.w_body_rads, body.inertia_kgm2)
}

/// Mechanical energy ½ m v² + ½ ΩᵀΘΩ − m g·r in the gravity field `g_ms2`, J.
pub fn mechanical_j(body: &RockBody, s: &RockState, g_ms2: V3) -> f64 {
    kinetic_j(body, s) - body.mass_kg * g_ms2.dot(s.r_m)
}

/// Angular momentum about the centre of mass, world frame: R Θ Ω, kg m²/s.
pub fn angular_momentum(body: &RockBody, s: &RockState) -> V3 {
    s.q * (body.inertia_kgm2 * s.w_body_rads)
}

/// Rotation angle between two orientations, rad (in [0, π]).
pub fn rotation_angle(a: Quat, b: Quat) -> f64 {
    let d = (a.inverse() * b).normalize();
    2.0 * d.w.abs().min(1.0).acos()
}

/// Steps `state` `n` times, calling `f(k, state, report)` after step k (1-based); stops early
/// when `f` returns `false`. Returns the number of steps done.
pub fn run(
    state: &mut RockState,
    p: &StepParams<'_>,
    ground: &Ground,
    stand: Option<&Stand<'_>>,
    n: usize,
    mut f: impl FnMut(usize, &RockState, &StepReport) -> bool,
) -> usize {
    let mut scratch = StepScratch::default();
    for k in 1..=n {
        let report = step(state, p, ground, stand, &mut scratch);
        assert!(
            state.is_finite(),
            "non-finite state after step {k}: {state:?}"
        );
        if !f(k, state, &report) {
            return k;
        }
    }
    n
}

/// Least-squares fit of `s = ½ a t² + v0 t + s0` to the samples; returns a.
pub fn fit_acceleration(samples: &[(f64, f64)]) -> f64 {
    // normal equations of the basis (1, t, t²/2)
    let mut m = [[0.0f64; 3]; 3];
    let mut b = [0.0f64; 3];
    for &(t, s) in samples {
        let phi = [1.0, t, 0.5 * t * t];
        for i in 0..3 {
            b[i] += phi[i] * s;
            for j in 0..3 {
                m[i][j] += phi[i] * phi[j];
            }
        }
    }
    let x = solve3(m, b);
    x[2]
}

/// Solves the 3×3 system by Cramer's rule.
fn solve3(m: [[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    let det = |a: [[f64; 3]; 3]| {
        a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
    };
    let d = det(m);
    let mut x = [0.0; 3];
    for (k, xk) in x.iter_mut().enumerate() {
        let mut a = m;
        for i in 0..3 {
            a[i][k] = b[i];
        }
        *xk = det(a) / d;
    }
    x
}

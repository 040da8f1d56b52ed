//! The engine parameters of a run, as `summary.json` records them under `parameters`.

use rockfall_engine::Plan;
use rockfall_lumped::LumpedModel;
use rockfall_rigid::RigidModel;
use rockfall_scenario::{ContactParams, Scenario};
use serde_json::{Map, Value, json};

/// The parameters of a lumped run of `scenario`.
pub fn lumped(scenario: &Scenario, plan: &Plan<LumpedModel<'_>>) -> Map<String, Value> {
    let l = &scenario.lumped;
    let first = plan.launches().first();
    let v = json!({
        "moh": l.moh.name(),
        "tangential_law": l.tangential.name(),
        "rt_variation": l.rt_variation,
        "slope_reduction_max_deg": l.slope_reduction_max_deg,
        "max_lateral_deviation_deg": l.max_lateral_deviation_deg,
        "stop_velocity_ms": l.stop_velocity_ms,
        "rn_velocity_scale_ms": l.rn_velocity_scale_ms,
        "roughness_tilt_factor": l.roughness_tilt_factor,
        "lift_off_obstacle_factor": l.lift_off_obstacle_factor,
        "max_time_s": scenario.simulation.max_time_s,
        "rocks_per_cell": scenario.simulation.rocks_per_cell,
        "rocks_per_point": scenario.simulation.rocks_per_point,
        "source_cells": scenario.release.cells.len(),
        "release_points": scenario.release.points.len(),
        "stems": plan.engine().stems(),
        "rock_mass_kg": first.map(|s| s.body.mass_kg),
        "rock_radius_m": first.map(|s| s.body.radius_m),
        "tree_energy_units": "seed 000 eq. 2 read as joules (DBH in cm)",
    });
    object(v)
}

/// The parameters of a rigid run of `scenario`.
pub fn rigid(scenario: &Scenario, model: &RigidModel<'_>) -> Map<String, Value> {
    let b = model.body();
    let g = &b.geometry;
    let c = &scenario.contact;
    let st = model.settings();
    let law = |p: &ContactParams| json!({"mu": p.mu, "eps_n": p.eps_n, "eps_t": p.eps_t});
    let v = json!({
        "rock_shape": scenario.rock.shape.describe(),
        "rock_vertices": g.vertices_m.len(),
        "rock_volume_m3": g.volume_m3,
        "rock_mass_kg": b.mass_kg,
        "rock_inertia_kgm2": [b.inertia_kgm2.x, b.inertia_kgm2.y, b.inertia_kgm2.z],
        "rock_lengths_m": g.lengths_m,
        "rock_aspect_ratio": g.aspect_ratio(),
        "rock_class": g.class().name(),
        "contact_ground": law(&c.ground),
        "contact_tree": law(&c.tree),
        "slippage": c.slippage.map(|s| json!({"mu_min": s.mu_min, "mu_max": s.mu_max, "beta_per_s": s.beta_per_s, "kappa_per_m": s.kappa_per_m})),
        "dt_s": scenario.simulation.dt_s,
        "max_time_s": scenario.simulation.max_time_s,
        "rocks_per_cell": scenario.simulation.rocks_per_cell,
        "rocks_per_point": scenario.simulation.rocks_per_point,
        "source_cells": scenario.release.cells.len(),
        "release_points": scenario.release.points.len(),
        "stems": model.stems(),
        "solver": {"alpha": st.solver.alpha, "tolerance_ms": st.solver.tolerance_ms, "max_iterations": st.solver.max_iterations, "warm_start": st.solver.warm_start},
        "stop_speed_ms": st.stop.stop_speed_ms,
        "rest_time_s": st.stop.rest_time_s,
    });
    object(v)
}

fn object(v: Value) -> Map<String, Value> {
    match v {
        Value::Object(m) => m,
        _ => Map::new(),
    }
}

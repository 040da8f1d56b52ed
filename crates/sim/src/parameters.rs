//! The engine parameters of a run, as `summary.json` records them under `parameters`: the
//! engine's settings serialised from the scenario's typed settings (keys as in the scenario
//! file), and what the engine made of the scenario (rock, stems).

use rockfall_engine::Plan;
use rockfall_lumped::LumpedModel;
use rockfall_results::{LegacySolver, LumpedParameters, RigidParameters, RunSize};
use rockfall_rigid::RigidModel;
use rockfall_scenario::{GroundModel, Scenario};

/// The parameters of a lumped run of `scenario`; the rock is the first release's.
pub fn lumped(scenario: &Scenario, plan: &Plan<LumpedModel<'_>>) -> LumpedParameters {
    let first = plan.launches().first();
    LumpedParameters {
        settings: scenario.lumped.clone(),
        size: RunSize::of(scenario, plan.engine().stems()),
        rock_mass_kg: first.map(|s| s.body.mass_kg),
        rock_radius_m: first.map(|s| s.body.radius_m),
        tree_energy_units: "seed 000 eq. 2 read as joules (DBH in cm)".into(),
    }
}

/// The parameters of a rigid run of `scenario`.
pub fn rigid(scenario: &Scenario, model: &RigidModel<'_>) -> RigidParameters {
    let b = model.body();
    let g = &b.geometry;
    RigidParameters {
        rock_shape: scenario.rock.shape.describe(),
        rock_vertices: g.vertices_m.len() as u64,
        rock_volume_m3: g.volume_m3,
        rock_mass_kg: b.mass_kg,
        rock_inertia_kgm2: [b.inertia_kgm2.x, b.inertia_kgm2.y, b.inertia_kgm2.z],
        rock_lengths_m: g.lengths_m,
        rock_aspect_ratio: g.aspect_ratio(),
        rock_class: g.class().name().into(),
        contact_ground: scenario.contact.ground,
        contact_tree: scenario.contact.tree,
        slippage: scenario.contact.slippage,
        ground_model: scenario.contact.model,
        scarring: (scenario.contact.model == GroundModel::Scarring)
            .then(|| Box::new(scenario.contact.scarring.clone())),
        dt_s: scenario.simulation.dt_s,
        size: RunSize::of(scenario, model.stems()),
        settings: scenario.rigid,
        solver: LegacySolver::from(&scenario.rigid),
    }
}

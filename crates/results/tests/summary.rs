//! `summary.json` as a [`Summary`]: the keys it had when it was built key by key, and the
//! text read back into the same summary.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{layout, lumped_parameters, rigid_parameters, simulate_rock};
use rockfall_results::{
    CellVisit, Outcome, Parameters, Results, RockEnd, RockStart, RunInfo, Summary, Tally,
};
use serde_json::Value;

/// A run of `rocks` synthetic rocks recording `parameters`.
fn run(rocks: u64, engine: &str, parameters: Parameters) -> Results {
    let mut t = Tally::new(layout());
    for i in 0..rocks {
        simulate_rock(&mut t, i);
    }
    let info = RunInfo {
        engine: engine.into(),
        scenario: "unit".into(),
        seed: 3,
        threads: 2,
        wall_time_s: 0.25,
        parameters,
    };
    Results::new(&layout(), t, info)
}

/// The keys of a JSON object, sorted.
fn keys(v: &Value) -> Vec<&str> {
    let mut k: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
    k.sort_unstable();
    k
}

fn sorted<'a>(k: &[&'a str]) -> Vec<&'a str> {
    let mut k = k.to_vec();
    k.sort_unstable();
    k
}

/// The keys `Results::summary_json` put into `summary.json` when it was built with `json!`.
const OLD_KEYS: [&str; 26] = [
    "engine",
    "scenario",
    "version",
    "seed",
    "rocks",
    "threads",
    "wall_time_s",
    "trajectories_per_s",
    "stopped_fraction",
    "net_stopped_fraction",
    "left_dem_fraction",
    "time_limit_fraction",
    "failed_fraction",
    "outcomes",
    "runout_m",
    "max_velocity_ms",
    "max_jump_height_m",
    "time_s",
    "tree_impacts_per_rock",
    "stems_broken_per_rock",
    "rebounds_per_rock",
    "cells_reached",
    "trajectory_rows",
    "screens",
    "percentile_relative_error",
    "parameters",
];
const OLD_OUTCOMES: [&str; 5] = ["stopped", "net_stopped", "left_dem", "time_limit", "failed"];
const OLD_SCREEN_KEYS: [&str; 7] = [
    "name",
    "passed_fraction",
    "rocks_passed",
    "crossings",
    "velocity_ms",
    "energy_kj",
    "jump_height_m",
];
const MEAN_P95_MAX: [&str; 3] = ["mean", "p95", "max"];
/// `lumped_parameters` of the command line before the parameters were typed.
const OLD_LUMPED_PARAMETERS: [&str; 18] = [
    "moh",
    "tangential_law",
    "rt_variation",
    "slope_reduction_max_deg",
    "max_lateral_deviation_deg",
    "stop_velocity_ms",
    "rn_velocity_scale_ms",
    "roughness_tilt_factor",
    "lift_off_obstacle_factor",
    "max_time_s",
    "rocks_per_cell",
    "rocks_per_point",
    "source_cells",
    "release_points",
    "stems",
    "rock_mass_kg",
    "rock_radius_m",
    "tree_energy_units",
];
/// `rigid_parameters` of the command line before the parameters were typed.
const OLD_RIGID_PARAMETERS: [&str; 21] = [
    "rock_shape",
    "rock_vertices",
    "rock_volume_m3",
    "rock_mass_kg",
    "rock_inertia_kgm2",
    "rock_lengths_m",
    "rock_aspect_ratio",
    "rock_class",
    "contact_ground",
    "contact_tree",
    "slippage",
    "dt_s",
    "max_time_s",
    "rocks_per_cell",
    "rocks_per_point",
    "source_cells",
    "release_points",
    "stems",
    "solver",
    "stop_speed_ms",
    "rest_time_s",
];
/// What the rigid parameters gained: the `[rigid]` settings under their scenario-file keys.
/// Keys added since: the engine's events (flight arcs and rolling steps, or time steps), and
/// the shares of the modes of motion (rigid engine; `null` for the lumped one), the rocks
/// the ground held where they were released.
const NEW_KEYS: [&str; 7] = [
    "events",
    "events_per_rock",
    "motion",
    "held_at_release",
    "held_at_release_fraction",
    "cell_statistics_bytes",
    "cell_statistics_bytes_per_reached_cell",
];

/// What the lumped parameters gained: the scale of the ground material's rolling friction.
const NEW_LUMPED_PARAMETERS: [&str; 1] = ["soil_friction_scale"];

const NEW_RIGID_PARAMETERS: [&str; 9] = [
    "solver_alpha",
    "solver_tolerance_ms",
    "solver_max_iterations",
    "warm_start",
    "max_speed_ms",
    "linear_damping_per_s",
    "angular_damping_per_s",
    "ground_model",
    "scarring",
];

#[test]
fn the_summary_has_exactly_the_keys_of_the_old_construction() {
    let s = run(200, "lumped", lumped_parameters()).summary_json();
    let all: Vec<&str> = OLD_KEYS.iter().chain(&NEW_KEYS).copied().collect();
    assert_eq!(keys(&s), sorted(&all));
    assert_eq!(keys(&s["outcomes"]), sorted(&OLD_OUTCOMES));
    assert_eq!(keys(&s["runout_m"]), sorted(&["p50", "p95", "max", "mean"]));
    for k in ["max_velocity_ms", "max_jump_height_m"] {
        assert_eq!(keys(&s[k]), sorted(&MEAN_P95_MAX), "{k}");
    }
    assert_eq!(keys(&s["time_s"]), sorted(&["mean", "max"]));
    let screens = s["screens"].as_array().unwrap();
    assert_eq!(screens.len(), 2);
    for sc in screens {
        assert_eq!(keys(sc), sorted(&OLD_SCREEN_KEYS));
        for k in ["velocity_ms", "energy_kj", "jump_height_m"] {
            assert_eq!(keys(&sc[k]), sorted(&MEAN_P95_MAX), "{k}");
        }
        // counts are integers, never `3.0`
        assert!(sc["rocks_passed"].is_u64() && sc["crossings"].is_u64());
    }
    for k in [
        "seed",
        "rocks",
        "threads",
        "cells_reached",
        "trajectory_rows",
    ] {
        assert!(s[k].is_u64(), "{k}: {}", s[k]);
    }
    for k in OLD_OUTCOMES {
        assert!(s["outcomes"][k].is_u64(), "{k}");
    }
    assert_eq!(s["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(s["percentile_relative_error"], 0.0746079);

    let p = &s["parameters"];
    let lumped: Vec<&str> = (OLD_LUMPED_PARAMETERS.iter())
        .chain(&NEW_LUMPED_PARAMETERS)
        .copied()
        .collect();
    assert_eq!(keys(p), sorted(&lumped));
    assert_eq!(p["moh"], "draw");
    assert_eq!(p["tangential_law"], "pfeiffer-bowen");
    for k in [
        "rocks_per_cell",
        "rocks_per_point",
        "source_cells",
        "release_points",
        "stems",
    ] {
        assert!(p[k].is_u64(), "{k}");
    }

    let s = run(200, "rigid", rigid_parameters(0.001)).summary_json();
    let p = &s["parameters"];
    let mut rigid = OLD_RIGID_PARAMETERS.to_vec();
    rigid.extend(NEW_RIGID_PARAMETERS);
    assert_eq!(keys(p), sorted(&rigid));
    assert_eq!(
        keys(&p["solver"]),
        sorted(&["alpha", "tolerance_ms", "max_iterations", "warm_start"])
    );
    for law in ["contact_ground", "contact_tree"] {
        assert_eq!(keys(&p[law]), sorted(&["mu", "eps_n", "eps_t"]));
    }
    assert_eq!(
        keys(&p["slippage"]),
        sorted(&["mu_min", "mu_max", "beta_per_s", "kappa_per_m"])
    );
    assert!(p["rock_vertices"].is_u64() && p["solver"]["max_iterations"].is_u64());
    assert!(p["solver_max_iterations"].is_u64());
    // the old solver object and the new keys hold the same values
    assert_eq!(p["solver"]["alpha"], p["solver_alpha"]);
    assert_eq!(p["solver"]["tolerance_ms"], p["solver_tolerance_ms"]);
    assert_eq!(p["solver"]["max_iterations"], p["solver_max_iterations"]);
    assert_eq!(p["solver"]["warm_start"], p["warm_start"]);

    assert_eq!(
        run(0, "lumped", Parameters::None).summary_json()["parameters"],
        serde_json::json!({})
    );
}

/// `summary` written as `summary.json` is, then read back.
fn round_trip(summary: &Summary) -> Summary {
    let text = serde_json::to_string_pretty(&serde_json::to_value(summary).unwrap()).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn a_summary_reads_back_as_itself() {
    for (engine, parameters) in [
        ("lumped", lumped_parameters()),
        ("rigid", rigid_parameters(0.001)),
    ] {
        let r = run(300, engine, parameters.clone());
        let s = r.summary();
        assert_eq!(round_trip(&s), s, "{engine}");
        assert_eq!(s.parameters, parameters);
        // the file holds the same text as the summary written again
        let dir = tempfile::tempdir().unwrap();
        r.write(dir.path(), false).unwrap();
        let text = std::fs::read_to_string(dir.path().join("summary.json")).unwrap();
        let back: Summary = serde_json::from_str(&text).unwrap();
        assert_eq!(back, s, "{engine}");
        let again = serde_json::to_string_pretty(&serde_json::to_value(&back).unwrap()).unwrap();
        assert_eq!(again + "\n", text, "{engine}");
    }
}

#[test]
fn a_summary_without_rocks_reads_back_with_its_nulls() {
    for parameters in [
        Parameters::None,
        lumped_parameters(),
        rigid_parameters(0.01),
    ] {
        let s = run(0, "lumped", parameters).summary();
        assert_eq!(s.rocks, 0);
        assert_eq!(s.stopped_fraction, None);
        assert_eq!(s.runout_m.p50, None);
        assert_eq!(s.max_velocity_ms.mean, None);
        assert_eq!(s.screens[0].passed_fraction, None);
        assert_eq!(s.screens[0].energy_kj.max, None);
        let v = serde_json::to_value(&s).unwrap();
        assert!(v["stopped_fraction"].is_null() && v["time_s"]["max"].is_null());
        assert_eq!(round_trip(&s), s);
    }
}

#[test]
fn summaries_of_other_shapes_are_refused() {
    // a rigid summary without its rock, a lumped one without its law
    let mut v = run(10, "rigid", rigid_parameters(0.001)).summary_json();
    v["parameters"]
        .as_object_mut()
        .unwrap()
        .remove("rock_mass_kg");
    let e = serde_json::from_value::<Summary>(v)
        .unwrap_err()
        .to_string();
    assert!(e.contains("rock_mass_kg"), "{e}");
    let mut v = run(10, "lumped", lumped_parameters()).summary_json();
    v["parameters"].as_object_mut().unwrap().remove("moh");
    let e = serde_json::from_value::<Summary>(v)
        .unwrap_err()
        .to_string();
    assert!(e.contains("moh"), "{e}");
    let mut v = run(10, "lumped", lumped_parameters()).summary_json();
    v["parameters"]["tangential_law"] = "sideways".into();
    let e = serde_json::from_value::<Summary>(v)
        .unwrap_err()
        .to_string();
    assert!(e.contains("sideways"), "{e}");
}

/// One rock of a hand-made run: released from cell 0, visiting `cells`, hitting a tree in
/// `tree_cell`, ending as `outcome`.
fn hand_rock(t: &mut Tally, rock_id: u64, cells: &[usize], tree_cell: usize, outcome: Outcome) {
    t.begin_rock(RockStart {
        rock_id,
        source_cell: 0,
        x_m: 1001.0,
        y_m: 5009.0,
        z_m: 100.0,
        volume_m3: 1.0,
        mass_kg: 2700.0,
    });
    for &cell in cells {
        let visit = CellVisit {
            energy_j: 1e3,
            velocity_ms: 3.0,
            passing_height_m: 0.5,
        };
        t.cell_visit(cell, visit);
    }
    t.tree_impact(tree_cell, 1.0, false);
    t.end_rock(RockEnd {
        outcome,
        x_m: 1005.0,
        y_m: 5001.0,
        runout_m: 4.0,
        max_velocity_ms: 3.0,
        max_jump_height_m: 0.5,
        tree_impacts: 1,
        stems_broken: 0,
        rebounds: 2,
        time_s: 1.0,
        events: 7,
        motion: Default::default(),
    });
}

/// `cells_reached` counts the cells some rock went through, not every cell the tallies
/// touched: a stem hit across a cell border and a deposit are kept in cells no rock visited.
/// The outcome shares count a net's rocks among the stopped ones.
#[test]
fn cells_reached_are_the_cells_rocks_went_through() {
    let mut t = Tally::new(layout());
    hand_rock(&mut t, 0, &[1, 2], 8, Outcome::Stopped { cell: 2 });
    hand_rock(&mut t, 1, &[2], 2, Outcome::NetStopped { cell: 14 });
    let s = Results::new(&layout(), t, RunInfo::default()).summary();
    assert_eq!(s.rocks, 2);
    assert_eq!(s.cells_reached, 2);
    assert_eq!(s.stopped_fraction, Some(1.0));
    assert_eq!(s.net_stopped_fraction, Some(0.5));
    assert_eq!(s.tree_impacts_per_rock, Some(1.0));
    assert_eq!(s.rebounds_per_rock, Some(2.0));
    assert_eq!((s.events, s.events_per_rock), (14, Some(7.0)));
}

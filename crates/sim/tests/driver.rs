//! The driver's promises: both engines run through it alike; overrides come before anything
//! random (a stand forest included); tallies of disjoint rock sets merge exactly into the
//! tally of their union, for both engines.

#![allow(clippy::unwrap_used)]

use rockfall_engine::RockSet;
use rockfall_forest::StandOptions;
use rockfall_raster::Field;
use rockfall_results::{Layout, Results, RunInfo, Tally};
use rockfall_scenario::{Engine, ForestSpec, Scenario, Stands};
use rockfall_sim::{Overrides, Quiet, Simulation, simulate};
use std::sync::Arc;

/// vaujany-site2 (lumped, its forest) with `rocks` rocks.
fn lumped_site(rocks: u64) -> Scenario {
    let mut s = rockfall_sites::build("vaujany-site2").unwrap();
    s.simulation.rocks_per_cell = rocks;
    s
}

/// forest-slope-40 (rigid, its forest) with `rocks` rocks per point, cut short at 6 s.
fn rigid_site(rocks: u64) -> Scenario {
    let mut s = rockfall_sites::build("forest-slope-40").unwrap();
    s.simulation.rocks_per_point = rocks;
    s.simulation.rocks_per_cell = rocks;
    s.simulation.max_time_s = 6.0;
    s
}

fn threads(n: usize) -> Overrides {
    Overrides {
        threads: Some(n),
        ..Overrides::default()
    }
}

/// Everything a run's results say, but the timings: summary, rasters, paths and rock records.
fn fingerprint(r: &Results) -> String {
    let mut s = r.summary_json();
    if let Some(m) = s.as_object_mut() {
        for k in ["wall_time_s", "trajectories_per_s", "threads"] {
            m.remove(k);
        }
    }
    let mut out = s.to_string();
    for name in r.raster_names() {
        let g = r.raster(&name).unwrap();
        let bits: Vec<u64> = g.values().iter().map(|v| v.to_bits()).collect();
        out += &format!("\n{name} {bits:?}");
    }
    out += &format!("\n{:?}\n{:?}", r.trajectories(), r.rock_records());
    out
}

#[test]
fn both_engines_run_through_the_one_driver() {
    for (scenario, engine, rocks) in [
        (lumped_site(200), "lumped", 200),
        (
            rigid_site(1),
            "rigid",
            rigid_site(1).release.points.len() as u64,
        ),
    ] {
        let kind = scenario.engine;
        let r = simulate(scenario, &threads(2)).unwrap();
        let s = r.summary_json();
        assert_eq!(s["engine"], engine);
        assert_eq!(kind.to_string(), engine);
        assert_eq!(r.rocks(), rocks, "{engine}");
        assert!(
            s["parameters"]["stems"].as_u64().unwrap() > 0,
            "{engine}: {s}"
        );
        assert!(r.raster("Nr_passages").is_some());
    }
}

#[test]
fn the_engine_override_picks_the_engine() {
    // the rigid engine on seed 000's site: spheres are a block shape it can build
    let o = Overrides {
        engine: Some(Engine::Rigid),
        rocks_per_cell: Some(1),
        ..threads(2)
    };
    let mut s = lumped_site(1);
    s.simulation.max_time_s = 3.0;
    s.forest = None;
    let r = simulate(s, &o).unwrap();
    assert_eq!(r.summary_json()["engine"], "rigid");
    assert_eq!(r.rocks(), 1);
}

#[test]
fn rocks_and_seed_overrides_equal_the_same_values_in_the_scenario() {
    let o = Overrides {
        seed: Some(7),
        rocks_per_cell: Some(150),
        ..threads(2)
    };
    let by_override = simulate(lumped_site(400), &o).unwrap();
    let mut s = lumped_site(150);
    s.seed = 7;
    let in_file = simulate(s, &threads(1)).unwrap();
    assert_eq!(fingerprint(&by_override), fingerprint(&in_file));
    assert_eq!(by_override.rocks(), 150);
    let other_seed = simulate(lumped_site(150), &threads(2)).unwrap();
    assert_ne!(fingerprint(&by_override), fingerprint(&other_seed));
}

/// A stand map is expanded into stems from the seed: the seed override must come first.
#[test]
fn a_stand_forest_is_expanded_from_the_overridden_seed() {
    let mut s = lumped_site(100);
    s.forest = Some(ForestSpec::Stands(Box::new(Stands {
        stems_per_ha: Field::Const(400.0),
        dbh_mean_cm: Field::Const(30.0),
        dbh_sd_cm: Field::Const(10.0),
        conifer_percent: Field::Const(50.0),
        height_m: None,
        options: StandOptions::default(),
    })));
    let seeded = |seed: u64, file_seed: u64| {
        let mut sc = s.clone();
        sc.seed = file_seed;
        let o = Overrides {
            seed: Some(seed),
            ..threads(2)
        };
        Simulation::new(sc, &o).unwrap()
    };
    let (a, b) = (seeded(5, 1), seeded(5, 5));
    assert!(!a.forest().is_empty());
    assert_eq!(a.forest().stems(), b.forest().stems());
    assert_ne!(a.forest().stems(), seeded(6, 5).forest().stems());
    let (ra, rb) = (
        a.run(true, "", &Quiet).unwrap(),
        b.run(true, "", &Quiet).unwrap(),
    );
    assert_eq!(fingerprint(&ra), fingerprint(&rb));
}

/// Runs `rocks` of `sim` into a tally on `layout`.
fn tally(sim: &Simulation, layout: &Arc<Layout>, rocks: RockSet) -> Tally {
    sim.tally(layout, &rocks).unwrap()
}

fn merged_equals_union(scenario: Scenario, split: &[std::ops::Range<u64>]) {
    let total = rockfall_sim::rocks(&scenario);
    let sim = Simulation::new(scenario, &threads(2)).unwrap();
    let layout = Arc::new(Layout {
        rock_ends: true,
        trajectories: u64::MAX,
        ..Layout::of(sim.scenario())
    });
    let part = RockSet::from_ranges(split.iter().cloned());
    let rest = RockSet::from_ranges(
        std::iter::once(0..total)
            .flat_map(|r| r.filter(|id| !part.contains(*id)).map(|id| id..id + 1)),
    );
    assert!(!part.is_empty() && !rest.is_empty() && part.len() + rest.len() == total);
    let mut merged = tally(&sim, &layout, rest);
    merged.merge(tally(&sim, &layout, part));
    let union = tally(&sim, &layout, RockSet::all(total));
    let results = |t| Results::new(&layout, t, RunInfo::default());
    let (m, u) = (results(merged), results(union));
    assert_eq!(m.rocks(), total);
    assert_eq!(fingerprint(&m), fingerprint(&u));
    // and the whole run through the driver is that union too
    let run = sim.run(true, "", &Quiet).unwrap();
    assert_eq!(run.rocks(), total);
}

#[test]
fn lumped_tallies_of_disjoint_rock_sets_merge_into_the_tally_of_their_union() {
    merged_equals_union(lumped_site(300), &[3..40, 77..78, 200..260]);
}

#[test]
fn rigid_tallies_of_disjoint_rock_sets_merge_into_the_tally_of_their_union() {
    let s = rigid_site(2);
    assert!(rockfall_sim::rocks(&s) >= 2);
    merged_equals_union(s, &[1..2, 5..5]);
}

//! The driver's promises: both engines run through it alike; overrides come before anything
//! random (a stand forest included); tallies of disjoint rock sets merge exactly into the
//! tally of their union, for both engines.

#![allow(clippy::unwrap_used)]

use rockfall_engine::{PoolError, RockSet};
use rockfall_forest::StandOptions;
use rockfall_raster::Field;
use rockfall_results::{Layout, Parameters, Results, RunInfo, Tally};
use rockfall_scenario::{Engine, ForestSpec, ReleasePoint, RockSpec, Scenario, Stands};
use rockfall_sim::{Overrides, Quiet, RigidRock, SimError, Simulation, simulate};
use std::path::Path;
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
    // a set reaching past the last rock runs the rocks there are, no more
    let past = tally(
        &sim,
        &layout,
        RockSet::from_ranges(std::iter::once(0..total + 7)),
    );
    assert_eq!(fingerprint(&results(past)), fingerprint(&u));
    // and the whole run through the driver is that union too, forest included: a partial
    // tally is a part of the run, not of a run without trees
    let run = sim.run(true, "", &Quiet).unwrap();
    assert_eq!(run.rocks(), total);
    let own = Arc::new(Layout::of(sim.scenario()));
    let s = run.summary();
    let info = RunInfo {
        engine: s.engine,
        scenario: s.scenario,
        seed: s.seed,
        threads: 2,
        wall_time_s: 1.0,
        parameters: s.parameters,
    };
    let whole = Results::new(&own, tally(&sim, &own, RockSet::all(total)), info);
    assert_eq!(fingerprint(&whole), fingerprint(&run));
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

/// Every scenario override reaches the scenario as simulated — `--rocks-per-point` as well as
/// the others — and the threads override the workers.
#[test]
fn every_override_reaches_the_scenario() {
    let s = rigid_site(1);
    let points = s.release.points.len() as u64;
    let cells = s.release.cells.len() as u64;
    assert!(points > 0);
    let o = Overrides {
        seed: Some(9),
        rocks_per_cell: Some(4),
        rocks_per_point: Some(3),
        engine: Some(Engine::Lumped),
        threads: Some(3),
        until_stable_pct: Some(0.5),
    };
    let sim = Simulation::new(s, &o).unwrap();
    let sc = sim.scenario();
    assert_eq!(sc.seed, 9);
    assert_eq!(sc.simulation.rocks_per_cell, 4);
    assert_eq!(sc.simulation.rocks_per_point, 3);
    assert_eq!(sc.engine, Engine::Lumped);
    assert_eq!(sim.threads(), 3);
    assert_eq!(sc.simulation.until_stable_pct, Some(0.5));
    assert_eq!(rockfall_sim::rocks(sc), 4 * cells + 3 * points);
}

/// The overridden scenario is validated before anything runs (an override can make it
/// invalid), and the error names the file its parameter came from; an engine that cannot
/// start names the file of the rock (for a lumped run, `rockdensity`: a Rockyfor3D folder's
/// source cells); only a pool that cannot start is not the input's fault.
#[test]
fn errors_are_found_before_anything_runs_and_name_their_file() {
    let mut s = lumped_site(10);
    let toml = Path::new("in/scenario.toml");
    s.sources
        .insert("simulation.rocks_per_cell".into(), toml.into());
    let o = Overrides {
        rocks_per_cell: Some(0),
        ..threads(2)
    };
    let e = Simulation::new(s.clone(), &o).unwrap_err();
    assert!(matches!(e, SimError::Scenario { .. }), "{e:?}");
    assert!(e.is_bad_input());
    assert_eq!(e.file(), Some(toml));
    assert!(e.to_string().starts_with("in/scenario.toml: "), "{e}");

    // the lumped engine has no use for a named seed 001 shape
    s.rock = RockSpec::named("cubic1.2", None, 2700.0).unwrap();
    let density = Path::new("in/rockdensity.asc");
    s.sources.insert("rockdensity".into(), density.into());
    s.sources.insert("dem".into(), "in/dem.asc".into());
    let e = simulate(s, &threads(2)).unwrap_err();
    assert!(matches!(e, SimError::Engine { .. }), "{e:?}");
    assert!(e.is_bad_input());
    assert_eq!(e.file(), Some(density));

    let pool = SimError::Pool(PoolError(4));
    assert!(!pool.is_bad_input());
    assert_eq!(pool.file(), None);
}

/// `summary.json`'s parameters are those of the run: the engine settings of the scenario as
/// simulated (not the defaults), its size (source cells, points, rocks, stems), the rock the
/// engine made of it.
#[test]
fn the_parameters_are_the_runs_settings_size_and_rock() {
    let mut s = lumped_site(20);
    s.rock = RockSpec::sphere(0.8, 2500.0);
    s.lumped.roughness_tilt_factor = 0.5;
    s.lumped.rt_variation = 0.2;
    let sim = Simulation::new(s, &threads(2)).unwrap();
    let stems = sim.forest().len() as u64;
    assert!(stems > 0);
    let r = sim.run(true, "", &Quiet).unwrap();
    let Parameters::Lumped(p) = r.summary().parameters else {
        panic!("not lumped")
    };
    assert_eq!(p.settings, sim.scenario().lumped);
    assert_eq!(p.settings.roughness_tilt_factor, 0.5);
    let size = (
        p.size.rocks_per_cell,
        p.size.source_cells,
        p.size.release_points,
    );
    assert_eq!(size, (20, 1, 0));
    assert_eq!((p.size.stems, p.size.max_time_s), (stems, 600.0));
    let (radius, mass) = (
        0.4,
        2500.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.4f64.powi(3),
    );
    assert!((p.rock_radius_m.unwrap() - radius).abs() < 1e-12, "{p:?}");
    assert!(
        (p.rock_mass_kg.unwrap() / mass - 1.0).abs() < 1e-12,
        "{p:?}"
    );

    let mut s = rigid_site(1);
    s.simulation.max_time_s = 1.0;
    s.rigid.solver_max_iterations = 77;
    s.rigid.rest_time_s = 0.7;
    let sim = Simulation::new(s, &threads(2)).unwrap();
    let sc = sim.scenario();
    let r = sim.run(true, "", &Quiet).unwrap();
    let Parameters::Rigid(p) = r.summary().parameters else {
        panic!("not rigid")
    };
    assert_eq!(p.settings, sc.rigid);
    assert_eq!((p.solver.max_iterations, p.settings.rest_time_s), (77, 0.7));
    assert_eq!(
        (p.dt_s, p.contact_ground),
        (sc.simulation.dt_s, sc.contact.ground)
    );
    let size = (
        p.size.rocks_per_point,
        p.size.source_cells,
        p.size.release_points,
    );
    assert_eq!(size, (1, 0, 1));
    assert_eq!(p.size.stems, sim.forest().len() as u64);
    let rock = RigidRock::of(sc).unwrap();
    assert_eq!(
        (p.rock_mass_kg, p.rock_vertices),
        (rock.mass_kg, rock.vertices as u64)
    );
}

/// Every rock reports under its global number (release after release) and the cell it was
/// released from — for a release point, the cell the point lies in — in `rocks.csv` and the
/// trajectories, on both engines.
#[test]
fn rocks_report_their_global_number_and_source_cell() {
    let mut s = lumped_site(1);
    let g = *s.terrain.dem.geometry();
    let c0 = s.release.cells[0];
    let (row, col) = g.row_col(c0);
    let (x0, y0) = g.cell_center(row, col);
    let d = g.cell_size_m;
    s.release.points = vec![
        ReleasePoint::at_rest(x0 + d + 0.3, y0 - 0.4, 0.5),
        ReleasePoint::at_rest(x0 - 2.0 * d - 0.3, y0 + 0.2, 0.5),
    ];
    s.simulation.rocks_per_point = 2;
    s.simulation.max_time_s = 1.0;
    s.output.rocks_csv = true;
    s.output.trajectories = u64::MAX;
    s.forest = None;
    let (c1, c2) = (g.index(row, col + 1), g.index(row, col - 2));
    for engine in [Engine::Lumped, Engine::Rigid] {
        let o = Overrides {
            engine: Some(engine),
            ..threads(2)
        };
        let r = simulate(s.clone(), &o).unwrap();
        let records: Vec<(u64, usize)> = (r.rock_records().iter())
            .map(|rec| (rec.rock_id, rec.source_cell))
            .collect();
        let expected = [(0, c0), (1, c1), (2, c1), (3, c2), (4, c2)];
        assert_eq!(records, expected, "{engine}");
        let mut ids: Vec<u64> = r.trajectories().iter().map(|row| row.rock_id).collect();
        ids.dedup();
        ids.sort_unstable();
        ids.dedup();
        assert_eq!(ids, [0, 1, 2, 3, 4], "{engine}");
    }
}

/// A scenario built by hand that lists a source cell twice (or out of order) is refused: the
/// two releases would share one random-stream key, and their rocks would be copies.
#[test]
fn a_source_cell_listed_twice_is_refused() {
    for twice in [true, false] {
        let mut s = lumped_site(10);
        let c = s.release.cells[0];
        s.release.cells = if twice { vec![c, c] } else { vec![c + 1, c] };
        let e = Simulation::new(s, &threads(1)).unwrap_err();
        let text = e.to_string();
        assert!(e.is_bad_input(), "{text}");
        assert!(
            text.contains("release.cells") && text.contains("once each"),
            "{text}"
        );
    }
}

/// An observer that sets its cancel flag once `after` rocks are done, and counts the rocks.
struct Stopping {
    flag: std::sync::atomic::AtomicBool,
    done: std::sync::atomic::AtomicU64,
    after: u64,
}

impl rockfall_sim::Observer for Stopping {
    fn advanced(&self, rocks: u64) {
        use std::sync::atomic::Ordering::Relaxed;
        if self.done.fetch_add(rocks, Relaxed) + rocks >= self.after {
            self.flag.store(true, Relaxed);
        }
    }
    fn cancel_flag(&self) -> Option<&std::sync::atomic::AtomicBool> {
        Some(&self.flag)
    }
}

/// A run whose observer raises its cancel flag stops taking rocks and ends in
/// `SimError::Cancelled` (not bad input), on both engines, having run far fewer rocks than
/// asked; a flag never raised changes nothing.
#[test]
fn a_cancelled_run_stops_early_and_says_so() {
    for (scenario, rocks) in [(lumped_site(20_000), 20_000), (rigid_site(200), 200)] {
        let sim = Simulation::new(scenario, &threads(2)).unwrap();
        let stop = Stopping {
            flag: false.into(),
            done: 0.into(),
            after: 1,
        };
        let err = sim.run(true, "x", &stop).unwrap_err();
        assert!(matches!(err, SimError::Cancelled), "{err}");
        assert!(!err.is_bad_input());
        let done = stop.done.load(std::sync::atomic::Ordering::Relaxed);
        assert!(
            done < rocks / 4,
            "{done} of {rocks} rocks ran after the flag"
        );
    }
    let sim = Simulation::new(lumped_site(200), &threads(2)).unwrap();
    let never = Stopping {
        flag: false.into(),
        done: 0.into(),
        after: u64::MAX,
    };
    let a = sim.run(true, "x", &never).unwrap();
    let b = sim.run(true, "x", &Quiet).unwrap();
    assert_eq!(fingerprint(&a), fingerprint(&b));
}

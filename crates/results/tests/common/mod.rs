//! Shared helpers of the integration tests: a small layout and a seeded pseudo-random stream
//! of rock events.
#![allow(dead_code)]

use std::sync::Arc;

use rockfall_raster::{Crs, GridGeometry};
use rockfall_results::{
    CellVisit, Event, Layout, LegacySolver, LumpedParameters, Outcome, Parameters, Results,
    RigidParameters, RockEnd, RockStart, RunInfo, RunSize, ScreenCrossing, Tally, TrajectoryRow,
};
use rockfall_scenario::{ContactSettings, LumpedSettings, RigidParams, Screen, Slippage};

/// 6 columns × 5 rows of 2 m, lower-left corner (1000, 5000), EPSG:2056, two screens.
pub fn layout() -> Arc<Layout> {
    Arc::new(Layout {
        geometry: GridGeometry {
            ncols: 6,
            nrows: 5,
            x_min_m: 1000.0,
            y_min_m: 5000.0,
            cell_size_m: 2.0,
        },
        crs: Some(Crs::from_epsg(2056)),
        screens: vec![
            Screen {
                name: "upper".into(),
                points_m: vec![[1000.0, 5006.0], [1012.0, 5006.0]],
                capacity_kj: None,
                height_m: None,
                net: None,
            },
            Screen {
                name: "lower".into(),
                points_m: vec![[1000.0, 5002.0], [1006.0, 5003.0], [1012.0, 5002.0]],
                capacity_kj: None,
                height_m: None,
                net: None,
            },
        ],
        percentiles: vec![50.0, 99.5, 95.0],
        energy_thresholds_kj: vec![0.1, 1.0],
        trajectories: 7,
        rock_ends: false,
        screen_crossings: false,
        elevation: Default::default(),
        trusted: Default::default(),
    })
}

/// A 64-bit LCG (Knuth's MMIX constants).
pub struct Lcg(pub u64);

impl Lcg {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 11
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.next_u64() as f64 / (1u64 << 53) as f64
    }

    /// Uniform in 0 .. n.
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }

    /// Log-uniform over `decades` decades from `lo`.
    pub fn log(&mut self, lo: f64, decades: f64) -> f64 {
        lo * 10f64.powf(decades * self.unit())
    }
}

/// Simulates rock `rock_id` into `tally`: a pseudo-random but reproducible stream of events
/// depending only on the rock id (as the real engines' streams do).
/// The end of a rock that left the DEM after 1 m, 1 s, at 1 m/s and 1 m high at most.
pub fn left_dem() -> RockEnd {
    RockEnd {
        outcome: Outcome::LeftDem,
        x_m: 0.0,
        y_m: 0.0,
        runout_m: 1.0,
        max_velocity_ms: 1.0,
        max_jump_height_m: 1.0,
        tree_impacts: 0,
        stems_broken: 0,
        rebounds: 0,
        time_s: 1.0,
        events: 0,
        motion: Default::default(),
    }
}

pub fn simulate_rock(tally: &mut Tally, rock_id: u64) {
    let mut r = Lcg(rock_id.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ 0x1234_5678);
    let ncells = tally.layout().geometry.len() as u64;
    let source = r.below(4) as usize;
    tally.begin_rock(RockStart {
        rock_id,
        source_cell: source,
        x_m: 1001.0,
        y_m: 5009.0,
        z_m: 100.0,
        volume_m3: 1.0,
        mass_kg: 2700.0,
    });
    let mut t = 0.0;
    for step in 0..(1 + r.below(12)) {
        let cell = r.below(ncells) as usize;
        tally.cell_visit(
            cell,
            CellVisit {
                energy_j: if r.below(20) == 0 {
                    0.0
                } else {
                    r.log(0.1, 8.0)
                },
                velocity_ms: r.log(0.01, 3.5),
                passing_height_m: r.log(1e-4, 5.0),
            },
        );
        if r.below(5) == 0 {
            tally.tree_impact(cell, r.unit() * 8.0, r.below(3) == 0);
        }
        if r.below(4) == 0 {
            let screen = r.below(2) as usize;
            tally.screen_crossing(
                screen,
                ScreenCrossing {
                    velocity_ms: r.log(0.1, 2.0),
                    energy_j: r.log(10.0, 6.0),
                    jump_height_m: r.unit() * 3.0,
                    x_m: 0.0,
                    y_m: 0.0,
                },
            );
        }
        t += r.unit() * 0.37;
        if tally.records() {
            tally.record(TrajectoryRow {
                rock_id,
                t_s: t,
                x_m: 1000.0 + r.unit() * 12.0,
                y_m: 5000.0 + r.unit() * 10.0,
                z_m: r.unit() * 100.0,
                vx_ms: r.unit(),
                vy_ms: -r.unit(),
                vz_ms: r.unit() - 0.5,
                wx_rads: 0.1,
                wy_rads: 0.2,
                wz_rads: 1.0 / 3.0,
                e_trans_j: r.log(1.0, 5.0),
                e_rot_j: r.log(1.0, 3.0),
                event: [Event::Flight, Event::Impact, Event::Roll, Event::Tree][step as usize % 4],
            });
        }
    }
    let outcome = match r.below(6) {
        0 | 1 => Outcome::Stopped {
            cell: r.below(ncells) as usize,
        },
        2 => Outcome::NetStopped {
            cell: r.below(ncells) as usize,
        },
        3 => Outcome::LeftDem,
        4 => Outcome::TimeLimit,
        _ => Outcome::Failed,
    };
    tally.end_rock(RockEnd {
        outcome,
        x_m: 1005.0,
        y_m: 5001.0,
        runout_m: r.log(0.5, 3.0),
        max_velocity_ms: r.log(1.0, 1.5),
        max_jump_height_m: r.log(0.01, 2.0),
        tree_impacts: r.below(4) as u32,
        stems_broken: r.below(2) as u32,
        rebounds: r.below(9) as u32,
        time_s: t,
        events: r.below(50) as u32,
        motion: rockfall_results::Motion::from_array([0; 5].map(|_| r.log(0.001, 3.0))),
    });
}

/// Lumped-engine parameters as a run of the default scenario settings records them.
pub fn lumped_parameters() -> Parameters {
    Parameters::Lumped(LumpedParameters {
        settings: LumpedSettings::default(),
        size: size(),
        rock_mass_kg: Some(1256.9774006400553),
        rock_radius_m: Some(0.4749999999999999),
        tree_energy_units: "seed 000 eq. 2 read as joules (DBH in cm)".into(),
    })
}

/// Rigid-engine parameters with the default settings and a time step of `dt_s`.
pub fn rigid_parameters(dt_s: f64) -> Parameters {
    let contact = ContactSettings::default();
    let settings = RigidParams::default();
    Parameters::Rigid(RigidParameters {
        rock_shape: "cubic1.2".into(),
        rock_vertices: 100,
        rock_volume_m3: 0.020000000000000004,
        rock_mass_kg: 54.00000000000001,
        rock_inertia_kgm2: [0.5671454909719857, 0.6046061072747274, 0.6982751108487305],
        rock_lengths_m: [0.36660269175904725, 0.34914745626840127, 0.2991830931004344],
        rock_aspect_ratio: 1.2253456168259496,
        rock_class: "cubic".into(),
        contact_ground: contact.ground,
        contact_tree: contact.tree,
        slippage: Some(Slippage {
            mu_min: 0.2,
            mu_max: 1.3,
            beta_per_s: 20.0,
            kappa_per_m: 0.7,
        }),
        ground_model: Default::default(),
        scarring: None,
        dt_s,
        size: size(),
        settings,
        solver: LegacySolver::from(&settings),
    })
}

fn size() -> RunSize {
    RunSize {
        max_time_s: 600.0,
        rocks_per_cell: 4,
        rocks_per_point: 1,
        source_cells: 4,
        release_points: 0,
        stems: 1333,
    }
}

/// The results of a merged `tally` on [`layout`], seed 42.
pub fn results(tally: Tally, threads: usize, wall: f64) -> Results {
    let info = RunInfo {
        engine: "lumped".into(),
        scenario: "test".into(),
        seed: 42,
        threads,
        wall_time_s: wall,
        parameters: Default::default(),
    };
    Results::new(&layout(), tally, info)
}

/// Summary without the keys that may depend on the thread count.
pub fn summary(r: &Results) -> serde_json::Value {
    let mut s = r.summary_json();
    let m = s.as_object_mut().unwrap();
    for k in ["threads", "wall_time_s", "trajectories_per_s"] {
        assert!(m.remove(k).is_some(), "{k}");
    }
    s
}

/// Every raster, the summary (timings aside), the trajectories and the speed profile agree
/// bit for bit.
pub fn assert_identical(a: &Results, b: &Results) {
    assert_eq!(summary(a), summary(b));
    assert_eq!(a.raster_names(), b.raster_names());
    for name in a.raster_names() {
        let (ga, gb) = (a.raster(&name).unwrap(), b.raster(&name).unwrap());
        assert_eq!(ga.mask(), gb.mask(), "{name}");
        let bits = |g: &rockfall_raster::Grid<f64>| -> Vec<u64> {
            g.values().iter().map(|v| v.to_bits()).collect()
        };
        assert_eq!(bits(&ga), bits(&gb), "{name}");
    }
    let bits = |r: &Results| -> Vec<(u64, u64)> {
        (r.trajectories().iter())
            .map(|t| (t.rock_id, t.t_s.to_bits()))
            .collect()
    };
    assert_eq!(bits(a), bits(b));
    let profile = |r: &Results| -> Vec<[u64; 5]> {
        (r.speed_profile().iter())
            .map(|p| {
                let f = |v: f64| v.to_bits();
                [
                    f(p.from_m),
                    p.visits,
                    f(p.median_ms),
                    f(p.p95_ms),
                    f(p.max_ms),
                ]
            })
            .collect()
    };
    assert!(!profile(a).is_empty(), "the speed profile must hold visits");
    assert_eq!(profile(a), profile(b));
}

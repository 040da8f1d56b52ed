//! Free keys applied to a scenario: values, scales of constants and maps, the release.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_calibrate::keys::{apply, value_of};
use rockfall_calibrate::run::{calibrate_with, candidate};
use rockfall_calibrate::{Evaluator, Mode, Options, Parameter, Residual, Silent};
use rockfall_raster::{Field, Grid, GridGeometry};
use rockfall_results::Results;
use rockfall_scenario::{Release, RockSpec, Scenario};
use rockfall_sim::{Overrides, Simulation};
use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};

fn scenario() -> Scenario {
    let g = GridGeometry {
        ncols: 10,
        nrows: 40,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 2.0,
    };
    let dem = Grid::from_fn(g, |row, _| Some(200.0 - 1.2 * row as f64));
    let mut surface = SurfaceMap::uniform(SoilType::new(4).unwrap(), 0.05, 0.1, 0.2);
    surface.rg20_m = Field::Grid(Grid::filled(g, 0.1));
    let terrain = Terrain::new(Dem::new(dem).unwrap(), surface).unwrap();
    let release = Release {
        cells: vec![g.index(1, 5)],
        cell_height_m: 0.5,
        cell_velocity_ms: [0.0, -1.0, 0.5],
        ..Release::default()
    };
    let mut s = Scenario::new("keys", terrain, RockSpec::sphere(1.0, 2650.0), release);
    s.simulation.rocks_per_cell = 5;
    s
}

fn p(key: &str, mode: Mode) -> Parameter {
    Parameter {
        key: key.into(),
        mode,
        lo: 0.0,
        hi: 4.0,
    }
}

#[test]
fn values_and_scales_of_settings_maps_and_the_release() {
    let base = scenario();
    let mut s = base.clone();
    // a setting: a value, or a factor on the base's value
    apply(
        &mut s,
        &base,
        &p("lumped.roughness_tilt_factor", Mode::Value),
        0.3,
    )
    .unwrap();
    assert_eq!(s.lumped.roughness_tilt_factor, 0.3);
    apply(
        &mut s,
        &base,
        &p("lumped.rn_velocity_scale_ms", Mode::Scale),
        2.0,
    )
    .unwrap();
    assert_eq!(s.lumped.rn_velocity_scale_ms, 2.0 * 9.144);
    apply(&mut s, &base, &p("contact.ground.mu", Mode::Value), 0.7).unwrap();
    assert_eq!(s.contact.ground.mu, 0.7);
    // the scarring ground's default class under [contact.ground], the hard law's keys kept
    apply(
        &mut s,
        &base,
        &p("contact.ground.me_mn_m2", Mode::Scale),
        2.0,
    )
    .unwrap();
    apply(&mut s, &base, &p("contact.ground.c_s", Mode::Value), 2.5).unwrap();
    let d = &s.contact.scarring.default.params;
    assert_eq!((d.me_mn_m2, d.c_s, d.kappa_per_m), (30.0, 2.5, 3.0));
    assert_eq!(s.contact.ground.mu, 0.7);
    // terrain.rg_m scales the three obstacle-height maps together, constants and rasters
    apply(&mut s, &base, &p("terrain.rg_m", Mode::Scale), 2.0).unwrap();
    let t = &s.terrain.surface;
    assert_eq!(t.rg70_m, Field::Const(0.1));
    assert_eq!(t.rg10_m, Field::Const(0.4));
    assert_eq!(t.rg20_m.at(3, 3), Some(0.2));
    // the release: a height, a speed scaled as a vector
    apply(&mut s, &base, &p("release.height_m", Mode::Value), 1.25).unwrap();
    apply(&mut s, &base, &p("release.velocity_ms", Mode::Scale), 2.0).unwrap();
    assert_eq!(s.release.cell_height_m, 1.25);
    assert_eq!(s.release.cell_velocity_ms, [0.0, -2.0, 1.0]);
    let speed = value_of(&s, &p("release.velocity_ms", Mode::Scale)).unwrap();
    assert!((speed - 5f64.sqrt()).abs() < 1e-12);
    // an optional map not set gets a constant from a range, and refuses a scale
    apply(
        &mut s,
        &base,
        &p("terrain.rolling_friction", Mode::Value),
        0.4,
    )
    .unwrap();
    assert_eq!(s.terrain.surface.rolling_friction, Some(Field::Const(0.4)));
    let e = apply(&mut s, &base, &p("terrain.r_n", Mode::Scale), 2.0).unwrap_err();
    assert!(e.contains("not set"), "{e}");
    // scales always apply to the base: applying twice gives the same scenario
    let once = candidate(&base, &[p("terrain.rg_m", Mode::Scale)], &[3.0]).unwrap();
    let twice = candidate(&once, &[p("terrain.rg_m", Mode::Scale)], &[1.0]).unwrap();
    assert_eq!(once.terrain.surface.rg70_m, twice.terrain.surface.rg70_m);
    assert_eq!(
        once.terrain.surface.rg70_m,
        Field::Const(0.15000000000000002)
    );
}

/// Every candidate alike: the best is the first of equals.
struct Flat;

impl Evaluator for Flat {
    fn residuals(&self, _: &Results) -> Vec<Residual> {
        vec![Residual {
            path: "flat".into(),
            observed: 0.0,
            simulated: Some(1.0),
            sigma: 1.0,
            z: 1.0,
        }]
    }
}

#[test]
fn the_best_of_equal_candidates_is_the_first() {
    let sim = Simulation::new(scenario(), &Overrides::default()).unwrap();
    let opts = Options {
        budget: 5,
        seed: None,
        threads: 1,
    };
    let params = [p("lumped.roughness_tilt_factor", Mode::Value)];
    let c = calibrate_with(&sim, &params, &Flat, &opts, &Silent).unwrap();
    assert_eq!((c.best, c.evaluations.len()), (0, 5));
    assert!(c.evaluations.iter().all(|e| e.objective == 1.0 && e.fits));
}

//! The twin experiment: observations made by the engine itself at known parameter values;
//! the calibration must find those values again, within the ranges it reports as fitting.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_calibrate::{Mode, Options, Parameter, Silent, Spec, Target, Uncertainty, calibrate};
use rockfall_raster::{Grid, GridGeometry};
use rockfall_scenario::{Release, RockSpec, Scenario};
use rockfall_sim::{Overrides, simulate};
use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};

/// A 35° slope, 100 m long in plan, onto 200 m of flat talus; one source cell at the top.
fn slope() -> Scenario {
    let g = GridGeometry {
        ncols: 20,
        nrows: 150,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 2.0,
    };
    let tan = 35f64.to_radians().tan();
    let dem = Grid::from_fn(g, |row, _| {
        let d = (row as f64 + 0.5) * 2.0;
        Some(400.0 - tan * d.min(100.0))
    });
    let surface = SurfaceMap::uniform(SoilType::new(4).unwrap(), 0.05, 0.1, 0.2);
    let terrain = Terrain::new(Dem::new(dem).unwrap(), surface).unwrap();
    let release = Release {
        cells: vec![g.index(2, 10)],
        cell_height_m: 1.0,
        cell_velocity_ms: [0.0, -2.0, 0.0],
        ..Release::default()
    };
    let mut s = Scenario::new("twin", terrain, RockSpec::sphere(1.0, 2650.0), release);
    s.simulation.rocks_per_cell = 400;
    s.output.trajectories = 0;
    s
}

#[test]
fn calibration_recovers_the_parameters_that_made_the_observations() {
    let truth = [
        ("lumped.soil_friction_scale", 1.3),
        ("lumped.rn_velocity_scale_ms", 6.0),
    ];
    let mut twin = slope();
    twin.lumped.soil_friction_scale = truth[0].1;
    twin.lumped.rn_velocity_scale_ms = truth[1].1;
    let observed = simulate(twin, &Overrides::default())
        .unwrap()
        .summary_json();
    let paths = [
        "runout_m.p50",
        "runout_m.p95",
        "max_velocity_ms.mean",
        "max_jump_height_m.mean",
    ];
    let targets: Vec<Target> = paths
        .iter()
        .map(|p| {
            let v = rockfall_calibrate::targets::lookup(&observed, p)
                .and_then(|v| v.as_f64())
                .unwrap();
            Target {
                path: p.to_string(),
                value: v,
                // the observations' uncertainty: 3 % of each
                uncertainty: Uncertainty::Sd(0.03 * v.abs()),
            }
        })
        .collect();
    let spec = Spec {
        file: None,
        parameters: vec![
            Parameter {
                key: truth[0].0.into(),
                mode: Mode::Value,
                lo: 0.2,
                hi: 2.5,
            },
            Parameter {
                key: truth[1].0.into(),
                mode: Mode::Value,
                lo: 2.0,
                hi: 20.0,
            },
        ],
        targets,
        deposits: None,
        rocks_per_cell: None,
        rocks_per_point: None,
    };
    let opts = Options {
        budget: 60,
        seed: None,
        threads: 2,
    };
    let c = calibrate(slope(), &spec, &opts, &Silent).unwrap();
    assert!(c.evaluations.len() <= 60);
    let best = c.best();
    let ranges = c.fit_ranges();
    for (k, (key, value)) in truth.iter().enumerate() {
        let p = &spec.parameters[k];
        let [lo, hi] = ranges[k].unwrap_or_else(|| panic!("{key}: no candidate fits"));
        assert!(
            lo <= *value && *value <= hi,
            "{key}: the truth {value} lies outside the fitting range {lo} – {hi}"
        );
        // the fitting range narrows the prior range, and the best lies near the truth
        assert!(hi - lo < 0.6 * (p.hi - p.lo), "{key}: fits {lo} – {hi}");
        assert!(
            (best.values[k] - value).abs() < 0.15 * (p.hi - p.lo),
            "{key}: best {} against the truth {value}",
            best.values[k]
        );
    }
    assert!(best.fits && best.objective < 1.0, "{best:?}");

    // the same seed gives the same calibration, whatever the thread count
    let again = calibrate(slope(), &spec, &Options { threads: 1, ..opts }, &Silent).unwrap();
    assert_eq!(again.evaluations, c.evaluations);
}

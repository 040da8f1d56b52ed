//! Classification on synthetic runs: scenario mode, frequency mode, and their agreement.

use rockfall_hazard::{
    Class, Level, Matrix, ReachRule, ScenarioMaps, SourceMaps, classify_frequency,
    classify_scenario,
};
use rockfall_raster::{Grid, GridGeometry};

fn geometry(n: usize) -> GridGeometry {
    GridGeometry {
        ncols: n,
        nrows: 1,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 2.0,
    }
}

fn grid(v: &[Option<f64>]) -> Grid<f64> {
    Grid::from_options(geometry(v.len()), v.to_vec()).expect("cells")
}

#[test]
fn scenario_mode_reads_intensity_and_reach() {
    let m = Matrix::swiss();
    // cells: strong and reached; medium reached; weak but below the reach rule; not reached
    let s = ScenarioMaps {
        label: "30y".into(),
        return_period_years: 30.0,
        intensity_kj: grid(&[Some(500.0), Some(100.0), Some(10.0), None]),
        reach_pct: grid(&[Some(80.0), Some(5.0), Some(0.5), Some(0.0)]),
    };
    let c = classify_scenario(&m, &s, ReachRule::default());
    let levels: Vec<u8> = c.iter().map(|c| c.level).collect();
    let fields: Vec<u8> = c.iter().map(|c| c.field).collect();
    assert_eq!(levels, [4, 3, 0, 0]);
    assert_eq!(fields, [9, 6, 0, 0]);
    // the rule moves the limit: at 0.1 % the third cell is reached (weak, ≤ 30 y: field 3)
    let c = classify_scenario(&m, &s, ReachRule { min_reach_pct: 0.1 });
    assert_eq!((c[2].field, c[2].level), (3, Level::Medium as u8));
    assert_eq!(c[3], Class::default(), "no rock passed: never reached");
}

/// One source whose rocks all pass every cell, with the energies of `kj` per cell for all
/// its `rocks` rocks: counts above each limit are all or nothing.
fn uniform_source(kj: &[f64], rocks: u64, f: f64, limits: &[f64]) -> SourceMaps {
    let n = kj.len();
    SourceMaps {
        label: "s".into(),
        frequency_per_year: f,
        rocks,
        reach_pct: grid(&vec![Some(100.0); n]),
        above: (limits.iter())
            .map(|&e| {
                let v: Vec<Option<f64>> = (kj.iter())
                    .map(|&k| Some(if k > e { rocks as f64 } else { 0.0 }))
                    .collect();
                (e, grid(&v))
            })
            .collect(),
    }
}

#[test]
fn frequency_mode_agrees_with_scenario_mode_where_both_apply() {
    // every rock reaches every cell with the same energy: the cell's return period is the
    // scenario's, and the intensity class that of the energy
    for m in [Matrix::swiss(), Matrix::austria()] {
        let kj = [5.0, 50.0, 150.0, 400.0];
        for t in [10.0, 30.0, 50.0, 100.0, 200.0, 300.0, 1000.0] {
            let scen = ScenarioMaps {
                label: "t".into(),
                return_period_years: t,
                intensity_kj: grid(&kj.map(Some)),
                reach_pct: grid(&[Some(100.0); 4]),
            };
            let by_scenario = classify_scenario(&m, &scen, ReachRule::default());
            let src = uniform_source(&kj, 1000, 1.0 / t, &m.intensity_thresholds_kj);
            let by_frequency = classify_frequency(&m, &geometry(4), &[src]).expect("counts");
            assert_eq!(by_frequency.classes, by_scenario, "{} {t} y", m.name);
        }
    }
}

#[test]
fn frequency_mode_adds_sources_and_takes_the_worst_intensity() {
    let m = Matrix::swiss();
    let g = geometry(1);
    // source a: every 50 years a block, half of them above 300 kJ at the cell, all reach
    let a = SourceMaps {
        label: "a".into(),
        frequency_per_year: 0.02,
        rocks: 100,
        reach_pct: grid(&[Some(100.0)]),
        above: vec![(30.0, grid(&[Some(100.0)])), (300.0, grid(&[Some(50.0)]))],
    };
    // above 300 kJ: λ = 0.02 · 0.5 = 0.01 → T = 100 y → strong, 30–100 y: field 8 (red)
    let r = classify_frequency(&m, &g, std::slice::from_ref(&a)).expect("counts");
    assert_eq!((r.classes[0].field, r.classes[0].level), (8, 4));
    assert!((r.frequencies[2].1[0] - 0.01).abs() < 1e-15);
    // a second, rarer source adds its frequency: λ(>300) = 0.01 + 0.005 → T ≈ 67 y, still 8
    let b = SourceMaps {
        frequency_per_year: 0.005,
        label: "b".into(),
        ..a.clone()
    };
    let both = classify_frequency(&m, &g, &[a.clone(), b.clone()]).expect("counts");
    let weak = both.frequencies[0].1[0];
    assert!((weak - 0.025).abs() < 1e-15, "{weak}");
    // raising a source's frequency never lowers a level
    let mut often = a.clone();
    often.frequency_per_year = 0.1;
    let r2 = classify_frequency(&m, &g, &[often]).expect("counts");
    assert!(r2.classes[0].level >= r.classes[0].level);
    assert_eq!(r2.classes[0].field, 9, "T = 20 y above 300 kJ");
    // a missing count is named
    let mut lacking = a;
    lacking.above.pop();
    let e = classify_frequency(&m, &g, &[lacking]).expect_err("no counts above 300 kJ");
    assert_eq!(e, ("a".to_string(), 300.0));
}

/// The reach rule's limit is inclusive; a cell no rock passed is never reached, even at 0 %.
#[test]
fn reach_rule_limit_and_zero() {
    let m = Matrix::swiss();
    let s = ScenarioMaps {
        label: "30y".into(),
        return_period_years: 30.0,
        intensity_kj: grid(&[Some(10.0), Some(10.0)]),
        reach_pct: grid(&[Some(1.0), Some(0.0)]),
    };
    let c = classify_scenario(&m, &s, ReachRule::default());
    assert_eq!((c[0].field, c[0].level), (3, 3));
    let c = classify_scenario(&m, &s, ReachRule { min_reach_pct: 0.0 });
    assert_eq!(c[1], Class::default());
}

//! Stand expansion: reproducibility, order independence, statistics of large stands and
//! input validation.

use rockfall_forest::{
    BREAST_HEIGHT_M, ForestError, Species, StandCell, StandOptions, Stem, expand_stands,
    height_from_dbh_m,
};
use rockfall_raster::GridGeometry;

fn geometry(n: usize, cell_size_m: f64) -> GridGeometry {
    GridGeometry {
        ncols: n,
        nrows: n,
        x_min_m: 600_000.0,
        y_min_m: 200_000.0,
        cell_size_m,
    }
}

/// The forested site of seed 000: 290 stems/ha, DBH 31 ± 21 cm, 75 % conifers.
fn seed_000_stand() -> StandCell {
    StandCell {
        stems_per_ha: 290.0,
        dbh_mean_cm: 31.0,
        dbh_sd_cm: 21.0,
        conifer_percent: 75.0,
        height: None,
    }
}

/// Sample mean, sd, and their standard errors (the sd's from the fourth central moment).
fn stats(values: impl Iterator<Item = f64> + Clone) -> (f64, f64, f64, f64) {
    let n = values.clone().count() as f64;
    let mean = values.clone().sum::<f64>() / n;
    let m2 = values.clone().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    let m4 = values.map(|v| (v - mean).powi(4)).sum::<f64>() / n;
    let sd = m2.sqrt();
    (
        mean,
        sd,
        sd / n.sqrt(),
        ((m4 - m2 * m2) / n).sqrt() / (2.0 * sd),
    )
}

fn expand(g: &GridGeometry, stand: StandCell, seed: u64) -> Vec<Stem> {
    expand_stands(g, |_, _| Some(stand), seed, &StandOptions::default()).expect("valid stand")
}

#[test]
fn same_seed_same_stems_different_seed_different_stems() {
    let g = geometry(20, 5.0);
    let a = expand(&g, seed_000_stand(), 7);
    let b = expand(&g, seed_000_stand(), 7);
    let c = expand(&g, seed_000_stand(), 8);
    assert!(!a.is_empty());
    assert_eq!(a, b);
    assert_ne!(a, c);
}

#[test]
fn sub_region_gives_the_same_stems_for_its_cells() {
    let g = geometry(20, 5.0);
    let full = expand(&g, seed_000_stand(), 11);
    let inside = |row: usize, col: usize| (5..12).contains(&row) && (3..9).contains(&col);
    let sub = expand_stands(
        &g,
        |row, col| inside(row, col).then(seed_000_stand),
        11,
        &StandOptions::default(),
    )
    .expect("valid");
    let from_full: Vec<Stem> = full
        .into_iter()
        .filter(|s| g.cell_of(s.x_m, s.y_m).is_some_and(|(r, c)| inside(r, c)))
        .collect();
    assert!(!sub.is_empty());
    assert_eq!(sub, from_full);
}

#[test]
fn stems_lie_in_their_cells_and_integer_densities_are_exact() {
    // 1600 stems/ha on 2.5 m cells: exactly one stem per cell.
    let g = geometry(30, 2.5);
    let stand = StandCell {
        stems_per_ha: 1600.0,
        ..seed_000_stand()
    };
    let stems = expand(&g, stand, 3);
    assert_eq!(stems.len(), g.len());
    for (i, s) in stems.iter().enumerate() {
        let (row, col) = g.row_col(i);
        let (cx, cy) = g.cell_center(row, col);
        assert!(
            (s.x_m - cx).abs() <= 1.25 && (s.y_m - cy).abs() <= 1.25,
            "stem {i}"
        );
    }
}

#[test]
fn large_stand_matches_the_requested_statistics() {
    // 200 × 200 cells of 2.5 m = 25 ha; 290 stems/ha → 7250 stems expected.
    let g = geometry(200, 2.5);
    let stand = StandCell {
        conifer_percent: 50.0,
        ..seed_000_stand()
    };
    let stems = expand(&g, stand, 2024);
    let area_ha = g.len() as f64 * g.cell_area_m2() / 1e4;
    let expected = 290.0 * area_ha;
    // Count variance: per cell frac·(1 − frac) with frac = 0.18125.
    let per_cell = 290.0 * g.cell_area_m2() / 1e4;
    let count_se = (g.len() as f64 * per_cell * (1.0 - per_cell)).sqrt();
    let n = stems.len() as f64;
    assert!(
        (n - expected).abs() < 4.0 * count_se,
        "{n} stems, expected {expected} ± {count_se}"
    );

    let (mean, sd, mean_se, sd_se) = stats(stems.iter().map(|s| s.dbh_cm));
    assert!(
        (mean - 31.0).abs() < 4.0 * mean_se,
        "DBH mean {mean} ± {mean_se}"
    );
    assert!((sd - 21.0).abs() < 4.0 * sd_se, "DBH sd {sd} ± {sd_se}");
    assert!(stems.iter().all(|s| (5.0..=250.0).contains(&s.dbh_cm)));

    let conifers = stems
        .iter()
        .filter(|s| s.species == Species::OtherConifer)
        .count() as f64;
    let share_se = (0.25 / n).sqrt();
    assert!(
        (conifers / n - 0.5).abs() < 4.0 * share_se,
        "conifer share {}",
        conifers / n
    );
    assert!(stems.iter().all(|s| s.species != Species::Unknown));

    // Without given heights, heights follow the allometry.
    for s in &stems {
        assert_eq!(s.height_m, height_from_dbh_m(s.dbh_cm));
        assert!(s.validate().is_ok());
    }
}

#[test]
fn forest_slope_stand_of_seed_001() {
    // 500 stems/ha, DBH 50 ± 5 cm, heights 22.87 ± 1.82 m; 6.25 ha → 3125 stems.
    let g = geometry(100, 2.5);
    let stand = StandCell {
        stems_per_ha: 500.0,
        dbh_mean_cm: 50.0,
        dbh_sd_cm: 5.0,
        conifer_percent: 100.0,
        height: Some((22.87, 1.82)),
    };
    let stems = expand(&g, stand, 1);
    // 500/ha on 6.25 m² cells is 0.3125 per cell.
    let count_se = (g.len() as f64 * 0.3125 * 0.6875).sqrt();
    assert!((stems.len() as f64 - 3125.0).abs() < 4.0 * count_se);
    let (mean, sd, mean_se, sd_se) = stats(stems.iter().map(|s| s.height_m));
    assert!(
        (mean - 22.87).abs() < 4.0 * mean_se,
        "height mean {mean} ± {mean_se}"
    );
    assert!((sd - 1.82).abs() < 4.0 * sd_se, "height sd {sd} ± {sd_se}");
    let (mean, sd, mean_se, sd_se) = stats(stems.iter().map(|s| s.dbh_cm));
    assert!(
        (mean - 50.0).abs() < 4.0 * mean_se,
        "DBH mean {mean} ± {mean_se}"
    );
    assert!((sd - 5.0).abs() < 4.0 * sd_se, "DBH sd {sd} ± {sd_se}");
    assert!(stems.iter().all(|s| s.species == Species::OtherConifer));
}

#[test]
fn zero_sd_gives_every_stem_the_mean() {
    let stand = StandCell {
        dbh_sd_cm: 0.0,
        height: Some((18.0, 0.0)),
        conifer_percent: 0.0,
        ..seed_000_stand()
    };
    let stems = expand(&geometry(10, 5.0), stand, 5);
    assert!(!stems.is_empty());
    assert!(stems.iter().all(|s| s.dbh_cm == 31.0 && s.height_m == 18.0));
    assert!(stems.iter().all(|s| s.species == Species::OtherBroadleaf));
}

#[test]
fn heights_stay_above_breast_height() {
    // Parent height 2 ± 3 m: a large share of the parent lies below breast height.
    let stand = StandCell {
        height: Some((2.0, 3.0)),
        ..seed_000_stand()
    };
    let stems = expand(&geometry(20, 5.0), stand, 9);
    assert!(
        stems
            .iter()
            .all(|s| s.height_m > BREAST_HEIGHT_M && s.validate().is_ok())
    );
}

/// Expands a 6 × 6 grid where only cell (2, 3) has `bad`; the rest are valid.
fn expand_with_bad_cell(bad: StandCell) -> Result<Vec<Stem>, ForestError> {
    expand_stands(
        &geometry(6, 5.0),
        |row, col| {
            Some(if (row, col) == (2, 3) {
                bad
            } else {
                seed_000_stand()
            })
        },
        1,
        &StandOptions::default(),
    )
}

#[test]
fn infeasible_dbh_is_reported_with_its_cell() {
    for (mean, sd) in [(31.0, 30.0), (3.0, 1.0), (260.0, 10.0), (125.0, 100.0)] {
        let bad = StandCell {
            dbh_mean_cm: mean,
            dbh_sd_cm: sd,
            ..seed_000_stand()
        };
        match expand_with_bad_cell(bad) {
            Err(e @ ForestError::InfeasibleDbh { row: 2, col: 3, .. }) => {
                let message = e.to_string();
                assert!(message.contains("row 2, column 3"), "{message}");
            }
            other => panic!("{mean} ± {sd}: expected InfeasibleDbh at (2, 3), got {other:?}"),
        }
    }
}

#[test]
fn invalid_cell_values_name_row_column_and_field() {
    let base = seed_000_stand();
    let cases = [
        (
            StandCell {
                stems_per_ha: -1.0,
                ..base
            },
            "stems_per_ha",
        ),
        (
            StandCell {
                stems_per_ha: f64::NAN,
                ..base
            },
            "stems_per_ha",
        ),
        (
            StandCell {
                stems_per_ha: 1e9,
                ..base
            },
            "stems_per_ha",
        ),
        (
            StandCell {
                dbh_mean_cm: f64::NAN,
                ..base
            },
            "dbh_mean_cm",
        ),
        (
            StandCell {
                dbh_mean_cm: -3.0,
                ..base
            },
            "dbh_mean_cm",
        ),
        (
            StandCell {
                dbh_sd_cm: -1.0,
                ..base
            },
            "dbh_sd_cm",
        ),
        (
            StandCell {
                conifer_percent: 150.0,
                ..base
            },
            "conifer_percent",
        ),
        (
            StandCell {
                conifer_percent: -0.1,
                ..base
            },
            "conifer_percent",
        ),
        (
            StandCell {
                height: Some((1.0, 1.0)),
                ..base
            },
            "height mean",
        ),
        (
            StandCell {
                height: Some((20.0, f64::NAN)),
                ..base
            },
            "height sd",
        ),
    ];
    for (bad, want) in cases {
        match expand_with_bad_cell(bad) {
            Err(ForestError::InvalidStand {
                row: 2,
                col: 3,
                field,
                ..
            }) => {
                assert_eq!(field, want);
            }
            other => panic!("expected InvalidStand {want} at (2, 3), got {other:?}"),
        }
    }
}

#[test]
fn cells_without_stems_are_not_checked() {
    let empty = StandCell {
        stems_per_ha: 0.0,
        dbh_mean_cm: 0.0,
        dbh_sd_cm: f64::NAN,
        conifer_percent: -9999.0,
        height: None,
    };
    let stems = expand(&geometry(5, 5.0), empty, 1);
    assert!(stems.is_empty());
}

#[test]
fn invalid_options_and_geometry() {
    let g = geometry(2, 5.0);
    let cell = |_, _| Some(seed_000_stand());
    for (min, max) in [(0.0, 250.0), (50.0, 40.0), (f64::NAN, 250.0)] {
        let options = StandOptions {
            dbh_min_cm: min,
            dbh_max_cm: max,
        };
        assert!(matches!(
            expand_stands(&g, cell, 1, &options),
            Err(ForestError::InvalidDbhBounds { .. })
        ));
    }
    let unbounded = StandOptions {
        dbh_max_cm: f64::INFINITY,
        ..StandOptions::default()
    };
    assert!(expand_stands(&g, cell, 1, &unbounded).is_ok());
    let bad = GridGeometry {
        cell_size_m: 0.0,
        ..g
    };
    assert!(matches!(
        expand_stands(&bad, cell, 1, &StandOptions::default()),
        Err(ForestError::InvalidGeometry { .. })
    ));
}

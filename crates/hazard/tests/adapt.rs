//! A hazard scenario's design block and thresholds applied to the scenario it runs.

use rockfall_hazard::Matrix;
use rockfall_hazard::adapt::{add_thresholds, set_block};
use rockfall_hazard::hazard_file::Block;
use rockfall_scenario::VolumeDistribution;

fn site() -> rockfall_scenario::Scenario {
    rockfall_sites::build("vaujany-site2").expect("built-in site")
}

#[test]
fn a_percentile_of_the_block_size_distribution_becomes_the_design_block() {
    let mut s = site();
    // the inventory: 679 kg median at 2800 kg/m³, ln-sd 0.6
    let median_m3 = 679.0 / 2800.0;
    s.rock.volume_distribution = Some(VolumeDistribution::LogNormal {
        median_m3,
        sd_ln: 0.6,
    });
    let block = Block {
        percentile: Some(95.0),
        ..Block::default()
    };
    set_block(&mut s, &block).expect("a distribution to take the percentile of");
    let v = s.rock.volume_m3.expect("a design volume");
    let expected = median_m3 * (0.6 * 1.644_853_626_951_472_2f64).exp();
    assert!(
        (v / expected - 1.0).abs() < 1e-9,
        "{v} m³ against {expected}"
    );
    assert!(
        s.rock.volume_distribution.is_none(),
        "one block, not a spread"
    );
    // without a distribution: named
    let mut bare = site();
    let e = set_block(&mut bare, &block).expect_err("no distribution");
    assert_eq!(e.0, "block_percentile");
}

#[test]
fn a_mass_is_turned_into_a_volume_at_the_density_and_the_spread_dropped() {
    let mut s = site();
    s.rock.volume_variation_percent = 30.0;
    let block = Block {
        mass_kg: Some(1400.0),
        ..Block::default()
    };
    set_block(&mut s, &block).expect("constant density");
    assert_eq!(s.rock.volume_m3, Some(0.5), "1400 kg at 2800 kg/m³");
    assert_eq!(s.rock.volume_variation_percent, 0.0);
    let mut t = site();
    set_block(
        &mut t,
        &Block {
            volume_m3: Some(0.02),
            ..Block::default()
        },
    )
    .expect("a volume");
    assert_eq!(t.rock.volume_m3, Some(0.02));
}

#[test]
fn the_matrix_thresholds_are_always_counted() {
    let mut s = site();
    s.output.energy_thresholds_kj = vec![5.0, 50.0, 500.0, 1000.0, 2000.0, 4000.0];
    add_thresholds(&mut s, &Matrix::swiss());
    // the matrix's 30 and 300 kJ first, then the scenario's while there is room (6)
    assert_eq!(
        s.output.energy_thresholds_kj,
        [5.0, 30.0, 50.0, 300.0, 500.0, 1000.0]
    );
    let mut a = site();
    add_thresholds(&mut a, &Matrix::austria());
    assert_eq!(a.output.energy_thresholds_kj, [30.0, 100.0, 300.0]);
}

/// A matrix's own limits are added to the scenario's, ascending.
#[test]
fn thresholds_of_the_matrix_are_added() {
    let mut s = rockfall_sites::build("vaujany-site2").unwrap();
    let mut m = Matrix::swiss();
    m.intensity_thresholds_kj = vec![50.0, 500.0];
    rockfall_hazard::adapt::add_thresholds(&mut s, &m);
    assert_eq!(
        s.output.energy_thresholds_kj,
        vec![30.0, 50.0, 100.0, 300.0, 500.0]
    );
}

//! `[rock] volume_distribution`: each kind's inverse cumulative distribution against its
//! closed form, percentiles, medians, the checks and the `check` text.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_scenario::{ObservedVolumes, VolumeDistribution, VolumeDistributionError};

/// Φ⁻¹(0.95), the standard normal's 95th percentile (to 17 digits).
const Z_95: f64 = 1.644_853_626_951_472_2;

fn close(a: f64, b: f64, rel: f64) -> bool {
    ((a - b) / b).abs() <= rel
}

fn lognormal() -> VolumeDistribution {
    VolumeDistribution::LogNormal {
        median_m3: 0.25,
        sd_ln: 0.6,
    }
}

fn power_law() -> VolumeDistribution {
    VolumeDistribution::PowerLaw {
        min_m3: 0.01,
        max_m3: 10.0,
        exponent: 0.5,
    }
}

fn observed(values: &[f64]) -> VolumeDistribution {
    VolumeDistribution::Observed(ObservedVolumes::new(values.to_vec()))
}

/// Log-normal percentile p = median · exp(σ z_p): z_0.95 = 1.6448536, z_0.05 = −z_0.95,
/// z_0.5 = 0.
#[test]
fn lognormal_percentiles_are_median_times_exp_sd_z() {
    let d = lognormal();
    d.check().unwrap();
    let p95 = d.percentile_m3(95.0);
    assert!(close(p95, 0.25 * (0.6 * Z_95).exp(), 1e-12), "{p95}");
    assert!(close(
        d.percentile_m3(5.0),
        0.25 * (-0.6 * Z_95).exp(),
        1e-12
    ));
    assert!(close(d.percentile_m3(50.0), 0.25, 1e-15));
    assert_eq!(d.median_m3(), 0.25);
    // Φ⁻¹(0.8413447460685429) = 1: one σ above the median
    assert!(close(
        d.sample_m3(0.841_344_746_068_542_9),
        0.25 * 0.6f64.exp(),
        1e-12
    ));
    // the ends of [0, 1) still give finite, positive volumes, and the draw is monotone
    let (lo, hi) = (d.sample_m3(0.0), d.sample_m3(1.0 - f64::EPSILON / 2.0));
    assert!(lo > 0.0 && hi.is_finite() && lo < hi, "{lo} {hi}");
    let mut last = 0.0;
    for k in 0..1000 {
        let v = d.sample_m3(k as f64 / 1000.0);
        assert!(v > last, "not increasing at {k}");
        last = v;
    }
}

/// The power law's draw V(u) against its analytic complementary cumulative distribution:
/// P(> V) = ((a/V)^b − (a/c)^b) / (1 − (a/c)^b) = 1 − u, from a at u = 0 to c as u → 1.
#[test]
fn power_law_draws_follow_the_truncated_ccdf() {
    let d = power_law();
    d.check().unwrap();
    let (a, c, b) = (0.01f64, 10.0f64, 0.5f64);
    let r = (a / c).powf(b);
    let ccdf = |v: f64| ((a / v).powf(b) - r) / (1.0 - r);
    for k in 0..=100 {
        let u = k as f64 / 100.0 * (1.0 - 1e-12);
        let v = d.sample_m3(u);
        assert!((a..=c).contains(&v), "{u}: {v}");
        assert!((ccdf(v) - (1.0 - u)).abs() < 1e-12, "{u}: {v}");
    }
    assert_eq!(d.sample_m3(0.0), a);
    assert!(close(d.sample_m3(1.0 - 1e-15), c, 1e-12));
    // the median: (a/V)^b = (1 + r)/2
    let median = a * ((1.0 + r) / 2.0).powf(-1.0 / b);
    assert!(close(d.median_m3(), median, 1e-12), "{}", d.median_m3());
    // the 95th percentile leaves 5 % above it
    assert!((ccdf(d.percentile_m3(95.0)) - 0.05).abs() < 1e-12);
    // with b = 1 the median of [1, 100] is 2/(1 + 1/100) ≈ 1.980
    let b1 = VolumeDistribution::PowerLaw {
        min_m3: 1.0,
        max_m3: 100.0,
        exponent: 1.0,
    };
    assert!(close(b1.median_m3(), 2.0 / 1.01, 1e-12));
}

/// Observed values: the inverse of the empirical distribution function — percentile p is
/// the value of rank ⌈p n/100⌉, and uniform draws take each value equally often.
#[test]
fn observed_values_are_drawn_equally_and_give_empirical_percentiles() {
    let d = observed(&[5.0, 1.0, 3.0, 2.0, 4.0]);
    d.check().unwrap();
    assert_eq!(d.median_m3(), 3.0);
    assert_eq!(d.percentile_m3(20.0), 1.0);
    assert_eq!(d.percentile_m3(21.0), 2.0);
    assert_eq!(d.percentile_m3(80.0), 4.0);
    assert_eq!(d.percentile_m3(99.9), 5.0);
    assert_eq!(d.percentile_m3(0.1), 1.0);
    // of 20 values 1..20, the 95th percentile is the 19th, the median the 10th
    let twenty = observed(&(1..=20).rev().map(f64::from).collect::<Vec<_>>());
    assert_eq!(twenty.percentile_m3(95.0), 19.0);
    assert_eq!(twenty.percentile_m3(95.1), 20.0);
    assert_eq!(twenty.median_m3(), 10.0);
    // a fine grid of u (cell midpoints) gives each value the same share
    let n = 100_000;
    let mut counts = [0usize; 5];
    for k in 0..n {
        let v = d.sample_m3((k as f64 + 0.5) / n as f64);
        counts[v as usize - 1] += 1;
    }
    assert!(counts.iter().all(|&c| c == n / 5), "{counts:?}");
    assert_eq!(d.sample_m3(0.0), 1.0);
    assert_eq!(d.sample_m3(1.0 - f64::EPSILON), 5.0);
    // a single value is every rock
    let one = observed(&[0.3]);
    assert_eq!((one.sample_m3(0.0), one.sample_m3(0.99)), (0.3, 0.3));
    assert_eq!(one.percentile_m3(95.0), 0.3);
}

#[test]
fn checks_name_the_key_at_fault() {
    let key = |d: VolumeDistribution| d.check().unwrap_err().key();
    for sd in [0.0, -0.5, f64::NAN, f64::INFINITY] {
        let d = VolumeDistribution::LogNormal {
            median_m3: 0.25,
            sd_ln: sd,
        };
        assert_eq!(key(d), "sd_ln", "{sd}");
    }
    let median = VolumeDistribution::LogNormal {
        median_m3: 0.0,
        sd_ln: 0.5,
    };
    assert_eq!(key(median), "median_m3");
    let pl = |min_m3, max_m3, exponent| VolumeDistribution::PowerLaw {
        min_m3,
        max_m3,
        exponent,
    };
    assert_eq!(key(pl(1.0, 1.0, 0.5)), "max_m3");
    assert_eq!(key(pl(2.0, 1.0, 0.5)), "max_m3");
    assert_eq!(key(pl(-1.0, 1.0, 0.5)), "min_m3");
    assert_eq!(key(pl(0.1, 1.0, 0.0)), "exponent");
    assert_eq!(key(pl(0.1, f64::INFINITY, 0.5)), "max_m3");
    assert!(matches!(
        observed(&[]).check(),
        Err(VolumeDistributionError::NoValues)
    ));
    assert_eq!(key(observed(&[0.2, 0.0])), "volumes_m3");
    assert_eq!(key(observed(&[0.2, f64::NAN])), "volumes_m3");
    let many = observed(&vec![1.0; rockfall_scenario::volume::MAX_OBSERVED + 1]);
    assert!(matches!(
        many.check(),
        Err(VolumeDistributionError::TooMany { .. })
    ));
    observed(&vec![1.0; rockfall_scenario::volume::MAX_OBSERVED])
        .check()
        .unwrap();
    let msg = pl(2.0, 1.0, 0.5).check().unwrap_err().to_string();
    assert!(msg.contains("must be below"), "{msg}");
}

/// The `check` line: kind, median (with its mass at one density), 5–95 % range, three
/// significant digits.
#[test]
fn descriptions_round_to_three_significant_digits() {
    let d = VolumeDistribution::LogNormal {
        median_m3: 0.25,
        sd_ln: 0.8,
    };
    let text = d.describe(Some(2716.0));
    // 0.25 · exp(±0.8 · 1.6449) = 0.067059, 0.93201
    assert_eq!(
        text,
        "log-normal (sd_ln 0.8), median 0.25 m³ (679 kg), 5–95 %: 0.0671–0.932 m³"
    );
    assert!(!d.describe(None).contains("kg"));
    let text = power_law().describe(None);
    assert!(
        text.starts_with("power law N(>V) ∝ V^-0.5 on 0.01–10 m³"),
        "{text}"
    );
    let text = observed(&[0.05, 0.7, 0.123456]).describe(Some(2700.0));
    assert!(
        text.starts_with("drawn from 3 observed values, 0.05–0.7 m³, median 0.123 m³ (333 kg)"),
        "{text}"
    );
}

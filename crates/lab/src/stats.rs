//! Sample statistics of the impact metrics: mean, median, and the most likely value — the peak
//! of a Gaussian kernel density estimate, the same curve the PDF figures draw (seed 001
//! figs. 3–4 are PDFs and the paper reads its "highest probability" losses off their peaks).
//!
//! Bandwidth: Silverman's rule of thumb, `h = 0.9 · min(σ, IQR/1.34) · n^(−1/5)` (Silverman
//! 1986, eq. 3.31), robust to the long tail of Δω (a rock barely spinning before an impact
//! can leave it spinning many times faster: Δω → −∞). Non-finite values are left out.
//!
//! The mean carries a 95 % percentile-bootstrap interval (Efron & Tibshirani 1993, ch. 13):
//! [`BOOTSTRAP_RESAMPLES`] resamples with replacement, their means' 2.5th and 97.5th
//! percentiles. The resampling stream is keyed by the sample's size only, so the interval is
//! a pure function of the sample (same sample, same interval, on any thread count).

use serde::{Deserialize, Serialize};

/// Kernel support, in bandwidths (the Gaussian beyond 6 h is below 1.6e-8 of its peak).
const CUTOFF: f64 = 6.0;

/// Grid points of the mode search.
const MODE_GRID: usize = 512;

/// Resamples of the bootstrap interval of the mean.
pub const BOOTSTRAP_RESAMPLES: usize = 2000;

/// Mean (with its bootstrap 95 % interval), median and mode of a sample; written as
/// `{"n", "mean", "ci95", "p50", "mode"}`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Described {
    /// Values described (finite ones).
    pub n: usize,
    /// Arithmetic mean.
    pub mean: f64,
    /// 95 % percentile-bootstrap interval of the mean, [low, high] (both the mean for one
    /// value); absent (NaN) in summaries written before it existed.
    #[serde(default = "no_interval")]
    pub ci95: [f64; 2],
    /// Median (linear interpolation between order statistics).
    pub p50: f64,
    /// Peak of the kernel density estimate.
    pub mode: f64,
}

/// The finite values of `values`, sorted.
pub fn sorted_finite(values: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = values.into_iter().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    v
}

/// Describes `values`; `None` when none is finite.
pub fn describe(values: impl IntoIterator<Item = f64>) -> Option<Described> {
    let v = sorted_finite(values);
    if v.is_empty() {
        return None;
    }
    Some(Described {
        n: v.len(),
        mean: v.iter().sum::<f64>() / v.len() as f64,
        ci95: bootstrap_mean_ci95(&v),
        p50: quantile(&v, 0.5),
        mode: mode(&v),
    })
}

fn no_interval() -> [f64; 2] {
    [f64::NAN; 2]
}

/// 95 % percentile-bootstrap interval of the mean of `values` (non-empty): the 2.5th and
/// 97.5th percentiles of the means of [`BOOTSTRAP_RESAMPLES`] resamples with replacement,
/// drawn from a stream keyed by the sample size.
pub fn bootstrap_mean_ci95(values: &[f64]) -> [f64; 2] {
    use rand::RngExt;
    let n = values.len();
    let mut rng = rockfall_rng::stream(
        0,
        rockfall_rng::Purpose::Sampling,
        &[0x626f_6f74_7374_7270, n as u64],
    );
    let mut means: Vec<f64> = (0..BOOTSTRAP_RESAMPLES)
        .map(|_| (0..n).map(|_| values[rng.random_range(0..n)]).sum::<f64>() / n as f64)
        .collect();
    means.sort_by(f64::total_cmp);
    [quantile(&means, 0.025), quantile(&means, 0.975)]
}

/// Quantile `p` ∈ [0, 1] of `sorted` (ascending), by linear interpolation between order
/// statistics (Hyndman & Fan type 7); NaN for an empty sample.
pub fn quantile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let h = (sorted.len() - 1) as f64 * p.clamp(0.0, 1.0);
    let (lo, frac) = (h.floor() as usize, h - h.floor());
    let hi = (lo + 1).min(sorted.len() - 1);
    sorted[lo] + frac * (sorted[hi] - sorted[lo])
}

/// Silverman's bandwidth of `sorted` (non-empty); positive even for a constant sample.
pub fn bandwidth(sorted: &[f64]) -> f64 {
    let n = sorted.len() as f64;
    let mean = sorted.iter().sum::<f64>() / n;
    let var = sorted.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    let iqr = quantile(sorted, 0.75) - quantile(sorted, 0.25);
    let spread = match (var.sqrt(), iqr / 1.34) {
        (s, q) if q > 0.0 => s.min(q),
        (s, _) => s,
    };
    let scale = sorted[sorted.len() - 1].abs().max(sorted[0].abs()).max(1.0);
    (0.9 * spread * n.powf(-0.2)).max(1e-9 * scale)
}

/// The kernel density estimate of `sorted` with bandwidth `h` at `x`.
pub fn density(sorted: &[f64], h: f64, x: f64) -> f64 {
    let lo = sorted.partition_point(|v| *v < x - CUTOFF * h);
    let hi = sorted.partition_point(|v| *v <= x + CUTOFF * h);
    let sum: f64 = sorted[lo..hi]
        .iter()
        .map(|v| (-0.5 * ((x - v) / h).powi(2)).exp())
        .sum();
    sum / (sorted.len() as f64 * h * (std::f64::consts::TAU).sqrt())
}

/// The density curve of `values` at `points` evenly spaced x over `range` (x, density).
pub fn pdf_curve(values: &[f64], range: (f64, f64), points: usize) -> Vec<(f64, f64)> {
    let v = sorted_finite(values.iter().copied());
    if v.is_empty() || points < 2 {
        return Vec::new();
    }
    let h = bandwidth(&v);
    let step = (range.1 - range.0) / (points - 1) as f64;
    (0..points)
        .map(|k| {
            let x = range.0 + k as f64 * step;
            (x, density(&v, h, x))
        })
        .collect()
}

/// The peak of the density of `sorted` (non-empty): the best of a grid over the 1st–99th
/// percentile range, refined on a finer grid around it.
pub fn mode(sorted: &[f64]) -> f64 {
    let h = bandwidth(sorted);
    let (mut lo, mut hi) = (quantile(sorted, 0.01) - h, quantile(sorted, 0.99) + h);
    let mut best = lo;
    for _ in 0..2 {
        let step = (hi - lo) / (MODE_GRID - 1) as f64;
        let mut best_d = f64::NEG_INFINITY;
        for k in 0..MODE_GRID {
            let x = lo + k as f64 * step;
            let d = density(sorted, h, x);
            if d > best_d {
                (best, best_d) = (x, d);
            }
        }
        (lo, hi) = (best - 2.0 * step, best + 2.0 * step);
    }
    best
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// The bootstrap interval of a mean: about ±1.96 σ/√n for a large normal-like sample,
    /// around the mean, the same for the same sample, a point for one value.
    #[test]
    fn the_bootstrap_interval_brackets_the_mean_by_its_standard_error() {
        // 400 evenly spread values on [0, 1]: σ = 0.2887, σ/√n = 0.01443
        let v: Vec<f64> = (0..400).map(|k| (k as f64 + 0.5) / 400.0).collect();
        let d = describe(v.iter().copied()).unwrap();
        let [lo, hi] = d.ci95;
        assert!(lo < d.mean && d.mean < hi, "{d:?}");
        let half = 1.96 * (1.0f64 / 12.0).sqrt() / 20.0;
        assert!(
            ((hi - lo) / 2.0 / half - 1.0).abs() < 0.15,
            "{lo} {hi} vs ±{half}"
        );
        assert!(((lo + hi) / 2.0 - d.mean).abs() < 0.2 * half);
        assert_eq!(describe(v.iter().copied()).unwrap().ci95, d.ci95);
        assert_eq!(describe([0.7]).unwrap().ci95, [0.7, 0.7]);
    }

    #[test]
    fn quantiles_by_hand() {
        let v = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(quantile(&v, 0.5), 2.5);
        assert_eq!(quantile(&v, 0.0), 1.0);
        assert_eq!(quantile(&v, 1.0), 4.0);
        assert!((quantile(&v, 0.25) - 1.75).abs() < 1e-15);
    }

    #[test]
    fn the_mode_finds_the_peak_of_a_skewed_sample() {
        // a triangular sample peaking at 0.85 on [0, 1]: most values near 0.85, mean 0.617
        let n = 20_000;
        let c: f64 = 0.85;
        let v: Vec<f64> = (0..n)
            .map(|k| {
                let u = (k as f64 + 0.5) / n as f64;
                if u < c {
                    (u * c).sqrt()
                } else {
                    1.0 - ((1.0 - u) * (1.0 - c)).sqrt()
                }
            })
            .collect();
        let d = describe(v.iter().copied()).unwrap();
        assert!((d.mean - (1.0 + c) / 3.0).abs() < 1e-3, "{d:?}");
        assert!((d.mode - c).abs() < 0.05, "{d:?}");
        assert!((d.p50 - (0.5_f64 * c).sqrt()).abs() < 1e-3, "{d:?}");
    }

    #[test]
    fn density_integrates_to_one_and_ignores_non_finite_values() {
        let v = [0.1, 0.2, 0.25, 0.7, f64::NAN, f64::INFINITY];
        let curve = pdf_curve(&v, (-2.0, 3.0), 2001);
        let dx = 5.0 / 2000.0;
        let area: f64 = curve.iter().map(|(_, d)| d * dx).sum();
        assert!((area - 1.0).abs() < 1e-3, "{area}");
        assert!(describe([f64::NAN]).is_none());
        assert!(quantile(&[], 0.5).is_nan());
        assert_eq!(describe([0.4, f64::NAN]).unwrap().n, 1);
        let constant = describe([0.3; 10]).unwrap();
        assert!((constant.mode - 0.3).abs() < 1e-6 && constant.p50 == 0.3);
    }
}

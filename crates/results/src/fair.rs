//! Order statistics and interval estimates for comparing simulated with observed samples
//! fairly (used by `rockfall validate` and `rockfall calibrate`):
//!
//! - the largest of m independent values drawn from a distribution F has
//!   `P(max ≤ x) = F(x)^m`, so its p-quantile is `F⁻¹(p^{1/m})` (order statistics; e.g. David &
//!   Nagaraja, *Order Statistics*, §2.1);
//! - an observed share gets its 95 % Wilson score interval (Wilson 1927).

use crate::Distribution;

/// Quantiles of the largest of a group of values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroupMax {
    /// Rocks (or crossings) per group.
    pub group: f64,
    /// 5th percentile of the group maximum.
    pub p5: f64,
    /// Median of the group maximum.
    pub p50: f64,
    /// 95th percentile of the group maximum.
    pub p95: f64,
}

/// The quantiles of the largest of `m` independent draws from `d` (m ≥ 1; linear within a
/// histogram bin); `None` for an empty distribution.
pub fn group_max(d: &Distribution, m: f64) -> Option<GroupMax> {
    if d.count == 0 || m.is_nan() || m < 1.0 {
        return None;
    }
    let q = |p: f64| quantile(d, p.powf(1.0 / m));
    Some(GroupMax {
        group: m,
        p5: q(0.05)?,
        p50: q(0.5)?,
        p95: q(0.95)?,
    })
}

/// The p-quantile of `d` (0 ≤ p ≤ 1), linear within its bins, never above its maximum.
pub fn quantile(d: &Distribution, p: f64) -> Option<f64> {
    let total = d.bins.iter().map(|b| b.count).sum::<u64>();
    if total == 0 {
        return None;
    }
    let target = p.clamp(0.0, 1.0) * total as f64;
    let mut below = 0.0;
    for b in &d.bins {
        let c = b.count as f64;
        if c > 0.0 && below + c >= target {
            let x = b.lo + (b.hi - b.lo) * ((target - below) / c).clamp(0.0, 1.0);
            return Some(d.max.map_or(x, |m| x.min(m)));
        }
        below += c;
    }
    d.max
}

/// The 95 % Wilson score interval of a share `pct` (%) observed on `n` items, in %.
pub fn wilson_ci95(pct: f64, n: u32) -> [f64; 2] {
    let z = 1.959_963_984_540_054;
    let n = f64::from(n.max(1));
    let p = (pct / 100.0).clamp(0.0, 1.0);
    let centre = (p + z * z / (2.0 * n)) / (1.0 + z * z / n);
    let half = z / (1.0 + z * z / n) * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt();
    [
        100.0 * (centre - half).max(0.0),
        100.0 * (centre + half).min(1.0),
    ]
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::Bin;

    /// Uniform on [0, 100) in 100 bins of 1, `per_bin` values each.
    fn uniform(per_bin: u64) -> Distribution {
        Distribution {
            count: 100 * per_bin,
            max: Some(100.0),
            bins: (0..100)
                .map(|i| Bin {
                    lo: f64::from(i),
                    hi: f64::from(i + 1),
                    count: per_bin,
                })
                .collect(),
        }
    }

    #[test]
    fn quantiles_of_a_uniform_histogram() {
        let d = uniform(10);
        assert!((quantile(&d, 0.25).unwrap() - 25.0).abs() < 1e-9);
        assert!((quantile(&d, 0.999).unwrap() - 99.9).abs() < 1e-9);
        assert_eq!(quantile(&d, 1.0), Some(100.0));
    }

    #[test]
    fn quantiles_never_pass_the_exact_maximum() {
        // the last bin reaches 100 but the largest value counted is 93
        let d = Distribution {
            count: 10,
            max: Some(93.0),
            bins: vec![Bin {
                lo: 90.0,
                hi: 100.0,
                count: 10,
            }],
        };
        assert_eq!(quantile(&d, 1.0), Some(93.0));
        assert!((quantile(&d, 0.2).unwrap() - 92.0).abs() < 1e-9);
    }

    #[test]
    fn group_maximum_by_order_statistics() {
        // the largest of m uniforms on [0, 100): P(max ≤ x) = (x/100)^m
        let d = uniform(1000);
        let g = group_max(&d, 100.0).unwrap();
        let exact = |p: f64| 100.0 * p.powf(0.01);
        assert!((g.p50 - exact(0.5)).abs() < 1e-6, "{g:?}");
        assert!((g.p5 - exact(0.05)).abs() < 1e-6);
        assert!((g.p95 - exact(0.95)).abs() < 1e-6);
        assert!(g.p5 < g.p50 && g.p50 < g.p95);
        // a group of one is the distribution itself; larger groups reach further
        let one = group_max(&d, 1.0).unwrap();
        assert!((one.p50 - 50.0).abs() < 1e-9);
        assert!(group_max(&d, 1000.0).unwrap().p50 > g.p50);
        assert_eq!(group_max(&d, 0.5), None);
    }

    #[test]
    fn wilson_interval_by_hand() {
        // 5 of 100: the textbook interval 2.15–11.18 %
        let [lo, hi] = wilson_ci95(5.0, 100);
        assert!(
            (lo - 2.154).abs() < 0.01 && (hi - 11.175).abs() < 0.01,
            "{lo} {hi}"
        );
        // 0 of 100 still has an upper bound
        let [lo, hi] = wilson_ci95(0.0, 100);
        assert!(lo.abs() < 1e-12, "{lo}");
        assert!((hi - 3.699).abs() < 0.01, "{hi}");
        let [lo, hi] = wilson_ci95(74.0, 100);
        assert!(lo < 74.0 && hi > 74.0 && hi - lo < 20.0);
    }
}

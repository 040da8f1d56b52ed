//! Order-independent statistics: fixed-point integer sums, maxima and fixed-bin log histograms.
//!
//! Every value is first *cleaned* ([`clean`]): NaN becomes 0, negative values 0, values above
//! [`VALUE_CAP`] the cap. Sums are of the cleaned value quantised to an integer number of
//! fixed-point units (`(value × scale).round()` as `u64`) and are kept in `u128`, so adding
//! them is exact and associative: any merge order gives the same bits. Maxima use `f64::max`
//! (commutative and associative on non-NaN values). Histograms count values in log-spaced bins
//! ([`LogAxis`]) and give percentiles to within one bin (see [`LogAxis::percentile`]).
//!
//! Overflow: a `u64` of a cleaned value × scale is at most 10¹² × 10⁶ = 10¹⁸ < 1.8·10¹⁹, and a
//! `u128` sum of 10¹⁰ such values is 10²⁸ < 3.4·10³⁸.

use std::sync::LazyLock;

/// Largest value kept (in the quantity's unit: J, m, m/s, s); larger ones are clamped.
pub(crate) const VALUE_CAP: f64 = 1e12;

/// Bins per decade of every axis: bin edges grow by the ratio 10^(1/32) ≈ 1.0746.
pub(crate) const BINS_PER_DECADE: u32 = 32;

/// Largest relative error of a percentile inside an axis' range: one bin width,
/// 10^(1/32) − 1 ≈ 7.46 %.
pub const PERCENTILE_RELATIVE_ERROR: f64 = 0.074_607_9;

/// Fixed-point units per joule (sums of energies are in mJ).
pub(crate) const ENERGY_SCALE: f64 = 1e3;
/// Fixed-point units per metre, metre per second and second (sums in µm, µm/s, µs).
pub(crate) const LENGTH_SCALE: f64 = 1e6;

/// A value made safe for the statistics: NaN and negative values → 0, larger than
/// [`VALUE_CAP`] → the cap.
#[inline]
pub(crate) fn clean(v: f64) -> f64 {
    if v.is_nan() {
        0.0
    } else {
        v.clamp(0.0, VALUE_CAP)
    }
}

/// The cleaned value in fixed-point units.
#[inline]
pub(crate) fn fixed(v: f64, scale: f64) -> u64 {
    // `as` saturates; the cleaned value times either scale fits a u64 anyway.
    (clean(v) * scale).round() as u64
}

/// Mean from a fixed-point sum, in the quantity's unit; `None` for no values.
pub(crate) fn mean(sum: u128, count: u64, scale: f64) -> Option<f64> {
    (count > 0).then(|| sum as f64 / count as f64 / scale)
}

/// Log-spaced bins over `[lo, lo·10^decades)`, [`BINS_PER_DECADE`] per decade, plus an
/// underflow bin (index 0: values below `lo`, including 0) and an overflow bin (last index:
/// values at or above the top edge).
#[derive(Debug)]
pub(crate) struct LogAxis {
    /// `edges[i] = lo · 10^(i / BINS_PER_DECADE)`, `i = 0 ..= decades·BINS_PER_DECADE`.
    edges: Vec<f64>,
}

impl LogAxis {
    fn new(lo: f64, decades: u32) -> LogAxis {
        let n = decades * BINS_PER_DECADE;
        let edges = (0..=n)
            .map(|i| lo * 10f64.powf(f64::from(i) / f64::from(BINS_PER_DECADE)))
            .collect();
        LogAxis { edges }
    }

    /// Number of bins, underflow and overflow included.
    pub(crate) fn len(&self) -> usize {
        self.edges.len() + 1
    }

    /// Bin of a cleaned value: the number of edges at or below it.
    #[inline]
    pub(crate) fn bin(&self, v: f64) -> usize {
        self.edges.partition_point(|&e| e <= v)
    }

    /// The `p`-th percentile (`p` in 0 ..= 100) of the values counted in `counts` (one count
    /// per bin), clamped to their exact maximum `max`; `None` when nothing was counted.
    ///
    /// The target rank is `r = p/100 · n`; the value is interpolated inside the bin holding the
    /// `⌈r⌉`-th smallest value: geometrically inside a log bin, linearly in the underflow bin
    /// `[0, lo)`, geometrically between the top edge and `max` in the overflow bin. The
    /// nearest-rank percentile lies in the same bin, so the error is at most one bin: a
    /// relative error below [`PERCENTILE_RELATIVE_ERROR`] inside the range, an absolute error
    /// below `lo` under it, and at most `max / top − 1` relative above it.
    pub(crate) fn percentile<C: Copy + Into<u64>>(
        &self,
        counts: &[C],
        p: f64,
        max: f64,
    ) -> Option<f64> {
        self.percentile_of_bins(counts.iter().copied().enumerate(), p, max)
    }

    /// As [`LogAxis::percentile`], of the `(bin, count)` pairs of `bins` (ascending bins;
    /// bins left out count 0): the same value, bit for bit, as of the dense counts.
    pub(crate) fn percentile_of_bins<C: Copy + Into<u64>>(
        &self,
        bins: impl Iterator<Item = (usize, C)> + Clone,
        p: f64,
        max: f64,
    ) -> Option<f64> {
        let total: u64 = bins.clone().map(|(_, c)| c.into()).sum();
        self.percentile_of_counted(bins, total, p, max)
    }

    /// As [`LogAxis::percentile_of_bins`] when the sum of the counts, `total`, is known.
    pub(crate) fn percentile_of_counted<C: Copy + Into<u64>>(
        &self,
        bins: impl Iterator<Item = (usize, C)>,
        total: u64,
        p: f64,
        max: f64,
    ) -> Option<f64> {
        if total == 0 || p.is_nan() {
            return None;
        }
        let rank = p.clamp(0.0, 100.0) / 100.0 * total as f64;
        let mut before = 0u64;
        for (i, c) in bins {
            let c: u64 = c.into();
            if c == 0 {
                continue;
            }
            let after = before + c;
            if (after as f64) >= rank || after == total {
                let f = ((rank - before as f64) / c as f64).clamp(0.0, 1.0);
                let top = self.edges[self.edges.len() - 1];
                let v = if i == 0 {
                    self.edges[0] * f
                } else if i >= self.edges.len() {
                    top * (max.max(top) / top).powf(f)
                } else {
                    let (a, b) = (self.edges[i - 1], self.edges[i]);
                    a * (b / a).powf(f)
                };
                return Some(v.min(max));
            }
            before = after;
        }
        None
    }
}

/// Energies, J: 1 J … 10¹⁰ J (320 log bins + 2).
pub(crate) static ENERGY_AXIS: LazyLock<LogAxis> = LazyLock::new(|| LogAxis::new(1.0, 10));
/// Heights (m) and speeds (m/s): 10⁻³ … 10³ (192 log bins + 2).
pub(crate) static SHORT_AXIS: LazyLock<LogAxis> = LazyLock::new(|| LogAxis::new(1e-3, 6));
/// Runout distances (m) and times (s): 10⁻³ … 10⁵ (256 log bins + 2).
pub(crate) static LONG_AXIS: LazyLock<LogAxis> = LazyLock::new(|| LogAxis::new(1e-3, 8));

/// Bins of [`ENERGY_AXIS`].
pub(crate) const ENERGY_BINS: usize = 10 * BINS_PER_DECADE as usize + 2;
/// Bins of [`SHORT_AXIS`].
pub(crate) const SHORT_BINS: usize = 6 * BINS_PER_DECADE as usize + 2;

/// Count, fixed-point sum, maximum and histogram of one quantity (a global statistic: `u64`
/// bin counts).
#[derive(Debug, Clone)]
pub(crate) struct Stat {
    axis: &'static LazyLock<LogAxis>,
    scale: f64,
    pub(crate) count: u64,
    pub(crate) sum: u128,
    pub(crate) max: f64,
    pub(crate) hist: Vec<u64>,
}

impl Stat {
    /// An empty statistic on `axis` with `scale` fixed-point units per unit.
    pub(crate) fn new(axis: &'static LazyLock<LogAxis>, scale: f64) -> Stat {
        Stat {
            axis,
            scale,
            count: 0,
            sum: 0,
            max: 0.0,
            hist: vec![0; axis.len()],
        }
    }

    /// Adds one value.
    pub(crate) fn add(&mut self, v: f64) {
        let v = clean(v);
        self.count += 1;
        self.sum += u128::from(fixed(v, self.scale));
        self.max = self.max.max(v);
        self.hist[self.axis.bin(v)] += 1;
    }

    /// Adds every value of `other` (same axis and scale).
    pub(crate) fn merge(&mut self, other: &Stat) {
        self.count += other.count;
        self.sum += other.sum;
        self.max = self.max.max(other.max);
        for (a, b) in self.hist.iter_mut().zip(&other.hist) {
            *a += b;
        }
    }

    /// Number of values.
    pub(crate) fn count(&self) -> u64 {
        self.count
    }

    /// Mean, `None` without values.
    pub(crate) fn mean(&self) -> Option<f64> {
        mean(self.sum, self.count, self.scale)
    }

    /// Exact maximum, `None` without values.
    pub(crate) fn max(&self) -> Option<f64> {
        (self.count > 0).then_some(self.max)
    }

    /// `p`-th percentile (see [`LogAxis::percentile`]).
    pub(crate) fn percentile(&self, p: f64) -> Option<f64> {
        self.axis.percentile(&self.hist, p, self.max)
    }

    /// The histogram as its non-empty bins `(lo, hi, count)`, ascending: the underflow bin is
    /// `[0, lo)` (0 included), a log bin `[edge, next edge)`, the overflow bin `[top, max]`
    /// (of zero width should the maximum be the top edge itself).
    pub(crate) fn bins(&self) -> Vec<(f64, f64, u64)> {
        let edges = &self.axis.edges;
        let top = edges[edges.len() - 1];
        (self.hist.iter().enumerate())
            .filter(|&(_, &c)| c > 0)
            .map(|(i, &c)| {
                let lo = if i == 0 { 0.0 } else { edges[i - 1] };
                let hi = edges.get(i).copied().unwrap_or(top.max(self.max));
                (lo, hi, c)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nearest-rank percentile of sorted values.
    fn exact(sorted: &[f64], p: f64) -> f64 {
        let r = (p / 100.0 * sorted.len() as f64).ceil().max(1.0) as usize;
        sorted[r - 1]
    }

    #[test]
    fn error_bound_is_one_bin() {
        let ratio = 10f64.powf(1.0 / f64::from(BINS_PER_DECADE));
        assert!((ratio - 1.0 - PERCENTILE_RELATIVE_ERROR).abs() < 1e-6);
        assert_eq!(ENERGY_AXIS.len(), ENERGY_BINS);
        assert_eq!(SHORT_AXIS.len(), SHORT_BINS);
    }

    #[test]
    fn percentiles_within_one_bin_of_the_exact_ones() {
        // 10 000 values spread over 6 decades of energy (log-uniform, LCG), a few zeros.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut values: Vec<f64> = (0..10_000)
            .map(|i| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                let u = (state >> 11) as f64 / (1u64 << 53) as f64;
                if i % 1000 == 0 {
                    0.0
                } else {
                    10f64.powf(1.0 + 6.0 * u)
                }
            })
            .collect();
        let mut stat = Stat::new(&ENERGY_AXIS, ENERGY_SCALE);
        for &v in &values {
            stat.add(v);
        }
        values.sort_by(f64::total_cmp);
        for p in [1.0, 5.0, 25.0, 50.0, 90.0, 95.0, 99.0, 99.9, 100.0] {
            let est = stat.percentile(p).unwrap();
            let ex = exact(&values, p);
            let rel = (est / ex - 1.0).abs();
            assert!(
                rel <= PERCENTILE_RELATIVE_ERROR,
                "p{p}: {est} vs {ex} ({rel})"
            );
        }
        // p0 is in the underflow bin (zeros): within lo = 1 J of the exact 0.
        assert!(stat.percentile(0.0).unwrap() < 1.0);
        assert_eq!(stat.percentile(100.0), Some(values[values.len() - 1]));
        let exact_mean = values.iter().sum::<f64>() / values.len() as f64;
        assert!((stat.mean().unwrap() / exact_mean - 1.0).abs() < 1e-9);
    }

    #[test]
    fn percentile_is_clamped_to_the_maximum_and_handles_out_of_range() {
        let mut s = Stat::new(&SHORT_AXIS, LENGTH_SCALE);
        assert_eq!(s.percentile(50.0), None);
        assert_eq!(s.mean(), None);
        assert_eq!(s.max(), None);
        s.add(2.0);
        assert_eq!(s.percentile(95.0), Some(2.0));
        s.add(5e3); // above the axis: overflow bin
        s.add(f64::NAN); // → 0, underflow bin
        s.add(-1.0); // → 0
        assert_eq!(s.max(), Some(5e3));
        assert_eq!(s.percentile(100.0), Some(5e3));
        let p95 = s.percentile(95.0).unwrap();
        assert!((1e3..=5e3).contains(&p95), "{p95}");
        assert!(s.percentile(10.0).unwrap() < 1e-3);
    }

    #[test]
    fn bins_follow_the_edges() {
        let a = &*SHORT_AXIS;
        assert_eq!(a.bin(0.0), 0);
        assert_eq!(a.bin(0.999e-3), 0);
        assert_eq!(a.bin(1e-3), 1);
        assert_eq!(a.bin(1e3), a.len() - 1);
        assert_eq!(a.bin(VALUE_CAP), a.len() - 1);
        assert_eq!(fixed(1.5, LENGTH_SCALE), 1_500_000);
        assert_eq!(fixed(f64::INFINITY, ENERGY_SCALE), 1e15 as u64);
    }

    #[test]
    fn bins_hold_every_value_inside_their_edges() {
        let mut s = Stat::new(&SHORT_AXIS, LENGTH_SCALE);
        let values = [0.0, 5e-4, 0.5, 0.52, 7.0, 7.0, 999.0, 2500.0];
        for v in values {
            s.add(v);
        }
        let bins = s.bins();
        assert_eq!(bins.iter().map(|b| b.2).sum::<u64>(), values.len() as u64);
        assert!(bins.windows(2).all(|w| w[0].1 <= w[1].0), "{bins:?}");
        for v in values {
            let inside = |b: &&(f64, f64, u64)| b.0 <= v && (v < b.1 || v == 2500.0 && v == b.1);
            assert!(
                bins.iter().find(inside).is_some(),
                "{v} in no bin of {bins:?}"
            );
        }
        assert_eq!(bins[0], (0.0, 1e-3, 2));
        assert_eq!(bins.last().copied(), Some((1e3, 2500.0, 1)));
        let twin = bins.iter().find(|b| b.0 <= 7.0 && 7.0 < b.1).unwrap();
        assert_eq!(twin.2, 2);
        assert!(twin.1 / twin.0 < 1.08);
    }
}

//! Speed along the slope: every cell visit's speed, by horizontal distance from the rock's
//! release point.
//!
//! It runs for every cell visit, so it is kept cheap: per distance bin a linear histogram of
//! speeds in [`SPEED_STEP_MS`] steps (an O(1) bin, integer counts, merged exactly) and the
//! exact maximum. Percentiles are within one step.

use crate::{Layout, Results};

/// Most distance bins a profile keeps; farther visits count in the last one.
const MAX_BINS: usize = 2000;
/// Width of a speed bin, m/s: the accuracy of the profile's percentiles.
pub const SPEED_STEP_MS: f64 = 0.25;
/// Speed bins: 0 … 128 m/s, faster visits in the last one.
const SPEED_BINS: usize = 512;

/// The speeds of the visits at one distance.
#[derive(Debug, Clone)]
pub(crate) struct SpeedHistogram {
    /// Visits per speed bin `[j·step, (j+1)·step)`.
    pub(crate) counts: Vec<u64>,
    /// Largest speed, m/s.
    pub(crate) max_ms: f64,
}

impl SpeedHistogram {
    pub(crate) fn new() -> Self {
        SpeedHistogram {
            counts: vec![0; SPEED_BINS],
            max_ms: 0.0,
        }
    }

    fn add(&mut self, speed_ms: f64) {
        let v = if speed_ms > 0.0 { speed_ms } else { 0.0 }; // NaN → 0
        let j = ((v / SPEED_STEP_MS) as usize).min(SPEED_BINS - 1);
        self.counts[j] += 1;
        self.max_ms = self.max_ms.max(v);
    }

    fn merge(&mut self, other: &SpeedHistogram) {
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
        self.max_ms = self.max_ms.max(other.max_ms);
    }

    fn count(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// The `p`-th percentile of `total` visits: linear inside the bin holding the rank, at
    /// most the maximum.
    fn percentile(&self, p: f64, total: u64) -> f64 {
        let rank = p / 100.0 * total as f64;
        let mut before = 0u64;
        for (j, &c) in self.counts.iter().enumerate().filter(|(_, c)| **c > 0) {
            if (before + c) as f64 >= rank {
                let f = ((rank - before as f64) / c as f64).clamp(0.0, 1.0);
                let lo = j as f64 * SPEED_STEP_MS;
                let hi = match j + 1 == SPEED_BINS {
                    true => self.max_ms.max(lo), // the open-ended last bin ends at the maximum
                    false => lo + SPEED_STEP_MS,
                };
                return (lo + f * (hi - lo)).min(self.max_ms);
            }
            before += c;
        }
        self.max_ms
    }
}

/// Per distance bin, the speeds of the cell visits at that distance (a global statistic,
/// merged exactly like the others).
#[derive(Debug, Clone)]
pub(crate) struct SpeedProfile {
    /// Width of a bin, m.
    pub(crate) bin_m: f64,
    /// Bin `k` holds visits at distances in `[k·bin_m, (k+1)·bin_m)`; grown on demand.
    pub(crate) bins: Vec<SpeedHistogram>,
}

impl SpeedProfile {
    /// An empty profile for `layout`: bins one cell wide, or wider on grids whose diagonal
    /// spans more than [`MAX_BINS`] cells.
    pub(crate) fn new(layout: &Layout) -> SpeedProfile {
        let g = &layout.geometry;
        let diagonal_m = (g.ncols as f64).hypot(g.nrows as f64) * g.cell_size_m;
        SpeedProfile {
            bin_m: g.cell_size_m.max(diagonal_m / MAX_BINS as f64),
            bins: Vec::new(),
        }
    }

    /// Adds a visit at `distance_m` from its release point with speed `speed_ms`.
    pub(crate) fn add(&mut self, distance_m: f64, speed_ms: f64) {
        let k = (distance_m.max(0.0) / self.bin_m) as usize; // NaN → 0
        let k = k.min(MAX_BINS - 1);
        if k >= self.bins.len() {
            self.bins.resize_with(k + 1, SpeedHistogram::new);
        }
        self.bins[k].add(speed_ms);
    }

    /// Adds everything `other` (a profile of the same layout) holds.
    pub(crate) fn merge(&mut self, other: &SpeedProfile) {
        if other.bins.len() > self.bins.len() {
            self.bins.resize_with(other.bins.len(), SpeedHistogram::new);
        }
        for (a, b) in self.bins.iter_mut().zip(&other.bins) {
            a.merge(b);
        }
    }
}

/// One distance bin of [`Results::speed_profile`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProfileBin {
    /// Horizontal distance from release where the bin starts, m.
    pub from_m: f64,
    /// Where it ends, m.
    pub to_m: f64,
    /// Cell visits in the bin.
    pub visits: u64,
    /// Median speed of the visits, m/s (within [`SPEED_STEP_MS`]).
    pub median_ms: f64,
    /// 95th percentile of their speed, m/s (same accuracy).
    pub p95_ms: f64,
    /// Largest speed, m/s (exact).
    pub max_ms: f64,
}

impl Results {
    /// Speed along the slope: for every distance from the release point (bins one cell wide,
    /// wider on grids more than 2000 cells across), the speeds of every rock's cell visits
    /// there (each visit's largest speed in the cell, distance from the rock's release point
    /// to the cell's centre). Bins without visits are left out. Memory: 4 kB per distance
    /// bin reached, per worker.
    pub fn speed_profile(&self) -> Vec<ProfileBin> {
        let p = &self.tally.profile;
        (p.bins.iter().enumerate())
            .map(|(k, s)| (k, s, s.count()))
            .filter(|&(_, _, n)| n > 0)
            .map(|(k, s, n)| ProfileBin {
                from_m: k as f64 * p.bin_m,
                to_m: (k + 1) as f64 * p.bin_m,
                visits: n,
                median_ms: s.percentile(50.0, n),
                p95_ms: s.percentile(95.0, n),
                max_ms: s.max_ms,
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rockfall_raster::GridGeometry;

    fn layout(ncols: usize, nrows: usize, cell_size_m: f64) -> Layout {
        Layout {
            geometry: GridGeometry {
                ncols,
                nrows,
                x_min_m: 0.0,
                y_min_m: 0.0,
                cell_size_m,
            },
            crs: None,
            screens: Vec::new(),
            percentiles: Vec::new(),
            energy_thresholds_kj: Vec::new(),
            trajectories: 0,
            rock_ends: false,
            screen_crossings: false,
            elevation: Default::default(),
            trusted: Default::default(),
        }
    }

    #[test]
    fn bins_are_a_cell_wide_unless_the_grid_spans_more_than_max_bins_cells() {
        assert_eq!(SpeedProfile::new(&layout(60, 142, 2.5)).bin_m, 2.5);
        let big = SpeedProfile::new(&layout(6000, 8000, 1.0));
        assert!(
            (big.bin_m - 10_000.0 / MAX_BINS as f64).abs() < 1e-9,
            "{}",
            big.bin_m
        );
        let mut p = SpeedProfile::new(&layout(10, 10, 1.0));
        p.add(1e9, 3.0);
        assert_eq!(
            p.bins.len(),
            MAX_BINS,
            "farther visits go into the last bin"
        );
    }

    #[test]
    fn speed_percentiles_are_within_a_step() {
        let mut h = SpeedHistogram::new();
        let speeds: Vec<f64> = (0..1000).map(|i| f64::from(i) * 0.0173).collect();
        for &v in &speeds {
            h.add(v);
        }
        h.add(f64::NAN);
        h.add(500.0);
        let n = h.count();
        assert_eq!(n, 1002);
        for p in [5.0, 50.0, 95.0] {
            let rank = (p / 100.0 * n as f64).ceil() as usize;
            let exact = speeds.get(rank - 2).copied().unwrap_or(0.0); // NaN counted as 0 first
            let got = h.percentile(p, n);
            assert!(
                (got - exact).abs() <= SPEED_STEP_MS,
                "p{p}: {got} vs {exact}"
            );
        }
        assert_eq!(h.max_ms, 500.0);
        assert_eq!(h.percentile(100.0, n), 500.0);
    }
}

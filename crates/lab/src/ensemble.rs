//! Statistics of a class of rocks with their 95 % intervals, over an ensemble of shapes and
//! the rocks of each.
//!
//! A class (`rough-flat2.2*10`: ten members of the rough flat rocks of Π 2.2) is run once per
//! member; its statistics are those of all its rocks pooled. Their intervals come from a
//! two-stage (hierarchical) percentile bootstrap (Davison & Hinkley 1997, *Bootstrap Methods
//! and their Application*, §3.8, "multi-stage sampling"): each of [`RESAMPLES`] replicates
//! draws the members with replacement, then within each drawn member its rocks with
//! replacement, and computes the statistic on that pool; the interval is the 2.5th and 97.5th
//! percentiles of the replicates. Drawing members first lets the interval carry the variation
//! between shapes of a class as well as between rocks of one shape; with one member it is the
//! ordinary bootstrap over rocks. The stream is keyed by the sample's sizes only, so the
//! intervals are a pure function of the sample.

use crate::stats::quantile;
use rand::RngExt;
use serde::Serialize;

/// Bootstrap replicates of each interval.
pub const RESAMPLES: usize = 1000;

/// What a rock contributes: its run-out and final lateral offset along and across the fall
/// line (m) and its time in each mode of motion (s, as `rockfall_results::Motion::as_array`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RockMeasure {
    /// Run-out along the fall line, m.
    pub runout_m: f64,
    /// Final lateral offset, m.
    pub lateral_m: f64,
    /// Time per mode of motion, s.
    pub motion_s: [f64; 5],
}

/// A statistic of the pooled rocks and its 95 % interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    /// The statistic of all rocks.
    pub value: f64,
    /// Its 95 % two-stage bootstrap interval.
    pub ci95: [f64; 2],
}

/// The statistics of a class with intervals.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ClassEstimates {
    /// Members (shapes) of the class.
    pub members: usize,
    /// Mean run-out, m.
    pub runout_mean_m: Estimate,
    /// 95th percentile of run-out, m.
    pub runout_p95_m: Estimate,
    /// Standard deviation of the final lateral offsets, m.
    pub lateral_sd_m: Estimate,
    /// Width of the central 90 % of the final lateral offsets, m.
    pub spread_width_m: Estimate,
    /// Share of the rocks' time in each mode of motion (flight, rolling, sliding on a face,
    /// sliding on an edge, slow), NaN when no time was classified.
    pub motion_share: [Estimate; 5],
}

/// The statistics of one pool of rocks, in the order of [`ClassEstimates`]' fields.
fn statistics(pool: &[RockMeasure]) -> [f64; 9] {
    let n = pool.len() as f64;
    let mut runout: Vec<f64> = pool.iter().map(|r| r.runout_m).collect();
    let mut lateral: Vec<f64> = pool.iter().map(|r| r.lateral_m).collect();
    runout.sort_by(f64::total_cmp);
    lateral.sort_by(f64::total_cmp);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / n;
    let lateral_mean = mean(&lateral);
    let sd = (lateral
        .iter()
        .map(|x| (x - lateral_mean).powi(2))
        .sum::<f64>()
        / (n - 1.0))
        .sqrt();
    let mut time = [0.0; 5];
    for r in pool {
        for (t, m) in time.iter_mut().zip(r.motion_s) {
            *t += m;
        }
    }
    let total: f64 = time.iter().sum();
    let share = |k: usize| {
        if total > 0.0 {
            time[k] / total
        } else {
            f64::NAN
        }
    };
    [
        mean(&runout),
        quantile(&runout, 0.95),
        sd,
        quantile(&lateral, 0.95) - quantile(&lateral, 0.05),
        share(0),
        share(1),
        share(2),
        share(3),
        share(4),
    ]
}

/// The estimates of a class whose members' rocks are `members` (each non-empty); `None`
/// without rocks.
pub fn estimates(members: &[Vec<RockMeasure>]) -> Option<ClassEstimates> {
    let members: Vec<&Vec<RockMeasure>> = members.iter().filter(|m| !m.is_empty()).collect();
    let pooled: Vec<RockMeasure> = members.iter().flat_map(|m| m.iter().copied()).collect();
    if pooled.is_empty() {
        return None;
    }
    let point = statistics(&pooled);
    let mut rng = rockfall_rng::stream(
        0,
        rockfall_rng::Purpose::Sampling,
        &[
            0x656e_7365_6d62_6c65,
            members.len() as u64,
            pooled.len() as u64,
        ],
    );
    let mut replicates: Vec<[f64; 9]> = Vec::with_capacity(RESAMPLES);
    let mut pool = Vec::with_capacity(pooled.len());
    for _ in 0..RESAMPLES {
        pool.clear();
        for _ in 0..members.len() {
            let m = members[rng.random_range(0..members.len())];
            pool.extend((0..m.len()).map(|_| m[rng.random_range(0..m.len())]));
        }
        replicates.push(statistics(&pool));
    }
    let estimate = |k: usize| {
        let mut v: Vec<f64> = replicates
            .iter()
            .map(|r| r[k])
            .filter(|x| x.is_finite())
            .collect();
        v.sort_by(f64::total_cmp);
        Estimate {
            value: point[k],
            ci95: [quantile(&v, 0.025), quantile(&v, 0.975)],
        }
    };
    Some(ClassEstimates {
        members: members.len(),
        runout_mean_m: estimate(0),
        runout_p95_m: estimate(1),
        lateral_sd_m: estimate(2),
        spread_width_m: estimate(3),
        motion_share: [
            estimate(4),
            estimate(5),
            estimate(6),
            estimate(7),
            estimate(8),
        ],
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn rock(runout_m: f64, lateral_m: f64, rolling_s: f64) -> RockMeasure {
        RockMeasure {
            runout_m,
            lateral_m,
            motion_s: [1.0, rolling_s, 0.0, 0.0, 0.0],
        }
    }

    /// The values are those of the pooled rocks; the intervals contain them, are a pure
    /// function of the sample, and widen when the members differ from each other although
    /// the pool is the same.
    #[test]
    fn intervals_cover_the_pooled_values_and_see_the_members() {
        let alike: Vec<Vec<RockMeasure>> = (0..4)
            .map(|m| {
                (0..50)
                    .map(|k| rock(100.0 + ((k * 7 + m * 13) % 50) as f64, (k % 9) as f64, 1.0))
                    .collect()
            })
            .collect();
        let e = estimates(&alike).unwrap();
        assert_eq!(e.members, 4);
        let pooled: Vec<f64> = alike.iter().flatten().map(|r| r.runout_m).collect();
        let mean = pooled.iter().sum::<f64>() / 200.0;
        assert!((e.runout_mean_m.value - mean).abs() < 1e-12);
        for est in [
            e.runout_mean_m,
            e.runout_p95_m,
            e.lateral_sd_m,
            e.spread_width_m,
            e.motion_share[1],
        ] {
            assert!(
                est.ci95[0] <= est.value && est.value <= est.ci95[1],
                "{est:?}"
            );
        }
        assert!((e.motion_share[1].value - 0.5).abs() < 1e-12);
        assert_eq!(estimates(&alike).unwrap(), e, "deterministic");
        // the same 200 run-outs, but each member holding one quarter of the sorted values
        let mut sorted = pooled.clone();
        sorted.sort_by(f64::total_cmp);
        let apart: Vec<Vec<RockMeasure>> = sorted
            .chunks(50)
            .map(|c| c.iter().map(|&x| rock(x, 0.0, 1.0)).collect())
            .collect();
        let f = estimates(&apart).unwrap();
        assert!((f.runout_mean_m.value - mean).abs() < 1e-9);
        let width = |e: &ClassEstimates| e.runout_mean_m.ci95[1] - e.runout_mean_m.ci95[0];
        assert!(
            width(&f) > 2.0 * width(&e),
            "{} vs {}",
            width(&f),
            width(&e)
        );
        assert!(estimates(&[Vec::new()]).is_none());
    }
}

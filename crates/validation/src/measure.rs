//! The simulated values of seed 000's tables 2 and 3, computed from a run of a Vaujany site
//! exactly as §2.6 defines them.
//!
//! - **average maximum translation velocity**: over rocks, of each rock's largest
//!   translational speed (`summary.json` `max_velocity_ms.mean`); the **maximum** is the
//!   largest of them;
//! - **stopped within the first 223.5 m**: rocks that came to rest (nets aside) less than
//!   223.5 m along the ground from the start, measured on the site's profile at their end
//!   point's position along the fall line (needs the per-rock records);
//! - **passed the lower forest road**: rocks that crossed the screen on the road's lower edge;
//! - **mean tree impacts per rock**: all tree impacts over all rocks;
//! - **rebound height**: vertical height of the rock centre above the ground
//!   (`max_jump_height_m`; at a screen `jump_height_m`);
//! - **at a screen** (table 3): mean and maximum over the crossings of the screen of the
//!   translational velocity, rebound height and kinetic energy (translational + rotational).

use rockfall_results::{Outcome, RockRecord, ScreenSummary, Summary};
use rockfall_sites::vaujany::{ROAD_START_ALONG_M, along_at_y};
use std::collections::BTreeMap;

/// Name of the screen on the lower edge of the road in the built-in sites.
pub const ROAD_SCREEN: &str = "lower_road";

fn put(m: &mut BTreeMap<String, f64>, key: &str, v: Option<f64>) {
    if let Some(v) = v.filter(|v| v.is_finite()) {
        m.insert(key.to_string(), v);
    }
}

/// The screen of `summary.json` named `name`.
fn screen<'a>(summary: &'a Summary, name: &str) -> Option<&'a ScreenSummary> {
    summary.screens.iter().find(|s| s.name == name)
}

/// Table 2's quantities (keys of [`crate::observed`]) of a run on a Vaujany site, from its
/// `summary.json` and per-rock records. Quantities that cannot be computed are left out.
pub fn slope_quantities(summary: &Summary, records: &[RockRecord]) -> BTreeMap<String, f64> {
    let mut m = BTreeMap::new();
    put(&mut m, "mean_max_velocity_ms", summary.max_velocity_ms.mean);
    put(&mut m, "max_velocity_ms", summary.max_velocity_ms.max);
    put(
        &mut m,
        "max_rebound_height_m",
        summary.max_jump_height_m.max,
    );
    put(
        &mut m,
        "tree_impacts_per_rock",
        summary.tree_impacts_per_rock,
    );
    let passed = screen(summary, ROAD_SCREEN).and_then(|s| s.passed_fraction);
    put(&mut m, "passed_lower_road_pct", passed.map(|p| 100.0 * p));
    put(
        &mut m,
        "stopped_within_223_5m_pct",
        stopped_within_pct(records, ROAD_START_ALONG_M),
    );
    m
}

/// Share of rocks at rest (nets aside) less than `along_m` along the ground from the start
/// of a Vaujany site, %; `None` without records.
pub fn stopped_within_pct(records: &[RockRecord], along_m: f64) -> Option<f64> {
    let n = records
        .iter()
        .filter(|r| matches!(r.end.outcome, Outcome::Stopped { .. }))
        .filter(|r| r.end.y_m.is_finite() && along_at_y(r.end.y_m) < along_m)
        .count();
    (!records.is_empty()).then(|| 100.0 * n as f64 / records.len() as f64)
}

/// Table 3's quantities at screen `name` of a run's `summary.json`; empty when no rock
/// crossed it.
pub fn screen_quantities(summary: &Summary, name: &str) -> BTreeMap<String, f64> {
    let mut m = BTreeMap::new();
    let Some(s) = screen(summary, name) else {
        return m;
    };
    for (ours, q) in [
        ("velocity_ms", &s.velocity_ms),
        ("rebound_height_m", &s.jump_height_m),
        ("energy_kj", &s.energy_kj),
    ] {
        put(&mut m, &format!("mean_{ours}"), q.mean);
        put(&mut m, &format!("max_{ours}"), q.max);
    }
    m
}

/// The sample maximum of `observed_rocks` rocks is, in expectation, near the
/// `1 − 1/(n + 1)` quantile of the per-rock values: a maximum over 10 000 simulated rocks
/// reaches further than one over 100 observed ones. Returns that quantile of the per-rock
/// largest velocity (m/s) and rebound height (m), or `None` without records.
pub fn per_rock_quantile_of_max(records: &[RockRecord], observed_rocks: u32) -> Option<(f64, f64)> {
    let p = 1.0 - 1.0 / (f64::from(observed_rocks) + 1.0);
    let q = |f: fn(&RockRecord) -> f64| {
        let mut v: Vec<f64> = records.iter().map(f).filter(|x| x.is_finite()).collect();
        v.sort_by(f64::total_cmp);
        let i = ((v.len() as f64 - 1.0) * p).round() as usize;
        v.get(i).copied()
    };
    Some((
        q(|r| r.end.max_velocity_ms)?,
        q(|r| r.end.max_jump_height_m)?,
    ))
}

/// Rocks by their number of tree impacts: `counts[k]` rocks hit `k` trees.
pub fn tree_impact_counts(records: &[RockRecord]) -> Vec<u64> {
    let mut counts = Vec::new();
    for r in records {
        let k = r.end.tree_impacts as usize;
        if counts.len() <= k {
            counts.resize(k + 1, 0);
        }
        counts[k] += 1;
    }
    counts
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use rockfall_results::{MeanP95Max, RockEnd};
    use rockfall_sites::vaujany::d_at_along;

    fn record(id: u64, outcome: Outcome, along_m: f64, trees: u32) -> RockRecord {
        let y = 6_460_400.0 - d_at_along(along_m);
        RockRecord {
            rock_id: id,
            source_cell: 0,
            start_m: [0.0; 3],
            volume_m3: 1.0,
            mass_kg: 2700.0,
            end: RockEnd {
                outcome,
                x_m: 939_425.0,
                y_m: y,
                runout_m: 0.0,
                max_velocity_ms: 0.0,
                max_jump_height_m: 0.0,
                tree_impacts: trees,
                stems_broken: 0,
                rebounds: 0,
                time_s: 0.0,
                events: 0,
                motion: Default::default(),
            },
        }
    }

    #[test]
    fn stopped_within_counts_rocks_at_rest_above_the_mark() {
        let stop = Outcome::Stopped { cell: 0 };
        let recs = [
            record(0, stop, 100.0, 0),
            record(1, stop, 223.0, 3),
            record(2, stop, 224.0, 1),
            record(3, Outcome::NetStopped { cell: 0 }, 50.0, 0),
            record(4, Outcome::LeftDem, 10.0, 3),
        ];
        // an end point that is not a number is not "within"
        let mut nan = recs;
        nan[2].end.y_m = f64::NAN;
        assert_eq!(stopped_within_pct(&nan, 223.5), Some(40.0));
        assert_eq!(stopped_within_pct(&recs, 223.5), Some(40.0));
        assert_eq!(stopped_within_pct(&[], 223.5), None);
        assert_eq!(tree_impact_counts(&recs), vec![2, 1, 0, 2]);
        assert_eq!(per_rock_quantile_of_max(&[], 100), None);
    }

    #[test]
    fn the_quantile_of_a_sample_maximum() {
        let recs: Vec<RockRecord> = (0..1001)
            .map(|i| {
                let mut r = record(i, Outcome::LeftDem, 0.0, 0);
                r.end.max_velocity_ms = i as f64;
                r.end.max_jump_height_m = 2.0 * i as f64;
                r
            })
            .collect();
        // 1 − 1/100 of 0 … 1000 is 990
        assert_eq!(per_rock_quantile_of_max(&recs, 99), Some((990.0, 1980.0)));
    }

    #[test]
    fn quantities_come_from_the_summary_keys() {
        let stats = |mean, max| MeanP95Max {
            mean: Some(mean),
            p95: None,
            max,
        };
        let summary = Summary {
            max_velocity_ms: stats(15.0, Some(30.0)),
            max_jump_height_m: stats(1.0, Some(7.5)),
            tree_impacts_per_rock: Some(2.5),
            screens: vec![
                ScreenSummary {
                    name: "screen_185m".into(),
                    velocity_ms: stats(12.0, Some(28.0)),
                    jump_height_m: stats(1.4, Some(5.0)),
                    energy_kj: stats(200.0, None),
                    ..ScreenSummary::default()
                },
                ScreenSummary {
                    name: "lower_road".into(),
                    passed_fraction: Some(0.74),
                    ..ScreenSummary::default()
                },
            ],
            ..Summary::default()
        };
        let recs = [record(0, Outcome::Stopped { cell: 0 }, 10.0, 0)];
        let m = slope_quantities(&summary, &recs);
        assert_eq!(m["mean_max_velocity_ms"], 15.0);
        assert_eq!(m["max_velocity_ms"], 30.0);
        assert_eq!(m["max_rebound_height_m"], 7.5);
        assert_eq!(m["tree_impacts_per_rock"], 2.5);
        assert_eq!(m["passed_lower_road_pct"], 74.0);
        assert_eq!(m["stopped_within_223_5m_pct"], 100.0);
        let s = screen_quantities(&summary, "screen_185m");
        assert_eq!(s["mean_velocity_ms"], 12.0);
        assert_eq!(s["max_velocity_ms"], 28.0);
        assert_eq!(s["mean_rebound_height_m"], 1.4);
        assert_eq!(s["max_rebound_height_m"], 5.0);
        assert_eq!(s["mean_energy_kj"], 200.0);
        assert!(!s.contains_key("max_energy_kj"), "null is left out");
        assert!(screen_quantities(&summary, "nowhere").is_empty());
        // the keys are those of the published cases
        for p in crate::observed::published() {
            for q in &p.quantities {
                let known = if p.screen.is_some() { &s } else { &m };
                assert!(
                    known.contains_key(q.key) || q.key == "max_energy_kj",
                    "{}",
                    q.key
                );
            }
        }
    }
}

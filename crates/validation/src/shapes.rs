//! Seed 001 §3.4 as a validation case: the forest-slope runs of three rock shapes, where the
//! paper reports findings (fig. 6), not numbers: flat2.2 runs out farthest and spreads widest,
//! long2.2 spreads least.

use crate::case::{CaseReport, Check, Row};
use rockfall_lab::slope::{SlopeStats, ranking};
use rockfall_results::Summary;

/// The shapes of seed 001 table 2, in its order.
pub const SHAPES: [&str; 3] = ["cubic1.2", "flat2.2", "long2.2"];

/// The case of a shape study: per shape its run-out and spread (no observed values), and the
/// paper's three findings checked against them. `summaries` are the runs' `summary.json`, in
/// the order of `stats`.
pub fn shape_case(
    name: &str,
    stats: &[SlopeStats],
    summaries: &[Summary],
    rocks: u64,
) -> CaseReport {
    let mut rows = Vec::new();
    for (s, summary) in stats.iter().zip(summaries) {
        let stopped = summary.stopped_fraction.map(|f| 100.0 * f);
        for (key, what, v) in [
            (
                "runout_p50_m",
                "run-out p50 along the fall line (m)",
                Some(s.runout_m[1]),
            ),
            (
                "runout_p95_m",
                "run-out p95 along the fall line (m)",
                Some(s.runout_m[2]),
            ),
            (
                "spread_width_m",
                "lateral spread, 5–95 % width (m)",
                Some(s.spread_width_m()),
            ),
            ("stopped_pct", "rocks at rest inside the DEM (%)", stopped),
        ] {
            rows.push(Row {
                key: format!("{}:{key}", s.label),
                quantity: format!("{}: {what}", s.label),
                group: String::new(),
                observed: None,
                simulated: v.filter(|v| v.is_finite()),
                error_pct: None,
                rockyfor: None,
                rockyfor_error_pct: None,
                simulated_group_max: None,
                observed_ci95: None,
            });
        }
    }
    let rank = ranking(stats);
    let check = |claim: &str, paper: &str, simulated: &Option<String>| {
        let simulated = simulated.as_deref().unwrap_or("–").to_string();
        Check {
            claim: claim.to_string(),
            holds: paper == simulated,
            paper: paper.to_string(),
            simulated,
        }
    };
    CaseReport {
        name: name.to_string(),
        title: "Forest slope of 40°, run-out and spread per rock shape".to_string(),
        source: "Lu et al. (seed 001) §3.4 and fig. 6: findings, no observed values".to_string(),
        engine: "rigid".to_string(),
        rocks,
        rows,
        rmse_pct: None,
        rmse_pct_fair: None,
        groups: Vec::new(),
        checks: vec![
            check(
                "farthest run-out (p95)",
                rank.paper.farthest_runout,
                &rank.farthest_runout_p95,
            ),
            check(
                "widest lateral spread",
                rank.paper.widest_spread,
                &rank.widest_spread,
            ),
            check(
                "least lateral spread",
                rank.paper.least_spread,
                &rank.least_spread,
            ),
        ],
        notes: vec![
            "the shapes are stand-in ellipsoids of seed 001's aspect ratios, not its scanned \
             rocks"
                .to_string(),
        ],
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn stats(label: &str, p95: f64, width: f64) -> SlopeStats {
        SlopeStats {
            label: label.into(),
            rocks: 10,
            runout_m: [1.0, 2.0, p95, 4.0],
            lateral_end_m: [1.0, -width / 2.0, width / 2.0, width],
            lateral_path_m: [1.0, 2.0, 3.0],
        }
    }

    #[test]
    fn findings_are_checked_against_the_ranking() {
        let st = [
            stats("cubic1.2", 300.0, 100.0),
            stats("flat2.2", 350.0, 120.0),
            stats("long2.2", 200.0, 50.0),
        ];
        let summary = Summary {
            stopped_fraction: Some(0.9),
            ..Summary::default()
        };
        let sums = vec![summary; 3];
        let c = shape_case("forest-slope-40", &st, &sums, 10);
        assert!(c.checks.iter().all(|c| c.holds), "{:?}", c.checks);
        assert_eq!(c.rows.len(), 12);
        assert_eq!(
            c.rows[5].quantity,
            "flat2.2: run-out p95 along the fall line (m)"
        );
        assert_eq!(c.rows[5].simulated, Some(350.0));
        assert_eq!(c.rows[7].simulated, Some(90.0));
        assert_eq!(c.rmse_pct, None);
        let st = [
            stats("cubic1.2", 400.0, 130.0),
            stats("flat2.2", 350.0, 120.0),
            stats("long2.2", 200.0, 125.0),
        ];
        let c = shape_case("forest-slope-40", &st, &sums, 10);
        let holds: Vec<bool> = c.checks.iter().map(|c| c.holds).collect();
        assert_eq!(holds, [false, false, false]);
        assert_eq!(c.checks[0].simulated, "cubic1.2");
        assert_eq!(c.checks[2].simulated, "flat2.2");
    }
}

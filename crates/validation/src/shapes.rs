//! Seed 001 §3.4 as a validation case: the forest-slope runs of rock shapes, where the papers
//! report findings, not numbers.
//!
//! - Seed 001 fig. 6: flat rocks run out farthest and spread widest, long rocks spread least.
//!   Checked twice: on the smooth stand-ins of its three rocks (`cubic1.2`, `flat2.2`,
//!   `long2.2`), and on ensembles of rough rocks of the same classes and Π
//!   (`rough-cubic1.2*N` …), whose intervals carry the variation between shapes of a class.
//! - Caviezel et al. 2021 ("The relevance of rock shape over mass", Nat. Commun. 12): at Chant
//!   Sura the wheel-shaped EOTA₂₂₁ blocks ran out farther than compact EOTA₁₁₁ blocks of the
//!   same mass. Checked on `eota221` against `eota111`, at the study's common rock volume.

use crate::case::{CaseReport, Check, Row};
use rockfall_lab::ensemble::Estimate;
use rockfall_lab::slope::{SlopeStats, ranking};

/// The shapes of seed 001 table 2, in its order.
pub const SHAPES: [&str; 3] = ["cubic1.2", "flat2.2", "long2.2"];

/// The rough-rock classes of seed 001's three rocks (ensembles `CLASS*N`).
pub const ROUGH_CLASSES: [&str; 3] = ["rough-cubic1.2", "rough-flat2.2", "rough-long2.2"];

/// The EOTA test blocks.
pub const EOTA: [&str; 2] = ["eota111", "eota221"];

/// Members of each rough class for `rocks` rocks per shape: ten, or fewer for fewer rocks.
pub fn rough_members(rocks: u64) -> u64 {
    rocks.clamp(1, 10)
}

/// The studies of the case: the stand-ins, the rough classes, the EOTA blocks (each possibly
/// empty).
#[derive(Debug, Clone, Default)]
pub struct ShapeStudies {
    /// Seed 001's stand-ins.
    pub stand_ins: Vec<SlopeStats>,
    /// The rough classes.
    pub rough: Vec<SlopeStats>,
    /// The EOTA blocks.
    pub eota: Vec<SlopeStats>,
}

/// The cubic / flat / long class a label names (`flat2.2`, `rough-flat2.2` → `flat`).
fn class_of(label: &str) -> &str {
    let l = label.strip_prefix("rough-").unwrap_or(label);
    ["cubic", "flat", "long"]
        .into_iter()
        .find(|c| l.starts_with(c))
        .unwrap_or(l)
}

/// ` [lo, hi]` of an interval, or nothing.
fn ci_text(e: Option<Estimate>) -> String {
    e.map_or(String::new(), |e| {
        format!(" [95 % CI {:.1}–{:.1}]", e.ci95[0], e.ci95[1])
    })
}

/// The rows of one shape or class: run-out p50 and p95, spread, share stopped, and the shares
/// of time rolling and sliding on a face.
fn rows_of(s: &SlopeStats) -> Vec<Row> {
    let e = s.estimates;
    let share = |k: usize| e.map(|e| 100.0 * e.motion_share[k].value);
    let stopped = s.outcomes.stopped_fraction.map(|f| 100.0 * f);
    [
        (
            "runout_p50_m",
            "run-out p50 along the fall line (m)".to_string(),
            Some(s.runout_m[1]),
        ),
        (
            "runout_p95_m",
            format!(
                "run-out p95 along the fall line (m){}",
                ci_text(e.map(|e| e.runout_p95_m))
            ),
            Some(s.runout_m[2]),
        ),
        (
            "spread_width_m",
            format!(
                "lateral spread, 5–95 % width (m){}",
                ci_text(e.map(|e| e.spread_width_m))
            ),
            Some(s.spread_width_m()),
        ),
        (
            "stopped_pct",
            "rocks at rest inside the DEM (%)".to_string(),
            stopped,
        ),
        ("rolling_pct", "time rolling (%)".to_string(), share(1)),
        (
            "sliding_face_pct",
            "time sliding on a face (%)".to_string(),
            share(2),
        ),
    ]
    .into_iter()
    .map(|(key, what, v)| Row {
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
    })
    .collect()
}

/// Seed 001's three findings on `stats`, compared by class; `what` names the shapes.
fn fig6_checks(stats: &[SlopeStats], what: &str) -> Vec<Check> {
    if stats.is_empty() {
        return Vec::new();
    }
    let rank = ranking(stats);
    let check = |claim: &str, paper: &str, simulated: &Option<String>, clear: Option<bool>| {
        let label = simulated.as_deref().unwrap_or("–");
        let note = match clear {
            Some(true) => " (clear of the others' 95 % intervals)",
            Some(false) => " (95 % intervals overlap)",
            None => "",
        };
        Check {
            claim: format!("{what}: {claim}"),
            holds: class_of(paper) == class_of(label),
            paper: paper.to_string(),
            simulated: format!("{label}{note}"),
        }
    };
    vec![
        check(
            "farthest run-out (p95)",
            rank.paper.farthest_runout,
            &rank.farthest_runout_p95,
            rank.clear[0],
        ),
        check(
            "widest lateral spread",
            rank.paper.widest_spread,
            &rank.widest_spread,
            rank.clear[1],
        ),
        check(
            "least lateral spread",
            rank.paper.least_spread,
            &rank.least_spread,
            rank.clear[2],
        ),
    ]
}

/// Caviezel et al. 2021's finding on the EOTA blocks: EOTA₂₂₁ runs out farther (mean run-out).
fn eota_check(eota: &[SlopeStats]) -> Option<Check> {
    let get = |l: &str| eota.iter().find(|s| s.label == l);
    let (compact, wheel) = (get("eota111")?, get("eota221")?);
    let mean = |s: &SlopeStats| s.estimates.map(|e| e.runout_mean_m);
    let (c, w) = (mean(compact)?, mean(wheel)?);
    let apart = w.ci95[0] > c.ci95[1] || c.ci95[0] > w.ci95[1];
    Some(Check {
        claim: "EOTA₂₂₁ runs out farther than EOTA₁₁₁ (mean run-out, same mass)".into(),
        paper: "eota221 (Caviezel et al. 2021, Chant Sura)".into(),
        simulated: format!(
            "eota221 {:.0} m [{:.0}–{:.0}], eota111 {:.0} m [{:.0}–{:.0}]{}",
            w.value,
            w.ci95[0],
            w.ci95[1],
            c.value,
            c.ci95[0],
            c.ci95[1],
            if apart { "" } else { " (intervals overlap)" }
        ),
        holds: w.value > c.value && apart,
    })
}

/// The same finding on the p95 run-out along the fall line (issue 29's measure): EOTA₂₂₁'s is
/// at least EOTA₁₁₁'s.
fn eota_p95_check(eota: &[SlopeStats]) -> Option<Check> {
    let get = |l: &str| eota.iter().find(|s| s.label == l);
    let p95 = |s: &SlopeStats| s.estimates.map(|e| e.runout_p95_m);
    let (c, w) = (p95(get("eota111")?)?, p95(get("eota221")?)?);
    Some(Check {
        claim: "EOTA₂₂₁'s p95 run-out is at least EOTA₁₁₁'s (same mass)".into(),
        paper: "eota221 (Caviezel et al. 2021, Chant Sura)".into(),
        simulated: format!(
            "eota221 {:.0} m [{:.0}–{:.0}], eota111 {:.0} m [{:.0}–{:.0}]",
            w.value, w.ci95[0], w.ci95[1], c.value, c.ci95[0], c.ci95[1]
        ),
        holds: w.value >= c.value,
    })
}

/// The case of the shape studies: per shape or class its run-out, spread, outcomes and modes
/// of motion (no observed values), and the papers' findings checked against them.
pub fn shape_case(name: &str, ground: &str, studies: &ShapeStudies, rocks: u64) -> CaseReport {
    let all = (studies.stand_ins.iter())
        .chain(&studies.rough)
        .chain(&studies.eota);
    let rows = all.flat_map(rows_of).collect();
    let mut checks = fig6_checks(&studies.stand_ins, "stand-ins");
    checks.extend(fig6_checks(&studies.rough, "rough ensembles"));
    checks.extend(eota_check(&studies.eota));
    checks.extend(eota_p95_check(&studies.eota));
    CaseReport {
        name: name.to_string(),
        title: "Forest slope of 40°, run-out and spread per rock shape".to_string(),
        source: "Lu et al. (seed 001) §3.4 and fig. 6; Caviezel et al. 2021 (Chant Sura): \
                 findings, no observed values"
            .to_string(),
        engine: "rigid".to_string(),
        rocks,
        rows,
        rmse_pct: None,
        rmse_pct_fair: None,
        groups: Vec::new(),
        checks,
        notes: vec![
            format!("ground: {ground}"),
            "stand-ins: smooth 100-point hulls of seed 001's dimensions, not its scanned rocks"
                .to_string(),
            format!(
                "rough ensembles: {} members per class, each the hull of 60 random points \
                 with ±15 % roughness at the class's Π; intervals are two-stage bootstrap \
                 intervals over members and rocks",
                rough_members(rocks)
            ),
            "EOTA blocks: rebuilt from the Chant Sura shape files, at the study's rock \
             volume (0.02 m³, 54 kg), not Chant Sura's 800 or 2670 kg, on seed 001's forest \
             slope, not Chant Sura's terrain"
                .to_string(),
        ],
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use rockfall_lab::ensemble::ClassEstimates;
    use rockfall_lab::slope::Outcomes;

    fn est(value: f64, half: f64) -> Estimate {
        Estimate {
            value,
            ci95: [value - half, value + half],
        }
    }

    fn stats(label: &str, p95: f64, width: f64, half: f64) -> SlopeStats {
        SlopeStats {
            label: label.into(),
            rocks: 10,
            runout_m: [p95 - 50.0, 2.0, p95, 4.0],
            lateral_end_m: [1.0, -width / 2.0, width / 2.0, width],
            lateral_path_m: [1.0, 2.0, 3.0],
            estimates: Some(ClassEstimates {
                members: 1,
                runout_mean_m: est(p95 - 50.0, half),
                runout_p95_m: est(p95, half),
                lateral_sd_m: est(1.0, 0.1),
                spread_width_m: est(width, half),
                motion_share: [
                    est(0.5, 0.01),
                    est(0.2, 0.01),
                    est(0.1, 0.01),
                    est(0.1, 0.01),
                    est(0.1, 0.01),
                ],
            }),
            outcomes: Outcomes {
                stopped_fraction: Some(0.9),
                ..Outcomes::default()
            },
        }
    }

    #[test]
    fn findings_are_checked_against_the_ranking() {
        let studies = ShapeStudies {
            stand_ins: vec![
                stats("cubic1.2", 300.0, 100.0, 5.0),
                stats("flat2.2", 350.0, 120.0, 5.0),
                stats("long2.2", 200.0, 50.0, 5.0),
            ],
            ..ShapeStudies::default()
        };
        let c = shape_case("forest-slope-40", "test ground", &studies, 10);
        assert_eq!(c.checks.len(), 3);
        assert!(c.checks.iter().all(|c| c.holds), "{:?}", c.checks);
        assert!(c.checks[0].simulated.contains("clear"), "{:?}", c.checks[0]);
        assert_eq!(c.rows.len(), 18);
        assert!(
            c.rows[7]
                .quantity
                .starts_with("flat2.2: run-out p95 along the fall line (m) [95 % CI 345.0–355.0]"),
            "{}",
            c.rows[7].quantity
        );
        assert_eq!(c.rows[7].simulated, Some(350.0));
        assert_eq!(c.rows[9].simulated, Some(90.0));
        assert_eq!(c.rows[10].simulated, Some(20.0));
        assert_eq!(c.rmse_pct, None);
        // by class: the rough flat class answers the paper's flat2.2; overlapping intervals
        // are said
        let studies = ShapeStudies {
            rough: vec![
                stats("rough-cubic1.2", 400.0, 130.0, 80.0),
                stats("rough-flat2.2", 350.0, 120.0, 80.0),
                stats("rough-long2.2", 200.0, 125.0, 80.0),
            ],
            eota: vec![
                stats("eota111", 300.0, 100.0, 5.0),
                stats("eota221", 330.0, 100.0, 5.0),
            ],
            ..ShapeStudies::default()
        };
        let c = shape_case("forest-slope-40", "test ground", &studies, 10);
        let holds: Vec<bool> = c.checks.iter().map(|c| c.holds).collect();
        assert_eq!(holds, [false, false, false, true, true]);
        assert_eq!(
            c.checks[0].simulated,
            "rough-cubic1.2 (95 % intervals overlap)"
        );
        assert!(c.checks[0].claim.starts_with("rough ensembles"));
        // EOTA: farther but within the other's interval does not hold
        let studies = ShapeStudies {
            eota: vec![
                stats("eota111", 300.0, 100.0, 30.0),
                stats("eota221", 330.0, 100.0, 30.0),
            ],
            ..ShapeStudies::default()
        };
        let c = shape_case("forest-slope-40", "test ground", &studies, 10);
        assert_eq!(c.checks.len(), 2);
        assert!(
            !c.checks[0].holds && c.checks[0].simulated.contains("overlap"),
            "{:?}",
            c.checks[0]
        );
        // the p95 finding holds when EOTA₂₂₁'s p95 is at least EOTA₁₁₁'s, whatever the
        // intervals, and not when it is shorter
        assert!(
            c.checks[1].holds && c.checks[1].claim.contains("p95"),
            "{:?}",
            c.checks[1]
        );
        assert!(
            c.checks[1].simulated.starts_with("eota221 330 m"),
            "{:?}",
            c.checks[1]
        );
        let studies = ShapeStudies {
            eota: vec![
                stats("eota111", 300.0, 100.0, 5.0),
                stats("eota221", 299.0, 100.0, 5.0),
            ],
            ..ShapeStudies::default()
        };
        let c = shape_case("forest-slope-40", "test ground", &studies, 10);
        assert!(!c.checks[1].holds, "{:?}", c.checks[1]);
        assert_eq!(c.notes[0], "ground: test ground");
        assert_eq!(class_of("rough-long2.2"), "long");
        assert_eq!(rough_members(3), 3);
        assert_eq!(rough_members(500), 10);
    }
}

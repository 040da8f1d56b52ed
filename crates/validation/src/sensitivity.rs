//! The sensitivity table of `rockfall validate`: each Vaujany site's table 2 case run again
//! with one unknown of the reconstruction (`vaujany::Unknowns`) or one rule of ours (the
//! settings `roughness_tilt_factor` and `lift_off_obstacle_factor`, docs/lumped-model.md) or
//! Pfeiffer & Bowen's velocity scale of r_n (`rn_velocity_scale_ms`)
//! at each end of its plausible range, so that a reader sees which rows the reconstruction
//! decides and which the model does.

use crate::{CaseReport, SensitivityRow, ValidationError, fair, measure, published};
use rockfall_scenario::Scenario;
use rockfall_sim::{Observer, Overrides, Simulation};
use rockfall_sites::vaujany::{self, Site, Unknowns};

/// How one run differs from the default reconstruction.
struct Variant {
    unknown: String,
    setting: String,
    unknowns: Unknowns,
    tilt: Option<f64>,
    lift: Option<f64>,
    rn_scale: Option<f64>,
}

/// The variants of a site: the default, each unknown at both ends, each rule of ours (and
/// Pfeiffer & Bowen's velocity scale of r_n) off and doubled (or halved).
fn variants(site: Site) -> Vec<Variant> {
    let d = Unknowns::default();
    let plain = |unknown: &str, setting: String, unknowns: Unknowns| Variant {
        unknown: unknown.to_string(),
        setting,
        unknowns,
        tilt: None,
        lift: None,
        rn_scale: None,
    };
    let mut v = vec![plain("default", "–".into(), d)];
    for (name, lo, hi) in Unknowns::ranges(site) {
        v.push(plain(name, "low".into(), lo));
        v.push(plain(name, "high".into(), hi));
    }
    for (rule, values) in [
        ("roughness tilt factor (ours: 1)", [0.0, 0.5]),
        ("lift-off obstacle factor (ours: 1)", [0.0, 2.0]),
        (
            "r_n velocity scale K (P&B: 9.144 m/s; 0: off)",
            [0.0, 18.288],
        ),
    ] {
        for x in values {
            v.push(Variant {
                tilt: rule.starts_with("roughness").then_some(x),
                lift: rule.starts_with("lift").then_some(x),
                rn_scale: rule.starts_with("r_n velocity").then_some(x),
                ..plain(rule, format!("{x}"), d)
            });
        }
    }
    v
}

/// Runs every variant of the sites among `names` with `rocks` rocks each, telling
/// `observer` about each run.
pub fn sensitivity(
    names: &[&str],
    rocks: u64,
    seed: u64,
    threads: usize,
    observer: &dyn Observer,
) -> Result<Vec<SensitivityRow>, ValidationError> {
    let mut rows = Vec::new();
    for &name in names {
        let site = match name {
            "vaujany-site1" => Site::One,
            "vaujany-site2" => Site::Two,
            _ => continue,
        };
        let Some(table2) = published()
            .into_iter()
            .find(|p| p.site == name && p.screen.is_none())
        else {
            continue;
        };
        for v in variants(site) {
            let mut s: Scenario = vaujany::build_observed_with(site, &v.unknowns)?;
            s.output.rocks_csv = true;
            s.output.trajectories = 0;
            if let Some(t) = v.tilt {
                s.lumped.roughness_tilt_factor = t;
            }
            if let Some(l) = v.lift {
                s.lumped.lift_off_obstacle_factor = l;
            }
            if let Some(k) = v.rn_scale {
                s.lumped.rn_velocity_scale_ms = k;
            }
            let overrides = Overrides {
                seed: Some(seed),
                rocks_per_cell: Some(rocks),
                threads: Some(threads),
                ..Overrides::default()
            };
            let label = format!("{name} sensitivity: {} {}", v.unknown, v.setting);
            let results = Simulation::new(s, &overrides)?.run(true, &label, observer)?;
            let simulated = measure::slope_quantities(&results.summary(), results.rock_records());
            let mut case = CaseReport::compare(&table2, "lumped", results.rocks(), &simulated);
            if let Some(n) = table2.observed_rocks {
                case.add_fair(&fair::group_maxima(&results, None, n), n);
            }
            rows.push(SensitivityRow {
                case: table2.name.to_string(),
                unknown: v.unknown,
                setting: v.setting,
                rmse_pct: case.rmse_pct,
                rmse_pct_fair: case.rmse_pct_fair,
            });
        }
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rockfall_results::Results;
    use std::sync::Mutex;

    /// The runs an observer was told of: (label, rocks) when each started, (label, seed,
    /// rocks) of each finished run's summary.
    #[derive(Default)]
    struct Runs {
        started: Mutex<Vec<(String, u64)>>,
        finished: Mutex<Vec<(String, u64, u64)>>,
    }

    impl Observer for Runs {
        fn started(&self, label: &str, rocks: u64) {
            self.started.lock().unwrap().push((label.into(), rocks));
        }

        fn finished(&self, label: &str, results: &Results) {
            let s = results.summary();
            let run = (label.into(), s.seed, s.rocks);
            self.finished.lock().unwrap().push(run);
        }
    }

    /// Every variant runs with the seed and the rocks it is asked for — not the site's own
    /// seed (1) and 10 000 rocks — so that the table compares variants of one run, the one
    /// `validate --seed` names; each run announces its rocks before it starts.
    #[test]
    fn every_variant_runs_with_the_requested_seed_and_rocks() {
        let runs = Runs::default();
        let rows = sensitivity(&["vaujany-site2"], 200, 11, 2, &runs).unwrap();
        let n = variants(Site::Two).len();
        assert_eq!(rows.len(), n);
        let started = runs.started.into_inner().unwrap();
        let finished = runs.finished.into_inner().unwrap();
        assert_eq!((started.len(), finished.len()), (n, n));
        for (label, rocks) in &started {
            assert_eq!(*rocks, 200, "{label}");
        }
        for (label, seed, rocks) in &finished {
            assert_eq!((*seed, *rocks), (11, 200), "{label}");
        }
    }

    #[test]
    fn each_variant_moves_one_thing() {
        let v = variants(Site::One);
        let d = Unknowns::default();
        assert_eq!(v[0].unknown, "default");
        assert!(v[0].unknowns == d && v[0].tilt.is_none() && v[0].lift.is_none());
        // every unknown at both ends, then three rules at two values each
        assert_eq!(v.len(), 1 + 2 * Unknowns::ranges(Site::One).len() + 6);
        for pair in v[1..].chunks(2) {
            assert_eq!(pair[0].unknown, pair[1].unknown);
            assert_ne!(pair[0].setting, pair[1].setting);
        }
        let rule = |name: &'static str| v.iter().filter(move |x| x.unknown.starts_with(name));
        for x in rule("roughness") {
            assert!(x.unknowns == d && x.lift.is_none() && x.rn_scale.is_none());
            assert!(matches!(x.tilt, Some(t) if t == 0.0 || t == 0.5));
        }
        for x in rule("lift-off") {
            assert!(x.unknowns == d && x.tilt.is_none() && x.rn_scale.is_none());
            assert!(matches!(x.lift, Some(l) if l == 0.0 || l == 2.0));
        }
        for x in rule("r_n velocity") {
            assert!(x.unknowns == d && x.tilt.is_none() && x.lift.is_none());
            assert!(matches!(x.rn_scale, Some(k) if k == 0.0 || k == 18.288));
        }
        let rules = ["roughness", "lift-off", "r_n velocity"];
        assert_eq!(rules.iter().map(|r| rule(r).count()).sum::<usize>(), 6);
    }
}

//! The sensitivity table of `rockfall validate`: each Vaujany site's table 2 case run again
//! with one unknown of the reconstruction (`vaujany::Unknowns`) or one rule of ours (the
//! settings `roughness_tilt_factor` and `lift_off_obstacle_factor`, docs/lumped-model.md),
//! Pfeiffer & Bowen's velocity scale of r_n (`rn_velocity_scale_ms`) or the scale of STONE's
//! rolling friction of the soil (`soil_friction_scale`)
//! at each end of its plausible range, so that a reader sees which rows the reconstruction
//! decides and which the model does.

use crate::{CaseReport, SensitivityRow, ValidationError, fair, measure, published};
use rockfall_scenario::{LumpedSettings, Scenario};
use rockfall_sim::{Observer, Overrides, Simulation};
use rockfall_sites::vaujany::{self, Site, Unknowns};

/// Sets one engine setting of the lumped engine to a value.
type SetRule = fn(&mut LumpedSettings, f64);

/// How one run differs from the default reconstruction.
struct Variant {
    unknown: String,
    setting: String,
    unknowns: Unknowns,
    rule: Option<(SetRule, f64)>,
}

/// The variants of a site: the default, each unknown at both ends, each rule of ours (and
/// Pfeiffer & Bowen's velocity scale of r_n) off and doubled (or halved).
fn variants(site: Site) -> Vec<Variant> {
    let d = Unknowns::default();
    let plain = |unknown: &str, setting: String, unknowns: Unknowns| Variant {
        unknown: unknown.to_string(),
        setting,
        unknowns,
        rule: None,
    };
    let mut v = vec![plain("default", "–".into(), d)];
    for (name, lo, hi) in Unknowns::ranges(site) {
        v.push(plain(name, "low".into(), lo));
        v.push(plain(name, "high".into(), hi));
    }
    let rules: [(&str, [f64; 2], SetRule); 4] = [
        ("roughness tilt factor (ours: 1)", [0.0, 0.5], |l, x| {
            l.roughness_tilt_factor = x;
        }),
        ("lift-off obstacle factor (ours: 1)", [0.0, 2.0], |l, x| {
            l.lift_off_obstacle_factor = x;
        }),
        (
            "r_n velocity scale K (P&B: 9.144 m/s; 0: off)",
            [0.0, 18.288],
            |l, x| l.rn_velocity_scale_ms = x,
        ),
        (
            "soil rolling friction × (STONE: 1; 0: MOH/R)",
            [0.0, 0.5],
            |l, x| l.soil_friction_scale = x,
        ),
    ];
    for (rule, values, set) in rules {
        for x in values {
            v.push(Variant {
                rule: Some((set, x)),
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
            if let Some((set, x)) = v.rule {
                set(&mut s.lumped, x);
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
        assert!(v[0].unknowns == d && v[0].rule.is_none());
        // every unknown at both ends, then four rules at two values each
        assert_eq!(v.len(), 1 + 2 * Unknowns::ranges(Site::One).len() + 8);
        for pair in v[1..].chunks(2) {
            assert_eq!(pair[0].unknown, pair[1].unknown);
            assert_ne!(pair[0].setting, pair[1].setting);
        }
        // each rule sets its own setting to its value and nothing else
        let rule = |name: &'static str| v.iter().filter(move |x| x.unknown.starts_with(name));
        type Read = fn(&LumpedSettings) -> f64;
        let get: [(&str, Read); 4] = [
            ("roughness", |l| l.roughness_tilt_factor),
            ("lift-off", |l| l.lift_off_obstacle_factor),
            ("r_n velocity", |l| l.rn_velocity_scale_ms),
            ("soil rolling", |l| l.soil_friction_scale),
        ];
        for (name, read) in get {
            assert_eq!(rule(name).count(), 2, "{name}");
            for x in rule(name) {
                assert!(x.unknowns == d);
                let (set, value) = x.rule.unwrap();
                let mut l = LumpedSettings::default();
                set(&mut l, value);
                assert_eq!(read(&l), value, "{name}");
                assert_ne!(read(&LumpedSettings::default()), value, "{name}");
                for (other, read_other) in get {
                    if other != name {
                        assert_eq!(read_other(&l), read_other(&LumpedSettings::default()));
                    }
                }
            }
        }
    }
}

//! Targets: numbers of `summary.json` compared with what was observed.
//!
//! Each target gives a standardised residual `z = (simulated − observed) / σ`:
//! - with `sd`: σ = sd, the simulated value as `summary.json` has it;
//! - with `n` for a **share** (a path ending in `_fraction`): σ is the half-width of the
//!   observed share's 95 % Wilson interval over 1.96 (Wilson 1927), which stays positive for
//!   an observed 0 or 1;
//! - with `n` for a **maximum** (`max_velocity_ms.max`, `max_jump_height_m.max`,
//!   `runout_m.max`, `screens.<name>.{velocity_ms, energy_kj, jump_height_m}.max`): the
//!   largest of n rocks is compared, not the largest of the run's. The simulated value is the
//!   median of the maximum over groups of n rocks (order statistics,
//!   `rockfall_results::fair`; at a screen, n times the simulated share crossing it) and σ
//!   the spread of that group maximum, (p95 − p5) / 3.29, at least 5 % of the observed value
//!   (ours, [`MAX_SIGMA_FLOOR`]).
//!
//! **The objective is ours**: the mean of z² over the targets (a weighted least-squares
//! misfit, −2 log-likelihood per target for independent normal errors up to a constant). A
//! candidate **fits** when every |z| ≤ 2.

use rockfall_results::fair::{GroupMax, group_max, wilson_ci95};
use rockfall_results::{Quantity, Results};
use serde_json::Value;

use crate::spec::{Target, Uncertainty};

/// Smallest σ of a maximum compared over n rocks, as a share of the observed value: where
/// the simulated rocks all end alike (held at release, one path) the group maximum has no
/// spread, and a σ of zero would make any difference infinitely bad. Ours.
pub const MAX_SIGMA_FLOOR: f64 = 0.05;

/// The residual z a target takes when the run gives no value for it (`null` in
/// `summary.json`, e.g. a screen no rock crossed): ours, a clear misfit.
pub const MISSING_Z: f64 = 10.0;

/// One target's comparison in one run.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Residual {
    /// The target's path (or `deposits.along` / `deposits.across`).
    pub path: String,
    /// Observed value.
    pub observed: f64,
    /// Simulated value compared (`None`: the run gives none).
    pub simulated: Option<f64>,
    /// σ of the comparison.
    pub sigma: f64,
    /// (simulated − observed) / σ.
    pub z: f64,
}

/// The value at `path` of a `summary.json` object: keys joined by dots; `screens.<name>`
/// selects the screen of that name.
pub fn lookup<'a>(summary: &'a Value, path: &str) -> Option<&'a Value> {
    let mut v = summary;
    let mut parts = path.split('.');
    while let Some(part) = parts.next() {
        v = match v {
            Value::Object(m) => m.get(part)?,
            Value::Array(a) => {
                let named = a
                    .iter()
                    .find(|x| x.get("name").and_then(Value::as_str) == Some(part));
                match named {
                    Some(x) => x,
                    None => a.get(part.parse::<usize>().ok()?)?,
                }
            }
            _ => return None,
        };
        if parts.clone().next().is_none() {
            return Some(v);
        }
    }
    Some(v)
}

/// Every numeric leaf path of a `summary.json` (screens by name), for messages.
pub fn numeric_paths(summary: &Value) -> Vec<String> {
    fn walk(v: &Value, prefix: &str, out: &mut Vec<String>) {
        let join = |k: &str| {
            if prefix.is_empty() {
                k.to_string()
            } else {
                format!("{prefix}.{k}")
            }
        };
        match v {
            Value::Object(m) => {
                for (k, x) in m {
                    if k == "parameters" || k == "convergence" {
                        continue;
                    }
                    walk(x, &join(k), out);
                }
            }
            Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    let key = (x.get("name").and_then(Value::as_str))
                        .map_or(i.to_string(), str::to_string);
                    walk(x, &join(&key), out);
                }
            }
            Value::Number(_) | Value::Null => out.push(prefix.to_string()),
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(summary, "", &mut out);
    out
}

/// The distribution behind a maximum's path, with the group size for `n` observed rocks.
fn maximum_of(results: &Results, summary: &Value, path: &str, n: u32) -> Option<(Quantity, f64)> {
    let n = f64::from(n);
    let rocks = results.rocks().max(1) as f64;
    let q = match path {
        "max_velocity_ms.max" => Quantity::MaxVelocity,
        "max_jump_height_m.max" => Quantity::MaxJumpHeight,
        "runout_m.max" => Quantity::Runout,
        _ => {
            let rest = path.strip_prefix("screens.")?.strip_suffix(".max")?;
            let (name, what) = rest.rsplit_once('.')?;
            let screens = summary.get("screens")?.as_array()?;
            let i = screens
                .iter()
                .position(|s| s.get("name").and_then(Value::as_str) == Some(name))?;
            let q = match what {
                "velocity_ms" => Quantity::ScreenVelocity(i),
                "energy_kj" => Quantity::ScreenEnergy(i),
                "jump_height_m" => Quantity::ScreenJumpHeight(i),
                _ => return None,
            };
            let d = results.distribution(q)?;
            return Some((q, n * d.count as f64 / rocks));
        }
    };
    Some((q, n))
}

/// Whether `path` names a share (compared through its Wilson interval when given `n`).
pub fn is_share(path: &str) -> bool {
    path.ends_with("_fraction")
}

/// Whether `path` names a maximum that `n` can compare fairly.
pub fn is_fair_maximum(path: &str) -> bool {
    matches!(
        path,
        "max_velocity_ms.max" | "max_jump_height_m.max" | "runout_m.max"
    ) || (path.starts_with("screens.")
        && ["velocity_ms.max", "energy_kj.max", "jump_height_m.max"]
            .iter()
            .any(|s| path.ends_with(s)))
}

/// Checks a target against a `summary.json` of the scenario: its path must name a number
/// there (or a `null` one), and `n` must name a share or a fair maximum. `Err` carries the
/// message, with the near matches of an unknown path.
pub fn check(target: &Target, summary: &Value) -> Result<(), String> {
    let path = &target.path;
    match lookup(summary, path) {
        Some(Value::Number(_) | Value::Null) => {}
        Some(_) => return Err(format!("`{path}` in summary.json is not a number")),
        None => {
            let paths = numeric_paths(summary);
            let near = crate::keys::near(path, &paths);
            let hint = if near.is_empty() {
                String::new()
            } else {
                format!("; near matches: {}", near.join(", "))
            };
            return Err(format!("`{path}` is not a number of summary.json{hint}"));
        }
    }
    if let Uncertainty::N(_) = target.uncertainty
        && !is_share(path)
        && !is_fair_maximum(path)
    {
        return Err(format!(
            "`{path}`: `n` compares shares (`*_fraction`) and the maxima of rocks or screen \
             crossings (`*.max`); give `sd` for this number"
        ));
    }
    if is_share(path) && !(0.0..=1.0).contains(&target.value) {
        return Err(format!(
            "`{path}` is a share (0–1); the observed value {} is not",
            target.value
        ));
    }
    Ok(())
}

/// The residual of `target` in a run (`results`, its `summary.json` as `summary`).
pub fn residual(target: &Target, results: &Results, summary: &Value) -> Residual {
    let path = target.path.clone();
    let observed = target.value;
    let plain = lookup(summary, &path).and_then(Value::as_f64);
    let (simulated, sigma) = match target.uncertainty {
        Uncertainty::Sd(sd) => (plain, sd),
        Uncertainty::N(n) if is_share(&path) => (plain, share_sigma(observed, n)),
        Uncertainty::N(n) => {
            let g = maximum_of(results, summary, &path, n)
                .and_then(|(q, m)| group_max(&results.distribution(q)?, m.max(1.0)));
            match g {
                Some(g) => {
                    let (s, sigma) = maximum_comparison(&g, observed);
                    (Some(s), sigma)
                }
                None => (None, 1.0),
            }
        }
    };
    let z = simulated.map_or(MISSING_Z, |s| (s - observed) / sigma);
    Residual {
        path,
        observed,
        simulated,
        sigma,
        z,
    }
}

/// σ of a share `p` (0–1) observed on `n` rocks: the half-width of its 95 % Wilson
/// interval over 1.96.
pub fn share_sigma(p: f64, n: u32) -> f64 {
    let [lo, hi] = wilson_ci95(100.0 * p, n);
    ((hi - lo) / 100.0 / (2.0 * 1.959_964)).max(1e-9)
}

/// The simulated value and σ of a maximum compared over groups of n rocks: the median of the
/// group maximum, and its spread (p95 − p5)/3.29, at least [`MAX_SIGMA_FLOOR`] of the
/// observed value.
pub fn maximum_comparison(g: &GroupMax, observed: f64) -> (f64, f64) {
    let sigma = ((g.p95 - g.p5) / 3.29)
        .max(MAX_SIGMA_FLOOR * observed.abs())
        .max(1e-9);
    (g.p50, sigma)
}

/// The objective of a set of residuals: the mean of z² (ours; see the module docs).
pub fn objective(residuals: &[Residual]) -> f64 {
    if residuals.is_empty() {
        return 0.0;
    }
    residuals.iter().map(|r| r.z * r.z).sum::<f64>() / residuals.len() as f64
}

/// Whether every residual lies within the targets' uncertainty (|z| ≤ 2).
pub fn fits(residuals: &[Residual]) -> bool {
    residuals.iter().all(|r| r.z.abs() <= 2.0)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use serde_json::json;

    fn summary() -> Value {
        json!({
            "runout_m": {"p50": 10.0, "max": null},
            "stopped_fraction": 0.5,
            "screens": [{"name": "road", "passed_fraction": 0.25, "velocity_ms": {"max": 9.0}}],
            "parameters": {"seed": 3}
        })
    }

    #[test]
    fn paths_reach_numbers_and_screens_by_name() {
        let s = summary();
        assert_eq!(lookup(&s, "runout_m.p50"), Some(&json!(10.0)));
        assert_eq!(
            lookup(&s, "screens.road.passed_fraction"),
            Some(&json!(0.25))
        );
        assert_eq!(lookup(&s, "screens.0.passed_fraction"), Some(&json!(0.25)));
        assert_eq!(lookup(&s, "screens.gate.passed_fraction"), None);
        assert_eq!(lookup(&s, "runout_m.p51"), None);
        let paths = numeric_paths(&s);
        assert!(
            paths.contains(&"screens.road.velocity_ms.max".to_string()),
            "{paths:?}"
        );
        assert!(paths.contains(&"runout_m.max".to_string()));
        assert!(!paths.iter().any(|p| p.starts_with("parameters")));
    }

    #[test]
    fn checks_name_the_path_and_its_near_matches() {
        let s = summary();
        let t = |path: &str, u| Target {
            path: path.into(),
            value: 0.3,
            uncertainty: u,
        };
        let e = check(&t("runout_m.p05", Uncertainty::Sd(1.0)), &s).unwrap_err();
        assert!(
            e.contains("runout_m.p05") && e.contains("runout_m.p50"),
            "{e}"
        );
        let e = check(&t("runout_m.p50", Uncertainty::N(10)), &s).unwrap_err();
        assert!(e.contains("give `sd`"), "{e}");
        check(&t("screens.road.passed_fraction", Uncertainty::N(10)), &s).unwrap();
        check(&t("runout_m.max", Uncertainty::Sd(1.0)), &s).unwrap();
        let e = check(
            &Target {
                value: 2.0,
                ..t("stopped_fraction", Uncertainty::Sd(0.1))
            },
            &s,
        )
        .unwrap_err();
        assert!(e.contains("share"), "{e}");
    }

    #[test]
    fn objective_is_the_mean_square_residual() {
        let r = |z: f64| Residual {
            path: "x".into(),
            observed: 0.0,
            simulated: Some(z),
            sigma: 1.0,
            z,
        };
        assert_eq!(objective(&[r(1.0), r(3.0)]), 5.0);
        assert!(fits(&[r(1.9), r(-2.0)]) && !fits(&[r(2.1)]) && !fits(&[r(-2.1)]));
    }

    #[test]
    fn share_and_maximum_sigmas_by_hand() {
        // 21 of 102: Wilson 95 % interval 14.2–29.9 %, half-width 7.85 pp
        let s = share_sigma(0.21, 102);
        assert!((s - 0.0785 / 1.96).abs() < 3e-4, "{s}");
        // a maximum: the median of the group maximum, σ its 5–95 % spread / 3.29 …
        let g = GroupMax {
            group: 100.0,
            p5: 20.0,
            p50: 24.0,
            p95: 29.87,
        };
        let (sim, sigma) = maximum_comparison(&g, 22.0);
        assert_eq!(sim, 24.0);
        assert!((sigma - 3.0).abs() < 1e-9, "{sigma}");
        // … at least 5 % of the observed value where the runs all end alike
        let flat = GroupMax {
            p5: 24.0,
            p95: 24.0,
            ..g
        };
        assert!((maximum_comparison(&flat, 30.0).1 - 1.5).abs() < 1e-12);
    }
}

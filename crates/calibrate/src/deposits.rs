//! Observed deposits: mapped blocks compared with where the simulated rocks came to rest.
//!
//! The points are projected on the fall line of the release — the unit vector from the mean
//! release position to the mean observed deposit, in plan — and across it. Along and across
//! are each compared as distributions by the two-sample Kolmogorov–Smirnov statistic D
//! between the observed points and the simulated rocks at rest (stopped inside the DEM or
//! by a net). Each gives a residual `z = 1.96 · D / D₀.₀₅` with `D₀.₀₅ = 1.358 ·
//! √((n + m)/(n m))`, the statistic's 5 % critical value for n observed and m simulated
//! points (Smirnov 1948): z ≤ 1.96 exactly when the test does not reject the two samples as
//! one distribution. Turning D into a residual that way is ours. A run in which no rock
//! came to rest gets [`crate::targets::MISSING_Z`].

use std::path::Path;

use rockfall_io::vector::Geometry;
use rockfall_io::vector::inputs::{Frame, open};
use rockfall_results::{Outcome, Results};
use rockfall_scenario::Scenario;

use crate::CalibrationError;
use crate::targets::{MISSING_Z, Residual};

/// Observed deposits, projected on the release's fall line.
#[derive(Debug, Clone, PartialEq)]
pub struct Deposits {
    /// Mean release position (x, y), m.
    origin: [f64; 2],
    /// Unit vector along the fall line, in plan.
    along: [f64; 2],
    /// Observed positions along the fall line, sorted, m.
    obs_along: Vec<f64>,
    /// Observed positions across it (to the left positive), sorted, m.
    obs_across: Vec<f64>,
}

impl Deposits {
    /// Reads the point layer `path` and checks it against `scenario`'s DEM: the same CRS
    /// (where both are known) and every point inside the DEM's extent.
    pub fn read(path: &Path, scenario: &Scenario) -> Result<Deposits, CalibrationError> {
        let dem = &scenario.terrain.dem;
        let frame = Frame {
            geometry: *dem.geometry(),
            crs: dem.crs().cloned(),
            window: None,
        };
        let mut notes = Vec::new();
        let layer = open(path, None, &frame, &mut notes)?;
        let mut points = Vec::new();
        for f in &layer.features {
            let bad = |what: String| CalibrationError::Deposits {
                path: path.to_path_buf(),
                what: format!("feature {}: {what}", f.id),
            };
            match &f.geometry {
                Geometry::Points(p) => {
                    for &[x, y] in p {
                        if !frame.geometry.contains(x, y) {
                            return Err(bad(format!(
                                "the point ({x}, {y}) lies outside the DEM (x {} – {} m, y {} – {} m)",
                                frame.geometry.x_min_m,
                                frame.geometry.x_max_m(),
                                frame.geometry.y_min_m,
                                frame.geometry.y_max_m()
                            )));
                        }
                        points.push([x, y]);
                    }
                }
                Geometry::Empty => {}
                _ => return Err(bad("a deposit layer holds points only".into())),
            }
        }
        let releases = rockfall_engine::Releases::of(scenario);
        let starts: Vec<[f64; 2]> = releases.list().iter().map(|r| r.xy_m).collect();
        let bad = |what: &str| CalibrationError::Deposits {
            path: path.to_path_buf(),
            what: what.into(),
        };
        if points.len() < 2 {
            return Err(bad(
                "fewer than two deposit points: no distribution to compare",
            ));
        }
        let origin = mean(&starts).ok_or_else(|| bad("the scenario releases no rock"))?;
        let centre = mean(&points).unwrap_or(origin);
        let (dx, dy) = (centre[0] - origin[0], centre[1] - origin[1]);
        let len = dx.hypot(dy);
        if len < frame.geometry.cell_size_m {
            return Err(bad(
                "the deposits lie around the release itself: no fall line to compare along",
            ));
        }
        let along = [dx / len, dy / len];
        let d = Deposits {
            origin,
            along,
            obs_along: Vec::new(),
            obs_across: Vec::new(),
        };
        let (obs_along, obs_across) = d.project(&points);
        Ok(Deposits {
            obs_along,
            obs_across,
            ..d
        })
    }

    /// Positions along and across the fall line, each sorted.
    fn project(&self, points: &[[f64; 2]]) -> (Vec<f64>, Vec<f64>) {
        let [ux, uy] = self.along;
        let (mut a, mut c): (Vec<f64>, Vec<f64>) = points
            .iter()
            .map(|p| {
                let (dx, dy) = (p[0] - self.origin[0], p[1] - self.origin[1]);
                (dx * ux + dy * uy, -dx * uy + dy * ux)
            })
            .unzip();
        a.sort_by(f64::total_cmp);
        c.sort_by(f64::total_cmp);
        (a, c)
    }

    /// The two residuals of a run (`deposits.along`, `deposits.across`); the run must keep
    /// its rock records.
    pub fn residuals(&self, results: &Results) -> Vec<Residual> {
        let stops: Vec<[f64; 2]> = (results.rock_records().iter())
            .filter(|r| {
                matches!(
                    r.end.outcome,
                    Outcome::Stopped { .. } | Outcome::NetStopped { .. }
                )
            })
            .map(|r| [r.end.x_m, r.end.y_m])
            .collect();
        let (sim_along, sim_across) = self.project(&stops);
        [
            ("deposits.along", &self.obs_along, &sim_along),
            ("deposits.across", &self.obs_across, &sim_across),
        ]
        .into_iter()
        .map(|(path, obs, sim)| ks_residual(path, obs, sim))
        .collect()
    }
}

/// The residual of two sorted samples: 1.96 D over the 5 % critical value of the two-sample
/// KS test (see the module docs); an empty simulated sample is [`MISSING_Z`].
pub fn ks_residual(path: &str, obs: &[f64], sim: &[f64]) -> Residual {
    let (n, m) = (obs.len() as f64, sim.len() as f64);
    let critical = if m > 0.0 && n > 0.0 {
        1.358 * ((n + m) / (n * m)).sqrt()
    } else {
        1.0
    };
    let sigma = critical / 1.96;
    let d = (!sim.is_empty()).then(|| ks_statistic(obs, sim));
    Residual {
        path: path.to_string(),
        observed: 0.0,
        simulated: d,
        sigma,
        z: d.map_or(MISSING_Z, |d| d / sigma),
    }
}

fn mean(p: &[[f64; 2]]) -> Option<[f64; 2]> {
    let n = p.len() as f64;
    (!p.is_empty()).then(|| {
        let (x, y) = p.iter().fold((0.0, 0.0), |(x, y), q| (x + q[0], y + q[1]));
        [x / n, y / n]
    })
}

/// The two-sample Kolmogorov–Smirnov statistic of two sorted samples: the largest distance
/// between their empirical distribution functions.
pub fn ks_statistic(a: &[f64], b: &[f64]) -> f64 {
    let (n, m) = (a.len() as f64, b.len() as f64);
    let (mut i, mut j, mut d) = (0usize, 0usize, 0.0f64);
    while i < a.len() && j < b.len() {
        let x = a[i].min(b[j]);
        while i < a.len() && a[i] <= x {
            i += 1;
        }
        while j < b.len() && b[j] <= x {
            j += 1;
        }
        d = d.max((i as f64 / n - j as f64 / m).abs());
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ks_statistic_by_hand() {
        assert_eq!(ks_statistic(&[1.0, 2.0, 3.0], &[1.0, 2.0, 3.0]), 0.0);
        assert_eq!(ks_statistic(&[1.0, 2.0], &[3.0, 4.0]), 1.0);
        // F_a jumps at 1 and 3, F_b at 2 and 4: the largest gap is 1/2
        assert_eq!(ks_statistic(&[1.0, 3.0], &[2.0, 4.0]), 0.5);
        let d = ks_statistic(&[0.0, 1.0, 2.0, 3.0], &[1.5]);
        assert!((d - 0.5).abs() < 1e-12, "{d}");
    }

    #[test]
    fn ks_residual_is_d_over_its_critical_value() {
        // n = 4, m = 2, D = 0.5: D₀.₀₅ = 1.358 √(6/8)
        let r = ks_residual("deposits.along", &[0.0, 1.0, 2.0, 3.0], &[1.5, 2.5]);
        assert_eq!(r.simulated, Some(0.5));
        let z = 1.96 * 0.5 / (1.358 * (6.0f64 / 8.0).sqrt());
        assert!((r.z - z).abs() < 1e-12, "{} vs {z}", r.z);
        assert_eq!(ks_residual("x", &[1.0, 2.0], &[]).z, MISSING_Z);
    }

    #[test]
    fn projection_on_the_fall_line() {
        let d = Deposits {
            origin: [0.0, 100.0],
            along: [0.0, -1.0],
            obs_along: vec![],
            obs_across: vec![],
        };
        // 30 m down the fall line (south), 5 m to its east: to the left of a rock going
        // south is east
        let (a, c) = d.project(&[[5.0, 70.0]]);
        assert!(
            (a[0] - 30.0).abs() < 1e-12 && (c[0] - 5.0).abs() < 1e-12,
            "{a:?} {c:?}"
        );
    }
}

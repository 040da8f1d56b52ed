//! The checks of a scenario's engine settings, contact laws, simulation and outputs (the
//! terrain, rock, release, forest, nets and screens are checked in `validate.rs`).

use crate::validate::{Check, out_of_range};
use crate::{Scenario, ScenarioError};

impl Scenario {
    pub(crate) fn check_rigid(&self) -> Check {
        let r = &self.rigid;
        let nonneg = |x: f64| x >= 0.0 && x.is_finite();
        let checks: [(&str, f64, bool, &str); 8] = [
            (
                "rigid.solver_alpha",
                r.solver_alpha,
                r.solver_alpha > 0.0 && r.solver_alpha < 2.0,
                "0 < α < 2",
            ),
            (
                "rigid.solver_tolerance_ms",
                r.solver_tolerance_ms,
                r.solver_tolerance_ms > 0.0 && r.solver_tolerance_ms.is_finite(),
                "> 0 m/s",
            ),
            (
                "rigid.solver_max_iterations",
                f64::from(r.solver_max_iterations),
                r.solver_max_iterations >= 1,
                "≥ 1",
            ),
            (
                "rigid.stop_speed_ms",
                r.stop_speed_ms,
                nonneg(r.stop_speed_ms),
                "≥ 0 m/s",
            ),
            (
                "rigid.rest_time_s",
                r.rest_time_s,
                nonneg(r.rest_time_s),
                "≥ 0 s",
            ),
            (
                "rigid.max_speed_ms",
                r.max_speed_ms,
                r.max_speed_ms > 0.0 && !r.max_speed_ms.is_nan(),
                "> 0 m/s",
            ),
            (
                "rigid.linear_damping_per_s",
                r.linear_damping_per_s,
                nonneg(r.linear_damping_per_s),
                "≥ 0 1/s",
            ),
            (
                "rigid.angular_damping_per_s",
                r.angular_damping_per_s,
                nonneg(r.angular_damping_per_s),
                "≥ 0 1/s",
            ),
        ];
        for (name, value, ok, expected) in checks {
            if !ok {
                return Err(out_of_range(name, None, value, expected));
            }
        }
        Ok(())
    }

    pub(crate) fn check_settings(&self) -> Check {
        let l = &self.lumped;
        let s = &self.simulation;
        let checks: [(&str, f64, bool, &str); 13] = [
            (
                "lumped.rt_variation",
                l.rt_variation,
                (0.0..1.0).contains(&l.rt_variation),
                "0 ≤ x < 1",
            ),
            (
                "lumped.slope_reduction_max_deg",
                l.slope_reduction_max_deg,
                (0.0..90.0).contains(&l.slope_reduction_max_deg),
                "0 ≤ x < 90°",
            ),
            (
                "lumped.max_lateral_deviation_deg",
                l.max_lateral_deviation_deg,
                (0.0..=180.0).contains(&l.max_lateral_deviation_deg),
                "0–180°",
            ),
            (
                "lumped.stop_velocity_ms",
                l.stop_velocity_ms,
                l.stop_velocity_ms > 0.0 && l.stop_velocity_ms.is_finite(),
                "> 0 m/s",
            ),
            (
                "lumped.rn_velocity_scale_ms",
                l.rn_velocity_scale_ms,
                l.rn_velocity_scale_ms >= 0.0 && l.rn_velocity_scale_ms.is_finite(),
                "≥ 0 m/s (0: r_n constant)",
            ),
            (
                "lumped.roughness_tilt_factor",
                l.roughness_tilt_factor,
                (0.0..=10.0).contains(&l.roughness_tilt_factor),
                "0–10",
            ),
            (
                "lumped.lift_off_obstacle_factor",
                l.lift_off_obstacle_factor,
                (0.0..=10.0).contains(&l.lift_off_obstacle_factor),
                "0–10",
            ),
            (
                "lumped.soil_friction_scale",
                l.soil_friction_scale,
                (0.0..=10.0).contains(&l.soil_friction_scale),
                "0–10 (0: roughness alone)",
            ),
            (
                "simulation.dt_s",
                s.dt_s,
                s.dt_s > 0.0 && s.dt_s <= 1.0,
                "0 < dt ≤ 1 s",
            ),
            (
                "simulation.max_time_s",
                s.max_time_s,
                s.max_time_s > 0.0 && s.max_time_s.is_finite(),
                "> 0 s",
            ),
            (
                "simulation.rocks_per_cell",
                s.rocks_per_cell as f64,
                s.rocks_per_cell >= 1,
                "≥ 1",
            ),
            (
                "simulation.rocks_per_point",
                s.rocks_per_point as f64,
                s.rocks_per_point >= 1,
                "≥ 1",
            ),
            (
                "simulation.until_stable_pct",
                s.until_stable_pct.unwrap_or(1.0),
                s.until_stable_pct.is_none_or(|t| t > 0.0 && t <= 100.0),
                "0 < tolerance ≤ 100 %",
            ),
        ];
        for (name, value, ok, expected) in checks {
            if !ok {
                return Err(out_of_range(name, None, value, expected));
            }
        }
        self.check_rigid()?;
        let c = &self.contact;
        for (name, p) in [("contact.ground", c.ground), ("contact.tree", c.tree)] {
            if !(p.mu >= 0.0 && p.mu.is_finite()) {
                return Err(out_of_range(&format!("{name}.mu"), None, p.mu, "≥ 0"));
            }
            for (k, e) in [("eps_n", p.eps_n), ("eps_t", p.eps_t)] {
                if !(0.0..=1.0).contains(&e) {
                    return Err(out_of_range(&format!("{name}.{k}"), None, e, "0–1"));
                }
            }
        }
        if c.model == crate::GroundModel::Scarring {
            c.scarring
                .check(self.terrain.surface.ground_class.as_ref())?;
        }
        if let Some(sl) = c.slippage {
            let ok = sl.mu_min >= 0.0
                && sl.mu_max >= sl.mu_min
                && sl.beta_per_s >= 0.0
                && sl.kappa_per_m > 0.0
                && [sl.mu_max, sl.beta_per_s, sl.kappa_per_m]
                    .iter()
                    .all(|v| v.is_finite());
            if !ok {
                return Err(ScenarioError::invalid(
                    "contact.slippage",
                    "need 0 ≤ mu_min ≤ mu_max, beta_per_s ≥ 0, kappa_per_m > 0",
                ));
            }
        }
        let interval = self.output.trajectory_interval_s;
        if !(interval.is_finite() && interval >= 0.0) {
            return Err(out_of_range(
                "output.trajectory_interval_s",
                None,
                interval,
                "finite and ≥ 0",
            ));
        }
        if let Some(&p) = self
            .output
            .percentiles
            .iter()
            .find(|p| !(**p > 0.0 && **p < 100.0))
        {
            return Err(out_of_range(
                "output.percentiles",
                None,
                p,
                "strictly between 0 and 100",
            ));
        }
        self.check_energy_thresholds()
    }

    /// `[output] energy_thresholds_kj`: finite, > 0, strictly ascending, at most
    /// [`crate::params::MAX_ENERGY_THRESHOLDS`].
    fn check_energy_thresholds(&self) -> Result<(), ScenarioError> {
        let t = &self.output.energy_thresholds_kj;
        let key = "output.energy_thresholds_kj";
        if t.len() > crate::params::MAX_ENERGY_THRESHOLDS {
            return Err(out_of_range(
                key,
                None,
                t.len() as f64,
                &format!(
                    "at most {} thresholds",
                    crate::params::MAX_ENERGY_THRESHOLDS
                ),
            ));
        }
        if let Some(&e) = t.iter().find(|e| !(e.is_finite() && **e > 0.0)) {
            return Err(out_of_range(key, None, e, "finite and > 0 kJ"));
        }
        if let Some(w) = t.windows(2).find(|w| w[1] <= w[0]) {
            return Err(out_of_range(
                key,
                None,
                w[1],
                &format!("strictly above the threshold before it ({} kJ)", w[0]),
            ));
        }
        Ok(())
    }
}

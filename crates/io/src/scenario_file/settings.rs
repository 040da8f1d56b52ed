//! The plain settings sections of a scenario file (`[rigid]`, `[simulation]`, `[output]`):
//! each key given, or its default.

use crate::schema;
use rockfall_scenario::{OutputSettings, RigidParams, SimulationSettings};

pub(super) fn rigid(r: Option<schema::RigidSec>) -> RigidParams {
    let d = RigidParams::default();
    let Some(r) = r else { return d };
    RigidParams {
        solver_alpha: r.solver_alpha.unwrap_or(d.solver_alpha),
        solver_tolerance_ms: r.solver_tolerance_ms.unwrap_or(d.solver_tolerance_ms),
        solver_max_iterations: r.solver_max_iterations.unwrap_or(d.solver_max_iterations),
        warm_start: r.warm_start.unwrap_or(d.warm_start),
        stop_speed_ms: r.stop_speed_ms.unwrap_or(d.stop_speed_ms),
        rest_time_s: r.rest_time_s.unwrap_or(d.rest_time_s),
        max_speed_ms: r.max_speed_ms.unwrap_or(d.max_speed_ms),
        linear_damping_per_s: r.linear_damping_per_s.unwrap_or(d.linear_damping_per_s),
        angular_damping_per_s: r.angular_damping_per_s.unwrap_or(d.angular_damping_per_s),
    }
}

pub(super) fn simulation(s: Option<schema::SimulationSec>) -> SimulationSettings {
    let d = SimulationSettings::default();
    let Some(s) = s else {
        return SimulationSettings {
            rocks_per_cell_given: false,
            rocks_per_point_given: false,
            ..d
        };
    };
    SimulationSettings {
        dt_s: s.dt_s.unwrap_or(d.dt_s),
        max_time_s: s.max_time_s.unwrap_or(d.max_time_s),
        rocks_per_cell: s.rocks_per_cell.unwrap_or(d.rocks_per_cell),
        rocks_per_point: s.rocks_per_point.unwrap_or(d.rocks_per_point),
        until_stable_pct: s.until_stable_pct,
        rocks_per_cell_given: s.rocks_per_cell.is_some(),
        rocks_per_point_given: s.rocks_per_point.is_some(),
    }
}

pub(super) fn output(o: Option<schema::OutputSec>) -> OutputSettings {
    let d = OutputSettings::default();
    let Some(o) = o else { return d };
    OutputSettings {
        trajectories: o.trajectories.unwrap_or(d.trajectories),
        trajectory_interval_s: o.trajectory_interval_s.unwrap_or(d.trajectory_interval_s),
        ascii_rasters: o.ascii_rasters.unwrap_or(d.ascii_rasters),
        rocks_csv: o.rocks_csv.unwrap_or(d.rocks_csv),
        screen_crossings: o.screen_crossings.unwrap_or(d.screen_crossings),
        percentiles: o.percentiles.unwrap_or(d.percentiles),
        energy_thresholds_kj: o.energy_thresholds_kj.unwrap_or(d.energy_thresholds_kj),
    }
}

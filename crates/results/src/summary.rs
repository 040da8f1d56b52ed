//! `summary.json`.

use serde_json::{Map, Value, json};

use crate::Results;
use crate::hist::Stat;
use crate::tally::OUTCOME_NAMES;

/// A number, or `null` when undefined (no values, non-finite).
pub(crate) fn num(v: Option<f64>) -> Value {
    v.filter(|x| x.is_finite()).map_or(Value::Null, Value::from)
}

/// `part / whole`, `null` when `whole` is 0.
pub(crate) fn fraction(part: u64, whole: u64) -> Value {
    num((whole > 0).then(|| part as f64 / whole as f64))
}

/// {mean, p95, max} of a statistic, every value divided by `divisor`.
fn mean_p95_max(s: &Stat, divisor: f64) -> Value {
    json!({
        "mean": num(s.mean().map(|v| v / divisor)),
        "p95": num(s.percentile(95.0).map(|v| v / divisor)),
        "max": num(s.max().map(|v| v / divisor)),
    })
}

impl Results {
    /// `summary.json` as a JSON value (keys sorted). Undefined statistics (no rocks, no
    /// crossings) are `null`, never NaN.
    ///
    /// Keys (units in the names): `engine`, `scenario`, `version`, `seed`, `rocks`, `threads`,
    /// `wall_time_s`, `trajectories_per_s`; `stopped_fraction` (stopped inside the DEM, nets
    /// included), `net_stopped_fraction`, `left_dem_fraction`, `time_limit_fraction`,
    /// `failed_fraction`, `outcomes` (counts); `runout_m` {`p50`,`p95`,`max`,`mean`},
    /// `max_velocity_ms` and `max_jump_height_m` {`mean`,`p95`,`max`} over rocks of each
    /// rock's maximum; `time_s` {`mean`,`max`}; `tree_impacts_per_rock`,
    /// `stems_broken_per_rock`, `rebounds_per_rock`; `cells_reached`,
    /// `trajectory_rows`; `screens`: per screen {`name`, `passed_fraction` (distinct
    /// rocks that crossed / rocks), `rocks_passed`, `crossings`, `velocity_ms`, `energy_kj`,
    /// `jump_height_m`}, the last three {`mean`,`p95`,`max`} over every crossing (a rock
    /// crossing twice contributes twice); `percentile_relative_error`; `parameters`.
    ///
    /// Only `threads`, `wall_time_s` and `trajectories_per_s` depend on how the run was
    /// parallelised.
    pub fn summary_json(&self) -> Value {
        let r = &self.tally.rock;
        let rocks = r.rocks();
        let [stopped, net, left, time_limit, failed] = r.outcomes;
        let per_rock = |n: u64| fraction(n, rocks);
        let screens: Vec<Value> = (self.layout.screens.iter().zip(&self.tally.screens))
            .map(|(screen, s)| {
                json!({
                    "name": screen.name,
                    "passed_fraction": fraction(s.rocks, rocks),
                    "rocks_passed": s.rocks,
                    "crossings": s.velocity.count(),
                    "velocity_ms": mean_p95_max(&s.velocity, 1.0),
                    "energy_kj": mean_p95_max(&s.energy, 1e3),
                    "jump_height_m": mean_p95_max(&s.height, 1.0),
                })
            })
            .collect();
        let info = &self.info;
        let per_s = (info.wall_time_s > 0.0).then(|| rocks as f64 / info.wall_time_s);
        let cells_reached = (self.tally.cells.touched().iter())
            .filter(|c| c.visits > 0)
            .count();
        let mut m = Map::new();
        let mut put = |k: &str, v: Value| {
            m.insert(k.to_string(), v);
        };
        put("engine", json!(info.engine));
        put("scenario", json!(info.scenario));
        put("version", json!(env!("CARGO_PKG_VERSION")));
        put("seed", json!(info.seed));
        put("rocks", json!(rocks));
        put("threads", json!(info.threads));
        put("wall_time_s", num(Some(info.wall_time_s)));
        put("trajectories_per_s", num(per_s));
        put("stopped_fraction", fraction(stopped + net, rocks));
        put("net_stopped_fraction", fraction(net, rocks));
        put("left_dem_fraction", fraction(left, rocks));
        put("time_limit_fraction", fraction(time_limit, rocks));
        put("failed_fraction", fraction(failed, rocks));
        let outcomes = (OUTCOME_NAMES.iter().zip(r.outcomes))
            .map(|(name, n)| (name.to_string(), json!(n)))
            .collect();
        put("outcomes", Value::Object(outcomes));
        put(
            "runout_m",
            json!({
                "p50": num(r.runout.percentile(50.0)),
                "p95": num(r.runout.percentile(95.0)),
                "max": num(r.runout.max()),
                "mean": num(r.runout.mean()),
            }),
        );
        put("max_velocity_ms", mean_p95_max(&r.max_velocity, 1.0));
        put("max_jump_height_m", mean_p95_max(&r.max_jump, 1.0));
        put(
            "time_s",
            json!({ "mean": num(r.time.mean()), "max": num(r.time.max()) }),
        );
        put("tree_impacts_per_rock", per_rock(r.tree_impacts));
        put("stems_broken_per_rock", per_rock(r.stems_broken));
        put("rebounds_per_rock", per_rock(r.rebounds));
        put("cells_reached", json!(cells_reached));
        put("trajectory_rows", json!(self.rows.len()));
        put("screens", Value::Array(screens));
        put(
            "percentile_relative_error",
            json!(crate::PERCENTILE_RELATIVE_ERROR),
        );
        put("parameters", Value::Object(info.extra.clone()));
        Value::Object(m)
    }
}

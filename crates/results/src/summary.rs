//! `summary.json`: the [`Summary`] of a run, one field per key.

use serde::{Deserialize, Serialize};

use crate::Results;
use crate::convergence::ConvergenceSummary;
use crate::hist::Stat;
use crate::parameters::Parameters;

/// `v` when it is a finite number; `None` (written `null`) when undefined or not finite.
pub(crate) fn finite(v: Option<f64>) -> Option<f64> {
    v.filter(|x| x.is_finite())
}

/// `part / whole`, `None` (written `null`) when `whole` is 0.
pub(crate) fn fraction(part: u64, whole: u64) -> Option<f64> {
    finite((whole > 0).then(|| part as f64 / whole as f64))
}

/// `summary.json` of a run: the headline numbers, per screen, and the engine's parameters.
/// Units are in the names. Undefined statistics (no rocks, no crossings) are `None`, written
/// `null`, never NaN; fractions are `None` when no rock was simulated.
///
/// Written with its keys sorted ([`crate::write_json`]). Only `threads`, `wall_time_s` and
/// `trajectories_per_s` depend on how the run was parallelised.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Summary {
    /// Engine name: `lumped` or `rigid`.
    pub engine: String,
    /// Scenario name.
    pub scenario: String,
    /// Version of rockfall that wrote the summary.
    pub version: String,
    /// Master seed.
    pub seed: u64,
    /// Rocks simulated.
    pub rocks: u64,
    /// Worker threads used.
    pub threads: u64,
    /// Wall-clock time of the simulation, s.
    pub wall_time_s: Option<f64>,
    /// Rocks per second of wall-clock time (`None` for a zero wall time).
    pub trajectories_per_s: Option<f64>,
    /// Share of rocks stopped inside the DEM, nets included.
    pub stopped_fraction: Option<f64>,
    /// Share of rocks stopped by a net.
    pub net_stopped_fraction: Option<f64>,
    /// Share of rocks that left the DEM.
    pub left_dem_fraction: Option<f64>,
    /// Share of rocks still moving at the time limit.
    pub time_limit_fraction: Option<f64>,
    /// Share of rocks the engine gave up on.
    pub failed_fraction: Option<f64>,
    /// Rocks per outcome.
    pub outcomes: Outcomes,
    /// Rocks that came to rest in the cell they were released from: released where the ground
    /// holds a rock at rest (the lumped engine's rolling friction at least the tangent of the
    /// slope), they never left it. `[release] height_m` and `velocity_ms` start them moving.
    #[serde(default)]
    pub held_at_release: u64,
    /// `held_at_release` / rocks (`None` without rocks).
    #[serde(default)]
    pub held_at_release_fraction: Option<f64>,
    /// Run-out (horizontal distance from release to end point) over rocks, m.
    pub runout_m: Runout,
    /// Each rock's largest translational speed, over rocks, m/s.
    pub max_velocity_ms: MeanP95Max,
    /// Each rock's largest jump height (centre above the ground), over rocks, m.
    pub max_jump_height_m: MeanP95Max,
    /// Simulated time per rock, s.
    pub time_s: TimeStats,
    /// Tree impacts per rock.
    pub tree_impacts_per_rock: Option<f64>,
    /// Stems broken per rock.
    pub stems_broken_per_rock: Option<f64>,
    /// Ground rebounds per rock.
    pub rebounds_per_rock: Option<f64>,
    /// Events the engine simulated over all rocks: flight arcs and rolling steps (lumped), time
    /// steps (rigid); `events / wall_time_s` is the engine's cost per event.
    pub events: u64,
    /// Events per rock.
    pub events_per_rock: Option<f64>,
    /// Share of the simulated time in each mode of motion ([`crate::Motion`]; rigid engine,
    /// `None` for the lumped engine).
    #[serde(default)]
    pub motion: Option<MotionShares>,
    /// Cells visited by at least one rock.
    pub cells_reached: u64,
    /// Bytes of the run's per-cell statistics (counters, histograms, source cells and the
    /// table that finds them) once merged, each cell's histograms in their smaller form (the
    /// same whatever the threads, shares and merges); 0 in summaries written before it was
    /// added.
    #[serde(default)]
    pub cell_statistics_bytes: u64,
    /// `cell_statistics_bytes` per reached cell (`None` when no cell was reached).
    #[serde(default)]
    pub cell_statistics_bytes_per_reached_cell: Option<f64>,
    /// Rows of `trajectories.csv`.
    pub trajectory_rows: u64,
    /// The evaluation screens, in scenario order.
    pub screens: Vec<ScreenSummary>,
    /// Relative error bound of the percentiles inside the histograms' ranges
    /// ([`crate::PERCENTILE_RELATIVE_ERROR`]).
    pub percentile_relative_error: f64,
    /// The engine's parameters.
    pub parameters: Parameters,
    /// How a convergence-driven run (`--until-stable`) ended; absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub convergence: Option<ConvergenceSummary>,
}

/// Mean, 95th percentile and maximum of a statistic (`None` without values).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct MeanP95Max {
    /// Mean.
    pub mean: Option<f64>,
    /// 95th percentile (from the histogram, see the crate docs).
    pub p95: Option<f64>,
    /// Maximum (exact).
    pub max: Option<f64>,
}

impl MeanP95Max {
    /// {mean, p95, max} of `s`, every value divided by `divisor`.
    fn of(s: &Stat, divisor: f64) -> MeanP95Max {
        MeanP95Max {
            mean: finite(s.mean().map(|v| v / divisor)),
            p95: finite(s.percentile(95.0).map(|v| v / divisor)),
            max: finite(s.max().map(|v| v / divisor)),
        }
    }
}

/// Run-out over rocks, m (`None` without rocks).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Runout {
    /// Median.
    pub p50: Option<f64>,
    /// 95th percentile.
    pub p95: Option<f64>,
    /// Longest.
    pub max: Option<f64>,
    /// Mean.
    pub mean: Option<f64>,
}

/// Shares of the simulated time of all rocks in each mode of motion ([`crate::Motion`]);
/// they sum to 1.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct MotionShares {
    /// In flight.
    pub flight: f64,
    /// Rolling.
    pub rolling: f64,
    /// Sliding on a face.
    pub sliding_face: f64,
    /// Sliding on an edge or a vertex.
    pub sliding_edge: f64,
    /// In slow ground contact.
    pub slow: f64,
    /// The time they share, summed over rocks, s.
    pub total_s: f64,
}

impl MotionShares {
    /// The shares of times summed in microseconds; `None` when they sum to zero.
    pub(crate) fn of(motion_us: &[u64; 5]) -> Option<MotionShares> {
        let total: u64 = motion_us.iter().sum();
        let share = |k: usize| motion_us[k] as f64 / total as f64;
        (total > 0).then(|| MotionShares {
            flight: share(0),
            rolling: share(1),
            sliding_face: share(2),
            sliding_edge: share(3),
            slow: share(4),
            total_s: total as f64 * 1e-6,
        })
    }
}

/// Simulated time per rock, s (`None` without rocks).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct TimeStats {
    /// Mean.
    pub mean: Option<f64>,
    /// Longest.
    pub max: Option<f64>,
}

/// Rocks per outcome, keyed by [`crate::Outcome::name`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Outcomes {
    /// Came to rest inside the DEM.
    pub stopped: u64,
    /// Stopped by a net.
    pub net_stopped: u64,
    /// Left the DEM.
    pub left_dem: u64,
    /// Still moving at the time limit.
    pub time_limit: u64,
    /// The engine gave up on the rock.
    pub failed: u64,
}

/// What crossed one evaluation screen. The statistics are over every crossing (a rock
/// crossing twice contributes twice).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ScreenSummary {
    /// Screen name, as in the scenario.
    pub name: String,
    /// Distinct rocks that crossed / rocks (`None` without rocks).
    pub passed_fraction: Option<f64>,
    /// Distinct rocks that crossed.
    pub rocks_passed: u64,
    /// Crossings.
    pub crossings: u64,
    /// Translational speed at the crossings, m/s.
    pub velocity_ms: MeanP95Max,
    /// Kinetic energy at the crossings, kJ.
    pub energy_kj: MeanP95Max,
    /// Height of the rock centre above the ground at the crossings, m.
    pub jump_height_m: MeanP95Max,
    /// The screen's energy capacity, kJ, when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capacity_kj: Option<f64>,
    /// Crossings with more kinetic energy than `capacity_kj` / crossings (`None` without
    /// a capacity or without crossings).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exceed_energy_fraction: Option<f64>,
    /// The screen's barrier height, m, when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height_m: Option<f64>,
    /// Crossings with the rock's centre higher above the ground than `height_m` /
    /// crossings (`None` without a height or without crossings).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exceed_height_fraction: Option<f64>,
}

impl Results {
    /// The run's `summary.json` (see [`Summary`]).
    pub fn summary(&self) -> Summary {
        let r = &self.tally.rock;
        let rocks = r.rocks();
        let [stopped, net_stopped, left_dem, time_limit, failed] = r.outcomes;
        let per_rock = |n: u64| fraction(n, rocks);
        let screens = (self.layout.screens.iter().zip(&self.tally.screens))
            .map(|(screen, s)| ScreenSummary {
                name: screen.name.clone(),
                passed_fraction: fraction(s.rocks, rocks),
                rocks_passed: s.rocks,
                crossings: s.velocity.count(),
                velocity_ms: MeanP95Max::of(&s.velocity, 1.0),
                energy_kj: MeanP95Max::of(&s.energy, 1e3),
                jump_height_m: MeanP95Max::of(&s.height, 1.0),
                capacity_kj: screen.capacity_kj,
                exceed_energy_fraction: screen
                    .capacity_kj
                    .and_then(|_| fraction(s.over_capacity, s.velocity.count())),
                height_m: screen.height_m,
                exceed_height_fraction: screen
                    .height_m
                    .and_then(|_| fraction(s.over_height, s.velocity.count())),
            })
            .collect();
        let info = &self.info;
        let per_s = (info.wall_time_s > 0.0).then(|| rocks as f64 / info.wall_time_s);
        let (cells_reached, cell_bytes) = match self.streamed {
            Some((reached, bytes)) => (reached as usize, bytes),
            None => (
                self.tally.cells.touched().filter(|c| c.visits > 0).count(),
                self.tally.cells.compact_bytes(),
            ),
        };
        Summary {
            engine: info.engine.clone(),
            scenario: info.scenario.clone(),
            version: env!("CARGO_PKG_VERSION").to_string(),
            seed: info.seed,
            rocks,
            threads: info.threads as u64,
            wall_time_s: finite(Some(info.wall_time_s)),
            trajectories_per_s: finite(per_s),
            stopped_fraction: fraction(stopped + net_stopped, rocks),
            net_stopped_fraction: fraction(net_stopped, rocks),
            left_dem_fraction: fraction(left_dem, rocks),
            time_limit_fraction: fraction(time_limit, rocks),
            failed_fraction: fraction(failed, rocks),
            outcomes: Outcomes {
                stopped,
                net_stopped,
                left_dem,
                time_limit,
                failed,
            },
            held_at_release: r.held_at_release,
            held_at_release_fraction: fraction(r.held_at_release, rocks),
            runout_m: Runout {
                p50: finite(r.runout.percentile(50.0)),
                p95: finite(r.runout.percentile(95.0)),
                max: finite(r.runout.max()),
                mean: finite(r.runout.mean()),
            },
            max_velocity_ms: MeanP95Max::of(&r.max_velocity, 1.0),
            max_jump_height_m: MeanP95Max::of(&r.max_jump, 1.0),
            time_s: TimeStats {
                mean: finite(r.time.mean()),
                max: finite(r.time.max()),
            },
            tree_impacts_per_rock: per_rock(r.tree_impacts),
            stems_broken_per_rock: per_rock(r.stems_broken),
            rebounds_per_rock: per_rock(r.rebounds),
            events: r.events,
            events_per_rock: per_rock(r.events),
            motion: MotionShares::of(&r.motion_us),
            cells_reached: cells_reached as u64,
            cell_statistics_bytes: cell_bytes as u64,
            cell_statistics_bytes_per_reached_cell: (cells_reached > 0)
                .then(|| cell_bytes as f64 / cells_reached as f64),
            trajectory_rows: self.rows.len() as u64,
            screens,
            percentile_relative_error: crate::PERCENTILE_RELATIVE_ERROR,
            parameters: info.parameters.clone(),
            convergence: self.convergence.clone(),
        }
    }

    /// [`Results::summary`] as a JSON value (keys sorted), as `summary.json` holds it.
    pub fn summary_json(&self) -> serde_json::Value {
        // cannot fail: every map of a summary is keyed by strings
        serde_json::to_value(self.summary()).unwrap_or_default()
    }
}

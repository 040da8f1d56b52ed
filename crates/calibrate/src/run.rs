//! A calibration end to end: the keys and targets checked, the forest built once, every
//! candidate run on the same seed (common random numbers: the objective moves with the
//! parameters, not with the Monte Carlo noise of fresh random streams), the search, the
//! record of every evaluation.

use std::time::Instant;

use rockfall_results::Results;
use rockfall_scenario::Scenario;
use rockfall_sim::{Overrides, Simulation};
use serde::Serialize;

use crate::deposits::Deposits;
use crate::keys;
use crate::search::{Phase, search};
use crate::spec::{Parameter, Spec};
use crate::targets::{self, Residual};
use crate::{CalibrationError, Evaluator};

/// How a calibration runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Candidates evaluated at most.
    pub budget: usize,
    /// Seed of the design and master seed of every candidate's run (none: the scenario's).
    pub seed: Option<u64>,
    /// Worker threads of each run (0: every core).
    pub threads: usize,
}

/// One candidate's run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    /// Order of evaluation, from 0.
    pub index: usize,
    /// Which phase of the search proposed it.
    pub phase: Phase,
    /// The parameters' values (for a scale: the factor), in the order of the spec.
    pub values: Vec<f64>,
    /// The objective: mean z² over the targets.
    pub objective: f64,
    /// Every target's comparison.
    pub residuals: Vec<Residual>,
    /// Whether every |z| ≤ 2.
    pub fits: bool,
}

/// A finished calibration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Calibration {
    /// Scenario name.
    pub scenario: String,
    /// Master seed of every run and of the design.
    pub seed: u64,
    /// Candidates asked for.
    pub budget: usize,
    /// Rocks per source cell and per release point of each candidate.
    pub rocks_per_cell: u64,
    /// Rocks per release point of each candidate.
    pub rocks_per_point: u64,
    /// Rocks of each candidate's run.
    pub rocks: u64,
    /// The free parameters.
    #[serde(skip)]
    pub parameters: Vec<Parameter>,
    /// Every evaluation, in order.
    pub evaluations: Vec<Evaluation>,
    /// Index of the best evaluation (smallest objective; the first of equals).
    pub best: usize,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
}

impl Calibration {
    /// The best evaluation.
    pub fn best(&self) -> &Evaluation {
        &self.evaluations[self.best]
    }

    /// The evaluations that fit every target within its uncertainty.
    pub fn fitting(&self) -> impl Iterator<Item = &Evaluation> {
        self.evaluations.iter().filter(|e| e.fits)
    }

    /// Each parameter's range `[min, max]` over the fitting evaluations (`None`: none fits).
    pub fn fit_ranges(&self) -> Vec<Option<[f64; 2]>> {
        (0..self.parameters.len())
            .map(|k| {
                self.fitting().fold(None, |r: Option<[f64; 2]>, e| {
                    let v = e.values[k];
                    Some(r.map_or([v, v], |[lo, hi]| [lo.min(v), hi.max(v)]))
                })
            })
            .collect()
    }
}

/// Applies every parameter of `params` at `values` to a copy of `base`.
pub fn candidate(
    base: &Scenario,
    params: &[Parameter],
    values: &[f64],
) -> Result<Scenario, CalibrationError> {
    let mut s = base.clone();
    for (p, &x) in params.iter().zip(values) {
        keys::apply(&mut s, base, p, x).map_err(|what| CalibrationError::Key {
            key: p.key.clone(),
            what,
        })?;
    }
    s.validate().map_err(|e| CalibrationError::Key {
        key: e.parameter().unwrap_or("?").to_string(),
        what: format!("a candidate is not a valid scenario: {e}"),
    })?;
    Ok(s)
}

/// Checks every parameter at both ends of its range: its key must exist, be numeric, and
/// give a valid scenario there.
pub fn check_parameters(base: &Scenario, params: &[Parameter]) -> Result<(), CalibrationError> {
    let known = keys::numeric_keys(base);
    for p in params {
        for x in [p.lo, p.hi] {
            let mut s = base.clone();
            if let Err(what) = keys::apply(&mut s, base, p, x) {
                let near = keys::near(&p.key, &known);
                let what = if what.starts_with("unknown key") && !near.is_empty() {
                    format!("{what}; near matches: {}", near.join(", "))
                } else {
                    what
                };
                return Err(CalibrationError::Key {
                    key: p.key.clone(),
                    what,
                });
            }
            s.validate().map_err(|e| CalibrationError::Key {
                key: p.key.clone(),
                what: format!("at {x}, the end of its range: {e}"),
            })?;
        }
    }
    Ok(())
}

/// The base scenario of a calibration: `scenario` with the spec's numbers of rocks, the
/// seed, no trajectories written, rock records kept where deposits are compared.
pub fn base_of(mut scenario: Scenario, spec: &Spec, seed: Option<u64>) -> Scenario {
    if let Some(n) = spec.rocks_per_cell {
        scenario.simulation.rocks_per_cell = n;
    }
    if let Some(n) = spec.rocks_per_point {
        scenario.simulation.rocks_per_point = n;
    }
    if let Some(s) = seed {
        scenario.seed = s;
    }
    scenario.simulation.until_stable_pct = None;
    scenario.output.trajectories = 0;
    scenario.output.rocks_csv = spec.deposits.is_some();
    scenario
}

/// The evaluator of a spec's targets and deposits (what `rockfall calibrate` compares).
pub struct SummaryTargets {
    spec: Spec,
    deposits: Option<Deposits>,
}

impl SummaryTargets {
    /// Checks the spec's targets against a quick run of `scenario` (one rock per release:
    /// the paths of `summary.json` do not depend on the number of rocks) and reads its
    /// deposits.
    pub fn new(
        spec: &Spec,
        scenario: &Scenario,
        forest_sim: &Simulation,
    ) -> Result<Self, CalibrationError> {
        let mut quick = scenario.clone();
        quick.simulation.rocks_per_cell = 1;
        quick.simulation.rocks_per_point = 1;
        let opts = rockfall_engine::RunOptions {
            threads: 1,
            progress: None,
            cancel: None,
        };
        let results = rockfall_sim::run(&quick, forest_sim.stems(), None, &opts)?;
        let summary = results.summary_json();
        for t in &spec.targets {
            targets::check(t, &summary).map_err(|what| CalibrationError::Target {
                path: t.path.clone(),
                what,
            })?;
        }
        let deposits = match &spec.deposits {
            Some(path) => Some(Deposits::read(path, scenario)?),
            None => None,
        };
        Ok(SummaryTargets {
            spec: spec.clone(),
            deposits,
        })
    }
}

impl Evaluator for SummaryTargets {
    fn residuals(&self, results: &Results) -> Vec<Residual> {
        let summary = results.summary_json();
        let mut r: Vec<Residual> = (self.spec.targets.iter())
            .map(|t| targets::residual(t, results, &summary))
            .collect();
        if let Some(d) = &self.deposits {
            r.extend(d.residuals(results));
        }
        r
    }
}

/// What a calibration tells its caller as it goes.
pub trait Progress {
    /// `done` of `budget` candidates evaluated; the best objective so far.
    fn evaluated(&self, done: usize, budget: usize, best: f64);
    /// Whether to stop now (a cancelled run).
    fn cancelled(&self) -> bool {
        false
    }
}

/// No progress reports.
pub struct Silent;

impl Progress for Silent {
    fn evaluated(&self, _: usize, _: usize, _: f64) {}
}

/// Calibrates `scenario`'s free parameters of `spec` against its targets: see the crate docs.
pub fn calibrate(
    scenario: Scenario,
    spec: &Spec,
    opts: &Options,
    progress: &dyn Progress,
) -> Result<Calibration, CalibrationError> {
    let scenario = base_of(scenario, spec, opts.seed);
    // the keys first (before the forest is built and the targets are checked by a run)
    check_parameters(&scenario, &spec.parameters)?;
    let sim = Simulation::new(
        scenario,
        &Overrides {
            threads: Some(opts.threads),
            ..Overrides::default()
        },
    )?;
    let evaluator = SummaryTargets::new(spec, sim.scenario(), &sim)?;
    calibrate_with(&sim, &spec.parameters, &evaluator, opts, progress)
}

/// Calibrates the parameters `params` of `sim`'s scenario (its forest built once) against
/// what `evaluator` compares.
pub fn calibrate_with(
    sim: &Simulation,
    params: &[Parameter],
    evaluator: &dyn Evaluator,
    opts: &Options,
    progress: &dyn Progress,
) -> Result<Calibration, CalibrationError> {
    let started = Instant::now();
    let base = sim.scenario();
    // cheap next to one run (`calibrate` checks before building the forest, too)
    check_parameters(base, params)?;
    let run_opts = rockfall_engine::RunOptions {
        threads: sim.threads(),
        progress: None,
        cancel: None,
    };
    let mut evaluations: Vec<Evaluation> = Vec::new();
    let mut failure: Option<CalibrationError> = None;
    let mut best = f64::INFINITY;
    let mut eval = |u: &[f64], phase: Phase| -> Option<f64> {
        if progress.cancelled() {
            failure = Some(CalibrationError::Cancelled);
            return None;
        }
        let values: Vec<f64> = params.iter().zip(u).map(|(p, &x)| p.at(x)).collect();
        let outcome = candidate(base, params, &values)
            .and_then(|s| Ok(rockfall_sim::run(&s, sim.stems(), None, &run_opts)?));
        let results = match outcome {
            Ok(r) => r,
            Err(e) => {
                failure = Some(e);
                return None;
            }
        };
        let residuals = evaluator.residuals(&results);
        let objective = targets::objective(&residuals);
        best = best.min(objective);
        evaluations.push(Evaluation {
            index: evaluations.len(),
            phase,
            values,
            objective,
            fits: targets::fits(&residuals),
            residuals,
        });
        progress.evaluated(evaluations.len(), opts.budget, best);
        Some(objective)
    };
    search(params.len(), opts.budget, sim.scenario().seed, &mut eval);
    if let Some(e) = failure {
        return Err(e);
    }
    let best = (evaluations.iter())
        .min_by(|a, b| {
            a.objective
                .total_cmp(&b.objective)
                .then(a.index.cmp(&b.index))
        })
        .map(|e| e.index)
        .ok_or(CalibrationError::NoEvaluation)?;
    Ok(Calibration {
        scenario: base.name.clone(),
        seed: base.seed,
        budget: opts.budget,
        rocks_per_cell: base.simulation.rocks_per_cell,
        rocks_per_point: base.simulation.rocks_per_point,
        rocks: rockfall_sim::rocks(base),
        parameters: params.to_vec(),
        evaluations,
        best,
        wall_time_s: started.elapsed().as_secs_f64(),
    })
}

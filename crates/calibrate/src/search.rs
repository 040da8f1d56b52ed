//! The search over the unit cube of the free parameters: a Latin hypercube, then a
//! Nelder–Mead refinement from its best point.
//!
//! - **Global**: a Latin hypercube design (McKay, Beckman & Conover 1979) of about 60 % of the
//!   budget (at least 2d + 2 points): every parameter's range is cut into as many strata as
//!   points, each stratum used once, at a random place within it, from the calibration's
//!   seed. Space-filling and deterministic.
//! - **Local**: the Nelder–Mead simplex (argmin's `NelderMead`, Nelder & Mead 1965) from the
//!   best design point, its first simplex a tenth of each range wide, until the budget is
//!   spent or the simplex's objective values agree within [`SD_TOLERANCE`] (the best value
//!   has stopped improving). The simplex may step outside the cube: such a point is
//!   evaluated at its projection onto the cube, plus a penalty of its squared distance
//!   (ours), so that the search comes back inside the ranges. Points already evaluated are
//!   not run again.
//!
//! Why argmin and not a derivative-based method: the objective comes from Monte Carlo runs,
//! piecewise constant in places; Nelder–Mead needs no gradient and argmin's is well kept.

use std::cell::RefCell;
use std::collections::HashMap;

use argmin::core::{CostFunction, Error, Executor};
use argmin::solver::neldermead::NelderMead;
use rand::RngExt;
use rand::seq::SliceRandom;
use rockfall_rng::{Purpose, stream};

/// Spread of the simplex's objective values below which the refinement stops.
pub const SD_TOLERANCE: f64 = 1e-4;

/// Which phase proposed a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// The Latin hypercube.
    Design,
    /// The Nelder–Mead refinement.
    Refine,
}

/// Evaluations of the design for `dims` parameters and a budget of `budget` evaluations.
pub fn design_size(dims: usize, budget: usize) -> usize {
    let min = 2 * dims + 2;
    if budget <= min {
        budget
    } else {
        ((budget as f64 * 0.6).round() as usize).clamp(min, budget)
    }
}

/// A Latin hypercube of `n` points in `[0, 1]^dims` from `seed`.
pub fn latin_hypercube(n: usize, dims: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = stream(seed, Purpose::Calibration, &[n as u64, dims as u64]);
    let mut points = vec![vec![0.0; dims]; n];
    for d in 0..dims {
        let mut strata: Vec<usize> = (0..n).collect();
        strata.shuffle(&mut rng);
        for (p, s) in points.iter_mut().zip(strata) {
            p[d] = (s as f64 + rng.random::<f64>()) / n as f64;
        }
    }
    points
}

/// What a search asks of its caller: the objective at a point of the unit cube, `None` to
/// stop (the run was cancelled or failed).
pub type Evaluate<'a> = dyn FnMut(&[f64], Phase) -> Option<f64> + 'a;

/// Runs the search with at most `budget` evaluations of `eval`; returns the evaluations made.
pub fn search(dims: usize, budget: usize, seed: u64, eval: &mut Evaluate<'_>) -> usize {
    let mut done = 0;
    let mut best: Option<(f64, Vec<f64>)> = None;
    for u in latin_hypercube(design_size(dims, budget), dims, seed) {
        let Some(j) = eval(&u, Phase::Design) else {
            return done;
        };
        done += 1;
        if best.as_ref().is_none_or(|(b, _)| j < *b) {
            best = Some((j, u));
        }
    }
    let Some((_, start)) = best else { return done };
    if budget <= done || dims == 0 {
        return done;
    }
    let cost = Cost {
        eval: RefCell::new(eval),
        left: RefCell::new(budget - done),
        seen: RefCell::new(HashMap::new()),
        stopped: RefCell::new(false),
    };
    // argmin refuses only a negative tolerance; without a solver the design is the search
    let Ok(solver) = NelderMead::new(simplex(&start, 0.1)).with_sd_tolerance(SD_TOLERANCE) else {
        return done;
    };
    let iters = (budget - done) as u64;
    // the refinement ends by the budget (every later point +∞, no run) or by convergence
    let _ = Executor::new(&cost, solver)
        .configure(|state| state.max_iters(iters))
        .run();
    done + (budget - done - *cost.left.borrow())
}

/// The first simplex: `start` and one point a step `h` along each axis (inwards where the
/// step would leave the cube).
fn simplex(start: &[f64], h: f64) -> Vec<Vec<f64>> {
    let mut s = vec![start.to_vec()];
    for d in 0..start.len() {
        let mut p = start.to_vec();
        p[d] = if p[d] + h <= 1.0 { p[d] + h } else { p[d] - h };
        s.push(p);
    }
    s
}

struct Cost<'a, 'b> {
    eval: RefCell<&'a mut Evaluate<'b>>,
    left: RefCell<usize>,
    seen: RefCell<HashMap<Vec<u64>, f64>>,
    stopped: RefCell<bool>,
}

impl CostFunction for &Cost<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, p: &Vec<f64>) -> Result<f64, Error> {
        let inside: Vec<f64> = p.iter().map(|x| x.clamp(0.0, 1.0)).collect();
        let outside2: f64 = p.iter().zip(&inside).map(|(a, b)| (a - b) * (a - b)).sum();
        let key: Vec<u64> = inside.iter().map(|x| x.to_bits()).collect();
        let known = self.seen.borrow().get(&key).copied();
        let j = match known {
            Some(j) => j,
            None => {
                // argmin's Nelder–Mead unwraps some of its cost calls: once the budget is
                // spent (or the caller stopped), every new point costs +∞ without a run, and
                // the iterations left end cheaply
                if *self.left.borrow() == 0 || *self.stopped.borrow() {
                    return Ok(f64::INFINITY);
                }
                let Some(j) = (self.eval.borrow_mut())(&inside, Phase::Refine) else {
                    *self.stopped.borrow_mut() = true;
                    return Ok(f64::INFINITY);
                };
                *self.left.borrow_mut() -= 1;
                self.seen.borrow_mut().insert(key, j);
                j
            }
        };
        Ok(j + 1e3 * outside2)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn latin_hypercube_uses_every_stratum_once() {
        let pts = latin_hypercube(20, 3, 7);
        for d in 0..3 {
            let mut strata: Vec<usize> = pts.iter().map(|p| (p[d] * 20.0) as usize).collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..20).collect::<Vec<_>>());
        }
        assert_eq!(pts, latin_hypercube(20, 3, 7));
        assert_ne!(pts, latin_hypercube(20, 3, 8));
    }

    #[test]
    fn finds_the_minimum_of_a_bowl_within_the_budget() {
        let target = [0.3, 0.72];
        let mut calls = Vec::new();
        let mut f = |u: &[f64], phase: Phase| {
            calls.push(phase);
            Some((u[0] - target[0]).powi(2) + 10.0 * (u[1] - target[1]).powi(2))
        };
        let n = search(2, 80, 1, &mut f);
        assert!(
            n <= 80 && n == calls.len(),
            "{n} evaluations, {} calls",
            calls.len()
        );
        assert_eq!(calls.iter().filter(|p| **p == Phase::Design).count(), 48);
        // the refinement improves on the design's best by far, down to the tolerance
        let (mut design, mut best) = (f64::MAX, f64::MAX);
        let mut g = |u: &[f64], phase: Phase| {
            let j = (u[0] - target[0]).powi(2) + 10.0 * (u[1] - target[1]).powi(2);
            if phase == Phase::Design {
                design = design.min(j);
            }
            best = best.min(j);
            Some(j)
        };
        search(2, 80, 1, &mut g);
        assert!(
            best < 1e-3 && best < 0.1 * design,
            "best {best}, design {design}"
        );
    }

    #[test]
    fn a_minimum_on_the_edge_of_the_cube_is_reached_from_inside() {
        let mut best = (f64::MAX, vec![]);
        let mut f = |u: &[f64], _: Phase| {
            let j = (u[0] - 1.4).powi(2);
            if j < best.0 {
                best = (j, u.to_vec());
            }
            Some(j)
        };
        search(1, 40, 3, &mut f);
        assert!(best.1[0] > 0.99 && best.1[0] <= 1.0, "{:?}", best.1);
    }

    #[test]
    fn a_flat_objective_spends_the_budget_and_no_more() {
        let mut n = 0;
        let mut f = |_: &[f64], _: Phase| {
            n += 1;
            Some(1.0)
        };
        let done = search(3, 30, 2, &mut f);
        assert!(done <= 30 && done == n, "{done} done, {n} calls");
    }

    #[test]
    fn stops_when_asked() {
        let mut n = 0;
        let mut f = |_: &[f64], _: Phase| {
            n += 1;
            (n < 5).then_some(1.0)
        };
        assert_eq!(search(2, 50, 1, &mut f), 4);
    }
}

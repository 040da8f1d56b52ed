//! Normal distributions truncated to an interval, fitted so that the *truncated* distribution
//! has a requested mean and standard deviation.
//!
//! # Why fit the parent
//!
//! Forest inventories report the mean and spread of the stems they measured, and they measure
//! only stems above a calliper threshold (5 cm DBH is common in the Alps). Drawing DBH from
//! `Normal(mean, sd)` and discarding values below the threshold shifts the mean up and shrinks
//! the spread: for the seed-000 stand (31 ± 21 cm, threshold 5 cm) the naive draw gives about
//! 35 ± 18 cm. So we look for the *parent* normal N(μ′, σ′) whose truncation to [a, b] has
//! exactly the reported mean m and standard deviation s.
//!
//! # The moments of a truncated normal
//!
//! With α = (a − μ′)/σ′, β = (b − μ′)/σ′ and Z = Φ(β) − Φ(α) (Johnson, Kotz & Balakrishnan
//! 1994, *Continuous Univariate Distributions* vol. 1, §10.1):
//!
//! ```text
//! mean = μ′ + σ′ · (φ(α) − φ(β)) / Z
//! var  = σ′² · [1 + (α φ(α) − β φ(β)) / Z − ((φ(α) − φ(β)) / Z)²]
//! ```
//!
//! When both bounds lie in the same tail, Z and the φ's underflow long before their ratios do,
//! so the ratios are formed from Mills ratios R = Q/φ ([`crate::normal::mills_ratio`]).
//!
//! # Solving for the parent
//!
//! The solver works relative to the bound nearer to the mean (mirroring the problem when that
//! is the upper bound) with unknowns (α, ln σ′/s): in these coordinates the equations are
//! scale-free and well conditioned even when the parent mean lies far below the bound, as it
//! does for strongly skewed stands (31 ± 25 cm above 5 cm needs μ′ ≈ −528 cm, σ′ ≈ 123 cm).
//! Newton's method with a central-difference Jacobian and a backtracking line search
//! converges in 5–15 iterations from the untruncated guess (μ′, σ′) = (m, s).
//!
//! # Which requests are feasible
//!
//! A truncated normal is log-concave, and a log-concave distribution on [a, ∞) has
//! sd ≤ mean − a, with equality only in the exponential limit (μ′ → −∞). So s must be below
//! the distance from m to the nearer bound; [`TruncatedNormal::fit`] rejects larger values with
//! [`TruncatedNormalError::SdTooLarge`]. Close to that limit (within about 0.5 %) or to the
//! uniform limit of a narrow interval, the parent runs off to infinity and no finite parent
//! reproduces the request to solver precision: that is reported as
//! [`TruncatedNormalError::NoSolution`].
//!
//! # Sampling
//!
//! By inverse transform: u ~ U[0, 1) maps to Φ⁻¹(Φ(α) + u·Z), evaluated through upper-tail
//! probabilities when the interval lies in the upper tail, so that no precision is lost there.
//! One uniform per draw keeps the random stream's layout fixed whatever the parameters.

use crate::normal;
use rand::{Rng, RngExt};

/// Largest distance of a bound from the parent mean, in parent standard deviations, on the
/// far side (|α| for an interval entirely above the mean). Beyond it the interval's
/// probability underflows and the distribution is, to double precision, exponential.
pub const MAX_TAIL_OFFSET: f64 = 30.0;

/// Newton iterations allowed when fitting the parent.
const MAX_ITERATIONS: usize = 100;

/// Residual (relative to the requested sd) at which the fit is accepted.
const FIT_TOLERANCE: f64 = 1e-11;

/// Step of the central-difference Jacobian, in the solver's dimensionless unknowns.
const JACOBIAN_STEP: f64 = 1e-7;

/// Why a truncated normal could not be built.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum TruncatedNormalError {
    /// The bounds are NaN or not increasing.
    #[error("truncation bounds [{lower}, {upper}] are not an increasing pair")]
    InvalidBounds {
        /// Lower bound (units of the variable).
        lower: f64,
        /// Upper bound (units of the variable).
        upper: f64,
    },
    /// Mean not finite, or sd negative or not finite.
    #[error("mean {mean} and standard deviation {sd} must be finite, with sd ≥ 0")]
    InvalidParameters {
        /// Requested mean (units of the variable).
        mean: f64,
        /// Requested standard deviation (units of the variable).
        sd: f64,
    },
    /// The requested mean is not inside the bounds.
    #[error("mean {mean} lies outside the truncation bounds [{lower}, {upper}]")]
    MeanOutsideBounds {
        /// Requested mean (units of the variable).
        mean: f64,
        /// Lower bound (units of the variable).
        lower: f64,
        /// Upper bound (units of the variable).
        upper: f64,
    },
    /// The requested spread is more than any truncated normal on the interval can have.
    #[error(
        "standard deviation {sd} is too large: a truncated normal needs sd < {limit} \
         (the distance from the mean to the nearer bound)"
    )]
    SdTooLarge {
        /// Requested standard deviation (units of the variable).
        sd: f64,
        /// Exclusive upper limit for the sd (units of the variable).
        limit: f64,
    },
    /// The request is at the edge of what a truncated normal can represent.
    #[error(
        "no parent normal reproduces mean {mean} and sd {sd}: the request is too close to \
         the exponential (sd ≈ distance to a bound) or uniform (narrow interval) limit"
    )]
    NoSolution {
        /// Requested mean (units of the variable).
        mean: f64,
        /// Requested standard deviation (units of the variable).
        sd: f64,
    },
    /// The interval lies more than [`MAX_TAIL_OFFSET`] parent sds into one tail.
    #[error("the interval lies {offset} parent standard deviations into the tail")]
    FarInTail {
        /// Distance of the nearer bound from the parent mean, parent sds.
        offset: f64,
    },
}

/// A normal distribution N(μ′, σ′) truncated to [lower, upper].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruncatedNormal {
    parent_mean: f64,
    parent_sd: f64,
    lower: f64,
    upper: f64,
}

impl TruncatedNormal {
    /// The truncation of N(`parent_mean`, `parent_sd`²) to [`lower`, `upper`] (all in the
    /// variable's units; `lower` may be −∞ and `upper` +∞). A zero `parent_sd` is a point
    /// mass at the parent mean, which must then lie within the bounds.
    pub fn from_parent(
        parent_mean: f64,
        parent_sd: f64,
        lower: f64,
        upper: f64,
    ) -> Result<Self, TruncatedNormalError> {
        check_bounds(lower, upper)?;
        if !parent_mean.is_finite() || !parent_sd.is_finite() || parent_sd < 0.0 {
            return Err(TruncatedNormalError::InvalidParameters {
                mean: parent_mean,
                sd: parent_sd,
            });
        }
        if parent_sd == 0.0 {
            if !(lower..=upper).contains(&parent_mean) {
                return Err(TruncatedNormalError::MeanOutsideBounds {
                    mean: parent_mean,
                    lower,
                    upper,
                });
            }
        } else {
            let alpha = (lower - parent_mean) / parent_sd;
            let beta = (upper - parent_mean) / parent_sd;
            let offset = alpha.max(-beta);
            if offset > MAX_TAIL_OFFSET {
                return Err(TruncatedNormalError::FarInTail { offset });
            }
        }
        Ok(TruncatedNormal {
            parent_mean,
            parent_sd,
            lower,
            upper,
        })
    }

    /// The truncated normal on [`lower`, `upper`] whose own mean and standard deviation are
    /// `mean` and `sd` (variable's units), found by solving for the parent (see the module
    /// docs). `sd` = 0 gives a point mass at `mean`.
    pub fn fit(mean: f64, sd: f64, lower: f64, upper: f64) -> Result<Self, TruncatedNormalError> {
        check_bounds(lower, upper)?;
        if !mean.is_finite() || !sd.is_finite() || sd < 0.0 {
            return Err(TruncatedNormalError::InvalidParameters { mean, sd });
        }
        if sd == 0.0 {
            return Self::from_parent(mean, 0.0, lower, upper);
        }
        if !(lower < mean && mean < upper) {
            return Err(TruncatedNormalError::MeanOutsideBounds { mean, lower, upper });
        }
        let (near_gap, far_gap) = if mean - lower <= upper - mean {
            (mean - lower, upper - mean)
        } else {
            (upper - mean, mean - lower)
        };
        if near_gap.is_infinite() {
            // Both bounds infinite: no truncation at all.
            return Self::from_parent(mean, sd, lower, upper);
        }
        if sd >= near_gap {
            return Err(TruncatedNormalError::SdTooLarge {
                sd,
                limit: near_gap,
            });
        }
        let (alpha, ln_scale) = solve_standardised(near_gap / sd, (near_gap + far_gap) / sd)
            .ok_or(TruncatedNormalError::NoSolution { mean, sd })?;
        let parent_sd = sd * ln_scale.exp();
        // In mirrored coordinates the nearer bound is the lower one; map back.
        let parent_mean = if mean - lower <= upper - mean {
            lower - alpha * parent_sd
        } else {
            upper + alpha * parent_sd
        };
        Self::from_parent(parent_mean, parent_sd, lower, upper)
    }

    /// Mean of the parent normal μ′ (variable's units).
    pub fn parent_mean(&self) -> f64 {
        self.parent_mean
    }

    /// Standard deviation of the parent normal σ′ (variable's units).
    pub fn parent_sd(&self) -> f64 {
        self.parent_sd
    }

    /// Lower truncation bound (variable's units).
    pub fn lower(&self) -> f64 {
        self.lower
    }

    /// Upper truncation bound (variable's units).
    pub fn upper(&self) -> f64 {
        self.upper
    }

    /// Standardised bounds (α, β).
    fn standard_bounds(&self) -> (f64, f64) {
        (
            (self.lower - self.parent_mean) / self.parent_sd,
            (self.upper - self.parent_mean) / self.parent_sd,
        )
    }

    /// Mean and standard deviation of the truncated distribution (variable's units).
    pub fn moments(&self) -> (f64, f64) {
        if self.parent_sd == 0.0 {
            return (self.parent_mean, 0.0);
        }
        let (alpha, beta) = self.standard_bounds();
        let (m, v) = standard_moments(alpha, beta);
        (
            self.parent_mean + self.parent_sd * m,
            self.parent_sd * v.max(0.0).sqrt(),
        )
    }

    /// The value at which the truncated distribution function equals `u` (a probability in
    /// [0, 1]); always within the bounds.
    pub fn quantile(&self, u: f64) -> f64 {
        if self.parent_sd == 0.0 {
            return self.parent_mean;
        }
        let (alpha, beta) = self.standard_bounds();
        let z = standard_quantile(alpha, beta, u.clamp(0.0, 1.0));
        (self.parent_mean + self.parent_sd * z).clamp(self.lower, self.upper)
    }

    /// One draw (variable's units), consuming exactly one uniform from `rng`.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> f64 {
        let u: f64 = rng.random();
        self.quantile(u)
    }
}

fn check_bounds(lower: f64, upper: f64) -> Result<(), TruncatedNormalError> {
    if lower < upper && lower < f64::INFINITY && upper > f64::NEG_INFINITY {
        Ok(())
    } else {
        Err(TruncatedNormalError::InvalidBounds { lower, upper })
    }
}

/// `x · w` with the convention ∞ · 0 = 0 (a bound at infinity contributes nothing).
fn times_weight(x: f64, w: f64) -> f64 {
    if w == 0.0 { 0.0 } else { x * w }
}

/// Mean and variance of the standard normal truncated to [α, β] (standard units), α < β.
pub(crate) fn standard_moments(alpha: f64, beta: f64) -> (f64, f64) {
    if alpha.partial_cmp(&beta) != Some(std::cmp::Ordering::Less) {
        return (alpha, 0.0);
    }
    if beta <= 0.0 {
        let (m, v) = standard_moments(-beta, -alpha);
        return (-m, v);
    }
    // λa = φ(α)/Z and λb = φ(β)/Z.
    let (lambda_a, lambda_b) = if alpha >= 0.0 {
        // Both bounds in the upper tail: divide through by φ(α) to avoid underflow.
        let ratio = if beta.is_infinite() {
            0.0
        } else {
            (-0.5 * (beta - alpha) * (beta + alpha)).exp()
        };
        let tail_b = if ratio == 0.0 {
            0.0
        } else {
            normal::mills_ratio(beta) * ratio
        };
        let lambda_a = 1.0 / (normal::mills_ratio(alpha) - tail_b);
        (lambda_a, lambda_a * ratio)
    } else {
        let z = normal::centred_cdf(beta) - normal::centred_cdf(alpha);
        (normal::pdf(alpha) / z, normal::pdf(beta) / z)
    };
    let m = lambda_a - lambda_b;
    let v = 1.0 + times_weight(alpha, lambda_a) - times_weight(beta, lambda_b) - m * m;
    (m, v)
}

/// Inverse distribution function of the standard normal truncated to [α, β], at u ∈ [0, 1].
fn standard_quantile(alpha: f64, beta: f64, u: f64) -> f64 {
    if beta <= 0.0 {
        return -standard_quantile(-beta, -alpha, 1.0 - u);
    }
    let z = if alpha >= 0.0 {
        let qa = normal::upper_tail(alpha);
        let qb = normal::upper_tail(beta);
        normal::upper_quantile(qa - u * (qa - qb))
    } else {
        let mass = normal::centred_cdf(beta) - normal::centred_cdf(alpha);
        let p = normal::cdf(alpha) + u * mass;
        if p <= 0.5 {
            normal::quantile(p)
        } else {
            normal::upper_quantile(normal::upper_tail(beta) + (1.0 - u) * mass)
        }
    };
    z.clamp(alpha, beta)
}

/// Solves the dimensionless fit relative to the nearer bound, taken as the lower one at 0:
/// find (α, w) such that the standard normal scaled by σ = e^w (units of the requested sd)
/// and truncated to [0, `width`] has mean `kappa` (> 1) and sd 1. Returns (α, w).
fn solve_standardised(kappa: f64, width: f64) -> Option<(f64, f64)> {
    let residual = |x: [f64; 2]| -> [f64; 2] {
        let [alpha, w] = x;
        if !(alpha.abs() <= MAX_TAIL_OFFSET && w.abs() <= MAX_TAIL_OFFSET) {
            return [f64::INFINITY; 2];
        }
        let scale = w.exp();
        let (m, v) = standard_moments(alpha, alpha + width / scale);
        [scale * (m - alpha) - kappa, scale * v.max(0.0).sqrt() - 1.0]
    };
    let norm = |f: [f64; 2]| f[0].hypot(f[1]);

    let mut x = [-kappa, 0.0];
    let mut f = residual(x);
    let mut f_norm = norm(f);
    for _ in 0..MAX_ITERATIONS {
        if f_norm < FIT_TOLERANCE {
            return Some((x[0], x[1]));
        }
        let mut jacobian = [[0.0; 2]; 2];
        for j in 0..2 {
            let mut plus = x;
            let mut minus = x;
            plus[j] += JACOBIAN_STEP;
            minus[j] -= JACOBIAN_STEP;
            let (fp, fm) = (residual(plus), residual(minus));
            for i in 0..2 {
                jacobian[i][j] = (fp[i] - fm[i]) / (2.0 * JACOBIAN_STEP);
            }
        }
        let det = jacobian[0][0] * jacobian[1][1] - jacobian[0][1] * jacobian[1][0];
        if !det.is_finite() || det == 0.0 {
            return None;
        }
        let step = [
            -(jacobian[1][1] * f[0] - jacobian[0][1] * f[1]) / det,
            -(jacobian[0][0] * f[1] - jacobian[1][0] * f[0]) / det,
        ];
        // Backtracking: halve the step until the residual decreases.
        let mut t = 1.0;
        loop {
            let trial = [x[0] + t * step[0], x[1] + t * step[1]];
            let f_trial = residual(trial);
            let n_trial = norm(f_trial);
            if n_trial < f_norm {
                x = trial;
                f = f_trial;
                f_norm = n_trial;
                break;
            }
            t *= 0.5;
            if t < 1e-10 {
                return None;
            }
        }
    }
    (f_norm < FIT_TOLERANCE).then_some((x[0], x[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Moments by Simpson's rule on the truncated density (reference for the closed forms).
    fn simpson_moments(alpha: f64, beta: f64) -> (f64, f64) {
        let n = 20_000;
        let h = (beta - alpha) / n as f64;
        let (mut s0, mut s1, mut s2) = (0.0, 0.0, 0.0);
        for i in 0..=n {
            let z = alpha + i as f64 * h;
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            // Density relative to φ(α) or φ(0), whichever is larger, to avoid underflow.
            let shift = if alpha > 0.0 { alpha } else { 0.0 };
            let d = w * (-0.5 * (z * z - shift * shift)).exp();
            s0 += d;
            s1 += d * z;
            s2 += d * z * z;
        }
        let m = s1 / s0;
        (m, s2 / s0 - m * m)
    }

    #[test]
    fn closed_form_moments_match_quadrature() {
        for (a, b) in [
            (-1.0, 2.0),
            (0.5, 3.0),
            (3.0, 6.0),
            (12.0, 13.0),
            (-4.0, -1.0),
            (-0.1, 0.1),
        ] {
            let (m, v) = standard_moments(a, b);
            let (mq, vq) = simpson_moments(a, b);
            assert!((m - mq).abs() < 1e-9, "mean on [{a}, {b}]: {m} vs {mq}");
            assert!(
                (v - vq).abs() < 1e-9 * (1.0 + vq),
                "var on [{a}, {b}]: {v} vs {vq}"
            );
        }
        let (m, v) = standard_moments(f64::NEG_INFINITY, f64::INFINITY);
        assert!(m.abs() < 1e-15 && (v - 1.0).abs() < 1e-15);
        // Half-normal: mean √(2/π), variance 1 − 2/π.
        let (m, v) = standard_moments(0.0, f64::INFINITY);
        let two_over_pi = 2.0 / std::f64::consts::PI;
        assert!((m - two_over_pi.sqrt()).abs() < 1e-15 && (v - (1.0 - two_over_pi)).abs() < 1e-15);
    }

    #[test]
    fn fit_reproduces_requested_moments() {
        let cases = [
            (31.0, 21.0),
            (31.0, 25.0),
            (31.0, 25.8),
            (50.0, 5.0),
            (6.0, 0.5),
            (10.0, 4.9),
            (125.0, 70.0),
            (245.0, 4.0),
            (240.0, 9.9),
        ];
        for (mean, sd) in cases {
            let t = TruncatedNormal::fit(mean, sd, 5.0, 250.0).expect("feasible");
            let (m, s) = t.moments();
            assert!((m - mean).abs() < 1e-8 * mean, "{mean} ± {sd}: mean {m}");
            assert!((s - sd).abs() < 1e-8 * sd, "{mean} ± {sd}: sd {s}");
        }
        // The seed-000 stand needs a parent well below the threshold.
        let t = TruncatedNormal::fit(31.0, 21.0, 5.0, 250.0).expect("feasible");
        assert!((t.parent_mean() + 14.99).abs() < 0.01 && (t.parent_sd() - 40.46).abs() < 0.01);
        // Far from the bounds the parent is the request itself.
        let t = TruncatedNormal::fit(50.0, 5.0, 5.0, 250.0).expect("feasible");
        assert_eq!((t.parent_mean(), t.parent_sd()), (50.0, 5.0));
    }

    #[test]
    fn fit_rejects_infeasible_requests() {
        use TruncatedNormalError as E;
        let fit = |m, s| TruncatedNormal::fit(m, s, 5.0, 250.0);
        assert!(matches!(fit(31.0, 26.0), Err(E::SdTooLarge { limit, .. }) if limit == 26.0));
        assert!(matches!(fit(125.0, 100.0), Err(E::NoSolution { .. })));
        assert!(matches!(fit(31.0, 25.99), Err(E::NoSolution { .. })));
        assert!(matches!(fit(4.0, 1.0), Err(E::MeanOutsideBounds { .. })));
        assert!(matches!(fit(250.0, 1.0), Err(E::MeanOutsideBounds { .. })));
        assert!(matches!(
            fit(f64::NAN, 1.0),
            Err(E::InvalidParameters { .. })
        ));
        assert!(matches!(fit(30.0, -1.0), Err(E::InvalidParameters { .. })));
        assert!(matches!(
            TruncatedNormal::fit(30.0, 1.0, 40.0, 20.0),
            Err(E::InvalidBounds { .. })
        ));
        assert!(matches!(
            TruncatedNormal::from_parent(0.0, 1.0, 31.0, 40.0),
            Err(E::FarInTail { .. })
        ));
    }

    #[test]
    fn point_mass_and_unbounded_cases() {
        let t = TruncatedNormal::fit(31.0, 0.0, 5.0, 250.0).expect("point mass");
        assert_eq!(t.quantile(0.3), 31.0);
        assert_eq!(t.moments(), (31.0, 0.0));
        let t = TruncatedNormal::fit(3.0, 2.0, f64::NEG_INFINITY, f64::INFINITY).expect("plain");
        assert_eq!((t.parent_mean(), t.parent_sd()), (3.0, 2.0));
        // Only an upper bound: mirrored solve.
        let t = TruncatedNormal::fit(3.0, 0.8, f64::NEG_INFINITY, 4.0).expect("upper only");
        let (m, s) = t.moments();
        assert!((m - 3.0).abs() < 1e-9 && (s - 0.8).abs() < 1e-9);
        assert!(t.parent_mean() > 4.0);
    }

    #[test]
    fn quantile_is_monotone_and_bounded() {
        for (lo, hi, mu, sd) in [
            (5.0, 250.0, -14.99, 40.46),
            (5.0, 250.0, -528.0, 123.0),
            (1.3, f64::INFINITY, 22.87, 1.82),
            (0.0, 1.0, 0.5, 1e-3),
            (-3.0, -2.0, 10.0, 1.0),
        ] {
            let t = TruncatedNormal::from_parent(mu, sd, lo, hi).expect("valid");
            let mut previous = f64::NEG_INFINITY;
            for i in 0..=1000 {
                let x = t.quantile(i as f64 / 1000.0);
                assert!(x >= lo && x <= hi, "{x} outside [{lo}, {hi}]");
                assert!(x >= previous, "not monotone at {i}");
                previous = x;
            }
        }
    }

    #[test]
    fn quantile_inverts_the_truncated_cdf() {
        let t = TruncatedNormal::from_parent(-14.99, 40.46, 5.0, 250.0).expect("valid");
        let (a, b) = t.standard_bounds();
        let z_mass = normal::upper_tail(a) - normal::upper_tail(b);
        for u in [0.01, 0.25, 0.5, 0.9, 0.999] {
            let x = t.quantile(u);
            let z = (x - t.parent_mean()) / t.parent_sd();
            let back = (normal::upper_tail(a) - normal::upper_tail(z)) / z_mass;
            assert!((back - u).abs() < 1e-12, "u {u} back {back}");
        }
    }
}

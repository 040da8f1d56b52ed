//! The standard normal distribution: density φ, distribution function Φ, upper tail Q = 1 − Φ,
//! Mills ratio R = Q/φ and quantile Φ⁻¹, accurate to a few units in the last place across the
//! whole range (relative accuracy also far in the tails).
//!
//! Stand expansion draws DBH and heights from *truncated* normals by inverse transform
//! ([`crate::truncated_normal`]), so it needs Φ and Φ⁻¹ that stay accurate where the
//! truncation bound sits several standard deviations out. Rust's standard library has no `erf`
//! on stable, and the popular one-line approximations (Abramowitz & Stegun 26.2.17, ~10⁻⁷) are
//! far too coarse for a Newton solver, so this module implements:
//!
//! - **Centre, |x| < 2.5**: Marsaglia's series (G. Marsaglia 2004, "Evaluating the Normal
//!   Distribution", *J. Stat. Softw.* 11(4)),
//!   `Φ(x) − ½ = φ(x) · (x + x³/3 + x⁵/(3·5) + x⁷/(3·5·7) + …)`.
//!   All terms have the sign of x, so the sum has no cancellation.
//! - **Tails, |x| ≥ 2.5**: Laplace's continued fraction for the Mills ratio,
//!   `R(x) = Q(x)/φ(x) = 1/(x + 1/(x + 2/(x + 3/(x + …))))`, evaluated with the modified Lentz
//!   algorithm (≤ 70 terms at x = 2.5, 7 at x = 30). `Q(x) = φ(x)·R(x)` then keeps full
//!   *relative* accuracy until it underflows (x ≈ 38).
//! - **Quantile**: P. J. Acklam's rational approximation (2003, relative error 1.15·10⁻⁹)
//!   followed by one Halley step on the accurate Φ, which brings it to machine precision.

/// 1/√(2π).
const FRAC_1_SQRT_2PI: f64 = 0.398_942_280_401_432_7;

/// Where the centre series hands over to the tail continued fraction (in standard units).
const SERIES_LIMIT: f64 = 2.5;

/// Relative change below which the series and the continued fraction stop.
const TOLERANCE: f64 = 1e-17;

/// Iteration cap of the series and the continued fraction (never reached for finite x).
const MAX_TERMS: usize = 500;

/// Standard normal density φ(x) = exp(−x²/2)/√(2π) (dimensionless; x in standard units).
pub fn pdf(x: f64) -> f64 {
    if x.is_infinite() {
        0.0
    } else {
        FRAC_1_SQRT_2PI * (-0.5 * x * x).exp()
    }
}

/// Φ(x) − ½ for |x| < [`SERIES_LIMIT`], by Marsaglia's series.
fn centred_series(x: f64) -> f64 {
    let x2 = x * x;
    let mut term = x;
    let mut sum = x;
    let mut k = 1.0;
    for _ in 0..MAX_TERMS {
        k += 2.0;
        term *= x2 / k;
        let next = sum + term;
        if next == sum {
            break;
        }
        sum = next;
    }
    pdf(x) * sum
}

/// Mills ratio by Laplace's continued fraction, for x ≥ [`SERIES_LIMIT`] (modified Lentz).
fn mills_continued_fraction(x: f64) -> f64 {
    // f = x + 1/(x + 2/(x + 3/(x + …))); all partial terms are positive, so no zero guard.
    let mut f = x;
    let mut c = x;
    let mut d = 0.0;
    for n in 1..MAX_TERMS {
        let a = n as f64;
        d = 1.0 / (x + a * d);
        c = x + a / c;
        let delta = c * d;
        f *= delta;
        if (delta - 1.0).abs() < TOLERANCE {
            break;
        }
    }
    1.0 / f
}

/// Mills ratio R(x) = Q(x)/φ(x) for x ≥ 0 (in standard units; R(0) = √(π/2), R(x) → 1/x).
///
/// For x < 0 it is still defined but grows like exp(x²/2); it is computed directly as Q/φ.
pub fn mills_ratio(x: f64) -> f64 {
    if x.is_nan() {
        f64::NAN
    } else if x == f64::INFINITY {
        0.0
    } else if x >= SERIES_LIMIT {
        mills_continued_fraction(x)
    } else {
        upper_tail(x) / pdf(x)
    }
}

/// Upper tail Q(x) = 1 − Φ(x) = P(Z > x) (probability; x in standard units), accurate in
/// relative terms for large positive x.
pub fn upper_tail(x: f64) -> f64 {
    if x.is_nan() {
        f64::NAN
    } else if x >= SERIES_LIMIT {
        if x == f64::INFINITY {
            0.0
        } else {
            pdf(x) * mills_continued_fraction(x)
        }
    } else if x > -SERIES_LIMIT {
        0.5 - centred_series(x)
    } else {
        1.0 - upper_tail(-x)
    }
}

/// Distribution function Φ(x) = P(Z ≤ x) (probability; x in standard units), accurate in
/// relative terms for large negative x.
pub fn cdf(x: f64) -> f64 {
    upper_tail(-x)
}

/// Φ(x) − ½ (in [−½, ½]), without the cancellation of `cdf(x) − 0.5` near 0.
///
/// The probability of an interval that straddles 0 is `centred_cdf(b) − centred_cdf(a)`, a
/// sum of two terms of the same sign.
pub fn centred_cdf(x: f64) -> f64 {
    if x.is_nan() {
        f64::NAN
    } else if x.abs() < SERIES_LIMIT {
        centred_series(x)
    } else {
        (0.5 - upper_tail(x.abs())).copysign(x)
    }
}

/// Acklam's coefficients, central region numerator.
const A: [f64; 6] = [
    -3.969_683_028_665_376e1,
    2.209_460_984_245_205e2,
    -2.759_285_104_469_687e2,
    1.383_577_518_672_69e2,
    -3.066_479_806_614_716e1,
    2.506_628_277_459_239,
];
/// Acklam's coefficients, central region denominator.
const B: [f64; 5] = [
    -5.447_609_879_822_406e1,
    1.615_858_368_580_409e2,
    -1.556_989_798_598_866e2,
    6.680_131_188_771_972e1,
    -1.328_068_155_288_572e1,
];
/// Acklam's coefficients, tail numerator.
const C: [f64; 6] = [
    -7.784_894_002_430_293e-3,
    -3.223_964_580_411_365e-1,
    -2.400_758_277_161_838,
    -2.549_732_539_343_734,
    4.374_664_141_464_968,
    2.938_163_982_698_783,
];
/// Acklam's coefficients, tail denominator.
const D: [f64; 4] = [
    7.784_695_709_041_462e-3,
    3.224_671_290_700_398e-1,
    2.445_134_137_142_996,
    3.754_408_661_907_416,
];
/// Where Acklam's tail formula takes over.
const P_LOW: f64 = 0.024_25;

/// Acklam's lower-tail formula (p ≤ [`P_LOW`]).
fn acklam_lower_tail(p: f64) -> f64 {
    let q = (-2.0 * p.ln()).sqrt();
    (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
        / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
}

/// Acklam's approximation of Φ⁻¹(p), relative error ≤ 1.15·10⁻⁹.
fn acklam(p: f64) -> f64 {
    if p < P_LOW {
        acklam_lower_tail(p)
    } else if p <= 1.0 - P_LOW {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        -acklam_lower_tail(1.0 - p)
    }
}

/// Quantile Φ⁻¹(p): the x (standard units) with Φ(x) = p, for a probability p in [0, 1]
/// (−∞ at 0, +∞ at 1, NaN outside). Accurate to machine precision; for p close to 1 prefer
/// [`upper_quantile`] of 1 − p, which keeps the information p has lost.
pub fn quantile(p: f64) -> f64 {
    if p.is_nan() || !(0.0..=1.0).contains(&p) {
        return f64::NAN;
    }
    if p == 0.0 {
        return f64::NEG_INFINITY;
    }
    if p == 1.0 {
        return f64::INFINITY;
    }
    let x = acklam(p);
    // One Halley step on Φ(x) − p; Φ is evaluated in whichever tail keeps relative accuracy.
    let e = if p <= 0.5 {
        cdf(x) - p
    } else {
        (1.0 - p) - upper_tail(x)
    };
    let density = pdf(x);
    if density <= 0.0 {
        return x;
    }
    let u = e / density;
    let refined = x - u / (1.0 + 0.5 * x * u);
    if refined.is_finite() { refined } else { x }
}

/// Upper quantile Q⁻¹(q): the x (standard units) with P(Z > x) = q, for q in [0, 1].
/// Accurate for tiny q (far upper tail).
pub fn upper_quantile(q: f64) -> f64 {
    -quantile(q)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        if a == b { 0.0 } else { ((a - b) / b).abs() }
    }

    /// Reference values from mpmath (40 digits).
    const CDF_REFERENCE: [(f64, f64); 14] = [
        (-37.0, 5.725_571_222_524_577e-300),
        (-30.0, 4.906_713_927_148_187e-198),
        (-10.0, 7.619_853_024_160_526e-24),
        (-5.0, 2.866_515_718_791_939e-7),
        (-3.0, 1.349_898_031_630_094_5e-3),
        (-2.5, 6.209_665_325_776_135e-3),
        (-2.4999, 6.211_418_374_944_59e-3),
        (-1.0, 0.158_655_253_931_457_05),
        (-0.5, 0.308_537_538_725_986_9),
        (-1e-3, 0.499_601_057_786_088_94),
        (0.3, 0.617_911_422_188_952_6),
        (2.0, 0.977_249_868_051_820_8),
        (3.0, 0.998_650_101_968_369_9),
        (5.0, 0.999_999_713_348_428_1),
    ];

    #[test]
    fn cdf_matches_reference_values() {
        for (x, want) in CDF_REFERENCE {
            let got = cdf(x);
            assert!(rel(got, want) < 2e-14, "Φ({x}) = {got:e}, want {want:e}");
        }
        assert_eq!(cdf(0.0), 0.5);
        assert_eq!(cdf(f64::NEG_INFINITY), 0.0);
        assert_eq!(cdf(f64::INFINITY), 1.0);
        assert!(cdf(f64::NAN).is_nan());
    }

    #[test]
    fn upper_tail_is_relatively_accurate_far_out() {
        assert!(rel(upper_tail(10.0), 7.619_853_024_160_526e-24) < 1e-14);
        assert!(rel(upper_tail(30.0), 4.906_713_927_148_187e-198) < 1e-14);
        assert!(rel(mills_ratio(0.0), (std::f64::consts::PI / 2.0).sqrt()) < 1e-15);
        assert!(rel(mills_ratio(1e6), 1e-6) < 1e-11);
    }

    #[test]
    fn centred_cdf_has_no_cancellation_near_zero() {
        let x = 1e-9;
        assert!(rel(centred_cdf(x), x * FRAC_1_SQRT_2PI) < 1e-12);
        assert_eq!(centred_cdf(-3.0), -centred_cdf(3.0));
        assert!(rel(centred_cdf(3.0), 0.998_650_101_968_369_9 - 0.5) < 1e-15);
    }

    #[test]
    fn quantile_matches_reference_values() {
        let cases = [
            (1e-300, -37.047_096_299_361_2),
            (1e-100, -21.273_453_560_965_324),
            (1e-20, -9.262_340_089_798_408),
            (1e-5, -4.264_890_793_922_825),
            (0.01, -2.326_347_874_040_841),
            (0.024_25, -1.972_961_051_311_885),
            (0.3, -0.524_400_512_708_040_8),
            (0.7, 0.524_400_512_708_040_8),
            (0.99, 2.326_347_874_040_841),
            (0.999_999, 4.753_424_308_822_899),
        ];
        for (p, want) in cases {
            let got = quantile(p);
            // 0.999999 carries only ~10 significant digits of 1 − p.
            let tol = if p > 0.9 { 1e-9 } else { 1e-14 };
            assert!(rel(got, want) < tol, "Φ⁻¹({p}) = {got}, want {want}");
        }
        assert_eq!(quantile(0.5), 0.0);
        assert_eq!(quantile(0.0), f64::NEG_INFINITY);
        assert_eq!(quantile(1.0), f64::INFINITY);
        assert!(quantile(-0.1).is_nan() && quantile(1.1).is_nan() && quantile(f64::NAN).is_nan());
        assert!(rel(upper_quantile(1e-20), 9.262_340_089_798_408) < 1e-14);
    }

    #[test]
    fn quantile_inverts_cdf() {
        // Each direction is exact on the side where its probability keeps full precision.
        for i in 1..400 {
            let x = -12.0 + 0.06 * i as f64;
            if x <= 1.0 {
                let back = quantile(cdf(x));
                assert!(
                    (back - x).abs() < 1e-12 * (1.0 + x.abs()),
                    "x {x} back {back}"
                );
            }
            if x >= -1.0 {
                let up = upper_quantile(upper_tail(x));
                assert!((up - x).abs() < 1e-12 * (1.0 + x.abs()), "x {x} up {up}");
            }
        }
    }
}

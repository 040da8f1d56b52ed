//! Block sizes as distributions: `[rock] volume_distribution`.
//!
//! A hazard engineer's design block comes from a block-size distribution (a high percentile
//! of it), and rockfall inventories are fitted with a log-normal or a power law. Given a
//! [`VolumeDistribution`], each rock's volume is drawn from it by inverse transform: a
//! uniform u from the rock's own random stream (`Purpose::Volume`, see `rockfall-rng`) gives
//! V = F⁻¹(u), F the distribution's cumulative distribution function. The drawn volume
//! replaces the volume the other rock keys give (the nominal one); shape and density are
//! kept.
//!
//! Every volume here is in m³; every distribution is of the volume of single blocks.

use crate::{RockSpec, ScenarioError};
use rockfall_forest::normal;

/// Most values a distribution of observed volumes may list: far more than any block
/// inventory, few enough that the scenario stays a readable file.
pub const MAX_OBSERVED: usize = 100_000;

/// The smallest u the log-normal's inverse transform uses, 2⁻⁵⁴: half the step of a 53-bit
/// uniform draw, so that u = 0 (possible, once in 2⁵³ draws) still gives a finite, positive
/// volume. Symmetrically, u is taken at most 1 − 2⁻⁵⁴.
const U_EDGE: f64 = 1.0 / (1u64 << 54) as f64;

/// The distribution of the volume of single blocks, m³.
#[derive(Debug, Clone, PartialEq)]
pub enum VolumeDistribution {
    /// Log-normal: ln V is normal with median ln `median_m3` and standard deviation `sd_ln`,
    /// so V = median · exp(sd_ln · z), z standard normal; its percentile p is
    /// median · exp(sd_ln · Φ⁻¹(p)) (e.g. Johnson, Kotz & Balakrishnan 1994, *Continuous
    /// Univariate Distributions* vol. 1, ch. 14).
    LogNormal {
        /// The median volume exp(μ), m³ (> 0).
        median_m3: f64,
        /// The standard deviation σ of ln V (dimensionless, > 0).
        sd_ln: f64,
    },
    /// Bounded power law (a Pareto distribution truncated to [`min_m3`, `max_m3`]), stated
    /// as rockfall inventories are: the complementary cumulative number of blocks larger
    /// than V, N(> V) ∝ V^(−b) with b = `exponent` (Dussauge-Peisser et al. 2002,
    /// *Probabilistic approach to rock fall hazard assessment: potential of historical data
    /// analysis*, NHESS 2, 15–26, doi:10.5194/nhess-2-15-2002; Dussauge, Grasso &
    /// Helmstetter 2003, *Statistical analysis of rockfall volume distributions:
    /// implications for rockfall dynamics*, JGR 108(B6)). Truncated to [a, c] =
    /// [min, max], the cumulative distribution is F(V) = (1 − (a/V)^b) / (1 − (a/c)^b) and
    /// its inverse V = a · (1 − u (1 − (a/c)^b))^(−1/b), m³.
    ///
    /// [`min_m3`]: VolumeDistribution::PowerLaw::min_m3
    /// [`max_m3`]: VolumeDistribution::PowerLaw::max_m3
    PowerLaw {
        /// The smallest volume a, m³ (> 0).
        min_m3: f64,
        /// The largest volume c, m³ (> a).
        max_m3: f64,
        /// The exponent b of the complementary cumulative N(> V) ∝ V^(−b) (> 0; the
        /// density then falls as V^(−b−1)).
        exponent: f64,
    },
    /// Observed volumes: each rock takes one of them, each with the same probability 1/n —
    /// the inverse of the empirical distribution function F_n(V) = #{Vᵢ ≤ V}/n, so
    /// percentile p is the smallest Vᵢ with F_n(Vᵢ) ≥ p (Hyndman & Fan 1996, definition 1).
    /// Nothing is interpolated: no rock is smaller than the smallest or larger than the
    /// largest value observed.
    Observed(ObservedVolumes),
}

/// Observed block volumes, m³, kept sorted ascending.
#[derive(Debug, Clone, PartialEq)]
pub struct ObservedVolumes(Vec<f64>);

impl ObservedVolumes {
    /// The volumes `values_m3`, m³, in any order (sorted here; checked by
    /// [`VolumeDistribution::check`]).
    pub fn new(mut values_m3: Vec<f64>) -> Self {
        values_m3.sort_by(f64::total_cmp);
        ObservedVolumes(values_m3)
    }

    /// The volumes, m³, ascending.
    pub fn values_m3(&self) -> &[f64] {
        &self.0
    }

    /// The value of rank ⌈r⌉ (1-based) for a rank `r` in [0, n]: the empirical quantile at
    /// r/n; rank 0 gives the smallest value.
    fn at_rank(&self, r: f64) -> f64 {
        let n = self.0.len();
        let k = (r.ceil().max(1.0) as usize).min(n);
        self.0[k - 1]
    }
}

/// Why a volume distribution is unusable; [`VolumeDistributionError::key`] names the key of
/// `[rock] volume_distribution` at fault.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VolumeDistributionError {
    /// A parameter is not finite or not positive.
    #[error("{value} is out of range ({expected})")]
    OutOfRange {
        /// The key, e.g. `sd_ln`.
        key: &'static str,
        /// Its value.
        value: f64,
        /// The allowed range in words.
        expected: &'static str,
    },
    /// A power law whose smallest volume is not below its largest.
    #[error("min_m3 ({min_m3} m³) must be below max_m3 ({max_m3} m³)")]
    EmptyRange {
        /// The smallest volume, m³.
        min_m3: f64,
        /// The largest volume, m³.
        max_m3: f64,
    },
    /// No observed values.
    #[error("no values: list at least one")]
    NoValues,
    /// Too many observed values.
    #[error("{count} values: at most {MAX_OBSERVED}")]
    TooMany {
        /// How many were given.
        count: usize,
    },
    /// An observed value not finite or not positive.
    #[error("value {index} (from 1, ascending) is {value}: every volume is finite and > 0")]
    BadValue {
        /// 1-based rank in ascending order.
        index: usize,
        /// The value.
        value: f64,
    },
}

impl VolumeDistributionError {
    /// The key of `[rock] volume_distribution` the error is about, in its volume form
    /// (`median_m3`, `sd_ln`, `min_m3`, `max_m3`, `exponent`, `volumes_m3`).
    pub fn key(&self) -> &'static str {
        match self {
            VolumeDistributionError::OutOfRange { key, .. } => key,
            VolumeDistributionError::EmptyRange { .. } => "max_m3",
            VolumeDistributionError::NoValues
            | VolumeDistributionError::TooMany { .. }
            | VolumeDistributionError::BadValue { .. } => "volumes_m3",
        }
    }
}

/// `v` when finite and > 0, else the error naming `key`.
fn positive(key: &'static str, v: f64) -> Result<(), VolumeDistributionError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(VolumeDistributionError::OutOfRange {
            key,
            value: v,
            expected: "finite and > 0",
        })
    }
}

impl VolumeDistribution {
    /// The kind as scenario files name it: `lognormal`, `power-law`, `observed`.
    pub fn kind(&self) -> &'static str {
        match self {
            VolumeDistribution::LogNormal { .. } => "lognormal",
            VolumeDistribution::PowerLaw { .. } => "power-law",
            VolumeDistribution::Observed(_) => "observed",
        }
    }

    /// Checks the parameters: median, sd_ln, bounds and exponent finite and > 0, min < max;
    /// 1 to [`MAX_OBSERVED`] observed values, each finite and > 0.
    pub fn check(&self) -> Result<(), VolumeDistributionError> {
        match self {
            VolumeDistribution::LogNormal { median_m3, sd_ln } => {
                positive("median_m3", *median_m3)?;
                positive("sd_ln", *sd_ln)
            }
            VolumeDistribution::PowerLaw {
                min_m3,
                max_m3,
                exponent,
            } => {
                positive("min_m3", *min_m3)?;
                positive("max_m3", *max_m3)?;
                positive("exponent", *exponent)?;
                if min_m3 < max_m3 {
                    Ok(())
                } else {
                    Err(VolumeDistributionError::EmptyRange {
                        min_m3: *min_m3,
                        max_m3: *max_m3,
                    })
                }
            }
            VolumeDistribution::Observed(o) => {
                let v = o.values_m3();
                if v.is_empty() {
                    return Err(VolumeDistributionError::NoValues);
                }
                if v.len() > MAX_OBSERVED {
                    return Err(VolumeDistributionError::TooMany { count: v.len() });
                }
                match v.iter().position(|x| !(x.is_finite() && *x > 0.0)) {
                    None => Ok(()),
                    Some(i) => Err(VolumeDistributionError::BadValue {
                        index: i + 1,
                        value: v[i],
                    }),
                }
            }
        }
    }

    /// The volume at u ∈ [0, 1) of the inverse cumulative distribution function, m³: a
    /// rock's volume for its uniform draw u. Log-normal median · exp(σ Φ⁻¹(u)) with u kept
    /// within [2⁻⁵⁴, 1 − 2⁻⁵⁴]; power law a · (1 − u (1 − (a/c)^b))^(−1/b); observed the
    /// value of rank ⌈u n⌉ (the smallest for u = 0), each of the n values with probability
    /// 1/n for u uniform. Assumes a distribution that passed [`VolumeDistribution::check`].
    pub fn sample_m3(&self, u: f64) -> f64 {
        match self {
            VolumeDistribution::LogNormal { median_m3, sd_ln } => {
                let u = u.clamp(U_EDGE, 1.0 - U_EDGE);
                median_m3 * (sd_ln * normal::quantile(u)).exp()
            }
            VolumeDistribution::PowerLaw {
                min_m3,
                max_m3,
                exponent,
            } => {
                let ratio = (min_m3 / max_m3).powf(*exponent);
                let v = min_m3 * (1.0 - u * (1.0 - ratio)).powf(-1.0 / exponent);
                v.clamp(*min_m3, *max_m3)
            }
            VolumeDistribution::Observed(o) => o.at_rank(u * o.values_m3().len() as f64),
        }
    }

    /// The volume of percentile `p_pct` ∈ (0, 100), m³: the inverse cumulative distribution
    /// function at p/100 (see [`VolumeDistribution::sample_m3`]), e.g. "the 95th-percentile
    /// block". For observed values the rank ⌈p n / 100⌉ is computed from p as given, so that
    /// p = 95 of 20 values is exactly the 19th.
    pub fn percentile_m3(&self, p_pct: f64) -> f64 {
        match self {
            VolumeDistribution::Observed(o) => {
                o.at_rank(p_pct * o.values_m3().len() as f64 / 100.0)
            }
            _ => self.sample_m3(p_pct / 100.0),
        }
    }

    /// The median volume, m³ (for observed values of even count, the lower of the middle
    /// two: the empirical distribution's inverse at ½).
    pub fn median_m3(&self) -> f64 {
        match self {
            VolumeDistribution::LogNormal { median_m3, .. } => *median_m3,
            _ => self.percentile_m3(50.0),
        }
    }

    /// One line for `rockfall check`: the kind and its parameters, the median and the 5–95 %
    /// range, m³ (and kg at `density_kg_m3`, when one density holds everywhere), to three
    /// significant digits.
    pub fn describe(&self, density_kg_m3: Option<f64>) -> String {
        let s = |v: f64| crate::summary::sig_digits(v, 3);
        let what = match self {
            VolumeDistribution::LogNormal { sd_ln, .. } => {
                format!("log-normal (sd_ln {})", s(*sd_ln))
            }
            VolumeDistribution::PowerLaw {
                min_m3,
                max_m3,
                exponent,
            } => format!(
                "power law N(>V) ∝ V^-{} on {}–{} m³",
                s(*exponent),
                s(*min_m3),
                s(*max_m3)
            ),
            VolumeDistribution::Observed(o) => {
                let v = o.values_m3();
                format!(
                    "drawn from {} observed values, {}–{} m³",
                    v.len(),
                    s(v[0]),
                    s(v[v.len() - 1])
                )
            }
        };
        let median = self.median_m3();
        let mass = density_kg_m3
            .map(|rho| format!(" ({} kg)", s(median * rho)))
            .unwrap_or_default();
        format!(
            "{what}, median {} m³{mass}, 5–95 %: {}–{} m³",
            s(median),
            s(self.percentile_m3(5.0)),
            s(self.percentile_m3(95.0))
        )
    }
}

/// The rock's volume keys together: a usable `volume_distribution`, and not alongside
/// `volume_variation_percent`, which must lie in [0, 100) %.
pub(crate) fn check_rock_volume(r: &RockSpec) -> Result<(), ScenarioError> {
    let p = r.volume_variation_percent;
    if !(0.0..100.0).contains(&p) {
        return Err(ScenarioError::OutOfRange {
            parameter: "rock.volume_variation_percent".into(),
            cell: None,
            value: p,
            expected: "0 ≤ P < 100 %".into(),
        });
    }
    let Some(d) = &r.volume_distribution else {
        return Ok(());
    };
    if p > 0.0 {
        return Err(ScenarioError::invalid(
            "rock.volume_distribution",
            BOTH_KEYS.to_string(),
        ));
    }
    d.check().map_err(|e| {
        ScenarioError::invalid(
            &format!("rock.volume_distribution.{}", e.key()),
            e.to_string(),
        )
    })
}

/// Why `volume_distribution` and `volume_variation_percent` cannot go together.
pub const BOTH_KEYS: &str = "give `volume_distribution` or `volume_variation_percent`, not \
    both: the distribution gives each rock's whole volume";

#[cfg(test)]
mod tests {
    use super::*;

    /// `volume_variation_percent` out of [0, 100), or beside a distribution, is refused
    /// naming the keys; a bad distribution names its own key.
    #[test]
    fn the_volume_keys_are_checked_together() {
        let mut r = RockSpec::sphere(1.0, 2700.0);
        check_rock_volume(&r).unwrap();
        r.volume_variation_percent = 100.0;
        let e = check_rock_volume(&r).unwrap_err().to_string();
        assert!(e.contains("rock.volume_variation_percent"), "{e}");
        r.volume_variation_percent = 10.0;
        r.volume_distribution = Some(VolumeDistribution::LogNormal {
            median_m3: 0.25,
            sd_ln: 0.5,
        });
        let e = check_rock_volume(&r).unwrap_err().to_string();
        assert!(
            e.contains("rock.volume_distribution") && e.contains("volume_variation_percent"),
            "{e}"
        );
        r.volume_variation_percent = 0.0;
        check_rock_volume(&r).unwrap();
        r.volume_distribution = Some(VolumeDistribution::LogNormal {
            median_m3: 0.25,
            sd_ln: 0.0,
        });
        let e = check_rock_volume(&r).unwrap_err().to_string();
        assert!(e.starts_with("rock.volume_distribution.sd_ln: 0 "), "{e}");
    }
}

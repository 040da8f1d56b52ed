//! Axis ranges: validation of fixed ranges, fitting to the data, and tick positions.

use crate::PlotError;

/// Fraction of the data span added on each side of a fitted range.
const MARGIN: f64 = 0.05;

/// A validated range of finite `lo < hi`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Span {
    /// Low end.
    pub lo: f64,
    /// High end.
    pub hi: f64,
}

impl Span {
    /// Checks that `(lo, hi)` is finite with `lo < hi`.
    pub fn checked(what: &'static str, (lo, hi): (f64, f64)) -> Result<Self, PlotError> {
        if lo.is_finite() && hi.is_finite() && lo < hi {
            Ok(Self { lo, hi })
        } else {
            Err(PlotError::InvalidRange { what, lo, hi })
        }
    }

    /// `hi - lo`.
    pub fn width(self) -> f64 {
        self.hi - self.lo
    }

    /// The range widened symmetrically to `width` (never narrowed).
    pub fn widened_to(self, width: f64) -> Self {
        let extra = (width - self.width()).max(0.0) / 2.0;
        Self {
            lo: self.lo - extra,
            hi: self.hi + extra,
        }
    }

    /// `lo..hi`, as plotters takes it.
    pub fn range(self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

/// The fixed range if given (validated), else the range of the finite `values` with a margin.
/// With `include_zero`, a fitted range reaches zero without a margin below (bar heights).
pub(crate) fn fit(
    what: &'static str,
    fixed: Option<(f64, f64)>,
    values: impl IntoIterator<Item = f64>,
    include_zero: bool,
) -> Result<Span, PlotError> {
    if let Some(r) = fixed {
        return Span::checked(what, r);
    }
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return Ok(Span { lo: 0.0, hi: 1.0 });
    }
    let pad = if hi > lo {
        (hi - lo) * MARGIN
    } else {
        (lo.abs() * MARGIN).max(0.5)
    };
    let span = Span {
        lo: lo - pad,
        hi: hi + pad,
    };
    Ok(if include_zero && lo >= 0.0 {
        Span { lo: 0.0, ..span }
    } else {
        span
    })
}

/// About `target` "nice" tick positions (1, 2 or 5 × 10^k apart) inside `[lo, hi]`.
pub(crate) fn nice_ticks(span: Span, target: usize) -> Vec<f64> {
    let step = nice_step(span.width() / target.max(1) as f64);
    let first = (span.lo / step).ceil() as i64;
    let last = (span.hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// The smallest round step, 1, 2 or 5 × 10^k, at least `raw` (`raw` finite and > 0; other
/// values give NaN). Used for tick spacing and for bin widths.
pub fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return f64::NAN;
    }
    let magnitude = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * magnitude)
        .find(|s| *s >= raw * (1.0 - 1e-12))
        .unwrap_or(10.0 * magnitude)
}

/// Tick positions in `log10` units for a logarithmic scale over `span` (also `log10` units):
/// the decades inside it; 1, 2 and 5 times the decades when fewer than two decades fall
/// inside; linear nice ticks when even those are fewer than two.
pub(crate) fn log_ticks(span: Span) -> Vec<f64> {
    let first = span.lo.floor() as i64;
    let last = span.hi.ceil() as i64;
    let inside = |t: &f64| *t >= span.lo - 1e-9 && *t <= span.hi + 1e-9;
    let decades: Vec<f64> = (first..=last).map(|k| k as f64).filter(inside).collect();
    if decades.len() >= 2 {
        return decades;
    }
    let mantissas: Vec<f64> = (first..=last)
        .flat_map(|k| [1.0f64, 2.0, 5.0].map(|m| k as f64 + m.log10()))
        .filter(inside)
        .collect();
    if mantissas.len() >= 2 {
        return mantissas;
    }
    let linear = Span {
        lo: 10f64.powf(span.lo),
        hi: 10f64.powf(span.hi),
    };
    nice_ticks(linear, 4).into_iter().map(f64::log10).collect()
}

/// A tick label: short, without float noise; exponent form below 0.001 and from 10^15 on, so
/// that large map coordinates (e.g. 2600000) keep all their digits.
pub(crate) fn format_tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 {
            "0".to_owned()
        } else {
            v.to_string()
        };
    }
    if (1e-3..1e15).contains(&v.abs()) {
        let s = format!("{v:.6}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        return if s == "-0" {
            "0".to_owned()
        } else {
            s.to_owned()
        };
    }
    let s = format!("{v:.3e}");
    match s.split_once('e') {
        Some((mantissa, exp)) => {
            let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
            format!("{mantissa}e{exp}")
        }
        None => s,
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn fixed_ranges_are_validated() {
        assert!(fit("x range", Some((1.0, 1.0)), [], false).is_err());
        assert!(fit("x range", Some((2.0, 1.0)), [], false).is_err());
        assert!(fit("x range", Some((0.0, f64::NAN)), [], false).is_err());
        assert_eq!(
            fit("x range", Some((0.0, 2.0)), [], false).unwrap(),
            Span { lo: 0.0, hi: 2.0 }
        );
    }

    #[test]
    fn fitted_ranges_skip_non_finite_and_pad() {
        let s = fit("x", None, [0.0, f64::NAN, 10.0, f64::INFINITY], false).unwrap();
        assert_eq!(s, Span { lo: -0.5, hi: 10.5 });
        let s = fit("x", None, [3.0, 3.0], false).unwrap();
        assert!(s.lo < 3.0 && s.hi > 3.0);
        assert_eq!(
            fit("x", None, [f64::NAN], false).unwrap(),
            Span { lo: 0.0, hi: 1.0 }
        );
        assert_eq!(fit("y", None, [2.0, 10.0], true).unwrap().lo, 0.0);
    }

    #[test]
    fn ticks_are_nice() {
        assert_eq!(
            nice_ticks(Span { lo: 0.0, hi: 10.0 }, 5),
            [0.0, 2.0, 4.0, 6.0, 8.0, 10.0]
        );
        assert_eq!(log_ticks(Span { lo: 0.0, hi: 3.0 }), [0.0, 1.0, 2.0, 3.0]);
        assert_eq!(log_ticks(Span { lo: 0.1, hi: 0.9 }).len(), 2);
        assert!(log_ticks(Span { lo: 0.32, hi: 0.6 }).len() >= 2);
        assert_eq!(format_tick(0.30000000000000004), "0.3");
        assert_eq!(format_tick(2_600_100.0), "2600100");
        assert_eq!(format_tick(1e-4), "1e-4");
        assert_eq!(format_tick(2.5e-5), "2.5e-5");
        assert_eq!(format_tick(3e20), "3e20");
        assert_eq!(format_tick(-2.5), "-2.5");
    }
}

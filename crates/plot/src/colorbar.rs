//! Value-to-colour scales and the colour bar that explains them.

use plotters::prelude::{BLACK, FontTransform, PathElement, Rectangle, Text};
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::font::{LABEL_SIZE, TICK_SIZE, font};
use crate::layout::Area;
use crate::palette::rgb;
use crate::range::{Span, format_tick, log_ticks, nice_ticks};
use crate::{ColorScale, PlotError, Ramp};

/// Left edge (px) of the bar within its strip.
const BAR_LEFT: i32 = 14;
/// Width (px) of the bar.
const BAR_WIDTH: i32 = 28;
/// Length (px) of a tick mark.
const TICK_LENGTH: i32 = 6;
/// Distance (px) of the scale's label from the strip's right edge.
const LABEL_INSET: i32 = 22;

/// A validated [`ColorScale`], in the units colours are interpolated in (`log10` for a log
/// scale), with its ramp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ValueScale {
    /// The scale's extent, in interpolation units.
    span: Span,
    /// Whether values are mapped through `log10`.
    log: bool,
    /// The colour ramp.
    pub ramp: Ramp,
}

impl ValueScale {
    /// Checks a [`ColorScale`]: finite `min < max`, and `min > 0` on a log scale.
    pub fn new(scale: &ColorScale) -> Result<Self, PlotError> {
        let span = Span::checked("colour scale", (scale.min, scale.max))?;
        let ramp = scale.ramp;
        if !scale.log {
            return Ok(Self {
                span,
                log: false,
                ramp,
            });
        }
        if scale.min <= 0.0 {
            return Err(PlotError::LogScaleNotPositive { min: scale.min });
        }
        let span = Span::checked("colour scale", (scale.min.log10(), scale.max.log10()))?;
        Ok(Self {
            span,
            log: true,
            ramp,
        })
    }

    /// Where `value` falls on the scale, clamped to `[0, 1]`; `None` if it is not finite.
    pub fn fraction(&self, value: f64) -> Option<f64> {
        if !value.is_finite() {
            return None;
        }
        let v = match (self.log, value > 0.0) {
            (false, _) => value,
            (true, true) => value.log10(),
            (true, false) => self.span.lo,
        };
        Some(((v - self.span.lo) / self.span.width()).clamp(0.0, 1.0))
    }

    /// The colour of `value` on the scale's ramp; `None` if it is not finite.
    pub fn color(&self, value: f64) -> Option<(u8, u8, u8)> {
        self.fraction(value).map(|f| self.ramp.at(f))
    }

    /// Tick positions as fractions of the scale, with their labels.
    fn ticks(&self) -> Vec<(f64, String)> {
        let (positions, value): (Vec<f64>, fn(f64) -> f64) = if self.log {
            (log_ticks(self.span), |t| 10f64.powf(t))
        } else {
            (nice_ticks(self.span, 6), |t| t)
        };
        positions
            .into_iter()
            .map(|t| {
                (
                    (t - self.span.lo) / self.span.width(),
                    format_tick(value(t)),
                )
            })
            .collect()
    }
}

/// Draws the colour bar of `scale`, in its ramp, in `strip`, spanning pixel rows `rows` (top,
/// bottom exclusive) so that it lines up with the plotting windows, with ticks and `label`.
pub(crate) fn draw_color_bar(
    strip: &Area<'_>,
    scale: &ValueScale,
    label: &str,
    (top, bottom): (i32, i32),
) -> Result<(), PlotError> {
    let right = BAR_LEFT + BAR_WIDTH - 1;
    let row_of = |f: f64| bottom - 1 - (f * f64::from(bottom - 1 - top)).round() as i32;
    for y in top..bottom {
        let f = f64::from(bottom - 1 - y) / f64::from((bottom - 1 - top).max(1));
        let row = vec![(BAR_LEFT, y), (right, y)];
        strip.draw(&PathElement::new(row, rgb(scale.ramp.at(f))))?;
    }
    let frame = [(BAR_LEFT - 1, top - 1), (right + 1, bottom)];
    strip.draw(&Rectangle::new(frame, BLACK))?;
    let tick_style = font(TICK_SIZE)
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    for (f, text) in scale.ticks() {
        let y = row_of(f);
        let tick = vec![(right + 1, y), (right + 1 + TICK_LENGTH, y)];
        strip.draw(&PathElement::new(tick, BLACK))?;
        strip.draw(&Text::new(
            text,
            (right + TICK_LENGTH + 4, y),
            tick_style.clone(),
        ))?;
    }
    let (width, _) = strip.dim_in_pixel();
    let label_style = font(LABEL_SIZE)
        .transform(FontTransform::Rotate270)
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Center));
    let centre = (width as i32 - LABEL_INSET, (top + bottom) / 2);
    strip.draw(&Text::new(label, centre, label_style))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn scale(min: f64, max: f64, log: bool) -> ColorScale {
        ColorScale {
            label: String::new(),
            min,
            max,
            log,
            ramp: Ramp::Viridis,
        }
    }

    #[test]
    fn scales_are_validated() {
        assert!(ValueScale::new(&scale(1.0, 1.0, false)).is_err());
        assert!(ValueScale::new(&scale(2.0, 1.0, false)).is_err());
        assert!(ValueScale::new(&scale(f64::NAN, 1.0, false)).is_err());
        assert!(matches!(
            ValueScale::new(&scale(0.0, 1.0, true)),
            Err(PlotError::LogScaleNotPositive { .. })
        ));
    }

    #[test]
    fn values_map_to_clamped_fractions() {
        let lin = ValueScale::new(&scale(0.0, 10.0, false)).unwrap();
        assert_eq!(lin.fraction(5.0), Some(0.5));
        assert_eq!(lin.fraction(-3.0), Some(0.0));
        assert_eq!(lin.fraction(30.0), Some(1.0));
        assert_eq!(lin.fraction(f64::NAN), None);
        let log = ValueScale::new(&scale(1.0, 1000.0, true)).unwrap();
        assert!((log.fraction(10.0).unwrap() - 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(log.fraction(-1.0), Some(0.0));
        let labels: Vec<String> = log.ticks().into_iter().map(|t| t.1).collect();
        assert_eq!(labels, ["1", "10", "100", "1000"]);
    }
}

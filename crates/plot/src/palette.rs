//! Colours: the series palette (Okabe–Ito) and the default value colour map (viridis).

use plotters::style::RGBColor;

use crate::Ramp;

/// The Okabe–Ito colour-blind-safe palette (Okabe & Ito 2008), ordered so that the first
/// colours contrast most on white; black, the colour of axes and text, comes last.
const OKABE_ITO: [(u8, u8, u8); 8] = [
    (0x00, 0x72, 0xB2), // blue
    (0xD5, 0x5E, 0x00), // vermillion
    (0x00, 0x9E, 0x73), // bluish green
    (0xE6, 0x9F, 0x00), // orange
    (0x56, 0xB4, 0xE9), // sky blue
    (0xCC, 0x79, 0xA7), // reddish purple
    (0xF0, 0xE4, 0x42), // yellow
    (0x00, 0x00, 0x00), // black
];

/// Colour `i` of the series palette as `(r, g, b)`: the eight Okabe–Ito colour-blind-safe
/// colours (blue, vermillion, bluish green, orange, sky blue, reddish purple, yellow, black);
/// the index wraps. Returned as a plain tuple to keep plotters out of the public API.
pub fn series_color(i: usize) -> (u8, u8, u8) {
    OKABE_ITO[i % OKABE_ITO.len()]
}

/// The viridis colour map at `t` in `[0, 1]` (clamped; NaN gives the low end) as `(r, g, b)`:
/// [`Ramp::Viridis`]`.at(t)`, the colour of a value at fraction `t` of a [`crate::ColorScale`]
/// with the default ramp.
pub fn colormap(t: f64) -> (u8, u8, u8) {
    Ramp::Viridis.at(t)
}

/// [`series_color`] as a plotters colour.
pub(crate) fn series_rgb(i: usize) -> RGBColor {
    rgb(series_color(i))
}

/// A tuple as a plotters colour.
pub(crate) fn rgb((r, g, b): (u8, u8, u8)) -> RGBColor {
    RGBColor(r, g, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn palette_wraps_and_viridis_runs_dark_purple_to_yellow() {
        assert_eq!(series_color(0), series_color(8));
        assert_ne!(series_color(0), series_color(1));
        let (r0, g0, b0) = colormap(0.0);
        let (r1, g1, b1) = colormap(1.0);
        assert!(r0 < 90 && g0 < 20 && b0 > 60, "{:?}", colormap(0.0));
        assert!(r1 > 230 && g1 > 210 && b1 < 60, "{:?}", colormap(1.0));
        assert_eq!(colormap(-1.0), colormap(0.0));
        assert_eq!(colormap(f64::NAN), colormap(0.0));
    }
}

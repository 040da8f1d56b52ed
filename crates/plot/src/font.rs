//! The embedded font (DejaVu Sans, see `assets/DejaVuSans-LICENSE.txt`) and the text styles.

use std::sync::OnceLock;

use plotters::style::{FontDesc, FontFamily, FontStyle, IntoFont, register_font};

use crate::PlotError;

/// Family name under which the embedded font is registered and which every text style uses.
const FAMILY: &str = "rockfall-dejavu-sans";

/// The font file, embedded in the library.
const DEJAVU_SANS: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Registers the embedded font with plotters, once per process.
pub(crate) fn ensure_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok =
        *REGISTERED.get_or_init(|| register_font(FAMILY, FontStyle::Normal, DEJAVU_SANS).is_ok());
    if ok { Ok(()) } else { Err(PlotError::Font) }
}

/// The embedded font at `size` pixels.
pub(crate) fn font(size: f64) -> FontDesc<'static> {
    FontFamily::Name(FAMILY).into_font().resize(size)
}

/// Figure title size.
pub(crate) const TITLE_SIZE: f64 = 26.0;
/// Panel title size.
pub(crate) const PANEL_TITLE_SIZE: f64 = 20.0;
/// Axis label size.
pub(crate) const LABEL_SIZE: f64 = 18.0;
/// Tick label and legend size.
pub(crate) const TICK_SIZE: f64 = 15.0;

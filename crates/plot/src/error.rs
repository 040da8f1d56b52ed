//! The crate's error type.

use std::path::PathBuf;

/// Why a figure could not be drawn or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlotError {
    /// The figure file (or its temporary sibling) could not be written.
    #[error("cannot write figure {}: {source}", path.display())]
    Io {
        /// The figure's target path.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// The rendered image could not be encoded as PNG.
    #[error("cannot encode figure {} as PNG: {message}", path.display())]
    Encode {
        /// The figure's target path.
        path: PathBuf,
        /// The encoder's message.
        message: String,
    },
    /// Drawing into the in-memory image failed.
    #[error("cannot draw figure: {0}")]
    Draw(String),
    /// The embedded font could not be loaded.
    #[error("cannot load the embedded font")]
    Font,
    /// A figure needs at least one panel.
    #[error("nothing to draw: no panels")]
    NoPanels,
    /// A histogram needs at least one set of bars.
    #[error("nothing to draw: no bar sets")]
    NoBars,
    /// A range (axis or colour scale) is not finite with `lo < hi`.
    #[error("invalid {what} ({lo}, {hi}): needs finite lo < hi")]
    InvalidRange {
        /// Which range: `"x range"`, `"y range"`, `"colour scale"`, `"map x extent"` or
        /// `"map y extent"`.
        what: &'static str,
        /// Low end as given.
        lo: f64,
        /// High end as given.
        hi: f64,
    },
    /// A logarithmic colour scale must start above zero.
    #[error("invalid logarithmic colour scale: min {min} must be > 0")]
    LogScaleNotPositive {
        /// The scale's minimum as given.
        min: f64,
    },
    /// A map's release cells need a finite, positive cell size.
    #[error("invalid release cell size {cell_size_m} m: needs finite and > 0")]
    InvalidCellSize {
        /// The cell size as given (m).
        cell_size_m: f64,
    },
    /// A polyline has not one value per point.
    #[error(
        "polyline {line} of panel {panel} has {points} points but {values} values (need one value per point)"
    )]
    LengthMismatch {
        /// Index of the panel.
        panel: usize,
        /// Index of the polyline in its panel.
        line: usize,
        /// Number of points.
        points: usize,
        /// Number of values.
        values: usize,
    },
}

impl<E: std::error::Error + Send + Sync> From<plotters::drawing::DrawingAreaErrorKind<E>>
    for PlotError
{
    fn from(e: plotters::drawing::DrawingAreaErrorKind<E>) -> Self {
        Self::Draw(e.to_string())
    }
}

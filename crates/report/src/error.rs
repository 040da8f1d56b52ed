//! What can go wrong writing the report and its GIS files.

use std::path::PathBuf;

use rockfall_plot::PlotError;

/// An error writing the report, its figures or its GIS files; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A file could not be written or read back.
    #[error("{path}: {source}", path = path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// A figure could not be drawn or written (the error names the file).
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// The run's rasters, summary or CSV files could not be written (the error names the
    /// file).
    #[error(transparent)]
    Results(#[from] rockfall_results::ResultsError),
    /// A raster of the report (the DEM under the QGIS project) could not be written (the
    /// error names the file).
    #[error(transparent)]
    Raster(#[from] rockfall_raster::RasterError),
}

impl From<(PathBuf, std::io::Error)> for ReportError {
    fn from((path, source): (PathBuf, std::io::Error)) -> Self {
        ReportError::Io { path, source }
    }
}

use rockfall_raster::GeometryMismatch;

/// Problems building a terrain. Parameter names are the scenario / Rockyfor3D names
/// (`soiltype`, `rg70`, …) so that the caller can point at the file.
#[derive(Debug, thiserror::Error)]
pub enum TerrainError {
    /// The DEM is too small to form a surface.
    #[error("DEM has {ncols} columns × {nrows} rows; at least 2 × 2 cells are needed")]
    TooSmall {
        /// Columns.
        ncols: usize,
        /// Rows.
        nrows: usize,
    },
    /// Every DEM cell is nodata.
    #[error("DEM holds no data (every cell is nodata)")]
    NoData,
    /// A parameter raster is not on the DEM's grid.
    #[error("{parameter}: {mismatch}")]
    Misaligned {
        /// Parameter name.
        parameter: String,
        /// How it differs.
        mismatch: GeometryMismatch,
    },
    /// A parameter value is out of its range.
    #[error("{parameter}: value {value} at row {row}, column {col} is out of range ({expected})")]
    OutOfRange {
        /// Parameter name.
        parameter: String,
        /// 0-based row from the north.
        row: usize,
        /// 0-based column from the west.
        col: usize,
        /// The value found.
        value: f64,
        /// The allowed range in words.
        expected: String,
    },
}

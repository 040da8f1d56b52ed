//! The crate's error type.

use crate::truncated_normal::TruncatedNormalError;

/// Everything that can go wrong building stems, stands and indexes. Variants carry the
/// offending values and, for stands, the grid cell (row 0 north, column 0 west).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ForestError {
    /// A stem failed [`crate::Stem::validate`].
    #[error("stem {index}: {reason}")]
    InvalidStem {
        /// Position of the stem in the list given.
        index: usize,
        /// What is wrong, with the value.
        reason: String,
    },
    /// A stand cell holds a value outside its valid range.
    #[error("stand cell (row {row}, column {col}): {field} = {value} {requirement}")]
    InvalidStand {
        /// Grid row of the cell (0 = north).
        row: usize,
        /// Grid column of the cell (0 = west).
        col: usize,
        /// Name of the offending field (`"stems_per_ha"`, `"dbh_sd_cm"`, …).
        field: &'static str,
        /// The offending value (field's units).
        value: f64,
        /// What the value must satisfy, e.g. `"must be finite and ≥ 0"`.
        requirement: &'static str,
    },
    /// No truncated normal on [min, max] has the cell's DBH mean and sd.
    #[error(
        "stand cell (row {row}, column {col}): no DBH distribution on [{min_cm}, {max_cm}] cm \
         has mean {mean_cm} cm and sd {sd_cm} cm: {cause}"
    )]
    InfeasibleDbh {
        /// Grid row of the cell (0 = north).
        row: usize,
        /// Grid column of the cell (0 = west).
        col: usize,
        /// Requested mean DBH, cm.
        mean_cm: f64,
        /// Requested DBH standard deviation, cm.
        sd_cm: f64,
        /// Smallest DBH generated ([`crate::StandOptions::dbh_min_cm`]), cm.
        min_cm: f64,
        /// Largest DBH generated ([`crate::StandOptions::dbh_max_cm`]), cm.
        max_cm: f64,
        /// Why the fit failed.
        #[source]
        cause: TruncatedNormalError,
    },
    /// The DBH bounds of [`crate::StandOptions`] are unusable.
    #[error(
        "DBH bounds [{min_cm}, {max_cm}] cm are invalid: need 0 < min < max, min finite \
         (max may be infinite)"
    )]
    InvalidDbhBounds {
        /// Lower bound given, cm.
        min_cm: f64,
        /// Upper bound given, cm.
        max_cm: f64,
    },
    /// The stand grid's geometry is unusable (non-finite origin, cell size not > 0).
    #[error(
        "stand grid geometry is invalid: origin ({x_min_m}, {y_min_m}) m, cell size {cell_size_m} m"
    )]
    InvalidGeometry {
        /// Western edge, m.
        x_min_m: f64,
        /// Southern edge, m.
        y_min_m: f64,
        /// Cell edge length, m.
        cell_size_m: f64,
    },
    /// The bucket size of a [`crate::StemIndex`] is not finite and > 0.
    #[error("index bucket size {bucket_size_m} m must be finite and > 0")]
    InvalidBucketSize {
        /// The size given, m.
        bucket_size_m: f64,
    },
    /// The stems spread over an extent too large to represent.
    #[error("stems spread over {width_m} × {height_m} m, too large to index")]
    ExtentTooLarge {
        /// East–west extent, m.
        width_m: f64,
        /// North–south extent, m.
        height_m: f64,
    },
}

use rockfall_forest::ForestError;
use rockfall_raster::GeometryMismatch;
use rockfall_terrain::TerrainError;

/// A scenario that cannot be simulated. Parameters are named as in the scenario file
/// (`rock.density_kg_m3`) or the Rockyfor3D folder (`rockdensity`); see
/// [`ScenarioError::parameter`] to look up the file in `Scenario::sources`.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// DEM or surface parameters.
    #[error(transparent)]
    Terrain(#[from] TerrainError),
    /// A raster parameter not on the DEM's grid.
    #[error("{parameter}: {mismatch}")]
    Misaligned {
        /// Parameter name.
        parameter: String,
        /// How it differs.
        mismatch: GeometryMismatch,
    },
    /// A value out of range, in a cell (rasters) or as a whole (constants).
    #[error("{parameter}: value {value}{} is out of range ({expected})", cell_text(*.cell))]
    OutOfRange {
        /// Parameter name.
        parameter: String,
        /// (row, col) of the cell, for rasters.
        cell: Option<(usize, usize)>,
        /// The value.
        value: f64,
        /// The allowed range in words.
        expected: String,
    },
    /// Something else wrong with a parameter.
    #[error("{parameter}: {message}")]
    Invalid {
        /// Parameter name.
        parameter: String,
        /// What is wrong.
        message: String,
    },
    /// No release cell and no release point.
    #[error("no release cell and no release point: nothing to simulate ({hint})")]
    NoRelease {
        /// Where release cells were expected.
        hint: String,
    },
    /// The forest could not be built.
    #[error("forest: {0}")]
    Forest(#[from] ForestError),
}

fn cell_text(cell: Option<(usize, usize)>) -> String {
    cell.map(|(r, c)| format!(" at row {r}, column {c}"))
        .unwrap_or_default()
}

impl ScenarioError {
    /// The parameter the error is about, when there is one.
    pub fn parameter(&self) -> Option<&str> {
        match self {
            ScenarioError::Terrain(
                TerrainError::Misaligned { parameter, .. }
                | TerrainError::OutOfRange { parameter, .. },
            ) => Some(parameter),
            ScenarioError::Terrain(_) => Some("dem"),
            ScenarioError::Misaligned { parameter, .. }
            | ScenarioError::OutOfRange { parameter, .. }
            | ScenarioError::Invalid { parameter, .. } => Some(parameter),
            ScenarioError::NoRelease { .. } | ScenarioError::Forest(_) => None,
        }
    }

    pub(crate) fn invalid(parameter: &str, message: impl Into<String>) -> Self {
        ScenarioError::Invalid {
            parameter: parameter.into(),
            message: message.into(),
        }
    }
}

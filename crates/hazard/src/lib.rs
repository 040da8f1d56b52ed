//! Hazard zone maps from rockfall runs.
//!
//! A hazard engineer's deliverable is a zone map: each cell classified by crossing the
//! **intensity** of the process (the kinetic energy of the blocks reaching it) with its
//! **probability** (the return period of such events), by the matrix of a national
//! guideline ([`Matrix::swiss`], [`Matrix::austria`], or a matrix file).
//!
//! Two modes ([`Mode`]):
//! - **scenario mode** (Swiss practice): each scenario is a run of the block of one return
//!   period; a cell reached in it ([`ReachRule`]) takes the class of its intensity raster
//!   (default `E_95`) and the scenario's return period, and the map is the highest class over
//!   the scenarios ([`Class::max`]);
//! - **frequency mode**: each scenario is a release with an onset frequency f (1/year); the
//!   annual frequency of a block above e kJ passing cell x is
//!   λ(x, e) = Σ f · N_pass(x, E > e) / N_sim (the runs' `Nr_rocks_above_<e>kJ` and
//!   `Reach_probability`), and each intensity class is placed at T = 1/λ at its floor.
//!
//! [`build`] reads finished run folders into a [`HazardMap`]; [`outputs`] writes the
//! rasters, styles and `hazard.json`; [`zones`] the polygons.

pub mod adapt;
pub mod build;
pub mod classify;
pub mod deliver;
pub mod error;
pub mod hazard_file;
pub mod level;
pub mod matrix;
mod matrix_check;
pub mod matrix_file;
pub mod outputs;
pub mod runner;
pub mod runs;
pub mod zones;

pub use build::{HazardMap, ScenarioLayer, build};
pub use classify::{ReachRule, ScenarioMaps, SourceMaps, classify_frequency, classify_scenario};
pub use deliver::{Relief, write_all};
pub use error::HazardError;
pub use hazard_file::{
    HazardSpec, Mode, ScenarioEntry, Source, parse_hazard_file, read_hazard_file,
};
pub use level::Level;
pub use matrix::{Class, Colours, FieldLevel, Matrix, MatrixError};
pub use matrix_file::parse_matrix;

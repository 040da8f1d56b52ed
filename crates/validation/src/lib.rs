//! The published-experiment cases of `rockfall validate`.
//!
//! - Seed 000 (Dorren et al. 2006) tables 2 and 3: the observed figures of the Vaujany
//!   experiments ([`observed`]), the same quantities computed from a run of the built-in
//!   sites exactly as §2.6 defines them ([`measure`]), the error of each (eq. 5) and the RMSE
//!   of each case and group (eq. 6, [`metrics`], [`case`]); each table 3 screen is a case of
//!   its own (`vaujany-site1/screen-185m`, `…/screen-235m`) with the paper's mean and max
//!   groups.
//! - Seed 001 §3.4: the forest-slope runs of three rock shapes, whose findings (fig. 6) are
//!   checked rather than measured ([`shapes`]).
//! - Beside the paper's protocol, a fair comparison ([`fair`]): each maximum also over groups
//!   of the observed sample size, each observed share with its 95 % interval, and
//!   `rmse_pct_fair` from the median group maxima.
//! - Outputs: the terminal table, `validation.json`, `validation.md` ([`report`]) and the
//!   fig. 2 histogram ([`figure`]).
//!
//! [`run::run_validation`] runs it all through the driver (`rockfall_sim`), each run written
//! as a run folder, and [`sensitivity`] reruns each site with one unknown of the
//! reconstruction or one rule of ours moved; the comparisons work on run summaries
//! (`rockfall_results::Summary`, as in `summary.json`), per-rock records and slope-study statistics.

pub mod case;
pub mod crossval;
pub mod fair;
pub mod figure;
pub mod lab;
pub mod measure;
pub mod metrics;
pub mod observed;
pub mod ramp;
pub mod report;
pub mod run;
pub mod sensitivity;
pub mod shapes;

pub use case::{CaseReport, Check, GroupRmse, Row};
pub use observed::{Published, published};
pub use report::{Meta, SensitivityRow};

use std::path::{Path, PathBuf};

/// What can go wrong writing the validation's outputs.
#[derive(Debug, thiserror::Error)]
pub enum ValidationError {
    /// Writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Writing JSON failed.
    #[error(transparent)]
    Results(#[from] rockfall_results::ResultsError),
    /// Drawing a figure failed.
    #[error("figure: {0}")]
    Plot(String),
    /// Nothing to draw or compare.
    #[error("{0}")]
    Empty(String),
    /// A case the validation does not know (bad input).
    #[error("{0}")]
    UnknownCase(String),
    /// A built-in site cannot be built.
    #[error(transparent)]
    Site(#[from] rockfall_sites::SiteError),
    /// A run cannot start or failed.
    #[error(transparent)]
    Sim(#[from] rockfall_sim::SimError),
    /// A cross-validation fold's calibration failed.
    #[error("calibration: {0}")]
    Calibration(String),
    /// A run's outputs could not be written.
    #[error(transparent)]
    Report(#[from] rockfall_report::ReportError),
    /// The shape study failed.
    #[error(transparent)]
    Lab(#[from] rockfall_lab::LabError),
}

impl ValidationError {
    /// True when the input is at fault (an unknown case), false for an internal failure:
    /// every other input of a validation is built in.
    pub fn is_bad_input(&self) -> bool {
        matches!(self, ValidationError::UnknownCase(_))
    }
}

/// Writes `validation.json` and `validation.md` into `out_dir` (atomically); returns their
/// paths.
pub fn write_reports(
    out_dir: &Path,
    cases: &[CaseReport],
    meta: &Meta,
) -> Result<Vec<PathBuf>, ValidationError> {
    std::fs::create_dir_all(out_dir).map_err(|e| ValidationError::Io {
        path: out_dir.to_path_buf(),
        source: e,
    })?;
    let json_path = out_dir.join("validation.json");
    rockfall_results::write_json(&json_path, &report::validation_json(cases, meta))?;
    let md_path = out_dir.join("validation.md");
    let md = report::markdown(cases, meta);
    rockfall_raster::atomic::write_bytes_atomic(&md_path, md.as_bytes())
        .map_err(|(path, source)| ValidationError::Io { path, source })?;
    Ok(vec![json_path, md_path])
}

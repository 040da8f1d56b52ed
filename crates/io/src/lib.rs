//! Reading and writing rockfall inputs.
//!
//! - [`load`]: a Rockyfor3D input folder ([`rockyfor`]) or a scenario file
//!   ([`scenario_file`], TOML) → a validated
//!   [`rockfall_scenario::Scenario`].
//! - [`trees`]: tree lists (CSV and the Rockyfor3D tree file).
//! - [`shape`]: rock point clouds and meshes (`.xyz`, `.csv`, `.txt`, `.obj`, `.ply`, `.stl`)
//!   → points; a scenario's rock file is read as the scenario is, so that the engines get
//!   points, never a path.
//! - [`schema_doc`]: the scenario file's JSON Schema and Markdown key reference, generated
//!   from the structures that read it (`rockfall schema`).
//! - [`write`]: a scenario written back as input files (rasters, tree list, scenario file,
//!   and the Rockyfor3D file set where the scenario fits it) — how `rockfall site` exports
//!   the built-in sites.
//!
//! Every error is an [`InputError`] naming the file and, where it applies, the line, the cell
//! or the key. Nothing here panics on bad input.

mod contact_file;
mod error;
mod nets;
pub mod rockyfor;
pub mod scenario_file;
mod schema;
pub mod schema_doc;
pub mod shape;
pub mod tile_index;
pub mod trees;
pub mod vector;
mod volume_distribution;
pub mod write;

pub use error::InputError;

use rockfall_scenario::{Scenario, ScenarioError};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Reads an input: a folder is a Rockyfor3D input folder, a `.toml` file a scenario file.
pub fn load(path: &Path) -> Result<Scenario, InputError> {
    if path.is_dir() {
        return rockyfor::read_folder(path);
    }
    load_kind(path)?;
    scenario_file::read_scenario(path)
}

/// The region's grid: the grid of the DEM `path` (a scenario file or a Rockyfor3D folder)
/// names, from its header where it can (a Rockyfor3D folder is read whole).
pub fn region_geometry(path: &Path) -> Result<rockfall_raster::GridGeometry, InputError> {
    if path.is_dir() || !path.exists() {
        return Ok(*load(path)?.terrain.dem.geometry());
    }
    scenario_file::read_dem_geometry(path)
}

/// [`load`] as the spatial tile of its region released from the cells of `core`, its grids
/// holding `window` (see [`rockfall_scenario::Scenario::tile`]): a scenario file's rasters
/// are read over the window only; a Rockyfor3D folder (ASCII grids) is read whole and cut.
///
/// `counts` are a tile index's counts of the release raster (see
/// [`scenario_file::read_scenario_tile`]); returned with the scenario: the release raster's
/// counts when it was scanned whole.
pub fn load_tile(
    path: &Path,
    core: rockfall_raster::Window,
    window: rockfall_raster::Window,
    counts: Option<std::sync::Arc<tile_index::ReleaseCounts>>,
) -> Result<(Scenario, Option<tile_index::ReleaseCounts>), InputError> {
    if path.is_dir() {
        let mut s = rockyfor::read_folder(path)?;
        s.cut_to_tile(core, window)
            .map_err(|e| scenario_error(e, &s.sources, path))?;
        return Ok((s, None));
    }
    load_kind(path)?;
    scenario_file::read_scenario_tile(path, core, window, counts)
}

/// Checks that `path` is a scenario file (the errors of [`load`] otherwise).
fn load_kind(path: &Path) -> Result<(), InputError> {
    if !path.exists() {
        return Err(InputError::Missing {
            path: path.to_path_buf(),
            what: "input (a scenario .toml file or a Rockyfor3D input folder)".into(),
        });
    }
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("toml") => Ok(()),
        _ => Err(InputError::invalid(
            path,
            "not a scenario file (*.toml) nor a Rockyfor3D input folder",
        )),
    }
}

/// Turns a scenario error into an input error naming the file the offending parameter came
/// from (or `fallback`, the scenario file or folder).
pub(crate) fn scenario_error(
    e: ScenarioError,
    sources: &BTreeMap<String, PathBuf>,
    fallback: &Path,
) -> InputError {
    let path = e
        .parameter()
        .and_then(|p| sources.get(p))
        .map(PathBuf::as_path)
        .unwrap_or(fallback);
    InputError::invalid(path, e.to_string())
}

/// Writes a text file atomically.
pub(crate) fn write_text(path: &Path, text: &str) -> Result<(), InputError> {
    rockfall_raster::atomic::write_bytes_atomic(path, text.as_bytes())
        .map_err(|(p, e)| InputError::io(&p, e))
}

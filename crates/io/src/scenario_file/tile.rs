//! Reading a scenario file as one spatial tile of its region (`rockfall run --tile`).

use super::{parse, parse_toml};
use crate::InputError;
use crate::tile_index::ReleaseCounts;
use rockfall_raster::{Grid, GridGeometry, Window, read_geometry, read_grid, read_grid_window};
use rockfall_scenario::Scenario;
use std::path::Path;
use std::sync::Arc;

/// Reads and validates a scenario file as the spatial tile of its region released from the
/// cells of `core`: every raster is read over `window` only (the core and its halo; a
/// GeoTIFF decodes only the tiles or strips it touches), vector layers are burnt over the
/// window only, and the core's source cells are numbered among the region's (from the tile
/// index's counts, or from the whole release raster or layer). See [`Scenario::tile`].
///
/// `counts` are the tile index's counts of the release raster or layer: used while its file
/// has the stamp they were counted from. Returned: the scenario, and the counts of the
/// release when it was read whole (no usable counts given).
pub fn read_scenario_tile(
    path: &Path,
    core: Window,
    window: Window,
    counts: Option<Arc<ReleaseCounts>>,
) -> Result<(Scenario, Option<ReleaseCounts>), InputError> {
    let text = std::fs::read_to_string(path).map_err(|e| InputError::io(path, e))?;
    let tile = TileRead {
        core,
        window,
        found: None,
        counts,
        built: None,
    };
    parse(&text, path, Some(tile))
}

/// The grid of the DEM a scenario file names, read from the DEM's header.
pub fn read_dem_geometry(path: &Path) -> Result<GridGeometry, InputError> {
    let text = std::fs::read_to_string(path).map_err(|e| InputError::io(path, e))?;
    let file = parse_toml(&text, path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let dem = base.join(&file.terrain.dem);
    if !dem.is_file() {
        return Err(InputError::Missing {
            path: dem,
            what: format!("raster for `dem` (named in {})", path.display()),
        });
    }
    Ok(rockfall_raster::read_geometry(&dem)?.0)
}

/// A tile's windows while its scenario is read, and what the release scan found: the
/// region's source cells and the numbers of the core's among them.
pub(super) struct TileRead {
    pub(super) core: Window,
    pub(super) window: Window,
    pub(super) found: Option<(u64, Vec<u64>)>,
    /// The tile index's counts of the release raster or layer, if any.
    pub(super) counts: Option<Arc<ReleaseCounts>>,
    /// The release's counts when it was read whole.
    pub(super) built: Option<ReleaseCounts>,
}

/// The raster `path` holding `window` only, on its whole grid; a raster whose grid the window
/// does not fit (not the DEM's) is read whole, for the usual check to name the mismatch.
pub(super) fn windowed(path: &Path, window: Window) -> Result<Grid<f64>, InputError> {
    let (whole, _) = read_geometry(path)?;
    if !window.fits(whole.ncols, whole.nrows) {
        return Ok(read_grid(path)?);
    }
    let part = read_grid_window(path, &window)?;
    part.placed(whole, window)
        .ok_or_else(|| InputError::invalid(path, "the tile's window does not fit"))
}

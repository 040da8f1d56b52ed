//! What users look at: hazard maps over a hillshade, distribution plots and an offline HTML
//! report, and the GIS files beside the rasters.
//!
//! [`write`] adds to a run's output folder (where `rockfall_results::Results::write` put
//! the GeoTIFFs, `summary.json` and `trajectories.csv`):
//!
//! - `<raster>.qml` beside every GeoTIFF: a QGIS style with the colour ramp and scale of the
//!   report's map of that raster ([`qml`], [`layers`]).
//! - `trajectories.geojson` (the recorded trajectories as lines, thinned to half a cell) and
//!   `stems.geojson` (the simulated stems as points), named in the rasters' CRS
//!   ([`geojson`]).
//! - `rockfall.qgs`: a QGIS project of these layers over a hillshade of the DEM ([`project`]);
//!   `dem.tif` beside it when the DEM is no file (a built-in site).
//! - `report/*.png`: the site map, each key raster over the hillshade ([`maps`]), the
//!   run-out and screen distributions, a few trajectories coloured by energy ([`plots`]),
//!   speed and ground along the slope ([`profiles`]).
//! - `report.html`: one self-contained page (figures embedded, no network) with what was run,
//!   the headline numbers, the screens, the figures, the engine parameters, every number of
//!   `summary.json` and the files of the folder ([`html`], written last and atomically).
//!
//! Files of an earlier report in the same folder that this run does not write again (a
//! figure, a GeoJSON file) are removed, so the folder holds one run. On a grid of up to
//! [`WHOLE_GRID_MAX_CELLS`] cells the hillshade and one raster at a time are held whole (fast
//! maps: a pixel covers less than a cell); on a larger one the run's rasters are read as
//! views of its per-cell statistics ([`Layer`]) and the relief is shaded where a map pixel
//! asks for it, so the report allocates nothing per grid cell. Both draw the same maps.

pub mod content;
mod error;
pub mod figure;
pub mod geojson;
mod gis;
mod hazard;
pub mod hillshade;
pub mod html;
pub mod layers;
pub mod maps;
pub mod plots;
pub mod profiles;
pub mod project;
mod qgis_crs;
pub mod qml;
mod run;
mod sections;

use std::path::{Path, PathBuf};

use rockfall_forest::Stem;
use rockfall_raster::{Grid, GridGeometry, RasterView};
use rockfall_results::RasterCells;
use rockfall_results::{ForestEffect, Results};
use rockfall_scenario::Scenario;

pub use error::ReportError;
pub use figure::Figure;
pub use hazard::{HazardReport, LegendEntry, MatrixCell, MatrixTable, write_hazard_report};
pub use run::write_run;

use crate::maps::MapBase;
use crate::sections::LayerMaps;

/// The rasters mapped in the report, in order (those a run has; `Nr_tree_impacts` only
/// with stems).
pub const MAPPED: [&str; 7] = [
    "Reach_probability",
    "Nr_passages",
    "E_95",
    "Ph_95",
    "V_max",
    "Nr_deposited",
    "Nr_tree_impacts",
];

/// What a report is about.
pub struct ReportInput<'a> {
    /// The scenario simulated.
    pub scenario: &'a Scenario,
    /// Its results.
    pub results: &'a Results,
    /// The stems simulated (empty without a forest).
    pub stems: &'a [Stem],
    /// What was read, for the header: a file, a folder, or a built-in site.
    pub input: String,
    /// The command line, for the header.
    pub command: String,
    /// Files already written into the output folder (listed in the report).
    pub files: Vec<PathBuf>,
    /// The forest's effect, mapped when given (the demo).
    pub forest_effect: Option<&'a ForestEffect>,
    /// Links to related reports: (label, path relative to the output folder).
    pub links: Vec<(String, String)>,
    /// Words added to the title and the maps' titles, e.g. "with forest"; may be empty.
    pub label: String,
}

impl ReportInput<'_> {
    /// Names of every raster of the run, then of the forest effect.
    pub fn raster_names(&self) -> Vec<String> {
        let effect = self.forest_effect.into_iter().flat_map(|e| e.rasters());
        let mut names = self.results.raster_names();
        names.extend(effect.map(|(n, _)| n.to_owned()));
        names
    }

    /// The raster called `name`: the run's, or the forest effect's; `None` if neither has it.
    pub fn raster(&self, name: &str) -> Option<Layer<'_>> {
        let small = self.scenario.terrain.dem.geometry().len() <= WHOLE_GRID_MAX_CELLS;
        let run = match small {
            true => self.results.raster(name).map(Layer::Whole),
            false => self.results.raster_view(name).map(Layer::Run),
        };
        run.or_else(|| {
            let effect = self.forest_effect.into_iter().flat_map(|e| e.rasters());
            effect
                .into_iter()
                .find(|(n, _)| *n == name)
                .map(|(_, g)| Layer::Effect(g))
        })
    }
}

/// Largest grid the report holds whole (the hillshade, one raster at a time): 2²² cells,
/// ≤ 38 MB a grid. Larger grids are read as views and shaded where asked, at the cost of
/// computing a cell once per map pixel that covers it.
pub const WHOLE_GRID_MAX_CELLS: usize = 1 << 22;

/// A raster the report shows: one of the run's, whole or computed cell by cell from the run's
/// statistics when read, or a forest-effect difference grid.
pub enum Layer<'a> {
    /// A raster of the run read cell by cell ([`rockfall_results::Results::raster_view`]).
    Run(RasterCells<'a>),
    /// A raster of the run, whole ([`rockfall_results::Results::raster`]).
    Whole(Grid<f64>),
    /// A forest-effect difference.
    Effect(&'a Grid<f64>),
}

impl RasterView for Layer<'_> {
    fn view_geometry(&self) -> GridGeometry {
        match self {
            Layer::Run(r) => r.view_geometry(),
            Layer::Whole(g) => g.view_geometry(),
            Layer::Effect(g) => g.view_geometry(),
        }
    }

    fn cell(&self, row: usize, col: usize) -> Option<f64> {
        match self {
            Layer::Run(r) => r.cell(row, col),
            Layer::Whole(g) => g.cell(row, col),
            Layer::Effect(g) => g.cell(row, col),
        }
    }

    fn for_each_valid(&self, f: &mut dyn FnMut(usize, usize, f64)) {
        match self {
            Layer::Run(r) => r.for_each_valid(f),
            Layer::Whole(g) => g.for_each_valid(f),
            Layer::Effect(g) => g.for_each_valid(f),
        }
    }
}

/// Writes the report of `input` and its GIS files into `out` (see the crate docs); returns
/// the files written, `report.html` last.
///
/// # Errors
/// [`ReportError`] naming the file that could not be written or removed. Every file is
/// written atomically, so an error leaves earlier files whole and later ones absent.
pub fn write(out: &Path, input: &ReportInput<'_>) -> Result<Vec<PathBuf>, ReportError> {
    let dir = out.join("report");
    clear_figures(&dir)?;
    let base = MapBase::new(input.scenario, input.stems, &input.label)?;
    let mut layers = LayerMaps::default();
    let mut written = Vec::new();
    let mut pipes = Vec::new();
    // One raster in memory at a time: its QGIS style, then its map.
    for name in input.raster_names() {
        let Some(grid) = input.raster(&name) else {
            continue;
        };
        let (style, pipe) = gis::write_style(out, &name, &grid)?;
        written.push(style);
        pipes.push((name.clone(), pipe));
        layers.draw(&dir, input, &base, &name, grid)?;
    }
    written.extend(gis::write_vectors(out, input)?);
    written.extend(project::write_project(out, input.scenario, &pipes)?);
    let summary = input.results.summary();
    let sections = sections::figure_sections(&dir, input, &base, layers, &summary)?;
    written.extend(
        sections
            .iter()
            .flat_map(|s| s.figures.iter().map(|f| f.path.clone())),
    );
    let html_path = out.join("report.html");
    let mut listed = input.files.clone();
    listed.extend(written.iter().cloned());
    listed.push(html_path.clone());
    let page = content::page(out, input, &summary, sections, &listed);
    let text = html::render(&page)?;
    rockfall_raster::atomic::write_bytes_atomic(&html_path, text.as_bytes())?;
    written.push(html_path);
    Ok(written)
}

/// Creates the figure folder `dir`, removing the PNGs an earlier report left in it.
fn clear_figures(dir: &Path) -> Result<(), ReportError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| ReportError::Io { path, source }
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    for entry in std::fs::read_dir(dir).map_err(io(dir))? {
        let path = entry.map_err(io(dir))?.path();
        if path.extension().is_some_and(|e| e == "png") {
            std::fs::remove_file(&path).map_err(io(&path))?;
        }
    }
    Ok(())
}

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
//! - `report/*.png`: the site map, each key raster over the hillshade ([`maps`]), the
//!   run-out and screen distributions, speed and ground along the slope, a few trajectories
//!   coloured by energy ([`plots`]).
//! - `report.html`: one self-contained page (figures embedded, no network) with what was run,
//!   the headline numbers, the screens, the figures, the engine parameters, every number of
//!   `summary.json` and the files of the folder ([`html`], written last and atomically).

pub mod content;
mod error;
pub mod figure;
pub mod geojson;
pub mod hillshade;
pub mod html;
pub mod layers;
pub mod maps;
pub mod plots;
pub mod qml;

use std::path::{Path, PathBuf};

use rockfall_forest::Stem;
use rockfall_plot::ColorScale;
use rockfall_raster::Grid;
use rockfall_results::{ForestEffect, Results};
use rockfall_scenario::{Engine, Scenario};

pub use error::ReportError;
pub use figure::Figure;

use crate::html::{FigureSection, Page};
use crate::maps::MapBase;

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
    /// Words added to the title, e.g. "with forest"; may be empty.
    pub label: String,
}

/// Writes the report of `input` and its GIS files into `out` (see the crate docs); returns
/// the files written, `report.html` last.
///
/// # Errors
/// [`ReportError`] naming the file that could not be written. Every file is written
/// atomically, so an error leaves earlier files whole and later ones absent.
pub fn write(out: &Path, input: &ReportInput<'_>) -> Result<Vec<PathBuf>, ReportError> {
    let dir = out.join("report");
    std::fs::create_dir_all(&dir).map_err(|source| ReportError::Io {
        path: dir.clone(),
        source,
    })?;
    let mut written = gis(out, input)?;
    let sections = figure_sections(&dir, input)?;
    written.extend(
        sections
            .iter()
            .flat_map(|s| s.figures.iter().map(|f| f.path.clone())),
    );
    let html_path = out.join("report.html");
    let mut listed = input.files.clone();
    listed.extend(written.iter().cloned());
    listed.push(html_path.clone());
    let page = page(out, input, sections, &listed);
    let text = html::render(&page)?;
    rockfall_raster::atomic::write_bytes_atomic(&html_path, text.as_bytes())?;
    written.push(html_path);
    Ok(written)
}

/// Every raster of the run (and of the forest effect) with its name.
fn rasters(input: &ReportInput<'_>) -> Vec<(String, Grid<f64>)> {
    let r = input.results;
    let mut v: Vec<(String, Grid<f64>)> = (r.raster_names().into_iter())
        .filter_map(|n| r.raster(&n).map(|g| (n, g)))
        .collect();
    if let Some(e) = input.forest_effect {
        v.extend(
            e.rasters()
                .into_iter()
                .map(|(n, g)| (n.to_owned(), g.clone())),
        );
    }
    v
}

/// The QGIS styles and the GeoJSON files.
fn gis(out: &Path, input: &ReportInput<'_>) -> Result<Vec<PathBuf>, ReportError> {
    let mut written = Vec::new();
    for (name, grid) in rasters(input) {
        let style = layers::style(&name);
        let scale = style.fit(&grid).unwrap_or_else(|| ColorScale {
            label: style.label(),
            min: if style.scale == layers::ScaleKind::Symmetric {
                -1.0
            } else {
                0.0
            },
            max: 1.0,
            log: false,
            ramp: style.ramp,
        });
        let path = out.join(format!("{name}.qml"));
        qml::write_qml(&path, &style, &scale)?;
        written.push(path);
    }
    let crs = input.scenario.terrain.dem.crs();
    let cell = input.scenario.terrain.dem.geometry().cell_size_m;
    let rows = input.results.trajectories();
    if !rows.is_empty() {
        let path = out.join("trajectories.geojson");
        geojson::write_geojson(&path, &geojson::feature_collection(rows, crs, cell))?;
        written.push(path);
    }
    if !input.stems.is_empty() {
        let path = out.join("stems.geojson");
        geojson::write_geojson(&path, &geojson::stems_collection(input.stems, crs))?;
        written.push(path);
    }
    Ok(written)
}

/// The figures, drawn, in their sections.
fn figure_sections(dir: &Path, input: &ReportInput<'_>) -> Result<Vec<FigureSection>, ReportError> {
    let sc = input.scenario;
    let r = input.results;
    let base = MapBase::new(sc, input.stems)?;
    let mut maps = vec![base.site_map(dir, &sc.name)?];
    let grids = rasters(input);
    let grid = |name: &str| grids.iter().find(|(n, _)| n == name).map(|(_, g)| g);
    for name in MAPPED {
        if name == "Nr_tree_impacts" && input.stems.is_empty() {
            continue;
        }
        if let Some(g) = grid(name) {
            maps.extend(base.layer_map(dir, name, g, name == "Nr_tree_impacts")?);
        }
    }
    let mut sections = vec![FigureSection {
        id: "maps".into(),
        title: "Maps".into(),
        intro: "Each raster over the relief of the DEM (hillshade lit from the north-west); \
                release cells and points as squares, evaluation screens as labelled lines. Uncoloured: \
                no rock got there (or, for differences, no difference)."
            .into(),
        figures: maps,
    }];
    if let Some(e) = input.forest_effect {
        let mut figures = Vec::new();
        for (name, g) in e.rasters() {
            figures.extend(base.layer_map(dir, name, g, false)?);
        }
        sections.push(FigureSection {
            id: "forest-effect".into(),
            title: "Forest effect".into(),
            intro: "The same rocks run with the forest minus without it. Negative (blue): the \
                    forest lowers the hazard."
                .into(),
            figures,
        });
    }
    let mut plots: Vec<Figure> = plots::runout(dir, r)?.into_iter().collect();
    plots.extend(plots::screens(dir, r)?);
    plots.extend(plots::speed_profile(dir, r)?);
    if let Some(passages) = grid("Nr_passages") {
        let bin_m = r.speed_profile().first().map_or(0.0, |b| b.to_m - b.from_m);
        let sources = base.release_positions_m();
        plots.extend(plots::slope_profile(
            dir,
            &sc.terrain.dem,
            passages,
            &sources,
            bin_m,
        )?);
    }
    sections.push(FigureSection {
        id: "plots".into(),
        title: "Distributions and profiles".into(),
        intro: "Every rock of the run: its run-out, its crossings of the screens, its speed \
                in every cell it crossed."
            .into(),
        figures: plots,
    });
    let traj = plots::trajectories(dir, r.trajectories(), sc.engine == Engine::Rigid)?;
    if !traj.is_empty() {
        sections.push(FigureSection {
            id: "trajectories".into(),
            title: "Trajectories".into(),
            intro: "Also in trajectories.csv (every recorded state) and trajectories.geojson \
                    (lines for a GIS)."
                .into(),
            figures: traj,
        });
    }
    Ok(sections)
}

/// The page of the report.
fn page(
    out: &Path,
    input: &ReportInput<'_>,
    sections: Vec<FigureSection>,
    files: &[PathBuf],
) -> Page {
    let s = input.results.summary_json();
    let crs = input
        .scenario
        .terrain
        .dem
        .crs()
        .map_or("no CRS".into(), |c| c.describe());
    let mut numbers = Vec::new();
    let mut summary = s.clone();
    if let Some(m) = summary.as_object_mut() {
        m.remove("parameters");
    }
    content::flatten("", &summary, &mut numbers);
    let mut parameters = Vec::new();
    content::flatten("", &s["parameters"], &mut parameters);
    let label = match input.label.is_empty() {
        true => String::new(),
        false => format!(" ({})", input.label),
    };
    Page {
        title: format!("Rockfall report: {}{label}", input.scenario.name),
        subtitle: format!(
            "{} engine · {} rocks · seed {} · rockfall {}",
            content::text(&s["engine"]),
            content::text(&s["rocks"]),
            content::text(&s["seed"]),
            content::text(&s["version"])
        ),
        links: input.links.clone(),
        run: content::run_rows(input, &s, &content::utc_now()),
        glance: content::glance(&s),
        screens: content::screens(&s),
        sections,
        parameters,
        numbers,
        files: content::files(out, files, &crs),
    }
}

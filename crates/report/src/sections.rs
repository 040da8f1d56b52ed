//! The report's figure sections: maps, forest effect, distributions and profiles,
//! trajectories. A figure that cannot be drawn (nothing to show) is named in its section's
//! introduction instead.

use std::path::Path;

use rockfall_scenario::Engine;
use serde_json::Value;

use crate::html::FigureSection;
use crate::maps::MapBase;
use crate::{Figure, MAPPED, ReportError, ReportInput, plots, profiles};

/// Every figure section of the report, its figures drawn into `dir`.
pub(crate) fn figure_sections(
    dir: &Path,
    input: &ReportInput<'_>,
    summary: &Value,
) -> Result<Vec<FigureSection>, ReportError> {
    let base = MapBase::new(input.scenario, input.stems, &input.label)?;
    let mut sections = vec![maps(dir, input, &base)?];
    if let Some(effect) = forest_effect(dir, input, &base)? {
        sections.push(effect);
    }
    sections.push(distributions(dir, input, &base, summary)?);
    if let Some(t) = trajectories(dir, input)? {
        sections.push(t);
    }
    Ok(sections)
}

/// A section; `skipped` figures are named after the introduction.
fn section(
    id: &str,
    title: &str,
    intro: &str,
    figures: Vec<Figure>,
    skipped: &[String],
) -> FigureSection {
    let mut intro = intro.to_owned();
    if !skipped.is_empty() {
        intro.push_str(&format!(" Not drawn: {}.", skipped.join("; ")));
    }
    FigureSection {
        id: id.into(),
        title: title.into(),
        intro,
        figures,
    }
}

/// The site map and the key rasters over the hillshade.
fn maps(dir: &Path, input: &ReportInput<'_>, base: &MapBase) -> Result<FigureSection, ReportError> {
    let mut figures = vec![base.site_map(dir, &input.scenario.name)?];
    let mut skipped = Vec::new();
    for name in MAPPED {
        if name == "Nr_tree_impacts" && input.stems.is_empty() {
            continue;
        }
        let Some(grid) = input.raster(name) else {
            skipped.push(format!("{name} (not written by this run)"));
            continue;
        };
        match base.layer_map(dir, name, &grid)? {
            Some(fig) => figures.push(fig),
            None => skipped.push(format!("{name} (no cell to colour)")),
        }
    }
    let intro = "Each raster over the relief of the DEM (hillshade lit from the north-west), \
                 with the release cells and points as squares and the evaluation screens as \
                 labelled lines. Uncoloured: no rock got there.";
    Ok(section("maps", "Maps", intro, figures, &skipped))
}

/// The forest effect's maps, when the report has one.
fn forest_effect(
    dir: &Path,
    input: &ReportInput<'_>,
    base: &MapBase,
) -> Result<Option<FigureSection>, ReportError> {
    let Some(effect) = input.forest_effect else {
        return Ok(None);
    };
    let mut figures = Vec::new();
    let mut skipped = Vec::new();
    for (name, grid) in effect.rasters() {
        match base.layer_map(dir, name, grid)? {
            Some(fig) => figures.push(fig),
            None => skipped.push(format!("{name} (no cell to colour)")),
        }
    }
    let intro = "The same rocks run with the forest minus without it. Negative (blue): the \
                 forest lowers the hazard. The reach-probability difference is uncoloured \
                 where it is zero; the energy difference where neither run got there.";
    Ok(Some(section(
        "forest-effect",
        "Forest effect",
        intro,
        figures,
        &skipped,
    )))
}

/// Run-out and screen distributions, the speed and slope profiles.
fn distributions(
    dir: &Path,
    input: &ReportInput<'_>,
    base: &MapBase,
    summary: &Value,
) -> Result<FigureSection, ReportError> {
    let r = input.results;
    let mut figures: Vec<Figure> = plots::runout(dir, r, summary)?.into_iter().collect();
    figures.extend(plots::screens(dir, r, summary)?);
    let profile = r.speed_profile();
    figures.extend(profiles::speed_profile(dir, &profile, r.rocks())?);
    let mut skipped = Vec::new();
    let bin_m = profile.first().map_or(0.0, |b| b.to_m - b.from_m);
    let sources = base.release_positions_m();
    let passages = input.raster("Nr_passages");
    let dem = &input.scenario.terrain.dem;
    match passages
        .map(|p| profiles::slope_profile(dir, dem, &p, &sources, bin_m))
        .transpose()?
    {
        Some(Some(fig)) => figures.push(fig),
        _ => skipped.push(format!(
            "the slope profile (drawn for 1 to {} release positions over two or more distances)",
            profiles::MAX_PROFILE_SOURCES
        )),
    }
    let intro = "Every rock of the run: its run-out, its crossings of the screens, its speed \
                 in every cell it crossed.";
    Ok(section(
        "plots",
        "Distributions and profiles",
        intro,
        figures,
        &skipped,
    ))
}

/// A few recorded trajectories, when there are any.
fn trajectories(dir: &Path, input: &ReportInput<'_>) -> Result<Option<FigureSection>, ReportError> {
    let rigid = input.scenario.engine == Engine::Rigid;
    let figures = plots::trajectories(dir, input.results.trajectories(), rigid)?;
    if figures.is_empty() {
        return Ok(None);
    }
    let intro = "Also in trajectories.csv (every recorded state) and trajectories.geojson \
                 (lines for a GIS).";
    Ok(Some(section(
        "trajectories",
        "Trajectories",
        intro,
        figures,
        &[],
    )))
}

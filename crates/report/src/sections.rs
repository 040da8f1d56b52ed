//! The report's figure sections: maps, forest effect, distributions and profiles,
//! trajectories. A figure that cannot be drawn (nothing to show) is named in its section's
//! introduction instead.

use std::path::Path;

use rockfall_results::{ForestEffectSummary, MIN_REACH_PCT, Summary};
use rockfall_scenario::Engine;

use crate::html::FigureSection;
use crate::maps::MapBase;
use crate::{Figure, Layer, MAPPED, ReportError, ReportInput, plots, profiles};

/// The maps of the rasters, drawn while each raster is in memory ([`LayerMaps::draw`]).
#[derive(Default)]
pub(crate) struct LayerMaps<'a> {
    /// Key rasters' maps with their place in [`MAPPED`].
    maps: Vec<(usize, Figure)>,
    /// Forest-effect maps.
    effect: Vec<Figure>,
    /// Rasters not mapped, with why.
    skipped: Vec<String>,
    effect_skipped: Vec<String>,
    /// `Nr_passages`, kept for the slope profile.
    passages: Option<Layer<'a>>,
}

impl<'a> LayerMaps<'a> {
    /// Maps the raster `name` (`grid`) if the report shows it: a key raster of [`MAPPED`]
    /// (`Nr_tree_impacts` only with stems) or a forest-effect difference; keeps
    /// `Nr_passages` for the slope profile.
    pub(crate) fn draw(
        &mut self,
        dir: &Path,
        input: &ReportInput<'_>,
        base: &MapBase,
        name: &str,
        grid: Layer<'a>,
    ) -> Result<(), ReportError> {
        self.map(dir, input, base, name, &grid)?;
        if name == "Nr_passages" {
            self.passages = Some(grid);
        }
        Ok(())
    }

    fn map(
        &mut self,
        dir: &Path,
        input: &ReportInput<'_>,
        base: &MapBase,
        name: &str,
        grid: &Layer<'_>,
    ) -> Result<(), ReportError> {
        let effect = name.starts_with("Forest_effect_");
        let key = MAPPED.iter().position(|m| *m == name);
        let stemless = name == "Nr_tree_impacts" && input.stems.is_empty();
        if !effect && (key.is_none() || stemless) {
            return Ok(());
        }
        let figure = base.layer_map(dir, name, grid)?;
        let skipped = format!("{name} (no cell to colour)");
        match (figure, key) {
            (Some(f), Some(k)) => self.maps.push((k, f)),
            (Some(f), None) => self.effect.push(f),
            (None, Some(_)) => self.skipped.push(skipped),
            (None, None) => self.effect_skipped.push(skipped),
        }
        Ok(())
    }
}

/// Every figure section of the report, its figures drawn into `dir`; `layers` holds the
/// rasters' maps, drawn already.
pub(crate) fn figure_sections(
    dir: &Path,
    input: &ReportInput<'_>,
    base: &MapBase,
    layers: LayerMaps<'_>,
    summary: &Summary,
) -> Result<Vec<FigureSection>, ReportError> {
    let mut sections = vec![maps(dir, input, base, layers.maps, &layers.skipped)?];
    if let Some(effect) = input.forest_effect {
        let intro = effect_intro(effect.summary());
        let (figures, skipped) = (layers.effect, &layers.effect_skipped);
        sections.push(section(
            "forest-effect",
            "Forest effect",
            &intro,
            figures,
            skipped,
        ));
    }
    sections.push(distributions(
        dir,
        input,
        base,
        layers.passages.as_ref(),
        summary,
    )?);
    if let Some(t) = trajectories(dir, input)? {
        sections.push(t);
    }
    Ok(sections)
}

/// The forest-effect section's introduction, with its headline figures: over the cells the
/// run without the forest reached (one set of cells for both runs), and the areas above each
/// energy threshold.
fn effect_intro(e: &ForestEffectSummary) -> String {
    let mut intro = String::from(
        "The same rocks run with the forest minus without it. Negative (blue): the forest \
         lowers the hazard. The reach-probability difference is uncoloured where it is zero; \
         the energy difference where neither run got there.",
    );
    let bare = &e.on_cells_reached_without_forest;
    if let (Some(p), Some(k)) = (
        bare.reach_probability_pp.mean_difference,
        bare.e_95_kj.mean_difference,
    ) {
        intro.push_str(&format!(
            " Over the {} cells reached without the forest (a cell the forest kept every rock \
             from counts 0), the forest changes the reach probability by {p:+.2} percentage \
             points and E_95 by {k:+.1} kJ on average.",
            bare.e_95_kj.cells
        ));
    }
    let areas: Vec<String> = (e.area_e_95_above.iter())
        .filter_map(|a| {
            let (w, o) = a.hectares()?;
            Some(format!(
                "> {} kJ: {w:.2} ha with, {o:.2} ha without",
                a.energy_kj
            ))
        })
        .collect();
    if !areas.is_empty() {
        intro.push_str(&format!(
            " Area reached by at least {MIN_REACH_PCT} % of the rocks with E_95 {}.",
            areas.join("; ")
        ));
    }
    intro
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

/// The site map, then the key rasters' `maps` in the order of [`MAPPED`].
fn maps(
    dir: &Path,
    input: &ReportInput<'_>,
    base: &MapBase,
    mut maps: Vec<(usize, Figure)>,
    skipped: &[String],
) -> Result<FigureSection, ReportError> {
    maps.sort_by_key(|(k, _)| *k);
    let mut figures = vec![base.site_map(dir, &input.scenario.name)?];
    figures.extend(maps.into_iter().map(|(_, f)| f));
    let intro = "Each raster over the relief of the DEM (hillshade lit from the north-west), \
                 with the release cells and points as squares and the evaluation screens as \
                 labelled lines. Uncoloured: no rock got there.";
    Ok(section("maps", "Maps", intro, figures, skipped))
}

/// Run-out and screen distributions, the speed and slope profiles.
fn distributions(
    dir: &Path,
    input: &ReportInput<'_>,
    base: &MapBase,
    passages: Option<&Layer<'_>>,
    summary: &Summary,
) -> Result<FigureSection, ReportError> {
    let r = input.results;
    let mut figures: Vec<Figure> = plots::runout(dir, r, summary)?.into_iter().collect();
    figures.extend(plots::screens(dir, r, summary)?);
    let profile = r.speed_profile();
    figures.extend(profiles::speed_profile(dir, &profile, r.rocks())?);
    let mut skipped = Vec::new();
    let bin_m = profile.first().map_or(0.0, |b| b.to_m - b.from_m);
    let sources = base.release_positions_m();
    let dem = &input.scenario.terrain.dem;
    match passages
        .map(|p| profiles::slope_profile(dir, dem, p, &sources, bin_m))
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

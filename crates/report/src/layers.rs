//! How each raster is coloured, on the report's maps and in its QGIS style alike.

use rockfall_plot::{ColorScale, Ramp};
use rockfall_raster::RasterView;

/// Opacity of a raster's colours over the hillshade, on the report's maps and in the QGIS
/// styles alike.
pub const LAYER_OPACITY: f64 = 0.8;

/// How the colour scale of a layer is fitted to its values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScaleKind {
    /// From 0 (or the smallest value, if negative) to the largest value.
    Linear,
    /// Logarithmic, from the smallest positive value to the largest: counts and
    /// probabilities spanning decades.
    Log,
    /// Centred on 0, from −m to +m with m the [`SYMMETRIC_PERCENTILE`]th percentile of the
    /// magnitudes: differences.
    Symmetric,
}

/// How a raster is drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct LayerStyle {
    /// What the raster shows, for titles: "Reach probability".
    pub title: String,
    /// Unit of the values, for the colour bar: "% of rocks".
    pub unit: &'static str,
    /// Colour ramp (perceptually uniform; diverging for differences).
    pub ramp: Ramp,
    /// How the scale is fitted.
    pub scale: ScaleKind,
    /// Zero means "nothing happened here" and is left uncoloured (counts, probabilities).
    pub zero_is_empty: bool,
    /// One sentence for the report: what the map shows.
    pub caption: String,
}

impl LayerStyle {
    fn new(title: &str, unit: &'static str, ramp: Ramp, scale: ScaleKind) -> Self {
        LayerStyle {
            title: title.to_owned(),
            unit,
            ramp,
            scale,
            zero_is_empty: scale == ScaleKind::Log,
            caption: String::new(),
        }
    }

    fn empty_at_zero(mut self) -> Self {
        self.zero_is_empty = true;
        self
    }

    fn says(mut self, caption: &str) -> Self {
        self.caption = caption.to_owned();
        self
    }

    /// The label of the colour bar: "Reach probability (% of rocks)".
    pub fn label(&self) -> String {
        format!("{} ({})", self.title, self.unit)
    }

    /// Whether a value is coloured (non-empty): finite, and non-zero where zero is empty.
    pub fn shows(&self, v: f64) -> bool {
        v.is_finite()
            && !(self.zero_is_empty && v == 0.0)
            && !(self.scale == ScaleKind::Log && v < 0.0)
    }

    /// The colour scale fitted to the values `grid` shows; `None` when it shows none.
    ///
    /// A symmetric scale spans ± the 98th percentile of the magnitudes (so that a few
    /// extreme cells do not wash out the rest; larger ones take the end colours); the others
    /// span the values' whole range (see [`ScaleKind`]).
    pub fn fit(&self, grid: &impl RasterView) -> Option<ColorScale> {
        let mut shown: Vec<f64> = Vec::new();
        grid.for_each_valid(&mut |_, _, v| {
            if self.shows(v) {
                shown.push(v);
            }
        });
        let lo = shown.iter().copied().reduce(f64::min)?;
        let hi = shown.iter().copied().reduce(f64::max)?;
        let (min, max) = match self.scale {
            ScaleKind::Linear => {
                let min = lo.min(0.0);
                (min, if hi > min { hi } else { min + 1.0 })
            }
            // A single value takes the top colour of a decade below it.
            ScaleKind::Log if hi > lo => (lo, hi),
            ScaleKind::Log => (lo / 10.0, lo),
            ScaleKind::Symmetric => {
                let mut magnitudes: Vec<f64> = shown.iter().map(|v| v.abs()).collect();
                magnitudes.sort_by(f64::total_cmp);
                let rank = (SYMMETRIC_PERCENTILE / 100.0 * magnitudes.len() as f64).ceil() as usize;
                let m = magnitudes[rank.clamp(1, magnitudes.len()) - 1];
                let m = if m > 0.0 { m } else { 1.0 };
                (-m, m)
            }
        };
        Some(ColorScale {
            label: self.label(),
            min,
            max,
            log: self.scale == ScaleKind::Log,
            ramp: self.ramp,
        })
    }
}

/// Percentile of the magnitudes a symmetric scale spans.
pub const SYMMETRIC_PERCENTILE: f64 = 98.0;

/// The style of the raster called `name` (a Rockyfor3D name as the run writes it, or a
/// `Forest_effect_*` difference). Unknown names get a neutral linear viridis style.
pub fn style(name: &str) -> LayerStyle {
    use ScaleKind::{Linear, Log, Symmetric};
    match name {
        "E_95CI" => {
            return LayerStyle::new("Kinetic energy, mean + 1.645 sd", "kJ", Ramp::Magma, Linear)
                .says(
                    "Rockyfor3D's E_95CI: mean + 1.645 standard deviations of the passages' \
                     energies, the value 95 % of them stay below if normally distributed.",
                );
        }
        "Ph_95CI" => {
            return LayerStyle::new("Passing height, mean + 1.645 sd", "m", Ramp::Plasma, Linear)
                .says(
                    "Rockyfor3D's Ph_95CI: mean + 1.645 standard deviations of the passing \
                     heights (rock centre above the ground).",
                );
        }
        "EL_angles" => {
            return LayerStyle::new("Energy-line angle", "°", Ramp::Cividis, Linear).says(
                "Largest angle above the horizontal from a reaching rock's release cell to the \
                 cell, DEM surface to DEM surface.",
            );
        }
        _ => {}
    }
    if let Some(p) = name.strip_prefix("E_").filter(|p| *p != "mean") {
        let title = format!("Kinetic energy, {p}th percentile");
        return LayerStyle::new(&title, "kJ", Ramp::Magma, Linear).says(&format!(
            "{p} % of the passages through a cell carried less energy (translational + rotational)."
        ));
    }
    match name {
        "Reach_probability" => LayerStyle::new("Reach probability", "% of rocks", Ramp::Viridis, Log)
            .says("Share of the simulated rocks that reached the cell (empty: none)."),
        "Nr_passages" => LayerStyle::new("Passages", "passages", Ramp::Viridis, Log)
            .says("Number of rock passages through the cell."),
        "Nr_deposited" => LayerStyle::new("Deposited rocks", "rocks", Ramp::Viridis, Log)
            .says("Rocks that came to rest in the cell."),
        "Nr_sourcecells" => LayerStyle::new("Source cells reaching", "cells", Ramp::Viridis, Log)
            .says("Number of distinct release cells whose rocks reached the cell."),
        "E_mean" => LayerStyle::new("Mean kinetic energy", "kJ", Ramp::Magma, Linear)
            .says("Mean energy (translational + rotational) over the passages through the cell."),
        "Ph_mean" => LayerStyle::new("Mean passing height", "m", Ramp::Plasma, Linear)
            .says("Mean height of the rock centre above the ground, over the passages."),
        "Ph_50" => LayerStyle::new("Passing height, median", "m", Ramp::Plasma, Linear)
            .says("Half of the passages through the cell were lower (rock centre above the ground)."),
        "Ph_90" => LayerStyle::new("Passing height, 90th percentile", "m", Ramp::Plasma, Linear)
            .says("90 % of the passages through the cell were lower (rock centre above the ground)."),
        "Ph_95" => LayerStyle::new("Passing height, 95th percentile", "m", Ramp::Plasma, Linear)
            .says("95 % of the passages through the cell were lower (rock centre above the ground)."),
        "V_max" => LayerStyle::new("Maximum velocity", "m/s", Ramp::Inferno, Linear)
            .says("Largest translational speed of any rock in the cell."),
        "Nr_tree_impacts" => LayerStyle::new("Tree impacts", "impacts", Ramp::Viridis, Log)
            .says("Rock–tree impacts in the cell."),
        "Tree_impact_height_max" => {
            LayerStyle::new("Highest tree impact", "m", Ramp::Plasma, Linear)
                .says("Largest height above the ground at which a stem was hit in the cell.")
        }
        "Nr_stems_broken" => LayerStyle::new("Stems broken", "stems", Ramp::Magma, Log)
            .says("Stems broken by rock impacts in the cell."),
        "Forest_effect_Reach_probability" => LayerStyle::new(
            "Forest effect on reach probability",
            "percentage points",
            Ramp::Diverging,
            Symmetric,
        )
        .empty_at_zero()
        .says(
            "Reach probability with the forest minus without it: blue where the forest protects \
             (uncoloured where the difference is zero).",
        ),
        "Forest_effect_E_95" => LayerStyle::new(
            "Forest effect on E_95",
            "kJ",
            Ramp::Diverging,
            Symmetric,
        )
        .says("95th-percentile energy with the forest minus without it: blue where the forest protects."),
        _ => LayerStyle::new(name, "value", Ramp::Viridis, Linear),
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use rockfall_raster::{Grid, GridGeometry};

    fn grid(values: Vec<f64>) -> Grid<f64> {
        let g = GridGeometry {
            ncols: values.len(),
            nrows: 1,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        Grid::from_values(g, values).unwrap()
    }

    #[test]
    fn scales_fit_what_the_layer_shows() {
        let reach = style("Reach_probability")
            .fit(&grid(vec![0.0, 0.01, 2.0, 100.0]))
            .unwrap();
        assert_eq!((reach.min, reach.max, reach.log), (0.01, 100.0, true));
        let e = style("E_95").fit(&grid(vec![0.0, 12.0, 340.0])).unwrap();
        assert_eq!((e.min, e.max, e.log), (0.0, 340.0, false));
        assert_eq!(e.label, "Kinetic energy, 95th percentile (kJ)");
        let d = style("Forest_effect_E_95")
            .fit(&grid(vec![-80.0, 0.0, 20.0]))
            .unwrap();
        assert_eq!((d.min, d.max), (-80.0, 80.0));
        assert_eq!(d.ramp, Ramp::Diverging);
    }

    #[test]
    fn the_parity_rasters_are_not_taken_for_energy_percentiles() {
        assert_eq!(style("E_95CI").title, "Kinetic energy, mean + 1.645 sd");
        assert_eq!(style("E_95CI").unit, "kJ");
        assert_eq!(style("Ph_95CI").unit, "m");
        assert_eq!(style("EL_angles").unit, "°");
        assert_eq!(style("E_95").title, "Kinetic energy, 95th percentile");
    }

    #[test]
    fn degenerate_layers_still_get_a_valid_scale_or_none() {
        assert_eq!(style("Nr_passages").fit(&grid(vec![0.0, 0.0])), None);
        let one = style("Nr_passages")
            .fit(&grid(vec![0.0, 3.0, 3.0]))
            .unwrap();
        assert_eq!(
            (one.min, one.max),
            (0.3, 3.0),
            "a single value takes the top colour"
        );
        let flat = style("V_max").fit(&grid(vec![0.0, 0.0])).unwrap();
        assert!(flat.max > flat.min);
        let mut many = vec![-10.0; 99];
        many.push(1000.0);
        let robust = style("Forest_effect_E_95").fit(&grid(many)).unwrap();
        assert_eq!(
            (robust.min, robust.max),
            (-10.0, 10.0),
            "one extreme cell is clipped"
        );
        let zero = style("Forest_effect_E_95").fit(&grid(vec![0.0])).unwrap();
        assert!(zero.max > 0.0 && zero.min < 0.0);
    }

    #[test]
    fn zero_is_empty_for_counts_and_probabilities_only() {
        assert!(!style("Nr_passages").shows(0.0));
        assert!(!style("Reach_probability").shows(0.0));
        assert!(style("E_95").shows(0.0));
        assert!(!style("Forest_effect_Reach_probability").shows(0.0));
        assert!(style("Forest_effect_E_95").shows(0.0));
        assert!(!style("E_95").shows(f64::NAN));
        assert_eq!(style("E_99.5").title, "Kinetic energy, 99.5th percentile");
    }
}

//! The forested virtual slope of seed 001 §3.4, for the rigid engine.
//!
//! Given by the paper and used as given: inclination 40°; release at an altitude of 200 m,
//! "corresponding to a slope length of 240 m" (read as the horizontal length: 200 m /
//! tan 40° = 238.4 m), ending on a horizontal plane at altitude 0; trees randomly placed on
//! the inclined surface at 500 stems/ha, DBH 0.5 ± 0.05 m, height 22.87 ± 1.82 m; tree
//! friction μ = 0.1 (ε_N = ε_T = 0, §2); rocks of 0.02 m³ and 2700 kg/m³ (table 1), the
//! shapes of table 2 (cubic1.2 by default here; the shape study runs all three); 500 runs per
//! shape with varying orientations.
//!
//! Chosen here (not in the paper): the density is taken per hectare of *inclined* surface
//! ("randomly distributed on the inclined terrain surface"), i.e. 500/cos 40° ≈ 653 stems per
//! hectare of map; the slope extends 10 m (horizontal) above the release so the release point
//! lies inside the DEM; the plane below is 160 m long and the site 300 m wide, so that the
//! rocks' run-out and lateral spread (the shape study's measures) are not cut off by the edges;
//! a 2 m grid in local coordinates (no CRS); the ground is RAMMS::ROCKFALL's scarring ground
//! (Lu et al. 2019; seed 001's authors' own production model, which the paper does not
//! parameterise) with its `medium` class, Lu et al. 2019's whole-trajectory set
//! ([`scarring_contact`]; the hard ground of Leine et al. 2014, reference [12] of seed 001,
//! which the site used before, is [`leine_2014_contact`]); rocks start 0.1 m above the
//! ground at rest, with a random orientation each.

use crate::profile::{Profile, Section, sample_dem};
use crate::{SITE_SEED, SiteError};
use rockfall_forest::{Species, StandCell, StandOptions, expand_stands};
use rockfall_raster::GridGeometry;
use rockfall_scenario::{
    ContactParams, ContactSettings, Engine, ForestSpec, LumpedSettings, OutputSettings, Release,
    ReleasePoint, RigidParams, RockSpec, Scenario, Screen, SimulationSettings, Slippage,
};
use rockfall_scenario::{GroundModel, ScarringSettings};
use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};
use std::collections::BTreeMap;

/// Slope angle, degrees (seed 001 §3.4).
pub const SLOPE_DEG: f64 = 40.0;
/// Release altitude above the plane, m (seed 001 §3.4).
pub const DROP_M: f64 = 200.0;
/// Stems per hectare of inclined surface (seed 001 §3.4).
pub const STEMS_PER_HA_SURFACE: f64 = 500.0;

const CELL_M: f64 = 2.0;
const ABOVE_M: f64 = 10.0;
const PLANE_M: f64 = 160.0;
const WIDTH_M: f64 = 300.0;

/// Horizontal length of the slope below the release, m.
pub fn slope_length_m() -> f64 {
    DROP_M / SLOPE_DEG.to_radians().tan()
}

/// The rock–ground law of Leine et al. (2014), reference [12] of seed 001, as the hard ground:
/// ε_N = ε_T = 0 with their slippage friction (μ_min 0.2, μ_max 1.3, β 20 s⁻¹, κ 0.7 m⁻¹; μ 0.2
/// without slippage); stems with seed 001's μ = 0.1 and ε = 0. The built-in rigid sites used
/// it before the scarring ground; `rockfall validate` keeps it as the named alternative.
pub fn leine_2014_contact() -> ContactSettings {
    ContactSettings {
        ground: ContactParams {
            mu: 0.2,
            eps_n: 0.0,
            eps_t: 0.0,
        },
        tree: ContactParams {
            mu: 0.1,
            eps_n: 0.0,
            eps_t: 0.0,
        },
        slippage: Some(Slippage {
            mu_min: 0.2,
            mu_max: 1.3,
            beta_per_s: 20.0,
            kappa_per_m: 0.7,
        }),
        model: GroundModel::Hard,
        scarring: ScarringSettings::default(),
    }
}

/// RAMMS::ROCKFALL's production ground (Lu et al. 2019): the scarring ground of the `medium`
/// class (their whole-trajectory set), ε_N = ε_T = 0 on the rebound plane; stems with seed
/// 001's μ = 0.1 and ε = 0. The built-in rigid sites use it.
pub fn scarring_contact() -> ContactSettings {
    ContactSettings {
        model: GroundModel::Scarring,
        slippage: None,
        ..leine_2014_contact()
    }
}

/// Builds the site.
pub fn build() -> Result<Scenario, SiteError> {
    let t = SLOPE_DEG.to_radians().tan();
    let length = ABOVE_M + slope_length_m() + PLANE_M;
    let nrows = (length / CELL_M).ceil() as usize;
    let ncols = (WIDTH_M / CELL_M) as usize;
    let g = GridGeometry {
        ncols,
        nrows,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: CELL_M,
    };
    let profile = Profile {
        top_z_m: DROP_M + ABOVE_M * t,
        sections: vec![
            Section {
                length_m: ABOVE_M + slope_length_m(),
                slope_deg: SLOPE_DEG,
            },
            Section {
                length_m: PLANE_M,
                slope_deg: 0.0,
            },
        ],
    };
    let dem = Dem::new(sample_dem(g, &profile, None))?;
    let terrain = Terrain::new(
        dem,
        SurfaceMap::uniform(SoilType::new(4).ok_or(SiteError::Internal)?, 0.0, 0.0, 0.0),
    )?;
    let y_top = g.y_max_m();
    let foot_d = ABOVE_M + slope_length_m();
    let release_y = y_top - ABOVE_M;
    let stems_per_ha_map = STEMS_PER_HA_SURFACE / SLOPE_DEG.to_radians().cos();
    let cell = |row: usize, _col: usize| {
        // cells wholly on the slope, below the release
        let d0 = row as f64 * CELL_M;
        (d0 >= ABOVE_M && d0 + CELL_M <= foot_d).then_some(StandCell {
            stems_per_ha: stems_per_ha_map,
            dbh_mean_cm: 50.0,
            dbh_sd_cm: 5.0,
            conifer_percent: 0.0,
            height: Some((22.87, 1.82)),
        })
    };
    let mut stems = expand_stands(&g, cell, SITE_SEED, &StandOptions::default())?;
    for s in &mut stems {
        s.species = Species::Unknown;
    }
    let release_point = ReleasePoint::at_rest(WIDTH_M / 2.0, release_y, 0.1);
    Ok(Scenario {
        name: "forest-slope-40".into(),
        engine: Engine::Rigid,
        seed: 1,
        terrain,
        forest: Some(ForestSpec::Stems(stems)),
        nets: None,
        rock: RockSpec::named("cubic1.2", None, 2700.0).ok_or(SiteError::Internal)?,
        release: Release {
            points: vec![release_point],
            ..Release::default()
        },
        screens: vec![Screen {
            name: "slope_foot".into(),
            points_m: vec![[0.0, y_top - foot_d], [WIDTH_M, y_top - foot_d]],
            capacity_kj: None,
            height_m: None,
            net: None,
        }],
        lumped: LumpedSettings::default(),
        rigid: RigidParams::default(),
        contact: scarring_contact(),
        simulation: SimulationSettings {
            rocks_per_point: 500,
            ..SimulationSettings::default()
        },
        output: OutputSettings::default(),
        sources: BTreeMap::new(),
        notes: Vec::new(),
        tile: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_geometry_and_forest() {
        let s = build().unwrap();
        let dem = &s.terrain.dem;
        let g = dem.geometry();
        let (x, y) = (WIDTH_M / 2.0, g.y_max_m() - ABOVE_M);
        assert!(
            (dem.height_m(x, y).unwrap() - 200.0).abs() < 1e-6,
            "release at 200 m"
        );
        assert!((dem.slope_deg(x, y - 50.0).unwrap() - 40.0).abs() < 1e-6);
        assert!(
            dem.height_m(x, g.y_min_m + 10.0).unwrap().abs() < 1e-9,
            "plane at 0 m"
        );
        let f = s.build_forest().unwrap();
        let slope_area_ha = (slope_length_m() / SLOPE_DEG.to_radians().cos()) * WIDTH_M / 1e4;
        let per_surface_ha = f.len() as f64 / slope_area_ha;
        // cells partly on the slope carry no stems: allow for the lost edge row plus 4 sd
        assert!((per_surface_ha - 500.0).abs() < 25.0, "{per_surface_ha}");
        let (lo, mean, hi) = f.dbh_stats_cm().unwrap();
        assert!(
            (mean - 50.0).abs() < 0.5 && lo >= 5.0 && hi < 80.0,
            "{lo} {mean} {hi}"
        );
        let (hlo, hhi) = f.height_range_m().unwrap();
        assert!(hlo > 10.0 && hhi < 35.0);
        s.validate().unwrap();
    }
}

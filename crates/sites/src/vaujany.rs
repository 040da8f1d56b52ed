//! The Vaujany experiment slopes of seed 000 (Dorren et al. 2006, §2.1), rebuilt synthetically.
//!
//! What the paper gives, and is used as given: mean gradient 38°; spherical rocks of mean
//! diameter 0.95 m and density 2800 kg/m³; a 2.5 m DEM; evaluation screens 185 m and 235 m
//! along the slope from the start (site 1); the share of rocks stopped within the first
//! 223.5 m and the share passing the lower forest road; site 2 forested except its upper 40 m,
//! 290 stems/ha, DBH 31 ± 21 cm, *Abies alba* 50 %, *Picea abies* 25 %, *Fagus sylvatica* 17 %,
//! *Acer pseudoplatanus* 4 %; location lat 45°12′, long 6°3′ (placed in Lambert-93, EPSG:2154).
//!
//! What the paper does not give, and how it is chosen here (none of it tuned to tables 2–3):
//! - **Profile**: 11.25 m at 20° above the start (the launch area), 38° for 223.5 m of ground
//!   down to the lower forest road, the road 5 m wide at 3°, 38° for 60 m of ground below it,
//!   then a run-out of 30 m at 25° and 80 m at 5° (horizontal lengths). The road's position
//!   follows from the paper: the shares stopped before 223.5 m, stopped on the road and passed
//!   it add up to 100 % on site 2 (66 + 13 + 21, §3.1 and §4), so the road begins at 223.5 m.
//! - **Cross profile**: a shallow gully (lateral slope growing to 8°, width scale 25 m) keeps
//!   the fall line on the corridor the cameras covered; site 1 is an avalanche track.
//! - **Soil type** from the measured r_n of seed 000 table 4 (mean r_n 0.26 on site 1, 0.36 on
//!   site 2): the Rockyfor3D class whose range holds it and whose mean is closest — class 2
//!   (r_n 0.25–0.31) on site 1, class 4 (0.34–0.42) on site 2; the road is class 3 ("forest
//!   road").
//! - **Obstacle heights** from the measured mean r_t of table 4 (0.70 site 1, 0.77 site 2)
//!   through eq. 3 with R = 0.475 m: MOH = R(1/r_t − 1) = 0.204 m (site 1), 0.142 m (site 2).
//!   The three cover classes are spread around that mean with 0.7·rg70 + 0.2·rg20 + 0.1·rg10 =
//!   MOH (eq. 4): site 1, "relatively uniform" (§2.5), 0.17 / 0.25 / 0.35 m; site 2 wider,
//!   0.10 / 0.20 / 0.32 m. The undisturbed road has 0 / 0.02 / 0.05 m (§4: "on undisturbed
//!   forest roads … the MOH is very low").
//! - **Release**: one source cell at the start, rocks 0.5 m above the ground moving 1 m/s
//!   downslope (pushed over the edge by a caterpillar, §2.1); 10 000 rocks as in the paper.
//! - **Forest** (site 2): stands expanded into explicit stems with a fixed seed, so the site's
//!   trees are the same in every run; species drawn by the stated shares, the 4 % the paper
//!   leaves unnamed as other broadleaves (the mixed montane stand's minor species); no stems on the road; heights from the DBH allometry.

use crate::profile::{Gully, Profile, Section, sample_dem};
use crate::{SITE_SEED, SiteError};
use rand::RngExt;
use rockfall_forest::{Species, StandCell, StandOptions, expand_stands};
use rockfall_raster::{Crs, Field, Grid, GridGeometry};
use rockfall_rng::{Purpose, stream};
use rockfall_scenario::{
    ContactSettings, Engine, ForestSpec, LumpedSettings, MohMode, OutputSettings, Release,
    RigidParams, RockSpec, Scenario, Screen, SimulationSettings,
};
use rockfall_terrain::{Dem, SurfaceMap, Terrain};
use std::collections::BTreeMap;

/// DEM cell size, m (seed 000 §2.1).
pub const CELL_M: f64 = 2.5;
/// Mean gradient, degrees (seed 000 §2.1).
pub const SLOPE_DEG: f64 = 38.0;
/// Rock diameter, m, and density, kg/m³ (seed 000 §2.1).
pub const ROCK_DIAMETER_M: f64 = 0.95;
/// Rock density, kg/m³ (seed 000 §2.1).
pub const ROCK_DENSITY_KG_M3: f64 = 2800.0;
/// Ground distance from the start to the upper edge of the lower forest road, m.
pub const ROAD_START_ALONG_M: f64 = 223.5;
/// Width of the road, m (horizontal).
pub const ROAD_WIDTH_M: f64 = 5.0;
/// Evaluation screens of seed 000 table 3, ground distance from the start, m.
pub const SCREENS_ALONG_M: [f64; 2] = [185.0, 235.0];
/// Unforested upper part of site 2, ground distance from the start, m.
pub const UNFORESTED_TOP_ALONG_M: f64 = 40.0;

const NCOLS: usize = 60;
const NROWS: usize = 142;
const X_MIN_M: f64 = 939_350.0; // Lambert-93 near lat 45°12′, long 6°3′
const Y_MAX_M: f64 = 6_460_400.0;
/// Horizontal distance of the start below the DEM's top edge (centre of row 4), m.
const START_D_M: f64 = 11.25;
const START_COL: usize = 30;

/// Which of the two sites.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Site {
    /// Site 1: the unforested avalanche track.
    One,
    /// Site 2: the forested slope.
    Two,
}

fn geometry(nrows: usize) -> GridGeometry {
    GridGeometry {
        ncols: NCOLS,
        nrows,
        x_min_m: X_MIN_M,
        y_min_m: Y_MAX_M - nrows as f64 * CELL_M,
        cell_size_m: CELL_M,
    }
}

/// How far down the experiments observed each site, ground distance from the start, m:
/// site 1 5 m past its second evaluation screen (235 m, table 3); site 2 to the lower edge of
/// the forest road "that limits the foot of Site 2" (§4).
pub fn observed_extent_along_m(site: Site) -> f64 {
    match site {
        Site::One => SCREENS_ALONG_M[1] + 5.0,
        Site::Two => ROAD_START_ALONG_M + ROAD_WIDTH_M / 3f64.to_radians().cos(),
    }
}

/// The slope profile along the fall line (towards −y).
pub fn profile() -> Profile {
    let c = SLOPE_DEG.to_radians().cos();
    Profile {
        top_z_m: 1400.0,
        sections: vec![
            Section {
                length_m: START_D_M,
                slope_deg: 20.0,
            },
            Section {
                length_m: ROAD_START_ALONG_M * c,
                slope_deg: SLOPE_DEG,
            },
            Section {
                length_m: ROAD_WIDTH_M,
                slope_deg: 3.0,
            },
            Section {
                length_m: 60.0 * c,
                slope_deg: SLOPE_DEG,
            },
            Section {
                length_m: 30.0,
                slope_deg: 25.0,
            },
            Section {
                length_m: 80.0,
                slope_deg: 5.0,
            },
        ],
    }
}

/// Horizontal distance below the top edge of a point `along_m` of ground below the start.
pub fn d_at_along(along_m: f64) -> f64 {
    profile().horizontal_at_slope_distance(START_D_M, along_m)
}

/// Distance along the ground from the start to the point of northing `y_m` on the fall line
/// (negative above the start), m: how seed 000 measures its 185 m and 235 m screens and its
/// 223.5 m.
pub fn along_at_y(y_m: f64) -> f64 {
    profile().slope_distance_m(START_D_M, Y_MAX_M - y_m)
}

/// One parameter of the reconstructed sites: what it is set to and where that comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Assumption {
    /// The parameter.
    pub parameter: &'static str,
    /// Its value on the built-in sites.
    pub value: &'static str,
    /// Its source: the paper's section, or why it was chosen where the paper is silent.
    pub source: &'static str,
}

/// How `vaujany-site1` and `vaujany-site2` are rebuilt, parameter by parameter (none of it
/// tuned to seed 000's tables 2–3).
pub const RECONSTRUCTION: &[Assumption] = &[
    Assumption {
        parameter: "Location, DEM",
        value: "Lambert-93 (EPSG:2154) near lat 45°12′ N, long 6°3′ E; 2.5 m cells, 60 × 142 (150 m × 355 m)",
        source: "seed 000 §2.1 (location, 2.5 m DEM); the extent holds the slope and its run-out",
    },
    Assumption {
        parameter: "Extent `rockfall validate` runs",
        value: "site 1 down to 5 m of ground past the 235 m screen (60 × 82 cells); site 2 down to the lower edge of the road (60 × 78 cells); rocks that run past the cut leave the DEM",
        source: "seed 000: the observations of site 1 reach the 235 m screen (table 3), the road 'limits the foot of Site 2' (§4); the 5 m margin is ours",
    },
    Assumption {
        parameter: "Slope",
        value: "38° from the start down to the lower forest road (223.5 m of ground), 38° for 60 m of ground below the road, then 30 m at 25° and 80 m at 5° (horizontal)",
        source: "seed 000 §2.1: mean gradient 38°; the run-out below the road is ours, so that rocks passing the road can stop inside the DEM",
    },
    Assumption {
        parameter: "Launch area",
        value: "11.25 m (horizontal) at 20° above the start",
        source: "ours: the platform a caterpillar threw the rocks from (seed 000 §2.1)",
    },
    Assumption {
        parameter: "Lower forest road",
        value: "starts 223.5 m along the slope from the start; 5 m wide, 3°",
        source: "seed 000 §3.1 and §4: on site 2 the shares stopped within 223.5 m (66 %), stopped on the road (13 %) and passing it (21 %) add up to 100 %, so the road begins there; its width is a typical forest road's (ours)",
    },
    Assumption {
        parameter: "Cross profile",
        value: "a shallow gully: lateral slope growing to 8°, width scale 25 m",
        source: "ours: keeps the fall line on the corridor the cameras covered; site 1 is an avalanche track (seed 000 §2.1)",
    },
    Assumption {
        parameter: "Soil type (r_n)",
        value: "site 1 class 2 (r_n 0.25–0.31); site 2 class 4 (0.34–0.42); road class 3",
        source: "seed 000 table 4: mean measured r_n 0.26 (site 1) and 0.36 (site 2), each the Rockyfor3D class whose range holds it and whose mean is closest",
    },
    Assumption {
        parameter: "Obstacle heights rg70 / rg20 / rg10",
        value: "site 1 0.17 / 0.25 / 0.35 m; site 2 0.10 / 0.20 / 0.32 m; road 0 / 0.02 / 0.05 m",
        source: "seed 000 table 4: mean measured r_t 0.70 (site 1) and 0.77 (site 2) through eq. 3 with R = 0.475 m give MOH 0.204 m and 0.142 m, the eq. 4 mean of the classes; the spread over the classes is ours (site 1 'relatively uniform', §2.5); road: §4, 'the MOH is very low'",
    },
    Assumption {
        parameter: "Obstacle height per rebound",
        value: "`rockfall validate`: the eq. 4 mean of the cell (`moh = \"mean\"`); the built-in sites otherwise draw a class 70/20/10 % per rebound (the default)",
        source: "seed 000 §3.2: table 2 came from the mean; drawing the class was tried on site 2 only and raised its RMSE by 8 %",
    },
    Assumption {
        parameter: "Rock",
        value: "sphere of 0.95 m, 2800 kg/m³ (1257 kg)",
        source: "seed 000 §2.1",
    },
    Assumption {
        parameter: "Release",
        value: "one source cell at the start; the rock centre 0.5 m above the ground, moving 1 m/s downslope",
        source: "ours: rocks thrown over the edge by a caterpillar (seed 000 §2.1)",
    },
    Assumption {
        parameter: "Forest (site 2)",
        value: "290 stems/ha, DBH 31 ± 21 cm, below the upper 40 m and off the road; Abies alba 50 %, Picea abies 25 %, Fagus sylvatica 17 %, Acer pseudoplatanus 4 %, other broadleaves 4 %; one fixed stem map",
        source: "seed 000 §2.1; the 4 % the paper leaves unnamed are ours",
    },
    Assumption {
        parameter: "Evaluation screens",
        value: "across the slope at 185 m and 235 m along the ground from the start, and on the lower edge of the road (the cut site 2 keeps the first and the road)",
        source: "seed 000 §2.6 and table 3",
    },
];

/// The unknowns of the reconstruction that [`RECONSTRUCTION`] sets where seed 000 is silent
/// or gives a range, with their values on the built-in sites ([`Unknowns::default`]); the
/// validation's sensitivity table moves each across its plausible range
/// ([`Unknowns::ranges`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unknowns {
    /// Release height of the rock centre above the ground, m (0.5).
    pub release_height_m: f64,
    /// Release speed downslope, m/s (1).
    pub release_speed_ms: f64,
    /// Largest lateral slope of the cross-profile's gully, degrees (8).
    pub gully_side_slope_deg: f64,
    /// r_n of the slope (the road keeps its class); `None`: the soil class's mean.
    pub r_n: Option<f64>,
}

impl Default for Unknowns {
    fn default() -> Self {
        Unknowns {
            release_height_m: 0.5,
            release_speed_ms: 1.0,
            gully_side_slope_deg: 8.0,
            r_n: None,
        }
    }
}

impl Unknowns {
    /// Each unknown's plausible range as (name, low, high) variants of the default; r_n spans
    /// the site's soil class (site 1 class 2: 0.25–0.31, site 2 class 4: 0.34–0.42). (The
    /// spread of the three obstacle classes is not among them: the validation rebounds on their
    /// eq. 4 mean, as the paper did, so it does not enter.)
    pub fn ranges(site: Site) -> Vec<(&'static str, Unknowns, Unknowns)> {
        let d = Unknowns::default();
        let (rn_lo, rn_hi) = match site {
            Site::One => (0.25, 0.31),
            Site::Two => (0.34, 0.42),
        };
        vec![
            (
                "release height 0–1.5 m",
                Unknowns {
                    release_height_m: 0.0,
                    ..d
                },
                Unknowns {
                    release_height_m: 1.5,
                    ..d
                },
            ),
            (
                "release speed 0–3 m/s",
                Unknowns {
                    release_speed_ms: 0.0,
                    ..d
                },
                Unknowns {
                    release_speed_ms: 3.0,
                    ..d
                },
            ),
            (
                "gully side slope 0–12°",
                Unknowns {
                    gully_side_slope_deg: 0.0,
                    ..d
                },
                Unknowns {
                    gully_side_slope_deg: 12.0,
                    ..d
                },
            ),
            (
                "r_n across the soil class",
                Unknowns {
                    r_n: Some(rn_lo),
                    ..d
                },
                Unknowns {
                    r_n: Some(rn_hi),
                    ..d
                },
            ),
        ]
    }
}

/// Builds site 1 or site 2 as a scenario, with the run-out below the road.
pub fn build(site: Site) -> Result<Scenario, SiteError> {
    build_rows(site, NROWS, &Unknowns::default())
}

/// Site 1 or site 2 as the experiments observed it and seed 000 simulated it for its table 2:
/// the same slope, cut where the observations end ([`observed_extent_along_m`]), so that each
/// rock's maxima and tree impacts are those on the observed slope (rocks running past the cut
/// leave the DEM; screens below it are dropped); and the obstacle height of every rebound the
/// eq. 4 mean of the cover classes, the method behind table 2 (§3.2: drawing the class per
/// rebound was tried on site 2 only, and raised its RMSE by 8 %).
pub fn build_observed(site: Site) -> Result<Scenario, SiteError> {
    build_observed_with(site, &Unknowns::default())
}

/// [`build_observed`] with the reconstruction's unknowns set to `u`.
pub fn build_observed_with(site: Site, u: &Unknowns) -> Result<Scenario, SiteError> {
    let d_m = d_at_along(observed_extent_along_m(site));
    // the last row's centre at or below the cut: the bilinear surface reaches it
    let nrows = (d_m / CELL_M - 0.5).ceil() as usize + 1;
    let mut s = build_rows(site, nrows.min(NROWS), u)?;
    s.lumped.moh = MohMode::Mean;
    Ok(s)
}

fn build_rows(site: Site, nrows: usize, u: &Unknowns) -> Result<Scenario, SiteError> {
    let g = geometry(nrows);
    let axis_x = g.cell_center(0, START_COL).0;
    let gully = Gully {
        axis_x_m: axis_x,
        width_m: 25.0,
        max_side_slope_deg: u.gully_side_slope_deg,
    };
    let dem_grid = sample_dem(g, &profile(), Some(gully)).with_crs(Some(Crs::from_epsg(2154)));
    let dem = Dem::new(dem_grid)?;

    let road = (
        d_at_along(ROAD_START_ALONG_M),
        d_at_along(ROAD_START_ALONG_M) + ROAD_WIDTH_M,
    );
    let on_road = |row: usize| {
        let d = (row as f64 + 0.5) * CELL_M;
        d >= road.0 && d <= road.1
    };
    let (soil, rg) = match site {
        Site::One => (2.0, [0.17, 0.25, 0.35]),
        Site::Two => (4.0, [0.10, 0.20, 0.32]),
    };
    let per_row = |slope: f64, road_value: f64| {
        Field::Grid(Grid::from_fn(g, |row, _| {
            Some(if on_road(row) { road_value } else { slope })
        }))
    };
    let surface = SurfaceMap {
        soil_type: per_row(soil, 3.0),
        r_n: u.r_n.map(|r_n| {
            let road = rockfall_terrain::SoilType::new(3).map_or(0.33, |c| c.r_n_mean());
            per_row(r_n, road)
        }),
        rolling_friction: None,
        ground_class: None,
        rg70_m: per_row(rg[0], 0.0),
        rg20_m: per_row(rg[1], 0.02),
        rg10_m: per_row(rg[2], 0.05),
    };
    let terrain = Terrain::new(dem, surface)?;

    let start_row = (START_D_M / CELL_M) as usize;
    let release = Release {
        cells: vec![g.index(start_row, START_COL)],
        cell_height_m: u.release_height_m,
        cell_velocity_ms: [0.0, -u.release_speed_ms, 0.0],
        points: Vec::new(),
    };
    let across = |d: f64, name: &str| Screen {
        name: name.into(),
        points_m: vec![[g.x_min_m, Y_MAX_M - d], [g.x_max_m(), Y_MAX_M - d]],
        capacity_kj: None,
        height_m: None,
        net: None,
    };
    let last_centre_d = (nrows as f64 - 0.5) * CELL_M;
    let screens: Vec<Screen> = [
        (d_at_along(SCREENS_ALONG_M[0]), "screen_185m"),
        (d_at_along(SCREENS_ALONG_M[1]), "screen_235m"),
        (road.1, "lower_road"),
    ]
    .into_iter()
    .filter(|&(d, _)| d <= last_centre_d)
    .map(|(d, name)| across(d, name))
    .collect();

    let forest = match site {
        Site::One => None,
        Site::Two => Some(ForestSpec::Stems(site2_stems(&g, &on_road)?)),
    };
    Ok(Scenario {
        name: match site {
            Site::One => "vaujany-site1".into(),
            Site::Two => "vaujany-site2".into(),
        },
        engine: Engine::Lumped,
        seed: 1,
        terrain,
        forest,
        nets: None,
        rock: RockSpec::sphere(ROCK_DIAMETER_M, ROCK_DENSITY_KG_M3),
        release,
        screens,
        lumped: LumpedSettings::default(),
        rigid: RigidParams::default(),
        contact: ContactSettings::default(),
        simulation: SimulationSettings {
            rocks_per_cell: 10_000,
            // a safeguard only: a rock hopping slowly down the whole 310 m slope needs more
            // than the 60 s default, and a rock still moving is not a stopped rock
            max_time_s: 600.0,
            ..SimulationSettings::default()
        },
        output: OutputSettings::default(),
        sources: BTreeMap::new(),
        notes: Vec::new(),
        tile: None,
    })
}

/// Site 2's stems: 290 stems/ha, DBH 31 ± 21 cm below the upper 40 m, none on the road;
/// species by the shares of seed 000 §2.1.
fn site2_stems(
    g: &GridGeometry,
    on_road: &dyn Fn(usize) -> bool,
) -> Result<Vec<rockfall_forest::Stem>, SiteError> {
    let forest_top_d = d_at_along(UNFORESTED_TOP_ALONG_M);
    let cell = |row: usize, _col: usize| {
        // cells wholly below the unforested top, off the road
        let d_top_edge = row as f64 * CELL_M;
        (d_top_edge >= forest_top_d && !on_road(row)).then_some(StandCell {
            stems_per_ha: 290.0,
            dbh_mean_cm: 31.0,
            dbh_sd_cm: 21.0,
            conifer_percent: 75.0,
            height: None,
        })
    };
    let mut stems = expand_stands(g, cell, SITE_SEED, &StandOptions::default())?;
    for (i, s) in stems.iter_mut().enumerate() {
        let u: f64 = stream(SITE_SEED, Purpose::SiteBuild, &[2, i as u64]).random();
        s.species = species_share(u);
    }
    Ok(stems)
}

/// Species by cumulative share: Abies 50 %, Picea 25 %, Fagus 17 %, Acer 4 %, unnamed 4 % (as other broadleaves).
fn species_share(u: f64) -> Species {
    match u {
        u if u < 0.50 => Species::AbiesAlba,
        u if u < 0.75 => Species::PiceaAbies,
        u if u < 0.92 => Species::FagusSylvatica,
        u if u < 0.96 => Species::AcerPseudoplatanus,
        _ => Species::OtherBroadleaf,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screens_and_road_sit_at_the_paper_distances() {
        let p = profile();
        // ground distance from the start to each screen, integrated numerically
        let ground = |d1: f64| {
            let n = 20_000;
            let h = (d1 - START_D_M) / n as f64;
            (0..n)
                .map(|k| {
                    let a = START_D_M + k as f64 * h;
                    (h * h + (p.z_m(a + h) - p.z_m(a)).powi(2)).sqrt()
                })
                .sum::<f64>()
        };
        for s in SCREENS_ALONG_M {
            assert!((ground(d_at_along(s)) - s).abs() < 0.01, "{s}");
        }
        assert!((ground(d_at_along(ROAD_START_ALONG_M)) - 223.5).abs() < 0.01);
        // mean gradient of the slope between start and road is 38°
        let d0 = START_D_M;
        let d1 = d_at_along(ROAD_START_ALONG_M);
        let mean = ((p.z_m(d0) - p.z_m(d1)) / (d1 - d0)).atan().to_degrees();
        assert!((mean - 38.0).abs() < 1e-9);
        assert!(p.length_m() <= NROWS as f64 * CELL_M);
    }

    #[test]
    fn observed_sites_end_below_their_last_observation() {
        for site in [Site::One, Site::Two] {
            let full = build(site).unwrap();
            let cut = build_observed(site).unwrap();
            let (gf, gc) = (full.terrain.dem.geometry(), cut.terrain.dem.geometry());
            assert!(gc.nrows < gf.nrows && gc.y_max_m() == gf.y_max_m());
            // the last cell centre lies below the extent, by less than a cell
            let last = gc.cell_center(gc.nrows - 1, 0).1;
            let extent = (Y_MAX_M - last) - d_at_along(observed_extent_along_m(site));
            assert!((0.0..CELL_M).contains(&extent), "{extent}");
            // the same ground where both have it
            for i in [0, 7 * NCOLS + 3, gc.len() - 1] {
                assert_eq!(
                    full.terrain.dem.grid().get_index(i),
                    cut.terrain.dem.grid().get_index(i)
                );
            }
            // table 2's rebounds: the eq. 4 mean obstacle height
            assert_eq!(
                (cut.lumped.moh, full.lumped.moh),
                (MohMode::Mean, MohMode::Draw)
            );
            let names: Vec<&str> = cut.screens.iter().map(|s| s.name.as_str()).collect();
            match site {
                Site::One => assert_eq!(names, ["screen_185m", "screen_235m", "lower_road"]),
                Site::Two => assert_eq!(names, ["screen_185m", "lower_road"]),
            }
        }
        // site 2's stems stop at the cut
        let cut = build_observed(Site::Two).unwrap();
        let y_min = cut.terrain.dem.geometry().y_min_m;
        assert!(
            cut.build_forest()
                .unwrap()
                .stems()
                .iter()
                .all(|t| t.y_m >= y_min)
        );
    }

    #[test]
    fn along_slope_distances_invert_the_profile() {
        for along in [0.0, 40.0, 185.0, 223.5, 235.0, 280.0] {
            let y = Y_MAX_M - d_at_along(along);
            assert!((along_at_y(y) - along).abs() < 1e-9, "{along}");
        }
        assert!(along_at_y(Y_MAX_M - 5.0) < 0.0, "above the start");
    }

    #[test]
    fn site2_forest_matches_the_stand_description() {
        let s = build(Site::Two).unwrap();
        let f = s.build_forest().unwrap();
        let stems = f.stems();
        let g = s.terrain.dem.geometry();
        let forest_top = Y_MAX_M - d_at_along(UNFORESTED_TOP_ALONG_M);
        assert!(
            stems.iter().all(|t| t.y_m < forest_top),
            "upper 40 m unforested"
        );
        // area of forested cells
        let forested_rows = (0..g.nrows)
            .filter(|&r| {
                let d = (r as f64 + 0.5) * CELL_M;
                let road0 = d_at_along(ROAD_START_ALONG_M);
                r as f64 * CELL_M >= d_at_along(UNFORESTED_TOP_ALONG_M)
                    && !(d >= road0 && d <= road0 + ROAD_WIDTH_M)
            })
            .count();
        let area_ha = forested_rows as f64 * g.ncols as f64 * CELL_M * CELL_M / 1e4;
        let density = stems.len() as f64 / area_ha;
        // Poisson-like sd ≈ sqrt(n); allow 4 sd
        let n = 290.0 * area_ha;
        assert!(
            (density - 290.0).abs() < 4.0 * n.sqrt() / area_ha,
            "{density}"
        );
        let (_, mean, _) = f.dbh_stats_cm().unwrap();
        assert!(
            (mean - 31.0).abs() < 4.0 * 21.0 / (stems.len() as f64).sqrt(),
            "{mean}"
        );
        let abies = stems
            .iter()
            .filter(|t| t.species == Species::AbiesAlba)
            .count() as f64;
        let p = abies / stems.len() as f64;
        assert!(
            (p - 0.5).abs() < 4.0 * (0.25 / stems.len() as f64).sqrt(),
            "{p}"
        );
    }
}

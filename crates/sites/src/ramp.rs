//! The 40° ramp of Leine et al. (2021, "Stability of rigid body motion through an extended
//! intermediate axis theorem: application to rockfall simulation", Multibody Syst. Dyn. 52),
//! for the rigid engine: EOTA₂₂₁ blocks down a plane, 1 000 rocks at Δt = 2 ms, whose mean
//! (sd) energy, speed, rotation and jump height the paper reports.
//!
//! Given by the paper (§6, §6.1, table 2): a 40° ramp ("an idealized digital elevation model
//! with an inclined slope of 40°" running out onto a flat area); the EOTA₂₂₁ block of 780 kg,
//! "homogeneously distributed in a rigid body with dimensions of 0.93, 0.93, and 0.47 m along
//! the three principal axes"; 1 000 simulations whose "initial rock orientation was the only
//! varying input parameter"; Δt = 2 ms; the soil of Lu et al. 2019 (the same authors' scarring
//! ground, reference [17]): here the `medium` ground class, their whole-trajectory set.
//!
//! Ours, because the paper does not give them:
//!
//! - **the ramp**: a plane of 40° over 100 m (horizontal) with 10 m above the release, then a
//!   horizontal plane of 60 m; 80 m wide; 1 m grid (a plane is exact on any grid);
//! - **the block's size**: EOTA₂₂₁'s 2:2:1 shape scaled to 0.93 × 0.93 × 0.465 m (0.285 m³;
//!   the paper's 0.47 is that rounded), at the density that makes 780 kg (2 738 kg/m³);
//! - **the release**: at rest, the lowest vertex 2 m above the ground, a random orientation
//!   per rock;
//! - **the statistics** (`rockfall validate`): over every trajectory row (every 0.05 s) of
//!   every rock while its centre is above the ramp's 40° section, excluding the final row.
use crate::SiteError;
use crate::profile::{Profile, Section, sample_dem};
use rockfall_raster::GridGeometry;
use rockfall_scenario::{Engine, Release, ReleasePoint, RockSpec, Scenario};
use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};

/// Ramp angle, degrees.
pub const RAMP_DEG: f64 = 40.0;
/// Horizontal length of the ramp below the release, m (ours).
pub const RAMP_LENGTH_M: f64 = 100.0;
/// Block mass, kg (Leine et al. 2021 §6).
pub const BLOCK_MASS_KG: f64 = 780.0;
/// The block's length along its two major axes, m (Leine et al. 2021 §6).
pub const BLOCK_LENGTH_M: f64 = 0.93;
/// Rocks of the published run.
pub const ROCKS: u64 = 1000;

const CELL_M: f64 = 1.0;
const ABOVE_M: f64 = 10.0;
const PLANE_M: f64 = 60.0;
const WIDTH_M: f64 = 80.0;

/// The y (m) of the foot of the ramp: rows above it are on the 40° section.
pub fn foot_y_m() -> f64 {
    PLANE_M
}

/// Volume of the EOTA₂₂₁ block whose major axes are [`BLOCK_LENGTH_M`] long, m³: the
/// named shape's volume (1 m³) times the cube of the length ratio.
pub fn block_volume_m3() -> Option<f64> {
    let dims = rockfall_scenario::rock::named_dims("eota221")?;
    Some((BLOCK_LENGTH_M / dims[0]).powi(3))
}

/// Builds the site.
pub fn build() -> Result<Scenario, SiteError> {
    let t = RAMP_DEG.to_radians().tan();
    let length = ABOVE_M + RAMP_LENGTH_M + PLANE_M;
    let g = GridGeometry {
        ncols: (WIDTH_M / CELL_M) as usize,
        nrows: (length / CELL_M).round() as usize,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: CELL_M,
    };
    let profile = Profile {
        top_z_m: (ABOVE_M + RAMP_LENGTH_M) * t,
        sections: vec![
            Section {
                length_m: ABOVE_M + RAMP_LENGTH_M,
                slope_deg: RAMP_DEG,
            },
            Section {
                length_m: PLANE_M,
                slope_deg: 0.0,
            },
        ],
    };
    let dem = Dem::new(sample_dem(g, &profile, None))?;
    let soil = SoilType::new(4).ok_or(SiteError::Internal)?;
    let terrain = Terrain::new(dem, SurfaceMap::uniform(soil, 0.0, 0.0, 0.0))?;
    let volume_m3 = block_volume_m3().ok_or(SiteError::Internal)?;
    let rock = RockSpec::named("eota221", Some(volume_m3), BLOCK_MASS_KG / volume_m3)
        .ok_or(SiteError::Internal)?;
    let release = Release {
        points: vec![ReleasePoint::at_rest(
            WIDTH_M / 2.0,
            g.y_max_m() - ABOVE_M,
            2.0,
        )],
        ..Release::default()
    };
    let mut scenario = Scenario::new("leine-ramp-40", terrain, rock, release);
    scenario.engine = Engine::Rigid;
    scenario.contact = crate::forest_slope::scarring_contact();
    scenario.simulation.rocks_per_point = ROCKS;
    scenario.simulation.dt_s = 0.002;
    Ok(scenario)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_geometry_and_block() {
        let s = build().unwrap();
        let dem = &s.terrain.dem;
        let (x, y) = (WIDTH_M / 2.0, foot_y_m() + 50.0);
        assert!((dem.slope_deg(x, y).unwrap() - RAMP_DEG).abs() < 1e-6);
        assert!(
            dem.height_m(x, foot_y_m() - 10.0).unwrap().abs() < 1e-9,
            "plane at 0"
        );
        let release = &s.release.points[0];
        let expected_z = (release.y_m - foot_y_m()) * RAMP_DEG.to_radians().tan();
        assert!((dem.height_m(release.x_m, release.y_m).unwrap() - expected_z).abs() < 1e-6);
        assert_eq!(s.simulation.dt_s, 0.002);
        let v = s.rock.volume_m3.unwrap();
        assert!((v - 17.0 / 24.0 * 0.93 * 0.93 * 0.465).abs() < 2e-4, "{v}");
        let rho = s.rock.density_kg_m3.at(0, 0).unwrap();
        assert!((rho * v - 780.0).abs() < 1e-9, "{rho}");
        assert_eq!(s.contact.model, rockfall_scenario::GroundModel::Scarring);
        s.validate().unwrap();
    }
}

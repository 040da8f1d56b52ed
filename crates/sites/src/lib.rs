//! Built-in synthetic sites: complete scenarios built in memory, written as real input files
//! by `rockfall site NAME --out DIR`, run by `rockfall demo` and `rockfall validate`.
//!
//! | name | from | engine |
//! |---|---|---|
//! | `vaujany-site1` | seed 000 §2.1: the unforested avalanche track | lumped |
//! | `vaujany-site2` | seed 000 §2.1: the forested slope | lumped |
//! | `forest-slope-40` | seed 001 §3.4: the forested virtual 40° slope | rigid |
//!
//! | `alpine-region` | a procedural mountain region of 10⁴–4·10⁹ cells, written as COGs ([`region`]) | lumped |
//!
//! Each module documents what its paper gives and how every unknown (profile, roughness, soil
//! type, release) was chosen, with its source. Nothing is tuned to the observed results.

pub mod forest_slope;
pub mod profile;
pub mod ramp;
pub mod region;
pub mod vaujany;

use rockfall_scenario::Scenario;

/// Seed of the random draws that build the sites (stems), fixed so that a site is the same
/// in every run; runs draw from the scenario's own seed.
pub const SITE_SEED: u64 = 2006;

/// The built-in sites: (name, one-line description).
pub const SITES: [(&str, &str); 4] = [
    (
        "vaujany-site1",
        "seed 000: Vaujany site 1, open 38° avalanche track, 0.95 m spheres",
    ),
    (
        "vaujany-site2",
        "seed 000: Vaujany site 2, the same slope forested below its upper 40 m",
    ),
    (
        "forest-slope-40",
        "seed 001: 40° virtual slope, 200 m drop, 500 stems/ha, rigid engine, scarring ground",
    ),
    (
        "leine-ramp-40",
        "Leine et al. 2021: 780 kg EOTA221 blocks down a bare 40° ramp, rigid engine, scarring \
         ground, dt 2 ms",
    ),
];

/// The regional test site, written by [`region::write`] rather than built in memory.
pub const REGION_SITE: (&str, &str) = (
    "alpine-region",
    "procedural mountain region (--cells 10⁴–4·10⁹, 5 m cells): cliffs, talus, valleys, \
     forest stands; tiled COGs",
);

/// Why a site could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SiteError {
    /// No site of that name.
    #[error("unknown site `{0}` (built-in sites: {names})", names = SITES.map(|s| s.0).join(", "))]
    Unknown(String),
    /// Terrain construction failed.
    #[error(transparent)]
    Terrain(#[from] rockfall_terrain::TerrainError),
    /// Forest construction failed.
    #[error(transparent)]
    Forest(#[from] rockfall_forest::ForestError),
    /// A built-in constant is inconsistent (a bug).
    #[error("internal error building a site")]
    Internal,
}

/// Builds a site by name.
pub fn build(name: &str) -> Result<Scenario, SiteError> {
    match name {
        "vaujany-site1" => vaujany::build(vaujany::Site::One),
        "vaujany-site2" => vaujany::build(vaujany::Site::Two),
        "forest-slope-40" => forest_slope::build(),
        "leine-ramp-40" => ramp::build(),
        other => Err(SiteError::Unknown(other.into())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_site_builds_and_validates() {
        for (name, _) in SITES {
            let s = build(name).unwrap();
            assert_eq!(s.name, name);
            s.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        assert!(
            build("nowhere")
                .unwrap_err()
                .to_string()
                .contains("vaujany-site1")
        );
    }
}

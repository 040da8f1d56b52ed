//! Trees for rockfall simulation: stems, species, stand expansion and a spatial index.
//!
//! A rock crossing a forest loses energy on the stems it hits, so both engines need to know
//! where every stem stands, how thick it is and how tall. This crate provides:
//!
//! - [`Stem`]: one tree as a vertical cylinder (position, DBH, height, [`Species`]);
//! - [`expand_stands`]: turns per-cell stand descriptions ([`StandCell`]: stems/ha, DBH mean
//!   and sd, conifer share, optional heights) into explicit stems, reproducibly from the master
//!   seed; DBH follows a truncated normal fitted to the stand's mean and sd
//!   ([`truncated_normal`]), heights a generic allometry ([`allometry`]) unless given;
//! - [`StemIndex`]: a uniform bucket grid answering "which stems come within r of this point
//!   or this segment?" without allocating;
//! - [`Forest`]: validated stems together with their index, plus summary statistics;
//! - [`normal`]: accurate standard-normal Φ, tail and quantile, on which the truncated
//!   normal builds.
//!
//! - [`ImpactType`]: the frontal / lateral / scratch classes of an impact's eccentricity.
//!
//! Fracture-energy ratios and the impact physics live with the engines, not here.
//!
//! ```
//! use rockfall_forest::{Forest, Species, Stem};
//! let stems = vec![
//!     Stem { x_m: 2.0, y_m: 3.0, dbh_cm: 30.0, height_m: 20.0, species: Species::PiceaAbies },
//!     Stem { x_m: 9.0, y_m: 3.0, dbh_cm: 50.0, height_m: 25.0, species: Species::FagusSylvatica },
//! ];
//! let forest = Forest::new(stems)?;
//! // A rock of radius 0.4 m moving from (0, 3) to (5, 3): which trunks can it touch?
//! let hits = forest.index().within_segment((0.0, 3.0), (5.0, 3.0), 0.4);
//! assert_eq!(hits.len(), 1);
//! assert_eq!(hits[0].index, 0);
//! assert_eq!(forest.conifer_share(), Some(0.5));
//! # Ok::<(), rockfall_forest::ForestError>(())
//! ```

pub mod allometry;
mod error;
pub mod impact_type;
pub mod index;
pub mod normal;
mod species;
pub mod stand;
mod stem;
pub mod truncated_normal;

pub use allometry::height_from_dbh_m;
pub use error::ForestError;
pub use impact_type::ImpactType;
pub use index::{DEFAULT_BUCKET_SIZE_M, StemHit, StemIndex};
pub use species::Species;
pub use stand::{StandCell, StandOptions, expand_stands, expand_stands_in};
pub use stem::{BREAST_HEIGHT_M, Stem};

/// A validated set of stems and their spatial index.
#[derive(Debug, Clone, PartialEq)]
pub struct Forest {
    stems: Vec<Stem>,
    index: StemIndex,
}

impl Forest {
    /// Validates every stem ([`Stem::validate`]) and indexes them with
    /// [`DEFAULT_BUCKET_SIZE_M`] buckets. The error names the first invalid stem's position.
    pub fn new(stems: Vec<Stem>) -> Result<Forest, ForestError> {
        Self::with_bucket_size(stems, DEFAULT_BUCKET_SIZE_M)
    }

    /// As [`Forest::new`], with index buckets of `bucket_size_m` (m, finite and > 0).
    pub fn with_bucket_size(stems: Vec<Stem>, bucket_size_m: f64) -> Result<Forest, ForestError> {
        for (index, stem) in stems.iter().enumerate() {
            stem.validate()
                .map_err(|reason| ForestError::InvalidStem { index, reason })?;
        }
        let index = StemIndex::new(&stems, bucket_size_m)?;
        Ok(Forest { stems, index })
    }

    /// The stems, in the order given; [`StemHit::index`] refers to this slice.
    pub fn stems(&self) -> &[Stem] {
        &self.stems
    }

    /// The spatial index over [`Forest::stems`].
    pub fn index(&self) -> &StemIndex {
        &self.index
    }

    /// Number of stems.
    pub fn len(&self) -> usize {
        self.stems.len()
    }

    /// True when there are no stems.
    pub fn is_empty(&self) -> bool {
        self.stems.is_empty()
    }

    /// Smallest, mean and largest DBH, cm; `None` without stems.
    pub fn dbh_stats_cm(&self) -> Option<(f64, f64, f64)> {
        let (min, max, sum) = self.stems.iter().fold(
            (f64::INFINITY, f64::NEG_INFINITY, 0.0),
            |(min, max, sum), s| (min.min(s.dbh_cm), max.max(s.dbh_cm), sum + s.dbh_cm),
        );
        (!self.is_empty()).then(|| (min, sum / self.len() as f64, max))
    }

    /// Smallest and largest tree height, m; `None` without stems.
    pub fn height_range_m(&self) -> Option<(f64, f64)> {
        let (min, max) = self
            .stems
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(min, max), s| {
                (min.min(s.height_m), max.max(s.height_m))
            });
        (!self.is_empty()).then_some((min, max))
    }

    /// Share of conifers (0–1) among the stems whose type is known (stems of
    /// [`Species::Unknown`] are left out); `None` when no stem has a known type.
    pub fn conifer_share(&self) -> Option<f64> {
        let (known, conifers) = self
            .stems
            .iter()
            .filter_map(|s| s.species.is_conifer())
            .fold((0usize, 0usize), |(known, conifers), c| {
                (known + 1, conifers + usize::from(c))
            });
        (known > 0).then(|| conifers as f64 / known as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stem(x_m: f64, dbh_cm: f64, height_m: f64, species: Species) -> Stem {
        Stem {
            x_m,
            y_m: 0.0,
            dbh_cm,
            height_m,
            species,
        }
    }

    #[test]
    fn new_names_the_invalid_stem() {
        let stems = vec![
            stem(0.0, 30.0, 20.0, Species::AbiesAlba),
            stem(1.0, 30.0, 1.0, Species::AbiesAlba),
        ];
        match Forest::new(stems) {
            Err(ForestError::InvalidStem { index, reason }) => {
                assert_eq!(index, 1);
                assert!(reason.contains("height"), "{reason}");
            }
            other => panic!("expected InvalidStem, got {other:?}"),
        }
    }

    #[test]
    fn summaries() {
        let forest = Forest::new(vec![
            stem(0.0, 20.0, 15.0, Species::AbiesAlba),
            stem(1.0, 40.0, 25.0, Species::FagusSylvatica),
            stem(2.0, 60.0, 30.0, Species::Unknown),
            stem(3.0, 40.0, 20.0, Species::LarixDecidua),
        ])
        .expect("valid");
        assert_eq!(forest.len(), 4);
        assert_eq!(forest.dbh_stats_cm(), Some((20.0, 40.0, 60.0)));
        assert_eq!(forest.height_range_m(), Some((15.0, 30.0)));
        assert_eq!(forest.conifer_share(), Some(2.0 / 3.0));
        assert_eq!(forest.index().len(), 4);
    }

    #[test]
    fn empty_forest() {
        let forest = Forest::new(Vec::new()).expect("empty is valid");
        assert!(forest.is_empty());
        assert_eq!(forest.dbh_stats_cm(), None);
        assert_eq!(forest.height_range_m(), None);
        assert_eq!(forest.conifer_share(), None);
        let unknown = Forest::new(vec![stem(0.0, 30.0, 20.0, Species::Unknown)]).expect("valid");
        assert_eq!(unknown.conifer_share(), None);
    }
}

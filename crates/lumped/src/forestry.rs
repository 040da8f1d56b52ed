//! Stems as the engine needs them: position, radius, top height, the energy each can take
//! (seed 000 eq. 2) and its cell, in one compact array beside the forest's spatial index.

use crate::ground::Ground;
use crate::trees::{fe_ratio, max_dissipation_j};
use rockfall_forest::{Forest, StemIndex};

/// One stem, precomputed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StemData {
    /// Axis position, m.
    pub x_m: f64,
    /// Axis position, m.
    pub y_m: f64,
    /// Trunk radius DBH/2, m.
    pub radius_m: f64,
    /// Ground height at the stem, m.
    pub base_z_m: f64,
    /// Height of the stem's top, m a.s.l. (−∞ for a stem off the terrain: never hit).
    pub top_z_m: f64,
    /// Largest energy the stem can dissipate, J (seed 000 eq. 2 with the species' FE ratio).
    pub e_max_j: f64,
    /// Row-major index of the cell holding the stem.
    pub cell: usize,
}

/// The forest of a run.
#[derive(Debug)]
pub struct Trees<'f> {
    index: &'f StemIndex,
    stems: Vec<StemData>,
}

impl<'f> Trees<'f> {
    /// Precomputes every stem of `forest` on `ground`.
    pub fn new(forest: &'f Forest, ground: &Ground) -> Trees<'f> {
        let stems = forest
            .stems()
            .iter()
            .map(|s| {
                let base = ground.height_m(s.x_m, s.y_m);
                let cell = ground.cell_index(s.x_m, s.y_m);
                let (base_z_m, top_z_m, cell) = match (base, cell) {
                    (Some(z), Some(c)) => (z, z + s.height_m, c),
                    _ => (f64::NAN, f64::NEG_INFINITY, 0),
                };
                StemData {
                    x_m: s.x_m,
                    y_m: s.y_m,
                    radius_m: s.radius_m(),
                    base_z_m,
                    top_z_m,
                    e_max_j: max_dissipation_j(fe_ratio(s.species), s.dbh_cm),
                    cell,
                }
            })
            .collect();
        Trees {
            index: forest.index(),
            stems,
        }
    }

    /// The spatial index (its stem numbers index [`Trees::stem`]).
    #[inline]
    pub fn index(&self) -> &StemIndex {
        self.index
    }

    /// Stem `i`.
    #[inline]
    pub fn stem(&self, i: usize) -> &StemData {
        &self.stems[i]
    }

    /// Number of stems.
    pub fn len(&self) -> usize {
        self.stems.len()
    }

    /// True without stems.
    pub fn is_empty(&self) -> bool {
        self.stems.is_empty()
    }
}

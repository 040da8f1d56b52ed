//! One release list, rock numbering and random-stream key scheme for both engines.

use rockfall_scenario::{Scenario, StartHeight};
use std::ops::Range;

/// Where a release comes from in the scenario.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    /// A source cell (row-major index on the DEM's grid).
    Cell(usize),
    /// The scenario's release point with this index.
    Point(usize),
}

/// One release: a source cell or a point, how its rocks start and how many there are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Release {
    /// The source cell or release point.
    pub origin: Origin,
    /// Release position in plan (x, y), m: the cell centre or the point.
    pub xy_m: [f64; 2],
    /// How high the rock starts: a gap between the ground under its centre and its lowest
    /// point (m, ≥ 0), or its centre's elevation (m); see [`StartHeight`].
    pub start: StartHeight,
    /// Initial velocity (x, y, z), m/s.
    pub velocity_ms: [f64; 3],
    /// Initial angular velocity (x, y, z) in the world frame, rad/s.
    pub angular_velocity_rads: [f64; 3],
    /// Initial orientation as a quaternion (w, x, y, z); `None` → random per rock.
    pub orientation_wxyz: Option<[f64; 4]>,
    /// Rocks released.
    pub rocks: u64,
}

impl Release {
    /// The key of this release's random streams: (0, cell) for a source cell, (1, point) for
    /// a release point; rock k draws from the stream keyed by the key and k.
    pub fn key(&self) -> [u64; 2] {
        match self.origin {
            Origin::Cell(cell) => [0, cell as u64],
            Origin::Point(k) => [1, k as u64],
        }
    }

    /// `Ok` when the rock, reaching `extent_below_m` (m) below its centre, starts out of the
    /// ground at `ground_z_m` (m) under its centre; a `z_m` that puts it in the ground is an
    /// [`InsideGround`] error naming the release point.
    pub fn check_fits(&self, ground_z_m: f64, extent_below_m: f64) -> Result<(), InsideGround> {
        match self.start {
            StartHeight::CentreZ { z_m } if !self.start.fits(ground_z_m, extent_below_m) => {
                Err(InsideGround {
                    point: match self.origin {
                        Origin::Point(k) => Some(k),
                        Origin::Cell(_) => None,
                    },
                    xy_m: self.xy_m,
                    z_m,
                    ground_z_m,
                    extent_below_m,
                })
            }
            _ => Ok(()),
        }
    }
}

/// A release point whose `z_m` puts its rock (partly) in the ground: the centre less than the
/// rock's reach below it above the ground under the centre.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error(
    "{}: z_m = {z_m} m puts the rock into the ground: the ground under its centre ({}, {}) \
     is at {ground_z_m:.3} m and the rock reaches {extent_below_m:.3} m below its centre, so \
     z_m must be at least {:.3} m",
    point.map_or("release".to_string(), |k| format!("release.points[{k}]")),
    xy_m[0],
    xy_m[1],
    ground_z_m + extent_below_m
)]
pub struct InsideGround {
    /// The release point's index in the scenario (`None` for a source cell).
    pub point: Option<usize>,
    /// The point (x, y), m.
    pub xy_m: [f64; 2],
    /// The elevation asked for the centre, m.
    pub z_m: f64,
    /// The ground's elevation under the centre, m.
    pub ground_z_m: f64,
    /// How far the rock reaches below its centre, m.
    pub extent_below_m: f64,
}

/// The releases of a scenario with the global numbering of their rocks.
#[derive(Debug, Clone, PartialEq)]
pub struct Releases {
    list: Vec<Release>,
    numbering: RockNumbering,
}

impl Releases {
    /// The releases of `scenario` (already validated): its source cells first, ascending, each
    /// with `rocks_per_cell` rocks released with the gap `cell_height_m` over the cell centre,
    /// then its points in file order with `rocks_per_point` rocks each. Negative gaps count
    /// as 0.
    ///
    /// For a spatial tile ([`Scenario::tile`]): the core's source cells, then the points in
    /// the core, each numbered as in the region's run (source cell by its number among the
    /// region's, point by its index), so that its rocks are the region's rocks of the same
    /// numbers.
    pub fn of(scenario: &Scenario) -> Releases {
        let all = Releases::listed(scenario);
        let Some(tile) = &scenario.tile else {
            return Releases::new(all);
        };
        let (rpc, rpp) = (
            scenario.simulation.rocks_per_cell,
            scenario.simulation.rocks_per_point,
        );
        let g = *scenario.terrain.dem.geometry();
        let cells_end = tile.region_source_cells.saturating_mul(rpc);
        let mut placed = Vec::with_capacity(all.len());
        for r in all {
            let first = match r.origin {
                Origin::Cell(k) => {
                    let at = scenario.release.cells.binary_search(&k).unwrap_or(0);
                    tile.ordinals
                        .get(at)
                        .copied()
                        .unwrap_or(0)
                        .saturating_mul(rpc)
                }
                Origin::Point(k) => {
                    let inside = g.cell_of(r.xy_m[0], r.xy_m[1]);
                    if !inside.is_some_and(|(row, col)| tile.core.contains(row, col)) {
                        continue;
                    }
                    cells_end.saturating_add((k as u64).saturating_mul(rpp))
                }
            };
            placed.push((r, first));
        }
        let total =
            cells_end.saturating_add((scenario.release.points.len() as u64).saturating_mul(rpp));
        let numbering = RockNumbering::placed(placed.iter().map(|(r, f)| (*f, r.rocks)), total);
        Releases {
            list: placed.into_iter().map(|(r, _)| r).collect(),
            numbering,
        }
    }

    /// Every release the scenario lists, in release order.
    fn listed(scenario: &Scenario) -> Vec<Release> {
        let g = *scenario.terrain.dem.geometry();
        let rel = &scenario.release;
        let sim = &scenario.simulation;
        let cells = rel.cells.iter().map(|&cell| {
            let (row, col) = g.row_col(cell);
            let (x, y) = g.cell_center(row, col);
            Release {
                origin: Origin::Cell(cell),
                xy_m: [x, y],
                start: StartHeight::Gap {
                    gap_m: rel.cell_height_m.max(0.0),
                },
                velocity_ms: rel.cell_velocity_ms,
                angular_velocity_rads: [0.0; 3],
                orientation_wxyz: None,
                rocks: sim.rocks_per_cell,
            }
        });
        let points = rel.points.iter().enumerate().map(|(k, pt)| Release {
            origin: Origin::Point(k),
            xy_m: [pt.x_m, pt.y_m],
            start: pt.start.with_gap_at_least_zero(),
            velocity_ms: pt.velocity_ms,
            angular_velocity_rads: pt.angular_velocity_rads,
            orientation_wxyz: pt.orientation_wxyz,
            rocks: sim.rocks_per_point,
        });
        cells.chain(points).collect()
    }

    /// The rock numbers of every release, as sorted disjoint ranges.
    pub fn rock_set(&self) -> crate::RockSet {
        crate::RockSet::from_ranges((0..self.list.len()).map(|k| self.rocks_of(k)))
    }

    /// Releases in the given order.
    pub fn new(list: Vec<Release>) -> Releases {
        let numbering = RockNumbering::new(list.iter().map(|r| r.rocks));
        Releases { list, numbering }
    }

    /// The releases, in numbering order.
    pub fn list(&self) -> &[Release] {
        &self.list
    }

    /// Rocks over all releases.
    pub fn rocks(&self) -> u64 {
        self.numbering.total()
    }

    /// The numbering of the rocks.
    pub fn numbering(&self) -> &RockNumbering {
        &self.numbering
    }

    /// The global numbers of release `k`'s rocks.
    pub fn rocks_of(&self, k: usize) -> Range<u64> {
        self.numbering.range(k)
    }
}

/// Global rock numbers over a list of releases: release k owns the consecutive numbers
/// `first[k] .. end[k]`, in release order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RockNumbering {
    first: Vec<u64>,
    end: Vec<u64>,
    total: u64,
}

impl RockNumbering {
    /// Numbers the rocks of releases with `counts` rocks each.
    pub fn new(counts: impl IntoIterator<Item = u64>) -> RockNumbering {
        let mut total = 0u64;
        let (first, end) = counts
            .into_iter()
            .map(|n| {
                let f = total;
                total = total.saturating_add(n);
                (f, total)
            })
            .unzip();
        RockNumbering { first, end, total }
    }

    /// Numbers releases that own `(first, count)` numbers each, ascending and disjoint, out of
    /// `total` (a tile's releases among a region's: the numbers between belong to others).
    pub fn placed(releases: impl IntoIterator<Item = (u64, u64)>, total: u64) -> RockNumbering {
        let (first, end) = releases
            .into_iter()
            .map(|(f, n)| (f, f.saturating_add(n)))
            .unzip();
        RockNumbering { first, end, total }
    }

    /// Number of rocks over all releases.
    pub fn total(&self) -> u64 {
        self.total
    }

    /// The release of global rock `id` (< [`RockNumbering::total`]) and the rock's index
    /// within that release.
    pub fn locate(&self, id: u64) -> (usize, u64) {
        let k = self.first.partition_point(|&f| f <= id).saturating_sub(1);
        (k, id - self.first.get(k).copied().unwrap_or(0))
    }

    /// The global numbers of release `k`'s rocks (empty for an unknown release).
    pub fn range(&self, k: usize) -> Range<u64> {
        let start = self.first.get(k).copied().unwrap_or(self.total);
        let end = self.end.get(k).copied().unwrap_or(self.total);
        start..end.max(start)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rocks_are_numbered_release_after_release_skipping_empty_ones() {
        let n = RockNumbering::new([3, 0, 2]);
        assert_eq!(n.total(), 5);
        let located: Vec<_> = (0..5).map(|id| n.locate(id)).collect();
        assert_eq!(located, [(0, 0), (0, 1), (0, 2), (2, 0), (2, 1)]);
        assert_eq!([n.range(0), n.range(1), n.range(2)], [0..3, 3..3, 3..5]);
        assert_eq!(n.range(7), 5..5);
    }

    #[test]
    fn cells_and_points_have_keys_of_their_own() {
        let r = |origin| Release {
            origin,
            xy_m: [0.0; 2],
            start: StartHeight::Gap { gap_m: 0.0 },
            velocity_ms: [0.0; 3],
            angular_velocity_rads: [0.0; 3],
            orientation_wxyz: None,
            rocks: 1,
        };
        assert_eq!(r(Origin::Cell(7)).key(), [0, 7]);
        assert_eq!(r(Origin::Point(7)).key(), [1, 7]);
    }
}

//! Rockfall nets, as both engines meet them (Rockyfor3D's nets, Dorren 2016 §2.3).
//!
//! A net is a set of cells with a number, an energy capacity and a height (`[nets]`). A rock
//! meets a net when it enters one of the net's cells on a new passage (not the cells it was
//! released among, nor the next cell of the same net on the same passage: a rasterised line is
//! often two cells wide along a path, ours) with its centre below the net's height above the
//! ground. The net then takes its capacity from the rock's kinetic energy: a rock with no more
//! than the capacity is stopped, any other goes on with speed and spin scaled by
//! √((E − E_net)/E), so that its kinetic energy drops by E_net.

use rockfall_raster::GridGeometry;
use rockfall_scenario::Nets;
use std::collections::HashMap;

/// A net's properties in one cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetCell {
    /// Net number (≥ 1).
    pub id: u32,
    /// Energy capacity, J.
    pub energy_j: f64,
    /// Height above the ground, m.
    pub height_m: f64,
}

/// What a net does to a rock of kinetic energy E that meets it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NetEffect {
    /// E ≤ the capacity: the rock stops in the net.
    Stopped,
    /// E > the capacity: speed and spin are multiplied by `keep` = √((E − E_net)/E).
    Passed {
        /// Factor on speed and spin.
        keep: f64,
    },
}

/// The effect of a net of capacity `capacity_j` on a rock of kinetic energy `energy_j`.
pub fn net_effect(energy_j: f64, capacity_j: f64) -> NetEffect {
    if energy_j <= capacity_j {
        NetEffect::Stopped
    } else {
        NetEffect::Passed {
            keep: ((energy_j - capacity_j) / energy_j).sqrt(),
        }
    }
}

/// A rock's passage through net cells: which net's cells it is in.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NetPassage {
    net_id: u32,
}

impl NetPassage {
    /// The rock enters a cell of net `net_id` (0: none); `first` when it is the first cell of
    /// the rock's path. Returns `true` when this entry begins a new passage through a net: the
    /// net acts (if the rock is below its height).
    pub fn enter(&mut self, net_id: u32, first: bool) -> bool {
        let new = !first && net_id != 0 && net_id != self.net_id;
        self.net_id = net_id;
        new
    }
}

/// The net cells of a scenario, by row-major cell index.
#[derive(Debug, Clone, Default)]
pub struct NetMap {
    cells: HashMap<usize, NetCell>,
}

impl NetMap {
    /// The cells of `nets` (number ≥ 1) on `grid`; values as the scenario validated them.
    pub fn new(nets: &Nets, grid: &GridGeometry) -> NetMap {
        let mut cells = HashMap::new();
        for row in 0..grid.nrows {
            for col in 0..grid.ncols {
                let id = nets.number.at(row, col).unwrap_or(0.0);
                if id >= 1.0 {
                    cells.insert(
                        row * grid.ncols + col,
                        NetCell {
                            id: id as u32,
                            energy_j: nets.energy_kj.at(row, col).unwrap_or(0.0) * 1e3,
                            height_m: nets.height_m.at(row, col).unwrap_or(0.0),
                        },
                    );
                }
            }
        }
        NetMap { cells }
    }

    /// The net of `cell`, if any.
    pub fn at(&self, cell: usize) -> Option<&NetCell> {
        self.cells.get(&cell)
    }

    /// `true` without net cells.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_net_takes_its_capacity_or_stops_the_rock() {
        assert_eq!(net_effect(100.0, 100.0), NetEffect::Stopped);
        assert_eq!(net_effect(0.0, 0.0), NetEffect::Stopped);
        let NetEffect::Passed { keep } = net_effect(400.0, 300.0) else {
            panic!("passes")
        };
        assert!((keep - 0.5).abs() < 1e-15);
        // the kinetic energy drops by exactly the capacity
        assert!((400.0 * keep * keep - 100.0).abs() < 1e-12);
    }

    #[test]
    fn a_net_acts_once_per_passage_and_not_where_the_rock_starts() {
        let mut p = NetPassage::default();
        assert!(!p.enter(3, true), "released in the net's cells");
        assert!(!p.enter(3, false), "same passage");
        assert!(!p.enter(0, false));
        assert!(p.enter(3, false), "a new passage");
        assert!(!p.enter(3, false));
        assert!(p.enter(5, false), "another net");
    }
}

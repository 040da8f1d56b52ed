//! Per-cell surface and net parameters, each distinct set stored once.
//!
//! A scenario's surface parameters are constants or rasters of few distinct values (soil type
//! classes, obstacle-height classes), so the engine keeps a palette of the distinct
//! [`CellParams`] and one 2-byte index per cell — or nothing per cell when every valid cell
//! has the same parameters (constant parameters, no nets). Only a scenario with more than
//! 65 535 distinct sets falls back to one [`CellParams`] (72 bytes) per cell.

use std::collections::HashMap;

use rockfall_scenario::Nets;
use rockfall_terrain::{Lattice, Terrain};

use crate::LumpedError;

/// Surface and net parameters of one DEM cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellParams {
    /// Normal coefficient of restitution r_n (from the soil type), dimensionless.
    pub r_n: f64,
    /// Obstacle heights of the 70 / 20 / 10 % cover classes, m (seed 000 §2.5).
    pub moh_m: [f64; 3],
    /// Cover-weighted mean obstacle height, m (seed 000 eq. 4).
    pub moh_mean_m: f64,
    /// Rolling friction tan φ of the ground material (STONE per soil class, or the
    /// `rolling_friction` map), dimensionless.
    pub soil_mu: f64,
    /// Id of the net standing in the cell (`net_number`; 0: none).
    pub net_id: u32,
    /// Energy one net absorbs, J.
    pub net_energy_j: f64,
    /// Net height above the ground, m.
    pub net_height_m: f64,
}

impl CellParams {
    /// Parameters of a nodata cell (never used for a rebound).
    pub(crate) const NONE: CellParams = CellParams {
        r_n: 0.0,
        moh_m: [0.0; 3],
        moh_mean_m: 0.0,
        soil_mu: 0.0,
        net_id: 0,
        net_energy_j: 0.0,
        net_height_m: 0.0,
    };

    /// The bits of every field: equal keys, identical parameters.
    fn key(&self) -> [u64; 9] {
        [
            self.r_n.to_bits(),
            self.moh_m[0].to_bits(),
            self.moh_m[1].to_bits(),
            self.moh_m[2].to_bits(),
            self.moh_mean_m.to_bits(),
            self.soil_mu.to_bits(),
            u64::from(self.net_id),
            self.net_energy_j.to_bits(),
            self.net_height_m.to_bits(),
        ]
    }
}

/// Most distinct parameter sets a palette holds (its indices are `u16`).
const PALETTE_MAX: usize = 1 << 16;

/// The parameters of every cell of the DEM; nodata cells read [`CellParams::NONE`].
#[derive(Debug, Clone)]
pub(crate) enum CellMap {
    /// Every valid cell has these parameters.
    Uniform {
        params: CellParams,
        /// The DEM's validity, to answer NONE on nodata cells.
        lattice: Lattice,
    },
    /// `palette[index[slot]]`; `palette[0]` is [`CellParams::NONE`].
    Palette {
        palette: Vec<CellParams>,
        /// One entry per cell the DEM holds (its storage slots).
        index: Vec<u16>,
        slots: Slots,
    },
    /// One entry per cell the DEM holds (more than [`PALETTE_MAX`] distinct sets).
    Dense(Vec<CellParams>, Slots),
}

/// Where a cell's entry is: its row-major index on a whole DEM, its slot in the window a
/// tile's DEM holds.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Slots {
    whole: bool,
    ncols: usize,
    stored: rockfall_raster::Window,
}

impl Slots {
    fn of_lattice(lattice: &Lattice) -> Slots {
        Slots {
            whole: lattice.holds_whole_grid(),
            ncols: lattice.geometry().ncols,
            stored: lattice.stored(),
        }
    }

    /// The entry of cell `index` (row-major on the whole grid), `None` for a cell not held.
    #[inline]
    fn of(&self, index: usize) -> Option<usize> {
        if self.whole {
            return Some(index);
        }
        let s = &self.stored;
        let (row, col) = (index / self.ncols, index % self.ncols);
        s.contains(row, col)
            .then(|| (row - s.row0) * s.ncols + col - s.col0)
    }

    /// The cells held, as (row, col), row-major.
    fn cells(&self) -> impl Iterator<Item = (usize, usize)> + use<> {
        let s = self.stored;
        (s.row0..s.row0 + s.nrows)
            .flat_map(move |row| (s.col0..s.col0 + s.ncols).map(move |col| (row, col)))
    }
}

impl CellMap {
    /// The parameters of every valid cell of `lattice` (the DEM of `terrain`) from the
    /// surface map and the nets. The first valid cell (row-major) whose surface parameters
    /// are missing is [`LumpedError::MissingSurface`].
    pub(crate) fn new(
        terrain: &Terrain,
        nets: Option<&Nets>,
        lattice: &Lattice,
    ) -> Result<CellMap, LumpedError> {
        let g = *lattice.geometry();
        let slots = Slots::of_lattice(lattice);
        let s = &terrain.surface;
        let constant = nets.is_none()
            && (s.fields().iter()).all(|(_, f)| matches!(f, rockfall_raster::Field::Const(_)));
        if constant {
            // every valid cell reads the same constants: the first one stands for all
            let first = slots
                .cells()
                .find(|&(r, c)| lattice.is_valid(g.index(r, c)));
            if let Some((row, col)) = first {
                return Ok(CellMap::Uniform {
                    params: cell_params(terrain, nets, row, col)?,
                    lattice: lattice.clone(),
                });
            }
        }
        let mut palette = vec![CellParams::NONE];
        let mut known: HashMap<[u64; 9], u16> = HashMap::from([(CellParams::NONE.key(), 0)]);
        let mut index: Vec<u16> = Vec::with_capacity(slots.stored.ncols * slots.stored.nrows);
        let mut last: Option<(CellParams, u16)> = None;
        for (row, col) in slots.cells() {
            {
                let i = g.index(row, col);
                let params = match lattice.is_valid(i) {
                    false => CellParams::NONE,
                    true => cell_params(terrain, nets, row, col)?,
                };
                // neighbouring cells mostly share their parameters: skip the hash
                let slot = match last {
                    Some((p, slot)) if p.key() == params.key() => slot,
                    _ => match known.get(&params.key()) {
                        Some(&slot) => slot,
                        None if palette.len() < PALETTE_MAX => {
                            let slot = palette.len() as u16;
                            known.insert(params.key(), slot);
                            palette.push(params);
                            slot
                        }
                        None => return dense(terrain, nets, lattice),
                    },
                };
                last = Some((params, slot));
                index.push(slot);
            }
        }
        Ok(CellMap::Palette {
            palette,
            index,
            slots,
        })
    }

    /// Parameters of cell `index` (row-major).
    #[inline]
    pub(crate) fn get(&self, index: usize) -> &CellParams {
        match self {
            CellMap::Uniform { params, lattice } => match lattice.is_valid(index) {
                true => params,
                false => &CellParams::NONE,
            },
            CellMap::Palette {
                palette,
                index: i,
                slots,
            } => match slots.of(index) {
                Some(s) => &palette[usize::from(i[s])],
                None => &CellParams::NONE,
            },
            CellMap::Dense(cells, slots) => match slots.of(index) {
                Some(s) => &cells[s],
                None => &CellParams::NONE,
            },
        }
    }
}

/// One [`CellParams`] per cell.
fn dense(
    terrain: &Terrain,
    nets: Option<&Nets>,
    lattice: &Lattice,
) -> Result<CellMap, LumpedError> {
    let g = *lattice.geometry();
    let slots = Slots::of_lattice(lattice);
    let mut cells = Vec::with_capacity(slots.stored.ncols * slots.stored.nrows);
    for (row, col) in slots.cells() {
        cells.push(match lattice.is_valid(g.index(row, col)) {
            false => CellParams::NONE,
            true => cell_params(terrain, nets, row, col)?,
        });
    }
    Ok(CellMap::Dense(cells, slots))
}

/// Parameters of the valid cell (row, col).
fn cell_params(
    terrain: &Terrain,
    nets: Option<&Nets>,
    row: usize,
    col: usize,
) -> Result<CellParams, LumpedError> {
    let s = terrain
        .surface
        .cell(row, col)
        .ok_or(LumpedError::MissingSurface { row, col })?;
    let (id, energy_kj, height_m) = match nets {
        Some(n) => (
            n.number.at(row, col).unwrap_or(0.0),
            n.energy_kj.at(row, col).unwrap_or(0.0),
            n.height_m.at(row, col).unwrap_or(0.0),
        ),
        None => (0.0, 0.0, 0.0),
    };
    Ok(CellParams {
        r_n: s.r_n,
        moh_m: [s.rg70_m, s.rg20_m, s.rg10_m],
        moh_mean_m: s.mean_obstacle_height_m(),
        soil_mu: s.rolling_friction,
        // validated: a whole number in 0 ..= u32::MAX
        net_id: id as u32,
        net_energy_j: energy_kj * 1e3,
        net_height_m: height_m,
    })
}

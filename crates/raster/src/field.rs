//! A per-cell parameter given either as one constant for the whole site or as a raster on
//! the DEM's grid (the scenario file's "constant or raster path" choice).

use crate::{GeometryMismatch, Grid, GridGeometry};

/// A per-cell quantity: a constant or a raster aligned with the DEM.
#[derive(Debug, Clone, PartialEq)]
pub enum Field {
    /// The same value in every cell.
    Const(f64),
    /// One value per cell (nodata cells have no value).
    Grid(Grid<f64>),
}

impl Field {
    /// Value in cell (row, col); `None` on a nodata cell of a raster.
    #[inline]
    pub fn at(&self, row: usize, col: usize) -> Option<f64> {
        match self {
            Field::Const(v) => Some(*v),
            Field::Grid(g) => g.get(row, col),
        }
    }

    /// Value at a row-major cell index.
    #[inline]
    pub fn at_index(&self, index: usize) -> Option<f64> {
        match self {
            Field::Const(v) => Some(*v),
            Field::Grid(g) => g.get_index(index),
        }
    }

    /// The raster, when this field is one.
    pub fn as_grid(&self) -> Option<&Grid<f64>> {
        match self {
            Field::Const(_) => None,
            Field::Grid(g) => Some(g),
        }
    }

    /// Checks a raster field against the DEM's geometry (constants always fit).
    pub fn check_aligned(&self, dem: &GridGeometry) -> Result<(), GeometryMismatch> {
        match self {
            Field::Const(_) => Ok(()),
            Field::Grid(g) => dem.check_aligned(g.geometry()),
        }
    }

    /// Smallest and largest value over valid cells (`None` for an all-nodata raster).
    pub fn range(&self) -> Option<(f64, f64)> {
        match self {
            Field::Const(v) => Some((*v, *v)),
            Field::Grid(g) => g.min_max(),
        }
    }

    /// The first cell (row, col, value) for which `bad(value)` holds; a constant reports
    /// cell (0, 0).
    pub fn find(&self, mut bad: impl FnMut(f64) -> bool) -> Option<(usize, usize, f64)> {
        match self {
            Field::Const(v) => bad(*v).then_some((0, 0, *v)),
            Field::Grid(g) => g.iter_valid().find(|(_, _, v)| bad(*v)),
        }
    }

    /// The field as a raster on `geometry` (constants are expanded).
    pub fn to_grid(&self, geometry: &GridGeometry) -> Grid<f64> {
        match self {
            Field::Const(v) => Grid::filled(*geometry, *v),
            Field::Grid(g) => g.clone(),
        }
    }
}

impl From<f64> for Field {
    fn from(v: f64) -> Self {
        Field::Const(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn const_and_grid_fields() {
        let geom = GridGeometry {
            ncols: 2,
            nrows: 2,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        let c = Field::Const(3.0);
        assert_eq!(c.at(1, 1), Some(3.0));
        assert!(c.check_aligned(&geom).is_ok());
        let mut g = Grid::from_values(geom, vec![1.0, -2.0, 3.0, 4.0]).unwrap();
        g.set_nodata(1, 1);
        let f = Field::Grid(g);
        assert_eq!(f.at(1, 1), None);
        assert_eq!(f.range(), Some((-2.0, 3.0)));
        assert_eq!(f.find(|v| v < 0.0), Some((0, 1, -2.0)));
        let mut other = geom;
        other.nrows = 3;
        assert!(f.check_aligned(&other).is_err());
    }
}

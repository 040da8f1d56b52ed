//! Per-cell surface parameters of seed 000: soil type (→ r_n, rolling friction) and obstacle
//! heights.

use crate::{SoilType, TerrainError};
use rockfall_raster::{Field, GridGeometry};

/// The surface parameters of one cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellSurface {
    /// Soil type class.
    pub soil: SoilType,
    /// Normal coefficient of restitution r_n, dimensionless: the `r_n` override when the
    /// scenario gives one, else the class mean.
    pub r_n: f64,
    /// Rolling friction coefficient tan φ of the ground material, dimensionless: the
    /// `rolling_friction` override when the scenario gives one, else the class's
    /// ([`SoilType::rolling_friction`]).
    pub rolling_friction: f64,
    /// Obstacle height of the 70 % cover class, m (seed 000 §2.5, eq. 4).
    pub rg70_m: f64,
    /// Obstacle height of the 20 % cover class, m.
    pub rg20_m: f64,
    /// Obstacle height of the 10 % cover class, m.
    pub rg10_m: f64,
}

impl CellSurface {
    /// Cover-weighted mean obstacle height `0.7·rg70 + 0.2·rg20 + 0.1·rg10`, m
    /// (seed 000 eq. 4).
    pub fn mean_obstacle_height_m(&self) -> f64 {
        0.7 * self.rg70_m + 0.2 * self.rg20_m + 0.1 * self.rg10_m
    }
}

/// Surface parameters over the DEM's grid, each a constant or a raster.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceMap {
    /// Soil type class 0–7 (`soiltype`).
    pub soil_type: Field,
    /// Optional direct r_n (overrides the soil-type mapping), 0–1.
    pub r_n: Option<Field>,
    /// Optional direct rolling friction tan φ (overrides the soil-type mapping), 0–5.
    pub rolling_friction: Option<Field>,
    /// Optional ground class number 0–255 of the rigid engine's scarring ground
    /// (`rockfall_scenario::ground`; 0: the scenario's default class); the lumped engine does
    /// not read it.
    pub ground_class: Option<Field>,
    /// Obstacle height of the 70 % cover class, m (`rg70`).
    pub rg70_m: Field,
    /// Obstacle height of the 20 % cover class, m (`rg20`).
    pub rg20_m: Field,
    /// Obstacle height of the 10 % cover class, m (`rg10`).
    pub rg10_m: Field,
}

impl SurfaceMap {
    /// A uniform surface.
    pub fn uniform(soil: SoilType, rg70_m: f64, rg20_m: f64, rg10_m: f64) -> Self {
        SurfaceMap {
            soil_type: Field::Const(soil.class() as f64),
            r_n: None,
            rolling_friction: None,
            ground_class: None,
            rg70_m: Field::Const(rg70_m),
            rg20_m: Field::Const(rg20_m),
            rg10_m: Field::Const(rg10_m),
        }
    }

    /// The named fields, in the order they are checked.
    pub fn fields(&self) -> Vec<(&'static str, &Field)> {
        let mut v = vec![
            ("soiltype", &self.soil_type),
            ("rg70", &self.rg70_m),
            ("rg20", &self.rg20_m),
            ("rg10", &self.rg10_m),
        ];
        if let Some(r) = &self.r_n {
            v.push(("r_n", r));
        }
        if let Some(m) = &self.rolling_friction {
            v.push(("rolling_friction", m));
        }
        if let Some(m) = &self.ground_class {
            v.push(("ground_class", m));
        }
        v
    }

    /// Checks alignment with the DEM and value ranges: soil type a whole number 0–7, obstacle
    /// heights finite and ≥ 0 (≤ 100 m, Rockyfor3D's limit), r_n in [0, 1], rolling friction
    /// in [0, 5] (tan 79°: steeper ground than any rock rests on).
    pub fn check_against(&self, dem: &GridGeometry) -> Result<(), TerrainError> {
        for (name, field) in self.fields() {
            field
                .check_aligned(dem)
                .map_err(|mismatch| TerrainError::Misaligned {
                    parameter: name.into(),
                    mismatch,
                })?;
        }
        let out = |parameter: &str, (row, col, value): (usize, usize, f64), expected: &str| {
            TerrainError::OutOfRange {
                parameter: parameter.into(),
                row,
                col,
                value,
                expected: expected.into(),
            }
        };
        if let Some(bad) = self.soil_type.find(|v| SoilType::from_value(v).is_none()) {
            return Err(out("soiltype", bad, "a whole number 0–7"));
        }
        for (name, f) in [
            ("rg70", &self.rg70_m),
            ("rg20", &self.rg20_m),
            ("rg10", &self.rg10_m),
        ] {
            if let Some(bad) = f.find(|v| !(0.0..=100.0).contains(&v)) {
                return Err(out(name, bad, "0–100 m"));
            }
        }
        if let Some(r) = &self.r_n
            && let Some(bad) = r.find(|v| !(0.0..=1.0).contains(&v))
        {
            return Err(out("r_n", bad, "0–1"));
        }
        if let Some(m) = &self.rolling_friction
            && let Some(bad) = m.find(|v| !(0.0..=5.0).contains(&v))
        {
            return Err(out("rolling_friction", bad, "0–5"));
        }
        if let Some(m) = &self.ground_class
            && let Some(bad) = m.find(|v| !(v.fract() == 0.0 && (0.0..=255.0).contains(&v)))
        {
            return Err(out("ground_class", bad, "a whole number 0–255"));
        }
        Ok(())
    }

    /// Parameters of cell (row, col); `None` when any parameter is nodata there.
    #[inline]
    pub fn cell(&self, row: usize, col: usize) -> Option<CellSurface> {
        let soil = SoilType::from_value(self.soil_type.at(row, col)?)?;
        let r_n = match &self.r_n {
            Some(f) => f.at(row, col)?,
            None => soil.r_n_mean(),
        };
        let rolling_friction = match &self.rolling_friction {
            Some(f) => f.at(row, col)?,
            None => soil.rolling_friction(),
        };
        Some(CellSurface {
            soil,
            r_n,
            rolling_friction,
            rg70_m: self.rg70_m.at(row, col)?,
            rg20_m: self.rg20_m.at(row, col)?,
            rg10_m: self.rg10_m.at(row, col)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rockfall_raster::Grid;

    fn geom() -> GridGeometry {
        GridGeometry {
            ncols: 3,
            nrows: 2,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        }
    }

    #[test]
    fn cell_values_and_mean_obstacle_height() {
        let s = SurfaceMap::uniform(SoilType::new(4).unwrap(), 0.1, 0.2, 0.5);
        s.check_against(&geom()).unwrap();
        let c = s.cell(1, 2).unwrap();
        assert!((c.r_n - 0.38).abs() < 1e-12);
        assert_eq!(c.rolling_friction, 0.65);
        let mut s = s;
        s.rolling_friction = Some(Field::Const(0.2));
        assert_eq!(s.cell(0, 0).unwrap().rolling_friction, 0.2);
        assert!((c.mean_obstacle_height_m() - (0.07 + 0.04 + 0.05)).abs() < 1e-12);
    }

    #[test]
    fn range_and_alignment_errors_name_parameter_and_cell() {
        let mut s = SurfaceMap::uniform(SoilType::new(4).unwrap(), 0.1, 0.2, 0.5);
        let mut soil = Grid::filled(geom(), 3.0);
        soil.set(1, 2, 9.0);
        s.soil_type = Field::Grid(soil);
        let e = s.check_against(&geom()).unwrap_err().to_string();
        assert!(
            e.contains("soiltype") && e.contains("row 1, column 2") && e.contains('9'),
            "{e}"
        );

        let mut s = SurfaceMap::uniform(SoilType::new(4).unwrap(), 0.1, 0.2, 0.5);
        let mut rg = Grid::filled(geom(), 0.1);
        rg.set(0, 1, -0.5);
        s.rg20_m = Field::Grid(rg);
        let e = s.check_against(&geom()).unwrap_err().to_string();
        assert!(e.contains("rg20") && e.contains("row 0, column 1"), "{e}");

        let mut s = SurfaceMap::uniform(SoilType::new(4).unwrap(), 0.1, 0.2, 0.5);
        let mut g = geom();
        g.ncols = 4;
        s.rg70_m = Field::Grid(Grid::filled(g, 0.1));
        let e = s.check_against(&geom()).unwrap_err().to_string();
        assert!(e.contains("rg70") && e.contains("4 columns"), "{e}");

        let mut s = SurfaceMap::uniform(SoilType::new(4).unwrap(), 0.1, 0.2, 0.5);
        let mut mu = Grid::filled(geom(), 0.5);
        mu.set(0, 2, -0.1);
        s.rolling_friction = Some(Field::Grid(mu));
        let e = s.check_against(&geom()).unwrap_err().to_string();
        assert!(
            e.contains("rolling_friction") && e.contains("row 0, column 2"),
            "{e}"
        );
    }
}

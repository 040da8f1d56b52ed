//! The `[rock]` section of a scenario file.

use super::{DEFAULT_DENSITY_KG_M3, DEFAULT_SHAPE, Resolver};
use crate::{InputError, schema};
use rockfall_raster::Field;
use rockfall_scenario::{BlockShape, RockShape, RockSpec};

impl Resolver {
    /// The `[rock]` section: shape, dimensions, volume or mass, density and the volume keys.
    pub(super) fn rock(&mut self, r: schema::RockSec) -> Result<RockSpec, InputError> {
        let density = self.field("rock.density_kg_m3", r.density_kg_m3, DEFAULT_DENSITY_KG_M3)?;
        let shape = match (r.shape.as_deref(), r.blshape) {
            (Some(_), Some(_)) => {
                return Err(self.invalid("rock", "give either `shape` or `blshape`, not both"));
            }
            (None, Some(p)) => RockShape::PerCell(self.field("rock.blshape", Some(p), 0.0)?),
            (s, None) => match RockShape::parse(s.unwrap_or(DEFAULT_SHAPE))
                .map_err(|m| self.invalid("rock.shape", m))?
            {
                RockShape::File(p) => {
                    let path = self.path(&p.to_string_lossy());
                    if !path.is_file() {
                        return Err(InputError::Missing {
                            path,
                            what: format!(
                                "rock shape file for `rock.shape` (named in {})",
                                self.file.display()
                            ),
                        });
                    }
                    self.sources.insert("rock.shape".into(), path.clone());
                    crate::shape::read_shape(RockShape::File(path))?
                }
                other => other,
            },
        };
        let given = [
            r.diameter_m.is_some(),
            r.dims_m.is_some(),
            r.d1_m.is_some() || r.d2_m.is_some() || r.d3_m.is_some(),
        ];
        if given.iter().filter(|g| **g).count() > 1 {
            return Err(self.invalid(
                "rock",
                "give one of `diameter_m`, `dims_m` or `d1_m`/`d2_m`/`d3_m`",
            ));
        }
        // checked here, where the key the user wrote is known: a diameter becomes d1–d3
        let size_ok = |d: f64| d.is_finite() && d > 0.0 && d <= 50.0;
        if let Some(d) = r.diameter_m.filter(|d| !size_ok(*d)) {
            return Err(self.invalid(
                "rock.diameter_m",
                format!("{d} m: a diameter is > 0 and at most 50 m"),
            ));
        }
        if let Some(d) = r.dims_m.and_then(|d| d.into_iter().find(|d| !size_ok(*d))) {
            return Err(self.invalid(
                "rock.dims_m",
                format!("{d} m: each dimension is > 0 and at most 50 m"),
            ));
        }
        let dims_m =
            if let Some(d) = r.diameter_m {
                [Field::Const(d), Field::Const(d), Field::Const(d)]
            } else if let Some(d) = r.dims_m {
                d.map(Field::Const)
            } else if given[2] {
                [
                    self.field("rock.d1_m", r.d1_m, 0.0)?,
                    self.field("rock.d2_m", r.d2_m, 0.0)?,
                    self.field("rock.d3_m", r.d3_m, 0.0)?,
                ]
            } else {
                match &shape {
                    RockShape::Named(n) => rockfall_scenario::rock::named_dims(n)
                        .map(|d| d.map(Field::Const))
                        .ok_or_else(|| {
                            self.invalid("rock.shape", format!("unknown named shape {n}"))
                        })?,
                    RockShape::File(_) | RockShape::Cloud { .. } => {
                        [Field::Const(0.0), Field::Const(0.0), Field::Const(0.0)]
                    }
                    _ => return Err(self.invalid(
                        "rock",
                        "missing dimensions: give `diameter_m`, `dims_m` or `d1_m`/`d2_m`/`d3_m`",
                    )),
                }
            };
        let volume_m3 = match (&shape, r.volume_m3, r.mass_kg) {
            (_, Some(_), Some(_)) => {
                return Err(self.invalid("rock", "give `volume_m3` or `mass_kg`, not both"));
            }
            (_, None, Some(m)) => Some(self.volume_of_mass(m, &density)?),
            (RockShape::Named(n), None, None) => {
                Some(rockfall_scenario::rock::default_volume_m3(n))
            }
            (_, v, None) => v,
        };
        if matches!(shape, RockShape::Block(BlockShape::Spherical))
            && r.dims_m.is_some_and(|d| d[0] != d[1] || d[1] != d[2])
        {
            return Err(self.invalid(
                "rock.dims_m",
                "a sphere has equal dimensions; use `diameter_m`",
            ));
        }
        if r.volume_distribution.is_some() && r.volume_variation_percent.is_some() {
            return Err(self.invalid(
                "rock.volume_distribution",
                rockfall_scenario::volume::BOTH_KEYS,
            ));
        }
        let volume_distribution = (r.volume_distribution)
            .map(|d| crate::volume_distribution::parse(d, &density))
            .transpose()
            .map_err(|e| self.invalid(&format!("rock.volume_distribution.{}", e.key), e.message))?;
        let variation = r.volume_variation_percent.unwrap_or(0.0);
        if !(0.0..100.0).contains(&variation) {
            return Err(self.invalid(
                "rock.volume_variation_percent",
                format!("{variation} %: the volume varies by a share in [0, 100) %"),
            ));
        }
        Ok(RockSpec {
            shape,
            dims_m,
            volume_m3,
            density_kg_m3: density,
            volume_variation_percent: variation,
            volume_distribution,
        })
    }

    /// The volume of a rock of `mass_kg` at the scenario's density (a constant), m³.
    fn volume_of_mass(&self, mass_kg: f64, density: &Field) -> Result<f64, InputError> {
        if !(mass_kg.is_finite() && mass_kg > 0.0) {
            return Err(self.invalid("rock.mass_kg", format!("{mass_kg} kg: a mass is > 0")));
        }
        match density {
            Field::Const(rho) => Ok(mass_kg / rho),
            _ => Err(self.invalid(
                "rock.mass_kg",
                "a mass needs one density: give `density_kg_m3` as a number, or give `volume_m3`",
            )),
        }
    }
}

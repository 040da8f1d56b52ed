//! The `[release]` section of a scenario file.

use super::Resolver;
use crate::vector::inputs;
use crate::{InputError, schema};
use rockfall_scenario::{Release, ReleasePoint, StartHeight};
use rockfall_terrain::Terrain;

impl Resolver {
    /// The `[release]` section: source cells (a raster or polygons on the DEM's grid) with
    /// their gap and velocity, and the `[[release.points]]`, each with either a gap
    /// (`height_m`) or its centre's elevation (`z_m`), never both.
    pub(super) fn release(
        &mut self,
        r: schema::ReleaseSec,
        terrain: &Terrain,
    ) -> Result<Release, InputError> {
        let cells = match r.cells.map(Self::layer_ref) {
            None => Vec::new(),
            Some(Ok((p, layer))) if self.tile.is_some() => {
                self.release_layer_cells(&p, layer.as_deref(), terrain)?
            }
            Some(Ok((p, layer))) => {
                let l = self.layer("release.cells", &p, layer.as_deref())?;
                let cells = inputs::release_cells(&l, &self.frame()?)?;
                self.notes.push(inputs::describe(
                    "release.cells",
                    &l,
                    cells.len(),
                    "cells covered",
                ));
                cells
            }
            Some(Err(p)) if self.tile.is_some() => self.scan_release(&p, terrain)?,
            Some(Err(p)) => {
                let p = &p;
                let g = self.grid("release.cells", p)?;
                let path = self.path(p);
                terrain
                    .dem
                    .geometry()
                    .check_aligned(g.geometry())
                    .map_err(|m| InputError::invalid(&path, m.to_string()))?;
                let cells: Vec<usize> = g
                    .iter_valid()
                    .filter(|(_, _, v)| *v > 0.0)
                    .map(|(row, col, _)| g.geometry().index(row, col))
                    .collect();
                if cells.is_empty() {
                    return Err(InputError::invalid(
                        &path,
                        "release raster has no cell > 0: nothing to release",
                    ));
                }
                cells
            }
        };
        let points = (r.points.into_iter().enumerate())
            .map(|(k, p)| {
                let start = match (p.height_m, p.z_m) {
                    (Some(_), Some(_)) => {
                        return Err(self.invalid(
                            &format!("release.points[{k}]"),
                            "give either `height_m` (the gap between the ground under the \
                             rock's centre and its lowest point) or `z_m` (the elevation of \
                             its centre), not both",
                        ));
                    }
                    (None, Some(z_m)) => StartHeight::CentreZ { z_m },
                    (gap_m, None) => StartHeight::Gap {
                        gap_m: gap_m.unwrap_or(0.0),
                    },
                };
                Ok(ReleasePoint {
                    x_m: p.x_m,
                    y_m: p.y_m,
                    start,
                    velocity_ms: p.velocity_ms.unwrap_or([0.0; 3]),
                    angular_velocity_rads: p.angular_velocity_rads.unwrap_or([0.0; 3]),
                    orientation_wxyz: p.orientation_wxyz,
                })
            })
            .collect::<Result<Vec<_>, InputError>>()?;
        Ok(Release {
            cells,
            cell_height_m: r.height_m.unwrap_or(0.0),
            cell_velocity_ms: r.velocity_ms.unwrap_or([0.0; 3]),
            points,
        })
    }
}

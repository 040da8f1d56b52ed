//! The `[release]` section of a scenario file.

use super::Resolver;
use crate::vector::inputs;
use crate::{InputError, schema};
use rockfall_raster::Window;
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
            Some(Ok((p, layer))) => {
                let l = self.layer("release.cells", &p, layer.as_deref())?;
                let cells = inputs::release_cells(&l, &self.frame()?)?;
                self.notes.push(inputs::describe(
                    "release.cells",
                    &l,
                    cells.len(),
                    "cells covered",
                ));
                self.tile_cells(cells, terrain)
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

impl Resolver {
    /// A tile's source cells of the region's (ascending): those of the core, each with its
    /// number among the region's recorded.
    fn tile_cells(&mut self, cells: Vec<usize>, terrain: &Terrain) -> Vec<usize> {
        let Some(t) = self.tile.as_mut() else {
            return cells;
        };
        let g = terrain.dem.geometry();
        let mut ordinals = Vec::new();
        let mut kept = Vec::new();
        for (k, &c) in cells.iter().enumerate() {
            let (row, col) = g.row_col(c);
            if t.core.contains(row, col) {
                kept.push(c);
                ordinals.push(k as u64);
            }
        }
        t.found = Some((cells.len() as u64, ordinals));
        kept
    }

    /// A tile's source cells from the release raster `p`, read band by band over the whole
    /// region without holding its list: every cell > 0 is counted in row-major order, and
    /// those in the core are kept with their numbers.
    fn scan_release(&mut self, p: &str, terrain: &Terrain) -> Result<Vec<usize>, InputError> {
        let path = self.raster_path("release.cells", p)?;
        let g = *terrain.dem.geometry();
        let (whole, _) = rockfall_raster::read_geometry(&path)?;
        g.check_aligned(&whole)
            .map_err(|m| InputError::invalid(&path, m.to_string()))?;
        let core = self.tile.as_ref().map_or(Window::whole(&g), |t| t.core);
        // bands of whole rows of about 4 M cells, a multiple of 256 rows (COG tiles)
        let band = ((1usize << 22) / g.ncols.max(1))
            .max(1)
            .next_multiple_of(256);
        let (mut count, mut cells, mut ordinals) = (0u64, Vec::new(), Vec::new());
        let mut row0 = 0;
        while row0 < g.nrows {
            let nrows = band.min(g.nrows - row0);
            let w = Window {
                col0: 0,
                row0,
                ncols: g.ncols,
                nrows,
            };
            let part = rockfall_raster::read_grid_window(&path, &w)?;
            for (r, col, v) in part.iter_valid() {
                if v > 0.0 {
                    let row = row0 + r;
                    if core.contains(row, col) {
                        cells.push(g.index(row, col));
                        ordinals.push(count);
                    }
                    count += 1;
                }
            }
            row0 += nrows;
        }
        if count == 0 {
            return Err(InputError::invalid(
                &path,
                "release raster has no cell > 0: nothing to release",
            ));
        }
        if let Some(t) = self.tile.as_mut() {
            t.found = Some((count, ordinals));
        }
        Ok(cells)
    }
}

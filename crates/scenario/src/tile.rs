//! A scenario cut to one spatial tile of its region (`rockfall run --tile`): its grids hold
//! the tile's window only, its release keeps the core's source cells with their numbers
//! among the region's ([`TileFrame`]).

use rockfall_raster::{Field, Grid, Window};
use rockfall_terrain::Dem;

use crate::{ForestSpec, RockShape, Scenario, ScenarioError, TileFrame};

/// `grid` holding `window` only (its geometry, rows and indices unchanged); a grid already
/// held as a window is cut further. `None` when the grid does not hold all of `window`.
pub fn cut_grid(grid: &Grid<f64>, window: &Window) -> Option<Grid<f64>> {
    grid.window(window)?.placed(*grid.geometry(), *window)
}

fn cut_field(f: &mut Field, window: &Window) -> Result<(), ScenarioError> {
    if let Field::Grid(g) = f {
        *g = cut_grid(g, window).ok_or_else(outside)?;
    }
    Ok(())
}

fn outside() -> ScenarioError {
    ScenarioError::Invalid {
        parameter: "terrain.dem".into(),
        message: "a raster does not hold the tile's window".into(),
    }
}

impl Scenario {
    /// This scenario (read whole) as the tile of its region released from the cells of
    /// `core`, its grids cut to `window` (the core and its halo), its rocks free to visit
    /// `window` (narrow it with [`TileFrame::trusted`] before running). The source cells
    /// outside the core are dropped, those inside keep their numbers among the region's.
    pub fn cut_to_tile(&mut self, core: Window, window: Window) -> Result<(), ScenarioError> {
        let region_source_cells = self.release.cells.len() as u64;
        let g = *self.terrain.dem.geometry();
        let (cells, ordinals) = (self.release.cells.iter().enumerate())
            .filter(|(_, c)| {
                let (row, col) = g.row_col(**c);
                core.contains(row, col)
            })
            .map(|(k, c)| (*c, k as u64))
            .unzip();
        self.release.cells = cells;
        self.restrict_grids(&window)?;
        self.tile = Some(Box::new(TileFrame {
            core,
            window,
            trusted: window,
            region_source_cells,
            ordinals,
        }));
        Ok(())
    }

    /// Cuts every grid of the scenario (DEM, surface, rock, stands, nets) to `window`, and
    /// keeps the explicit stems that stand in it (a tile's rocks meet no other:
    /// `rockfall_sim::tile::margin_cells`), in their order.
    pub fn restrict_grids(&mut self, window: &Window) -> Result<(), ScenarioError> {
        let region = *self.terrain.dem.geometry();
        if let Some(ForestSpec::Stems(stems)) = &mut self.forest {
            stems.retain(|s| window.holds_point(&region, s.x_m, s.y_m));
        }
        let dem = cut_grid(self.terrain.dem.grid(), window).ok_or_else(outside)?;
        self.terrain.dem = Dem::new(dem).map_err(|e| ScenarioError::Invalid {
            parameter: "terrain.dem".into(),
            message: format!("the tile's window of the DEM: {e}"),
        })?;
        let s = &mut self.terrain.surface;
        for f in [
            &mut s.soil_type,
            &mut s.rg70_m,
            &mut s.rg20_m,
            &mut s.rg10_m,
        ] {
            cut_field(f, window)?;
        }
        for f in [&mut s.r_n, &mut s.rolling_friction, &mut s.ground_class]
            .into_iter()
            .flatten()
        {
            cut_field(f, window)?;
        }
        if let Some(ForestSpec::Stands(st)) = &mut self.forest {
            for f in [
                &mut st.stems_per_ha,
                &mut st.dbh_mean_cm,
                &mut st.dbh_sd_cm,
                &mut st.conifer_percent,
            ] {
                cut_field(f, window)?;
            }
        }
        let rock = &mut self.rock;
        for f in rock.dims_m.iter_mut().chain([&mut rock.density_kg_m3]) {
            cut_field(f, window)?;
        }
        if let RockShape::PerCell(f) = &mut rock.shape {
            cut_field(f, window)?;
        }
        if let Some(n) = &mut self.nets {
            for f in [&mut n.number, &mut n.energy_kj, &mut n.height_m] {
                cut_field(f, window)?;
            }
        }
        Ok(())
    }
}

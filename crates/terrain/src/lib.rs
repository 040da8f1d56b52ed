//! The terrain both engines roll on.
//!
//! - [`Dem`]: the digital elevation model as a continuous surface. Heights are known at cell
//!   centres; between four neighbouring centres the surface is the bilinear patch
//!   `z(u,v) = z00(1−u)(1−v) + z10·u(1−v) + z01(1−u)v + z11·uv` ([`BilinearPatch`]), which is
//!   continuous across patch edges. Height, gradient, unit normal, slope and aspect are
//!   available at any point. A patch with a nodata corner is *outside* the terrain: nodata is
//!   never read as a height.
//! - [`SurfaceMap`]: per-cell surface parameters of seed 000 — the soil type class (0–7,
//!   mapped to the normal coefficient of restitution r_n as in Rockyfor3D, [`SoilType`]) and
//!   the obstacle heights of the 70 / 20 / 10 % cover classes (rg70, rg20, rg10, m).
//! - [`Lattice`]: the same surface on the south-up lattice of cell centres, for the engines'
//!   inner loops; it reads the [`Dem`]'s grid in place (shared, not copied).
//! - [`Terrain`]: both together, checked to share one grid.

mod dem;
mod error;
mod lattice;
mod patch;
mod soil;
mod surface;

pub use dem::{Dem, SurfacePoint};
pub use error::TerrainError;
pub use lattice::{Lattice, PatchCoefficients};
pub use patch::BilinearPatch;
pub use soil::SoilType;
pub use surface::{CellSurface, SurfaceMap};

/// The DEM and its per-cell surface parameters on one grid.
#[derive(Debug, Clone)]
pub struct Terrain {
    /// The elevation surface.
    pub dem: Dem,
    /// The per-cell surface parameters.
    pub surface: SurfaceMap,
}

impl Terrain {
    /// Combines a DEM and a surface map, checking that every raster parameter lies on the
    /// DEM's grid.
    pub fn new(dem: Dem, surface: SurfaceMap) -> Result<Self, TerrainError> {
        surface.check_against(dem.geometry())?;
        Ok(Terrain { dem, surface })
    }
}

//! A hazard scenario's changes to the scenario it runs: the design block of its return
//! period, and the energy thresholds the matrix needs counted.

use std::path::Path;

use rockfall_io::vector::inputs::{Frame, open, release_cells};
use rockfall_raster::Field;
use rockfall_scenario::{MAX_ENERGY_THRESHOLDS, Scenario};

use crate::hazard_file::Block;
use crate::matrix::Matrix;

/// The entry's design block in place of the scenario's: a volume, a mass at the scenario's
/// constant density, or a percentile of its `[rock] volume_distribution` (ONR 24810 takes the
/// 95th–98th); the block is then the same for every rock.
pub fn set_block(s: &mut Scenario, b: &Block) -> Result<(), (&'static str, String)> {
    if let Some(v) = b.volume_m3 {
        s.rock.volume_m3 = Some(v);
    }
    if let Some(m) = b.mass_kg {
        match s.rock.density_kg_m3 {
            Field::Const(rho) => s.rock.volume_m3 = Some(m / rho),
            _ => {
                return Err((
                    "mass_kg",
                    "the scenario's density varies per cell: give volume_m3".into(),
                ));
            }
        }
    }
    if let Some(p) = b.percentile {
        let Some(d) = &s.rock.volume_distribution else {
            return Err((
                "block_percentile",
                "the scenario has no [rock] volume_distribution to take a percentile of".into(),
            ));
        };
        s.rock.volume_m3 = Some(d.percentile_m3(p));
    }
    // the design block is one block: no spread around it
    if b.volume_m3.is_some() || b.mass_kg.is_some() || b.percentile.is_some() {
        s.rock.volume_variation_percent = 0.0;
        s.rock.volume_distribution = None;
    }
    Ok(())
}

/// Makes the run count rocks above every intensity limit of `matrix` (kept first when more
/// than [`MAX_ENERGY_THRESHOLDS`] would be counted).
pub fn add_thresholds(s: &mut Scenario, matrix: &Matrix) {
    let mut t = matrix.intensity_thresholds_kj.clone();
    for &e in &s.output.energy_thresholds_kj {
        if t.len() < MAX_ENERGY_THRESHOLDS && !t.contains(&e) {
            t.push(e);
        }
    }
    t.sort_by(f64::total_cmp);
    s.output.energy_thresholds_kj = t;
}

/// The release area of `s` replaced by the polygons of the layer at `path` (only the feature
/// of OGR id `fid` when given): the cells whose centres they hold, as `[release] cells`
/// takes a layer; the scenario's release points are dropped.
pub fn set_release(
    s: &mut Scenario,
    path: &Path,
    fid: Option<i64>,
) -> Result<(), (&'static str, String)> {
    if !rockfall_io::vector::is_vector_path(path) {
        return Err((
            "release",
            format!(
                "{}: a polygon layer (.geojson, .gpkg, .shp)",
                path.display()
            ),
        ));
    }
    let dem = &s.terrain.dem;
    let frame = Frame {
        geometry: *dem.geometry(),
        crs: dem.crs().cloned(),
        window: None,
    };
    let mut notes = Vec::new();
    let mut layer = open(path, None, &frame, &mut notes).map_err(|e| ("release", e.to_string()))?;
    if let Some(id) = fid {
        layer.features.retain(|f| f.id == id);
        if layer.features.is_empty() {
            return Err((
                "release_fid",
                format!("{}: no feature with FID {id}", path.display()),
            ));
        }
    }
    s.release.cells = release_cells(&layer, &frame).map_err(|e| ("release", e.to_string()))?;
    s.release.points.clear();
    Ok(())
}

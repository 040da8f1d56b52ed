//! Everything about a scenario that can be checked before simulating.

use crate::{ForestSpec, RockShape, Scenario, ScenarioError, StartHeight};
use rockfall_raster::{Field, GridGeometry};

pub(crate) type Check = Result<(), ScenarioError>;

impl Scenario {
    /// Checks the DEM's CRS (projected, in metres), alignment, ranges, release, screens and
    /// parameters (see the crate docs).
    /// Surface parameters are checked when the [`rockfall_terrain::Terrain`] is built.
    pub fn validate(&self) -> Check {
        if let Some(crs) = self.terrain.dem.crs()
            && crs.is_geographic()
        {
            return Err(ScenarioError::invalid(
                "dem",
                format!(
                    "the CRS {} is geographic (degrees), but coordinates and cell sizes must be \
                     in metres: reproject the DEM to a projected CRS (or remove a wrong .prj)",
                    crs.describe()
                ),
            ));
        }
        let dem = *self.terrain.dem.geometry();
        if !(dem.cell_size_m > 0.0 && dem.cell_size_m <= 1000.0) {
            return Err(out_of_range(
                "dem cell size",
                None,
                dem.cell_size_m,
                "> 0 and ≤ 1000 m",
            ));
        }
        self.check_rock(&dem)?;
        self.check_release(&dem)?;
        self.check_forest(&dem)?;
        self.check_nets(&dem)?;
        self.check_screens()?;
        self.check_settings()
    }

    fn check_rock(&self, dem: &GridGeometry) -> Check {
        let r = &self.rock;
        aligned("rock.density_kg_m3", &r.density_kg_m3, dem)?;
        for (i, d) in r.dims_m.iter().enumerate() {
            aligned(dim_name(i), d, dem)?;
        }
        if let RockShape::PerCell(f) = &r.shape {
            aligned("rock.blshape", f, dem)?;
            in_range("rock.blshape", f, "a whole number 0–4", |v| {
                v.fract() == 0.0 && (0.0..=4.0).contains(&v)
            })?;
        }
        // physically plausible rock: 0 marks a cell without release
        in_range(
            "rock.density_kg_m3",
            &r.density_kg_m3,
            "0 (no release) or 1000–6000 kg/m³",
            |v| v == 0.0 || (1000.0..=6000.0).contains(&v),
        )?;
        for (i, d) in r.dims_m.iter().enumerate() {
            in_range(dim_name(i), d, "0–50 m", |v| (0.0..=50.0).contains(&v))?;
        }
        if let Some(v) = r.volume_m3
            && !(v > 0.0 && v.is_finite())
        {
            return Err(out_of_range("rock.volume_m3", None, v, "> 0 m³"));
        }
        crate::volume::check_rock_volume(r)?;
        // Every source cell needs a usable rock.
        for &i in &self.release.cells {
            let (row, col) = dem.row_col(i);
            let density = r.density_kg_m3.at(row, col).unwrap_or(0.0);
            if density <= 0.0 {
                return Err(out_of_range(
                    "rock.density_kg_m3",
                    Some((row, col)),
                    density,
                    "> 0 kg/m³ in a source cell",
                ));
            }
            if matches!(r.shape, RockShape::Block(_) | RockShape::PerCell(_)) {
                let Some((_, d)) = r.block_at(row, col) else {
                    return Err(ScenarioError::invalid(
                        "rock.blshape",
                        format!(
                            "source cell at row {row}, column {col} has no block shape (1–4) or no dimensions"
                        ),
                    ));
                };
                if let Some(k) = d.iter().position(|x| *x <= 0.0) {
                    return Err(out_of_range(
                        dim_name(k),
                        Some((row, col)),
                        d[k],
                        "> 0 m in a source cell",
                    ));
                }
            }
        }
        Ok(())
    }

    fn check_release(&self, dem: &GridGeometry) -> Check {
        let rel = &self.release;
        // a tile of a region may hold no source cell of its own
        let region_has = (self.tile.as_ref()).is_some_and(|t| t.region_source_cells > 0);
        if rel.is_empty() && !region_has {
            return Err(ScenarioError::NoRelease {
                hint: "give source cells (rockdensity > 0) or [[release.points]]".into(),
            });
        }
        if let Some(&i) = rel.cells.iter().find(|&&i| i >= dem.len()) {
            return Err(ScenarioError::invalid(
                "release.cells",
                format!("cell index {i} outside the DEM"),
            ));
        }
        // each source cell once: its rocks' random streams are keyed by the cell
        if let Some(w) = rel.cells.windows(2).find(|w| w[0] >= w[1]) {
            let (row, col) = dem.row_col(w[1]);
            return Err(ScenarioError::invalid(
                "release.cells",
                format!(
                    "source cells must be listed once each, in ascending order: the cell at row \
                     {row}, column {col} (index {}) comes after index {}",
                    w[1], w[0]
                ),
            ));
        }
        for &i in &rel.cells {
            let (row, col) = dem.row_col(i);
            let (x, y) = dem.cell_center(row, col);
            if !self.terrain.dem.contains(x, y) || self.terrain.surface.cell(row, col).is_none() {
                return Err(ScenarioError::invalid(
                    "release.cells",
                    format!(
                        "source cell at row {row}, column {col} lies on or next to nodata \
                         (DEM or surface parameters), where the terrain is not defined"
                    ),
                ));
            }
        }
        finite_nonneg("release.height_m", rel.cell_height_m)?;
        finite3("release.velocity_ms", rel.cell_velocity_ms)?;
        for (k, p) in rel.points.iter().enumerate() {
            let name = format!("release.points[{k}]");
            // a point of another tile of the region is that tile's to check
            let cell = dem.cell_of(p.x_m, p.y_m);
            if let (Some(t), Some((row, col))) = (&self.tile, cell)
                && !t.core.contains(row, col)
            {
                continue;
            }
            if !(p.x_m.is_finite() && p.y_m.is_finite() && self.terrain.dem.contains(p.x_m, p.y_m))
            {
                return Err(ScenarioError::invalid(
                    &name,
                    format!("({}, {}) is not on the terrain surface", p.x_m, p.y_m),
                ));
            }
            let (row, col) = dem.cell_of(p.x_m, p.y_m).unwrap_or_default();
            let block = matches!(self.rock.shape, RockShape::Block(_) | RockShape::PerCell(_));
            if (block && self.rock.block_at(row, col).is_none())
                || !self
                    .rock
                    .density_kg_m3
                    .at(row, col)
                    .is_some_and(|d| d > 0.0)
            {
                return Err(ScenarioError::invalid(
                    &name,
                    format!(
                        "no usable rock in the cell under ({}, {}) (row {row}, column {col}): \
                         shape, dimensions or density missing or not positive",
                        p.x_m, p.y_m
                    ),
                ));
            }
            match p.start {
                StartHeight::Gap { gap_m } => finite_nonneg(&format!("{name}.height_m"), gap_m)?,
                // whether the rock fits above the ground there is the engines' to say: only
                // they know how far it reaches below its centre
                StartHeight::CentreZ { z_m } if !z_m.is_finite() => {
                    return Err(out_of_range(&format!("{name}.z_m"), None, z_m, "finite"));
                }
                StartHeight::CentreZ { .. } => {}
            }
            finite3(&format!("{name}.velocity_ms"), p.velocity_ms)?;
            finite3(
                &format!("{name}.angular_velocity_rads"),
                p.angular_velocity_rads,
            )?;
            if let Some(q) = p.orientation_wxyz {
                let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
                if (n - 1.0).abs() >= 1e-3 || n.is_nan() {
                    return Err(ScenarioError::invalid(
                        &format!("{name}.orientation_wxyz"),
                        format!("quaternion norm is {n}, expected 1"),
                    ));
                }
            }
        }
        Ok(())
    }

    fn check_forest(&self, dem: &GridGeometry) -> Check {
        let Some(ForestSpec::Stands(st)) = &self.forest else {
            return Ok(());
        };
        for (name, f) in st.fields() {
            aligned(name, f, dem)?;
        }
        in_range("nrtrees", &st.stems_per_ha, "≥ 0 stems/ha", |v| v >= 0.0)?;
        in_range("dbhmean", &st.dbh_mean_cm, "≥ 0 cm", |v| v >= 0.0)?;
        in_range("dbhstd", &st.dbh_sd_cm, "≥ 0 cm", |v| v >= 0.0)?;
        in_range("conif_percent", &st.conifer_percent, "0–100 %", |v| {
            (0.0..=100.0).contains(&v)
        })?;
        if let Some((mean, sd)) = st.height_m
            && !(mean > 1.3 && sd >= 0.0 && mean.is_finite() && sd.is_finite())
        {
            return Err(ScenarioError::invalid(
                "forest.height_mean_m",
                format!("height {mean} ± {sd} m: mean must exceed breast height (1.3 m), sd ≥ 0"),
            ));
        }
        Ok(())
    }

    fn check_nets(&self, dem: &GridGeometry) -> Check {
        let Some(n) = &self.nets else { return Ok(()) };
        for (name, f) in [
            ("net_number", &n.number),
            ("net_energy", &n.energy_kj),
            ("net_height", &n.height_m),
        ] {
            aligned(name, f, dem)?;
            in_range(name, f, "≥ 0", |v| v >= 0.0)?;
        }
        in_range(
            "net_number",
            &n.number,
            "a whole number (the net's id; 0: no net)",
            |v| v.fract() == 0.0 && v <= f64::from(u32::MAX),
        )?;
        Ok(())
    }

    fn check_screens(&self) -> Check {
        let mut names = std::collections::BTreeSet::new();
        for (k, s) in self.screens.iter().enumerate() {
            let name = format!("screens[{k}]");
            if s.name.trim().is_empty() || !names.insert(s.name.as_str()) {
                return Err(ScenarioError::invalid(
                    &name,
                    format!("screen name `{}` is empty or used twice", s.name),
                ));
            }
            let vertices_ok = s.points_m.len() >= 2 || (s.net.is_some() && s.points_m.is_empty());
            if !vertices_ok || s.points_m.iter().flatten().any(|v| !v.is_finite()) {
                return Err(ScenarioError::invalid(
                    &name,
                    "a screen needs at least two finite vertices [x_m, y_m]",
                ));
            }
            for (key, v) in [("capacity_kj", s.capacity_kj), ("height_m", s.height_m)] {
                if let Some(v) = v
                    && !(v.is_finite() && v > 0.0)
                {
                    return Err(ScenarioError::invalid(
                        &name,
                        format!("`{key}` must be a finite number > 0, found {v}"),
                    ));
                }
            }
        }
        Ok(())
    }
}

pub(crate) fn dim_name(i: usize) -> &'static str {
    ["rock.d1_m", "rock.d2_m", "rock.d3_m"][i]
}

pub(crate) fn out_of_range(
    parameter: &str,
    cell: Option<(usize, usize)>,
    value: f64,
    expected: &str,
) -> ScenarioError {
    ScenarioError::OutOfRange {
        parameter: parameter.into(),
        cell,
        value,
        expected: expected.into(),
    }
}

pub(crate) fn aligned(parameter: &str, f: &Field, dem: &GridGeometry) -> Check {
    f.check_aligned(dem)
        .map_err(|mismatch| ScenarioError::Misaligned {
            parameter: parameter.into(),
            mismatch,
        })
}

/// Every value of `f` satisfies `ok` (NaN never does).
pub(crate) fn in_range(
    parameter: &str,
    f: &Field,
    expected: &str,
    ok: impl Fn(f64) -> bool,
) -> Check {
    match f.find(|v| !(v.is_finite() && ok(v))) {
        None => Ok(()),
        Some((row, col, value)) => {
            let cell = matches!(f, Field::Grid(_)).then_some((row, col));
            Err(out_of_range(parameter, cell, value, expected))
        }
    }
}

pub(crate) fn finite_nonneg(parameter: &str, v: f64) -> Check {
    if v >= 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(out_of_range(parameter, None, v, "finite and ≥ 0"))
    }
}

pub(crate) fn finite3(parameter: &str, v: [f64; 3]) -> Check {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(ScenarioError::invalid(
            parameter,
            format!("{v:?} is not finite"),
        ))
    }
}

//! A scenario written back as input files.
//!
//! Writes into a folder: `scenario.toml` (complete, commented, every constant inline and
//! every raster by relative path), the rasters as ESRI ASCII grids with `.prj` sidecars, the
//! tree list as `trees.csv`, and — where the scenario fits the Rockyfor3D model (source cells
//! and block shapes) — the full Rockyfor3D file set (`rockdensity.asc`, `d1–d3.asc`,
//! `blshape.asc`, `rg70/20/10.asc`, `soiltype.asc`, `treefile.txt` or stand rasters, nets), so
//! that the folder itself is also a Rockyfor3D input folder. Every file is written
//! atomically.

use crate::{InputError, trees, write_text};
use rockfall_raster::{Field, Grid, GridGeometry, ascii_grid};
use rockfall_scenario::{ForestSpec, RockShape, Scenario, StartHeight};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Writes `scenario` into `dir` (created if needed) and returns the files written.
pub fn write_scenario_dir(scenario: &Scenario, dir: &Path) -> Result<Vec<PathBuf>, InputError> {
    std::fs::create_dir_all(dir).map_err(|e| InputError::io(dir, e))?;
    let mut w = Writer {
        dir: dir.to_path_buf(),
        geometry: *scenario.terrain.dem.geometry(),
        crs: scenario.terrain.dem.crs().cloned(),
        written: Vec::new(),
    };
    w.grid("dem.asc", scenario.terrain.dem.grid())?;
    if fits_rockyfor3d(scenario) {
        w.rockyfor3d_set(scenario)?;
    }
    if let Some(ForestSpec::Stems(stems)) = &scenario.forest {
        let p = dir.join("trees.csv");
        trees::write_tree_csv(&p, stems)?;
        w.written.push(p);
    }
    let toml = w.scenario_toml(scenario)?;
    let p = dir.join("scenario.toml");
    write_text(&p, &toml)?;
    w.written.push(p);
    Ok(w.written)
}

/// True when the scenario can be expressed as a Rockyfor3D folder: source cells only, and
/// block shapes.
pub fn fits_rockyfor3d(s: &Scenario) -> bool {
    !s.release.cells.is_empty()
        && s.release.points.is_empty()
        && matches!(s.rock.shape, RockShape::Block(_) | RockShape::PerCell(_))
        && s.rock.volume_m3.is_none()
        && s.rock.volume_variation_percent == 0.0
        && s.rock.volume_distribution.is_none()
        && s.screens.iter().all(|sc| sc.net.is_none())
}

struct Writer {
    dir: PathBuf,
    geometry: GridGeometry,
    crs: Option<rockfall_raster::Crs>,
    written: Vec<PathBuf>,
}

impl Writer {
    fn grid(&mut self, name: &str, g: &Grid<f64>) -> Result<(), InputError> {
        let p = self.dir.join(name);
        if self.written.contains(&p) {
            // the Rockyfor3D set and the scenario file may both name a raster: write it once
            return Ok(());
        }
        let g = g.clone().with_crs(self.crs.clone());
        ascii_grid::write(&p, &g)?;
        self.written.push(p);
        Ok(())
    }

    fn field_grid(&mut self, name: &str, f: &Field) -> Result<(), InputError> {
        let g = f.to_grid(&self.geometry);
        self.grid(name, &g)
    }

    fn rockyfor3d_set(&mut self, s: &Scenario) -> Result<(), InputError> {
        let g = self.geometry;
        // rockdensity: density in source cells, 0 elsewhere
        let mut density = Grid::filled(g, 0.0);
        for &i in &s.release.cells {
            let (row, col) = g.row_col(i);
            density.set(row, col, s.rock.density_kg_m3.at(row, col).unwrap_or(0.0));
        }
        self.grid("rockdensity.asc", &density)?;
        let blshape = match &s.rock.shape {
            RockShape::Block(b) => Field::Const(b.code() as f64),
            RockShape::PerCell(f) => f.clone(),
            _ => Field::Const(0.0),
        };
        self.field_grid("blshape.asc", &blshape)?;
        for (i, d) in s.rock.dims_m.iter().enumerate() {
            self.field_grid(&format!("d{}.asc", i + 1), d)?;
        }
        let t = &s.terrain.surface;
        self.field_grid("soiltype.asc", &t.soil_type)?;
        self.field_grid("rg70.asc", &t.rg70_m)?;
        self.field_grid("rg20.asc", &t.rg20_m)?;
        self.field_grid("rg10.asc", &t.rg10_m)?;
        match &s.forest {
            Some(ForestSpec::Stems(stems)) => {
                let p = self.dir.join("treefile.txt");
                trees::write_treefile(&p, stems)?;
                self.written.push(p);
            }
            Some(ForestSpec::Stands(st)) => {
                for (name, f) in st.fields() {
                    self.field_grid(&format!("{name}.asc"), f)?;
                }
            }
            None => {}
        }
        if let Some(n) = &s.nets {
            self.field_grid("net_number.asc", &n.number)?;
            self.field_grid("net_energy.asc", &n.energy_kj)?;
            self.field_grid("net_height.asc", &n.height_m)?;
        }
        Ok(())
    }

    /// `key = value` for a field: the constant inline, or a raster written beside.
    fn param(&mut self, key: &str, file: &str, f: &Field) -> Result<String, InputError> {
        Ok(match f {
            Field::Const(v) => format!("{key} = {}\n", num(*v)),
            Field::Grid(g) => {
                self.grid(file, g)?;
                format!("{key} = \"{file}\"\n")
            }
        })
    }

    fn scenario_toml(&mut self, s: &Scenario) -> Result<String, InputError> {
        let mut t = String::new();
        let _ = writeln!(
            t,
            "# rockfall scenario {}, written by rockfall-io.",
            quote(&s.name)
        );
        let _ = writeln!(
            t,
            "# Paths are relative to this file. Units are in the key names.\n"
        );
        let _ = writeln!(
            t,
            "name = {}\nengine = \"{}\"\nseed = {}\n",
            quote(&s.name),
            s.engine,
            s.seed
        );
        t += "[terrain]\ndem = \"dem.asc\"\n";
        if let Some(code) = s.terrain.dem.crs().and_then(|c| c.epsg) {
            let _ = writeln!(t, "epsg = {code}");
        }
        let sf = &s.terrain.surface;
        t += &self.param("soiltype", "soiltype.asc", &sf.soil_type)?;
        if let Some(r) = &sf.r_n {
            t += &self.param("r_n", "r_n.asc", r)?;
        }
        if let Some(m) = &sf.rolling_friction {
            t += &self.param("rolling_friction", "rolling_friction.asc", m)?;
        }
        if let Some(m) = &sf.ground_class {
            t += &self.param("ground_class", "ground_class.asc", m)?;
        }
        t += &self.param("rg70_m", "rg70.asc", &sf.rg70_m)?;
        t += &self.param("rg20_m", "rg20.asc", &sf.rg20_m)?;
        t += &self.param("rg10_m", "rg10.asc", &sf.rg10_m)?;

        t += "\n[rock]\n";
        let r = &s.rock;
        match &r.shape {
            RockShape::PerCell(f) => t += &self.param("blshape", "blshape.asc", f)?,
            RockShape::File(p) | RockShape::Cloud { source: p, .. } => {
                let _ = writeln!(t, "shape = {}", quote(&p.to_string_lossy()));
            }
            other => {
                let _ = writeln!(t, "shape = \"{}\"", other.describe());
            }
        }
        let named = matches!(
            r.shape,
            RockShape::Named(_) | RockShape::File(_) | RockShape::Cloud { .. }
        );
        let same = r.dims_m.iter().all(|d| matches!(d, Field::Const(_)))
            && r.dims_m[0] == r.dims_m[1]
            && r.dims_m[1] == r.dims_m[2];
        if !named {
            if same {
                if let Field::Const(d) = r.dims_m[0] {
                    let _ = writeln!(t, "diameter_m = {}", num(d));
                }
            } else {
                for (i, d) in r.dims_m.iter().enumerate() {
                    t += &self.param(&format!("d{}_m", i + 1), &format!("d{}.asc", i + 1), d)?;
                }
            }
        }
        if let Some(v) = r.volume_m3 {
            let _ = writeln!(t, "volume_m3 = {}", num(v));
        }
        t += &self.param("density_kg_m3", "density.asc", &r.density_kg_m3)?;
        if r.volume_variation_percent > 0.0 {
            let _ = writeln!(
                t,
                "volume_variation_percent = {}",
                num(r.volume_variation_percent)
            );
        }
        if let Some(d) = &r.volume_distribution {
            t += &crate::volume_distribution::table(d, num);
        }

        t += "\n[release]\n";
        let rel = &s.release;
        if !rel.cells.is_empty() {
            let mut mask = Grid::filled(self.geometry, 0.0);
            for &i in &rel.cells {
                let (row, col) = self.geometry.row_col(i);
                mask.set(row, col, 1.0);
            }
            self.grid("release.asc", &mask)?;
            t += "cells = \"release.asc\"          # cells > 0 are source cells\n";
            let _ = writeln!(t, "height_m = {}", num(rel.cell_height_m));
            let _ = writeln!(t, "velocity_ms = {}", arr(&rel.cell_velocity_ms));
        }
        for p in &rel.points {
            t += "\n[[release.points]]\n";
            let (key, value) = match p.start {
                StartHeight::Gap { gap_m } => ("height_m", gap_m),
                StartHeight::CentreZ { z_m } => ("z_m", z_m),
            };
            let _ = writeln!(
                t,
                "x_m = {}\ny_m = {}\n{key} = {}",
                num(p.x_m),
                num(p.y_m),
                num(value)
            );
            let _ = writeln!(t, "velocity_ms = {}", arr(&p.velocity_ms));
            let _ = writeln!(
                t,
                "angular_velocity_rads = {}",
                arr(&p.angular_velocity_rads)
            );
            if let Some(q) = p.orientation_wxyz {
                let _ = writeln!(t, "orientation_wxyz = {}", arr(&q));
            }
        }
        self.forest_toml(s, &mut t)?;
        if let Some(n) = &s.nets {
            t += "\n[nets]\n";
            t += &self.param("number", "net_number.asc", &n.number)?;
            t += &self.param("energy_kj", "net_energy.asc", &n.energy_kj)?;
            t += &self.param("height_m", "net_height.asc", &n.height_m)?;
            if s.screens.iter().any(|sc| sc.net.is_some()) {
                t += "screens = true\n";
            }
        }
        // nets' screens come back from `[nets] screens` (without their lines: the nets are
        // written as rasters)
        for sc in s.screens.iter().filter(|sc| sc.net.is_none()) {
            let pts: Vec<String> = sc.points_m.iter().map(|p| arr(p)).collect();
            let _ = write!(
                t,
                "\n[[screens]]\nname = {}\npoints_m = [{}]\n",
                quote(&sc.name),
                pts.join(", ")
            );
            for (key, v) in [("capacity_kj", sc.capacity_kj), ("height_m", sc.height_m)] {
                if let Some(v) = v {
                    let _ = writeln!(t, "{key} = {v:?}");
                }
            }
        }
        settings_toml(s, &mut t);
        Ok(t)
    }

    fn forest_toml(&mut self, s: &Scenario, t: &mut String) -> Result<(), InputError> {
        match &s.forest {
            None => {}
            Some(ForestSpec::Stems(_)) => *t += "\n[forest]\ntrees_csv = \"trees.csv\"\n",
            Some(ForestSpec::Stands(st)) => {
                *t += "\n[forest]\n";
                *t += &self.param("stems_per_ha", "nrtrees.asc", &st.stems_per_ha)?;
                *t += &self.param("dbh_mean_cm", "dbhmean.asc", &st.dbh_mean_cm)?;
                *t += &self.param("dbh_sd_cm", "dbhstd.asc", &st.dbh_sd_cm)?;
                *t += &self.param("conifer_percent", "conif_percent.asc", &st.conifer_percent)?;
                if let Some((m, sd)) = st.height_m {
                    let _ = writeln!(t, "height_mean_m = {}\nheight_sd_m = {}", num(m), num(sd));
                }
                let _ = writeln!(
                    t,
                    "dbh_min_cm = {}\ndbh_max_cm = {}",
                    num(st.options.dbh_min_cm),
                    num(st.options.dbh_max_cm)
                );
            }
        }
        Ok(())
    }
}

fn settings_toml(s: &Scenario, t: &mut String) {
    let l = &s.lumped;
    let moh = l.moh.name();
    let _ = write!(
        t,
        "\n[lumped]\nmoh = \"{moh}\"\ntangential_law = \"{}\"\nrt_variation = {}\nslope_reduction_max_deg = {}\nmax_lateral_deviation_deg = {}\nstop_velocity_ms = {}\nrn_velocity_scale_ms = {}\nroughness_tilt_factor = {}\nlift_off_obstacle_factor = {}\nsoil_friction_scale = {}\n",
        l.tangential.name(),
        num(l.rt_variation),
        num(l.slope_reduction_max_deg),
        num(l.max_lateral_deviation_deg),
        num(l.stop_velocity_ms),
        num(l.rn_velocity_scale_ms),
        num(l.roughness_tilt_factor),
        num(l.lift_off_obstacle_factor),
        num(l.soil_friction_scale)
    );
    let r = &s.rigid;
    let _ = write!(
        t,
        "\n[rigid]\nsolver_alpha = {}\nsolver_tolerance_ms = {}\nsolver_max_iterations = {}\nwarm_start = {}\nstop_speed_ms = {}\nrest_time_s = {}\nmax_speed_ms = {}\nlinear_damping_per_s = {}\nangular_damping_per_s = {}\n",
        num(r.solver_alpha),
        num(r.solver_tolerance_ms),
        r.solver_max_iterations,
        r.warm_start,
        num(r.stop_speed_ms),
        num(r.rest_time_s),
        num(r.max_speed_ms),
        num(r.linear_damping_per_s),
        num(r.angular_damping_per_s)
    );
    let c = &s.contact;
    for (name, p) in [("ground", c.ground), ("tree", c.tree)] {
        let _ = write!(
            t,
            "\n[contact.{name}]\nmu = {}\neps_n = {}\neps_t = {}\n",
            num(p.mu),
            num(p.eps_n),
            num(p.eps_t)
        );
        if name == "ground" {
            let d = &c.scarring.default;
            let _ = write!(t, "model = \"{}\"\nclass = {}\n", c.model, quote(&d.name));
            t.push_str(&scarring_keys(&d.params));
        }
    }
    let builtin = rockfall_scenario::ground::builtin_ground_classes();
    for class in c.scarring.classes.iter().filter(|k| !builtin.contains(k)) {
        let _ = write!(
            t,
            "\n[[contact.ground_class]]\nid = {}\nname = {}\nsource = {}\n",
            class.id,
            quote(&class.name),
            quote(&class.source)
        );
        t.push_str(&scarring_keys(&class.params));
    }
    if let Some(sl) = c.slippage {
        let _ = write!(
            t,
            "\n[contact.slippage]\nmu_min = {}\nmu_max = {}\nbeta_per_s = {}\nkappa_per_m = {}\n",
            num(sl.mu_min),
            num(sl.mu_max),
            num(sl.beta_per_s),
            num(sl.kappa_per_m)
        );
    }
    let m = &s.simulation;
    let _ = write!(
        t,
        "\n[simulation]\ndt_s = {}\nmax_time_s = {}\nrocks_per_cell = {}\nrocks_per_point = {}\n",
        num(m.dt_s),
        num(m.max_time_s),
        m.rocks_per_cell,
        m.rocks_per_point
    );
    if let Some(tol) = m.until_stable_pct {
        let _ = writeln!(t, "until_stable_pct = {}", num(tol));
    }
    let o = &s.output;
    let _ = write!(
        t,
        "\n[output]\ntrajectories = {}\ntrajectory_interval_s = {}\nascii_rasters = {}\n\
         rocks_csv = {}\nscreen_crossings = {}\npercentiles = {}\nenergy_thresholds_kj = {}\n",
        o.trajectories,
        num(o.trajectory_interval_s),
        o.ascii_rasters,
        o.rocks_csv,
        o.screen_crossings,
        arr(&o.percentiles),
        arr(&o.energy_thresholds_kj)
    );
}

/// A string as a one-line TOML basic string (quotes, backslashes and control characters
/// escaped), so that names and paths can neither break the file nor a comment line.
fn quote(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out += "\\\"",
            '\\' => out += "\\\\",
            '\n' => out += "\\n",
            '\t' => out += "\\t",
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A float as TOML (always with a decimal point or exponent; shortest round-trip form).
fn num(v: f64) -> String {
    format!("{v:?}")
}

fn arr(v: &[f64]) -> String {
    format!(
        "[{}]",
        v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ")
    )
}

/// The scarring ground's keys of `g`, one per line.
fn scarring_keys(g: &rockfall_scenario::ScarringGround) -> String {
    format!(
        "me_mn_m2 = {}\nc_s = {}\nc_f = {}\nrho_kg_m3 = {}\nmu_min = {}\nmu_max = {}\n\
         beta_per_s = {}\nkappa_per_m = {}\n",
        num(g.me_mn_m2),
        num(g.c_s),
        num(g.c_f),
        num(g.rho_kg_m3),
        num(g.mu_min),
        num(g.mu_max),
        num(g.beta_per_s),
        num(g.kappa_per_m)
    )
}

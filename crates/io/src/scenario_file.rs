//! Scenario files (TOML) → [`Scenario`].

use crate::schema::{self, LayerRef, Param};
use crate::vector::inputs::{self, Frame, Outside};
use crate::vector::{self as vec_io, is_vector_path};
use crate::{InputError, scenario_error, trees};
use rockfall_forest::StandOptions;
use rockfall_raster::{Crs, Field, Grid, read_grid};
use rockfall_scenario::{Engine, ForestSpec, LumpedSettings, Nets, Scenario, Screen, Stands};
use rockfall_terrain::{Dem, SurfaceMap, Terrain};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

mod release;
mod rock;
mod settings;
mod tile;
mod tile_release;

use crate::tile_index::ReleaseCounts;
use settings::{output, rigid, simulation};
use tile::{TileRead, windowed};
pub use tile::{read_dem_geometry, read_scenario_tile};

/// Default soil type when a scenario gives none: class 4 (talus slope, r_n 0.38).
pub const DEFAULT_SOILTYPE: u8 = 4;
/// Default rock density when a scenario gives none, kg/m³ (seed 001 table 1).
pub const DEFAULT_DENSITY_KG_M3: f64 = 2700.0;
/// Default master seed when a scenario gives none.
pub const DEFAULT_SEED: u64 = 1;
/// Default share of conifers of a stand when a scenario gives none, %.
pub const DEFAULT_CONIFER_PERCENT: f64 = 50.0;
/// Default rock shape when a scenario gives neither `shape` nor `blshape`.
pub const DEFAULT_SHAPE: &str = "sphere";

/// Reads and validates a scenario file.
pub fn read_scenario(path: &Path) -> Result<Scenario, InputError> {
    let text = std::fs::read_to_string(path).map_err(|e| InputError::io(path, e))?;
    parse_scenario(&text, path)
}

fn parse_toml(text: &str, path: &Path) -> Result<schema::File, InputError> {
    toml::from_str(text).map_err(|e| InputError::Toml {
        path: path.to_path_buf(),
        message: e.to_string().trim_end().to_string(),
    })
}

/// [`read_scenario`] on a scenario file's text already read: `path` names it in errors and
/// its folder is where the files it names are found.
pub fn parse_scenario(text: &str, path: &Path) -> Result<Scenario, InputError> {
    Ok(parse(text, path, None)?.0)
}

/// The scenario of a scenario file's text, and when reading a tile, the release's
/// counts if it was scanned whole.
fn parse(
    text: &str,
    path: &Path,
    tile: Option<TileRead>,
) -> Result<(Scenario, Option<ReleaseCounts>), InputError> {
    let file = parse_toml(text, path)?;
    let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let mut r = Resolver {
        base,
        file: path.to_path_buf(),
        sources: BTreeMap::new(),
        frame: None,
        notes: Vec::new(),
        layers: BTreeMap::new(),
        tile,
    };
    let mut scenario = r.build(file, path)?;
    let mut built = None;
    if let Some(t) = r.tile.take() {
        built = t.built;
        let (region_source_cells, ordinals) = t.found.unwrap_or_default();
        scenario.tile = Some(Box::new(rockfall_scenario::TileFrame {
            core: t.core,
            window: t.window,
            trusted: t.window,
            region_source_cells,
            ordinals,
        }));
    }
    scenario
        .validate()
        .map_err(|e| scenario_error(e, &scenario.sources, path))?;
    Ok((scenario, built))
}

/// Reads rasters relative to the scenario's folder and records where every parameter came
/// from. No copy of a raster is kept: a file named for two parameters is read twice, so that
/// loading never holds a second copy of a (possibly huge) DEM.
struct Resolver {
    base: PathBuf,
    file: PathBuf,
    sources: BTreeMap<String, PathBuf>,
    /// The DEM's grid and CRS, once read: what vector layers are checked against and burnt on.
    frame: Option<Frame>,
    /// What reading found worth saying (printed by `check`).
    notes: Vec<String>,
    /// Vector layers read so far, by (file, layer asked for, read for a per-cell parameter):
    /// a layer that gives several keys (a stand layer's attributes) is read and checked once.
    /// A tile reads a per-cell parameter's layer and tree points over its window only; the
    /// same file as nets is read whole (their numbering and screens span the region), as a
    /// release is without the tile index's counts (`tile_release.rs`).
    layers: BTreeMap<(PathBuf, Option<String>, bool), Rc<vec_io::Layer>>,
    /// Reading one spatial tile of the region: its windows.
    tile: Option<TileRead>,
}

/// What a per-cell key burnt from polygons takes outside every polygon: its default, except
/// for keys without one (r_n, rolling_friction, the rock's dimensions and shape: an error) and the stand keys
/// (no value: no stand there). Ours: the scenario format has no other place to say it.
fn outside(param: &str, default: f64) -> Outside {
    match param {
        "r_n" | "rolling_friction" | "rock.d1_m" | "rock.d2_m" | "rock.d3_m" | "rock.blshape" => {
            Outside::Error
        }
        "nrtrees" | "dbhmean" | "dbhstd" => Outside::Nodata,
        _ => Outside::Default(default),
    }
}

impl Resolver {
    fn path(&self, p: &str) -> PathBuf {
        self.base.join(p)
    }

    /// The path of the raster named `p` for `param`, recorded as its source; a missing file
    /// is an error naming the scenario file.
    fn raster_path(&mut self, param: &str, p: &str) -> Result<PathBuf, InputError> {
        let path = self.path(p);
        self.sources.insert(param.into(), path.clone());
        if !path.is_file() {
            return Err(InputError::Missing {
                path,
                what: format!("raster for `{param}` (named in {})", self.file.display()),
            });
        }
        Ok(path)
    }

    fn grid(&mut self, param: &str, p: &str) -> Result<Grid<f64>, InputError> {
        let path = self.raster_path(param, p)?;
        match self.tile.as_ref().map(|t| t.window) {
            None => Ok(read_grid(&path)?),
            Some(window) => windowed(&path, window),
        }
    }

    fn field(&mut self, param: &str, p: Option<Param>, default: f64) -> Result<Field, InputError> {
        match p {
            None => Ok(Field::Const(default)),
            Some(Param::Num(v)) => Ok(Field::Const(v)),
            Some(Param::Path(s)) => Ok(Field::Grid(self.grid(param, &s)?)),
            Some(Param::Vector(v)) => {
                let layer = self.read_layer(param, &v.vector, v.layer.as_deref(), true)?;
                let frame = self.frame()?;
                let (grid, cells) =
                    inputs::field_grid(&layer, &v.field, &frame, outside(param, default), param)?;
                self.notes
                    .push(inputs::describe(param, &layer, cells, "cells covered"));
                Ok(Field::Grid(grid))
            }
        }
    }

    fn frame(&self) -> Result<Frame, InputError> {
        self.frame
            .clone()
            .ok_or_else(|| self.invalid("terrain", "vector inputs need the DEM read first"))
    }

    /// Reads a vector layer named by the scenario, checked against the DEM's CRS.
    fn layer(
        &mut self,
        param: &str,
        p: &str,
        layer: Option<&str>,
    ) -> Result<Rc<vec_io::Layer>, InputError> {
        self.read_layer(param, p, layer, false)
    }

    /// [`Self::layer`]; `for_cells` for a per-cell parameter's polygons or tree points, which
    /// a tile reads over its window only ([`inputs::open_windowed`]).
    fn read_layer(
        &mut self,
        param: &str,
        p: &str,
        layer: Option<&str>,
        for_cells: bool,
    ) -> Result<Rc<vec_io::Layer>, InputError> {
        let path = self.path(p);
        self.sources.insert(param.into(), path.clone());
        let frame = self.frame()?;
        // on the whole grid both reads are the same: one read serves both
        let windowed = for_cells && frame.window.is_some();
        let key = (path, layer.map(str::to_string), windowed);
        if let Some(l) = self.layers.get(&key) {
            return Ok(Rc::clone(l));
        }
        let open = match windowed {
            true => inputs::open_windowed,
            false => inputs::open,
        };
        let l = Rc::new(open(&key.0, layer, &frame, &mut self.notes)?);
        self.layers.insert(key, Rc::clone(&l));
        Ok(l)
    }

    /// A layer reference: (path, layer) when it names a vector file, else the raster path.
    fn layer_ref(r: LayerRef) -> Result<(String, Option<String>), String> {
        match r {
            LayerRef::Path(p) if is_vector_path(Path::new(&p)) => Ok((p, None)),
            LayerRef::Path(p) => Err(p),
            LayerRef::Vector(v) => Ok((v.vector, v.layer)),
        }
    }

    fn invalid(&self, key: &str, message: impl std::fmt::Display) -> InputError {
        InputError::invalid(&self.file, format!("{key}: {message}"))
    }

    fn build(&mut self, f: schema::File, path: &Path) -> Result<Scenario, InputError> {
        let engine = match &f.engine {
            None => Engine::Lumped,
            Some(e) => e.parse().map_err(|m| self.invalid("engine", m))?,
        };
        let terrain = self.terrain(f.terrain)?;
        let rock = self.rock(f.rock)?;
        let release = self.release(f.release, &terrain)?;
        let forest = f.forest.map(|s| self.forest(s)).transpose()?;
        let (nets, net_screens) = match f.nets.map(|n| self.nets(n)).transpose()? {
            Some((nets, screens)) => (Some(nets), screens),
            None => (None, Vec::new()),
        };
        let screens = (f.screens.into_iter())
            .map(|s| Screen {
                name: s.name,
                points_m: s.points_m,
                capacity_kj: s.capacity_kj,
                height_m: s.height_m,
                net: None,
            })
            .chain(net_screens)
            .collect();
        let lumped = self.lumped(f.lumped)?;
        let rigid = rigid(f.rigid);
        let contact =
            crate::contact_file::contact(f.contact).map_err(|(key, m)| self.invalid(&key, m))?;
        let simulation = simulation(f.simulation);
        let output = output(f.output);
        let name = f.name.unwrap_or_else(|| {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scenario".into())
        });
        Ok(Scenario {
            name,
            engine,
            seed: f.seed.unwrap_or(DEFAULT_SEED),
            terrain,
            forest,
            nets,
            rock,
            release,
            screens,
            lumped,
            rigid,
            contact,
            simulation,
            output,
            sources: std::mem::take(&mut self.sources),
            notes: std::mem::take(&mut self.notes),
            tile: None,
        })
    }

    fn terrain(&mut self, t: schema::TerrainSec) -> Result<Terrain, InputError> {
        let mut dem_grid = self.grid("dem", &t.dem)?;
        if let Some(code) = t.epsg {
            dem_grid.set_crs(Some(Crs::from_epsg(code)));
        }
        self.frame = Some(Frame {
            geometry: *dem_grid.geometry(),
            crs: dem_grid.crs().cloned(),
            window: self.tile.as_ref().map(|t| t.window),
        });
        let dem_path = self.path(&t.dem);
        let dem = Dem::new(dem_grid).map_err(|e| InputError::invalid(&dem_path, e.to_string()))?;
        let surface = SurfaceMap {
            soil_type: self.field("soiltype", t.soiltype, DEFAULT_SOILTYPE as f64)?,
            r_n: t.r_n.map(|p| self.field("r_n", Some(p), 0.0)).transpose()?,
            rolling_friction: (t.rolling_friction)
                .map(|p| self.field("rolling_friction", Some(p), 0.0))
                .transpose()?,
            ground_class: (t.ground_class)
                .map(|p| self.field("ground_class", Some(p), 0.0))
                .transpose()?,
            rg70_m: self.field("rg70", t.rg70_m, 0.0)?,
            rg20_m: self.field("rg20", t.rg20_m, 0.0)?,
            rg10_m: self.field("rg10", t.rg10_m, 0.0)?,
        };
        Terrain::new(dem, surface).map_err(|e| scenario_error(e.into(), &self.sources, &self.file))
    }

    fn forest(&mut self, f: schema::ForestSec) -> Result<ForestSpec, InputError> {
        let stands_given = f.stems_per_ha.is_some()
            || f.dbh_mean_cm.is_some()
            || f.dbh_sd_cm.is_some()
            || f.conifer_percent.is_some();
        let lists = [
            f.trees.is_some(),
            f.trees_csv.is_some(),
            f.treefile.is_some(),
            stands_given,
        ];
        if lists.iter().filter(|g| **g).count() != 1 {
            return Err(self.invalid("forest", "give exactly one of `trees` (a point layer), `trees_csv`, `treefile` or stands (`stems_per_ha`, `dbh_mean_cm`, `dbh_sd_cm`, `conifer_percent`)"));
        }
        if !stands_given {
            self.note_stand_only_keys(&f);
        }
        if let Some(r) = f.trees {
            let (p, layer) = Self::layer_ref(r).map_err(|p| {
                self.invalid("forest.trees", format!("`{p}` is not a vector file (.geojson, .json, .shp, .gpkg); tree lists go in `trees_csv`"))
            })?;
            let l = self.read_layer("forest.trees", &p, layer.as_deref(), true)?;
            let stems = inputs::stems(&l, &self.frame()?)?;
            self.notes
                .push(inputs::describe("forest.trees", &l, stems.len(), "stems"));
            return Ok(ForestSpec::Stems(stems));
        }
        if let Some(p) = f.trees_csv.or(f.treefile.clone()) {
            let path = self.path(&p);
            if !path.is_file() {
                return Err(InputError::Missing {
                    path,
                    what: format!("tree list (named in {})", self.file.display()),
                });
            }
            self.sources.insert("forest.trees".into(), path.clone());
            let format = match f.treefile.is_some() {
                true => trees::TreeFormat::Treefile,
                false => trees::TreeFormat::Csv,
            };
            // a tile holds the stems of its window only
            let frame = self.frame()?;
            let (stems, all) = trees::read_tree_list(&path, format, |s| frame.keeps(s.x_m, s.y_m))?;
            if frame.window.is_some() {
                self.notes.push(format!(
                    "forest.trees: {}: {all} trees, {} in the tile's window",
                    path.display(),
                    stems.len()
                ));
            }
            return Ok(ForestSpec::Stems(stems));
        }
        let need = |p: Option<Param>, key: &str| {
            p.ok_or_else(|| self.invalid("forest", format!("stands need `{key}`")))
        };
        let stems = need(f.stems_per_ha, "stems_per_ha")?;
        let mean = need(f.dbh_mean_cm, "dbh_mean_cm")?;
        let sd = need(f.dbh_sd_cm, "dbh_sd_cm")?;
        let height_m = match (f.height_mean_m, f.height_sd_m) {
            (None, None) => None,
            (Some(m), sd) => Some((m, sd.unwrap_or(0.0))),
            (None, Some(_)) => {
                return Err(self.invalid("forest.height_sd_m", "needs `height_mean_m`"));
            }
        };
        let defaults = StandOptions::default();
        Ok(ForestSpec::Stands(Box::new(Stands {
            stems_per_ha: self.field("nrtrees", Some(stems), 0.0)?,
            dbh_mean_cm: self.field("dbhmean", Some(mean), 0.0)?,
            dbh_sd_cm: self.field("dbhstd", Some(sd), 0.0)?,
            conifer_percent: self.field(
                "conif_percent",
                f.conifer_percent,
                DEFAULT_CONIFER_PERCENT,
            )?,
            height_m,
            options: StandOptions {
                dbh_min_cm: f.dbh_min_cm.unwrap_or(defaults.dbh_min_cm),
                dbh_max_cm: f.dbh_max_cm.unwrap_or(defaults.dbh_max_cm),
            },
        })))
    }

    /// Notes the keys that shape stands only (heights and the DBH truncation) when the forest
    /// is a tree list, which gives every stem's DBH and (optionally) height itself.
    fn note_stand_only_keys(&mut self, f: &schema::ForestSec) {
        let given: Vec<&str> = [
            ("height_mean_m", f.height_mean_m.is_some()),
            ("height_sd_m", f.height_sd_m.is_some()),
            ("dbh_min_cm", f.dbh_min_cm.is_some()),
            ("dbh_max_cm", f.dbh_max_cm.is_some()),
        ]
        .into_iter()
        .filter_map(|(k, g)| g.then_some(k))
        .collect();
        if !given.is_empty() {
            self.notes.push(format!(
                "ignored forest.{}: stands only; a tree list gives each stem's DBH and height",
                given.join(", forest.")
            ));
        }
    }

    /// The nets and, with `screens = true`, one screen per net.
    fn nets(&mut self, n: schema::NetsSec) -> Result<(Nets, Vec<Screen>), InputError> {
        let with_screens = n.screens.unwrap_or(false);
        let (nets, lines) = match (n.lines, n.number, n.energy_kj, n.height_m) {
            (Some(r), None, None, None) => {
                let (p, layer) = Self::layer_ref(r).map_err(|p| {
                    self.invalid(
                        "nets.lines",
                        format!("`{p}` is not a vector file (.geojson, .json, .shp, .gpkg)"),
                    )
                })?;
                let l = self.layer("net_number", &p, layer.as_deref())?;
                let frame = self.frame()?;
                let lines = inputs::net_lines(&l, &frame)?;
                let cells: usize = lines.iter().map(|n| n.cells.len()).sum();
                self.notes
                    .push(inputs::describe("nets.lines", &l, cells, "cells covered"));
                for key in ["net_energy", "net_height"] {
                    self.sources.insert(key.into(), self.path(&p));
                }
                let [number, energy_kj, height_m] =
                    inputs::net_grids(&lines, &frame).ok_or_else(|| {
                        self.invalid("nets.lines", "the tile's window does not fit the DEM")
                    })?;
                let nets = Nets {
                    number: Field::Grid(number),
                    energy_kj: Field::Grid(energy_kj),
                    height_m: Field::Grid(height_m),
                };
                (nets, Some(lines))
            }
            (None, Some(number), Some(energy_kj), Some(height_m)) => {
                let nets = Nets {
                    number: self.field("net_number", Some(number), 0.0)?,
                    energy_kj: self.field("net_energy", Some(energy_kj), 0.0)?,
                    height_m: self.field("net_height", Some(height_m), 0.0)?,
                };
                (nets, None)
            }
            _ => {
                return Err(self.invalid(
                    "nets",
                    "give either `lines` (a line layer) or all of `number`, `energy_kj` and \
                     `height_m`",
                ));
            }
        };
        let screens = match (with_screens, &lines) {
            (false, _) => Vec::new(),
            (true, Some(lines)) => crate::nets::line_screens(lines),
            (true, None) => crate::nets::raster_screens(&nets),
        };
        Ok((nets, screens))
    }

    fn lumped(&self, l: Option<schema::LumpedSec>) -> Result<LumpedSettings, InputError> {
        let d = LumpedSettings::default();
        let Some(l) = l else { return Ok(d) };
        Ok(LumpedSettings {
            moh: match l.moh {
                None => d.moh,
                Some(m) => m.parse().map_err(|e| self.invalid("lumped.moh", e))?,
            },
            tangential: match l.tangential_law {
                None => d.tangential,
                Some(m) => (m.parse()).map_err(|e| self.invalid("lumped.tangential_law", e))?,
            },
            rt_variation: l.rt_variation.unwrap_or(d.rt_variation),
            slope_reduction_max_deg: l
                .slope_reduction_max_deg
                .unwrap_or(d.slope_reduction_max_deg),
            max_lateral_deviation_deg: l
                .max_lateral_deviation_deg
                .unwrap_or(d.max_lateral_deviation_deg),
            stop_velocity_ms: l.stop_velocity_ms.unwrap_or(d.stop_velocity_ms),
            rn_velocity_scale_ms: l.rn_velocity_scale_ms.unwrap_or(d.rn_velocity_scale_ms),
            roughness_tilt_factor: l.roughness_tilt_factor.unwrap_or(d.roughness_tilt_factor),
            lift_off_obstacle_factor: l
                .lift_off_obstacle_factor
                .unwrap_or(d.lift_off_obstacle_factor),
            soil_friction_scale: l.soil_friction_scale.unwrap_or(d.soil_friction_scale),
        })
    }
}

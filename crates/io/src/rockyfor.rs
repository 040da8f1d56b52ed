//! Rockyfor3D input folders.
//!
//! Required (ESRI ASCII grids on the DEM's grid): `dem.asc`; `rockdensity.asc` (kg/m³;
//! cells above 0 are source cells); `d1.asc`, `d2.asc`, `d3.asc` (block dimensions, m); `blshape.asc`
//! (1 rectangular, 2 ellipsoidal, 3 spherical, 4 disc); `rg70.asc`, `rg20.asc`, `rg10.asc`
//! (obstacle heights, m); `soiltype.asc` (0–7). Optional forest: `nrtrees.asc` (stems/ha),
//! `dbhmean.asc`, `dbhstd.asc` (cm), `conif_percent.asc` (all four together), or a tree file
//! `treefile.txt`. Optional nets: `net_number.asc`, `net_energy.asc` (kJ), `net_height.asc`
//! (m), all three together. File names match in any case; `.prj` sidecars are read with their
//! grids; other files are ignored with a note.

use crate::{InputError, scenario_error, trees};
use rockfall_forest::StandOptions;
use rockfall_raster::{Field, Grid, ascii_grid};
use rockfall_scenario::{ForestSpec, Nets, Release, RockShape, RockSpec, Scenario, Stands};
use rockfall_terrain::{Dem, SurfaceMap, Terrain};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const REQUIRED: [(&str, &str); 10] = [
    ("dem", "the digital elevation model (m)"),
    (
        "rockdensity",
        "rock density per cell (kg/m³; cells > 0 are source cells)",
    ),
    ("d1", "block dimension d1 (m)"),
    ("d2", "block dimension d2 (m)"),
    ("d3", "block dimension d3 (m)"),
    ("blshape", "block shape codes (1–4)"),
    ("rg70", "obstacle height of the 70 % cover class (m)"),
    ("rg20", "obstacle height of the 20 % cover class (m)"),
    ("rg10", "obstacle height of the 10 % cover class (m)"),
    ("soiltype", "soil type classes (0–7)"),
];
const STANDS: [&str; 4] = ["nrtrees", "dbhmean", "dbhstd", "conif_percent"];
const NETS: [&str; 3] = ["net_number", "net_energy", "net_height"];
const TREEFILE: &str = "treefile.txt";

/// Reads a Rockyfor3D input folder into a scenario (lumped engine, seed 1, defaults of
/// [`SimulationSettings`]); validates it completely.
pub fn read_folder(dir: &Path) -> Result<Scenario, InputError> {
    if !dir.is_dir() {
        return Err(InputError::Missing {
            path: dir.to_path_buf(),
            what: "input folder".into(),
        });
    }
    let files = list_files(dir)?;
    let mut used: Vec<String> = Vec::new();
    let mut sources = BTreeMap::new();
    let mut notes = Vec::new();

    let mut grids = Vec::with_capacity(REQUIRED.len());
    for (name, what) in REQUIRED {
        let key = format!("{name}.asc");
        let Some(path) = files.get(&key) else {
            return Err(InputError::Missing {
                path: dir.join(key),
                what: what.into(),
            });
        };
        used.push(key);
        grids.push((path.clone(), ascii_grid::read(path)?));
    }
    let [
        dem,
        density,
        d1,
        d2,
        d3,
        blshape,
        rg70,
        rg20,
        rg10,
        soiltype,
    ]: [(PathBuf, Grid<f64>); 10] = grids
        .try_into()
        .map_err(|_| InputError::invalid(dir, "internal: required grid count"))?;
    // The DEM first: every other grid must sit on it.
    let dem_path = dem.0.clone();
    sources.insert("dem".into(), dem.0);
    let mut field = |param: &str, (path, grid): (PathBuf, Grid<f64>)| {
        sources.insert(param.to_string(), path);
        Field::Grid(grid)
    };
    let dem = Dem::new(dem.1).map_err(|e| InputError::invalid(&dem_path, e.to_string()))?;
    let surface = SurfaceMap {
        soil_type: field("soiltype", soiltype),
        r_n: None,
        rolling_friction: None,
        ground_class: None,
        rg70_m: field("rg70", rg70),
        rg20_m: field("rg20", rg20),
        rg10_m: field("rg10", rg10),
    };
    let density_path = density.0.clone();
    let rock = RockSpec {
        shape: RockShape::PerCell(field("rock.blshape", blshape)),
        dims_m: [
            field("rock.d1_m", d1),
            field("rock.d2_m", d2),
            field("rock.d3_m", d3),
        ],
        volume_m3: None,
        density_kg_m3: field("rock.density_kg_m3", density),
        volume_variation_percent: 0.0,
        volume_distribution: None,
    };
    // Source cells: rockdensity > 0. Alignment is checked first so the index is meaningful.
    dem.geometry()
        .check_aligned(
            rock.density_kg_m3
                .as_grid()
                .map(|g| g.geometry())
                .unwrap_or(dem.geometry()),
        )
        .map_err(|m| InputError::invalid(&density_path, m.to_string()))?;
    let cells: Vec<usize> = rock
        .density_kg_m3
        .as_grid()
        .map(|g| {
            g.values()
                .iter()
                .zip(g.mask())
                .enumerate()
                .filter(|(_, (v, ok))| **ok && **v > 0.0)
                .map(|(i, _)| i)
                .collect()
        })
        .unwrap_or_default();
    if cells.is_empty() {
        return Err(InputError::invalid(
            &density_path,
            "no source cell: no cell has a rock density > 0, so there is nothing to release",
        ));
    }

    let forest = read_forest(dir, &files, &mut used, &mut sources, &mut notes)?;
    let nets = read_nets(dir, &files, &mut used, &mut sources)?;

    for (name, path) in &files {
        let sidecar = name.ends_with(".prj") && files.contains_key(&name.replace(".prj", ".asc"));
        if !used.contains(name) && !sidecar {
            notes.push(format!(
                "ignored {} (not a Rockyfor3D input)",
                path.display()
            ));
        }
    }
    let terrain =
        Terrain::new(dem, surface).map_err(|e| scenario_error(e.into(), &sources, &dem_path))?;
    let name = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "rockyfor3d".into());
    let release = Release {
        cells,
        ..Release::default()
    };
    let mut scenario = Scenario {
        forest,
        nets,
        sources,
        notes,
        tile: None,
        ..Scenario::new(&name, terrain, rock, release)
    };
    // a folder names no number of rocks: the defaults stand in for them
    scenario.simulation.rocks_per_cell_given = false;
    scenario.simulation.rocks_per_point_given = false;
    scenario
        .validate()
        .map_err(|e| scenario_error(e, &scenario.sources, &dem_path))?;
    Ok(scenario)
}

/// Lower-case file name → path, for the files directly in `dir`.
fn list_files(dir: &Path) -> Result<BTreeMap<String, PathBuf>, InputError> {
    let mut out = BTreeMap::new();
    let entries = std::fs::read_dir(dir).map_err(|e| InputError::io(dir, e))?;
    for e in entries {
        let e = e.map_err(|e| InputError::io(dir, e))?;
        let path = e.path();
        if path.is_file() {
            out.insert(e.file_name().to_string_lossy().to_ascii_lowercase(), path);
        }
    }
    Ok(out)
}

fn read_forest(
    dir: &Path,
    files: &BTreeMap<String, PathBuf>,
    used: &mut Vec<String>,
    sources: &mut BTreeMap<String, PathBuf>,
    notes: &mut Vec<String>,
) -> Result<Option<ForestSpec>, InputError> {
    let present: Vec<&str> = STANDS
        .iter()
        .copied()
        .filter(|n| files.contains_key(&format!("{n}.asc")))
        .collect();
    if let Some(path) = files.get(TREEFILE) {
        used.push(TREEFILE.into());
        sources.insert("forest.trees".into(), path.clone());
        if !present.is_empty() {
            notes.push(format!(
                "{TREEFILE} given: the stand rasters ({}) are not used",
                present.join(", ")
            ));
            used.extend(present.iter().map(|n| format!("{n}.asc")));
        }
        return Ok(Some(ForestSpec::Stems(trees::read_treefile(path)?)));
    }
    let Some([stems, mean, sd, conifer]) = read_group(dir, files, used, sources, STANDS, "stand")?
    else {
        return Ok(None);
    };
    Ok(Some(ForestSpec::Stands(Box::new(Stands {
        stems_per_ha: stems,
        dbh_mean_cm: mean,
        dbh_sd_cm: sd,
        conifer_percent: conifer,
        height_m: None,
        options: StandOptions::default(),
    }))))
}

fn read_nets(
    dir: &Path,
    files: &BTreeMap<String, PathBuf>,
    used: &mut Vec<String>,
    sources: &mut BTreeMap<String, PathBuf>,
) -> Result<Option<Nets>, InputError> {
    let group = read_group(dir, files, used, sources, NETS, "net")?;
    Ok(group.map(|[number, energy_kj, height_m]| Nets {
        number,
        energy_kj,
        height_m,
    }))
}

/// Reads rasters that come together (`{name}.asc` for every name): `None` when none is
/// present, an error naming the first missing one when only some are.
fn read_group<const N: usize>(
    dir: &Path,
    files: &BTreeMap<String, PathBuf>,
    used: &mut Vec<String>,
    sources: &mut BTreeMap<String, PathBuf>,
    names: [&str; N],
    what: &str,
) -> Result<Option<[Field; N]>, InputError> {
    let key = |n: &str| format!("{n}.asc");
    if !names.iter().any(|n| files.contains_key(&key(n))) {
        return Ok(None);
    }
    let mut fields = Vec::with_capacity(N);
    for name in names {
        let Some(path) = files.get(&key(name)) else {
            return Err(InputError::Missing {
                path: dir.join(key(name)),
                what: format!(
                    "{what} raster (the {what} rasters {} come together)",
                    names.join(", ")
                ),
            });
        };
        used.push(key(name));
        sources.insert(name.into(), path.clone());
        fields.push(Field::Grid(ascii_grid::read(path)?));
    }
    Ok(fields.try_into().ok())
}

//! `rockfall.qgs`: a QGIS 3 project that opens a run's output folder as a map — every raster
//! with the style of its `.qml` (the same renderer, embedded), the trajectories and stems,
//! over the DEM drawn with QGIS's hillshade renderer, in the DEM's CRS.
//!
//! The project's paths are relative (QGIS's `Paths/Absolute` false), so the folder can be
//! moved; the DEM is referred to relative to the folder when it can be, absolutely when it is
//! on another root. A run of a built-in site has no DEM file: its project has no hillshade.

use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

use rockfall_raster::{Crs, GridGeometry};

use crate::qml::{number, xml_escape};
use crate::{ReportError, ReportInput};

/// The project file's name in the output folder.
pub const PROJECT_FILE: &str = "rockfall.qgs";

/// Rasters shown when the project opens; the others are listed, unchecked.
const SHOWN: [&str; 2] = ["Reach_probability", "E_95"];

/// One map layer of the project.
struct MapLayer {
    id: String,
    name: String,
    /// Path as written in the project (relative to it, or absolute).
    source: String,
    /// `raster` or `vector`.
    kind: &'static str,
    provider: &'static str,
    /// `<pipe>` of a raster, the geometry type of a vector.
    body: String,
    /// A vector's `<renderer-v2>` element (empty: QGIS's default symbol).
    renderer: String,
    checked: bool,
}

/// Writes `rockfall.qgs` into `out` for the rasters of `pipes` (name, `<pipe>` element) whose
/// GeoTIFFs are there; returns its path.
pub(crate) fn write_project(
    out: &Path,
    input: &ReportInput<'_>,
    pipes: &[(String, String)],
) -> Result<PathBuf, ReportError> {
    let mut layers = Vec::new();
    for (file, geometry) in [("trajectories.geojson", "Line"), ("stems.geojson", "Point")] {
        if out.join(file).is_file() {
            layers.push(MapLayer {
                id: layer_id(file),
                name: file.trim_end_matches(".geojson").into(),
                source: format!("./{file}"),
                kind: "vector",
                provider: "ogr",
                body: geometry.into(),
                renderer: String::new(),
                checked: true,
            });
        }
    }
    for (name, pipe) in pipes {
        let file = format!("{name}.tif");
        if out.join(&file).is_file() {
            layers.push(MapLayer {
                id: layer_id(name),
                name: name.clone(),
                source: format!("./{file}"),
                kind: "raster",
                provider: "gdal",
                body: pipe.clone(),
                renderer: String::new(),
                checked: SHOWN.contains(&name.as_str()),
            });
        }
    }
    if let Some(dem) = input.scenario.source_of("dem").filter(|p| p.is_file()) {
        layers.push(MapLayer {
            id: layer_id("hillshade"),
            name: "Hillshade (DEM)".into(),
            source: relative_to(out, dem),
            kind: "raster",
            provider: "gdal",
            body: HILLSHADE.into(),
            renderer: String::new(),
            checked: true,
        });
    }
    let dem = &input.scenario.terrain.dem;
    let text = project(&input.scenario.name, dem.geometry(), dem.crs(), &layers);
    let path = out.join(PROJECT_FILE);
    rockfall_raster::atomic::write_bytes_atomic(&path, text.as_bytes())?;
    Ok(path)
}

/// A layer of a project written by [`write_layers_project`].
#[derive(Debug, Clone)]
pub struct ProjectLayer {
    /// Its name in the layer tree.
    pub name: String,
    /// Its data source, relative to the project (`./Hazard_level.tif`,
    /// `./hazard_zones.gpkg|layername=hazard_zones`).
    pub source: String,
    /// A raster's `<pipe>` element (its renderer), or a vector's `<renderer-v2>` element.
    pub style: String,
    /// `Some(geometry)` (`Polygon`, `Line`, `Point`) for a vector layer, `None` for a raster.
    pub vector: Option<&'static str>,
    /// Shown when the project opens.
    pub checked: bool,
}

/// Writes a QGIS project at `path` showing `layers` (first on top) over the extent of `g`
/// in `crs`, with a hillshade of the DEM file `dem` at the bottom when given.
pub fn write_layers_project(
    path: &Path,
    title: &str,
    g: &GridGeometry,
    crs: Option<&Crs>,
    layers: &[ProjectLayer],
    dem: Option<&Path>,
) -> Result<PathBuf, ReportError> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut all: Vec<MapLayer> = layers.iter().map(MapLayer::from).collect();
    if let Some(dem) = dem.filter(|p| p.is_file()) {
        all.push(MapLayer {
            id: layer_id("hillshade"),
            name: "Hillshade (DEM)".into(),
            source: relative_to(dir, dem),
            kind: "raster",
            provider: "gdal",
            body: HILLSHADE.into(),
            renderer: String::new(),
            checked: true,
        });
    }
    let text = project(title, g, crs, &all);
    rockfall_raster::atomic::write_bytes_atomic(path, text.as_bytes())?;
    Ok(path.to_path_buf())
}

/// QGIS's hillshade renderer (sun from the north-west at 45°, as the report's relief).
const HILLSHADE: &str = "  <pipe>\n    <rasterrenderer type=\"hillshade\" band=\"1\" opacity=\"1\" \
    alphaBand=\"-1\" zFactor=\"1\" altitude=\"45\" azimuth=\"315\" multidirection=\"0\"/>\n\
    <brightnesscontrast brightness=\"0\" contrast=\"0\" gamma=\"1\"/>\n  </pipe>\n";

fn layer_id(name: &str) -> String {
    let clean: String = (name.chars())
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    format!("rockfall_{clean}")
}

/// `target` as the project in `dir` should name it: relative when both are absolute paths
/// on the same root, else absolute.
fn relative_to(dir: &Path, target: &Path) -> String {
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let (dir, target) = (abs(dir), abs(target));
    let (d, t): (Vec<Component>, Vec<Component>) =
        (dir.components().collect(), target.components().collect());
    let common = d.iter().zip(&t).take_while(|(a, b)| a == b).count();
    if common == 0 {
        return target.to_string_lossy().into_owned();
    }
    let mut rel = PathBuf::from(".");
    for _ in common..d.len() {
        rel.push("..");
    }
    for c in &t[common..] {
        rel.push(c);
    }
    rel.to_string_lossy().into_owned()
}

/// The `<spatialrefsys>` of a CRS: its WKT and, when known, its EPSG authority id.
fn srs(crs: Option<&Crs>) -> String {
    let Some(crs) = crs else {
        return "<spatialrefsys/>".into();
    };
    let wkt = crs.wkt_for_prj().unwrap_or_default();
    let authid = crs.epsg.map(|c| format!("EPSG:{c}")).unwrap_or_default();
    format!(
        "<spatialrefsys><wkt>{}</wkt><authid>{authid}</authid><description>{}</description></spatialrefsys>",
        xml_escape(&wkt),
        xml_escape(&crs.describe())
    )
}

impl From<&ProjectLayer> for MapLayer {
    fn from(l: &ProjectLayer) -> MapLayer {
        MapLayer {
            id: layer_id(&l.name),
            name: l.name.clone(),
            source: l.source.clone(),
            kind: if l.vector.is_some() {
                "vector"
            } else {
                "raster"
            },
            provider: if l.vector.is_some() { "ogr" } else { "gdal" },
            body: l.vector.map_or(l.style.clone(), str::to_string),
            renderer: if l.vector.is_some() {
                l.style.clone()
            } else {
                String::new()
            },
            checked: l.checked,
        }
    }
}

/// A layer's entry in the layer tree.
fn tree_entry(l: &MapLayer) -> String {
    format!(
        "    <layer-tree-layer id=\"{}\" name=\"{}\" source=\"{}\" providerKey=\"{}\" checked=\"{}\" expanded=\"0\"/>\n",
        l.id,
        xml_escape(&l.name),
        xml_escape(&l.source),
        l.provider,
        if l.checked {
            "Qt::Checked"
        } else {
            "Qt::Unchecked"
        }
    )
}

/// A layer's `<maplayer>` element, with the project's `extent` and `srs` elements.
fn map_layer(l: &MapLayer, extent: &str, srs: &str) -> String {
    let mut s = String::new();
    let geometry = match l.kind {
        "vector" => format!(" geometry=\"{}\"", l.body),
        _ => String::new(),
    };
    let _ = writeln!(s, "    <maplayer type=\"{}\"{geometry}>", l.kind);
    let _ = writeln!(s, "      {extent}");
    let _ = writeln!(s, "      <id>{}</id>", l.id);
    let _ = writeln!(
        s,
        "      <datasource>{}</datasource>",
        xml_escape(&l.source)
    );
    let _ = writeln!(s, "      <layername>{}</layername>", xml_escape(&l.name));
    let _ = writeln!(s, "      <srs>{srs}</srs>");
    let _ = writeln!(s, "      <provider>{}</provider>", l.provider);
    if l.kind == "raster" {
        s += &l.body;
    } else {
        s += &l.renderer;
    }
    let _ = writeln!(s, "      <blendMode>0</blendMode>");
    let _ = writeln!(s, "    </maplayer>");
    s
}

/// Adds `layers` on top of the project at `path` written by a run (`rockfall.qgs`), in
/// its extent and CRS; a layer already there (same id) is replaced. Sources are relative
/// to the project.
pub fn add_layers(path: &Path, layers: &[ProjectLayer]) -> Result<(), ReportError> {
    let text = std::fs::read_to_string(path).map_err(|source| ReportError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let between = |a: &str, b: &str| -> Option<String> {
        let i = text.find(a)?;
        let j = text[i..].find(b)? + i + b.len();
        Some(text[i..j].to_string())
    };
    let (Some(extent), Some(srs)) = (
        between("<extent>", "</extent>"),
        between("<projectCrs>", "</projectCrs>"),
    ) else {
        return Err(ReportError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::other("not a project written by rockfall"),
        });
    };
    let srs = srs
        .trim_start_matches("<projectCrs>")
        .trim_end_matches("</projectCrs>")
        .to_string();
    let mut text = text.clone();
    for l in layers.iter().rev() {
        let m = MapLayer::from(l);
        text = remove_layer(&text, &m.id);
        text = text.replacen(
            "  <layer-tree-group>\n",
            &format!("  <layer-tree-group>\n{}", tree_entry(&m)),
            1,
        );
        text = text.replacen(
            "  <projectlayers>\n",
            &format!("  <projectlayers>\n{}", map_layer(&m, &extent, &srs)),
            1,
        );
    }
    rockfall_raster::atomic::write_bytes_atomic(path, text.as_bytes())?;
    Ok(())
}

/// The project text without the layer `id` (its tree entry and its `<maplayer>`).
fn remove_layer(text: &str, id: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut skipping = false;
    for line in text.split_inclusive('\n') {
        if line.contains(&format!("<layer-tree-layer id=\"{id}\"")) {
            continue;
        }
        if line.trim_start().starts_with("<maplayer") {
            skipping = false;
        }
        out.push_str(line);
        if line.trim() == format!("<id>{id}</id>") {
            // the <maplayer> line and its extent went out already: drop the whole element
            skipping = true;
            let start = out.rfind("    <maplayer").unwrap_or(out.len());
            out.truncate(start);
            continue;
        }
        if skipping {
            out.truncate(out.len() - line.len());
            if line.trim() == "</maplayer>" {
                skipping = false;
            }
        }
    }
    out
}

fn project(title: &str, g: &GridGeometry, crs: Option<&Crs>, layers: &[MapLayer]) -> String {
    let srs = srs(crs);
    let extent = format!(
        "<extent><xmin>{}</xmin><ymin>{}</ymin><xmax>{}</xmax><ymax>{}</ymax></extent>",
        number(g.x_min_m),
        number(g.y_min_m),
        number(g.x_max_m()),
        number(g.y_max_m())
    );
    let mut s = String::from("<!DOCTYPE qgis PUBLIC 'http://mrcc.com/qgis.dtd' 'SYSTEM'>\n");
    let _ = writeln!(
        s,
        "<qgis projectname=\"{}\" version=\"3.28.0\">",
        xml_escape(title)
    );
    let _ = writeln!(s, "  <title>{}</title>", xml_escape(title));
    let _ = writeln!(s, "  <projectCrs>{srs}</projectCrs>");
    let _ = writeln!(s, "  <layer-tree-group>");
    for l in layers {
        s += &tree_entry(l);
    }
    let _ = writeln!(s, "  </layer-tree-group>");
    let _ = writeln!(s, "  <mapcanvas name=\"theMapCanvas\">");
    let _ = writeln!(s, "    <units>meters</units>");
    let _ = writeln!(s, "    {extent}");
    let _ = writeln!(s, "    <destinationsrs>{srs}</destinationsrs>");
    let _ = writeln!(s, "  </mapcanvas>");
    let _ = writeln!(s, "  <projectlayers>");
    for l in layers {
        s += &map_layer(l, &extent, &srs);
    }
    let _ = writeln!(s, "  </projectlayers>");
    let _ = writeln!(
        s,
        "  <properties><Paths><Absolute type=\"bool\">false</Absolute></Paths></properties>"
    );
    let _ = writeln!(s, "</qgis>");
    s
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
    use super::*;

    #[test]
    fn relative_paths_climb_to_the_common_folder() {
        let out = Path::new("/data/runs/a");
        assert_eq!(
            relative_to(out, Path::new("/data/site/dem.tif")),
            "./../../site/dem.tif"
        );
        assert_eq!(
            relative_to(out, Path::new("/data/runs/a/dem.tif")),
            "./dem.tif"
        );
    }

    #[test]
    fn the_project_parses_and_names_its_crs() {
        let g = GridGeometry {
            ncols: 3,
            nrows: 2,
            x_min_m: 10.0,
            y_min_m: 20.0,
            cell_size_m: 5.0,
        };
        let layers = [MapLayer {
            id: layer_id("E_95"),
            name: "E_95 <kJ>".into(),
            source: "./E_95.tif".into(),
            kind: "raster",
            provider: "gdal",
            body: HILLSHADE.into(),
            renderer: String::new(),
            checked: true,
        }];
        let text = project("a & b", &g, Some(&Crs::from_epsg(2154)), &layers);
        let options = roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        };
        let doc = roxmltree::Document::parse_with_options(&text, options).unwrap();
        let authid = doc
            .descendants()
            .find(|n| n.has_tag_name("authid"))
            .unwrap();
        assert_eq!(authid.text(), Some("EPSG:2154"));
        let name = doc
            .descendants()
            .find(|n| n.has_tag_name("layername"))
            .unwrap();
        assert_eq!(name.text(), Some("E_95 <kJ>"));
        let xmax = doc.descendants().find(|n| n.has_tag_name("xmax")).unwrap();
        assert_eq!(xmax.text(), Some("25"));
    }
}

//! `rockfall.qgs`: a QGIS 3 project that opens a run's output folder as a map — every raster
//! with the style of its `.qml` (the same renderer, embedded), the trajectories and the stems
//! (small dark-green dots), over the DEM drawn with QGIS's hillshade renderer, in the DEM's
//! CRS. It is written in the form QGIS 3.22 (Debian 12's) writes and reads, every CRS with
//! all the fields of [`crate::qgis_crs`].
//!
//! The project's paths are relative (QGIS's `Paths/Absolute` false), so the folder can be
//! moved; the DEM is referred to relative to the folder when it can be, absolutely when it is
//! on another root. A run of a built-in site has no DEM file: the run writes its DEM as
//! `dem.tif` beside the rasters for the hillshade ([`crate::gis::relief_dem`]).

use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

use rockfall_raster::{Crs, GridGeometry};
use rockfall_scenario::Scenario;

use crate::ReportError;
use crate::qgis_crs::{project_properties, spatialrefsys};
use crate::qml::{number, xml_escape};

/// The project file's name in the output folder.
pub const PROJECT_FILE: &str = "rockfall.qgs";

/// The DEM a run writes beside its rasters when the scenario's DEM is no file (a built-in
/// site), for the project's hillshade.
pub const DEM_FILE: &str = "dem.tif";

/// The QGIS version whose project format is written: Debian 12's, the oldest QGIS the
/// projects are tested with (a later QGIS reads it as it is).
const QGIS_VERSION: &str = "3.22.16";

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
/// GeoTIFFs are there, and the GeoJSON files there, over the hillshade of the scenario's DEM
/// ([`crate::gis::relief_dem`], which may write [`DEM_FILE`]); returns the files written,
/// the project last.
pub(crate) fn write_project(
    out: &Path,
    scenario: &Scenario,
    pipes: &[(String, String)],
) -> Result<Vec<PathBuf>, ReportError> {
    let (dem, dem_written) = crate::gis::relief_dem(out, scenario)?;
    let mut written: Vec<PathBuf> = dem_written.then(|| dem.clone()).into_iter().collect();
    let mut layers = Vec::new();
    for (file, geometry, renderer) in [
        ("trajectories.geojson", "Line", String::new()),
        ("stems.geojson", "Point", stems_renderer()),
    ] {
        if out.join(file).is_file() {
            layers.push(MapLayer {
                id: layer_id(file),
                name: file.trim_end_matches(".geojson").into(),
                source: format!("./{file}"),
                kind: "vector",
                provider: "ogr",
                body: geometry.into(),
                renderer,
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
    layers.push(hillshade_layer(out, &dem));
    let dem = &scenario.terrain.dem;
    let text = project(&scenario.name, dem.geometry(), dem.crs(), &layers);
    let path = out.join(PROJECT_FILE);
    rockfall_raster::atomic::write_bytes_atomic(&path, text.as_bytes())?;
    written.push(path);
    Ok(written)
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
        all.push(hillshade_layer(dir, dem));
    }
    let text = project(title, g, crs, &all);
    rockfall_raster::atomic::write_bytes_atomic(path, text.as_bytes())?;
    Ok(path.to_path_buf())
}

/// The name of the hillshade layer in the layer tree.
pub const HILLSHADE_LAYER: &str = "Hillshade (DEM)";

/// The hillshade of the DEM file `dem` for a project in `dir`: the bottom layer.
fn hillshade_layer(dir: &Path, dem: &Path) -> MapLayer {
    MapLayer {
        id: layer_id("hillshade"),
        name: HILLSHADE_LAYER.into(),
        source: relative_to(dir, dem),
        kind: "raster",
        provider: "gdal",
        body: hillshade_pipe(),
        renderer: String::new(),
        checked: true,
    }
}

/// QGIS's hillshade renderer, lit as the report's relief ([`crate::hillshade`]: the sun's
/// azimuth and altitude), with the attribute names QGIS reads (`angle` is the altitude). The
/// DEM is resampled bilinearly by the data provider before it is shaded ("early resampling",
/// QGIS ≥ 3.16): zoomed in past the DEM's cells, nearest-neighbour heights would shade every
/// cell flat and draw its edges as lines.
fn hillshade_pipe() -> String {
    use crate::hillshade::{SUN_ALTITUDE_DEG, SUN_AZIMUTH_DEG};
    format!(
        "      <pipe>\n        <provider>\n          <resampling enabled=\"true\" \
         zoomedInResamplingMethod=\"bilinear\" zoomedOutResamplingMethod=\"bilinear\" \
         maxOversampling=\"2\"/>\n        </provider>\n        <rasterrenderer \
         type=\"hillshade\" band=\"1\" opacity=\"1\" alphaBand=\"-1\" zfactor=\"1\" \
         angle=\"{}\" azimuth=\"{}\" multidirection=\"0\"/>\n        <brightnesscontrast \
         brightness=\"0\" contrast=\"0\" gamma=\"1\"/>\n        \
         <resamplingStage>provider</resamplingStage>\n      </pipe>\n",
        number(SUN_ALTITUDE_DEG),
        number(SUN_AZIMUTH_DEG)
    )
}

/// Size of a stem's dot, mm on the map at any scale: a stand of thousands of stems stays
/// readable (QGIS's default point symbol is 2 mm with an outline).
pub const STEM_SYMBOL_MM: f64 = 1.2;

/// The stems' renderer: one small dark-green dot per stem, [`STEM_SYMBOL_MM`] across, no
/// outline (the `<prop>` form that QGIS 3.22 and later read).
fn stems_renderer() -> String {
    let props = [
        ("name", "circle".to_string()),
        ("color", "0,100,0,255".into()),
        ("outline_style", "no".into()),
        ("outline_width", "0".into()),
        ("size", number(STEM_SYMBOL_MM)),
        ("size_unit", "MM".into()),
        ("scale_method", "diameter".into()),
    ];
    let mut s = String::from(
        "      <renderer-v2 type=\"singleSymbol\" symbollevels=\"0\" enableorderby=\"0\" \
         forceraster=\"0\">\n        <symbols>\n          <symbol type=\"marker\" name=\"0\" \
         alpha=\"1\" clip_to_extent=\"1\" force_rhr=\"0\">\n            <layer \
         class=\"SimpleMarker\" enabled=\"1\" pass=\"0\" locked=\"0\">\n",
    );
    for (k, v) in props {
        let _ = writeln!(s, "              <prop k=\"{k}\" v=\"{v}\"/>");
    }
    s + "            </layer>\n          </symbol>\n        </symbols>\n      </renderer-v2>\n"
}

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

/// A layer's `<maplayer>` element, with the project's `extent` and `srs` (its
/// `<spatialrefsys>` element).
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
    let _ = write!(s, "      <srs>\n{srs}      </srs>\n");
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
        .trim_start_matches('\n')
        .trim_end_matches(' ')
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

/// The project's text: `layers` (first on top) over the extent of `g` in `crs`.
fn project(title: &str, g: &GridGeometry, crs: Option<&Crs>, layers: &[MapLayer]) -> String {
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
        "<qgis projectname=\"{}\" version=\"{QGIS_VERSION}\">",
        xml_escape(title)
    );
    let _ = writeln!(s, "  <title>{}</title>", xml_escape(title));
    let _ = write!(
        s,
        "  <projectCrs>\n{}  </projectCrs>\n",
        spatialrefsys(crs, "    ")
    );
    let _ = writeln!(s, "  <layer-tree-group>");
    for l in layers {
        s += &tree_entry(l);
    }
    let _ = writeln!(s, "  </layer-tree-group>");
    let _ = writeln!(s, "  <mapcanvas name=\"theMapCanvas\">");
    let _ = writeln!(s, "    <units>meters</units>");
    let _ = writeln!(s, "    {extent}");
    let _ = write!(
        s,
        "    <destinationsrs>\n{}    </destinationsrs>\n",
        spatialrefsys(crs, "      ")
    );
    let _ = writeln!(s, "  </mapcanvas>");
    let _ = writeln!(s, "  <projectlayers>");
    let srs = spatialrefsys(crs, "        ");
    for l in layers {
        s += &map_layer(l, &extent, &srs);
    }
    let _ = writeln!(s, "  </projectlayers>");
    let _ = writeln!(
        s,
        "  <properties><Paths><Absolute type=\"bool\">false</Absolute></Paths>{}</properties>",
        project_properties(crs)
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
            body: hillshade_pipe(),
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

    fn parse(text: &str) -> roxmltree::Document<'_> {
        let options = roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        };
        roxmltree::Document::parse_with_options(text, options).unwrap()
    }

    /// The `<maplayer>` named `name`.
    fn map_layer_named<'a>(doc: &'a roxmltree::Document, name: &str) -> roxmltree::Node<'a, 'a> {
        doc.descendants()
            .filter(|n| n.has_tag_name("maplayer"))
            .find(|l| {
                l.children()
                    .any(|c| c.has_tag_name("layername") && c.text() == Some(name))
            })
            .unwrap()
    }

    /// A built-in site has no DEM file: its run writes the DEM as `dem.tif`, drawn at the
    /// bottom of the project by QGIS's hillshade renderer lit as the report's relief.
    #[test]
    fn a_built_in_site_gets_its_dem_written_under_a_hillshade() {
        let scenario = rockfall_sites::build("vaujany-site1").unwrap();
        assert!(scenario.source_of("dem").is_none());
        let dir = tempfile::tempdir().unwrap();
        let files = write_project(dir.path(), &scenario, &[]).unwrap();
        let (dem, qgs) = (dir.path().join(DEM_FILE), dir.path().join(PROJECT_FILE));
        assert_eq!(files, [dem.clone(), qgs.clone()]);
        let grid = rockfall_raster::read_grid(&dem).unwrap();
        assert_eq!(grid.geometry(), scenario.terrain.dem.geometry());
        assert_eq!(
            grid.crs().and_then(|c| c.epsg),
            scenario.terrain.dem.crs().and_then(|c| c.epsg)
        );
        let text = std::fs::read_to_string(&qgs).unwrap();
        let doc = parse(&text);
        let tree: Vec<_> = (doc.descendants())
            .filter(|n| n.has_tag_name("layer-tree-layer"))
            .collect();
        let bottom = tree.last().unwrap();
        assert_eq!(bottom.attribute("name"), Some(HILLSHADE_LAYER));
        assert_eq!(bottom.attribute("source"), Some("./dem.tif"));
        let layer = map_layer_named(&doc, HILLSHADE_LAYER);
        let renderer = (layer.descendants())
            .find(|n| n.has_tag_name("rasterrenderer"))
            .unwrap();
        // the names QGIS reads: `angle` (the altitude) and `zfactor`
        for (key, value) in [
            ("type", "hillshade"),
            ("band", "1"),
            ("azimuth", "315"),
            ("angle", "45"),
            ("zfactor", "1"),
        ] {
            assert_eq!(renderer.attribute(key), Some(value), "{key}");
        }
        let stage = (layer.descendants())
            .find(|n| n.has_tag_name("resamplingStage"))
            .and_then(|n| n.text());
        assert_eq!(stage, Some("provider"));
    }

    /// The stems are small dots of a fixed size on the map, not QGIS's default symbol.
    #[test]
    fn stems_are_drawn_as_small_dots() {
        let scenario = rockfall_sites::build("vaujany-site2").unwrap();
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("stems.geojson"), "{}").unwrap();
        write_project(dir.path(), &scenario, &[]).unwrap();
        let text = std::fs::read_to_string(dir.path().join(PROJECT_FILE)).unwrap();
        let doc = parse(&text);
        let stems = map_layer_named(&doc, "stems");
        assert_eq!(stems.attribute("geometry"), Some("Point"));
        let renderer = (stems.children())
            .find(|n| n.has_tag_name("renderer-v2"))
            .unwrap();
        assert_eq!(renderer.attribute("type"), Some("singleSymbol"));
        let prop = |k: &str| {
            (renderer.descendants())
                .find(|n| n.has_tag_name("prop") && n.attribute("k") == Some(k))
                .and_then(|n| n.attribute("v"))
                .unwrap()
        };
        let size: f64 = prop("size").parse().unwrap();
        assert!((0.5..=1.5).contains(&size), "{size} mm");
        assert_eq!(prop("size_unit"), "MM");
        assert_eq!(prop("color"), "0,100,0,255");
        assert_eq!(prop("outline_style"), "no");
    }

    /// QGIS reads the project CRS only with `ProjectionsEnabled`; the project's and every
    /// layer's CRS carry the fields QGIS 3.22 writes.
    #[test]
    fn the_crs_is_written_as_qgis_3_22_reads_it() {
        let g = GridGeometry {
            ncols: 3,
            nrows: 2,
            x_min_m: 10.0,
            y_min_m: 20.0,
            cell_size_m: 5.0,
        };
        let layers = [MapLayer::from(&ProjectLayer {
            name: "E_95".into(),
            source: "./E_95.tif".into(),
            style: String::new(),
            vector: None,
            checked: true,
        })];
        let text = project("t", &g, Some(&Crs::from_epsg(2056)), &layers);
        let doc = parse(&text);
        let enabled = (doc.descendants())
            .find(|n| n.has_tag_name("ProjectionsEnabled"))
            .unwrap();
        assert_eq!(enabled.parent().unwrap().tag_name().name(), "SpatialRefSys");
        assert_eq!(enabled.text(), Some("1"));
        let systems: Vec<_> = (doc.descendants())
            .filter(|n| n.has_tag_name("spatialrefsys"))
            .collect();
        // the project's, the canvas's and the layer's
        assert_eq!(systems.len(), 3);
        for srs in systems {
            let field = |tag: &str| {
                (srs.children())
                    .find(|n| n.has_tag_name(tag))
                    .and_then(|n| n.text())
                    .unwrap_or_default()
            };
            assert_eq!(field("authid"), "EPSG:2056");
            assert_eq!(field("srsid"), "47");
            assert_eq!(field("srid"), "2056");
            assert_eq!(field("projectionacronym"), "somerc");
            assert_eq!(field("ellipsoidacronym"), "EPSG:7004");
            assert_eq!(field("geographicflag"), "false");
            assert!(field("proj4").starts_with("+proj=somerc "));
            assert!(field("wkt").starts_with("PROJCS[\"CH1903+ / LV95\""));
        }
        assert!(text.contains(&format!("version=\"{QGIS_VERSION}\"")));
    }

    /// A layer added to a run's project takes the project's CRS, every field of it.
    #[test]
    fn added_layers_take_the_projects_crs() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(PROJECT_FILE);
        let g = GridGeometry {
            ncols: 2,
            nrows: 2,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        write_layers_project(&path, "t", &g, Some(&Crs::from_epsg(2154)), &[], None).unwrap();
        let zones = ProjectLayer {
            name: "Hazard zones".into(),
            source: "./z.gpkg|layername=z".into(),
            style: String::new(),
            vector: Some("Polygon"),
            checked: true,
        };
        add_layers(&path, std::slice::from_ref(&zones)).unwrap();
        add_layers(&path, &[zones]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let doc = parse(&text);
        let layer = map_layer_named(&doc, "Hazard zones");
        let srsid = (layer.descendants())
            .find(|n| n.has_tag_name("srsid"))
            .and_then(|n| n.text());
        assert_eq!(srsid, Some("145"));
        assert_eq!(text.matches("<maplayer").count(), 1);
    }
}

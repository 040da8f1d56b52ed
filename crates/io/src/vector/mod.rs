//! GIS vector layers as inputs: polygons, lines and points from GeoJSON (`.geojson`,
//! `.json`), ESRI Shapefiles (`.shp` with `.dbf` and `.prj`) and GeoPackages (`.gpkg`,
//! cargo feature `gpkg`, on by default), read into one small model ([`Layer`]) and burnt
//! onto the DEM's grid by [`burn`]. The other way, [`polygonize()`] turns a raster of classes
//! into dissolved polygons and [`write_gpkg_polygons`] writes them as a GeoPackage layer.
//!
//! Feature ids are the ones GDAL/OGR gives (its FID): a GeoPackage's primary key, a
//! Shapefile's record number from 0, a GeoJSON feature's numeric `id` or else its position
//! from 0. Errors name the file, the layer and the feature.

pub mod burn;
mod envelope;
mod geojson;
#[cfg(feature = "gpkg")]
mod gpkg;
#[cfg(feature = "gpkg")]
mod gpkg_write;
pub mod inputs;
pub mod polygonize;
mod shp;
pub mod wkb;

pub use self::geojson::parse_geojson;
pub use envelope::Envelope;
pub use polygonize::polygonize;
pub use shp::parse_shapefile;

use rockfall_raster::Crs;
use std::path::{Path, PathBuf};

/// A point (x, y) in the layer's CRS, m for the projected CRSs a DEM uses.
pub type Xy = [f64; 2];

/// A polygon as its rings, each closed (its first point repeated last): the exterior first,
/// then its holes.
pub type Polygon = Vec<Vec<Xy>>;

/// A feature's geometry, its multi-form included; Z and M values are dropped.
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    /// No geometry (null or empty).
    Empty,
    /// Points.
    Points(Vec<Xy>),
    /// Line strings.
    Lines(Vec<Vec<Xy>>),
    /// Polygons, each as its rings (the exterior first, then holes).
    Polygons(Vec<Vec<Vec<Xy>>>),
}

impl Geometry {
    /// `points`, `lines`, `polygons` or `no geometry`.
    pub fn kind(&self) -> &'static str {
        match self {
            Geometry::Empty => "no geometry",
            Geometry::Points(_) => "points",
            Geometry::Lines(_) => "lines",
            Geometry::Polygons(_) => "polygons",
        }
    }
}

/// An attribute value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A number (integers included).
    Num(f64),
    /// Text.
    Text(String),
    /// Null or absent.
    Null,
}

/// One feature.
#[derive(Debug, Clone, PartialEq)]
pub struct Feature {
    /// OGR's FID (see the module documentation).
    pub id: i64,
    /// Its geometry.
    pub geometry: Geometry,
    /// Attributes by name: in the layer's field order for a GeoPackage or Shapefile, by name
    /// for a GeoJSON feature.
    pub attributes: Vec<(String, Value)>,
}

impl Feature {
    /// The attribute called `name` (ASCII case-insensitive, as OGR matches field names).
    pub fn attribute(&self, name: &str) -> Option<&Value> {
        (self.attributes.iter())
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, v)| v)
    }
}

/// A layer of features.
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    /// The file.
    pub path: PathBuf,
    /// The layer's name (a GeoPackage table, else the file stem).
    pub name: String,
    /// Its CRS; `None` when the file names none (a Shapefile without `.prj`).
    pub crs: Option<Crs>,
    /// Its features, in the file's order.
    pub features: Vec<Feature>,
    /// `Some(e)` when only the features whose bounding box meets `e` were read (a tile's
    /// read of a polygon layer, [`read_layer_in`]).
    pub within: Option<Envelope>,
}

/// A vector input that cannot be used: the file, the layer and the feature where they apply.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}{}{}: {message}", path.display(), layer.as_ref().map(|l| format!(", layer `{l}`")).unwrap_or_default(), feature.map(|f| format!(", feature {f}")).unwrap_or_default())]
pub struct VectorError {
    /// The file.
    pub path: PathBuf,
    /// The layer, where known.
    pub layer: Option<String>,
    /// The feature id, where one is at fault.
    pub feature: Option<i64>,
    /// What is wrong.
    pub message: String,
}

impl VectorError {
    /// An error of the file as a whole.
    pub fn file(path: &Path, message: impl Into<String>) -> Self {
        VectorError {
            path: path.to_path_buf(),
            layer: None,
            feature: None,
            message: message.into(),
        }
    }

    /// An error of one feature of a layer.
    pub fn feature(layer: &Layer, id: i64, message: impl Into<String>) -> Self {
        VectorError {
            path: layer.path.clone(),
            layer: Some(layer.name.clone()),
            feature: Some(id),
            message: message.into(),
        }
    }

    /// An error of a layer as a whole.
    pub fn layer(layer: &Layer, message: impl Into<String>) -> Self {
        VectorError {
            path: layer.path.clone(),
            layer: Some(layer.name.clone()),
            feature: None,
            message: message.into(),
        }
    }
}

/// True when `path` names a vector file by its extension.
pub fn is_vector_path(path: &Path) -> bool {
    matches!(
        extension(path).as_deref(),
        Some("geojson" | "json" | "shp" | "gpkg")
    )
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

/// Reads the layer `layer` of a vector file (the only layer when `None`; a GeoPackage of
/// several layers then needs the name).
pub fn read_layer(path: &Path, layer: Option<&str>) -> Result<Layer, VectorError> {
    read_layer_in(path, layer, None)
}

/// [`read_layer`] keeping, with `within`, only the features whose bounding box meets it, in
/// the file's order (see `envelope.rs`). A GeoPackage with the R-tree index of its geometry
/// column (`rtree_<table>_<column>`, which GDAL writes) is asked for those features alone;
/// other files are read whole and the features that miss it dropped once decoded.
pub fn read_layer_in(
    path: &Path,
    layer: Option<&str>,
    within: Option<Envelope>,
) -> Result<Layer, VectorError> {
    let mut l = read_whole_or_indexed(path, layer, within)?;
    if let Some(e) = &within {
        envelope::keep_meeting(&mut l.features, e);
        l.within = within;
    }
    Ok(l)
}

fn read_whole_or_indexed(
    path: &Path,
    layer: Option<&str>,
    within: Option<Envelope>,
) -> Result<Layer, VectorError> {
    if !path.is_file() {
        return Err(VectorError::file(path, "no such vector file"));
    }
    let read = |p: &Path| std::fs::read(p).map_err(|e| VectorError::file(p, e.to_string()));
    let layer_of_file = |l: Layer| match layer {
        Some(name) if name != l.name => Err(VectorError::file(
            path,
            format!("no layer `{name}`: the file's one layer is `{}`", l.name),
        )),
        _ => Ok(l),
    };
    #[cfg(not(feature = "gpkg"))]
    let _ = within;
    match extension(path).as_deref() {
        Some("geojson" | "json") => layer_of_file(parse_geojson(&read(path)?, path)?),
        Some("shp") => {
            let dbf = path.with_extension("dbf");
            let prj = path.with_extension("prj");
            let prj = match prj.is_file() {
                true => Some(String::from_utf8_lossy(&read(&prj)?).into_owned()),
                false => None,
            };
            let dbf = match dbf.is_file() {
                true => read(&dbf)?,
                false => return Err(VectorError::file(path, "no .dbf beside the .shp")),
            };
            layer_of_file(parse_shapefile(&read(path)?, &dbf, prj.as_deref(), path)?)
        }
        #[cfg(feature = "gpkg")]
        Some("gpkg") => gpkg::read(path, layer, within),
        #[cfg(not(feature = "gpkg"))]
        Some("gpkg") => Err(VectorError::file(
            path,
            "this build has no GeoPackage support (cargo feature `gpkg`): export the layer as GeoJSON or Shapefile, or rebuild with default features",
        )),
        _ => Err(VectorError::file(
            path,
            "unknown vector format: use .geojson, .json, .shp or .gpkg",
        )),
    }
}

/// The SQL type of an attribute column of a layer we write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldType {
    /// Whole numbers (SQLite `INTEGER`, OGR's Integer64): [`Value::Num`] without a fraction.
    Integer,
    /// Numbers (`REAL`): a finite [`Value::Num`].
    Real,
    /// Text (`TEXT`): [`Value::Text`].
    Text,
}

/// Writes polygons as the one layer `layer` of a new GeoPackage at `path` (OGC 12-128r18,
/// GeoPackage 1.3; cargo feature `gpkg`), replacing any file there, atomically: the file is
/// built beside the target and renamed over it only when complete.
///
/// Each feature is a MultiPolygon (its polygons, each its rings, the exterior first: written
/// as given, so counter-clockwise exteriors and clockwise holes as [`polygonize()`] makes them
/// and OGC 06-103r4 §6.1.11.1 wants) and its values of `fields` in order, [`Value::Null`]
/// allowed for any. Features get the ids (`fid`) 1, 2, … in order. The layer's CRS is
/// recorded by its EPSG code when it has one (with the WKT we ship for it), else by its WKT;
/// without a CRS the layer is in GeoPackage's undefined Cartesian system (−1). See
/// `gpkg_write.rs` for the tables written. GDAL (`ogrinfo`), QGIS and [`read_layer`] read the
/// file.
///
/// Errors name the file, the layer and, where one is at fault, the feature's id: a layer or
/// field name that is empty, reserved (`gpkg_`, `sqlite_`, `rtree_`, a field `fid` or
/// `geom`) or repeated; a value of the wrong type or count; a polygon without rings, a ring
/// of fewer than 4 points, not closed or with a coordinate that is not finite; a file that
/// cannot be written. Without the `gpkg` feature every call is an error saying so.
pub fn write_gpkg_polygons(
    path: &Path,
    layer: &str,
    crs: Option<&Crs>,
    fields: &[(&str, FieldType)],
    features: &[(Vec<Polygon>, Vec<Value>)],
) -> Result<(), VectorError> {
    #[cfg(feature = "gpkg")]
    return gpkg_write::write(path, layer, crs, fields, features);
    #[cfg(not(feature = "gpkg"))]
    {
        let _ = (crs, fields, features);
        Err(VectorError {
            path: path.to_path_buf(),
            layer: Some(layer.to_string()),
            feature: None,
            message: "this build has no GeoPackage support (cargo feature `gpkg`): rebuild with default features".into(),
        })
    }
}

/// True when two CRSs are the same as far as we can tell: equal EPSG codes, else equal WKT
/// once spaces are ignored.
pub fn same_crs(a: &Crs, b: &Crs) -> bool {
    match (a.epsg, b.epsg) {
        (Some(x), Some(y)) => x == y,
        _ => match (&a.wkt, &b.wkt) {
            (Some(x), Some(y)) => {
                let squash = |s: &str| s.split_whitespace().collect::<String>();
                squash(x) == squash(y)
            }
            _ => false,
        },
    }
}

/// The EPSG code in a CRS name such as `urn:ogc:def:crs:EPSG::2154` or `EPSG:2154`; CRS84
/// (`urn:ogc:def:crs:OGC:1.3:CRS84`, GeoJSON's default) is EPSG:4326 with lon/lat order.
pub(crate) fn epsg_of_name(name: &str) -> Option<u32> {
    let upper = name.to_ascii_uppercase();
    if upper.ends_with("CRS84") {
        return Some(4326);
    }
    if !upper.contains("EPSG") {
        return None;
    }
    upper.rsplit(':').next()?.trim().parse().ok()
}

#[cfg(all(test, not(feature = "gpkg")))]
mod tests {
    use super::*;

    #[test]
    fn without_the_feature_writing_a_geopackage_is_refused() {
        let path = Path::new("never_written.gpkg");
        let e = write_gpkg_polygons(path, "zones", None, &[], &[]);
        assert!(e.is_err_and(|e| e.message.contains("cargo feature `gpkg`")));
        assert!(!path.exists());
    }
}

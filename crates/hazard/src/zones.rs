//! `hazard_zones.gpkg`: the zones as polygons, for QGIS and every GIS that reads
//! GeoPackages, with their QGIS symbols.
//!
//! One layer, `hazard_zones`, dissolved per hazard level and matrix field: each feature is
//! the (multi)polygon of the cells of one level and one field, with `level` (0–4), `zone`
//! (its colour name), `field` (the matrix field; 0 for residual hazard) and its area. The
//! polygons follow cell edges exactly ([`rockfall_io::vector::polygonize`]), so the areas
//! are those of `Hazard_level.tif`.

use std::path::{Path, PathBuf};

use rockfall_io::vector::{FieldType, Value, polygonize, write_gpkg_polygons};

use crate::build::HazardMap;
use crate::error::HazardError;
use crate::level::Level;
use crate::matrix::Matrix;

/// The GeoPackage's file name.
pub const ZONES_FILE: &str = "hazard_zones.gpkg";
/// Its layer.
pub const ZONES_LAYER: &str = "hazard_zones";

/// A (level, field) pair as one byte for [`polygonize`]: level·16 + field (fields ≤ 15).
fn code(level: u8, field: u8) -> u8 {
    level * 16 + field.min(15)
}

/// Writes `hazard_zones.gpkg` into `out`; returns its path.
pub fn write_zones(out: &Path, m: &Matrix, map: &HazardMap) -> Result<PathBuf, HazardError> {
    if m.levels.keys().any(|&f| f > 15) {
        return Err(HazardError::Output(format!(
            "{ZONES_FILE}: fields above 15 cannot be written as zones"
        )));
    }
    let codes: Vec<u8> = (map.classes.iter())
        .map(|c| {
            if c.level == 0 {
                0
            } else {
                code(c.level, c.field)
            }
        })
        .collect();
    let cell_area = map.geometry.cell_area_m2();
    let mut features = Vec::new();
    for (value, polygons) in polygonize(&codes, &map.geometry).into_iter().rev() {
        let (level, field) = (value / 16, value % 16);
        let cells = codes.iter().filter(|&&c| c == value).count() as f64;
        let zone = Level::from_code(level).map_or("", Level::colour_name);
        features.push((
            polygons,
            vec![
                Value::Num(f64::from(level)),
                Value::Text(zone.into()),
                Value::Num(f64::from(field)),
                Value::Num(cells * cell_area),
                Value::Num(cells * cell_area / 1e4),
            ],
        ));
    }
    let path = out.join(ZONES_FILE);
    write_gpkg_polygons(
        &path,
        ZONES_LAYER,
        map.crs.as_ref(),
        &[
            ("level", FieldType::Integer),
            ("zone", FieldType::Text),
            ("field", FieldType::Integer),
            ("area_m2", FieldType::Real),
            ("area_ha", FieldType::Real),
        ],
        &features,
    )
    .map_err(|e| HazardError::Output(e.to_string()))?;
    Ok(path)
}

/// The QGIS renderer of the zone layer: a fill per level in the matrix's colours.
pub fn renderer(m: &Matrix) -> String {
    let mut cats = String::new();
    let mut symbols = String::new();
    for (k, l) in Level::ALL[1..].iter().enumerate() {
        let (r, g, b) = m.colours.rgb(*l);
        cats += &format!(
            "        <category render=\"true\" symbol=\"{k}\" value=\"{}\" label=\"{} hazard ({})\"/>\n",
            *l as u8,
            l.name(),
            l.colour_name()
        );
        symbols += &format!(
            "        <symbol type=\"fill\" name=\"{k}\" alpha=\"0.75\" clip_to_extent=\"1\" force_rhr=\"0\">\n\
             \x20         <layer class=\"SimpleFill\" enabled=\"1\" pass=\"0\" locked=\"0\">\n\
             \x20           <prop k=\"color\" v=\"{r},{g},{b},255\"/>\n\
             \x20           <prop k=\"outline_color\" v=\"60,60,60,255\"/>\n\
             \x20           <prop k=\"outline_width\" v=\"0.2\"/>\n\
             \x20           <prop k=\"style\" v=\"solid\"/>\n\
             \x20         </layer>\n        </symbol>\n"
        );
    }
    format!(
        "      <renderer-v2 type=\"categorizedSymbol\" attr=\"level\" symbollevels=\"0\" \
         enableorderby=\"0\" forceraster=\"0\">\n        <categories>\n{cats}        </categories>\n\
         \x20       <symbols>\n{symbols}        </symbols>\n      </renderer-v2>\n"
    )
}

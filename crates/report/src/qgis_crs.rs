//! A CRS as a QGIS project names it: the `<spatialrefsys>` element with every field QGIS 3.22
//! writes (and older readers need), and the project property without which QGIS reads no
//! project CRS at all.
//!
//! QGIS reads a `<spatialrefsys>` by its `authid` only when its `srsid` (the row of QGIS's own
//! `srs.db`) is between 1 and 99 999; otherwise by its `wkt`, then its `proj4`. So the
//! element carries, as QGIS 3.22 writes it: the WKT, the PROJ string, the srsid and srid, the
//! authority id, the name, the projection and ellipsoid acronyms and the geographic flag.
//! Every field is known for the EPSG codes of [`rockfall_raster::crs::KNOWN`]; for another
//! code or a CRS known by its WKT alone, the PROJ string is left empty and the srsid is 0,
//! and QGIS goes by the WKT (and, for the project, the `ProjectCrs` property).

use rockfall_raster::Crs;

use crate::qml::xml_escape;

/// QGIS's `srsid` of each EPSG code of [`rockfall_raster::crs::KNOWN`]
/// (`QgsCoordinateReferenceSystem("EPSG:n").srsid()` in QGIS 3.22.16).
const QGIS_SRSID: [(u32, u32); 11] = [
    (2154, 145),
    (2056, 47),
    (21781, 1919),
    (4326, 3452),
    (3857, 3857),
    (25832, 2105),
    (25833, 2106),
    (32632, 3116),
    (32633, 3117),
    (31287, 2628),
    (3035, 1000),
];

/// The `<spatialrefsys>` element of `crs` (an empty one for an unknown CRS), its lines
/// indented by `indent`.
pub(crate) fn spatialrefsys(crs: Option<&Crs>, indent: &str) -> String {
    let Some(crs) = crs else {
        return format!("{indent}<spatialrefsys/>\n");
    };
    let wkt = crs.wkt_for_prj().unwrap_or_default();
    let proj4 = crs.proj4().unwrap_or_default();
    let srsid = (crs.epsg)
        .and_then(|c| QGIS_SRSID.iter().find(|(code, _)| *code == c))
        .map_or(0, |(_, id)| *id);
    let authid = crs.epsg.map(|c| format!("EPSG:{c}")).unwrap_or_default();
    let description = match crs.epsg.and_then(rockfall_raster::crs::known) {
        Some(k) => k.name.to_string(),
        None => crs.describe(),
    };
    let fields = [
        ("wkt", xml_escape(&wkt)),
        ("proj4", xml_escape(proj4)),
        ("srsid", srsid.to_string()),
        ("srid", crs.epsg.unwrap_or(0).to_string()),
        ("authid", authid),
        ("description", xml_escape(&description)),
        ("projectionacronym", projection_acronym(proj4).into()),
        (
            "ellipsoidacronym",
            ellipsoid_acronym(&wkt).unwrap_or_default(),
        ),
        ("geographicflag", crs.is_geographic().to_string()),
    ];
    let mut s = format!("{indent}<spatialrefsys>\n");
    for (tag, text) in fields {
        s += &format!("{indent}  <{tag}>{text}</{tag}>\n");
    }
    s + &format!("{indent}</spatialrefsys>\n")
}

/// The project properties naming its CRS: `ProjectionsEnabled` (QGIS reads `<projectCrs>`
/// only when it is 1, 3.22 as today's) and `ProjectCrs`, the authority id QGIS falls back on
/// when it cannot read `<projectCrs>`.
pub(crate) fn project_properties(crs: Option<&Crs>) -> String {
    let Some(crs) = crs else {
        return String::new();
    };
    let authid = match crs.epsg {
        Some(c) => format!("<ProjectCrs type=\"QString\">EPSG:{c}</ProjectCrs>"),
        None => String::new(),
    };
    format!(
        "<SpatialRefSys><ProjectionsEnabled type=\"int\">1</ProjectionsEnabled>{authid}</SpatialRefSys>"
    )
}

/// The projection's PROJ name (`lcc`, `utm`, `longlat`), as QGIS shows it; empty without a
/// PROJ string.
fn projection_acronym(proj4: &str) -> &str {
    (proj4.split_whitespace())
        .find_map(|p| p.strip_prefix("+proj="))
        .unwrap_or_default()
}

/// The ellipsoid's authority id (`EPSG:7019`), as QGIS 3.22 writes it: the `AUTHORITY` (WKT 1)
/// or `ID` (WKT 2) of the WKT's `SPHEROID` or `ELLIPSOID` node.
fn ellipsoid_acronym(wkt: &str) -> Option<String> {
    let upper = wkt.to_ascii_uppercase();
    let start = ["SPHEROID[", "ELLIPSOID["]
        .iter()
        .find_map(|k| upper.find(k).map(|i| i + k.len()))?;
    // the node ends where its bracket closes
    let mut depth = 1;
    let end = (upper[start..].char_indices())
        .find(|&(_, c)| {
            match c {
                '[' | '(' => depth += 1,
                ']' | ')' => depth -= 1,
                _ => {}
            }
            depth == 0
        })
        .map(|(i, _)| start + i)?;
    let node = &wkt[start..end];
    let upper = &upper[start..end];
    let id = ["AUTHORITY[", "ID["]
        .iter()
        .find_map(|k| upper.find(k).map(|i| i + k.len()))?;
    let parts: Vec<&str> = node[id..]
        .split([',', ']'])
        .take(2)
        .map(|p| p.trim().trim_matches('"'))
        .collect();
    match parts.as_slice() {
        [auth, code] if !auth.is_empty() && !code.is_empty() => Some(format!("{auth}:{code}")),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
    use super::*;

    fn field(xml: &str, tag: &str) -> String {
        let doc = roxmltree::Document::parse(xml).unwrap();
        let node = doc.descendants().find(|n| n.has_tag_name(tag)).unwrap();
        node.text().unwrap_or_default().to_string()
    }

    /// Lambert-93 as QGIS 3.22 writes it (a project saved by QGIS 3.22.16), WKT aside.
    #[test]
    fn a_known_code_has_every_field_qgis_writes() {
        let xml = spatialrefsys(Some(&Crs::from_epsg(2154)), "");
        for (tag, text) in [
            (
                "proj4",
                "+proj=lcc +lat_0=46.5 +lon_0=3 +lat_1=49 +lat_2=44 +x_0=700000 \
                 +y_0=6600000 +ellps=GRS80 +towgs84=0,0,0,0,0,0,0 +units=m +no_defs",
            ),
            ("srsid", "145"),
            ("srid", "2154"),
            ("authid", "EPSG:2154"),
            ("description", "RGF93 v1 / Lambert-93"),
            ("projectionacronym", "lcc"),
            ("ellipsoidacronym", "EPSG:7019"),
            ("geographicflag", "false"),
        ] {
            assert_eq!(field(&xml, tag), text, "{tag}");
        }
        assert!(field(&xml, "wkt").starts_with("PROJCS[\"RGF93 v1 / Lambert-93\""));
        let wgs84 = spatialrefsys(Some(&Crs::from_epsg(4326)), "");
        assert_eq!(field(&wgs84, "geographicflag"), "true");
        assert_eq!(field(&wgs84, "projectionacronym"), "longlat");
        assert_eq!(field(&wgs84, "ellipsoidacronym"), "EPSG:7030");
    }

    #[test]
    fn every_known_code_has_a_qgis_srsid() {
        for k in rockfall_raster::crs::KNOWN {
            let xml = spatialrefsys(Some(&Crs::from_epsg(k.epsg)), "");
            assert_ne!(field(&xml, "srsid"), "0", "{}", k.name);
            assert!(!field(&xml, "proj4").is_empty(), "{}", k.name);
        }
    }

    #[test]
    fn an_unknown_crs_has_an_empty_proj_string_and_no_srsid() {
        let wkt = r#"PROJCS["Local",GEOGCS["x",DATUM["d",SPHEROID["Bessel 1841",6377397.155,299.1528128,AUTHORITY["EPSG","7004"]]]],UNIT["metre",1]]"#;
        let xml = spatialrefsys(Some(&Crs::from_wkt(wkt)), "  ");
        assert_eq!(field(&xml, "proj4"), "");
        assert_eq!(field(&xml, "srsid"), "0");
        assert_eq!(field(&xml, "authid"), "");
        assert_eq!(field(&xml, "description"), "Local");
        assert_eq!(field(&xml, "ellipsoidacronym"), "EPSG:7004");
        let code = spatialrefsys(Some(&Crs::from_epsg(31255)), "");
        assert_eq!(field(&code, "authid"), "EPSG:31255");
        assert_eq!(field(&code, "srsid"), "0");
        assert_eq!(spatialrefsys(None, ""), "<spatialrefsys/>\n");
    }

    #[test]
    fn the_ellipsoid_is_read_from_wkt_1_and_wkt_2() {
        let wkt2 = r#"GEOGCRS["x",DATUM["d",ELLIPSOID["GRS 1980",6378137,298.257222101,LENGTHUNIT["metre",1],ID["EPSG",7019]]],ID["EPSG",4171]]"#;
        assert_eq!(ellipsoid_acronym(wkt2).as_deref(), Some("EPSG:7019"));
        assert_eq!(ellipsoid_acronym(r#"GEOGCS["x",SPHEROID["a",1,2]]"#), None);
    }

    #[test]
    fn the_project_enables_its_crs() {
        let p = project_properties(Some(&Crs::from_epsg(2056)));
        assert!(p.contains("<ProjectionsEnabled type=\"int\">1</ProjectionsEnabled>"));
        assert!(p.contains("<ProjectCrs type=\"QString\">EPSG:2056</ProjectCrs>"));
        assert_eq!(project_properties(None), "");
    }
}

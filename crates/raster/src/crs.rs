//! Coordinate reference systems: an EPSG code and/or a WKT text.
//!
//! The CRS travels with a grid from its source (a `.prj` sidecar of an ASCII grid, the GeoKeys
//! of a GeoTIFF, an `epsg` key in a scenario) to every raster written from it. For the EPSG
//! codes in [`KNOWN`] we ship the WKT so that a `.prj` can be written from the code alone and
//! a GeoTIFF's EPSG code can be recovered from a `.prj`.

/// A coordinate reference system.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Crs {
    /// EPSG code, when known.
    pub epsg: Option<u32>,
    /// WKT definition (as found in a `.prj`, or shipped for a known EPSG code).
    pub wkt: Option<String>,
}

/// A CRS whose WKT we ship.
#[derive(Debug, Clone, Copy)]
pub struct KnownCrs {
    /// EPSG code.
    pub epsg: u32,
    /// Name.
    pub name: &'static str,
    /// True for a geographic (degrees) CRS, false for a projected one (metres).
    pub geographic: bool,
    /// The PROJ string (`+proj=… +no_defs`), as GDAL exports it and QGIS writes it into a
    /// project for readers without WKT 2 support.
    pub proj4: &'static str,
    /// OGC WKT 1 with EPSG authority codes, as GDAL reads it from a `.prj`.
    pub wkt: &'static str,
}

/// The EPSG codes we ship WKT for.
pub const KNOWN: &[KnownCrs] = &crate::crs_table::TABLE;

impl Crs {
    /// A CRS from an EPSG code; the WKT is filled in when the code is in [`KNOWN`].
    pub fn from_epsg(epsg: u32) -> Self {
        Crs {
            epsg: Some(epsg),
            wkt: known(epsg).map(|k| k.wkt.to_string()),
        }
    }

    /// A CRS from a WKT text (a `.prj`); the EPSG code is taken from the outermost
    /// `AUTHORITY["EPSG","…"]` (WKT 1) or `ID["EPSG",…]` (WKT 2) when present.
    pub fn from_wkt(wkt: &str) -> Self {
        let wkt = wkt.trim();
        Crs {
            epsg: epsg_of_wkt(wkt),
            wkt: Some(wkt.to_string()),
        }
    }

    /// The WKT to write into a `.prj`: the one we have, else the shipped one for the EPSG code.
    pub fn wkt_for_prj(&self) -> Option<String> {
        self.wkt
            .clone()
            .or_else(|| self.epsg.and_then(known).map(|k| k.wkt.to_string()))
    }

    /// The PROJ string of the EPSG code when it is in [`KNOWN`]; `None` for another code or a
    /// CRS known by its WKT alone (we do not convert WKT to PROJ strings).
    pub fn proj4(&self) -> Option<&'static str> {
        self.epsg.and_then(known).map(|k| k.proj4)
    }

    /// True when the CRS is geographic (degrees), as far as we can tell.
    pub fn is_geographic(&self) -> bool {
        if let Some(k) = self.epsg.and_then(known) {
            return k.geographic;
        }
        self.wkt
            .as_deref()
            .map(|w| {
                let w = w.trim_start().to_ascii_uppercase();
                w.starts_with("GEOGCS") || w.starts_with("GEOGCRS")
            })
            .unwrap_or(false)
    }

    /// A short human description: `EPSG:2154 (RGF93 v1 / Lambert-93)`, or the WKT's name.
    pub fn describe(&self) -> String {
        match (self.epsg, self.wkt.as_deref()) {
            (Some(code), _) => match known(code) {
                Some(k) => format!("EPSG:{code} ({})", k.name),
                None => format!("EPSG:{code}"),
            },
            (None, Some(w)) => wkt_name(w).unwrap_or_else(|| "custom WKT".into()),
            (None, None) => "unknown".into(),
        }
    }
}

/// The shipped definition of an EPSG code.
pub fn known(epsg: u32) -> Option<&'static KnownCrs> {
    KNOWN.iter().find(|k| k.epsg == epsg)
}

/// The EPSG code of the outermost definition of a WKT: the last top-level `AUTHORITY` (WKT 1)
/// or `ID` (WKT 2) before the final bracket; else a match of the CRS name against [`KNOWN`].
fn epsg_of_wkt(wkt: &str) -> Option<u32> {
    let bytes = wkt.as_bytes();
    let mut depth = 0i32;
    let mut last_top: Option<usize> = None;
    for (i, &b) in bytes.iter().enumerate() {
        match b {
            b'[' | b'(' => {
                depth += 1;
                if depth == 2 {
                    // start of a direct child of the root node: remember where its keyword begins
                    let start = wkt[..i].rfind([',', '[', '(']).map(|p| p + 1).unwrap_or(0);
                    let kw = wkt[start..i].trim().to_ascii_uppercase();
                    if kw == "AUTHORITY" || kw == "ID" {
                        last_top = Some(i);
                    }
                }
            }
            b']' | b')' => depth -= 1,
            _ => {}
        }
    }
    if let Some(i) = last_top {
        let rest = &wkt[i + 1..];
        let end = rest.find([']', ')'])?;
        let parts: Vec<&str> = rest[..end]
            .split(',')
            .map(|s| s.trim().trim_matches('"'))
            .collect();
        if parts.len() >= 2 && parts[0].eq_ignore_ascii_case("EPSG") {
            return parts[1].parse().ok();
        }
    }
    let name = wkt_name(wkt)?;
    KNOWN
        .iter()
        .find(|k| k.name.eq_ignore_ascii_case(&name) || wkt_name(k.wkt).as_deref() == Some(&name))
        .map(|k| k.epsg)
        .or_else(|| {
            (ESRI_NAMES.iter())
                .find(|(n, _)| n.eq_ignore_ascii_case(&name))
                .map(|(_, c)| *c)
        })
}

/// The names ESRI-flavoured WKT (the `.prj` of a Shapefile, which carries no EPSG code) gives
/// the CRSs of [`KNOWN`], as `gdalsrsinfo -o wkt_esri EPSG:code` prints them.
const ESRI_NAMES: [(&str, u32); 11] = [
    ("RGF_1993_Lambert_93", 2154),
    ("CH1903+_LV95", 2056),
    ("CH1903_LV03", 21781),
    ("GCS_WGS_1984", 4326),
    ("WGS_1984_Web_Mercator_Auxiliary_Sphere", 3857),
    ("ETRS_1989_UTM_Zone_32N", 25832),
    ("ETRS_1989_UTM_Zone_33N", 25833),
    ("WGS_1984_UTM_Zone_32N", 32632),
    ("WGS_1984_UTM_Zone_33N", 32633),
    ("MGI_Austria_Lambert", 31287),
    ("ETRS_1989_LAEA", 3035),
];

/// The quoted name of the root node of a WKT.
fn wkt_name(wkt: &str) -> Option<String> {
    let start = wkt.find('"')? + 1;
    let len = wkt[start..].find('"')?;
    Some(wkt[start..start + len].to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn epsg_from_outer_authority_not_inner() {
        let wkt = r#"PROJCS["RGF93 v1 / Lambert-93",GEOGCS["RGF93 v1",DATUM["Reseau_Geodesique_Francais_1993_v1",SPHEROID["GRS 1980",6378137,298.257222101,AUTHORITY["EPSG","7019"]],AUTHORITY["EPSG","6171"]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433],AUTHORITY["EPSG","4171"]],PROJECTION["Lambert_Conformal_Conic_2SP"],UNIT["metre",1],AUTHORITY["EPSG","2154"]]"#;
        let crs = Crs::from_wkt(wkt);
        assert_eq!(crs.epsg, Some(2154));
        assert!(!crs.is_geographic());
    }

    #[test]
    fn esri_prj_without_authority_matches_by_name_or_stays_unknown() {
        let crs = Crs::from_wkt(r#"PROJCS["My_Local_Grid",GEOGCS["x"]]"#);
        assert_eq!(crs.epsg, None);
        assert_eq!(crs.describe(), "My_Local_Grid");
    }

    #[test]
    fn esri_prj_names_give_the_epsg_code() {
        let prj = r#"PROJCS["RGF_1993_Lambert_93",GEOGCS["GCS_RGF_1993",DATUM["D_RGF_1993",SPHEROID["GRS_1980",6378137.0,298.257222101]]],PROJECTION["Lambert_Conformal_Conic"],UNIT["Meter",1.0]]"#;
        assert_eq!(Crs::from_wkt(prj).epsg, Some(2154));
        assert_eq!(
            Crs::from_wkt(r#"PROJCS["ETRS_1989_UTM_Zone_32N"]"#).epsg,
            Some(25832)
        );
    }

    #[test]
    fn every_known_wkt_names_its_own_code() {
        for k in KNOWN {
            assert_eq!(Crs::from_wkt(k.wkt).epsg, Some(k.epsg), "{}", k.name);
            assert_eq!(Crs::from_epsg(k.epsg).is_geographic(), k.geographic);
        }
    }

    #[test]
    fn every_known_code_has_a_proj_string_of_its_kind() {
        for k in KNOWN {
            let crs = Crs::from_epsg(k.epsg);
            let proj = crs.proj4().unwrap_or_default();
            assert!(
                proj.starts_with("+proj=") && proj.ends_with("+no_defs"),
                "{proj}"
            );
            assert_eq!(
                proj.starts_with("+proj=longlat"),
                k.geographic,
                "{}",
                k.name
            );
        }
        assert_eq!(Crs::from_epsg(9999).proj4(), None);
        assert_eq!(Crs::from_wkt(r#"PROJCS["My_Local_Grid"]"#).proj4(), None);
    }
}

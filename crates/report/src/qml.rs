//! QGIS layer styles (`.qml`) beside the GeoTIFFs, with the colour ramp of the report's maps.
//!
//! QGIS loads `<name>.qml` as the default style of `<name>.tif` when both sit in one folder.
//! The style is a single-band pseudocolour renderer whose interpolated colour-ramp items are
//! sampled from the same [`rockfall_plot::Ramp`] and scale as the PNG map: evenly spaced
//! values on a linear or symmetric scale, log-spaced values on a log scale (QGIS interpolates
//! linearly between items, so a log scale gets more of them). Where zero means "nothing
//! happened" it is made transparent; nodata is transparent in QGIS anyway.

use std::fmt::Write as _;
use std::path::Path;

use rockfall_plot::ColorScale;
use rockfall_raster::atomic::write_bytes_atomic;

use crate::ReportError;
use crate::layers::{LAYER_OPACITY, LayerStyle};

/// Colour-ramp items of a linear or symmetric scale.
const LINEAR_ITEMS: usize = 11;
/// Colour-ramp items of a log scale.
const LOG_ITEMS: usize = 21;

/// The `(value, (r, g, b))` items of the colour ramp of `scale`, ascending.
pub fn ramp_items(scale: &ColorScale) -> Vec<(f64, (u8, u8, u8))> {
    let n = if scale.log { LOG_ITEMS } else { LINEAR_ITEMS };
    (0..n)
        .map(|k| {
            let t = k as f64 / (n - 1) as f64;
            let v = if scale.log {
                scale.min * (scale.max / scale.min).powf(t)
            } else {
                scale.min + t * (scale.max - scale.min)
            };
            (v, scale.ramp.at(t))
        })
        .collect()
}

/// The `.qml` document of a layer drawn with `style` over `scale`.
pub fn qml(style: &LayerStyle, scale: &ColorScale) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<!DOCTYPE qgis PUBLIC 'http://mrcc.com/qgis.dtd' 'SYSTEM'>"
    );
    let _ = writeln!(
        s,
        "<qgis version=\"3.28.0\" styleCategories=\"AllStyleCategories\">"
    );
    s += &pipe(style, scale);
    let _ = writeln!(s, "  <blendMode>0</blendMode>");
    let _ = writeln!(s, "</qgis>");
    s
}

/// The `<pipe>` element of a layer drawn with `style` over `scale`: its renderer, as a
/// style file and a project's map layer both hold it.
pub fn pipe(style: &LayerStyle, scale: &ColorScale) -> String {
    let items = ramp_items(scale);
    let hex = |(r, g, b): (u8, u8, u8)| format!("#{r:02x}{g:02x}{b:02x}");
    let mut s = String::new();
    let (min, max) = (number(scale.min), number(scale.max));
    let _ = writeln!(s, "  <pipe>");
    let _ = writeln!(
        s,
        "    <rasterrenderer type=\"singlebandpseudocolor\" band=\"1\" opacity=\"{LAYER_OPACITY}\" \
         alphaBand=\"-1\" classificationMin=\"{min}\" classificationMax=\"{max}\" nodataColor=\"\">"
    );
    if style.zero_is_empty {
        let _ = writeln!(
            s,
            "      <rasterTransparency><singleValuePixelList>\
             <pixelListEntry min=\"0\" max=\"0\" percentTransparent=\"100\"/>\
             </singleValuePixelList></rasterTransparency>"
        );
    }
    let _ = writeln!(
        s,
        "      <minMaxOrigin><limits>None</limits><extent>WholeRaster</extent>\
         <statAccuracy>Exact</statAccuracy></minMaxOrigin>"
    );
    let _ = writeln!(s, "      <rastershader>");
    let _ = writeln!(
        s,
        "        <colorrampshader colorRampType=\"INTERPOLATED\" classificationMode=\"1\" \
         clip=\"0\" minimumValue=\"{min}\" maximumValue=\"{max}\" labelPrecision=\"4\">"
    );
    for (v, rgb) in &items {
        let _ = writeln!(
            s,
            "          <item alpha=\"255\" value=\"{v}\" label=\"{} {}\" color=\"{}\"/>",
            number(*v),
            xml_escape(style.unit),
            hex(*rgb)
        );
    }
    let _ = writeln!(s, "        </colorrampshader>");
    let _ = writeln!(s, "      </rastershader>");
    let _ = writeln!(s, "    </rasterrenderer>");
    let _ = writeln!(
        s,
        "    <brightnesscontrast brightness=\"0\" contrast=\"0\" gamma=\"1\"/>"
    );
    let _ = writeln!(s, "    <rasterresampler maxOversampling=\"2\"/>");
    let _ = writeln!(s, "  </pipe>");
    s
}

/// Writes `qml(style, scale)` to `path` atomically.
pub fn write_qml(path: &Path, style: &LayerStyle, scale: &ColorScale) -> Result<(), ReportError> {
    write_bytes_atomic(path, qml(style, scale).as_bytes()).map_err(ReportError::from)
}

/// A value as a short label: four significant digits, no trailing zeros.
pub(crate) fn number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (3 - v.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{v:.digits$}");
    match s.contains('.') {
        true => s.trim_end_matches('0').trim_end_matches('.').to_owned(),
        false => s,
    }
}

/// `&`, `<`, `>`, `"` and `'` as XML entities.
pub(crate) fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::layers::style;
    use rockfall_plot::Ramp;

    fn scale(min: f64, max: f64, log: bool, ramp: Ramp) -> ColorScale {
        ColorScale {
            label: String::new(),
            min,
            max,
            log,
            ramp,
        }
    }

    /// A QML document parsed as XML (it has a DOCTYPE).
    fn parse(doc: &str) -> roxmltree::Document<'_> {
        let options = roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        };
        roxmltree::Document::parse_with_options(doc, options).unwrap()
    }

    /// The items of a QML document, read back as XML.
    fn items(doc: &str) -> Vec<(f64, String)> {
        let xml = parse(doc);
        xml.descendants()
            .filter(|n| n.has_tag_name("item"))
            .map(|n| {
                let v = n.attribute("value").unwrap().parse().unwrap();
                (v, n.attribute("color").unwrap().to_owned())
            })
            .collect()
    }

    #[test]
    fn items_span_the_scale_with_the_ramps_colours() {
        let s = scale(0.0, 340.0, false, Ramp::Magma);
        let doc = qml(&style("E_95"), &s);
        let got = items(&doc);
        assert_eq!(got.len(), LINEAR_ITEMS);
        assert_eq!((got[0].0, got[10].0), (0.0, 340.0));
        assert!((got[5].0 - 170.0).abs() < 1e-9);
        let hex = |(r, g, b): (u8, u8, u8)| format!("#{r:02x}{g:02x}{b:02x}");
        for (item, t) in [(0, 0.0), (5, 0.5), (10, 1.0)] {
            assert_eq!(got[item].1, hex(Ramp::Magma.at(t)), "item {item}");
        }
        assert!(
            !doc.contains("pixelListEntry"),
            "energy 0 is a value, not empty"
        );
    }

    #[test]
    fn log_scales_get_log_spaced_items_and_zero_is_transparent() {
        let s = scale(0.01, 100.0, true, Ramp::Viridis);
        let doc = qml(&style("Reach_probability"), &s);
        let got = items(&doc);
        assert_eq!(got.len(), LOG_ITEMS);
        assert!((got[0].0 - 0.01).abs() < 1e-15 && (got[20].0 - 100.0).abs() < 1e-9);
        assert!(
            (got[10].0 - 1.0).abs() < 1e-12,
            "the middle item is the geometric mean"
        );
        assert!(got.windows(2).all(|w| w[0].0 < w[1].0));
        let xml = parse(&doc);
        let entry = xml
            .descendants()
            .find(|n| n.has_tag_name("pixelListEntry"))
            .unwrap();
        assert_eq!(entry.attribute("percentTransparent"), Some("100"));
        let renderer = xml
            .descendants()
            .find(|n| n.has_tag_name("rasterrenderer"))
            .unwrap();
        assert_eq!(renderer.attribute("type"), Some("singlebandpseudocolor"));
        assert_eq!(renderer.attribute("opacity"), Some("0.8"));
        let diff = scale(-5.0, 5.0, false, Ramp::Diverging);
        let reach_diff = qml(&style("Forest_effect_Reach_probability"), &diff);
        let zero = "pixelListEntry min=\"0\" max=\"0\"";
        assert!(
            reach_diff.contains(zero),
            "zero is no difference: transparent"
        );
        assert!(!qml(&style("Forest_effect_E_95"), &diff).contains("pixelListEntry"));
    }

    #[test]
    fn labels_are_short_and_escaped() {
        assert_eq!(number(0.0), "0");
        assert_eq!(number(340.0), "340");
        assert_eq!(number(0.0123456), "0.01235");
        assert_eq!(number(-80.0), "-80");
        assert_eq!(number(123456.0), "123456");
        assert_eq!(xml_escape("a<b & 'c'"), "a&lt;b &amp; &#39;c&#39;");
    }
}

//! The report page: one self-contained HTML file, readable offline.
//!
//! Figures are embedded as `data:` URIs (the same PNGs are also in the `report/` folder, for
//! documents), styles are inline, and nothing is fetched from the network. A few lines of
//! script mark on the `<html>` element how many images loaded (`data-images-loaded="n/N"`)
//! and show a banner naming any that did not; the page reads the same without script.

use std::fmt::Write as _;

use base64::Engine as _;
use base64::engine::general_purpose::STANDARD;

use crate::ReportError;
use crate::figure::Figure;

/// A table of label–value rows.
pub type Rows = Vec<(String, String)>;

/// A section of figures.
#[derive(Debug, Clone, Default)]
pub struct FigureSection {
    /// Anchor id.
    pub id: String,
    /// Heading.
    pub title: String,
    /// A paragraph under the heading; may be empty.
    pub intro: String,
    /// The figures, in order.
    pub figures: Vec<Figure>,
}

/// A table with a header row.
#[derive(Debug, Clone, Default)]
pub struct Table {
    /// Column headings.
    pub header: Vec<String>,
    /// Cells, row by row.
    pub rows: Vec<Vec<String>>,
}

/// Everything the page shows.
#[derive(Debug, Clone, Default)]
pub struct Page {
    /// `<title>` and heading.
    pub title: String,
    /// The line under the heading.
    pub subtitle: String,
    /// Links to related reports: (label, relative href).
    pub links: Rows,
    /// What was run.
    pub run: Rows,
    /// Headline figures: (label, value).
    pub glance: Rows,
    /// Per-screen figures.
    pub screens: Table,
    /// Figure sections, in order.
    pub sections: Vec<FigureSection>,
    /// Engine parameters.
    pub parameters: Rows,
    /// Every number of `summary.json`, flattened.
    pub numbers: Rows,
    /// Files of the output folder: (name, what it is).
    pub files: Rows,
    /// Sections of ready-made HTML shown after the headline figures: (anchor id, heading,
    /// HTML body; the caller escapes its text).
    pub html_sections: Vec<(String, String, String)>,
}

/// `&`, `<`, `>`, `"` and `'` escaped for HTML text and attributes.
pub fn escape(s: &str) -> String {
    crate::qml::xml_escape(s)
}

const STYLE: &str = "
body{font-family:'DejaVu Sans',Helvetica,Arial,sans-serif;margin:0;color:#1d1d1d;background:#fafafa;line-height:1.45}
header{background:#26323a;color:#fff;padding:18px 32px}
header h1{margin:0;font-size:1.6em}
header p{margin:4px 0 0;color:#d6dde2}
nav{padding:8px 32px;background:#e9edf0;font-size:.95em}
nav a{margin-right:16px;color:#1a4e7a}
main{max-width:1400px;margin:0 auto;padding:8px 32px 40px}
h2{border-bottom:2px solid #26323a;padding-bottom:4px;margin-top:36px}
table{border-collapse:collapse;margin:8px 0;font-size:.93em}
th,td{border:1px solid #c9d1d6;padding:4px 10px;text-align:left;vertical-align:top}
th{background:#e9edf0}
td.num{text-align:right;font-variant-numeric:tabular-nums}
tr:nth-child(even) td{background:#f3f5f6}
.glance{display:flex;flex-wrap:wrap;gap:12px;margin:12px 0}
.card{background:#fff;border:1px solid #c9d1d6;border-radius:6px;padding:10px 14px;min-width:150px}
.card .v{font-size:1.35em;font-weight:bold}
.card .l{font-size:.85em;color:#4a555c}
.figures{display:flex;flex-wrap:wrap;gap:20px}
figure{margin:0;background:#fff;border:1px solid #c9d1d6;border-radius:6px;padding:10px;max-width:calc(100% - 22px)}
figure img{display:block;width:100%;height:auto}
figcaption{font-size:.92em;color:#333;margin-top:6px}
figcaption .note{color:#5b666d}
.banner{background:#b3261e;color:#fff;padding:10px 32px;font-weight:bold}
code{background:#eef1f3;padding:0 3px;border-radius:3px}
footer{color:#5b666d;font-size:.85em;padding:16px 32px}
";

const SCRIPT: &str = "
window.addEventListener('load', function () {
  var imgs = document.images, ok = 0, bad = [];
  for (var i = 0; i < imgs.length; i++) {
    if (imgs[i].complete && imgs[i].naturalWidth > 0) { ok++; } else { bad.push(imgs[i].alt); }
  }
  document.documentElement.setAttribute('data-images-loaded', ok + '/' + imgs.length);
  if (bad.length) {
    var b = document.getElementById('missing');
    b.textContent = 'These figures did not load: ' + bad.join(', ');
    b.hidden = false;
  }
});
";

/// The page as HTML, every figure read from its file and embedded.
pub fn render(page: &Page) -> Result<String, ReportError> {
    let mut h = String::with_capacity(1 << 20);
    let t = escape(&page.title);
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{t}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n\
         <header><h1>{t}</h1><p>{}</p></header>\n\
         <div id=\"missing\" class=\"banner\" hidden></div>\n",
        escape(&page.subtitle)
    );
    nav(&mut h, page);
    h.push_str("<main>\n");
    section_rows(&mut h, "run", "What was run", &page.run);
    glance(&mut h, page);
    for (id, title, body) in &page.html_sections {
        let _ = write!(
            h,
            "<section id=\"{}\">\n<h2>{}</h2>\n{body}\n</section>\n",
            escape(id),
            escape(title)
        );
    }
    for s in &page.sections {
        figures(&mut h, s)?;
    }
    section_rows(&mut h, "parameters", "Engine parameters", &page.parameters);
    section_rows(
        &mut h,
        "numbers",
        "Every number of summary.json",
        &page.numbers,
    );
    section_rows(&mut h, "files", "Files in this folder", &page.files);
    let _ = write!(
        h,
        "</main>\n<footer>Written by rockfall {}. Everything on this page is in this one file; \
         the figures are also in <code>report/</code>.</footer>\n<script>{SCRIPT}</script>\n\
         </body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    Ok(h)
}

fn nav(h: &mut String, page: &Page) {
    h.push_str("<nav>");
    let mut link = |id: &str, label: &str| {
        let _ = write!(h, "<a href=\"#{}\">{}</a>", escape(id), escape(label));
    };
    link("run", "What was run");
    link("glance", "Results");
    for (id, title, _) in &page.html_sections {
        link(id, title);
    }
    for s in &page.sections {
        link(&s.id, &s.title);
    }
    link("parameters", "Parameters");
    link("files", "Files");
    for (label, href) in &page.links {
        let _ = write!(h, "<a href=\"{}\">{}</a>", escape(href), escape(label));
    }
    h.push_str("</nav>\n");
}

fn section_rows(h: &mut String, id: &str, title: &str, rows: &Rows) {
    if rows.is_empty() {
        return;
    }
    let _ = write!(
        h,
        "<section id=\"{id}\">\n<h2>{}</h2>\n<table>\n",
        escape(title)
    );
    for (k, v) in rows {
        let _ = writeln!(h, "<tr><th>{}</th><td>{}</td></tr>", escape(k), escape(v));
    }
    h.push_str("</table>\n</section>\n");
}

fn glance(h: &mut String, page: &Page) {
    h.push_str("<section id=\"glance\">\n<h2>Results at a glance</h2>\n<div class=\"glance\">\n");
    for (label, value) in &page.glance {
        let _ = writeln!(
            h,
            "<div class=\"card\"><div class=\"v\">{}</div><div class=\"l\">{}</div></div>",
            escape(value),
            escape(label)
        );
    }
    h.push_str("</div>\n");
    let table = &page.screens;
    if !table.rows.is_empty() {
        h.push_str("<h3>Evaluation screens</h3>\n<table>\n<tr>");
        for c in &table.header {
            let _ = write!(h, "<th>{}</th>", escape(c));
        }
        h.push_str("</tr>\n");
        for row in &table.rows {
            h.push_str("<tr>");
            for (i, c) in row.iter().enumerate() {
                let class = if i > 0 { " class=\"num\"" } else { "" };
                let _ = write!(h, "<td{class}>{}</td>", escape(c));
            }
            h.push_str("</tr>\n");
        }
        h.push_str("</table>\n");
    }
    h.push_str("</section>\n");
}

fn figures(h: &mut String, s: &FigureSection) -> Result<(), ReportError> {
    let _ = write!(
        h,
        "<section id=\"{}\">\n<h2>{}</h2>\n",
        escape(&s.id),
        escape(&s.title)
    );
    if !s.intro.is_empty() {
        let _ = writeln!(h, "<p>{}</p>", escape(&s.intro));
    }
    h.push_str("<div class=\"figures\">\n");
    for f in &s.figures {
        let bytes = std::fs::read(&f.path).map_err(|source| ReportError::Io {
            path: f.path.clone(),
            source,
        })?;
        let file = f
            .path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let width = png_width(&bytes).map_or(String::new(), |w| format!(" style=\"width:{w}px\""));
        let _ = write!(
            h,
            "<figure{width}><img alt=\"{}\" src=\"data:image/png;base64,{}\">\n<figcaption><b>{}</b>. {}",
            escape(&f.title),
            STANDARD.encode(&bytes),
            escape(&f.title),
            escape(&f.caption)
        );
        for n in &f.notes {
            let _ = write!(h, " <span class=\"note\">{}</span>", escape(n));
        }
        let _ = writeln!(
            h,
            " <span class=\"note\">(<code>report/{}</code>)</span></figcaption></figure>",
            escape(&file)
        );
    }
    h.push_str("</div>\n</section>\n");
    Ok(())
}

/// The width (px) in a PNG's header (the IHDR chunk right after the signature).
fn png_width(bytes: &[u8]) -> Option<u32> {
    let signature = b"\x89PNG\r\n\x1a\n";
    let ihdr = bytes.get(12..16)?;
    let width = bytes.get(16..20)?;
    (bytes.starts_with(signature) && ihdr == b"IHDR")
        .then(|| u32::from_be_bytes([width[0], width[1], width[2], width[3]]))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn text_is_escaped_and_figures_are_embedded() {
        let dir = tempfile::tempdir().unwrap();
        let png = dir.path().join("a.png");
        std::fs::write(&png, [0x89, b'P', b'N', b'G']).unwrap();
        let page = Page {
            title: "site <1> & co".into(),
            run: vec![("seed".into(), "\"7\"".into())],
            sections: vec![FigureSection {
                id: "maps".into(),
                title: "Maps".into(),
                intro: String::new(),
                figures: vec![Figure {
                    path: png,
                    title: "Reach".into(),
                    caption: "x < y".into(),
                    notes: vec!["GIS: a.tif".into()],
                }],
            }],
            ..Page::default()
        };
        let html = render(&page).unwrap();
        assert!(html.contains("<title>site &lt;1&gt; &amp; co</title>"));
        assert!(html.contains("<td>&quot;7&quot;</td>"));
        assert!(
            html.contains("src=\"data:image/png;base64,iVBORw==\""),
            "{html}"
        );
        assert!(html.contains("x &lt; y"));
        let linked = Page {
            links: vec![("a \"b\"".into(), "x\" onclick=\"y".into())],
            ..Page::default()
        };
        let html = render(&linked).unwrap();
        assert!(
            html.contains("<a href=\"x&quot; onclick=&quot;y\">a &quot;b&quot;</a>"),
            "{html}"
        );
        assert!(
            !html.contains("http://") && !html.contains("https://"),
            "nothing from the network"
        );
    }

    #[test]
    fn png_widths_come_from_the_header() {
        let mut png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR".to_vec();
        png.extend(600u32.to_be_bytes());
        png.extend(900u32.to_be_bytes());
        assert_eq!(png_width(&png), Some(600));
        assert_eq!(png_width(b"GIF89a"), None);
        let mut other_chunk = png.clone();
        other_chunk[12..16].copy_from_slice(b"IDAT");
        assert_eq!(png_width(&other_chunk), None, "the width is IHDR's");
        assert_eq!(png_width(&png[..18]), None);
    }

    #[test]
    fn a_missing_figure_is_an_error_naming_it() {
        let page = Page {
            sections: vec![FigureSection {
                figures: vec![Figure {
                    path: "/nonexistent/fig.png".into(),
                    title: String::new(),
                    caption: String::new(),
                    notes: Vec::new(),
                }],
                ..FigureSection::default()
            }],
            ..Page::default()
        };
        let err = render(&page).unwrap_err().to_string();
        assert!(err.contains("/nonexistent/fig.png"), "{err}");
    }
}

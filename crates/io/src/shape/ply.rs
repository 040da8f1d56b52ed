//! Stanford PLY files, `ascii` and `binary_little_endian` (Turk 1994, "The PLY polygon file
//! format"): the x, y, z properties of the `vertex` element.
//!
//! Elements before `vertex` are read past (their scalar and list properties by their sizes),
//! elements after it are ignored, and so are all other vertex properties. Errors name the line
//! (header and ASCII body) or the record, e.g. vertex 7 (binary body).

use super::ShapeFileError;
use super::{finite_point, parse_error};
use std::path::Path;

/// A PLY scalar type.
#[derive(Debug, Clone, Copy)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    /// The type of a PLY type name (both the old and the sized spellings).
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// Size in bytes.
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// The little-endian value at the start of `b` (at least `size()` bytes).
    fn read_le(self, b: &[u8]) -> f64 {
        match self {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
        }
    }
}

/// A property: one scalar, or a list (a count, then that many items).
#[derive(Debug, Clone, Copy)]
enum Property {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// An element declaration of the header.
#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<(String, Property)>,
    /// Header line of the declaration.
    line: usize,
}

/// The parsed header.
#[derive(Debug)]
struct Header {
    binary: bool,
    elements: Vec<Element>,
    /// Byte offset of the body.
    body_start: usize,
    /// Number of header lines.
    lines: usize,
}

/// The vertices of a PLY file.
pub(super) fn parse_ply(path: &Path, bytes: &[u8]) -> Result<Vec<[f64; 3]>, ShapeFileError> {
    let header = parse_header(path, bytes)?;
    let last_line = header.lines;
    let vertex = header
        .elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or_else(|| parse_error(path, last_line, "no `vertex` element in the header"))?;
    let el = &header.elements[vertex];
    let find = |axis: &str| {
        el.properties
            .iter()
            .position(|(n, p)| n == axis && matches!(p, Property::Scalar(_)))
    };
    let (Some(ix), Some(iy), Some(iz)) = (find("x"), find("y"), find("z")) else {
        return Err(parse_error(
            path,
            el.line,
            "the vertex element has no scalar x, y, z properties",
        ));
    };
    let mut body = Body::new(path, bytes, &header)?;
    let mut points = Vec::with_capacity(el.count.min(1 << 16)); // the header may lie
    for (e, element) in header.elements[..=vertex].iter().enumerate() {
        if element.properties.is_empty() {
            // records without properties hold nothing to read past, however many the
            // header declares (a count of 10^15 must not be counted through)
            continue;
        }
        for r in 0..element.count {
            let values = body.record(&element.properties).ok_or_else(|| {
                let what = format!(
                    "cannot read {} {} of {}",
                    element.name,
                    r + 1,
                    element.count
                );
                parse_error(path, body.position(r), what)
            })?;
            if e == vertex {
                let xyz = [values[ix], values[iy], values[iz]];
                points.push(finite_point(path, body.position(r), xyz)?);
            }
        }
    }
    Ok(points)
}

/// Parses the header up to and including `end_header`.
fn parse_header(path: &Path, bytes: &[u8]) -> Result<Header, ShapeFileError> {
    let mut binary = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut offset = 0;
    for (i, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        offset += raw.len() + 1;
        let line_no = i + 1;
        let err = |what: String| parse_error(path, line_no, what);
        let line = std::str::from_utf8(raw)
            .map_err(|_| err("the PLY header is not text".into()))?
            .trim();
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["ply"] if i == 0 => {}
            _ if i == 0 => return Err(err("not a PLY file (no `ply` first line)".into())),
            ["format", "ascii", _] => binary = Some(false),
            ["format", "binary_little_endian", _] => binary = Some(true),
            ["format", f, ..] => return Err(err(format!("unsupported PLY format `{f}`"))),
            ["comment" | "obj_info", ..] | [] => {}
            ["element", name, count] => elements.push(Element {
                name: (*name).into(),
                count: count
                    .parse()
                    .map_err(|_| err(format!("bad element count `{count}`")))?,
                properties: Vec::new(),
                line: line_no,
            }),
            ["property", rest @ ..] => {
                let el = elements
                    .last_mut()
                    .ok_or_else(|| err("a property before any element".into()))?;
                let property = parse_property(rest)
                    .ok_or_else(|| err(format!("bad property declaration `{line}`")))?;
                el.properties.push(property);
            }
            ["end_header"] => {
                let binary = binary.ok_or_else(|| err("no `format` line".into()))?;
                return Ok(Header {
                    binary,
                    elements,
                    body_start: offset.min(bytes.len()),
                    lines: line_no,
                });
            }
            _ => return Err(err(format!("unexpected header line `{line}`"))),
        }
    }
    Err(parse_error(path, 1, "no `end_header` line"))
}

/// `type name` or `list count_type item_type name`.
fn parse_property(words: &[&str]) -> Option<(String, Property)> {
    match words {
        ["list", count, item, name] => Some((
            (*name).into(),
            Property::List {
                count: Scalar::parse(count)?,
                item: Scalar::parse(item)?,
            },
        )),
        [ty, name] => Some(((*name).into(), Property::Scalar(Scalar::parse(ty)?))),
        _ => None,
    }
}

/// The body of the file, read record by record.
enum Body<'a> {
    /// One record per line; `line` is the file line number of the last line read.
    Ascii {
        lines: std::str::Lines<'a>,
        line: usize,
    },
    /// Packed little-endian records.
    Binary { bytes: &'a [u8], pos: usize },
}

impl<'a> Body<'a> {
    fn new(path: &Path, bytes: &'a [u8], header: &Header) -> Result<Body<'a>, ShapeFileError> {
        let body = &bytes[header.body_start..];
        if header.binary {
            return Ok(Body::Binary {
                bytes: body,
                pos: 0,
            });
        }
        let text = std::str::from_utf8(body)
            .map_err(|_| parse_error(path, header.lines + 1, "the ASCII PLY body is not text"))?;
        Ok(Body::Ascii {
            lines: text.lines(),
            line: header.lines,
        })
    }

    /// The values of one record's properties (0 for lists, which are read past).
    fn record(&mut self, properties: &[(String, Property)]) -> Option<Vec<f64>> {
        match self {
            Body::Ascii { lines, line } => {
                let mut text = "";
                while text.trim().is_empty() {
                    text = lines.next()?;
                    *line += 1;
                }
                let mut words = text.split_whitespace();
                read_record(properties, |_| words.next()?.parse().ok())
            }
            Body::Binary { bytes, pos } => read_record(properties, |s| {
                let b = bytes.get(*pos..*pos + s.size())?;
                *pos += s.size();
                Some(s.read_le(b))
            }),
        }
    }

    /// Where record `index` (0-based) is, for messages: its line (ASCII) or its number
    /// (binary, 1-based).
    fn position(&self, index: usize) -> usize {
        match self {
            Body::Ascii { line, .. } => *line,
            Body::Binary { .. } => index + 1,
        }
    }
}

/// Reads one record with `next` giving the next value of a type.
fn read_record(
    properties: &[(String, Property)],
    mut next: impl FnMut(Scalar) -> Option<f64>,
) -> Option<Vec<f64>> {
    properties
        .iter()
        .map(|(_, p)| match *p {
            Property::Scalar(s) => next(s),
            Property::List { count, item } => {
                let n = next(count)?;
                if !(n >= 0.0 && n.fract() == 0.0) {
                    return None;
                }
                for _ in 0..n as usize {
                    next(item)?;
                }
                Some(0.0)
            }
        })
        .collect()
}

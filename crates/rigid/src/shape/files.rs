//! Rock point clouds from files.
//!
//! | extension | content |
//! |---|---|
//! | `.xyz`, `.csv`, `.txt` | one point per line: x y z separated by whitespace, commas or semicolons (further columns ignored); blank lines and `#` comments skipped; a first line that is not numbers is a header |
//! | `.obj` | Wavefront OBJ: the `v x y z` lines (faces and everything else ignored) |
//! | `.ply` | Stanford PLY, `ascii` or `binary_little_endian`: the x, y, z properties of the `vertex` element |
//! | `.stl` | STL, ASCII (`vertex x y z`) or binary |
//!
//! Only the points matter: the rock is their convex hull, so faces, normals and duplicates are
//! ignored. Errors name the file and the line (text) or the vertex / triangle (binary).

use super::ShapeError;
use crate::math::V3;
use std::path::Path;

/// The points of a point cloud or mesh file, by its extension (see the module documentation).
/// At least 4 points; whether they span a solid is checked by
/// [`super::RockGeometry::from_points`].
pub fn load_points(path: &Path) -> Result<Vec<V3>, ShapeError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let read_text = || {
        std::fs::read_to_string(path).map_err(|source| ShapeError::Io {
            path: path.into(),
            source,
        })
    };
    let read_bytes = || {
        std::fs::read(path).map_err(|source| ShapeError::Io {
            path: path.into(),
            source,
        })
    };
    let points = match ext.as_deref() {
        Some("xyz" | "csv" | "txt") => parse_xyz(path, &read_text()?)?,
        Some("obj") => keyword_points(path, &read_text()?, "v")?,
        Some("ply") => super::ply::parse_ply(path, &read_bytes()?)?,
        Some("stl") => super::stl::parse_stl(path, &read_bytes()?)?,
        _ => {
            return Err(ShapeError::UnknownShape(format!(
                "{} (expected a .xyz, .csv, .txt, .obj, .ply or .stl file)",
                path.display()
            )));
        }
    };
    if points.len() < 4 {
        return Err(ShapeError::Degenerate(format!(
            "{} has {} points, a rock needs at least 4",
            path.display(),
            points.len()
        )));
    }
    Ok(points)
}

/// A [`ShapeError::Parse`] at `line` of `path`.
pub(super) fn parse_error(path: &Path, line: usize, what: impl Into<String>) -> ShapeError {
    ShapeError::Parse {
        path: path.into(),
        line,
        what: what.into(),
    }
}

/// The point (x, y, z), or a parse error at `line` when a coordinate is not finite.
pub(super) fn finite_point(path: &Path, line: usize, xyz: [f64; 3]) -> Result<V3, ShapeError> {
    let p = V3::from_array(xyz);
    if crate::math::finite(p) {
        Ok(p)
    } else {
        Err(parse_error(
            path,
            line,
            format!("coordinate is not finite: {p}"),
        ))
    }
}

/// The first three numbers of `fields`, `None` when there are fewer or one does not parse.
fn three_numbers<'a>(mut fields: impl Iterator<Item = &'a str>) -> Option<[f64; 3]> {
    let mut next = || fields.next()?.parse::<f64>().ok();
    Some([next()?, next()?, next()?])
}

/// Points of an `.xyz` / `.csv` / `.txt` file.
fn parse_xyz(path: &Path, text: &str) -> Result<Vec<V3>, ShapeError> {
    let mut points = Vec::new();
    let mut first = true;
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields = line
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|f| !f.is_empty());
        match three_numbers(fields) {
            Some(xyz) => points.push(finite_point(path, i + 1, xyz)?),
            None if first => {} // a header
            None => {
                return Err(parse_error(
                    path,
                    i + 1,
                    format!("expected x y z, found `{line}`"),
                ));
            }
        }
        first = false;
    }
    Ok(points)
}

/// Points of the lines `keyword x y z` of a text file (`v` in Wavefront OBJ, `vertex` in ASCII
/// STL); other lines are ignored.
pub(super) fn keyword_points(
    path: &Path,
    text: &str,
    keyword: &str,
) -> Result<Vec<V3>, ShapeError> {
    let mut points = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut fields = line.split_whitespace();
        if fields.next() != Some(keyword) {
            continue;
        }
        let xyz = three_numbers(fields).ok_or_else(|| {
            let found = line.trim();
            parse_error(
                path,
                i + 1,
                format!("expected `{keyword} x y z`, found `{found}`"),
            )
        })?;
        points.push(finite_point(path, i + 1, xyz)?);
    }
    Ok(points)
}

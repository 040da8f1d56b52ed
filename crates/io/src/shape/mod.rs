//! Rock point clouds from files: the rigid engine's rock is the convex hull of these points.
//!
//! | extension | content |
//! |---|---|
//! | `.xyz`, `.csv`, `.txt` | one point per line: x y z separated by whitespace, commas or semicolons (further columns ignored); blank lines and `#` comments skipped; a first line that is not numbers is a header |
//! | `.obj` | Wavefront OBJ: the `v x y z` lines (faces and everything else ignored) |
//! | `.ply` | Stanford PLY, `ascii` or `binary_little_endian`: the x, y, z properties of the `vertex` element |
//! | `.stl` | STL, ASCII (`vertex x y z`) or binary |
//!
//! Only the points matter: the rock is their convex hull, so faces, normals and duplicates are
//! ignored. Coordinates are metres. Errors name the file and the line (text) or the vertex /
//! triangle (binary).
//!
//! A scenario names its rock file as a path ([`RockShape::File`]); [`read_shape`] reads it into
//! [`RockShape::Cloud`], which is what the engines take. Scenario files do this as they are read
//! ([`crate::load`]), with the path resolved against the scenario's folder.

mod ply;
mod stl;
#[cfg(test)]
mod tests;

use rockfall_scenario::RockShape;
use std::path::{Path, PathBuf};

/// A rock shape file that cannot be used: every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum ShapeFileError {
    /// The file could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// A line (text formats) or record (binary formats) is not valid.
    #[error("{}:{line}: {what}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number (text), or 1-based vertex / triangle number (binary PLY / STL).
        line: usize,
        /// What is wrong.
        what: String,
    },
    /// The extension is not one of the formats read here.
    #[error(
        "unknown rock shape `{} (expected a .xyz, .csv, .txt, .obj, .ply or .stl file)`",
        path.display()
    )]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// Fewer than 4 points: no solid.
    #[error(
        "degenerate rock shape: {} has {count} points, a rock needs at least 4",
        path.display()
    )]
    TooFewPoints {
        /// The file.
        path: PathBuf,
        /// How many points it has.
        count: usize,
    },
}

/// The points of a point cloud or mesh file, m, by its extension (see the module
/// documentation): at least 4, each finite. Whether they span a solid is the engine's check
/// (`rockfall_rigid::shape::RockGeometry::from_points`).
pub fn read_points(path: &Path) -> Result<Vec<[f64; 3]>, ShapeFileError> {
    let bytes = std::fs::read(path).map_err(|source| ShapeFileError::Io {
        path: path.into(),
        source,
    })?;
    parse_points(path, &bytes)
}

/// [`read_points`] on a file's bytes already read; the format comes from `path`'s extension,
/// which also names the source in errors.
pub fn parse_points(path: &Path, bytes: &[u8]) -> Result<Vec<[f64; 3]>, ShapeFileError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let text = || {
        std::str::from_utf8(bytes).map_err(|e| ShapeFileError::Io {
            path: path.into(),
            source: std::io::Error::new(std::io::ErrorKind::InvalidData, e),
        })
    };
    let points = match ext.as_deref() {
        Some("xyz" | "csv" | "txt") => parse_xyz(path, text()?)?,
        Some("obj") => keyword_points(path, text()?, "v")?,
        Some("ply") => ply::parse_ply(path, bytes)?,
        Some("stl") => stl::parse_stl(path, bytes)?,
        _ => return Err(ShapeFileError::UnknownFormat { path: path.into() }),
    };
    if points.len() < 4 {
        return Err(ShapeFileError::TooFewPoints {
            path: path.into(),
            count: points.len(),
        });
    }
    Ok(points)
}

/// `shape` with its file read: [`RockShape::File`] becomes [`RockShape::Cloud`] of the file's
/// points (the path, as given, kept as its source); every other shape is returned as it is.
pub fn read_shape(shape: RockShape) -> Result<RockShape, ShapeFileError> {
    match shape {
        RockShape::File(path) => Ok(RockShape::Cloud {
            points_m: read_points(&path)?,
            source: path,
        }),
        other => Ok(other),
    }
}

/// A [`ShapeFileError::Parse`] at `line` of `path`.
fn parse_error(path: &Path, line: usize, what: impl Into<String>) -> ShapeFileError {
    ShapeFileError::Parse {
        path: path.into(),
        line,
        what: what.into(),
    }
}

/// The point (x, y, z), or a parse error at `line` when a coordinate is not finite.
fn finite_point(path: &Path, line: usize, xyz: [f64; 3]) -> Result<[f64; 3], ShapeFileError> {
    if xyz.iter().all(|c| c.is_finite()) {
        Ok(xyz)
    } else {
        let [x, y, z] = xyz;
        Err(parse_error(
            path,
            line,
            format!("coordinate is not finite: [{x}, {y}, {z}]"),
        ))
    }
}

/// The first three numbers of `fields`, `None` when there are fewer or one does not parse.
fn three_numbers<'a>(mut fields: impl Iterator<Item = &'a str>) -> Option<[f64; 3]> {
    let mut next = || fields.next()?.parse::<f64>().ok();
    Some([next()?, next()?, next()?])
}

/// Points of an `.xyz` / `.csv` / `.txt` file.
fn parse_xyz(path: &Path, text: &str) -> Result<Vec<[f64; 3]>, ShapeFileError> {
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
fn keyword_points(path: &Path, text: &str, keyword: &str) -> Result<Vec<[f64; 3]>, ShapeFileError> {
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

//! ESRI ASCII grid (`.asc`), the format of Rockyfor3D input folders.
//!
//! ```text
//! ncols         4
//! nrows         3
//! xllcorner     912000.0      (or xllcenter: centre of the lower-left cell)
//! yllcorner     6456000.0     (or yllcenter)
//! cellsize      2.5
//! NODATA_value  -9999         (optional)
//! 1 2 3 4
//! ...                          nrows × ncols values, row 0 = north, any line breaks
//! ```
//!
//! Keys are matched in any case and order; each must appear once. Parsing is strict: a
//! missing or repeated key, a non-number, NaN or infinity, or a value count other than
//! `nrows × ncols` is an error naming the file, the line and (for values) the cell.
//! Non-square cells (`dx`/`dy`) are not supported. The CRS lives in a `.prj` sidecar (WKT),
//! read when present and written whenever the grid's CRS is known.

use crate::atomic::write_atomic;
use crate::rows::try_for_each_row;
use crate::{Crs, Grid, GridGeometry, RasterError, Rows, SampleType};
use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};

/// Reads an ESRI ASCII grid and its `.prj` sidecar, if any. The file is read line by line
/// into the grid: beside the grid (9 bytes a cell) only one line of text is in memory.
pub fn read(path: &Path) -> Result<Grid<f64>, RasterError> {
    let file = std::fs::File::open(path).map_err(|e| RasterError::io(path, e))?;
    let size = file.metadata().map_or(0, |m| m.len());
    let lines = std::io::BufReader::new(file)
        .lines()
        .enumerate()
        .map(|(i, line)| line.map(|l| (i, l)).map_err(|e| RasterError::io(path, e)));
    let mut grid = parse_lines(lines, usize::try_from(size).unwrap_or(usize::MAX), path)?;
    let prj = [prj_path(path), path.with_extension("PRJ")]
        .into_iter()
        .find(|p| p.is_file());
    if let Some(prj) = prj {
        let wkt = std::fs::read_to_string(&prj).map_err(|e| RasterError::io(&prj, e))?;
        if !wkt.trim().is_empty() {
            grid.set_crs(Some(Crs::from_wkt(&wkt)));
        }
    }
    Ok(grid)
}

/// The grid and CRS of an ESRI ASCII grid (read whole: ASCII grids are the small ones).
pub fn read_geometry(path: &Path) -> Result<(GridGeometry, Option<Crs>), RasterError> {
    let grid = read(path)?;
    Ok((*grid.geometry(), grid.crs().cloned()))
}

/// The `.prj` sidecar of a grid file (same stem).
pub fn prj_path(path: &Path) -> PathBuf {
    path.with_extension("prj")
}

/// Largest grid we read: 2³¹ cells (16 GiB of f64 values).
pub const MAX_CELLS: usize = 1 << 31;

#[derive(Default)]
struct Header {
    ncols: Option<usize>,
    nrows: Option<usize>,
    x: Option<(f64, bool)>, // (value, is_center)
    y: Option<(f64, bool)>,
    cell_size: Option<f64>,
    nodata: Option<f64>,
}

/// Parses the text of an ASCII grid; `path` is only used in error messages.
pub fn parse(text: &str, path: &Path) -> Result<Grid<f64>, RasterError> {
    parse_lines(text.lines().enumerate().map(Ok), text.len(), path)
}

/// Parses the numbered lines (0-based) of an ASCII grid of `text_len` bytes.
fn parse_lines<S: AsRef<str>>(
    lines: impl Iterator<Item = Result<(usize, S), RasterError>>,
    text_len: usize,
    path: &Path,
) -> Result<Grid<f64>, RasterError> {
    let header_err = |line: usize, message: String| RasterError::Header {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut h = Header::default();
    let mut lines = lines.peekable();
    let mut last_line = 0;
    // Header: lines whose first token is a key (anything starting with a letter that is
    // not a number such as "nan" or "inf").
    loop {
        // a header line is blank or starts with a key; the first other line is data
        let header = match lines.peek() {
            None => false,
            Some(Err(_)) => true,
            Some(Ok((_, line))) => line.as_ref().split_whitespace().next().is_none_or(|key| {
                key.starts_with(|c: char| c.is_ascii_alphabetic()) && key.parse::<f64>().is_err()
            }),
        };
        let Some(item) = header.then(|| lines.next()).flatten() else {
            break;
        };
        let (i, line) = item?;
        let line_no = i + 1;
        let mut tokens = line.as_ref().split_whitespace();
        let Some(key) = tokens.next() else {
            continue;
        };
        last_line = line_no;
        let value = tokens
            .next()
            .ok_or_else(|| header_err(line_no, format!("header key `{key}` has no value")))?;
        if let Some(extra) = tokens.next() {
            return Err(header_err(
                line_no,
                format!("unexpected `{extra}` after `{key} {value}`"),
            ));
        }
        let num = |what: &str| -> Result<f64, RasterError> {
            match value.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(header_err(
                    line_no,
                    format!("{what} `{value}` is not a finite number"),
                )),
            }
        };
        let count = |what: &str| -> Result<usize, RasterError> {
            value
                .parse::<usize>()
                .map_err(|_| header_err(line_no, format!("{what} `{value}` is not a whole number")))
        };
        let lower = key.to_ascii_lowercase();
        let dup = || header_err(line_no, format!("header key `{key}` given twice"));
        match lower.as_str() {
            "ncols" => set_once(&mut h.ncols, count("ncols")?).map_err(|_| dup())?,
            "nrows" => set_once(&mut h.nrows, count("nrows")?).map_err(|_| dup())?,
            "xllcorner" => set_once(&mut h.x, (num("xllcorner")?, false)).map_err(|_| dup())?,
            "xllcenter" => set_once(&mut h.x, (num("xllcenter")?, true)).map_err(|_| dup())?,
            "yllcorner" => set_once(&mut h.y, (num("yllcorner")?, false)).map_err(|_| dup())?,
            "yllcenter" => set_once(&mut h.y, (num("yllcenter")?, true)).map_err(|_| dup())?,
            "cellsize" => set_once(&mut h.cell_size, num("cellsize")?).map_err(|_| dup())?,
            "nodata_value" => set_once(&mut h.nodata, num("NODATA_value")?).map_err(|_| dup())?,
            "dx" | "dy" => {
                return Err(header_err(
                    line_no,
                    "non-square cells (dx/dy) are not supported; resample to square cells".into(),
                ));
            }
            _ => return Err(header_err(line_no, format!("unknown header key `{key}`"))),
        }
    }
    let geometry = header_geometry(&h, last_line, &header_err)?;
    let (values, valid) = parse_values(&mut lines, text_len, &geometry, h.nodata, path)?;
    let mut grid = Grid::from_values(geometry, values).ok_or_else(|| RasterError::Invalid {
        path: path.to_path_buf(),
        message: "internal: value count".into(),
    })?;
    for (i, _) in valid.iter().enumerate().filter(|(_, ok)| !**ok) {
        let (row, col) = geometry.row_col(i);
        grid.set_nodata(row, col);
    }
    grid.set_nodata_value(h.nodata);
    Ok(grid)
}

fn set_once<T>(slot: &mut Option<T>, value: T) -> Result<(), ()> {
    if slot.is_some() {
        return Err(());
    }
    *slot = Some(value);
    Ok(())
}

fn header_geometry(
    h: &Header,
    last_line: usize,
    header_err: &impl Fn(usize, String) -> RasterError,
) -> Result<GridGeometry, RasterError> {
    let missing = |key: &str| header_err(last_line, format!("missing header key `{key}`"));
    let ncols = h.ncols.ok_or_else(|| missing("ncols"))?;
    let nrows = h.nrows.ok_or_else(|| missing("nrows"))?;
    let (x, x_center) = h.x.ok_or_else(|| missing("xllcorner"))?;
    let (y, y_center) = h.y.ok_or_else(|| missing("yllcorner"))?;
    let cell = h.cell_size.ok_or_else(|| missing("cellsize"))?;
    if ncols == 0 || nrows == 0 {
        return Err(header_err(
            last_line,
            format!("empty grid ({ncols} columns × {nrows} rows)"),
        ));
    }
    if ncols.checked_mul(nrows).is_none_or(|n| n > MAX_CELLS) {
        return Err(header_err(
            last_line,
            format!("grid of {ncols} × {nrows} cells is larger than the {MAX_CELLS} cells we read"),
        ));
    }
    if cell <= 0.0 {
        return Err(header_err(
            last_line,
            format!("cellsize must be positive, found {cell}"),
        ));
    }
    let half = if x_center { 0.5 * cell } else { 0.0 };
    let half_y = if y_center { 0.5 * cell } else { 0.0 };
    Ok(GridGeometry {
        ncols,
        nrows,
        x_min_m: x - half,
        y_min_m: y - half_y,
        cell_size_m: cell,
    })
}

/// The values (nodata cells hold 0) and the validity of every cell, row-major.
fn parse_values<S: AsRef<str>>(
    lines: &mut impl Iterator<Item = Result<(usize, S), RasterError>>,
    text_len: usize,
    geometry: &GridGeometry,
    nodata: Option<f64>,
    path: &Path,
) -> Result<(Vec<f64>, Vec<bool>), RasterError> {
    let expected = geometry.len();
    // Reserve by what the text can hold (a value takes at least two bytes), so that a header
    // promising more cells than the file has cannot trigger a huge allocation.
    let mut values = Vec::with_capacity(expected.min(text_len / 2 + 1));
    let mut valid = Vec::with_capacity(expected.min(text_len / 2 + 1));
    let mut last_line = 0;
    for item in lines {
        let (i, line) = item?;
        let line = line.as_ref();
        let line_no = i + 1;
        for token in line.split_whitespace() {
            let n = values.len();
            if n == expected {
                return Err(RasterError::Count {
                    path: path.to_path_buf(),
                    line: line_no,
                    message: format!(
                        "more values than nrows × ncols = {} × {} = {expected}; the first extra value is `{token}`",
                        geometry.nrows, geometry.ncols
                    ),
                });
            }
            let (row, col) = geometry.row_col(n);
            let value_err = |message: String| RasterError::Value {
                path: path.to_path_buf(),
                line: line_no,
                row,
                col,
                message,
            };
            let v: f64 = token
                .parse()
                .map_err(|_| value_err(format!("`{token}` is not a number")))?;
            if v.is_nan() {
                return Err(value_err(format!(
                    "`{token}` (NaN) is not allowed; mark missing cells with NODATA_value"
                )));
            }
            if !v.is_finite() {
                return Err(value_err(format!("`{token}` is not a finite number")));
            }
            let ok = Some(v) != nodata;
            values.push(if ok { v } else { 0.0 });
            valid.push(ok);
        }
        if !line.trim().is_empty() {
            last_line = line_no;
        }
    }
    if values.len() != expected {
        return Err(RasterError::Count {
            path: path.to_path_buf(),
            line: last_line,
            message: format!(
                "found {} values, expected nrows × ncols = {} × {} = {expected} (file truncated?)",
                values.len(),
                geometry.nrows,
                geometry.ncols
            ),
        });
    }
    Ok((values, valid))
}

/// Writes an ESRI ASCII grid (`xllcorner`/`yllcorner` form) atomically, with a `.prj`
/// sidecar when the grid's CRS is known. Values are written in the shortest form that reads
/// back to the same `f64` (exact round trip); nodata cells as the grid's nodata value, or
/// −9999 when it has none.
pub fn write(path: &Path, grid: &Grid<f64>) -> Result<(), RasterError> {
    write_rows(path, grid)
}

/// [`write`] of a raster given row by row: one pass to check the values and count nodata
/// cells, one to write, one row in memory.
pub fn write_rows(path: &Path, rows: &impl Rows) -> Result<(), RasterError> {
    write_rows_as(path, rows, SampleType::F64)
}

/// [`write_rows`] of values of type `sample`, as the GeoTIFF of the same raster holds them:
/// [`SampleType::I32`] values (counts, classes) rounded to the nearest integer (half away
/// from zero) and written without a fraction, as is the nodata marker; a value outside the
/// `i32` range is [`RasterError::Invalid`]. Float types are written as they are.
pub fn write_rows_as(path: &Path, rows: &impl Rows, sample: SampleType) -> Result<(), RasterError> {
    let g = rows.geometry();
    let invalid = |message: String| RasterError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    if g.is_empty() {
        return Err(invalid("cannot write an empty grid".into()));
    }
    let integers = sample == SampleType::I32;
    // `+ 0.0` turns −0 into 0
    let stored = |v: f64| if integers { v.round() + 0.0 } else { v };
    let mut has_nodata = false;
    try_for_each_row(rows, |row, cells| {
        for (col, c) in cells.iter().enumerate() {
            match c {
                None => has_nodata = true,
                Some(v) if !v.is_finite() => {
                    return Err(invalid(format!("cannot write non-finite value {v}")));
                }
                Some(v) if integers && !fits_i32(stored(*v)) => {
                    return Err(invalid(format!(
                        "cell (row {row}, column {col}) = {v:?} does not fit I32"
                    )));
                }
                Some(_) => {}
            }
        }
        Ok(())
    })?;
    let nodata = stored(rows.nodata_value().unwrap_or(-9999.0));
    write_atomic(path, |w| {
        let io = |e| RasterError::io(path, e);
        writeln!(w, "ncols {}", g.ncols).map_err(io)?;
        writeln!(w, "nrows {}", g.nrows).map_err(io)?;
        writeln!(w, "xllcorner {}", g.x_min_m).map_err(io)?;
        writeln!(w, "yllcorner {}", g.y_min_m).map_err(io)?;
        writeln!(w, "cellsize {}", g.cell_size_m).map_err(io)?;
        if has_nodata || rows.nodata_value().is_some() {
            writeln!(w, "NODATA_value {nodata}").map_err(io)?;
        }
        let mut line = String::with_capacity(g.ncols * 8);
        try_for_each_row(rows, |_, cells| {
            line.clear();
            for (col, c) in cells.iter().enumerate() {
                if col > 0 {
                    line.push(' ');
                }
                // `{}` of an f64 never writes an exponent, nor `.0` after an integer
                let v = c.map_or(nodata, stored);
                use std::fmt::Write as _;
                let _ = write!(line, "{v}");
            }
            line.push('\n');
            w.write_all(line.as_bytes()).map_err(io)
        })
    })?;
    let prj = prj_path(path);
    if let Some(wkt) = rows.crs().and_then(Crs::wkt_for_prj) {
        crate::atomic::write_bytes_atomic(&prj, wkt.as_bytes()).map_err(RasterError::from)?;
    }
    Ok(())
}

fn fits_i32(v: f64) -> bool {
    v >= f64::from(i32::MIN) && v <= f64::from(i32::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> &'static Path {
        Path::new("dem.asc")
    }

    #[test]
    fn reads_corner_and_center_forms_in_any_case() {
        let a = parse(
            "NCOLS 3\nnRows 2\nXLLCORNER 10\nyllcorner 20\nCellSize 2\n1 2 3\n4 5 6\n",
            p(),
        )
        .unwrap();
        let b = parse(
            "ncols 3\nnrows 2\nxllcenter 11\nyllcenter 21\ncellsize 2\n1 2 3 4 5 6\n",
            p(),
        )
        .unwrap();
        assert_eq!(a.geometry(), b.geometry());
        assert_eq!(a.geometry().x_min_m, 10.0);
        assert_eq!(a.get(0, 0), Some(1.0));
        assert_eq!(a.get(1, 2), Some(6.0));
        assert_eq!(a.values(), b.values());
    }

    #[test]
    fn nodata_cells_are_masked() {
        let g = parse(
            "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n1 -9999\n3 4\n",
            p(),
        )
        .unwrap();
        assert_eq!(g.get(0, 1), None);
        assert_eq!(g.nodata_count(), 1);
        assert_eq!(g.nodata_value(), Some(-9999.0));
    }

    /// The error of parsing `text`, which reading it from a file line by line must give too.
    fn err(text: &str) -> String {
        let from_text = parse(text, p()).unwrap_err().to_string();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("dem.asc");
        std::fs::write(&path, text).unwrap();
        let from_file = read(&path).unwrap_err().to_string();
        let full = path.to_str().unwrap();
        assert_eq!(from_file.replace(full, "dem.asc"), from_text);
        from_text
    }

    #[test]
    fn reading_a_file_line_by_line_equals_parsing_its_text() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("dem.asc");
        for text in [
            "ncols 3\nnrows 2\nxllcorner 1\nyllcorner 2\ncellsize 2\nNODATA_value -1\n1 -1 3\n4 5 6\n",
            "ncols 2\r\nnrows 2\r\n\r\nxllcenter 1\r\nyllcenter 2\r\ncellsize 2\r\n1 2\r\n\r\n3 4",
        ] {
            std::fs::write(&path, text).unwrap();
            assert_eq!(read(&path).unwrap(), parse(text, p()).unwrap(), "{text:?}");
        }
    }

    const HEAD: &str = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";

    #[test]
    fn strict_errors_name_file_line_and_cell() {
        let e = err(&format!("{HEAD}1 2\n3 x\n"));
        assert!(
            e.contains("dem.asc, line 7 (row 1, column 1)") && e.contains("`x`"),
            "{e}"
        );
        let e = err(&format!("{HEAD}1 NaN\n3 4\n"));
        assert!(
            e.contains("line 6 (row 0, column 1)") && e.contains("NaN"),
            "{e}"
        );
        let e = err(&format!("{HEAD}1 2\n3 inf\n"));
        assert!(e.contains("finite"), "{e}");
        let e = err(&format!("{HEAD}1 2\n3\n"));
        assert!(
            e.contains("found 3 values, expected") && e.contains("line 7"),
            "{e}"
        );
        let e = err(&format!("{HEAD}1 2\n3 4\n5\n"));
        assert!(e.contains("line 8") && e.contains("more values"), "{e}");
        let e = err("ncols 2\nnrows 2\nxllcorner 0\ncellsize 1\n1 2 3 4\n");
        assert!(e.contains("missing header key `yllcorner`"), "{e}");
        let e = err("ncols 2\nncols 2\n");
        assert!(e.contains("line 2") && e.contains("twice"), "{e}");
        let e = err("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nfoo 3\n");
        assert!(e.contains("unknown header key `foo`"), "{e}");
        let e = err("ncols 4294967296\nnrows 4294967297\nxllcorner 0\nyllcorner 0\ncellsize 1\n");
        assert!(e.contains("larger than"), "{e}");
        let e = err("ncols 100000000\nnrows 10\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n");
        assert!(e.contains("found 2 values"), "{e}");
        let e = err("ncols 2.5\n");
        assert!(e.contains("whole number"), "{e}");
        let e = err("ncols 0\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n");
        assert!(e.contains("empty grid"), "{e}");
        let e = err("");
        assert!(e.contains("missing header key `ncols`"), "{e}");
        let e = err("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize -1\n1 2 3 4\n");
        assert!(e.contains("positive"), "{e}");
    }

    #[test]
    fn round_trip_is_exact_with_prj() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("g.asc");
        let geom = GridGeometry {
            ncols: 5,
            nrows: 4,
            x_min_m: 912_345.25,
            y_min_m: 6_456_789.5,
            cell_size_m: 2.5,
        };
        let mut grid = Grid::from_fn(geom, |r, c| {
            Some(1234.5678901234 + r as f64 * 0.1 - c as f64 / 3.0)
        })
        .with_crs(Some(Crs::from_epsg(2154)));
        grid.set_nodata(2, 3);
        write(&path, &grid).unwrap();
        assert!(prj_path(&path).is_file());
        let back = read(&path).unwrap();
        assert_eq!(back.geometry(), grid.geometry());
        assert_eq!(back.mask(), grid.mask());
        assert_eq!(back.values(), grid.values());
        assert_eq!(back.crs().and_then(|c| c.epsg), Some(2154));
    }

    #[test]
    fn integer_grids_are_written_as_integers() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("n.asc");
        let geom = GridGeometry {
            ncols: 4,
            nrows: 1,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        let mut grid = Grid::from_values(geom, vec![3.0, 2.5, -0.4, 1e10]).unwrap();
        grid.set_nodata(0, 3);
        write_rows_as(&path, &grid, SampleType::I32).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        // 2.5 rounds half away from zero, −0.4 to 0 (not "-0"), nodata as −9999
        assert!(
            text.ends_with("NODATA_value -9999\n3 3 0 -9999\n"),
            "{text}"
        );
        // floats are written as they are, integers without `.0` in either case
        write_rows_as(&path, &grid, SampleType::F32).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.ends_with("\n3 2.5 -0.4 -9999\n"), "{text}");
        grid.set(0, 3, 3e9);
        let err = write_rows_as(&path, &grid, SampleType::I32).unwrap_err();
        assert!(
            err.to_string()
                .contains("(row 0, column 3) = 3000000000.0 does not fit I32"),
            "{err}"
        );
    }

    #[test]
    fn missing_file_is_an_io_error_naming_it() {
        let e = read(Path::new("/nonexistent/dem.asc"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/dem.asc"), "{e}");
    }
}

//! Vector layers as scenario inputs: per-cell parameters from polygon attributes, release
//! areas from polygons, stems from points, nets from lines — each checked against the DEM's
//! CRS and extent, and described for `rockfall check`.

use super::burn::{line_cells, polygon_cells_in};
use super::{Envelope, Feature, Geometry, Layer, Value, VectorError, Xy, read_layer_in, same_crs};
use rockfall_forest::Stem;
use rockfall_raster::{Crs, Grid, GridGeometry, Window};
use std::path::Path;

/// The DEM's grid and CRS, which every vector is checked against and burnt onto.
#[derive(Debug, Clone)]
pub struct Frame {
    /// The DEM's grid.
    pub geometry: GridGeometry,
    /// The DEM's CRS, if known.
    pub crs: Option<Crs>,
    /// The cells burnt: a tile's window of the grid (its grids hold only it), or the whole
    /// grid (`None`). A window burns each of its cells exactly as the whole grid does. A layer
    /// that covers no cell of a window is no error (it may cover other tiles); a run of the
    /// whole region or `rockfall check` makes that check.
    pub window: Option<Window>,
}

impl Frame {
    /// The cells burnt.
    pub fn cells(&self) -> Window {
        self.window.unwrap_or(Window::whole(&self.geometry))
    }

    /// The rectangle of a tile's window; `None` on the whole grid.
    pub fn envelope(&self) -> Option<Envelope> {
        (self.window).map(|w| Envelope::of_window(&self.geometry, &w))
    }

    /// True when a point is to be kept: on a tile's frame, when it lies in the window's
    /// rectangle (what its rocks can meet: `rockfall_sim::tile::margin_cells`); on the whole
    /// grid, always.
    pub fn keeps(&self, x_m: f64, y_m: f64) -> bool {
        (self.window).is_none_or(|w| w.holds_point(&self.geometry, x_m, y_m))
    }

    /// A grid of the burnt cells' `values` (row-major over [`Frame::cells`]), placed on the
    /// whole grid.
    fn grid(&self, values: Vec<Option<f64>>) -> Option<Grid<f64>> {
        let (g, w) = (self.geometry, self.cells());
        let part = GridGeometry {
            ncols: w.ncols,
            nrows: w.nrows,
            ..g
        };
        let grid = Grid::from_options(part, values)?;
        let grid = match self.window {
            None => grid,
            Some(w) => grid.placed(g, w)?,
        };
        Some(grid.with_crs(self.crs.clone()))
    }
}

/// What a per-cell parameter takes in the cells no polygon holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outside {
    /// The key's default.
    Default(f64),
    /// No value (nodata): for stand keys, no stand there.
    Nodata,
    /// Nothing: an error, for keys without a default.
    Error,
}

/// Reads a layer and checks its CRS against the DEM's: different known CRSs are an error
/// naming both; where either is unknown the layer is taken as it is and `notes` says so.
pub fn open(
    path: &Path,
    layer: Option<&str>,
    frame: &Frame,
    notes: &mut Vec<String>,
) -> Result<Layer, VectorError> {
    checked(read_layer_in(path, layer, None)?, frame, notes)
}

/// [`open`] for a layer whose features matter only where they meet a tile's window — a per-cell
/// parameter's polygons ([`field_grid`]: the others burn no cell of the window) and tree points
/// ([`stems`]: a tile's rocks meet no stem outside it): on a tile's frame only the features
/// whose bounding box meets the window are read, so a tile of a national run does not hold a
/// national layer; on the whole grid, every feature.
pub fn open_windowed(
    path: &Path,
    layer: Option<&str>,
    frame: &Frame,
    notes: &mut Vec<String>,
) -> Result<Layer, VectorError> {
    checked(read_layer_in(path, layer, frame.envelope())?, frame, notes)
}

/// Checks a layer's CRS against the DEM's (see [`open`]).
fn checked(l: Layer, frame: &Frame, notes: &mut Vec<String>) -> Result<Layer, VectorError> {
    match (&l.crs, &frame.crs) {
        (Some(a), Some(b)) if !same_crs(a, b) => {
            return Err(VectorError::layer(
                &l,
                format!(
                    "its CRS {} is not the DEM's {}: reproject the layer (e.g. `ogr2ogr -t_srs`)",
                    a.describe(),
                    b.describe()
                ),
            ));
        }
        (Some(_), Some(_)) => {}
        (None, _) => notes.push(format!(
            "{} layer `{}`: no CRS given; taken to be the DEM's",
            l.path.display(),
            l.name
        )),
        (Some(_), None) => notes.push(format!(
            "{} layer `{}`: the DEM has no CRS; the layer's coordinates are taken as the DEM's",
            l.path.display(),
            l.name
        )),
    }
    Ok(l)
}

/// The error of a feature whose geometry is not the kind `needed`.
fn wrong_kind(layer: &Layer, f: &Feature, needed: &str) -> VectorError {
    VectorError::feature(
        layer,
        f.id,
        format!("{} where {needed} are needed", f.geometry.kind()),
    )
}

fn polygons<'a>(layer: &Layer, f: &'a Feature) -> Result<Vec<&'a [Xy]>, VectorError> {
    match &f.geometry {
        Geometry::Polygons(ps) => Ok(ps.iter().flatten().map(Vec::as_slice).collect()),
        Geometry::Empty => Ok(Vec::new()),
        _ => Err(wrong_kind(layer, f, "polygons")),
    }
}

fn number(layer: &Layer, f: &Feature, field: &str) -> Result<Option<f64>, VectorError> {
    match f.attribute(field) {
        None => Err(VectorError::feature(
            layer,
            f.id,
            format!("no field `{field}`"),
        )),
        Some(Value::Null) => Ok(None),
        Some(Value::Num(v)) if v.is_finite() => Ok(Some(*v)),
        Some(Value::Num(v)) => Err(VectorError::feature(
            layer,
            f.id,
            format!("field `{field}` is {v}, not a finite number"),
        )),
        Some(Value::Text(t)) => match t.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Some(v)),
            _ => Err(VectorError::feature(
                layer,
                f.id,
                format!("field `{field}` holds `{t}`, not a number"),
            )),
        },
    }
}

fn no_overlap(layer: &Layer, frame: &Frame) -> VectorError {
    let g = &frame.geometry;
    VectorError::layer(
        layer,
        format!(
            "no feature covers a cell of the DEM (x {}–{} m, y {}–{} m)",
            g.x_min_m,
            g.x_max_m(),
            g.y_min_m,
            g.y_max_m()
        ),
    )
}

/// A per-cell parameter from the attribute `field` of a polygon layer: each cell takes the
/// value of the polygon holding its centre; where polygons overlap the one later in the
/// layer wins (GDAL burns features in layer order); a feature whose field is null burns
/// nothing. Returns the raster and the number of cells the polygons cover.
pub fn field_grid(
    layer: &Layer,
    field: &str,
    frame: &Frame,
    outside: Outside,
    key: &str,
) -> Result<(Grid<f64>, usize), VectorError> {
    let (g, w) = (frame.geometry, frame.cells());
    let mut cells: Vec<Option<f64>> = vec![None; w.ncols * w.nrows];
    let mut covered = 0;
    for f in &layer.features {
        let rings = polygons(layer, f)?;
        let Some(v) = number(layer, f, field)? else {
            continue;
        };
        for c in polygon_cells_in(&g, &rings, &w) {
            let (row, col) = g.row_col(c);
            let k = (row - w.row0) * w.ncols + (col - w.col0);
            covered += usize::from(cells[k].is_none());
            cells[k] = Some(v);
        }
    }
    if covered == 0 && frame.window.is_none() {
        return Err(no_overlap(layer, frame));
    }
    let missing = (w.ncols * w.nrows) - covered;
    match outside {
        Outside::Default(d) => cells.iter_mut().for_each(|c| *c = c.or(Some(d))),
        Outside::Nodata => {}
        Outside::Error if missing > 0 => {
            let first = cells.iter().position(Option::is_none).unwrap_or(0);
            let (row, col) = (
                w.row0 + first / w.ncols.max(1),
                w.col0 + first % w.ncols.max(1),
            );
            return Err(VectorError::layer(
                layer,
                format!(
                    "`{key}` has no default, but {missing} cells lie outside every polygon with a `{field}` (the first at row {row}, column {col})"
                ),
            ));
        }
        Outside::Error => {}
    }
    let grid =
        (frame.grid(cells)).ok_or_else(|| VectorError::layer(layer, "internal: grid size"))?;
    Ok((grid, covered))
}

/// Release cells: the cells whose centres the polygons hold (of the frame's window),
/// ascending.
pub fn release_cells(layer: &Layer, frame: &Frame) -> Result<Vec<usize>, VectorError> {
    let mut cells = Vec::new();
    let w = frame.cells();
    for f in &layer.features {
        cells.extend(polygon_cells_in(&frame.geometry, &polygons(layer, f)?, &w));
    }
    cells.sort_unstable();
    cells.dedup();
    if cells.is_empty() && frame.window.is_none() {
        return Err(no_overlap(layer, frame));
    }
    Ok(cells)
}

/// Stems from a point layer: `dbh_cm` (required), `species` and `height_m` (optional). On a
/// tile's frame, the stems in its window ([`Frame::keeps`]), none an error only on the whole
/// grid.
pub fn stems(layer: &Layer, frame: &Frame) -> Result<Vec<Stem>, VectorError> {
    let mut stems = Vec::new();
    for f in &layer.features {
        let points = match &f.geometry {
            Geometry::Points(p) => p,
            Geometry::Empty => continue,
            _ => return Err(wrong_kind(layer, f, "tree points")),
        };
        let dbh = number(layer, f, "dbh_cm")?
            .ok_or_else(|| VectorError::feature(layer, f.id, "`dbh_cm` is null"))?;
        let species = match f.attribute("species") {
            Some(Value::Text(t)) if !t.trim().is_empty() => Some(t.trim().to_string()),
            Some(Value::Num(v)) => Some(v.to_string()),
            _ => None,
        };
        let height = match f.attribute("height_m") {
            None => None,
            Some(_) => number(layer, f, "height_m")?,
        };
        for p in points {
            let stem = crate::trees::make_stem(p[0], p[1], dbh, species.as_deref(), height)
                .map_err(|m| VectorError::feature(layer, f.id, m))?;
            if frame.keeps(stem.x_m, stem.y_m) {
                stems.push(stem);
            }
        }
    }
    if frame.window.is_some() {
        return Ok(stems);
    }
    let inside = stems
        .iter()
        .filter(|s| frame.geometry.contains(s.x_m, s.y_m))
        .count();
    if inside == 0 {
        return Err(no_overlap(layer, frame));
    }
    Ok(stems)
}

/// A net given as a line.
#[derive(Debug, Clone, PartialEq)]
pub struct NetLine {
    /// Net number (the `net_id` or `id` attribute, else the feature's position from 1).
    pub id: u32,
    /// Its vertices (x, y), m; every part of a multi-line in turn.
    pub points_m: Vec<Vec<Xy>>,
    /// Energy the net stops, kJ.
    pub energy_kj: f64,
    /// Net height, m.
    pub height_m: f64,
    /// Cells the line touches.
    pub cells: Vec<usize>,
}

/// Nets from a line layer with `energy_kj` and `height_m` attributes: every cell a line
/// touches holds its net (a later line wins a shared cell).
pub fn net_lines(layer: &Layer, frame: &Frame) -> Result<Vec<NetLine>, VectorError> {
    let mut nets = Vec::new();
    for (k, f) in layer.features.iter().enumerate() {
        let lines = match &f.geometry {
            Geometry::Lines(l) => l,
            Geometry::Empty => continue,
            _ => return Err(wrong_kind(layer, f, "net lines")),
        };
        let need = |name: &str| {
            number(layer, f, name)?
                .filter(|v| *v > 0.0)
                .ok_or_else(|| VectorError::feature(layer, f.id, format!("`{name}` must be > 0")))
        };
        let (energy_kj, height_m) = (need("energy_kj")?, need("height_m")?);
        let id_key = ["net_id", "id"]
            .into_iter()
            .find(|k| f.attribute(k).is_some());
        let id = match id_key.map(|key| number(layer, f, key)).transpose()? {
            None => k as u32 + 1,
            Some(Some(v)) if v >= 1.0 && v.fract() == 0.0 && v <= f64::from(u32::MAX) => v as u32,
            Some(_) => {
                return Err(VectorError::feature(
                    layer,
                    f.id,
                    "the net id must be a whole number ≥ 1",
                ));
            }
        };
        let mut cells: Vec<usize> = (lines.iter())
            .flat_map(|l| line_cells(&frame.geometry, l))
            .collect();
        cells.sort_unstable();
        cells.dedup();
        nets.push(NetLine {
            id,
            points_m: lines.clone(),
            energy_kj,
            height_m,
            cells,
        });
    }
    if nets.iter().all(|n| n.cells.is_empty()) {
        return Err(no_overlap(layer, frame));
    }
    Ok(nets)
}

/// The Rockyfor3D net rasters (`net_number`, `net_energy` kJ, `net_height` m) of net lines
/// over the frame's cells; 0 where no net. `None` when the frame's window does not fit its
/// grid.
pub fn net_grids(nets: &[NetLine], frame: &Frame) -> Option<[Grid<f64>; 3]> {
    let (g, w) = (frame.geometry, frame.cells());
    let zeros = || frame.grid(vec![Some(0.0); w.ncols * w.nrows]);
    let mut out = [zeros()?, zeros()?, zeros()?];
    for n in nets {
        for &c in &n.cells {
            // cells outside the window are not held: `set` leaves them
            let (row, col) = g.row_col(c);
            out[0].set(row, col, f64::from(n.id));
            out[1].set(row, col, n.energy_kj);
            out[2].set(row, col, n.height_m);
        }
    }
    Some(out)
}

/// One line for `rockfall check`: the file, layer, features read and what they gave —
/// `count` of `what` (e.g. "cells covered", "stems").
pub fn describe(key: &str, layer: &Layer, count: usize, what: &str) -> String {
    format!(
        "vector {key}: {} layer `{}`: {} features{} ({}), {count} {what}",
        layer.path.display(),
        layer.name,
        layer.features.len(),
        match layer.within {
            Some(_) => " meeting the tile's window",
            None => "",
        },
        kinds(layer)
    )
}

fn kinds(layer: &Layer) -> String {
    let mut k: Vec<&str> = layer.features.iter().map(|f| f.geometry.kind()).collect();
    k.sort_unstable();
    k.dedup();
    k.join(", ")
}

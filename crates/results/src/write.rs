//! Writing results into an output folder, every file atomically.

use std::io::Write;
use std::path::{Path, PathBuf};

use rockfall_raster::{RasterError, Rows, SampleType, atomic, write_rows};
use serde::Serialize;

use crate::{CrossingRecord, Results, RockRecord, TrajectoryRow};

/// Header of `trajectories.csv` (a contract, see `product.md`).
pub const TRAJECTORY_HEADER: &str =
    "rock_id,t_s,x_m,y_m,z_m,vx_ms,vy_ms,vz_ms,wx_rads,wy_rads,wz_rads,e_trans_j,e_rot_j,event";

/// Header of `rocks.csv`: one row per rock, written when [`crate::Layout::rock_ends`].
pub const ROCKS_HEADER: &str = "rock_id,source_cell,x0_m,y0_m,z0_m,outcome,x_m,y_m,runout_m,\
max_velocity_ms,max_jump_height_m,tree_impacts,stems_broken,rebounds,time_s,volume_m3,mass_kg,\
flight_s,rolling_s,sliding_face_s,sliding_edge_s,slow_s";

/// Header of `screen_crossings.csv`: one row per crossing of a screen, energy in kJ, the
/// passing height (vertical, of the rock centre above the ground) in m.
pub const CROSSINGS_HEADER: &str =
    "rock_id,screen,x_m,y_m,velocity_ms,energy_kj,passing_height_m,mass_kg";

/// What can go wrong writing results. Every variant names the file or folder.
#[derive(Debug, thiserror::Error)]
pub enum ResultsError {
    /// The output folder could not be created.
    #[error("{path}: cannot create the output folder: {source}")]
    CreateDir {
        /// The folder.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// A file could not be written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// A raster could not be written (the error names the file).
    #[error(transparent)]
    Raster(#[from] RasterError),
    /// A tally file streamed into the results could not be read (the error names it).
    #[error(transparent)]
    Tally(#[from] crate::TallyFileError),
}

impl From<(PathBuf, std::io::Error)> for ResultsError {
    fn from((path, source): (PathBuf, std::io::Error)) -> Self {
        ResultsError::Io { path, source }
    }
}

/// Creates `dir` (and its parents) when missing.
pub(crate) fn create_dir(dir: &Path) -> Result<(), ResultsError> {
    std::fs::create_dir_all(dir).map_err(|source| ResultsError::CreateDir {
        path: dir.to_path_buf(),
        source,
    })
}

/// Writes `grid` (a [`rockfall_raster::Grid`] or rows computed on the fly) as `<name>.tif` (and `<name>.asc` +
/// `.prj` when `ascii`) into `dir`, row by row; pushes the paths written.
pub(crate) fn write_raster(
    dir: &Path,
    name: &str,
    grid: &impl Rows,
    sample: SampleType,
    ascii: bool,
    written: &mut Vec<PathBuf>,
) -> Result<(), ResultsError> {
    let tif = dir.join(format!("{name}.tif"));
    write_rows(&tif, grid, sample)?;
    written.push(tif);
    if ascii {
        let asc = dir.join(format!("{name}.asc"));
        write_rows(&asc, grid, sample)?;
        written.push(asc.clone());
        let prj = rockfall_raster::ascii_grid::prj_path(&asc);
        if grid.crs().and_then(|c| c.wkt_for_prj()).is_some() {
            written.push(prj);
        }
    }
    Ok(())
}

/// Writes `value` as JSON, pretty-printed with a final newline, to `path` atomically. The value
/// goes through a [`serde_json::Value`] first, so the keys of every object come out sorted
/// (serde_json's maps are ordered by key), whatever the order of a struct's fields.
pub fn write_json(path: &Path, value: &impl Serialize) -> Result<(), ResultsError> {
    let json_error = |e| ResultsError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e),
    };
    let value = serde_json::to_value(value).map_err(json_error)?;
    let mut text = serde_json::to_string_pretty(&value).map_err(json_error)?;
    text.push('\n');
    atomic::write_bytes_atomic(path, text.as_bytes()).map_err(ResultsError::from)
}

/// Writes a CSV file atomically: `header`, then one line per row by `line`.
fn write_csv<T>(
    path: &Path,
    header: &str,
    rows: &[T],
    line: impl Fn(&mut dyn Write, &T) -> std::io::Result<()>,
) -> Result<(), ResultsError> {
    atomic::write_atomic(path, |w| {
        let io = |e| ResultsError::Io {
            path: path.to_path_buf(),
            source: e,
        };
        writeln!(w, "{header}").map_err(io)?;
        for r in rows {
            line(w, r).map_err(io)?;
        }
        Ok(())
    })
}

/// Writes `trajectories.csv`: the header, then one line per row; numbers in the shortest form
/// that reads back to the same `f64`.
pub(crate) fn write_trajectories(path: &Path, rows: &[TrajectoryRow]) -> Result<(), ResultsError> {
    write_csv(path, TRAJECTORY_HEADER, rows, |w, r| {
        write!(w, "{}", r.rock_id)?;
        for v in r.values() {
            write!(w, ",{v}")?;
        }
        writeln!(w, ",{}", r.event.name())
    })
}

/// Writes `rocks.csv`: the header, then one line per record; numbers in the shortest form
/// that reads back to the same `f64`, the outcome by [`crate::Outcome::name`].
pub(crate) fn write_rocks(path: &Path, records: &[RockRecord]) -> Result<(), ResultsError> {
    write_csv(path, ROCKS_HEADER, records, |w, r| {
        let [x0, y0, z0] = r.start_m;
        let e = &r.end;
        writeln!(
            w,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.rock_id,
            r.source_cell,
            x0,
            y0,
            z0,
            e.outcome.name(),
            e.x_m,
            e.y_m,
            e.runout_m,
            e.max_velocity_ms,
            e.max_jump_height_m,
            e.tree_impacts,
            e.stems_broken,
            e.rebounds,
            e.time_s,
            r.volume_m3,
            r.mass_kg,
            motion_fields(&e.motion)
        )
    })
}

/// The motion columns of `rocks.csv`: the five times, or five empty fields when the engine
/// does not classify motion (all zero: the lumped engine).
fn motion_fields(m: &crate::Motion) -> String {
    let t = m.as_array();
    if t.iter().all(|&v| v == 0.0) {
        ",,,,".into()
    } else {
        t.map(|v| v.to_string()).join(",")
    }
}

/// Writes `screen_crossings.csv`: the header [`CROSSINGS_HEADER`], then one line per record,
/// the screen by name; numbers in the shortest form that reads back to the same `f64`.
pub(crate) fn write_crossings(
    path: &Path,
    records: &[CrossingRecord],
    screens: &[rockfall_scenario::Screen],
) -> Result<(), ResultsError> {
    write_csv(path, CROSSINGS_HEADER, records, |w, r| {
        let c = &r.crossing;
        let name = screens.get(r.screen).map_or("", |s| s.name.as_str());
        writeln!(
            w,
            "{},{},{},{},{},{},{},{}",
            r.rock_id,
            csv_field(name),
            c.x_m,
            c.y_m,
            c.velocity_ms,
            c.energy_j / 1e3,
            c.jump_height_m,
            r.mass_kg
        )
    })
}

/// `s` as a CSV field: quoted (quotes doubled) when it holds a comma, a quote or a line break.
fn csv_field(s: &str) -> std::borrow::Cow<'_, str> {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\"")).into()
    } else {
        s.into()
    }
}

impl Results {
    /// Writes every raster as `<name>.tif` (GeoTIFF with the layout's CRS; counts as 32-bit
    /// integers, others as 32-bit floats with nodata −9999) and, when `ascii`, also
    /// `<name>.asc` (+ `.prj` when the CRS is known), plus `summary.json` and
    /// `trajectories.csv` (header only when no trajectory was recorded) and, when the layout
    /// kept per-rock records ([`crate::Layout::rock_ends`]), `rocks.csv` (one row per rock,
    /// by rock id, columns [`ROCKS_HEADER`]), into `out_dir` (created when missing). Every file is written atomically: a temporary name, then a
    /// rename over any earlier file. Returns the paths written.
    pub fn write(&self, out_dir: &Path, ascii: bool) -> Result<Vec<PathBuf>, ResultsError> {
        create_dir(out_dir)?;
        let mut written = Vec::new();
        for (name, kind) in self.kinds() {
            let sample = self.sample_type(kind);
            write_raster(
                out_dir,
                &name,
                &self.rows(kind),
                sample,
                ascii,
                &mut written,
            )?;
        }
        self.write_tables(out_dir, &mut written)?;
        Ok(written)
    }

    /// Writes `summary.json`, `trajectories.csv` and, as the layout asks, `rocks.csv` and
    /// `screen_crossings.csv` into `out_dir`; pushes the paths written.
    pub(crate) fn write_tables(
        &self,
        out_dir: &Path,
        written: &mut Vec<PathBuf>,
    ) -> Result<(), ResultsError> {
        let summary = out_dir.join("summary.json");
        write_json(&summary, &self.summary())?;
        written.push(summary);
        let csv = out_dir.join("trajectories.csv");
        write_trajectories(&csv, &self.rows)?;
        written.push(csv);
        if self.layout.rock_ends {
            let rocks = out_dir.join("rocks.csv");
            write_rocks(&rocks, &self.rock_records)?;
            written.push(rocks);
        }
        if self.layout.screen_crossings {
            let path = out_dir.join("screen_crossings.csv");
            write_crossings(&path, &self.crossing_records, &self.layout.screens)?;
            written.push(path);
        }
        Ok(())
    }
}

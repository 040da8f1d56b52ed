//! The merged outcome of a run: rasters, summary and trajectories.

use rockfall_raster::{Crs, Grid, GridGeometry, RasterView, Rows, SampleType};

use crate::cells::CellStats;
use crate::convergence::ConvergenceSummary;
use crate::{CrossingRecord, Layout, Parameters, RockRecord, Tally, TrajectoryRow};

/// Nodata marker written into the float rasters.
pub(crate) const NODATA: f64 = -9999.0;

/// What the run was, beside what its tally holds.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct RunInfo {
    /// Engine name: `"lumped"` or `"rigid"`.
    pub engine: String,
    /// Scenario name.
    pub scenario: String,
    /// Master seed.
    pub seed: u64,
    /// Worker threads used.
    pub threads: usize,
    /// Wall-clock time of the simulation, s.
    pub wall_time_s: f64,
    /// Engine parameters, written under the key `parameters` of `summary.json`.
    pub parameters: Parameters,
}

/// One raster of [`Results`]: what it shows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Kind {
    Passages,
    Reach,
    Deposited,
    Sources,
    EnergyMean,
    EnergyPercentile(f64),
    HeightMean,
    /// A percentile (0–100) of the passing heights of the cell's visits.
    HeightPercentile(f64),
    /// Mean + [`Z_95`] sample standard deviations of the visit energies (`E_95CI`).
    EnergyCi95,
    /// Mean + [`Z_95`] sample standard deviations of the passing heights (`Ph_95CI`).
    HeightCi95,
    /// Largest energy-line angle of the visits (`EL_angles`).
    EnergyLineAngle,
    VelocityMax,
    TreeImpacts,
    TreeHeightMax,
    StemsBroken,
    /// Distinct rocks that passed with more energy than the layout's `k`-th threshold.
    RocksAbove(usize),
}

/// The one-sided 95 % quantile of the standard normal distribution: `E_95CI` and `Ph_95CI`
/// are the mean plus this many standard deviations, the value below which 95 % of the visits
/// lie if they are normally distributed (see docs/guide/outputs.md, "Rockyfor3D output parity").
pub(crate) const Z_95: f64 = 1.644_853_626_951_472_2;

/// Mean + [`Z_95`] standard deviations; the mean alone for a single value (no spread
/// measured).
fn ci95(mean: Option<f64>, sd: Option<f64>) -> Option<f64> {
    Some(mean? + Z_95 * sd.unwrap_or(0.0))
}

impl Kind {
    /// Counts are written as 32-bit integers and are 0 (never nodata) where nothing happened.
    pub(crate) fn is_count(self) -> bool {
        matches!(
            self,
            Kind::Passages
                | Kind::Deposited
                | Kind::Sources
                | Kind::TreeImpacts
                | Kind::StemsBroken
                | Kind::RocksAbove(_)
        )
    }

    /// Rasters with a value in every cell: the counts, and `Reach_probability` (0 where no
    /// rock passed). The others are nodata where nothing happened.
    pub(crate) fn always_valid(self) -> bool {
        self.is_count() || self == Kind::Reach
    }
}

/// The result of a run: the merged tally turned into rasters (named as Rockyfor3D users know
/// them), `summary.json`, `trajectories.csv` and, when [`Layout::rock_ends`], `rocks.csv`.
///
/// Everything but `threads`, `wall_time_s` and `trajectories_per_s` of the summary is a pure
/// function of the merged tally, hence identical whatever the thread count.
#[derive(Debug, Clone)]
pub struct Results {
    pub(crate) layout: Layout,
    pub(crate) tally: Tally,
    pub(crate) info: RunInfo,
    pub(crate) rows: Vec<TrajectoryRow>,
    /// One record per rock, sorted by rock id (empty unless `layout.rock_ends`).
    pub(crate) rock_records: Vec<RockRecord>,
    /// One record per screen crossing, sorted by (rock id, sequence) (empty unless
    /// `layout.screen_crossings`).
    pub(crate) crossing_records: Vec<CrossingRecord>,
    /// How a convergence-driven run ended (`summary.json` `convergence`).
    pub(crate) convergence: Option<ConvergenceSummary>,
    /// Cells reached and the bytes of their statistics, counted as they streamed past
    /// ([`Results::write_streamed`]) when the tally holds no cells.
    pub(crate) streamed: Option<(u64, usize)>,
}

/// `Nr_rocks_above_<e>kJ` raster name: `Nr_rocks_above_30kJ` for 30 kJ.
pub fn rocks_above_name(e_kj: f64) -> String {
    format!("Nr_rocks_above_{e_kj}kJ")
}

/// `E_<p>` raster name: `E_95` for 95, `E_99.5` for 99.5.
pub(crate) fn percentile_name(prefix: &str, p: f64) -> String {
    format!("{prefix}_{p}")
}

impl Results {
    /// The results of a run on `layout` whose merged tally is `tally`. Trajectory rows are
    /// sorted by rock id, then in the order they were recorded; rock records by rock id, so
    /// neither depends on the thread count or the merge order.
    pub fn new(layout: &Layout, mut tally: Tally, info: RunInfo) -> Results {
        let mut rows = std::mem::take(&mut tally.rows);
        rows.sort_by_key(|&(rock, seq, _)| (rock, seq));
        let mut rock_records = std::mem::take(&mut tally.rock_records);
        rock_records.sort_by_key(|r| r.rock_id);
        let mut crossing_records = std::mem::take(&mut tally.crossing_records);
        crossing_records.sort_by_key(|c| (c.rock_id, c.seq));
        Results {
            layout: layout.clone(),
            tally,
            info,
            rows: rows.into_iter().map(|(_, _, r)| r).collect(),
            rock_records,
            crossing_records,
            convergence: None,
            streamed: None,
        }
    }

    /// The same results, recorded as the end of a convergence-driven run.
    pub fn with_convergence(mut self, convergence: ConvergenceSummary) -> Results {
        self.convergence = Some(convergence);
        self
    }

    /// What the run was.
    pub fn info(&self) -> &RunInfo {
        &self.info
    }

    /// Rocks simulated (ended).
    pub fn rocks(&self) -> u64 {
        self.tally.rocks()
    }

    /// The recorded trajectory rows, sorted by rock id, then time of recording.
    pub fn trajectories(&self) -> &[TrajectoryRow] {
        &self.rows
    }

    /// One record per rock (release cell and position, outcome, end position, maxima), sorted
    /// by rock id; empty unless the layout kept them ([`Layout::rock_ends`]).
    pub fn rock_records(&self) -> &[RockRecord] {
        &self.rock_records
    }

    /// One record per screen crossing, sorted by rock id and then in the order the rock
    /// crossed; empty unless the layout kept them ([`Layout::screen_crossings`]).
    pub fn crossing_records(&self) -> &[CrossingRecord] {
        &self.crossing_records
    }

    /// The energy percentiles written as `E_<p>` rasters: the layout's valid ones (0 ..= 100)
    /// and 95, ascending, without duplicates.
    pub(crate) fn energy_percentiles(&self) -> Vec<f64> {
        let mut ps: Vec<f64> = (self.layout.percentiles.iter().copied())
            .filter(|p| (0.0..=100.0).contains(p))
            .chain([95.0])
            .collect();
        ps.sort_by(f64::total_cmp);
        ps.dedup_by(|a, b| percentile_name("E", *a) == percentile_name("E", *b));
        ps
    }

    /// Every raster, in writing order.
    pub(crate) fn kinds(&self) -> Vec<(String, Kind)> {
        let mut v = vec![
            ("Nr_passages".to_string(), Kind::Passages),
            ("Reach_probability".into(), Kind::Reach),
            ("Nr_deposited".into(), Kind::Deposited),
            ("Nr_sourcecells".into(), Kind::Sources),
            ("E_mean".into(), Kind::EnergyMean),
        ];
        for p in self.energy_percentiles() {
            v.push((percentile_name("E", p), Kind::EnergyPercentile(p)));
        }
        v.extend([
            ("Ph_mean".into(), Kind::HeightMean),
            ("Ph_50".into(), Kind::HeightPercentile(50.0)),
            ("Ph_90".into(), Kind::HeightPercentile(90.0)),
            ("Ph_95".into(), Kind::HeightPercentile(95.0)),
            ("E_95CI".into(), Kind::EnergyCi95),
            ("Ph_95CI".into(), Kind::HeightCi95),
            ("EL_angles".into(), Kind::EnergyLineAngle),
            ("V_max".into(), Kind::VelocityMax),
            ("Nr_tree_impacts".into(), Kind::TreeImpacts),
            ("Tree_impact_height_max".into(), Kind::TreeHeightMax),
            ("Nr_stems_broken".into(), Kind::StemsBroken),
        ]);
        let counted = self.tally.cells.thresholds().len();
        for (k, &e) in self.layout.energy_thresholds_kj[..counted]
            .iter()
            .enumerate()
        {
            v.push((rocks_above_name(e), Kind::RocksAbove(k)));
        }
        v
    }

    /// Names of every raster, in writing order: `Nr_passages`, `Reach_probability`,
    /// `Nr_deposited`, `Nr_sourcecells`, `E_mean`, `E_<p>` (ascending, `E_95` always),
    /// `Ph_mean`, `Ph_50`, `Ph_90`, `Ph_95`, `E_95CI`, `Ph_95CI`, `EL_angles`, `V_max`,
    /// `Nr_tree_impacts`, `Tree_impact_height_max`, `Nr_stems_broken`, then
    /// `Nr_rocks_above_<e>kJ` per energy threshold ([`Layout::energy_thresholds_kj`]).
    pub fn raster_names(&self) -> Vec<String> {
        self.kinds().into_iter().map(|(n, _)| n).collect()
    }

    /// The raster called `name` (a Rockyfor3D name, see [`Results::raster_names`]), on the
    /// layout's grid and with its CRS; `None` for an unknown name.
    ///
    /// Units: `Reach_probability` % of the rocks; `E_mean`, `E_<p>` kJ (over visits);
    /// `Ph_mean`, `Ph_50`, `Ph_90`, `Ph_95` (percentiles of the passing heights of the cell's
    /// visits, as Rockyfor3D's `Ph_95` and its median and 90 % companions),
    /// `Tree_impact_height_max` m; `E_95CI` kJ and `Ph_95CI` m: mean + 1.645 sample standard
    /// deviations of the cell's visits (the mean for a single visit); `EL_angles` degrees:
    /// the largest energy-line angle of a visit, from the DEM surface at the centre of the
    /// rock's release cell to the centre of the cell (none within half a cell of the release
    /// point); `V_max` m/s; the others are counts
    /// (0 where nothing happened); `Nr_rocks_above_<e>kJ` counts the distinct rocks whose
    /// kinetic energy in the cell exceeded e kJ. The non-count rasters are nodata where no rock passed (no
    /// tree was hit, for `Tree_impact_height_max`). Percentiles come from log histograms:
    /// within 7.5 % of the exact nearest-rank value (see [`crate::PERCENTILE_RELATIVE_ERROR`]).
    pub fn raster(&self, name: &str) -> Option<Grid<f64>> {
        let (_, kind) = self.kinds().into_iter().find(|(n, _)| n == name)?;
        Some(self.grid(kind))
    }

    /// The raster called `name`, as [`Results::raster`] gives it, but as a view that computes
    /// each cell from the per-cell statistics when read: nothing per grid cell is allocated,
    /// for maps and statistics of huge grids. `None` for an unknown name.
    pub fn raster_view(&self, name: &str) -> Option<RasterCells<'_>> {
        let (_, kind) = self.kinds().into_iter().find(|(n, _)| n == name)?;
        Some(self.rows(kind))
    }

    /// Sample type a raster is written with: `I32` for counts (`F64` should a count exceed
    /// the `i32` range), `F32` for the others.
    pub(crate) fn sample_type(&self, kind: Kind) -> SampleType {
        // cells nothing happened in count 0: only the touched cells can exceed the range
        let rocks = self.rocks();
        let too_big = self
            .tally
            .cells
            .touched()
            .filter_map(|c| self.cell_value(kind, rocks, Some(c)))
            .any(|v| v > f64::from(i32::MAX));
        match (kind.is_count(), too_big) {
            (false, _) => SampleType::F32,
            (true, true) => SampleType::F64,
            (true, false) => SampleType::I32,
        }
    }

    /// The value of raster `kind` in a cell with statistics `c` (`None`: nothing happened
    /// there) of a run of `rocks` rocks; `None` for nodata.
    pub(crate) fn cell_value(&self, kind: Kind, rocks: u64, c: Option<&CellStats>) -> Option<f64> {
        let visited = c.filter(|c| c.visits > 0);
        match kind {
            Kind::Passages => Some(c.map_or(0, |c| c.visits) as f64),
            Kind::Reach => Some(match (c, rocks) {
                (Some(c), 1..) => c.reached as f64 / rocks as f64 * 100.0,
                _ => 0.0,
            }),
            Kind::Deposited => Some(c.map_or(0, |c| c.deposited()) as f64),
            Kind::Sources => Some(c.map_or(0, |c| c.sources.len()) as f64),
            Kind::EnergyMean => visited?.energy_mean_j().map(|e| e / 1e3),
            Kind::EnergyPercentile(p) => visited?.energy_percentile_j(p).map(|e| e / 1e3),
            Kind::HeightMean => visited?.height_mean_m(),
            Kind::HeightPercentile(p) => visited?.height_percentile_m(p),
            Kind::EnergyCi95 => {
                let c = visited?;
                ci95(c.energy_mean_j(), c.energy_sd_j()).map(|e| e / 1e3)
            }
            Kind::HeightCi95 => {
                let c = visited?;
                ci95(c.height_mean_m(), c.height_sd_m())
            }
            Kind::EnergyLineAngle => Some(visited?.el_angle_max_deg).filter(|a| !a.is_nan()),
            Kind::VelocityMax => visited.map(|c| c.velocity_max_ms),
            Kind::TreeImpacts => Some(c.map_or(0, |c| c.tree_impacts()) as f64),
            Kind::TreeHeightMax => c
                .filter(|c| c.tree_impacts() > 0)
                .map(|c| c.tree_height_max_m()),
            Kind::StemsBroken => Some(c.map_or(0, |c| c.stems_broken()) as f64),
            Kind::RocksAbove(k) => Some(visited.map_or(0, |c| c.above(k)) as f64),
        }
    }

    /// Raster `kind` as rows computed on the fly from the per-cell statistics: what the
    /// writers read, so that no whole-grid buffer is ever made.
    pub(crate) fn rows(&self, kind: Kind) -> RasterCells<'_> {
        RasterCells {
            results: self,
            kind,
            rocks: self.rocks(),
        }
    }

    /// Raster `kind` as a whole grid (for [`Results::raster`]).
    pub(crate) fn grid(&self, kind: Kind) -> Grid<f64> {
        let rows = self.rows(kind);
        let geometry = self.layout.geometry;
        let mut grid = Grid::filled(geometry, 0.0).with_crs(self.layout.crs.clone());
        rockfall_raster::rows::for_each_row(&rows, |row, cells| {
            for (col, c) in cells.iter().enumerate() {
                match c {
                    Some(v) => grid.set(row, col, *v),
                    None => grid.set_nodata(row, col),
                }
            }
        });
        grid.set_nodata_value(Rows::nodata_value(&rows));
        grid
    }
}

/// One raster of [`Results`] seen row by row ([`Rows`], what the writers read) or cell by cell
/// ([`RasterView`]), each cell computed from the per-cell statistics when read
/// ([`Results::raster_view`]).
#[derive(Clone, Copy)]
pub struct RasterCells<'a> {
    results: &'a Results,
    kind: Kind,
    rocks: u64,
}

impl RasterCells<'_> {
    /// Value of the cell at row-major `index` (inside the grid).
    pub(crate) fn at(&self, index: usize) -> Option<f64> {
        let r = self.results;
        r.cell_value(self.kind, self.rocks, r.tally.cells.get(index))
    }
}

impl RasterView for RasterCells<'_> {
    fn view_geometry(&self) -> GridGeometry {
        self.results.layout.geometry
    }

    fn cell(&self, row: usize, col: usize) -> Option<f64> {
        let g = &self.results.layout.geometry;
        (row < g.nrows && col < g.ncols)
            .then(|| self.at(g.index(row, col)))
            .flatten()
    }

    fn for_each_valid(&self, f: &mut dyn FnMut(usize, usize, f64)) {
        rockfall_raster::rows::for_each_row(self, |row, cells| {
            for (col, c) in cells.iter().enumerate() {
                if let Some(v) = *c {
                    f(row, col, v);
                }
            }
        });
    }
}

impl Rows for RasterCells<'_> {
    fn geometry(&self) -> GridGeometry {
        self.results.layout.geometry
    }

    fn crs(&self) -> Option<&Crs> {
        self.results.layout.crs.as_ref()
    }

    /// −9999 for the non-count rasters; counts have no nodata.
    fn nodata_value(&self) -> Option<f64> {
        (!self.kind.is_count()).then_some(NODATA)
    }

    fn row(&self, row: usize, out: &mut [Option<f64>]) {
        let first = row * self.results.layout.geometry.ncols;
        for (col, o) in out.iter_mut().enumerate() {
            *o = self.at(first + col);
        }
    }
}

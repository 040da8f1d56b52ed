//! Command-line flags, defined once with their documentation (the `--help` text).

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// rockfall — a fast 3-D rockfall simulator for forested and open mountain slopes.
///
/// Two engines behind one set of inputs and outputs: `lumped` (seed 000, RockyFor:
/// probabilistic point masses on a raster DEM, rebound coefficients from surface maps,
/// explicit tree impacts) and `rigid` (seed 001: convex polyhedral rocks, non-smooth contact
/// with terrain and trees). Inputs are a scenario file (`*.toml`) or a Rockyfor3D input folder.
///
/// Exit codes: 0 success, 2 bad input (the message names the file, cell or key), 1 internal
/// failure.
#[derive(Debug, Parser)]
#[command(name = "rockfall", version, about, long_about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Build the embedded demo site (vaujany-site2), run it with and without its forest, and
    /// write every output: the forested run in OUT, the bare run in OUT/without_forest, the
    /// forest's protective effect (Forest_effect_*.tif, forest_effect.json) in OUT. Open
    /// OUT/report.html in a browser (offline): maps, plots and every number of both runs.
    Demo {
        /// Output folder (created if needed).
        #[arg(long, default_value = "rockfall-demo")]
        out: PathBuf,
    },
    /// Simulate rocks on an input: a scenario file (*.toml) or a Rockyfor3D input folder.
    /// Writes the hazard rasters (GeoTIFF: Nr_passages, Reach_probability, Nr_deposited,
    /// Nr_sourcecells, E_mean, E_<percentile> and E_95CI in kJ, Ph_mean, Ph_50, Ph_90, Ph_95
    /// and Ph_95CI in m, EL_angles in degrees, V_max in m/s, Nr_tree_impacts,
    /// Tree_impact_height_max in m, Nr_stems_broken) each with a QGIS style (.qml), a QGIS
    /// project (rockfall.qgs), summary.json, trajectories.csv and .geojson, rocks.csv and
    /// screen_crossings.csv when the scenario asks for them, and report.html: an offline page
    /// with the maps (report/map_*.png, over the hillshade), distribution and profile plots,
    /// and every number of the run.
    ///
    /// Regional runs: `--partition i/N` runs the i-th of N fixed shares of the rocks (a job
    /// of a job array) and also writes its exact tallies (rockfall.tally) for `rockfall
    /// merge`; `--until-stable TOL` runs doubling batches until the maps change by at most
    /// TOL % (rocks_per_cell and rocks_per_point are then the caps). Both save the run after
    /// every batch (checkpoint.tally); `--resume OUT` continues an interrupted run to the
    /// same end.
    Run {
        /// Scenario file or Rockyfor3D input folder (not with --resume).
        #[arg(required_unless_present = "resume", conflicts_with = "resume")]
        input: Option<PathBuf>,
        /// Output folder (created if needed; files of an earlier run are replaced).
        #[arg(long, default_value = "rockfall-out")]
        out: PathBuf,
        /// Engine: `lumped` (seed 000) or `rigid` (seed 001); default: the scenario's.
        #[arg(long, value_parser = ["lumped", "rigid"], ignore_case = true)]
        engine: Option<String>,
        /// Rocks released per source cell (≥ 1); default: the scenario's (100 for a Rockyfor3D
        /// folder).
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        rocks_per_cell: Option<u64>,
        /// Rocks released per release point (≥ 1); default: the scenario's
        /// (`[simulation] rocks_per_point`, 1).
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        rocks_per_point: Option<u64>,
        /// Master seed fixing every random draw; default: the scenario's (1).
        #[arg(long)]
        seed: Option<u64>,
        /// Worker threads (≥ 1); default: all cores. Results do not depend on it.
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        threads: Option<u64>,
        /// Also write every raster as an ESRI ASCII grid (.asc + .prj) for Rockyfor3D users.
        #[arg(long)]
        ascii: bool,
        /// Run only the i-th of N equal shares of the rocks (1 ≤ i ≤ N), fixed by source cell
        /// and rock index under the master seed; writes the share's run folder and its exact
        /// tallies (rockfall.tally) for `rockfall merge`.
        #[arg(long, value_name = "i/N", value_parser = parse_partition, conflicts_with = "until_stable")]
        partition: Option<rockfall_sim::Partition>,
        /// Run doubling batches (10, 20, 40, … rocks per source cell and point) until
        /// Reach_probability (percentage points, cells reached by ≥ 1 % of the rocks) and
        /// E_95 (relative change of the map) change by at most TOL % between batches, or
        /// until rocks_per_cell / rocks_per_point (the caps) are reached; default: the
        /// scenario's `until_stable_pct`, none.
        #[arg(long, value_name = "TOL", value_parser = parse_tolerance)]
        until_stable: Option<f64>,
        /// Run only spatial tile i of N (row-major from the north-west) of the region: the
        /// rocks of the tile's source cells, on the tile and a halo around it (--halo-m),
        /// bit-identical to the same rocks in a run of the whole region. Writes the tile's
        /// exact tallies (rockfall.tally) and tile.json for `rockfall merge`; the grid is cut
        /// into N near-square tiles, or into squares of --tile-size-m.
        #[arg(long, value_name = "i/N", value_parser = parse_partition, conflicts_with_all = ["partition", "until_stable"], group = "tiling")]
        tile: Option<rockfall_sim::Partition>,
        /// Run every one of N spatial tiles of the region, one after the other (under
        /// `mpirun`, spread over the ranks and merged up a reduction tree), and write the
        /// region's run folder: the single run's files, byte for byte, from one tile's
        /// memory at a time plus the region's statistics. With --until-stable, batch after
        /// batch over every tile, deciding on the region's maps.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..), conflicts_with = "partition", group = "tiling")]
        tiles: Option<u64>,
        /// Side of the square tiles, m (with --tile or --tiles; N must then be the number of
        /// tiles this size makes, which the error states).
        #[arg(long, value_name = "D", requires = "tiling", value_parser = parse_positive_m)]
        tile_size_m: Option<f64>,
        /// Halo read around a tile, m (with --tile or --tiles; default 1000). A rock that
        /// goes farther is simulated again on a halo twice as wide.
        #[arg(long, value_name = "H", requires = "tiling", value_parser = parse_positive_m)]
        halo_m: Option<f64>,
        /// The region's tile index (with --tile or --tiles): read when it exists, written
        /// when it does not or is out of date. It holds the release raster's or layer's source
        /// cells counted per row and block and the digest of the input files, so that a tile
        /// reads its own rows of the release and hashes no input file instead of reading the
        /// whole region. Every part is used only while its files keep their canonical path,
        /// size, modification and status-change times and inode.
        #[arg(long, value_name = "FILE", requires = "tiling")]
        tile_index: Option<PathBuf>,
        /// Continue the interrupted run whose output folder is DIR (its checkpoint.tally),
        /// with the input, seed and rocks it started with; ends bit-identical to an
        /// uninterrupted run.
        #[arg(long, value_name = "DIR", conflicts_with_all = ["engine", "rocks_per_cell", "rocks_per_point", "seed", "partition", "until_stable", "tile", "tiles"])]
        resume: Option<PathBuf>,
    },
    /// Merge the run folders of the shares of one run (`rockfall run --partition i/N` or
    /// `--tile i/N`, all N of them) into the folder of the whole run: tallies summed exactly,
    /// so the rasters and summary.json are bit-identical to a single run's (timings aside).
    /// Folders of different inputs, seeds or versions, missing or repeated shares, and
    /// unfinished shares are refused (exit 2), naming the difference. --stream merges regions
    /// too large to hold.
    Merge {
        /// The shares' or tiles' output folders (each holds a rockfall.tally).
        #[arg(required = true, num_args = 1..)]
        dirs: Vec<PathBuf>,
        /// Output folder of the merged run (created if needed).
        #[arg(long, default_value = "rockfall-merged")]
        out: PathBuf,
        /// The input, where it is now, for the report's maps (default: the path the shares
        /// recorded); without it only the rasters, summary and tables are written.
        #[arg(long)]
        input: Option<PathBuf>,
        /// Also write every raster as an ESRI ASCII grid (.asc + .prj).
        #[arg(long)]
        ascii: bool,
        /// Stream the per-cell statistics instead of holding them: for regions whose merge
        /// does not fit in memory. The tallies are read twice (three times when their bounds
        /// leave a raster's sample type open), and memory holds only the rows being written
        /// and the cells of the tiles that span them. Writes the same rasters (GeoTIFF),
        /// summary.json and tables, but no merged rockfall.tally, report, styles or ASCII
        /// grids.
        #[arg(long, conflicts_with_all = ["ascii", "input"])]
        stream: bool,
        /// Threads of a streamed merge: reading the tallies the first time, compressing the
        /// rasters' tiles (default: the machine's cores; the files are the same whatever
        /// the number).
        #[arg(long, requires = "stream")]
        threads: Option<u64>,
    },
    /// Read and validate every input; print extent, cell size, CRS, source cells, stems and
    /// parameter ranges. Exit 2 on any problem.
    Check {
        /// Scenario file or Rockyfor3D input folder.
        input: PathBuf,
    },
    /// Print the JSON Schema (draft 2020-12) of the scenario file: every key with its
    /// description, unit, default and range, every table closed to unknown keys. Point an
    /// editor at it (taplo / Even Better TOML: a `#:schema ./scenario.schema.json` first line
    /// or a `.taplo.toml` rule) to have a scenario checked and completed as it is written.
    /// With --markdown, a Markdown reference of every key instead, generated from the schema.
    Schema {
        /// Print the Markdown key reference (one table per section) instead of the schema.
        #[arg(long)]
        markdown: bool,
        /// Write to FILE (atomically: a temporary file, then renamed) instead of standard
        /// output.
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// Write a built-in synthetic site as input files: rasters (ESRI ASCII grids with .prj),
    /// tree list, scenario.toml, and the Rockyfor3D file set where the site fits it.
    /// `alpine-region` is a procedural mountain region of any size (--cells) written as tiled
    /// Cloud-Optimised GeoTIFFs (DEM, source cells where the slope is ≥ 45°, soil type,
    /// roughness, forest stands) with its scenario.toml: the regional test site.
    Site {
        /// Site name (see --list): vaujany-site1, vaujany-site2, forest-slope-40, leine-ramp-40,
        /// alpine-region.
        #[arg(required_unless_present = "list")]
        name: Option<String>,
        /// Output folder (created if needed).
        #[arg(long, required_unless_present = "list")]
        out: Option<PathBuf>,
        /// List the built-in sites.
        #[arg(long)]
        list: bool,
        /// alpine-region: cells of the DEM, 10 000 to 4·10⁹, rounded to a square (default
        /// 10⁶). Writing holds 4 bytes per cell; 10⁹ cells take some minutes.
        #[arg(long)]
        cells: Option<u64>,
        /// alpine-region: cell size, m, 1 to 25 (default 5).
        #[arg(long)]
        cell_size_m: Option<f64>,
        /// alpine-region: seed of the relief (default 1).
        #[arg(long)]
        seed: Option<u64>,
    },
    /// The single-tree virtual impact experiment of seed 001 §2 (rigid engine): rocks of one
    /// shape (0.02 m³, 2700 kg/m³) released 5 m high from a 1 m² lattice in front of one rigid
    /// stem, random speed 5–40 m/s, spin 0–60 rad/s, direction θ 0–180°, χ −40–40°; the first
    /// impact of N rocks that hit it, as frontal, lateral or scratch by the eccentricity ζ_CT.
    /// Writes impacts.csv, summary.json (per-regime energy loss and spin change) and the
    /// figures (PDFs of ΔE_total, ΔE_trans, Δω; δE_rot vs δE_trans). With --compare, draws
    /// earlier runs side by side instead of simulating.
    ImpactLab {
        /// Rock shape: sphere, cubic1.2, flat2.2, long2.2, box, ellipsoid, disc, a rough rock
        /// rough-<class><Π>-<member> (e.g. rough-flat2.2-7), or a point cloud / mesh file
        /// (.xyz .csv .txt .obj .ply .stl); rescaled to 0.02 m³.
        #[arg(long, default_value = "sphere")]
        shape: String,
        /// Impacts sampled (≥ 1).
        #[arg(long, default_value_t = 5000, value_parser = clap::value_parser!(u64).range(1..))]
        samples: u64,
        /// Master seed fixing every random draw.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output folder (created if needed).
        #[arg(long, default_value = "rockfall-impact-lab")]
        out: PathBuf,
        /// Stem diameter at the ground d0, m; the stem tapers by 0.01 m per m over its 10 m
        /// (seed 001: d0 0.55 m, d1 0.45 m).
        #[arg(long, default_value_t = 0.55)]
        dbh_m: f64,
        /// Friction coefficient of the stem surface.
        #[arg(long, default_value_t = 0.6)]
        mu: f64,
        /// Normal restitution of rock–stem contacts.
        #[arg(long, default_value_t = 0.0)]
        eps_n: f64,
        /// Tangential restitution of rock–stem contacts.
        #[arg(long, default_value_t = 0.0)]
        eps_t: f64,
        /// Time step, s.
        #[arg(long, default_value_t = 1e-4)]
        dt_s: f64,
        /// Worker threads (≥ 1); default: all cores. Results do not depend on it.
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        threads: Option<u64>,
        /// Compare earlier runs (their output folders) instead of simulating: figures with one
        /// curve per run, comparison.json and comparison.md, written to --out.
        #[arg(
            long,
            num_args = 1..,
            value_name = "DIR",
            conflicts_with_all = ["shape", "samples", "seed", "dbh_m", "mu", "eps_n", "eps_t", "dt_s", "threads"]
        )]
        compare: Vec<PathBuf>,
    },
    /// The forest-slope rock-shape study of seed 001 §3.4: the same slope run once per rock
    /// shape. Writes each shape's full run (rasters, summary.json, trajectories.csv every
    /// --interval-s) in OUT/<shape>, the plan view of all trajectories coloured by total
    /// energy (trajectories_plan.png), and run-out and lateral spread per shape (study.json,
    /// study.md).
    ShapeStudy {
        /// Scenario file or Rockyfor3D input folder; default: the built-in forest-slope-40.
        input: Option<PathBuf>,
        /// Rock shapes, comma-separated (as for impact-lab --shape); each keeps the
        /// scenario's rock volume and density. `rough-<class><Π>*N` is an ensemble: N rough
        /// rocks of the class (members rough-<class><Π>-1 … -N), each run with --rocks rocks,
        /// reported as one class with 95 % intervals over members and rocks.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "cubic1.2,flat2.2,long2.2"
        )]
        shapes: Vec<String>,
        /// Rocks per release point (≥ 1).
        #[arg(long, default_value_t = 500, value_parser = clap::value_parser!(u64).range(1..))]
        rocks: u64,
        /// Master seed; default: the scenario's.
        #[arg(long)]
        seed: Option<u64>,
        /// Time between recorded trajectory rows, s (> 0).
        #[arg(long, default_value_t = 0.05)]
        interval_s: f64,
        /// Worker threads (≥ 1); default: all cores. Results do not depend on it.
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        threads: Option<u64>,
        /// Output folder (created if needed).
        #[arg(long, default_value = "rockfall-shape-study")]
        out: PathBuf,
    },
    /// Draw the hazard zone map: each cell's intensity (block kinetic energy, kJ) crossed with
    /// the probability of its events (return period, years) by a national matrix. FILE
    /// (TOML) names `matrix` ("swiss", "austria" or a matrix file), `intensity` (the energy
    /// raster, default "E_95") and `[[scenario]]` entries: in scenario mode each with
    /// `return_period_years` and `scenario = "<scenario file>"` (run into OUT/runs/<label>
    /// unless already finished there; `volume_m3`, `mass_kg` or `block_percentile` set its
    /// design block) or `run = "<finished run folder>"`; in frequency mode each with
    /// `frequency_per_year`, the release's onset frequency, and the return period of a block
    /// above each intensity limit follows per cell from the run's passage counts. Writes
    /// Hazard_level.tif (0 none, 1 residual, 2 low, 3 medium, 4 high; styled by its .qml),
    /// Hazard_field.tif (matrix field 1–9), Intensity_class*.tif, Return_period_class*.tif,
    /// hazard_zones.gpkg (polygons per level and field with their areas), hazard.json,
    /// hazard.html and hazard.qgs. See docs/hazard.md.
    Hazard {
        /// Hazard file (TOML); paths in it are relative to it.
        file: PathBuf,
        /// The matrix, replacing the file's: swiss, austria or a matrix file (TOML).
        #[arg(long)]
        matrix: Option<String>,
        /// Rocks per source cell of every scenario run (default: each scenario's).
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        rocks_per_cell: Option<u64>,
        /// Seed of every scenario run (default: each scenario's).
        #[arg(long)]
        seed: Option<u64>,
        /// Worker threads (≥ 1); default: all cores. Results do not depend on it.
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        threads: Option<u64>,
        /// Run every scenario again, even where OUT/runs holds its finished run.
        #[arg(long)]
        rerun: bool,
        /// Output folder (created if needed); scenario runs go into OUT/runs/<label>.
        #[arg(long, default_value = "rockfall-hazard")]
        out: PathBuf,
    },
    /// Fit a scenario's free parameters to what the slope shows. TARGETS (TOML) names the
    /// free keys (`[[parameter]] key = "lumped.roughness_tilt_factor"`, `range = [lo, hi]`,
    /// or `scale = [lo, hi]` to multiply a map or constant) and the observations
    /// (`[[target]] path = "runout_m.p50"` of summary.json, `value`, and `sd` or `n`, the
    /// rocks observed for a share or a maximum; `[deposits] points = "layer.geojson"`,
    /// mapped blocks). Every candidate runs with the same seed; a Latin hypercube of about
    /// 60 % of the budget, then a Nelder–Mead refinement. Writes calibration.json (every
    /// evaluation, the best values, the set fitting every target within 2σ and each
    /// parameter's range in it), calibrated.toml (the scenario with the best values,
    /// runnable as is; its inputs in calibrated/), calibration.md and calibration.html with
    /// figures.
    Calibrate {
        /// Scenario file or Rockyfor3D input folder.
        scenario: PathBuf,
        /// Targets file (TOML).
        #[arg(long)]
        targets: PathBuf,
        /// Candidates evaluated at most (≥ 1).
        #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u64).range(1..))]
        budget: u64,
        /// Seed of the design and of every candidate's run; default: the scenario's.
        #[arg(long)]
        seed: Option<u64>,
        /// Worker threads (≥ 1); default: all cores. Results do not depend on it.
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        threads: Option<u64>,
        /// Output folder (created if needed).
        #[arg(long, default_value = "rockfall-calibration")]
        out: PathBuf,
    },
    /// Run the published-experiment cases and print observed against simulated, with the
    /// error E = (C − O)·100/O of each quantity and the RMSE of each case (seed 000 eqs. 5
    /// and 6). Cases: `vaujany-site1` (seed 000 table 2, site 1, and table 3 at its screens at
    /// 185 m and 235 m, each screen a case of its own), `vaujany-site2` (table 2, site 2, and
    /// the fig. 2 histogram of tree impacts per rock), both on the lumped engine;
    /// `vaujany-crossval` (each site's table 2 run with the lumped engine's free factors
    /// calibrated on the other site's: `vaujany-site2 (calibrated on site 1)` and the
    /// reverse);
    /// `impact-lab` (seed 001 §3.1–3.3: the single-tree laboratory for sphere, cubic1.2,
    /// flat2.2 and long2.2, losses per regime and the rotation and energy-partition findings);
    /// `forest-slope-40` (seed 001 §3.4: run-out and spread of its three rock shapes, of rough
    /// ensembles of their classes and of the EOTA blocks on the rigid engine, seed 001's and
    /// Caviezel et al. 2021's findings checked); and `leine-ramp-40` (Leine et al. 2021:
    /// EOTA221 of 780 kg down a 40° ramp, mean and sd of energy, speed, rotation and jump
    /// height). The two rigid cases run on the scarring ground of Lu et al. 2019 (the sites'
    /// own) and again on the hard ground of Leine et al. 2014 as `forest-slope-40-hard` and
    /// `leine-ramp-40-hard` (docs/rigid-ground.md).
    /// Beside the paper's protocol, a fair comparison:
    /// each maximum also over groups of the observed sample size, each observed share with
    /// its 95 % interval, and the fair RMSE; and a sensitivity table (each Vaujany site rerun
    /// with a fifth of the rocks, every unknown of its reconstruction and our two ground-
    /// contact rules at both ends of their range). Writes validation.json, validation.md,
    /// fig2_tree_impacts_per_rock.png and every run's outputs in OUT/<case>.
    Validate {
        /// Cases to run: vaujany-site1, vaujany-site2, vaujany-crossval, impact-lab,
        /// forest-slope-40, leine-ramp-40 (default: all).
        cases: Vec<String>,
        /// Rocks per case (per shape for forest-slope-40; ≥ 1); default 10 000 for the
        /// Vaujany sites as in seed 000, 500 per shape as in seed 001 (ten times as many
        /// impacts per shape in impact-lab, twice as many rocks on leine-ramp-40).
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        rocks: Option<u64>,
        /// A quick look: 1000 rocks per Vaujany site, 30 per shape.
        #[arg(long, conflicts_with = "rocks")]
        quick: bool,
        /// Master seed of every run; default 1.
        #[arg(long)]
        seed: Option<u64>,
        /// Worker threads (≥ 1); default: all cores. Results do not depend on it.
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        threads: Option<u64>,
        /// Output folder (created if needed; files of an earlier run are replaced).
        #[arg(long, default_value = "rockfall-validation")]
        out: PathBuf,
    },
}

/// `i/N` as a [`rockfall_sim::Partition`].
fn parse_partition(s: &str) -> Result<rockfall_sim::Partition, String> {
    s.parse()
}

/// A length in metres above 0.
fn parse_positive_m(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err(format!("`{s}`: a length in metres above 0, e.g. 5000")),
    }
}

/// A convergence tolerance: a percentage above 0 and at most 100.
fn parse_tolerance(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(t) if t > 0.0 && t <= 100.0 => Ok(t),
        _ => Err(format!(
            "`{s}`: the tolerance is a percentage above 0 and at most 100, e.g. 1"
        )),
    }
}

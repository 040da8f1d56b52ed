//! A run split into shares and put back together: partitions for job arrays, their record in
//! a tally file, and the exact merge of saved tallies.
//!
//! The rocks of a run are numbered in release order (source cells ascending, then points; in
//! each release by rock index), and every rock draws from its own stream `(seed, release,
//! index)`. Share `i` of `N` is the contiguous block of rock numbers
//! `⌊(i−1)·R/N⌋ .. ⌊i·R/N⌋` of the run's `R` rocks: fixed by source cell and rock index under
//! the master seed, the same on every machine, and together the shares hold every rock exactly
//! once. Tallies of disjoint rock sets merge exactly, so the merge of all shares is
//! bit-identical to the single run.

use std::fmt;
use std::ops::Range;
use std::path::PathBuf;

use rockfall_engine::RockSet;
use rockfall_results::{Layout, RunInfo, SavedTally, Tally};
use rockfall_scenario::Scenario;

use crate::batches::BatchState;
pub use crate::fingerprint::{fingerprint, input_digest, tile_fingerprint};
use serde::{Deserialize, Serialize};

/// Share `index` (1-based) of `count` equal shares of a run's rocks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Partition {
    /// Which share, 1 ..= count.
    pub index: u64,
    /// How many shares.
    pub count: u64,
}

impl std::str::FromStr for Partition {
    type Err = String;

    /// `i/N` with 1 ≤ i ≤ N.
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("`{s}`: a partition is i/N with whole numbers 1 ≤ i ≤ N, e.g. 3/8");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (i.trim().parse::<u64>(), n.trim().parse::<u64>());
        match (index, count) {
            (Ok(index), Ok(count)) if (1..=count).contains(&index) => {
                Ok(Partition { index, count })
            }
            _ => Err(bad()),
        }
    }
}

impl fmt::Display for Partition {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Partition {
    /// The rock numbers of this share of `total` rocks.
    pub fn range(&self, total: u64) -> Range<u64> {
        let cut = |k: u64| (u128::from(total) * u128::from(k) / u128::from(self.count)) as u64;
        cut(self.index - 1)..cut(self.index)
    }

    /// The rocks of this share of `total` rocks, as a set.
    pub fn rocks(&self, total: u64) -> RockSet {
        RockSet::from_ranges([self.range(total)])
    }
}

/// What a tally file says about the run its tally belongs to: enough to refuse a merge of
/// tallies from different runs and to continue an interrupted one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// Version of rockfall that simulated it.
    pub rockfall_version: String,
    /// The input read (a scenario file or Rockyfor3D folder), as given on the command line
    /// made absolute; empty for a scenario built in memory.
    pub input: String,
    /// Hash of the scenario as simulated, overrides applied (see [`fingerprint`]).
    pub fingerprint: String,
    /// Engine.
    pub engine: String,
    /// Scenario name.
    pub scenario: String,
    /// Master seed.
    pub seed: u64,
    /// Rocks per source cell.
    pub rocks_per_cell: u64,
    /// Rocks per release point.
    pub rocks_per_point: u64,
    /// Rocks of the whole run.
    pub rocks_total: u64,
    /// The rock numbers the tally holds, as sorted disjoint `[start, end)` ranges.
    pub rocks: Vec<[u64; 2]>,
    /// The share this run was (`i/N`), if it was one.
    pub partition: Option<String>,
    /// Every rock it was to simulate is in the tally.
    pub complete: bool,
    /// How the run proceeds in batches, and how far it is.
    pub batch: BatchState,
}

impl RunRecord {
    /// The record of a run of every rock of `scenario` (in batches when it has a tolerance)
    /// read from `input`, before any rock ran.
    pub fn new(scenario: &Scenario, input: &str) -> RunRecord {
        let total = crate::rocks(scenario);
        RunRecord {
            rockfall_version: env!("CARGO_PKG_VERSION").to_string(),
            input: input.to_string(),
            fingerprint: fingerprint(scenario),
            engine: scenario.engine.to_string(),
            scenario: scenario.name.clone(),
            seed: scenario.seed,
            rocks_per_cell: scenario.simulation.rocks_per_cell,
            rocks_per_point: scenario.simulation.rocks_per_point,
            rocks_total: total,
            rocks: Vec::new(),
            partition: None,
            complete: false,
            batch: BatchState {
                wanted: vec![[0, total]],
                batches: 0,
                until_stable_pct: scenario.simulation.until_stable_pct,
                history: Vec::new(),
                converged: false,
            },
        }
    }

    /// The record of spatial tile `spec` of a region's run, complete: it holds `rocks` of the
    /// region's `region_rocks`; `fingerprint` is the region's ([`tile_fingerprint`]).
    pub fn of_tile(
        scenario: &Scenario,
        input: &str,
        fingerprint: String,
        rocks: &RockSet,
        region_rocks: u64,
        spec: &crate::tile::TileSpec,
    ) -> RunRecord {
        let held = ranges(rocks);
        RunRecord {
            rockfall_version: env!("CARGO_PKG_VERSION").to_string(),
            input: input.to_string(),
            fingerprint,
            engine: scenario.engine.to_string(),
            scenario: scenario.name.clone(),
            seed: scenario.seed,
            rocks_per_cell: scenario.simulation.rocks_per_cell,
            rocks_per_point: scenario.simulation.rocks_per_point,
            rocks_total: region_rocks,
            rocks: held.clone(),
            partition: Some(format!("tile {spec}")),
            complete: true,
            batch: BatchState {
                wanted: held,
                batches: 1,
                until_stable_pct: scenario.simulation.until_stable_pct,
                history: Vec::new(),
                converged: false,
            },
        }
    }

    /// The record of share `p` of the run.
    pub fn with_partition(mut self, p: Partition) -> RunRecord {
        self.batch.wanted = ranges(&p.rocks(self.rocks_total));
        self.partition = Some(p.to_string());
        self
    }

    /// The rocks the run is to simulate.
    pub fn wanted(&self) -> RockSet {
        RockSet::from_ranges(self.batch.wanted.iter().map(|r| r[0]..r[1]))
    }

    /// The rocks the tally holds.
    pub fn rock_set(&self) -> RockSet {
        RockSet::from_ranges(self.rocks.iter().map(|r| r[0]..r[1]))
    }

    /// The fields two records of one run share, named as an error message names them.
    fn identity(&self) -> [(&'static str, String); 8] {
        [
            ("rockfall version", self.rockfall_version.clone()),
            ("engine", self.engine.clone()),
            ("scenario", self.scenario.clone()),
            ("seed", self.seed.to_string()),
            ("rocks per cell", self.rocks_per_cell.to_string()),
            ("rocks per point", self.rocks_per_point.to_string()),
            ("rocks in the run", self.rocks_total.to_string()),
            (
                "inputs (scenario fingerprint: DEM, maps, forest, parameters)",
                self.fingerprint.clone(),
            ),
        ]
    }
}

/// `rocks` as `[start, end)` pairs.
pub fn ranges(rocks: &RockSet) -> Vec<[u64; 2]> {
    rocks.ranges().iter().map(|r| [r.start, r.end]).collect()
}

/// Why saved tallies cannot be merged. Each names the folders or files at fault.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// Nothing to merge.
    #[error("no run folder to merge")]
    Empty,
    /// Two tallies come from different runs.
    #[error(
        "{a} and {b} are not parts of one run: they differ in {what} ({a_value} against {b_value})"
    )]
    Different {
        /// First file.
        a: PathBuf,
        /// Second file.
        b: PathBuf,
        /// What differs.
        what: String,
        /// Its value in `a`.
        a_value: String,
        /// Its value in `b`.
        b_value: String,
    },
    /// A tally of a run that did not finish.
    #[error(
        "{path}: this run did not finish ({done} of its {wanted} rocks); continue it with \
         `rockfall run --resume` on its folder"
    )]
    Unfinished {
        /// The file.
        path: PathBuf,
        /// Rocks in the tally.
        done: u64,
        /// Rocks it was to simulate.
        wanted: u64,
    },
    /// Two tallies hold some of the same rocks (the same partition twice, or partitions of
    /// different splits).
    #[error(
        "{a} and {b} hold the same rocks ({from} .. {to}): each share may be merged once \
         (partitions {pa} and {pb})"
    )]
    Overlap {
        /// First file.
        a: PathBuf,
        /// Second file.
        b: PathBuf,
        /// First shared rock.
        from: u64,
        /// End of the shared rocks.
        to: u64,
        /// Partition of `a`.
        pa: String,
        /// Partition of `b`.
        pb: String,
    },
    /// Some rocks of the run are in no tally.
    #[error(
        "rocks {missing} of the run's {total} are in none of the folders: a partition is \
         missing (the folders hold {have})"
    )]
    Missing {
        /// The missing rock ranges.
        missing: String,
        /// Rocks of the run.
        total: u64,
        /// Partitions found.
        have: String,
    },
}

/// Saved tallies merged into the tally of their whole run.
#[derive(Debug)]
pub struct Merged {
    /// The merged tally.
    pub tally: Tally,
    /// The run: the first part's, with the largest thread count and the summed wall time.
    pub info: RunInfo,
    /// The whole run's record (every rock, no partition).
    pub record: RunRecord,
}

fn show(r: &[Range<u64>]) -> String {
    let v: Vec<String> = r
        .iter()
        .map(|r| format!("{} .. {}", r.start, r.end))
        .collect();
    v.join(", ")
}

/// Merges saved tallies (each with the file it came from) of one run's disjoint shares that
/// together hold every rock of the run: exactly, so the result is bit-identical to the
/// single run's tally.
pub fn merge(parts: Vec<(PathBuf, SavedTally<RunRecord>)>) -> Result<Merged, MergeError> {
    let mut parts = parts;
    // by first rock, a tile without rocks (no source cell in it) last: the first part holds
    // rock 0, whose parameters (the first source's rock) the whole run records
    parts.sort_by_key(|(_, s)| s.run.rocks.first().map_or((true, 0), |r| (false, r[0])));
    let (first_path, first) = parts.first().ok_or(MergeError::Empty)?;
    let (first_path, record, layout) =
        (first_path.clone(), first.run.clone(), first.layout.clone());
    for (path, s) in &parts {
        check_same(&first_path, &record, &layout, &first.info, path, s)?;
        if let Some(tol) = s.run.batch.until_stable_pct {
            return Err(MergeError::Different {
                a: first_path.clone(),
                b: path.clone(),
                what: "kind of run (a convergence run is whole, not a share)".into(),
                a_value: "until_stable_pct".into(),
                b_value: format!("{tol}"),
            });
        }
        let (done, wanted) = (s.tally.rocks(), s.run.wanted().len());
        if !s.run.complete || done != wanted || s.run.rock_set().len() != wanted {
            return Err(MergeError::Unfinished {
                path: path.clone(),
                done,
                wanted,
            });
        }
    }
    check_cover(&parts, record.rocks_total)?;
    let mut info = first.info.clone();
    if record.fingerprint.starts_with("tiles-") {
        // each tile counted the stems of its own cells
        let stems = (parts.iter())
            .filter_map(|(_, s)| s.info.parameters.clone().size_mut().map(|z| z.stems))
            .sum();
        if let Some(size) = info.parameters.size_mut() {
            size.stems = stems;
        }
    }
    info.threads = parts.iter().map(|(_, s)| s.info.threads).max().unwrap_or(1);
    info.wall_time_s = parts.iter().map(|(_, s)| s.info.wall_time_s).sum();
    let mut tally = Tally::new(layout);
    for (_, s) in parts {
        tally.merge(s.tally);
    }
    let all = vec![[0, record.rocks_total]];
    let record = RunRecord {
        rocks: all.clone(),
        partition: None,
        complete: true,
        batch: BatchState {
            wanted: all,
            ..record.batch
        },
        ..record
    };
    Ok(Merged {
        tally,
        info,
        record,
    })
}

pub(crate) fn check_same(
    a: &std::path::Path,
    ra: &RunRecord,
    layout: &Layout,
    info: &RunInfo,
    b: &std::path::Path,
    s: &SavedTally<RunRecord>,
) -> Result<(), MergeError> {
    let different = |what: &str, x: String, y: String| MergeError::Different {
        a: a.to_path_buf(),
        b: b.to_path_buf(),
        what: what.to_string(),
        a_value: x,
        b_value: y,
    };
    for ((what, x), (_, y)) in ra.identity().into_iter().zip(s.run.identity()) {
        if x != y {
            return Err(different(what, x, y));
        }
    }
    if *layout != *s.layout {
        let g = |l: &Layout| format!("{:?}", l.geometry);
        return Err(different("grids or screens", g(layout), g(&s.layout)));
    }
    let tiles = |r: &RunRecord| r.fingerprint.starts_with("tiles-");
    let (pa, pb) = match tiles(ra) && tiles(&s.run) {
        true => (
            info.parameters.shared_by_tiles(),
            s.info.parameters.shared_by_tiles(),
        ),
        false => (info.parameters.clone(), s.info.parameters.clone()),
    };
    if pa != pb {
        return Err(different(
            "engine parameters",
            "one set".into(),
            "another".into(),
        ));
    }
    Ok(())
}

/// Every rock of `0 .. total` in exactly one part (`parts` sorted by first rock).
fn check_cover(parts: &[(PathBuf, SavedTally<RunRecord>)], total: u64) -> Result<(), MergeError> {
    let mut all: Vec<(Range<u64>, usize)> = Vec::new();
    for (k, (_, s)) in parts.iter().enumerate() {
        all.extend(s.run.rock_set().ranges().iter().map(|r| (r.clone(), k)));
    }
    all.sort_by_key(|(r, _)| r.start);
    let partition = |k: usize| parts[k].1.run.partition.clone().unwrap_or("–".into());
    for w in all.windows(2) {
        let ((ra, ka), (rb, kb)) = (&w[0], &w[1]);
        if rb.start < ra.end {
            return Err(MergeError::Overlap {
                a: parts[*ka].0.clone(),
                b: parts[*kb].0.clone(),
                from: rb.start,
                to: ra.end.min(rb.end),
                pa: partition(*ka),
                pb: partition(*kb),
            });
        }
    }
    let have = RockSet::from_ranges(all.iter().map(|(r, _)| r.clone()));
    let mut missing = Vec::new();
    let mut at = 0;
    for r in have.ranges() {
        if r.start > at {
            missing.push(at..r.start);
        }
        at = r.end;
    }
    if at < total {
        missing.push(at..total);
    }
    if missing.is_empty() {
        return Ok(());
    }
    let have: Vec<String> = (0..parts.len()).map(partition).collect();
    Err(MergeError::Missing {
        missing: show(&missing),
        total,
        have: have.join(", "),
    })
}

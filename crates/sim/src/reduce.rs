//! Merging the parts of a run two at a time, in any grouping (a reduction tree over MPI
//! ranks, or tiles folded as they finish): [`combine`] checks and adds two parts without
//! asking that they hold every rock; [`crate::share::merge`] of the last part then checks
//! that every rock is there.

use std::path::PathBuf;

use rockfall_engine::RockSet;
use rockfall_results::SavedTally;

use crate::share::{MergeError, RunRecord, check_same, ranges};

/// A part of a run: the tally file (or rank) it came from, and its saved tally.
pub type Part = (PathBuf, SavedTally<RunRecord>);

/// Two disjoint parts of one run as one: checked as [`crate::share::merge`] checks its parts
/// (same run, disjoint rocks), their tallies added exactly, their rocks united. The part
/// holding the lower first rock gives the run's parameters (its first source's rock); stems
/// counted per tile are summed, wall times summed, the larger thread count kept.
pub fn combine(a: Part, b: Part) -> Result<Part, MergeError> {
    join(a, b, true)
}

/// A batch of a convergence run added to the run so far: as [`combine`], but the stems
/// counted per tile are those of the run so far (the batch counted the same tiles' again).
pub fn accumulate(run: Part, batch: Part) -> Result<Part, MergeError> {
    join(run, batch, false)
}

fn join(a: Part, b: Part, sum_stems: bool) -> Result<Part, MergeError> {
    let first = |p: &Part| p.1.run.rocks.first().map_or((true, 0), |r| (false, r[0]));
    let (mut a, b) = if first(&b) < first(&a) {
        (b, a)
    } else {
        (a, b)
    };
    check_same(&a.0, &a.1.run, &a.1.layout, &a.1.info, &b.0, &b.1)?;
    let (ra, rb) = (a.1.run.rock_set(), b.1.run.rock_set());
    if let Some(r) = ra.ranges().iter().find_map(|r| overlap(r, &rb)) {
        return Err(MergeError::Overlap {
            a: a.0,
            b: b.0,
            from: r.start,
            to: r.end,
            pa: a.1.run.partition.unwrap_or_default(),
            pb: b.1.run.partition.unwrap_or_default(),
        });
    }
    let all = RockSet::from_ranges(ra.ranges().iter().chain(rb.ranges()).cloned());
    let (sa, sb) = (&mut a.1, b.1);
    if sum_stems && sa.run.fingerprint.starts_with("tiles-") {
        let stems = |p: &mut rockfall_results::Parameters| p.size_mut().map_or(0, |s| s.stems);
        let sum = stems(&mut sa.info.parameters) + stems(&mut sb.info.parameters.clone());
        if let Some(s) = sa.info.parameters.size_mut() {
            s.stems = sum;
        }
    }
    sa.info.wall_time_s += sb.info.wall_time_s;
    sa.info.threads = sa.info.threads.max(sb.info.threads);
    sa.tally.merge(sb.tally);
    sa.run.rocks = ranges(&all);
    sa.run.batch.wanted = sa.run.rocks.clone();
    sa.run.partition = match (sa.run.partition.take(), sb.run.partition) {
        (Some(x), Some(y)) => Some(format!("{x} + {y}")),
        (x, y) => x.or(y),
    };
    let name = PathBuf::from(format!("{} + {}", a.0.display(), b.0.display()));
    Ok((name, a.1))
}

/// The first rocks of `r` that `set` also holds.
fn overlap(r: &std::ops::Range<u64>, set: &RockSet) -> Option<std::ops::Range<u64>> {
    set.ranges().iter().find_map(|s| {
        let (lo, hi) = (r.start.max(s.start), r.end.min(s.end));
        (lo < hi).then_some(lo..hi)
    })
}

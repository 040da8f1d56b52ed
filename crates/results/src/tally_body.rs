//! The body of a tally file ([`crate::persist`]): per-rock statistics, screens, the speed
//! profile, per-cell statistics sorted by cell, trajectory rows, rock records and screen
//! crossings; integers as varints, floats as their bit patterns, histograms as their
//! non-empty bins, ascending indices as gaps ([`crate::codec`]).

use crate::cells::{CellStats, Extra};
use crate::codec::{Dec, DecodeError, Enc};
use crate::hist::Stat;
use crate::hist::{ENERGY_BINS, SHORT_BINS};
use crate::packed::PackedHists;
use crate::profile::SpeedHistogram;
use crate::source_set::SourceSet;
use crate::{
    CrossingRecord, Event, Motion, Outcome, RockEnd, RockRecord, ScreenCrossing, Tally,
    TrajectoryRow,
};

fn stat(e: &mut Enc, s: &Stat) {
    e.u64(s.count);
    e.u128(s.sum);
    e.f64(s.max);
    e.sparse(&s.hist);
}

fn read_stat(d: &mut Dec<'_>, s: &mut Stat) -> Result<(), DecodeError> {
    s.count = d.u64()?;
    s.sum = d.u128()?;
    s.max = d.f64()?;
    d.sparse_into(&mut s.hist, Some)
}

pub(crate) fn body(e: &mut Enc, t: &Tally) {
    let r = &t.rock;
    for &n in &r.outcomes {
        e.u64(n);
    }
    for s in [&r.runout, &r.max_velocity, &r.max_jump, &r.time] {
        stat(e, s);
    }
    for n in [
        r.tree_impacts,
        r.stems_broken,
        r.rebounds,
        r.events,
        r.held_at_release,
    ] {
        e.u64(n);
    }
    for &n in &r.motion_us {
        e.u64(n);
    }
    e.len(t.screens.len());
    for s in &t.screens {
        e.u64(s.rocks);
        e.u64(s.over_capacity);
        e.u64(s.over_height);
        for st in [&s.velocity, &s.energy, &s.height] {
            stat(e, st);
        }
    }
    e.f64(t.profile.bin_m);
    e.len(t.profile.bins.len());
    for b in &t.profile.bins {
        e.sparse(&b.counts);
        e.f64(b.max_ms);
    }
    let mut cells: Vec<&CellStats> = t.cells.touched().collect();
    cells.sort_unstable_by_key(|c| c.cell);
    e.len(cells.len());
    let thresholds = t.cells.thresholds().len();
    let mut next = 0;
    for c in cells {
        cell(e, c, thresholds, next);
        next = c.cell + 1;
    }
    let mut rows: Vec<_> = t.rows.iter().collect();
    rows.sort_unstable_by_key(|(rock, seq, _)| (*rock, *seq));
    e.len(rows.len());
    for (rock, seq, row) in rows {
        e.u64(*rock);
        e.u64(*seq);
        trajectory_row(e, row);
    }
    let mut records: Vec<_> = t.rock_records.iter().collect();
    records.sort_unstable_by_key(|r| r.rock_id);
    e.len(records.len());
    for r in records {
        rock_record(e, r);
    }
    let mut crossings: Vec<_> = t.crossing_records.iter().collect();
    crossings.sort_unstable_by_key(|c| (c.rock_id, c.seq));
    e.len(crossings.len());
    for c in crossings {
        crossing_record(e, c);
    }
}

fn crossing_record(e: &mut Enc, c: &CrossingRecord) {
    e.u64(c.rock_id);
    e.len(c.screen);
    e.u32(c.seq);
    let x = &c.crossing;
    for v in [
        x.velocity_ms,
        x.energy_j,
        x.jump_height_m,
        x.x_m,
        x.y_m,
        c.mass_kg,
    ] {
        e.f64(v);
    }
}

fn read_crossing_record(d: &mut Dec<'_>, screens: usize) -> Result<CrossingRecord, DecodeError> {
    let rock_id = d.u64()?;
    let at = d.pos();
    let screen = d.u64()? as usize;
    if screen >= screens {
        return Err(d.corrupt(at, format!("crossing of screen {screen} of {screens}")));
    }
    let seq = d.u32()?;
    let [velocity_ms, energy_j, jump_height_m, x_m, y_m, mass_kg] =
        [d.f64()?, d.f64()?, d.f64()?, d.f64()?, d.f64()?, d.f64()?];
    Ok(CrossingRecord {
        rock_id,
        screen,
        seq,
        crossing: ScreenCrossing {
            velocity_ms,
            energy_j,
            jump_height_m,
            x_m,
            y_m,
        },
        mass_kg,
    })
}

pub(crate) fn read_body(d: &mut Dec<'_>, t: &mut Tally) -> Result<(), DecodeError> {
    read_head(d, t)?;
    let n = d.len(8)?;
    let len = t.layout().geometry.len();
    let thresholds = t.cells.thresholds().len();
    let mut next = 0;
    for _ in 0..n {
        let c = read_cell(d, thresholds, next)?;
        if c.cell >= len {
            return Err(d.corrupt(d.pos(), format!("cell {} outside the grid", c.cell)));
        }
        next = c.cell + 1;
        t.cells.absorb_owned([c]);
    }
    read_tail(d, t)
}

/// The body up to its cells: per-rock statistics, screens, speed profile.
pub(crate) fn read_head(d: &mut Dec<'_>, t: &mut Tally) -> Result<(), DecodeError> {
    let r = &mut t.rock;
    for n in &mut r.outcomes {
        *n = d.u64()?;
    }
    for s in [
        &mut r.runout,
        &mut r.max_velocity,
        &mut r.max_jump,
        &mut r.time,
    ] {
        read_stat(d, s)?;
    }
    for n in [
        &mut r.tree_impacts,
        &mut r.stems_broken,
        &mut r.rebounds,
        &mut r.events,
        &mut r.held_at_release,
    ] {
        *n = d.u64()?;
    }
    for n in &mut r.motion_us {
        *n = d.u64()?;
    }
    let at = d.pos();
    let screens = d.len(1)?;
    if screens != t.screens.len() {
        return Err(DecodeError::Corrupt {
            offset: at,
            what: format!("{screens} screens, the layout has {}", t.screens.len()),
        });
    }
    for s in &mut t.screens {
        s.rocks = d.u64()?;
        s.over_capacity = d.u64()?;
        s.over_height = d.u64()?;
        for st in [&mut s.velocity, &mut s.energy, &mut s.height] {
            read_stat(d, st)?;
        }
    }
    let bin_m = d.f64()?;
    if bin_m.to_bits() != t.profile.bin_m.to_bits() {
        return Err(d.corrupt(d.pos(), format!("profile bins of {bin_m} m")));
    }
    let bins = d.len(9)?;
    t.profile.bins = Vec::with_capacity(bins);
    for _ in 0..bins {
        let mut h = SpeedHistogram::new();
        d.sparse_into(&mut h.counts, Some)?;
        h.max_ms = d.f64()?;
        t.profile.bins.push(h);
    }
    Ok(())
}

/// The body after its cells: trajectory rows, rock records, screen crossings.
pub(crate) fn read_tail(d: &mut Dec<'_>, t: &mut Tally) -> Result<(), DecodeError> {
    let n = d.len(16)?;
    t.rows.reserve(d.capacity(n, 16));
    for _ in 0..n {
        let (rock, seq) = (d.u64()?, d.u64()?);
        t.rows.push((rock, seq, read_trajectory_row(d)?));
    }
    let n = d.len(8)?;
    t.rock_records.reserve(d.capacity(n, 8));
    for _ in 0..n {
        t.rock_records.push(read_rock_record(d)?);
    }
    let n = d.len(54)?;
    t.crossing_records.reserve(d.capacity(n, 54));
    for _ in 0..n {
        let screens = t.screens.len();
        t.crossing_records.push(read_crossing_record(d, screens)?);
    }
    Ok(())
}

/// Cell `c`, the one before it being `next` − 1 (`next` = 0 for the first): its index is
/// written as the gap from `next`.
fn cell(e: &mut Enc, c: &CellStats, thresholds: usize, next: usize) {
    e.len(c.cell - next);
    for n in [
        c.visits,
        c.reached,
        c.deposited(),
        c.tree_impacts(),
        c.stems_broken(),
    ] {
        e.u64(n);
    }
    e.f64(c.tree_height_max_m());
    e.u128(c.energy_sum);
    e.u128(c.height_sum);
    e.u128(c.energy_sq_sum);
    e.u128(c.height_sq_sum);
    for v in [
        c.energy_max_j,
        c.height_max_m,
        c.velocity_max_ms,
        c.el_angle_max_deg,
    ] {
        e.f64(v);
    }
    if c.hists.is_empty() {
        e.u8(0);
    } else {
        e.u8(1);
        e.sparse_bins(c.hists.energy());
        e.sparse_bins(c.hists.height());
        for k in 0..thresholds {
            e.u64(c.above(k));
        }
    }
    let n = usize::try_from(c.sources.len()).unwrap_or(usize::MAX);
    e.ascending(n, c.sources.iter().map(u64::from));
}

/// A cell written by `cell` after the one before `next` (0 for the first).
pub(crate) fn read_cell(
    d: &mut Dec<'_>,
    thresholds: usize,
    next: usize,
) -> Result<CellStats, DecodeError> {
    let at = d.pos();
    let cell = usize::try_from(d.u64()?)
        .ok()
        .and_then(|gap| next.checked_add(gap))
        .ok_or_else(|| d.corrupt(at, "cell index".into()))?;
    let mut c = CellStats::new(cell);
    c.visits = d.u64()?;
    c.reached = d.u64()?;
    let mut extra = Extra {
        deposited: d.u64()?,
        tree_impacts: d.u64()?,
        stems_broken: d.u64()?,
        tree_height_max_m: d.f64()?,
        ..Extra::default()
    };
    c.energy_sum = d.u128()?;
    c.height_sum = d.u128()?;
    c.energy_sq_sum = d.u128()?;
    c.height_sq_sum = d.u128()?;
    for v in [
        &mut c.energy_max_j,
        &mut c.height_max_m,
        &mut c.velocity_max_ms,
        &mut c.el_angle_max_deg,
    ] {
        *v = d.f64()?;
    }
    if d.u8()? == 1 {
        let energy = d.sparse_bins(ENERGY_BINS)?;
        let height = d.sparse_bins(SHORT_BINS)?;
        c.hists = PackedHists::from_bins(&energy, &height);
        for n in &mut extra.above[..thresholds] {
            *n = d.u64()?;
        }
    }
    if extra.deposited > 0 || extra.tree_impacts > 0 || extra.above.iter().any(|&n| n > 0) {
        c.extra = Some(Box::new(extra));
    }
    let sources = d.ascending(u64::from(u32::MAX))?;
    let sources: Vec<u32> = sources.into_iter().map(|s| s as u32).collect();
    c.sources = SourceSet::from_sorted(sources)
        .ok_or_else(|| d.corrupt(at, format!("sources of cell {cell} not ascending")))?;
    Ok(c)
}

const EVENTS: [Event; 5] = [
    Event::Flight,
    Event::Impact,
    Event::Roll,
    Event::Tree,
    Event::Stop,
];

fn trajectory_row(e: &mut Enc, r: &TrajectoryRow) {
    e.u64(r.rock_id);
    for v in r.values() {
        e.f64(v);
    }
    e.u8(EVENTS.iter().position(|&k| k == r.event).unwrap_or(0) as u8);
}

fn read_trajectory_row(d: &mut Dec<'_>) -> Result<TrajectoryRow, DecodeError> {
    let rock_id = d.u64()?;
    let mut v = [0.0; 12];
    for x in &mut v {
        *x = d.f64()?;
    }
    let at = d.pos();
    let k = d.u8()?;
    let event = *(EVENTS.get(k as usize)).ok_or_else(|| d.corrupt(at, format!("event {k}")))?;
    Ok(TrajectoryRow::from_values(rock_id, v, event))
}

fn rock_record(e: &mut Enc, r: &RockRecord) {
    e.u64(r.rock_id);
    e.len(r.source_cell);
    for v in r.start_m {
        e.f64(v);
    }
    e.f64(r.volume_m3);
    e.f64(r.mass_kg);
    let end = &r.end;
    let (kind, cell) = match end.outcome {
        Outcome::Stopped { cell } => (0, cell),
        Outcome::NetStopped { cell } => (1, cell),
        Outcome::LeftDem => (2, 0),
        Outcome::TimeLimit => (3, 0),
        Outcome::Failed => (4, 0),
    };
    e.u8(kind);
    e.len(cell);
    for v in [
        end.x_m,
        end.y_m,
        end.runout_m,
        end.max_velocity_ms,
        end.max_jump_height_m,
        end.time_s,
    ] {
        e.f64(v);
    }
    for n in [end.tree_impacts, end.stems_broken, end.rebounds, end.events] {
        e.u32(n);
    }
    for t in end.motion.as_array() {
        e.f64(t);
    }
}

fn read_rock_record(d: &mut Dec<'_>) -> Result<RockRecord, DecodeError> {
    let rock_id = d.u64()?;
    let source_cell = d.u64()? as usize;
    let start_m = [d.f64()?, d.f64()?, d.f64()?];
    let (volume_m3, mass_kg) = (d.f64()?, d.f64()?);
    let at = d.pos();
    let kind = d.u8()?;
    let cell = d.u64()? as usize;
    let outcome = match kind {
        0 => Outcome::Stopped { cell },
        1 => Outcome::NetStopped { cell },
        2 => Outcome::LeftDem,
        3 => Outcome::TimeLimit,
        4 => Outcome::Failed,
        k => return Err(d.corrupt(at, format!("outcome {k}"))),
    };
    let [
        x_m,
        y_m,
        runout_m,
        max_velocity_ms,
        max_jump_height_m,
        time_s,
    ] = [d.f64()?, d.f64()?, d.f64()?, d.f64()?, d.f64()?, d.f64()?];
    let [tree_impacts, stems_broken, rebounds, events] = [d.u32()?, d.u32()?, d.u32()?, d.u32()?];
    let motion = Motion::from_array([d.f64()?, d.f64()?, d.f64()?, d.f64()?, d.f64()?]);
    Ok(RockRecord {
        rock_id,
        source_cell,
        start_m,
        volume_m3,
        mass_kg,
        end: RockEnd {
            outcome,
            x_m,
            y_m,
            runout_m,
            max_velocity_ms,
            max_jump_height_m,
            tree_impacts,
            stems_broken,
            rebounds,
            time_s,
            events,
            motion,
        },
    })
}

//! The forest-slope rock-shape study of seed 001 §3.4 (fig. 6): one slope, one run per rock
//! shape, compared by run-out and lateral spread.
//!
//! Each shape's run is an ordinary rigid-engine run whose trajectories are all recorded every
//! few hundredths of a second; this module reduces them. Distances are horizontal, measured
//! from each rock's own start along and across the fall line of the (first) release point —
//! the steepest descent of the DEM there:
//!
//! - **run-out**: how far along the fall line the rock ends up (m; the end point is where it
//!   stopped, left the DEM or was at the time limit);
//! - **lateral offset**: the signed distance across the fall line (m, positive to the left
//!   looking downhill); the *spread* of a shape is the standard deviation and the 5–95 %
//!   width of its rocks' final offsets, and its *reach* sideways the largest offset any point
//!   of a rock's path takes (per rock, then its 95th percentile and maximum over rocks).
//!
//! The module is split by responsibility: the recorded paths and the fall-line frame
//! (`path`), the statistics of one shape or class (`shape_stats`), the ranking of the shapes
//! against the paper's (`rank`) and the files of the study (`report`).

mod path;
mod rank;
mod report;
mod shape_stats;

pub use path::{FallLine, RockPath, SlopeRun};
pub use rank::{PAPER_RANKING, PaperRanking, Ranking, ranking};
pub use report::{Study, plan_view, table, write_study};
pub use shape_stats::{Outcomes, SlopeStats, classes};

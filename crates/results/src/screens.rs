//! Evaluation screens: where a rock's plan-view path crosses a screen polyline, and what the
//! rocks were like when they crossed.

use rockfall_scenario::Screen;

use crate::ScreenCrossing;
use crate::hist::{ENERGY_AXIS, ENERGY_SCALE, LENGTH_SCALE, SHORT_AXIS, Stat};

/// One straight piece of a screen polyline.
#[derive(Debug, Clone, Copy)]
struct Piece {
    screen: usize,
    q0: [f64; 2],
    q1: [f64; 2],
    /// The last piece of its polyline: its end vertex belongs to it (t ∈ [0, 1] instead of
    /// [0, 1)), so every vertex belongs to exactly one piece.
    last: bool,
    /// Bounding box (x_min, y_min, x_max, y_max), m.
    bbox: [f64; 4],
}

/// The screens as horizontal (plan-view) polylines, built once and shared read-only by every
/// worker thread.
///
/// Crossing rules (all exact for repeated points, which is what makes consecutive segments
/// of a path report each crossing once):
/// - a path segment `p0 → p1` crosses a screen piece when `p0` and `p1` lie strictly on
///   opposite sides of the piece's line, or when `p0` lies on the line and `p1` does not;
///   `p1` on the line is *not* a crossing of this segment (it is one of the next segment,
///   at `s = 0`). A path touching the screen at a point therefore counts one crossing;
/// - the crossing point must lie on the piece, vertices included, each vertex in one piece
///   only (the one it starts), so a path through a vertex crosses once;
/// - a path segment lying along a screen piece (collinear) does not cross it, nor does a
///   zero-length segment.
///
/// The screen of a net (`Screen::net`) has no pieces: its crossings are the rocks' entries
/// into the net's cells, which the engine reports through [`ScreenSet::net_screen`].
#[derive(Debug, Clone, Default)]
pub struct ScreenSet {
    pieces: Vec<Piece>,
    /// (net id, screen index) of the nets' screens, sorted by id.
    nets: Vec<(u32, usize)>,
}

/// Twice the signed area of triangle (a, b, c): > 0 when c lies left of a → b.
#[inline]
fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

impl ScreenSet {
    /// The screens' polylines (screen index = position in `screens`). Pieces with non-finite
    /// or repeated vertices are skipped.
    pub fn new(screens: &[Screen]) -> ScreenSet {
        let mut pieces = Vec::new();
        let mut nets = Vec::new();
        for (screen, s) in screens.iter().enumerate() {
            if let Some(id) = s.net {
                nets.push((id, screen));
                continue;
            }
            let pts: Vec<[f64; 2]> = s
                .points_m
                .iter()
                .copied()
                .filter(|p| p[0].is_finite() && p[1].is_finite())
                .collect();
            let n = pts.len();
            for (k, w) in pts.windows(2).enumerate() {
                let (q0, q1) = (w[0], w[1]);
                if q0 == q1 {
                    continue;
                }
                pieces.push(Piece {
                    screen,
                    q0,
                    q1,
                    last: k + 2 == n,
                    bbox: [
                        q0[0].min(q1[0]),
                        q0[1].min(q1[1]),
                        q0[0].max(q1[0]),
                        q0[1].max(q1[1]),
                    ],
                });
            }
        }
        nets.sort_unstable();
        nets.dedup_by_key(|n| n.0);
        ScreenSet { pieces, nets }
    }

    /// True when there is no screen polyline to cross (nets' screens aside).
    pub fn is_empty(&self) -> bool {
        self.pieces.is_empty()
    }

    /// Index of the screen of net `id`, when it has one.
    pub fn net_screen(&self, id: u32) -> Option<usize> {
        let k = self.nets.binary_search_by_key(&id, |n| n.0).ok()?;
        Some(self.nets[k].1)
    }

    /// Calls `f(screen_index, s)` for every crossing of the horizontal segment `p0 → p1`
    /// (x, y in m) with a screen polyline, `s` in [0, 1) the fraction along the segment, in
    /// increasing `s` (ties by screen index, then polyline order).
    ///
    /// A crossing exactly at `p1` is *not* reported (it is reported as `s = 0` of the next
    /// segment), so a path split into consecutive segments reports each crossing once. See
    /// the type's documentation for touching and collinear paths.
    pub fn for_each_crossing(&self, p0: [f64; 2], p1: [f64; 2], mut f: impl FnMut(usize, f64)) {
        if p0 == p1 {
            return;
        }
        let bx = [p0[0].min(p1[0]), p0[1].min(p1[1])];
        let by = [p0[0].max(p1[0]), p0[1].max(p1[1])];
        // Allocates only when there is a crossing.
        let mut found: Vec<(f64, usize, usize)> = Vec::new();
        for (i, q) in self.pieces.iter().enumerate() {
            if q.bbox[2] < bx[0] || q.bbox[0] > by[0] || q.bbox[3] < bx[1] || q.bbox[1] > by[1] {
                continue;
            }
            let o0 = orient(q.q0, q.q1, p0);
            let o1 = orient(q.q0, q.q1, p1);
            let straddles =
                (o0 == 0.0 && o1 != 0.0) || (o0 > 0.0 && o1 < 0.0) || (o0 < 0.0 && o1 > 0.0);
            if !straddles {
                continue;
            }
            // Where the path's line meets the piece: q0 and q1 on opposite sides (or on it).
            let u0 = orient(p0, p1, q.q0);
            let u1 = orient(p0, p1, q.q1);
            let on_piece = u0 == 0.0
                || (u1 == 0.0 && q.last)
                || (u0 > 0.0 && u1 < 0.0)
                || (u0 < 0.0 && u1 > 0.0);
            if !on_piece {
                continue;
            }
            let s = if o0 == 0.0 { 0.0 } else { o0 / (o0 - o1) };
            let s = s.clamp(0.0, 1.0 - f64::EPSILON / 2.0);
            found.push((s, q.screen, i));
        }
        found.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        for (s, screen, _) in found {
            f(screen, s);
        }
    }
}

/// What the tally keeps per screen.
#[derive(Debug, Clone)]
pub(crate) struct ScreenStats {
    /// `rock_id + 1` of the last rock that crossed (0: none), to count rocks once.
    last_rock: u64,
    /// Distinct rocks that crossed.
    pub(crate) rocks: u64,
    /// The screen's limits: energy capacity, J, and barrier height, m.
    limits: (Option<f64>, Option<f64>),
    /// Crossings with more kinetic energy than the capacity.
    pub(crate) over_capacity: u64,
    /// Crossings with the centre higher above the ground than the barrier.
    pub(crate) over_height: u64,
    /// Speed at every crossing, m/s.
    pub(crate) velocity: Stat,
    /// Energy at every crossing, J.
    pub(crate) energy: Stat,
    /// Jump height at every crossing, m.
    pub(crate) height: Stat,
}

impl ScreenStats {
    /// Empty statistics of `screen`, with its limits.
    pub(crate) fn new(screen: &Screen) -> ScreenStats {
        ScreenStats {
            last_rock: 0,
            rocks: 0,
            limits: (screen.capacity_kj.map(|e| e * 1e3), screen.height_m),
            over_capacity: 0,
            over_height: 0,
            velocity: Stat::new(&SHORT_AXIS, LENGTH_SCALE),
            energy: Stat::new(&ENERGY_AXIS, ENERGY_SCALE),
            height: Stat::new(&SHORT_AXIS, LENGTH_SCALE),
        }
    }

    pub(crate) fn add(&mut self, rock_key: u64, c: &ScreenCrossing) {
        if self.last_rock != rock_key {
            self.last_rock = rock_key;
            self.rocks += 1;
        }
        self.velocity.add(c.velocity_ms);
        self.energy.add(c.energy_j);
        self.height.add(c.jump_height_m);
        // strictly above: a crossing at exactly the capacity or height is within it
        self.over_capacity += u64::from(self.limits.0.is_some_and(|e| c.energy_j > e));
        self.over_height += u64::from(self.limits.1.is_some_and(|h| c.jump_height_m > h));
    }

    pub(crate) fn merge(&mut self, o: &ScreenStats) {
        self.rocks += o.rocks;
        self.over_capacity += o.over_capacity;
        self.over_height += o.over_height;
        self.velocity.merge(&o.velocity);
        self.energy.merge(&o.energy);
        self.height.merge(&o.height);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(points: &[[f64; 2]]) -> ScreenSet {
        ScreenSet::new(&[Screen {
            name: "a".into(),
            points_m: points.to_vec(),
            capacity_kj: None,
            height_m: None,
            net: None,
        }])
    }

    fn crossings(s: &ScreenSet, p0: [f64; 2], p1: [f64; 2]) -> Vec<(usize, f64)> {
        let mut v = Vec::new();
        s.for_each_crossing(p0, p1, |i, s| v.push((i, s)));
        v
    }

    /// Crossings of a path split into consecutive segments.
    fn path(s: &ScreenSet, pts: &[[f64; 2]]) -> usize {
        pts.windows(2).map(|w| crossings(s, w[0], w[1]).len()).sum()
    }

    #[test]
    fn two_piece_polyline() {
        // A "V": (0, 10) → (5, 0) → (10, 10).
        let s = set(&[[0.0, 10.0], [5.0, 0.0], [10.0, 10.0]]);
        assert!(!s.is_empty());
        // Once, through the left arm at its middle.
        assert_eq!(crossings(&s, [0.0, 5.0], [5.0, 5.0]), vec![(0, 0.5)]);
        // Twice, through both arms, in increasing s.
        let c = crossings(&s, [-1.0, 5.0], [11.0, 5.0]);
        assert_eq!(c.len(), 2);
        assert!(c[0].1 < c[1].1);
        assert!((c[0].1 - 3.5 / 12.0).abs() < 1e-12 && (c[1].1 - 8.5 / 12.0).abs() < 1e-12);
        // Touching at the end point: not reported; the next segment reports it at s = 0.
        assert!(crossings(&s, [0.0, 5.0], [2.5, 5.0]).is_empty());
        assert_eq!(crossings(&s, [2.5, 5.0], [5.0, 5.0]), vec![(0, 0.0)]);
        // Parallel to the left arm (and beside it): nothing.
        assert!(crossings(&s, [-1.0, 10.0], [4.0, 0.0]).is_empty());
        // Collinear with the left arm: nothing.
        assert!(crossings(&s, [0.0, 10.0], [2.5, 5.0]).is_empty());
        // Missing the screen: nothing; zero-length segment: nothing.
        assert!(crossings(&s, [0.0, 11.0], [10.0, 11.0]).is_empty());
        assert!(crossings(&s, [2.5, 5.0], [2.5, 5.0]).is_empty());
        // Beyond the end of the polyline.
        assert!(crossings(&s, [11.0, 5.0], [12.0, 5.0]).is_empty());
    }

    #[test]
    fn consecutive_segments_report_a_shared_point_once() {
        let s = set(&[[0.0, 10.0], [5.0, 0.0], [10.0, 10.0]]);
        // Split exactly on the left arm.
        assert_eq!(path(&s, &[[0.0, 5.0], [2.5, 5.0], [5.0, 5.0]]), 1);
        // Split on the screen and then back (touch): one crossing.
        assert_eq!(path(&s, &[[0.0, 5.0], [2.5, 5.0], [0.0, 6.0]]), 1);
        // Straight through the vertex (5, 0), split there and not split.
        assert_eq!(path(&s, &[[5.0, -5.0], [5.0, 0.0], [5.0, 5.0]]), 1);
        assert_eq!(path(&s, &[[5.0, -5.0], [5.0, 5.0]]), 1);
        // Through the far end vertex (10, 10), which belongs to the last piece.
        assert_eq!(path(&s, &[[9.0, 11.0], [11.0, 9.0]]), 1);
        assert_eq!(path(&s, &[[9.0, 11.0], [10.0, 10.0], [11.0, 9.0]]), 1);
        // Through the start vertex (0, 10).
        assert_eq!(path(&s, &[[-1.0, 9.0], [0.0, 10.0], [1.0, 11.0]]), 1);
        // A wiggly path split at many points crosses a slanted screen exactly once.
        let line = set(&[[0.1, 0.3], [9.7, 1.9]]);
        let pts: Vec<[f64; 2]> = (0..=1000)
            .map(|i| {
                let t = f64::from(i) / 1000.0;
                [5.0 + 0.3 * (17.0 * t).sin(), 7.0 * t - 3.0]
            })
            .collect();
        assert_eq!(path(&line, &pts), 1);
    }

    #[test]
    fn several_screens_sorted_by_s() {
        let s = ScreenSet::new(&[
            Screen {
                name: "far".into(),
                points_m: vec![[8.0, -1.0], [8.0, 1.0]],
                capacity_kj: None,
                height_m: None,
                net: None,
            },
            Screen {
                name: "near".into(),
                points_m: vec![[2.0, -1.0], [2.0, 1.0]],
                capacity_kj: None,
                height_m: None,
                net: None,
            },
        ]);
        assert_eq!(
            crossings(&s, [0.0, 0.0], [10.0, 0.0]),
            vec![(1, 0.2), (0, 0.8)]
        );
        assert!(ScreenSet::new(&[]).is_empty());
    }
}

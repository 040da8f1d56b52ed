//! Clipping to the plotting window. Plotters clamps out-of-range coordinates onto the
//! window's border, which would distort lines and pile points up on the edges, so everything
//! is clipped (or filtered) before it is drawn.

use crate::range::Span;

/// A point in data coordinates.
pub(crate) type Point = (f64, f64);

/// The rectangular plotting window in data coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Window {
    /// Horizontal extent.
    pub x: Span,
    /// Vertical extent.
    pub y: Span,
}

impl Window {
    /// Whether `p` is finite and inside the window (borders included).
    pub fn contains(&self, (x, y): Point) -> bool {
        x >= self.x.lo && x <= self.x.hi && y >= self.y.lo && y <= self.y.hi
    }

    /// The part of the segment `a`–`b` inside the window (Liang–Barsky), or `None` if there is
    /// none or an end is not finite.
    pub fn clip_segment(&self, a: Point, b: Point) -> Option<(Point, Point)> {
        if ![a.0, a.1, b.0, b.1].iter().all(|v| v.is_finite()) {
            return None;
        }
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let edges = [
            (-dx, a.0 - self.x.lo),
            (dx, self.x.hi - a.0),
            (-dy, a.1 - self.y.lo),
            (dy, self.y.hi - a.1),
        ];
        for (p, q) in edges {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
            } else if p < 0.0 {
                t0 = t0.max(q / p);
            } else {
                t1 = t1.min(q / p);
            }
        }
        (t0 <= t1).then(|| {
            let at = |t: f64| (a.0 + t * dx, a.1 + t * dy);
            (at(t0), at(t1))
        })
    }

    /// The visible pieces of a polyline: split where a point is not finite or the line leaves
    /// the window. Pieces have at least two points.
    pub fn clip_polyline(&self, points: &[Point]) -> Vec<Vec<Point>> {
        let mut pieces: Vec<Vec<Point>> = Vec::new();
        let mut current: Vec<Point> = Vec::new();
        for pair in points.windows(2) {
            match self.clip_segment(pair[0], pair[1]) {
                Some((a, b)) if current.last() == Some(&a) => current.push(b),
                Some((a, b)) => {
                    flush(&mut pieces, &mut current);
                    current.extend([a, b]);
                }
                None => flush(&mut pieces, &mut current),
            }
        }
        flush(&mut pieces, &mut current);
        pieces
    }
}

/// Moves a finished piece (if it has a segment) into `pieces`.
fn flush(pieces: &mut Vec<Vec<Point>>, current: &mut Vec<Point>) {
    if current.len() >= 2 {
        pieces.push(std::mem::take(current));
    } else {
        current.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Window {
        Window {
            x: Span { lo: 0.0, hi: 1.0 },
            y: Span { lo: 0.0, hi: 1.0 },
        }
    }

    #[test]
    fn segments_are_clipped_to_the_window() {
        let w = unit();
        assert_eq!(
            w.clip_segment((-1.0, 0.5), (2.0, 0.5)),
            Some(((0.0, 0.5), (1.0, 0.5)))
        );
        assert_eq!(w.clip_segment((-1.0, 2.0), (2.0, 2.0)), None);
        assert_eq!(w.clip_segment((0.5, f64::NAN), (0.5, 0.5)), None);
    }

    #[test]
    fn polylines_split_at_gaps_and_exits() {
        let w = unit();
        let pts = [
            (0.1, 0.1),
            (0.2, 0.2),
            (f64::NAN, 0.0),
            (0.3, 0.3),
            (0.4, 0.4),
            (0.5, 0.5),
            (0.5, 3.0),
            (0.6, 3.0),
            (0.6, 0.5),
        ];
        let pieces = w.clip_polyline(&pts);
        assert_eq!(pieces.len(), 3, "{pieces:?}");
        assert_eq!(pieces[1], [(0.3, 0.3), (0.4, 0.4), (0.5, 0.5), (0.5, 1.0)]);
        assert_eq!(pieces[2], [(0.6, 1.0), (0.6, 0.5)]);
    }
}

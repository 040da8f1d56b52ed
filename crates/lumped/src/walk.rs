//! Walking a straight horizontal ray across a square lattice, cell by cell (Amanatides & Woo
//! 1987). Used for the DEM's bilinear patches (lattice on the cell centres) and for its cells
//! (lattice on the cell corners): a path is never stepped past a cell.

/// One lattice cell crossed by the ray: column `i` from the lattice origin eastward, row `j`
/// northward, entered at parameter `s_a` and left at `s_b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// Column index (may be negative or beyond the lattice: the caller checks).
    pub i: i64,
    /// Row index counted northward from the origin.
    pub j: i64,
    /// Parameter where the ray enters the cell.
    pub s_a: f64,
    /// Parameter where the ray leaves the cell (or `s_max`).
    pub s_b: f64,
}

/// The ray `(x0 + dx·s, y0 + dy·s)` for `s` in `[0, s_max]` over the lattice with origin
/// `(ox, oy)` and spacing `h`.
#[derive(Debug, Clone)]
pub struct Walk {
    i: i64,
    j: i64,
    step_i: i64,
    step_j: i64,
    next_x: f64,
    next_y: f64,
    delta_x: f64,
    delta_y: f64,
    s: f64,
    s_max: f64,
    done: bool,
}

impl Walk {
    /// A walk; `snap` lattice units of tolerance put a start point that lies on the far edge
    /// of the lattice back into its last cell (see [`Walk::clamp_start`]).
    pub fn new(origin: (f64, f64), h: f64, start: (f64, f64), dir: (f64, f64), s_max: f64) -> Walk {
        let u = (start.0 - origin.0) / h;
        let v = (start.1 - origin.1) / h;
        let (i, step_i, next_x, delta_x) = axis(u, dir.0 / h);
        let (j, step_j, next_y, delta_y) = axis(v, dir.1 / h);
        Walk {
            i,
            j,
            step_i,
            step_j,
            next_x,
            next_y,
            delta_x,
            delta_y,
            s: 0.0,
            s_max,
            done: s_max.is_nan() || s_max < 0.0,
        }
    }

    /// Moves a start index that lies on the upper bound `max_i + 1`/`max_j + 1` (a point on
    /// the east or north rim) into the last valid cell when the ray does not move along that
    /// axis, so rims belong to the lattice. (A ray moving back from the rim enters the last
    /// cell by itself after a zero-length first step; one moving outward leaves at once.)
    pub fn clamp_start(&mut self, max_i: i64, max_j: i64) {
        if self.i == max_i + 1 && self.step_i == 0 {
            self.i = max_i;
        }
        if self.j == max_j + 1 && self.step_j == 0 {
            self.j = max_j;
        }
    }
}

/// Start cell, step, parameter of the first boundary and parameter per cell along one axis.
fn axis(u: f64, du: f64) -> (i64, i64, f64, f64) {
    let i = u.floor() as i64;
    if du > 0.0 {
        (i, 1, ((i + 1) as f64 - u) / du, 1.0 / du)
    } else if du < 0.0 {
        // on a boundary moving backward, the ray is already leaving cell i
        (i, -1, (i as f64 - u) / du, -1.0 / du)
    } else {
        (i, 0, f64::INFINITY, f64::INFINITY)
    }
}

impl Iterator for Walk {
    type Item = Crossing;

    #[inline]
    fn next(&mut self) -> Option<Crossing> {
        if self.done {
            return None;
        }
        let s_a = self.s;
        let exit = self.next_x.min(self.next_y);
        let item = Crossing {
            i: self.i,
            j: self.j,
            s_a,
            s_b: exit.min(self.s_max),
        };
        if exit >= self.s_max {
            self.done = true;
        } else if self.next_x <= self.next_y {
            self.i += self.step_i;
            self.s = self.next_x;
            self.next_x += self.delta_x;
        } else {
            self.j += self.step_j;
            self.s = self.next_y;
            self.next_y += self.delta_y;
        }
        Some(item)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diagonal_walk_visits_cells_in_order_and_covers_the_segment() {
        let w: Vec<_> = Walk::new((0.0, 0.0), 1.0, (0.5, 0.4), (2.0, 1.0), 1.0).collect();
        let cells: Vec<_> = w.iter().map(|c| (c.i, c.j)).collect();
        assert_eq!(cells, vec![(0, 0), (1, 0), (1, 1), (2, 1)]);
        assert_eq!(w[0].s_a, 0.0);
        assert_eq!(w.last().unwrap().s_b, 1.0);
        for pair in w.windows(2) {
            assert_eq!(pair[0].s_b, pair[1].s_a);
        }
    }

    #[test]
    fn backward_and_still() {
        let w: Vec<_> = Walk::new((0.0, 0.0), 2.0, (3.0, 1.0), (-4.0, 0.0), 1.0).collect();
        let cells: Vec<_> = w.iter().map(|c| (c.i, c.j)).collect();
        assert_eq!(cells, vec![(1, 0), (0, 0), (-1, 0)]);
        assert!((w[1].s_a - 0.25).abs() < 1e-12 && (w[2].s_a - 0.75).abs() < 1e-12);
        let still: Vec<_> = Walk::new((0.0, 0.0), 1.0, (0.5, 0.5), (0.0, 0.0), 3.0).collect();
        assert_eq!(still.len(), 1);
        assert_eq!(still[0].s_b, 3.0);
    }

    #[test]
    fn rim_start_is_clamped_into_the_lattice() {
        let mut w = Walk::new((0.0, 0.0), 1.0, (3.0, 1.5), (0.0, 1.0), 0.5);
        w.clamp_start(2, 5);
        assert_eq!(w.next().map(|c| c.i), Some(2));
        // moving back from the rim: a zero-length step outside, then the last cell
        let w: Vec<_> = Walk::new((0.0, 0.0), 1.0, (3.0, 1.5), (-1.0, 0.0), 0.5).collect();
        assert_eq!((w[0].i, w[0].s_b), (3, 0.0));
        assert_eq!((w[1].i, w[1].s_a, w[1].s_b), (2, 0.0, 0.5));
    }
}

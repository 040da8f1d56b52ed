//! What a tile reads of a polygon layer: only the features whose bounding box meets its
//! window. A cell takes a polygon's value when the polygon holds the cell's centre, half a
//! cell inside the window's edge; a polygon whose bounding box misses the window's rectangle
//! holds no such centre, so leaving it out changes no cell of the window. The features kept
//! are in the file's order, which decides overlaps (the later wins).

use super::{Feature, Geometry, Xy};
use rockfall_raster::{GridGeometry, Window};

/// A closed rectangle of the plane in the layer's CRS (m for a DEM's projected CRS).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Envelope {
    /// Western edge, m.
    pub x_min_m: f64,
    /// Southern edge, m.
    pub y_min_m: f64,
    /// Eastern edge, m.
    pub x_max_m: f64,
    /// Northern edge, m.
    pub y_max_m: f64,
}

impl Envelope {
    /// The rectangle of window `w`'s cells (their outer edges) on grid `g`.
    pub fn of_window(g: &GridGeometry, w: &Window) -> Envelope {
        let [x_min_m, y_min_m, x_max_m, y_max_m] = w.bounds_m(g);
        Envelope {
            x_min_m,
            y_min_m,
            x_max_m,
            y_max_m,
        }
    }

    /// The bounding box of a geometry's finite coordinates; `None` for an empty geometry (or
    /// one without a finite coordinate), which burns no cell.
    pub fn of_geometry(geometry: &Geometry) -> Option<Envelope> {
        let mut b = Envelope {
            x_min_m: f64::INFINITY,
            y_min_m: f64::INFINITY,
            x_max_m: f64::NEG_INFINITY,
            y_max_m: f64::NEG_INFINITY,
        };
        let mut add = |p: &Xy| {
            if p[0].is_finite() && p[1].is_finite() {
                b.x_min_m = b.x_min_m.min(p[0]);
                b.x_max_m = b.x_max_m.max(p[0]);
                b.y_min_m = b.y_min_m.min(p[1]);
                b.y_max_m = b.y_max_m.max(p[1]);
            }
        };
        match geometry {
            Geometry::Empty => {}
            Geometry::Points(ps) => ps.iter().for_each(&mut add),
            Geometry::Lines(ls) => ls.iter().flatten().for_each(&mut add),
            Geometry::Polygons(ps) => ps.iter().flatten().flatten().for_each(&mut add),
        }
        (b.x_min_m <= b.x_max_m).then_some(b)
    }

    /// True when the two closed rectangles share a point.
    pub fn meets(&self, other: &Envelope) -> bool {
        self.x_min_m <= other.x_max_m
            && other.x_min_m <= self.x_max_m
            && self.y_min_m <= other.y_max_m
            && other.y_min_m <= self.y_max_m
    }
}

/// Keeps the features whose bounding box meets `within`, in order.
pub(crate) fn keep_meeting(features: &mut Vec<Feature>, within: &Envelope) {
    features.retain(|f| Envelope::of_geometry(&f.geometry).is_some_and(|b| b.meets(within)));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64, side: f64) -> Geometry {
        let ring = vec![
            [x, y],
            [x + side, y],
            [x + side, y + side],
            [x, y + side],
            [x, y],
        ];
        Geometry::Polygons(vec![vec![ring]])
    }

    #[test]
    fn a_window_spans_its_cells_outer_edges() {
        // the window's edges are `Window::bounds_m`'s (tested in rockfall-raster): here, that
        // each lands on its side
        let g = GridGeometry {
            ncols: 10,
            nrows: 8,
            x_min_m: 100.0,
            y_min_m: 200.0,
            cell_size_m: 5.0,
        };
        let e = Envelope::of_window(&g, &Window::whole(&g));
        assert_eq!(
            (e.x_min_m, e.y_min_m, e.x_max_m, e.y_max_m),
            (100.0, 200.0, 150.0, 240.0)
        );
    }

    #[test]
    fn features_are_kept_when_their_box_meets_the_rectangle() {
        let within = Envelope {
            x_min_m: 0.0,
            y_min_m: 0.0,
            x_max_m: 10.0,
            y_max_m: 10.0,
        };
        let feature = |id, geometry| Feature {
            id,
            geometry,
            attributes: Vec::new(),
        };
        let mut fs = vec![
            feature(1, square(-5.0, -5.0, 2.0)),    // south-west, apart
            feature(2, square(9.0, 9.0, 3.0)),      // overlaps the corner
            feature(3, square(10.0, 2.0, 1.0)),     // touches the east edge
            feature(4, square(10.5, 2.0, 1.0)),     // just east
            feature(5, Geometry::Empty),            // burns nothing
            feature(6, square(-20.0, -20.0, 50.0)), // holds the whole rectangle
            feature(7, Geometry::Points(vec![[5.0, 5.0]])),
            feature(8, Geometry::Lines(vec![vec![[5.0, 11.0], [6.0, 12.0]]])),
            feature(9, square(f64::NAN, 3.0, 1.0)), // x not finite: its y alone is no box
        ];
        keep_meeting(&mut fs, &within);
        let ids: Vec<i64> = fs.iter().map(|f| f.id).collect();
        assert_eq!(ids, vec![2, 3, 6, 7]);
        // a point on any edge or corner meets the rectangle; just outside, not
        let point = |x: f64, y: f64| Envelope::of_geometry(&Geometry::Points(vec![[x, y]]));
        for (x, y) in [
            (0.0, 5.0),
            (10.0, 5.0),
            (5.0, 0.0),
            (5.0, 10.0),
            (10.0, 10.0),
        ] {
            assert!(point(x, y).is_some_and(|b| b.meets(&within)), "({x}, {y})");
        }
        for (x, y) in [(-0.01, 5.0), (10.01, 5.0), (5.0, -0.01), (5.0, 10.01)] {
            assert!(point(x, y).is_some_and(|b| !b.meets(&within)), "({x}, {y})");
        }
    }
}

//! A uniform-grid spatial index for "which stems does this rock pass?" queries.
//!
//! # The question
//!
//! Stems are vertical cylinders, so whether a rock can touch a stem is decided in the
//! horizontal plane: a rock of radius r whose centre moves from p₀ to p₁ during a time step can
//! touch a stem of radius ρ only if the stem axis comes within r + ρ of the segment p₀p₁. Both
//! queries here report exactly the stems whose *trunk circle* comes within `r` of a point or a
//! segment, i.e. whose axis distance d satisfies d ≤ r + ρ. Whether the contact happens below
//! the tree top, and where on the trunk, is the engine's business.
//!
//! # The structure
//!
//! The extent of the stems is cut into square buckets (5 m by default, about the spacing of
//! trees in a dense stand, so a bucket holds a handful of stems). Stems are stored sorted by
//! bucket, row-major, with a compressed-sparse-row offset table: the stems of buckets
//! (row, c₀) … (row, c₁) form one contiguous slice, so a query walks a few short, contiguous
//! runs of memory and never allocates. Each entry keeps the stem's position in the slice the
//! index was built from, reported as [`StemHit::index`].
//!
//! # Segment traversal
//!
//! With `reach` = r + the largest stem radius, a stem in bucket row j can only be hit from the
//! part of the segment whose y lies in that row's band widened by `reach`. So for each bucket
//! row the segment is clipped to the widened band, and the clipped piece's x-range, widened by
//! `reach`, gives one contiguous run of bucket columns. Every bucket is visited at most once,
//! and the cost grows with the segment's length, not with the area of its bounding box.
//!
//! Queries partly or wholly outside the indexed extent are clipped to it; bucket ranges are
//! widened by a rounding margin so that floating-point error never drops a stem. Queries with
//! a NaN or negative-enough radius, non-finite coordinates, or coordinates so large (beyond
//! about 10¹⁵⁰ m) that the squared segment length overflows, report nothing.

use crate::{ForestError, Stem};

/// Default bucket edge length, m.
pub const DEFAULT_BUCKET_SIZE_M: f64 = 5.0;

/// Buckets allowed regardless of the number of stems; beyond `max(4 × stems, this)` the
/// bucket size is doubled until the grid fits (a few stems spread over a huge area).
const MIN_BUCKET_CAP: usize = 1 << 16;

/// Relative rounding margin added to query ranges (a few thousand ulps).
const ROUNDING_MARGIN: f64 = 1e-12;

/// A stem reported by a query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StemHit {
    /// Position of the stem in the slice the index was built from.
    pub index: usize,
    /// Horizontal distance from the stem axis to the query point or segment, m.
    pub distance_m: f64,
    /// Segment parameter of the closest point, 0 at p₀ to 1 at p₁ (0 for point queries).
    pub t: f64,
}

/// One stem as stored in the index.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Entry {
    x_m: f64,
    y_m: f64,
    radius_m: f64,
    index: usize,
}

/// Stems bucketed on a uniform grid, for point and segment proximity queries.
#[derive(Debug, Clone, PartialEq)]
pub struct StemIndex {
    x_min_m: f64,
    y_min_m: f64,
    bucket_size_m: f64,
    ncols: usize,
    nrows: usize,
    /// `offsets[b]..offsets[b + 1]` are the entries of bucket b (row-major, row 0 south).
    offsets: Vec<usize>,
    entries: Vec<Entry>,
    max_radius_m: f64,
    /// Largest absolute coordinate of the extent, m (scales the rounding margin).
    magnitude_m: f64,
}

impl StemIndex {
    /// Indexes `stems` with buckets of `bucket_size_m` (m, finite and > 0). The size is
    /// doubled as often as needed to keep the bucket count below `max(4 × stems, 65 536)`;
    /// [`StemIndex::bucket_size_m`] tells the size used.
    ///
    /// Fails when the bucket size is invalid, a stem has a non-finite position or a negative
    /// or non-finite radius, or the extent is too large to represent.
    pub fn new(stems: &[Stem], bucket_size_m: f64) -> Result<Self, ForestError> {
        if !(bucket_size_m.is_finite() && bucket_size_m > 0.0) {
            return Err(ForestError::InvalidBucketSize { bucket_size_m });
        }
        let mut x_min = f64::INFINITY;
        let mut y_min = f64::INFINITY;
        let mut x_max = f64::NEG_INFINITY;
        let mut y_max = f64::NEG_INFINITY;
        let mut max_radius_m: f64 = 0.0;
        for (index, stem) in stems.iter().enumerate() {
            let radius = stem.radius_m();
            if !(stem.x_m.is_finite() && stem.y_m.is_finite()) {
                return Err(ForestError::InvalidStem {
                    index,
                    reason: format!("position ({}, {}) m is not finite", stem.x_m, stem.y_m),
                });
            }
            if !(radius.is_finite() && radius >= 0.0) {
                return Err(ForestError::InvalidStem {
                    index,
                    reason: format!("DBH {} cm is negative or not finite", stem.dbh_cm),
                });
            }
            x_min = x_min.min(stem.x_m);
            y_min = y_min.min(stem.y_m);
            x_max = x_max.max(stem.x_m);
            y_max = y_max.max(stem.y_m);
            max_radius_m = max_radius_m.max(radius);
        }
        if stems.is_empty() {
            return Ok(StemIndex {
                x_min_m: 0.0,
                y_min_m: 0.0,
                bucket_size_m,
                ncols: 0,
                nrows: 0,
                offsets: vec![0],
                entries: Vec::new(),
                max_radius_m: 0.0,
                magnitude_m: 0.0,
            });
        }
        let (width, height) = (x_max - x_min, y_max - y_min);
        if !(width.is_finite() && height.is_finite()) {
            return Err(ForestError::ExtentTooLarge {
                width_m: width,
                height_m: height,
            });
        }
        let cap = (4 * stems.len()).max(MIN_BUCKET_CAP) as f64;
        let mut size = bucket_size_m;
        let (ncols, nrows) = loop {
            let nc = (width / size).floor() + 1.0;
            let nr = (height / size).floor() + 1.0;
            if nc * nr <= cap {
                break (nc as usize, nr as usize);
            }
            size *= 2.0;
        };

        let bucket_of = |stem: &Stem| {
            let col = (((stem.x_m - x_min) / size).floor() as usize).min(ncols - 1);
            let row = (((stem.y_m - y_min) / size).floor() as usize).min(nrows - 1);
            row * ncols + col
        };
        // Counting sort by bucket; stable, so stems keep their order within a bucket.
        let mut offsets = vec![0usize; ncols * nrows + 1];
        for stem in stems {
            offsets[bucket_of(stem) + 1] += 1;
        }
        for b in 0..ncols * nrows {
            offsets[b + 1] += offsets[b];
        }
        let mut next = offsets.clone();
        let mut entries = vec![
            Entry {
                x_m: 0.0,
                y_m: 0.0,
                radius_m: 0.0,
                index: 0,
            };
            stems.len()
        ];
        for (index, stem) in stems.iter().enumerate() {
            let slot = &mut next[bucket_of(stem)];
            entries[*slot] = Entry {
                x_m: stem.x_m,
                y_m: stem.y_m,
                radius_m: stem.radius_m(),
                index,
            };
            *slot += 1;
        }
        let magnitude_m = x_min
            .abs()
            .max(x_max.abs())
            .max(y_min.abs())
            .max(y_max.abs());
        Ok(StemIndex {
            x_min_m: x_min,
            y_min_m: y_min,
            bucket_size_m: size,
            ncols,
            nrows,
            offsets,
            entries,
            max_radius_m,
            magnitude_m,
        })
    }

    /// Indexes `stems` with [`DEFAULT_BUCKET_SIZE_M`] buckets.
    pub fn with_default_bucket(stems: &[Stem]) -> Result<Self, ForestError> {
        Self::new(stems, DEFAULT_BUCKET_SIZE_M)
    }

    /// Number of indexed stems.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when no stem is indexed.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Bucket edge length actually used, m.
    pub fn bucket_size_m(&self) -> f64 {
        self.bucket_size_m
    }

    /// Bucket grid size as (columns west → east, rows south → north).
    pub fn bucket_dims(&self) -> (usize, usize) {
        (self.ncols, self.nrows)
    }

    /// Largest trunk radius among the stems, m.
    pub fn max_radius_m(&self) -> f64 {
        self.max_radius_m
    }

    /// Calls `f` for every stem whose trunk circle comes within `r_m` (m) of the point
    /// (`x_m`, `y_m`): axis distance ≤ `r_m` + trunk radius. Hits have `t` = 0.
    pub fn for_each_near_point(&self, x_m: f64, y_m: f64, r_m: f64, mut f: impl FnMut(StemHit)) {
        let Some(reach) = self.reach(r_m, x_m.abs().max(y_m.abs())) else {
            return;
        };
        if !(x_m.is_finite() && y_m.is_finite()) {
            return;
        }
        let Some((row0, row1)) = self.rows(y_m - reach, y_m + reach) else {
            return;
        };
        let Some(cols) = self.cols(x_m - reach, x_m + reach) else {
            return;
        };
        for row in row0..=row1 {
            for e in self.run(row, cols) {
                let (dx, dy) = (e.x_m - x_m, e.y_m - y_m);
                if let Some(distance_m) = within(dx * dx + dy * dy, r_m + e.radius_m) {
                    f(StemHit {
                        index: e.index,
                        distance_m,
                        t: 0.0,
                    });
                }
            }
        }
    }

    /// Calls `f` for every stem whose trunk circle comes within `r_m` (m) of the segment from
    /// `p0` to `p1` ((x, y) in m): axis distance to the segment ≤ `r_m` + trunk radius. `t` is
    /// the segment parameter of the closest point (0 for a zero-length segment). Each stem is
    /// reported at most once; the order is deterministic but unspecified.
    pub fn for_each_near_segment(
        &self,
        p0: (f64, f64),
        p1: (f64, f64),
        r_m: f64,
        mut f: impl FnMut(StemHit),
    ) {
        let (x0, y0) = p0;
        let (dx, dy) = (p1.0 - x0, p1.1 - y0);
        let len2 = dx * dx + dy * dy;
        let largest = x0.abs().max(y0.abs()).max(p1.0.abs()).max(p1.1.abs());
        let Some(reach) = self.reach(r_m, largest) else {
            return;
        };
        if !(largest.is_finite() && len2.is_finite()) {
            return;
        }
        let Some((row0, row1)) = self.rows(y0.min(p1.1) - reach, y0.max(p1.1) + reach) else {
            return;
        };
        for row in row0..=row1 {
            // Clip the segment to the row's band widened by `reach`.
            let band_lo = self.y_min_m + row as f64 * self.bucket_size_m - reach;
            let band_hi = band_lo + self.bucket_size_m + 2.0 * reach;
            let (t_lo, t_hi) = if dy == 0.0 {
                (0.0, 1.0)
            } else {
                let (ta, tb) = ((band_lo - y0) / dy, (band_hi - y0) / dy);
                (ta.min(tb).max(0.0), ta.max(tb).min(1.0))
            };
            if t_lo > t_hi {
                continue;
            }
            let (xa, xb) = (x0 + t_lo * dx, x0 + t_hi * dx);
            let Some(cols) = self.cols(xa.min(xb) - reach, xa.max(xb) + reach) else {
                continue;
            };
            for e in self.run(row, cols) {
                let (px, py) = (e.x_m - x0, e.y_m - y0);
                let t = if len2 > 0.0 {
                    ((px * dx + py * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let (ex, ey) = (t * dx - px, t * dy - py);
                if let Some(distance_m) = within(ex * ex + ey * ey, r_m + e.radius_m) {
                    f(StemHit {
                        index: e.index,
                        distance_m,
                        t,
                    });
                }
            }
        }
    }

    /// The hits of [`StemIndex::for_each_near_point`], collected (allocates).
    pub fn within_point(&self, x_m: f64, y_m: f64, r_m: f64) -> Vec<StemHit> {
        let mut hits = Vec::new();
        self.for_each_near_point(x_m, y_m, r_m, |hit| hits.push(hit));
        hits
    }

    /// The hits of [`StemIndex::for_each_near_segment`], collected (allocates).
    pub fn within_segment(&self, p0: (f64, f64), p1: (f64, f64), r_m: f64) -> Vec<StemHit> {
        let mut hits = Vec::new();
        self.for_each_near_segment(p0, p1, r_m, |hit| hits.push(hit));
        hits
    }

    /// Search distance r + largest radius plus the rounding margin, m; `None` when no stem
    /// can qualify (empty index, NaN or too negative r).
    fn reach(&self, r_m: f64, query_magnitude_m: f64) -> Option<f64> {
        let reach = r_m + self.max_radius_m;
        if self.entries.is_empty() || !(reach.is_finite() && reach >= 0.0) {
            return None;
        }
        let margin =
            ROUNDING_MARGIN * (1.0 + self.magnitude_m + query_magnitude_m.min(f64::MAX) + reach);
        Some(reach + margin)
    }

    /// Bucket rows overlapping [lo, hi] (m), clipped to the grid.
    fn rows(&self, lo: f64, hi: f64) -> Option<(usize, usize)> {
        span(lo, hi, self.y_min_m, self.bucket_size_m, self.nrows)
    }

    /// Bucket columns overlapping [lo, hi] (m), clipped to the grid.
    fn cols(&self, lo: f64, hi: f64) -> Option<(usize, usize)> {
        span(lo, hi, self.x_min_m, self.bucket_size_m, self.ncols)
    }

    /// The entries of buckets (row, c₀) … (row, c₁): one contiguous slice.
    fn run(&self, row: usize, (c0, c1): (usize, usize)) -> &[Entry] {
        let first = row * self.ncols;
        &self.entries[self.offsets[first + c0]..self.offsets[first + c1 + 1]]
    }
}

/// Buckets of size `size` from `origin` overlapping [lo, hi], clipped to 0..n.
fn span(lo: f64, hi: f64, origin: f64, size: f64, n: usize) -> Option<(usize, usize)> {
    let first = ((lo - origin) / size).floor();
    let last = ((hi - origin) / size).floor();
    let max = n.checked_sub(1)? as f64;
    if !(first <= last && last >= 0.0 && first <= max) {
        return None;
    }
    Some((first.max(0.0) as usize, last.min(max) as usize))
}

/// The distance √`d2` when it is at most `limit` (m), else `None`.
#[inline]
fn within(d2: f64, limit: f64) -> Option<f64> {
    (limit >= 0.0 && d2 <= limit * limit).then(|| d2.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Species;

    fn stem(x_m: f64, y_m: f64, dbh_cm: f64) -> Stem {
        Stem {
            x_m,
            y_m,
            dbh_cm,
            height_m: 20.0,
            species: Species::Unknown,
        }
    }

    fn indices(mut hits: Vec<StemHit>) -> Vec<usize> {
        hits.sort_by_key(|h| h.index);
        hits.into_iter().map(|h| h.index).collect()
    }

    #[test]
    fn point_query_counts_the_trunk_radius() {
        // A 40 cm stem (radius 0.2 m) at the origin, another 10 m east.
        let stems = [stem(0.0, 0.0, 40.0), stem(10.0, 0.0, 40.0)];
        let index = StemIndex::with_default_bucket(&stems).expect("valid");
        assert_eq!(
            indices(index.within_point(1.0, 0.0, 0.79)),
            Vec::<usize>::new()
        );
        let hits = index.within_point(1.0, 0.0, 0.81);
        assert_eq!(indices(hits.clone()), vec![0]);
        assert!((hits[0].distance_m - 1.0).abs() < 1e-15 && hits[0].t == 0.0);
        assert_eq!(indices(index.within_point(5.0, 0.0, 4.9)), vec![0, 1]);
    }

    #[test]
    fn segment_query_reports_closest_parameter() {
        let stems = [
            stem(5.0, 1.0, 20.0),
            stem(5.0, 3.0, 20.0),
            stem(12.0, 0.0, 20.0),
        ];
        let index = StemIndex::new(&stems, 2.0).expect("valid");
        let hits = index.within_segment((0.0, 0.0), (10.0, 0.0), 0.95);
        assert_eq!(hits.len(), 1);
        assert_eq!(hits[0].index, 0);
        assert!((hits[0].t - 0.5).abs() < 1e-15 && (hits[0].distance_m - 1.0).abs() < 1e-15);
        // Past the end: the closest point is p1 (t = 1).
        let hits = index.within_segment((0.0, 0.0), (10.0, 0.0), 1.95);
        let far = hits
            .iter()
            .find(|h| h.index == 2)
            .expect("stem 2 within reach of p1");
        assert_eq!(far.t, 1.0);
        assert!((far.distance_m - 2.0).abs() < 1e-15);
    }

    #[test]
    fn queries_outside_the_extent() {
        let stems = [stem(0.0, 0.0, 30.0), stem(3.0, 4.0, 30.0)];
        let index = StemIndex::with_default_bucket(&stems).expect("valid");
        assert!(index.within_point(-100.0, -100.0, 5.0).is_empty());
        assert_eq!(indices(index.within_point(-2.0, 0.0, 1.9)), vec![0]);
        // A segment passing through the extent from far outside to far outside.
        let hits = index.within_segment((-1e4, 4.0), (1e4, 4.0), 0.1);
        assert_eq!(indices(hits), vec![1]);
        // Entirely outside, parallel to the extent.
        assert!(
            index
                .within_segment((-50.0, 10.0), (50.0, 10.0), 1.0)
                .is_empty()
        );
    }

    #[test]
    fn degenerate_inputs_report_nothing_and_do_not_panic() {
        let stems = [stem(0.0, 0.0, 30.0)];
        let index = StemIndex::with_default_bucket(&stems).expect("valid");
        assert!(index.within_point(f64::NAN, 0.0, 1.0).is_empty());
        assert!(index.within_point(0.0, 0.0, f64::NAN).is_empty());
        assert!(index.within_point(0.0, 0.0, -1.0).is_empty());
        assert!(
            index
                .within_segment((0.0, 0.0), (f64::INFINITY, 0.0), 1.0)
                .is_empty()
        );
        // Absurd magnitudes: no panic (the squared length overflows, nothing is reported).
        let _ = index.within_segment((-1e300, 0.0), (1e300, 0.0), 1.0);
        // Zero-length segment = point.
        assert_eq!(
            indices(index.within_segment((0.5, 0.0), (0.5, 0.0), 0.4)),
            vec![0]
        );
        let empty = StemIndex::with_default_bucket(&[]).expect("empty");
        assert!(empty.is_empty() && empty.within_point(0.0, 0.0, 1e9).is_empty());
    }

    #[test]
    fn construction_checks() {
        assert!(matches!(
            StemIndex::new(&[stem(0.0, 0.0, 30.0)], 0.0),
            Err(ForestError::InvalidBucketSize { .. })
        ));
        assert!(matches!(
            StemIndex::new(&[stem(0.0, 0.0, 30.0), stem(f64::NAN, 0.0, 30.0)], 5.0),
            Err(ForestError::InvalidStem { index: 1, .. })
        ));
        assert!(matches!(
            StemIndex::new(&[stem(-1e308, 0.0, 30.0), stem(1e308, 0.0, 30.0)], 5.0),
            Err(ForestError::ExtentTooLarge { .. })
        ));
        // Two stems 100 km apart on a diagonal: the bucket size grows instead of allocating
        // 4·10⁸ buckets.
        let index =
            StemIndex::new(&[stem(0.0, 0.0, 30.0), stem(1e5, 1e5, 30.0)], 5.0).expect("valid");
        let (nc, nr) = index.bucket_dims();
        assert!(nc * nr <= MIN_BUCKET_CAP && index.bucket_size_m() > 5.0);
        assert_eq!(indices(index.within_point(1e5, 1e5, 0.0)), vec![1]);
    }
}

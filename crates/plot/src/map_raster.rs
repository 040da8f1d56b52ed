//! The pixels of a map's plotting window: the fill, and the overlays drawn straight into them
//! (tree stems and release cells).

use crate::map_figure::{MIN_STEM_SPACING_PX, MapGeometry};

/// Colour of the pixels where the map has no data.
pub(crate) const NO_DATA: (u8, u8, u8) = (235, 235, 235);
/// Colour of the tree stems.
pub(crate) const STEM_GREEN: (u8, u8, u8) = (0, 90, 40);
/// Smallest drawn radius (px) of a tree stem.
const MIN_STEM_RADIUS_PX: f64 = 1.5;
/// Smallest drawn side (px) of a release cell.
const MIN_CELL_SIDE_PX: f64 = 7.0;
/// White.
const WHITE: (u8, u8, u8) = (255, 255, 255);
/// Black.
const BLACK: (u8, u8, u8) = (0, 0, 0);

/// The RGB pixels of a map's plotting window, row by row from the top.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Raster {
    /// `width × height × 3` bytes.
    pub rgb: Vec<u8>,
    /// Width and height (px).
    pub size_px: (u32, u32),
}

impl Raster {
    /// The window of `geo` with each pixel coloured by `fill` at its centre ([`NO_DATA`] where
    /// it gives `None`).
    pub fn filled(geo: &MapGeometry, fill: &dyn Fn(f64, f64) -> Option<(u8, u8, u8)>) -> Self {
        let (w, h) = geo.size_px;
        let mut rgb = Vec::with_capacity(w as usize * h as usize * 3);
        for j in 0..h {
            for i in 0..w {
                let (x_m, y_m) = geo.pixel_centre_m(i, j);
                let (r, g, b) = fill(x_m, y_m).unwrap_or(NO_DATA);
                rgb.extend_from_slice(&[r, g, b]);
            }
        }
        Self {
            rgb,
            size_px: geo.size_px,
        }
    }

    /// Sets pixel `(i, j)` to `colour` if it is inside the raster.
    pub fn put(&mut self, (i, j): (i64, i64), (r, g, b): (u8, u8, u8)) {
        let (w, h) = (i64::from(self.size_px.0), i64::from(self.size_px.1));
        if i < 0 || j < 0 || i >= w || j >= h {
            return;
        }
        let at = 3 * (j * w + i) as usize;
        if let Some(px) = self.rgb.get_mut(at..at + 3) {
            px.copy_from_slice(&[r, g, b]);
        }
    }

    /// Pixel `(i, j)`, if inside the raster.
    #[cfg(test)]
    pub fn get(&self, (i, j): (u32, u32)) -> Option<(u8, u8, u8)> {
        let (w, h) = self.size_px;
        if i >= w || j >= h {
            return None;
        }
        let at = 3 * (j as usize * w as usize + i as usize);
        let px = self.rgb.get(at..at + 3)?;
        Some((px[0], px[1], px[2]))
    }

    /// Fills the pixels whose centres lie within `radius_px` of `centre_px` (continuous pixel
    /// coordinates).
    fn disc(&mut self, (cx, cy): (f64, f64), radius_px: f64, colour: (u8, u8, u8)) {
        let reach = radius_px.ceil() as i64 + 1;
        let (ci, cj) = (cx.floor() as i64, cy.floor() as i64);
        for j in cj - reach..=cj + reach {
            for i in ci - reach..=ci + reach {
                let (dx, dy) = (i as f64 + 0.5 - cx, j as f64 + 0.5 - cy);
                if dx * dx + dy * dy <= radius_px * radius_px {
                    self.put((i, j), colour);
                }
            }
        }
    }

    /// Draws the 1 px outline of the pixel rectangle `i0..=i1 × j0..=j1`.
    fn outline(&mut self, (i0, j0, i1, j1): (i64, i64, i64, i64), colour: (u8, u8, u8)) {
        for i in i0..=i1 {
            self.put((i, j0), colour);
            self.put((i, j1), colour);
        }
        for j in j0..=j1 {
            self.put((i0, j), colour);
            self.put((i1, j), colour);
        }
    }
}

/// Draws the tree stems inside the window as dark green dots with a white ring, if their mean
/// spacing is at least [`MIN_STEM_SPACING_PX`]; returns whether they were drawn.
pub(crate) fn draw_stems(raster: &mut Raster, geo: &MapGeometry, stems_m: &[[f64; 3]]) -> bool {
    let inside = |s: &&[f64; 3]| geo.window.contains((s[0], s[1]));
    let count = stems_m.iter().filter(inside).count();
    if count == 0 {
        return false;
    }
    let (w, h) = geo.size_px;
    let spacing_px = (f64::from(w) * f64::from(h) / count as f64).sqrt();
    if spacing_px < MIN_STEM_SPACING_PX {
        return false;
    }
    for stem in stems_m.iter().filter(inside) {
        // Centred on the pixel holding the stem, so that small dots all look alike.
        let (x_px, y_px) = geo.px_of((stem[0], stem[1]));
        let centre = (x_px.floor() + 0.5, y_px.floor() + 0.5);
        let radius_px = (stem[2] / geo.metres_per_px).max(MIN_STEM_RADIUS_PX);
        raster.disc(centre, radius_px + 1.0, WHITE);
        raster.disc(centre, radius_px, STEM_GREEN);
    }
    true
}

/// Draws the release cells as unfilled squares of `cell_size_m` (at least 7 px): a 2 px black
/// outline with a 1 px white one inside. Returns how many were at least partly in the window.
pub(crate) fn draw_release_cells(
    raster: &mut Raster,
    geo: &MapGeometry,
    cells_m: &[[f64; 2]],
    cell_size_m: f64,
) -> usize {
    let side_px = (cell_size_m / geo.metres_per_px)
        .max(MIN_CELL_SIDE_PX)
        .round() as i64;
    let (w, h) = (i64::from(geo.size_px.0), i64::from(geo.size_px.1));
    let mut drawn = 0;
    for cell in cells_m
        .iter()
        .filter(|c| c[0].is_finite() && c[1].is_finite())
    {
        let (cx, cy) = geo.px_of((cell[0], cell[1]));
        let i0 = (cx - side_px as f64 / 2.0).round() as i64;
        let j0 = (cy - side_px as f64 / 2.0).round() as i64;
        let (i1, j1) = (i0 + side_px - 1, j0 + side_px - 1);
        if i1 < 0 || j1 < 0 || i0 >= w || j0 >= h {
            continue;
        }
        for (inset, colour) in [(0, BLACK), (1, BLACK), (2, WHITE)] {
            raster.outline((i0 + inset, j0 + inset, i1 - inset, j1 - inset), colour);
        }
        drawn += 1;
    }
    drawn
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::clip::Window;
    use crate::range::Span;

    /// A 100 × 100 m map: 780 × 780 px.
    fn square() -> MapGeometry {
        let span = Span { lo: 0.0, hi: 100.0 };
        MapGeometry::new(Window { x: span, y: span })
    }

    #[test]
    fn fill_is_asked_at_pixel_centres_and_none_is_grey() {
        let geo = square();
        let fill = |x: f64, _: f64| (x < 50.0).then_some((200, 0, 0));
        let raster = Raster::filled(&geo, &fill);
        assert_eq!(raster.rgb.len(), 780 * 780 * 3);
        assert_eq!(raster.get((389, 10)), Some((200, 0, 0)));
        assert_eq!(raster.get((390, 10)), Some(NO_DATA));
        assert_eq!(raster.get((780, 10)), None);
    }

    #[test]
    fn only_the_stems_in_the_window_count_for_the_spacing() {
        let geo = square();
        let mut raster = Raster::filled(&geo, &|_, _| Some((0, 0, 200)));
        // 100 stems inside (spacing 78 px) and a dense stand of 100 000 outside the window.
        let mut stems: Vec<[f64; 3]> = (0..100)
            .map(|k| {
                [
                    5.0 + f64::from(k % 10) * 10.0,
                    5.0 + f64::from(k / 10) * 10.0,
                    0.2,
                ]
            })
            .collect();
        stems.extend((0..100_000).map(|k| [200.0 + f64::from(k % 300), 50.0, 0.2]));
        assert!(draw_stems(&mut raster, &geo, &stems));
    }

    #[test]
    fn stems_are_green_dots_with_a_white_ring_and_skipped_when_dense() {
        let geo = square();
        let mut raster = Raster::filled(&geo, &|_, _| Some((0, 0, 200)));
        let stems = [[50.0, 50.0, 0.0], [f64::NAN, 1.0, 1.0], [500.0, 1.0, 1.0]];
        assert!(draw_stems(&mut raster, &geo, &stems));
        // On the corner of pixels 389 and 390: centred on pixel 390; radius 1.5 px (3 × 3),
        // ring to 2.5 px.
        let row: Vec<_> = (387..394).map(|i| raster.get((i, 390)).unwrap()).collect();
        let (g, w, f) = (STEM_GREEN, WHITE, (0, 0, 200));
        assert_eq!(row, [f, w, g, g, g, w, f]);
        assert_eq!(raster.get((391, 391)), Some(g));
        assert_eq!(raster.get((392, 391)), Some(w));
        assert_eq!(raster.get((392, 392)), Some(f));
        let dense = vec![[50.0, 50.0, 0.1]; 780 * 780 / 30];
        assert!(!draw_stems(&mut raster, &geo, &dense));
        assert!(!draw_stems(&mut raster, &geo, &[]));
    }

    #[test]
    fn release_cells_are_outlined_squares() {
        let geo = square();
        let mut raster = Raster::filled(&geo, &|_, _| Some((0, 0, 200)));
        // 0.1 m cells would be under a pixel: drawn 7 px wide, centred on the cell.
        let cells = [[50.0, 50.0], [1e6, 0.0]];
        assert_eq!(draw_release_cells(&mut raster, &geo, &cells, 0.1), 1);
        let row: Vec<_> = (385..396).map(|i| raster.get((i, 390)).unwrap()).collect();
        let fill = (0, 0, 200);
        assert_eq!(
            row,
            [
                fill, fill, BLACK, BLACK, WHITE, fill, WHITE, BLACK, BLACK, fill, fill
            ]
        );
    }
}

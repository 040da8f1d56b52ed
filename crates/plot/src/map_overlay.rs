//! Vector overlays of a map's plotting window, drawn with plotters into its pixels: the
//! labelled lines, the scale bar, the north arrow and the legend.

use plotters::prelude::{
    BLACK, BitMapBackend, Circle, Color, IntoDrawingArea, PathElement, Polygon, Rectangle, Text,
    WHITE,
};
use plotters::style::TextStyle;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::MapLine;
use crate::PlotError;
use crate::clip::Point;
use crate::font::{LABEL_SIZE, TICK_SIZE, font};
use crate::layout::Area;
use crate::map_figure::MapGeometry;
use crate::map_raster::{Raster, STEM_GREEN};
use crate::palette::rgb;
use crate::range::format_tick;

/// Which overlays a map shows, for its legend.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Present {
    /// Release cells were drawn.
    pub release_cells: bool,
    /// Lines were drawn (set by [`draw_overlays`]).
    pub lines: bool,
    /// Stems were drawn.
    pub stems: bool,
}

/// A pixel rectangle `(x0, y0, x1, y1)` of the window.
type Rect = (i32, i32, i32, i32);

/// Distance (px) of the scale bar, north arrow and legend boxes from the window's edges.
const INSET_PX: i32 = 10;
/// Padding (px) inside a box.
const PAD_PX: i32 = 6;
/// Opacity of the white boxes under text.
const BOX_OPACITY: f64 = 0.85;
/// Height (px) of the scale bar.
const SCALE_BAR_HEIGHT_PX: i32 = 8;
/// Length (px) of the north arrow.
const ARROW_LENGTH_PX: i32 = 30;
/// Height (px) of a legend row.
const LEGEND_ROW_PX: i32 = 22;
/// Width (px) of a legend symbol.
const LEGEND_SYMBOL_PX: i32 = 24;
/// Width (px) of a line.
const LINE_WIDTH_PX: u32 = 2;
/// Width (px) of a line's white halo.
const HALO_WIDTH_PX: u32 = 4;

/// Draws the lines, the scale bar, the north arrow and the legend into `raster`.
pub(crate) fn draw_overlays(
    raster: &mut Raster,
    geo: &MapGeometry,
    lines: &[MapLine],
    mut present: Present,
) -> Result<(), PlotError> {
    let size_px = raster.size_px;
    let area = BitMapBackend::with_buffer(&mut raster.rgb, size_px).into_drawing_area();
    present.lines = draw_lines(&area, geo, lines)?;
    let bar_box = draw_scale_bar(&area, geo)?;
    draw_north_arrow(&area)?;
    draw_legend(&area, present, bar_box)?;
    area.present()?;
    Ok(())
}

/// A nice scale-bar length (m) for a window `window_width_m` wide: 1, 2 or 5 × 10^k m,
/// between 1/8 and 1/3 of the width and the closest such length to a quarter of it (by
/// ratio). NaN if the width is not finite and positive.
pub fn scale_bar_length_m(window_width_m: f64) -> f64 {
    if !(window_width_m.is_finite() && window_width_m > 0.0) {
        return f64::NAN;
    }
    let target = window_width_m / 4.0;
    let (lo, hi) = (window_width_m / 8.0, window_width_m / 3.0);
    let distance = |l: &f64| (l / target).ln().abs();
    (lo.log10().floor() as i32..=hi.log10().ceil() as i32)
        .flat_map(|k| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k)))
        .filter(|l| (lo..=hi).contains(l))
        .min_by(|a, b| distance(a).total_cmp(&distance(b)))
        .unwrap_or(target)
}

/// The scale bar's label: `"50 m"`, or kilometres from 1000 m on (`"2 km"`).
fn scale_label(length_m: f64) -> String {
    if length_m >= 1000.0 {
        format!("{} km", format_tick(length_m / 1000.0))
    } else {
        format!("{} m", format_tick(length_m))
    }
}

/// Draws the lines clipped to the window, black over a white halo, then their labels.
/// Returns whether any part of a line was visible.
fn draw_lines(area: &Area<'_>, geo: &MapGeometry, lines: &[MapLine]) -> Result<bool, PlotError> {
    let mut pieces: Vec<(usize, Vec<(i32, i32)>)> = Vec::new();
    for (k, line) in lines.iter().enumerate() {
        let points: Vec<Point> = line.points_m.iter().map(|p| (p[0], p[1])).collect();
        for piece in geo.window.clip_polyline(&points) {
            pieces.push((k, piece.into_iter().map(|p| pixel(geo.px_of(p))).collect()));
        }
    }
    for (style, width) in [(WHITE, HALO_WIDTH_PX), (BLACK, LINE_WIDTH_PX)] {
        for (_, piece) in &pieces {
            area.draw(&PathElement::new(piece.clone(), style.stroke_width(width)))?;
        }
    }
    let mut placed: Vec<Rect> = Vec::new();
    for (k, line) in lines.iter().enumerate() {
        let ends = |piece: Option<&(usize, Vec<(i32, i32)>)>, last: bool| {
            piece
                .and_then(|(_, p)| if last { p.last() } else { p.first() })
                .copied()
        };
        let last = ends(pieces.iter().rev().find(|(i, _)| *i == k), true);
        let first = ends(pieces.iter().find(|(i, _)| *i == k), false);
        if let Some(rect) = place_label(area, &line.label, [last, first], &placed)? {
            draw_label(area, &line.label, rect)?;
            placed.push(rect);
        }
    }
    Ok(!pieces.is_empty())
}

/// The pixel holding a point in continuous pixel coordinates.
fn pixel((x, y): Point) -> (i32, i32) {
    (x.floor() as i32, y.floor() as i32)
}

/// Where the label `text` of a line goes: above its last visible vertex, else above its first,
/// else below the last, else below the first: the first of these boxes that overlaps no box
/// in `placed` (the first one if all do). `None` for an empty label or a line not in view.
fn place_label(
    area: &Area<'_>,
    text: &str,
    vertices: [Option<(i32, i32)>; 2],
    placed: &[Rect],
) -> Result<Option<Rect>, PlotError> {
    if text.is_empty() {
        return Ok(None);
    }
    let style = text_style(TICK_SIZE, Pos::new(HPos::Left, VPos::Top));
    let (tw, th) = area.estimate_text_size(text, &style)?;
    let size = (tw as i32 + 2 * 3, th as i32 + 2 * 3);
    let candidates: Vec<Rect> = [true, false]
        .into_iter()
        .flat_map(|above| {
            let boxes = vertices.into_iter().flatten();
            boxes.map(move |v| label_box(area, size, v, above))
        })
        .collect();
    let free = |r: &Rect| !placed.iter().any(|p| overlaps(*r, *p));
    Ok(candidates
        .iter()
        .copied()
        .find(free)
        .or(candidates.first().copied()))
}

/// Whether two boxes `(x0, y0, x1, y1)` share pixels.
fn overlaps(a: Rect, b: Rect) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// A label box of `(bw, bh)` px next to `vertex`: right of it if it fits (else left), above
/// or below it, kept inside the window.
fn label_box(area: &Area<'_>, (bw, bh): (i32, i32), (vx, vy): (i32, i32), above: bool) -> Rect {
    let (w, h) = window_size(area);
    let right = vx + 6;
    let x0 = if right + bw <= w - 2 {
        right
    } else {
        vx - 6 - bw
    };
    let y0 = if above { vy - 6 - bh } else { vy + 6 };
    let x0 = x0.clamp(2, (w - 2 - bw).max(2));
    let y0 = y0.clamp(2, (h - 2 - bh).max(2));
    (x0, y0, x0 + bw, y0 + bh)
}

/// Draws `text` on a white box `rect`.
fn draw_label(area: &Area<'_>, text: &str, rect: Rect) -> Result<(), PlotError> {
    let style = text_style(TICK_SIZE, Pos::new(HPos::Left, VPos::Top));
    draw_box(area, rect, false)?;
    area.draw(&Text::new(text, (rect.0 + 3, rect.1 + 3), style))?;
    Ok(())
}

/// Black text of `size` px anchored at `anchor`.
fn text_style(size: f64, anchor: Pos) -> TextStyle<'static> {
    font(size).color(&BLACK).pos(anchor)
}

/// The window's size (px) as `i32`.
fn window_size(area: &Area<'_>) -> (i32, i32) {
    let (w, h) = area.dim_in_pixel();
    (w as i32, h as i32)
}

/// Draws a white box at [`BOX_OPACITY`], with a grey border if `border`.
fn draw_box(area: &Area<'_>, (x0, y0, x1, y1): Rect, border: bool) -> Result<(), PlotError> {
    let corners = [(x0, y0), (x1, y1)];
    area.draw(&Rectangle::new(corners, WHITE.mix(BOX_OPACITY).filled()))?;
    if border {
        area.draw(&Rectangle::new(corners, BLACK.mix(0.6)))?;
    }
    Ok(())
}

/// Draws the scale bar in the lower left corner: alternating black and white segments under
/// the length, on a white box. Returns the box.
fn draw_scale_bar(area: &Area<'_>, geo: &MapGeometry) -> Result<Rect, PlotError> {
    let length_m = scale_bar_length_m(geo.window.x.width());
    let length_px = (length_m / geo.metres_per_px).round() as i32;
    let label = scale_label(length_m);
    let style = text_style(TICK_SIZE, Pos::new(HPos::Center, VPos::Top));
    let (tw, th) = area.estimate_text_size(&label, &style)?;
    let inner_w = length_px.max(tw as i32);
    let bh = 2 * PAD_PX + th as i32 + 4 + SCALE_BAR_HEIGHT_PX;
    let (x0, y1) = (INSET_PX, window_size(area).1 - INSET_PX);
    let rect = (x0, y1 - bh, x0 + inner_w + 2 * PAD_PX, y1);
    draw_box(area, rect, true)?;
    let bar_x0 = x0 + PAD_PX + (inner_w - length_px) / 2;
    let (bar_y0, bar_y1) = (y1 - PAD_PX - SCALE_BAR_HEIGHT_PX, y1 - PAD_PX);
    let n = if length_px >= 80 { 4 } else { 2 };
    for k in 0..n {
        let xa = bar_x0 + k * length_px / n;
        let xb = bar_x0 + (k + 1) * length_px / n;
        let colour = if k % 2 == 0 { BLACK } else { WHITE };
        area.draw(&Rectangle::new(
            [(xa, bar_y0), (xb, bar_y1)],
            colour.filled(),
        ))?;
    }
    let outline = [(bar_x0, bar_y0), (bar_x0 + length_px, bar_y1)];
    area.draw(&Rectangle::new(outline, BLACK))?;
    let centre = (bar_x0 + length_px / 2, rect.1 + PAD_PX);
    area.draw(&Text::new(label, centre, style))?;
    Ok(rect)
}

/// Draws the north arrow in the upper right corner: an arrow pointing up under an "N", on a
/// white box.
fn draw_north_arrow(area: &Area<'_>) -> Result<(), PlotError> {
    let style = text_style(LABEL_SIZE, Pos::new(HPos::Center, VPos::Top));
    let (_, th) = area.estimate_text_size("N", &style)?;
    let bh = 2 * PAD_PX + th as i32 + 4 + ARROW_LENGTH_PX;
    let x1 = window_size(area).0 - INSET_PX;
    let (x0, y0) = (x1 - 34, INSET_PX);
    draw_box(area, (x0, y0, x1, y0 + bh), true)?;
    let cx = (x0 + x1) / 2;
    area.draw(&Text::new("N", (cx, y0 + PAD_PX), style))?;
    let tip = y0 + PAD_PX + th as i32 + 4;
    let head = vec![(cx, tip), (cx - 7, tip + 14), (cx + 7, tip + 14)];
    area.draw(&Polygon::new(head, BLACK.filled()))?;
    let shaft = [(cx - 1, tip + 10), (cx + 1, tip + ARROW_LENGTH_PX)];
    area.draw(&Rectangle::new(shaft, BLACK.filled()))?;
    Ok(())
}

/// A legend entry's symbol.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Symbol {
    /// An outlined square: release cells.
    Square,
    /// A haloed line: screens.
    Line,
    /// A green dot: stems.
    Dot,
}

/// Draws the legend of the overlays `present` in the lower right corner, above the scale
/// bar's box `avoid` if they would overlap. Nothing if no overlay is present.
fn draw_legend(area: &Area<'_>, present: Present, avoid: Rect) -> Result<(), PlotError> {
    let entries: Vec<(Symbol, &str)> = [
        (present.release_cells, Symbol::Square, "release"),
        (present.lines, Symbol::Line, "screens"),
        (present.stems, Symbol::Dot, "stems"),
    ]
    .into_iter()
    .filter_map(|(shown, symbol, text)| shown.then_some((symbol, text)))
    .collect();
    if entries.is_empty() {
        return Ok(());
    }
    let style = text_style(TICK_SIZE, Pos::new(HPos::Left, VPos::Center));
    let mut text_w = 0;
    for (_, text) in &entries {
        text_w = text_w.max(area.estimate_text_size(text, &style)?.0 as i32);
    }
    let bw = 2 * PAD_PX + LEGEND_SYMBOL_PX + 6 + text_w;
    let bh = 2 * PAD_PX + LEGEND_ROW_PX * entries.len() as i32;
    let (w, h) = window_size(area);
    let x0 = w - INSET_PX - bw;
    let y1 = if x0 < avoid.2 + 6 {
        avoid.1 - 6
    } else {
        h - INSET_PX
    };
    draw_box(area, (x0, y1 - bh, x0 + bw, y1), true)?;
    for (row, (symbol, text)) in entries.into_iter().enumerate() {
        let cy = y1 - bh + PAD_PX + LEGEND_ROW_PX * row as i32 + LEGEND_ROW_PX / 2;
        draw_symbol(area, symbol, (x0 + PAD_PX + LEGEND_SYMBOL_PX / 2, cy))?;
        // Plotters centres text a little high: 2 px lower lines it up with the symbol.
        let at = (x0 + PAD_PX + LEGEND_SYMBOL_PX + 6, cy + 2);
        area.draw(&Text::new(text, at, style.clone()))?;
    }
    Ok(())
}

/// Draws a legend symbol centred on `(cx, cy)`, looking like the overlay it names.
fn draw_symbol(area: &Area<'_>, symbol: Symbol, (cx, cy): (i32, i32)) -> Result<(), PlotError> {
    match symbol {
        Symbol::Square => {
            for (half, colour) in [(5, BLACK), (4, BLACK), (3, WHITE)] {
                let corners = [(cx - half, cy - half), (cx + half, cy + half)];
                area.draw(&Rectangle::new(corners, colour))?;
            }
        }
        Symbol::Line => {
            let ends = vec![(cx - 11, cy), (cx + 11, cy)];
            for (colour, width) in [(WHITE, HALO_WIDTH_PX), (BLACK, LINE_WIDTH_PX)] {
                area.draw(&PathElement::new(ends.clone(), colour.stroke_width(width)))?;
            }
        }
        Symbol::Dot => {
            area.draw(&Circle::new((cx, cy), 5, WHITE.filled()))?;
            area.draw(&Circle::new((cx, cy), 4, rgb(STEM_GREEN).filled()))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use plotters::prelude::{BitMapBackend, IntoDrawingArea};

    /// A white 300 × 300 m map (780 × 780 px) with the overlays drawn on it.
    fn overlays_on_white() -> (Raster, MapGeometry) {
        use crate::clip::Window;
        use crate::range::Span;
        crate::font::ensure_font().unwrap();
        let span = Span { lo: 0.0, hi: 300.0 };
        let geo = MapGeometry::new(Window { x: span, y: span });
        let mut raster = Raster::filled(&geo, &|_, _| Some((255, 255, 255)));
        draw_overlays(&mut raster, &geo, &[], Present::default()).unwrap();
        (raster, geo)
    }

    fn is_black(p: Option<(u8, u8, u8)>) -> bool {
        p.is_some_and(|(r, g, b)| r < 60 && g < 60 && b < 60)
    }

    #[test]
    fn the_scale_bar_is_as_long_as_its_label_says() {
        let (raster, geo) = overlays_on_white();
        let length_px = scale_bar_length_m(300.0) / geo.metres_per_px; // 100 m: 260 px
        // The bar's row: black from its first segment's left edge to its outline's right edge.
        let y = (geo.size_px.1 as i32 - INSET_PX - PAD_PX - SCALE_BAR_HEIGHT_PX / 2) as u32;
        let black: Vec<u32> = (0..geo.size_px.0 / 2)
            .filter(|&x| is_black(raster.get((x, y))))
            .collect();
        let (first, last) = (black[0], black[black.len() - 1]);
        let drawn = f64::from(last - first);
        assert!(
            (drawn - length_px).abs() <= 2.0,
            "{drawn} px drawn for {length_px} px"
        );
    }

    #[test]
    fn the_north_arrow_points_up() {
        let (raster, geo) = overlays_on_white();
        let (w, _) = geo.size_px;
        let columns = (w - INSET_PX as u32 - 34)..(w - INSET_PX as u32);
        // Widest black run per row inside the arrow's box, below the "N".
        let width = |y: u32| {
            columns
                .clone()
                .filter(|&x| is_black(raster.get((x, y))))
                .count()
        };
        let rows: Vec<(u32, usize)> = (INSET_PX as u32 + 25..INSET_PX as u32 + 75)
            .map(|y| (y, width(y)))
            .filter(|&(_, n)| n > 0)
            .collect();
        // Pointing up: the head (widening rows) lies above its widest row, the thin shaft below.
        let widest = (0..rows.len()).max_by_key(|&i| rows[i].1).unwrap();
        let mean = |r: &[(u32, usize)]| r.iter().map(|x| x.1 as f64).sum::<f64>() / r.len() as f64;
        let (above, below) = (mean(&rows[..widest]), mean(&rows[widest + 1..]));
        assert!(
            above > 1.5 * below,
            "head above {above}, below {below}: {rows:?}"
        );
    }

    #[test]
    fn labels_of_close_lines_do_not_overlap() {
        crate::font::ensure_font().unwrap();
        let mut rgb = vec![255u8; 400 * 300 * 3];
        let area = BitMapBackend::with_buffer(&mut rgb, (400, 300)).into_drawing_area();
        let mut placed = Vec::new();
        // Three horizontal lines 4 px apart, from x = 20 to x = 380.
        for (k, y) in [150, 154, 158].into_iter().enumerate() {
            let label = format!("screen_{k}");
            let rect = place_label(&area, &label, [Some((380, y)), Some((20, y))], &placed)
                .unwrap()
                .unwrap();
            assert!(
                !placed.iter().any(|p| overlaps(rect, *p)),
                "{rect:?} on {placed:?}"
            );
            assert!(rect.0 >= 2 && rect.2 <= 398 && rect.1 >= 2 && rect.3 <= 298);
            placed.push(rect);
        }
        assert_eq!(
            place_label(&area, "", [Some((5, 5)), None], &[]).unwrap(),
            None
        );
        assert!(overlaps((0, 0, 10, 10), (9, 9, 20, 20)));
        assert!(!overlaps((0, 0, 10, 10), (10, 0, 20, 10)));
    }

    #[test]
    fn scale_bars_are_nice_lengths_near_a_quarter_of_the_width() {
        assert_eq!(scale_bar_length_m(355.0), 100.0);
        assert_eq!(scale_bar_length_m(150.0), 50.0);
        assert_eq!(scale_bar_length_m(10_000.0), 2000.0);
        for width_m in [
            0.37, 1.0, 13.2, 150.0, 355.0, 999.0, 4321.0, 10_000.0, 2.6e6,
        ] {
            let l = scale_bar_length_m(width_m);
            assert!(l >= width_m / 8.0 && l <= width_m / 3.0, "{width_m}: {l}");
            let mantissa = l / 10f64.powf(l.log10().floor());
            let nice = [1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-9);
            assert!(nice, "{width_m}: {l}");
        }
        assert!(scale_bar_length_m(0.0).is_nan());
        assert!(scale_bar_length_m(f64::NAN).is_nan());
    }

    #[test]
    fn scale_labels_switch_to_kilometres() {
        assert_eq!(scale_label(50.0), "50 m");
        assert_eq!(scale_label(500.0), "500 m");
        assert_eq!(scale_label(2000.0), "2 km");
        assert_eq!(scale_label(0.5), "0.5 m");
    }
}

//! Rendering into memory and writing the PNG atomically (`rockfall_raster::atomic`).

use std::path::Path;

use image::ImageEncoder;
use image::codecs::png::PngEncoder;
use plotters::prelude::{BitMapBackend, IntoDrawingArea, WHITE};

use crate::PlotError;
use crate::font::ensure_font;
use crate::layout::Area;

/// Renders a `width × height` figure with `draw` (given the white root area) and writes it to
/// `path` as PNG, atomically.
pub(crate) fn render_png(
    path: &Path,
    (width, height): (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> Result<(), PlotError>,
) -> Result<(), PlotError> {
    ensure_font()?;
    let mut rgb = vec![255u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        draw(&root)?;
        root.present()?;
    }
    let png = encode_png(path, &rgb, (width, height))?;
    rockfall_raster::atomic::write_bytes_atomic(path, &png)
        .map_err(|(path, source)| PlotError::Io { path, source })
}

/// Encodes an RGB8 buffer as PNG in memory.
fn encode_png(path: &Path, rgb: &[u8], (width, height): (u32, u32)) -> Result<Vec<u8>, PlotError> {
    let mut png = Vec::new();
    PngEncoder::new(&mut png)
        .write_image(rgb, width, height, image::ColorType::Rgb8)
        .map_err(|e| PlotError::Encode {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
    Ok(png)
}

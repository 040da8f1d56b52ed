//! Rendering into memory and writing the PNG atomically.

use std::io::Write;
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
    write_atomically(path, &png)
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

/// Writes `bytes` to a temporary file in `path`'s folder, then renames it over `path`.
/// The temporary file is removed on every error.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), PlotError> {
    let io_err = |source| PlotError::Io {
        path: path.to_owned(),
        source,
    };
    let mut tmp = temp_builder()
        .tempfile_in(folder_of(path))
        .map_err(io_err)?;
    tmp.write_all(bytes).map_err(io_err)?;
    tmp.as_file().sync_all().map_err(io_err)?;
    tmp.persist(path).map_err(|e| io_err(e.error))?;
    Ok(())
}

/// The folder `path` is in: its parent, or `.` for a bare file name.
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Names temporary files `.rockfall-plot-*.tmp`, created with the permissions of an ordinary
/// new file (read-write for all, less the umask) rather than tempfile's owner-only default.
fn temp_builder() -> tempfile::Builder<'static, 'static> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(".rockfall-plot-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_files_go_next_to_the_target() {
        assert_eq!(folder_of(Path::new("fig.png")), Path::new("."));
        assert_eq!(folder_of(Path::new("out/fig.png")), Path::new("out"));
        assert_eq!(folder_of(Path::new("/fig.png")), Path::new("/"));
    }
}

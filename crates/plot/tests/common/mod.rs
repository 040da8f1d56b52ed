//! Helpers shared by the figure tests: decoding PNGs and looking for colours and text.

#![allow(clippy::unwrap_used, dead_code)]

use std::path::Path;

use image::RgbImage;

/// Decodes a PNG written by the crate.
pub fn decode(path: &Path) -> RgbImage {
    image::open(path).unwrap().to_rgb8()
}

/// Pixels of `img` inside `x0..x1 × y0..y1` within `tol` of `rgb` in every channel.
pub fn count_near(
    img: &RgbImage,
    rgb: (u8, u8, u8),
    tol: u8,
    (x0, y0, x1, y1): (u32, u32, u32, u32),
) -> usize {
    let want = [rgb.0, rgb.1, rgb.2];
    let mut n = 0;
    for y in y0..y1.min(img.height()) {
        for x in x0..x1.min(img.width()) {
            let p = img.get_pixel(x, y).0;
            if p.iter().zip(want).all(|(a, b)| a.abs_diff(b) <= tol) {
                n += 1;
            }
        }
    }
    n
}

/// Pixels of exactly `rgb` anywhere in `img`.
pub fn count_exact(img: &RgbImage, rgb: (u8, u8, u8)) -> usize {
    count_near(img, rgb, 0, (0, 0, img.width(), img.height()))
}

/// Dark (text-like) pixels in the horizontal band `y0..y1`.
pub fn dark_pixels_in_band(img: &RgbImage, y0: u32, y1: u32) -> usize {
    let mut n = 0;
    for y in y0..y1.min(img.height()) {
        for x in 0..img.width() {
            if img.get_pixel(x, y).0.iter().all(|c| *c < 110) {
                n += 1;
            }
        }
    }
    n
}

/// `rgb` drawn with opacity `alpha` over white.
pub fn over_white(rgb: (u8, u8, u8), alpha: f64) -> (u8, u8, u8) {
    let mix = |c: u8| (f64::from(c) * alpha + 255.0 * (1.0 - alpha)).round() as u8;
    (mix(rgb.0), mix(rgb.1), mix(rgb.2))
}

/// Names of the entries of `dir`, sorted.
pub fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

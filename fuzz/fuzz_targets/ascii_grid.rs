//! ESRI ASCII grids: any text must give a grid or an error naming the file, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = rockfall_raster::ascii_grid::parse(text, Path::new("fuzz.asc"));
    }
});

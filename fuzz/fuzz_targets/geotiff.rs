//! GeoTIFFs: a grid or an error naming the file, never a panic nor an allocation the file's
//! data could not fill.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let _ = rockfall_raster::geotiff::decode(data, Path::new("fuzz.tif"));
});

//! GeoJSON layers: a layer or an error naming the file, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let _ = rockfall_io::vector::parse_geojson(data, Path::new("fuzz.geojson"));
});

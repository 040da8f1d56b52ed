//! Shapefiles: the input is split into the `.shp` and the `.dbf` bytes (the first two bytes,
//! little-endian, give the length of the `.shp` part); a layer or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if data.len() < 2 {
        return;
    }
    let n = usize::from(u16::from_le_bytes([data[0], data[1]])).min(data.len() - 2);
    let (shp, dbf) = data[2..].split_at(n);
    let _ = rockfall_io::vector::parse_shapefile(shp, dbf, None, Path::new("fuzz.shp"));
});

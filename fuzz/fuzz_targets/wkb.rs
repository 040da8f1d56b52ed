//! GeoPackage geometry blobs and well-known binary: a geometry or an error, never a panic nor
//! an allocation larger than the blob.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = rockfall_io::vector::wkb::decode_gpkg_geometry(data);
    let _ = rockfall_io::vector::wkb::decode_wkb(data);
});

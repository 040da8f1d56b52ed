//! Our GeoTIFFs are Cloud-Optimised GeoTIFFs that read back bit for bit: the structure GDAL's
//! COG driver writes (tiles, predictor, overview IFDs, the order of IFDs and tile data, the
//! ghost area with tile leaders and trailers) and the overviews' resampling rules, checked
//! here without GDAL (GDAL's own view of the files: `gdal_oracle.rs`).

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use rockfall_raster::{Grid, SampleType, geotiff};
use tiff::decoder::{Decoder, DecodingResult};
use tiff::tags::Tag;

mod common;
use common::{Rule, counts, expected_level, grid, quarters, ramp};

const SIZES: [(usize, usize); 7] = [
    (1, 1),
    (3, 7),
    (256, 256),
    (257, 1),
    (1, 300),
    (255, 257),
    (600, 520),
];

#[test]
fn round_trips_are_bit_exact_for_every_type_and_size() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("g.tif");
    for (ncols, nrows) in SIZES {
        // f64 values need all 53 bits; the grid's own marker sits on a valid cell
        let f64_grid = {
            let mut g = grid(ncols, nrows, |r, c| {
                quarters(r, c).map(|v| v + ((r * ncols + c) as f64).sqrt() * 1e-9)
            });
            g.set_nodata_value(Some(-9999.0));
            g.set(0, 0, -9999.0);
            g
        };
        let cases = [
            (grid(ncols, nrows, quarters), SampleType::F32),
            (f64_grid, SampleType::F64),
            (
                grid(ncols, nrows, |r, c| {
                    quarters(r, c).map(|v| (v * 4.0).round())
                }),
                SampleType::I32,
            ),
        ];
        for (g, sample) in cases {
            geotiff::write(&path, &g, sample).unwrap();
            let back = geotiff::read(&path).unwrap();
            let what = format!("{ncols} × {nrows} {sample:?}");
            assert_eq!(back.geometry(), g.geometry(), "{what}");
            assert_eq!(back.mask(), g.mask(), "{what}");
            assert_eq!(back.crs(), g.crs(), "{what}");
            let bits = |g: &Grid<f64>| {
                g.iter_valid()
                    .map(|(_, _, v)| v.to_bits())
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&back), bits(&g), "{what}");
            // the marker: the grid's unless a valid cell holds it
            let marker = if sample == SampleType::F64 {
                f64::MIN
            } else {
                -9999.0
            };
            let expected = (g.nodata_count() > 0).then_some(marker);
            assert_eq!(back.nodata_value(), expected, "{what}");
            // one input, one file
            let first = std::fs::read(&path).unwrap();
            geotiff::write(&path, &g, sample).unwrap();
            assert!(
                std::fs::read(&path).unwrap() == first,
                "{what}: not deterministic"
            );
        }
    }
}

/// What one IFD of a file says.
#[derive(Debug)]
struct Ifd {
    offset: u64,
    size: (u32, u32),
    tile: (u32, u32),
    subfile: u32,
    predictor: u16,
    compression: u16,
    nodata: Option<String>,
    geokeys: bool,
    offsets: Vec<u64>,
    counts: Vec<u64>,
}

/// Every IFD of a TIFF, in file order.
fn ifds(path: &Path) -> Vec<Ifd> {
    let mut dec = Decoder::new(BufReader::new(File::open(path).unwrap())).unwrap();
    let mut out = Vec::new();
    loop {
        let u16_tag =
            |dec: &mut Decoder<_>, tag| dec.find_tag_unsigned::<u16>(tag).unwrap().unwrap();
        let ifd = Ifd {
            offset: dec.ifd_pointer().unwrap().0,
            size: dec.dimensions().unwrap(),
            tile: (
                dec.get_tag_u32(Tag::TileWidth).unwrap(),
                dec.get_tag_u32(Tag::TileLength).unwrap(),
            ),
            subfile: dec
                .find_tag_unsigned(Tag::NewSubfileType)
                .unwrap()
                .unwrap_or(0),
            predictor: u16_tag(&mut dec, Tag::Predictor),
            compression: u16_tag(&mut dec, Tag::Compression),
            nodata: dec
                .find_tag(Tag::GdalNodata)
                .unwrap()
                .map(|v| v.into_string().unwrap()),
            geokeys: dec.find_tag(Tag::GeoKeyDirectoryTag).unwrap().is_some(),
            offsets: dec
                .find_tag_unsigned_vec(Tag::TileOffsets)
                .unwrap()
                .unwrap(),
            counts: dec
                .find_tag_unsigned_vec(Tag::TileByteCounts)
                .unwrap()
                .unwrap(),
        };
        out.push(ifd);
        if !dec.more_images() {
            return out;
        }
        dec.next_image().unwrap();
    }
}

#[test]
fn the_layout_is_the_one_gdal_validates() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("g.tif");
    // 1 100 × 600: overviews of 550 × 300, 275 × 150 and 138 × 75 (the first ≤ 256 across)
    let g = grid(1100, 600, quarters);
    for (sample, predictor) in [
        (SampleType::F32, 3),
        (SampleType::I32, 2),
        (SampleType::F64, 3),
    ] {
        geotiff::write(&path, &g, sample).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let ifds = ifds(&path);
        let sizes: Vec<(u32, u32)> = ifds.iter().map(|i| i.size).collect();
        assert_eq!(sizes, [(1100, 600), (550, 300), (275, 150), (138, 75)]);
        // the ghost area right after the 8-byte header, the first IFD after it
        let ghost = "GDAL_STRUCTURAL_METADATA_SIZE=000140 bytes\nLAYOUT=IFDS_BEFORE_DATA\n\
                     BLOCK_ORDER=ROW_MAJOR\nBLOCK_LEADER=SIZE_AS_UINT4\n\
                     BLOCK_TRAILER=LAST_4_BYTES_REPEATED\nKNOWN_INCOMPATIBLE_EDITION=NO\n ";
        assert_eq!(&bytes[..4], b"II*\0");
        assert_eq!(&bytes[8..8 + ghost.len()], ghost.as_bytes());
        assert_eq!(ifds[0].offset, 192);
        for (k, ifd) in ifds.iter().enumerate() {
            assert_eq!(ifd.tile, (256, 256));
            assert_eq!((ifd.predictor, ifd.compression), (predictor, 8));
            assert_eq!(ifd.subfile, u32::from(k > 0), "NewSubfileType of IFD {k}");
            assert_eq!(ifd.nodata.as_deref(), Some("-9999"), "IFD {k}");
            assert_eq!(ifd.geokeys, k == 0, "GeoKeys on the first IFD only");
            let tiles = ifd.size.0.div_ceil(256) * ifd.size.1.div_ceil(256);
            assert_eq!(ifd.offsets.len(), tiles as usize);
            // row-major tiles, each with its size before it and its last 4 bytes after it
            assert!(ifd.offsets.windows(2).all(|w| w[0] < w[1]), "IFD {k}");
            for (&o, &n) in ifd.offsets.iter().zip(&ifd.counts) {
                let (o, n) = (o as usize, n as usize);
                assert_eq!(&bytes[o - 4..o], &(n as u32).to_le_bytes());
                assert_eq!(&bytes[o + n..o + n + 4], &bytes[o + n - 4..o + n]);
            }
        }
        // IFDs in order, all before the data; data of the smallest level first
        let last_ifd = ifds.last().unwrap().offset;
        assert!(ifds.windows(2).all(|w| w[0].offset < w[1].offset));
        let starts: Vec<u64> = ifds.iter().map(|i| i.offsets[0]).collect();
        assert!(starts.windows(2).all(|w| w[0] > w[1]), "{starts:?}");
        assert!(*starts.last().unwrap() > last_ifd);
        // and the full resolution's last tile ends the file, trailer included
        let (o, n) = (
            ifds[0].offsets.last().unwrap(),
            ifds[0].counts.last().unwrap(),
        );
        assert_eq!(o + n + 4, bytes.len() as u64);
    }
}

/// The cells of IFD `index` of a single-tile-wide-or-more TIFF, decoded tile by tile.
fn level_values(path: &Path, index: usize) -> (usize, usize, Vec<f64>) {
    let mut dec = Decoder::new(BufReader::new(File::open(path).unwrap())).unwrap();
    dec.seek_to_image(index).unwrap();
    let (w, h) = dec.dimensions().unwrap();
    let (w, h) = (w as usize, h as usize);
    let mut values = vec![f64::NAN; w * h];
    let across = w.div_ceil(256);
    for t in 0..across * h.div_ceil(256) {
        let (tw, th) = dec.chunk_data_dimensions(t as u32);
        let chunk: Vec<f64> = match dec.read_chunk(t as u32).unwrap() {
            DecodingResult::F32(v) => v.into_iter().map(f64::from).collect(),
            DecodingResult::I32(v) => v.into_iter().map(f64::from).collect(),
            other => panic!("{:?}", std::mem::discriminant(&other)),
        };
        let (x0, y0) = ((t % across) * 256, (t / across) * 256);
        for (r, line) in chunk
            .chunks_exact(tw as usize)
            .take(th as usize)
            .enumerate()
        {
            values[(y0 + r) * w + x0..][..line.len()].copy_from_slice(line);
        }
    }
    (w, h, values)
}

#[test]
fn overviews_hold_block_means_of_floats_and_centre_cells_of_integers() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("g.tif");
    // 600 × 520: levels 300 × 260 and 150 × 130
    let g = grid(600, 520, ramp);
    geotiff::write(&path, &g, SampleType::F32).unwrap();
    for k in 1..=2 {
        let (_, _, values) = level_values(&path, k as usize);
        assert_eq!(values, expected_level(&g, k, Rule::MeanF32), "level {k}");
    }
    let (_, _, level2) = level_values(&path, 2);
    assert_eq!(
        level2[2 * 150 + 2],
        -9999.0,
        "the all-nodata block is nodata"
    );
    let counts = grid(600, 520, counts);
    geotiff::write(&path, &counts, SampleType::I32).unwrap();
    for k in 1..=2 {
        let (_, _, values) = level_values(&path, k as usize);
        assert_eq!(
            values,
            expected_level(&counts, k, Rule::Centre),
            "level {k}"
        );
    }
}

#[test]
fn a_grid_that_fits_one_tile_has_no_overview() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("g.tif");
    for (ncols, nrows, levels) in [
        (256, 256, 1),
        (257, 256, 2),
        (1, 1, 1),
        (1, 257, 2),
        (2049, 3, 5),
    ] {
        geotiff::write(&path, &grid(ncols, nrows, quarters), SampleType::F32).unwrap();
        let ifds = ifds(&path);
        assert_eq!(ifds.len(), levels, "{ncols} × {nrows}: {ifds:?}");
        let smallest = ifds.last().unwrap().size;
        assert!(smallest.0 <= 256 && smallest.1 <= 256);
    }
}

#!/usr/bin/env bash
# Writes the vector fixtures of crates/io/tests/vector.rs with GDAL's ogr2ogr, from the
# hand-written GeoJSON sources in src/ (EPSG:2154, on a 12 × 10 grid of 10 m cells with
# its lower-left corner at (900000, 6400000)). Run from this folder; needs gdal-bin.
set -euo pipefail
cd "$(dirname "$0")"
rm -f ./*.gpkg ./*.shp ./*.shx ./*.dbf ./*.prj ./*.cpg ./*.geojson
for layer in stands release trees nets; do
  ogr2ogr -f GeoJSON "$layer.geojson" "src/$layer.geojson" -lco RFC7946=NO
  ogr2ogr -f "ESRI Shapefile" "$layer.shp" "src/$layer.geojson"
  ogr2ogr -f GPKG -update -append site.gpkg "src/$layer.geojson" -nln "$layer" 2>/dev/null \
    || ogr2ogr -f GPKG site.gpkg "src/$layer.geojson" -nln "$layer"
done
# the stands again in WGS 84: a CRS that is not the DEM's
ogr2ogr -f GeoJSON stands_wgs84.geojson src/stands.geojson -t_srs EPSG:4326

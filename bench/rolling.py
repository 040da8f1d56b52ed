#!/usr/bin/env python3
"""The lumped engine's run-out on gentle ground (docs/lumped-model.md rule 13, issue "energy
loss on gentle ground").

PlatRock's test case as we rebuilt it: a 38° planar slope, 100 m long in plan, then 420 m of
flat ground, 2 m cells; a sphere of 1 m (R = 0.5 m, 2650 kg/m³) released from one cell near the
top, 1 m above the ground at rest; obstacle heights 0.0556 m everywhere, so that seed 000
eq. 3 gives r_t = 1/(1 + MOH/R) = 0.9, PlatRock's R_t. Prints the median and 90th percentile
of how far past the slope's foot rocks stop, and the mean of their top speeds:

- for every soil type class 0–7 (the soil's rolling friction, STONE per class);
- for the obstacle heights scaled by 0.5–8 on soil class 4 (the roughness response);
- for `soil_friction_scale = 0` (the roughness term alone, the rule before).

    bench/rolling.py [OUT] [ROCKS]      (default OUT=rolling-study, ROCKS=2000)

ROCKFALL=path/to/rockfall runs that binary (default: target/release/rockfall of this checkout,
built first with `cargo build --release -p rockfall-cli`).
"""
import csv
import math
import os
import statistics
import subprocess
import sys

CELL_M, NCOLS, SLOPE_M, FLAT_M, RG_M = 2.0, 30, 100.0, 420.0, 0.0556


def grid(path, values):
    nrows = len(values)
    with open(path, "w") as f:
        f.write(f"ncols {NCOLS}\nnrows {nrows}\nxllcorner 0\nyllcorner 0\n")
        f.write(f"cellsize {CELL_M}\nNODATA_value -9999\n")
        for row in values:
            f.write(" ".join(row) + "\n")


def site(out):
    nrows = int((SLOPE_M + FLAT_M) / CELL_M)
    top, tan = nrows * CELL_M, math.tan(math.radians(38.0))
    dem = []
    for r in range(nrows):
        d = (r + 0.5) * CELL_M
        dem.append([f"{500.0 - min(d, SLOPE_M) * tan:.4f}"] * NCOLS)
    grid(os.path.join(out, "dem.asc"), dem)
    rel = [["1" if (r == 1 and c == NCOLS // 2) else "0" for c in range(NCOLS)] for r in range(nrows)]
    grid(os.path.join(out, "release.asc"), rel)
    return top - SLOPE_M  # y of the slope's foot


def scenario(out, name, soil=4, rg_scale=1.0, soil_scale=1.0, rocks=2000):
    rg = RG_M * rg_scale
    path = os.path.join(out, f"{name}.toml")
    with open(path, "w") as f:
        f.write(f'name = "{name}"\nengine = "lumped"\nseed = 1\n[terrain]\ndem = "dem.asc"\n')
        f.write(f"soiltype = {soil}\nrg70_m = {rg}\nrg20_m = {rg}\nrg10_m = {rg}\n")
        f.write('[rock]\nshape = "sphere"\ndiameter_m = 1.0\ndensity_kg_m3 = 2650\n')
        f.write('[release]\ncells = "release.asc"\nheight_m = 1.0\n')
        f.write(f"[lumped]\nsoil_friction_scale = {soil_scale}\n")
        f.write(f"[simulation]\nrocks_per_cell = {rocks}\n[output]\nrocks_csv = true\ntrajectories = 0\n")
    return path


def run(binary, out, foot_y, label, **kw):
    path = scenario(out, label.replace(" ", "_").replace("×", "x"), **kw)
    run_dir = path[:-5]
    subprocess.run([binary, "run", path, "--out", run_dir, "--threads", "2"], check=True,
                   stdout=subprocess.DEVNULL)
    rows = list(csv.DictReader(open(os.path.join(run_dir, "rocks.csv"))))
    past = sorted(foot_y - float(r["y_m"]) for r in rows)
    vmax = statistics.mean(float(r["max_velocity_ms"]) for r in rows)
    on_slope = 100.0 * sum(p < 0 for p in past) / len(past)
    print(f"| {label} | {statistics.median(past):.1f} | {past[int(0.9 * len(past))]:.1f} | "
          f"{vmax:.1f} | {on_slope:.0f} |")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "rolling-study"
    rocks = int(sys.argv[2]) if len(sys.argv) > 2 else 2000
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    binary = os.environ.get("ROCKFALL", os.path.join(here, "target", "release", "rockfall"))
    os.makedirs(out, exist_ok=True)
    foot_y = site(out)
    print("| case | median past foot (m) | p90 (m) | mean top speed (m/s) | stopped on the slope (%) |")
    print("|---|--:|--:|--:|--:|")
    for soil in range(8):
        run(binary, out, foot_y, f"soil {soil}", soil=soil, rocks=rocks)
    run(binary, out, foot_y, "soil 4, soil_friction_scale 0", soil_scale=0.0, rocks=rocks)
    for scale in (0.5, 2.0, 4.0, 8.0):
        run(binary, out, foot_y, f"soil 4, rg ×{scale:g}", rg_scale=scale, rocks=rocks)
        run(binary, out, foot_y, f"soil 4, rg ×{scale:g}, soil_friction_scale 0", rg_scale=scale,
            soil_scale=0.0, rocks=rocks)


if __name__ == "__main__":
    main()

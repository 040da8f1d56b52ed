"""The Python package against the command line: the API, bit-for-bit equality of summaries and
rasters on small sites of both engines, error messages, the released GIL and Ctrl-C.

The command line is found through ROCKFALL_BIN or in the repository's target/release; the
tests that compare with it fail (they do not skip) when it is missing.
"""

import _thread
import json
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import rockfall

REPO = Path(__file__).resolve().parents[3]
TIMING_KEYS = {"threads", "wall_time_s", "trajectories_per_s"}


def cli() -> str:
    path = os.environ.get("ROCKFALL_BIN") or str(REPO / "target" / "release" / "rockfall")
    assert Path(path).is_file(), f"the command line is needed: build it or set ROCKFALL_BIN ({path})"
    return path


def sh(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([cli(), *args], capture_output=True, text=True)


@pytest.fixture(scope="module")
def site2(tmp_path_factory) -> Path:
    """vaujany-site2 written as input files by the command line."""
    d = tmp_path_factory.mktemp("site") / "vaujany-site2"
    out = sh("site", "vaujany-site2", "--out", str(d))
    assert out.returncode == 0, out.stderr
    return d


def summary_of(path: Path) -> dict:
    s = json.loads(path.read_text())
    return {k: v for k, v in s.items() if k not in TIMING_KEYS}


def test_api_shapes_units_and_georeferencing(site2):
    sc = rockfall.Scenario.load(site2 / "scenario.toml")
    assert sc.name == "vaujany-site2" and sc.engine == "lumped"
    sc.seed = 3
    sc.rocks_per_cell = 300
    sc.rocks_csv = True
    res = rockfall.run(sc, threads=2)
    assert res.rocks_simulated == 300
    names = res.raster_names()
    assert names[:2] == ["Nr_passages", "Reach_probability"] and "E_95" in names
    a = res.raster("Nr_passages")
    x0, cell, _, y1, _, neg = res.transform
    assert a.dtype == np.float64 and a.ndim == 2 and cell == 2.5 and neg == -2.5
    assert np.nanmax(a) == 300  # every rock passes its source cell
    e = res.raster("E_mean")
    assert np.isnan(e).any() and np.nanmin(e) > 0  # nodata where no rock passed
    assert res.crs == "EPSG:2154"
    s = res.summary
    assert s["rocks"] == 300 and s["seed"] == 3 and s["engine"] == "lumped"
    rocks = res.rocks()
    assert len(rocks["rock_id"]) == 300 and rocks["outcome"].dtype.kind == "U"
    assert np.isnan(rocks["flight_s"]).all()  # the lumped engine does not classify motion
    with pytest.raises(KeyError, match="Nr_passages"):
        res.raster("Nr_nothing")
    # the scenario object is not changed by a run's overrides
    res2 = rockfall.run(sc, threads=1, seed=4, rocks_per_cell=50)
    assert res2.summary["rocks"] == 50 and sc.seed == 3 and sc.rocks_per_cell == 300


def read_asc(path: Path) -> tuple[np.ndarray, tuple[float, float, float]]:
    """An ESRI ASCII grid: its values (NaN at nodata) and (xllcorner, yllcorner, cellsize)."""
    lines = path.read_text().splitlines()
    head = {}
    while lines and lines[0].split()[0][0].isalpha():
        key, value = lines.pop(0).split()
        head[key.lower()] = float(value)
    values = np.array([[float(v) for v in line.split()] for line in lines])
    if "nodata_value" in head:  # count grids have no nodata
        values[values == head["nodata_value"]] = np.nan
    return values, (head["xllcorner"], head["yllcorner"], head["cellsize"])


def test_same_numbers_as_the_command_line_lumped(site2, tmp_path):
    cli_out, py_out = tmp_path / "cli", tmp_path / "py"
    scenario = site2 / "with_rocks.toml"
    text = (site2 / "scenario.toml").read_text()
    assert "rocks_csv = false" in text
    scenario.write_text(text.replace("rocks_csv = false", "rocks_csv = true"))
    r = sh("run", str(scenario), "--rocks-per-cell", "400", "--seed", "5",
           "--threads", "2", "--ascii", "--out", str(cli_out))
    assert r.returncode == 0, r.stderr
    res = rockfall.run(str(scenario), rocks_per_cell=400, seed=5, threads=1)
    res.write(py_out)
    assert summary_of(cli_out / "summary.json") == summary_of(py_out / "summary.json")
    assert {k: v for k, v in res.summary.items() if k not in TIMING_KEYS} == summary_of(
        cli_out / "summary.json")
    tifs = sorted(p.name for p in cli_out.glob("*.tif"))
    assert len(tifs) >= 17
    for name in tifs:
        assert (cli_out / name).read_bytes() == (py_out / name).read_bytes(), name
    # the arrays themselves: every raster against the command line's ASCII grid, which holds
    # rows north to south like the array; and the transform against its corner
    for name in res.raster_names():
        cli_values, (xll, yll, cell) = read_asc(cli_out / f"{name}.asc")
        a = res.raster(name)
        assert a.shape == cli_values.shape, name
        assert np.allclose(a, cli_values, rtol=1e-6, atol=1e-9, equal_nan=True), name
    x0, cell_m, _, y1, _, _ = res.transform
    assert (x0, cell_m) == (xll, cell) and y1 == yll + cell * a.shape[0]
    # rocks(): rocks.csv's columns and values (text as written, numbers to the bit)
    lines = (cli_out / "rocks.csv").read_text().splitlines()
    header = lines[0].split(",")
    rocks = res.rocks()
    assert list(rocks) == header
    rows = [line.split(",") for line in lines[1:]]
    for k, name in enumerate(header):
        col = rocks[name]
        for row, v in zip(rows, col):
            if name == "outcome":
                assert row[k] == v
            elif row[k] == "":
                assert np.isnan(v), name
            else:
                assert float(row[k]) == float(v), name


def test_same_numbers_as_the_command_line_rigid(tmp_path):
    d = tmp_path / "fs40"
    assert sh("site", "forest-slope-40", "--out", str(d)).returncode == 0
    text = (d / "scenario.toml").read_text().replace("max_time_s = 60.0", "max_time_s = 4.0")
    (d / "short.toml").write_text(text)
    r = sh("run", str(d / "short.toml"), "--rocks-per-point", "4", "--seed", "2",
           "--out", str(tmp_path / "cli"))
    assert r.returncode == 0, r.stderr
    res = rockfall.run(d / "short.toml", rocks_per_point=4, seed=2, threads=2)
    res.write(tmp_path / "py")
    assert summary_of(tmp_path / "cli" / "summary.json") == summary_of(tmp_path / "py" / "summary.json")
    assert res.summary["motion"]["flight"] > 0
    for name in ["Nr_passages.tif", "E_95.tif", "V_max.tif"]:
        assert (tmp_path / "cli" / name).read_bytes() == (tmp_path / "py" / name).read_bytes()


def test_errors_carry_the_command_lines_message(site2, tmp_path):
    with pytest.raises(ValueError, match="nowhere.toml"):
        rockfall.Scenario.load(tmp_path / "nowhere.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text((site2 / "scenario.toml").read_text().replace("[rock]\n", "[rock]\nsize = 3\n"))
    out = sh("check", str(bad))
    assert out.returncode == 2
    with pytest.raises(ValueError) as e:
        rockfall.Scenario.load(bad)
    assert "bad.toml" in str(e.value) and "size" in str(e.value)
    assert str(e.value) in out.stderr  # the command line prints the same message
    sc = rockfall.Scenario.load(site2 / "scenario.toml")
    with pytest.raises(ValueError, match="rocks_per_cell"):
        sc.rocks_per_cell = 0
    with pytest.raises(ValueError, match="rocks_per_cell"):
        rockfall.run(sc, rocks_per_cell=0)
    with pytest.raises(ValueError, match="unknown engine"):
        sc.engine = "ballistic"
    with pytest.raises(ValueError, match="unknown shape"):
        rockfall.impact_lab("pyramid", 10)
    with pytest.raises(ValueError, match="unknown site"):
        rockfall.Scenario.site("nowhere")


def test_the_gil_is_released_during_a_run(site2):
    sc = rockfall.Scenario.load(site2 / "scenario.toml")
    sc.rocks_per_cell = 200_000
    ticks = 0
    done = threading.Event()

    def work():
        rockfall.run(sc, threads=1)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    assert ticks > 50, ticks  # the main thread ran while the run went on


def test_ctrl_c_interrupts_a_run_cleanly(site2, tmp_path):
    sc = rockfall.Scenario.load(site2 / "scenario.toml")
    sc.rocks_per_cell = 50_000_000  # minutes of work
    timer = threading.Timer(0.5, _thread.interrupt_main)
    started = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        rockfall.run(sc, threads=2)
    elapsed = time.monotonic() - started
    assert elapsed < 10, elapsed  # the workers stopped, the call returned
    # the session goes on: a new run works and nothing was left behind
    assert rockfall.run(sc, rocks_per_cell=10).summary["rocks"] == 10
    assert not any(tmp_path.iterdir())


def test_impact_lab_columns_equal_the_command_lines(tmp_path):
    d = rockfall.impact_lab("flat2.2", 60, seed=4, threads=2)
    assert len(d["sample"]) == 60
    assert set(d["regime"]) <= {"frontal", "lateral", "scratch"}
    r = sh("impact-lab", "--shape", "flat2.2", "--samples", "60", "--seed", "4", "--out",
           str(tmp_path / "lab"))
    assert r.returncode == 0, r.stderr
    lines = (tmp_path / "lab" / "impacts.csv").read_text().splitlines()
    header = lines[0].split(",")
    assert header == list(d)  # the same columns, in the same order
    col = header.index("total_energy_loss")
    cli_loss = [float(line.split(",")[col]) for line in lines[1:]]
    assert cli_loss == list(d["total_energy_loss"])


def test_to_xarray(site2, monkeypatch):
    res = rockfall.run(site2 / "scenario.toml", rocks_per_cell=50, threads=1)
    monkeypatch.setitem(sys.modules, "xarray", None)  # as if it were not installed
    with pytest.raises(ImportError, match="xarray"):
        res.to_xarray()
    monkeypatch.undo()
    xr = pytest.importorskip("xarray") if not os.environ.get("CI") else __import__("xarray")
    ds = res.to_xarray()
    a = res.raster("Nr_passages")
    assert ds["Nr_passages"].shape == a.shape
    assert np.array_equal(ds["Nr_passages"].values, a, equal_nan=True)
    x0, cell, _, y1, _, _ = res.transform
    assert ds.x.values[0] == x0 + cell / 2 and ds.y.values[0] == y1 - cell / 2
    assert ds.attrs["crs"] == "EPSG:2154"
    assert isinstance(ds, xr.Dataset)


CALIBRATION = """
rocks_per_cell = 100

[[parameter]]
key = "lumped.roughness_tilt_factor"
range = [0.0, 2.0]

[[target]]
path = "max_velocity_ms.mean"
value = 11.7
sd = 1.0

[[target]]
path = "screens.lower_road.passed_fraction"
value = 0.21
n = 102
"""


def test_calibrate_returns_the_command_lines_record(site2, tmp_path):
    targets = tmp_path / "targets.toml"
    targets.write_text(CALIBRATION)
    c = rockfall.calibrate(site2 / "scenario.toml", targets, budget=6, threads=2, out=tmp_path / "py")
    cli_out = tmp_path / "cli"
    run = sh("calibrate", str(site2 / "scenario.toml"), "--targets", str(targets), "--budget", "6",
             "--out", str(cli_out))
    assert run.returncode == 0, run.stderr
    on_cli = json.loads((cli_out / "calibration.json").read_text())
    assert c["evaluations"] == on_cli["evaluations"]
    assert c["best"] == on_cli["best"] and len(c["evaluations"]) == 6
    assert (tmp_path / "py" / "calibrated.toml").is_file()
    # bad input: the command line's message as a ValueError
    targets.write_text(CALIBRATION.replace("roughness_tilt_factor", "roughness_tilt_factr"))
    with pytest.raises(ValueError, match="near matches: lumped.roughness_tilt_factor"):
        rockfall.calibrate(site2 / "scenario.toml", targets, budget=2)


HAZARD = """
matrix = "swiss"
[[scenario]]
return_period_years = 30
site = "vaujany-site2"
volume_m3 = 0.02
[[scenario]]
return_period_years = 300
site = "vaujany-site2"
volume_m3 = 0.45
"""


def test_hazard_returns_the_command_lines_map(tmp_path):
    f = tmp_path / "hazard.toml"
    f.write_text(HAZARD)
    r = sh("hazard", str(f), "--rocks-per-cell", "100", "--out", str(tmp_path / "cli"))
    assert r.returncode == 0, r.stderr
    hz = rockfall.hazard(f, out=tmp_path / "py", rocks_per_cell=100, threads=1)
    assert hz.scenarios == ["30y", "300y"]
    assert hz.level.dtype == np.uint8 and hz.level.shape == (142, 60)
    assert set(np.unique(hz.level)) <= {0, 1, 2, 3, 4} and (hz.level == 4).any()
    assert hz.crs == "EPSG:2154"
    x0, cell, _, y1, _, _ = hz.transform
    assert cell == 2.5 and y1 - x0 > 0
    # the same zones as the command line's Hazard_level.tif, cell for cell
    cli = (tmp_path / "cli" / "hazard.json").read_text()
    assert json.loads(cli)["areas"] == hz.summary["areas"]
    for name in ["Hazard_level.tif", "Hazard_field.tif", "hazard_zones.gpkg"]:
        assert (tmp_path / "py" / name).is_file(), name
    counts = np.bincount(hz.level.ravel(), minlength=5)
    areas = {a["level"]: a["cells"] for a in hz.summary["areas"]["levels"]}
    assert [areas[k] for k in range(1, 5)] == list(counts[1:])
    with pytest.raises(ValueError, match=r"split\.6.*purple"):
        bad = tmp_path / "bad.toml"
        bad.write_text('[split]\n6 = "purple"\n' + HAZARD.replace('matrix = "swiss"\n', ""))
        rockfall.hazard(bad, out=tmp_path / "bad")

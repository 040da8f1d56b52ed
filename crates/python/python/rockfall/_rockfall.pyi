"""Type stubs of the Rust extension behind ``rockfall``. Units are in the names (SI)."""

import os
from typing import Any, Optional, Union

import numpy as np
import numpy.typing as npt

__version__: str

PathLike = Union[str, "os.PathLike[str]"]

def sites() -> list[tuple[str, str]]:
    """The built-in sites as (name, description)."""

class Scenario:
    """A scenario: terrain, rock, release, forest and settings, as ``rockfall run`` reads them."""

    @staticmethod
    def load(path: PathLike) -> "Scenario":
        """Reads a scenario file (``*.toml``) or a Rockyfor3D input folder.

        Raises ``ValueError`` with the command line's message (file, cell, key) on bad input.
        """
    @staticmethod
    def site(name: str) -> "Scenario":
        """A built-in site (see ``sites()``)."""
    @property
    def name(self) -> str: ...
    seed: int
    """Master seed: one seed fixes every result."""
    rocks_per_cell: int
    """Rocks per source cell (>= 1)."""
    rocks_per_point: int
    """Rocks per release point (>= 1)."""
    engine: str
    """``"lumped"`` or ``"rigid"``."""
    rocks_csv: bool
    """Keep one record per rock (``Results.rocks()``)."""
    trajectories: int
    """Rocks whose paths are recorded (``Results.trajectories()``)."""
    max_time_s: float
    """Longest simulated time per rock, s."""

class Results:
    """The results of a run."""

    def raster_names(self) -> list[str]:
        """Names of the rasters, in the command line's writing order."""
    def raster(self, name: str) -> npt.NDArray[np.float64]:
        """The raster ``name`` as a 2-D array, rows north to south, NaN where nodata.

        Units as in the GeoTIFFs: energies kJ, heights m, speeds m/s, ``Reach_probability`` %,
        ``EL_angles`` degrees, counts otherwise. Raises ``KeyError`` for an unknown name.
        """
    @property
    def transform(self) -> tuple[float, float, float, float, float, float]:
        """GDAL geotransform (x_min_m, cell_m, 0, y_max_m, 0, -cell_m)."""
    @property
    def crs(self) -> Optional[str]:
        """``"EPSG:<code>"`` when known, else the WKT, else None."""
    @property
    def summary(self) -> dict[str, Any]:
        """``summary.json`` as a dict."""
    @property
    def rocks_simulated(self) -> int: ...
    def rocks(self) -> dict[str, npt.NDArray[Any]]:
        """One record per rock, the columns of ``rocks.csv`` (needs ``Scenario.rocks_csv``)."""
    def trajectories(self) -> dict[str, npt.NDArray[Any]]:
        """The recorded paths, the columns of ``trajectories.csv``."""
    def write(self, out: PathLike, *, ascii: bool = False) -> list[str]:
        """Writes the command line's files into ``out``; returns the paths written."""
    def to_xarray(self) -> Any:
        """The rasters as an ``xarray.Dataset`` on x/y cell centres (m), CRS in the attributes.

        Raises ``ImportError`` naming xarray when it is not installed.
        """

def run(
    scenario: Union[Scenario, PathLike],
    *,
    threads: Optional[int] = None,
    seed: Optional[int] = None,
    rocks_per_cell: Optional[int] = None,
    rocks_per_point: Optional[int] = None,
    engine: Optional[str] = None,
) -> Results:
    """Simulates a scenario (object or path) with the GIL released.

    Ctrl-C stops the workers and raises ``KeyboardInterrupt``; bad input raises ``ValueError``.
    """

def calibrate(
    scenario: Union[Scenario, str, os.PathLike[str]],
    targets: Union[str, os.PathLike[str]],
    *,
    budget: int = 200,
    seed: Optional[int] = None,
    threads: Optional[int] = None,
    out: Optional[Union[str, os.PathLike[str]]] = None,
) -> dict[str, Any]:
    """Fit the free keys of the targets file (``[[parameter]]``) to its observations
    (``[[target]]`` paths of summary.json with ``sd`` or ``n``, ``[deposits]``), as
    ``rockfall calibrate``: at most ``budget`` candidates, each a run with seed ``seed``.
    Returns calibration.json as a dict (``best``, ``parameters`` with ``fit_range``,
    ``evaluations``); ``out`` also writes calibrated.toml, calibration.md and .html there.
    Bad input raises ``ValueError``; Ctrl-C raises ``KeyboardInterrupt`` after the current
    candidate.
    """

def impact_lab(
    shape: str = "sphere",
    samples: int = 5000,
    *,
    seed: int = 1,
    threads: Optional[int] = None,
    dt_s: Optional[float] = None,
    mu: Optional[float] = None,
) -> dict[str, npt.NDArray[Any]]:
    """Seed 001's single-tree impact laboratory: the impacts as a dict of numpy columns."""


class Hazard:
    """A hazard zone map (``rockfall.hazard``): arrays north-up, rows north to south."""

    @property
    def level(self) -> npt.NDArray[np.uint8]:
        """Hazard level per cell: 0 none, 1 residual, 2 low, 3 medium, 4 high."""
    @property
    def field(self) -> npt.NDArray[np.uint8]:
        """Matrix field per cell (1–9 for the Swiss matrix; 0 none or residual)."""
    @property
    def intensity_class(self) -> npt.NDArray[np.uint8]:
        """Intensity class that decided each cell (1 weakest; 0 none)."""
    @property
    def return_period_class(self) -> npt.NDArray[np.uint8]:
        """Probability class that decided each cell (1 most frequent; 0 none)."""
    @property
    def transform(self) -> tuple[float, float, float, float, float, float]:
        """GDAL geotransform (x_min, cell, 0, y_max, 0, -cell), m."""
    @property
    def crs(self) -> Optional[str]:
        """``"EPSG:<code>"`` when known, else the WKT, else None."""
    @property
    def scenarios(self) -> list[str]:
        """The scenarios' labels, in file order."""
    @property
    def summary(self) -> dict[str, Any]:
        """hazard.json: the settings and the area of each level and field."""
    @property
    def out(self) -> str:
        """The folder the map's files were written into."""

def hazard(
    path: PathLike,
    *,
    out: PathLike = "rockfall-hazard",
    matrix: Optional[str] = None,
    rocks_per_cell: Optional[int] = None,
    seed: Optional[int] = None,
    threads: Optional[int] = None,
    rerun: bool = False,
) -> Hazard:
    """The hazard zone map of a hazard file, as ``rockfall hazard``: runs its scenarios not
    yet run into ``out/runs/<label>`` (GIL released), writes Hazard_level.tif, hazard_zones.gpkg,
    hazard.json, hazard.html … into ``out`` and returns the map. Bad input raises
    ``ValueError`` naming the file and the key.
    """

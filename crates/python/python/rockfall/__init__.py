"""rockfall: 3-D rockfall simulation for forested and open mountain slopes.

Two engines behind one set of inputs and outputs: ``lumped`` (seed 000, RockyFor: probabilistic
point masses on a raster DEM) and ``rigid`` (seed 001: convex polyhedral rocks with non-smooth
contact). The numbers are the command line's, bit for bit, for the same scenario and seed.

    import rockfall
    sc = rockfall.Scenario.load("site/scenario.toml")   # or a Rockyfor3D folder
    sc.seed = 3; sc.rocks_per_cell = 1000
    res = rockfall.run(sc, threads=2)
    a = res.raster("Nr_passages")        # 2-D numpy array, north-up rows, NaN where nodata
    res.transform, res.crs, res.summary
    res.write("out")                     # the same files as `rockfall run`
    hz = rockfall.hazard("hazard.toml", out="zones")   # as `rockfall hazard`
    hz.level, hz.field, hz.transform, hz.crs, hz.summary
"""

from ._rockfall import (
    Hazard,
    Results,
    Scenario,
    __version__,
    calibrate,
    hazard,
    impact_lab,
    run,
    sites,
)

__all__ = [
    "Hazard",
    "Results",
    "Scenario",
    "__version__",
    "calibrate",
    "hazard",
    "impact_lab",
    "run",
    "sites",
]

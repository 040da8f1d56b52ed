"""Opens a QGIS project written by rockfall with QGIS itself (PyQGIS) and checks it as QGIS
reads it: the project CRS, every layer, the stems' symbol and the hillshade at the bottom.

Run with the system Python that has the QGIS bindings (Debian: python3-qgis), headless:

    QT_QPA_PLATFORM=offscreen /usr/bin/python3 qgis_open.py PROJECT --epsg 2154 [--stems]
        [--render map.png]

Exits 0 and prints one line per layer when every check holds; raises AssertionError (exit 1)
naming the first that does not. Called by crates/cli/tests/report.rs and hazard.rs.
"""

import argparse
import os
import sys

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from qgis.core import (  # noqa: E402  (the environment first)
    Qgis,
    QgsApplication,
    QgsMapLayerType,
    QgsProject,
    QgsUnitTypes,
)

#: Largest stem dot, mm: a stand of thousands of stems must stay readable.
MAX_STEM_MM = 1.5


def check(path, epsg, stems, render):
    project = QgsProject.instance()
    assert project.read(path), f"QGIS cannot read {path}: {project.error()}"
    crs = project.crs()
    assert crs.isValid(), f"{path}: no valid project CRS"
    assert crs.authid() == f"EPSG:{epsg}", f"project CRS {crs.authid()}, expected EPSG:{epsg}"
    layers = project.mapLayers().values()
    assert layers, f"{path}: no layer"
    for layer in layers:
        assert layer.isValid(), f"layer {layer.name()} ({layer.source()}) is not valid"
        assert layer.crs() == crs, f"layer {layer.name()}: CRS {layer.crs().authid()}"
        print(f"{layer.name()}: valid, {layer.crs().authid()}, {layer.providerType()}")

    if stems:
        found = project.mapLayersByName("stems")
        assert found, "no stems layer"
        layer = found[0]
        assert layer.featureCount() > 0, "the stems layer has no feature"
        symbol = layer.renderer().symbol()
        assert symbol.sizeUnit() == QgsUnitTypes.RenderMillimeters, symbol.sizeUnit()
        assert 0 < symbol.size() <= MAX_STEM_MM, f"stem symbol {symbol.size()} mm"
        print(f"stems: {layer.featureCount()} points, {symbol.size()} mm, {symbol.color().name()}")

    # the hillshade: a raster drawn by QGIS's hillshade renderer, the bottom of the tree
    tree = [node.layer() for node in project.layerTreeRoot().findLayers()]
    shaded = [
        l for l in tree if l.type() == QgsMapLayerType.RasterLayer and l.renderer().type() == "hillshade"
    ]
    assert shaded, "no hillshade layer"
    assert tree[-1] is shaded[0], f"the bottom layer is {tree[-1].name()}, not the hillshade"
    print(f"hillshade: {shaded[0].name()} ({shaded[0].source()}), bottom of {len(tree)} layers")

    if render:
        render_map(project, render)


def render_map(project, png):
    """Draws the layers shown when the project opens, as QGIS would, into `png`."""
    from qgis.core import QgsMapRendererSequentialJob, QgsMapSettings
    from qgis.PyQt.QtCore import QSize

    visible = [
        n.layer() for n in project.layerTreeRoot().findLayers() if n.isVisible()
    ]
    settings = QgsMapSettings()
    settings.setLayers(visible)
    settings.setDestinationCrs(project.crs())
    extent = visible[-1].extent()
    settings.setExtent(extent)
    settings.setOutputSize(QSize(600, int(600 * extent.height() / extent.width())))
    job = QgsMapRendererSequentialJob(settings)
    job.start()
    job.waitForFinished()
    job.renderedImage().save(png, "png")
    print(f"rendered {len(visible)} layers into {png}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("project")
    parser.add_argument("--epsg", type=int, required=True, help="the run's EPSG code")
    parser.add_argument("--stems", action="store_true", help="the project has stems")
    parser.add_argument("--render", help="also draw the visible layers into this PNG")
    args = parser.parse_args()
    app = QgsApplication([], False)
    app.initQgis()
    print(f"QGIS {Qgis.QGIS_VERSION}")
    try:
        check(args.project, args.epsg, args.stems, args.render)
    finally:
        QgsProject.instance().clear()
        app.exitQgis()
    print("ok")


if __name__ == "__main__":
    sys.exit(main())

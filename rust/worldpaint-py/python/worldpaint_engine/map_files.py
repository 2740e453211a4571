"""Color maps a world is painted from: a grid of whole-number labels (.asc or .npy) and a legend (JSON) naming the
palette color of each label, or polygons (GeoJSON) each naming its color.

    map:     an ESRI ASCII grid (.asc) of labels, placed by its header (each value a cell's square), or a 2-D .npy
             array of whole numbers, rows along +Y, stretched over the world's region
    legend:  {"7": "Forest", "3": "Meadow"}: label -> the palette's color name
    polygons: a GeoJSON FeatureCollection (.geojson) of Polygon and MultiPolygon features in the world's coordinates
             (m), each with the property "color" naming its palette color; a later feature paints over an earlier
             one, holes are kept, and the collection's "background" names the color of the world no feature covers.
             The polygons are drawn onto square cells (``GEOJSON_CELLS`` across the region's longer side, at least
             1 m)

Every reader checks what it reads before a tile is started and raises ``FileFormatError`` (an ``InputError``) with
one line naming the file and what was wrong: a label that is not a whole number from 0 to 2^32 - 1, no-data cells
(every cell needs a label), a .npy whose cells would not be square over the region, a legend that is not a JSON
object of labels and color names, a color the palette does not have. A label with no legend entry and a map that
does not cover the world are refused by the engine's plan, also before any tile runs.
"""

from __future__ import annotations

import math

import numpy as np

from . import _engine
from .terrain_files import read_ascii_values, read_json, refuse

MAX_LABEL = 2**32 - 1
GEOJSON_CELLS = 1000


def checked_labels(path, values):
    """``values`` as uint32 labels, each checked to be a whole number from 0 to 2^32 - 1."""
    values = np.asarray(values)
    if values.dtype.kind not in "iuf":
        raise refuse(path, f"a map holds whole-number labels, not {values.dtype}")
    as_float = values.astype(np.float64)
    bad = ~np.isfinite(as_float) | (as_float < 0) | (as_float > MAX_LABEL) | (as_float != np.floor(as_float))
    if bad.any():
        j, i = (int(k) for k in np.argwhere(bad)[0])
        raise refuse(path, f"the label {float(values[j, i]):g} (column {i}, row {j} from the south) is not a whole "
                           f"number from 0 to {MAX_LABEL}")
    return np.ascontiguousarray(as_float.astype(np.uint32))


def read_ascii_labels(path):
    """An ESRI ASCII grid of labels: (labels rows along +Y, origin of the grid's corner, cell)."""
    header, values = read_ascii_values(path, "labels")
    cell = header["cellsize"]
    nodata = header.get("nodata_value")
    if nodata is not None and (values == nodata).any():
        raise refuse(path, f"it has no-data cells ({nodata:g}): every cell of a map needs a label")
    # the centre convention names the first cell's centre; a map's cells are squares from the corner
    shift = 0.0 if "xllcorner" in header else -0.5 * cell
    origin = (header.get("xllcorner", header.get("xllcenter")) + shift,
              header.get("yllcorner", header.get("yllcenter")) + shift)
    return checked_labels(path, values[::-1]), origin, cell


def read_npy_labels(path, region):
    """A .npy array of labels, rows along +Y, stretched over ``region`` ((x0, y0), (x1, y1)) in square cells."""
    try:
        values = np.load(path, allow_pickle=False)
    except OSError:
        raise
    except Exception as e:  # numpy raises several kinds for a damaged header
        raise refuse(path, f"not a readable .npy array ({e})") from None
    if not isinstance(values, np.ndarray) or values.ndim != 2 or 0 in values.shape:
        raise refuse(path, f"a map is a 2-D array of labels, not of shape {getattr(values, 'shape', '?')}")
    (x0, y0), (x1, y1) = region
    ny, nx = values.shape
    cx, cy = (x1 - x0) / nx, (y1 - y0) / ny
    if abs(cx - cy) > 1e-3 * max(cx, cy):
        raise refuse(path, f"its {nx} x {ny} cells over the world's {x1 - x0:g} x {y1 - y0:g} m would not be square "
                           f"({cx:g} x {cy:g} m): give a map of the world's proportions, or an .asc placed by its "
                           "header")
    return checked_labels(path, values), (x0, y0), cx


def read_legend(path, palette_colors):
    """The legend file's {label: color JSON}, in the file's order; ``palette_colors`` is {name: color JSON}."""
    legend = read_json(path)
    if not isinstance(legend, dict) or not legend:
        raise refuse(path, 'a legend is a JSON object of labels and color names, e.g. {"1": "Forest"}')
    out = {}
    for label, name in legend.items():
        try:
            value = int(label, 10)
        except ValueError:
            value = -1
        if not 0 <= value <= MAX_LABEL:
            raise refuse(path, f"the label {label!r} is not a whole number from 0 to {MAX_LABEL}")
        if value in out:
            raise refuse(path, f"the label {value} is given twice")
        if not isinstance(name, str) or name not in palette_colors:
            raise refuse(path, f"the label {label} names the color {name!r}, which the palette does not have (it has "
                               f"{', '.join(sorted(palette_colors)) or 'none'})")
        out[value] = palette_colors[name]
    return out


def feature_region(path, where, geometry):
    """The engine's region of a GeoJSON Polygon or MultiPolygon (its holes cut out), each ring checked."""
    kind = geometry.get("type") if isinstance(geometry, dict) else None
    if kind not in ("Polygon", "MultiPolygon"):
        raise refuse(path, f"{where} is a {kind or 'feature without geometry'}: a map's features are Polygons or "
                           "MultiPolygons")
    polygons = geometry.get("coordinates")
    if kind == "Polygon":
        polygons = [polygons]
    if not isinstance(polygons, list) or not polygons:
        raise refuse(path, f"{where} has no coordinates")
    parts = []
    for polygon in polygons:
        if not isinstance(polygon, list) or not polygon:
            raise refuse(path, f"{where} has a polygon without rings")
        rings = []
        for ring in polygon:
            try:
                points = np.asarray(ring, dtype=np.float64)
            except (TypeError, ValueError):
                points = np.zeros((0, 0))
            if points.ndim != 2 or points.shape[1] < 2 or len(points) < 4:
                raise refuse(path, f"{where} has a ring that is not a list of at least 4 positions [x, y]")
            if not np.isfinite(points[:, :2]).all():
                raise refuse(path, f"{where} has a position that is not a pair of finite numbers")
            rings.append({"shape": "polygon", "points": points[:-1, :2].tolist()})
        parts.append({"shape": "clipped", "within": rings[:1], "without": rings[1:]})
    return {"shape": "clipped", "within": parts, "without": []}


def read_geojson_labels(path, palette_colors, region):
    """A GeoJSON map drawn over ``region`` ((x0, y0), (x1, y1)): (labels rows along +Y, the grid's corner, cell,
    {label: color name}), a label per color in the order the features first name them (the background's first)."""
    data = read_json(path)
    if not isinstance(data, dict) or data.get("type") != "FeatureCollection" or not isinstance(
            data.get("features"), list):
        raise refuse(path, 'a map of polygons is a GeoJSON FeatureCollection ({"type": "FeatureCollection", '
                           '"features": [...]})')

    def known(name, where):
        if not isinstance(name, str) or name not in palette_colors:
            raise refuse(path, f"{where} names the color {name!r}, which the palette does not have (it has "
                               f"{', '.join(sorted(palette_colors)) or 'none'})")
        return name

    names = []
    background = data.get("background")
    if background is not None:
        names.append(known(background, "the background"))
    (x0, y0), (x1, y1) = region
    cell = max(1.0, max(x1 - x0, y1 - y0) / GEOJSON_CELLS)
    nx, ny = max(1, math.ceil((x1 - x0) / cell)), max(1, math.ceil((y1 - y0) / cell))
    labels = np.full((ny, nx), 0 if background is not None else MAX_LABEL, dtype=np.uint32)
    for k, feature in enumerate(data["features"], start=1):
        where = f"feature {k}"
        if not isinstance(feature, dict) or feature.get("type") != "Feature":
            raise refuse(path, f"{where} is not a GeoJSON Feature")
        properties = feature.get("properties")
        name = known(properties.get("color") if isinstance(properties, dict) else None, f"{where}'s \"color\"")
        shape = feature_region(path, where, feature.get("geometry"))
        try:
            (bx0, by0), (bx1, by1) = _engine.region_bbox(shape)
        except _engine.InputError as e:
            raise refuse(path, f"{where}: {e}") from None
        i0, i1 = max(0, math.floor((bx0 - x0) / cell)), min(nx, math.ceil((bx1 - x0) / cell))
        j0, j1 = max(0, math.floor((by0 - y0) / cell)), min(ny, math.ceil((by1 - y0) / cell))
        if i0 >= i1 or j0 >= j1:
            continue  # off the world
        xs, ys = np.meshgrid(x0 + (np.arange(i0, i1) + 0.5) * cell, y0 + (np.arange(j0, j1) + 0.5) * cell)
        inside = _engine.region_contains(shape, np.column_stack([xs.ravel(), ys.ravel()])).reshape(xs.shape)
        if name not in names:
            names.append(name)
        labels[j0:j1, i0:i1][inside] = names.index(name)
    bare = labels == MAX_LABEL
    if bare.any():
        j, i = (int(v) for v in np.argwhere(bare)[0])
        raise refuse(path, f"the point {x0 + (i + 0.5) * cell:g} {y0 + (j + 0.5) * cell:g} lies in no feature, and "
                           'the collection names no "background" color for the world the features leave')
    return labels, (x0, y0), cell, dict(enumerate(names))


def read_map(map_path, legend_path, palette_colors, region, band=None):
    """The engine's map of ``map_path`` and ``legend_path`` over ``region`` (for a .npy or a .geojson; an .asc is
    placed by its header), its colors from ``palette_colors`` ({name: color JSON}), its transition band ``band`` (m;
    None: three regions of influence). A .geojson names its colors itself and takes no legend."""
    if map_path.lower().endswith(".geojson"):
        if legend_path is not None:
            raise _engine.InputError(f"--legend {legend_path}: the polygons of --map {map_path} name their colors "
                                     'themselves (each feature\'s "color"), and take no legend')
        labels, origin, cell, names = read_geojson_labels(map_path, palette_colors, region)
        legend = {label: palette_colors[name] for label, name in names.items()}
        return {"labels": labels, "origin": origin, "cell": cell, "legend": legend, "band": band}
    if legend_path is None:
        raise _engine.InputError(f"--map {map_path}: a map needs its --legend (a JSON file "
                                 '{"label": "color name"})')
    if map_path.lower().endswith(".asc"):
        labels, origin, cell = read_ascii_labels(map_path)
    elif map_path.lower().endswith(".npy"):
        labels, origin, cell = read_npy_labels(map_path, region)
    else:
        raise _engine.InputError(f"--map {map_path}: a map is an .asc or .npy grid of labels, or .geojson polygons")
    return {"labels": labels, "origin": origin, "cell": cell, "legend": read_legend(legend_path, palette_colors),
            "band": band}

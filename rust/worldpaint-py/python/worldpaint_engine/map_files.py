"""Color maps a world is painted from: a grid of whole-number labels (.asc or .npy) and a legend (JSON) naming the
palette color of each label.

    map:    an ESRI ASCII grid (.asc) of labels, placed by its header (each value a cell's square), or a 2-D .npy
            array of whole numbers, rows along +Y, stretched over the world's region
    legend: {"7": "Forest", "3": "Meadow"}: label -> the palette's color name

Every reader checks what it reads before a tile is started and raises ``FileFormatError`` (an ``InputError``) with
one line naming the file and what was wrong: a label that is not a whole number from 0 to 2^32 - 1, no-data cells
(every cell needs a label), a .npy whose cells would not be square over the region, a legend that is not a JSON
object of labels and color names, a color the palette does not have. A label with no legend entry and a map that
does not cover the world are refused by the engine's plan, also before any tile runs.
"""

from __future__ import annotations

import numpy as np

from . import _engine
from .terrain_files import read_ascii_values, read_json, refuse

MAX_LABEL = 2**32 - 1


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


def read_map(map_path, legend_path, palette_colors, region, band=None):
    """The engine's map of ``map_path`` and ``legend_path`` over ``region`` (for a .npy; an .asc is placed by its
    header), its colors from ``palette_colors`` ({name: color JSON}), its transition band ``band`` (m; None: three
    regions of influence)."""
    if map_path.lower().endswith(".asc"):
        labels, origin, cell = read_ascii_labels(map_path)
    elif map_path.lower().endswith(".npy"):
        labels, origin, cell = read_npy_labels(map_path, region)
    else:
        raise _engine.InputError(f"--map {map_path}: a map is an .asc or .npy grid of labels")
    return {"labels": labels, "origin": origin, "cell": cell, "legend": read_legend(legend_path, palette_colors),
            "band": band}

"""Heightmap files a world is filled on: ESRI ASCII grids (.asc), numpy arrays (.npy) and Blender files (.blend).

Every reader checks what it reads before a tile is started and raises ``FileFormatError`` (an ``InputError``, so a
``ValueError``) with one line naming the file, what was wrong and the rule: a header key missing, repeated or not a
number; a cell size that is not a positive length; a height that is not a finite number (NaN, inf, or beyond a
32-bit float, which the engine keeps); a grid smaller than 2 x 2 samples or larger than the engine's grid budget;
values that do not fill the grid the header declares. No-data samples of an .asc (``NODATA_value``) take the lowest
height the grid holds.
"""

from __future__ import annotations

import json
import math
import os
import warnings
from dataclasses import dataclass

import numpy as np

from . import _engine

# the header keys of an ESRI ASCII grid (the x and y of the lower-left corner or of its cell's centre)
ASC_KEYS = ("ncols", "nrows", "xllcorner", "xllcenter", "yllcorner", "yllcenter", "cellsize", "nodata_value")
FLOAT32_MAX = float(np.finfo(np.float32).max)


@dataclass(frozen=True)
class TerrainGrid:
    """Heights on a regular grid: sample (i, j) = heights[j, i] at origin + (i, j) * cell."""

    origin: tuple[float, float]
    cell: float
    heights: np.ndarray

    def bbox(self):
        ny, nx = self.heights.shape
        ox, oy = self.origin
        return (ox, oy), (ox + (nx - 1) * self.cell, oy + (ny - 1) * self.cell)

    def window(self, lo, hi):
        """The samples covering the box ``lo``–``hi`` (clamped to the grid), None where it misses the grid."""
        ny, nx = self.heights.shape
        i0 = max(int(np.floor((lo[0] - self.origin[0]) / self.cell)), 0)
        j0 = max(int(np.floor((lo[1] - self.origin[1]) / self.cell)), 0)
        i1 = min(int(np.ceil((hi[0] - self.origin[0]) / self.cell)), nx - 1)
        j1 = min(int(np.ceil((hi[1] - self.origin[1]) / self.cell)), ny - 1)
        if i1 - i0 < 1 or j1 - j0 < 1:
            return None
        origin = (self.origin[0] + i0 * self.cell, self.origin[1] + j0 * self.cell)
        return TerrainGrid(origin, self.cell, np.ascontiguousarray(self.heights[j0:j1 + 1, i0:i1 + 1]))


def refuse(path, message):
    return _engine.FileFormatError(f"{path}: {message}")


def read_json(path):
    """The JSON value of the file ``path`` (a map's legend, village sites); refused when it is not UTF-8 JSON."""
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except json.JSONDecodeError as e:
        raise refuse(path, f"not JSON ({e})") from None
    except UnicodeDecodeError as e:
        raise refuse(path, f"not UTF-8 text ({e})") from None


def checked_grid(path, origin, cell, heights):
    """A ``TerrainGrid`` of ``heights`` (rows along +Y), every number checked."""
    if not (math.isfinite(cell) and cell > 0.0):
        raise refuse(path, f"the cell size {cell:g} must be a positive length (m)")
    for axis, v in zip("xy", origin, strict=True):
        if not math.isfinite(v):
            raise refuse(path, f"the origin's {axis} {v:g} must be a finite number")
    ny, nx = heights.shape
    far = max(abs(origin[0]), abs(origin[1])) + max(nx, ny) * cell
    if not math.isfinite(far) or far > FLOAT32_MAX:
        raise refuse(path, f"the grid reaches {far:g} m: its origin and cell size must keep it within "
                           f"{FLOAT32_MAX:.3g}")
    check_finite(path, heights, "rows from the south")
    return TerrainGrid((float(origin[0]), float(origin[1])), float(cell), heights.astype(np.float32))


def check_finite(path, heights, rows):
    """Refuses NaN, infinite heights and heights a 32-bit float (the engine's) cannot hold, naming the first."""
    with np.errstate(invalid="ignore"):
        bad = ~np.isfinite(heights) | (np.abs(heights) > FLOAT32_MAX)
    if bad.any():
        j, i = (int(k) for k in np.argwhere(bad)[0])
        raise refuse(path, f"{int(bad.sum())} of its heights are not finite numbers within a 32-bit float's range, "
                           f"the first {float(heights[j, i])} at column {i}, row {j} ({rows}); heights must be "
                           f"finite (an .asc marks missing samples with NODATA_value)")


def check_size(path, nx, ny):
    if nx < 2 or ny < 2:
        raise refuse(path, f"a terrain needs at least 2 x 2 samples, not {nx} x {ny}")
    limit = _engine.LIMITS["grid_cells"]
    if nx * ny > limit:
        raise refuse(path, f"{nx} x {ny} samples are more than the engine's limit of {limit:,} for one terrain")


def read_ascii_header(path, lines):
    """The header of an ESRI ASCII grid's lines and the index of its first line of values."""
    header = {}
    first = 0
    while first < len(lines):
        parts = lines[first].split()
        if parts and (not parts[0][0].isalpha() or parts[0].lower() in ("nan", "inf", "infinity")):
            break
        first += 1
        if not parts:
            continue
        line = lines[first - 1]
        key = parts[0].lower()
        if key not in ASC_KEYS:
            raise refuse(path, f"the ASCII grid's header has the unknown key {parts[0]!r} (it knows "
                               f"{', '.join(ASC_KEYS)})")
        if len(parts) != 2:
            raise refuse(path, f"the ASCII grid's header line {line.strip()[:60]!r} is not one key and one value")
        if key in header:
            raise refuse(path, f"the ASCII grid's header gives {key} twice")
        try:
            header[key] = float(parts[1])
        except ValueError:
            raise refuse(path, f"the ASCII grid's {key} {parts[1][:40]!r} is not a number") from None
    for key in ("ncols", "nrows", "cellsize"):
        if key not in header:
            raise refuse(path, f"the ASCII grid's header has no {key}")
    for axis in "xy":
        given = [k for k in (f"{axis}llcorner", f"{axis}llcenter") if k in header]
        if len(given) != 1:
            raise refuse(path, f"the ASCII grid's header needs one of {axis}llcorner and {axis}llcenter, "
                               f"not {' and '.join(given) or 'neither'}")
    for key in ("ncols", "nrows"):
        v = header[key]
        if not (math.isfinite(v) and v == int(v) and v >= 2):
            raise refuse(path, f"the ASCII grid's {key} {v:g} must be a whole number of at least 2")
    nodata = header.get("nodata_value")
    if nodata is not None and not math.isfinite(nodata):
        raise refuse(path, f"the ASCII grid's NODATA_value {nodata:g} must be a finite number")
    return header, first


def read_ascii_values(path, what="values"):
    """The header of an ESRI ASCII grid and its values (ny, nx), rows as the file has them (from the north), each
    checked against the header; ``what`` names the values in messages."""
    with open(path, "rb") as f:
        data = f.read()
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError as e:
        raise refuse(path, f"an ASCII grid holds ASCII text only; byte {e.start} is 0x{data[e.start]:02x}") from None
    lines = text.splitlines()
    header, first = read_ascii_header(path, lines)
    nx, ny, cell = int(header["ncols"]), int(header["nrows"]), header["cellsize"]
    check_size(path, nx, ny)
    if not (math.isfinite(cell) and cell > 0.0):
        raise refuse(path, f"the ASCII grid's cellsize {cell:g} must be a positive length (m)")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an empty grid is refused below, not warned about
            values = np.loadtxt(lines[first:], dtype=np.float64, ndmin=2)
    except ValueError as e:
        raise refuse(path, f"the ASCII grid's {what}: {str(e).rstrip('.')} (one row of ncols {what} a line)") from None
    if values.shape != (ny, nx):
        raise refuse(path, f"{values.shape[1]} x {values.shape[0]} {what} where the header says {nx} x {ny}")
    return header, values


def read_ascii_grid(path):
    """An ESRI ASCII grid (.asc): rows from north to south; no-data samples take the lowest height."""
    header, values = read_ascii_values(path)
    cell = header["cellsize"]
    check_finite(path, values, "the file's values, rows from the north")
    # the corner convention puts samples at cell centres
    shift = 0.5 * cell if "xllcorner" in header else 0.0
    origin = (header.get("xllcorner", header.get("xllcenter")) + shift,
              header.get("yllcorner", header.get("yllcenter")) + shift)
    heights = values[::-1]
    nodata = header.get("nodata_value")
    if nodata is not None:
        missing = heights == nodata
        if missing.all():
            raise refuse(path, f"every sample is no-data ({nodata:g})")
        if missing.any():
            heights = np.where(missing, heights[~missing].min(), heights)
    return checked_grid(path, origin, cell, heights)


def read_npy(path, cell, origin):
    """A .npy heightmap: a 2-D array of real numbers, rows along +Y, sample spacing ``cell`` from ``origin``."""
    try:
        # mapped, not read: the shape and type are checked before the data is touched
        heights = np.load(path, mmap_mode="r", allow_pickle=False)
    except OSError:
        raise
    except Exception as e:  # numpy raises several kinds for a damaged header
        raise refuse(path, f"not a readable .npy array ({e})") from None
    if not isinstance(heights, np.ndarray):
        raise refuse(path, "holds several arrays (an .npz); a heightmap is one 2-D array")
    if heights.dtype.kind not in "iuf":
        raise refuse(path, f"a heightmap holds real numbers, not {heights.dtype}")
    if heights.ndim != 2:
        raise refuse(path, f"a heightmap is a 2-D array of heights, not of shape {heights.shape}")
    check_size(path, heights.shape[1], heights.shape[0])
    if cell is None:
        raise refuse(path, "a .npy heightmap needs its sample spacing (--cell)")
    try:
        heights = np.array(heights, dtype=np.float64)
    except (OSError, ValueError) as e:
        raise refuse(path, f"its data cannot be read ({e})") from None
    return checked_grid(path, origin, cell, heights)


def read_blend_terrain(path, object_name):
    """The named mesh object of a .blend, rasterized by the engine (needs Blender's Python module ``bpy``)."""
    try:
        import bpy
    except ImportError:
        raise _engine.InputError("reading a .blend needs Blender's Python module bpy (pip install bpy)") from None
    try:
        bpy.ops.wm.open_mainfile(filepath=str(path))
    except RuntimeError as e:
        raise refuse(path, f"Blender cannot open it ({str(e).strip().splitlines()[-1]})") from None
    obj = bpy.data.objects.get(object_name) if object_name else None
    if obj is None or obj.type != 'MESH':
        names = sorted(o.name for o in bpy.data.objects if o.type == 'MESH')
        raise refuse(path, f"no mesh object {object_name!r} (--object; meshes: {', '.join(names) or 'none'})")
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        co = np.empty(len(mesh.vertices) * 3)
        mesh.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3)
        tris = np.empty(len(mesh.loop_triangles) * 3, np.int32)
        mesh.loop_triangles.foreach_get("vertices", tris)
        world = np.array(obj.matrix_world)
        co = co @ world[:3, :3].T + world[:3, 3]
    finally:
        evaluated.to_mesh_clear()
    grid = _engine.Terrain(co, tris.reshape(-1, 3)).grid()
    return TerrainGrid(tuple(grid["origin"]), grid["cell"], grid["heights"])


def load_terrain(path, *, cell=None, origin=None, object_name=None):
    """A terrain from a heightmap file: .asc (ESRI ASCII grid), .npy (2-D heights, rows along +Y; needs ``cell``,
    ``origin`` defaults to (0, 0)) or .blend (the mesh object ``object_name``). Options that do not apply to the
    file's kind are refused rather than ignored."""
    suffix = os.path.splitext(str(path))[1].lower()
    if suffix not in (".asc", ".npy", ".blend"):
        raise refuse(path, "a terrain is an .asc, .npy or .blend file")
    given = {"--cell": cell, "--origin": origin, "--object": object_name}
    applies = {".asc": (), ".npy": ("--cell", "--origin"), ".blend": ("--object",)}[suffix]
    for option, value in given.items():
        if value is not None and option not in applies:
            raise _engine.InputError(f"{option} does not apply to a {suffix} terrain ({path}): "
                                     f"{'it gives its own' if suffix == '.asc' else 'it is read from the file'}")
    os.stat(path)  # a missing file is told as such before any reader (or Blender) starts
    if suffix == ".asc":
        return read_ascii_grid(path)
    if suffix == ".npy":
        return read_npy(path, cell, (0.0, 0.0) if origin is None else tuple(origin))
    return read_blend_terrain(path, object_name)

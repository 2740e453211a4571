"""The engine's import of real places (OpenStreetMap layers, elevation models, tree inventories), typed: the part of
the facade (``engine``) that reads places, kept apart as it is a concern of its own."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .engine import _lib, _pair_of

if TYPE_CHECKING:
    from worldpaint_engine._engine import Progress


@dataclass(frozen=True)
class PlaceTerrain:
    """The terrain of an imported place: heights (ny, nx) float32, node (i, j) at ``origin + (i, j) * cell``."""

    origin: tuple[float, float]
    cell: float
    heights: NDArray[np.float32]


@dataclass(frozen=True)
class PlaceBuildings:
    """The buildings of a place, one row each: area centroid (N, 2) and its ground height (NaN off the terrain), the
    minimum-area rectangle's (length, width) (N, 2) and its long side's angle from +X in [0, pi), the area, the type
    (house, farm, church, barn, shed, apartments, industrial, commercial, garage, other), the ``building`` tag, the
    name ("" when none), and the footprint rings (outer counter-clockwise, holes clockwise)."""

    centroid: NDArray[np.float64]
    height: NDArray[np.float64]
    size: NDArray[np.float64]
    orientation: NDArray[np.float64]
    area: NDArray[np.float64]
    type: tuple[str, ...]
    building: tuple[str, ...]
    name: tuple[str, ...]
    footprints: tuple[tuple[NDArray[np.float64], ...], ...]


@dataclass(frozen=True)
class PlaceLines:
    """Roads (``kind``: major, minor, residential, track, path, other; ``tag``: the ``highway`` value) or waterways
    (``kind`` and ``tag``: the ``waterway`` value) of a place: (N, 2) points, their ground heights, names."""

    kind: tuple[str, ...]
    tag: tuple[str, ...]
    name: tuple[str, ...]
    points: tuple[NDArray[np.float64], ...]
    heights: tuple[NDArray[np.float64], ...]


@dataclass(frozen=True)
class PlaceAreas:
    """Water, land-use and land-cover areas: ``kind`` (water, residential, farmland, meadow, forest, ...), the tag it
    was classed by (``landuse=forest``), the name and the rings (outer counter-clockwise, holes clockwise)."""

    kind: tuple[str, ...]
    tag: tuple[str, ...]
    name: tuple[str, ...]
    rings: tuple[tuple[NDArray[np.float64], ...], ...]


@dataclass(frozen=True)
class PlacePoints:
    """Named places (``kind``: the ``place`` tag) or inventory trees (``kind``: the species; ``size``: dbh or height,
    NaN where unknown): positions (N, 2) and ground heights."""

    position: NDArray[np.float64]
    height: NDArray[np.float64]
    kind: tuple[str, ...]
    name: tuple[str, ...] = ()
    size: NDArray[np.float64] | None = None


@dataclass(frozen=True)
class ImportedPlace:
    """A real place in local metres: its frame (``origin`` lon/lat and the ``projection`` from WGS84 lon/lat, both
    None for local data only), the files it came from, its terrain and content, and what was read and left out."""

    origin: tuple[float, float] | None
    projection: str | None
    layers: tuple[str, ...]
    elevation: str | None
    inventory: str | None
    terrain: PlaceTerrain | None
    buildings: PlaceBuildings
    roads: PlaceLines
    waterways: PlaceLines
    areas: PlaceAreas
    places: PlacePoints
    trees: PlacePoints
    report: dict[str, Any]


def import_place(geojson_paths: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
                 dem_path: str | os.PathLike[str] | None = None,
                 inventory_path: str | os.PathLike[str] | None = None, *, origin: tuple[float, float] | None = None,
                 cell: float | None = None, margin: float = 200.0, progress: Progress | None = None) -> ImportedPlace:
    """Imports OpenStreetMap layers (GeoJSON), an elevation model (.asc, .hgt, .tif) and a tree inventory (CSV) into
    one local metric frame centred on ``origin`` (lon, lat; None: the layers' centre; give a first import's origin to
    line a second one up with it); ``geojson_paths`` may be one path."""
    paths = [geojson_paths] if isinstance(geojson_paths, str | os.PathLike) else list(geojson_paths)
    d = _lib.import_place(paths, dem_path, inventory_path, origin=origin, cell=cell, margin=margin,
                          progress=progress)
    t = d["terrain"]
    b, r, w, a, p, tr = d["buildings"], d["roads"], d["waterways"], d["areas"], d["places"], d["trees"]
    return ImportedPlace(
        origin=d["frame"]["origin"],
        projection=d["frame"]["projection"],
        layers=tuple(d["sources"]["layers"]),
        elevation=d["sources"]["elevation"],
        inventory=d["sources"]["inventory"],
        terrain=None if t is None else PlaceTerrain(_pair_of(t["origin"]), t["cell"], t["heights"]),
        buildings=PlaceBuildings(
            centroid=b["centroid"], height=b["height"], size=b["size"], orientation=b["orientation"], area=b["area"],
            type=tuple(b["type"]), building=tuple(b["building"]), name=tuple(b["name"]),
            footprints=tuple(tuple(rings) for rings in b["footprints"])),
        roads=PlaceLines(tuple(r["kind"]), tuple(r["highway"]), tuple(r["name"]), tuple(r["points"]),
                         tuple(r["heights"])),
        waterways=PlaceLines(tuple(w["kind"]), tuple(w["kind"]), tuple(w["name"]), tuple(w["points"]),
                             tuple(w["heights"])),
        areas=PlaceAreas(tuple(a["kind"]), tuple(a["tag"]), tuple(a["name"]),
                         tuple(tuple(rings) for rings in a["rings"])),
        places=PlacePoints(p["position"], p["height"], tuple(p["kind"]), tuple(p["name"])),
        trees=PlacePoints(tr["position"], tr["height"], tuple(tr["species"]), size=tr["size"]),
        report=dict(d["report"]),
    )

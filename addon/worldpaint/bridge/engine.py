"""The one typed facade over the compiled engine ``worldpaint_engine``.

Everything the add-on asks of the engine goes through the functions here: they take plain Python values and numpy
arrays and return the dataclasses below, built from the engine's dicts in this one place. The engine's Scene,
Terrain and TerrainSurface are opaque handles that are only passed back in.

The engine's exceptions are reachable here under their own names (``WorldPaintError``, ``InputError``,
``FileFormatError``, ``NothingToLearn``, ``Cancelled``, ``InternalError``), and so are its generators of example
scenes (``exemplar_uniform``, ``exemplar_clustered``, ``exemplar_hard_core``, ``exemplar_slope_scene``,
``exemplar_village``, ``exemplar_demo_terrain``, for the tests, the demo and the benchmarks: what they return is the
engine's, as its stub types it); all looked up when first used so the add-on loads without the wheel and says so when
it is needed.

Long computations take ``progress``: a callable ``progress(fraction)`` or ``progress(fraction, stage)`` returning
False to cancel; the engine gives a stage's name to a callable that takes the second argument.

The import of real places is typed alike in ``engine_place``.

The compiled module's types (its functions, and the dicts it takes and returns) are in its stub,
``worldpaint_engine/_engine.pyi``; a type checker reads ``_lib`` below as that module, so every call here is checked
against it.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, fields, replace
from typing import TYPE_CHECKING, Any, Literal, NamedTuple, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import WorldPaintError as AddonError

if TYPE_CHECKING:
    from typing import Unpack

    import worldpaint_engine._engine as _lib

    # the engine's exceptions and example scenes are reachable as this module's own (``__getattr__`` looks them up
    # when the add-on runs)
    from worldpaint_engine._engine import (  # noqa: F401
        AnalysisOptions,
        ArrangementChanges,
        ArrangementSettings,
        Camera,
        Cancelled,
        CategoryInput,
        DecompositionDict,
        EditDict,
        FidelityDict,
        FileFormatError,
        GradientShape,
        InputError,
        InterestSetting,
        InternalError,
        LatticeDict,
        LearnedVillageDict,
        Model,
        NothingToLearn,
        PatternFidelityDict,
        PatternGuides,
        Progress,
        Region,
        Scene,
        SceneColumns,
        SceneStructures,
        SketchSecondsDict,
        Terrain,
        TerrainSurface,
        TextureVarietyDict,
        VariantsDict,
        VillageDict,
        VillageReportDict,
        VillageSetting,
        WaterfallController,
        WaterfallDict,
        WaterfallOptions,
        WorldPaintError,
        exemplar_clustered,
        exemplar_demo_terrain,
        exemplar_hard_core,
        exemplar_slope_scene,
        exemplar_uniform,
        exemplar_village,
    )
    from worldpaint_engine._engine import Stroke as StrokeHandle

T = TypeVar("T")

ENGINE_ERRORS = ("WorldPaintError", "InputError", "FileFormatError", "NothingToLearn", "Cancelled", "InternalError")
EXEMPLARS = ("exemplar_uniform", "exemplar_clustered", "exemplar_hard_core", "exemplar_slope_scene", "exemplar_village",
             "exemplar_demo_terrain")


def _engine_module() -> Any:
    """The compiled engine module; a clear error when the wheel is missing."""
    try:
        from worldpaint_engine import _engine
    except ImportError as exc:  # pragma: no cover - only without the bundled wheel
        raise AddonError(f"The WorldPaint engine is not installed ({exc})") from exc
    return _engine


if not TYPE_CHECKING:
    class _Engine:
        """The compiled module, imported when first used: the add-on loads without the wheel and says so when it is
        needed."""

        def __getattr__(self, name: str) -> Any:
            return getattr(_engine_module(), name)

    _lib = _Engine()

    def __getattr__(name: str) -> Any:
        if name in ENGINE_ERRORS or name in EXEMPLARS:
            return getattr(_lib, name)
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def engine_error() -> type[WorldPaintError]:
    """The base class of every exception the engine raises (``Cancelled``, ``InputError`` and the rest)."""
    return _lib.WorldPaintError


def is_cancelled(exc: BaseException) -> bool:
    return isinstance(exc, _lib.Cancelled)


def _pair_of(values: Sequence[T]) -> tuple[T, T]:
    """A pair as a tuple, as the engine takes pairs."""
    a, b = values
    return a, b


# --- what the engine returns --------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Category:
    """A category as a color knows it: what it is and how much of it the example held."""

    name: str
    layer: str
    kind: str
    priority: int
    count: int = 0
    density: float = 0.0
    min_distance: float = 0.0

    def as_input(self) -> CategoryInput:
        """The category as the engine's Scene takes it."""
        return {"name": self.name, "layer": self.layer, "kind": self.kind, "priority": self.priority}


class Interaction(NamedTuple):
    """A statistic of a color: how ``category`` relates to ``other`` (a category or a map), of a ``kind``."""

    category: str
    other: str
    kind: str


@dataclass(frozen=True)
class ColorSummary:
    """What a color (its JSON) holds: its categories, its interactions and the preview of its example."""

    name: str
    categories: tuple[Category, ...]
    pairs: tuple[Interaction, ...]
    maps: tuple[Interaction, ...]
    preview: NDArray[np.float64]  # (N, 3): x, y from the example's corner, category index
    preview_size: tuple[float, float]
    region: Region  # the example's region, as the engine's region dict
    # {road, river or coast category: the shortest edge the color makes of it (m)}
    shortest_edges: dict[str, float]

    @property
    def category_names(self) -> list[str]:
        return [c.name for c in self.categories]

    @property
    def interactions(self) -> tuple[Interaction, ...]:
        return self.pairs + self.maps


class Polyline(NamedTuple):
    """A line on the terrain: XY points (N, 2) and their heights (N,), NaN off the terrain."""

    points: NDArray[np.float64]
    heights: NDArray[np.float64]


class Line(NamedTuple):
    """A path or contour of an edit: its category (an index into the edit's categories), points and heights."""

    category: int
    points: NDArray[np.float64]
    heights: NDArray[np.float64]


@dataclass(frozen=True)
class Instances:
    """Instances as columns: XY (N, 2), height on the terrain (NaN off it or without one), rotation about Z, scale,
    category index, prototype and tint."""

    positions: NDArray[np.float64]
    heights: NDArray[np.float64]
    rotations: NDArray[np.float64]
    scales: NDArray[np.float64]
    category_index: NDArray[np.int32]
    prototype: NDArray[np.int32]
    tints: NDArray[np.float32]


@dataclass(frozen=True)
class Edit(Instances):
    """What a tool did to a scene: the rows of its instances removed, the instances added (the columns), and the
    paths and contours removed (indices) and added."""

    category_names: tuple[str, ...]
    removed: NDArray[np.int64]
    removed_paths: NDArray[np.int64]
    removed_contours: NDArray[np.int64]
    added_paths: tuple[Line, ...]
    added_contours: tuple[Line, ...]
    # {map name: share of the painted region where it read values the color's example never showed}
    unseen_maps: dict[str, float]

    @classmethod
    def of(cls, d: EditDict) -> Edit:
        def lines(key: Literal["added_paths", "added_contours"]) -> tuple[Line, ...]:
            return tuple(Line(int(line["category"]), line["points"], line["heights"]) for line in d[key])

        return cls(
            category_names=tuple(c["name"] for c in d["categories"]),
            removed=np.asarray(d["removed"], dtype=np.int64),
            positions=d["positions"],
            heights=d["heights"],
            rotations=d["rotations"],
            scales=d["scales"],
            category_index=d["category_index"],
            prototype=d["prototype"],
            tints=d["tints"],
            removed_paths=np.asarray(d["removed_paths"], dtype=np.int64),
            removed_contours=np.asarray(d["removed_contours"], dtype=np.int64),
            added_paths=lines("added_paths"),
            added_contours=lines("added_contours"),
            unseen_maps=dict(d.get("unseen_maps", {})),
        )

    def restricted(self, allowed: ArrayLike) -> Edit:
        """This edit without the instances, paths and contours it adds of the categories ``allowed`` (one bool per
        category name) rules out; what it removes stays."""
        by_category = np.asarray(allowed, dtype=bool)
        keep = by_category[self.category_index] if len(self.category_index) else np.zeros(0, dtype=bool)
        columns = {column.name: getattr(self, column.name)[keep] for column in fields(Instances)}
        return replace(
            self, **columns,
            added_paths=tuple(line for line in self.added_paths if by_category[line.category]),
            added_contours=tuple(line for line in self.added_contours if by_category[line.category]),
        )

    def painted_categories(self) -> set[str]:
        """The names of the categories this edit added instances, paths or contours of."""
        names = {self.category_names[i] for i in np.unique(self.category_index)}
        return names | {self.category_names[line.category] for line in self.added_paths + self.added_contours}


def fidelity_line(max_rdf_l2: float, density_factor: float) -> str:
    """The one-line figure of a color's fidelity: its worst pcf L2 against the example and its density factor."""
    return f"pcf L2 {max_rdf_l2:.2f} against the example (density ×{density_factor:.2f})"


@dataclass(frozen=True)
class Fidelity:
    """How close what a color painted is to its example: per category the density ratio (painted / example), per
    pair of categories the L2 distance between their pair-correlation functions (rdf), and the worst of these."""

    density_ratio: dict[str, float]
    rdf_l2: tuple[tuple[str, str, float], ...]  # (category, other, l2)
    max_rdf_l2: float  # over the measured categories
    too_few: tuple[str, ...] = ()  # categories the example holds too few of to measure

    @classmethod
    def of(cls, d: FidelityDict) -> Fidelity:
        return cls(density_ratio=dict(d["density_ratio"]), rdf_l2=tuple((a, b, float(v)) for a, b, v in d["rdf_l2"]),
                   max_rdf_l2=float(d["max_rdf_l2"]), too_few=tuple(d["too_few"]))

    @property
    def density_factor(self) -> float:
        """The density ratio farthest from 1 over the measured categories (1 when there is none)."""
        measured = (r for c, r in self.density_ratio.items() if c not in self.too_few)
        return max(measured, key=lambda r: abs(r - 1.0), default=1.0)

    def line(self) -> str:
        return fidelity_line(self.max_rdf_l2, self.density_factor)


@dataclass(frozen=True)
class FidelityView:
    """A color's fidelity view: the figure of its self-synthesis against its example, and the plot of their pcfs
    (and slope histograms when it has a slope map) as RGBA uint8 (height, width, 4), rows from the top, with the
    ends of its axes (``max_slope_degrees`` None without a slope panel)."""

    fidelity: Fidelity
    image: NDArray[np.uint8]
    max_distance: float
    max_pcf: float
    max_slope_degrees: float | None


@dataclass(frozen=True)
class PatternFidelity:
    """What a region holds of an arrangement color against its reference: the share of its interior elements whose
    neighbour ring is one of the reference's (and the reference's own share, each of its rings against the others),
    how many elements it holds, and their count over what the reference's density gives for the region."""

    ring_share: float
    reference_ring_share: float
    interior: int
    elements: int
    count_ratio: float

    @classmethod
    def of(cls, d: PatternFidelityDict) -> PatternFidelity:
        return cls(ring_share=float(d["ring_share"]), reference_ring_share=float(d["reference_ring_share"]),
                   interior=int(d["interior"]), elements=int(d["elements"]), count_ratio=float(d["count_ratio"]))

    def line(self) -> str:
        return (f"neighbour rings as the reference's for {self.ring_share:.0%} of {self.interior} interior elements "
                f"(the reference's own {self.reference_ring_share:.0%}); {self.elements} elements, "
                f"×{self.count_ratio:.2f} the reference's density")


@dataclass(frozen=True)
class Pasted:
    """A paste: the edit, and the figure of what the region holds afterwards against the color (None when it could
    not be learned back; ``fidelity_error`` then says why), or for an arrangement color against its reference."""

    edit: Edit
    fidelity: Fidelity | None
    fidelity_error: str = ""
    pattern: PatternFidelity | None = None


@dataclass(frozen=True)
class Moved:
    """A moved region: the edit, and how many instances moved, adapted in place, were replaced, found no place or
    stayed where they were because the move would have put them off the terrain."""

    edit: Edit
    moved: int
    displaced: int
    reborn: int
    lost: int
    stayed: int


@dataclass(frozen=True)
class Stretched:
    """A stretched region: the edit, the region's new rectangle (min, max) and the instances it would have pushed
    off the terrain (not moved)."""

    edit: Edit
    region_min: tuple[float, float]
    region_max: tuple[float, float]
    pushed_off: int


class Stroke:
    """A brush or eraser stroke on a scene; ``follow`` may run on a worker thread while ``edit`` is read."""

    def __init__(self, handle: StrokeHandle) -> None:
        self._handle = handle

    def follow(self, path: ArrayLike, progress: Progress | None = None) -> int:
        """Moves the brush along float64 (N, 2) points; returns the number of dabs."""
        return self._handle.follow(np.ascontiguousarray(path, dtype=np.float64), progress=progress)

    def dab_count(self) -> int:
        return len(self._handle.dabs())

    def edit(self) -> Edit:
        return Edit.of(self._handle.edit())


@dataclass(frozen=True)
class FilledPolygons:
    """The triangulated inside of polygons: vertices XY (N, 2), their heights (N,) and triangles (M, 3)."""

    vertices: NDArray[np.float64]
    heights: NDArray[np.float64]
    triangles: NDArray[np.int32]


@dataclass(frozen=True)
class Encyclopedia:
    """A building encyclopedia: its JSON text (None: the shipped one) and the types it defines."""

    text: str | None
    village_types: list[str]
    buildings: list[str]


@dataclass(frozen=True)
class House:
    """One house mesh in world space: vertices (V, 3), faces as loop starts into ``indices``, a material per face;
    ``seed`` indexes the village's kept seeds and footprints."""

    seed: int
    vertices: NDArray[np.float64]
    loop_starts: NDArray[np.int32]
    indices: NDArray[np.int32]
    materials: NDArray[np.int32]


@dataclass(frozen=True)
class VillageResult:
    """A generated village: new roads, parcels (N, 2), footprints (M, 4, 2) and houses per kept seed, the seeds'
    building and village types, the connections used, and the engine's report of how it grew (figures, kept as the
    engine gives them: they are saved with the village as JSON)."""

    roads: tuple[Polyline, ...]
    parcels: tuple[NDArray[np.float64], ...]
    footprints: NDArray[np.float64]
    houses: tuple[House, ...]
    seed_buildings: tuple[str, ...]
    seed_village_types: tuple[str, ...]
    connections: NDArray[np.float64]
    report: VillageReportDict

    @classmethod
    def of(cls, d: VillageDict) -> VillageResult:
        seeds = d["seeds"]
        return cls(
            roads=tuple(Polyline(r["points"], r["heights"]) for r in d["roads"]),
            parcels=tuple(d["parcels"]),
            footprints=d["footprints"],
            houses=tuple(House(int(h["seed"]), h["vertices"], h["loop_starts"], h["indices"], h["materials"])
                         for h in d["houses"]),
            seed_buildings=tuple(seeds["building"]),
            seed_village_types=tuple(seeds["village_type"]),
            connections=d["connections"],
            report=d["report"],
        )


@dataclass(frozen=True)
class RoadEmbedding:
    """Roads cut into a terrain: the height change (N,) at the points asked about."""

    displacement: NDArray[np.float64]


@dataclass(frozen=True)
class WaterMesh:
    """The water's integration mesh (world XYZ vertices, triangles) and its per-vertex attributes: speed, foam,
    rocks, disturbance and invalid (floats), and the part of the water each vertex belongs to."""

    vertices: NDArray[np.float64]
    triangles: NDArray[np.uint32]
    speed: NDArray[np.float64]
    foam: NDArray[np.float64]
    rocks: NDArray[np.float64]
    disturbance: NDArray[np.float64]
    invalid: NDArray[np.float64]
    part: NDArray[np.int32]


class WaterfallSegment(NamedTuple):
    kind: str
    controller: int
    valid: bool


@dataclass(frozen=True)
class WaterfallResult:
    """A waterfall scene: at the points asked about, the terrain's height change (N,), horizontal shift (N, 2) and
    whether water stands there; the water mesh; the classified segments; the river rocks (XYZ, rotation, scale,
    prototype); and the number of arcs of its hydraulic graph."""

    displacement: NDArray[np.float64]
    horizontal: NDArray[np.float64]
    is_water: NDArray[np.bool_]
    water: WaterMesh
    segments: tuple[WaterfallSegment, ...]
    rocks: NDArray[np.float64]
    rock_rotation: NDArray[np.float64]
    rock_scale: NDArray[np.float64]
    rock_prototype: NDArray[np.int32]
    arcs: int

    @classmethod
    def of(cls, d: WaterfallDict) -> WaterfallResult:
        water = d["water"]
        return cls(
            displacement=d["displacement"],
            horizontal=d["horizontal"],
            is_water=d["is_water"],
            water=WaterMesh(water["vertices"], water["triangles"], water["speed"], water["foam"], water["rocks"],
                            water["disturbance"], water["invalid"], water["part"]),
            segments=tuple(WaterfallSegment(s["type"], int(s["controller"]), bool(s["valid"]))
                           for s in d["segments"]),
            rocks=np.asarray(d["rocks"], dtype=np.float64).reshape(-1, 3),
            rock_rotation=np.asarray(d["rock_rotation"], dtype=np.float64),
            rock_scale=np.asarray(d["rock_scale"], dtype=np.float64),
            rock_prototype=np.asarray(d["rock_prototype"], dtype=np.int32),
            arcs=int(d["report"]["arcs"]),
        )


# --- terrain, scenes and regions ----------------------------------------------------------------------------------

def terrain(vertices: ArrayLike, triangles: ArrayLike) -> Terrain:
    """The engine's Terrain (a heightfield) of a world-space triangle mesh: vertices (N, 3), triangles (M, 3)."""
    return _lib.Terrain(vertices, triangles)


def terrain_surface(vertices: ArrayLike, triangles: ArrayLike) -> TerrainSurface:
    """The engine's TerrainSurface of a world-space triangle mesh, vertices (N, 3) and triangles (M, 3): its
    triangles binned for ``surface_heights``."""
    return _lib.TerrainSurface(vertices, triangles)


def surface_heights(surface: TerrainSurface, xy: ArrayLike) -> NDArray[np.float64]:
    """The height of the surface's highest triangle over each world XY point (N, 2); NaN over none."""
    return surface.heights(np.asarray(xy, dtype=np.float64).reshape(-1, 2))


def terrain_from_grid(origin: Sequence[float], cell: float, heights: ArrayLike) -> Terrain:
    """The engine's Terrain of a regular grid of heights (ny, nx), sample (i, j) at ``origin`` + (i, j) * ``cell``."""
    return _lib.Terrain.from_grid((float(origin[0]), float(origin[1])), float(cell),
                                       np.ascontiguousarray(heights, dtype=np.float64))


def scene(heightfield: Terrain | None, instances: SceneColumns, structures: SceneStructures) -> Scene:
    """The engine's Scene of the instances (keyword arrays) and the paths and contours (keyword lists) on a terrain."""
    return _lib.Scene(heightfield, **instances, **structures)


@dataclass(frozen=True)
class WorldTile(Instances):
    """One tile of a world's tile set: its instances' columns, ``category_index`` into ``categories`` (names)."""

    column: int
    row: int
    categories: list[str]


def world_manifest(folder: str) -> dict[str, Any]:
    """The manifest (a dict) of the tile set in ``folder``; ``ValueError`` when it is not one."""
    _engine_module()
    from worldpaint_engine import world

    manifest: dict[str, Any] = world.read_manifest(folder)
    return manifest


def read_world_tile(path: str | os.PathLike[str]) -> WorldTile:
    with open(path, "rb") as f:
        d = _lib.read_world_tile(f.read())
    return WorldTile(d["positions"], d["heights"], d["rotations"], d["scales"], d["category_index"], d["prototype"],
                     d["tints"], column=d["column"], row=d["row"], categories=list(d["categories"]))


def region_bbox(region: Region) -> tuple[tuple[float, float], tuple[float, float]]:
    """((xmin, ymin), (xmax, ymax)) of a region."""
    return _lib.region_bbox(region)


def region_contains(region: Region, points: ArrayLike) -> NDArray[np.bool_]:
    """bool (N,): which of the XY points (N, 2) lie inside the region."""
    return _lib.region_contains(region, np.ascontiguousarray(points, dtype=np.float64))


def fill_polygons(contours: Iterable[ArrayLike], spacing: float, heightfield: Terrain | None) -> FilledPolygons:
    """The triangulated inside of closed XY contours, inner vertices about ``spacing`` apart, on the terrain."""
    mesh = _lib.fill_polygons([np.ascontiguousarray(c, dtype=np.float64) for c in contours], spacing,
                                   heightfield)
    return FilledPolygons(mesh["vertices"], mesh["heights"], mesh["triangles"])


# --- colors and palettes ------------------------------------------------------------------------------------------

def learn_color(scene_handle: Scene, region: Region, name: str, maps: Iterable[str],
                oriented: Iterable[Sequence[str]] | None = None) -> str:
    """The color (JSON) of a scene's content inside ``region``, with the terrain ``maps`` and the ``oriented``
    pairs (category, other); raises ``NothingToLearn`` when the region holds nothing."""
    options: AnalysisOptions = {"maps": list(maps)}
    if oriented is not None:
        options["oriented"] = [_pair_of(pair) for pair in oriented]
    return _lib.learn_color(scene_handle, region, name, options=options)


def color_summary(color_json: str) -> ColorSummary:
    d = _lib.color_summary(color_json)
    return ColorSummary(
        name=d["name"],
        categories=tuple(Category(c["name"], c["layer"], c["kind"], c["priority"], c["count"], c["density"],
                                  c["min_distance"]) for c in d["categories"]),
        pairs=tuple(Interaction(*p) for p in d["pairs"]),
        maps=tuple(Interaction(*m) for m in d["maps"]),
        preview=np.asarray(d["preview"], dtype=np.float64).reshape(-1, 3),
        preview_size=d["preview_size"],
        region=d["region"],
        shortest_edges=dict(d["shortest_edges"]),
    )


def fidelity(color_json: str, heightfield: Terrain | None, seed: int, width: int, height: int,
             progress: Progress | None = None) -> FidelityView:
    """The fidelity view of a color: its self-synthesis with ``seed`` in its example region on ``heightfield`` (the
    terrain it was learned on; None: without terrain), compared with it and plotted ``width`` x ``height``."""
    d = _lib.fidelity(color_json, heightfield, seed, width=width, height=height, progress=progress)
    return FidelityView(Fidelity.of(d), d["image"], float(d["max_distance"]), float(d["max_pcf"]),
                        d["max_slope_degrees"])


def color_renamed(color_json: str, name: str) -> str:
    return _lib.color_renamed(color_json, name)


def color_without_interactions(color_json: str, off: Iterable[tuple[str, str]]) -> str:
    """The color with the interactions (category, other) in ``off`` switched off."""
    return _lib.color_without_interactions(color_json, sorted(off))


def interpolate_colors(a_json: str, b_json: str, factor: float, name: str) -> str:
    """The color ``factor`` of the way from color a to color b (optimal transport of their statistics)."""
    return _lib.interpolate_colors(a_json, b_json, factor, name)


def palette_to_json(colors: Iterable[str]) -> str:
    return _lib.palette_to_json(list(colors))


def palette_from_json(text: str) -> list[str]:
    """The colors (JSON each) of a palette file's text; raises ``FileFormatError`` when it is not one."""
    return list(_lib.palette_from_json(text))


# --- arrangements -------------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class ArrangementSummary:
    """What an arrangement color holds: its reference (XY relative to its region's corner, symbol per element), the
    reference's connectivity as index pairs, which elements lie on its boundary, how many of its edges were flipped,
    the lattice it was placed on when it is near-regular ({"name", "spacing": its shortest step (m), "spread": how far
    the hand placed elements from it (m, root mean square)}, else None), and how it is painted."""

    positions: NDArray[np.float64]
    symbols: tuple[int, ...]
    edges: NDArray[np.int64]
    boundary: tuple[bool, ...]
    flips: int
    lattice: LatticeDict | None
    settings: ArrangementSettings


def learn_arrangement(scene_handle: Scene, region: Region, name: str) -> str:
    """The arrangement color (JSON) of the scene's arrangement elements inside ``region``."""
    return _lib.learn_arrangement(scene_handle, region, name)


def arrangement_summary(color_json: str) -> ArrangementSummary | None:
    """The ``ArrangementSummary`` of a color, or None when it is a color of statistics."""
    d = _lib.arrangement_summary(color_json)
    if d is None:
        return None
    settings: ArrangementSettings = {"rotation": d["rotation"], "scale_noise": d["scale_noise"],
                                     "rotation_noise": d["rotation_noise"], "color_noise": d["color_noise"],
                                     "relax_every": d["relax_every"]}
    return ArrangementSummary(
        positions=np.asarray(d["positions"], dtype=np.float64).reshape(-1, 2), symbols=tuple(d["symbols"]),
        edges=np.asarray(d["edges"], dtype=np.int64).reshape(-1, 2), boundary=tuple(d["boundary"]),
        flips=d["flips"], lattice=d["lattice"], settings=settings,
    )


def arrangement_edited(color_json: str, **changes: Unpack[ArrangementChanges]) -> str:
    """The arrangement color with ``changes`` (rotation, scale_noise, rotation_noise, color_noise, relax_every,
    flip=(a, b))."""
    return _lib.arrangement_edited(color_json, **changes)


# --- model variety ------------------------------------------------------------------------------------------------

def decompose_model(model: Model, labels: ArrayLike, root: int | None = None) -> DecompositionDict:
    """The components of a model (dict of mesh arrays) by a label per face: labels, face counts, connecting regions
    (a, b, vertex count), root, whether the graph is fully cyclic or tree-like, and each component's sub-mesh."""
    return _lib.decompose_model(model, np.ascontiguousarray(labels, dtype=np.int64), root)


def generate_variants(model: Model, labels: ArrayLike, variants: Sequence[Sequence[Model]], count: int, seed: int, *,
                      root: int | None = None, cycles: Sequence[tuple[int, int]] | None = None,
                      picks: Sequence[int] | None = None, names: Sequence[str] | None = None,
                      variant_names: Sequence[Sequence[str]] | None = None,
                      progress: Progress | None = None) -> VariantsDict:
    """``count`` variants assembled from the components' edited ``variants`` (per component a list of model dicts),
    or the one that ``picks`` (per component: 0 its original, k its k-th edit): their classes, #V (a string: the
    number of different models), the accepted models with their hashes, the rejections. ``names`` (per component)
    and ``variant_names`` (per component, per variant) are what the errors call the parts and their copies."""
    return _lib.generate_variants(model, np.ascontiguousarray(labels, dtype=np.int64), variants, count, seed,
                                       root=root, cycles=cycles, picks=picks, names=names,
                                       variant_names=variant_names, progress=progress)


def texture_variety(model: Model, base: ArrayLike, edits: Iterable[ArrayLike], count: int, probability: float = 0.5,
                    seed: int = 0, *, names: Sequence[str] | None = None) -> TextureVarietyDict:
    """Texture variety (seed §5): each edit (uint8 (H, W, 4), the size of ``base``) becomes a texture component over
    the model's UVs; the components packed into the fewest atlases (no two conflicting in one), and ``count``
    variants' picks with face locking: components (texels, face texels, faces), conflicts, atlas_of, atlases, exact,
    images (uint8 (H, W, 4)), chosen (per variant), face_atlas (int64 (count, F), -1: the base texture)."""
    return _lib.texture_variety(model, np.ascontiguousarray(base, dtype=np.uint8),
                                     [np.ascontiguousarray(e, dtype=np.uint8) for e in edits], count, probability,
                                     seed, names=names)


def assign_variants(positions: ArrayLike, fixed: ArrayLike, count: int, window: float = 50.0,
                    seed: int = 0) -> NDArray[np.int64]:
    """int64 (N,): the variant of each XY position, ``fixed`` (-1: to choose) kept, the others the least used around."""
    return _lib.assign_variants(np.ascontiguousarray(positions, dtype=np.float64),
                                     np.ascontiguousarray(fixed, dtype=np.int64), count, window, seed)


# --- painting tools -----------------------------------------------------------------------------------------------

def paste(scene_handle: Scene, color: str, region: Region, seed: int, influence_radius: float | None,
          progress: Progress | None = None, guides: PatternGuides | None = None,
          only_categories: Sequence[str] | None = None, iterations_per_instance: float | None = None) -> Pasted:
    """Paints ``color`` into ``region`` (only its ``only_categories`` when given); ``guides`` ({"start",
    "boundaries", "flow"}) steer an arrangement color."""
    d = _lib.paste(scene_handle, color=color, region=region, seed=seed, influence_radius=influence_radius,
                        progress=progress, guides=guides, only_categories=only_categories,
                        iterations_per_instance=iterations_per_instance)
    fidelity, pattern = d.get("fidelity"), d.get("pattern")
    return Pasted(Edit.of(d), None if fidelity is None else Fidelity.of(fidelity), d.get("fidelity_error", ""),
                  None if pattern is None else PatternFidelity.of(pattern))


def clear_region(scene_handle: Scene, region: Region, category: str | None = None) -> Edit:
    return Edit.of(_lib.clear_region(scene_handle, region, category=category))


def blur(scene_handle: Scene, region: Region, windows: int, cells: int, seed: int, influence_radius: float | None,
         progress: Progress | None = None) -> Edit:
    return Edit.of(_lib.blur(scene_handle, region=region, windows=windows, cells=cells, seed=seed,
                                  influence_radius=influence_radius, progress=progress))


def gradient(scene_handle: Scene, start: str, end: str, region: Region, shape: GradientShape, bands: int | None,
             seed: int, influence_radius: float | None, progress: Progress | None = None) -> Edit:
    """Paints ``region`` from color ``start`` to color ``end`` (JSON) along ``shape`` (see
    ``regions.gradient_shape``) in ``bands`` bands (None: one per interaction radius); a shape
    {"kind": "bilinear", "north_west", "north_east"} puts ``start``, ``end`` and those two colors at the corners of
    the region's box (south-west, south-east, north-west, north-east) in ``bands`` × ``bands`` cells."""
    return Edit.of(_lib.gradient(scene_handle, start=start, end=end, region=region, shape=shape, bands=bands,
                                      seed=seed, influence_radius=influence_radius, progress=progress))


def stretch_region(scene_handle: Scene, region: Region, side: Literal["east", "west", "north", "south"], amount: float,
                   color: str | None, seed: int, influence_radius: float | None,
                   progress: Progress | None = None) -> Stretched:
    d = _lib.stretch_region(scene_handle, region=region, side=side, amount=amount, color=color, seed=seed,
                                 influence_radius=influence_radius, progress=progress)
    return Stretched(Edit.of(d), _pair_of(d["region"]["min"]), _pair_of(d["region"]["max"]), int(d["pushed_off"]))


def move_region(scene_handle: Scene, color: str | None, source: Region, offset: Sequence[float], seed: int,
                influence_radius: float | None) -> Moved:
    d = _lib.move_region(scene_handle, color=color, source=source, offset=(float(offset[0]), float(offset[1])),
                              seed=seed, influence_radius=influence_radius)
    return Moved(Edit.of(d), int(d["moved"]), int(d["displaced"]), int(d["reborn"]), int(d["lost"]),
                 int(d["stayed"]))


def paint_stroke(scene_handle: Scene, color: str, radius: float, spacing: float, opacity: float,
                 falloff: Literal["constant", "linear", "smooth"], seed: int, influence_radius: float | None,
                 guides: PatternGuides | None = None, iterations_per_instance: float | None = None) -> Stroke:
    """A brush stroke painting ``color`` (JSON); ``falloff`` is "constant", "linear" or "smooth"; an arrangement
    color sprays its pattern, steered by ``guides`` (boundary and flow curves)."""
    return Stroke(_lib.Stroke(scene_handle, color=color, radius=radius, spacing=spacing, opacity=opacity,
                                   falloff=falloff, seed=seed, influence_radius=influence_radius, guides=guides,
                                   iterations_per_instance=iterations_per_instance))


def erase_stroke(scene_handle: Scene, radius: float, only_categories: Sequence[str] | None = None,
                 shortest_edges: dict[str, float] | None = None) -> Stroke:
    """An eraser stroke removing synthesized instances (of ``only_categories``; None: all) and cutting the roads,
    rivers and coasts of the categories it names, with no piece left shorter than ``shortest_edges[category]``."""
    return Stroke(_lib.Stroke(scene_handle, erase=True, only_categories=only_categories, radius=radius,
                                   shortest_edges=shortest_edges))


# --- villages -----------------------------------------------------------------------------------------------------

def encyclopedia(text: str | None = None) -> Encyclopedia:
    """The encyclopedia of a JSON text (None: the shipped one); raises the engine's error when it is not usable."""
    village_types, buildings = _lib.encyclopedia_contents(_lib.default_encyclopedia() if text is None else text)
    return Encyclopedia(text, list(village_types), list(buildings))


def scenario_presets() -> dict[str, list[dict[str, Any]]]:
    """{name: [event dicts]} of the shipped growth scenario presets."""
    return {name: preset["events"] for name, preset in json.loads(_lib.scenario_presets())["presets"].items()}


def generate_village(heightfield: Terrain, region: Region, scenario: str, seed: int, *,
                     progress: Progress | None = None, **setting: Unpack[VillageSetting]) -> VillageResult:
    """A village grown on the terrain inside ``region`` by the ``scenario`` (JSON); ``setting`` holds the
    encyclopedia, connections, existing roads, cells and surroundings. The engine reports its stages by name."""
    return VillageResult.of(_lib.generate_village(heightfield, region, scenario, seed, progress=progress,
                                                       **setting))


def learn_village(heightfield: Terrain, region: Region, buildings: ArrayLike, orientations: ArrayLike,
                  roads: Sequence[ArrayLike], *, progress: Progress | None = None,
                  **options: Any) -> LearnedVillageDict:
    """A village type learned from the real village of ``buildings`` (centres (N, 2), long axes ``orientations``
    (N,)) and ``roads`` inside ``region``: the encyclopedia with the type added, the scenario growing the real count
    with it, and how the fit went. ``options`` are the engine's (``name``, ``base_type``, ``max_seconds``...)."""
    return _lib.learn_village(heightfield, region, np.ascontiguousarray(buildings, dtype=np.float64),
                              np.ascontiguousarray(orientations, dtype=np.float64),
                              [np.ascontiguousarray(r, dtype=np.float64) for r in roads], progress=progress,
                              **options)


def village_interest(heightfield: Terrain, region: Region, points: ArrayLike, village_type: str, building: str,
                     criterion: str | None = None, **setting: Unpack[InterestSetting]) -> NDArray[np.float64]:
    """float (N,) at the XY points: one criterion of a building type's interest (None: the combined interest)."""
    return _lib.village_interest(heightfield, region, np.ascontiguousarray(points, dtype=np.float64),
                                      village_type, building, criterion, **setting)


# --- terrain edits ------------------------------------------------------------------------------------------------

def embed_roads(heightfield: Terrain, roads: Sequence[ArrayLike], points: ArrayLike, width: float, bank_width: float, *,
                use_heights: bool, smoothing: float | None) -> RoadEmbedding:
    d = _lib.embed_roads(heightfield, roads, np.ascontiguousarray(points, dtype=np.float64), width, bank_width,
                              use_heights=use_heights, smoothing=smoothing)
    return RoadEmbedding(d["displacement"])


def build_waterfall(heightfield: Terrain, controllers: Sequence[WaterfallController], points: ArrayLike, seed: int,
                    **options: Unpack[WaterfallOptions]) -> WaterfallResult:
    """The waterfall scene of the controllers on the terrain, read at the XY ``points``."""
    d = _lib.build_waterfall(heightfield, controllers, np.ascontiguousarray(points, dtype=np.float64), seed,
                                  **options)
    return WaterfallResult.of(d)


@dataclass(frozen=True)
class SketchResult:
    """A sketch applied (thesis ch. 5): the height change at the points asked about; the strokes' order front to back;
    the terrain features detected (world XYZ polylines, with their kinds); per stroke its 3D curve, the indices where
    that curve jumps from one silhouette to another (no part of it between them), and the feature it deforms (-2: the
    skyline under the stroke; -1: embedded, no feature could serve); the protruding silhouettes as lowered; and how it
    went."""

    displacement: NDArray[np.float64]
    order: list[int]
    features: list[NDArray[np.float64]]
    feature_kinds: list[str]
    curves: list[NDArray[np.float64]]
    curve_breaks: list[list[int]]
    sources: list[int]
    lowered: list[NDArray[np.float64]]
    rounds: int
    hidden_columns: int
    reach: float
    junctions: int
    seconds: SketchSecondsDict


def apply_sketch(heightfield: Terrain, camera: Camera, strokes: Iterable[ArrayLike], points: ArrayLike, *,
                 reach: float | None = None, completion: bool = True, aspect: float | None = None,
                 max_change: float | None = None, progress: Progress | None = None) -> SketchResult:
    """The terrain deformed so that, seen from ``camera`` (a dict: eye, forward, up, frame_min, frame_max), its
    silhouettes follow the ``strokes`` (camera-frame (N, 2) arrays), read at the XY ``points``; ``aspect``: the
    frame's width over its height, for the stroke ordering (None: the camera frame's); ``max_change``: the largest
    height change allowed (None: the terrain's relief, at least a quarter of its shorter side)."""
    d = _lib.apply_sketch(heightfield, camera, [np.ascontiguousarray(s, dtype=np.float64) for s in strokes],
                               np.ascontiguousarray(points, dtype=np.float64), reach=reach, completion=completion,
                               aspect=aspect, max_change=max_change, progress=progress)
    return SketchResult(**d)

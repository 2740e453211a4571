"""Types of the compiled engine module ``worldpaint_engine._engine`` (the pyo3 bindings in ``rust/worldpaint-py/src``).

``__all__`` lists every name the module exports, no more: ``blender_tests/test_engine_stub.py`` checks it against the
compiled module, and each function's and method's parameters against the signature pyo3 gives it. The other public
names here (the ``TypedDict`` dicts the engine takes and returns, and the aliases) exist for type checkers only.

Keywords several functions share are declared once, in a ``TypedDict`` a function unpacks (``**options:
Unpack[SynthesisOptions]``, PEP 692): its keys are keyword-only parameters of the compiled function, with the default
None where their type admits None (a key whose type does not, as ``WaterfallOptions``' ``subdivide``, has the default
its ``TypedDict`` names). A function that takes ``**surroundings`` itself reads their keys (``Surroundings``).

Arrays: an argument typed ``ArrayLike`` takes any real numeric dtype whose meaning is clear and is cast to the
engine's (see ``arrays.rs``); a result is a numpy array of the dtype given. A progress callback is
``progress(fraction)`` or ``progress(fraction, stage)``, returning False to cancel (then ``Cancelled`` is raised).
"""

from collections.abc import Callable, Sequence
from os import PathLike
from typing import Final, Literal, NotRequired, Required, TypeAlias, TypedDict, Unpack

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "LIMITS",
    "PALETTE_FORMAT_VERSION",
    "Cancelled",
    "FileFormatError",
    "InputError",
    "InternalError",
    "NothingToLearn",
    "Scene",
    "Stroke",
    "Terrain",
    "TerrainSurface",
    "WorldPaintError",
    "__version__",
    "apply_sketch",
    "arrangement_edited",
    "arrangement_summary",
    "assign_variants",
    "blur",
    "build_waterfall",
    "clear_region",
    "color_renamed",
    "color_summary",
    "color_without_interactions",
    "compare",
    "decompose_model",
    "default_encyclopedia",
    "embed_roads",
    "encyclopedia_contents",
    "exemplar_clustered",
    "exemplar_demo_terrain",
    "exemplar_hard_core",
    "exemplar_slope_scene",
    "exemplar_uniform",
    "exemplar_village",
    "fidelity",
    "fill_polygons",
    "generate_variants",
    "generate_village",
    "gradient",
    "import_place",
    "interpolate_colors",
    "learn_arrangement",
    "learn_color",
    "learn_village",
    "move_region",
    "palette_from_json",
    "palette_to_json",
    "paste",
    "read_world_tile",
    "region_area",
    "region_bbox",
    "region_contains",
    "scenario_presets",
    "stretch_region",
    "synthesize",
    "texture_variety",
    "village_interest",
    "world_plan",
    "world_tile",
    "world_villages",
]

# --- values the caller gives -----------------------------------------------------------------------------------------

Float64Array: TypeAlias = NDArray[np.float64]
Int32Array: TypeAlias = NDArray[np.int32]
Int64Array: TypeAlias = NDArray[np.int64]
# an (x, y) pair: a tuple, a list or an array of two numbers
Pair: TypeAlias = Sequence[float]
Box: TypeAlias = tuple[tuple[float, float], tuple[float, float]]
Progress: TypeAlias = Callable[[float], bool] | Callable[[float, str], bool]

class RectRegion(TypedDict):
    shape: Literal["rect"]
    min: Pair
    max: Pair

class CircleRegion(TypedDict):
    shape: Literal["circle"]
    center: Pair
    radius: float

class PolygonRegion(TypedDict):
    shape: Literal["polygon"]
    points: Sequence[Pair]

class ClippedRegion(TypedDict, total=False):
    shape: Required[Literal["clipped"]]
    within: Sequence[Region]
    without: Sequence[Region]

Region: TypeAlias = RectRegion | CircleRegion | PolygonRegion | ClippedRegion

class CategoryInput(TypedDict, total=False):
    """A category of a scene: all but the name optional (layer "default", kind "distribution", priority its
    index)."""

    name: Required[str]
    layer: str
    kind: str
    priority: int

class StructureInput(TypedDict):
    """A path (of a graph category) or a contour (of a polygon category) of a scene; ``locked`` defaults to True."""

    category: int
    points: ArrayLike
    locked: NotRequired[bool]

class AnalysisOptions(TypedDict, total=False):
    bin_width: float
    max_radius: float
    oriented: Sequence[tuple[str, str]]
    maps: Sequence[str]

class PatternGuides(TypedDict, total=False):
    """Where an arrangement color's pattern starts, the curves it must not cross and the curves it follows."""

    start: Pair | None
    boundaries: Sequence[ArrayLike] | None
    flow: Sequence[ArrayLike] | None

class SynthesisOptions(TypedDict, total=False):
    """The keywords of the tools that synthesize: how far around the region the scene conditions it (None: the
    color's interaction radius), the synthesis' iterations per instance (None: the engine's), and progress."""

    influence_radius: float | None
    iterations_per_instance: float | None
    progress: Progress | None

class PasteOptions(SynthesisOptions, total=False):
    """The keywords of ``synthesize`` and ``paste``: also the categories painted (None: all) and the guides of an
    arrangement color."""

    only_categories: Sequence[str] | None
    guides: PatternGuides | None

LinearShape = TypedDict("LinearShape", {"kind": Literal["linear"], "from": Pair, "to": Pair})

class RadialShape(TypedDict):
    kind: Literal["radial"]
    center: Pair
    radius: float

class BilinearShape(TypedDict):
    """The gradient shape whose two other colors (JSON) take the region's northern corners."""

    kind: Literal["bilinear"]
    north_west: str
    north_east: str

GradientShape: TypeAlias = LinearShape | RadialShape | BilinearShape

class Model(TypedDict):
    """A mesh as Blender's arrays read it: corners per face, the vertex of each corner face after face, a UV per
    corner and a material per face."""

    vertices: Float64Array
    loop_totals: Int64Array
    corners: Int64Array
    uvs: NotRequired[Float64Array | None]
    materials: NotRequired[Int64Array | None]

class Camera(TypedDict):
    """A camera: its eye, viewing direction and image up, and its frame on the plane one metre ahead."""

    eye: Sequence[float]
    forward: Sequence[float]
    up: Sequence[float]
    frame_min: Pair
    frame_max: Pair

class WaterfallController(TypedDict):
    kind: Literal["contact", "free_fall", "pool"]
    points: ArrayLike
    strength: NotRequired[float | None]

class WaterfallOptions(TypedDict, total=False):
    """The keywords of ``build_waterfall``; ``subdivide`` defaults to True."""

    min_slope: float | None
    overhang: float | None
    falloff: float | None
    freeboard: float | None
    max_width: float | None
    subdivide: bool
    rock_color: str | None

class InstanceOptions(TypedDict, total=False):
    """The instance columns a scene may go without (rotation 0, scale 1, prototype 0, locked, no tint)."""

    rotations: ArrayLike | None
    scales: ArrayLike | None
    prototype: ArrayLike | None
    locked: ArrayLike | None
    tints: ArrayLike | None

class SceneColumns(InstanceOptions, total=False):
    """The instance columns of a scene, as ``Scene`` takes them by keyword."""

    categories: Required[Sequence[CategoryInput]]
    positions: Required[ArrayLike]
    category_index: Required[ArrayLike]

class SceneStructures(TypedDict, total=False):
    paths: Sequence[StructureInput] | None
    contours: Sequence[StructureInput] | None

class SceneOptions(InstanceOptions, SceneStructures, total=False):
    """The keywords of ``Scene``."""

class ArrangementChanges(TypedDict, total=False):
    """The settings ``arrangement_edited`` changes; ``flip``: the two reference elements whose shared edge flips."""

    rotation: Literal["none", "best_fit", "flow"] | None
    scale_noise: float | None
    rotation_noise: float | None
    color_noise: float | None
    relax_every: int | None
    flip: tuple[int, int] | None

class Surroundings(TypedDict, total=False):
    """The water and walls around a village: ``generate_village`` and ``village_interest`` refuse other keywords."""

    water_level: float | None
    water_areas: Sequence[ArrayLike]
    rivers: Sequence[ArrayLike]
    river_half_width: float
    walls: Sequence[ArrayLike]

class VillageSetting(Surroundings, total=False):
    """The keywords of ``generate_village`` besides its progress."""

    encyclopedia: str | None
    connections: ArrayLike | None
    existing_roads: Sequence[ArrayLike] | None
    cell: float
    parcel_cell: float

class InterestSetting(Surroundings, total=False):
    """The keywords of ``village_interest``."""

    encyclopedia: str | None
    buildings: Sequence[tuple[str, float, float]] | None
    roads: Sequence[ArrayLike] | None
    cell: float

# --- what the engine returns -----------------------------------------------------------------------------------------

class CategoryDict(TypedDict):
    name: str
    layer: str
    kind: str
    priority: int

class Polyline(TypedDict):
    """A path or contour: its category index, XY points (N, 2) and terrain heights (N,), NaN off the terrain."""

    category: int
    points: Float64Array
    heights: Float64Array

class InstanceColumns(TypedDict):
    """Instances as columns: XY (N, 2), terrain height (NaN without one), rotation about Z, scale, category index,
    prototype and tint."""

    positions: Float64Array
    heights: Float64Array
    rotations: Float64Array
    scales: Float64Array
    category_index: Int32Array
    prototype: Int32Array
    tints: NDArray[np.float32]

class EditDict(InstanceColumns):
    """An edit of a scene: the rows of the instances removed, the instances added, the paths and contours removed
    (indices) and added, and the share of the painted region where each map read values the example never showed."""

    categories: list[CategoryDict]
    removed: Int64Array
    removed_paths: Int64Array
    removed_contours: Int64Array
    added_paths: list[Polyline]
    added_contours: list[Polyline]
    unseen_maps: dict[str, float]

class SynthesisDict(InstanceColumns):
    categories: list[CategoryDict]
    paths: list[Polyline]
    contours: list[Polyline]

class FidelityDict(TypedDict):
    density_ratio: dict[str, float]
    rdf_l2: list[tuple[str, str, float]]
    map_tv: list[tuple[str, str, float]]
    too_few: list[str]
    worst_density_error: float
    max_rdf_l2: float
    max_map_tv: float

class FidelityViewDict(FidelityDict):
    image: NDArray[np.uint8]
    max_distance: float
    max_pcf: float
    max_slope_degrees: float | None
    candidate: str

class PatternFidelityDict(TypedDict):
    ring_share: float
    reference_ring_share: float
    interior: int
    elements: int
    count_ratio: float

class PastedDict(EditDict):
    fidelity: FidelityDict | None
    fidelity_error: NotRequired[str]
    pattern: NotRequired[PatternFidelityDict]

class MovedDict(EditDict):
    moved: int
    displaced: int
    reborn: int
    lost: int
    stayed: int

class StretchedDict(EditDict):
    seam: Float64Array
    band: Region
    region: RectRegion  # the stretched rectangle, resized
    pushed_off: int

class ColorCategoryDict(CategoryDict):
    count: int
    density: float
    min_distance: float

class ColorSummaryDict(TypedDict):
    name: str
    region: Region
    region_area: float
    max_radius: float
    bin_width: float
    categories: list[ColorCategoryDict]
    pairs: list[tuple[str, str, str]]
    maps: list[tuple[str, str, str]]
    shortest_edges: list[tuple[str, float]]
    preview: Float64Array
    preview_size: tuple[float, float]

class LatticeDict(TypedDict):
    name: str
    spacing: float
    spread: float

class ArrangementSettings(TypedDict):
    """How an arrangement color paints: its elements' rotation, the noise of their scale, rotation (radians) and
    tint, and every how many elements the growing pattern relaxes (0: at the end only)."""

    rotation: str
    scale_noise: float
    rotation_noise: float
    color_noise: float
    relax_every: int

class ArrangementSummaryDict(ArrangementSettings):
    positions: Float64Array
    symbols: list[int]
    edges: Int64Array
    boundary: list[bool]
    flips: int
    lattice: LatticeDict | None

class FilledPolygonsDict(TypedDict):
    vertices: Float64Array
    heights: Float64Array
    triangles: Int32Array

class SceneDict(InstanceColumns):
    categories: list[CategoryDict]

class SlopeSceneDict(SceneDict):
    terrain: Terrain | None

class VillageSceneDict(SceneDict):
    paths: list[Polyline]
    contours: list[Polyline]

class DecompositionDict(TypedDict):
    labels: list[int]
    faces: list[int]
    regions: list[tuple[int, int, int]]
    root: int
    fully_cyclic: bool
    tree_like: bool
    components: list[Model]

class MemoryDict(TypedDict):
    overhead_percent: float
    original_bytes: int
    shared_bytes: int
    full_bytes: int

class VariantsDict(TypedDict):
    classes: list[list[str]]
    memory: MemoryDict
    total: str
    exhausted: bool
    models: list[Model]
    face_origin: list[Int64Array]
    hashes: list[str]
    rejected: list[tuple[str, str]]

class TextureComponentDict(TypedDict):
    texels: int
    face_texels: int
    faces: Int64Array

class TextureVarietyDict(TypedDict):
    components: list[TextureComponentDict]
    conflicts: list[tuple[int, int]]
    atlas_of: Int64Array
    atlases: int
    exact: bool
    images: list[NDArray[np.uint8]]
    chosen: list[list[int]]
    face_atlas: Int64Array

class VillageSeedsDict(TypedDict):
    positions: Float64Array
    heights: Float64Array
    building: list[str]
    village_type: list[str]

class RoadDict(TypedDict):
    points: Float64Array
    heights: Float64Array

class HouseDict(TypedDict):
    seed: int
    vertices: Float64Array
    loop_starts: Int32Array
    loop_totals: Int32Array
    indices: Int32Array
    materials: Int32Array

class VillageReportDict(TypedDict):
    requested: int
    seeded: int
    fallbacks: int
    unplaced: list[str]
    # per building type left unplaced: of unplaced_candidates places, how many each criterion forbade, "land"
    # (off the buildable land) and "no_interest"
    unplaced_causes: dict[str, dict[str, int]]
    unplaced_candidates: int
    unreachable: int
    without_access: int
    without_footprint: int
    roads_over_max_grade: int
    cycles: int
    seconds: list[float]
    road_width: float
    max_grade: float

class VillageDict(TypedDict):
    seeds: VillageSeedsDict
    roads: list[RoadDict]
    parcels: list[Float64Array]
    footprints: Float64Array
    houses: list[HouseDict]
    connections: Float64Array
    report: VillageReportDict

class VillageFiguresDict(TypedDict):
    buildings: int
    mean_nearest_neighbour: float
    share_within_20m: float
    road_length_per_house: float
    mean_road_distance: float
    buildings_per_hectare: float
    road_length: float
    hairpins_per_km: float
    dead_end_share: float
    orientation_to_road: list[float]

class LearnedVillageDict(TypedDict):
    encyclopedia: str
    scenario: str
    base_type: str
    objective: float
    held_out_objective: float | None
    base_objective: float
    evaluations: int
    generations: int
    seconds: float
    stopped_early: bool
    real: VillageFiguresDict

class RoadEmbeddingDict(TypedDict):
    displacement: Float64Array
    profiles: list[Float64Array]
    residual: float
    cycles: int
    converged: bool

class WaterMeshDict(TypedDict):
    vertices: Float64Array
    triangles: NDArray[np.uint32]
    speed: Float64Array
    speed_xy: Float64Array
    foam: Float64Array
    rocks: Float64Array
    disturbance: Float64Array
    invalid: Float64Array
    part: Int32Array

class WaterfallSegmentDict(TypedDict):
    type: str
    arc: int
    controller: int
    slope: float
    flow: float
    speed: float
    width: float
    depth: float
    valid: bool
    points: Float64Array

class WaterfallNodesDict(TypedDict):
    source: int
    well: int
    branch: int
    pool: int

class WaterfallReportDict(TypedDict):
    nodes: WaterfallNodesDict
    arcs: int
    segments: int
    invalid_segments: int
    max_flow_imbalance: float
    water_nodes: int
    rocks: int
    converged: bool

class WaterfallDict(TypedDict):
    displacement: Float64Array
    horizontal: Float64Array
    is_water: NDArray[np.bool_]
    water: WaterMeshDict
    segments: list[WaterfallSegmentDict]
    rocks: Float64Array
    rock_rotation: Float64Array
    rock_scale: Float64Array
    rock_prototype: Int32Array
    report: WaterfallReportDict

class SketchSecondsDict(TypedDict):
    ordering: float
    features: float
    matching: float
    deformation: float
    lowering: float

class SketchDict(TypedDict):
    displacement: Float64Array
    order: list[int]
    junctions: int
    features: list[Float64Array]
    feature_kinds: list[str]
    curves: list[Float64Array]
    curve_breaks: list[list[int]]
    sources: list[int]
    lowered: list[Float64Array]
    rounds: int
    hidden_columns: int
    reach: float
    seconds: SketchSecondsDict

class WorldPlanDict(TypedDict):
    min: tuple[float, float]
    max: tuple[float, float]
    tile: float
    influence: float
    columns: int
    rows: int
    # (column, row, phase, [(column, row) of the earlier neighbours it is conditioned on])
    tiles: list[tuple[int, int, int, list[tuple[int, int]]]]
    # the tiles' category names: every category of the colors, each once, in the legend's order
    categories: list[str]

class ColorMapDict(TypedDict):
    # uint32 (ny, nx), row 0 at the smallest Y
    labels: NDArray[np.uint32]
    origin: tuple[float, float]
    cell: float
    # label -> color JSON
    legend: dict[int, str]
    # width of the transition band (m); None: three regions of influence
    band: float | None

class ObstaclesDict(TypedDict):
    # house outlines (N, 2) and road polylines (N, 2), the roads `width` metres wide
    footprints: Sequence[ArrayLike]
    roads: Sequence[ArrayLike]
    width: float

class VillageSiteDict(TypedDict):
    position: tuple[float, float]
    type: str
    buildings: int
    seed: int

class WorldVillagesDict(TypedDict):
    roads: list[RoadDict]
    road_width: float
    villages: list[VillageDict]

class WorldTileDict(InstanceColumns):
    column: int
    row: int
    categories: list[str]

class TerrainGrid(TypedDict):
    origin: tuple[float, float]
    cell: float
    nx: int
    ny: int
    heights: NDArray[np.float32]

class Limits(TypedDict):
    grid_cells: int
    instances: int
    world_instances: int
    world_tiles: int
    iterations_per_instance: int

# --- the module ------------------------------------------------------------------------------------------------------

__version__: Final[str]
PALETTE_FORMAT_VERSION: Final[int]
LIMITS: Final[Limits]

class WorldPaintError(Exception): ...
class InputError(WorldPaintError, ValueError): ...
class FileFormatError(InputError): ...
class NothingToLearn(InputError): ...  # noqa: N818 (the module's names)
class Cancelled(WorldPaintError): ...  # noqa: N818
class InternalError(WorldPaintError): ...

class Terrain:
    def __new__(cls, vertices: ArrayLike, triangles: ArrayLike, cell: float | None = None) -> Terrain: ...
    @staticmethod
    def from_grid(origin: tuple[float, float], cell: float, heights: ArrayLike) -> Terrain: ...
    def heights_at(self, xy: ArrayLike) -> Float64Array: ...
    def map_at(self, name: str, xy: ArrayLike) -> Float64Array: ...
    def with_vertex_map(self, name: str, vertices: ArrayLike, triangles: ArrayLike, values: ArrayLike) -> Terrain: ...
    def with_distance_map(self, name: str, vertices: ArrayLike, edges: ArrayLike, triangles: ArrayLike) -> Terrain: ...
    def bbox(self) -> Box: ...
    def map_names(self) -> list[str]: ...
    def grid(self) -> TerrainGrid: ...
    def __repr__(self) -> str: ...

class TerrainSurface:
    def __new__(cls, vertices: ArrayLike, triangles: ArrayLike) -> TerrainSurface: ...
    def heights(self, xy: ArrayLike) -> Float64Array: ...

class Scene:
    def __new__(
        cls,
        terrain: Terrain | None,
        categories: Sequence[CategoryInput],
        positions: ArrayLike,
        category_index: ArrayLike,
        **options: Unpack[SceneOptions],
    ) -> Scene: ...
    def __len__(self) -> int: ...

class Stroke:
    def __new__(
        cls,
        scene: Scene,
        *,
        color: str | None = None,
        erase: bool = False,
        only_categories: Sequence[str] | None = None,
        radius: float = 20.0,
        spacing: float = 0.5,
        opacity: float = 1.0,
        falloff: Literal["constant", "linear", "smooth"] = "constant",
        seed: int = 0,
        influence_radius: float | None = None,
        iterations_per_instance: float | None = None,
        guides: PatternGuides | None = None,
        shortest_edges: dict[str, float] | None = None,
    ) -> Stroke: ...
    def follow(self, path: ArrayLike, progress: Progress | None = None) -> int: ...
    def edit(self) -> EditDict: ...
    def dabs(self) -> Float64Array: ...

# colors and palettes

def learn_color(scene: Scene, region: Region, name: str, *, options: AnalysisOptions | None = None) -> str: ...
def synthesize(
    scene: Scene,
    color: str,
    region: Region,
    seed: int = 0,
    **options: Unpack[PasteOptions],
) -> SynthesisDict: ...
def interpolate_colors(a: str, b: str, t: float, name: str) -> str: ...
def color_renamed(color: str, name: str) -> str: ...
def compare(reference: str, candidate: str) -> FidelityDict: ...
def fidelity(
    color: str,
    terrain: Terrain | None = None,
    seed: int = 0,
    *,
    width: int = 256,
    height: int = 128,
    progress: Progress | None = None,
) -> FidelityViewDict: ...
def palette_to_json(colors: Sequence[str]) -> str: ...
def palette_from_json(text: str) -> list[str]: ...
def color_summary(color: str) -> ColorSummaryDict: ...
def color_without_interactions(color: str, off: Sequence[tuple[str, str]]) -> str: ...

# arrangements

def learn_arrangement(scene: Scene, region: Region, name: str) -> str: ...
def arrangement_summary(color: str) -> ArrangementSummaryDict | None: ...
def arrangement_edited(color: str, **changes: Unpack[ArrangementChanges]) -> str: ...

# exemplars

def exemplar_uniform(region: Region, density: float, seed: int) -> Float64Array: ...
def exemplar_clustered(
    region: Region, parent_density: float, children_mean: float, sigma: float, seed: int
) -> Float64Array: ...
def exemplar_hard_core(region: Region, density: float, min_distance: float, seed: int) -> Float64Array: ...
def exemplar_slope_scene(size: float, seed: int) -> SlopeSceneDict: ...
def exemplar_village(size: float, seed: int) -> VillageSceneDict: ...
def exemplar_demo_terrain(size: float, cell: float, seed: int) -> Terrain: ...

# regions

def region_contains(region: Region, xy: ArrayLike) -> NDArray[np.bool_]: ...
def region_area(region: Region) -> float: ...
def region_bbox(region: Region) -> Box: ...
def fill_polygons(
    contours: Sequence[ArrayLike], spacing: float, terrain: Terrain | None = None
) -> FilledPolygonsDict: ...

# painting tools

def paste(
    scene: Scene,
    color: str,
    region: Region,
    seed: int = 0,
    **options: Unpack[PasteOptions],
) -> PastedDict: ...
def clear_region(scene: Scene, region: Region, *, category: str | None = None) -> EditDict: ...
def move_region(
    scene: Scene,
    color: str | None,
    source: Region,
    offset: tuple[float, float],
    seed: int = 0,
    *,
    influence_radius: float | None = None,
    steps: int | None = None,
    reach: float | None = None,
) -> MovedDict: ...
def stretch_region(
    scene: Scene,
    region: Region,
    side: Literal["east", "west", "north", "south"],
    amount: float,
    color: str | None = None,
    seed: int = 0,
    *,
    cell: float | None = None,
    **options: Unpack[SynthesisOptions],
) -> StretchedDict: ...
def gradient(
    scene: Scene,
    start: str,
    end: str,
    region: Region,
    shape: GradientShape,
    bands: int | None = None,
    seed: int = 0,
    **options: Unpack[SynthesisOptions],
) -> EditDict: ...
def blur(
    scene: Scene,
    region: Region,
    seed: int = 0,
    *,
    windows: int = 8,
    cells: int = 4,
    **options: Unpack[SynthesisOptions],
) -> EditDict: ...

# model variety

def decompose_model(model: Model, labels: Int64Array, root: int | None = None) -> DecompositionDict: ...
def generate_variants(
    model: Model,
    labels: Int64Array,
    variants: Sequence[Sequence[Model]],
    count: int,
    seed: int = 0,
    *,
    root: int | None = None,
    cycles: Sequence[tuple[int, int]] | None = None,
    picks: Sequence[int] | None = None,
    names: Sequence[str] | None = None,
    variant_names: Sequence[Sequence[str]] | None = None,
    progress: Progress | None = None,
) -> VariantsDict: ...
def assign_variants(
    positions: ArrayLike, fixed: Int64Array, count: int, window: float = 50.0, seed: int = 0
) -> Int64Array: ...
def texture_variety(
    model: Model,
    base: NDArray[np.uint8],
    edits: Sequence[NDArray[np.uint8]],
    count: int,
    probability: float = 0.5,
    seed: int = 0,
    *,
    names: Sequence[str] | None = None,
) -> TextureVarietyDict: ...

# villages

def default_encyclopedia() -> str: ...
def scenario_presets() -> str: ...
def encyclopedia_contents(encyclopedia: str) -> tuple[list[str], list[str]]: ...
def generate_village(
    terrain: Terrain,
    region: Region,
    scenario: str,
    seed: int = 0,
    *,
    encyclopedia: str | None = None,
    connections: ArrayLike | None = None,
    existing_roads: Sequence[ArrayLike] | None = None,
    cell: float = 2.0,
    parcel_cell: float = 1.0,
    progress: Progress | None = None,
    **surroundings: Unpack[Surroundings],
) -> VillageDict: ...
def learn_village(
    terrain: Terrain,
    region: Region,
    buildings: ArrayLike,
    orientations: ArrayLike,
    roads: Sequence[ArrayLike],
    *,
    encyclopedia: str | None = None,
    base_type: str | None = None,
    name: str = "learned",
    connections: ArrayLike | None = None,
    seeds: Sequence[int] | None = None,
    seed: int = 1,
    max_evaluations: int = 0,
    max_seconds: float = 540.0,
    cell: float = 2.0,
    parcel_cell: float = 1.0,
    progress: Progress | None = None,
    **surroundings: Unpack[Surroundings],
) -> LearnedVillageDict: ...
def village_interest(
    terrain: Terrain,
    region: Region,
    points: ArrayLike,
    village_type: str,
    building: str,
    criterion: str | None = None,
    *,
    encyclopedia: str | None = None,
    buildings: Sequence[tuple[str, float, float]] | None = None,
    roads: Sequence[ArrayLike] | None = None,
    cell: float = 2.0,
    **surroundings: Unpack[Surroundings],
) -> Float64Array: ...

# terrain edits

def embed_roads(
    terrain: Terrain,
    roads: Sequence[ArrayLike],
    points: ArrayLike,
    width: float = 5.0,
    bank_width: float = 8.0,
    *,
    use_heights: bool = False,
    smoothing: float | None = None,
) -> RoadEmbeddingDict: ...
def build_waterfall(
    terrain: Terrain,
    controllers: Sequence[WaterfallController],
    points: ArrayLike,
    seed: int = 0,
    **options: Unpack[WaterfallOptions],
) -> WaterfallDict: ...
def apply_sketch(
    terrain: Terrain,
    camera: Camera,
    strokes: Sequence[ArrayLike],
    points: ArrayLike,
    *,
    reach: float | None = None,
    completion: bool = True,
    aspect: float | None = None,
    max_change: float | None = None,
    max_camera_distance: float | None = None,
    progress: Progress | None = None,
) -> SketchDict: ...

# worlds in tiles

def world_plan(
    paint: str | ColorMapDict,
    min: tuple[float, float],
    max: tuple[float, float],
    *,
    tile: float | None = None,
    iterations_per_instance: float | None = None,
) -> WorldPlanDict: ...
def world_tile(
    paint: str | ColorMapDict,
    plan: WorldPlanDict,
    column: int,
    row: int,
    neighbours: Sequence[bytes],
    seed: int,
    *,
    terrain: Terrain | None = None,
    iterations_per_instance: float | None = None,
    obstacles: ObstaclesDict | None = None,
) -> tuple[bytes, bytes, list[int]]: ...
def world_villages(
    terrain: Terrain,
    min: tuple[float, float],
    max: tuple[float, float],
    sites: Sequence[VillageSiteDict],
    *,
    encyclopedia: str | None = None,
    cell: float = 2.0,
) -> WorldVillagesDict: ...
def read_world_tile(data: bytes) -> WorldTileDict: ...

# real places

class PlaceFrameDict(TypedDict):
    """Where a place's metres are: (lon, lat) of the local origin and the proj string from WGS84 lon/lat; both None
    for a place of local data only."""

    origin: tuple[float, float] | None
    projection: str | None

class PlaceSourcesDict(TypedDict):
    layers: list[str]
    elevation: str | None
    inventory: str | None

class PlaceBuildingsDict(TypedDict):
    """One row per building: area centroid, its ground height, the minimum-area rectangle's (length, width) and its
    long side's angle from +X in [0, pi), the area, the type (house, farm, church, barn, shed, apartments,
    industrial, commercial, garage, other), the ``building`` tag, the name ("" when none), and the footprint rings
    (outer counter-clockwise, holes clockwise)."""

    centroid: Float64Array
    height: Float64Array
    size: Float64Array
    orientation: Float64Array
    area: Float64Array
    type: list[str]
    building: list[str]
    name: list[str]
    footprints: list[list[Float64Array]]

class PlaceLinesDict(TypedDict):
    """One row per line: its (N, 2) points and their ground heights (N,), NaN off the terrain, and its name."""

    name: list[str]
    points: list[Float64Array]
    heights: list[Float64Array]

class PlaceRoadsDict(PlaceLinesDict):
    """``kind``: the road's class, major, minor, residential, track, path or other; ``highway``: the tag."""

    kind: list[str]
    highway: list[str]

class PlaceWaterwaysDict(PlaceLinesDict):
    """``kind``: the ``waterway`` tag (river, stream, canal, ditch...)."""

    kind: list[str]

class PlaceAreasDict(TypedDict):
    """``kind``: the area's class, water, residential, commercial, industrial, farmland, meadow, orchard, forest,
    farmyard, cemetery, wetland or other; ``tag``: the tag it was classed by (``landuse=forest``); rings as the
    footprints'."""

    kind: list[str]
    tag: list[str]
    name: list[str]
    rings: list[list[Float64Array]]

class PlacePointsDict(TypedDict):
    """Named places: ``kind`` is the ``place`` tag (village, hamlet, town...)."""

    position: Float64Array
    height: Float64Array
    kind: list[str]
    name: list[str]

class PlaceTreesDict(TypedDict):
    """``size``: the inventory's dbh or height, NaN where unknown."""

    position: Float64Array
    height: Float64Array
    species: list[str]
    size: Float64Array

class PlaceReportDict(TypedDict):
    features: int
    unreadable: int
    left_out: int
    trees_not_alive: int
    trees_unreadable: int
    holes_filled: int
    hole_share: float
    source_spacing: tuple[float, float] | None

class PlaceDict(TypedDict):
    frame: PlaceFrameDict
    sources: PlaceSourcesDict
    terrain: TerrainGrid | None
    buildings: PlaceBuildingsDict
    roads: PlaceRoadsDict
    waterways: PlaceWaterwaysDict
    areas: PlaceAreasDict
    places: PlacePointsDict
    trees: PlaceTreesDict
    report: PlaceReportDict

def import_place(
    geojson_paths: Sequence[str | PathLike[str]],
    dem_path: str | PathLike[str] | None = None,
    inventory_path: str | PathLike[str] | None = None,
    *,
    origin: tuple[float, float] | None = None,
    cell: float | None = None,
    margin: float = 200.0,
    progress: Progress | None = None,
) -> PlaceDict: ...

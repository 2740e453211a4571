//! # worldpaint-core
//!
//! The engine of worldpaint: an implementation of *WorldBrush: Interactive Example-based Synthesis of Procedural
//! Virtual Worlds* (Emilien et al., SIGGRAPH 2015). An exemplar arrangement of instances (trees, rocks, grass on a
//! terrain) is analysed into a *color* — interaction histograms between categories (radial distribution functions,
//! eq. (2)), map-sampling histograms of external maps such as slope — and a Metropolis-Hastings birth-and-death
//! sampler (eq. (1)) paints new arrangements with the same statistics into any region, consistent with what
//! surrounds it (the region of influence).
//!
//! The modules are private: what a caller uses is re-exported at the crate root under a name that says what it is
//! (`worldpaint_core::generate_village`, `worldpaint_core::VillageRequest`). The main entry points of each module
//! are named beside it.
//!
//! | module | part of the paper |
//! |---|---|
//! | `error` ([`Error`], [`Result`]) | typed errors: what was wrong, the bad value and the rule it breaks |
//! | `geom` ([`Region`], [`PreparedRegion`], [`VerticalLookup`]) | active regions, window-edge correction α (§3, §4.1); a region prepared once for many queries (indexed polygons); the height of a triangle mesh under points |
//! | `search` | the min-cost order of the best-first (Dijkstra, A*) searches |
//! | `spatial` | neighbour queries behind the product simplification (§6) |
//! | `graph` ([`Graph`], [`SegmentIndex`]) | roads and rivers as planar graphs of intersecting paths, segment queries (§4.2) |
//! | `grid` ([`Grid`]) | one regular grid for every raster and bucket index, with its two size rules |
//! | `limits` ([`check`], [`MAX_INSTANCES`], [`MAX_GRID_CELLS`]) | the work budget every entry point checks before allocating: instances, cells, bins, region size |
//! | `progress` | progress and cancelling of work done item by item on several threads |
//! | `contour` ([`fill_polygons`], [`trace_contours`], [`islands`]) | islands and lakes: contours to dense points and back, signed distance (§6, thesis 6.2.1) |
//! | `polygon_mesh` ([`triangulate`]) | polygons as a filled mesh (constrained Delaunay triangulation) for display |
//! | `terrain` ([`Heightfield`]) | the terrain and its external maps (§3) |
//! | `distance` ([`distance_transform`]) | exact Euclidean distance transforms on grids |
//! | `scene_maps` | maps made in the scene on the terrain's grid: a value per mesh vertex, the distance to geometry (§3) |
//! | `terrain_edit` ([`diffuse`], [`embed_roads`]) | terrain that adapts: constraint-based deformation by multigrid diffusion (thesis 4.4.2, 5.3.3) |
//! | `sketch` ([`apply_sketch`], [`SketchStroke`], [`Camera`]) | terrain edited from silhouettes sketched over a first-person view (thesis ch. 5) |
//! | `scene` ([`Scene`], [`Category`], [`Instance`]) | categories, priority order, instances (§3) |
//! | `palette` ([`Color`], [`Palette`]) | histograms, colors, palettes (§3, §4.1) |
//! | `analysis` ([`learn_color`]) | learning a color (§4.1); its radius, which follows a clustered example (`radius`), the pair correlation of a map preference (`intensity`), and the instances' sizes and facing of the nearest road ([`RoadFacing`], `facing`) |
//! | `compare` ([`compare()`], [`Fidelity`], [`self_synthesis`]) | fidelity metrics between two colors; a color learned back from what it painted |
//! | `fidelity_plot` ([`draw_fidelity`]) | the fidelity picture: example and self-synthesis pcf and slope histograms |
//! | `interpolate` ([`interpolate_colors`]) | distribution interpolation by optimal mass transport (§5.2) |
//! | `paint` ([`synthesize`]) | the one door through which a color is painted into a scene, whichever kind it is |
//! | `synthesis` ([`SynthesisOptions`], [`SynthesisResult`]) | Metropolis-Hastings synthesis with a region of influence (§4.1, §4.3, §5.1, §6); adapting moved content (§5.4); island count and size matched after tracing (`islands`) |
//! | `tools` ([`paste`], [`BrushStroke`], [`move_region`], [`stretch`], [`gradient`], [`blur`]) | the painting tools: paste, brush and eraser, move, seam-carving stretch, gradient, blur (§5) |
//! | `world` ([`WorldPlan`], [`synthesize_tile`]) | worlds larger than one paste, synthesized tile by tile |
//! | `village` ([`generate_village`], [`VillageRequest`], [`Encyclopedia`]) | villages on arbitrary terrain: growth, roads, parcels, houses (thesis ch. 3) |
//! | `waterfall` ([`build_waterfall_scene`], [`WaterfallParams`]) | waterfall scenes: controller network, hydraulic graph and flow, terrain-adapted subdivision, slope-flow types, integration mesh, terrain deformation, decoration maps (thesis ch. 4) |
//! | `variety` ([`generate_variants`], [`Atlas`], [`Model`]) | model variety (Maréchal et al.): components, connecting regions, variant atlas, assembly with frames, self-intersection rejection, texture components |
//! | `arrangement` ([`grow_arrangement`], [`relax_arrangement`]) | element arrangement by example (Ijiri et al. 2008): reference connectivity, local growth from a seed, relaxation |
//! | `exemplar` ([`uniform_points`], [`slope_scene`], [`demo_terrain`]) | generating processes for demo scenes, tests and benchmarks |
//! | `place` ([`import_place`]) | real places: OpenStreetMap layers, elevation models and tree inventories in a local metric frame |

// `!(x > 0.0)` is used on purpose: it rejects NaN as well as non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::nonminimal_bool)]
// Every public item says what it is; `make lint` turns this into an error.
#![warn(missing_docs)]
// An item is `pub` only when the root re-exports it; internal helpers are `pub(crate)`.
#![warn(unreachable_pub)]

mod analysis;
mod arrangement;
mod compare;
mod contour;
mod distance;
mod error;
mod exemplar;
mod fidelity_plot;
mod geom;
mod graph;
mod grid;
mod interpolate;
mod limits;
mod paint;
mod palette;
mod place;
mod polygon_mesh;
mod progress;
mod scene;
mod scene_maps;
mod search;
mod sketch;
mod spatial;
mod synthesis;
mod terrain;
mod terrain_edit;
mod tools;
mod variety;
mod village;
mod waterfall;
mod world;

// analysis: learning a color
pub use analysis::{learn_arrangement, learn_color, AnalysisOptions, HeldGraph, SLOPE_BIN_DEGREES};
// arrangement: element arrangement by example
pub use arrangement::{
    grow_arrangement, grow_arrangement_around, pattern_fidelity, reference_density,
    relax_arrangement, Arrangement, Element, FlowField, GrowthNoise, GrowthOptions,
    PatternFidelity, PatternGuides, PatternRotation, ReferenceArrangement, RingMatch, RotationMode,
    DEFAULT_RELAX_EVERY, RING_RADIUS,
};
// compare: fidelity between colors
pub use compare::{compare, learned_back, self_synthesis, Fidelity};
// contour: islands and lakes as dense points and back
pub use contour::{fill_polygons, islands, trace_contours, Polygons};
// distance: distance transforms
pub use distance::distance_transform;
// error
pub use error::{Error, FileKind, Result};
// exemplar: demo scenes and terrains
pub use exemplar::{
    archipelago_scene, clustered_points, demo_terrain, hard_core_points, random_strokes,
    river_rocks, rough_terrain, scene_from_points, slope_scene, undergrowth_scene, uniform_points,
    village_scene, village_terrain, waterfall_controllers, RIVER_ROCK_CATEGORY, RIVER_ROCK_DENSITY,
    RIVER_ROCK_SPACING,
};
// fidelity_plot
pub use fidelity_plot::{draw_fidelity, FidelityPlot};
// geom: regions, polygons and the height of a mesh under points
pub use geom::{
    polygon_contains, polygon_signed_area, segment_distance, segments_distance, DVec2, DVec3,
    PreparedRegion, Region, RegionQueries, VerticalLookup,
};
// graph: roads and rivers as planar graphs
pub use graph::{Graph, SegmentIndex};
// grid
pub use grid::Grid;
// interpolate: interpolation between colors
pub use interpolate::{displacement_interpolate, interpolate_colors};
// limits: the work budget
pub use limits::{
    check, MAX_GRID_CELLS, MAX_INSTANCES, MAX_ITERATIONS_PER_INSTANCE, MAX_PLACE_FILE_BYTES,
    MAX_REGION_DEPTH, MAX_WORLD_INSTANCES,
};
// paint: a color painted into a scene
pub use paint::{painted_fidelity, synthesize, synthesize_with_progress};
// palette: histograms, colors, palettes
pub use palette::{
    Color, ColorKind, GraphColor, Histogram, Interaction, MapSource, Palette, RoadFacing,
    PALETTE_FORMAT_VERSION,
};
// place: real places read from map, elevation and inventory files
pub use place::{
    import_place, min_area_rectangle, read_elevation_model, read_map_layer, read_tree_inventory,
    AreaClass, BuildingType, ElevationModel, InventoryCoordinates, InventoryRow, InventoryTree,
    LocalProjection, LonLat, LonLatShape, MapFeature, MapLayer, MappedArea, MappedBuilding,
    MappedRoad, MappedWaterway, NamedPlace, Place, PlaceFrame, PlaceOptions, PlaceReport,
    PlaceSources, RoadClass, TerrainReport, TreeInventory, DEFAULT_MARGIN, MAX_EXTENT_DEGREES,
    MAX_HOLE_SHARE,
};
// polygon_mesh
pub use polygon_mesh::triangulate;
// scene
pub use scene::{Category, CategoryKind, Contour, Instance, Path, Scene};
// sketch: terrain edited from sketched silhouettes
pub use sketch::apply::{apply_sketch, stroke_targets, CurveSource, SketchEdit, SketchOptions};
pub use sketch::checks::MAX_MATCHING_WORK;
pub use sketch::deform::{deform_to_targets, SketchDeformOptions, StrokeTarget};
pub use sketch::features::{detect_features, ridges, silhouettes, FeatureOptions};
pub use sketch::matching::{MatchingOptions, MAX_ASSIGNMENT_NODES};
pub use sketch::{Camera, Feature, FeatureKind, Sight, SketchStroke};
// synthesis
pub use synthesis::{AdaptOptions, SynthesisOptions, SynthesisResult};
// terrain
pub use terrain::Heightfield;
// terrain_edit: constraint-based terrain deformation
pub use terrain_edit::rasterize::{
    rasterize_corridor, rasterize_gradient_polyline, rasterize_point, rasterize_polyline,
};
pub use terrain_edit::{
    diffuse, diffuse_horizontal, diffuse_jacobi, embed_road, embed_roads, laplace_residual,
    Constraints, DiffusionOptions, EmbeddedRoad, HorizontalConstraints, RoadEmbedding,
    RoadEmbeddingOptions, RoadProfile,
};
// tools: the painting tools
pub use tools::blur::{blur, BlurOptions};
pub use tools::brush::{BrushMode, BrushOptions, BrushStroke, Falloff};
pub use tools::gradient::{bilinear_gradient, gradient, GradientOptions, GradientShape};
pub use tools::moving::{move_region, Moved};
pub use tools::stretch::{stretch, StretchOptions, StretchSide, Stretched};
pub use tools::{clear_region, color_of_region, paste, with_painted_preview, ToolEdit};
// variety: model variety
pub use variety::model::error_about as model_error_about;
pub use variety::{
    assign_variants, atlas_images, check_assemblies, check_assembly, generate as generate_variants,
    memory_report, new_intersection, pack_components, pick_texture_variants, pick_textures,
    Assembled, Atlas, Choice, Decomposition, GenerateOptions, Generation, Image,
    IntersectionLabels, MemoryReport, Model, Rejection, TextureComponent, VariantClass,
};
// village: villages on arbitrary terrain
pub use village::encyclopedia::{
    BuildingKind, FootprintSize, ParcelParams, Placement, RoadParams, RoofStyle, ScenarioEvent,
};
pub use village::footprint::{house_footprint, house_footprints};
pub use village::generate::{
    generate_village, interest_at, InterestRequest, Village, VillageReport, VillageRequest,
    VillageStage, UNPLACED_CANDIDATES,
};
pub use village::house::{
    build_house, house_layout, openings_below_ground, HouseReport, OpeningKind, PlacedOpening,
};
pub use village::interest::{InterestCriterion, StaticInterestMaps};
// village::figures, village::fit: a village's figures, and a village type learned from a real village's
pub use village::figures::{
    hairpins, network_shape, village_figures, NetworkShape, SitedBuilding, VillageFigures,
    ORIENTATION_BINS,
};
pub use village::fit::objective::{objective as village_objective, Figure as FitFigure};
pub use village::fit::{
    border_crossings, fit_village_type, grow_village_figures, rank_village_types, scenario_for,
    FitOptions, FitProgress, FitTarget, FittedVillage, RankedType,
    MIN_BUILDINGS as FIT_MIN_BUILDINGS,
};
pub use village::metrics::{
    footprint_conflicts, layout_statistics, mean_elevation_percentile, road_grades, road_length,
    unreachable_footprints, LayoutStatistics,
};
pub use village::parcels::{
    parcel_statistics, parcel_statistics_with, parcels, parcels_with, ParcelOptions, ParcelSeed,
    ParcelStatistics,
};
pub use village::roads::{RoadConnection, RoadNetwork};
pub use village::{
    BuildingSeed, Encyclopedia, Environment, HouseFootprint, HouseMaterial, HouseMesh, Land,
    Parcel, Road, Scenario, ScenarioPresets, Site,
};
// waterfall: waterfall scenes
pub use waterfall::classify::classify_waterfall;
pub use waterfall::hydraulics::{distribute_flow, max_imbalance};
pub use waterfall::subdivide::{detail_length, downhill, MAX_DEVIATION_FACTOR};
pub use waterfall::{
    build_waterfall_network, build_waterfall_scene, river_rock_color, waterfall_footprint,
    Controller, ControllerKind, HydraulicGraph, HydraulicNodeKind, Rock, WaterPart,
    WaterfallFootprint, WaterfallNetwork, WaterfallParams, WaterfallScene, WaterfallSceneOptions,
    WaterfallSceneReport, WaterfallType, ROCK_MAP, TABLE_4_1,
};
// world: worlds of tiles
pub use world::tile_file::{decode_tile, encode_tile};
pub use world::{
    check_iterations, grow_world_villages, road_categories, synthesize_tile, village_side, Block,
    ColorMap, LabelGrid, Obstacles, Paint, TileContent, TileId, VillageSite, WorldPlan,
    WorldVillages, DEFAULT_BAND_RADII, MAX_TILES,
};

//! # worldpaint-core
//!
//! The engine of worldpaint: an implementation of *WorldBrush: Interactive Example-based Synthesis of Procedural
//! Virtual Worlds* (Emilien et al., SIGGRAPH 2015). An exemplar arrangement of instances (trees, rocks, grass on a
//! terrain) is analysed into a *color* — interaction histograms between categories (radial distribution functions,
//! eq. (2)), map-sampling histograms of external maps such as slope — and a Metropolis-Hastings birth-and-death
//! sampler (eq. (1)) paints new arrangements with the same statistics into any region, consistent with what
//! surrounds it (the region of influence).
//!
//! | module | part of the paper |
//! |---|---|
//! | [`geom`] | active regions, window-edge correction α (§3, §4.1); a region prepared once for many queries (indexed polygons) |
//! | [`search`] | the min-cost order of the best-first (Dijkstra, A*) searches |
//! | [`spatial`] | neighbour queries behind the product simplification (§6) |
//! | [`graph`] | roads and rivers as planar graphs of intersecting paths, segment queries (§4.2) |
//! | [`grid`] | one regular grid for every raster and bucket index, with its two size rules |
//! | [`limits`] | the work budget every entry point checks before allocating: instances, cells, bins, region size |
//! | `progress` | progress and cancelling of work done item by item on several threads |
//! | [`contour`] | islands and lakes: contours to dense points and back, signed distance (§6, thesis 6.2.1) |
//! | [`polygon_mesh`] | polygons as a filled mesh (constrained Delaunay triangulation) for display |
//! | [`terrain`] | the terrain and its external maps (§3) |
//! | [`distance`] | exact Euclidean distance transforms on grids |
//! | `scene_maps` | maps made in the scene on the terrain's grid: a value per mesh vertex, the distance to geometry (§3) |
//! | [`terrain_edit`] | terrain that adapts: constraint-based deformation by multigrid diffusion (thesis 4.4.2, 5.3.3) |
//! | [`sketch`] | terrain edited from silhouettes sketched over a first-person view (thesis ch. 5) |
//! | [`scene`] | categories, priority order, instances (§3) |
//! | [`palette`] | histograms, colors, palettes (§3, §4.1) |
//! | `analysis` ([`learn_color`]) | learning a color (§4.1); its radius, which follows a clustered example (`radius`), and the pair correlation of a map preference (`intensity`) |
//! | `compare` ([`compare()`], [`Fidelity`], [`self_synthesis`]) | fidelity metrics between two colors; a color learned back from what it painted |
//! | [`fidelity_plot`] | the fidelity picture: example and self-synthesis pcf and slope histograms |
//! | [`interpolate`] | distribution interpolation by optimal mass transport (§5.2) |
//! | [`synthesis`] | Metropolis-Hastings synthesis with a region of influence (§4.1, §4.3, §5.1, §6); adapting moved content (§5.4); island count and size matched after tracing (`islands`) |
//! | [`tools`] | the painting tools: paste, brush and eraser, move, seam-carving stretch, gradient, blur (§5) |
//! | [`village`] | villages on arbitrary terrain: growth, roads, parcels, houses (thesis ch. 3) |
//! | [`waterfall`] | waterfall scenes: controller network, hydraulic graph and flow, terrain-adapted subdivision, slope-flow types, integration mesh, terrain deformation, decoration maps (thesis ch. 4) |
//! | [`variety`] | model variety (Maréchal et al.): components, connecting regions, variant atlas, assembly with frames, self-intersection rejection, texture components |
//! | [`arrangement`] | element arrangement by example (Ijiri et al. 2008): reference connectivity, local growth from a seed, relaxation |
//! | [`exemplar`] | generating processes for demo scenes, tests and benchmarks |
//! | `place` ([`import_place`]) | real places: OpenStreetMap layers, elevation models and tree inventories in a local metric frame |

// `!(x > 0.0)` is used on purpose: it rejects NaN as well as non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::nonminimal_bool)]
// Every public item says what it is; `make lint` turns this into an error.
#![warn(missing_docs)]

mod analysis;
pub mod arrangement;
mod compare;
pub mod contour;
pub mod distance;
mod error;
pub mod exemplar;
pub mod fidelity_plot;
pub mod geom;
pub mod graph;
pub mod grid;
pub mod interpolate;
pub mod limits;
mod paint;
pub mod palette;
mod place;
pub mod polygon_mesh;
mod progress;
pub mod scene;
mod scene_maps;
pub mod search;
pub mod sketch;
pub mod spatial;
pub mod synthesis;
pub mod terrain;
pub mod terrain_edit;
pub mod tools;
pub mod variety;
pub mod village;
pub mod waterfall;
pub mod world;

pub use analysis::{learn_arrangement, learn_color, AnalysisOptions, HeldGraph, SLOPE_BIN_DEGREES};
pub use compare::{compare, learned_back, same_options, self_synthesis, Fidelity};
pub use error::{check, Error, FileKind, Result};
pub use geom::Region;
pub use interpolate::interpolate_colors;
pub use paint::{painted_fidelity, synthesize, synthesize_with_progress};
pub use palette::{Color, Palette};
pub use place::{
    import_place, read_elevation_model, read_map_layer, read_tree_inventory, AreaClass,
    BuildingType, ElevationModel, InventoryCoordinates, InventoryRow, InventoryTree,
    LocalProjection, LonLat, LonLatShape, MapFeature, MapLayer, MappedArea, MappedBuilding,
    MappedRoad, MappedWaterway, NamedPlace, Place, PlaceFrame, PlaceOptions, PlaceReport,
    PlaceSources, RoadClass, TerrainReport, TreeInventory, DEFAULT_MARGIN, MAX_EXTENT_DEGREES,
    MAX_HOLE_SHARE,
};
pub use scene::{Category, CategoryKind, Instance, Scene};
pub use synthesis::{SynthesisOptions, SynthesisResult};
pub use terrain::Heightfield;

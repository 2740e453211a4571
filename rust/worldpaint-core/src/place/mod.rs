//! # Real places
//!
//! A real place brought into the engine, so that colors and villages can be learned from it (issue 41, "Import a
//! real place"; the papers learn from example content, and this is where real content comes from): OpenStreetMap
//! layers, an elevation model and a tree inventory, in one local metric frame.
//!
//! | file | what it does |
//! |---|---|
//! | `layer` | GeoJSON FeatureCollections read into lon/lat features with their tags ([`read_map_layer`]) |
//! | `classify` | tags to kinds: [`BuildingType`], [`RoadClass`], [`AreaClass`] (the mappings are in their docs) |
//! | `footprint` | rings in metres: area, centroid, minimum-area bounding rectangle (size, orientation) |
//! | `elevation/` | ESRI ASCII grids, SRTM `.hgt`, GeoTIFF into one [`ElevationModel`]; holes filled when few |
//! | `inventory` | tree inventories (CSV) ([`read_tree_inventory`]) |
//! | `crs` | which CRS a file names; only WGS84 lon/lat can be placed |
//! | `frame` | lon/lat to metres: [`PlaceFrame`], a transverse Mercator centred on the place |
//! | `terrain` | the elevation model resampled onto a metric grid cropped to the place |
//! | `imported` | the [`Place`] and its parts, serialisable |
//! | `import` | [`import_place`]: all of the above in order |
//!
//! Readings chosen where the issue leaves room:
//! * **Projection.** `proj4rs` (a pure-Rust port of proj4js, MIT/Apache, kept by 3Liz) gives the transverse Mercator;
//!   pure Rust, so the engine's wheel builds on every platform without a C library (the `proj` crate needs
//!   libproj). The frame is `+proj=tmerc` on the WGS84 ellipsoid, centred on the origin, scale 1.
//! * **GeoJSON.** The `geojson` crate (georust) reads each feature; the collection around them is read with
//!   `serde_json`, since the real OpenStreetMap extracts write the collection's `bbox` as an object, which the crate
//!   refuses for the whole file.
//! * **One feature, one kind.** A feature is a building, a road, a waterway, an area or a place, in that precedence
//!   (see `classify`); a (Multi)LineString feature gives one road or waterway per line; a building or area keeps all
//!   its polygons' rings.
//! * **Terrain extent.** The box of every imported feature and tree, grown by the margin, clipped to where the
//!   elevation model can be interpolated; the whole model when there is nothing else. Its default cell is the
//!   model's finer spacing in metres at its centre (59.6 m for SRTM 3″ at 50° N).
//! * **Holes** (no data) are filled from the nearest valid sample when they are at most 5 % of the samples under the
//!   place, and refused above, naming the share.
//! * **Files** are refused past [`limits::MAX_PLACE_FILE_BYTES`](crate::limits::MAX_PLACE_FILE_BYTES), grids past
//!   the grid budget, before they are read or allocated.

mod classify;
mod crs;
mod elevation;
mod footprint;
mod frame;
mod import;
mod imported;
mod inventory;
mod layer;
mod terrain;

pub use classify::{AreaClass, BuildingType, RoadClass};
pub use elevation::{read_elevation_model, ElevationModel, MAX_HOLE_SHARE};
pub use footprint::min_area_rectangle;
pub use frame::{LocalProjection, PlaceFrame, MAX_EXTENT_DEGREES};
pub use import::{import_place, PlaceOptions, DEFAULT_MARGIN};
pub use imported::{
    InventoryTree, MappedArea, MappedBuilding, MappedRoad, MappedWaterway, NamedPlace, Place,
    PlaceReport, PlaceSources, TerrainReport,
};
pub use inventory::{read_tree_inventory, InventoryCoordinates, InventoryRow, TreeInventory};
pub use layer::{read_map_layer, LonLat, LonLatShape, MapFeature, MapLayer};

use crate::error::{Error, FileKind, Result};
use std::path::Path;

/// The bytes of a file of a place, refused past the size limit before it is read.
pub(crate) fn read_file(path: &Path, kind: FileKind) -> Result<Vec<u8>> {
    let source = path.display();
    let meta = std::fs::metadata(path)
        .map_err(|e| Error::parse(kind, format!("{source}: cannot read it ({e})")))?;
    crate::limits::check(
        &format!("the {kind} {source}"),
        meta.len() as f64,
        crate::limits::MAX_PLACE_FILE_BYTES,
        "bytes",
    )?;
    std::fs::read(path).map_err(|e| Error::parse(kind, format!("{source}: cannot read it ({e})")))
}

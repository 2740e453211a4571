//! A place as imported: everything in the metres of its frame, with the files it came from, serialisable so that a
//! later import can be made in the same frame (give it the same origin).

use super::classify::{AreaClass, BuildingType, RoadClass};
use super::frame::PlaceFrame;
use crate::terrain::Heightfield;
use glam::DVec2;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A building of the map.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MappedBuilding {
    /// Its type, from its tags.
    pub kind: BuildingType,
    /// Its `name` tag.
    pub name: Option<String>,
    /// All its tags.
    pub tags: BTreeMap<String, String>,
    /// Its footprint: outer rings counter-clockwise, holes clockwise, no closing repetition (m).
    pub footprint: Vec<Vec<DVec2>>,
    /// Its area centroid (m).
    pub centroid: DVec2,
    /// Its area (m²).
    pub area: f64,
    /// The long and short sides of its minimum-area bounding rectangle (m).
    pub size: [f64; 2],
    /// The angle of that rectangle's long side from +X (east), counter-clockwise, in [0, π) (radians).
    pub orientation: f64,
}

/// A road or path of the map: one line of a `highway` feature.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MappedRoad {
    /// Its class.
    pub class: RoadClass,
    /// Its `highway` tag.
    pub highway: String,
    /// Its `name` tag.
    pub name: Option<String>,
    /// Its points (m).
    pub points: Vec<DVec2>,
}

/// A waterway of the map (river, stream, canal, ditch...): one line of a `waterway` feature.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MappedWaterway {
    /// Its `waterway` tag.
    pub kind: String,
    /// Its `name` tag.
    pub name: Option<String>,
    /// Its points (m).
    pub points: Vec<DVec2>,
}

/// An area of the map: water, land use or land cover.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MappedArea {
    /// Its class.
    pub class: AreaClass,
    /// The tag it was classed by, as `key=value` (`landuse=forest`, `natural=water`).
    pub tag: String,
    /// Its `name` tag.
    pub name: Option<String>,
    /// Its rings: outer rings counter-clockwise, holes clockwise, no closing repetition (m).
    pub rings: Vec<Vec<DVec2>>,
}

/// A named place of the map (`place=village`, `hamlet`, ...).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NamedPlace {
    /// Its `place` tag.
    pub kind: String,
    /// Its `name` tag.
    pub name: Option<String>,
    /// Where it is (m).
    pub position: DVec2,
}

/// A tree of the inventory.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InventoryTree {
    /// Where it stands (m).
    pub position: DVec2,
    /// Its species, as the inventory writes it.
    pub species: String,
    /// Its size in the inventory's unit (trunk diameter or height), when given.
    pub size: Option<f64>,
}

/// The files a place was imported from, as given.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PlaceSources {
    /// The map layers (GeoJSON).
    pub layers: Vec<String>,
    /// The elevation model.
    pub elevation: Option<String>,
    /// The tree inventory.
    pub inventory: Option<String>,
}

/// How the elevation model became the terrain.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TerrainReport {
    /// The model's samples (columns, rows).
    pub source_size: [usize; 2],
    /// The model's sample spacing east–west and north–south at its centre (m).
    pub source_spacing: [f64; 2],
    /// Samples of the whole model that had no data and were filled.
    pub holes_filled: usize,
    /// Share of the samples under the place that had no data.
    pub hole_share: f64,
}

/// What the import read and what it left out.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PlaceReport {
    /// Features read from the map layers.
    pub features: usize,
    /// Features left out as unreadable (no geometry, one it cannot read, too short).
    pub unreadable: usize,
    /// Features read but of no kind the import keeps (a parking lot, a lone tree of the map).
    pub left_out: usize,
    /// The terrain, when there is an elevation model.
    pub terrain: Option<TerrainReport>,
    /// Inventory rows left out as not alive.
    pub trees_not_alive: usize,
    /// Inventory rows left out without a readable position.
    pub trees_unreadable: usize,
}

/// A real place in the metres of its frame.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Place {
    /// Where its metres are.
    pub frame: PlaceFrame,
    /// The files it came from.
    pub sources: PlaceSources,
    /// Its terrain, when an elevation model was given.
    #[serde(with = "terrain_record")]
    pub terrain: Option<Heightfield>,
    /// Buildings.
    pub buildings: Vec<MappedBuilding>,
    /// Roads and paths.
    pub roads: Vec<MappedRoad>,
    /// Rivers, streams, canals and ditches.
    pub waterways: Vec<MappedWaterway>,
    /// Water, land-use and land-cover areas.
    pub areas: Vec<MappedArea>,
    /// Named places.
    pub places: Vec<NamedPlace>,
    /// Trees of the inventory.
    pub trees: Vec<InventoryTree>,
    /// What was read and left out.
    pub report: PlaceReport,
}

impl Place {
    /// The place as JSON.
    pub fn to_json(&self) -> crate::Result<String> {
        serde_json::to_string(self).map_err(|e| crate::Error::invalid("the place", e.to_string()))
    }

    /// A place from its JSON.
    pub fn from_json(text: &str) -> crate::Result<Place> {
        serde_json::from_str(text)
            .map_err(|e| crate::Error::parse(crate::FileKind::Place, e.to_string()))
    }
}

/// The terrain of a place as its grid: origin, cell, node counts and heights (its maps are made again on reading).
mod terrain_record {
    use crate::terrain::Heightfield;
    use glam::DVec2;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    struct Grid {
        origin: DVec2,
        cell: f64,
        nx: usize,
        ny: usize,
        heights: Vec<f32>,
    }

    pub(super) fn serialize<S: Serializer>(
        terrain: &Option<Heightfield>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        terrain
            .as_ref()
            .map(|t| Grid {
                origin: t.origin,
                cell: t.cell,
                nx: t.nx,
                ny: t.ny,
                heights: t.heights.clone(),
            })
            .serialize(s)
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<Heightfield>, D::Error> {
        match Option::<Grid>::deserialize(d)? {
            Some(g) => Heightfield::new(g.origin, g.cell, g.nx, g.ny, g.heights)
                .map(Some)
                .map_err(serde::de::Error::custom),
            None => Ok(None),
        }
    }
}

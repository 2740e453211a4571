//! A map layer as read: the features of a GeoJSON FeatureCollection, each with its tags (the feature's properties,
//! OpenStreetMap's `key=value` pairs) and its geometry in lon/lat degrees, before anything is projected or classified.
//!
//! Features are read one by one with the `geojson` crate; the collection around them is read with `serde_json`,
//! since OpenStreetMap extract tools write a collection `bbox` as an object (`{"minlat": ...}`) where RFC 7946 wants
//! an array, and the crate refuses the whole file for it. A feature the crate cannot read, or whose geometry is
//! missing, of a kind with no place in a map (MultiPoint, GeometryCollection) or too short (a line of one point, an
//! outer ring of fewer than three; a hole that short is dropped), is counted as unreadable and left out; a coordinate
//! outside the ranges of degrees refuses the whole layer as being in a CRS it cannot place.

use super::crs::{self, Crs};
use super::read_file;
use crate::error::{Error, FileKind, Result};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// A lon/lat pair (degrees, WGS84).
pub type LonLat = [f64; 2];

/// The geometry of a map feature in lon/lat degrees, as in the file (rings keep their closing point).
#[derive(Clone, Debug, PartialEq)]
pub enum LonLatShape {
    /// A Point.
    Point(LonLat),
    /// A LineString or MultiLineString: its lines, each of two points or more.
    Lines(Vec<Vec<LonLat>>),
    /// A Polygon or MultiPolygon: its polygons, each its outer ring then its holes.
    Polygons(Vec<Vec<Vec<LonLat>>>),
}

impl LonLatShape {
    /// Every point of the shape.
    pub fn points(&self) -> Box<dyn Iterator<Item = &LonLat> + '_> {
        match self {
            LonLatShape::Point(p) => Box::new(std::iter::once(p)),
            LonLatShape::Lines(lines) => Box::new(lines.iter().flatten()),
            LonLatShape::Polygons(polygons) => Box::new(polygons.iter().flatten().flatten()),
        }
    }
}

/// One feature of a map layer.
#[derive(Clone, Debug, PartialEq)]
pub struct MapFeature {
    /// The feature's properties as text (numbers and booleans written out; nulls, lists and objects left out).
    pub tags: BTreeMap<String, String>,
    /// Its geometry.
    pub shape: LonLatShape,
}

impl MapFeature {
    /// The value of tag `key`.
    pub fn tag(&self, key: &str) -> Option<&str> {
        self.tags.get(key).map(String::as_str)
    }
}

/// The features of one GeoJSON file.
#[derive(Clone, Debug)]
pub struct MapLayer {
    /// The file, as given.
    pub source: String,
    /// Its readable features, in file order.
    pub features: Vec<MapFeature>,
    /// Features left out as unreadable.
    pub unreadable: usize,
}

impl MapLayer {
    /// The (west, south) and (east, north) corners of the layer's points, `None` for a layer with none.
    pub fn lon_lat_box(&self) -> Option<(LonLat, LonLat)> {
        lon_lat_box(self.features.iter().flat_map(|f| f.shape.points()))
    }
}

/// The box of lon/lat points.
pub(crate) fn lon_lat_box<'a>(
    points: impl Iterator<Item = &'a LonLat>,
) -> Option<(LonLat, LonLat)> {
    let mut out: Option<(LonLat, LonLat)> = None;
    for p in points {
        let (lo, hi) = out.get_or_insert((*p, *p));
        *lo = [lo[0].min(p[0]), lo[1].min(p[1])];
        *hi = [hi[0].max(p[0]), hi[1].max(p[1])];
    }
    out
}

fn parse_error(source: &str, reason: impl std::fmt::Display) -> Error {
    Error::parse(FileKind::MapLayer, format!("{source}: {reason}"))
}

/// Reads a GeoJSON FeatureCollection of WGS84 lon/lat features. Refused: a file that is not JSON, not GeoJSON, not a
/// FeatureCollection, in a CRS other than WGS84 lon/lat, larger than the limit, or with no readable feature.
pub fn read_map_layer(path: &Path) -> Result<MapLayer> {
    let source = path.display().to_string();
    let bytes = read_file(path, FileKind::MapLayer)?;
    let value: Value = serde_json::from_slice(&bytes)
        .map_err(|e| parse_error(&source, format!("not GeoJSON: not JSON ({e})")))?;
    drop(bytes);
    map_layer_from_json(value, &source)
}

/// The layer of a parsed GeoJSON document (see [`read_map_layer`]).
pub(crate) fn map_layer_from_json(mut value: Value, source: &str) -> Result<MapLayer> {
    let Some(object) = value.as_object_mut() else {
        return Err(parse_error(
            source,
            "not GeoJSON: the document is not an object",
        ));
    };
    let not_a_collection = match object.get("type").and_then(Value::as_str) {
        Some("FeatureCollection") => None,
        Some(other) => Some(format!(
            "a GeoJSON {other}, not a FeatureCollection: a layer is a collection of features"
        )),
        None => Some("not GeoJSON: it has no \"type\" member".to_string()),
    };
    if let Some(reason) = not_a_collection {
        return Err(parse_error(source, reason));
    }
    if let Some(member) = object.get("crs") {
        if let Crs::Other(name) = crs::of_geojson_member(member) {
            return Err(crs::cannot_place(FileKind::MapLayer, source, &name));
        }
    }
    let features = match object.remove("features") {
        Some(Value::Array(features)) => features,
        _ => {
            return Err(parse_error(
                source,
                "a FeatureCollection without a \"features\" list",
            ))
        }
    };
    if features.is_empty() {
        return Err(parse_error(
            source,
            "an empty layer: the collection holds no feature",
        ));
    }
    let total = features.len();
    let mut out = Vec::with_capacity(total);
    for value in features {
        let Ok(feature) = serde_json::from_value::<geojson::Feature>(value) else {
            continue;
        };
        let Some(shape) = feature.geometry.as_ref().and_then(|g| shape(&g.value)) else {
            continue;
        };
        if let Some(p) = shape.points().find(|p| !crs::is_lon_lat(**p)) {
            return Err(crs::not_lon_lat(FileKind::MapLayer, source, *p));
        }
        out.push(MapFeature {
            tags: tags(feature.properties.as_ref()),
            shape,
        });
    }
    if out.is_empty() {
        return Err(parse_error(
            source,
            format!("an empty layer: none of its {total} features has a geometry it can read"),
        ));
    }
    Ok(MapLayer {
        source: source.to_string(),
        unreadable: total - out.len(),
        features: out,
    })
}

fn tags(properties: Option<&geojson::JsonObject>) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for (key, value) in properties.into_iter().flatten() {
        let text = match value {
            Value::String(s) => s.clone(),
            Value::Number(n) => n.to_string(),
            Value::Bool(b) => b.to_string(),
            _ => continue,
        };
        out.insert(key.clone(), text);
    }
    out
}

fn position(p: &geojson::Position) -> Option<LonLat> {
    match p.as_slice() {
        [lon, lat, ..] => Some([*lon, *lat]),
        _ => None,
    }
}

/// A line of at least `min` positions.
fn line(points: &[geojson::Position], min: usize) -> Option<Vec<LonLat>> {
    let line: Option<Vec<LonLat>> = points.iter().map(position).collect();
    line.filter(|l| l.len() >= min)
}

/// A polygon: its outer ring then its holes, each of at least three positions; a hole too short is left out, an
/// outer ring too short leaves out the polygon.
fn polygon(rings: &[Vec<geojson::Position>]) -> Option<Vec<Vec<LonLat>>> {
    let mut out = vec![line(rings.first()?, 3)?];
    out.extend(rings[1..].iter().filter_map(|r| line(r, 3)));
    Some(out)
}

fn shape(value: &geojson::GeometryValue) -> Option<LonLatShape> {
    use geojson::GeometryValue as G;
    match value {
        G::Point { coordinates } => position(coordinates).map(LonLatShape::Point),
        G::LineString { coordinates } => line(coordinates, 2).map(|l| LonLatShape::Lines(vec![l])),
        G::MultiLineString { coordinates } => {
            let lines: Option<Vec<Vec<LonLat>>> = coordinates.iter().map(|l| line(l, 2)).collect();
            lines.filter(|l| !l.is_empty()).map(LonLatShape::Lines)
        }
        G::Polygon { coordinates } => polygon(coordinates).map(|p| LonLatShape::Polygons(vec![p])),
        G::MultiPolygon { coordinates } => {
            let polygons: Option<Vec<Vec<Vec<LonLat>>>> =
                coordinates.iter().map(|p| polygon(p)).collect();
            polygons
                .filter(|p| !p.is_empty())
                .map(LonLatShape::Polygons)
        }
        _ => None,
    }
}

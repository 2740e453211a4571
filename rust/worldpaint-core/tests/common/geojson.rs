//! GeoJSON as the real-data tests read it (OpenStreetMap layers, the cadastre): features, lon/lat pairs, and the
//! lines or outer rings of a geometry, with nothing taken on trust from the file.

use serde_json::Value;
use std::path::Path;

/// The features of a FeatureCollection file.
pub fn read_features(path: &Path) -> Result<Vec<Value>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let mut value: Value =
        serde_json::from_str(&text).map_err(|e| format!("{} is not JSON: {e}", path.display()))?;
    match value.get_mut("features").map(Value::take) {
        Some(Value::Array(features)) => Ok(features),
        _ => Err(format!("{} has no feature list", path.display())),
    }
}

/// `highway` values of ways for people on foot, on bicycles or on horses: not part of a village's road network.
pub const FOOT_AND_BRIDLE_WAYS: [&str; 6] = [
    "footway",
    "path",
    "cycleway",
    "steps",
    "pedestrian",
    "bridleway",
];

/// The string value of a feature's property `key`.
pub fn tag<'a>(feature: &'a Value, key: &str) -> Option<&'a str> {
    feature.get("properties")?.get(key)?.as_str()
}

fn lon_lat(v: &Value) -> Option<[f64; 2]> {
    let a = v.as_array()?;
    let (lon, lat) = (a.first()?.as_f64()?, a.get(1)?.as_f64()?);
    (lon.abs() <= 180.0 && lat.abs() <= 90.0).then_some([lon, lat])
}

fn line(v: &Value) -> Option<Vec<[f64; 2]>> {
    let points: Option<Vec<[f64; 2]>> = v.as_array()?.iter().map(lon_lat).collect();
    points.filter(|p| p.len() >= 2)
}

/// The lines of a (Multi)LineString, the outer rings of a (Multi)Polygon, or a Point as a one-point line.
pub fn geometry(feature: &Value) -> Option<Vec<Vec<[f64; 2]>>> {
    let g = feature.get("geometry")?;
    let coordinates = g.get("coordinates")?;
    let parts: Option<Vec<Vec<[f64; 2]>>> = match g.get("type")?.as_str()? {
        "Point" => Some(vec![vec![lon_lat(coordinates)?]]),
        "LineString" => Some(vec![line(coordinates)?]),
        "MultiLineString" => coordinates.as_array()?.iter().map(line).collect(),
        "Polygon" => Some(vec![line(coordinates.as_array()?.first()?)?]),
        "MultiPolygon" => coordinates
            .as_array()?
            .iter()
            .map(|p| line(p.as_array()?.first()?))
            .collect(),
        _ => None,
    };
    parts.filter(|p| !p.is_empty())
}

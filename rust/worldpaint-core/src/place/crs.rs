//! Which coordinate reference system a file says it is in, read from what the formats carry: a GeoJSON `crs`
//! member, the WKT of a `.prj` beside a grid or an inventory, a GeoTIFF's GeoKeys. Only WGS84 lon/lat can be placed
//! (and, for an inventory, local metres); any other CRS is named in the refusal. Where a file names none, its numbers
//! must look like lon/lat degrees.

use crate::error::{Error, FileKind, Result};

/// The coordinate system of a file.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Crs {
    /// WGS84 longitude and latitude in degrees.
    LonLat,
    /// Metres in a local engineering frame (a `LOCAL_CS`).
    LocalMetres,
    /// Anything else, by the name the file gives it.
    Other(String),
}

/// The CRS a GeoJSON `crs` member names (the 2008 GeoJSON form `{"type": "name", "properties": {"name": ...}}`);
/// RFC 7946 dropped the member, so its absence means WGS84 lon/lat.
pub(crate) fn of_geojson_member(member: &serde_json::Value) -> Crs {
    if member.is_null() {
        return Crs::LonLat;
    }
    let name = member
        .get("properties")
        .and_then(|p| p.get("name").or_else(|| p.get("href")))
        .and_then(|n| n.as_str());
    match name {
        Some(name) if names_wgs84_lon_lat(name) => Crs::LonLat,
        Some(name) => Crs::Other(name.to_string()),
        None => Crs::Other(member.to_string()),
    }
}

/// Whether a CRS name (URN, URL or `EPSG:` code) is WGS84 lon/lat: OGC's CRS84 or EPSG 4326.
fn names_wgs84_lon_lat(name: &str) -> bool {
    let n = name.trim().to_ascii_lowercase();
    n.ends_with("crs84") || (n.contains("epsg") && (n.ends_with(":4326") || n.ends_with("/4326")))
}

/// The CRS a `.prj` (ESRI or OGC WKT) names.
pub(crate) fn of_wkt(text: &str) -> Crs {
    let upper = text.trim_start().to_ascii_uppercase();
    let keyword: String = upper
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
        .collect();
    let name = text
        .split('"')
        .nth(1)
        .unwrap_or(keyword.as_str())
        .to_string();
    match keyword.as_str() {
        "LOCAL_CS" | "ENGCRS" | "ENGINEERINGCRS" => Crs::LocalMetres,
        "GEOGCS" | "GEOGCRS" | "GEOGRAPHICCRS" | "GEODCRS" => {
            let wgs84 = ["WGS_1984", "WGS 84", "WGS84", "WGS 1984"]
                .iter()
                .any(|w| upper.contains(w));
            if wgs84 {
                Crs::LonLat
            } else {
                Crs::Other(name)
            }
        }
        _ => Crs::Other(if name.is_empty() {
            text.chars().take(60).collect()
        } else {
            name
        }),
    }
}

/// The CRS of a `.prj` beside `path`, if there is one.
pub(crate) fn of_prj_beside(path: &std::path::Path, kind: FileKind) -> Result<Option<Crs>> {
    for ext in ["prj", "PRJ"] {
        let prj = path.with_extension(ext);
        if prj.is_file() {
            let text = std::fs::read_to_string(&prj).map_err(|e| {
                Error::parse(
                    kind,
                    format!("{}: cannot read its .prj: {e}", prj.display()),
                )
            })?;
            return Ok(Some(of_wkt(&text)));
        }
    }
    Ok(None)
}

/// The refusal of a file in a CRS it cannot place.
pub(crate) fn cannot_place(kind: FileKind, source: &str, crs: &str) -> Error {
    Error::parse(
        kind,
        format!(
            "{source}: its coordinates are in a CRS it cannot place ({crs}); reproject it to WGS84 lon/lat \
             (EPSG:4326)"
        ),
    )
}

/// The refusal of a file whose coordinates name no CRS and are not lon/lat degrees.
pub(crate) fn not_lon_lat(kind: FileKind, source: &str, example: [f64; 2]) -> Error {
    Error::parse(
        kind,
        format!(
            "{source}: its coordinates ({}, {}) are not lon/lat degrees and the file names no CRS: a CRS it \
             cannot place; reproject it to WGS84 lon/lat (EPSG:4326)",
            example[0], example[1]
        ),
    )
}

/// Whether a lon/lat pair lies in the ranges of degrees.
pub(crate) fn is_lon_lat(p: [f64; 2]) -> bool {
    p[0].abs() <= 180.0 && p[1].abs() <= 90.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_of_wgs84_and_others() {
        let member = |name: &str| serde_json::json!({"type": "name", "properties": {"name": name}});
        assert_eq!(
            of_geojson_member(&member("urn:ogc:def:crs:OGC:1.3:CRS84")),
            Crs::LonLat
        );
        assert_eq!(of_geojson_member(&member("EPSG:4326")), Crs::LonLat);
        assert_eq!(
            of_geojson_member(&member("urn:ogc:def:crs:EPSG::25832")),
            Crs::Other("urn:ogc:def:crs:EPSG::25832".into())
        );
        assert_eq!(
            of_wkt(
                r#"GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",SPHEROID["WGS_1984",6378137,298.257223563]]]"#
            ),
            Crs::LonLat
        );
        assert_eq!(
            of_wkt(r#"PROJCS["ETRS_1989_UTM_Zone_32N",GEOGCS["GCS_ETRS_1989"]]"#),
            Crs::Other("ETRS_1989_UTM_Zone_32N".into())
        );
        assert_eq!(of_wkt(r#"LOCAL_CS["plot"]"#), Crs::LocalMetres);
    }
}

//! The local frame of a place: metres east (X) and north (Y) of an origin given in lon/lat, by a transverse Mercator
//! projection centred on that origin (`+proj=tmerc`, scale 1 on the central meridian, WGS84 ellipsoid). Its scale
//! error grows as the square of the distance from the central meridian: 3 parts in a million 15 km away, 0.05 % at
//! 200 km. A place wider than [`MAX_EXTENT_DEGREES`] is refused rather than laid flat with a visible error.
//!
//! A place made only of local data (a tree inventory in metres) has a local frame: no origin, no projection.

use crate::error::{Error, Result};
use glam::DVec2;
use proj4rs::proj::Proj;
use serde::{Deserialize, Serialize};

/// Largest span of a place in longitude or latitude (degrees) that one local frame holds.
pub const MAX_EXTENT_DEGREES: f64 = 5.0;

/// Where the local metres of a place are: the lon/lat (degrees) of the local (0, 0) and the projection from lon/lat,
/// or neither for a place of local data only.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlaceFrame {
    /// Longitude and latitude (degrees, WGS84) of the local origin.
    pub origin: Option<[f64; 2]>,
    /// The projection from WGS84 lon/lat to the local metres, as a proj string.
    pub projection: Option<String>,
}

impl PlaceFrame {
    /// The frame centred on `origin` (lon, lat in degrees).
    pub fn centred_on(origin: [f64; 2]) -> Result<PlaceFrame> {
        let [lon, lat] = origin;
        if !(lon.abs() <= 180.0) || !(lat.abs() < 89.0) {
            return Err(Error::invalid(
                "the place's origin",
                format!("({lon}, {lat}) is not a longitude and a latitude in degrees (within ±180 and ±89)"),
            ));
        }
        Ok(PlaceFrame {
            origin: Some(origin),
            projection: Some(format!(
                "+proj=tmerc +lat_0={lat} +lon_0={lon} +k=1 +x_0=0 +y_0=0 +ellps=WGS84 +datum=WGS84 +units=m +no_defs"
            )),
        })
    }

    /// A frame of local metres only (no lon/lat origin).
    pub fn local() -> PlaceFrame {
        PlaceFrame {
            origin: None,
            projection: None,
        }
    }

    /// The projection of this frame, `None` for a local one.
    pub fn projection(&self) -> Result<Option<LocalProjection>> {
        match &self.projection {
            Some(text) => LocalProjection::new(text).map(Some),
            None => Ok(None),
        }
    }
}

/// Lon/lat (degrees) to a frame's metres and back.
pub struct LocalProjection {
    lon_lat: Proj,
    local: Proj,
}

impl LocalProjection {
    fn new(projection: &str) -> Result<LocalProjection> {
        let bad = |e: proj4rs::errors::Error| {
            Error::invalid("the place's projection", format!("'{projection}': {e}"))
        };
        Ok(LocalProjection {
            lon_lat: Proj::from_proj_string("+proj=longlat +ellps=WGS84 +datum=WGS84 +no_defs")
                .map_err(bad)?,
            local: Proj::from_proj_string(projection).map_err(bad)?,
        })
    }

    /// Metres east and north of the origin of lon/lat points (degrees).
    pub fn to_local(&self, lon_lat: &[[f64; 2]]) -> Result<Vec<DVec2>> {
        let mut points: Vec<(f64, f64)> = lon_lat
            .iter()
            .map(|p| (p[0].to_radians(), p[1].to_radians()))
            .collect();
        proj4rs::transform::transform(&self.lon_lat, &self.local, points.as_mut_slice())
            .map_err(|e| Error::invalid("a lon/lat point", format!("cannot be projected: {e}")))?;
        finite_points(points.into_iter().map(|(x, y)| DVec2::new(x, y)).collect())
    }

    /// One lon/lat point (degrees) in metres.
    pub fn point_to_local(&self, lon_lat: [f64; 2]) -> Result<DVec2> {
        self.to_local(&[lon_lat]).map(|p| p[0])
    }

    /// Lon/lat (degrees) of local points (m).
    pub fn to_lon_lat(&self, local: &[DVec2]) -> Result<Vec<[f64; 2]>> {
        let mut points: Vec<(f64, f64)> = local.iter().map(|p| (p.x, p.y)).collect();
        proj4rs::transform::transform(&self.local, &self.lon_lat, points.as_mut_slice())
            .map_err(|e| Error::invalid("a local point", format!("has no lon/lat: {e}")))?;
        let out: Vec<[f64; 2]> = points
            .into_iter()
            .map(|(lon, lat)| [lon.to_degrees(), lat.to_degrees()])
            .collect();
        match out
            .iter()
            .position(|p| !(p[0].is_finite() && p[1].is_finite()))
        {
            Some(k) => Err(Error::invalid(
                format!("local point {k}"),
                "has no lon/lat in this frame",
            )),
            None => Ok(out),
        }
    }
}

fn finite_points(points: Vec<DVec2>) -> Result<Vec<DVec2>> {
    match points.iter().position(|p| !p.is_finite()) {
        Some(k) => Err(Error::invalid(
            format!("lon/lat point {k}"),
            "lies too far from the place's origin to be projected",
        )),
        None => Ok(points),
    }
}

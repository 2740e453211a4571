//! The single-band GeoTIFF: heights of any integer or float sample type, placed by the GeoTIFF tags
//! `ModelPixelScale` (cell size) and `ModelTiepoint` (a raster point and its lon/lat), area- or point-registered as
//! the `GTRasterTypeGeoKey` says (area by default), with GDAL's `GDAL_NODATA` tag for holes. The GeoKeys must name
//! WGS84 lon/lat (`GTModelTypeGeoKey` geographic and `GeographicTypeGeoKey` 4326, or a user-defined geographic CRS
//! on the WGS84 datum); a file with no GeoKeys must read as lon/lat. A rotated or sheared grid
//! (`ModelTransformation`) is refused.

use super::{
    check_grid_size, check_reads_as_lon_lat, not_finite_height, ElevationModel, SRTM_VOID,
};
use crate::error::{Error, FileKind, Result};
use crate::place::crs;
use crate::place::read_file;
use std::path::Path;
use tiff::decoder::{Decoder, DecodingResult, Limits};
use tiff::tags::Tag;
use tiff::ColorType;

/// GeoKey ids (GeoTIFF 1.1, section 7).
const GT_MODEL_TYPE: u16 = 1024;
const GT_RASTER_TYPE: u16 = 1025;
const GEOGRAPHIC_TYPE: u16 = 2048;
const GEOG_GEODETIC_DATUM: u16 = 2050;
const PROJECTED_CS_TYPE: u16 = 3072;
/// `GTModelTypeGeoKey` of a geographic (lon/lat) model; `GTRasterTypeGeoKey` of a point-registered raster.
const MODEL_GEOGRAPHIC: u16 = 2;
const RASTER_PIXEL_IS_POINT: u16 = 2;
/// EPSG codes of WGS84 lon/lat and of its datum, and GeoTIFF's "user-defined".
const EPSG_WGS84: u16 = 4326;
const EPSG_WGS84_DATUM: u16 = 6326;
const USER_DEFINED: u16 = 32767;

/// The short-valued GeoKeys of a GeoKeyDirectory: (id, value) pairs.
fn geo_keys(directory: &[u16]) -> Vec<(u16, u16)> {
    let count = directory.get(3).copied().unwrap_or(0) as usize;
    directory
        .get(4..)
        .unwrap_or(&[])
        .chunks_exact(4)
        .take(count)
        .filter(|k| k[1] == 0) // a value held in the key itself, not in another tag
        .map(|k| (k[0], k[3]))
        .collect()
}

/// Whether the GeoKeys name WGS84 lon/lat; the refusal names what they say otherwise.
fn check_crs(keys: &[(u16, u16)], source: &str) -> Result<()> {
    let key = |id: u16| keys.iter().find(|k| k.0 == id).map(|k| k.1);
    let refuse = |name: String| Err(crs::cannot_place(FileKind::ElevationModel, source, &name));
    match (key(GT_MODEL_TYPE), key(PROJECTED_CS_TYPE)) {
        (Some(MODEL_GEOGRAPHIC), _) | (None, None) => {}
        (_, Some(code)) if code != USER_DEFINED => {
            return refuse(format!("EPSG:{code}, a projected CRS"))
        }
        (Some(1), _) => return refuse("a projected CRS".into()),
        (Some(t), _) => return refuse(format!("GeoTIFF model type {t}")),
        (None, Some(_)) => return refuse("a user-defined projected CRS".into()),
    }
    match (key(GEOGRAPHIC_TYPE), key(GEOG_GEODETIC_DATUM)) {
        (Some(EPSG_WGS84), _) => Ok(()),
        (None | Some(USER_DEFINED), None | Some(EPSG_WGS84_DATUM)) => Ok(()),
        (Some(USER_DEFINED), Some(datum)) => {
            refuse(format!("a geographic CRS on datum EPSG:{datum}"))
        }
        (Some(code), _) => refuse(format!("EPSG:{code}")),
        (None, Some(datum)) => refuse(format!("a geographic CRS on datum EPSG:{datum}")),
    }
}

fn values(image: DecodingResult) -> Vec<f64> {
    match image {
        DecodingResult::U8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U64(v) => v.into_iter().map(|x| x as f64).collect(),
        DecodingResult::F16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F64(v) => v,
        DecodingResult::I8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I64(v) => v.into_iter().map(|x| x as f64).collect(),
    }
}

pub(super) fn read(path: &Path, source: &str) -> Result<ElevationModel> {
    let bad =
        |reason: String| Error::parse(FileKind::ElevationModel, format!("{source}: {reason}"));
    let tiff_error = |e: tiff::TiffError| bad(format!("not a GeoTIFF it reads ({e})"));
    let bytes = read_file(path, FileKind::ElevationModel)?;
    let mut decoder = Decoder::new(std::io::Cursor::new(bytes))
        .map_err(tiff_error)?
        .with_limits(Limits::unlimited());
    let (ncols, nrows) = decoder.dimensions().map_err(tiff_error)?;
    let (ncols, nrows) = (ncols as usize, nrows as usize);
    check_grid_size(source, ncols, nrows)?;
    match decoder.colortype().map_err(tiff_error)? {
        ColorType::Gray(_) => {}
        other => {
            return Err(bad(format!(
                "an image of {} bands: an elevation model has one",
                other.num_samples()
            )))
        }
    }
    let (lower_left, cell, keys) = georeference(&mut decoder, source, nrows)?;
    match &keys {
        Some(keys) => check_crs(keys, source)?,
        None => check_reads_as_lon_lat(source, lower_left, cell, ncols, nrows)?,
    }
    let nodata = match decoder.find_tag(Tag::GdalNodata).map_err(tiff_error)? {
        Some(value) => {
            let text = value.into_string().map_err(tiff_error)?;
            let text = text.trim_matches(|c: char| c.is_whitespace() || c == '\0');
            Some(
                text.parse::<f64>()
                    .map_err(|_| bad(format!("its GDAL_NODATA '{text}' is not a number")))?,
            )
        }
        None => None,
    };
    let heights = values(decoder.read_image().map_err(tiff_error)?);
    let model = ElevationModel::new(source, (ncols, nrows), lower_left, cell, heights);
    holes_marked(model, nodata)
}

/// The model with its holes (the SRTM void, NaN or the GDAL_NODATA value) as NaN; any other non-finite height is
/// refused.
fn holes_marked(mut model: ElevationModel, nodata: Option<f64>) -> Result<ElevationModel> {
    for (k, h) in model.heights.iter_mut().enumerate() {
        let hole = *h == SRTM_VOID || h.is_nan() || nodata.is_some_and(|n| *h == n);
        if hole {
            *h = f64::NAN;
        } else if !h.is_finite() {
            return Err(not_finite_height(&model.source, *h, k, model.ncols));
        }
    }
    Ok(model)
}

/// Where the raster lies: its lower-left corner and cell size from the ModelPixelScale and ModelTiepoint tags (the
/// tiepoint's raster point is the first pixel's corner when area-registered, its centre when point-registered), and
/// the GeoKeys when there are any.
#[allow(clippy::type_complexity)]
fn georeference<R: std::io::Read + std::io::Seek>(
    decoder: &mut Decoder<R>,
    source: &str,
    nrows: usize,
) -> Result<([f64; 2], [f64; 2], Option<Vec<(u16, u16)>>)> {
    let bad =
        |reason: String| Error::parse(FileKind::ElevationModel, format!("{source}: {reason}"));
    let tiff_error = |e: tiff::TiffError| bad(format!("not a GeoTIFF it reads ({e})"));
    let mut find_f64s = |tag: Tag| -> Result<Option<Vec<f64>>> {
        match decoder.find_tag(tag).map_err(tiff_error)? {
            Some(value) => value.into_f64_vec().map(Some).map_err(tiff_error),
            None => Ok(None),
        }
    };
    let scale = find_f64s(Tag::ModelPixelScaleTag)?;
    let tiepoint = find_f64s(Tag::ModelTiepointTag)?;
    let (scale, tiepoint) = match (scale, tiepoint) {
        (Some(s), Some(t)) if s.len() >= 2 && t.len() >= 6 => (s, t),
        _ => {
            let transformed = decoder
                .find_tag(Tag::ModelTransformationTag)
                .map_err(tiff_error)?
                .is_some();
            return Err(bad(if transformed {
                "its grid is placed by a ModelTransformation (rotated or sheared), which it cannot place".into()
            } else {
                "a TIFF without the GeoTIFF tags ModelPixelScale and ModelTiepoint: nothing says where it lies"
                    .into()
            }));
        }
    };
    let keys = match decoder
        .find_tag(Tag::GeoKeyDirectoryTag)
        .map_err(tiff_error)?
    {
        Some(value) => Some(geo_keys(&value.into_u16_vec().map_err(tiff_error)?)),
        None => None,
    };
    let cell = [scale[0], scale[1]];
    let point_registered = keys
        .as_ref()
        .and_then(|k| k.iter().find(|k| k.0 == GT_RASTER_TYPE))
        .is_some_and(|k| k.1 == RASTER_PIXEL_IS_POINT);
    let shift = if point_registered { 0.5 } else { 0.0 };
    let west = tiepoint[3] - (tiepoint[0] + shift) * cell[0];
    let north = tiepoint[4] + (tiepoint[1] + shift) * cell[1];
    let lower_left = [west, north - nrows as f64 * cell[1]];
    if !(cell.iter().all(|c| c.is_finite() && *c > 0.0) && lower_left.iter().all(|v| v.is_finite()))
    {
        return Err(bad(
            "its ModelPixelScale or ModelTiepoint is not usable".into()
        ));
    }
    Ok((lower_left, cell, keys))
}

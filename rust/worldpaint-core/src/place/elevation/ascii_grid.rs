//! The ESRI ASCII grid: a header of `key value` lines (`ncols`, `nrows`, `xllcorner` or `xllcenter`, `yllcorner` or
//! `yllcenter`, `cellsize` or `dx` and `dy`, optional `NODATA_value`; keys in any case), then the heights row by row,
//! the first row the northern edge. A `.prj` beside it must name WGS84 lon/lat; without one the grid must read as
//! lon/lat (see [`super::check_reads_as_lon_lat`]).

use super::{
    check_grid_size, check_reads_as_lon_lat, not_finite_height, ElevationModel, SRTM_VOID,
};
use crate::error::{Error, FileKind, Result};
use crate::place::crs::{self, Crs};
use crate::place::read_file;
use std::collections::HashMap;
use std::path::Path;

const HEADER_KEYS: [&str; 10] = [
    "ncols",
    "nrows",
    "xllcorner",
    "xllcenter",
    "yllcorner",
    "yllcenter",
    "cellsize",
    "dx",
    "dy",
    "nodata_value",
];

pub(super) fn read(path: &Path, source: &str) -> Result<ElevationModel> {
    let bad = |reason: String| bad(source, reason);
    let bytes = read_file(path, FileKind::ElevationModel)?;
    let text =
        std::str::from_utf8(&bytes).map_err(|_| bad("not an ESRI ASCII grid: not text".into()))?;
    let mut tokens = text.split_ascii_whitespace().peekable();
    let header = read_header(&mut tokens, source)?;
    let get = |k: &str| header.get(k).copied();
    let count = |k: &str| -> Result<usize> {
        match get(k) {
            Some(v) if v >= 2.0 && v.fract() == 0.0 && v <= 1e9 => Ok(v as usize),
            _ => Err(bad(format!(
                "not an ESRI ASCII grid: header '{k}' missing or not a whole number of at least 2"
            ))),
        }
    };
    let (ncols, nrows) = (count("ncols")?, count("nrows")?);
    let cell = match (get("cellsize"), get("dx"), get("dy")) {
        (Some(c), _, _) => [c, c],
        (None, Some(dx), Some(dy)) => [dx, dy],
        _ => {
            return Err(bad(
                "not an ESRI ASCII grid: header 'cellsize' missing".into()
            ))
        }
    };
    if !cell.iter().all(|c| c.is_finite() && *c > 0.0) {
        return Err(bad(
            "not an ESRI ASCII grid: its cell size is not positive".into()
        ));
    }
    let corner = |corner: &str, centre: &str, half: f64| -> Result<f64> {
        get(corner)
            .or_else(|| get(centre).map(|c| c - half))
            .ok_or_else(|| bad(format!("not an ESRI ASCII grid: header '{corner}' missing")))
    };
    let lower_left = [
        corner("xllcorner", "xllcenter", 0.5 * cell[0])?,
        corner("yllcorner", "yllcenter", 0.5 * cell[1])?,
    ];
    match crs::of_prj_beside(path, FileKind::ElevationModel)? {
        Some(Crs::LonLat) => {}
        Some(Crs::LocalMetres) => {
            return Err(crs::cannot_place(
                FileKind::ElevationModel,
                source,
                "a local frame",
            ))
        }
        Some(Crs::Other(name)) => {
            return Err(crs::cannot_place(FileKind::ElevationModel, source, &name))
        }
        None => check_reads_as_lon_lat(source, lower_left, cell, ncols, nrows)?,
    }
    check_grid_size(source, ncols, nrows)?;
    let heights = read_heights(tokens, source, ncols, nrows, get("nodata_value"))?;
    Ok(ElevationModel::new(
        source,
        (ncols, nrows),
        lower_left,
        cell,
        heights,
    ))
}

fn bad(source: &str, reason: String) -> Error {
    Error::parse(FileKind::ElevationModel, format!("{source}: {reason}"))
}

/// The header's `key value` pairs, keys in lower case, up to the first token that is no header key.
fn read_header<'a>(
    tokens: &mut std::iter::Peekable<impl Iterator<Item = &'a str>>,
    source: &str,
) -> Result<HashMap<String, f64>> {
    let mut header = HashMap::new();
    while let Some(t) = tokens.peek() {
        let key = t.to_ascii_lowercase();
        if !HEADER_KEYS.contains(&key.as_str()) {
            break;
        }
        tokens.next();
        let value = tokens
            .next()
            .and_then(|v| v.parse::<f64>().ok())
            .ok_or_else(|| {
                bad(
                    source,
                    format!("not an ESRI ASCII grid: header '{key}' has no number"),
                )
            })?;
        header.insert(key, value);
    }
    Ok(header)
}

/// The `ncols` × `nrows` heights after the header, holes (the SRTM void or the header's NODATA) as NaN.
fn read_heights<'a>(
    tokens: impl Iterator<Item = &'a str>,
    source: &str,
    ncols: usize,
    nrows: usize,
    nodata: Option<f64>,
) -> Result<Vec<f64>> {
    let mut heights = Vec::with_capacity(ncols * nrows);
    for t in tokens {
        let k = heights.len();
        let v: f64 = t.parse().map_err(|_| {
            bad(
                source,
                format!(
                    "'{t}' at row {}, column {} is not a number",
                    k / ncols,
                    k % ncols
                ),
            )
        })?;
        let hole = v == SRTM_VOID || nodata.is_some_and(|n| v == n || (n.is_nan() && v.is_nan()));
        if hole {
            heights.push(f64::NAN);
        } else if v.is_finite() {
            heights.push(v);
        } else {
            return Err(not_finite_height(source, v, k, ncols));
        }
        if heights.len() > ncols * nrows {
            break;
        }
    }
    if heights.len() != ncols * nrows {
        let found = if heights.len() > ncols * nrows {
            format!("more than {}", ncols * nrows)
        } else {
            heights.len().to_string()
        };
        return Err(bad(
            source,
            format!("{found} heights for a {ncols} x {nrows} grid"),
        ));
    }
    Ok(heights)
}

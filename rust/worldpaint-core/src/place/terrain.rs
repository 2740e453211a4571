//! The terrain of a place: the elevation model resampled onto a square metric grid of the place's frame, cropped to
//! the place. Each node of the grid is taken back to lon/lat by the frame's projection and its height interpolated
//! bilinearly between the model's four samples around it. The grid's nodes lie on whole multiples of the cell from
//! the frame's origin, so two imports in the same frame with the same cell share their nodes.

use super::elevation::ElevationModel;
use super::frame::LocalProjection;
use crate::error::{Error, Result};
use crate::limits;
use crate::terrain::Heightfield;
use glam::DVec2;
use rayon::prelude::*;

/// Points per side of the model's box taken to find where its projection lies.
const EDGE_SAMPLES: usize = 64;
/// The model's box in metres is taken this much (m) inside the sampled sides, for the curve between two samples.
const EDGE_INSET: f64 = 0.01;

/// A box in the local frame: (min, max) corners.
pub(crate) type LocalBox = (DVec2, DVec2);

/// The largest axis-aligned box of the local frame inside the model's sample centres once projected (their box in
/// lon/lat is a slightly curved quadrilateral in metres).
pub(crate) fn model_box(model: &ElevationModel, projection: &LocalProjection) -> Result<LocalBox> {
    let (lo, hi) = model.lon_lat_box();
    let along = |a: [f64; 2], b: [f64; 2]| -> Vec<[f64; 2]> {
        (0..=EDGE_SAMPLES)
            .map(|k| {
                let t = k as f64 / EDGE_SAMPLES as f64;
                [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t]
            })
            .collect()
    };
    let west = projection.to_local(&along([lo[0], lo[1]], [lo[0], hi[1]]))?;
    let east = projection.to_local(&along([hi[0], lo[1]], [hi[0], hi[1]]))?;
    let south = projection.to_local(&along([lo[0], lo[1]], [hi[0], lo[1]]))?;
    let north = projection.to_local(&along([lo[0], hi[1]], [hi[0], hi[1]]))?;
    let max =
        |pts: &[DVec2], f: fn(&DVec2) -> f64| pts.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
    let min = |pts: &[DVec2], f: fn(&DVec2) -> f64| pts.iter().map(f).fold(f64::INFINITY, f64::min);
    Ok((
        DVec2::new(max(&west, |p| p.x), max(&south, |p| p.y)) + EDGE_INSET,
        DVec2::new(min(&east, |p| p.x), min(&north, |p| p.y)) - EDGE_INSET,
    ))
}

/// The model's own resolution in metres at its centre: the distance from the central sample to its east and north
/// neighbours.
pub(crate) fn native_spacing(
    model: &ElevationModel,
    projection: &LocalProjection,
) -> Result<DVec2> {
    let (c, r) = (model.ncols / 2, model.nrows / 2);
    let r = r.max(1);
    let c = c.min(model.ncols - 2);
    let p = projection.to_local(&[
        model.sample_lon_lat(c, r),
        model.sample_lon_lat(c + 1, r),
        model.sample_lon_lat(c, r - 1),
    ])?;
    Ok(DVec2::new(p[0].distance(p[1]), p[0].distance(p[2])))
}

/// The lon/lat box around a local box (its corners and the middles of its sides).
pub(crate) fn lon_lat_box_of(
    (lo, hi): LocalBox,
    projection: &LocalProjection,
) -> Result<([f64; 2], [f64; 2])> {
    let mid = (lo + hi) * 0.5;
    let points = [
        lo,
        hi,
        DVec2::new(lo.x, hi.y),
        DVec2::new(hi.x, lo.y),
        DVec2::new(mid.x, lo.y),
        DVec2::new(mid.x, hi.y),
        DVec2::new(lo.x, mid.y),
        DVec2::new(hi.x, mid.y),
    ];
    let ll = projection.to_lon_lat(&points)?;
    let mut out = (ll[0], ll[0]);
    for p in &ll {
        out.0 = [out.0[0].min(p[0]), out.0[1].min(p[1])];
        out.1 = [out.1[0].max(p[0]), out.1[1].max(p[1])];
    }
    Ok(out)
}

/// The grid of `cell` metres whose nodes are the multiples of `cell` inside `bounds`: (origin, nx, ny).
pub(crate) fn grid_in((lo, hi): LocalBox, cell: f64) -> (DVec2, usize, usize) {
    let first = (lo / cell).ceil();
    let last = (hi / cell).floor();
    let count = |a: f64, b: f64| if b >= a { (b - a) as usize + 1 } else { 0 };
    (first * cell, count(first.x, last.x), count(first.y, last.y))
}

/// The model's heights on the grid of `cell` metres inside `bounds` (see the module doc).
pub(crate) fn resample(
    model: &ElevationModel,
    projection: &LocalProjection,
    bounds: LocalBox,
    cell: f64,
) -> Result<Heightfield> {
    let (origin, nx, ny) = grid_in(bounds, cell);
    let size = bounds.1 - bounds.0;
    if nx < 2 || ny < 2 {
        return Err(Error::invalid(
            format!("the terrain of {}", model.source),
            format!(
                "the place and the elevation model share {:.0} x {:.0} m, less than two cells of {cell} m",
                size.x.max(0.0),
                size.y.max(0.0)
            ),
        ));
    }
    limits::check(
        &format!("the terrain of {} at {cell} m cells", model.source),
        nx as f64 * ny as f64,
        limits::MAX_GRID_CELLS,
        "grid cells",
    )?;
    let rows: Vec<Vec<f32>> = (0..ny)
        .into_par_iter()
        .map(|j| -> Result<Vec<f32>> {
            let row: Vec<DVec2> = (0..nx)
                .map(|i| origin + DVec2::new(i as f64, j as f64) * cell)
                .collect();
            let lon_lat = projection.to_lon_lat(&row)?;
            lon_lat
                .iter()
                .map(|p| match model.height_at(*p) {
                    Some(h) if h.is_finite() => Ok(h as f32),
                    _ => Err(Error::invalid(
                        format!("the terrain of {}", model.source),
                        format!("has no height at lon {:.6}, lat {:.6}", p[0], p[1]),
                    )),
                })
                .collect()
        })
        .collect::<Result<_>>()?;
    Heightfield::new(origin, cell, nx, ny, rows.concat())
}

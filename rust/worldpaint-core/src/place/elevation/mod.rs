//! Elevation models as read: a grid of heights (m) on WGS84 lon/lat, whatever the file format, with its holes (no
//! data) as NaN. Three formats: the ESRI ASCII grid (`.asc`, with or without a `.prj` beside it), the SRTM tile
//! (`.hgt`) and the single-band GeoTIFF (`.tif`, `.tiff`). A hole is a sample equal to the file's no-data value, or
//! -32768, SRTM's void, in any format (no land lies 32 km deep).
//!
//! Holes are filled by [`ElevationModel::fill_holes`]: each takes the height of the valid sample that reaches it
//! first breadth-first over the grid (4-neighbours in the order west, east, north, south, starting from every valid
//! sample in row order), so the nearest valid one in steps, deterministically. The import fills only where the holes
//! are a small share of the samples under the place ([`MAX_HOLE_SHARE`]); a larger share is refused, since a filled
//! valley or summit would be invented land.

mod ascii_grid;
mod geotiff;
mod hgt;

use super::layer::LonLat;
use crate::error::{Error, FileKind, Result};
use std::collections::VecDeque;
use std::path::Path;

/// Largest share of no-data samples under a place that the import fills.
pub const MAX_HOLE_SHARE: f64 = 0.05;

/// SRTM's void value, a hole in every format.
pub(crate) const SRTM_VOID: f64 = -32768.0;

/// Coarsest cell (degrees) of a grid that names no CRS and is still read as lon/lat: 0.1° is 11 km, far coarser than
/// any elevation model of a place, and finer than the cells of a metric grid read as degrees.
pub(crate) const MAX_DEGREE_CELL: f64 = 0.1;

/// A grid of heights on WGS84 lon/lat: sample (c, r) at the centre of its cell, row 0 the northern edge.
#[derive(Clone, Debug)]
pub struct ElevationModel {
    /// The file, as given.
    pub source: String,
    /// Samples west to east.
    pub ncols: usize,
    /// Samples north to south.
    pub nrows: usize,
    /// Lon/lat (degrees) of the lower-left corner of the lower-left cell.
    pub lower_left: LonLat,
    /// Cell size in longitude and latitude (degrees).
    pub cell: [f64; 2],
    /// Heights (m), `heights[r * ncols + c]`, row 0 north; NaN where the file has no data.
    pub heights: Vec<f64>,
}

impl ElevationModel {
    /// The model of `heights` (row-major, row 0 north) over `ncols` × `nrows` cells of `cell` degrees from
    /// `lower_left`, read from `source`.
    pub(crate) fn new(
        source: &str,
        (ncols, nrows): (usize, usize),
        lower_left: LonLat,
        cell: [f64; 2],
        heights: Vec<f64>,
    ) -> ElevationModel {
        ElevationModel {
            source: source.to_string(),
            ncols,
            nrows,
            lower_left,
            cell,
            heights,
        }
    }

    /// Lon/lat of sample (c, r).
    pub fn sample_lon_lat(&self, c: usize, r: usize) -> LonLat {
        [
            self.lower_left[0] + (c as f64 + 0.5) * self.cell[0],
            self.lower_left[1] + ((self.nrows - 1 - r) as f64 + 0.5) * self.cell[1],
        ]
    }

    /// The (west, south) and (east, north) sample centres: where heights can be interpolated.
    pub fn lon_lat_box(&self) -> (LonLat, LonLat) {
        (
            self.sample_lon_lat(0, self.nrows - 1),
            self.sample_lon_lat(self.ncols - 1, 0),
        )
    }

    /// Samples with no data.
    pub fn holes(&self) -> usize {
        self.heights.iter().filter(|h| h.is_nan()).count()
    }

    /// The fractional (column, row) of a lon/lat point.
    fn grid_position(&self, p: LonLat) -> (f64, f64) {
        let north = self.lower_left[1] + self.nrows as f64 * self.cell[1];
        (
            (p[0] - self.lower_left[0]) / self.cell[0] - 0.5,
            (north - p[1]) / self.cell[1] - 0.5,
        )
    }

    /// The height at a lon/lat point, bilinear between the four samples around it; `None` outside the sample
    /// centres' box (NaN where a hole is among the four).
    pub fn height_at(&self, p: LonLat) -> Option<f64> {
        let (fc, fr) = self.grid_position(p);
        let (maxc, maxr) = ((self.ncols - 1) as f64, (self.nrows - 1) as f64);
        let eps = 1e-9;
        if !(fc >= -eps && fr >= -eps && fc <= maxc + eps && fr <= maxr + eps) {
            return None;
        }
        let (fc, fr) = (fc.clamp(0.0, maxc), fr.clamp(0.0, maxr));
        let c = (fc.floor() as usize).min(self.ncols - 2);
        let r = (fr.floor() as usize).min(self.nrows - 2);
        let (tc, tr) = (fc - c as f64, fr - r as f64);
        let h = |c: usize, r: usize| self.heights[r * self.ncols + c];
        let top = h(c, r) * (1.0 - tc) + h(c + 1, r) * tc;
        let bottom = h(c, r + 1) * (1.0 - tc) + h(c + 1, r + 1) * tc;
        Some(top * (1.0 - tr) + bottom * tr)
    }

    /// (holes, samples) among the samples whose cells meet the lon/lat box `lo`..`hi`.
    pub fn holes_in(&self, lo: LonLat, hi: LonLat) -> (usize, usize) {
        let (c0, r1) = self.grid_position(lo);
        let (c1, r0) = self.grid_position(hi);
        let clamp = |v: f64, n: usize| (v.max(0.0) as usize).min(n - 1);
        let (c0, c1) = (clamp(c0.floor(), self.ncols), clamp(c1.ceil(), self.ncols));
        let (r0, r1) = (clamp(r0.floor(), self.nrows), clamp(r1.ceil(), self.nrows));
        let mut holes = 0;
        for r in r0..=r1 {
            holes += self.heights[r * self.ncols + c0..=r * self.ncols + c1]
                .iter()
                .filter(|h| h.is_nan())
                .count();
        }
        (holes, (c1 + 1 - c0) * (r1 + 1 - r0))
    }

    /// Fills every hole with the height of the nearest valid sample (breadth-first, see the module doc); returns
    /// the number filled. A grid with no valid sample is refused.
    pub fn fill_holes(&mut self) -> Result<usize> {
        let (ncols, nrows) = (self.ncols, self.nrows);
        let valid: Vec<bool> = self.heights.iter().map(|h| !h.is_nan()).collect();
        let filled = valid.iter().filter(|v| !**v).count();
        if filled == 0 {
            return Ok(0);
        }
        if filled == valid.len() {
            return Err(Error::parse(
                FileKind::ElevationModel,
                format!("{}: it holds no data", self.source),
            ));
        }
        let mut done = valid.clone();
        let mut queue: VecDeque<usize> = (0..valid.len()).filter(|k| valid[*k]).collect();
        let heights = &mut self.heights;
        while let Some(k) = queue.pop_front() {
            let (r, c) = (k / ncols, k % ncols);
            let mut visit = |n: usize| {
                if !done[n] {
                    done[n] = true;
                    heights[n] = heights[k];
                    queue.push_back(n);
                }
            };
            if c > 0 {
                visit(k - 1);
            }
            if c + 1 < ncols {
                visit(k + 1);
            }
            if r > 0 {
                visit(k - ncols);
            }
            if r + 1 < nrows {
                visit(k + ncols);
            }
        }
        Ok(filled)
    }

    /// Checks the grid's geometry: at least 2 × 2 samples, positive finite cells, a finite corner, within the
    /// engine's grid budget.
    pub(crate) fn checked(self) -> Result<ElevationModel> {
        let bad = |reason: String| {
            Error::parse(
                FileKind::ElevationModel,
                format!("{}: {reason}", self.source),
            )
        };
        if self.ncols < 2 || self.nrows < 2 {
            return Err(bad(format!(
                "a {} x {} grid: an elevation model needs at least 2 x 2 samples",
                self.ncols, self.nrows
            )));
        }
        if !self.cell.iter().all(|c| c.is_finite() && *c > 0.0)
            || !self.lower_left.iter().all(|v| v.is_finite())
        {
            return Err(bad(
                "its corner or cell size is not a positive finite number".into(),
            ));
        }
        if self.heights.len() != self.ncols * self.nrows {
            return Err(bad(format!(
                "{} heights for a {} x {} grid",
                self.heights.len(),
                self.ncols,
                self.nrows
            )));
        }
        Ok(self)
    }
}

/// Refuses a grid of `ncols` × `nrows` samples past the engine's grid budget, before it is allocated.
pub(crate) fn check_grid_size(source: &str, ncols: usize, nrows: usize) -> Result<()> {
    crate::limits::check(
        &format!("the elevation model {source}"),
        ncols as f64 * nrows as f64,
        crate::limits::MAX_GRID_CELLS,
        "grid cells",
    )
}

/// Refuses a grid that names no CRS and does not read as lon/lat: its corners must lie in the ranges of degrees and
/// its cells be at most [`MAX_DEGREE_CELL`].
pub(crate) fn check_reads_as_lon_lat(
    source: &str,
    lower_left: LonLat,
    cell: [f64; 2],
    ncols: usize,
    nrows: usize,
) -> Result<()> {
    let upper_right = [
        lower_left[0] + ncols as f64 * cell[0],
        lower_left[1] + nrows as f64 * cell[1],
    ];
    if super::crs::is_lon_lat(lower_left)
        && super::crs::is_lon_lat(upper_right)
        && cell.iter().all(|c| *c <= MAX_DEGREE_CELL)
    {
        return Ok(());
    }
    Err(super::crs::not_lon_lat(
        FileKind::ElevationModel,
        source,
        lower_left,
    ))
}

/// The refusal of sample `k` (row-major, `ncols` a row) whose height `v` is not finite and no hole.
pub(crate) fn not_finite_height(source: &str, v: f64, k: usize, ncols: usize) -> Error {
    Error::parse(
        FileKind::ElevationModel,
        format!(
            "{source}: the height at row {}, column {} is not finite ({v})",
            k / ncols,
            k % ncols
        ),
    )
}

/// Reads an elevation model by its file's extension: `.asc` (ESRI ASCII grid), `.hgt` (SRTM), `.tif`/`.tiff`
/// (GeoTIFF).
pub fn read_elevation_model(path: &Path) -> Result<ElevationModel> {
    let source = path.display().to_string();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    let model = match ext.as_deref() {
        Some("asc") => ascii_grid::read(path, &source)?,
        Some("hgt") => hgt::read(path, &source)?,
        Some("tif" | "tiff") => geotiff::read(path, &source)?,
        _ => {
            return Err(Error::parse(
                FileKind::ElevationModel,
                format!(
                    "{source}: not an elevation model it reads: an ESRI ASCII grid (.asc), an SRTM tile (.hgt) or a \
                     GeoTIFF (.tif)"
                ),
            ))
        }
    };
    model.checked()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model(heights: Vec<f64>, ncols: usize) -> ElevationModel {
        ElevationModel {
            source: "test".into(),
            ncols,
            nrows: heights.len() / ncols,
            lower_left: [10.0, 40.0],
            cell: [0.001, 0.001],
            heights,
        }
    }

    #[test]
    fn bilinear_between_sample_centres() {
        // row 0 north: 0 1 / 2 3
        let m = model(vec![0.0, 1.0, 2.0, 3.0], 2);
        let at = |c: f64, r: f64| {
            m.height_at([10.0 + (c + 0.5) * 0.001, 40.0 + (1.5 - r) * 0.001])
                .unwrap()
        };
        assert!((at(0.0, 0.0) - 0.0).abs() < 1e-9);
        assert!((at(1.0, 1.0) - 3.0).abs() < 1e-9);
        assert!((at(0.5, 0.5) - 1.5).abs() < 1e-9);
        assert!(m.height_at([10.0, 40.0]).is_none());
    }

    #[test]
    fn holes_take_the_nearest_valid_height() {
        let nan = f64::NAN;
        let mut m = model(vec![5.0, nan, nan, nan, nan, 9.0], 3);
        assert_eq!(m.holes(), 4);
        assert_eq!(m.fill_holes().unwrap(), 4);
        assert_eq!(m.heights, vec![5.0, 5.0, 9.0, 5.0, 9.0, 9.0]);
        let mut empty = model(vec![nan; 4], 2);
        assert!(empty.fill_holes().is_err());
    }
}

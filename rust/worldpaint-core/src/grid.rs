//! One regular grid for every raster and bucket index of the engine: the village land, the parcel grid and the
//! spatial indexes of points and segments. Two rules bound its size: a raster that would have more than
//! 16 million nodes is an error (the caller asked for too fine a cell), and a bucket index enlarges its cells
//! until it has at most 4 million (its queries stay exact, only slower).

use crate::error::{check, Error, Result};
use crate::limits;
use glam::DVec2;

/// Largest number of nodes of a raster (village land, parcel grids).
pub(crate) const MAX_NODES: usize = 16_000_000;
/// Largest number of cells of a bucket index (fixed-radius neighbour and nearest-segment queries).
pub(crate) const MAX_BUCKETS: usize = 4_000_000;

/// A regular grid of square cells; node (i, j) is at `origin + (i, j) * cell`, index `j * nx + i`. Bucket indexes
/// read it as cells instead: cell (i, j) spans `origin + (i, j) * cell` to `origin + (i + 1, j + 1) * cell`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Grid {
    /// World XY of node (0, 0), the corner of bucket (0, 0) (m).
    pub origin: DVec2,
    /// Side of a cell, the spacing of nodes (m).
    pub cell: f64,
    /// Nodes (or buckets) along X.
    pub nx: usize,
    /// Nodes (or buckets) along Y.
    pub ny: usize,
}

impl Grid {
    /// The grid of nodes `cell` apart covering the box `min..max` (at least 2×2 nodes, at most [`MAX_NODES`]).
    pub(crate) fn nodes_covering(min: DVec2, max: DVec2, cell: f64) -> Result<Grid> {
        check::positive("village grid cell", cell)?;
        let size = max - min;
        if !(size.x.is_finite() && size.y.is_finite() && size.x > 0.0 && size.y > 0.0) {
            return Err(Error::bad_region("the village region has no area"));
        }
        let nx = (size.x / cell).ceil() as usize + 1;
        let ny = (size.y / cell).ceil() as usize + 1;
        limits::check(
            &format!("a village grid of {cell} m cells"),
            nx as f64 * ny as f64,
            MAX_NODES as u64,
            "nodes",
        )?;
        Ok(Grid {
            origin: min,
            cell,
            nx: nx.max(2),
            ny: ny.max(2),
        })
    }

    /// Buckets of side `cell` (or the box's larger side where `cell` is not a positive number) over the box
    /// `min..max`, enlarged until there are at most [`MAX_BUCKETS`].
    pub(crate) fn buckets_covering(min: DVec2, max: DVec2, cell: f64) -> Grid {
        let ext = (max - min).max(DVec2::splat(1e-9));
        let mut cell = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            ext.x.max(ext.y)
        };
        let max_cells = MAX_BUCKETS as f64;
        if (ext.x / cell + 1.0) * (ext.y / cell + 1.0) > max_cells {
            // the smallest cell with (a/c + 1)(b/c + 1) <= max: the positive root in 1/c, in a form that stays
            // exact for a sliver (b near 0), where the square root of the area alone would give billions of cells
            let (a, b) = (ext.x, ext.y);
            let inverse = 2.0 * (max_cells - 1.0)
                / ((a + b) + ((a + b) * (a + b) + 4.0 * a * b * (max_cells - 1.0)).sqrt());
            cell = (1.0 / inverse).max(cell);
        }
        Grid {
            origin: min,
            cell,
            nx: ((ext.x / cell).floor() as usize + 1).max(1),
            ny: ((ext.y / cell).floor() as usize + 1).max(1),
        }
    }

    /// The first and last buckets (column, row) of the square of half-side `radius` about `p`: the buckets a
    /// fixed-radius query visits.
    #[inline]
    pub(crate) fn buckets_within(&self, p: DVec2, radius: f64) -> ((usize, usize), (usize, usize)) {
        (
            self.bucket_of(p - DVec2::splat(radius)),
            self.bucket_of(p + DVec2::splat(radius)),
        )
    }

    /// The bucket holding `p`; points outside the box (or not finite) are clamped into the border buckets.
    #[inline]
    pub(crate) fn bucket_of(&self, p: DVec2) -> (usize, usize) {
        let f = (p - self.origin) / self.cell;
        // truncation is the floor of a non-negative value (and cheaper: x86-64 has no floor instruction before
        // SSE4.1); `max` turns NaN into 0, `as` saturates +∞
        let clamp = |v: f64, n: usize| {
            if v == f64::INFINITY {
                0
            } else {
                (v.max(0.0) as usize).min(n - 1)
            }
        };
        (clamp(f.x, self.nx), clamp(f.y, self.ny))
    }

    /// World XY of the centre of bucket (i, j).
    pub(crate) fn bucket_centre(&self, i: usize, j: usize) -> DVec2 {
        self.origin + DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * self.cell
    }

    /// Number of nodes (or buckets), `nx * ny`.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Whether the grid has no node.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The index of node (i, j), `j * nx + i`.
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.nx + i
    }

    /// (i, j) of a node index.
    pub(crate) fn ij(&self, k: usize) -> (usize, usize) {
        (k % self.nx, k / self.nx)
    }

    /// World XY of node (i, j).
    pub fn point(&self, i: usize, j: usize) -> DVec2 {
        self.origin + DVec2::new(i as f64, j as f64) * self.cell
    }

    /// World XY of a node index.
    pub fn point_of(&self, k: usize) -> DVec2 {
        let (i, j) = self.ij(k);
        self.point(i, j)
    }

    /// The node nearest to `p`, if `p` lies within half a cell of the grid.
    pub fn nearest(&self, p: DVec2) -> Option<(usize, usize)> {
        let f = (p - self.origin) / self.cell;
        let (i, j) = (f.x.round(), f.y.round());
        if !(i >= 0.0 && j >= 0.0 && i < self.nx as f64 && j < self.ny as f64) {
            return None;
        }
        Some((i as usize, j as usize))
    }

    /// The node index nearest to `p`, clamped onto the grid.
    pub fn nearest_clamped(&self, p: DVec2) -> usize {
        let f = (p - self.origin) / self.cell;
        let i = f.x.round().clamp(0.0, (self.nx - 1) as f64) as usize;
        let j = f.y.round().clamp(0.0, (self.ny - 1) as f64) as usize;
        self.index(i, j)
    }

    /// Bilinear interpolation of node values at `p` (clamped onto the grid).
    pub(crate) fn bilinear(&self, values: &[f32], p: DVec2) -> f64 {
        let f = (p - self.origin) / self.cell;
        let fx = f.x.clamp(0.0, (self.nx - 1) as f64);
        let fy = f.y.clamp(0.0, (self.ny - 1) as f64);
        let i = (fx.floor() as usize).min(self.nx - 2);
        let j = (fy.floor() as usize).min(self.ny - 2);
        let (tx, ty) = (fx - i as f64, fy - j as f64);
        let at = |i: usize, j: usize| values[self.index(i, j)] as f64;
        let a = at(i, j) * (1.0 - tx) + at(i + 1, j) * tx;
        let b = at(i, j + 1) * (1.0 - tx) + at(i + 1, j + 1) * tx;
        a * (1.0 - ty) + b * ty
    }
}

//! Uniform-grid index for fixed-radius neighbour queries. The Metropolis-Hastings inner loop of Section 4.1
//! evaluates, for one changed point `p`, only the factors `h(d(p, y_j))` of its neighbours closer than the
//! histograms' maximum radius (the product simplification of Section 6); with cells as large as that radius a
//! query visits at most 3×3 cells.
//!
//! Points outside the grid's box are clamped into the border cells, so queries stay correct for them too.

use crate::grid::Grid;
use glam::DVec2;

/// One indexed point: its position, a caller-defined `tag` (e.g. which interaction table applies) and `id`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct GridEntry {
    /// World XY (m).
    pub position: DVec2,
    /// What the caller groups entries by (a category, an interaction table).
    pub tag: u32,
    /// The caller's index of the entry; [`SpatialGrid::remove`] finds an entry by it.
    pub id: u32,
}

/// A uniform grid of square cells over a box.
#[derive(Clone, Debug)]
pub(crate) struct SpatialGrid {
    grid: Grid,
    cells: Vec<Vec<GridEntry>>,
}

impl SpatialGrid {
    /// Grid over the box `min..max` with cells of side `cell` (normally the largest query radius).
    /// The cell count is capped (4 million) by enlarging cells, which keeps queries correct.
    pub(crate) fn new(min: DVec2, max: DVec2, cell: f64) -> Self {
        let grid = Grid::buckets_covering(min, max, cell);
        SpatialGrid {
            grid,
            cells: vec![Vec::new(); grid.nx * grid.ny],
        }
    }

    fn cell_coords(&self, p: DVec2) -> (usize, usize) {
        self.grid.bucket_of(p)
    }

    /// Adds an entry to the cell of its position.
    pub(crate) fn insert(&mut self, entry: GridEntry) {
        let (cx, cy) = self.cell_coords(entry.position);
        self.cells[cy * self.grid.nx + cx].push(entry);
    }

    /// Removes the entry with this `id` stored at `position`; returns whether it was found.
    pub(crate) fn remove(&mut self, position: DVec2, id: u32) -> bool {
        let (cx, cy) = self.cell_coords(position);
        let cell = &mut self.cells[cy * self.grid.nx + cx];
        if let Some(k) = cell.iter().position(|e| e.id == id) {
            cell.swap_remove(k);
            true
        } else {
            false
        }
    }

    /// Calls `visit(entry, distance²)` for every entry within `radius` of `p` (inclusive).
    #[inline]
    pub(crate) fn for_each_within<F: FnMut(&GridEntry, f64)>(
        &self,
        p: DVec2,
        radius: f64,
        mut visit: F,
    ) {
        let r2 = radius * radius;
        let ((x0, y0), (x1, y1)) = self.grid.buckets_within(p, radius);
        for cy in y0..=y1 {
            let row = cy * self.grid.nx;
            for cx in x0..=x1 {
                for e in &self.cells[row + cx] {
                    let d2 = e.position.distance_squared(p);
                    if d2 <= r2 {
                        visit(e, d2);
                    }
                }
            }
        }
    }

    /// All entries, cell by cell.
    pub(crate) fn entries(&self) -> impl Iterator<Item = &GridEntry> {
        self.cells.iter().flatten()
    }

    /// Whether any entry other than `skip_id` lies strictly closer than `radius` to `p`.
    pub(crate) fn any_closer_than(&self, p: DVec2, radius: f64, skip_id: Option<u32>) -> bool {
        let r2 = radius * radius;
        let ((x0, y0), (x1, y1)) = self.grid.buckets_within(p, radius);
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                for e in &self.cells[cy * self.grid.nx + cx] {
                    if Some(e.id) != skip_id && e.position.distance_squared(p) < r2 {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// A uniform grid of points that only grows: each cell's points in a list threaded through two arrays, so an
/// insertion allocates nothing per cell (a million darts otherwise allocate a vector per cell they land in, and
/// every query chases its heap block).
#[derive(Clone, Debug)]
pub(crate) struct GrowingPoints {
    grid: Grid,
    head: Vec<u32>,
    next: Vec<u32>,
    points: Vec<DVec2>,
}

impl GrowingPoints {
    const NONE: u32 = u32::MAX;

    /// Grid over the box `min..max` with cells of side `cell`, room for `capacity` points.
    pub(crate) fn new(min: DVec2, max: DVec2, cell: f64, capacity: usize) -> Self {
        let grid = Grid::buckets_covering(min, max, cell);
        GrowingPoints {
            grid,
            head: vec![Self::NONE; grid.nx * grid.ny],
            next: Vec::with_capacity(capacity),
            points: Vec::with_capacity(capacity),
        }
    }

    /// Adds a point (its id is the count before it).
    pub(crate) fn push(&mut self, p: DVec2) {
        let (cx, cy) = self.grid.bucket_of(p);
        let cell = &mut self.head[cy * self.grid.nx + cx];
        self.next.push(*cell);
        *cell = self.points.len() as u32;
        self.points.push(p);
    }

    /// The points in the order they were pushed.
    pub(crate) fn points(&self) -> &[DVec2] {
        &self.points
    }

    pub(crate) fn into_points(self) -> Vec<DVec2> {
        self.points
    }

    /// Whether `found(offset, distance²)` holds for a point within `radius` of `p` (inclusive), its offset being
    /// the point less `p`.
    #[inline]
    pub(crate) fn any_within(
        &self,
        p: DVec2,
        radius: f64,
        found: impl FnMut(DVec2, f64) -> bool,
    ) -> bool {
        self.any_within_since(p, radius, 0, found)
    }

    /// Appends to `out` the ids of the points within `radius` of `p` (inclusive), in no particular order.
    pub(crate) fn ids_within(&self, p: DVec2, radius: f64, out: &mut Vec<u32>) {
        self.visit_within(p, radius, 0, |j, _, _| {
            out.push(j);
            false
        });
    }

    /// [`Self::any_within`] among the points pushed from the `since`-th on (a cell lists its points newest first,
    /// so its older ones are not read).
    #[inline]
    pub(crate) fn any_within_since(
        &self,
        p: DVec2,
        radius: f64,
        since: usize,
        mut found: impl FnMut(DVec2, f64) -> bool,
    ) -> bool {
        self.visit_within(p, radius, since, |_, v, d2| found(v, d2))
    }

    /// Calls `visit(id, offset, distance²)` for the points from the `since`-th on within `radius` of `p`
    /// (inclusive) until it returns true; whether it did.
    #[inline]
    fn visit_within(
        &self,
        p: DVec2,
        radius: f64,
        since: usize,
        mut visit: impl FnMut(u32, DVec2, f64) -> bool,
    ) -> bool {
        let r2 = radius * radius;
        let ((x0, y0), (x1, y1)) = self.grid.buckets_within(p, radius);
        for cy in y0..=y1 {
            for &first in &self.head[cy * self.grid.nx + x0..=cy * self.grid.nx + x1] {
                let mut j = first;
                while j != Self::NONE && j as usize >= since {
                    let v = self.points[j as usize] - p;
                    let d2 = v.length_squared();
                    if d2 <= r2 && visit(j, v, d2) {
                        return true;
                    }
                    j = self.next[j as usize];
                }
            }
        }
        false
    }
}

/// A static uniform grid stored flat: entries sorted by cell (struct of arrays), one offset per cell, so that
/// consecutive cells of a row are one contiguous slice. Built once by a counting sort; read-only.
#[derive(Clone, Debug, Default)]
pub(crate) struct FlatGrid {
    grid: Grid,
    start: Vec<u32>,
    pub(crate) xs: Vec<f64>,
    pub(crate) ys: Vec<f64>,
    pub(crate) tags: Vec<u32>,
    pub(crate) ids: Vec<u32>,
}

impl FlatGrid {
    /// Grid over the box `min..max` with cells of side `cell` holding the `n` entries `entry(0..n)`.
    pub(crate) fn build(
        min: DVec2,
        max: DVec2,
        cell: f64,
        n: usize,
        entry: impl Fn(usize) -> GridEntry,
    ) -> Self {
        let grid = Grid::buckets_covering(min, max, cell);
        let (nx, ny) = (grid.nx, grid.ny);
        let mut grid = FlatGrid {
            grid,
            start: vec![0; nx * ny + 1],
            xs: vec![0.0; n],
            ys: vec![0.0; n],
            tags: vec![0; n],
            ids: vec![0; n],
        };
        let cells: Vec<u32> = (0..n)
            .map(|i| {
                let (cx, cy) = grid.cell_coords(entry(i).position);
                (cy * nx + cx) as u32
            })
            .collect();
        for &c in &cells {
            grid.start[c as usize + 1] += 1;
        }
        for c in 0..nx * ny {
            grid.start[c + 1] += grid.start[c];
        }
        let mut fill = grid.start.clone();
        for (i, &c) in cells.iter().enumerate() {
            let e = entry(i);
            let slot = fill[c as usize] as usize;
            fill[c as usize] += 1;
            grid.xs[slot] = e.position.x;
            grid.ys[slot] = e.position.y;
            grid.tags[slot] = e.tag;
            grid.ids[slot] = e.id;
        }
        grid
    }

    #[inline]
    pub(crate) fn cell_coords(&self, p: DVec2) -> (usize, usize) {
        self.grid.bucket_of(p)
    }

    /// Entry index range of cells `x0..=x1` of row `cy` (one contiguous slice).
    #[inline]
    pub(crate) fn row_range(&self, cy: usize, x0: usize, x1: usize) -> (usize, usize) {
        let row = cy * self.grid.nx;
        (
            self.start[row + x0] as usize,
            self.start[row + x1 + 1] as usize,
        )
    }

    pub(crate) fn nx(&self) -> usize {
        self.grid.nx
    }

    pub(crate) fn n_cells(&self) -> usize {
        self.grid.nx * self.grid.ny
    }

    /// Calls `keep_going(index, distance²)` for every entry within `radius` of `p` (inclusive) until it returns
    /// false.
    #[inline]
    pub(crate) fn for_each_within<F: FnMut(usize, f64) -> bool>(
        &self,
        p: DVec2,
        radius: f64,
        mut keep_going: F,
    ) {
        let r2 = radius * radius;
        let ((x0, y0), (x1, y1)) = self.grid.buckets_within(p, radius);
        for cy in y0..=y1 {
            let row = cy * self.grid.nx;
            let (a, b) = (
                self.start[row + x0] as usize,
                self.start[row + x1 + 1] as usize,
            );
            for (o, (x, y)) in self.xs[a..b].iter().zip(&self.ys[a..b]).enumerate() {
                let dx = x - p.x;
                let dy = y - p.y;
                let d2 = dx * dx + dy * dy;
                if d2 <= r2 && !keep_going(a + o, d2) {
                    return;
                }
            }
        }
    }

    /// Calls `visit(index)` for every entry in the cells overlapping the box `lo..hi` (a superset of the
    /// entries inside it).
    pub(crate) fn for_each_in_box_cells<F: FnMut(usize)>(
        &self,
        lo: DVec2,
        hi: DVec2,
        mut visit: F,
    ) {
        let (x0, y0) = self.cell_coords(lo);
        let (x1, y1) = self.cell_coords(hi);
        for cy in y0..=y1 {
            let row = cy * self.grid.nx;
            for i in self.start[row + x0] as usize..self.start[row + x1 + 1] as usize {
                visit(i);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Looking among the points pushed since a count finds those, and none pushed before it, whatever the cell.
    #[test]
    fn growing_points_since_reads_only_the_later_points() {
        let mut grid = GrowingPoints::new(DVec2::ZERO, DVec2::splat(10.0), 1.0, 8);
        for p in [(5.0, 5.0), (5.2, 5.0), (9.0, 9.0), (5.1, 5.1), (1.0, 1.0)] {
            grid.push(DVec2::new(p.0, p.1));
        }
        let near = |since: usize| {
            let mut seen = 0;
            grid.any_within_since(DVec2::new(5.0, 5.0), 0.5, since, |_, _| {
                seen += 1;
                false
            });
            seen
        };
        assert_eq!(near(0), 3);
        assert_eq!(near(1), 2); // (5.2, 5.0) and (5.1, 5.1)
        assert_eq!(near(3), 1); // (5.1, 5.1)
        assert_eq!(near(4), 0);
        assert!(grid.any_within_since(DVec2::new(1.0, 1.0), 0.1, 4, |_, _| true));
    }
}

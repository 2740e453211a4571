//! Between roads as world polylines and roads as grid nodes (thesis 3.2.4): the nodes a segment passes over
//! (its closed cell squares meet the segment), which an existing road puts on the network, and the turning
//! vertices of a node path, which a new road keeps.

use crate::geom::clip_segment_to_box;
use crate::grid::Grid;
use glam::DVec2;

/// The turning vertices of a node path (collinear moves merged).
pub(super) fn node_polyline(grid: &Grid, path: &[usize]) -> Vec<DVec2> {
    let mut points = Vec::new();
    let step = |a: usize, b: usize| {
        let (ai, aj) = grid.ij(a);
        let (bi, bj) = grid.ij(b);
        (bi as i64 - ai as i64, bj as i64 - aj as i64)
    };
    for (k, &n) in path.iter().enumerate() {
        let keep = k == 0 || k + 1 == path.len() || step(path[k - 1], n) != step(n, path[k + 1]);
        if keep {
            points.push(grid.point_of(n));
        }
    }
    points
}

/// The nodes whose closed cell square meets the segment `a`–`b` (world XY), clipped to the grid.
pub(super) fn segment_cells(grid: &Grid, a: DVec2, b: DVec2) -> Vec<usize> {
    let fa = (a - grid.origin) / grid.cell;
    let fb = (b - grid.origin) / grid.cell;
    let lo = DVec2::splat(-0.5);
    let hi = DVec2::new(grid.nx as f64 - 0.5, grid.ny as f64 - 0.5);
    let Some((t0, t1)) = clip_segment_to_box(fa, fb, lo, hi) else {
        return Vec::new();
    };
    let (pa, pb) = (fa + (fb - fa) * t0, fa + (fb - fa) * t1);
    let mut cells: Vec<usize> = Vec::new();
    let n = ((pb - pa).length() * 4.0).ceil().max(1.0) as usize;
    for s in 0..=n {
        let q = pa + (pb - pa) * (s as f64 / n as f64);
        let (qi, qj) = (q.x.round() as i64, q.y.round() as i64);
        for j in qj - 1..=qj + 1 {
            for i in qi - 1..=qi + 1 {
                if i < 0 || j < 0 || i >= grid.nx as i64 || j >= grid.ny as i64 {
                    continue;
                }
                let c = DVec2::new(i as f64, j as f64);
                if clip_segment_to_box(pa, pb, c - 0.5 - 1e-9, c + 0.5 + 1e-9).is_some() {
                    cells.push(grid.index(i as usize, j as usize));
                }
            }
        }
    }
    cells.sort_unstable();
    cells.dedup();
    cells
}

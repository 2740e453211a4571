//! A uniform grid of the arcs of a graph under construction, updated as arcs come and go and nodes move: the
//! crossing and gap tests of the arc chain and the relaxation visit the arcs near a segment only.

use crate::geom::DVec2;
use crate::palette::Histogram;

/// The gap between an arc and another one it does not meet at a node, relative to the shortest learned edge.
const GAP: f64 = 0.3;

/// The smallest distance between arcs that do not share a node, for the learned edge lengths: never 0, so that no
/// two arcs cross even where the shortest edges fall in the first bin (real roads drawn with short segments).
pub(super) fn arc_gap(lengths: &Histogram) -> f64 {
    let first = lengths.values.iter().position(|v| *v > 0.0).unwrap_or(0);
    let shortest = lengths.start + first as f64 * lengths.bin_width;
    GAP * shortest.max(0.5 * lengths.bin_width)
}

/// Arcs in a uniform grid of cells as large as the longest arc over the nodes' box, updated as nodes move
/// (moved nodes stay in the region, inside the box).
pub(super) struct ArcGrid {
    origin: DVec2,
    cell: f64,
    nx: i64,
    ny: i64,
    cells: Vec<Vec<u32>>,
}

impl ArcGrid {
    pub(super) fn new(nodes: &[DVec2], cell: f64) -> Self {
        let (lo, hi) = nodes.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let ext = (hi - lo).max(DVec2::splat(1e-9));
        // at most about a million cells
        let cell = cell.max((ext.x * ext.y / 1.0e6).sqrt()).max(1e-6);
        let nx = (ext.x / cell).floor() as i64 + 1;
        let ny = (ext.y / cell).floor() as i64 + 1;
        ArcGrid {
            origin: lo,
            cell,
            nx,
            ny,
            cells: vec![Vec::new(); (nx * ny) as usize],
        }
    }

    /// The cells within `margin` of the box of `a`–`b`, clamped to the grid.
    fn range(&self, a: DVec2, b: DVec2, margin: f64) -> (i64, i64, i64, i64) {
        let lo = (a.min(b) - DVec2::splat(margin) - self.origin) / self.cell;
        let hi = (a.max(b) + DVec2::splat(margin) - self.origin) / self.cell;
        let clamp = |v: f64, n: i64| (v.floor() as i64).clamp(0, n - 1);
        (
            clamp(lo.x, self.nx),
            clamp(lo.y, self.ny),
            clamp(hi.x, self.nx),
            clamp(hi.y, self.ny),
        )
    }

    pub(super) fn insert(&mut self, arc: u32, a: DVec2, b: DVec2) {
        let (x0, y0, x1, y1) = self.range(a, b, 0.0);
        for y in y0..=y1 {
            for x in x0..=x1 {
                self.cells[(y * self.nx + x) as usize].push(arc);
            }
        }
    }

    pub(super) fn remove(&mut self, arc: u32, a: DVec2, b: DVec2) {
        let (x0, y0, x1, y1) = self.range(a, b, 0.0);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let cell = &mut self.cells[(y * self.nx + x) as usize];
                if let Some(k) = cell.iter().position(|&c| c == arc) {
                    cell.swap_remove(k);
                }
            }
        }
    }

    /// Arcs listed within `margin` of the box of `a`–`b`, each once.
    pub(super) fn near(&self, a: DVec2, b: DVec2, margin: f64, out: &mut Vec<u32>) {
        out.clear();
        let (x0, y0, x1, y1) = self.range(a, b, margin);
        for y in y0..=y1 {
            for x in x0..=x1 {
                for &c in &self.cells[(y * self.nx + x) as usize] {
                    if !out.contains(&c) {
                        out.push(c);
                    }
                }
            }
        }
    }
}

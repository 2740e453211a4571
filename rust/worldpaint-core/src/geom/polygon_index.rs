//! Containment in a large polygon without reading all of its edges: the edges bucketed by horizontal bands.

use super::DVec2;

/// Polygons with more vertices than this answer many queries through an index ([`PolygonIndex`], and the
/// [`super::PreparedRegion`]'s edge tree): below it, reading every edge costs about as much as the index does.
pub(crate) const INDEXED_POLYGON: usize = 32;

/// The edges of a polygon bucketed by horizontal bands, so that a containment query reads only the edges of its
/// band instead of all of them: a region of a million vertices is sampled in a second, not in minutes. It gives the
/// same answers as [`super::polygon_contains`]: the edges a horizontal ray crosses all lie in the ray's band, and
/// each is tested with the same arithmetic.
#[derive(Clone, Debug)]
pub(crate) struct PolygonIndex {
    y0: f64,
    band: f64,
    /// Band `k` lists the edges `edges[starts[k]..starts[k + 1]]`.
    starts: Vec<u32>,
    /// Per band, the edges (index of their first point, the edge running to the point before it) whose y-range
    /// meets it.
    edges: Vec<u32>,
}

impl PolygonIndex {
    /// The index of the closed polygon `points`. About four edges per band beyond those every band holds where
    /// the boundary climbs through it, and at most about eight entries per edge in all (an outline that zigzags
    /// across its whole height gets fewer, taller bands).
    pub(crate) fn new(points: &[DVec2]) -> Self {
        let n = points.len();
        let (y0, y1) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.y), hi.max(p.y))
            });
        let edge = |i: usize| (points[i], points[(i + n - 1) % n]);
        // the boundary's total climb over its height: how many bands an average band's edges span
        let climb: f64 = (0..n).map(|i| (edge(i).0.y - edge(i).1.y).abs()).sum();
        let by_budget = 8.0 * n as f64 * (y1 - y0) / climb;
        let bands = if by_budget.is_finite() {
            (n / 4).min(by_budget as usize).max(1)
        } else {
            1
        };
        let band = ((y1 - y0) / bands as f64).max(f64::MIN_POSITIVE);
        // `as` rounds towards zero, which is down for the non-negative, and saturates below at 0
        let band_of = |y: f64| (((y - y0) / band) as usize).min(bands - 1);
        let span = |i: usize| {
            let (a, b) = edge(i);
            band_of(a.y.min(b.y))..=band_of(a.y.max(b.y))
        };
        // counts, then offsets, then the lists (each band's edges in index order)
        let mut starts = vec![0u32; bands + 1];
        for i in 0..n {
            for k in span(i) {
                starts[k + 1] += 1;
            }
        }
        for k in 0..bands {
            starts[k + 1] += starts[k];
        }
        let mut fill: Vec<u32> = starts[..bands].to_vec();
        let mut edges = vec![0u32; starts[bands] as usize];
        for i in 0..n {
            for k in span(i) {
                edges[fill[k] as usize] = i as u32;
                fill[k] += 1;
            }
        }
        PolygonIndex {
            y0,
            band,
            starts,
            edges,
        }
    }

    /// [`super::polygon_contains`] of `p` in `points` (the polygon the index was built on), reading only the
    /// edges of `p`'s band.
    pub(crate) fn contains(&self, points: &[DVec2], p: DVec2) -> bool {
        let bands = self.starts.len() - 1;
        let k = (p.y - self.y0) / self.band;
        if !(k >= 0.0 && k < bands as f64 + 1.0) {
            return false;
        }
        let last = points.len() - 1;
        let k = (k as usize).min(bands - 1);
        let list = &self.edges[self.starts[k] as usize..self.starts[k + 1] as usize];
        let mut inside = false;
        for &i in list {
            let i = i as usize;
            let (a, b) = (points[i], points[if i == 0 { last } else { i - 1 }]);
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
                if p.x < x {
                    inside = !inside;
                }
            }
        }
        inside
    }
}

//! Boundary curves (seed §5.3's boundary tool: "a set of boundary strokes which stop the local growth"), indexed so
//! that a growth step asks only the curve pieces near it whether a new edge crosses them.
//!
//! Readings: a segment that touches a curve (an end on it) crosses it, so that no element stands on a boundary; no
//! element stands nearer a curve than r_short either (half the reference's shortest edge: the room an element keeps
//! from its neighbours, so that a stone does not straddle a wall);
//! each curve segment is cut into pieces no longer than a grid cell (the reference's mean edge, larger for curves
//! so long that more than [`MAX_PIECES`] pieces would be needed), each piece listed in the cells its box covers.

use std::collections::HashMap;

use glam::DVec2;

use crate::error::{Error, Result};

/// The most pieces the index cuts the curves into (its cells grow to keep within).
const MAX_PIECES: f64 = 4_000_000.0;

/// The boundary curves' pieces in a grid of square cells.
pub(crate) struct BoundaryIndex {
    cell: f64,
    pieces: Vec<(DVec2, DVec2)>,
    cells: HashMap<(i64, i64), Vec<u32>>,
}

impl BoundaryIndex {
    /// Indexes `curves` with cells of about `cell` (m). Errors on a point that is not finite or too many points.
    pub(crate) fn new(curves: &[Vec<DVec2>], cell: f64) -> Result<BoundaryIndex> {
        let points: usize = curves.iter().map(Vec::len).sum();
        crate::error::check::at_most_items(
            "boundary curves' points",
            points,
            crate::limits::MAX_REGION_VERTICES as usize,
        )?;
        let mut total = 0.0;
        for (k, curve) in curves.iter().enumerate() {
            if curve.iter().any(|p| !p.is_finite()) {
                return Err(Error::invalid(
                    "boundary curves",
                    format!("curve {k} has a point that is not finite"),
                ));
            }
            total += curve.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
        }
        if !total.is_finite() {
            return Err(Error::invalid(
                "boundary curves",
                "their length is not finite",
            ));
        }
        let cell = cell.max(total / MAX_PIECES).max(f64::MIN_POSITIVE);
        let mut index = BoundaryIndex {
            cell,
            pieces: Vec::new(),
            cells: HashMap::new(),
        };
        for curve in curves {
            for w in curve.windows(2) {
                let (a, b) = (w[0], w[1]);
                let length = a.distance(b);
                if !(length > 0.0) {
                    continue;
                }
                let count = (length / cell).ceil().max(1.0) as usize;
                for k in 0..count {
                    let p = a.lerp(b, k as f64 / count as f64);
                    let q = a.lerp(b, (k + 1) as f64 / count as f64);
                    index.insert(p, q);
                }
            }
        }
        Ok(index)
    }

    fn insert(&mut self, a: DVec2, b: DVec2) {
        let id = self.pieces.len() as u32;
        self.pieces.push((a, b));
        let (lo, hi) = (self.cell_of(a.min(b)), self.cell_of(a.max(b)));
        for cx in lo.0..=hi.0 {
            for cy in lo.1..=hi.1 {
                self.cells.entry((cx, cy)).or_default().push(id);
            }
        }
    }

    fn cell_of(&self, p: DVec2) -> (i64, i64) {
        (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
        )
    }

    /// Whether there are no curves.
    pub(crate) fn is_empty(&self) -> bool {
        self.pieces.is_empty()
    }

    /// Whether a boundary curve passes within `radius` of `p`.
    pub(crate) fn near(&self, p: DVec2, radius: f64) -> bool {
        if self.pieces.is_empty() {
            return false;
        }
        let (lo, hi) = (
            self.cell_of(p - DVec2::splat(radius)),
            self.cell_of(p + DVec2::splat(radius)),
        );
        let close = |&id: &u32| {
            let (c, d) = self.pieces[id as usize];
            let t = ((p - c).dot(d - c) / (d - c).length_squared()).clamp(0.0, 1.0);
            p.distance_squared(c.lerp(d, t)) <= radius * radius
        };
        (lo.0..=hi.0).any(|cx| {
            (lo.1..=hi.1).any(|cy| {
                self.cells
                    .get(&(cx, cy))
                    .is_some_and(|ids| ids.iter().any(close))
            })
        })
    }

    /// Whether the segment `a`–`b` crosses or touches a boundary curve.
    pub(crate) fn crosses(&self, a: DVec2, b: DVec2) -> bool {
        if self.pieces.is_empty() {
            return false;
        }
        let (lo, hi) = (self.cell_of(a.min(b)), self.cell_of(a.max(b)));
        // a segment across very many cells (never one a growth step makes) reads the pieces instead
        let span = |a: i64, b: i64| b.saturating_sub(a).saturating_add(1);
        if span(lo.0, hi.0).saturating_mul(span(lo.1, hi.1)) > self.pieces.len() as i64 {
            return self.pieces.iter().any(|&(c, d)| segments_meet(a, b, c, d));
        }
        for cx in lo.0..=hi.0 {
            for cy in lo.1..=hi.1 {
                if let Some(ids) = self.cells.get(&(cx, cy)) {
                    if ids.iter().any(|&id| {
                        let (c, d) = self.pieces[id as usize];
                        segments_meet(a, b, c, d)
                    }) {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// Whether the closed segments `a`–`b` and `c`–`d` share a point.
fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let o1 = (b - a).perp_dot(c - a);
    let o2 = (b - a).perp_dot(d - a);
    let o3 = (d - c).perp_dot(a - c);
    let o4 = (d - c).perp_dot(b - c);
    if o1 == 0.0 && o2 == 0.0 {
        // collinear: they meet where their extents along the line overlap
        let axis = if (b - a).length_squared() > 0.0 {
            b - a
        } else {
            d - c
        };
        let t = |p: DVec2| p.dot(axis);
        let (a0, a1) = (t(a).min(t(b)), t(a).max(t(b)));
        let (c0, c1) = (t(c).min(t(d)), t(c).max(t(d)));
        return a0 <= c1 && c0 <= a1;
    }
    o1 * o2 <= 0.0 && o3 * o4 <= 0.0
}

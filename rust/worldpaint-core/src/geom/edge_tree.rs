//! Distance, circle and segment queries on a large polygon that read only the edges near the query: the
//! boundary's runs of consecutive edges boxed, and the boxes nested in a binary tree.
//!
//! A drawn outline is a chain: consecutive edges lie close together, so runs of a few of them have small boxes
//! and the boxes of runs of runs stay tight. A query descends from the root into the boxes that can hold an edge
//! that matters to it, so that it reads a few dozen edges of a polygon of any size.
//!
//! The answers are those of reading every edge: the edges read are tested with the same arithmetic, and a box is
//! passed over only when every edge in it is farther (for a circle, wholly inside or outside; for a segment, off
//! its box) by a margin far above the rounding of that arithmetic (see [`EdgeTree::margin`]).

use super::{segment_distance, DVec2};

/// Consecutive edges boxed together in a leaf.
const LEAF_EDGES: usize = 8;
/// Room for a depth-first descent: at most one pending sibling per level of a tree whose node indices fit in a
/// `usize`, and the node being entered.
const STACK: usize = usize::BITS as usize + 2;

/// Boxes over the edges `(points[i], points[(i + 1) % n])` of a closed polygon (the edges of
/// [`super::Region::distance_to_boundary`] and of the crossings), in a complete binary tree: node 1 is the
/// root, node `k` has the children `2k` and `2k + 1`, and leaf `j` (node `leaves + j`) holds the edges
/// `j * LEAF_EDGES..(j + 1) * LEAF_EDGES`.
#[derive(Clone, Debug)]
pub(crate) struct EdgeTree {
    /// Per node, its box (min, max corners); empty boxes have infinite corners the wrong way round.
    boxes: Vec<(DVec2, DVec2)>,
    leaves: usize,
    /// Above every coordinate's magnitude and every edge's length: the scale of the rounding in the edge tests.
    scale: f64,
}

/// The smallest box holding both.
fn union(a: (DVec2, DVec2), b: (DVec2, DVec2)) -> (DVec2, DVec2) {
    (a.0.min(b.0), a.1.max(b.1))
}

/// Distance from `p` to the nearest point of the box (infinite for an empty box).
fn nearest(b: (DVec2, DVec2), p: DVec2) -> f64 {
    (b.0 - p).max(p - b.1).max(DVec2::ZERO).length()
}

/// Distance from `p` to the farthest corner of the box.
fn farthest(b: (DVec2, DVec2), p: DVec2) -> f64 {
    (p - b.0).abs().max((b.1 - p).abs()).length()
}

impl EdgeTree {
    /// The tree of the closed polygon `points`.
    pub(crate) fn new(points: &[DVec2]) -> Self {
        let n = points.len();
        let used = n.div_ceil(LEAF_EDGES).max(1);
        let leaves = used.next_power_of_two();
        let empty = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        let mut boxes = vec![empty; 2 * leaves];
        for (j, b) in boxes[leaves..leaves + used].iter_mut().enumerate() {
            for i in j * LEAF_EDGES..((j + 1) * LEAF_EDGES).min(n) {
                let (a, c) = (points[i], points[(i + 1) % n]);
                *b = union(*b, (a.min(c), a.max(c)));
            }
        }
        for k in (1..leaves).rev() {
            boxes[k] = union(boxes[2 * k], boxes[2 * k + 1]);
        }
        let (lo, hi) = boxes[1];
        let scale = 4.0 * lo.abs().max(hi.abs()).max_element();
        EdgeTree {
            boxes,
            leaves,
            scale: if scale.is_finite() { scale } else { 0.0 },
        }
    }

    /// How much farther than a distance `reach` from `p` a box must lie before its edges are passed over: a
    /// millionth of the lengths in play. The edge tests round to some units in the last place of those lengths (a
    /// circle's crossings near a tangent to about their square root, 10⁻⁸ of them), so the margin keeps the
    /// answers those of reading every edge while costing nothing (micrometres on a world of kilometres).
    fn margin(&self, p: DVec2, reach: f64) -> f64 {
        1e-6 * (self.scale + p.abs().max_element() + reach)
    }

    /// The edges of leaf node `k`, handed to `visit` in order.
    fn leaf_edges(&self, points: &[DVec2], k: usize, mut visit: impl FnMut(DVec2, DVec2)) {
        let n = points.len();
        let j = k - self.leaves;
        for i in j * LEAF_EDGES..((j + 1) * LEAF_EDGES).min(n) {
            visit(points[i], points[if i + 1 == n { 0 } else { i + 1 }]);
        }
    }

    /// The smaller of `max` and the distance from `p` to the nearest edge of `points` (the polygon the tree was
    /// built on): `min(max, min_i segment_distance(p, a_i, b_i))` exactly, reading the nearest boxes first and
    /// passing over the boxes that cannot hold a nearer edge.
    pub(crate) fn distance(&self, points: &[DVec2], p: DVec2, max: f64) -> f64 {
        // `f64::min` passes over NaN: a NaN bound bounds nothing
        let mut best = if max.is_nan() { f64::INFINITY } else { max };
        let margin = self.margin(p, 0.0);
        // depth-first, the nearer child on top: (node, distance to its box)
        let mut stack = [(0usize, 0.0f64); STACK];
        stack[0] = (1, nearest(self.boxes[1], p));
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (k, d) = stack[top];
            // `!(<)`: a NaN query point reads nothing, as every edge would give NaN and leave `best` alone
            if !(d - margin < best) {
                continue;
            }
            if k >= self.leaves {
                self.leaf_edges(points, k, |a, b| best = best.min(segment_distance(p, a, b)));
                continue;
            }
            let (c0, c1) = (2 * k, 2 * k + 1);
            let (d0, d1) = (nearest(self.boxes[c0], p), nearest(self.boxes[c1], p));
            let (near, far) = if d1 < d0 {
                ((c1, d1), (c0, d0))
            } else {
                ((c0, d0), (c1, d1))
            };
            stack[top] = far;
            stack[top + 1] = near;
            top += 2;
        }
        best
    }

    /// Hands `visit` every edge that can cross the circle `C(p, r)` — all edges but those in boxes wholly inside or
    /// wholly outside it, by the margin — in no particular order.
    pub(crate) fn edges_near_circle(
        &self,
        points: &[DVec2],
        p: DVec2,
        r: f64,
        mut visit: impl FnMut(DVec2, DVec2),
    ) {
        // the crossings depend on r² alone
        let r = r.abs();
        let margin = self.margin(p, r);
        self.edges_in_boxes(
            points,
            |b| !(nearest(b, p) - margin > r || farthest(b, p) + margin < r),
            &mut visit,
        );
    }

    /// Hands `visit` every edge that can cross the segment `a`–`b` — all edges but those in boxes off the segment's
    /// box by the margin — in no particular order.
    pub(crate) fn edges_near_segment(
        &self,
        points: &[DVec2],
        a: DVec2,
        b: DVec2,
        mut visit: impl FnMut(DVec2, DVec2),
    ) {
        let margin = self.margin(a.abs().max(b.abs()), (b - a).abs().max_element());
        let (lo, hi) = (
            a.min(b) - DVec2::splat(margin),
            a.max(b) + DVec2::splat(margin),
        );
        self.edges_in_boxes(
            points,
            |(blo, bhi)| !(blo.x > hi.x || blo.y > hi.y || bhi.x < lo.x || bhi.y < lo.y),
            &mut visit,
        );
    }

    /// Hands `visit` the edges of every leaf reached through boxes that `enter` accepts, depth-first, the lower
    /// child first.
    fn edges_in_boxes(
        &self,
        points: &[DVec2],
        enter: impl Fn((DVec2, DVec2)) -> bool,
        mut visit: impl FnMut(DVec2, DVec2),
    ) {
        let mut stack = [0usize; STACK];
        stack[0] = 1;
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let k = stack[top];
            if !enter(self.boxes[k]) {
                continue;
            }
            if k >= self.leaves {
                self.leaf_edges(points, k, &mut visit);
                continue;
            }
            stack[top] = 2 * k + 1;
            stack[top + 1] = 2 * k;
            top += 2;
        }
    }
}

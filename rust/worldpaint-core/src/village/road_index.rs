//! Road centre lines as segments in buckets: the queries land parcels (thesis 3.3, Emilien 2014 ch. 3) and
//! building footprints make of the roads — the closest road point, the segments near a box, the clearance of a
//! segment.

use super::Road;
use crate::geom::{closest_on_segment, polyline_segments, segments_distance};
use crate::graph::SegmentIndex;
use glam::DVec2;

/// The closest point of the roads to a point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Projection {
    pub point: DVec2,
    pub segment: usize,
    pub distance: f64,
    /// The side of the segment the point stands on: +1 on its left (or on it), −1 on its right.
    pub side: f64,
}

/// Road centre-line segments in a [`SegmentIndex`], with the queries parcels and footprints make of them.
#[derive(Clone, Debug, Default)]
pub(crate) struct RoadIndex {
    index: SegmentIndex,
}

/// The segments of a road's centre line; a one-point road is a zero-length segment.
fn road_segments(points: &[DVec2]) -> Vec<(DVec2, DVec2)> {
    match points.len() {
        1 => vec![(points[0], points[0])],
        _ => polyline_segments(points).collect(),
    }
}

fn side_of(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    if (b - a).perp_dot(p - a) >= 0.0 {
        1.0
    } else {
        -1.0
    }
}

impl RoadIndex {
    /// The segments of `roads` (a one-point road is a zero-length segment) in cells of about `cell` metres.
    pub(crate) fn new(roads: &[Road], cell: f64) -> RoadIndex {
        let segments = roads
            .iter()
            .flat_map(|r| road_segments(&r.points))
            .collect();
        RoadIndex {
            index: SegmentIndex::with_cell(segments, cell),
        }
    }

    /// An index without roads over the box `min..max` (cells of about `cell` metres) that roads within it are
    /// added to one by one ([`RoadIndex::add`]).
    pub(crate) fn over(min: DVec2, max: DVec2, cell: f64) -> RoadIndex {
        RoadIndex {
            index: SegmentIndex::empty_over(min, max, cell),
        }
    }

    /// Adds the segments of `road` (the centre line from its first point) after those held.
    pub(crate) fn add(&mut self, road: &[DVec2]) {
        self.index.extend(road_segments(road));
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.index.is_empty()
    }

    pub(crate) fn segments(&self) -> &[(DVec2, DVec2)] {
        self.index.segments()
    }

    /// The segments that may come within the box `lo..hi`, each once, in index order.
    pub(crate) fn candidates(&self, lo: DVec2, hi: DVec2, out: &mut Vec<u32>) {
        self.index.candidates(lo, hi, out);
    }

    /// The closest road point to `p` within `limit`, if any.
    pub(crate) fn nearest(&self, p: DVec2, limit: f64) -> Option<Projection> {
        let mut c = Vec::new();
        self.candidates(p - DVec2::splat(limit), p + DVec2::splat(limit), &mut c);
        let mut best: Option<Projection> = None;
        for &s in &c {
            let (a, b) = self.segments()[s as usize];
            let q = closest_on_segment(p, a, b);
            let d = q.distance(p);
            if d <= limit && best.is_none_or(|b| d < b.distance) {
                best = Some(Projection {
                    point: q,
                    segment: s as usize,
                    distance: d,
                    side: side_of(p, a, b),
                });
            }
        }
        best
    }

    /// The distance from `p` to the roads, or `max` when they are farther.
    pub(crate) fn distance(&self, p: DVec2, max: f64) -> f64 {
        self.index.distance(p, max)
    }

    /// The closest road point to `p`, however far (`p` itself at an infinite distance when there is no road).
    pub(crate) fn project(&self, p: DVec2) -> Projection {
        let d = self.index.distance(p, f64::INFINITY);
        self.nearest(p, d * (1.0 + 1e-9) + 1e-9)
            .unwrap_or(Projection {
                point: p,
                segment: 0,
                distance: f64::INFINITY,
                side: 1.0,
            })
    }

    /// The distance from the segment `a`–`b` to the roads, or `limit` when it is farther than `limit`.
    pub(crate) fn segment_clearance(&self, a: DVec2, b: DVec2, limit: f64) -> f64 {
        let pad = DVec2::splat(limit);
        let mut best = limit;
        self.index
            .visit_candidates(a.min(b) - pad, a.max(b) + pad, |s| {
                let (p, q) = self.segments()[s as usize];
                best = best.min(segments_distance(a, b, p, q));
                best > 0.0
            });
        best
    }
}

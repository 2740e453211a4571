//! A region prepared once for the many queries of a synthesis: its large polygons (also those nested in a clipped
//! region) indexed, so that a query reads the edges near it instead of all of them.
//!
//! A chain asks its region, per proposal, whether the point is inside, how far the boundary is and which share of
//! the circles around the point lies inside (the window-edge correction). Read edge by edge, each of these costs
//! the polygon's vertex count, and a drawn outline of 16,384 vertices made a paste of a thousand instances take
//! seconds. Indexed, they cost a few dozen edges whatever the outline.

use super::edge_tree::EdgeTree;
use super::polygon_index::{PolygonIndex, INDEXED_POLYGON};
use super::queries::{
    clipped_circle_crossings, clipped_contains, clipped_distance, clipped_segment_crossings,
    push_edge_crossing, push_segment_crossings, RegionQueries,
};
use super::{DVec2, Region};

/// A [`Region`] with indexes over its large polygons: it answers the [`RegionQueries`] exactly as the region does
/// (the same edges tested with the same arithmetic), reading only the edges near each query.
#[derive(Clone, Debug)]
pub struct PreparedRegion<'r> {
    region: &'r Region,
    bbox: (DVec2, DVec2),
    shape: Prepared<'r>,
}

/// How a prepared region answers.
#[derive(Clone, Debug)]
enum Prepared<'r> {
    /// Rectangles, circles and polygons too small to index: the region answers itself.
    Direct,
    /// A polygon of more than [`INDEXED_POLYGON`] vertices: bands for containment, a tree of edge boxes for the
    /// distance and the crossings.
    Polygon {
        points: &'r [DVec2],
        bands: PolygonIndex,
        edges: EdgeTree,
    },
    /// A clipped region, its parts prepared.
    Clipped {
        within: Vec<PreparedRegion<'r>>,
        without: Vec<PreparedRegion<'r>>,
    },
}

impl<'r> PreparedRegion<'r> {
    /// Indexes the large polygons of `region` (linear in their vertex count).
    pub fn new(region: &'r Region) -> Self {
        let shape = match region {
            Region::Polygon { points } if points.len() > INDEXED_POLYGON => Prepared::Polygon {
                points,
                bands: PolygonIndex::new(points),
                edges: EdgeTree::new(points),
            },
            Region::Clipped { within, without } => Prepared::Clipped {
                within: within.iter().map(PreparedRegion::new).collect(),
                without: without.iter().map(PreparedRegion::new).collect(),
            },
            _ => Prepared::Direct,
        };
        PreparedRegion {
            region,
            bbox: region.bbox(),
            shape,
        }
    }

    /// The region prepared.
    pub fn region(&self) -> &'r Region {
        self.region
    }
}

impl RegionQueries for PreparedRegion<'_> {
    fn contains(&self, p: DVec2) -> bool {
        match &self.shape {
            Prepared::Direct => {
                // a small polygon still tests its every edge; outside its box it holds nothing
                let (lo, hi) = self.bbox;
                let in_box = p.x >= lo.x && p.y >= lo.y && p.x <= hi.x && p.y <= hi.y;
                (in_box || !matches!(self.region, Region::Polygon { .. }))
                    && self.region.contains(p)
            }
            Prepared::Polygon { points, bands, .. } => bands.contains(points, p),
            Prepared::Clipped { within, without } => clipped_contains(within, without, p),
        }
    }

    fn distance_to_boundary(&self, p: DVec2) -> f64 {
        match &self.shape {
            Prepared::Direct => self.region.distance_to_boundary(p),
            _ => self.distance_to_boundary_within(p, f64::INFINITY),
        }
    }

    fn distance_to_boundary_within(&self, p: DVec2, max: f64) -> f64 {
        match &self.shape {
            Prepared::Direct => self.region.distance_to_boundary(p).min(max),
            Prepared::Polygon { points, edges, .. } => edges.distance(points, p, max),
            Prepared::Clipped { within, without } => clipped_distance(within, without, p, max),
        }
    }

    fn push_circle_crossings(&self, p: DVec2, r: f64, angles: &mut Vec<f64>) {
        match &self.shape {
            Prepared::Direct => self.region.push_circle_crossings(p, r, angles),
            Prepared::Polygon { points, edges, .. } => {
                edges.edges_near_circle(points, p, r, |a, b| {
                    push_segment_crossings(p, r, a, b, angles)
                });
            }
            Prepared::Clipped { within, without } => {
                clipped_circle_crossings(within, without, p, r, angles)
            }
        }
    }

    fn push_segment_crossings(&self, a: DVec2, b: DVec2, out: &mut Vec<f64>) {
        match &self.shape {
            Prepared::Direct => self.region.push_segment_crossings(a, b, out),
            Prepared::Polygon { points, edges, .. } => {
                edges.edges_near_segment(points, a, b, |c, d| push_edge_crossing(a, b, c, d, out));
            }
            Prepared::Clipped { within, without } => {
                clipped_segment_crossings(within, without, a, b, out)
            }
        }
    }

    fn rectangle(&self) -> Option<(DVec2, DVec2)> {
        match self.shape {
            Prepared::Direct => self.region.rectangle(),
            _ => None,
        }
    }

    fn bbox(&self) -> (DVec2, DVec2) {
        self.bbox
    }
}

//! The footprint of the integration mesh on the terrain's grid (see [`super::integration`]): per grid node, the
//! element it lies deepest inside, or the nearest element within a margin outside all water.

use super::integration::{
    fall_width, ribbon_end, ribbon_rows, under_quad, IntegrationOptions, PoolWater, RibbonEnd,
    WaterMesh, WaterPart,
};
use crate::error::{check, Result};
use crate::geom::{polygon_contains, segment_distance};
use crate::terrain::Heightfield;
use crate::waterfall::{ControllerKind, WaterfallNetwork};
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// What the integration mesh puts over one grid node, seen from above.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FootprintNode {
    /// The kind of element.
    pub part: WaterPart,
    /// Segment (contact, free-fall) or pool controller.
    pub element: usize,
    /// Signed plan distance to the element's border: positive inside the water, negative outside (m).
    pub inside: f64,
    /// Distance from the border to the element's middle: the half-width of a ribbon, the largest inside
    /// distance of a pool (m).
    pub half_width: f64,
    /// Water surface height above the node.
    pub surface: f64,
    /// The highest water surface among the elements whose bank band holds the node (−∞ when none does): a bank
    /// between two waters, such as beside a stream above the pool it falls into, holds the higher one.
    pub bank_level: f64,
    /// `ζ` of the element.
    pub depth: f64,
    /// Plan direction of the flow (zero in a pool).
    pub along: DVec2,
}

/// The integration mesh rendered from above onto the terrain's grid: per node, the element it lies deepest
/// inside, or, within `margin` outside all water, the nearest element (its bank).
#[derive(Clone, Debug)]
pub struct WaterfallFootprint {
    /// Nodes along X (the terrain's).
    pub nx: usize,
    /// Nodes along Y.
    pub ny: usize,
    /// World XY of node (0, 0).
    pub origin: DVec2,
    /// Spacing of the nodes (m).
    pub cell: f64,
    /// How far outside the water a node still gets its nearest element (m).
    pub margin: f64,
    /// Per node, row-major: what lies over it, `None` beyond the margin.
    pub nodes: Vec<Option<FootprintNode>>,
}

impl WaterfallFootprint {
    /// Whether node `k` lies under water.
    pub fn is_water(&self, k: usize) -> bool {
        self.nodes
            .get(k)
            .copied()
            .flatten()
            .is_some_and(|n| n.inside > 0.0)
    }
}

/// Footprint nodes of one element: grid node index and what lies over it.
type Hits = Vec<(usize, FootprintNode)>;

/// The terrain nodes in the box `[lo, hi]`, row by row: their index and plan position.
fn nodes_in_box(
    t: &Heightfield,
    lo: DVec2,
    hi: DVec2,
) -> impl Iterator<Item = (usize, DVec2)> + '_ {
    t.nodes_in(lo, hi)
        .into_iter()
        .flat_map(move |(columns, rows)| {
            rows.flat_map(move |j| {
                columns.clone().map(move |i| {
                    (
                        j * t.nx + i,
                        t.origin + DVec2::new(i as f64, j as f64) * t.cell,
                    )
                })
            })
        })
}

/// A free-fall sheet's footprint: the nodes within `hw` of its plan segment `ab`.
fn hits_of_fall(
    t: &Heightfield,
    a: DVec3,
    b: DVec3,
    hw: f64,
    make: impl Fn(f64, f64) -> FootprintNode,
) -> Hits {
    let (a2, b2) = (a.truncate(), b.truncate());
    let ab = b2 - a2;
    let len2 = ab.length_squared();
    nodes_in_box(t, a2.min(b2) - hw, a2.max(b2) + hw)
        .filter_map(|(k, p)| {
            let d = segment_distance(p, a2, b2);
            if d > hw {
                return None;
            }
            let along = if len2 > 0.0 {
                (p - a2).dot(ab) / len2
            } else {
                0.0
            };
            Some((k, make(hw - d, along.clamp(0.0, 1.0))))
        })
        .collect()
}

/// One element of the footprint: a contact or free-fall segment of an arc, or a pool of the mesh.
#[derive(Clone, Copy)]
enum FootprintJob {
    Segment { arc: usize, segment: usize },
    Pool(usize),
}

/// What the footprint of every element is computed from.
struct FootprintInputs<'a> {
    terrain: &'a Heightfield,
    net: &'a WaterfallNetwork,
    mesh: &'a WaterMesh,
    options: &'a IntegrationOptions,
    margin: f64,
    /// The ribbon rows of each contact arc (empty for the others).
    ribbons: Vec<Vec<[DVec3; 3]>>,
}

impl FootprintInputs<'_> {
    /// The elements in a fixed order: the segments of the arcs, then the pools.
    fn jobs(&self) -> Vec<FootprintJob> {
        let mut jobs = Vec::new();
        for (a, arc) in self.net.graph.arcs.iter().enumerate() {
            for s in self.net.segment_ranges[a].clone() {
                if arc.kind != ControllerKind::Pool {
                    jobs.push(FootprintJob::Segment { arc: a, segment: s });
                }
            }
        }
        for p in 0..self.mesh.pools.len() {
            jobs.push(FootprintJob::Pool(p));
        }
        jobs
    }

    /// The nodes an element covers, and whether it is a free-fall.
    fn hits(&self, job: FootprintJob) -> (bool, Hits) {
        match job {
            FootprintJob::Pool(p) => (
                false,
                pool_hits(self.terrain, &self.mesh.pools[p], self.margin),
            ),
            FootprintJob::Segment { arc, segment } => self.segment_hits(arc, segment),
        }
    }

    /// The nodes segment `s` of arc `a` covers: a free-fall's sheet or a contact's ribbon quad, with the surface
    /// interpolated along the segment.
    fn segment_hits(&self, a: usize, s: usize) -> (bool, Hits) {
        let net = self.net;
        let arc = &net.graph.arcs[a];
        let seg = &net.segments[s];
        let range = &net.segment_ranges[a];
        let (p0, p1) = (seg.points[0], seg.points[seg.points.len() - 1]);
        let along = (p1 - p0).truncate().normalize_or_zero();
        let node = |part: WaterPart, hw: f64, inside: f64, t: f64| FootprintNode {
            part,
            element: s,
            inside,
            half_width: hw,
            surface: p0.z + t * (p1.z - p0.z),
            bank_level: f64::NEG_INFINITY,
            depth: seg.section.depth,
            along,
        };
        if arc.kind == ControllerKind::FreeFall {
            let hw = 0.5 * fall_width(net, a, self.options);
            let hit = hits_of_fall(self.terrain, p0, p1, hw, |inside, t| {
                node(WaterPart::FreeFall, hw, inside, t)
            });
            return (true, hit);
        }
        let ends = (
            ribbon_end(net, arc.from, true),
            ribbon_end(net, arc.to, false),
        );
        let hit = hits_of_quad(
            self.terrain,
            &self.ribbons[a],
            s - range.start,
            self.margin,
            ends,
            |hw, inside, t| node(WaterPart::Contact, hw, inside, t),
        );
        (false, hit)
    }
}

/// Rasterizes the mesh's footprint: contacts and pools first (the node takes the element it is deepest in), then
/// free-falls on the nodes no other water covers.
pub fn waterfall_footprint(
    terrain: &Heightfield,
    net: &WaterfallNetwork,
    mesh: &WaterMesh,
    options: &IntegrationOptions,
    margin: f64,
) -> Result<WaterfallFootprint> {
    check::non_negative("footprint margin", margin)?;
    let ribbons: Vec<Vec<[DVec3; 3]>> = net
        .graph
        .arcs
        .iter()
        .enumerate()
        .map(|(a, arc)| match arc.kind {
            ControllerKind::Contact => ribbon_rows(net, a, options),
            _ => Vec::new(),
        })
        .collect();
    let inputs = FootprintInputs {
        terrain,
        net,
        mesh,
        options,
        margin,
        ribbons,
    };
    // (free-fall, hits) per element in a fixed order, computed in parallel
    let hits: Vec<(bool, Hits)> = inputs
        .jobs()
        .par_iter()
        .map(|&job| inputs.hits(job))
        .collect();
    Ok(WaterfallFootprint {
        nx: terrain.nx,
        ny: terrain.ny,
        origin: terrain.origin,
        cell: terrain.cell,
        margin,
        nodes: merged_hits(terrain.nx * terrain.ny, &hits),
    })
}

/// The footprint's nodes from the elements' hits: contacts and pools first, each node taking the element it is
/// deepest in and the highest surface among the bank bands holding it, then free-falls where no water is.
fn merged_hits(len: usize, hits: &[(bool, Hits)]) -> Vec<Option<FootprintNode>> {
    let mut nodes: Vec<Option<FootprintNode>> = vec![None; len];
    // every water element whose bank band holds a node holds it up to its level
    let mut banks = vec![f64::NEG_INFINITY; nodes.len()];
    for (_, list) in hits.iter().filter(|(fall, _)| !fall) {
        for (k, h) in list {
            if h.inside <= 0.0 {
                banks[*k] = banks[*k].max(h.surface);
            }
            match &nodes[*k] {
                Some(old) if old.inside >= h.inside => {}
                _ => nodes[*k] = Some(*h),
            }
        }
    }
    for (node, bank) in nodes.iter_mut().zip(banks) {
        if let Some(n) = node {
            n.bank_level = bank;
        }
    }
    for (_, list) in hits.iter().filter(|(fall, _)| *fall) {
        for (k, h) in list {
            if !nodes[*k].is_some_and(|n| n.inside > 0.0) {
                nodes[*k] = Some(*h);
            }
        }
    }
    nodes
}

/// The footprint of quad `k` of a ribbon, between rows `k` and `k + 1`: the nodes under its triangles (those of
/// the mesh) are inside by their plan distance to the nearest bank edge of this quad or its neighbours, the others
/// within `margin` of those banks outside by it. Beyond the ribbon's first or last row `ends` decide: nothing
/// (open), the row as a bank (closed) or a round cap (joined). `make(half_width, inside, t)` makes the node, `t`
/// the position along the quad.
fn hits_of_quad(
    t: &Heightfield,
    ribbon: &[[DVec3; 3]],
    k: usize,
    margin: f64,
    ends: (RibbonEnd, RibbonEnd),
    make: impl Fn(f64, f64, f64) -> FootprintNode,
) -> Hits {
    if k + 1 >= ribbon.len() {
        return Vec::new();
    }
    let last = ribbon.len() - 2;
    let plan = |j: usize, c: usize| ribbon[j][c].truncate();
    let (l0, c0, r0) = (plan(k, 0), plan(k, 1), plan(k, 2));
    let (l1, c1, r1) = (plan(k + 1, 0), plan(k + 1, 1), plan(k + 1, 2));
    let (hw0, hw1) = (l0.distance(c0), l1.distance(c1));
    // the quad's own bank edges (with its end row where the water is closed there), then its neighbours'
    let mut banks: Vec<(DVec2, DVec2)> = vec![(l0, l1), (r0, r1)];
    if k == 0 && ends.0 == RibbonEnd::Closed {
        banks.push((l0, r0));
    }
    if k == last && ends.1 == RibbonEnd::Closed {
        banks.push((l1, r1));
    }
    let own = banks.len();
    if k > 0 {
        banks.extend([(plan(k - 1, 0), l0), (plan(k - 1, 2), r0)]);
    }
    if k < last {
        banks.extend([(l1, plan(k + 2, 0)), (r1, plan(k + 2, 2))]);
    }
    let reach = margin + hw0.max(hw1);
    let (lo, hi) = [l0, c0, r0, l1, c1, r1].iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let axis = c1 - c0;
    let len2 = axis.length_squared();
    nodes_in_box(t, lo - reach, hi + reach)
        .filter_map(|(node, p)| {
            let raw = if len2 > 0.0 {
                (p - c0).dot(axis) / len2
            } else {
                0.0
            };
            let tt = raw.clamp(0.0, 1.0);
            let hw = hw0 + tt * (hw1 - hw0);
            let under = under_quad(p, &ribbon[k], &ribbon[k + 1]);
            // under the quad the nearest bank may be a neighbour's; outside it the quad's own is what it banks
            let bank = |edges: &[(DVec2, DVec2)]| {
                edges
                    .iter()
                    .map(|(a, b)| segment_distance(p, *a, *b))
                    .fold(f64::INFINITY, f64::min)
            };
            let beyond = match (k == 0 && raw < 0.0, k == last && raw > 1.0) {
                (true, _) => Some((ends.0, c0, hw0)),
                (_, true) => Some((ends.1, c1, hw1)),
                _ => None,
            };
            let inside = match beyond {
                _ if under => bank(&banks),
                Some((RibbonEnd::Open, ..)) => return None,
                Some((RibbonEnd::Joined, c, hw)) => hw - p.distance(c),
                _ => -bank(&banks[..own]),
            };
            (inside >= -margin).then(|| (node, make(hw, inside, tt)))
        })
        .collect()
}

fn pool_hits(t: &Heightfield, pool: &PoolWater, margin: f64) -> Hits {
    let c = &pool.contour;
    let (lo, hi) = c.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let edge = |p: DVec2| {
        (0..c.len())
            .map(|k| segment_distance(p, c[k], c[(k + 1) % c.len()]))
            .fold(f64::INFINITY, f64::min)
    };
    let raw: Vec<(usize, f64)> = nodes_in_box(t, lo - margin, hi + margin)
        .filter_map(|(k, p)| {
            let d = edge(p);
            let inside = if polygon_contains(c, p) { d } else { -d };
            (inside >= -margin).then_some((k, inside))
        })
        .collect();
    let deepest = raw.iter().map(|r| r.1).fold(t.cell * 0.5, f64::max);
    raw.into_iter()
        .map(|(k, inside)| {
            (
                k,
                FootprintNode {
                    part: WaterPart::Pool,
                    element: pool.controller,
                    inside,
                    half_width: deepest,
                    surface: pool.level,
                    bank_level: f64::NEG_INFINITY,
                    depth: pool.depth,
                    along: DVec2::ZERO,
                },
            )
        })
        .collect()
}

//! Land parcels by anisotropic conquest: thesis 3.3.1–3.3.4 ("Land Parcel Generation"). Each building seed `B_i`
//! gets a parcel `P_i` in three conquest steps on a grid of cells, then a simplified contour:
//!
//! 1. **Road conquest** (3.3.1). The source `S_i` is the projection of `B_i` on the closest road. The cells along
//!    the road corridor's edge, on the seed's side, are conquered from `S_i` in both directions along the road
//!    "until collision with a neighboring parcel or until a maximum distance from `S_i` is reached"
//!    ([`ParcelParams::road_reach`]). All seeds advance together, so two neighbours meet half-way; the cells
//!    round a dead end's cap are no road front, so a parcel does not follow its road round its end.
//! 2. **Corner conquest** (3.3.2). "We allow parcel `P_i` arrived first at a junction to annex its
//!    neighborhood": in each junction sector narrower than [`ParcelOptions::corner_angle_degrees`], the parcel
//!    whose road cells come nearest the corner annexes the sector's road cells on both roads within its depth
//!    (`c_max / ω_conquest`) of the corner, and at most half-way to the next junction. The corner lot then fronts
//!    both roads and its neighbours begin where its land ends, instead of meeting it along a diagonal with sharp
//!    angles. "Building seeds that lose access to roads are suppressed": a seed left with no road cell, or with
//!    less than half of its front, gets `None`.
//! 3. **Anisotropic land conquest** (3.3.3). Every road cell a parcel owns is a source with the fund
//!    `c_max` ([`ParcelParams::budget`]), and the parcel spreads until the cost from its source reaches `c_max`:
//!
//!    > dc_s(d_s, n) = Σ_{i=0}^{n−1} ω_i c_i(d_s, n)
//!
//!    * the *conquest cost* is the infinite-norm distance to the source in the frame of the road normal `n` and
//!      tangent `t` at the source. The thesis prints it as `|max(p·n, p·t)|`; the infinite norm it names is
//!      `max(|p·n|, |p·t|)`, which is what is used (a square around each source, so parcels come out almost
//!      quadrilateral). A tiny multiple of the Euclidean distance breaks its ties, so a cell goes to the source
//!      straight in front of it and neighbouring parcels part along the road normal. A source conquers only in
//!      front of itself (`p·n ≥ 0`): parcels grow away from their road;
//!    * *water, wall and road* cells cost `+∞`; so do cells outside `Ω` and road cells owned by another parcel;
//!    * the *slope cost* is quadratic in the directional gradients of the terrain along the conquest directions
//!      `n` and `t` of the source: each grid step adds `(∇h·n)²·|Δ·n| + (∇h·t)²·|Δ·t|` for its displacement
//!      `Δ`, which on a uniform slope sums to `(∇h·n)²·|p·n| + (∇h·t)²·|p·t|` whatever the path. Spreading along
//!      the main slope is expensive, along the contour lines free, so parcels grow along the contour lines.
//!      (Measured along each step instead, the squared rise would make a zig-zag climb cheaper than a straight
//!      one; measured along the line to the source, the infinite norm's indifference to lateral offsets would
//!      let cells pick far sources to halve their slope.)
//!
//!    Every parcel conquers its own neighbourhood (within `c_max / ω_conquest` of its road cells) on its own, in
//!    parallel; a cell claimed by several parcels goes to the lowest cost, exact ties to the source cell first
//!    in grid order (so that two facing rows part along a straight line). The result does not depend on the
//!    number of threads. Only the 4-connected component holding the parcel's source is kept; a mode filter
//!    trims one-cell spikes and fills unclaimed cells enclosed between parcels, and pinch points (two cells of
//!    one parcel touching at a corner only) and enclosed holes are resolved, so that every parcel is a simple
//!    polygon.
//! 4. **Parcel simplification** (3.3.4). The cell outlines of all parcels form one planar boundary graph; each
//!    chain between junctions (points where three or more parcels or the unclaimed land meet) is simplified once,
//!    so neighbours keep sharing their boundary exactly. Staircases are first straightened (Douglas–Peucker
//!    within [`ParcelOptions::straighten`] cells), then "we remove vertices that have little influence on the
//!    contour shape": a vertex whose edges turn by less than `ε` ([`ParcelOptions::merge_angle_degrees`]) goes,
//!    and so does a vertex of an edge shorter than [`ParcelOptions::short_edge`] cells (a clipped corner).
//!    Junctions are simplified by edge collapses, as in mesh simplification: a chain of a cell or so between two
//!    junctions collapses onto one of them, and — "we remove unplausible acute angles that appear at some
//!    T-vertices" — a junction where a parcel has an angle below [`ParcelOptions::acute_angle_degrees`] moves
//!    onto the neighbouring vertex that best opens it. No simplified edge may come within `road_width / 2` of a
//!    road's centre line or swallow a water, wall or out-of-`Ω` node, and simplified chains may not cross; a
//!    chain that breaks a rule is simplified less, down to its cell outline.
//!
//! The conquest grid has cells of side `cell` over the land's box (water, walls and `Ω` are read at the nearest
//! land node); it is allocated only over the neighbourhoods the seeds can reach.

use super::encyclopedia::ParcelParams;
use super::land::Land;
use super::{Parcel, Road};
use crate::error::{Error, Result};
use crate::geom::{
    closest_on_segment, polygon_contains, polygon_signed_area, segment_distance, segments_distance,
};
use crate::graph::{angle_between, Graph, SegmentIndex};
use glam::DVec2;
use rayon::prelude::*;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};
use std::f64::consts::{FRAC_1_SQRT_2, PI, TAU};

/// No parcel.
const NONE: u32 = u32::MAX;
/// Cell states of the conquest grid.
const FREE: u8 = 0;
const ROAD: u8 = 1;
const BLOCKED: u8 = 2;
/// Weight of the Euclidean distance that breaks ties of the infinite-norm conquest cost.
const TIE: f64 = 1e-3;
/// Largest number of cells of a conquest grid.
const MAX_CELLS: usize = 16_000_000;

/// A building seed asking for a parcel: its position and the conquest parameters of its (village, building) type.
#[derive(Clone, Copy, Debug)]
pub struct ParcelSeed<'a> {
    pub position: DVec2,
    pub params: &'a ParcelParams,
}

/// How parcel contours are simplified and corners resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParcelOptions {
    /// Largest distance (in cells) a straightened boundary may stray from the cell outline.
    pub straighten: f64,
    /// `ε` of 3.3.4: a vertex whose edges turn by less than this (degrees) is removed.
    pub merge_angle_degrees: f64,
    /// Largest distance (in cells) the removal of vertices may move a boundary away from the cell outline.
    pub merge_deviation: f64,
    /// An edge shorter than this (in cells) loses one of its vertices, within the same deviation.
    pub short_edge: f64,
    /// A parcel angle below this (degrees) at a junction of the boundary graph is opened by an edge collapse.
    pub acute_angle_degrees: f64,
    /// Junction sectors (between two consecutive roads) narrower than this (degrees) get a corner conquest.
    pub corner_angle_degrees: f64,
}

impl Default for ParcelOptions {
    fn default() -> Self {
        ParcelOptions {
            straighten: 1.5,
            merge_angle_degrees: 30.0,
            merge_deviation: 3.0,
            short_edge: 4.0,
            acute_angle_degrees: 30.0,
            corner_angle_degrees: 150.0,
        }
    }
}

/// One parcel per seed, or `None` for a seed that lost access to the roads (3.3.2: "building seeds that lose
/// access to roads are suppressed"), with the default [`ParcelOptions`].
///
/// `cell` is the side of the conquest grid's cells (metres): no coarser than the land's grid, so that no water,
/// wall or out-of-`Ω` node falls between two conquest nodes (1 m suits villages; 100 parcels on 1 km² take a
/// fraction of a second). The road corridor is every point within `road_width / 2` of a road's centre line;
/// parcels keep out of it, and of water, walls and the outside of `Ω`. Contours are counter-clockwise, simple,
/// pairwise disjoint, and neighbours share their common boundary vertex for vertex.
pub fn parcels(
    land: &Land,
    roads: &[Road],
    road_width: f64,
    seeds: &[ParcelSeed],
    cell: f64,
) -> Result<Vec<Option<Parcel>>> {
    parcels_with(
        land,
        roads,
        road_width,
        seeds,
        cell,
        &ParcelOptions::default(),
    )
}

/// [`parcels`] with explicit simplification and corner options.
pub fn parcels_with(
    land: &Land,
    roads: &[Road],
    road_width: f64,
    seeds: &[ParcelSeed],
    cell: f64,
    options: &ParcelOptions,
) -> Result<Vec<Option<Parcel>>> {
    validate(land, roads, road_width, seeds, cell, options)?;
    let n = seeds.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let half = 0.5 * road_width;
    let index = RoadIndex::new(roads, road_width.max(4.0 * cell));
    if index.is_empty() {
        return Ok(vec![None; n]);
    }
    let projections: Vec<Projection> = seeds.iter().map(|s| index.project(s.position)).collect();
    let Some(work) = Work::new(land, roads, &index, half, cell, seeds, &projections)? else {
        return Ok(vec![None; n]);
    };

    // 3.3.1 road conquest
    let sources: Vec<Option<usize>> = projections
        .iter()
        .map(|p| work.source_cell(&index, p, half))
        .collect();
    let mut road = road_conquest(&work, seeds, &sources);

    // 3.3.2 corner conquest
    let longest = seeds
        .iter()
        .map(|s| s.params.budget / s.params.conquest_weight + s.params.road_reach)
        .fold(0.0, f64::max);
    let junctions = junctions(
        roads,
        &work,
        half,
        longest + road_width + 4.0 * cell,
        options,
    );
    let frontage = |road: &RoadConquest| {
        let mut count = vec![0usize; n];
        for &o in &road.owner {
            if o != NONE {
                count[o as usize] += 1;
            }
        }
        count
    };
    let before = frontage(&road);
    corner_conquest(&work, seeds, &junctions, half, options, &mut road);
    // a seed left with less than half its road front by a corner lot has lost its access: what remains would
    // make a sliver of a parcel
    let after = frontage(&road);
    for o in road.owner.iter_mut() {
        if *o != NONE && 2 * after[*o as usize] < before[*o as usize] {
            *o = NONE;
        }
    }

    let mut fronts: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (k, &o) in road.owner.iter().enumerate() {
        if o != NONE {
            fronts[o as usize].push(k);
        }
    }
    // the parcel's anchor: its source cell, or the owned road cell nearest to it along the road
    let anchors: Vec<Option<usize>> = (0..n)
        .map(|i| match sources[i] {
            Some(s) if road.owner[s] == i as u32 => Some(s),
            _ => fronts[i]
                .iter()
                .copied()
                .min_by(|&a, &b| road.arrival[a].total_cmp(&road.arrival[b]).then(a.cmp(&b))),
        })
        .collect();

    // 3.3.3 anisotropic land conquest, each parcel on its own
    let claims: Vec<Vec<Claim>> = (0..n)
        .into_par_iter()
        .map(|i| {
            if anchors[i].is_none() {
                return Vec::new();
            }
            conquer(
                &work,
                land,
                &index,
                &road.owner,
                i as u32,
                &fronts[i],
                seeds[i].params,
            )
        })
        .collect();
    // a cell claimed by several parcels goes to the lowest cost; costs equal but for rounding (facing rows
    // meeting half-way on the lattice) go to the source first in grid order, so that such a boundary stays on one
    // side of the lattice line all along instead of zig-zagging with the seeds' order
    let mut best = vec![f64::INFINITY; work.len()];
    let mut from = vec![u32::MAX; work.len()];
    let mut label = vec![NONE; work.len()];
    for (i, cl) in claims.iter().enumerate() {
        for c in cl {
            let k = c.cell as usize;
            let tie = 1e-9 * (1.0 + c.cost.abs());
            if c.cost < best[k] - tie || (c.cost <= best[k] + tie && c.source < from[k]) {
                best[k] = c.cost;
                from[k] = c.source;
                label[k] = i as u32;
            }
        }
    }
    let is_anchor = {
        let mut a = vec![false; work.len()];
        for k in anchors.iter().flatten() {
            a[*k] = true;
        }
        a
    };
    clean_labels(
        &work,
        &road.owner,
        &anchors,
        &is_anchor,
        &mut label,
        &mut best,
    );

    // 3.3.4 simplification of the shared boundary graph
    let contours = simplified_contours(&work, &index, half, &label, n, options);
    Ok(contours
        .into_iter()
        .enumerate()
        .map(|(i, c)| {
            c.filter(|c| c.len() >= 3)
                .map(|contour| Parcel { seed: i, contour })
        })
        .collect())
}

fn finite(p: DVec2) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

fn validate(
    land: &Land,
    roads: &[Road],
    road_width: f64,
    seeds: &[ParcelSeed],
    cell: f64,
    options: &ParcelOptions,
) -> Result<()> {
    let bad = |what: String| Err(Error::InvalidInput(format!("parcels: {what}")));
    if !(cell.is_finite() && cell > 0.0) {
        return bad(format!("grid cell {cell} must be positive"));
    }
    if !(road_width.is_finite() && road_width >= 0.0) {
        return bad(format!("road width {road_width} must be zero or more"));
    }
    let g = &land.grid;
    let nodes = g.len();
    if g.nx < 2
        || g.ny < 2
        || [
            land.height.len(),
            land.inside.len(),
            land.water.len(),
            land.wall.len(),
        ]
        .iter()
        .any(|&l| l != nodes)
    {
        return bad("the land's maps do not match its grid".into());
    }
    for (r, road) in roads.iter().enumerate() {
        if road.points.iter().any(|p| !finite(*p)) {
            return bad(format!("road {r} has a point that is not finite"));
        }
    }
    for (i, s) in seeds.iter().enumerate() {
        let p = s.params;
        if !finite(s.position) {
            return bad(format!("seed {i} position is not finite"));
        }
        if !(p.budget.is_finite() && p.budget > 0.0) {
            return bad(format!("seed {i} budget {} must be positive", p.budget));
        }
        if !(p.road_reach.is_finite() && p.road_reach >= 0.0) {
            return bad(format!(
                "seed {i} road reach {} must be zero or more",
                p.road_reach
            ));
        }
        if !(p.conquest_weight.is_finite() && p.conquest_weight > 0.0) {
            return bad(format!(
                "seed {i} conquest weight {} must be positive",
                p.conquest_weight
            ));
        }
        if !(p.slope_weight.is_finite() && p.slope_weight >= 0.0) {
            return bad(format!(
                "seed {i} slope weight {} must be zero or more",
                p.slope_weight
            ));
        }
    }
    let o = options;
    for (name, v) in [
        ("straighten", o.straighten),
        ("merge_angle_degrees", o.merge_angle_degrees),
        ("merge_deviation", o.merge_deviation),
        ("acute_angle_degrees", o.acute_angle_degrees),
        ("corner_angle_degrees", o.corner_angle_degrees),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return bad(format!("option {name} = {v} must be zero or more"));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------------------------
// Roads as segments in buckets

/// The ends of roads that meet no other road (nor their own road elsewhere).
fn dead_ends(roads: &[Road], index: &RoadIndex, cell: f64) -> Vec<DVec2> {
    let mut ends = Vec::new();
    let mut near = Vec::new();
    let tol = 0.1 * cell;
    for r in roads.iter().filter(|r| r.points.len() >= 2) {
        let m = r.points.len();
        for (e, own) in [
            (r.points[0], (r.points[0], r.points[1])),
            (r.points[m - 1], (r.points[m - 2], r.points[m - 1])),
        ] {
            index.candidates(e - DVec2::splat(tol), e + DVec2::splat(tol), &mut near);
            let met = near.iter().any(|&s| {
                let (a, b) = index.segments()[s as usize];
                (a, b) != own && (b, a) != own && segment_distance(e, a, b) <= tol
            });
            if !met {
                ends.push(e);
            }
        }
    }
    ends
}

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
        let mut segments = Vec::new();
        for r in roads {
            match r.points.len() {
                0 => {}
                1 => segments.push((r.points[0], r.points[0])),
                _ => segments.extend(r.points.windows(2).map(|w| (w[0], w[1]))),
            }
        }
        RoadIndex {
            index: SegmentIndex::with_cell(segments, cell),
        }
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
        let mut c = Vec::new();
        let pad = DVec2::splat(limit);
        self.candidates(a.min(b) - pad, a.max(b) + pad, &mut c);
        let mut best = limit;
        for &s in &c {
            let (p, q) = self.segments()[s as usize];
            best = best.min(segments_distance(a, b, p, q));
        }
        best
    }
}

// ---------------------------------------------------------------------------------------------------------------
// The conquest grid

/// The part of the conquest grid where parcels may grow: node (i, j) at `origin + (i, j) * cell`, one cell
/// (a square of side `cell`) around each node.
struct Work {
    origin: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    state: Vec<u8>,
    /// Free cells beside the road corridor: where road conquest runs and parcels have their sources.
    edge: Vec<bool>,
}

const N4: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];
const N8: [(i64, i64); 8] = [
    (1, 0),
    (0, 1),
    (-1, 0),
    (0, -1),
    (1, 1),
    (-1, 1),
    (-1, -1),
    (1, -1),
];

impl Work {
    /// The grid over the neighbourhoods the seeds can reach, with the road corridor rasterized conservatively: a
    /// cell is road when any of its points may lie within `half` of a centre line.
    fn new(
        land: &Land,
        roads: &[Road],
        index: &RoadIndex,
        half: f64,
        cell: f64,
        seeds: &[ParcelSeed],
        projections: &[Projection],
    ) -> Result<Option<Work>> {
        let lg = &land.grid;
        let land_max = lg.point(lg.nx - 1, lg.ny - 1);
        let gx = ((land_max.x - lg.origin.x) / cell).floor() as i64 + 1;
        let gy = ((land_max.y - lg.origin.y) / cell).floor() as i64 + 1;
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for (s, p) in seeds.iter().zip(projections) {
            let reach = s.params.budget / s.params.conquest_weight;
            let r = s.params.road_reach + 2.0 * reach + half + 4.0 * cell;
            lo = lo.min(p.point - DVec2::splat(r));
            hi = hi.max(p.point + DVec2::splat(r));
        }
        let i0 = (((lo.x - lg.origin.x) / cell).floor() as i64).clamp(0, gx - 1);
        let j0 = (((lo.y - lg.origin.y) / cell).floor() as i64).clamp(0, gy - 1);
        let i1 = (((hi.x - lg.origin.x) / cell).ceil() as i64).clamp(0, gx - 1);
        let j1 = (((hi.y - lg.origin.y) / cell).ceil() as i64).clamp(0, gy - 1);
        if i1 <= i0 || j1 <= j0 {
            return Ok(None);
        }
        let (nx, ny) = ((i1 - i0 + 1) as usize, (j1 - j0 + 1) as usize);
        if nx.saturating_mul(ny) > MAX_CELLS {
            return Err(Error::InvalidInput(format!(
                "parcels: a conquest grid of {nx}x{ny} cells is too large; use a coarser cell than {cell} m or \
                 smaller budgets"
            )));
        }
        let origin = lg.origin + DVec2::new(i0 as f64, j0 as f64) * cell;
        let mut state: Vec<u8> = vec![FREE; nx * ny];
        state.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
            for (i, s) in row.iter_mut().enumerate() {
                let p = origin + DVec2::new(i as f64, j as f64) * cell;
                if !land.buildable(lg.nearest_clamped(p)) {
                    *s = BLOCKED;
                }
            }
        });
        let mut work = Work {
            origin,
            cell,
            nx,
            ny,
            state,
            edge: Vec::new(),
        };
        // a cell's points lie within half a diagonal of its node
        let margin = half + cell * FRAC_1_SQRT_2 * (1.0 + 1e-9);
        for &(a, b) in index.segments() {
            let (x0, y0) = work.clamped(a.min(b) - DVec2::splat(margin));
            let (x1, y1) = work.clamped(a.max(b) + DVec2::splat(margin));
            for j in y0..=y1 {
                for i in x0..=x1 {
                    if segment_distance(work.point(i, j), a, b) <= margin {
                        work.state[j * nx + i] = ROAD;
                    }
                }
            }
        }
        let mut edge = vec![false; nx * ny];
        for j in 0..ny {
            for i in 0..nx {
                let k = j * nx + i;
                edge[k] = work.state[k] == FREE
                    && N4
                        .iter()
                        .any(|&(di, dj)| work.at(i as i64 + di, j as i64 + dj) == Some(ROAD));
            }
        }
        // the cells round a dead end's cap are not a road front: a parcel does not follow the road round its end
        let ends = dead_ends(roads, index, cell);
        if !ends.is_empty() {
            for (k, e) in edge.iter_mut().enumerate() {
                if *e {
                    let foot = index.nearest(work.point_of(k), margin + 2.0 * cell);
                    if foot.is_some_and(|f| {
                        ends.iter()
                            .any(|q| q.distance(f.point) <= 1e-9 * (1.0 + q.abs().max_element()))
                    }) {
                        *e = false;
                    }
                }
            }
        }
        work.edge = edge;
        Ok(Some(work))
    }

    fn len(&self) -> usize {
        self.nx * self.ny
    }

    fn point(&self, i: usize, j: usize) -> DVec2 {
        self.origin + DVec2::new(i as f64, j as f64) * self.cell
    }

    fn point_of(&self, k: usize) -> DVec2 {
        self.point(k % self.nx, k / self.nx)
    }

    fn ij(&self, k: usize) -> (usize, usize) {
        (k % self.nx, k / self.nx)
    }

    fn inside(&self, i: i64, j: i64) -> Option<usize> {
        (i >= 0 && j >= 0 && (i as usize) < self.nx && (j as usize) < self.ny)
            .then(|| j as usize * self.nx + i as usize)
    }

    fn at(&self, i: i64, j: i64) -> Option<u8> {
        self.inside(i, j).map(|k| self.state[k])
    }

    /// The node (i, j) nearest to `p`, clamped onto the grid.
    fn clamped(&self, p: DVec2) -> (usize, usize) {
        let f = (p - self.origin) / self.cell;
        let c = |v: f64, n: usize| {
            if v.is_finite() {
                v.round().clamp(0.0, (n - 1) as f64) as usize
            } else if v > 0.0 {
                n - 1
            } else {
                0
            }
        };
        (c(f.x, self.nx), c(f.y, self.ny))
    }

    /// The cells within `r` of `p` (a box), as index ranges.
    fn around(&self, p: DVec2, r: f64) -> (usize, usize, usize, usize) {
        let (x0, y0) = self.clamped(p - DVec2::splat(r));
        let (x1, y1) = self.clamped(p + DVec2::splat(r));
        (x0, y0, x1, y1)
    }

    /// The road-edge cell where a seed enters its road: the closest to `S_i` on the seed's side of the road.
    fn source_cell(&self, index: &RoadIndex, p: &Projection, half: f64) -> Option<usize> {
        let (a, b) = index.segments()[p.segment];
        let dir = b - a;
        let (x0, y0, x1, y1) = self.around(p.point, half + 3.0 * self.cell);
        let mut best: Option<(f64, usize)> = None;
        for j in y0..=y1 {
            for i in x0..=x1 {
                let k = j * self.nx + i;
                if !self.edge[k] {
                    continue;
                }
                let q = self.point(i, j);
                if dir.length_squared() > 0.0 && dir.perp_dot(q - p.point) * p.side <= 0.0 {
                    continue;
                }
                let d = q.distance(p.point);
                // (a road point off the grid finds nothing, not the grid's border)
                if d <= half + 3.0 * self.cell && best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, k));
                }
            }
        }
        best.map(|(_, k)| k)
    }

    /// Whether parcel `seed` may not enter cell `k`: road, water, wall, outside `Ω`, or another parcel's road cell.
    fn closed_to(&self, owner: &[u32], seed: u32, k: usize) -> bool {
        self.state[k] != FREE || (self.edge[k] && owner[k] != NONE && owner[k] != seed)
    }
}

// ---------------------------------------------------------------------------------------------------------------
// 3.3.1 road conquest

struct RoadConquest {
    /// The parcel owning each road-edge cell.
    owner: Vec<u32>,
    /// Distance along the road edge from the owner's source (infinite for annexed cells).
    arrival: Vec<f64>,
}

/// All seeds advance from their sources along the road-edge cells at the same speed; a cell goes to the first
/// to arrive (ties to the lower seed index), and a seed stops at its road reach.
fn road_conquest(work: &Work, seeds: &[ParcelSeed], sources: &[Option<usize>]) -> RoadConquest {
    let mut owner = vec![NONE; work.len()];
    let mut arrival = vec![f64::INFINITY; work.len()];
    let mut heap = BinaryHeap::new();
    for (i, s) in sources.iter().enumerate() {
        if let Some(k) = s {
            heap.push(Reverse((0u64, i as u32, *k as u32)));
        }
    }
    while let Some(Reverse((bits, i, k))) = heap.pop() {
        let k = k as usize;
        if owner[k] != NONE {
            continue;
        }
        let d = f64::from_bits(bits);
        owner[k] = i;
        arrival[k] = d;
        let reach = seeds[i as usize].params.road_reach;
        let (ci, cj) = work.ij(k);
        for &(di, dj) in &N8 {
            let Some(nk) = work.inside(ci as i64 + di, cj as i64 + dj) else {
                continue;
            };
            if !work.edge[nk] || owner[nk] != NONE {
                continue;
            }
            let step = if di != 0 && dj != 0 {
                std::f64::consts::SQRT_2
            } else {
                1.0
            };
            let nd = d + step * work.cell;
            if nd <= reach + 1e-9 {
                // non-negative floats order as their bits
                heap.push(Reverse((nd.to_bits(), i, nk as u32)));
            }
        }
    }
    RoadConquest { owner, arrival }
}

// ---------------------------------------------------------------------------------------------------------------
// 3.3.2 corner conquest

/// A road leaving a junction: its centre line from the junction, and its direction near the junction.
struct Branch {
    points: Vec<DVec2>,
    dir: DVec2,
    /// Its length up to the next junction or dead end (or as far as it was followed).
    length: f64,
    /// Whether it was followed up to another junction.
    to_junction: bool,
}

/// A road junction (or a sharp bend where two roads meet) with its branches counter-clockwise.
struct Junction {
    point: DVec2,
    branches: Vec<Branch>,
}

/// The distance from `p` to a polyline, the arc length of the closest point, and the side of `p` (positive on the
/// left of the polyline's direction).
fn locate_on(p: DVec2, points: &[DVec2]) -> (f64, f64, f64) {
    let mut best = (f64::INFINITY, 0.0, 0.0);
    let mut arc = 0.0;
    for w in points.windows(2) {
        let q = closest_on_segment(p, w[0], w[1]);
        let d = q.distance(p);
        if d < best.0 {
            best = (d, arc + q.distance(w[0]), (w[1] - w[0]).perp_dot(p - q));
        }
        arc += w[0].distance(w[1]);
    }
    best
}

/// The counter-clockwise angle from `u` to `v`, in [0, 2π).
fn ccw_angle(u: DVec2, v: DVec2) -> f64 {
    let a = u.perp_dot(v).atan2(u.dot(v));
    if a < 0.0 {
        a + TAU
    } else {
        a
    }
}

/// The junctions of the road network (nodes of its planar graph where three roads or more meet, or two roads
/// meet at an angle below the corner angle) inside the conquest grid, with their branches followed for `length`.
fn junctions(
    roads: &[Road],
    work: &Work,
    half: f64,
    length: f64,
    options: &ParcelOptions,
) -> Vec<Junction> {
    let paths: Vec<&[DVec2]> = roads
        .iter()
        .filter(|r| r.points.len() >= 2)
        .map(|r| r.points.as_slice())
        .collect();
    let graph = Graph::from_paths(&paths, 0.1 * work.cell);
    let adj = graph.adjacency();
    let probe = 2.0 * half + 2.0 * work.cell;
    let lo = work.origin;
    let hi = work.point(work.nx - 1, work.ny - 1);
    let corner = options.corner_angle_degrees.to_radians();
    let mut out = Vec::new();
    for (v, nb) in adj.iter().enumerate() {
        let point = graph.nodes[v];
        if nb.len() < 2 || point.cmplt(lo).any() || point.cmpgt(hi).any() {
            continue;
        }
        let mut branches: Vec<Branch> = nb
            .iter()
            .map(|&first| {
                let mut points = vec![point, graph.nodes[first as usize]];
                let mut total = point.distance(points[1]);
                let (mut prev, mut cur) = (v as u32, first);
                while total < length && adj[cur as usize].len() == 2 {
                    let next = if adj[cur as usize][0] == prev {
                        adj[cur as usize][1]
                    } else {
                        adj[cur as usize][0]
                    };
                    if next as usize == v {
                        break;
                    }
                    let q = graph.nodes[next as usize];
                    total += q.distance(graph.nodes[cur as usize]);
                    points.push(q);
                    (prev, cur) = (cur, next);
                }
                // the direction at a short distance, past the corridor, where the road is what parcels see
                let mut arc = 0.0;
                let mut at = *points.last().unwrap_or(&point);
                for w in points.windows(2) {
                    let l = w[0].distance(w[1]);
                    if arc + l >= probe && l > 0.0 {
                        at = w[0] + (w[1] - w[0]) * ((probe - arc) / l);
                        break;
                    }
                    arc += l;
                }
                Branch {
                    dir: (at - point).normalize_or_zero(),
                    points,
                    length: total,
                    to_junction: adj[cur as usize].len() >= 3,
                }
            })
            .filter(|b| b.dir != DVec2::ZERO)
            .collect();
        if branches.len() < 2 {
            continue;
        }
        if branches.len() == 2 && angle_between(branches[0].dir, branches[1].dir) >= corner {
            continue;
        }
        branches.sort_by(|a, b| a.dir.y.atan2(a.dir.x).total_cmp(&b.dir.y.atan2(b.dir.x)));
        out.push(Junction { point, branches });
    }
    out
}

/// In each junction sector narrower than the corner angle, the parcel whose road cells come nearest the corner
/// (the first to arrive there) annexes the sector's road cells on both roads within its depth
/// (`c_max / ω_conquest`) of the corner: the corner lot then fronts both roads, and its neighbours on either road
/// begin where its land ends instead of meeting it along a diagonal.
fn corner_conquest(
    work: &Work,
    seeds: &[ParcelSeed],
    junctions: &[Junction],
    half: f64,
    options: &ParcelOptions,
    road: &mut RoadConquest,
) {
    let corner = options.corner_angle_degrees.to_radians();
    let c = work.cell;
    let depth_of = |seed: u32| {
        let p = seeds[seed as usize].params;
        p.budget / p.conquest_weight
    };
    let deepest = (0..seeds.len() as u32).map(depth_of).fold(0.0, f64::max);
    for jn in junctions {
        let m = jn.branches.len();
        for k in 0..m {
            let (b0, b1) = (&jn.branches[k], &jn.branches[(k + 1) % m]);
            let alpha = ccw_angle(b0.dir, b1.dir);
            if !(alpha >= 15f64.to_radians() && alpha < corner) {
                continue;
            }
            let bisector = (b0.dir + b1.dir).normalize_or_zero();
            if bisector == DVec2::ZERO {
                continue;
            }
            let corner_point = jn.point + bisector * ((half + c) / (0.5 * alpha).sin());
            // the corner's foot on either road, measured from the junction
            let start = (half + c) / (0.5 * alpha).tan();
            // a road cell of the sector: beside one of its two roads, on the sector's side (left of b0, right of
            // b1), with that road and its arc length from the junction along it
            let sector_cell = |p: DVec2| -> Option<(&Branch, f64)> {
                let (d0, arc0, side0) = locate_on(p, &b0.points);
                let (d1, arc1, side1) = locate_on(p, &b1.points);
                let (d, arc, ok, b) = if d0 <= d1 {
                    (d0, arc0, side0 > 0.0, b0)
                } else {
                    (d1, arc1, side1 < 0.0, b1)
                };
                (ok && d <= half + 2.0 * c).then_some((b, arc))
            };
            // whoever's road cells come nearest the corner arrived first
            let (x0, y0, x1, y1) = work.around(corner_point, deepest + half + 3.0 * c);
            let mut nearest: Option<(f64, usize)> = None;
            for j in y0..=y1 {
                for i in x0..=x1 {
                    let e = j * work.nx + i;
                    if !work.edge[e] || road.owner[e] == NONE {
                        continue;
                    }
                    let p = work.point(i, j);
                    let d = p.distance(corner_point);
                    if nearest.is_some_and(|(bd, _)| d >= bd) || sector_cell(p).is_none() {
                        continue;
                    }
                    nearest = Some((d, e));
                }
            }
            let Some((distance, corner_cell)) = nearest else {
                continue;
            };
            let winner = road.owner[corner_cell];
            let depth = depth_of(winner);
            if distance > depth + half + 2.0 * c {
                continue;
            }
            let (x0, y0, x1, y1) = work.around(jn.point, start + depth + half + 3.0 * c);
            for j in y0..=y1 {
                for i in x0..=x1 {
                    let e = j * work.nx + i;
                    if !work.edge[e] || road.owner[e] == winner {
                        continue;
                    }
                    // as far as its depth, and at most half-way to the next junction, whose own corner lot takes
                    // the other half
                    let within = |(b, arc): (&Branch, f64)| {
                        arc <= start + depth && (!b.to_junction || arc <= 0.5 * b.length)
                    };
                    if sector_cell(work.point(i, j)).is_some_and(within) {
                        road.owner[e] = winner;
                        road.arrival[e] = f64::INFINITY;
                    }
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------------------------
// 3.3.3 anisotropic land conquest

/// A cell conquered by a parcel: its cost and the road cell it was conquered from.
struct Claim {
    cell: u32,
    cost: f64,
    source: u32,
}

/// The cells one parcel conquers on its own from its road cells `fronts`, with their costs (at most `c_max`).
///
/// Each cell keeps the source it was reached from; its conquest cost is measured to that source in the source's
/// road frame, and the slope cost is summed along the steps that reached it (see the module documentation).
fn conquer(
    work: &Work,
    land: &Land,
    index: &RoadIndex,
    owner: &[u32],
    seed: u32,
    fronts: &[usize],
    params: &ParcelParams,
) -> Vec<Claim> {
    if fronts.is_empty() {
        return Vec::new();
    }
    let c = work.cell;
    let reach = params.budget / params.conquest_weight;
    // (an enormous fund reaches the whole grid, no farther)
    let r = (reach / c).ceil().min((work.nx + work.ny) as f64) as usize + 1;
    let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
    for &k in fronts {
        let (i, j) = work.ij(k);
        (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
    }
    let (i0, j0) = (i0.saturating_sub(r), j0.saturating_sub(r));
    let (i1, j1) = ((i1 + r).min(work.nx - 1), (j1 + r).min(work.ny - 1));
    let (lnx, lny) = (i1 - i0 + 1, j1 - j0 + 1);
    let global = |l: usize| (j0 + l / lnx) * work.nx + i0 + l % lnx;
    // the road frame (normal n away from the road) of every source
    let frames: Vec<(DVec2, DVec2)> = fronts
        .iter()
        .map(|&k| {
            let p = work.point_of(k);
            let n = (p - index.project(p).point).normalize_or_zero();
            // (a road cell lies beside its road, never on its centre line)
            let n = if n == DVec2::ZERO { DVec2::Y } else { n };
            (p, n)
        })
        .collect();
    // the terrain gradient on the window's cells (central differences)
    let gradients: Option<Vec<DVec2>> = (params.slope_weight > 0.0).then(|| {
        let h: Vec<f64> = (0..lnx * lny)
            .map(|l| land.height_at(work.point_of(global(l))))
            .collect();
        (0..lnx * lny)
            .map(|l| {
                let (i, j) = (l % lnx, l / lnx);
                let (a, b) = (i.saturating_sub(1), (i + 1).min(lnx - 1));
                let (e, f) = (j.saturating_sub(1), (j + 1).min(lny - 1));
                DVec2::new(
                    (h[j * lnx + b] - h[j * lnx + a]) / ((b - a).max(1) as f64 * c),
                    (h[f * lnx + i] - h[e * lnx + i]) / ((f - e).max(1) as f64 * c),
                )
            })
            .collect()
    });
    let mut cost = vec![f64::INFINITY; lnx * lny];
    let mut origin = vec![u32::MAX; lnx * lny];
    let mut slope = vec![0.0f64; lnx * lny];
    let mut heap = BinaryHeap::new();
    for (f, &k) in fronts.iter().enumerate() {
        let (i, j) = work.ij(k);
        let l = (j - j0) * lnx + (i - i0);
        cost[l] = 0.0;
        origin[l] = f as u32;
        heap.push(Reverse((0u64, l as u32)));
    }
    // each cell is conquered once, in order of cost: the cost to a source is not monotone along a path (the
    // ∞-norm distance can fall on a sideways step), and letting later, cheaper arrivals reopen conquered cells
    // made some windows re-spread over a thousand times
    let mut settled = vec![false; lnx * lny];
    while let Some(Reverse((bits, l))) = heap.pop() {
        let l = l as usize;
        if f64::from_bits(bits) > cost[l] || settled[l] {
            continue;
        }
        settled[l] = true;
        let (li, lj) = ((l % lnx) as i64, (l / lnx) as i64);
        let o = origin[l];
        let (so, n) = frames[o as usize];
        let t = n.perp();
        for &(di, dj) in &N8 {
            let (ni, nj) = (li + di, lj + dj);
            if ni < 0 || nj < 0 || ni >= lnx as i64 || nj >= lny as i64 {
                continue;
            }
            let nl = nj as usize * lnx + ni as usize;
            let k = global(nl);
            if work.closed_to(owner, seed, k) {
                continue;
            }
            if di != 0 && dj != 0 {
                // no slipping between two closed cells that touch at a corner (a diagonal wall)
                let a = global(lj as usize * lnx + ni as usize);
                let b = global(nj as usize * lnx + li as usize);
                if work.closed_to(owner, seed, a) && work.closed_to(owner, seed, b) {
                    continue;
                }
            }
            let d = work.point_of(k) - so;
            if d.dot(n) < -0.5 * c {
                // behind the source: across its road
                continue;
            }
            let conquest = d.dot(n).abs().max(d.dot(t).abs()) + TIE * d.length();
            let mut s = slope[l];
            if let Some(g) = &gradients {
                // the step's advance along n and along t, each at the squared directional gradient of the
                // terrain in that direction
                let step = DVec2::new(di as f64, dj as f64) * c;
                let slope_at = 0.5 * (g[l] + g[nl]);
                s += slope_at.dot(n).powi(2) * step.dot(n).abs()
                    + slope_at.dot(t).powi(2) * step.dot(t).abs();
            }
            let total = params.conquest_weight * conquest + params.slope_weight * s;
            if total <= params.budget && total < cost[nl] && !settled[nl] {
                cost[nl] = total;
                origin[nl] = o;
                slope[nl] = s;
                heap.push(Reverse((total.to_bits(), nl as u32)));
            }
        }
    }
    cost.iter()
        .enumerate()
        .filter(|(_, c)| c.is_finite())
        .map(|(l, &c)| Claim {
            cell: global(l) as u32,
            cost: c,
            source: fronts[origin[l] as usize] as u32,
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------------------------
// From claimed cells to simple regions

/// A mode filter on the claimed cells, up to twice: a cell most of whose eight neighbours (five or more) share another
/// label takes it, and an unclaimed cell enclosed on three sides or more by parcels joins the most frequent one.
/// Where many parcels compete (rough terrain), cost ties leave one-cell spikes and chains of unclaimed cells
/// between two parcels; every corner of those is a junction of the boundary graph, which no simplification may
/// remove. Road cells keep their owner, and closed cells stay out.
fn smooth_labels(
    work: &Work,
    owner: &[u32],
    is_anchor: &[bool],
    label: &mut [u32],
    best: &mut [f64],
) -> bool {
    let nx = work.nx;
    let mut any = false;
    for _ in 0..2 {
        let (old, old_best) = (label.to_vec(), best.to_vec());
        let lab = |i: i64, j: i64| work.inside(i, j).map_or(NONE, |k| old[k]);
        // every cell from the previous labels, in parallel
        let changes: Vec<(usize, u32, f64)> = (0..work.len())
            .into_par_iter()
            .filter_map(|k| {
                if is_anchor[k] || work.state[k] != FREE || (work.edge[k] && owner[k] != NONE) {
                    return None;
                }
                let (i, j) = ((k % nx) as i64, (k / nx) as i64);
                let mut counts: Vec<(u32, usize)> = Vec::with_capacity(8);
                for &(di, dj) in &N8 {
                    let l = lab(i + di, j + dj);
                    match counts.iter_mut().find(|c| c.0 == l) {
                        Some(c) => c.1 += 1,
                        None => counts.push((l, 1)),
                    }
                }
                // the most frequent label, ties to the lower one
                counts.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
                let (top, count) = counts[0];
                let target = if old[k] == NONE {
                    let parcels4 = N4
                        .iter()
                        .filter(|&&(di, dj)| lab(i + di, j + dj) != NONE)
                        .count();
                    match counts.iter().find(|c| c.0 != NONE).map(|c| c.0) {
                        Some(x) if parcels4 >= 3 && !work.closed_to(owner, x, k) => x,
                        _ => return None,
                    }
                } else if top != old[k]
                    && count >= 5
                    && (top == NONE || !work.closed_to(owner, top, k))
                {
                    top
                } else {
                    return None;
                };
                let cost = if target == NONE {
                    f64::INFINITY
                } else {
                    N8.iter()
                        .filter_map(|&(di, dj)| work.inside(i + di, j + dj))
                        .filter(|&m| old[m] == target)
                        .map(|m| old_best[m])
                        .fold(0.0, f64::max)
                };
                Some((k, target, cost))
            })
            .collect();
        if changes.is_empty() {
            break;
        }
        for (k, target, cost) in changes {
            label[k] = target;
            best[k] = cost;
        }
        any = true;
    }
    any
}

/// Keeps each parcel's 4-connected component that holds its anchor, smooths the labels (the first rounds), fills
/// pinch points and enclosed holes, until every parcel is one simply connected 4-connected region without cells
/// touching at a corner only.
fn clean_labels(
    work: &Work,
    owner: &[u32],
    anchors: &[Option<usize>],
    is_anchor: &[bool],
    label: &mut [u32],
    best: &mut [f64],
) {
    for round in 0..12 {
        keep_components(work, anchors, label, best);
        let smoothed = round < 3 && smooth_labels(work, owner, is_anchor, label, best);
        let pinched = fix_pinches(work, owner, is_anchor, label, best);
        let holed = fix_holes(work, owner, is_anchor, label, best, anchors.len());
        if !smoothed && !pinched && !holed {
            return;
        }
    }
    keep_components(work, anchors, label, best);
}

fn keep_components(work: &Work, anchors: &[Option<usize>], label: &mut [u32], best: &mut [f64]) {
    let mut keep = vec![false; work.len()];
    let mut queue = VecDeque::new();
    for (i, a) in anchors.iter().enumerate() {
        let Some(a) = *a else { continue };
        if label[a] != i as u32 {
            continue;
        }
        keep[a] = true;
        queue.push_back(a);
        while let Some(k) = queue.pop_front() {
            let (ci, cj) = work.ij(k);
            for &(di, dj) in &N4 {
                if let Some(nk) = work.inside(ci as i64 + di, cj as i64 + dj) {
                    if !keep[nk] && label[nk] == i as u32 {
                        keep[nk] = true;
                        queue.push_back(nk);
                    }
                }
            }
        }
    }
    for k in 0..work.len() {
        if label[k] != NONE && !keep[k] {
            label[k] = NONE;
            best[k] = f64::INFINITY;
        }
    }
}

/// Whether parcel `x` may take cell `k` that nobody holds.
fn fillable(work: &Work, owner: &[u32], label: &[u32], x: u32, k: usize) -> bool {
    label[k] == NONE && !work.closed_to(owner, x, k)
}

/// Two cells of one parcel touching at a corner only (the other two cells of the 2×2 block not in it) make its
/// outline touch itself: a free cell of the other diagonal joins the parcel, or else the costlier cell leaves it.
fn fix_pinches(
    work: &Work,
    owner: &[u32],
    is_anchor: &[bool],
    label: &mut [u32],
    best: &mut [f64],
) -> bool {
    let nx = work.nx;
    let mut any = false;
    for _ in 0..64 {
        let mut changed = false;
        for j in 0..work.ny.saturating_sub(1) {
            for i in 0..nx - 1 {
                let (a, b, c, d) = (
                    j * nx + i,
                    j * nx + i + 1,
                    (j + 1) * nx + i,
                    (j + 1) * nx + i + 1,
                );
                for (p, q, r, s) in [(a, d, b, c), (b, c, a, d)] {
                    let x = label[p];
                    if x == NONE || label[q] != x || label[r] == x || label[s] == x {
                        continue;
                    }
                    changed = true;
                    let fill = [r, s]
                        .into_iter()
                        .find(|&k| fillable(work, owner, label, x, k));
                    if let Some(k) = fill {
                        label[k] = x;
                        best[k] = best[p].max(best[q]);
                        continue;
                    }
                    // never the anchor; else the costlier
                    let drop = if is_anchor[p] || (!is_anchor[q] && (best[q], q) > (best[p], p)) {
                        q
                    } else {
                        p
                    };
                    label[drop] = NONE;
                    best[drop] = f64::INFINITY;
                }
            }
        }
        if !changed {
            break;
        }
        any = true;
    }
    any
}

/// A parcel enclosing cells that are not its own: free unclaimed cells join it; otherwise (water, a wall, another
/// parcel) the parcel is cut back to the cells cheaper than those touching the hole.
fn fix_holes(
    work: &Work,
    owner: &[u32],
    is_anchor: &[bool],
    label: &mut [u32],
    best: &mut [f64],
    n: usize,
) -> bool {
    let mut boxes = vec![(usize::MAX, usize::MAX, 0usize, 0usize); n];
    for (k, &x) in label.iter().enumerate() {
        if x != NONE {
            let (i, j) = work.ij(k);
            let b = &mut boxes[x as usize];
            *b = (b.0.min(i), b.1.min(j), b.2.max(i), b.3.max(j));
        }
    }
    let mut changed = false;
    for (x, &(bi0, bj0, bi1, bj1)) in boxes.iter().enumerate() {
        if bi0 == usize::MAX {
            continue;
        }
        let x = x as u32;
        // the box with a ring of one cell around it (possibly outside the grid, where nothing is)
        let (i0, j0) = (bi0 as i64 - 1, bj0 as i64 - 1);
        let (lnx, lny) = (bi1 - bi0 + 3, bj1 - bj0 + 3);
        let lab = |l: usize, label: &[u32]| {
            work.inside(i0 + (l % lnx) as i64, j0 + (l / lnx) as i64)
                .map_or(NONE, |k| label[k])
        };
        let mut outside = vec![false; lnx * lny];
        let mut queue = VecDeque::new();
        for (l, out) in outside.iter_mut().enumerate() {
            let (li, lj) = (l % lnx, l / lnx);
            if li == 0 || lj == 0 || li == lnx - 1 || lj == lny - 1 {
                *out = true;
                queue.push_back(l);
            }
        }
        let neighbours = |l: usize| {
            let (li, lj) = ((l % lnx) as i64, (l / lnx) as i64);
            N4.iter().filter_map(move |&(di, dj)| {
                let (a, b) = (li + di, lj + dj);
                (a >= 0 && b >= 0 && a < lnx as i64 && b < lny as i64)
                    .then(|| b as usize * lnx + a as usize)
            })
        };
        while let Some(l) = queue.pop_front() {
            for m in neighbours(l) {
                if !outside[m] && lab(m, label) != x {
                    outside[m] = true;
                    queue.push_back(m);
                }
            }
        }
        let mut seen = outside.clone();
        for start in 0..lnx * lny {
            if seen[start] || lab(start, label) == x {
                continue;
            }
            // one hole
            let mut hole = vec![start];
            seen[start] = true;
            let mut q = 0;
            while q < hole.len() {
                let l = hole[q];
                q += 1;
                for m in neighbours(l) {
                    if !seen[m] && lab(m, label) != x {
                        seen[m] = true;
                        hole.push(m);
                    }
                }
            }
            let global = |l: usize| {
                work.inside(i0 + (l % lnx) as i64, j0 + (l / lnx) as i64)
                    .unwrap_or(0)
            };
            if hole
                .iter()
                .all(|&l| fillable(work, owner, label, x, global(l)))
            {
                let rim = hole
                    .iter()
                    .flat_map(|&l| neighbours(l))
                    .filter(|&m| lab(m, label) == x)
                    .map(|m| best[global(m)])
                    .fold(0.0, f64::max);
                for &l in &hole {
                    label[global(l)] = x;
                    best[global(l)] = rim;
                }
                changed = true;
                continue;
            }
            let threshold = hole
                .iter()
                .flat_map(|&l| neighbours(l))
                .filter(|&m| lab(m, label) == x)
                .map(|m| best[global(m)])
                .fold(f64::INFINITY, f64::min);
            if !(threshold > 0.0 && threshold.is_finite()) {
                // the hole touches the parcel's own road cells: its outline is kept around it
                continue;
            }
            for j in bj0..=bj1 {
                for i in bi0..=bi1 {
                    let k = j * work.nx + i;
                    if label[k] == x && best[k] >= threshold && !is_anchor[k] {
                        label[k] = NONE;
                        best[k] = f64::INFINITY;
                        changed = true;
                    }
                }
            }
            // the parcel changed: its other holes are looked at again in the next round
            break;
        }
    }
    changed
}

// ---------------------------------------------------------------------------------------------------------------
// 3.3.4 the boundary graph and its simplification

/// The lattice of cell corners: vertex (I, J) is the lower-left corner of cell (I, J). Directions at a vertex
/// count counter-clockwise: 0 east, 1 north, 2 west, 3 south.
struct Lattice<'a> {
    work: &'a Work,
    label: &'a [u32],
    vx: usize,
}

impl<'a> Lattice<'a> {
    fn new(work: &'a Work, label: &'a [u32]) -> Self {
        Lattice {
            work,
            label,
            vx: work.nx + 1,
        }
    }

    fn lab(&self, i: i64, j: i64) -> u32 {
        self.work.inside(i, j).map_or(NONE, |k| self.label[k])
    }

    fn vij(&self, v: u32) -> (i64, i64) {
        ((v as usize % self.vx) as i64, (v as usize / self.vx) as i64)
    }

    fn vid(&self, i: i64, j: i64) -> u32 {
        (j as usize * self.vx + i as usize) as u32
    }

    fn pos(&self, v: u32) -> DVec2 {
        let (i, j) = self.vij(v);
        self.work.origin + DVec2::new(i as f64 - 0.5, j as f64 - 0.5) * self.work.cell
    }

    /// The label of the cell in the quadrant counter-clockwise after direction `d`.
    fn quadrant(&self, v: u32, d: u8) -> u32 {
        let (i, j) = self.vij(v);
        match d {
            0 => self.lab(i, j),
            1 => self.lab(i - 1, j),
            2 => self.lab(i - 1, j - 1),
            _ => self.lab(i, j - 1),
        }
    }

    /// Whether a boundary edge leaves `v` in direction `d` (the cells on its two sides differ).
    fn has(&self, v: u32, d: u8) -> bool {
        self.quadrant(v, d) != self.quadrant(v, (d + 3) % 4)
    }

    fn degree(&self, v: u32) -> usize {
        (0..4).filter(|&d| self.has(v, d)).count()
    }

    fn step(&self, v: u32, d: u8) -> u32 {
        let (i, j) = self.vij(v);
        match d {
            0 => self.vid(i + 1, j),
            1 => self.vid(i, j + 1),
            2 => self.vid(i - 1, j),
            _ => self.vid(i, j - 1),
        }
    }

    fn edge_id(&self, v: u32, d: u8) -> usize {
        let (i, j) = self.vij(v);
        match d {
            0 => 2 * self.vid(i, j) as usize,
            1 => 2 * self.vid(i, j) as usize + 1,
            2 => 2 * self.vid(i - 1, j) as usize,
            _ => 2 * self.vid(i, j - 1) as usize + 1,
        }
    }
}

/// A maximal boundary path between junctions (or a closed loop without one).
struct Chain {
    ids: Vec<u32>,
    /// A loop without junction: `ids` ends where it starts and no vertex is fixed.
    closed: bool,
    /// Direction of the first edge from `ids[0]`, and of the last edge seen from the end vertex.
    first_dir: u8,
    last_dir: u8,
    /// The labels on its two sides.
    labels: [u32; 2],
}

impl Chain {
    fn is_loop(&self) -> bool {
        self.ids.first() == self.ids.last()
    }
}

/// All chains of the boundary graph, and each parcel's outline as lattice vertices (counter-clockwise).
fn trace(lat: &Lattice, n: usize) -> (Vec<Chain>, Vec<Vec<u32>>) {
    let work = lat.work;
    // the box of labelled cells
    let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
    let mut first = vec![usize::MAX; n];
    let mut cells = vec![0usize; n];
    for (k, &x) in lat.label.iter().enumerate() {
        if x != NONE {
            let (i, j) = work.ij(k);
            (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
            first[x as usize] = first[x as usize].min(k);
            cells[x as usize] += 1;
        }
    }
    if i0 == usize::MAX {
        return (Vec::new(), vec![Vec::new(); n]);
    }
    let mut visited = vec![false; 2 * lat.vx * (work.ny + 1)];
    let mut chains = Vec::new();
    let walk = |v: u32, d: u8, visited: &mut Vec<bool>| -> Chain {
        let mut ids = vec![v];
        let (mut cur, mut dir) = (v, d);
        loop {
            visited[lat.edge_id(cur, dir)] = true;
            let next = lat.step(cur, dir);
            ids.push(next);
            if next == v || lat.degree(next) != 2 {
                break;
            }
            let back = (dir + 2) % 4;
            dir = (0..4)
                .find(|&e| e != back && lat.has(next, e))
                .unwrap_or(back);
            cur = next;
        }
        let closed = lat.degree(v) == 2;
        Chain {
            labels: [lat.quadrant(v, d), lat.quadrant(v, (d + 3) % 4)],
            ids,
            closed,
            first_dir: d,
            last_dir: (dir + 2) % 4,
        }
    };
    let vertices =
        |pass: u8| (j0..=j1 + 1).flat_map(move |j| (i0..=i1 + 1).map(move |i| (pass, i, j)));
    for (pass, i, j) in vertices(0).chain(vertices(1)) {
        let v = lat.vid(i as i64, j as i64);
        let deg = lat.degree(v);
        // junctions first, then loops without junction
        if (pass == 0 && deg < 3) || (pass == 1 && deg != 2) {
            continue;
        }
        for d in 0..4u8 {
            if lat.has(v, d) && !visited[lat.edge_id(v, d)] {
                chains.push(walk(v, d, &mut visited));
            }
        }
    }
    // each parcel's outline, keeping the parcel on the left
    let loops = (0..n)
        .map(|x| {
            if first[x] == usize::MAX {
                return Vec::new();
            }
            let (ci, cj) = work.ij(first[x]);
            let start = lat.vid(ci as i64, cj as i64);
            let (mut v, mut d) = (start, 0u8);
            let mut out = Vec::new();
            let limit = 4 * cells[x] + 8;
            loop {
                out.push(v);
                v = lat.step(v, d);
                d = if lat.quadrant(v, d) != x as u32 {
                    (d + 1) % 4
                } else if lat.quadrant(v, (d + 3) % 4) == x as u32 {
                    (d + 3) % 4
                } else {
                    d
                };
                if (v == start && d == 0) || out.len() > limit {
                    break;
                }
            }
            out
        })
        .collect();
    (chains, loops)
}

/// What a simplified boundary may not come near.
struct Rules<'a> {
    work: &'a Work,
    index: &'a RoadIndex,
    half: f64,
}

impl Rules<'_> {
    /// Whether the edge `a`–`b` keeps `road_width / 2` from every centre line and half a cell from every
    /// water, wall or out-of-`Ω` node (as the cell outlines do).
    fn clear(&self, a: DVec2, b: DVec2) -> bool {
        let c = self.work.cell;
        if self.half > 0.0
            && self.index.segment_clearance(a, b, self.half) < self.half * (1.0 - 1e-9)
        {
            return false;
        }
        let r = 0.5 * c * (1.0 - 1e-9);
        let (x0, y0) = self.work.clamped(a.min(b) - DVec2::splat(c));
        let (x1, y1) = self.work.clamped(a.max(b) + DVec2::splat(c));
        for j in y0..=y1 {
            for i in x0..=x1 {
                if self.work.state[j * self.work.nx + i] == BLOCKED
                    && segment_distance(self.work.point(i, j), a, b) < r
                {
                    return false;
                }
            }
        }
        true
    }

    /// Whether the edge from the first to the last of `span` (a stretch of a cell outline, in order) may replace
    /// the stretch: it keeps `road_width / 2` from every centre line, and no water, wall or out-of-`Ω` node lies
    /// between the two (the parcel would swallow it). Along a diagonal wall or shore, whose nodes make a
    /// staircase, no straight edge passes this, and the outline keeps its steps.
    fn replaces(&self, span: &[DVec2]) -> bool {
        let (Some(&a), Some(&b)) = (span.first(), span.last()) else {
            return true;
        };
        let c = self.work.cell;
        if self.half > 0.0
            && self.index.segment_clearance(a, b, self.half) < self.half * (1.0 - 1e-9)
        {
            return false;
        }
        // the region between the stretch and the edge lies within the stretch's largest deviation of the edge
        let reach = span
            .iter()
            .map(|p| segment_distance(*p, a, b))
            .fold(0.0, f64::max)
            + 1e-6 * c;
        let (x0, y0) = self.work.clamped(a.min(b) - DVec2::splat(reach));
        let (x1, y1) = self.work.clamped(a.max(b) + DVec2::splat(reach));
        for j in y0..=y1 {
            for i in x0..=x1 {
                // road nodes are rasterized with a margin: the exact distance to the centre lines rules there
                if self.work.state[j * self.work.nx + i] != BLOCKED {
                    continue;
                }
                let q = self.work.point(i, j);
                let d = segment_distance(q, a, b);
                if d > reach {
                    continue;
                }
                if d <= 1e-6 * c || polygon_contains(span, q) {
                    return false;
                }
            }
        }
        true
    }
}

/// Douglas–Peucker between `s` and `e`: a span becomes one edge when every vertex lies within `tol` of it and the
/// edge is clear.
fn douglas_peucker(pts: &[DVec2], s: usize, e: usize, tol: f64, rules: &Rules, keep: &mut [bool]) {
    let mut stack = vec![(s, e)];
    while let Some((s, e)) = stack.pop() {
        if e <= s + 1 {
            continue;
        }
        let (mut far, mut dmax) = (s + 1, -1.0);
        for (q, p) in pts.iter().enumerate().take(e).skip(s + 1) {
            let d = segment_distance(*p, pts[s], pts[e]);
            if d > dmax {
                (far, dmax) = (q, d);
            }
        }
        if dmax <= tol && rules.replaces(&pts[s..=e]) {
            continue;
        }
        keep[far] = true;
        stack.push((s, far));
        stack.push((far, e));
    }
}

/// Kept vertices with a score, as (score, index into the kept list).
type ScoredVertices = Vec<(f64, usize)>;

/// The vertices of a chain (indices into `ids`) kept at simplification level `level`: 0 the full simplification,
/// 1 half of it, 2 the cell outline (only its corners).
fn simplify_chain(
    ch: &Chain,
    lat: &Lattice,
    rules: &Rules,
    options: &ParcelOptions,
    level: u8,
) -> Vec<usize> {
    let m = ch.ids.len();
    let pts: Vec<DVec2> = ch.ids.iter().map(|&v| lat.pos(v)).collect();
    // a closed loop is cyclic over 0..m-1 (its last vertex repeats the first)
    let cyc = if ch.closed { m - 1 } else { m };
    let mut keep = vec![false; m];
    if !ch.closed {
        keep[0] = true;
        keep[m - 1] = true;
    }
    if level >= 2 {
        for (q, k) in keep.iter_mut().enumerate().take(cyc) {
            if !ch.closed && (q == 0 || q == m - 1) {
                continue;
            }
            let prev = if q == 0 { m - 2 } else { q - 1 };
            let (a, b, c) = (
                lat.vij(ch.ids[prev]),
                lat.vij(ch.ids[q]),
                lat.vij(ch.ids[q + 1]),
            );
            if (b.0 - a.0, b.1 - a.1) != (c.0 - b.0, c.1 - b.1) {
                *k = true;
            }
        }
        return (0..cyc).filter(|&q| keep[q]).collect();
    }
    let scale = 0.5f64.powi(level as i32);
    let c = rules.work.cell;
    let tol = options.straighten * c * scale;
    if ch.is_loop() {
        let far = (1..m - 1)
            .max_by(|&a, &b| {
                pts[a]
                    .distance(pts[0])
                    .total_cmp(&pts[b].distance(pts[0]))
                    .then(b.cmp(&a))
            })
            .unwrap_or(0);
        keep[0] = true;
        keep[far] = true;
        douglas_peucker(&pts, 0, far, tol, rules, &mut keep);
        douglas_peucker(&pts, far, m - 1, tol, rules, &mut keep);
        if (0..m - 1).filter(|&q| keep[q]).count() < 3 {
            let third = (1..m - 1).filter(|&q| q != far).max_by(|&a, &b| {
                segment_distance(pts[a], pts[0], pts[far])
                    .total_cmp(&segment_distance(pts[b], pts[0], pts[far]))
                    .then(b.cmp(&a))
            });
            if let Some(t) = third {
                keep[t] = true;
            }
        }
    } else {
        douglas_peucker(&pts, 0, m - 1, tol, rules, &mut keep);
    }
    let mut kept: Vec<usize> = (0..cyc).filter(|&q| keep[q]).collect();
    let max_dev = options.merge_deviation * c * scale;
    // removes, one at a time, the removable vertex with the smallest score among `candidates` (score, index into
    // `kept`), until none is left or the chain is as short as it may be
    let mut remove_while = |candidates: &dyn Fn(&[usize]) -> ScoredVertices| loop {
        let km = kept.len();
        if (ch.closed && km <= 3) || (!ch.closed && km <= 2) {
            break;
        }
        let mut found = candidates(&kept);
        found.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        match found
            .into_iter()
            .find(|&(_, q)| removable(&kept, q, &pts, cyc, max_dev, rules))
        {
            Some((_, q)) => {
                kept.remove(q);
            }
            None => break,
        }
    };
    // the vertices where the contour turns by less than ε
    let eps = options.merge_angle_degrees.to_radians() * scale;
    remove_while(&|kept: &[usize]| {
        let km = kept.len();
        let range = if ch.closed { 0..km } else { 1..km - 1 };
        range
            .map(|q| {
                let (p, x, nx) = (kept[(q + km - 1) % km], kept[q], kept[(q + 1) % km]);
                (angle_between(pts[x] - pts[p], pts[nx] - pts[x]), q)
            })
            .filter(|&(turn, _)| turn < eps)
            .collect()
    });
    // then a vertex of an edge shorter than `short_edge` cells (a clipped corner, a one-cell jog): it has as
    // little influence on the shape as a flat one
    let short = options.short_edge * c * scale;
    remove_while(&|kept: &[usize]| {
        let km = kept.len();
        let interior = |q: usize| ch.closed || (q > 0 && q < km - 1);
        (0..if ch.closed { km } else { km - 1 })
            .map(|q| (pts[kept[q]].distance(pts[kept[(q + 1) % km]]), q))
            .filter(|&(len, _)| len < short)
            .flat_map(|(len, q)| [(len, q), (len, (q + 1) % km)])
            .filter(|&(_, q)| interior(q))
            .collect()
    });
    kept
}

/// Whether kept vertex `q` may go: the outline between its neighbours stays within `max_dev` of the new edge,
/// which [`Rules::replaces`] the outline.
fn removable(
    kept: &[usize],
    q: usize,
    pts: &[DVec2],
    cyc: usize,
    max_dev: f64,
    rules: &Rules,
) -> bool {
    let km = kept.len();
    let (p, nx) = (kept[(q + km - 1) % km], kept[(q + 1) % km]);
    let mut span = vec![pts[p]];
    let mut r = (p + 1) % cyc;
    while r != nx {
        if segment_distance(pts[r], pts[p], pts[nx]) > max_dev {
            return false;
        }
        span.push(pts[r]);
        r = (r + 1) % cyc;
    }
    span.push(pts[nx]);
    rules.replaces(&span)
}

/// Where each junction vertex has moved to by an edge collapse.
type Moves = std::collections::HashMap<u32, u32>;

fn position(lat: &Lattice, moved: &Moves, v: u32) -> DVec2 {
    lat.pos(*moved.get(&v).unwrap_or(&v))
}

/// Edge collapses at the junctions of the boundary graph, as in mesh simplification. A chain between two
/// junctions no longer than the straightening tolerance collapses onto one of its ends, unless that makes an
/// acute angle. Then the second step of 3.3.4: at a junction where a parcel has an acute angle, the junction
/// moves onto the next vertex of one of its chains when that opens the smallest parcel angle there.
fn collapse_junctions(
    lat: &Lattice,
    chains: &[Chain],
    kept: &[Vec<usize>],
    levels: &[u8],
    rules: &Rules,
    options: &ParcelOptions,
) -> Moves {
    let acute = options.acute_angle_degrees.to_radians();
    let mut moved = Moves::new();
    // (vertex, direction, chain, at its start)
    let mut ends: Vec<(u32, u8, usize, bool)> = Vec::new();
    for (c, ch) in chains.iter().enumerate() {
        if ch.closed {
            continue;
        }
        ends.push((ch.ids[0], ch.first_dir, c, true));
        ends.push((ch.ids[ch.ids.len() - 1], ch.last_dir, c, false));
    }
    ends.sort_unstable();
    let mut used = vec![false; chains.len()];
    // the next kept vertex along a chain from one end, whether it is the far end, and the one after it
    let next = |c: usize, at_start: bool| -> (u32, bool, Option<u32>) {
        let ids = &chains[c].ids;
        let k = &kept[c];
        let len = k.len();
        if at_start {
            (ids[k[1]], len == 2, (len >= 3).then(|| ids[k[2]]))
        } else {
            (
                ids[k[len - 2]],
                len == 2,
                (len >= 3).then(|| ids[k[len - 3]]),
            )
        }
    };
    // first, a chain no longer than the straightening tolerance between two junctions collapses to one of them
    // (an edge collapse): a jog of a cell or so between two junctions is the grid's noise
    let short = options.straighten * lat.work.cell;
    let group_of = |v: u32| -> &[(u32, u8, usize, bool)] {
        let lo = ends.partition_point(|e| e.0 < v);
        let hi = ends.partition_point(|e| e.0 <= v);
        &ends[lo..hi]
    };
    // the smallest angle between the edges from `centre` to `targets`, whatever lies between them
    let tightest = |centre: DVec2, targets: &[DVec2]| -> Option<f64> {
        if targets
            .iter()
            .any(|t| (*t - centre).length_squared() == 0.0)
        {
            return None;
        }
        let mut a: Vec<f64> = targets
            .iter()
            .map(|t| (t.y - centre.y).atan2(t.x - centre.x))
            .collect();
        a.sort_by(f64::total_cmp);
        let g = a.len();
        Some(
            (0..g)
                .map(|q| {
                    if q + 1 < g {
                        a[q + 1] - a[q]
                    } else {
                        a[0] + TAU - a[q]
                    }
                })
                .fold(TAU, f64::min),
        )
    };
    let mut touched = std::collections::HashSet::new();
    for (ci, ch) in chains.iter().enumerate() {
        if ch.closed || ch.is_loop() || levels[ci] != 0 || kept[ci].len() != 2 {
            continue;
        }
        let (v1, v2) = (ch.ids[0], ch.ids[ch.ids.len() - 1]);
        if touched.contains(&v1)
            || touched.contains(&v2)
            || lat.pos(v1).distance(lat.pos(v2)) > short
        {
            continue;
        }
        let (g1, g2) = (group_of(v1), group_of(v2));
        if g1
            .iter()
            .chain(g2)
            .any(|e| levels[e.2] != 0 || kept[e.2].len() < 2 || chains[e.2].is_loop())
        {
            continue;
        }
        let heads = |g: &[(u32, u8, usize, bool)]| -> Vec<DVec2> {
            g.iter()
                .filter(|e| e.2 != ci)
                .map(|e| position(lat, &moved, next(e.2, e.3).0))
                .collect()
        };
        let (h1, h2) = (heads(g1), heads(g2));
        let (p1, p2) = (lat.pos(v1), lat.pos(v2));
        let before = [
            tightest(p1, &[h1.clone(), vec![p2]].concat()),
            tightest(p2, &[h2.clone(), vec![p1]].concat()),
        ];
        let [Some(b1), Some(b2)] = before else {
            continue;
        };
        let others = [h1, h2].concat();
        let mut best: Option<(f64, u32, u32)> = None;
        for (from, to) in [(v1, v2), (v2, v1)] {
            let centre = lat.pos(to);
            if !others.iter().all(|t| rules.clear(centre, *t)) {
                continue;
            }
            if let Some(a) = tightest(centre, &others) {
                if best.is_none_or(|(b, _, _)| a > b) {
                    best = Some((a, from, to));
                }
            }
        }
        // no new acute angle (nor a tighter one where there was one)
        if let Some((a, from, to)) = best {
            if a >= b1.min(b2).min(acute) {
                moved.insert(from, to);
                used[ci] = true;
                touched.insert(v1);
                touched.insert(v2);
            }
        }
    }
    let mut g0 = 0;
    while g0 < ends.len() {
        let v = ends[g0].0;
        let mut g1 = g0;
        while g1 < ends.len() && ends[g1].0 == v {
            g1 += 1;
        }
        let group = &ends[g0..g1];
        g0 = g1;
        if group.len() < 3
            || touched.contains(&v)
            || group
                .iter()
                .any(|e| levels[e.2] != 0 || kept[e.2].len() < 2)
        {
            continue;
        }
        let faces: Vec<u32> = group.iter().map(|e| lat.quadrant(v, e.1)).collect();
        // the smallest parcel angle around `centre` with the chains heading to `targets`
        let smallest = |centre: DVec2, targets: &[DVec2]| -> Option<f64> {
            let dirs: Vec<DVec2> = targets.iter().map(|t| *t - centre).collect();
            if dirs.iter().any(|d| d.length_squared() == 0.0) {
                return None;
            }
            let g = dirs.len();
            let angles: Vec<f64> = (0..g)
                .map(|q| ccw_angle(dirs[q], dirs[(q + 1) % g]))
                .collect();
            if (angles.iter().sum::<f64>() - TAU).abs() > 1e-6 {
                return None;
            }
            Some(
                (0..g)
                    .filter(|&q| faces[q] != NONE)
                    .map(|q| angles[q])
                    .fold(PI * 2.0, f64::min),
            )
        };
        let heads: Vec<(u32, bool, Option<u32>)> = group.iter().map(|e| next(e.2, e.3)).collect();
        let targets: Vec<DVec2> = heads.iter().map(|h| position(lat, &moved, h.0)).collect();
        let Some(old) = smallest(position(lat, &moved, v), &targets) else {
            continue;
        };
        if old >= acute {
            continue;
        }
        let mut best: Option<(f64, usize)> = None;
        for (q, e) in group.iter().enumerate() {
            let (w, is_end, after) = heads[q];
            if is_end || used[e.2] || chains[e.2].is_loop() {
                continue;
            }
            let Some(after) = after else { continue };
            let centre = lat.pos(w);
            let mut t = targets.clone();
            t[q] = position(lat, &moved, after);
            let clear = (0..group.len())
                .filter(|&r| r != q)
                .all(|r| rules.clear(centre, targets[r]));
            if !clear {
                continue;
            }
            if let Some(a) = smallest(centre, &t) {
                if best.is_none_or(|(b, _)| a > b) {
                    best = Some((a, q));
                }
            }
        }
        if let Some((a, q)) = best {
            if a > old + 1e-6 {
                moved.insert(v, heads[q].0);
                used[group[q].2] = true;
            }
        }
    }
    moved
}

/// Whether two segments share any point other than one common endpoint.
fn conflict(a: DVec2, b: DVec2, c: DVec2, d: DVec2, eps: f64) -> bool {
    let (r, s) = (b - a, d - c);
    let (lr, ls) = (r.length(), s.length());
    let same = |p: DVec2, q: DVec2| p.distance(q) <= eps;
    let common = same(a, c) || same(a, d) || same(b, c) || same(b, d);
    let denom = r.perp_dot(s);
    if denom.abs() > 1e-9 * lr * ls {
        let q = c - a;
        let (t, u) = (q.perp_dot(s) / denom, q.perp_dot(r) / denom);
        let (et, eu) = (eps / lr, eps / ls);
        if t < -et || t > 1.0 + et || u < -eu || u > 1.0 + eu {
            return false;
        }
        let p = a + r * t;
        let at_ends = (same(p, a) || same(p, b)) && (same(p, c) || same(p, d));
        return !(at_ends && common);
    }
    if segment_distance(c, a, b) > eps
        && segment_distance(d, a, b) > eps
        && segment_distance(a, c, d) > eps
        && segment_distance(b, c, d) > eps
    {
        return false;
    }
    let dir = r / lr;
    let (u0, u1) = {
        let (x, y) = ((c - a).dot(dir), (d - a).dot(dir));
        (x.min(y), x.max(y))
    };
    if lr.min(u1) - u0.max(0.0) > eps {
        return true;
    }
    !common
}

/// The chains that cross or touch another chain (or themselves) anywhere but at a shared end.
fn crossing_chains(segments: &[(DVec2, DVec2, usize)], eps: f64, bad: &mut [bool]) {
    let index = SegmentIndex::new(segments.iter().map(|&(a, b, _)| (a, b)).collect());
    let mut near = Vec::new();
    for (s, &(a, b, cs)) in segments.iter().enumerate() {
        index.candidates(
            a.min(b) - DVec2::splat(eps),
            a.max(b) + DVec2::splat(eps),
            &mut near,
        );
        for &t in near.iter().filter(|&&t| t as usize > s) {
            let (c, d, ct) = segments[t as usize];
            if conflict(a, b, c, d, eps) {
                bad[cs] = true;
                bad[ct] = true;
            }
        }
    }
}

/// Every parcel's simplified contour (counter-clockwise), from the one boundary graph of all parcels.
fn simplified_contours(
    work: &Work,
    index: &RoadIndex,
    half: f64,
    label: &[u32],
    n: usize,
    options: &ParcelOptions,
) -> Vec<Option<Vec<DVec2>>> {
    let lat = Lattice::new(work, label);
    let (chains, loops) = trace(&lat, n);
    let rules = Rules { work, index, half };
    let c = work.cell;
    let eps = 1e-6 * c;
    let mut cells = vec![0usize; n];
    for &x in label {
        if x != NONE {
            cells[x as usize] += 1;
        }
    }
    let mut levels = vec![0u8; chains.len()];
    let mut flag = vec![false; lat.vx * (work.ny + 1)];
    let mut polygons: Vec<Option<Vec<DVec2>>> = vec![None; n];
    for round in 0.. {
        let kept: Vec<Vec<usize>> = chains
            .par_iter()
            .zip(levels.par_iter())
            .map(|(ch, &level)| simplify_chain(ch, &lat, &rules, options, level))
            .collect();
        let moved = collapse_junctions(&lat, &chains, &kept, &levels, &rules, options);
        for (ch, k) in chains.iter().zip(&kept) {
            for &v in &ch.ids {
                flag[v as usize] = false;
            }
            for &q in k {
                flag[ch.ids[q] as usize] = true;
            }
        }
        polygons = loops
            .iter()
            .map(|lp| {
                if lp.is_empty() {
                    return None;
                }
                let mut poly: Vec<DVec2> = Vec::new();
                for &v in lp {
                    if flag[v as usize] {
                        let p = position(&lat, &moved, v);
                        if poly.last() != Some(&p) {
                            poly.push(p);
                        }
                    }
                }
                while poly.len() > 1 && poly.first() == poly.last() {
                    poly.pop();
                }
                Some(poly)
            })
            .collect();
        // the rules every simplified chain must keep
        let mut bad = vec![false; chains.len()];
        let mut segments: Vec<(DVec2, DVec2, usize)> = Vec::new();
        for (ci, (ch, k)) in chains.iter().zip(&kept).enumerate() {
            let mut pts: Vec<DVec2> = k
                .iter()
                .map(|&q| position(&lat, &moved, ch.ids[q]))
                .collect();
            if ch.closed {
                if let Some(&p) = pts.first() {
                    pts.push(p);
                }
            }
            pts.dedup();
            segments.extend(pts.windows(2).map(|w| (w[0], w[1], ci)));
        }
        crossing_chains(&segments, eps, &mut bad);
        let mut bad_parcel = vec![false; n];
        for (x, poly) in polygons.iter().enumerate() {
            let Some(poly) = poly else { continue };
            let raw = cells[x] as f64 * c * c;
            let mut sorted = poly.clone();
            sorted.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
            let repeated = sorted.windows(2).any(|w| w[0].distance(w[1]) <= eps);
            if poly.len() < 3 || !(polygon_signed_area(poly) > 0.5 * raw) || repeated {
                bad_parcel[x] = true;
            }
        }
        for (ch, b) in chains.iter().zip(bad.iter_mut()) {
            if ch
                .labels
                .iter()
                .any(|&l| l != NONE && bad_parcel[l as usize])
            {
                *b = true;
            }
        }
        let mut raised = false;
        for (level, &b) in levels.iter_mut().zip(&bad) {
            if b && *level < 2 {
                // after a few rounds, straight to the cell outline, which always keeps the rules
                *level = if round >= 4 { 2 } else { *level + 1 };
                raised = true;
            }
        }
        if !raised {
            break;
        }
    }
    polygons
}

// ---------------------------------------------------------------------------------------------------------------
// Statistics of a parcel layout (the thesis's validation in 3.5)

/// Consecutive contour edges turning by less than this many degrees count as one edge in
/// [`parcel_statistics`]: a vertex where a neighbour's boundary meets a straight side is not a corner.
pub const STRAIGHT_DEGREES: f64 = 10.0;

/// What the thesis measures on a parcel layout: the number of parcels, the mean number of neighbouring parcels
/// and the mean number of contour edges per parcel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ParcelStatistics {
    pub parcels: usize,
    pub mean_neighbours: f64,
    pub mean_edges: f64,
}

/// Mean number of neighbouring parcels (sharing a boundary stretch longer than `tolerance`) and of contour edges
/// per parcel, with edges turning by less than [`STRAIGHT_DEGREES`] merged.
pub fn parcel_statistics(parcels: &[Vec<DVec2>], tolerance: f64) -> ParcelStatistics {
    parcel_statistics_with(parcels, tolerance, STRAIGHT_DEGREES)
}

/// The number of edges of a closed contour once consecutive edges turning by less than `straight` (radians) are
/// merged into one.
fn edge_count(poly: &[DVec2], straight: f64) -> usize {
    let mut q = poly.to_vec();
    loop {
        let m = q.len();
        if m <= 3 {
            return m;
        }
        let flat = (0..m).find(|&i| {
            let (a, b, c) = (q[(i + m - 1) % m], q[i], q[(i + 1) % m]);
            angle_between(b - a, c - b) < straight
        });
        match flat {
            Some(i) => {
                q.remove(i);
            }
            None => return m,
        }
    }
}

/// [`parcel_statistics`] with the merging angle `straight_degrees` given. Contours may be given either way round,
/// closed or not; repeated points are ignored, and contours with fewer than three distinct points are left out.
/// Two boundary edges are shared where they run within `tolerance / 10` of each other.
pub fn parcel_statistics_with(
    parcels: &[Vec<DVec2>],
    tolerance: f64,
    straight_degrees: f64,
) -> ParcelStatistics {
    let tolerance = if tolerance.is_finite() {
        tolerance.max(0.0)
    } else {
        0.0
    };
    let lateral = (0.1 * tolerance).max(1e-9);
    let polys: Vec<Vec<DVec2>> = parcels
        .iter()
        .map(|p| {
            let mut q: Vec<DVec2> = Vec::with_capacity(p.len());
            for &v in p.iter().filter(|v| finite(**v)) {
                if q.last().is_none_or(|l| l.distance(v) > 1e-9) {
                    q.push(v);
                }
            }
            while q.len() > 1 && q[0].distance(q[q.len() - 1]) <= 1e-9 {
                q.pop();
            }
            q
        })
        .filter(|q| q.len() >= 3)
        .collect();
    let count = polys.len();
    if count == 0 {
        return ParcelStatistics::default();
    }
    let straight = straight_degrees.to_radians();
    let edges: usize = polys.iter().map(|p| edge_count(p, straight)).sum();
    // shared boundary length per pair of parcels
    let mut segments: Vec<(DVec2, DVec2, u32)> = Vec::new();
    for (i, p) in polys.iter().enumerate() {
        for k in 0..p.len() {
            segments.push((p[k], p[(k + 1) % p.len()], i as u32));
        }
    }
    let index = SegmentIndex::new(segments.iter().map(|&(a, b, _)| (a, b)).collect());
    let mut shared: std::collections::BTreeMap<(u32, u32), f64> = Default::default();
    let mut near = Vec::new();
    for (s, &(a, b, ps)) in segments.iter().enumerate() {
        let pad = DVec2::splat(lateral);
        index.candidates(a.min(b) - pad, a.max(b) + pad, &mut near);
        for &t in near.iter().filter(|&&t| t as usize > s) {
            let (c, d, pt) = segments[t as usize];
            if ps == pt {
                continue;
            }
            let overlap = collinear_overlap(a, b, c, d, lateral);
            if overlap > 0.0 {
                *shared.entry((ps.min(pt), ps.max(pt))).or_default() += overlap;
            }
        }
    }
    let mut neighbours = vec![0usize; count];
    for (&(a, b), &len) in &shared {
        if len > tolerance {
            neighbours[a as usize] += 1;
            neighbours[b as usize] += 1;
        }
    }
    ParcelStatistics {
        parcels: count,
        mean_neighbours: neighbours.iter().sum::<usize>() as f64 / count as f64,
        mean_edges: edges as f64 / count as f64,
    }
}

/// The length along which two segments run within `lateral` of each other (the shorter lying along the longer).
fn collinear_overlap(a: DVec2, b: DVec2, c: DVec2, d: DVec2, lateral: f64) -> f64 {
    let ((a, b), (c, d)) = if a.distance(b) >= c.distance(d) {
        ((a, b), (c, d))
    } else {
        ((c, d), (a, b))
    };
    let len = a.distance(b);
    if len <= 0.0 {
        return 0.0;
    }
    let dir = (b - a) / len;
    if dir.perp_dot(c - a).abs() > lateral || dir.perp_dot(d - a).abs() > lateral {
        return 0.0;
    }
    let (u, v) = ((c - a).dot(dir), (d - a).dot(dir));
    (len.min(u.max(v)) - 0f64.max(u.min(v))).max(0.0)
}

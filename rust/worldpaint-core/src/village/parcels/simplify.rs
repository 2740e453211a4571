//! Parcel simplification (thesis 3.3.4, Emilien 2014 ch. 3): each chain of the boundary graph is simplified once,
//! so neighbours keep sharing their boundary exactly. A side two parcels share becomes one straight edge between
//! its corners when it may (see [`simplify_chain`]). Otherwise staircases are first straightened (Douglas–Peucker), then
//! "we remove vertices that have little influence on the contour shape": a vertex whose edges turn by less than
//! `ε` goes, and so does a vertex of a short edge; behind the road fronts (a chain's stretch away from the roads,
//! whether it parts two parcels or a parcel from the unclaimed land) with a wider angle and deviation. No simplified edge may come within `road_width / 2` of a
//! road's centre line or swallow a water, wall or out-of-`Ω` node, and simplified chains may not cross; a chain
//! that breaks a rule is simplified less, down to its cell outline.

use super::super::road_index::RoadIndex;
use super::boundary::{trace, Chain, Lattice};
use super::grid::{Work, BLOCKED};
use super::junctions::{collapse_junctions, position, Moves};
use super::{ParcelOptions, NONE};
use crate::geom::{
    douglas_peucker, polygon_contains, polygon_signed_area, polyline_segments, segment_distance,
};
use crate::graph::{angle_between, SegmentIndex};
use glam::DVec2;
use rayon::prelude::*;

/// What a simplified boundary may not come near.
pub(super) struct Rules<'a> {
    pub(super) work: &'a Work,
    pub(super) index: &'a RoadIndex,
    pub(super) half: f64,
}

impl Rules<'_> {
    /// Whether the edge `a`–`b` keeps `road_width / 2` from every centre line and half a cell from every
    /// water, wall or out-of-`Ω` node (as the cell outlines do).
    pub(super) fn clear(&self, a: DVec2, b: DVec2) -> bool {
        let c = self.work.grid.cell;
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
                if self.work.state[j * self.work.grid.nx + i] == BLOCKED
                    && segment_distance(self.work.grid.point(i, j), a, b) < r
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
    pub(super) fn replaces(&self, span: &[DVec2]) -> bool {
        let (Some(&a), Some(&b)) = (span.first(), span.last()) else {
            return true;
        };
        let c = self.work.grid.cell;
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
                if self.work.state[j * self.work.grid.nx + i] != BLOCKED {
                    continue;
                }
                let q = self.work.grid.point(i, j);
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

/// Kept vertices with a score, as (score, index into the kept list).
type ScoredVertices = Vec<(f64, usize)>;

/// How the chains leave each junction: per junction vertex, (chain, direction from the junction to the chain's
/// cell outline `short_edge` cells away).
type Leaving = std::collections::HashMap<u32, Vec<(usize, DVec2)>>;

fn leaving_directions(chains: &[Chain], lat: &Lattice, reach: f64) -> Leaving {
    let towards = |from: DVec2, along: &mut dyn Iterator<Item = DVec2>| {
        let mut last = from;
        for p in along {
            last = p;
            if p.distance(from) >= reach {
                break;
            }
        }
        last - from
    };
    let mut map = Leaving::new();
    for (ci, ch) in chains.iter().enumerate() {
        let (Some(&first), Some(&last)) = (ch.ids.first(), ch.ids.last()) else {
            continue;
        };
        if ch.closed {
            continue;
        }
        let (a, b) = (lat.pos(first), lat.pos(last));
        let d = towards(a, &mut ch.ids.iter().map(|&v| lat.pos(v)));
        map.entry(first).or_default().push((ci, d));
        let d = towards(b, &mut ch.ids.iter().rev().map(|&v| lat.pos(v)));
        map.entry(last).or_default().push((ci, d));
    }
    map
}

/// The vertices of a chain (indices into `ids`) kept at simplification level `level`: 0 the full simplification,
/// 1 half of it, 2 the cell outline (only its corners).
fn simplify_chain(
    (ci, ch): (usize, &Chain),
    leaving: &Leaving,
    lat: &Lattice,
    rules: &Rules,
    options: &ParcelOptions,
    level: u8,
) -> Vec<usize> {
    if level >= 2 {
        return outline_corners(ch, lat);
    }
    let m = ch.ids.len();
    let pts: Vec<DVec2> = ch.ids.iter().map(|&v| lat.pos(v)).collect();
    // a closed loop is cyclic over 0..m-1 (its last vertex repeats the first)
    let cyc = if ch.closed { m - 1 } else { m };
    let scale = 0.5f64.powi(level as i32);
    let c = rules.work.grid.cell;
    if level == 0 && runs_straight((ci, ch), &pts, leaving, rules, options) {
        return vec![0, m - 1];
    }
    let keep = straightened(ch, &pts, options.straighten * c * scale, rules);
    let mut kept: Vec<usize> = (0..cyc).filter(|&q| keep[q]).collect();
    let max_dev = options.merge_deviation * c * scale;
    // behind the road fronts, where the conquests' budgets and costs drew the line (a far side, or where two
    // conquests met), not the road, a stretch may straighten further
    let front = rules.half + max_dev;
    let far_dev = options.far_deviation * c * scale;
    let far = |a: DVec2, b: DVec2| rules.index.segment_clearance(a, b, front) >= front;
    let deviation = |a: DVec2, b: DVec2| {
        if far(a, b) {
            far_dev.max(max_dev)
        } else {
            max_dev
        }
    };
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
            .find(|&(_, q)| removable(&kept, q, &pts, cyc, &deviation, rules))
        {
            Some((_, q)) => {
                kept.remove(q);
            }
            None => break,
        }
    };
    // the vertices where the contour turns by less than ε
    let eps = options.merge_angle_degrees.to_radians() * scale;
    // a far side (unclaimed land beyond) keeps some of its bends: it is the parcel's own outline; a side two
    // parcels share straightens further
    let far_eps = if ch.labels.contains(&NONE) {
        options.far_merge_angle_degrees
    } else {
        options.shared_merge_angle_degrees
    }
    .to_radians()
        * scale;
    remove_while(&|kept: &[usize]| {
        let km = kept.len();
        let range = if ch.closed { 0..km } else { 1..km - 1 };
        range
            .filter_map(|q| {
                let (p, x, nx) = (kept[(q + km - 1) % km], kept[q], kept[(q + 1) % km]);
                let turn = angle_between(pts[x] - pts[p], pts[nx] - pts[x]);
                let limit = if far(pts[p], pts[x]) && far(pts[x], pts[nx]) {
                    far_eps.max(eps)
                } else {
                    eps
                };
                (turn < limit).then_some((turn, q))
            })
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

/// Whether a side two parcels share runs straight between its corners (where it meets a third parcel, the
/// unclaimed land or the road): where two conquests met, no road drew its line. Within the far deviation and 0.4 of
/// its length, and making no angle below the acute angle with the other chains at its corners.
fn runs_straight(
    (ci, ch): (usize, &Chain),
    pts: &[DVec2],
    leaving: &Leaving,
    rules: &Rules,
    options: &ParcelOptions,
) -> bool {
    if ch.closed || ch.is_loop() || ch.labels.contains(&NONE) {
        return false;
    }
    let (m, c) = (pts.len(), rules.work.grid.cell);
    let (a, b) = (pts[0], pts[m - 1]);
    let bound = (options.far_deviation * c).min(0.4 * a.distance(b));
    let acute = options.acute_angle_degrees.to_radians();
    let opens = |v: u32, d: DVec2| {
        leaving.get(&v).is_none_or(|ends| {
            ends.iter()
                .all(|&(other, e)| other == ci || angle_between(d, e) >= acute)
        })
    };
    opens(ch.ids[0], b - a)
        && opens(ch.ids[m - 1], a - b)
        && pts.iter().all(|p| segment_distance(*p, a, b) <= bound)
        && rules.replaces(pts)
}

/// The corners of a chain's cell outline (indices into `ids`), with the ends of an open chain: the simplification
/// that always keeps the rules.
fn outline_corners(ch: &Chain, lat: &Lattice) -> Vec<usize> {
    let m = ch.ids.len();
    let cyc = if ch.closed { m - 1 } else { m };
    let mut keep = vec![false; m];
    if !ch.closed {
        keep[0] = true;
        keep[m - 1] = true;
    }
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
    (0..cyc).filter(|&q| keep[q]).collect()
}

/// The vertices of a chain's cell outline `pts` that its staircases straightened within `tol` keep
/// (Douglas–Peucker, each new edge [`Rules::replaces`] its stretch). A loop is split at its farthest vertex from
/// the first, and keeps three vertices at least.
fn straightened(ch: &Chain, pts: &[DVec2], tol: f64, rules: &Rules) -> Vec<bool> {
    let m = pts.len();
    let mut keep = vec![false; m];
    if !ch.closed {
        keep[0] = true;
        keep[m - 1] = true;
    }
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
        douglas_peucker(pts, 0, far, tol, &mut keep, |span| rules.replaces(span));
        douglas_peucker(pts, far, m - 1, tol, &mut keep, |span| rules.replaces(span));
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
        douglas_peucker(pts, 0, m - 1, tol, &mut keep, |span| rules.replaces(span));
    }
    keep
}

/// Whether kept vertex `q` may go: the outline between its neighbours stays within `deviation(a, b)` of the new
/// edge `a`–`b`, which [`Rules::replaces`] the outline.
fn removable(
    kept: &[usize],
    q: usize,
    pts: &[DVec2],
    cyc: usize,
    deviation: &dyn Fn(DVec2, DVec2) -> f64,
    rules: &Rules,
) -> bool {
    let km = kept.len();
    let (p, nx) = (kept[(q + km - 1) % km], kept[(q + 1) % km]);
    let max_dev = deviation(pts[p], pts[nx]);
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
pub(super) fn simplified_contours(
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
    let mut cells = vec![0usize; n];
    for &x in label {
        if x != NONE {
            cells[x as usize] += 1;
        }
    }
    let leaving = leaving_directions(&chains, &lat, options.short_edge * work.grid.cell);
    let mut levels = vec![0u8; chains.len()];
    let mut flag = vec![false; lat.vx * (work.grid.ny + 1)];
    let mut polygons: Vec<Option<Vec<DVec2>>> = vec![None; n];
    for round in 0.. {
        let kept: Vec<Vec<usize>> = chains
            .par_iter()
            .enumerate()
            .zip(levels.par_iter())
            .map(|(ch, &level)| simplify_chain(ch, &leaving, &lat, &rules, options, level))
            .collect();
        let moved = collapse_junctions(&lat, &chains, &kept, &levels, &rules, options);
        polygons = outlines(&lat, &chains, &kept, &moved, &loops, &mut flag);
        let bad = broken_chains(&lat, &chains, &kept, &moved, &polygons, &cells);
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

/// Each parcel's outline through the kept vertices of the chains, at their moved positions. `flag` (one per
/// lattice vertex) is scratch space.
fn outlines(
    lat: &Lattice,
    chains: &[Chain],
    kept: &[Vec<usize>],
    moved: &Moves,
    loops: &[Vec<u32>],
    flag: &mut [bool],
) -> Vec<Option<Vec<DVec2>>> {
    for (ch, k) in chains.iter().zip(kept) {
        for &v in &ch.ids {
            flag[v as usize] = false;
        }
        for &q in k {
            flag[ch.ids[q] as usize] = true;
        }
    }
    loops
        .iter()
        .map(|lp| {
            if lp.is_empty() {
                return None;
            }
            let mut poly: Vec<DVec2> = Vec::new();
            for &v in lp {
                if flag[v as usize] {
                    let p = position(lat, moved, v);
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
        .collect()
}

/// The chains that break the rules every simplified chain must keep: chains may not cross, and a parcel
/// (`cells` of the grid) must stay a polygon of three vertices or more, counter-clockwise, without repeated
/// vertices, and of at least half its cells' area; every chain of a parcel that does not is broken.
fn broken_chains(
    lat: &Lattice,
    chains: &[Chain],
    kept: &[Vec<usize>],
    moved: &Moves,
    polygons: &[Option<Vec<DVec2>>],
    cells: &[usize],
) -> Vec<bool> {
    let c = lat.work.grid.cell;
    let eps = 1e-6 * c;
    let mut bad = vec![false; chains.len()];
    let mut segments: Vec<(DVec2, DVec2, usize)> = Vec::new();
    for (ci, (ch, k)) in chains.iter().zip(kept).enumerate() {
        let mut pts: Vec<DVec2> = k.iter().map(|&q| position(lat, moved, ch.ids[q])).collect();
        if ch.closed {
            if let Some(&p) = pts.first() {
                pts.push(p);
            }
        }
        pts.dedup();
        segments.extend(polyline_segments(&pts).map(|(a, b)| (a, b, ci)));
    }
    crossing_chains(&segments, eps, &mut bad);
    let mut bad_parcel = vec![false; polygons.len()];
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
    bad
}

//! Junction simplification (thesis 3.3.4, Emilien 2014 ch. 3) by edge collapses, as in mesh simplification: a
//! chain of a cell or so between two junctions collapses onto one of them, and — "we remove unplausible acute
//! angles that appear at some T-vertices" — a junction where a parcel has an angle below
//! [`ParcelOptions::acute_angle_degrees`] moves onto the neighbouring vertex that best opens it. Last, a T behind
//! the road fronts, where the boundary runs on through the junction turning by less than `ε`, moves onto that
//! boundary's straight line (by at most the merge deviation), as a vertex turning by less than `ε` goes on a
//! chain.

use super::boundary::{Chain, Lattice};
use super::simplify::Rules;
use super::{ParcelOptions, NONE};
use crate::geom::ccw_angle;
use glam::DVec2;
use std::f64::consts::{PI, TAU};

/// Where each junction vertex has moved to, by an edge collapse or a straightening.
pub(super) type Moves = std::collections::HashMap<u32, DVec2>;

pub(super) fn position(lat: &Lattice, moved: &Moves, v: u32) -> DVec2 {
    moved.get(&v).copied().unwrap_or_else(|| lat.pos(v))
}

/// An end of an open chain: its vertex, the direction of its edge there, the chain, and whether it is the chain's
/// start. Sorted, the ends at one junction are consecutive.
type ChainEnd = (u32, u8, usize, bool);

/// The simplified boundary graph around its junctions, as the edge collapses see it.
struct JunctionGraph<'a> {
    lat: &'a Lattice<'a>,
    chains: &'a [Chain],
    kept: &'a [Vec<usize>],
    levels: &'a [u8],
    rules: &'a Rules<'a>,
    ends: Vec<ChainEnd>,
    acute: f64,
}

/// Edge collapses at the junctions of the boundary graph, as in mesh simplification. A chain between two
/// junctions no longer than the straightening tolerance collapses onto one of its ends, unless that makes an
/// acute angle. Then the second step of 3.3.4: at a junction where a parcel has an acute angle, the junction
/// moves onto the next vertex of one of its chains when that opens the smallest parcel angle there. Last, the
/// T-junctions behind the road fronts are straightened.
pub(super) fn collapse_junctions(
    lat: &Lattice,
    chains: &[Chain],
    kept: &[Vec<usize>],
    levels: &[u8],
    rules: &Rules,
    options: &ParcelOptions,
) -> Moves {
    let graph = JunctionGraph {
        lat,
        chains,
        kept,
        levels,
        rules,
        ends: chain_ends(chains),
        acute: options.acute_angle_degrees.to_radians(),
    };
    let mut moved = Moves::new();
    let mut used = vec![false; chains.len()];
    let short = options.straighten * lat.work.grid.cell;
    let touched = graph.collapse_short_chains(short, &mut moved, &mut used);
    graph.open_acute_junctions(&touched, &mut moved, &mut used);
    let eps = options.merge_angle_degrees.to_radians();
    let max_dev = options.merge_deviation * lat.work.grid.cell;
    graph.straighten_junctions(&touched, eps, max_dev, &mut moved);
    moved
}

/// The ends of every open chain, sorted.
fn chain_ends(chains: &[Chain]) -> Vec<ChainEnd> {
    let mut ends: Vec<ChainEnd> = Vec::new();
    for (c, ch) in chains.iter().enumerate() {
        if ch.closed {
            continue;
        }
        ends.push((ch.ids[0], ch.first_dir, c, true));
        ends.push((ch.ids[ch.ids.len() - 1], ch.last_dir, c, false));
    }
    ends.sort_unstable();
    ends
}

/// The smallest angle between the edges from `centre` to `targets`, whatever lies between them.
fn tightest(centre: DVec2, targets: &[DVec2]) -> Option<f64> {
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
}

/// The smallest parcel angle around `centre` with the chains heading to `targets` (counter-clockwise), the sector
/// after chain `q` belonging to `faces[q]`.
fn smallest_parcel_angle(centre: DVec2, targets: &[DVec2], faces: &[u32]) -> Option<f64> {
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
}

impl JunctionGraph<'_> {
    /// The next kept vertex along a chain from one end, whether it is the far end, and the one after it.
    fn next(&self, c: usize, at_start: bool) -> (u32, bool, Option<u32>) {
        let ids = &self.chains[c].ids;
        let k = &self.kept[c];
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
    }

    /// The chain ends at vertex `v`.
    fn group_of(&self, v: u32) -> &[ChainEnd] {
        let lo = self.ends.partition_point(|e| e.0 < v);
        let hi = self.ends.partition_point(|e| e.0 <= v);
        &self.ends[lo..hi]
    }

    /// First, a chain no longer than `short` (the straightening tolerance) between two junctions collapses to one
    /// of them (an edge collapse): a jog of a cell or so between two junctions is the grid's noise. Returns the
    /// junctions involved, which the second step leaves alone.
    fn collapse_short_chains(
        &self,
        short: f64,
        moved: &mut Moves,
        used: &mut [bool],
    ) -> std::collections::HashSet<u32> {
        let (lat, chains, kept, levels) = (self.lat, self.chains, self.kept, self.levels);
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
            let (g1, g2) = (self.group_of(v1), self.group_of(v2));
            if g1
                .iter()
                .chain(g2)
                .any(|e| levels[e.2] != 0 || kept[e.2].len() < 2 || chains[e.2].is_loop())
            {
                continue;
            }
            let heads = |g: &[ChainEnd]| -> Vec<DVec2> {
                g.iter()
                    .filter(|e| e.2 != ci)
                    .map(|e| position(lat, moved, self.next(e.2, e.3).0))
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
                if !others.iter().all(|t| self.rules.clear(centre, *t)) {
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
                if a >= b1.min(b2).min(self.acute) {
                    moved.insert(from, lat.pos(to));
                    used[ci] = true;
                    touched.insert(v1);
                    touched.insert(v2);
                }
            }
        }
        touched
    }

    /// Then, at each junction (not `touched`) where a parcel has an acute angle, the junction moves onto the next
    /// vertex of one of its chains when that opens the smallest parcel angle there.
    fn open_acute_junctions(
        &self,
        touched: &std::collections::HashSet<u32>,
        moved: &mut Moves,
        used: &mut [bool],
    ) {
        let (lat, kept, levels) = (self.lat, self.kept, self.levels);
        let ends = &self.ends;
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
            let heads: Vec<(u32, bool, Option<u32>)> =
                group.iter().map(|e| self.next(e.2, e.3)).collect();
            let targets: Vec<DVec2> = heads.iter().map(|h| position(lat, moved, h.0)).collect();
            let Some(old) = smallest_parcel_angle(position(lat, moved, v), &targets, &faces) else {
                continue;
            };
            if old >= self.acute {
                continue;
            }
            let mut best: Option<(f64, usize)> = None;
            for (q, e) in group.iter().enumerate() {
                let (w, is_end, after) = heads[q];
                if is_end || used[e.2] || self.chains[e.2].is_loop() {
                    continue;
                }
                let Some(after) = after else { continue };
                let centre = lat.pos(w);
                let mut t = targets.clone();
                t[q] = position(lat, moved, after);
                let clear = (0..group.len())
                    .filter(|&r| r != q)
                    .all(|r| self.rules.clear(centre, targets[r]));
                if !clear {
                    continue;
                }
                if let Some(a) = smallest_parcel_angle(centre, &t, &faces) {
                    if best.is_none_or(|(b, _)| a > b) {
                        best = Some((a, q));
                    }
                }
            }
            if let Some((a, q)) = best {
                if a > old + 1e-6 {
                    moved.insert(v, lat.pos(heads[q].0));
                    used[group[q].2] = true;
                }
            }
        }
    }

    /// Last, a junction where one boundary runs on through a T (two of its three chains turning by less than `ε`)
    /// moves onto the straight line between their next vertices, by at most `max_dev`: the boundary the third
    /// chain meets stays one straight side, as a vertex turning by less than `ε` goes on a chain. No parcel angle
    /// may become acute, and the moved edges keep the rules.
    fn straighten_junctions(
        &self,
        touched: &std::collections::HashSet<u32>,
        eps: f64,
        max_dev: f64,
        moved: &mut Moves,
    ) {
        let (lat, kept, levels) = (self.lat, self.kept, self.levels);
        let ends = &self.ends;
        let mut g0 = 0;
        while g0 < ends.len() {
            let v = ends[g0].0;
            let g1 = g0 + ends[g0..].partition_point(|e| e.0 == v);
            let group = &ends[g0..g1];
            g0 = g1;
            if group.len() != 3
                || touched.contains(&v)
                || moved.contains_key(&v)
                || group
                    .iter()
                    .any(|e| levels[e.2] != 0 || kept[e.2].len() < 2 || self.chains[e.2].is_loop())
            {
                continue;
            }
            let centre = lat.pos(v);
            // the fronts follow their road, and a footprint is centred on its frontage: only a T behind them
            let front = self.rules.half + max_dev;
            if self.rules.index.segment_clearance(centre, centre, front) < front {
                continue;
            }
            let faces: Vec<u32> = group.iter().map(|e| lat.quadrant(v, e.1)).collect();
            let targets: Vec<DVec2> = group
                .iter()
                .map(|e| position(lat, moved, self.next(e.2, e.3).0))
                .collect();
            let Some(old) = smallest_parcel_angle(centre, &targets, &faces) else {
                continue;
            };
            let straightest = [(0, 1), (1, 2), (0, 2)]
                .into_iter()
                .map(|(a, b)| {
                    let turn =
                        crate::graph::angle_between(centre - targets[a], targets[b] - centre);
                    (turn, a, b)
                })
                .min_by(|x, y| x.0.total_cmp(&y.0));
            let Some((turn, a, b)) = straightest else {
                continue;
            };
            if turn >= eps {
                continue;
            }
            let p = closest_on_segment(centre, targets[a], targets[b]);
            if p.distance(centre) > max_dev || p.distance(centre) < 1e-9 {
                continue;
            }
            let keeps = targets
                .iter()
                .all(|&t| self.rules.clear(p, t) && self.rules.replaces(&[t, centre, p]));
            let opens = smallest_parcel_angle(p, &targets, &faces)
                .is_some_and(|angle| angle >= old.min(self.acute));
            if keeps && opens {
                moved.insert(v, p);
            }
        }
    }
}

/// The point of the segment `a`–`b` closest to `p`.
fn closest_on_segment(p: DVec2, a: DVec2, b: DVec2) -> DVec2 {
    let ab = b - a;
    let l2 = ab.length_squared();
    if l2 <= 0.0 {
        return a;
    }
    a + ab * ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
}

//! Corner conquest (thesis 3.3.2, Emilien 2014 ch. 3): "We allow parcel `P_i` arrived first at a junction to
//! annex its neighborhood": in each junction sector narrower than
//! [`ParcelOptions::corner_angle_degrees`], the parcel whose road cells come nearest the corner annexes the
//! sector's road cells on both roads within its road reach (3.3.1's maximum distance, at most its depth
//! `c_max / ω_conquest`) of the corner's foot, and at most half-way to the next junction. The corner lot then
//! fronts both roads and its neighbours begin where its land ends, instead of meeting it along a diagonal with
//! sharp angles; annexing as far as its depth instead stripped whole rows of neighbours of their front along the
//! short side roads of a dense village.

use super::super::Road;
use super::grid::Work;
use super::road_conquest::RoadConquest;
use super::{ParcelOptions, ParcelSeed, NONE};
use crate::geom::{ccw_angle, closest_on_segment};
use crate::graph::{angle_between, Graph};
use glam::DVec2;

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
pub(super) struct Junction {
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

/// The junctions of the road network (nodes of its planar graph where three roads or more meet, or two roads
/// meet at an angle below the corner angle) inside the conquest grid, with their branches followed for `length`.
pub(super) fn junctions(
    roads: &[Road],
    work: &Work,
    seeds: &[ParcelSeed],
    road_width: f64,
    options: &ParcelOptions,
) -> Vec<Junction> {
    let half = 0.5 * road_width;
    // as far as any corner lot may reach along a road
    let longest = seeds
        .iter()
        .map(|s| s.params.budget / s.params.conquest_weight + s.params.road_reach)
        .fold(0.0, f64::max);
    let length = longest + road_width + 4.0 * work.grid.cell;
    let paths: Vec<&[DVec2]> = roads
        .iter()
        .filter(|r| r.points.len() >= 2)
        .map(|r| r.points.as_slice())
        .collect();
    let graph = Graph::from_paths(&paths, 0.1 * work.grid.cell);
    let adj = graph.adjacency();
    let probe = 2.0 * half + 2.0 * work.grid.cell;
    let lo = work.grid.origin;
    let hi = work.grid.point(work.grid.nx - 1, work.grid.ny - 1);
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

/// `conquest` (a [`corner_conquest`]), after which a seed left with less than half its road front by a corner lot
/// has lost its access: what remains would make a sliver of a parcel, and it loses its road cells.
pub(super) fn keeping_access(
    seeds: usize,
    road: &mut RoadConquest,
    conquest: impl FnOnce(&mut RoadConquest),
) {
    let frontage = |road: &RoadConquest| {
        let mut count = vec![0usize; seeds];
        for &o in &road.owner {
            if o != NONE {
                count[o as usize] += 1;
            }
        }
        count
    };
    let before = frontage(road);
    conquest(road);
    let after = frontage(road);
    for o in road.owner.iter_mut() {
        if *o != NONE && 2 * after[*o as usize] < before[*o as usize] {
            *o = NONE;
        }
    }
}

/// In each junction sector narrower than the corner angle, the parcel whose road cells come nearest the corner
/// (the first to arrive there) annexes the sector's road cells on both roads within its road reach (at most its
/// depth `c_max / ω_conquest`) of the corner: the corner lot then fronts both roads, and its neighbours on either
/// road begin where its land ends instead of meeting it along a diagonal.
pub(super) fn corner_conquest(
    work: &Work,
    seeds: &[ParcelSeed],
    junctions: &[Junction],
    half: f64,
    options: &ParcelOptions,
    road: &mut RoadConquest,
) {
    let corner = options.corner_angle_degrees.to_radians();
    let c = work.grid.cell;
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
                    let e = j * work.grid.nx + i;
                    if !work.edge[e] || road.owner[e] == NONE {
                        continue;
                    }
                    let p = work.grid.point(i, j);
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
            // the corner lot's front on either road reaches as far as a road conquest does (3.3.1's maximum
            // distance), so it does not strip its neighbours of their own front
            let depth = depth.min(seeds[winner as usize].params.road_reach);
            let (x0, y0, x1, y1) = work.around(jn.point, start + depth + half + 3.0 * c);
            for j in y0..=y1 {
                for i in x0..=x1 {
                    let e = j * work.grid.nx + i;
                    if !work.edge[e] || road.owner[e] == winner {
                        continue;
                    }
                    // as far as its depth, and at most half-way to the next junction, whose own corner lot takes
                    // the other half
                    let within = |(b, arc): (&Branch, f64)| {
                        arc <= start + depth && (!b.to_junction || arc <= 0.5 * b.length)
                    };
                    if sector_cell(work.grid.point(i, j)).is_some_and(within) {
                        road.owner[e] = winner;
                        road.arrival[e] = f64::INFINITY;
                    }
                }
            }
        }
    }
}

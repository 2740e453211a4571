//! Islands, lakes and fields as contours (Section 6, "Implementation and results"; thesis 6.2.1): "we provide an
//! automatic method for creating dense point clusters from closed contours: we generate a dense set of points in the
//! region within the contours using a jittered grid ... synthesized islands and lakes are rendered as contours by
//! tracing a contour around dense clusters".
//!
//! * [`fill_polygons`]: one point per cell of a grid of side `spacing`, jittered uniformly within its cell, kept where
//!   the contours (combined by the even-odd rule, so a lake in an island is a hole) contain it.
//! * [`trace_contours`]: the density of the points, smoothed by a Gaussian of `0.6 × spacing` and scaled so that a
//!   filled area reads 1, is contoured by marching squares on a grid of half the spacing, and the closed loops are
//!   simplified (Douglas–Peucker, a tenth of the spacing). Loops smaller than four cells are dropped. The level is the
//!   one that keeps the points' area (one spacing² each): ½ for a jittered grid, down to 0.3 for the looser clusters
//!   synthesis makes, whose rim never reaches ½.
//! * `cut` and `split`: a contour less a region, or its parts inside and outside, by the same dense points:
//!   filled, the points parted by the region, traced.
//! * [`islands`]: the islands of a set of contours (each outer contour with the lakes directly inside it, by the
//!   even-odd rule) and their land areas, which a color learns and the synthesis matches.
//! * [`Polygons::signed_distance`]: the interaction of a distribution with a polygon category (thesis 6.2.1),
//!   `d` outside and `−d / d_max` inside, where `d_max` is the largest distance to the border inside the contour
//!   that holds the point.

use crate::geom::{douglas_peucker, polygon_signed_area, DVec2, Region, RegionQueries};
use crate::graph::SegmentIndex;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// Smoothing of the traced density, in units of the spacing.
const TRACE_SIGMA: f64 = 0.6;
/// The lowest iso-level a trace uses (see [`trace_contours`]).
const MIN_LEVEL: f64 = 0.3;
/// Samples across a contour's bounding box to find its largest inner distance.
const INNER_SAMPLES: usize = 64;

/// The contours of one polygon category, ready for containment and signed-distance queries.
#[derive(Clone, Debug, Default)]
pub struct Polygons {
    contours: Vec<Region>,
    /// Per contour: its bounding box, so that containment tests only the contours whose box holds the point.
    boxes: Vec<(DVec2, DVec2)>,
    /// Per contour: its area (to find the innermost contour holding a point) and its largest inner distance, found
    /// when first asked (a place holds a thousand fields, of which a paste reads a few).
    areas: Vec<f64>,
    inner: Vec<OnceLock<f64>>,
    border: SegmentIndex,
}

impl Polygons {
    /// Contours with fewer than three points or no area are left out.
    pub fn new(contours: &[Vec<DVec2>]) -> Polygons {
        let contours: Vec<Region> = contours
            .iter()
            .filter(|c| c.len() >= 3 && polygon_signed_area(c).abs() > 0.0)
            .map(|c| Region::Polygon { points: c.clone() })
            .collect();
        let segments = contours
            .iter()
            .flat_map(|r| match r {
                Region::Polygon { points } => (0..points.len())
                    .map(|i| (points[i], points[(i + 1) % points.len()]))
                    .collect::<Vec<_>>(),
                _ => Vec::new(),
            })
            .collect();
        Polygons {
            areas: contours.iter().map(|c| c.area()).collect(),
            boxes: contours.iter().map(|c| c.bbox()).collect(),
            inner: contours.iter().map(|_| OnceLock::new()).collect(),
            border: SegmentIndex::new(segments),
            contours,
        }
    }

    /// Whether no contour was kept.
    pub fn is_empty(&self) -> bool {
        self.contours.is_empty()
    }

    /// Inside by the even-odd rule over all contours.
    pub fn contains(&self, p: DVec2) -> bool {
        self.holding(p).count() % 2 == 1
    }

    /// The contours that hold `p`.
    fn holding(&self, p: DVec2) -> impl Iterator<Item = usize> + '_ {
        (0..self.contours.len()).filter(move |&i| self.holds(i, p))
    }

    /// Whether contour `i` holds `p`.
    fn holds(&self, i: usize, p: DVec2) -> bool {
        let (lo, hi) = self.boxes[i];
        p.cmpge(lo).all() && p.cmple(hi).all() && self.contours[i].contains(p)
    }

    fn largest_inner_distance(&self, i: usize) -> f64 {
        let (lo, hi) = self.boxes[i];
        let step = (hi - lo) / INNER_SAMPLES as f64;
        let reach = (hi - lo).length();
        // only the contours whose boxes meet this one's can hold its samples
        let near: Vec<usize> = (0..self.contours.len())
            .filter(|&k| {
                let (a, b) = self.boxes[k];
                a.cmple(hi).all() && b.cmpge(lo).all()
            })
            .collect();
        let mut best: f64 = 0.0;
        for j in 0..INNER_SAMPLES {
            for k in 0..INNER_SAMPLES {
                let p = lo + DVec2::new(k as f64 + 0.5, j as f64 + 0.5) * step;
                let holding = near.iter().copied().filter(|&c| self.holds(c, p));
                let (count, owner) = holding.fold((0, None::<usize>), |(n, o), c| {
                    (
                        n + 1,
                        Some(o.filter(|o| self.areas[*o] <= self.areas[c]).unwrap_or(c)),
                    )
                });
                if owner == Some(i) && count % 2 == 1 {
                    best = best.max(self.border.distance(p, reach));
                }
            }
        }
        best.max(step.x.min(step.y))
    }

    /// The contours' edges.
    pub fn border(&self) -> &SegmentIndex {
        &self.border
    }

    /// Distance to the nearest border, looking no farther than `max`.
    pub fn distance(&self, p: DVec2, max: f64) -> f64 {
        self.border.distance(p, max)
    }

    /// `d` outside, `−d / d_max` inside (thesis 6.2.1); outside distances saturate at `max`.
    pub fn signed_distance(&self, p: DVec2, max: f64) -> f64 {
        self.side_and_signed_distance(p, max).1
    }

    /// Whether `p` lies inside, and [`Polygons::signed_distance`] there (one containment test for both).
    pub(crate) fn side_and_signed_distance(&self, p: DVec2, max: f64) -> (bool, f64) {
        if self.contours.is_empty() {
            return (false, max);
        }
        let (inside, reach) = self.side_and_reach(p, max);
        signed(inside, reach, self.border.distance(p, reach))
    }

    /// [`Polygons::side_and_signed_distance`] of every point (the nearest borders found a block of points at
    /// a time, see [`SegmentIndex::distances`]).
    pub(crate) fn sides_and_signed_distances(
        &self,
        points: &[DVec2],
        max: f64,
    ) -> Vec<(bool, f64)> {
        use rayon::prelude::*;
        if self.contours.is_empty() {
            return vec![(false, max); points.len()];
        }
        let sides: Vec<(bool, f64)> = points
            .par_iter()
            .map(|p| self.side_and_reach(*p, max))
            .collect();
        let d = self.border.distances(points, |i| sides[i].1);
        sides
            .iter()
            .zip(d)
            .map(|(&(inside, reach), d)| signed(inside, reach, d))
            .collect()
    }

    /// Whether `p` is inside, and how far its distance is read: `max` outside, inside the largest distance to the
    /// border within its innermost contour (`d_max`). The contours holding `p` are read once: inside when odd.
    fn side_and_reach(&self, p: DVec2, max: f64) -> (bool, f64) {
        let (mut holding, mut owner) = (0usize, None::<usize>);
        for i in self.holding(p) {
            holding += 1;
            if owner.is_none_or(|o| self.areas[i] < self.areas[o]) {
                owner = Some(i);
            }
        }
        if holding % 2 == 1 {
            let d_max = owner
                .map_or(1.0, |i| {
                    *self.inner[i].get_or_init(|| self.largest_inner_distance(i))
                })
                .max(1e-9);
            (true, d_max)
        } else {
            (false, max)
        }
    }

    /// The contours' points.
    pub fn contours(&self) -> impl Iterator<Item = &[DVec2]> {
        self.contours.iter().filter_map(|r| match r {
            Region::Polygon { points } => Some(points.as_slice()),
            _ => None,
        })
    }
}

/// The signed distance of a point inside (`−d / d_max`, at most 1 deep) or outside (`d`), `d` read within `reach`.
fn signed(inside: bool, reach: f64, d: f64) -> (bool, f64) {
    if inside {
        (true, -(d / reach).min(1.0))
    } else {
        (false, d)
    }
}

/// Dense points filling the contours (see the module documentation); `seed` draws the jitter.
pub fn fill_polygons(polygons: &Polygons, spacing: f64, seed: u64) -> Vec<DVec2> {
    let whole = polygons.boxes.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), (a, b)| (lo.min(*a), hi.max(*b)),
    );
    fill_polygons_within(polygons, spacing, seed, whole)
}

/// The points of [`fill_polygons`] inside the box `within`: the same points there, whatever the box, and a cost
/// that grows with the box rather than with the contours' extent (a place's fields span kilometres).
pub(crate) fn fill_polygons_within(
    polygons: &Polygons,
    spacing: f64,
    seed: u64,
    within: (DVec2, DVec2),
) -> Vec<DVec2> {
    let mut out = Vec::new();
    if !(spacing > 0.0 && spacing.is_finite()) {
        return out;
    }
    let covers = |(a, b): &(DVec2, DVec2), p: DVec2| p.cmpge(*a).all() && p.cmple(*b).all();
    for (k, (lo, hi)) in polygons.boxes.iter().enumerate() {
        let (lo, hi) = (lo.max(within.0), hi.min(within.1));
        if !(lo.x <= hi.x && lo.y <= hi.y) {
            continue;
        }
        // cells aligned on a global lattice, so overlapping contours share them
        let (i0, j0) = (
            (lo.x / spacing).floor() as i64,
            (lo.y / spacing).floor() as i64,
        );
        let (i1, j1) = (
            (hi.x / spacing).ceil() as i64,
            (hi.y / spacing).ceil() as i64,
        );
        for j in j0..j1 {
            for i in i0..i1 {
                let p = (DVec2::new(i as f64, j as f64) + cell_jitter(seed, i, j)) * spacing;
                // a cell belongs to the first contour whose box covers its point, so it is drawn once
                let first = covers(&polygons.boxes[k], p)
                    && !polygons.boxes[..k].iter().any(|b| covers(b, p));
                if first && covers(&within, p) && polygons.contains(p) {
                    out.push(p);
                }
            }
        }
    }
    out
}

/// The jitter of cell `(i, j)` within it, drawn from the seed and the cell alone, so that a cell's point does not
/// depend on which part of the contours is filled.
fn cell_jitter(seed: u64, i: i64, j: i64) -> DVec2 {
    let cell = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (j as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ cell);
    DVec2::new(rng.random(), rng.random())
}

/// Dense points along a contour's perimeter when a tool cuts it: the traced cut stays within two cells of it.
const CUT_SAMPLES: f64 = 400.0;

/// The contour less `region` (see the module documentation), or `None` when the contour does not meet the region.
pub(crate) fn cut(contour: &[DVec2], region: &impl RegionQueries) -> Option<Loops> {
    split(contour, region).map(|(_, outside)| outside)
}

/// Closed contours.
pub(crate) type Loops = Vec<Vec<DVec2>>;

/// The parts of the contour inside `region` and outside it, by the same dense points as [`cut`], or `None` when
/// the contour does not meet the region. A contour wholly inside comes back as it is.
pub(crate) fn split(contour: &[DVec2], region: &impl RegionQueries) -> Option<(Loops, Loops)> {
    let n = contour.len();
    if n < 3 {
        return None;
    }
    let edges = || (0..n).map(|i| (contour[i], contour[(i + 1) % n]));
    let outline = Region::Polygon {
        points: contour.to_vec(),
    };
    let (lo, hi) = region.bbox();
    let any_inside = contour.iter().any(|p| region.contains(*p));
    let crosses = edges().any(|(a, b)| !region.segment_crossings(a, b).is_empty());
    if !crosses && contour.iter().all(|p| region.contains(*p)) {
        return Some((vec![contour.to_vec()], Vec::new()));
    }
    let meets = any_inside
        || crosses
        || outline.contains(0.5 * (lo + hi)) && region.contains(0.5 * (lo + hi));
    if !meets {
        return None;
    }
    let perimeter: f64 = edges().map(|(a, b)| a.distance(b)).sum();
    let spacing = (perimeter / CUT_SAMPLES).max(1e-3);
    let polygons = Polygons::new(&[contour.to_vec()]);
    let (inside, outside): (Vec<DVec2>, Vec<DVec2>) = fill_polygons(&polygons, spacing, n as u64)
        .into_iter()
        .partition(|p| region.contains(*p));
    Some((
        trace_contours(&inside, spacing),
        trace_contours(&outside, spacing),
    ))
}

/// Closed contours around dense points (see the module documentation).
pub fn trace_contours(points: &[DVec2], spacing: f64) -> Vec<Vec<DVec2>> {
    if points.is_empty() || !(spacing > 0.0 && spacing.is_finite()) {
        return Vec::new();
    }
    let sigma = TRACE_SIGMA * spacing;
    let reach = 3.0 * sigma;
    let h = 0.5 * spacing;
    let (lo, hi) = points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(a, b), p| (a.min(*p), b.max(*p)),
    );
    let (lo, hi) = (lo - DVec2::splat(reach + h), hi + DVec2::splat(reach + h));
    let nx = ((hi.x - lo.x) / h).ceil() as usize + 1;
    let ny = ((hi.y - lo.y) / h).ceil() as usize + 1;
    if nx * ny > 64_000_000 {
        return Vec::new();
    }
    // density at the lattice vertices: a filled area of one point per spacing² reads 1
    let norm = spacing * spacing / (std::f64::consts::TAU * sigma * sigma);
    let mut f = vec![0.0; nx * ny];
    let r = (reach / h).ceil() as i64;
    for p in points {
        let (ci, cj) = (
            ((p.x - lo.x) / h).round() as i64,
            ((p.y - lo.y) / h).round() as i64,
        );
        for j in (cj - r).max(0)..=(cj + r).min(ny as i64 - 1) {
            for i in (ci - r).max(0)..=(ci + r).min(nx as i64 - 1) {
                let v = lo + DVec2::new(i as f64, j as f64) * h;
                let d2 = v.distance_squared(*p);
                f[j as usize * nx + i as usize] += norm * (-d2 / (2.0 * sigma * sigma)).exp();
            }
        }
    }
    let level = area_preserving_level(&f, points.len() as f64 * 4.0);
    let loops = marching_squares(&f, nx, ny, level, |i, j| lo + DVec2::new(i, j) * h);
    loops
        .into_iter()
        .map(|l| simplify(&l, 0.1 * spacing))
        .filter(|l| l.len() >= 3 && polygon_signed_area(l).abs() >= 4.0 * spacing * spacing)
        .collect()
}

/// The iso-level at which the traced area is the points' own (`lattice_vertices` of the half-spacing lattice: four
/// per point): ½ for points packed like a jittered grid, lower for a looser cluster whose smoothed density never
/// reaches ½ at its rim, but never below `MIN_LEVEL`, so that stray points stay out.
fn area_preserving_level(f: &[f64], lattice_vertices: f64) -> f64 {
    let m = (lattice_vertices.round() as usize).clamp(1, f.len());
    let mut values = f.to_vec();
    let (_, v, _) = values.select_nth_unstable_by(m - 1, |a, b| b.total_cmp(a));
    v.clamp(MIN_LEVEL, 0.5)
}

/// Closed iso-lines at `level` of a field on an `nx × ny` lattice (vertex `(i, j)` at `at(i, j)`), whose border
/// lies below the level.
fn marching_squares(
    f: &[f64],
    nx: usize,
    ny: usize,
    level: f64,
    at: impl Fn(f64, f64) -> DVec2,
) -> Vec<Vec<DVec2>> {
    // a crossing point on a lattice edge, keyed by the edge: (i, j, 0) horizontal from (i, j), (i, j, 1) vertical
    type Key = (usize, usize, u8);
    let value = |i: usize, j: usize| f[j * nx + i] - level;
    let point = |k: Key| {
        let (i, j, dir) = k;
        let (i2, j2) = if dir == 0 { (i + 1, j) } else { (i, j + 1) };
        let (a, b) = (value(i, j), value(i2, j2));
        let t = if (a - b).abs() > 1e-300 {
            a / (a - b)
        } else {
            0.5
        };
        let (x, y) = (
            i as f64 + t * (i2 - i) as f64,
            j as f64 + t * (j2 - j) as f64,
        );
        at(x, y)
    };
    // ordered, so that loops start at the same lattice edge on every run (a hash map's order is random)
    let mut next: BTreeMap<Key, Key> = BTreeMap::new();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let inside = [
                value(i, j) > 0.0,
                value(i + 1, j) > 0.0,
                value(i + 1, j + 1) > 0.0,
                value(i, j + 1) > 0.0,
            ];
            let case = inside
                .iter()
                .enumerate()
                .fold(0u8, |c, (k, &b)| c | (u8::from(b) << k));
            let (bottom, right, top, left) = ((i, j, 0), (i + 1, j, 1), (i, j + 1, 0), (i, j, 1));
            // segments oriented with the inside on their right, so that they link into loops
            let segments: &[(Key, Key)] = match case {
                1 => &[(left, bottom)],
                2 => &[(bottom, right)],
                3 => &[(left, right)],
                4 => &[(right, top)],
                5 => &[(left, top), (right, bottom)],
                6 => &[(bottom, top)],
                7 => &[(left, top)],
                8 => &[(top, left)],
                9 => &[(top, bottom)],
                10 => &[(top, right), (bottom, left)],
                11 => &[(top, right)],
                12 => &[(right, left)],
                13 => &[(right, bottom)],
                14 => &[(bottom, left)],
                _ => &[],
            };
            for &(a, b) in segments {
                next.insert(a, b);
            }
        }
    }
    let mut loops = Vec::new();
    while let Some(&start) = next.keys().next() {
        let mut loop_points = Vec::new();
        let mut k = start;
        while let Some(n) = next.remove(&k) {
            loop_points.push(point(k));
            k = n;
        }
        if loop_points.len() >= 3 {
            loops.push(loop_points);
        }
    }
    loops
}

/// Douglas–Peucker simplification of a closed loop.
fn simplify(points: &[DVec2], tolerance: f64) -> Vec<DVec2> {
    if points.len() < 4 {
        return points.to_vec();
    }
    // split the loop at its farthest point from the first
    let far = (0..points.len())
        .max_by(|&a, &b| {
            points[a]
                .distance_squared(points[0])
                .total_cmp(&points[b].distance_squared(points[0]))
        })
        .unwrap_or(0);
    let mut ring: Vec<DVec2> = points.to_vec();
    ring.push(points[0]);
    let mut kept = vec![false; ring.len()];
    kept[0] = true;
    kept[far] = true;
    douglas_peucker(&ring, 0, far, tolerance, &mut kept, |_| true);
    douglas_peucker(&ring, far, ring.len() - 1, tolerance, &mut kept, |_| true);
    ring.iter()
        .zip(&kept)
        .take(points.len())
        .filter(|(_, k)| **k)
        .map(|(p, _)| *p)
        .collect()
}

/// An island of a set of contours combined by the even-odd rule: a contour inside an even number of others, with
/// the contours directly inside it (its lakes).
#[derive(Clone, Debug, PartialEq)]
pub struct Island {
    /// Index of its outer contour.
    pub outer: usize,
    /// Indices of its lakes.
    pub lakes: Vec<usize>,
    /// Its land: the outer contour's area less its lakes' (m²).
    pub area: f64,
}

/// The islands of `contours` (see `Island`), in the order of their outer contours.
pub fn islands(contours: &[Vec<DVec2>]) -> Vec<Island> {
    let valid = |c: &Vec<DVec2>| c.len() >= 3;
    // per contour: the contours holding its first vertex
    let holders: Vec<Vec<usize>> = contours
        .iter()
        .enumerate()
        .map(|(i, c)| {
            if !valid(c) {
                return Vec::new();
            }
            (0..contours.len())
                .filter(|&j| j != i && valid(&contours[j]))
                .filter(|&j| crate::geom::polygon_contains(&contours[j], c[0]))
                .collect()
        })
        .collect();
    let area = |i: usize| polygon_signed_area(&contours[i]).abs();
    (0..contours.len())
        .filter(|&i| valid(&contours[i]) && holders[i].len().is_multiple_of(2))
        .map(|i| {
            let depth = holders[i].len();
            let lakes: Vec<usize> = (0..contours.len())
                .filter(|&j| holders[j].len() == depth + 1 && holders[j].contains(&i))
                .collect();
            let land = area(i) - lakes.iter().map(|&j| area(j)).sum::<f64>();
            Island {
                outer: i,
                lakes,
                area: land.max(0.0),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An island with a lake and a second island: the values read a block of points at a time are those read
    /// one point at a time, on land, in the lake and at sea.
    #[test]
    fn signed_distances_at_once_are_those_one_by_one() {
        let ring = |c: DVec2, r: f64, n: usize| -> Vec<DVec2> {
            (0..n)
                .map(|i| c + DVec2::from_angle(i as f64 / n as f64 * std::f64::consts::TAU) * r)
                .collect()
        };
        let mut lake = ring(DVec2::ZERO, 12.0, 40);
        lake.reverse();
        let polygons = Polygons::new(&[
            ring(DVec2::ZERO, 50.0, 120),
            lake,
            ring(DVec2::new(90.0, 0.0), 20.0, 60),
        ]);
        let points: Vec<DVec2> = (0..120)
            .flat_map(|j| {
                (0..120).map(move |i| DVec2::new(i as f64 * 1.7 - 80.0, j as f64 * 1.1 - 66.0))
            })
            .collect();
        let at_once = polygons.sides_and_signed_distances(&points, 15.0);
        assert!(at_once.iter().any(|s| s.0) && at_once.iter().any(|s| !s.0));
        for (p, s) in points.iter().zip(&at_once) {
            let one = polygons.side_and_signed_distance(*p, 15.0);
            assert!(
                one.0 == s.0 && one.1.to_bits() == s.1.to_bits(),
                "{p}: {s:?} against {one:?}"
            );
        }
    }
}

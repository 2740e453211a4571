//! The queries a chain asks of its region for every proposal — containment, the distance to the boundary, the
//! fraction `α` of a circle inside (the window-edge correction) — written once over the few a region answers by
//! its shape: a [`Region`] answers them by reading its parts whole, a [`super::PreparedRegion`] through its
//! indexes, and both give the same answers.
//!
//! `α` is computed exactly (not by sampling): the circle is cut at its crossings with the region's boundary
//! (line segments for rectangles and polygons, a second circle for circles), and each arc between two
//! consecutive crossings is wholly inside or outside, which one test at its midpoint decides. A clipped region's
//! boundary is made of pieces of its parts', so the same crossing-and-midpoint rule gives its `α` exactly.

use super::{segment_intersection, DVec2, Region};
use std::f64::consts::TAU;

/// The questions a synthesis asks its region for every proposal, answered alike by a [`Region`] (reading its
/// parts whole) and by a [`super::PreparedRegion`] (through its indexes). Each answers the first six by its shape;
/// the others are written once on top of them. Among them the fraction `α` of a circle inside the region, exact:
/// the circle is cut where it crosses the boundary (line segments for rectangles and polygons, a second circle for
/// circles, the parts' boundaries for a clipped region) and each arc between two crossings is inside or not as its
/// midpoint is.
pub trait RegionQueries {
    /// Whether `p` lies in the region ([`Region::contains`]).
    fn contains(&self, p: DVec2) -> bool;

    /// The distance from `p` to the region's boundary ([`Region::distance_to_boundary`]).
    fn distance_to_boundary(&self, p: DVec2) -> f64;

    /// `distance_to_boundary(p).min(max)`: a query that only needs to know whether the boundary comes within
    /// `max` lets an index stop looking there.
    fn distance_to_boundary_within(&self, p: DVec2, max: f64) -> f64;

    /// Pushes the angles (in [0, 2π)) at which the circle `C(p, r)` crosses the region's boundary (or its parts'
    /// boundaries).
    fn push_circle_crossings(&self, p: DVec2, r: f64, angles: &mut Vec<f64>);

    /// Pushes the parameters `t` in (0, 1) at which the segment `a`–`b` crosses the region's boundary (or its
    /// parts' boundaries), in no particular order.
    fn push_segment_crossings(&self, a: DVec2, b: DVec2, out: &mut Vec<f64>);

    /// The axis-aligned bounding box (min, max), as [`Region::bbox`] gives it.
    fn bbox(&self) -> (DVec2, DVec2);

    /// The corners (min, max) when the region is an axis-aligned rectangle, whose `α` has a closed form.
    fn rectangle(&self) -> Option<(DVec2, DVec2)> {
        None
    }

    /// Whether `p` lies in the region at least `r` from its boundary: the whole disc `D(p, r)` is inside and the
    /// window-edge correction has nothing to correct there.
    fn covers_disc(&self, p: DVec2, r: f64) -> bool {
        self.contains(p) && self.distance_to_boundary_within(p, r) >= r
    }

    /// 0 inside, else the distance to the region's boundary.
    fn distance_outside(&self, p: DVec2) -> f64 {
        if self.contains(p) {
            0.0
        } else {
            self.distance_to_boundary(p)
        }
    }

    /// Fraction `α ∈ [0, 1]` of the circumference of the circle `C(p, r)` that lies inside the region
    /// (the window-edge correction of Section 4.1). Exact: see the module documentation.
    fn circle_fraction_inside(&self, p: DVec2, r: f64) -> f64 {
        let inside = self.contains(p);
        let near = if r > 0.0 && r.is_finite() {
            self.distance_to_boundary_within(p, r)
        } else {
            0.0
        };
        circle_fraction(self, p, r, inside, near)
    }

    /// Parameters `t` in (0, 1) at which the segment `a`–`b` crosses the region's boundary, ascending.
    fn segment_crossings(&self, a: DVec2, b: DVec2) -> Vec<f64> {
        let mut out = Vec::new();
        self.push_segment_crossings(a, b, &mut out);
        out.sort_by(f64::total_cmp);
        out
    }

    /// A polyline cut at the region's boundary: the pieces inside it and the pieces outside it.
    fn clip_polyline(&self, points: &[DVec2]) -> (Vec<Vec<DVec2>>, Vec<Vec<DVec2>>) {
        let (mut inside, mut outside) = (Vec::new(), Vec::new());
        if points.len() < 2 {
            return (inside, outside);
        }
        let mut current: Vec<DVec2> = vec![points[0]];
        let mut current_in = self.contains(points[0]);
        for w in points.windows(2) {
            let (a, b) = (w[0], w[1]);
            let mut cuts = self.segment_crossings(a, b);
            cuts.push(1.0);
            let mut t0 = 0.0;
            for t in cuts {
                let p = a + (b - a) * t;
                let mid = a + (b - a) * (0.5 * (t0 + t));
                let piece_in = self.contains(mid);
                if piece_in != current_in {
                    let start = *current.last().unwrap_or(&a);
                    let done = std::mem::replace(&mut current, vec![start]);
                    if done.len() >= 2 {
                        if current_in {
                            inside.push(done);
                        } else {
                            outside.push(done);
                        }
                    }
                    current_in = piece_in;
                }
                current.push(p);
                t0 = t;
            }
        }
        if current.len() >= 2 {
            if current_in {
                inside.push(current);
            } else {
                outside.push(current);
            }
        }
        (inside, outside)
    }

    /// Uniform random point in the region (rejection from the bounding box); `None` after many misses.
    fn sample_uniform<R: rand::Rng>(&self, rng: &mut R) -> Option<DVec2> {
        let (lo, hi) = self.bbox();
        for _ in 0..1000 {
            let p = DVec2::new(rng.random_range(lo.x..=hi.x), rng.random_range(lo.y..=hi.y));
            if self.contains(p) {
                return Some(p);
            }
        }
        None
    }
}

/// [`RegionQueries::circle_fraction_inside`] from what it shares with the other circles around `p`: whether `p` is
/// inside, and `near`, the distance from `p` to the boundary within some reach of at least `r`
/// (`distance_to_boundary_within(p, reach)`). Per distance bin of a point, only the crossings are asked anew.
pub(crate) fn circle_fraction<S: RegionQueries + ?Sized>(
    region: &S,
    p: DVec2,
    r: f64,
    inside: bool,
    near: f64,
) -> f64 {
    let all_or_nothing = if inside { 1.0 } else { 0.0 };
    if !(r > 0.0) || !r.is_finite() || near.min(r) >= r {
        return all_or_nothing;
    }
    if let Some((lo, hi)) = region.rectangle() {
        return rectangle_circle_fraction(lo, hi, p, r);
    }
    let mut angles: Vec<f64> = Vec::with_capacity(8);
    region.push_circle_crossings(p, r, &mut angles);
    if angles.is_empty() {
        let probe = p + DVec2::new(r, 0.0);
        return if region.contains(probe) { 1.0 } else { 0.0 };
    }
    angles.sort_by(f64::total_cmp);
    let mut covered = 0.0;
    for i in 0..angles.len() {
        let a0 = angles[i];
        let a1 = if i + 1 < angles.len() {
            angles[i + 1]
        } else {
            angles[0] + TAU
        };
        let span = a1 - a0;
        if span <= 0.0 {
            continue;
        }
        let mid = 0.5 * (a0 + a1);
        if region.contains(p + DVec2::new(mid.cos(), mid.sin()) * r) {
            covered += span;
        }
    }
    (covered / TAU).clamp(0.0, 1.0)
}

/// The fraction of the circle `C(p, r)` inside the rectangle `lo..hi`: one less the union of the arcs beyond its
/// sides, the arc beyond a side at signed distance `d` from `p` being `2 acos(d / r)` wide about the side's normal
/// (the crossings and midpoints of [`circle_fraction`] without their arctangents, sines and allocation).
fn rectangle_circle_fraction(lo: DVec2, hi: DVec2, p: DVec2, r: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, PI};
    let sides = [
        (hi.x - p.x, 0.0),
        (hi.y - p.y, FRAC_PI_2),
        (p.x - lo.x, PI),
        (p.y - lo.y, 3.0 * FRAC_PI_2),
    ];
    if sides.iter().all(|(d, _)| *d >= 0.0) {
        // inside, each arc is at most a half circle: only the arcs of neighbouring sides can overlap, by
        // `θᵢ + θⱼ − π/2`, and no three do (a point is not beyond two opposite sides at once)
        let half = sides.map(|(d, _)| if d >= r { 0.0 } else { (d / r).acos() });
        let overlap: f64 = (0..4)
            .map(|i| (half[i] + half[(i + 1) % 4] - FRAC_PI_2).max(0.0))
            .sum();
        let beyond = 2.0 * half.iter().sum::<f64>() - overlap;
        return (1.0 - beyond / TAU).clamp(0.0, 1.0);
    }
    // the arcs beyond, in [0, 2π) (one crossing 0 split in two)
    let mut arcs = [(0.0, 0.0); 8];
    let mut n = 0;
    for (d, normal) in sides {
        if d >= r {
            continue;
        }
        if d <= -r {
            return 0.0;
        }
        let half = (d / r).acos();
        let (a, b) = (normal - half, normal + half);
        let pieces = if a < 0.0 {
            [(a + TAU, TAU), (0.0, b)]
        } else if b > TAU {
            [(a, TAU), (0.0, b - TAU)]
        } else {
            [(a, b), (0.0, 0.0)]
        };
        for piece in pieces.into_iter().filter(|(a, b)| b > a) {
            arcs[n] = piece;
            n += 1;
        }
    }
    let arcs = &mut arcs[..n];
    arcs.sort_by(|x, y| x.0.total_cmp(&y.0));
    let (mut beyond, mut end) = (0.0, 0.0f64);
    for &(a, b) in arcs.iter() {
        if b > end {
            beyond += b - a.max(end);
            end = b;
        }
    }
    (1.0 - beyond / TAU).clamp(0.0, 1.0)
}

/// Pushes the angles at which the circle `C(p, r)` crosses the segment `a`–`b`.
pub(super) fn push_segment_crossings(p: DVec2, r: f64, a: DVec2, b: DVec2, angles: &mut Vec<f64>) {
    // |a + t (b - a) - p| = r, t in [0, 1]
    let ab = b - a;
    let ap = a - p;
    let qa = ab.length_squared();
    if qa <= 0.0 {
        return;
    }
    let qb = 2.0 * ap.dot(ab);
    let qc = ap.length_squared() - r * r;
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 {
        return;
    }
    let s = disc.sqrt();
    for t in [(-qb - s) / (2.0 * qa), (-qb + s) / (2.0 * qa)] {
        if (0.0..=1.0).contains(&t) {
            let q = a + ab * t - p;
            angles.push(q.y.atan2(q.x).rem_euclid(TAU));
        }
    }
}

/// Pushes the parameter `t` in (0, 1) at which the segment `a`–`b` crosses the segment `c`–`d`, if it does.
pub(super) fn push_edge_crossing(a: DVec2, b: DVec2, c: DVec2, d: DVec2, out: &mut Vec<f64>) {
    if let Some((t, _)) = segment_intersection(a, b, c, d) {
        if t > 0.0 && t < 1.0 {
            out.push(t);
        }
    }
}

/// Pushes the parameters `t` in (0, 1) at which the segment `a`–`b` crosses the circle of `center` and `radius`.
fn push_segment_circle_crossings(
    a: DVec2,
    b: DVec2,
    center: DVec2,
    radius: f64,
    out: &mut Vec<f64>,
) {
    // |a + t (b − a) − c| = r
    let ab = b - a;
    let ac = a - center;
    let qa = ab.length_squared();
    if qa > 0.0 {
        let qb = 2.0 * ac.dot(ab);
        let qc = ac.length_squared() - radius * radius;
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            let s = disc.sqrt();
            for t in [(-qb - s) / (2.0 * qa), (-qb + s) / (2.0 * qa)] {
                if t > 0.0 && t < 1.0 {
                    out.push(t);
                }
            }
        }
    }
}

/// Pushes the angles at which the circle `C(p, r)` crosses the circle of `center` and `radius`.
fn push_circle_circle_crossings(
    p: DVec2,
    r: f64,
    center: DVec2,
    radius: f64,
    angles: &mut Vec<f64>,
) {
    let dv = center - p;
    let dist = dv.length();
    if dist > 0.0 && dist <= r + radius && dist >= (r - radius).abs() {
        let base = dv.y.atan2(dv.x);
        let cos_half =
            ((r * r + dist * dist - radius * radius) / (2.0 * r * dist)).clamp(-1.0, 1.0);
        let half = cos_half.acos();
        angles.push((base - half).rem_euclid(TAU));
        angles.push((base + half).rem_euclid(TAU));
    }
}

/// [`RegionQueries::contains`] of a clipped region: in every `within` part and in no `without` part.
pub(super) fn clipped_contains<S: RegionQueries>(within: &[S], without: &[S], p: DVec2) -> bool {
    within.iter().all(|r| r.contains(p)) && !without.iter().any(|r| r.contains(p))
}

/// [`RegionQueries::distance_to_boundary_within`] of a clipped region: the nearest of its parts' boundaries
/// (never more than the true distance), each part asked within the nearest found so far.
pub(super) fn clipped_distance<S: RegionQueries>(
    within: &[S],
    without: &[S],
    p: DVec2,
    max: f64,
) -> f64 {
    within.iter().chain(without).fold(max, |best, r| {
        best.min(r.distance_to_boundary_within(p, best))
    })
}

/// [`RegionQueries::push_segment_crossings`] of a clipped region: those of all its parts.
pub(super) fn clipped_segment_crossings<S: RegionQueries>(
    within: &[S],
    without: &[S],
    a: DVec2,
    b: DVec2,
    out: &mut Vec<f64>,
) {
    for part in within.iter().chain(without) {
        part.push_segment_crossings(a, b, out);
    }
}

/// [`RegionQueries::push_circle_crossings`] of a clipped region: those of the parts whose boundary the circle
/// reaches.
pub(super) fn clipped_circle_crossings<S: RegionQueries>(
    within: &[S],
    without: &[S],
    p: DVec2,
    r: f64,
    angles: &mut Vec<f64>,
) {
    // any bound above r tells whether the boundary lies within r
    let reach = if r > 0.0 { 2.0 * r } else { f64::INFINITY };
    for part in within.iter().chain(without) {
        if part.distance_to_boundary_within(p, reach) <= r {
            part.push_circle_crossings(p, r, angles);
        }
    }
}

impl RegionQueries for Region {
    fn contains(&self, p: DVec2) -> bool {
        Region::contains(self, p)
    }

    fn rectangle(&self) -> Option<(DVec2, DVec2)> {
        match self {
            Region::Rect { min, max } => Some((*min, *max)),
            _ => None,
        }
    }

    fn distance_to_boundary(&self, p: DVec2) -> f64 {
        Region::distance_to_boundary(self, p)
    }

    fn distance_to_boundary_within(&self, p: DVec2, max: f64) -> f64 {
        Region::distance_to_boundary(self, p).min(max)
    }

    fn push_circle_crossings(&self, p: DVec2, r: f64, angles: &mut Vec<f64>) {
        match self {
            Region::Rect { .. } | Region::Polygon { .. } => {
                for (a, b) in self.straight_edges() {
                    push_segment_crossings(p, r, a, b, angles);
                }
            }
            Region::Circle { center, radius } => {
                push_circle_circle_crossings(p, r, *center, *radius, angles);
            }
            Region::Clipped { within, without } => {
                clipped_circle_crossings(within, without, p, r, angles);
            }
        }
    }

    fn push_segment_crossings(&self, a: DVec2, b: DVec2, out: &mut Vec<f64>) {
        match self {
            Region::Rect { .. } | Region::Polygon { .. } => {
                for (c, d) in self.straight_edges() {
                    push_edge_crossing(a, b, c, d, out);
                }
            }
            Region::Circle { center, radius } => {
                push_segment_circle_crossings(a, b, *center, *radius, out);
            }
            Region::Clipped { within, without } => {
                clipped_segment_crossings(within, without, a, b, out);
            }
        }
    }

    fn bbox(&self) -> (DVec2, DVec2) {
        Region::bbox(self)
    }
}

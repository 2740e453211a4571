//! Plane geometry of the method: the *active region* `φ` a user selects (Section 3, "Parameter learning":
//! "axis-aligned bounding boxes (default), circles, and polygons defined by sketching a nonintersecting closed
//! contour") and the fraction `α` of a circle inside it used by the window-edge correction of Section 4.1:
//!
//! > "we approximate the area dA' = dA ∩ φ by computing for each point the proportion α_{x_i,r} of the outer
//! > circle's circumference that intersects the active region, and by setting dA' = α_{x_i,r} dA."
//!
//! `α` is computed exactly (not by sampling), once for every kind of region: see [`RegionQueries`].
//!
//! The painting tools synthesize in parts of regions (Section 5.3: a brush step `φ_k` without the regions
//! `φ_i, i < k` already painted in the stroke; the bands of a gradient): a [`Region::Clipped`] is the part of
//! its `within` regions outside all of its `without` regions; its area is integrated on a fine lattice.
//!
//! A synthesis asks its region these questions for every proposal: it asks them of a [`PreparedRegion`], which
//! indexes the region's large polygons once and gives the same answers reading only the edges near each query;
//! [`RegionQueries`] are the questions both answer.
//!
//! A [`VerticalLookup`] answers the height of a triangle mesh under points, as a ray from above meets it.

use crate::error::{Error, Result};
use crate::limits;
pub use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

mod edge_tree;
mod polygon_index;
mod prepared;
mod queries;
mod vertical_lookup;

pub use prepared::PreparedRegion;
pub(crate) use queries::circle_fraction;
pub use queries::RegionQueries;
pub use vertical_lookup::VerticalLookup;

/// An area of the world plane (XY) selected by the user: where an exemplar is read or where content is painted.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum Region {
    /// An axis-aligned box, boundary included.
    Rect {
        /// The corner with the smaller coordinates, world XY (m).
        min: DVec2,
        /// The corner with the larger coordinates, world XY (m).
        max: DVec2,
    },
    /// A disc, boundary included.
    Circle {
        /// World XY (m).
        center: DVec2,
        /// In metres, positive.
        radius: f64,
    },
    /// Closed implicitly, either orientation, non-self-intersecting.
    Polygon {
        /// The vertices, world XY (m), at least three.
        points: Vec<DVec2>,
    },
    /// The points inside every `within` region and inside none of the `without` regions.
    Clipped {
        /// Regions the points must all lie in (at least one).
        within: Vec<Region>,
        /// Regions the points must all lie outside.
        without: Vec<Region>,
    },
}

/// Scanlines that integrate the area of a clipped region (exact along each line, midpoint rule across them).
const AREA_SCANLINES: usize = 512;

/// A box as a message shows it: `x 0.0..200.0, y -5.5..80.0` (metres; far-off values in scientific notation).
pub(crate) fn describe_box((lo, hi): (DVec2, DVec2)) -> String {
    let m = |v: f64| {
        if v.abs() < 1e6 {
            format!("{v:.1}")
        } else {
            format!("{v:.3e}")
        }
    };
    format!("x {}..{}, y {}..{}", m(lo.x), m(hi.x), m(lo.y), m(hi.y))
}

/// Whether both coordinates are finite numbers.
pub(crate) fn finite(p: DVec2) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

/// Every triangle of a mesh of `vertices` vertices names vertices of it; a triangle that does not is refused as
/// `what` and its index ("terrain mesh triangle 7").
pub(crate) fn check_triangle_indices(
    what: &str,
    vertices: usize,
    triangles: &[[u32; 3]],
) -> Result<()> {
    match triangles
        .iter()
        .position(|t| t.iter().any(|&i| i as usize >= vertices))
    {
        Some(k) => Err(Error::invalid(
            format!("{what} {k}"),
            format!("refers to a vertex beyond the {vertices} given"),
        )),
        None => Ok(()),
    }
}

/// The point of the segment `a`-`b` closest to `p`.
pub(crate) fn closest_on_segment(p: DVec2, a: DVec2, b: DVec2) -> DVec2 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    a + ab * t
}

/// Distance from `p` to the segment `a`-`b`.
pub fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    closest_on_segment(p, a, b).distance(p)
}

/// The distance between the segments `a`-`b` and `c`-`d` (0 when they cross).
pub fn segments_distance(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> f64 {
    if segment_intersection(a, b, c, d).is_some() {
        return 0.0;
    }
    segment_distance(a, c, d)
        .min(segment_distance(b, c, d))
        .min(segment_distance(c, a, b))
        .min(segment_distance(d, a, b))
}

/// The segments of an open polyline, in order.
pub(crate) fn polyline_segments(points: &[DVec2]) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
    points.windows(2).map(|w| (w[0], w[1]))
}

/// Length of an open polyline.
pub(crate) fn polyline_length(points: &[DVec2]) -> f64 {
    polyline_segments(points).map(|(a, b)| a.distance(b)).sum()
}

/// Distance from `p` to an open polyline (`f64::INFINITY` when it has fewer than two points).
pub(crate) fn polyline_distance(p: DVec2, points: &[DVec2]) -> f64 {
    polyline_segments(points)
        .map(|(a, b)| segment_distance(p, a, b))
        .fold(f64::INFINITY, f64::min)
}

/// Liang–Barsky clipping: the parameter range `t0..=t1` of `a + t (b − a)`, `t ∈ [0, 1]`, inside the closed
/// axis-aligned box `lo..hi`, or `None` when the segment misses it.
pub(crate) fn clip_segment_to_box(a: DVec2, b: DVec2, lo: DVec2, hi: DVec2) -> Option<(f64, f64)> {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x - lo.x),
        (d.x, hi.x - a.x),
        (-d.y, a.y - lo.y),
        (d.y, hi.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// The intersection of two sorted lists of disjoint intervals.
fn intersect_intervals(a: &[(f64, f64)], b: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        let (lo, hi) = (a[i].0.max(b[j].0), a[i].1.min(b[j].1));
        if hi > lo {
            out.push((lo, hi));
        }
        if a[i].1 < b[j].1 {
            i += 1;
        } else {
            j += 1;
        }
    }
    out
}

/// The parts of the sorted disjoint intervals `a` outside the sorted disjoint intervals `b`.
fn subtract_intervals(a: &[(f64, f64)], b: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for &(mut lo, hi) in a {
        for &(c, d) in b {
            if d <= lo || c >= hi {
                continue;
            }
            if c > lo {
                out.push((lo, c));
            }
            lo = lo.max(d);
        }
        if hi > lo {
            out.push((lo, hi));
        }
    }
    out
}

/// Where the segments `a`–`b` and `c`–`d` meet: the parameters `(t, u)` along each (both in [0, 1]), or `None`
/// when they do not meet or are parallel.
pub(crate) fn segment_intersection(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> Option<(f64, f64)> {
    let r = b - a;
    let s = d - c;
    let denom = r.perp_dot(s);
    let scale = r.length() * s.length();
    if denom.abs() <= 1e-12 * scale || !(scale > 0.0) {
        return None;
    }
    let q = c - a;
    let t = q.perp_dot(s) / denom;
    let u = q.perp_dot(r) / denom;
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)).then_some((t, u))
}

/// Whether `p` lies inside the closed polygon `points` (even-odd rule by a horizontal ray; the polygon closes from
/// its last point to its first).
pub fn polygon_contains(points: &[DVec2], p: DVec2) -> bool {
    let n = points.len();
    let mut inside = false;
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (a, b) = (points[i], points[j]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Signed area of a closed polygon (positive when counter-clockwise).
pub fn polygon_signed_area(points: &[DVec2]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| points[i].perp_dot(points[(i + 1) % n]))
        .sum::<f64>()
        * 0.5
}

/// The counter-clockwise angle from `u` to `v`, in [0, 2π).
pub(crate) fn ccw_angle(u: DVec2, v: DVec2) -> f64 {
    let a = u.perp_dot(v).atan2(u.dot(v));
    if a < 0.0 {
        a + TAU
    } else {
        a
    }
}

/// Douglas–Peucker on the stretch `first..=last` of a polyline: marks in `keep` the vertices that stay (the ends'
/// marks are left as they are). A stretch becomes one edge when every vertex lies within `tolerance` of it and
/// `may_join` accepts the stretch (its vertices, ends included), which is where callers forbid removing vertices
/// (an edge that would cross an obstacle); otherwise its farthest vertex (the first of equals) stays and both
/// halves are simplified in turn.
pub(crate) fn douglas_peucker(
    points: &[DVec2],
    first: usize,
    last: usize,
    tolerance: f64,
    keep: &mut [bool],
    mut may_join: impl FnMut(&[DVec2]) -> bool,
) {
    let mut stack = vec![(first, last)];
    while let Some((s, e)) = stack.pop() {
        if e <= s + 1 {
            continue;
        }
        let (mut far, mut dmax) = (s + 1, -1.0);
        for (q, p) in points.iter().enumerate().take(e).skip(s + 1) {
            let d = segment_distance(*p, points[s], points[e]);
            if d > dmax {
                (far, dmax) = (q, d);
            }
        }
        if dmax <= tolerance && may_join(&points[s..=e]) {
            continue;
        }
        keep[far] = true;
        stack.push((s, far));
        stack.push((far, e));
    }
}

/// Vertices of a polygon region the engine works with: a drawn outline with more is simplified first.
const MAX_DETAIL: usize = 16_384;

/// A closed polygon reduced to at most [`MAX_DETAIL`] vertices by Douglas–Peucker, at the smallest tolerance (from
/// a millionth of its size, doubling) that does it; `None` when it has no more than that, or the reduction would
/// leave fewer than three vertices.
fn simplified_polygon(points: &[DVec2]) -> Option<Vec<DVec2>> {
    if points.len() <= MAX_DETAIL {
        return None;
    }
    let ring: Vec<DVec2> = points
        .iter()
        .copied()
        .chain(points.first().copied())
        .collect();
    let (lo, hi) = points.iter().fold((points[0], points[0]), |(lo, hi), p| {
        (lo.min(*p), hi.max(*p))
    });
    let mut tolerance = 1e-6 * (hi - lo).max_element();
    while tolerance.is_finite() && tolerance > 0.0 {
        let mut keep = vec![false; ring.len()];
        keep[0] = true;
        douglas_peucker(&ring, 0, ring.len() - 1, tolerance, &mut keep, |_| true);
        let kept: Vec<DVec2> = points
            .iter()
            .zip(&keep)
            .filter_map(|(p, k)| k.then_some(*p))
            .collect();
        if kept.len() <= MAX_DETAIL {
            return (kept.len() >= 3 && polygon_signed_area(&kept).abs() > 0.0).then_some(kept);
        }
        tolerance *= 2.0;
    }
    None
}

impl Region {
    /// The region as the engine works with it: every polygon of more than 16,384 vertices simplified to at most
    /// that many (Douglas–Peucker at the smallest tolerance that does it). Each point's work reads every vertex of
    /// its region, and an outline of a million drawn points holds no more shape than that.
    pub fn with_bounded_detail(&self) -> std::borrow::Cow<'_, Region> {
        use std::borrow::Cow;
        match self {
            Region::Polygon { points } => match simplified_polygon(points) {
                Some(points) => Cow::Owned(Region::Polygon { points }),
                None => Cow::Borrowed(self),
            },
            Region::Clipped { within, without } => {
                fn parts(rs: &[Region]) -> Vec<Cow<'_, Region>> {
                    rs.iter().map(|r| r.with_bounded_detail()).collect()
                }
                let (w, o) = (parts(within), parts(without));
                if w.iter().chain(&o).all(|r| matches!(r, Cow::Borrowed(_))) {
                    return Cow::Borrowed(self);
                }
                Cow::Owned(Region::Clipped {
                    within: w.into_iter().map(Cow::into_owned).collect(),
                    without: o.into_iter().map(Cow::into_owned).collect(),
                })
            }
            _ => Cow::Borrowed(self),
        }
    }

    /// Rejects regions with zero area, non-finite coordinates or fewer than three polygon points.
    pub fn validate(&self) -> Result<()> {
        let vertices = self.validate_nested(0)?;
        limits::check(
            "the region",
            vertices as f64,
            limits::MAX_REGION_VERTICES,
            "vertices",
        )
    }

    /// [`Region::validate`] of a part nested `depth` deep; returns its vertex count.
    fn validate_nested(&self, depth: u64) -> Result<usize> {
        limits::check(
            "the region's nesting",
            depth as f64,
            limits::MAX_REGION_DEPTH,
            "levels",
        )?;
        let mut vertices = 0;
        match self {
            Region::Rect { min, max } => {
                if !finite(*min) || !finite(*max) {
                    return Err(Error::bad_region("rectangle has non-finite corners"));
                }
                if max.x <= min.x || max.y <= min.y {
                    return Err(Error::bad_region(format!(
                        "rectangle min {min:?} is not below max {max:?}"
                    )));
                }
            }
            Region::Circle { center, radius } => {
                if !finite(*center) || !radius.is_finite() || *radius <= 0.0 {
                    return Err(Error::bad_region(format!(
                        "circle at {center:?} with radius {radius}"
                    )));
                }
            }
            Region::Polygon { points } => {
                if points.len() < 3 {
                    return Err(Error::bad_region(format!(
                        "polygon has {} points, needs at least 3",
                        points.len()
                    )));
                }
                if points.iter().any(|p| !finite(*p)) {
                    return Err(Error::bad_region("polygon has non-finite points"));
                }
                if polygon_signed_area(points).abs() <= 0.0 {
                    return Err(Error::bad_region("polygon has zero area"));
                }
                vertices = points.len();
            }
            Region::Clipped { within, without } => {
                if within.is_empty() {
                    return Err(Error::bad_region("clipped region has nothing within"));
                }
                for r in within.iter().chain(without) {
                    vertices += r.validate_nested(depth + 1)?;
                }
                let (lo, hi) = self.bbox();
                if !(hi.x > lo.x && hi.y > lo.y) {
                    return Err(Error::bad_region("clipped region's parts do not overlap"));
                }
            }
        }
        Ok(vertices)
    }

    /// The same region moved by `offset`.
    pub fn translated(&self, offset: DVec2) -> Region {
        match self {
            Region::Rect { min, max } => Region::Rect {
                min: *min + offset,
                max: *max + offset,
            },
            Region::Circle { center, radius } => Region::Circle {
                center: *center + offset,
                radius: *radius,
            },
            Region::Polygon { points } => Region::Polygon {
                points: points.iter().map(|p| *p + offset).collect(),
            },
            Region::Clipped { within, without } => Region::Clipped {
                within: within.iter().map(|r| r.translated(offset)).collect(),
                without: without.iter().map(|r| r.translated(offset)).collect(),
            },
        }
    }

    /// Whether the two regions' bounding boxes overlap.
    pub(crate) fn bbox_overlaps(&self, other: &Region) -> bool {
        let (a0, a1) = self.bbox();
        let (b0, b1) = other.bbox();
        a0.x < b1.x && b0.x < a1.x && a0.y < b1.y && b0.y < a1.y
    }

    /// Area (m²): exact for rectangles, circles and polygons, integrated on 512 scanlines for a clipped region
    /// whose parts overlap.
    pub fn area(&self) -> f64 {
        match self {
            Region::Rect { min, max } => ((max.x - min.x) * (max.y - min.y)).max(0.0),
            Region::Circle { radius, .. } => std::f64::consts::PI * radius * radius,
            Region::Polygon { points } => polygon_signed_area(points).abs(),
            Region::Clipped { within, without } => {
                if within.len() == 1 && without.iter().all(|w| !w.bbox_overlaps(&within[0])) {
                    return within[0].area();
                }
                let (lo, hi) = self.bbox();
                if !(hi.y > lo.y && hi.x > lo.x) {
                    return 0.0;
                }
                let dy = (hi.y - lo.y) / AREA_SCANLINES as f64;
                (0..AREA_SCANLINES)
                    .map(|j| {
                        let y = lo.y + (j as f64 + 0.5) * dy;
                        self.scanline(y).iter().map(|(a, b)| b - a).sum::<f64>()
                    })
                    .sum::<f64>()
                    * dy
            }
        }
    }

    /// Whether `p` lies in the region (on the boundary of a rectangle or circle counts as inside; polygons follow
    /// the even-odd rule).
    pub fn contains(&self, p: DVec2) -> bool {
        match self {
            Region::Rect { min, max } => {
                p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y
            }
            Region::Circle { center, radius } => p.distance_squared(*center) <= radius * radius,
            Region::Polygon { points } => polygon_contains(points, p),
            Region::Clipped { within, without } => queries::clipped_contains(within, without, p),
        }
    }

    /// Which of `points` lie inside, as [`Region::contains`] says: the region is prepared once for all of them
    /// ([`PreparedRegion`]).
    pub(crate) fn contains_each(&self, points: &[DVec2]) -> Vec<bool> {
        let prepared = PreparedRegion::new(self);
        points.iter().map(|p| prepared.contains(*p)).collect()
    }

    /// The intervals `[a, b]` of x (ascending, disjoint) where the horizontal line at `y` lies inside the region.
    pub(crate) fn scanline(&self, y: f64) -> Vec<(f64, f64)> {
        match self {
            Region::Rect { min, max } => {
                if y >= min.y && y <= max.y {
                    vec![(min.x, max.x)]
                } else {
                    Vec::new()
                }
            }
            Region::Circle { center, radius } => {
                let h = radius * radius - (y - center.y).powi(2);
                if h > 0.0 {
                    let w = h.sqrt();
                    vec![(center.x - w, center.x + w)]
                } else {
                    Vec::new()
                }
            }
            Region::Polygon { points } => {
                // even-odd rule: the edges' crossings, paired in order
                let n = points.len();
                let mut xs: Vec<f64> = (0..n)
                    .filter_map(|i| {
                        let (a, b) = (points[i], points[(i + 1) % n]);
                        ((a.y > y) != (b.y > y))
                            .then(|| a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y))
                    })
                    .collect();
                xs.sort_by(f64::total_cmp);
                xs.chunks_exact(2).map(|c| (c[0], c[1])).collect()
            }
            Region::Clipped { within, without } => {
                let mut out = match within.first() {
                    Some(r) => r.scanline(y),
                    None => return Vec::new(),
                };
                for r in &within[1..] {
                    out = intersect_intervals(&out, &r.scanline(y));
                }
                for r in without {
                    out = subtract_intervals(&out, &r.scanline(y));
                }
                out
            }
        }
    }

    /// Axis-aligned bounding box (min, max).
    pub fn bbox(&self) -> (DVec2, DVec2) {
        match self {
            Region::Rect { min, max } => (*min, *max),
            Region::Circle { center, radius } => (
                *center - DVec2::splat(*radius),
                *center + DVec2::splat(*radius),
            ),
            Region::Polygon { points } => points.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            ),
            Region::Clipped { within, .. } => within.iter().fold(
                (DVec2::splat(f64::NEG_INFINITY), DVec2::splat(f64::INFINITY)),
                |(lo, hi), r| {
                    let (a, b) = r.bbox();
                    (lo.max(a), hi.min(b))
                },
            ),
        }
    }

    /// Distance from `p` to the region's boundary (whether `p` is inside or not). For a clipped region, the
    /// distance to the nearest boundary of its parts: never more than the true distance.
    pub fn distance_to_boundary(&self, p: DVec2) -> f64 {
        match self {
            Region::Rect { min, max } => {
                if self.contains(p) {
                    (p.x - min.x)
                        .min(max.x - p.x)
                        .min(p.y - min.y)
                        .min(max.y - p.y)
                } else {
                    let d = (*min - p).max(p - *max).max(DVec2::ZERO);
                    d.length()
                }
            }
            Region::Circle { center, radius } => (p.distance(*center) - radius).abs(),
            Region::Polygon { .. } => self
                .straight_edges()
                .map(|(a, b)| segment_distance(p, a, b))
                .fold(f64::INFINITY, f64::min),
            Region::Clipped { within, without } => {
                queries::clipped_distance(within, without, p, f64::INFINITY)
            }
        }
    }

    /// Fraction `α ∈ [0, 1]` of the circumference of the circle `C(p, r)` that lies inside the region
    /// (the window-edge correction of Section 4.1). Exact: the circle is cut where it crosses the boundary, and
    /// each arc between two crossings is inside or not as its midpoint is.
    pub fn circle_fraction_inside(&self, p: DVec2, r: f64) -> f64 {
        RegionQueries::circle_fraction_inside(self, p, r)
    }

    /// The edges of a rectangle's or a polygon's boundary, in order (none for a circle or a clipped region),
    /// without copying a polygon's points: the distance and the circle crossings read them for every query.
    fn straight_edges(&self) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
        let none: &[DVec2] = &[];
        let (n, rect, points) = match self {
            Region::Rect { min, max } => (
                4,
                [
                    *min,
                    DVec2::new(max.x, min.y),
                    *max,
                    DVec2::new(min.x, max.y),
                ],
                none,
            ),
            Region::Polygon { points } => (points.len(), [DVec2::ZERO; 4], points.as_slice()),
            Region::Circle { .. } | Region::Clipped { .. } => (0, [DVec2::ZERO; 4], none),
        };
        let corner = move |i: usize| {
            if points.is_empty() {
                rect[i]
            } else {
                points[i]
            }
        };
        (0..n).map(move |i| (corner(i), corner((i + 1) % n)))
    }

    /// Parameters `t` in (0, 1) at which the segment `a`–`b` crosses the boundary of the region (or of its parts),
    /// ascending.
    pub fn segment_crossings(&self, a: DVec2, b: DVec2) -> Vec<f64> {
        RegionQueries::segment_crossings(self, a, b)
    }

    /// A polyline cut at the region's boundary: the pieces inside it and the pieces outside it.
    pub fn clip_polyline(&self, points: &[DVec2]) -> (Vec<Vec<DVec2>>, Vec<Vec<DVec2>>) {
        RegionQueries::clip_polyline(self, points)
    }

    /// The smaller side of the bounding box (a size scale of the region).
    pub(crate) fn smaller_side(&self) -> f64 {
        let (lo, hi) = self.bbox();
        (hi.x - lo.x).min(hi.y - lo.y)
    }
}

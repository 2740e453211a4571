//! The shape of a mapped building or area in metres: its rings (outer rings counter-clockwise, holes clockwise, no
//! closing repetition), its area and area centroid, and its size and orientation as those of its minimum-area
//! bounding rectangle (the rectangle of least area holding every outer vertex: one of its sides lies along an edge
//! of the convex hull, so each hull edge's direction is tried; the first of equal areas wins).

use crate::geom::polygon_signed_area;
use glam::DVec2;
use std::f64::consts::PI;

/// A ring without its closing repetition nor repeated consecutive vertices, if it still encloses an area.
pub(crate) fn open_ring(ring: Vec<DVec2>) -> Option<Vec<DVec2>> {
    let mut out: Vec<DVec2> = Vec::with_capacity(ring.len());
    for p in ring {
        if out.last() != Some(&p) {
            out.push(p);
        }
    }
    while out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    (out.len() >= 3 && polygon_signed_area(&out) != 0.0).then_some(out)
}

/// The ring turned to the orientation of its role: counter-clockwise when `outer`, clockwise for a hole.
pub(crate) fn oriented(mut ring: Vec<DVec2>, outer: bool) -> Vec<DVec2> {
    if (polygon_signed_area(&ring) > 0.0) != outer {
        ring.reverse();
    }
    ring
}

/// Rings of a shape in metres (polygons of rings, the outer first), opened and oriented; a polygon whose outer ring
/// encloses nothing is left out, and so is such a hole.
pub(crate) fn rings_of(polygons: Vec<Vec<Vec<DVec2>>>) -> Vec<Vec<DVec2>> {
    let mut out = Vec::new();
    for polygon in polygons {
        let mut rings = polygon.into_iter();
        let Some(outer) = rings.next().and_then(open_ring) else {
            continue;
        };
        out.push(oriented(outer, true));
        out.extend(rings.filter_map(open_ring).map(|h| oriented(h, false)));
    }
    out
}

/// Area (m²) of oriented rings: outer rings add, holes take away.
pub(crate) fn area(rings: &[Vec<DVec2>]) -> f64 {
    rings.iter().map(|r| polygon_signed_area(r)).sum()
}

/// The area centroid of oriented rings (the mean of their vertices where they enclose no area).
pub(crate) fn centroid(rings: &[Vec<DVec2>]) -> DVec2 {
    let Some(o) = rings.iter().flatten().next().copied() else {
        return DVec2::ZERO;
    };
    let (mut twice_area, mut sum, mut mean, mut n) = (0.0, DVec2::ZERO, DVec2::ZERO, 0.0);
    for ring in rings {
        for (i, p) in ring.iter().enumerate() {
            let (p, q) = (*p - o, ring[(i + 1) % ring.len()] - o);
            let cross = p.perp_dot(q);
            twice_area += cross;
            sum += (p + q) * cross;
            mean += p;
            n += 1.0;
        }
    }
    if twice_area.abs() > 0.0 {
        o + sum / (3.0 * twice_area)
    } else {
        o + mean / n
    }
}

/// The minimum-area bounding rectangle of points: (length, width, orientation), the length the longer side, the
/// orientation the angle of the long side from +X (east), counter-clockwise, in [0, π).
pub fn min_area_rectangle(points: &[DVec2]) -> (f64, f64, f64) {
    let hull = convex_hull(points);
    if hull.len() < 2 {
        return (0.0, 0.0, 0.0);
    }
    let o = hull[0];
    let mut best: Option<(f64, f64, f64, f64)> = None; // area, length along the edge, across, angle
    for i in 0..hull.len() {
        let edge = hull[(i + 1) % hull.len()] - hull[i];
        let len = edge.length();
        if !(len > 0.0) {
            continue;
        }
        let u = edge / len;
        let v = u.perp();
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for p in &hull {
            let d = *p - o;
            let q = DVec2::new(d.dot(u), d.dot(v));
            lo = lo.min(q);
            hi = hi.max(q);
        }
        let size = hi - lo;
        let area = size.x * size.y;
        if best.is_none_or(|b| area < b.0) {
            best = Some((area, size.x, size.y, u.y.atan2(u.x)));
        }
    }
    let Some((_, along, across, angle)) = best else {
        return (0.0, 0.0, 0.0);
    };
    let (length, width, angle) = if along >= across {
        (along, across, angle)
    } else {
        (across, along, angle + 0.5 * PI)
    };
    (length, width, angle.rem_euclid(PI))
}

/// The convex hull of points, counter-clockwise, without collinear points (Andrew's monotone chain).
fn convex_hull(points: &[DVec2]) -> Vec<DVec2> {
    let mut pts: Vec<DVec2> = points.to_vec();
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = hull.len();
        let ordered: Box<dyn Iterator<Item = &DVec2>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for p in ordered {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], *p) <= 0.0
            {
                hull.pop();
            }
            hull.push(*p);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turned_rectangle_keeps_its_size_and_angle() {
        let angle: f64 = 0.6;
        let (u, v) = (DVec2::from_angle(angle), DVec2::from_angle(angle).perp());
        let corners = [DVec2::ZERO, u * 12.0, u * 12.0 + v * 8.0, v * 8.0];
        let ring: Vec<DVec2> = corners
            .iter()
            .map(|c| *c + DVec2::new(500.0, -40.0))
            .collect();
        let (length, width, orientation) = min_area_rectangle(&ring);
        assert!((length - 12.0).abs() < 1e-9 && (width - 8.0).abs() < 1e-9);
        assert!((orientation - angle).abs() < 1e-9, "{orientation}");
        let rings = rings_of(vec![vec![ring
            .iter()
            .rev()
            .copied()
            .chain([ring[3]])
            .collect()]]);
        assert!((area(&rings) - 96.0).abs() < 1e-9);
        let c = centroid(&rings);
        let expected = DVec2::new(500.0, -40.0) + u * 6.0 + v * 4.0;
        assert!(c.distance(expected) < 1e-9);
    }

    #[test]
    fn holes_take_area_away() {
        let square = |s: f64| {
            vec![
                DVec2::new(-s, -s),
                DVec2::new(s, -s),
                DVec2::new(s, s),
                DVec2::new(-s, s),
            ]
        };
        let rings = rings_of(vec![vec![square(10.0), square(5.0)]]);
        assert!(polygon_signed_area(&rings[1]) < 0.0);
        assert!((area(&rings) - 300.0).abs() < 1e-9);
    }
}

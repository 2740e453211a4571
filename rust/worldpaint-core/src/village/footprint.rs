//! Building footprints: thesis 3.3.5 ("Building Footprint Computation"). Footprints are quadrilaterals, "the most
//! frequently observed shape for buildings":
//!
//! > "We initialize a quad in each parcel, at the closest position to the road, and oriented according to the
//! > closest normal to the road. The quad grows until it either reaches the maximal size for its building type,
//! > or collides with the contour of the parcel. If one of the segments is close to the contour, its vertices are
//! > projected onto it, enabling the generation of terraced houses when several neighboring houses use this
//! > strategy."
//!
//! The closest position to the road is the middle of the stretch of the contour that faces the road (the contour
//! points within 1.5 m of the smallest distance to a road centre line), so a parcel fronting a
//! straight road gets its house centred on its frontage. The quad's front wall lies along the road tangent there;
//! its left, right and back walls move out in small steps, each until it would leave the parcel or the size
//! reaches `max_size` (width along the road, depth away from it). Where the contour is not parallel to the road
//! or the frontage ends at a slanted side, a few set-backs of the front wall and shifts along it are tried, and
//! the largest quad kept (the nearest to the road among near equals); the search stops at the first quad of full
//! size. Last, a wall whose two ends lie within `snap` of a nearly parallel contour edge (within 15°) is projected
//! onto that edge's line, when the quad still fits: two neighbours whose houses fill their frontage then stand on
//! their shared parcel boundary, wall to wall.
//!
//! A footprint lies inside its parcel and keeps `road_width / 2` from every road centre line (both are checked at
//! every step), so footprints never overlap roads nor each other, except along shared walls.

use super::road_index::RoadIndex;
use super::{HouseFootprint, Parcel, Road};
use crate::error::{check, Error, Result};
use crate::geom::{
    polygon_contains, polygon_signed_area, segment_distance, segment_intersection,
    segments_distance,
};
use glam::DVec2;
use rayon::prelude::*;

/// The footprint of one parcel, or `None` when not even a `min_size` quad fits in it (or the inputs are not
/// usable: a degenerate contour, no road, sizes that are not positive with `min_size <= max_size`).
pub fn house_footprint(
    parcel: &Parcel,
    roads: &[Road],
    road_width: f64,
    min_size: [f64; 2],
    max_size: [f64; 2],
    snap: f64,
) -> Option<HouseFootprint> {
    let index = RoadIndex::new(roads, road_width.max(8.0));
    footprint_indexed(parcel, &index, road_width, (min_size, max_size), snap, 0.0)
}

/// The footprints of many parcels in parallel: `sizes[i]` holds the `(min_size, max_size)` of `parcels[i]`.
pub fn house_footprints(
    parcels: &[Parcel],
    sizes: &[([f64; 2], [f64; 2])],
    roads: &[Road],
    road_width: f64,
    snap: f64,
) -> Result<Vec<Option<HouseFootprint>>> {
    check::same_len("footprint sizes", sizes.len(), parcels.len())?;
    check::non_negative("footprint road width", road_width)?;
    check::non_negative("footprint snapping distance", snap)?;
    for (i, (min, max)) in sizes.iter().enumerate() {
        if !(0..2)
            .all(|k| min[k].is_finite() && min[k] > 0.0 && max[k].is_finite() && max[k] >= min[k])
        {
            return Err(Error::invalid(
                format!("footprint sizes of parcel {i}"),
                format!("need 0 < min <= max, got {min:?} and {max:?}"),
            ));
        }
    }
    let index = RoadIndex::new(roads, road_width.max(8.0));
    Ok(parcels
        .par_iter()
        .zip(sizes.par_iter())
        .map(|(p, sizes)| footprint_indexed(p, &index, road_width, *sizes, snap, 0.0))
        .collect())
}

/// A quad in the frame of the road: its front wall from `q + n * front - u * left` to `q + n * front + u * right`
/// (`-left <= right`; the quad need not cover `q`'s place along the road), `depth` along `n`.
#[derive(Clone, Copy, Debug)]
struct Quad {
    front: f64,
    left: f64,
    right: f64,
    depth: f64,
}

struct Frame {
    q: DVec2,
    /// Along the road, with the parcel on its left.
    u: DVec2,
    /// Away from the road.
    n: DVec2,
}

impl Frame {
    /// The frame turned by `angle` (radians, counter-clockwise) about its origin.
    fn turned(self, angle: f64) -> Frame {
        let r = DVec2::from_angle(angle);
        Frame {
            q: self.q,
            u: r.rotate(self.u),
            n: r.rotate(self.n),
        }
    }

    fn corners(&self, r: &Quad) -> [DVec2; 4] {
        let f = self.q + self.n * r.front;
        let c0 = f - self.u * r.left;
        let c1 = f + self.u * r.right;
        [c0, c1, c1 + self.n * r.depth, c0 + self.n * r.depth]
    }
}

/// Points of a contour within this distance (m) of the closest one to the road make the frontage: a simplified
/// front is not exactly parallel to its road.
pub(crate) const FRONT_TOLERANCE: f64 = 1.5;

/// [`house_footprint`] with the roads already indexed (cells of at least 8 m), as many parcels share them, and
/// the quad turned by `turn` (radians) from the road's direction.
pub(crate) fn footprint_indexed(
    parcel: &Parcel,
    index: &RoadIndex,
    road_width: f64,
    (min_size, max_size): ([f64; 2], [f64; 2]),
    snap: f64,
    turn: f64,
) -> Option<HouseFootprint> {
    let sizes_ok = (0..2).all(|k| {
        min_size[k].is_finite()
            && min_size[k] > 0.0
            && max_size[k].is_finite()
            && max_size[k] >= min_size[k]
    });
    if !sizes_ok
        || !(road_width.is_finite() && road_width >= 0.0)
        || !(snap.is_finite() && snap >= 0.0)
    {
        return None;
    }
    if index.is_empty() {
        return None;
    }
    let poly = counter_clockwise(&parcel.contour)?;
    let scale = poly
        .iter()
        .fold(1.0f64, |m, p| m.max(p.abs().max_element()));
    let eps = 1e-9 * scale;
    let half = 0.5 * road_width;
    let frame = road_frame(&poly, index)?.turned(turn);
    let near = roads_near(index, &poly, half);
    let fits = |corners: &[DVec2; 4]| {
        quad_inside(&poly, corners, eps) && clear_of_roads(&near, corners, half)
    };

    let quad = largest_quad(&frame, min_size, max_size, &fits)?;
    let mut corners = frame.corners(&quad);
    // walls near the contour are projected onto it: neighbours then share them
    for side in [3usize, 1, 2, 0] {
        let (i, j) = (side, (side + 1) % 4);
        let Some((a, b)) = wall_support(&poly, corners[i], corners[j], snap, eps) else {
            continue;
        };
        let onto = |p: DVec2| a + (b - a) * ((p - a).dot(b - a) / (b - a).length_squared());
        let mut moved = corners;
        moved[i] = onto(corners[i]);
        moved[j] = onto(corners[j]);
        if convex_ccw(&moved, eps) && fits(&moved) {
            corners = moved;
        }
    }
    Some(HouseFootprint {
        seed: parcel.seed,
        corners,
    })
}

/// The contour without repeated points and its closing point, counter-clockwise; None when it has a point that is
/// not finite or no area.
fn counter_clockwise(contour: &[DVec2]) -> Option<Vec<DVec2>> {
    let mut poly: Vec<DVec2> = Vec::with_capacity(contour.len());
    for &p in contour {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return None;
        }
        if poly.last() != Some(&p) {
            poly.push(p);
        }
    }
    while poly.len() > 1 && poly.first() == poly.last() {
        poly.pop();
    }
    if poly.len() < 3 {
        return None;
    }
    let area = polygon_signed_area(&poly);
    if area == 0.0 || !area.is_finite() {
        return None;
    }
    if area < 0.0 {
        poly.reverse();
    }
    Some(poly)
}

/// The largest quad grown from a few set-backs of the front wall and shifts along it, at least `min_size`; a quad
/// nearer the road wins unless a farther one is clearly larger.
fn largest_quad(
    frame: &Frame,
    min_size: [f64; 2],
    max_size: [f64; 2],
    fits: &dyn Fn(&[DVec2; 4]) -> bool,
) -> Option<Quad> {
    let step = (max_size[0].min(max_size[1]) / 64.0).clamp(0.02, 0.25);
    let setback = (max_size[1] / 16.0).max(step);
    let shift = 0.25 * max_size[0];
    let starts = (0..=8).flat_map(|s| {
        [0.0, 1.0, -1.0, 2.0, -2.0, 3.0, -3.0, 4.0, -4.0]
            .map(move |k| (s as f64 * setback, k * shift))
    });
    let mut best: Option<(f64, Quad)> = None;
    for (front, lateral) in starts {
        // a wall-less start, so that a quad at a corner of the parcel may grow along one side only
        let start = Quad {
            front,
            left: -lateral,
            right: lateral,
            depth: step,
        };
        if !fits(&frame.corners(&start)) {
            continue;
        }
        let grown = grow(frame, start, max_size, step, &fits);
        let (width, depth) = (grown.left + grown.right, grown.depth);
        if width + 1e-9 < min_size[0] || depth + 1e-9 < min_size[1] {
            continue;
        }
        let a = width * depth;
        // a quad nearer the road wins unless a farther one is clearly larger
        if best.is_none_or(|(b, _)| a > 1.02 * b) {
            best = Some((a, grown));
        }
        // no later quad, at most the largest size, could be clearly larger
        let largest = max_size[0] * max_size[1];
        if (width >= max_size[0] - 1e-9 && depth >= max_size[1] - 1e-9)
            || best.is_some_and(|(b, _)| largest * (1.0 + 1e-9) < 1.02 * b)
        {
            break;
        }
    }
    best.map(|(_, quad)| quad)
}

/// The frontage middle of the contour and the road frame there.
fn road_frame(poly: &[DVec2], index: &RoadIndex) -> Option<Frame> {
    let m = poly.len();
    let perimeter: f64 = (0..m).map(|i| poly[i].distance(poly[(i + 1) % m])).sum();
    let spacing = (perimeter / 4000.0).max(0.1);
    // samples along the contour with their distance to the roads
    let mut samples: Vec<(DVec2, f64)> = Vec::new();
    for i in 0..m {
        let (a, b) = (poly[i], poly[(i + 1) % m]);
        let steps = ((a.distance(b) / spacing).ceil() as usize).max(1);
        for s in 0..steps {
            let p = a + (b - a) * (s as f64 / steps as f64);
            samples.push((p, index.project(p).distance));
        }
    }
    let dmin = samples.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
    if !dmin.is_finite() {
        return None;
    }
    let near: Vec<bool> = samples
        .iter()
        .map(|s| s.1 <= dmin + FRONT_TOLERANCE)
        .collect();
    // the longest run of near samples, going round the contour
    let count = samples.len();
    let start = (0..count)
        .find(|&i| !near[i])
        .map_or(0, |i| (i + 1) % count);
    let (mut best, mut run) = ((0usize, 0usize), (0usize, 0usize));
    for step in 0..count {
        let i = (start + step) % count;
        if near[i] {
            if run.1 == 0 {
                run = (i, 0);
            }
            run.1 += 1;
            if run.1 > best.1 {
                best = run;
            }
        } else {
            run = (0, 0);
        }
    }
    let q = samples[(best.0 + best.1 / 2) % count].0;
    let proj = index.project(q);
    let (a, b) = index.segments()[proj.segment];
    let mut tangent = (b - a).normalize_or_zero();
    if tangent == DVec2::ZERO {
        tangent = (q - proj.point).perp().normalize_or_zero();
    }
    if tangent == DVec2::ZERO {
        return None;
    }
    let mut n = tangent.perp();
    // the normal points away from the road, into the parcel
    let centroid = poly.iter().copied().sum::<DVec2>() / m as f64;
    let away = if (q - proj.point).length() > 1e-9 {
        q - proj.point
    } else {
        centroid - q
    };
    if n.dot(away) < 0.0 {
        n = -n;
    }
    // the parcel on the left of the front wall: corners counter-clockwise
    let u = DVec2::new(n.y, -n.x);
    Some(Frame { q, u, n })
}

/// Moves the left, right and back walls out in steps of `step` while the quad fits, up to `max_size`.
fn grow(
    frame: &Frame,
    start: Quad,
    max_size: [f64; 2],
    step: f64,
    fits: &impl Fn(&[DVec2; 4]) -> bool,
) -> Quad {
    let mut quad = start;
    let mut active = [true; 3];
    while active.iter().any(|a| *a) {
        for (side, on) in active.iter_mut().enumerate() {
            if !*on {
                continue;
            }
            let room = match side {
                0 | 1 => max_size[0] - quad.left - quad.right,
                _ => max_size[1] - quad.depth,
            };
            if room <= 1e-12 {
                *on = false;
                continue;
            }
            // a full step, then finer ones against the contour
            let mut grown = false;
            let mut s = step.min(room);
            for _ in 0..4 {
                let mut next = quad;
                match side {
                    0 => next.left += s,
                    1 => next.right += s,
                    _ => next.depth += s,
                }
                if fits(&frame.corners(&next)) {
                    quad = next;
                    grown = true;
                    break;
                }
                s *= 0.25;
            }
            if !grown {
                *on = false;
            }
        }
    }
    quad
}

/// Whether the convex quad lies inside the closed simple polygon (touching its boundary allowed).
fn quad_inside(poly: &[DVec2], quad: &[DVec2; 4], eps: f64) -> bool {
    let m = poly.len();
    let inside_poly = |p: DVec2| {
        (0..m).any(|i| segment_distance(p, poly[i], poly[(i + 1) % m]) <= eps)
            || polygon_contains(poly, p)
    };
    // strictly inside the quad, away from its walls
    let inside_quad = |p: DVec2| {
        (0..4).all(|k| {
            let (a, b) = (quad[k], quad[(k + 1) % 4]);
            let len = a.distance(b);
            len > 0.0 && (b - a).perp_dot(p - a) / len > eps
        })
    };
    if !quad.iter().all(|&c| inside_poly(c)) {
        return false;
    }
    for i in 0..m {
        let (a, b) = (poly[i], poly[(i + 1) % m]);
        if inside_quad(a) || inside_quad(0.5 * (a + b)) {
            return false;
        }
        for k in 0..4 {
            let (c, d) = (quad[k], quad[(k + 1) % 4]);
            if let Some((t, u)) = segment_intersection(a, b, c, d) {
                let (lab, lcd) = (a.distance(b), c.distance(d));
                // a proper crossing, not a touch at an end
                if t * lab > eps && (1.0 - t) * lab > eps && u * lcd > eps && (1.0 - u) * lcd > eps
                {
                    return false;
                }
            }
        }
    }
    true
}

/// The road segments that may come within `half` of a quad inside the contour `poly`: the quads of one parcel
/// are tested against these few instead of the index's cells, many times over as they grow.
fn roads_near(index: &RoadIndex, poly: &[DVec2], half: f64) -> Vec<(DVec2, DVec2)> {
    let (lo, hi) = poly.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    // a quad may stand a rounding outside its contour
    let pad = DVec2::splat(half.max(0.0) + 1.0);
    let mut found = Vec::new();
    index.candidates(lo - pad, hi + pad, &mut found);
    found
        .iter()
        .map(|&s| index.segments()[s as usize])
        .collect()
}

/// Whether every wall keeps `half` from the road centre lines `near` it.
fn clear_of_roads(near: &[(DVec2, DVec2)], quad: &[DVec2; 4], half: f64) -> bool {
    if half <= 0.0 {
        return true;
    }
    (0..4).all(|k| {
        let (a, b) = (quad[k], quad[(k + 1) % 4]);
        let (lo, hi) = (a.min(b) - half, a.max(b) + half);
        near.iter().all(|&(p, q)| {
            // a segment whose box lies `half` away from the wall's cannot come nearer
            let apart = p.max(q).cmplt(lo).any() || p.min(q).cmpgt(hi).any();
            apart || segments_distance(a, b, p, q) >= half * (1.0 - 1e-9)
        })
    })
}

/// The contour edge nearly parallel to the wall `p`–`q` (within 15°) that both its ends lie within `snap` of
/// (the nearest such edge), unless the wall already lies on it.
fn wall_support(poly: &[DVec2], p: DVec2, q: DVec2, snap: f64, eps: f64) -> Option<(DVec2, DVec2)> {
    let m = poly.len();
    let wall = q - p;
    let mut best: Option<(f64, (DVec2, DVec2))> = None;
    for k in 0..m {
        let (a, b) = (poly[k], poly[(k + 1) % m]);
        let edge = b - a;
        if edge.length() <= eps
            || wall.perp_dot(edge).abs() > 15f64.to_radians().sin() * wall.length() * edge.length()
        {
            continue;
        }
        let far = segment_distance(p, a, b).max(segment_distance(q, a, b));
        if far <= snap && best.is_none_or(|(d, _)| far < d) {
            best = Some((far, (a, b)));
        }
    }
    let (far, edge) = best?;
    let line = |x: DVec2| (edge.1 - edge.0).perp_dot(x - edge.0).abs() / edge.0.distance(edge.1);
    (far > eps || line(p) > eps || line(q) > eps).then_some(edge)
}

/// Whether four corners make a convex counter-clockwise quad.
fn convex_ccw(c: &[DVec2; 4], eps: f64) -> bool {
    (0..4).all(|k| {
        let (a, b, d) = (c[k], c[(k + 1) % 4], c[(k + 2) % 4]);
        a.distance(b) > eps && (b - a).perp_dot(d - b) > 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_skewed_footprint_turns_from_its_road_and_stays_in_its_parcel_clear_of_the_road() {
        // a 30 m square lot whose front lies 4 m from a road along x
        let road = Road {
            points: vec![DVec2::new(-50.0, 0.0), DVec2::new(80.0, 0.0)],
        };
        let parcel = Parcel {
            seed: 0,
            contour: vec![
                DVec2::new(0.0, 4.0),
                DVec2::new(30.0, 4.0),
                DVec2::new(30.0, 34.0),
                DVec2::new(0.0, 34.0),
            ],
        };
        let index = RoadIndex::new(std::slice::from_ref(&road), 8.0);
        let sizes = ([6.0, 5.0], [12.0, 8.0]);
        let front_angle = |f: &HouseFootprint| {
            let v = f.corners[1] - f.corners[0];
            v.y.atan2(v.x).to_degrees()
        };
        let straight = footprint_indexed(&parcel, &index, 5.0, sizes, 0.0, 0.0);
        let straight = straight.expect("a footprint along the road");
        assert!(front_angle(&straight).abs() < 1e-9);
        for turn in [-25.0f64, 20.0] {
            let skewed = footprint_indexed(&parcel, &index, 5.0, sizes, 0.0, turn.to_radians());
            let skewed = skewed.expect("a skewed footprint");
            assert!(
                (front_angle(&skewed) - turn).abs() < 1e-6,
                "front at {:.2}° for a turn of {turn}°",
                front_angle(&skewed)
            );
            assert!(quad_inside(&parcel.contour, &skewed.corners, 1e-9));
            assert!(clear_of_roads(
                &[(road.points[0], road.points[1])],
                &skewed.corners,
                2.5
            ));
        }
    }
}

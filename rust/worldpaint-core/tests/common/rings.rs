//! The outer rings of buildings and land-use areas, in metres, as the real-data reports reduce them to a point.

use worldpaint_core::DVec2;

/// The area centroid of `rings` taken together; the mean of their vertices when twice their signed area is
/// within `flat` (m²) of zero.
pub fn area_centroid<R: AsRef<[DVec2]>>(rings: &[R], flat: f64) -> DVec2 {
    let o = rings[0].as_ref()[0];
    let (mut area, mut sum) = (0.0, DVec2::ZERO);
    let (mut mean, mut n) = (DVec2::ZERO, 0.0);
    for ring in rings {
        let ring = ring.as_ref();
        for (i, p) in ring.iter().enumerate() {
            let (p, q) = (*p - o, ring[(i + 1) % ring.len()] - o);
            let cross = p.perp_dot(q);
            area += cross;
            sum += (p + q) * cross;
            mean += p;
            n += 1.0;
        }
    }
    if area.abs() > flat {
        o + sum / (3.0 * area)
    } else {
        o + mean / n
    }
}

//! Statistics of a parcel layout: the thesis's validation of land parcels (3.5, Emilien 2014 ch. 3) counts the
//! mean number of neighbouring parcels and of contour edges per parcel.

use super::finite;
use crate::graph::{angle_between, SegmentIndex};
use glam::DVec2;

/// Consecutive contour edges turning by less than this many degrees count as one edge in
/// [`parcel_statistics`]: a vertex where a neighbour's boundary meets a straight side is not a corner.
pub(crate) const STRAIGHT_DEGREES: f64 = 10.0;

/// What the thesis measures on a parcel layout: the number of parcels, the mean number of neighbouring parcels
/// and the mean number of contour edges per parcel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ParcelStatistics {
    /// Parcels counted (contours with at least three distinct points).
    pub parcels: usize,
    /// Mean number of neighbouring parcels per parcel.
    pub mean_neighbours: f64,
    /// Mean number of contour edges per parcel, nearly straight runs counted as one edge.
    pub mean_edges: f64,
}

/// Mean number of neighbouring parcels (sharing a boundary stretch longer than `tolerance`) and of contour edges
/// per parcel, with edges turning by less than 10° merged.
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

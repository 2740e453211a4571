//! Per-instance statistics of real content (issue 41, "houses face their street"): how large the instances are and
//! how they are turned to the nearest road. The paper learns only positions (Section 4.1); a color learned from a
//! real village must also give its houses the village's sizes and turn them to their streets.
//!
//! * **Size.** The histogram of `ln(scale)` on [`SIZE_BINS`] bins from the smallest to the largest scale. An
//!   instance carries one uniform scale (its prototype's size times it), so one dimension is all there is to learn;
//!   the log because real sizes spread over an order of magnitude (a 4 m shed and a 40 m barn of one category): on
//!   a linear scale the few large ones would make bins as wide as a small house, on the log each bin is the same
//!   share (under 10 % from 3 m to 60 m) of the sizes it holds.
//! * **Facing.** An instance's direction is its local +X axis (its rotation about Z). What is learned is its angle
//!   from the direction towards the nearest point of the roads, counter-clockwise over [0, 2π), on [`FACING_BINS`]
//!   bins, for the instances closer than the reach to a road. The full turn rather than the angle modulo π: an
//!   exemplar made in Blender may give its models a front (the built-in hamlet's cottages have their +X towards the
//!   street), which the synthesis then keeps towards the street on either side of it; a footprint from a map has
//!   none (the import gives its long side's angle modulo π), and its angles are learned as they come, which
//!   reproduces them as well. Towards the nearest point rather than along the nearest segment, because that
//!   direction is the same whichever of two segments meeting at a bend is taken as the nearest (the points beyond
//!   the bend are equally near both). The roads are the graph categories of higher priority with content in the
//!   example (what the synthesis will have painted or kept by the time the category is painted), all of them
//!   together: a house faces whichever way is nearest, a street or a farm track. The reach is the color's radius,
//!   the distance at which the synthesis lets one thing condition another.
//! * **By distance to the road.** One histogram per band of distance, the bands holding equal shares of the
//!   instances near a road (at least [`MIN_PER_BAND`] each, at most [`MAX_BANDS`] bands), because how strictly a
//!   building follows its road depends on how far it stands from it: north of Bayreuth 61 % of the buildings
//!   within 10 m of a road lie along it (within 10°) and 16 % across it, against 31 % and 25 % at 20–30 m and
//!   12 % and 14 % at 60–90 m. One histogram for all would turn the houses on the street as loosely as the barns
//!   behind them.
//! * **Whether the category faces the roads at all.** Unrotated trees near a diagonal road are aligned to the
//!   world, not to the road: a category whose instances all share one rotation keeps it, and facing is kept only
//!   when the instances' long axes (modulo π, folded into [0, π/2]: the reading that a footprint without a front
//!   allows) are at least as concentrated (lower or equal entropy on the same bins) against the road's direction
//!   at its nearest point as against the world's X axis; otherwise the category keeps its world rotation histogram
//!   alone, as before.

use super::structure::Structures;
use crate::geom::{closest_on_segment, DVec2};
use crate::graph::SegmentIndex;
use crate::palette::{Histogram, RoadFacing};
use crate::scene::Instance;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Bins of the histogram of the log of the scale.
pub(crate) const SIZE_BINS: usize = 32;
/// Bins of the angle from the direction towards the nearest road, over [0, 2π) (5° each).
pub(crate) const FACING_BINS: usize = 72;
/// Bins of the folded angles over [0, π/2] that tell whether a category faces the roads (5° each).
const FOLDED_BINS: usize = 18;
/// Bands of distance to the road: as many as hold this many instances each, at most `MAX_BANDS`.
const MIN_PER_BAND: usize = 50;
const MAX_BANDS: usize = 4;

/// The angle between a direction `rotation` (radians from +X) read modulo π and the undirected line of direction
/// `along`, folded into [0, π/2].
fn folded_angle(rotation: f64, along: DVec2) -> f64 {
    let delta = (rotation - along.y.atan2(along.x)).rem_euclid(PI);
    delta.min(PI - delta).clamp(0.0, FRAC_PI_2)
}

/// The histogram of the log of the instances' scales (empty without a positive finite scale).
pub(super) fn size_histogram(instances: &[Instance]) -> Histogram {
    let logs: Vec<f64> = instances
        .iter()
        .filter(|i| i.scale.is_finite() && i.scale > 0.0)
        .map(|i| i.scale.ln())
        .collect();
    let Some(lo) = logs.iter().copied().reduce(f64::min) else {
        return Histogram::zeros(0.0, 1.0, 0);
    };
    let hi = logs.iter().copied().fold(lo, f64::max);
    // one size: a single narrow bin at it
    let width = ((hi - lo) / SIZE_BINS as f64).max(1e-9);
    let n = (((hi - lo) / width).floor() as usize + 1).min(SIZE_BINS);
    let mut h = Histogram::zeros(lo, width, n);
    for v in logs {
        h.add(v.min(h.end() - 1e-9 * width), 1.0);
    }
    h.normalized()
}

/// The direction from `p` towards the nearest point of the segment `a`–`b` (across the segment when `p` lies on
/// it).
pub(crate) fn toward_road(p: DVec2, (a, b): (DVec2, DVec2)) -> DVec2 {
    let toward = closest_on_segment(p, a, b) - p;
    if toward.length() > 1e-9 * (1.0 + p.length()) {
        toward
    } else {
        (b - a).perp()
    }
}

/// The segments of the named graph categories in one index (`None` when they have none).
fn road_index(structures: &Structures, roads: &[String]) -> Option<SegmentIndex> {
    let segments: Vec<(DVec2, DVec2)> = roads
        .iter()
        .filter_map(|r| structures.graph(r))
        .flat_map(|g| g.segments())
        .collect();
    (!segments.is_empty()).then(|| SegmentIndex::new(segments))
}

/// How the instances are turned to the roads `roads` (graph categories) within `reach`, when they face them (see
/// the module documentation); `None` when no instance is near a road, when they all share one rotation, or when
/// the world's axes explain their rotations better.
pub(super) fn road_facing(
    instances: &[Instance],
    structures: &Structures,
    roads: Vec<String>,
    reach: f64,
) -> Option<RoadFacing> {
    let first = instances.first()?.rotation;
    if instances.iter().all(|i| (i.rotation - first).abs() <= 1e-9) {
        return None;
    }
    let index = road_index(structures, &roads)?;
    // (distance to the nearest road, angle from the way to it, folded angles to the road and to the world's X axis)
    // of the instances near one
    let mut near: Vec<(f64, f64, f64, f64)> = instances
        .iter()
        .filter(|i| i.rotation.is_finite())
        .filter_map(|i| {
            let (d, segment) = index.nearest(i.position, reach)?;
            let toward = toward_road(i.position, segment);
            Some((
                d,
                (i.rotation - toward.y.atan2(toward.x)).rem_euclid(TAU),
                folded_angle(i.rotation, toward.perp()),
                folded_angle(i.rotation, DVec2::X),
            ))
        })
        .collect();
    if near.is_empty() {
        return None;
    }
    let folded = |angle: fn(&(f64, f64, f64, f64)) -> f64| {
        let mut h = Histogram::zeros(0.0, FRAC_PI_2 / FOLDED_BINS as f64, FOLDED_BINS);
        for n in &near {
            h.add(angle(n).min(FRAC_PI_2 * (1.0 - 1e-12)), 1.0);
        }
        h
    };
    if entropy(&folded(|n| n.2)) > entropy(&folded(|n| n.3)) {
        return None;
    }
    near.sort_by(|x, y| x.0.total_cmp(&y.0));
    // bands holding equal shares of the instances, split halfway between neighbouring distances
    let n_bands = (near.len() / MIN_PER_BAND).clamp(1, MAX_BANDS);
    let mut bands: Vec<f64> = Vec::with_capacity(n_bands);
    for k in 1..n_bands {
        let split = k * near.len() / n_bands;
        let edge = 0.5 * (near[split - 1].0 + near[split].0);
        if edge > bands.last().copied().unwrap_or(0.0) {
            bands.push(edge);
        }
    }
    bands.push(reach);
    let mut angles =
        vec![Histogram::zeros(0.0, TAU / FACING_BINS as f64, FACING_BINS); bands.len()];
    for (d, from_road, _, _) in &near {
        let band = bands
            .iter()
            .position(|edge| d < edge)
            .unwrap_or(bands.len() - 1);
        angles[band].add(from_road.min(TAU * (1.0 - 1e-12)), 1.0);
    }
    // a band left empty by equal distances joins the one above it
    let mut k = 0;
    while k + 1 < bands.len() {
        if angles[k].total() > 0.0 {
            k += 1;
        } else {
            bands.remove(k);
            angles.remove(k);
        }
    }
    let angles = angles.iter().map(Histogram::normalized).collect();
    Some(RoadFacing {
        roads,
        bands,
        angles,
        near_share: near.len() as f64 / instances.len() as f64,
    })
}

/// Shannon entropy (nats) of a histogram's masses.
fn entropy(h: &Histogram) -> f64 {
    let total = h.total();
    h.values
        .iter()
        .filter(|v| **v > 0.0)
        .map(|v| {
            let p = v / total;
            -p * p.ln()
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_fold_into_a_quarter_turn_whatever_the_sense() {
        let along = DVec2::new(1.0, 1.0);
        let q = std::f64::consts::FRAC_PI_4;
        for (rotation, expected) in [
            (q, 0.0),
            (q + PI, 0.0),
            (q + 0.1, 0.1),
            (q - 0.1, 0.1),
            (q + FRAC_PI_2, FRAC_PI_2),
            (q - FRAC_PI_2 + 0.2, FRAC_PI_2 - 0.2),
        ] {
            let got = folded_angle(rotation, along);
            assert!((got - expected).abs() < 1e-9, "{rotation}: {got}");
            assert!((folded_angle(rotation, -along) - expected).abs() < 1e-9);
        }
    }

    #[test]
    fn sizes_are_binned_on_their_log_from_the_smallest_to_the_largest() {
        let at = |scale: f64| Instance {
            scale,
            ..Instance::at(DVec2::ZERO, 0)
        };
        let h = size_histogram(&[at(4.0), at(40.0), at(10.0), at(10.0)]);
        assert_eq!(h.values.len(), SIZE_BINS);
        assert!((h.start - 4f64.ln()).abs() < 1e-12);
        assert!((h.end() - 40f64.ln()).abs() < 1e-9);
        assert!((h.total() - 1.0).abs() < 1e-12);
        assert_eq!(h.values[SIZE_BINS - 1], 0.25);
        assert_eq!(h.value_at(10f64.ln()), 0.5);
        let one = size_histogram(&[at(2.0), at(2.0)]);
        assert_eq!(one.values, vec![1.0]);
    }
}

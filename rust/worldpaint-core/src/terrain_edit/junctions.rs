//! Where roads meet — crossings, T-junctions, a road ending on another, a road crossing itself: the carriageway
//! profile of a road meets the carriageways given before it instead of stepping onto them.
//!
//! Roads are taken in the order given; the first keeps its profile. A later road *reaches* an earlier carriageway
//! wherever its cross-section at a sample of its centreline (the segment across its carriageway; at its two ends,
//! the round end of the carriageway) comes within half the earlier road's width of the earlier centreline: the two
//! carriageways touch there. There its profile is *held* at the earlier carriageway's height: the earlier profile at
//! the nearest point of the earlier centreline — the height the terrain takes there, since the earlier road keeps
//! the nodes where carriageways overlap. Where several earlier carriageways reach a sample, one that contains the
//! sample wins over one that only touches its cross-section, then the earliest road, then the nearest segment.
//!
//! On each side of a held stretch the profile returns to its own: the difference `δ = z − z_own` goes from its
//! value `δ₀` and grade `δ'₀` at the stretch's end (the grade over at most a width into it) to 0, with no grade,
//! along a cubic Hermite curve over the blend length `L = max(2 × width, 1.5 |δ₀| / 8 %)`. So the profile's grade
//! is continuous (C1) through the stretch's ends; the height difference adds at most 8 % to the grade (its Hermite
//! basis `1 − 3u² + 2u³`, a falling smoothstep, is at most 1.5 / L steep), or spreads over two widths where the heights
//! nearly agree; and the change from the held grade to the road's own is spread over `L` (overshooting by at most a
//! third of it). Where two held stretches are closer than their two blend lengths, the difference runs from one to
//! the other along one Hermite curve without returning to the road's own profile. Near the road's ends a blend
//! keeps its length and stops where the road does, so a road ending just past a junction stays close to it.
//!
//! A road meets itself where, after leaving a sample by more than twice its width, it comes back and its cross-section
//! there reaches the carriageway of that earlier pass: the later pass is held at the earlier pass's height (as the
//! earlier pass is after meeting the other roads).
//!
//! User heights are blended in the same way as profiles taken from the terrain.

use super::roads::RoadProfile;
use crate::geom::{closest_on_segment, segment_distance, segments_distance};
use crate::graph::SegmentIndex;
use glam::DVec2;
use rayon::prelude::*;

/// Blend lengths are at least this many carriageway widths.
const BLEND_WIDTHS: f64 = 2.0;
/// The largest grade (rise per metre) a blend adds to the road's own.
const MAX_ADDED_GRADE: f64 = 0.08;
/// The steepest slope of the Hermite value basis `1 − 3u² + 2u³` over a unit length.
const HERMITE_PEAK: f64 = 1.5;
/// A road has left a sample of itself once it is this many widths away.
const DEPARTURE_WIDTHS: f64 = 2.0;

/// Makes every profile after the first meet the carriageways before it (and its own earlier passes), in order;
/// `widths[r]` is the carriageway width of road `r`.
pub(crate) fn meet_earlier_roads(profiles: &mut [RoadProfile], widths: &[f64]) {
    if profiles.len() != widths.len() || profiles.is_empty() {
        return;
    }
    // every centreline segment of every road; segment `offsets[r] + k` joins samples k and k + 1 of road r
    let mut offsets = Vec::with_capacity(profiles.len() + 1);
    let mut segments = Vec::new();
    for p in profiles.iter() {
        offsets.push(segments.len());
        segments.extend(
            p.points
                .windows(2)
                .map(|w| (w[0].truncate(), w[1].truncate())),
        );
    }
    offsets.push(segments.len());
    let widest = widths.iter().copied().fold(0.0, f64::max);
    // cells a third of the widest carriageway: a query's box, grown by a cell, then holds few segments
    let index = SegmentIndex::with_cell(segments, widest / 3.0);
    let network = Network {
        index: &index,
        offsets: &offsets,
        widths,
        widest,
    };
    for (r, width) in widths.iter().enumerate() {
        let (earlier, rest) = profiles.split_at_mut(r);
        let Some(road) = rest.first_mut() else {
            break;
        };
        let own: Vec<f64> = road.points.iter().map(|p| p.z).collect();
        let plan: Vec<DVec2> = road.points.iter().map(|p| p.truncate()).collect();
        let reached: Vec<Reached> = (0..plan.len())
            .into_par_iter()
            .map(|k| network.reached(r, &plan, &road.s, k, earlier))
            .collect();
        let held: Vec<Option<f64>> = reached.iter().map(|h| h.earlier).collect();
        let met = blend(&road.s, &own, &held, *width);
        // the later passes of the road over itself meet its earlier passes as they now are
        let held_with_itself: Vec<Option<f64>> = reached
            .iter()
            .map(|h| {
                h.earlier.or_else(|| {
                    h.itself
                        .map(|(k, t)| met[k] + t * (met[(k + 1).min(met.len() - 1)] - met[k]))
                })
            })
            .collect();
        let z = if reached
            .iter()
            .any(|h| h.earlier.is_none() && h.itself.is_some())
        {
            blend(&road.s, &own, &held_with_itself, *width)
        } else {
            met
        };
        for (p, z) in road.points.iter_mut().zip(z) {
            p.z = z;
        }
    }
}

/// All the roads' centreline segments in one index.
struct Network<'a> {
    index: &'a SegmentIndex,
    offsets: &'a [usize],
    widths: &'a [f64],
    widest: f64,
}

/// What a sample of a road's centreline reaches.
#[derive(Clone, Copy, Debug, Default)]
struct Reached {
    /// The height of the earlier carriageway it meets.
    earlier: Option<f64>,
    /// An earlier pass of the same road: its segment (joining samples k and k + 1) and the fraction along it.
    itself: Option<(usize, f64)>,
}

impl Network<'_> {
    /// The road and segment a global segment number belongs to.
    fn owner(&self, segment: usize) -> (usize, usize) {
        let r = self.offsets.partition_point(|o| *o <= segment) - 1;
        (r, segment - self.offsets[r])
    }

    /// The carriageways that sample `k` of road `r` (at `plan[k]`, `s[k]` along it) reaches.
    fn reached(
        &self,
        r: usize,
        plan: &[DVec2],
        s: &[f64],
        k: usize,
        earlier: &[RoadProfile],
    ) -> Reached {
        let p = plan[k];
        let half = 0.5 * self.widths[r];
        // the carriageway's cross-section at the sample; at the road's ends, its round end
        let tangent =
            (plan[(k + 1).min(plan.len() - 1)] - plan[k.saturating_sub(1)]).normalize_or_zero();
        let end = k == 0 || k + 1 == plan.len() || tangent == DVec2::ZERO;
        let across = tangent.perp() * half;
        let touches = |a: DVec2, b: DVec2, other_half: f64| {
            // the round end first: the cross-section lies within it
            let near = segment_distance(p, a, b) <= other_half + half;
            near && (end || segments_distance(p - across, p + across, a, b) <= other_half)
        };
        let look = DVec2::splat(half + 0.5 * self.widest);
        let mut candidates = Vec::new();
        self.index.candidates(p - look, p + look, &mut candidates);
        // (outside its carriageway, road, distance) of the best earlier carriageway so far, and its height
        let mut best: Option<((bool, usize, f64), f64)> = None;
        let mut itself: Option<(f64, usize, f64)> = None;
        let mut departed: Option<Option<usize>> = None;
        for segment in candidates {
            let (q, j) = self.owner(segment as usize);
            if q > r {
                break; // candidates come in segment order, so road order
            }
            // the road cannot have left the sample along less than the departure radius
            let departure_radius = DEPARTURE_WIDTHS * self.widths[r];
            if q == r && (j + 1 >= k || s[k] - s[j + 1] <= departure_radius) {
                continue;
            }
            let other_half = 0.5 * self.widths[q];
            let (a, b) = self.index.segments()[segment as usize];
            if !touches(a, b, other_half) {
                continue;
            }
            let c = closest_on_segment(p, a, b);
            let d = c.distance(p);
            let len = a.distance(b);
            let t = if len > 0.0 { c.distance(a) / len } else { 0.0 };
            if q < r {
                let prof = &earlier[q].points;
                let z = prof[j].z + t * (prof[j + 1].z - prof[j].z);
                let key = (d > other_half, q, d);
                if best.is_none_or(|(b, _)| key < b) {
                    best = Some((key, z));
                }
            } else {
                // only a pass the road came back on after leaving this sample
                let left_at = *departed.get_or_insert_with(|| departure(plan, k, departure_radius));
                if left_at.is_some_and(|i| j < i) && itself.is_none_or(|(bd, _, _)| d < bd) {
                    itself = Some((d, j, t));
                }
            }
        }
        Reached {
            earlier: best.map(|(_, z)| z),
            itself: itself.map(|(_, j, t)| (j, t)),
        }
    }
}

/// The last sample before `k` farther than `radius` from it: where the road, walked back from `k`, leaves it.
fn departure(plan: &[DVec2], k: usize, radius: f64) -> Option<usize> {
    (0..k).rev().find(|i| plan[*i].distance(plan[k]) > radius)
}

/// One stretch of a road held at other carriageways' heights: samples `first..=last`.
#[derive(Clone, Copy, Debug)]
struct Hold {
    first: usize,
    last: usize,
}

/// One end of a hold: where it is, the held height less the road's own there and the grade of that difference,
/// and the blend length beyond it.
#[derive(Clone, Copy, Debug)]
struct HoldEnd {
    s: f64,
    difference: f64,
    grade: f64,
    length: f64,
}

/// The cubic Hermite curve from value `d0` with slope `m0` to `d1` with slope `m1` over `span`, at `u ∈ [0, 1]`.
fn hermite(d0: f64, m0: f64, d1: f64, m1: f64, span: f64, u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    let (u2, u3) = (u * u, u * u * u);
    d0 * (2.0 * u3 - 3.0 * u2 + 1.0)
        + span * m0 * (u3 - 2.0 * u2 + u)
        + d1 * (3.0 * u2 - 2.0 * u3)
        + span * m1 * (u3 - u2)
}

/// The blend length for a road of `width` whose own profile is `dz` away from the held height.
fn blend_length(width: f64, dz: f64) -> f64 {
    (BLEND_WIDTHS * width).max(HERMITE_PEAK * dz.abs() / MAX_ADDED_GRADE)
}

/// The end of a hold at sample `edge`, the grade of the difference taken towards sample `inner` (at most a width
/// into the hold).
fn hold_end(s: &[f64], difference: &[f64], edge: usize, inner: usize, width: f64) -> HoldEnd {
    let span = s[inner] - s[edge];
    let grade = if span.abs() > 1e-9 {
        (difference[inner] - difference[edge]) / span
    } else {
        0.0
    };
    HoldEnd {
        s: s[edge],
        difference: difference[edge],
        grade,
        length: blend_length(width, difference[edge]),
    }
}

/// The profile `own` (sampled at `s`) held at `held` where it has a value and blended back to `own` around the
/// held stretches (see the module's rule).
fn blend(s: &[f64], own: &[f64], held: &[Option<f64>], width: f64) -> Vec<f64> {
    let n = own.len();
    let mut holds: Vec<Hold> = Vec::new();
    for (k, h) in held.iter().enumerate() {
        if h.is_none() {
            continue;
        }
        match holds.last_mut() {
            Some(h) if h.last + 1 == k => h.last = k,
            _ => holds.push(Hold { first: k, last: k }),
        }
    }
    if holds.is_empty() {
        return own.to_vec();
    }
    // the held height less the own, 0 where nothing is held; the blends below shape it where nothing is
    let mut difference: Vec<f64> = held
        .iter()
        .zip(own)
        .map(|(h, o)| h.map_or(0.0, |h| h - o))
        .collect();
    let within_width = |from: usize, k: usize| (s[k] - s[from]).abs() <= width;
    let starts: Vec<HoldEnd> = holds
        .iter()
        .map(|h| {
            let inner = (h.first..=h.last)
                .take_while(|k| within_width(h.first, *k))
                .last()
                .unwrap_or(h.first);
            hold_end(s, &difference, h.first, inner, width)
        })
        .collect();
    let ends: Vec<HoldEnd> = holds
        .iter()
        .map(|h| {
            let inner = (h.first..=h.last)
                .rev()
                .take_while(|k| within_width(h.last, *k))
                .last()
                .unwrap_or(h.last);
            hold_end(s, &difference, h.last, inner, width)
        })
        .collect();
    // a blend away from a hold's end: from its difference and grade to none over its length
    let away = |end: &HoldEnd, direction: f64, at: f64| {
        let x = direction * (at - end.s);
        hermite(
            end.difference,
            direction * end.grade,
            0.0,
            0.0,
            end.length,
            x / end.length,
        )
    };
    let (first, last) = (holds[0], holds[holds.len() - 1]);
    for k in 0..first.first {
        difference[k] = away(&starts[0], -1.0, s[k]);
    }
    for k in last.last + 1..n {
        difference[k] = away(&ends[holds.len() - 1], 1.0, s[k]);
    }
    // between holds: back to the own profile and out again, or straight across when the gap is too short
    for (h, (from, to)) in holds.windows(2).zip(ends.iter().zip(&starts[1..])) {
        let gap = to.s - from.s;
        let bridge = from.length + to.length > gap;
        for k in h[0].last + 1..h[1].first {
            difference[k] = if bridge {
                let u = (s[k] - from.s) / gap.max(1e-9);
                hermite(from.difference, from.grade, to.difference, to.grade, gap, u)
            } else {
                away(from, 1.0, s[k]) + away(to, -1.0, s[k])
            };
        }
    }
    own.iter().zip(&difference).map(|(o, d)| o + d).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(n: usize, spacing: f64) -> Vec<f64> {
        (0..n).map(|k| k as f64 * spacing).collect()
    }

    #[test]
    fn a_hold_blends_back_with_a_gentle_continuous_grade() {
        let s = line(1001, 0.1);
        let own = vec![0.0; s.len()];
        let held: Vec<Option<f64>> = s
            .iter()
            .map(|x| (45.0..=55.0).contains(x).then_some(2.0))
            .collect();
        let z = blend(&s, &own, &held, 6.0);
        let length = blend_length(6.0, 2.0);
        assert!((length - 37.5).abs() < 1e-9);
        let grades: Vec<f64> = z.windows(2).map(|w| (w[1] - w[0]) / 0.1).collect();
        let steepest = grades.iter().map(|g| g.abs()).fold(0.0, f64::max);
        let kink = grades
            .windows(2)
            .map(|g| (g[1] - g[0]).abs())
            .fold(0.0, f64::max);
        assert!(steepest <= MAX_ADDED_GRADE + 1e-3, "grade {steepest}");
        assert!(kink < 1e-3, "grade changes by {kink} between samples");
        assert_eq!(z[500], 2.0);
        assert!(z[60].abs() < 1e-12 && z[1000].abs() < 1e-12);
    }

    #[test]
    fn close_holds_are_bridged_and_ends_stop_the_blend() {
        let s = line(201, 0.5);
        let own: Vec<f64> = s.iter().map(|x| 0.1 * x).collect();
        let held: Vec<Option<f64>> = s
            .iter()
            .map(|x| {
                if *x <= 2.0 {
                    Some(5.0)
                } else if (20.0..=24.0).contains(x) {
                    Some(6.0)
                } else {
                    None
                }
            })
            .collect();
        let z = blend(&s, &own, &held, 4.0);
        // between the holds the road never goes back down to its own profile (2 m to 2.4 m there)
        assert!(
            z[4..40].iter().all(|z| (5.0..=6.0).contains(z)),
            "{:?}",
            &z[4..40]
        );
        assert!(z.iter().all(|z| z.is_finite()));
        assert_eq!(z[0], 5.0);
    }
}

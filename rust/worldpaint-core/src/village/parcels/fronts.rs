//! Straight road fronts of the parcels that grow fields (our reading of thesis 3.3's "most parcels have one side
//! neighboring a road and two sides perpendicular to it" and 3.3.4's "parcel boundaries mainly consist of
//! straight lines"): a parcel with a [`ParcelParams::fill`](super::super::encyclopedia::ParcelParams::fill) keeps
//! behind one straight line along its road, or two on a corner, and its fields grow in front of them only.
//!
//! A parcel's road cells (its cells beside the road corridor) are grouped by the direction of the road normal at
//! each: one group when they all face within [`RUN_SPREAD_DEGREES`] of their mean normal (a straight or gently
//! bending road), else the two groups of a corner lot fronting two roads, or, where the two face more than
//! [`CORNER_DEGREES`] apart (the two sides of one road, round its dead end or a hairpin), only the larger one;
//! a front winding further is left as it is. Each group is a front: its line is normal to the group's mean road
//! normal, through its road cell farthest from the road. Where a road cell lies behind that line by more than the
//! straightening tolerance (the road bends), the parcel's cells more than half a cell behind it leave the parcel:
//! a front along the outside of a bend becomes its chord, set back to touch the road corridor at the bend's
//! apex, one along the inside of a bend the chord between its ends, and the land conquered round the end of a
//! road or round a hairpin goes back to the unclaimed land (the slivers left beside the road are its verge).
//! Then the fill grows only in front of the fronts (see `fill`), so the fields no longer wrap round the
//! switchbacks.
//!
//! Only parcels that grow fields: in the dense villages north of Bayreuth in `tests/real_village_generation.rs`
//! (no fill), cutting every bent front cost 20-36 of 400-458 footprints and the parcel neighbours fell from
//! 2.49-2.64 to 2.17-2.35, for 0.1-0.4 fewer contour edges; their lots are bounded by their neighbours, not by
//! their fronts' wanderings.

use super::super::road_index::RoadIndex;
use super::grid::Work;
use super::NONE;
use crate::graph::angle_between;
use glam::DVec2;
use rayon::prelude::*;

/// Largest angle (degrees) between a road cell's normal and its front's mean normal: gentler bends than this are
/// straightened into one front.
pub(super) const RUN_SPREAD_DEGREES: f64 = 30.0;
/// Fronts facing more than this apart (degrees) are not the two sides of a corner lot but the two sides of one
/// road (round its end, or a hairpin): the larger one is kept.
pub(super) const CORNER_DEGREES: f64 = 120.0;

/// A front's line: points `p` with `p·normal < offset` lie behind it (on the road's side).
#[derive(Clone, Copy, Debug)]
pub(super) struct Front {
    pub(super) normal: DVec2,
    pub(super) offset: f64,
}

/// Every parcel's fronts (the first the larger), from its road cells in `label`.
pub(super) fn parcel_fronts(
    work: &Work,
    index: &RoadIndex,
    n: usize,
    label: &[u32],
) -> Vec<Vec<Front>> {
    let mut road_cells: Vec<Vec<(DVec2, DVec2)>> = vec![Vec::new(); n];
    for (k, &x) in label.iter().enumerate() {
        if x == NONE || !work.edge[k] {
            continue;
        }
        let p = work.grid.point_of(k);
        let normal = (p - index.project(p).point).normalize_or_zero();
        if normal != DVec2::ZERO {
            road_cells[x as usize].push((p, normal));
        }
    }
    road_cells.par_iter().map(|c| fronts_of(c)).collect()
}

/// The fronts of one parcel from its road cells' positions and road normals (see the module documentation).
fn fronts_of(cells: &[(DVec2, DVec2)]) -> Vec<Front> {
    let spread = RUN_SPREAD_DEGREES.to_radians();
    let mean =
        |group: &[(DVec2, DVec2)]| group.iter().map(|c| c.1).sum::<DVec2>().normalize_or_zero();
    let within = |group: &[(DVec2, DVec2)], m: DVec2| {
        m != DVec2::ZERO && group.iter().all(|c| angle_between(c.1, m) <= spread)
    };
    let front = |group: &[(DVec2, DVec2)], m: DVec2| Front {
        normal: m,
        // the road cell farthest from the road along the normal: the line touches the corridor there
        offset: group
            .iter()
            .map(|c| c.0.dot(m))
            .fold(f64::NEG_INFINITY, f64::max),
    };
    let m = mean(cells);
    if within(cells, m) {
        return vec![front(cells, m)];
    }
    // two groups: seeded by the normal farthest from the mean and the one farthest from it, then refined
    let farthest = |from: DVec2| {
        cells
            .iter()
            .map(|c| c.1)
            .max_by(|a, b| angle_between(*a, from).total_cmp(&angle_between(*b, from)))
            .unwrap_or(from)
    };
    let mut a = farthest(m);
    let mut b = farthest(a);
    let mut groups: [Vec<(DVec2, DVec2)>; 2] = [Vec::new(), Vec::new()];
    for _ in 0..4 {
        groups = [Vec::new(), Vec::new()];
        for &c in cells {
            let g = usize::from(angle_between(c.1, b) < angle_between(c.1, a));
            groups[g].push(c);
        }
        (a, b) = (mean(&groups[0]), mean(&groups[1]));
    }
    if !within(&groups[0], a) || !within(&groups[1], b) {
        // a front winding round more than a corner: left as it is
        return Vec::new();
    }
    let (big, small) = if groups[0].len() >= groups[1].len() {
        ((&groups[0], a), (&groups[1], b))
    } else {
        ((&groups[1], b), (&groups[0], a))
    };
    if angle_between(a, b) > CORNER_DEGREES.to_radians() {
        vec![front(big.0, big.1)]
    } else {
        vec![front(big.0, big.1), front(small.0, small.1)]
    }
}

/// Takes out of each parcel `x` for which `applies(x)` the cells behind its `fronts` (see the module
/// documentation); `best` of those cells becomes infinite. Returns whether any cell left its parcel.
pub(super) fn cut_behind_fronts(
    work: &Work,
    fronts: &[Vec<Front>],
    tolerance: f64,
    applies: &(dyn Fn(usize) -> bool + Sync),
    (label, best): (&mut [u32], &mut [f64]),
) -> bool {
    // only parcels with a road cell behind a front by more than `tolerance`: a straight front stays as it is
    let mut bent = vec![false; fronts.len()];
    for (k, &x) in label.iter().enumerate() {
        if x == NONE || !work.edge[k] || bent[x as usize] || !applies(x as usize) {
            continue;
        }
        let p = work.grid.point_of(k);
        bent[x as usize] = fronts[x as usize]
            .iter()
            .any(|f| p.dot(f.normal) < f.offset - tolerance);
    }
    // half a cell behind: the road cell the line runs through stays
    let slack = 0.5 * work.grid.cell;
    let behind: Vec<usize> = label
        .par_iter()
        .enumerate()
        .filter_map(|(k, &x)| {
            if x == NONE || !bent[x as usize] {
                return None;
            }
            let p = work.grid.point_of(k);
            fronts[x as usize]
                .iter()
                .any(|f| p.dot(f.normal) < f.offset - slack)
                .then_some(k)
        })
        .collect();
    for &k in &behind {
        label[k] = NONE;
        best[k] = f64::INFINITY;
    }
    !behind.is_empty()
}

/// The anchor of every parcel whose anchor cell left it: its road cell nearest to the old anchor (or, without
/// road cells, its cell nearest to it); `is_anchor` follows.
pub(super) fn reanchor(
    work: &Work,
    label: &[u32],
    anchors: &mut [Option<usize>],
    is_anchor: &mut [bool],
) {
    let lost: Vec<usize> = (0..anchors.len())
        .filter(|&i| anchors[i].is_some_and(|a| label[a] != i as u32))
        .collect();
    if lost.is_empty() {
        return;
    }
    // the nearest road cell, else the nearest cell, of each parcel that lost its anchor: (not a road cell,
    // distance, cell), the least first
    let mut nearest: Vec<Option<(bool, f64, usize)>> = vec![None; anchors.len()];
    for (k, &x) in label.iter().enumerate() {
        let Some(Some(a)) = (x != NONE).then(|| anchors[x as usize]) else {
            continue;
        };
        if label[a] == x {
            continue;
        }
        let d = work.grid.point_of(k).distance(work.grid.point_of(a));
        let candidate = (!work.edge[k], d, k);
        let best = &mut nearest[x as usize];
        if best.is_none_or(|b| (candidate.0, candidate.1) < (b.0, b.1)) {
            *best = Some(candidate);
        }
    }
    for i in lost {
        if let Some(a) = anchors[i] {
            is_anchor[a] = false;
        }
        anchors[i] = nearest[i].map(|(_, _, k)| k);
        if let Some(k) = anchors[i] {
            is_anchor[k] = true;
        }
    }
}

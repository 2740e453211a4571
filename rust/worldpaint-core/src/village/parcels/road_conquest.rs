//! Road conquest (thesis 3.3.1, Emilien 2014 ch. 3): the source `S_i` is the projection of `B_i` on the closest
//! road. The cells along the road corridor's edge, on the seed's side, are conquered from `S_i` in both directions
//! along the road "until collision with a neighboring parcel or until a maximum distance from `S_i` is reached"
//! ([`ParcelParams::road_reach`](super::super::encyclopedia::ParcelParams::road_reach)). All seeds advance
//! together, so two neighbours meet half-way.

use super::grid::{Work, N8};
use super::{ParcelSeed, NONE};
use crate::search::{MinCost, MinHeap};

pub(super) struct RoadConquest {
    /// The parcel owning each road-edge cell.
    pub(super) owner: Vec<u32>,
    /// Distance along the road edge from the owner's source (infinite for annexed cells).
    pub(super) arrival: Vec<f64>,
}

/// All seeds advance from their sources along the road-edge cells at the same speed; a cell goes to the first
/// to arrive (ties to the lower seed index), and a seed stops at its road reach.
pub(super) fn road_conquest(
    work: &Work,
    seeds: &[ParcelSeed],
    sources: &[Option<usize>],
) -> RoadConquest {
    let mut owner = vec![NONE; work.grid.len()];
    let mut arrival = vec![f64::INFINITY; work.grid.len()];
    let mut heap = MinHeap::new();
    for (i, s) in sources.iter().enumerate() {
        if let Some(k) = s {
            heap.push(0.0, (i as u32, *k as u32));
        }
    }
    while let Some(MinCost {
        cost: d,
        item: (i, k),
    }) = heap.pop()
    {
        let k = k as usize;
        if owner[k] != NONE {
            continue;
        }
        owner[k] = i;
        arrival[k] = d;
        let reach = seeds[i as usize].params.road_reach;
        let (ci, cj) = work.grid.ij(k);
        for &(di, dj) in &N8 {
            let Some(nk) = work.inside(ci as i64 + di, cj as i64 + dj) else {
                continue;
            };
            if !work.edge[nk] || owner[nk] != NONE {
                continue;
            }
            let step = if di != 0 && dj != 0 {
                std::f64::consts::SQRT_2
            } else {
                1.0
            };
            let nd = d + step * work.grid.cell;
            if nd <= reach + 1e-9 {
                heap.push(nd, (i, nk as u32));
            }
        }
    }
    RoadConquest { owner, arrival }
}

/// Each parcel's road cells, and its anchor: its source cell, or the owned road cell nearest to it along the road.
pub(super) fn fronts_and_anchors(
    road: &RoadConquest,
    sources: &[Option<usize>],
) -> (Vec<Vec<usize>>, Vec<Option<usize>>) {
    let n = sources.len();
    let mut fronts: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (k, &o) in road.owner.iter().enumerate() {
        if o != NONE {
            fronts[o as usize].push(k);
        }
    }
    let anchors: Vec<Option<usize>> = (0..n)
        .map(|i| match sources[i] {
            Some(s) if road.owner[s] == i as u32 => Some(s),
            _ => fronts[i]
                .iter()
                .copied()
                .min_by(|&a, &b| road.arrival[a].total_cmp(&road.arrival[b]).then(a.cmp(&b))),
        })
        .collect();
    (fronts, anchors)
}

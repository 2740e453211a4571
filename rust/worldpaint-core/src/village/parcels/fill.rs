//! Unclaimed land given to the parcels around it (our addition to thesis 3.3.3): a real cadastre has no
//! no-man's-land between its lots, while the conquest's budget leaves two kinds of it:
//!
//! * *pockets*: small pieces of open land enclosed by parcels and roads (at most
//!   [`ParcelOptions::pocket_area`](super::ParcelOptions::pocket_area)), which no parcel's budget reached. Their
//!   outlines notch the parcels around them (every corner a vertex) and part neighbours that would otherwise
//!   touch;
//! * *gaps* of a sparse village: farms and houses tens of metres apart whose strips along the road never meet.
//!   There a parcel keeps growing over the open land beyond its conquest by up to its
//!   [`ParcelParams::fill`](super::super::encyclopedia::ParcelParams::fill) metres (its fields), until it meets its
//!   neighbours, and only in front of its straight road fronts (see `fronts`; within the straightening
//!   tolerance), so that its fields do not wrap round the end of its road or round a hairpin of it.
//!
//! Both are one multi-source shortest-path growth from every parcel's cells over the unclaimed open cells (not
//! road, water, wall, outside `Ω`, nor another parcel's road cell), at the Euclidean length of 8-connected steps:
//! a cell goes to the parcel that reaches it first, so neighbours part half-way. A pocket's cells have no depth
//! limit; other cells are taken within the parcel's `fill`. The growth runs on one thread in a total order (cost,
//! then parcel, then cell), so its result does not depend on the number of threads.

use super::fronts::Front;
use super::grid::{Work, N4, N8, ROAD};
use super::{ParcelSeed, NONE};
use crate::search::{MinCost, MinHeap};
use glam::DVec2;
use std::collections::VecDeque;
use std::f64::consts::SQRT_2;

/// Depth (cells) of the strip beside the road corridor that only the road conquest gives out: a fill reaching
/// the road there would lengthen the frontage on which the footprint is centred (3.3.5) and move the house.
const FRONT: i64 = 2;

/// Gives unclaimed open land to the parcels around it (see the module documentation); beyond the pockets, parcel
/// `x` grows only where `p·n >= offset - tolerance` for each of its `fronts[x]`. `label` and `best` are
/// the cells' parcels and costs; a filled cell's cost is above every conquered cell's of its parcel (its
/// budget plus the distance grown), so that the clean-up drops filled cells first.
pub(super) fn fill_unclaimed(
    work: &Work,
    owner: &[u32],
    seeds: &[ParcelSeed],
    pocket_cells: usize,
    (fronts, tolerance): (&[Vec<Front>], f64),
    (label, best): (&mut [u32], &mut [f64]),
) {
    let open = |k: usize| label[k] == NONE && !work.closed_to(owner, NONE, k);
    let pocket = pockets(work, &open, pocket_cells);
    let depth: Vec<f64> = seeds.iter().map(|s| s.params.fill.max(0.0)).collect();
    if depth.iter().all(|&d| d <= 0.0) && !pocket.iter().any(|&p| p) {
        return;
    }
    let c = work.grid.cell;
    let len = work.grid.len();
    let by_road = beside_roads(work);
    let mut dist = vec![f64::INFINITY; len];
    let mut from = vec![NONE; len];
    // beyond the pockets, a parcel grows only in front of its road fronts, not round its road's end or a hairpin
    let in_front = |x: u32, p: DVec2| {
        fronts[x as usize]
            .iter()
            .all(|f| p.dot(f.normal) >= f.offset - tolerance)
    };
    let mut heap = MinHeap::new();
    let nx = work.grid.nx;
    for k in 0..len {
        let x = label[k];
        if x == NONE || (depth[x as usize] <= 0.0 && !near_pocket(work, &pocket, k)) {
            continue;
        }
        dist[k] = 0.0;
        from[k] = x;
        heap.push(0.0, (x, k as u32));
    }
    let mut settled = vec![false; len];
    while let Some(MinCost {
        cost: d,
        item: (x, k),
    }) = heap.pop()
    {
        let k = k as usize;
        if settled[k] || from[k] != x || d > dist[k] {
            continue;
        }
        settled[k] = true;
        let (i, j) = ((k % nx) as i64, (k / nx) as i64);
        for &(di, dj) in &N8 {
            let Some(m) = work.inside(i + di, j + dj) else {
                continue;
            };
            if settled[m] || !open(m) || work.closed_to(owner, x, m) {
                continue;
            }
            if di != 0 && dj != 0 {
                // no slipping between two cells that touch at a corner, whoever holds them
                let a = work.inside(i + di, j);
                let b = work.inside(i, j + dj);
                if a.is_none_or(|a| !open(a)) && b.is_none_or(|b| !open(b)) {
                    continue;
                }
            }
            let step = if di != 0 && dj != 0 { SQRT_2 * c } else { c };
            let nd = d + step;
            // beyond the pockets, a parcel keeps the frontage its road conquest gave it (its house is centred
            // on it) and grows behind it only
            if !pocket[m]
                && (nd > depth[x as usize] || by_road[m] || !in_front(x, work.grid.point_of(m)))
            {
                continue;
            }
            if nd < dist[m] || (nd == dist[m] && x < from[m]) {
                dist[m] = nd;
                from[m] = x;
                heap.push(nd, (x, m as u32));
            }
        }
    }
    for k in 0..len {
        if label[k] == NONE && from[k] != NONE {
            let x = from[k];
            label[k] = x;
            best[k] = seeds[x as usize].params.budget + dist[k];
        }
    }
}

/// Cells of the road corridor's edge zone: within [`FRONT`] cells (box distance) of a road cell.
fn beside_roads(work: &Work) -> Vec<bool> {
    let (nx, ny) = (work.grid.nx as i64, work.grid.ny as i64);
    let mut near = vec![false; work.grid.len()];
    for (k, &s) in work.state.iter().enumerate() {
        if s != ROAD {
            continue;
        }
        let (i, j) = ((k as i64) % nx, (k as i64) / nx);
        for b in (j - FRONT).max(0)..=(j + FRONT).min(ny - 1) {
            for a in (i - FRONT).max(0)..=(i + FRONT).min(nx - 1) {
                near[(b * nx + a) as usize] = true;
            }
        }
    }
    near
}

/// Whether cell `k` touches a pocket cell.
fn near_pocket(work: &Work, pocket: &[bool], k: usize) -> bool {
    let nx = work.grid.nx;
    let (i, j) = ((k % nx) as i64, (k / nx) as i64);
    N8.iter()
        .filter_map(|&(di, dj)| work.inside(i + di, j + dj))
        .any(|m| pocket[m])
}

/// The open cells in 4-connected pieces of at most `max_cells` cells that do not touch the grid's border.
fn pockets(work: &Work, open: &dyn Fn(usize) -> bool, max_cells: usize) -> Vec<bool> {
    let len = work.grid.len();
    let mut pocket = vec![false; len];
    if max_cells == 0 {
        return pocket;
    }
    let (nx, ny) = (work.grid.nx, work.grid.ny);
    let mut seen = vec![false; len];
    let mut piece = Vec::new();
    let mut queue = VecDeque::new();
    for start in 0..len {
        if seen[start] || !open(start) {
            continue;
        }
        piece.clear();
        seen[start] = true;
        queue.push_back(start);
        let mut bordered = false;
        while let Some(k) = queue.pop_front() {
            piece.push(k);
            let (i, j) = (k % nx, k / nx);
            bordered |= i == 0 || j == 0 || i == nx - 1 || j == ny - 1;
            for &(di, dj) in &N4 {
                if let Some(m) = work.inside(i as i64 + di, j as i64 + dj) {
                    if !seen[m] && open(m) {
                        seen[m] = true;
                        queue.push_back(m);
                    }
                }
            }
        }
        if !bordered && piece.len() <= max_cells {
            for &k in &piece {
                pocket[k] = true;
            }
        }
    }
    pocket
}

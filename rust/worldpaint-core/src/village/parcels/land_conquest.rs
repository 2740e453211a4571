//! Anisotropic land conquest (thesis 3.3.3, Emilien 2014 ch. 3): every road cell a parcel owns is a source with
//! the fund `c_max`, and the parcel spreads until the cost from its source reaches `c_max`:
//!
//! > dc_s(d_s, n) = Σ_{i=0}^{n−1} ω_i c_i(d_s, n)
//!
//! with the infinite-norm conquest cost in the road frame of the source (a tiny multiple of the Euclidean distance
//! breaking its ties), `+∞` on water, walls, roads, outside `Ω` and on other parcels' road cells, and the slope
//! cost quadratic in the directional gradients of the terrain along the source's normal and tangent. Every parcel
//! conquers its own neighbourhood on its own; a cell claimed by several parcels goes to the lowest cost.

use super::super::encyclopedia::ParcelParams;
use super::super::land::Land;
use super::super::road_index::RoadIndex;
use super::grid::{Work, N8};
use super::NONE;
use crate::search::{MinCost, MinHeap};
use glam::DVec2;

/// Weight of the Euclidean distance that breaks ties of the infinite-norm conquest cost.
const TIE: f64 = 1e-3;

/// A cell conquered by a parcel: its cost and the road cell it was conquered from.
pub(super) struct Claim {
    pub(super) cell: u32,
    pub(super) cost: f64,
    pub(super) source: u32,
}

/// The cells one parcel conquers on its own from its road cells `fronts`, with their costs (at most `c_max`).
///
/// Each cell keeps the source it was reached from; its conquest cost is measured to that source in the source's
/// road frame, and the slope cost is summed along the steps that reached it (see the module documentation).
pub(super) fn conquer(
    work: &Work,
    land: &Land,
    index: &RoadIndex,
    owner: &[u32],
    seed: u32,
    fronts: &[usize],
    params: &ParcelParams,
) -> Vec<Claim> {
    if fronts.is_empty() {
        return Vec::new();
    }
    let c = work.grid.cell;
    let win = Window::new(work, fronts, params);
    let (i0, j0, lnx, lny) = (win.i0, win.j0, win.lnx, win.lny);
    let global = |l: usize| win.global(l);
    let frames = road_frames(work, index, fronts);
    let gradients = (params.slope_weight > 0.0).then(|| win.gradients(land));
    let mut cost = vec![f64::INFINITY; lnx * lny];
    let mut origin = vec![u32::MAX; lnx * lny];
    let mut slope = vec![0.0f64; lnx * lny];
    let mut heap = MinHeap::new();
    for (f, &k) in fronts.iter().enumerate() {
        let (i, j) = work.grid.ij(k);
        let l = (j - j0) * lnx + (i - i0);
        cost[l] = 0.0;
        origin[l] = f as u32;
        heap.push(0.0, l as u32);
    }
    // each cell is conquered once, in order of cost: the cost to a source is not monotone along a path (the
    // ∞-norm distance can fall on a sideways step), and letting later, cheaper arrivals reopen conquered cells
    // made some windows re-spread over a thousand times
    let mut settled = vec![false; lnx * lny];
    while let Some(MinCost {
        cost: reached,
        item: l,
    }) = heap.pop()
    {
        let l = l as usize;
        if reached > cost[l] || settled[l] {
            continue;
        }
        settled[l] = true;
        let (li, lj) = ((l % lnx) as i64, (l / lnx) as i64);
        let o = origin[l];
        let (so, n) = frames[o as usize];
        let t = n.perp();
        for &(di, dj) in &N8 {
            let (ni, nj) = (li + di, lj + dj);
            if ni < 0 || nj < 0 || ni >= lnx as i64 || nj >= lny as i64 {
                continue;
            }
            let nl = nj as usize * lnx + ni as usize;
            let k = global(nl);
            if work.closed_to(owner, seed, k) {
                continue;
            }
            if di != 0 && dj != 0 {
                // no slipping between two closed cells that touch at a corner (a diagonal wall)
                let a = global(lj as usize * lnx + ni as usize);
                let b = global(nj as usize * lnx + li as usize);
                if work.closed_to(owner, seed, a) && work.closed_to(owner, seed, b) {
                    continue;
                }
            }
            let d = work.grid.point_of(k) - so;
            if d.dot(n) < -0.5 * c {
                // behind the source: across its road
                continue;
            }
            let conquest = d.dot(n).abs().max(d.dot(t).abs()) + TIE * d.length();
            let mut s = slope[l];
            if let Some(g) = &gradients {
                // the step's advance along n and along t, each at the squared directional gradient of the
                // terrain in that direction
                let step = DVec2::new(di as f64, dj as f64) * c;
                let slope_at = 0.5 * (g[l] + g[nl]);
                s += slope_at.dot(n).powi(2) * step.dot(n).abs()
                    + slope_at.dot(t).powi(2) * step.dot(t).abs();
            }
            let total = params.conquest_weight * conquest + params.slope_weight * s;
            if total <= params.budget && total < cost[nl] && !settled[nl] {
                cost[nl] = total;
                origin[nl] = o;
                slope[nl] = s;
                heap.push(total, nl as u32);
            }
        }
    }
    cost.iter()
        .enumerate()
        .filter(|(_, c)| c.is_finite())
        .map(|(l, &c)| Claim {
            cell: global(l) as u32,
            cost: c,
            source: fronts[origin[l] as usize] as u32,
        })
        .collect()
}

/// The label (parcel) and cost of every cell from all parcels' claims. A cell claimed by several parcels goes to
/// the lowest cost; costs equal but for rounding (facing rows meeting half-way on the lattice) go to the source
/// first in grid order, so that such a boundary stays on one side of the lattice line all along instead of
/// zig-zagging with the seeds' order.
pub(super) fn resolve_claims(claims: &[Vec<Claim>], cells: usize) -> (Vec<u32>, Vec<f64>) {
    let mut best = vec![f64::INFINITY; cells];
    let mut from = vec![u32::MAX; cells];
    let mut label = vec![NONE; cells];
    for (i, cl) in claims.iter().enumerate() {
        for c in cl {
            let k = c.cell as usize;
            let tie = 1e-9 * (1.0 + c.cost.abs());
            if c.cost < best[k] - tie || (c.cost <= best[k] + tie && c.source < from[k]) {
                best[k] = c.cost;
                from[k] = c.source;
                label[k] = i as u32;
            }
        }
    }
    (label, best)
}

/// The part of the grid a parcel may conquer: the box of its road cells grown by its reach, with local cell
/// indices `l` (row by row, `lnx` cells a row).
struct Window<'a> {
    work: &'a Work,
    i0: usize,
    j0: usize,
    lnx: usize,
    lny: usize,
}

impl<'a> Window<'a> {
    fn new(work: &'a Work, fronts: &[usize], params: &ParcelParams) -> Self {
        let reach = params.budget / params.conquest_weight;
        // (an enormous fund reaches the whole grid, no farther)
        let r = (reach / work.grid.cell)
            .ceil()
            .min((work.grid.nx + work.grid.ny) as f64) as usize
            + 1;
        let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
        for &k in fronts {
            let (i, j) = work.grid.ij(k);
            (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
        }
        let (i0, j0) = (i0.saturating_sub(r), j0.saturating_sub(r));
        let (i1, j1) = (
            (i1 + r).min(work.grid.nx - 1),
            (j1 + r).min(work.grid.ny - 1),
        );
        Window {
            work,
            i0,
            j0,
            lnx: i1 - i0 + 1,
            lny: j1 - j0 + 1,
        }
    }

    /// The grid cell of local cell `l`.
    fn global(&self, l: usize) -> usize {
        (self.j0 + l / self.lnx) * self.work.grid.nx + self.i0 + l % self.lnx
    }

    /// The terrain gradient on the window's cells (central differences).
    fn gradients(&self, land: &Land) -> Vec<DVec2> {
        let (lnx, lny, c) = (self.lnx, self.lny, self.work.grid.cell);
        let h: Vec<f64> = (0..lnx * lny)
            .map(|l| land.height_at(self.work.grid.point_of(self.global(l))))
            .collect();
        (0..lnx * lny)
            .map(|l| {
                let (i, j) = (l % lnx, l / lnx);
                let (a, b) = (i.saturating_sub(1), (i + 1).min(lnx - 1));
                let (e, f) = (j.saturating_sub(1), (j + 1).min(lny - 1));
                DVec2::new(
                    (h[j * lnx + b] - h[j * lnx + a]) / ((b - a).max(1) as f64 * c),
                    (h[f * lnx + i] - h[e * lnx + i]) / ((f - e).max(1) as f64 * c),
                )
            })
            .collect()
    }
}

/// The road frame of every source: its position and the road normal `n` there, pointing away from the road.
fn road_frames(work: &Work, index: &RoadIndex, fronts: &[usize]) -> Vec<(DVec2, DVec2)> {
    fronts
        .iter()
        .map(|&k| {
            let p = work.grid.point_of(k);
            let n = (p - index.project(p).point).normalize_or_zero();
            // (a road cell lies beside its road, never on its centre line)
            let n = if n == DVec2::ZERO { DVec2::Y } else { n };
            (p, n)
        })
        .collect()
}

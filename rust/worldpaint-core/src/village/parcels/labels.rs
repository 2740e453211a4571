//! From claimed cells to simple regions (thesis 3.3.3, Emilien 2014 ch. 3): only the 4-connected component holding
//! the parcel's source is kept; a mode filter trims one-cell spikes and fills unclaimed cells enclosed between
//! parcels, and pinch points (two cells of one parcel touching at a corner only) and enclosed holes are resolved,
//! so that every parcel is a simple polygon.

use super::grid::{Work, FREE, N4, N8};
use super::NONE;
use crate::error::Result;
use rayon::prelude::*;
use std::collections::VecDeque;

/// Rounds of clean-up at the most; each reports its progress.
const ROUNDS: usize = 12;

/// The labels being cleaned (the parcel of each cell, or `NONE`) with the cost at which each cell was claimed,
/// and what the cleaning respects: the road cells' owners and the parcels' anchors.
struct Labels<'a> {
    work: &'a Work,
    owner: &'a [u32],
    is_anchor: &'a [bool],
    label: &'a mut [u32],
    best: &'a mut [f64],
}

impl Labels<'_> {
    /// A mode filter on the claimed cells, up to twice: a cell most of whose eight neighbours (five or more) share
    /// another label takes it, and an unclaimed cell enclosed on three sides or more by parcels joins the most
    /// frequent one. Where many parcels compete (rough terrain), cost ties leave one-cell spikes and chains of
    /// unclaimed cells between two parcels; every corner of those is a junction of the boundary graph, which no
    /// simplification may remove. Road cells keep their owner, and closed cells stay out.
    fn smooth(&mut self) -> bool {
        let nx = self.work.grid.nx;
        let ny = self.work.grid.ny;
        let mut any = false;
        // the cells to look at: all of them, then those around the cells the pass before changed (no other
        // cell's neighbourhood changed)
        let mut around: Option<Vec<usize>> = None;
        for _ in 0..2 {
            // every change from the labels before the pass, applied after it
            let changes: Vec<(usize, u32, f64)> = match &around {
                None => (0..self.work.grid.len())
                    .into_par_iter()
                    .filter_map(|k| self.smoothed(k))
                    .collect(),
                Some(cells) => cells.par_iter().filter_map(|&k| self.smoothed(k)).collect(),
            };
            if changes.is_empty() {
                break;
            }
            let mut next: Vec<usize> = Vec::with_capacity(9 * changes.len());
            for &(k, target, cost) in &changes {
                self.label[k] = target;
                self.best[k] = cost;
                let (i, j) = (k % nx, k / nx);
                for jj in j.saturating_sub(1)..=(j + 1).min(ny - 1) {
                    next.extend((i.saturating_sub(1)..=(i + 1).min(nx - 1)).map(|ii| jj * nx + ii));
                }
            }
            next.sort_unstable();
            next.dedup();
            around = Some(next);
            any = true;
        }
        any
    }

    /// What the mode filter does to cell `k`: its new label and cost, or `None` when it keeps its label.
    fn smoothed(&self, k: usize) -> Option<(usize, u32, f64)> {
        let (old, old_best): (&[u32], &[f64]) = (self.label, self.best);
        let (nx, ny) = (self.work.grid.nx, self.work.grid.ny);
        let lab = |i: i64, j: i64| self.work.inside(i, j).map_or(NONE, |k| old[k]);
        // a cell off the grid's border inside its parcel or inside unclaimed land (most cells) keeps its label
        let uniform = |k: usize| {
            let (i, j, l) = (k % nx, k / nx, old[k]);
            i > 0
                && j > 0
                && i + 1 < nx
                && j + 1 < ny
                && [k - nx, k + nx]
                    .iter()
                    .all(|&r| old[r - 1] == l && old[r] == l && old[r + 1] == l)
                && old[k - 1] == l
                && old[k + 1] == l
        };
        if self.is_anchor[k]
            || self.work.state[k] != FREE
            || (self.work.edge[k] && self.owner[k] != NONE)
        {
            return None;
        }
        if uniform(k) {
            return None;
        }
        let (i, j) = ((k % nx) as i64, (k / nx) as i64);
        let mut counts = [(NONE, 0usize); 8];
        let mut distinct = 0;
        for l in N8.map(|(di, dj)| lab(i + di, j + dj)) {
            match counts[..distinct].iter_mut().find(|c| c.0 == l) {
                Some(c) => c.1 += 1,
                None => {
                    counts[distinct] = (l, 1);
                    distinct += 1;
                }
            }
        }
        let counts = &mut counts[..distinct];
        // the most frequent label, ties to the lower one
        counts.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let (top, count) = counts[0];
        let target = if old[k] == NONE {
            let parcels4 = N4
                .iter()
                .filter(|&&(di, dj)| lab(i + di, j + dj) != NONE)
                .count();
            match counts.iter().find(|c| c.0 != NONE).map(|c| c.0) {
                Some(x) if parcels4 >= 3 && !self.work.closed_to(self.owner, x, k) => x,
                _ => return None,
            }
        } else if top != old[k]
            && count >= 5
            && (top == NONE || !self.work.closed_to(self.owner, top, k))
        {
            top
        } else {
            return None;
        };
        let cost = if target == NONE {
            f64::INFINITY
        } else {
            N8.iter()
                .filter_map(|&(di, dj)| self.work.inside(i + di, j + dj))
                .filter(|&m| old[m] == target)
                .map(|m| old_best[m])
                .fold(0.0, f64::max)
        };
        Some((k, target, cost))
    }
}

/// Keeps each parcel's 4-connected component that holds its anchor, smooths the labels (the first rounds), fills
/// pinch points and enclosed holes, until every parcel is one simply connected 4-connected region without cells
/// touching at a corner only. Without `smooth`, no mode filter runs (it would give cells taken out on purpose back
/// to the parcels around them). `rounds_done(fraction)` hears of each round and may stop the work.
pub(super) fn clean_labels(
    work: &Work,
    owner: &[u32],
    (anchors, is_anchor): (&[Option<usize>], &[bool]),
    (label, best): (&mut [u32], &mut [f64]),
    smooth: bool,
    rounds_done: &dyn Fn(f64) -> Result<()>,
) -> Result<()> {
    let mut labels = Labels {
        work,
        owner,
        is_anchor,
        label,
        best,
    };
    for round in 0..ROUNDS {
        keep_components(work, anchors, labels.label, labels.best);
        let smoothed = smooth && round < 3 && labels.smooth();
        let pinched = labels.fix_pinches();
        let holed = labels.fix_holes(anchors.len());
        if !smoothed && !pinched && !holed {
            return Ok(());
        }
        rounds_done((round + 1) as f64 / ROUNDS as f64)?;
    }
    keep_components(work, anchors, labels.label, labels.best);
    Ok(())
}

fn keep_components(work: &Work, anchors: &[Option<usize>], label: &mut [u32], best: &mut [f64]) {
    let mut keep = vec![false; work.grid.len()];
    let mut queue = VecDeque::new();
    for (i, a) in anchors.iter().enumerate() {
        let Some(a) = *a else { continue };
        if label[a] != i as u32 {
            continue;
        }
        keep[a] = true;
        queue.push_back(a);
        while let Some(k) = queue.pop_front() {
            let (ci, cj) = work.grid.ij(k);
            for &(di, dj) in &N4 {
                if let Some(nk) = work.inside(ci as i64 + di, cj as i64 + dj) {
                    if !keep[nk] && label[nk] == i as u32 {
                        keep[nk] = true;
                        queue.push_back(nk);
                    }
                }
            }
        }
    }
    for k in 0..work.grid.len() {
        if label[k] != NONE && !keep[k] {
            label[k] = NONE;
            best[k] = f64::INFINITY;
        }
    }
}

/// Whether parcel `x` may take cell `k` that nobody holds.
fn fillable(work: &Work, owner: &[u32], label: &[u32], x: u32, k: usize) -> bool {
    label[k] == NONE && !work.closed_to(owner, x, k)
}

impl Labels<'_> {
    /// Two cells of one parcel touching at a corner only (the other two cells of the 2×2 block not in it) make
    /// its outline touch itself: a free cell of the other diagonal joins the parcel, or else the costlier cell
    /// leaves it.
    fn fix_pinches(&mut self) -> bool {
        let nx = self.work.grid.nx;
        let mut any = false;
        for _ in 0..64 {
            let mut changed = false;
            for j in 0..self.work.grid.ny.saturating_sub(1) {
                for i in 0..nx - 1 {
                    let (a, b, c, d) = (
                        j * nx + i,
                        j * nx + i + 1,
                        (j + 1) * nx + i,
                        (j + 1) * nx + i + 1,
                    );
                    for (p, q, r, s) in [(a, d, b, c), (b, c, a, d)] {
                        let x = self.label[p];
                        if x == NONE
                            || self.label[q] != x
                            || self.label[r] == x
                            || self.label[s] == x
                        {
                            continue;
                        }
                        changed = true;
                        let fill = [r, s]
                            .into_iter()
                            .find(|&k| fillable(self.work, self.owner, self.label, x, k));
                        if let Some(k) = fill {
                            self.label[k] = x;
                            self.best[k] = self.best[p].max(self.best[q]);
                            continue;
                        }
                        // never the anchor; else the costlier
                        let drop = if self.is_anchor[p]
                            || (!self.is_anchor[q] && (self.best[q], q) > (self.best[p], p))
                        {
                            q
                        } else {
                            p
                        };
                        self.label[drop] = NONE;
                        self.best[drop] = f64::INFINITY;
                    }
                }
            }
            if !changed {
                break;
            }
            any = true;
        }
        any
    }

    /// A parcel enclosing cells that are not its own: free unclaimed cells join it; otherwise (water, a wall,
    /// another parcel) the parcel is cut back to the cells cheaper than those touching the hole.
    fn fix_holes(&mut self, n: usize) -> bool {
        let mut boxes = vec![(usize::MAX, usize::MAX, 0usize, 0usize); n];
        for (k, &x) in self.label.iter().enumerate() {
            if x != NONE {
                let (i, j) = self.work.grid.ij(k);
                let b = &mut boxes[x as usize];
                *b = (b.0.min(i), b.1.min(j), b.2.max(i), b.3.max(j));
            }
        }
        let mut changed = false;
        for (x, &bbox) in boxes.iter().enumerate() {
            if bbox.0 == usize::MAX {
                continue;
            }
            changed |= self.fix_holes_of(x as u32, bbox);
        }
        changed
    }

    /// [`Labels::fix_holes`] for parcel `x` whose cells lie in the box `(i0, j0, i1, j1)`.
    fn fix_holes_of(&mut self, x: u32, (bi0, bj0, bi1, bj1): (usize, usize, usize, usize)) -> bool {
        let ring = RingedBox {
            work: self.work,
            i0: bi0 as i64 - 1,
            j0: bj0 as i64 - 1,
            lnx: bi1 - bi0 + 3,
            lny: bj1 - bj0 + 3,
        };
        let mut changed = false;
        let mut seen = ring.outside(self.label, x);
        for start in 0..ring.lnx * ring.lny {
            if seen[start] || ring.label(start, self.label) == x {
                continue;
            }
            let hole = ring.hole(start, self.label, x, &mut seen);
            if hole
                .iter()
                .all(|&l| fillable(self.work, self.owner, self.label, x, ring.global(l)))
            {
                let rim = ring
                    .rim_costs(&hole, self.label, self.best, x)
                    .fold(0.0, f64::max);
                for &l in &hole {
                    self.label[ring.global(l)] = x;
                    self.best[ring.global(l)] = rim;
                }
                changed = true;
                continue;
            }
            let threshold = ring
                .rim_costs(&hole, self.label, self.best, x)
                .fold(f64::INFINITY, f64::min);
            if !(threshold > 0.0 && threshold.is_finite()) {
                // the hole touches the parcel's own road cells: its outline is kept around it
                continue;
            }
            for j in bj0..=bj1 {
                for i in bi0..=bi1 {
                    let k = j * self.work.grid.nx + i;
                    if self.label[k] == x && self.best[k] >= threshold && !self.is_anchor[k] {
                        self.label[k] = NONE;
                        self.best[k] = f64::INFINITY;
                        changed = true;
                    }
                }
            }
            // the parcel changed: its other holes are looked at again in the next round
            break;
        }
        changed
    }
}

/// A parcel's box with a ring of one cell around it (possibly outside the grid, where nothing is), its cells
/// numbered row by row from the lower left (`lnx` a row).
struct RingedBox<'a> {
    work: &'a Work,
    i0: i64,
    j0: i64,
    lnx: usize,
    lny: usize,
}

impl RingedBox<'_> {
    /// The grid cell of box cell `l`, `None` off the grid.
    fn cell(&self, l: usize) -> Option<usize> {
        self.work.inside(
            self.i0 + (l % self.lnx) as i64,
            self.j0 + (l / self.lnx) as i64,
        )
    }

    fn label(&self, l: usize, label: &[u32]) -> u32 {
        self.cell(l).map_or(NONE, |k| label[k])
    }

    /// The grid cell of box cell `l` (`l` lies inside the ring, so on the grid).
    fn global(&self, l: usize) -> usize {
        self.cell(l).unwrap_or(0)
    }

    /// The costs of the cells of parcel `x` bordering `hole`, once per side they share with it.
    fn rim_costs<'b>(
        &'b self,
        hole: &'b [usize],
        label: &'b [u32],
        best: &'b [f64],
        x: u32,
    ) -> impl Iterator<Item = f64> + 'b {
        hole.iter()
            .flat_map(|&l| self.neighbours(l))
            .filter(move |&m| self.label(m, label) == x)
            .map(|m| best[self.global(m)])
    }

    /// The 4-neighbours of box cell `l` within the box.
    fn neighbours(&self, l: usize) -> impl Iterator<Item = usize> {
        let (lnx, lny) = (self.lnx, self.lny);
        let (li, lj) = ((l % lnx) as i64, (l / lnx) as i64);
        N4.iter().filter_map(move |&(di, dj)| {
            let (a, b) = (li + di, lj + dj);
            (a >= 0 && b >= 0 && a < lnx as i64 && b < lny as i64)
                .then(|| b as usize * lnx + a as usize)
        })
    }

    /// The box cells reached from the ring without entering parcel `x`.
    fn outside(&self, label: &[u32], x: u32) -> Vec<bool> {
        let (lnx, lny) = (self.lnx, self.lny);
        let mut outside = vec![false; lnx * lny];
        let mut queue = VecDeque::new();
        for (l, out) in outside.iter_mut().enumerate() {
            let (li, lj) = (l % lnx, l / lnx);
            if li == 0 || lj == 0 || li == lnx - 1 || lj == lny - 1 {
                *out = true;
                queue.push_back(l);
            }
        }
        while let Some(l) = queue.pop_front() {
            for m in self.neighbours(l) {
                if !outside[m] && self.label(m, label) != x {
                    outside[m] = true;
                    queue.push_back(m);
                }
            }
        }
        outside
    }

    /// The hole of parcel `x` holding box cell `start`: the cells not of `x` 4-connected to it and not `seen`
    /// yet, which it marks seen.
    fn hole(&self, start: usize, label: &[u32], x: u32, seen: &mut [bool]) -> Vec<usize> {
        let mut hole = vec![start];
        seen[start] = true;
        let mut q = 0;
        while q < hole.len() {
            let l = hole[q];
            q += 1;
            for m in self.neighbours(l) {
                if !seen[m] && self.label(m, label) != x {
                    seen[m] = true;
                    hole.push(m);
                }
            }
        }
        hole
    }
}

//! The moves of one tile of the rdf-matching chain (see "Tiles and determinism" in the module documentation of
//! [`super::super`]): relocations and shifts of the tile's own instances, each accepted with `exp(−ΔE / τ)`
//! times the ratio of the product factors, where `ΔE` is computed from the pairs of the moved instance alone, and
//! the Hastings ratio of a relocation born from the map-weighted intensity (see [`super::super::births`]).

use super::{inverse_alphas, Shared};
use crate::analysis::folded_angle_bin;
use crate::geom::{DVec2, RegionQueries};
use crate::spatial::{FlatGrid, GridEntry};
use crate::synthesis::births::RectProposal;
use crate::synthesis::gaussian;
use crate::synthesis::target::{Target, CONTEXT_TAG};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// One tile of one phase: its rectangle `[lo, hi)`, its instances (global indices) and its share of the
/// phase's instances.
pub(super) struct Tile {
    pub(super) lo: DVec2,
    pub(super) hi: DVec2,
    pub(super) members: Vec<u32>,
    /// Its index in the sweep's tiles, and its colour phase.
    pub(super) index: usize,
    pub(super) phase: usize,
    pub(super) share: f64,
    pub(super) proposals: usize,
    pub(super) seed: u64,
}

/// The moving instances of a tile per cell of a `FlatGrid`'s layout: each cell a run of slots with room to grow,
/// its members' positions in them, so that a neighbour search reads a cell in order (a list per cell made it
/// chase one link per neighbour: the archipelago's coast points, about 190 neighbours a move, took 4–6 % longer).
struct MemberCells {
    /// Per cell: its first slot, its members and its slots.
    start: Vec<u32>,
    len: Vec<u32>,
    cap: Vec<u32>,
    /// Per slot: the position, the member and its row of `1/α` (read with the position, not through the member).
    xs: Vec<f64>,
    ys: Vec<f64>,
    who: Vec<u32>,
    weight_row: Vec<u32>,
    /// Per member: its cell and its slot.
    cell_of: Vec<u32>,
    slot_of: Vec<u32>,
}

impl MemberCells {
    /// The members at `pos` in the cells `cell_of` (of `cells` cells), with their rows of `1/α` `rows`.
    fn new(cells: usize, cell_of: Vec<u32>, pos: &[DVec2], rows: &[u32]) -> Self {
        let mut mc = MemberCells {
            start: vec![0; cells],
            len: vec![0; cells],
            cap: vec![0; cells],
            xs: Vec::new(),
            ys: Vec::new(),
            who: Vec::new(),
            weight_row: Vec::new(),
            slot_of: vec![0; cell_of.len()],
            cell_of,
        };
        mc.lay_out(pos, rows);
        mc
    }

    /// Slots for every cell's members and half as many more (at least two), the members written in.
    fn lay_out(&mut self, pos: &[DVec2], rows: &[u32]) {
        self.len.fill(0);
        for &c in &self.cell_of {
            self.len[c as usize] += 1;
        }
        let mut next = 0u32;
        for c in 0..self.start.len() {
            self.start[c] = next;
            self.cap[c] = self.len[c] + self.len[c] / 2 + 2;
            next += self.cap[c];
            self.len[c] = 0;
        }
        let slots = next as usize;
        self.xs = vec![0.0; slots];
        self.ys = vec![0.0; slots];
        self.who = vec![NONE; slots];
        self.weight_row = vec![0; slots];
        for (k, p) in pos.iter().enumerate() {
            self.place(k, *p, rows[k]);
        }
    }

    /// Writes member `k` at `p` (its row of `1/α` `row`) into the next slot of its cell, which has room.
    fn place(&mut self, k: usize, p: DVec2, row: u32) {
        let c = self.cell_of[k] as usize;
        let slot = (self.start[c] + self.len[c]) as usize;
        self.len[c] += 1;
        self.xs[slot] = p.x;
        self.ys[slot] = p.y;
        self.who[slot] = k as u32;
        self.weight_row[slot] = row;
        self.slot_of[k] = slot as u32;
    }

    /// Member `k` moves to `p` in cell `cell` (`pos` and `rows`: every member's position and row of `1/α` after
    /// the move).
    fn move_to(&mut self, k: usize, cell: usize, p: DVec2, pos: &[DVec2], rows: &[u32]) {
        let old = self.cell_of[k] as usize;
        if old == cell {
            let slot = self.slot_of[k] as usize;
            self.xs[slot] = p.x;
            self.ys[slot] = p.y;
            self.weight_row[slot] = rows[k];
            return;
        }
        // the cell's last member fills the slot left
        let (slot, last) = (
            self.slot_of[k] as usize,
            (self.start[old] + self.len[old] - 1) as usize,
        );
        self.xs[slot] = self.xs[last];
        self.ys[slot] = self.ys[last];
        self.who[slot] = self.who[last];
        self.weight_row[slot] = self.weight_row[last];
        self.slot_of[self.who[slot] as usize] = slot as u32;
        self.len[old] -= 1;
        self.cell_of[k] = cell as u32;
        if self.len[cell] < self.cap[cell] {
            self.place(k, p, rows[k]);
        } else {
            self.lay_out(pos, rows);
        }
    }

    /// The slots of cell `c`'s members.
    #[inline]
    fn run(&self, c: usize) -> std::ops::Range<usize> {
        let a = self.start[c] as usize;
        a..a + self.len[c] as usize
    }
}

const NONE: u32 = u32::MAX;
/// A map bin not read yet, and a map read outside its bins (see [`TileChain::bins`]).
const UNREAD: u32 = u32::MAX;
const NO_BIN: u32 = u32::MAX - 1;

/// Each map's bin at `at` into `out` (`NO_BIN` outside its bins).
fn read_bins(target: &Target, at: DVec2, out: &mut [u32]) {
    for (m, b) in target.maps.iter().zip(out) {
        *b = m.bin_at(target.terrain, at).map_or(NO_BIN, |k| k as u32);
    }
}

/// `ln` of the map factors of a point whose bins are `bins`, as [`Target::map_log`] reads them.
fn log_factor_of(target: &Target, bins: &[u32]) -> f64 {
    let mut sum = 0.0;
    for (m, &b) in target.maps.iter().zip(bins) {
        if b == NO_BIN {
            return f64::NEG_INFINITY;
        }
        sum += m.hist.values[b as usize];
    }
    sum
}

/// Moves of one tile: returns the new positions of its members (in order) and its change of `H` (flat).
pub(super) fn run_tile(sh: &Shared, tile: &Tile) -> (Vec<DVec2>, Vec<f64>) {
    let offs = sh.offs;
    let delta = vec![0.0; offs[offs.len() - 1]];
    if tile.members.is_empty() || tile.proposals == 0 {
        return (Vec::new(), delta);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(tile.seed);
    let mut chain = TileChain::new(sh, tile, delta);
    if sh.own_pairs {
        chain.count_own_pairs();
    }
    for _ in 0..tile.proposals {
        // a tile whose own pairs lie within the targets' noise is done (see "When to stop")
        if sh.own_pairs && chain.own_chi2 <= sh.chi2_bound {
            break;
        }
        chain.step(&mut rng);
    }
    let mut pos = chain.pos;
    pos.truncate(tile.members.len());
    (pos, chain.delta)
}

/// A neighbour within the interaction radius of a moved instance: pair tag, weight row, offset, squared distance.
type Neighbour = (u32, u32, DVec2, f64);
/// An own moving instance within the interaction radius of a moved one: weight row, offset, squared distance.
type OwnNeighbour = (u32, DVec2, f64);

/// A tile's rectangle `[lo, hi)` and its halo `[elo, ehi]`: the rectangle grown by the interaction radius.
#[derive(Clone, Copy)]
struct Bounds {
    lo: DVec2,
    hi: DVec2,
    elo: DVec2,
    ehi: DVec2,
}

impl Bounds {
    fn in_tile(&self, p: DVec2) -> bool {
        p.x >= self.lo.x && p.x < self.hi.x && p.y >= self.lo.y && p.y < self.hi.y
    }

    fn in_halo(&self, p: DVec2) -> bool {
        p.x >= self.elo.x && p.x <= self.ehi.x && p.y >= self.elo.y && p.y <= self.ehi.y
    }
}

/// The chain of one tile, on a local copy: the tile's instances (ids `0..m`, moving), the own instances around
/// it (ids from `m` on) and the fixed content around it (static).
struct TileChain<'s, 'a, 'b> {
    sh: &'s Shared<'a, 'b>,
    bounds: Bounds,
    /// Where relocations land: the tile within the region's box.
    slo: DVec2,
    shi: DVec2,
    /// Relocations drawn from the map-weighted intensity over `slo..shi` (uniformly without it).
    births: Option<RectProposal<'a>>,
    /// Whether the region covers the tile with a margin of the interaction radius: then every proposal in the
    /// tile lies inside it with its whole disc (α = 1), which need not be asked of the region proposal by proposal.
    interior: bool,
    m: usize,
    pos: Vec<DVec2>,
    /// `1/α` per local own point: a row of `pool` (row 0: zeros, for the fixed content; row 1: ones, interior).
    pool: Vec<f64>,
    slot: Vec<u32>,
    /// The static content, with its weight row as id.
    grid: FlatGrid,
    cells: MemberCells,
    /// The tile's accepted change of `H`.
    delta: Vec<f64>,
    /// The change of `H` of the move under way; every histogram index is listed at most once in `touched`.
    d_h: Vec<f64>,
    touched: Vec<u32>,
    nt: usize,
    ia_new: Vec<f64>,
    cand: Vec<Neighbour>,
    own_cand: Vec<OwnNeighbour>,
    /// Per distance bin of the own pairs (one angle bin): the weights of the move under way's own pairs there, in
    /// two sums taken in turn (see [`Self::own_changes`]), zero between moves.
    bin_even: Vec<f64>,
    bin_odd: Vec<f64>,
    inv_share: f64,
    /// With `own_pairs`, per pair histogram index: the tile's own pairs less its share of the targets, and the
    /// weight of its chi-square scaled up to the region (see "Tiles match their own pairs" in [`super::super`]).
    own_dev: Vec<f64>,
    own_weight: Vec<f64>,
    /// With `own_pairs`: the tile's chi-square `Σ own_weight · (own_dev + delta)²`, kept by the accepted moves.
    own_chi2: f64,
    /// Each map's bin at each member's position (`maps` a member, `UNREAD` until a move of the member reads
    /// them) and at the proposed position: the terrain is sampled once a proposal, not at both ends twice.
    bins: Vec<u32>,
    q_bins: Vec<u32>,
}

impl<'s, 'a, 'b> TileChain<'s, 'a, 'b> {
    fn new(sh: &'s Shared<'a, 'b>, tile: &'s Tile, delta: Vec<f64>) -> Self {
        let r = sh.target.radius;
        let bounds = Bounds {
            lo: tile.lo,
            hi: tile.hi,
            elo: tile.lo - DVec2::splat(r),
            ehi: tile.hi + DVec2::splat(r),
        };
        let m = tile.members.len();
        let pos = local_points(sh, tile, &bounds);
        let (pool, slot) = weight_rows(sh, &pos);
        let grid = static_grid(sh, &bounds, &pos[m..], &slot[m..], grid_cell(sh, tile));
        let grid_len = grid.xs.len();
        let cell_of = pos[..m]
            .iter()
            .map(|p| {
                let (cx, cy) = grid.cell_coords(*p);
                (cy * grid.nx() + cx) as u32
            })
            .collect();
        let cells = MemberCells::new(grid.n_cells(), cell_of, &pos[..m], &slot[..m]);
        let (rlo, rhi) = sh.region.bbox();
        let (slo, shi) = (tile.lo.max(rlo), tile.hi.min(rhi));
        let half = (tile.hi - tile.lo) * 0.5;
        let reach = half.length() + sh.target.bin_width * sh.n_alpha as f64;
        let interior = sh.region.covers_disc(tile.lo + half, reach * (1.0 + 1e-6));
        TileChain {
            sh,
            bounds,
            slo,
            shi,
            births: sh.births.map(|b| b.over(slo, shi)),
            interior,
            m,
            pos,
            pool,
            slot,
            grid,
            cells,
            d_h: delta.clone(),
            touched: vec![0; delta.len() + 1],
            delta,
            nt: 0,
            ia_new: vec![1.0; sh.n_alpha],
            cand: vec![(0, 0, DVec2::ZERO, 0.0); grid_len],
            own_cand: vec![(0, DVec2::ZERO, 0.0); m],
            bin_even: vec![0.0; sh.last_bin[sh.self_tag as usize] + 1],
            bin_odd: vec![0.0; sh.last_bin[sh.self_tag as usize] + 1],
            inv_share: 1.0 / tile.share,
            own_dev: Vec::new(),
            own_weight: Vec::new(),
            own_chi2: 0.0,
            bins: vec![UNREAD; m * sh.target.maps.len()],
            q_bins: vec![UNREAD; sh.target.maps.len()],
        }
    }

    /// The tile's own pair histograms, less its share `f` of the targets (its count over the own instances'),
    /// and their weights `1 / (f max(f T, 1))`: its chi-square as the region's would read were every tile as far
    /// from its share as this one. A member's pairs are read as a move counts them: with the own instances both
    /// ways, halved (a pair within the tile then counts once each way, one with the halo about once), with the
    /// fixed content one way.
    fn count_own_pairs(&mut self) {
        let offs = self.sh.offs;
        let n_pairs = offs[self.sh.target.tables.len()];
        let tag = self.sh.self_tag as usize;
        let both_ways = offs[tag]..offs[tag + 1];
        let frac = self.m as f64 / self.sh.own.len().max(1) as f64;
        let mut own = vec![0.0; n_pairs];
        for k in 0..self.m {
            self.nt = 0;
            // a removal is never refused: it only reads the member's pairs
            let _ = self.pair_changes(-1.0, self.pos[k], k, false);
            for &h in &self.touched[..self.nt] {
                let h = h as usize;
                if h < n_pairs {
                    let half = if both_ways.contains(&h) { 0.5 } else { 1.0 };
                    own[h] -= half * self.d_h[h];
                }
                self.d_h[h] = 0.0;
            }
        }
        self.nt = 0;
        self.own_weight = (0..n_pairs)
            .map(|h| {
                let t = frac * self.sh.targets[h];
                if self.sh.weight[h] > 0.0 {
                    1.0 / (frac * t.max(1.0))
                } else {
                    0.0
                }
            })
            .collect();
        self.own_dev = (0..n_pairs)
            .map(|h| own[h] - frac * self.sh.targets[h])
            .collect();
        self.own_chi2 = super::chi2(&self.own_dev, &self.own_weight);
    }

    fn cell_index(&self, p: DVec2) -> usize {
        let (cx, cy) = self.grid.cell_coords(p);
        cy * self.grid.nx() + cx
    }

    /// One proposal: a relocation or a shift of a random member, its change of `H`, and its acceptance.
    fn step(&mut self, rng: &mut ChaCha8Rng) {
        let sh = self.sh;
        let target = sh.target;
        let k = rng.random_range(0..self.m);
        let p = self.pos[k];
        let (q, hastings) = self.propose(p, rng);
        if !self.bounds.in_tile(q) || !(self.interior || sh.region.contains(q)) {
            return;
        }
        read_bins(target, q, &mut self.q_bins);
        let map_new = log_factor_of(target, &self.q_bins);
        if map_new == f64::NEG_INFINITY {
            return;
        }
        let q_border =
            !self.interior && inverse_alphas(sh.region, q, target.bin_width, &mut self.ia_new);
        self.nt = 0;
        // pairs at q (added) and at p (removed)
        let Some(ctx_new) = self.pair_changes(1.0, q, k, q_border) else {
            self.forget_move();
            return;
        };
        let Some(ctx_old) = self.pair_changes(-1.0, p, k, q_border) else {
            self.forget_move();
            return;
        };
        let nm = target.maps.len();
        if self.bins[k * nm..].first() == Some(&UNREAD) {
            read_bins(target, p, &mut self.bins[k * nm..(k + 1) * nm]);
        }
        self.map_changes(k);
        let d_e = self.energy_change();
        let log_accept = -d_e / sh.tau
            + (map_new - log_factor_of(target, &self.bins[k * nm..(k + 1) * nm]))
            + (target.ghost_log(q) - target.ghost_log(p))
            + (ctx_new.min(target.saturation) - ctx_old.min(target.saturation))
            + hastings;
        let accept = rng.random::<f64>().ln() < log_accept;
        for &h in &self.touched[..self.nt] {
            let h = h as usize;
            if accept {
                self.delta[h] += self.d_h[h];
            }
            self.d_h[h] = 0.0;
        }
        if accept {
            // with own pairs every touched bin is the tile's own (no maps), so `d_e` is its chi-square's change
            self.own_chi2 += d_e;
            self.move_member(k, q, q_border);
            self.bins[k * nm..(k + 1) * nm].copy_from_slice(&self.q_bins);
        }
    }

    /// A relocation inside the tile (the death of p and the birth of q, drawn from the map-weighted intensity
    /// `g` when there is one) or a symmetric Gaussian shift, with the log Hastings ratio `ln g(p) − ln g(q)` of
    /// the move (0 when symmetric).
    fn propose(&self, p: DVec2, rng: &mut ChaCha8Rng) -> (DVec2, f64) {
        let (slo, shi) = (self.slo, self.shi);
        if rng.random::<f64>() < 0.5 {
            match &self.births {
                Some(b) => {
                    let q = b.sample(rng);
                    (q, b.log_weight(p) - b.log_weight(q))
                }
                None => (
                    DVec2::new(
                        slo.x + rng.random::<f64>() * (shi.x - slo.x),
                        slo.y + rng.random::<f64>() * (shi.y - slo.y),
                    ),
                    0.0,
                ),
            }
        } else {
            (p + gaussian(rng) * self.sh.shift_sigma, 0.0)
        }
    }

    /// Clears the change of `H` of a rejected (forbidden) move.
    fn forget_move(&mut self) {
        for &h in &self.touched[..self.nt] {
            self.d_h[h as usize] = 0.0;
        }
    }

    /// Gathers the neighbours within the radius of `at` (member `k` left out), without branching on the distance:
    /// the fixed content into `cand`, the moving own instances into `own_cand`; returns their counts. Both hold a
    /// slot for every local point, so they never grow here, and the loops read local slices (writes to them would
    /// otherwise make them reload every field of `self`).
    fn gather_neighbours(&mut self, at: DVec2, k: usize) -> (usize, usize) {
        let r = self.sh.target.radius;
        let r2 = r * r;
        let grid = &self.grid;
        let (xs, ys, tags, ids) = (&grid.xs[..], &grid.ys[..], &grid.tags[..], &grid.ids[..]);
        let cells = &self.cells;
        let (mx, my, rows) = (&cells.xs[..], &cells.ys[..], &cells.weight_row[..]);
        // member `k` by its slot, so the loop reads no member index
        let skip = cells.slot_of[k] as usize;
        let (cand, own_cand) = (&mut self.cand[..], &mut self.own_cand[..]);
        let lnx = grid.nx();
        let (mut n, mut no) = (0usize, 0usize);
        let (x0, y0) = grid.cell_coords(at - DVec2::splat(r));
        let (x1, y1) = grid.cell_coords(at + DVec2::splat(r));
        for cy in y0..=y1 {
            let (a, b) = grid.row_range(cy, x0, x1);
            for i in a..b {
                let v = DVec2::new(xs[i] - at.x, ys[i] - at.y);
                let d2 = v.x * v.x + v.y * v.y;
                cand[n] = (tags[i], ids[i], v, d2);
                n += usize::from(d2 <= r2);
            }
            for c in cy * lnx + x0..=cy * lnx + x1 {
                for i in cells.run(c) {
                    let v = DVec2::new(mx[i] - at.x, my[i] - at.y);
                    let d2 = v.x * v.x + v.y * v.y;
                    own_cand[no] = (rows[i], v, d2);
                    no += usize::from(d2 <= r2 && i != skip);
                }
            }
        }
        (n, no)
    }

    /// Adds (`sign` 1, member `k` born at `at`) or removes (−1, member `k` dying at `at`) its pairs in `d_h`;
    /// returns the log product factor of its pairs with the context, None when a birth breaks a hard core.
    fn pair_changes(&mut self, sign: f64, at: DVec2, k: usize, q_border: bool) -> Option<f64> {
        let (n, no) = self.gather_neighbours(at, k);
        // the moved instance's weights `1/α`: its own near the border at a new position, else a pool row (row 1
        // of ones for a birth inside)
        let row = if sign > 0.0 && q_border {
            None
        } else {
            let nb = self.sh.n_alpha;
            let row = if sign > 0.0 { 1 } else { self.slot[k] as usize };
            Some(row * nb..(row + 1) * nb)
        };
        if !self.own_changes(sign, no, row.clone()) {
            return None;
        }
        self.fixed_changes(sign, n, row)
    }

    /// The pairs with the `no` own neighbours gathered (weights of the moved instance at `row` of the pool, or
    /// `ia_new`); false when a birth breaks a hard core. All of one table, whose constants are read once (the
    /// archipelago's coast points have about 190 own neighbours a move).
    fn own_changes(&mut self, sign: f64, no: usize, row: Option<std::ops::Range<usize>>) -> bool {
        let sh = self.sh;
        let (nb, log_factor) = (sh.n_alpha, sh.log_factor);
        let st = sh.self_tag as usize;
        let t = &sh.target.tables[st];
        let (off, last, inv_bw, hc2, ab) = (
            sh.offs[st],
            sh.last_bin[st],
            t.inv_bin_width,
            t.hard_core2,
            t.angle_bins,
        );
        let pool = &self.pool[..];
        let ia_x = row.map_or(&self.ia_new[..], |r| &pool[r]);
        let (d_h, touched, nt) = (&mut self.d_h[..], &mut self.touched[..], &mut self.nt);
        let own = &self.own_cand[..no];
        if ab == 1 && own.len() > last {
            // more neighbours than bins are summed per distance bin first, fewer are cheaper one at a time; in two
            // sums taken in turn, as neighbours read in a cell's order often share a bin and one sum would wait
            // on its last addition (pairs' weights are positive: a bin with none sums to zero)
            let (even, odd) = (&mut self.bin_even[..], &mut self.bin_odd[..]);
            let mut nearest = f64::INFINITY;
            let mut bin = |&(row, _, d2): &OwnNeighbour| {
                let kd = ((d2.sqrt() * inv_bw) as usize).min(last);
                let kw = kd.min(nb - 1);
                nearest = nearest.min(d2);
                (kd, ia_x[kw] + pool[row as usize * nb + kw])
            };
            let pairs = own.chunks_exact(2);
            let rest = pairs.remainder();
            for p in pairs {
                let ((ka, wa), (kb, wb)) = (bin(&p[0]), bin(&p[1]));
                even[ka] += wa;
                odd[kb] += wb;
            }
            for c in rest {
                let (k, w) = bin(c);
                even[k] += w;
            }
            let mut forbidden = sign > 0.0 && nearest < hc2;
            for kd in 0..=last {
                let w = even[kd] + odd[kd];
                if w != 0.0 {
                    forbidden |= sign > 0.0 && log_factor[off + kd] == f64::NEG_INFINITY;
                    touch(d_h, touched, nt, off + kd, sign * w);
                    even[kd] = 0.0;
                    odd[kd] = 0.0;
                }
            }
            return !forbidden;
        }
        for &(row, v, d2) in own {
            let kd = ((d2.sqrt() * inv_bw) as usize).min(last);
            let h = off
                + if ab == 1 {
                    kd
                } else {
                    kd * ab + folded_angle_bin(v, ab)
                };
            if sign > 0.0 && (d2 < hc2 || log_factor[h] == f64::NEG_INFINITY) {
                return false;
            }
            let kw = kd.min(nb - 1);
            let w = ia_x[kw] + pool[row as usize * nb + kw];
            touch(d_h, touched, nt, h, sign * w);
        }
        true
    }

    /// The pairs with the `n` fixed neighbours gathered (see [`Self::own_changes`]): the log product factor of
    /// those with the context, None when a birth breaks a hard core.
    fn fixed_changes(
        &mut self,
        sign: f64,
        n: usize,
        row: Option<std::ops::Range<usize>>,
    ) -> Option<f64> {
        let sh = self.sh;
        let (tables, offs, nb) = (&sh.target.tables, sh.offs, sh.n_alpha);
        let (last_bin, log_factor) = (sh.last_bin, sh.log_factor);
        let pool = &self.pool[..];
        let ia_x = row.map_or(&self.ia_new[..], |r| &pool[r]);
        let (d_h, touched, nt) = (&mut self.d_h[..], &mut self.touched[..], &mut self.nt);
        let mut ctx = 0.0;
        for &(tag, row, v, d2) in &self.cand[..n] {
            let ti = (tag & !CONTEXT_TAG) as usize;
            let t = &tables[ti];
            let kd = ((d2.sqrt() * t.inv_bin_width) as usize).min(last_bin[ti]);
            let idx = if t.angle_bins == 1 {
                kd
            } else {
                kd * t.angle_bins + folded_angle_bin(v, t.angle_bins)
            };
            let h = offs[ti] + idx;
            let lf = if d2 < t.hard_core2 {
                f64::NEG_INFINITY
            } else {
                log_factor[h]
            };
            if sign > 0.0 && lf == f64::NEG_INFINITY {
                return None;
            }
            if tag & CONTEXT_TAG != 0 {
                ctx += lf;
                continue;
            }
            let kd = kd.min(nb - 1);
            let w = ia_x[kd] + pool[row as usize * nb + kd];
            touch(d_h, touched, nt, h, sign * w);
        }
        Some(ctx)
    }

    /// The map histograms: member `k` leaves its bins for those of the proposed position.
    fn map_changes(&mut self, k: usize) {
        let target = self.sh.target;
        let offs = self.sh.offs;
        let nm = target.maps.len();
        for (mi, m) in target.maps.iter().enumerate() {
            if m.wanted.is_empty() {
                continue;
            }
            for (sign, b) in [(1.0, self.q_bins[mi]), (-1.0, self.bins[k * nm + mi])] {
                if b != NO_BIN {
                    let h = offs[target.tables.len() + mi] + b as usize;
                    touch(&mut self.d_h, &mut self.touched, &mut self.nt, h, sign);
                }
            }
        }
    }

    /// `ΔE` of the move under way: the tile sees its own pairs against its share of the targets where it matches
    /// them, and otherwise `H − T` at the start of the phase plus its own changes scaled by its share (see "Tiles
    /// match their own pairs").
    fn energy_change(&self) -> f64 {
        let sh = self.sh;
        let mut d_e = 0.0;
        let n_own = self.own_dev.len();
        for &h in &self.touched[..self.nt] {
            let h = h as usize;
            let dh = self.d_h[h];
            if h < n_own {
                let view = self.own_dev[h] + self.delta[h];
                d_e += self.own_weight[h] * (2.0 * view * dh + dh * dh);
            } else {
                let view = sh.dev[h] + self.delta[h] * self.inv_share;
                d_e += sh.weight[h] * (2.0 * view * dh + dh * dh * self.inv_share);
            }
        }
        d_e
    }

    /// Member `k` moves to `q`: its cell, its position, and its `1/α` row (its own row when the window cuts
    /// its disc, reused when it had one).
    fn move_member(&mut self, k: usize, q: DVec2, q_border: bool) {
        let nb = self.sh.n_alpha;
        let cell = self.cell_index(q);
        self.pos[k] = q;
        if q_border {
            if self.slot[k] <= 1 {
                self.slot[k] = (self.pool.len() / nb) as u32;
                self.pool.extend_from_slice(&self.ia_new);
            } else {
                let s0 = self.slot[k] as usize * nb;
                self.pool[s0..s0 + nb].copy_from_slice(&self.ia_new);
            }
        } else {
            self.slot[k] = 1;
        }
        self.cells
            .move_to(k, cell, q, &self.pos[..self.m], &self.slot[..self.m]);
    }
}

/// The tile's members, then the own instances in its halo: members of the neighbouring tiles, as tiles are at
/// least twice the interaction radius wide.
fn local_points(sh: &Shared, tile: &Tile, bounds: &Bounds) -> Vec<DVec2> {
    let mut pos: Vec<DVec2> = tile.members.iter().map(|&g| sh.own[g as usize]).collect();
    for next in sh.tiles.neighbours(tile.index) {
        pos.extend(
            next.members
                .iter()
                .map(|&g| sh.own[g as usize])
                .filter(|p| bounds.in_halo(*p)),
        );
    }
    pos
}

/// The `1/α` rows of the local points (`pool`, rows of `n_alpha`) and each point's row (`slot`): the shared
/// interior row 1 unless the window cuts its disc.
fn weight_rows(sh: &Shared, pos: &[DVec2]) -> (Vec<f64>, Vec<u32>) {
    let nb = sh.n_alpha;
    let mut pool: Vec<f64> = vec![0.0; nb];
    pool.extend(std::iter::repeat_n(1.0, nb));
    let mut slot = vec![1u32; pos.len()];
    let mut scratch = vec![1.0; nb];
    for (id, p) in pos.iter().enumerate() {
        if inverse_alphas(sh.region, *p, sh.target.bin_width, &mut scratch) {
            slot[id] = (pool.len() / nb) as u32;
            pool.extend_from_slice(&scratch);
        }
    }
    (pool, slot)
}

/// Own instances within the interaction radius of an instance, about, below which a neighbour search reads cells
/// of the radius rather than of half of it.
const SPARSE_NEIGHBOURS: f64 = 16.0;

/// The side of the cells of a tile's grids: the radius where a search finds few neighbours (fewer, larger cells:
/// the grass of the scale bench, five neighbours in 25 cells of half the radius, spent most of a search on its
/// cells), half of it where it finds many (the archipelago's coasts, over 200 neighbours, read a quarter of the
/// area beyond the radius).
fn grid_cell(sh: &Shared, tile: &Tile) -> f64 {
    let r = sh.target.radius;
    let area = (tile.hi - tile.lo).x * (tile.hi - tile.lo).y;
    let neighbours = tile.members.len() as f64 / area * std::f64::consts::PI * r * r;
    if neighbours < SPARSE_NEIGHBOURS {
        sh.target.cell
    } else {
        0.5 * sh.target.cell
    }
}

/// The static content in a grid of cells of `cell` over the halo: the own instances around the tile (`around`,
/// with their weight rows `rows` as ids), then the fixed content in the halo (row 0).
fn static_grid(
    sh: &Shared,
    bounds: &Bounds,
    around: &[DVec2],
    rows: &[u32],
    cell: f64,
) -> FlatGrid {
    let mut statics: Vec<GridEntry> = around
        .iter()
        .zip(rows)
        .map(|(p, row)| GridEntry {
            position: *p,
            tag: sh.self_tag,
            id: *row,
        })
        .collect();
    let fg = sh.fixed;
    fg.for_each_in_box_cells(bounds.elo, bounds.ehi, |i| {
        let p = DVec2::new(fg.xs[i], fg.ys[i]);
        if bounds.in_halo(p) {
            statics.push(GridEntry {
                position: p,
                tag: fg.tags[i],
                id: 0,
            });
        }
    });
    FlatGrid::build(bounds.elo, bounds.ehi, cell, statics.len(), |i| statics[i])
}

/// Adds `change` to histogram index `h` of the move's `d_h`, listing `h` in `touched` the first time.
#[inline]
fn touch(d_h: &mut [f64], touched: &mut [u32], nt: &mut usize, h: usize, change: f64) {
    let cell = &mut d_h[h];
    touched[*nt] = h as u32;
    *nt += usize::from(*cell == 0.0);
    *cell += change;
    if *cell == 0.0 {
        // keep it listed once: a tiny non-zero marks it as touched
        *cell = f64::MIN_POSITIVE;
    }
}

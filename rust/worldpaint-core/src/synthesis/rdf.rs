//! The rdf-matching chain for larger counts (see "Larger regions: matching the rdf" in the module documentation
//! of [`super`]): an annealed chi-square energy between the window-corrected pair histograms and the learned
//! ones, evaluated on tiles in parallel.

use super::target::{PairTable, Target, CONTEXT_TAG};
use super::{annealed, gaussian, mix_seed};
use crate::analysis::folded_angle_bin;
use crate::error::{Error, Result};
use crate::geom::{DVec2, Region};
use crate::spatial::{FlatGrid, GridEntry, SpatialGrid};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Sweeps of the rdf-matching chain (tiles are redrawn and the temperature lowered between sweeps).
const RDF_SWEEPS: usize = 12;
/// Temperature of the first and of the last sweeps (in units of the chi-square energy, see the module docs).
const TAU_START: f64 = 1.0;
const TAU_END: f64 = 0.02;
/// Fraction of the sweeps over which the temperature decreases (it is then held at `TAU_END`).
const ANNEALING_FRACTION: f64 = 0.75;
/// Tiles hold at least this many expected instances (and are at least twice the interaction radius wide).
const MIN_TILE_INSTANCES: f64 = 256.0;

/// `1 / α` per distance bin at `p`, written into `out`; returns false (and leaves `out` alone) when the
/// whole disc of the interaction radius lies inside the region (α = 1).
fn inverse_alphas(region: &Region, p: DVec2, bin_width: f64, n: usize, out: &mut [f64]) -> bool {
    if region.contains(p) && region.distance_to_boundary(p) >= bin_width * n as f64 {
        return false;
    }
    for (o, a) in out
        .iter_mut()
        .zip(crate::analysis::alphas(region, p, bin_width, n))
    {
        *o = 1.0 / a;
    }
    true
}

/// Distance bins of a pair table in the flat histograms: its own, then zero-weight padding up to the
/// interaction radius so that any neighbour's bin is an index (bins beyond the table count for nothing).
fn padded_bins(t: &PairTable, radius: f64) -> usize {
    let reach = radius / t.bin_width;
    if reach.is_finite() && reach >= 0.0 {
        t.n_bins.max((reach.min(1e6)) as usize + 2)
    } else {
        t.n_bins
    }
}

/// Offsets of the matched histograms in one flat array: every pair table (padded, see `padded_bins`), then
/// every map (empty when its wanted distribution is unknown); the last entry is the total length.
fn histogram_offsets(target: &Target) -> Vec<usize> {
    let mut offs = vec![0];
    let sizes = target
        .tables
        .iter()
        .map(|t| padded_bins(t, target.radius) * t.angle_bins.max(1))
        .chain(target.maps.iter().map(|m| m.wanted.len()));
    for len in sizes {
        offs.push(offs[offs.len() - 1] + len);
    }
    offs
}

/// Bin of map `mi` at `p` (None for a map without a wanted distribution).
#[inline]
fn map_bin(target: &Target, mi: usize, p: DVec2) -> Option<usize> {
    let m = &target.maps[mi];
    if m.wanted.is_empty() {
        return None;
    }
    m.bin_at(target.terrain, p)
}

/// Read-only state shared by the tiles of one phase.
struct Shared<'a, 'b> {
    target: &'a Target<'b>,
    region: &'a Region,
    self_tag: u32,
    n_alpha: usize,
    own: &'a [DVec2],
    /// The own points (ids: indices into `own`).
    own_grid: &'a FlatGrid,
    /// The fixed content (other categories inside the region, context outside it).
    fixed: &'a FlatGrid,
    /// Offsets of the histograms in the flat arrays (see `histogram_offsets`).
    offs: &'a [usize],
    /// Per table: its last padded distance bin.
    last_bin: &'a [usize],
    /// Per pair histogram index: the log factor (0 in the padding).
    log_factor: &'a [f64],
    /// Per histogram index: current pair histogram minus target, `H − T`, over the whole region.
    dev: &'a [f64],
    /// Per histogram index: weight `1 / max(T, 1)`.
    weight: &'a [f64],
    tau: f64,
    shift_sigma: f64,
}

/// One tile of one phase: its rectangle `[lo, hi)`, its instances (global indices) and its share of the
/// phase's instances.
struct Tile {
    lo: DVec2,
    hi: DVec2,
    members: Vec<u32>,
    share: f64,
    proposals: usize,
    seed: u64,
}

/// Pair histograms `H` (flat, see `histogram_offsets`) of the own points with the own points and with the fixed
/// content inside the region: `H(k) = Σ_i Σ_j [d(x_i, y_j) in cell k] / α_{x_i}(k)` — eq. (2) before
/// normalization.
fn pair_histograms(sh: &Shared) -> Vec<f64> {
    use rayon::prelude::*;
    let tables = &sh.target.tables;
    let offs = sh.offs;
    let n_hist = offs[offs.len() - 1];
    let r = sh.target.radius;
    let chunks: Vec<Vec<f64>> = sh
        .own
        .par_chunks(1024)
        .enumerate()
        .map(|(c, chunk)| {
            let mut h = vec![0.0; n_hist];
            let mut ia = vec![1.0; sh.n_alpha];
            for (o, &p) in chunk.iter().enumerate() {
                let id = (c * 1024 + o) as u32;
                if !inverse_alphas(sh.region, p, sh.target.bin_width, sh.n_alpha, &mut ia) {
                    ia.fill(1.0);
                }
                for g in [sh.own_grid, sh.fixed] {
                    g.for_each_within(p, r, |i, d2| {
                        let tag = g.tags[i];
                        if tag & CONTEXT_TAG != 0 || (tag == sh.self_tag && g.ids[i] == id) {
                            return true;
                        }
                        let t = &tables[tag as usize];
                        let v = DVec2::new(g.xs[i] - p.x, g.ys[i] - p.y);
                        if let Some((idx, k)) = t.bin_of(v, d2) {
                            h[offs[tag as usize] + idx] += ia[k.min(sh.n_alpha - 1)];
                        }
                        true
                    });
                }
                for mi in 0..sh.target.maps.len() {
                    if let Some(b) = map_bin(sh.target, mi, p) {
                        h[offs[tables.len() + mi] + b] += 1.0;
                    }
                }
            }
            h
        })
        .collect();
    let mut total = vec![0.0; n_hist];
    for h in chunks {
        for (x, y) in total.iter_mut().zip(h) {
            *x += y;
        }
    }
    total
}

/// The moving instances of a tile, listed per cell of a `FlatGrid`'s layout (doubly linked lists).
struct MemberCells {
    head: Vec<u32>,
    next: Vec<u32>,
    prev: Vec<u32>,
    cell_of: Vec<u32>,
}

const NONE: u32 = u32::MAX;

impl MemberCells {
    fn new(cells: usize, members: usize) -> Self {
        MemberCells {
            head: vec![NONE; cells],
            next: vec![NONE; members],
            prev: vec![NONE; members],
            cell_of: vec![0; members],
        }
    }

    fn insert(&mut self, k: usize, cell: usize) {
        let h = self.head[cell];
        self.next[k] = h;
        self.prev[k] = NONE;
        if h != NONE {
            self.prev[h as usize] = k as u32;
        }
        self.head[cell] = k as u32;
        self.cell_of[k] = cell as u32;
    }

    fn remove(&mut self, k: usize) {
        let (p, n) = (self.prev[k], self.next[k]);
        if p != NONE {
            self.next[p as usize] = n;
        } else {
            self.head[self.cell_of[k] as usize] = n;
        }
        if n != NONE {
            self.prev[n as usize] = p;
        }
    }
}

/// Moves of one tile: returns the new positions of its members (in order) and its change of `H` (flat).
fn run_tile(sh: &Shared, tile: &Tile) -> (Vec<DVec2>, Vec<f64>) {
    let target = sh.target;
    let tables = &target.tables;
    let offs = sh.offs;
    let r = target.radius;
    let r2 = r * r;
    let nb = sh.n_alpha;
    let mut delta = vec![0.0; offs[offs.len() - 1]];
    let m = tile.members.len();
    if m == 0 || tile.proposals == 0 {
        return (Vec::new(), delta);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(tile.seed);
    let elo = tile.lo - DVec2::splat(r);
    let ehi = tile.hi + DVec2::splat(r);
    let in_tile =
        |p: DVec2| p.x >= tile.lo.x && p.x < tile.hi.x && p.y >= tile.lo.y && p.y < tile.hi.y;
    let in_halo = |p: DVec2| p.x >= elo.x && p.x <= ehi.x && p.y >= elo.y && p.y <= ehi.y;
    // local copy: the tile's instances (ids 0..m, moving), the own instances around it (ids from m on) and the
    // fixed content around it (static)
    let mut pos: Vec<DVec2> = tile.members.iter().map(|&g| sh.own[g as usize]).collect();
    let og = sh.own_grid;
    og.for_each_in_box_cells(elo, ehi, |i| {
        let p = DVec2::new(og.xs[i], og.ys[i]);
        if in_halo(p) && !in_tile(p) {
            pos.push(p);
        }
    });
    // 1/α per local own point: a row of `pool` (row 0: zeros, for the fixed content; row 1: ones, interior)
    let mut pool: Vec<f64> = vec![0.0; nb];
    pool.extend(std::iter::repeat_n(1.0, nb));
    let mut slot = vec![1u32; pos.len()];
    let mut scratch = vec![1.0; nb];
    for (id, p) in pos.iter().enumerate() {
        if inverse_alphas(sh.region, *p, target.bin_width, nb, &mut scratch) {
            slot[id] = (pool.len() / nb) as u32;
            pool.extend_from_slice(&scratch);
        }
    }
    // the static content, with its weight row as id
    let mut statics: Vec<GridEntry> = pos[m..]
        .iter()
        .enumerate()
        .map(|(j, p)| GridEntry {
            position: *p,
            tag: sh.self_tag,
            id: slot[m + j],
        })
        .collect();
    let fg = sh.fixed;
    fg.for_each_in_box_cells(elo, ehi, |i| {
        let p = DVec2::new(fg.xs[i], fg.ys[i]);
        if in_halo(p) {
            statics.push(GridEntry {
                position: p,
                tag: fg.tags[i],
                id: 0,
            });
        }
    });
    let grid = FlatGrid::build(elo, ehi, 0.5 * target.cell, statics.len(), |i| statics[i]);
    drop(statics);
    let lnx = grid.nx();
    let cell_index = |p: DVec2| {
        let (cx, cy) = grid.cell_coords(p);
        cy * lnx + cx
    };
    let mut cells = MemberCells::new(grid.n_cells(), m);
    for (k, p) in pos[..m].iter().enumerate() {
        cells.insert(k, cell_index(*p));
    }
    let (rlo, rhi) = sh.region.bbox();
    let (slo, shi) = (tile.lo.max(rlo), tile.hi.min(rhi));
    let mut d_h: Vec<f64> = delta.clone();
    // every histogram index is listed at most once per move
    let mut touched: Vec<u32> = vec![0; d_h.len() + 1];
    let mut ia_new = vec![1.0; nb];
    let mut cand: Vec<(u32, u32, DVec2, f64)> = Vec::new();
    let inv_share = 1.0 / tile.share;
    for _ in 0..tile.proposals {
        let k = rng.random_range(0..m);
        let p = pos[k];
        let q = if rng.random::<f64>() < 0.5 {
            // relocation inside the tile (the death of p and the birth of q), symmetric
            DVec2::new(
                slo.x + rng.random::<f64>() * (shi.x - slo.x),
                slo.y + rng.random::<f64>() * (shi.y - slo.y),
            )
        } else {
            p + gaussian(&mut rng) * sh.shift_sigma
        };
        if !in_tile(q) || !sh.region.contains(q) {
            continue;
        }
        let map_new = target.map_log(q);
        if map_new == f64::NEG_INFINITY {
            continue;
        }
        let q_border = inverse_alphas(sh.region, q, target.bin_width, nb, &mut ia_new);
        // pairs at q (added) and at p (removed)
        let mut forbidden = false;
        let mut ctx_new = 0.0;
        let mut ctx_old = 0.0;
        let mut nt = 0usize;
        for (sign, at) in [(1.0, q), (-1.0, p)] {
            let ia_x: &[f64] = if sign > 0.0 && q_border {
                &ia_new
            } else {
                let row = if sign > 0.0 { 1 } else { slot[k] as usize };
                &pool[row * nb..(row + 1) * nb]
            };
            // the neighbours within r (tag, weight row, offset, d²), gathered without branching on the distance
            let mut n = 0usize;
            let (x0, y0) = grid.cell_coords(at - DVec2::splat(r));
            let (x1, y1) = grid.cell_coords(at + DVec2::splat(r));
            for cy in y0..=y1 {
                let (a, b) = grid.row_range(cy, x0, x1);
                if cand.len() < n + (b - a) {
                    cand.resize(n + (b - a), (0, 0, DVec2::ZERO, 0.0));
                }
                for i in a..b {
                    let v = DVec2::new(grid.xs[i] - at.x, grid.ys[i] - at.y);
                    let d2 = v.x * v.x + v.y * v.y;
                    cand[n] = (grid.tags[i], grid.ids[i], v, d2);
                    n += usize::from(d2 <= r2);
                }
                for c in cy * lnx + x0..=cy * lnx + x1 {
                    let mut j = cells.head[c];
                    while j != NONE {
                        if cand.len() <= n {
                            cand.resize(n + 64, (0, 0, DVec2::ZERO, 0.0));
                        }
                        let v = pos[j as usize] - at;
                        let d2 = v.length_squared();
                        cand[n] = (sh.self_tag, slot[j as usize], v, d2);
                        n += usize::from(d2 <= r2 && j != k as u32);
                        j = cells.next[j as usize];
                    }
                }
            }
            let mut ctx = 0.0;
            for &(tag, row, v, d2) in &cand[..n] {
                let ti = (tag & !CONTEXT_TAG) as usize;
                let t = &tables[ti];
                let kd = ((d2.sqrt() / t.bin_width) as usize).min(sh.last_bin[ti]);
                let idx = if t.angle_bins == 1 {
                    kd
                } else {
                    kd * t.angle_bins + folded_angle_bin(v, t.angle_bins)
                };
                let h = offs[ti] + idx;
                let lf = if d2 < t.hard_core2 {
                    f64::NEG_INFINITY
                } else {
                    sh.log_factor[h]
                };
                if sign > 0.0 && lf == f64::NEG_INFINITY {
                    forbidden = true;
                    break;
                }
                if tag & CONTEXT_TAG != 0 {
                    ctx += lf;
                    continue;
                }
                let kd = kd.min(nb - 1);
                let w = ia_x[kd] + pool[row as usize * nb + kd];
                let cell = &mut d_h[h];
                touched[nt] = h as u32;
                nt += usize::from(*cell == 0.0);
                *cell += sign * w;
                if *cell == 0.0 {
                    // keep it listed once: a tiny non-zero marks it as touched
                    *cell = f64::MIN_POSITIVE;
                }
            }
            if forbidden {
                break;
            }
            if sign > 0.0 {
                ctx_new = ctx;
            } else {
                ctx_old = ctx;
            }
        }
        if !forbidden {
            // the map histograms: one instance leaves p's bins for q's
            for mi in 0..target.maps.len() {
                for (sign, at) in [(1.0, q), (-1.0, p)] {
                    if let Some(b) = map_bin(target, mi, at) {
                        let h = offs[tables.len() + mi] + b;
                        let cell = &mut d_h[h];
                        touched[nt] = h as u32;
                        nt += usize::from(*cell == 0.0);
                        *cell += sign;
                        if *cell == 0.0 {
                            *cell = f64::MIN_POSITIVE;
                        }
                    }
                }
            }
        }
        if forbidden {
            for &h in &touched[..nt] {
                d_h[h as usize] = 0.0;
            }
            continue;
        }
        let mut d_e = 0.0;
        for &h in &touched[..nt] {
            let h = h as usize;
            let dh = d_h[h];
            let view = sh.dev[h] + delta[h] * inv_share;
            d_e += sh.weight[h] * (2.0 * view * dh + dh * dh * inv_share);
        }
        let log_accept = -d_e / sh.tau
            + (map_new - target.map_log(p))
            + (target.ghost_log(q) - target.ghost_log(p))
            + (ctx_new.min(target.saturation) - ctx_old.min(target.saturation));
        let accept = rng.random::<f64>().ln() < log_accept;
        for &h in &touched[..nt] {
            let h = h as usize;
            if accept {
                delta[h] += d_h[h];
            }
            d_h[h] = 0.0;
        }
        if accept {
            cells.remove(k);
            cells.insert(k, cell_index(q));
            pos[k] = q;
            if q_border {
                if slot[k] <= 1 {
                    slot[k] = (pool.len() / nb) as u32;
                    pool.extend_from_slice(&ia_new);
                } else {
                    let s0 = slot[k] as usize * nb;
                    pool[s0..s0 + nb].copy_from_slice(&ia_new);
                }
            } else {
                slot[k] = 1;
            }
        }
    }
    pos.truncate(m);
    (pos, delta)
}

/// Whether a point at `p` is allowed at all (map preference non-zero, no hard core violated with the fixed
/// content or with `own_grid`'s points).
fn allowed(target: &Target, own_grid: &SpatialGrid, self_tag: u32, p: DVec2) -> bool {
    if target.map_log(p) == f64::NEG_INFINITY {
        return false;
    }
    let mut ok = true;
    let mut check = |e: &GridEntry, d2: f64| {
        if ok
            && target.tables[(e.tag & !CONTEXT_TAG) as usize].log_factor(e.position - p, d2)
                == f64::NEG_INFINITY
        {
            ok = false;
        }
    };
    target.grid.for_each_within(p, target.radius, &mut check);
    let t = &target.tables[self_tag as usize];
    own_grid.for_each_within(p, target.radius, |e, d2| {
        if ok && t.log_factor(e.position - p, d2) == f64::NEG_INFINITY {
            ok = false;
        }
    });
    ok
}

/// The rdf-matching chain (see "Larger regions: matching the rdf" in the module documentation).
#[allow(clippy::too_many_arguments)]
pub(super) fn run_rdf_chain<R: Rng>(
    target: &Target,
    region: &Region,
    area: f64,
    expected: f64,
    self_tag: u32,
    max_radius: f64,
    iterations_per_instance: f64,
    rng: &mut R,
    progress: &dyn Fn(f64) -> bool,
) -> Result<Vec<DVec2>> {
    use rayon::prelude::*;
    let r = target.radius;
    let (rlo, rhi) = region.bbox();
    let pad = DVec2::splat(r);
    let new_own_grid = |own: &[DVec2]| {
        let mut g = SpatialGrid::new(rlo - pad, rhi + pad, target.cell);
        for (id, p) in own.iter().enumerate() {
            g.insert(GridEntry {
                position: *p,
                tag: self_tag,
                id: id as u32,
            });
        }
        g
    };
    // the count (see "The count"), then dart throwing among allowed positions
    let want = expected.floor() as usize + usize::from(rng.random::<f64>() < expected.fract());
    let mut own: Vec<DVec2> = Vec::with_capacity(want);
    let mut own_grid = new_own_grid(&own);
    for _ in 0..(30 * want + 1000) {
        if own.len() >= want {
            break;
        }
        let Some(p) = region.sample_uniform(rng) else {
            break;
        };
        if allowed(target, &own_grid, self_tag, p) {
            own_grid.insert(GridEntry {
                position: p,
                tag: self_tag,
                id: own.len() as u32,
            });
            own.push(p);
        }
    }
    let n = own.len() as f64;
    if own.len() < 2 {
        return Ok(own);
    }
    // targets T = h · cell area · n_X · n_Y / A (ordered pairs), weights 1 / max(T, 1) (0 in the padding), flat
    let offs = histogram_offsets(target);
    let mut targets: Vec<f64> = vec![0.0; offs[offs.len() - 1]];
    let mut weight: Vec<f64> = vec![0.0; targets.len()];
    let mut log_factor: Vec<f64> = vec![0.0; offs[target.tables.len()]];
    let mut last_bin: Vec<usize> = Vec::new();
    for (ti, t) in target.tables.iter().enumerate() {
        let n_other = if ti as u32 == self_tag {
            n - 1.0
        } else {
            t.others_inside.unwrap_or(0) as f64
        };
        for (idx, h) in t.target_hist.iter().enumerate() {
            let v = h * t.cell_area(idx) * n * n_other / area;
            targets[offs[ti] + idx] = v;
            weight[offs[ti] + idx] = 1.0 / v.max(1.0);
            log_factor[offs[ti] + idx] = t.log_factor[idx];
        }
        last_bin.push(padded_bins(t, r) - 1);
    }
    for (mi, m) in target.maps.iter().enumerate() {
        let o = offs[target.tables.len() + mi];
        for (b, w) in m.wanted.iter().enumerate() {
            targets[o + b] = w * n;
            weight[o + b] = 1.0 / (w * n).max(1.0);
        }
    }
    let fixed_entries: Vec<GridEntry> = target.grid.entries().copied().collect();
    let fixed = FlatGrid::build(
        rlo - pad,
        rhi + pad,
        target.cell,
        fixed_entries.len(),
        |i| fixed_entries[i],
    );
    drop(fixed_entries);
    let new_own_flat = |own: &[DVec2]| {
        FlatGrid::build(rlo - pad, rhi + pad, target.cell, own.len(), |i| {
            GridEntry {
                position: own[i],
                tag: self_tag,
                id: i as u32,
            }
        })
    };
    let mut own_flat = new_own_flat(&own);
    drop(own_grid);
    let n_alpha = ((r / target.bin_width).ceil() as usize).max(1);
    let tile_size = (2.0 * r)
        .max((MIN_TILE_INSTANCES / (n / area)).sqrt())
        .max(1e-6);
    let ext = rhi - rlo;
    let tiled = ext.x >= 3.0 * tile_size && ext.y >= 3.0 * tile_size;
    let base_seed: u64 = rng.random();
    let shift_sigma = max_radius / 8.0;
    let mut dev: Vec<f64> = Vec::new();
    for sweep in 0..RDF_SWEEPS {
        let tau = annealed(TAU_START, TAU_END, sweep, RDF_SWEEPS, ANNEALING_FRACTION);
        let sweep_seed = mix_seed(base_seed, sweep as u64);
        let mut sweep_rng = ChaCha8Rng::seed_from_u64(sweep_seed);
        // the tiling of this sweep: a random offset, 2 × 2 colour phases
        let (origin, size, nx, ny) = if tiled {
            let off = DVec2::new(sweep_rng.random::<f64>(), sweep_rng.random::<f64>()) * tile_size;
            let origin = rlo - off;
            let nx = ((rhi.x - origin.x) / tile_size).floor() as usize + 1;
            let ny = ((rhi.y - origin.y) / tile_size).floor() as usize + 1;
            (origin, DVec2::splat(tile_size), nx, ny)
        } else {
            (rlo, ext * (1.0 + 1e-9) + DVec2::splat(1e-9), 1, 1)
        };
        let tile_of = |p: DVec2| {
            let ix = (((p.x - origin.x) / size.x).floor().max(0.0) as usize).min(nx - 1);
            let iy = (((p.y - origin.y) / size.y).floor().max(0.0) as usize).min(ny - 1);
            iy * nx + ix
        };
        // H − T: computed in full once, then carried over by the tiles' changes (see "Tiles and determinism")
        if sweep == 0 {
            dev = pair_histograms(&Shared {
                target,
                region,
                self_tag,
                n_alpha,
                own: &own,
                own_grid: &own_flat,
                fixed: &fixed,
                offs: &offs,
                last_bin: &last_bin,
                log_factor: &log_factor,
                dev: &[],
                weight: &weight,
                tau,
                shift_sigma,
            });
            for (x, y) in dev.iter_mut().zip(&targets) {
                *x -= y;
            }
        }
        let phases = if tiled { 4 } else { 1 };
        for phase in 0..phases {
            let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); nx * ny];
            for (id, p) in own.iter().enumerate() {
                buckets[tile_of(*p)].push(id as u32);
            }
            let active: Vec<usize> = (0..nx * ny)
                .filter(|&t| !tiled || ((t % nx) % 2) + 2 * ((t / nx) % 2) == phase)
                .collect();
            let phase_total: usize = active.iter().map(|&t| buckets[t].len()).sum();
            if phase_total == 0 {
                continue;
            }
            let tiles: Vec<Tile> = active
                .iter()
                .map(|&t| {
                    let lo = origin + DVec2::new((t % nx) as f64, (t / nx) as f64) * size;
                    let members = std::mem::take(&mut buckets[t]);
                    let count = members.len();
                    Tile {
                        lo,
                        hi: lo + size,
                        share: count as f64 / phase_total as f64,
                        proposals: (count as f64 * iterations_per_instance / RDF_SWEEPS as f64)
                            .ceil() as usize,
                        members,
                        seed: mix_seed(sweep_seed, (phase * nx * ny + t) as u64 + 1),
                    }
                })
                .collect();
            let shared = Shared {
                target,
                region,
                self_tag,
                n_alpha,
                own: &own,
                own_grid: &own_flat,
                fixed: &fixed,
                offs: &offs,
                last_bin: &last_bin,
                log_factor: &log_factor,
                dev: &dev,
                weight: &weight,
                tau,
                shift_sigma,
            };
            let results: Vec<(Vec<DVec2>, Vec<f64>)> =
                tiles.par_iter().map(|t| run_tile(&shared, t)).collect();
            for (tile, (positions, delta)) in tiles.iter().zip(results) {
                for (&g, p) in tile.members.iter().zip(positions) {
                    own[g as usize] = p;
                }
                for (a, b) in dev.iter_mut().zip(delta) {
                    *a += b;
                }
            }
            own_flat = new_own_flat(&own);
        }
        if !progress((sweep + 1) as f64 / RDF_SWEEPS as f64) {
            return Err(Error::Cancelled);
        }
    }
    Ok(own)
}

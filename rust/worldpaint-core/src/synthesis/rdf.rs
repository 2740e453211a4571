//! The rdf-matching chain for larger counts (see "Larger regions: matching the rdf" in the module documentation
//! of [`super`]): an annealed chi-square energy between the window-corrected pair histograms and the learned
//! ones, evaluated on tiles in parallel.

use super::births::{birth_in, BirthIntensity, Clusters};
use super::target::{PairTable, Target, CONTEXT_TAG};
use super::{annealed, mix_seed};
use crate::error::{Error, Result};
use crate::geom::{DVec2, PreparedRegion, RegionQueries};
use crate::spatial::{FlatGrid, GridEntry, GrowingPoints};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tile::{run_tile, Tile};
use tiling::{SweepTiles, Tiling};

mod tile;
mod tiling;

/// Sweeps of the rdf-matching chain (tiles are redrawn and the temperature lowered between sweeps).
const RDF_SWEEPS: usize = 12;
/// Darts thrown between two progress reports (a cancel is heard within some milliseconds).
const DARTS_PER_PROGRESS: usize = 1 << 16;
/// Darts thrown at once (see [`RdfChain::dart_batches`]).
const DARTS_PER_BATCH: usize = 4096;
/// Temperature of the first and of the last sweeps (in units of the chi-square energy, see the module docs).
const TAU_START: f64 = 1.0;
const TAU_END: f64 = 0.02;
/// Fraction of the sweeps over which the temperature decreases (it is then held at `TAU_END`).
const ANNEALING_FRACTION: f64 = 0.75;
/// The chain stops before a phase of a sweep once its histograms' χ² per bin is at most this (see [`converged`]).
const CONVERGED_CHI2_PER_BIN: f64 = 0.25;
/// A chain is held by targets it cannot reach once a sweep lowers its χ² by less than this share while it stays
/// above `STALLED_CHI2_PER_BIN` per bin (see "When to stop" in the module documentation of [`super`]).
const STALLED_GAIN: f64 = 0.1;
const STALLED_CHI2_PER_BIN: f64 = 1.0;
/// ... once its temperature is at most this (from the sixth of the twelve sweeps on): a hot chain may gain little
/// because it is hot.
const STALLED_TAU: f64 = 0.1;
/// Tiles hold at least this many expected instances (and are at least twice the interaction radius wide).
const MIN_TILE_INSTANCES: f64 = 256.0;

/// `1 / α` per distance bin at `p`, as many bins as `out` holds, written into `out`; returns false (and leaves
/// `out` alone) when the whole disc of the interaction radius lies inside the region (α = 1).
fn inverse_alphas(region: &PreparedRegion, p: DVec2, bin_width: f64, out: &mut [f64]) -> bool {
    if !crate::analysis::alphas_into(region, p, bin_width, out) {
        return false;
    }
    for o in out.iter_mut() {
        *o = 1.0 / *o;
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
    region: &'a PreparedRegion<'a>,
    self_tag: u32,
    n_alpha: usize,
    own: &'a [DVec2],
    /// The sweep's tiles and their members: a tile's halo holds own points of its eight neighbours only.
    tiles: &'a SweepTiles,
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
    /// Per histogram index: the target `T` over the whole region.
    targets: &'a [f64],
    /// Whether each tile matches its own pairs (see "Tiles match their own pairs"), or all of them the region's.
    own_pairs: bool,
    /// The χ² within the noise of the targets (see [`Matched::chi2_bound`]): a tile that matches its own pairs
    /// stops once its chi-square, as the region's would read, is at most this (see "When to stop").
    chi2_bound: f64,
    tau: f64,
    shift_sigma: f64,
    /// Where relocations are born (uniformly in the tile without it).
    births: Option<&'a BirthIntensity>,
}

/// Pair histograms `H` (flat, see `histogram_offsets`) of the own points with the own points and with the fixed
/// content inside the region: `H(k) = Σ_i Σ_j [d(x_i, y_j) in cell k] / α_{x_i}(k)` — eq. (2) before
/// normalization. `own_grid` holds the own points (ids: indices into `own`).
fn pair_histograms(sh: &Shared, own_grid: &FlatGrid) -> Vec<f64> {
    use rayon::prelude::*;
    let tables = &sh.target.tables;
    let offs = sh.offs;
    let n_hist = offs[offs.len() - 1];
    let r = sh.target.radius;
    // in the grid's order, cell by cell: neighbouring points read the same cells
    let chunks: Vec<Vec<f64>> = (0..sh.own.len().div_ceil(1024))
        .into_par_iter()
        .map(|c| {
            let mut h = vec![0.0; n_hist];
            let mut ia = vec![1.0; sh.n_alpha];
            for i in c * 1024..((c + 1) * 1024).min(sh.own.len()) {
                let (p, id) = (DVec2::new(own_grid.xs[i], own_grid.ys[i]), own_grid.ids[i]);
                if !inverse_alphas(sh.region, p, sh.target.bin_width, &mut ia) {
                    ia.fill(1.0);
                }
                for g in [own_grid, sh.fixed] {
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

/// Whether a point at `p` is allowed at all (map preference non-zero, no hard core violated with the fixed
/// content or with the points of `own`); `reach` holds how far a pair may be forbidden, with the fixed content and
/// with the own points ([`PairTable::forbidden_reach`]), so that a dart looks no farther.
fn allowed(
    target: &Target,
    own: &GrowingPoints,
    self_tag: u32,
    reach: (f64, f64),
    p: DVec2,
) -> bool {
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
    target.grid.for_each_within(p, reach.0, &mut check);
    if !ok {
        return false;
    }
    let t = &target.tables[self_tag as usize];
    !own.any_within(p, reach.1, |v, d2| t.log_factor(v, d2) == f64::NEG_INFINITY)
}

/// The rdf-matching chain of one category (see "Larger regions: matching the rdf" in the module documentation).
pub(super) struct RdfChain<'c, 'a> {
    pub(super) target: &'c Target<'a>,
    pub(super) region: &'c PreparedRegion<'c>,
    pub(super) area: f64,
    /// The expected count (see "The count").
    pub(super) expected: f64,
    pub(super) self_tag: u32,
    /// The factor of the self pair's target counts: the concentration the example's maps gave its pairs over the
    /// one the painted region's maps give them (see "Maps" in the module documentation of [`super`]).
    pub(super) self_pair_scale: f64,
    pub(super) iterations_per_instance: f64,
    /// The category's instances in the example, whose counting noise the targets carry (see [`converged`]).
    pub(super) exemplar_count: f64,
    /// The map-weighted intensity births are drawn from (None: uniformly), see [`super::births`].
    pub(super) births: Option<&'c BirthIntensity>,
    /// Whether one tile over the region reads the stopping rule four times a sweep (the dense points of polygons,
    /// see "When to stop" in the module documentation of [`super`]).
    pub(super) quartered: bool,
}

/// The matched histograms, flat (see `histogram_offsets`): their targets `T = h · cell area · n_X · n_Y / A`
/// (ordered pairs) and `n w_m` (maps), the weights `1 / max(T, 1)` (0 in the padding), the pairs' log factors,
/// and per table its last padded distance bin.
struct Matched {
    offs: Vec<usize>,
    targets: Vec<f64>,
    weight: Vec<f64>,
    log_factor: Vec<f64>,
    last_bin: Vec<usize>,
}

/// Whether the matched histograms lie within the noise of their targets: Pearson's χ², the chain's energy
/// `Σ w (H − T)²` with `w = 1 / max(T, 1)`, at most [`CONVERGED_CHI2_PER_BIN`] per bin that has a target, times
/// `noise_scale`, the paste's size in examples (see "When to stop" in the module documentation of [`super`]):
/// at most `bound` ([`Matched::chi2_bound`]).
fn converged(dev: &[f64], matched: &Matched, bound: f64) -> bool {
    chi2(dev, &matched.weight) <= bound
}

/// The chi-square `Σ w d²` of the deviations `d` at the weights `w`.
fn chi2(dev: &[f64], weight: &[f64]) -> f64 {
    dev.iter().zip(weight).map(|(d, w)| w * d * d).sum()
}

impl Matched {
    /// `per_bin` times the bins that have a target, times `noise_scale` (negative without such a bin: nothing is
    /// within the noise of no target). At [`CONVERGED_CHI2_PER_BIN`], the largest χ² that lies within the noise of
    /// the targets.
    fn chi2_bound(&self, per_bin: f64, noise_scale: f64) -> f64 {
        let bins = self.targets.iter().filter(|t| **t > 0.0).count();
        if bins == 0 {
            return -1.0;
        }
        per_bin * noise_scale * bins as f64
    }
}

/// What every sweep of the chain shares: the matched histograms and the fixed content in a flat grid.
struct Sweeps<'c, 'a> {
    chain: &'c RdfChain<'c, 'a>,
    matched: Matched,
    fixed: FlatGrid,
    n_alpha: usize,
    shift_sigma: f64,
    /// Whether the tiles match their own pairs (see "Tiles match their own pairs").
    own_pairs: bool,
    /// The stopping bound (see [`Matched::chi2_bound`]), read once for the chain.
    chi2_bound: f64,
    /// The χ² above which a chain that gains less than `STALLED_GAIN` a sweep stops.
    stalled_above: f64,
}

impl<'a> RdfChain<'_, 'a> {
    /// Runs the chain: the count, dart throwing, then the annealed sweeps over tiles.
    pub(super) fn run<R: Rng>(
        &self,
        rng: &mut R,
        progress: &dyn Fn(f64) -> bool,
    ) -> Result<Vec<DVec2>> {
        self.run_carried(rng, progress).map(|ran| ran.points)
    }

    /// [`Self::run`], with the `H − T` the chain carried to its end (empty when it made no moves).
    fn run_carried<R: Rng>(&self, rng: &mut R, progress: &dyn Fn(f64) -> bool) -> Result<Ran> {
        let mut own = self.dart_throwing(rng, progress)?;
        let n = own.len() as f64;
        if own.len() < 2 || self.target.matches_nothing() {
            return Ok(Ran {
                points: own,
                dev: Vec::new(),
            });
        }
        let (tile_size, tiled) = self.tile_size(n);
        let sweeps = self.sweeps(n, tiled);
        let base_seed: u64 = rng.random();
        let mut dev: Vec<f64> = Vec::new();
        let mut last_chi2 = f64::INFINITY;
        for sweep in 0..RDF_SWEEPS {
            let tau = annealed(TAU_START, TAU_END, sweep, RDF_SWEEPS, ANNEALING_FRACTION);
            let sweep_seed = mix_seed(base_seed, sweep as u64);
            let mut sweep_rng = ChaCha8Rng::seed_from_u64(sweep_seed);
            let tiling = Tiling::draw(
                tiled,
                self.quartered,
                tile_size,
                self.region.bbox(),
                &mut sweep_rng,
            );
            // an instance stays in its tile over the sweep: the instances are sorted into tiles once for its phases
            let tiles = tiling.tiles(&own, sweep_seed, self.iterations_per_instance);
            // H − T: computed in full once, then carried over by the tiles' changes (see "Tiles and determinism")
            if sweep == 0 {
                dev = sweeps.deviation(&own, &tiles);
            }
            let now = chi2(&dev, &sweeps.matched.weight);
            if tau <= STALLED_TAU
                && now > sweeps.stalled_above
                && last_chi2 - now < STALLED_GAIN * last_chi2
            {
                return Ok(Ran { points: own, dev });
            }
            last_chi2 = now;
            let phases = tiling.phases();
            for phase in 0..phases {
                // before each phase: a sweep's last phases are not run once the first have matched the targets
                if converged(&dev, &sweeps.matched, sweeps.chi2_bound) {
                    return Ok(Ran { points: own, dev });
                }
                if tiles.phase_total[phase] == 0 {
                    continue;
                }
                sweeps.run_phase(&tiles, phase, &mut own, &mut dev, tau);
                // each phase, so that a cancel is heard within a phase's time, not a sweep's
                if !progress(
                    (sweep as f64 + (phase + 1) as f64 / phases as f64) / RDF_SWEEPS as f64,
                ) {
                    return Err(Error::Cancelled);
                }
            }
        }
        Ok(Ran { points: own, dev })
    }

    /// What every sweep of a chain of `n` own instances shares (`tiled`: whether the region is cut into tiles).
    fn sweeps(&self, n: f64, tiled: bool) -> Sweeps<'_, 'a> {
        let target = self.target;
        let noise_scale = if self.exemplar_count > 0.0 {
            (n / self.exemplar_count).max(1.0)
        } else {
            1.0
        };
        let matched = self.matched_histograms(n);
        Sweeps {
            chain: self,
            chi2_bound: matched.chi2_bound(CONVERGED_CHI2_PER_BIN, noise_scale),
            stalled_above: matched.chi2_bound(STALLED_CHI2_PER_BIN, noise_scale),
            matched,
            fixed: self.flat_grid(&target.grid.entries().copied().collect::<Vec<_>>()),
            n_alpha: ((target.radius / target.bin_width).ceil() as usize).max(1),
            shift_sigma: 3.0 * target.bin_width,
            own_pairs: self.own_pairs(tiled),
        }
    }

    /// The side of the chain's tiles at `n` own instances, and whether the region is cut into tiles (see "Tiles
    /// and determinism").
    fn tile_size(&self, n: f64) -> (f64, bool) {
        let (rlo, rhi) = self.region.bbox();
        let size = (2.0 * self.target.radius)
            .max((MIN_TILE_INSTANCES / (n / self.area)).sqrt())
            .max(1e-6);
        let ext = rhi - rlo;
        (size, ext.x >= 3.0 * size && ext.y >= 3.0 * size)
    }

    /// Whether the tiles of a tiled region match their own pairs: where no map shapes the density (see "Tiles match
    /// their own pairs").
    fn own_pairs(&self, tiled: bool) -> bool {
        tiled && self.target.maps.is_empty()
    }

    /// The count (see "The count"), then dart throwing among allowed positions: uniformly without maps; with
    /// them drawn from the map-weighted intensity. A clustered color that follows maps, or whose tiles match
    /// their own pairs (see "Tiles match their own pairs"), throws only the first instance of each cluster so,
    /// the others around them (see "Clusters" in [`super::births`]); a small paste without maps builds its
    /// clusters in the chain, against the content around it (clusters thrown blind to it would be cut at its
    /// border).
    fn dart_throwing<R: Rng>(
        &self,
        rng: &mut R,
        progress: &dyn Fn(f64) -> bool,
    ) -> Result<Vec<DVec2>> {
        let (target, self_tag) = (self.target, self.self_tag);
        let want = self.expected.floor() as usize
            + usize::from(rng.random::<f64>() < self.expected.fract());
        let table = &target.tables[self_tag as usize];
        let own_pairs = self.own_pairs(self.tile_size(want as f64).1);
        let clusters = (self.births.is_some() || own_pairs)
            .then(|| {
                Clusters::of_rdf(
                    &table.target_hist,
                    table.angle_bins,
                    table.bin_width,
                    want as f64 / self.area,
                    target.radius,
                )
            })
            .flatten();
        let darts = 30 * want + 1000;
        // darts grown around the first instances of the clusters, while half the darts remain
        let grown = clusters.map(|c| {
            (
                c,
                ((want as f64 * c.seed_share()).ceil() as usize).max(1),
                darts / 2,
            )
        });
        let reach = (
            target
                .tables
                .iter()
                .map(PairTable::forbidden_reach)
                .fold(0.0, f64::max)
                .min(target.radius),
            table.forbidden_reach().min(target.radius),
        );
        self.dart_batches(rng, progress, (want, darts), reach, grown)
    }

    /// Dart throwing in batches with the result of one dart at a time: a batch's darts are drawn in turn, checked
    /// against the instances before the batch in parallel, then kept in turn unless an instance kept earlier in
    /// the batch forbids them. A batch holds no more darts than instances are still wanted, and none past the
    /// first instances of the clusters (`grown`: the clusters, how many first instances, until which dart darts
    /// are grown around them), so that every dart is drawn as the one-at-a-time throwing would have drawn it.
    fn dart_batches<R: Rng>(
        &self,
        rng: &mut R,
        progress: &dyn Fn(f64) -> bool,
        (want, darts): (usize, usize),
        reach: (f64, f64),
        grown: Option<(Clusters, usize, usize)>,
    ) -> Result<Vec<DVec2>> {
        use rayon::prelude::*;
        let (target, self_tag) = (self.target, self.self_tag);
        let (lo, hi) = self.grid_bounds();
        let mut own = GrowingPoints::new(lo, hi, target.cell, want);
        let (rlo, rhi) = self.region.bbox();
        let births = self.births.map(|b| b.over(rlo, rhi));
        let births = births.as_ref();
        let own_table = &target.tables[self_tag as usize];
        let mut thrown = 0;
        let mut batch = Vec::with_capacity(DARTS_PER_BATCH);
        while thrown < darts && own.points().len() < want {
            if thrown % DARTS_PER_PROGRESS + DARTS_PER_BATCH > DARTS_PER_PROGRESS && !progress(0.0)
            {
                return Err(Error::Cancelled);
            }
            let count = own.points().len();
            let mut size = DARTS_PER_BATCH.min(want - count).min(darts - thrown);
            // around the first instances of the clusters once they are all thrown, uniformly before and after
            let around = match grown {
                Some((c, seeds, until)) if count >= seeds && thrown < until => {
                    size = size.min(until - thrown);
                    Some((c, seeds))
                }
                Some((_, seeds, _)) if count < seeds => {
                    size = size.min(seeds - count);
                    None
                }
                _ => None,
            };
            batch.clear();
            let mut exhausted = false;
            for _ in 0..size {
                thrown += 1;
                match around {
                    Some((c, seeds)) => {
                        let p = own.points()[rng.random_range(0..seeds)] + c.offset_from_seed(rng);
                        if self.region.contains(p) {
                            batch.push(p);
                        }
                    }
                    None => match birth_in(self.region, births, rng) {
                        Some(p) => batch.push(p),
                        None => {
                            exhausted = true;
                            break;
                        }
                    },
                }
            }
            let before: Vec<bool> = batch
                .par_iter()
                .with_min_len(256)
                .map(|&p| allowed(target, &own, self_tag, reach, p))
                .collect();
            let since = own.points().len();
            for (&p, ok) in batch.iter().zip(before) {
                if ok
                    && !own.any_within_since(p, reach.1, since, |v, d2| {
                        own_table.log_factor(v, d2) == f64::NEG_INFINITY
                    })
                {
                    own.push(p);
                }
            }
            if exhausted {
                break;
            }
        }
        Ok(own.into_points())
    }

    /// The targets and weights of the matched histograms at `n` own points (see [`Matched`]).
    fn matched_histograms(&self, n: f64) -> Matched {
        let target = self.target;
        let offs = histogram_offsets(target);
        let mut targets: Vec<f64> = vec![0.0; offs[offs.len() - 1]];
        let mut weight: Vec<f64> = vec![0.0; targets.len()];
        let mut log_factor: Vec<f64> = vec![0.0; offs[target.tables.len()]];
        let mut last_bin: Vec<usize> = Vec::new();
        for (ti, t) in target.tables.iter().enumerate() {
            let (n_other, scale) = if ti as u32 == self.self_tag {
                (n - 1.0, self.self_pair_scale)
            } else {
                (t.others_inside.unwrap_or(0) as f64, 1.0)
            };
            for (idx, h) in t.target_hist.iter().enumerate() {
                let v = h * t.cell_area(idx) * n * n_other / self.area * scale;
                targets[offs[ti] + idx] = v;
                weight[offs[ti] + idx] = 1.0 / v.max(1.0);
                log_factor[offs[ti] + idx] = t.log_factor[idx];
            }
            last_bin.push(padded_bins(t, target.radius) - 1);
        }
        for (mi, m) in target.maps.iter().enumerate() {
            let o = offs[target.tables.len() + mi];
            for (b, w) in m.wanted.iter().enumerate() {
                targets[o + b] = w * n;
                weight[o + b] = 1.0 / (w * n).max(1.0);
            }
        }
        Matched {
            offs,
            targets,
            weight,
            log_factor,
            last_bin,
        }
    }

    /// The extent of the chain's grids: the region's box grown by the interaction radius.
    fn grid_bounds(&self) -> (DVec2, DVec2) {
        let (rlo, rhi) = self.region.bbox();
        let pad = DVec2::splat(self.target.radius);
        (rlo - pad, rhi + pad)
    }

    fn flat_grid(&self, entries: &[GridEntry]) -> FlatGrid {
        let (lo, hi) = self.grid_bounds();
        FlatGrid::build(lo, hi, self.target.cell, entries.len(), |i| entries[i])
    }

    /// The own points in a flat grid, their indices as ids.
    fn own_flat(&self, own: &[DVec2]) -> FlatGrid {
        let (lo, hi) = self.grid_bounds();
        FlatGrid::build(lo, hi, self.target.cell, own.len(), |i| GridEntry {
            position: own[i],
            tag: self.self_tag,
            id: i as u32,
        })
    }
}

/// What a chain ends with (see [`RdfChain::run_carried`]): its points, and for the tests the `H − T` it carried.
struct Ran {
    points: Vec<DVec2>,
    #[cfg_attr(not(test), allow(dead_code))]
    dev: Vec<f64>,
}

impl<'a> Sweeps<'_, 'a> {
    /// `H − T` of the own instances `own` counted in full (`tiles`: the sweep's).
    fn deviation(&self, own: &[DVec2], tiles: &SweepTiles) -> Vec<f64> {
        let mut dev = pair_histograms(
            &self.shared(own, tiles, &[], 0.0),
            &self.chain.own_flat(own),
        );
        for (x, y) in dev.iter_mut().zip(&self.matched.targets) {
            *x -= y;
        }
        dev
    }

    /// The state the tiles of a phase read.
    fn shared<'s>(
        &'s self,
        own: &'s [DVec2],
        tiles: &'s SweepTiles,
        dev: &'s [f64],
        tau: f64,
    ) -> Shared<'s, 'a> {
        Shared {
            target: self.chain.target,
            region: self.chain.region,
            self_tag: self.chain.self_tag,
            n_alpha: self.n_alpha,
            own,
            tiles,
            fixed: &self.fixed,
            offs: &self.matched.offs,
            last_bin: &self.matched.last_bin,
            log_factor: &self.matched.log_factor,
            dev,
            weight: &self.matched.weight,
            targets: &self.matched.targets,
            own_pairs: self.own_pairs,
            chi2_bound: self.chi2_bound,
            tau,
            shift_sigma: self.shift_sigma,
            births: self.chain.births,
        }
    }

    /// The tiles of one phase in parallel, their moves and changes of `H` merged in tile order.
    fn run_phase(
        &self,
        tiles: &SweepTiles,
        phase: usize,
        own: &mut [DVec2],
        dev: &mut [f64],
        tau: f64,
    ) {
        use rayon::prelude::*;
        let active: Vec<&Tile> = tiles.tiles.iter().filter(|t| t.phase == phase).collect();
        let results: Vec<(Vec<DVec2>, Vec<f64>)> = {
            let shared = self.shared(own, tiles, dev, tau);
            active.par_iter().map(|t| run_tile(&shared, t)).collect()
        };
        for (tile, (positions, delta)) in active.iter().zip(results) {
            for (&g, p) in tile.members.iter().zip(positions) {
                own[g as usize] = p;
            }
            for (a, b) in dev.iter_mut().zip(delta) {
                *a += b;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{learn_color, AnalysisOptions};
    use crate::exemplar::{clustered_points, scene_from_points};
    use crate::geom::Region;
    use crate::scene::Scene;
    use crate::synthesis::painting::{Painted, Painting};
    use crate::synthesis::structures::StructuredContent;
    use crate::synthesis::{SynthesisOptions, SynthesisResult};

    fn square(lo: f64, side: f64) -> Region {
        Region::Rect {
            min: DVec2::splat(lo),
            max: DVec2::splat(lo + side),
        }
    }

    /// What a chain ended with, and what its points give counted in full.
    struct Recounted {
        ran: Ran,
        /// The share of its points the chain moved from where dart throwing put them.
        moved: f64,
        /// `H − T` of the points counted in full, its chi-square, and the chain's stopping bound.
        dev: Vec<f64>,
        chi2: f64,
        bound: f64,
        stalled_above: f64,
        tiled: bool,
        /// The last progress the chain reported (1 after its last sweep).
        progress: f64,
    }

    /// A clustered example's color pasted alone over a square of `side`, its chain's end recounted.
    fn pasted(side: f64, seed: u64) -> Recounted {
        pasted_at(side, seed, 1.0)
    }

    /// [`pasted`], the self pair's targets scaled by `pair_scale`.
    fn pasted_at(side: f64, seed: u64, pair_scale: f64) -> Recounted {
        let example = scene_from_points(
            "shrub",
            &clustered_points(&square(0.0, 100.0), 0.004, 8.0, 2.0, seed),
        );
        let color = match learn_color(
            &example,
            &square(0.0, 100.0),
            "shrubs",
            &AnalysisOptions::default(),
        ) {
            Ok(c) => c,
            Err(e) => panic!("learning: {e}"),
        };
        let region = square(1000.0, side);
        let prepared = PreparedRegion::new(&region);
        let opts = SynthesisOptions::default();
        let scene = Scene::default();
        let painting = Painting::new(&scene, &color, &prepared, &opts, color.max_radius, vec![0]);
        let state = Painted {
            synthesized: vec![None],
            context: vec![Vec::new()],
            structured: StructuredContent::default(),
            structure_values: Default::default(),
            out: SynthesisResult::default(),
        };
        let (target, self_tag) = painting.category_target(0, &state);
        let chain = RdfChain {
            target: &target,
            region: &prepared,
            area: region.area(),
            expected: color.categories[0].density * region.area(),
            self_tag,
            self_pair_scale: pair_scale,
            iterations_per_instance: opts.iterations_per_instance,
            exemplar_count: color.categories[0].count as f64,
            births: None,
            quartered: false,
        };
        let progress = std::sync::Mutex::new(0.0);
        let report = |f: f64| {
            if let Ok(mut p) = progress.lock() {
                *p = f;
            }
            true
        };
        let ran = match chain.run_carried(&mut ChaCha8Rng::seed_from_u64(seed), &report) {
            Ok(r) => r,
            Err(e) => panic!("the chain: {e}"),
        };
        let thrown = match chain.dart_throwing(&mut ChaCha8Rng::seed_from_u64(seed), &|_| true) {
            Ok(p) => p,
            Err(e) => panic!("dart throwing: {e}"),
        };
        let n = ran.points.len() as f64;
        let moved = thrown
            .iter()
            .zip(&ran.points)
            .filter(|(a, b)| a != b)
            .count() as f64
            / n;
        let tiled = chain.tile_size(n).1;
        let sweeps = chain.sweeps(n, tiled);
        let tiles = Tiling::draw(
            false,
            false,
            1.0,
            region.bbox(),
            &mut ChaCha8Rng::seed_from_u64(0),
        )
        .tiles(&ran.points, 0, 1.0);
        let dev = sweeps.deviation(&ran.points, &tiles);
        Recounted {
            chi2: chi2(&dev, &sweeps.matched.weight),
            bound: sweeps.chi2_bound,
            stalled_above: sweeps.stalled_above,
            ran,
            moved,
            dev,
            tiled,
            progress: progress.into_inner().unwrap_or(f64::NAN),
        }
    }

    /// A chain held by targets it cannot reach (the self pair's ten times what the count can give) stops once a
    /// sweep of the cold chain lowers its χ² by less than a tenth, instead of spending its budget; the same chain
    /// against the learned targets reaches them (see "When to stop").
    #[test]
    fn a_chain_held_by_unreachable_targets_stops_once_it_stalls() {
        let held = pasted_at(200.0, 4, 10.0);
        println!(
            "targets ×10: χ² {:.0} (stalled above {:.0}), progress {:.3}",
            held.chi2, held.stalled_above, held.progress
        );
        assert!(held.chi2 > held.stalled_above, "χ² {}", held.chi2);
        assert!(
            held.progress < 1.0,
            "the chain ran {:.2} of its sweeps",
            held.progress
        );
        let free = pasted(200.0, 4);
        assert!(free.chi2 <= free.bound * (1.0 + 1e-9), "χ² {}", free.chi2);
    }

    /// The histograms a chain carries from move to move are those of its points, and a chain that stopped on them
    /// is within the targets' noise by a full count: on one tile over the region, and on tiles that match their own
    /// pairs.
    #[test]
    fn carried_histograms_are_a_full_count_of_the_points() {
        for (side, want_tiled) in [(200.0, false), (600.0, true)] {
            let r = pasted(side, 3);
            assert_eq!(r.tiled, want_tiled, "a square of {side} m");
            println!(
                "{side} m: {} points, {:.0} % moved, χ² {:.2} (bound {})",
                r.ran.points.len(),
                100.0 * r.moved,
                r.chi2,
                r.bound
            );
            assert!(
                r.moved > 0.1,
                "{side} m: the chain moved {:.0} %",
                100.0 * r.moved
            );
            assert_eq!(r.ran.dev.len(), r.dev.len());
            let scale = r.dev.iter().fold(1.0f64, |m, x| m.max(x.abs()));
            for (h, (a, b)) in r.ran.dev.iter().zip(&r.dev).enumerate() {
                assert!(
                    (a - b).abs() <= 1e-9 * scale,
                    "{side} m, bin {h}: carried {a}, counted {b}"
                );
            }
            assert!(
                r.chi2 <= r.bound * (1.0 + 1e-9),
                "{side} m: χ² {} above the bound {}",
                r.chi2,
                r.bound
            );
        }
    }
}

//! Synthesis of a color in a region (Sections 4.1, 4.3, 5.1 and 6): Metropolis-Hastings birth-and-death
//! sampling, category by category in priority order, with a region of influence.
//!
//! ## The target density and eq. (1)
//! For the category `X` being synthesized, with `Y_k` the content of equal or higher priority (already
//! synthesized categories inside the region, and existing instances within the region of influence),
//!
//! ```text
//! f(X) ∝ β^{n_X} · Π_{x_i ∈ X} Π_m ψ_m(m(x_i)) · Π_{C_Yk ≤ C_X} Π_{x_i ∈ X} Π_{y_j ∈ Y_k} h_{X,Y_k}(d(x_i, y_j))
//! ```
//!
//! and the birth / death acceptance ratios of eq. (1) (Geyer & Møller 1994),
//! `R_b = f(X ∪ {p}) / f(X) · A / (n_X + 1)` and `R_d = f(X \ {x}) / f(X) · n_X / A`.
//! These are the Metropolis-Hastings ratios for a density `f` *relative to a unit-rate Poisson process*, with
//! births proposed uniformly in the region (density 1/A) and deaths uniformly among the points. Without
//! interactions `f(X) = β^{n}` is a Poisson process of intensity β, whose expected count is `β A`: the
//! intensity term β is what makes the density come out right, and the paper's `A / n_X` factor alone (β = 1)
//! would give one instance per m². (How β is handled here: see "The count".)
//!
//! The product simplification of Section 6 — `R_b = A/n_X · Π_{C_Yk ≤ C_X} Π_{y_j} h_{X,Y_k}(p, y_j)` — means
//! only factors involving the changed point are evaluated, through a uniform grid (`spatial`): a pair
//! contributes `h(d)` for `d < max_radius` and 1 beyond. Shift moves (a point displaced by a small Gaussian
//! step, symmetric proposal) use `f(X')/f(X)` alone and speed up mixing.
//!
//! ## The count (β)
//! Pair factors bias the count of a birth-death chain with β fixed at the exemplar density: `h > 1` at short
//! range (clusters) favours births, a hard core suppresses them, and with attraction an adaptive β lags behind
//! a runaway. We therefore integrate β out: the chain samples the process *conditioned on its count*
//! `n = target = λ_exemplar · ∫_φ ψ(m(x)) dx` (the exemplar density weighted by the map preference over the
//! painted region, rounded stochastically). At fixed `n` a death followed by a birth is one *relocation* move
//! (a point moved to a uniform position) with ratio `f(X')/f(X)`: the conditional of the chain of eq. (1),
//! whatever β. Relocations and small Gaussian shifts alternate; when a hard core leaves the dart-throwing start
//! short of `n`, allowed births fill the gap.
//!
//! ## Small counts: the product model of eq. (1)
//! When the painted region holds fewer than 100 expected instances of a category, the chain is the paper's:
//! relocations and shifts accepted with `f(X')/f(X)`, the exemplar's `h` used directly as pair factors, a
//! point's total log pair factor capped at `SATURATION_PAIRS` times the largest single-pair log factor (a
//! Geyer-style saturation that keeps attraction from condensing everything into one clump).
//!
//! ## Larger regions: matching the rdf (and the map histograms) directly
//! Used as pair factors, the exemplar's rdfs reproduce themselves only for weak interactions: with clusters
//! (`h ≫ 1` at short range) the product of many factors collapses clusters into clumps (the clustered
//! exemplar came out at 3.4× the second-draw rdf error). With enough points we therefore sample, in the spirit
//! of the rdf of Öztireli & Gross 2012 that the paper adopts, the tempered density
//!
//! ```text
//! f(X) ∝ exp(−E(X) / τ) · Π_{x_i} Π_m ψ_m(m(x_i)) · Π_{x_i} Π_{context y_j} h(d(x_i, y_j))
//! E(X) = Σ_pairs Σ_k (H(k) − T(k))² / max(T(k), 1)  +  Σ_maps Σ_b (M(b) − n w_m(b))² / max(n w_m(b), 1)
//! ```
//!
//! * `H(k) = Σ_{x_i} Σ_{y_j} [d(x_i, y_j) in cell k] / α_{x_i}(k)` is the window-corrected pair count of eq.
//!   (2) before normalization, for the self pair and for every higher-priority category already inside the
//!   region; `T(k) = h(k) · |cell k| · n_X n_Y / A` is what the learned rdf `h` gives at the current counts.
//!   Oriented rdfs use the same formula per (distance, angle) cell.
//! * `M(b)` counts the instances in bin `b` of each map; `w_m` is the distribution of the map over the region
//!   that the map factors give (see "Maps"), so the slope histogram is matched as well: at low τ the energy
//!   would otherwise override the weak factor ψ.
//! * Fixed content *outside* the region (the region of influence) keeps the product factors of eq. (1) (with
//!   the saturation): its pairs cannot be window-corrected against the region.
//! * Zeros stay hard: hard-core distances (with any neighbour, inside or outside) and map values where
//!   `h_m = 0` are rejected outright.
//!
//! The weights make `E` a chi-square in units of counting noise. A move changes `H` only through the pairs of
//! the moved point (O(neighbours + bins)); acceptance is `exp(−ΔE/τ)` times the ratio of the other factors,
//! with τ lowered geometrically from `TAU_START` to `TAU_END` over the first `ANNEALING_FRACTION` of the
//! `RDF_SWEEPS` sweeps (simulated annealing). This keeps eq. (1)'s Metropolis-Hastings chain, its birth/death
//! pairs as relocations at fixed count, its product simplification (only the moved point's factors are
//! evaluated) and its priority order; what changes is `f`: the learned histograms are the *targets* of the
//! statistics rather than the factors, which by Henderson's theorem is what reproducing them at a given density
//! requires. It holds for clusters, hard cores and cross-category pairs alike.
//!
//! **Interaction radius.** Each pair's rdf is cut after its last bin that differs from 1 by more than
//! `SIGNIFICANCE` standard deviations of the exemplar's counting noise (the larger of the Poisson noise of
//! the bin and the RMS deviation of the outer third of the bins, which measures clump noise), keeping hard-core
//! bins. Beyond it the learned rdf is noise around 1 and the factor is neutral; the moves' cost grows with the
//! radius squared.
//!
//! **Tiles and determinism.** The region is cut into square tiles at least twice the interaction radius wide
//! (and holding ≥ `MIN_TILE_INSTANCES` expected instances), with a random offset per sweep; tiles are processed
//! in four 2 × 2 colour phases, so tiles of a phase never share a neighbour, in parallel with rayon. Each
//! tile moves only its own instances, inside itself, with its own ChaCha8 generator seeded from (seed,
//! category, sweep, phase, tile). `E` is global: a tile sees the deviation `H − T` at the start of the phase
//! plus its own changes scaled by its share of the phase's instances (it is responsible for that share of the
//! correction). A tile's changes of `H` are exact (tiles of a phase are at least twice the radius apart, so no
//! pair joins two moving tiles): `H` is computed in full once, then carried by the tiles' changes. Results are
//! merged in tile order: the same seed gives the same result whatever the thread count. Small regions are one tile.
//!
//! ## Zeros of the histograms
//! * Distances below the first non-empty bin of a pair (and below the exemplar's smallest same-category
//!   distance) were never seen: a hard core, factor 0 (rejected outright), which is what keeps a pasted
//!   hard-core color from crowding its neighbours across the region's border.
//! * Empty bins further out are sampling noise of a finite exemplar: they get the floor `1e-3` (relative to
//!   the rdf's Poisson level 1), so log-probabilities stay finite and a chance gap does not forbid a distance,
//!   while one such pair still costs a factor 1000.
//!
//! ## Maps
//! For a map `m` the factor is `ψ(v) = h_m(v) / q(v)`, where `q` is the histogram of the map over the whole
//! exemplar region: the intensity then follows the exemplar's *preference* for values of `m` (a region with the
//! exemplar's own map distribution gets the exemplar density; the count is calibrated by the mean of `Π ψ`
//! over the exemplar region, when it lies on the terrain, since correlated maps such as elevation and slope do
//! not average to 1). With several maps the factors are raked over the painted region (`rake_maps`) so each
//! map's distribution is what its own factor gives. Values the exemplar region showed but where `h_m = 0` —
//! the exemplar never had an instance there — get factor 0: no instance lands there. Values the region never
//! showed (beyond its range, or a gap) take the factor of the nearest value it did show: the exemplar holds no
//! evidence about them, and a neutral reading keeps, say, a grove learned on flat ground pastable on hills.
//!
//! ## Determinism
//! Every random choice comes from ChaCha8 generators seeded from (seed, category) and, for tiles, (sweep,
//! phase, tile); parallel results are merged in a fixed order, so nothing depends on the rayon thread count.

use crate::analysis::{folded_angle_bin, region_lattice};
use crate::error::{Error, Result};
use crate::geom::{DVec2, Region};
use crate::palette::{CategoryColor, Color, Histogram, Interaction};
use crate::scene::{Category, Instance, Scene};
use crate::spatial::{FlatGrid, GridEntry, SpatialGrid};
use crate::terrain::Heightfield;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Floor of empty rdf bins beyond the hard core (see the module documentation).
pub const HISTOGRAM_FLOOR: f64 = 1e-3;
/// Default Metropolis-Hastings proposals per expected instance.
pub const DEFAULT_ITERATIONS_PER_INSTANCE: f64 = 40.0;
const FIXED_ID: u32 = u32::MAX;
/// Tag bit of fixed content outside the region (the region of influence): such pairs enter as product factors.
const CONTEXT_TAG: u32 = 1 << 31;
/// A point's total log pair factor is capped at this many times the largest single-pair log factor.
pub const SATURATION_PAIRS: f64 = 2.0;
/// Expected count from which synthesis matches the rdf directly (below it, the exemplar's `h` is used as the
/// pair factor, as in the paper).
const MIN_COUNT_FOR_RDF_MATCHING: f64 = 100.0;

/// How to synthesize.
#[derive(Clone, Debug)]
pub struct SynthesisOptions {
    pub seed: u64,
    /// None = `color.max_radius`; `Some(0.0)` disables the region of influence.
    pub influence_radius: Option<f64>,
    /// Proposal count = this × expected count (default 40).
    pub iterations_per_instance: f64,
    /// Restrict to these categories (None = all of the color).
    pub categories: Option<Vec<String>>,
}

impl Default for SynthesisOptions {
    fn default() -> Self {
        SynthesisOptions {
            seed: 0,
            influence_radius: None,
            iterations_per_instance: DEFAULT_ITERATIONS_PER_INSTANCE,
            categories: None,
        }
    }
}

/// New instances, with `category` indices into `categories` (the scene's categories plus any the color added).
#[derive(Clone, Debug)]
pub struct SynthesisResult {
    pub categories: Vec<Category>,
    pub instances: Vec<Instance>,
}

/// Synthesize the color in `region`. The scene's existing instances *inside* the region are treated as removed
/// (paste replaces); instances within the influence radius outside it condition the result.
pub fn synthesize(
    scene: &Scene,
    color: &Color,
    region: &Region,
    opts: &SynthesisOptions,
) -> Result<SynthesisResult> {
    synthesize_with_progress(scene, color, region, opts, &|_| true)
}

/// Log-factor table of one pair interaction, indexed by distance bin (× angle bin for an oriented rdf).
struct PairTable {
    log_factor: Vec<f64>,
    /// The learned histogram (the target of the rdf-matching energy).
    target_hist: Vec<f64>,
    /// Points of the other category inside the region (fixed); `None` for the self pair (the chain's own).
    others_inside: Option<usize>,
    angle_bins: usize,
    bin_width: f64,
    n_bins: usize,
    hard_core2: f64,
}

impl PairTable {
    fn new(values: &[f64], angle_bins: usize, bin_width: f64, hard_core: f64) -> Self {
        let n_bins = values.len() / angle_bins.max(1);
        let first_seen = (0..n_bins)
            .find(|&k| {
                values[k * angle_bins..(k + 1) * angle_bins]
                    .iter()
                    .any(|v| *v > 0.0)
            })
            .unwrap_or(n_bins);
        let log_factor = values
            .iter()
            .enumerate()
            .map(|(idx, &v)| {
                if idx / angle_bins < first_seen {
                    f64::NEG_INFINITY
                } else {
                    v.max(HISTOGRAM_FLOOR).ln()
                }
            })
            .collect();
        PairTable {
            log_factor,
            target_hist: values.to_vec(),
            others_inside: None,
            angle_bins,
            bin_width,
            n_bins,
            hard_core2: if hard_core.is_finite() {
                hard_core * hard_core
            } else {
                0.0
            },
        }
    }

    /// Drops the distance bins from which on the learned rdf no longer differs from 1 (the Poisson level)
    /// by more than `SIGNIFICANCE` standard deviations of its own counting noise in the exemplar, where the expected
    /// pair count of cell `k` is `pairs_per_area · h(k) · |cell k|`. Those factors are neutral anyway; the
    /// interaction radius (and the cost of every move, which grows with its square) shrinks to the range over
    /// which the exemplar shows structure. Forbidden (hard-core) bins are kept.
    fn truncate_to_significant(&mut self, pairs_per_area: f64) {
        if !(pairs_per_area > 0.0) || !pairs_per_area.is_finite() {
            return;
        }
        let a = self.angle_bins.max(1);
        // clustered exemplars count pairs in clumps, far noisier than Poisson: the outer third of the bins
        // (beyond two mean spacings of the sparsest category) measures that noise
        let outer = &self.target_hist[(2 * self.n_bins / 3) * a..];
        let outer_rms = if outer.is_empty() {
            0.0
        } else {
            (outer.iter().map(|h| (h - 1.0).powi(2)).sum::<f64>() / outer.len() as f64).sqrt()
        };
        let mut keep = 0;
        for idx in 0..self.log_factor.len() {
            let h = self.target_hist[idx];
            let count = (pairs_per_area * self.cell_area(idx)).max(1e-12);
            let sigma = (h.max(1.0) / count).sqrt();
            if self.log_factor[idx] == f64::NEG_INFINITY
                || (h - 1.0).abs() > SIGNIFICANCE * sigma.max(outer_rms)
            {
                keep = keep.max(idx / a + 1);
            }
        }
        self.n_bins = keep.min(self.n_bins);
        self.log_factor.truncate(self.n_bins * a);
        self.target_hist.truncate(self.n_bins * a);
    }

    /// Histogram index (distance bin × angle bin) and distance bin of a pair at offset `v`, `d2 = |v|²`.
    #[inline]
    fn bin_of(&self, v: DVec2, d2: f64) -> Option<(usize, usize)> {
        let k = (d2.sqrt() / self.bin_width) as usize;
        if k >= self.n_bins {
            return None;
        }
        if self.angle_bins == 1 {
            Some((k, k))
        } else {
            Some((
                k * self.angle_bins + folded_angle_bin(v, self.angle_bins),
                k,
            ))
        }
    }

    /// Area of the cell (annulus, or annular sector) of histogram index `idx`.
    fn cell_area(&self, idx: usize) -> f64 {
        let k = (idx / self.angle_bins.max(1)) as f64;
        std::f64::consts::PI * self.bin_width * self.bin_width * ((k + 1.0).powi(2) - k * k)
            / self.angle_bins.max(1) as f64
    }

    #[inline]
    fn log_factor(&self, v: DVec2, d2: f64) -> f64 {
        if d2 < self.hard_core2 {
            return f64::NEG_INFINITY;
        }
        let k = (d2.sqrt() / self.bin_width) as usize;
        if k >= self.n_bins {
            return 0.0;
        }
        if self.angle_bins == 1 {
            self.log_factor[k]
        } else {
            self.log_factor[k * self.angle_bins + folded_angle_bin(v, self.angle_bins)]
        }
    }
}

/// `ln ψ` per bin of one map.
struct MapTable<'a> {
    map: &'a str,
    hist: Histogram,
    /// Wanted distribution of the instances over the bins in the painted region (normalized; empty when
    /// unknown): what the map factors give over the region's lattice.
    wanted: Vec<f64>,
}

impl<'a> MapTable<'a> {
    fn new(map: &'a str, h: &Histogram, q: &Histogram) -> Self {
        let min_q = q
            .values
            .iter()
            .copied()
            .filter(|v| *v > 0.0)
            .fold(f64::INFINITY, f64::min);
        let values = h
            .values
            .iter()
            .enumerate()
            .map(|(k, &hv)| {
                if hv <= 0.0 {
                    return f64::NEG_INFINITY;
                }
                let x = h.start + (k as f64 + 0.5) * h.bin_width;
                let qv = q.value_at(x);
                let qv = if qv > 0.0 {
                    qv
                } else if min_q.is_finite() {
                    min_q
                } else {
                    hv
                };
                (hv / qv).ln()
            })
            .collect();
        let values = extrapolate_unseen(values, |k| {
            q.value_at(h.start + (k as f64 + 0.5) * h.bin_width) > 0.0
        });
        MapTable {
            map,
            hist: Histogram {
                start: h.start,
                bin_width: h.bin_width,
                values,
            },
            wanted: Vec::new(),
        }
    }
}

impl MapTable<'_> {
    /// Bin of map value `v`; values beyond the learned range take the end bins (see `extrapolate_unseen`).
    #[inline]
    fn bin_of(&self, v: f64) -> Option<usize> {
        let last = self.hist.values.len().checked_sub(1)?;
        if !v.is_finite() || !(self.hist.bin_width > 0.0) {
            return None;
        }
        let f = ((v - self.hist.start) / self.hist.bin_width).floor();
        Some(f.clamp(0.0, last as f64) as usize)
    }
}

/// The exemplar says nothing about map values its region never showed (a grove learned on flat ground knows
/// nothing of slopes): such bins take the preference of the nearest bin the region did show, so a flat
/// exemplar is neutral to slope, and a forest that avoided the steepest slopes it saw avoids steeper ones too.
fn extrapolate_unseen(values: Vec<f64>, seen: impl Fn(usize) -> bool) -> Vec<f64> {
    let seen_bins: Vec<usize> = (0..values.len()).filter(|&k| seen(k)).collect();
    if seen_bins.is_empty() {
        return values;
    }
    (0..values.len())
        .map(|k| {
            if seen(k) {
                return values[k];
            }
            let nearest = seen_bins
                .iter()
                .copied()
                .min_by_key(|&j| (j.abs_diff(k), j))
                .unwrap_or(k);
            values[nearest]
        })
        .collect()
}

/// Everything the chain of one category evaluates.
struct Target<'a> {
    grid: SpatialGrid,
    tables: Vec<PairTable>,
    maps: Vec<MapTable<'a>>,
    terrain: Option<&'a Heightfield>,
    radius: f64,
    /// Upper bound of a point's total log pair factor (saturation, see the module documentation).
    saturation: f64,
    /// Distance bin of the color (window-edge fractions are taken per distance bin).
    bin_width: f64,
    /// Cell size of the spatial grids.
    cell: f64,
}

impl Target<'_> {
    fn map_log(&self, p: DVec2) -> f64 {
        let mut sum = 0.0;
        for m in &self.maps {
            let Some(t) = self.terrain else {
                return f64::NEG_INFINITY;
            };
            match t.map_at(m.map, p).and_then(|v| m.bin_of(v)) {
                Some(k) => sum += m.hist.values[k],
                None => return f64::NEG_INFINITY,
            }
        }
        sum
    }

    /// `ln` of the product of all factors involving a point at `p` (skipping the grid entry `skip`).
    #[inline]
    fn energy(&self, p: DVec2, skip: u32) -> f64 {
        let m = self.map_log(p);
        if m == f64::NEG_INFINITY {
            return m;
        }
        let mut pairs = 0.0;
        self.grid.for_each_within(p, self.radius, |entry, d2| {
            if entry.id != skip || skip == FIXED_ID {
                pairs += self.tables[(entry.tag & !CONTEXT_TAG) as usize]
                    .log_factor(entry.position - p, d2);
            }
        });
        m + pairs.min(self.saturation)
    }
}

/// Iterations of the raking of several map factors (iterative proportional fitting).
const RAKING_ITERATIONS: usize = 12;

/// Several maps (elevation and slope of one terrain) are correlated, so the product of their marginal factors
/// `Π_m h_m / q_m` does not give each map the distribution the exemplar preferred. Raking (iterative
/// proportional fitting) over the painted region's lattice rescales each map's factors, bin by bin, until the
/// distribution `∝ Π_m ψ_m` over the region has, for every map, the marginal that map's own factor gives
/// alone (`∝ h_m q_region / q_exemplar`, which is `h_m` on the same kind of terrain): the maximum-entropy
/// arrangement with the learned marginals. Zero factors stay zero.
#[allow(clippy::needless_range_loop)] // bins[map][point]: the loops run over points and maps crosswise
fn rake_maps(target: &mut Target, lattice: &[DVec2]) {
    let Some(terrain) = target.terrain else {
        return;
    };
    let bins: Vec<Vec<Option<usize>>> = target
        .maps
        .iter()
        .map(|m| {
            lattice
                .iter()
                .map(|p| terrain.map_at(m.map, *p).and_then(|v| m.bin_of(v)))
                .collect()
        })
        .collect();
    let marginals = |maps: &[MapTable], only: Option<usize>| -> Vec<Vec<f64>> {
        let mut out: Vec<Vec<f64>> = maps
            .iter()
            .map(|m| vec![0.0; m.hist.values.len()])
            .collect();
        for i in 0..lattice.len() {
            let mut log_w = 0.0;
            for (mi, m) in maps.iter().enumerate() {
                if only.is_some_and(|o| o != mi) {
                    continue;
                }
                match bins[mi][i] {
                    Some(b) => log_w += m.hist.values[b],
                    None => log_w = f64::NEG_INFINITY,
                }
            }
            let w = log_w.exp();
            if w > 0.0 {
                for (mi, out_m) in out.iter_mut().enumerate() {
                    if let Some(b) = bins[mi][i] {
                        out_m[b] += w;
                    }
                }
            }
        }
        for o in &mut out {
            let total: f64 = o.iter().sum();
            if total > 0.0 {
                o.iter_mut().for_each(|v| *v /= total);
            }
        }
        out
    };
    // each map's wanted marginal: what its factor alone gives over the region
    let wanted: Vec<Vec<f64>> = (0..target.maps.len())
        .map(|mi| marginals(&target.maps, Some(mi)).swap_remove(mi))
        .collect();
    for (m, w) in target.maps.iter_mut().zip(&wanted) {
        m.wanted = w.clone();
    }
    let iterations = if target.maps.len() >= 2 {
        RAKING_ITERATIONS
    } else {
        0
    };
    for _ in 0..iterations {
        for mi in 0..target.maps.len() {
            let current = marginals(&target.maps, None).swap_remove(mi);
            for (b, v) in target.maps[mi].hist.values.iter_mut().enumerate() {
                if v.is_finite() && current[b] > 0.0 && wanted[mi][b] > 0.0 {
                    *v += (wanted[mi][b] / current[b]).ln();
                }
            }
        }
    }
}

fn mix_seed(seed: u64, a: u64) -> u64 {
    // splitmix64 of the pair: independent streams per category
    let mut z = seed
        ^ a.wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(0xD1B5_4A32_D192_ED03);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn gaussian<R: Rng>(rng: &mut R) -> DVec2 {
    let u1: f64 = rng.random::<f64>().max(1e-300);
    let u2: f64 = rng.random();
    let r = (-2.0 * u1.ln()).sqrt();
    let a = std::f64::consts::TAU * u2;
    DVec2::new(r * a.cos(), r * a.sin())
}

fn draw_from_histogram<R: Rng>(h: &Histogram, rng: &mut R, fallback: f64) -> f64 {
    let total = h.total();
    if !(total > 0.0) || !(h.bin_width > 0.0) {
        return fallback;
    }
    let mut u = rng.random::<f64>() * total;
    for (k, v) in h.values.iter().enumerate() {
        if u < *v {
            return h.start + (k as f64 + rng.random::<f64>()) * h.bin_width;
        }
        u -= v;
    }
    h.start + (h.values.len() as f64 - 0.5) * h.bin_width
}

fn draw_index<R: Rng>(weights: &[f64], rng: &mut R) -> u32 {
    let total: f64 = weights.iter().sum();
    if !(total > 0.0) {
        return 0;
    }
    let mut u = rng.random::<f64>() * total;
    for (k, w) in weights.iter().enumerate() {
        if u < *w {
            return k as u32;
        }
        u -= w;
    }
    (weights.len().saturating_sub(1)) as u32
}

/// As [`synthesize`], calling `progress` with the fraction done; returning false cancels
/// ([`Error::Cancelled`]).
pub fn synthesize_with_progress(
    scene: &Scene,
    color: &Color,
    region: &Region,
    opts: &SynthesisOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<SynthesisResult> {
    region.validate()?;
    color.validate()?;
    if !(opts.iterations_per_instance.is_finite() && opts.iterations_per_instance > 0.0) {
        return Err(Error::InvalidInput(format!(
            "iterations_per_instance {} must be positive",
            opts.iterations_per_instance
        )));
    }
    let influence = opts.influence_radius.unwrap_or(color.max_radius);
    if !(influence.is_finite() && influence >= 0.0) {
        return Err(Error::InvalidInput(format!(
            "influence radius {influence} must be zero or positive"
        )));
    }
    // categories in priority order (ties: order in the color)
    let mut order: Vec<usize> = (0..color.categories.len()).collect();
    order.sort_by_key(|&c| (color.categories[c].category.priority, c));
    if let Some(names) = &opts.categories {
        for n in names {
            if color.category(n).is_none() {
                return Err(Error::InvalidInput(format!(
                    "category '{n}' is not in color '{}'",
                    color.name
                )));
            }
        }
        order.retain(|&c| names.contains(&color.categories[c].category.name));
    }
    let terrain = scene.terrain.as_ref();
    let uses_maps = color.maps.iter().any(|m| {
        order
            .iter()
            .any(|&c| color.categories[c].category.name == m.category)
    });
    if uses_maps {
        let t = terrain.ok_or_else(|| {
            Error::InvalidInput(format!(
                "color '{}' follows terrain maps but the scene has no terrain",
                color.name
            ))
        })?;
        let (lo, hi) = region.bbox();
        let (tlo, thi) = t.bbox();
        if hi.x < tlo.x || hi.y < tlo.y || lo.x > thi.x || lo.y > thi.y {
            return Err(Error::RegionOffTerrain(format!(
                "region bbox {:?} misses the terrain {:?}",
                (lo, hi),
                (tlo, thi)
            )));
        }
    }

    // the scene's categories, then the color's new ones
    let mut listed = Scene {
        categories: scene.categories.clone(),
        ..Default::default()
    };
    let scene_index: Vec<usize> = color
        .categories
        .iter()
        .map(|c| listed.ensure_category(&c.category))
        .collect();
    let out_categories = listed.categories;

    // existing content in the region of influence (outside the region), per color category
    let context: Vec<Vec<DVec2>> = scene_index
        .iter()
        .map(|&si| {
            if influence <= 0.0 {
                return Vec::new();
            }
            scene
                .instances
                .iter()
                .filter(|i| i.category == si && !region.contains(i.position))
                .filter(|i| region.distance_outside(i.position) <= influence)
                .map(|i| i.position)
                .collect()
        })
        .collect();

    let area = region.area();
    let lattice = terrain
        .map(|t| region_lattice(region, t))
        .unwrap_or_default();
    let exemplar_lattice = terrain
        .map(|t| region_lattice(&color.region, t))
        .filter(|l| !l.is_empty());
    let (rlo, rhi) = region.bbox();
    let pad = DVec2::splat(color.max_radius);
    let mut synthesized: Vec<Option<Vec<DVec2>>> = vec![None; color.categories.len()];
    let mut instances = Vec::new();
    let n_cats = order.len().max(1);

    for (step, &ci) in order.iter().enumerate() {
        let cat = &color.categories[ci];
        let name = &cat.category.name;
        // pair tables for the self pair and every already-present other category
        let mut tables = Vec::new();
        let mut fixed_entries: Vec<GridEntry> = Vec::new();
        let mut self_tag = None;
        for (oi, other) in color.categories.iter().enumerate() {
            let same = oi == ci;
            if !same && synthesized[oi].is_none() && context[oi].is_empty() {
                continue;
            }
            let pair = color
                .pairs
                .iter()
                .filter(|p| &p.category == name && p.other == other.category.name)
                .max_by_key(|p| matches!(p.interaction, Interaction::OrientedRdf { .. }));
            let Some(pair) = pair else { continue };
            let hard_core = if same { cat.min_distance } else { 0.0 };
            let table = match &pair.interaction {
                Interaction::Rdf { hist } => {
                    PairTable::new(&hist.values, 1, hist.bin_width, hard_core)
                }
                Interaction::OrientedRdf {
                    distance_bin,
                    angle_bins,
                    values,
                } => PairTable::new(values, *angle_bins, *distance_bin, hard_core),
            };
            let mut table = table;
            if !same {
                table.others_inside = Some(synthesized[oi].as_ref().map_or(0, |v| v.len()));
            }
            let n_other = other.count as f64 - if same { 1.0 } else { 0.0 };
            table.truncate_to_significant(cat.count as f64 * n_other / color.region_area);
            let tag = tables.len() as u32;
            tables.push(table);
            if same {
                self_tag = Some(tag);
            }
            for p in synthesized[oi].iter().flatten() {
                fixed_entries.push(GridEntry {
                    position: *p,
                    tag,
                    id: FIXED_ID,
                });
            }
            for p in &context[oi] {
                fixed_entries.push(GridEntry {
                    position: *p,
                    tag: tag | CONTEXT_TAG,
                    id: FIXED_ID,
                });
            }
        }
        let self_tag = match self_tag {
            Some(t) => t,
            None => {
                tables.push(PairTable::new(&[], 1, color.bin_width, cat.min_distance));
                (tables.len() - 1) as u32
            }
        };
        let maps: Vec<MapTable> = color
            .maps
            .iter()
            .filter(|m| &m.category == name)
            .map(|m| MapTable::new(&m.map, &m.hist, &m.region_hist))
            .collect();
        // the interaction radius: as far as some pair's rdf differs from 1 (or a hard core reaches)
        let radius = tables
            .iter()
            .map(|t| t.bin_width * t.n_bins as f64)
            .fold(
                if cat.min_distance.is_finite() {
                    cat.min_distance
                } else {
                    0.0
                },
                f64::max,
            )
            .max(color.bin_width);
        // grid cells: the radius, but not much finer than the mean spacing of the content
        let spacing = (area / (cat.density * area + fixed_entries.len() as f64).max(1.0)).sqrt();
        let cell = radius.max(spacing);
        let mut grid = SpatialGrid::new(rlo - pad, rhi + pad, cell);
        for e in fixed_entries {
            grid.insert(e);
        }
        let saturation = SATURATION_PAIRS
            * tables
                .iter()
                .flat_map(|t| t.target_hist.iter())
                .fold(1.0f64, |m, v| m.max(*v))
                .ln();
        let target = Target {
            grid,
            tables,
            maps,
            terrain,
            radius,
            saturation,
            bin_width: color.bin_width,
            cell,
        };
        // expected count: exemplar density times the map preference integrated over the region
        let mean_preference = |points: &[DVec2]| {
            points.iter().map(|p| target.map_log(*p).exp()).sum::<f64>() / points.len() as f64
        };
        let preference = if target.maps.is_empty() || lattice.is_empty() {
            1.0
        } else {
            // relative to the exemplar region's own preference when it lies on this terrain: several maps
            // (elevation and slope) are correlated, and the product of their marginal ratios averages to more
            // than 1 over the exemplar itself
            let own = exemplar_lattice
                .as_deref()
                .map(mean_preference)
                .filter(|v| v.is_finite() && *v > 0.0)
                .unwrap_or(1.0);
            mean_preference(&lattice) / own
        };
        let expected = cat.density * area * preference;
        let mut target = target;
        if !target.maps.is_empty() && !lattice.is_empty() {
            rake_maps(&mut target, &lattice);
        }
        let mut rng = ChaCha8Rng::seed_from_u64(mix_seed(opts.seed, ci as u64 + 1));
        let points = run_chain(
            target,
            region,
            area,
            expected,
            self_tag,
            color.max_radius,
            opts.iterations_per_instance,
            &mut rng,
            &|f| progress((step as f64 + f) / n_cats as f64),
        )?;
        for p in &points {
            instances.push(attributes(cat, *p, scene_index[ci], &mut rng));
        }
        synthesized[ci] = Some(points);
    }
    if !progress(1.0) {
        return Err(Error::Cancelled);
    }
    Ok(SynthesisResult {
        categories: out_categories,
        instances,
    })
}

fn attributes<R: Rng>(cat: &CategoryColor, p: DVec2, category: usize, rng: &mut R) -> Instance {
    Instance {
        position: p,
        rotation: draw_from_histogram(&cat.rotation, rng, 0.0).rem_euclid(std::f64::consts::TAU),
        scale: draw_from_histogram(&cat.scale, rng, 1.0),
        category,
        prototype: draw_index(&cat.prototype_weights, rng),
    }
}

/// The birth / death / shift chain of one category; returns the final points.
#[allow(clippy::too_many_arguments)]
fn run_chain<R: Rng>(
    mut target: Target,
    region: &Region,
    area: f64,
    expected: f64,
    self_tag: u32,
    max_radius: f64,
    iterations_per_instance: f64,
    rng: &mut R,
    progress: &dyn Fn(f64) -> bool,
) -> Result<Vec<DVec2>> {
    let mut own: Vec<DVec2> = Vec::new();
    if !(expected > 0.0) || !expected.is_finite() {
        return Ok(own);
    }
    if expected >= MIN_COUNT_FOR_RDF_MATCHING {
        return run_rdf_chain(
            &target,
            region,
            area,
            expected,
            self_tag,
            max_radius,
            iterations_per_instance,
            rng,
            progress,
        );
    }
    let insert = |target: &mut Target, own: &mut Vec<DVec2>, p: DVec2| {
        target.grid.insert(GridEntry {
            position: p,
            tag: self_tag,
            id: own.len() as u32,
        });
        own.push(p);
    };
    // the count: the expected count, rounded stochastically (see "The count" in the module documentation)
    let want = expected.floor() as usize + usize::from(rng.random::<f64>() < expected.fract());
    // start from dart throwing among allowed positions
    for _ in 0..(4 * want + 100) {
        if own.len() >= want {
            break;
        }
        let Some(p) = region.sample_uniform(rng) else {
            break;
        };
        if target.energy(p, FIXED_ID) > f64::NEG_INFINITY {
            insert(&mut target, &mut own, p);
        }
    }
    let total = (iterations_per_instance * expected.max(1.0)).ceil() as usize;
    let sweep = (expected.ceil() as usize).max(64);
    let shift_sigma = max_radius / 8.0;
    let mut done = 0usize;
    while done < total {
        let end = (done + sweep).min(total);
        for _ in done..end {
            if own.len() < want {
                // a hard core left the start short: keep trying allowed births
                if let Some(p) = region.sample_uniform(rng) {
                    if target.energy(p, FIXED_ID) > f64::NEG_INFINITY {
                        insert(&mut target, &mut own, p);
                    }
                }
                continue;
            }
            if own.is_empty() {
                break;
            }
            let k = rng.random_range(0..own.len());
            let p = own[k];
            let q = if rng.random::<f64>() < 0.5 {
                // relocation: the death of p and the birth of q in one move (f(X')/f(X), symmetric)
                match region.sample_uniform(rng) {
                    Some(q) => q,
                    None => continue,
                }
            } else {
                // shift: a small Gaussian step
                p + gaussian(rng) * shift_sigma
            };
            if !region.contains(q) {
                continue;
            }
            let e_new = target.energy(q, k as u32);
            if e_new == f64::NEG_INFINITY {
                continue;
            }
            let e_old = target.energy(p, k as u32);
            if rng.random::<f64>().ln() < e_new - e_old {
                target.grid.remove(p, k as u32);
                target.grid.insert(GridEntry {
                    position: q,
                    tag: self_tag,
                    id: k as u32,
                });
                own[k] = q;
            }
        }
        done = end;
        if !progress(done as f64 / total as f64) {
            return Err(Error::Cancelled);
        }
    }
    Ok(own)
}

/// A learned rdf bin differs from 1 when it is this many standard deviations of counting noise away.
const SIGNIFICANCE: f64 = 3.0;
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
    target
        .terrain
        .and_then(|t| t.map_at(m.map, p))
        .and_then(|v| m.bin_of(v))
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
fn run_rdf_chain<R: Rng>(
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
        let frac = (sweep as f64 / ((RDF_SWEEPS - 1) as f64 * ANNEALING_FRACTION)).min(1.0);
        let tau = TAU_START * (TAU_END / TAU_START).powf(frac);
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

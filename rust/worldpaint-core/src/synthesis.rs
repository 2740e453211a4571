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
//! ## Pair factors: inversion and saturation
//! Used directly as pair factors, the exemplar's rdfs reproduce themselves only for weak interactions (a hard
//! core at finite density shifts the first peak; clusters collapse into clumps). When the painted region holds
//! enough points (≥ 100 expected), the isotropic tables start neutral and are refined during the first half of
//! the iterations by iterative Boltzmann inversion (`refine_tables`); a point's total log pair factor is capped
//! at `SATURATION_PAIRS` times the largest single-pair log factor (a Geyer-style saturation that keeps
//! attraction from condensing everything into one clump). With fewer points the exemplar's `h` is used as is,
//! as in the paper.
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
//! exemplar's own map distribution gets the exemplar density). Values where `h_m = 0` — the exemplar never had
//! an instance there, including values outside the exemplar's range — get factor 0: no instance lands there.
//!
//! ## Determinism
//! The chain of each category is sequential, driven by a ChaCha8 generator seeded from (seed, category);
//! nothing depends on the rayon thread count.

use crate::analysis::{folded_angle_bin, region_lattice};
use crate::error::{Error, Result};
use crate::geom::{DVec2, Region};
use crate::palette::{CategoryColor, Color, Histogram, Interaction};
use crate::scene::{Category, Instance, Scene};
use crate::spatial::{GridEntry, SpatialGrid};
use crate::terrain::Heightfield;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Floor of empty rdf bins beyond the hard core (see the module documentation).
pub const HISTOGRAM_FLOOR: f64 = 1e-3;
/// Default Metropolis-Hastings proposals per expected instance.
pub const DEFAULT_ITERATIONS_PER_INSTANCE: f64 = 60.0;
const FIXED_ID: u32 = u32::MAX;
/// A point's total log pair factor is capped at this many times the largest single-pair log factor.
pub const SATURATION_PAIRS: f64 = 2.0;
/// Expected count from which the pair tables are refined by inversion (below it, the exemplar's `h` is used
/// as the pair factor directly, as in the paper).
const MIN_COUNT_FOR_INVERSION: f64 = 100.0;

/// How to synthesize.
#[derive(Clone, Debug)]
pub struct SynthesisOptions {
    pub seed: u64,
    /// None = `color.max_radius`; `Some(0.0)` disables the region of influence.
    pub influence_radius: Option<f64>,
    /// Proposal count = this × expected count (default 60).
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
    /// The learned histogram the table should reproduce (refined by inversion when isotropic).
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
        MapTable {
            map,
            hist: Histogram {
                start: h.start,
                bin_width: h.bin_width,
                values,
            },
        }
    }
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
}

impl Target<'_> {
    fn map_log(&self, p: DVec2) -> f64 {
        let mut sum = 0.0;
        for m in &self.maps {
            let Some(t) = self.terrain else {
                return f64::NEG_INFINITY;
            };
            match t.map_at(m.map, p).and_then(|v| m.hist.bin_of(v)) {
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
                pairs += self.tables[entry.tag as usize].log_factor(entry.position - p, d2);
            }
        });
        m + pairs.min(self.saturation)
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

    let mut out_categories = scene.categories.clone();
    let scene_index: Vec<usize> = color
        .categories
        .iter()
        .map(|c| {
            let idx = out_categories
                .iter()
                .position(|x| x.name == c.category.name);
            idx.unwrap_or_else(|| {
                out_categories.push(c.category.clone());
                out_categories.len() - 1
            })
        })
        .collect();

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
        let mut grid = SpatialGrid::new(rlo - pad, rhi + pad, color.max_radius);
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
            let tag = tables.len() as u32;
            tables.push(table);
            if same {
                self_tag = Some(tag);
            }
            let fixed = synthesized[oi].iter().flatten().chain(context[oi].iter());
            for p in fixed {
                grid.insert(GridEntry {
                    position: *p,
                    tag,
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
        let radius = tables
            .iter()
            .map(|t| t.bin_width * t.n_bins as f64)
            .fold(color.max_radius, f64::max);
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
        };
        // expected count: exemplar density times the map preference integrated over the region
        let preference = if target.maps.is_empty() || lattice.is_empty() {
            1.0
        } else {
            lattice
                .iter()
                .map(|p| target.map_log(*p).exp())
                .sum::<f64>()
                / lattice.len() as f64
        };
        let expected = cat.density * area * preference;
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
    if expected >= MIN_COUNT_FOR_INVERSION {
        // enough points to measure the rdf: start neutral (Poisson, hard cores kept) and let the inversion
        // build the interactions up, rather than start from h and collapse into clumps first
        for t in target.tables.iter_mut().filter(|t| t.angle_bins == 1) {
            for v in t.log_factor.iter_mut().filter(|v| v.is_finite()) {
                *v = 0.0;
            }
        }
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
    let burn_in = total / 2;
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
        if end <= burn_in && expected >= MIN_COUNT_FOR_INVERSION {
            refine_tables(&mut target, &own, region, area, self_tag);
        }
        done = end;
        if !progress(done as f64 / total as f64) {
            return Err(Error::Cancelled);
        }
    }
    Ok(own)
}

/// Iterative Boltzmann inversion (Reith, Pütz & Müller 2003) of the isotropic pair tables during burn-in.
///
/// Using the exemplar's `h` itself as the pair factor (the paper's model) reproduces `h` only when the
/// interactions are weak: with clusters (`h ≫ 1` at short range) the product of many factors makes clusters
/// collapse into ever denser clumps, and a hard core at finite density shifts the first peak. So after every
/// burn-in sweep we measure the rdf of the current points (eq. (2), window-corrected, inside the region) and
/// correct each bin `ln φ_k ← ln φ_k + ½ (ln h_k − ln ĥ_k)`, for bins with at least 10 measured pairs; factors
/// are kept within [floor, 10³] and the hard-core bins stay at 0. By Henderson's theorem the pair factor that
/// reproduces a given rdf at a given density is unique, so this converges toward the model that has the
/// exemplar's statistics; the tables are frozen for the second half.
fn refine_tables(target: &mut Target, own: &[DVec2], region: &Region, area: f64, self_tag: u32) {
    use rayon::prelude::*;
    if own.len() < 2 {
        return;
    }
    let n_tables = target.tables.len();
    let layout: Vec<(usize, f64, bool)> = target
        .tables
        .iter()
        .map(|t| (t.n_bins, t.bin_width, t.angle_bins == 1))
        .collect();
    let radius = target.radius;
    let grid = &target.grid;
    // raw pair counts and window-corrected sums per table and bin, per point (ordered, so deterministic)
    let per_point: Vec<Vec<(Vec<f64>, Vec<f64>)>> = own
        .par_iter()
        .enumerate()
        .map(|(k, &p)| {
            let mut acc: Vec<(Vec<f64>, Vec<f64>)> = layout
                .iter()
                .map(|(n, _, _)| (vec![0.0; *n], vec![0.0; *n]))
                .collect();
            grid.for_each_within(p, radius, |e, d2| {
                let t = e.tag as usize;
                if (e.tag == self_tag && e.id == k as u32) || !layout[t].2 {
                    return;
                }
                if !region.contains(e.position) {
                    return;
                }
                let b = (d2.sqrt() / layout[t].1) as usize;
                if b < layout[t].0 {
                    acc[t].0[b] += 1.0;
                }
            });
            for (t, (counts, corrected)) in acc.iter_mut().enumerate() {
                if counts.iter().any(|c| *c > 0.0) {
                    let a = crate::analysis::alphas(region, p, layout[t].1, layout[t].0);
                    for b in 0..counts.len() {
                        corrected[b] = counts[b] / a[b];
                    }
                }
            }
            acc
        })
        .collect();
    let mut counts: Vec<Vec<f64>> = layout.iter().map(|(n, _, _)| vec![0.0; *n]).collect();
    let mut corrected = counts.clone();
    for point in per_point {
        for (t, (c, w)) in point.into_iter().enumerate() {
            for b in 0..c.len() {
                counts[t][b] += c[b];
                corrected[t][b] += w[b];
            }
        }
    }
    let min_log = HISTOGRAM_FLOOR.ln();
    for t in 0..n_tables {
        let table = &mut target.tables[t];
        if table.angle_bins != 1 {
            continue;
        }
        let max_log = table.target_hist.iter().fold(1.0f64, |m, v| m.max(*v)).ln();
        let n_other = match table.others_inside {
            Some(n) => n as f64,
            None => own.len() as f64 - 1.0,
        };
        if n_other <= 0.0 {
            continue;
        }
        let norm = area / (own.len() as f64 * n_other);
        for b in 0..table.n_bins {
            if counts[t][b] < 10.0 || table.log_factor[b] == f64::NEG_INFINITY {
                continue;
            }
            let h = table.target_hist[b];
            if h <= 0.0 {
                continue;
            }
            let shell = std::f64::consts::PI
                * table.bin_width
                * table.bin_width
                * ((b + 1).pow(2) - b.pow(2)) as f64;
            let measured = corrected[t][b] * norm / shell;
            let step = (0.5 * (h.ln() - measured.ln())).clamp(-0.5, 0.5);
            table.log_factor[b] = (table.log_factor[b] + step).clamp(min_log, max_log);
        }
    }
}

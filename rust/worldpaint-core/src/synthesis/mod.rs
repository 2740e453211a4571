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
//! ## Births where the maps say
//! A color that follows maps has its births — the darts of the start, the births of a relocation — drawn from the
//! map-weighted intensity `λ(x) ∝ Π_m ψ_m(m(x))` of the painted terrain instead of uniformly, and the move is
//! accepted with the Hastings ratio of that proposal (`g(x_old) / g(x_new)` times the ratio of `f`): the chain
//! samples the same `f`, but content starts where the terrain says instead of being moved there from uniform
//! darts. The rdf-matching chain starts a clustered color, with maps or without, as clusters of the size and
//! spread its rdf shows, their first instances drawn from `λ` (uniformly without maps; module `births`).
//!
//! ## Small counts: the product model of eq. (1)
//! When the painted region holds fewer than 100 expected instances of a category (or the caller asks for it,
//! [`SynthesisOptions::product_model`]), the chain is the paper's:
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
//! **When to stop.** The seed sets the number of iterations by the category's density and notes that sparse
//! categories with many interactions need more; `iterations_per_instance` is therefore a budget, and the chain
//! stops before any of a sweep's phases once `E` (Pearson's χ²) is at most `CONVERGED_CHI2_PER_BIN` per bin that
//! has a target, times the paste's size in examples `k = n / n_example` (at least 1). Why `k`: the targets are the
//! example's counts scaled up by about `k`, so each carries the example's counting noise scaled up too, a variance
//! of about `k T` against the `T` of the paste's own counts. Matching them more closely than that copies the
//! example's noise, not its process; the bound lets the chain leave a quarter of the variance the target already
//! carries. On the bench color (trees, rocks and clumped grass) the grass, started as clusters, stops after its
//! first sweep of 12 at 100k instances and at 1M (see "Tiles match their own pairs"; started uniformly and matched
//! to the region's `H − T` only, it stopped one phase into its third), where a bound of a quarter alone ran 7 and
//! all 12. The slope forest's rock–grass pair, which converges slowly, is left at the level of a
//! second draw of the example (rdf L2 7.2 against 7.8) rather than well below it. The bound is a quarter rather
//! than one because at one the chain stopped while the borders of small patches were still 14 % denser than their
//! insides.
//!
//! Some targets cannot be reached: the trees of an archipelago learned their pairs around the example's islands,
//! and the synthesized islands are others, so their chain gains less and less a sweep (χ² 793, 248, 151, 118, 105,
//! 97, 87, 84, 79, 75, 73 against a bound of 11, over its twelve sweeps) and spends its whole budget. The chain
//! therefore also stops before a sweep that follows one which lowered χ² by less than `STALLED_GAIN` (a tenth)
//! while it stays above `STALLED_CHI2_PER_BIN` (one) per bin, times `k`: deviations as large as the targets'
//! own counting noise, which further sweeps would lower by a fraction, not bring within it. The archipelago's
//! trees stop at 97 before their seventh sweep, its boats at 136 (bound 14) before theirs, and the benchmark's
//! paste (Table 2, Fig. 1 right) takes 0.91–0.95 of the paper's time per object instead of 1.04–1.34. Only once
//! the chain is cold (`τ ≤ STALLED_TAU`, from the sixth sweep on): a hot chain may gain little because it is hot
//! (against targets ten times what its count can give, a chain gained less than a tenth in each of its first two
//! sweeps). Chains that still gain, and those within the noise that approach the bound slowly (the slope
//! forest's rock–grass pair), run on.
//!
//! A chain on one tile over the region reads the bound once a sweep, those on tiles before each of a sweep's four
//! phases. The dense points of a polygon category read it four times a sweep on one tile too, each quarter of its
//! proposals run as a phase of its own (`quartered`): the archipelago's coast (1,686 points of about 190
//! neighbours a move) stood at χ² 7.6 before its fifth sweep and 4.9 before its sixth against a bound of 6, and
//! now stops within its fourth, which takes the benchmark's paste (Table 2, Fig. 1 right) from 0.92–1.45 to
//! 0.76–0.97 of the paper's time per object. Instances keep the rule once a sweep: stopping within one left the
//! outer 2 m of hard-core patches (80 m squares, 0.04 per m²) at 1.16 × the density instead of 1.10, and the seams
//! of world tiles showing in their grass (pcf L2 0.165 against a second draw's 0.122): the rest of the sweep
//! relaxes a free border that χ² does not see. The islands' land shows no such outline either way (its share by
//! distance to the border in `tests/borders.rs`).
//!
//! **Interaction radius.** Each pair's rdf is cut after its last bin that differs from 1 by more than
//! `SIGNIFICANCE` standard deviations of the exemplar's counting noise (the larger of the Poisson noise of
//! the bin and the RMS deviation of the outer third of the bins, which measures clump noise), keeping hard-core
//! bins. Beyond it the learned rdf is noise around 1 and the factor is neutral; the moves' cost grows with the
//! radius squared. An rdf that stays clustered (read in blocks of one mean spacing, as the analysis follows a
//! clustered exemplar: see "Bin width and maximum radius" in `analysis`) keeps twice its clustered range, so the
//! chain also holds it at 1 beyond the clusters: at a fixed count, excess pairs inside the clusters are otherwise
//! paid for with a ring of gaps right behind them (measured on the Luquillo plot: a pcf of 0.91–0.96 at 15–30 m
//! where the real one stays at 1.0–1.1). Shift moves are three bins long (an eighth of three mean spacings),
//! whatever the radius.
//! A pair whose rdf is cut to nothing (the other category's placement is independent of this one's) leaves
//! that category's content out of the chain altogether, and a chain left with nothing to match (only hard-core
//! bins and no map) makes no moves: the dart throwing that starts it already keeps every hard core, and its moves
//! would only trade one such arrangement for another at the cost of every neighbour search.
//!
//! **Tiles and determinism.** The region is cut into square tiles at least twice the interaction radius wide
//! (and holding ≥ `MIN_TILE_INSTANCES` expected instances), with a random offset per sweep; tiles are processed
//! in four 2 × 2 colour phases, so tiles of a phase never share a neighbour, in parallel with rayon. Each
//! tile moves only its own instances, inside itself, with its own ChaCha8 generator seeded from (seed,
//! category, sweep, phase, tile). A tile's changes of `H` are exact (tiles of a phase are at least twice the
//! radius apart, so no pair joins two moving tiles): `H` is computed in full once, then carried by the tiles'
//! changes, and the stopping bound is read on it. Results are merged in tile order: the same seed gives the same
//! result whatever the thread count. Small regions are one tile. An instance never leaves its tile, so a sweep
//! sorts the instances into its tiles once, and a tile finds the instances around it among its eight neighbours'
//! (no index of all instances is rebuilt between phases).
//!
//! **Tiles match their own pairs.** Without maps a tile matches its own pair histograms — its members' pairs,
//! counted when the phase starts and carried by its moves — to its share `f` of the targets (its count over the
//! category's), at the weights `1 / (f max(f T, 1))`: its chi-square as the region's would read were every tile
//! as far from its share as this one, so `τ` means what it means for one tile over the region. Matched only to
//! the region's `H − T` (each tile its share of the correction, as before), every tile of a phase was pushed the
//! same way whatever its own clumps, and a phase overshot to make up for the tiles still to come: a paste of 1 km²
//! of the benchmark grass was uneven from one 62.5 m square to the next (the neighbours within 4 m of an
//! instance spread 1.79 between squares, 1.41 in the process that made the example), 2.7–3.1 once the chain
//! started from clusters. Matching their own pairs, the squares spread 0.94 and the chain reaches the stopping
//! bound in one sweep. With maps the density follows the terrain, a tile's share of the pairs is not its share
//! of the instances, and tiles see the region's `H − T` plus their own changes scaled by their share of the
//! phase's instances; the map histograms are always read so.
//! A tile matching its own pairs also stops on its own, once its chi-square (as the region's would read) is
//! within the region's stopping bound: were every tile so, `H − T` would be too (its square is at most the tiles'
//! count times the sum of theirs), and the tile is then as near its share of the targets as the example's own
//! counting noise allows (its relative deviation per bin at most that of the example, whatever the paste's size).
//! On the bench grass at 100k, tiles started at 70–400 times the bound and stopped after a tenth to seven tenths
//! of their budget; the region's χ² ended at half the bound (a twentieth with every tile spending its budget),
//! the squares spread 0.92, and the chain's phases took 4.5 ms instead of 9.
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
//! over the exemplar region, when it lies on the terrain and the color was learned there
//! ([`SynthesisOptions::exemplar_on_terrain`]), since correlated maps such as elevation and slope do
//! not average to 1). With several maps the factors are raked over the painted region (`rake_maps`) so each
//! map's distribution is what its own factor gives. Values the exemplar region showed but where `h_m = 0` —
//! the exemplar never had an instance there — get factor 0: no instance lands there. Values the region never
//! showed (beyond its range, or a gap) take the factor of the nearest value it did show, but never more than 1:
//! the exemplar holds no evidence about them, so they get at most its mean density. A neutral reading keeps, say,
//! a grove learned on flat ground pastable on hills, a forest that thinned out towards the steepest slopes it saw
//! stays thin beyond them, and a preference read at the edge of the example on a few samples is not extrapolated
//! into more content over a destination that lies beyond it. The share of the region where each map reads such
//! values is reported ([`SynthesisResult::unseen_maps`]).
//!
//! The maps also concentrate the pairs: a forest that grows only on the upper half of its example has twice the
//! neighbours at short range that its density over the whole region predicts, and the learned rdf holds that
//! factor. Where the painted region's maps allow a fifth of it, the factor is five, and pair counts normalised by
//! the whole region's area would make the rdf chain spread the clumps apart. So the self pair's target counts are
//! scaled by `κ_example / κ_painted`, with `κ = (mean ψ)² / mean ψ²` over a region (its effective share, as in
//! the inhomogeneous pair-correlation function of Baddeley, Møller and Waagepetersen 2000): 1 where both regions
//! hold their maps' values alike. `κ_example` is read on the exemplar region when the color was learned on this
//! terrain, else from the map histograms as if the maps were independent (`1 / Σ h² / q` each).
//!
//! ## Free borders
//! Where the region of influence holds no content, the neighbours an instance would have beyond the border are
//! missing and the chain crowds the border; a first-order field of them is added to the log-density of instances
//! near such free borders (module `ghosts`).
//!
//! ## Attributes
//! Rotation, scale and prototype are drawn for the points the chain leaves, from the category's histograms (module
//! `draws`): the scale from the size histogram (its log) when the color has one; near a road, for a category that
//! faces the roads, the rotation from the angles learned in the band of distance to the nearest road, turned from
//! the direction towards it (the roads being those painted or kept by then: see `analysis::facing`).
//!
//! ## Determinism
//! Every random choice comes from ChaCha8 generators seeded from (seed, category) and, for tiles, (sweep,
//! phase, tile); parallel results are merged in a fixed order, so nothing depends on the rayon thread count.

mod adapt;
mod arc_grid;
mod arcs;
mod births;
mod draws;
mod ghosts;
mod islands;
mod painting;
mod product;
mod rdf;
mod relax;
mod structures;
mod target;

pub(crate) use draws::{attributes, gaussian, Facing};

pub(crate) use adapt::adapt;
pub use adapt::AdaptOptions;

use crate::arrangement::PatternGuides;
use crate::error::{check, Error, Result};
use crate::geom::{describe_box, DVec2, PreparedRegion, Region, RegionQueries};
use crate::limits;
use crate::palette::{Color, MapSource};
use crate::scene::{Category, Contour, Instance, Path, Scene};
use painting::{Painted, Painting};
use structures::StructuredContent;

/// Floor of empty rdf bins beyond the hard core (see the module documentation).
pub(crate) const HISTOGRAM_FLOOR: f64 = 1e-3;
/// Default Metropolis-Hastings proposals per expected instance.
pub(crate) const DEFAULT_ITERATIONS_PER_INSTANCE: f64 = 40.0;
/// A point's total log pair factor is capped at this many times the largest single-pair log factor.
pub(crate) const SATURATION_PAIRS: f64 = 2.0;

/// How to synthesize.
#[derive(Clone, Debug)]
pub struct SynthesisOptions {
    /// Seed of every random choice: the same seed, scene, color and region give the same result on every machine
    /// and thread count.
    pub seed: u64,
    /// None = `color.max_radius`; `Some(0.0)` disables the region of influence.
    pub influence_radius: Option<f64>,
    /// Proposal budget = this × expected count (default 40); the chain stops earlier once its histograms match
    /// (see "When to stop").
    pub iterations_per_instance: f64,
    /// Restrict to these categories (None = all of the color).
    pub categories: Option<Vec<String>>,
    /// Whether the scene's terrain is the one the color was learned on (the default): the expected count is then
    /// calibrated by the color's map preference over its exemplar region on that terrain (see "Maps"). False
    /// for a color learned on another terrain (a built-in exemplar): there its region says nothing, and the
    /// preference is taken to average to 1 over the exemplar, as a single map's does by construction
    /// (`Σ_b q(b) ψ(b) = Σ_b h_m(b) = 1`).
    pub exemplar_on_terrain: bool,
    /// Keep the product model of eq. (1) whatever the expected count (see "Small counts"): for content that
    /// its maps confine to a small part of the region (rocks along rivers), whose pair counts cannot be compared
    /// with those the region's whole area would give.
    pub product_model: bool,
    /// Where an arrangement color's pattern starts, and the curves it must not cross or follows (ignored by other
    /// colors).
    pub guides: PatternGuides,
}

impl Default for SynthesisOptions {
    fn default() -> Self {
        SynthesisOptions {
            seed: 0,
            influence_radius: None,
            iterations_per_instance: DEFAULT_ITERATIONS_PER_INSTANCE,
            categories: None,
            exemplar_on_terrain: true,
            product_model: false,
            guides: PatternGuides::default(),
        }
    }
}

/// New content, with `category` indices into `categories` (the scene's categories plus any the color added): new
/// instances, new paths (graph categories), and new contours (polygon categories), which replace the scene's
/// contours listed in `replaced_contours` (unlocked contours at the region, merged with the new ones).
#[derive(Clone, Debug, Default)]
pub struct SynthesisResult {
    /// The scene's categories, then those of the color the scene lacked.
    pub categories: Vec<Category>,
    /// The new instances.
    pub instances: Vec<Instance>,
    /// The new paths of graph categories.
    pub paths: Vec<Path>,
    /// The new contours of polygon categories.
    pub contours: Vec<Contour>,
    /// Indices into the scene's contours of those the new contours replace.
    pub replaced_contours: Vec<usize>,
    /// Per map (by name), the share of the region where the map reads values the color's example never showed:
    /// there the color paints at most its mean density (see the module documentation, "Maps"). Maps whose values
    /// the example covered everywhere are left out.
    pub unseen_maps: Vec<(String, f64)>,
}

/// Records that `share` of a painted region read map `name` outside its example (the largest share per map).
pub(crate) fn add_unseen(unseen: &mut Vec<(String, f64)>, name: String, share: f64) {
    match unseen.iter_mut().find(|(n, _)| *n == name) {
        Some((_, s)) => *s = s.max(share),
        None => unseen.push((name, share)),
    }
}

/// The annealing schedule the chains share: a value lowered geometrically from `start` to `end` over the first
/// `cooling` share of `sweeps` sweeps, then held at `end`.
pub(crate) fn annealed(start: f64, end: f64, sweep: usize, sweeps: usize, cooling: f64) -> f64 {
    let frac = (sweep as f64 / ((sweeps.max(2) - 1) as f64 * cooling)).min(1.0);
    start * (end / start).powf(frac)
}

pub(crate) fn mix_seed(seed: u64, a: u64) -> u64 {
    // splitmix64 of the pair: independent streams per category
    let mut z = seed
        ^ a.wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(0xD1B5_4A32_D192_ED03);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The color's categories in priority order (ties: order in the color), restricted to `only` when given.
pub(crate) fn priority_order(color: &Color, only: Option<&[String]>) -> Result<Vec<usize>> {
    let mut order: Vec<usize> = (0..color.categories.len()).collect();
    order.sort_by_key(|&c| (color.categories[c].category.priority, c));
    if let Some(names) = only {
        for n in names {
            if color.category(n).is_none() {
                return Err(Error::invalid(
                    format!("category '{n}'"),
                    format!("is not in color '{}'", color.name),
                ));
            }
        }
        order.retain(|&c| names.contains(&color.categories[c].category.name));
    }
    Ok(order)
}

/// Index of each of the color's categories in the scene's category list, extended by the color's new ones.
pub(crate) fn scene_categories(scene: &Scene, color: &Color) -> (Vec<Category>, Vec<usize>) {
    let mut listed = Scene {
        categories: scene.categories.clone(),
        ..Default::default()
    };
    let scene_index: Vec<usize> = color
        .categories
        .iter()
        .map(|c| listed.ensure_category(&c.category))
        .collect();
    (listed.categories, scene_index)
}

/// A clear error when the color follows terrain maps (for the given categories) and the region misses the terrain.
pub(crate) fn check_terrain(
    scene: &Scene,
    color: &Color,
    order: &[usize],
    region: &Region,
) -> Result<()> {
    let uses_maps = color.maps.iter().any(|m| {
        m.source == MapSource::Terrain
            && order
                .iter()
                .any(|&c| color.categories[c].category.name == m.category)
    });
    if !uses_maps {
        return Ok(());
    }
    let t = scene.terrain.as_deref().ok_or_else(|| {
        Error::invalid(
            format!("color '{}'", color.name),
            "follows terrain maps but the scene has no terrain",
        )
    })?;
    // a map made in the scene (a painted group, a distance) must be read on the destination too: without it the
    // category would be painted as if the map did not matter
    if let Some(m) = color.maps.iter().find(|m| {
        m.source == MapSource::Terrain
            && !t.maps.contains_key(&m.map)
            && order
                .iter()
                .any(|&c| color.categories[c].category.name == m.category)
    }) {
        let known: Vec<&str> = t.maps.keys().map(String::as_str).collect();
        return Err(Error::invalid(
            format!("color '{}'", color.name),
            format!(
                "follows the map '{}', which the terrain does not have (it has {})",
                m.map,
                known.join(", ")
            ),
        ));
    }
    let (lo, hi) = region.bbox();
    let (tlo, thi) = t.bbox();
    if hi.x < tlo.x || hi.y < tlo.y || lo.x > thi.x || lo.y > thi.y {
        return Err(Error::RegionOffTerrain {
            reason: format!(
                "the region ({}) misses the terrain ({})",
                describe_box((lo, hi)),
                describe_box((tlo, thi))
            ),
        });
    }
    Ok(())
}

/// Positions of the scene's instances, per color category (`scene_index`), for which `keep` holds and that lie
/// within `influence` of the region (inside it too).
pub(crate) fn conditioning_content(
    scene: &Scene,
    scene_index: &[usize],
    region: &PreparedRegion,
    influence: f64,
    keep: &dyn Fn(&Instance) -> bool,
) -> Vec<Vec<DVec2>> {
    let (lo, hi) = region.bbox();
    let (lo, hi) = (lo - DVec2::splat(influence), hi + DVec2::splat(influence));
    let mut out = vec![Vec::new(); scene_index.len()];
    for i in &scene.instances {
        let p = i.position;
        if p.x < lo.x || p.y < lo.y || p.x > hi.x || p.y > hi.y || !keep(i) {
            continue;
        }
        if let Some(ci) = scene_index.iter().position(|&s| s == i.category) {
            if region.distance_outside(p) <= influence {
                out[ci].push(p);
            }
        }
    }
    out
}

/// What every painter of a color takes: paint `color` into `region` of `scene`, conditioned on the instances for
/// which `keep` holds.
#[derive(Clone, Copy)]
pub(crate) struct PaintRequest<'a> {
    pub scene: &'a Scene,
    pub color: &'a Color,
    pub region: &'a Region,
    pub opts: &'a SynthesisOptions,
    pub progress: &'a (dyn Fn(f64) -> bool + Sync),
    pub keep: &'a (dyn Fn(&Instance) -> bool + Sync),
}

/// Synthesize the request's statistical color (validated, with its region, by the caller) in its region, conditioned
/// on the scene's instances for which `keep` holds: those inside the region (locked content) and those within the
/// influence radius around it enter as fixed content, and the kept instances of a category inside the region count
/// towards its expected number. Instances for which `keep` fails are ignored (the caller removes them).
pub(crate) fn synthesize_keeping(request: PaintRequest<'_>) -> Result<SynthesisResult> {
    let PaintRequest {
        scene,
        color,
        region,
        opts,
        progress,
        keep,
    } = request;
    let influence = checked_influence(color, opts)?;
    let order = priority_order(color, opts.categories.as_deref())?;
    check_terrain(scene, color, &order, region)?;
    let region = &*region.with_bounded_detail();
    let on_terrain = match scene.terrain.as_deref() {
        Some(t) => t.clip(region).ok_or_else(|| Error::RegionOffTerrain {
            reason: format!(
                "the region ({}) and the terrain ({}) do not overlap",
                describe_box(region.bbox()),
                describe_box(t.bbox())
            ),
        })?,
        None => region.clone(),
    };
    check_instance_budget(color, &order, &on_terrain)?;
    let (out_categories, scene_index) = scene_categories(scene, color);
    // every proposal asks the region: its large polygons are indexed once for the whole call
    let region = &PreparedRegion::new(&on_terrain);
    let context = conditioning_content(scene, &scene_index, region, influence, keep);
    let painting = Painting::new(scene, color, region, opts, influence, scene_index);
    let mut state = Painted {
        synthesized: vec![None; color.categories.len()],
        context,
        structured: StructuredContent::near(scene, &on_terrain, influence + color.max_radius),
        structure_values: Default::default(),
        out: SynthesisResult {
            categories: out_categories,
            ..Default::default()
        },
    };
    let n_cats = order.len().max(1);
    for (step, &ci) in order.iter().enumerate() {
        let report = |f: f64| progress((step as f64 + f) / n_cats as f64);
        painting.synthesize_category(ci, &mut state, &report)?;
    }
    if !progress(1.0) {
        return Err(Error::Cancelled);
    }
    let mut out = state.out;
    out.replaced_contours.sort_unstable();
    out.replaced_contours.dedup();
    Ok(out)
}

/// Refuses a synthesis whose categories would make more than [`limits::MAX_INSTANCES`] instances at the color's
/// densities, before anything is allocated for it.
fn check_instance_budget(color: &Color, order: &[usize], region: &Region) -> Result<()> {
    let area = region.area();
    let count: f64 = order
        .iter()
        .map(|&ci| color.categories[ci].density * area)
        .sum();
    limits::check(
        &format!("painting color '{}' over {area:.0} m²", color.name),
        count,
        limits::MAX_INSTANCES,
        "instances",
    )
}

/// Checks the options' iteration count and returns the radius of the region of influence.
fn checked_influence(color: &Color, opts: &SynthesisOptions) -> Result<f64> {
    check::positive("iterations_per_instance", opts.iterations_per_instance)?;
    let influence = opts.influence_radius.unwrap_or(color.max_radius);
    check::non_negative("influence radius", influence)
}

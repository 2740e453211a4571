//! Where births are proposed (Section 4.1, eq. (1), with the map-sampling histograms `h_m`): the map-weighted
//! intensity
//!
//! ```text
//! λ(x) ∝ Π_m ψ_m(m(x)),   ψ_m = h_m / q_m
//! ```
//!
//! read on the painted terrain: the learned map-sampling histograms over the exemplar region's own histograms of
//! the maps (raked when there are several, see `rake_maps`), which is the example's instances per unit area of
//! each map bin, as the inhomogeneous Poisson process fitted on the same maps has it. The paper proposes births
//! uniformly in the region (the `A / n_X` of eq. (1) is the inverse of a uniform proposal density); here a birth
//! (the birth half of a relocation, and each dart of the start) is drawn from `λ` instead, so content is born
//! where the terrain says, rather than where a uniform draw happens to land and the chain must then move it from.
//!
//! **The acceptance.** A Metropolis-Hastings move proposed from a density `g` is accepted with
//! `f(X') / f(X) · g(x_old) / g(x_new)` (Hastings 1970): the proposal density of the reverse move over the
//! forward one. With `g = 1/A` this is the paper's ratio; with `g ∝ λ` the map factor `ψ(q)/ψ(p)` of the target
//! is largely paid back by the proposal, and the chain's stationary distribution is exactly the one it had with
//! uniform proposals: the proposals change how fast it gets there (see the module documentation of [`super`] for
//! the target itself).
//!
//! **The proposal density.** `λ` is read as the mean of `Π_m ψ_m` over the lattice points of each cell of a grid
//! (about four lattice points a cell, at most `MAX_CELLS` cells; every k-th lattice point where they hold more),
//! held constant over the cell and floored at `ε = FLOOR_SHARE` times its mean over the region. A proposal over a
//! rectangle (a tile of the rdf-matching chain, or the region's box) draws a cell by `λ_c · |cell ∩ rectangle|`
//! and a point uniformly in that part of it:
//!
//! ```text
//! g(x) = max(λ_c(x), ε λ̄) / Σ_c max(λ_c, ε λ̄) |c ∩ R|
//! ```
//!
//! The floor keeps `g` positive everywhere, so an instance that stands where the grid reads no intensity (a cell
//! whose lattice points all lie where `ψ = 0`, a sliver of the region no lattice point falls in) can still be
//! relocated: with `g(x_old) = 0` the ratio would hold it there forever. Two points of one rectangle share its
//! denominator, so their ratio `g(x_old) / g(x_new)` is that of their cells' floored `λ`, read from one table.
//! Colors without maps keep the uniform proposals, the start and the random streams they had.
//!
//! Drawn from `λ`, a start also reaches its count where the maps confine a color to a sliver of the region, which
//! uniform darts miss (the product model painted 251 of a band's 618 trees where its heights cover under 1 % of
//! the region).
//!
//! ## Clusters
//! The rdf-matching chain starts a clustered color that follows maps as clusters: only the first instance of each
//! cluster is drawn from `λ`, the others uniformly in a disc around it. The rdf gives the clusters' size and
//! spread: the *excess neighbours* `E = ρ ∫ (h − 1) dA` (a cluster's mean size less one, so one instance in
//! `1 + E` starts a cluster) and the radius holding nine tenths of them (the disc's pairs lie within it as often).
//! Drawing every dart from `λ` piled instances up where `λ` is high while the chain's first, hot sweeps formed the
//! clusters (they grow fastest where instances already stand): on the benchmark's clustered grass the map
//! histogram's χ² rose from 497 to 4,739 over the first two sweeps and the chain needed a fifth; from clustered
//! starts it falls from 1,275 to 82 over the first three, the pairs' from 17,426 (813,939 from single darts) to
//! 108, and the chain stops after four sweeps, as with uniform darts. Relocations that grow a cluster next to
//! another instance (a mixture proposal with its Hastings ratio) mixed the chain enough to relax, beyond the range
//! of the pairs it matches, the wider clustering of a color learned on part of its example (clumps within 4 m at
//! 0.69 to 0.91 times the example's, against 1.00 to 1.14 without), so relocations keep drawing from `λ` alone.
//! The product model keeps its darts from `λ`: its factors, not a start, make its clusters.

use crate::geom::{DVec2, PreparedRegion, RegionQueries};
use crate::grid::Grid;
use rand::Rng;

/// Most cells of the intensity grid.
const MAX_CELLS: f64 = 65_536.0;
/// Lattice points per cell of the intensity grid, about.
const LATTICE_POINTS_PER_CELL: f64 = 4.0;
/// The proposal's intensity is at least this share of `λ`'s mean over the region (`ε` above).
const FLOOR_SHARE: f64 = 0.1;

/// The map-weighted intensity `λ` of one category over the painted region, constant per grid cell and floored
/// (see "The proposal density").
pub(super) struct BirthIntensity {
    grid: Grid,
    /// The floored `λ` per cell, row-major.
    lambda: Vec<f64>,
    /// Its logarithm.
    log_lambda: Vec<f64>,
}

impl BirthIntensity {
    /// `λ` from `psi`, `Π_m ψ_m` at each point of `lattice` (the region's sample points), over the box `bounds`.
    /// None when `λ` vanishes everywhere (the chain then finds no allowed place anyway, and uniform proposals say
    /// so as well as any).
    pub(super) fn new(
        lattice: &[DVec2],
        psi: impl Fn(usize) -> f64 + Sync,
        bounds: (DVec2, DVec2),
    ) -> Option<Self> {
        use rayon::prelude::*;
        let (lo, hi) = bounds;
        let ext = (hi - lo).max(DVec2::splat(1e-9));
        let area = ext.x * ext.y;
        let cell = (LATTICE_POINTS_PER_CELL * area / lattice.len().max(1) as f64)
            .sqrt()
            .max((area / MAX_CELLS).sqrt());
        let grid = Grid::buckets_covering(lo, hi, cell);
        // about LATTICE_POINTS_PER_CELL of them a cell: every `stride`-th where the cells hold more
        let stride = (lattice.len() as f64 / (LATTICE_POINTS_PER_CELL * grid.len() as f64))
            .floor()
            .max(1.0) as usize;
        let read: Vec<usize> = (0..lattice.len()).step_by(stride).collect();
        let values: Vec<f64> = read
            .par_iter()
            .map(|&i| {
                Some(psi(i))
                    .filter(|v| v.is_finite() && *v > 0.0)
                    .unwrap_or(0.0)
            })
            .collect();
        let mut sum = vec![0.0; grid.nx * grid.ny];
        let mut count = vec![0u32; grid.nx * grid.ny];
        for (&i, v) in read.iter().zip(&values) {
            let (cx, cy) = grid.bucket_of(lattice[i]);
            let k = cy * grid.nx + cx;
            sum[k] += v;
            count[k] += 1;
        }
        let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
        if !(mean > 0.0) || !mean.is_finite() {
            return None;
        }
        // cells no lattice point fell in take the floor: a sliver of the region may lie in them
        let lambda: Vec<f64> = sum
            .iter()
            .zip(&count)
            .map(|(s, n)| (s / (*n).max(1) as f64).max(FLOOR_SHARE * mean))
            .collect();
        let log_lambda = lambda.iter().map(|l| l.ln()).collect();
        Some(BirthIntensity {
            grid,
            lambda,
            log_lambda,
        })
    }

    /// The proposal over the rectangle `lo..hi` (see "The proposal density").
    pub(super) fn over(&self, lo: DVec2, hi: DVec2) -> RectProposal<'_> {
        let g = &self.grid;
        let hi = hi.max(lo);
        let (x0, y0) = g.bucket_of(lo);
        let (x1, y1) = g.bucket_of(hi);
        let nx = x1 - x0 + 1;
        let mut cdf = Vec::with_capacity(nx * (y1 - y0 + 1));
        let mut total = 0.0;
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                let (clo, chi) = self.clipped_cell(cx, cy, lo, hi);
                let part = (chi - clo).max(DVec2::ZERO);
                total += self.lambda[cy * g.nx + cx] * part.x * part.y;
                cdf.push(total);
            }
        }
        RectProposal {
            intensity: self,
            lo,
            hi,
            x0,
            y0,
            nx,
            cdf,
        }
    }

    /// `ln` of the proposal's intensity at `p`: the log density of a birth at `p` drawn over any rectangle holding
    /// it, less the log of the rectangle's total (a constant that cancels in the Hastings ratio of two points of
    /// the same rectangle).
    #[inline]
    pub(super) fn log_weight(&self, p: DVec2) -> f64 {
        let (cx, cy) = self.grid.bucket_of(p);
        self.log_lambda[cy * self.grid.nx + cx]
    }

    /// Cell `(cx, cy)` of the grid within the rectangle `lo..hi`.
    fn clipped_cell(&self, cx: usize, cy: usize, lo: DVec2, hi: DVec2) -> (DVec2, DVec2) {
        let g = &self.grid;
        let clo = g.origin + DVec2::new(cx as f64, cy as f64) * g.cell;
        let chi = clo + DVec2::splat(g.cell);
        // the border cells also hold what lies beyond the grid's box (points are clamped into them)
        let clo = DVec2::new(
            if cx == 0 { lo.x } else { clo.x },
            if cy == 0 { lo.y } else { clo.y },
        );
        let chi = DVec2::new(
            if cx + 1 == g.nx { hi.x } else { chi.x },
            if cy + 1 == g.ny { hi.y } else { chi.y },
        );
        (clo.max(lo), chi.min(hi))
    }
}

/// Births proposed over one rectangle from a [`BirthIntensity`].
pub(super) struct RectProposal<'a> {
    intensity: &'a BirthIntensity,
    lo: DVec2,
    hi: DVec2,
    /// The grid cells of the rectangle: from `(x0, y0)`, `nx` a row.
    x0: usize,
    y0: usize,
    nx: usize,
    /// Cumulative `λ_c |c ∩ R|` over the cells, row-major.
    cdf: Vec<f64>,
}

impl RectProposal<'_> {
    /// `ln g(p)` up to the rectangle's constant (see [`BirthIntensity::log_weight`]).
    #[inline]
    pub(super) fn log_weight(&self, p: DVec2) -> f64 {
        self.intensity.log_weight(p)
    }

    /// A point drawn from `g` (see "The proposal density").
    pub(super) fn sample<R: Rng>(&self, rng: &mut R) -> DVec2 {
        let total = self.cdf.last().copied().unwrap_or(0.0);
        let t = rng.random::<f64>() * total;
        let k = self
            .cdf
            .partition_point(|c| *c <= t)
            .min(self.cdf.len().saturating_sub(1));
        let (cx, cy) = (self.x0 + k % self.nx, self.y0 + k / self.nx);
        let (lo, hi) = self.intensity.clipped_cell(cx, cy, self.lo, self.hi);
        DVec2::new(
            lo.x + rng.random::<f64>() * (hi.x - lo.x),
            lo.y + rng.random::<f64>() * (hi.y - lo.y),
        )
    }
}

/// A color is clustered when its rdf holds at least this many excess neighbours per instance.
const CLUSTERED_EXCESS: f64 = 0.5;
/// The clusters' pairs lie within the radius that holds this share of the excess neighbours.
const CLUSTER_EXCESS_SHARE: f64 = 0.9;
/// Two points drawn uniformly in a disc of radius 1 lie closer than this nine times in ten.
const DISC_PAIR_DISTANCE_90: f64 = 1.49;

/// The clusters of a clustered color as its rdf shows them (see "Clusters" in the module documentation): the
/// radius within which its cluster pairs lie, and how many neighbours a cluster gives an instance.
#[derive(Clone, Copy, Debug)]
pub(super) struct Clusters {
    pub(super) radius: f64,
    /// The excess neighbours per instance `density · ∫ (h − 1) dA`: about the mean size of a cluster less one.
    pub(super) excess: f64,
}

impl Clusters {
    /// The clusters of a color whose self-pair rdf is `hist` (`angle_bins` per distance bin of `bin_width`) at
    /// `density` instances per unit area: the radius (at most `max_radius`) within which the rdf holds
    /// `CLUSTER_EXCESS_SHARE` of its excess neighbours; None when they are fewer than `CLUSTERED_EXCESS` (a
    /// Poisson, regular or hard-core color).
    pub(super) fn of_rdf(
        hist: &[f64],
        angle_bins: usize,
        bin_width: f64,
        density: f64,
        max_radius: f64,
    ) -> Option<Clusters> {
        let a = angle_bins.max(1);
        let bins = hist.len() / a;
        // excess neighbours out to the end of each distance bin
        let mut excess = Vec::with_capacity(bins);
        let mut total = 0.0;
        for k in 0..bins {
            let cell = std::f64::consts::PI * bin_width * bin_width * (2 * k + 1) as f64 / a as f64;
            total += hist[k * a..(k + 1) * a]
                .iter()
                .map(|h| (h - 1.0) * cell * density)
                .sum::<f64>();
            excess.push(total);
        }
        let most = excess.iter().copied().fold(0.0, f64::max);
        if !(most >= CLUSTERED_EXCESS) || !most.is_finite() {
            return None;
        }
        let k = excess
            .iter()
            .position(|e| *e >= CLUSTER_EXCESS_SHARE * most)
            .unwrap_or(bins.saturating_sub(1));
        let radius = ((k + 1) as f64 * bin_width).min(max_radius);
        (radius > 0.0).then_some(Clusters {
            radius,
            excess: most,
        })
    }

    /// The share of a cluster's instances that start it: one per mean cluster size.
    pub(super) fn seed_share(&self) -> f64 {
        1.0 / (1.0 + self.excess)
    }

    /// An offset from the first instance of a cluster for another of its instances: uniform in the disc whose
    /// pairs lie within the clusters' radius nine times in ten, as the clusters' excess pairs do.
    pub(super) fn offset_from_seed<R: Rng>(&self, rng: &mut R) -> DVec2 {
        let r = self.radius / DISC_PAIR_DISTANCE_90 * rng.random::<f64>().sqrt();
        let a = std::f64::consts::TAU * rng.random::<f64>();
        DVec2::new(r * a.cos(), r * a.sin())
    }
}

/// A birth in the region: drawn from `proposal` (over the region's box) until one lands inside — its density
/// there is `g` over the share of `g` inside, a constant that cancels in the Hastings ratio — or uniformly
/// without one; None when a thousand draws miss the region.
pub(super) fn birth_in<R: Rng>(
    region: &PreparedRegion,
    proposal: Option<&RectProposal>,
    rng: &mut R,
) -> Option<DVec2> {
    let Some(b) = proposal else {
        return region.sample_uniform(rng);
    };
    (0..1000)
        .map(|_| b.sample(rng))
        .find(|p| region.contains(*p))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// A lattice over 0..100 × 0..50, `ψ` 4 on the right half and 1 on the left.
    fn half_and_half() -> BirthIntensity {
        let lattice: Vec<DVec2> = (0..100)
            .flat_map(|i| (0..50).map(move |j| DVec2::new(i as f64 + 0.5, j as f64 + 0.5)))
            .collect();
        let psi = |i: usize| if lattice[i].x > 50.0 { 4.0 } else { 1.0 };
        match BirthIntensity::new(&lattice, psi, (DVec2::ZERO, DVec2::new(100.0, 50.0))) {
            Some(b) => b,
            None => panic!("the intensity is positive"),
        }
    }

    #[test]
    fn births_land_in_proportion_to_the_intensity() {
        let b = half_and_half();
        // a rectangle across the step, not aligned with the grid's cells
        let (lo, hi) = (DVec2::new(20.3, 3.1), DVec2::new(70.7, 41.9));
        let prop = b.over(lo, hi);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let n = 200_000;
        let right = (0..n)
            .map(|_| prop.sample(&mut rng))
            .inspect(|p| assert!(p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y))
            .filter(|p| p.x > 50.0)
            .count() as f64
            / n as f64;
        // areas 29.7 (ψ 1) and 20.7 (ψ 4)
        let (a, b_) = (29.7, 20.7);
        let want = 4.0 * b_ / (a + 4.0 * b_);
        assert!((right - want).abs() < 0.005, "{right} vs {want}");
        // the log weights are those of λ, whatever the rectangle
        let log_ratio = b.log_weight(DVec2::new(60.0, 10.0)) - b.log_weight(DVec2::new(40.0, 10.0));
        assert!((log_ratio - 4f64.ln()).abs() < 1e-12, "{log_ratio}");
    }

    #[test]
    fn where_the_maps_allow_nothing_births_keep_a_floor() {
        let lattice: Vec<DVec2> = (0..100)
            .flat_map(|i| (0..50).map(move |j| DVec2::new(i as f64 + 0.5, j as f64 + 0.5)))
            .collect();
        // ψ = 2 on a tenth of the region, 0 elsewhere: the floor is a tenth of the mean, 0.02
        let b = match BirthIntensity::new(
            &lattice,
            |i| if lattice[i].x < 10.0 { 2.0 } else { 0.0 },
            (DVec2::ZERO, DVec2::new(100.0, 50.0)),
        ) {
            Some(b) => b,
            None => panic!("the intensity is positive"),
        };
        let ratio =
            (b.log_weight(DVec2::new(5.0, 5.0)) - b.log_weight(DVec2::new(50.0, 5.0))).exp();
        assert!((ratio - 100.0).abs() < 1e-9, "{ratio}");
        let prop = b.over(DVec2::ZERO, DVec2::new(100.0, 50.0));
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        let n = 100_000;
        let inside = (0..n).filter(|_| prop.sample(&mut rng).x < 10.0).count() as f64 / n as f64;
        // weights 2 × 10 against 0.02 × 90
        let want = 20.0 / (20.0 + 1.8);
        assert!((inside - want).abs() < 0.005, "{inside} vs {want}");
    }

    #[test]
    fn clusters_are_read_off_a_thomas_rdf_and_started_with_its_spread() {
        // Thomas process: h(r) = 1 + A exp(−r² / 4σ²), whose excess neighbours are ρ A 4πσ², nine tenths of them
        // within 2σ √ln 10
        let (sigma, amplitude, density, bin) = (2.0, 5.0, 0.05, 0.1);
        let hist: Vec<f64> = (0..300)
            .map(|k| {
                let r = (k as f64 + 0.5) * bin;
                1.0 + amplitude * (-r * r / (4.0 * sigma * sigma)).exp()
            })
            .collect();
        let c = match Clusters::of_rdf(&hist, 1, bin, density, 100.0) {
            Some(c) => c,
            None => panic!("a Thomas rdf is clustered"),
        };
        let excess = density * amplitude * 4.0 * std::f64::consts::PI * sigma * sigma;
        assert!(
            (c.excess / excess - 1.0).abs() < 0.01,
            "{} vs {excess}",
            c.excess
        );
        let radius = 2.0 * sigma * 10f64.ln().sqrt();
        assert!((c.radius - radius).abs() <= bin, "{} vs {radius}", c.radius);
        // pairs of the start's offsets lie within the radius nine times in ten
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let n = 100_000;
        let within = (0..n)
            .filter(|_| {
                (c.offset_from_seed(&mut rng) - c.offset_from_seed(&mut rng)).length() < c.radius
            })
            .count() as f64
            / n as f64;
        assert!((within - 0.9).abs() < 0.01, "{within}");
        // a Poisson rdf, a hard core: no clusters
        assert!(Clusters::of_rdf(&[1.0; 300], 1, bin, density, 100.0).is_none());
        let hard_core: Vec<f64> = (0..300).map(|k| if k < 20 { 0.0 } else { 1.0 }).collect();
        assert!(Clusters::of_rdf(&hard_core, 1, bin, density, 100.0).is_none());
    }

    #[test]
    fn no_intensity_anywhere_gives_no_proposal() {
        let lattice = vec![DVec2::new(1.0, 1.0), DVec2::new(2.0, 2.0)];
        assert!(BirthIntensity::new(&lattice, |_| 0.0, (DVec2::ZERO, DVec2::splat(3.0))).is_none());
    }
}

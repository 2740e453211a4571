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
//! (and the birth half of a relocation, and each dart of the start) is drawn from `λ` instead, so content is
//! born — and clusters start and grow — where the terrain says, rather than where a uniform draw happens to land
//! and the chain must then move it away from.
//!
//! **The acceptance.** A Metropolis-Hastings move proposed from a density `g` is accepted with
//! `f(X') / f(X) · g(x_old) / g(x_new)` (Hastings 1970): the proposal density of the reverse move over the
//! forward one. With `g = 1/A` this is the paper's ratio; with `g ∝ λ` the map factor `ψ(q)/ψ(p)` of the target
//! is largely paid back by the proposal, and the chain's stationary distribution is exactly the one it had with
//! uniform proposals: the proposals only change how fast it gets there (see the module documentation of
//! [`super`] for the target itself).
//!
//! **The proposal density.** `λ` is read as the mean of `Π_m ψ_m` over the lattice points of each cell of a grid
//! (about four lattice points a cell, at most `MAX_CELLS` cells) and held constant over the cell; a proposal over
//! a rectangle (a tile of the rdf-matching chain, or the region's box) draws with probability
//! `1 − UNIFORM_SHARE` a cell by `λ_c · |cell ∩ rectangle|` and a point uniformly in that part of the cell, and
//! otherwise a point uniformly in the rectangle:
//!
//! ```text
//! g(x) = (1 − ε) λ_c(x) / Σ_c λ_c |c ∩ R|  +  ε / |R|
//! ```
//!
//! The uniform share keeps `g` positive everywhere, so an instance that stands where the grid reads no intensity
//! (a cell whose lattice points all lie where `ψ = 0`, a sliver of the region no lattice point falls in) can
//! still be relocated: with `g(x_old) = 0` the ratio would hold it there forever.
//!
//! Colors without maps keep the uniform proposals (and the random streams) they had.

use crate::geom::{DVec2, PreparedRegion, RegionQueries};
use crate::grid::Grid;
use rand::Rng;

/// Most cells of the intensity grid.
const MAX_CELLS: f64 = 65_536.0;
/// Lattice points per cell of the intensity grid, about.
const LATTICE_POINTS_PER_CELL: f64 = 4.0;
/// Share of the proposals drawn uniformly over the rectangle (ε above).
const UNIFORM_SHARE: f64 = 0.1;

/// The map-weighted intensity `λ` of one category over the painted region, constant per grid cell.
pub(super) struct BirthIntensity {
    grid: Grid,
    /// `λ` per cell (row-major), 0 where no lattice point fell.
    lambda: Vec<f64>,
}

impl BirthIntensity {
    /// `λ` from `log_psi`, `ln Π_m ψ_m` at each point of `lattice` (the region's sample points, about `spacing`
    /// apart), over the box `bounds`. None when `λ` vanishes everywhere (the chain then finds no allowed place
    /// anyway, and uniform proposals say so as well as any).
    pub(super) fn new(
        lattice: &[DVec2],
        log_psi: impl Fn(usize) -> f64,
        bounds: (DVec2, DVec2),
    ) -> Option<Self> {
        let (lo, hi) = bounds;
        let ext = (hi - lo).max(DVec2::splat(1e-9));
        let area = ext.x * ext.y;
        let cell = (LATTICE_POINTS_PER_CELL * area / lattice.len().max(1) as f64)
            .sqrt()
            .max((area / MAX_CELLS).sqrt());
        let grid = Grid::buckets_covering(lo, hi, cell);
        let mut sum = vec![0.0; grid.nx * grid.ny];
        let mut count = vec![0u32; grid.nx * grid.ny];
        for (i, p) in lattice.iter().enumerate() {
            let (cx, cy) = grid.bucket_of(*p);
            let k = cy * grid.nx + cx;
            let psi = log_psi(i).exp();
            if psi.is_finite() {
                sum[k] += psi;
            }
            count[k] += 1;
        }
        let lambda: Vec<f64> = sum
            .iter()
            .zip(&count)
            .map(|(s, n)| if *n > 0 { s / *n as f64 } else { 0.0 })
            .collect();
        lambda
            .iter()
            .any(|l| *l > 0.0)
            .then_some(BirthIntensity { grid, lambda })
    }

    /// The proposal over the rectangle `lo..hi` (see "The proposal density").
    pub(super) fn over(&self, lo: DVec2, hi: DVec2) -> RectProposal<'_> {
        let g = &self.grid;
        let hi = hi.max(lo);
        let (x0, y0) = g.bucket_of(lo);
        let (x1, y1) = g.bucket_of(hi);
        let (nx, ny) = (x1 - x0 + 1, y1 - y0 + 1);
        let mut cdf = Vec::with_capacity(nx * ny);
        let mut total = 0.0;
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                let (clo, chi) = self.clipped_cell(cx, cy, lo, hi);
                let part = (chi - clo).max(DVec2::ZERO);
                total += self.lambda[cy * g.nx + cx] * part.x * part.y;
                cdf.push(total);
            }
        }
        let ext = hi - lo;
        let area = ext.x * ext.y;
        // ln g per cell of the rectangle: the same over a whole cell, clipped or not
        let log_density = (y0..=y1)
            .flat_map(|cy| (x0..=x1).map(move |cx| (cx, cy)))
            .map(|(cx, cy)| {
                let drawn = if total > 0.0 {
                    (1.0 - UNIFORM_SHARE) * self.lambda[cy * g.nx + cx] / total
                } else {
                    0.0
                };
                let uniform = if total > 0.0 { UNIFORM_SHARE } else { 1.0 };
                (drawn + uniform / area.max(1e-300)).ln()
            })
            .collect();
        RectProposal {
            intensity: self,
            lo,
            hi,
            x0,
            y0,
            nx,
            ny,
            cdf,
            log_density,
        }
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

/// Births proposed over one rectangle from a [`BirthIntensity`], with their density.
pub(super) struct RectProposal<'a> {
    intensity: &'a BirthIntensity,
    lo: DVec2,
    hi: DVec2,
    /// The grid cells of the rectangle: from `(x0, y0)`, `nx × ny` of them.
    x0: usize,
    y0: usize,
    nx: usize,
    ny: usize,
    /// Cumulative `λ_c |c ∩ R|` over the cells, row-major.
    cdf: Vec<f64>,
    /// `ln g` per cell.
    log_density: Vec<f64>,
}

impl RectProposal<'_> {
    /// A point drawn from `g` (see "The proposal density").
    pub(super) fn sample<R: Rng>(&self, rng: &mut R) -> DVec2 {
        let total = self.cdf.last().copied().unwrap_or(0.0);
        let (lo, hi) = if total > 0.0 && rng.random::<f64>() >= UNIFORM_SHARE {
            let t = rng.random::<f64>() * total;
            let k = self
                .cdf
                .partition_point(|c| *c <= t)
                .min(self.cdf.len() - 1);
            let (cx, cy) = (self.x0 + k % self.nx, self.y0 + k / self.nx);
            self.intensity.clipped_cell(cx, cy, self.lo, self.hi)
        } else {
            (self.lo, self.hi)
        };
        DVec2::new(
            lo.x + rng.random::<f64>() * (hi.x - lo.x),
            lo.y + rng.random::<f64>() * (hi.y - lo.y),
        )
    }

    /// `ln g(p)` for a point of the rectangle.
    #[inline]
    pub(super) fn log_density(&self, p: DVec2) -> f64 {
        let (cx, cy) = self.intensity.grid.bucket_of(p);
        let i = cx.saturating_sub(self.x0).min(self.nx - 1);
        let j = cy.saturating_sub(self.y0).min(self.ny - 1);
        self.log_density[j * self.nx + i]
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
        let log_psi = |i: usize| if lattice[i].x > 50.0 { 4f64.ln() } else { 0.0 };
        match BirthIntensity::new(&lattice, log_psi, (DVec2::ZERO, DVec2::new(100.0, 50.0))) {
            Some(b) => b,
            None => panic!("the intensity is positive"),
        }
    }

    #[test]
    fn births_land_in_proportion_to_the_intensity_and_the_density_integrates_to_one() {
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
        // areas 29.7 (ψ 1) and 20.7 (ψ 4): (1 − ε) 82.8 / 112.5 + ε 20.7 / 50.4
        let (a, b_) = (29.7, 20.7);
        let want =
            (1.0 - UNIFORM_SHARE) * 4.0 * b_ / (a + 4.0 * b_) + UNIFORM_SHARE * b_ / (a + b_);
        assert!((right - want).abs() < 0.005, "{right} vs {want}");
        // ∫ g over the rectangle = 1 (midpoint sums on a fine lattice)
        let step = 0.1;
        let mut integral = 0.0;
        let mut y = lo.y + 0.5 * step;
        while y < hi.y {
            let mut x = lo.x + 0.5 * step;
            while x < hi.x {
                integral += prop.log_density(DVec2::new(x, y)).exp() * step * step;
                x += step;
            }
            y += step;
        }
        assert!((integral - 1.0).abs() < 0.01, "∫ g = {integral}");
    }

    #[test]
    fn no_intensity_anywhere_gives_no_proposal() {
        let lattice = vec![DVec2::new(1.0, 1.0), DVec2::new(2.0, 2.0)];
        assert!(BirthIntensity::new(
            &lattice,
            |_| f64::NEG_INFINITY,
            (DVec2::ZERO, DVec2::splat(3.0))
        )
        .is_none());
    }
}

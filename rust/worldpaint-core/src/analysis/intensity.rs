//! How much a map preference alone correlates pairs: the pair correlation of an intensity over a region,
//!
//! ```text
//! c(r) = E_x[ ψ(x) · E_{y ∈ C(x, r) ∩ W}[ψ(y)] ] / E_x[ψ(x)]²
//! ```
//!
//! with `ψ` the product of the map factors and `W` the region. It is what the window-corrected rdf of eq. (2)
//! reads on a Poisson process whose intensity follows `ψ` and nothing else: 1 where the maps are uniform, the
//! inverse of the share they allow at `r = 0` when they allow a part of the region evenly, falling back to 1 over
//! the distance at which the maps change. The rdf of points that follow the maps *and* cluster is `c(r)` times
//! their inhomogeneous pcf (Baddeley, Møller and Waagepetersen 2000), so the analysis divides `c` out before it
//! decides how far the points are clustered: a slope preference is not read as clustering.
//!
//! `ψ` is read once on a grid of at most `MAX_CELLS` cells over the region, and every cell is paired with the
//! cells `r` away in `DIRECTIONS` evenly spaced directions (grid lookups): all the region counts, so a spiky
//! preference learned from a few instances gives the same `c` on two regions that hold the same map values.

use crate::geom::DVec2;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Most cells of the grid `ψ` is read on.
const MAX_CELLS: f64 = 40_000.0;
/// Directions each cell is paired in.
const DIRECTIONS: usize = 8;

/// `ψ` on a grid over a region: `None` outside the region or off the maps.
struct Field {
    values: Vec<Option<f64>>,
    nx: usize,
    ny: usize,
    step: f64,
}

impl Field {
    fn read<F>(psi: &F, contains: &(impl Fn(DVec2) -> bool + Sync), bounds: (DVec2, DVec2)) -> Field
    where
        F: Fn(DVec2) -> Option<f64> + Sync,
    {
        let (lo, hi) = bounds;
        let ext = (hi - lo).max(DVec2::splat(1e-9));
        let step = (ext.x * ext.y / MAX_CELLS).sqrt().max(1e-9);
        let nx = ((ext.x / step).ceil() as usize).max(1);
        let ny = ((ext.y / step).ceil() as usize).max(1);
        let values = (0..nx * ny)
            .into_par_iter()
            .map(|k| {
                let p = lo + DVec2::new((k % nx) as f64 + 0.5, (k / nx) as f64 + 0.5) * step;
                if contains(p) {
                    psi(p)
                } else {
                    None
                }
            })
            .collect();
        Field {
            values,
            nx,
            ny,
            step,
        }
    }

    fn at(&self, i: isize, j: isize) -> Option<f64> {
        if i < 0 || j < 0 || i as usize >= self.nx || j as usize >= self.ny {
            return None;
        }
        self.values[j as usize * self.nx + i as usize]
    }

    /// `c` at radius `r`, over the field's mean `mean`.
    fn correlation(&self, r: f64, mean: f64) -> f64 {
        let offsets: Vec<(isize, isize)> = (0..DIRECTIONS)
            .map(|d| {
                let a = TAU * d as f64 / DIRECTIONS as f64;
                let v = r * DVec2::new(a.cos(), a.sin()) / self.step;
                (v.x.round() as isize, v.y.round() as isize)
            })
            .collect();
        let (mut sum, mut weight) = (0.0, 0.0);
        for j in 0..self.ny as isize {
            for i in 0..self.nx as isize {
                let Some(px) = self.at(i, j) else { continue };
                let (mut s, mut m) = (0.0, 0usize);
                for (di, dj) in &offsets {
                    if let Some(py) = self.at(i + di, j + dj) {
                        s += py;
                        m += 1;
                    }
                }
                if m > 0 {
                    sum += px * s / m as f64;
                    weight += 1.0;
                }
            }
        }
        if weight > 0.0 {
            sum / weight / (mean * mean)
        } else {
            1.0
        }
    }
}

/// `c(r)` at the middle of `n_bins` distance bins of width `bin_width` over the region in `bounds` whose points
/// `contains` tells; `psi` is the intensity factor at a point (None off the maps). All ones when `ψ` vanishes.
pub(crate) fn intensity_pair_correlation<F>(
    psi: F,
    contains: impl Fn(DVec2) -> bool + Sync,
    bounds: (DVec2, DVec2),
    bin_width: f64,
    n_bins: usize,
) -> Vec<f64>
where
    F: Fn(DVec2) -> Option<f64> + Sync,
{
    let field = Field::read(&psi, &contains, bounds);
    let read: Vec<f64> = field.values.iter().flatten().copied().collect();
    let mean = read.iter().sum::<f64>() / read.len().max(1) as f64;
    if !(mean > 0.0) || !mean.is_finite() || n_bins == 0 {
        return vec![1.0; n_bins];
    }
    (0..n_bins)
        .into_par_iter()
        .map(|k| field.correlation((k as f64 + 0.5) * bin_width, mean))
        .collect()
}

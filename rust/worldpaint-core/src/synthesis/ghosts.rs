//! Free borders: the neighbours a region's content would have beyond its border where nothing stands yet.
//!
//! A chain confined to a region with nothing around it crowds the border, as hard disks crowd a wall: an instance
//! there is excluded by neighbours on one side only (measured on a hard-core color of 0.04 per m², 3 m: 1.30 × the
//! density in the outer 2 m, 0.86 × in the next 2 m, whether pasted or brushed). A pasted patch then shows a dense
//! outline, and a brush stroke an arc of instances along the leading edge of every dab.
//!
//! Where the region of influence holds content, that content supplies the neighbours. Where it holds none (a
//! *free* direction), the missing neighbours are integrated out to first order, as a Poisson field of the other
//! category's density `ρ`: an instance at `x` is excluded by them with probability `1 − exp(−ρ |A(x)|)`, where
//! `A(x)` is the part of the pair's hard-core disc around `x` that is free — outside the region and farther than
//! one mean spacing of that category from any content of it. Its log-density therefore gains
//! `−κ Σ_pairs ρ |A(x)|`. The first-order field ignores that the missing neighbours exclude each other as well,
//! which weighs more the denser they pack: the gain `κ = 1 + 2.5 η` (`η = ρ π d² / 4`, the packing fraction of
//! the hard-core discs of diameter `d`) makes up for it, calibrated on hard-core colors of 0.02 to 0.06 per m²
//! (3 m) in both chains (figures in `tests/borders.rs`: the outer 2 m hold 0.95 to 1.09 × the density, but for the
//! densest color with the rdf-matching chain, 1.25 ×). Only the hard core is integrated: the attraction of clusters
//! saturates in the product model, and the rdf beyond the core is too noisy in a small exemplar to integrate.

use crate::geom::{DVec2, PreparedRegion, RegionQueries};
use crate::spatial::SpatialGrid;
use std::f64::consts::TAU;

/// Gain of the first-order field at packing fraction `η` of the hard-core discs (see the module documentation).
fn ghost_gain(packing: f64) -> f64 {
    1.0 + 2.5 * packing
}

/// Directions sampled on each circle.
const DIRECTIONS: usize = 16;

/// Where the content of one other category stands, on a raster: cells within one of its mean spacings of it.
struct Occupancy {
    origin: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    occupied: Vec<bool>,
}

impl Occupancy {
    fn new(lo: DVec2, hi: DVec2, spacing: f64, points: &[DVec2]) -> Occupancy {
        let cell = (0.5 * spacing).max(1e-6);
        let nx = (((hi.x - lo.x) / cell).ceil() as usize + 1).clamp(1, 4096);
        let ny = (((hi.y - lo.y) / cell).ceil() as usize + 1).clamp(1, 4096);
        let cell = cell
            .max((hi.x - lo.x) / nx as f64)
            .max((hi.y - lo.y) / ny as f64);
        let mut occupied = vec![false; nx * ny];
        let reach = (spacing / cell).ceil() as i64;
        for p in points {
            let (ci, cj) = (
                ((p.x - lo.x) / cell).floor() as i64,
                ((p.y - lo.y) / cell).floor() as i64,
            );
            for j in cj - reach..=cj + reach {
                for i in ci - reach..=ci + reach {
                    if i < 0 || j < 0 || i >= nx as i64 || j >= ny as i64 {
                        continue;
                    }
                    let centre = lo + DVec2::new((i as f64 + 0.5) * cell, (j as f64 + 0.5) * cell);
                    if centre.distance(*p) <= spacing + 0.71 * cell {
                        occupied[j as usize * nx + i as usize] = true;
                    }
                }
            }
        }
        Occupancy {
            origin: lo,
            cell,
            nx,
            ny,
            occupied,
        }
    }

    fn is_occupied(&self, p: DVec2) -> bool {
        let f = (p - self.origin) / self.cell;
        if !(f.x >= 0.0 && f.y >= 0.0) {
            return false;
        }
        let (i, j) = (f.x as usize, f.y as usize);
        i < self.nx && j < self.ny && self.occupied[j * self.nx + i]
    }
}

/// The ghost neighbours of one pair: rings of its hard-core disc, and where its other category stands.
struct PairGhosts {
    /// (ring radius, weight `−κ ρ · |ring|`).
    rings: Vec<(f64, f64)>,
    occupancy: Occupancy,
}

/// The free-border term of one category's chain (see the module documentation).
pub(super) struct Ghosts<'r> {
    region: &'r PreparedRegion<'r>,
    pairs: Vec<PairGhosts>,
    reach: f64,
    directions: [DVec2; DIRECTIONS],
}

/// What `Ghosts::new` needs of one pair table: its hard-core radius, the other category's density, and where that
/// category's content stands.
pub(super) struct PairInput<'a> {
    pub(super) core: f64,
    pub(super) density: f64,
    pub(super) points: &'a [DVec2],
}

/// Rings the hard-core disc is cut into (each sampled on its middle circle).
const CORE_RINGS: usize = 3;

impl<'r> Ghosts<'r> {
    /// The term for a chain in `region` with the given pairs; the rasters cover `bounds`.
    pub(super) fn new(
        region: &'r PreparedRegion<'r>,
        bounds: (DVec2, DVec2),
        pairs: &[PairInput],
    ) -> Ghosts<'r> {
        let mut reach: f64 = 0.0;
        let pairs = pairs
            .iter()
            .filter(|p| p.density > 0.0 && p.core > 0.0 && p.core.is_finite())
            .map(|p| {
                let rings = (0..CORE_RINGS)
                    .map(|j| {
                        let (r0, r1) = (
                            p.core * j as f64 / CORE_RINGS as f64,
                            p.core * (j + 1) as f64 / CORE_RINGS as f64,
                        );
                        let ring = std::f64::consts::PI * (r1 * r1 - r0 * r0);
                        let packing = p.density * std::f64::consts::PI * p.core * p.core / 4.0;
                        (0.5 * (r0 + r1), -ghost_gain(packing) * p.density * ring)
                    })
                    .collect();
                reach = reach.max(p.core);
                PairGhosts {
                    rings,
                    occupancy: Occupancy::new(bounds.0, bounds.1, 1.0 / p.density.sqrt(), p.points),
                }
            })
            .collect();
        let directions = std::array::from_fn(|j| {
            let a = TAU * (j as f64 + 0.5) / DIRECTIONS as f64;
            DVec2::new(a.cos(), a.sin())
        });
        Ghosts {
            region,
            pairs,
            reach,
            directions,
        }
    }

    /// The log-density an instance at `p` gains from the missing neighbours in the free directions (≤ 0).
    pub(super) fn log_factor(&self, p: DVec2) -> f64 {
        if self.region.covers_disc(p, self.reach) {
            return 0.0;
        }
        let mut sum = 0.0;
        for pair in &self.pairs {
            for &(r, w) in &pair.rings {
                let free = self
                    .directions
                    .iter()
                    .filter(|u| {
                        let y = p + **u * r;
                        !self.region.contains(y) && !pair.occupancy.is_occupied(y)
                    })
                    .count();
                sum += w * free as f64 / DIRECTIONS as f64;
            }
        }
        sum
    }
}

/// Positions of the grid's fixed entries per table tag (`tag & !context_tag`), for the pairs' occupancy.
pub(super) fn points_by_table(
    grid: &SpatialGrid,
    tables: usize,
    context_tag: u32,
) -> Vec<Vec<DVec2>> {
    let mut out = vec![Vec::new(); tables];
    for e in grid.entries() {
        if let Some(v) = out.get_mut((e.tag & !context_tag) as usize) {
            v.push(e.position);
        }
    }
    out
}

//! The estimators of Section 4.1: the window-edge correction α, the radial distribution function of eq. (2) (and
//! its oriented form), and the bins of map histograms (see the module documentation of `analysis`).

use super::{MAP_BINS, SLOPE_BIN_DEGREES};
use crate::geom::{circle_fraction, DVec2, PreparedRegion, RegionQueries};
use crate::palette::{Histogram, MapSource};
use crate::spatial::SpatialGrid;
use rayon::prelude::*;
use std::f64::consts::PI;

const ALPHA_FLOOR: f64 = 0.05;
/// Most bins of a distance map.
const DISTANCE_BINS: usize = 256;

/// Bins of a distance map: metres from 0 to twice the color's radius for graphs; for polygons `−1` (deep inside)
/// to 2 (two radii outside). Eight bins span the middle 90 % of the category's own values (at least
/// `span / DISTANCE_BINS` wide, at most a 32nd of the span for graphs and 0.125 for polygons), so a band of
/// distances is resolved without splitting a small exemplar into empty bins.
pub(super) fn distance_bins(source: MapSource, max_radius: f64, at: &[f64]) -> Histogram {
    let mut sorted: Vec<f64> = at.iter().copied().filter(|v| v.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    let quantile = |q: f64| {
        sorted
            .get((q * sorted.len() as f64) as usize)
            .copied()
            .unwrap_or(0.0)
    };
    let range = quantile(0.95) - quantile(0.05);
    let (start, span, coarsest) = match source {
        MapSource::PolygonDistance => (-1.0, 3.0, 0.125),
        _ => (0.0, 2.0 * max_radius, 2.0 * max_radius / 32.0),
    };
    let finest = span / DISTANCE_BINS as f64;
    let mut width = (range / 8.0).clamp(finest, coarsest.max(finest));
    if source == MapSource::PolygonDistance {
        // the coast is a bin edge: no bin holds both land and water
        width = 1.0 / (1.0 / width).ceil();
    }
    Histogram::zeros(start, width, (span / width).ceil() as usize)
}

/// α per distance bin for the point `p` (1 everywhere when the whole disc lies inside).
pub(crate) fn alphas(
    region: &impl RegionQueries,
    p: DVec2,
    bin_width: f64,
    n_bins: usize,
) -> Vec<f64> {
    let mut out = vec![1.0; n_bins];
    alphas_into(region, p, bin_width, &mut out);
    out
}

/// α per distance bin for the point `p`, as many bins as `out` holds, written into `out`; returns false (and
/// leaves `out` alone) when the whole disc of the bins lies inside the region (α = 1).
pub(crate) fn alphas_into(
    region: &impl RegionQueries,
    p: DVec2,
    bin_width: f64,
    out: &mut [f64],
) -> bool {
    // whether p is inside and how near the boundary comes are the same for every bin: asked once
    let reach = bin_width * out.len() as f64;
    let inside = region.contains(p);
    let near = region.distance_to_boundary_within(p, reach);
    if inside && near >= reach {
        return false;
    }
    for (k, a) in out.iter_mut().enumerate() {
        *a =
            circle_fraction(region, p, (k as f64 + 0.5) * bin_width, inside, near).max(ALPHA_FLOOR);
    }
    true
}

/// Window-corrected rdf of eq. (2) between `xs` and the points of `grid_y` (`ys`), each shell split into
/// `sectors` of the folded angle (one sector: the plain rdf), sector fastest.
#[allow(clippy::too_many_arguments)]
pub(crate) fn rdf(
    region: &PreparedRegion,
    area: f64,
    xs: &[DVec2],
    ys: &[DVec2],
    grid_y: &SpatialGrid,
    same: bool,
    bin_width: f64,
    n_bins: usize,
    sectors: usize,
) -> Vec<f64> {
    let na = sectors;
    let pairs_norm = xs.len() as f64 * (ys.len() as f64 - if same { 1.0 } else { 0.0 });
    let mut values = vec![0.0; n_bins * na];
    if pairs_norm <= 0.0 {
        return values;
    }
    let r_max = bin_width * n_bins as f64;
    // per-point contributions in parallel, summed in a fixed order (deterministic)
    let per_point: Vec<Vec<f64>> = xs
        .par_iter()
        .enumerate()
        .map(|(k, &p)| {
            let mut counts = vec![0.0; n_bins * na];
            grid_y.for_each_within(p, r_max, |e, d2| {
                if same && e.id == k as u32 {
                    return;
                }
                let b = (d2.sqrt() / bin_width) as usize;
                if b < n_bins {
                    // a single sector needs no angle
                    let sector = if na > 1 {
                        folded_angle_bin(e.position - p, na)
                    } else {
                        0
                    };
                    counts[b * na + sector] += 1.0;
                }
            });
            if counts.iter().any(|c| *c > 0.0) {
                let a = alphas(region, p, bin_width, n_bins);
                for (idx, c) in counts.iter_mut().enumerate() {
                    *c /= a[idx / na];
                }
            }
            counts
        })
        .collect();
    for counts in per_point {
        for (h, c) in values.iter_mut().zip(counts) {
            *h += c;
        }
    }
    for (idx, h) in values.iter_mut().enumerate() {
        let k = idx / na;
        let sector = PI * bin_width * bin_width * ((k + 1).pow(2) - k.pow(2)) as f64 / na as f64;
        *h *= area / (sector * pairs_norm);
    }
    values
}

/// Bin of the direction of `v` relative to world X, folded to [0, π).
#[inline]
pub(crate) fn folded_angle_bin(v: DVec2, angle_bins: usize) -> usize {
    let a = v.y.atan2(v.x).rem_euclid(PI);
    ((a / PI * angle_bins as f64) as usize).min(angle_bins - 1)
}

/// Bins of a map histogram: fixed 2.5° bins for "slope", else the values' range in `MAP_BINS` bins.
pub(super) fn map_bins(map: &str, values: &[f64]) -> Histogram {
    if map == "slope" {
        let w = SLOPE_BIN_DEGREES.to_radians();
        return Histogram::zeros(0.0, w, (90.0 / SLOPE_BIN_DEGREES) as usize + 1);
    }
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    if !(lo.is_finite() && hi.is_finite()) {
        return Histogram::zeros(0.0, 1.0, 1);
    }
    let span = (hi - lo).max(1e-6 * lo.abs().max(1.0));
    Histogram::zeros(lo, span * (1.0 + 1e-9) / MAP_BINS as f64, MAP_BINS)
}

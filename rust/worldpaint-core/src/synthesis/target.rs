//! What the chain of one category evaluates (Section 4.1, eq. (1) and the product simplification of Section 6):
//! the pair factors `h` of the category with itself and with every category of equal or higher priority present,
//! the map factors `ψ`, and a grid of the fixed content they apply to.

use super::ghosts::{points_by_table, Ghosts, PairInput};
use super::structures::StructuredContent;
use super::{HISTOGRAM_FLOOR, SATURATION_PAIRS};
use crate::analysis::folded_angle_bin;
use crate::analysis::structure::{
    graph_map_value, graph_map_values, polygon_map_value, polygon_map_values,
};
use crate::contour::Polygons;
use crate::geom::{DVec2, PreparedRegion};
use crate::graph::SegmentIndex;
use crate::palette::{Color, Histogram, Interaction, MapSource};
use crate::spatial::{GridEntry, SpatialGrid};
use crate::terrain::Heightfield;
use std::sync::Arc;

/// Id of fixed grid entries (content that does not move in the chain).
pub(super) const FIXED_ID: u32 = u32::MAX;
/// Tag bit of fixed content that conditions by product factors (the region of influence, locked content).
pub(super) const CONTEXT_TAG: u32 = 1 << 31;
/// A learned rdf bin differs from 1 when it is this many standard deviations of counting noise away.
const SIGNIFICANCE: f64 = 3.0;
/// The smallest mean excess of an rdf over one mean spacing that counts as clustering (see `CLUSTER_EXCESS` in
/// the analysis, which follows a clustered exemplar out as far).
const CLUSTER_EXCESS: f64 = crate::analysis::CLUSTER_EXCESS;

/// Log-factor table of one pair interaction, indexed by distance bin (× angle bin for an oriented rdf).
pub(super) struct PairTable {
    pub(super) log_factor: Vec<f64>,
    /// The learned histogram (the target of the rdf-matching energy).
    pub(super) target_hist: Vec<f64>,
    /// Points of the other category inside the region (fixed); `None` for the self pair (the chain's own).
    pub(super) others_inside: Option<usize>,
    /// The other category's density in the color.
    pub(super) other_density: f64,
    pub(super) angle_bins: usize,
    pub(super) bin_width: f64,
    /// `1 / bin_width`: a pair's bin is read millions of times, and a product is cheaper than a quotient.
    pub(super) inv_bin_width: f64,
    pub(super) n_bins: usize,
    pub(super) hard_core2: f64,
}

impl PairTable {
    pub(super) fn new(values: &[f64], angle_bins: usize, bin_width: f64, hard_core: f64) -> Self {
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
            other_density: 0.0,
            angle_bins,
            bin_width,
            inv_bin_width: 1.0 / bin_width,
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
    /// which the exemplar shows structure. Forbidden (hard-core) bins are kept, and for a color whose radius
    /// follows a clustered example (`spacing` given: its mean spacing), twice the range over which a clustered
    /// rdf stays clustered (see `clustered_range`). Colors within three spacings keep the cheaper cut: doubling
    /// their short clustered range made the 100k benchmark 2.2× slower.
    pub(super) fn truncate_to_significant(&mut self, pairs_per_area: f64, spacing: Option<f64>) {
        if !(pairs_per_area > 0.0) || !pairs_per_area.is_finite() {
            return;
        }
        let a = self.angle_bins.max(1);
        // clustered exemplars count pairs in clumps, far noisier than Poisson: the outer third of the bins
        // (beyond two mean spacings of the sparsest category, or beyond the clusters) measures that noise
        let outer = &self.target_hist[(2 * self.n_bins / 3) * a..];
        let outer_rms = if outer.is_empty() {
            0.0
        } else {
            (outer.iter().map(|h| (h - 1.0).powi(2)).sum::<f64>() / outer.len() as f64).sqrt()
        };
        let mut keep = match spacing {
            Some(spacing) => 2 * self.clustered_range(pairs_per_area, spacing),
            None => 0,
        };
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

    /// The distance bins over which the rdf stays clustered, read in blocks one mean spacing wide (`spacing`) as
    /// the analysis reads it (see `clustering_range` there): the blocks from the first on whose area-weighted
    /// mean excess over 1 is beyond `CLUSTER_EXCESS` and `SIGNIFICANCE` standard deviations of counting noise.
    /// The chain holds the rdf at 1 as far again beyond, or it would pay for the clusters' excess pairs (the
    /// count is fixed) with a ring of gaps right behind them.
    fn clustered_range(&self, pairs_per_area: f64, spacing: f64) -> usize {
        let a = self.angle_bins.max(1);
        let block = if spacing.is_finite() && spacing > 0.0 {
            ((spacing / self.bin_width).round() as usize).clamp(1, self.n_bins.max(1))
        } else {
            return 0;
        };
        let mut end = 0;
        for first in (0..self.n_bins).step_by(block) {
            let cells = first * a..((first + block).min(self.n_bins)) * a;
            let area: f64 = cells.clone().map(|i| self.cell_area(i)).sum();
            let mean = cells
                .clone()
                .map(|i| self.target_hist[i] * self.cell_area(i))
                .sum::<f64>()
                / area;
            let sigma = (mean.max(1.0) / (pairs_per_area * area).max(1e-12)).sqrt();
            if mean - 1.0 <= (SIGNIFICANCE * sigma).max(CLUSTER_EXCESS) {
                break;
            }
            end = cells.end / a;
        }
        end
    }

    /// Histogram index (distance bin × angle bin) and distance bin of a pair at offset `v`, `d2 = |v|²`.
    #[inline]
    pub(super) fn bin_of(&self, v: DVec2, d2: f64) -> Option<(usize, usize)> {
        let k = (d2.sqrt() * self.inv_bin_width) as usize;
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
    pub(super) fn cell_area(&self, idx: usize) -> f64 {
        let k = (idx / self.angle_bins.max(1)) as f64;
        std::f64::consts::PI * self.bin_width * self.bin_width * ((k + 1.0).powi(2) - k * k)
            / self.angle_bins.max(1) as f64
    }

    /// The distance within which [`Self::log_factor`] may forbid a pair (the hard core, or the bins below the
    /// first the example showed), a hair beyond it: no pair farther apart is forbidden.
    pub(super) fn forbidden_reach(&self) -> f64 {
        let a = self.angle_bins.max(1);
        let unseen = self
            .log_factor
            .iter()
            .rposition(|v| *v == f64::NEG_INFINITY)
            .map_or(0, |idx| idx / a + 1);
        (unseen as f64 * self.bin_width).max(self.hard_core2.sqrt()) * (1.0 + 1e-9)
    }

    #[inline]
    pub(super) fn log_factor(&self, v: DVec2, d2: f64) -> f64 {
        if d2 < self.hard_core2 {
            return f64::NEG_INFINITY;
        }
        let k = (d2.sqrt() * self.inv_bin_width) as usize;
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

/// Where a map reads its values: a terrain map, or the distance to a graph or to polygons (Section 4.1, thesis
/// 6.2.1) as the synthesis has them so far.
#[derive(Clone)]
pub(super) enum MapField<'a> {
    Terrain(&'a str),
    Graph(Arc<SegmentIndex>, f64),
    Polygons(Arc<Polygons>, f64),
}

/// `ln ψ` per bin of one map, with one more bin at each end for the values below and above the learned range.
pub(super) struct MapTable<'a> {
    /// The map's name in the color.
    pub(super) name: &'a str,
    pub(super) field: MapField<'a>,
    pub(super) hist: Histogram,
    /// Whether the exemplar's region showed each bin's values (see [`with_unseen_bins`]).
    pub(super) seen: Vec<bool>,
    /// [`concentration`] of this map's factor over the exemplar's region, from the histograms: `1 / Σ h² / q`.
    pub(super) learned_concentration: f64,
    /// Wanted distribution of the instances over the bins in the painted region (normalized; empty when
    /// unknown): what the map factors give over the region's lattice.
    pub(super) wanted: Vec<f64>,
}

impl<'a> MapTable<'a> {
    pub(super) fn new(name: &'a str, field: MapField<'a>, h: &Histogram, q: &Histogram) -> Self {
        let min_q = q
            .values
            .iter()
            .copied()
            .filter(|v| *v > 0.0)
            .fold(f64::INFINITY, f64::min);
        let centre = |k: usize| h.start + (k as f64 - 0.5) * h.bin_width;
        // bins 1..=n are the learned ones; 0 and n + 1 hold what lies below and above them
        let n = h.values.len();
        let learned = |k: usize| (1..=n).contains(&k);
        let hs: Vec<f64> = (0..n + 2)
            .map(|k| if learned(k) { h.values[k - 1] } else { 0.0 })
            .collect();
        let qs: Vec<f64> = (0..n + 2)
            .map(|k| {
                if learned(k) {
                    q.value_at(centre(k))
                } else {
                    0.0
                }
            })
            .collect();
        let seen: Vec<bool> = qs.iter().map(|v| *v > 0.0).collect();
        let mean_square: f64 = (0..n + 2)
            .filter(|&k| seen[k])
            .map(|k| hs[k] * hs[k] / qs[k])
            .sum();
        let values = (0..n + 2)
            .map(|k| {
                let hv = hs[k];
                if hv <= 0.0 {
                    return f64::NEG_INFINITY;
                }
                let qv = qs[k];
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
            name,
            field,
            hist: Histogram {
                start: h.start - h.bin_width,
                bin_width: h.bin_width,
                values: with_unseen_bins(values, &hs, &qs),
            },
            seen,
            learned_concentration: if mean_square > 0.0 && mean_square.is_finite() {
                1.0 / mean_square
            } else {
                1.0
            },
            wanted: Vec::new(),
        }
    }
}

impl MapField<'_> {
    /// The value at `p` of a structure's distance map (NaN for a terrain map, which [`MapTable::value`] reads).
    #[inline]
    fn structure_value(&self, p: DVec2) -> f64 {
        match self {
            MapField::Terrain(_) => f64::NAN,
            MapField::Graph(index, r) => graph_map_value(index, p, *r),
            MapField::Polygons(polygons, r) => polygon_map_value(polygons, p, *r),
        }
    }

    /// Whether both read the distance to the same structure, saturating alike.
    fn same_structure(&self, other: &MapField) -> bool {
        match (self, other) {
            (MapField::Graph(a, r), MapField::Graph(b, s)) => Arc::ptr_eq(a, b) && r == s,
            (MapField::Polygons(a, r), MapField::Polygons(b, s)) => Arc::ptr_eq(a, b) && r == s,
            _ => false,
        }
    }
}

impl MapTable<'_> {
    /// The map's value at `p` (None off the terrain).
    #[inline]
    pub(super) fn value(&self, terrain: Option<&Heightfield>, p: DVec2) -> Option<f64> {
        match &self.field {
            MapField::Terrain(name) => terrain?.map_at(name, p),
            structure => Some(structure.structure_value(p)),
        }
    }

    /// Bin of the map at `p`.
    #[inline]
    pub(super) fn bin_at(&self, terrain: Option<&Heightfield>, p: DVec2) -> Option<usize> {
        self.value(terrain, p).and_then(|v| self.bin_of(v))
    }

    pub(super) fn is_terrain(&self) -> bool {
        matches!(self.field, MapField::Terrain(_))
    }

    /// Bin of map value `v`; values beyond the learned range take the end bins (see [`with_unseen_bins`]).
    #[inline]
    pub(super) fn bin_of(&self, v: f64) -> Option<usize> {
        let last = self.hist.values.len().checked_sub(1)?;
        if !v.is_finite() || !(self.hist.bin_width > 0.0) {
            return None;
        }
        let f = ((v - self.hist.start) / self.hist.bin_width).floor();
        Some(f.clamp(0.0, last as f64) as usize)
    }
}

/// The share of the exemplar's region whose preference a value it never showed takes (see
/// [`with_unseen_bins`]).
const NEAREST_SHARE: f64 = 0.1;

/// The exemplar says nothing about map values its region never showed (a grove learned on flat ground knows
/// nothing of slopes; a forest learned between 300 and 400 m knows nothing of 600 m). Such a bin takes the
/// preference `Σh / Σq` of the nearest bins the region did show, enough of them to hold [`NEAREST_SHARE`] of its
/// area (so that a preference read on a few samples at the edge of the example does not decide alone), but never
/// more than the neutral 1: a flat exemplar is neutral to slope, a forest that avoided the steepest slopes it saw
/// avoids steeper ones too, and a forest that grew denser towards its highest ground is not extrapolated into
/// more content than the example's mean density above it. `h` and `q` are the instances' and the region's
/// histograms; `values` the learned `ln ψ`, kept where the region showed the bin.
fn with_unseen_bins(values: Vec<f64>, h: &[f64], q: &[f64]) -> Vec<f64> {
    let total: f64 = q.iter().filter(|v| **v > 0.0).sum();
    if !(total > 0.0) {
        return values;
    }
    let n = values.len();
    (0..n)
        .map(|k| {
            if q[k] > 0.0 {
                return values[k];
            }
            // the seen bins outwards from k, the lower first at equal distance
            let (mut hs, mut qs) = (0.0, 0.0);
            for d in 1..n {
                for j in [k.checked_sub(d), Some(k + d).filter(|j| *j < n)]
                    .into_iter()
                    .flatten()
                {
                    if q[j] > 0.0 && qs < NEAREST_SHARE * total {
                        hs += h[j].max(0.0);
                        qs += q[j];
                    }
                }
                if qs >= NEAREST_SHARE * total {
                    break;
                }
            }
            (hs / qs).min(1.0).ln()
        })
        .collect()
}

/// How concentrated the terrain maps make the intensity over `lattice`: `(mean ψ)² / mean ψ²` with `ψ` the
/// product of the terrain map factors, 1 where they are uniform and the share of the lattice they allow when
/// they allow a part of it evenly (the "effective area" of an inhomogeneous process, Baddeley, Møller and
/// Waagepetersen 2000). Distance maps are left out: they change as the synthesis adds content. 1 without terrain
/// maps or samples. `log_psi`: `ln ψ` at each sample.
pub(super) fn concentration(target: &Target, log_psi: impl Iterator<Item = f64>) -> f64 {
    if !target.maps.iter().any(|m| m.is_terrain()) {
        return 1.0;
    }
    let (sum, sum2, n) = log_psi.fold((0.0, 0.0, 0usize), |(s, s2, n), l| {
        let psi = l.exp();
        (s + psi, s2 + psi * psi, n + 1)
    });
    if n == 0 {
        return 1.0;
    }
    let n = n as f64;
    let kappa = (sum / n).powi(2) / (sum2 / n);
    if kappa.is_finite() && kappa > 0.0 {
        kappa
    } else {
        1.0
    }
}

/// [`concentration`] over the exemplar's region as its histograms give it, for a color learned on another
/// terrain: the product of the terrain maps' own (as if they were independent).
pub(super) fn learned_concentration(target: &Target) -> f64 {
    target
        .maps
        .iter()
        .filter(|m| m.is_terrain())
        .map(|m| m.learned_concentration)
        .product()
}

/// The bins each map reads over `lattice`, `bins[map][point]`: read once per category, as the expected count, the
/// unseen shares and the raking all use them (a distance map's reads are nearest-segment searches, whose values
/// `read` keeps for the next categories).
pub(super) fn lattice_bins(
    target: &Target,
    lattice: &[DVec2],
    read: &mut StructureValues,
) -> Vec<Vec<Option<usize>>> {
    use rayon::prelude::*;
    target
        .maps
        .iter()
        .map(|m| match read.values(&m.field, lattice) {
            Some(values) => values.par_iter().map(|v| m.bin_of(*v)).collect(),
            None => lattice
                .par_iter()
                .map(|p| m.bin_at(target.terrain, *p))
                .collect(),
        })
        .collect()
}

/// The values of the distance maps of structures over a synthesis's lattice, read once for all its categories:
/// the trees and the boats of an archipelago both read the distance to its islands, 40,000 nearest-segment
/// searches each. A structure the synthesis changes is a new one (its own `Arc`), so values are never stale.
#[derive(Default)]
pub(super) struct StructureValues {
    read: Vec<(MapField<'static>, Vec<f64>)>,
}

impl StructureValues {
    /// The values of `field` over `lattice` (None for a terrain map: cheap to read, and a million a lattice).
    fn values(&mut self, field: &MapField, lattice: &[DVec2]) -> Option<&[f64]> {
        let key = match field {
            MapField::Terrain(_) => return None,
            MapField::Graph(index, r) => MapField::Graph(index.clone(), *r),
            MapField::Polygons(polygons, r) => MapField::Polygons(polygons.clone(), *r),
        };
        let at = match self.read.iter().position(|(k, _)| k.same_structure(&key)) {
            Some(at) => at,
            None => {
                let values = match &key {
                    MapField::Graph(index, r) => graph_map_values(index, lattice, *r),
                    MapField::Polygons(polygons, r) => polygon_map_values(polygons, lattice, *r),
                    MapField::Terrain(_) => return None,
                };
                self.read.push((key, values));
                self.read.len() - 1
            }
        };
        Some(&self.read[at].1)
    }
}

/// `ln` of the map factors at lattice point `i` of `bins` (see [`lattice_bins`]), of the terrain maps only when
/// `terrain_only`: [`Target::maps_log`] read from the bins.
pub(super) fn lattice_log(
    target: &Target,
    bins: &[Vec<Option<usize>>],
    i: usize,
    terrain_only: bool,
) -> f64 {
    let mut sum = 0.0;
    for (m, b) in target.maps.iter().zip(bins) {
        if terrain_only && !m.is_terrain() {
            continue;
        }
        match b[i] {
            Some(k) => sum += m.hist.values[k],
            None => return f64::NEG_INFINITY,
        }
    }
    sum
}

/// The share of the painted region's lattice, read as `bins` (see [`lattice_bins`]), where each map reads a value
/// the exemplar's region never showed, by map name; maps with none are left out.
pub(super) fn unseen_shares(target: &Target, bins: &[Vec<Option<usize>>]) -> Vec<(String, f64)> {
    target
        .maps
        .iter()
        .zip(bins)
        .filter_map(|(m, b)| {
            let unseen = b.iter().filter(|b| b.is_some_and(|b| !m.seen[b])).count();
            (unseen > 0).then(|| (m.name.to_string(), unseen as f64 / b.len() as f64))
        })
        .collect()
}

/// Everything the chain of one category evaluates.
pub(super) struct Target<'a> {
    pub(super) grid: SpatialGrid,
    pub(super) tables: Vec<PairTable>,
    pub(super) maps: Vec<MapTable<'a>>,
    pub(super) terrain: Option<&'a Heightfield>,
    pub(super) radius: f64,
    /// Upper bound of a point's total log pair factor (saturation, see the module documentation).
    pub(super) saturation: f64,
    /// Distance bin of the color (window-edge fractions are taken per distance bin).
    pub(super) bin_width: f64,
    /// Cell size of the spatial grids.
    pub(super) cell: f64,
    /// The missing neighbours beyond the region's free borders (see [`super::ghosts`]).
    pub(super) ghosts: Option<Ghosts<'a>>,
}

impl<'a> Target<'a> {
    pub(super) fn map_log(&self, p: DVec2) -> f64 {
        self.maps_log(p, false)
    }

    /// `ln` of the map factors at `p`, of the terrain maps only when `terrain_only`.
    pub(super) fn maps_log(&self, p: DVec2, terrain_only: bool) -> f64 {
        let mut sum = 0.0;
        for m in self.maps.iter().filter(|m| !terrain_only || m.is_terrain()) {
            match m.bin_at(self.terrain, p) {
                Some(k) => sum += m.hist.values[k],
                None => return f64::NEG_INFINITY,
            }
        }
        sum
    }

    /// `ln` of the product of all factors involving a point at `p` (skipping the grid entry `skip`).
    #[inline]
    pub(super) fn energy(&self, p: DVec2, skip: u32) -> f64 {
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
        m + pairs.min(self.saturation) + self.ghost_log(p)
    }

    /// The free-border term at `p` (0 without ghosts).
    #[inline]
    /// Whether the rdf-matching chain has nothing to match: every pair table holds only forbidden (hard-core)
    /// bins and no map has a wanted distribution. Its moves would then only trade one arrangement that keeps the
    /// hard cores for another, and the dart throwing that starts it is already one.
    pub(super) fn matches_nothing(&self) -> bool {
        self.tables
            .iter()
            .all(|t| t.log_factor.iter().all(|v| *v == f64::NEG_INFINITY))
            && self.maps.iter().all(|m| m.wanted.is_empty())
    }

    pub(super) fn ghost_log(&self, p: DVec2) -> f64 {
        self.ghosts.as_ref().map_or(0.0, |g| g.log_factor(p))
    }

    /// Adds the free-border term of `region` to the chain (see [`super::ghosts`]).
    pub(super) fn add_ghosts(&mut self, region: &'a PreparedRegion<'a>, bounds: (DVec2, DVec2)) {
        let points = points_by_table(&self.grid, self.tables.len(), CONTEXT_TAG);
        let inputs: Vec<PairInput> = self
            .tables
            .iter()
            .zip(&points)
            .map(|(t, pts)| {
                let a = t.angle_bins.max(1);
                // forbidden distance bins, then the hard core of the category's own pairs
                let seen = (0..t.n_bins)
                    .find(|&k| {
                        t.log_factor[k * a..(k + 1) * a]
                            .iter()
                            .any(|v| v.is_finite())
                    })
                    .unwrap_or(t.n_bins);
                PairInput {
                    core: (seen as f64 * t.bin_width).max(t.hard_core2.sqrt()),
                    density: t.other_density,
                    points: pts,
                }
            })
            .collect();
        self.ghosts = Some(Ghosts::new(region, bounds, &inputs));
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
pub(super) fn rake_maps(target: &mut Target, bins: &[Vec<Option<usize>>]) {
    let points = bins.first().map_or(0, Vec::len);
    let marginals = |maps: &[MapTable], only: Option<usize>| -> Vec<Vec<f64>> {
        let mut out: Vec<Vec<f64>> = maps
            .iter()
            .map(|m| vec![0.0; m.hist.values.len()])
            .collect();
        for i in 0..points {
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

/// What conditions the chain of one category, per color category: the content synthesized inside the region in
/// this call (window-corrected pairs in the rdf-matching chain) and the fixed content that conditions by product
/// factors (the region of influence, locked content inside the region).
pub(super) struct Conditioning<'c> {
    pub(super) inside: &'c [Option<Vec<DVec2>>],
    pub(super) context: &'c [Vec<DVec2>],
}

/// The target of the chain of color category `ci`: the self pair and a pair with every category present in
/// `cond`, the category's map factors, and a grid over `bounds` of the fixed content. Returns it with the tag of
/// the self pair.
pub(super) fn build_target<'a>(
    color: &'a Color,
    ci: usize,
    cond: &Conditioning,
    structures: &StructuredContent,
    terrain: Option<&'a Heightfield>,
    bounds: (DVec2, DVec2),
    area: f64,
) -> (Target<'a>, u32) {
    let cat = &color.categories[ci];
    let (tables, fixed_entries, self_tag) = pair_tables(color, ci, cond);
    let maps = map_tables(color, &cat.category.name, structures);
    let radius = interaction_radius(&tables, cat.min_distance, color.bin_width);
    // grid cells: the radius, but not much finer than the mean spacing of the content
    let spacing = (area / (cat.density * area + fixed_entries.len() as f64).max(1.0)).sqrt();
    let cell = radius.max(spacing);
    let mut grid = SpatialGrid::new(bounds.0, bounds.1, cell);
    for e in fixed_entries {
        grid.insert(e);
    }
    let saturation = saturation(&tables);
    let target = Target {
        grid,
        tables,
        maps,
        terrain,
        radius,
        saturation,
        bin_width: color.bin_width,
        cell,
        ghosts: None,
    };
    (target, self_tag)
}

/// The pair tables of color category `ci` (the self pair, then one per category present in `cond`), the fixed
/// content they apply to as grid entries, and the tag of the self pair (an empty table when the color has none).
fn pair_tables(
    color: &Color,
    ci: usize,
    cond: &Conditioning,
) -> (Vec<PairTable>, Vec<GridEntry>, u32) {
    let cat = &color.categories[ci];
    let mut tables = Vec::new();
    let mut fixed_entries: Vec<GridEntry> = Vec::new();
    let mut self_tag = None;
    for oi in 0..color.categories.len() {
        let same = oi == ci;
        if !same && cond.inside[oi].is_none() && cond.context[oi].is_empty() {
            continue;
        }
        let Some(table) = pair_table(color, ci, oi, cond) else {
            continue;
        };
        let tag = tables.len() as u32;
        // a pair whose rdf was 1 at every distance leaves the other category out: its points would cost every
        // move a neighbour search and change nothing
        let interacts = table.n_bins > 0 || table.hard_core2 > 0.0;
        tables.push(table);
        if same {
            self_tag = Some(tag);
        }
        if interacts {
            push_fixed_entries(&mut fixed_entries, cond, oi, tag);
        }
    }
    let self_tag = match self_tag {
        Some(t) => t,
        None => {
            tables.push(PairTable::new(&[], 1, color.bin_width, cat.min_distance));
            (tables.len() - 1) as u32
        }
    };
    (tables, fixed_entries, self_tag)
}

/// The pair table of color category `ci` with category `oi` (the oriented rdf when the color has both kinds),
/// cut to its significant range; None when the color learned no such pair.
fn pair_table(color: &Color, ci: usize, oi: usize, cond: &Conditioning) -> Option<PairTable> {
    let cat = &color.categories[ci];
    let other = &color.categories[oi];
    let same = oi == ci;
    let pair = color
        .pairs
        .iter()
        .filter(|p| p.category == cat.category.name && p.other == other.category.name)
        .max_by_key(|p| matches!(p.interaction, Interaction::OrientedRdf { .. }))?;
    let hard_core = if same { cat.min_distance } else { 0.0 };
    let mut table = match &pair.interaction {
        Interaction::Rdf { hist } => PairTable::new(&hist.values, 1, hist.bin_width, hard_core),
        Interaction::OrientedRdf {
            distance_bin,
            angle_bins,
            values,
        } => PairTable::new(values, *angle_bins, *distance_bin, hard_core),
    };
    if !same {
        table.others_inside = Some(cond.inside[oi].as_ref().map_or(0, |v| v.len()));
    }
    table.other_density = other.density;
    let n_other = other.count as f64 - if same { 1.0 } else { 0.0 };
    let pairs_per_area = cat.count as f64 * n_other / color.region_area;
    // the analysis's default radius is 24 bins unless it followed a clustered example further
    let follows_clustering =
        color.max_radius > 1.001 * crate::analysis::DEFAULT_RDF_BINS as f64 * color.bin_width;
    let spacing = (color.region_area / (pairs_per_area * color.region_area).sqrt()).sqrt();
    table.truncate_to_significant(pairs_per_area, follows_clustering.then_some(spacing));
    Some(table)
}

/// The fixed content of category `oi` under pair tag `tag`: inside the region as is (window-corrected in the
/// rdf-matching chain), around it with `CONTEXT_TAG` (product factors).
fn push_fixed_entries(out: &mut Vec<GridEntry>, cond: &Conditioning, oi: usize, tag: u32) {
    for p in cond.inside[oi].iter().flatten() {
        out.push(GridEntry {
            position: *p,
            tag,
            id: FIXED_ID,
        });
    }
    for p in &cond.context[oi] {
        out.push(GridEntry {
            position: *p,
            tag: tag | CONTEXT_TAG,
            id: FIXED_ID,
        });
    }
}

/// The map factors `ψ` of the category `name`, each reading its terrain map or its distance to structured content.
fn map_tables<'a>(
    color: &'a Color,
    name: &str,
    structures: &StructuredContent,
) -> Vec<MapTable<'a>> {
    color
        .maps
        .iter()
        .filter(|m| m.category == name)
        .map(|m| {
            let field = match m.source {
                MapSource::Terrain => MapField::Terrain(&m.map),
                MapSource::GraphDistance => {
                    MapField::Graph(structures.graph(&m.map), color.max_radius)
                }
                MapSource::PolygonDistance => {
                    MapField::Polygons(structures.polygons(&m.map), color.max_radius)
                }
            };
            MapTable::new(&m.map, field, &m.hist, &m.region_hist)
        })
        .collect()
}

/// The interaction radius: as far as some pair's rdf differs from 1 (or a hard core reaches), at least a bin.
fn interaction_radius(tables: &[PairTable], min_distance: f64, bin_width: f64) -> f64 {
    tables
        .iter()
        .map(|t| t.bin_width * t.n_bins as f64)
        .fold(
            if min_distance.is_finite() {
                min_distance
            } else {
                0.0
            },
            f64::max,
        )
        .max(bin_width)
}

/// The cap of a point's total log pair factor: `SATURATION_PAIRS` times the largest single-pair log factor.
fn saturation(tables: &[PairTable]) -> f64 {
    SATURATION_PAIRS
        * tables
            .iter()
            .flat_map(|t| t.target_hist.iter())
            .fold(1.0f64, |m, v| m.max(*v))
            .ln()
}

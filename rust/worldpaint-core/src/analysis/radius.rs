//! The rdf's bin width and maximum radius when the options do not give them.
//!
//! `max_radius = 3 / √λ_min`, where `λ_min` is the density of the sparsest category with at least 5 instances
//! (any with 2 if none has 5): three mean spacings of the sparsest category, which spans its clusters or its
//! hard-core ring and the first neighbours. It is bounded by a quarter of the region's smaller side so the
//! window-edge correction stays reliable. `bin_width` is a 24th of that.
//!
//! Real forests are clustered at several scales (the Luquillo plot's pcf stays above 1 out to 15–40 m, five to
//! twenty spacings), and three spacings would cut that off. So the radius follows each category that is still
//! clustered further (`clustering_range`): its rdf, divided by the pair correlation its map preference alone
//! gives (module `intensity`), is probed in bins one mean spacing wide, out to 16 spacings, and the clustered
//! range ends where the excess over 1 falls below 5 % or its counting noise. The radius is twice that range
//! (bounded by half the region's smaller side): at a fixed count the synthesis would otherwise pay for the
//! clusters' excess pairs with a ring of gaps right behind them. The bins keep their width (the fine structure
//! at short range stays resolved), so such a color has more of them. This is the "learn out to the scales where
//! the exemplar is still clustered" reading, with uniform rather than log-spaced bins: the synthesis matches pair
//! counts per bin in units of their counting noise, which is small at long range whatever the bin width, and
//! uniform bins keep one bin lookup per pair.

use super::{intensity, point_grid, rdf, AnalysisOptions, Group, DEFAULT_RDF_BINS};
use crate::error::{check, Result};
use crate::geom::{DVec2, PreparedRegion, Region, RegionQueries};
use crate::palette::MapInteraction;
use crate::scene::{CategoryKind, Scene};
use crate::terrain::Heightfield;
use std::f64::consts::PI;

/// The smallest excess of the rdf over 1 that counts as clustering when the radius follows a clustered exemplar.
pub(crate) const CLUSTER_EXCESS: f64 = 0.05;
/// How far (in mean spacings) the radius may follow a clustered category.
const PROBE_SPACINGS: f64 = 16.0;
/// Fewer points than this say nothing of clustering beyond three spacings.
const PROBE_MIN_POINTS: usize = 50;

/// The rdf's maximum radius and bin width: the options' when given (and valid), else the rule in the module
/// documentation.
pub(super) fn radius_and_bin_width(
    opts: &AnalysisOptions,
    region: &Region,
    groups: &[Group],
    scene: &Scene,
    terrain_maps: &[MapInteraction],
) -> Result<(f64, f64)> {
    // a given radius is cut in `DEFAULT_RDF_BINS`; the default one in bins of a 24th of three mean spacings
    let (max_radius, base) = match opts.max_radius {
        Some(r) => (check::positive("max_radius", r)?, r),
        None => {
            let maps = MapPreference {
                terrain: scene.terrain.as_deref(),
                maps: terrain_maps,
            };
            default_max_radius(region, groups, &maps, opts.local)
        }
    };
    let bin_width = match opts.bin_width {
        Some(w) => {
            check::positive("bin_width", w)?;
            check::within("bin_width", w, 0.0, max_radius)?
        }
        None => base / DEFAULT_RDF_BINS as f64,
    };
    Ok((max_radius, bin_width))
}

/// The radius of the rule in the module documentation, and the base radius (three mean spacings) that sets the
/// bin width.
fn default_max_radius(
    region: &Region,
    groups: &[Group],
    maps: &MapPreference,
    local: bool,
) -> (f64, f64) {
    let area = region.area();
    let cap = 0.25 * region.smaller_side();
    // the dense points of polygons have a radius of their own
    let sparsest = |min_count: usize| {
        groups
            .iter()
            .filter(|g| g.kind() != CategoryKind::Polygon && g.positions.len() >= min_count)
            .map(|g| g.positions.len())
            .min()
    };
    let base = match sparsest(5).or_else(|| sparsest(2)) {
        Some(n) => (3.0 / (n as f64 / area).sqrt()).min(cap),
        None => cap,
    };
    if local {
        return (base, base);
    }
    let prepared = PreparedRegion::new(region);
    let clustered = groups
        .iter()
        .filter(|g| g.kind() != CategoryKind::Polygon)
        .map(|g| clustering_range(region, &prepared, g, maps))
        .fold(0.0, f64::max);
    // twice the clustered range: the chain must also hold the rdf at 1 beyond the clusters, or it pays for their
    // excess pairs (the count is fixed) with a ring of gaps right behind them
    (
        base.max((2.0 * clustered).min(0.5 * region.smaller_side())),
        base,
    )
}

/// The learned terrain maps' preference of each category: `ψ = Π h_m / q_m` (what the synthesis's map factors
/// are, before its treatment of values never seen).
struct MapPreference<'a> {
    terrain: Option<&'a Heightfield>,
    maps: &'a [MapInteraction],
}

impl MapPreference<'_> {
    /// ψ of `category` at `p`; None off the terrain, Some(1) without maps.
    fn at(&self, category: &str, p: DVec2) -> Option<f64> {
        let mut psi = 1.0;
        for m in self.maps.iter().filter(|m| m.category == category) {
            let v = self.terrain?.map_at(&m.map, p)?;
            let v = v.clamp(m.hist.start, m.hist.end() - 1e-9 * m.hist.bin_width);
            let q = m.region_hist.value_at(v);
            psi *= if q > 0.0 { m.hist.value_at(v) / q } else { 0.0 };
        }
        Some(psi)
    }
}

/// How far the points stay clustered beyond what their map preference explains: their rdf, divided by the pair
/// correlation of that preference (module `intensity`), is probed in bins one mean spacing wide out to
/// `PROBE_SPACINGS` spacings (and half the region's smaller side), and the range ends with the first bin, after
/// the first, whose excess over 1 is below `CLUSTER_EXCESS` or three standard deviations of its counting noise
/// (Poisson noise times the clusters' size, as the excess neighbours out to that bin count it). 0 for fewer than
/// `PROBE_MIN_POINTS` points.
fn clustering_range(
    region: &Region,
    prepared: &PreparedRegion,
    g: &Group,
    maps: &MapPreference,
) -> f64 {
    let (positions, n) = (&g.positions, g.positions.len());
    if n < PROBE_MIN_POINTS {
        return 0.0;
    }
    let area = region.area();
    let spacing = (area / n as f64).sqrt();
    let bins = ((PROBE_SPACINGS * spacing).min(0.5 * region.smaller_side()) / spacing) as usize;
    if bins < 2 {
        return 0.0;
    }
    let grid = point_grid(region, positions, spacing * bins as f64);
    let mut g_hat = rdf(
        prepared, area, positions, positions, &grid, true, spacing, bins, 1,
    );
    let has_maps = maps.maps.iter().any(|m| m.category == g.category.name);
    if let (Some(terrain), true) = (maps.terrain, has_maps) {
        let psi = |p: DVec2| maps.at(&g.category.name, p).filter(|_| terrain.contains(p));
        let inside = |p: DVec2| prepared.contains(p);
        let c = intensity::intensity_pair_correlation(psi, inside, region.bbox(), spacing, bins);
        for (v, c) in g_hat.iter_mut().zip(c) {
            if c > 0.0 {
                *v /= c;
            }
        }
    }
    let pairs_per_area = (n * (n - 1)) as f64 / area;
    let ring = |k: usize| PI * spacing * spacing * ((k + 1).pow(2) - k.pow(2)) as f64;
    // pairs come in bundles of clusters: their counts vary as many times more as a cluster holds points,
    // 1 + λ ∫ (g − 1)⁺ over the probed range (λ |ring| = n |ring| / A)
    let cluster_size = 1.0
        + (0..bins)
            .map(|k| (g_hat[k] - 1.0).max(0.0) * n as f64 * ring(k) / area)
            .sum::<f64>();
    let clustered: Vec<bool> = (0..bins)
        .map(|k| {
            let sigma = (g_hat[k].max(1.0) * cluster_size / (pairs_per_area * ring(k))).sqrt();
            g_hat[k] - 1.0 > CLUSTER_EXCESS.max(3.0 * sigma)
        })
        .collect();
    match (1..bins).find(|k| !clustered[*k]) {
        Some(k) if k > 1 || clustered[0] => k as f64 * spacing,
        Some(_) => 0.0,
        None => bins as f64 * spacing,
    }
}

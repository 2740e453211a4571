//! Where the statistics of a region are sampled: points spread over the region for the maps' histograms over it
//! (the `h_m` denominators), and a lattice of a region on a terrain.

use crate::geom::{DVec2, Region};
use crate::terrain::Heightfield;

/// Samples of a region for the distribution of a distance map over it.
const REGION_SAMPLES: f64 = 40_000.0;
/// Lattice samples over a region on a terrain, at most.
const LATTICE_SAMPLES: f64 = 1e6;

/// One axis of a sampling lattice: `count` points `step` apart, unless a region far longer than wide would make more
/// than `max` of them; then `max` points spread over its `extent`. So a sliver of a region is sampled along its
/// length with a bounded number of points, instead of one point per `step` (which the area alone sets).
fn lattice_axis(count: f64, extent: f64, step: f64, max: f64) -> (usize, f64) {
    if count <= max {
        (count as usize, step)
    } else {
        (max as usize, extent / max)
    }
}

/// Points spread over the region (a lattice of about `REGION_SAMPLES` points).
pub(crate) fn region_samples(region: &Region) -> Vec<DVec2> {
    let (lo, hi) = region.bbox();
    let ext = hi - lo;
    let step = (ext.x * ext.y / REGION_SAMPLES).sqrt().max(1e-9);
    let (nx, sx) = lattice_axis((ext.x / step).ceil().max(1.0), ext.x, step, REGION_SAMPLES);
    let (ny, sy) = lattice_axis((ext.y / step).ceil().max(1.0), ext.y, step, REGION_SAMPLES);
    let lattice: Vec<DVec2> = (0..ny)
        .flat_map(|j| {
            (0..nx).map(move |i| lo + DVec2::new((i as f64 + 0.5) * sx, (j as f64 + 0.5) * sy))
        })
        .collect();
    inside_of(region, lattice)
}

/// The points that lie in the region, in their order.
fn inside_of(region: &Region, points: Vec<DVec2>) -> Vec<DVec2> {
    let inside = region.contains_each(&points);
    points
        .into_iter()
        .zip(inside)
        .filter_map(|(p, i)| i.then_some(p))
        .collect()
}

/// Sample positions on a lattice covering `region` and the terrain (spacing half a terrain cell, coarser when
/// that would exceed a million points).
pub(crate) fn region_lattice(region: &Region, terrain: &Heightfield) -> Vec<DVec2> {
    let (lo, hi) = region.bbox();
    let (tlo, thi) = terrain.bbox();
    let lo = lo.max(tlo);
    let hi = hi.min(thi);
    if !(hi.x >= lo.x && hi.y >= lo.y) {
        return Vec::new();
    }
    let ext = hi - lo;
    let step = (0.5 * terrain.cell)
        .max((ext.x * ext.y / LATTICE_SAMPLES).sqrt())
        .max(1e-9);
    let (nx, sx) = lattice_axis((ext.x / step).floor() + 1.0, ext.x, step, LATTICE_SAMPLES);
    let (ny, sy) = lattice_axis((ext.y / step).floor() + 1.0, ext.y, step, LATTICE_SAMPLES);
    let lattice: Vec<DVec2> = (0..ny)
        .flat_map(|j| {
            (0..nx).map(move |i| lo + DVec2::new((i as f64 + 0.5) * sx, (j as f64 + 0.5) * sy))
        })
        .filter(|p| p.x <= hi.x && p.y <= hi.y && terrain.contains(*p))
        .collect();
    inside_of(region, lattice)
}

//! The size of synthesized islands. The dense points of a polygon category are synthesized by their rdf (module
//! `rdf`) and traced into contours (`crate::contour::trace`); the rdf holds the land share and the points'
//! clustering, but not how the land splits into islands: one island of the learned size and two of half its
//! size have much the same pair counts at short range, and the chain's tiles, which move points only within
//! themselves, break the larger clusters sooner than they build them. An archipelago came out with twice the
//! exemplar's contours per area at half their size, and more iterations made it worse.
//!
//! So the traced islands (outer contours with their lakes, [`crate::contour::islands`]) are matched to the
//! learned ones ([`PolygonColor::islands_per_area`], [`PolygonColor::island_areas`]) after tracing:
//!
//! * **Count.** The region should hold `N = islands per area × its area` islands (by their centroids, as they
//!   were learned). While it holds more, the smallest island lying wholly inside the region is removed with its
//!   lakes, as long as it is smaller than the learned median island: islands of the learned sizes stay, and
//!   islands the synthesis makes too large are left as they are.
//! * **Land.** The land the removed islands held goes to the islands that stay: each one wholly inside the region
//!   is scaled about its centroid by `s = √(1 + removed / kept)`, its lakes with it, when the scaled island
//!   stays in the region and at least two dense-point spacings clear of every other island (otherwise it keeps
//!   its size). The land share, which the rdf chain matched, is kept, and the mean island area follows. When
//!   the islands that stay cannot take the land back (near the border, crowded) and more than `LAND_LOSS` of
//!   it would be lost, the islands stay as traced: the land share matters more than their count.
//!
//! Why not a term of the rdf chain or births of whole islands: the chain moves single points in parallel
//! tiles, and a term on component sizes needs the connectivity of the whole region at every move; whole-island
//! births would bypass the dense points that carry the islands' interactions with the categories around them.
//! The pass is deterministic (islands in order of area, then of tracing).

use crate::analysis::structure::centroid;
use crate::contour::{islands, Island, Polygons};
use crate::geom::{polygon_contains, DVec2, PreparedRegion, RegionQueries};
use crate::palette::PolygonColor;

/// Islands are kept at least this many dense-point spacings apart when they grow.
const GAP_SPACINGS: f64 = 2.0;
/// The largest share of the traced land the matching may lose (when the islands that stay cannot grow).
const LAND_LOSS: f64 = 0.1;

/// The traced contours with their islands matched to the learned count and sizes (see the module
/// documentation); `area` is the region's.
pub(super) fn match_sizes(
    traced: Vec<Vec<DVec2>>,
    pc: Option<&PolygonColor>,
    region: &PreparedRegion,
    area: f64,
) -> Vec<Vec<DVec2>> {
    let Some(pc) = pc.filter(|pc| pc.islands_per_area > 0.0 && !pc.island_areas.is_empty()) else {
        return traced;
    };
    let all = islands(&traced);
    let wholly_inside = |i: &Island| traced[i.outer].iter().all(|p| region.contains(*p));
    let counted = all
        .iter()
        .filter(|i| region.contains(centroid(&traced[i.outer])))
        .count();
    let target = (pc.islands_per_area * area).round().max(1.0) as usize;
    let median = pc.island_areas[pc.island_areas.len() / 2];
    // the smallest removable islands first (stable: ties keep the tracing order)
    let mut order: Vec<usize> = (0..all.len()).filter(|&k| wholly_inside(&all[k])).collect();
    order.sort_by(|&a, &b| all[a].area.total_cmp(&all[b].area));
    let mut removed = vec![false; all.len()];
    let (mut count, mut lost) = (counted, 0.0);
    for k in order {
        if count <= target || all[k].area >= median {
            break;
        }
        removed[k] = true;
        count -= 1;
        lost += all[k].area;
    }
    let mut contours = traced.clone();
    let kept: Vec<usize> = (0..all.len()).filter(|&k| !removed[k]).collect();
    let growing: Vec<usize> = kept
        .iter()
        .copied()
        .filter(|&k| wholly_inside(&all[k]))
        .collect();
    let growing_land: f64 = growing.iter().map(|&k| all[k].area).sum();
    let mut regained = 0.0;
    if lost > 0.0 && growing_land > 0.0 {
        let scale = (1.0 + lost / growing_land).sqrt();
        let gap = GAP_SPACINGS * pc.spacing;
        for &k in &growing {
            if grow(&mut contours, &all, &kept, k, scale, gap, region) {
                regained += all[k].area * (scale * scale - 1.0);
            }
        }
    }
    // islands too close to the border or to each other to grow would lose the land the chain matched: the
    // islands stay as traced rather than the land share falling
    if lost - regained > LAND_LOSS * all.iter().map(|i| i.area).sum::<f64>() {
        return traced;
    }
    kept.iter()
        .flat_map(|&k| std::iter::once(all[k].outer).chain(all[k].lakes.iter().copied()))
        .map(|c| contours[c].clone())
        .collect()
}

/// Scales island `k` (its outer contour and lakes) about its centroid by `scale`, when it then stays in the
/// region, `gap` clear of the other `kept` islands, and holds none of them; whether it did.
fn grow(
    contours: &mut [Vec<DVec2>],
    all: &[Island],
    kept: &[usize],
    k: usize,
    scale: f64,
    gap: f64,
    region: &PreparedRegion,
) -> bool {
    let island = &all[k];
    let c = centroid(&contours[island.outer]);
    let scaled =
        |points: &[DVec2]| -> Vec<DVec2> { points.iter().map(|p| c + (*p - c) * scale).collect() };
    let outer = scaled(&contours[island.outer]);
    let others: Vec<usize> = kept
        .iter()
        .copied()
        .filter(|&j| j != k)
        .map(|j| all[j].outer)
        .collect();
    let neighbours = Polygons::new(
        &others
            .iter()
            .map(|&o| contours[o].clone())
            .collect::<Vec<_>>(),
    );
    let fits = outer.iter().all(|p| {
        region.contains(*p) && !neighbours.contains(*p) && neighbours.distance(*p, gap) >= gap
    }) && others.iter().all(|&o| {
        contours[o]
            .first()
            .is_none_or(|p| !polygon_contains(&outer, *p))
    });
    if fits {
        contours[island.outer] = outer;
        for &lake in &island.lakes {
            contours[lake] = scaled(&contours[lake]);
        }
    }
    fits
}

//! Dynamic interest maps (thesis 3.2.2). The interest of a location `p` for a building type `B` of a village type
//! `V` combines `n` criteria `f_i(p, V, B) ∈ [-1, 1]` with the encyclopedia's weights `w_i(V, B)`:
//!
//! > I(p, B, V) = 0 if ∃ i such that f_i(p, V, B) = −1, max(0, Σ w_i(V, B) f_i(p, V, B)) otherwise.
//!
//! The criteria are sociability and worship (sums of attraction-repulsion functions of the distances to the
//! surrounding buildings, resp. religious ones), accessibility (an asymmetric bell of the distance to the closest
//! road), slope (a bell of the terrain grade), water (a close-distance function of the distance to water),
//! fortification (an open-distance function of the distance to a fortified enclosure or a castle, 1 inside) and
//! geographical domination:
//!
//! > f(x) = Σ_{p, ‖x−p‖ < r} (h(x) − h(p)) / (1 + ‖x − p‖²).
//!
//! Fig. 3.6 shows the four templates only as curves; the readings chosen here:
//! - attraction-repulsion: −1 below `λ_min` (too close: impossible), rising from −1 to 1 on `[λ_min, λ_0]`,
//!   falling from 1 to 0 on `[λ_0, λ_max]`, 0 beyond;
//! - balance (bell): −1 outside `[λ_min, λ_max]` (prohibited), 1 at `λ_0`, `1 − t²` towards each bound;
//! - close distance: −1 below `λ_min`, 1 on `[λ_min, λ_0]`, falling to 0 at `λ_max`, 0 beyond;
//! - open distance (`λ_min = 0`): 1 inside and up to `λ_0`, falling to 0 at `λ_max`, 0 beyond.
//!
//! The domination sum measures distances in units of `r/4` (in metres the weights would vanish beyond a few
//! metres and `r` would not matter) and is divided by its largest magnitude over `Ω`, so it spans `[-1, 1]`.
//! Before the village has a road, accessibility is 0 (the first building is placed by the other criteria and
//! its road is built right after). A criterion whose weight is 0 cannot forbid a location, except sociability,
//! whose `λ_min` keeps buildings apart whatever the weights.

use super::encyclopedia::{Placement, Shape};
use super::land::Land;
use super::BuildingSeed;
use crate::grid::Grid;
use crate::spatial::GrowingPoints;
use glam::DVec2;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// The criteria of 3.2.2, in the order of [`InterestCriterion::ALL`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum InterestCriterion {
    /// Attraction-repulsion to the surrounding buildings.
    Sociability,
    /// Attraction-repulsion to the religious buildings.
    Worship,
    /// Asymmetric bell of the distance to the closest road.
    Accessibility,
    /// Bell of the terrain grade.
    Slope,
    /// Close-distance function of the distance to water.
    Water,
    /// Open-distance function of the distance to a fortified enclosure or a castle.
    Fortification,
    /// Geographical domination: how much the place overlooks its surroundings.
    Domination,
}

impl InterestCriterion {
    /// The criteria in the order of `InterestWeights`' fields.
    pub const ALL: [InterestCriterion; 7] = [
        InterestCriterion::Sociability,
        InterestCriterion::Worship,
        InterestCriterion::Accessibility,
        InterestCriterion::Slope,
        InterestCriterion::Water,
        InterestCriterion::Fortification,
        InterestCriterion::Domination,
    ];

    /// The criterion's name in lower case, as the encyclopedia's weights and the add-on spell it.
    pub fn name(self) -> &'static str {
        match self {
            InterestCriterion::Sociability => "sociability",
            InterestCriterion::Worship => "worship",
            InterestCriterion::Accessibility => "accessibility",
            InterestCriterion::Slope => "slope",
            InterestCriterion::Water => "water",
            InterestCriterion::Fortification => "fortification",
            InterestCriterion::Domination => "domination",
        }
    }

    /// The criterion of that [`InterestCriterion::name`], if any.
    pub fn from_name(name: &str) -> Option<InterestCriterion> {
        InterestCriterion::ALL
            .into_iter()
            .find(|c| c.name() == name)
    }
}

/// Linear ramp from 0 at `a` to 1 at `b` (1 when the interval is empty).
fn ramp(x: f64, a: f64, b: f64) -> f64 {
    if b - a <= 1e-12 {
        return 1.0;
    }
    ((x - a) / (b - a)).clamp(0.0, 1.0)
}

/// Fig. 3.6 (a): attraction-repulsion (sociability, worship).
pub(crate) fn attraction_repulsion(d: f64, s: &Shape) -> f64 {
    if d < s.min {
        -1.0
    } else if d <= s.zero {
        -1.0 + 2.0 * ramp(d, s.min, s.zero)
    } else if d <= s.max {
        1.0 - ramp(d, s.zero, s.max)
    } else {
        0.0
    }
}

/// Fig. 3.6 (b): balance (roads, slope).
pub(crate) fn balance(x: f64, s: &Shape) -> f64 {
    if !(x >= s.min && x <= s.max) {
        return -1.0;
    }
    let t = if x < s.zero {
        1.0 - ramp(x, s.min, s.zero)
    } else {
        ramp(x, s.zero, s.max)
    };
    1.0 - t * t
}

/// Fig. 3.6 (c): close distance (water).
pub(crate) fn close_distance(d: f64, s: &Shape) -> f64 {
    if d < s.min {
        -1.0
    } else if d <= s.zero {
        1.0
    } else {
        1.0 - ramp(d, s.zero, s.max)
    }
}

/// Fig. 3.6 (d): open distance (fortifications); `d` is 0 inside.
pub(crate) fn open_distance(d: f64, s: &Shape) -> f64 {
    if d <= s.zero {
        1.0
    } else {
        1.0 - ramp(d, s.zero, s.max)
    }
}

/// The interest equation over criterion values (in [`InterestCriterion::ALL`] order), clipped to `[0, 1]` so it is the
/// probability of the aggregation test.
pub(crate) fn combine(values: &[f64; 7], placement: &Placement) -> f64 {
    let w = placement.weights.as_array();
    let forbidden = values
        .iter()
        .zip(w.iter())
        .enumerate()
        .any(|(k, (v, w))| *v <= -1.0 && (k == 0 || *w != 0.0));
    if forbidden {
        return 0.0;
    }
    values
        .iter()
        .zip(w.iter())
        .map(|(v, w)| v * w)
        .sum::<f64>()
        .clamp(0.0, 1.0)
}

/// Exact Euclidean distance (m) from every node to the nearest node where `mask` is true; infinite everywhere
/// when the mask is empty.
pub(crate) fn distance_transform(grid: &Grid, mask: &[bool]) -> Vec<f32> {
    crate::distance::distance_transform(grid.nx, grid.ny, grid.cell, mask)
}

/// The criteria that do not change while the village grows, computed once per village.
pub struct StaticInterestMaps {
    /// Terrain grade (rise over run) per node.
    pub grade: Vec<f32>,
    /// Distance (m) to the nearest water node.
    pub water_distance: Vec<f32>,
    /// Distance (m) to the nearest fortified node (0 inside an enclosure).
    pub enclosure_distance: Vec<f32>,
    /// Normalized geographical domination per influence radius (keyed by the radius's bits).
    domination: BTreeMap<u64, (Grid, Vec<f32>)>,
}

impl StaticInterestMaps {
    /// The static maps, with the domination of every radius in `radii`.
    pub fn new(land: &Land, radii: &[f64]) -> StaticInterestMaps {
        let grade = (0..land.grid().len())
            .into_par_iter()
            .map(|k| land.grade_at_node(k) as f32)
            .collect();
        let water_distance = distance_transform(land.grid(), land.water());
        let enclosure_distance = distance_transform(land.grid(), land.fortified());
        let mut domination = BTreeMap::new();
        for r in radii {
            domination
                .entry(r.to_bits())
                .or_insert_with(|| domination_map(land, *r));
        }
        StaticInterestMaps {
            grade,
            water_distance,
            enclosure_distance,
            domination,
        }
    }

    /// Normalized domination at `p` for radius `r` (0 for a radius the maps were not built with).
    pub(crate) fn domination_at(&self, r: f64, p: DVec2) -> f64 {
        self.domination
            .get(&r.to_bits())
            .map_or(0.0, |(g, v)| g.bilinear(v, p))
    }
}

/// Domination on a grid about `r/16` apart (upsampled bilinearly when read), from height samples `r/8` apart.
fn domination_map(land: &Land, r: f64) -> (Grid, Vec<f32>) {
    let g = land.grid();
    let step = (r / 16.0).max(g.cell);
    let coarse = Grid::nodes_covering(g.origin, g.point(g.nx - 1, g.ny - 1), step).unwrap_or(*g);
    let spacing = (r / 8.0).max(g.cell);
    let unit = r / 4.0;
    let m = (r / spacing).ceil() as i64;
    let offsets: Vec<(DVec2, f64)> = (-m..=m)
        .flat_map(|j| (-m..=m).map(move |i| DVec2::new(i as f64, j as f64) * spacing))
        .filter(|o| o.length() < r && o.length() > 0.0)
        .map(|o| (o, 1.0 / (1.0 + (o.length() / unit).powi(2))))
        .collect();
    let (lo, hi) = (g.origin, g.point(g.nx - 1, g.ny - 1));
    let raw: Vec<f64> = (0..coarse.len())
        .into_par_iter()
        .map(|k| {
            let x = coarse.point_of(k);
            let hx = land.height_at(x);
            offsets
                .iter()
                .filter(|(o, _)| {
                    let p = x + *o;
                    p.x >= lo.x && p.y >= lo.y && p.x <= hi.x && p.y <= hi.y
                })
                .map(|(o, w)| (hx - land.height_at(x + *o)) * w)
                .sum()
        })
        .collect();
    let scale = raw.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-9);
    (coarse, raw.iter().map(|v| (v / scale) as f32).collect())
}

/// A distance map read bilinearly (a map is wholly infinite when nothing was there to measure to).
fn distance_at(grid: &Grid, values: &[f32], p: DVec2) -> f64 {
    if values.first().is_none_or(|v| v.is_infinite()) {
        return f64::INFINITY;
    }
    grid.bilinear(values, p)
}

/// Side (m) of the cells the buildings are binned in for the sociability sums: about the reach of a house's.
const BUILDING_CELL: f64 = 32.0;

/// What the dynamic criteria see of the growing village.
pub(crate) struct VillageState<'a> {
    buildings: &'a [BuildingSeed],
    /// The buildings' positions binned, in their order: a location's sociability sums the buildings within its
    /// reach only (beyond it every term is 0), so that a candidate costs the same in a town as in a hamlet.
    binned: GrowingPoints,
    /// The religious buildings (worship is measured to them) and the castles and fortresses (fortification is
    /// measured to them as to an enclosure), by index.
    religious: Vec<usize>,
    fortresses: Vec<usize>,
    /// Distance (m) to the closest road, looked for no farther than the limit given (the limit or more beyond it).
    road_distance: &'a (dyn Fn(DVec2, f64) -> f64 + Sync),
    has_roads: bool,
}

impl<'a> VillageState<'a> {
    /// The village of `buildings`, `religious[k]` and `fortress[k]` telling whether building `k` is religious, a
    /// castle or a fortress, with the distance to its roads (`has_roads` false: there is none yet).
    pub(crate) fn new(
        buildings: &'a [BuildingSeed],
        religious: &[bool],
        fortress: &[bool],
        road_distance: &'a (dyn Fn(DVec2, f64) -> f64 + Sync),
        has_roads: bool,
    ) -> VillageState<'a> {
        let (lo, hi) = buildings
            .iter()
            .map(|b| b.position)
            .filter(|p| p.is_finite())
            .fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(p), hi.max(p)),
            );
        let (lo, hi) = if lo.cmple(hi).all() {
            (lo, hi)
        } else {
            (DVec2::ZERO, DVec2::ZERO)
        };
        let mut binned = GrowingPoints::new(lo, hi, BUILDING_CELL, buildings.len());
        buildings.iter().for_each(|b| binned.push(b.position));
        let flagged = |flags: &[bool]| -> Vec<usize> {
            (0..buildings.len())
                .filter(|&k| flags.get(k).copied().unwrap_or(false))
                .collect()
        };
        VillageState {
            buildings,
            binned,
            religious: flagged(religious),
            fortresses: flagged(fortress),
            road_distance,
            has_roads,
        }
    }
}

/// Distance (m) beyond which no building adds to the sociability of a building placed by `placement`.
fn sociability_reach(placement: &Placement) -> f64 {
    placement
        .sociability_with
        .values()
        .fold(placement.sociability.max, |r, s| r.max(s.max))
}

/// Accessibility, slope and water at `p`: what the land and the roads say, without the buildings.
fn land_criteria(
    land: &Land,
    maps: &StaticInterestMaps,
    state: &VillageState,
    placement: &Placement,
    p: DVec2,
) -> [f64; 3] {
    [0, 1, 2].map(|k| land_criterion(k, land, maps, state, placement, p))
}

/// One of [`land_criteria`]: 0 accessibility, 1 slope, 2 water.
fn land_criterion(
    k: usize,
    land: &Land,
    maps: &StaticInterestMaps,
    state: &VillageState,
    placement: &Placement,
    p: DVec2,
) -> f64 {
    let g = land.grid();
    match k {
        0 if state.has_roads => {
            // beyond the bell's far end the criterion is −1 whatever the distance: no need to look farther
            let limit = placement.accessibility.max.max(0.0) * (1.0 + 1e-9) + 1e-6;
            balance((state.road_distance)(p, limit), &placement.accessibility)
        }
        0 => 0.0,
        1 => balance(g.bilinear(&maps.grade, p), &placement.slope),
        _ => close_distance(distance_at(g, &maps.water_distance, p), &placement.water),
    }
}

/// The seven criterion values `f_i(p, V, B)` at `p` for a building placed by `placement`.
pub(crate) fn criteria(
    land: &Land,
    maps: &StaticInterestMaps,
    state: &VillageState,
    placement: &Placement,
    p: DVec2,
) -> [f64; 7] {
    let mut near = Vec::new();
    state
        .binned
        .ids_within(p, sociability_reach(placement), &mut near);
    // summed in the buildings' order, as over all of them (the others add 0)
    near.sort_unstable();
    let mut sociability = 0.0;
    let mut too_close = false;
    for &k in &near {
        let b = &state.buildings[k as usize];
        let shape = placement
            .sociability_with
            .get(&b.building)
            .unwrap_or(&placement.sociability);
        let f = attraction_repulsion(b.position.distance(p), shape);
        too_close |= f <= -1.0;
        sociability += f;
    }
    let distance = |k: &usize| state.buildings[*k].position.distance(p);
    let worship = state
        .religious
        .iter()
        .map(|k| attraction_repulsion(distance(k), &placement.worship).max(-0.999))
        .fold(0.0, |sum, w| sum + w);
    let nearest_fortress = state
        .fortresses
        .iter()
        .map(distance)
        .fold(f64::INFINITY, f64::min);
    let sociability = if too_close {
        -1.0
    } else {
        sociability.clamp(-0.999, 1.0)
    };
    let [accessibility, slope, water] = land_criteria(land, maps, state, placement, p);
    let g = land.grid();
    let enclosure = distance_at(g, &maps.enclosure_distance, p).min(nearest_fortress);
    let fortification = open_distance(enclosure, &placement.fortification);
    let domination = maps
        .domination_at(placement.domination_radius, p)
        .clamp(-1.0, 1.0);
    [
        sociability,
        worship.clamp(-0.999, 1.0),
        accessibility,
        slope,
        water,
        fortification,
        domination,
    ]
}

/// `I(p, B, V)` at `p`, 0 where the land cannot take a building.
pub(crate) fn interest(
    land: &Land,
    maps: &StaticInterestMaps,
    state: &VillageState,
    placement: &Placement,
    p: DVec2,
) -> f64 {
    let Some((i, j)) = land.grid().nearest(p) else {
        return 0.0;
    };
    // most places of a large land are too far from the roads, too steep or too wet: said before the buildings
    // are gone through (the same answer, [`combine`] forbids them as well); the roads are asked first, their
    // index stays in the cache where the land's maps, read at random places, do not
    let w = placement.weights.as_array();
    let forbids =
        |k: usize| w[2 + k] != 0.0 && land_criterion(k, land, maps, state, placement, p) <= -1.0;
    if forbids(0) || !land.buildable(land.grid().index(i, j)) || forbids(1) || forbids(2) {
        return 0.0;
    }
    combine(&criteria(land, maps, state, placement, p), placement)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(min: f64, zero: f64, max: f64) -> Shape {
        Shape { min, zero, max }
    }

    #[test]
    fn templates_follow_their_shape_parameters() {
        let s = shape(5.0, 15.0, 40.0);
        assert_eq!(attraction_repulsion(4.9, &s), -1.0);
        assert!((attraction_repulsion(10.0, &s) - 0.0).abs() < 1e-12);
        assert_eq!(attraction_repulsion(15.0, &s), 1.0);
        assert!((attraction_repulsion(27.5, &s) - 0.5).abs() < 1e-12);
        assert_eq!(attraction_repulsion(41.0, &s), 0.0);
        assert_eq!(balance(4.0, &s), -1.0);
        assert_eq!(balance(15.0, &s), 1.0);
        assert!((balance(27.5, &s) - 0.75).abs() < 1e-12);
        assert_eq!(balance(40.5, &s), -1.0);
        assert_eq!(close_distance(2.0, &s), -1.0);
        assert_eq!(close_distance(12.0, &s), 1.0);
        assert!((close_distance(27.5, &s) - 0.5).abs() < 1e-12);
        assert_eq!(close_distance(100.0, &s), 0.0);
        let o = shape(0.0, 10.0, 30.0);
        assert_eq!(open_distance(0.0, &o), 1.0);
        assert!((open_distance(20.0, &o) - 0.5).abs() < 1e-12);
        assert_eq!(open_distance(31.0, &o), 0.0);
    }

    #[test]
    fn distance_transform_is_exact_on_a_grid() {
        let grid = Grid {
            origin: DVec2::ZERO,
            cell: 2.0,
            nx: 40,
            ny: 30,
        };
        let mut mask = vec![false; grid.len()];
        let seeds = [(3usize, 4usize), (30, 20), (12, 27)];
        for (i, j) in seeds {
            mask[grid.index(i, j)] = true;
        }
        let d = distance_transform(&grid, &mask);
        for (k, dk) in d.iter().enumerate() {
            let p = grid.point_of(k);
            let exact = seeds
                .iter()
                .map(|(i, j)| grid.point(*i, *j).distance(p))
                .fold(f64::INFINITY, f64::min);
            assert!(
                (*dk as f64 - exact).abs() < 1e-4,
                "node {k}: {dk} vs {exact}"
            );
        }
        assert!(distance_transform(&grid, &vec![false; grid.len()])
            .iter()
            .all(|v| v.is_infinite()));
    }
}

//! The heuristics of the road search (thesis 3.2.4): the closed-form bound
//! `h(x) = min_{L ≥ L₀} (distance_weight · L + slope_weight / max_grade² · Δh² / L)` of the module
//! documentation, admissible and consistent; the same bound towards many sources at once (each source, or
//! tiles of them); and the estimate the A* runs on once the node-level search has settled its field.

use super::moves::MoveTable;
use super::search::BUILDING;
use crate::village::encyclopedia::RoadParams;
use crate::village::land::Land;
use glam::DVec2;

/// Up to this many sources, the node-level search is an A* towards each of them; beyond, towards tiles of them,
/// at most this many.
const FEW_SOURCES: usize = 32;
const MAX_SOURCE_TILES: usize = 48;

/// The closed-form lower bound of the module documentation on the cost of any path between two nodes.
pub(super) struct Bound<'a> {
    land: &'a Land,
    table: &'a MoveTable,
    distance_weight: f64,
    /// `slope_weight / max_grade²`.
    slope: f64,
    max_grade: f64,
    steep: bool,
}

impl Bound<'_> {
    pub(super) fn new<'a>(
        land: &'a Land,
        table: &'a MoveTable,
        p: &RoadParams,
        steep: bool,
    ) -> Bound<'a> {
        Bound {
            land,
            table,
            distance_weight: p.distance_weight,
            slope: p.slope_weight / (p.max_grade * p.max_grade),
            max_grade: p.max_grade,
            steep,
        }
    }

    pub(super) fn between(&self, a: usize, b: usize) -> f64 {
        let g = self.land.grid();
        let (ai, aj) = g.ij(a);
        let (bi, bj) = g.ij(b);
        let v = DVec2::new(ai as f64 - bi as f64, aj as f64 - bj as f64);
        let dh = (self.land.height()[a] as f64 - self.land.height()[b] as f64).abs();
        self.of(self.table.gauge(v) * g.cell, dh)
    }

    /// The least cost of a path at least `length` long (m) that climbs `dh`.
    fn of(&self, length: f64, dh: f64) -> f64 {
        let w_d = self.distance_weight;
        let lmin = if self.steep {
            length
        } else {
            length.max(dh / self.max_grade)
        };
        if self.slope <= 0.0 || dh <= 0.0 {
            return w_d * lmin;
        }
        // the best length for the climb, no shorter than possible
        let l = (dh * (self.slope / w_d).sqrt()).max(lmin);
        w_d * l + self.slope * dh * dh / l
    }

    /// Lower bound on the cost from `x` to the cheapest source, its initial cost included.
    pub(super) fn to_sources(&self, x: usize, sources: &SourceBound) -> f64 {
        match sources {
            SourceBound::Nodes(few) => few
                .iter()
                .map(|&(r, t)| t + self.between(x, r))
                .fold(f64::INFINITY, f64::min),
            SourceBound::Tiles(tiles) => {
                let g = self.land.grid();
                let (i, j) = g.ij(x);
                let (q, h) = (DVec2::new(i as f64, j as f64), self.land.height()[x] as f64);
                tiles
                    .iter()
                    .map(|t| {
                        let d = (t.min - q).max(q - t.max).max(DVec2::ZERO).length() * g.cell;
                        let dh = (t.low - h).max(h - t.high).max(0.0);
                        t.cost + self.of(d, dh)
                    })
                    .fold(f64::INFINITY, f64::min)
            }
        }
    }
}

/// What the node-level search knows of the sources, for a consistent bound towards them.
pub(super) enum SourceBound {
    /// A few sources (node, initial cost).
    Nodes(Vec<(usize, f64)>),
    /// Many sources, gathered in tiles.
    Tiles(Vec<SourceTile>),
}

/// Sources of one tile: the box of their nodes (grid units), their lowest initial cost, their heights.
pub(super) struct SourceTile {
    min: DVec2,
    max: DVec2,
    cost: f64,
    low: f64,
    high: f64,
}

impl SourceBound {
    pub(super) fn new(land: &Land, sources: &[(usize, f64)]) -> SourceBound {
        if sources.len() <= FEW_SOURCES {
            return SourceBound::Nodes(sources.to_vec());
        }
        let g = land.grid();
        let mut size = 8;
        loop {
            let mut keyed: Vec<(usize, usize)> = sources
                .iter()
                .enumerate()
                .map(|(k, &(r, _))| {
                    let (i, j) = g.ij(r);
                    ((j / size) * g.nx.div_ceil(size) + i / size, k)
                })
                .collect();
            keyed.sort_unstable();
            let mut tiles: Vec<SourceTile> = Vec::new();
            let mut last = usize::MAX;
            for (key, k) in keyed {
                let (r, t) = sources[k];
                let (i, j) = g.ij(r);
                let q = DVec2::new(i as f64, j as f64);
                let h = land.height()[r] as f64;
                if key != last {
                    tiles.push(SourceTile {
                        min: q,
                        max: q,
                        cost: t,
                        low: h,
                        high: h,
                    });
                    last = key;
                } else if let Some(tile) = tiles.last_mut() {
                    tile.min = tile.min.min(q);
                    tile.max = tile.max.max(q);
                    tile.cost = tile.cost.min(t);
                    tile.low = tile.low.min(h);
                    tile.high = tile.high.max(h);
                }
            }
            if tiles.len() <= MAX_SOURCE_TILES || size >= g.nx.max(g.ny) {
                return SourceBound::Tiles(tiles);
            }
            size *= 2;
        }
    }
}

/// How the A* estimates the cost left to the target.
#[derive(Clone, Copy)]
pub(super) enum Estimate<'a> {
    /// The closed-form bound of the module documentation.
    Bound,
    /// The node-level costs from the target where settled; elsewhere the key the node-level search stopped at
    /// less the bound to the sources (see `Search::node_field`).
    Field(f64, &'a SourceBound),
    /// The same, the paths kept within `Search::corridor`.
    Corridor(f64, &'a SourceBound),
    /// None: a Dijkstra, to check the others against.
    #[cfg(test)]
    Zero,
}

/// The cost left from a node to the target of an A*, under its [`Estimate`].
pub(super) struct Remaining<'a> {
    pub(super) estimate: Estimate<'a>,
    pub(super) bound: &'a Bound<'a>,
    pub(super) target: usize,
    pub(super) building_cost: f64,
    /// The search's node flags, and the node-level field (see `Search::node_field`).
    pub(super) flags: &'a [u8],
    pub(super) settled: &'a [bool],
    pub(super) field: &'a [f32],
}

impl Remaining<'_> {
    pub(super) fn at(&self, y: usize) -> f64 {
        let (stop, towards) = match self.estimate {
            Estimate::Bound => return self.bound.between(y, self.target),
            #[cfg(test)]
            Estimate::Zero => return 0.0,
            Estimate::Field(stop, towards) | Estimate::Corridor(stop, towards) => (stop, towards),
        };
        // `field[y]` counts the building on `y`, which the A*'s cost to `y` already holds
        let charge = if y != self.target && self.flags[y] & BUILDING != 0 {
            self.building_cost
        } else {
            0.0
        };
        let from_target = if self.settled[y] {
            self.field[y] as f64 - 1.0
        } else {
            stop - self.bound.to_sources(y, towards)
        };
        (from_target - charge).max(0.0)
    }
}

//! Long roads coarse to fine: a connection whose target lies farther than [`LONG_ROAD_CELLS`] from every source is
//! first searched on the land sampled every [`COARSE_STRIDE`] nodes (the same costs; buildings and the other
//! goal nodes left out), then laid on the village grid within [`COURSE_CELLS`] of that coarse course. The road is
//! then the cheapest within that corridor, as a search over [`STATE_BUDGET`](super::search) states is.
//!
//! Without it, the first road of a town, from the lowest point of the land's border to its first building across
//! 3 × 3 km of hills, had its node-level search settle 1.6 million of the 2.25 million nodes before it reached
//! the connection point (the closed-form bound knows nothing of the hills between), 0.9 s of the town's 4.7 s.

use super::checks::nearest_inside;
use super::heuristic::{Estimate, SourceBound};
use super::search::{Ctx, Outcome, Query, Search, BUILDING, GOAL};
use crate::grid::Grid;
use crate::village::land::Land;
use glam::DVec2;

/// Straight distance (cells) from the target to the nearest source beyond which a search goes coarse first: the
/// longest roads of the real villages of `tests/real_village_generation.rs` (between their connection points, up
/// to 523 cells) stay exact, the first road of the 1,000-building town of `benches/town.rs` (1,603) does not.
const LONG_ROAD_CELLS: f64 = 1000.0;
/// Nodes of the village grid a coarse cell spans.
const COARSE_STRIDE: usize = 4;
/// Half-width (cells of the village grid) of the corridor around the coarse course: three coarse cells.
const COURSE_CELLS: usize = 3 * COARSE_STRIDE;

/// The land sampled every `stride` nodes (its heights and masks at those nodes); `None` when that leaves fewer
/// than 2 × 2 nodes.
fn coarse_land(land: &Land, stride: usize) -> Option<Land> {
    let g = land.grid();
    let grid = Grid {
        origin: g.origin,
        cell: g.cell * stride as f64,
        nx: (g.nx - 1) / stride + 1,
        ny: (g.ny - 1) / stride + 1,
    };
    let fine: Vec<usize> = (0..grid.len())
        .map(|k| {
            let (i, j) = grid.ij(k);
            g.index(i * stride, j * stride)
        })
        .collect();
    let pick = |mask: &[bool]| fine.iter().map(|&k| mask[k]).collect::<Vec<bool>>();
    Land::from_maps(
        grid,
        fine.iter().map(|&k| land.height()[k]).collect(),
        [
            pick(land.inside()),
            pick(land.water()),
            pick(land.wall()),
            pick(land.fortified()),
        ],
    )
    .ok()
}

impl Search {
    /// The road of `query` when its target lies far from every source: searched on the coarse land, then within
    /// the corridor around that course; the final state. `None` (nothing left marked) when the target is not far,
    /// or no road was found that way.
    pub(super) fn along_coarse_course(&mut self, query: &Query) -> Option<usize> {
        if !self.coarse_first || query.ellipse.is_some() {
            return None;
        }
        let grid = self.grid;
        let target = grid.point_of(query.target);
        let nearest = query
            .sources
            .iter()
            .map(|&(r, _)| grid.point_of(r).distance(target))
            .fold(f64::INFINITY, f64::min);
        if !(nearest > LONG_ROAD_CELLS * grid.cell) {
            return None;
        }
        let course = coarse_course(query)?;
        self.mark_course(&course);
        let towards = SourceBound::new(query.ctx.land, query.sources);
        let found = self
            .node_field(query, &towards, true)
            .and_then(|(stop, _)| {
                match self.astar(query, Estimate::Corridor(stop, &towards), None) {
                    Outcome::Found(s) => Some(s),
                    _ => None,
                }
            });
        if found.is_none() {
            self.reset_states();
            self.field.clear();
            self.corridor.clear();
        }
        found
    }

    /// Marks the nodes within [`COURSE_CELLS`] of the polyline `course`.
    fn mark_course(&mut self, course: &[DVec2]) {
        let g = self.grid;
        for w in course.windows(2) {
            let steps = (w[0].distance(w[1]) / g.cell).ceil().max(1.0) as usize;
            for s in 0..=steps {
                let p = w[0].lerp(w[1], s as f64 / steps as f64);
                self.corridor
                    .mark_around(&g, g.nearest_clamped(p), COURSE_CELLS);
            }
        }
    }
}

/// The road of `query` on the coarse land, as points from the target to a source; `None` when the land is too
/// small to sample, the target and the sources meet on it, or no road joins them there.
fn coarse_course(query: &Query) -> Option<Vec<DVec2>> {
    let land = query.ctx.land;
    let coarse = coarse_land(land, COARSE_STRIDE)?;
    let g = *land.grid();
    let cg = *coarse.grid();
    let target = nearest_inside(&coarse, g.point_of(query.target))?;
    let mut sources: Vec<(usize, f64)> = query
        .sources
        .iter()
        .filter_map(|&(r, t)| Some((nearest_inside(&coarse, g.point_of(r))?, t)))
        .collect();
    // one source a coarse node, at its lowest initial cost
    sources.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    sources.dedup_by_key(|s| s.0);
    if sources.is_empty() || sources.iter().any(|s| s.0 == target) {
        return None;
    }
    let mut search = Search::new(&coarse, query.ctx.params).ok()?;
    search.coarse_first = false;
    search.flags = coarse
        .wall()
        .iter()
        .map(|&w| if w { BUILDING } else { 0 })
        .collect();
    for &(r, _) in &sources {
        search.flags[r] |= GOAL;
    }
    let ctx = Ctx {
        land: &coarse,
        params: query.ctx.params,
    };
    let (path, _) = search.run(&ctx, &sources, target, query.steep, None)?;
    Some(path.into_iter().map(|k| cg.point_of(k)).collect())
}

//! The node-level search of the road search (thesis 3.2.4, module documentation): from `B`, turns ignored so
//! its costs are lower bounds, an A* towards the sources that runs until its key passes the cost of its own path
//! with the turns added. Its settled nodes then know their exact node-level cost to `B`, which the state search
//! restarts with; the corridor around its path is where a state search over budget finishes.

use super::heuristic::{Bound, SourceBound};
use super::move_costs::{cached_cost, usable, CostKey};
use super::moves::MoveTable;
use super::search::{crossing_charge, Deeper, Query, Search, BUILDING, GOAL};
use crate::grid::Grid;
use crate::search::MinHeap;

/// Half-width (cells) of the corridor around the node-level path.
pub(super) const CORRIDOR_CELLS: usize = 8;

/// The turn costs along the node-level path from `target` to `node` (see [`Search::node_field`]).
fn path_turns(
    table: &MoveTable,
    grid: &Grid,
    moves: &[u8],
    target: usize,
    node: usize,
    curvature_weight: f64,
) -> f64 {
    let m_count = table.moves.len();
    let (mut x, mut turns, mut next) = (node, 0.0, None::<usize>);
    let mut steps = 0;
    while x != target && steps < grid.len() {
        let m = moves[x] as usize;
        if let Some(n) = next {
            turns += table.turn[m * m_count + n];
        }
        next = Some(m);
        x = (x as isize - table.moves[m].delta) as usize;
        steps += 1;
    }
    turns * curvature_weight
}

/// What a move costs in the node-level search: the search's tables and the rules of one query.
struct NodeMoves<'s> {
    query: &'s Query<'s>,
    table: &'s MoveTable,
    key: &'s CostKey,
    near: &'s [u8],
    costs: &'s mut [f32],
    flags: &'s [u8],
    source_cost: &'s [f32],
}

impl NodeMoves<'_> {
    /// The node-level cost at `y` after move `m` from `x` at cost `g`: its static cost and the buildings it
    /// lands on or passes over, no turn; `None` when the move is not allowed.
    fn step(&mut self, x: usize, y: usize, m: usize, g: f32) -> Option<f32> {
        let land = self.query.ctx.land;
        // the A* starts at the sources wherever they are: so must the paths here end
        if let Some(el) = self.query.ellipse {
            if self.source_cost[y] == 0.0 && el.excludes(land.grid().point_of(y)) {
                return None;
            }
        }
        let cost = cached_cost(self.costs, self.table, self.key, land, self.near, x, m);
        let c = usable(cost, self.query.steep)?;
        let building = self.flags[y] & BUILDING != 0;
        let mv = &self.table.moves[m];
        let building_cost = self.query.ctx.params.building_cost;
        let charge = crossing_charge(self.flags, x, mv, 0.0, building, building_cost)?;
        Some((g as f64 + c as f64 + charge) as f32)
    }
}

impl Search {
    /// Node-level search from `target` (paths `target → x`, charged like the A* but without turns): an A* towards
    /// the sources under the consistent bound `towards`, until its key passes the cost, turns included, of the
    /// path to the cheapest source reached. Returns that key and that source, or `None` when no source can be
    /// reached. The settled nodes have their exact cost from `target`, and every other node `x` costs at least
    /// the returned key less the bound from `x` to the sources.
    pub(super) fn node_field(
        &mut self,
        query: &Query,
        towards: &SourceBound,
    ) -> Option<(f64, usize)> {
        let land = query.ctx.land;
        let p = query.ctx.params;
        let (target, steep) = (query.target, query.steep);
        let grid = *land.grid();
        let Search {
            key,
            table,
            costs,
            near,
            flags,
            source_cost,
            field,
            settled,
            field_touched,
            field_move,
            ..
        } = self;
        let mut moves = NodeMoves {
            query,
            table,
            key,
            near,
            costs,
            flags,
            source_cost,
        };
        let bound = Bound::new(land, table, p, steep);
        let mut heap = MinHeap::new();
        field[target] = 1.0;
        field_touched.push(target as u32);
        heap.push(bound.to_sources(target, towards), Deeper::new(0.0, target));
        // the cheapest source reached: its cost and node; then the cost of that path with its turns, which the
        // search runs up to so that the A* that follows need not leave the settled nodes
        let mut best = (f64::INFINITY, usize::MAX);
        let mut upper: Option<f64> = None;
        let mut stop = f64::INFINITY;
        while let Some(e) = heap.pop() {
            let (x, gx) = (e.item.state as usize, e.item.g);
            if settled[x] || gx + 1.0 > field[x] {
                continue;
            }
            if e.cost >= best.0 {
                let u = *upper.get_or_insert_with(|| {
                    let (r, t) = (best.1, best.0 - field[best.1] as f64 + 1.0);
                    t + path_turns(table, &grid, field_move, target, r, p.curvature_weight)
                        + field[r] as f64
                        - 1.0
                });
                if e.cost >= u {
                    stop = e.cost;
                    break;
                }
            }
            settled[x] = true;
            if x != target && moves.source_cost[x] != 0.0 {
                let c = gx as f64 + (moves.source_cost[x] - 1.0) as f64;
                if c < best.0 {
                    best = (c, x);
                }
                continue;
            }
            if x != target && moves.flags[x] & GOAL != 0 {
                continue;
            }
            let xij = grid.ij(x);
            for m in 0..table.moves.len() {
                let Some(y) = table.target(&grid, x, xij, m) else {
                    continue;
                };
                if settled[y] {
                    continue;
                }
                let Some(d) = moves.step(x, y, m, gx) else {
                    continue;
                };
                if field[y] == 0.0 || d + 1.0 < field[y] {
                    if field[y] == 0.0 {
                        field_touched.push(y as u32);
                    }
                    field[y] = d + 1.0;
                    field_move[y] = m as u8;
                    heap.push(d as f64 + bound.to_sources(y, towards), Deeper::new(d, y));
                }
            }
        }
        if best.0.is_finite() {
            Some((stop.min(upper.unwrap_or(best.0)), best.1))
        } else {
            None
        }
    }

    /// Marks the nodes within [`CORRIDOR_CELLS`] of the node-level path from `target` to `source`.
    pub(super) fn mark_corridor(&mut self, target: usize, source: usize) {
        let g = self.grid;
        let r = CORRIDOR_CELLS as i64;
        let (mut x, mut steps) = (source, 0);
        loop {
            let (i, j) = g.ij(x);
            for jj in (j as i64 - r).max(0)..=(j as i64 + r).min(g.ny as i64 - 1) {
                for ii in (i as i64 - r).max(0)..=(i as i64 + r).min(g.nx as i64 - 1) {
                    let k = g.index(ii as usize, jj as usize);
                    if !self.corridor[k] {
                        self.corridor[k] = true;
                        self.corridor_touched.push(k as u32);
                    }
                }
            }
            if x == target || steps > g.len() {
                break;
            }
            x = (x as isize - self.table.moves[self.field_move[x] as usize].delta) as usize;
            steps += 1;
        }
    }
}

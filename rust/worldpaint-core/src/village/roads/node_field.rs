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

/// The node-level search's knowledge of each node, reset after each query through the nodes it touched.
pub(super) struct NodeField {
    /// Cost from the target plus one (0 = not reached).
    pub(super) cost: Vec<f32>,
    /// Whether that cost is final.
    pub(super) settled: Vec<bool>,
    /// The move that reached each node.
    pub(super) moves: Vec<u8>,
    /// The nodes reached since the last reset.
    touched: Vec<u32>,
}

impl NodeField {
    pub(super) fn new(nodes: usize) -> NodeField {
        NodeField {
            cost: vec![0.0; nodes],
            settled: vec![false; nodes],
            moves: vec![0; nodes],
            touched: Vec::new(),
        }
    }

    /// Records cost `g` (plus one) and the move `m` that reached `x`.
    fn reach(&mut self, x: usize, g: f32, m: u8) {
        if self.cost[x] == 0.0 {
            self.touched.push(x as u32);
        }
        self.cost[x] = g + 1.0;
        self.moves[x] = m;
    }

    pub(super) fn clear(&mut self) {
        for &x in &self.touched {
            self.cost[x as usize] = 0.0;
            self.settled[x as usize] = false;
        }
        self.touched.clear();
    }
}

/// The nodes near the node-level path, reset after each query through the nodes it marked.
pub(super) struct Corridor {
    pub(super) inside: Vec<bool>,
    marked: Vec<u32>,
}

impl Corridor {
    pub(super) fn new(nodes: usize) -> Corridor {
        Corridor {
            inside: vec![false; nodes],
            marked: Vec::new(),
        }
    }

    fn mark(&mut self, k: usize) {
        if !self.inside[k] {
            self.inside[k] = true;
            self.marked.push(k as u32);
        }
    }

    /// Marks the nodes of `grid` within `r` cells (a square) of node `k`.
    pub(super) fn mark_around(&mut self, grid: &Grid, k: usize, r: usize) {
        let (i, j) = grid.ij(k);
        for jj in j.saturating_sub(r)..=(j + r).min(grid.ny - 1) {
            for ii in i.saturating_sub(r)..=(i + r).min(grid.nx - 1) {
                self.mark(grid.index(ii, jj));
            }
        }
    }

    pub(super) fn clear(&mut self) {
        for &x in &self.marked {
            self.inside[x as usize] = false;
        }
        self.marked.clear();
    }
}

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
    /// The nodes the search keeps to (`None`: anywhere).
    corridor: Option<&'s [bool]>,
}

impl NodeMoves<'_> {
    /// The node-level cost at `y` after move `m` from `x` at cost `g`: its static cost and the buildings it
    /// lands on or passes over, no turn; `None` when the move is not allowed.
    fn step(&mut self, x: usize, y: usize, m: usize, g: f32) -> Option<f32> {
        let land = self.query.ctx.land;
        if self.corridor.is_some_and(|c| !c[y]) {
            return None;
        }
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
    /// the returned key less the bound from `x` to the sources. With `within_corridor`, the paths keep to
    /// `Search::corridor` and the costs are those of paths that do.
    pub(super) fn node_field(
        &mut self,
        query: &Query,
        towards: &SourceBound,
        within_corridor: bool,
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
            corridor,
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
            corridor: within_corridor.then_some(&corridor.inside[..]),
        };
        let bound = Bound::new(land, table, p, steep);
        let mut heap = MinHeap::new();
        field.reach(target, 0.0, 0);
        heap.push(bound.to_sources(target, towards), Deeper::new(0.0, target));
        // the cheapest source reached: its cost and node; then the cost of that path with its turns, which the
        // search runs up to so that the A* that follows need not leave the settled nodes
        let mut best = (f64::INFINITY, usize::MAX);
        let mut upper: Option<f64> = None;
        let mut stop = f64::INFINITY;
        while let Some(e) = heap.pop() {
            let (x, gx) = (e.item.state as usize, e.item.g);
            if field.settled[x] || gx + 1.0 > field.cost[x] {
                continue;
            }
            if e.cost >= best.0 {
                let u = *upper.get_or_insert_with(|| {
                    let (r, t) = (best.1, best.0 - field.cost[best.1] as f64 + 1.0);
                    t + path_turns(table, &grid, &field.moves, target, r, p.curvature_weight)
                        + field.cost[r] as f64
                        - 1.0
                });
                if e.cost >= u {
                    stop = e.cost;
                    break;
                }
            }
            field.settled[x] = true;
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
                if field.settled[y] {
                    continue;
                }
                let Some(d) = moves.step(x, y, m, gx) else {
                    continue;
                };
                if field.cost[y] == 0.0 || d + 1.0 < field.cost[y] {
                    field.reach(y, d, m as u8);
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
        let (mut x, mut steps) = (source, 0);
        loop {
            self.corridor.mark_around(&g, x, CORRIDOR_CELLS);
            if x == target || steps > g.len() {
                break;
            }
            x = (x as isize - self.table.moves[self.field.moves[x] as usize].delta) as usize;
            steps += 1;
        }
    }
}

//! The A* over the states (node, incoming move) of the road search (thesis 3.2.4): a move costs its static cost
//! (see `move_costs`), `curvature_weight` per radian of turn from the incoming move (a U-turn is not allowed),
//! and `building_cost` per building node it lands on or passes over; it may not land on or pass over a goal
//! node other than the target. The estimate of the cost left is the bound or the node-level field
//! (see `heuristic`).

use super::cycles::Ellipse;
use super::heuristic::{Bound, Estimate, Remaining};
use super::move_costs::{cached_cost, usable, CostKey};
use super::moves::MoveTable;
use super::search::{crossing_charge, Deeper, Outcome, Query, Search, BUILDING, GOAL};
use crate::search::MinHeap;
use crate::village::encyclopedia::RoadParams;
use crate::village::land::Land;

/// Sharpest turn between two consecutive moves (radians): anything but going straight back. A hairpin of a
/// serpentine on a steep slope turns between two moves close to the contour lines, up to 180° minus the
/// smallest angle between two moves of the mask.
const MAX_TURN: f64 = std::f64::consts::PI - 1e-6;

/// What a move from a state costs: the search's tables and the rules of one query.
struct Moves<'s> {
    land: &'s Land,
    params: &'s RoadParams,
    table: &'s MoveTable,
    key: &'s CostKey,
    near: &'s [u8],
    costs: &'s mut [f32],
    flags: &'s [u8],
    /// The nodes a corridor search keeps to (`None`: anywhere).
    corridor: Option<&'s [bool]>,
    target: usize,
    steep: bool,
    ellipse: Option<Ellipse>,
}

impl Moves<'_> {
    /// The node move `m` leads to from node `x` = `xij` entered by move `slot` (the source slot: none), and the
    /// path cost `g` there from `g` at `x`; `None` when the move is not allowed.
    fn step(
        &mut self,
        x: usize,
        xij: (usize, usize),
        slot: usize,
        m: usize,
        g: f32,
    ) -> Option<(usize, f32)> {
        let grid = self.land.grid();
        let table = self.table;
        let y = table.target(grid, x, xij, m)?;
        let m_count = table.moves.len();
        let turn = if slot < m_count {
            let a = table.turn[slot * m_count + m];
            if a > MAX_TURN {
                return None;
            }
            a * self.params.curvature_weight
        } else {
            0.0
        };
        let fy = self.flags[y];
        if y != self.target && fy & GOAL != 0 || self.corridor.is_some_and(|c| !c[y]) {
            return None;
        }
        let cost = cached_cost(self.costs, table, self.key, self.land, self.near, x, m);
        let c = usable(cost, self.steep)?;
        let building = y != self.target && fy & BUILDING != 0;
        let mv = &table.moves[m];
        let extra = crossing_charge(self.flags, x, mv, turn, building, self.params.building_cost)?;
        if self.ellipse.is_some_and(|el| el.excludes(grid.point_of(y))) {
            return None;
        }
        Some((y, (g as f64 + c as f64 + extra) as f32))
    }
}

/// The states reached: best path cost plus one (0 = not reached), predecessors, and the open heap.
struct Open<'s> {
    g: &'s mut [f32],
    pred: &'s mut [u8],
    touched: &'s mut Vec<u32>,
    heap: &'s mut MinHeap<Deeper>,
}

impl Open<'_> {
    /// Records path cost `g` at state `s` (reached from incoming move `pred`) when it is the best yet, and
    /// queues it under `g` plus the estimate `left`.
    fn offer(&mut self, s: usize, g: f32, pred: Option<usize>, left: impl FnOnce() -> f64) {
        if self.g[s] == 0.0 || g + 1.0 < self.g[s] {
            if self.g[s] == 0.0 {
                self.touched.push(s as u32);
            }
            self.g[s] = g + 1.0;
            if let Some(m) = pred {
                self.pred[s] = m as u8;
            }
            self.heap.push(g as f64 + left(), Deeper::new(g, s));
        }
    }
}

impl Search {
    /// The A* of `query` under `estimate`, over at most `budget` settled states: the final state when found.
    pub(super) fn astar(
        &mut self,
        query: &Query,
        estimate: Estimate<'_>,
        budget: Option<usize>,
    ) -> Outcome {
        let land = query.ctx.land;
        let params = query.ctx.params;
        let target = query.target;
        let Search {
            key,
            table,
            costs,
            near,
            g,
            pred,
            touched,
            heap,
            flags,
            field,
            corridor,
            ..
        } = self;
        let bound = Bound::new(land, table, params, query.steep);
        let remaining = Remaining {
            estimate,
            bound: &bound,
            target,
            building_cost: params.building_cost,
            flags,
            settled: &field.settled,
            field: &field.cost,
        };
        let mut moves = Moves {
            land,
            params,
            table,
            key,
            near,
            costs,
            flags,
            corridor: matches!(estimate, Estimate::Corridor(..)).then_some(&corridor.inside[..]),
            target,
            steep: query.steep,
            ellipse: query.ellipse,
        };
        let mut open = Open {
            g,
            pred,
            touched,
            heap,
        };
        let m_count = table.moves.len();
        let m1 = m_count + 1;
        for &(r, t) in query.sources {
            open.offer(r * m1 + m_count, t as f32, None, || remaining.at(r));
        }
        let mut popped = 0usize;
        while let Some(e) = open.heap.pop() {
            let (s, gs) = (e.item.state as usize, e.item.g);
            if gs + 1.0 > open.g[s] {
                continue;
            }
            let (x, slot) = (s / m1, s % m1);
            if x == target {
                return Outcome::Found(s);
            }
            popped += 1;
            if budget.is_some_and(|b| popped >= b) {
                return Outcome::OverBudget;
            }
            let xij = land.grid().ij(x);
            for m in 0..m_count {
                if let Some((y, gy)) = moves.step(x, xij, slot, m, gs) {
                    open.offer(y * m1 + m, gy, Some(slot), || remaining.at(y));
                }
            }
        }
        Outcome::Unreachable
    }
}

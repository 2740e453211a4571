//! The road search of one connection (thesis 3.2.4): a backwards search from the goal nodes (road nodes joined
//! to `Ψ`, with their re-use cost `T(r)`) to the building `B` over states (node, incoming move), so that turns
//! can be charged. A first A* runs under the closed-form bound; past [`BOUND_BUDGET`] states the node-level
//! field takes over, and past [`STATE_BUDGET`] the corridor around its path (see the module documentation).
//! The state arrays are kept between connections and reset through the lists of what was touched.

use super::cycles::Ellipse;
use super::heuristic::{Estimate, SourceBound};
use super::move_costs::{cached_cost, near, CostKey, NEAR_OUTSIDE, NEAR_WATER};
use super::moves::{Move, MoveTable};
use super::node_field::{Corridor, NodeField};
use super::MAX_STATES;
use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::search::MinHeap;
use crate::village::encyclopedia::RoadParams;
use crate::village::land::Land;
use std::cmp::Ordering;

/// States the first A* (with the closed-form bound) may settle before the node-level field is computed.
const BOUND_BUDGET: usize = 3_000;
/// States the A* with the node-level field may settle before it keeps to a corridor of
/// [`CORRIDOR_CELLS`](super::node_field::CORRIDOR_CELLS) around the node-level path.
const STATE_BUDGET: usize = 250_000;

/// Node flags of one search.
pub(super) const GOAL: u8 = 1;
pub(super) const BUILDING: u8 = 2;

/// The order among heap entries of equal key in the road searches: the deeper state (larger path cost `g`)
/// first, then the smaller state index.
#[derive(Clone, Copy, Debug)]
pub(super) struct Deeper {
    pub(super) g: f32,
    pub(super) state: u32,
}

impl Deeper {
    pub(super) fn new(g: f32, state: usize) -> Deeper {
        Deeper {
            g,
            state: state as u32,
        }
    }
}

impl Ord for Deeper {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .g
            .total_cmp(&self.g)
            .then(self.state.cmp(&other.state))
    }
}

impl PartialOrd for Deeper {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Deeper {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Deeper {}

/// The land and parameters of one connection.
pub(super) struct Ctx<'a> {
    pub(super) land: &'a Land,
    pub(super) params: &'a RoadParams,
}

/// One search: from `sources` (node, initial cost) to `target`, steeper moves than `max_grade` allowed or not,
/// within an ellipse or not (cycle roads).
#[derive(Clone, Copy)]
pub(super) struct Query<'a> {
    pub(super) ctx: &'a Ctx<'a>,
    pub(super) sources: &'a [(usize, f64)],
    pub(super) target: usize,
    pub(super) steep: bool,
    pub(super) ellipse: Option<Ellipse>,
}

pub(super) enum Outcome {
    Found(usize),
    Unreachable,
    OverBudget,
}

/// The state of the road search kept between connections.
pub(super) struct Search {
    pub(super) grid: Grid,
    pub(super) key: CostKey,
    pub(super) table: MoveTable,
    /// Static cost of move `m` from node `x` at `x * moves + m`: 0 not computed yet, positive within the grade
    /// limit, negative (its opposite) steeper than it, infinite through a node outside `Ω`.
    pub(super) costs: Vec<f32>,
    /// [`NEAR_WATER`] and [`NEAR_OUTSIDE`] within the mask radius of each node: the moves of other nodes need
    /// not look for them.
    pub(super) near: Vec<u8>,
    /// Best path cost plus one of each state (node × (moves + 1), the last slot for sources); 0 = not reached.
    pub(super) g: Vec<f32>,
    /// The incoming move of the state each state was reached from.
    pub(super) pred: Vec<u8>,
    pub(super) touched: Vec<u32>,
    pub(super) heap: MinHeap<Deeper>,
    pub(super) flags: Vec<u8>,
    /// Network cost from each road node to `Ψ` (see `RoadNetwork::exit_costs`; infinite elsewhere), for the
    /// first `exit_nodes` road nodes.
    pub(super) exit: Vec<f64>,
    pub(super) exit_nodes: usize,
    /// Initial cost plus one of each source node (0 = not a source).
    pub(super) source_cost: Vec<f32>,
    /// What the node-level search knows of each node (see [`Search::node_field`]).
    pub(super) field: NodeField,
    /// States the first A* and the A* with the node-level field may settle (see [`BOUND_BUDGET`],
    /// [`STATE_BUDGET`]).
    pub(super) budget: usize,
    pub(super) state_budget: usize,
    /// Nodes near the node-level path, where an A* over [`STATE_BUDGET`] finishes (see [`Search::run`]), or
    /// near the coarse course of a long road (see `coarse`).
    pub(super) corridor: Corridor,
    /// Whether a long road is searched on a coarser land first (see `coarse`; not on that coarser land itself).
    pub(super) coarse_first: bool,
}

/// What landing on `y` by move `mv` from `x` adds to `start`: the building cost of each building node passed
/// over, and of `y` when `charge_end`; `None` when the move passes over a goal node, where a path would have
/// joined the network.
pub(super) fn crossing_charge(
    flags: &[u8],
    x: usize,
    mv: &Move,
    start: f64,
    charge_end: bool,
    building_cost: f64,
) -> Option<f64> {
    let mut charge = start;
    if charge_end {
        charge += building_cost;
    }
    let mut blocked = false;
    for &d in &mv.inner {
        let f = flags[(x as isize + d) as usize];
        blocked |= f & GOAL != 0;
        if f & BUILDING != 0 {
            charge += building_cost;
        }
    }
    (!blocked).then_some(charge)
}

impl Search {
    pub(super) fn new(land: &Land, params: &RoadParams) -> Result<Search> {
        let grid = land.grid();
        let n = grid.len();
        let mut radius = params.mask_radius;
        let table = loop {
            let table = MoveTable::new(grid, radius);
            if n.saturating_mul(table.moves.len() + 1) <= MAX_STATES {
                break table;
            }
            if radius == 1 {
                return Err(Error::invalid(
                    "roads",
                    format!(
                        "a grid of {n} nodes is too large for the road search; use a coarser cell"
                    ),
                ));
            }
            radius -= 1;
        };
        let m = table.moves.len();
        Ok(Search {
            grid: *grid,
            key: CostKey::of(params),
            costs: vec![0.0; n * m],
            near: {
                let outside: Vec<bool> = land.inside().iter().map(|&i| !i).collect();
                let r = radius as usize + 1;
                near(grid, land.water(), r)
                    .into_iter()
                    .zip(near(grid, &outside, r))
                    .map(|(w, o)| if w { NEAR_WATER } else { 0 } | if o { NEAR_OUTSIDE } else { 0 })
                    .collect()
            },
            g: vec![0.0; n * (m + 1)],
            pred: vec![0; n * (m + 1)],
            touched: Vec::new(),
            heap: MinHeap::new(),
            flags: Vec::with_capacity(n),
            exit: vec![f64::INFINITY; n],
            exit_nodes: 0,
            source_cost: vec![0.0; n],
            field: NodeField::new(n),
            budget: BOUND_BUDGET,
            state_budget: STATE_BUDGET,
            corridor: Corridor::new(n),
            coarse_first: true,
            table,
        })
    }

    pub(super) fn fits(&self, params: &RoadParams, grid: &Grid) -> bool {
        self.key == CostKey::of(params) && self.field.cost.len() == grid.len()
    }

    /// The static cost of move `m` from `x` (see `costs`), computed once.
    pub(super) fn cost(&mut self, land: &Land, x: usize, m: usize) -> f32 {
        cached_cost(
            &mut self.costs,
            &self.table,
            &self.key,
            land,
            &self.near,
            x,
            m,
        )
    }

    /// The cheapest path from one of `sources` (node, initial cost) to `target`, as nodes from `target` to the
    /// source, and its cost; `None` when there is none.
    ///
    /// A first A* with the closed-form bound settles the easy cases within a few thousand states. Past that, a
    /// node-level search from the target (turns ignored, so lower bounds) gives the exact cost left wherever it
    /// settles, and the A* restarts with it: the long first roads across rough terrain then expand little more
    /// than their own corridor. The node-level search also tells, on nodes only, that no path exists at all.
    /// Past [`STATE_BUDGET`] states the A* finishes within a corridor (see the module documentation).
    pub(super) fn run(
        &mut self,
        ctx: &Ctx,
        sources: &[(usize, f64)],
        target: usize,
        steep: bool,
        ellipse: Option<Ellipse>,
    ) -> Option<(Vec<usize>, f64)> {
        self.find(&Query {
            ctx,
            sources,
            target,
            steep,
            ellipse,
        })
    }

    /// [`Search::run`] for one query.
    pub(super) fn find(&mut self, query: &Query) -> Option<(Vec<usize>, f64)> {
        let sources = query.sources;
        for &(r, t) in sources {
            let v = t as f32 + 1.0;
            if self.source_cost[r] == 0.0 || v < self.source_cost[r] {
                self.source_cost[r] = v;
            }
        }
        let found = self.along_coarse_course(query).or_else(|| {
            match self.astar(query, Estimate::Bound, Some(self.budget)) {
                Outcome::Found(s) => Some(s),
                Outcome::Unreachable => None,
                Outcome::OverBudget => self.run_on_field(query),
            }
        });
        let path = found.map(|state| (self.backtrack(state), self.g[state] as f64 - 1.0));
        self.reset_states();
        self.field.clear();
        self.corridor.clear();
        for &(r, _) in sources {
            self.source_cost[r] = 0.0;
        }
        path
    }

    /// The A* after the first one ran over its budget: with the node-level field, then, past
    /// [`STATE_BUDGET`], within the corridor around the node-level path. The final state, if any.
    fn run_on_field(&mut self, query: &Query) -> Option<usize> {
        self.reset_states();
        let towards = SourceBound::new(query.ctx.land, query.sources);
        let (stop, source) = self.node_field(query, &towards, false)?;
        let estimate = Estimate::Field(stop, &towards);
        match self.astar(query, estimate, Some(self.state_budget)) {
            Outcome::Found(s) => Some(s),
            Outcome::Unreachable => None,
            Outcome::OverBudget => {
                // forced turns (switchbacks) cost more than the node-level search knows, and every state within
                // that margin is explored: finish near its path
                self.reset_states();
                self.mark_corridor(query.target, source);
                match self.astar(query, Estimate::Corridor(stop, &towards), None) {
                    Outcome::Found(s) => Some(s),
                    _ => None,
                }
            }
        }
    }

    /// The cost of the cheapest path by a plain Dijkstra over the states, to check the A* against.
    #[cfg(test)]
    pub(super) fn dijkstra(&mut self, query: &Query) -> Option<f64> {
        let cost = match self.astar(query, Estimate::Zero, None) {
            Outcome::Found(s) => Some(self.g[s] as f64 - 1.0),
            _ => None,
        };
        self.reset_states();
        cost
    }

    pub(super) fn reset_states(&mut self) {
        for &s in &self.touched {
            self.g[s as usize] = 0.0;
        }
        self.touched.clear();
        self.heap.clear();
    }

    /// The nodes of the path to `state`, from the target back to its source.
    fn backtrack(&self, mut state: usize) -> Vec<usize> {
        let m1 = self.table.moves.len() + 1;
        let mut path = vec![state / m1];
        while state % m1 != m1 - 1 {
            let (x, m) = (state / m1, state % m1);
            let prev = (x as isize - self.table.moves[m].delta) as usize;
            path.push(prev);
            state = prev * m1 + self.pred[state] as usize;
        }
        path
    }
}

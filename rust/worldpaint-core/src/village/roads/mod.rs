//! Connection of every new building to the road network (thesis 3.2.4, "Connection to the Road Network"), after
//! the road generation of Galin et al. 2010 (GPMG10): a weighted anisotropic shortest path on the terrain whose
//! cost is `C(R) = Σ_j w_j g_j(R)`, extended with road re-use and road cycles.
//!
//! **Costs.** A road is a chain of *moves* on the [`Grid`]: grid offsets `(dx, dy)` with coprime coordinates
//! and `max(|dx|, |dy|) ≤ k` (`mask_radius`; k = 1, 2, 3 give 8, 16, 32 moves), so roads are not bound to the
//! eight grid directions. Each move is integrated along its segment, sampled every half cell at most, so a long
//! move cannot jump over a ridge or a river. Per metre (planar) of a sub-segment of grade `g` (rise over run):
//! `distance_weight + slope_weight · (g / max_grade)²`, plus `water_weight` times the water fraction (the
//! bilinear water indicator, integrated). A sub-segment steeper than `max_grade` is forbidden; when no road
//! exists under that rule, a second search allows it at a high finite price (per metre
//! `100 (distance_weight + slope_weight) (g / max_grade)²`) and the connection reports `over_max_grade`. Every node a move lands on or passes over (its closed cell square meets
//! the segment) must be inside `Ω`, and costs `building_cost` when a building or a fortification wall covers it,
//! so roads cross walls only where they must (gates). Turning costs `curvature_weight` per radian between
//! consecutive moves (only a U-turn back along the same move is not allowed), so a search state is (node,
//! incoming move).
//!
//! **Re-use.** The thesis lowers the cost along existing roads by a re-use weight `w_ex ≪ 1`:
//!
//! ```text
//! C'(R) = w_ex · C(R)   if R belongs to a road
//!         C(R)          otherwise
//! ```
//!
//! A path from a building `B` to `Ψ` leaves the ground at the first road node `r` it meets and follows the
//! network from there, so its cost is `C(B → r) + T(r)` with `T(r) = w_ex · (network cost from r to Ψ)`. `T`
//! comes from a Dijkstra over the road nodes (few), brought up to date whenever roads are added. The search runs
//! *backwards*: from every goal node `r` (road nodes joined to `Ψ`, and the connection points, `T = 0`) with the
//! initial cost `T(r)`, towards the single node `B`. A path may not land on or pass over another goal node,
//! which is where a forward path would have joined the network. The new road is the off-road part, from `B` to
//! `r`. A road node is any node a road passes over, up to a cell off its centre line, so the new road's last
//! vertex then moves from `r` onto the centre line of the road it joins (unless that makes its last segment
//! steeper than the grade limit): the two meet at a junction. Left at `r`, the joining ends of over 40 % of the
//! new roads stopped 1–2.5 m short of the road they join, and the network read as a dead end there; near
//! Bayreuth in `tests/real_village_generation.rs` that put 22–23 dead ends in every kilometre of road where the
//! real villages have 2.4–2.8 (now 9–11), in Andorra 6–10 where they have 1.4–2.3 (now 2.8–3.5).
//!
//! **Heuristic.** Towards one target a closed-form bound is cheap:
//! `h(x) = min_{L ≥ L₀} (distance_weight · L + slope_weight / max_grade² · Δh² / L)`, where `L₀` is the length of
//! the shortest chain of mask moves from `x` to `B` on a flat, empty plane (the gauge of the mask's polygon,
//! at least `Δh / max_grade` under the grade limit) and `Δh = |h(x) − h(B)|`. It is admissible: every path of
//! planar length `L ≥ L₀` costs at least `distance_weight · L` plus, since `Σ g² ℓ ≥ (Σ g ℓ)² / L ≥ Δh² / L`
//! (Cauchy–Schwarz), that slope term; curvature, water and building costs are non-negative. It is also
//! consistent (the gauge is a norm, and `Δh² / L` is sub-additive), so each state is settled once.
//!
//! Most connections end within a few thousand states. A long road across rough land does not: the bound ignores
//! the detours the grade limit forces, and every node holds one state per incoming move. Past `BOUND_BUDGET`
//! (3 000) states the search first runs on nodes alone (turns ignored, so its costs are lower bounds): from `B`,
//! an A* towards the sources (each source, or tiles of them, under the same closed-form bound) that goes on until
//! its key passes the cost of its own path with turns added. Its settled nodes then know their exact node-level
//! cost to `B`; any other node `x` costs at least the key reached less the bound from `x` to the sources. Both
//! are admissible, and the state search restarts with them: it then hardly leaves the nodes settled. The node
//! search also tells, cheaply, that no road can reach `B` at all.
//!
//! One case stays costly: when forced turns (switchbacks up a cliff band) make the road dearer than the
//! node-level path by a wide margin, every state within that margin is a candidate. Past `STATE_BUDGET`
//! (250 000) states the search keeps to a corridor of `CORRIDOR_CELLS` (8) around the node-level path, where it
//! is exact; the road is then the cheapest within that corridor (never dearer than the node-level path with its
//! turns), no longer proven the cheapest of all. In the 100-building test village this never happens.
//!
//! **Long roads** (our addition, `coarse.rs`). A building more than 1,000 cells from every goal node (the first
//! road of a town, from the lowest point of the land's border) is joined first on the land sampled every fourth
//! node, then within twelve cells of that coarse course, where the road is again the cheapest within a corridor.
//! Across 3 × 3 km of hills the node-level search alone settled 1.6 of the 2.25 million nodes before it met the
//! connection point (0.9 s); coarse then fine, 0.18 s, for a road 0.9 % dearer.
//!
//! **Cycles.** After the first road to `B`, the closest road node `p` in the cone of half-angle
//! `cycle_angle_degrees` around the direction in which the road arrives at `B` (continuing past `B`), off the
//! road just built and at most `cycle_max_length` away, gets a road from `B` under the same costs; it is built
//! when it is at most `cycle_max_length` long and more than half of its length lies farther than
//! `cycle_min_separation` from the first road serving `B`.
//!
//! **Streets** (our addition). A building that got a road of its own and no cycle may have that road laid on past
//! it, straight ahead, for up to `street_length` metres while the land allows ([`RoadNetwork::lay_street`]):
//! the street the houses that come next front, instead of each getting a road of its own. Road by road, the
//! thesis's network branches once per house beyond its frontage. Near Bayreuth in `tests/real_village_generation.rs`
//! that made 9–11 dead ends and 16–17 junctions per kilometre of road, where the real villages have 2.4–2.8 and
//! 4.1–5.7. The parcels then wrapped the dead ends and turned the corners: 5.4–5.5 contour edges on average. The
//! shipped `farming` type lays streets of 50 m and keeps its houses within 16 m of a road (accessibility
//! `λ_max`, 25 before). That gives 4.6–7.8 dead ends and 12–14 junctions per km, and 4.88–4.99 contour edges
//! (4.80–5.15 over seeds 1–3). Road length per house is 1.01–1.13 of the real, against 1.13–1.16. The price is in
//! the buildings built: Stöckig's fell from 87.6 to 82.6 % of those asked for, its lots narrower along the roads
//! (the others 89–91 and 87 %). Streets alone (40 m) made 1.43–1.47 times the real road per house. Houses kept
//! near the roads alone built 78–84 % and left the network as branched.
//!
//! The search keeps flat arrays over the states (a lazily filled move-cost cache and the path costs; both are
//! zero-initialised, so pages of the grid never searched are never touched). Grids too large for
//! `nodes × (moves + 1)` states within 2²⁶ search with a smaller move mask.
//!
//! | file | part |
//! |---|---|
//! | `mod.rs` | the network: connection points, roads, connecting a building |
//! | `checks.rs` | what the network accepts, the land's fingerprint, snapping `Ψ` |
//! | `grid_lines.rs` | roads as polylines and as grid nodes |
//! | `moves.rs` | the move mask |
//! | `move_costs.rs` | the static cost of a move, cached |
//! | `heuristic.rs` | the closed-form bound, towards one target or many sources |
//! | `search.rs` | the state of the search, its phases |
//! | `astar.rs` | the A* over (node, incoming move) |
//! | `coarse.rs` | long roads: a coarse course first, then the road within its corridor |
//! | `node_field.rs` | the node-level search and its corridor |
//! | `network_costs.rs` | the network cost `T(r)` of re-use |
//! | `cycles.rs` | cycle roads |

mod astar;
mod checks;
mod coarse;
mod cycles;
mod grid_lines;
mod heuristic;
mod move_costs;
mod moves;
mod network_costs;
mod node_field;
mod search;
#[cfg(test)]
mod tests;

use crate::error::{Error, Result};
use crate::geom::finite;
use crate::grid::Grid;
use crate::village::encyclopedia::RoadParams;
use crate::village::land::Land;
use crate::village::road_index::RoadIndex;
use crate::village::Road;
use checks::{land_mark, nearest_inside};
use glam::DVec2;
use grid_lines::{node_polyline, segment_cells};
use search::{Ctx, Search, BUILDING, GOAL};

/// Largest number of search states (nodes × (moves + 1)).
pub(crate) const MAX_STATES: usize = 1 << 26;
/// A grade above `max_grade` costs, per metre, this times `(distance_weight + slope_weight) · (g / max_grade)²`
/// in the search that allows it.
pub(crate) const STEEP_WEIGHT: f64 = 100.0;

/// A village road network: the connection points `Ψ`, the roads, and what the road search keeps between calls.
pub struct RoadNetwork {
    /// The roads: the existing ones first, then those [`RoadNetwork::connect`] added, in order.
    pub roads: Vec<Road>,
    grid: Grid,
    connections: Vec<DVec2>,
    connection_nodes: Vec<usize>,
    /// Nodes under a road (or a connection point).
    on_road: Vec<bool>,
    /// The nodes of `on_road`, in the order they were added.
    road_nodes: Vec<u32>,
    index: RoadIndex,
    /// A fingerprint of the land the network was made on: the cached move costs belong to it.
    land_mark: u64,
    search: Option<Box<Search>>,
}

/// What [`RoadNetwork::connect`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RoadConnection {
    /// Indices in [`RoadNetwork::roads`] of the roads added (the first road, then the cycle road if any).
    pub roads: Vec<usize>,
    /// Whether the building is served by the network (false when nothing can reach it).
    pub reached: bool,
    /// Steepest grade along the new roads, sampled on the terrain.
    pub steepest_grade: f64,
    /// The first road had to be steeper than `max_grade`.
    pub over_max_grade: bool,
    /// A cycle road was added.
    pub cycle: bool,
}

impl Clone for RoadNetwork {
    /// A copy of the network; the search caches are not copied (they are rebuilt on demand).
    fn clone(&self) -> Self {
        RoadNetwork {
            roads: self.roads.clone(),
            grid: self.grid,
            connections: self.connections.clone(),
            connection_nodes: self.connection_nodes.clone(),
            on_road: self.on_road.clone(),
            road_nodes: self.road_nodes.clone(),
            index: self.index.clone(),
            land_mark: self.land_mark,
            search: None,
        }
    }
}

impl std::fmt::Debug for RoadNetwork {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RoadNetwork")
            .field("roads", &self.roads.len())
            .field("connections", &self.connections)
            .field("road_nodes", &self.road_nodes.len())
            .finish()
    }
}

impl RoadNetwork {
    /// A network with the connection points `Ψ` (each snapped to the nearest node inside `Ω`) and the existing
    /// roads (polylines, kept as they are).
    pub fn new(land: &Land, connections: &[DVec2], existing: &[Vec<DVec2>]) -> Result<RoadNetwork> {
        let grid = *land.grid();
        if connections.is_empty() {
            return Err(Error::invalid(
                "roads",
                "at least one connection point to the outside world is needed",
            ));
        }
        let mut network = RoadNetwork {
            roads: Vec::new(),
            grid,
            connections: Vec::new(),
            connection_nodes: Vec::new(),
            on_road: vec![false; grid.len()],
            road_nodes: Vec::new(),
            // every road the network adds lies on its grid; the existing ones may reach beyond it
            index: {
                let (lo, hi) = existing.iter().flatten().filter(|p| finite(**p)).fold(
                    (grid.origin, grid.point(grid.nx - 1, grid.ny - 1)),
                    |(lo, hi), p| (lo.min(*p), hi.max(*p)),
                );
                RoadIndex::over(lo, hi, 4.0 * grid.cell)
            },
            land_mark: land_mark(land),
            search: None,
        };
        for (n, &p) in connections.iter().enumerate() {
            if !finite(p) {
                return Err(Error::invalid(
                    "roads",
                    format!("connection point {} is not finite", n + 1),
                ));
            }
            let node = nearest_inside(land, p).ok_or_else(|| {
                Error::invalid(
                    "roads",
                    format!(
                        "connection point {} ({:.2}, {:.2}) is not inside the village region",
                        n + 1,
                        p.x,
                        p.y
                    ),
                )
            })?;
            network.connection_nodes.push(node);
            network.connections.push(grid.point_of(node));
            network.mark(node);
        }
        for (n, line) in existing.iter().enumerate() {
            if let Some(k) = line.iter().position(|p| !finite(*p)) {
                return Err(Error::invalid(
                    "roads",
                    format!("point {} of existing road {} is not finite", k + 1, n + 1),
                ));
            }
            if line.len() == 1 {
                if let Some((i, j)) = grid.nearest(line[0]) {
                    network.mark(grid.index(i, j));
                }
            }
            for w in line.windows(2) {
                for node in segment_cells(&grid, w[0], w[1]) {
                    network.mark(node);
                }
            }
            network.index.add(line);
            network.roads.push(Road {
                points: line.clone(),
            });
        }
        Ok(network)
    }

    /// The connection points `Ψ` as snapped onto the grid.
    pub fn connections(&self) -> &[DVec2] {
        &self.connections
    }

    /// Distance (m) from `p` to the closest road segment (`f64::INFINITY` when there is none).
    pub fn distance(&self, p: DVec2) -> f64 {
        self.index.distance(p, f64::INFINITY)
    }

    /// [`RoadNetwork::distance`], looking no farther than `max` (`max` beyond it): a short search where only near
    /// roads matter.
    pub fn distance_within(&self, p: DVec2, max: f64) -> f64 {
        self.index.distance(p, max)
    }

    fn mark(&mut self, node: usize) {
        if !self.on_road[node] {
            self.on_road[node] = true;
            self.road_nodes.push(node as u32);
        }
    }

    /// Lays road `road` on past its first point (the building it was built for) by up to `params.street_length`
    /// metres, straight ahead, as far as the land stays inside `Ω`, dry, unwalled, unoccupied, clear of the
    /// other roads and within the grade limit, in whole cells (nothing under two). Returns the metres laid.
    pub fn lay_street(
        &mut self,
        land: &Land,
        params: &RoadParams,
        occupied: &[bool],
        road: usize,
    ) -> f64 {
        let Some(r) = self.roads.get(road) else {
            return 0.0;
        };
        let (Some(&start), Some(&next)) = (r.points.first(), r.points.get(1)) else {
            return 0.0;
        };
        let Some(dir) = (start - next).try_normalize() else {
            return 0.0;
        };
        let grid = self.grid;
        let step = 0.5 * grid.cell;
        // clear of the other roads' corridors, the road's own end behind it aside
        let clear = params.width + grid.cell;
        let mut laid = 0.0;
        let mut previous = land.height_at(start);
        let mut t = step;
        while t <= params.street_length {
            let q = start + dir * t;
            let Some((i, j)) = grid.nearest(q) else {
                break;
            };
            let k = grid.index(i, j);
            let h = land.height_at(q);
            let open = land.inside()[k]
                && land.buildable(k)
                && !occupied[k]
                && self.index.distance(q, clear) >= clear.min(t)
                && (h - previous).abs() <= params.max_grade * step;
            if !open {
                break;
            }
            previous = h;
            laid = t;
            t += step;
        }
        let laid = (laid / grid.cell).floor() * grid.cell;
        if laid < 2.0 * grid.cell {
            return 0.0;
        }
        let end = start + dir * laid;
        for c in segment_cells(&grid, end, start) {
            self.mark(c);
        }
        self.roads[road].points.insert(0, end);
        self.index.add(&[end, start]);
        laid
    }

    /// Adds the connection point `p` (snapped to the nearest node inside `Ω`) to `Ψ`, joined to the network by the
    /// lowest-cost road with re-use (a through road: the way from one connection to the outside world to the
    /// others). Returns that road's connection (`reached` false, and `p` not added, when no road can join it).
    pub fn link_connection(
        &mut self,
        land: &Land,
        params: &RoadParams,
        occupied: &[bool],
        p: DVec2,
    ) -> Result<RoadConnection> {
        let Some(node) = nearest_inside(land, p) else {
            return Ok(RoadConnection::default());
        };
        let connection = if self.on_road[node] {
            RoadConnection {
                reached: true,
                ..RoadConnection::default()
            }
        } else {
            self.connect(land, params, occupied, self.grid.point_of(node), 0.0)?
        };
        if connection.reached {
            self.connection_nodes.push(node);
            self.connections.push(self.grid.point_of(node));
            self.mark(node);
            // the network costs to `Ψ` change everywhere
            if let Some(search) = self.search.as_mut() {
                search.exit_nodes = 0;
            }
        }
        Ok(connection)
    }

    /// Connects a new building at `from` to `Ψ` (3.2.4): the lowest-cost road with re-use of the existing roads,
    /// then a cycle road when one fits. `occupied[k]` is true on the land nodes covered by other buildings.
    ///
    /// A building within `frontage` (m) of a road already linked to `Ψ` is served by that road: its lot fronts
    /// it, and no road is added (otherwise every house along a street would get a dead end of its own).
    pub fn connect(
        &mut self,
        land: &Land,
        params: &RoadParams,
        occupied: &[bool],
        from: DVec2,
        frontage: f64,
    ) -> Result<RoadConnection> {
        if *land.grid() != self.grid || land_mark(land) != self.land_mark {
            return Err(Error::invalid(
                "roads",
                "the land differs from the one the road network was made on",
            ));
        }
        params.validate("roads: params")?;
        if occupied.len() != self.grid.len() {
            return Err(Error::invalid(
                "roads",
                format!(
                    "{} occupancy flags for {} land nodes",
                    occupied.len(),
                    self.grid.len()
                ),
            ));
        }
        if !finite(from) {
            return Err(Error::invalid(
                "roads",
                "the building position is not finite",
            ));
        }
        let Some((bi, bj)) = self.grid.nearest(from) else {
            return Err(Error::invalid(
                "roads",
                format!(
                    "the building at ({:.2}, {:.2}) is outside the village grid",
                    from.x, from.y
                ),
            ));
        };
        let b = self.grid.index(bi, bj);
        if !land.inside()[b] {
            return Ok(RoadConnection::default());
        }
        let mut search = match self.search.take() {
            Some(s) if s.fits(params, &self.grid) => s,
            _ => Box::new(Search::new(land, params)?),
        };
        let result = self.connect_with(&mut search, land, params, occupied, b, frontage);
        self.search = Some(search);
        result
    }

    fn connect_with(
        &mut self,
        search: &mut Search,
        land: &Land,
        params: &RoadParams,
        occupied: &[bool],
        b: usize,
        frontage: f64,
    ) -> Result<RoadConnection> {
        self.exit_costs(search, land);
        let mut sources: Vec<(usize, f64)> = Vec::new();
        search.flags.clear();
        search
            .flags
            .extend(
                occupied
                    .iter()
                    .zip(land.wall())
                    .map(|(&o, &w)| if o || w { BUILDING } else { 0 }),
            );
        for &r in &self.road_nodes {
            let r = r as usize;
            if search.exit[r].is_finite() {
                search.flags[r] |= GOAL;
                sources.push((r, params.reuse_weight * search.exit[r]));
            }
        }
        if search.flags[b] & GOAL != 0 || self.fronts(search, b, frontage) {
            // already on the network
            return Ok(RoadConnection {
                reached: true,
                ..RoadConnection::default()
            });
        }
        let ctx = Ctx { land, params };
        let mut over_max_grade = false;
        let mut path = search.run(&ctx, &sources, b, false, None);
        if path.is_none() {
            path = search.run(&ctx, &sources, b, true, None);
            over_max_grade = path.is_some();
        }
        let Some((path, _)) = path else {
            return Ok(RoadConnection::default());
        };
        let mut connection = RoadConnection {
            reached: true,
            over_max_grade,
            ..RoadConnection::default()
        };
        let before = self.roads.len();
        let first_cells = self.add_road(search, &ctx, &path, &mut connection);
        for &c in &first_cells {
            search.flags[c] |= GOAL;
        }
        self.try_cycle(search, &ctx, b, &path, &first_cells, &mut connection);
        for road in &self.roads[before..] {
            self.index.add(&road.points);
        }
        Ok(connection)
    }

    /// Whether a road node linked to `Ψ` lies within `frontage` of node `b`.
    fn fronts(&self, search: &Search, b: usize, frontage: f64) -> bool {
        if !(frontage > 0.0) {
            return false;
        }
        let grid = self.grid;
        let (bi, bj) = grid.ij(b);
        let r = (frontage / grid.cell).floor() as usize;
        let p = grid.point_of(b);
        (bj.saturating_sub(r)..=(bj + r).min(grid.ny - 1)).any(|j| {
            (bi.saturating_sub(r)..=(bi + r).min(grid.nx - 1)).any(|i| {
                let k = grid.index(i, j);
                search.flags[k] & GOAL != 0 && grid.point_of(k).distance(p) <= frontage
            })
        })
    }

    /// Adds the road along `path` (nodes from `B` on), marks the nodes it covers; returns them.
    fn add_road(
        &mut self,
        search: &Search,
        ctx: &Ctx,
        path: &[usize],
        connection: &mut RoadConnection,
    ) -> Vec<usize> {
        let grid = self.grid;
        let mut cells = Vec::new();
        for w in path.windows(2) {
            if let Some(m) = search.table.move_between(&grid, w[0], w[1]) {
                let mv = &search.table.moves[m];
                connection.steepest_grade =
                    connection.steepest_grade.max(mv.steepest(ctx.land, w[0]));
                for &d in &mv.cells {
                    cells.push((w[0] as isize + d) as usize);
                }
            }
        }
        cells.sort_unstable();
        cells.dedup();
        for &c in &cells {
            self.mark(c);
        }
        let mut points = node_polyline(&grid, path);
        // the node the road joins the network at lies beside the road it joins (a road puts the nodes it passes
        // over on the network), up to a cell off its centre line: the road's last vertex moves onto that centre
        // line, so the two meet instead of leaving the end a dead end a metre or two short of the junction, unless
        // that would make its last segment steeper than the grade limit
        let n = points.len();
        if n >= 2 {
            let (before, end) = (points[n - 2], points[n - 1]);
            let reach = grid.cell * std::f64::consts::SQRT_2;
            if let Some(foot) = self.index.nearest(end, reach).map(|p| p.point) {
                let grade = |a: DVec2, b: DVec2| {
                    (ctx.land.height_at(b) - ctx.land.height_at(a)).abs() / a.distance(b).max(1e-9)
                };
                if foot.distance(before) > 1e-9
                    && grade(before, foot) <= ctx.params.max_grade.max(grade(before, end))
                {
                    points[n - 1] = foot;
                }
            }
        }
        connection.roads.push(self.roads.len());
        self.roads.push(Road { points });
        cells
    }
}

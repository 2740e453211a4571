//! Connection of every new building to the road network (thesis 3.2.4, "Connection to the Road Network"), after
//! the road generation of Galin et al. 2010 (GPMG10): a weighted anisotropic shortest path on the terrain whose
//! cost is `C(R) = Σ_j w_j g_j(R)`, extended with road re-use and road cycles.
//!
//! **Costs.** A road is a chain of *moves* on the [`LandGrid`]: grid offsets `(dx, dy)` with coprime coordinates
//! and `max(|dx|, |dy|) ≤ k` (`mask_radius`; k = 1, 2, 3 give 8, 16, 32 moves), so roads are not bound to the
//! eight grid directions. Each move is integrated along its segment, sampled every half cell at most, so a long
//! move cannot jump over a ridge or a river. Per metre (planar) of a sub-segment of grade `g` (rise over run):
//! `distance_weight + slope_weight · (g / max_grade)²`, plus `water_weight` times the water fraction (the
//! bilinear water indicator, integrated). A sub-segment steeper than `max_grade` is forbidden; when no road
//! exists under that rule, a second search allows it at a high finite price (see [`STEEP_WEIGHT`]) and the
//! connection reports `over_max_grade`. Every node a move lands on or passes over (its closed cell square meets
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
//! `r`.
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
//! **Cycles.** After the first road to `B`, the closest road node `p` in the cone of half-angle
//! `cycle_angle_degrees` around the direction in which the road arrives at `B` (continuing past `B`), off the
//! road just built and at most `cycle_max_length` away, gets a road from `B` under the same costs; it is built
//! when it is at most `cycle_max_length` long and more than half of its length lies farther than
//! `cycle_min_separation` from the first road serving `B`.
//!
//! The search keeps flat arrays over the states (a lazily filled move-cost cache and the path costs; both are
//! zero-initialised, so pages of the grid never searched are never touched). Grids too large for
//! `nodes × (moves + 1)` states within [`MAX_STATES`] search with a smaller move mask.

use crate::error::{Error, Result};
use crate::graph::SegmentIndex;
use crate::village::encyclopedia::RoadParams;
use crate::village::land::{Land, LandGrid};
use crate::village::Road;
use glam::DVec2;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Largest number of search states (nodes × (moves + 1)).
pub const MAX_STATES: usize = 1 << 26;
/// A grade above `max_grade` costs, per metre, this times `(distance_weight + slope_weight) · (g / max_grade)²`
/// in the search that allows it.
pub const STEEP_WEIGHT: f64 = 100.0;
/// Sharpest turn between two consecutive moves (radians): anything but going straight back. A hairpin of a
/// serpentine on a steep slope turns between two moves close to the contour lines, up to 180° minus the
/// smallest angle between two moves of the mask.
const MAX_TURN: f64 = std::f64::consts::PI - 1e-6;
/// Up to this many sources, the node-level search is an A* towards each of them; beyond, towards tiles of them,
/// at most this many.
const FEW_SOURCES: usize = 32;
const MAX_SOURCE_TILES: usize = 48;
/// States the first A* (with the closed-form bound) may settle before the node-level field is computed.
const BOUND_BUDGET: usize = 3_000;
/// States the A* with the node-level field may settle before it keeps to a corridor of [`CORRIDOR_CELLS`]
/// around the node-level path.
const STATE_BUDGET: usize = 250_000;
const CORRIDOR_CELLS: usize = 8;
/// A cycle road is built when more than this fraction of its length is far enough from the first road.
const CYCLE_FAR_FRACTION: f64 = 0.5;
/// The direction in which a road arrives at `B` is taken over this length (m) of the road.
const ARRIVAL_LENGTH: f64 = 10.0;
/// A connection point snaps to an inside node at most this many cells away.
const CONNECTION_SNAP_CELLS: i64 = 3;

/// Node flags of one search.
const GOAL: u8 = 1;
const BUILDING: u8 = 2;
/// Node surroundings, for the move costs.
const NEAR_WATER: u8 = 1;
const NEAR_OUTSIDE: u8 = 2;

/// A village road network: the connection points `Ψ`, the roads, and what the road search keeps between calls.
pub struct RoadNetwork {
    pub roads: Vec<Road>,
    grid: LandGrid,
    connections: Vec<DVec2>,
    connection_nodes: Vec<usize>,
    /// Nodes under a road (or a connection point).
    on_road: Vec<bool>,
    /// The nodes of `on_road`, in the order they were added.
    road_nodes: Vec<u32>,
    index: SegmentIndex,
    /// A fingerprint of the land the network was made on: the cached move costs belong to it.
    land_mark: u64,
    search: Option<Box<Search>>,
}

/// What [`RoadNetwork::connect`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Connection {
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

fn invalid(what: String) -> Error {
    Error::InvalidInput(what)
}

fn finite(p: DVec2) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

impl RoadNetwork {
    /// A network with the connection points `Ψ` (each snapped to the nearest node inside `Ω`) and the existing
    /// roads (polylines, kept as they are).
    pub fn new(land: &Land, connections: &[DVec2], existing: &[Vec<DVec2>]) -> Result<RoadNetwork> {
        check_land(land)?;
        let grid = land.grid;
        if connections.is_empty() {
            return Err(invalid(
                "roads: at least one connection point to the outside world is needed".into(),
            ));
        }
        let mut network = RoadNetwork {
            roads: Vec::new(),
            grid,
            connections: Vec::new(),
            connection_nodes: Vec::new(),
            on_road: vec![false; grid.len()],
            road_nodes: Vec::new(),
            index: SegmentIndex::default(),
            land_mark: land_mark(land),
            search: None,
        };
        for (n, &p) in connections.iter().enumerate() {
            if !finite(p) {
                return Err(invalid(format!(
                    "roads: connection point {} is not finite",
                    n + 1
                )));
            }
            let node = nearest_inside(land, p).ok_or_else(|| {
                invalid(format!(
                    "roads: connection point {} ({:.2}, {:.2}) is not inside the village region",
                    n + 1,
                    p.x,
                    p.y
                ))
            })?;
            network.connection_nodes.push(node);
            network.connections.push(grid.point_of(node));
            network.mark(node);
        }
        for (n, line) in existing.iter().enumerate() {
            if let Some(k) = line.iter().position(|p| !finite(*p)) {
                return Err(invalid(format!(
                    "roads: point {} of existing road {} is not finite",
                    k + 1,
                    n + 1
                )));
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
            network.roads.push(Road {
                points: line.clone(),
            });
        }
        network.rebuild_index();
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

    fn mark(&mut self, node: usize) {
        if !self.on_road[node] {
            self.on_road[node] = true;
            self.road_nodes.push(node as u32);
        }
    }

    fn rebuild_index(&mut self) {
        let segments: Vec<(DVec2, DVec2)> = self
            .roads
            .iter()
            .flat_map(|r| r.points.windows(2).map(|w| (w[0], w[1])))
            .collect();
        self.index = SegmentIndex::new(segments);
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
    ) -> Result<Connection> {
        check_land(land)?;
        if land.grid != self.grid || land_mark(land) != self.land_mark {
            return Err(invalid(
                "roads: the land differs from the one the road network was made on".into(),
            ));
        }
        check_params(params)?;
        if occupied.len() != self.grid.len() {
            return Err(invalid(format!(
                "roads: {} occupancy flags for {} land nodes",
                occupied.len(),
                self.grid.len()
            )));
        }
        if !finite(from) {
            return Err(invalid("roads: the building position is not finite".into()));
        }
        let Some((bi, bj)) = self.grid.nearest(from) else {
            return Err(invalid(format!(
                "roads: the building at ({:.2}, {:.2}) is outside the village grid",
                from.x, from.y
            )));
        };
        let b = self.grid.index(bi, bj);
        if !land.inside[b] {
            return Ok(Connection::default());
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
    ) -> Result<Connection> {
        self.exit_costs(search, land);
        let mut sources: Vec<(usize, f64)> = Vec::new();
        search.flags.clear();
        search.flags.extend(
            occupied
                .iter()
                .zip(&land.wall)
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
            return Ok(Connection {
                reached: true,
                ..Connection::default()
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
            return Ok(Connection::default());
        };
        let mut connection = Connection {
            reached: true,
            over_max_grade,
            ..Connection::default()
        };
        let first_cells = self.add_road(search, &ctx, &path, &mut connection);
        for &c in &first_cells {
            search.flags[c] |= GOAL;
        }
        self.try_cycle(search, &ctx, b, &path, &first_cells, &mut connection);
        self.rebuild_index();
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
        connection: &mut Connection,
    ) -> Vec<usize> {
        let grid = self.grid;
        let mut cells = Vec::new();
        for w in path.windows(2) {
            if let Some(m) = search.table.move_between(&grid, w[0], w[1]) {
                let mv = &search.table.moves[m];
                connection.steepest_grade = connection
                    .steepest_grade
                    .max(steepest_on_move(ctx.land, mv, w[0]));
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
        let points = polyline(&grid, path);
        connection.roads.push(self.roads.len());
        self.roads.push(Road { points });
        cells
    }

    /// The thesis' cycle step: a second road from `B` to the closest road node ahead of it, when it is short
    /// enough and keeps away from the first road.
    fn try_cycle(
        &mut self,
        search: &mut Search,
        ctx: &Ctx,
        b: usize,
        first: &[usize],
        first_cells: &[usize],
        connection: &mut Connection,
    ) {
        let params = ctx.params;
        if params.cycle_max_length <= 0.0 {
            return;
        }
        let grid = self.grid;
        let first_line = polyline(&grid, first);
        let bp = grid.point_of(b);
        let Some(axis) = arrival_direction(&first_line) else {
            return;
        };
        let cos_max = params
            .cycle_angle_degrees
            .to_radians()
            .min(std::f64::consts::PI)
            .cos();
        let mut best: Option<(f64, usize)> = None;
        for &r in &self.road_nodes {
            let r = r as usize;
            if search.flags[r] & GOAL == 0 || first_cells.binary_search(&r).is_ok() {
                continue;
            }
            let d = grid.point_of(r) - bp;
            let dist = d.length();
            if dist <= 0.0 || dist > params.cycle_max_length || d.dot(axis) < cos_max * dist {
                continue;
            }
            if best.is_none_or(|(bd, _)| dist < bd) {
                best = Some((dist, r));
            }
        }
        let Some((_, p)) = best else {
            return;
        };
        let ellipse = Ellipse {
            a: bp,
            b: grid.point_of(p),
            length: params.cycle_max_length,
        };
        let Some((path, _)) = search.run(ctx, &[(p, 0.0)], b, false, Some(ellipse)) else {
            return;
        };
        let line = polyline(&grid, &path);
        let length: f64 = line.windows(2).map(|w| w[0].distance(w[1])).sum();
        if length > params.cycle_max_length
            || far_fraction(&line, &first_line, params.cycle_min_separation, grid.cell)
                <= CYCLE_FAR_FRACTION
        {
            return;
        }
        let mut cycle = Connection::default();
        self.add_road(search, ctx, &path, &mut cycle);
        connection.roads.extend(cycle.roads);
        connection.steepest_grade = connection.steepest_grade.max(cycle.steepest_grade);
        connection.cycle = true;
    }

    /// Network cost from every road node to `Ψ` along the roads (without the re-use weight; `INFINITY` off the
    /// network or on roads not joined to `Ψ`): a Dijkstra over the road nodes, eight-connected. Roads are only
    /// ever added, so after the first time only the new road nodes and what they shorten are visited.
    fn exit_costs(&self, search: &mut Search, land: &Land) {
        let mut exit = std::mem::take(&mut search.exit);
        let mut heap = BinaryHeap::new();
        if search.exit_nodes == 0 {
            for &r in &self.road_nodes {
                exit[r as usize] = f64::INFINITY;
            }
            for &c in &self.connection_nodes {
                exit[c] = 0.0;
                heap.push(Entry {
                    f: 0.0,
                    g: 0.0,
                    state: c as u32,
                });
            }
        } else {
            for &r in &self.road_nodes[search.exit_nodes..] {
                let r = r as usize;
                for u in 0..search.table.unit.len() {
                    if let Some((y, c)) = self.road_edge(search, land, r, search.table.unit[u]) {
                        exit[r] = exit[r].min(exit[y] + c);
                    }
                }
                if exit[r].is_finite() {
                    heap.push(Entry {
                        f: exit[r],
                        g: 0.0,
                        state: r as u32,
                    });
                }
            }
        }
        while let Some(e) = heap.pop() {
            let x = e.state as usize;
            if e.f > exit[x] {
                continue;
            }
            for u in 0..search.table.unit.len() {
                let Some((y, c)) = self.road_edge(search, land, x, search.table.unit[u]) else {
                    continue;
                };
                let g = e.f + c;
                if g < exit[y] {
                    exit[y] = g;
                    heap.push(Entry {
                        f: g,
                        g: 0.0,
                        state: y as u32,
                    });
                }
            }
        }
        search.exit = exit;
        search.exit_nodes = self.road_nodes.len();
    }

    /// The road node one move `m` from road node `x`, and the cost of going there (the same both ways).
    fn road_edge(
        &self,
        search: &mut Search,
        land: &Land,
        x: usize,
        m: usize,
    ) -> Option<(usize, f64)> {
        let grid = &self.grid;
        let (i, j) = grid.ij(x);
        let mv = &search.table.moves[m];
        let (ti, tj) = (i as i64 + mv.dx as i64, j as i64 + mv.dy as i64);
        if ti < 0 || tj < 0 || ti >= grid.nx as i64 || tj >= grid.ny as i64 {
            return None;
        }
        let y = (x as isize + mv.delta) as usize;
        if !self.on_road[y] {
            return None;
        }
        let c = search.cost(land, x, m);
        if c.is_infinite() {
            return None;
        }
        // a road steeper than the limit exists: it costs what its length and slope cost, no penalty
        let c = if c < 0.0 {
            let mv = &search.table.moves[m];
            static_cost(land, &search.key, mv, x, search.near[x], false)
        } else {
            c
        };
        Some((y, c as f64))
    }
}

/// The direction (unit) in which a road `B = line[0], ...` arrives at `B`, over its last few metres.
fn arrival_direction(line: &[DVec2]) -> Option<DVec2> {
    let b = *line.first()?;
    let mut walked = 0.0;
    let mut at = b;
    for w in line.windows(2) {
        let l = w[0].distance(w[1]);
        if walked + l >= ARRIVAL_LENGTH {
            at = w[0] + (w[1] - w[0]) * ((ARRIVAL_LENGTH - walked) / l);
            break;
        }
        walked += l;
        at = w[1];
    }
    (b - at).try_normalize()
}

/// Fraction of the length of `line` farther than `separation` from `other`, sampled every half cell.
fn far_fraction(line: &[DVec2], other: &[DVec2], separation: f64, cell: f64) -> f64 {
    let (mut far, mut total) = (0.0, 0.0);
    let step = 0.5 * cell;
    for w in line.windows(2) {
        let l = w[0].distance(w[1]);
        let n = (l / step).ceil().max(1.0) as usize;
        for s in 0..n {
            let p = w[0] + (w[1] - w[0]) * ((s as f64 + 0.5) / n as f64);
            let d = other
                .windows(2)
                .map(|o| crate::geom::segment_distance(p, o[0], o[1]))
                .fold(f64::INFINITY, f64::min);
            total += l / n as f64;
            if d > separation {
                far += l / n as f64;
            }
        }
    }
    if total > 0.0 {
        far / total
    } else {
        0.0
    }
}

/// The turning vertices of a node path (collinear moves merged).
fn polyline(grid: &LandGrid, path: &[usize]) -> Vec<DVec2> {
    let mut points = Vec::new();
    let step = |a: usize, b: usize| {
        let (ai, aj) = grid.ij(a);
        let (bi, bj) = grid.ij(b);
        (bi as i64 - ai as i64, bj as i64 - aj as i64)
    };
    for (k, &n) in path.iter().enumerate() {
        let keep = k == 0 || k + 1 == path.len() || step(path[k - 1], n) != step(n, path[k + 1]);
        if keep {
            points.push(grid.point_of(n));
        }
    }
    points
}

/// Steepest sub-segment grade along a move.
fn steepest_on_move(land: &Land, mv: &Move, x: usize) -> f64 {
    let sub = mv.length / (mv.samples.len() - 1) as f64;
    let mut prev = sample(&land.height, x, &mv.samples[0]);
    let mut steepest: f64 = 0.0;
    for s in &mv.samples[1..] {
        let h = sample(&land.height, x, s);
        steepest = steepest.max((h - prev).abs() / sub);
        prev = h;
    }
    steepest
}

/// A fingerprint of the grid and of a sample of the land's nodes (every 31st), cheap enough for every call.
fn land_mark(land: &Land) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |v: u64| {
        h ^= v;
        h = h.wrapping_mul(0x0100_0000_01b3);
    };
    let g = &land.grid;
    for v in [
        g.nx as u64,
        g.ny as u64,
        g.cell.to_bits(),
        g.origin.x.to_bits(),
        g.origin.y.to_bits(),
    ] {
        eat(v);
    }
    for k in (0..g.len()).step_by(31) {
        let flags = land.inside[k] as u64
            | (land.water[k] as u64) << 1
            | (land.wall[k] as u64) << 2
            | (land.fortified[k] as u64) << 3;
        eat((land.height[k].to_bits() as u64) << 4 | flags);
    }
    h
}

fn check_land(land: &Land) -> Result<()> {
    let n = land.grid.len();
    if land.height.len() != n
        || land.inside.len() != n
        || land.water.len() != n
        || land.wall.len() != n
        || land.fortified.len() != n
    {
        return Err(invalid(format!(
            "roads: the land's maps do not all have the {n} nodes of its grid"
        )));
    }
    if land.grid.nx < 2 || land.grid.ny < 2 || !(land.grid.cell.is_finite() && land.grid.cell > 0.0)
    {
        return Err(invalid("roads: the land grid is degenerate".into()));
    }
    Ok(())
}

fn check_params(p: &RoadParams) -> Result<()> {
    for (name, v) in [
        ("distance_weight", p.distance_weight),
        ("max_grade", p.max_grade),
        ("reuse_weight", p.reuse_weight),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(invalid(format!("roads: {name} must be positive, got {v}")));
        }
    }
    for (name, v) in [
        ("slope_weight", p.slope_weight),
        ("curvature_weight", p.curvature_weight),
        ("water_weight", p.water_weight),
        ("building_cost", p.building_cost),
        ("cycle_angle_degrees", p.cycle_angle_degrees),
        ("cycle_max_length", p.cycle_max_length),
        ("cycle_min_separation", p.cycle_min_separation),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(invalid(format!(
                "roads: {name} must be zero or more, got {v}"
            )));
        }
    }
    if p.reuse_weight > 1.0 {
        return Err(invalid(format!(
            "roads: reuse_weight must be at most 1, got {}",
            p.reuse_weight
        )));
    }
    if !(1..=8).contains(&p.mask_radius) {
        return Err(invalid(format!(
            "roads: mask_radius must be 1 to 8, got {}",
            p.mask_radius
        )));
    }
    Ok(())
}

/// The inside node nearest to `p`, within [`CONNECTION_SNAP_CELLS`] cells.
fn nearest_inside(land: &Land, p: DVec2) -> Option<usize> {
    let g = &land.grid;
    let f = (p - g.origin) / g.cell;
    let (ci, cj) = (f.x.round(), f.y.round());
    let r = CONNECTION_SNAP_CELLS as f64;
    if !(ci >= -r && cj >= -r && ci <= (g.nx - 1) as f64 + r && cj <= (g.ny - 1) as f64 + r) {
        return None;
    }
    let (ci, cj) = (ci as i64, cj as i64);
    let mut best: Option<(f64, usize)> = None;
    for j in cj - CONNECTION_SNAP_CELLS..=cj + CONNECTION_SNAP_CELLS {
        for i in ci - CONNECTION_SNAP_CELLS..=ci + CONNECTION_SNAP_CELLS {
            if i < 0 || j < 0 || i >= g.nx as i64 || j >= g.ny as i64 {
                continue;
            }
            let k = g.index(i as usize, j as usize);
            let d = g.point_of(k).distance(p);
            if land.inside[k] && d <= r * g.cell && best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, k));
            }
        }
    }
    best.map(|(_, k)| k)
}

/// The nodes whose closed cell square meets the segment `a`–`b` (world XY), clipped to the grid.
fn segment_cells(grid: &LandGrid, a: DVec2, b: DVec2) -> Vec<usize> {
    let fa = (a - grid.origin) / grid.cell;
    let fb = (b - grid.origin) / grid.cell;
    let lo = DVec2::splat(-0.5);
    let hi = DVec2::new(grid.nx as f64 - 0.5, grid.ny as f64 - 0.5);
    let Some((t0, t1)) = clip(fa, fb, lo, hi) else {
        return Vec::new();
    };
    let (pa, pb) = (fa + (fb - fa) * t0, fa + (fb - fa) * t1);
    let mut cells: Vec<usize> = Vec::new();
    let n = ((pb - pa).length() * 4.0).ceil().max(1.0) as usize;
    for s in 0..=n {
        let q = pa + (pb - pa) * (s as f64 / n as f64);
        let (qi, qj) = (q.x.round() as i64, q.y.round() as i64);
        for j in qj - 1..=qj + 1 {
            for i in qi - 1..=qi + 1 {
                if i < 0 || j < 0 || i >= grid.nx as i64 || j >= grid.ny as i64 {
                    continue;
                }
                let c = DVec2::new(i as f64, j as f64);
                if clip(pa, pb, c - 0.5 - 1e-9, c + 0.5 + 1e-9).is_some() {
                    cells.push(grid.index(i as usize, j as usize));
                }
            }
        }
    }
    cells.sort_unstable();
    cells.dedup();
    cells
}

/// Liang–Barsky: the parameter range of `a + t (b − a)`, `t ∈ [0, 1]`, inside the closed box `lo..hi`.
fn clip(a: DVec2, b: DVec2, lo: DVec2, hi: DVec2) -> Option<(f64, f64)> {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x - lo.x),
        (d.x, hi.x - a.x),
        (-d.y, a.y - lo.y),
        (d.y, hi.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

// ---------------------------------------------------------------------------------------------------------------
// The move mask

/// A bilinear sample along a move: four (node offset, weight) taps, unused ones of weight 0 on the start node.
#[derive(Clone, Copy, Debug)]
struct Sample {
    taps: [(isize, f64); 4],
}

fn sample(values: &[f32], x: usize, s: &Sample) -> f64 {
    s.taps
        .iter()
        .map(|&(d, w)| values[(x as isize + d) as usize] as f64 * w)
        .sum()
}

fn sample_bool(values: &[bool], x: usize, s: &Sample) -> f64 {
    s.taps
        .iter()
        .map(|&(d, w)| {
            if values[(x as isize + d) as usize] {
                w
            } else {
                0.0
            }
        })
        .sum()
}

#[derive(Clone, Debug)]
struct Move {
    dx: i32,
    dy: i32,
    /// Index offset of the end node.
    delta: isize,
    /// Planar length (m).
    length: f64,
    /// Index offsets of the nodes whose closed cell square meets the segment, both ends included.
    cells: Vec<isize>,
    /// Those without the two ends.
    inner: Vec<isize>,
    /// Samples at most half a cell apart, both ends included.
    samples: Vec<Sample>,
}

/// The move mask of one grid and radius, with the turn angles and the heuristic's gauge.
#[derive(Clone, Debug)]
struct MoveTable {
    moves: Vec<Move>,
    /// `rev[m]` is the move opposite `m`.
    rev: Vec<usize>,
    /// The moves of length one cell or one diagonal.
    unit: Vec<usize>,
    /// Turn angle (radians) from move `a` to move `b` at `a * moves + b`.
    turn: Vec<f64>,
    /// Facets `c` of the mask's gauge in the first octant: `gauge(v) = max c·v` for `v.x ≥ v.y ≥ 0` (cells).
    facets: Vec<DVec2>,
}

fn gcd(a: i32, b: i32) -> i32 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

impl MoveTable {
    fn new(grid: &LandGrid, radius: u32) -> MoveTable {
        let k = radius as i32;
        let mut offsets: Vec<(i32, i32)> = Vec::new();
        for dy in -k..=k {
            for dx in -k..=k {
                if (dx, dy) != (0, 0) && gcd(dx.abs(), dy.abs()) == 1 {
                    offsets.push((dx, dy));
                }
            }
        }
        offsets.sort_by(|a, b| {
            (a.1 as f64)
                .atan2(a.0 as f64)
                .total_cmp(&(b.1 as f64).atan2(b.0 as f64))
        });
        let nx = grid.nx as isize;
        let moves: Vec<Move> = offsets
            .iter()
            .map(|&(dx, dy)| {
                let end = DVec2::new(dx as f64, dy as f64);
                let mut cells = Vec::new();
                let mut inner = Vec::new();
                for j in dy.min(0)..=dy.max(0) {
                    for i in dx.min(0)..=dx.max(0) {
                        let c = DVec2::new(i as f64, j as f64);
                        if clip(DVec2::ZERO, end, c - 0.5 - 1e-9, c + 0.5 + 1e-9).is_some() {
                            let d = j as isize * nx + i as isize;
                            cells.push(d);
                            if (i, j) != (0, 0) && (i, j) != (dx, dy) {
                                inner.push(d);
                            }
                        }
                    }
                }
                let n = (2.0 * end.length()).ceil() as usize;
                let samples = (0..=n)
                    .map(|s| {
                        let q =
                            DVec2::new((dx * s as i32) as f64, (dy * s as i32) as f64) / n as f64;
                        let (fx, fy) = (q.x.floor(), q.y.floor());
                        let (tx, ty) = (q.x - fx, q.y - fy);
                        let mut taps = [(0, 0.0); 4];
                        for (t, (oi, oj, w)) in [
                            (0, 0, (1.0 - tx) * (1.0 - ty)),
                            (1, 0, tx * (1.0 - ty)),
                            (0, 1, (1.0 - tx) * ty),
                            (1, 1, tx * ty),
                        ]
                        .into_iter()
                        .enumerate()
                        {
                            // a zero weight may lie off the grid: leave it on the start node
                            if w > 1e-12 {
                                taps[t] = ((fy as isize + oj) * nx + fx as isize + oi, w);
                            }
                        }
                        Sample { taps }
                    })
                    .collect();
                Move {
                    dx,
                    dy,
                    delta: dy as isize * nx + dx as isize,
                    length: end.length() * grid.cell,
                    cells,
                    inner,
                    samples,
                }
            })
            .collect();
        let m = moves.len();
        let rev = (0..m)
            .map(|a| {
                (0..m)
                    .find(|&b| moves[b].dx == -moves[a].dx && moves[b].dy == -moves[a].dy)
                    .unwrap_or(a)
            })
            .collect();
        let unit = (0..m)
            .filter(|&a| moves[a].dx.abs() <= 1 && moves[a].dy.abs() <= 1)
            .collect();
        let mut turn = vec![0.0; m * m];
        for a in 0..m {
            for b in 0..m {
                let u = DVec2::new(moves[a].dx as f64, moves[a].dy as f64);
                let v = DVec2::new(moves[b].dx as f64, moves[b].dy as f64);
                turn[a * m + b] = crate::graph::angle_between(u, v);
            }
        }
        // first-octant directions, by increasing angle, as unit vectors
        let mut octant: Vec<DVec2> = offsets
            .iter()
            .filter(|&&(dx, dy)| dx >= dy && dy >= 0)
            .map(|&(dx, dy)| DVec2::new(dx as f64, dy as f64).normalize())
            .collect();
        octant.sort_by(|a, b| a.y.atan2(a.x).total_cmp(&b.y.atan2(b.x)));
        let facets = octant
            .windows(2)
            .map(|w| {
                // c·w0 = c·w1 = 1
                let det = w[0].x * w[1].y - w[0].y * w[1].x;
                DVec2::new((w[1].y - w[0].y) / det, (w[0].x - w[1].x) / det)
            })
            .collect();
        MoveTable {
            moves,
            rev,
            unit,
            turn,
            facets,
        }
    }

    /// Length (cells) of the shortest chain of mask moves, with real multiplicities, covering `v` (cells).
    fn gauge(&self, v: DVec2) -> f64 {
        let (a, b) = (v.x.abs(), v.y.abs());
        let w = DVec2::new(a.max(b), a.min(b));
        self.facets.iter().map(|c| c.dot(w)).fold(w.x, f64::max)
    }

    /// The move from node `a` to node `b`, if they are one move apart.
    fn move_between(&self, grid: &LandGrid, a: usize, b: usize) -> Option<usize> {
        let (ai, aj) = grid.ij(a);
        let (bi, bj) = grid.ij(b);
        let (dx, dy) = (bi as i64 - ai as i64, bj as i64 - aj as i64);
        self.moves
            .iter()
            .position(|m| m.dx as i64 == dx && m.dy as i64 == dy)
    }
}

// ---------------------------------------------------------------------------------------------------------------
// The search

/// A heap entry: estimated total `f`, path cost `g`, state; the smallest `f` pops first (deeper on ties).
#[derive(Clone, Copy, Debug)]
struct Entry {
    f: f64,
    g: f32,
    state: u32,
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Entry {}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .f
            .total_cmp(&self.f)
            .then(self.g.total_cmp(&other.g))
            .then(other.state.cmp(&self.state))
    }
}

struct Ctx<'a> {
    land: &'a Land,
    params: &'a RoadParams,
}

/// The points through which a path between the foci `a` and `b` is at most `length` long.
#[derive(Clone, Copy, Debug)]
struct Ellipse {
    a: DVec2,
    b: DVec2,
    length: f64,
}

impl Ellipse {
    fn excludes(&self, q: DVec2) -> bool {
        q.distance(self.a) + q.distance(self.b) > self.length
    }
}

/// The closed-form lower bound of the module documentation on the cost of any path between two nodes.
struct Bound<'a> {
    land: &'a Land,
    table: &'a MoveTable,
    distance_weight: f64,
    /// `slope_weight / max_grade²`.
    slope: f64,
    max_grade: f64,
    steep: bool,
}

impl Bound<'_> {
    fn new<'a>(land: &'a Land, table: &'a MoveTable, p: &RoadParams, steep: bool) -> Bound<'a> {
        Bound {
            land,
            table,
            distance_weight: p.distance_weight,
            slope: p.slope_weight / (p.max_grade * p.max_grade),
            max_grade: p.max_grade,
            steep,
        }
    }

    fn between(&self, a: usize, b: usize) -> f64 {
        let g = &self.land.grid;
        let (ai, aj) = g.ij(a);
        let (bi, bj) = g.ij(b);
        let v = DVec2::new(ai as f64 - bi as f64, aj as f64 - bj as f64);
        let dh = (self.land.height[a] as f64 - self.land.height[b] as f64).abs();
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
    fn to_sources(&self, x: usize, sources: &SourceBound) -> f64 {
        match sources {
            SourceBound::Nodes(few) => few
                .iter()
                .map(|&(r, t)| t + self.between(x, r))
                .fold(f64::INFINITY, f64::min),
            SourceBound::Tiles(tiles) => {
                let g = &self.land.grid;
                let (i, j) = g.ij(x);
                let (q, h) = (DVec2::new(i as f64, j as f64), self.land.height[x] as f64);
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
enum SourceBound {
    /// A few sources (node, initial cost).
    Nodes(Vec<(usize, f64)>),
    /// Many sources, gathered in tiles.
    Tiles(Vec<SourceTile>),
}

/// Sources of one tile: the box of their nodes (grid units), their lowest initial cost, their heights.
struct SourceTile {
    min: DVec2,
    max: DVec2,
    cost: f64,
    low: f64,
    high: f64,
}

impl SourceBound {
    fn new(land: &Land, sources: &[(usize, f64)]) -> SourceBound {
        if sources.len() <= FEW_SOURCES {
            return SourceBound::Nodes(sources.to_vec());
        }
        let g = &land.grid;
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
                let h = land.height[r] as f64;
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

/// The parameters the cached move costs depend on.
#[derive(Clone, Copy, Debug, PartialEq)]
struct CostKey {
    distance_weight: f64,
    slope_weight: f64,
    max_grade: f64,
    water_weight: f64,
    mask_radius: u32,
}

impl CostKey {
    fn of(p: &RoadParams) -> CostKey {
        CostKey {
            distance_weight: p.distance_weight,
            slope_weight: p.slope_weight,
            max_grade: p.max_grade,
            water_weight: p.water_weight,
            mask_radius: p.mask_radius,
        }
    }
}

/// How the A* estimates the cost left to the target.
#[derive(Clone, Copy)]
enum Estimate<'a> {
    /// The closed-form bound of the module documentation.
    Bound,
    /// The node-level costs from the target where settled; elsewhere the key the node-level search stopped at
    /// less the bound to the sources (see [`Search::node_field`]).
    Field(f64, &'a SourceBound),
    /// The same, the paths kept within [`Search::corridor`].
    Corridor(f64, &'a SourceBound),
    /// None: a Dijkstra, to check the others against.
    #[cfg(test)]
    Zero,
}

enum Outcome {
    Found(usize),
    Unreachable,
    OverBudget,
}

/// The state of the road search kept between connections.
struct Search {
    grid: LandGrid,
    key: CostKey,
    table: MoveTable,
    /// Static cost of move `m` from node `x` at `x * moves + m`: 0 not computed yet, positive within the grade
    /// limit, negative (its opposite) steeper than it, infinite through a node outside `Ω`.
    costs: Vec<f32>,
    /// [`NEAR_WATER`] and [`NEAR_OUTSIDE`] within the mask radius of each node: the moves of other nodes need
    /// not look for them.
    near: Vec<u8>,
    /// Best path cost plus one of each state (node × (moves + 1), the last slot for sources); 0 = not reached.
    g: Vec<f32>,
    /// The incoming move of the state each state was reached from.
    pred: Vec<u8>,
    touched: Vec<u32>,
    heap: BinaryHeap<Entry>,
    flags: Vec<u8>,
    /// Network cost from each road node to `Ψ` (see [`RoadNetwork::exit_costs`]; infinite elsewhere), for the
    /// first `exit_nodes` road nodes.
    exit: Vec<f64>,
    exit_nodes: usize,
    /// Initial cost plus one of each source node (0 = not a source).
    source_cost: Vec<f32>,
    /// Node-level cost from the target plus one (0 = not reached), whether it is final, the nodes touched.
    field: Vec<f32>,
    settled: Vec<bool>,
    field_touched: Vec<u32>,
    /// The move that reached each node in the node-level search.
    field_move: Vec<u8>,
    /// States the first A* and the A* with the node-level field may settle (see [`BOUND_BUDGET`],
    /// [`STATE_BUDGET`]).
    budget: usize,
    state_budget: usize,
    /// Nodes near the node-level path, where an A* over [`STATE_BUDGET`] finishes (see [`Search::run`]).
    corridor: Vec<bool>,
    corridor_touched: Vec<u32>,
}

/// The cached static cost of move `m` from `x` (see [`Search::costs`]).
fn cached_cost(
    costs: &mut [f32],
    table: &MoveTable,
    key: &CostKey,
    land: &Land,
    near: &[u8],
    x: usize,
    m: usize,
) -> f32 {
    let m_count = table.moves.len();
    let c = costs[x * m_count + m];
    if c != 0.0 {
        return c;
    }
    let c = static_cost(land, key, &table.moves[m], x, near[x], true);
    costs[x * m_count + m] = c;
    let y = (x as isize + table.moves[m].delta) as usize;
    costs[y * m_count + table.rev[m]] = c;
    c
}

/// The turn costs along the node-level path from `target` to `node` (see [`Search::node_field`]).
fn path_turns(
    table: &MoveTable,
    grid: &LandGrid,
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

/// The cost a move may take in a search that allows steep moves or not (`None`: not allowed).
fn usable(c: f32, steep: bool) -> Option<f32> {
    if c.is_infinite() || (c < 0.0 && !steep) {
        None
    } else {
        Some(c.abs())
    }
}

impl Search {
    fn new(land: &Land, params: &RoadParams) -> Result<Search> {
        let grid = &land.grid;
        let n = grid.len();
        let mut radius = params.mask_radius;
        let table = loop {
            let table = MoveTable::new(grid, radius);
            if n.saturating_mul(table.moves.len() + 1) <= MAX_STATES {
                break table;
            }
            if radius == 1 {
                return Err(invalid(format!(
                    "roads: a grid of {n} nodes is too large for the road search; use a coarser cell"
                )));
            }
            radius -= 1;
        };
        let m = table.moves.len();
        Ok(Search {
            grid: *grid,
            key: CostKey::of(params),
            costs: vec![0.0; n * m],
            near: {
                let outside: Vec<bool> = land.inside.iter().map(|&i| !i).collect();
                let r = radius as usize + 1;
                near(grid, &land.water, r)
                    .into_iter()
                    .zip(near(grid, &outside, r))
                    .map(|(w, o)| if w { NEAR_WATER } else { 0 } | if o { NEAR_OUTSIDE } else { 0 })
                    .collect()
            },
            g: vec![0.0; n * (m + 1)],
            pred: vec![0; n * (m + 1)],
            touched: Vec::new(),
            heap: BinaryHeap::new(),
            flags: Vec::with_capacity(n),
            exit: vec![f64::INFINITY; n],
            exit_nodes: 0,
            source_cost: vec![0.0; n],
            field: vec![0.0; n],
            settled: vec![false; n],
            field_touched: Vec::new(),
            field_move: vec![0; n],
            budget: BOUND_BUDGET,
            state_budget: STATE_BUDGET,
            corridor: vec![false; n],
            corridor_touched: Vec::new(),
            table,
        })
    }

    fn fits(&self, params: &RoadParams, grid: &LandGrid) -> bool {
        self.key == CostKey::of(params) && self.field.len() == grid.len()
    }

    /// The static cost of move `m` from `x` (see `costs`), computed once.
    fn cost(&mut self, land: &Land, x: usize, m: usize) -> f32 {
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
    fn run(
        &mut self,
        ctx: &Ctx,
        sources: &[(usize, f64)],
        target: usize,
        steep: bool,
        ellipse: Option<Ellipse>,
    ) -> Option<(Vec<usize>, f64)> {
        for &(r, t) in sources {
            let v = t as f32 + 1.0;
            if self.source_cost[r] == 0.0 || v < self.source_cost[r] {
                self.source_cost[r] = v;
            }
        }
        let first = self.astar(
            ctx,
            sources,
            target,
            steep,
            ellipse,
            Estimate::Bound,
            Some(self.budget),
        );
        let found = match first {
            Outcome::Found(s) => Some(s),
            Outcome::Unreachable => None,
            Outcome::OverBudget => {
                self.reset_states();
                let towards = SourceBound::new(ctx.land, sources);
                match self.node_field(ctx, &towards, target, steep, ellipse) {
                    None => None,
                    Some((stop, source)) => {
                        let estimate = Estimate::Field(stop, &towards);
                        let limit = Some(self.state_budget);
                        match self.astar(ctx, sources, target, steep, ellipse, estimate, limit) {
                            Outcome::Found(s) => Some(s),
                            Outcome::Unreachable => None,
                            Outcome::OverBudget => {
                                // forced turns (switchbacks) cost more than the node-level search knows, and
                                // every state within that margin is explored: finish near its path
                                self.reset_states();
                                self.mark_corridor(target, source);
                                let estimate = Estimate::Corridor(stop, &towards);
                                match self
                                    .astar(ctx, sources, target, steep, ellipse, estimate, None)
                                {
                                    Outcome::Found(s) => Some(s),
                                    _ => None,
                                }
                            }
                        }
                    }
                }
            }
        };
        let path = found.map(|state| (self.backtrack(state), self.g[state] as f64 - 1.0));
        self.reset_states();
        for &x in &self.field_touched {
            self.field[x as usize] = 0.0;
            self.settled[x as usize] = false;
        }
        self.field_touched.clear();
        for &x in &self.corridor_touched {
            self.corridor[x as usize] = false;
        }
        self.corridor_touched.clear();
        for &(r, _) in sources {
            self.source_cost[r] = 0.0;
        }
        path
    }

    /// The cost of the cheapest path by a plain Dijkstra over the states, to check the A* against.
    #[cfg(test)]
    fn dijkstra(
        &mut self,
        ctx: &Ctx,
        sources: &[(usize, f64)],
        target: usize,
        steep: bool,
        ellipse: Option<Ellipse>,
    ) -> Option<f64> {
        let found = self.astar(ctx, sources, target, steep, ellipse, Estimate::Zero, None);
        let cost = match found {
            Outcome::Found(s) => Some(self.g[s] as f64 - 1.0),
            _ => None,
        };
        self.reset_states();
        cost
    }

    fn reset_states(&mut self) {
        for &s in &self.touched {
            self.g[s as usize] = 0.0;
        }
        self.touched.clear();
        self.heap.clear();
    }

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

    /// Node-level search from `target` (paths `target → x`, charged like the A* but without turns): an A* towards
    /// the sources under the consistent bound `towards`, until its key passes the cost, turns included, of the
    /// path to the cheapest source reached. Returns that key and that source, or `None` when no source can be
    /// reached. The settled nodes have their exact cost from `target`, and every other node `x` costs at least
    /// the returned key less the bound from `x` to the sources.
    fn node_field(
        &mut self,
        ctx: &Ctx,
        towards: &SourceBound,
        target: usize,
        steep: bool,
        ellipse: Option<Ellipse>,
    ) -> Option<(f64, usize)> {
        let land = ctx.land;
        let p = ctx.params;
        let grid = land.grid;
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
        let bound = Bound::new(land, table, p, steep);
        let mut heap = BinaryHeap::new();
        field[target] = 1.0;
        field_touched.push(target as u32);
        heap.push(Entry {
            f: bound.to_sources(target, towards),
            g: 0.0,
            state: target as u32,
        });
        // the cheapest source reached: its cost and node; then the cost of that path with its turns, which the
        // search runs up to so that the A* that follows need not leave the settled nodes
        let mut best = (f64::INFINITY, usize::MAX);
        let mut upper: Option<f64> = None;
        let mut stop = f64::INFINITY;
        while let Some(e) = heap.pop() {
            let x = e.state as usize;
            if settled[x] || e.g + 1.0 > field[x] {
                continue;
            }
            if e.f >= best.0 {
                let u = *upper.get_or_insert_with(|| {
                    let (r, t) = (best.1, best.0 - field[best.1] as f64 + 1.0);
                    t + path_turns(table, &grid, field_move, target, r, p.curvature_weight)
                        + field[r] as f64
                        - 1.0
                });
                if e.f >= u {
                    stop = e.f;
                    break;
                }
            }
            settled[x] = true;
            if x != target && source_cost[x] != 0.0 {
                let c = e.g as f64 + (source_cost[x] - 1.0) as f64;
                if c < best.0 {
                    best = (c, x);
                }
                continue;
            }
            if x != target && flags[x] & GOAL != 0 {
                continue;
            }
            let (xi, xj) = grid.ij(x);
            for m in 0..table.moves.len() {
                let mv = &table.moves[m];
                let (yi, yj) = (xi as i64 + mv.dx as i64, xj as i64 + mv.dy as i64);
                if yi < 0 || yj < 0 || yi >= grid.nx as i64 || yj >= grid.ny as i64 {
                    continue;
                }
                let y = (x as isize + mv.delta) as usize;
                if settled[y] {
                    continue;
                }
                // the A* starts at the sources wherever they are: so must the paths here end
                if let Some(el) = ellipse {
                    if source_cost[y] == 0.0 && el.excludes(grid.point(yi as usize, yj as usize)) {
                        continue;
                    }
                }
                let Some(c) = usable(cached_cost(costs, table, key, land, near, x, m), steep)
                else {
                    continue;
                };
                let mv = &table.moves[m];
                let mut charge = if flags[y] & BUILDING != 0 {
                    p.building_cost
                } else {
                    0.0
                };
                let mut blocked = false;
                for &d in &mv.inner {
                    let f = flags[(x as isize + d) as usize];
                    blocked |= f & GOAL != 0;
                    if f & BUILDING != 0 {
                        charge += p.building_cost;
                    }
                }
                if blocked {
                    continue;
                }
                let d = (e.g as f64 + c as f64 + charge) as f32;
                if field[y] == 0.0 || d + 1.0 < field[y] {
                    if field[y] == 0.0 {
                        field_touched.push(y as u32);
                    }
                    field[y] = d + 1.0;
                    field_move[y] = m as u8;
                    heap.push(Entry {
                        f: d as f64 + bound.to_sources(y, towards),
                        g: d,
                        state: y as u32,
                    });
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
    fn mark_corridor(&mut self, target: usize, source: usize) {
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

    #[allow(clippy::too_many_arguments)]
    fn astar(
        &mut self,
        ctx: &Ctx,
        sources: &[(usize, f64)],
        target: usize,
        steep: bool,
        ellipse: Option<Ellipse>,
        estimate: Estimate<'_>,
        budget: Option<usize>,
    ) -> Outcome {
        let land = ctx.land;
        let p = ctx.params;
        let grid = land.grid;
        let Search {
            key,
            table,
            costs,
            near,
            g: gs,
            pred,
            touched,
            heap,
            flags,
            field,
            settled,
            corridor,
            ..
        } = self;
        let in_corridor = matches!(estimate, Estimate::Corridor(..));
        let m_count = table.moves.len();
        let m1 = m_count + 1;
        let bound = Bound::new(land, table, p, steep);
        let heuristic = |y: usize| -> f64 {
            let (stop, towards) = match estimate {
                Estimate::Bound => return bound.between(y, target),
                #[cfg(test)]
                Estimate::Zero => return 0.0,
                Estimate::Field(stop, towards) | Estimate::Corridor(stop, towards) => {
                    (stop, towards)
                }
            };
            let charge = if y != target && flags[y] & BUILDING != 0 {
                p.building_cost
            } else {
                0.0
            };
            let from_target = if settled[y] {
                field[y] as f64 - 1.0
            } else {
                stop - bound.to_sources(y, towards)
            };
            (from_target - charge).max(0.0)
        };
        for &(r, t) in sources {
            let s = r * m1 + m_count;
            let g = t as f32;
            if gs[s] == 0.0 || g + 1.0 < gs[s] {
                if gs[s] == 0.0 {
                    touched.push(s as u32);
                }
                gs[s] = g + 1.0;
                heap.push(Entry {
                    f: g as f64 + heuristic(r),
                    g,
                    state: s as u32,
                });
            }
        }
        let mut popped = 0usize;
        while let Some(e) = heap.pop() {
            let s = e.state as usize;
            if e.g + 1.0 > gs[s] {
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
            let (xi, xj) = grid.ij(x);
            for m in 0..m_count {
                let mv = &table.moves[m];
                let (yi, yj) = (xi as i64 + mv.dx as i64, xj as i64 + mv.dy as i64);
                if yi < 0 || yj < 0 || yi >= grid.nx as i64 || yj >= grid.ny as i64 {
                    continue;
                }
                let turn = if slot < m_count {
                    let a = table.turn[slot * m_count + m];
                    if a > MAX_TURN {
                        continue;
                    }
                    a * p.curvature_weight
                } else {
                    0.0
                };
                let y = (x as isize + mv.delta) as usize;
                let fy = flags[y];
                if y != target && fy & GOAL != 0 || in_corridor && !corridor[y] {
                    continue;
                }
                let Some(c) = usable(cached_cost(costs, table, key, land, near, x, m), steep)
                else {
                    continue;
                };
                let mv = &table.moves[m];
                let mut extra = turn;
                if y != target && fy & BUILDING != 0 {
                    extra += p.building_cost;
                }
                let mut blocked = false;
                for &d in &mv.inner {
                    let f = flags[(x as isize + d) as usize];
                    blocked |= f & GOAL != 0;
                    if f & BUILDING != 0 {
                        extra += p.building_cost;
                    }
                }
                if blocked {
                    continue;
                }
                if let Some(el) = ellipse {
                    if el.excludes(grid.point(yi as usize, yj as usize)) {
                        continue;
                    }
                }
                let g = (e.g as f64 + c as f64 + extra) as f32;
                let t = y * m1 + m;
                if gs[t] == 0.0 || g + 1.0 < gs[t] {
                    if gs[t] == 0.0 {
                        touched.push(t as u32);
                    }
                    gs[t] = g + 1.0;
                    pred[t] = slot as u8;
                    heap.push(Entry {
                        f: g as f64 + heuristic(y),
                        g,
                        state: t as u32,
                    });
                }
            }
        }
        Outcome::Unreachable
    }
}

/// The cost of a move from `x` under the grade limit (positive), above it (negative), or through a node outside
/// `Ω` (infinite); see the module documentation. `near` says whether water
/// ([`NEAR_WATER`]) or nodes outside `Ω` ([`NEAR_OUTSIDE`]) may lie within the move's reach.
fn static_cost(land: &Land, key: &CostKey, mv: &Move, x: usize, near: u8, penalise: bool) -> f32 {
    if near & NEAR_OUTSIDE != 0
        && mv
            .cells
            .iter()
            .any(|&d| !land.inside[(x as isize + d) as usize])
    {
        return f32::INFINITY;
    }
    let n = mv.samples.len() - 1;
    let sub = mv.length / n as f64;
    // grade over max grade = |Δh| · to_ratio
    let to_ratio = 1.0 / (sub * key.max_grade);
    let steep_weight = if penalise {
        STEEP_WEIGHT * (key.distance_weight + key.slope_weight)
    } else {
        0.0
    };
    let mut h0 = sample(&land.height, x, &mv.samples[0]);
    let (mut slope, mut steep_cost, mut steep) = (0.0, 0.0, false);
    for s in &mv.samples[1..] {
        let h1 = sample(&land.height, x, s);
        let r = (h1 - h0).abs() * to_ratio;
        slope += r * r;
        if r > 1.0 + 1e-9 {
            steep = true;
            steep_cost += r * r;
        }
        h0 = h1;
    }
    let mut cost = key.distance_weight * mv.length
        + (key.slope_weight * slope + steep_weight * steep_cost) * sub;
    if near & NEAR_WATER != 0 && key.water_weight > 0.0 {
        // trapezoids of the bilinear water indicator
        let mut w0 = sample_bool(&land.water, x, &mv.samples[0]);
        let mut wet_length = 0.0;
        for s in &mv.samples[1..] {
            let w1 = sample_bool(&land.water, x, s);
            wet_length += 0.5 * (w0 + w1) * sub;
            w0 = w1;
        }
        cost += key.water_weight * wet_length;
    }
    let c = (cost as f32).max(f32::MIN_POSITIVE);
    if steep && penalise {
        -c
    } else {
        c
    }
}

/// Nodes with a `values` node within `radius` cells (Chebyshev): a dilation along the rows, then the columns.
fn near(g: &LandGrid, values: &[bool], radius: usize) -> Vec<bool> {
    let mut rows = vec![false; g.len()];
    for j in 0..g.ny {
        let line: Vec<bool> = (0..g.nx).map(|i| values[g.index(i, j)]).collect();
        for (i, v) in dilate_line(&line, radius).into_iter().enumerate() {
            rows[g.index(i, j)] = v;
        }
    }
    let mut out = vec![false; g.len()];
    for i in 0..g.nx {
        let line: Vec<bool> = (0..g.ny).map(|j| rows[g.index(i, j)]).collect();
        for (j, v) in dilate_line(&line, radius).into_iter().enumerate() {
            out[g.index(i, j)] = v;
        }
    }
    out
}

/// The places of a line within `radius` of a set place: the nearest one on the left, then on the right.
fn dilate_line(line: &[bool], radius: usize) -> Vec<bool> {
    let mut out = vec![false; line.len()];
    let mut last: Option<usize> = None;
    for (k, &set) in line.iter().enumerate() {
        if set {
            last = Some(k);
        }
        out[k] = last.is_some_and(|l| k - l <= radius);
    }
    last = None;
    for (k, &set) in line.iter().enumerate().rev() {
        if set {
            last = Some(k);
        }
        out[k] |= last.is_some_and(|l| l - k <= radius);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(nx: usize, ny: usize) -> LandGrid {
        LandGrid {
            origin: DVec2::ZERO,
            cell: 2.0,
            nx,
            ny,
        }
    }

    #[test]
    fn mask_sizes() {
        let g = grid(20, 20);
        for (k, n) in [(1, 8), (2, 16), (3, 32), (4, 48)] {
            let t = MoveTable::new(&g, k);
            assert_eq!(t.moves.len(), n, "radius {k}");
            for (a, &b) in t.rev.iter().enumerate() {
                assert_eq!(t.moves[a].dx, -t.moves[b].dx);
                assert_eq!(t.moves[a].dy, -t.moves[b].dy);
            }
        }
    }

    #[test]
    fn gauge_is_exact_on_mask_directions_and_below_on_others() {
        let t = MoveTable::new(&grid(20, 20), 3);
        for mv in &t.moves {
            let v = DVec2::new(mv.dx as f64, mv.dy as f64);
            assert!((t.gauge(v) - v.length()).abs() < 1e-12);
        }
        // (5, 1) is covered by (3, 1) + (2, 0): 3.162 + 2 = 5.162 cells at best, Euclid 5.099
        let g = t.gauge(DVec2::new(5.0, 1.0));
        assert!(g > 5.099 && g <= 5.1623, "{g}");
    }

    #[test]
    fn move_cells_are_symmetric() {
        let g = grid(20, 20);
        let t = MoveTable::new(&g, 3);
        let x = g.index(10, 10);
        for (a, mv) in t.moves.iter().enumerate() {
            let y = (x as isize + mv.delta) as usize;
            let mut fwd: Vec<isize> = mv.cells.iter().map(|&d| x as isize + d).collect();
            let mut back: Vec<isize> = t.moves[t.rev[a]]
                .cells
                .iter()
                .map(|&d| y as isize + d)
                .collect();
            fwd.sort_unstable();
            back.sort_unstable();
            assert_eq!(fwd, back, "move {} {}", mv.dx, mv.dy);
        }
        // a diagonal move touches the two corner cells too
        let diag = t.moves.iter().find(|m| m.dx == 1 && m.dy == 1).unwrap();
        assert_eq!(diag.inner.len(), 2);
    }

    #[test]
    fn segment_cells_follow_the_segment() {
        let g = grid(10, 10);
        let cells = segment_cells(&g, DVec2::new(0.0, 0.0), DVec2::new(8.0, 0.0));
        assert_eq!(cells, vec![0, 1, 2, 3, 4]);
        assert!(segment_cells(&g, DVec2::new(-50.0, -50.0), DVec2::new(-40.0, -50.0)).is_empty());
    }

    /// Bumpy random land with water, holes in the region, and a steep band.
    fn random_land(rng: &mut rand_chacha::ChaCha8Rng, n: usize) -> Land {
        use rand::Rng;
        let g = grid(n, n);
        let bumps: Vec<(DVec2, f64, f64)> = (0..6)
            .map(|_| {
                (
                    DVec2::new(
                        rng.random_range(0.0..2.0 * n as f64),
                        rng.random_range(0.0..2.0 * n as f64),
                    ),
                    rng.random_range(-15.0..15.0),
                    rng.random_range(8.0..30.0),
                )
            })
            .collect();
        let height = (0..g.len())
            .map(|k| {
                let p = g.point_of(k);
                bumps
                    .iter()
                    .map(|&(c, a, r)| a * (-(p - c).length_squared() / (r * r)).exp())
                    .sum::<f64>() as f32
            })
            .collect();
        let inside = (0..g.len())
            .map(|_| rng.random_range(0.0..1.0) > 0.04)
            .collect();
        let lake = DVec2::new(
            rng.random_range(0.0..2.0 * n as f64),
            rng.random_range(0.0..2.0 * n as f64),
        );
        let water = (0..g.len())
            .map(|k| g.point_of(k).distance(lake) < 15.0)
            .collect();
        Land {
            grid: g,
            height,
            inside,
            water,
            wall: (0..g.len())
                .map(|_| rng.random_range(0.0..1.0) < 0.01)
                .collect(),
            fortified: vec![false; g.len()],
        }
    }

    #[test]
    fn the_searches_find_the_cheapest_path() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut compared = 0;
        for case in 0..24 {
            let n = 40;
            let land = random_land(&mut rng, n);
            let params = RoadParams {
                width: 4.0,
                distance_weight: rng.random_range(0.5..2.0),
                slope_weight: rng.random_range(0.0..4.0),
                max_grade: rng.random_range(0.1..0.3),
                curvature_weight: rng.random_range(0.0..4.0),
                water_weight: rng.random_range(0.0..30.0),
                building_cost: rng.random_range(0.0..200.0),
                reuse_weight: 0.1,
                mask_radius: 1 + case % 3,
                cycle_angle_degrees: 30.0,
                cycle_max_length: 100.0,
                cycle_min_separation: 20.0,
            };
            let mut search = Search::new(&land, &params).unwrap();
            search.flags = (0..land.grid.len())
                .map(|_| {
                    if rng.random_range(0.0..1.0) < 0.05 {
                        BUILDING
                    } else {
                        0
                    }
                })
                .collect();
            // many sources in some cases (the tiled bound), a few in the others
            let count = if case % 2 == 0 {
                rng.random_range(1..6)
            } else {
                rng.random_range(40..80)
            };
            let sources: Vec<(usize, f64)> = (0..count)
                .map(|_| {
                    (
                        rng.random_range(0..land.grid.len()),
                        rng.random_range(0.0..40.0),
                    )
                })
                .collect();
            for &(r, _) in &sources {
                search.flags[r] |= GOAL;
            }
            let target = rng.random_range(0..land.grid.len());
            if search.flags[target] & GOAL != 0 {
                continue;
            }
            let ellipse = (case % 4 == 3).then(|| Ellipse {
                a: land.grid.point_of(target),
                b: land.grid.point_of(sources[0].0),
                length: 1.3
                    * land
                        .grid
                        .point_of(target)
                        .distance(land.grid.point_of(sources[0].0))
                    + 10.0,
            });
            let ctx = Ctx {
                land: &land,
                params: &params,
            };
            for steep in [false, true] {
                let reference = search.dijkstra(&ctx, &sources, target, steep, ellipse);
                // the bound alone, the field at once, the field after a few states, the corridor
                for (budget, state_budget) in
                    [(usize::MAX, 0), (0, usize::MAX), (40, usize::MAX), (0, 20)]
                {
                    search.budget = budget;
                    search.state_budget = state_budget;
                    let got = search.run(&ctx, &sources, target, steep, ellipse);
                    match (reference, &got) {
                        (None, None) => {}
                        (Some(a), Some((path, b))) => {
                            let exact = state_budget > 20;
                            assert!(
                                (a - b).abs() <= 1e-3 * a.max(1.0) || !exact && *b >= a,
                                "case {case} steep {steep} budget {budget}: {a} vs {b}"
                            );
                            assert_eq!(path[0], target);
                            let last = *path.last().unwrap();
                            assert!(sources.iter().any(|&(r, _)| r == last));
                            compared += 1;
                        }
                        _ => panic!(
                            "case {case} steep {steep} budget {budget}: {reference:?} vs {:?}",
                            got.map(|g| g.1)
                        ),
                    }
                }
            }
        }
        assert!(compared >= 60, "{compared}");
    }

    #[test]
    fn network_costs_kept_up_to_date_match_a_full_computation() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let land = random_land(&mut rng, 80);
        let params = RoadParams {
            width: 4.0,
            distance_weight: 1.0,
            slope_weight: 1.0,
            max_grade: 0.3,
            curvature_weight: 1.0,
            water_weight: 5.0,
            building_cost: 100.0,
            reuse_weight: 0.2,
            mask_radius: 2,
            cycle_angle_degrees: 40.0,
            cycle_max_length: 80.0,
            cycle_min_separation: 10.0,
        };
        let free = vec![false; land.grid.len()];
        let mut net = RoadNetwork::new(
            &land,
            &[DVec2::new(0.0, 80.0), DVec2::new(158.0, 100.0)],
            &[],
        )
        .unwrap();
        let mut cycles = 0;
        for _ in 0..25 {
            let b = DVec2::new(rng.random_range(0.0..158.0), rng.random_range(0.0..158.0));
            cycles += net.connect(&land, &params, &free, b, 0.0).unwrap().cycle as usize;
            let mut search = net.search.take().unwrap();
            net.exit_costs(&mut search, &land);
            let kept = search.exit.clone();
            search.exit_nodes = 0;
            net.exit_costs(&mut search, &land);
            for &r in &net.road_nodes {
                let (a, b) = (kept[r as usize], search.exit[r as usize]);
                assert!(a == b || (a - b).abs() < 1e-9 * a.max(1.0), "{a} vs {b}");
            }
            net.search = Some(search);
        }
        assert!(cycles > 0);
    }
}

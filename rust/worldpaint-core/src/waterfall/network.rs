//! The controller network `U` as an oriented graph, and its minimum-slope correction (thesis 4.2.1, and the
//! node and arc structure of the hydraulic graph of 4.2.2).
//!
//! Connections: the editor's magnets make connected control points coincide; here control points closer than
//! [`WaterfallParams::snap_distance`] (3D) are one connection, moved to their mean. A contact or free-fall end is
//! connected to a pool when it lies inside the pool's contour or horizontally within the snap distance of it, and
//! at its level (within the snap distance; an end flowing in may also lie below the level, as the thesis's
//! free-falls end "inside a pool"). A contact curve that other controllers end on is cut there into several arcs
//! ("branches are created at the intersections between controllers").
//!
//! Minimum slope, in the thesis's words: "starting with the flow sources of the network, and traversing it in a
//! topologically sorted order, we check if each control point `p_{j,k}` of curve `Δ_j` of each controller
//! maintains the minimum slope `ω_min` with respect to its predecessor `p_{j,k-1}`. If not, point `p_{j,k}` is
//! lowered to match the constraint. [...] Pool contour points are lowered, if necessary, according to the full
//! set of free-fall segments coming into the pool." The slope is an inclination: a step of horizontal length `d`
//! must drop by at least `d · tan ω_min`. A free-fall keeps the drop the user gave it (it moves down with its
//! start when that is lowered) and drops at least as much as the minimum slope asks over its horizontal run.

use super::model::{Controller, ControllerKind, WaterfallParams};
use crate::error::{check, Error, Result};
use crate::geom::{polygon_contains, segment_distance, DVec2};
use crate::terrain::Heightfield;
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// The node type `β_j` of the hydraulic graph.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HydraulicNodeKind {
    /// Where flow enters the network: no arc comes in.
    Source,
    /// Where flow leaves the network: no arc goes out.
    Well,
    /// A connection of arcs (also the one-in, one-out joints of a curve cut by a tributary).
    Branch,
    /// A pool controller; a pool without inflow is also a source, one without outflow also a well.
    Pool,
}

/// A node `N_j = (β_j, γ_j)` of the hydraulic graph, and the waterfall node `B_j = (μ_j, γ_j, ζ_j)` made from it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HydraulicNode {
    /// `β_j`.
    pub kind: HydraulicNodeKind,
    /// The connection point; for a pool the centroid of its contour at its level.
    pub position: DVec3,
    /// The pool controller of a pool node.
    pub pool: Option<usize>,
    /// Indices of the arcs that end here.
    pub arcs_in: Vec<usize>,
    /// Indices of the arcs that start here.
    pub arcs_out: Vec<usize>,
    /// Flow coming in: the sum of the incoming arcs, or what a source supplies.
    pub inflow: f64,
    /// Flow going out: the sum of the outgoing arcs, or what a well takes.
    pub outflow: f64,
    /// `ζ_j`, the depth (the section's `f_d`, half the flow).
    pub depth: f64,
}

/// An arc `A_k = ((N_i, N_j), η_k, γ_k)`: a contact or free-fall controller, or the part of one between two
/// connections.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HydraulicArc {
    /// Index of the controller it comes from.
    pub controller: usize,
    /// `η_k`: contact or free-fall.
    pub kind: ControllerKind,
    /// Index in the controller of its first control point.
    pub first_point: usize,
    /// Index in the controller of its last control point.
    pub last_point: usize,
    /// The node it starts at.
    pub from: usize,
    /// The node it ends at.
    pub to: usize,
    /// Its control points (a free-fall: start and end), with the connections' positions at its ends; corrected
    /// by [`HydraulicGraph::correct_slopes`].
    pub points: Vec<DVec3>,
    /// The controller's strength when the arc is where the controller starts.
    pub strength: Option<f64>,
    /// `γ_k`.
    pub flow: f64,
}

/// The hydraulic graph `G` of a controller network.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HydraulicGraph {
    /// The nodes: the pools first, then the other connections and curve ends.
    pub nodes: Vec<HydraulicNode>,
    /// The arcs; arc `k` is `k` in the nodes' `arcs_in` and `arcs_out`.
    pub arcs: Vec<HydraulicArc>,
    /// The nodes in dependency order, sources first.
    pub order: Vec<usize>,
}

/// Horizontal distances below this are "the same place" (scene units).
const SAME_PLACE: f64 = 1e-6;

fn xy(p: DVec3) -> DVec2 {
    p.truncate()
}

fn name(kind: ControllerKind) -> &'static str {
    match kind {
        ControllerKind::Contact => "contact",
        ControllerKind::FreeFall => "free-fall",
        ControllerKind::Pool => "pool",
    }
}

/// Checks one controller; says which controller and which point is wrong.
fn validate_controller(terrain: &Heightfield, i: usize, c: &Controller) -> Result<()> {
    let kind = name(c.kind);
    let needed = if c.kind == ControllerKind::Pool { 3 } else { 2 };
    if c.points.len() < needed {
        return Err(Error::invalid(
            format!("{kind} controller {i}"),
            format!(
                "has {} point(s), it needs at least {needed}",
                c.points.len()
            ),
        ));
    }
    for (k, p) in c.points.iter().enumerate() {
        if !p.is_finite() {
            return Err(Error::invalid(
                format!("{kind} controller {i}"),
                format!("point {k} is not finite"),
            ));
        }
        if !terrain.contains(xy(*p)) {
            return Err(Error::invalid(
                format!("{kind} controller {i}"),
                format!(
                    "point {k} at ({:.2}, {:.2}) lies outside the terrain",
                    p.x, p.y
                ),
            ));
        }
    }
    if let Some(s) = c.strength {
        check::positive(&format!("{kind} controller {i} strength"), s)?;
    }
    if c.kind == ControllerKind::Contact {
        for k in 1..c.points.len() {
            if xy(c.points[k]).distance(xy(c.points[k - 1])) < SAME_PLACE {
                return Err(Error::invalid(
                    format!("contact controller {i}"),
                    format!("points {} and {k} are at the same place in plan", k - 1),
                ));
            }
        }
    }
    Ok(())
}

/// A pool's contour in plan and its level.
struct PoolShape {
    contour: Vec<DVec2>,
    level: f64,
}

impl PoolShape {
    fn new(c: &Controller) -> Self {
        let contour: Vec<DVec2> = c.points.iter().map(|p| xy(*p)).collect();
        let level = c.points.iter().map(|p| p.z).sum::<f64>() / c.points.len() as f64;
        PoolShape { contour, level }
    }

    fn near(&self, p: DVec2, snap: f64) -> bool {
        if polygon_contains(&self.contour, p) {
            return true;
        }
        let n = self.contour.len();
        (0..n).any(|k| segment_distance(p, self.contour[k], self.contour[(k + 1) % n]) <= snap)
    }

    fn centroid(&self) -> DVec2 {
        self.contour.iter().copied().sum::<DVec2>() / self.contour.len() as f64
    }
}

/// Union-find with path halving; the representative is the smallest index, so the result does not depend on
/// the order of the unions.
struct Sets(Vec<usize>);

impl Sets {
    fn find(&mut self, mut a: usize) -> usize {
        while self.0[a] != a {
            self.0[a] = self.0[self.0[a]];
            a = self.0[a];
        }
        a
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        self.0[hi] = lo;
    }
}

/// A candidate connection point: an end of a contact or free-fall curve, or an interior point of a contact
/// curve, with the pool node its end lies in.
struct Candidate {
    controller: usize,
    point: usize,
    end: bool,
    pool_node: Option<usize>,
}

/// A node with no arcs yet.
fn bare_node(kind: HydraulicNodeKind, position: DVec3, pool: Option<usize>) -> HydraulicNode {
    HydraulicNode {
        kind,
        position,
        pool,
        arcs_in: Vec::new(),
        arcs_out: Vec::new(),
        inflow: 0.0,
        outflow: 0.0,
        depth: 0.0,
    }
}

/// The candidate connection points of the linear controllers, controller by controller in point order; an end
/// within `snap` of a pool (at its level for a start, not above it for an end) belongs to that pool's node.
fn connection_candidates(
    controllers: &[Controller],
    pools: &[(usize, PoolShape)],
    snap: f64,
) -> Vec<Candidate> {
    let mut cands: Vec<Candidate> = Vec::new();
    for (i, c) in controllers.iter().enumerate() {
        if c.kind == ControllerKind::Pool {
            continue;
        }
        let last = c.points.len() - 1;
        for (k, p) in c.points.iter().enumerate() {
            let end = k == 0 || k == last;
            if !end && c.kind == ControllerKind::FreeFall {
                continue;
            }
            let pool_node = if end {
                pools.iter().position(|(_, shape)| {
                    let at_level = if k == 0 {
                        (p.z - shape.level).abs() <= snap
                    } else {
                        p.z <= shape.level + snap
                    };
                    at_level && shape.near(xy(*p), snap)
                })
            } else {
                None
            };
            cands.push(Candidate {
                controller: i,
                point: k,
                end,
                pool_node,
            });
        }
    }
    cands
}

/// The candidates that meet: ends not in a pool snap to any candidate of another controller within `snap`
/// (sorted by x to prune the search).
fn snapped_sets(controllers: &[Controller], cands: &[Candidate], snap: f64) -> Sets {
    let pos = |c: &Candidate| controllers[c.controller].points[c.point];
    let mut by_x: Vec<usize> = (0..cands.len())
        .filter(|&k| cands[k].pool_node.is_none())
        .collect();
    by_x.sort_by(|&a, &b| {
        pos(&cands[a])
            .x
            .total_cmp(&pos(&cands[b]).x)
            .then(a.cmp(&b))
    });
    let xs: Vec<f64> = by_x.iter().map(|&k| pos(&cands[k]).x).collect();
    let mut sets = Sets((0..cands.len()).collect());
    for (a, ca) in cands.iter().enumerate() {
        if !ca.end || ca.pool_node.is_some() {
            continue;
        }
        let p = pos(ca);
        let from = xs.partition_point(|&x| x < p.x - snap);
        for &b in &by_x[from..] {
            let cb = &cands[b];
            let q = pos(cb);
            if q.x > p.x + snap {
                break;
            }
            if cb.controller != ca.controller && p.distance(q) <= snap {
                sets.union(a, b);
            }
        }
    }
    sets
}

/// The node of each candidate: its pool, or its set's node, added to `nodes` at the mean of the set (sets in
/// order of their smallest member); `None` for an interior point that meets nothing.
fn candidate_nodes(
    controllers: &[Controller],
    cands: &[Candidate],
    sets: &mut Sets,
    nodes: &mut Vec<HydraulicNode>,
) -> Vec<Option<usize>> {
    let pos = |c: &Candidate| controllers[c.controller].points[c.point];
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); cands.len()];
    for (k, cand) in cands.iter().enumerate() {
        if cand.pool_node.is_none() {
            let r = sets.find(k);
            members[r].push(k);
        }
    }
    let mut node_of: Vec<Option<usize>> = vec![None; cands.len()];
    for k in 0..cands.len() {
        if let Some(pn) = cands[k].pool_node {
            node_of[k] = Some(pn);
            continue;
        }
        let r = sets.find(k);
        // interior points alone are no connection
        if !cands[k].end && members[r].len() < 2 {
            continue;
        }
        if r == k {
            let mean =
                members[r].iter().map(|&m| pos(&cands[m])).sum::<DVec3>() / members[r].len() as f64;
            nodes.push(bare_node(HydraulicNodeKind::Branch, mean, None));
            node_of[k] = Some(nodes.len() - 1);
        } else {
            node_of[k] = node_of[r];
        }
    }
    node_of
}

/// The arcs: each linear controller cut at its connected points, its ends moved onto their nodes (a pool's at
/// the pool's level); a controller's strength goes to its first arc.
fn cut_arcs(
    controllers: &[Controller],
    cands: &[Candidate],
    node_of: &[Option<usize>],
    nodes: &[HydraulicNode],
) -> Vec<HydraulicArc> {
    let mut arcs: Vec<HydraulicArc> = Vec::new();
    let mut k = 0;
    while k < cands.len() {
        let i = cands[k].controller;
        let c = &controllers[i];
        let mut cuts: Vec<(usize, usize)> = Vec::new();
        while k < cands.len() && cands[k].controller == i {
            if let Some(n) = node_of[k] {
                cuts.push((cands[k].point, n));
            }
            k += 1;
        }
        for (w, pair) in cuts.windows(2).enumerate() {
            let ((p0, n0), (p1, n1)) = (pair[0], pair[1]);
            let mut points: Vec<DVec3> = match c.kind {
                ControllerKind::FreeFall => vec![c.points[p0], c.points[p1]],
                _ => c.points[p0..=p1].to_vec(),
            };
            let at_node = |p: DVec3, n: usize| -> DVec3 {
                let node = &nodes[n];
                if node.pool.is_some() {
                    DVec3::new(p.x, p.y, node.position.z)
                } else {
                    node.position
                }
            };
            let last = points.len() - 1;
            points[0] = at_node(points[0], n0);
            points[last] = at_node(points[last], n1);
            arcs.push(HydraulicArc {
                controller: i,
                kind: c.kind,
                first_point: p0,
                last_point: p1,
                from: n0,
                to: n1,
                points,
                strength: if w == 0 { c.strength } else { None },
                flow: 0.0,
            });
        }
    }
    arcs
}

/// Records each arc at its two nodes; refuses an arc that returns to its own node and a free-fall that does
/// not fall.
fn link_arcs(nodes: &mut [HydraulicNode], arcs: &[HydraulicArc]) -> Result<()> {
    for (a, arc) in arcs.iter().enumerate() {
        nodes[arc.from].arcs_out.push(a);
        nodes[arc.to].arcs_in.push(a);
        if arc.from == arc.to {
            return Err(Error::invalid(
                format!("{} controller {}", name(arc.kind), arc.controller),
                "starts and ends at the same connection: water cannot flow in a loop",
            ));
        }
        if arc.kind == ControllerKind::FreeFall {
            let (s, e) = (arc.points[0], arc.points[1]);
            if xy(s).distance(xy(e)) < SAME_PLACE && !(e.z < s.z) {
                return Err(Error::invalid(
                    format!("free-fall controller {}", arc.controller),
                    "its end is straight above or at its start",
                ));
            }
        }
    }
    Ok(())
}

/// A connection with no arc in is a source, one with no arc out a well, any other a branch.
fn classify_connections(nodes: &mut [HydraulicNode]) {
    for node in nodes {
        if node.pool.is_none() {
            node.kind = match (node.arcs_in.is_empty(), node.arcs_out.is_empty()) {
                (true, _) => HydraulicNodeKind::Source,
                (false, true) => HydraulicNodeKind::Well,
                _ => HydraulicNodeKind::Branch,
            };
        }
    }
}

impl HydraulicGraph {
    /// The graph of a controller network: connections, pools, arcs and their dependency order. Refuses bad
    /// controllers (too few points, not finite, off the terrain) and networks with a cycle.
    pub fn new(
        terrain: &Heightfield,
        controllers: &[Controller],
        params: &WaterfallParams,
    ) -> Result<Self> {
        params.validate()?;
        for (i, c) in controllers.iter().enumerate() {
            validate_controller(terrain, i, c)?;
        }
        let snap = params.snap_distance;
        let pools: Vec<(usize, PoolShape)> = controllers
            .iter()
            .enumerate()
            .filter(|(_, c)| c.kind == ControllerKind::Pool)
            .map(|(i, c)| (i, PoolShape::new(c)))
            .collect();
        let mut nodes: Vec<HydraulicNode> = pools
            .iter()
            .map(|(i, shape)| {
                bare_node(
                    HydraulicNodeKind::Pool,
                    shape.centroid().extend(shape.level),
                    Some(*i),
                )
            })
            .collect();
        let cands = connection_candidates(controllers, &pools, snap);
        let mut sets = snapped_sets(controllers, &cands, snap);
        let node_of = candidate_nodes(controllers, &cands, &mut sets, &mut nodes);
        let arcs = cut_arcs(controllers, &cands, &node_of, &nodes);
        link_arcs(&mut nodes, &arcs)?;
        classify_connections(&mut nodes);
        let order = dependency_order(&nodes, &arcs)?;
        Ok(HydraulicGraph { nodes, arcs, order })
    }

    /// Lowers control points so that every contact step drops by at least `tan ω_min` times its horizontal
    /// length and every free-fall falls, visiting the nodes from the sources (4.2.1); connections and pools take
    /// the lowest height their incoming arcs ask for. Returns the controllers with the corrected points (pools
    /// flat at their level).
    pub fn correct_slopes(
        &mut self,
        controllers: &[Controller],
        params: &WaterfallParams,
    ) -> Result<Vec<Controller>> {
        let t = params.min_slope.tan();
        let mut node_z: Vec<f64> = self.nodes.iter().map(|n| n.position.z).collect();
        for &n in &self.order {
            let z0 = node_z[n];
            self.nodes[n].position.z = z0;
            for &a in &self.nodes[n].arcs_out {
                let arc = &mut self.arcs[a];
                let user = arc.points.clone();
                arc.points[0].z = z0;
                match arc.kind {
                    ControllerKind::FreeFall => {
                        let run = xy(user[0]).distance(xy(user[1]));
                        let drop = (user[0].z - user[1].z).max(t * run);
                        arc.points[1].z = z0 - drop;
                    }
                    _ => {
                        for k in 1..arc.points.len() {
                            let run = xy(arc.points[k]).distance(xy(arc.points[k - 1]));
                            let highest = arc.points[k - 1].z - t * run;
                            arc.points[k].z = arc.points[k].z.min(highest);
                        }
                    }
                }
                let end = arc.points[arc.points.len() - 1].z;
                node_z[arc.to] = node_z[arc.to].min(end);
            }
        }
        // an arc's end takes its node's final height (never higher than it asked for)
        for arc in &mut self.arcs {
            let last = arc.points.len() - 1;
            arc.points[last].z = node_z[arc.to];
            if !arc.points.iter().all(|p| p.is_finite()) {
                return Err(Error::invalid(
                    format!("{} controller {}", name(arc.kind), arc.controller),
                    "the slope correction gave non-finite heights",
                ));
            }
        }
        let mut out = controllers.to_vec();
        for arc in &self.arcs {
            let c = &mut out[arc.controller];
            match arc.kind {
                ControllerKind::FreeFall => {
                    c.points[arc.first_point] = arc.points[0];
                    c.points[arc.last_point] = arc.points[1];
                }
                _ => {
                    c.points[arc.first_point..=arc.last_point].copy_from_slice(&arc.points);
                }
            }
        }
        for node in &self.nodes {
            if let Some(i) = node.pool {
                for p in &mut out[i].points {
                    p.z = node.position.z;
                }
            }
        }
        Ok(out)
    }
}

/// Kahn's order, smallest ready node first; a cycle is refused, naming the controllers on it.
fn dependency_order(nodes: &[HydraulicNode], arcs: &[HydraulicArc]) -> Result<Vec<usize>> {
    let mut missing: Vec<usize> = nodes.iter().map(|n| n.arcs_in.len()).collect();
    let mut ready: VecDeque<usize> = (0..nodes.len()).filter(|&n| missing[n] == 0).collect();
    let mut order = Vec::with_capacity(nodes.len());
    while let Some(n) = ready.pop_front() {
        order.push(n);
        for &a in &nodes[n].arcs_out {
            let to = arcs[a].to;
            missing[to] -= 1;
            if missing[to] == 0 {
                ready.push_back(to);
            }
        }
    }
    if order.len() < nodes.len() {
        let mut on_cycle: Vec<usize> = arcs
            .iter()
            .filter(|a| missing[a.from] > 0 && missing[a.to] > 0)
            .map(|a| a.controller)
            .collect();
        on_cycle.sort_unstable();
        on_cycle.dedup();
        let list: Vec<String> = on_cycle.iter().map(|c| c.to_string()).collect();
        return Err(Error::invalid(
            "the controller network",
            format!(
                "has a cycle through controllers {}: water cannot flow downhill around a loop",
                list.join(", ")
            ),
        ));
    }
    Ok(order)
}

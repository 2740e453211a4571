//! Arcs of a synthesized graph (Section 4.2; thesis 6.3.2): once the nodes are placed, "edges are constructed from
//! a node to its closest neighbors. The connecting node is chosen based on the statistics of edge lengths and
//! angles", by "the same algorithm as the point distribution synthesis ... using the arc probability function".
//!
//! * **Candidates** are the edges of the Delaunay triangulation of the new nodes and of the kept graph's nodes
//!   near the region (so arcs never cross each other, and a pasted network can end on the roads around it),
//!   that touch a new node, are no longer than the exemplar's longest edge, and do not cross the kept graph,
//!   come closer than the learned clearance to higher-priority instances, or cross polygons the exemplar's graph
//!   never crossed ("we do not allow new edges that would collide with existing content").
//! * **Constraint**: no two arcs (kept ones included) at a node make an angle below the exemplar's smallest one.
//! * **Chain**: as many arcs as the exemplar has per node, started from a random valid set, then relocated by
//!   Metropolis-Hastings moves (an arc swapped for a random candidate, or for one sharing a node with it).
//! * **Density.** As for distributions (see "Larger regions: matching the rdf" in [`super`]), the learned
//!   histograms are the targets of the statistics rather than product factors: the product `Π h_l Π h_a` of the
//!   thesis's `f_a` leaves the lengths and angles far from the exemplar's (total variation 0.2–0.3 in a first
//!   reading). The chain samples `exp(−E / τ)` with the chi-square energy
//!   `E = Σ_k (H(k) − T(k))² / max(T(k), 1)` over three histograms — edge lengths, angles between arcs sharing a
//!   node, and node degrees (0 to 4 or more; the thesis's "topological statistics") — where `T` is the learned
//!   distribution times the current count, annealed from `τ = 1` to `τ = 0.01`. Kept nodes that a candidate
//!   touches count in the angle and degree histograms with their kept arcs, so a road cut at the region's border
//!   (a dead end) draws a new arc that continues it.

use super::mix_seed;
use crate::geom::{segment_distance, DVec2};
use crate::graph::{angle_between, Graph, SegmentIndex};
use crate::palette::{GraphColor, Histogram};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use spade::{DelaunayTriangulation, Point2, Triangulation};

/// Metropolis-Hastings proposals per arc.
const PROPOSALS_PER_ARC: usize = 400;
/// Sweeps of the annealing (the temperature falls between sweeps).
const SWEEPS: usize = 20;
const TAU_START: f64 = 1.0;
const TAU_END: f64 = 0.01;
/// Degree bins: 0, 1, 2, 3, 4 or more.
const DEGREE_BINS: usize = 5;

/// What the arcs must keep away from.
pub(super) struct Obstacles<'a> {
    /// Higher-priority instances with the clearance arcs keep from them.
    pub(super) points: Vec<(&'a [DVec2], f64)>,
    /// Borders of polygons the arcs must not cross.
    pub(super) borders: Vec<&'a SegmentIndex>,
}

/// A candidate arc between node `a` and node `b`, in length bin `bin`.
#[derive(Clone, Copy)]
struct Candidate {
    a: usize,
    b: usize,
    bin: usize,
}

/// The three matched histograms and their targets' shapes.
#[derive(Clone)]
struct Counts {
    length: Vec<f64>,
    angle: Vec<f64>,
    degree: Vec<f64>,
}

/// The chain's state.
struct State<'g> {
    gc: &'g GraphColor,
    nodes: &'g [DVec2],
    candidates: Vec<Candidate>,
    chosen: Vec<bool>,
    /// Per node: candidate ids of its chosen arcs.
    at: Vec<Vec<usize>>,
    /// Per node: directions of its kept arcs.
    kept: Vec<Vec<DVec2>>,
    /// Per node: whether it counts in the degree histogram.
    counted: Vec<bool>,
    counts: Counts,
    /// The learned shapes: lengths, angles, degrees (0 to 4+).
    shape: Counts,
    arcs: f64,
    nodes_counted: f64,
}

fn chi2(h: &[f64], shape: &[f64], total: f64) -> f64 {
    h.iter()
        .zip(shape)
        .map(|(h, s)| {
            let t = s * total;
            (h - t).powi(2) / t.max(1.0)
        })
        .sum()
}

impl State<'_> {
    fn direction(&self, node: usize, c: usize) -> DVec2 {
        let cand = self.candidates[c];
        let other = if cand.a == node { cand.b } else { cand.a };
        self.nodes[other] - self.nodes[node]
    }

    /// Directions of every arc at `node` (kept and chosen), with `remove` left out and `add` put in.
    fn directions(&self, node: usize, remove: Option<usize>, add: Option<usize>) -> Vec<DVec2> {
        let mut d = self.kept[node].clone();
        d.extend(
            self.at[node]
                .iter()
                .filter(|&&c| Some(c) != remove)
                .map(|&c| self.direction(node, c)),
        );
        if let Some(c) = add {
            let cand = self.candidates[c];
            if cand.a == node || cand.b == node {
                d.push(self.direction(node, c));
            }
        }
        d
    }

    /// Adds (`sign` 1) or removes (−1) a node's angle pairs and degree in `counts`; false below the smallest angle.
    fn count_node(&self, node: usize, dirs: &[DVec2], sign: f64, counts: &mut Counts) -> bool {
        let bins = counts.angle.len();
        for (i, u) in dirs.iter().enumerate() {
            for v in &dirs[i + 1..] {
                let t = angle_between(*u, *v);
                if sign > 0.0 && t < self.gc.min_angle - 1e-9 {
                    return false;
                }
                let k = ((t / std::f64::consts::PI * bins as f64) as usize).min(bins - 1);
                counts.angle[k] += sign;
            }
        }
        if self.counted[node] {
            counts.degree[dirs.len().min(DEGREE_BINS - 1)] += sign;
        }
        true
    }

    fn energy(&self, c: &Counts) -> f64 {
        let pairs: f64 = c.angle.iter().sum();
        chi2(&c.length, &self.shape.length, self.arcs)
            + chi2(&c.angle, &self.shape.angle, pairs)
            + chi2(&c.degree, &self.shape.degree, self.nodes_counted)
    }

    /// The counts after choosing `add` and dropping `remove` (None when an angle gets too sharp).
    fn counts_after(&self, add: Option<usize>, remove: Option<usize>) -> Option<Counts> {
        let mut counts = self.counts.clone();
        let mut touched: Vec<usize> = Vec::with_capacity(4);
        for c in add.iter().chain(remove.iter()) {
            for n in [self.candidates[*c].a, self.candidates[*c].b] {
                if !touched.contains(&n) {
                    touched.push(n);
                }
            }
        }
        for &n in &touched {
            self.count_node(n, &self.directions(n, None, None), -1.0, &mut counts);
            if !self.count_node(n, &self.directions(n, remove, add), 1.0, &mut counts) {
                return None;
            }
        }
        if let Some(c) = add {
            counts.length[self.candidates[c].bin] += 1.0;
        }
        if let Some(c) = remove {
            counts.length[self.candidates[c].bin] -= 1.0;
        }
        Some(counts)
    }

    fn set(&mut self, c: usize, on: bool) {
        self.chosen[c] = on;
        let (a, b) = (self.candidates[c].a, self.candidates[c].b);
        for n in [a, b] {
            if on {
                self.at[n].push(c);
            } else {
                self.at[n].retain(|&x| x != c);
            }
        }
    }
}

/// The degree shape: no isolated node, then the exemplar's fractions of degrees 1, 2, 3, 4+.
fn degree_shape(gc: &GraphColor) -> Vec<f64> {
    let mut s = vec![0.0; DEGREE_BINS];
    for (k, d) in gc.degree.iter().enumerate().take(DEGREE_BINS - 1) {
        s[k + 1] = *d;
    }
    s
}

/// The arcs among `new` nodes and the `kept` graph's nodes (see the module documentation). Returns the new
/// graph: the new nodes that got arcs, the kept nodes they reach, and the arcs.
pub(super) fn synthesize_arcs(
    gc: &GraphColor,
    new: &[DVec2],
    kept: &Graph,
    obstacles: &Obstacles,
    seed: u64,
) -> Graph {
    // nodes: the new ones, then the kept ones
    let mut nodes: Vec<DVec2> = new.to_vec();
    nodes.extend_from_slice(&kept.nodes);
    let n_new = new.len();
    if n_new == 0 {
        return Graph::default();
    }
    let mut kept_dirs: Vec<Vec<DVec2>> = vec![Vec::new(); nodes.len()];
    for &[a, b] in &kept.edges {
        let (a, b) = (a as usize + n_new, b as usize + n_new);
        kept_dirs[a].push(nodes[b] - nodes[a]);
        kept_dirs[b].push(nodes[a] - nodes[b]);
    }
    let kept_index = SegmentIndex::new(kept.segments());
    let mut triangulation: DelaunayTriangulation<Point2<f64>> = DelaunayTriangulation::new();
    let mut handle_node: Vec<usize> = Vec::new();
    for (i, p) in nodes.iter().enumerate() {
        if let Ok(h) = triangulation.insert(Point2::new(p.x, p.y)) {
            if h.index() >= handle_node.len() {
                handle_node.resize(h.index() + 1, usize::MAX);
            }
            // coincident points share a handle: the first node keeps it
            if handle_node[h.index()] == usize::MAX {
                handle_node[h.index()] = i;
            }
        }
    }
    let clear = |a: DVec2, b: DVec2| {
        obstacles.points.iter().all(|(points, clearance)| {
            points
                .iter()
                .all(|p| segment_distance(*p, a, b) >= *clearance)
        }) && obstacles
            .borders
            .iter()
            .all(|border| !border.crosses(a, b, 0.0))
    };
    let lengths: &Histogram = &gc.edge_length;
    let mut candidates: Vec<Candidate> = Vec::new();
    for e in triangulation.undirected_edges() {
        let [u, v] = e.vertices();
        let (a, b) = (handle_node[u.fix().index()], handle_node[v.fix().index()]);
        if a == usize::MAX || b == usize::MAX || (a >= n_new && b >= n_new) {
            continue;
        }
        let (pa, pb) = (nodes[a], nodes[b]);
        let length = pa.distance(pb);
        let Some(bin) = lengths.bin_of(length) else {
            continue;
        };
        if kept_index.crosses(pa, pb, 1e-6 * length) || !clear(pa, pb) {
            continue;
        }
        candidates.push(Candidate { a, b, bin });
    }
    let mut counted = vec![false; nodes.len()];
    for n in counted.iter_mut().take(n_new) {
        *n = true;
    }
    for c in &candidates {
        counted[c.a] = true;
        counted[c.b] = true;
    }
    let angle_bins = gc.angle.values.len().max(1);
    let mut state = State {
        gc,
        nodes: &nodes,
        chosen: vec![false; candidates.len()],
        candidates,
        at: vec![Vec::new(); nodes.len()],
        kept: kept_dirs,
        counted,
        counts: Counts {
            length: vec![0.0; lengths.values.len()],
            angle: vec![0.0; angle_bins],
            degree: vec![0.0; DEGREE_BINS],
        },
        shape: Counts {
            length: lengths.normalized().values,
            angle: gc.angle.normalized().values,
            degree: degree_shape(gc),
        },
        arcs: 0.0,
        nodes_counted: 0.0,
    };
    // the degrees and angles of the nodes before any arc
    let mut counts = state.counts.clone();
    for n in 0..nodes.len() {
        let dirs = state.directions(n, None, None);
        state.count_node(n, &dirs, 1.0, &mut counts);
    }
    state.counts = counts;
    state.nodes_counted = state.counted.iter().filter(|c| **c).count() as f64;

    let mut rng = ChaCha8Rng::seed_from_u64(mix_seed(seed, 0xa2c5));
    let target = ((gc.edges_per_node * n_new as f64).round() as usize).min(state.candidates.len());
    state.arcs = target as f64;
    // a valid start: candidates in random order, taken while they keep every angle
    let mut order: Vec<usize> = (0..state.candidates.len()).collect();
    for k in (1..order.len()).rev() {
        order.swap(k, rng.random_range(0..=k));
    }
    let mut chosen: Vec<usize> = Vec::new();
    for &c in &order {
        if chosen.len() >= target {
            break;
        }
        if let Some(counts) = state.counts_after(Some(c), None) {
            state.set(c, true);
            state.counts = counts;
            chosen.push(c);
        }
    }
    state.arcs = chosen.len() as f64;
    // relocations at a fixed count, annealed
    let n_candidates = state.candidates.len();
    let mut at_node: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
    for (c, cand) in state.candidates.iter().enumerate() {
        at_node[cand.a].push(c);
        at_node[cand.b].push(c);
    }
    let mut energy = state.energy(&state.counts);
    let per_sweep = PROPOSALS_PER_ARC * chosen.len() / SWEEPS;
    for sweep in 0..SWEEPS {
        let frac = (sweep as f64 / (0.75 * (SWEEPS - 1) as f64)).min(1.0);
        let tau = TAU_START * (TAU_END / TAU_START).powf(frac);
        for _ in 0..per_sweep {
            let slot = rng.random_range(0..chosen.len());
            let remove = chosen[slot];
            let add = if rng.random::<f64>() < 0.5 {
                // a candidate sharing a node with the removed arc
                let cand = state.candidates[remove];
                let near = &at_node[if rng.random::<bool>() { cand.a } else { cand.b }];
                near[rng.random_range(0..near.len())]
            } else {
                rng.random_range(0..n_candidates)
            };
            if state.chosen[add] {
                continue;
            }
            let Some(counts) = state.counts_after(Some(add), Some(remove)) else {
                continue;
            };
            let e = state.energy(&counts);
            if rng.random::<f64>().ln() < -(e - energy) / tau {
                state.set(remove, false);
                state.set(add, true);
                state.counts = counts;
                chosen[slot] = add;
                energy = e;
            }
        }
    }
    // the new graph: nodes that got arcs
    let mut index = vec![u32::MAX; nodes.len()];
    let mut out = Graph::default();
    for &c in &chosen {
        let cand = state.candidates[c];
        for n in [cand.a, cand.b] {
            if index[n] == u32::MAX {
                index[n] = out.nodes.len() as u32;
                out.nodes.push(nodes[n]);
            }
        }
        let (a, b) = (index[cand.a], index[cand.b]);
        out.edges.push([a.min(b), a.max(b)]);
    }
    out
}

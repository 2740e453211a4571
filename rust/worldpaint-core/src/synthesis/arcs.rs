//! Arcs of a synthesized graph (Section 4.2; thesis 6.3.2): once the nodes are placed, "edges are constructed from
//! a node to its closest neighbors. The connecting node is chosen based on the statistics of edge lengths and
//! angles", by "the same algorithm as the point distribution synthesis ... using the arc probability function".
//!
//! * **Candidates** join a new node to any node, new or of the kept graph near the region (so a pasted network
//!   can end on the roads around it), no farther than the exemplar's longest edge, where the arc does not cross
//!   the kept graph, come closer than the learned clearance to higher-priority instances, or cross polygons the
//!   exemplar's graph never crossed ("we do not allow new edges that would collide with existing content").
//! * **Constraints**: no two arcs (kept ones included) at a node make an angle below the exemplar's smallest one;
//!   arcs that do not share a node stay a gap apart (a third of the shortest learned edge), so none crosses
//!   another or passes by a node it does not join.
//! * **Chain**: as many arcs as the exemplar has per node, started from a random valid set, then relocated by
//!   Metropolis-Hastings moves (an arc swapped for a random candidate, or for one sharing a node with it).
//! * **Density.** As for distributions (see "Larger regions: matching the rdf" in [`super`]), the learned
//!   histograms are the targets of the statistics rather than product factors: the product `Π h_l Π h_a` of the
//!   thesis's `f_a` leaves the lengths and angles far from the exemplar's (total variation 0.2–0.3 in a first
//!   reading). The chain samples `exp(−E / τ)` with the chi-square energy
//!   `E = Σ_k (H(k) − T(k))² / max(T(k), 1)` over four histograms — edge lengths, angles between arcs sharing a
//!   node, turning angles at nodes of two arcs (the paper's "angles along a path"), and node degrees (0 to 4 or
//!   more; the thesis's "topological statistics") — where `T` is the learned distribution times the current
//!   count, plus `w_c (C − C*)² / max(C*, 1)` on the count `C` of connected pieces (of the chosen arcs, joined
//!   through the kept graph's) against `C*`, the learned pieces per area times the region's area; annealed from
//!   `τ = 1` to `τ = 0.01`. A swap changes `C` by what two searches for a detour around the swapped arcs find
//!   (bounded to `SEARCH_NODES` nodes; `C` is recounted exactly every sweep). Kept nodes that a candidate
//!   touches count in the angle and degree histograms with their kept arcs, so a road cut at the region's border
//!   (a dead end) draws a new arc that continues it.
//! * **Dead ends.** The nodes lie where their rdf put them, and few of them have a continuation within the
//!   learned lengths: over nine times a village's area the candidates were 1.5 per arc, and at the chain's end
//!   the degree-1 nodes were three times the learned share with the junctions over and the through nodes short
//!   (139 / 660 / 393 of degrees 1 / 2 / 3+ against 45 / 873 / 297), whatever the degree term's weight: at a
//!   fixed count of arcs, continuing one dead end leaves another. So once the chain has run, dead ends beyond
//!   the learned share of degree-1 nodes are first continued, each by the candidate at it that keeps the
//!   constraints and leaves the energy lowest (one arc more; a join of two pieces only while there are more
//!   than the learned count), then pruned: a dead end that reaches a junction of three arcs or more through at
//!   most `SPUR_ARCS` arcs loses them (the junction becomes a through node, which the graph lacks; nodes left
//!   without an arc are dropped). Both go in random order. Nodes within the longest learned edge of the region's
//!   border are neither changed nor counted: there a road may end because the region cuts it.
//! * **Relaxation**: the nodes then move to fit the arcs (module `relax`).

use super::arc_grid::{arc_gap, ArcGrid};
use super::relax::{relax, Network};
use super::{annealed, mix_seed};
use crate::geom::segments_distance;
use crate::geom::{segment_distance, DVec2, PreparedRegion, RegionQueries};
use crate::graph::{angle_between, Graph, SegmentIndex};
use crate::palette::{GraphColor, Histogram};
use crate::spatial::{GridEntry, SpatialGrid};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Metropolis-Hastings proposals per arc.
const PROPOSALS_PER_ARC: usize = 400;
/// Sweeps of the annealing (the temperature falls between sweeps).
const SWEEPS: usize = 20;
const TAU_START: f64 = 1.0;
const TAU_END: f64 = 0.01;
/// The share of the sweeps over which the temperature falls.
const COOLING: f64 = 0.75;
/// Weight of the degree term: without it dead ends outnumber the exemplar's (a village's share of degree-1 nodes
/// 0.07 came out 0.17 at weight 1, 0.13 at weight 5).
const DEGREE_WEIGHT: f64 = 5.0;
/// Weight of the term on the count of connected pieces (a chi-square of one bin).
const COMPONENT_WEIGHT: f64 = 20.0;
/// Degree bins: 0, 1, 2, 3, 4 or more.
const DEGREE_BINS: usize = 5;
/// The longest spur (in arcs) that pruning a dead end removes.
const SPUR_ARCS: usize = 2;
/// The most nodes a search for a detour around a swapped arc visits.
const SEARCH_NODES: usize = 256;

/// What the arcs must keep away from.
pub(super) struct Obstacles<'a> {
    /// Higher-priority instances in grids, with the clearance arcs keep from them.
    points: Vec<(SpatialGrid, f64)>,
    /// Borders of polygons the arcs must not cross.
    borders: Vec<&'a SegmentIndex>,
}

impl<'a> Obstacles<'a> {
    pub(super) fn new(points: &[(&[DVec2], f64)], borders: Vec<&'a SegmentIndex>) -> Self {
        let points = points
            .iter()
            .filter(|(p, c)| !p.is_empty() && *c > 0.0)
            .map(|(p, c)| {
                let (lo, hi) = p.iter().fold(
                    (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                    |(lo, hi), q| (lo.min(*q), hi.max(*q)),
                );
                let mut grid = SpatialGrid::new(lo, hi, *c);
                for (id, q) in p.iter().enumerate() {
                    grid.insert(GridEntry {
                        position: *q,
                        tag: 0,
                        id: id as u32,
                    });
                }
                (grid, *c)
            })
            .collect();
        Obstacles { points, borders }
    }

    /// Whether the segment `a`–`b` keeps its clearance from every instance and crosses no border.
    pub(super) fn clear(&self, a: DVec2, b: DVec2) -> bool {
        let (mid, half) = (0.5 * (a + b), 0.5 * a.distance(b));
        self.points.iter().all(|(grid, clearance)| {
            let mut ok = true;
            grid.for_each_within(mid, half + clearance, |e, _| {
                ok = ok && segment_distance(e.position, a, b) >= *clearance;
            });
            ok
        }) && self.borders.iter().all(|border| !border.crosses(a, b, 0.0))
    }
}

/// A candidate arc between node `a` and node `b`, in length bin `bin`.
#[derive(Clone, Copy)]
struct Candidate {
    a: usize,
    b: usize,
    bin: usize,
}

/// The matched histograms and their targets' shapes: edge lengths; angles between arcs sharing a node, then
/// (from `angle_bins` on) turning angles at nodes of two arcs; node degrees; and the count of connected pieces.
#[derive(Clone)]
struct Counts {
    length: Vec<f64>,
    angle: Vec<f64>,
    degree: Vec<f64>,
    components: f64,
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
    /// The chosen arcs, for the crossing and gap tests.
    grid: ArcGrid,
    gap: f64,
    /// Bins of the angle histogram (the turning angles' follow).
    angle_bins: usize,
    /// The connected pieces the region should hold: the learned count per area times its area.
    components_target: f64,
    /// Per node: its neighbours along the kept graph's arcs (a piece joined to the kept graph is one with it).
    kept_links: Vec<Vec<usize>>,
    /// Scratch of the bounded searches: per node the search that last visited it, the current one, the queue.
    visited: Vec<u32>,
    search: u32,
    queue: Vec<usize>,
}

/// The chi-square distance of the counts `h` from `shape` scaled to `total`, in units of counting noise.
pub(super) fn chi2(h: &[f64], shape: &[f64], total: f64) -> f64 {
    h.iter()
        .zip(shape)
        .map(|(h, s)| {
            let t = s * total;
            (h - t).powi(2) / t.max(1.0)
        })
        .sum()
}

/// The bin of angle `t` (radians, 0 to π) among `bins` equal bins.
pub(super) fn angle_bin(t: f64, bins: usize) -> usize {
    ((t / std::f64::consts::PI * bins as f64) as usize).min(bins - 1)
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

    /// Adds (`sign` 1) or removes (−1) a node's angle pairs, turning angle and degree in `counts`; false below
    /// the smallest angle.
    fn count_node(&self, node: usize, dirs: &[DVec2], sign: f64, counts: &mut Counts) -> bool {
        let bins = self.angle_bins;
        let turn_bins = counts.angle.len() - bins;
        for (i, u) in dirs.iter().enumerate() {
            for v in &dirs[i + 1..] {
                let t = angle_between(*u, *v);
                if sign > 0.0 && t < self.gc.min_angle - 1e-9 {
                    return false;
                }
                counts.angle[angle_bin(t, bins)] += sign;
                if dirs.len() == 2 && turn_bins > 0 {
                    counts.angle[bins + angle_bin(std::f64::consts::PI - t, turn_bins)] += sign;
                }
            }
        }
        if self.counted[node] {
            counts.degree[dirs.len().min(DEGREE_BINS - 1)] += sign;
        }
        true
    }

    fn energy(&self, c: &Counts) -> f64 {
        let (pairs, turns) = c.angle.split_at(self.angle_bins);
        let (pair_shape, turn_shape) = self.shape.angle.split_at(self.angle_bins);
        let target = self.components_target;
        chi2(&c.length, &self.shape.length, self.arcs)
            + chi2(pairs, pair_shape, pairs.iter().sum())
            + chi2(turns, turn_shape, turns.iter().sum())
            + DEGREE_WEIGHT * chi2(&c.degree, &self.shape.degree, self.nodes_counted)
            + COMPONENT_WEIGHT * (c.components - target).powi(2) / target.max(1.0)
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

    /// Whether candidate `add` keeps the gap from every chosen arc (`remove` left out) it does not share a node
    /// with; arcs sharing a node are kept apart by the smallest angle.
    fn fits(&self, add: usize, remove: Option<usize>, near: &mut Vec<u32>) -> bool {
        let Candidate { a, b, .. } = self.candidates[add];
        let (pa, pb) = (self.nodes[a], self.nodes[b]);
        self.grid.near(pa, pb, self.gap, near);
        near.iter().all(|&j| {
            let j = j as usize;
            let Candidate { a: c, b: d, .. } = self.candidates[j];
            Some(j) == remove
                || c == a
                || c == b
                || d == a
                || d == b
                || segments_distance(pa, pb, self.nodes[c], self.nodes[d]) >= self.gap
        })
    }

    fn set(&mut self, c: usize, on: bool) {
        self.chosen[c] = on;
        let (a, b) = (self.candidates[c].a, self.candidates[c].b);
        if on {
            self.grid.insert(c as u32, self.nodes[a], self.nodes[b]);
        } else {
            self.grid.remove(c as u32, self.nodes[a], self.nodes[b]);
        }
        for n in [a, b] {
            if on {
                self.at[n].push(c);
            } else {
                self.at[n].retain(|&x| x != c);
            }
        }
    }
}

/// The shapes of the angles between arcs sharing a node and (after them) of the turning angles, as one vector,
/// with the number of angle bins: both are matched in one pass over a node's arcs. A color learned before turning
/// angles were has no turning bins.
pub(super) fn angle_and_turn_shape(gc: &GraphColor) -> (Vec<f64>, usize) {
    let angle_bins = gc.angle.values.len().max(1);
    let mut shape = gc.angle.normalized().values;
    shape.resize(angle_bins, 0.0);
    shape.extend(gc.turn.normalized().values);
    (shape, angle_bins)
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
    region: &PreparedRegion,
    seed: u64,
) -> Graph {
    // nodes: the new ones, then the kept ones
    let mut nodes: Vec<DVec2> = new.to_vec();
    nodes.extend_from_slice(&kept.nodes);
    let n_new = new.len();
    if n_new == 0 {
        return Graph::default();
    }
    let kept_dirs = kept_directions(&nodes, kept, n_new);
    let kept_index = SegmentIndex::new(kept.segments());
    let lengths: &Histogram = &gc.edge_length;
    let longest = lengths.start + lengths.values.len() as f64 * lengths.bin_width;
    let candidates = candidate_arcs(&nodes, n_new, lengths, longest, &kept_index, obstacles);
    let counted = counted_nodes(nodes.len(), n_new, &candidates);
    let mut state = State::new(gc, &nodes, candidates, kept_dirs, counted, longest);
    state.components_target = gc.components_per_area * region.region().area();
    state.kept_links = vec![Vec::new(); nodes.len()];
    for &[a, b] in &kept.edges {
        let (a, b) = (a as usize + n_new, b as usize + n_new);
        state.kept_links[a].push(b);
        state.kept_links[b].push(a);
    }

    let mut rng = ChaCha8Rng::seed_from_u64(mix_seed(seed, 0xa2c5));
    let target = ((gc.edges_per_node * n_new as f64).round() as usize).min(state.candidates.len());
    state.arcs = target as f64;
    let mut near: Vec<u32> = Vec::new();
    let mut chosen = state.valid_start(target, &mut rng, &mut near);
    state.arcs = chosen.len() as f64;
    state.relocate(&mut chosen, &mut rng, &mut near);
    state.close_dead_ends(&mut chosen, region, longest, &mut rng, &mut near);
    state.prune_spurs(&mut chosen, region, longest, &mut rng);
    let mut network = Network {
        arcs: chosen
            .iter()
            .map(|&c| [state.candidates[c].a, state.candidates[c].b])
            .collect(),
        nodes: nodes.clone(),
        movable: n_new,
        kept_dirs: &state.kept,
        kept_index: &kept_index,
    };
    relax(gc, &mut network, obstacles, region, seed);
    graph_of_arcs(&network)
}

/// Per node (the `n_new` new ones first): the directions of the kept graph's arcs at it.
fn kept_directions(nodes: &[DVec2], kept: &Graph, n_new: usize) -> Vec<Vec<DVec2>> {
    let mut kept_dirs: Vec<Vec<DVec2>> = vec![Vec::new(); nodes.len()];
    for &[a, b] in &kept.edges {
        let (a, b) = (a as usize + n_new, b as usize + n_new);
        kept_dirs[a].push(nodes[b] - nodes[a]);
        kept_dirs[b].push(nodes[a] - nodes[b]);
    }
    kept_dirs
}

/// The candidate arcs: from each new node to any node within the `longest` learned edge, in a length bin, that
/// neither crosses the kept graph nor comes too close to the obstacles (each pair of new nodes once).
fn candidate_arcs(
    nodes: &[DVec2],
    n_new: usize,
    lengths: &Histogram,
    longest: f64,
    kept_index: &SegmentIndex,
    obstacles: &Obstacles,
) -> Vec<Candidate> {
    let mut node_grid = SpatialGrid::new(
        nodes
            .iter()
            .fold(DVec2::splat(f64::INFINITY), |m, p| m.min(*p)),
        nodes
            .iter()
            .fold(DVec2::splat(f64::NEG_INFINITY), |m, p| m.max(*p)),
        longest,
    );
    for (i, p) in nodes.iter().enumerate() {
        node_grid.insert(GridEntry {
            position: *p,
            tag: 0,
            id: i as u32,
        });
    }
    let mut candidates: Vec<Candidate> = Vec::new();
    for (a, &pa) in nodes.iter().enumerate().take(n_new) {
        node_grid.for_each_within(pa, longest, |e, _| {
            let b = e.id as usize;
            // each pair of new nodes once
            if b < n_new && b <= a {
                return;
            }
            let pb = nodes[b];
            let length = pa.distance(pb);
            let Some(bin) = lengths.bin_of(length) else {
                return;
            };
            if kept_index.crosses(pa, pb, 1e-6 * length) || !obstacles.clear(pa, pb) {
                return;
            }
            candidates.push(Candidate { a, b, bin });
        });
    }
    candidates
}

/// The nodes that count in the degree histogram: the new ones, and the kept ones some candidate reaches.
fn counted_nodes(n_nodes: usize, n_new: usize, candidates: &[Candidate]) -> Vec<bool> {
    let mut counted = vec![false; n_nodes];
    for n in counted.iter_mut().take(n_new) {
        *n = true;
    }
    for c in candidates {
        counted[c.a] = true;
        counted[c.b] = true;
    }
    counted
}

impl<'g> State<'g> {
    /// The state without any chosen arc: the counts hold the degrees and angles of the kept arcs at the counted
    /// nodes.
    fn new(
        gc: &'g GraphColor,
        nodes: &'g [DVec2],
        candidates: Vec<Candidate>,
        kept_dirs: Vec<Vec<DVec2>>,
        counted: Vec<bool>,
        longest: f64,
    ) -> Self {
        let lengths = &gc.edge_length;
        let (angle_shape, angle_bins) = angle_and_turn_shape(gc);
        let mut state = State {
            gc,
            nodes,
            chosen: vec![false; candidates.len()],
            candidates,
            at: vec![Vec::new(); nodes.len()],
            kept: kept_dirs,
            counted,
            counts: Counts {
                length: vec![0.0; lengths.values.len()],
                angle: vec![0.0; angle_shape.len()],
                degree: vec![0.0; DEGREE_BINS],
                components: 0.0,
            },
            shape: Counts {
                length: lengths.normalized().values,
                angle: angle_shape,
                degree: degree_shape(gc),
                components: 0.0,
            },
            arcs: 0.0,
            nodes_counted: 0.0,
            grid: ArcGrid::new(nodes, longest),
            gap: arc_gap(lengths),
            angle_bins,
            components_target: 0.0,
            kept_links: Vec::new(),
            visited: vec![0; nodes.len()],
            search: 0,
            queue: Vec::new(),
        };
        // the degrees and angles of the nodes before any arc
        let mut counts = state.counts.clone();
        for n in (0..nodes.len()).filter(|&n| state.counted[n]) {
            let dirs = state.directions(n, None, None);
            state.count_node(n, &dirs, 1.0, &mut counts);
        }
        state.counts = counts;
        state.nodes_counted = state.counted.iter().filter(|c| **c).count() as f64;
        state
    }

    /// A valid start: candidates in random order, taken while they keep the gap and every angle, up to `target`.
    fn valid_start<R: Rng>(
        &mut self,
        target: usize,
        rng: &mut R,
        near: &mut Vec<u32>,
    ) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.candidates.len()).collect();
        for k in (1..order.len()).rev() {
            order.swap(k, rng.random_range(0..=k));
        }
        let mut chosen: Vec<usize> = Vec::new();
        for &c in &order {
            if chosen.len() >= target {
                break;
            }
            if !self.fits(c, None, near) {
                continue;
            }
            if let Some(counts) = self.counts_after(Some(c), None) {
                self.set(c, true);
                self.counts = counts;
                chosen.push(c);
            }
        }
        chosen
    }

    /// Relocations at a fixed count, annealed: a chosen arc swapped for a candidate sharing one of its nodes or for
    /// any candidate, accepted with `exp(−ΔE / τ)` (both proposals are symmetric).
    fn relocate<R: Rng>(&mut self, chosen: &mut [usize], rng: &mut R, near: &mut Vec<u32>) {
        let n_candidates = self.candidates.len();
        let mut at_node: Vec<Vec<usize>> = vec![Vec::new(); self.nodes.len()];
        for (c, cand) in self.candidates.iter().enumerate() {
            at_node[cand.a].push(c);
            at_node[cand.b].push(c);
        }
        let per_sweep = PROPOSALS_PER_ARC * chosen.len() / SWEEPS;
        for sweep in 0..SWEEPS {
            // the pieces are counted exactly once a sweep: the moves' bounded searches may miss a change
            self.counts.components = self.count_components();
            let mut energy = self.energy(&self.counts);
            let tau = annealed(TAU_START, TAU_END, sweep, SWEEPS, COOLING);
            for _ in 0..per_sweep {
                let slot = rng.random_range(0..chosen.len());
                let remove = chosen[slot];
                let add = if rng.random::<f64>() < 0.5 {
                    // a candidate sharing a node with the removed arc
                    let cand = self.candidates[remove];
                    let sharing = &at_node[if rng.random::<bool>() { cand.a } else { cand.b }];
                    sharing[rng.random_range(0..sharing.len())]
                } else {
                    rng.random_range(0..n_candidates)
                };
                if self.chosen[add] || !self.fits(add, Some(remove), near) {
                    continue;
                }
                let Some(mut counts) = self.counts_after(Some(add), Some(remove)) else {
                    continue;
                };
                counts.components += self.components_delta(add, Some(remove));
                let e = self.energy(&counts);
                if rng.random::<f64>().ln() < -(e - energy) / tau {
                    self.set(remove, false);
                    self.set(add, true);
                    self.counts = counts;
                    chosen[slot] = add;
                    energy = e;
                }
            }
        }
    }
}

impl State<'_> {
    /// The connected pieces of the chosen and kept arcs that hold a chosen arc.
    fn count_components(&self) -> f64 {
        self.pieces().1.iter().filter(|h| **h).count() as f64
    }

    /// The union-find forest of the chosen and kept arcs, and per node whether it is a root whose piece holds a
    /// chosen arc.
    fn pieces(&self) -> (Vec<usize>, Vec<bool>) {
        let mut parent: Vec<usize> = (0..self.nodes.len()).collect();
        let chosen = self
            .candidates
            .iter()
            .enumerate()
            .filter(|(c, _)| self.chosen[*c])
            .map(|(_, cand)| (cand.a, cand.b));
        let kept = self
            .kept_links
            .iter()
            .enumerate()
            .flat_map(|(a, links)| links.iter().map(move |&b| (a, b)));
        for (a, b) in chosen.chain(kept) {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            if ra != rb {
                parent[ra] = rb;
            }
        }
        let mut holds = vec![false; self.nodes.len()];
        for n in (0..self.nodes.len()).filter(|&n| !self.at[n].is_empty()) {
            holds[root(&mut parent, n)] = true;
        }
        (parent, holds)
    }

    /// Whether nodes `a` and `b` are joined by kept arcs and chosen ones other than `skip`: a breadth-first
    /// search from `a`
    /// bounded to `SEARCH_NODES` nodes, which reads a longer detour as a join (a street grid's detours are short;
    /// the sweep's exact count catches the rest).
    fn joined_without(&mut self, a: usize, b: usize, skip: usize) -> bool {
        self.search = self.search.wrapping_add(1);
        if self.search == 0 {
            self.visited.iter_mut().for_each(|v| *v = 0);
            self.search = 1;
        }
        self.queue.clear();
        self.queue.push(a);
        self.visited[a] = self.search;
        let mut head = 0;
        while head < self.queue.len() {
            if self.queue.len() > SEARCH_NODES {
                return true;
            }
            let n = self.queue[head];
            head += 1;
            let chosen = self.at[n].iter().filter(|&&c| c != skip).map(|&c| {
                let cand = self.candidates[c];
                if cand.a == n {
                    cand.b
                } else {
                    cand.a
                }
            });
            let next: Vec<usize> = chosen.chain(self.kept_links[n].iter().copied()).collect();
            for m in next {
                if m == b {
                    return true;
                }
                if self.visited[m] != self.search {
                    self.visited[m] = self.search;
                    self.queue.push(m);
                }
            }
        }
        false
    }

    /// The change of the count of pieces when chosen arc `remove` (if any) is swapped for candidate `add`. A
    /// node's side holds a chosen arc when the node itself keeps one (exact without kept arcs).
    fn components_delta(&mut self, add: usize, remove: Option<usize>) -> f64 {
        let c = self.candidates[add];
        let r = remove.map(|r| self.candidates[r]);
        let remove = remove.unwrap_or(usize::MAX);
        // whether a node keeps a chosen arc once `remove` is gone
        let keeps = |s: &Self, n: usize| {
            s.at[n].len() > usize::from(r.is_some_and(|r| n == r.a || n == r.b))
        };
        let sides =
            |s: &Self, a: usize, b: usize| f64::from(u8::from(keeps(s, a)) + u8::from(keeps(s, b)));
        // removing: one piece becomes the sides that keep an arc, or stays one (gone with its last arc)
        let removed = match r {
            None => 0.0,
            Some(r) if self.joined_without(r.a, r.b, remove) => {
                -f64::from(u8::from(sides(self, r.a, r.b) == 0.0))
            }
            Some(r) => sides(self, r.a, r.b) - 1.0,
        };
        // adding: the sides with an arc become one piece, or a piece gains its first arc
        let added = if self.joined_without(c.a, c.b, remove) {
            f64::from(u8::from(sides(self, c.a, c.b) == 0.0))
        } else {
            1.0 - sides(self, c.a, c.b)
        };
        removed + added
    }

    /// The dead ends at least `margin` inside the region's border (ends of a chosen arc with no other arc), in
    /// random order, and how many of them the learned share of degree-1 nodes allows.
    fn interior_dead_ends<R: Rng>(
        &self,
        region: &PreparedRegion,
        margin: f64,
        rng: &mut R,
    ) -> (Vec<usize>, f64) {
        let interior: Vec<usize> = (0..self.nodes.len())
            .filter(|&n| {
                !self.at[n].is_empty() && region.distance_to_boundary(self.nodes[n]) >= margin
            })
            .collect();
        let allowed =
            (self.gc.degree.first().copied().unwrap_or(0.0) * interior.len() as f64).round();
        let mut dead: Vec<usize> = interior
            .into_iter()
            .filter(|&n| self.kept[n].is_empty() && self.at[n].len() == 1)
            .collect();
        for k in (1..dead.len()).rev() {
            dead.swap(k, rng.random_range(0..=k));
        }
        (dead, allowed)
    }

    /// Continues dead ends beyond the exemplar's share (see the module documentation): in random order, a dead
    /// end gets the candidate at it that keeps the gap and every angle and leaves the energy lowest, unless it
    /// would join two pieces when there are no more than the learned count.
    fn close_dead_ends<R: Rng>(
        &mut self,
        chosen: &mut Vec<usize>,
        region: &PreparedRegion,
        margin: f64,
        rng: &mut R,
        near: &mut Vec<u32>,
    ) {
        let (dead, allowed) = self.interior_dead_ends(region, margin, rng);
        // arcs are only added here: a union-find keeps the pieces exactly
        let (mut parent, mut holds) = self.pieces();
        self.counts.components = holds.iter().filter(|h| **h).count() as f64;
        let mut at_node: Vec<Vec<usize>> = vec![Vec::new(); self.nodes.len()];
        for (c, cand) in self.candidates.iter().enumerate() {
            at_node[cand.a].push(c);
            at_node[cand.b].push(c);
        }
        let mut count = dead.len() as f64;
        for n in dead {
            if count <= allowed {
                break;
            }
            if self.at[n].len() != 1 {
                continue; // joined by an earlier one
            }
            let mut best: Option<(f64, usize, Counts)> = None;
            for &c in &at_node[n] {
                if self.chosen[c] || !self.fits(c, None, near) {
                    continue;
                }
                if let Some(mut counts) = self.counts_after(Some(c), None) {
                    let cand = self.candidates[c];
                    let (ra, rb) = (root(&mut parent, cand.a), root(&mut parent, cand.b));
                    // the dead end's piece holds a chosen arc: the other one is joined to it, if it holds one
                    let delta = if ra != rb && holds[ra] && holds[rb] {
                        -1.0
                    } else {
                        0.0
                    };
                    counts.components += delta;
                    // a join of two pieces only while there are more than the learned count
                    if delta < 0.0 && counts.components < self.components_target {
                        continue;
                    }
                    let e = self.energy(&counts);
                    if best.as_ref().is_none_or(|(b, _, _)| e < *b) {
                        best = Some((e, c, counts));
                    }
                }
            }
            if let Some((_, c, counts)) = best {
                let cand = self.candidates[c];
                let other = if cand.a == n { cand.b } else { cand.a };
                // joining two dead ends removes both
                count -= if self.at[other].len() == 1 { 2.0 } else { 1.0 };
                self.set(c, true);
                self.counts = counts;
                self.arcs += 1.0;
                chosen.push(c);
                let (ra, rb) = (root(&mut parent, cand.a), root(&mut parent, cand.b));
                if ra != rb {
                    parent[ra] = rb;
                    holds[rb] = true;
                }
            }
        }
    }

    /// Drops dead ends beyond the exemplar's share (see the module documentation): in random order, a dead end
    /// at least `margin` inside the region's border that reaches a junction of three arcs or more through at most
    /// `SPUR_ARCS` arcs loses them.
    fn prune_spurs<R: Rng>(
        &mut self,
        chosen: &mut Vec<usize>,
        region: &PreparedRegion,
        margin: f64,
        rng: &mut R,
    ) {
        let (dead, allowed) = self.interior_dead_ends(region, margin, rng);
        let mut count = dead.len() as f64;
        for n in dead {
            if count <= allowed {
                break;
            }
            // the spur: from the dead end through nodes of two arcs, up to `SPUR_ARCS` arcs, to a junction
            let (mut node, mut from, mut spur) = (n, usize::MAX, Vec::new());
            let junction = loop {
                let Some(&c) = self.at[node].iter().find(|&&c| c != from) else {
                    break false;
                };
                spur.push(c);
                let cand = self.candidates[c];
                node = if cand.a == node { cand.b } else { cand.a };
                from = c;
                let degree = self.at[node].len() + self.kept[node].len();
                if degree >= 3 {
                    break true;
                }
                if degree != 2 || spur.len() >= SPUR_ARCS {
                    break false;
                }
            };
            if junction {
                for c in spur {
                    self.set(c, false);
                }
                count -= 1.0;
            }
        }
        chosen.retain(|&c| self.chosen[c]);
    }
}

/// The root of `x` in a union-find forest (halving the path on the way).
fn root(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// The graph of the network's arcs: the nodes that got arcs (renumbered in order of appearance), and the arcs.
fn graph_of_arcs(network: &Network) -> Graph {
    let mut index = vec![u32::MAX; network.nodes.len()];
    let mut out = Graph::default();
    for &[a, b] in &network.arcs {
        for n in [a, b] {
            if index[n] == u32::MAX {
                index[n] = out.nodes.len() as u32;
                out.nodes.push(network.nodes[n]);
            }
        }
        let (a, b) = (index[a], index[b]);
        out.edges.push([a.min(b), a.max(b)]);
    }
    out
}

//! Relaxation of a synthesized graph's new nodes. The node sampler places nodes by their rdf alone, and arcs
//! chosen among them (module `arcs`) can only be as straight, or as long, as the nodes happen to lie: a street
//! that runs on through a node needs its two neighbours on opposite sides. The thesis builds arcs "with the same
//! algorithm as the point distribution synthesis"; here that algorithm continues on the nodes: displacement
//! moves of the new nodes (Gaussian steps, symmetric proposals) accepted by Metropolis-Hastings on the same
//! chi-square energy of edge lengths, angles at nodes and turning angles, annealed, with the same hard constraints as the arcs:
//! nodes stay in the region, no arc crosses another or comes closer than a gap to a node it does not join, no
//! angle falls below the exemplar's smallest, no arc leaves the learned length range or comes closer to
//! obstacles than their clearance.

use super::arc_grid::{arc_gap, ArcGrid};
use super::arcs::{angle_and_turn_shape, angle_bin, chi2, Obstacles};
use super::{annealed, mix_seed};
use crate::geom::segments_distance;
use crate::geom::{DVec2, PreparedRegion, RegionQueries};
use crate::graph::{angle_between, SegmentIndex};
use crate::palette::{GraphColor, Histogram};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Displacement proposals per movable node.
const PROPOSALS_PER_NODE: usize = 100;
const SWEEPS: usize = 15;
const TAU_START: f64 = 0.3;
const TAU_END: f64 = 0.01;
/// Step length relative to the mean learned edge length, at the start and at the end of the annealing.
const STEP_START: f64 = 0.2;
const STEP_END: f64 = 0.03;
/// The share of straightening proposals for nodes between two arcs, and their step relative to the other moves'.
const STRAIGHTENING: f64 = 0.5;
const STRAIGHT_STEP: f64 = 0.3;

/// What a relaxation works on: the nodes (the first `movable` of them may move), the arcs between them, and
/// per node the directions of the kept graph's arcs at it.
pub(super) struct Network<'a> {
    pub(super) nodes: Vec<DVec2>,
    pub(super) movable: usize,
    pub(super) arcs: Vec<[usize; 2]>,
    pub(super) kept_dirs: &'a [Vec<DVec2>],
    pub(super) kept_index: &'a SegmentIndex,
}

/// Moves the network's movable nodes (see the module documentation).
pub(super) fn relax(
    gc: &GraphColor,
    net: &mut Network,
    obstacles: &Obstacles,
    region: &PreparedRegion,
    seed: u64,
) {
    let Some((longest, mean)) = learned_lengths(&gc.edge_length) else {
        return;
    };
    let n = net.nodes.len();
    let at = arcs_at_nodes(n, &net.arcs);
    let movable: Vec<usize> = (0..net.movable.min(n))
        .filter(|&v| !at[v].is_empty())
        .collect();
    if movable.is_empty() {
        return;
    }
    let nodes = &mut net.nodes;
    let (angle_shape, angle_bins) = angle_and_turn_shape(gc);
    let mut rel = Relaxation {
        gc,
        length_shape: gc.edge_length.normalized().values,
        angle_shape,
        angle_bins,
        longest,
        gap: arc_gap(&gc.edge_length),
        arcs: &net.arcs,
        at,
        kept_dirs: net.kept_dirs,
        kept_index: net.kept_index,
        obstacles,
        arcs_total: net.arcs.len() as f64,
        pairs_total: 0.0,
        turns_total: 0.0,
    };
    let mut chain = Chain::new(&rel, nodes, longest);
    rel.pairs_total = chain.angle_h[..angle_bins].iter().sum();
    rel.turns_total = chain.angle_h[angle_bins..].iter().sum();
    chain.energy = rel.energy(&chain.length_h, &chain.angle_h);

    let mut rng = ChaCha8Rng::seed_from_u64(mix_seed(seed, 0x7e1a));
    let per_sweep = PROPOSALS_PER_NODE * movable.len() / SWEEPS;
    for sweep in 0..SWEEPS {
        let tau = annealed(TAU_START, TAU_END, sweep, SWEEPS, 1.0);
        let step = mean * annealed(STEP_START, STEP_END, sweep, SWEEPS, 1.0);
        for _ in 0..per_sweep {
            let v = movable[rng.random_range(0..movable.len())];
            let old = nodes[v];
            let (p, log_hastings) = rel.propose(nodes, v, step, &mut rng);
            if !region.contains(p) || !rel.arcs_fit(nodes, &chain.grid, v, p, &mut chain.near) {
                continue;
            }
            let mv = Move {
                v,
                old,
                p,
                log_hastings,
            };
            chain.try_move(&rel, nodes, &mv, tau, &mut rng);
        }
    }
}

/// The longest learned edge (the end of the last non-empty length bin) and the mean learned edge length; None
/// when no length was learned.
fn learned_lengths(lengths: &Histogram) -> Option<(f64, f64)> {
    let length_shape = lengths.normalized().values;
    let nonzero: Vec<usize> = (0..lengths.values.len())
        .filter(|&k| lengths.values[k] > 0.0)
        .collect();
    let (Some(_), Some(&last)) = (nonzero.first(), nonzero.last()) else {
        return None;
    };
    let longest = lengths.start + (last + 1) as f64 * lengths.bin_width;
    let mean: f64 = nonzero
        .iter()
        .map(|&k| length_shape[k] * (lengths.start + (k as f64 + 0.5) * lengths.bin_width))
        .sum();
    Some((longest, mean))
}

/// Per node: the indices of the arcs at it.
fn arcs_at_nodes(n: usize, arcs: &[[usize; 2]]) -> Vec<Vec<usize>> {
    let mut at: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (k, &[a, b]) in arcs.iter().enumerate() {
        at[a].push(k);
        at[b].push(k);
    }
    at
}

/// What the relaxation compares and checks against: the learned shapes, the hard constraints, the arcs.
struct Relaxation<'r> {
    gc: &'r GraphColor,
    length_shape: Vec<f64>,
    /// The shapes of the angles between arcs at a node, then of the turning angles (module `arcs`).
    angle_shape: Vec<f64>,
    angle_bins: usize,
    longest: f64,
    gap: f64,
    arcs: &'r [[usize; 2]],
    /// Per node: the arcs at it.
    at: Vec<Vec<usize>>,
    kept_dirs: &'r [Vec<DVec2>],
    kept_index: &'r SegmentIndex,
    obstacles: &'r Obstacles<'r>,
    /// The counts the histograms are matched at: arcs, angle pairs and turns (nodes of two arcs).
    arcs_total: f64,
    pairs_total: f64,
    turns_total: f64,
}

/// A proposed displacement of node `v` from `old` to `p`.
struct Move {
    v: usize,
    old: DVec2,
    p: DVec2,
    log_hastings: f64,
}

impl Relaxation<'_> {
    /// The node at the other end of arc `k` from `v`.
    fn other_end(&self, k: usize, v: usize) -> usize {
        let [a, b] = self.arcs[k];
        if a == v {
            b
        } else {
            a
        }
    }

    /// The directions of the arcs at `v` (kept ones first) into `d`.
    fn directions(&self, nodes: &[DVec2], v: usize, d: &mut Vec<DVec2>) {
        d.clear();
        d.extend_from_slice(&self.kept_dirs[v]);
        d.extend(
            self.at[v]
                .iter()
                .map(|&k| nodes[self.other_end(k, v)] - nodes[v]),
        );
    }

    /// Adds (sign 1) or removes (−1) the angle pairs of directions `d` (and their turning angle when there are
    /// two); false when one is too sharp.
    fn count_angles(&self, d: &[DVec2], sign: f64, h: &mut [f64]) -> bool {
        let bins = self.angle_bins;
        let turn_bins = self.angle_shape.len() - bins;
        for (i, u) in d.iter().enumerate() {
            for w in &d[i + 1..] {
                let t = angle_between(*u, *w);
                if sign > 0.0 && t < self.gc.min_angle - 1e-9 {
                    return false;
                }
                h[angle_bin(t, bins)] += sign;
                if d.len() == 2 && turn_bins > 0 {
                    h[bins + angle_bin(std::f64::consts::PI - t, turn_bins)] += sign;
                }
            }
        }
        true
    }

    /// The chi-square energy of the length, angle and turning-angle histograms.
    fn energy(&self, l: &[f64], a: &[f64]) -> f64 {
        let (pairs, turns) = a.split_at(self.angle_bins);
        let (pair_shape, turn_shape) = self.angle_shape.split_at(self.angle_bins);
        chi2(l, &self.length_shape, self.arcs_total)
            + chi2(pairs, pair_shape, self.pairs_total)
            + chi2(turns, turn_shape, self.turns_total)
    }

    /// A displacement of `v`: a node between two arcs may be proposed near the line through its neighbours
    /// (straightening, for the straight runs of streets), otherwise anywhere near; the Hastings ratio of the
    /// mixture (returned with the position, as a log) keeps the chain reversible.
    fn propose<R: Rng>(&self, nodes: &[DVec2], v: usize, step: f64, rng: &mut R) -> (DVec2, f64) {
        let old = nodes[v];
        let line = (self.at[v].len() == 2).then(|| {
            let ends: Vec<DVec2> = self.at[v]
                .iter()
                .map(|&k| nodes[self.other_end(k, v)])
                .collect();
            (ends[0], (ends[1] - ends[0]).normalize_or_zero())
        });
        let straight_step = STRAIGHT_STEP * step;
        let p = match line {
            Some((a, u)) if rng.random::<f64>() < STRAIGHTENING => {
                a + u * (old - a).dot(u) + super::gaussian(rng) * straight_step
            }
            _ => old + super::gaussian(rng) * step,
        };
        let log_hastings = line.map_or(0.0, |(a, u)| {
            let density = |from: DVec2, to: DVec2| {
                let on_line = a + u * (from - a).dot(u);
                let g = |d: DVec2, s: f64| (-0.5 * d.length_squared() / (s * s)).exp() / (s * s);
                STRAIGHTENING * g(to - on_line, straight_step)
                    + (1.0 - STRAIGHTENING) * g(to - from, step)
            };
            (density(p, old) / density(old, p)).ln()
        });
        (p, log_hastings)
    }

    /// Whether `v`'s arcs, with `v` at `p`, keep their lengths in range and cross or graze nothing.
    fn arcs_fit(
        &self,
        nodes: &[DVec2],
        grid: &ArcGrid,
        v: usize,
        p: DVec2,
        near: &mut Vec<u32>,
    ) -> bool {
        let lengths = &self.gc.edge_length;
        for &k in &self.at[v] {
            let o = self.other_end(k, v);
            let q = nodes[o];
            let len = p.distance(q);
            if len >= self.longest || lengths.bin_of(len).is_none() {
                return false;
            }
            if self.kept_index.crosses(p, q, 1e-6 * len) || !self.obstacles.clear(p, q) {
                return false;
            }
            grid.near(p, q, self.gap, near);
            for &j in near.iter() {
                let [c, d] = self.arcs[j as usize];
                if c == v || d == v {
                    continue;
                }
                if c == o || d == o {
                    continue; // shares the far node: the angle there decides
                }
                if segments_distance(p, q, nodes[c], nodes[d]) < self.gap {
                    return false;
                }
            }
        }
        true
    }

    /// Adds (`sign` 1) or removes (−1) the lengths of `v`'s arcs in `l`.
    fn count_lengths(&self, nodes: &[DVec2], v: usize, sign: f64, l: &mut [f64]) {
        for &k in &self.at[v] {
            let [a, b] = self.arcs[k];
            if let Some(bin) = self.gc.edge_length.bin_of(nodes[a].distance(nodes[b])) {
                l[bin] += sign;
            }
        }
    }
}

/// The chain's state: the current histograms and energy, the arcs in a grid, and scratch buffers.
struct Chain {
    length_h: Vec<f64>,
    angle_h: Vec<f64>,
    energy: f64,
    /// The histograms after a proposed move.
    l2: Vec<f64>,
    a2: Vec<f64>,
    grid: ArcGrid,
    d: Vec<DVec2>,
    near: Vec<u32>,
    touched: Vec<usize>,
}

impl Chain {
    /// The histograms of the network as it is (the energy is set by the caller).
    fn new(rel: &Relaxation, nodes: &[DVec2], longest: f64) -> Self {
        let mut grid = ArcGrid::new(nodes, longest);
        for (k, &[a, b]) in rel.arcs.iter().enumerate() {
            grid.insert(k as u32, nodes[a], nodes[b]);
        }
        let mut length_h = vec![0.0; rel.length_shape.len()];
        let mut angle_h = vec![0.0; rel.angle_shape.len()];
        for &[a, b] in rel.arcs {
            if let Some(k) = rel.gc.edge_length.bin_of(nodes[a].distance(nodes[b])) {
                length_h[k] += 1.0;
            }
        }
        let mut d = Vec::new();
        for (v, arcs) in rel.at.iter().enumerate() {
            if !arcs.is_empty() {
                rel.directions(nodes, v, &mut d);
                rel.count_angles(&d, 1.0, &mut angle_h);
            }
        }
        let (l2, a2) = (length_h.clone(), angle_h.clone());
        Chain {
            length_h,
            angle_h,
            energy: 0.0,
            l2,
            a2,
            grid,
            d,
            near: Vec::new(),
            touched: Vec::new(),
        }
    }

    /// Moves the node to `mv.p` and counts into `l2`, `a2` the histograms after the move: the node's and its
    /// neighbours' angles, the node's arcs' lengths. False when an angle gets too sharp.
    fn count_after(&mut self, rel: &Relaxation, nodes: &mut [DVec2], mv: &Move) -> bool {
        let v = mv.v;
        self.touched.clear();
        self.touched.push(v);
        for &k in &rel.at[v] {
            self.touched.push(rel.other_end(k, v));
        }
        self.l2.copy_from_slice(&self.length_h);
        self.a2.copy_from_slice(&self.angle_h);
        for &t in &self.touched {
            rel.directions(nodes, t, &mut self.d);
            rel.count_angles(&self.d, -1.0, &mut self.a2);
        }
        rel.count_lengths(nodes, v, -1.0, &mut self.l2);
        nodes[v] = mv.p;
        for &t in &self.touched {
            rel.directions(nodes, t, &mut self.d);
            if !rel.count_angles(&self.d, 1.0, &mut self.a2) {
                return false;
            }
        }
        rel.count_lengths(nodes, v, 1.0, &mut self.l2);
        true
    }

    /// The Metropolis-Hastings step of a move: accepted with `exp(−ΔE / τ)` times the Hastings ratio, the
    /// node put back otherwise.
    fn try_move<R: Rng>(
        &mut self,
        rel: &Relaxation,
        nodes: &mut [DVec2],
        mv: &Move,
        tau: f64,
        rng: &mut R,
    ) {
        if self.count_after(rel, nodes, mv) {
            let e = rel.energy(&self.l2, &self.a2);
            if rng.random::<f64>().ln() < -(e - self.energy) / tau + mv.log_hastings {
                for &k in &rel.at[mv.v] {
                    let [a, b] = rel.arcs[k];
                    let (pa, pb) = (nodes[a], nodes[b]);
                    let o = if a == mv.v { pb } else { pa };
                    self.grid.remove(k as u32, mv.old, o);
                    self.grid.insert(k as u32, pa, pb);
                }
                std::mem::swap(&mut self.length_h, &mut self.l2);
                std::mem::swap(&mut self.angle_h, &mut self.a2);
                self.energy = e;
                return;
            }
        }
        nodes[mv.v] = mv.old;
    }
}

//! Relaxation of a synthesized graph's new nodes. The node sampler places nodes by their rdf alone, and arcs
//! chosen among them (module `arcs`) can only be as straight, or as long, as the nodes happen to lie: a street
//! that runs on through a node needs its two neighbours on opposite sides. The thesis builds arcs "with the same
//! algorithm as the point distribution synthesis"; here that algorithm continues on the nodes: displacement
//! moves of the new nodes (Gaussian steps, symmetric proposals) accepted by Metropolis-Hastings on the same
//! chi-square energy of edge lengths and angles at nodes, annealed, with the same hard constraints as the arcs:
//! nodes stay in the region, no arc crosses another or comes closer than a gap to a node it does not join, no
//! angle falls below the exemplar's smallest, no arc leaves the learned length range or comes closer to
//! obstacles than their clearance.

use super::arc_grid::{arc_gap, ArcGrid};
use super::arcs::{angle_bin, chi2, Obstacles};
use super::{annealed, mix_seed};
use crate::geom::segments_distance;
use crate::geom::{DVec2, Region};
use crate::graph::{angle_between, SegmentIndex};
use crate::palette::GraphColor;
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
    region: &Region,
    seed: u64,
) {
    let lengths = &gc.edge_length;
    let length_shape = lengths.normalized().values;
    let angle_shape = gc.angle.normalized().values;
    let angle_bins = angle_shape.len().max(1);
    let nonzero: Vec<usize> = (0..lengths.values.len())
        .filter(|&k| lengths.values[k] > 0.0)
        .collect();
    let (Some(_), Some(&last)) = (nonzero.first(), nonzero.last()) else {
        return;
    };
    let longest = lengths.start + (last + 1) as f64 * lengths.bin_width;
    let mean: f64 = nonzero
        .iter()
        .map(|&k| length_shape[k] * (lengths.start + (k as f64 + 0.5) * lengths.bin_width))
        .sum();
    let gap = arc_gap(lengths);
    let n = net.nodes.len();
    let mut at: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (k, &[a, b]) in net.arcs.iter().enumerate() {
        at[a].push(k);
        at[b].push(k);
    }
    let movable: Vec<usize> = (0..net.movable.min(n))
        .filter(|&v| !at[v].is_empty())
        .collect();
    if movable.is_empty() {
        return;
    }
    let mut grid = ArcGrid::new(&net.nodes, longest);
    for (k, &[a, b]) in net.arcs.iter().enumerate() {
        grid.insert(k as u32, net.nodes[a], net.nodes[b]);
    }
    let dirs = |nodes: &[DVec2], v: usize, d: &mut Vec<DVec2>| {
        d.clear();
        d.extend_from_slice(&net.kept_dirs[v]);
        d.extend(at[v].iter().map(|&k| {
            let [a, b] = net.arcs[k];
            let o = if a == v { b } else { a };
            nodes[o] - nodes[v]
        }));
    };
    // adds (sign 1) or removes (−1) the angle pairs at v; false when one is too sharp
    let count_angles = |d: &[DVec2], sign: f64, h: &mut [f64]| -> bool {
        for (i, u) in d.iter().enumerate() {
            for w in &d[i + 1..] {
                let t = angle_between(*u, *w);
                if sign > 0.0 && t < gc.min_angle - 1e-9 {
                    return false;
                }
                h[angle_bin(t, angle_bins)] += sign;
            }
        }
        true
    };
    let mut length_h = vec![0.0; length_shape.len()];
    let mut angle_h = vec![0.0; angle_bins];
    for &[a, b] in &net.arcs {
        if let Some(k) = lengths.bin_of(net.nodes[a].distance(net.nodes[b])) {
            length_h[k] += 1.0;
        }
    }
    let mut d = Vec::new();
    for (v, arcs) in at.iter().enumerate() {
        if !arcs.is_empty() {
            dirs(&net.nodes, v, &mut d);
            count_angles(&d, 1.0, &mut angle_h);
        }
    }
    let arcs_total = net.arcs.len() as f64;
    let pairs_total: f64 = angle_h.iter().sum();
    let energy_of = |l: &[f64], a: &[f64]| {
        chi2(l, &length_shape, arcs_total) + chi2(a, &angle_shape, pairs_total)
    };
    let mut energy = energy_of(&length_h, &angle_h);

    let mut rng = ChaCha8Rng::seed_from_u64(mix_seed(seed, 0x7e1a));
    let per_sweep = PROPOSALS_PER_NODE * movable.len() / SWEEPS;
    let mut near: Vec<u32> = Vec::new();
    let mut touched: Vec<usize> = Vec::new();
    let (mut l2, mut a2) = (length_h.clone(), angle_h.clone());
    for sweep in 0..SWEEPS {
        let tau = annealed(TAU_START, TAU_END, sweep, SWEEPS, 1.0);
        let step = mean * annealed(STEP_START, STEP_END, sweep, SWEEPS, 1.0);
        'moves: for _ in 0..per_sweep {
            let v = movable[rng.random_range(0..movable.len())];
            let old = net.nodes[v];
            // a node between two arcs may be proposed near the line through its neighbours (straightening, for
            // the straight runs of streets), otherwise anywhere near; the Hastings ratio of the mixture keeps
            // the chain reversible
            let line = (at[v].len() == 2).then(|| {
                let ends: Vec<DVec2> = at[v]
                    .iter()
                    .map(|&k| {
                        let [a, b] = net.arcs[k];
                        net.nodes[if a == v { b } else { a }]
                    })
                    .collect();
                (ends[0], (ends[1] - ends[0]).normalize_or_zero())
            });
            let straight_step = STRAIGHT_STEP * step;
            let p = match line {
                Some((a, u)) if rng.random::<f64>() < STRAIGHTENING => {
                    a + u * (old - a).dot(u) + super::gaussian(&mut rng) * straight_step
                }
                _ => old + super::gaussian(&mut rng) * step,
            };
            let log_hastings = line.map_or(0.0, |(a, u)| {
                let density = |from: DVec2, to: DVec2| {
                    let on_line = a + u * (from - a).dot(u);
                    let g =
                        |d: DVec2, s: f64| (-0.5 * d.length_squared() / (s * s)).exp() / (s * s);
                    STRAIGHTENING * g(to - on_line, straight_step)
                        + (1.0 - STRAIGHTENING) * g(to - from, step)
                };
                (density(p, old) / density(old, p)).ln()
            });
            if !region.contains(p) {
                continue;
            }
            // the moved arcs: lengths in range, nothing crossed or grazed
            for &k in &at[v] {
                let [a, b] = net.arcs[k];
                let o = if a == v { b } else { a };
                let q = net.nodes[o];
                let len = p.distance(q);
                if len >= longest || lengths.bin_of(len).is_none() {
                    continue 'moves;
                }
                if net.kept_index.crosses(p, q, 1e-6 * len) || !obstacles.clear(p, q) {
                    continue 'moves;
                }
                grid.near(p, q, gap, &mut near);
                for &j in &near {
                    let [c, d] = net.arcs[j as usize];
                    if c == v || d == v {
                        continue;
                    }
                    if c == o || d == o {
                        continue; // shares the far node: the angle there decides
                    }
                    if segments_distance(p, q, net.nodes[c], net.nodes[d]) < gap {
                        continue 'moves;
                    }
                }
            }
            // counts after the move: the node and its neighbours' angles, the node's arcs' lengths
            touched.clear();
            touched.push(v);
            for &k in &at[v] {
                let [a, b] = net.arcs[k];
                touched.push(if a == v { b } else { a });
            }
            l2.copy_from_slice(&length_h);
            a2.copy_from_slice(&angle_h);
            for &t in &touched {
                dirs(&net.nodes, t, &mut d);
                count_angles(&d, -1.0, &mut a2);
            }
            for &k in &at[v] {
                let [a, b] = net.arcs[k];
                if let Some(bin) = lengths.bin_of(net.nodes[a].distance(net.nodes[b])) {
                    l2[bin] -= 1.0;
                }
            }
            net.nodes[v] = p;
            let mut valid = true;
            for &t in &touched {
                dirs(&net.nodes, t, &mut d);
                if !count_angles(&d, 1.0, &mut a2) {
                    valid = false;
                    break;
                }
            }
            if valid {
                for &k in &at[v] {
                    let [a, b] = net.arcs[k];
                    if let Some(bin) = lengths.bin_of(net.nodes[a].distance(net.nodes[b])) {
                        l2[bin] += 1.0;
                    }
                }
                let e = energy_of(&l2, &a2);
                if rng.random::<f64>().ln() < -(e - energy) / tau + log_hastings {
                    for &k in &at[v] {
                        let [a, b] = net.arcs[k];
                        let (pa, pb) = (net.nodes[a], net.nodes[b]);
                        let o = if a == v { pb } else { pa };
                        grid.remove(k as u32, old, o);
                        grid.insert(k as u32, pa, pb);
                    }
                    std::mem::swap(&mut length_h, &mut l2);
                    std::mem::swap(&mut angle_h, &mut a2);
                    energy = e;
                    continue;
                }
            }
            net.nodes[v] = old;
        }
    }
}

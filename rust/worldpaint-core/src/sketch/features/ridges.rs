//! Ridge lines by profile recognition and a maximum spanning forest (PPA with the thesis's change; see the
//! parent module for the readings).

use super::chains::chains;
use super::FeatureOptions;
use crate::error::Result;
use crate::sketch::{Feature, FeatureKind};
use crate::terrain::Heightfield;
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// The four profile directions: the grid's axes and diagonals.
const DIRECTIONS: [(isize, isize); 4] = [(1, 0), (0, 1), (1, 1), (1, -1)];

/// A segment between two neighbouring candidates: its height (the sum of its ends'), its ends (grid ids), and its
/// length in cells.
#[derive(Clone, Copy, Debug)]
struct Segment {
    height: f64,
    a: u32,
    b: u32,
    length: f64,
}

/// The terrain's ridge lines: polylines between endpoints and branching points, smoothed and draped on the
/// terrain. Polylines of one ridge system share their branching points exactly, and together form a tree.
pub fn ridges(terrain: &Heightfield, options: &FeatureOptions) -> Result<Vec<Feature>> {
    options.check()?;
    super::check_terrain(terrain)?;
    let grid = Grid { t: terrain };
    let candidate = candidates(terrain, options.ridge_window, options.ridge_directions);
    let mut segments: Vec<Segment> = (0..terrain.ny)
        .into_par_iter()
        .map(|j| grid.row_segments(j, &candidate))
        .collect::<Vec<_>>()
        .concat();
    // the graph on the candidates alone, numbered in grid order
    let ids: Vec<u32> = (0..candidate.len() as u32)
        .filter(|&v| candidate[v as usize])
        .collect();
    let mut compact = vec![u32::MAX; candidate.len()];
    for (k, &v) in ids.iter().enumerate() {
        compact[v as usize] = k as u32;
    }
    for s in &mut segments {
        (s.a, s.b) = (compact[s.a as usize], compact[s.b as usize]);
    }
    let mut forest = spanning_forest(&mut segments, ids.len());
    prune(&mut forest, options.ridge_prune_length);
    drop_short_trees(&mut forest, options.min_ridge_length);
    let edges: Vec<(u32, u32)> = forest
        .iter()
        .enumerate()
        .flat_map(|(v, next)| {
            let ids = &ids;
            next.iter()
                .filter(move |&&(w, _)| w as usize > v)
                .map(move |&(w, _)| (ids[v], ids[w as usize]))
        })
        .collect();
    Ok(chains(&edges)
        .into_iter()
        .map(|line| Feature {
            kind: FeatureKind::Ridge,
            points: grid.smooth(&line, options.ridge_smoothing),
        })
        .collect())
}

/// Profile recognition: the samples with, in at least `needed` of the four directions, a sample lower than
/// themselves on each side within `window` samples. Row by row over a copy of the heights bordered by `window`
/// samples of +∞ (never lower), so that each side's test is the minimum of `window` shifted rows, which the
/// compiler vectorises.
fn candidates(t: &Heightfield, window: usize, needed: usize) -> Vec<bool> {
    let (nx, ny, w) = (t.nx, t.ny, window);
    let stride = nx + 2 * w;
    let mut padded = vec![f32::INFINITY; stride * (ny + 2 * w)];
    for (row, heights) in padded[w * stride..]
        .chunks_exact_mut(stride)
        .zip(t.heights.chunks_exact(nx))
    {
        row[w..w + nx].copy_from_slice(heights);
    }
    (0..ny)
        .into_par_iter()
        .flat_map_iter(|j| {
            let start = (j + w) * stride + w;
            let centre = &padded[start..start + nx];
            let mut count = vec![0u8; nx];
            let (mut ahead, mut behind) = (vec![0f32; nx], vec![0f32; nx]);
            for (dx, dy) in DIRECTIONS {
                let offset = dy * stride as isize + dx;
                ahead.fill(f32::INFINITY);
                behind.fill(f32::INFINITY);
                for k in 1..=w as isize {
                    let (a, b) = (start as isize + k * offset, start as isize - k * offset);
                    let row_a = &padded[a as usize..a as usize + nx];
                    let row_b = &padded[b as usize..b as usize + nx];
                    for ((m, n), (&x, &y)) in ahead
                        .iter_mut()
                        .zip(&mut behind)
                        .zip(row_a.iter().zip(row_b))
                    {
                        *m = m.min(x);
                        *n = n.min(y);
                    }
                }
                for (((c, &h), &m), &n) in count.iter_mut().zip(centre).zip(&ahead).zip(&behind) {
                    *c += u8::from(m < h && n < h);
                }
            }
            count.into_iter().map(move |c| c as usize >= needed)
        })
        .collect()
}

struct Grid<'a> {
    t: &'a Heightfield,
}

impl Grid<'_> {
    fn h(&self, i: usize, j: usize) -> f32 {
        self.t.heights[j * self.t.nx + i]
    }

    /// The sample `k` steps from `(i, j)` along `d`, if on the grid.
    fn step(&self, i: usize, j: usize, d: (isize, isize), k: isize) -> Option<(usize, usize)> {
        let x = i as isize + d.0 * k;
        let y = j as isize + d.1 * k;
        (x >= 0 && y >= 0 && (x as usize) < self.t.nx && (y as usize) < self.t.ny)
            .then_some((x as usize, y as usize))
    }

    fn id(&self, i: usize, j: usize) -> u32 {
        (j * self.t.nx + i) as u32
    }

    /// Target connection from the candidates of row `j` to their neighbours east, north, north-east and
    /// north-west; of two crossing diagonals only the higher (the north-east one on a tie) is kept.
    fn row_segments(&self, j: usize, candidate: &[bool]) -> Vec<Segment> {
        let nx = self.t.nx;
        let is = |p: Option<(usize, usize)>| p.is_some_and(|(x, y)| candidate[y * nx + x]);
        let sum = |a: (usize, usize), b: (usize, usize)| {
            self.h(a.0, a.1) as f64 + self.h(b.0, b.1) as f64
        };
        let mut out = Vec::new();
        for i in 0..nx {
            if !candidate[j * nx + i] {
                continue;
            }
            let p = (i, j);
            let mut push = |q: (usize, usize), length: f64| {
                out.push(Segment {
                    height: sum(p, q),
                    a: self.id(i, j),
                    b: self.id(q.0, q.1),
                    length,
                })
            };
            for d in [(1, 0), (0, 1)] {
                let q = self.step(i, j, d, 1);
                if let (true, Some(q)) = (is(q), q) {
                    push(q, 1.0);
                }
            }
            let diagonal = std::f64::consts::SQRT_2;
            // north-east, unless the north-west diagonal crossing it in this cell is higher
            if let Some(q) = self.step(i, j, (1, 1), 1).filter(|&q| is(Some(q))) {
                let crossing = (self.step(i, j, (1, 0), 1), self.step(i, j, (0, 1), 1));
                let beaten = match crossing {
                    (Some(r), Some(s)) if is(Some(r)) && is(Some(s)) => sum(r, s) > sum(p, q),
                    _ => false,
                };
                if !beaten {
                    push(q, diagonal);
                }
            }
            // north-west, unless the north-east diagonal crossing it is as high
            if let Some(q) = self.step(i, j, (-1, 1), 1).filter(|&q| is(Some(q))) {
                let crossing = (self.step(i, j, (-1, 0), 1), self.step(i, j, (0, 1), 1));
                let beaten = match crossing {
                    (Some(r), Some(s)) if is(Some(r)) && is(Some(s)) => sum(r, s) >= sum(p, q),
                    _ => false,
                };
                if !beaten {
                    push(q, diagonal);
                }
            }
        }
        out
    }

    fn point(&self, v: u32) -> DVec2 {
        let v = v as usize;
        self.t.origin + DVec2::new((v % self.t.nx) as f64, (v / self.t.nx) as f64) * self.t.cell
    }

    /// The polyline through grid samples `line`, smoothed by `passes` (¼, ½, ¼) passes with its ends fixed, and
    /// draped on the terrain.
    fn smooth(&self, line: &[u32], passes: usize) -> Vec<DVec3> {
        let mut xy: Vec<DVec2> = line.iter().map(|&v| self.point(v)).collect();
        let closed = line.len() > 2 && line.first() == line.last();
        for _ in 0..passes {
            if xy.len() < 3 {
                break;
            }
            let before = xy.clone();
            for k in 1..xy.len() - 1 {
                xy[k] = 0.25 * before[k - 1] + 0.5 * before[k] + 0.25 * before[k + 1];
            }
            if closed {
                let n = xy.len();
                xy[0] = 0.25 * before[n - 2] + 0.5 * before[0] + 0.25 * before[1];
                xy[n - 1] = xy[0];
            }
        }
        xy.iter()
            .zip(line)
            .map(|(&p, &v)| {
                let fallback = self.t.heights[v as usize] as f64;
                p.extend(self.t.height_at(p).unwrap_or(fallback))
            })
            .collect()
    }
}

/// The maximum spanning forest of the segments on their height (Kruskal, highest first, union-find), as
/// adjacency lists on the `n` candidates: `(neighbour, length in cells)`.
fn spanning_forest(segments: &mut [Segment], n: usize) -> Vec<Vec<(u32, f64)>> {
    segments.sort_unstable_by(|x, y| {
        y.height
            .total_cmp(&x.height)
            .then(x.a.cmp(&y.a))
            .then(x.b.cmp(&y.b))
    });
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn root(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    }
    let mut forest = vec![Vec::new(); n];
    for s in segments.iter() {
        let (ra, rb) = (root(&mut parent, s.a), root(&mut parent, s.b));
        if ra != rb {
            parent[ra.max(rb) as usize] = ra.min(rb);
            forest[s.a as usize].push((s.b, s.length));
            forest[s.b as usize].push((s.a, s.length));
        }
    }
    forest
}

/// The branch from leaf `leaf` to the first sample where the tree does not simply pass through: its samples and
/// its length (cells); the walk stops once the length reaches `limit`.
fn branch(forest: &[Vec<(u32, f64)>], leaf: u32, limit: f64) -> (Vec<u32>, f64) {
    let (mut path, mut length) = (vec![leaf], 0.0);
    let (mut prev, mut cur) = (u32::MAX, leaf);
    while let Some(&(next, l)) = forest[cur as usize].iter().find(|e| e.0 != prev) {
        length += l;
        path.push(next);
        (prev, cur) = (cur, next);
        if forest[next as usize].len() != 2 || length >= limit {
            break;
        }
    }
    (path, length)
}

/// Branch reduction: branches from a leaf to a branching point shorter than `min_length` cells are removed,
/// shortest first, as long as their branching point keeps at least two other branches.
fn prune(forest: &mut [Vec<(u32, f64)>], min_length: f64) {
    if !(min_length > 0.0) {
        return;
    }
    // pruning makes no leaf (a branching point keeps two branches): the leaves are found once
    let mut leaves: Vec<u32> = (0..forest.len() as u32)
        .filter(|&v| forest[v as usize].len() == 1)
        .collect();
    loop {
        let mut short: Vec<(f64, u32, Vec<u32>)> = leaves
            .iter()
            .filter_map(|&leaf| {
                let (path, length) = branch(forest, leaf, min_length);
                let end = *path.last()? as usize;
                (length < min_length && forest[end].len() >= 3).then_some((length, leaf, path))
            })
            .collect();
        if short.is_empty() {
            return;
        }
        short.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let mut removed = false;
        for (_, _, path) in short {
            let Some(&end) = path.last() else { continue };
            if forest[end as usize].len() < 3 {
                continue;
            }
            for w in path.windows(2) {
                forest[w[0] as usize].retain(|e| e.0 != w[1]);
                forest[w[1] as usize].retain(|e| e.0 != w[0]);
            }
            removed = true;
        }
        if !removed {
            return;
        }
        leaves.retain(|&v| forest[v as usize].len() == 1);
    }
}

/// Removes the trees shorter than `min_length` cells in all.
fn drop_short_trees(forest: &mut [Vec<(u32, f64)>], min_length: f64) {
    let mut seen = vec![false; forest.len()];
    let mut stack = Vec::new();
    for start in 0..forest.len() {
        if seen[start] || forest[start].is_empty() {
            continue;
        }
        let (mut tree, mut length) = (Vec::new(), 0.0);
        seen[start] = true;
        stack.push(start);
        while let Some(v) = stack.pop() {
            tree.push(v);
            for &(w, l) in &forest[v] {
                length += 0.5 * l;
                if !seen[w as usize] {
                    seen[w as usize] = true;
                    stack.push(w as usize);
                }
            }
        }
        if length < min_length {
            for v in tree {
                forest[v].clear();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use std::collections::BTreeMap;

    fn terrain(n: usize, f: impl Fn(f64, f64) -> f64) -> Heightfield {
        let heights = (0..n * n)
            .map(|k| f((k % n) as f64, (k / n) as f64) as f32)
            .collect();
        Heightfield::new(DVec2::ZERO, 1.0, n, n, heights).expect("a valid grid")
    }

    fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
        p.distance(a + ab * t)
    }

    fn distance_to(p: DVec2, lines: &[Vec<DVec2>]) -> f64 {
        lines
            .iter()
            .flat_map(|l| l.windows(2).map(|w| segment_distance(p, w[0], w[1])))
            .fold(f64::INFINITY, f64::min)
    }

    /// Points every half cell along polylines.
    fn samples(lines: &[Vec<DVec2>]) -> Vec<DVec2> {
        let mut out = Vec::new();
        for l in lines {
            for w in l.windows(2) {
                let n = (w[0].distance(w[1]) / 0.5).ceil().max(1.0) as usize;
                out.extend((0..n).map(|k| w[0].lerp(w[1], k as f64 / n as f64)));
            }
        }
        out
    }

    /// The share of the `truth` lines within `tolerance` of the `found` ones, and the share of the found within
    /// `tolerance` of the truth.
    fn agreement(found: &[Feature], truth: &[Vec<DVec2>], tolerance: f64) -> (f64, f64) {
        let found: Vec<Vec<DVec2>> = found
            .iter()
            .map(|f| f.points.iter().map(|p| p.truncate()).collect())
            .collect();
        let share = |from: &[Vec<DVec2>], to: &[Vec<DVec2>]| {
            let s = samples(from);
            let near = s
                .iter()
                .filter(|&&p| distance_to(p, to) <= tolerance)
                .count();
            near as f64 / s.len().max(1) as f64
        };
        (share(truth, &found), share(&found, truth))
    }

    /// Trees and edges of the graph whose nodes are the polylines' ends and whose edges are the polylines.
    fn trees_and_cycles(found: &[Feature]) -> (usize, usize) {
        let mut nodes = BTreeMap::new();
        let mut key = |p: DVec3| {
            let n = nodes.len();
            *nodes.entry((p.x.to_bits(), p.y.to_bits())).or_insert(n)
        };
        let edges: Vec<(usize, usize)> = found
            .iter()
            .map(|f| (key(f.points[0]), key(f.points[f.points.len() - 1])))
            .collect();
        let mut parent: Vec<usize> = (0..nodes.len()).collect();
        fn root(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                x = p[x];
            }
            x
        }
        let mut cycles = 0;
        for (a, b) in edges {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            if ra == rb {
                cycles += 1;
            } else {
                parent[ra] = rb;
            }
        }
        let trees = (0..nodes.len())
            .filter(|&v| root(&mut parent, v) == v)
            .count();
        (trees, cycles)
    }

    #[test]
    fn an_oblique_ridge_is_found_along_its_crest() {
        // a Gaussian ridge through (64, 64) at 25° from X, rising gently along its crest
        let (c, dir) = (DVec2::splat(64.0), DVec2::from_angle(25f64.to_radians()));
        let t = terrain(129, |x, y| {
            let p = DVec2::new(x, y) - c;
            let (s, d) = (p.dot(dir), p.perp_dot(dir));
            (30.0 + 0.05 * s) * (-(d / 7.0).powi(2)).exp()
        });
        let found = ridges(&t, &FeatureOptions::default()).expect("valid options");
        // the crest inside the grid, three cells clear of its border
        let (mut lo, mut hi) = (-200.0f64, 200.0f64);
        for (o, d) in [(c.x, dir.x), (c.y, dir.y)] {
            let (a, b) = ((3.0 - o) / d, (125.0 - o) / d);
            lo = lo.max(a.min(b));
            hi = hi.min(a.max(b));
        }
        let truth = vec![vec![c + dir * lo, c + dir * hi]];
        let (recall, precision) = agreement(&found, &truth, 1.5);
        assert!(recall >= 0.9, "{recall} of the crest found");
        assert!(precision >= 0.9, "{precision} of the ridges on the crest");
        assert_eq!(trees_and_cycles(&found), (1, 0));
    }

    #[test]
    fn a_three_armed_ridge_is_one_tree_along_its_arms() {
        // three arms of 45 m from (64, 64), at 90°, 210° and 330°, falling from 40 m at the centre
        let c = DVec2::splat(64.0);
        let tips: Vec<DVec2> = [90.0f64, 210.0, 330.0]
            .iter()
            .map(|a| c + 45.0 * DVec2::from_angle(a.to_radians()))
            .collect();
        let t = terrain(129, |x, y| {
            let p = DVec2::new(x, y);
            tips.iter()
                .map(|&tip| {
                    let along = (tip - c) / 45.0;
                    let s = (p - c).dot(along).clamp(0.0, 45.0);
                    let d = p.distance(c + along * s);
                    (40.0 - 0.3 * s) * (-(d / 6.0).powi(2)).exp()
                })
                .fold(0.0, f64::max)
        });
        let found = ridges(&t, &FeatureOptions::default()).expect("valid options");
        let truth: Vec<Vec<DVec2>> = tips.iter().map(|&tip| vec![c, tip]).collect();
        let (recall, precision) = agreement(&found, &truth, 2.0);
        assert!(recall >= 0.9, "{recall} of the arms found");
        // beyond its tip an arm's rounded end may carry the ridge on for a few cells
        let (_, near) = agreement(&found, &truth, 4.0);
        assert!(
            precision >= 0.8 && near >= 0.97,
            "{precision}, {near} on the arms"
        );
        assert_eq!(trees_and_cycles(&found), (1, 0));
        // one branching point near the centre
        let mut ends: BTreeMap<(u64, u64), (DVec2, usize)> = BTreeMap::new();
        for f in &found {
            for p in [f.points[0], f.points[f.points.len() - 1]] {
                ends.entry((p.x.to_bits(), p.y.to_bits()))
                    .or_insert((p.truncate(), 0))
                    .1 += 1;
            }
        }
        let branching: Vec<DVec2> = ends.values().filter(|e| e.1 >= 3).map(|e| e.0).collect();
        assert_eq!(branching.len(), 1, "{branching:?}");
        assert!(branching[0].distance(c) <= 2.0, "{branching:?}");
    }

    #[test]
    fn short_spurs_on_a_noisy_cone_are_pruned() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let noise: Vec<f64> = (0..129 * 129)
            .map(|_| rng.random_range(-0.4..0.4))
            .collect();
        let t = terrain(129, |x, y| {
            let r = DVec2::new(x, y).distance(DVec2::splat(64.0));
            60.0 - 0.6 * r + noise[y as usize * 129 + x as usize]
        });
        let raw = FeatureOptions {
            ridge_prune_length: 0.0,
            min_ridge_length: 0.0,
            ..Default::default()
        };
        let unpruned = ridges(&t, &raw).expect("valid options");
        let options = FeatureOptions::default();
        let pruned = ridges(&t, &options).expect("valid options");
        let length = |f: &Feature| super::super::polyline_length(&f.points);
        let short = |fs: &[Feature]| fs.iter().filter(|f| length(f) < 5.0).count();
        // 704 polylines (691 shorter than 5 cells) before, 16 (none short) after
        assert!(short(&unpruned) >= 20, "{} short", short(&unpruned));
        assert!(pruned.len() * 5 <= unpruned.len());
        // no leaf branch shorter than the prune length remains at a branching point
        let mut degree: BTreeMap<(u64, u64), usize> = BTreeMap::new();
        for f in &pruned {
            for p in [f.points[0], f.points[f.points.len() - 1]] {
                *degree.entry((p.x.to_bits(), p.y.to_bits())).or_default() += 1;
            }
        }
        let deg = |p: DVec3| degree[&(p.x.to_bits(), p.y.to_bits())];
        for f in &pruned {
            let (a, b) = (deg(f.points[0]), deg(f.points[f.points.len() - 1]));
            if (a == 1) != (b == 1) {
                // smoothing shortens a polyline a little
                assert!(length(f) >= 0.8 * options.ridge_prune_length, "{f:?}");
            }
        }
        assert_eq!(trees_and_cycles(&pruned).1, 0);
    }

    #[test]
    fn the_forest_has_no_cycle_and_keeps_the_highest_segments() {
        // a ring of candidates around a pit: the ring's lowest segment is the one left out
        let t = terrain(33, |x, y| {
            let r = DVec2::new(x, y).distance(DVec2::splat(16.0));
            10.0 * (-((r - 8.0) / 2.0).powi(2)).exp() + 0.02 * x
        });
        let options = FeatureOptions {
            ridge_smoothing: 0,
            ..Default::default()
        };
        let found = ridges(&t, &options).expect("valid options");
        assert!(!found.is_empty());
        assert_eq!(trees_and_cycles(&found), (1, 0));
        // the ring is cut on its low (west) side: its ends are there
        let mut ends: BTreeMap<(u64, u64), (DVec3, usize)> = BTreeMap::new();
        for f in &found {
            for p in [f.points[0], f.points[f.points.len() - 1]] {
                ends.entry((p.x.to_bits(), p.y.to_bits()))
                    .or_insert((p, 0))
                    .1 += 1;
            }
        }
        let leaves: Vec<DVec3> = ends.values().filter(|e| e.1 == 1).map(|e| e.0).collect();
        assert!(!leaves.is_empty());
        let lowest_kept = leaves.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
        assert!(lowest_kept < 10.0, "{leaves:?}");
    }
}

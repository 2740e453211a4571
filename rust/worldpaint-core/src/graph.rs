//! Structured content as graphs (Section 4.2; thesis 6.3): "the input graph is represented as a set of paths that
//! may possibly intersect ... Nodes are automatically added at the intersection points between these paths".
//!
//! A [`Graph`] is built from paths (polylines) by making every vertex a node (vertices closer than a snapping
//! distance merge) and every crossing of two segments a node that splits both; it goes back to paths as its
//! maximal chains through nodes of degree 2. The statistics the method learns of a graph — edge lengths, the
//! angles between edges sharing a node, node degrees, connected components — are read here, and a
//! [`SegmentIndex`] answers the distance-to-graph and crossing queries of the synthesis in constant time per query.

mod distances;

use crate::geom::{polyline_segments, segment_distance, segment_intersection, DVec2};
use crate::grid::Grid;
use std::collections::HashMap;
use std::f64::consts::PI;

/// A planar graph: nodes and undirected edges between them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Graph {
    /// Node positions, world XY (m).
    pub nodes: Vec<DVec2>,
    /// Pairs of node indices, smaller first (as [`Graph::to_paths`] expects); [`Graph::from_paths`] lists each
    /// edge once, sorted.
    pub edges: Vec<[u32; 2]>,
}

/// Merges points closer than `snap` into one node (a hash of cells of side `snap`, neighbours included).
struct NodeMerger {
    snap: f64,
    cells: HashMap<(i64, i64), Vec<u32>>,
    nodes: Vec<DVec2>,
}

impl NodeMerger {
    fn new(snap: f64) -> Self {
        NodeMerger {
            snap: snap.max(1e-12),
            cells: HashMap::new(),
            nodes: Vec::new(),
        }
    }

    fn key(&self, p: DVec2) -> (i64, i64) {
        (
            (p.x / self.snap).floor() as i64,
            (p.y / self.snap).floor() as i64,
        )
    }

    fn node(&mut self, p: DVec2) -> u32 {
        let (kx, ky) = self.key(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(ids) = self.cells.get(&(kx + dx, ky + dy)) {
                    if let Some(&id) = ids
                        .iter()
                        .find(|&&id| self.nodes[id as usize].distance(p) <= self.snap)
                    {
                        return id;
                    }
                }
            }
        }
        let id = self.nodes.len() as u32;
        self.nodes.push(p);
        self.cells.entry((kx, ky)).or_default().push(id);
        id
    }
}

impl Graph {
    /// The planar graph of a set of paths (see the module documentation); vertices closer than `snap` merge.
    pub fn from_paths(paths: &[&[DVec2]], snap: f64) -> Graph {
        let segments: Vec<(DVec2, DVec2)> = paths
            .iter()
            .flat_map(|p| polyline_segments(p))
            .filter(|(a, b)| a.is_finite() && b.is_finite() && a.distance(*b) > snap)
            .collect();
        // crossings, found through a grid of segments
        let index = SegmentIndex::new(segments.clone());
        let mut cuts: Vec<Vec<f64>> = vec![vec![0.0, 1.0]; segments.len()];
        for (i, &(a, b)) in segments.iter().enumerate() {
            index.for_each_candidate(a, b, |j| {
                if j <= i {
                    return;
                }
                let (c, d) = segments[j];
                if let Some((t, u)) = segment_intersection(a, b, c, d) {
                    cuts[i].push(t);
                    cuts[j].push(u);
                }
            });
        }
        let mut merger = NodeMerger::new(snap);
        let mut edges: Vec<[u32; 2]> = Vec::new();
        for (&(a, b), ts) in segments.iter().zip(cuts.iter_mut()) {
            ts.sort_by(f64::total_cmp);
            let mut prev = merger.node(a);
            for &t in &ts[1..] {
                let node = merger.node(a + (b - a) * t);
                if node != prev {
                    edges.push([prev.min(node), prev.max(node)]);
                }
                prev = node;
            }
        }
        edges.sort_unstable();
        edges.dedup();
        Graph {
            nodes: merger.nodes,
            edges,
        }
    }

    /// The neighbours of every node.
    pub fn adjacency(&self) -> Vec<Vec<u32>> {
        let mut adj = vec![Vec::new(); self.nodes.len()];
        for &[a, b] in &self.edges {
            adj[a as usize].push(b);
            adj[b as usize].push(a);
        }
        adj
    }

    /// The length of edge `e` (m).
    pub fn edge_length(&self, e: [u32; 2]) -> f64 {
        self.nodes[e[0] as usize].distance(self.nodes[e[1] as usize])
    }

    /// The angle (in [0, π]) between the edges `node`–`a` and `node`–`b`.
    pub fn angle_at(&self, node: u32, a: u32, b: u32) -> f64 {
        let o = self.nodes[node as usize];
        angle_between(self.nodes[a as usize] - o, self.nodes[b as usize] - o)
    }

    /// The turning angle (in [0, π]: 0 straight on, π back) at each node of exactly two edges, where a path runs
    /// through: the paper's "angles along a path", read on the planar graph (junctions and dead ends have none).
    pub fn turning_angles(&self) -> Vec<f64> {
        self.adjacency()
            .iter()
            .enumerate()
            .filter(|(_, nb)| nb.len() == 2)
            .map(|(n, nb)| PI - self.angle_at(n as u32, nb[0], nb[1]))
            .collect()
    }

    /// The smallest angle between two edges sharing a node (π when no node has two edges).
    pub fn min_angle(&self) -> f64 {
        let adj = self.adjacency();
        let mut best = PI;
        for (n, nb) in adj.iter().enumerate() {
            for (i, &a) in nb.iter().enumerate() {
                for &b in &nb[i + 1..] {
                    best = best.min(self.angle_at(n as u32, a, b));
                }
            }
        }
        best
    }

    /// Connected components among the nodes that have at least one edge.
    pub fn components(&self) -> usize {
        let adj = self.adjacency();
        let labels = self.component_labels();
        let mut seen = vec![false; self.nodes.len()];
        (0..self.nodes.len())
            .filter(|&n| !adj[n].is_empty() && !std::mem::replace(&mut seen[labels[n]], true))
            .count()
    }

    /// The connected component of every node (labels 0.., an isolated node has its own).
    pub(crate) fn component_labels(&self) -> Vec<usize> {
        let adj = self.adjacency();
        let mut label = vec![usize::MAX; self.nodes.len()];
        let mut next = 0;
        for start in 0..self.nodes.len() {
            if label[start] != usize::MAX {
                continue;
            }
            label[start] = next;
            let mut stack = vec![start];
            while let Some(n) = stack.pop() {
                for &m in &adj[n] {
                    if label[m as usize] == usize::MAX {
                        label[m as usize] = next;
                        stack.push(m as usize);
                    }
                }
            }
            next += 1;
        }
        label
    }

    /// The graph as polylines: its maximal chains through nodes of degree 2 (cycles of such nodes included).
    pub fn to_paths(&self) -> Vec<Vec<DVec2>> {
        let adj = self.adjacency();
        let mut used = vec![false; self.edges.len()];
        let edge_id: HashMap<[u32; 2], usize> = self
            .edges
            .iter()
            .enumerate()
            .map(|(i, e)| (*e, i))
            .collect();
        let key = |a: u32, b: u32| [a.min(b), a.max(b)];
        let mut paths = Vec::new();
        let walk = |start: u32, first: u32, used: &mut Vec<bool>| {
            let mut path = vec![self.nodes[start as usize]];
            let (mut prev, mut cur) = (start, first);
            loop {
                if let Some(&e) = edge_id.get(&key(prev, cur)) {
                    used[e] = true;
                }
                path.push(self.nodes[cur as usize]);
                if adj[cur as usize].len() != 2 || cur == start {
                    break;
                }
                let next = if adj[cur as usize][0] == prev {
                    adj[cur as usize][1]
                } else {
                    adj[cur as usize][0]
                };
                if edge_id.get(&key(cur, next)).is_some_and(|&e| used[e]) {
                    break;
                }
                prev = cur;
                cur = next;
            }
            path
        };
        // chains from every node that is not a plain pass-through, then the remaining cycles
        for n in 0..self.nodes.len() as u32 {
            if adj[n as usize].len() == 2 {
                continue;
            }
            for &m in &adj[n as usize] {
                if edge_id.get(&key(n, m)).is_some_and(|&e| !used[e]) {
                    paths.push(walk(n, m, &mut used));
                }
            }
        }
        for (e, &[a, b]) in self.edges.iter().enumerate() {
            if !used[e] {
                paths.push(walk(a, b, &mut used));
            }
        }
        paths
    }

    /// The segments of the graph's edges.
    pub fn segments(&self) -> Vec<(DVec2, DVec2)> {
        self.edges
            .iter()
            .map(|e| (self.nodes[e[0] as usize], self.nodes[e[1] as usize]))
            .collect()
    }

    /// How many pairs of edges cross away from a shared node.
    pub fn crossings(&self) -> usize {
        let segments = self.segments();
        let index = SegmentIndex::new(segments.clone());
        let mut count = 0;
        for (i, e) in self.edges.iter().enumerate() {
            let (a, b) = segments[i];
            index.for_each_candidate(a, b, |j| {
                let f = self.edges[j];
                if j > i && f[0] != e[0] && f[0] != e[1] && f[1] != e[0] && f[1] != e[1] {
                    let (c, d) = segments[j];
                    if segment_intersection(a, b, c, d).is_some() {
                        count += 1;
                    }
                }
            });
        }
        count
    }
}

/// The angle between two vectors, in [0, π].
pub(crate) fn angle_between(u: DVec2, v: DVec2) -> f64 {
    u.perp_dot(v).abs().atan2(u.dot(v))
}

/// Per cell of an `nx × ny` grid, the Chebyshev distance in cells to the nearest non-empty cell (saturating;
/// `u16::MAX` everywhere when all are empty): the two-pass distance transform with unit steps to the 8
/// neighbours, exact for this metric.
fn chebyshev_rings(cells: &[Vec<u32>], nx: usize, ny: usize) -> Vec<u16> {
    let mut d: Vec<u16> = cells
        .iter()
        .map(|c| if c.is_empty() { u16::MAX } else { 0 })
        .collect();
    let at = |x: usize, y: usize| y * nx + x;
    for y in 0..ny {
        for x in 0..nx {
            let mut v = d[at(x, y)];
            if x > 0 {
                v = v.min(d[at(x - 1, y)].saturating_add(1));
            }
            if y > 0 {
                for xx in x.saturating_sub(1)..=(x + 1).min(nx - 1) {
                    v = v.min(d[at(xx, y - 1)].saturating_add(1));
                }
            }
            d[at(x, y)] = v;
        }
    }
    for y in (0..ny).rev() {
        for x in (0..nx).rev() {
            let mut v = d[at(x, y)];
            if x + 1 < nx {
                v = v.min(d[at(x + 1, y)].saturating_add(1));
            }
            if y + 1 < ny {
                for xx in x.saturating_sub(1)..=(x + 1).min(nx - 1) {
                    v = v.min(d[at(xx, y + 1)].saturating_add(1));
                }
            }
            d[at(x, y)] = v;
        }
    }
    d
}

/// Segments in a uniform grid: nearest-segment distances and crossing tests visit the cells near the query only.
#[derive(Clone, Debug, Default)]
pub struct SegmentIndex {
    segments: Vec<(DVec2, DVec2)>,
    grid: Grid,
    cells: Vec<Vec<u32>>,
    /// Per cell: the ring (Chebyshev distance in cells) of the nearest cell that lists a segment, so that a
    /// distance query skips the empty rings around it (far from every segment, it answers at once).
    empty_rings: Vec<u16>,
}

impl SegmentIndex {
    /// An index of the segments with cells about as large as their mean length (at most 4 million cells,
    /// enlarged beyond that).
    pub fn new(segments: Vec<(DVec2, DVec2)>) -> Self {
        let total: f64 = segments.iter().map(|(a, b)| a.distance(*b)).sum();
        let mean = total / segments.len().max(1) as f64;
        SegmentIndex::with_cell(segments, mean)
    }

    /// An index of the segments with cells of about `cell` metres (larger where the bucket limit would not cover
    /// them):
    /// small cells for many queries near short distances.
    pub(crate) fn with_cell(segments: Vec<(DVec2, DVec2)>, cell: f64) -> Self {
        if segments.is_empty() {
            return SegmentIndex::default();
        }
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for (a, b) in &segments {
            lo = lo.min(a.min(*b));
            hi = hi.max(a.max(*b));
        }
        let mut index = SegmentIndex::empty_over(lo, hi, cell);
        for (i, &(a, b)) in segments.iter().enumerate() {
            index.list(i, a, b, None);
        }
        index.segments = segments;
        index.empty_rings = chebyshev_rings(&index.cells, index.grid.nx, index.grid.ny);
        index
    }

    /// An index without segments over the box `min..max`, with cells of about `cell` metres, that segments within
    /// that box are then added to ([`SegmentIndex::extend`]).
    pub(crate) fn empty_over(min: DVec2, max: DVec2, cell: f64) -> Self {
        let grid = Grid::buckets_covering(
            min,
            max,
            if cell.is_finite() {
                cell.max(1e-9)
            } else {
                0.0
            },
        );
        SegmentIndex {
            segments: Vec::new(),
            grid,
            cells: vec![Vec::new(); grid.len()],
            empty_rings: vec![u16::MAX; grid.len()],
        }
    }

    /// Adds `segments` after those the index holds (a part beyond the index's box is not found). Only the cells
    /// around them learn how near a segment now is, so that a growing road network is indexed at the cost of its
    /// new roads, not of all of them.
    pub(crate) fn extend(&mut self, segments: impl IntoIterator<Item = (DVec2, DVec2)>) {
        let nx = self.grid.nx;
        let mut front = std::collections::VecDeque::new();
        let mut listed = Vec::new();
        for (a, b) in segments {
            listed.clear();
            self.list(self.segments.len(), a, b, Some(&mut listed));
            for &c in &listed {
                if self.empty_rings[c] != 0 {
                    self.empty_rings[c] = 0;
                    front.push_back(c);
                }
            }
            self.segments.push((a, b));
        }
        // breadth first over the eight neighbours: the rings (Chebyshev distances) that shrink
        while let Some(c) = front.pop_front() {
            let (x, y) = (c % nx, c / nx);
            let next = self.empty_rings[c].saturating_add(1);
            for yy in y.saturating_sub(1)..=(y + 1).min(self.grid.ny - 1) {
                for xx in x.saturating_sub(1)..=(x + 1).min(nx - 1) {
                    let k = yy * nx + xx;
                    if self.empty_rings[k] > next {
                        self.empty_rings[k] = next;
                        front.push_back(k);
                    }
                }
            }
        }
    }

    /// Lists segment `i` (`a`–`b`) in the cells it passes near, and those cells in `listed`.
    fn list(&mut self, i: usize, a: DVec2, b: DVec2, mut listed: Option<&mut Vec<usize>>) {
        let (nx, cell) = (self.grid.nx, self.grid.cell);
        let (x0, y0) = self.cell_of(a.min(b));
        let (x1, y1) = self.cell_of(a.max(b));
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                // only the cells the segment passes near
                let c = self.grid.bucket_centre(cx, cy);
                if segment_distance(c, a, b) <= 0.75 * cell {
                    self.cells[cy * nx + cx].push(i as u32);
                    if let Some(l) = listed.as_deref_mut() {
                        l.push(cy * nx + cx);
                    }
                }
            }
        }
    }

    /// Whether the index holds no segment.
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }

    /// The indexed segments, in the order they were given.
    pub fn segments(&self) -> &[(DVec2, DVec2)] {
        &self.segments
    }

    fn cell_of(&self, p: DVec2) -> (usize, usize) {
        self.grid.bucket_of(p)
    }

    /// Calls `visit(segment)` once for every segment listed in the cells the box of `a`–`b` covers.
    pub(crate) fn for_each_candidate(&self, a: DVec2, b: DVec2, mut visit: impl FnMut(usize)) {
        let mut found = Vec::new();
        self.candidates(a.min(b), a.max(b), &mut found);
        for s in found {
            visit(s as usize);
        }
    }

    /// Calls `visit(segment)` for the segments listed in the cells that the box `lo..hi`, grown by a cell,
    /// covers, until it returns false: no list is gathered, so a segment in several of the cells comes once per
    /// cell. For questions whose answer no repeat changes (a nearest distance, whether any is near).
    pub(crate) fn visit_candidates(
        &self,
        lo: DVec2,
        hi: DVec2,
        mut visit: impl FnMut(u32) -> bool,
    ) {
        if self.segments.is_empty() {
            return;
        }
        let (x0, y0) = self.cell_of(lo - DVec2::splat(self.grid.cell));
        let (x1, y1) = self.cell_of(hi + DVec2::splat(self.grid.cell));
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                for &s in &self.cells[cy * self.grid.nx + cx] {
                    if !visit(s) {
                        return;
                    }
                }
            }
        }
    }

    /// The segments listed in the cells that the box `lo..hi`, grown by a cell, covers: each once, in index
    /// order (so that ties between them resolve the same way whatever the cells).
    pub(crate) fn candidates(&self, lo: DVec2, hi: DVec2, out: &mut Vec<u32>) {
        out.clear();
        self.visit_candidates(lo, hi, |s| {
            out.push(s);
            true
        });
        out.sort_unstable();
        out.dedup();
    }

    /// Distance from `p` to the nearest segment, looking no farther than `max` (returns `max` beyond it, and
    /// `f64::INFINITY` for an empty index). Visits rings of cells around `p` outwards and stops once no unvisited
    /// cell can hold a nearer segment (a segment is listed in every cell it passes through).
    pub fn distance(&self, p: DVec2, max: f64) -> f64 {
        if self.segments.is_empty() {
            return f64::INFINITY;
        }
        self.nearest_within(p, max).0
    }

    /// The nearest segment to `p` closer than `max`, with its distance; `None` beyond `max` (and for an empty
    /// index). Of segments at the same distance, the first in the cells' order.
    pub fn nearest(&self, p: DVec2, max: f64) -> Option<(f64, (DVec2, DVec2))> {
        match self.nearest_within(p, max) {
            (d, Some(s)) => Some((d, self.segments[s])),
            _ => None,
        }
    }

    /// The distance from `p` to the nearest segment closer than `max` (else `max`) and that segment's index.
    fn nearest_within(&self, p: DVec2, max: f64) -> (f64, Option<usize>) {
        if self.segments.is_empty() || !(p.x.is_finite() && p.y.is_finite()) {
            return (max, None);
        }
        let (mut best, mut which) = (max, None);
        let f = (p - self.grid.origin) / self.grid.cell;
        let (px, py) = (f.x.floor() as i64, f.y.floor() as i64);
        let (nx, ny) = (self.grid.nx as i64, self.grid.ny as i64);
        // rings beyond this one lie wholly outside the grid
        let last = (px.max(nx - 1 - px).max(py).max(ny - 1 - py)).max(0);
        // and rings before this one miss it, or hold no segment
        let mut first = (px - (nx - 1)).max(-px).max(py - (ny - 1)).max(-py).max(0);
        if first == 0 {
            first = i64::from(self.empty_rings[(py * nx + px) as usize]);
        }
        let mut visit = |cx: i64, cy: i64, best: &mut f64| {
            if cx < 0 || cy < 0 || cx >= nx || cy >= ny {
                return;
            }
            for &s in &self.cells[(cy * nx + cx) as usize] {
                let (a, b) = self.segments[s as usize];
                let d = segment_distance(p, a, b);
                if d < *best {
                    *best = d;
                    which = Some(s as usize);
                }
            }
        };
        for ring in first..=last {
            // a segment first met in this ring is at least (ring − 1) cells away
            if (ring - 1) as f64 * self.grid.cell >= best {
                break;
            }
            if ring == 0 {
                visit(px, py, &mut best);
                continue;
            }
            for cx in px - ring..=px + ring {
                visit(cx, py - ring, &mut best);
                visit(cx, py + ring, &mut best);
            }
            for cy in py - ring + 1..=py + ring - 1 {
                visit(px - ring, cy, &mut best);
                visit(px + ring, cy, &mut best);
            }
        }
        (best, which)
    }

    /// Whether the segment `a`–`b` crosses or touches an indexed segment anywhere but at `a` or `b` themselves.
    pub fn crosses(&self, a: DVec2, b: DVec2, tolerance: f64) -> bool {
        let mut hit = false;
        self.for_each_candidate(a, b, |s| {
            if hit {
                return;
            }
            let (c, d) = self.segments[s];
            if let Some((t, _)) = segment_intersection(a, b, c, d) {
                let p = a + (b - a) * t;
                if p.distance(a) > tolerance && p.distance(b) > tolerance {
                    hit = true;
                }
            }
        });
        hit
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Roads added a few at a time give the rings and the distances an index of all of them at once gives.
    #[test]
    fn an_index_grown_road_by_road_answers_as_one_built_at_once() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (lo, hi) = (DVec2::new(-40.0, 10.0), DVec2::new(460.0, 310.0));
        let mut grown = SegmentIndex::empty_over(lo, hi, 8.0);
        let mut all = Vec::new();
        for _ in 0..30 {
            // a short road of a few segments somewhere in the box
            let mut p = DVec2::new(rng.random_range(lo.x..hi.x), rng.random_range(lo.y..hi.y));
            let mut road = Vec::new();
            for _ in 0..rng.random_range(1..6) {
                let q =
                    (p + DVec2::new(rng.random_range(-30.0..30.0), rng.random_range(-30.0..30.0)))
                        .clamp(lo, hi);
                road.push((p, q));
                p = q;
            }
            all.extend(road.iter().copied());
            grown.extend(road);
            let mut at_once = SegmentIndex::empty_over(lo, hi, 8.0);
            for (i, &(a, b)) in all.iter().enumerate() {
                at_once.list(i, a, b, None);
            }
            let rings = chebyshev_rings(&at_once.cells, at_once.grid.nx, at_once.grid.ny);
            assert_eq!(grown.empty_rings, rings);
            assert_eq!(grown.cells, at_once.cells);
        }
        for _ in 0..2000 {
            let p = DVec2::new(
                rng.random_range(-100.0..520.0),
                rng.random_range(-50.0..370.0),
            );
            let exact = all
                .iter()
                .map(|&(a, b)| segment_distance(p, a, b))
                .fold(f64::INFINITY, f64::min);
            assert_eq!(grown.distance(p, f64::INFINITY), exact);
            assert_eq!(grown.distance(p, 20.0), exact.min(20.0));
        }
    }
}

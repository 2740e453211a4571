//! Local growth from a seed (seed §5.1–5.4). "We sort seeds by the distance from the initial seed and choose the
//! nearest one in each growth step." For the chosen seed e^tar, every non-boundary reference element e^ref whose ring
//! is at least as large as the seed's current (partial) ring is compared by eq. (2)–(3) over the matching patterns
//! "which have no skipping and flipping": both rings counter-clockwise, the target's first neighbour paired in turn
//! with each reference neighbour. "We overlay a copy of the reference ring shape with the target seed neighborhood
//! … delete every neighboring element which was paired … The remaining elements will form new seeds with
//! corresponding symbol ids … Finally, we construct edges to connect the new seeds", with the heuristics of Fig. 6.
//!
//! Readings where the seed is vague:
//! - the target ring starts after its widest angular gap ("we start with the element which is on the boundary");
//! - `subid(e_i^tar, e_j^ref)` is 1 when the target neighbour is a copy of the very reference element it is paired
//!   with, so that the same reference patch does not repeat itself; seeds (not yet elements) have no sub-id, and a
//!   seed with no symbol id matches any symbol (`id` = 0);
//! - eq. (4) is solved as shape matching [MHTG05], i.e. the least-squares rotation θ = atan2(Σ r×q, Σ r·q) of the
//!   paired offsets, and the pattern's error is then eq. (2) at that θ; a seed with no neighbour takes a reference
//!   element drawn with the run's seeded generator, unrotated;
//! - seed priority (§5.1): a seed waits while a seed of higher priority lies within 5 l (l the reference's mean edge);
//!   symbols not listed and seeds with no symbol have priority 0;
//! - Fig. 6 (b): a new seed within r_short of an existing element or seed is dropped and the edge goes to that one;
//!   (c) a new edge whose angle to the seed's nearest edge on either side is under half the reference ring's angle
//!   there is dropped with its seed; (d) a new edge crossing an existing edge is dropped with its seed; (e) an edge
//!   between two consecutive ring neighbours longer than 1.5 × its reference length gets an extra seed, with no
//!   symbol id, on the bisector of the angle at the grown element at the mean length of the two edges; (f) where the
//!   extra seed's edges would cross existing ones, those edges are left out;
//! - seeds outside the region are not created; the element that wanted them is flagged `at_region_boundary`;
//! - a seed no reference element can match (its ring is larger than every reference ring) is removed;
//! - relaxation during growth ("after each growth step") is run every [`GrowthOptions::relax_every`] placed elements
//!   over elements and seeds, seeds and edges without a reference ring keeping their current shape.
//!
//! Growth is sequential and uses one `ChaCha8Rng` seeded from [`GrowthOptions::seed`]: the result does not depend on
//! the thread count.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::connectivity::segments_cross;
use super::relax::{solve, Term};
use super::{Arrangement, Element, Reference, RingTarget};
use crate::error::{check, Error, Result};
use crate::geom::Region;

/// How a reference ring is turned when it is matched to a seed (seed §5.3; the flow-field mode comes later).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RotationMode {
    /// The reference is used as it is: the pattern keeps the reference's orientation.
    #[default]
    None,
    /// Each match is turned by its best-fitting rotation (eq. (4), shape matching).
    BestFit,
}

/// The weights of eq. (2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MatchWeights {
    /// w1: distance between paired relative positions (per metre).
    pub distance: f64,
    /// w2: paired neighbours of different symbol ids.
    pub symbol: f64,
    /// w3: a paired neighbour that is a copy of the reference neighbour it is paired with.
    pub sub_id: f64,
}

impl Default for MatchWeights {
    /// The seed's values: w1 = 1, w2 = 1, w3 = 100.
    fn default() -> Self {
        MatchWeights {
            distance: 1.0,
            symbol: 1.0,
            sub_id: 100.0,
        }
    }
}

/// How a pattern is grown.
#[derive(Clone, Debug, PartialEq)]
pub struct GrowthOptions {
    /// How reference rings are turned.
    pub rotation: RotationMode,
    /// Growth stops once this many elements are placed (or no seed is left).
    pub max_elements: usize,
    /// The seed of the run's random generator.
    pub seed: u64,
    /// The weights of eq. (2).
    pub weights: MatchWeights,
    /// Priority per symbol id (higher grows first within 5 l); unlisted symbols have 0.
    pub priorities: Vec<(u32, i32)>,
    /// The symbol the initial seed must become, if any.
    pub initial_symbol: Option<u32>,
    /// Relax (eq. (5)–(6)) the elements and seeds grown so far after every this many placed elements; 0 never.
    /// The seed relaxes "after each growth step" (1); a few steps apart keep the pattern as regular for less work.
    pub relax_every: usize,
}

impl Default for GrowthOptions {
    fn default() -> Self {
        GrowthOptions {
            rotation: RotationMode::None,
            max_elements: 1_000,
            seed: 0,
            weights: MatchWeights::default(),
            priorities: Vec::new(),
            initial_symbol: None,
            relax_every: 0,
        }
    }
}

/// Grows a pattern from one seed at `start` inside `region`, copying `reference`'s local structure.
pub fn grow(
    reference: &Reference,
    region: &Region,
    start: DVec2,
    options: &GrowthOptions,
) -> Result<Arrangement> {
    region.validate()?;
    if !start.is_finite() || !region.contains(start) {
        return Err(Error::invalid(
            "growth start",
            format!(
                "({}, {}) is not a point inside the region",
                start.x, start.y
            ),
        ));
    }
    if options.max_elements == 0 {
        return Err(Error::invalid("max elements", "must be at least 1"));
    }
    crate::limits::check(
        "arrangement growth",
        options.max_elements as f64,
        crate::limits::MAX_INSTANCES,
        "instances",
    )?;
    check::non_negative("match weight w1", options.weights.distance)?;
    check::non_negative("match weight w2", options.weights.symbol)?;
    check::non_negative("match weight w3", options.weights.sub_id)?;
    if let Some(symbol) = options.initial_symbol {
        let found = (0..reference.elements().len())
            .any(|i| !reference.is_boundary(i) && reference.elements()[i].symbol == symbol);
        if !found {
            return Err(Error::unknown(
                "symbol id among the reference's interior elements",
                symbol.to_string(),
            ));
        }
    }
    let mut grower = Grower::new(reference, region, start, options);
    grower.run()?;
    Ok(grower.finish())
}

#[derive(Clone, Copy, PartialEq)]
enum State {
    Seed,
    Element { sub_id: usize, rotation: f64 },
    Dead,
}

struct Node {
    position: DVec2,
    symbol: Option<u32>,
    state: State,
}

/// One reference element's ring, as offsets from it.
struct RefRing {
    sub_id: usize,
    symbol: u32,
    offsets: Vec<DVec2>,
    symbols: Vec<u32>,
    sub_ids: Vec<usize>,
}

struct Match {
    ring: usize,
    theta: f64,
    shift: usize,
    targets: Vec<usize>,
}

struct Grower<'a> {
    reference: &'a Reference,
    region: &'a Region,
    options: &'a GrowthOptions,
    rings: Vec<RefRing>,
    start: DVec2,
    nodes: Vec<Node>,
    adjacency: Vec<Vec<usize>>,
    targets: Vec<Vec<(usize, DVec2)>>,
    cut: Vec<bool>,
    grid: HashMap<(i64, i64), Vec<usize>>,
    cell: f64,
    max_edge: f64,
    r_short: f64,
    heap: BinaryHeap<Reverse<(u64, usize)>>,
    placed: Vec<usize>,
    rng: ChaCha8Rng,
}

impl<'a> Grower<'a> {
    fn new(
        reference: &'a Reference,
        region: &'a Region,
        start: DVec2,
        options: &'a GrowthOptions,
    ) -> Self {
        let elements = reference.elements();
        let rings = (0..elements.len())
            .filter(|&i| !reference.is_boundary(i))
            .map(|i| {
                let ring = reference.ring(i);
                RefRing {
                    sub_id: i,
                    symbol: elements[i].symbol,
                    offsets: ring
                        .iter()
                        .map(|&j| elements[j].position - elements[i].position)
                        .collect(),
                    symbols: ring.iter().map(|&j| elements[j].symbol).collect(),
                    sub_ids: ring.to_vec(),
                }
            })
            .collect();
        let mut grower = Grower {
            reference,
            region,
            options,
            rings,
            start,
            nodes: Vec::new(),
            adjacency: Vec::new(),
            targets: Vec::new(),
            cut: Vec::new(),
            grid: HashMap::new(),
            cell: reference.mean_edge().max(f64::MIN_POSITIVE),
            max_edge: 0.0,
            r_short: reference.r_short(),
            heap: BinaryHeap::new(),
            placed: Vec::new(),
            rng: ChaCha8Rng::seed_from_u64(options.seed),
        };
        grower.add_seed(start, options.initial_symbol);
        grower
    }

    fn cell_of(&self, p: DVec2) -> (i64, i64) {
        (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
        )
    }

    fn add_seed(&mut self, position: DVec2, symbol: Option<u32>) -> usize {
        let id = self.nodes.len();
        self.nodes.push(Node {
            position,
            symbol,
            state: State::Seed,
        });
        self.adjacency.push(Vec::new());
        self.targets.push(Vec::new());
        self.cut.push(false);
        let cell = self.cell_of(position);
        self.grid.entry(cell).or_default().push(id);
        let distance = position.distance(self.start);
        self.heap.push(Reverse((distance.to_bits(), id)));
        id
    }

    /// Live nodes within `radius` of `p`, in index order.
    fn near(&self, p: DVec2, radius: f64) -> Vec<usize> {
        let (lo, hi) = (self.cell_of(p - radius), self.cell_of(p + radius));
        let mut found = Vec::new();
        for cx in lo.0..=hi.0 {
            for cy in lo.1..=hi.1 {
                if let Some(bucket) = self.grid.get(&(cx, cy)) {
                    found.extend(bucket.iter().copied().filter(|&i| {
                        self.nodes[i].state != State::Dead
                            && self.nodes[i].position.distance(p) <= radius
                    }));
                }
            }
        }
        found.sort_unstable();
        found
    }

    /// Whether the segment `a`–`b` between node `from` and `to` (a node, or none yet) crosses an existing edge.
    fn collides(&self, from: usize, to: Option<usize>, a: DVec2, b: DVec2) -> bool {
        let radius = 0.5 * a.distance(b) + self.max_edge;
        self.near(0.5 * (a + b), radius).into_iter().any(|u| {
            u != from
                && Some(u) != to
                && self.adjacency[u].iter().any(|&v| {
                    v != from
                        && Some(v) != to
                        && segments_cross(a, b, self.nodes[u].position, self.nodes[v].position)
                })
        })
    }

    fn connect(&mut self, a: usize, b: usize) {
        if a != b && !self.adjacency[a].contains(&b) {
            self.adjacency[a].push(b);
            self.adjacency[b].push(a);
            let length = self.nodes[a].position.distance(self.nodes[b].position);
            self.max_edge = self.max_edge.max(length);
        }
    }

    fn priority(&self, symbol: Option<u32>) -> i32 {
        symbol
            .and_then(|s| self.options.priorities.iter().find(|p| p.0 == s))
            .map_or(0, |p| p.1)
    }

    /// The next seed to grow: the nearest to the initial one, unless one of higher priority lies within 5 l.
    fn next_seed(&mut self) -> Option<usize> {
        let mut s = loop {
            let Reverse((_, id)) = self.heap.pop()?;
            if self.nodes[id].state == State::Seed {
                break id;
            }
        };
        if self.options.priorities.is_empty() {
            return Some(s);
        }
        loop {
            let p = self.priority(self.nodes[s].symbol);
            let higher = self
                .near(self.nodes[s].position, 5.0 * self.reference.mean_edge())
                .into_iter()
                .filter(|&i| {
                    self.nodes[i].state == State::Seed && self.priority(self.nodes[i].symbol) > p
                })
                .min_by(|&i, &j| {
                    let (di, dj) = (
                        self.nodes[i].position.distance(self.start),
                        self.nodes[j].position.distance(self.start),
                    );
                    di.total_cmp(&dj).then(i.cmp(&j))
                });
            match higher {
                Some(h) => {
                    let d = self.nodes[s].position.distance(self.start);
                    self.heap.push(Reverse((d.to_bits(), s)));
                    s = h;
                }
                None => return Some(s),
            }
        }
    }

    fn run(&mut self) -> Result<()> {
        while self.placed.len() < self.options.max_elements {
            let Some(s) = self.next_seed() else { break };
            match self.best_match(s) {
                Some(m) => {
                    self.place(s, m);
                    let every = self.options.relax_every;
                    if every > 0 && self.placed.len().is_multiple_of(every) {
                        self.relax()?;
                    }
                }
                None => self.remove(s),
            }
        }
        Ok(())
    }

    /// Eq. (5)–(6) over the elements and seeds so far: elements pull their ring neighbours to their reference
    /// offsets, every other edge keeps its current offset (seed §5.5: "All seeds do not have corresponding reference
    /// elements yet … we use their current neighboring shapes"); the initial element and the elements the region
    /// stopped are held. The seeds move with the elements, and the heap order (distance to the start) is kept.
    fn relax(&mut self) -> Result<()> {
        let n = self.nodes.len();
        let x0: Vec<DVec2> = self.nodes.iter().map(|node| node.position).collect();
        let mut terms = Vec::new();
        let mut targeted = std::collections::BTreeSet::new();
        for i in 0..n {
            if self.nodes[i].state == State::Dead {
                continue;
            }
            for &(j, offset) in &self.targets[i] {
                if self.nodes[j].state != State::Dead && targeted.insert((i, j)) {
                    terms.push(Term { i, j, offset });
                }
            }
        }
        for i in 0..n {
            for &j in &self.adjacency[i] {
                if !targeted.contains(&(i, j)) {
                    terms.push(Term {
                        i,
                        j,
                        offset: x0[j] - x0[i],
                    });
                }
            }
        }
        let fixed: Vec<bool> = (0..n)
            .map(|i| i == 0 || self.cut[i] || self.nodes[i].state == State::Dead)
            .collect();
        let x = solve(&x0, &terms, &fixed)?;
        self.grid.clear();
        for (i, p) in x.into_iter().enumerate() {
            self.nodes[i].position = p;
            let cell = self.cell_of(p);
            self.grid.entry(cell).or_default().push(i);
        }
        self.max_edge = 0.0;
        for i in 0..n {
            for &j in &self.adjacency[i] {
                let length = self.nodes[i].position.distance(self.nodes[j].position);
                self.max_edge = self.max_edge.max(length);
            }
        }
        Ok(())
    }

    fn remove(&mut self, s: usize) {
        self.nodes[s].state = State::Dead;
        for n in std::mem::take(&mut self.adjacency[s]) {
            self.adjacency[n].retain(|&x| x != s);
        }
    }

    /// The seed's live neighbours, counter-clockwise, starting after the widest angular gap.
    fn target_ring(&self, s: usize) -> Vec<usize> {
        let p = self.nodes[s].position;
        let mut ring: Vec<(f64, usize)> = self.adjacency[s]
            .iter()
            .map(|&n| ((self.nodes[n].position - p).to_angle(), n))
            .collect();
        ring.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let m = ring.len();
        if m < 2 {
            return ring.into_iter().map(|r| r.1).collect();
        }
        let gap = |k: usize| (ring[(k + 1) % m].0 - ring[k].0).rem_euclid(std::f64::consts::TAU);
        let widest = (0..m)
            .max_by(|&a, &b| gap(a).total_cmp(&gap(b)).then(b.cmp(&a)))
            .unwrap_or(0);
        (0..m).map(|i| ring[(widest + 1 + i) % m].1).collect()
    }

    fn best_match(&mut self, s: usize) -> Option<Match> {
        let symbol = self.nodes[s].symbol;
        let targets = self.target_ring(s);
        let m = targets.len();
        let candidates: Vec<usize> = (0..self.rings.len())
            .filter(|&r| symbol.is_none_or(|sym| self.rings[r].symbol == sym))
            .filter(|&r| self.rings[r].offsets.len() >= m)
            .collect();
        if candidates.is_empty() {
            return None;
        }
        if m == 0 {
            let ring = candidates[self.rng.random_range(0..candidates.len())];
            return Some(Match {
                ring,
                theta: 0.0,
                shift: 0,
                targets,
            });
        }
        let p = self.nodes[s].position;
        let q: Vec<DVec2> = targets
            .iter()
            .map(|&t| self.nodes[t].position - p)
            .collect();
        let w = self.options.weights;
        let mut best: Option<(f64, Match)> = None;
        for &r in &candidates {
            let ring = &self.rings[r];
            let n = ring.offsets.len();
            for shift in 0..n {
                let theta = match self.options.rotation {
                    RotationMode::None => 0.0,
                    RotationMode::BestFit => {
                        let (mut cross, mut dot) = (0.0, 0.0);
                        for (i, qi) in q.iter().enumerate() {
                            let o = ring.offsets[(shift + i) % n];
                            cross += o.perp_dot(*qi);
                            dot += o.dot(*qi);
                        }
                        cross.atan2(dot)
                    }
                };
                let rot = DVec2::from_angle(theta);
                let mut error = 0.0;
                for (i, &t) in targets.iter().enumerate() {
                    let slot = (shift + i) % n;
                    error += w.distance * q[i].distance(rot.rotate(ring.offsets[slot]));
                    let node = &self.nodes[t];
                    if node.symbol.is_some_and(|sym| sym != ring.symbols[slot]) {
                        error += w.symbol;
                    }
                    if let State::Element { sub_id, .. } = node.state {
                        if sub_id == ring.sub_ids[slot] {
                            error += w.sub_id;
                        }
                    }
                }
                if best.as_ref().is_none_or(|b| error < b.0) {
                    best = Some((
                        error,
                        Match {
                            ring: r,
                            theta,
                            shift,
                            targets: Vec::new(),
                        },
                    ));
                }
            }
        }
        best.map(|(_, mut m)| {
            m.targets = targets;
            m
        })
    }

    /// Replaces seed `s` by the matched reference element and grows its ring (Fig. 2 d–h, Fig. 6).
    fn place(&mut self, s: usize, m: Match) {
        let ring = &self.rings[m.ring];
        let (sub_id, n) = (ring.sub_id, ring.offsets.len());
        let rot = DVec2::from_angle(m.theta);
        let offsets: Vec<DVec2> = ring.offsets.iter().map(|&o| rot.rotate(o)).collect();
        let symbols = ring.symbols.clone();
        let rotation = self.reference.elements()[sub_id].rotation + m.theta;
        self.nodes[s].state = State::Element { sub_id, rotation };
        self.nodes[s].symbol = Some(self.reference.elements()[sub_id].symbol);
        self.placed.push(s);
        let p = self.nodes[s].position;

        let mut assigned: Vec<Option<usize>> = vec![None; n];
        for (i, &t) in m.targets.iter().enumerate() {
            let slot = (m.shift + i) % n;
            assigned[slot] = Some(t);
            self.targets[s].push((t, offsets[slot]));
        }
        let first_free = m.shift + m.targets.len();
        for step in 0..n {
            let j = (first_free + step) % n;
            if assigned[j].is_some() {
                continue;
            }
            let c = p + offsets[j];
            if !self.region.contains(c) {
                self.cut[s] = true;
                continue;
            }
            // (b) an element or seed already within r_short takes the slot
            if let Some(&found) = self
                .near(c, self.r_short)
                .iter()
                .filter(|&&i| i != s)
                .min_by(|&&a, &&b| {
                    let (da, db) = (
                        self.nodes[a].position.distance(c),
                        self.nodes[b].position.distance(c),
                    );
                    da.total_cmp(&db).then(a.cmp(&b))
                })
            {
                let fp = self.nodes[found].position;
                if self.adjacency[s].contains(&found) || !self.collides(s, Some(found), p, fp) {
                    self.connect(s, found);
                    assigned[j] = Some(found);
                    self.targets[s].push((found, offsets[j]));
                }
                continue;
            }
            // (c) the angle to the nearest edges on either side
            if self.too_narrow(s, offsets[j], &offsets, j) {
                continue;
            }
            // (d) edge collisions
            if self.collides(s, None, p, c) {
                continue;
            }
            let seed = self.add_seed(c, Some(symbols[j]));
            self.connect(s, seed);
            assigned[j] = Some(seed);
            self.targets[s].push((seed, offsets[j]));
        }
        // edges between consecutive ring neighbours, with (e)–(f) for the long ones
        for j in 0..n {
            let next = (j + 1) % n;
            let (Some(a), Some(b)) = (assigned[j], assigned[next]) else {
                continue;
            };
            if a == b || self.adjacency[a].contains(&b) {
                continue;
            }
            let (pa, pb) = (self.nodes[a].position, self.nodes[b].position);
            let original = offsets[j].distance(offsets[next]);
            if pa.distance(pb) > 1.5 * original {
                self.extra_seed(s, a, b);
            } else if !self.collides(a, Some(b), pa, pb) {
                self.connect(a, b);
            }
        }
    }

    /// Fig. 6 (c): whether a new edge along `d` at `s` makes an angle under half the reference's with the nearest
    /// existing edge on either side.
    fn too_narrow(&self, s: usize, d: DVec2, offsets: &[DVec2], j: usize) -> bool {
        if self.adjacency[s].is_empty() {
            return false;
        }
        let n = offsets.len();
        let tau = std::f64::consts::TAU;
        let ccw_original = d.angle_to(offsets[(j + 1) % n]).rem_euclid(tau);
        let cw_original = offsets[(j + n - 1) % n].angle_to(d).rem_euclid(tau);
        let p = self.nodes[s].position;
        let (mut ccw, mut cw) = (tau, tau);
        for &nb in &self.adjacency[s] {
            let e = self.nodes[nb].position - p;
            ccw = ccw.min(d.angle_to(e).rem_euclid(tau));
            cw = cw.min(e.angle_to(d).rem_euclid(tau));
        }
        ccw < 0.5 * ccw_original || cw < 0.5 * cw_original
    }

    /// Fig. 6 (e)–(f): an extra seed, with no symbol, on the bisector of the angle a–s–b.
    fn extra_seed(&mut self, s: usize, a: usize, b: usize) {
        let p = self.nodes[s].position;
        let (da, db) = (self.nodes[a].position - p, self.nodes[b].position - p);
        let half = 0.5 * da.angle_to(db).rem_euclid(std::f64::consts::TAU);
        let length = 0.5 * (da.length() + db.length());
        let x = p + DVec2::from_angle(half).rotate(da.normalize_or_zero()) * length;
        if !self.region.contains(x) {
            self.cut[s] = true;
            return;
        }
        if !self.near(x, self.r_short).is_empty() || self.collides(s, None, p, x) {
            return;
        }
        let seed = self.add_seed(x, None);
        self.connect(s, seed);
        for end in [a, b] {
            let pe = self.nodes[end].position;
            if !self.collides(seed, Some(end), x, pe) {
                self.connect(seed, end);
            }
        }
    }

    fn finish(self) -> Arrangement {
        let mut index = vec![usize::MAX; self.nodes.len()];
        for (k, &node) in self.placed.iter().enumerate() {
            index[node] = k;
        }
        let mut arrangement = Arrangement::default();
        for &node in &self.placed {
            let (sub_id, rotation) = match self.nodes[node].state {
                State::Element { sub_id, rotation } => (sub_id, rotation),
                _ => (0, 0.0),
            };
            arrangement.elements.push(Element {
                position: self.nodes[node].position,
                symbol: self.nodes[node].symbol.unwrap_or(0),
                rotation,
            });
            arrangement.sub_ids.push(sub_id);
            arrangement.at_region_boundary.push(self.cut[node]);
            arrangement.ring_targets.push(
                self.targets[node]
                    .iter()
                    .filter(|t| index[t.0] != usize::MAX)
                    .map(|&(t, offset)| RingTarget {
                        neighbour: index[t],
                        offset,
                    })
                    .collect(),
            );
            for &nb in &self.adjacency[node] {
                let (i, j) = (index[node], index[nb]);
                if j != usize::MAX && i < j {
                    arrangement.edges.push((i, j));
                }
            }
        }
        arrangement.edges.sort_unstable();
        arrangement
    }
}

//! Local growth from seeds (seed §5.1–5.4). "We sort seeds by the distance from the initial seed and choose the
//! nearest one in each growth step." The chosen seed is matched to a reference element (`super::matching`), then
//! "we overlay a copy of the reference ring shape with the target seed neighborhood … delete every neighboring
//! element which was paired … The remaining elements will form new seeds with corresponding symbol ids … Finally,
//! we construct edges to connect the new seeds", with the heuristics of Fig. 6.
//!
//! Readings where the seed is vague:
//! - seed priority (§5.1): a seed waits while a seed of higher priority lies within 5 l (l the reference's mean edge);
//!   symbols not listed and seeds with no symbol have priority 0;
//! - Fig. 6 (b): a new seed within r_short of an existing element or seed is dropped and the edge goes to that one;
//!   a new seed between r_short and 0.8 × the shortest reference edge of another node is dropped with its edge (the
//!   seed's figure leaves this band open, and an irregular reference's spacing is lost through it: with r_short alone
//!   6.5 % of grown elements stood closer than 0.8 mean spacings to a neighbour, none of the reference's did);
//!   (c) a new edge whose angle to the seed's nearest edge on either side is under half the reference ring's angle
//!   there is dropped with its seed (not on a lattice, whose sites are a spacing apart); (d) a new edge crossing an existing edge is dropped with its seed; (e) an edge
//!   between two consecutive ring neighbours longer than 1.5 × its reference length gets an extra seed, with no
//!   symbol id, on the bisector of the angle at the grown element at the mean length of the two edges (on a lattice,
//!   at the site nearest that point); (f) where the extra seed's edges would cross existing ones, those edges are
//!   left out;
//! - a near-regular reference's rings are copied with the offsets of the lattice it stands on (`super::lattice`);
//! - seeds outside the region or across a boundary curve are not created, and no edge crosses a boundary curve; the
//!   element that wanted them is flagged `at_region_boundary` (held by the relaxation, as §5.5 holds "elements at
//!   their generated positions" when "there are user-specified boundaries");
//! - a seed no reference element can match (its ring is larger than every reference ring) is removed;
//! - relaxation during growth ("after each growth step") is run every [`GrowthOptions::relax_every`] placed elements
//!   over a window: the elements placed in the last 2 × `relax_every` steps and the seeds next to them, their other
//!   neighbours held. Seeds and edges without a reference ring keep their current shape. The seed relaxes the whole
//!   pattern, which costs the pattern's size at each step (it reports 5 s for 1,000 elements); what a step changes is
//!   the newest elements' rings, so the window does the same work where it matters, in time independent of the
//!   pattern's size. A node whose move would cross a boundary curve (or take an edge across one) stays put.
//!
//! Growth is sequential and uses one `ChaCha8Rng` seeded from [`GrowthOptions::seed`]: the result does not depend on
//! the thread count.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::DVec2;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::boundary::BoundaryIndex;
use super::cells::{Cells, FastMap, FastSet};
use super::connectivity::segments_cross;
use super::lattice::Lattice;
use super::matching::Match;
use super::options::GrowthOptions;
use super::relax::{solve, Term};
use super::ReferenceArrangement;
use crate::error::{Error, Result};
use crate::geom::{PreparedRegion, RegionQueries};

/// Progress is reported every this many placed elements.
const PROGRESS_EVERY: usize = 256;
/// A new seed nearer than this fraction of the reference's shortest edge to another node (but beyond r_short, where
/// Fig. 6 (b) pairs it) is not created.
const CROWDED: f64 = 0.8;

#[derive(Clone, Copy, PartialEq)]
pub(super) enum State {
    Seed,
    Element { sub_id: usize, rotation: f64 },
    Dead,
}

pub(super) struct Node {
    pub(super) position: DVec2,
    pub(super) symbol: Option<u32>,
    pub(super) state: State,
}

/// One reference element's ring, as offsets from it.
pub(super) struct RefRing {
    pub(super) sub_id: usize,
    pub(super) symbol: u32,
    pub(super) offsets: Vec<DVec2>,
    pub(super) symbols: Vec<u32>,
    pub(super) sub_ids: Vec<usize>,
}

/// The state of one growth: the nodes (existing elements first, then the grown elements and seeds), their
/// connectivity and the seeds' queue.
pub(super) struct Grower<'a> {
    pub(super) reference: &'a ReferenceArrangement,
    region: PreparedRegion<'a>,
    pub(super) options: &'a GrowthOptions,
    boundaries: BoundaryIndex,
    pub(super) rings: Vec<RefRing>,
    /// Seeds are grown nearest-first from here.
    pub(super) origin: DVec2,
    pub(super) nodes: Vec<Node>,
    pub(super) adjacency: Vec<Vec<usize>>,
    pub(super) targets: Vec<Vec<(usize, DVec2)>>,
    pub(super) cut: Vec<bool>,
    /// Nodes `0..existing` are the caller's existing elements: never moved or removed.
    pub(super) existing: usize,
    /// The initial seed, held by the relaxation.
    pub(super) initial: Option<usize>,
    grid: Cells,
    max_edge: f64,
    pub(super) r_short: f64,
    /// The lattice a near-regular reference stands on (see `lattice`).
    pub(super) lattice: Option<Lattice>,
    heap: BinaryHeap<Reverse<(u64, usize)>>,
    /// The new elements, in the order they were placed.
    pub(super) placed: Vec<usize>,
    pub(super) rng: ChaCha8Rng,
}

impl<'a> Grower<'a> {
    pub(super) fn new(
        reference: &'a ReferenceArrangement,
        region: PreparedRegion<'a>,
        options: &'a GrowthOptions,
    ) -> Result<Self> {
        let elements = reference.elements();
        // a near-regular reference's rings are copied on the lattice it was meant to be (see `lattice`)
        let lattice = reference.lattice().copied();
        let ring_of = |i: usize, lattice: Option<&Lattice>| {
            let ring = reference.ring(i);
            let offset = |j: usize| {
                let o = elements[j].position - elements[i].position;
                lattice.map_or(o, |l| l.vector_near(o))
            };
            RefRing {
                sub_id: i,
                symbol: elements[i].symbol,
                offsets: ring.iter().map(|&j| offset(j)).collect(),
                symbols: ring.iter().map(|&j| elements[j].symbol).collect(),
                sub_ids: ring.to_vec(),
            }
        };
        let interior = || (0..elements.len()).filter(|&i| !reference.is_boundary(i));
        let on_lattice: Vec<RefRing> = match &lattice {
            Some(l) => interior()
                .map(|i| ring_of(i, Some(l)))
                .filter(|r| l.is_ring(&r.offsets))
                .collect(),
            None => Vec::new(),
        };
        let (lattice, rings) = if on_lattice.is_empty() {
            (None, interior().map(|i| ring_of(i, None)).collect())
        } else {
            (lattice, on_lattice)
        };
        let cell = reference.mean_edge().max(f64::MIN_POSITIVE);
        Ok(Grower {
            reference,
            region,
            options,
            boundaries: BoundaryIndex::new(&options.boundaries, cell)?,
            rings,
            origin: DVec2::ZERO,
            nodes: Vec::new(),
            adjacency: Vec::new(),
            targets: Vec::new(),
            cut: Vec::new(),
            existing: 0,
            initial: None,
            grid: Cells::new(cell),
            max_edge: 0.0,
            r_short: reference.r_short(),
            lattice,
            heap: BinaryHeap::new(),
            placed: Vec::new(),
            rng: ChaCha8Rng::seed_from_u64(options.seed),
        })
    }

    pub(super) fn region_contains(&self, p: DVec2) -> bool {
        self.region.contains(p)
    }

    /// The distance from `p` to the region's boundary, read no further than `max`.
    pub(super) fn region_distance_within(&self, p: DVec2, max: f64) -> f64 {
        self.region.distance_to_boundary_within(p, max)
    }

    /// A new node (not yet queued).
    pub(super) fn add_node(&mut self, position: DVec2, symbol: Option<u32>, state: State) -> usize {
        let id = self.nodes.len();
        self.nodes.push(Node {
            position,
            symbol,
            state,
        });
        self.adjacency.push(Vec::new());
        self.targets.push(Vec::new());
        self.cut.push(false);
        self.grid.insert(position, id);
        id
    }

    /// Queues node `id` as a seed, by its distance from the origin.
    pub(super) fn queue(&mut self, id: usize) {
        let distance = self.nodes[id].position.distance(self.origin);
        self.heap.push(Reverse((distance.to_bits(), id)));
    }

    fn add_seed(&mut self, position: DVec2, symbol: Option<u32>) -> usize {
        let id = self.add_node(position, symbol, State::Seed);
        self.queue(id);
        id
    }

    /// A seed at `start` (the initial one), unless an existing element lies within the reference's shortest edge
    /// (2 r_short) of it: there is no room for an element there (a spray dab over a full pattern adds nothing).
    pub(super) fn add_initial_seed(&mut self, start: DVec2) {
        if !self.any_within(start, 2.0 * self.r_short, None) {
            let id = self.add_seed(start, self.options.initial_symbol);
            self.initial = Some(id);
        }
    }

    /// Live nodes within `radius` of `p`, in index order.
    pub(super) fn near(&self, p: DVec2, radius: f64) -> Vec<usize> {
        let mut found = Vec::new();
        self.grid.any_near(p, radius, |i| {
            if self.is_within(i, p, radius) {
                found.push(i);
            }
            false
        });
        found.sort_unstable();
        found
    }

    fn is_within(&self, i: usize, p: DVec2, radius: f64) -> bool {
        self.nodes[i].state != State::Dead
            && self.nodes[i].position.distance_squared(p) <= radius * radius
    }

    /// Whether a live node other than `except` lies within `radius` of `p`.
    fn any_within(&self, p: DVec2, radius: f64, except: Option<usize>) -> bool {
        self.grid.any_near(p, radius, |i| {
            Some(i) != except && self.is_within(i, p, radius)
        })
    }

    /// The live node other than `except` nearest to `p` within `radius` (the lower index among equally near ones).
    fn nearest_within(&self, p: DVec2, radius: f64, except: usize) -> Option<usize> {
        let mut best: Option<(f64, usize)> = None;
        self.grid.any_near(p, radius, |i| {
            if i != except && self.is_within(i, p, radius) {
                let d = self.nodes[i].position.distance(p);
                if best.is_none_or(|(bd, bi)| d.total_cmp(&bd).then(i.cmp(&bi)).is_lt()) {
                    best = Some((d, i));
                }
            }
            false
        });
        best.map(|(_, i)| i)
    }

    /// Whether the segment `a`–`b` between node `from` and `to` (a node, or none yet) crosses an existing edge. An
    /// edge that crosses it has an end within half its length of the crossing, so within half the segment's
    /// length and half the longest edge of the segment's middle.
    fn collides(&self, from: usize, to: Option<usize>, a: DVec2, b: DVec2) -> bool {
        let (mid, radius) = (0.5 * (a + b), 0.5 * (a.distance(b) + self.max_edge));
        self.grid.any_near(mid, radius, |u| {
            u != from
                && Some(u) != to
                && self.is_within(u, mid, radius)
                && self.adjacency[u].iter().any(|&v| {
                    v != from
                        && Some(v) != to
                        && segments_cross(a, b, self.nodes[u].position, self.nodes[v].position)
                })
        })
    }

    pub(super) fn connect(&mut self, a: usize, b: usize) {
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

    /// The next seed to grow: the nearest to the origin, unless one of higher priority lies within 5 l.
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
                        self.nodes[i].position.distance(self.origin),
                        self.nodes[j].position.distance(self.origin),
                    );
                    di.total_cmp(&dj).then(i.cmp(&j))
                });
            match higher {
                Some(h) => {
                    self.queue(s);
                    s = h;
                }
                None => return Some(s),
            }
        }
    }

    /// Grows until no seed is left or `max_elements` are placed; `progress` hears the fraction of `expected`
    /// elements placed every few hundred, and cancels with `false`.
    pub(super) fn run(
        &mut self,
        expected: f64,
        reopened: &std::collections::HashMap<usize, (usize, f64)>,
        progress: &dyn Fn(f64) -> bool,
    ) -> Result<()> {
        while self.placed.len() < self.options.max_elements {
            let Some(s) = self.next_seed() else { break };
            match self.best_match(s, true) {
                Some(m) => {
                    let before = self.placed.len();
                    self.place(s, m);
                    let every = self.options.relax_every;
                    if self.placed.len() > before {
                        if every > 0 && self.placed.len().is_multiple_of(every) {
                            self.relax_window()?;
                        }
                        if self.placed.len().is_multiple_of(PROGRESS_EVERY)
                            && !progress((self.placed.len() as f64 / expected).min(0.99))
                        {
                            return Err(Error::Cancelled);
                        }
                    }
                }
                None => match reopened.get(&s) {
                    // an existing element stays what it was
                    Some(&(sub_id, rotation)) => {
                        self.nodes[s].state = State::Element { sub_id, rotation }
                    }
                    None => self.remove(s),
                },
            }
        }
        Ok(())
    }

    /// Whether the relaxation may move node `i`.
    fn movable(&self, i: usize) -> bool {
        i >= self.existing
            && !self.cut[i]
            && Some(i) != self.initial
            && self.nodes[i].state != State::Dead
    }

    /// Eq. (5)–(6) over the newest elements and the seeds next to them (see the module's readings): elements pull
    /// their ring neighbours to their reference offsets, every other edge keeps its current offset (seed §5.5: "All
    /// seeds do not have corresponding reference elements yet … we use their current neighboring shapes"); the
    /// window's other neighbours are held, as are existing elements, the initial element and those the region or a
    /// boundary stopped. The heap order (distance to the origin at queueing) is kept.
    fn relax_window(&mut self) -> Result<()> {
        let recent = self
            .placed
            .len()
            .saturating_sub(2 * self.options.relax_every);
        let mut local: FastMap<usize, usize> = FastMap::default();
        let mut order: Vec<usize> = Vec::new();
        let mut free: Vec<bool> = Vec::new();
        let mut add = |node: usize, is_free: bool, order: &mut Vec<usize>, free: &mut Vec<bool>| {
            local.entry(node).or_insert_with(|| {
                order.push(node);
                free.push(is_free);
                order.len() - 1
            });
        };
        for &e in &self.placed[recent..] {
            if self.movable(e) {
                add(e, true, &mut order, &mut free);
            }
        }
        for &e in &self.placed[recent..] {
            for &nb in &self.adjacency[e] {
                if self.nodes[nb].state == State::Seed && self.movable(nb) {
                    add(nb, true, &mut order, &mut free);
                }
            }
        }
        let movers = order.len();
        if movers == 0 {
            return Ok(());
        }
        for k in 0..movers {
            for &nb in &self.adjacency[order[k]] {
                add(nb, false, &mut order, &mut free);
            }
        }
        let mut terms = Vec::new();
        let mut seen: FastSet<(usize, usize)> = FastSet::default();
        let mut targeted: FastSet<(usize, usize)> = FastSet::default();
        for &i in &order[..movers] {
            for &nb in &self.adjacency[i] {
                for (a, b) in [(i, nb), (nb, i)] {
                    if let Some(&(_, offset)) = self.targets[a].iter().find(|t| t.0 == b) {
                        targeted.insert((a, b));
                        if seen.insert((a, b)) {
                            terms.push(Term {
                                i: local[&a],
                                j: local[&b],
                                offset,
                            });
                        }
                    }
                }
            }
        }
        for &i in &order[..movers] {
            for &nb in &self.adjacency[i] {
                for (a, b) in [(i, nb), (nb, i)] {
                    if !targeted.contains(&(a, b)) && seen.insert((a, b)) {
                        terms.push(Term {
                            i: local[&a],
                            j: local[&b],
                            offset: self.nodes[b].position - self.nodes[a].position,
                        });
                    }
                }
            }
        }
        let x0: Vec<DVec2> = order.iter().map(|&i| self.nodes[i].position).collect();
        let fixed: Vec<bool> = free.iter().map(|f| !f).collect();
        let mut x = solve(&x0, &terms, &fixed)?;
        if !self.boundaries.is_empty() {
            self.keep_off_boundaries(&order[..movers], &x0, &mut x, &local);
        }
        for (k, &i) in order[..movers].iter().enumerate() {
            // a move out of the region, or within r_short of another node, is not made (Fig. 6 (b) holds after it too)
            if x[k] == x0[k]
                || !self.region.contains(x[k])
                || self.any_within(x[k], self.r_short, Some(i))
            {
                continue;
            }
            self.grid.shift(i, x0[k], x[k]);
            self.nodes[i].position = x[k];
            for &nb in &self.adjacency[i] {
                let length = x[k].distance(self.nodes[nb].position);
                self.max_edge = self.max_edge.max(length);
            }
        }
        Ok(())
    }

    /// Whether a node at `from` may not reach `to`: the way crosses a boundary curve, or `to` lies within r_short of
    /// one.
    fn off_limits(&self, from: DVec2, to: DVec2) -> bool {
        self.boundaries.crosses(from, to) || self.boundaries.near(to, self.r_short)
    }

    /// Puts back every moved node whose move, or one of whose edges, would cross a boundary curve, or which would
    /// come within r_short of one.
    fn keep_off_boundaries(
        &self,
        movers: &[usize],
        x0: &[DVec2],
        x: &mut [DVec2],
        local: &FastMap<usize, usize>,
    ) {
        let at = |x: &[DVec2], n: usize| local.get(&n).map_or(self.nodes[n].position, |&k| x[k]);
        loop {
            let mut reverted = false;
            for (k, &i) in movers.iter().enumerate() {
                if x[k] == x0[k] {
                    continue;
                }
                let crossing = self.off_limits(x0[k], x[k])
                    || self.adjacency[i]
                        .iter()
                        .any(|&nb| self.boundaries.crosses(x[k], at(x, nb)));
                if crossing {
                    x[k] = x0[k];
                    reverted = true;
                }
            }
            if !reverted {
                return;
            }
        }
    }

    fn remove(&mut self, s: usize) {
        self.nodes[s].state = State::Dead;
        for n in std::mem::take(&mut self.adjacency[s]) {
            self.adjacency[n].retain(|&x| x != s);
        }
    }

    /// Replaces seed `s` by the matched reference element and grows its ring (Fig. 2 d–h, Fig. 6). A reopened
    /// existing element keeps its place and is not counted as placed.
    fn place(&mut self, s: usize, m: Match) {
        let ring = &self.rings[m.ring];
        let (sub_id, n) = (ring.sub_id, ring.offsets.len());
        let rot = DVec2::from_angle(m.theta);
        let offsets: Vec<DVec2> = ring.offsets.iter().map(|&o| rot.rotate(o)).collect();
        let symbols = ring.symbols.clone();
        let rotation = self.reference.elements()[sub_id].rotation + m.theta;
        self.nodes[s].state = State::Element { sub_id, rotation };
        self.nodes[s].symbol = Some(self.reference.elements()[sub_id].symbol);
        if s >= self.existing {
            self.placed.push(s);
        }
        let p = self.nodes[s].position;

        let mut assigned: Vec<Option<usize>> = vec![None; n];
        for (&t, &slot) in m.targets.iter().zip(&m.slots) {
            assigned[slot] = Some(t);
            self.targets[s].push((t, offsets[slot]));
        }
        let first_free = m.slots.last().map_or(0, |&k| k + 1);
        for step in 0..n {
            let j = (first_free + step) % n;
            if assigned[j].is_some() {
                continue;
            }
            let c = p + offsets[j];
            if !self.region.contains(c) || self.off_limits(p, c) {
                self.cut[s] = true;
                continue;
            }
            // (b) an element or seed already within r_short takes the slot
            if let Some(found) = self.nearest_within(c, self.r_short, s) {
                let fp = self.nodes[found].position;
                if self.boundaries.crosses(p, fp) {
                    self.cut[s] = true;
                } else if self.adjacency[s].contains(&found)
                    || !self.collides(s, Some(found), p, fp)
                {
                    self.connect(s, found);
                    assigned[j] = Some(found);
                    self.targets[s].push((found, offsets[j]));
                }
                continue;
            }
            // (b') a slot too near another node for the reference's spacing stays empty
            if self.any_within(c, CROWDED * 2.0 * self.r_short, Some(s)) {
                continue;
            }
            // (c) the angle to the nearest edges on either side (a lattice's sites are a spacing apart already: an
            // edge along a cell's diagonal, which the ring copied may not have, would leave a site empty)
            if self.lattice.is_none() && self.too_narrow(s, offsets[j], &offsets, j) {
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
            if self.boundaries.crosses(pa, pb) {
                continue;
            }
            if pa.distance(pb) > 1.5 * original {
                self.extra_seed(s, a, b, rot);
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
    /// On a lattice, the seed goes to the lattice site nearest that point (`rot`: the match's turn).
    fn extra_seed(&mut self, s: usize, a: usize, b: usize, rot: DVec2) {
        let p = self.nodes[s].position;
        let (da, db) = (self.nodes[a].position - p, self.nodes[b].position - p);
        let half = 0.5 * da.angle_to(db).rem_euclid(std::f64::consts::TAU);
        let length = 0.5 * (da.length() + db.length());
        let mut x = p + DVec2::from_angle(half).rotate(da.normalize_or_zero()) * length;
        if let Some(lattice) = &self.lattice {
            let back = DVec2::new(rot.x, -rot.y);
            x = p + rot.rotate(lattice.vector_near(back.rotate(x - p)));
        }
        if !self.region.contains(x) || self.off_limits(p, x) {
            self.cut[s] = true;
            return;
        }
        if self.any_within(x, self.r_short, None) || self.collides(s, None, p, x) {
            return;
        }
        let seed = self.add_seed(x, None);
        self.connect(s, seed);
        for end in [a, b] {
            let pe = self.nodes[end].position;
            if !self.boundaries.crosses(x, pe) && !self.collides(seed, Some(end), x, pe) {
                self.connect(seed, end);
            }
        }
    }
}

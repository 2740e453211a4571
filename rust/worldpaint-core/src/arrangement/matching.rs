//! Finding the best matching element (seed §5.2–5.3): for a seed e^tar and its current (partial) ring, every
//! non-boundary reference element e^ref whose ring is at least as large is compared by eq. (2)–(3).
//!
//! The seed's matching patterns F pair the rings "without skipping and flipping": both rings counter-clockwise, the
//! target's first neighbour paired in turn with each reference neighbour. Readings where the seed is vague:
//! - the target ring starts after its widest angular gap ("we start with the element which is on the boundary");
//! - `subid(e_i^tar, e_j^ref)` is 1 when the target neighbour is a copy of the very reference element it is paired
//!   with, so that the same reference patch does not repeat itself; seeds (not yet elements) have no sub-id, and a
//!   seed with no symbol id matches any symbol (`id` = 0);
//! - eq. (4) is solved as shape matching [MHTG05], i.e. the least-squares rotation θ = atan2(Σ r×q, Σ r·q) of the
//!   paired offsets, and the pattern's error is then eq. (2) at that θ; in the flow-field mode θ is the flow's
//!   angle at the seed ("we then rotate the whole reference pattern so as to adjust its local x coordinate to the
//!   orientation"); a seed with no neighbour takes a reference element drawn with the run's seeded generator.
//!
//! **On a lattice** (a near-regular reference, see `super::lattice`), in the non-rotation and best-fit modes:
//! - where growth fronts meet, a seed's neighbours are not one run of its ring: one is missing between two that are
//!   there, and no pattern without skipping pairs them with the right offsets. Each target neighbour is then paired
//!   with the reference offset nearest to it (turned by θ), which skips the missing one and never flips, since the
//!   offsets are a lattice's, a spacing apart;
//! - θ is one of the turns that map the lattice onto itself (0 in the non-rotation mode, else the one of least
//!   error), since any other turn starts a grain of another orientation;
//! - a match is *on the lattice* when every pair lies within a quarter of the lattice's shortest vector, and only
//!   those are compared by eq. (2): the sub-id term (w3 = 100) would otherwise prefer a ring put a whole spacing off
//!   to one that repeats a neighbour's reference element. For the same reason the matches with the fewest paired
//!   neighbours of another symbol are compared first (a checkerboard keeps its alternation). When no candidate is on
//!   the lattice, the seed's patterns are searched as without one.

use glam::DVec2;
use rand::Rng;

use super::growth::{Grower, RefRing, State};
use super::lattice::OFF_SITE;
use super::options::RotationMode;

/// A seed matched to a reference element: its ring, its turn, and the ring slot of each of the seed's neighbours.
pub(super) struct Match {
    pub(super) ring: usize,
    pub(super) theta: f64,
    /// The seed's neighbours, counter-clockwise.
    pub(super) targets: Vec<usize>,
    /// The reference ring's slot each of `targets` is paired with, increasing counter-clockwise.
    pub(super) slots: Vec<usize>,
}

impl Match {
    /// The reference element matched.
    pub(super) fn sub_id(&self, grower: &Grower) -> usize {
        grower.rings[self.ring].sub_id
    }

    /// The size of the reference element's ring.
    pub(super) fn ring_len(&self, grower: &Grower) -> usize {
        grower.rings[self.ring].offsets.len()
    }
}

/// A candidate match: the reference ring, its turn and the pairs (index among the seed's neighbours, ring slot).
struct Candidate {
    ring: usize,
    theta: f64,
    pairs: Vec<(usize, usize)>,
}

impl Grower<'_> {
    /// The node's live neighbours, counter-clockwise, starting after the widest angular gap.
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

    /// The best-matching reference element for node `s` and its current ring (eq. (1)–(4)); a node with no
    /// neighbour takes a reference element drawn with the run's generator when `draw`, else the first that fits.
    pub(super) fn best_match(&mut self, s: usize, draw: bool) -> Option<Match> {
        let symbol = self.nodes[s].symbol;
        let targets = self.target_ring(s);
        let m = targets.len();
        // on a lattice whose cells' diagonals fall either way, a neighbour along one need not be in the ring
        let either = |t: &usize| {
            self.lattice.is_some_and(|l| {
                l.is_either_diagonal(self.nodes[*t].position - self.nodes[s].position)
            })
        };
        let required = m - targets.iter().filter(|t| either(t)).count();
        let candidates: Vec<usize> = (0..self.rings.len())
            .filter(|&r| symbol.is_none_or(|sym| self.rings[r].symbol == sym))
            .filter(|&r| self.rings[r].offsets.len() >= required)
            .collect();
        if candidates.is_empty() {
            return None;
        }
        let p = self.nodes[s].position;
        let flow_theta = match (&self.options.flow, self.options.rotation) {
            (Some(flow), RotationMode::Flow) => flow.angle_at(p),
            _ => 0.0,
        };
        if m == 0 {
            let ring = if draw {
                candidates[self.rng.random_range(0..candidates.len())]
            } else {
                candidates[0]
            };
            return Some(Match {
                ring,
                theta: flow_theta,
                targets,
                slots: Vec::new(),
            });
        }
        let q: Vec<DVec2> = targets
            .iter()
            .map(|&t| self.nodes[t].position - p)
            .collect();
        let on_lattice = match self.options.rotation {
            RotationMode::None | RotationMode::BestFit => {
                self.lattice_match(&candidates, &targets, &q)
            }
            RotationMode::Flow => None,
        };
        let found = on_lattice.or_else(|| {
            let candidates: Vec<usize> = candidates
                .into_iter()
                .filter(|&r| self.rings[r].offsets.len() >= m)
                .collect();
            self.pattern_match(&candidates, &targets, &q, flow_theta)
        })?;
        let (targets, slots) = found
            .pairs
            .iter()
            .map(|&(i, slot)| (targets[i], slot))
            .unzip();
        Some(Match {
            ring: found.ring,
            theta: found.theta,
            targets,
            slots,
        })
    }

    /// The seed's search: every candidate ring with every matching pattern (a shift, no skipping), turned by the
    /// mode's θ.
    fn pattern_match(
        &self,
        candidates: &[usize],
        targets: &[usize],
        q: &[DVec2],
        flow_theta: f64,
    ) -> Option<Candidate> {
        let fixed_theta = if self.options.rotation == RotationMode::Flow {
            flow_theta
        } else {
            0.0
        };
        let fixed_rot = DVec2::from_angle(fixed_theta);
        let mut pairs: Vec<(usize, usize)> = Vec::with_capacity(q.len());
        let mut best: Option<(f64, Candidate)> = None;
        for &r in candidates {
            let ring = &self.rings[r];
            let n = ring.offsets.len();
            for shift in 0..n {
                pairs.clear();
                pairs.extend((0..targets.len()).map(|i| (i, (shift + i) % n)));
                let (theta, rot) = match self.options.rotation {
                    RotationMode::None | RotationMode::Flow => (fixed_theta, fixed_rot),
                    RotationMode::BestFit => {
                        let (mut cross, mut dot) = (0.0, 0.0);
                        for &(i, slot) in &pairs {
                            cross += ring.offsets[slot].perp_dot(q[i]);
                            dot += ring.offsets[slot].dot(q[i]);
                        }
                        let theta = cross.atan2(dot);
                        let theta = self.lattice.map_or(theta, |l| l.nearest_symmetry(theta));
                        (theta, DVec2::from_angle(theta))
                    }
                };
                let error = self.error(ring, targets, q, rot, &pairs);
                if best.as_ref().is_none_or(|b| error < b.0) {
                    let pairs = pairs.clone();
                    best = Some((
                        error,
                        Candidate {
                            ring: r,
                            theta,
                            pairs,
                        },
                    ));
                }
            }
        }
        best.map(|b| b.1)
    }

    /// On a lattice: every candidate ring turned by each of the lattice's symmetry turns the mode allows, each
    /// target neighbour paired with the nearest offset (a neighbour along a cell diagonal that falls either way left
    /// unpaired when the ring does not have it); the least error among the matches on the lattice, with the pairs
    /// (target index, slot).
    fn lattice_match(
        &self,
        candidates: &[usize],
        targets: &[usize],
        q: &[DVec2],
    ) -> Option<Candidate> {
        let lattice = self.lattice?;
        let tolerance2 = (OFF_SITE * lattice.basis[0].length()).powi(2);
        let turns: Vec<(f64, DVec2)> = match self.options.rotation {
            RotationMode::BestFit => lattice.symmetries(),
            _ => vec![0.0],
        }
        .into_iter()
        .map(|theta| (theta, DVec2::from_angle(theta)))
        .collect();
        let either: Vec<bool> = q.iter().map(|&qi| lattice.is_either_diagonal(qi)).collect();
        let mut pairs: Vec<(usize, usize)> = Vec::with_capacity(q.len());
        let mut best: Option<((usize, f64), Candidate)> = None;
        for &r in candidates {
            let ring = &self.rings[r];
            'turns: for &(theta, rot) in &turns {
                pairs.clear();
                for (i, qi) in q.iter().enumerate() {
                    let (mut slot, mut nearest) = (0, f64::INFINITY);
                    for (k, &o) in ring.offsets.iter().enumerate() {
                        let d2 = qi.distance_squared(rot.rotate(o));
                        if d2 < nearest {
                            (slot, nearest) = (k, d2);
                        }
                    }
                    if nearest <= tolerance2 && pairs.iter().all(|p| p.1 != slot) {
                        pairs.push((i, slot));
                    } else if !either[i] {
                        continue 'turns;
                    }
                }
                if !counter_clockwise(&pairs) {
                    continue;
                }
                // a pattern of symbols on a lattice (a checkerboard) keeps them before it avoids repeats
                let mismatches = pairs
                    .iter()
                    .filter(|&&(i, slot)| {
                        self.nodes[targets[i]]
                            .symbol
                            .is_some_and(|sym| sym != ring.symbols[slot])
                    })
                    .count();
                let key = (mismatches, self.error(ring, targets, q, rot, &pairs));
                if best
                    .as_ref()
                    .is_none_or(|b| key.0 < b.0 .0 || (key.0 == b.0 .0 && key.1 < b.0 .1))
                {
                    let pairs = pairs.clone();
                    best = Some((
                        key,
                        Candidate {
                            ring: r,
                            theta,
                            pairs,
                        },
                    ));
                }
            }
        }
        best.map(|b| b.1)
    }

    /// Eq. (2) for one pairing of the seed's neighbours (`targets`, at offsets `q`) with `ring`'s slots, turned by
    /// `rot`: `pairs` of (index among the neighbours, slot).
    fn error(
        &self,
        ring: &RefRing,
        targets: &[usize],
        q: &[DVec2],
        rot: DVec2,
        pairs: &[(usize, usize)],
    ) -> f64 {
        let w = self.options.weights;
        let mut error = 0.0;
        for &(i, slot) in pairs {
            error += w.distance * q[i].distance(rot.rotate(ring.offsets[slot]));
            let node = &self.nodes[targets[i]];
            if node.symbol.is_some_and(|sym| sym != ring.symbols[slot]) {
                error += w.symbol;
            }
            if let State::Element { sub_id, .. } = node.state {
                if sub_id == ring.sub_ids[slot] {
                    error += w.sub_id;
                }
            }
        }
        error
    }
}

/// Whether the pairs' ring slots, read from the first, go once round counter-clockwise (no flipping): at most one
/// descent, and none unless the last slot comes before the first.
fn counter_clockwise(pairs: &[(usize, usize)]) -> bool {
    let descents = pairs.windows(2).filter(|w| w[1].1 < w[0].1).count();
    match (pairs.first(), pairs.last()) {
        (Some(first), Some(last)) => descents == 0 || (descents == 1 && last.1 < first.1),
        _ => true,
    }
}

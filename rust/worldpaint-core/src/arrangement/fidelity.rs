//! How well a painted pattern keeps its reference, as a user checks it: whether each element has the neighbours its
//! reference element has, where it has them, and whether the pattern is as dense. A pair-correlation function says
//! little of an arrangement (a lattice's is a comb of peaks), so an arrangement color is judged by these instead.
//!
//! An element's *ring* is the offsets and symbols of the elements within [`RING_RADIUS`] spacings of it (the spacing:
//! the mean distance to the reference's first shell of neighbours; on hexagonal, square and brick lattices this
//! radius lies between the first and the second shell, 0.16 spacings or more from either). A ring *matches* a reference
//! element's when the centres' symbols agree and both rings hold as many neighbours, each of the same symbol within
//! [`RING_TOLERANCE`] spacings of one of the other's, one to one. Interior elements are those whose ring disc lies
//! inside the region (for the reference, inside its convex hull). The reference's own score pairs each of its
//! interior rings with the others' (a hand's noise can make two of its own rings differ).
//!
//! The reference's density is read from its triangulation: a triangulation of many points has about two triangles a
//! point, so its kept triangles' count over twice their area (exact on a lattice, whose triangles are half a cell).

use glam::DVec2;

use super::{Element, ReferenceArrangement};
use crate::geom::{PreparedRegion, Region, RegionQueries};
use crate::spatial::{GridEntry, SpatialGrid};

/// An element's ring reaches this many spacings.
pub const RING_RADIUS: f64 = 1.25;
/// Two rings' neighbours pair within this many spacings.
pub(super) const RING_TOLERANCE: f64 = 0.15;

/// A painted pattern's figures against its reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatternFidelity {
    /// The share of the pattern's interior elements whose ring matches one of the reference's (0–1).
    pub ring_share: f64,
    /// The share of the reference's interior elements whose ring matches another of its own (0–1).
    pub reference_ring_share: f64,
    /// The pattern's interior elements (those the share counts).
    pub interior: usize,
    /// The pattern's elements in the region.
    pub elements: usize,
    /// The pattern's elements per square metre of the region over the reference's (1: as dense).
    pub count_ratio: f64,
}

/// The reference's rings, to match a pattern's against.
pub struct RingMatch {
    spacing: f64,
    rings: Vec<(u32, Vec<(DVec2, u32)>)>,
    own: f64,
}

impl RingMatch {
    /// The rings of `reference`'s interior elements.
    pub fn new(reference: &ReferenceArrangement) -> RingMatch {
        let elements = reference.elements();
        let points: Vec<DVec2> = elements.iter().map(|e| e.position).collect();
        let spacing = first_shell_spacing(reference);
        let interior = interior_of_hull(&points, RING_RADIUS * spacing);
        let index = Neighbours::new(elements, RING_RADIUS * spacing);
        let rings: Vec<(u32, Vec<(DVec2, u32)>)> = interior
            .iter()
            .map(|&i| (elements[i].symbol, index.ring(elements, i)))
            .collect();
        let mut matcher = RingMatch {
            spacing,
            rings,
            own: 0.0,
        };
        let kept = interior
            .iter()
            .enumerate()
            .filter(|&(k, &i)| {
                matcher.matches(&index.ring(elements, i), elements[i].symbol, Some(k))
            })
            .count();
        matcher.own = kept as f64 / interior.len().max(1) as f64;
        matcher
    }

    /// The reference's spacing: the mean distance to its first shell of neighbours (m).
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// The share of the reference's interior elements whose ring matches another of its own.
    pub fn reference_share(&self) -> f64 {
        self.own
    }

    /// Whether each of `elements` has a ring that matches one of the reference's.
    pub fn matching(&self, elements: &[Element]) -> Vec<bool> {
        let index = Neighbours::new(elements, RING_RADIUS * self.spacing);
        (0..elements.len())
            .map(|i| self.matches(&index.ring(elements, i), elements[i].symbol, None))
            .collect()
    }

    /// Whether `ring` around an element of `symbol` matches one of the reference's interior rings (other than the
    /// one numbered `except`).
    fn matches(&self, ring: &[(DVec2, u32)], symbol: u32, except: Option<usize>) -> bool {
        let tolerance = RING_TOLERANCE * self.spacing;
        self.rings.iter().enumerate().any(|(k, (s, reference))| {
            Some(k) != except
                && *s == symbol
                && reference.len() == ring.len()
                && rings_pair(ring, reference, tolerance)
        })
    }
}

/// The elements' neighbours within a radius, by a grid of that radius.
struct Neighbours {
    grid: SpatialGrid,
    radius: f64,
}

impl Neighbours {
    fn new(elements: &[Element], radius: f64) -> Neighbours {
        let (lo, hi) = elements
            .iter()
            .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), e| {
                (lo.min(e.position), hi.max(e.position))
            });
        let mut grid = SpatialGrid::new(lo, hi.max(lo), radius.max(f64::MIN_POSITIVE));
        for (i, e) in elements.iter().enumerate() {
            grid.insert(GridEntry {
                position: e.position,
                tag: e.symbol,
                id: i as u32,
            });
        }
        Neighbours { grid, radius }
    }

    /// Element `i`'s ring: the offsets and symbols of the others within the radius.
    fn ring(&self, elements: &[Element], i: usize) -> Vec<(DVec2, u32)> {
        let p = elements[i].position;
        let mut ring = Vec::new();
        self.grid.for_each_within(p, self.radius, |e, _| {
            if e.id as usize != i {
                ring.push((e.position - p, e.tag));
            }
        });
        ring
    }
}

/// The figures of the pattern `elements` (its elements in `region`) against `reference`.
pub fn pattern_fidelity(
    reference: &ReferenceArrangement,
    elements: &[Element],
    region: &Region,
) -> PatternFidelity {
    let matcher = RingMatch::new(reference);
    let prepared = PreparedRegion::new(region);
    let inside: Vec<Element> = elements
        .iter()
        .copied()
        .filter(|e| prepared.contains(e.position))
        .collect();
    let margin = RING_RADIUS * matcher.spacing;
    let interior: Vec<usize> = (0..inside.len())
        .filter(|&i| {
            prepared.distance_to_boundary_within(inside[i].position, 2.0 * margin) > margin
        })
        .collect();
    let matching = matcher.matching(&inside);
    let kept = interior.iter().filter(|&&i| matching[i]).count();
    let area = region.area();
    let count_ratio = if area > 0.0 {
        inside.len() as f64 / (area * reference_density(reference))
    } else {
        0.0
    };
    PatternFidelity {
        ring_share: kept as f64 / interior.len().max(1) as f64,
        reference_ring_share: matcher.reference_share(),
        interior: interior.len(),
        elements: inside.len(),
        count_ratio,
    }
}

/// Elements per square metre of the reference: its kept triangles' count over twice their area.
pub fn reference_density(reference: &ReferenceArrangement) -> f64 {
    let p = |i: usize| reference.elements()[i].position;
    let area: f64 = reference
        .triangles()
        .iter()
        .map(|t| 0.5 * (p(t[1]) - p(t[0])).perp_dot(p(t[2]) - p(t[0])).abs())
        .sum();
    if area > 0.0 {
        reference.triangles().len() as f64 / (2.0 * area)
    } else {
        0.0
    }
}

/// The reference's spacing: the mean length of its first shell of neighbours, the edges of its connectivity no
/// longer than 1.2 times the median distance from an element to its nearest neighbour (a nearest neighbour is a
/// Delaunay neighbour). The mean nearest distance alone is biased short by the hand's noise (0.91 spacings with 5 %
/// noise), and a ring radius read from it cuts through the first shell.
fn first_shell_spacing(reference: &ReferenceArrangement) -> f64 {
    let elements = reference.elements();
    let edges: Vec<(usize, f64)> = reference
        .edges()
        .into_iter()
        .map(|(i, j)| (i, elements[i].position.distance(elements[j].position)))
        .collect();
    let mut nearest: Vec<f64> = (0..elements.len())
        .filter_map(|i| {
            let p = elements[i].position;
            reference
                .ring(i)
                .iter()
                .map(|&j| elements[j].position.distance(p))
                .min_by(f64::total_cmp)
        })
        .collect();
    nearest.sort_by(f64::total_cmp);
    let Some(&median) = nearest.get(nearest.len() / 2) else {
        return 0.0;
    };
    let shell: Vec<f64> = edges
        .iter()
        .map(|e| e.1)
        .filter(|&d| d <= 1.2 * median)
        .collect();
    shell.iter().sum::<f64>() / shell.len().max(1) as f64
}

/// The points farther than `margin` inside their convex hull.
fn interior_of_hull(points: &[DVec2], margin: f64) -> Vec<usize> {
    let hull = convex_hull(points);
    (0..points.len())
        .filter(|&i| {
            (0..hull.len()).all(|k| {
                crate::geom::segment_distance(points[i], hull[k], hull[(k + 1) % hull.len()])
                    > margin
            })
        })
        .collect()
}

/// Whether every offset of `a` has its own offset of `b`, of the same symbol, within `tolerance` (the offsets of one
/// ring are about a spacing apart, so the nearest is the only candidate).
fn rings_pair(a: &[(DVec2, u32)], b: &[(DVec2, u32)], tolerance: f64) -> bool {
    let mut used = vec![false; b.len()];
    a.iter().all(|(offset, symbol)| {
        let found = (0..b.len())
            .find(|&k| !used[k] && b[k].1 == *symbol && b[k].0.distance(*offset) <= tolerance);
        found.map(|k| used[k] = true).is_some()
    })
}

/// The convex hull, counter-clockwise (Andrew's monotone chain).
fn convex_hull(points: &[DVec2]) -> Vec<DVec2> {
    let mut sorted: Vec<DVec2> = points.to_vec();
    sorted.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let turn = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::new();
    for pass in [sorted.clone(), sorted.into_iter().rev().collect()] {
        let start = hull.len();
        for q in pass {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_lattice(side: usize, jitter: impl Fn(usize) -> DVec2) -> Vec<Element> {
        (0..side * side)
            .map(|k| Element {
                position: DVec2::new((k % side) as f64, (k / side) as f64) + jitter(k),
                symbol: 0,
                rotation: 0.0,
                scale: 1.0,
            })
            .collect()
    }

    #[test]
    fn a_lattice_keeps_its_rings_and_a_sheared_one_does_not() {
        let reference =
            ReferenceArrangement::new(square_lattice(7, |_| DVec2::ZERO)).expect("a reference");
        let region = Region::Rect {
            min: DVec2::splat(-0.5),
            max: DVec2::splat(19.5),
        };
        let exact = pattern_fidelity(&reference, &square_lattice(20, |_| DVec2::ZERO), &region);
        assert_eq!(exact.ring_share, 1.0);
        assert_eq!(exact.reference_ring_share, 1.0);
        assert!(
            (exact.count_ratio - 1.0).abs() < 1e-9,
            "{}",
            exact.count_ratio
        );
        assert_eq!(exact.elements, 400);
        // every other row shifted by a third of a spacing: no ring is the reference's
        let sheared = square_lattice(20, |k| {
            DVec2::new(if (k / 20) % 2 == 1 { 0.33 } else { 0.0 }, 0.0)
        });
        assert_eq!(
            pattern_fidelity(&reference, &sheared, &region).ring_share,
            0.0
        );
        // a seventh of the sites empty: their neighbours' rings lack one
        let holes: Vec<Element> = square_lattice(20, |_| DVec2::ZERO)
            .into_iter()
            .enumerate()
            .filter(|(k, _)| k % 7 != 3)
            .map(|(_, e)| e)
            .collect();
        let f = pattern_fidelity(&reference, &holes, &region);
        assert!(
            f.ring_share < 0.75 && (f.count_ratio - 6.0 / 7.0).abs() < 0.01,
            "{f:?}"
        );
    }
}

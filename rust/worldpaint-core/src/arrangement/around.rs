//! Growing next to elements already in the scene (a paste beside an earlier pattern, the spray tool's dabs, seed
//! §5.1: "we generate an initial seed at the cursor position … and grow all the seeds which are in the
//! user-specified distance from the cursor").
//!
//! Readings chosen:
//! - the existing elements' connectivity is rebuilt as [`ReferenceArrangement::new`] builds a reference's (Delaunay,
//!   triangles with an angle over 2π/3 dropped), also dropping edges longer than 1.5 × the longest edge of the
//!   reference's interior rings (the rings growth copies; the reference's hull can hold a triangle of nearly 2π/3 whose
//!   long side would bridge a missing element at a pattern's frontier), and each existing element takes as sub-id the
//!   reference element that best matches its ring (eq. (1)–(4) as for a seed, with no sub-id term: the existing sub-ids
//!   are not known);
//! - an existing element within the region, or within that longest ring edge of it, whose ring has fewer
//!   neighbours than its matched reference element's is *reopened*: it is queued as a seed at its fixed position
//!   and, when its turn comes, matched again to its current ring, which places seeds for its missing neighbours
//!   (inside the region only). The pattern grows on from the old one without a seam;
//! - existing elements are never moved or removed: they are held by every relaxation, flagged
//!   [`super::Arrangement::at_region_boundary`] in the result so that [`super::relax_arrangement`] holds them too, and
//!   keep their position, symbol, rotation and scale;
//! - an edge from a reopened element outside the region to a new element inside is kept (it necessarily crosses the
//!   region's outline); every new element and seed lies inside the region;
//! - without a reopened element growth starts with one seed at `start`, or at the region's centroid when it lies
//!   inside, else at the middle of the widest stretch inside on the scanline through the centroid (or the nearest
//!   scanline that meets the region); that seed is not made within the reference's shortest edge (2 r_short) of
//!   an existing element, where no element has room (a dab over a full pattern adds nothing), nor any other seed
//!   within r_short of one;
//! - noise is drawn after growth, from the same generator, for the new elements in order (scale first, then
//!   rotation), so that growth is the same with and without it.

use std::collections::HashMap;

use glam::DVec2;
use rand::Rng;

use super::existing::{existing_edges, fallback_sub_id, longest_ring_edge};
use super::fidelity::reference_density;
use super::growth::{Grower, State};
use super::options::GrowthOptions;
use super::{Arrangement, Element, ReferenceArrangement, RingTarget};
use crate::error::{Error, Result};
use crate::geom::{PreparedRegion, Region};

/// Grows a pattern from one seed at `start` inside `region`, copying `reference`'s local structure:
/// [`grow_arrangement_around`] with no existing element.
pub fn grow_arrangement(
    reference: &ReferenceArrangement,
    region: &Region,
    start: DVec2,
    options: &GrowthOptions,
) -> Result<Arrangement> {
    grow_arrangement_around(reference, region, &[], Some(start), options, &|_| true)
}

/// Grows a pattern inside `region` next to the `existing` elements (held fixed, listed first in the result, in their
/// order), continuing them where their rings are incomplete, else from `start` (see the module's readings).
/// `progress` hears the fraction done every few hundred elements; returning false cancels ([`Error::Cancelled`]).
pub fn grow_arrangement_around(
    reference: &ReferenceArrangement,
    region: &Region,
    existing: &[Element],
    start: Option<DVec2>,
    options: &GrowthOptions,
    progress: &dyn Fn(f64) -> bool,
) -> Result<Arrangement> {
    region.validate()?;
    options.validate(reference)?;
    crate::limits::check(
        "existing elements",
        existing.len() as f64,
        crate::limits::MAX_INSTANCES,
        "instances",
    )?;
    for (i, e) in existing.iter().enumerate() {
        if !(e.position.is_finite() && e.rotation.is_finite() && e.scale.is_finite()) {
            return Err(Error::invalid(
                "existing elements",
                format!("element {i} has a non-finite position, rotation or scale"),
            ));
        }
    }
    if let Some(s) = start {
        if !s.is_finite() {
            return Err(Error::invalid(
                "growth start",
                format!("({}, {}) is not a point inside the region", s.x, s.y),
            ));
        }
    }
    // the work budget before the work: a region whose pattern would pass it is refused at once, however far growth
    // is asked to go
    crate::limits::check(
        "the pattern over the region (its area times the reference's density)",
        region_count(reference, region),
        crate::limits::MAX_INSTANCES,
        "instances",
    )?;
    let region = &*region.with_bounded_detail();
    let mut grower = Grower::new(reference, PreparedRegion::new(region), options)?;
    let reopened = add_existing(&mut grower, reference, existing);
    let mut order: Vec<usize> = reopened.keys().copied().collect();
    order.sort_unstable();
    match (order.first(), start) {
        (Some(&first), start) => {
            grower.origin = start.unwrap_or(grower.nodes[first].position);
            for &i in &order {
                grower.nodes[i].state = State::Seed;
                grower.queue(i);
            }
        }
        (None, Some(s)) => {
            if !grower.region_contains(s) {
                return Err(Error::invalid(
                    "growth start",
                    format!("({}, {}) is not a point inside the region", s.x, s.y),
                ));
            }
            grower.origin = s;
            grower.add_initial_seed(s);
        }
        (None, None) => {
            let s = interior_point(region)?;
            grower.origin = s;
            grower.add_initial_seed(s);
        }
    }
    grower.run(
        expected_count(reference, region, options),
        &reopened,
        progress,
    )?;
    Ok(finish(grower, existing, options))
}

/// Adds the existing elements as nodes with their rebuilt connectivity and matched sub-ids; returns the reopened
/// ones with their matched sub-id and rotation.
fn add_existing(
    grower: &mut Grower,
    reference: &ReferenceArrangement,
    existing: &[Element],
) -> HashMap<usize, (usize, f64)> {
    for e in existing {
        grower.add_node(
            e.position,
            Some(e.symbol),
            State::Element {
                sub_id: usize::MAX,
                rotation: e.rotation,
            },
        );
    }
    grower.existing = existing.len();
    let longest = longest_ring_edge(reference);
    for (a, b) in existing_edges(reference, existing, 1.5 * longest) {
        grower.connect(a, b);
    }
    let matches: Vec<Option<(usize, usize, f64)>> = (0..existing.len())
        .map(|i| {
            grower.best_match(i, false).map(|m| {
                let rotation = existing[i].rotation;
                (m.sub_id(grower), m.ring_len(grower), rotation)
            })
        })
        .collect();
    let mut reopened = HashMap::new();
    for (i, found) in matches.into_iter().enumerate() {
        let sub_id = match found {
            Some((sub_id, ring_len, rotation)) => {
                let p = existing[i].position;
                let near_region = grower.region_contains(p)
                    || grower.region_distance_within(p, longest) < longest;
                if grower.adjacency[i].len() < ring_len && near_region {
                    reopened.insert(i, (sub_id, rotation));
                }
                sub_id
            }
            None => fallback_sub_id(reference, existing[i].symbol),
        };
        grower.nodes[i].state = State::Element {
            sub_id,
            rotation: existing[i].rotation,
        };
    }
    reopened
}

/// A point inside the region: its centroid if inside, else the middle of the widest stretch inside on the scanline
/// through the centroid or the nearest one that meets the region.
fn interior_point(region: &Region) -> Result<DVec2> {
    let (lo, hi) = region.bbox();
    let rows = 256;
    let dy = (hi.y - lo.y) / rows as f64;
    let (mut area, mut moment) = (0.0, DVec2::ZERO);
    let mut lines = Vec::with_capacity(rows);
    for j in 0..rows {
        let y = lo.y + (j as f64 + 0.5) * dy;
        let spans = region.scanline(y);
        for &(a, b) in &spans {
            area += b - a;
            moment += DVec2::new(0.5 * (a + b), y) * (b - a);
        }
        lines.push((y, spans));
    }
    if !(area > 0.0) {
        return Err(Error::bad_region("it holds no point to grow from"));
    }
    let centroid = match region {
        Region::Polygon { points } => polygon_centroid(points).unwrap_or(moment / area),
        Region::Rect { .. } | Region::Circle { .. } => 0.5 * (lo + hi),
        Region::Clipped { .. } => moment / area,
    };
    if region.contains(centroid) {
        return Ok(centroid);
    }
    lines
        .iter()
        .filter(|(_, spans)| !spans.is_empty())
        .min_by(|a, b| {
            (a.0 - centroid.y)
                .abs()
                .total_cmp(&(b.0 - centroid.y).abs())
        })
        .and_then(|(y, spans)| {
            spans
                .iter()
                .max_by(|a, b| (a.1 - a.0).total_cmp(&(b.1 - b.0)))
                .map(|&(a, b)| DVec2::new(0.5 * (a + b), *y))
        })
        .ok_or_else(|| Error::bad_region("it holds no point to grow from"))
}

/// The area centroid of a simple polygon (none for a zero signed area).
fn polygon_centroid(points: &[DVec2]) -> Option<DVec2> {
    let (mut twice_area, mut sum) = (0.0, DVec2::ZERO);
    for (k, &a) in points.iter().enumerate() {
        let b = points[(k + 1) % points.len()];
        let cross = a.perp_dot(b);
        twice_area += cross;
        sum += (a + b) * cross;
    }
    (twice_area != 0.0).then(|| sum / (3.0 * twice_area))
}

/// How many elements the region holds at the reference's density (for the progress fraction).
fn expected_count(
    reference: &ReferenceArrangement,
    region: &Region,
    options: &GrowthOptions,
) -> f64 {
    region_count(reference, region)
        .min(options.max_elements as f64)
        .max(1.0)
}

/// The elements `region` holds at the reference's density.
fn region_count(reference: &ReferenceArrangement, region: &Region) -> f64 {
    region.area() * reference_density(reference)
}

/// The arrangement: the existing elements as given, then the new ones in the order they were placed, with noise.
fn finish(mut grower: Grower, existing: &[Element], options: &GrowthOptions) -> Arrangement {
    let nodes = grower.nodes.len();
    let mut index = vec![usize::MAX; nodes];
    let order: Vec<usize> = (0..grower.existing)
        .chain(grower.placed.iter().copied())
        .collect();
    for (k, &node) in order.iter().enumerate() {
        index[node] = k;
    }
    let mut arrangement = Arrangement::default();
    for &node in &order {
        let (sub_id, rotation) = match grower.nodes[node].state {
            State::Element { sub_id, rotation } => (sub_id, rotation),
            _ => (0, 0.0),
        };
        let element = match existing.get(node) {
            Some(e) => *e,
            None => Element {
                position: grower.nodes[node].position,
                symbol: grower.nodes[node].symbol.unwrap_or(0),
                rotation,
                scale: grower
                    .reference
                    .elements()
                    .get(sub_id)
                    .map_or(1.0, |r| r.scale),
            },
        };
        arrangement.elements.push(element);
        arrangement.sub_ids.push(sub_id);
        arrangement
            .at_region_boundary
            .push(node < grower.existing || grower.cut[node]);
        arrangement.ring_targets.push(
            grower.targets[node]
                .iter()
                .filter(|t| index[t.0] != usize::MAX)
                .map(|&(t, offset)| RingTarget {
                    neighbour: index[t],
                    offset,
                })
                .collect(),
        );
        for &nb in &grower.adjacency[node] {
            let (i, j) = (index[node], index[nb]);
            if j != usize::MAX && i < j {
                arrangement.edges.push((i, j));
            }
        }
    }
    arrangement.edges.sort_unstable();
    let noise = options.noise;
    if noise.scale > 0.0 || noise.rotation > 0.0 {
        // log-normal scale factor of mean 1 and relative standard deviation `noise.scale`
        let sigma = (1.0 + noise.scale * noise.scale).ln().sqrt();
        for e in &mut arrangement.elements[grower.existing..] {
            let (z_scale, z_rotation) = (gaussian(&mut grower.rng), gaussian(&mut grower.rng));
            e.scale *= (sigma * z_scale - 0.5 * sigma * sigma).exp();
            e.rotation += noise.rotation * z_rotation;
        }
    }
    arrangement
}

/// A standard normal draw (Box–Muller).
pub(crate) fn gaussian(rng: &mut impl Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

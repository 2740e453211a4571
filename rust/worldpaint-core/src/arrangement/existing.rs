//! The connectivity of elements already in the scene, rebuilt for [`super::grow_arrangement_around`] from their
//! positions alone, as [`ReferenceArrangement::new`] builds a reference's: a Delaunay triangulation without the
//! triangles that have an angle over 2π/3, and without edges longer than 1.5 × the longest edge of the reference's
//! interior rings.
//!
//! Where four elements lie nearly on a circle (a square lattice, bricks), the Delaunay diagonal of their
//! quadrilateral falls either way with the smallest jitter, where the pattern was grown with the diagonal the
//! reference has (seed Fig. 3: its user flips them all one way). So each diagonal shared by two kept triangles is
//! flipped when the other diagonal matches an offset of the reference's rings better (by more than 5 % of the mean
//! edge), the offsets read in the element's frame: its rotation less that of the reference's first interior element
//! of its symbol (the flow or best-fit turn a grown element carries). A reference whose rings hold more than 64
//! distinct offsets (5 % of the mean edge apart) is irregular: its patterns have no ambiguous diagonals, and none is
//! flipped. One pass over the edges, in order.

use glam::DVec2;
use spade::{DelaunayTriangulation, Point2, Triangulation};

use super::cells::FastMap;
use super::connectivity::{largest_angle, segments_cross, MAX_TRIANGLE_ANGLE};
use super::{Element, ReferenceArrangement};

/// The most distinct ring offsets for which diagonals are chosen.
const MAX_OFFSETS: usize = 64;

/// The existing elements' connectivity: Delaunay edges of a triangle with no angle over 2π/3, at most `longest`.
/// An element at the same place as an earlier one gets no edge.
pub(super) fn existing_edges(
    reference: &ReferenceArrangement,
    existing: &[Element],
    longest: f64,
) -> Vec<(usize, usize)> {
    let mut tri: DelaunayTriangulation<Point2<f64>> = DelaunayTriangulation::new();
    let mut owner: Vec<usize> = Vec::with_capacity(existing.len());
    for (i, e) in existing.iter().enumerate() {
        let Ok(handle) = tri.insert(Point2::new(e.position.x, e.position.y)) else {
            continue;
        };
        if handle.index() == owner.len() {
            owner.push(i);
        }
    }
    let mut triangles = Vec::new();
    for face in tri.inner_faces() {
        let v = face.vertices().map(|v| v.fix().index());
        if v.iter().any(|&k| k >= owner.len()) {
            continue;
        }
        let v = v.map(|k| owner[k]);
        if largest_angle(v.map(|i| existing[i].position)) <= MAX_TRIANGLE_ANGLE {
            triangles.push(v);
        }
    }
    choose_diagonals(reference, existing, &mut triangles);
    let mut edges = Vec::new();
    for v in &triangles {
        for k in 0..3 {
            let (a, b) = (v[k].min(v[(k + 1) % 3]), v[k].max(v[(k + 1) % 3]));
            if existing[a].position.distance(existing[b].position) <= longest {
                edges.push((a, b));
            }
        }
    }
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// Flips the diagonals that match the reference's ring offsets worse than the other diagonal (see the module doc).
fn choose_diagonals(
    reference: &ReferenceArrangement,
    existing: &[Element],
    triangles: &mut [[usize; 3]],
) {
    let Some(offsets) = ring_offsets(reference) else {
        return;
    };
    let margin = 0.05 * reference.mean_edge();
    let elements = reference.elements();
    let frame_of = |e: &Element| {
        let base = (0..elements.len())
            .find(|&i| !reference.is_boundary(i) && elements[i].symbol == e.symbol)
            .map_or(0.0, |i| elements[i].rotation);
        DVec2::from_angle(base - e.rotation)
    };
    let frames: Vec<DVec2> = existing.iter().map(frame_of).collect();
    let cost = |x: usize, y: usize| {
        let d = frames[x].rotate(existing[y].position - existing[x].position);
        offsets
            .iter()
            .map(|o| o.distance(d))
            .fold(f64::INFINITY, f64::min)
    };
    let key = |a: usize, b: usize| (a.min(b), a.max(b));
    let mut sharing: FastMap<(usize, usize), Vec<usize>> = FastMap::default();
    for (t, v) in triangles.iter().enumerate() {
        for k in 0..3 {
            sharing
                .entry(key(v[k], v[(k + 1) % 3]))
                .or_default()
                .push(t);
        }
    }
    let mut diagonals: Vec<(usize, usize)> = sharing
        .iter()
        .filter(|(_, ts)| ts.len() == 2)
        .map(|(e, _)| *e)
        .collect();
    diagonals.sort_unstable();
    let p = |i: usize| existing[i].position;
    for (a, b) in diagonals {
        let Some(&[t0, t1]) = sharing.get(&(a, b)).map(Vec::as_slice) else {
            continue;
        };
        let other = |t: [usize; 3]| t.into_iter().find(|&v| v != a && v != b);
        let (Some(c), Some(d)) = (other(triangles[t0]), other(triangles[t1])) else {
            continue;
        };
        let (new0, new1) = ([c, d, a], [d, c, b]);
        let flips = segments_cross(p(a), p(b), p(c), p(d))
            && largest_angle(new0.map(p)) <= MAX_TRIANGLE_ANGLE
            && largest_angle(new1.map(p)) <= MAX_TRIANGLE_ANGLE
            && cost(c, d) + margin < cost(a, b);
        if !flips {
            continue;
        }
        triangles[t0] = new0;
        triangles[t1] = new1;
        sharing.remove(&(a, b));
        sharing.insert(key(c, d), vec![t0, t1]);
        // the sides a–d and b–c change triangle
        for (side, from, to) in [(key(a, d), t1, t0), (key(b, c), t0, t1)] {
            if let Some(ts) = sharing.get_mut(&side) {
                for t in ts.iter_mut().filter(|t| **t == from) {
                    *t = to;
                }
            }
        }
    }
}

/// The distinct offsets of the reference's interior rings (none past [`MAX_OFFSETS`]: an irregular reference).
fn ring_offsets(reference: &ReferenceArrangement) -> Option<Vec<DVec2>> {
    let e = reference.elements();
    let near = 0.05 * reference.mean_edge();
    let mut offsets: Vec<DVec2> = Vec::new();
    for i in (0..e.len()).filter(|&i| !reference.is_boundary(i)) {
        for &j in reference.ring(i) {
            let o = e[j].position - e[i].position;
            if offsets.iter().all(|q| q.distance(o) > near) {
                if offsets.len() == MAX_OFFSETS {
                    return None;
                }
                offsets.push(o);
            }
        }
    }
    Some(offsets)
}

/// The longest edge of the rings growth copies (the reference's interior elements'): the reference's own longest
/// edge can be a hull triangle's, near √3 × the spacing, long enough to bridge a missing element of a lattice.
pub(super) fn longest_ring_edge(reference: &ReferenceArrangement) -> f64 {
    let e = reference.elements();
    (0..e.len())
        .filter(|&i| !reference.is_boundary(i))
        .flat_map(|i| {
            reference
                .ring(i)
                .iter()
                .map(move |&j| e[i].position.distance(e[j].position))
        })
        .fold(0.0, f64::max)
}

/// The sub-id of an existing element no reference ring matches: the first interior reference element of its
/// symbol, else the first interior one.
pub(super) fn fallback_sub_id(reference: &ReferenceArrangement, symbol: u32) -> usize {
    let interior = |i: &usize| !reference.is_boundary(*i);
    let n = reference.elements().len();
    (0..n)
        .filter(interior)
        .find(|&i| reference.elements()[i].symbol == symbol)
        .or_else(|| (0..n).find(interior))
        .unwrap_or(0)
}

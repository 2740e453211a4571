//! Self-intersection labels and rejection (seed §4.3).
//!
//! The seed labels the faces that intersect in the original ("a face can have multiple labels") and rejects an
//! assembled object when two intersecting faces carry different labels. Reading chosen: a label is one intersecting
//! pair of original faces ([`IntersectionLabels`]), so an assembly is kept when every pair of intersecting faces in it
//! copies a pair that intersected in the original, and rejected on the first other pair. Faces are fanned into
//! triangles; two triangles of one polygon, or two that share a vertex (adjacent after welding), are never tested.
//! Two triangles intersect when an edge of one meets the other (touching counts); coplanar triangles when their
//! outlines overlap in the plane.
//!
//! The candidate pairs come from a small bounding-volume hierarchy written here (a median split on the longest axis,
//! four triangles a leaf): a model of a thousand faces needs no more, and a collision crate such as `parry3d-f64`
//! would bring a linear-algebra stack to the engine and minutes to its build on the shared machines for one query.
//! An assembly is checked in parts (`between_parts`): the faces inside one placed variant keep
//! their relative places in every assembly (the variant moves as a solid), so each node variant is checked alone
//! once per atlas, and an assembly only tests pairs of faces from two placed variants whose boxes overlap — the
//! triangles of each inside the other's box, by brute force when few and through the hierarchy otherwise. The query
//! is sequential inside one model, and models are checked in parallel ([`super::generate`]), so a result never
//! depends on the thread count. (Welding moves a region vertex by at most the 1e-6 m tolerance, which a variant
//! checked alone does not see; only a contact exactly at that distance could be judged differently.)

use super::model::Model;
use crate::error::{check, Result};
use glam::DVec3;
use std::collections::HashSet;

/// The pairs of original faces that intersect in the original model: the intersections an assembly may keep.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IntersectionLabels {
    pairs: HashSet<(u32, u32)>,
}

impl IntersectionLabels {
    /// Labels the intersecting face pairs of `model` (the original). A face corner that names no vertex leaves its
    /// triangles out (validate the model first to be told).
    pub fn of_model(model: &Model) -> IntersectionLabels {
        IntersectionLabels {
            pairs: intersecting_faces(model, |_, _| false, usize::MAX)
                .into_iter()
                .collect(),
        }
    }

    /// The labelled pairs (lower face first), sorted.
    pub fn pairs(&self) -> Vec<(u32, u32)> {
        let mut p: Vec<_> = self.pairs.iter().copied().collect();
        p.sort_unstable();
        p
    }

    /// Whether original faces `a` and `b` intersected in the original.
    pub fn allows(&self, a: u32, b: u32) -> bool {
        self.pairs.contains(&(a.min(b), a.max(b)))
    }
}

/// The first intersecting pair of faces of an assembled model that is not an original intersection, given each
/// face's original face (`None` for a new face): `None` when the assembly is clean.
pub fn new_intersection(
    model: &Model,
    face_origin: &[Option<u32>],
    labels: &IntersectionLabels,
) -> Result<Option<(u32, u32)>> {
    model.validate()?;
    check::same_len("face origins", face_origin.len(), model.faces.len())?;
    let allowed = |a: u32, b: u32| match (
        face_origin.get(a as usize).copied().flatten(),
        face_origin.get(b as usize).copied().flatten(),
    ) {
        (Some(oa), Some(ob)) => labels.allows(oa, ob),
        _ => false,
    };
    Ok(intersecting_faces(model, allowed, 1).into_iter().next())
}

/// The model's triangles with their faces, corners and boxes.
struct Soup {
    tris: Vec<(u32, [u32; 3])>,
    corners: Vec<[DVec3; 3]>,
    boxes: Vec<(DVec3, DVec3)>,
}

impl Soup {
    fn of(model: &Model) -> Soup {
        let n = model.vertices.len();
        let mut tris = model.triangles();
        tris.retain(|(_, t)| t.iter().all(|&v| (v as usize) < n));
        let corners: Vec<[DVec3; 3]> = tris
            .iter()
            .map(|(_, t)| t.map(|v| model.vertices[v as usize]))
            .collect();
        let boxes = corners
            .iter()
            .map(|c| {
                let (lo, hi) = bounds(c);
                let pad = (hi - lo).max_element() * 1e-9 + 1e-12;
                (lo - pad, hi + pad)
            })
            .collect();
        Soup {
            tris,
            corners,
            boxes,
        }
    }

    /// The faces of triangles `i` and `j` (lower first) when they are a candidate pair: different faces, no shared
    /// vertex, not `allowed`.
    fn candidate(
        &self,
        i: usize,
        j: usize,
        allowed: &impl Fn(u32, u32) -> bool,
    ) -> Option<(u32, u32)> {
        let ((fi, ti), (fj, tj)) = (&self.tris[i], &self.tris[j]);
        if fi == fj || ti.iter().any(|v| tj.contains(v)) {
            return None;
        }
        let pair = ((*fi).min(*fj), (*fi).max(*fj));
        (!allowed(pair.0, pair.1)).then_some(pair)
    }
}

fn overlaps(a: &(DVec3, DVec3), b: &(DVec3, DVec3)) -> bool {
    !(a.0.cmpgt(b.1).any() || a.1.cmplt(b.0).any())
}

/// Pairs of faces (lower first) with intersecting non-adjacent triangles, skipping those `allowed` says may
/// intersect, stopping after `limit` pairs.
pub(crate) fn intersecting_faces(
    model: &Model,
    allowed: impl Fn(u32, u32) -> bool,
    limit: usize,
) -> Vec<(u32, u32)> {
    let soup = Soup::of(model);
    let bvh = Bvh::build(&soup.boxes, (0..soup.tris.len() as u32).collect());
    let mut found: Vec<(u32, u32)> = Vec::new();
    let mut seen: HashSet<(u32, u32)> = HashSet::new();
    for i in 0..soup.tris.len() {
        let stopped = bvh.query(&soup.boxes, &soup.boxes[i], |j| {
            let j = j as usize;
            if j <= i {
                return false;
            }
            let Some(pair) = soup.candidate(i, j, &allowed) else {
                return false;
            };
            if seen.contains(&pair) || !triangles_intersect(&soup.corners[i], &soup.corners[j]) {
                return false;
            }
            seen.insert(pair);
            found.push(pair);
            found.len() >= limit
        });
        if stopped {
            return found;
        }
    }
    found.sort_unstable();
    found
}

/// The first intersecting pair of faces (lower first) that lie in different parts (`face_part`, one per face,
/// numbered densely from 0) and are not an original intersection by `face_origin`, on a valid model: the check of
/// an assembly whose parts were each checked alone. Each part gets its own hierarchy; only parts whose boxes overlap
/// are queried, the smaller against the larger.
pub(crate) fn between_parts(
    model: &Model,
    face_origin: &[Option<u32>],
    face_part: &[u32],
    labels: &IntersectionLabels,
) -> Option<(u32, u32)> {
    let allowed = |a: u32, b: u32| match (
        face_origin.get(a as usize).copied().flatten(),
        face_origin.get(b as usize).copied().flatten(),
    ) {
        (Some(oa), Some(ob)) => labels.allows(oa, ob),
        _ => false,
    };
    let soup = Soup::of(model);
    let parts = face_part
        .iter()
        .copied()
        .max()
        .map_or(0, |m| m as usize + 1);
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); parts];
    for (t, (f, _)) in soup.tris.iter().enumerate() {
        if let Some(&p) = face_part.get(*f as usize) {
            members[p as usize].push(t as u32);
        }
    }
    let part_box = |ids: &[u32]| {
        ids.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &t| {
                (
                    lo.min(soup.boxes[t as usize].0),
                    hi.max(soup.boxes[t as usize].1),
                )
            },
        )
    };
    let boxes: Vec<(DVec3, DVec3)> = members.iter().map(|m| part_box(m)).collect();
    let mut pairs: Vec<(usize, usize)> = Vec::new();
    for a in 0..parts {
        for b in a + 1..parts {
            if !members[a].is_empty() && !members[b].is_empty() && overlaps(&boxes[a], &boxes[b]) {
                pairs.push((a, b));
            }
        }
    }
    for (a, b) in pairs {
        // The triangles of each part inside the other's box: few where two parts only meet at a region.
        let near = |p: usize, q: usize| -> Vec<u32> {
            members[p]
                .iter()
                .copied()
                .filter(|&t| overlaps(&soup.boxes[t as usize], &boxes[q]))
                .collect()
        };
        let (na, nb) = (near(a, b), near(b, a));
        let (small, big) = if na.len() <= nb.len() {
            (na, nb)
        } else {
            (nb, na)
        };
        let mut hit = None;
        let mut test = |i: usize, j: usize| match soup.candidate(i, j, &allowed) {
            Some(pair) if triangles_intersect(&soup.corners[i], &soup.corners[j]) => {
                hit = Some(pair);
                true
            }
            _ => false,
        };
        if small.len() * big.len() <= BRUTE_FORCE_PAIRS {
            for &i in &small {
                for &j in &big {
                    if overlaps(&soup.boxes[i as usize], &soup.boxes[j as usize])
                        && test(i as usize, j as usize)
                    {
                        return hit;
                    }
                }
            }
        } else {
            let tree = Bvh::build(&soup.boxes, big);
            for &i in &small {
                if tree.query(&soup.boxes, &soup.boxes[i as usize], |j| {
                    test(i as usize, j as usize)
                }) {
                    return hit;
                }
            }
        }
    }
    None
}

/// Above this many box tests between the near triangles of two parts, a hierarchy is built.
const BRUTE_FORCE_PAIRS: usize = 20_000;

fn bounds(t: &[DVec3; 3]) -> (DVec3, DVec3) {
    (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]))
}

/// A node of the hierarchy: a box and either two children (`count == 0`, at `first` and `first + 1`) or `count`
/// triangles from `order[first..]`.
struct Node {
    lo: DVec3,
    hi: DVec3,
    first: usize,
    count: usize,
}

/// A bounding-volume hierarchy over triangles.
struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl Bvh {
    /// The hierarchy over triangles `order` (indices into `boxes`).
    fn build(boxes: &[(DVec3, DVec3)], mut order: Vec<u32>) -> Bvh {
        let n = order.len();
        let centres: Vec<DVec3> = boxes.iter().map(|(a, b)| (*a + *b) * 0.5).collect();
        let centre = |t: u32| centres[t as usize];
        let mut nodes = vec![Node {
            lo: DVec3::ZERO,
            hi: DVec3::ZERO,
            first: 0,
            count: n,
        }];
        let mut work = vec![(0usize, 0usize, n)];
        while let Some((node, start, end)) = work.pop() {
            let slice = &mut order[start..end];
            let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
            let (mut clo, mut chi) = (lo, hi);
            for &t in slice.iter() {
                let (a, b) = boxes[t as usize];
                lo = lo.min(a);
                hi = hi.max(b);
                clo = clo.min(centre(t));
                chi = chi.max(centre(t));
            }
            nodes[node].lo = lo;
            nodes[node].hi = hi;
            if end - start <= 4 {
                nodes[node].first = start;
                nodes[node].count = end - start;
                continue;
            }
            let extent = chi - clo;
            let axis = if extent.x >= extent.y && extent.x >= extent.z {
                0
            } else if extent.y >= extent.z {
                1
            } else {
                2
            };
            let mid = slice.len() / 2;
            slice.select_nth_unstable_by(mid, |&a, &b| {
                centre(a)[axis].total_cmp(&centre(b)[axis]).then(a.cmp(&b))
            });
            let left = nodes.len();
            for _ in 0..2 {
                nodes.push(Node {
                    lo: DVec3::ZERO,
                    hi: DVec3::ZERO,
                    first: 0,
                    count: 0,
                });
            }
            nodes[node].first = left;
            nodes[node].count = 0;
            work.push((left, start, start + mid));
            work.push((left + 1, start + mid, end));
        }
        Bvh { nodes, order }
    }

    /// Calls `visit` on every triangle whose leaf box meets `target`, until it returns true; returns whether it did.
    fn query(
        &self,
        boxes: &[(DVec3, DVec3)],
        target: &(DVec3, DVec3),
        mut visit: impl FnMut(u32) -> bool,
    ) -> bool {
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let Some(node) = self.nodes.get(n) else {
                continue;
            };
            if self.order.is_empty() || !overlaps(&(node.lo, node.hi), target) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.first + 1);
                stack.push(node.first);
                continue;
            }
            for &t in &self.order[node.first..node.first + node.count] {
                if overlaps(&boxes[t as usize], target) && visit(t) {
                    return true;
                }
            }
        }
        false
    }
}

/// Whether two triangles share a point.
pub(crate) fn triangles_intersect(a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    let scale = bounds(a).1.max(bounds(b).1) - bounds(a).0.min(bounds(b).0);
    let eps = scale.max_element().max(1e-300) * 1e-10;
    let na = (a[1] - a[0]).cross(a[2] - a[0]);
    let nb = (b[1] - b[0]).cross(b[2] - b[0]);
    if na.length() <= eps * eps || nb.length() <= eps * eps {
        return false;
    }
    let (na, nb) = (na.normalize(), nb.normalize());
    let coplanar = b.iter().all(|p| (*p - a[0]).dot(na).abs() <= eps);
    if coplanar {
        return coplanar_overlap(a, b, na, eps);
    }
    (0..3).any(|k| segment_hits(a[k], a[(k + 1) % 3], b, nb, eps))
        || (0..3).any(|k| segment_hits(b[k], b[(k + 1) % 3], a, na, eps))
}

/// Whether segment p–q meets triangle `t` (unit normal `n`), not lying in its plane.
fn segment_hits(p: DVec3, q: DVec3, t: &[DVec3; 3], n: DVec3, eps: f64) -> bool {
    let dp = (p - t[0]).dot(n);
    let dq = (q - t[0]).dot(n);
    if (dp > eps && dq > eps) || (dp < -eps && dq < -eps) {
        return false;
    }
    if dp.abs() <= eps && dq.abs() <= eps {
        return false; // in the plane: the coplanar case is the other triangle's edges' business
    }
    let x = p + (q - p) * (dp / (dp - dq));
    inside(x, t, n, eps)
}

/// Whether point `x` in the plane of `t` lies inside it (boundary included).
fn inside(x: DVec3, t: &[DVec3; 3], n: DVec3, eps: f64) -> bool {
    (0..3).all(|k| {
        let e = t[(k + 1) % 3] - t[k];
        e.cross(x - t[k]).dot(n) >= -eps * e.length()
    })
}

/// Overlap of two coplanar triangles: an edge crossing or a corner inside the other.
fn coplanar_overlap(a: &[DVec3; 3], b: &[DVec3; 3], n: DVec3, eps: f64) -> bool {
    if a.iter().any(|&p| inside(p, b, n, eps)) || b.iter().any(|&p| inside(p, a, n, eps)) {
        return true;
    }
    for i in 0..3 {
        for j in 0..3 {
            let (p, q) = (a[i], a[(i + 1) % 3]);
            let (r, s) = (b[j], b[(j + 1) % 3]);
            let d1 = (q - p).cross(r - p).dot(n);
            let d2 = (q - p).cross(s - p).dot(n);
            let d3 = (s - r).cross(p - r).dot(n);
            let d4 = (s - r).cross(q - r).dot(n);
            if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
                return true;
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_triangles_intersect_and_apart_ones_do_not() {
        let a = [DVec3::ZERO, DVec3::X * 2.0, DVec3::Y * 2.0];
        let b = [
            DVec3::new(0.5, 0.5, -1.0),
            DVec3::new(0.5, 0.5, 1.0),
            DVec3::new(0.6, 3.0, 0.0),
        ];
        assert!(triangles_intersect(&a, &b));
        let c = b.map(|p| p + DVec3::X * 5.0);
        assert!(!triangles_intersect(&a, &c));
        let d = [
            DVec3::new(0.2, 0.2, 0.0),
            DVec3::new(0.4, 0.2, 0.0),
            DVec3::new(0.2, 0.4, 0.0),
        ];
        assert!(triangles_intersect(&a, &d), "coplanar, inside");
    }

    #[test]
    fn a_model_finds_its_crossing_faces_and_allows_the_labelled_ones() {
        let v = vec![
            DVec3::ZERO,
            DVec3::X * 2.0,
            DVec3::Y * 2.0,
            DVec3::new(0.5, 0.5, -1.0),
            DVec3::new(0.5, 0.5, 1.0),
            DVec3::new(0.6, 3.0, 0.0),
            DVec3::new(9.0, 0.0, 0.0),
            DVec3::new(9.0, 1.0, 0.0),
            DVec3::new(9.0, 0.0, 1.0),
        ];
        let m = Model::new(v, vec![vec![0, 1, 2], vec![3, 4, 5], vec![6, 7, 8]]).unwrap();
        let labels = IntersectionLabels::of_model(&m);
        assert_eq!(labels.pairs(), vec![(0, 1)]);
        let origin = vec![Some(0), Some(1), Some(2)];
        assert_eq!(new_intersection(&m, &origin, &labels).unwrap(), None);
        let origin = vec![Some(0), None, Some(2)];
        assert_eq!(
            new_intersection(&m, &origin, &labels).unwrap(),
            Some((0, 1))
        );
    }
}

//! Polygon meshes of the house volumes: the builder that welds vertices and drops degenerate faces, convex
//! polygon helpers (offset, half-plane clipping) and the closed solids: storey prisms, the foundation, the roof and
//! the stair blocks. Every solid is closed and wound counter-clockwise seen from outside.

use crate::geom::polygon_signed_area;
use crate::village::encyclopedia::RoofStyle;
use crate::village::{HouseMaterial, HouseMesh};
use glam::{DVec2, DVec3};
use std::collections::HashMap;

/// Positions closer than this (m) share a vertex, so faces computed separately (two roof planes meeting at the
/// ridge) close up.
const WELD: f64 = 1e-6;
/// A face of a smaller area (m²) is degenerate and left out.
const MIN_AREA: f64 = 1e-8;

/// Twice the vector area of a polygon (Newell): its direction is the normal seen counter-clockwise.
pub(super) fn newell(points: &[DVec3]) -> DVec3 {
    let Some(&first) = points.first() else {
        return DVec3::ZERO;
    };
    let mut n = DVec3::ZERO;
    for i in 1..points.len().saturating_sub(1) {
        n += (points[i] - first).cross(points[i + 1] - first);
    }
    n
}

/// Faces over welded vertices, one material each.
#[derive(Default)]
pub(super) struct MeshBuilder {
    vertices: Vec<[f64; 3]>,
    lookup: HashMap<[i64; 3], u32>,
    faces: Vec<Vec<u32>>,
    materials: Vec<HouseMaterial>,
}

impl MeshBuilder {
    fn vertex(&mut self, p: DVec3) -> u32 {
        let key = [
            (p.x / WELD).round() as i64,
            (p.y / WELD).round() as i64,
            (p.z / WELD).round() as i64,
        ];
        if let Some(&i) = self.lookup.get(&key) {
            return i;
        }
        let i = self.vertices.len() as u32;
        self.vertices.push([p.x, p.y, p.z]);
        self.lookup.insert(key, i);
        i
    }

    /// Adds the polygon `points` (counter-clockwise seen from the side it faces). Repeated consecutive points
    /// are merged; a polygon left with no area is dropped.
    pub(super) fn face(&mut self, points: &[DVec3], material: HouseMaterial) {
        if points.len() < 3 || points.iter().any(|p| !p.is_finite()) {
            return;
        }
        let mut idx: Vec<u32> = Vec::with_capacity(points.len());
        for &p in points {
            let i = self.vertex(p);
            if idx.last() != Some(&i) {
                idx.push(i);
            }
        }
        while idx.len() > 1 && idx.first() == idx.last() {
            idx.pop();
        }
        if idx.len() < 3 {
            return;
        }
        let welded: Vec<DVec3> = idx
            .iter()
            .map(|&i| DVec3::from_array(self.vertices[i as usize]))
            .collect();
        if newell(&welded).length() * 0.5 < MIN_AREA {
            return;
        }
        self.faces.push(idx);
        self.materials.push(material);
    }

    /// A closed prism over the counter-clockwise polygon `poly`, from `z0` up to `z1`.
    pub(super) fn prism(&mut self, poly: &[DVec2], z0: f64, z1: f64, material: HouseMaterial) {
        let bottom: Vec<DVec3> = poly.iter().rev().map(|p| p.extend(z0)).collect();
        let top: Vec<DVec3> = poly.iter().map(|p| p.extend(z1)).collect();
        self.face(&bottom, material);
        self.face(&top, material);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            self.face(
                &[a.extend(z0), b.extend(z0), b.extend(z1), a.extend(z1)],
                material,
            );
        }
    }

    pub(super) fn finish(self, seed: usize) -> HouseMesh {
        HouseMesh {
            seed,
            vertices: self.vertices,
            faces: self.faces,
            materials: self.materials,
        }
    }
}

/// The convex counter-clockwise polygon `poly` with each edge moved `d` outward (inward when negative).
pub(super) fn offset(poly: &[DVec2], d: f64) -> Vec<DVec2> {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let prev = poly[(i + n - 1) % n];
            let (p, next) = (poly[i], poly[(i + 1) % n]);
            let n1 = outward(next - p);
            let n0 = outward(p - prev);
            // The miter point lies on both moved edge lines; convex corners keep 1 + n0·n1 well above zero.
            let s = 1.0 + n0.dot(n1);
            if s > 1e-6 {
                p + (n0 + n1) * (d / s)
            } else {
                p + n1 * d
            }
        })
        .collect()
}

/// Unit outward normal of an edge of a counter-clockwise polygon (its right side).
pub(super) fn outward(edge: DVec2) -> DVec2 {
    DVec2::new(edge.y, -edge.x).normalize_or_zero()
}

/// The part of the convex polygon `poly` where the affine function `f` is at most zero.
fn clip(poly: &[DVec2], f: impl Fn(DVec2) -> f64) -> Vec<DVec2> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let (fa, fb) = (f(a), f(b));
        if fa <= 0.0 {
            out.push(a);
        }
        if (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0) {
            out.push(a + (b - a) * (fa / (fa - fb)));
        }
    }
    out
}

/// What the roof is made of, drawn per house.
#[derive(Clone, Copy, Debug)]
pub(super) struct RoofParams {
    pub style: RoofStyle,
    /// Slope of the roof planes (rise over run).
    pub pitch: f64,
    /// Horizontal overhang beyond the walls (m).
    pub overhang: f64,
    /// Vertical thickness of the roof slab (m).
    pub thickness: f64,
}

/// Flat roofs: deck above the top of the walls and parapet crest (m), parapet thickness (m).
const FLAT_DECK: f64 = 0.25;
const FLAT_CREST: f64 = 0.7;
const PARAPET: f64 = 0.25;

/// The roof over the counter-clockwise footprint `f` whose walls end at `z_top`.
pub(super) fn roof(b: &mut MeshBuilder, f: &[DVec2; 4], z_top: f64, p: &RoofParams) {
    match p.style {
        RoofStyle::Flat => flat_roof(b, f, z_top, p),
        RoofStyle::Gable => pitched_roof(b, f, z_top, p, true),
        RoofStyle::Hip => pitched_roof(b, f, z_top, p, false),
    }
}

/// A slab with a parapet ring around a sunken deck; a plain slab when the footprint is too narrow for the ring.
fn flat_roof(b: &mut MeshBuilder, f: &[DVec2; 4], z_top: f64, p: &RoofParams) {
    let o = offset(f, p.overhang);
    let inner = offset(&o, -PARAPET);
    let ring_fits = polygon_signed_area(&inner) > 0.05
        && (0..4).all(|k| (inner[(k + 1) % 4] - inner[k]).dot(o[(k + 1) % 4] - o[k]) > 0.0);
    if !ring_fits {
        b.prism(&o, z_top, z_top + FLAT_DECK, HouseMaterial::Roof);
        return;
    }
    let (deck, crest) = (z_top + FLAT_DECK, z_top + FLAT_CREST);
    let bottom: Vec<DVec3> = o.iter().rev().map(|q| q.extend(z_top)).collect();
    b.face(&bottom, HouseMaterial::Roof);
    let top: Vec<DVec3> = inner.iter().map(|q| q.extend(deck)).collect();
    b.face(&top, HouseMaterial::Roof);
    for k in 0..4 {
        let (o0, o1) = (o[k], o[(k + 1) % 4]);
        let (i0, i1) = (inner[k], inner[(k + 1) % 4]);
        b.face(
            &[
                o0.extend(z_top),
                o1.extend(z_top),
                o1.extend(crest),
                o0.extend(crest),
            ],
            HouseMaterial::Roof,
        );
        b.face(
            &[
                o0.extend(crest),
                o1.extend(crest),
                i1.extend(crest),
                i0.extend(crest),
            ],
            HouseMaterial::Roof,
        );
        // The inner face of the parapet looks at the deck, towards the middle.
        b.face(
            &[
                i1.extend(deck),
                i0.extend(deck),
                i0.extend(crest),
                i1.extend(crest),
            ],
            HouseMaterial::Roof,
        );
    }
}

/// Gable and hip roofs as the height field `z_top + pitch · min_i d_i(p)`, `d_i` the distance inside the wall
/// line `i`, over the eave walls only (gable: the two longer opposite walls) or over all four (hip: the straight
/// skeleton roof of a convex footprint). Every roof plane is then planar whatever the quad, the eaves lie exactly
/// on the wall tops, and the same field extended beyond the walls gives the overhang.
fn pitched_roof(b: &mut MeshBuilder, f: &[DVec2; 4], z_top: f64, p: &RoofParams, gable: bool) {
    let lines: Vec<(DVec2, DVec2)> = (0..4)
        .map(|i| (f[i], (f[(i + 1) % 4] - f[i]).normalize_or_zero()))
        .collect();
    let active: Vec<usize> = if gable {
        let len = |i: usize| (f[(i + 1) % 4] - f[i]).length();
        // The ridge runs along the longer sides: they carry the eaves.
        if len(0) + len(2) >= len(1) + len(3) {
            vec![0, 2]
        } else {
            vec![1, 3]
        }
    } else {
        vec![0, 1, 2, 3]
    };
    let dist = |i: usize, q: DVec2| lines[i].1.perp_dot(q - lines[i].0);
    let height = |q: DVec2| {
        let d = active
            .iter()
            .map(|&i| dist(i, q))
            .fold(f64::INFINITY, f64::min);
        z_top + p.pitch * d
    };
    let regions = |poly: &[DVec2]| -> Vec<Vec<DVec2>> {
        active
            .iter()
            .map(|&i| {
                active
                    .iter()
                    .filter(|&&j| j != i)
                    .fold(poly.to_vec(), |r, &j| clip(&r, |q| dist(i, q) - dist(j, q)))
            })
            .filter(|r| r.len() >= 3)
            .collect()
    };
    let up = DVec3::Z * p.thickness;

    let o = offset(f, p.overhang);
    let slab = regions(&o);
    for r in &slab {
        let lower: Vec<DVec3> = r.iter().rev().map(|&q| q.extend(height(q))).collect();
        let upper: Vec<DVec3> = r.iter().map(|&q| q.extend(height(q)) + up).collect();
        b.face(&lower, HouseMaterial::Roof);
        b.face(&upper, HouseMaterial::Roof);
    }
    for k in 0..4 {
        let chain = boundary_chain(o[k], o[(k + 1) % 4], &slab);
        let mut side: Vec<DVec3> = chain.iter().map(|&q| q.extend(height(q))).collect();
        side.extend(chain.iter().rev().map(|&q| q.extend(height(q)) + up));
        b.face(&side, HouseMaterial::Roof);
    }

    if gable {
        // The attic: gable walls in the plane of the end walls, closed by the roof planes over the footprint.
        let under = regions(f);
        let bottom: Vec<DVec3> = f.iter().rev().map(|q| q.extend(z_top)).collect();
        b.face(&bottom, HouseMaterial::Wall);
        for r in &under {
            let top: Vec<DVec3> = r.iter().map(|&q| q.extend(height(q))).collect();
            b.face(&top, HouseMaterial::Roof);
        }
        for k in 0..4 {
            let chain = boundary_chain(f[k], f[(k + 1) % 4], &under);
            let mut side = vec![f[k].extend(z_top), f[(k + 1) % 4].extend(z_top)];
            side.extend(chain.iter().rev().map(|&q| q.extend(height(q))));
            b.face(&side, HouseMaterial::Wall);
        }
    }
}

/// The points of segment `a..b` where the region polygons have a corner, in order from `a` to `b`, ends included.
fn boundary_chain(a: DVec2, b: DVec2, regions: &[Vec<DVec2>]) -> Vec<DVec2> {
    let ab = b - a;
    let len2 = ab.length_squared();
    let mut inner: Vec<(f64, DVec2)> = Vec::new();
    if len2 > 0.0 {
        for q in regions.iter().flatten() {
            let t = (*q - a).dot(ab) / len2;
            let off = (*q - a).perp_dot(ab).abs() / len2.sqrt();
            if off < WELD && t > 1e-9 && t < 1.0 - 1e-9 {
                inner.push((t, *q));
            }
        }
    }
    inner.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut chain = vec![a];
    for (_, q) in inner {
        if chain.last().is_none_or(|l| l.distance(q) > WELD) {
            chain.push(q);
        }
    }
    chain.push(b);
    chain
}

/// A stair block: the convex quad `corners` from `z0` up to its tread at `z1`.
pub(super) fn block(b: &mut MeshBuilder, corners: &[DVec2; 4], z0: f64, z1: f64) {
    b.prism(corners, z0, z1, HouseMaterial::Foundation);
}

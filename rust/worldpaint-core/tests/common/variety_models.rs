//! Models made by code for the variety tests and benchmark: a low-poly tree (trunk in two pieces, three branches
//! with foliage clusters, a crown) decomposed into 6 components with 3 variants each, a fully cyclic rock of four
//! pieces, and a column whose middle piece has identical ends.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::TAU;
use worldpaint_core::{Atlas, DVec2, Decomposition, Model, VariantClass};

pub use glam::DVec3;

/// What a vertex of the tree is, so that edits can pick vertices as a modeller would.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Role {
    /// On ring `r` of the trunk (z = r metres).
    Trunk(usize),
    /// On ring `k` (1 to 4, 4 the tip) of a branch tube.
    Tube(usize),
    /// A corner of leaf `id` (an octahedron).
    Leaf(usize),
}

/// The tree and what the edits need to know about it.
pub struct Tree {
    pub model: Model,
    /// Component label per face: 0 lower trunk, 1 upper trunk, 2–4 branches, 5 crown.
    pub labels: Vec<u32>,
    pub roles: Vec<Role>,
    /// The leaf each face belongs to.
    pub face_leaf: Vec<Option<usize>>,
}

const SIDES: usize = 8;
const RINGS: usize = 9;

fn radial(p: DVec3, factor: f64) -> DVec3 {
    DVec3::new(p.x * factor, p.y * factor, p.z)
}

struct Builder {
    v: Vec<DVec3>,
    f: Vec<Vec<u32>>,
    labels: Vec<u32>,
    roles: Vec<Role>,
    face_leaf: Vec<Option<usize>>,
    leaves: usize,
}

impl Builder {
    fn vertex(&mut self, p: DVec3, role: Role) -> u32 {
        self.v.push(p);
        self.roles.push(role);
        (self.v.len() - 1) as u32
    }
    fn face(&mut self, f: Vec<u32>, label: u32, leaf: Option<usize>) {
        self.f.push(f);
        self.labels.push(label);
        self.face_leaf.push(leaf);
    }
    fn leaf(&mut self, c: DVec3, r: f64, label: u32) {
        let id = self.leaves;
        self.leaves += 1;
        let d = [
            DVec3::X,
            DVec3::Y,
            -DVec3::X,
            -DVec3::Y,
            DVec3::Z,
            -DVec3::Z,
        ];
        let i: Vec<u32> = d
            .iter()
            .map(|&a| self.vertex(c + a * r, Role::Leaf(id)))
            .collect();
        let (top, bottom) = (i[4], i[5]);
        for k in 0..4 {
            let (a, b) = (i[k], i[(k + 1) % 4]);
            self.face(vec![a, b, top], label, Some(id));
            self.face(vec![b, a, bottom], label, Some(id));
        }
    }
    fn cluster(&mut self, centre: DVec3, spread: f64, n: usize, label: u32, rng: &mut ChaCha8Rng) {
        for _ in 0..n {
            let offset = loop {
                let p = DVec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                if p.length() <= 1.0 {
                    break p;
                }
            };
            self.leaf(centre + offset * spread, 0.28, label);
        }
    }
    /// A four-sided branch tube out of the hole `[a, b, c, d]`, its tip capped, and a foliage cluster.
    fn branch(&mut self, hole: [u32; 4], label: u32, leaves: usize, rng: &mut ChaCha8Rng) {
        let base: Vec<DVec3> = hole.iter().map(|&i| self.v[i as usize]).collect();
        let centre = base.iter().copied().sum::<DVec3>() / 4.0;
        let out = DVec3::new(centre.x, centre.y, 0.0).normalize();
        let dir = (out + DVec3::Z * 0.6).normalize();
        let length = 1.8;
        let mut prev = hole;
        for k in 1..=4 {
            let shrink = 1.0 - 0.15 * k as f64;
            let ring: Vec<u32> = base
                .iter()
                .map(|&p| {
                    let q = centre + dir * length * k as f64 / 4.0 + (p - centre) * shrink;
                    self.vertex(q, Role::Tube(k))
                })
                .collect();
            for e in 0..4 {
                let (p, q) = (prev[e], prev[(e + 1) % 4]);
                self.face(vec![p, q, ring[(e + 1) % 4], ring[e]], label, None);
            }
            prev = [ring[0], ring[1], ring[2], ring[3]];
        }
        self.face(prev.to_vec(), label, None);
        let tip = centre + dir * length;
        self.cluster(tip + dir * 1.03, 0.7, leaves, label, rng);
    }
}

/// The tree: 8-sided trunk of 9 rings (z = 0 … 8 m), holes for three branches, a crown cap with foliage; with
/// `leaves` octahedral leaves per branch and twice that on the crown: 114 + 40 × `leaves` faces (714 for 15).
pub fn tree(leaves: usize) -> Tree {
    let mut b = Builder {
        v: Vec::new(),
        f: Vec::new(),
        labels: Vec::new(),
        roles: Vec::new(),
        face_leaf: Vec::new(),
        leaves: 0,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(20);
    let ring = |r: usize, s: usize| (r * SIDES + s % SIDES) as u32;
    for r in 0..RINGS {
        let radius = 0.35 - 0.02 * r as f64;
        for s in 0..SIDES {
            let a = TAU * s as f64 / SIDES as f64;
            b.vertex(
                DVec3::new(radius * a.cos(), radius * a.sin(), r as f64),
                Role::Trunk(r),
            );
        }
    }
    let holes = [(1usize, 0usize, 2u32), (2, 4, 3), (6, 2, 4)];
    for seg in 0..RINGS - 1 {
        let label = if seg < 4 { 0 } else { 1 };
        for s in 0..SIDES {
            let quad = [
                ring(seg, s),
                ring(seg, s + 1),
                ring(seg + 1, s + 1),
                ring(seg + 1, s),
            ];
            if holes.iter().any(|h| h.0 == seg && h.1 == s) {
                continue;
            }
            b.face(quad.to_vec(), label, None);
        }
    }
    b.face((0..SIDES).rev().map(|s| ring(0, s)).collect(), 0, None);
    for &(seg, s, label) in &holes {
        let hole = [
            ring(seg, s),
            ring(seg, s + 1),
            ring(seg + 1, s + 1),
            ring(seg + 1, s),
        ];
        b.branch(hole, label, leaves, &mut rng);
    }
    b.face((0..SIDES).map(|s| ring(RINGS - 1, s)).collect(), 5, None);
    b.cluster(DVec3::new(0.0, 0.0, 9.3), 0.8, 2 * leaves, 5, &mut rng);
    let uvs: Vec<Vec<DVec2>> =
        b.f.iter()
            .map(|face| {
                face.iter()
                    .map(|&i| {
                        let p = b.v[i as usize];
                        DVec2::new(p.x.atan2(p.y) / TAU + 0.5, p.z / 10.0)
                    })
                    .collect()
            })
            .collect();
    let materials: Vec<u32> = b.face_leaf.iter().map(|l| l.is_some() as u32).collect();
    let model = Model::new(b.v, b.f)
        .and_then(|m| m.with_uvs(uvs))
        .and_then(|m| m.with_materials(materials));
    let model = match model {
        Ok(m) => m,
        Err(e) => panic!("the test tree: {e}"),
    };
    Tree {
        model,
        labels: b.labels,
        roles: b.roles,
        face_leaf: b.face_leaf,
    }
}

/// An edit of component `c`'s sub-mesh: `move_vertex(role, position)` gives each vertex's new place, `keep_face`
/// says which faces stay (by the leaf they belong to).
pub fn edit(
    tree: &Tree,
    d: &Decomposition,
    c: usize,
    move_vertex: impl Fn(Role, DVec3) -> DVec3,
    keep_face: impl Fn(Option<usize>) -> bool,
) -> Model {
    let mut m = match d.component_model(&tree.model, c) {
        Ok(m) => m,
        Err(e) => panic!("component {c}: {e}"),
    };
    let comp = &d.components[c];
    for (k, &v) in comp.vertices.iter().enumerate() {
        m.vertices[k] = move_vertex(tree.roles[v as usize], m.vertices[k]);
    }
    let keep: Vec<bool> = comp
        .faces
        .iter()
        .map(|&f| keep_face(tree.face_leaf[f as usize]))
        .collect();
    let mut k = keep.iter();
    m.faces.retain(|_| *k.next().unwrap_or(&true));
    if let Some(uvs) = m.uvs.as_mut() {
        let mut k = keep.iter();
        uvs.retain(|_| *k.next().unwrap_or(&true));
    }
    if let Some(mats) = m.materials.as_mut() {
        let mut k = keep.iter();
        mats.retain(|_| *k.next().unwrap_or(&true));
    }
    m
}

/// The tree's decomposition (root: the lower trunk) and its atlas of 3 variants per component: the original and
/// two edits each — local edits of the trunk, a solid bend of the upper trunk (its branch and crown regions rotate
/// 12° about a horizontal axis at z = 5 m), branch tips thinned with their foliage raised, foliage deleted, the
/// crown's foliage raised.
pub fn tree_atlas(tree: &Tree) -> (Decomposition, Atlas, Vec<Vec<VariantClass>>) {
    let d = match Decomposition::from_labels(&tree.model, &tree.labels, Some(0)) {
        Ok(d) => d,
        Err(e) => panic!("decomposing the tree: {e}"),
    };
    let mut atlas = match Atlas::new(&tree.model, d.clone()) {
        Ok(a) => a,
        Err(e) => panic!("the tree's atlas: {e}"),
    };
    let in_region = |c: usize, p: DVec3| {
        d.arcs(c).iter().any(|&r| {
            d.regions[r]
                .vertices
                .iter()
                .any(|&v| tree.model.vertices[v as usize].distance(p) < 1e-12)
        })
    };
    let bend = glam::DAffine3::from_translation(DVec3::Z * 5.0)
        * glam::DAffine3::from_rotation_x(12f64.to_radians())
        * glam::DAffine3::from_translation(-DVec3::Z * 5.0);
    let all = |_: Option<usize>| true;
    let mut edits: Vec<(usize, Model)> = vec![
        (
            0,
            edit(
                tree,
                &d,
                0,
                |r, p| {
                    if r == Role::Trunk(0) {
                        radial(p, 1.4)
                    } else {
                        p
                    }
                },
                all,
            ),
        ),
        (
            0,
            edit(
                tree,
                &d,
                0,
                |r, p| {
                    if r == Role::Trunk(2) && !in_region(0, p) {
                        radial(p, 1.2)
                    } else {
                        p
                    }
                },
                all,
            ),
        ),
        (
            1,
            edit(
                tree,
                &d,
                1,
                |r, p| match r {
                    Role::Trunk(k) if k >= 6 => bend.transform_point3(p),
                    _ => p,
                },
                all,
            ),
        ),
        (
            1,
            edit(
                tree,
                &d,
                1,
                |r, p| {
                    if r == Role::Trunk(5) {
                        radial(p, 1.25)
                    } else {
                        p
                    }
                },
                all,
            ),
        ),
    ];
    for c in 2..=4 {
        let comp = &d.components[c];
        let tip: Vec<DVec3> = comp
            .vertices
            .iter()
            .filter(|&&v| tree.roles[v as usize] == Role::Tube(4))
            .map(|&v| tree.model.vertices[v as usize])
            .collect();
        let centre = tip.iter().copied().sum::<DVec3>() / tip.len().max(1) as f64;
        edits.push((
            c,
            edit(
                tree,
                &d,
                c,
                |r, p| match r {
                    Role::Tube(4) => centre + (p - centre) * 0.6,
                    Role::Leaf(_) => p + DVec3::Z * 0.15,
                    _ => p,
                },
                all,
            ),
        ));
        edits.push((
            c,
            edit(
                tree,
                &d,
                c,
                |_, p| p,
                |leaf| leaf.is_none_or(|l| l % 2 == 1),
            ),
        ));
    }
    edits.push((
        5,
        edit(
            tree,
            &d,
            5,
            |_, p| p,
            |leaf| leaf.is_none_or(|l| l % 2 == 0),
        ),
    ));
    edits.push((
        5,
        edit(
            tree,
            &d,
            5,
            |r, p| {
                if matches!(r, Role::Leaf(_)) {
                    p + DVec3::Z * 0.3
                } else {
                    p
                }
            },
            all,
        ),
    ));
    let mut classes = vec![vec![VariantClass::Local]; 6];
    for (c, m) in edits {
        match atlas.add_variant(c, m) {
            Ok(class) => classes[c].push(class),
            Err(e) => panic!("a variant of component {c}: {e}"),
        }
    }
    (d, atlas, classes)
}

/// A rock: a sphere of 16 meridians and 7 parallels, cut along four meridians into four pieces; each piece touches
/// the next along a meridian and all meet at the poles, so the graph is fully cyclic (seed Fig. 11).
pub fn rock() -> (Model, Vec<u32>) {
    let (m, p) = (16usize, 7usize);
    let mut v = vec![DVec3::new(0.0, 0.0, -1.0)];
    for i in 0..p {
        let lat =
            -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * (i + 1) as f64 / (p + 1) as f64;
        for j in 0..m {
            let lon = TAU * j as f64 / m as f64;
            let r = 1.0 + 0.08 * ((3 * j + 5 * i) % 7) as f64 / 7.0;
            v.push(DVec3::new(
                r * lat.cos() * lon.cos(),
                r * lat.cos() * lon.sin(),
                r * lat.sin(),
            ));
        }
    }
    v.push(DVec3::new(0.0, 0.0, 1.0));
    let at = |i: usize, j: usize| (1 + i * m + j % m) as u32;
    let north = (1 + p * m) as u32;
    let mut faces = Vec::new();
    let mut labels = Vec::new();
    for j in 0..m {
        let piece = (j / 4) as u32;
        faces.push(vec![0, at(0, j + 1), at(0, j)]);
        labels.push(piece);
        for i in 0..p - 1 {
            faces.push(vec![at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)]);
            labels.push(piece);
        }
        faces.push(vec![at(p - 1, j), at(p - 1, j + 1), north]);
        labels.push(piece);
    }
    match Model::new(v, faces) {
        Ok(model) => (model, labels),
        Err(e) => panic!("the test rock: {e}"),
    }
}

/// A square column of three pieces: a base (with its bottom), a middle piece whose two ends are the same square
/// one metre apart, a top (with its lid). Labels 0, 1, 2.
pub fn column() -> (Model, Vec<u32>) {
    let heights = [0.0, 1.0, 1.5, 2.0, 3.0];
    let mut v = Vec::new();
    for &z in &heights {
        for s in 0..4 {
            let a = TAU * s as f64 / 4.0 + 0.3;
            v.push(DVec3::new(0.5 * a.cos(), 0.5 * a.sin(), z));
        }
    }
    let at = |r: usize, s: usize| (r * 4 + s % 4) as u32;
    let mut faces = vec![vec![at(0, 3), at(0, 2), at(0, 1), at(0, 0)]];
    let mut labels = vec![0];
    for (seg, label) in [(0, 0), (1, 1), (2, 1), (3, 2)] {
        for s in 0..4 {
            faces.push(vec![
                at(seg, s),
                at(seg, s + 1),
                at(seg + 1, s + 1),
                at(seg + 1, s),
            ]);
            labels.push(label);
        }
    }
    faces.push(vec![at(4, 0), at(4, 1), at(4, 2), at(4, 3)]);
    labels.push(2);
    match Model::new(v, faces) {
        Ok(model) => (model, labels),
        Err(e) => panic!("the test column: {e}"),
    }
}

/// A ring of four parts (seed Fig. 11's fully cyclic graph, as a torus): 16 sections of 6 vertices around a circle of
/// radius 2 m (tube radius 0.5 m), parts of four segments each (labels 0–3); each part meets the next in one section.
/// Returns the model, the labels and, per vertex, (section, corner).
pub fn ring() -> (Model, Vec<u32>, Vec<(usize, usize)>) {
    let (sections, corners) = (16usize, 6usize);
    let mut v = Vec::new();
    let mut place = Vec::new();
    for i in 0..sections {
        let a = TAU * i as f64 / sections as f64;
        let (out, z) = (DVec3::new(a.cos(), a.sin(), 0.0), DVec3::Z);
        for j in 0..corners {
            let b = TAU * j as f64 / corners as f64;
            v.push(out * (2.0 + 0.5 * b.cos()) + z * 0.5 * b.sin());
            place.push((i, j));
        }
    }
    let at = |i: usize, j: usize| ((i % sections) * corners + j % corners) as u32;
    let mut faces = Vec::new();
    let mut labels = Vec::new();
    for i in 0..sections {
        for j in 0..corners {
            faces.push(vec![at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
            labels.push((i / 4) as u32);
        }
    }
    match Model::new(v, faces) {
        Ok(model) => (model, labels, place),
        Err(e) => panic!("the test ring: {e}"),
    }
}

/// Where a vertex of the cactus is, so that edits can pick vertices as a modeller would.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CactusPart {
    /// On ring `r` (z = 0.8 r m) of the trunk, or its apex (ring 9).
    Trunk(usize),
    /// On ring `k` of arm `a` (0 or 1): 1–2 out from the hole in the trunk, 3 the elbow, 4–6 up (4 where the tip
    /// part starts).
    Arm(usize, usize),
}

/// The cactus and what the edits need to know about it.
pub struct Cactus {
    pub model: Model,
    /// Part per face: 0 lower trunk (root), 1 middle trunk, 2 top with its dome, 3 arm A, 4 arm A's tip, 5 arm B,
    /// 6 arm B's tip.
    pub labels: Vec<u32>,
    pub parts: Vec<CactusPart>,
}

/// A low-poly cactus of seven parts as a tree: an 8-sided trunk of 9 rings 0.8 m apart (lower, middle and top
/// parts, a dome on top), two arms out of quad holes in the lower and middle trunk, each going out then up through
/// an elbow, its upper rings a part of their own (the tip).
pub fn cactus() -> Cactus {
    let sides = 8usize;
    let mut v: Vec<DVec3> = Vec::new();
    let mut parts = Vec::new();
    for r in 0..9 {
        for s in 0..sides {
            let a = TAU * (s as f64 + 0.5) / sides as f64;
            v.push(DVec3::new(0.5 * a.cos(), 0.5 * a.sin(), 0.8 * r as f64));
            parts.push(CactusPart::Trunk(r));
        }
    }
    v.push(DVec3::new(0.0, 0.0, 7.0));
    parts.push(CactusPart::Trunk(9));
    let apex = (v.len() - 1) as u32;
    let at = |r: usize, s: usize| (r * sides + s % sides) as u32;
    let trunk_label = |seg: usize| match seg {
        0..=2 => 0,
        3..=5 => 1,
        _ => 2,
    };
    let holes = [(1usize, 0usize, 3u32), (4, 4, 5)];
    let mut faces = Vec::new();
    let mut labels = Vec::new();
    for seg in 0..8 {
        for s in 0..sides {
            if holes.iter().any(|h| h.0 == seg && h.1 == s) {
                continue;
            }
            faces.push(vec![
                at(seg, s),
                at(seg, s + 1),
                at(seg + 1, s + 1),
                at(seg + 1, s),
            ]);
            labels.push(trunk_label(seg));
        }
    }
    faces.push((0..sides).rev().map(|s| at(0, s)).collect());
    labels.push(0);
    for s in 0..sides {
        faces.push(vec![at(8, s), at(8, s + 1), apex]);
        labels.push(2);
    }
    for (a, &(seg, s, label)) in holes.iter().enumerate() {
        let hole = [
            at(seg, s),
            at(seg, s + 1),
            at(seg + 1, s + 1),
            at(seg + 1, s),
        ];
        let corners: Vec<DVec3> = hole.iter().map(|&i| v[i as usize]).collect();
        let centre = corners.iter().copied().sum::<DVec3>() / 4.0;
        let out = DVec3::new(centre.x, centre.y, 0.0).normalize();
        // each corner as (across, up) in the hole's plane, carried along the arm's frames
        let across = DVec3::Z.cross(out);
        let offsets: Vec<(f64, f64)> = corners
            .iter()
            .map(|&p| ((p - centre).dot(across), (p - centre).dot(DVec3::Z)))
            .collect();
        let mut previous = hole;
        for k in 1..=6 {
            let (c, up, shrink) = match k {
                1 | 2 => (centre + out * 0.45 * k as f64, DVec3::Z, 0.8),
                3 => (
                    centre + out * 1.3 + DVec3::Z * 0.35,
                    (DVec3::Z - out).normalize(),
                    0.7,
                ),
                _ => (
                    centre + out * 1.5 + DVec3::Z * (0.9 + 0.55 * (k - 4) as f64),
                    -out,
                    0.6,
                ),
            };
            let ring: Vec<u32> = offsets
                .iter()
                .map(|&(x, y)| {
                    v.push(c + (across * x + up * y * 0.45) * shrink);
                    parts.push(CactusPart::Arm(a, k));
                    (v.len() - 1) as u32
                })
                .collect();
            let part = if k <= 4 { label } else { label + 1 };
            for e in 0..4 {
                faces.push(vec![
                    previous[e],
                    previous[(e + 1) % 4],
                    ring[(e + 1) % 4],
                    ring[e],
                ]);
                labels.push(part);
            }
            previous = [ring[0], ring[1], ring[2], ring[3]];
        }
        faces.push(previous.to_vec());
        labels.push(label + 1);
    }
    match Model::new(v, faces) {
        Ok(model) => Cactus {
            model,
            labels,
            parts,
        },
        Err(e) => panic!("the test cactus: {e}"),
    }
}

/// Component `c`'s sub-mesh with each vertex moved by `move_vertex(vertex of the model, position)`.
pub fn moved_piece(
    model: &Model,
    d: &Decomposition,
    c: usize,
    move_vertex: impl Fn(usize, DVec3) -> DVec3,
) -> Model {
    let mut m = match d.component_model(model, c) {
        Ok(m) => m,
        Err(e) => panic!("component {c}: {e}"),
    };
    for (k, &v) in d.components[c].vertices.iter().enumerate() {
        m.vertices[k] = move_vertex(v as usize, m.vertices[k]);
    }
    m
}

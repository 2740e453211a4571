//! The variety test tree from `assets/birch.obj` (made by `assets/birch.py`): a low-poly birch of six components, one
//! material each — trunk, two branches, the crown and a leaf mass on each branch — and its atlas of three variants
//! per component, made by the same kinds of edits a user makes in Blender (and `blender_tests/test_variety.py` does):
//! a twist and a flared base on the trunk, a branch tilted as a solid (its leaf mass follows) or kinked, leaf
//! clumps deleted, a leaf mass sheared as a Lattice does.
//!
//! The file is read by the small reader below rather than by an OBJ crate: it is the plain subset
//! `assets/birch.py` writes (`v x y z`, `vt u v`, `usemtl name`, `f v/vt …`, comments), and a reader of it is shorter
//! than the crate's options, and the test then follows the file line for line (a line it does not know is an error).

use glam::DVec3;
use std::collections::HashSet;
use worldpaint_core::{Atlas, DVec2, Decomposition, Model, VariantClass};

/// The birch as the engine sees it.
pub struct Birch {
    pub model: Model,
    /// Component label per face: the index of its material in the order the file names them.
    pub labels: Vec<u32>,
    /// The materials (components) in that order.
    pub names: Vec<String>,
}

/// Reads `assets/birch.obj` from the repository.
pub fn birch() -> Birch {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/birch.obj");
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{path}: {e} (remake it with `python assets/birch.py`)"));
    read_obj(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// A Wavefront OBJ of one object with texture coordinates and materials (the subset `assets/birch.py` writes).
pub fn read_obj(text: &str) -> Result<Birch, String> {
    let (mut v, mut vt, mut faces, mut uvs, mut labels, mut names) =
        (vec![], vec![], vec![], vec![], vec![], Vec::<String>::new());
    let mut current: Option<u32> = None;
    for (n, line) in text.lines().enumerate() {
        let at = |what: &str| format!("line {}: {what}: {line}", n + 1);
        let mut words = line.split_whitespace();
        let numbers = |words: std::str::SplitWhitespace<'_>| -> Result<Vec<f64>, String> {
            words
                .map(|w| w.parse::<f64>().map_err(|_| at("not a number")))
                .collect()
        };
        match words.next() {
            None | Some("#") | Some("mtllib") | Some("o") => {}
            Some("v") => match numbers(words)?[..] {
                [x, y, z] => v.push(DVec3::new(x, y, z)),
                _ => return Err(at("a vertex takes x y z")),
            },
            Some("vt") => match numbers(words)?[..] {
                [a, b] => vt.push(DVec2::new(a, b)),
                _ => return Err(at("a texture coordinate takes u v")),
            },
            Some("usemtl") => {
                let name = words.next().ok_or_else(|| at("usemtl without a name"))?;
                let k = names.iter().position(|m| m == name).unwrap_or_else(|| {
                    names.push(name.to_string());
                    names.len() - 1
                });
                current = Some(k as u32);
            }
            Some("f") => {
                let (mut face, mut corners) = (vec![], vec![]);
                for w in words {
                    let mut ids = w.split('/').map(|i| i.parse::<usize>().ok());
                    match (ids.next().flatten(), ids.next().flatten()) {
                        (Some(a), Some(b)) if a >= 1 && a <= v.len() && b >= 1 && b <= vt.len() => {
                            face.push((a - 1) as u32);
                            corners.push(vt[b - 1]);
                        }
                        _ => return Err(at("a corner is v/vt with both defined before")),
                    }
                }
                faces.push(face);
                uvs.push(corners);
                labels.push(current.ok_or_else(|| at("a face before any usemtl"))?);
            }
            Some(_) => return Err(at("not part of the OBJ subset read here")),
        }
    }
    let materials = labels.clone();
    let model = Model::new(v, faces)
        .and_then(|m| m.with_uvs(uvs))
        .and_then(|m| m.with_materials(materials))
        .map_err(|e| e.to_string())?;
    Ok(Birch {
        model,
        labels,
        names,
    })
}

/// The vertices of component `c` (local numbering) that lie on one of its connecting regions, by neighbour.
fn region_vertices(d: &Decomposition, c: usize) -> Vec<(usize, HashSet<usize>)> {
    let comp = &d.components[c];
    d.arcs(c)
        .iter()
        .map(|&r| {
            let region = &d.regions[r];
            let local = region
                .vertices
                .iter()
                .filter_map(|&v| comp.local_index(v))
                .collect();
            (region.other(c), local)
        })
        .collect()
}

/// Groups of faces of a sub-mesh joined by shared vertices, each sorted, the groups by their first face.
fn islands(m: &Model) -> Vec<Vec<usize>> {
    let mut parent: Vec<usize> = (0..m.vertices.len()).collect();
    fn root(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    for f in &m.faces {
        for w in f.windows(2) {
            let (a, b) = (
                root(&mut parent, w[0] as usize),
                root(&mut parent, w[1] as usize),
            );
            parent[a] = b;
        }
    }
    let mut groups: Vec<(usize, Vec<usize>)> = vec![];
    for (k, f) in m.faces.iter().enumerate() {
        let r = root(&mut parent, f[0] as usize);
        match groups.iter_mut().find(|g| g.0 == r) {
            Some(g) => g.1.push(k),
            None => groups.push((r, vec![k])),
        }
    }
    groups.into_iter().map(|g| g.1).collect()
}

/// Component `c`'s sub-mesh with `moved(k, p)` giving vertex `k`'s new place and the faces of `drop` deleted.
fn edited(
    b: &Birch,
    d: &Decomposition,
    c: usize,
    moved: impl Fn(usize, DVec3) -> DVec3,
    drop: &HashSet<usize>,
) -> Model {
    let mut m = d
        .component_model(&b.model, c)
        .unwrap_or_else(|e| panic!("component {c}: {e}"));
    for (k, p) in m.vertices.iter_mut().enumerate() {
        *p = moved(k, *p);
    }
    fn keep<T>(list: &mut Vec<T>, drop: &HashSet<usize>) {
        let mut k = 0;
        list.retain(|_| {
            k += 1;
            !drop.contains(&(k - 1))
        });
    }
    keep(&mut m.faces, drop);
    if let Some(uvs) = m.uvs.as_mut() {
        keep(uvs, drop);
    }
    if let Some(mats) = m.materials.as_mut() {
        keep(mats, drop);
    }
    m
}

fn centre(m: &Model, ids: &HashSet<usize>) -> DVec3 {
    ids.iter().map(|&k| m.vertices[k]).sum::<DVec3>() / ids.len().max(1) as f64
}

/// The leaf clumps of a leaf mass (the islands that do not touch a connecting region), every other one from
/// `first` (0 or 1): the faces a user deletes to thin the foliage.
fn every_other_clump(m: &Model, ring: &HashSet<usize>, first: usize) -> HashSet<usize> {
    islands(m)
        .into_iter()
        .filter(|faces| {
            !faces
                .iter()
                .any(|&f| m.faces[f].iter().any(|&v| ring.contains(&(v as usize))))
        })
        .enumerate()
        .filter(|(k, _)| k % 2 == first)
        .flat_map(|(_, faces)| faces)
        .collect()
}

/// A Lattice's shear of a leaf mass: every vertex off its ring moves `amount` along +x times its height over the ring
/// as a fraction of the mass's height (a 2×2×2 lattice whose top corners are moved).
fn sheared(m: &Model, ring: &HashSet<usize>, amount: f64) -> impl Fn(usize, DVec3) -> DVec3 {
    let low = ring
        .iter()
        .map(|&k| m.vertices[k].z)
        .fold(f64::INFINITY, f64::min);
    let high = m.vertices.iter().map(|p| p.z).fold(low, f64::max);
    let ring = ring.clone();
    move |k, p| {
        if ring.contains(&k) {
            p
        } else {
            p + DVec3::X * amount * ((p.z - low) / (high - low)).clamp(0.0, 1.0)
        }
    }
}

/// The birch's decomposition (root: the trunk) and its atlas of 3 variants per component, with their classes.
pub fn birch_atlas(b: &Birch) -> (Decomposition, Atlas, Vec<Vec<VariantClass>>) {
    let d = Decomposition::from_labels(&b.model, &b.labels, Some(0))
        .unwrap_or_else(|e| panic!("decomposing the birch: {e}"));
    let mut atlas =
        Atlas::new(&b.model, d.clone()).unwrap_or_else(|e| panic!("the birch's atlas: {e}"));
    let none = HashSet::new();
    let part = |c: usize| d.component_model(&b.model, c).expect("sub-mesh");
    let mut edits: Vec<(usize, Model)> = vec![];
    // trunk: its base flared (an edit-mode scale of the bottom ring) and its two lowest rings twisted (Simple Deform)
    let trunk = part(0);
    let base: HashSet<usize> = (0..trunk.vertices.len())
        .filter(|&k| trunk.vertices[k].z.abs() < 1e-6)
        .collect();
    let foot = centre(&trunk, &base);
    let flare = |k: usize, p: DVec3| {
        if base.contains(&k) {
            foot + (p - foot) * DVec3::new(1.35, 1.35, 1.0)
        } else {
            p
        }
    };
    edits.push((0, edited(b, &d, 0, flare, &none)));
    let twist = |_: usize, p: DVec3| {
        if p.z > 0.5 && p.z < 2.5 {
            glam::DQuat::from_rotation_z(p.z * 10f64.to_radians()) * p
        } else {
            p
        }
    };
    edits.push((0, edited(b, &d, 0, twist, &none)));
    // branches: tilted as a solid from their first ring (8° up for a, 8° down for b), or kinked at their middle ring
    for (c, angle) in [(1usize, 8f64), (2, -8.0)] {
        let m = part(c);
        let regions = region_vertices(&d, c);
        let at_trunk = &regions.iter().find(|r| r.0 == 0).expect("on the trunk").1;
        let at_tip = &regions.iter().find(|r| r.0 != 0).expect("a leaf mass").1;
        let (root, tip) = (centre(&m, at_trunk), centre(&m, at_tip));
        let axis = tip - root;
        let ring = |p: DVec3| ((p - root).dot(axis) / axis.length_squared() * 5.0).round() as i64;
        let first: Vec<DVec3> = m
            .vertices
            .iter()
            .copied()
            .filter(|&p| ring(p) == 1)
            .collect();
        let pivot = first.iter().copied().sum::<DVec3>() / first.len() as f64;
        let across = axis.cross(DVec3::Z).normalize();
        let turn = glam::DAffine3::from_translation(pivot)
            * glam::DAffine3::from_axis_angle(across, angle.to_radians())
            * glam::DAffine3::from_translation(-pivot);
        let tilt = move |_: usize, p: DVec3| {
            if ring(p) >= 2 {
                turn.transform_point3(p)
            } else {
                p
            }
        };
        edits.push((c, edited(b, &d, c, tilt, &none)));
        let kink = move |_: usize, p: DVec3| if ring(p) == 3 { p + DVec3::Z * 0.08 } else { p };
        edits.push((c, edited(b, &d, c, kink, &none)));
    }
    // leaf masses: every other clump deleted, and the mass sheared by a Lattice
    for (c, first, shear) in [(3usize, 1usize, 0.3), (4, 0, 0.25), (5, 0, -0.25)] {
        let m = part(c);
        let ring: HashSet<usize> = region_vertices(&d, c)
            .into_iter()
            .flat_map(|r| r.1)
            .collect();
        let thin = every_other_clump(&m, &ring, first);
        edits.push((c, edited(b, &d, c, |_, p| p, &thin)));
        edits.push((c, edited(b, &d, c, sheared(&m, &ring, shear), &none)));
    }
    let mut classes = vec![vec![VariantClass::Local]; d.components.len()];
    for (c, m) in edits {
        match atlas.add_variant(c, m) {
            Ok(class) => classes[c].push(class),
            Err(e) => panic!("a variant of component {c} ({}): {e}", b.names[c]),
        }
    }
    (d, atlas, classes)
}

//! Assembly (seed §4.3): one variant per node, frames applied down the component tree, connecting regions welded.
//!
//! The graph is walked from the root ([`super::Decomposition::order`]); a component is placed by its parent's
//! placement composed with the frame its parent's chosen variant stores on the region between them (§4.2.2: "we
//! apply the frame transformation of the connecting region to all the components of the sub-tree"). A component
//! in a local cycle is laid `r` times, each copy moved by the cycle's step and the previous copy's exit frame.
//! Welding: a connecting-region vertex of a component takes the output vertex that the already placed neighbour
//! across that region made for it; the distance between the two placements is the assembly's crack measure
//! ([`Assembled::max_gap`], within 1e-6 m when the atlas is sound). Vertices no face uses are dropped.
//!
//! The count #V = Σ_graphs Π_i #F_i (eq. 1 per graph): the number of different models, since the atlas holds no
//! variant that would repeat one (see [`super::atlas`]), where a component in a local cycle counts
//! Σ_{r=1}^{max} #F_i^r (each copy picks its variant). It saturates at `u128::MAX`. [`Atlas::choice`] numbers the
//! assemblies 0..#V (a mixed radix in graph, then component order), so all of them can be listed;
//! [`Atlas::random_choice`] draws a graph by its count, then each node's repetition by its count, then variants
//! uniformly: every assembly equally likely.

use super::atlas::{Atlas, AtlasGraph, LocalCycle, Variant, VariantClass};
use super::model::Model;
use crate::error::{Error, Result};
use glam::{DAffine3, DVec2, DVec3};
use rand::Rng;

/// Which variant each node takes in one assembly.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Choice {
    /// The graph of the atlas ([`Atlas::graphs`]; 0 is the main one).
    pub graph: usize,
    /// For each component, the chosen entries of its node (`AtlasGraph::nodes`): one per copy (one unless the
    /// component repeats in a local cycle).
    pub picks: Vec<Vec<usize>>,
}

/// An assembled model.
#[derive(Clone, Debug)]
pub struct Assembled {
    /// The welded mesh, with the variants' texture coordinates (when every chosen variant has them) and materials.
    pub model: Model,
    /// For each face, the original model face it copies (`None` for a face an edit added).
    pub face_origin: Vec<Option<u32>>,
    /// For each face, its component.
    pub face_component: Vec<u32>,
    /// For each face, the placed component it comes from (an index into [`Assembled::instances`]) and its face in
    /// that variant's mesh.
    pub face_source: Vec<(u32, u32)>,
    /// The placed components, in placing order: a renderer may instance the variants' meshes with these
    /// placements instead of storing the welded mesh (the seed's memory argument, §6).
    pub instances: Vec<Placed>,
    /// The largest distance between the two placements of a welded connecting-region vertex (m): the crack the
    /// weld closed.
    pub max_gap: f64,
    /// A hash of the geometry (vertex positions quantised to 1e-5 m, face by face): equal models hash equal.
    pub hash: u64,
}

/// One component placed in an assembly.
#[derive(Clone, Debug, PartialEq)]
pub struct Placed {
    /// The component.
    pub component: usize,
    /// The entry of its node in the chosen graph ([`AtlasGraph::nodes`]).
    pub entry: usize,
    /// The atlas variant that entry holds.
    pub variant: usize,
    /// Where it is placed: the product of the frames from the root (and the local cycle's steps).
    pub placement: DAffine3,
}

/// Multiplies counts, saturating.
fn mul(a: u128, b: u128) -> u128 {
    a.saturating_mul(b)
}

impl Atlas {
    /// How many ways node `c` of graph `g` can be filled (with its repetitions).
    fn node_count(&self, g: &AtlasGraph, main: bool, c: usize) -> u128 {
        let k = g.nodes[c].len() as u128;
        match self.cycle_of(c).filter(|_| main) {
            Some(cycle) => {
                let mut total: u128 = 0;
                let mut power: u128 = 1;
                for _ in 0..cycle.max_repeat {
                    power = mul(power, k);
                    total = total.saturating_add(power);
                }
                total
            }
            None => k,
        }
    }

    /// The number of assemblies #V (eq. 1), each a different model, saturating at `u128::MAX`.
    pub fn count(&self) -> u128 {
        self.graphs()
            .iter()
            .enumerate()
            .map(|(gi, g)| {
                (0..g.nodes.len()).fold(1u128, |a, c| mul(a, self.node_count(g, gi == 0, c)))
            })
            .fold(0u128, |a, b| a.saturating_add(b))
    }

    /// The assembly that shows variant `variants[c]` of each component `c` (0 its original; seed §4.3's "pick
    /// components by hand"): in the first graph holding them all, each component once. An error names a variant
    /// that does not exist, or picks no graph holds together (a region-changing variant with a neighbour it was
    /// not adapted to).
    pub fn choice_of_variants(&self, variants: &[usize]) -> Result<Choice> {
        let n = self.decomposition().components.len();
        if variants.len() != n {
            return Err(Error::invalid(
                "picked variants",
                format!("{} picks for {n} components", variants.len()),
            ));
        }
        for (c, &v) in variants.iter().enumerate() {
            if v >= self.variants(c).len() {
                return Err(Error::invalid(
                    "picked variants",
                    format!(
                        "'{}' has variants 0 (its original) to {}, not {v}",
                        self.name(c),
                        self.variants(c).len() - 1
                    ),
                ));
            }
        }
        self.graphs()
            .iter()
            .enumerate()
            .find_map(|(graph, g)| {
                let picks: Option<Vec<Vec<usize>>> = variants
                    .iter()
                    .enumerate()
                    .map(|(c, &v)| g.nodes[c].iter().position(|e| e.variant == v).map(|e| vec![e]))
                    .collect();
                picks.map(|picks| Choice { graph, picks })
            })
            .ok_or_else(|| {
                let reshaping: Vec<String> = variants
                    .iter()
                    .enumerate()
                    .filter(|&(c, &v)| self.variants(c)[v].class == VariantClass::RegionChange)
                    .map(|(c, &v)| format!("copy '{}' in '{}'", self.variants(c)[v].name, self.name(c)))
                    .collect();
                Error::invalid(
                    "picked variants",
                    format!(
                        "no assembly holds them together: {} each reshape a connecting region, and a copy that \
                         does goes only with parts that keep theirs (the neighbour adapted to it); pick one of them",
                        reshaping.join(" and ")
                    ),
                )
            })
    }

    /// The assembly numbered `index` in 0..[`Atlas::count`].
    pub fn choice(&self, mut index: u128) -> Result<Choice> {
        let total = self.count();
        if index >= total {
            return Err(Error::invalid(
                "assembly number",
                format!("{index} is past the {total} assemblies the atlas makes"),
            ));
        }
        for (gi, g) in self.graphs().iter().enumerate() {
            let counts: Vec<u128> = (0..g.nodes.len())
                .map(|c| self.node_count(g, gi == 0, c))
                .collect();
            let size = counts.iter().fold(1u128, |a, &b| mul(a, b));
            if index >= size {
                index -= size;
                continue;
            }
            let mut picks = Vec::with_capacity(g.nodes.len());
            for (c, &count) in counts.iter().enumerate() {
                let mut digit = index % count.max(1);
                index /= count.max(1);
                let k = g.nodes[c].len() as u128;
                let mut copies = 1u32;
                if gi == 0 && self.cycle_of(c).is_some() {
                    let mut power = k;
                    while digit >= power {
                        digit -= power;
                        power = mul(power, k);
                        copies += 1;
                    }
                }
                let mut node = Vec::with_capacity(copies as usize);
                for _ in 0..copies {
                    node.push((digit % k.max(1)) as usize);
                    digit /= k.max(1);
                }
                picks.push(node);
            }
            return Ok(Choice { graph: gi, picks });
        }
        Err(Error::invalid(
            "assembly number",
            "past the assemblies of the atlas",
        ))
    }

    /// A random assembly, every one equally likely.
    pub fn random_choice<R: Rng>(&self, rng: &mut R) -> Choice {
        let weights: Vec<f64> = self
            .graphs()
            .iter()
            .enumerate()
            .map(|(gi, g)| {
                (0..g.nodes.len())
                    .map(|c| self.node_count(g, gi == 0, c) as f64)
                    .product()
            })
            .collect();
        let gi = weighted(&weights, rng);
        let g = &self.graphs()[gi];
        let picks = (0..g.nodes.len())
            .map(|c| {
                let k = g.nodes[c].len();
                let copies = match self.cycle_of(c).filter(|_| gi == 0) {
                    Some(cycle) => {
                        let w: Vec<f64> = (1..=cycle.max_repeat as i32)
                            .map(|r| (k as f64).powi(r))
                            .collect();
                        weighted(&w, rng) + 1
                    }
                    None => 1,
                };
                (0..copies).map(|_| rng.random_range(0..k.max(1))).collect()
            })
            .collect();
        Choice { graph: gi, picks }
    }

    /// Checks that `choice` names existing graph entries with allowed repetitions.
    fn check_choice(&self, choice: &Choice) -> Result<&AtlasGraph> {
        let g = self.graphs().get(choice.graph).ok_or_else(|| {
            Error::invalid(
                "assembly choice",
                format!(
                    "graph {} is not one of the {}",
                    choice.graph,
                    self.graphs().len()
                ),
            )
        })?;
        crate::error::check::same_len(
            "assembly choice (components)",
            choice.picks.len(),
            g.nodes.len(),
        )?;
        for (c, picks) in choice.picks.iter().enumerate() {
            let max = match self.cycle_of(c).filter(|_| choice.graph == 0) {
                Some(cycle) => cycle.max_repeat as usize,
                None => 1,
            };
            if picks.is_empty() || picks.len() > max {
                return Err(Error::invalid(
                    format!("assembly choice of component {c}"),
                    format!(
                        "it takes {} copies, and 1 to {max} are allowed",
                        picks.len()
                    ),
                ));
            }
            if let Some(&p) = picks.iter().find(|&&p| p >= g.nodes[c].len()) {
                return Err(Error::invalid(
                    format!("assembly choice of component {c}"),
                    format!("entry {p} is not one of the node's {}", g.nodes[c].len()),
                ));
            }
        }
        Ok(g)
    }

    /// Assembles the model that `choice` describes.
    pub fn assemble(&self, choice: &Choice) -> Result<Assembled> {
        let g = self.check_choice(choice)?;
        let d = self.decomposition();
        let n = d.components.len();
        let mut out = Assembly::default();
        // For each component: its last copy's output index per variant vertex, and that copy's placement.
        let mut placed: Vec<Option<Vec<u32>>> = vec![None; n];
        let mut last_frame: Vec<DAffine3> = vec![DAffine3::IDENTITY; n];
        let mut last_variant: Vec<usize> = vec![0; n];
        for &c in d.order() {
            let mut world = match d.parent(c) {
                Some((p, r)) => last_frame[p] * self.variants(p)[last_variant[p]].frame(r),
                None => DAffine3::IDENTITY,
            };
            let cycle = self.cycle_of(c).filter(|_| choice.graph == 0);
            let mut previous: Option<Vec<u32>> = None;
            for (copy, &pick) in choice.picks[c].iter().enumerate() {
                let node = &g.nodes[c][pick];
                let variant = &self.variants(c)[node.variant];
                let positions = node.positions.as_ref().unwrap_or(&variant.model.vertices);
                if copy > 0 {
                    if let Some(cycle) = cycle {
                        let before = &self.variants(c)[last_variant[c]];
                        world = world * before.frame(cycle.exit) * cycle.step;
                    }
                }
                let map: Vec<u32> = positions
                    .iter()
                    .enumerate()
                    .map(|(k, p)| {
                        let weld = d.components[c].vertices.get(k).and_then(|&v| {
                            self.weld_target(c, copy, v, cycle, previous.as_deref(), &placed)
                        });
                        out.add_vertex(world.transform_point3(*p), weld)
                    })
                    .collect();
                out.add_faces(c, variant, &map);
                out.instances.push(Placed {
                    component: c,
                    entry: pick,
                    variant: node.variant,
                    placement: world,
                });
                last_frame[c] = world;
                last_variant[c] = node.variant;
                previous = Some(map);
            }
            placed[c] = previous;
        }
        Ok(out.finish())
    }

    /// The output vertex that vertex `v` (model index) of copy `copy` of component `c` welds to, if any: on a local
    /// cycle the previous copy's exit vertex it continues, else the same vertex of an already placed neighbour
    /// across a connecting region holding it (a later copy of a cycle does not weld back to the parent).
    fn weld_target(
        &self,
        c: usize,
        copy: usize,
        v: u32,
        cycle: Option<&LocalCycle>,
        previous: Option<&[u32]>,
        placed: &[Option<Vec<u32>>],
    ) -> Option<u32> {
        let d = self.decomposition();
        if let (Some(cycle), Some(prev)) = (cycle, previous) {
            if let Some(&(_, exit_v)) = cycle.matching.iter().find(|m| m.0 == v) {
                if let Some(weld) = d.components[c].local_index(exit_v).map(|l| prev[l]) {
                    return Some(weld);
                }
            }
        }
        d.arcs(c).iter().find_map(|&r| {
            let o = d.regions[r].other(c);
            if copy > 0 && d.parent(c).is_some_and(|(p, _)| p == o) {
                return None;
            }
            let other = placed[o].as_ref()?;
            d.regions[r].vertices.binary_search(&v).ok()?;
            d.components[o].local_index(v).map(|l| other[l])
        })
    }
}

/// The welded model as it is assembled, copy after copy, with what it records per face.
#[derive(Default)]
struct Assembly {
    model: Model,
    uvs: Vec<Vec<DVec2>>,
    missing_uvs: bool,
    materials: Vec<u32>,
    face_origin: Vec<Option<u32>>,
    face_component: Vec<u32>,
    face_source: Vec<(u32, u32)>,
    instances: Vec<Placed>,
    max_gap: f64,
}

impl Assembly {
    /// The output index of a vertex placed `at`: the vertex it welds to (the gap between the two recorded), or a
    /// new one.
    fn add_vertex(&mut self, at: DVec3, weld: Option<u32>) -> u32 {
        match weld {
            Some(idx) => {
                self.max_gap = self
                    .max_gap
                    .max(self.model.vertices[idx as usize].distance(at));
                idx
            }
            None => {
                self.model.vertices.push(at);
                (self.model.vertices.len() - 1) as u32
            }
        }
    }

    /// Adds the faces of `variant` of component `c` with its vertices at `map`, as the next placed instance; a face
    /// that welding folded to fewer than three corners is left out.
    fn add_faces(&mut self, c: usize, variant: &Variant, map: &[u32]) {
        for (f, face) in variant.model.faces.iter().enumerate() {
            let mut mapped: Vec<u32> = Vec::with_capacity(face.len());
            let mut corner_uvs = Vec::with_capacity(face.len());
            for (corner, &v) in face.iter().enumerate() {
                let idx = map[v as usize];
                if !mapped.contains(&idx) {
                    mapped.push(idx);
                    if let Some(u) = &variant.model.uvs {
                        corner_uvs.push(u[f][corner]);
                    }
                }
            }
            if mapped.len() < 3 {
                continue;
            }
            self.missing_uvs |= variant.model.uvs.is_none();
            self.uvs.push(corner_uvs);
            self.model.faces.push(mapped);
            self.materials.push(variant.model.material(f));
            self.face_origin.push(variant.face_origin[f]);
            self.face_component.push(c as u32);
            self.face_source
                .push((self.instances.len() as u32, f as u32));
        }
    }

    fn finish(self) -> Assembled {
        let mut out = self.model;
        out.uvs = (!self.missing_uvs).then_some(self.uvs);
        out.materials = Some(self.materials);
        let model = out.compacted();
        let hash = geometry_hash(&model);
        Assembled {
            model,
            face_origin: self.face_origin,
            face_component: self.face_component,
            face_source: self.face_source,
            instances: self.instances,
            max_gap: self.max_gap,
            hash,
        }
    }
}

/// Picks an index with probability proportional to its weight.
fn weighted<R: Rng>(weights: &[f64], rng: &mut R) -> usize {
    let total: f64 = weights.iter().sum();
    if !(total > 0.0) || !total.is_finite() {
        return 0;
    }
    let mut x = rng.random::<f64>() * total;
    for (k, &w) in weights.iter().enumerate() {
        if x < w {
            return k;
        }
        x -= w;
    }
    weights.len().saturating_sub(1)
}

/// A hash of the faces' corner positions quantised to 1e-5 m (FNV-1a over 64-bit words, then a final mix): models
/// with the same faces at the same places hash equal.
pub(super) fn geometry_hash(model: &Model) -> u64 {
    let mut h = Fnv::new();
    h.eat(model.faces.len() as u64);
    for face in &model.faces {
        h.eat(face.len() as u64);
        for &v in face {
            let p: DVec3 = model.vertices[v as usize];
            for x in p.to_array() {
                h.eat(((x * 1e5).round() as i64) as u64);
            }
        }
    }
    h.finish()
}

/// FNV-1a over 64-bit words with a shift after each, then a final mix.
struct Fnv(u64);

impl Fnv {
    fn new() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }

    fn eat(&mut self, x: u64) {
        const PRIME: u64 = 0x0000_0100_0000_01b3;
        self.0 = (self.0 ^ x).wrapping_mul(PRIME);
        self.0 ^= self.0 >> 29;
    }

    fn finish(self) -> u64 {
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^ (h >> 33)
    }
}

/// A hash of a model's shape whatever the order of its faces and vertices: each face's material and its corners
/// (positions quantised to 1e-5 m as [`geometry_hash`] does, and texture coordinates to 1e-5), started at its least
/// corner, the faces sorted, then hashed as [`geometry_hash`] does. Two models with the same faces at the same places,
/// of the same materials and texture coordinates, hash equal.
pub(super) fn shape_hash(model: &Model) -> u64 {
    let corner = |f: usize, k: usize, v: u32| -> [i64; 5] {
        let p = model
            .vertices
            .get(v as usize)
            .copied()
            .unwrap_or(DVec3::NAN)
            * 1e5;
        let uv = model
            .uvs
            .as_ref()
            .and_then(|u| u.get(f))
            .and_then(|u| u.get(k))
            .map_or(DVec2::ZERO, |&uv| uv * 1e5);
        [p.x, p.y, p.z, uv.x, uv.y].map(|x| x.round() as i64)
    };
    let mut faces: Vec<Vec<[i64; 5]>> = model
        .faces
        .iter()
        .enumerate()
        .map(|(f, face)| {
            let corners: Vec<[i64; 5]> = face
                .iter()
                .enumerate()
                .map(|(k, &v)| corner(f, k, v))
                .collect();
            let first = (0..corners.len()).min_by_key(|&k| corners[k]).unwrap_or(0);
            let material = [i64::from(model.material(f)), 0, 0, 0, 0];
            std::iter::once(material)
                .chain(corners[first..].iter().chain(&corners[..first]).copied())
                .collect()
        })
        .collect();
    faces.sort_unstable();
    let mut h = Fnv::new();
    h.eat(faces.len() as u64);
    for face in &faces {
        h.eat(face.len() as u64);
        for x in face.iter().flatten() {
            h.eat(*x as u64);
        }
    }
    h.finish()
}

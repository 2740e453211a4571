//! The atlas of component variants (seed §4.2) and how each variant updates the graph.
//!
//! A variant F_i^k is an edit of component F_i's sub-mesh ([`super::Decomposition::component_model`]). Its vertex
//! `k < n_i` is the component's vertex `k` (the n_i vertices of [`super::Component::vertices`], in that order),
//! moved or not; vertices past n_i are new. That is how Blender keeps them when the user moves vertices, runs a
//! Lattice (FFD) or Simple Deform (axial deformation) or deletes faces only; deleting vertices renumbers them and is
//! refused by the check that the connecting-region vertices are still there. A variant face copies an original face
//! when it uses the same component vertices (the self-intersection labels follow it).
//!
//! Each connecting region of the variant is classified ([`RegionChange`]):
//! - **untouched** (every vertex within the tolerance of its place): §4.2.1, a local change when all are;
//! - **solid**: moved by one similarity (translation, rotation, uniform scale) fitted by least squares
//!   ([`super::fit_similarity`]): §4.2.2, the map is stored as the region's frame and applied at assembly to the subtree
//!   beyond it. When the moved region is the one towards the root, the whole variant is brought back by the inverse
//!   map (the same geometry seen from its parent: a branch whose base was turned leaves the trunk tilted the other
//!   way), so that only regions towards the leaves carry frames; such a variant is still a solid transform;
//! - **changed**: any other move, §4.2.3. Reading chosen: the graph is duplicated into a graph G' in which node N_i
//!   holds this variant only and each neighbour N_j across a changed region holds every variant of F_j adapted to
//!   it — their region's vertices put where the changed variant put them (through F_j's own frame on that region,
//!   if it has one). Other nodes hold all their variants; changed variants are never combined with each other, and
//!   local cycles apply in the main graph only. The main graph holds every variant that changes no region.
//!
//! A solid transform of a region that lies on a cycle of the graph is refused (§4.2.3, Fig. 11: on a fully cyclic
//! graph, no region can move without opening a crack where the cycle closes); the refusal names the region and says
//! whether the whole graph is fully cyclic.
//!
//! Local cycles (§4.2.4): a component whose two connecting regions are identical up to a similarity T (the same
//! vertex count, matched along their chains in either direction from any start) can be repeated 1 to `max_repeat`
//! times, each copy moved by T from the one before and welded to it; each copy picks its own variant. As in the seed
//! they are allowed only on tree-like graphs and never on a terminal node; readings chosen: the repeated component
//! has exactly two regions, the one to its parent is the entry and it is not the root.

use super::decompose::Decomposition;
use super::frame::{fit_similarity, is_identity};
use super::model::Model;
use crate::error::{Error, Result};
use glam::{DAffine3, DVec3};
use std::collections::HashMap;

/// Distance (m, per metre from the origin past the first) within which a vertex counts as in place, and a fit as
/// solid. Blender stores positions as 32-bit floats, whose rounding is far below it.
pub const TOLERANCE: f64 = 1e-6;

/// Most repetitions a local cycle may allow.
pub const MAX_REPEAT: u32 = 64;

/// What a variant did to one of its component's connecting regions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RegionChange {
    /// Every vertex in place.
    Untouched,
    /// Moved as one solid by this frame (a similarity).
    Solid(DAffine3),
    /// Reshaped.
    Changed,
}

/// The kind of a variant, as the seed sorts them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VariantClass {
    /// §4.2.1: no connecting region moved.
    Local,
    /// §4.2.2: some region moved as a solid, none reshaped.
    SolidTransform,
    /// §4.2.3: some region reshaped; the variant lives in a duplicated graph.
    RegionChange,
}

/// One variant F_i^k of a component, ready for assembly.
#[derive(Clone, Debug)]
pub struct Variant {
    /// The mesh, numbered as the component's sub-mesh, brought back so its region towards the root is in place.
    pub model: Model,
    /// What it did to each of its component's regions: (region index, change), in the order of
    /// [`Decomposition::arcs`].
    pub regions: Vec<(usize, RegionChange)>,
    /// Its class.
    pub class: VariantClass,
    /// For each face, the model face it copies (`None` for a face the edit added).
    pub face_origin: Vec<Option<u32>>,
    /// The frame that brought it back (identity unless it moved its region towards the root).
    pub normalised_by: DAffine3,
}

impl Variant {
    /// The frame of region `r` (identity unless it moved as a solid).
    pub fn frame(&self, r: usize) -> DAffine3 {
        match self.regions.iter().find(|(q, _)| *q == r) {
            Some((_, RegionChange::Solid(f))) => *f,
            _ => DAffine3::IDENTITY,
        }
    }

    /// What happened to region `r`.
    pub fn change(&self, r: usize) -> RegionChange {
        self.regions
            .iter()
            .find(|(q, _)| *q == r)
            .map(|&(_, c)| c)
            .unwrap_or(RegionChange::Untouched)
    }
}

/// A variant as a node of one graph holds it: the atlas variant, with its region vertices moved when adapted to a
/// neighbour's region change.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeVariant {
    /// Index into [`Atlas::variants`] of the component.
    pub variant: usize,
    /// The adapted positions of the variant's vertices (§4.2.3), or `None` to use its own.
    pub positions: Option<Vec<DVec3>>,
}

/// One graph of the atlas: for each component, the variants its node holds.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasGraph {
    /// `nodes[i]`: the variants of node N_i.
    pub nodes: Vec<Vec<NodeVariant>>,
}

/// A local cycle (§4.2.4): a component repeated between its two identical regions.
#[derive(Clone, Debug, PartialEq)]
pub struct LocalCycle {
    /// The repeated component.
    pub component: usize,
    /// Most copies in one assembly (at least 1).
    pub max_repeat: u32,
    /// The region towards the parent (each copy's entry).
    pub entry: usize,
    /// The other region (each copy's exit, where the next copy and then the child attach).
    pub exit: usize,
    /// The similarity carrying the entry region onto the exit region.
    pub step: DAffine3,
    /// For each entry vertex (model index), the exit vertex it lands on.
    pub matching: Vec<(u32, u32)>,
}

/// The atlas F: the model, its decomposition, every component's variants, the graphs they make and the local cycles.
#[derive(Clone, Debug)]
pub struct Atlas {
    model: Model,
    decomposition: Decomposition,
    variants: Vec<Vec<Variant>>,
    graphs: Vec<AtlasGraph>,
    cycles: Vec<LocalCycle>,
}

impl Atlas {
    /// An atlas whose every node holds its original component (variant 0).
    pub fn new(model: &Model, mut decomposition: Decomposition) -> Result<Atlas> {
        model.validate()?;
        decomposition.revalidate(model)?;
        let mut atlas = Atlas {
            model: model.clone(),
            decomposition,
            variants: Vec::new(),
            graphs: Vec::new(),
            cycles: Vec::new(),
        };
        for c in 0..atlas.decomposition.components.len() {
            let sub = atlas.decomposition.component_model(model, c)?;
            let v = atlas.prepare(c, sub)?;
            atlas.variants.push(vec![v]);
        }
        atlas.rebuild();
        Ok(atlas)
    }

    /// The model the atlas was made from.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The decomposition.
    pub fn decomposition(&self) -> &Decomposition {
        &self.decomposition
    }

    /// The variants of component `c` (the original first).
    pub fn variants(&self, c: usize) -> &[Variant] {
        self.variants.get(c).map(Vec::as_slice).unwrap_or(&[])
    }

    /// The graphs: the main one first, then one per region-changing variant (§4.2.3).
    pub fn graphs(&self) -> &[AtlasGraph] {
        &self.graphs
    }

    /// The local cycles.
    pub fn cycles(&self) -> &[LocalCycle] {
        &self.cycles
    }

    /// The local cycle on component `c`, if any.
    pub fn cycle_of(&self, c: usize) -> Option<&LocalCycle> {
        self.cycles.iter().find(|l| l.component == c)
    }

    /// Adds an edit of component `c`'s sub-mesh as a new variant; returns its class. A solid transform of a region
    /// on a cycle of the graph is refused (§4.2.3).
    pub fn add_variant(&mut self, c: usize, edited: Model) -> Result<VariantClass> {
        self.component_checked(c)?;
        let v = self.prepare(c, edited)?;
        let class = v.class;
        if let Some(cycle) = self.cycle_of(c) {
            if v.change(cycle.entry) != RegionChange::Untouched
                || v.change(cycle.exit) == RegionChange::Changed
            {
                return Err(Error::invalid(
                    format!("variant of component {c}"),
                    "the component repeats in a local cycle, so its two ends must keep their shape",
                ));
            }
        }
        self.variants[c].push(v);
        self.rebuild();
        Ok(class)
    }

    fn component_checked(&self, c: usize) -> Result<()> {
        if c >= self.decomposition.components.len() {
            return Err(Error::invalid(
                "component",
                format!(
                    "{c} is not one of the {} components",
                    self.decomposition.components.len()
                ),
            ));
        }
        Ok(())
    }

    /// Classifies an edited sub-mesh of component `c` and brings it back to its parent region.
    fn prepare(&self, c: usize, mut edited: Model) -> Result<Variant> {
        let what = format!("variant of component {c}");
        edited
            .validate()
            .map_err(|e| Error::invalid(what.clone(), e.reason()))?;
        let d = &self.decomposition;
        let comp = &d.components[c];
        let n = comp.vertices.len();
        if edited.vertices.len() < n {
            return Err(Error::invalid(
                what,
                format!(
                    "it has {} vertices but the component has {n}: a variant keeps the component's vertices first, \
                     in their order (move vertices or delete faces, not vertices)",
                    edited.vertices.len()
                ),
            ));
        }
        let mut regions = self.classify(c, &edited);
        let mut normalised_by = DAffine3::IDENTITY;
        if let Some((_, pr)) = d.parent(c) {
            if let Some((_, RegionChange::Solid(t))) = regions.iter().find(|(r, _)| *r == pr) {
                let inverse = t.inverse();
                if inverse.is_finite() {
                    normalised_by = inverse;
                    for p in &mut edited.vertices {
                        *p = inverse.transform_point3(*p);
                    }
                    regions = self.classify(c, &edited);
                }
            }
        }
        for &(r, change) in &regions {
            if matches!(change, RegionChange::Solid(_)) && d.region_on_cycle(r) {
                let other = d.regions[r].other(c);
                let whole = if d.is_fully_cyclic() {
                    "the component graph is fully cyclic (no terminal node), so"
                } else {
                    "that region lies on a cycle of the component graph, so"
                };
                return Err(Error::invalid(
                    what,
                    format!(
                        "it moves its connecting region with component {other} as a solid (a frame transform), but \
                         {whole} moving what lies beyond it would open a crack where the cycle closes (seed §4.2.3, \
                         Fig. 11); keep that region in place or reshape it"
                    ),
                ));
            }
        }
        let class = if regions.iter().any(|r| r.1 == RegionChange::Changed) {
            VariantClass::RegionChange
        } else if normalised_by != DAffine3::IDENTITY
            || regions
                .iter()
                .any(|r| matches!(r.1, RegionChange::Solid(_)))
        {
            VariantClass::SolidTransform
        } else {
            VariantClass::Local
        };
        let face_origin = self.face_origins(c, &edited);
        Ok(Variant {
            model: edited,
            regions,
            class,
            face_origin,
            normalised_by,
        })
    }

    /// What the edit did to each region of component `c`.
    fn classify(&self, c: usize, edited: &Model) -> Vec<(usize, RegionChange)> {
        let d = &self.decomposition;
        let comp = &d.components[c];
        d.arcs(c)
            .iter()
            .map(|&r| {
                let region = &d.regions[r];
                let mut from = Vec::with_capacity(region.vertices.len());
                let mut to = Vec::with_capacity(region.vertices.len());
                for &v in &region.vertices {
                    let local = comp.local_index(v).unwrap_or(0);
                    from.push(self.model.vertices[v as usize]);
                    to.push(edited.vertices[local]);
                }
                let reach = from.iter().map(|p| p.length()).fold(1.0, f64::max);
                let tol = TOLERANCE * reach;
                let moved = from
                    .iter()
                    .zip(&to)
                    .map(|(a, b)| a.distance(*b))
                    .fold(0.0, f64::max);
                let change = if moved <= tol {
                    RegionChange::Untouched
                } else {
                    let (frame, residual) = fit_similarity(&from, &to);
                    if residual <= tol && frame.is_finite() && !is_identity(&frame, reach, tol) {
                        RegionChange::Solid(frame)
                    } else {
                        RegionChange::Changed
                    }
                };
                (r, change)
            })
            .collect()
    }

    /// For each face of an edit of component `c`, the model face with the same component vertices.
    fn face_origins(&self, c: usize, edited: &Model) -> Vec<Option<u32>> {
        let comp = &self.decomposition.components[c];
        let n = comp.vertices.len() as u32;
        let key = |face: &[u32]| {
            let mut k: Vec<u32> = face.to_vec();
            k.sort_unstable();
            k
        };
        let mut originals: HashMap<Vec<u32>, u32> = HashMap::new();
        for &f in &comp.faces {
            let local: Vec<u32> = self.model.faces[f as usize]
                .iter()
                .map(|&v| comp.local_index(v).unwrap_or(0) as u32)
                .collect();
            originals.entry(key(&local)).or_insert(f);
        }
        edited
            .faces
            .iter()
            .map(|face| {
                if face.iter().any(|&v| v >= n) {
                    None
                } else {
                    originals.get(&key(face)).copied()
                }
            })
            .collect()
    }

    /// Adds a local cycle on component `c` with at most `max_repeat` copies (§4.2.4).
    pub fn add_local_cycle(&mut self, c: usize, max_repeat: u32) -> Result<()> {
        self.component_checked(c)?;
        let d = &self.decomposition;
        let what = format!("local cycle on component {c}");
        if max_repeat == 0 || max_repeat > MAX_REPEAT {
            return Err(Error::OutOfRange {
                what: format!("maximum repetition of the {what}"),
                rule: format!("between 1 and {MAX_REPEAT}"),
                value: max_repeat as f64,
            });
        }
        if !d.is_tree_like() {
            return Err(Error::invalid(
                what,
                "local cycles are only added on tree-like graphs (seed §4.2.4), and this component graph has a cycle",
            ));
        }
        if d.degree(c) <= 1 {
            return Err(Error::invalid(
                what,
                "it is a terminal node of the graph, and terminal nodes cannot be in a local cycle (seed §4.2.4)",
            ));
        }
        if d.degree(c) != 2 {
            return Err(Error::invalid(
                what,
                format!(
                    "a repeated component needs exactly two connecting regions (its two ends), it has {}",
                    d.degree(c)
                ),
            ));
        }
        let Some((_, entry)) = d.parent(c) else {
            return Err(Error::invalid(
                what,
                "the root cannot repeat; choose another root for the decomposition",
            ));
        };
        let exit = d
            .arcs(c)
            .iter()
            .copied()
            .find(|&r| r != entry)
            .unwrap_or(entry);
        let (step, matching) = self.match_ends(entry, exit).ok_or_else(|| {
            Error::invalid(
                what.clone(),
                "its two connecting regions are not identical (the same number of vertices along the same shape, \
                 up to a move, a rotation and a uniform scale)",
            )
        })?;
        for (k, v) in self.variants[c].iter().enumerate() {
            if v.change(entry) != RegionChange::Untouched || v.change(exit) == RegionChange::Changed
            {
                return Err(Error::invalid(
                    what,
                    format!("variant {k} of the component reshapes one of its ends, so it cannot repeat"),
                ));
            }
        }
        self.cycles.retain(|l| l.component != c);
        self.cycles.push(LocalCycle {
            component: c,
            max_repeat,
            entry,
            exit,
            step,
            matching,
        });
        self.cycles.sort_by_key(|l| l.component);
        self.rebuild();
        Ok(())
    }

    /// The components that could repeat in a local cycle (§4.2.4: "we check if identical connecting regions exist"):
    /// on a tree-like graph, not the root, two regions, the one to the parent identical to the other up to a
    /// similarity.
    pub fn local_cycle_candidates(&self) -> Vec<usize> {
        let d = &self.decomposition;
        if !d.is_tree_like() {
            return Vec::new();
        }
        (0..d.components.len())
            .filter(|&c| d.degree(c) == 2)
            .filter(|&c| {
                d.parent(c).is_some_and(|(_, entry)| {
                    let exit = d.arcs(c).iter().copied().find(|&r| r != entry);
                    exit.is_some_and(|exit| self.match_ends(entry, exit).is_some())
                })
            })
            .collect()
    }

    /// Matches the vertices of two regions along their chains (each one chain) and fits the step between them.
    fn match_ends(&self, entry: usize, exit: usize) -> Option<(DAffine3, Vec<(u32, u32)>)> {
        let d = &self.decomposition;
        let (a, b) = (&d.regions[entry], &d.regions[exit]);
        if a.chains.len() != 1 || b.chains.len() != 1 {
            return None;
        }
        let (ca, cb) = (&a.chains[0], &b.chains[0]);
        if ca.vertices.len() != cb.vertices.len() || ca.closed != cb.closed {
            return None;
        }
        let n = ca.vertices.len();
        let pos = |v: u32| self.model.vertices[v as usize];
        let from: Vec<DVec3> = ca.vertices.iter().map(|&v| pos(v)).collect();
        let reach = from.iter().map(|p| p.length()).fold(1.0, f64::max);
        let mut best: Option<(f64, DAffine3, Vec<u32>)> = None;
        let shifts = if ca.closed { n } else { 1 };
        for reverse in [false, true] {
            for shift in 0..shifts {
                let order: Vec<u32> = (0..n)
                    .map(|k| {
                        let k = if reverse { n - 1 - k } else { k };
                        cb.vertices[(k + shift) % n]
                    })
                    .collect();
                let to: Vec<DVec3> = order.iter().map(|&v| pos(v)).collect();
                let (frame, residual) = fit_similarity(&from, &to);
                if best.as_ref().is_none_or(|b| residual < b.0) {
                    best = Some((residual, frame, order));
                }
            }
        }
        let (residual, frame, order) = best?;
        let tol = TOLERANCE * reach;
        if residual > tol || is_identity(&frame, reach, tol) || !frame.is_finite() {
            return None;
        }
        Some((frame, ca.vertices.iter().copied().zip(order).collect()))
    }

    /// Rebuilds the graphs from the variants (§4.2.3).
    fn rebuild(&mut self) {
        let d = &self.decomposition;
        let plain = |c: usize| -> Vec<NodeVariant> {
            self.variants[c]
                .iter()
                .enumerate()
                .filter(|(_, v)| v.class != VariantClass::RegionChange)
                .map(|(k, _)| NodeVariant {
                    variant: k,
                    positions: None,
                })
                .collect()
        };
        let main = AtlasGraph {
            nodes: (0..self.variants.len()).map(plain).collect(),
        };
        let mut graphs = vec![main];
        for (c, list) in self.variants.iter().enumerate() {
            for (k, changed) in list.iter().enumerate() {
                if changed.class != VariantClass::RegionChange {
                    continue;
                }
                let mut nodes: Vec<Vec<NodeVariant>> =
                    (0..self.variants.len()).map(plain).collect();
                nodes[c] = vec![NodeVariant {
                    variant: k,
                    positions: None,
                }];
                for &(r, change) in &changed.regions {
                    if change != RegionChange::Changed {
                        continue;
                    }
                    let o = d.regions[r].other(c);
                    let (comp_c, comp_o) = (&d.components[c], &d.components[o]);
                    nodes[o] = plain(o)
                        .into_iter()
                        .map(|mut node| {
                            let v = &self.variants[o][node.variant];
                            let frame = v.frame(r);
                            let mut positions = v.model.vertices.clone();
                            for &rv in &d.regions[r].vertices {
                                if let (Some(lc), Some(lo)) =
                                    (comp_c.local_index(rv), comp_o.local_index(rv))
                                {
                                    positions[lo] =
                                        frame.transform_point3(changed.model.vertices[lc]);
                                }
                            }
                            node.positions = Some(positions);
                            node
                        })
                        .collect();
                }
                graphs.push(AtlasGraph { nodes });
            }
        }
        self.graphs = graphs;
    }
}

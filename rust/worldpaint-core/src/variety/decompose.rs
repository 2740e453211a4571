//! Decomposition into components and the component graph (seed §4.1).
//!
//! The input is a label per face: faces with the same label form a component F_i. Blender turns a face selection,
//! face sets or materials into labels. The seed's cut "along a path of existing vertices" (its Fig. 5, right) adds
//! no vertex, so it too is a labelling: the faces on each side of the path get their side's label. (The cut along a
//! drawn path that adds vertices is a mesh edit done before labelling.)
//!
//! Readings chosen where the seed is vague:
//! - The connecting region R_ij is every vertex used by faces of both F_i and F_j. Its *chains* order it: the edges
//!   used by faces of both components, walked end to end (open paths from their ends first, then closed loops), each
//!   started at its lowest vertex index and oriented as F_i's faces (i < j) run along it. A vertex shared without a
//!   shared edge (a point contact) is a chain of one vertex. An arc A_ij of the graph joins two components exactly
//!   when R_ij is not empty.
//! - The root is the component with the most faces (the lowest index on a tie) unless one is given. The graph is
//!   walked breadth-first from the root, neighbours in index order; that walk's tree gives each component its
//!   parent region. Components that the graph does not join to the root start their own trees, in index order, and
//!   stay where they are at assembly.
//! - Components are numbered by ascending label.

use super::model::Model;
use crate::error::{Error, Result};
use std::collections::{BTreeMap, HashMap, VecDeque};

/// A component F_i: the faces of one label.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// The label its faces carry.
    pub label: u32,
    /// Its faces (indices into the model's faces, ascending).
    pub faces: Vec<u32>,
    /// The vertices its faces use (indices into the model's vertices, ascending). A component's sub-mesh
    /// ([`Decomposition::component_model`]) and every variant of it number their vertices in this order.
    pub vertices: Vec<u32>,
}

impl Component {
    /// The position of model vertex `v` in this component's vertex list.
    pub fn local_index(&self, v: u32) -> Option<usize> {
        self.vertices.binary_search(&v).ok()
    }
}

/// One ordered piece of a connecting region.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// Model vertex indices in order along the shared edges.
    pub vertices: Vec<u32>,
    /// Whether the last vertex joins the first (a boundary loop).
    pub closed: bool,
}

/// A connecting region R_ij between two components: the arc A_ij of the component graph.
#[derive(Clone, Debug, PartialEq)]
pub struct ConnectingRegion {
    /// The two components (i < j).
    pub components: (usize, usize),
    /// Every model vertex shared by faces of both (ascending).
    pub vertices: Vec<u32>,
    /// The shared boundary as ordered chains.
    pub chains: Vec<Chain>,
}

impl ConnectingRegion {
    /// The component across this region from `c`.
    pub fn other(&self, c: usize) -> usize {
        if self.components.0 == c {
            self.components.1
        } else {
            self.components.0
        }
    }
}

/// A model decomposed into components, with the component graph G = (N, A) and its walk from the root.
#[derive(Clone, Debug, PartialEq)]
pub struct Decomposition {
    /// The components, by ascending label.
    pub components: Vec<Component>,
    /// The connecting regions (the graph's arcs), sorted by their pair of components.
    pub regions: Vec<ConnectingRegion>,
    /// The root component.
    pub root: usize,
    /// The model's vertex and face counts, to check the model given with the decomposition later.
    pub model_size: (usize, usize),
    /// Each component's parent and the region to it in the walk (`None` for the root and other tree roots).
    parent: Vec<Option<(usize, usize)>>,
    /// The components in walk order (parents before children).
    order: Vec<usize>,
    /// The arcs on a cycle of the graph (not bridges).
    on_cycle: Vec<bool>,
    /// Arcs (region indices) of each component.
    arcs: Vec<Vec<usize>>,
}

/// The connecting regions of each pair of components that share vertices: the vertices and, as chains, the
/// edges they share (oriented as the first component's faces run along them).
fn connecting_regions(
    model: &Model,
    comp_of_face: &[usize],
    comps_of_vertex: &[Vec<usize>],
) -> Vec<ConnectingRegion> {
    let mut shared: BTreeMap<(usize, usize), Vec<u32>> = BTreeMap::new();
    for (v, list) in comps_of_vertex.iter().enumerate() {
        for (k, &a) in list.iter().enumerate() {
            for &b in &list[k + 1..] {
                shared.entry((a, b)).or_default().push(v as u32);
            }
        }
    }
    // Directed edges of each component, to find and orient the shared ones.
    let mut edge_comps: HashMap<(u32, u32), Vec<(usize, bool)>> = HashMap::new();
    for (f, face) in model.faces.iter().enumerate() {
        let c = comp_of_face[f];
        for (k, &a) in face.iter().enumerate() {
            let b = face[(k + 1) % face.len()];
            let key = (a.min(b), a.max(b));
            edge_comps.entry(key).or_default().push((c, a < b));
        }
    }
    let mut region_edges: BTreeMap<(usize, usize), Vec<(u32, u32)>> = BTreeMap::new();
    for (&(a, b), uses) in &edge_comps {
        let mut comps: Vec<usize> = uses.iter().map(|u| u.0).collect();
        comps.sort_unstable();
        comps.dedup();
        for (k, &i) in comps.iter().enumerate() {
            for &j in &comps[k + 1..] {
                // Oriented as component i's face runs along it.
                let forward = uses.iter().find(|u| u.0 == i).is_none_or(|u| u.1);
                let e = if forward { (a, b) } else { (b, a) };
                region_edges.entry((i, j)).or_default().push(e);
            }
        }
    }
    shared
        .into_iter()
        .map(|(pair, vertices)| {
            let edges = region_edges.remove(&pair).unwrap_or_default();
            let chains = chains_of(&vertices, edges);
            ConnectingRegion {
                components: pair,
                vertices,
                chains,
            }
        })
        .collect()
}

impl Decomposition {
    /// Decomposes `model` by a label per face. `root` names the root component by its label; `None` takes the
    /// component with the most faces.
    pub fn from_labels(model: &Model, labels: &[u32], root: Option<u32>) -> Result<Decomposition> {
        model.validate()?;
        if model.faces.is_empty() {
            return Err(Error::invalid("model", "it has no faces to decompose"));
        }
        if labels.is_empty() {
            return Err(Error::invalid(
                "component labels",
                "none given: each face needs the label of its component",
            ));
        }
        crate::error::check::same_len("component labels", labels.len(), model.faces.len())?;
        let mut distinct: Vec<u32> = labels.to_vec();
        distinct.sort_unstable();
        distinct.dedup();
        let index_of: HashMap<u32, usize> =
            distinct.iter().enumerate().map(|(i, &l)| (l, i)).collect();
        let comp_of_face: Vec<usize> = labels.iter().map(|l| index_of[l]).collect();
        let mut components: Vec<Component> = distinct
            .iter()
            .map(|&label| Component {
                label,
                faces: Vec::new(),
                vertices: Vec::new(),
            })
            .collect();
        // Components of each vertex (few per vertex).
        let mut comps_of_vertex: Vec<Vec<usize>> = vec![Vec::new(); model.vertices.len()];
        for (f, face) in model.faces.iter().enumerate() {
            let c = comp_of_face[f];
            components[c].faces.push(f as u32);
            for &v in face {
                let list = &mut comps_of_vertex[v as usize];
                if !list.contains(&c) {
                    list.push(c);
                }
            }
        }
        for (v, list) in comps_of_vertex.iter_mut().enumerate() {
            list.sort_unstable();
            for &c in list.iter() {
                components[c].vertices.push(v as u32);
            }
        }
        let regions = connecting_regions(model, &comp_of_face, &comps_of_vertex);
        let root = match root {
            Some(label) => *index_of.get(&label).ok_or_else(|| {
                Error::invalid(
                    "root component",
                    format!("no face carries the label {label}"),
                )
            })?,
            None => {
                let most = components.iter().map(|c| c.faces.len()).max().unwrap_or(0);
                components
                    .iter()
                    .position(|c| c.faces.len() == most)
                    .unwrap_or(0)
            }
        };
        let mut d = Decomposition {
            components,
            regions,
            root,
            model_size: (model.vertices.len(), model.faces.len()),
            parent: Vec::new(),
            order: Vec::new(),
            on_cycle: Vec::new(),
            arcs: Vec::new(),
        };
        d.walk();
        Ok(d)
    }

    /// Checks a decomposition whose public fields may have been changed since it was made (the root, the
    /// components, the regions) against `model`, and walks its graph again.
    pub fn revalidate(&mut self, model: &Model) -> Result<()> {
        self.check_model(model)?;
        let n = self.components.len();
        if n == 0 || self.root >= n {
            return Err(Error::invalid(
                "decomposition",
                format!("root {} is not one of its {n} components", self.root),
            ));
        }
        let (nv, nf) = self.model_size;
        for (c, comp) in self.components.iter().enumerate() {
            let sorted = |list: &[u32], below: usize| {
                list.windows(2).all(|w| w[0] < w[1])
                    && list.last().is_none_or(|&x| (x as usize) < below)
            };
            if !sorted(&comp.faces, nf) || !sorted(&comp.vertices, nv) {
                return Err(Error::invalid(
                    format!("decomposition component {c}"),
                    "its faces and vertices must be ascending model indices",
                ));
            }
            for &f in &comp.faces {
                if model.faces[f as usize]
                    .iter()
                    .any(|v| comp.local_index(*v).is_none())
                {
                    return Err(Error::invalid(
                        format!("decomposition component {c}"),
                        format!("face {f} uses a vertex the component does not list"),
                    ));
                }
            }
        }
        for (r, region) in self.regions.iter().enumerate() {
            let (a, b) = region.components;
            let known = a < b
                && b < n
                && region.vertices.iter().all(|&v| {
                    self.components[a].local_index(v).is_some()
                        && self.components[b].local_index(v).is_some()
                });
            if !known {
                return Err(Error::invalid(
                    format!("decomposition region {r}"),
                    "it must join two components (lower first) by vertices both of them use",
                ));
            }
        }
        self.walk();
        Ok(())
    }

    /// Breadth-first walk from the root: parents, order, and which arcs lie on a cycle.
    fn walk(&mut self) {
        let n = self.components.len();
        self.arcs = vec![Vec::new(); n];
        for (r, region) in self.regions.iter().enumerate() {
            self.arcs[region.components.0].push(r);
            self.arcs[region.components.1].push(r);
        }
        self.parent = vec![None; n];
        self.order.clear();
        let mut depth = vec![usize::MAX; n];
        let mut tree_arc = vec![false; self.regions.len()];
        let starts = std::iter::once(self.root).chain(0..n);
        for start in starts {
            if depth[start] != usize::MAX {
                continue;
            }
            depth[start] = 0;
            let mut queue = VecDeque::from([start]);
            while let Some(c) = queue.pop_front() {
                self.order.push(c);
                let mut next: Vec<(usize, usize)> = self.arcs[c]
                    .iter()
                    .map(|&r| (self.regions[r].other(c), r))
                    .collect();
                next.sort_unstable();
                for (o, r) in next {
                    if depth[o] == usize::MAX {
                        depth[o] = depth[c] + 1;
                        self.parent[o] = Some((c, r));
                        tree_arc[r] = true;
                        queue.push_back(o);
                    }
                }
            }
        }
        // An arc is on a cycle when it closes one, or lies on the tree path a closing arc spans.
        self.on_cycle = vec![false; self.regions.len()];
        for (r, region) in self.regions.iter().enumerate() {
            if tree_arc[r] {
                continue;
            }
            self.on_cycle[r] = true;
            let (mut a, mut b) = region.components;
            while a != b {
                if depth[a] < depth[b] {
                    std::mem::swap(&mut a, &mut b);
                }
                match self.parent[a] {
                    Some((p, pr)) => {
                        self.on_cycle[pr] = true;
                        a = p;
                    }
                    None => break,
                }
            }
        }
    }

    /// The component's parent in the walk from the root and the region joining them.
    pub fn parent(&self, c: usize) -> Option<(usize, usize)> {
        self.parent.get(c).copied().flatten()
    }

    /// The components in walk order: every parent before its children.
    pub fn order(&self) -> &[usize] {
        &self.order
    }

    /// The regions (arcs) that touch component `c`.
    pub fn arcs(&self, c: usize) -> &[usize] {
        self.arcs.get(c).map(Vec::as_slice).unwrap_or(&[])
    }

    /// The number of arcs at component `c`; a terminal node has one.
    pub fn degree(&self, c: usize) -> usize {
        self.arcs(c).len()
    }

    /// Whether arc `r` lies on a cycle of the graph (removing it leaves its two components joined).
    pub fn region_on_cycle(&self, r: usize) -> bool {
        self.on_cycle.get(r).copied().unwrap_or(false)
    }

    /// Whether the graph has no cycle (every arc is a bridge).
    pub fn is_tree_like(&self) -> bool {
        !self.on_cycle.iter().any(|&c| c)
    }

    /// Whether the graph is fully cyclic (seed Fig. 11): more than one component and no terminal node.
    pub fn is_fully_cyclic(&self) -> bool {
        self.components.len() > 1 && (0..self.components.len()).all(|c| self.degree(c) >= 2)
    }

    /// Whether component `d` lies in the subtree of `c` (is `c` or a descendant of it).
    pub fn in_subtree(&self, c: usize, mut d: usize) -> bool {
        loop {
            if d == c {
                return true;
            }
            match self.parent(d) {
                Some((p, _)) => d = p,
                None => return false,
            }
        }
    }

    /// The sub-mesh of component `c`: its vertices in `Component::vertices` order, its faces renumbered, with the
    /// model's texture coordinates and materials of those faces. Variants are edits of this mesh.
    pub fn component_model(&self, model: &Model, c: usize) -> Result<Model> {
        self.check_model(model)?;
        model.validate()?;
        let comp = self.components.get(c).ok_or_else(|| {
            Error::invalid(
                "component",
                format!("{c} is not one of the {} components", self.components.len()),
            )
        })?;
        let stale = || {
            Error::invalid(
                format!("decomposition component {c}"),
                "it lists a face the model does not have (check it with revalidate)",
            )
        };
        let mut faces = Vec::with_capacity(comp.faces.len());
        for &f in &comp.faces {
            let face = model.faces.get(f as usize).ok_or_else(stale)?;
            let mut local = Vec::with_capacity(face.len());
            for &v in face {
                local.push(comp.local_index(v).unwrap_or(0) as u32);
            }
            faces.push(local);
        }
        Ok(Model {
            vertices: comp
                .vertices
                .iter()
                .map(|&v| model.vertices.get(v as usize).copied().ok_or_else(stale))
                .collect::<Result<_>>()?,
            faces,
            uvs: model.uvs.as_ref().map(|uvs| {
                comp.faces
                    .iter()
                    .map(|&f| uvs[f as usize].clone())
                    .collect()
            }),
            materials: model
                .materials
                .as_ref()
                .map(|m| comp.faces.iter().map(|&f| m[f as usize]).collect()),
        })
    }

    /// Refuses a model other than the one decomposed (by its vertex and face counts).
    pub fn check_model(&self, model: &Model) -> Result<()> {
        if (model.vertices.len(), model.faces.len()) != self.model_size {
            return Err(Error::invalid(
                "model",
                format!(
                    "it has {} vertices and {} faces, but the decomposition was made of one with {} and {}",
                    model.vertices.len(),
                    model.faces.len(),
                    self.model_size.0,
                    self.model_size.1
                ),
            ));
        }
        Ok(())
    }
}

/// Orders a region's shared edges into chains; vertices on no shared edge become one-vertex chains.
fn chains_of(vertices: &[u32], mut edges: Vec<(u32, u32)>) -> Vec<Chain> {
    edges.sort_unstable();
    edges.dedup();
    let mut next: BTreeMap<u32, Vec<(u32, usize)>> = BTreeMap::new();
    for (k, &(a, b)) in edges.iter().enumerate() {
        next.entry(a).or_default().push((b, k));
        next.entry(b).or_default().push((a, k));
    }
    let mut used = vec![false; edges.len()];
    let mut chains = Vec::new();
    let ends: Vec<u32> = next
        .iter()
        .filter(|(_, n)| n.len() != 2)
        .map(|(&v, _)| v)
        .collect();
    let all: Vec<u32> = next.keys().copied().collect();
    for start in ends.into_iter().chain(all) {
        while let Some(first) = pick(&next, &edges, &used, start) {
            let mut chain = vec![start];
            let mut at = start;
            let mut edge = first;
            loop {
                used[edge] = true;
                let (a, b) = edges[edge];
                at = if a == at { b } else { a };
                if at == start {
                    break;
                }
                chain.push(at);
                match pick(&next, &edges, &used, at) {
                    Some(e) => edge = e,
                    None => break,
                }
            }
            let closed = at == start && chain.len() > 2;
            chains.push(Chain {
                vertices: chain,
                closed,
            });
        }
    }
    for &v in vertices {
        if !next.contains_key(&v) {
            chains.push(Chain {
                vertices: vec![v],
                closed: false,
            });
        }
    }
    chains
}

/// An unused edge at `v`, preferring one oriented away from it.
fn pick(
    next: &BTreeMap<u32, Vec<(u32, usize)>>,
    edges: &[(u32, u32)],
    used: &[bool],
    v: u32,
) -> Option<usize> {
    let list = next.get(&v)?;
    let free = || list.iter().filter(|(_, k)| !used[*k]);
    free()
        .find(|(_, k)| edges[*k].0 == v)
        .or_else(|| free().next())
        .map(|&(_, k)| k)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// A strip of three quads in a row, labelled 0, 1, 2.
    fn strip() -> (Model, Vec<u32>) {
        let mut v = Vec::new();
        for x in 0..4 {
            v.push(DVec3::new(x as f64, 0.0, 0.0));
            v.push(DVec3::new(x as f64, 1.0, 0.0));
        }
        let faces = (0..3u32)
            .map(|q| vec![2 * q, 2 * q + 2, 2 * q + 3, 2 * q + 1])
            .collect();
        (Model::new(v, faces).unwrap(), vec![0, 1, 2])
    }

    #[test]
    fn a_strip_gives_a_chain_of_three_components_with_two_regions() {
        let (m, labels) = strip();
        let d = Decomposition::from_labels(&m, &labels, Some(0)).unwrap();
        assert_eq!(d.components.len(), 3);
        assert_eq!(d.regions.len(), 2);
        assert_eq!(d.regions[0].vertices, vec![2, 3]);
        assert_eq!(d.regions[0].chains.len(), 1);
        assert_eq!(d.regions[0].chains[0].vertices, vec![2, 3]);
        assert!(d.is_tree_like());
        assert!(!d.is_fully_cyclic());
        assert_eq!(d.order(), &[0, 1, 2]);
        assert_eq!(d.parent(2), Some((1, 1)));
        let sub = d.component_model(&m, 1).unwrap();
        assert_eq!(sub.vertices.len(), 4);
        assert_eq!(sub.faces, vec![vec![0, 2, 3, 1]]);
    }

    #[test]
    fn labels_must_cover_every_face() {
        let (m, _) = strip();
        let e = Decomposition::from_labels(&m, &[], None).unwrap_err();
        assert!(e.to_string().contains("none given"), "{e}");
        let e = Decomposition::from_labels(&m, &[0, 1], None).unwrap_err();
        assert!(e.to_string().contains("2 items where 3"), "{e}");
        let e = Decomposition::from_labels(&m, &[0, 1, 1], Some(7)).unwrap_err();
        assert!(e.to_string().contains("label 7"), "{e}");
    }
}

//! The atlas of component variants (seed §4.2) and how each variant updates the graph.
//!
//! A variant F_i^k is an edit of component F_i's sub-mesh ([`super::Decomposition::component_model`]). Its vertex
//! `k < n_i` is the component's vertex `k` (the n_i vertices of [`super::Component::vertices`], in that order),
//! moved or not; vertices past n_i are new. That is how Blender keeps them when the user moves vertices, runs a
//! Lattice (FFD) or Simple Deform (axial deformation) or deletes faces only; deleting vertices renumbers them and is
//! refused by the check that the connecting-region vertices are still there. A variant face copies an original face
//! when it uses the same component vertices (the self-intersection labels follow it).
//!
//! A copy must be an edit of its own part's piece, and is refused, by name, when it is not: one with no faces left
//! (every vertex or face deleted: it would only take the part off), one with a vertex farther from the model than
//! [`MAX_REACH`] times the model's size (a typo, a piece thrown 1e30 m away), and one put in another part's
//! collection. Reading chosen for the last: a copy is another part's when more than half of its edges between the
//! piece's vertices (numbered as the piece's) are not edges of the piece; edits keep the piece's edges or add a few.
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
//! Every model once: #V ([`Atlas::count`]) counts different models, exactly, by construction (no assembly is hashed
//! to find repeats). [`Atlas::add_named_variant`] refuses, naming the copy, its part and the neighbour, a copy that
//! would only repeat models or that the assembly could not show as it was edited:
//! - one that moves its region towards the root as a solid and carries vertices off that region with the same move
//!   (more of them in place once the copy is brought back than before): a piece turned or moved whole, in Edit Mode
//!   or by an Object Mode transform read into its mesh. Bringing it back would undo the turn (the frames of §4.2.2
//!   carry what lies towards the leaves only) and leave the original. Reading chosen: refused, saying how to make
//!   the turn (keep that region, turn the rest of the piece about it); in a cycle, that no region can move. The root
//!   moved whole moves the whole model and makes no new one: refused too;
//! - one with the same shape as a variant its node holds ([`super::shape_hash`]: faces, corners to 1e-5 m, texture
//!   coordinates and materials, in any order): a copy left as it was, a copy of a copy;
//! - one that reshapes a region exactly as a copy of the neighbour across it does: both duplicated graphs would hold
//!   the models where each side is adapted to the other.
//!
//! With these, two choices of one graph differ at the first component (in assembly order) whose pick differs, placed
//! the same way, so they make different models; a duplicated graph's models differ from the others' in the region
//! its variant reshaped.
//!
//! Local cycles (§4.2.4) are in `local_cycles`.

mod local_cycles;

use super::decompose::Decomposition;
use super::frame::{fit_similarity, is_identity};
use super::model::Model;
use crate::error::{Error, Result};
use glam::{DAffine3, DVec3};
use std::collections::HashMap;

/// Distance (m, per metre from the origin past the first) within which a vertex counts as in place, and a fit as
/// solid. Blender stores positions as 32-bit floats, whose rounding is far below it.
pub(crate) const TOLERANCE: f64 = 1e-6;

/// Most repetitions a local cycle may allow.
pub(crate) const MAX_REPEAT: u32 = 64;

/// How far from the model a copy's vertices may lie, in times the model's size (its box's diagonal, 1 m at least).
pub(crate) const MAX_REACH: f64 = 100.0;

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
    /// What the user calls it (the copy's object name; the original piece is named after its component).
    pub name: String,
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
    /// Its [`super::shape_hash`] (faces, corners, texture coordinates and materials, whatever their order): two
    /// variants of one component with the same shape hash equal.
    pub shape: u64,
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
    names: Vec<String>,
    variants: Vec<Vec<Variant>>,
    graphs: Vec<AtlasGraph>,
    cycles: Vec<LocalCycle>,
}

impl Atlas {
    /// An atlas whose every node holds its original component (variant 0).
    pub fn new(model: &Model, mut decomposition: Decomposition) -> Result<Atlas> {
        model.validate()?;
        decomposition.revalidate(model)?;
        let names = (0..decomposition.components.len())
            .map(|c| format!("component {c}"))
            .collect();
        let mut atlas = Atlas {
            model: model.clone(),
            decomposition,
            names,
            variants: Vec::new(),
            graphs: Vec::new(),
            cycles: Vec::new(),
        };
        for c in 0..atlas.decomposition.components.len() {
            let sub = atlas.decomposition.component_model(model, c)?;
            let v = atlas.prepare(c, atlas.names[c].clone(), sub)?;
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

    /// Names the components as the user knows them (a part's collection): messages about a component or its copies
    /// use these names. Each original piece takes its component's name.
    pub fn set_names(&mut self, names: Vec<String>) -> Result<()> {
        crate::error::check::same_len("component names", names.len(), self.names.len())?;
        for (list, name) in self.variants.iter_mut().zip(&names) {
            if let Some(original) = list.first_mut() {
                original.name = name.clone();
            }
        }
        self.names = names;
        Ok(())
    }

    /// The name of component `c` ("component c" unless [`Atlas::set_names`] named it).
    pub fn name(&self, c: usize) -> &str {
        self.names.get(c).map_or("?", String::as_str)
    }

    /// How messages name a copy of component `c`.
    fn copy_what(&self, c: usize, name: &str) -> String {
        format!("copy '{name}' in '{}'", self.name(c))
    }

    /// Adds an edit of component `c`'s sub-mesh as a new variant called "copy k"; see [`Atlas::add_named_variant`].
    pub fn add_variant(&mut self, c: usize, edited: Model) -> Result<VariantClass> {
        let k = self.variants(c).len();
        self.add_named_variant(c, &format!("copy {k}"), edited)
    }

    /// Adds an edit of component `c`'s sub-mesh, called `name` (the copy's object), as a new variant; returns its
    /// class. Refused, with a message naming the copy and its component, when the assembly could not show it as it
    /// was edited or it would only repeat models (see the module documentation): its region towards the root moved
    /// as one solid with vertices off it (the root: the whole piece moved), the same shape as a variant the node holds
    /// already, a solid transform of a region on a cycle of the graph (§4.2.3), a reshaped end of a piece that repeats
    /// in a local cycle, a connecting region reshaped exactly as a copy of the neighbour reshapes it.
    pub fn add_named_variant(
        &mut self,
        c: usize,
        name: &str,
        edited: Model,
    ) -> Result<VariantClass> {
        self.component_checked(c)?;
        let v = self.prepare(c, name.to_string(), edited)?;
        let what = self.copy_what(c, name);
        if let Some((k, same)) = self.variants[c]
            .iter()
            .enumerate()
            .find(|(_, w)| w.shape == v.shape)
        {
            let reason = if k == 0 {
                "no vertex of it is away from the original piece (once brought back onto its connecting region \
                 towards the root), so it would only repeat the original's models; edit it or remove it"
                    .to_string()
            } else {
                format!(
                    "it has the same shape as copy '{}', so it would only repeat that copy's models; edit it or \
                     remove it",
                    same.name
                )
            };
            return Err(Error::invalid(what, reason));
        }
        let class = v.class;
        if let Some(cycle) = self.cycle_of(c) {
            if v.change(cycle.entry) != RegionChange::Untouched
                || v.change(cycle.exit) == RegionChange::Changed
            {
                return Err(Error::invalid(
                    what,
                    "the part repeats in a local cycle, so its two ends must keep their shape",
                ));
            }
        }
        if class == VariantClass::RegionChange {
            self.check_reshaped_once(c, &v, &what)?;
        }
        self.variants[c].push(v);
        self.rebuild();
        Ok(class)
    }

    /// Refuses a variant `v` of component `c` that reshapes a connecting region exactly as a variant of the
    /// neighbour across it does: each would bring a duplicated graph (§4.2.3) holding the other's models.
    fn check_reshaped_once(&self, c: usize, v: &Variant, what: &str) -> Result<()> {
        let d = &self.decomposition;
        for &(r, change) in &v.regions {
            if change != RegionChange::Changed {
                continue;
            }
            let o = d.regions[r].other(c);
            let (comp_c, comp_o) = (&d.components[c], &d.components[o]);
            let reach = d.regions[r]
                .vertices
                .iter()
                .map(|&x| self.model.vertices[x as usize].length())
                .fold(1.0, f64::max);
            let same = self.variants[o].iter().find(|w| {
                w.change(r) == RegionChange::Changed
                    && d.regions[r].vertices.iter().all(|&x| {
                        match (comp_c.local_index(x), comp_o.local_index(x)) {
                            (Some(lc), Some(lo)) => {
                                v.model.vertices[lc].distance(w.model.vertices[lo])
                                    <= TOLERANCE * reach
                            }
                            _ => false,
                        }
                    })
            });
            if let Some(w) = same {
                return Err(Error::invalid(
                    what,
                    format!(
                        "it reshapes its connecting region with '{}' exactly as copy '{}' in '{}' does, so some \
                         models would be made twice; reshape that region in one of the two parts only",
                        self.name(o),
                        w.name,
                        self.name(o)
                    ),
                ));
            }
        }
        Ok(())
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

    /// Refuses a copy (`what`) with a vertex farther from the model's box than [`MAX_REACH`] times the model's size:
    /// an edit of a piece, not a piece thrown away (a typo, a move of the whole copy). Past that the tolerances,
    /// relative to the distance from the origin, would no longer see the model.
    fn check_near_model(&self, what: &str, edited: &Model) -> Result<()> {
        let (lo, hi) = self.model.bounds();
        let size = lo.distance(hi).max(1.0);
        let far = edited
            .vertices
            .iter()
            .map(|&v| (v, v.clamp(lo, hi).distance(v)))
            .find(|&(_, d)| d > MAX_REACH * size);
        match far {
            Some((v, d)) => Err(Error::invalid(
                what,
                format!(
                    "it has a vertex at ({}, {}, {}), {} m from the model, more than {MAX_REACH} times the model's \
                     size ({size:.3} m): a copy is an edit of the piece where it lies; move it back",
                    metres(v.x),
                    metres(v.y),
                    metres(v.z),
                    metres(d)
                ),
            )),
            None => Ok(()),
        }
    }

    /// Refuses a copy (`what`) put in component `c`'s collection that is not a copy of `c`'s piece: more than half of
    /// its edges between the piece's vertices (numbered as the piece's) join vertices the piece does not join. An
    /// edit keeps the piece's edges (moves, deformers, deleted faces), or adds a few (a quad split in two keeps
    /// two thirds); a copy of another part's piece, numbered as that part, matches by chance only.
    fn check_piece_edges(&self, c: usize, what: &str, edited: &Model) -> Result<()> {
        let comp = &self.decomposition.components[c];
        let n = comp.vertices.len() as u32;
        let piece: std::collections::HashSet<(u32, u32)> = comp
            .faces
            .iter()
            .flat_map(|&f| {
                let face = &self.model.faces[f as usize];
                (0..face.len()).map(move |k| (face[k], face[(k + 1) % face.len()]))
            })
            .filter_map(|(a, b)| Some((comp.local_index(a)? as u32, comp.local_index(b)? as u32)))
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        let own: Vec<(u32, u32)> = edited
            .edge_uses()
            .into_iter()
            .map(|(e, _)| e)
            .filter(|&(a, b)| a < n && b < n)
            .collect();
        let kept = own.iter().filter(|e| piece.contains(e)).count();
        if 2 * kept >= own.len() {
            return Ok(());
        }
        Err(Error::invalid(
            what,
            format!(
                "its vertices and faces do not match the piece of '{}': only {kept} of its {} edges between the \
                 piece's vertices are edges of the piece (is it a copy of another part's piece? Each copy goes in \
                 the collection of the part it was copied from)",
                self.name(c),
                own.len()
            ),
        ))
    }

    /// Classifies an edited sub-mesh of component `c` and brings it back to its parent region. Refuses a piece moved
    /// with its region towards the root (or, the root, moved whole) and a solid transform of a region on a cycle.
    fn prepare(&self, c: usize, name: String, mut edited: Model) -> Result<Variant> {
        let what = self.copy_what(c, &name);
        self.check_copy(c, &what, &edited)?;
        let comp = &self.decomposition.components[c];
        let original: Vec<DVec3> = comp
            .vertices
            .iter()
            .map(|&v| self.model.vertices[v as usize])
            .collect();
        let reach = original.iter().map(|p| p.length()).fold(1.0, f64::max);
        let tol = TOLERANCE * reach;
        let mut regions = self.classify(c, &edited);
        let mut normalised_by = DAffine3::IDENTITY;
        match self.decomposition.parent(c) {
            Some(parent) => {
                if let Some(inverse) =
                    self.bring_back(c, &what, parent, &regions, &original, tol, &mut edited)?
                {
                    normalised_by = inverse;
                    regions = self.classify(c, &edited);
                }
            }
            None => {
                self.check_root_not_moved_whole(c, &what, &regions, &original, &edited, reach, tol)?
            }
        }
        self.check_no_solid_region_on_cycle(c, &what, &regions)?;
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
        let shape = super::assemble::shape_hash(&edited);
        Ok(Variant {
            name,
            model: edited,
            regions,
            class,
            face_origin,
            normalised_by,
            shape,
        })
    }

    /// Refuses a copy (`what`) of component `c`'s piece that is not a mesh, lost vertices or every face, lies far
    /// from the model or is a copy of another part.
    fn check_copy(&self, c: usize, what: &str, edited: &Model) -> Result<()> {
        edited
            .validate()
            .map_err(|e| super::model::error_about(e, what))?;
        let n = self.decomposition.components[c].vertices.len();
        if edited.vertices.len() < n {
            return Err(Error::invalid(
                what,
                format!(
                    "it has {} vertices but the piece has {n}: a copy keeps the piece's vertices first, in their \
                     order (move vertices or delete faces, not vertices)",
                    edited.vertices.len()
                ),
            ));
        }
        if edited.faces.is_empty() {
            return Err(Error::invalid(
                what,
                "it has no faces (every vertex or face of it deleted), so it would only take the part off the \
                 model; delete the copy, or keep the faces of the part you want it to show",
            ));
        }
        self.check_near_model(what, edited)?;
        self.check_piece_edges(c, what, edited)
    }

    /// A copy of component `c` that moves its region `pr` with its parent `p` as one solid is brought back by that
    /// solid's inverse (returned), unless that puts more of the piece's other vertices in place than it took away:
    /// then the piece itself was moved with its region, which is refused.
    #[allow(clippy::too_many_arguments)]
    fn bring_back(
        &self,
        c: usize,
        what: &str,
        (p, pr): (usize, usize),
        regions: &[(usize, RegionChange)],
        original: &[DVec3],
        tol: f64,
        edited: &mut Model,
    ) -> Result<Option<DAffine3>> {
        let Some((_, RegionChange::Solid(t))) = regions.iter().find(|(r, _)| *r == pr) else {
            return Ok(None);
        };
        let inverse = t.inverse();
        if !inverse.is_finite() {
            return Ok(None);
        }
        let d = &self.decomposition;
        let comp = &d.components[c];
        // the vertices off that region in their place, before and after bringing the copy back
        let off: Vec<usize> = (0..comp.vertices.len())
            .filter(|&k| {
                d.regions[pr]
                    .vertices
                    .binary_search(&comp.vertices[k])
                    .is_err()
            })
            .collect();
        let in_place = |m: &Model| {
            off.iter()
                .filter(|&&k| original[k].distance(m.vertices[k]) <= tol)
                .count()
        };
        let before = in_place(edited);
        for q in &mut edited.vertices {
            *q = inverse.transform_point3(*q);
        }
        let after = in_place(edited);
        if after > before {
            return Err(self.moved_with_region(what, (p, pr), after, off.len()));
        }
        Ok(Some(inverse))
    }

    /// Refuses a copy of the root component `c` that turns or moves the whole piece as one solid.
    #[allow(clippy::too_many_arguments)]
    fn check_root_not_moved_whole(
        &self,
        c: usize,
        what: &str,
        regions: &[(usize, RegionChange)],
        original: &[DVec3],
        edited: &Model,
        reach: f64,
        tol: f64,
    ) -> Result<()> {
        if regions.is_empty()
            || !regions
                .iter()
                .all(|r| matches!(r.1, RegionChange::Solid(_)))
        {
            return Ok(());
        }
        let (frame, residual) = fit_similarity(original, &edited.vertices[..original.len()]);
        if residual > tol || is_identity(&frame, reach, tol) {
            return Ok(());
        }
        let d = &self.decomposition;
        let neighbours: Vec<String> = d
            .arcs(c)
            .iter()
            .map(|&r| format!("'{}'", self.name(d.regions[r].other(c))))
            .collect();
        Err(Error::invalid(
            what,
            format!(
                "it turns or moves the whole piece as one solid, its connecting regions with {} \
                 included; the root carries every other part, so that only moves the whole model \
                 and makes no new one. Reshape the piece, or turn what lies beyond one of its \
                 connecting regions about it",
                neighbours.join(", ")
            ),
        ))
    }

    /// Refuses a copy of component `c` that moves one of its connecting regions on a cycle as a solid.
    fn check_no_solid_region_on_cycle(
        &self,
        c: usize,
        what: &str,
        regions: &[(usize, RegionChange)],
    ) -> Result<()> {
        let d = &self.decomposition;
        let Some(&(r, _)) = regions
            .iter()
            .find(|&&(r, change)| matches!(change, RegionChange::Solid(_)) && d.region_on_cycle(r))
        else {
            return Ok(());
        };
        let other = d.regions[r].other(c);
        let whole = if d.is_fully_cyclic() {
            "the parts form a ring (the component graph is fully cyclic, no terminal node), so"
        } else {
            "that region lies on a cycle of the component graph, so"
        };
        Err(Error::invalid(
            what,
            format!(
                "it turns or moves its connecting region with '{}' as a solid (a frame transform), but \
                 {whole} moving what lies beyond it would open a crack where the cycle closes (seed \
                 §4.2.3, Fig. 11); keep that region in place or reshape it",
                self.name(other)
            ),
        ))
    }

    /// The refusal of a copy (`what`) that moves its region `pr` to its parent `p` as one solid together with `with`
    /// of its `n` other vertices.
    fn moved_with_region(
        &self,
        what: &str,
        (p, pr): (usize, usize),
        with: usize,
        n: usize,
    ) -> Error {
        let d = &self.decomposition;
        let parent = self.name(p);
        let how_much = if with == n {
            "the whole piece".to_string()
        } else {
            format!("{with} of its {n} other vertices")
        };
        let advice = if d.region_on_cycle(pr) {
            let ring = if d.is_fully_cyclic() {
                "the parts form a ring"
            } else {
                "that region lies on a cycle of the parts"
            };
            format!(
                "{ring}, where no connecting region can turn or move (seed §4.2.3, Fig. 11): keep its connecting \
                 regions in place and reshape what lies between them"
            )
        } else {
            format!(
                "to turn the part, keep its connecting region with '{parent}' in place and turn the rest of the \
                 piece about it (Edit Mode)"
            )
        };
        Error::invalid(
            what,
            format!(
                "it turns or moves its connecting region with '{parent}' as one solid together with {how_much}, and \
                 the assembly keeps that region where '{parent}' has it, so the copy would come out unturned and \
                 unmoved; {advice}"
            ),
        )
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

/// A length for a message: millimetres near the model, powers of ten far from it.
fn metres(x: f64) -> String {
    if x.abs() < 1e6 {
        format!("{x:.3}")
    } else {
        format!("{x:.3e}")
    }
}

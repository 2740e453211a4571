//! Model variety: *Component-Based Model Synthesis for Low Polygonal Models* (Maréchal, Galin, Guérin, Akkouche).
//! One low-polygon model (a tree, a rock, a house) is decomposed into components joined by connecting regions
//! (§4.1), each component is edited into an atlas of variants (§4.2), and variants are assembled into new models
//! (§4.3): #V = Π #F_i different objects from Σ #F_i edited pieces (a copy that would repeat a model, or whose turn
//! the assembly would undo, is refused by name: [`atlas`]). Self-intersections that the original did not
//! have reject an assembly (§4.3). Texture variety (§5) paints details into texture components packed into atlases
//! without touching the texture coordinates.
//!
//! One concern per file: [`model`] (the mesh), [`decompose`] (components, connecting regions, graph), `frame`
//! (the least-squares frame of a region), [`atlas`] (variants and their classes, duplicated graphs, local cycles),
//! `assemble` (choices, count, welding), [`intersect`] (labels and the hierarchy of boxes), `generate` (seeded,
//! parallel), [`texture`] (§5), [`memory`] (Table 2), `assign` (which variant each painted instance shows). Each
//! says the readings it chose where the seed is vague.
//!
//! # The API the bindings call
//!
//! ```text
//! Model::new(vertices: Vec<DVec3>, faces: Vec<Vec<u32>>) -> Result<Model>
//!     .with_uvs(Vec<Vec<DVec2>>) / .with_materials(Vec<u32>) -> Result<Model>
//! Decomposition::from_labels(&model, labels: &[u32], root: Option<u32>) -> Result<Decomposition>
//!     .components / .regions / .root, .parent(c), .order(), .component_model(&model, c) -> Result<Model>
//! Atlas::new(&model, decomposition) -> Result<Atlas>            // variant 0 of each node is the original piece
//!     .set_names(Vec<String>) -> Result<()>                     // the parts as the user knows them (messages)
//!     .add_named_variant(c, name, edited: Model) -> Result<VariantClass>  // Local | SolidTransform | RegionChange
//!     .add_variant(c, edited: Model) -> Result<VariantClass>    // named "copy k"
//!     .local_cycle_candidates() -> Vec<usize>, .add_local_cycle(c, max_repeat) -> Result<()>
//!     .variants(c) -> &[Variant], .graphs() -> &[AtlasGraph], .cycles() -> &[LocalCycle]
//!     .count() -> u128                                           // #V: different models, exactly
//!     .choice(index: u128) -> Result<Choice>, .random_choice(&mut rng) -> Choice
//!     .assemble(&choice) -> Result<Assembled>  // model, face_origin, face_source, instances, max_gap, hash
//! IntersectionLabels::of_model(&model) -> IntersectionLabels   // the original's own intersections (§4.3)
//! new_intersection(&model, face_origin, &labels) -> Result<Option<(u32, u32)>>
//! generate(&atlas, &labels, &GenerateOptions { count, seed, max_attempts }) -> Result<Generation>  // count ≥ #V: all
//! AssemblyChecker::new(&atlas, &labels).check(&choice) -> Result<Result<Assembled, Rejection>>
//! check_assemblies(&atlas, &labels, &[Choice]) -> Result<Vec<Result<Assembled, Rejection>>>
//! memory_report(&atlas, &[Choice]) -> Result<MemoryReport>
//! Image::new(width, height, rgba: Vec<u8>) -> Result<Image>
//! TextureComponent::from_edit(&model, &base, &painted) -> Result<TextureComponent>
//! pack_components(&[TextureComponent]) -> Packing               // §5.2, fewest atlases
//! atlas_images(&base, &[TextureComponent], &packing) -> Vec<Image>
//! pick_textures(&[TextureComponent], &packing, face_count, probability, seed) -> Result<TextureChoice>
//! pick_texture_variants(&[TextureComponent], &packing, face_count, probability, count, seed)
//!     -> Result<Vec<TextureChoice>>                              // one choice per variant, seeded
//! ```
//!
//! A typical call from Blender: build the [`Model`] of the object, labels from its face sets, an [`Atlas`] of the
//! decomposition; for each edited copy of a component's sub-mesh call [`Atlas::add_named_variant`] (an error names
//! the copy and its part and says why it cannot be used); [`generate`] N variants with a seed; write each [`Assembled::model`] as a mesh.

mod assemble;
mod assign;
pub(crate) mod atlas;
pub(crate) mod decompose;
mod frame;
mod generate;
pub(crate) mod intersect;
pub(crate) mod memory;
pub(crate) mod model;
pub(crate) mod texture;

pub use assemble::{Assembled, Choice};
pub use assign::assign_variants;
pub use atlas::{Atlas, VariantClass};
pub use decompose::Decomposition;
pub use generate::{
    check_assemblies, check_assembly, generate, GenerateOptions, Generation, Rejection,
};
pub use intersect::{new_intersection, IntersectionLabels};
pub use memory::{memory_report, MemoryReport};
pub use model::Model;
pub use texture::{
    atlas_images, pack_components, pick_texture_variants, pick_textures, Image, TextureComponent,
};

//! Terrain that adapts: constraint-based terrain deformation (thesis 4.4.2 "Constraint-based Terrain Deformation"
//! and 5.3.3 "Terrain Deformation", after Hnaidi et al. 2010). Height *differences* `d = z − H(x, y)` between
//! wanted heights and the terrain are rasterized as constraints on the heightfield grid and diffused into a
//! displacement map `D`; the new terrain is `H' = H + D`. Because differences, not heights, are diffused, the
//! terrain keeps its fine detail.
//!
//! The diffusion solves the discrete Laplace equation with the standard 5-point stencil — each free cell is the
//! mean of its 4 neighbours, constrained cells keep their value — by multigrid. (The thesis prints the iteration
//! as the mean of `d(i, j), d(i+1, j), d(i, j+1), d(i+1, j+1)`, which is not a Laplace stencil; the standard
//! stencil is used instead.) Beyond a falloff radius the terrain stays as it was.
//!
//! | module | part |
//! |---|---|
//! | `diffusion` ([`diffuse`], [`Constraints`]) | constraints, falloff, `D` and the solver's statistics |
//! | [`rasterize`] | point, curve, gradient and level-corridor constraints (4.4.2 border constraints, 5.3.3 strokes) |
//! | `horizontal` ([`diffuse_horizontal`]) | horizontal displacement maps, diffused per channel (4.4.2 overhang constraints) |
//! | [`roads`] | roads embedded in the terrain: level carriageway, smooth grade, cut and fill banks |
//! | `junctions` | where roads meet: a later road's profile held at the earlier carriageways' heights, blended back |

mod diffusion;
mod horizontal;
mod junctions;
mod multigrid;
pub(crate) mod rasterize;
pub(crate) mod roads;

pub(crate) use diffusion::displaced;
pub(crate) use diffusion::Diffusion;
pub use diffusion::{diffuse, diffuse_jacobi, laplace_residual, Constraints, DiffusionOptions};
pub(crate) use horizontal::HorizontalDisplacement;
pub use horizontal::{diffuse_horizontal, HorizontalConstraints};
pub use roads::{
    embed_road, embed_roads, EmbeddedRoad, RoadEmbedding, RoadEmbeddingOptions, RoadProfile,
};

//! Villages on arbitrary terrain: thesis (Emilien 2014) chapter 3, "Procedural generation of villages on
//! arbitrary terrains". A growth scenario drives the coupled generation of building seeds and roads (the village
//! skeleton, 3.2), the land is then split into parcels by anisotropic conquest and each parcel gets a footprint
//! (3.3), and each footprint a house from an open shape grammar adapted to the slope (3.4).
//!
//! | module | part of chapter 3 |
//! |---|---|
//! | `land` ([`Land`], [`Environment`]) | `Ω`, `h(p)`, `w(p)`, walls on a grid |
//! | [`encyclopedia`] | the building encyclopedia and the growth scenario (3.1, 3.2.1) |
//! | [`interest`] | dynamic interest maps and the interest equation, Fig. 3.6 templates (3.2.2) |
//! | `seeding` | aggregation-based building seeding, Algorithm 1 (3.2.3) |
//! | [`roads`] | weighted anisotropic shortest path with re-use and cycles (3.2.4) |
//! | `spurs` | new dead ends no building uses, removed before the parcels (our addition to 3.2.4) |
//! | [`parcels`] | road, corner and anisotropic land conquest, simplification (3.3.1–3.3.4) |
//! | [`footprint`] | quad footprints grown from the road (3.3.5) |
//! | [`house`] | open shape grammar houses (3.4) |
//! | [`metrics`] | what a layout team checks: reachability, overlaps, grades, parcel statistics |
//! | [`figures`] | the statistics a village is compared by, real or generated (issue 42) |
//! | [`fit`] | a village type learned from a real village's figures by CMA-ES (our addition) |

pub(crate) mod encyclopedia;
pub(crate) mod figures;
pub(crate) mod fit;
pub(crate) mod footprint;
pub(crate) mod generate;
pub(crate) mod house;
pub(crate) mod interest;
mod land;
pub(crate) mod metrics;
pub(crate) mod parcels;
mod road_index;
pub(crate) mod roads;
mod seeding;
mod spurs;

pub use encyclopedia::{Encyclopedia, Scenario, ScenarioPresets};
pub use land::{Environment, Land, Site};

use glam::DVec2;
use serde::{Deserialize, Serialize};

/// A settlement seed `B_i = (B, p)` of the village skeleton.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BuildingSeed {
    /// Building type `B` (a key of the encyclopedia's `buildings`).
    pub building: String,
    /// Village type `V` in force when it was seeded.
    pub village_type: String,
    /// Where the building stands, world XY (m).
    pub position: DVec2,
}

/// A road `R_j`: the node positions of its central curve, in the plane (heights come from the terrain).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Road {
    /// The central curve's vertices, world XY (m).
    pub points: Vec<DVec2>,
}

/// A land parcel `P_i` of seed `seed`: a simple closed contour (counter-clockwise, not repeated at the end).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parcel {
    /// Index of its building seed.
    pub seed: usize,
    /// The contour's vertices, world XY (m).
    pub contour: Vec<DVec2>,
}

/// A quadrilateral building footprint `F_i ⊂ P_i`: corners counter-clockwise, `corners[0]..corners[1]` the front
/// (road side) wall.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HouseFootprint {
    /// Index of its building seed.
    pub seed: usize,
    /// The four corners, world XY (m).
    pub corners: [DVec2; 4],
}

/// Material slots of a house mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[repr(u8)]
pub enum HouseMaterial {
    /// The storeys' walls and the gable walls of the attic.
    Wall = 0,
    /// The roof: its slab and edges, a flat roof's parapet, the attic's ceiling.
    Roof = 1,
    /// Doors.
    Door = 2,
    /// Windows.
    Window = 3,
    /// The base under the ground floor, down to below the terrain, and the steps under doors.
    Foundation = 4,
}

/// The 3D geometry of one house: polygons over shared vertices (world XYZ), one material per polygon.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HouseMesh {
    /// Index of its building seed.
    pub seed: usize,
    /// Vertex positions, world XYZ (m).
    pub vertices: Vec<[f64; 3]>,
    /// Polygons as vertex indices.
    pub faces: Vec<Vec<u32>>,
    /// One per face.
    pub materials: Vec<HouseMaterial>,
}

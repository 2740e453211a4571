//! Sketch-based terrain editing from a first-person view (thesis ch. 5, after Tasse, Emilien et al. 2014): the user
//! draws the silhouettes they want to see from a camera, and the terrain is deformed so that, seen from there, its
//! silhouettes follow the strokes and nothing else hides them, while staying plausible from every other view.
//!
//! The five steps of §5.1, each in its own module:
//!
//! | module | step |
//! |---|---|
//! | [`view`] | the camera (projection to the image, rays through it) and rays cast on the heightfield |
//! | [`ordering`] | 1. strokes ordered in depth by the left-to-right sweep with T-junctions (§5.2) |
//! | [`features`] | 2. the terrain's features: silhouettes from the camera and ridges (PPA with a spanning forest, §5.3.1) |
//! | [`matching`] | 3. each stroke's priority list of deformed features, and their assignment by branch and bound (§5.3.2) |
//! | [`skyline`] | 3. the visible silhouettes per image column: the skyline under a stroke, the lowering a candidate forces |
//! | [`curves`] | 3. the strokes' 3D curves: matched features, embedded strokes, completion to the ground (§5.3.2) |
//! | [`deform`] | 4. and 5. the deformation (§5.3.3) and the lowering of protruding silhouettes (§5.4) |
//! | [`checks`] | what a sketch is checked for before any work: the frame, the camera, the work, the change |
//! | [`apply`] | the whole edit (§5.1) |
//!
//! Image coordinates are those of Blender's camera view: `x` from 0 (left) to 1 (right) and `y` from 0 (bottom)
//! to 1 (top) of the camera frame; the "altitude" of a point in the sketching plane is its `y`.

pub(crate) mod apply;
pub(crate) mod checks;
pub(crate) mod curves;
pub(crate) mod deform;
pub(crate) mod features;
pub(crate) mod matching;
pub(crate) mod ordering;
pub(crate) mod skyline;
pub(crate) mod view;

pub use view::{Camera, Sight};

use glam::{DVec2, DVec3};

/// A silhouette stroke drawn over the camera view: points in image coordinates (see the module documentation), in
/// the order they were drawn.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SketchStroke {
    /// Points `(x, y)`, 0–1 across the camera frame.
    pub points: Vec<DVec2>,
}

/// What a terrain feature is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FeatureKind {
    /// A visible silhouette of the terrain seen from the camera (§5.3.1).
    Silhouette,
    /// A ridge line of the terrain, whatever the camera (§5.3.1, PPA).
    Ridge,
}

/// A terrain feature: a polyline on the terrain's surface (world coordinates, z the height).
#[derive(Clone, Debug, PartialEq)]
pub struct Feature {
    /// Silhouette or ridge.
    pub kind: FeatureKind,
    /// Its points, in order along it.
    pub points: Vec<DVec3>,
}

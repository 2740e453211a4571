//! Element arrangement by example: *An Example-based Procedural System for Element Arrangement* (Ijiri, Měch, Igarashi,
//! Miller 2008). A small reference arrangement placed by hand is analysed into its connectivity
//! ([`ReferenceArrangement`], seed §4), a larger pattern is grown from one seed by neighbourhood matching
//! ([`grow_arrangement`], seed §5.1–5.4), and the grown pattern is relaxed towards the reference's ring shapes
//! ([`relax_arrangement`], seed §5.5).
//!
//! The matching error of a target seed's neighbourhood against a reference element's, for one matching pattern
//! f ∈ F (pairs counter-clockwise "without skipping and flipping"):
//!
//! ```text
//! error(w(e_tar), w(e_ref)) = Σ_{i,j ∈ f} w1 d(e_i^tar, e_j^ref) + w2 id(e_i^tar, e_j^ref) + w3 subid(e_i^tar, e_j^ref)   (2)
//! ERROR(w(e_tar), w(e_ref)) = min_{f ∈ F} error(w(e_tar), w(e_ref))                                             (3)
//! min_θ Σ_{i,j ∈ f} d(e_i^tar, R_θ(e_j^ref))                                                                    (4)
//! ```
//!
//! with w1 = 1, w2 = 1, w3 = 100; the relaxation solves
//!
//! ```text
//! min_x Σ_i Σ_{j ∈ w(x_i)} ‖x_j − (x_i + r_j^i)‖²      (5)      x_k = x_k^0, k ∈ constraints      (6)
//! ```
//!
//! Growth can relax the newest elements and seeds every k placed elements ([`GrowthOptions::relax_every`]): the
//! seed relaxes after each step; without it the small mismatches of each match add up into sheared patches (on a
//! lattice the rings agree exactly and there is nothing to relax).
//!
//! Built so far: the reference's connectivity with edge flips and the lattice it was placed on ([`Lattice`]), growth
//! with the non-rotation, best-fit rotation and flow-field modes ([`FlowField`], a thin-plate spline through the
//! directions of drawn strokes), seed priorities, the region and boundary curves as limits of growth, growth next to
//! existing elements ([`grow_arrangement_around`]: a paste beside an earlier pattern, the spray tool's dabs), scale and
//! rotation noise, relaxation, the arrangement as a color of the palette ([`ArrangementColor`]) painted into a scene by
//! every tool, and the figures a paste reports ([`pattern_fidelity`]). Colour noise is the caller's.
//!
//! The modules are one concern each: [`connectivity`] (analysis), `lattice` (the lattice under a near-regular
//! reference placed by hand), `options` (what a growth is asked), `flow` (the flow field), `boundary` (the boundary
//! curves' index), `cells` (the growth's grid of nodes), `matching` (the best matching element, eq. (1)–(4)),
//! `growth` (local growth), `around` (growing next to existing elements, the start, the result and its noise),
//! `existing` (the existing elements' connectivity), `relax` (relaxation), `fidelity` (a painted pattern's rings
//! and density against its reference), `color` (the arrangement as a color), `paint` (a color painted into a
//! scene). Each says the readings it chose where the seed is vague.
//!
mod around;
mod boundary;
mod cells;
mod color;
pub(crate) mod connectivity;
mod existing;
mod fidelity;
mod flow;
mod growth;
mod lattice;
mod matching;
mod options;
mod relax;

use glam::DVec2;
use serde::{Deserialize, Serialize};

pub(crate) use around::gaussian;
pub use around::{grow_arrangement, grow_arrangement_around};
pub(crate) use color::{ArrangementColor, ReferenceElement};
pub use color::{PatternRotation, DEFAULT_RELAX_EVERY};
pub use connectivity::ReferenceArrangement;
pub use fidelity::{pattern_fidelity, reference_density, PatternFidelity, RingMatch, RING_RADIUS};
pub use flow::FlowField;
pub use options::{GrowthNoise, GrowthOptions, PatternGuides, RotationMode};
pub use relax::relax_arrangement;

/// One element of an arrangement: where it stands, which symbol it is, how it is turned.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Element {
    /// The element's centre, world XY (m).
    pub position: DVec2,
    /// The symbol id (the category of the element).
    pub symbol: u32,
    /// Rotation about Z (radians, counter-clockwise).
    pub rotation: f64,
    /// Uniform scale (1 = the symbol's reference size).
    #[serde(default = "unit_scale")]
    pub scale: f64,
}

fn unit_scale() -> f64 {
    1.0
}

/// One neighbour of a grown element and where the element's reference ring puts it: `r_j^i` of eq. (5), already
/// rotated by the element's rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingTarget {
    /// The neighbour's index in [`Arrangement::elements`].
    pub neighbour: usize,
    /// Where the reference ring puts it, relative to the element (m).
    pub offset: DVec2,
}

/// A grown arrangement: its elements, their connectivity and what each copies from the reference.
#[derive(Clone, Debug, Default)]
pub struct Arrangement {
    /// The elements: the existing ones given to [`grow_arrangement_around`] first, in their order, then the new ones in
    /// the order they were placed (the initial one first).
    pub elements: Vec<Element>,
    /// For each element, the reference element (sub-id) it copies.
    pub sub_ids: Vec<usize>,
    /// The connectivity, each edge once as `(i, j)` with `i < j`, sorted.
    pub edges: Vec<(usize, usize)>,
    /// For each element, the reference ring's offsets to the neighbours it was placed with (eq. (5)'s `r_j^i`);
    /// neighbours connected later are not listed: the relaxation keeps their current offsets (seed §5.5).
    pub ring_targets: Vec<Vec<RingTarget>>,
    /// Elements the relaxation holds ([`relax_arrangement`], eq. (6)): those whose growth the region or a boundary
    /// curve stopped (a neighbour of their reference ring would have fallen outside or across), and the existing
    /// elements of [`grow_arrangement_around`].
    pub at_region_boundary: Vec<bool>,
}

impl Arrangement {
    /// Each element's neighbours (the connectivity as adjacency lists, in index order).
    pub fn neighbours(&self) -> Vec<Vec<usize>> {
        let mut adjacency = vec![Vec::new(); self.elements.len()];
        for &(i, j) in &self.edges {
            adjacency[i].push(j);
            adjacency[j].push(i);
        }
        adjacency
    }
}

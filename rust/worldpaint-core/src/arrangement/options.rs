//! How a pattern is grown: the rotation mode, the matching weights, priorities, relaxation, the flow field, the
//! boundary curves and the per-element noise, with the checks a growth makes of them before it starts.

use glam::DVec2;

use super::flow::FlowField;
use super::ReferenceArrangement;
use crate::error::{check, Error, Result};

/// The largest relative standard deviation of an element's scale: beyond it, the log-normal factor's spread is
/// no longer noise about one size.
pub(super) const MAX_SCALE_NOISE: f64 = 1.0;
/// The largest standard deviation of an element's rotation (radians): half a turn already turns elements anyhow.
pub(super) const MAX_ROTATION_NOISE: f64 = std::f64::consts::PI;
/// The largest standard deviation of an element's tint (tints are kept within ±1).
pub(super) const MAX_COLOR_NOISE: f64 = 1.0;

/// How a reference ring is turned when it is matched to a seed (seed §5.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RotationMode {
    /// The reference is used as it is: the pattern keeps the reference's orientation.
    #[default]
    None,
    /// Each match is turned by its best-fitting rotation (eq. (4), shape matching).
    BestFit,
    /// Each match is turned so that the reference's x axis follows [`GrowthOptions::flow`] at the seed.
    Flow,
}

/// The weights of eq. (2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MatchWeights {
    /// w1: distance between paired relative positions (per metre).
    pub distance: f64,
    /// w2: paired neighbours of different symbol ids.
    pub symbol: f64,
    /// w3: a paired neighbour that is a copy of the reference neighbour it is paired with.
    pub sub_id: f64,
}

impl Default for MatchWeights {
    /// The seed's values: w1 = 1, w2 = 1, w3 = 100.
    fn default() -> Self {
        MatchWeights {
            distance: 1.0,
            symbol: 1.0,
            sub_id: 100.0,
        }
    }
}

/// Per-element noise drawn after growth (seed §3: "random noises to modify the scale, rotation, and color of each
/// synthesized element"); colour noise is left to the caller.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GrowthNoise {
    /// Relative standard deviation of the scale (0 = none). The factor is log-normal with mean 1 and this relative
    /// standard deviation, so that it is never zero or negative.
    pub scale: f64,
    /// Standard deviation of a rotation added to each element (radians; 0 = none), normal.
    pub rotation: f64,
}

/// How a pattern is grown.
#[derive(Clone, Debug, PartialEq)]
pub struct GrowthOptions {
    /// How reference rings are turned.
    pub rotation: RotationMode,
    /// Growth stops once this many new elements are placed, or when no seed is left (the region is full).
    pub max_elements: usize,
    /// The seed of the run's random generator.
    pub seed: u64,
    /// The weights of eq. (2).
    pub weights: MatchWeights,
    /// Priority per symbol id (higher grows first within 5 l); unlisted symbols have 0.
    pub priorities: Vec<(u32, i32)>,
    /// The symbol the initial seed must become, if any.
    pub initial_symbol: Option<u32>,
    /// Relax (eq. (5)–(6)) the newest elements and their seeds after every this many placed elements; 0 never.
    /// The seed relaxes "after each growth step" (1); a few steps apart keep the pattern as regular for less work.
    pub relax_every: usize,
    /// The flow field that [`RotationMode::Flow`] follows (required by that mode, unused by the others).
    pub flow: Option<FlowField>,
    /// Boundary curves (seed §5.3's boundary tool), open polylines (a closed one repeats its first point at its
    /// end): no seed, element or edge crosses them.
    pub boundaries: Vec<Vec<DVec2>>,
    /// Scale and rotation noise of the new elements, drawn after growth.
    pub noise: GrowthNoise,
}

impl Default for GrowthOptions {
    fn default() -> Self {
        GrowthOptions {
            rotation: RotationMode::None,
            max_elements: crate::limits::MAX_INSTANCES as usize,
            seed: 0,
            weights: MatchWeights::default(),
            priorities: Vec::new(),
            initial_symbol: None,
            relax_every: 0,
            flow: None,
            boundaries: Vec::new(),
            noise: GrowthNoise::default(),
        }
    }
}

impl GrowthOptions {
    /// The checks a growth makes before it starts: numbers in range, the flow field there when its mode asks for
    /// it, the initial symbol one of the reference's interior elements.
    pub(crate) fn validate(&self, reference: &ReferenceArrangement) -> Result<()> {
        if self.max_elements == 0 {
            return Err(Error::invalid("max elements", "must be at least 1"));
        }
        crate::limits::check(
            "arrangement growth",
            self.max_elements as f64,
            crate::limits::MAX_INSTANCES,
            "instances",
        )?;
        check::non_negative("match weight w1", self.weights.distance)?;
        check::non_negative("match weight w2", self.weights.symbol)?;
        check::non_negative("match weight w3", self.weights.sub_id)?;
        check::within("scale noise", self.noise.scale, 0.0, MAX_SCALE_NOISE)?;
        check::within(
            "rotation noise",
            self.noise.rotation,
            0.0,
            MAX_ROTATION_NOISE,
        )?;
        if self.rotation == RotationMode::Flow && self.flow.is_none() {
            return Err(Error::invalid(
                "rotation mode",
                "the flow-field mode needs a flow field (draw flow curves first)",
            ));
        }
        if let Some(symbol) = self.initial_symbol {
            let found = (0..reference.elements().len())
                .any(|i| !reference.is_boundary(i) && reference.elements()[i].symbol == symbol);
            if !found {
                return Err(Error::unknown(
                    "symbol id among the reference's interior elements",
                    symbol.to_string(),
                ));
            }
        }
        Ok(())
    }
}

/// What guides a painted pattern (seed §5.3's tools): where it starts, the curves it must not cross, and the
/// curves whose direction it follows in the flow-field mode.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PatternGuides {
    /// Where growth starts when no element of the pattern is already around the region (None: its centre).
    pub start: Option<DVec2>,
    /// Curves (world XY polylines) no element or connectivity edge crosses: the boundary tool.
    pub boundaries: Vec<Vec<DVec2>>,
    /// Curves whose tangents, interpolated, orient the pattern when the color's rotation mode is the flow field.
    pub flow: Vec<Vec<DVec2>>,
}

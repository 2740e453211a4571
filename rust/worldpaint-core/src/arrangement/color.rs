//! The arrangement as a color of the palette: the reference a user placed by hand, the edges flipped since, and
//! how the pattern is painted (rotation mode, noise, relaxation). A color holding one paints by local growth
//! ([`super::paint`]) instead of by its statistics; its categories are the reference's symbols, in order (symbol
//! id k is the color's category k), and carry the prototypes' and scales' statistics like any color's.

use glam::DVec2;
use serde::{Deserialize, Serialize};

use super::options::{MAX_COLOR_NOISE, MAX_ROTATION_NOISE, MAX_SCALE_NOISE};
use super::{Element, ReferenceArrangement, RotationMode};
use crate::error::{check, Error, Result};
use crate::limits;

/// How a painted pattern's reference rings are turned (seed §5.3), as a color stores it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PatternRotation {
    /// The pattern keeps the reference's orientation.
    #[default]
    None,
    /// Each match is turned by its best-fitting rotation (eq. (4)).
    BestFit,
    /// The reference is turned to the flow field drawn as curves.
    Flow,
}

impl PatternRotation {
    pub(crate) fn mode(self) -> RotationMode {
        match self {
            PatternRotation::None => RotationMode::None,
            PatternRotation::BestFit => RotationMode::BestFit,
            PatternRotation::Flow => RotationMode::Flow,
        }
    }
}

/// One element of the reference as learned: where it stood, its symbol, and the instance it was.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReferenceElement {
    /// World XY where it stood (m).
    pub position: DVec2,
    /// Its symbol id: the index of its category in the color.
    pub symbol: u32,
    /// Its rotation about Z (radians).
    pub rotation: f64,
    /// Its scale; the copies of it are painted at this scale (times the scale noise).
    pub scale: f64,
    /// Which prototype model of its category it showed; its copies show the same.
    pub prototype: u32,
}

fn default_relax_every() -> usize {
    DEFAULT_RELAX_EVERY
}

/// Relaxation every this many placed elements: the seed relaxes after every step; a few steps apart give the same
/// regularity (issue 19's lattice tests) for a fraction of the work.
pub const DEFAULT_RELAX_EVERY: usize = 8;

/// What a color knows of an arrangement (seed §4): the reference and how to paint it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ArrangementColor {
    /// The reference elements, in the order the connectivity's indices (and `flips`) refer to.
    pub elements: Vec<ReferenceElement>,
    /// Edges flipped by the user after learning (seed Fig. 3), as pairs of reference indices, in order.
    #[serde(default)]
    pub flips: Vec<(usize, usize)>,
    /// How reference rings are turned.
    #[serde(default)]
    pub rotation: PatternRotation,
    /// Standard deviation of each painted element's scale, relative (0: none).
    #[serde(default)]
    pub scale_noise: f64,
    /// Standard deviation of each painted element's rotation (radians; 0: none).
    #[serde(default)]
    pub rotation_noise: f64,
    /// Standard deviation of each painted element's tint (the colour noise; the tint is kept within ±1, and a
    /// material reads it as a relative change of brightness).
    #[serde(default)]
    pub color_noise: f64,
    /// Relax the growing pattern every this many placed elements (eq. (5)–(6)); 0 relaxes only at the end.
    #[serde(default = "default_relax_every")]
    pub relax_every: usize,
}

impl ArrangementColor {
    /// The arrangement of `elements` as learned: no flip, no noise, the reference's orientation.
    pub fn new(elements: Vec<ReferenceElement>) -> Self {
        ArrangementColor {
            elements,
            flips: Vec::new(),
            rotation: PatternRotation::None,
            scale_noise: 0.0,
            rotation_noise: 0.0,
            color_noise: 0.0,
            relax_every: DEFAULT_RELAX_EVERY,
        }
    }

    /// The reference's connectivity (seed §4) with the user's flips applied.
    pub fn reference(&self) -> Result<ReferenceArrangement> {
        let elements = self
            .elements
            .iter()
            .map(|e| Element {
                position: e.position,
                symbol: e.symbol,
                rotation: e.rotation,
                scale: 1.0,
            })
            .collect();
        let mut reference = ReferenceArrangement::new(elements)?;
        for &(a, b) in &self.flips {
            reference.flip(a, b)?;
        }
        Ok(reference)
    }

    /// Flips the edge between reference elements `a` and `b` (seed Fig. 3) and records it; the color is unchanged
    /// when the edge cannot be flipped.
    pub fn flip(&mut self, a: usize, b: usize) -> Result<()> {
        let mut reference = self.reference()?;
        reference.flip(a, b)?;
        self.flips.push((a, b));
        Ok(())
    }

    /// Checks what painting relies on, for a color of `n_categories` categories; `at` names the field.
    pub(crate) fn validate(&self, n_categories: usize, at: &dyn Fn(&str) -> String) -> Result<()> {
        check::at_most_items(
            &at("arrangement.elements"),
            self.elements.len(),
            limits::MAX_INSTANCES as usize,
        )?;
        for (k, e) in self.elements.iter().enumerate() {
            let field = |f: &str| at(&format!("arrangement.elements[{k}].{f}"));
            if !e.position.is_finite() {
                return Err(Error::invalid(field("position"), "is not finite"));
            }
            check::finite(&field("rotation"), e.rotation)?;
            check::positive(&field("scale"), e.scale)?;
            if e.symbol as usize >= n_categories {
                return Err(Error::invalid(
                    field("symbol"),
                    format!(
                        "is {}, but the color has {n_categories} categories",
                        e.symbol
                    ),
                ));
            }
        }
        check::within(
            &at("arrangement.scale_noise"),
            self.scale_noise,
            0.0,
            MAX_SCALE_NOISE,
        )?;
        check::within(
            &at("arrangement.rotation_noise"),
            self.rotation_noise,
            0.0,
            MAX_ROTATION_NOISE,
        )?;
        check::within(
            &at("arrangement.color_noise"),
            self.color_noise,
            0.0,
            MAX_COLOR_NOISE,
        )?;
        self.reference()
            .map(drop)
            .map_err(|e| Error::invalid(at("arrangement"), e.reason()))
    }
}

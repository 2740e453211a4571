//! The shared types of the waterfall pipeline: the user's controllers and parameters (4.1.1, 4.2.1), and the
//! network of classified segments it makes (4.3.2).

use super::classify::{Section, WaterfallType};
use super::network::HydraulicGraph;
use crate::error::{check, Error, Result};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// The controller type `α_i` the user chooses (4.1.1: "we leave the choice of these three classes, contact,
/// free-fall, and pool, to the user").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ControllerKind {
    /// An open curve of running water on the terrain, oriented from its first point to its last.
    Contact,
    /// Water in the air, from its first point to its last.
    FreeFall,
    /// A closed flat contour; its level is the mean height of its points (the user's horizontal plane).
    Pool,
}

/// A vectorial controller `V_i` drawn by the user: its type and control points `Δ_i` (world XYZ).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Controller {
    /// Contact, free-fall or pool.
    pub kind: ControllerKind,
    /// The control points `Δ_i`, world XYZ (m): in flow order for a curve, around the contour for a pool.
    pub points: Vec<DVec3>,
    /// For a controller starting at a source (and a pool with no inflow): its flow in flow units. Where it
    /// leaves a pool or a branch: its relative share (default 1). `None`: the default flow, equal shares.
    #[serde(default)]
    pub strength: Option<f64>,
}

impl Controller {
    /// A controller with the default strength.
    pub fn new(kind: ControllerKind, points: Vec<DVec3>) -> Self {
        Controller {
            kind,
            points,
            strength: None,
        }
    }

    /// The same controller with its strength set.
    pub fn with_strength(mut self, strength: f64) -> Self {
        self.strength = Some(strength);
        self
    }
}

/// Parameters of the pipeline; the defaults are the thesis's values where it gives them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct WaterfallParams {
    /// `ω_min`, the smallest inclination (radians) of a contact segment and of a free-fall chord (4.2.1; the
    /// thesis gives no value).
    pub min_slope: f64,
    /// Control points closer than this (3D, scene units) are one connection; a curve's end within this distance
    /// of a pool's contour (horizontally, or inside it) and of its level flows into or out of the pool.
    pub snap_distance: f64,
    /// Flow of a source whose controller has no strength, in flow units (not in the thesis: a stream, the
    /// seed flow of Table 4.1's stream, horsetail and plunge).
    pub source_flow: f64,
    /// Adapt contact curves to the terrain (4.3.1; optional in the thesis).
    pub subdivide: bool,
    /// `σ` in `l = γ/σ`, the detail length of the subdivision (thesis: 1/2).
    pub sigma: f64,
    /// `w_g`, weight of the gradient cost (thesis: 1).
    pub w_gradient: f64,
    /// `w_a`, weight of the angle cost (thesis: 0.1).
    pub w_angle: f64,
    /// `w_r`, weight of the random cost (thesis: 0.2).
    pub w_random: f64,
    /// The displacement amplitude as a fraction of the segment's length (`τ = ‖u‖/2` read with `u` the segment
    /// vector, as in 4.3.2: 0.5).
    pub amplitude: f64,
    /// The midpoint search tries `2 · search_steps + 1` displacements evenly spread over `[-τ, τ]`.
    pub search_steps: usize,
    /// At most this many levels of subdivision (a bound on the work when the flow is tiny).
    pub max_levels: usize,
    /// `k` in the speed `δ = k s` (thesis: 10).
    pub speed_factor: f64,
    /// Points of the parabola drawn for a free-fall segment.
    pub fall_samples: usize,
}

impl Default for WaterfallParams {
    fn default() -> Self {
        WaterfallParams {
            min_slope: 0.01,
            snap_distance: 1.0,
            source_flow: 2.0,
            subdivide: true,
            sigma: 0.5,
            w_gradient: 1.0,
            w_angle: 0.1,
            w_random: 0.2,
            amplitude: 0.5,
            search_steps: 8,
            max_levels: 12,
            speed_factor: 10.0,
            fall_samples: 16,
        }
    }
}

impl WaterfallParams {
    /// Checks the ranges (positive slope below π/2, weights not negative, bounded search work) and says which
    /// parameter is wrong.
    pub fn validate(&self) -> Result<()> {
        let positive =
            |name: &str, v: f64| check::positive(&format!("waterfall parameter {name}"), v);
        let non_negative =
            |name: &str, v: f64| check::non_negative(&format!("waterfall parameter {name}"), v);
        positive("min_slope", self.min_slope)?;
        if !(self.min_slope < std::f64::consts::FRAC_PI_2) {
            return Err(Error::OutOfRange {
                what: "waterfall parameter min_slope".into(),
                rule: "below π/2".into(),
                value: self.min_slope,
            });
        }
        non_negative("snap_distance", self.snap_distance)?;
        positive("source_flow", self.source_flow)?;
        positive("sigma", self.sigma)?;
        non_negative("w_gradient", self.w_gradient)?;
        non_negative("w_angle", self.w_angle)?;
        non_negative("w_random", self.w_random)?;
        non_negative("amplitude", self.amplitude)?;
        positive("speed_factor", self.speed_factor)?;
        // bounds on the work a parameter can ask for: 2001 candidates per cut, 4096 cuts per control segment
        if self.search_steps > 1000 || self.max_levels > 12 || self.fall_samples > 10_000 {
            return Err(Error::invalid(
                "waterfall parameters",
                format!(
                    "search_steps = {}, max_levels = {}, fall_samples = {}: at most 1000, 12 and 10000",
                    self.search_steps, self.max_levels, self.fall_samples
                ),
            ));
        }
        check::within(
            "waterfall parameter fall_samples",
            self.fall_samples as f64,
            2.0,
            10_000.0,
        )?;
        Ok(())
    }
}

/// A waterfall segment `S_i = (u_i, γ_i, κ_i, δ_i, ε_i, ζ_i)` (4.3.2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// The hydraulic arc it belongs to.
    pub arc: usize,
    /// Contact or free-fall, from the arc's controller.
    pub kind: ControllerKind,
    /// Its points: start and end for a contact segment, the parabola for a free-fall.
    pub points: Vec<DVec3>,
    /// `s_i`, the mean inclination from start to end (radians).
    pub slope: f64,
    /// `γ_i`, the flow of its arc.
    pub flow: f64,
    /// `κ_i`, the Voronoi cell of `(s_i, γ_i)` among the seeds of Table 4.1.
    pub kind_of_water: WaterfallType,
    /// `δ_i`, `ε_i`, `ζ_i` from the triangular section.
    pub section: Section,
    /// False when the closest type belongs to the other class (a free-fall classified as a contact type or the
    /// reverse: the thesis draws such segments in red) or when no water flows.
    pub valid: bool,
}

/// The result of [`super::build_waterfall_network`]: the corrected controllers, the hydraulic graph with its flows, and
/// the waterfall network `W` as segments along each arc.
#[derive(Clone, Debug)]
pub struct WaterfallNetwork {
    /// The controllers after the minimum-slope correction (pools flattened to their level).
    pub controllers: Vec<Controller>,
    /// The hydraulic graph, with the flow of every arc and node.
    pub graph: HydraulicGraph,
    /// Per arc: the subdivided path of a contact arc or the sampled parabola of a free-fall.
    pub paths: Vec<Vec<DVec3>>,
    /// All segments, arc after arc, in path order; `segment_ranges[a]` are those of arc `a`.
    pub segments: Vec<Segment>,
    /// Per arc: the range of its segments in `segments`.
    pub segment_ranges: Vec<std::ops::Range<usize>>,
}

impl WaterfallNetwork {
    /// Segments drawn in red by the thesis: outside the valid range of their class.
    pub fn invalid_segments(&self) -> impl Iterator<Item = (usize, &Segment)> {
        self.segments.iter().enumerate().filter(|(_, s)| !s.valid)
    }
}

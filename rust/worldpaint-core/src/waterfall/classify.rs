//! The slope-flow classification of running water (thesis 4.1.1, Table 4.1, Fig. 4.3) and the segment
//! properties of the waterfall network (4.3.2).
//!
//! Type: "we use Voronoi cells, whose coordinates are detailed in Table 4.1, to determine to which type the
//! coordinates belong". The diagram's axes are not scaled in the text; here a point `(s, γ)` is compared with the
//! seeds at `(s / (π/2), log₂ γ / 3)`: the slopes of the table span `[0, π/2]` and its flows `[1, 8]` (flow units
//! are "relative proportions", so their ratios count), both mapped onto `[0, 1]`. The nearest seed wins (the
//! first in table order on a tie). Ribbon, plunge, ledge and cataract are free-fall types, the others contact
//! types; a segment whose nearest seed is of the other class keeps that type but is marked invalid ("the
//! parametric model is still set using the closest type, but the user is notified").
//!
//! Section: a closed pipe with a triangular cross-section, `γ = δ ε ζ / 2` (4.1), speed `δ = k s` with `k = 10`,
//! depth `ζ = f_d(ε, γ) = γ/2` (the thesis's only profile function), hence the width `ε = 2γ/(δ ζ) = 4/(k s)`:
//! with this profile the flow sets the depth and the slope the width. A segment without flow is dry: depth and
//! width 0.

use super::model::{ControllerKind, Segment, WaterfallParams};
use super::network::HydraulicArc;
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI};

/// `κ`, the type of a waterfall segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WaterfallType {
    /// Contact: a gentle slope with little flow (seed π/16, 2).
    Stream,
    /// Contact: a steep slope with little flow, the water staying on the rock (seed π/4, 2).
    Horsetail,
    /// Contact: a steep slope broken in steps (seed π/8, 3).
    Cascade,
    /// Contact: a gentle slope with much flow (seed π/16, 5).
    Rapid,
    /// Contact: a steep slope with much flow (seed π/4, 6).
    Block,
    /// Contact: nearly flat, with much flow (seed π/32, 5).
    River,
    /// Free-fall: a thin vertical fall (seed π/2, 1).
    Ribbon,
    /// Free-fall: a vertical fall into a pool (seed π/2, 2).
    Plunge,
    /// Free-fall: a fall over a ledge with much flow (seed π/2, 5).
    Ledge,
    /// Free-fall: the largest falls (seed π/2, 8).
    Cataract,
}

/// A row of Table 4.1: the seed `(slope, flow)` of a type in the slope-flow diagram and its visual parameters
/// (foam, rocks, disturbance, particles, all in `[0, 1]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TypeSeed {
    /// The type this row seeds.
    pub kind: WaterfallType,
    /// Mean inclination, radians.
    pub slope: f64,
    /// Flow units.
    pub flow: f64,
    /// How much foam the type shows.
    pub foam: f64,
    /// How many rocks stand in it.
    pub rocks: f64,
    /// How disturbed its surface is.
    pub disturbance: f64,
    /// How many particles (spray) it throws.
    pub particles: f64,
    /// Right of the red division of Fig. 4.3: water in the air.
    pub free_fall: bool,
}

const fn seed(
    kind: WaterfallType,
    slope: f64,
    flow: f64,
    [foam, rocks, disturbance, particles]: [f64; 4],
    free_fall: bool,
) -> TypeSeed {
    TypeSeed {
        kind,
        slope,
        flow,
        foam,
        rocks,
        disturbance,
        particles,
        free_fall,
    }
}

/// Table 4.1, in the thesis's row order.
pub const TABLE_4_1: [TypeSeed; 10] = {
    use WaterfallType::*;
    [
        seed(Ribbon, FRAC_PI_2, 1.0, [0.0, 0.3, 0.0, 0.0], true),
        seed(Plunge, FRAC_PI_2, 2.0, [1.0, 0.4, 0.0, 0.2], true),
        seed(Ledge, FRAC_PI_2, 5.0, [0.0, 0.5, 0.0, 0.5], true),
        seed(Cataract, FRAC_PI_2, 8.0, [1.0, 1.0, 1.0, 1.0], true),
        seed(Stream, PI / 16.0, 2.0, [0.0, 0.2, 0.0, 0.0], false),
        seed(River, PI / 32.0, 5.0, [0.0, 0.2, 0.1, 0.0], false),
        seed(Rapid, PI / 16.0, 5.0, [0.2, 0.5, 0.5, 0.0], false),
        seed(Cascade, PI / 8.0, 3.0, [0.5, 1.0, 1.0, 0.0], false),
        seed(Horsetail, PI / 4.0, 2.0, [1.0, 0.0, 0.0, 0.0], false),
        seed(Block, PI / 4.0, 6.0, [1.0, 0.0, 0.2, 0.0], false),
    ]
};

impl WaterfallType {
    /// Its row of Table 4.1.
    pub fn seed(self) -> &'static TypeSeed {
        // every type has a row
        match TABLE_4_1.iter().find(|s| s.kind == self) {
            Some(s) => s,
            None => &TABLE_4_1[0],
        }
    }

    /// Whether it is a free-fall type (ribbon, plunge, ledge, cataract).
    pub fn is_free_fall(self) -> bool {
        self.seed().free_fall
    }
}

/// Flows are compared on a log scale; this keeps a dry segment finite.
const SMALLEST_FLOW: f64 = 1e-9;

/// The position of `(slope, flow)` in the scaled diagram.
pub(crate) fn diagram_point(slope: f64, flow: f64) -> (f64, f64) {
    (slope / FRAC_PI_2, flow.max(SMALLEST_FLOW).log2() / 3.0)
}

/// The Voronoi cell of `(slope, flow)` among the seeds of Table 4.1.
pub fn classify_waterfall(slope: f64, flow: f64) -> WaterfallType {
    let (x, y) = diagram_point(slope, flow);
    let mut best = (f64::INFINITY, TABLE_4_1[0].kind);
    for s in &TABLE_4_1 {
        let (sx, sy) = diagram_point(s.slope, s.flow);
        let d = (x - sx).powi(2) + (y - sy).powi(2);
        if d < best.0 {
            best = (d, s.kind);
        }
    }
    best.1
}

/// Speed `δ`, width `ε` and depth `ζ` of a segment.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Section {
    /// `δ = k s`: the speed factor times the slope (radians).
    pub speed: f64,
    /// `ε = 2γ/(δ ζ)`; 0 for a dry or flat segment.
    pub width: f64,
    /// `ζ = γ/2`; 0 without flow.
    pub depth: f64,
}

/// The triangular-section model: `δ = k s`, `ζ = γ/2`, `ε = 2γ/(δ ζ)`. The slope is positive wherever the
/// minimum slope holds.
pub(crate) fn section(slope: f64, flow: f64, k: f64) -> Section {
    let speed = k * slope;
    let depth = 0.5 * flow.max(0.0);
    let width = if depth > 0.0 && speed > 0.0 {
        2.0 * flow / (speed * depth)
    } else {
        0.0
    };
    Section {
        speed,
        width,
        depth,
    }
}

/// Mean inclination from `a` to `b` (radians; π/2 for a vertical drop).
pub(crate) fn inclination(a: DVec3, b: DVec3) -> f64 {
    (a.z - b.z).atan2(a.truncate().distance(b.truncate()))
}

/// The segments of arc `a` along its path: one per path step for a contact arc, one for a free-fall.
pub(crate) fn arc_segments(
    a: usize,
    arc: &HydraulicArc,
    path: &[DVec3],
    params: &WaterfallParams,
) -> Vec<Segment> {
    let make = |points: Vec<DVec3>| {
        let slope = inclination(points[0], points[points.len() - 1]);
        let kind_of_water = classify_waterfall(slope, arc.flow);
        let class_ok = kind_of_water.is_free_fall() == (arc.kind == ControllerKind::FreeFall);
        Segment {
            arc: a,
            kind: arc.kind,
            points,
            slope,
            flow: arc.flow,
            kind_of_water,
            section: section(slope, arc.flow, params.speed_factor),
            valid: class_ok && arc.flow > 0.0 && slope > 0.0,
        }
    };
    match arc.kind {
        ControllerKind::FreeFall => vec![make(path.to_vec())],
        _ => path.windows(2).map(|s| make(s.to_vec())).collect(),
    }
}

//! Waterfall scenes, the hydraulic part: thesis (Emilien 2014) chapter 4, "Interactive procedural modeling of
//! coherent waterfall scenes", sections 4.1.1 to 4.3.2. The user draws controller curves over a terrain and marks
//! each as *contact*, *free-fall* or *pool*; the engine turns them into a consistent waterfall network:
//!
//! | module | part of chapter 4 |
//! |---|---|
//! | `network` ([`HydraulicGraph`]) | the controller network `U` as a graph, minimum-slope correction of control points (4.2.1) |
//! | [`hydraulics`] | the hydraulic graph `G`: sources, wells, branches, pools and the flow through them (4.2.2) |
//! | [`subdivide`] | midpoint-displacement subdivision of contact curves adapted to the terrain (4.3.1) |
//! | [`classify`] | Table 4.1, the slope-flow Voronoi classification and the triangular section (4.1.1, 4.3.2) |
//! | `integration` ([`WaterMesh`], [`waterfall_footprint()`]) | the integration mesh, its contour `Ω` and its footprint on the terrain grid (4.4.1) |
//! | `deform` ([`TerrainDeformation`]) | border, riverbed and overhang constraints diffused into the terrain (4.4.2) |
//! | `decoration` ([`WaterMaps`], [`Rock`]) | water, foam, rock, disturbance and speed maps; rocks along the riverbeds, synthesized from a learned rock color following the rock map (4.4.3) |
//!
//! [`build_waterfall_network`] runs the hydraulic pipeline: correction, graph, flow, subdivision, classification.
//! [`build_waterfall_scene`] runs it and then adapts the terrain to the water and makes the decoration maps.
//!
//! Readings of the thesis where it is silent or ambiguous (each module says more):
//!
//! * the minimum slope `ω_min` is an angle (Table 4.1 gives slopes as inclinations in radians); its value is not
//!   given, the default is 0.01 rad (a 1 % grade);
//! * controllers connect where a control point lies within [`WaterfallParams::snap_distance`] (3D) of another
//!   controller's control point, which stands for the magnets of the editor; contact curves are split into arcs
//!   at the control points other controllers end on;
//! * the curves are subdivided through their control polygons (the Cardinal splines are for display);
//! * a free-fall is given by its start and end (the thesis's parabola "automatically parameterized by \[its\]
//!   start and end points"): water leaves the lip horizontally and falls on a parabola with its apex there;
//! * [`Controller::strength`] is the flow of a controller that starts at a source, and its relative share where
//!   it leaves a pool or a branch (the thesis's "relative strength pre-set by the user").

pub(crate) mod classify;
mod decoration;
mod deform;
mod footprint;
pub(crate) mod hydraulics;
mod integration;
mod model;
mod network;
mod pipeline;
pub(crate) mod subdivide;

pub use classify::{WaterfallType, TABLE_4_1};
pub use decoration::{river_rock_color, Rock, ROCK_MAP};
pub(crate) use decoration::{DecorationOptions, WaterMaps};
pub(crate) use deform::{TerrainDeformation, WaterfallDeformOptions};
pub use integration::{waterfall_footprint, WaterPart, WaterfallFootprint};
pub(crate) use integration::{IntegrationOptions, WaterMesh};
pub use model::{Controller, ControllerKind, WaterfallNetwork, WaterfallParams};
pub use network::{HydraulicGraph, HydraulicNodeKind};
pub use pipeline::{
    build_waterfall_network, build_waterfall_scene, WaterfallScene, WaterfallSceneOptions,
    WaterfallSceneReport,
};

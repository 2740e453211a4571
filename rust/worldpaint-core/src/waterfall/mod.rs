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
//! | `integration` ([`WaterMesh`], [`footprint()`]) | the integration mesh, its contour `Ω` and its footprint on the terrain grid (4.4.1) |
//! | `deform` ([`TerrainDeformation`]) | border, riverbed and overhang constraints diffused into the terrain (4.4.2) |
//! | `decoration` ([`WaterMaps`], [`Rock`]) | water, foam, rock, disturbance and speed maps; rocks along the riverbeds, synthesized from a learned rock color following the rock map (4.4.3) |
//!
//! [`build`] runs the hydraulic pipeline: correction, graph, flow, subdivision, classification. [`scene`] runs it
//! and then adapts the terrain to the water and makes the decoration maps.
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

pub mod classify;
mod decoration;
mod deform;
mod footprint;
pub mod hydraulics;
mod integration;
mod network;
pub mod subdivide;

pub use classify::{Section, TypeSeed, WaterfallType, TABLE_4_1};
pub use decoration::{river_rock_color, DecorationOptions, Rock, WaterMaps, ROCK_MAP};
pub use deform::{DeformOptions, TerrainDeformation};
pub use integration::{
    footprint, Border, Footprint, FootprintNode, IntegrationOptions, PoolWater, WaterMesh,
    WaterPart,
};
pub use network::{HydraulicArc, HydraulicGraph, Node, NodeKind};

use decoration::{scatter_rocks, water_maps};
use deform::deform;
use integration::integration_mesh;

use crate::error::{check, Error, Result};
use crate::terrain::Heightfield;
use crate::terrain_edit::HorizontalDisplacement;
use glam::DVec3;
use rayon::prelude::*;
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

/// The result of [`build`]: the corrected controllers, the hydraulic graph with its flows, and the waterfall
/// network `W` as segments along each arc.
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

/// The hydraulic pipeline of chapter 4: connects and corrects the controllers (4.2.1), builds the hydraulic graph
/// and distributes the flow (4.2.2), subdivides the contact arcs on the terrain (4.3.1, seeded) and classifies
/// every segment with its speed, width and depth (4.3.2). Same input and seed give the same network whatever the
/// number of threads.
pub fn build(
    terrain: &Heightfield,
    controllers: &[Controller],
    params: &WaterfallParams,
    seed: u64,
) -> Result<WaterfallNetwork> {
    params.validate()?;
    let mut graph = HydraulicGraph::new(terrain, controllers, params)?;
    let corrected = graph.correct_slopes(controllers, params)?;
    hydraulics::distribute_flow(&mut graph, &corrected, params)?;
    let paths: Vec<Vec<DVec3>> = graph
        .arcs
        .par_iter()
        .enumerate()
        .map(|(a, arc)| match arc.kind {
            ControllerKind::Contact if params.subdivide => {
                subdivide::subdivide_arc(terrain, &arc.points, arc.flow, params, arc_seed(seed, a))
            }
            ControllerKind::FreeFall => subdivide::free_fall_path(&arc.points, params.fall_samples),
            _ => arc.points.clone(),
        })
        .collect();
    let per_arc: Vec<Vec<Segment>> = graph
        .arcs
        .par_iter()
        .zip(paths.par_iter())
        .enumerate()
        .map(|(a, (arc, path))| classify::arc_segments(a, arc, path, params))
        .collect();
    let mut segments = Vec::new();
    let mut segment_ranges = Vec::with_capacity(per_arc.len());
    for s in per_arc {
        let start = segments.len();
        segments.extend(s);
        segment_ranges.push(start..segments.len());
    }
    Ok(WaterfallNetwork {
        controllers: corrected,
        graph,
        paths,
        segments,
        segment_ranges,
    })
}

/// The seed of arc `a`'s generator: independent of the order the arcs are processed in.
fn arc_seed(seed: u64, a: usize) -> u64 {
    // SplitMix64 finaliser, so neighbouring arcs get unrelated streams
    let mut z = seed
        ^ (a as u64)
            .wrapping_add(1)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Options of the terrain and decoration stages of [`scene`].
#[derive(Clone, Debug, Default)]
pub struct SceneOptions {
    /// Widths and resolution of the integration mesh (4.4.1).
    pub integration: IntegrationOptions,
    /// How the terrain is deformed under the water (4.4.2).
    pub deform: DeformOptions,
    /// The decoration maps and the rocks (4.4.3).
    pub decoration: DecorationOptions,
}

/// Figures of a scene.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SceneReport {
    /// Source nodes of the hydraulic graph.
    pub sources: usize,
    /// Well nodes.
    pub wells: usize,
    /// Branch nodes.
    pub branches: usize,
    /// Pool nodes.
    pub pools: usize,
    /// Arcs of the hydraulic graph.
    pub arcs: usize,
    /// Waterfall segments.
    pub segments: usize,
    /// Segments outside the valid range of their class (see [`WaterfallNetwork::invalid_segments`]).
    pub invalid_segments: usize,
    /// Largest relative difference between a node's inflow and outflow.
    pub max_flow_imbalance: f64,
    /// Vertices of the integration mesh.
    pub mesh_vertices: usize,
    /// Triangles of the integration mesh.
    pub mesh_triangles: usize,
    /// Terrain nodes under water (water map above one half).
    pub water_nodes: usize,
    /// Terrain nodes with a riverbed constraint.
    pub riverbed_nodes: usize,
    /// Terrain nodes with a border (bank) constraint.
    pub border_nodes: usize,
    /// Terrain nodes with an overhang constraint.
    pub overhang_nodes: usize,
    /// Rocks scattered along the riverbeds.
    pub rocks: usize,
    /// The vertical diffusion's final residual (m).
    pub residual: f64,
    /// Whether the vertical diffusion reached its tolerance.
    pub converged: bool,
}

/// A waterfall scene: the network, its water surface, the terrain adapted to it and the decoration.
#[derive(Clone, Debug)]
pub struct WaterfallScene {
    /// The hydraulic network (4.1–4.3).
    pub network: WaterfallNetwork,
    /// The integration mesh: the water surface (4.4.1).
    pub mesh: WaterMesh,
    /// The deformed terrain, its displacement maps and constraint masks.
    pub terrain: TerrainDeformation,
    /// The decoration maps on the terrain's grid (4.4.3).
    pub maps: WaterMaps,
    /// Rocks along the riverbeds, on the deformed terrain.
    pub rocks: Vec<Rock>,
    /// Figures of the scene.
    pub report: SceneReport,
}

impl WaterfallScene {
    /// The horizontal displacement map of the overhangs.
    pub fn horizontal(&self) -> &HorizontalDisplacement {
        &self.terrain.horizontal
    }
}

/// The whole of chapter 4: [`build`] (4.1–4.3), the integration mesh (4.4.1), the terrain deformation (4.4.2),
/// the decoration maps and rocks (4.4.3). Same input and seed give the same scene whatever the number of threads.
pub fn scene(
    terrain: &Heightfield,
    controllers: &[Controller],
    params: &WaterfallParams,
    options: &SceneOptions,
    seed: u64,
) -> Result<WaterfallScene> {
    options.integration.validate()?;
    options.deform.validate()?;
    options.decoration.validate()?;
    let network = build(terrain, controllers, params, seed)?;
    let mut mesh = integration_mesh(&network, &options.integration)?;
    let print = footprint(
        terrain,
        &network,
        &mesh,
        &options.integration,
        options.deform.bank(terrain.cell),
    )?;
    let (deformed, maps) = rayon::join(
        || deform(terrain, &network, &mesh, &print, &options.deform),
        || water_maps(&network, &mesh, &print, &options.decoration),
    );
    let (deformed, maps) = (deformed?, maps?);
    // pool vertices take the pool speeds just computed
    for (v, p) in mesh.vertices.iter().enumerate() {
        if mesh.part[v] == WaterPart::Pool {
            mesh.speed[v] = maps.speed_at(p.truncate());
        }
    }
    let rocks = scatter_rocks(
        &maps,
        &deformed.terrain,
        &options.decoration,
        arc_seed(seed, usize::MAX),
    )?;
    let g = &network.graph;
    let count = |k: NodeKind| g.nodes.iter().filter(|n| n.kind == k).count();
    let report = SceneReport {
        sources: count(NodeKind::Source),
        wells: count(NodeKind::Well),
        branches: count(NodeKind::Branch),
        pools: count(NodeKind::Pool),
        arcs: g.arcs.len(),
        segments: network.segments.len(),
        invalid_segments: network.invalid_segments().count(),
        max_flow_imbalance: hydraulics::max_imbalance(g),
        mesh_vertices: mesh.vertices.len(),
        mesh_triangles: mesh.triangles.len(),
        water_nodes: maps.water.iter().filter(|w| **w > 0.5).count(),
        riverbed_nodes: deformed.riverbed_nodes,
        border_nodes: deformed.border_nodes,
        overhang_nodes: deformed.overhang_constrained.iter().filter(|b| **b).count(),
        rocks: rocks.len(),
        residual: deformed.vertical.residual,
        converged: deformed.vertical.converged,
    };
    Ok(WaterfallScene {
        network,
        mesh,
        terrain: deformed,
        maps,
        rocks,
        report,
    })
}

//! The pipeline of chapter 4: [`build_waterfall_network`] (4.1–4.3) and [`build_waterfall_scene`] (the integration
//! mesh, the terrain deformation and the decoration after it, 4.4).

use super::decoration::{scatter_rocks, water_maps};
use super::deform::deform;
use super::integration::integration_mesh;
use super::integration::{waterfall_footprint, WaterPart};
use super::model::{Controller, ControllerKind, Segment, WaterfallNetwork, WaterfallParams};
use super::network::{HydraulicGraph, HydraulicNodeKind};
use super::{classify, hydraulics, subdivide};
use super::{
    DecorationOptions, IntegrationOptions, Rock, TerrainDeformation, WaterMaps, WaterMesh,
    WaterfallDeformOptions,
};
use crate::error::Result;
use crate::terrain::Heightfield;
use crate::terrain_edit::HorizontalDisplacement;
use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The hydraulic pipeline of chapter 4: connects and corrects the controllers (4.2.1), builds the hydraulic graph
/// and distributes the flow (4.2.2), subdivides the contact arcs on the terrain (4.3.1, seeded) and classifies
/// every segment with its speed, width and depth (4.3.2). Same input and seed give the same network whatever the
/// number of threads.
pub fn build_waterfall_network(
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

/// Options of the terrain and decoration stages of [`build_waterfall_scene`].
#[derive(Clone, Debug, Default)]
pub struct WaterfallSceneOptions {
    /// Widths and resolution of the integration mesh (4.4.1).
    pub integration: IntegrationOptions,
    /// How the terrain is deformed under the water (4.4.2).
    pub deform: WaterfallDeformOptions,
    /// The decoration maps and the rocks (4.4.3).
    pub decoration: DecorationOptions,
}

/// Figures of a scene.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WaterfallSceneReport {
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
    pub report: WaterfallSceneReport,
}

impl WaterfallScene {
    /// The horizontal displacement map of the overhangs.
    pub fn horizontal(&self) -> &HorizontalDisplacement {
        &self.terrain.horizontal
    }
}

/// The whole of chapter 4: [`build_waterfall_network`] (4.1–4.3), the integration mesh (4.4.1), the terrain deformation
/// (4.4.2), the decoration maps and rocks (4.4.3). Same input and seed give the same scene whatever the number of
/// threads.
pub fn build_waterfall_scene(
    terrain: &Heightfield,
    controllers: &[Controller],
    params: &WaterfallParams,
    options: &WaterfallSceneOptions,
    seed: u64,
) -> Result<WaterfallScene> {
    options.integration.validate()?;
    options.deform.validate()?;
    options.decoration.validate()?;
    let network = build_waterfall_network(terrain, controllers, params, seed)?;
    let mut mesh = integration_mesh(&network, &options.integration)?;
    let print = waterfall_footprint(
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
    let count = |k: HydraulicNodeKind| g.nodes.iter().filter(|n| n.kind == k).count();
    let report = WaterfallSceneReport {
        sources: count(HydraulicNodeKind::Source),
        wells: count(HydraulicNodeKind::Well),
        branches: count(HydraulicNodeKind::Branch),
        pools: count(HydraulicNodeKind::Pool),
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

//! Benchmark of the hydraulic part of a waterfall scene against the requirement "a waterfall scene of 20
//! controllers end to end ≤ 2 s" (which also covers the later terrain deformation), beside a baseline measured in
//! the same run:
//!
//! * `waterfall/20_controllers`: [`build`] on `exemplar::waterfall_controllers(terrain, 20, 7)` (4 rivers of
//!   contact, free-fall, pool and contact, and 4 tributaries) over `exemplar::village_terrain` (1000 m, 1 m
//!   cells): connection and minimum-slope correction, hydraulic graph and flow, terrain-adapted subdivision,
//!   classification with speed, width and depth;
//! * baseline `waterfall/graph_and_flow`: the controller network, its correction and the flow alone (what the
//!   editor recomputes while the user drags a control point, before any subdivision).
//!
//! * `waterfall/scene_20_controllers`: [`scene`] end to end on the same scene and terrain (1 m cells, 1001 × 1001
//!   nodes): the hydraulic part, the integration mesh, the terrain deformation (border, riverbed and overhang
//!   constraints, multigrid diffusion within a 30 m falloff), the decoration maps and the rocks (the built-in
//!   river-rock color synthesized over the water's bounding rectangle).
//!
//! The summary prints the medians, their ratios, the time per stage of one run and the share of the budget.
//!
//! `cargo bench -p worldpaint-core --bench waterfall`

mod timing;

use criterion::Criterion;
use std::hint::black_box;
use std::time::{Duration, Instant};
use worldpaint_core::{
    build_waterfall_network, build_waterfall_scene, distribute_flow, village_terrain,
    waterfall_controllers, HydraulicGraph, WaterfallParams, WaterfallSceneOptions,
};

const BUDGET_S: f64 = 2.0;

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let mut g = timing::flat_group(&mut c, "waterfall", 20, Duration::from_secs(10));
    let terrain = village_terrain(1000.0, 1.0, 3);
    let controllers = waterfall_controllers(&terrain, 20, 7);
    let params = WaterfallParams::default();

    // one run stage by stage
    let t0 = Instant::now();
    let mut graph = match HydraulicGraph::new(&terrain, &controllers, &params) {
        Ok(g) => g,
        Err(e) => panic!("the benchmark scene: {e}"),
    };
    let t_graph = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let corrected = match graph.correct_slopes(&controllers, &params) {
        Ok(c) => c,
        Err(e) => panic!("the benchmark scene: {e}"),
    };
    let t_correct = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    if let Err(e) = distribute_flow(&mut graph, &corrected, &params) {
        panic!("the benchmark scene: {e}");
    }
    let t_flow = t2.elapsed().as_secs_f64();
    let t3 = Instant::now();
    let net = match build_waterfall_network(&terrain, &controllers, &params, 1) {
        Ok(n) => n,
        Err(e) => panic!("the benchmark scene: {e}"),
    };
    let t_build = t3.elapsed().as_secs_f64();
    let unsubdivided = WaterfallParams {
        subdivide: false,
        ..params.clone()
    };
    let t4 = Instant::now();
    black_box(build_waterfall_network(&terrain, &controllers, &unsubdivided, 1).ok());
    let t_plain = t4.elapsed().as_secs_f64();
    let points: usize = net.paths.iter().map(|p| p.len()).sum();
    println!(
        "{} controllers: {} nodes, {} arcs, {points} path points, {} segments ({} flagged); graph {:.2} ms, correction {:.3} ms, flow {:.3} ms; whole build {:.1} ms of which subdivision about {:.1} ms",
        controllers.len(),
        net.graph.nodes.len(),
        net.graph.arcs.len(),
        net.segments.len(),
        net.invalid_segments().count(),
        1e3 * t_graph,
        1e3 * t_correct,
        1e3 * t_flow,
        1e3 * t_build,
        1e3 * (t_build - t_plain).max(0.0)
    );

    let full_s = timing::median(&mut g, "20_controllers", || {
        let t = Instant::now();
        black_box(build_waterfall_network(&terrain, &controllers, &params, 1).ok());
        t.elapsed()
    });
    let base_s = timing::median(&mut g, "graph_and_flow", || {
        let t = Instant::now();
        if let Ok(mut graph) = HydraulicGraph::new(&terrain, &controllers, &params) {
            if let Ok(corrected) = graph.correct_slopes(&controllers, &params) {
                black_box(distribute_flow(&mut graph, &corrected, &params).ok());
            }
        }
        t.elapsed()
    });
    let options = WaterfallSceneOptions::default();
    let one = match build_waterfall_scene(&terrain, &controllers, &params, &options, 1) {
        Ok(s) => s,
        Err(e) => panic!("the benchmark scene: {e}"),
    };
    println!("scene report: {:?}", one.report);
    let scene_s = timing::median(&mut g, "scene_20_controllers", || {
        let t = Instant::now();
        black_box(build_waterfall_scene(&terrain, &controllers, &params, &options, 1).ok());
        t.elapsed()
    });
    g.finish();
    c.final_summary();

    println!();
    println!("== waterfall summary ==");
    println!(
        "20 controllers, hydraulic part end to end: {:.2} ms; graph, correction and flow alone: {:.3} ms; full / baseline = {:.0}",
        1e3 * full_s,
        1e3 * base_s,
        full_s / base_s
    );
    println!(
        "20 controllers, whole scene (hydraulics, mesh, terrain deformation, maps, rocks) on 1001 x 1001 nodes of 1 m: {:.1} ms; scene / hydraulic part = {:.2}",
        1e3 * scene_s,
        scene_s / full_s
    );
    println!(
        "requirement ≤ {BUDGET_S} s for the whole scene: the hydraulic part takes {:.4} of the budget, the whole scene {:.3}",
        full_s / BUDGET_S,
        scene_s / BUDGET_S
    );
}

//! Benchmarks of the engine, with the paper's Table 2 for scale (Fig. 1 centre: 83,209 objects of 4 categories
//! synthesized in 13.9 s on one 3.2 GHz core):
//!
//! * `synthesis/100k_3_categories`: ~100,000 instances painted on 1 km² of demo terrain from a color learned
//!   from generated exemplars (uniform trees, hard-core rocks, clustered grass; slope map);
//! * `learn_color/slope_scene`: learning the color of the 200 m slope exemplar (3 categories, slope and
//!   elevation maps), and `learn_color/slope_scene_in_*_vertices` the same inside a drawn outline of 10^4 and
//!   10^6 vertices;
//! * `paste_color/hard_core_in_*_vertices`: ~1,250 hard-core instances pasted into a wavy drawn outline of 100
//!   (the baseline), 10^4 and 10^6 vertices (radius 100 ± 5 m, 40 waves), whose cost per proposal the engine keeps
//!   from growing with the outline's detail;
//! * `terrain/from_mesh_*`: a heightfield from a 1M-triangle irregular mesh (jittered grid, rasterized) and
//!   from a 1025² regular grid mesh (used as a lattice).
//!
//! One 100k synthesis takes seconds, so that group runs the minimum criterion allows (10 samples of one run,
//! one warm-up run). After the benchmarks a summary is printed: synthesized count, time, µs per object and the
//! ratio to the paper, then the Luquillo forest report (skipped with a message when the data is absent).
//!
//! `cargo bench -p worldpaint-core --bench synthesis`

#[path = "../tests/common/mod.rs"]
mod common;
use common::forest_report;
mod timing;

use criterion::Criterion;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::cell::RefCell;
use std::hint::black_box;
use std::time::{Duration, Instant};
use worldpaint_core::{
    clustered_points, demo_terrain, hard_core_points, learn_color, slope_scene, synthesize,
    uniform_points, AnalysisOptions, Category, Color, DVec2, Heightfield, Instance, Region, Scene,
    SynthesisOptions,
};

/// Table 2, Fig. 1 (centre): objects and seconds on one 3.2 GHz core.
const PAPER_OBJECTS: f64 = 83_209.0;
const PAPER_SECONDS: f64 = 13.9;

const WORLD: f64 = 1000.0;
const EXEMPLAR: f64 = 250.0;

/// The demo terrain (1 km, 2 m cells), the color learned from its exemplar corner, and the painted region.
fn synthesis_setup() -> (Scene, Color, Region) {
    let terrain = demo_terrain(WORLD, 2.0, 3);
    let ex_region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(EXEMPLAR),
    };
    let mut instances = Vec::new();
    let mut add = |points: Vec<DVec2>, category: usize| {
        instances.extend(points.into_iter().map(|p| Instance::at(p, category)));
    };
    // 0.02 + 0.02 + 0.06 instances per m²: ~100,000 on a square kilometre
    add(uniform_points(&ex_region, 0.02, 1), 0);
    add(hard_core_points(&ex_region, 0.02, 3.0, 2), 1);
    add(clustered_points(&ex_region, 0.003, 20.0, 2.0, 3), 2);
    let mut scene = Scene {
        categories: vec![
            Category::distribution("tree", "vegetation", 0),
            Category::distribution("rock", "vegetation", 1),
            Category::distribution("grass", "vegetation", 2),
        ],
        instances,
        terrain: Some(terrain.into()),
        ..Default::default()
    };
    let opts = AnalysisOptions {
        maps: vec!["slope".into()],
        ..Default::default()
    };
    let color = match learn_color(&scene, &ex_region, "demo", &opts) {
        Ok(c) => c,
        Err(e) => panic!("learning the demo color failed: {e}"),
    };
    scene.instances.clear();
    let world = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(WORLD),
    };
    (scene, color, world)
}

/// A `side × side` grid mesh over 1 km with smooth hills; interior vertices jittered by up to ±`jitter` cells.
fn grid_mesh(side: usize, jitter: f64, seed: u64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let cell = WORLD / (side - 1) as f64;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut vertices = Vec::with_capacity(side * side);
    for j in 0..side {
        for i in 0..side {
            let (mut x, mut y) = (i as f64 * cell, j as f64 * cell);
            if jitter > 0.0 && i > 0 && j > 0 && i + 1 < side && j + 1 < side {
                x += (rng.random::<f64>() * 2.0 - 1.0) * jitter * cell;
                y += (rng.random::<f64>() * 2.0 - 1.0) * jitter * cell;
            }
            let z = 30.0 * (x / 90.0).sin() * (y / 70.0).cos() + 0.02 * x;
            vertices.push([x, y, z]);
        }
    }
    let mut triangles = Vec::with_capacity(2 * (side - 1) * (side - 1));
    for j in 0..side - 1 {
        for i in 0..side - 1 {
            let a = (j * side + i) as u32;
            let (b, c, d) = (a + 1, a + side as u32, a + side as u32 + 1);
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    }
    (vertices, triangles)
}

/// One timed 100k synthesis: (instances, seconds).
type Run = (usize, f64);

fn bench_synthesis(c: &mut Criterion, runs: &RefCell<Vec<Run>>) {
    let (scene, color, world) = synthesis_setup();
    let opts = SynthesisOptions {
        seed: 1,
        ..Default::default()
    };
    let mut group = timing::flat_group(c, "synthesis", 10, Duration::from_secs(5));
    group.warm_up_time(Duration::from_millis(1));
    group.bench_function("100k_3_categories", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let t0 = Instant::now();
                let out = synthesize(&scene, &color, &world, &opts);
                let dt = t0.elapsed();
                total += dt;
                match out {
                    Ok(out) => runs
                        .borrow_mut()
                        .push((out.instances.len(), dt.as_secs_f64())),
                    Err(e) => panic!("synthesis failed: {e}"),
                }
            }
            total
        })
    });
    group.finish();
}

/// A drawn outline of `n` vertices around `centre`: a circle of `radius` with `waves` bumps of `amplitude` metres.
fn outline(n: usize, centre: DVec2, radius: f64, waves: f64, amplitude: f64) -> Region {
    Region::Polygon {
        points: (0..n)
            .map(|k| {
                let a = k as f64 / n as f64 * std::f64::consts::TAU;
                centre + DVec2::new(a.cos(), a.sin()) * (radius + amplitude * (waves * a).sin())
            })
            .collect(),
    }
}

fn bench_learn(c: &mut Criterion) {
    let scene = slope_scene(200.0, 7);
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(200.0),
    };
    let opts = AnalysisOptions::default();
    let mut group = c.benchmark_group("learn_color");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(5));
    group.bench_function("slope_scene", |b| {
        b.iter(|| learn_color(black_box(&scene), &region, "slope", &opts))
    });
    // the same exemplar inside a drawn outline of 10^4 and 10^6 vertices (a circle of 90 m), whose cost the
    // engine bounds by simplifying outlines of more than 16,384 vertices
    for n in [10_000usize, 1_000_000] {
        let outline = outline(n, DVec2::splat(100.0), 90.0, 0.0, 0.0);
        group.bench_function(format!("slope_scene_in_{n}_vertices"), |b| {
            b.iter(|| learn_color(black_box(&scene), &outline, "slope", &opts))
        });
    }
    group.finish();
}

/// Pasting a hard-core color (density 0.04, hard core 2.5 m, learned on a 50 m square) into an empty scene inside
/// wavy outlines of 100, 10^4 and 10^6 vertices: the time a proposal's region queries add with the outline's
/// detail.
fn bench_paste_in_outline(c: &mut Criterion) {
    let square = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(50.0),
    };
    let categories = vec![Category::distribution("tree", "vegetation", 0)];
    let exemplar = Scene {
        categories: categories.clone(),
        instances: hard_core_points(&square, 0.04, 2.5, 1)
            .into_iter()
            .map(|p| Instance::at(p, 0))
            .collect(),
        ..Default::default()
    };
    let color = match learn_color(&exemplar, &square, "trees", &AnalysisOptions::default()) {
        Ok(c) => c,
        Err(e) => panic!("learning the hard-core color failed: {e}"),
    };
    let empty = Scene {
        categories,
        ..Default::default()
    };
    let opts = SynthesisOptions {
        seed: 1,
        ..Default::default()
    };
    let mut group = timing::flat_group(c, "paste_color", 10, Duration::from_secs(5));
    group.warm_up_time(Duration::from_millis(1));
    for n in [100usize, 10_000, 1_000_000] {
        let region = outline(n, DVec2::splat(200.0), 100.0, 40.0, 5.0);
        group.bench_function(format!("hard_core_in_{n}_vertices"), |b| {
            b.iter(
                || match synthesize(&empty, &color, black_box(&region), &opts) {
                    Ok(out) => out.instances.len(),
                    Err(e) => panic!("pasting into {n} vertices failed: {e}"),
                },
            )
        });
    }
    group.finish();
}

fn bench_terrain(c: &mut Criterion) {
    // 708² vertices: 2 × 707² = 999,698 triangles
    let (jv, jt) = grid_mesh(708, 0.35, 5);
    let (gv, gt) = grid_mesh(1025, 0.0, 0);
    let mut group = timing::flat_group(c, "terrain", 10, Duration::from_secs(5));
    group.warm_up_time(Duration::from_millis(500));
    group.bench_function("from_mesh_1M_triangles_jittered", |b| {
        b.iter(|| Heightfield::from_mesh(black_box(&jv), &jt, None))
    });
    group.bench_function("from_mesh_1025x1025_grid", |b| {
        b.iter(|| Heightfield::from_mesh(black_box(&gv), &gt, None))
    });
    group.finish();
}

fn summary(runs: &[Run]) {
    let paper_us = PAPER_SECONDS * 1e6 / PAPER_OBJECTS;
    println!();
    println!("== synthesis summary ==");
    if runs.is_empty() {
        println!("synthesis/100k_3_categories did not run (filtered out)");
    } else {
        let n = runs[runs.len() - 1].0;
        let mut secs: Vec<f64> = runs.iter().map(|r| r.1).collect();
        secs.sort_by(f64::total_cmp);
        let median = secs[secs.len() / 2];
        let us = median * 1e6 / n.max(1) as f64;
        println!(
            "synthesized {n} instances of 3 categories on 1 km²: median {median:.2} s over {} runs \
             (min {:.2} s, max {:.2} s), {us:.1} µs per object",
            secs.len(),
            secs[0],
            secs[secs.len() - 1]
        );
        println!(
            "paper, Table 2 (Fig. 1 centre): {PAPER_OBJECTS:.0} objects of 4 categories in {PAPER_SECONDS} s on \
             one 3.2 GHz core = {paper_us:.1} µs per object; ours / paper per object = {:.2}",
            us / paper_us
        );
    }
    println!();
    println!("== forest report ==");
    if !forest_report::data_dir().is_dir() {
        println!("skipped: {} is absent", forest_report::data_dir().display());
        return;
    }
    match forest_report::run() {
        Ok(report) => println!("{}", report.table()),
        Err(e) => println!("forest report failed: {e}"),
    }
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let listing = std::env::args().any(|a| a == "--list");
    let runs = RefCell::new(Vec::new());
    bench_synthesis(&mut c, &runs);
    bench_learn(&mut c);
    bench_paste_in_outline(&mut c);
    bench_terrain(&mut c);
    c.final_summary();
    if !listing {
        summary(&runs.borrow());
    }
}

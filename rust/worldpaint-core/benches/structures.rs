//! Benchmark of structured synthesis against the requirement "a 10 km road network (about 500 nodes) with
//! 2,000 houses along it in at most 0.5 s", beside a baseline measured in the same run:
//!
//! * `structures/roads_and_houses`: the color of a 450 m village exemplar (roads as graph paths, houses 8–15 m
//!   from them) synthesized into an 880 m square, roads and houses only (no trees), in one `synthesize` call;
//! * baseline `structures/houses_on_given_roads`: the same square with those synthesized roads already in the
//!   scene (locked paths, which synthesis keeps and conditions on), and only the houses synthesized.
//!
//! The requirement's village is denser than the exemplar (about 35 m of road per node and 80 houses per km of
//! road), so the square is sized for about 500 road nodes (about 17 km of road) and the color's house density is
//! raised to put 2,000 houses along them; everything else is as learned. The counts are printed before timing;
//! the summary prints the medians, the counts, the ratio of the full synthesis to the baseline and whether the
//! full one meets 0.5 s.
//!
//! `cargo bench -p worldpaint-core --bench structures`

mod timing;

use criterion::Criterion;
use std::hint::black_box;
use std::time::{Duration, Instant};
use worldpaint_core::{
    learn_color, synthesize, village_scene, AnalysisOptions, Color, DVec2, Graph, Region, Scene,
    SynthesisOptions, SynthesisResult,
};

const EXEMPLAR: f64 = 450.0;
const SIZE: f64 = 880.0;
const BUDGET_S: f64 = 0.5;
/// Houses per learned house: 2,000 along the roads of the square instead of about 1,300.
const HOUSE_DENSITY: f64 = 1.53;

fn square(origin: f64, size: f64) -> Region {
    Region::Rect {
        min: DVec2::splat(origin),
        max: DVec2::splat(origin + size),
    }
}

/// The village exemplar (roads, houses, trees) and its color, learned as in `tests/structures.rs`, with its house
/// density raised by `HOUSE_DENSITY`.
fn village_color() -> (Scene, Color) {
    let scene = village_scene(EXEMPLAR, 1);
    let opts = AnalysisOptions::default();
    let mut color = match learn_color(&scene, &square(0.0, EXEMPLAR), "village", &opts) {
        Ok(color) => color,
        Err(e) => panic!("learning the village color failed: {e}"),
    };
    for c in color
        .categories
        .iter_mut()
        .filter(|c| c.category.name == "house")
    {
        c.density *= HOUSE_DENSITY;
    }
    (scene, color)
}

fn options(categories: &[&str]) -> SynthesisOptions {
    SynthesisOptions {
        seed: 3,
        categories: Some(categories.iter().map(|c| c.to_string()).collect()),
        ..Default::default()
    }
}

fn run(scene: &Scene, color: &Color, dest: &Region, opts: &SynthesisOptions) -> SynthesisResult {
    match synthesize(scene, color, dest, opts) {
        Ok(out) => out,
        Err(e) => panic!("synthesizing the village failed: {e}"),
    }
}

/// Road nodes, road length in km and houses of a synthesis result.
fn counts(out: &SynthesisResult) -> (usize, f64, usize) {
    let points: Vec<&[DVec2]> = out.paths.iter().map(|p| p.points.as_slice()).collect();
    let g = Graph::from_paths(&points, 1e-6);
    let km = g.edges.iter().map(|e| g.edge_length(*e)).sum::<f64>() / 1e3;
    let house = out.categories.iter().position(|c| c.name == "house");
    let houses = out
        .instances
        .iter()
        .filter(|i| Some(i.category) == house)
        .count();
    (g.nodes.len(), km, houses)
}

/// Runs `sample` as a criterion benchmark (10 samples of one run each) and returns its median in seconds.
fn median(c: &mut Criterion, name: &str, sample: impl FnMut() -> Duration) -> f64 {
    let mut g = timing::flat_group(c, "structures", 10, Duration::from_secs(8));
    g.warm_up_time(Duration::from_millis(500));
    timing::median_alone(g, name, sample)
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let (exemplar_scene, color) = village_color();
    let dest = square(1000.0, SIZE);
    let canvas = Scene {
        categories: exemplar_scene.categories.clone(),
        ..Default::default()
    };
    let full_opts = options(&["road", "house"]);
    let houses_opts = options(&["house"]);

    // the roads of one full run, locked, as the baseline's scene
    let full = run(&canvas, &color, &dest, &full_opts);
    let mut roads = full.paths.clone();
    roads.iter_mut().for_each(|p| p.locked = true);
    let given = Scene {
        categories: full.categories.clone(),
        paths: roads,
        ..Default::default()
    };
    let (nodes, km, houses) = counts(&full);
    let baseline_houses = counts(&run(&given, &color, &dest, &houses_opts)).2;
    println!(
        "{SIZE} m square from the {EXEMPLAR} m village: {nodes} road nodes, {km:.1} km of road, {houses} houses; \
         {baseline_houses} houses on the given roads"
    );

    let time = |scene: &Scene, opts: &SynthesisOptions| {
        let t0 = Instant::now();
        black_box(run(scene, &color, &dest, opts));
        t0.elapsed()
    };
    let full_s = median(&mut c, "roads_and_houses", || time(&canvas, &full_opts));
    let base_s = median(&mut c, "houses_on_given_roads", || {
        time(&given, &houses_opts)
    });
    c.final_summary();

    println!();
    println!("== structures summary ==");
    println!(
        "roads and houses ({nodes} nodes, {km:.1} km, {houses} houses): {:.0} ms; houses on the given roads \
         ({baseline_houses} houses): {:.0} ms; full / baseline = {:.2}",
        full_s * 1e3,
        base_s * 1e3,
        full_s / base_s
    );
    println!(
        "requirement ≤ {BUDGET_S} s: {} ({:.2} of the budget)",
        if full_s <= BUDGET_S { "met" } else { "NOT met" },
        full_s / BUDGET_S
    );
}

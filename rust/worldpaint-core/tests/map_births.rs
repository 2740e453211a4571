//! Births drawn where the map preference puts the intensity, as a user checks them: a forest three times as dense
//! on the upper half of a ramp as on its lower half is painted as much denser there by both chains (the paper's
//! product model and the rdf-matching chain), within 8 %, not with the preference counted twice (for the example's
//! 2.7 : 1, 6.3 : 1 with the product model and 3.0 : 1 with the rdf chain, measured without the Hastings correction
//! of a birth proposal that already follows the preference) nor evenly; and the same seed paints the same forest.

use std::sync::Arc;
use worldpaint_core::{
    learn_color, synthesize, uniform_points, AnalysisOptions, Color, DVec2, Heightfield, Instance,
    Region, Scene, SynthesisOptions,
};

const SIDE: f64 = 200.0;

fn rect(x0: f64, x1: f64) -> Region {
    Region::Rect {
        min: DVec2::new(x0, 0.0),
        max: DVec2::new(x1, SIDE),
    }
}

/// A ramp rising 0.25 m per metre eastwards over 200 × 200 m.
fn ramp() -> Arc<Heightfield> {
    let (n, cell) = (101, 2.0);
    let heights = (0..n * n)
        .map(|k| (0.25 * cell * (k % n) as f64) as f32)
        .collect();
    Arc::new(Heightfield::new(DVec2::ZERO, cell, n, n, heights).expect("a ramp"))
}

/// The example: 0.01 trees per m² on the lower half of the ramp, 0.03 on the upper half.
fn example(terrain: &Arc<Heightfield>) -> (Scene, Vec<DVec2>) {
    let mut trees = uniform_points(&rect(0.0, 100.0), 0.01, 1);
    trees.extend(uniform_points(&rect(100.0, 200.0), 0.03, 2));
    let scene = Scene {
        categories: vec![worldpaint_core::Category::distribution(
            "tree",
            "vegetation",
            0,
        )],
        instances: trees.iter().map(|p| Instance::at(*p, 0)).collect(),
        terrain: Some(terrain.clone()),
        ..Default::default()
    };
    (scene, trees)
}

fn upper_to_lower(points: &[DVec2]) -> f64 {
    let upper = points.iter().filter(|p| p.x >= 100.0).count() as f64;
    let lower = points.iter().filter(|p| p.x < 100.0).count() as f64;
    upper / lower.max(1.0)
}

fn paint(terrain: &Arc<Heightfield>, color: &Color, product_model: bool, seed: u64) -> Vec<DVec2> {
    let out = synthesize(
        &Scene::on(terrain.clone()),
        color,
        &rect(0.0, SIDE),
        &SynthesisOptions {
            seed,
            product_model,
            ..Default::default()
        },
    )
    .expect("the paste");
    out.instances.iter().map(|i| i.position).collect()
}

#[test]
fn a_forest_three_times_as_dense_uphill_is_painted_three_times_as_dense_uphill() {
    let terrain = ramp();
    let (scene, trees) = example(&terrain);
    let wanted = upper_to_lower(&trees);
    assert!((wanted - 3.0).abs() < 0.4, "the example's ratio {wanted}");
    let color = learn_color(
        &scene,
        &rect(0.0, SIDE),
        "uphill",
        &AnalysisOptions {
            maps: vec!["elevation".into()],
            ..Default::default()
        },
    )
    .expect("the color is learned");
    for (chain, product_model) in [("product model", true), ("rdf-matching chain", false)] {
        let painted: Vec<DVec2> = (1..=5)
            .flat_map(|seed| paint(&terrain, &color, product_model, seed))
            .collect();
        let ratio = upper_to_lower(&painted);
        println!(
            "{chain}: {} trees over five seeds, upper : lower = {ratio:.2} (example {wanted:.2})",
            painted.len()
        );
        assert!(
            (ratio / wanted - 1.0).abs() <= 0.08,
            "{chain}: upper : lower = {ratio:.2}, the example's {wanted:.2}"
        );
        assert_eq!(
            paint(&terrain, &color, product_model, 3),
            paint(&terrain, &color, product_model, 3),
            "{chain}: the same seed paints the same forest"
        );
    }
}

/// A ramp rising 0.25 m per metre eastwards over 1000 × 100 m.
fn long_ramp() -> Arc<Heightfield> {
    let (nx, ny, cell) = (501, 51, 2.0);
    let heights = (0..nx * ny)
        .map(|k| (0.25 * cell * (k % nx) as f64) as f32)
        .collect();
    Arc::new(Heightfield::new(DVec2::ZERO, cell, nx, ny, heights).expect("a ramp"))
}

#[test]
fn a_forest_its_map_confines_to_a_sliver_of_the_region_gets_its_whole_count() {
    let terrain = long_ramp();
    let strip = |x0: f64, x1: f64| Region::Rect {
        min: DVec2::new(x0, 0.0),
        max: DVec2::new(x1, 100.0),
    };
    // a band of trees 3 m wide across a 200 m example: the only heights they grow at
    let trees = uniform_points(&strip(120.0, 123.0), 2.0, 4);
    let scene = Scene {
        categories: vec![worldpaint_core::Category::distribution(
            "tree",
            "vegetation",
            0,
        )],
        instances: trees.iter().map(|p| Instance::at(*p, 0)).collect(),
        terrain: Some(terrain.clone()),
        ..Default::default()
    };
    let color = learn_color(
        &scene,
        &strip(0.0, 200.0),
        "band",
        &AnalysisOptions {
            maps: vec!["elevation".into()],
            ..Default::default()
        },
    )
    .expect("the color is learned");
    // painted over five times the example: the band's heights are under 1 % of it
    for product_model in [false, true] {
        let out = synthesize(
            &Scene::on(terrain.clone()),
            &color,
            &strip(0.0, 1000.0),
            &SynthesisOptions {
                seed: 1,
                product_model,
                ..Default::default()
            },
        )
        .expect("the paste");
        let painted: Vec<DVec2> = out.instances.iter().map(|i| i.position).collect();
        println!(
            "product model {product_model}: {} trees painted for the example's {}, x {:.1}..{:.1}",
            painted.len(),
            trees.len(),
            painted.iter().map(|p| p.x).fold(f64::INFINITY, f64::min),
            painted.iter().map(|p| p.x).fold(0.0, f64::max)
        );
        assert!(
            (painted.len() as f64 / trees.len() as f64 - 1.0).abs() <= 0.05,
            "{} trees painted for the example's {}",
            painted.len(),
            trees.len()
        );
    }
}

//! The seed's Table 2 (computation times of the paper's examples, on one 3.2 GHz core), row by row, with content of
//! the same kind and count made by the engine's exemplars, timed on one thread here:
//!
//! | row | paper: m, n, seconds | here |
//! |---|---|---|
//! | Fig. 1 (centre) | 4, 83,209, 13.9 | trees, rocks and grass following the slope (`slope_scene`), pasted |
//! | Fig. 1 (right) | 3, 522, 0.16 | islands with trees and boats (`archipelago_scene`), pasted |
//! | Fig. 7 | 4, 235, 0.13 | a village of roads, houses and trees (`village_scene`), pasted |
//! | Fig. 11 | 2, 3,936, 0.71 | a linear gradient from hard-core trees to clumped bushes |
//!
//! Each row prints the objects synthesized (instances, path nodes and contours), the median time, the paper's and
//! the ratios (time, and time per object). The paper's terrain column (heightmap generation) has no counterpart.
//!
//! `cargo bench -p worldpaint-core --bench table2`

mod timing;

use criterion::Criterion;
use std::time::{Duration, Instant};
use worldpaint_core::{
    archipelago_scene, clustered_points, gradient, hard_core_points, learn_color, paste,
    slope_scene, village_scene, AnalysisOptions, Category, Color, DVec2, GradientOptions,
    GradientShape, Instance, Region, Scene, SynthesisOptions, ToolEdit,
};

fn square(min: f64, side: f64) -> Region {
    Region::Rect {
        min: DVec2::splat(min),
        max: DVec2::splat(min + side),
    }
}

fn learned(scene: &Scene, region: &Region, name: &str, opts: &AnalysisOptions) -> Color {
    match learn_color(scene, region, name, opts) {
        Ok(c) => c,
        Err(e) => panic!("learning {name}: {e}"),
    }
}

/// Objects an edit adds: instances, path nodes and contours.
fn objects(edit: &ToolEdit) -> usize {
    edit.added.len()
        + edit
            .added_paths
            .iter()
            .map(|p| p.points.len())
            .sum::<usize>()
        + edit.added_contours.len()
}

/// One row: what to paint, and the paper's figures.
struct Row {
    name: &'static str,
    paper_categories: usize,
    paper_objects: f64,
    paper_seconds: f64,
    categories: usize,
    run: Box<dyn Fn() -> ToolEdit + Send + Sync>,
}

fn pasted(scene: Scene, color: Color, region: Region) -> Box<dyn Fn() -> ToolEdit + Send + Sync> {
    Box::new(move || {
        let opts = SynthesisOptions {
            seed: 1,
            ..Default::default()
        };
        match paste(&scene, &color, &region, &opts, &|_| true) {
            Ok(e) => e,
            Err(e) => panic!("paste: {e}"),
        }
    })
}

/// Fig. 1 (centre): the slope exemplar's color over a terrain sized for about 83,209 instances.
fn forest_on_slopes() -> Row {
    let example = slope_scene(400.0, 1);
    let opts = AnalysisOptions {
        maps: vec!["slope".into()],
        ..Default::default()
    };
    let color = learned(&example, &square(0.0, 100.0), "slope forest", &opts);
    let density: f64 = color.categories.iter().map(|c| c.density).sum();
    let side = (83_209.0 / density).sqrt();
    let terrain = slope_scene(side, 2).terrain;
    let scene = Scene {
        categories: example.categories.clone(),
        terrain,
        ..Default::default()
    };
    Row {
        name: "Fig. 1 (centre)",
        paper_categories: 4,
        paper_objects: 83_209.0,
        paper_seconds: 13.9,
        categories: color.categories.len(),
        run: pasted(scene, color, square(0.0, side)),
    }
}

/// Fig. 1 (right): islands with trees (and boats) pasted over a sea sized for about 522 objects.
fn islands() -> Row {
    let example = archipelago_scene(300.0, 4);
    let color = learned(
        &example,
        &square(0.0, 300.0),
        "islands",
        &AnalysisOptions::default(),
    );
    let per_area = example.instances.len() as f64 / 90_000.0;
    let side = (522.0 / per_area).sqrt();
    let scene = Scene {
        categories: example.categories.clone(),
        ..Default::default()
    };
    Row {
        name: "Fig. 1 (right)",
        paper_categories: 3,
        paper_objects: 522.0,
        paper_seconds: 0.16,
        categories: color.categories.len(),
        run: pasted(scene, color, square(1000.0, side)),
    }
}

/// Fig. 7: a village's roads, houses and trees pasted over a region sized for about 235 objects.
fn village() -> Row {
    let example = village_scene(300.0, 5);
    let color = learned(
        &example,
        &square(0.0, 300.0),
        "village",
        &AnalysisOptions::default(),
    );
    let nodes: usize = example.paths.iter().map(|p| p.points.len()).sum();
    let per_area = (example.instances.len() + nodes) as f64 / 90_000.0;
    let side = (235.0 / per_area).sqrt();
    let scene = Scene {
        categories: example.categories.clone(),
        ..Default::default()
    };
    Row {
        name: "Fig. 7",
        paper_categories: 4,
        paper_objects: 235.0,
        paper_seconds: 0.13,
        categories: color.categories.len(),
        run: pasted(scene, color, square(1000.0, side)),
    }
}

/// Fig. 11: a linear gradient from sparse hard-core trees to clumped bushes, sized for about 3,936 objects.
fn gradient_row() -> Row {
    let ex = square(0.0, 100.0);
    let one = |name: &str, points: Vec<DVec2>| {
        let scene = Scene {
            categories: vec![Category::distribution(name, "vegetation", 0)],
            instances: points.into_iter().map(|p| Instance::at(p, 0)).collect(),
            ..Default::default()
        };
        learned(&scene, &ex, name, &AnalysisOptions::default())
    };
    let trees = one("tree", hard_core_points(&ex, 0.01, 4.0, 6));
    let bushes = one("bush", clustered_points(&ex, 0.005, 8.0, 2.0, 7));
    // the mean of the two densities over a strip three times as long as wide
    let density = 0.5 * (trees.categories[0].density + bushes.categories[0].density);
    let width = (3936.0 / density / 3.0).sqrt();
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::new(3.0 * width, width),
    };
    let shape = GradientShape::Linear {
        from: DVec2::new(0.0, width / 2.0),
        to: DVec2::new(3.0 * width, width / 2.0),
    };
    let categories = vec![
        trees.categories[0].category.clone(),
        bushes.categories[0].category.clone(),
    ];
    Row {
        name: "Fig. 11",
        paper_categories: 2,
        paper_objects: 3936.0,
        paper_seconds: 0.71,
        categories: 2,
        run: Box::new(move || {
            let scene = Scene {
                categories: categories.clone(),
                ..Default::default()
            };
            let opts = GradientOptions {
                synthesis: SynthesisOptions {
                    seed: 1,
                    ..Default::default()
                },
                ..Default::default()
            };
            match gradient(&scene, &trees, &bushes, &region, shape, &opts, &|_| true) {
                Ok(e) => e,
                Err(e) => panic!("gradient: {e}"),
            }
        }),
    }
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(p) => p,
        Err(e) => panic!("thread pool: {e}"),
    };
    let rows = [forest_on_slopes(), islands(), village(), gradient_row()];
    let mut results = Vec::new();
    for row in &rows {
        let mut g = timing::flat_group(&mut c, "table2", 10, Duration::from_secs(5));
        g.warm_up_time(Duration::from_millis(1));
        let mut n = 0;
        let secs = timing::median(&mut g, row.name, || {
            let t0 = Instant::now();
            let edit = pool.install(|| (row.run)());
            let dt = t0.elapsed();
            n = objects(&edit);
            dt
        });
        g.finish();
        results.push((n, secs));
    }
    println!();
    println!("Table 2 of the seed, one thread here against one 3.2 GHz core there:");
    println!(
        "{:<16} {:>9} {:>9} {:>9} {:>9} {:>9} {:>8} {:>14}",
        "row", "m paper", "m here", "n paper", "n here", "s paper", "s here", "per object ×"
    );
    for (row, (n, secs)) in rows.iter().zip(&results) {
        let per_object = (secs / *n.max(&1) as f64) / (row.paper_seconds / row.paper_objects);
        println!(
            "{:<16} {:>9} {:>9} {:>9.0} {:>9} {:>9.2} {:>8.3} {:>14.2}",
            row.name,
            row.paper_categories,
            row.categories,
            row.paper_objects,
            n,
            row.paper_seconds,
            secs,
            per_object
        );
    }
}

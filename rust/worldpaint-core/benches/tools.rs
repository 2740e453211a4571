//! Benchmarks of the painting tools, each beside a baseline measured in the same run:
//!
//! * `brush/first_dab_r20`: the first dab of a stroke, radius 20 m, in a color of one tree per 25 m² (about 50 new
//!   trees) among existing trees around it; `brush/next_dab_r20`: a dab 10 m further (half the radius), beside the
//!   first; baseline `brush/paste_disc_r20`: the same disc pasted in one synthesis call.
//! * `move/5000_one_step`: a region of about 5,000 trees, rocks and grass of the slope scene (trees only on
//!   20–35° slopes) moved 5 m across the slopes, so that many trees have to find new places; baseline
//!   `move/paste_5000`: the same region pasted anew with the same color.
//!
//! A summary prints the medians and the ratios to the baselines.
//!
//! `cargo bench -p worldpaint-core --bench tools`

mod timing;

use criterion::Criterion;
use std::hint::black_box;
use std::time::{Duration, Instant};
use worldpaint_core::{
    demo_terrain, hard_core_points, learn_color, move_region, paste, slope_scene, AdaptOptions,
    AnalysisOptions, BrushMode, BrushOptions, BrushStroke, Category, Color, DVec2, Instance,
    Region, Scene, SynthesisOptions,
};

const WORLD: f64 = 600.0;
const RADIUS: f64 = 20.0;

/// Hills, and a hard-core color of one tree per 25 m² (3 m apart) learned with its slope preference.
fn hills_and_color() -> (Scene, Color) {
    let terrain = demo_terrain(WORLD, 2.0, 7);
    let corner = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(100.0),
    };
    let scene = Scene {
        categories: vec![Category::distribution("tree", "vegetation", 0)],
        instances: hard_core_points(&corner, 0.04, 3.0, 1)
            .into_iter()
            .map(|p| Instance::at(p, 0))
            .collect(),
        terrain: Some(terrain.into()),
        ..Default::default()
    };
    let opts = AnalysisOptions {
        maps: vec!["slope".into()],
        ..Default::default()
    };
    match learn_color(&scene, &corner, "trees", &opts) {
        Ok(color) => (scene, color),
        Err(e) => panic!("learning the bench color failed: {e}"),
    }
}

/// Trees everywhere on the hills but in a 60 m wide corridor along y = 300, where the brush goes.
fn forest_around_a_corridor(scene: &Scene) -> Scene {
    let world = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(WORLD),
    };
    Scene {
        instances: hard_core_points(&world, 0.04, 3.0, 2)
            .into_iter()
            .filter(|p| (p.y - 300.0).abs() > 30.0)
            .map(|p| Instance::at(p, 0))
            .collect(),
        ..scene.clone()
    }
}

fn brush_options() -> BrushOptions {
    BrushOptions {
        radius: RADIUS,
        synthesis: SynthesisOptions {
            seed: 1,
            ..Default::default()
        },
        ..Default::default()
    }
}

fn median(c: &mut Criterion, group: &str, name: &str, sample: impl FnMut() -> Duration) -> f64 {
    let mut g = c.benchmark_group(group);
    g.sample_size(30)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(3));
    timing::median_alone(g, name, sample)
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let (exemplar_scene, color) = hills_and_color();
    let scene = forest_around_a_corridor(&exemplar_scene);
    let centre = DVec2::new(300.0, 300.0);
    let disc = Region::Circle {
        center: centre,
        radius: RADIUS,
    };
    let paint = BrushMode::Paint(Box::new(color.clone()));
    let opts = SynthesisOptions {
        seed: 1,
        ..Default::default()
    };

    let paste_disc = median(&mut c, "brush", "paste_disc_r20", || {
        let t0 = Instant::now();
        black_box(paste(&scene, &color, &disc, &opts, &|_| true).ok());
        t0.elapsed()
    });
    let first_dab = median(&mut c, "brush", "first_dab_r20", || {
        let mut stroke = match BrushStroke::new(&scene, paint.clone(), brush_options()) {
            Ok(s) => s,
            Err(e) => panic!("stroke: {e}"),
        };
        let t0 = Instant::now();
        black_box(stroke.move_to(centre).ok());
        t0.elapsed()
    });
    let next_dab = median(&mut c, "brush", "next_dab_r20", || {
        let mut stroke = match BrushStroke::new(&scene, paint.clone(), brush_options()) {
            Ok(s) => s,
            Err(e) => panic!("stroke: {e}"),
        };
        let _ = stroke.move_to(centre);
        let t0 = Instant::now();
        black_box(stroke.move_to(centre + DVec2::new(0.5 * RADIUS, 0.0)).ok());
        t0.elapsed()
    });
    let new_in_first = {
        let mut stroke = BrushStroke::new(&scene, paint.clone(), brush_options()).ok();
        stroke
            .as_mut()
            .map(|s| {
                let _ = s.move_to(centre);
                s.edit().added.len()
            })
            .unwrap_or(0)
    };

    // move: about 5,000 instances of the slope scene (period 200 m across X), 5 m across the slopes
    let slopes = slope_scene(800.0, 3);
    let learn = AnalysisOptions {
        maps: vec!["slope".into()],
        ..Default::default()
    };
    let one_period = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(200.0),
    };
    let slope_color = match learn_color(&slopes, &one_period, "slope forest", &learn) {
        Ok(c) => c,
        Err(e) => panic!("learning the slope color failed: {e}"),
    };
    let square = Region::Rect {
        min: DVec2::new(215.0, 215.0),
        max: DVec2::new(590.0, 590.0),
    };
    let moved_scene = slopes;
    let color = slope_color;
    let adapt = AdaptOptions {
        seed: 1,
        ..Default::default()
    };
    let mut last = None;
    let move_step = median(&mut c, "move", "5000_one_step", || {
        let t0 = Instant::now();
        let out = move_region(
            &moved_scene,
            Some(&color),
            &square,
            DVec2::new(5.0, 0.0),
            &adapt,
        );
        let dt = t0.elapsed();
        last = out.ok();
        dt
    });
    let paste_square = median(&mut c, "move", "paste_5000", || {
        let t0 = Instant::now();
        black_box(paste(&moved_scene, &color, &square, &opts, &|_| true).ok());
        t0.elapsed()
    });
    c.final_summary();

    println!();
    println!("== painting tools summary ==");
    println!(
        "brush dab r = {RADIUS} m, 1 tree / 25 m²: first dab {:.2} ms ({new_in_first} new trees), next dab {:.2} ms; \
         pasting the same disc {:.2} ms (first dab / paste = {:.2})",
        first_dab * 1e3,
        next_dab * 1e3,
        paste_disc * 1e3,
        first_dab / paste_disc
    );
    if let Some(m) = last {
        println!(
            "move {} instances 5 m across the slopes: {:.1} ms ({} adapted, {} replaced); pasting the region anew {:.1} ms \
             (move / paste = {:.2})",
            m.moved,
            move_step * 1e3,
            m.displaced,
            m.reborn,
            paste_square * 1e3,
            move_step / paste_square
        );
    }
}

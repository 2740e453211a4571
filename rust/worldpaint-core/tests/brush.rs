//! Brush strokes (Section 5.3): a stroke of dabs paints the color's statistics along its whole length with no
//! seam between the dabs; alpha thins the color over bare ground; the eraser removes only what it should.

use worldpaint_core::{
    compare, demo_terrain, hard_core_points, learn_color, uniform_points, AnalysisOptions,
    BrushMode, BrushOptions, BrushStroke, Category, CategoryKind, Color, DVec2, Falloff, Instance,
    Path, Region, Scene, SynthesisOptions,
};

const RADIUS: f64 = 20.0;

/// A hilly terrain to paint on, and a hard-core color (3 m, 0.04 per m²) learned from an exemplar without terrain
/// (so it has no slope preference of its own that the hills could favour or not).
fn hard_core_on_hills() -> (Scene, Color) {
    let exemplar_region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(100.0),
    };
    let points = hard_core_points(&exemplar_region, 0.04, 3.0, 11);
    let exemplar = Scene {
        categories: vec![Category::distribution("tree", "vegetation", 0)],
        instances: points.iter().map(|p| Instance::at(*p, 0)).collect(),
        terrain: None,
        ..Default::default()
    };
    let color = learn_color(
        &exemplar,
        &exemplar_region,
        "hard core",
        &Default::default(),
    )
    .unwrap();
    let canvas = Scene {
        instances: Vec::new(),
        terrain: Some(demo_terrain(600.0, 2.0, 7).into()),
        ..exemplar
    };
    (canvas, color)
}

/// A gently curving path of `n` points from (120, 300) eastwards, one every 5 m.
fn path(n: usize) -> Vec<DVec2> {
    (0..n)
        .map(|k| {
            let x = 120.0 + 5.0 * k as f64;
            DVec2::new(x, 300.0 + 15.0 * (x / 120.0).sin())
        })
        .collect()
}

fn smallest_distance(points: &[DVec2]) -> f64 {
    let mut best = f64::INFINITY;
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            best = best.min(a.distance(*b));
        }
    }
    best
}

fn options(seed: u64) -> BrushOptions {
    BrushOptions {
        radius: RADIUS,
        synthesis: SynthesisOptions {
            seed,
            ..Default::default()
        },
        ..Default::default()
    }
}

#[test]
fn a_stroke_of_forty_dabs_paints_the_color_without_seams() {
    let (canvas, color) = hard_core_on_hills();
    let mut stroke = BrushStroke::new(
        &canvas,
        BrushMode::Paint(Box::new(color.clone())),
        options(3),
    )
    .unwrap();
    // 40 dabs every 10 m (spacing 0.5 × radius)
    let dabs = stroke.follow(&path(79), &|_| true).unwrap();
    assert_eq!(dabs, 40);
    let painted = stroke.edit().applied_to(&canvas);
    let points: Vec<DVec2> = painted.instances.iter().map(|i| i.position).collect();
    let closest = smallest_distance(&points);
    println!(
        "{} instances over 40 dabs; closest pair {closest:.3} m (exemplar minimum {:.3} m)",
        points.len(),
        color.categories[0].min_distance
    );
    assert!(closest >= color.categories[0].min_distance - 1e-9);

    // along the whole stroke: four stretches of the band within 10 m of the path, each at the color's density
    let half_width = 0.5 * RADIUS;
    let along = |x0: f64, x1: f64| {
        let poly = |side: f64| -> Vec<DVec2> {
            (0..=20)
                .map(|k| {
                    let x = x0 + (x1 - x0) * k as f64 / 20.0;
                    DVec2::new(x, 300.0 + 15.0 * (x / 120.0).sin() + side)
                })
                .collect()
        };
        let mut points = poly(-half_width);
        points.extend(poly(half_width).into_iter().rev());
        Region::Polygon { points }
    };
    for k in 0..4 {
        let x0 = 120.0 + RADIUS + 85.0 * k as f64;
        let band = along(x0, x0 + 85.0);
        let n = points.iter().filter(|p| band.contains(**p)).count() as f64;
        let ratio = n / (band.area() * color.categories[0].density);
        println!("stretch {k}: density ratio {ratio:.3}");
        assert!(
            (ratio - 1.0).abs() <= 0.15,
            "stretch {k}: density ratio {ratio:.3}"
        );
    }

    // the pair statistics of the whole band against those of a second draw of the exemplar's process
    let band = along(120.0 + RADIUS, 120.0 + 390.0 - RADIUS);
    let same_bins = AnalysisOptions {
        bin_width: Some(color.bin_width),
        max_radius: Some(color.max_radius),
        maps: vec!["slope".into()],
        ..Default::default()
    };
    // (the painted color is learned with the terrain's slope map, which the reference color does not compare)
    let stroke_color = learn_color(&painted, &band, "stroke", &same_bins).unwrap();
    let second = Scene {
        instances: hard_core_points(&band, 0.04, 3.0, 99)
            .into_iter()
            .map(|p| Instance::at(p, 0))
            .collect(),
        ..canvas.clone()
    };
    let second_color = learn_color(&second, &band, "second", &same_bins).unwrap();
    let synth = compare(&color, &stroke_color).max_rdf_l2();
    let reference = compare(&color, &second_color).max_rdf_l2();
    println!("rdf L2 along the stroke {synth:.4}, second draw in the same band {reference:.4}");
    assert!(synth <= 1.5 * reference);
}

#[test]
fn an_alpha_brush_thins_the_color_over_bare_ground() {
    let (canvas, color) = hard_core_on_hills();
    let density = color.categories[0].density;
    let count_within = |scene: &Scene, path: &[DVec2], r: f64| {
        scene
            .instances
            .iter()
            .filter(|i| {
                path.windows(2)
                    .any(|w| worldpaint_core::segment_distance(i.position, w[0], w[1]) <= r)
            })
            .count() as f64
    };
    let straight: Vec<DVec2> = (0..=60)
        .map(|k| DVec2::new(150.0 + 5.0 * k as f64, 200.0))
        .collect();
    // the painted area: a capsule of radius R around a 300 m segment, minus its rounded ends
    let inner = |r: f64| Region::Rect {
        min: DVec2::new(150.0 + RADIUS, 200.0 - r),
        max: DVec2::new(450.0 - RADIUS, 200.0 + r),
    };
    let mut half = options(5);
    half.opacity = 0.5;
    let mut stroke =
        BrushStroke::new(&canvas, BrushMode::Paint(Box::new(color.clone())), half).unwrap();
    stroke.follow(&straight, &|_| true).unwrap();
    let painted = stroke.edit().applied_to(&canvas);
    let region = inner(RADIUS);
    let n = painted
        .instances
        .iter()
        .filter(|i| region.contains(i.position))
        .count() as f64;
    let ratio = n / (region.area() * density);
    println!("opacity 0.5: density ratio {ratio:.3}");
    assert!(
        (ratio - 0.5).abs() <= 0.1,
        "opacity 0.5 gave density ratio {ratio:.3}"
    );

    // a smooth falloff: denser near the path than near the brush's edge
    let mut soft = options(6);
    soft.falloff = Falloff::Smooth;
    let mut stroke = BrushStroke::new(&canvas, BrushMode::Paint(Box::new(color)), soft).unwrap();
    stroke.follow(&straight, &|_| true).unwrap();
    let painted = stroke.edit().applied_to(&canvas);
    let core = count_within(&painted, &straight, RADIUS / 3.0);
    let all = count_within(&painted, &straight, RADIUS);
    let core_density = core / (2.0 * RADIUS / 3.0 * 300.0);
    let rim_density = (all - core) / (2.0 * 2.0 * RADIUS / 3.0 * 300.0);
    println!(
        "smooth falloff: density near the path {core_density:.4}, near the edge {rim_density:.4}"
    );
    assert!(core_density > 1.5 * rim_density);
}

#[test]
fn the_eraser_removes_unlocked_instances_of_its_categories_near_the_path() {
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(200.0),
    };
    let mut instances: Vec<Instance> = uniform_points(&region, 0.02, 1)
        .into_iter()
        .map(|p| Instance::at(p, 0))
        .collect();
    instances.extend(
        uniform_points(&region, 0.02, 2)
            .into_iter()
            .map(|p| Instance::at(p, 1)),
    );
    for i in instances.iter_mut().step_by(10) {
        i.locked = true;
    }
    let scene = Scene {
        categories: vec![
            Category::distribution("tree", "vegetation", 0),
            Category::distribution("rock", "vegetation", 1),
        ],
        instances,
        terrain: None,
        ..Default::default()
    };
    let path = [
        DVec2::new(20.0, 100.0),
        DVec2::new(180.0, 100.0),
        DVec2::new(180.0, 20.0),
    ];
    let mode = BrushMode::Erase(Some(vec!["rock".into()]));
    let mut stroke = BrushStroke::new(&scene, mode, options(0)).unwrap();
    stroke.follow(&path, &|_| true).unwrap();
    let edit = stroke.edit();
    assert!(edit.added.is_empty());
    let near = |p: DVec2| {
        path.windows(2)
            .any(|w| worldpaint_core::segment_distance(p, w[0], w[1]) <= RADIUS)
    };
    let expected: Vec<usize> = (0..scene.instances.len())
        .filter(|&k| {
            let i = &scene.instances[k];
            i.category == 1 && !i.locked && near(i.position)
        })
        .collect();
    println!("erased {} rocks", edit.removed.len());
    assert!(!expected.is_empty());
    assert_eq!(edit.removed, expected);
}

#[test]
fn the_same_stroke_and_seed_paint_the_same_instances() {
    let (canvas, color) = hard_core_on_hills();
    let run = || {
        let mut s = BrushStroke::new(
            &canvas,
            BrushMode::Paint(Box::new(color.clone())),
            options(9),
        )
        .unwrap();
        for p in path(20) {
            s.move_to(p).unwrap();
        }
        s.edit().added
    };
    let (a, b) = (run(), run());
    assert!(!a.is_empty());
    assert_eq!(a, b);
}

#[test]
fn the_eraser_cuts_a_road_under_the_brush_and_leaves_no_stub_shorter_than_its_shortest_edge() {
    // a road of 10 m edges from x = 0 to 200 along y = 50, and a hand-drawn one beside it that stays
    let road: Vec<DVec2> = (0..=20)
        .map(|k| DVec2::new(10.0 * k as f64, 50.0))
        .collect();
    let drawn: Vec<DVec2> = road.iter().map(|p| *p + DVec2::new(0.0, 4.0)).collect();
    let scene = Scene {
        categories: vec![Category::new("road", "roads", CategoryKind::Graph, 0)],
        paths: vec![
            Path {
                category: 0,
                points: road,
                locked: false,
            },
            Path {
                category: 0,
                points: drawn.clone(),
                locked: true,
            },
        ],
        ..Default::default()
    };
    // across the road at x = 103, then, as a second stroke, over its end at x = 192 (which would leave a 3 m stub)
    let strokes = [
        [DVec2::new(103.0, 0.0), DVec2::new(103.0, 70.0)],
        [DVec2::new(192.0, 30.0), DVec2::new(192.0, 70.0)],
    ];
    let mut now = scene.clone();
    for s in &strokes {
        let mode = BrushMode::Erase(Some(vec!["road".into()]));
        let mut stroke = BrushStroke::new(&now, mode, opts_radius(5.0)).unwrap();
        stroke.follow(s, &|_| true).unwrap();
        now = stroke.scene().clone();
    }
    let pieces: Vec<&Path> = now.paths.iter().filter(|p| !p.locked).collect();
    let lengths: Vec<f64> = pieces
        .iter()
        .map(|p| p.points.windows(2).map(|w| w[0].distance(w[1])).sum())
        .collect();
    println!("road pieces left: {lengths:?} m");
    assert_eq!(
        pieces.len(),
        2,
        "one piece each side of the first cut; the stub at the end is gone"
    );
    assert!(lengths.iter().all(|l| *l >= 10.0));
    assert!(
        (lengths.iter().sum::<f64>() - (98.0 + 79.0)).abs() < 1e-6,
        "cut at 98 and 108, and at 187"
    );
    let under_brush = |p: DVec2| {
        strokes
            .iter()
            .any(|s| worldpaint_core::segment_distance(p, s[0], s[1]) < 5.0 - 1e-6)
    };
    for piece in &pieces {
        assert!(piece.points.iter().all(|p| !under_brush(*p)));
    }
    assert_eq!(
        now.paths
            .iter()
            .filter(|p| p.locked)
            .map(|p| &p.points)
            .collect::<Vec<_>>(),
        vec![&drawn]
    );
    // erasing instances only (no category named) leaves roads alone
    let mut all = BrushStroke::new(&scene, BrushMode::Erase(None), opts_radius(5.0)).unwrap();
    all.follow(&strokes[0], &|_| true).unwrap();
    assert!(all.edit().removed_paths.is_empty());
    // the color's shortest edge given: a road color whose edges are 95 m or more keeps the 98 m piece only
    let mode = BrushMode::Erase(Some(vec!["road".into()]));
    let mut long = BrushStroke::new(&scene, mode, opts_radius(5.0)).unwrap();
    long.set_shortest_edge("road", 95.0).unwrap();
    assert!(long.set_shortest_edge("castle", 1.0).is_err());
    long.follow(&strokes[0], &|_| true).unwrap();
    let kept: Vec<usize> = long
        .edit()
        .added_paths
        .iter()
        .map(|p| p.points.len())
        .collect();
    assert_eq!(kept.len(), 1, "{kept:?}");
}

fn opts_radius(radius: f64) -> BrushOptions {
    BrushOptions {
        radius,
        ..options(0)
    }
}

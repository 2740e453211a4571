//! What a user checks first: palettes survive a save, bad files are refused with the right error, terrains
//! from meshes have the right heights, the window-edge fraction is right, pasting respects neighbours, and the
//! same seed gives the same world whatever the thread count.

use worldpaint_core::{
    hard_core_points, learn_color, scene_from_points, slope_scene, synthesize, DVec2, Error,
    Heightfield, Instance, Palette, Region, SynthesisOptions,
};

fn square(min: f64, max: f64) -> Region {
    Region::Rect {
        min: DVec2::splat(min),
        max: DVec2::splat(max),
    }
}

fn hard_core_color() -> worldpaint_core::Color {
    let region = square(0.0, 100.0);
    let scene = scene_from_points("tree", &hard_core_points(&region, 0.04, 3.0, 7));
    learn_color(&scene, &region, "hard core", &Default::default()).unwrap()
}

#[test]
fn palette_json_round_trip_and_errors() {
    let mut color = hard_core_color();
    color.categories[0].min_distance = f64::INFINITY;
    let palette = Palette {
        colors: vec![color.clone()],
    };
    let json = palette.to_json().unwrap();
    assert!(json.contains("\"version\": 1"));
    assert_eq!(Palette::from_json(&json).unwrap(), palette);
    assert_eq!(
        worldpaint_core::Color::from_json(&color.to_json().unwrap()).unwrap(),
        color
    );
    let future = json.replacen("\"version\": 1", "\"version\": 7", 1);
    assert!(matches!(
        Palette::from_json(&future),
        Err(Error::UnsupportedVersion {
            kind: worldpaint_core::FileKind::Palette,
            found: 7,
            supported: 1
        })
    ));
    assert!(matches!(
        Palette::from_json("{not json"),
        Err(Error::Parse { .. })
    ));
    assert!(matches!(
        Palette::from_json(&json[..json.len() / 2]),
        Err(Error::Parse { .. })
    ));
    let corrupt = json.replacen("\"bin_width\"", "\"bin_widht\"", 1);
    assert!(matches!(
        Palette::from_json(&corrupt),
        Err(Error::Parse { .. })
    ));
}

#[test]
fn window_edge_fraction() {
    let r = square(0.0, 100.0);
    assert_eq!(r.circle_fraction_inside(DVec2::splat(50.0), 10.0), 1.0);
    let half = r.circle_fraction_inside(DVec2::new(0.0, 50.0), 10.0);
    assert!((half - 0.5).abs() < 1e-9, "half-plane cut gives {half}");
    let corner = r.circle_fraction_inside(DVec2::ZERO, 10.0);
    assert!((corner - 0.25).abs() < 1e-9);
    let c = Region::Circle {
        center: DVec2::ZERO,
        radius: 50.0,
    };
    assert_eq!(c.circle_fraction_inside(DVec2::new(10.0, 0.0), 5.0), 1.0);
    let on_rim = c.circle_fraction_inside(DVec2::new(50.0, 0.0), 1.0);
    assert!((on_rim - 0.5).abs() < 0.01, "{on_rim}");
    assert!(Region::Polygon {
        points: vec![DVec2::ZERO, DVec2::X]
    }
    .validate()
    .is_err());
}

fn analytic(x: f64, y: f64) -> f64 {
    3.0 + 0.1 * x + 2.0 * (0.05 * y).sin()
}

#[test]
fn terrain_from_grid_and_irregular_meshes() {
    // grid mesh 101 x 101, spacing 1
    let n = 101;
    let verts: Vec<[f64; 3]> = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64, (k / n) as f64);
            [x, y, analytic(x, y)]
        })
        .collect();
    let mut tris = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = (j * n + i) as u32;
            tris.push([a, a + 1, a + n as u32 + 1]);
            tris.push([a, a + n as u32 + 1, a + n as u32]);
        }
    }
    let hf = Heightfield::from_mesh(&verts, &tris, None).unwrap();
    assert_eq!((hf.nx, hf.ny), (101, 101));
    for p in [DVec2::new(10.3, 20.7), DVec2::new(77.0, 3.5)] {
        let h = hf.height_at(p).unwrap();
        assert!((h - analytic(p.x, p.y)).abs() < 0.01, "{h}");
    }
    // irregular: jittered interior vertices (same topology), rasterized at 0.5 m
    let jittered: Vec<[f64; 3]> = verts
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let (i, j) = (k % n, k / n);
            let inner = i > 0 && j > 0 && i < n - 1 && j < n - 1;
            let dx = if inner {
                0.3 * ((k as f64) * 1.7).sin()
            } else {
                0.0
            };
            let dy = if inner {
                0.3 * ((k as f64) * 2.3).cos()
            } else {
                0.0
            };
            [v[0] + dx, v[1] + dy, analytic(v[0] + dx, v[1] + dy)]
        })
        .collect();
    let hf = Heightfield::from_mesh(&jittered, &tris, None).unwrap();
    let mut worst = 0.0f64;
    for k in 0..200 {
        let p = DVec2::new(
            1.0 + (k as f64 * 7.31) % 98.0,
            1.0 + (k as f64 * 3.17) % 98.0,
        );
        worst = worst.max((hf.height_at(p).unwrap() - analytic(p.x, p.y)).abs());
    }
    assert!(worst < 0.05, "irregular mesh height error {worst}");
    assert!(Heightfield::from_mesh(&verts, &[[0, 1, 999_999]], None).is_err());
    assert!(Heightfield::from_mesh(&[], &[], None).is_err());
}

#[test]
fn seamless_paste_keeps_the_hard_core_across_the_border() {
    let color = hard_core_color();
    let min_d = color.categories[0].min_distance;
    // existing content: the same color painted on the left
    let left = square(0.0, 200.0);
    let base = synthesize(
        &Default::default(),
        &color,
        &left,
        &SynthesisOptions {
            seed: 3,
            ..Default::default()
        },
    )
    .unwrap();
    let mut scene = worldpaint_core::Scene {
        categories: base.categories,
        instances: base.instances,
        terrain: None,
        ..Default::default()
    };
    let right = Region::Rect {
        min: DVec2::new(200.0, 0.0),
        max: DVec2::new(400.0, 200.0),
    };
    let pasted = synthesize(
        &scene,
        &color,
        &right,
        &SynthesisOptions {
            seed: 4,
            ..Default::default()
        },
    )
    .unwrap();
    let mut closest = f64::INFINITY;
    for a in &scene.instances {
        for b in &pasted.instances {
            closest = closest.min(a.position.distance(b.position));
        }
    }
    println!("closest pair across the border {closest:.3} m, exemplar minimum {min_d:.3} m");
    assert!(
        closest >= min_d,
        "pair across the border at {closest} < {min_d}"
    );
    scene.instances.extend(pasted.instances);
}

#[test]
fn same_seed_same_world_with_one_or_two_threads() {
    let scene = slope_scene(200.0, 5);
    let learn_region = square(0.0, 100.0);
    let run = || {
        let color = learn_color(&scene, &learn_region, "slope", &Default::default()).unwrap();
        let paint = Region::Rect {
            min: DVec2::new(100.0, 0.0),
            max: DVec2::new(200.0, 200.0),
        };
        synthesize(
            &scene,
            &color,
            &paint,
            &SynthesisOptions {
                seed: 11,
                ..Default::default()
            },
        )
        .unwrap()
        .instances
    };
    let one: Vec<Instance> = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(run);
    let two: Vec<Instance> = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(run);
    assert!(!one.is_empty());
    assert_eq!(one, two);
}

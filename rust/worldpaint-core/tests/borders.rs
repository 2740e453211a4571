//! A patch painted on empty ground has no dense outline: the density of its content near the region's border is
//! the density inside it (the free-border term of the synthesis), for the product model of small counts and for
//! the rdf-matching chain of larger ones; and islands pasted on an empty sea are not piled along its border.

use worldpaint_core::{
    archipelago_scene, hard_core_points, learn_color, synthesize, Category, DVec2, Instance,
    Polygons, Region, Scene, SynthesisOptions,
};

/// Density in 2 m bands by distance to the border of `side × side` squares painted `runs` times, relative to the
/// color's density.
fn border_profile(density: f64, side: f64, runs: u64) -> Vec<f64> {
    let exemplar_region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(100.0),
    };
    let scene = Scene {
        categories: vec![Category::distribution("tree", "vegetation", 0)],
        instances: hard_core_points(&exemplar_region, density, 3.0, 11)
            .into_iter()
            .map(|p| Instance::at(p, 0))
            .collect(),
        terrain: None,
        ..Default::default()
    };
    let color = learn_color(&scene, &exemplar_region, "hard core", &Default::default()).unwrap();
    let canvas = Scene {
        instances: Vec::new(),
        ..scene
    };
    let square = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(side),
    };
    let mut counts = [0.0; 4];
    for seed in 0..runs {
        let opts = SynthesisOptions {
            seed,
            ..Default::default()
        };
        for i in synthesize(&canvas, &color, &square, &opts)
            .unwrap()
            .instances
        {
            let band = (square.distance_to_boundary(i.position) / 2.0) as usize;
            if band < counts.len() {
                counts[band] += 1.0;
            }
        }
    }
    (0..counts.len())
        .map(|b| {
            let inner = side - 4.0 * b as f64;
            let area = inner * inner - (inner - 4.0) * (inner - 4.0);
            counts[b] / (runs as f64 * area * color.categories[0].density)
        })
        .collect()
}

#[test]
fn a_patch_on_empty_ground_has_no_dense_outline() {
    // hard cores of 3 m at packing fractions 0.14, 0.28 and 0.42; 40 m squares hold fewer than 100 trees (the
    // product model), 80 m squares more (the rdf-matching chain). Without the free-border term the outer 2 m held
    // 1.12, 1.30, 1.32 × the density (product model) and 1.12, 1.35, 1.50 × (rdf matching).
    for (density, side, limit) in [
        (0.02, 40.0, 0.12),
        (0.04, 40.0, 0.12),
        (0.06, 40.0, 0.12),
        (0.02, 80.0, 0.12),
        (0.04, 80.0, 0.12),
        (0.06, 80.0, 0.35),
    ] {
        let profile = border_profile(density, side, 120);
        println!("{density} per m², {side} m squares: density by 2 m bands from the border {profile:.3?}");
        assert!(
            (profile[0] - 1.0).abs() <= limit && (profile[1] - 1.0).abs() <= limit,
            "{density} per m², {side} m squares: {profile:.3?}"
        );
    }
}

#[test]
fn islands_pasted_on_an_empty_sea_have_no_land_outline() {
    // the chain of the islands' dense points stops within a sweep (see "When to stop" in the synthesis): the land
    // near the border is no larger a share than inside (measured 0.10 and 0.18 within 8 and 8–16 m, 0.20 inside)
    let exemplar_region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(300.0),
    };
    let example = archipelago_scene(300.0, 1);
    let color = learn_color(&example, &exemplar_region, "islands", &Default::default()).unwrap();
    let canvas = Scene {
        categories: example.categories.clone(),
        ..Default::default()
    };
    let (lo, side, step) = (1000.0, 260.0, 2.0);
    let square = Region::Rect {
        min: DVec2::splat(lo),
        max: DVec2::splat(lo + side),
    };
    // land and all lattice points within 8 m of the border, 8–16 m, and farther than 32 m
    let (mut land, mut all) = ([0.0; 3], [0.0; 3]);
    for seed in 0..16 {
        let opts = SynthesisOptions {
            seed,
            categories: Some(vec!["island".into()]),
            ..Default::default()
        };
        let out = synthesize(&canvas, &color, &square, &opts).unwrap();
        let contours: Vec<Vec<DVec2>> = out.contours.iter().map(|c| c.points.clone()).collect();
        let islands = Polygons::new(&contours);
        let cells = (side / step) as usize;
        for (i, j) in (0..cells).flat_map(|i| (0..cells).map(move |j| (i, j))) {
            let p = DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * step + DVec2::splat(lo);
            let band = match square.distance_to_boundary(p) {
                d if d < 8.0 => 0,
                d if d < 16.0 => 1,
                d if d >= 32.0 => 2,
                _ => continue,
            };
            all[band] += 1.0;
            land[band] += f64::from(u8::from(islands.contains(p)));
        }
    }
    let share: Vec<f64> = (0..3).map(|b| land[b] / all[b]).collect();
    println!("islands: land share within 8 m of the border, 8–16 m and inside {share:.3?}");
    assert!(share[2] > 0.1, "{share:.3?}");
    assert!(
        share[0] <= 1.1 * share[2] && share[1] <= 1.1 * share[2],
        "land piled along the border: {share:.3?}"
    );
}

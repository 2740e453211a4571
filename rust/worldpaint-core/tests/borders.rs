//! A patch painted on empty ground has no dense outline: the density of its content near the region's border is
//! the density inside it (the free-border term of the synthesis), for the product model of small counts and for
//! the rdf-matching chain of larger ones.

use worldpaint_core::{
    hard_core_points, learn_color, synthesize, Category, DVec2, Instance, Region, Scene,
    SynthesisOptions,
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

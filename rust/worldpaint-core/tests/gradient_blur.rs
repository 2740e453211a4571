//! Gradients (Section 5.2) and blur (thesis 6.5.2): a gradient from a sparse to a dense color makes density rise
//! steadily across the region; a blur across the edge between a dense and a sparse forest turns the step into a
//! slope.

use worldpaint_core::{
    bilinear_gradient, blur, gradient, hard_core_points, learn_color, BlurOptions, Category, Color,
    DVec2, GradientOptions, GradientShape, Instance, Region, Scene, SynthesisOptions,
};

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Region {
    Region::Rect {
        min: DVec2::new(x0, y0),
        max: DVec2::new(x1, y1),
    }
}

fn forest(region: &Region, density: f64, seed: u64) -> Vec<Instance> {
    hard_core_points(region, density, 2.0, seed)
        .into_iter()
        .map(|p| Instance::at(p, 0))
        .collect()
}

fn scene(instances: Vec<Instance>) -> Scene {
    Scene {
        categories: vec![Category::distribution("tree", "vegetation", 0)],
        instances,
        terrain: None,
        ..Default::default()
    }
}

fn color(density: f64, seed: u64) -> Color {
    let r = rect(0.0, 0.0, 100.0, 100.0);
    learn_color(
        &scene(forest(&r, density, seed)),
        &r,
        "c",
        &Default::default(),
    )
    .unwrap()
}

/// The empty scene once a gradient from `start` to `end` along `shape` is painted over `region`.
fn gradient_on_empty(
    start: &Color,
    end: &Color,
    region: &Region,
    shape: GradientShape,
    opts: &GradientOptions,
) -> Scene {
    gradient(&scene(Vec::new()), start, end, region, shape, opts, &|_| {
        true
    })
    .unwrap()
    .applied_to(&scene(Vec::new()))
}

/// Densities in `n` bands of x over `[x0, x1] × [y0, y1]`.
fn profile(s: &Scene, x0: f64, x1: f64, y0: f64, y1: f64, n: usize) -> Vec<f64> {
    let w = (x1 - x0) / n as f64;
    (0..n)
        .map(|k| {
            let band = rect(x0 + w * k as f64, y0, x0 + w * (k + 1) as f64, y1);
            s.instances
                .iter()
                .filter(|i| band.contains(i.position))
                .count() as f64
                / band.area()
        })
        .collect()
}

#[test]
fn a_linear_gradient_raises_density_across_the_region() {
    let (sparse, dense) = (color(0.01, 1), color(0.05, 2));
    let region = rect(0.0, 0.0, 400.0, 100.0);
    let shape = GradientShape::Linear {
        from: DVec2::new(0.0, 50.0),
        to: DVec2::new(400.0, 50.0),
    };
    let painted = gradient_on_empty(&sparse, &dense, &region, shape, &GradientOptions::default());
    let d = profile(&painted, 0.0, 400.0, 0.0, 100.0, 5);
    println!(
        "linear gradient, density in five bands: {d:.4?} (ends {:.4} and {:.4})",
        sparse.categories[0].density, dense.categories[0].density
    );
    assert!(
        d.windows(2).all(|w| w[1] > w[0]),
        "density must rise band after band"
    );
    assert!(d[0] < 0.5 * (sparse.categories[0].density + dense.categories[0].density));
    assert!(d[4] > 0.5 * (sparse.categories[0].density + dense.categories[0].density));
}

#[test]
fn a_radial_gradient_thins_out_from_the_centre() {
    let (dense, sparse) = (color(0.05, 3), color(0.01, 4));
    let region = Region::Circle {
        center: DVec2::splat(200.0),
        radius: 150.0,
    };
    let shape = GradientShape::Radial {
        center: DVec2::splat(200.0),
        radius: 150.0,
    };
    let opts = GradientOptions {
        bands: Some(6),
        synthesis: SynthesisOptions {
            seed: 3,
            ..Default::default()
        },
    };
    let painted = gradient_on_empty(&dense, &sparse, &region, shape, &opts);
    let ring = |r0: f64, r1: f64| {
        let n = painted
            .instances
            .iter()
            .filter(|i| {
                let d = i.position.distance(DVec2::splat(200.0));
                d >= r0 && d < r1
            })
            .count() as f64;
        n / (std::f64::consts::PI * (r1 * r1 - r0 * r0))
    };
    let d: Vec<f64> = (0..5)
        .map(|k| ring(30.0 * k as f64, 30.0 * (k + 1) as f64))
        .collect();
    println!("radial gradient, density in five rings: {d:.4?}");
    assert!(
        d.windows(2).all(|w| w[1] < w[0]),
        "density must fall ring after ring"
    );
}

#[test]
fn blur_turns_the_edge_between_two_forests_into_a_slope() {
    let (left, right) = (rect(0.0, 0.0, 200.0, 300.0), rect(200.0, 0.0, 400.0, 300.0));
    let mut instances = forest(&left, 0.05, 7);
    instances.extend(forest(&right, 0.008, 8));
    let before = scene(instances);
    let region = rect(140.0, 80.0, 260.0, 220.0);
    let opts = BlurOptions {
        synthesis: SynthesisOptions {
            seed: 5,
            ..Default::default()
        },
        ..Default::default()
    };
    let after = blur(&before, &region, &opts, &|_| true)
        .unwrap()
        .applied_to(&before);
    let was = profile(&before, 140.0, 260.0, 80.0, 220.0, 6);
    let now = profile(&after, 140.0, 260.0, 80.0, 220.0, 6);
    println!("across the blur, density before {was:.4?}");
    println!("                 density after  {now:.4?}");
    let step = |d: &[f64]| {
        d.windows(2)
            .map(|w| (w[0] - w[1]).abs())
            .fold(0.0, f64::max)
    };
    println!(
        "largest step between neighbouring bands: before {:.4}, after {:.4}",
        step(&was),
        step(&now)
    );
    assert!(
        now.windows(2).all(|w| w[1] <= w[0] + 0.004),
        "density falls from the dense side to the sparse side"
    );
    assert!(step(&now) < 0.6 * step(&was));
    assert!(now[0] > now[5] + 0.01);
    // outside the region nothing changed
    let outside = |s: &Scene| -> Vec<DVec2> {
        s.instances
            .iter()
            .map(|i| i.position)
            .filter(|p| !region.contains(*p))
            .collect()
    };
    assert_eq!(outside(&before), outside(&after));
}

#[test]
fn a_bilinear_gradient_takes_each_corner_color_at_its_corner() {
    // south-west, south-east, north-west, north-east
    let densities = [0.01, 0.03, 0.05, 0.07];
    let colors: Vec<Color> = densities
        .iter()
        .zip(5..)
        .map(|(&d, s)| color(d, s))
        .collect();
    let region = rect(0.0, 0.0, 300.0, 300.0);
    let corners = [&colors[0], &colors[1], &colors[2], &colors[3]];
    let opts = GradientOptions {
        bands: Some(4),
        ..Default::default()
    };
    let painted = bilinear_gradient(&scene(Vec::new()), corners, &region, &opts, &|_| true)
        .unwrap()
        .applied_to(&scene(Vec::new()));
    let density_in = |r: Region| {
        painted
            .instances
            .iter()
            .filter(|i| r.contains(i.position))
            .count() as f64
            / r.area()
    };
    let quarter = [
        rect(0.0, 0.0, 75.0, 75.0),
        rect(225.0, 0.0, 300.0, 75.0),
        rect(0.0, 225.0, 75.0, 300.0),
        rect(225.0, 225.0, 300.0, 300.0),
    ];
    let at_corners: Vec<f64> = quarter.into_iter().map(density_in).collect();
    let centre = density_in(rect(112.5, 112.5, 187.5, 187.5));
    println!("bilinear gradient: density at the corners {at_corners:.4?} (colors {densities:?}), centre {centre:.4}");
    for (d, want) in at_corners.iter().zip(densities) {
        assert!(
            (d / want - 1.0).abs() < 0.2,
            "a corner has {d:.4} per m² where its color has {want}"
        );
    }
    let mean = densities.iter().sum::<f64>() / 4.0;
    assert!(
        (centre / mean - 1.0).abs() < 0.2,
        "the centre has {centre:.4} per m², the corners' mean {mean}"
    );
}

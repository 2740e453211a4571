//! Clustering at two scales, as a user checks it: 5 m clumps inside 40 m patches, learned from a 240 m square and
//! painted over 16 times its area. The painted trees' pair-correlation function (translation-corrected, 0–60 m
//! in 2 m rings) is at most 1.5× as far from the example's as a second draw of the generating process over the
//! example's area is: the synthesis keeps the patches, not only the clumps.

mod common;

use common::pcf::{l2, pcf};
use worldpaint_core::{
    clustered_points, learn_color, scene_from_points, synthesize, uniform_points, AnalysisOptions,
    DVec2, Region, SynthesisOptions,
};

const SIDE: f64 = 240.0;
const PATCH_RADIUS: f64 = 20.0;
const PCF_RANGE: f64 = 60.0;
const PCF_RING: f64 = 2.0;

fn square(origin: f64, side: f64) -> Region {
    Region::Rect {
        min: DVec2::splat(origin),
        max: DVec2::splat(origin + side),
    }
}

/// Thomas clumps (σ 2.5 m, 8 trees each) kept inside 40 m wide patches (discs whose centres are a Poisson
/// process covering about a quarter of the ground).
fn clumps_in_patches(region: &Region, seed: u64) -> Vec<DVec2> {
    let (lo, hi) = region.bbox();
    let grown = Region::Rect {
        min: lo - DVec2::splat(PATCH_RADIUS),
        max: hi + DVec2::splat(PATCH_RADIUS),
    };
    let patch_density = 0.3 / (std::f64::consts::PI * PATCH_RADIUS * PATCH_RADIUS);
    let patches = uniform_points(&grown, patch_density, seed.wrapping_mul(7919));
    clustered_points(region, 0.006, 8.0, 2.5, seed)
        .into_iter()
        .filter(|p| patches.iter().any(|c| c.distance(*p) <= PATCH_RADIUS))
        .collect()
}

fn pcf_of(points: &[DVec2], region: &Region) -> Vec<f64> {
    let (lo, hi) = region.bbox();
    pcf(points, lo, hi, PCF_RANGE, PCF_RING)
}

#[test]
fn clumps_inside_patches_keep_both_scales_over_sixteen_times_the_area() {
    let example = square(0.0, SIDE);
    let trees = clumps_in_patches(&example, 1);
    let color = learn_color(
        &scene_from_points("tree", &trees),
        &example,
        "clumps in patches",
        &AnalysisOptions::default(),
    )
    .expect("the color is learned");
    let reference = pcf_of(&trees, &example);
    // natural variation: other draws of the process over the example's area
    let natural: Vec<f64> = (2..5)
        .map(|seed| {
            l2(
                &pcf_of(&clumps_in_patches(&example, seed), &example),
                &reference,
            )
        })
        .collect();
    let natural = natural.iter().sum::<f64>() / natural.len() as f64;

    let canvas = square(1000.0, 4.0 * SIDE);
    let painted = synthesize(
        &scene_from_points("tree", &[]),
        &color,
        &canvas,
        &SynthesisOptions {
            seed: 3,
            ..Default::default()
        },
    )
    .expect("the paste");
    let points: Vec<DVec2> = painted.instances.iter().map(|i| i.position).collect();
    let synthesized = pcf_of(&points, &canvas);
    let fmt = |g: &[f64]| {
        g.iter()
            .map(|v| format!("{v:.2}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    println!(
        "{} trees in the example, rdf to {:.1} m in {:.2} m bins; {} painted over 16x its area",
        trees.len(),
        color.max_radius,
        color.bin_width,
        points.len()
    );
    println!("example pcf   {}", fmt(&reference));
    println!("painted pcf   {}", fmt(&synthesized));
    let error = l2(&synthesized, &reference);
    println!(
        "pcf L2 (0-{PCF_RANGE} m): painted {error:.3}, second draws {natural:.3}, ratio {:.2}",
        error / natural
    );
    let density = points.len() as f64 / canvas.area() / (trees.len() as f64 / example.area());
    assert!((density - 1.0).abs() <= 0.1, "density ratio {density:.3}");
    assert!(
        error <= 1.5 * natural,
        "pcf L2 {error:.3} over 1.5 x the second draws' {natural:.3}"
    );
}

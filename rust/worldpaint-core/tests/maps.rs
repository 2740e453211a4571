//! Map preferences as a user checks them: a color learned where the terrain reads some values, pasted where it
//! reads others, paints no more there than the example's mean density, and says which share of the destination
//! lay outside what the example showed.

use std::sync::Arc;
use worldpaint_core::{
    clustered_points, learn_color, paste, scene_from_points, uniform_points, AnalysisOptions,
    Color, DVec2, Heightfield, Region, Scene,
};

fn rect(x0: f64, x1: f64) -> Region {
    Region::Rect {
        min: DVec2::new(x0, 0.0),
        max: DVec2::new(x1, 100.0),
    }
}

/// A ramp rising 0.5 m per metre eastwards: 0 m at x = 0, 200 m at x = 400; one slope everywhere.
fn ramp() -> Arc<Heightfield> {
    let (nx, ny, cell) = (201, 51, 2.0);
    let heights = (0..nx * ny)
        .map(|k| (0.5 * cell * (k % nx) as f64) as f32)
        .collect();
    Arc::new(Heightfield::new(DVec2::ZERO, cell, nx, ny, heights).expect("a ramp"))
}

/// Trees on the upper half of the example (x 50..100, heights 25..50 m) only, 0.02 per m² there: 0.01 per m² over
/// the example, twice that in its highest heights.
fn upper_half_color(terrain: &Arc<Heightfield>) -> Color {
    let trees = uniform_points(&rect(50.0, 100.0), 0.02, 7);
    let mut scene = scene_from_points("tree", &trees);
    scene.terrain = Some(terrain.clone());
    learn_color(
        &scene,
        &rect(0.0, 100.0),
        "upper half",
        &AnalysisOptions::default(),
    )
    .expect("the color is learned")
}

fn painted(
    terrain: &Arc<Heightfield>,
    color: &Color,
    region: &Region,
) -> (f64, Vec<(String, f64)>) {
    let edit = paste(
        &Scene::on(terrain.clone()),
        color,
        region,
        &Default::default(),
        &|_| true,
    )
    .expect("the paste");
    (edit.added.len() as f64, edit.unseen_maps)
}

#[test]
fn heights_the_example_never_showed_get_no_more_than_its_mean_density_and_are_reported() {
    let terrain = ramp();
    let color = upper_half_color(&terrain);
    let density = color.categories[0].density;
    assert!(
        (density - 0.01).abs() < 0.002,
        "the example's mean density {density}"
    );

    // heights 150..200 m: none in the example, whose preference rose towards its top (25..50 m: twice the mean).
    // The stated rule: at most the mean density there, so 0.01 × 10,000 m², not twice that
    let (count, unseen) = painted(&terrain, &color, &rect(300.0, 400.0));
    let expected = density * 100.0 * 100.0;
    assert!(
        (count / expected - 1.0).abs() <= 0.1,
        "{count} trees where the rule expects {expected:.0}"
    );
    let share = |name: &str| unseen.iter().find(|(n, _)| n == name).map(|(_, s)| *s);
    assert!(share("elevation").is_some_and(|s| s > 0.95), "{unseen:?}");
    assert_eq!(
        share("slope"),
        None,
        "the slope is the example's: {unseen:?}"
    );

    // half seen (50..100 m, the preferred top: 0.02 per m²), half beyond it (at most the mean, 0.01 per m²)
    let (count, unseen) = painted(&terrain, &color, &rect(50.0, 150.0));
    let expected = 0.02 * 50.0 * 100.0 + density * 50.0 * 100.0;
    assert!(
        (count / expected - 1.0).abs() <= 0.1,
        "{count} trees where the rule expects {expected:.0}"
    );
    let half = share_of(&unseen, "elevation");
    assert!((half - 0.5).abs() < 0.05, "{unseen:?}");

    // inside the example's heights nothing is reported
    let (_, unseen) = painted(&terrain, &color, &rect(0.0, 100.0));
    assert!(unseen.is_empty(), "{unseen:?}");
}

fn share_of(unseen: &[(String, f64)], name: &str) -> f64 {
    unseen
        .iter()
        .find(|(n, _)| n == name)
        .map_or(0.0, |(_, s)| *s)
}

/// Heights on a 400 × 200 m terrain: a ramp of 0.5 m per metre up to x = 100 (the example: 0..50 m), then level
/// ground at 10 m with bands at 37 m (heights the example preferred) for x in 240..260 and 340..360.
fn ramp_then_bands() -> Arc<Heightfield> {
    let (nx, ny, cell) = (201, 101, 2.0);
    let height = |x: f64| {
        if x <= 110.0 {
            0.5 * x
        } else if (240.0..=260.0).contains(&x) || (340.0..=360.0).contains(&x) {
            37.0
        } else {
            10.0
        }
    };
    let heights = (0..nx * ny)
        .map(|k| height(cell * (k % nx) as f64) as f32)
        .collect();
    Arc::new(Heightfield::new(DVec2::ZERO, cell, nx, ny, heights).expect("the terrain"))
}

/// Neighbours within `r` of the points at least `r` inside `band`, per point, over what a uniform scatter of the
/// same density would have: the pair-correlation function integrated over 0..r (1 for no clustering).
fn clustering_within(points: &[DVec2], band: (DVec2, DVec2), r: f64) -> f64 {
    let (lo, hi) = band;
    let inside: Vec<DVec2> = points
        .iter()
        .copied()
        .filter(|p| p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y)
        .collect();
    let density = inside.len() as f64 / ((hi.x - lo.x) * (hi.y - lo.y));
    let centres: Vec<&DVec2> = inside
        .iter()
        .filter(|p| p.x - lo.x >= r && hi.x - p.x >= r && p.y - lo.y >= r && hi.y - p.y >= r)
        .collect();
    let pairs = centres
        .iter()
        .map(|c| {
            inside
                .iter()
                .filter(|q| *q != *c && q.distance(**c) <= r)
                .count()
        })
        .sum::<usize>() as f64;
    pairs / centres.len().max(1) as f64 / (density * std::f64::consts::PI * r * r)
}

#[test]
fn clumps_keep_their_tightness_where_the_preferred_heights_are_a_small_share_of_the_destination() {
    let terrain = ramp_then_bands();
    let band = Region::Rect {
        min: DVec2::new(50.0, 0.0),
        max: DVec2::new(100.0, 200.0),
    };
    let trees = clustered_points(&band, 0.004, 8.0, 2.0, 11);
    let mut scene = scene_from_points("tree", &trees);
    scene.terrain = Some(terrain.clone());
    let opts = AnalysisOptions {
        maps: vec!["elevation".to_string()],
        ..Default::default()
    };
    let example = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::new(100.0, 200.0),
    };
    let color = learn_color(&scene, &example, "clumps on high ground", &opts).expect("learned");
    let destination = Region::Rect {
        min: DVec2::new(200.0, 0.0),
        max: DVec2::new(400.0, 200.0),
    };
    let r = 4.0;
    let real = clustering_within(&trees, (DVec2::new(50.0, 0.0), DVec2::new(100.0, 200.0)), r);
    // the bands hold a fifth of the destination, the preferred heights half of the example: pairs normalised by
    // the whole region's area spread the clumps to about half their tightness (1.5-1.9 against 3.6 measured)
    for (seed, exemplar_on_terrain) in [(1, true), (2, true), (3, true), (1, false), (2, false)] {
        let opts = worldpaint_core::SynthesisOptions {
            seed,
            exemplar_on_terrain,
            ..Default::default()
        };
        let edit = paste(
            &Scene::on(terrain.clone()),
            &color,
            &destination,
            &opts,
            &|_| true,
        )
        .expect("the paste");
        let painted: Vec<DVec2> = edit.added.iter().map(|i| i.position).collect();
        let bands = [240.0, 340.0].map(|x| (DVec2::new(x, 0.0), DVec2::new(x + 20.0, 200.0)));
        let synthesized = bands
            .iter()
            .map(|b| clustering_within(&painted, *b, r))
            .sum::<f64>()
            / 2.0;
        assert!(
            (synthesized / real - 1.0).abs() <= 0.25,
            "seed {seed} (learned here: {exemplar_on_terrain}): clumps within {r} m hold {synthesized:.2} times a \
             uniform scatter's neighbours, the example's {real:.2}"
        );
    }
}

#[test]
fn a_color_following_a_map_made_in_the_scene_refuses_a_terrain_without_it() {
    let mut wet = (*ramp()).clone();
    let moisture: Vec<f32> = (0..wet.nx * wet.ny)
        .map(|k| if k % wet.nx < 25 { 1.0 } else { 0.0 })
        .collect();
    wet.add_map("group:moisture", moisture)
        .expect("a map on the grid");
    let trees = uniform_points(&rect(0.0, 50.0), 0.02, 7);
    let mut scene = scene_from_points("tree", &trees);
    scene.terrain = Some(Arc::new(wet));
    let opts = AnalysisOptions {
        maps: vec!["group:moisture".into()],
        ..Default::default()
    };
    let color = learn_color(&scene, &rect(0.0, 100.0), "wet", &opts).expect("learned");
    let dry = Scene::on(ramp());
    let err = paste(
        &dry,
        &color,
        &rect(200.0, 300.0),
        &Default::default(),
        &|_| true,
    )
    .expect_err("the destination has no such map");
    assert!(
        err.to_string().contains("follows the map 'group:moisture'"),
        "{err}"
    );
}

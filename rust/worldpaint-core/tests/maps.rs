//! Map preferences as a user checks them: a color learned where the terrain reads some values, pasted where it
//! reads others, paints no more there than the example's mean density, and says which share of the destination
//! lay outside what the example showed.

use std::sync::Arc;
use worldpaint_core::exemplar::{self, scene_from_points};
use worldpaint_core::geom::DVec2;
use worldpaint_core::tools::paste;
use worldpaint_core::{learn_color, AnalysisOptions, Color, Heightfield, Region, Scene};

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
    let trees = exemplar::uniform(&rect(50.0, 100.0), 0.02, 7);
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

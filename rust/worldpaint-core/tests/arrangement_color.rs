//! An arrangement as a color of the palette, tried as a user would: learn a hand-placed reference, keep it in a
//! file, paste it elsewhere, paste beside what was pasted, spray more with the brush. Run with `--nocapture` to see
//! the figures.

use std::sync::Arc;

mod common;

use common::arrangement::nearest_distances;
use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use worldpaint_core::{
    clear_region, interpolate_colors, learn_arrangement, paste, BrushMode, BrushOptions,
    BrushStroke, Category, CategoryKind, Color, Heightfield, Instance, Region, Scene,
    SynthesisOptions,
};

/// Spacing of the reference lattice (m).
const SPACING: f64 = 1.0;
/// The hexagonal lattice's elements per m².
fn lattice_density() -> f64 {
    1.0 / (SPACING * SPACING * 3f64.sqrt() / 2.0)
}

fn flat_terrain() -> Arc<Heightfield> {
    Arc::new(
        Heightfield::new(DVec2::ZERO, 1.0, 121, 121, vec![0.0; 121 * 121]).expect("a flat terrain"),
    )
}

/// A scene with a hand-placed 7 × 7 hexagonal lattice of cobbles at (10, 10), jittered by 3 %, locked as placed
/// objects are.
fn reference_scene() -> Scene {
    let mut scene = Scene::on(flat_terrain());
    scene.categories.push(Category::new(
        "cobble",
        "pattern",
        CategoryKind::Arrangement,
        0,
    ));
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for row in 0..7 {
        for col in 0..7 {
            let p = DVec2::new(
                10.0 + (col as f64 + 0.5 * (row % 2) as f64) * SPACING,
                10.0 + row as f64 * SPACING * 3f64.sqrt() / 2.0,
            ) + DVec2::new(rng.random_range(-0.03..0.03), rng.random_range(-0.03..0.03));
            let mut i = Instance::at(p, 0);
            i.locked = true;
            scene.instances.push(i);
        }
    }
    scene
}

fn reference_region() -> Region {
    Region::Rect {
        min: DVec2::new(9.5, 9.5),
        max: DVec2::new(17.5, 15.8),
    }
}

fn learned() -> Color {
    learn_arrangement(&reference_scene(), &reference_region(), "cobbles")
        .expect("a lattice is learnable")
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Region {
    Region::Rect {
        min: DVec2::new(x0, y0),
        max: DVec2::new(x1, y1),
    }
}

fn positions_in(scene: &Scene, region: &Region) -> Vec<DVec2> {
    scene
        .instances
        .iter()
        .map(|i| i.position)
        .filter(|p| region.contains(*p))
        .collect()
}

/// The reference scene with `color` pasted into `region`.
fn pasted(color: &Color, region: &Region) -> Scene {
    let scene = reference_scene();
    paste(&scene, color, region, &SynthesisOptions::default(), &|_| {
        true
    })
    .unwrap()
    .applied_to(&scene)
}

#[test]
fn an_arrangement_color_survives_its_file_and_paints_its_lattice_elsewhere() {
    let color = learned();
    let pattern = color.arrangement().expect("an arrangement color");
    assert_eq!(pattern.elements.len(), 49);
    assert_eq!(color.categories.len(), 1);
    let back = Color::from_json(&color.to_json().unwrap()).unwrap();
    assert_eq!(back, color, "the color reads back as it was written");

    let scene = reference_scene();
    let region = rect(40.0, 40.0, 80.0, 80.0);
    let edit = paste(
        &scene,
        &color,
        &region,
        &SynthesisOptions::default(),
        &|_| true,
    )
    .unwrap();
    assert!(edit.removed.is_empty());
    let points: Vec<DVec2> = edit.added.iter().map(|i| i.position).collect();
    let expected = region.area() * lattice_density();
    let gaps = nearest_distances(&points);
    let mean_gap = gaps.iter().sum::<f64>() / gaps.len() as f64;
    let closest = gaps.iter().copied().fold(f64::INFINITY, f64::min);
    println!(
        "pasted {} elements, {:.0} expected at the lattice's density; nearest neighbour mean {:.3} m, closest \
         {:.3} m (spacing {SPACING} m)",
        points.len(),
        expected,
        mean_gap,
        closest
    );
    let outside: Vec<_> = edit
        .added
        .iter()
        .filter(|i| !region.contains(i.position) || i.category != 0)
        .collect();
    assert!(outside.is_empty(), "{outside:?}");
    assert!((points.len() as f64 / expected - 1.0).abs() < 0.10);
    assert!((mean_gap / SPACING - 1.0).abs() < 0.05);
    let r_short = pattern.reference().unwrap().r_short();
    assert!(
        closest > r_short,
        "no two elements within r_short = {r_short:.3} m"
    );
}

#[test]
fn a_paste_beside_a_pasted_pattern_continues_it_without_a_seam() {
    let color = learned();
    let opts = SynthesisOptions::default();
    let left = rect(40.0, 40.0, 60.0, 80.0);
    let scene = paste(&reference_scene(), &color, &left, &opts, &|_| true)
        .unwrap()
        .applied_to(&reference_scene());
    let right = rect(60.0, 40.0, 80.0, 80.0);
    let edit = paste(&scene, &color, &right, &opts, &|_| true).unwrap();
    assert!(edit.removed.is_empty(), "the left half stays as it was");
    let scene = edit.applied_to(&scene);
    let seam = rect(57.0, 45.0, 63.0, 75.0);
    let band = positions_in(&scene, &seam);
    let gaps = nearest_distances(&band);
    let closest = gaps.iter().copied().fold(f64::INFINITY, f64::min);
    let widest = gaps.iter().copied().fold(0.0, f64::max);
    let density = band.len() as f64 / seam.area();
    println!(
        "seam band: {} elements, density {:.3} /m² (lattice {:.3}), nearest neighbour from {:.3} to {:.3} m",
        band.len(),
        density,
        lattice_density(),
        closest,
        widest
    );
    assert!((density / lattice_density() - 1.0).abs() < 0.12);
    assert!(closest > 0.5 * SPACING, "no two elements crowd at the seam");
    assert!(widest < 1.5 * SPACING, "no gap opens at the seam");
}

#[test]
fn the_spray_brush_grows_the_pattern_and_keeps_what_is_there() {
    let color = learned();
    let patch = rect(40.0, 40.0, 50.0, 50.0);
    let scene = pasted(&color, &patch);
    let before = scene.instances.len();
    let opts = BrushOptions {
        radius: 4.0,
        ..Default::default()
    };
    let mut stroke =
        BrushStroke::new(&scene, BrushMode::Paint(Box::new(color.clone())), opts).unwrap();
    let path: Vec<DVec2> = (0..=20)
        .map(|k| DVec2::new(45.0 + k as f64, 45.0))
        .collect();
    stroke.follow(&path, &|_| true).unwrap();
    let edit = stroke.edit();
    let after = edit.applied_to(&scene);
    let sprayed = rect(51.0, 42.0, 64.0, 48.0);
    let band = positions_in(&after, &sprayed);
    let gaps = nearest_distances(&positions_in(&after, &rect(38.0, 38.0, 70.0, 52.0)));
    let closest = gaps.iter().copied().fold(f64::INFINITY, f64::min);
    println!(
        "spray: {} elements before, {} added, {} removed; {} in the sprayed band (lattice density gives {:.0}); \
         closest pair {:.3} m",
        before,
        edit.added.len(),
        edit.removed.len(),
        band.len(),
        sprayed.area() * lattice_density(),
        closest
    );
    assert!(
        edit.removed.is_empty(),
        "spraying keeps the pattern already there"
    );
    assert!(band.len() as f64 > 0.85 * sprayed.area() * lattice_density());
    assert!(closest > 0.5 * SPACING);
    // the eraser and Clear Region treat the elements as any instances
    let cleared = clear_region(&after, &rect(40.0, 40.0, 45.0, 45.0), Some("cobble")).unwrap();
    assert!(!cleared.removed.is_empty());
}

#[test]
fn an_arrangement_refuses_to_blend_and_keeps_its_flips() {
    let color = learned();
    let err = interpolate_colors(&color, &color, 0.5, "half").unwrap_err();
    assert!(err.to_string().contains("arrangement"), "{err}");

    let mut flipped = color.clone();
    let pattern = flipped.arrangement_mut().unwrap();
    let reference = pattern.reference().unwrap();
    // an interior edge of the lattice shared by two triangles
    let (a, b) = reference
        .edges()
        .into_iter()
        .find(|&(a, b)| !reference.is_boundary(a) && !reference.is_boundary(b))
        .unwrap();
    pattern.flip(a, b).unwrap();
    let edges = pattern.reference().unwrap().edges();
    assert!(!edges.contains(&(a, b)), "the flipped edge is gone");
    let back = Color::from_json(&flipped.to_json().unwrap()).unwrap();
    assert_eq!(
        back.arrangement().unwrap().reference().unwrap().edges(),
        edges
    );
}

#[test]
fn move_carries_a_pattern_rigidly_and_blur_leaves_it_as_it_is() {
    use worldpaint_core::move_region;
    use worldpaint_core::{blur, BlurOptions};
    let color = learned();
    let patch = rect(40.0, 40.0, 50.0, 50.0);
    let scene = pasted(&color, &patch);
    let inside: Vec<DVec2> = scene
        .instances
        .iter()
        .filter(|i| !i.locked)
        .map(|i| i.position)
        .collect();
    let offset = DVec2::new(20.0, 5.0);
    let moved = move_region(&scene, None, &patch, offset, &Default::default()).unwrap();
    assert_eq!(moved.moved, inside.len());
    let mut expected: Vec<[f64; 2]> = inside.iter().map(|p| (*p + offset).to_array()).collect();
    let mut landed: Vec<[f64; 2]> = moved
        .edit
        .added
        .iter()
        .map(|i| i.position.to_array())
        .collect();
    expected.sort_by(|a, b| a.partial_cmp(b).unwrap());
    landed.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(
        landed, expected,
        "every element moved by the offset, none adapted"
    );

    let blurred = blur(
        &scene,
        &rect(42.0, 42.0, 48.0, 48.0),
        &BlurOptions::default(),
        &|_| true,
    )
    .unwrap();
    assert!(
        blurred.removed.is_empty() && blurred.added.is_empty(),
        "blur leaves a pattern as it is"
    );
}

#[test]
fn colour_noise_tints_each_element_and_the_tint_moves_with_it() {
    use worldpaint_core::move_region;
    let plain = learned();
    let mut tinted = plain.clone();
    tinted
        .arrangement_mut()
        .expect("an arrangement color")
        .color_noise = 0.2;
    let patch = rect(40.0, 40.0, 60.0, 60.0);
    let (a, b) = (pasted(&plain, &patch), pasted(&tinted, &patch));
    let positions = |s: &Scene| -> Vec<DVec2> { s.instances.iter().map(|i| i.position).collect() };
    assert_eq!(
        positions(&a),
        positions(&b),
        "the colour noise leaves the pattern as it grew"
    );
    assert!(a.instances.iter().all(|i| i.tint == 0.0));
    let tints: Vec<f64> = b
        .instances
        .iter()
        .filter(|i| !i.locked)
        .map(|i| i.tint as f64)
        .collect();
    let mean = tints.iter().sum::<f64>() / tints.len() as f64;
    let sd = (tints.iter().map(|t| (t - mean).powi(2)).sum::<f64>() / tints.len() as f64).sqrt();
    println!(
        "colour noise 0.2: {} elements, tint mean {mean:.3}, standard deviation {sd:.3}",
        tints.len()
    );
    assert!(mean.abs() < 0.03 && (sd - 0.2).abs() < 0.03);
    assert!(tints.iter().all(|t| t.abs() <= 1.0));

    let moved = move_region(&b, None, &patch, DVec2::new(30.0, 0.0), &Default::default()).unwrap();
    let mut before: Vec<f32> = b
        .instances
        .iter()
        .filter(|i| !i.locked)
        .map(|i| i.tint)
        .collect();
    let mut after: Vec<f32> = moved.edit.added.iter().map(|i| i.tint).collect();
    before.sort_by(f32::total_cmp);
    after.sort_by(f32::total_cmp);
    assert_eq!(before, after, "each element keeps its tint when moved");
}

#[test]
fn noise_past_its_range_and_a_region_past_the_budget_are_refused_before_any_growth() {
    // a noise typed as infinity (Blender stores it as 3.4e38) or past its range, named by its field
    for (field, value) in [
        ("rotation_noise", 3.4e38),
        ("rotation_noise", 4.0),
        ("scale_noise", f64::INFINITY),
        ("color_noise", 1.5),
    ] {
        let mut color = learned();
        let pattern = color.arrangement_mut().unwrap();
        match field {
            "rotation_noise" => pattern.rotation_noise = value,
            "scale_noise" => pattern.scale_noise = value,
            _ => pattern.color_noise = value,
        }
        let err = color.validate().unwrap_err().to_string();
        assert!(
            err.contains(field) && err.contains("between 0 and"),
            "{field} = {value}: {err}"
        );
    }
    // 8 km × 8 km at the reference's density: 74 million elements, past the budget of 50 million
    let huge = rect(0.0, 0.0, 8_000.0, 8_000.0);
    let scene = Scene::default();
    match paste(
        &scene,
        &learned(),
        &huge,
        &SynthesisOptions::default(),
        &|_| true,
    ) {
        Err(e) => assert!(
            e.to_string().contains("too large") && e.to_string().contains("reference's density"),
            "{e}"
        ),
        Ok(edit) => panic!(
            "grown: {} elements",
            edit.applied_to(&scene).instances.len()
        ),
    }
}

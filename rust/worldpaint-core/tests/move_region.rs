//! Move (Section 5.4): a forest learned on 20–35° slopes, moved onto ground with other slopes, keeps its count,
//! keeps the trees that still fit exactly in place relative to each other, and leaves no tree on a slope the
//! color never had.

use worldpaint_core::{
    learn_color, move_region, slope_scene, AdaptOptions, AnalysisOptions, Color, DVec2, Instance,
    Region, Scene,
};

/// The slope scene (its terrain's slopes repeat every 100 m along X), and the color of its first 100 m square.
fn slope_forest() -> (Scene, Color) {
    let scene = slope_scene(400.0, 4);
    let exemplar_region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(100.0),
    };
    let opts = AnalysisOptions {
        maps: vec!["slope".into()],
        ..Default::default()
    };
    let color = learn_color(&scene, &exemplar_region, "slope forest", &opts).unwrap();
    (scene, color)
}

/// Slope bins (2.5°) in which the color had trees.
fn tree_slope_bins(color: &Color) -> Vec<bool> {
    let m = color
        .maps
        .iter()
        .find(|m| m.category == "tree" && m.map == "slope")
        .unwrap();
    m.hist.values.iter().map(|v| *v > 0.0).collect()
}

/// The 100 m square the tests move, one period of the slopes away from the color's exemplar.
fn source() -> Region {
    Region::Rect {
        min: DVec2::new(100.0, 100.0),
        max: DVec2::new(200.0, 200.0),
    }
}

/// The positions of the instances of category `tree` inside `region`.
fn trees_in(instances: &[Instance], tree: usize, region: &Region) -> Vec<DVec2> {
    instances
        .iter()
        .filter(|i| i.category == tree && region.contains(i.position))
        .map(|i| i.position)
        .collect()
}

fn slope_bin(scene: &Scene, p: DVec2) -> usize {
    let s = scene.terrain.as_ref().unwrap().map_at("slope", p).unwrap();
    (s.to_degrees() / 2.5) as usize
}

#[test]
fn a_moved_forest_keeps_its_count_and_what_still_fits() {
    let (scene, color) = slope_forest();
    let source = source();
    // 3 m across the slopes (their period is 100 m) and onto other ground along Y: about half the trees land on
    // slopes the forest never grew on, the others still fit
    let offset = DVec2::new(3.0, 150.0);
    let tree = scene.category_index("tree").unwrap();
    let trees_before = trees_in(&scene.instances, tree, &source);
    let allowed = tree_slope_bins(&color);
    let fits = |p: DVec2| allowed.get(slope_bin(&scene, p)).copied().unwrap_or(false);
    let opts = AdaptOptions {
        seed: 2,
        ..Default::default()
    };
    let moved = move_region(&scene, Some(&color), &source, offset, &opts).unwrap();
    let after = moved.edit.applied_to(&scene);
    let destination = source.translated(offset);
    let trees_after = trees_in(&after.instances, tree, &destination);
    println!(
        "moved {} instances: {} displaced, {} reborn, {} lost; trees {} before, {} after",
        moved.moved,
        moved.displaced,
        moved.reborn,
        moved.lost,
        trees_before.len(),
        trees_after.len()
    );
    assert_eq!(moved.lost, 0);
    assert_eq!(trees_after.len(), trees_before.len(), "the count is kept");

    // no tree on a slope the color never had
    let misplaced = trees_after.iter().filter(|p| !fits(**p)).count();
    assert_eq!(
        misplaced, 0,
        "{misplaced} trees on slopes the forest never grew on"
    );

    // the trees that still fit where the move put them stay there, all together
    let still_fit: Vec<DVec2> = trees_before
        .iter()
        .map(|p| *p + offset)
        .filter(|p| fits(*p))
        .collect();
    let kept = still_fit
        .iter()
        .filter(|p| trees_after.iter().any(|q| q.distance(**p) < 1e-9))
        .count();
    let share = kept as f64 / still_fit.len() as f64;
    println!(
        "{} of {} trees still fit after the move; {kept} stayed exactly in place ({share:.3})",
        still_fit.len(),
        trees_before.len()
    );
    assert!(still_fit.len() >= 10 && still_fit.len() < trees_before.len());
    assert!(share > 0.7);

    // the hard core holds among all trees
    let near_pair = trees_after.iter().enumerate().any(|(i, a)| {
        trees_after[i + 1..]
            .iter()
            .any(|b| a.distance(*b) < color.categories[0].min_distance - 1e-9)
    });
    assert!(!near_pair);
}

#[test]
fn a_drag_recomputed_from_the_original_does_not_flicker() {
    let (scene, color) = slope_forest();
    let source = source();
    let opts = AdaptOptions::default();
    let a = move_region(&scene, Some(&color), &source, DVec2::new(0.0, 40.0), &opts).unwrap();
    let b = move_region(&scene, Some(&color), &source, DVec2::new(0.0, 40.0), &opts).unwrap();
    assert_eq!(a.edit.added, b.edit.added);
    // along Y the slopes do not change: every tree travels rigidly
    let tree = scene.category_index("tree").unwrap();
    let moved_trees = a.edit.added.iter().filter(|i| i.category == tree).count();
    let rigid = a
        .edit
        .added
        .iter()
        .filter(|i| {
            i.category == tree
                && scene.instances.iter().any(|o| {
                    o.category == tree
                        && source.contains(o.position)
                        && (o.position + DVec2::new(0.0, 40.0)).distance(i.position) < 1e-9
                })
        })
        .count();
    println!("moving along the slopes' contour: {rigid} of {moved_trees} trees travel rigidly");
    assert!(rigid as f64 >= 0.9 * moved_trees as f64);
}

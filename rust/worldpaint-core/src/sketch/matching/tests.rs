use super::*;
use crate::sketch::FeatureKind;
use crate::terrain::Heightfield;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The assignment of least total cost by branch and bound, never stopped.
fn assign(front_to_back: &[usize], lists: &[Vec<Candidate>], separation: f64) -> Assignment {
    search(front_to_back, lists, separation, true, &|| false).0
}

/// The same minimum by exhaustive search (no bound): the baseline branch and bound is measured against.
fn assign_exhaustively(
    front_to_back: &[usize],
    lists: &[Vec<Candidate>],
    separation: f64,
) -> Assignment {
    search(front_to_back, lists, separation, false, &|| false).0
}

/// Ridges along X at the given (y, height) on flat ground at 0, Gaussian across (10 m), on 0..400 m.
fn ridges(crests: &[(f64, f64)]) -> Heightfield {
    let (n, cell) = (201, 2.0);
    let heights = (0..n * n)
        .map(|k| {
            let y = (k / n) as f64 * cell;
            crests
                .iter()
                .map(|&(c, h)| h * (-((y - c) / 10.0).powi(2)).exp())
                .fold(0.0, f64::max) as f32
        })
        .collect();
    Heightfield::new(DVec2::ZERO, cell, n, n, heights).expect("a valid grid")
}

fn crest(y: f64, h: f64) -> Feature {
    Feature {
        kind: FeatureKind::Ridge,
        points: (0..=50)
            .map(|k| DVec3::new(100.0 + 4.0 * k as f64, y, h))
            .collect(),
    }
}

fn level_camera() -> Camera {
    Camera::looking_at(
        DVec3::new(200.0, -50.0, 10.0),
        DVec3::new(200.0, 350.0, 10.0),
        60.0,
        1.5,
    )
    .expect("a camera")
}

/// A stroke over image x 0.3..0.7 at the projected height of a crest (y, h) plus `dy`.
fn stroke_over(camera: &Camera, y: f64, h: f64, dy: f64) -> StrokeCurve {
    let points = (0..=40)
        .map(|k| {
            let x = 0.3 + 0.01 * k as f64;
            let dir = camera.ray(DVec2::new(x, 0.5));
            let ground = camera.eye + dir * ((y - camera.eye.y) / dir.y);
            let (image, _) = camera
                .project(DVec3::new(ground.x, y, h))
                .expect("in front");
            DVec2::new(image.x, image.y + dy)
        })
        .collect();
    StrokeCurve::new(&SketchStroke { points })
}

/// The priority list of `stroke` among `pieces`, with the default options.
fn list_of(
    sight: &Sight,
    camera: &Camera,
    stroke: &StrokeCurve,
    pieces: &[FeaturePiece],
) -> Vec<Candidate> {
    let options = MatchingOptions::default();
    let context = MatchingContext::new(sight, camera, pieces, &options);
    priority_list(&context, stroke, &Neighbours::default(), pieces, &options)
}

#[test]
fn a_level_camera_lifts_points_by_the_thesis_formula() {
    let camera = level_camera();
    let terrain = ridges(&[(150.0, 30.0)]);
    let sight = Sight::new(&terrain);
    let stroke = stroke_over(&camera, 150.0, 30.0, 0.02);
    let q = DVec3::new(210.0, 150.0, 30.0);
    let lifted = on_stroke(&camera, &stroke, q).expect("on the stroke");
    // q'.z = q.z + k ‖q_p − q_p^s‖ ‖q − eye‖ / ‖q_p − eye‖, with q_p on the image plane at one metre
    let (image, _) = camera.project(q).expect("in front");
    let plane =
        |y: f64| camera.frame_min + DVec2::new(image.x, y) * (camera.frame_max - camera.frame_min);
    let q_p = camera.eye
        + camera.forward
        + plane(image.y).x * camera.right
        + plane(image.y).y * camera.up;
    let s_y = stroke.y_at(image.x).expect("under the stroke");
    let q_s = camera.eye + camera.forward + plane(s_y).x * camera.right + plane(s_y).y * camera.up;
    let thesis = q.z + q_p.distance(q_s) * q.distance(camera.eye) / q_p.distance(camera.eye);
    assert!((lifted.z - thesis).abs() < 1e-6, "{} vs {thesis}", lifted.z);
    assert!(lifted.z > q.z, "a stroke above lifts the point");
    let _ = sight;
}

#[test]
fn the_ridge_nearest_the_stroke_in_the_image_is_chosen() {
    let crests = [(100.0, 20.0), (200.0, 35.0), (300.0, 80.0)];
    let terrain = ridges(&crests);
    let sight = Sight::new(&terrain);
    let camera = level_camera();
    let features: Vec<Feature> = crests.iter().map(|&(y, h)| crest(y, h)).collect();
    let pieces = feature_pieces(&camera, &features);
    assert_eq!(
        pieces.len(),
        3,
        "each crest projects left to right in one piece"
    );
    let stroke = stroke_over(&camera, 200.0, 35.0, 0.01);
    let list = list_of(&sight, &camera, &stroke, &pieces);
    assert_eq!(list.len(), 3);
    assert_eq!(
        list[0].feature,
        Some(1),
        "costs: {:?}",
        list.iter()
            .map(|c| (c.feature, c.terms))
            .collect::<Vec<_>>()
    );
    // its f′ projects onto the stroke
    for p in &list[0].curve {
        let (image, _) = camera.project(*p).expect("in front");
        let y = stroke.y_at(image.x).expect("under the stroke");
        assert!((image.y - y).abs() < 1e-6);
    }
    assert!(
        list[0].terms[2] < 1.01,
        "the crest covers the stroke without extension: {:?}",
        list[0].terms
    );
}

#[test]
fn between_two_ridges_the_one_needing_less_deformation_wins() {
    // the near crest and the far one project equally far below and above the stroke; lifting the near one takes
    // fewer metres
    let crests = [(100.0, 20.0), (300.0, 56.6)];
    let terrain = ridges(&crests);
    let sight = Sight::new(&terrain);
    let camera = level_camera();
    let features: Vec<Feature> = crests.iter().map(|&(y, h)| crest(y, h)).collect();
    let pieces = feature_pieces(&camera, &features);
    let near = camera
        .project(DVec3::new(200.0, 100.0, 20.0))
        .expect("in front")
        .0
        .y;
    let far = camera
        .project(DVec3::new(200.0, 300.0, 56.6))
        .expect("in front")
        .0
        .y;
    assert!(far > near + 0.02);
    let stroke = stroke_over(&camera, 100.0, 20.0, 0.5 * (far - near));
    let list = list_of(&sight, &camera, &stroke, &pieces);
    assert_eq!(list.len(), 2);
    let (a, b) = (&list[0], &list[1]);
    assert_eq!(a.feature, Some(0), "{:?} vs {:?}", a.terms, b.terms);
    assert!(
        (a.terms[0] - b.terms[0]).abs() < 0.01 * a.terms[0].max(1e-3),
        "equal image distances"
    );
    assert!(
        a.terms[1] < 0.6 * b.terms[1],
        "the near crest moves less: {:?} vs {:?}",
        a.terms,
        b.terms
    );
}

#[test]
fn a_feature_shorter_than_the_stroke_is_extended_and_pays_for_it() {
    let terrain = ridges(&[(200.0, 35.0)]);
    let sight = Sight::new(&terrain);
    let camera = level_camera();
    let mut short = crest(200.0, 35.0);
    short.points.retain(|p| p.x >= 180.0 && p.x <= 240.0);
    let pieces = feature_pieces(&camera, &[short]);
    let stroke = stroke_over(&camera, 200.0, 35.0, 0.0);
    let list = list_of(&sight, &camera, &stroke, &pieces);
    assert_eq!(list.len(), 1);
    let c = &list[0];
    let (x0, x1) = stroke.x_range();
    assert!(
        c.xs[0] <= x0 + 1e-3 && *c.xs.last().expect("points") >= x1 - 1e-3,
        "covers the stroke"
    );
    assert!(c.terms[2] > 1.5, "extension penalised: {:?}", c.terms);
}

/// Random priority lists: features shared among strokes, depths that sometimes hide one another.
fn random_lists(rng: &mut ChaCha8Rng, strokes: usize, features: usize) -> Vec<Vec<Candidate>> {
    (0..strokes)
        .map(|_| {
            let m = rng.random_range(0..=4);
            let mut list: Vec<Candidate> = (0..m)
                .map(|_| {
                    let x0 = rng.random_range(0.0..0.5);
                    let x1 = x0 + rng.random_range(0.1..0.5);
                    let depth = rng.random_range(50.0..500.0);
                    Candidate {
                        feature: Some(rng.random_range(0..features)),
                        curve: Vec::new(),
                        breaks: Vec::new(),
                        depths: vec![depth, depth + rng.random_range(-40.0..40.0)],
                        xs: vec![x0, x1],
                        cost: rng.random_range(1.0..3.0),
                        terms: [0.0; 3],
                        largest_change: 0.0,
                    }
                })
                .collect();
            list.sort_by(|a, b| a.cost.total_cmp(&b.cost));
            list
        })
        .collect()
}

#[test]
fn branch_and_bound_finds_the_exhaustive_minimum_with_fewer_nodes() {
    let mut rng = ChaCha8Rng::seed_from_u64(18);
    let (mut bb_nodes, mut ex_nodes) = (0, 0);
    for case in 0..200 {
        let n = rng.random_range(1..=5);
        let lists = random_lists(&mut rng, n, 6);
        let order: Vec<usize> = (0..n).collect();
        let bb = assign(&order, &lists, 5.0);
        let ex = assign_exhaustively(&order, &lists, 5.0);
        assert!(
            (bb.cost - ex.cost).abs() < 1e-9,
            "case {case}: {} vs {}",
            bb.cost,
            ex.cost
        );
        // the assignment respects the rules
        for (k, &s) in order.iter().enumerate() {
            let Some(c) = bb.chosen[s] else { continue };
            let cand = &lists[s][c];
            for &front in &order[..k] {
                if let Some(f) = bb.chosen[front] {
                    assert_ne!(
                        lists[front][f].feature, cand.feature,
                        "case {case}: a feature serves once"
                    );
                    assert!(
                        !cand.hides(&lists[front][f], 5.0),
                        "case {case}: a back curve hides a front one"
                    );
                }
            }
        }
        bb_nodes += bb.nodes;
        ex_nodes += ex.nodes;
    }
    assert!(
        bb_nodes * 2 < ex_nodes,
        "branch and bound {bb_nodes} nodes, exhaustive {ex_nodes}"
    );
}

#[test]
fn a_stroke_without_candidates_is_left_to_the_embedding() {
    let lists = vec![Vec::new()];
    let a = assign(&[0], &lists, 5.0);
    assert_eq!(a.chosen, vec![None]);
    assert_eq!(a.cost, EMPTY_LIST_COST);
}

#[test]
fn a_stroke_just_above_a_skyline_of_two_ridges_takes_the_skyline_and_lifts_it_least() {
    use crate::sketch::features::{detect_features, FeatureOptions};
    // a near ridge 45 m high over the left of the view (200 m away, fading out beyond x = 200 m) and a far one
    // 60 m high across it (350 m away): the skyline is the near one on the left and the far one on the right
    let (n, cell) = (201, 2.0);
    let heights = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64 * cell, (k / n) as f64 * cell);
            let left = 1.0 / (1.0 + ((x - 210.0) / 5.0).exp());
            let near = 45.0 * left * (-((y - 150.0) / 12.0).powi(2)).exp();
            let far = 60.0 * (-((y - 300.0) / 12.0).powi(2)).exp();
            near.max(far) as f32
        })
        .collect();
    let terrain = Heightfield::new(DVec2::ZERO, cell, n, n, heights).expect("a valid grid");
    let sight = Sight::new(&terrain);
    let camera = level_camera();
    let features = detect_features(&sight, &camera, &FeatureOptions::default()).expect("features");
    let pieces = feature_pieces(&camera, &features);
    // the stroke: 3 % of the image above the skyline over x 0.3..0.7
    let skyline = |x: f64| {
        sight
            .column_silhouette(&camera, x, 0.0, 1.0)
            .expect("a skyline")
    };
    let stroke = StrokeCurve::new(&SketchStroke {
        points: (0..=40)
            .map(|k| {
                let x = 0.3 + 0.01 * k as f64;
                DVec2::new(x, skyline(x).0 + 0.03)
            })
            .collect(),
    });
    // what lifting the skyline's own points onto the stroke needs, column by column
    let needed = (0..=40)
        .map(|k| {
            let x = 0.3 + 0.01 * k as f64;
            let p = skyline(x).1;
            on_stroke(&camera, &stroke, p).expect("on the stroke").z - p.z
        })
        .fold(0.0, f64::max);
    let list = list_of(&sight, &camera, &stroke, &pieces);
    let best = &list[0];
    let others: Vec<(Option<usize>, f64, f64)> = list
        .iter()
        .map(|c| (c.feature, c.cost, c.largest_change))
        .collect();
    assert_eq!(best.feature, None, "the skyline wins: {others:?}");
    assert!(
        !best.breaks.is_empty(),
        "it jumps from the near ridge to the far one"
    );
    assert!(
        best.largest_change <= 1.25 * needed,
        "{} m for {needed} m",
        best.largest_change
    );
    // every single feature covering the stroke changes the terrain more
    for c in list.iter().filter(|c| c.feature.is_some()) {
        assert!(c.largest_change > best.largest_change, "{others:?}");
    }
}

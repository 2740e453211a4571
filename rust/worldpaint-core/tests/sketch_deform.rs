//! Deforming a terrain to sketched silhouettes (thesis §5.3–5.4), with the features given: the strokes' curves lie
//! on the deformed terrain, seen from the camera each stroke is a visible silhouette within 1 % of the image
//! height, what hid a stroke has been lowered, and the terrain beyond the deformation's reach is unchanged.

use glam::DVec3;
use worldpaint_core::{
    deform_to_targets, stroke_targets, Camera, CurveSource, DVec2, Feature, FeatureKind,
    Heightfield, MatchingOptions, Sight, SketchDeformOptions, SketchStroke, StrokeTarget,
};

const N: usize = 257;
const CELL: f64 = 2.0;

/// Rolling ground with a near ridge, a middle ridge and a near hill, plus metre-scale detail, on `n × n` nodes
/// `cell` metres apart.
fn hills_on(n: usize, cell: f64) -> Heightfield {
    let heights = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64 * cell, (k / n) as f64 * cell);
            let ridge = |c: f64, h: f64, w: f64| h * (-((y - c) / w).powi(2)).exp();
            let hill =
                45.0 * (-((x - 256.0).powi(2) + (y - 130.0).powi(2)) / 15.0f64.powi(2)).exp();
            let detail =
                0.8 * (0.31 * x).sin() * (0.27 * y).cos() + 0.5 * (0.53 * x + 0.41 * y).sin();
            (ridge(100.0, 18.0, 12.0)
                .max(ridge(260.0, 40.0, 18.0))
                .max(hill)
                + detail) as f32
        })
        .collect();
    Heightfield::new(DVec2::ZERO, cell, n, n, heights).expect("a valid grid")
}

fn hills() -> Heightfield {
    hills_on(N, CELL)
}

fn camera() -> Camera {
    Camera::looking_at(
        DVec3::new(256.0, -60.0, 12.0),
        DVec3::new(256.0, 400.0, 12.0),
        60.0,
        1.5,
    )
    .expect("a camera")
}

/// How far (image heights) a stroke's silhouette may lie from it.
const TOLERANCE: f64 = 0.01;

/// Columns where the stroke is not the visible silhouette: a ray `TOLERANCE` above it meets the terrain before
/// passing its curve, or a ray as far below passes it without meeting the terrain.
fn misplaced_columns(
    terrain: &Heightfield,
    camera: &Camera,
    target: &StrokeTarget,
) -> (usize, usize) {
    let sight = Sight::new(terrain);
    let depth_of = |p: DVec3| (p - camera.eye).dot(camera.forward);
    let mut projected: Vec<(DVec2, f64)> = target
        .curve
        .iter()
        .filter_map(|&p| camera.project(p))
        .collect();
    projected.sort_by(|a, b| a.0.x.total_cmp(&b.0.x));
    let (x0, x1) = target.stroke.x_range();
    let (mut checked, mut bad) = (0, 0);
    for k in 0..=200 {
        let x = x0 + (x1 - x0) * (0.02 + 0.96 * k as f64 / 200.0);
        let y = target.stroke.y_at(x).expect("on the stroke");
        let Some(w) = projected
            .windows(2)
            .find(|w| w[0].0.x <= x && w[1].0.x >= x)
        else {
            continue;
        };
        let depth = w[0].1 + (w[1].1 - w[0].1) * (x - w[0].0.x) / (w[1].0.x - w[0].0.x).max(1e-12);
        let margin = 3.0 * terrain.cell;
        let above = sight.hit(camera.eye, camera.ray(DVec2::new(x, y + TOLERANCE)));
        let below = sight.hit(camera.eye, camera.ray(DVec2::new(x, y - TOLERANCE)));
        let clear_above = above.is_none_or(|(_, p)| depth_of(p) > depth + margin);
        let stopped_below = below.is_some_and(|(_, p)| depth_of(p) < depth + margin);
        checked += 1;
        if !(clear_above && stopped_below) {
            bad += 1;
        }
    }
    (checked, bad)
}

fn crest(y: f64, z: f64) -> Feature {
    Feature {
        kind: FeatureKind::Ridge,
        points: (0..=100)
            .map(|k| DVec3::new(56.0 + 4.0 * k as f64, y, z))
            .collect(),
    }
}

#[test]
fn a_stroke_above_a_ridge_becomes_its_silhouette_and_the_hill_in_front_is_lowered() {
    let terrain = hills();
    let camera = camera();
    let sight = Sight::new(&terrain);
    // a stroke 4 % of the image height above the middle ridge's crest, rising in the middle
    let crest_y = |x: f64| {
        let dir = camera.ray(DVec2::new(x, 0.5));
        let ground = camera.eye + dir * ((260.0 - camera.eye.y) / dir.y);
        camera
            .project(DVec3::new(ground.x, 260.0, 40.0))
            .expect("in front")
            .0
            .y
    };
    let stroke = SketchStroke {
        points: (0..=60)
            .map(|k| {
                let x = 0.25 + 0.5 * k as f64 / 60.0;
                DVec2::new(
                    x,
                    crest_y(x) + 0.04 + 0.03 * (std::f64::consts::PI * (x - 0.25) / 0.5).sin(),
                )
            })
            .collect(),
    };
    let features = vec![crest(100.0, 18.0), crest(260.0, 40.0)];
    let t = stroke_targets(
        &sight,
        &camera,
        &[stroke],
        &[0],
        &features,
        &MatchingOptions::default(),
        true,
        &|| false,
    )
    .expect("a matching well within the work budget");
    assert_eq!(
        t.sources,
        vec![CurveSource::Feature(1)],
        "the middle ridge serves the stroke"
    );
    // deformed once, without lowering, the hill in front still hides part of the stroke
    let once = SketchDeformOptions {
        max_rounds: 1,
        ..SketchDeformOptions::default()
    };
    let first =
        deform_to_targets(&terrain, &camera, &t.targets, &once, &|_| true).expect("deformed");
    let (_, hidden) = misplaced_columns(&first.terrain, &camera, &t.targets[0]);
    assert!(
        hidden > 10,
        "the hill hides part of the stroke: {hidden} columns"
    );
    let d = deform_to_targets(
        &terrain,
        &camera,
        &t.targets,
        &SketchDeformOptions::default(),
        &|_| true,
    )
    .expect("deformed");
    let (checked, bad) = misplaced_columns(&d.terrain, &camera, &t.targets[0]);
    println!(
        "{checked} columns, {bad} misplaced after {} rounds ({} silhouettes lowered, reach {:.0} m); {hidden} hidden without lowering",
        d.rounds,
        d.lowered.len(),
        d.reach
    );
    assert_eq!(
        bad, 0,
        "every column of the stroke is a visible silhouette within 1 % of the image height"
    );
    assert!(!d.lowered.is_empty(), "the hill in front was lowered");
    // beyond the reach, nothing moved
    let curve = &t.targets[0].curve;
    let lowered: Vec<DVec3> = d.lowered.iter().flatten().copied().collect();
    for (k, (&a, &b)) in terrain.heights.iter().zip(&d.terrain.heights).enumerate() {
        let p = DVec2::new((k % N) as f64, (k / N) as f64) * CELL;
        let near = curve
            .iter()
            .chain(&lowered)
            .any(|c| c.truncate().distance(p) <= d.reach + CELL);
        if !near {
            assert_eq!(a, b, "node {k} beyond the reach moved");
        }
    }
}

/// The Blender test's scene: the same hills on a 4 m grid, the same camera.
fn hills_coarse() -> Heightfield {
    hills_on(129, 4.0)
}

/// A front mountain and two behind it, each ending on its slopes: two T-junctions.
fn three_strokes() -> Vec<SketchStroke> {
    let front = |x: f64| 0.62 + 0.09 * (-((x - 0.38) / 0.12).powi(2)).exp();
    let line = |x0: f64, x1: f64, n: usize, f: &dyn Fn(f64) -> f64| SketchStroke {
        points: (0..n)
            .map(|k| {
                let x = x0 + (x1 - x0) * k as f64 / (n - 1) as f64;
                DVec2::new(x, f(x))
            })
            .collect(),
    };
    let pi = std::f64::consts::PI;
    vec![
        line(0.18, 0.62, 30, &front),
        line(0.52, 0.9, 30, &|x| {
            front(0.52) + 0.1 * (pi * (x - 0.52) / 0.5).sin() + 0.01 * (x - 0.52)
        }),
        line(0.06, 0.27, 20, &|x| {
            front(0.27) + 0.08 * (pi * (0.27 - x) / 0.3).sin()
        }),
    ]
}

/// Nodes farther than `distance` from every point of `curves`.
fn away_from(terrain: &Heightfield, curves: &[&[DVec3]], distance: f64) -> Vec<bool> {
    let n = terrain.nx;
    (0..terrain.heights.len())
        .map(|k| {
            let p = terrain.origin + DVec2::new((k % n) as f64, (k / n) as f64) * terrain.cell;
            curves
                .iter()
                .all(|c| c.iter().all(|q| q.truncate().distance(p) > distance))
        })
        .collect()
}

/// The terrain minus its mean over a (2r+1)² window: its fine detail.
fn high_pass(terrain: &Heightfield, r: usize) -> Vec<f64> {
    let (nx, ny) = (terrain.nx, terrain.ny);
    let h = |i: usize, j: usize| terrain.heights[j * nx + i] as f64;
    (0..nx * ny)
        .map(|k| {
            let (i, j) = (k % nx, k / nx);
            let (i0, i1, j0, j1) = (
                i.saturating_sub(r),
                (i + r).min(nx - 1),
                j.saturating_sub(r),
                (j + r).min(ny - 1),
            );
            let mut sum = 0.0;
            for jj in j0..=j1 {
                for ii in i0..=i1 {
                    sum += h(ii, jj);
                }
            }
            h(i, j) - sum / ((i1 - i0 + 1) * (j1 - j0 + 1)) as f64
        })
        .collect()
}

fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}

#[test]
fn three_strokes_with_two_t_junctions_are_all_seen_and_the_detail_is_kept() {
    use worldpaint_core::{apply_sketch, CurveSource, SketchOptions};
    let terrain = hills_coarse();
    let camera = camera();
    let mut options = SketchOptions::default();
    options.deform.reach = Some(120.0);
    let edit =
        apply_sketch(&terrain, &camera, &three_strokes(), &options, &|_| true).expect("applied");
    let d = &edit.deformation;
    println!(
        "order {:?}, {} junctions, sources {:?} of {} features, {} rounds, {} lowered, {} hidden columns, {:?}",
        edit.order.front_to_back,
        edit.order.junctions.len(),
        edit.targets.sources,
        edit.features.len(),
        d.rounds,
        d.lowered.len(),
        d.hidden_columns,
        edit.seconds
    );
    assert_eq!(
        edit.order.front_to_back,
        vec![0, 1, 2],
        "the front mountain first, then the later one's"
    );
    assert_eq!(edit.order.junctions.len(), 2);
    assert!(
        edit.targets
            .sources
            .iter()
            .all(|s| !matches!(s, CurveSource::Embedded(_))),
        "the terrain's features or its skyline serve all"
    );
    for (s, target) in edit.targets.targets.iter().enumerate() {
        let (checked, bad) = misplaced_columns(&d.terrain, &camera, target);
        println!("stroke {s}: {bad} of {checked} columns misplaced");
        assert_eq!(
            bad, 0,
            "stroke {s} is a visible silhouette within 1 % of the image height"
        );
    }
    assert_eq!(d.hidden_columns, 0);
    // beyond the reach the terrain is as it was; away from the constraints its detail is kept
    let curves: Vec<&[DVec3]> = edit
        .targets
        .targets
        .iter()
        .map(|t| t.curve.as_slice())
        .chain(d.lowered.iter().map(Vec::as_slice))
        .collect();
    let far = away_from(&terrain, &curves, d.reach + terrain.cell);
    let moved_far = (0..far.len())
        .filter(|&k| far[k] && terrain.heights[k] != d.terrain.heights[k])
        .count();
    assert!(
        far.iter().filter(|&&f| f).count() > 1000 && moved_far == 0,
        "{moved_far} nodes beyond the reach moved"
    );
    let away = away_from(&terrain, &curves, 3.0 * terrain.cell);
    let (before, after) = (high_pass(&terrain, 2), high_pass(&d.terrain, 2));
    let pick = |v: &[f64]| -> Vec<f64> {
        v.iter()
            .zip(&away)
            .filter(|(_, &a)| a)
            .map(|(x, _)| *x)
            .collect()
    };
    let r = correlation(&pick(&before), &pick(&after));
    println!("high-pass correlation away from the constraints: {r:.4}");
    assert!(r >= 0.99, "the terrain keeps its fine detail: {r}");
}

#[test]
fn a_stroke_no_feature_can_serve_is_embedded_and_seen() {
    use worldpaint_core::{apply_sketch, CurveSource, SketchOptions};
    // flat ground: no ridge, no silhouette but its far edge
    let terrain =
        Heightfield::new(DVec2::ZERO, 4.0, 129, 129, vec![0.0; 129 * 129]).expect("a valid grid");
    let camera = camera();
    let stroke = SketchStroke {
        points: (0..=30)
            .map(|k| {
                let x = 0.3 + 0.4 * k as f64 / 30.0;
                DVec2::new(
                    x,
                    0.56 + 0.08 * (std::f64::consts::PI * (x - 0.3) / 0.4).sin(),
                )
            })
            .collect(),
    };
    let edit = apply_sketch(
        &terrain,
        &camera,
        &[stroke],
        &SketchOptions::default(),
        &|_| true,
    )
    .expect("applied");
    println!("sources {:?}", edit.targets.sources);
    assert!(
        matches!(edit.targets.sources[0], CurveSource::Embedded(d) if d > 0.0),
        "{:?}",
        edit.targets.sources
    );
    let (checked, bad) =
        misplaced_columns(&edit.deformation.terrain, &camera, &edit.targets.targets[0]);
    println!("embedded stroke: {bad} of {checked} columns misplaced");
    assert_eq!(bad, 0, "the embedded stroke is seen where it was drawn");
}

/// A rough terrain (2 m cells, `n` × `n` nodes) and a camera 15 m above it looking across it.
fn rough_view(n: usize) -> (Heightfield, Camera) {
    let size = 2.0 * (n - 1) as f64;
    let terrain = worldpaint_core::rough_terrain(size, 2.0, 3);
    let at = |x: f64, y: f64| {
        let p = DVec2::new(x, y) * size;
        p.extend(terrain.height_at(p).unwrap_or(0.0))
    };
    let eye = at(0.15, 0.15) + DVec3::Z * 15.0;
    let camera = Camera::looking_at(eye, at(0.7, 0.7), 60.0, 1.5).expect("a camera");
    (terrain, camera)
}

#[test]
fn the_features_do_not_depend_on_the_thread_count() {
    let (terrain, camera) = rough_view(160);
    let options = worldpaint_core::FeatureOptions::default();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a pool");
        pool.install(|| worldpaint_core::detect_features(&Sight::new(&terrain), &camera, &options))
            .expect("valid")
    };
    let one = run(1);
    assert!(one.iter().any(|f| f.kind == FeatureKind::Silhouette));
    assert!(one.iter().any(|f| f.kind == FeatureKind::Ridge));
    assert_eq!(one, run(3));
}

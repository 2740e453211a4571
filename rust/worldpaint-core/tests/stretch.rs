//! Seam-carving stretch (Section 5.5): stretching a region by 50 % keeps every object away from the cut where it
//! was (up to the rigid move of its side) and fills the opened band with the region's statistics; shrinking
//! removes only the content of the band.

use worldpaint_core::{
    color_of_region, hard_core_points, stretch, Category, DVec2, Instance, Region, Scene,
    StretchOptions, StretchSide, Stretched,
};

const WIDTH: f64 = 100.0;
const HEIGHT: f64 = 60.0;

fn region() -> Region {
    Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::new(WIDTH, HEIGHT),
    }
}

/// A hard-core arrangement (3 m, 0.04 per m²) filling the region, nothing around it.
fn scene() -> Scene {
    Scene {
        categories: vec![Category::distribution("tree", "vegetation", 0)],
        instances: hard_core_points(&region(), 0.04, 3.0, 5)
            .into_iter()
            .map(|p| Instance::at(p, 0))
            .collect(),
        terrain: None,
        ..Default::default()
    }
}

/// `x` of the cut at height `y` (the seam is a polyline ascending in `y`).
fn cut_at(seam: &[DVec2], y: f64) -> f64 {
    let k = seam.partition_point(|p| p.y < y).clamp(1, seam.len() - 1);
    let (a, b) = (seam[k - 1], seam[k]);
    let t = if b.y > a.y {
        ((y - a.y) / (b.y - a.y)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    a.x + t * (b.x - a.x)
}

fn has(points: &[DVec2], p: DVec2) -> bool {
    points.iter().any(|q| q.distance(p) < 1e-9)
}

/// `region` of `scene` stretched by `amount` on `side` with the default options, learning the color from the region.
fn stretched(
    scene: &Scene,
    region: &Region,
    side: StretchSide,
    amount: f64,
) -> worldpaint_core::Result<Stretched> {
    stretch(
        scene,
        region,
        side,
        amount,
        None,
        &StretchOptions::default(),
        &|_| true,
    )
}

/// The positions of the instances of `scene` once the stretch is applied.
fn positions_after(out: &Stretched, scene: &Scene) -> Vec<DVec2> {
    out.edit
        .applied_to(scene)
        .instances
        .iter()
        .map(|i| i.position)
        .collect()
}

/// Where an east stretch by `amount` puts an object at `p` that it keeps: moved with its side when beyond the cut.
fn kept_place(seam: &[DVec2], p: DVec2, amount: f64) -> DVec2 {
    if p.x > cut_at(seam, p.y) {
        p + DVec2::new(amount, 0.0)
    } else {
        p
    }
}

#[test]
fn stretching_by_half_keeps_both_sides_and_fills_the_band() {
    let scene = scene();
    let color = color_of_region(&scene, &region(), "region")
        .unwrap()
        .unwrap();
    let amount = 0.5 * WIDTH;
    let out = stretched(&scene, &region(), StretchSide::East, amount).unwrap();
    let after = positions_after(&out, &scene);
    let seam = &out.seam;
    let (lo, hi) = seam
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.x), b.max(p.x))
        });
    println!(
        "cut between x = {lo:.1} and {hi:.1}; {} instances before, {} after",
        scene.instances.len(),
        after.len()
    );
    assert!(lo >= 0.1 * WIDTH - 1.0 && hi <= 0.9 * WIDTH + 1.0);
    // every object keeps its place, or its place moved by the stretch, depending on its side of the cut
    for i in &scene.instances {
        let p = i.position;
        let want = kept_place(seam, p, amount);
        assert!(has(&after, want), "{p:?} should be at {want:?}");
    }
    // the opened band has the region's density and keeps the hard core with both sides
    let in_band: Vec<DVec2> = after
        .iter()
        .copied()
        .filter(|p| out.band.contains(*p))
        .collect();
    let ratio = in_band.len() as f64 / (out.band.area() * color.categories[0].density);
    let closest = after
        .iter()
        .enumerate()
        .flat_map(|(k, a)| after[k + 1..].iter().map(move |b| a.distance(*b)))
        .fold(f64::INFINITY, f64::min);
    println!(
        "band: {} instances, density ratio {ratio:.3}; closest pair {closest:.3} m",
        in_band.len()
    );
    assert!((ratio - 1.0).abs() <= 0.1);
    assert!(closest >= color.categories[0].min_distance - 1e-9);
    assert_eq!(
        out.region,
        Region::Rect {
            min: DVec2::ZERO,
            max: DVec2::new(1.5 * WIDTH, HEIGHT)
        }
    );
}

#[test]
fn shrinking_removes_the_band_only() {
    let scene = scene();
    let amount = -30.0;
    let out = stretched(&scene, &region(), StretchSide::East, amount).unwrap();
    let in_band: Vec<usize> = (0..scene.instances.len())
        .filter(|&k| out.band.contains(scene.instances[k].position))
        .collect();
    println!(
        "shrink: band holds {} instances; {} removed",
        in_band.len(),
        out.edit.removed.len()
    );
    let after = positions_after(&out, &scene);
    for (k, i) in scene.instances.iter().enumerate() {
        let p = i.position;
        if in_band.contains(&k) {
            assert!(!has(&after, p), "{p:?} in the band should be gone");
            continue;
        }
        let want = kept_place(&out.seam, p, amount);
        assert!(has(&after, want), "{p:?} should be at {want:?}");
    }
    // nothing lies beyond the region, so the released strip stays empty
    assert_eq!(after.len(), scene.instances.len() - in_band.len());
    assert!(after.iter().all(|p| p.x <= WIDTH + amount + 1e-9));
}

#[test]
fn stretching_north_and_west_mirror_east() {
    let scene = scene();
    for side in [StretchSide::West, StretchSide::North, StretchSide::South] {
        let out = stretched(&scene, &region(), side, 20.0).unwrap();
        let want = match side {
            StretchSide::West => Region::Rect {
                min: DVec2::new(-20.0, 0.0),
                max: DVec2::new(WIDTH, HEIGHT),
            },
            StretchSide::North => Region::Rect {
                min: DVec2::ZERO,
                max: DVec2::new(WIDTH, HEIGHT + 20.0),
            },
            _ => Region::Rect {
                min: DVec2::new(0.0, -20.0),
                max: DVec2::new(WIDTH, HEIGHT),
            },
        };
        assert_eq!(out.region, want);
        let after = out.edit.applied_to(&scene);
        assert!(after.instances.iter().all(|i| want.contains(i.position)));
        assert!(after.instances.len() > scene.instances.len());
    }
}

#[test]
fn stretching_asks_for_a_rectangle_and_a_length() {
    let scene = scene();
    let circle = Region::Circle {
        center: DVec2::splat(50.0),
        radius: 20.0,
    };
    assert!(stretched(&scene, &circle, StretchSide::East, 10.0).is_err());
    assert!(stretched(&scene, &region(), StretchSide::East, 0.0).is_err());
    assert!(stretched(&scene, &region(), StretchSide::East, -90.0).is_err());
}

/// The signed area of a closed polygon.
fn area(points: &[DVec2]) -> f64 {
    let n = points.len();
    0.5 * (0..n)
        .map(|k| points[k].perp_dot(points[(k + 1) % n]))
        .sum::<f64>()
}

#[test]
fn a_road_across_the_cut_is_stretched_whole_and_an_island_stays_closed() {
    use worldpaint_core::CategoryKind;
    use worldpaint_core::{Contour, Path};
    let mut scene = scene();
    scene
        .categories
        .push(Category::new("road", "roads", CategoryKind::Graph, 1));
    scene
        .categories
        .push(Category::new("island", "land", CategoryKind::Polygon, 2));
    // a road along the region from outside its west side to outside its east side, and an island across it
    let road: Vec<DVec2> = (0..=17)
        .map(|k| DVec2::new(-20.0 + 10.0 * k as f64, 30.0 + 0.1 * k as f64))
        .collect();
    let island: Vec<DVec2> = (0..24)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 24.0;
            DVec2::new(50.0 + 45.0 * a.cos(), 30.0 + 20.0 * a.sin())
        })
        .collect();
    scene.paths.push(Path {
        category: 1,
        points: road.clone(),
        locked: false,
    });
    scene.contours.push(Contour {
        category: 2,
        points: island.clone(),
        locked: false,
    });
    let color = color_of_region(&scene, &region(), "trees")
        .unwrap()
        .unwrap();
    let amount = 30.0;
    let Stretched { edit, .. } = stretch(
        &scene,
        &region(),
        StretchSide::East,
        amount,
        Some(&color),
        &StretchOptions::default(),
        &|_| true,
    )
    .unwrap();
    assert_eq!(
        (edit.removed_paths.clone(), edit.removed_contours.clone()),
        (vec![0], vec![0])
    );
    assert_eq!(
        (edit.added_paths.len(), edit.added_contours.len()),
        (1, 1),
        "one road, one island"
    );
    let length = |p: &[DVec2]| p.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
    let stretched = &edit.added_paths[0].points;
    println!(
        "road {:.2} m -> {:.2} m; island {:.1} m² -> {:.1} m²",
        length(&road),
        length(stretched),
        area(&island),
        area(&edit.added_contours[0].points)
    );
    // the part in the ground the east side lands on (100..130 m) goes: the road runs on from 130 m, as long as it was
    assert!((stretched[0] - road[0]).length() < 1e-9);
    assert!((stretched[stretched.len() - 1] - road[road.len() - 1]).length() < 1e-9);
    assert!(
        (length(stretched) - length(&road)).abs() < 0.005 * length(&road),
        "the road is as long, its band piece replacing the landing's"
    );
    // the island, cut across, is rejoined by two pieces across the band and gains the band between them
    let new_island = &edit.added_contours[0].points;
    let n = new_island.len();
    let bridges: Vec<f64> = (0..n)
        .map(|k| (new_island[k], new_island[(k + 1) % n]))
        .filter(|(a, b)| (b.y - a.y).abs() < 1e-9 && ((b.x - a.x).abs() - amount).abs() < 1e-6)
        .map(|(a, _)| a.y)
        .collect();
    assert_eq!(bridges.len(), 2, "{bridges:?}");
    let gained = area(new_island) - area(&island);
    let band = amount * (bridges[0] - bridges[1]).abs();
    assert!(
        (gained - band).abs() < 0.02 * band,
        "{gained} against {band}"
    );
}

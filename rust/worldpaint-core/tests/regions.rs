//! Clipped regions, the shapes the painting tools synthesize in (a brush dab without the earlier dabs, a ring of
//! a radial gradient): their area, what they contain, and the window-edge fraction α of Section 4.1, checked
//! against brute-force sampling. And prepared regions, which index large polygons for the synthesis: they answer
//! exactly as the regions do.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{PI, TAU};
use worldpaint_core::{DVec2, PreparedRegion, Region, RegionQueries};

fn circle(x: f64, y: f64, r: f64) -> Region {
    Region::Circle {
        center: DVec2::new(x, y),
        radius: r,
    }
}

/// α by sampling the circle's circumference densely.
fn sampled_alpha(region: &Region, p: DVec2, r: f64) -> f64 {
    let n = 200_000;
    (0..n)
        .filter(|k| {
            let a = TAU * (*k as f64 + 0.5) / n as f64;
            region.contains(p + DVec2::new(a.cos(), a.sin()) * r)
        })
        .count() as f64
        / n as f64
}

#[test]
fn a_disc_without_an_earlier_disc_has_the_area_of_the_crescent() {
    // two discs of radius 20 at 10 m: the lens has area 2r²acos(d/2r) − (d/2)√(4r² − d²)
    let (r, d) = (20.0f64, 10.0f64);
    let lens = 2.0 * r * r * (d / (2.0 * r)).acos() - 0.5 * d * (4.0 * r * r - d * d).sqrt();
    let crescent = Region::Clipped {
        within: vec![circle(d, 0.0, r)],
        without: vec![circle(0.0, 0.0, r)],
    };
    crescent.validate().unwrap();
    let area = crescent.area();
    let exact = PI * r * r - lens;
    println!("crescent area {area:.2} m², exact {exact:.2} m²");
    assert!((area - exact).abs() <= 0.001 * exact);
    assert!(crescent.contains(DVec2::new(d + 15.0, 0.0)));
    assert!(!crescent.contains(DVec2::new(d - 5.0, 0.0)));
    // an annulus too
    let ring = Region::Clipped {
        within: vec![circle(0.0, 0.0, 30.0)],
        without: vec![circle(0.0, 0.0, 10.0)],
    };
    assert!((ring.area() - PI * 800.0).abs() <= 0.001 * PI * 800.0);
}

#[test]
fn a_rectangles_window_edge_fraction_in_closed_form_is_its_polygons() {
    // the closed form of a rectangle against the crossings and midpoints of the same rectangle as a polygon:
    // centres inside, outside and on the sides, circles smaller than, across and larger than the rectangle
    let (lo, hi) = (DVec2::new(-10.0, 5.0), DVec2::new(30.0, 20.0));
    let rect = Region::Rect { min: lo, max: hi };
    let polygon = Region::Polygon {
        points: vec![lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)],
    };
    let prepared = PreparedRegion::new(&rect);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut worst: f64 = 0.0;
    let mut cut = 0;
    for k in 0..20_000 {
        let p = if k % 10 == 0 {
            DVec2::new(lo.x, rng.random_range(0.0..25.0)) // on a side
        } else {
            DVec2::new(rng.random_range(-30.0..50.0), rng.random_range(-10.0..35.0))
        };
        let r = rng.random_range(0.01..40.0);
        let closed = rect.circle_fraction_inside(p, r);
        assert_eq!(closed, prepared.circle_fraction_inside(p, r));
        let general = polygon.circle_fraction_inside(p, r);
        worst = worst.max((closed - general).abs());
        cut += usize::from(closed > 0.0 && closed < 1.0);
    }
    println!("largest |α rectangle − α polygon| = {worst:.2e} over {cut} cut circles");
    assert!(cut > 10_000);
    assert!(worst <= 1e-12);
}

#[test]
fn window_edge_fraction_of_clipped_regions_is_exact() {
    let regions = [
        Region::Clipped {
            within: vec![circle(10.0, 0.0, 20.0)],
            without: vec![circle(0.0, 0.0, 20.0), circle(-5.0, 8.0, 20.0)],
        },
        Region::Clipped {
            within: vec![
                Region::Rect {
                    min: DVec2::new(-30.0, -30.0),
                    max: DVec2::new(30.0, 30.0),
                },
                Region::Polygon {
                    points: vec![
                        DVec2::new(-5.0, -40.0),
                        DVec2::new(25.0, -40.0),
                        DVec2::new(15.0, 40.0),
                        DVec2::new(-15.0, 40.0),
                    ],
                },
            ],
            without: vec![circle(5.0, 5.0, 6.0)],
        },
    ];
    let mut worst: f64 = 0.0;
    for region in &regions {
        for (x, y) in [
            (20.0, 0.0),
            (12.0, 5.0),
            (0.0, 0.0),
            (5.0, -10.0),
            (10.0, 12.0),
        ] {
            for r in [1.0, 4.0, 9.0, 15.0] {
                let p = DVec2::new(x, y);
                let exact = region.circle_fraction_inside(p, r);
                let sampled = sampled_alpha(region, p, r);
                worst = worst.max((exact - sampled).abs());
            }
        }
    }
    println!("largest |α exact − α sampled| = {worst:.2e}");
    assert!(worst <= 1e-4);
}

#[test]
fn translated_regions_move_their_parts() {
    let r = Region::Clipped {
        within: vec![circle(0.0, 0.0, 5.0)],
        without: vec![circle(3.0, 0.0, 2.0)],
    };
    let t = r.translated(DVec2::new(100.0, -50.0));
    for p in [
        DVec2::new(-4.0, 0.0),
        DVec2::new(3.0, 0.0),
        DVec2::new(0.0, 4.9),
    ] {
        assert_eq!(r.contains(p), t.contains(p + DVec2::new(100.0, -50.0)));
    }
    assert!((r.area() - t.area()).abs() <= 1e-9 * r.area());
}

#[test]
fn clipped_regions_without_overlap_are_rejected() {
    let r = Region::Clipped {
        within: vec![circle(0.0, 0.0, 5.0), circle(100.0, 0.0, 5.0)],
        without: vec![],
    };
    assert!(r.validate().is_err());
    let empty = Region::Clipped {
        within: vec![],
        without: vec![],
    };
    assert!(empty.validate().is_err());
}

/// A closed outline of `n` vertices around `centre`: radius `radius` with `waves` bumps of `amplitude`.
fn wavy(n: usize, centre: DVec2, radius: f64, waves: f64, amplitude: f64) -> Region {
    Region::Polygon {
        points: (0..n)
            .map(|k| {
                let a = TAU * k as f64 / n as f64;
                centre + DVec2::new(a.cos(), a.sin()) * (radius + amplitude * (waves * a).sin())
            })
            .collect(),
    }
}

/// A staircase of `steps` unit steps up from (0, 0) and back along the axes: horizontal and vertical edges on
/// whole metres, where a query at a whole or half metre meets vertices and edges exactly.
fn staircase(steps: usize) -> Region {
    let mut points = vec![DVec2::ZERO];
    for k in 0..steps {
        let (x, y) = (k as f64, k as f64);
        points.push(DVec2::new(x + 1.0, y));
        points.push(DVec2::new(x + 1.0, y + 1.0));
    }
    points.push(DVec2::new(0.0, steps as f64));
    Region::Polygon { points }
}

/// The angles at which `C(p, r)` crosses the region's boundary, sorted.
fn crossings(region: &impl RegionQueries, p: DVec2, r: f64) -> Vec<u64> {
    let mut angles = Vec::new();
    region.push_circle_crossings(p, r, &mut angles);
    angles.sort_by(f64::total_cmp);
    angles.into_iter().map(f64::to_bits).collect()
}

/// Every query of `region` and of its prepared form at `p`, for circles of radius `radii` and the segment from
/// `p` to `q`: equal to the bit.
fn assert_same_answers(
    region: &Region,
    prepared: &PreparedRegion,
    p: DVec2,
    q: DVec2,
    radii: &[f64],
) {
    let same = |a: f64, b: f64, what: &str| {
        assert_eq!(a.to_bits(), b.to_bits(), "{what} at {p:?}: {a} vs {b}");
    };
    assert_eq!(prepared.contains(p), region.contains(p), "contains {p:?}");
    same(
        prepared.distance_to_boundary(p),
        region.distance_to_boundary(p),
        "distance",
    );
    same(
        RegionQueries::distance_outside(prepared, p),
        RegionQueries::distance_outside(region, p),
        "distance outside",
    );
    let bits = |ts: Vec<f64>| ts.into_iter().map(f64::to_bits).collect::<Vec<_>>();
    assert_eq!(
        bits(prepared.segment_crossings(p, q)),
        bits(region.segment_crossings(p, q)),
        "crossings of the segment {p:?}–{q:?}"
    );
    for &r in radii {
        same(
            prepared.circle_fraction_inside(p, r),
            region.circle_fraction_inside(p, r),
            &format!("α of radius {r}"),
        );
        same(
            prepared.distance_to_boundary_within(p, r),
            RegionQueries::distance_to_boundary_within(region, p, r),
            &format!("distance within {r}"),
        );
        assert_eq!(
            prepared.covers_disc(p, r),
            RegionQueries::covers_disc(region, p, r)
        );
        assert_eq!(
            crossings(prepared, p, r),
            crossings(region, p, r),
            "crossings of radius {r} at {p:?}"
        );
    }
}

#[test]
fn prepared_regions_answer_exactly_as_the_regions_do() {
    let outline = wavy(4096, DVec2::splat(200.0), 100.0, 40.0, 5.0);
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    // a jagged outline: random radii, so the indexes meet uneven edges
    let jagged = Region::Polygon {
        points: (0..1500)
            .map(|k| {
                let a = TAU * k as f64 / 1500.0;
                let r = 60.0 + rng.random_range(0.0..25.0);
                DVec2::new(-300.0, 50.0) + DVec2::new(a.cos(), a.sin()) * r
            })
            .collect(),
    };
    let regions = [
        outline.clone(),
        jagged.clone(),
        staircase(800),
        // the paste's region on a terrain: the outline within the terrain's box, minus a dab and a jagged hole
        Region::Clipped {
            within: vec![
                outline.clone(),
                Region::Rect {
                    min: DVec2::new(90.0, 120.0),
                    max: DVec2::new(400.0, 400.0),
                },
            ],
            without: vec![
                circle(150.0, 250.0, 20.0),
                Region::Clipped {
                    within: vec![wavy(1024, DVec2::new(250.0, 180.0), 25.0, 7.0, 3.0)],
                    without: Vec::new(),
                },
            ],
        },
        Region::Rect {
            min: DVec2::new(-10.0, 5.0),
            max: DVec2::new(70.0, 45.0),
        },
        circle(3.0, -4.0, 35.0),
        wavy(100, DVec2::ZERO, 50.0, 6.0, 4.0),
    ];
    for region in &regions {
        region.validate().unwrap();
        let prepared = PreparedRegion::new(region);
        assert_eq!(prepared.bbox(), region.bbox());
        let (lo, hi) = region.bbox();
        let (lo, hi) = (lo - DVec2::splat(30.0), hi + DVec2::splat(30.0));
        let vertices: Vec<DVec2> = match region {
            Region::Polygon { points } => points.clone(),
            Region::Clipped { within, .. } => match &within[0] {
                Region::Polygon { points } => points.clone(),
                _ => Vec::new(),
            },
            _ => Vec::new(),
        };
        for k in 0..1500 {
            let p = match (k % 4, vertices.is_empty()) {
                // anywhere around the region
                (0 | 1, _) | (_, true) => {
                    DVec2::new(rng.random_range(lo.x..hi.x), rng.random_range(lo.y..hi.y))
                }
                // on a vertex, or on an edge's midpoint
                (2, false) => {
                    let i = rng.random_range(0..vertices.len());
                    if k % 8 == 2 {
                        vertices[i]
                    } else {
                        0.5 * (vertices[i] + vertices[(i + 1) % vertices.len()])
                    }
                }
                // near the boundary
                _ => {
                    let i = rng.random_range(0..vertices.len());
                    let scale = [1e-9, 1e-3, 0.5, 3.0][rng.random_range(0..4)];
                    vertices[i]
                        + DVec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
                            * scale
                }
            };
            // a segment to a random point, a nearby one, or along the boundary (on an edge for the staircase)
            let q = match k % 3 {
                0 => DVec2::new(rng.random_range(lo.x..hi.x), rng.random_range(lo.y..hi.y)),
                1 => p + DVec2::new(rng.random_range(-2.0..2.0), rng.random_range(-2.0..2.0)),
                _ => vertices
                    .get(rng.random_range(0..vertices.len().max(1)))
                    .copied()
                    .unwrap_or(p + DVec2::X),
            };
            let d = region.distance_to_boundary(p);
            let mut radii = vec![0.3, 2.5, 10.0, 40.0, d, d * (1.0 + 1e-15), 0.0, -1.0];
            // a circle through a vertex
            if let Some(v) = vertices.get(k % vertices.len().max(1)) {
                radii.push(p.distance(*v));
            }
            assert_same_answers(region, &prepared, p, q, &radii);
        }
        // a wandering path cut at the boundary
        let mut at = 0.5 * (lo + hi);
        let path: Vec<DVec2> = (0..400)
            .map(|_| {
                at += DVec2::new(rng.random_range(-9.0..9.0), rng.random_range(-9.0..9.0));
                at
            })
            .collect();
        assert_eq!(prepared.clip_polyline(&path), region.clip_polyline(&path));
        // the same draws give the same points
        let (mut a, mut b) = (ChaCha8Rng::seed_from_u64(5), ChaCha8Rng::seed_from_u64(5));
        for _ in 0..50 {
            assert_eq!(
                prepared.sample_uniform(&mut a),
                region.sample_uniform(&mut b)
            );
        }
    }
}

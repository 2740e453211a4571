//! Clipped regions, the shapes the painting tools synthesize in (a brush dab without the earlier dabs, a ring of
//! a radial gradient): their area, what they contain, and the window-edge fraction α of Section 4.1, checked
//! against brute-force sampling.

use std::f64::consts::{PI, TAU};
use worldpaint_core::geom::DVec2;
use worldpaint_core::Region;

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

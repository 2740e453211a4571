//! Element arrangement by example (Ijiri et al. 2008), the tools of seed §5.3 and what the painting tools build on:
//! a flow field turns the pattern, a boundary curve stops it, a pattern grows on from an existing one without a
//! seam (a paste beside it, a spray dab, a stroke of overlapping dabs), noise leaves growth alone, progress is
//! reported, bad input is refused.
//! Run with `--nocapture` to see the figures.

mod common;

use common::arrangement::*;
use glam::DVec2;
use worldpaint_core::{
    grow_arrangement, grow_arrangement_around, relax_arrangement, Arrangement, Element, Error,
    FlowField, GrowthNoise, GrowthOptions, ReferenceArrangement, Region, RotationMode,
};

/// Two concentric arcs about (0, −30), drawn counter-clockwise... the flow turns about that centre.
fn two_arcs() -> Vec<Vec<DVec2>> {
    [25.0, 36.0]
        .iter()
        .map(|&r| {
            (0..=40)
                .map(|k| {
                    let a = (115.0 - 50.0 * k as f64 / 40.0f64).to_radians();
                    DVec2::new(0.0, -30.0) + r * DVec2::from_angle(a)
                })
                .collect()
        })
        .collect()
}

#[test]
fn the_flow_field_mode_turns_elements_along_the_strokes() {
    let flow = FlowField::from_curves(&two_arcs()).expect("a field");
    // between the arcs, the field follows the circles about (0, −30) (clockwise, as drawn)
    let mut worst: f64 = 0.0;
    for &p in &[
        DVec2::new(0.0, 0.0),
        DVec2::new(-8.0, 1.0),
        DVec2::new(9.0, -2.0),
    ] {
        let circle = (p - DVec2::new(0.0, -30.0)).perp() * -1.0;
        worst = worst.max(flow.direction_at(p).angle_to(circle).abs().to_degrees());
    }
    println!("flow field between the arcs: at most {worst:.2}° from the circles' tangents");
    assert!(worst < 3.0);

    let reference = hexagonal_reference();
    let region = rect((-12.0, -6.0), (12.0, 6.0));
    let grown_options = GrowthOptions {
        flow: Some(flow.clone()),
        ..options(RotationMode::Flow)
    };
    let mut grown =
        grow_arrangement(&reference, &region, DVec2::ZERO, &grown_options).expect("grows");
    relax_arrangement(&mut grown).expect("relaxes");
    let angles: Vec<f64> = grown
        .elements
        .iter()
        .map(|e| {
            let x_axis = DVec2::from_angle(e.rotation);
            x_axis
                .angle_to(flow.direction_at(e.position))
                .abs()
                .to_degrees()
        })
        .collect();
    let mean = angles.iter().sum::<f64>() / angles.len() as f64;
    let max = angles.iter().copied().fold(0.0, f64::max);
    let interior: Vec<usize> = (0..grown.elements.len())
        .filter(|&i| {
            let p = grown.elements[i].position;
            p.x.abs() < 10.0 && p.y.abs() < 4.0
        })
        .collect();
    let share = ring_share(&reference, &grown, &interior);
    let closest = closest_pair(&positions(&grown), 1.0);
    println!(
        "flow-field mode: {} elements; angle between each element's x axis and the flow: mean {mean:.2}°, max \
         {max:.2}°; same ring size {:.1} % of {} interior; closest pair {closest:.3} (r_short {:.3})",
        grown.elements.len(),
        100.0 * share,
        interior.len(),
        reference.r_short()
    );
    assert!(mean <= 5.0);
    assert!(share >= 0.8);
    assert!(closest >= reference.r_short());

    let missing = grow_arrangement(
        &reference,
        &region,
        DVec2::ZERO,
        &options(RotationMode::Flow),
    )
    .expect_err("no field");
    println!("flow mode without a field: {missing}");
    for (name, curves) in [
        ("no curve", vec![]),
        ("one point", vec![vec![DVec2::ONE]]),
        ("zero length", vec![vec![DVec2::ONE, DVec2::ONE]]),
        ("NaN", vec![vec![DVec2::ZERO, DVec2::new(f64::NAN, 1.0)]]),
    ] {
        let err = FlowField::from_curves(&curves).expect_err(name);
        println!("flow curves, {name}: {err}");
    }
    let straight = FlowField::from_curves(&[vec![DVec2::ZERO, DVec2::new(3.0, 4.0)]])
        .expect("one straight stroke");
    let d = straight.direction_at(DVec2::new(-50.0, 20.0));
    assert!((d - DVec2::new(0.6, 0.8)).length() < 1e-6, "{d}");
}

/// The boundary curve x = 3 + sin(y) from y = −20 to 20.
fn wavy_boundary() -> Vec<DVec2> {
    (0..=400)
        .map(|k| {
            let y = -20.0 + 0.1 * k as f64;
            DVec2::new(3.0 + y.sin(), y)
        })
        .collect()
}

#[test]
fn a_boundary_curve_stops_growth() {
    let reference = hexagonal_reference();
    let region = rect((-12.0, -12.0), (12.0, 12.0));
    let curve = wavy_boundary();
    let grown_options = GrowthOptions {
        boundaries: vec![curve.clone()],
        ..options(RotationMode::None)
    };
    let mut grown =
        grow_arrangement(&reference, &region, DVec2::ZERO, &grown_options).expect("grows");
    let far = grown
        .elements
        .iter()
        .filter(|e| e.position.x > 3.0 + e.position.y.sin())
        .count();
    let segment_crossings = |a: DVec2, b: DVec2| {
        curve.windows(2).any(|w| {
            let (c, d) = (w[0], w[1]);
            let o = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
            o(a, b, c) * o(a, b, d) < 0.0 && o(c, d, a) * o(c, d, b) < 0.0
        })
    };
    let crossing = grown
        .edges
        .iter()
        .filter(|&&(a, b)| {
            segment_crossings(grown.elements[a].position, grown.elements[b].position)
        })
        .count();
    let stopped: Vec<usize> = (0..grown.elements.len())
        .filter(|&i| {
            let p = grown.elements[i].position;
            grown.at_region_boundary[i] && (p.x - 3.0 - p.y.sin()).abs() < 1.5
        })
        .collect();
    let to_curve = |p: DVec2| {
        curve
            .windows(2)
            .map(|w| {
                let (c, d) = (w[0], w[1]);
                let t = ((p - c).dot(d - c) / (d - c).length_squared()).clamp(0.0, 1.0);
                p.distance(c.lerp(d, t))
            })
            .fold(f64::INFINITY, f64::min)
    };
    let gap = grown
        .elements
        .iter()
        .map(|e| to_curve(e.position))
        .fold(f64::INFINITY, f64::min);
    let r_short = reference.r_short();
    println!(
        "boundary x = 3 + sin y: {} elements, {far} on the far side, {crossing} edges across it, {} stopped by it; \
         the nearest element lies {gap:.3} m from it (r_short {r_short:.3} m)",
        grown.elements.len(),
        stopped.len()
    );
    assert!(grown.elements.len() > 200);
    assert!(gap >= r_short, "every element keeps r_short from the curve");
    assert_eq!(far, 0);
    assert_eq!(crossing, 0);
    assert!(
        stopped.len() >= 15,
        "the elements along the curve are flagged"
    );
    let before = grown.clone();
    relax_arrangement(&mut grown).expect("relaxes");
    for &i in &stopped {
        assert_eq!(grown.elements[i].position, before.elements[i].position);
    }
    let relaxed_gap = grown
        .elements
        .iter()
        .map(|e| to_curve(e.position))
        .fold(f64::INFINITY, f64::min);
    assert!(
        relaxed_gap >= r_short,
        "and keeps it through the relaxation"
    );
    let err = grow_arrangement(
        &reference,
        &region,
        DVec2::ZERO,
        &GrowthOptions {
            boundaries: vec![vec![DVec2::ZERO, DVec2::new(f64::INFINITY, 0.0)]],
            ..GrowthOptions::default()
        },
    )
    .expect_err("a curve to infinity");
    println!("boundary to infinity: {err}");
}

/// A pattern grown in the left half of a 30 × 20 m rectangle, then the right half grown on from it: the seam's
/// figures, checked; returns the left half.
fn paste_beside(reference: &ReferenceArrangement, name: &str, min_share: f64) -> Arrangement {
    let l = reference.mean_edge();
    let left_region = rect((-15.0, -10.0), (0.0, 10.0));
    let left = grow_arrangement(
        reference,
        &left_region,
        DVec2::new(-7.0, 0.0),
        &options(RotationMode::None),
    )
    .expect("the left half grows");
    let right_region = rect((0.0, -10.0), (15.0, 10.0));
    let both = grow_arrangement_around(
        reference,
        &right_region,
        &left.elements,
        None,
        &options(RotationMode::None),
        &|_| true,
    )
    .expect("the right half grows on");
    let n_left = left.elements.len();
    assert_eq!(
        &both.elements[..n_left],
        &left.elements[..],
        "existing elements kept, first"
    );
    let new = both.elements.len() - n_left;
    let outside = both.elements[n_left..]
        .iter()
        .filter(|e| !right_region.contains(e.position))
        .count();
    let seam: Vec<usize> = (0..both.elements.len())
        .filter(|&i| {
            let p = both.elements[i].position;
            p.x.abs() < 2.0 * l && p.y.abs() < 10.0 - 2.0 * l
        })
        .collect();
    let share = ring_share(reference, &both, &seam);
    let closest = closest_pair(&positions(&both), 1.0);
    let across = both
        .edges
        .iter()
        .filter(|&&(a, b)| a < n_left && b >= n_left)
        .count();
    println!(
        "{name}: paste beside a pattern: {n_left} existing + {new} new elements ({outside} outside the region), {across} \
         edges join them; within 2 edges of the seam {} elements, {:.1} % with the reference's ring size; closest \
         pair {closest:.3} (r_short {:.3})",
        seam.len(),
        100.0 * share,
        reference.r_short()
    );
    assert!(new > 200);
    assert_eq!(outside, 0);
    assert!(across >= 15, "the new pattern joins the old one");
    assert!(share >= min_share, "{name}: no gap or overlap at the seam");
    assert!(closest >= reference.r_short());
    // the existing elements' rebuilt connectivity is the one they were grown with
    let rebuilt: Vec<(usize, usize)> = both
        .edges
        .iter()
        .copied()
        .filter(|&(_, b)| b < n_left)
        .collect();
    let kept = left
        .edges
        .iter()
        .filter(|e| rebuilt.binary_search(e).is_ok())
        .count();
    println!(
        "{name}: the existing elements' rebuilt connectivity has {} edges, {kept} of the {} they were grown with",
        rebuilt.len(),
        left.edges.len()
    );
    assert!(kept as f64 >= 0.97 * left.edges.len() as f64);
    left
}

#[test]
fn a_pattern_grows_on_from_an_existing_one_without_a_seam() {
    let mut square = ReferenceArrangement::new(lattice(false, 7, |_, _| 0)).expect("valid");
    let backward: Vec<(usize, usize)> = square
        .edges()
        .into_iter()
        .filter(|&(a, b)| b - a == 6 && a % 7 != 0)
        .collect();
    for (a, b) in backward {
        square.flip(a, b).expect("a diagonal flips");
    }
    paste_beside(&square, "square lattice", 0.9);
    let reference = hexagonal_reference();
    let l = reference.mean_edge();
    let left = paste_beside(&reference, "hexagonal lattice", 0.95);

    // a spray dab over the full pattern adds nothing
    let (center, radius) = (DVec2::new(-7.3, 0.4), 3.0);
    let (nearby, over) = spray_dab(
        &reference,
        &left,
        &Region::Circle { center, radius },
        center,
    );
    println!(
        "spray dab over the full pattern: {} existing passed, {} new",
        nearby.len(),
        over.elements.len() - nearby.len()
    );
    assert!(over.elements.len() - nearby.len() <= 2);

    // spray dabs: one at the edge of the left pattern continues it, one in the empty right starts anew
    for (name, center) in [
        ("at the pattern's edge", DVec2::new(1.0, 0.0)),
        ("in empty space", DVec2::new(9.0, 0.0)),
    ] {
        let radius = 3.0;
        let dab = Region::Circle { center, radius };
        let (nearby, sprayed) = spray_dab(&reference, &left, &dab, center);
        let k = nearby.len();
        let fresh: Vec<usize> = (k..sprayed.elements.len()).collect();
        let inside = fresh
            .iter()
            .filter(|&&i| dab.contains(sprayed.elements[i].position))
            .count();
        let core: Vec<usize> = fresh
            .iter()
            .copied()
            .filter(|&i| sprayed.elements[i].position.distance(center) < radius - 1.2 * l)
            .collect();
        let share = ring_share(&reference, &sprayed, &core);
        let mut all = positions(&left);
        all.extend(fresh.iter().map(|&i| sprayed.elements[i].position));
        let closest = closest_pair(&all, 1.0);
        let joined = sprayed
            .edges
            .iter()
            .filter(|&&(a, b)| a < k && b >= k)
            .count();
        println!(
            "spray dab {name}: {k} existing passed, {} new ({inside} inside the disc), {joined} edges to the \
             existing ones; {:.1} % of {} core elements with the reference's ring size; closest pair with the \
             whole pattern {closest:.3}",
            fresh.len(),
            100.0 * share,
            core.len()
        );
        assert!(fresh.len() >= 15 && inside == fresh.len());
        assert!(share >= 0.9);
        assert!(closest >= reference.r_short());
        if k > 0 {
            assert!(joined >= 3, "the dab continues the pattern");
        }
    }
}

#[test]
fn noise_leaves_growth_alone_and_results_do_not_depend_on_the_thread_count() {
    let reference = hexagonal_reference();
    let left = grow_arrangement(
        &reference,
        &rect((-10.0, -8.0), (0.0, 8.0)),
        DVec2::new(-5.0, 0.0),
        &options(RotationMode::BestFit),
    )
    .expect("grows");
    let right = rect((0.0, -8.0), (10.0, 8.0));
    let noisy = GrowthOptions {
        noise: GrowthNoise {
            scale: 0.2,
            rotation: 0.3,
        },
        ..options(RotationMode::BestFit)
    };
    let run = |threads: usize, options: &GrowthOptions| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        pool.install(|| {
            grow_arrangement_around(&reference, &right, &left.elements, None, options, &|_| true)
                .expect("grows")
        })
    };
    let bits = |a: &Arrangement| {
        a.elements
            .iter()
            .map(|e| {
                [
                    e.position.x.to_bits(),
                    e.position.y.to_bits(),
                    e.rotation.to_bits(),
                    e.scale.to_bits(),
                ]
            })
            .collect::<Vec<_>>()
    };
    let (one, two) = (run(1, &noisy), run(2, &noisy));
    assert_eq!(bits(&one), bits(&two), "the same with 1 and 2 threads");
    let quiet = run(1, &options(RotationMode::BestFit));
    assert_eq!(
        positions(&quiet),
        positions(&one),
        "noise does not change growth"
    );
    let n = left.elements.len();
    let scales: Vec<f64> = one.elements[n..].iter().map(|e| e.scale).collect();
    let turns: Vec<f64> = one.elements[n..]
        .iter()
        .zip(&quiet.elements[n..])
        .map(|(a, b)| a.rotation - b.rotation)
        .collect();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let sd = |v: &[f64]| {
        let m = mean(v);
        (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
    };
    println!(
        "noise on {} new elements: scale mean {:.3}, relative sd {:.3} (asked 0.2), min {:.3}; rotation sd {:.3} \
         rad (asked 0.3); identical with 1 and 2 threads",
        scales.len(),
        mean(&scales),
        sd(&scales) / mean(&scales),
        scales.iter().copied().fold(f64::INFINITY, f64::min),
        sd(&turns)
    );
    assert!((mean(&scales) - 1.0).abs() < 0.05 && (sd(&scales) - 0.2).abs() < 0.05);
    assert!((sd(&turns) - 0.3).abs() < 0.06);
    assert!(
        one.elements[..n] == left.elements[..],
        "existing elements get no noise"
    );
}

#[test]
fn progress_is_reported_and_cancels() {
    let reference = hexagonal_reference();
    let region = rect((-20.0, -20.0), (20.0, 20.0));
    let reports = std::cell::RefCell::new(Vec::new());
    let grown = grow_arrangement_around(
        &reference,
        &region,
        &[],
        None,
        &GrowthOptions::default(),
        &|f| {
            reports.borrow_mut().push(f);
            true
        },
    )
    .expect("grows");
    let reports = reports.into_inner();
    println!(
        "{} elements from the centroid, progress reported {} times, last {:.2}",
        grown.elements.len(),
        reports.len(),
        reports.last().copied().unwrap_or(0.0)
    );
    assert!(reports.len() >= 3 && reports.windows(2).all(|w| w[0] <= w[1]));
    assert!(region.contains(grown.elements[0].position));
    let cancelled = grow_arrangement_around(
        &reference,
        &region,
        &[],
        None,
        &GrowthOptions::default(),
        &|_| false,
    );
    assert!(matches!(cancelled, Err(Error::Cancelled)));
}

#[test]
fn a_long_boundary_curve_keeps_growth_fast() {
    let reference = hexagonal_reference();
    let region = rect((-12.0, -12.0), (12.0, 12.0));
    // the wave of `a_boundary_curve_stops_growth` drawn with 200,001 points
    let curve: Vec<DVec2> = (0..=200_000)
        .map(|k| {
            let y = -20.0 + 0.0002 * k as f64;
            DVec2::new(3.0 + y.sin(), y)
        })
        .collect();
    let t0 = std::time::Instant::now();
    let grown = grow_arrangement(
        &reference,
        &region,
        DVec2::ZERO,
        &GrowthOptions {
            boundaries: vec![curve, vec![DVec2::ONE], vec![DVec2::ONE, DVec2::ONE]],
            ..options(RotationMode::None)
        },
    )
    .expect("grows");
    let far = grown
        .elements
        .iter()
        .filter(|e| e.position.x > 3.0 + e.position.y.sin())
        .count();
    println!(
        "boundary of 200,001 points (and a one-point and a zero-length curve): {} elements, {far} on the far side, \
         {:.0} ms",
        grown.elements.len(),
        1e3 * t0.elapsed().as_secs_f64()
    );
    assert!(grown.elements.len() > 200);
    assert_eq!(far, 0);
}

#[test]
fn bad_input_to_grow_around_is_refused_with_clear_messages() {
    let reference = hexagonal_reference();
    let region = rect((0.0, 0.0), (10.0, 10.0));
    let run =
        |region: &Region, existing: &[Element], start: Option<DVec2>, options: &GrowthOptions| {
            grow_arrangement_around(&reference, region, existing, start, options, &|_| true)
        };
    let fine = GrowthOptions::default();
    let nan = element(DVec2::new(f64::NAN, 1.0), 0);
    let covered = Region::Clipped {
        within: vec![region.clone()],
        without: vec![rect((-1.0, -1.0), (11.0, 11.0))],
    };
    let cases: Vec<(&str, worldpaint_core::Result<Arrangement>, &str)> = vec![
        (
            "NaN existing element",
            run(&region, &[nan], None, &fine),
            "non-finite",
        ),
        (
            "NaN start",
            run(&region, &[], Some(DVec2::new(f64::NAN, 0.0)), &fine),
            "growth start",
        ),
        (
            "start outside",
            run(&region, &[], Some(DVec2::new(20.0, 0.0)), &fine),
            "growth start",
        ),
        (
            "flat region",
            run(&rect((0.0, 0.0), (10.0, 0.0)), &[], None, &fine),
            "region",
        ),
        (
            "region cut away entirely",
            run(&covered, &[], None, &fine),
            "region",
        ),
        (
            "negative noise",
            run(
                &region,
                &[],
                None,
                &GrowthOptions {
                    noise: GrowthNoise {
                        scale: -1.0,
                        rotation: 0.0,
                    },
                    ..GrowthOptions::default()
                },
            ),
            "scale noise",
        ),
        (
            "no elements",
            run(
                &region,
                &[],
                None,
                &GrowthOptions {
                    max_elements: 0,
                    ..GrowthOptions::default()
                },
            ),
            "max elements",
        ),
    ];
    for (name, result, words) in cases {
        match result {
            Ok(_) => panic!("{name}: accepted"),
            Err(err) => {
                println!("{name}: {err}");
                assert!(err.to_string().contains(words), "{name}: {err}");
            }
        }
    }
    // existing elements at one place, far from the region, or of a symbol the reference lacks are taken as they are
    let odd = vec![
        element(DVec2::new(5.0, 5.0), 0),
        element(DVec2::new(5.0, 5.0), 0),
        element(DVec2::new(500.0, 5.0), 0),
        element(DVec2::new(2.0, 2.0), 9),
    ];
    let read: Element =
        serde_json::from_str(r#"{"position":[1.0,2.0],"symbol":3,"rotation":0.5}"#).expect("reads");
    assert_eq!(
        read.scale, 1.0,
        "an element written before scales existed has scale 1"
    );
    let grown = run(&region, &odd, None, &fine).expect("grows");
    assert_eq!(&grown.elements[..4], &odd[..]);
    println!(
        "odd existing elements: {} new elements",
        grown.elements.len() - 4
    );
}

#[test]
fn a_spray_stroke_of_overlapping_dabs_paints_one_pattern() {
    let reference = hexagonal_reference();
    let l = reference.mean_edge();
    let radius = 3.0;
    let mut scene: Vec<Element> = Vec::new();
    let mut slowest: f64 = 0.0;
    // a stroke along a gentle curve, a dab every 1.5 m
    let centers: Vec<DVec2> = (0..12)
        .map(|k| DVec2::new(1.5 * k as f64, 2.0 * (0.3 * k as f64).sin()))
        .collect();
    for (k, &center) in centers.iter().enumerate() {
        let nearby: Vec<Element> = scene
            .iter()
            .filter(|e| e.position.distance(center) <= radius + 3.0 * l)
            .copied()
            .collect();
        let t0 = std::time::Instant::now();
        let dab = grow_arrangement_around(
            &reference,
            &Region::Circle { center, radius },
            &nearby,
            Some(center),
            &GrowthOptions {
                seed: k as u64,
                ..options(RotationMode::None)
            },
            &|_| true,
        )
        .expect("a dab grows");
        slowest = slowest.max(t0.elapsed().as_secs_f64());
        scene.extend_from_slice(&dab.elements[nearby.len()..]);
    }
    let points: Vec<DVec2> = scene.iter().map(|e| e.position).collect();
    let closest = closest_pair(&points, 1.0);
    // the painted pattern's own Delaunay connectivity: an unambiguous one on a hexagonal lattice
    let painted = ReferenceArrangement::new(scene.clone()).expect("a triangulation");
    // interior: the painted area (the union of the dabs) holds a circle of 1.3 mean edges around the element
    let painted_area = |p: DVec2| centers.iter().any(|c| c.distance(p) <= radius);
    let interior: Vec<usize> = (0..scene.len())
        .filter(|&i| {
            !painted.is_boundary(i)
                && (0..16).all(|k| {
                    let around = DVec2::from_angle(k as f64 * std::f64::consts::TAU / 16.0);
                    painted_area(scene[i].position + 1.3 * l * around)
                })
        })
        .collect();
    let six = interior
        .iter()
        .filter(|&&i| painted.ring(i).len() == 6)
        .count() as f64
        / interior.len() as f64;
    println!(
        "spray stroke of 12 overlapping dabs: {} elements, {} interior with 6 Delaunay neighbours {:.1} %; closest \
         pair {closest:.3} (r_short {:.3}); slowest dab {:.1} ms",
        scene.len(),
        interior.len(),
        100.0 * six,
        reference.r_short(),
        1e3 * slowest
    );
    assert!(scene.len() > 100);
    assert!(closest >= reference.r_short());
    assert!(six >= 0.95, "the dabs join without seams");
}

/// A spray dab of `reference` over the disc `dab` centred at `center`, growing from the elements of `pattern`
/// within three mean edges of it (the spray tool's context): those elements and the grown arrangement.
fn spray_dab(
    reference: &ReferenceArrangement,
    pattern: &Arrangement,
    dab: &Region,
    center: DVec2,
) -> (Vec<Element>, Arrangement) {
    let Region::Circle { radius, .. } = *dab else {
        panic!("a dab is a disc")
    };
    let reach = radius + 3.0 * reference.mean_edge();
    let nearby: Vec<Element> = pattern
        .elements
        .iter()
        .filter(|e| e.position.distance(center) <= reach)
        .copied()
        .collect();
    let grown = grow_arrangement_around(
        reference,
        dab,
        &nearby,
        Some(center),
        &options(RotationMode::None),
        &|_| true,
    )
    .expect("a dab grows");
    (nearby, grown)
}

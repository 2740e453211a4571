//! Land parcels and building footprints (thesis 3.3): layouts checked for what a village plan must hold —
//! parcels pairwise disjoint, simple, off the road corridor, water and walls; footprints inside their parcels,
//! off the roads and apart except along shared walls — and the shapes the thesis describes: almost quadrilateral
//! parcels on flat land, parcels stretched along the contour lines on a slope, corner lots, seeds suppressed when
//! they lose their road front. The parcel statistics of 3.5 are measured on the real cadastre of Épinay-sur-Orge
//! (read beside the project: `#[ignore]`d with the reason, `make test-rust` runs it where present) and on a
//! synthetic village.
//!
//! Figures seen (cell 1 m, road width 5 m, `--nocapture`): cadastre 4,241 parcels, 3.538 neighbours and 5.415
//! edges per parcel (10.578 counting every vertex); synthetic village 40 parcels, 2.750 neighbours and 4.100
//! edges (the thesis: real village 2.812 and 4.068, its model 2.873 and 4.29); 100 parcels on 1 km² in about
//! 0.25 s on two threads (the ignored timing test).

mod common;

mod village {
    use crate::common::real_data::{real_data_dir, require, Projection};
    use std::f64::consts::PI;
    use std::path::Path;
    use worldpaint_core::Heightfield;
    use worldpaint_core::ParcelParams;
    use worldpaint_core::{house_footprint, house_footprints};
    use worldpaint_core::{
        parcel_statistics, parcel_statistics_with, parcels, parcels_with, ParcelOptions, ParcelSeed,
    };
    use worldpaint_core::{
        polygon_signed_area, segment_distance, segments_distance, DVec2, Region,
    };
    use worldpaint_core::{Environment, HouseFootprint, Land, Parcel, Road};

    const CELL: f64 = 1.0;
    const WIDTH: f64 = 5.0;
    const HALF: f64 = 0.5 * WIDTH;
    /// Terraced houses: as wide as a narrow parcel at most, so that they fill it.
    const HOUSE_MIN: [f64; 2] = [4.0, 4.0];
    const HOUSE_MAX: [f64; 2] = [12.0, 9.0];
    const SNAP: f64 = 0.75;

    /// A square of land `size` metres wide with heights `h(p) = gradient · p`.
    fn land(size: f64, gradient: DVec2, environment: &Environment) -> Land {
        let n = size as usize + 1;
        let heights: Vec<f32> = (0..n * n)
            .map(|k| gradient.dot(DVec2::new((k % n) as f64, (k / n) as f64)) as f32)
            .collect();
        let terrain = Heightfield::new(DVec2::ZERO, 1.0, n, n, heights).expect("terrain");
        let region = Region::Rect {
            min: DVec2::ZERO,
            max: DVec2::splat(size),
        };
        Land::new(&terrain, &region, environment, CELL).expect("land")
    }

    fn params(budget: f64, road_reach: f64, slope_weight: f64) -> ParcelParams {
        ParcelParams {
            budget,
            road_reach,
            conquest_weight: 1.0,
            slope_weight,
            fill: 0.0,
        }
    }

    fn road(points: &[(f64, f64)]) -> Road {
        Road {
            points: points.iter().map(|&(x, y)| DVec2::new(x, y)).collect(),
        }
    }

    fn seeds<'a>(positions: &[DVec2], p: &'a ParcelParams) -> Vec<ParcelSeed<'a>> {
        positions
            .iter()
            .map(|&position| ParcelSeed {
                position,
                params: p,
            })
            .collect()
    }

    fn contains(poly: &[DVec2], p: DVec2) -> bool {
        Region::Polygon {
            points: poly.to_vec(),
        }
        .contains(p)
    }

    fn boundary_distance(poly: &[DVec2], p: DVec2) -> f64 {
        (0..poly.len())
            .map(|i| segment_distance(p, poly[i], poly[(i + 1) % poly.len()]))
            .fold(f64::INFINITY, f64::min)
    }

    fn road_gap(roads: &[Road], a: DVec2, b: DVec2) -> f64 {
        roads
            .iter()
            .flat_map(|r| r.points.windows(2))
            .map(|w| segments_distance(a, b, w[0], w[1]))
            .fold(f64::INFINITY, f64::min)
    }

    /// No two edges meet except consecutive ones at their shared vertex.
    fn is_simple(poly: &[DVec2]) -> bool {
        let m = poly.len();
        if m < 3 || polygon_signed_area(poly) <= 0.0 {
            return false;
        }
        for i in 0..m {
            for j in i + 1..m {
                let adjacent = j == i + 1 || (i == 0 && j == m - 1);
                let (a, b) = (poly[i], poly[(i + 1) % m]);
                let (c, d) = (poly[j], poly[(j + 1) % m]);
                if adjacent {
                    // consecutive edges must not fold back onto each other
                    let shared = if j == i + 1 { b } else { a };
                    let (u, v) = if j == i + 1 {
                        (a - b, d - c)
                    } else {
                        (b - a, c - d)
                    };
                    if u.perp_dot(v).abs() < 1e-12 && u.dot(v) > 0.0 {
                        return false;
                    }
                    let _ = shared;
                    continue;
                }
                if segments_distance(a, b, c, d) < 1e-9 {
                    return false;
                }
            }
        }
        true
    }

    /// The interior angles of a counter-clockwise polygon (radians).
    fn interior_angles(poly: &[DVec2]) -> Vec<(DVec2, f64)> {
        let m = poly.len();
        (0..m)
            .map(|i| {
                let (p, v, n) = (poly[(i + m - 1) % m], poly[i], poly[(i + 1) % m]);
                let (a, b) = (n - v, p - v);
                let mut angle = a.perp_dot(b).atan2(a.dot(b));
                if angle < 0.0 {
                    angle += 2.0 * PI;
                }
                (v, angle)
            })
            .collect()
    }

    /// Sample points (on a lattice offset from every cell line) lying inside two parcels at once.
    fn overlapping_samples(polys: &[&[DVec2]], step: f64) -> usize {
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for p in polys {
            for q in p.iter() {
                lo = lo.min(*q);
                hi = hi.max(*q);
            }
        }
        let boxes: Vec<(DVec2, DVec2)> = polys
            .iter()
            .map(|p| {
                p.iter().fold(
                    (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                    |(a, b), q| (a.min(*q), b.max(*q)),
                )
            })
            .collect();
        let mut count = 0;
        let mut y = lo.y + 0.0567;
        while y < hi.y {
            let mut x = lo.x + 0.0123;
            while x < hi.x {
                let p = DVec2::new(x, y);
                let inside = polys
                    .iter()
                    .zip(&boxes)
                    .filter(|(poly, (a, b))| {
                        p.cmpge(*a).all() && p.cmple(*b).all() && contains(poly, p)
                    })
                    .count();
                if inside > 1 {
                    count += 1;
                }
                x += step;
            }
            y += step;
        }
        count
    }

    /// Whether the interiors of two convex quads overlap (separating axis test with a tolerance).
    fn quads_overlap(a: &[DVec2; 4], b: &[DVec2; 4]) -> bool {
        for quad in [a, b] {
            for k in 0..4 {
                let e = quad[(k + 1) % 4] - quad[k];
                let axis = DVec2::new(-e.y, e.x).normalize();
                let span = |q: &[DVec2; 4]| {
                    q.iter()
                        .map(|p| p.dot(axis))
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                            (lo.min(v), hi.max(v))
                        })
                };
                let ((a0, a1), (b0, b1)) = (span(a), span(b));
                if a1.min(b1) - a0.max(b0) <= 1e-6 {
                    return false;
                }
            }
        }
        true
    }

    /// The longest stretch along which a wall of `a` and a wall of `b` lie on one line.
    fn shared_wall(a: &HouseFootprint, b: &HouseFootprint) -> f64 {
        let mut best: f64 = 0.0;
        for i in 0..4 {
            for j in 0..4 {
                let (p, q) = (a.corners[i], a.corners[(i + 1) % 4]);
                let (r, s) = (b.corners[j], b.corners[(j + 1) % 4]);
                let len = p.distance(q);
                let dir = (q - p) / len;
                if dir.perp_dot(r - p).abs() > 1e-6 || dir.perp_dot(s - p).abs() > 1e-6 {
                    continue;
                }
                let (u, v) = ((r - p).dot(dir), (s - p).dot(dir));
                best = best.max(len.min(u.max(v)) - 0f64.max(u.min(v)));
            }
        }
        best
    }

    /// Whether a footprint lies inside its parcel: corners inside or on the contour, no contour vertex inside the
    /// quad, and its inner points inside the parcel.
    fn footprint_inside(f: &HouseFootprint, poly: &[DVec2]) -> bool {
        let corners_in = f
            .corners
            .iter()
            .all(|&c| contains(poly, c) || boundary_distance(poly, c) < 1e-6);
        let strictly_in_quad = |p: DVec2| {
            (0..4).all(|k| {
                let (a, b) = (f.corners[k], f.corners[(k + 1) % 4]);
                (b - a).perp_dot(p - a) / a.distance(b) > 1e-6
            })
        };
        let no_vertex_in = poly.iter().all(|&p| !strictly_in_quad(p));
        let mut samples_in = true;
        for s in 1..10 {
            for t in 1..10 {
                let (u, v) = (s as f64 / 10.0, t as f64 / 10.0);
                let a = f.corners[0] + (f.corners[1] - f.corners[0]) * u;
                let b = f.corners[3] + (f.corners[2] - f.corners[3]) * u;
                let p = a + (b - a) * v;
                samples_in &= contains(poly, p) || boundary_distance(poly, p) < 1e-6;
            }
        }
        corners_in && no_vertex_in && samples_in
    }

    /// Everything a village plan must hold, asserted; returns the footprints.
    fn check_layout(
        land: &Land,
        roads: &[Road],
        result: &[Option<Parcel>],
        footprints: &[Option<HouseFootprint>],
    ) {
        let got: Vec<&Parcel> = result.iter().flatten().collect();
        for p in &got {
            assert!(
                is_simple(&p.contour),
                "parcel {} is not a simple ccw polygon: {:?}",
                p.seed,
                p.contour
            );
            for i in 0..p.contour.len() {
                let (a, b) = (p.contour[i], p.contour[(i + 1) % p.contour.len()]);
                let gap = road_gap(roads, a, b);
                assert!(
                    gap >= HALF - 1e-9,
                    "parcel {} comes {gap:.3} m from a road centre line",
                    p.seed
                );
            }
            for r in roads {
                for w in r.points.windows(2) {
                    for s in 0..=100 {
                        let q = w[0] + (w[1] - w[0]) * (s as f64 / 100.0);
                        assert!(
                            !contains(&p.contour, q),
                            "parcel {} holds a road point {q:?}",
                            p.seed
                        );
                    }
                }
            }
            // no water, wall or out-of-region node inside a parcel
            for k in 0..land.grid().len() {
                if !land.buildable(k) {
                    let q = land.grid().point_of(k);
                    assert!(
                        !contains(&p.contour, q) || boundary_distance(&p.contour, q) < 1e-6,
                        "parcel {} holds the unbuildable node {q:?}",
                        p.seed
                    );
                }
            }
        }
        let polys: Vec<&[DVec2]> = got.iter().map(|p| p.contour.as_slice()).collect();
        assert_eq!(overlapping_samples(&polys, 0.25), 0, "parcels overlap");
        let fps: Vec<&HouseFootprint> = footprints.iter().flatten().collect();
        for f in &fps {
            let parcel = got
                .iter()
                .find(|p| p.seed == f.seed)
                .expect("the footprint's parcel");
            assert!(
                footprint_inside(f, &parcel.contour),
                "footprint {} leaves its parcel: {f:?}",
                f.seed
            );
            for k in 0..4 {
                let gap = road_gap(roads, f.corners[k], f.corners[(k + 1) % 4]);
                assert!(
                    gap >= HALF - 1e-9,
                    "footprint {} comes {gap:.3} m from a road",
                    f.seed
                );
            }
        }
        for (i, a) in fps.iter().enumerate() {
            for b in &fps[i + 1..] {
                assert!(
                    !quads_overlap(&a.corners, &b.corners),
                    "footprints {} and {} overlap",
                    a.seed,
                    b.seed
                );
            }
        }
    }

    fn footprints_of(result: &[Option<Parcel>], roads: &[Road]) -> Vec<Option<HouseFootprint>> {
        let got: Vec<Parcel> = result.iter().flatten().cloned().collect();
        let sizes = vec![(HOUSE_MIN, HOUSE_MAX); got.len()];
        house_footprints(&got, &sizes, roads, WIDTH, SNAP).expect("footprints")
    }

    fn contours(result: &[Option<Parcel>]) -> Vec<Vec<DVec2>> {
        result.iter().flatten().map(|p| p.contour.clone()).collect()
    }

    /// Two rows of seeds along a straight street.
    fn street(count: usize, spacing: f64) -> (Vec<Road>, Vec<DVec2>) {
        let roads = vec![road(&[(10.0, 100.0), (190.0, 100.0)])];
        let mut s = Vec::new();
        for k in 0..count {
            let x = 100.0 - 0.5 * spacing * (count - 1) as f64 + spacing * k as f64;
            s.push(DVec2::new(x, 106.0));
            s.push(DVec2::new(x + 0.3 * spacing, 94.0));
        }
        (roads, s)
    }

    /// A village of three streets: a main street, a second street behind its northern row and a cross street, with
    /// seeds on both sides (the rows of the two parallel streets meet at the back).
    fn village_layout() -> (Vec<Road>, Vec<DVec2>) {
        let roads = vec![
            road(&[(10.0, 100.0), (100.0, 100.0), (190.0, 100.0)]),
            road(&[(30.0, 136.0), (100.0, 136.0), (170.0, 136.0)]),
            road(&[
                (100.0, 20.0),
                (100.0, 100.0),
                (100.0, 136.0),
                (100.0, 185.0),
            ]),
        ];
        let mut s = Vec::new();
        for k in 0..7 {
            let x = 37.0 + 11.0 * k as f64;
            s.push(DVec2::new(x, 106.0));
            s.push(DVec2::new(200.0 - x, 106.0));
            s.push(DVec2::new(x + 4.0, 130.0));
            s.push(DVec2::new(196.0 - x, 130.0));
        }
        for k in 0..4 {
            let x = 45.0 + 12.0 * k as f64;
            s.push(DVec2::new(x, 94.0));
            s.push(DVec2::new(200.0 - x, 142.0));
        }
        for k in 0..3 {
            let y = 30.0 + 13.0 * k as f64;
            s.push(DVec2::new(106.0, y));
            s.push(DVec2::new(94.0, y + 6.0));
        }
        (roads, s)
    }

    #[test]
    fn street_layout_with_water_and_a_wall_is_valid() {
        let environment = Environment {
            water_areas: vec![vec![
                DVec2::new(60.0, 108.0),
                DVec2::new(75.0, 108.0),
                DVec2::new(75.0, 118.0),
                DVec2::new(60.0, 118.0),
            ]],
            walls: vec![vec![
                DVec2::new(120.0, 110.0),
                DVec2::new(160.0, 110.0),
                DVec2::new(160.0, 150.0),
                DVec2::new(120.0, 150.0),
            ]],
            ..Default::default()
        };
        let land = land(200.0, DVec2::ZERO, &environment);
        let (roads, positions) = street(12, 10.0);
        let p = params(22.0, 6.0, 0.0);
        let result = parcels(&land, &roads, WIDTH, &seeds(&positions, &p), CELL).expect("parcels");
        let fps = footprints_of(&result, &roads);
        check_layout(&land, &roads, &result, &fps);
        let got = result.iter().flatten().count();
        let houses = fps.iter().flatten().count();
        println!(
            "street with a pond and a wall: {got} parcels of {}, {houses} footprints",
            positions.len()
        );
        assert!(got >= positions.len() - 2, "only {got} parcels");
        assert!(
            houses >= got - 3,
            "only {houses} footprints for {got} parcels"
        );
    }

    #[test]
    fn village_layout_is_valid() {
        let land = land(200.0, DVec2::new(0.02, 0.05), &Environment::default());
        let (roads, positions) = village_layout();
        let p = params(20.0, 6.0, 5.0);
        let result = parcels(&land, &roads, WIDTH, &seeds(&positions, &p), CELL).expect("parcels");
        let fps = footprints_of(&result, &roads);
        check_layout(&land, &roads, &result, &fps);
    }

    #[test]
    fn village_terraced_houses_share_walls() {
        let land = land(200.0, DVec2::ZERO, &Environment::default());
        let roads = vec![road(&[(10.0, 100.0), (190.0, 100.0)])];
        // a row of seeds 8 m apart: the inner parcels have 8 m fronts, narrower than the houses may be
        let positions: Vec<DVec2> = (0..5)
            .map(|k| DVec2::new(84.0 + 8.0 * k as f64, 106.0))
            .collect();
        let p = params(16.0, 4.0, 0.0);
        let result = parcels(&land, &roads, WIDTH, &seeds(&positions, &p), CELL).expect("parcels");
        let fps = footprints_of(&result, &roads);
        check_layout(&land, &roads, &result, &fps);
        for k in 1..3 {
            let (Some(a), Some(b)) = (&fps[k], &fps[k + 1]) else {
                panic!("footprints expected: {fps:?}");
            };
            let wall = shared_wall(a, b);
            println!("terraced houses {k} and {}: shared wall {wall:.2} m", k + 1);
            assert!(
                wall >= 4.0,
                "houses {k} and {} share {wall:.2} m of wall",
                k + 1
            );
        }
        for f in fps[1..4].iter().flatten() {
            let front = f.corners[0].distance(f.corners[1]);
            let front_gap = road_gap(&roads, f.corners[0], f.corners[1]);
            assert!(
                front_gap < HALF + 2.0,
                "the front wall stands {front_gap:.2} m from the road centre"
            );
            assert!(
                front >= 7.0,
                "front wall {front:.2} m: the house does not fill its 8 m frontage"
            );
        }
    }

    #[test]
    fn village_parcels_on_a_flat_street_are_quadrilaterals_along_the_road() {
        let land = land(200.0, DVec2::ZERO, &Environment::default());
        let (roads, positions) = street(10, 11.0);
        let p = params(20.0, 6.0, 0.0);
        let result = parcels(&land, &roads, WIDTH, &seeds(&positions, &p), CELL).expect("parcels");
        check_layout(&land, &roads, &result, &footprints_of(&result, &roads));
        let stats = parcel_statistics(&contours(&result), 1.0);
        // contour length along the road tangent (x) or normal (y), within 5°
        let (mut aligned, mut total) = (0.0, 0.0);
        for poly in contours(&result) {
            for i in 0..poly.len() {
                let e = poly[(i + 1) % poly.len()] - poly[i];
                let off_axis = e.x.abs().min(e.y.abs()) / e.length();
                total += e.length();
                if off_axis < 5f64.to_radians().sin() {
                    aligned += e.length();
                }
            }
        }
        println!(
            "flat street: {stats:?}; {:.1}% of the contour length along the road's tangent or normal",
            100.0 * aligned / total
        );
        assert_eq!(stats.parcels, positions.len());
        assert!(
            (4.0..=6.0).contains(&stats.mean_edges),
            "mean edges {}",
            stats.mean_edges
        );
        assert!(
            aligned / total >= 0.9,
            "only {:.2} of the contour is aligned",
            aligned / total
        );
    }

    /// Extent of the parcel of one seed along x and along y.
    fn single_parcel_extent(gradient: DVec2, roads: &[Road], seed: DVec2) -> DVec2 {
        let land = land(200.0, gradient, &Environment::default());
        let p = params(20.0, 6.0, 10.0);
        let result = parcels(&land, roads, WIDTH, &seeds(&[seed], &p), CELL).expect("parcels");
        let poly = &result[0].as_ref().expect("a parcel").contour;
        let (lo, hi) = poly.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(a, b), q| (a.min(*q), b.max(*q)),
        );
        hi - lo
    }

    #[test]
    fn village_parcels_on_a_slope_stretch_along_the_contour_lines() {
        // the slope rises along y (grade 0.3): contour lines run along x
        let slope = DVec2::new(0.0, 0.3);
        // a road along a contour line, and a road straight up the slope
        let along = vec![road(&[(10.0, 100.0), (190.0, 100.0)])];
        let up = vec![road(&[(100.0, 10.0), (100.0, 190.0)])];
        for (name, roads, seed) in [
            (
                "road along the contour lines",
                &along,
                DVec2::new(100.0, 106.0),
            ),
            ("road up the slope", &up, DVec2::new(106.0, 100.0)),
        ] {
            let flat = single_parcel_extent(DVec2::ZERO, roads, seed);
            let sloped = single_parcel_extent(slope, roads, seed);
            // extent along the contour lines (x) over extent along the gradient (y)
            let (rf, rs) = (flat.x / flat.y, sloped.x / sloped.y);
            println!(
                "{name}: flat {:.0} x {:.0} m (ratio {rf:.2}), slope {:.0} x {:.0} m (ratio {rs:.2})",
                flat.x, flat.y, sloped.x, sloped.y
            );
            assert!(
                rs >= 1.3 * rf,
                "{name}: the slope does not stretch the parcel along the contour lines"
            );
            assert!(
                sloped.y < 0.8 * flat.y,
                "{name}: the parcel reaches as far up the slope as on flat land"
            );
        }
    }

    #[test]
    fn village_corner_lots_take_the_corners_without_sharp_angles() {
        let land = land(200.0, DVec2::ZERO, &Environment::default());
        let roads = vec![
            road(&[(10.0, 100.0), (100.0, 100.0), (190.0, 100.0)]),
            road(&[(100.0, 10.0), (100.0, 100.0), (100.0, 190.0)]),
        ];
        // in each quarter, one seed on each road at the same distance from the junction
        let mut positions = Vec::new();
        for (sx, sy) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)] {
            for d in [9.0, 22.0, 35.0] {
                positions.push(DVec2::new(100.0 + sx * d, 100.0 + sy * 6.0));
                positions.push(DVec2::new(100.0 + sx * 6.0, 100.0 + sy * d));
            }
        }
        let p = params(16.0, 6.0, 0.0);
        let run = |options: &ParcelOptions| {
            parcels_with(
                &land,
                &roads,
                WIDTH,
                &seeds(&positions, &p),
                CELL,
                options,
                &|_| true,
            )
            .expect("parcels")
        };
        let with = run(&ParcelOptions::default());
        check_layout(&land, &roads, &with, &footprints_of(&with, &roads));
        let without = run(&ParcelOptions {
            corner_angle_degrees: 0.0,
            ..Default::default()
        });
        let smallest = |result: &[Option<Parcel>]| {
            result
                .iter()
                .flatten()
                .flat_map(|p| interior_angles(&p.contour))
                .filter(|(v, _)| v.distance(DVec2::new(100.0, 100.0)) < 40.0)
                .map(|(_, a)| a.to_degrees())
                .fold(360.0, f64::min)
        };
        let corner_owners = |result: &[Option<Parcel>]| -> Vec<usize> {
            [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)]
                .iter()
                .map(|&(sx, sy)| {
                    let corner = DVec2::new(100.0 + sx * (HALF + 1.5), 100.0 + sy * (HALF + 1.5));
                    result
                        .iter()
                        .flatten()
                        .filter(|p| contains(&p.contour, corner))
                        .count()
                })
                .collect()
        };
        let (a_with, a_without) = (smallest(&with), smallest(&without));
        println!(
            "junction: smallest parcel angle {a_with:.1}° with corner conquest, {a_without:.1}° without; \
             parcels {} and {} of {}; owners of the four corners {:?}",
            with.iter().flatten().count(),
            without.iter().flatten().count(),
            positions.len(),
            corner_owners(&with)
        );
        assert_eq!(
            corner_owners(&with),
            vec![1; 4],
            "each corner belongs to exactly one parcel"
        );
        assert!(
            a_with >= 30.0,
            "a parcel has an angle of {a_with:.1}° near the junction"
        );
        assert!(a_without < a_with, "corner conquest changes nothing");
        // the corner lot fronts both roads (as far as its road reach, 6 m, past the corner's foot)
        for (sx, sy) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)] {
            let on_x = DVec2::new(100.0 + sx * 8.0, 100.0 + sy * (HALF + 1.5));
            let on_y = DVec2::new(100.0 + sx * (HALF + 1.5), 100.0 + sy * 8.0);
            let owner = |q: DVec2| {
                with.iter()
                    .flatten()
                    .find(|p| contains(&p.contour, q))
                    .map(|p| p.seed)
            };
            assert!(
                owner(on_x).is_some() && owner(on_x) == owner(on_y),
                "corner ({sx}, {sy}) is not one lot"
            );
        }
    }

    #[test]
    fn village_seeds_without_a_road_front_get_no_parcel() {
        let land = land(200.0, DVec2::ZERO, &Environment::default());
        let roads = vec![road(&[(10.0, 100.0), (190.0, 100.0)])];
        // seeds entering the road at the same cell: the first keeps it, the other has no road front
        let positions = [
            DVec2::new(100.0, 106.0),
            DVec2::new(100.3, 109.0),
            DVec2::new(60.0, 106.0),
            DVec2::new(72.0, 106.0),
            DVec2::new(72.4, 130.0),
        ];
        let p = params(16.0, 6.0, 0.0);
        let result = parcels(&land, &roads, WIDTH, &seeds(&positions, &p), CELL).expect("parcels");
        let got: Vec<bool> = result.iter().map(|r| r.is_some()).collect();
        println!("parcels: {got:?}");
        assert_eq!(got, vec![true, false, true, true, false]);
        // a corner lot annexing a short-fronted neighbour's whole front
        let roads = vec![
            road(&[(10.0, 100.0), (100.0, 100.0), (190.0, 100.0)]),
            road(&[(100.0, 100.0), (100.0, 190.0)]),
        ];
        let positions = [DVec2::new(106.0, 106.0), DVec2::new(106.0, 108.0)];
        let short = ParcelParams {
            road_reach: 2.0,
            ..p
        };
        let mut s = seeds(&positions, &p);
        s[1].params = &short;
        let result = parcels(&land, &roads, WIDTH, &s, CELL).expect("parcels");
        assert!(
            result[0].is_some() && result[1].is_none(),
            "{:?}",
            result.iter().map(|r| r.is_some()).collect::<Vec<_>>()
        );
    }

    /// The cadastre's parcels, projected from lon/lat to metres around their centre (equirectangular).
    fn cadastre(path: &Path) -> Result<Vec<Vec<DVec2>>, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let json: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| format!("not JSON: {e}"))?;
        let features = json["features"].as_array().ok_or("no features")?;
        let mut rings: Vec<Vec<(f64, f64)>> = Vec::new();
        for f in features {
            let geometry = &f["geometry"];
            let polygons: Vec<&serde_json::Value> = match geometry["type"].as_str() {
                Some("Polygon") => vec![&geometry["coordinates"]],
                Some("MultiPolygon") => geometry["coordinates"]
                    .as_array()
                    .map(|a| a.iter().collect())
                    .unwrap_or_default(),
                _ => continue,
            };
            for poly in polygons {
                let Some(outer) = poly.get(0).and_then(|r| r.as_array()) else {
                    continue;
                };
                let ring: Vec<(f64, f64)> = outer
                    .iter()
                    .filter_map(|c| Some((c.get(0)?.as_f64()?, c.get(1)?.as_f64()?)))
                    .collect();
                if ring.len() >= 3 {
                    rings.push(ring);
                }
            }
        }
        let n: usize = rings.iter().map(|r| r.len()).sum();
        let (lon0, lat0) = rings
            .iter()
            .flatten()
            .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x, b + y));
        let projection = Projection::new([lon0 / n as f64, lat0 / n as f64]);
        Ok(rings
            .into_iter()
            .map(|r| {
                r.into_iter()
                    .map(|(x, y)| projection.project([x, y]))
                    .collect()
            })
            .collect())
    }

    #[test]
    #[ignore = "needs shared/data/real (make test-rust runs it where present)"]
    fn village_parcel_statistics_of_a_real_cadastre() {
        let path = real_data_dir().join("parcels/cadastre-91216-parcelles.json");
        require(std::slice::from_ref(&path));
        let polys = match cadastre(&path) {
            Ok(p) => p,
            Err(e) => panic!("the cadastre could not be read: {e}"),
        };
        let stats = parcel_statistics(&polys, 1.0);
        let raw = parcel_statistics_with(&polys, 1.0, 0.0);
        println!(
            "cadastre of Épinay-sur-Orge: {} parcels, {:.3} neighbours, {:.3} edges ({:.3} counting every vertex); \
             thesis, real village: 2.812 and 4.068",
            stats.parcels, stats.mean_neighbours, stats.mean_edges, raw.mean_edges
        );
        assert_eq!(stats.parcels, 4241);
        assert!((2.0..=6.0).contains(&stats.mean_neighbours), "{stats:?}");
        assert!((3.0..=10.0).contains(&stats.mean_edges), "{stats:?}");
    }

    #[test]
    fn village_parcel_statistics_of_a_synthetic_village() {
        let land = land(200.0, DVec2::ZERO, &Environment::default());
        let (roads, positions) = village_layout();
        let p = params(20.0, 6.0, 0.0);
        let result = parcels(&land, &roads, WIDTH, &seeds(&positions, &p), CELL).expect("parcels");
        let stats = parcel_statistics(&contours(&result), 1.0);
        println!(
            "synthetic village: {} seeds, {} parcels, {:.3} neighbours, {:.3} edges; \
             thesis: real 2.812 and 4.068, model 2.873 and 4.29",
            positions.len(),
            stats.parcels,
            stats.mean_neighbours,
            stats.mean_edges
        );
        assert!(stats.parcels >= 24, "{stats:?}");
        assert!((2.0..=4.0).contains(&stats.mean_neighbours), "{stats:?}");
        assert!((3.5..=6.0).contains(&stats.mean_edges), "{stats:?}");
    }

    #[test]
    fn village_parcel_statistics_of_squares() {
        // a 3 × 3 block of 10 m squares, the middle one with an extra vertex on a side
        let mut polys = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                let o = DVec2::new(i as f64, j as f64) * 10.0;
                let mut sq = vec![
                    o,
                    o + DVec2::new(10.0, 0.0),
                    o + DVec2::new(10.0, 10.0),
                    o + DVec2::new(0.0, 10.0),
                ];
                if (i, j) == (1, 1) {
                    sq.insert(1, o + DVec2::new(4.0, 0.0));
                }
                polys.push(sq);
            }
        }
        let stats = parcel_statistics(&polys, 1.0);
        assert_eq!(stats.parcels, 9);
        assert!(
            (stats.mean_neighbours - 24.0 / 9.0).abs() < 1e-12,
            "{stats:?}"
        );
        assert!((stats.mean_edges - 4.0).abs() < 1e-12, "{stats:?}");
        // squares touching at a corner only, or along less than the tolerance, are not neighbours
        let far = vec![
            vec![
                DVec2::ZERO,
                DVec2::new(1.0, 0.0),
                DVec2::new(1.0, 1.0),
                DVec2::new(0.0, 1.0),
            ],
            vec![
                DVec2::new(1.0, 1.0),
                DVec2::new(2.0, 1.0),
                DVec2::new(2.0, 2.0),
                DVec2::new(1.0, 2.0),
            ],
            vec![
                DVec2::new(1.0, 0.5),
                DVec2::new(2.0, 0.5),
                DVec2::new(2.0, 0.9),
                DVec2::new(1.0, 0.9),
            ],
        ];
        assert_eq!(parcel_statistics(&far, 0.5).mean_neighbours, 0.0);
    }

    #[test]
    fn village_parcels_are_deterministic() {
        let land = land(200.0, DVec2::new(0.03, 0.1), &Environment::default());
        let (roads, positions) = village_layout();
        let p = params(20.0, 6.0, 5.0);
        let run = || parcels(&land, &roads, WIDTH, &seeds(&positions, &p), CELL).expect("parcels");
        let first = run();
        assert_eq!(first, run());
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("pool");
        assert_eq!(first, pool.install(run));
        let fps = footprints_of(&first, &roads);
        assert_eq!(fps, pool.install(|| footprints_of(&first, &roads)));
    }

    #[test]
    fn village_parcels_reject_bad_inputs() {
        let land = land(50.0, DVec2::ZERO, &Environment::default());
        let roads = vec![road(&[(5.0, 25.0), (45.0, 25.0)])];
        let good = params(10.0, 4.0, 0.0);
        let at = [DVec2::new(25.0, 30.0)];
        let invalid = |r: worldpaint_core::Result<Vec<Option<Parcel>>>| matches!(r, Err(e) if e.is_invalid_input());
        assert!(invalid(parcels(
            &land,
            &roads,
            WIDTH,
            &seeds(&at, &good),
            0.0
        )));
        assert!(invalid(parcels(
            &land,
            &roads,
            WIDTH,
            &seeds(&at, &good),
            f64::NAN
        )));
        assert!(invalid(parcels(
            &land,
            &roads,
            -1.0,
            &seeds(&at, &good),
            CELL
        )));
        assert!(invalid(parcels(
            &land,
            &roads,
            WIDTH,
            &seeds(&[DVec2::new(f64::NAN, 1.0)], &good),
            CELL
        )));
        for bad in [
            ParcelParams {
                budget: 0.0,
                ..good
            },
            ParcelParams {
                conquest_weight: 0.0,
                ..good
            },
            ParcelParams {
                slope_weight: -1.0,
                ..good
            },
            ParcelParams {
                road_reach: f64::INFINITY,
                ..good
            },
        ] {
            assert!(
                invalid(parcels(&land, &roads, WIDTH, &seeds(&at, &bad), CELL)),
                "{bad:?}"
            );
        }
        let nan_road = vec![road(&[(5.0, 25.0), (f64::NAN, 25.0)])];
        assert!(invalid(parcels(
            &land,
            &nan_road,
            WIDTH,
            &seeds(&at, &good),
            CELL
        )));
        // extreme but valid inputs: an endless fund, a seed whose road lies off the land
        let endless = ParcelParams {
            budget: 1e300,
            conquest_weight: 1e-300,
            ..good
        };
        let all = parcels(&land, &roads, WIDTH, &seeds(&at, &endless), CELL).expect("endless fund");
        assert!(all[0].is_some());
        let off = vec![road(&[(500.0, 500.0), (600.0, 500.0)])];
        assert_eq!(
            parcels(&land, &off, WIDTH, &seeds(&at, &good), CELL).expect("road off the land"),
            vec![None]
        );
        // no seed, no road: nothing to do, no error
        assert_eq!(
            parcels(&land, &roads, WIDTH, &[], CELL).expect("no seeds"),
            vec![]
        );
        assert_eq!(
            parcels(&land, &[], WIDTH, &seeds(&at, &good), CELL).expect("no roads"),
            vec![None]
        );
        // footprints
        let result = parcels(&land, &roads, WIDTH, &seeds(&at, &good), CELL).expect("parcels");
        let parcel = result[0].clone().expect("a parcel");
        assert!(house_footprint(&parcel, &roads, WIDTH, [0.0, 4.0], [8.0, 8.0], SNAP).is_none());
        assert!(house_footprint(&parcel, &roads, WIDTH, [6.0, 4.0], [5.0, 8.0], SNAP).is_none());
        assert!(
            house_footprint(&parcel, &roads, WIDTH, [4.0, 4.0], [8.0, f64::NAN], SNAP).is_none()
        );
        assert!(
            house_footprint(&parcel, &roads, WIDTH, [40.0, 40.0], [50.0, 50.0], SNAP).is_none(),
            "too large"
        );
        assert!(house_footprint(&parcel, &roads, WIDTH, [4.0, 4.0], [8.0, 8.0], SNAP).is_some());
        assert!(matches!(
            house_footprints(std::slice::from_ref(&parcel), &[], &roads, WIDTH, SNAP),
            Err(e) if e.is_invalid_input()
        ));
        assert!(matches!(
            house_footprints(&[parcel], &[([4.0, 4.0], [3.0, 8.0])], &roads, WIDTH, SNAP),
            Err(e) if e.is_invalid_input()
        ));
    }

    /// A random village: a few roads (bent, crossing, ending anywhere), bumpy terrain, a pond and a wall, seeds
    /// beside the roads with random conquest parameters.
    fn random_village(seed: u64) -> (Land, Vec<Road>, Vec<DVec2>, Vec<ParcelParams>) {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let size = 200.0;
        let (a, b, c) = (
            rng.random_range(0.0..5.0),
            rng.random_range(8.0..30.0),
            rng.random_range(8.0..30.0),
        );
        let n = size as usize + 1;
        let heights: Vec<f32> = (0..n * n)
            .map(|k| {
                let (x, y) = ((k % n) as f64, (k / n) as f64);
                (a * (x / b).sin() * (y / c).cos() + 0.03 * x) as f32
            })
            .collect();
        let terrain = Heightfield::new(DVec2::ZERO, 1.0, n, n, heights).expect("terrain");
        fn point(rng: &mut rand_chacha::ChaCha8Rng, lo: f64, hi: f64) -> DVec2 {
            DVec2::new(rng.random_range(lo..hi), rng.random_range(lo..hi))
        }
        let pond = point(&mut rng, 30.0, 170.0);
        let wall = point(&mut rng, 30.0, 170.0);
        let environment = Environment {
            water_areas: vec![vec![
                pond,
                pond + DVec2::new(12.0, 0.0),
                pond + DVec2::new(6.0, 9.0),
            ]],
            walls: vec![vec![
                wall,
                wall + DVec2::new(25.0, 3.0),
                wall + DVec2::new(20.0, 22.0),
            ]],
            ..Default::default()
        };
        let region = Region::Rect {
            min: DVec2::ZERO,
            max: DVec2::splat(size),
        };
        let land = Land::new(&terrain, &region, &environment, CELL).expect("land");
        let mut roads = Vec::new();
        for _ in 0..rng.random_range(2..5) {
            let mut p = vec![point(&mut rng, 10.0, 190.0)];
            for _ in 0..rng.random_range(1..4) {
                let last = p[p.len() - 1];
                let step = DVec2::new(rng.random_range(-70.0..70.0), rng.random_range(-70.0..70.0));
                p.push((last + step).clamp(DVec2::splat(5.0), DVec2::splat(195.0)));
            }
            roads.push(Road { points: p });
        }
        // a road ending on another one, as road searches make them
        let host = &roads[0].points;
        let on = host[0] + (host[1] - host[0]) * 0.5;
        roads.push(Road {
            points: vec![point(&mut rng, 10.0, 190.0), on],
        });
        let mut positions = Vec::new();
        let mut params_list = Vec::new();
        for r in &roads {
            for w in r.points.windows(2) {
                let len = w[0].distance(w[1]);
                let (dir, normal) = ((w[1] - w[0]) / len, (w[1] - w[0]).perp() / len);
                let mut s = rng.random_range(0.0..8.0);
                while s < len {
                    let side = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
                    positions.push(w[0] + dir * s + normal * side * rng.random_range(3.0..12.0));
                    params_list.push(ParcelParams {
                        budget: rng.random_range(10.0..35.0),
                        road_reach: rng.random_range(3.0..12.0),
                        conquest_weight: rng.random_range(0.5..1.5),
                        slope_weight: rng.random_range(0.0..10.0),
                        fill: 0.0,
                    });
                    s += rng.random_range(6.0..20.0);
                }
            }
        }
        (land, roads, positions, params_list)
    }

    #[test]
    fn village_random_layouts_are_valid() {
        for seed in 0..12 {
            let (land, roads, positions, params_list) = random_village(seed);
            let s: Vec<ParcelSeed> = positions
                .iter()
                .zip(&params_list)
                .map(|(&position, params)| ParcelSeed { position, params })
                .collect();
            let result = parcels(&land, &roads, WIDTH, &s, CELL).expect("parcels");
            let fps = footprints_of(&result, &roads);
            println!(
                "random village {seed}: {} seeds, {} parcels, {} footprints, {:?}",
                s.len(),
                result.iter().flatten().count(),
                fps.iter().flatten().count(),
                parcel_statistics(&contours(&result), 1.0)
            );
            check_layout(&land, &roads, &result, &fps);
        }
    }
    /// About 100 buildings on a square kilometre: a main road, side streets and back lanes, with seeds on both
    /// sides. Prints the time of the parcels and of the footprints (`--ignored --nocapture`).
    #[test]
    #[ignore]
    fn village_timing_of_a_hundred_parcels() {
        let size = 1000.0;
        let land = land(size, DVec2::new(0.02, 0.04), &Environment::default());
        let mut roads = vec![road(&[(20.0, 500.0), (980.0, 500.0)])];
        let mut positions = Vec::new();
        for k in 0..5 {
            let x = 150.0 + 175.0 * k as f64;
            roads.push(road(&[(x, 200.0), (x, 800.0)]));
            for j in 0..10 {
                let y = 240.0 + 55.0 * j as f64 + (k % 2) as f64 * 9.0;
                if (y - 500.0).abs() < 12.0 {
                    continue;
                }
                positions.push(DVec2::new(x + if j % 2 == 0 { 7.0 } else { -7.0 }, y));
                positions.push(DVec2::new(
                    x + if j % 2 == 0 { -7.0 } else { 7.0 },
                    y + 20.0,
                ));
            }
        }
        positions.truncate(100);
        let house = params(20.0, 8.0, 5.0);
        let farm = params(45.0, 15.0, 5.0);
        let s: Vec<ParcelSeed> = positions
            .iter()
            .enumerate()
            .map(|(i, &position)| ParcelSeed {
                position,
                params: if i % 10 == 0 { &farm } else { &house },
            })
            .collect();
        let mut times = Vec::new();
        let mut result = Vec::new();
        for _ in 0..3 {
            let t = std::time::Instant::now();
            result = parcels(&land, &roads, WIDTH, &s, CELL).expect("parcels");
            times.push(t.elapsed().as_secs_f64());
        }
        let got: Vec<Parcel> = result.iter().flatten().cloned().collect();
        let sizes = vec![(HOUSE_MIN, HOUSE_MAX); got.len()];
        let t = std::time::Instant::now();
        let fps = house_footprints(&got, &sizes, &roads, WIDTH, SNAP).expect("footprints");
        let tf = t.elapsed().as_secs_f64();
        times.sort_by(f64::total_cmp);
        println!(
            "{} seeds on 1 km² ({} threads): {} parcels in {:.3} s (best of 3; worst {:.3} s), {} footprints in {:.3} s",
            s.len(),
            rayon::current_num_threads(),
            got.len(),
            times[0],
            times[2],
            fps.iter().flatten().count(),
            tf
        );
        check_layout(&land, &roads, &result, &fps);
    }
}

//! A parcel's far side (thesis 3.3.4): where the conquest's budget, not a neighbour nor a road, drew the line, the
//! simplification straightens it further (`ParcelOptions::far_merge_angle_degrees`, `far_deviation`), so that a
//! parcel on a slope whose steepness varies keeps one straight far side instead of the bowed iso-cost line. And a
//! parcel growing fields beyond its conquest (`ParcelParams::fill`) keeps them in front of its straight road front,
//! instead of wrapping them round its road's end.

use worldpaint_core::{
    parcel_statistics, parcels_with, polygon_signed_area, DVec2, Environment, Heightfield, Land,
    ParcelOptions, ParcelParams, ParcelSeed, Region, Road,
};

const CELL: f64 = 1.0;
const WIDTH: f64 = 5.0;

#[test]
fn village_parcel_far_sides_on_a_curved_slope_come_out_straight() {
    // the slope steepens away from x = 100, so the budget's iso-cost line (the far side) bows up the slope
    let size = 200.0;
    let n = size as usize + 1;
    let heights: Vec<f32> = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64, (k / n) as f64);
            (0.15 * y * (1.0 + ((x - 100.0) / 40.0).powi(2))) as f32
        })
        .collect();
    let terrain = Heightfield::new(DVec2::ZERO, 1.0, n, n, heights).expect("terrain");
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(size),
    };
    let land = Land::new(&terrain, &region, &Environment::default(), CELL).expect("land");
    let roads = vec![Road {
        points: vec![DVec2::new(10.0, 100.0), DVec2::new(190.0, 100.0)],
    }];
    let params = ParcelParams {
        budget: 40.0,
        road_reach: 40.0,
        conquest_weight: 1.0,
        slope_weight: 40.0,
        fill: 0.0,
    };
    let seed = [ParcelSeed {
        position: DVec2::new(100.0, 106.0),
        params: &params,
    }];
    let edges = |options: &ParcelOptions| {
        let result =
            parcels_with(&land, &roads, WIDTH, &seed, CELL, options, &|_| true).expect("parcels");
        let contours: Vec<Vec<DVec2>> =
            result.iter().flatten().map(|p| p.contour.clone()).collect();
        assert_eq!(contours.len(), 1, "the seed keeps its parcel");
        assert!(
            polygon_signed_area(&contours[0]) > 0.0,
            "a counter-clockwise contour"
        );
        parcel_statistics(&contours, 1.0).mean_edges
    };
    let defaults = ParcelOptions::default();
    let straight = edges(&defaults);
    let bowed = edges(&ParcelOptions {
        far_merge_angle_degrees: defaults.merge_angle_degrees,
        far_deviation: defaults.merge_deviation,
        ..defaults
    });
    println!("far side on a curved slope: {straight} edges, {bowed} with the far side simplified as the rest");
    // a quadrilateral: the road front, two sides, one far side
    assert!(straight <= 4.0, "{straight} edges");
    assert!(
        straight < bowed,
        "{straight} edges, {bowed} without the far-side rule"
    );
}

#[test]
fn village_parcel_fields_stay_in_front_of_their_road() {
    // a dead-end road on flat land: a parcel growing fields near its end keeps to its own side of the road
    // instead of wrapping round the end to the other side
    let size = 200.0;
    let n = size as usize + 1;
    let terrain = Heightfield::new(DVec2::ZERO, 1.0, n, n, vec![0.0; n * n]).expect("terrain");
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(size),
    };
    let land = Land::new(&terrain, &region, &Environment::default(), CELL).expect("land");
    let roads = vec![Road {
        points: vec![DVec2::new(10.0, 100.0), DVec2::new(100.0, 100.0)],
    }];
    let params = ParcelParams {
        budget: 20.0,
        road_reach: 9.0,
        conquest_weight: 1.0,
        slope_weight: 0.0,
        fill: 40.0,
    };
    let seed = [ParcelSeed {
        position: DVec2::new(92.0, 106.0),
        params: &params,
    }];
    let result = parcels_with(
        &land,
        &roads,
        WIDTH,
        &seed,
        CELL,
        &ParcelOptions::default(),
        &|_| true,
    )
    .expect("parcels");
    let Some(parcel) = &result[0] else {
        panic!("the seed keeps its parcel");
    };
    let lowest = parcel
        .contour
        .iter()
        .map(|p| p.y)
        .fold(f64::INFINITY, f64::min);
    let beyond = parcel
        .contour
        .iter()
        .map(|p| p.x)
        .fold(f64::NEG_INFINITY, f64::max);
    println!("fields beside a dead end: lowest y {lowest}, farthest x {beyond}");
    assert!(
        beyond > 110.0,
        "the fields grow past the road's end ({beyond})"
    );
    // the road's corridor edge is at y = 97.5 on the far side, 102.5 on the seed's
    assert!(
        lowest >= 100.0 + 0.5 * WIDTH - ParcelOptions::default().straighten * CELL - 1e-9,
        "the fields wrap round the road's end (lowest y {lowest})"
    );
}

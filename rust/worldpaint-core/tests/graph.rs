//! Graphs of paths (Section 4.2): crossings become nodes, the graph goes back to the same paths, its statistics
//! and segment queries are right.

use std::f64::consts::PI;
use worldpaint_core::{DVec2, Graph, Region, SegmentIndex};

fn v(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

#[test]
fn crossing_paths_meet_at_a_node() {
    let a = [v(0.0, 0.0), v(10.0, 0.0), v(20.0, 0.0)];
    let b = [v(5.0, -5.0), v(5.0, 5.0)];
    // a path ending on another one (a T junction) and one touching an end
    let c = [v(15.0, 10.0), v(15.0, 0.0)];
    let d = [v(20.0, 0.0), v(25.0, 5.0)];
    let g = Graph::from_paths(&[&a, &b, &c, &d], 1e-6);
    assert_eq!(g.nodes.len(), 9, "{:?}", g.nodes);
    assert_eq!(g.edges.len(), 8);
    let degrees: Vec<usize> = g.adjacency().iter().map(|n| n.len()).collect();
    assert_eq!(
        degrees.iter().filter(|&&d| d == 4).count(),
        1,
        "the crossing at (5, 0)"
    );
    assert_eq!(
        degrees.iter().filter(|&&d| d == 3).count(),
        1,
        "the T junction at (15, 0)"
    );
    assert_eq!(g.components(), 1);
    assert!(
        (g.min_angle() - PI / 2.0).abs() < 1e-9,
        "right angles at both junctions: {}",
        g.min_angle()
    );
    assert_eq!(g.crossings(), 0);
    // back to paths: every edge once
    let paths = g.to_paths();
    let edges: usize = paths.iter().map(|p| p.len() - 1).sum();
    assert_eq!(edges, g.edges.len());
    let again = Graph::from_paths(
        &paths.iter().map(|p| p.as_slice()).collect::<Vec<_>>(),
        1e-6,
    );
    assert_eq!(again.nodes.len(), g.nodes.len());
    assert_eq!(again.edges.len(), g.edges.len());
}

#[test]
fn segment_index_finds_distances_and_crossings() {
    let segments = vec![
        (v(0.0, 0.0), v(100.0, 0.0)),
        (v(50.0, -20.0), v(50.0, 20.0)),
    ];
    let index = SegmentIndex::new(segments);
    assert!((index.distance(v(30.0, 7.0), 100.0) - 7.0).abs() < 1e-12);
    assert!((index.distance(v(53.0, 10.0), 100.0) - 3.0).abs() < 1e-12);
    assert_eq!(index.distance(v(30.0, 70.0), 20.0), 20.0);
    assert!(index.crosses(v(20.0, -5.0), v(20.0, 5.0), 1e-9));
    assert!(!index.crosses(v(20.0, 1.0), v(30.0, 5.0), 1e-9));
    // touching at its own end is no crossing
    assert!(!index.crosses(v(20.0, 0.0), v(30.0, 5.0), 1e-6));
}

#[test]
fn polylines_are_cut_at_a_region_border() {
    let square = Region::Rect {
        min: v(0.0, 0.0),
        max: v(10.0, 10.0),
    };
    let line = [
        v(-5.0, 5.0),
        v(5.0, 5.0),
        v(15.0, 5.0),
        v(15.0, 8.0),
        v(5.0, 8.0),
    ];
    let (inside, outside) = square.clip_polyline(&line);
    assert_eq!(inside.len(), 2);
    assert_eq!(outside.len(), 2);
    let length = |p: &Vec<DVec2>| p.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
    let total_in: f64 = inside.iter().map(length).sum();
    let total_out: f64 = outside.iter().map(length).sum();
    assert!((total_in - 15.0).abs() < 1e-9 && (total_out - 18.0).abs() < 1e-9);
    let circle = Region::Circle {
        center: v(0.0, 0.0),
        radius: 5.0,
    };
    let (inside, _) = circle.clip_polyline(&[v(-10.0, 0.0), v(10.0, 0.0)]);
    assert!((length(&inside[0]) - 10.0).abs() < 1e-9);
}

proptest::proptest! {
    #![proptest_config(proptest::test_runner::Config {
        cases: 128,
        rng_seed: proptest::test_runner::RngSeed::Fixed(4242),
        failure_persistence: None,
        ..Default::default()
    })]

    /// The ring search of the segment index finds the nearest segment a scan of all of them finds, for points
    /// inside and far outside the indexed box.
    #[test]
    fn segment_distance_matches_a_scan(
        ends in proptest::collection::vec((0.0..200.0f64, 0.0..200.0f64, -30.0..30.0f64, -30.0..30.0f64), 1..40),
        queries in proptest::collection::vec((-400.0..600.0f64, -400.0..600.0f64), 1..20),
        max in 1.0..500.0f64,
    ) {
        let segments: Vec<(DVec2, DVec2)> = ends.iter().map(|&(x, y, dx, dy)| (v(x, y), v(x + dx, y + dy))).collect();
        let index = SegmentIndex::new(segments.clone());
        for (x, y) in queries {
            let p = v(x, y);
            let scan = segments
                .iter()
                .map(|(a, b)| worldpaint_core::segment_distance(p, *a, *b))
                .fold(max, f64::min);
            proptest::prop_assert!((index.distance(p, max) - scan).abs() < 1e-9);
        }
    }
}

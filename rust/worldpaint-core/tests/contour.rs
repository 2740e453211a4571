//! Islands and lakes: a contour filled with dense points and traced back keeps its shape; signed distances.

use std::f64::consts::TAU;
use worldpaint_core::{
    fill_polygons, polygon_signed_area, segment_distance, trace_contours, triangulate, DVec2,
    Polygons,
};

/// A wobbly island around `c`.
fn island(c: DVec2, r: f64) -> Vec<DVec2> {
    (0..120)
        .map(|k| {
            let a = TAU * k as f64 / 120.0;
            let rr = r * (1.0 + 0.2 * (3.0 * a).sin() + 0.1 * (5.0 * a).cos());
            c + DVec2::new(a.cos(), a.sin()) * rr
        })
        .collect()
}

/// An island of radius about 50 m around the origin with a round lake of radius 10 m at its centre.
fn island_with_a_lake() -> (Vec<DVec2>, Vec<DVec2>) {
    let lake = (0..60)
        .map(|k| {
            let a = TAU * k as f64 / 60.0;
            DVec2::new(a.cos(), a.sin()) * 10.0
        })
        .collect();
    (island(DVec2::ZERO, 50.0), lake)
}

fn distance_to(p: DVec2, c: &[DVec2]) -> f64 {
    (0..c.len())
        .map(|i| segment_distance(p, c[i], c[(i + 1) % c.len()]))
        .fold(f64::INFINITY, f64::min)
}

fn hausdorff(a: &[DVec2], b: &[DVec2]) -> f64 {
    let one = |a: &[DVec2], b: &[DVec2]| a.iter().map(|p| distance_to(*p, b)).fold(0.0, f64::max);
    one(a, b).max(one(b, a))
}

#[test]
fn a_contour_traced_back_from_its_dense_points_keeps_its_shape() {
    let spacing = 2.0;
    let shape = island(DVec2::new(100.0, 80.0), 40.0);
    let polygons = Polygons::new(std::slice::from_ref(&shape));
    let points = fill_polygons(&polygons, spacing, 1);
    let area = polygon_signed_area(&shape).abs();
    assert!((points.len() as f64 * spacing * spacing / area - 1.0).abs() < 0.05);
    let traced = trace_contours(&points, spacing);
    assert_eq!(traced.len(), 1);
    let traced_area = polygon_signed_area(&traced[0]).abs();
    let h = hausdorff(&shape, &traced[0]);
    println!(
        "contour of {area:.0} m²: {} dense points, traced {traced_area:.0} m² ({:+.2} %), Hausdorff {h:.2} m ({:.2} cells)",
        points.len(),
        100.0 * (traced_area / area - 1.0),
        h / spacing
    );
    assert!((traced_area / area - 1.0).abs() <= 0.05);
    assert!(h < 2.0 * spacing);
}

#[test]
fn a_lake_in_an_island_is_a_hole() {
    let (outer, lake) = island_with_a_lake();
    let polygons = Polygons::new(&[outer.clone(), lake.clone()]);
    assert!(!polygons.contains(DVec2::ZERO), "the lake");
    assert!(polygons.contains(DVec2::new(25.0, 0.0)), "the island");
    assert!(!polygons.contains(DVec2::new(200.0, 0.0)), "the sea");
    // signed distance: the sea positive in metres, the island negative and normalized
    assert!(
        (polygons.signed_distance(DVec2::new(200.0, 0.0), 1000.0)
            - distance_to(DVec2::new(200.0, 0.0), &outer))
        .abs()
            < 1e-9
    );
    let s = polygons.signed_distance(DVec2::new(25.0, 0.0), 1000.0);
    assert!((-1.0..0.0).contains(&s), "{s}");
    let points = fill_polygons(&polygons, 2.0, 3);
    assert!(points.iter().all(|p| p.length() > 10.0 - 1e-9));
    let traced = trace_contours(&points, 2.0);
    assert_eq!(traced.len(), 2, "the coast and the lake shore");
}

#[test]
fn an_island_with_a_lake_fills_as_a_mesh_with_a_hole() {
    let (outer, lake) = island_with_a_lake();
    let polygons = Polygons::new(&[outer.clone(), lake.clone()]);
    let mesh = triangulate(&polygons, 4.0);
    let land = polygon_signed_area(&outer).abs() - polygon_signed_area(&lake).abs();
    println!(
        "island less lake {land:.0} m²: {} vertices, {} triangles, {:.0} m²",
        mesh.vertices.len(),
        mesh.triangles.len(),
        mesh.area()
    );
    assert!(
        (mesh.area() / land - 1.0).abs() < 1e-6,
        "the mesh covers the land exactly"
    );
    assert!(
        mesh.vertices.len() > 180 + 100,
        "inner points to follow the terrain"
    );
    for t in &mesh.triangles {
        let c = t.iter().map(|&i| mesh.vertices[i as usize]).sum::<DVec2>() / 3.0;
        assert!(
            c.length() > 10.0 * (std::f64::consts::PI / 60.0).cos() - 1e-9,
            "a triangle in the lake at {c}"
        );
    }
}

#[test]
fn tracing_the_same_points_gives_the_same_contours() {
    let (outer, lake) = island_with_a_lake();
    let points = fill_polygons(&Polygons::new(&[outer, lake]), 2.0, 5);
    let first = trace_contours(&points, 2.0);
    for _ in 0..5 {
        assert_eq!(
            trace_contours(&points, 2.0),
            first,
            "loops start at the same place on every call"
        );
    }
}

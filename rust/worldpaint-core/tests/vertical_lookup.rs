//! The height of a triangle mesh under points (the snap of point clouds onto their terrain mesh): exact on an
//! irregular mesh, on shared edges and under overhangs; nothing beyond the mesh; bad input refused or left out,
//! never a panic.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use worldpaint_core::{DVec2, Error, VerticalLookup};

/// Far from the world's origin, where float32 world coordinates would be centimetres off.
const CORNER: [f64; 2] = [52_000.0, -31_000.0];

/// An irregular mesh over a 100 m square at [`CORNER`]: a jittered 21 × 21 lattice of random heights, each quad cut
/// along a random diagonal.
fn irregular_mesh(seed: u64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (n, step) = (21u32, 5.0);
    let mut vertices = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let jitter = |rng: &mut ChaCha8Rng, k: u32| {
                if k == 0 || k == n - 1 {
                    0.0
                } else {
                    rng.random_range(-1.5..1.5)
                }
            };
            let x = CORNER[0] + f64::from(i) * step + jitter(&mut rng, i);
            let y = CORNER[1] + f64::from(j) * step + jitter(&mut rng, j);
            vertices.push([x, y, rng.random_range(-3.0..3.0)]);
        }
    }
    let mut triangles = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let [a, b, c, d] = [
                j * n + i,
                j * n + i + 1,
                (j + 1) * n + i + 1,
                (j + 1) * n + i,
            ];
            if rng.random_bool(0.5) {
                triangles.extend([[a, b, c], [a, c, d]]);
            } else {
                triangles.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    (vertices, triangles)
}

/// The height at `p` of the plane of the triangle `t`, and whether `p` lies in it (exact arithmetic in float64).
fn plane_height(vertices: &[[f64; 3]], t: &[u32; 3], p: DVec2) -> (f64, bool) {
    let [a, b, c] = t.map(|i| vertices[i as usize]);
    let (e1, e2, d) = (
        [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
        [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
        [p.x - a[0], p.y - a[1]],
    );
    let det = e1[0] * e2[1] - e1[1] * e2[0];
    let u = (d[0] * e2[1] - d[1] * e2[0]) / det;
    let v = (e1[0] * d[1] - e1[1] * d[0]) / det;
    let inside = u >= -1e-9 && v >= -1e-9 && u + v <= 1.0 + 1e-9;
    (a[2] + u * e1[2] + v * e2[2], inside)
}

fn at(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

#[test]
fn heights_are_those_of_the_triangle_under_each_point() {
    let (vertices, triangles) = irregular_mesh(7);
    let lookup = VerticalLookup::new(&vertices, &triangles).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let points: Vec<DVec2> = (0..20_000)
        .map(|_| {
            at(
                CORNER[0] + rng.random_range(0.0..100.0),
                CORNER[1] + rng.random_range(0.0..100.0),
            )
        })
        .collect();
    let heights = lookup.heights(&points);
    let mut worst = 0.0f64;
    for (p, z) in points.iter().zip(&heights) {
        let expected = triangles
            .iter()
            .map(|t| plane_height(&vertices, t, *p))
            .find(|(_, inside)| *inside)
            .map(|(z, _)| z)
            .unwrap();
        worst = worst.max((z - expected).abs());
    }
    // float32 about the mesh's corner: a tenth of a millimetre, 52 km from the world's origin
    assert!(worst < 1e-4, "worst height error {worst} m");
}

#[test]
fn a_point_on_an_edge_shared_by_two_triangles_gets_a_height() {
    let (vertices, triangles) = irregular_mesh(11);
    let lookup = VerticalLookup::new(&vertices, &triangles).unwrap();
    for t in &triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let [a, b] = [a, b].map(|i| vertices[i as usize]);
            for s in [0.0, 0.3, 0.5, 0.9] {
                let p = at(a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]));
                let z = lookup.height_at(p);
                let expected = a[2] + s * (b[2] - a[2]);
                assert!(
                    z.is_some_and(|z| (z - expected).abs() < 1e-4),
                    "at {p}: {z:?}, the edge is at {expected}"
                );
            }
        }
    }
}

#[test]
fn under_an_overhang_the_highest_triangle_is_met() {
    // ground at z = 0 over 10 m, a sloping ledge at z = 4..6 over part of it, and a vertical wall joining them
    let vertices = [
        [0.0, 0.0, 0.0],
        [10.0, 0.0, 0.0],
        [10.0, 10.0, 0.0],
        [0.0, 10.0, 0.0],
        [2.0, 2.0, 4.0],
        [8.0, 2.0, 6.0],
        [2.0, 8.0, 4.0],
        [2.0, 2.0, 0.0],
    ];
    let triangles = [[0, 1, 2], [0, 2, 3], [4, 5, 6], [7, 4, 6]];
    for order in [
        triangles,
        [triangles[2], triangles[0], triangles[3], triangles[1]],
    ] {
        let lookup = VerticalLookup::new(&vertices, &order).unwrap();
        let z = lookup.height_at(at(3.0, 3.0)).unwrap();
        assert!(
            (z - (4.0 + 2.0 * 1.0 / 6.0)).abs() < 1e-5,
            "on the ledge: {z}"
        );
        assert!(
            lookup.height_at(at(9.0, 9.0)).unwrap().abs() < 1e-6,
            "beside it, the ground"
        );
    }
}

#[test]
fn a_point_over_no_triangle_has_no_height() {
    let (vertices, triangles) = irregular_mesh(3);
    let lookup = VerticalLookup::new(&vertices, &triangles).unwrap();
    let beyond = [
        at(CORNER[0] - 1.0, CORNER[1] + 50.0),
        at(CORNER[0] + 100.1, CORNER[1] + 50.0),
        at(CORNER[0] + 50.0, CORNER[1] - 0.01),
        at(0.0, 0.0),
        at(1e12, -1e12),
    ];
    assert!(lookup.heights(&beyond).iter().all(|z| z.is_nan()));
    // a hole: one triangle of a square left out
    let square = [
        [0.0, 0.0, 1.0],
        [4.0, 0.0, 1.0],
        [4.0, 4.0, 1.0],
        [0.0, 4.0, 1.0],
    ];
    let lookup = VerticalLookup::new(&square, &[[0, 1, 2]]).unwrap();
    assert_eq!(lookup.height_at(at(3.0, 1.0)), Some(1.0));
    assert_eq!(lookup.height_at(at(1.0, 3.0)), None);
}

#[test]
fn an_empty_or_vertical_mesh_has_no_height_anywhere() {
    let points = [at(0.0, 0.0), at(1.0, 2.0)];
    let wall = [[0.0, 0.0, 0.0], [5.0, 5.0, 0.0], [5.0, 5.0, 3.0]];
    for (vertices, triangles) in [
        (&[][..], &[][..]),
        (&wall[..], &[][..]),
        (&wall[..], &[[0u32, 1, 2]][..]),
    ] {
        let lookup = VerticalLookup::new(vertices, triangles).unwrap();
        assert!(lookup.heights(&points).iter().all(|z| z.is_nan()));
        assert!(lookup.heights(&[]).is_empty());
    }
}

#[test]
fn vertices_or_points_that_are_not_finite_give_no_height_and_no_panic() {
    let bad = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
    for value in bad {
        // the bad vertex first, where it could become the mesh's corner; its triangle is left out
        let vertices = [
            [value, 1.0, 2.0],
            [0.0, 0.0, 1.0],
            [4.0, 0.0, 1.0],
            [4.0, 4.0, 1.0],
            [0.0, 4.0, 1.0],
            [1.0, 1.0, value],
        ];
        let triangles = [[0, 1, 2], [1, 2, 3], [1, 3, 4], [5, 1, 2]];
        let lookup = VerticalLookup::new(&vertices, &triangles).unwrap();
        assert_eq!(lookup.height_at(at(3.0, 1.0)), Some(1.0));
        assert_eq!(lookup.height_at(at(1.0, 3.0)), Some(1.0));
        let points = [at(value, 1.0), at(1.0, value), at(value, value)];
        assert!(lookup.heights(&points).iter().all(|z| z.is_nan()));
    }
    // coordinates whose differences overflow
    let vertices = [
        [-1e308, 0.0, 0.0],
        [1e308, 0.0, 0.0],
        [0.0, 1e308, 0.0],
        [1e308, 1e308, 5.0],
    ];
    let lookup = VerticalLookup::new(&vertices, &[[0, 1, 2], [1, 3, 2]]).unwrap();
    lookup.heights(&[at(0.0, 1.0), at(1e308, 1e308), at(f64::MAX, f64::MIN)]);
}

#[test]
fn a_triangle_naming_a_vertex_beyond_the_mesh_is_refused() {
    let vertices = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    for bad in [3, u32::MAX] {
        let e = VerticalLookup::new(&vertices, &[[0, 1, 2], [0, bad, 2]]).unwrap_err();
        assert!(matches!(e, Error::Invalid { .. }), "{e}");
        assert_eq!(
            e.to_string(),
            "invalid input: terrain mesh triangle 1: refers to a vertex beyond the 3 given"
        );
    }
}

#[test]
fn triangles_that_would_fill_too_many_cells_are_refused_before_binning() {
    // 40,000 triangles each over the whole mesh: ten thousand cells, each holding all of them
    let vertices = [
        [0.0, 0.0, 0.0],
        [100.0, 0.0, 0.0],
        [100.0, 100.0, 0.0],
        [0.0, 100.0, 0.0],
    ];
    let triangles: Vec<[u32; 3]> = (0..40_000)
        .map(|k| if k % 2 == 0 { [0, 1, 2] } else { [0, 2, 3] })
        .collect();
    let e = VerticalLookup::new(&vertices, &triangles).unwrap_err();
    assert!(matches!(e, Error::TooLarge { .. }), "{e}");
}

#[test]
fn triangles_far_apart_are_all_found() {
    // a thousand kilometres apart, in a grid of one cell
    let vertices = [
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
        [1e6, 1e6, 2.0],
        [1e6 + 1.0, 1e6, 2.0],
        [1e6, 1e6 + 1.0, 2.0],
    ];
    let lookup = VerticalLookup::new(&vertices, &[[0, 1, 2], [3, 4, 5]]).unwrap();
    assert_eq!(lookup.height_at(at(0.2, 0.2)), Some(1.0));
    assert_eq!(lookup.height_at(at(1e6 + 0.2, 1e6 + 0.2)), Some(2.0));
    assert_eq!(lookup.height_at(at(5e5, 5e5)), None);
}

#[test]
fn heights_do_not_depend_on_the_thread_count() {
    let (vertices, triangles) = irregular_mesh(5);
    let lookup = VerticalLookup::new(&vertices, &triangles).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let points: Vec<DVec2> = (0..50_000)
        .map(|_| {
            at(
                CORNER[0] + rng.random_range(-5.0..105.0),
                CORNER[1] + rng.random_range(-5.0..105.0),
            )
        })
        .collect();
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let again = VerticalLookup::new(&vertices, &triangles).unwrap();
                again.heights(&points)
            })
    };
    let bits = |h: Vec<f64>| h.into_iter().map(f64::to_bits).collect::<Vec<_>>();
    let one = bits(run(1));
    assert_eq!(one, bits(run(3)));
    assert_eq!(one, bits(lookup.heights(&points)));
}

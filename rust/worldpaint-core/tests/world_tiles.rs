//! A world filled tile by tile: the same bytes whatever the tile order and thread count, no seam a user can find
//! (hard cores kept across tile borders, the pcf of windows straddling four tiles as that of windows inside one),
//! and the color's density over the whole world.

mod common;
use common::pcf;
use common::world_driver::fill_tiles;

use std::collections::BTreeMap;
use worldpaint_core::{
    decode_tile, encode_tile, learn_color, undergrowth_scene, AnalysisOptions, Color, ColorMap,
    DVec2, Obstacles, Region, TileId, WorldPlan,
};

/// The Blender benchmark's color: trees with a 3 m hard core, uniform rocks, grass in 2 m clumps; 0.1 per m².
fn bench_color() -> Color {
    let ex = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(100.0),
    };
    let scene = undergrowth_scene(100.0);
    match learn_color(&scene, &ex, "Bench", &AnalysisOptions::default()) {
        Ok(c) => c,
        Err(e) => panic!("learning the bench color failed: {e}"),
    }
}

const SIDE: f64 = 400.0;
const TILE: f64 = 100.0;

fn uniform(color: &Color) -> ColorMap {
    match ColorMap::uniform(color.clone()) {
        Ok(m) => m,
        Err(e) => panic!("a map of one color: {e}"),
    }
}

fn plan(color: &Color) -> WorldPlan {
    match WorldPlan::for_map(DVec2::ZERO, DVec2::splat(SIDE), &uniform(color), Some(TILE)) {
        Ok(p) => p,
        Err(e) => panic!("plan: {e}"),
    }
}

/// Every tile's file bytes, the tiles of each phase taken in the order `order` gives them.
fn fill(color: &Color, seed: u64, order: fn(&mut Vec<TileId>)) -> BTreeMap<TileId, Vec<u8>> {
    fill_tiles(
        &plan(color),
        &uniform(color),
        &Obstacles::default(),
        seed,
        order,
    )
}

/// The world's instances of category `c`, read back from the tile files, with the tile each lies in.
fn points(files: &BTreeMap<TileId, Vec<u8>>, c: usize) -> Vec<(DVec2, TileId)> {
    let mut out = Vec::new();
    for (t, bytes) in files {
        let tile = match decode_tile(bytes) {
            Ok(tile) => tile,
            Err(e) => panic!("decoding {t:?}: {e}"),
        };
        out.extend(
            tile.instances
                .iter()
                .filter(|i| i.category == c)
                .map(|i| (i.position, *t)),
        );
    }
    out
}

#[test]
fn the_same_world_whatever_the_tile_order_and_thread_count() {
    let color = bench_color();
    let forward = fill(&color, 7, |_| {});
    let backward = fill(&color, 7, |tiles| tiles.reverse());
    let one_thread = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(pool) => pool.install(|| fill(&color, 7, |_| {})),
        Err(e) => panic!("thread pool: {e}"),
    };
    assert_eq!(forward.len(), 16);
    assert!(forward == backward, "the tile order changed the world");
    assert!(forward == one_thread, "the thread count changed the world");
    let other_seed = fill(&color, 8, |_| {});
    assert!(forward != other_seed, "another seed gave the same world");
}

#[test]
fn no_seam_between_tiles() {
    let color = bench_color();
    let files = fill(&color, 1, |_| {});
    let area = SIDE * SIDE;

    // the density of every category over the whole world, as the color's
    for (c, cat) in color.categories.iter().enumerate() {
        let n = points(&files, c).len() as f64;
        let expected = cat.density * area;
        println!(
            "{}: {n} instances, expected {expected:.0}",
            cat.category.name
        );
        assert!(
            (n / expected - 1.0).abs() < 0.05,
            "{}: {n} against {expected:.0}",
            cat.category.name
        );
    }

    // hard cores across tile borders: no two trees of different tiles closer than the color's minimum distance
    let trees = points(&files, 0);
    let min_distance = color.categories[0].min_distance;
    let mut closest = f64::INFINITY;
    for (k, (p, tp)) in trees.iter().enumerate() {
        for (q, tq) in &trees[k + 1..] {
            if tp != tq {
                closest = closest.min(p.distance(*q));
            }
        }
    }
    println!("closest trees across a tile border {closest:.3} m, the color's minimum distance {min_distance:.3} m");
    assert!(closest >= min_distance - 1e-3);

    // the pcf of windows straddling four tiles against windows inside one tile of other worlds, beside the pcf of
    // windows inside one tile against the same (a second draw); windows of two worlds on each side (the pcf of a
    // 60 m window of clumped grass is noisy)
    let (half, r_max, dr) = (30.0, 20.0, 1.0);
    let corners: Vec<DVec2> = (1..4)
        .flat_map(|j| (1..4).map(move |i| DVec2::new(i as f64, j as f64) * TILE))
        .collect();
    let centres: Vec<DVec2> = corners
        .iter()
        .map(|c| *c - DVec2::splat(TILE / 2.0))
        .collect();
    let worlds: Vec<_> = [
        files,
        fill(&color, 2, |_| {}),
        fill(&color, 3, |_| {}),
        fill(&color, 4, |_| {}),
    ]
    .into();
    for (c, name) in [(0, "trees"), (2, "grass")] {
        let mean_pcf = |worlds: &[BTreeMap<TileId, Vec<u8>>], at: &[DVec2]| {
            let mut sum = vec![0.0; (r_max / dr) as usize];
            let windows = (worlds.len() * at.len()) as f64;
            for w in worlds {
                let pts: Vec<DVec2> = points(w, c).into_iter().map(|(p, _)| p).collect();
                for &a in at {
                    let g = pcf::pcf(
                        &pts,
                        a - DVec2::splat(half),
                        a + DVec2::splat(half),
                        r_max,
                        dr,
                    );
                    sum.iter_mut().zip(g).for_each(|(s, v)| *s += v / windows);
                }
            }
            sum
        };
        let reference = mean_pcf(&worlds[2..], &centres);
        let seam = pcf::l2(&mean_pcf(&worlds[..2], &corners), &reference);
        let second_draw = pcf::l2(&mean_pcf(&worlds[..2], &centres), &reference);
        println!("{name}: pcf L2 straddling vs inside {seam:.3}, a second draw's {second_draw:.3}");
        assert!(
            seam <= 1.25 * second_draw,
            "{name}: the seams show ({seam:.3} against {second_draw:.3})"
        );
    }
}

#[test]
fn a_tile_file_reads_back_what_was_written_and_refuses_damage() {
    let color = bench_color();
    let files = fill(&color, 3, |_| {});
    let (t, bytes) = match files.iter().next() {
        Some(f) => f,
        None => panic!("no tile"),
    };
    let tile = match decode_tile(bytes) {
        Ok(tile) => tile,
        Err(e) => panic!("decoding: {e}"),
    };
    assert_eq!(tile.tile, *t);
    assert_eq!(tile.categories, ["Tree", "Rock", "Grass"]);
    assert_eq!(
        encode_tile(&tile).ok().as_ref(),
        Some(bytes),
        "a decoded tile encodes to other bytes"
    );
    assert_eq!(
        bytes.len(),
        8 + 8 + 16 + 8 + 3 * 2 + "TreeRockGrass".len() + 28 * tile.instances.len()
    );
    for cut in [0, 7, 20, bytes.len() / 2, bytes.len() - 1] {
        let e = decode_tile(&bytes[..cut]);
        assert!(
            matches!(e, Err(worldpaint_core::Error::Parse { .. })),
            "a file cut at {cut} was read"
        );
    }
    let mut bad = bytes.clone();
    bad[0] = b'X';
    assert!(decode_tile(&bad).is_err());
}

#[test]
fn a_plan_refuses_tiles_narrower_than_the_region_of_influence() {
    let color = bench_color();
    let narrow = WorldPlan::for_map(
        DVec2::ZERO,
        DVec2::splat(SIDE),
        &uniform(&color),
        Some(color.max_radius / 2.0),
    );
    assert!(narrow.is_err());
    let p = plan(&color);
    // each phase: no two tiles touch
    for a in p.tiles() {
        for n in p.earlier_neighbours(a) {
            assert!(p.phase(n) < p.phase(a));
        }
    }
    assert_eq!((p.columns, p.rows), (4, 4));
}

#[test]
fn a_plan_past_the_work_budget_is_refused_before_any_tile() {
    let color = bench_color();
    let map = uniform(&color);
    let refused = |min: f64, max: f64, tile: Option<f64>, words: &[&str]| match WorldPlan::for_map(
        DVec2::splat(min),
        DVec2::splat(max),
        &map,
        tile,
    ) {
        Ok(p) => panic!("{min}..{max} with tile {tile:?} was planned: {p:?}"),
        Err(e) => {
            let message = e.to_string();
            for w in words {
                assert!(message.contains(w), "'{message}' does not say '{w}'");
            }
        }
    };
    // 10,000 km square: 10^8 tiles of the default size
    refused(0.0, 1e7, None, &["too large", "tiles", "1000000"]);
    // one tile of 100 km² at 0.1 per m² is 10^9 instances, past one synthesis call's 5 × 10^7
    refused(
        0.0,
        1e5,
        Some(1e5),
        &["a tile of 100000 m", "instances", "50000000"],
    );
    // 10^6 tiles of 5 × 10^6 instances: past the world's 10^10
    refused(
        0.0,
        1e6,
        Some(5000.0),
        &["a world of", "instances", "10000000000"],
    );
    // an inverted or empty world, and tiles that are not a length
    refused(100.0, 0.0, None, &["max corner"]);
    refused(0.0, 100.0, Some(f64::NAN), &["tile size", "positive"]);
    refused(0.0, 100.0, Some(-50.0), &["tile size", "positive", "-50"]);
    // the chain length a tile is asked for
    for bad in [0.0, -5.0, f64::NAN, 1e300] {
        assert!(
            worldpaint_core::check_iterations(bad).is_err(),
            "{bad} iterations"
        );
    }
    assert!(worldpaint_core::check_iterations(60.0).is_ok());
}

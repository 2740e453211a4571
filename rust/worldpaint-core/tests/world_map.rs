//! A world painted from a map of two colors: across the boundary the density of each color's category moves
//! monotonically from one color's to the other's over the transition band, and the pcf's hard core from one color's
//! to the other's; away from the band each color keeps its own density; no two instances come closer than the hard
//! core across blocks, bands and tiles; the same seed gives the same bytes whatever the tile order; and bad maps are
//! refused before any tile runs.

mod common;

use common::world_driver::fill_tiles;
use std::collections::BTreeMap;
use worldpaint_core::{
    decode_tile, hard_core_points, learn_color, scene_from_points, uniform_points, AnalysisOptions,
    Color, ColorMap, DVec2, LabelGrid, Obstacles, Paint, Region, TileContent, TileId, WorldPlan,
};

const WIDTH: f64 = 600.0;
const HEIGHT: f64 = 400.0;
const TILE: f64 = 200.0;
/// The boundary between the two labels.
const BOUNDARY: f64 = 300.0;
const MAP_CELL: f64 = 20.0;
const SHRUBS: f64 = 0.05;
const TREES: f64 = 0.01;

/// A color of one category `name` at `density`, learned from a uniform example of 100 × 100 m.
fn color(name: &str, category: &str, density: f64, seed: u64) -> Color {
    let example = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(100.0),
    };
    let scene = scene_from_points(category, &uniform_points(&example, density, seed));
    match learn_color(&scene, &example, name, &AnalysisOptions::default()) {
        Ok(c) => c,
        Err(e) => panic!("learning {name}: {e}"),
    }
}

/// Label 7 (shrubs) west of the boundary, label 3 (trees) east of it, in cells of 20 m.
fn two_label_grid() -> LabelGrid {
    let (nx, ny) = ((WIDTH / MAP_CELL) as usize, (HEIGHT / MAP_CELL) as usize);
    LabelGrid {
        origin: DVec2::ZERO,
        cell: MAP_CELL,
        nx,
        ny,
        labels: (0..nx * ny)
            .map(|k| {
                if ((k % nx) as f64 + 0.5) * MAP_CELL < BOUNDARY {
                    7
                } else {
                    3
                }
            })
            .collect(),
    }
}

fn two_color_map() -> ColorMap {
    let legend = vec![
        (7, color("Shrubland", "shrub", SHRUBS, 1)),
        (3, color("Woods", "tree", TREES, 2)),
    ];
    match ColorMap::new(two_label_grid(), legend, None) {
        Ok(m) => m,
        Err(e) => panic!("the map: {e}"),
    }
}

/// Every tile of the world painted from `map`, the tiles of each phase in the order `order` gives them.
fn fill(
    map: &ColorMap,
    seed: u64,
    order: fn(&mut Vec<TileId>),
) -> (WorldPlan, BTreeMap<TileId, Vec<u8>>) {
    let plan = match WorldPlan::for_map(DVec2::ZERO, DVec2::new(WIDTH, HEIGHT), map, Some(TILE)) {
        Ok(p) => p,
        Err(e) => panic!("plan: {e}"),
    };
    let files = fill_tiles(&plan, map, &Obstacles::default(), seed, order);
    (plan, files)
}

#[test]
fn density_moves_monotonically_across_the_band_and_each_color_keeps_its_own_away_from_it() {
    let map = two_color_map();
    let band = map.band();
    assert!(band > 0.0 && band < BOUNDARY / 2.0, "band {band} m");
    let (_, files) = fill(&map, 5, |_| {});
    let tiles: Vec<TileContent> = files
        .values()
        .map(|b| match decode_tile(b) {
            Ok(t) => t,
            Err(e) => panic!("{e}"),
        })
        .collect();
    let categories = tiles[0].categories.clone();
    assert_eq!(categories, vec!["shrub".to_string(), "tree".into()]);
    // density of each category in windows across the whole height, along X
    let density = |category: usize, x0: f64, x1: f64| {
        let n = tiles
            .iter()
            .flat_map(|t| &t.instances)
            .filter(|i| i.category == category && i.position.x >= x0 && i.position.x < x1)
            .count();
        n as f64 / ((x1 - x0) * HEIGHT)
    };
    // away from the band (and a region of influence more): each color's own density, as a paste keeps it
    let away = band / 2.0 + map.influence();
    let (west_shrubs, west_trees) = (
        density(0, 0.0, BOUNDARY - away),
        density(1, 0.0, BOUNDARY - away),
    );
    let (east_shrubs, east_trees) = (
        density(0, BOUNDARY + away, WIDTH),
        density(1, BOUNDARY + away, WIDTH),
    );
    println!("band {band:.1} m; west shrubs {west_shrubs:.4} trees {west_trees:.4}; east shrubs {east_shrubs:.4} trees {east_trees:.4}");
    assert!(
        (west_shrubs / SHRUBS - 1.0).abs() < 0.1,
        "west shrubs {west_shrubs}"
    );
    assert!(
        (east_trees / TREES - 1.0).abs() < 0.15,
        "east trees {east_trees}"
    );
    assert_eq!((west_trees, east_shrubs), (0.0, 0.0));
    // across the band, in windows of a quarter band: shrubs never rise eastwards, trees never fall, beyond the
    // counting noise of a window (two standard deviations of a Poisson count)
    let windows = 8;
    let w = band * 1.5 / windows as f64;
    let x0 = BOUNDARY - band * 0.75;
    let mut last: Option<(f64, f64)> = None;
    let mut profile = Vec::new();
    for k in 0..windows {
        let (a, b) = (x0 + k as f64 * w, x0 + (k + 1) as f64 * w);
        let (s, t) = (density(0, a, b), density(1, a, b));
        profile.push(format!("{:.0}: {s:.4} {t:.4}", (a + b) / 2.0));
        let noise = |d: f64| 2.0 * (d.max(TREES) * w * HEIGHT).sqrt() / (w * HEIGHT);
        if let Some((ls, lt)) = last {
            assert!(s <= ls + noise(ls), "shrubs rise eastwards: {profile:?}");
            assert!(t >= lt - noise(lt), "trees fall eastwards: {profile:?}");
        }
        last = Some((s, t));
    }
    println!("across the band (x: shrubs trees per m²): {profile:?}");
    // the band does blend: its middle holds both, each well below its own color's density
    let (mid_shrubs, mid_trees) = (
        density(0, BOUNDARY - w, BOUNDARY + w),
        density(1, BOUNDARY - w, BOUNDARY + w),
    );
    assert!(
        mid_shrubs > 0.2 * SHRUBS && mid_shrubs < 0.8 * SHRUBS,
        "{profile:?}"
    );
    assert!(
        mid_trees > 0.2 * TREES && mid_trees < 0.8 * TREES,
        "{profile:?}"
    );
}

#[test]
fn a_map_world_is_the_same_whatever_the_tile_order() {
    let map = two_color_map();
    let (_, forward) = fill(&map, 9, |_| {});
    let (_, reversed) = fill(&map, 9, |tiles| tiles.reverse());
    assert_eq!(forward, reversed);
    let (_, other) = fill(&map, 10, |_| {});
    assert_ne!(forward, other);
}

#[test]
fn blocks_follow_the_boundary_and_slabs_run_from_one_color_to_the_other() {
    let map = two_color_map();
    let blocks = map.blocks(DVec2::new(200.0, 0.0), DVec2::new(400.0, 200.0));
    // the blocks tile the rectangle
    let area: f64 = blocks
        .iter()
        .map(|b| (b.max - b.min).x * (b.max - b.min).y)
        .sum();
    assert!(
        (area - 200.0 * 200.0).abs() < 1e-6,
        "blocks cover {area} m²"
    );
    // along X the paint goes from shrubs (color 0) through the slabs to trees (color 1), never back
    let mut xs: Vec<(f64, Paint)> = blocks
        .iter()
        .map(|b| ((b.min.x + b.max.x) / 2.0, b.paint))
        .collect();
    xs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let rank = |p: Paint| match p {
        Paint::Pure(0) => 0,
        Paint::Mix { a: 0, b: 1, slab } => slab + 1,
        Paint::Pure(1) => 1000,
        other => panic!("unexpected paint {other:?}"),
    };
    assert!(
        xs.windows(2).all(|w| rank(w[0].1) <= rank(w[1].1)),
        "{xs:?}"
    );
    assert_eq!(rank(xs[0].1), 0);
    assert_eq!(rank(xs[xs.len() - 1].1), 1000);
    // no blend outside half a band of the boundary
    for b in &blocks {
        if matches!(b.paint, Paint::Mix { .. }) {
            assert!(
                b.max.x > BOUNDARY - map.band() / 2.0 - 1e-9
                    && b.min.x < BOUNDARY + map.band() / 2.0 + 1e-9
            );
        }
    }
    // a tile away from the boundary is one block
    assert_eq!(map.blocks(DVec2::ZERO, DVec2::new(150.0, 200.0)).len(), 1);
}

#[test]
fn bad_maps_are_refused_with_what_is_wrong() {
    let said = |r: Result<ColorMap, worldpaint_core::Error>, words: &[&str]| match r {
        Ok(_) => panic!("a bad map was taken"),
        Err(e) => {
            let m = e.to_string();
            for w in words {
                assert!(m.contains(w), "'{m}' does not say '{w}'");
            }
        }
    };
    let shrubs = color("Shrubland", "shrub", SHRUBS, 1);
    // a label with no legend entry: which, and where
    said(
        ColorMap::new(two_label_grid(), vec![(7, shrubs.clone())], None),
        &["its label 3 (first at x 310.0, y 10.0) has no legend entry"],
    );
    // a label listed twice
    said(
        ColorMap::new(
            two_label_grid(),
            vec![
                (7, shrubs.clone()),
                (3, shrubs.clone()),
                (7, shrubs.clone()),
            ],
            None,
        ),
        &["label 7 twice"],
    );
    // labels that do not match the grid's size, a bad cell, a negative band
    let mut short = two_label_grid();
    short.labels.pop();
    said(
        ColorMap::new(short, vec![(7, shrubs.clone()), (3, shrubs.clone())], None),
        &["labels"],
    );
    let mut flat = two_label_grid();
    flat.cell = f64::NAN;
    said(
        ColorMap::new(flat, vec![(7, shrubs.clone()), (3, shrubs.clone())], None),
        &["cell"],
    );
    said(
        ColorMap::new(
            two_label_grid(),
            vec![(7, shrubs.clone()), (3, shrubs.clone())],
            Some(-1.0),
        ),
        &["band"],
    );
    // a map that does not cover the world: refused by the plan
    let map = two_color_map();
    match WorldPlan::for_map(
        DVec2::ZERO,
        DVec2::new(WIDTH + 100.0, HEIGHT),
        &map,
        Some(TILE),
    ) {
        Ok(_) => panic!("a world wider than its map was planned"),
        Err(e) => assert!(
            e.to_string().contains("the map: covers x 0.0..600.0"),
            "{e}"
        ),
    }
}

/// A color of trees with a hard core `core` (m) at `density`.
fn stand(name: &str, density: f64, core: f64, seed: u64) -> Color {
    let example = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(100.0),
    };
    let scene = scene_from_points("tree", &hard_core_points(&example, density, core, seed));
    match learn_color(&scene, &example, name, &AnalysisOptions::default()) {
        Ok(c) => c,
        Err(e) => panic!("learning {name}: {e}"),
    }
}

#[test]
fn no_two_trees_come_closer_than_the_hard_core_across_blocks_bands_and_tiles() {
    // dense trees with a 3 m core west, sparse ones with a 6 m core east: the band between them is painted in
    // blocks, each conditioned on those before it and on the earlier tiles
    let legend = vec![
        (7, stand("Stand", 0.03, 3.0, 1)),
        (3, stand("Grove", 0.006, 6.0, 2)),
    ];
    let map = match ColorMap::new(two_label_grid(), legend, None) {
        Ok(m) => m,
        Err(e) => panic!("the map: {e}"),
    };
    let (_, files) = fill(&map, 3, |_| {});
    let trees: Vec<DVec2> = files
        .values()
        .flat_map(|b| match decode_tile(b) {
            Ok(t) => t
                .instances
                .into_iter()
                .map(|i| i.position)
                .collect::<Vec<_>>(),
            Err(e) => panic!("{e}"),
        })
        .collect();
    // the closest pair, through a grid of 3 m cells
    let mut cells: std::collections::HashMap<(i64, i64), Vec<usize>> =
        std::collections::HashMap::new();
    let key = |p: DVec2| ((p.x / 3.0).floor() as i64, (p.y / 3.0).floor() as i64);
    for (k, p) in trees.iter().enumerate() {
        cells.entry(key(*p)).or_default().push(k);
    }
    let mut closest = f64::INFINITY;
    for (k, p) in trees.iter().enumerate() {
        let (i, j) = key(*p);
        for di in -1..=1 {
            for dj in -1..=1 {
                for &o in cells.get(&(i + di, j + dj)).map_or(&[][..], |v| &v[..]) {
                    if o > k {
                        closest = closest.min(p.distance(trees[o]));
                    }
                }
            }
        }
    }
    println!(
        "{} trees, the closest two {closest:.2} m apart (hard cores 3 and 6 m)",
        trees.len()
    );
    assert!(trees.len() > 1000);
    assert!(closest >= 0.95 * 3.0, "two trees {closest:.2} m apart");
    // displacement interpolation moves the pcf's hard core from 3 m to 6 m across the band: in windows along it,
    // the distance below which a tenth of the trees have their nearest neighbour never falls eastwards (beyond
    // 0.3 m), and runs from the stand's to the grove's
    let band = map.band();
    let windows = 6;
    let w = band * 1.5 / windows as f64;
    let x0 = BOUNDARY - band * 0.75;
    let nearest = |i: usize| {
        let (ci, cj) = key(trees[i]);
        (-2..=2)
            .flat_map(|di| (-2..=2).map(move |dj| (ci + di, cj + dj)))
            .flat_map(|c| cells.get(&c).map_or(&[][..], |v| &v[..]))
            .filter(|&&o| o != i)
            .map(|&o| trees[i].distance(trees[o]))
            .fold(f64::INFINITY, f64::min)
    };
    let mut cores = Vec::new();
    for k in 0..windows {
        let (a, b) = (x0 + k as f64 * w, x0 + (k + 1) as f64 * w);
        let mut d: Vec<f64> = (0..trees.len())
            .filter(|&i| {
                trees[i].x >= a && trees[i].x < b && trees[i].y >= 6.0 && trees[i].y < HEIGHT - 6.0
            })
            .map(nearest)
            .filter(|d| d.is_finite())
            .collect();
        d.sort_by(f64::total_cmp);
        cores.push(((a + b) / 2.0, d[d.len() / 10]));
    }
    println!("nearest-neighbour distance of the closest tenth across the band (x, m): {cores:.2?}");
    assert!(
        cores.windows(2).all(|c| c[1].1 >= c[0].1 - 0.3),
        "{cores:.2?}"
    );
    assert!(
        cores[0].1 < 4.0 && cores[windows - 1].1 > 5.5,
        "{cores:.2?}"
    );
}

//! A world's roads seen by its colors: a color that learned to keep its trees off its roads (a verge) keeps them
//! off the world's roads, which its tiles are conditioned on; a color learned without roads stands its trees up to
//! the carriageway.

mod common;

use common::world_driver::fill_tiles;
use std::collections::BTreeMap;
use worldpaint_core::{
    decode_tile, learn_color, road_categories, segment_distance, uniform_points, AnalysisOptions,
    Category, CategoryKind, Color, ColorMap, DVec2, Instance, Obstacles, Path, Region, Scene,
    TileId, WorldPlan,
};

const EXAMPLE: f64 = 240.0;
const VERGE: f64 = 15.0;
const SIDE: f64 = 600.0;
const ROAD_WIDTH: f64 = 4.0;

fn distance(p: DVec2, line: &[DVec2]) -> f64 {
    line.windows(2)
        .map(|s| segment_distance(p, s[0], s[1]))
        .fold(f64::INFINITY, f64::min)
}

/// A gently winding east-west road at `y`, from `x0` to `x1`, a vertex every 10 m.
fn road(y: f64, x0: f64, x1: f64) -> Vec<DVec2> {
    let n = ((x1 - x0) / 10.0) as usize;
    (0..=n)
        .map(|k| {
            let x = x0 + 10.0 * k as f64;
            DVec2::new(x, y + 6.0 * (x / 90.0).sin())
        })
        .collect()
}

/// The example: two roads across a 240 m square and trees (0.01 per m²) everywhere but within 15 m of them; with
/// `roads` false, the same trees without the roads.
fn learned(road_name: &str, roads: bool) -> Color {
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(EXAMPLE),
    };
    let lines = [road(60.0, -60.0, 300.0), road(180.0, -60.0, 300.0)];
    let trees: Vec<Instance> = uniform_points(&region, 0.01, 7)
        .into_iter()
        .filter(|p| lines.iter().all(|l| distance(*p, l) >= VERGE))
        .map(|p| Instance::at(p, 1))
        .collect();
    let scene = Scene {
        categories: vec![
            Category::new(road_name, "roads", CategoryKind::Graph, 0),
            Category::distribution("tree", "vegetation", 1),
        ],
        instances: trees,
        paths: if roads {
            lines
                .iter()
                .map(|points| Path {
                    category: 0,
                    points: points.clone(),
                    locked: false,
                })
                .collect()
        } else {
            Vec::new()
        },
        ..Default::default()
    };
    let scene = if roads {
        scene
    } else {
        Scene {
            categories: vec![Category::distribution("tree", "vegetation", 0)],
            instances: scene
                .instances
                .iter()
                .map(|i| Instance::at(i.position, 0))
                .collect(),
            ..Default::default()
        }
    };
    match learn_color(&scene, &region, "Verge", &AnalysisOptions::default()) {
        Ok(c) => c,
        Err(e) => panic!("learning the verge: {e}"),
    }
}

/// Every tree of a world of `color` over 600 m with one road across it at y = 300 m.
fn trees_of(color: &Color) -> Vec<DVec2> {
    let map = match ColorMap::uniform(color.clone()) {
        Ok(m) => m,
        Err(e) => panic!("a map of one color: {e}"),
    };
    let plan = match WorldPlan::for_map(DVec2::ZERO, DVec2::splat(SIDE), &map, Some(200.0)) {
        Ok(p) => p,
        Err(e) => panic!("plan: {e}"),
    };
    let obstacles = Obstacles::new(&[], &[road(300.0, -100.0, 700.0)], ROAD_WIDTH);
    let files: BTreeMap<TileId, Vec<u8>> = fill_tiles(&plan, &map, &obstacles, 5, |_| {});
    let mut trees = Vec::new();
    for bytes in files.values() {
        let tile = match decode_tile(bytes) {
            Ok(t) => t,
            Err(e) => panic!("decoding: {e}"),
        };
        let tree = tile.categories.iter().position(|c| c == "tree");
        trees.extend(
            tile.instances
                .iter()
                .filter(|i| Some(i.category) == tree)
                .map(|i| i.position),
        );
    }
    trees
}

/// Trees per m² within `near` of the world's road (beyond its carriageway) over those farther than 40 m.
fn verge_ratio(trees: &[DVec2], near: f64) -> f64 {
    let line = road(300.0, -100.0, 700.0);
    let d: Vec<f64> = trees.iter().map(|p| distance(*p, &line)).collect();
    let verge = d
        .iter()
        .filter(|&&d| d >= ROAD_WIDTH / 2.0 && d < near)
        .count() as f64;
    let far = d.iter().filter(|&&d| d >= 40.0).count() as f64;
    let verge_area = 2.0 * (near - ROAD_WIDTH / 2.0) * SIDE;
    let far_area = SIDE * SIDE - 2.0 * 40.0 * SIDE;
    (verge / verge_area) / (far / far_area)
}

#[test]
fn a_color_that_keeps_its_trees_off_its_roads_keeps_them_off_the_worlds() {
    let verge = learned("road", true);
    let plain = learned("road", false);
    let (with, without) = (trees_of(&verge), trees_of(&plain));
    let line = road(300.0, -100.0, 700.0);
    let nearest = with
        .iter()
        .map(|p| distance(*p, &line))
        .fold(f64::INFINITY, f64::min);
    let (ratio_with, ratio_without) = (verge_ratio(&with, 12.0), verge_ratio(&without, 12.0));
    println!(
        "trees within 2-12 m of the road over those beyond 40 m: {ratio_with:.2} learned with roads, \
         {ratio_without:.2} without ({} and {} trees); nearest to the road {nearest:.1} m",
        with.len(),
        without.len()
    );
    assert!(
        ratio_with < 0.3,
        "the verge's trees stand by the world's road: {ratio_with:.2} of the density beyond 40 m"
    );
    assert!(
        ratio_without > 0.7,
        "trees learned without roads keep off the road: {ratio_without:.2}"
    );
    // no tree on the carriageway either way
    assert!(without
        .iter()
        .all(|p| distance(*p, &line) > ROAD_WIDTH / 2.0 - 1e-9));
}

#[test]
fn the_worlds_roads_are_its_road_categories() {
    let cats = |names: &[(&str, CategoryKind)]| -> Vec<Category> {
        names
            .iter()
            .map(|(n, k)| Category::new(n, "x", *k, 0))
            .collect()
    };
    use CategoryKind::{Distribution, Graph};
    assert_eq!(
        road_categories(&cats(&[("tree", Distribution), ("Path", Graph)])),
        vec![1]
    );
    assert_eq!(
        road_categories(&cats(&[
            ("River", Graph),
            ("Main Road", Graph),
            ("tree", Distribution)
        ])),
        vec![1]
    );
    assert!(road_categories(&cats(&[("River", Graph), ("Stream", Graph)])).is_empty());
    assert!(road_categories(&cats(&[("tree", Distribution)])).is_empty());
}

//! Villages in a world: three sites on hills grow their villages after the roads that join them, every village is
//! reachable by road from every other, a color filled around them puts no instance on a road's carriageway or in a
//! house's footprint, and bad sites are refused with what is wrong.

use std::sync::Arc;
use worldpaint_core::{
    grow_world_villages, learn_color, scene_from_points, synthesize_tile, uniform_points,
    AnalysisOptions, ColorMap, DVec2, Encyclopedia, Heightfield, Obstacles, Region, VillageSite,
    WorldPlan, WorldVillages,
};

const ENCYCLOPEDIA: &str = include_str!("../../../assets/villages/encyclopedia.json");
const SIDE: f64 = 1600.0;
const CELL: f64 = 4.0;

/// Rolling hills over the world, 8 m samples: up to 60 m of relief, grades mostly under the roads' 15 %.
fn hills() -> Arc<Heightfield> {
    let n = (SIDE / 8.0) as usize + 1;
    let heights = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64 * 8.0, (k / n) as f64 * 8.0);
            (30.0 * (x / 260.0).sin() * (y / 310.0).cos() + 0.02 * x) as f32
        })
        .collect();
    match Heightfield::new(DVec2::ZERO, 8.0, n, n, heights) {
        Ok(h) => Arc::new(h),
        Err(e) => panic!("hills: {e}"),
    }
}

fn encyclopedia() -> Encyclopedia {
    match Encyclopedia::from_json(ENCYCLOPEDIA) {
        Ok(e) => e,
        Err(e) => panic!("the shipped encyclopedia: {e}"),
    }
}

fn site(x: f64, y: f64, village_type: &str, seed: u64) -> VillageSite {
    VillageSite {
        position: DVec2::new(x, y),
        village_type: village_type.into(),
        buildings: 12,
        seed,
    }
}

fn three_sites() -> Vec<VillageSite> {
    vec![
        site(300.0, 300.0, "farming", 1),
        site(1300.0, 350.0, "highland", 2),
        site(800.0, 1300.0, "farming", 3),
    ]
}

fn grow(sites: &[VillageSite]) -> Result<WorldVillages, worldpaint_core::Error> {
    grow_world_villages(
        &hills(),
        DVec2::ZERO,
        DVec2::splat(SIDE),
        sites,
        &encyclopedia(),
        CELL,
    )
}

/// The polylines of `roads` joined where one's end lies within `reach` of another: the groups they form.
fn connected_groups(roads: &[Vec<DVec2>], reach: f64) -> Vec<usize> {
    let n = roads.len();
    let mut group: Vec<usize> = (0..n).collect();
    fn find(g: &mut [usize], k: usize) -> usize {
        let mut r = k;
        while g[r] != r {
            r = g[r];
        }
        g[k] = r;
        r
    }
    let near = |p: DVec2, line: &[DVec2]| {
        line.windows(2)
            .any(|s| worldpaint_core::segment_distance(p, s[0], s[1]) <= reach)
    };
    for a in 0..n {
        for b in 0..n {
            let ends = [roads[a][0], roads[a][roads[a].len() - 1]];
            if a != b && ends.iter().any(|&p| near(p, &roads[b])) {
                let (ra, rb) = (find(&mut group, a), find(&mut group, b));
                group[ra] = rb;
            }
        }
    }
    (0..n).map(|k| find(&mut group, k)).collect()
}

#[test]
fn villages_grow_joined_by_roads_and_a_filled_color_keeps_off_roads_and_houses() {
    let sites = three_sites();
    let world = match grow(&sites) {
        Ok(w) => w,
        Err(e) => panic!("the villages did not grow: {e}"),
    };
    let built: Vec<usize> = world.villages.iter().map(|v| v.footprints.len()).collect();
    println!(
        "buildings {built:?}, {} world roads, {:.0} m",
        world.roads.len(),
        world
            .roads
            .iter()
            .flat_map(|r| r.points.windows(2))
            .map(|s| s[0].distance(s[1]))
            .sum::<f64>()
    );
    assert!(
        built.iter().all(|&b| b >= 9),
        "a village grew fewer than 9 of its 12 buildings: {built:?}"
    );
    // every village reachable from every other: the world roads and the villages' own form one network, and
    // each site lies on it
    let lines: Vec<Vec<DVec2>> = world
        .roads
        .iter()
        .chain(world.villages.iter().flat_map(|v| &v.roads))
        .map(|r| r.points.clone())
        .filter(|l| l.len() >= 2)
        .collect();
    let groups = connected_groups(&lines, 2.0 * CELL);
    let world_groups: std::collections::BTreeSet<usize> =
        groups[..world.roads.len()].iter().copied().collect();
    assert_eq!(
        world_groups.len(),
        1,
        "the roads between villages fall apart into {world_groups:?}"
    );
    for (k, s) in sites.iter().enumerate() {
        let on_road = world.roads.iter().any(|r| {
            r.points
                .windows(2)
                .any(|w| worldpaint_core::segment_distance(s.position, w[0], w[1]) <= 2.0 * CELL)
        });
        assert!(
            on_road,
            "village site {} is off the roads between villages",
            k + 1
        );
    }
    // a color filled over the world around them
    let example = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(100.0),
    };
    let scene = scene_from_points("tree", &uniform_points(&example, 0.01, 4));
    let color = match learn_color(&scene, &example, "Trees", &AnalysisOptions::default()) {
        Ok(c) => c,
        Err(e) => panic!("{e}"),
    };
    let footprints: Vec<Vec<DVec2>> = world
        .villages
        .iter()
        .flat_map(|v| &v.footprints)
        .map(|f| f.corners.to_vec())
        .collect();
    let obstacles = Obstacles::new(&footprints, &lines, world.road_width);
    let own: f64 = color.categories.iter().map(|c| c.density).sum();
    let map = match ColorMap::uniform(color) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    let plan = match WorldPlan::for_map(DVec2::ZERO, DVec2::splat(SIDE), &map, Some(800.0)) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    let mut instances = Vec::new();
    for t in plan.tiles() {
        // neighbours left out: this test reads where the instances stand, not the seams
        match synthesize_tile(&plan, t, &map, &obstacles, Some(hills()), &[], 7, None) {
            Ok(c) => instances.extend(c.instances),
            Err(e) => panic!("tile {t:?}: {e}"),
        }
    }
    let half = world.road_width / 2.0;
    let on_road = instances
        .iter()
        .filter(|i| {
            lines.iter().any(|l| {
                l.windows(2)
                    .any(|s| worldpaint_core::segment_distance(i.position, s[0], s[1]) < half)
            })
        })
        .count();
    let in_house = instances
        .iter()
        .filter(|i| {
            footprints
                .iter()
                .any(|f| worldpaint_core::polygon_contains(f, i.position))
        })
        .count();
    let density = instances.len() as f64 / (SIDE * SIDE);
    println!(
        "{} instances ({density:.4} per m²), {on_road} on a road, {in_house} in a house",
        instances.len()
    );
    assert_eq!((on_road, in_house), (0, 0));
    // the free ground keeps the color's density (the roads and houses cover a few per cent of the world)
    assert!(
        (density / own - 1.0).abs() < 0.08,
        "density {density}, the color's {own}"
    );
}

#[test]
fn bad_sites_are_refused_with_what_is_wrong() {
    let said = |sites: Vec<VillageSite>, words: &[&str]| match grow(&sites) {
        Ok(_) => panic!("bad sites grew"),
        Err(e) => {
            let m = e.to_string();
            for w in words {
                assert!(m.contains(w), "'{m}' does not say '{w}'");
            }
        }
    };
    let mut sites = three_sites();
    sites[1].position = DVec2::new(2500.0, 300.0);
    said(
        sites,
        &[
            "village site 2 at x 2500.0, y 300.0",
            "off the world's terrain",
        ],
    );
    let mut sites = three_sites();
    sites[2].village_type = "metropolis".into();
    said(sites, &["village site 3", "'metropolis'", "farming"]);
    let mut sites = three_sites();
    sites[0].buildings = 0;
    said(sites, &["village site 1", "0 buildings"]);
    let mut sites = three_sites();
    sites[2].position = DVec2::new(400.0, 400.0);
    said(
        sites,
        &[
            "village site 3",
            "m from village site 1; their villages",
            "apart",
        ],
    );
    let mut sites = three_sites();
    sites[0].position = DVec2::new(f64::NAN, 300.0);
    said(sites, &["village site 1", "off the world's terrain"]);
}

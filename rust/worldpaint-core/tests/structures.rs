//! Structured content in synthesis (Sections 4.1, 4.2 and 6): road networks keep their edge lengths, turning
//! angles, smallest angle and fragmentation; houses keep their band along the roads; islands keep their trees
//! on land and their boats along the coast.

use worldpaint_core::{
    archipelago_scene, learn_color, synthesize, village_scene, AnalysisOptions, Color, DVec2,
    Graph, Histogram, Polygons, Region, Scene, SynthesisOptions,
};

fn square(origin: f64, size: f64) -> Region {
    Region::Rect {
        min: DVec2::splat(origin),
        max: DVec2::splat(origin + size),
    }
}

/// The graph of the synthesized paths.
fn graph_of(paths: &[worldpaint_core::Path]) -> Graph {
    let paths: Vec<&[DVec2]> = paths.iter().map(|p| p.points.as_slice()).collect();
    Graph::from_paths(&paths, 1e-6)
}

/// The positions of the instances of the category `name` of a synthesis result.
fn positions_of(out: &worldpaint_core::SynthesisResult, name: &str) -> Vec<DVec2> {
    let k = out.categories.iter().position(|c| c.name == name).unwrap();
    out.instances
        .iter()
        .filter(|i| i.category == k)
        .map(|i| i.position)
        .collect()
}

/// Moves the content of `source` by `offset`: the move and the scene after it.
fn move_and_apply(
    scene: &Scene,
    color: &Color,
    source: &Region,
    offset: DVec2,
) -> (worldpaint_core::Moved, Scene) {
    let moved =
        worldpaint_core::move_region(scene, Some(color), source, offset, &Default::default())
            .unwrap();
    let after = moved.edit.applied_to(scene);
    (moved, after)
}

/// The paths as drawn: nodes at their vertices only (shared vertices merged), so that edges crossing away from a
/// node show up as crossings, which the planar graph of [`graph_of`] would have split into nodes.
fn drawn_graph(paths: &[worldpaint_core::Path]) -> Graph {
    let mut g = Graph::default();
    let mut ids = std::collections::HashMap::new();
    for p in paths {
        let ids: Vec<u32> = p
            .points
            .iter()
            .map(|q| {
                *ids.entry((q.x.to_bits(), q.y.to_bits()))
                    .or_insert_with(|| {
                        g.nodes.push(*q);
                        g.nodes.len() as u32 - 1
                    })
            })
            .collect();
        for w in ids.windows(2) {
            if w[0] != w[1] {
                g.edges.push([w[0].min(w[1]), w[0].max(w[1])]);
            }
        }
    }
    g
}

/// Edge lengths and angles at nodes of `g`, on the bins of the learned histograms.
fn statistics(g: &Graph, lengths: &Histogram, angles: &Histogram) -> (Histogram, Histogram) {
    let mut l = Histogram::zeros(lengths.start, lengths.bin_width, lengths.values.len());
    for e in &g.edges {
        l.add(g.edge_length(*e), 1.0);
    }
    let mut a = Histogram::zeros(angles.start, angles.bin_width, angles.values.len());
    for (n, nb) in g.adjacency().iter().enumerate() {
        for (i, &x) in nb.iter().enumerate() {
            for &y in &nb[i + 1..] {
                a.add(
                    g.angle_at(n as u32, x, y).min(std::f64::consts::PI - 1e-12),
                    1.0,
                );
            }
        }
    }
    (l, a)
}

/// The share of dead ends (nodes of one edge) among the nodes of `g` inside `region` and at least `margin` from
/// its border, with the count of those nodes. Nodes nearer the border are left out of both counts: there a road
/// may end because the region cuts it (its continuation lies beyond), which says nothing of the network.
fn dead_end_share(g: &Graph, region: &Region, margin: f64) -> (f64, usize) {
    let adj = g.adjacency();
    let interior: Vec<usize> = (0..g.nodes.len())
        .filter(|&n| {
            !adj[n].is_empty()
                && region.contains(g.nodes[n])
                && region.distance_to_boundary(g.nodes[n]) >= margin
        })
        .collect();
    let dead = interior.iter().filter(|&&n| adj[n].len() == 1).count();
    (dead as f64 / interior.len().max(1) as f64, interior.len())
}

/// The turning angles of `g` (at its nodes of two edges) on the bins of the learned histogram.
fn turns(g: &Graph, learned: &Histogram) -> Histogram {
    let mut h = Histogram::zeros(learned.start, learned.bin_width, learned.values.len());
    for t in g.turning_angles() {
        h.add(t.min(std::f64::consts::PI - 1e-12), 1.0);
    }
    h
}

/// The share of `points` whose distance to `g` lies in `band`.
fn share_in_band(points: &[DVec2], g: &Graph, band: std::ops::RangeInclusive<f64>) -> f64 {
    let index = worldpaint_core::SegmentIndex::new(g.segments());
    let inside = points
        .iter()
        .filter(|p| band.contains(&index.distance(**p, 1e3)))
        .count();
    inside as f64 / points.len().max(1) as f64
}

/// An exemplar scene of `size` m from the origin and the color `name` learned over all of it.
/// The archipelago exemplar of `size`, its color, and an empty canvas with its categories.
fn archipelago_color(size: f64) -> (Scene, Color, Scene) {
    let (scene, color) = with_color(archipelago_scene(size, 1), size, "islands");
    let canvas = Scene {
        categories: scene.categories.clone(),
        ..Default::default()
    };
    (scene, color, canvas)
}

fn with_color(scene: Scene, size: f64, name: &str) -> (Scene, Color) {
    let color = learn_color(
        &scene,
        &square(0.0, size),
        name,
        &AnalysisOptions::default(),
    )
    .unwrap();
    (scene, color)
}

fn village_color(size: f64) -> (Scene, Color) {
    with_color(village_scene(size, 1), size, "village")
}

#[test]
fn a_road_network_keeps_its_statistics_over_nine_times_the_area() {
    // large enough a village for its count of network pieces to mean something (three in the region)
    let size = 450.0;
    let (scene, color) = village_color(size);
    let roads = color.graph("road").unwrap();
    let dest = square(1000.0, 3.0 * size);
    let canvas = Scene {
        categories: scene.categories.clone(),
        ..Default::default()
    };
    let opts = SynthesisOptions {
        seed: 3,
        categories: Some(vec!["road".into(), "house".into()]),
        ..Default::default()
    };
    let out = synthesize(&canvas, &color, &dest, &opts).unwrap();
    let g = graph_of(&out.paths);
    let (lengths, angles) = statistics(&g, &roads.edge_length, &roads.angle);
    let length_tv = roads.edge_length.total_variation(&lengths);
    let angle_tv = roads.angle.total_variation(&angles);
    let components = g.components() as f64 / dest.area();
    let turn_tv = roads.turn.total_variation(&turns(&g, &roads.turn));
    // dead ends counted at least one longest learned edge inside the border, in the exemplar as in the painting
    let margin = roads.edge_length.start
        + roads.edge_length.values.len() as f64 * roads.edge_length.bin_width;
    let (dead_before, counted_before) =
        dead_end_share(&graph_of(&scene.paths), &square(0.0, size), margin);
    let (dead_after, counted_after) = dead_end_share(&g, &dest, margin);
    println!(
        "dead ends {:.3} of {counted_after} interior nodes (exemplar {:.3} of {counted_before}, learned degree-1 \
         share {:.3}), turning angle TV {turn_tv:.3}",
        dead_after, dead_before, roads.degree[0]
    );
    println!(
        "{} nodes, {} edges ({:.1} km): edge length TV {length_tv:.3}, angle TV {angle_tv:.3}, smallest angle \
         {:.1}° (learned {:.1}°), components per km² {:.1} (exemplar {:.1}), {} crossings",
        g.nodes.len(),
        g.edges.len(),
        g.edges.iter().map(|e| g.edge_length(*e)).sum::<f64>() / 1e3,
        g.min_angle().to_degrees(),
        roads.min_angle.to_degrees(),
        components * 1e6,
        roads.components_per_area * 1e6,
        drawn_graph(&out.paths).crossings()
    );
    assert!(
        g.nodes.len() > 300,
        "a 1350 m square of village has hundreds of road nodes"
    );
    assert!(length_tv <= 0.15, "edge length TV {length_tv}");
    assert!(angle_tv <= 0.15, "angle TV {angle_tv}");
    assert_eq!(
        drawn_graph(&out.paths).crossings(),
        0,
        "edges cross only at nodes"
    );
    assert!(g.min_angle() >= roads.min_angle - 1e-9);
    let ratio = components / roads.components_per_area;
    assert!(
        (0.7..=1.3).contains(&ratio),
        "components per area {ratio:.2}× the exemplar's"
    );
    assert!(turn_tv <= 0.15, "turning angle TV {turn_tv}");
    assert!(
        (dead_after / dead_before - 1.0).abs() <= 0.3,
        "dead-end share {dead_after:.3} against the exemplar's {dead_before:.3}"
    );

    // houses learned 8–15 m from the roads stay in that band
    let houses = positions_of(&out, "house");
    let painted = Scene {
        categories: out.categories.clone(),
        instances: out.instances.clone(),
        paths: out.paths.clone(),
        ..Default::default()
    };
    let again = AnalysisOptions {
        max_radius: Some(color.max_radius),
        bin_width: Some(color.bin_width),
        ..Default::default()
    };
    let learned = learn_color(&painted, &dest, "painted", &again).unwrap();
    let map = |c: &Color| {
        c.maps
            .iter()
            .find(|m| m.category == "house" && m.map == "road")
            .unwrap()
            .hist
            .clone()
    };
    let distance_tv = map(&color).total_variation(&map(&learned));
    let band = share_in_band(&houses, &g, 8.0..=15.0);
    println!(
        "{} houses: distance-to-road TV {distance_tv:.3}, {:.1} % within 8–15 m",
        houses.len(),
        100.0 * band
    );
    assert!(distance_tv <= 0.15, "distance-to-road TV {distance_tv}");
    assert!(band >= 0.9, "share of houses 8–15 m from a road {band}");
}

#[test]
fn island_trees_stay_on_land_and_boats_along_the_coast() {
    let size = 300.0;
    let (scene, color, canvas) = archipelago_color(size);
    let dest = square(2000.0, 2.0 * size);
    // the synthesis of a color and the land of its islands
    let paint = |color: &Color| {
        let opts = SynthesisOptions {
            seed: 5,
            ..Default::default()
        };
        let out = synthesize(&canvas, color, &dest, &opts).unwrap();
        let contours: Vec<Vec<DVec2>> = out.contours.iter().map(|c| c.points.clone()).collect();
        (out, Polygons::new(&contours))
    };
    let (out, land) = paint(&color);
    let (trees, boats) = (positions_of(&out, "tree"), positions_of(&out, "boat"));
    let land_share = |contours: &[worldpaint_core::Contour], region: &Region| {
        let polys = Polygons::new(
            &contours
                .iter()
                .map(|c| c.points.clone())
                .collect::<Vec<_>>(),
        );
        let (lo, hi) = region.bbox();
        let n = 200;
        let inside = (0..n * n)
            .filter(|k| {
                let t = DVec2::new((k % n) as f64 + 0.5, (k / n) as f64 + 0.5) / n as f64;
                polys.contains(lo + (hi - lo) * t)
            })
            .count();
        inside as f64 / (n * n) as f64
    };
    let (land_before, land_after) = (
        land_share(&scene.contours, &square(0.0, size)),
        land_share(&out.contours, &dest),
    );
    println!("land: {land_before:.3} of the exemplar, {land_after:.3} of the synthesized square");
    assert!(
        (land_after / land_before - 1.0).abs() <= 0.15,
        "the islands keep their share of the land"
    );
    let wet = trees.iter().filter(|p| !land.contains(**p)).count();
    let afloat = boats.iter().filter(|p| !land.contains(**p)).count();
    let coastal = boats
        .iter()
        .filter(|p| land.distance(**p, 1e3) <= 12.0)
        .count();
    println!(
        "{} contours, {} trees ({wet} in water), {} boats ({afloat} on water, {coastal} within 12 m of a coast)",
        out.contours.len(),
        trees.len(),
        boats.len()
    );
    assert!(out.contours.len() >= 4 && trees.len() > 100 && boats.len() > 20);
    assert_eq!(wet, 0, "trees never land in water");
    assert_eq!(afloat, boats.len(), "boats stay on the water");
    assert!(
        coastal as f64 >= 0.9 * boats.len() as f64,
        "boats stay along the coast"
    );

    // with their relation to the islands switched off, trees stand anywhere: the water no longer keeps them off
    let free = color.without_interactions(&[("tree".into(), "island".into())]);
    let (out, land) = paint(&free);
    let trees = positions_of(&out, "tree");
    let wet = trees.iter().filter(|p| !land.contains(**p)).count();
    println!(
        "tree-island interaction off: {} trees, {wet} in water",
        trees.len()
    );
    assert!(
        wet as f64 >= 0.2 * trees.len() as f64,
        "{wet} of {} trees in water",
        trees.len()
    );
}

/// Contours and islands of `contours` counted in `region` (by their centroids): contours per km², islands per
/// km², and the islands' mean land area (m²).
fn island_figures(contours: &[Vec<DVec2>], region: &Region) -> (f64, f64, f64) {
    let centroid = |c: &[DVec2]| c.iter().copied().sum::<DVec2>() / c.len().max(1) as f64;
    let km2 = region.area() / 1e6;
    let in_region = contours
        .iter()
        .filter(|c| region.contains(centroid(c)))
        .count();
    let islands: Vec<f64> = worldpaint_core::islands(contours)
        .into_iter()
        .filter(|i| region.contains(centroid(&contours[i.outer])))
        .map(|i| i.area)
        .collect();
    let mean = islands.iter().sum::<f64>() / islands.len().max(1) as f64;
    (in_region as f64 / km2, islands.len() as f64 / km2, mean)
}

#[test]
fn islands_keep_their_count_and_size_over_nine_times_the_area() {
    let size = 300.0;
    let (scene, color, canvas) = archipelago_color(size);
    let dest = square(2000.0, 3.0 * size);
    let contours = |c: &[worldpaint_core::Contour]| -> Vec<Vec<DVec2>> {
        c.iter().map(|c| c.points.clone()).collect()
    };
    let (before_contours, before_islands, before_mean) =
        island_figures(&contours(&scene.contours), &square(0.0, size));
    for seed in [5, 6] {
        let opts = SynthesisOptions {
            seed,
            categories: Some(vec!["island".into()]),
            ..Default::default()
        };
        let out = synthesize(&canvas, &color, &dest, &opts).unwrap();
        let (after_contours, after_islands, after_mean) =
            island_figures(&contours(&out.contours), &dest);
        println!(
            "seed {seed}: {after_contours:.1} contours and {after_islands:.1} islands per km² of mean land \
             {after_mean:.0} m² (exemplar {before_contours:.1} and {before_islands:.1}, {before_mean:.0} m²)"
        );
        assert!(
            (after_contours / before_contours - 1.0).abs() <= 0.25,
            "contours per area {after_contours:.1} against {before_contours:.1}"
        );
        assert!(
            (after_mean / before_mean - 1.0).abs() <= 0.25,
            "mean island area {after_mean:.0} m² against {before_mean:.0} m²"
        );
    }
}

/// Four wobbly islands of 25 to 32 m in a 200 m square of sea (the add-on's island example).
fn four_islands() -> Scene {
    let contours = [
        (50.0, 50.0, 30.0),
        (150.0, 60.0, 25.0),
        (60.0, 150.0, 28.0),
        (150.0, 150.0, 32.0),
    ]
    .iter()
    .map(|&(cx, cy, r): &(f64, f64, f64)| worldpaint_core::Contour {
        category: 0,
        points: (0..48)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 48.0;
                let rr = r * (1.0 + 0.15 * (3.0 * a + cx).sin());
                DVec2::new(cx + rr * a.cos(), cy + rr * a.sin())
            })
            .collect(),
        locked: false,
    })
    .collect();
    Scene {
        categories: vec![worldpaint_core::Category::new(
            "island",
            "terrain",
            worldpaint_core::CategoryKind::Polygon,
            0,
        )],
        contours,
        ..Default::default()
    }
}

#[test]
fn four_islands_pasted_into_a_small_region_keep_their_count_size_and_land() {
    // from so small an example the chain leaves a few large clusters and dozens of islets of a few points
    let (scene, color) = with_color(four_islands(), 200.0, "islands");
    let dest = Region::Rect {
        min: DVec2::new(250.0, 0.0),
        max: DVec2::new(550.0, 200.0),
    };
    let canvas = Scene {
        categories: scene.categories.clone(),
        ..Default::default()
    };
    let contours = |c: &[worldpaint_core::Contour]| -> Vec<Vec<DVec2>> {
        c.iter().map(|c| c.points.clone()).collect()
    };
    let (before_contours, before_islands, before_mean) =
        island_figures(&contours(&scene.contours), &square(0.0, 200.0));
    let before_land = before_islands * before_mean / 1e6;
    for seed in [1, 2] {
        let opts = SynthesisOptions {
            seed,
            ..Default::default()
        };
        let out = synthesize(&canvas, &color, &dest, &opts).unwrap();
        let (after_contours, after_islands, after_mean) =
            island_figures(&contours(&out.contours), &dest);
        let after_land = after_islands * after_mean / 1e6;
        println!(
            "seed {seed}: {after_contours:.0} contours per km² and islands of mean land {after_mean:.0} m², \
             land share {after_land:.3} (example {before_contours:.0}, {before_mean:.0} m², {before_land:.3})"
        );
        assert!(
            (after_contours / before_contours - 1.0).abs() <= 0.25,
            "contours per area {after_contours:.0} against {before_contours:.0}"
        );
        assert!(
            (after_mean / before_mean - 1.0).abs() <= 0.25,
            "mean island area {after_mean:.0} m² against {before_mean:.0} m²"
        );
        assert!(
            (after_land / before_land - 1.0).abs() <= 0.25,
            "land share {after_land:.3} against {before_land:.3}"
        );
    }
}

#[test]
fn colors_saved_before_turning_angles_and_island_sizes_still_load_and_paint() {
    let (_, roads) = village_color(450.0);
    let (_, islands) = with_color(archipelago_scene(300.0, 1), 300.0, "islands");
    // the files as written before these fields were learned
    let strip = |color: &Color, fields: &[&str]| -> Color {
        let mut json: serde_json::Value = serde_json::from_str(&color.to_json().unwrap()).unwrap();
        let text = serde_json::to_string(&json).unwrap();
        assert!(fields.iter().all(|f| text.contains(&format!("\"{f}\""))));
        strip_fields(&mut json, fields);
        Color::from_json(&serde_json::to_string(&json).unwrap()).unwrap()
    };
    let old_roads = strip(&roads, &["turn"]);
    let old_islands = strip(
        &islands,
        &["islands_per_area", "island_areas", "lakes_per_area"],
    );
    assert!(old_roads.graph("road").unwrap().turn.values.is_empty());
    let p = old_islands.polygon("island").unwrap();
    assert!(p.islands_per_area == 0.0 && p.island_areas.is_empty() && p.lakes_per_area.is_none());
    for (color, category) in [(&old_roads, "road"), (&old_islands, "island")] {
        let opts = SynthesisOptions {
            seed: 1,
            categories: Some(vec![category.into()]),
            ..Default::default()
        };
        let out = synthesize(&color.blank_scene(), color, &square(0.0, 400.0), &opts).unwrap();
        println!(
            "{category} from an older file: {} paths, {} contours",
            out.paths.len(),
            out.contours.len()
        );
        assert!(!out.paths.is_empty() || !out.contours.is_empty());
    }
}

/// Removes every object field named in `fields`, at any depth.
fn strip_fields(v: &mut serde_json::Value, fields: &[&str]) {
    match v {
        serde_json::Value::Object(map) => {
            map.retain(|k, _| !fields.contains(&k.as_str()));
            map.values_mut().for_each(|x| strip_fields(x, fields));
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(|x| strip_fields(x, fields)),
        _ => {}
    }
}

#[test]
fn pasted_roads_join_the_roads_around() {
    let (_, color) = village_color(450.0);
    let world = village_scene(900.0, 2);
    let region = square(350.0, 200.0);
    let opts = SynthesisOptions {
        seed: 7,
        ..Default::default()
    };
    let edit = worldpaint_core::paste(&world, &color, &region, &opts, &|_| true).unwrap();
    let after = edit.applied_to(&world);
    // the roads were cut at the border: their loose ends there
    let on_border = |p: DVec2| region.distance_to_boundary(p) < 1e-6;
    let cut_ends: Vec<DVec2> = edit
        .added_paths
        .iter()
        .filter(|p| {
            p.points
                .iter()
                .all(|q| !region.contains(*q) || on_border(*q))
        })
        .flat_map(|p| [p.points[0], p.points[p.points.len() - 1]])
        .filter(|q| on_border(*q))
        .collect();
    let new_paths: Vec<&worldpaint_core::Path> = edit
        .added_paths
        .iter()
        .filter(|p| {
            p.points
                .iter()
                .any(|q| region.contains(*q) && !on_border(*q))
        })
        .collect();
    let new_nodes: Vec<DVec2> = new_paths
        .iter()
        .flat_map(|p| p.points.iter().copied())
        .collect();
    let joined = cut_ends
        .iter()
        .filter(|e| new_nodes.iter().any(|n| n.distance(**e) < 1e-6))
        .count();
    let g = graph_of(&after.paths);
    println!(
        "{} roads cut, {} loose ends on the border, {} new roads, {joined} ends joined; {} crossings",
        edit.removed_paths.len(),
        cut_ends.len(),
        new_paths.len(),
        drawn_graph(&after.paths).crossings()
    );
    assert!(
        !edit.removed_paths.is_empty() && !cut_ends.is_empty(),
        "the world's roads cross the region"
    );
    assert!(!new_paths.is_empty());
    assert!(joined >= 1, "new roads end on the roads around");
    assert_eq!(drawn_graph(&after.paths).crossings(), 0);
    // the houses keep clear of every road, old and new
    let house = after
        .categories
        .iter()
        .position(|c| c.name == "house")
        .unwrap();
    let index = worldpaint_core::SegmentIndex::new(g.segments());
    let nearest = edit
        .added
        .iter()
        .filter(|i| i.category == house)
        .map(|i| index.distance(i.position, 1e3))
        .fold(f64::INFINITY, f64::min);
    println!("nearest new house to a road: {nearest:.1} m");
    assert!(nearest >= 6.0, "houses keep off the roads");
}

#[test]
fn clearing_a_region_cuts_the_roads_at_its_border_and_keeps_the_rest() {
    let scene = village_scene(450.0, 2);
    let region = Region::Circle {
        center: DVec2::splat(200.0),
        radius: 80.0,
    };
    let length = |paths: &[worldpaint_core::Path]| -> f64 {
        paths
            .iter()
            .flat_map(|p| p.points.windows(2).map(|w| w[0].distance(w[1])))
            .sum()
    };
    let outside = |paths: &[worldpaint_core::Path]| -> f64 {
        paths
            .iter()
            .flat_map(|p| region.clip_polyline(&p.points).1)
            .map(|piece| piece.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>())
            .sum()
    };
    let after = worldpaint_core::clear_region(&scene, &region, None)
        .unwrap()
        .applied_to(&scene);
    println!(
        "roads: {:.0} m, {:.0} m outside the region; after clearing {:.0} m",
        length(&scene.paths),
        outside(&scene.paths),
        length(&after.paths)
    );
    assert!((length(&after.paths) - outside(&scene.paths)).abs() < 1e-6);
    assert!(
        after.paths.iter().all(|p| p
            .points
            .iter()
            .all(|q| q.distance(DVec2::splat(200.0)) >= 80.0 - 1e-6)),
        "no road vertex inside the cleared circle"
    );
    assert!(after.instances.iter().all(|i| !region.contains(i.position)));
    assert!(after.instances.len() < scene.instances.len());

    // one category only: the roads stay
    let houses_only = worldpaint_core::clear_region(&scene, &region, Some("house"))
        .unwrap()
        .applied_to(&scene);
    assert_eq!(houses_only.paths, scene.paths);
    let house = scene.category_index("house").unwrap();
    assert!(houses_only
        .instances
        .iter()
        .all(|i| i.category != house || !region.contains(i.position)));
    assert!(houses_only
        .instances
        .iter()
        .any(|i| i.category != house && region.contains(i.position)));
    assert!(worldpaint_core::clear_region(&scene, &region, Some("castle")).is_err());
}

#[test]
fn moving_a_region_carries_its_roads_and_the_houses_keep_off_them() {
    let (scene, color) = village_color(450.0);
    let source = square(120.0, 150.0);
    let offset = DVec2::new(400.0, 20.0);
    let inside_length: f64 = scene
        .paths
        .iter()
        .flat_map(|p| source.clip_polyline(&p.points).0)
        .map(|piece| piece.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>())
        .sum();
    let (moved, after) = move_and_apply(&scene, &color, &source, offset);
    let destination = source.translated(offset);
    let length_in = |region: &Region| -> f64 {
        after
            .paths
            .iter()
            .flat_map(|p| region.clip_polyline(&p.points).0)
            .map(|piece| piece.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>())
            .sum()
    };
    let house = after.category_index("house").unwrap();
    let roads = worldpaint_core::SegmentIndex::new(graph_of(&after.paths).segments());
    let closest = after
        .instances
        .iter()
        .filter(|i| i.category == house && destination.contains(i.position))
        .map(|i| roads.distance(i.position, 100.0))
        .fold(f64::INFINITY, f64::min);
    println!(
        "{:.0} m of road in the source; after the move {:.0} m there and {:.0} m in the destination; {} houses \
         moved, the closest {closest:.1} m from a road",
        inside_length,
        length_in(&source).abs(),
        length_in(&destination),
        moved.moved
    );
    assert!(inside_length > 100.0);
    assert!(
        length_in(&source) < 1e-6,
        "the source is left without its roads"
    );
    assert!(
        (length_in(&destination) - inside_length).abs() < 1e-6,
        "the roads arrive whole"
    );
    assert!(closest >= 6.0, "moved houses keep off the roads");
}

#[test]
fn moving_a_region_carries_its_islands() {
    let (scene, color) = with_color(archipelago_scene(300.0, 1), 300.0, "islands");
    // a square that cuts some islands: their parts inside move, the rest stays
    let source = square(0.0, 160.0);
    let offset = DVec2::new(1000.0, 0.0);
    let area = |contours: &[worldpaint_core::Contour]| -> f64 {
        contours
            .iter()
            .map(|c| worldpaint_core::polygon_signed_area(&c.points).abs())
            .sum()
    };
    let (_, after) = move_and_apply(&scene, &color, &source, offset);
    let destination = source.translated(offset);
    let arrived: Vec<_> = after
        .contours
        .iter()
        .filter(|c| c.points.iter().all(|p| destination.contains(*p)))
        .cloned()
        .collect();
    println!(
        "{} contours of {:.0} m², cut and moved: {} arrived ({:.0} m²), {} stayed",
        scene.contours.len(),
        area(&scene.contours),
        arrived.len(),
        area(&arrived),
        after.contours.len() - arrived.len()
    );
    assert!(!arrived.is_empty() && arrived.len() < after.contours.len());
    assert!(
        (area(&after.contours) / area(&scene.contours) - 1.0).abs() < 0.03,
        "cut and moved, the islands keep their area"
    );
}

#[test]
fn a_gradient_paints_one_road_network_across_its_bands() {
    use worldpaint_core::{gradient, GradientOptions, GradientShape};
    let (_, sparse) = village_color(450.0);
    // the same village with three times the houses along its roads
    let mut dense = sparse.clone();
    for c in dense
        .categories
        .iter_mut()
        .filter(|c| c.category.name == "house")
    {
        c.density *= 3.0;
    }
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::new(1200.0, 400.0),
    };
    let canvas = sparse.blank_scene();
    let opts = GradientOptions {
        bands: Some(4),
        synthesis: SynthesisOptions {
            seed: 2,
            categories: Some(vec!["road".into(), "house".into()]),
            ..Default::default()
        },
    };
    let shape = GradientShape::Linear {
        from: DVec2::new(0.0, 200.0),
        to: DVec2::new(1200.0, 200.0),
    };
    let edit = gradient(&canvas, &sparse, &dense, &region, shape, &opts, &|_| true).unwrap();
    let after = edit.applied_to(&canvas);
    let roads = sparse.graph("road").unwrap();
    let g = graph_of(&after.paths);
    let components = g.components() as f64 / region.area() / roads.components_per_area;
    let house = after.category_index("house").unwrap();
    let per_band: Vec<usize> = (0..4)
        .map(|k| {
            let (x0, x1) = (300.0 * k as f64, 300.0 * (k + 1) as f64);
            after
                .instances
                .iter()
                .filter(|i| i.category == house && i.position.x >= x0 && i.position.x < x1)
                .count()
        })
        .collect();
    println!(
        "gradient over 4 bands: {} road nodes, components {components:.2} × the learned, {} crossings; houses per \
         band {per_band:?}",
        g.nodes.len(),
        drawn_graph(&after.paths).crossings()
    );
    assert_eq!(drawn_graph(&after.paths).crossings(), 0);
    assert!(
        (1.0 / 1.5..=1.5).contains(&components),
        "the bands' roads join into the learned number of networks"
    );
    assert!(
        per_band.windows(2).all(|w| w[1] > w[0]),
        "more houses toward the dense end"
    );
}

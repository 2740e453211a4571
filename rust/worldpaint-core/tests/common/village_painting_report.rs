//! The real-village report, for `tests/real_village_painting.rs`.
//!
//! Real data (OpenStreetMap, the countryside north of Bayreuth), read from `shared/data/real/villages` beside the
//! project — never copied into the repository. Roads (`highway` LineStrings; footways, paths, cycleways, steps
//! and bridleways left out) and buildings (Polygons, each one house at its area centroid) are projected from
//! lon/lat to metres, equirectangular around the centre of the two layers.
//!
//! * **Exemplar.** Squares of `SIDE` on a `SEARCH_STEP` grid, kept `MARGIN` inside the buildings' extent, are
//!   ranked by their building count; the densest one is re-centred on the mean of its buildings (the village
//!   rather than a window of the grid). The scene around it holds the road segments and houses within `PAD`:
//!   a graph category "road" (priority 0) and a distribution category "house" (priority 1), no terrain.
//! * **Color and painting.** The color is learned with the default `AnalysisOptions`, as `tests/structures.rs`
//!   does for its generated village, and painted with one seed into an empty square three times the side.
//! * **Measures.** The painted network is measured on the learned bins as the analysis reads a graph (nodes
//!   with an edge in the square, edges with an end in it, angles at those nodes, components of the edges held
//!   inside), both on the planar graph (`Graph::from_paths`: a node at every crossing, what a viewer sees) and
//!   on the paths as drawn (a node at every vertex only), where crossings away from nodes can be counted. The
//!   painted houses are relearned on the color's radius and bins for their distance-to-road histogram.
//! * **Reference.** The next densest square clear of the exemplar (another village) is measured on the same
//!   bins: the natural variation between two real villages.

use super::geojson::{geometry, read_features, tag, FOOT_AND_BRIDLE_WAYS};
use super::real_data::{real_data_dir, require, Projection};
use super::rings::area_centroid;
use super::squares::{centre_of_points_in, points_in, square, squares_by_count};
use std::path::{Path, PathBuf};
use std::time::Instant;
use worldpaint_core::{
    learn_color, synthesize, AnalysisOptions, Category, CategoryKind, Color, DVec2, Graph,
    GraphColor, HeldGraph, Histogram, Instance, MapSource, Path as ScenePath, Region, Scene,
    SegmentIndex, SynthesisOptions,
};

/// Where the village data lives.
pub fn data_dir() -> PathBuf {
    real_data_dir().join("villages")
}

const ROADS_FILE: &str = "north_bayreuth_roads.geojson";
const BUILDINGS_FILE: &str = "north_bayreuth_buildings.geojson";

/// Twice the area (m²) within which a building's rings count as enclosing none.
const FLAT_RINGS: f64 = 1e-6;
/// Side of the exemplar square (m).
pub const SIDE: f64 = 1000.0;
/// Step of the grid of candidate squares (m).
const SEARCH_STEP: f64 = 50.0;
/// The candidate squares stay this far inside the data's bounding box, so roads and houses surround them.
const MARGIN: f64 = 250.0;
/// The exemplar scene holds the road segments and houses this far around its square.
const PAD: f64 = 200.0;

/// The two layers, in metres.
pub struct Layers {
    /// Road polylines.
    pub roads: Vec<Vec<DVec2>>,
    /// Building centroids.
    pub houses: Vec<DVec2>,
    /// Ways left out as not roads (footways, paths, cycleways, steps, ...).
    pub not_roads: usize,
    /// Features whose geometry could not be read, and roads without a `highway` tag.
    pub unreadable: usize,
    /// Bounding box of the buildings (the extract's area: roads run on beyond it, buildings do not).
    pub bbox: (DVec2, DVec2),
    /// The projection's centre (lon, lat in degrees).
    pub centre: [f64; 2],
}

/// Loads the two layers; `Ok(None)` when a file is absent, `Err` when one cannot be read.
fn load(dir: &Path) -> Result<Layers, String> {
    let (roads_path, buildings_path) = (dir.join(ROADS_FILE), dir.join(BUILDINGS_FILE));
    require(&[roads_path.clone(), buildings_path.clone()]);
    let mut unreadable = 0usize;
    let mut not_roads = 0usize;
    let mut roads_ll: Vec<Vec<[f64; 2]>> = Vec::new();
    for f in read_features(&roads_path)? {
        match (tag(&f, "highway"), geometry(&f)) {
            (Some(h), Some(_)) if FOOT_AND_BRIDLE_WAYS.contains(&h) => not_roads += 1,
            (Some(_), Some(lines)) => roads_ll.extend(lines),
            _ => unreadable += 1,
        }
    }
    let mut buildings_ll: Vec<Vec<Vec<[f64; 2]>>> = Vec::new();
    for f in read_features(&buildings_path)? {
        match geometry(&f) {
            Some(rings) => buildings_ll.push(rings),
            None => unreadable += 1,
        }
    }
    if roads_ll.is_empty() || buildings_ll.is_empty() {
        return Err("no readable roads or no readable buildings".into());
    }
    let all = roads_ll
        .iter()
        .flatten()
        .chain(buildings_ll.iter().flatten().flatten());
    let (lo, hi) = all.fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    );
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let projection = Projection::new(centre);
    let project = |p: &[f64; 2]| projection.project(*p);
    let roads: Vec<Vec<DVec2>> = roads_ll
        .iter()
        .map(|l| l.iter().map(project).collect())
        .collect();
    let houses: Vec<DVec2> = buildings_ll
        .iter()
        .map(|rings| {
            let rings: Vec<Vec<DVec2>> = rings
                .iter()
                .map(|r| r.iter().map(project).collect())
                .collect();
            area_centroid(&rings, FLAT_RINGS)
        })
        .collect();
    let bbox = houses.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    Ok(Layers {
        roads,
        houses,
        not_roads,
        unreadable,
        bbox,
        centre,
    })
}

fn rect_min(r: &Region) -> DVec2 {
    r.bbox().0
}

/// The squares of `SIDE` on a `SEARCH_STEP` grid inside the buildings' box less `MARGIN`, by building count (most
/// first; ties in grid order), each with its count.
fn squares_by_density(layers: &Layers) -> Vec<(DVec2, usize)> {
    let (lo, hi) = (
        layers.bbox.0 + DVec2::splat(MARGIN),
        layers.bbox.1 - DVec2::splat(MARGIN),
    );
    squares_by_count(&layers.houses, lo, hi, SIDE, SEARCH_STEP)
}

/// The square of `SIDE` centred on the mean of the buildings in the square of `SIDE` at `min`: the village
/// itself rather than a window of the search grid.
fn centred(layers: &Layers, min: DVec2) -> Region {
    let centre = centre_of_points_in(&layers.houses, min, SIDE);
    square(centre - DVec2::splat(0.5 * SIDE), SIDE)
}

/// A scene of the roads and houses around `region` (road segments whose box meets the region padded by `PAD`,
/// in runs along their polylines, never cut: every edge near the region keeps its full length).
fn village_scene(layers: &Layers, region: &Region) -> Scene {
    let (lo, hi) = region.bbox();
    let (lo, hi) = (lo - DVec2::splat(PAD), hi + DVec2::splat(PAD));
    let near = |a: DVec2, b: DVec2| {
        let (l, h) = (a.min(b), a.max(b));
        l.x <= hi.x && l.y <= hi.y && h.x >= lo.x && h.y >= lo.y
    };
    let mut paths = Vec::new();
    for road in &layers.roads {
        let mut run: Vec<DVec2> = Vec::new();
        for w in road.windows(2) {
            if near(w[0], w[1]) {
                if run.is_empty() {
                    run.push(w[0]);
                }
                run.push(w[1]);
            } else if run.len() >= 2 {
                paths.push(std::mem::take(&mut run));
            }
        }
        if run.len() >= 2 {
            paths.push(run);
        }
    }
    let inside = |p: DVec2| p.x >= lo.x && p.y >= lo.y && p.x <= hi.x && p.y <= hi.y;
    Scene {
        categories: categories(),
        instances: layers
            .houses
            .iter()
            .filter(|p| inside(**p))
            .map(|p| Instance::at(*p, 1))
            .collect(),
        paths: paths
            .into_iter()
            .map(|points| ScenePath {
                category: 0,
                points,
                locked: false,
            })
            .collect(),
        ..Default::default()
    }
}

/// Roads first (a graph), then houses (a distribution), as in `exemplar::village`.
fn categories() -> Vec<Category> {
    vec![
        Category::new("road", "settlement", CategoryKind::Graph, 0),
        Category::distribution("house", "settlement", 1),
    ]
}

/// The planar graph of paths, as the engine's analysis reads them: a node at every vertex and at every crossing.
fn planar_graph(paths: &[ScenePath]) -> Graph {
    let paths: Vec<&[DVec2]> = paths.iter().map(|p| p.points.as_slice()).collect();
    Graph::from_paths(&paths, 1e-3)
}

/// The graph of paths as drawn: a node at every vertex (paths meet at identical vertices), no node where two
/// segments cross. Crossings away from nodes are only visible here: [`planar_graph`] turns each into a node.
fn drawn_graph(paths: &[ScenePath]) -> Graph {
    let mut ids = std::collections::HashMap::new();
    let mut g = Graph::default();
    for p in paths {
        let mut prev: Option<u32> = None;
        for q in &p.points {
            let id = *ids
                .entry((q.x.to_bits(), q.y.to_bits()))
                .or_insert_with(|| {
                    g.nodes.push(*q);
                    g.nodes.len() as u32 - 1
                });
            if let Some(a) = prev.filter(|a| *a != id) {
                g.edges.push([a.min(id), a.max(id)]);
            }
            prev = Some(id);
        }
    }
    g.edges.sort_unstable();
    g.edges.dedup();
    g
}

/// A graph measured in a region as the analysis reads one: the nodes with an edge inside the region, every edge
/// with an end inside (at its full length), the angles at those nodes; components of the edges with both ends
/// inside (inside nodes with no such edge count one each). Histograms on the bins of a learned graph.
pub struct GraphStats {
    pub nodes: usize,
    pub edges: usize,
    pub km: f64,
    pub length_tv: f64,
    pub angle_tv: f64,
    /// Turning angles at the inside nodes of two edges, against the learned histogram (0 when none was learned).
    pub turn_tv: f64,
    pub min_angle: f64,
    pub components_per_km2: f64,
}

/// The total variation of the turning angles at the `inside` nodes of two edges from `learned`.
fn turn_tv(g: &Graph, inside: &[bool], learned: &Histogram) -> f64 {
    if learned.values.is_empty() {
        return 0.0;
    }
    let mut turns = Histogram::zeros(learned.start, learned.bin_width, learned.values.len());
    for (n, nb) in g.adjacency().iter().enumerate() {
        if let (true, [a, b]) = (inside[n], nb.as_slice()) {
            let t = std::f64::consts::PI - g.angle_at(n as u32, *a, *b);
            turns.add(t.min(std::f64::consts::PI - 1e-12), 1.0);
        }
    }
    learned.total_variation(&turns)
}

fn graph_stats(g: &Graph, region: &Region, learned: &GraphColor) -> GraphStats {
    let held = HeldGraph::new(g, region);
    let (adj, inside, edges) = (held.adjacency(), held.inside(), held.edges());
    let (le, an) = (&learned.edge_length, &learned.angle);
    let mut lengths = Histogram::zeros(le.start, le.bin_width, le.values.len());
    for e in edges {
        lengths.add(g.edge_length(*e), 1.0);
    }
    let mut angles = Histogram::zeros(an.start, an.bin_width, an.values.len());
    let mut min_angle = std::f64::consts::PI;
    for (n, nb) in adj.iter().enumerate().filter(|(n, _)| inside[*n]) {
        for (i, &x) in nb.iter().enumerate() {
            for &y in &nb[i + 1..] {
                let t = g.angle_at(n as u32, x, y);
                angles.add(t.min(std::f64::consts::PI - 1e-12), 1.0);
                min_angle = min_angle.min(t);
            }
        }
    }
    GraphStats {
        nodes: inside.iter().filter(|i| **i).count(),
        edges: edges.len(),
        km: edges.iter().map(|e| g.edge_length(*e)).sum::<f64>() / 1e3,
        length_tv: le.total_variation(&lengths),
        angle_tv: an.total_variation(&angles),
        turn_tv: turn_tv(g, inside, &learned.turn),
        min_angle,
        components_per_km2: held.components() as f64 / region.area() * 1e6,
    }
}

/// A road network in a region: as the analysis reads it (the planar graph, a node at every crossing) and as its
/// paths were drawn, with the pairs of drawn segments (with an end in the region) that cross away from a node.
pub struct Network {
    pub planar: GraphStats,
    pub drawn: GraphStats,
    pub crossings: usize,
}

fn measure(paths: &[ScenePath], region: &Region, learned: &GraphColor) -> Network {
    let drawn = drawn_graph(paths);
    let near = Graph {
        nodes: drawn.nodes.clone(),
        edges: drawn
            .edges
            .iter()
            .copied()
            .filter(|e| e.iter().any(|n| region.contains(drawn.nodes[*n as usize])))
            .collect(),
    };
    Network {
        planar: graph_stats(&planar_graph(paths), region, learned),
        drawn: graph_stats(&drawn, region, learned),
        crossings: near.crossings(),
    }
}

/// Houses measured in a region against the learned ones.
pub struct Houses {
    pub count: usize,
    pub per_km2: f64,
    /// Their density over the exemplar's.
    pub density_ratio: f64,
    /// Total variation between their distance-to-road histogram and the learned one.
    pub distance_tv: f64,
    /// Median distance to the nearest road (m).
    pub median_distance: f64,
}

/// The houses' distance-to-road histogram of a color (the map `house` ← `road`, a graph distance).
fn road_distance_hist(c: &Color) -> Option<&Histogram> {
    c.maps
        .iter()
        .find(|m| m.category == "house" && m.map == "road" && m.source == MapSource::GraphDistance)
        .map(|m| &m.hist)
}

fn measure_houses(
    houses: &[DVec2],
    paths: &[ScenePath],
    region: &Region,
    relearned: &Color,
    exemplar: &Color,
) -> Houses {
    let inside = points_in(houses, region);
    let per_m2 = inside.len() as f64 / region.area();
    let index = SegmentIndex::new(planar_graph(paths).segments());
    let mut d: Vec<f64> = inside.iter().map(|p| index.distance(*p, 1e4)).collect();
    d.sort_by(f64::total_cmp);
    let learned_density = exemplar.category("house").map_or(f64::NAN, |c| c.density);
    Houses {
        count: inside.len(),
        per_km2: per_m2 * 1e6,
        density_ratio: per_m2 / learned_density,
        distance_tv: match (road_distance_hist(exemplar), road_distance_hist(relearned)) {
            (Some(a), Some(b)) => a.total_variation(b),
            _ => f64::NAN,
        },
        median_distance: d.get(d.len() / 2).copied().unwrap_or(f64::NAN),
    }
}

/// One measured column of the report.
pub struct Column {
    pub label: String,
    pub area_km2: f64,
    pub network: Network,
    pub houses: Houses,
}

pub struct VillageReport {
    pub centre: [f64; 2],
    pub roads: usize,
    pub not_roads: usize,
    pub houses: usize,
    pub unreadable: usize,
    /// The exemplar square (metres from the projection centre) and its centre in lon/lat.
    pub exemplar: Region,
    pub exemplar_lon_lat: [f64; 2],
    pub second: Region,
    pub max_radius: f64,
    pub bin_width: f64,
    pub seed: u64,
    pub learn_seconds: f64,
    pub synthesis_seconds: f64,
    /// The learned road statistics.
    pub learned: GraphColor,
    /// The exemplar measured against itself (TVs 0 up to binning).
    pub real: Column,
    /// The painted square, nine times the exemplar's area.
    pub synthesized: Column,
    /// The second-densest real village on the exemplar's bins.
    pub second_village: Column,
}

/// Learns a color of `scene` in `region` on the given radius and bins.
fn relearn(scene: &Scene, region: &Region, color: &Color, name: &str) -> Result<Color, String> {
    let opts = AnalysisOptions {
        max_radius: Some(color.max_radius),
        bin_width: Some(color.bin_width),
        ..Default::default()
    };
    learn_color(scene, region, name, &opts).map_err(|e| format!("learn {name}: {e}"))
}

fn column(
    label: String,
    scene: &Scene,
    region: &Region,
    exemplar: &Color,
    learned: &GraphColor,
) -> Result<Column, String> {
    let houses: Vec<DVec2> = scene
        .instances
        .iter()
        .filter(|i| scene.categories[i.category].name == "house")
        .map(|i| i.position)
        .collect();
    let relearned = relearn(scene, region, exemplar, &label)?;
    Ok(Column {
        area_km2: region.area() / 1e6,
        network: measure(&scene.paths, region, learned),
        houses: measure_houses(&houses, &scene.paths, region, &relearned, exemplar),
        label,
    })
}

/// The exemplar square (the densest village) and the second village (the densest square clear of the first and
/// its padding), each centred on its buildings.
fn villages(layers: &Layers) -> Result<(Region, Region), String> {
    let squares = squares_by_density(layers);
    let Some(&(first, _)) = squares.first() else {
        return Err("the buildings cover less than an exemplar square".into());
    };
    let clear = SIDE + PAD;
    let &(second, _) = squares
        .iter()
        .find(|(p, _)| (p.x - first.x).abs() >= clear || (p.y - first.y).abs() >= clear)
        .ok_or("the buildings cover no second village")?;
    Ok((centred(layers, first), centred(layers, second)))
}

/// Runs the report on the given exemplar square and second village, painting with `seed`.
fn report(
    layers: &Layers,
    exemplar: Region,
    second: Region,
    seed: u64,
) -> Result<VillageReport, String> {
    let t0 = Instant::now();
    let scene = village_scene(layers, &exemplar);
    let color = learn_color(
        &scene,
        &exemplar,
        "north of Bayreuth",
        &AnalysisOptions::default(),
    )
    .map_err(|e| format!("learn the exemplar: {e}"))?;
    let learn_seconds = t0.elapsed().as_secs_f64();
    let learned = color
        .graph("road")
        .cloned()
        .ok_or("the exemplar color has no road statistics")?;

    let dest = square(DVec2::splat(1e5), 3.0 * SIDE);
    let canvas = Scene {
        categories: categories(),
        ..Default::default()
    };
    let opts = SynthesisOptions {
        seed,
        categories: Some(vec!["road".into(), "house".into()]),
        ..Default::default()
    };
    let t0 = Instant::now();
    let out = synthesize(&canvas, &color, &dest, &opts).map_err(|e| format!("synthesize: {e}"))?;
    let synthesis_seconds = t0.elapsed().as_secs_f64();
    let painted = Scene {
        categories: out.categories.clone(),
        instances: out.instances.clone(),
        paths: out.paths.clone(),
        ..Default::default()
    };

    let centre = rect_min(&exemplar) + DVec2::splat(0.5 * SIDE);
    let exemplar_lon_lat = Projection::new(layers.centre).unproject(centre);
    Ok(VillageReport {
        centre: layers.centre,
        roads: layers.roads.len(),
        not_roads: layers.not_roads,
        houses: layers.houses.len(),
        unreadable: layers.unreadable,
        max_radius: color.max_radius,
        bin_width: color.bin_width,
        seed,
        learn_seconds,
        synthesis_seconds,
        real: column("real exemplar".into(), &scene, &exemplar, &color, &learned)?,
        synthesized: column(
            format!("synthesized (seed {seed})"),
            &painted,
            &dest,
            &color,
            &learned,
        )?,
        second_village: column(
            "real village 2".into(),
            &village_scene(layers, &second),
            &second,
            &color,
            &learned,
        )?,
        exemplar,
        exemplar_lon_lat,
        second,
        learned,
    })
}

impl VillageReport {
    /// The synthesized components per km² over the exemplar's learned ones.
    pub fn components_ratio(&self) -> f64 {
        self.synthesized.network.planar.components_per_km2
            / (self.learned.components_per_area * 1e6)
    }

    /// The report as a plain-text table.
    pub fn table(&self) -> String {
        let (e, s) = (rect_min(&self.exemplar), rect_min(&self.second));
        let mut out = format!(
            "OpenStreetMap north of Bayreuth (projection centre {:.4}° E {:.4}° N): {} road polylines ({} \
             footways, paths, cycleways and steps left out), {} buildings, {} unreadable features\n\
             exemplar: {SIDE:.0} m square centred on the densest village, x {:.0}..{:.0} m, y {:.0}..{:.0} m \
             (centre {:.4}° E {:.4}° N); real village 2: x {:.0}..{:.0} m, y {:.0}..{:.0} m\n\
             learned in {:.2} s (rdf to {:.1} m in {:.2} m bins); painted into a {:.0} m square (seed {}) in {:.2} s\n",
            self.centre[0],
            self.centre[1],
            self.roads,
            self.not_roads,
            self.houses,
            self.unreadable,
            e.x,
            e.x + SIDE,
            e.y,
            e.y + SIDE,
            self.exemplar_lon_lat[0],
            self.exemplar_lon_lat[1],
            s.x,
            s.x + SIDE,
            s.y,
            s.y + SIDE,
            self.learn_seconds,
            self.max_radius,
            self.bin_width,
            3.0 * SIDE,
            self.seed,
            self.synthesis_seconds,
        );
        let cols = [&self.real, &self.synthesized, &self.second_village];
        out.push_str(&format!("{:<34}", "measure"));
        for c in cols {
            out.push_str(&format!(" {:>24}", c.label));
        }
        out.push('\n');
        let mut row = |name: &str, f: &dyn Fn(&Column) -> String| {
            out.push_str(&format!("{name:<34}"));
            for c in cols {
                out.push_str(&format!(" {:>24}", f(c)));
            }
            out.push('\n');
        };
        row("area (km²)", &|c| format!("{:.2}", c.area_km2));
        row("road nodes", &|c| format!("{}", c.network.planar.nodes));
        row("road edges", &|c| format!("{}", c.network.planar.edges));
        row("road km (per km²)", &|c| {
            let n = &c.network.planar;
            format!("{:.1} ({:.1})", n.km, n.km / c.area_km2)
        });
        row("edge length TV vs learned", &|c| {
            format!("{:.3}", c.network.planar.length_tv)
        });
        row("angle TV vs learned", &|c| {
            format!("{:.3}", c.network.planar.angle_tv)
        });
        row("turning angle TV vs learned", &|c| {
            format!("{:.3}", c.network.planar.turn_tv)
        });
        row("smallest angle at nodes (learned)", &|c| {
            format!(
                "{:.2}° ({:.2}°)",
                c.network.drawn.min_angle.to_degrees(),
                self.learned.min_angle.to_degrees()
            )
        });
        row("crossings away from nodes", &|c| {
            format!("{}", c.network.crossings)
        });
        row("smallest angle, crossings as nodes", &|c| {
            format!("{:.2}°", c.network.planar.min_angle.to_degrees())
        });
        row("components per km² (learned)", &|c| {
            format!(
                "{:.2} ({:.2})",
                c.network.planar.components_per_km2,
                self.learned.components_per_area * 1e6
            )
        });
        row("as drawn: edges", &|c| format!("{}", c.network.drawn.edges));
        row("as drawn: edge length / angle TV", &|c| {
            let n = &c.network.drawn;
            format!("{:.3} / {:.3}", n.length_tv, n.angle_tv)
        });
        row("as drawn: components per km²", &|c| {
            format!("{:.2}", c.network.drawn.components_per_km2)
        });
        row("houses", &|c| format!("{}", c.houses.count));
        row("houses per km² (ratio)", &|c| {
            format!("{:.0} ({:.3})", c.houses.per_km2, c.houses.density_ratio)
        });
        row("house distance-to-road TV", &|c| {
            format!("{:.3}", c.houses.distance_tv)
        });
        row("median house-road distance (m)", &|c| {
            format!("{:.1}", c.houses.median_distance)
        });
        out
    }
}

/// Loads the data and runs the report.
pub fn run(seed: u64) -> Result<VillageReport, String> {
    let dir = data_dir();
    let layers =
        load(&dir).map_err(|e| format!("the data at {} is unusable: {e}", dir.display()))?;
    let (exemplar, second) =
        villages(&layers).map_err(|e| format!("the data at {} is unusable: {e}", dir.display()))?;
    report(&layers, exemplar, second, seed)
}

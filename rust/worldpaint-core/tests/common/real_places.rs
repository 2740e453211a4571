//! Real villages and real land, for `tests/real_village_generation.rs`.
//!
//! Everything here is read from `shared/data/real` beside the project (see its README) and never copied into the
//! repository; a loader panics with the reason when a file is absent (the tests that use it are `#[ignore]`d).
//!
//! * **Terrain.** `terrain/<place>_srtm3.asc`: SRTM 3″ elevations as an ESRI ASCII grid (lon/lat of the lower-left
//!   corner and the cell size in degrees, first data row at the northern edge, -32768 = no data), read by the
//!   engine's reader (`read_elevation_model`); no-data cells take the value of the nearest valid cell (breadth-first
//!   over the grid, `ElevationModel::fill_holes`). The grid is projected equirectangularly about its own centre,
//!   which maps it onto an axis-aligned grid of anisotropic cells (north of Bayreuth, 50° N: 59.6 m east–west by 92.7 m north–south; Andorra, 42.5° N: 68.3 m by 92.7 m). A
//!   [`Heightfield`] needs square cells, so the grid is resampled by bilinear interpolation onto [`TERRAIN_CELL`]
//!   metre cells, a quarter of the finer source spacing: the resampled surface departs from the source's
//!   bilinear surface by 0.02 m on average north of Bayreuth and 0.06 m in Andorra (at most 1.4 m and 7.4 m, on
//!   the sharpest ridges; 30 m cells gave 0.08 m and 0.29 m, at most 2.6 m and 19.7 m). Building the heightfield
//!   directly with the mean source spacing as its cell would stretch the terrain east–west by 18–28 % and shrink
//!   it north–south by 13–18 %, moving the valleys away from the villages.
//! * **Villages.** `villages/<place>_{buildings,roads,areas,places}.geojson` (OpenStreetMap, WGS84, read by the
//!   engine's `read_map_layer`), projected with the terrain's projection so both line up. Each building is one house at its area centroid. Roads are
//!   the `highway` ways people drive on: footways, paths, cycleways, steps, pedestrian ways and bridleways are
//!   left out, and so are motorways and trunk roads (no house is served by them) and ways under construction.
//!   Tracks and service ways stay: they are how farms are reached, and their share of the length is reported.
//!   Water areas (`natural=water`, `waterway=riverbank`, `landuse=reservoir` or `basin`) are kept for the
//!   environment of the generated villages.
//! * **Windows.** Squares of a given side on a 50 m grid, inside both the terrain (less one source cell) and the
//!   buildings' extent, ranked by building count; taken greedily, each clear of those before it by the side plus
//!   200 m, then re-centred on the mean of its buildings (the village rather than a window of the grid; a
//!   window that lands on one already taken is dropped) and named after the nearest `place` point inside it,
//!   else "near" the nearest one. Connection points are where through roads (primary to unclassified) cross the
//!   window's border, merged within 60 m.
//! * **Measured** on a window (houses and roads clipped to it) by the engine's own metrics: layout statistics
//!   (nearest neighbour, shares within 20 m and 50 m, road length per house, house-to-road distance histogram),
//!   road grades in pieces of [`GRADE_STEP`] metres on the heightfield, summarised in grade bins, and the houses'
//!   mean elevation percentile among the nodes of the window on a [`PERCENTILE_CELL`] metre grid.
//! * **Real parcels.** The cadastre of Épinay-sur-Orge (`parcels/cadastre-91216-parcelles.json`, outer rings in
//!   metres about their centre), and the OpenStreetMap land-use polygons of a place that tile the land: the
//!   `landuse` polygons whose centroid lies in no other land-use polygon and that hold no other one's centroid.
//!   Mapped fields, meadows, forests, farmyards and residential areas share their boundary nodes where they
//!   meet, as cadastral parcels share boundaries; a polygon drawn over others (a meadow on a forest, a cemetery
//!   in a residential area) is a second layer, not a neighbour, so both sides of such a nesting are left out.
//!   The share of polygons that share a boundary edge (two consecutive vertices) with another is reported: how
//!   far a set really tiles.
//!
//! What the real figures are, read with care:
//! * OpenStreetMap buildings include outbuildings (4,229 of the 4,267 north of Bayreuth are `building=yes`:
//!   barns, garages and sheds beside the houses), so real nearest-neighbour distances and road length per
//!   building are those of all buildings, shorter than between dwellings.
//! * The Andorra building layer is sparse (292 buildings in the whole extract), so its road length per building
//!   overstates a village's and its nearest-neighbour distances are those of the mapped buildings only.
//! * SRTM at 3″ cannot resolve the benches and hairpins a mountain road is built on: a road along a steep slope
//!   reads the slope's grade, so real road grades in Andorra read far steeper than the roads are.

use super::geojson::FOOT_AND_BRIDLE_WAYS;
use super::real_data::{real_data_dir, require, Projection};
use super::rings::area_centroid;
use super::squares::{centre_of_points_in, points_in, square, squares_by_count};
use std::collections::HashMap;
use std::path::Path;
use worldpaint_core::{
    layout_statistics, mean_elevation_percentile, min_area_rectangle, network_shape,
    polygon_contains, polygon_signed_area, read_elevation_model, read_map_layer, road_grades,
    road_length, DVec2, ElevationModel, Environment, Heightfield, Land, LayoutStatistics,
    LonLatShape, MapLayer, NetworkShape, Region, Road,
};

/// Cell (m) of the metre heightfield resampled from the SRTM grid.
pub const TERRAIN_CELL: f64 = 15.0;
/// Length (m) of the road pieces whose grade is measured.
pub const GRADE_STEP: f64 = 10.0;
/// Cell (m) of the grid over a window on which elevation percentiles are taken.
pub const PERCENTILE_CELL: f64 = 10.0;
/// Step (m) of the grid of candidate windows.
const SEARCH_STEP: f64 = 50.0;
/// Windows are kept this far (m) apart, beyond their side.
const WINDOW_GAP: f64 = 200.0;
/// Crossings of the window border by through roads closer than this (m) make one connection point.
const CONNECTION_MERGE: f64 = 60.0;
/// Twice the area (m²) within which a ring counts as enclosing none.
const FLAT_RING: f64 = 1e-9;
/// Upper bounds of the reported grade bins (rise over run); the last bin holds everything steeper.
pub const GRADE_BINS: [f64; 5] = [0.02, 0.05, 0.08, 0.12, 0.15];

/// `highway` values besides the foot and bridle ways that are not roads a house is served by.
const NOT_SERVING: [&str; 7] = [
    "motorway",
    "motorway_link",
    "trunk",
    "trunk_link",
    "construction",
    "proposed",
    "platform",
];
/// `highway` values of minor ways: farm tracks and service ways.
const MINOR_ROADS: [&str; 2] = ["track", "service"];
/// `highway` values of the roads by which a village is reached from outside (the classes of the roads between
/// villages): where they cross a window's border are its connection points. Residential streets and tracks
/// crossing the border are the village's own streets or field ways running on, not ways in.
const THROUGH_ROADS: [&str; 8] = [
    "primary",
    "primary_link",
    "secondary",
    "secondary_link",
    "tertiary",
    "tertiary_link",
    "unclassified",
    "road",
];

/// One place of the data: file stem and how the report calls it.
#[derive(Clone, Copy, Debug)]
pub struct PlaceSpec {
    pub stem: &'static str,
    pub label: &'static str,
}

pub const NORTH_BAYREUTH: PlaceSpec = PlaceSpec {
    stem: "north_bayreuth",
    label: "north of Bayreuth (Upper Franconia, Germany)",
};
pub const ANDORRA: PlaceSpec = PlaceSpec {
    stem: "andorra",
    label: "Andorra (Pyrenees)",
};

// ---------------------------------------------------------------------------------------------------------------
// Terrain

/// The engine's reading of an SRTM grid with its holes filled: `heights[r * ncols + c]`, row 0 the northern edge.
pub struct AsciiGrid {
    pub model: ElevationModel,
    /// Cells that had no data and took the nearest valid value.
    pub filled: usize,
}

/// Reads an ESRI ASCII grid with the engine's reader and fills its no-data cells with the nearest valid value.
pub fn read_ascii_grid(path: &Path) -> Result<AsciiGrid, String> {
    let mut model = read_elevation_model(path).map_err(|e| e.to_string())?;
    if model.cell[0] != model.cell[1] {
        return Err(format!(
            "{}: cells of {:?} degrees are not square",
            path.display(),
            model.cell
        ));
    }
    let filled = model.fill_holes().map_err(|e| e.to_string())?;
    Ok(AsciiGrid { model, filled })
}

/// A terrain in metres with the projection of its grid.
pub struct Terrain {
    pub heightfield: Heightfield,
    pub projection: Projection,
    /// Spacing (m) of the source samples east–west and north–south.
    pub source_spacing: DVec2,
    pub source_size: [usize; 2],
    pub filled: usize,
}

/// The grid projected about its centre and resampled by bilinear interpolation onto square cells of `cell` m.
pub fn terrain_from_grid(ascii: &AsciiGrid, cell: f64) -> Result<Terrain, String> {
    let grid = &ascii.model;
    let cs = grid.cell[0];
    let [xll, yll] = grid.lower_left;
    let projection = Projection::new([
        xll + 0.5 * grid.ncols as f64 * cs,
        yll + 0.5 * grid.nrows as f64 * cs,
    ]);
    // sample (i, j), j counted from the south, is the centre of its cell
    let origin = projection.project([xll + 0.5 * cs, yll + 0.5 * cs]);
    let spacing = projection.scale() * cs;
    let extent = DVec2::new(
        (grid.ncols - 1) as f64 * spacing.x,
        (grid.nrows - 1) as f64 * spacing.y,
    );
    let nx = (extent.x / cell).floor() as usize + 1;
    let ny = (extent.y / cell).floor() as usize + 1;
    let source = |i: usize, j: usize| grid.heights[(grid.nrows - 1 - j) * grid.ncols + i];
    let mut heights = Vec::with_capacity(nx * ny);
    for b in 0..ny {
        let fy = (b as f64 * cell / spacing.y).min((grid.nrows - 1) as f64);
        let j = (fy.floor() as usize).min(grid.nrows - 2);
        let ty = fy - j as f64;
        for a in 0..nx {
            let fx = (a as f64 * cell / spacing.x).min((grid.ncols - 1) as f64);
            let i = (fx.floor() as usize).min(grid.ncols - 2);
            let tx = fx - i as f64;
            let south = source(i, j) * (1.0 - tx) + source(i + 1, j) * tx;
            let north = source(i, j + 1) * (1.0 - tx) + source(i + 1, j + 1) * tx;
            heights.push((south * (1.0 - ty) + north * ty) as f32);
        }
    }
    let heightfield =
        Heightfield::new(origin, cell, nx, ny, heights).map_err(|e| format!("heightfield: {e}"))?;
    Ok(Terrain {
        heightfield,
        projection,
        source_spacing: spacing,
        source_size: [grid.ncols, grid.nrows],
        filled: ascii.filled,
    })
}

// ---------------------------------------------------------------------------------------------------------------
// GeoJSON

/// A map layer read by the engine's reader, refused with its message.
fn read_features(path: &Path) -> Result<MapLayer, String> {
    read_map_layer(path).map_err(|e| e.to_string())
}

/// The lines of a (Multi)LineString, the outer rings of a (Multi)Polygon, or a Point as a one-point line.
fn outer_lines(shape: &LonLatShape) -> Vec<Vec<[f64; 2]>> {
    match shape {
        LonLatShape::Point(p) => vec![vec![*p]],
        LonLatShape::Lines(lines) => lines.clone(),
        LonLatShape::Polygons(polygons) => polygons.iter().map(|rings| rings[0].clone()).collect(),
    }
}

/// A ring without its closing repetition, if at least a triangle is left.
fn open_ring(mut ring: Vec<DVec2>) -> Option<Vec<DVec2>> {
    if ring.len() >= 2 && ring.first() == ring.last() {
        ring.pop();
    }
    (ring.len() >= 3).then_some(ring)
}

fn ring_bbox(ring: &[DVec2]) -> (DVec2, DVec2) {
    ring.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

// ---------------------------------------------------------------------------------------------------------------
// A place

/// An OpenStreetMap road in metres.
pub struct RealRoad {
    pub highway: String,
    pub points: Vec<DVec2>,
}

/// A `place` point (village, hamlet, town...).
pub struct NamedPlace {
    pub kind: String,
    pub name: String,
    pub position: DVec2,
}

/// A vertex as read: the bit patterns of its lon/lat (polygons that meet share their vertices exactly).
type Node = (u64, u64);

/// A land-use polygon in metres.
pub struct Area {
    pub landuse: String,
    pub ring: Vec<DVec2>,
    /// Its vertices as read (degrees, bit patterns): where OpenStreetMap polygons share nodes.
    pub nodes: Vec<Node>,
}

/// The data of one place, in metres in its terrain's projection.
pub struct Place {
    pub terrain: Terrain,
    pub roads: Vec<RealRoad>,
    /// Building centroids.
    pub houses: Vec<DVec2>,
    /// Each building's long axis (radians from +X, any half-turn): its minimum-area rectangle's longer side.
    pub orientations: Vec<f64>,
    pub areas: Vec<Area>,
    /// Lakes, ponds, reservoirs and river areas (`natural=water`, `waterway=riverbank`, `landuse=reservoir` or
    /// `basin`).
    pub water: Vec<Vec<DVec2>>,
    pub places: Vec<NamedPlace>,
    /// Ways left out as not served roads (footways, paths, motorways...).
    pub not_roads: usize,
    /// Features whose geometry or tags could not be read.
    pub unreadable: usize,
}

/// Loads a place; `Err` when one of its files cannot be read.
pub fn load_place(spec: PlaceSpec) -> Result<Place, String> {
    let dir = real_data_dir();
    let terrain_path = dir.join(format!("terrain/{}_srtm3.asc", spec.stem));
    let layer = |name: &str| dir.join(format!("villages/{}_{name}.geojson", spec.stem));
    let paths = [
        terrain_path.clone(),
        layer("buildings"),
        layer("roads"),
        layer("areas"),
        layer("places"),
    ];
    require(&paths);
    let grid = read_ascii_grid(&terrain_path)?;
    let terrain = terrain_from_grid(&grid, TERRAIN_CELL)?;
    let proj = terrain.projection;
    let project =
        |line: &[[f64; 2]]| -> Vec<DVec2> { line.iter().map(|p| proj.project(*p)).collect() };

    let mut unreadable = 0;
    let mut not_roads = 0;
    let mut roads = Vec::new();
    let roads_layer = read_features(&paths[2])?;
    unreadable += roads_layer.unreadable;
    for f in &roads_layer.features {
        match (f.tag("highway"), Some(outer_lines(&f.shape))) {
            (Some(h), Some(_)) if FOOT_AND_BRIDLE_WAYS.contains(&h) || NOT_SERVING.contains(&h) => {
                not_roads += 1
            }
            (Some(h), Some(lines)) => {
                roads.extend(lines.iter().filter(|l| l.len() >= 2).map(|l| RealRoad {
                    highway: h.to_string(),
                    points: project(l),
                }))
            }
            _ => unreadable += 1,
        }
    }
    let mut houses = Vec::new();
    let mut orientations = Vec::new();
    let buildings_layer = read_features(&paths[1])?;
    unreadable += buildings_layer.unreadable;
    for f in &buildings_layer.features {
        match open_ring(project(&outer_lines(&f.shape)[0])) {
            Some(ring) => {
                orientations.push(min_area_rectangle(&ring).2);
                houses.push(area_centroid(&[ring], FLAT_RING));
            }
            None => unreadable += 1,
        }
    }
    let mut areas = Vec::new();
    let mut water = Vec::new();
    let areas_layer = read_features(&paths[3])?;
    unreadable += areas_layer.unreadable;
    for f in &areas_layer.features {
        let landuse = f.tag("landuse");
        let is_water = f.tag("natural") == Some("water")
            || f.tag("waterway") == Some("riverbank")
            || matches!(landuse, Some("reservoir" | "basin"));
        if !is_water && landuse.is_none() {
            continue;
        }
        let rings = outer_lines(&f.shape);
        if is_water {
            water.extend(rings.iter().filter_map(|r| open_ring(project(r))));
        }
        let Some(landuse) = landuse else {
            continue;
        };
        for r in rings {
            let mut r = r;
            if r.len() >= 2 && r.first() == r.last() {
                r.pop();
            }
            if let Some(ring) = open_ring(project(&r)) {
                areas.push(Area {
                    landuse: landuse.to_string(),
                    nodes: r.iter().map(|p| (p[0].to_bits(), p[1].to_bits())).collect(),
                    ring,
                });
            }
        }
    }
    let mut places = Vec::new();
    for f in &read_features(&paths[4])?.features {
        let point = outer_lines(&f.shape)
            .first()
            .and_then(|l| l.first().copied());
        if let (Some(kind), Some(p)) = (f.tag("place"), point) {
            places.push(NamedPlace {
                kind: kind.to_string(),
                name: f.tag("name").unwrap_or("(unnamed)").to_string(),
                position: proj.project(p),
            });
        }
    }
    if roads.is_empty() || houses.is_empty() {
        return Err(format!("{}: no readable roads or buildings", spec.label));
    }
    Ok(Place {
        terrain,
        roads,
        houses,
        orientations,
        areas,
        water,
        places,
        not_roads,
        unreadable,
    })
}

// ---------------------------------------------------------------------------------------------------------------
// Windows

/// A square window on a real village.
#[derive(Clone, Debug)]
pub struct Window {
    pub region: Region,
    /// Buildings inside.
    pub buildings: usize,
    /// The nearest village, hamlet or town inside, else "near" the nearest one.
    pub name: String,
    /// Centre in degrees (lon, lat).
    pub centre_lon_lat: [f64; 2],
}

/// Up to `count` windows of `side` metres holding the most buildings, clear of each other, each with at least
/// `min_buildings`.
pub fn densest_windows(
    place: &Place,
    side: f64,
    count: usize,
    min_buildings: usize,
) -> Vec<Window> {
    let (tlo, thi) = place.terrain.heightfield.bbox();
    let margin = place.terrain.source_spacing.max_element();
    let hbox = ring_bbox(&place.houses);
    let (lo, hi) = (
        (tlo + DVec2::splat(margin)).max(hbox.0),
        (thi - DVec2::splat(margin)).min(hbox.1),
    );
    let squares = squares_by_count(&place.houses, lo, hi, side, SEARCH_STEP);
    let clear = side + WINDOW_GAP;
    let mut picked: Vec<DVec2> = Vec::new();
    let mut out: Vec<Window> = Vec::new();
    for (min, n) in squares {
        if out.len() == count || n < min_buildings {
            break;
        }
        if picked
            .iter()
            .any(|q| (q.x - min.x).abs() < clear && (q.y - min.y).abs() < clear)
        {
            continue;
        }
        picked.push(min);
        // re-centred on its buildings, kept on the terrain
        let centre = centre_of_points_in(&place.houses, min, side);
        let min = (centre - DVec2::splat(0.5 * side))
            .max(tlo + DVec2::splat(margin))
            .min(thi - DVec2::splat(margin + side));
        let region = square(min, side);
        let centre = min + DVec2::splat(0.5 * side);
        if out.iter().any(|w| {
            let d = w.region.bbox().0 - min;
            d.x.abs() < side && d.y.abs() < side
        }) {
            continue; // re-centred onto a window already taken
        }
        let name = place
            .places
            .iter()
            .filter(|p| {
                ["village", "hamlet", "town", "isolated_dwelling", "locality"]
                    .contains(&p.kind.as_str())
            })
            .min_by(|a, b| {
                a.position
                    .distance(centre)
                    .total_cmp(&b.position.distance(centre))
            })
            .map_or("-".to_string(), |p| {
                if region.contains(p.position) {
                    p.name.clone()
                } else {
                    format!("near {}", p.name)
                }
            });
        // two windows near the same place are told apart by their rank
        let name = if out
            .iter()
            .any(|w| w.name == name || w.name.starts_with(&format!("{name} (")))
        {
            format!("{name} ({})", out.len() + 1)
        } else {
            name
        };
        out.push(Window {
            buildings: place.houses.iter().filter(|p| region.contains(**p)).count(),
            region,
            name,
            centre_lon_lat: place.terrain.projection.unproject(centre),
        });
    }
    out
}

/// The water areas of a place whose box meets a window's.
pub fn water_near(place: &Place, window: &Window) -> Vec<Vec<DVec2>> {
    let (lo, hi) = window.region.bbox();
    place
        .water
        .iter()
        .filter(|ring| {
            let (a, b) = ring_bbox(ring);
            a.x <= hi.x && a.y <= hi.y && b.x >= lo.x && b.y >= lo.y
        })
        .cloned()
        .collect()
}

/// The houses and roads of a real window, clipped to it.
pub struct RealWindow {
    pub houses: Vec<DVec2>,
    pub roads: Vec<Road>,
    /// Length (m) of tracks and service ways among the roads.
    pub minor_length: f64,
    /// Where through roads cross the window's border (merged within 60 m).
    pub connections: Vec<DVec2>,
}

pub fn real_window(place: &Place, window: &Window) -> RealWindow {
    let region = &window.region;
    let houses = points_in(&place.houses, region);
    let mut roads = Vec::new();
    let mut minor_length = 0.0;
    let mut connections: Vec<DVec2> = Vec::new();
    for road in &place.roads {
        let (inside, _) = region.clip_polyline(&road.points);
        let pieces: Vec<Road> = inside.into_iter().map(|points| Road { points }).collect();
        if MINOR_ROADS.contains(&road.highway.as_str()) {
            minor_length += road_length(&pieces);
        }
        roads.extend(pieces);
        if THROUGH_ROADS.contains(&road.highway.as_str()) {
            for s in road.points.windows(2) {
                for t in region.segment_crossings(s[0], s[1]) {
                    let p = s[0] + (s[1] - s[0]) * t;
                    if connections.iter().all(|c| c.distance(p) > CONNECTION_MERGE) {
                        connections.push(p);
                    }
                }
            }
        }
    }
    RealWindow {
        houses,
        roads,
        minor_length,
        connections,
    }
}

// ---------------------------------------------------------------------------------------------------------------
// Figures

/// Road grades summarised: shares of the length in [`GRADE_BINS`] (and beyond the last bound), the steepest.
#[derive(Clone, Debug, Default)]
pub struct GradeSummary {
    pub shares: [f64; 6],
    pub steepest: f64,
}

impl GradeSummary {
    pub fn new(grades: &[(f64, f64)]) -> GradeSummary {
        let mut lengths = [0.0; 6];
        let mut steepest: f64 = 0.0;
        for (g, l) in grades.iter().filter(|(g, l)| g.is_finite() && *l > 0.0) {
            let bin = GRADE_BINS.iter().position(|b| g <= b).unwrap_or(5);
            lengths[bin] += l;
            steepest = steepest.max(*g);
        }
        let length: f64 = lengths.iter().sum();
        GradeSummary {
            shares: lengths.map(|l| if length > 0.0 { l / length } else { 0.0 }),
            steepest,
        }
    }

    /// Share of the length steeper than `grade`, read from the pieces.
    pub fn share_over(grades: &[(f64, f64)], grade: f64) -> f64 {
        let total: f64 = grades.iter().map(|g| g.1).sum();
        let over: f64 = grades.iter().filter(|g| g.0 > grade).map(|g| g.1).sum();
        if total > 0.0 {
            over / total
        } else {
            0.0
        }
    }
}

/// The terrain under a window: its height range and mean grade, from the percentile grid.
#[derive(Clone, Copy, Debug, Default)]
pub struct Relief {
    pub lowest: f64,
    pub highest: f64,
    pub mean_grade: f64,
}

/// What is measured on a village, real or generated.
#[derive(Clone, Debug, Default)]
pub struct Figures {
    pub layout: LayoutStatistics,
    pub grades: GradeSummary,
    /// Share of the road length steeper than the encyclopedia's maximum grade.
    pub over_max_grade: f64,
    pub road_length: f64,
    pub elevation_percentile: f64,
    pub network: NetworkShape,
}

/// The grid over a window on which elevation percentiles and relief are read.
pub fn window_land(terrain: &Heightfield, window: &Window) -> Result<Land, String> {
    Land::new(
        terrain,
        &window.region,
        &Environment::default(),
        PERCENTILE_CELL,
    )
    .map_err(|e| format!("land of the window: {e}"))
}

pub fn relief(land: &Land) -> Relief {
    let inside: Vec<usize> = (0..land.grid().len())
        .filter(|k| land.inside()[*k])
        .collect();
    let n = inside.len().max(1) as f64;
    Relief {
        lowest: inside
            .iter()
            .map(|k| land.height()[*k] as f64)
            .fold(f64::INFINITY, f64::min),
        highest: inside
            .iter()
            .map(|k| land.height()[*k] as f64)
            .fold(f64::NEG_INFINITY, f64::max),
        mean_grade: inside.iter().map(|k| land.grade_at_node(*k)).sum::<f64>() / n,
    }
}

/// The figures of houses and roads on a terrain, grades read on the heightfield (clamped onto it).
pub fn figures(
    terrain: &Heightfield,
    land: &Land,
    region: &Region,
    houses: &[DVec2],
    roads: &[Road],
    max_grade: f64,
) -> Figures {
    let (lo, hi) = terrain.bbox();
    let ground = |p: DVec2| terrain.height_at(p.max(lo).min(hi)).unwrap_or(f64::NAN);
    let grades = road_grades(roads, &ground, GRADE_STEP);
    Figures {
        layout: layout_statistics(houses, roads),
        grades: GradeSummary::new(&grades),
        over_max_grade: GradeSummary::share_over(&grades, max_grade),
        road_length: road_length(roads),
        elevation_percentile: mean_elevation_percentile(land, houses),
        network: network_shape(region, roads),
    }
}

// ---------------------------------------------------------------------------------------------------------------
// Real parcels

/// Real parcels in metres, with what was left out.
pub struct RealParcels {
    pub contours: Vec<Vec<DVec2>>,
    /// Polygons read, and left out (unreadable, nested, or degenerate).
    pub read: usize,
    pub left_out: usize,
    /// Share of the kept polygons that share a boundary (two consecutive nodes) with another kept one.
    pub sharing: f64,
    /// Kept polygons per land-use class (land use only).
    pub classes: Vec<(String, usize)>,
}

/// Counter-clockwise contour (the engine's parcels are counter-clockwise).
fn counter_clockwise(mut ring: Vec<DVec2>) -> Vec<DVec2> {
    if polygon_signed_area(&ring) < 0.0 {
        ring.reverse();
    }
    ring
}

/// The cadastre of Épinay-sur-Orge (outer rings, projected about the centre of their bounding box).
pub fn load_cadastre() -> Result<RealParcels, String> {
    let path = real_data_dir().join("parcels/cadastre-91216-parcelles.json");
    require(std::slice::from_ref(&path));
    let layer = read_features(&path)?;
    let rings: Vec<Option<Vec<[f64; 2]>>> = layer
        .features
        .iter()
        .map(|f| outer_lines(&f.shape).into_iter().next())
        .collect();
    let read = layer.features.len() + layer.unreadable;
    let (lo, hi) = rings.iter().flatten().flatten().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    );
    if !(lo[0] <= hi[0] && lo[1] <= hi[1]) {
        return Err(format!("{}: no readable parcel", path.display()));
    }
    let proj = Projection::new([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])]);
    let mut contours = Vec::new();
    let mut nodes = Vec::new();
    for r in rings.into_iter().flatten() {
        let projected: Vec<DVec2> = r.iter().map(|p| proj.project(*p)).collect();
        if let Some(ring) = open_ring(projected) {
            nodes.push(
                ring.iter()
                    .map(|p| (p.x.to_bits(), p.y.to_bits()))
                    .collect(),
            );
            contours.push(counter_clockwise(ring));
        }
    }
    Ok(RealParcels {
        read,
        left_out: read - contours.len(),
        sharing: sharing(&nodes),
        contours,
        classes: Vec::new(),
    })
}

/// Share of polygons that have a boundary edge (a pair of consecutive nodes, either way round) in common with
/// another one.
fn sharing(polygons: &[Vec<Node>]) -> f64 {
    let mut edges: HashMap<(Node, Node), Vec<usize>> = HashMap::new();
    for (k, nodes) in polygons.iter().enumerate() {
        for i in 0..nodes.len() {
            let (a, b) = (nodes[i], nodes[(i + 1) % nodes.len()]);
            let key = if a <= b { (a, b) } else { (b, a) };
            edges.entry(key).or_default().push(k);
        }
    }
    let mut shares = vec![false; polygons.len()];
    for owners in edges.values() {
        if owners.iter().any(|o| *o != owners[0]) {
            for o in owners {
                shares[*o] = true;
            }
        }
    }
    shares.iter().filter(|s| **s).count() as f64 / polygons.len().max(1) as f64
}

/// The land-use polygons of a place that tile the land (see the module doc).
pub fn tiling_landuse(place: &Place) -> RealParcels {
    let areas = &place.areas;
    let boxes: Vec<(DVec2, DVec2)> = areas.iter().map(|a| ring_bbox(&a.ring)).collect();
    let centroids: Vec<DVec2> = areas
        .iter()
        .map(|a| area_centroid(&[&a.ring], FLAT_RING))
        .collect();
    let mut nested = vec![false; areas.len()];
    for (i, c) in centroids.iter().enumerate() {
        if !polygon_contains(&areas[i].ring, *c) {
            continue; // a concave polygon's centroid says nothing about nesting
        }
        for (j, a) in areas.iter().enumerate() {
            let (lo, hi) = boxes[j];
            if i != j
                && c.x >= lo.x
                && c.y >= lo.y
                && c.x <= hi.x
                && c.y <= hi.y
                && polygon_contains(&a.ring, *c)
            {
                nested[i] = true;
                nested[j] = true;
            }
        }
    }
    let kept: Vec<usize> = (0..areas.len()).filter(|k| !nested[*k]).collect();
    let mut classes: Vec<(String, usize)> = Vec::new();
    for k in &kept {
        match classes.iter_mut().find(|c| c.0 == areas[*k].landuse) {
            Some(c) => c.1 += 1,
            None => classes.push((areas[*k].landuse.clone(), 1)),
        }
    }
    classes.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let nodes: Vec<Vec<Node>> = kept.iter().map(|k| areas[*k].nodes.clone()).collect();
    RealParcels {
        contours: kept
            .iter()
            .map(|k| counter_clockwise(areas[*k].ring.clone()))
            .collect(),
        read: areas.len(),
        left_out: areas.len() - kept.len(),
        sharing: sharing(&nodes),
        classes,
    }
}

// ---------------------------------------------------------------------------------------------------------------
// Tables

/// A plain-text table: a label column and value columns.
pub struct Table {
    pub header: Vec<String>,
    pub rows: Vec<(String, Vec<String>)>,
}

impl Table {
    pub fn new(first: &str, columns: Vec<String>) -> Table {
        let mut header = vec![first.to_string()];
        header.extend(columns);
        Table {
            header,
            rows: Vec::new(),
        }
    }

    pub fn row(&mut self, label: impl Into<String>, values: Vec<String>) {
        self.rows.push((label.into(), values));
    }

    pub fn render(&self) -> String {
        let columns = self.header.len();
        let mut widths: Vec<usize> = self.header.iter().map(|h| h.chars().count()).collect();
        for (label, values) in &self.rows {
            widths[0] = widths[0].max(label.chars().count());
            for (k, v) in values.iter().enumerate().take(columns - 1) {
                widths[k + 1] = widths[k + 1].max(v.chars().count());
            }
        }
        let pad = |s: &str, w: usize, left: bool| {
            let fill = " ".repeat(w.saturating_sub(s.chars().count()));
            if left {
                format!("{s}{fill}")
            } else {
                format!("{fill}{s}")
            }
        };
        let mut out = String::new();
        let line = |cells: Vec<&str>, out: &mut String| {
            let mut parts = Vec::new();
            for (k, c) in cells.iter().enumerate() {
                parts.push(pad(c, widths[k], k == 0));
            }
            out.push_str(parts.join("  ").trim_end());
            out.push('\n');
        };
        line(self.header.iter().map(String::as_str).collect(), &mut out);
        let total: usize = widths.iter().sum::<usize>() + 2 * (columns - 1);
        out.push_str(&"-".repeat(total));
        out.push('\n');
        for (label, values) in &self.rows {
            let mut cells = vec![label.as_str()];
            cells.extend(values.iter().map(String::as_str));
            line(cells, &mut out);
        }
        out
    }
}

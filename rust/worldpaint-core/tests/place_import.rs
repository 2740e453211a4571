//! Real places imported: the OpenStreetMap layers and SRTM terrain north of Bayreuth and in Andorra, the layers of a
//! corner of Kirchberg an der Iller and the Luquillo tree inventory (from `shared/data/real` beside the project;
//! each test says it is skipped where the data is absent), measured against the source files read here on their own:
//! building counts, road lengths by haversine on the source lon/lat, the terrain's extent and heights. Then the other
//! formats on files written here (an SRTM `.hgt` tile, GeoTIFFs), and every bad file a user may bring, each refused
//! with a message that says what is wrong.
//!
//! Printed with `--nocapture`: per place the counts, lengths and extents, source against import.

mod common;
use common::real_data;

use serde_json::Value;
use std::path::{Path, PathBuf};
use worldpaint_core::DVec2;
use worldpaint_core::{
    import_place, read_elevation_model, BuildingType, Error, InventoryCoordinates, Place,
    PlaceOptions, RoadClass,
};

/// Mean Earth radius (m), for haversine lengths.
const EARTH_RADIUS: f64 = 6_371_008.8;

fn no_progress(_: f64, _: &'static str) -> bool {
    true
}

/// A file of the real data, or `None` with a message saying the test is skipped.
fn real(relative: &str) -> Option<PathBuf> {
    let path = real_data_dir().join(relative);
    if path.is_file() {
        Some(path)
    } else {
        println!(
            "skipped: {} not found (the real data lives beside the project, in shared/data/real)",
            path.display()
        );
        None
    }
}

use real_data::real_data_dir;

fn import(
    layers: &[PathBuf],
    dem: Option<&Path>,
    inventory: Option<&Path>,
    options: &PlaceOptions,
) -> Place {
    import_place(layers, dem, inventory, options, &no_progress)
        .unwrap_or_else(|e| panic!("import failed: {e}"))
}

fn haversine(a: [f64; 2], b: [f64; 2]) -> f64 {
    let (p1, p2) = (a[1].to_radians(), b[1].to_radians());
    let (dp, dl) = (p2 - p1, (b[0] - a[0]).to_radians());
    let h = (dp / 2.0).sin().powi(2) + p1.cos() * p2.cos() * (dl / 2.0).sin().powi(2);
    2.0 * EARTH_RADIUS * h.sqrt().asin()
}

fn polyline_length(points: &[DVec2]) -> f64 {
    points.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// The source's features, read here with serde_json alone.
fn source_features(path: &Path) -> Vec<Value> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    match v["features"].take() {
        Value::Array(a) => a,
        _ => panic!("{} has no features", path.display()),
    }
}

fn lon_lat_lines(geometry: &Value) -> Vec<Vec<[f64; 2]>> {
    let line = |v: &Value| -> Vec<[f64; 2]> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
            .collect()
    };
    let c = &geometry["coordinates"];
    match geometry["type"].as_str().unwrap() {
        "Point" => vec![vec![[c[0].as_f64().unwrap(), c[1].as_f64().unwrap()]]],
        "LineString" => vec![line(c)],
        "MultiLineString" | "Polygon" => c.as_array().unwrap().iter().map(line).collect(),
        "MultiPolygon" => c
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|p| p.as_array().unwrap().iter().map(line))
            .collect(),
        other => panic!("geometry {other}"),
    }
}

/// What the source layers hold, measured here: building features, highway line length by haversine, lon/lat box.
struct SourceFigures {
    buildings: usize,
    road_length: f64,
    lon_lat_box: ([f64; 2], [f64; 2]),
}

fn source_figures(layers: &[PathBuf]) -> SourceFigures {
    let mut out = SourceFigures {
        buildings: 0,
        road_length: 0.0,
        lon_lat_box: ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
    };
    for path in layers {
        for f in source_features(path) {
            let props = &f["properties"];
            let kind = f["geometry"]["type"].as_str().unwrap_or("");
            let lines = lon_lat_lines(&f["geometry"]);
            for p in lines.iter().flatten() {
                let (lo, hi) = &mut out.lon_lat_box;
                *lo = [lo[0].min(p[0]), lo[1].min(p[1])];
                *hi = [hi[0].max(p[0]), hi[1].max(p[1])];
            }
            let building = props["building"].as_str().is_some_and(|b| b != "no");
            if building && kind.contains("Polygon") {
                out.buildings += 1;
            }
            if props["highway"].is_string() && kind.contains("LineString") {
                out.road_length += lines
                    .iter()
                    .map(|l| l.windows(2).map(|w| haversine(w[0], w[1])).sum::<f64>())
                    .sum::<f64>();
            }
        }
    }
    out
}

/// A minimal ESRI ASCII grid reader of this test's own: header, then heights row by row from the north.
struct SourceGrid {
    ncols: usize,
    nrows: usize,
    xll: f64,
    yll: f64,
    cell: f64,
    nodata: f64,
    values: Vec<f64>,
}

fn source_grid(path: &Path) -> SourceGrid {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let mut header = std::collections::HashMap::new();
    for _ in 0..6 {
        let line = lines.next().unwrap();
        let mut parts = line.split_whitespace();
        let key = parts.next().unwrap().to_ascii_lowercase();
        header.insert(key, parts.next().unwrap().parse::<f64>().unwrap());
    }
    let values: Vec<f64> = lines
        .flat_map(|l| l.split_whitespace().map(|t| t.parse::<f64>().unwrap()))
        .collect();
    SourceGrid {
        ncols: header["ncols"] as usize,
        nrows: header["nrows"] as usize,
        xll: header["xllcorner"],
        yll: header["yllcorner"],
        cell: header["cellsize"],
        nodata: header["nodata_value"],
        values,
    }
}

impl SourceGrid {
    /// Lon/lat of sample (c, r), row 0 north.
    fn lon_lat(&self, c: usize, r: usize) -> [f64; 2] {
        [
            self.xll + (c as f64 + 0.5) * self.cell,
            self.yll + ((self.nrows - 1 - r) as f64 + 0.5) * self.cell,
        ]
    }

    /// Bilinear height at lon/lat between sample centres, `None` near a hole or outside.
    fn bilinear(&self, p: [f64; 2]) -> Option<f64> {
        let fc = (p[0] - self.xll) / self.cell - 0.5;
        let fr = (self.yll + self.nrows as f64 * self.cell - p[1]) / self.cell - 0.5;
        if fc < 0.0 || fr < 0.0 || fc > (self.ncols - 1) as f64 || fr > (self.nrows - 1) as f64 {
            return None;
        }
        let (c, r) = (
            (fc as usize).min(self.ncols - 2),
            (fr as usize).min(self.nrows - 2),
        );
        let (tc, tr) = (fc - c as f64, fr - r as f64);
        let h = |c: usize, r: usize| {
            Some(self.values[r * self.ncols + c]).filter(|v| *v != self.nodata)
        };
        let top = h(c, r)? * (1.0 - tc) + h(c + 1, r)? * tc;
        let bottom = h(c, r + 1)? * (1.0 - tc) + h(c + 1, r + 1)? * tc;
        Some(top * (1.0 - tr) + bottom * tr)
    }
}

fn village_layers(stem: &str, names: &[&str]) -> Option<Vec<PathBuf>> {
    names
        .iter()
        .map(|n| real(&format!("villages/{stem}_{n}.geojson")))
        .collect()
}

/// Imports a real place and checks it against its source files; returns the place.
/// `sample_error`: the mean height difference (m) allowed at the source's own samples, where the terrain's nodes,
/// laid on the frame's grid, do not fall on them (it grows with the relief).
fn check_real_place(
    stem: &str,
    layers: &[&str],
    with_dem: bool,
    sample_error: f64,
) -> Option<Place> {
    let layers = village_layers(stem, layers)?;
    let dem = if with_dem {
        Some(real(&format!("terrain/{stem}_srtm3.asc"))?)
    } else {
        None
    };
    let options = PlaceOptions::default();
    let place = import(&layers, dem.as_deref(), None, &options);
    let source = source_figures(&layers);

    let buildings = place.buildings.len();
    let road_length: f64 = place.roads.iter().map(|r| polyline_length(&r.points)).sum();
    println!(
        "{stem}: {} buildings (source {}), roads {:.1} km (source {:.1} km by haversine, {:+.3} %), {} areas, {} \
         places, {} features left out, {} unreadable",
        buildings,
        source.buildings,
        road_length / 1000.0,
        source.road_length / 1000.0,
        100.0 * (road_length / source.road_length - 1.0),
        place.areas.len(),
        place.places.len(),
        place.report.left_out,
        place.report.unreadable
    );
    assert!(
        (buildings as f64 - source.buildings as f64).abs() <= 0.01 * source.buildings as f64,
        "{stem}: {buildings} buildings imported of {}",
        source.buildings
    );
    assert!(
        (road_length / source.road_length - 1.0).abs() <= 0.01,
        "{stem}: road length {road_length:.0} m against {:.0} m",
        source.road_length
    );
    // every building has a footprint, a positive area and a size that holds it
    for b in &place.buildings {
        assert!(b.area > 0.0 && b.size[0] >= b.size[1] && b.size[1] > 0.0);
        assert!(b.size[0] * b.size[1] >= b.area * (1.0 - 1e-9), "{b:?}");
        assert!((0.0..std::f64::consts::PI).contains(&b.orientation));
    }

    let projection = place.frame.projection().unwrap().unwrap();
    let origin = place.frame.origin.unwrap();
    let (lo, hi) = source.lon_lat_box;
    assert!(
        (origin[0] - 0.5 * (lo[0] + hi[0])).abs() < 1e-9
            && (origin[1] - 0.5 * (lo[1] + hi[1])).abs() < 1e-9
    );

    if let Some(dem) = dem {
        let terrain = place.terrain.as_ref().unwrap();
        let grid = source_grid(&dem);
        // the layers' extent in metres, from every source point
        let mut points = Vec::new();
        for path in &layers {
            for f in source_features(path) {
                points.extend(lon_lat_lines(&f["geometry"]).into_iter().flatten());
            }
        }
        let local = projection.to_local(&points).unwrap();
        let (mut flo, mut fhi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for p in &local {
            flo = flo.min(*p);
            fhi = fhi.max(*p);
        }
        // the grid's box in metres: inside its sample centres, projected
        let corners = projection
            .to_local(&[
                grid.lon_lat(0, grid.nrows - 1),
                grid.lon_lat(grid.ncols - 1, 0),
                grid.lon_lat(0, 0),
                grid.lon_lat(grid.ncols - 1, grid.nrows - 1),
            ])
            .unwrap();
        let glo = DVec2::new(
            corners[0].x.max(corners[2].x),
            corners[0].y.max(corners[3].y),
        );
        let ghi = DVec2::new(
            corners[1].x.min(corners[3].x),
            corners[1].y.min(corners[2].y),
        );
        let margin = options.margin;
        let (elo, ehi) = ((flo - margin).max(glo), (fhi + margin).min(ghi));
        let (tlo, thi) = terrain.bbox();
        let cell = terrain.cell;
        println!(
            "{stem}: terrain {} x {} nodes of {cell:.1} m, x {:.0}..{:.0}, y {:.0}..{:.0}; layers + {margin} m within \
             the grid: x {:.0}..{:.0}, y {:.0}..{:.0}; {} holes filled ({:.2} % under the place)",
            terrain.nx,
            terrain.ny,
            tlo.x,
            thi.x,
            tlo.y,
            thi.y,
            elo.x,
            ehi.x,
            elo.y,
            ehi.y,
            place.report.terrain.as_ref().unwrap().holes_filled,
            100.0 * place.report.terrain.as_ref().unwrap().hole_share,
        );
        for (t, e) in [
            (tlo.x, elo.x),
            (tlo.y, elo.y),
            (thi.x, ehi.x),
            (thi.y, ehi.y),
        ] {
            assert!(
                (t - e).abs() <= cell + 0.05,
                "{stem}: terrain side {t:.1} against {e:.1}"
            );
        }
        let (tsize, esize) = (thi - tlo, ehi - elo);
        assert!((tsize.x / esize.x - 1.0).abs() < 0.01 && (tsize.y / esize.y - 1.0).abs() < 0.01);
        // the default cell is the finer source spacing (SRTM 3″ east–west)
        let east = haversine(
            grid.lon_lat(grid.ncols / 2, grid.nrows / 2),
            grid.lon_lat(grid.ncols / 2 + 1, grid.nrows / 2),
        );
        assert!(
            (cell / east - 1.0).abs() < 0.01,
            "cell {cell} against {east}"
        );

        // every node holds the source's bilinear height at its lon/lat
        let nodes: Vec<DVec2> = (0..terrain.ny)
            .flat_map(|j| (0..terrain.nx).map(move |i| (i, j)))
            .map(|(i, j)| terrain.origin + DVec2::new(i as f64, j as f64) * cell)
            .collect();
        let lon_lat = projection.to_lon_lat(&nodes).unwrap();
        let (mut worst, mut compared) = (0.0f64, 0);
        for (k, p) in lon_lat.iter().enumerate() {
            if let Some(h) = grid.bilinear(*p) {
                worst = worst.max((h - terrain.heights[k] as f64).abs());
                compared += 1;
            }
        }
        // at the source's own samples, the terrain reads the sample's height within the relief of one cell
        let (mut sum, mut n) = (0.0, 0);
        for r in (0..grid.nrows).step_by(3) {
            for c in (0..grid.ncols).step_by(3) {
                let v = grid.values[r * grid.ncols + c];
                let p = projection.point_to_local(grid.lon_lat(c, r)).unwrap();
                if v == grid.nodata {
                    continue;
                }
                if let Some(h) = terrain.height_at(p) {
                    sum += (h - v).abs();
                    n += 1;
                }
            }
        }
        println!(
            "{stem}: node heights against the source's bilinear surface: worst {worst:.4} m over {compared} nodes; \
             at {n} source samples the terrain reads them within {:.2} m on average",
            sum / n as f64
        );
        assert!(compared as f64 > 0.99 * nodes.len() as f64);
        assert!(
            worst < 0.01,
            "{stem}: a node departs {worst} m from the source"
        );
        assert!(
            n > 100 && sum / n as f64 <= sample_error,
            "{stem}: mean {:.2} m",
            sum / n as f64
        );
    }
    Some(place)
}

#[test]
fn north_of_bayreuth_imports_with_its_buildings_roads_and_terrain() {
    let Some(place) = check_real_place(
        "north_bayreuth",
        &["buildings", "roads", "areas", "places"],
        true,
        1.0,
    ) else {
        return;
    };
    // OpenStreetMap maps most buildings as building=yes; the typed ones keep their type
    let typed = |t: BuildingType| place.buildings.iter().filter(|b| b.kind == t).count();
    assert!(
        typed(BuildingType::Garage) >= 13 && typed(BuildingType::House) >= 11,
        "garages and houses"
    );
    assert!(typed(BuildingType::Church) >= 2, "places of worship");
    let class = |c: RoadClass| place.roads.iter().filter(|r| r.class == c).count();
    assert_eq!(class(RoadClass::Track), 900);
    assert_eq!(class(RoadClass::Major), 64 + 33 + 62 + 23 + 6);
    assert!(place
        .places
        .iter()
        .any(|p| p.kind == "village" && p.name.is_some()));
}

#[test]
fn andorra_imports_with_its_holes_filled() {
    let Some(place) = check_real_place(
        "andorra",
        &["buildings", "roads", "areas", "places"],
        true,
        3.0,
    ) else {
        return;
    };
    let report = place.report.terrain.as_ref().unwrap();
    assert!(report.holes_filled == 239 && report.hole_share > 0.0 && report.hole_share < 0.01);
    assert_eq!(
        place
            .buildings
            .iter()
            .filter(|b| b.kind == BuildingType::Church)
            .count(),
        2 + 3
    );
}

#[test]
fn kirchberg_imports_without_terrain() {
    let Some(place) = check_real_place("kirchberg_iller", &["buildings", "roads"], false, 0.0)
    else {
        return;
    };
    assert!(place.terrain.is_none());
    assert_eq!(place.buildings.len(), 32);
    assert_eq!(place.roads.len(), 14);
    // a house measured by hand on the source: footprints of real buildings are a few metres to a few tens
    let sizes: Vec<f64> = place.buildings.iter().map(|b| b.size[0]).collect();
    assert!(sizes.iter().all(|s| (3.0..80.0).contains(s)), "{sizes:?}");
}

#[test]
fn a_second_import_with_the_first_origin_lines_up() {
    let Some(layers) = village_layers("kirchberg_iller", &["buildings", "roads"]) else {
        return;
    };
    let both = import(&layers, None, None, &PlaceOptions::default());
    let origin = both.frame.origin;
    let roads_alone = import(
        &layers[1..],
        None,
        None,
        &PlaceOptions {
            origin,
            ..PlaceOptions::default()
        },
    );
    assert_eq!(roads_alone.frame, both.frame);
    assert_eq!(roads_alone.roads, both.roads);
    let other_origin = import(&layers[1..], None, None, &PlaceOptions::default());
    assert_ne!(
        other_origin.roads, both.roads,
        "the roads' own centre is another frame"
    );
    // the place survives its JSON with its sources and frame
    let back = Place::from_json(&both.to_json().unwrap()).unwrap();
    assert_eq!(back.frame, both.frame);
    assert_eq!(back.sources, both.sources);
    assert_eq!(back.buildings, both.buildings);
    assert_eq!(back.sources.layers.len(), 2);
}

#[test]
fn the_luquillo_inventory_keeps_its_living_trees() {
    let Some(path) = real("forest/luquillo_tree6_1ha.csv") else {
        return;
    };
    let place = import(&[], None, Some(&path), &PlaceOptions::default());
    assert_eq!(place.trees.len(), 2595);
    assert_eq!(place.report.trees_not_alive, 5415);
    assert!(
        place.frame.origin.is_none(),
        "a local inventory alone has a local frame"
    );
    let species: std::collections::BTreeSet<&str> =
        place.trees.iter().map(|t| t.species.as_str()).collect();
    // the source's living trees' species, read here: column 3 (sp) of the rows whose column 9 (status) is A
    let text = std::fs::read_to_string(&path).unwrap();
    let source_species: std::collections::BTreeSet<&str> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| f[8] == "A")
        .map(|f| f[2])
        .collect();
    assert_eq!(species, source_species);
    assert_eq!(place.trees.iter().filter(|t| t.size.is_none()).count(), 276);
    let (lo, hi) = place
        .trees
        .iter()
        .fold((DVec2::splat(1e9), DVec2::splat(-1e9)), |(lo, hi), t| {
            (lo.min(t.position), hi.max(t.position))
        });
    println!(
        "luquillo: {} trees of {} species, x {:.1}..{:.1}, y {:.1}..{:.1}",
        place.trees.len(),
        species.len(),
        lo.x,
        hi.x,
        lo.y,
        hi.y
    );
    assert!(lo.x >= 0.0 && lo.y >= 0.0 && hi.x <= 320.0 && hi.y <= 500.0);
}

// ---------------------------------------------------------------------------------------------------------------
// Formats written here

/// A folder of this test's own files.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("worldpaint-place-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The height of a plane tilted east and north, in metres of lon/lat degrees.
fn plane(p: [f64; 2]) -> f64 {
    400.0 + 2000.0 * (p[0] - 11.0) + 3000.0 * (p[1] - 49.0)
}

/// A GeoJSON layer of one building square of `half` degrees around `centre` and a road through it.
fn small_layer(dir: &Path, centre: [f64; 2], half: f64) -> PathBuf {
    let [x, y] = centre;
    let ring = serde_json::json!([[
        [x - half, y - half],
        [x + half, y - half],
        [x + half, y + half],
        [x - half, y + half],
        [x - half, y - half]
    ]]);
    let layer = serde_json::json!({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"building": "house", "name": "Test"}, "geometry": {"type": "Polygon", "coordinates": ring}},
        {"type": "Feature", "properties": {"highway": "residential"}, "geometry": {"type": "LineString", "coordinates": [[x - 3.0 * half, y], [x + 3.0 * half, y]]}},
        {"type": "Feature", "properties": {"waterway": "stream"}, "geometry": {"type": "LineString", "coordinates": [[x, y - 3.0 * half], [x, y + 3.0 * half]]}},
    ]});
    let path = dir.join("layer.geojson");
    std::fs::write(&path, layer.to_string()).unwrap();
    path
}

/// Checks that every node of the place's terrain holds the plane's height at its lon/lat.
fn terrain_follows_the_plane(place: &Place) -> usize {
    let terrain = place.terrain.as_ref().unwrap();
    let projection = place.frame.projection().unwrap().unwrap();
    let nodes: Vec<DVec2> = (0..terrain.ny)
        .flat_map(|j| (0..terrain.nx).map(move |i| (i, j)))
        .map(|(i, j)| terrain.origin + DVec2::new(i as f64, j as f64) * terrain.cell)
        .collect();
    let lon_lat = projection.to_lon_lat(&nodes).unwrap();
    for (k, p) in lon_lat.iter().enumerate() {
        let (h, expected) = (terrain.heights[k] as f64, plane(*p));
        assert!(
            (h - expected).abs() < 0.02,
            "node {k}: {h} where the plane is {expected}"
        );
    }
    nodes.len()
}

#[test]
fn an_srtm_tile_is_read_from_its_name_and_big_endian_samples() {
    let dir = scratch("hgt");
    let n = 1201;
    let step = 1.0 / (n - 1) as f64;
    let mut bytes = Vec::with_capacity(n * n * 2);
    for r in 0..n {
        for c in 0..n {
            let p = [11.0 + c as f64 * step, 50.0 - r as f64 * step];
            bytes.extend_from_slice(&(plane(p).round() as i16).to_be_bytes());
        }
    }
    let tile = dir.join("N49E011.hgt");
    std::fs::write(&tile, &bytes).unwrap();
    let model = read_elevation_model(&tile).unwrap();
    assert_eq!((model.ncols, model.nrows), (1201, 1201));
    // sample (0, 0) is the tile's north-west corner
    assert_eq!(model.heights[0], plane([11.0, 50.0]).round());
    let layer = small_layer(&dir, [11.5, 49.5], 0.0005);
    let place = import(&[layer], Some(&tile), None, &PlaceOptions::default());
    let terrain = place.terrain.as_ref().unwrap();
    // 3″ at 49.5° N: 60.2 m east–west
    assert!((terrain.cell - 60.2).abs() < 0.3, "cell {}", terrain.cell);
    // the samples are rounded to whole metres: the plane within half a metre
    let projection = place.frame.projection().unwrap().unwrap();
    let centre = projection.point_to_local([11.5, 49.5]).unwrap();
    let h = terrain.height_at(centre).unwrap();
    assert!((h - plane([11.5, 49.5])).abs() < 0.6, "{h}");
    assert_eq!(place.buildings.len(), 1);
    assert_eq!(place.waterways.len(), 1);
    // the building is 0.001° square: 72 m east–west by 111 m north–south at 49.5° N, turned north
    let b = &place.buildings[0];
    assert!(
        (b.size[0] - 111.2).abs() < 0.5 && (b.size[1] - 72.3).abs() < 0.5,
        "{:?}",
        b.size
    );
    assert!((b.orientation - std::f64::consts::FRAC_PI_2).abs() < 0.01);
    assert_eq!(b.name.as_deref(), Some("Test"));
    // the terrain survives the place's JSON
    let back = Place::from_json(&place.to_json().unwrap()).unwrap();
    let (t, u) = (
        place.terrain.as_ref().unwrap(),
        back.terrain.as_ref().unwrap(),
    );
    assert_eq!(
        (t.origin, t.cell, t.nx, t.ny),
        (u.origin, u.cell, u.nx, u.ny)
    );
    assert_eq!(t.heights, u.heights);
    // the tile alone is the place: its whole extent, less up to a cell on each side where the grid nodes fall
    let alone = import(&[], Some(&tile), None, &PlaceOptions::default());
    let (lo, hi) = alone.terrain.as_ref().unwrap().bbox();
    let size = hi - lo;
    println!(
        "the tile alone: {:.0} x {:.0} m, origin {:?}",
        size.x, size.y, alone.frame.origin
    );
    assert_eq!(alone.frame.origin, Some([11.5, 49.5]));
    assert!((size.y - 111_250.0).abs() < 300.0, "{size}");
}

/// Writes a single-band float GeoTIFF of the plane over lon 11..11.1, lat 49..49.1 in 0.001° cells, with the given
/// GeoKeys (none when empty) and no-data value.
fn write_geotiff(path: &Path, keys: &[u16], nodata: Option<&str>, point_registered: bool) {
    use tiff::encoder::{colortype, TiffEncoder};
    use tiff::tags::Tag;
    let (n, step) = (101usize, 0.001);
    let shift = if point_registered { 0.5 } else { 0.0 };
    let mut data = Vec::with_capacity(n * n);
    for r in 0..n {
        for c in 0..n {
            // pixel centres
            let p = [
                11.0 + (c as f64 + 0.5) * step,
                49.1 - (r as f64 + 0.5) * step,
            ];
            data.push(plane(p) as f32);
        }
    }
    let file = std::fs::File::create(path).unwrap();
    let mut tiff = TiffEncoder::new(file).unwrap();
    let mut image = tiff
        .new_image::<colortype::Gray32Float>(n as u32, n as u32)
        .unwrap();
    let dir = image.encoder();
    dir.write_tag(Tag::ModelPixelScaleTag, &[step, step, 0.0][..])
        .unwrap();
    // area-registered: raster (0, 0) is the corner; point-registered: the first pixel's centre
    dir.write_tag(
        Tag::ModelTiepointTag,
        &[0.0, 0.0, 0.0, 11.0 + shift * step, 49.1 - shift * step, 0.0][..],
    )
    .unwrap();
    if !keys.is_empty() {
        dir.write_tag(Tag::GeoKeyDirectoryTag, keys).unwrap();
    }
    if let Some(nodata) = nodata {
        dir.write_tag(Tag::GdalNodata, nodata).unwrap();
    }
    image.write_data(&data).unwrap();
}

/// GeoKeys: version 1.1.0, then (id, location 0, count 1, value) for model type, raster type, geographic type.
fn geo_keys(model: u16, raster: u16, crs_key: u16, code: u16) -> Vec<u16> {
    vec![
        1, 1, 0, 3, 1024, 0, 1, model, 1025, 0, 1, raster, crs_key, 0, 1, code,
    ]
}

#[test]
fn a_geotiff_is_placed_by_its_scale_and_tiepoint() {
    let dir = scratch("tiff");
    let layer = small_layer(&dir, [11.05, 49.05], 0.002);
    for (name, keys, point) in [
        ("area.tif", geo_keys(2, 1, 2048, 4326), false),
        ("point.tif", geo_keys(2, 2, 2048, 4326), true),
        ("nokeys.tif", vec![], false),
    ] {
        let path = dir.join(name);
        write_geotiff(&path, &keys, Some("-9999"), point);
        let place = import(
            std::slice::from_ref(&layer),
            Some(&path),
            None,
            &PlaceOptions {
                cell: Some(20.0),
                ..Default::default()
            },
        );
        let nodes = terrain_follows_the_plane(&place);
        println!("{name}: {nodes} nodes on the plane");
        assert!(nodes > 100);
    }
    // a projected GeoTIFF (UTM 32N) is refused by name
    let path = dir.join("utm.tif");
    write_geotiff(&path, &geo_keys(1, 1, 3072, 32632), None, false);
    refused(
        import_place(
            std::slice::from_ref(&layer),
            Some(&path),
            None,
            &PlaceOptions::default(),
            &no_progress,
        ),
        &["a CRS it cannot place", "EPSG:32632"],
    );
}

// ---------------------------------------------------------------------------------------------------------------
// Bad files

fn refused(result: worldpaint_core::Result<Place>, words: &[&str]) -> Error {
    let e = match result {
        Ok(_) => panic!("accepted where it should refuse ({words:?})"),
        Err(e) => e,
    };
    let message = e.to_string();
    for w in words {
        assert!(message.contains(w), "'{message}' does not say '{w}'");
    }
    println!("refused: {message}");
    e
}

fn layer_file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn try_layers(layers: &[PathBuf]) -> worldpaint_core::Result<Place> {
    import_place(layers, None, None, &PlaceOptions::default(), &no_progress)
}

#[test]
fn bad_map_layers_are_refused_with_what_is_wrong() {
    let dir = scratch("bad-layers");
    let f = |name: &str, text: &str| vec![layer_file(&dir, name, text)];
    refused(
        try_layers(&f("text.geojson", "hello, world")),
        &["text.geojson", "not GeoJSON", "not JSON"],
    );
    refused(try_layers(&f("list.geojson", "[1, 2]")), &["not GeoJSON"]);
    refused(
        try_layers(&f("notype.geojson", "{\"features\": []}")),
        &["not GeoJSON", "no \"type\""],
    );
    refused(
        try_layers(&f(
            "feature.geojson",
            r#"{"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": [1, 2]}}"#,
        )),
        &["a GeoJSON Feature, not a FeatureCollection"],
    );
    refused(
        try_layers(&f(
            "empty.geojson",
            r#"{"type": "FeatureCollection", "features": []}"#,
        )),
        &["an empty layer"],
    );
    refused(
        try_layers(&f(
            "nogeometry.geojson",
            r#"{"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"building": "yes"}, "geometry": null}]}"#,
        )),
        &["an empty layer", "none of its 1 features"],
    );
    let e = refused(
        try_layers(&f(
            "utm.geojson",
            r#"{"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::25832"}}, "features": [{"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": [1, 2]}}]}"#,
        )),
        &["a CRS it cannot place", "EPSG::25832"],
    );
    assert!(matches!(e, Error::Parse { .. }), "a file error");
    refused(
        try_layers(&f(
            "metres.geojson",
            r#"{"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"building": "yes"}, "geometry": {"type": "Polygon", "coordinates": [[[556440, 5394932], [556450, 5394932], [556450, 5394940], [556440, 5394932]]]}}]}"#,
        )),
        &["a CRS it cannot place", "556440", "not lon/lat"],
    );
    // a CRS84 or EPSG:4326 collection is fine, and so is a feature of a kind it does not keep beside good ones
    let good = f(
        "crs84.geojson",
        r#"{"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:OGC:1.3:CRS84"}}, "features": [{"type": "Feature", "properties": {"place": "hamlet", "name": "A"}, "geometry": {"type": "Point", "coordinates": [1, 2]}}, {"type": "Feature", "properties": {}, "geometry": {"type": "GeometryCollection", "geometries": []}}]}"#,
    );
    let place = try_layers(&good).unwrap();
    assert_eq!((place.places.len(), place.report.unreadable), (1, 1));
    refused(
        try_layers(&[dir.join("missing.geojson")]),
        &["missing.geojson", "cannot read"],
    );
    // a file past the size limit is refused before it is read (a sparse file: no disk is used)
    let huge = dir.join("huge.geojson");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len(worldpaint_core::MAX_PLACE_FILE_BYTES + 1)
        .unwrap();
    refused(
        try_layers(std::slice::from_ref(&huge)),
        &["too large", "huge.geojson", "bytes"],
    );
    std::fs::remove_file(&huge).unwrap();
    refused(
        import_place(&[], None, None, &PlaceOptions::default(), &no_progress),
        &["needs a map layer"],
    );
}

/// An ESRI ASCII grid of `n` × `n` samples of 0.001° from (11, 49), the plane's heights, with `holes` of them
/// (spread evenly: one sample in `n² / holes` of each row, shifted from row to row) set to -32768, and the given
/// text in place of one sample.
fn write_ascii_grid(path: &Path, n: usize, holes: usize, one_cell: Option<&str>) {
    let mut text = format!(
        "ncols {n}\nnrows {n}\nxllcorner 11\nyllcorner 49\ncellsize 0.001\nNODATA_value -32768\n"
    );
    let every = (n * n).checked_div(holes);
    for r in 0..n {
        let row: Vec<String> = (0..n)
            .map(|c| {
                let k = r * n + c;
                if k == n * n / 2 {
                    if let Some(v) = one_cell {
                        return v.to_string();
                    }
                }
                if every.is_some_and(|every| (r * 37 + c) % every == 0) {
                    "-32768".into()
                } else {
                    let p = [
                        11.0 + (c as f64 + 0.5) * 0.001,
                        49.0 + ((n - 1 - r) as f64 + 0.5) * 0.001,
                    ];
                    format!("{:.3}", plane(p))
                }
            })
            .collect();
        text.push_str(&row.join(" "));
        text.push('\n');
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn bad_elevation_models_are_refused_and_few_holes_filled() {
    let dir = scratch("bad-dem");
    let layer = small_layer(&dir, [11.05, 49.05], 0.002);
    let with = |dem: &Path| {
        import_place(
            std::slice::from_ref(&layer),
            Some(dem),
            None,
            &PlaceOptions::default(),
            &no_progress,
        )
    };
    // 2 % holes are filled from their neighbours
    let few = dir.join("few.asc");
    write_ascii_grid(&few, 100, 200, None);
    let place = with(&few).unwrap();
    let report = place.report.terrain.as_ref().unwrap();
    println!(
        "few holes: {} filled, {:.2} % under the place",
        report.holes_filled,
        100.0 * report.hole_share
    );
    assert_eq!(report.holes_filled, 200);
    assert!(report.hole_share > 0.01 && report.hole_share < 0.05);
    // 10 % are refused, naming the share
    let many = dir.join("many.asc");
    write_ascii_grid(&many, 100, 1000, None);
    refused(
        with(&many),
        &[
            "many.asc",
            "no data in 10.",
            "% of its samples under the place",
            "5 %",
        ],
    );
    // a .prj naming a projected CRS, and a metric grid without one (the real Kootenai grid is UTM metres)
    let projected = dir.join("projected.asc");
    write_ascii_grid(&projected, 50, 0, None);
    std::fs::write(
        dir.join("projected.prj"),
        r#"PROJCS["ETRS_1989_UTM_Zone_32N",GEOGCS["GCS_ETRS_1989"]]"#,
    )
    .unwrap();
    refused(
        with(&projected),
        &["a CRS it cannot place", "ETRS_1989_UTM_Zone_32N"],
    );
    let wgs84 = dir.join("wgs84.asc");
    write_ascii_grid(&wgs84, 100, 0, None);
    std::fs::write(
        dir.join("wgs84.prj"),
        r#"GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",SPHEROID["WGS_1984",6378137,298.257223563]]]"#,
    )
    .unwrap();
    assert!(with(&wgs84).is_ok());
    if let Some(kootenai) = real("terrain/DEM-kootenai_37x50_1x1.asc") {
        refused(with(&kootenai), &["a CRS it cannot place", "556440"]);
    }
    // not finite, not a number, the wrong count
    let inf = dir.join("inf.asc");
    write_ascii_grid(&inf, 50, 0, Some("inf"));
    refused(with(&inf), &["not finite"]);
    let word = dir.join("word.asc");
    write_ascii_grid(&word, 50, 0, Some("x12"));
    refused(with(&word), &["'x12'", "not a number"]);
    let short = dir.join("short.asc");
    std::fs::write(
        &short,
        "ncols 3\nnrows 3\nxllcorner 11\nyllcorner 49\ncellsize 0.01\n1 2 3 4\n",
    )
    .unwrap();
    refused(with(&short), &["4 heights for a 3 x 3 grid"]);
    // a layer elsewhere
    let far = small_layer(&scratch("far"), [12.5, 49.05], 0.002);
    refused(
        import_place(
            &[far],
            Some(&wgs84),
            None,
            &PlaceOptions::default(),
            &no_progress,
        ),
        &["does not overlap the elevation model", "wgs84.asc"],
    );
    // an SRTM tile of the wrong size or name
    let odd = dir.join("N49E011.hgt");
    std::fs::write(&odd, vec![0u8; 1000]).unwrap();
    refused(with(&odd), &["1000 bytes", "1201 x 1201"]);
    let unnamed = dir.join("tile.hgt");
    std::fs::write(&unnamed, vec![0u8; 1000]).unwrap();
    refused(with(&unnamed), &["south-west corner", "N49E011"]);
    refused(
        with(&dir.join("heights.xyz")),
        &["not an elevation model it reads"],
    );
    // options
    let with_options = |opts: PlaceOptions| {
        import_place(
            std::slice::from_ref(&layer),
            Some(&wgs84),
            None,
            &opts,
            &no_progress,
        )
    };
    refused(
        with_options(PlaceOptions {
            cell: Some(f64::NAN),
            ..Default::default()
        }),
        &["terrain cell", "positive"],
    );
    refused(
        with_options(PlaceOptions {
            origin: Some([0.0, 0.0]),
            ..Default::default()
        }),
        &["origin", "from the farthest point of the place"],
    );
    refused(
        with_options(PlaceOptions {
            origin: Some([f64::INFINITY, 0.0]),
            ..Default::default()
        }),
        &["origin"],
    );
}

#[test]
fn bad_inventories_are_refused() {
    let dir = scratch("bad-inventory");
    let with = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        import_place(
            &[],
            None,
            Some(&path),
            &PlaceOptions::default(),
            &no_progress,
        )
    };
    let place = with(
        "plain.csv",
        "x,y,species,size\n1,2,oak,0.3\n5,6,beech,\n7,,pine,1\n",
    )
    .unwrap();
    assert_eq!(place.trees.len(), 2);
    assert_eq!(place.report.trees_unreadable, 1);
    assert_eq!(place.trees[1].size, None);
    refused(
        with("nocols.csv", "a,b\n1,2\n"),
        &["no position columns", "a, b"],
    );
    refused(
        with("inf.csv", "x,y,species,size\n1,2,oak,inf\n"),
        &["line 2", "not finite"],
    );
    refused(
        with("dead.csv", "gx,gy,sp,dbh,status\n1,2,X,3,D\n"),
        &["an empty inventory", "1 rows not alive"],
    );
    refused(
        with("far.csv", "lon,lat,species\n556440,5394932,oak\n"),
        &["a CRS it cannot place"],
    );
    // lon/lat trees are projected into the frame centred on them
    let place = with(
        "lonlat.csv",
        "lon,lat,species\n11.0,49.0,oak\n11.001,49.0,oak\n",
    )
    .unwrap();
    assert!(place.frame.origin.is_some());
    let d = place.trees[0].position.distance(place.trees[1].position);
    assert!(
        (d - haversine([11.0, 49.0], [11.001, 49.0])).abs() < 0.3,
        "{d}"
    );
    assert_eq!(
        worldpaint_core::InventoryCoordinates::LonLat,
        InventoryCoordinates::LonLat
    );
}

#[test]
fn an_import_can_be_cancelled() {
    let dir = scratch("cancel");
    let layer = small_layer(&dir, [11.05, 49.05], 0.002);
    let stages = std::sync::Mutex::new(Vec::new());
    let result = import_place(
        &[layer],
        None,
        None,
        &PlaceOptions::default(),
        &|f, stage| {
            stages.lock().unwrap().push((f, stage));
            stage != "projecting"
        },
    );
    assert!(matches!(result, Err(Error::Cancelled)));
    let stages = stages.into_inner().unwrap();
    assert_eq!(stages.first().map(|s| s.1), Some("reading map layers"));
    assert!(
        stages.windows(2).all(|w| w[0].0 <= w[1].0),
        "progress never goes back"
    );
}

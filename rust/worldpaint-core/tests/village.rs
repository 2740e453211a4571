//! Villages as a layout team checks them (thesis ch. 3): every house reachable by road, no house on a road, in
//! the water or on another house, roads no steeper than the encyclopedia allows, village types that differ in
//! the way the thesis describes, and parcel figures beside the thesis's real village.

use worldpaint_core::{
    embed_roads, footprint_conflicts, generate_village, layout_statistics,
    mean_elevation_percentile, parcel_statistics, road_grades, unreachable_footprints,
    village_figures, village_terrain, DVec2, EmbeddedRoad, Encyclopedia, Environment, Error,
    Heightfield, Placement, Region, Road, RoadEmbeddingOptions, RoadParams, Scenario,
    ScenarioEvent, ScenarioPresets, Site, SitedBuilding, Village, VillageFigures, VillageRequest,
    VillageStage, UNPLACED_CANDIDATES,
};

const ENCYCLOPEDIA: &str = include_str!("../../../assets/villages/encyclopedia.json");
const SCENARIOS: &str = include_str!("../../../assets/villages/scenarios.json");

fn encyclopedia() -> Encyclopedia {
    Encyclopedia::from_json(ENCYCLOPEDIA).expect("the shipped encyclopedia is valid")
}

fn preset(name: &str) -> Scenario {
    let presets = ScenarioPresets::from_json(SCENARIOS).expect("the shipped presets are valid");
    presets.presets.get(name).cloned().expect("preset exists")
}

fn scenario(village_type: &str, houses: u32) -> Scenario {
    Scenario {
        events: vec![
            ScenarioEvent::ChangeVillageType {
                village_type: village_type.into(),
            },
            ScenarioEvent::Generate {
                count: 1,
                building: "church".into(),
            },
            ScenarioEvent::Generate {
                count: houses,
                building: "house".into(),
            },
        ],
    }
}

/// A request on `region` of `terrain` with no roads or connections given, 2 m skeleton cells and 1 m parcel cells.
fn request<'a>(
    terrain: &'a Heightfield,
    region: Region,
    environment: Environment,
    enc: &'a Encyclopedia,
    scenario: &'a Scenario,
    seed: u64,
) -> VillageRequest<'a> {
    VillageRequest {
        site: Site {
            terrain,
            region,
            environment,
            cell: 2.0,
        },
        connections: Vec::new(),
        existing_roads: Vec::new(),
        encyclopedia: enc,
        scenario,
        seed,
        parcel_cell: 1.0,
    }
}

fn village(terrain: &Heightfield, enc: &Encyclopedia, scenario: &Scenario, seed: u64) -> Village {
    let region = Region::Rect {
        min: DVec2::splat(20.0),
        max: DVec2::splat(980.0),
    };
    let sea = Environment {
        water_level: Some(0.0),
        ..Default::default()
    };
    generate_village(
        &request(terrain, region, sea, enc, scenario, seed),
        &|_, _| true,
    )
    .expect("the village grows")
}

fn roads(v: &Village) -> &[Road] {
    &v.roads
}

#[test]
fn a_fortified_village_keeps_every_house_reachable_off_the_roads_and_the_water() {
    let terrain = village_terrain(1000.0, 2.0, 3);
    let enc = encyclopedia();
    let v = village(&terrain, &enc, &preset("fortified_village"), 11);
    let land = v.land.as_ref().expect("land");
    let r = &v.report;
    println!("report: {r:?}");
    assert!(
        v.footprints.len() >= r.requested * 8 / 10,
        "{} houses for {} asked",
        v.footprints.len(),
        r.requested
    );
    assert_eq!(v.houses.len(), v.footprints.len());

    let width = enc.roads.width;
    let unreachable = unreachable_footprints(
        &v.footprints,
        roads(&v),
        &r.connections,
        0.5 * width + 12.0,
        0.5 * width,
    );
    assert_eq!(
        unreachable, 0,
        "houses without a road to a connection point"
    );

    let conflicts = footprint_conflicts(&v.footprints, roads(&v), width, land, 0.05);
    assert_eq!(conflicts.total(), 0, "{conflicts:?}");

    let grades = road_grades(roads(&v), &|p| land.height_at(p), 2.0);
    let steepest = grades.iter().map(|g| g.0).fold(0.0, f64::max);
    let length: f64 = grades.iter().map(|g| g.1).sum();
    let over: f64 = grades
        .iter()
        .filter(|g| g.0 > enc.roads.max_grade + 0.02)
        .map(|g| g.1)
        .sum();
    println!("roads {length:.0} m, steepest grade {steepest:.3}, {over:.0} m over the maximum");
    if r.roads_over_max_grade == 0 {
        assert!(
            over == 0.0,
            "{over:.1} m of road steeper than {} with none reported",
            enc.roads.max_grade
        );
    }

    let contours: Vec<Vec<DVec2>> = v.parcels.iter().map(|p| p.contour.clone()).collect();
    let stats = parcel_statistics(&contours, 0.5);
    println!(
        "parcels: {} with {:.3} neighbours and {:.3} contour edges on average (thesis real 2.812 / 4.068, model 2.873 / 4.29)",
        stats.parcels, stats.mean_neighbours, stats.mean_edges
    );
    // parcels share boundaries with their neighbours; the edge count is reported beside the thesis's figures
    assert_eq!(stats.parcels, v.parcels.len());
    assert!(stats.mean_neighbours > 1.0, "{stats:?}");
}

#[test]
fn village_types_differ_on_the_same_terrain() {
    let terrain = village_terrain(1000.0, 2.0, 5);
    let enc = encyclopedia();
    let mut rows = Vec::new();
    for (name, seed) in [("farming", 1), ("defensive", 1), ("fisherman", 1)] {
        let v = village(&terrain, &enc, &scenario(name, 30), seed);
        let land = v.land.as_ref().expect("land");
        let houses: Vec<DVec2> = v
            .seeds
            .iter()
            .filter(|s| s.building == "house")
            .map(|s| s.position)
            .collect();
        let stats = layout_statistics(&houses, roads(&v));
        let elevation = mean_elevation_percentile(land, &houses);
        // the coast: distance to the sea read on the land grid
        let water: f64 = houses
            .iter()
            .map(|p| {
                (0..land.grid().len())
                    .filter(|k| land.water()[*k])
                    .map(|k| land.grid().point_of(k).distance(*p))
                    .fold(f64::INFINITY, f64::min)
            })
            .sum::<f64>()
            / houses.len().max(1) as f64;
        println!(
            "{name}: {} houses, elevation percentile {elevation:.2}, nearest neighbour {:.1} m, water {water:.0} m",
            houses.len(),
            stats.mean_nearest_neighbour
        );
        // footprints are still lost in narrow parcels (see the parcels module): at least 60 % stand
        assert!(houses.len() >= 18, "{name}: {} houses", houses.len());
        rows.push((elevation, stats.mean_nearest_neighbour, water));
    }
    let (farming, defensive, fisherman) = (rows[0], rows[1], rows[2]);
    assert!(
        defensive.0 > farming.0 + 0.1,
        "fortified houses sit higher: {defensive:?} vs {farming:?}"
    );
    assert!(
        defensive.1 < farming.1,
        "fortified houses are more clustered: {defensive:?} vs {farming:?}"
    );
    assert!(
        fisherman.2 < 0.75 * farming.2,
        "fishermen live nearer the water: {fisherman:?} vs {farming:?}"
    );
}

#[test]
fn the_same_seed_gives_the_same_village_whatever_the_thread_count() {
    let terrain = village_terrain(600.0, 2.0, 2);
    let enc = encyclopedia();
    let s = scenario("farming", 12);
    let a = village(&terrain, &enc, &s, 4);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let b = pool.install(|| village(&terrain, &enc, &s, 4));
    assert_eq!(a.seeds, b.seeds);
    assert_eq!(a.roads, b.roads);
    assert_eq!(a.parcels, b.parcels);
    assert_eq!(a.houses, b.houses);
    let c = village(&terrain, &enc, &s, 5);
    assert_ne!(a.seeds, c.seeds);
}

#[test]
fn bad_scenarios_and_cancelling_give_clear_errors() {
    let terrain = village_terrain(400.0, 2.0, 2);
    let enc = encyclopedia();
    let bad = Scenario {
        events: vec![ScenarioEvent::Generate {
            count: 1,
            building: "house".into(),
        }],
    };
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(400.0),
    };
    let request = |scenario: &'static Scenario| {
        request(
            &terrain,
            region.clone(),
            Environment::default(),
            &enc,
            scenario,
            0,
        )
    };
    let bad: &'static Scenario = Box::leak(Box::new(bad));
    let err =
        generate_village(&request(bad), &|_, _| true).expect_err("generate before a village type");
    assert!(err.to_string().contains("before any village type"), "{err}");
    let unknown: &'static Scenario = Box::leak(Box::new(scenario("nomads", 3)));
    let err = generate_village(&request(unknown), &|_, _| true).expect_err("unknown village type");
    assert!(err.to_string().contains("nomads"), "{err}");
    let empty: &'static Scenario = Box::leak(Box::new(Scenario::default()));
    let err = generate_village(&request(empty), &|_, _| true).expect_err("no building asked");
    assert!(err.to_string().contains("generates no building"), "{err}");
    let mut palace = scenario("farming", 3);
    palace.events.push(ScenarioEvent::Generate {
        count: 1,
        building: "palace".into(),
    });
    let palace: &'static Scenario = Box::leak(Box::new(palace));
    let err = generate_village(&request(palace), &|_, _| true).expect_err("unknown building type");
    assert!(
        err.to_string().contains(
            "event 4: unknown building type 'palace' (the encyclopedia has castle, church"
        ),
        "{err}"
    );
    let fine: &'static Scenario = Box::leak(Box::new(scenario("farming", 3)));
    let err = generate_village(&request(fine), &|_, f| f < 0.5).expect_err("cancelled");
    assert!(matches!(err, Error::Cancelled));
    // each stage hears the cancel while it works, not only between stages: the land conquest of the parcels
    // (their first 20 % is the road conquest), the footprints (their last 20 %) and the houses
    for (name, stop_at) in [
        ("land conquest", (VillageStage::Parcels, 0.3)),
        ("footprints", (VillageStage::Parcels, 0.85)),
        ("houses", (VillageStage::Houses, 0.01)),
    ] {
        let seen = std::sync::Mutex::new(Vec::new());
        let cancel = |stage, f| {
            if let Ok(mut seen) = seen.lock() {
                seen.push((stage, f));
            }
            !(stage == stop_at.0 && f >= stop_at.1)
        };
        let err = generate_village(&request(fine), &cancel).expect_err(name);
        assert!(matches!(err, Error::Cancelled), "{name}: {err}");
        let seen = seen.into_inner().unwrap_or_default();
        assert!(
            seen.iter()
                .any(|&(s, f)| s == stop_at.0 && f >= stop_at.1 && f < 1.0),
            "{name}: no report within the stage: {seen:?}"
        );
    }
}

#[test]
fn a_request_for_more_houses_than_the_land_holds_stops_when_it_is_full() {
    let terrain = village_terrain(160.0, 2.0, 4);
    let enc = encyclopedia();
    let grow = |houses: u32| {
        let scenario = scenario("farming", houses);
        let region = Region::Rect {
            min: DVec2::splat(5.0),
            max: DVec2::splat(155.0),
        };
        let request = request(&terrain, region, Environment::default(), &enc, &scenario, 3);
        generate_village(&request, &|_, _| true)
    };
    let full = grow(400).expect("a full village");
    let more = grow(4000).expect("the same full village");
    assert!(
        full.report.unplaced.len() > 32,
        "the land should fill up: {:?}",
        full.report
    );
    let positions = |v: &Village| v.seeds.iter().map(|s| s.position).collect::<Vec<_>>();
    assert_eq!(positions(&full), positions(&more));
    // the report says why: the houses found no place near a road that was not next to another building
    let causes = full
        .report
        .unplaced_causes
        .get("house")
        .expect("why the houses were not placed");
    let share = |k: usize| causes[k] as f64 / UNPLACED_CANDIDATES as f64;
    println!(
        "no place for the houses: sociability {:.0} %, accessibility {:.0} %, slope {:.0} %, off the land {:.0} %",
        100.0 * share(0),
        100.0 * share(2),
        100.0 * share(3),
        100.0 * share(7)
    );
    assert!(share(0) + share(2) > 0.9, "{causes:?}");
    assert!(causes.iter().all(|&n| n <= UNPLACED_CANDIDATES));
    // every house asked for beyond the full village is reported, none is built
    let not_built = |v: &Village| v.report.unplaced.len() + v.report.unreachable;
    assert_eq!(not_built(&more), not_built(&full) + 3600);
    match grow(1_000_000) {
        Err(Error::TooLarge { unit, .. }) => assert_eq!(unit, "buildings"),
        other => panic!(
            "a million houses accepted: {:?}",
            other.map(|v| v.seeds.len())
        ),
    }
}

#[test]
fn a_village_over_the_whole_terrain_keeps_its_roads_on_it_and_they_embed() {
    let terrain = village_terrain(200.0, 2.0, 6);
    let enc = encyclopedia();
    let scenario = scenario("farming", 10);
    let (lo, hi) = terrain.bbox();
    for seed in 0..6 {
        let whole = Region::Rect { min: lo, max: hi };
        let request = request(
            &terrain,
            whole,
            Environment::default(),
            &enc,
            &scenario,
            seed,
        );
        let v = generate_village(&request, &|_, _| true).expect("the village grows");
        let on_terrain = |p: &DVec2| terrain.contains(*p);
        assert!(
            v.roads.iter().all(|r| r.points.iter().all(on_terrain)),
            "seed {seed}"
        );
        let roads: Vec<EmbeddedRoad> = v
            .roads
            .iter()
            .filter(|r| r.points.len() >= 2)
            .map(|r| EmbeddedRoad {
                centreline: r.points.clone(),
                heights: None,
                width: enc.roads.width,
                bank_width: 2.0,
            })
            .collect();
        if let Err(e) = embed_roads(&terrain, &roads, &RoadEmbeddingOptions::default()) {
            panic!("seed {seed}: {e}");
        }
    }
}

#[test]
fn a_village_on_land_all_under_water_is_refused_with_a_message() {
    let terrain = village_terrain(200.0, 2.0, 2);
    let enc = encyclopedia();
    let scenario = scenario("farming", 5);
    let (lo, hi) = terrain.bbox();
    let flooded = Environment {
        water_level: Some(1e4),
        ..Default::default()
    };
    let request = request(
        &terrain,
        Region::Rect { min: lo, max: hi },
        flooded,
        &enc,
        &scenario,
        1,
    );
    let refused = std::panic::catch_unwind(|| generate_village(&request, &|_, _| true))
        .expect("no panic on a drowned region");
    match refused {
        Err(e) => assert!(!e.to_string().is_empty()),
        Ok(v) => assert!(
            v.seeds.is_empty(),
            "houses built under water: {}",
            v.seeds.len()
        ),
    }
}

#[test]
fn a_village_type_may_set_its_own_road_costs_but_not_its_width() {
    let enc = encyclopedia();
    let highland = enc.road_params("highland");
    assert_eq!(highland.width, enc.roads.width);
    assert!(highland.cycle_max_length > enc.roads.cycle_max_length);
    assert_eq!(enc.road_params("defensive"), enc.roads);
    // farming lays streets past its new roads' buildings, with the shared costs
    let farming = enc.road_params("farming");
    assert!(farming.street_length > 0.0 && enc.roads.street_length == 0.0);
    assert_eq!(
        RoadParams {
            street_length: 0.0,
            ..farming
        },
        enc.roads
    );
    // a steep village type may take a finer move mask; it goes through the file, and its range is checked
    let mut steep = enc.clone();
    if let Some(v) = steep.village_types.get_mut("highland") {
        v.roads.mask_radius = Some(4);
    }
    let steep = Encyclopedia::from_json(&steep.to_json()).expect("a mask of radius 4");
    assert_eq!(steep.road_params("highland").mask_radius, 4);
    assert_eq!(
        steep.road_params("farming").mask_radius,
        enc.roads.mask_radius
    );
    let mut bad = enc.clone();
    if let Some(v) = bad.village_types.get_mut("highland") {
        v.roads.mask_radius = Some(0);
    }
    let err = Encyclopedia::from_json(&bad.to_json()).expect_err("a mask of radius 0");
    assert!(
        err.to_string()
            .contains("village_types.highland.roads.mask_radius"),
        "{err}"
    );
    let mut bad = enc.clone();
    if let Some(v) = bad.village_types.get_mut("farming") {
        v.roads.max_grade = Some(-0.1);
    }
    let err = Encyclopedia::from_json(&bad.to_json()).expect_err("a negative grade");
    assert!(
        err.to_string().contains("village_types.farming.roads"),
        "{err}"
    );
    let widened = ENCYCLOPEDIA.replacen(
        "\"roads\": {\n    \"reuse_weight\"",
        "\"roads\": {\n    \"width\": 9.0,\n    \"reuse_weight\"",
        1,
    );
    assert_ne!(widened, ENCYCLOPEDIA);
    assert!(
        Encyclopedia::from_json(&widened).is_err(),
        "a village type's road width"
    );
}

/// A farming village of 40 houses on 1 km of hills (seed 4), grown as shipped and with `set` applied to the
/// farming type's houses, each with its figures over the square. The altered village's footprints keep clear of
/// the roads, the water and each other, and it stands about as many houses.
fn farming_as_shipped_and(set: impl FnOnce(&mut Placement)) -> [(Village, VillageFigures); 2] {
    let terrain = village_terrain(1000.0, 2.0, 5);
    let region = Region::Rect {
        min: DVec2::splat(20.0),
        max: DVec2::splat(980.0),
    };
    let mut enc = encyclopedia();
    let grown = |enc: &Encyclopedia| {
        let v = village(&terrain, enc, &scenario("farming", 40), 4);
        let sited: Vec<SitedBuilding> = v
            .footprints
            .iter()
            .map(SitedBuilding::of_footprint)
            .collect();
        let figures = village_figures(&sited, &v.roads, &region);
        (v, figures)
    };
    let shipped = grown(&enc);
    if let Some(p) = enc
        .village_types
        .get_mut("farming")
        .and_then(|t| t.buildings.get_mut("house"))
    {
        set(p);
    }
    let altered = grown(&enc);
    let (n, m) = (shipped.1.layout.houses, altered.1.layout.houses);
    assert!(m + 3 >= n, "{m} houses altered, {n} shipped");
    let land = altered.0.land.as_ref().expect("land");
    let conflicts = footprint_conflicts(
        &altered.0.footprints,
        &altered.0.roads,
        enc.roads.width,
        land,
        0.05,
    );
    assert_eq!(conflicts.total(), 0, "{conflicts:?}");
    [shipped, altered]
}

#[test]
fn a_village_type_with_skewed_footprints_stands_its_houses_at_every_angle_to_the_road() {
    let [(_, straight), (_, skewed)] = farming_as_shipped_and(|p| p.skew_share = 0.6);
    let between = |f: &VillageFigures| {
        let h = &f.orientation_to_road;
        h[1..h.len() - 1].iter().sum::<f64>()
    };
    let (straight_between, skewed_between) = (between(&straight), between(&skewed));
    println!(
        "houses between along and across their road: {:.0} % of {} straight, {:.0} % of {} with 60 % skewed",
        100.0 * straight_between,
        straight.layout.houses,
        100.0 * skewed_between,
        skewed.layout.houses
    );
    // 60 % drawn evenly over ±90° put about 40 % in the four middle bins of six (a few stand straight when the
    // skewed footprint finds no room), as many nearer across the road as nearer along it
    assert!(straight_between < 0.15, "{straight_between}");
    assert!((0.25..0.55).contains(&skewed_between), "{skewed_between}");
    let h = &skewed.orientation_to_road;
    let nearer_across = h[3] + h[4];
    assert!(
        (0.3..0.7).contains(&(nearer_across / skewed_between)),
        "{:.0} % of the skewed at 45–75°",
        100.0 * nearer_across / skewed_between
    );
}

#[test]
fn a_village_type_that_clusters_its_houses_stands_them_in_pairs_and_groups() {
    let [(_, scattered), (_, clustered)] = farming_as_shipped_and(|p| p.cluster_share = 0.7);
    let (scattered, clustered) = (scattered.layout, clustered.layout);
    println!(
        "houses with another within 20 m: {:.0} % of {} scattered, {:.0} % of {} with 70 % seeded beside another; \
         nearest neighbour {:.1} m and {:.1} m",
        100.0 * scattered.share_within_20m,
        scattered.houses,
        100.0 * clustered.share_within_20m,
        clustered.houses,
        scattered.mean_nearest_neighbour,
        clustered.mean_nearest_neighbour,
    );
    assert!(
        clustered.share_within_20m > scattered.share_within_20m + 0.2,
        "{} against {}",
        clustered.share_within_20m,
        scattered.share_within_20m
    );
    assert!(clustered.mean_nearest_neighbour < 0.85 * scattered.mean_nearest_neighbour);
}

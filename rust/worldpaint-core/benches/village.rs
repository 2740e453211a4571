//! Benchmark of the village pipeline against the requirement "a village of 100 buildings with roads, parcels and
//! house meshes on a 1 km² terrain (grid cell 1 m) in at most 3 s", beside a baseline measured in the same run:
//!
//! * `village/100_buildings`: the whole pipeline (skeleton with roads, parcels and footprints, house meshes) for
//!   a scenario of 1 church, 70 houses, 25 farms and 4 villas on `exemplar::village_terrain` (1000 m, 1 m cells);
//! * baseline `village/land_and_interest_maps`: sampling the land and its static interest maps only (what any
//!   village on this terrain costs before the first building).
//!
//! The summary prints both medians, their ratio, the time per stage of one run, and the ratio to the thesis's
//! Table 3.1 (4–7 minutes for the skeleton and 7–13 minutes for the parcels of its villages).
//!
//! `cargo bench -p worldpaint-core --bench village`

mod timing;

use criterion::Criterion;
use std::hint::black_box;
use std::time::{Duration, Instant};
use worldpaint_core::{
    generate_village, village_terrain, DVec2, Encyclopedia, Environment, Land, Region, Scenario,
    ScenarioEvent, Site, StaticInterestMaps, VillageRequest,
};

const ENCYCLOPEDIA: &str = include_str!("../../../assets/villages/encyclopedia.json");
const BUDGET_S: f64 = 3.0;

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let mut g = timing::flat_group(&mut c, "village", 10, Duration::from_secs(30));
    let terrain = village_terrain(1000.0, 1.0, 3);
    let enc = match Encyclopedia::from_json(ENCYCLOPEDIA) {
        Ok(e) => e,
        Err(e) => panic!("the shipped encyclopedia: {e}"),
    };
    let generate_event = |count: u32, building: &str| ScenarioEvent::Generate {
        count,
        building: building.into(),
    };
    let scenario = Scenario {
        events: vec![
            ScenarioEvent::ChangeVillageType {
                village_type: "farming".into(),
            },
            generate_event(1, "church"),
            generate_event(70, "house"),
            generate_event(25, "farm"),
            generate_event(4, "villa"),
        ],
    };
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(1000.0),
    };
    let environment = Environment {
        water_level: Some(0.0),
        ..Default::default()
    };
    let request = VillageRequest {
        site: Site {
            terrain: &terrain,
            region: region.clone(),
            environment: environment.clone(),
            cell: 2.0,
        },
        connections: Vec::new(),
        existing_roads: Vec::new(),
        encyclopedia: &enc,
        scenario: &scenario,
        seed: 1,
        parcel_cell: 1.0,
    };
    let one = match generate_village(&request, &|_, _| true) {
        Ok(v) => v,
        Err(e) => panic!("the benchmark village: {e}"),
    };
    let r = &one.report;
    println!(
        "{} buildings asked, {} houses built, {} roads; skeleton {:.2} s, parcels and footprints {:.2} s, houses {:.2} s",
        r.requested,
        one.houses.len(),
        one.roads.len(),
        r.seconds[0],
        r.seconds[1],
        r.seconds[2]
    );

    let full_s = timing::median(&mut g, "100_buildings", || {
        let t0 = Instant::now();
        black_box(generate_village(&request, &|_, _| true).ok());
        t0.elapsed()
    });
    let radii: Vec<f64> = vec![150.0, 200.0];
    let base_s = timing::median(&mut g, "land_and_interest_maps", || {
        let t0 = Instant::now();
        if let Ok(land) = Land::new(&terrain, &region, &environment, 2.0) {
            black_box(StaticInterestMaps::new(&land, &radii));
        }
        t0.elapsed()
    });
    g.finish();
    c.final_summary();

    println!();
    println!("== village summary ==");
    println!(
        "100 buildings end to end: {:.2} s; land and interest maps alone: {:.3} s; full / baseline = {:.1}",
        full_s,
        base_s,
        full_s / base_s
    );
    println!(
        "requirement ≤ {BUDGET_S} s: {} ({:.2} of the budget); thesis Table 3.1 skeleton + parcels 11–24 min: {:.0}–{:.0}× faster",
        if full_s <= BUDGET_S { "met" } else { "NOT met" },
        full_s / BUDGET_S,
        11.0 * 60.0 / full_s,
        24.0 * 60.0 / full_s
    );
}

//! Benchmark of villages grown to towns: a farming scenario of 100, 400 and 1,000 buildings over 1, 2 × 2 and
//! 3 × 3 km of smooth hills (`exemplar::demo_terrain`, 2 m cells), each grown once, with what was built, why the rest
//! was not, the seconds of each stage and the time per building asked (issue 44: at least 90 % built, 1,000 in at
//! most 5 s, 100 in at most 0.5 s, the time per building about constant).
//!
//! The last column is a digest of the town (its roads, parcels and footprints, bit for bit): a change that should
//! not change what is grown keeps it.
//!
//! `cargo bench -p worldpaint-core --bench town [-- 100 400]` (the sizes to grow; default all three)

use std::time::Instant;
use worldpaint_core::{
    demo_terrain, generate_village, DVec2, Encyclopedia, Environment, InterestCriterion, Region,
    Scenario, ScenarioEvent, Site, Village, VillageRequest, UNPLACED_CANDIDATES,
};

const ENCYCLOPEDIA: &str = include_str!("../../../assets/villages/encyclopedia.json");

/// The scenario of `n` buildings: a church, then houses, farms and villas as 70 : 25 : 4.
fn farming(n: u32) -> Scenario {
    let generate = |count: u32, building: &str| ScenarioEvent::Generate {
        count,
        building: building.into(),
    };
    let farms = n * 25 / 100;
    let villas = n * 4 / 100;
    Scenario {
        events: vec![
            ScenarioEvent::ChangeVillageType {
                village_type: "farming".into(),
            },
            generate(1, "church"),
            generate(n - 1 - farms - villas, "house"),
            generate(farms, "farm"),
            generate(villas, "villa"),
        ],
    }
}

/// FNV-1a over the bits of every road, parcel and footprint point, in order.
fn digest(village: &Village) -> u64 {
    let points = village
        .roads
        .iter()
        .flat_map(|r| r.points.iter())
        .chain(village.parcels.iter().flat_map(|p| p.contour.iter()))
        .chain(village.footprints.iter().flat_map(|f| f.corners.iter()));
    points
        .flat_map(|p| [p.x.to_bits(), p.y.to_bits()])
        .fold(0xcbf2_9ce4_8422_2325, |h, v| {
            (h ^ v).wrapping_mul(0x100_0000_01b3)
        })
}

fn main() {
    let sizes: Vec<u32> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let sizes = if sizes.is_empty() {
        vec![100, 400, 1000]
    } else {
        sizes
    };
    let enc = match Encyclopedia::from_json(ENCYCLOPEDIA) {
        Ok(e) => e,
        Err(e) => panic!("the shipped encyclopedia: {e}"),
    };
    println!("== town summary ==");
    println!(
        "buildings | side km | built | skeleton s | parcels s | houses s | total s | ms / building | not built | digest"
    );
    for n in sizes {
        let side = 1000.0 * (n as f64 / 100.0).sqrt().round().max(1.0);
        let terrain = demo_terrain(side, 2.0, 1);
        let scenario = farming(n);
        let request = VillageRequest {
            site: Site {
                terrain: &terrain,
                region: Region::Rect {
                    min: DVec2::ZERO,
                    max: DVec2::splat(side),
                },
                environment: Environment::default(),
                cell: 2.0,
            },
            connections: Vec::new(),
            existing_roads: Vec::new(),
            encyclopedia: &enc,
            scenario: &scenario,
            seed: 1,
            parcel_cell: 1.0,
        };
        let t0 = Instant::now();
        let village = match generate_village(&request, &|_, _| true) {
            Ok(v) => v,
            Err(e) => panic!("the town of {n}: {e}"),
        };
        let total = t0.elapsed().as_secs_f64();
        let r = &village.report;
        println!(
            "{n} | {:.0} | {} | {:.2} | {:.2} | {:.2} | {total:.2} | {:.1} | unplaced {}, unreachable {}, without access {}, without footprint {} | {:016x}",
            side / 1000.0,
            village.footprints.len(),
            r.seconds[0],
            r.seconds[1],
            r.seconds[2],
            1000.0 * total / n as f64,
            r.unplaced.len(),
            r.unreachable,
            r.without_access,
            r.without_footprint,
            digest(&village)
        );
        for (building, counts) in &r.unplaced_causes {
            let shares: Vec<String> = InterestCriterion::ALL
                .iter()
                .map(|c| c.name())
                .chain(["off the land", "no interest"])
                .zip(counts)
                .filter(|(_, n)| **n > 0)
                .map(|(c, n)| {
                    format!(
                        "{c} {:.0} %",
                        100.0 * *n as f64 / UNPLACED_CANDIDATES as f64
                    )
                })
                .collect();
            println!("    no place for the {building}: {}", shares.join(", "));
        }
    }
}

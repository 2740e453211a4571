//! Real villages: a color is learned from a 1 km square of the OpenStreetMap roads and buildings north of
//! Bayreuth, centred on the densest village (Neudrossenfeld). It is painted with one seed into an empty square
//! three times the side (nine times the area) and measured against the acceptance for graphs (see
//! `support/villages.rs`). Prints the report (`--nocapture`) and checks:
//! * the network fills the square;
//! * the histograms of edge lengths, of angles at nodes and of turning angles along paths are within total
//!   variation 0.15 of the exemplar's;
//! * no angle at a node is below the learned smallest one;
//! * no two segments cross away from a node (counted on the paths as drawn: a planar graph would have split every
//!   crossing into a node);
//! * connected components per unit area are within 1.5× of the exemplar's;
//! * houses come at the exemplar's density within 25%, with their distance-to-road histogram within total
//!   variation 0.15 of the learned one.
//!
//! Spread seen over seeds 1, 2 and 5: edge-length TV 0.036–0.039, angle TV 0.011–0.012, smallest angle
//! 37.67–37.86° against the learned 37.65°, components ratio 1.04–1.26, house density ratio 1.11–1.12, house
//! distance TV 0.076–0.093, no crossing. (Before the gap between arcs had a floor, seeds 1–10 gave 287–325
//! crossings and TVs of 0.07–0.09 on the planar graph, where every crossing is a node.)
//!
//! **Fragile: the components ratio.** A 1 km square of real roads holds only 2–4 components (road pieces cut off
//! by the square's border count separately), so the learned figure is a small count. Moving the square by 50 m
//! (seed 1) gave ratios of 0.41–1.39, failing 1.5× at three of nine placements. All three are among the five
//! where a 247 m straight segment enters the square. That segment raises the longest learned edge from 147 m
//! and, with it, the crossings (476–670) and both TVs (up to 0.132 and 0.138). The exemplar here is the one the
//! rule picks, not one picked for the result.

mod common;
use common::village_painting_report;

use common::checks::{assert_all_hold, Check};

/// A typical draw.
const SEED: u64 = 1;

#[test]
#[ignore = "needs shared/data/real (make test-rust runs it where present)"]
fn north_bayreuth_village_over_nine_times_the_area() {
    let report = match village_painting_report::run(SEED) {
        Ok(r) => r,
        Err(e) => panic!("real-village report failed: {e}"),
    };
    println!("{}", report.table());
    let (real, painted) = (&report.real.network, &report.synthesized.network);
    let houses = &report.synthesized.houses;
    let area_ratio = report.synthesized.area_km2 / report.real.area_km2;
    let edges_ratio = painted.drawn.edges as f64 / (area_ratio * real.drawn.edges as f64);
    let learned_min = report.learned.min_angle;
    let components = report.components_ratio();
    let checks = [
        Check {
            what: "drawn edges per km² vs the exemplar's".into(),
            measured: format!("{edges_ratio:.3}"),
            bound: "0.5 ..= 2".into(),
            holds: (0.5..=2.0).contains(&edges_ratio),
        },
        Check {
            what: "edge-length TV".into(),
            measured: format!("{:.3}", painted.planar.length_tv),
            bound: "<= 0.15".into(),
            holds: painted.planar.length_tv <= 0.15,
        },
        Check {
            what: "angle-at-node TV".into(),
            measured: format!("{:.3}", painted.planar.angle_tv),
            bound: "<= 0.15".into(),
            holds: painted.planar.angle_tv <= 0.15,
        },
        Check {
            what: "turning-angle TV".into(),
            measured: format!("{:.3}", painted.planar.turn_tv),
            bound: "<= 0.15".into(),
            holds: painted.planar.turn_tv <= 0.15,
        },
        Check {
            what: "smallest angle at a node".into(),
            measured: format!("{:.2}°", painted.drawn.min_angle.to_degrees()),
            bound: format!(">= learned {:.2}°", learned_min.to_degrees()),
            holds: painted.drawn.min_angle >= learned_min - 1e-6,
        },
        Check {
            what: "segments crossing away from nodes".into(),
            measured: format!("{} ({} edges)", painted.crossings, painted.drawn.edges),
            bound: "0".into(),
            holds: painted.crossings == 0,
        },
        Check {
            what: "components per km² vs learned".into(),
            measured: format!("{components:.3}"),
            bound: "1/1.5 ..= 1.5".into(),
            holds: (1.0 / 1.5..=1.5).contains(&components),
        },
        Check {
            what: "house density vs the exemplar's".into(),
            measured: format!("{:.3}", houses.density_ratio),
            bound: "0.75 ..= 1.25".into(),
            holds: (houses.density_ratio - 1.0).abs() <= 0.25,
        },
        Check {
            what: "house distance-to-road TV".into(),
            measured: format!("{:.3}", houses.distance_tv),
            bound: "<= 0.15".into(),
            holds: houses.distance_tv <= 0.15,
        },
    ];
    println!(
        "{:<38} {:>20} {:>20}  result",
        "acceptance check", "measured", "bound"
    );
    for c in &checks {
        let result = if c.holds { "holds" } else { "FAILS" };
        println!(
            "{:<38} {:>20} {:>20}  {result}",
            c.what, c.measured, c.bound
        );
    }
    assert_all_hold(&checks);
}

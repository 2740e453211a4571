//! Checks of the road search against a plain Dijkstra over the states, and of the network costs kept up to
//! date against a full computation (thesis 3.2.4).

use super::cycles::Ellipse;
use super::search::{Ctx, Query, Search, BUILDING, GOAL};
use super::*;

pub(super) fn grid(nx: usize, ny: usize) -> Grid {
    Grid {
        origin: DVec2::ZERO,
        cell: 2.0,
        nx,
        ny,
    }
}

#[test]
fn segment_cells_follow_the_segment() {
    let g = grid(10, 10);
    let cells = segment_cells(&g, DVec2::new(0.0, 0.0), DVec2::new(8.0, 0.0));
    assert_eq!(cells, vec![0, 1, 2, 3, 4]);
    assert!(segment_cells(&g, DVec2::new(-50.0, -50.0), DVec2::new(-40.0, -50.0)).is_empty());
}

/// Bumpy random land with water, holes in the region, and a steep band.
fn random_land(rng: &mut rand_chacha::ChaCha8Rng, n: usize) -> Land {
    use rand::Rng;
    let g = grid(n, n);
    let bumps: Vec<(DVec2, f64, f64)> = (0..6)
        .map(|_| {
            (
                DVec2::new(
                    rng.random_range(0.0..2.0 * n as f64),
                    rng.random_range(0.0..2.0 * n as f64),
                ),
                rng.random_range(-15.0..15.0),
                rng.random_range(8.0..30.0),
            )
        })
        .collect();
    let height = (0..g.len())
        .map(|k| {
            let p = g.point_of(k);
            bumps
                .iter()
                .map(|&(c, a, r)| a * (-(p - c).length_squared() / (r * r)).exp())
                .sum::<f64>() as f32
        })
        .collect();
    let inside = (0..g.len())
        .map(|_| rng.random_range(0.0..1.0) > 0.04)
        .collect();
    let lake = DVec2::new(
        rng.random_range(0.0..2.0 * n as f64),
        rng.random_range(0.0..2.0 * n as f64),
    );
    let water = (0..g.len())
        .map(|k| g.point_of(k).distance(lake) < 15.0)
        .collect();
    Land::from_maps(
        g,
        height,
        [
            inside,
            water,
            (0..g.len())
                .map(|_| rng.random_range(0.0..1.0) < 0.01)
                .collect(),
            vec![false; g.len()],
        ],
    )
    .expect("land")
}

/// Road parameters drawn at random, the mask radius cycling with the case.
fn random_road_params(rng: &mut rand_chacha::ChaCha8Rng, case: u32) -> RoadParams {
    use rand::Rng;
    RoadParams {
        width: 4.0,
        distance_weight: rng.random_range(0.5..2.0),
        slope_weight: rng.random_range(0.0..4.0),
        max_grade: rng.random_range(0.1..0.3),
        curvature_weight: rng.random_range(0.0..4.0),
        water_weight: rng.random_range(0.0..30.0),
        building_cost: rng.random_range(0.0..200.0),
        reuse_weight: 0.1,
        mask_radius: 1 + case % 3,
        cycle_angle_degrees: 30.0,
        cycle_max_length: 100.0,
        cycle_min_separation: 20.0,
        street_length: 0.0,
    }
}

/// Searches `query` with the bound alone, the field at once, the field after a few states and in a corridor, and
/// checks each against Dijkstra's cost (a corridor may only cost more). Returns how many found a path.
fn compare_with_dijkstra(search: &mut Search, query: &Query, case: u32) -> usize {
    let reference = search.dijkstra(query);
    let mut compared = 0;
    for (budget, state_budget) in [(usize::MAX, 0), (0, usize::MAX), (40, usize::MAX), (0, 20)] {
        search.budget = budget;
        search.state_budget = state_budget;
        let got = search.find(query);
        let steep = query.steep;
        match (reference, &got) {
            (None, None) => {}
            (Some(a), Some((path, b))) => {
                let exact = state_budget > 20;
                assert!(
                    (a - b).abs() <= 1e-3 * a.max(1.0) || !exact && *b >= a,
                    "case {case} steep {steep} budget {budget}: {a} vs {b}"
                );
                assert_eq!(path[0], query.target);
                let last = *path.last().unwrap();
                assert!(query.sources.iter().any(|&(r, _)| r == last));
                compared += 1;
            }
            _ => panic!(
                "case {case} steep {steep} budget {budget}: {reference:?} vs {:?}",
                got.map(|g| g.1)
            ),
        }
    }
    compared
}

#[test]
fn the_searches_find_the_cheapest_path() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut compared = 0;
    for case in 0..24u32 {
        let n = 40;
        let land = random_land(&mut rng, n);
        let params = random_road_params(&mut rng, case);
        let mut search = Search::new(&land, &params).unwrap();
        search.flags = (0..land.grid().len())
            .map(|_| {
                if rng.random_range(0.0..1.0) < 0.05 {
                    BUILDING
                } else {
                    0
                }
            })
            .collect();
        // many sources in some cases (the tiled bound), a few in the others
        let count = if case % 2 == 0 {
            rng.random_range(1..6)
        } else {
            rng.random_range(40..80)
        };
        let sources: Vec<(usize, f64)> = (0..count)
            .map(|_| {
                (
                    rng.random_range(0..land.grid().len()),
                    rng.random_range(0.0..40.0),
                )
            })
            .collect();
        for &(r, _) in &sources {
            search.flags[r] |= GOAL;
        }
        let target = rng.random_range(0..land.grid().len());
        if search.flags[target] & GOAL != 0 {
            continue;
        }
        let (a, b) = (
            land.grid().point_of(target),
            land.grid().point_of(sources[0].0),
        );
        let ellipse = (case % 4 == 3).then(|| Ellipse {
            a,
            b,
            length: 1.3 * a.distance(b) + 10.0,
        });
        let ctx = Ctx {
            land: &land,
            params: &params,
        };
        for steep in [false, true] {
            let query = Query {
                ctx: &ctx,
                sources: &sources,
                target,
                steep,
                ellipse,
            };
            compared += compare_with_dijkstra(&mut search, &query, case);
        }
    }
    assert!(compared >= 60, "{compared}");
}

#[test]
fn network_costs_kept_up_to_date_match_a_full_computation() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let land = random_land(&mut rng, 80);
    let params = RoadParams {
        width: 4.0,
        distance_weight: 1.0,
        slope_weight: 1.0,
        max_grade: 0.3,
        curvature_weight: 1.0,
        water_weight: 5.0,
        building_cost: 100.0,
        reuse_weight: 0.2,
        mask_radius: 2,
        cycle_angle_degrees: 40.0,
        cycle_max_length: 80.0,
        cycle_min_separation: 10.0,
        street_length: 0.0,
    };
    let free = vec![false; land.grid().len()];
    let mut net = RoadNetwork::new(
        &land,
        &[DVec2::new(0.0, 80.0), DVec2::new(158.0, 100.0)],
        &[],
    )
    .unwrap();
    let mut cycles = 0;
    for _ in 0..25 {
        let b = DVec2::new(rng.random_range(0.0..158.0), rng.random_range(0.0..158.0));
        cycles += net.connect(&land, &params, &free, b, 0.0).unwrap().cycle as usize;
        let mut search = net.search.take().unwrap();
        net.exit_costs(&mut search, &land);
        let kept = search.exit.clone();
        search.exit_nodes = 0;
        net.exit_costs(&mut search, &land);
        for &r in &net.road_nodes {
            let (a, b) = (kept[r as usize], search.exit[r as usize]);
            assert!(a == b || (a - b).abs() < 1e-9 * a.max(1.0), "{a} vs {b}");
        }
        net.search = Some(search);
    }
    assert!(cycles > 0);
}

/// A road across 2.2 km of hills, laid coarse to fine, costs little more than the cheapest road, and reaches
/// the building from the source.
#[test]
fn a_long_road_laid_coarse_to_fine_costs_little_more_than_the_cheapest() {
    let g = grid(800, 800);
    let height = (0..g.len())
        .map(|k| {
            let p = g.point_of(k);
            (25.0 * (p.x / 160.0).sin() * (p.y / 210.0).cos()
                + 6.0 * ((p.x + 2.0 * p.y) / 75.0).sin()) as f32
        })
        .collect();
    let land = Land::from_maps(
        g,
        height,
        [
            vec![true; g.len()],
            vec![false; g.len()],
            vec![false; g.len()],
            vec![false; g.len()],
        ],
    )
    .unwrap();
    let params = RoadParams {
        width: 4.0,
        distance_weight: 1.0,
        slope_weight: 2.0,
        max_grade: 0.15,
        curvature_weight: 1.0,
        water_weight: 0.0,
        building_cost: 0.0,
        reuse_weight: 0.1,
        mask_radius: 2,
        cycle_angle_degrees: 30.0,
        cycle_max_length: 0.0,
        cycle_min_separation: 20.0,
        street_length: 0.0,
    };
    let (source, target) = (g.index(10, 20), g.index(790, 785));
    let ctx = Ctx {
        land: &land,
        params: &params,
    };
    let sources = [(source, 0.0)];
    let query = Query {
        ctx: &ctx,
        sources: &sources,
        target,
        steep: false,
        ellipse: None,
    };
    let cost = |coarse_first: bool| {
        let mut search = Search::new(&land, &params).unwrap();
        search.flags = vec![0; g.len()];
        search.flags[source] |= GOAL;
        search.coarse_first = coarse_first;
        let (path, cost) = search.find(&query).unwrap();
        assert_eq!((path[0], path[path.len() - 1]), (target, source));
        // the moves whose cost the search needed: where it looked
        (cost, search.costs.iter().filter(|c| **c != 0.0).count())
    };
    let ((coarse, looked_coarse), (cheapest, looked)) = (cost(true), cost(false));
    assert!(
        coarse >= cheapest - 1e-6 * cheapest && coarse <= 1.03 * cheapest,
        "coarse to fine {coarse}, the cheapest {cheapest}"
    );
    assert!(
        looked_coarse * 4 < looked,
        "coarse to fine costed {looked_coarse} moves, the exact search {looked}"
    );
}

//! Aggregation-based building seeding (thesis 3.2.3, Algorithm 1):
//!
//! > repeat p ← random location; p ← I(p, B, V); r ← uniform probability in [0, 1] until r < p
//!
//! Candidates are drawn in batches from the seeded generator and their interests evaluated in parallel; the
//! first candidate of the batch (in drawing order) that passes its aggregation test is the one kept, so the result
//! is what the sequential loop gives, whatever the number of threads. After `max_attempts` failed tests the
//! building goes to the most interesting candidate seen (if any had a positive interest) and the caller is told,
//! so that a scenario asking for ten farms gets ten farms wherever the land allows them.

use super::encyclopedia::Placement;
use super::interest::{interest, StaticInterestMaps, VillageState};
use super::land::Land;
use glam::DVec2;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Candidates drawn and evaluated together.
const BATCH: usize = 256;

/// Where a building was seeded and how.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Seeding {
    pub position: DVec2,
    /// Its interest `I(p, B, V)`.
    pub interest: f64,
    /// Candidates tried.
    pub attempts: usize,
    /// No candidate passed the aggregation test: the best one seen was taken.
    pub fallback: bool,
}

/// Algorithm 1 for one building; `None` when no candidate had a positive interest.
pub(super) fn seed_building(
    land: &Land,
    maps: &StaticInterestMaps,
    state: &VillageState,
    placement: &Placement,
    rng: &mut ChaCha8Rng,
    max_attempts: usize,
) -> Option<Seeding> {
    let g = land.grid();
    let (lo, hi) = (g.origin, g.point(g.nx - 1, g.ny - 1));
    let mut best: Option<Seeding> = None;
    let mut attempts = 0;
    while attempts < max_attempts {
        let n = BATCH.min(max_attempts - attempts);
        let draws: Vec<(DVec2, f64)> = (0..n)
            .map(|_| {
                let p = DVec2::new(rng.random_range(lo.x..=hi.x), rng.random_range(lo.y..=hi.y));
                (p, rng.random::<f64>())
            })
            .collect();
        let interests: Vec<f64> = draws
            .par_iter()
            .map(|(p, _)| interest(land, maps, state, placement, *p))
            .collect();
        for (k, ((p, r), i)) in draws.iter().zip(&interests).enumerate() {
            if *r < *i {
                return Some(Seeding {
                    position: *p,
                    interest: *i,
                    attempts: attempts + k + 1,
                    fallback: false,
                });
            }
            if *i > 0.0 && best.is_none_or(|b| *i > b.interest) {
                best = Some(Seeding {
                    position: *p,
                    interest: *i,
                    attempts: 0,
                    fallback: true,
                });
            }
        }
        attempts += n;
    }
    best.map(|b| Seeding { attempts, ..b })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Grid;
    use crate::village::encyclopedia::{InterestWeights, ParcelParams, Shape};
    use rand::SeedableRng;

    fn flat_land(n: usize, cell: f64) -> Land {
        let grid = Grid {
            origin: DVec2::ZERO,
            cell,
            nx: n,
            ny: n,
        };
        Land::from_maps(
            grid,
            (0..grid.len())
                .map(|k| (grid.point_of(k).x * 0.1) as f32)
                .collect(),
            [
                vec![true; grid.len()],
                (0..grid.len()).map(|k| grid.point_of(k).x < 20.0).collect(),
                vec![false; grid.len()],
                vec![false; grid.len()],
            ],
        )
        .expect("land")
    }

    fn placement(weights: InterestWeights) -> Placement {
        let s = |a, b, c| Shape {
            min: a,
            zero: b,
            max: c,
        };
        Placement {
            weights,
            sociability: s(10.0, 20.0, 60.0),
            sociability_with: Default::default(),
            worship: s(10.0, 30.0, 100.0),
            accessibility: s(5.0, 10.0, 40.0),
            slope: s(0.0, 0.0, 0.5),
            water: s(2.0, 5.0, 60.0),
            fortification: s(0.0, 10.0, 50.0),
            domination_radius: 80.0,
            parcel: ParcelParams {
                budget: 20.0,
                road_reach: 10.0,
                conquest_weight: 1.0,
                slope_weight: 1.0,
                fill: 0.0,
            },
            footprint: None,
            turned_share: 0.0,
            skew_share: 0.0,
        }
    }

    fn seed_many(land: &Land, p: &Placement, n: usize, seed: u64) -> Vec<DVec2> {
        let maps = StaticInterestMaps::new(land, &[p.domination_radius]);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut buildings = Vec::new();
        let mut out = Vec::new();
        for _ in 0..n {
            let flags = vec![false; buildings.len()];
            let state = VillageState {
                buildings: &buildings,
                religious: &flags,
                fortress: &flags,
                road_distance: &|_| f64::INFINITY,
                has_roads: false,
            };
            let Some(s) = seed_building(land, &maps, &state, p, &mut rng, 5000) else {
                break;
            };
            out.push(s.position);
            buildings.push(crate::village::BuildingSeed {
                building: "house".into(),
                village_type: "test".into(),
                position: s.position,
            });
        }
        out
    }

    #[test]
    fn water_interest_pulls_buildings_to_the_shore_and_keeps_them_dry() {
        let land = flat_land(101, 2.0);
        let thirty = |weights| seed_many(&land, &placement(weights), 30, 1);
        let near = thirty(InterestWeights {
            water: 1.0,
            ..Default::default()
        });
        let indifferent = thirty(InterestWeights {
            slope: 1.0,
            ..Default::default()
        });
        let mean_x = |v: &[DVec2]| v.iter().map(|p| p.x).sum::<f64>() / v.len() as f64;
        assert_eq!(near.len(), 30);
        assert!(
            near.iter().all(|p| p.x >= 20.0 + 2.0 - 1.0),
            "a building stands in the water"
        );
        // the shore is at x = 20 m; water interest fades out 60 m from it
        assert!(
            mean_x(&near) < 60.0,
            "mean x {} with water interest",
            mean_x(&near)
        );
        assert!(
            mean_x(&indifferent) > mean_x(&near) + 30.0,
            "{} vs {}",
            mean_x(&indifferent),
            mean_x(&near)
        );
        // sociability's λ_min keeps every pair apart
        for (a, p) in near.iter().enumerate() {
            for q in &near[a + 1..] {
                assert!(p.distance(*q) >= 10.0);
            }
        }
    }

    #[test]
    fn seeding_does_not_depend_on_the_thread_count() {
        let land = flat_land(81, 2.0);
        let p = placement(InterestWeights {
            water: 0.5,
            sociability: 0.5,
            ..Default::default()
        });
        let a = seed_many(&land, &p, 12, 7);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("pool");
        let b = pool.install(|| seed_many(&land, &p, 12, 7));
        assert_eq!(a, b);
    }
}

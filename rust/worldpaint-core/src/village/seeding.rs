//! Aggregation-based building seeding (thesis 3.2.3, Algorithm 1):
//!
//! > repeat p ← random location; p ← I(p, B, V); r ← uniform probability in [0, 1] until r < p
//!
//! Candidates are drawn from the seeded generator in batches of [`BATCH`] (the stream every village has been grown
//! from) and tried in turn; the first that passes its aggregation test is the one kept. Most candidates of a
//! large land are rejected by a look-up or two (too far from the roads), so they are tried on one thread: handing
//! batches of them to a pool cost more than trying them (0.60 s against 1.08 s over the 1,000-building town
//! of `benches/town.rs`). After `max_attempts` failed tests the building goes to the most interesting candidate
//! seen (if any had a positive interest) and the caller is told, so that a scenario asking for ten farms gets ten
//! farms wherever the land allows them.
//!
//! A building seeded beside one already there (a village type's cluster share) draws its candidates in rings
//! around the standing buildings instead of over the whole land; the aggregation test is the same.

use super::encyclopedia::Placement;
use super::interest::{combine, criteria, interest, StaticInterestMaps, VillageState};
use super::land::Land;
use glam::DVec2;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Candidates drawn from the generator at a time (the rest of a batch is drawn even when an earlier one passes).
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

/// A ring around a standing building, between `inner` and `outer` metres of its `centre`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Ring {
    pub centre: DVec2,
    pub inner: f64,
    pub outer: f64,
}

impl Ring {
    /// A point drawn evenly over the ring's area.
    fn draw(&self, rng: &mut ChaCha8Rng) -> DVec2 {
        let (a, b) = (self.inner * self.inner, self.outer * self.outer);
        let r = (a + (b - a) * rng.random::<f64>()).sqrt();
        self.centre + DVec2::from_angle(std::f64::consts::TAU * rng.random::<f64>()) * r
    }
}

/// Algorithm 1 for one building, its candidates drawn evenly over the land, or over one of `rings` drawn evenly
/// when there are some; `None` when no candidate had a positive interest.
pub(super) fn seed_building(
    land: &Land,
    maps: &StaticInterestMaps,
    state: &VillageState,
    placement: &Placement,
    rings: &[Ring],
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
                let p = if rings.is_empty() {
                    DVec2::new(rng.random_range(lo.x..=hi.x), rng.random_range(lo.y..=hi.y))
                } else {
                    rings[rng.random_range(0..rings.len())].draw(rng)
                };
                (p, rng.random::<f64>())
            })
            .collect();
        for (k, (p, r)) in draws.iter().enumerate() {
            let i = interest(land, maps, state, placement, *p);
            if *r < i {
                return Some(Seeding {
                    position: *p,
                    interest: i,
                    attempts: attempts + k + 1,
                    fallback: false,
                });
            }
            if i > 0.0 && best.is_none_or(|b| i > b.interest) {
                best = Some(Seeding {
                    position: *p,
                    interest: i,
                    attempts: 0,
                    fallback: true,
                });
            }
        }
        attempts += n;
    }
    best.map(|b| Seeding { attempts, ..b })
}

/// Why a building found no place: of `n` candidates drawn evenly over the land, how many each criterion forbids
/// (in [`super::interest::InterestCriterion::ALL`] order; a candidate may count under several), then how many lie
/// where nothing can be built (outside the region, in water, on a wall), and last how many no criterion forbids
/// but whose weighted criteria add up to nothing (an interest of 0: nothing draws the building there).
pub(super) fn causes(
    land: &Land,
    maps: &StaticInterestMaps,
    state: &VillageState,
    placement: &Placement,
    rng: &mut ChaCha8Rng,
    n: usize,
) -> [usize; 9] {
    let g = land.grid();
    let (lo, hi) = (g.origin, g.point(g.nx - 1, g.ny - 1));
    let draws: Vec<DVec2> = (0..n)
        .map(|_| DVec2::new(rng.random_range(lo.x..=hi.x), rng.random_range(lo.y..=hi.y)))
        .collect();
    let w = placement.weights.as_array();
    draws
        .par_iter()
        .map(|p| {
            let mut count = [0usize; 9];
            let buildable = g
                .nearest(*p)
                .is_some_and(|(i, j)| land.buildable(g.index(i, j)));
            if !buildable {
                count[7] = 1;
                return count;
            }
            let values = criteria(land, maps, state, placement, *p);
            for (k, v) in values.iter().enumerate() {
                count[k] = usize::from(*v <= -1.0 && (k == 0 || w[k] != 0.0));
            }
            count[8] = usize::from(
                count[..7].iter().all(|&n| n == 0) && combine(&values, placement) <= 0.0,
            );
            count
        })
        .reduce(|| [0usize; 9], |a, b| std::array::from_fn(|k| a[k] + b[k]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Grid;
    use crate::village::encyclopedia::{InterestWeights, ParcelParams, Shape};
    use crate::village::interest::{attraction_repulsion, open_distance};
    use crate::village::BuildingSeed;
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
            cluster_share: 0.0,
        }
    }

    fn house_at(position: DVec2) -> BuildingSeed {
        BuildingSeed {
            building: "house".into(),
            village_type: "test".into(),
            position,
        }
    }

    fn no_road(_: DVec2, _: f64) -> f64 {
        f64::INFINITY
    }

    /// A village of `buildings`, none religious or fortified, without roads.
    fn roadless<'a>(buildings: &'a [BuildingSeed], flags: &'a [bool]) -> VillageState<'a> {
        VillageState::new(buildings, flags, flags, &no_road, false)
    }

    fn seed_many(land: &Land, p: &Placement, n: usize, seed: u64) -> Vec<DVec2> {
        let maps = StaticInterestMaps::new(land, &[p.domination_radius]);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut buildings = Vec::new();
        let mut out = Vec::new();
        for _ in 0..n {
            let flags = vec![false; buildings.len()];
            let state = roadless(&buildings, &flags);
            let Some(s) = seed_building(land, &maps, &state, p, &[], &mut rng, 5000) else {
                break;
            };
            out.push(s.position);
            buildings.push(house_at(s.position));
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
    fn a_building_seeded_in_rings_stands_within_one_of_them() {
        let land = flat_land(101, 2.0);
        let p = placement(InterestWeights {
            slope: 1.0,
            ..Default::default()
        });
        let maps = StaticInterestMaps::new(&land, &[p.domination_radius]);
        let standing = [DVec2::new(60.0, 60.0), DVec2::new(150.0, 140.0)].map(house_at);
        let flags = [false; 2];
        let state = roadless(&standing, &flags);
        let rings: Vec<Ring> = standing
            .iter()
            .map(|b| Ring {
                centre: b.position,
                inner: 10.0,
                outer: 16.0,
            })
            .collect();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut near = [0usize; 2];
        for _ in 0..40 {
            let s = seed_building(&land, &maps, &state, &p, &rings, &mut rng, 1000)
                .expect("room in the rings");
            let d: Vec<f64> = standing
                .iter()
                .map(|b| b.position.distance(s.position))
                .collect();
            let k = usize::from(d[1] < d[0]);
            // within the ring, and outside the sociability's λ_min (10 m)
            assert!(
                (10.0..=16.0 + 1e-9).contains(&d[k]),
                "{} m from its building",
                d[k]
            );
            near[k] += 1;
        }
        // both rings are drawn from
        assert!(near.iter().all(|&n| n >= 10), "{near:?}");
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

    /// The sociability, worship and fortification of a location sum the buildings within reach only: the same
    /// values, bit for bit, as the sums over every building of the village.
    #[test]
    fn criteria_read_the_buildings_within_reach_as_all_of_them() {
        let land = flat_land(200, 2.0);
        let maps = StaticInterestMaps::new(&land, &[80.0]);
        let mut p = placement(InterestWeights::default());
        // farms draw a farm from farther than the others reach
        p.sociability_with.insert(
            "farm".into(),
            Shape {
                min: 25.0,
                zero: 45.0,
                max: 150.0,
            },
        );
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let buildings: Vec<BuildingSeed> = (0..300)
            .map(|k| BuildingSeed {
                building: if k % 3 == 0 { "farm" } else { "house" }.into(),
                village_type: "test".into(),
                position: DVec2::new(
                    rng.random_range(-50.0..450.0),
                    rng.random_range(-50.0..450.0),
                ),
            })
            .collect();
        let religious: Vec<bool> = (0..300).map(|k| k % 97 == 5).collect();
        let fortress: Vec<bool> = (0..300).map(|k| k % 113 == 7).collect();
        let state = VillageState::new(&buildings, &religious, &fortress, &no_road, false);
        for _ in 0..2000 {
            let at = DVec2::new(
                rng.random_range(-20.0..420.0),
                rng.random_range(-20.0..420.0),
            );
            let (mut sociability, mut worship, mut too_close, mut fort) =
                (0.0, 0.0, false, f64::INFINITY);
            for (k, b) in buildings.iter().enumerate() {
                let d = b.position.distance(at);
                let shape = p
                    .sociability_with
                    .get(&b.building)
                    .unwrap_or(&p.sociability);
                let f = attraction_repulsion(d, shape);
                too_close |= f <= -1.0;
                sociability += f;
                if religious[k] {
                    worship += attraction_repulsion(d, &p.worship).max(-0.999);
                }
                if fortress[k] {
                    fort = f64::min(fort, d);
                }
            }
            let sociability = if too_close {
                -1.0
            } else {
                sociability.clamp(-0.999, 1.0)
            };
            let c = criteria(&land, &maps, &state, &p, at);
            assert_eq!(c[0].to_bits(), sociability.to_bits(), "sociability at {at}");
            assert_eq!(
                c[1].to_bits(),
                worship.clamp(-0.999, 1.0).to_bits(),
                "worship at {at}"
            );
            let enclosure = f64::min(f64::INFINITY, fort);
            let fortification = open_distance(enclosure, &p.fortification);
            assert_eq!(
                c[5].to_bits(),
                fortification.to_bits(),
                "fortification at {at}"
            );
        }
    }
}

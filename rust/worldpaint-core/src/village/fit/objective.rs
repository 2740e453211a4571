//! How far a grown village's figures are from the real village's: each figure's difference over its tolerance
//! (the acceptance bands), squared, weighted and averaged, then averaged over the seeds the candidate
//! was grown at. A value of 1 or less means every figure lies within its band on average; each band counts
//! alike, so no figure is traded for another by its unit.
//!
//! Hairpins alone are judged on the seeds' villages together (their mean per kilometre): a hamlet's 1–2 km of
//! road holds one hairpin or none, a count that varies about as much as its mean, so judged village by village a
//! type that makes the real rate on average (0.57 per km: 0.8 hairpins a village, squared error 1.6 bands) would
//! lose to one that never makes one (1.3).

use crate::village::figures::{total_variation, VillageFigures};

/// A figure compared, its tolerance and its weight.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Figure {
    /// Mean nearest-neighbour distance, relative (±15 %).
    NearestNeighbour,
    /// Share of buildings with another within 20 m, in points (±10).
    ShareWithin20m,
    /// Road length per house, relative (±15 %).
    RoadPerHouse,
    /// Buildings per hectare, relative (±15 %).
    BuildingsPerArea,
    /// Hairpins per kilometre, absolute (±0.5).
    HairpinsPerKm,
    /// Orientation-to-road histogram, total variation (≤ 0.15).
    OrientationToRoad,
    /// Share of the network's ends that are dead ends, absolute (±0.15).
    DeadEndShare,
    /// Mean distance from a building to the road, relative (±25 %).
    RoadDistance,
}

impl Figure {
    /// Every figure, in the order of the report.
    pub const ALL: [Figure; 8] = [
        Figure::NearestNeighbour,
        Figure::ShareWithin20m,
        Figure::RoadPerHouse,
        Figure::BuildingsPerArea,
        Figure::HairpinsPerKm,
        Figure::OrientationToRoad,
        Figure::DeadEndShare,
        Figure::RoadDistance,
    ];

    /// The figure's name as the report prints it.
    pub fn name(self) -> &'static str {
        match self {
            Figure::NearestNeighbour => "mean nearest neighbour",
            Figure::ShareWithin20m => "share within 20 m",
            Figure::RoadPerHouse => "road length per house",
            Figure::BuildingsPerArea => "buildings per hectare",
            Figure::HairpinsPerKm => "hairpins per km",
            Figure::OrientationToRoad => "orientation to road (TV)",
            Figure::DeadEndShare => "dead-end share",
            Figure::RoadDistance => "mean house-road distance",
        }
    }

    /// The tolerance: relative for the figures with a unit, absolute for shares and counts per km.
    pub fn tolerance(self) -> f64 {
        match self {
            Figure::NearestNeighbour | Figure::RoadPerHouse | Figure::BuildingsPerArea => 0.15,
            Figure::ShareWithin20m => 0.10,
            Figure::HairpinsPerKm => 0.5,
            Figure::OrientationToRoad | Figure::DeadEndShare => 0.15,
            Figure::RoadDistance => 0.25,
        }
    }

    /// Weight in the objective: the acceptance figures 1, the others (which shape the village but are
    /// not acceptance criteria) a half.
    pub fn weight(self) -> f64 {
        match self {
            Figure::DeadEndShare | Figure::RoadDistance => 0.5,
            _ => 1.0,
        }
    }

    /// The figure's difference between `grown` and `real` over its tolerance (0 equal, 1 on the band's edge).
    pub fn error(self, real: &VillageFigures, grown: &VillageFigures) -> f64 {
        let relative = |r: f64, g: f64| (g - r).abs() / (r.abs().max(1e-9));
        let (rl, gl) = (&real.layout, &grown.layout);
        let e = match self {
            Figure::NearestNeighbour => {
                relative(rl.mean_nearest_neighbour, gl.mean_nearest_neighbour)
            }
            Figure::ShareWithin20m => (gl.share_within_20m - rl.share_within_20m).abs(),
            Figure::RoadPerHouse => relative(rl.road_length_per_house, gl.road_length_per_house),
            Figure::BuildingsPerArea => {
                relative(real.buildings_per_hectare, grown.buildings_per_hectare)
            }
            Figure::HairpinsPerKm => {
                (grown.network.hairpins_per_km - real.network.hairpins_per_km).abs()
            }
            Figure::OrientationToRoad => {
                total_variation(&real.orientation_to_road, &grown.orientation_to_road)
            }
            Figure::DeadEndShare => {
                (grown.network.dead_end_share - real.network.dead_end_share).abs()
            }
            Figure::RoadDistance => relative(rl.mean_road_distance, gl.mean_road_distance),
        };
        e / self.tolerance()
    }
}

/// The objective of one grown village: the weighted mean of its figures' squared errors, its hairpins'
/// `hairpin_error` given.
fn village_error_with(real: &VillageFigures, grown: &VillageFigures, hairpin_error: f64) -> f64 {
    let (mut sum, mut weights) = (0.0, 0.0);
    for f in Figure::ALL {
        let e = if f == Figure::HairpinsPerKm {
            hairpin_error
        } else {
            f.error(real, grown)
        };
        sum += f.weight() * e * e;
        weights += f.weight();
    }
    sum / weights
}

/// The objective of one grown village judged alone.
#[cfg(test)]
pub(crate) fn village_error(real: &VillageFigures, grown: &VillageFigures) -> f64 {
    village_error_with(real, grown, Figure::HairpinsPerKm.error(real, grown))
}

/// The objective of villages grown at several seeds: the mean of their errors, their hairpins judged on their
/// mean per km; `None` (a seed that grew nothing) counts as the worst village (1000).
pub fn objective(real: &VillageFigures, grown: &[Option<VillageFigures>]) -> f64 {
    if grown.is_empty() {
        return FAILED;
    }
    let mut pooled = VillageFigures::default();
    pooled.network.hairpins_per_km = pooled_hairpins(grown);
    let hairpin_error = Figure::HairpinsPerKm.error(real, &pooled);
    grown
        .iter()
        .map(|g| {
            g.as_ref().map_or(FAILED, |g| {
                village_error_with(real, g, hairpin_error).min(FAILED)
            })
        })
        .sum::<f64>()
        / grown.len() as f64
}

/// The hairpins per km of villages grown at several seeds, pooled: their mean (0 when none grew).
pub(crate) fn pooled_hairpins(grown: &[Option<VillageFigures>]) -> f64 {
    let villages: Vec<&VillageFigures> = grown.iter().flatten().collect();
    villages
        .iter()
        .map(|g| g.network.hairpins_per_km)
        .sum::<f64>()
        / villages.len().max(1) as f64
}

/// The error of a seed whose village could not be grown, and the most any village counts: far worse than any
/// village whose figures are off by ten bands.
pub(crate) const FAILED: f64 = 1e3;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::village::figures::ORIENTATION_BINS;

    fn figures(nn: f64, share: f64, per_house: f64, density: f64, hairpins: f64) -> VillageFigures {
        let mut f = VillageFigures::default();
        f.layout.mean_nearest_neighbour = nn;
        f.layout.share_within_20m = share;
        f.layout.road_length_per_house = per_house;
        f.layout.mean_road_distance = 12.0;
        f.buildings_per_hectare = density;
        f.network.hairpins_per_km = hairpins;
        f.network.dead_end_share = 0.4;
        f.orientation_to_road = [0.5, 0.1, 0.1, 0.1, 0.1, 0.1];
        f
    }

    #[test]
    fn each_band_edge_counts_one_and_the_objective_ranks_nearer_villages_lower() {
        let real = figures(20.0, 0.4, 100.0, 0.5, 0.3);
        assert_eq!(village_error(&real, &real), 0.0);
        // on each band's edge: every acceptance figure's error is 1
        let mut edge = figures(23.0, 0.5, 85.0, 0.575, 0.8);
        edge.orientation_to_road = [0.35, 0.1, 0.1, 0.1, 0.1, 0.25];
        for f in [
            Figure::NearestNeighbour,
            Figure::ShareWithin20m,
            Figure::RoadPerHouse,
            Figure::BuildingsPerArea,
            Figure::HairpinsPerKm,
            Figure::OrientationToRoad,
        ] {
            assert!((f.error(&real, &edge) - 1.0).abs() < 1e-9, "{}", f.name());
        }
        assert_eq!(Figure::DeadEndShare.error(&real, &edge), 0.0);
        // weights 1 x 6 and 0.5 x 2: six errors of 1 over a weight of 7
        assert!((village_error(&real, &edge) - 6.0 / 7.0).abs() < 1e-12);
        let far = figures(40.0, 0.0, 40.0, 0.2, 5.0);
        assert!(village_error(&real, &far) > village_error(&real, &edge));
        // seeds average, their hairpins together (0.55 per km, half a band off in each): 0.25 / 7 and 5.25 / 7
        let two = objective(&real, &[Some(real.clone()), Some(edge.clone())]);
        assert!((two - 5.5 / 14.0).abs() < 1e-12);
        // a failed seed weighs as FAILED
        assert_eq!(objective(&real, &[None, None]), FAILED);
        assert!(
            objective(&real, &[Some(real.clone()), None]) > objective(&real, &[Some(far.clone())])
        );
        assert_eq!(real.orientation_to_road.len(), ORIENTATION_BINS);
    }

    #[test]
    fn hairpins_are_judged_on_the_seeds_together() {
        let real = figures(20.0, 0.4, 100.0, 0.5, 0.5);
        let with = |hairpins: f64| figures(20.0, 0.4, 100.0, 0.5, hairpins);
        // one village of two with a hairpin a km: on average the real rate, so no error at all
        assert_eq!(objective(&real, &[Some(with(1.0)), Some(with(0.0))]), 0.0);
        // neither village with one: 0.5 off in each, one band
        let none = objective(&real, &[Some(with(0.0)), Some(with(0.0))]);
        assert!((none - 1.0 / 7.0).abs() < 1e-12);
        // judged village by village, the type that never makes a hairpin would have been as near
        let alone = 0.5 * (village_error(&real, &with(1.0)) + village_error(&real, &with(0.0)));
        assert!((alone - none).abs() < 1e-12);
    }
}

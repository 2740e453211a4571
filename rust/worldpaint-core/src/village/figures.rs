//! The figures a village is compared by, real or generated (issue 42's statistics of a village; the thesis
//! validates its model by eye and by parcel counts, 3.5): the layout figures of [`layout_statistics`] (nearest
//! neighbour, shares within 20 m and 50 m, road length per house, distances to the road), the road network's
//! dead ends, junctions and hairpins per kilometre, the share of its ends that are dead ends, the buildings per
//! hectare, and how the buildings stand to the road (the histogram of the angle between a building's long axis
//! and the nearest road). Learning a village type measures the real village and each village grown for it with
//! this one function, and so do the tests that hold generated villages beside real ones.
//!
//! Readings chosen where the statistics are vague:
//! * Everything is measured inside a region (a window on a real place): buildings whose centre lies outside are
//!   left out, roads are clipped to it, and road ends closer than [`BORDER_MARGIN`] to its border are where the
//!   region cut them, neither dead ends nor junctions.
//! * A building's orientation is that of its long axis (a footprint's longer side; for a real building, the long
//!   side of its minimum-area rectangle). Its angle to the nearest road segment is folded into 0–90°: a house
//!   with its eaves along the road reads 0°, one with its gable to the road 90°.
//! * The road length per house counts the roads that serve the village: the stretches within [`SERVING_REACH`] of
//!   one of its buildings. A window on a real place also holds roads that pass it by (a valley road, field
//!   tracks); they say nothing of the village and would make the figure depend on the window's size.
//! * OpenStreetMap ways meet at shared nodes, while a generated road may end inside a segment of the road it
//!   joins: every road end is made a vertex of the roads it passes within half a metre of before the network's
//!   nodes are counted.

use super::metrics::{layout_statistics, road_length, LayoutStatistics};
use super::{HouseFootprint, Road};
use crate::geom::Region;
use crate::graph::{Graph, SegmentIndex};
use glam::DVec2;

/// Bins of the orientation-to-road histogram, 90° / bins wide each.
pub const ORIENTATION_BINS: usize = 6;
/// Distance (m) from the region's border within which a road end is where the region clipped it.
pub(crate) const BORDER_MARGIN: f64 = 10.0;
/// Half the length (m) over which a road's turn is measured, and the turn (degrees) that makes a hairpin.
const HAIRPIN_REACH: f64 = 10.0;
const HAIRPIN_DEGREES: f64 = 120.0;
/// Road ends within this distance (m) of another road are joined to it.
const SNAP: f64 = 0.5;
/// Buildings farther than this (m) from every road have no orientation to the road.
const ORIENTATION_REACH: f64 = 200.0;
/// Roads within this distance (m) of a building serve the village; pieces this long (m) at most are judged.
pub(crate) const SERVING_REACH: f64 = 100.0;
const SERVING_PIECE: f64 = 2.0;

/// A building as measured: its centre, and the angle (radians from +X, counter-clockwise, any half-turn) of its
/// long axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SitedBuilding {
    /// Centre (m).
    pub centre: DVec2,
    /// Long axis (radians from +X).
    pub orientation: f64,
}

impl SitedBuilding {
    /// A generated building: its footprint's centre and longer side.
    pub fn of_footprint(f: &HouseFootprint) -> SitedBuilding {
        let c = &f.corners;
        let (front, side) = (c[1] - c[0], c[3] - c[0]);
        let long = if front.length_squared() >= side.length_squared() {
            front
        } else {
            side
        };
        SitedBuilding {
            centre: c.iter().copied().sum::<DVec2>() / 4.0,
            orientation: long.y.atan2(long.x),
        }
    }
}

/// The shape of a road network: its dead ends and junctions per kilometre of road, the share of its ends that
/// are dead ends (dead ends over dead ends and junctions), and its hairpins per kilometre (see [`hairpins`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NetworkShape {
    /// Dead ends per km of road.
    pub dead_ends_per_km: f64,
    /// Junctions (three roads or more) per km of road.
    pub junctions_per_km: f64,
    /// Dead ends over dead ends and junctions.
    pub dead_end_share: f64,
    /// Hairpins per km of road.
    pub hairpins_per_km: f64,
}

/// The figures of a village inside a region.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VillageFigures {
    /// Houses are the buildings inside the region; roads their clipped pieces.
    pub layout: LayoutStatistics,
    /// The road network's shape.
    pub network: NetworkShape,
    /// Length (m) of the roads inside the region.
    pub road_length: f64,
    /// Buildings per hectare of the region.
    pub buildings_per_hectare: f64,
    /// Shares of the buildings within [`ORIENTATION_BINS`] bins of their long axis's angle to the nearest road
    /// (0–90°); all zero without roads.
    pub orientation_to_road: [f64; ORIENTATION_BINS],
}

/// Total variation distance between two histograms of shares: half the sum of their differences (0 alike, 1
/// disjoint).
pub(crate) fn total_variation(a: &[f64], b: &[f64]) -> f64 {
    0.5 * a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum::<f64>()
}

/// The figures of `buildings` and `roads` inside `region`.
pub fn village_figures(
    buildings: &[SitedBuilding],
    roads: &[Road],
    region: &Region,
) -> VillageFigures {
    let inside: Vec<SitedBuilding> = buildings
        .iter()
        .copied()
        .filter(|b| region.contains(b.centre))
        .collect();
    let clipped: Vec<Road> = roads
        .iter()
        .flat_map(|r| region.clip_polyline(&r.points).0)
        .filter(|points| points.len() >= 2)
        .map(|points| Road { points })
        .collect();
    let centres: Vec<DVec2> = inside.iter().map(|b| b.centre).collect();
    let hectares = region.area() / 1e4;
    let mut layout = layout_statistics(&centres, &clipped);
    layout.road_length_per_house =
        serving_road_length(&centres, &clipped) / centres.len().max(1) as f64;
    VillageFigures {
        layout,
        network: network_shape(region, &clipped),
        road_length: road_length(&clipped),
        buildings_per_hectare: if hectares > 0.0 {
            inside.len() as f64 / hectares
        } else {
            0.0
        },
        orientation_to_road: orientation_to_road(&inside, &clipped),
    }
}

/// The length (m) of the roads' stretches within [`SERVING_REACH`] of a building (`centres`), judged on pieces of
/// at most [`SERVING_PIECE`] by their middles.
fn serving_road_length(centres: &[DVec2], roads: &[Road]) -> f64 {
    let reach2 = SERVING_REACH * SERVING_REACH;
    let serves = |p: DVec2| centres.iter().any(|c| c.distance_squared(p) <= reach2);
    let mut length = 0.0;
    for road in roads {
        for w in road.points.windows(2) {
            let (a, b) = (w[0], w[1]);
            let pieces = (a.distance(b) / SERVING_PIECE).ceil().max(1.0);
            let piece = a.distance(b) / pieces;
            for k in 0..pieces as usize {
                if serves(a.lerp(b, (k as f64 + 0.5) / pieces)) {
                    length += piece;
                }
            }
        }
    }
    length
}

/// The histogram of the buildings' long axes' angles to their nearest road segment, folded into 0–90°.
fn orientation_to_road(buildings: &[SitedBuilding], roads: &[Road]) -> [f64; ORIENTATION_BINS] {
    let index = SegmentIndex::new(
        roads
            .iter()
            .flat_map(|r| r.points.windows(2).map(|s| (s[0], s[1])))
            .filter(|(a, b)| a.distance(*b) > 1e-9)
            .collect(),
    );
    let mut counts = [0usize; ORIENTATION_BINS];
    for b in buildings {
        let Some((_, (p, q))) = index.nearest(b.centre, ORIENTATION_REACH) else {
            continue;
        };
        let d = q - p;
        let road = d.y.atan2(d.x);
        // the angle between two undirected lines, in [0, π/2]
        let mut a = (b.orientation - road).rem_euclid(std::f64::consts::PI);
        if a > std::f64::consts::FRAC_PI_2 {
            a = std::f64::consts::PI - a;
        }
        let bin = ((a / std::f64::consts::FRAC_PI_2) * ORIENTATION_BINS as f64) as usize;
        counts[bin.min(ORIENTATION_BINS - 1)] += 1;
    }
    let n: usize = counts.iter().sum();
    counts.map(|c| if n > 0 { c as f64 / n as f64 } else { 0.0 })
}

/// The hairpins of a road: the stretches where its heading over the 10 metres ahead turns from
/// its heading over the metres behind by more than 120°, each stretch counted once. Measured on
/// points a metre apart along the road, so that a hairpin counts alike whether one vertex or ten draw it.
pub fn hairpins(road: &[DVec2]) -> usize {
    let mut points = Vec::new();
    let mut next = 0.0;
    let mut walked = 0.0;
    for w in road.windows(2) {
        let length = w[0].distance(w[1]);
        while next <= walked + length && length > 0.0 {
            points.push(w[0].lerp(w[1], (next - walked) / length));
            next += 1.0;
        }
        walked += length;
    }
    let k = HAIRPIN_REACH as usize;
    let limit = HAIRPIN_DEGREES.to_radians();
    let mut count = 0;
    let mut within = false;
    for i in k..points.len().saturating_sub(k) {
        let (behind, ahead) = (points[i] - points[i - k], points[i + k] - points[i]);
        let turn = behind.angle_to(ahead).abs();
        let sharp = behind.length() > 0.0 && ahead.length() > 0.0 && turn > limit;
        count += usize::from(sharp && !within);
        within = sharp;
    }
    count
}

/// The network's dead ends, junctions and hairpins; nodes within 10 m of the region's border are
/// left out (the roads were clipped there).
pub fn network_shape(region: &Region, roads: &[Road]) -> NetworkShape {
    let ends: Vec<DVec2> = roads
        .iter()
        .filter_map(|r| Some([*r.points.first()?, *r.points.last()?]))
        .flatten()
        .collect();
    let noded: Vec<Vec<DVec2>> = roads
        .iter()
        .map(|r| {
            let mut out: Vec<DVec2> = Vec::with_capacity(r.points.len());
            for w in r.points.windows(2) {
                let (a, b) = (w[0], w[1]);
                out.push(a);
                let ab = b - a;
                let mut on: Vec<(f64, DVec2)> = ends
                    .iter()
                    .filter_map(|&e| {
                        let t = (e - a).dot(ab) / ab.length_squared().max(1e-12);
                        (t > 0.0 && t < 1.0 && (a + ab * t).distance(e) <= SNAP).then_some((t, e))
                    })
                    .collect();
                on.sort_by(|x, y| x.0.total_cmp(&y.0));
                out.extend(on.into_iter().map(|(_, e)| e));
            }
            out.extend(r.points.last());
            out
        })
        .collect();
    let paths: Vec<&[DVec2]> = noded.iter().map(|r| r.as_slice()).collect();
    let graph = Graph::from_paths(&paths, SNAP);
    let away_from_border =
        |p: DVec2| region.contains(p) && region.distance_to_boundary(p) > BORDER_MARGIN;
    let (mut dead, mut junctions) = (0usize, 0usize);
    for (v, nb) in graph.adjacency().iter().enumerate() {
        if !away_from_border(graph.nodes[v]) {
            continue;
        }
        match nb.len() {
            1 => dead += 1,
            n if n >= 3 => junctions += 1,
            _ => {}
        }
    }
    let km = (road_length(roads) / 1e3).max(1e-9);
    NetworkShape {
        dead_ends_per_km: dead as f64 / km,
        junctions_per_km: junctions as f64 / km,
        dead_end_share: dead as f64 / (dead + junctions).max(1) as f64,
        hairpins_per_km: roads.iter().map(|r| hairpins(&r.points)).sum::<usize>() as f64 / km,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(side: f64) -> Region {
        Region::Rect {
            min: DVec2::ZERO,
            max: DVec2::splat(side),
        }
    }

    #[test]
    fn houses_along_a_street_face_it_and_gables_to_it_read_90_degrees() {
        let region = square(200.0);
        let road = Road {
            points: vec![DVec2::new(-50.0, 100.0), DVec2::new(250.0, 100.0)],
        };
        let along: Vec<SitedBuilding> = (0..10)
            .map(|k| SitedBuilding {
                centre: DVec2::new(10.0 + 18.0 * k as f64, 110.0),
                orientation: 0.02 * k as f64 + std::f64::consts::PI,
            })
            .collect();
        let f = village_figures(&along, std::slice::from_ref(&road), &region);
        assert_eq!(f.orientation_to_road[0], 1.0);
        assert_eq!(f.layout.houses, 10);
        assert!((f.layout.mean_nearest_neighbour - 18.0).abs() < 1e-9);
        assert!((f.buildings_per_hectare - 10.0 / 4.0).abs() < 1e-12);
        // the road crosses the square: 200 m inside, no dead end (both ends on the border)
        assert!((f.road_length - 200.0).abs() < 1e-9);
        assert_eq!(f.network.dead_ends_per_km, 0.0);
        let gables: Vec<SitedBuilding> = along
            .iter()
            .map(|b| SitedBuilding {
                orientation: b.orientation + std::f64::consts::FRAC_PI_2,
                ..*b
            })
            .collect();
        let g = village_figures(&gables, &[road], &region);
        assert_eq!(g.orientation_to_road[ORIENTATION_BINS - 1], 1.0);
        assert_eq!(
            total_variation(&f.orientation_to_road, &g.orientation_to_road),
            1.0
        );
    }

    #[test]
    fn the_road_per_house_counts_the_roads_within_reach_of_the_village_not_those_passing_the_window(
    ) {
        let region = square(400.0);
        let street = Road {
            points: vec![DVec2::new(-50.0, 100.0), DVec2::new(450.0, 100.0)],
        };
        // a valley road 190 m from every house
        let valley = Road {
            points: vec![DVec2::new(-50.0, 300.0), DVec2::new(450.0, 300.0)],
        };
        let houses: Vec<SitedBuilding> = (0..10)
            .map(|k| SitedBuilding {
                centre: DVec2::new(110.0 + 18.0 * k as f64, 110.0),
                orientation: 0.0,
            })
            .collect();
        let f = village_figures(&houses, &[street, valley], &region);
        assert!((f.road_length - 800.0).abs() < 1e-9);
        // the street within 100 m of the houses at 10 m: x from 110 - 99.5 to 272 + 99.5
        let serving = 162.0 + 2.0 * (SERVING_REACH * SERVING_REACH - 100.0).sqrt();
        assert!(
            (f.layout.road_length_per_house * 10.0 - serving).abs() <= SERVING_PIECE,
            "{} m of serving road, {serving:.1} m expected",
            f.layout.road_length_per_house * 10.0
        );
    }

    #[test]
    fn a_branch_ending_inside_is_a_dead_end_and_its_joint_a_junction() {
        let region = square(400.0);
        let main = Road {
            points: vec![DVec2::new(-10.0, 200.0), DVec2::new(410.0, 200.0)],
        };
        // ends on the main road's segment, not on a vertex of it
        let branch = Road {
            points: vec![DVec2::new(200.0, 300.0), DVec2::new(200.0, 200.0)],
        };
        let f = village_figures(&[], &[main, branch], &region);
        assert!((f.road_length - 500.0).abs() < 1e-9);
        assert!((f.network.dead_ends_per_km - 2.0).abs() < 1e-9);
        assert!((f.network.junctions_per_km - 2.0).abs() < 1e-9);
        assert!((f.network.dead_end_share - 0.5).abs() < 1e-12);
        // buildings outside the region are not counted
        let out = SitedBuilding {
            centre: DVec2::new(500.0, 0.0),
            orientation: 0.0,
        };
        assert_eq!(village_figures(&[out], &[], &region).layout.houses, 0);
    }

    #[test]
    fn a_footprint_reads_its_longer_side() {
        let f = HouseFootprint {
            seed: 0,
            corners: [
                DVec2::new(0.0, 0.0),
                DVec2::new(6.0, 0.0),
                DVec2::new(6.0, 10.0),
                DVec2::new(0.0, 10.0),
            ],
        };
        let b = SitedBuilding::of_footprint(&f);
        assert_eq!(b.centre, DVec2::new(3.0, 5.0));
        assert!((b.orientation - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }
}

//! What a layout team checks on a village, generated or real: every house reachable by road from a connection
//! point, no house on a road corridor, in water, on a wall or on another house (terraced houses may share a wall),
//! road grades, and the layout figures compared with real villages (house-to-road distances, nearest-neighbour
//! distances, road length per house).

use super::land::Land;
use super::{HouseFootprint, Road};
use crate::graph::SegmentIndex;
use glam::DVec2;

/// Footprint conflicts found by [`footprint_conflicts`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Conflicts {
    /// Footprints reaching into a road corridor.
    pub road: usize,
    /// Footprints reaching onto water.
    pub water: usize,
    /// Footprints over a fortification wall's nodes.
    pub wall: usize,
    /// Pairs of footprints overlapping by more than a shared wall.
    pub house: usize,
    /// Footprints outside the region of interest.
    pub outside: usize,
}

impl Conflicts {
    /// All conflicts together.
    pub fn total(&self) -> usize {
        self.road + self.water + self.wall + self.house + self.outside
    }
}

/// Points on and inside a footprint, about `step` apart (edges included), for containment checks.
pub(crate) fn footprint_samples(f: &HouseFootprint, step: f64) -> Vec<DVec2> {
    let c = &f.corners;
    let nu = ((c[1] - c[0]).length() / step).ceil().max(1.0) as usize;
    let nv = ((c[3] - c[0]).length() / step).ceil().max(1.0) as usize;
    let mut out = Vec::with_capacity((nu + 1) * (nv + 1));
    for j in 0..=nv {
        let v = j as f64 / nv as f64;
        for i in 0..=nu {
            let u = i as f64 / nu as f64;
            // bilinear over the quad: exact for parallelograms, inside for any convex quad
            let a = c[0] + (c[1] - c[0]) * u;
            let b = c[3] + (c[2] - c[3]) * u;
            out.push(a + (b - a) * v);
        }
    }
    out
}

/// How deep two convex polygons overlap: the smallest penetration over their edge normals (separating axes);
/// 0 or less when they are apart or only touch.
pub(crate) fn overlap_depth(a: &[DVec2], b: &[DVec2]) -> f64 {
    let mut depth = f64::INFINITY;
    for poly in [a, b] {
        for k in 0..poly.len() {
            let e = poly[(k + 1) % poly.len()] - poly[k];
            if e.length_squared() < 1e-18 {
                continue;
            }
            let n = DVec2::new(-e.y, e.x).normalize();
            let (amin, amax) = a
                .iter()
                .map(|p| p.dot(n))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |m, v| {
                    (m.0.min(v), m.1.max(v))
                });
            let (bmin, bmax) = b
                .iter()
                .map(|p| p.dot(n))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |m, v| {
                    (m.0.min(v), m.1.max(v))
                });
            depth = depth.min(amax.min(bmax) - amin.max(bmin));
        }
    }
    depth
}

/// Counts the footprints that overlap a road corridor (closer than `road_width / 2` to a centreline), water, a
/// wall, the outside of the region, or each other by more than `tolerance` (m).
pub fn footprint_conflicts(
    footprints: &[HouseFootprint],
    roads: &[Road],
    road_width: f64,
    land: &Land,
    tolerance: f64,
) -> Conflicts {
    let index = road_index(roads);
    let mut out = Conflicts::default();
    let g = land.grid();
    for (k, f) in footprints.iter().enumerate() {
        let samples = footprint_samples(f, 0.5);
        let corner_road = (0..4)
            .map(|e| edge_distance(&index, f.corners[e], f.corners[(e + 1) % 4]))
            .fold(f64::INFINITY, f64::min);
        let sample_road = samples
            .iter()
            .map(|p| index.distance(*p, road_width))
            .fold(f64::INFINITY, f64::min);
        if corner_road.min(sample_road) < 0.5 * road_width - tolerance {
            out.road += 1;
        }
        let node_flag = |mask: &[bool]| {
            samples
                .iter()
                .any(|p| g.nearest(*p).is_some_and(|(i, j)| mask[g.index(i, j)]))
        };
        out.water += on_water(land, f) as usize;
        out.wall += node_flag(land.wall()) as usize;
        out.outside += samples.iter().any(|p| {
            g.nearest(*p)
                .is_none_or(|(i, j)| !land.inside()[g.index(i, j)])
        }) as usize;
        for other in &footprints[k + 1..] {
            if overlap_depth(&f.corners, &other.corners) > tolerance {
                out.house += 1;
            }
        }
    }
    out
}

/// Whether a footprint reaches onto water: a point of it nearer (bilinearly) to water nodes than to dry ones.
pub(crate) fn on_water(land: &Land, f: &HouseFootprint) -> bool {
    let g = land.grid();
    let wet = |i: i64, j: i64| {
        let (i, j) = (
            i.clamp(0, g.nx as i64 - 1) as usize,
            j.clamp(0, g.ny as i64 - 1) as usize,
        );
        land.water()[g.index(i, j)] as u8 as f64
    };
    footprint_samples(f, 0.5).iter().any(|p| {
        let q = (*p - g.origin) / g.cell;
        let (i, j) = (q.x.floor() as i64, q.y.floor() as i64);
        let (tx, ty) = (q.x - i as f64, q.y - j as f64);
        let w = wet(i, j) * (1.0 - tx) * (1.0 - ty)
            + wet(i + 1, j) * tx * (1.0 - ty)
            + wet(i, j + 1) * (1.0 - tx) * ty
            + wet(i + 1, j + 1) * tx * ty;
        w >= 0.5
    })
}

/// Distance from a segment to the nearest road centreline (its ends and points along it).
fn edge_distance(index: &SegmentIndex, a: DVec2, b: DVec2) -> f64 {
    let n = ((b - a).length() / 0.25).ceil().max(1.0) as usize;
    (0..=n)
        .map(|i| index.distance(a + (b - a) * (i as f64 / n as f64), 1e9))
        .fold(f64::INFINITY, f64::min)
}

fn road_index(roads: &[Road]) -> SegmentIndex {
    SegmentIndex::new(
        roads
            .iter()
            .flat_map(|r| r.points.windows(2).map(|s| (s[0], s[1])))
            .collect(),
    )
}

/// Footprints from which no road path leads to a connection point: the footprint must lie within `reach` (m) of
/// a road joined, through roads whose corridors meet (centrelines closer than `touch`), to a road passing within
/// `reach` of a connection point.
pub fn unreachable_footprints(
    footprints: &[HouseFootprint],
    roads: &[Road],
    connections: &[DVec2],
    reach: f64,
    touch: f64,
) -> usize {
    let indexes: Vec<SegmentIndex> = roads
        .iter()
        .map(|r| road_index(std::slice::from_ref(r)))
        .collect();
    let distance = |k: usize, p: DVec2| indexes[k].distance(p, 1e9);
    let meet = |i: usize, j: usize| {
        roads[i].points.iter().any(|p| distance(j, *p) <= touch)
            || roads[j].points.iter().any(|p| distance(i, *p) <= touch)
            || roads[i]
                .points
                .windows(2)
                .any(|s| indexes[j].crosses(s[0], s[1], 0.0))
    };
    // roads served from a connection point, grown through the roads they touch
    let mut served: Vec<bool> = (0..roads.len())
        .map(|k| connections.iter().any(|c| distance(k, *c) <= reach))
        .collect();
    let mut frontier: Vec<usize> = (0..roads.len()).filter(|k| served[*k]).collect();
    while let Some(i) = frontier.pop() {
        let joined: Vec<usize> = (0..roads.len())
            .filter(|&j| !served[j] && meet(i, j))
            .collect();
        for j in joined {
            served[j] = true;
            frontier.push(j);
        }
    }
    footprints
        .iter()
        .filter(|f| {
            let centre = f.corners.iter().copied().sum::<DVec2>() / 4.0;
            !(0..roads.len()).any(|k| {
                served[k]
                    && f.corners
                        .iter()
                        .chain(std::iter::once(&centre))
                        .any(|p| distance(k, *p) <= reach)
            })
        })
        .count()
}

/// Grades (rise over run) of the road pieces about `step` metres long, with their lengths.
pub fn road_grades(roads: &[Road], ground: &dyn Fn(DVec2) -> f64, step: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for r in roads {
        for s in r.points.windows(2) {
            let len = s[0].distance(s[1]);
            let n = (len / step).ceil().max(1.0) as usize;
            for i in 0..n {
                let a = s[0] + (s[1] - s[0]) * (i as f64 / n as f64);
                let b = s[0] + (s[1] - s[0]) * ((i + 1) as f64 / n as f64);
                let run = a.distance(b);
                if run > 1e-9 {
                    out.push(((ground(b) - ground(a)).abs() / run, run));
                }
            }
        }
    }
    out
}

/// Layout figures compared between generated and real villages.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LayoutStatistics {
    /// Number of houses.
    pub houses: usize,
    /// Mean distance from a house to the nearest other house (m), over the houses that have one.
    pub mean_nearest_neighbour: f64,
    /// Share of houses with another house within 20 m: the close pairs (a house and its barn, a row).
    pub share_within_20m: f64,
    /// Share of houses with another house within 50 m.
    pub share_within_50m: f64,
    /// Total road length over the number of houses (m).
    pub road_length_per_house: f64,
    /// House-to-nearest-road distance: counts in bins of 10 m (the last bin holds everything beyond).
    pub road_distance_histogram: Vec<usize>,
    /// Mean distance from a house to the nearest road centreline (m).
    pub mean_road_distance: f64,
}

/// Total length of the roads' centrelines (m).
pub fn road_length(roads: &[Road]) -> f64 {
    roads
        .iter()
        .map(|r| {
            r.points
                .windows(2)
                .map(|s| s[0].distance(s[1]))
                .sum::<f64>()
        })
        .sum()
}

/// Layout figures of houses (their centres) and roads.
pub fn layout_statistics(houses: &[DVec2], roads: &[Road]) -> LayoutStatistics {
    let index = road_index(roads);
    let n = houses.len();
    let nearest: Vec<f64> = houses
        .iter()
        .enumerate()
        .map(|(i, p)| {
            houses
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, q)| p.distance(*q))
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let finite: Vec<f64> = nearest.iter().copied().filter(|d| d.is_finite()).collect();
    let mut histogram = vec![0usize; 11];
    let mut road_sum = 0.0;
    for p in houses {
        let d = index.distance(*p, 1e9);
        road_sum += d;
        histogram[((d / 10.0) as usize).min(10)] += 1;
    }
    let length: f64 = road_length(roads);
    LayoutStatistics {
        houses: n,
        mean_nearest_neighbour: finite.iter().sum::<f64>() / finite.len().max(1) as f64,
        share_within_20m: nearest.iter().filter(|d| **d <= 20.0).count() as f64 / n.max(1) as f64,
        share_within_50m: nearest.iter().filter(|d| **d <= 50.0).count() as f64 / n.max(1) as f64,
        road_length_per_house: length / n.max(1) as f64,
        road_distance_histogram: histogram,
        mean_road_distance: road_sum / n.max(1) as f64,
    }
}

/// Mean elevation percentile of points among the nodes of `Ω` (0 lowest, 1 highest).
pub fn mean_elevation_percentile(land: &Land, points: &[DVec2]) -> f64 {
    let mut heights: Vec<f32> = land
        .height()
        .iter()
        .zip(land.inside())
        .filter(|(_, inside)| **inside)
        .map(|(h, _)| *h)
        .collect();
    heights.sort_by(f32::total_cmp);
    if heights.is_empty() || points.is_empty() {
        return 0.0;
    }
    let sum: f64 = points
        .iter()
        .map(|p| {
            let h = land.height_at(*p) as f32;
            heights.partition_point(|x| *x < h) as f64 / heights.len() as f64
        })
        .sum();
    sum / points.len() as f64
}

//! Dead-end roads no building uses (our addition to thesis 3.2.4). A building farther than its frontage from
//! the roads gets a road of its own, and is then set beside that road's last metres (`generate`). Where that
//! spot is nearer another road, the building's parcel fronts the other road (3.3.1: the source is its projection
//! on the *closest* road), and its own road is left a dead end that no lot fronts: a stub whose end the parcels
//! around it wrap round, each wrap a few more contour edges. Before the parcels are drawn, such stubs go: a new
//! road that is a leaf of the network (its other roads touch it at one of its ends only), whose other end is no
//! connection point, and on which no building seed projects. Removing one may leave the road it branched from a
//! leaf no one uses in turn, so the pruning repeats until nothing changes.

use super::road_index::RoadIndex;
use super::Road;
use crate::geom::segment_distance;
use glam::DVec2;

/// Which of `roads` to keep: the first `existing` (the roads given to the generator) always, the others unless
/// they are unused dead ends (see the module documentation). `seeds` are the buildings' positions,
/// `connections` the connection points `Ψ`, `tolerance` the distance (m) within which two roads touch.
pub(crate) fn used_roads(
    roads: &[Road],
    existing: usize,
    seeds: &[DVec2],
    connections: &[DVec2],
    tolerance: f64,
) -> Vec<bool> {
    let mut keep = vec![true; roads.len()];
    loop {
        let kept: Vec<usize> = (0..roads.len())
            .filter(|&r| keep[r] && roads[r].points.len() >= 2)
            .collect();
        if kept.is_empty() {
            return keep;
        }
        let polylines: Vec<Road> = kept.iter().map(|&r| roads[r].clone()).collect();
        // the road of each of the index's segments, in the order it numbers them
        let owner: Vec<usize> = kept
            .iter()
            .flat_map(|&r| std::iter::repeat_n(r, roads[r].points.len() - 1))
            .collect();
        let index = RoadIndex::new(&polylines, 8.0 * tolerance.max(0.5));
        let mut used = vec![false; roads.len()];
        for &s in seeds {
            let p = index.project(s);
            if p.distance.is_finite() {
                if let Some(&r) = owner.get(p.segment) {
                    used[r] = true;
                }
            }
        }
        let touches = |p: DVec2, r: usize| {
            roads[r]
                .points
                .windows(2)
                .any(|w| segment_distance(p, w[0], w[1]) <= tolerance)
        };
        let mut changed = false;
        for &r in kept.iter().filter(|&&r| r >= existing && !used[r]) {
            let points = &roads[r].points;
            let ends = [points[0], points[points.len() - 1]];
            // where the other kept roads touch this one: at its ends, or their ends on it
            let mut contacts: Vec<DVec2> = Vec::new();
            for &o in kept.iter().filter(|&&o| o != r && keep[o]) {
                let other = &roads[o].points;
                for e in ends {
                    if touches(e, o) {
                        contacts.push(e);
                    }
                }
                for e in [other[0], other[other.len() - 1]] {
                    if touches(e, r) {
                        contacts.push(e);
                    }
                }
            }
            let leaf_at = ends.iter().position(|&e| {
                !contacts.is_empty() && contacts.iter().all(|c| c.distance(e) <= tolerance)
            });
            let Some(joined) = leaf_at else {
                continue;
            };
            let free = ends[1 - joined];
            if connections.iter().any(|c| c.distance(free) <= tolerance) {
                continue;
            }
            keep[r] = false;
            changed = true;
        }
        if !changed {
            return keep;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn road(points: &[(f64, f64)]) -> Road {
        Road {
            points: points.iter().map(|&(x, y)| DVec2::new(x, y)).collect(),
        }
    }

    #[test]
    fn unused_dead_ends_go_and_the_rest_stays() {
        let roads = [
            // an existing road, never pruned, though no one uses it
            road(&[(0.0, -50.0), (0.0, -80.0)]),
            // the through road from the connection point (0, 0)
            road(&[(0.0, 0.0), (100.0, 0.0)]),
            // a spur a house stands beside
            road(&[(20.0, 30.0), (20.0, 0.0)]),
            // a spur no one uses, and a spur off its end no one uses either
            road(&[(60.0, 25.0), (60.0, 0.0)]),
            road(&[(80.0, 40.0), (60.0, 25.0)]),
            // a loop between two roads, unused but no dead end
            road(&[(20.0, 15.0), (60.0, 15.0)]),
        ];
        let seeds = [DVec2::new(12.0, 28.0), DVec2::new(90.0, -8.0)];
        let keep = used_roads(&roads, 1, &seeds, &[DVec2::ZERO], 1e-3);
        assert_eq!(keep, [true, true, true, true, false, true]);
        // without the loop, the unused spur and the one off its end both go
        let keep = used_roads(&roads[..5], 1, &seeds, &[DVec2::ZERO], 1e-3);
        assert_eq!(keep, [true, true, true, false, false]);
        // a road ending at a connection point is a way out, not a dead end
        let keep = used_roads(&roads[..5], 1, &seeds, &[DVec2::new(80.0, 40.0)], 1e-3);
        assert_eq!(keep, [true, true, true, true, true]);
    }
}

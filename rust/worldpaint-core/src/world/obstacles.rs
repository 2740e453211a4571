//! What a world's instances keep off: the houses' footprints and the roads' carriageways (issue 43). A tile's
//! blocks are synthesized as everywhere else and their instances on an obstacle removed at once, before the next
//! block and the tile's border see them: the free ground keeps the color's density and pair correlation, and no
//! tree stands on a road or in a house. The roads' polylines are kept too: a color that learned how its content
//! stands from roads sees them as its roads (see [`super::synthesize_tile`]).

use crate::geom::{polygon_contains, DVec2};
use crate::graph::SegmentIndex;
use crate::spatial::{GridEntry, SpatialGrid};

/// The footprints and carriageways of a world: the roads' segments in a [`SegmentIndex`], the footprints by their
/// centres in a uniform grid searched as far as the widest footprint reaches from its centre.
#[derive(Clone, Debug, Default)]
pub struct Obstacles {
    footprints: Vec<Vec<DVec2>>,
    centres: Option<SpatialGrid>,
    /// Farthest a footprint's corner lies from its centre (m).
    reach: f64,
    roads: SegmentIndex,
    road_lines: Vec<Vec<DVec2>>,
    half_width: f64,
}

impl Obstacles {
    /// The obstacles of `footprints` (closed outlines, at least three points; others are skipped) and `roads`
    /// (polylines), each road `width` metres wide. Shapes with a coordinate that is not finite are skipped.
    pub fn new(footprints: &[Vec<DVec2>], roads: &[Vec<DVec2>], width: f64) -> Obstacles {
        let footprints: Vec<Vec<DVec2>> = footprints
            .iter()
            .filter(|f| f.len() >= 3 && f.iter().all(|p| p.is_finite()))
            .cloned()
            .collect();
        let centre = |f: &[DVec2]| f.iter().copied().sum::<DVec2>() / f.len() as f64;
        let reach = footprints
            .iter()
            .map(|f| f.iter().map(|p| p.distance(centre(f))).fold(0.0, f64::max))
            .fold(0.0, f64::max);
        let centres = (!footprints.is_empty()).then(|| {
            let (lo, hi) = footprints.iter().flatten().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            let mut grid = SpatialGrid::new(lo, hi, reach.max(1.0));
            for (k, f) in footprints.iter().enumerate() {
                grid.insert(GridEntry {
                    position: centre(f),
                    tag: 0,
                    id: k as u32,
                });
            }
            grid
        });
        let half_width = (width / 2.0).max(0.0);
        let road_lines: Vec<Vec<DVec2>> = roads
            .iter()
            .filter(|r| r.len() >= 2 && r.iter().all(|p| p.is_finite()))
            .cloned()
            .collect();
        let segments = if half_width > 0.0 {
            road_lines
                .iter()
                .flat_map(|r| r.windows(2))
                .map(|s| (s[0], s[1]))
                .collect()
        } else {
            Vec::new()
        };
        Obstacles {
            footprints,
            centres,
            reach,
            roads: SegmentIndex::new(segments),
            road_lines,
            half_width,
        }
    }

    /// No obstacle at all.
    pub fn is_empty(&self) -> bool {
        self.footprints.is_empty() && self.road_lines.is_empty()
    }

    /// The roads' polylines (those with every coordinate finite).
    pub fn roads(&self) -> &[Vec<DVec2>] {
        &self.road_lines
    }

    /// Whether `p` lies on a footprint or a carriageway.
    pub fn covers(&self, p: DVec2) -> bool {
        if self.half_width > 0.0 && self.roads.distance(p, 2.0 * self.half_width) <= self.half_width
        {
            return true;
        }
        let mut inside = false;
        if let Some(grid) = &self.centres {
            grid.for_each_within(p, self.reach, |e, _| {
                inside = inside || polygon_contains(&self.footprints[e.id as usize], p);
            });
        }
        inside
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn footprints_and_carriageways_are_covered_and_the_ground_beside_them_is_not() {
        let house = vec![
            DVec2::new(10.0, 10.0),
            DVec2::new(20.0, 10.0),
            DVec2::new(20.0, 18.0),
            DVec2::new(10.0, 18.0),
        ];
        let road = vec![
            DVec2::new(0.0, 50.0),
            DVec2::new(100.0, 50.0),
            DVec2::new(100.0, 150.0),
        ];
        let o = Obstacles::new(&[house], &[road], 4.0);
        assert!(o.covers(DVec2::new(15.0, 14.0)));
        assert!(!o.covers(DVec2::new(21.0, 14.0)));
        assert!(o.covers(DVec2::new(60.0, 51.9)) && !o.covers(DVec2::new(60.0, 52.1)));
        // round the bend and across an index cell's edge
        assert!(o.covers(DVec2::new(101.5, 51.5)) && o.covers(DVec2::new(99.0, 125.0)));
        assert!(!o.covers(DVec2::new(-3.0, 50.0)));
        assert!(Obstacles::new(&[], &[], 4.0).is_empty());
        // a shape with a coordinate that is not finite is skipped, not indexed over the whole plane
        let bad = Obstacles::new(
            &[vec![DVec2::new(f64::NAN, 0.0), DVec2::X, DVec2::Y]],
            &[],
            4.0,
        );
        assert!(bad.is_empty());
    }
}

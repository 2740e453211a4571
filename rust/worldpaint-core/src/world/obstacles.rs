//! What a world's instances keep off: the houses' footprints and the roads' carriageways (issue 43). A tile's
//! blocks are synthesized as everywhere else and their instances on an obstacle removed at once, before the next
//! block and the tile's border see them: the free ground keeps the color's density and pair correlation, and no
//! tree stands on a road or in a house.

use crate::geom::{polygon_contains, segment_distance, DVec2};
use std::collections::HashMap;

/// Side (m) of the cells the obstacles are indexed in.
const INDEX_CELL: f64 = 25.0;

/// One obstacle.
#[derive(Clone, Debug, PartialEq)]
enum Shape {
    /// A closed outline (a house's footprint).
    Polygon(Vec<DVec2>),
    /// A road's segment with its half-width.
    Segment(DVec2, DVec2, f64),
}

impl Shape {
    fn bbox(&self) -> (DVec2, DVec2) {
        match self {
            Shape::Polygon(points) => points.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            ),
            Shape::Segment(a, b, r) => (a.min(*b) - *r, a.max(*b) + *r),
        }
    }

    fn is_finite(&self) -> bool {
        match self {
            Shape::Polygon(points) => points.iter().all(|p| p.is_finite()),
            Shape::Segment(a, b, r) => a.is_finite() && b.is_finite() && r.is_finite(),
        }
    }

    fn covers(&self, p: DVec2) -> bool {
        match self {
            Shape::Polygon(points) => polygon_contains(points, p),
            Shape::Segment(a, b, r) => segment_distance(p, *a, *b) <= *r,
        }
    }
}

/// The footprints and carriageways of a world, indexed on a grid.
#[derive(Clone, Debug, Default)]
pub struct Obstacles {
    shapes: Vec<Shape>,
    cells: HashMap<(i64, i64), Vec<u32>>,
}

impl Obstacles {
    /// The obstacles of `footprints` (closed outlines, at least three points; others are skipped) and `roads`
    /// (polylines), each road `width` metres wide. Shapes with a coordinate that is not finite are skipped.
    pub fn new(footprints: &[Vec<DVec2>], roads: &[Vec<DVec2>], width: f64) -> Obstacles {
        let half = (width / 2.0).max(0.0);
        let mut shapes: Vec<Shape> = footprints
            .iter()
            .filter(|f| f.len() >= 3)
            .map(|f| Shape::Polygon(f.clone()))
            .collect();
        if half > 0.0 {
            shapes.extend(
                roads
                    .iter()
                    .flat_map(|r| r.windows(2))
                    .map(|s| Shape::Segment(s[0], s[1], half)),
            );
        }
        shapes.retain(Shape::is_finite);
        let mut cells: HashMap<(i64, i64), Vec<u32>> = HashMap::new();
        for (k, s) in shapes.iter().enumerate() {
            let (lo, hi) = s.bbox();
            let (a, b) = (cell_of(lo), cell_of(hi));
            for i in a.0..=b.0 {
                for j in a.1..=b.1 {
                    cells.entry((i, j)).or_default().push(k as u32);
                }
            }
        }
        Obstacles { shapes, cells }
    }

    /// No obstacle at all.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// Whether `p` lies on a footprint or a carriageway.
    pub fn covers(&self, p: DVec2) -> bool {
        self.cells
            .get(&cell_of(p))
            .is_some_and(|ks| ks.iter().any(|&k| self.shapes[k as usize].covers(p)))
    }
}

fn cell_of(p: DVec2) -> (i64, i64) {
    (
        (p.x / INDEX_CELL).floor() as i64,
        (p.y / INDEX_CELL).floor() as i64,
    )
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

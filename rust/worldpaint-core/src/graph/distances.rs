//! Distances from many points to the segments of a [`SegmentIndex`] at once, as [`SegmentIndex::distance`] reads
//! each: the points in blocks of about `BLOCK_POINTS` neighbours, and per block the segments that can be nearest
//! to one of its points gathered once. A ring search per point visits every cell within its distance; far from
//! short segments (an archipelago's coast, 40,000 lattice samples) that was most of reading a distance map.

use super::SegmentIndex;
use crate::geom::{segment_distance, DVec2};
use crate::spatial::{FlatGrid, GridEntry};
use rayon::prelude::*;

/// About how many points share a block.
const BLOCK_POINTS: f64 = 16.0;

impl SegmentIndex {
    /// `distance(points[i], max(i))` for every point, the same values.
    pub(crate) fn distances(
        &self,
        points: &[DVec2],
        max: impl Fn(usize) -> f64 + Sync,
    ) -> Vec<f64> {
        if self.segments.is_empty() {
            return vec![f64::INFINITY; points.len()];
        }
        let blocks = blocks_of(points);
        let nx = blocks.nx();
        let members = |b: usize| {
            let (first, end) = blocks.row_range(b / nx, b % nx, b % nx);
            &blocks.ids[first..end]
        };
        let per_block: Vec<Vec<f64>> = (0..blocks.n_cells())
            .into_par_iter()
            .map(|b| self.block_distances(points, members(b), &max))
            .collect();
        let mut out: Vec<f64> = (0..points.len()).map(&max).collect();
        for (b, values) in per_block.iter().enumerate() {
            for (&i, &v) in members(b).iter().zip(values) {
                out[i as usize] = v;
            }
        }
        out
    }

    /// The distances of the points `members` of one block. Where a point `p` is nearer than its `max` to its
    /// nearest segment `s`, `|c s| ≤ |p s| + |p c| ≤ d(c) + 2ρ` and `< max + ρ` (`c` the block's centre, `ρ` its
    /// reach): the segments within the lesser of those of `c` hold `s`.
    fn block_distances(
        &self,
        points: &[DVec2],
        members: &[u32],
        max: &impl Fn(usize) -> f64,
    ) -> Vec<f64> {
        if members.is_empty() {
            return Vec::new();
        }
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        let mut cap = f64::NEG_INFINITY;
        for &i in members {
            lo = lo.min(points[i as usize]);
            hi = hi.max(points[i as usize]);
            cap = cap.max(max(i as usize));
        }
        let c = (lo + hi) * 0.5;
        let reach = members
            .iter()
            .map(|&i| points[i as usize].distance(c))
            .fold(0.0, f64::max);
        let d_c = self.nearest_within(c, cap + reach).0;
        // a margin for rounding: a candidate too many costs one distance
        let r = (d_c + 2.0 * reach).min(cap + reach) * (1.0 + 1e-9) + 1e-9;
        let mut near = Vec::new();
        self.candidates(c - DVec2::splat(r), c + DVec2::splat(r), &mut near);
        let near: Vec<(DVec2, DVec2)> = near
            .into_iter()
            .map(|s| self.segments[s as usize])
            .filter(|&(a, b)| segment_distance(c, a, b) <= r)
            .collect();
        members
            .iter()
            .map(|&i| {
                let p = points[i as usize];
                // as the ring search keeps its best: `max` itself unless a segment is nearer
                near.iter()
                    .map(|&(a, b)| segment_distance(p, a, b))
                    .fold(max(i as usize), |best, d| if d < best { d } else { best })
            })
            .collect()
    }
}

/// The finite points in square blocks of about `BLOCK_POINTS` points (their box's area shared out), as the cells
/// of a grid whose ids are the points' indices (non-finite points in none: their distance is their `max`).
fn blocks_of(points: &[DVec2]) -> FlatGrid {
    let finite: Vec<u32> = (0..points.len() as u32)
        .filter(|&i| points[i as usize].is_finite())
        .collect();
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for &i in &finite {
        lo = lo.min(points[i as usize]);
        hi = hi.max(points[i as usize]);
    }
    let n = finite.len().max(1) as f64;
    let ext = (hi - lo).max(DVec2::splat(1e-9));
    // square blocks over a box's area, or along a line of points
    let side = (ext.x * ext.y * BLOCK_POINTS / n)
        .sqrt()
        .max(ext.max_element() * BLOCK_POINTS / n);
    FlatGrid::build(lo, hi, side, finite.len(), |k| GridEntry {
        position: points[finite[k] as usize],
        tag: 0,
        id: finite[k],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A coast of short segments, a lattice, scattered points, far and non-finite ones, each with its own reach:
    /// every distance is the one a single query reads, bit for bit.
    #[test]
    fn distances_in_blocks_are_the_single_queries() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let coast: Vec<(DVec2, DVec2)> = (0..400)
            .map(|i| {
                let (a, b) = (i as f64 * 0.0157, (i + 1) as f64 * 0.0157);
                let r = |t: f64| 60.0 + 12.0 * (5.0 * t).sin();
                (DVec2::from_angle(a) * r(a), DVec2::from_angle(b) * r(b))
            })
            .collect();
        let index = SegmentIndex::new(coast);
        let mut points: Vec<DVec2> = (0..150)
            .flat_map(|j| (0..150).map(move |i| DVec2::new(i as f64 - 75.0, j as f64 * 1.3 - 80.0)))
            .collect();
        points.extend((0..2000).map(|_| {
            DVec2::new(
                rng.random_range(-300.0..300.0),
                rng.random_range(-300.0..300.0),
            )
        }));
        points.extend([
            DVec2::new(f64::NAN, 1.0),
            DVec2::new(1e7, -1e7),
            DVec2::splat(f64::INFINITY),
        ]);
        let max = |i: usize| [4.0, 30.0, 500.0, f64::INFINITY][i % 4];
        let blocked = index.distances(&points, max);
        for (i, p) in points.iter().enumerate() {
            let single = index.distance(*p, max(i));
            assert!(
                blocked[i].to_bits() == single.to_bits(),
                "point {p}: {} in blocks, {single} alone",
                blocked[i]
            );
        }
        assert!(SegmentIndex::default()
            .distances(&points[..3], max)
            .iter()
            .all(|d| d.is_infinite()));
    }
}

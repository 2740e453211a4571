//! Distances from many points to the segments of a [`SegmentIndex`] at once, as [`SegmentIndex::distance`] reads
//! each: the points in blocks of about `BLOCK_POINTS` neighbours, and per block the segments that can be nearest
//! to one of its points gathered once. A ring search per point visits every cell within its distance; far from
//! short segments (an archipelago's coast, 40,000 lattice samples) that was most of reading a distance map.

use super::SegmentIndex;
use crate::geom::{segment_distance, DVec2};
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
        let blocks = Blocks::of(points);
        let per_block: Vec<Vec<f64>> = (0..blocks.len())
            .into_par_iter()
            .map(|b| self.block_distances(points, blocks.members(b), &max))
            .collect();
        let mut out: Vec<f64> = (0..points.len()).map(&max).collect();
        for (b, values) in per_block.iter().enumerate() {
            for (&i, &v) in blocks.members(b).iter().zip(values) {
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
        self.visit_candidates(c - DVec2::splat(r), c + DVec2::splat(r), |s| {
            near.push(s);
            true
        });
        near.sort_unstable();
        near.dedup();
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

/// The finite points in square blocks of about `BLOCK_POINTS` points (their box's area shared out), each block's
/// members listed together (non-finite points in none: their distance is their `max`).
struct Blocks {
    start: Vec<usize>,
    order: Vec<u32>,
}

impl Blocks {
    fn of(points: &[DVec2]) -> Blocks {
        let finite = |p: &DVec2| p.x.is_finite() && p.y.is_finite();
        let (mut lo, mut hi, mut n) = (
            DVec2::splat(f64::INFINITY),
            DVec2::splat(f64::NEG_INFINITY),
            0usize,
        );
        for p in points.iter().filter(|p| finite(p)) {
            lo = lo.min(*p);
            hi = hi.max(*p);
            n += 1;
        }
        let ext = (hi - lo).max(DVec2::splat(1e-9));
        // square blocks over a box's area, or along a line of points
        let side = (ext.x * ext.y * BLOCK_POINTS / n.max(1) as f64)
            .sqrt()
            .max(ext.max_element() * BLOCK_POINTS / n.max(1) as f64);
        let cells = |e: f64| ((e / side) as usize + 1).min(1 << 12);
        let (nx, ny) = (cells(ext.x), cells(ext.y));
        let block_of = |p: &DVec2| {
            let f = (*p - lo) / side;
            ((f.y as usize).min(ny - 1)) * nx + (f.x as usize).min(nx - 1)
        };
        let mut start = vec![0usize; nx * ny + 1];
        for p in points.iter().filter(|p| finite(p)) {
            start[block_of(p) + 1] += 1;
        }
        for b in 0..nx * ny {
            start[b + 1] += start[b];
        }
        let mut next = start.clone();
        let mut order = vec![0u32; n];
        for (i, p) in points.iter().enumerate().filter(|(_, p)| finite(p)) {
            let b = block_of(p);
            order[next[b]] = i as u32;
            next[b] += 1;
        }
        Blocks { start, order }
    }

    fn len(&self) -> usize {
        self.start.len() - 1
    }

    fn members(&self, b: usize) -> &[u32] {
        &self.order[self.start[b]..self.start[b + 1]]
    }
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

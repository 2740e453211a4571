//! The move mask of the road search (thesis 3.2.4, after GPMG10): a road is a chain of grid offsets `(dx, dy)`
//! with coprime coordinates and `max(|dx|, |dy|) ≤ k`, so roads are not bound to the eight grid directions.
//! Each move knows the nodes it passes over and its samples every half cell at most, so a long move cannot jump
//! over a ridge or a river; the table also holds the turn angles and the gauge of the heuristic.

use crate::geom::clip_segment_to_box;
use crate::grid::Grid;
use crate::village::land::Land;
use glam::DVec2;

/// A bilinear sample along a move: four (node offset, weight) taps, unused ones of weight 0 on the start node.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sample {
    taps: [(isize, f64); 4],
}

impl Sample {
    /// The sample at `q` (cells from the start node) on a grid `nx` nodes wide.
    fn at(q: DVec2, nx: isize) -> Sample {
        let (fx, fy) = (q.x.floor(), q.y.floor());
        let (tx, ty) = (q.x - fx, q.y - fy);
        let mut taps = [(0, 0.0); 4];
        for (t, (oi, oj, w)) in [
            (0, 0, (1.0 - tx) * (1.0 - ty)),
            (1, 0, tx * (1.0 - ty)),
            (0, 1, (1.0 - tx) * ty),
            (1, 1, tx * ty),
        ]
        .into_iter()
        .enumerate()
        {
            // a zero weight may lie off the grid: leave it on the start node
            if w > 1e-12 {
                taps[t] = ((fy as isize + oj) * nx + fx as isize + oi, w);
            }
        }
        Sample { taps }
    }
}

/// The bilinear value of a node map at sample `s` of a move from node `x`.
pub(super) fn sample(values: &[f32], x: usize, s: &Sample) -> f64 {
    s.taps
        .iter()
        .map(|&(d, w)| values[(x as isize + d) as usize] as f64 * w)
        .sum()
}

/// The bilinear indicator of a node set at sample `s` of a move from node `x`.
pub(super) fn sample_bool(values: &[bool], x: usize, s: &Sample) -> f64 {
    s.taps
        .iter()
        .map(|&(d, w)| {
            if values[(x as isize + d) as usize] {
                w
            } else {
                0.0
            }
        })
        .sum()
}

#[derive(Clone, Debug)]
pub(super) struct Move {
    pub(super) dx: i32,
    pub(super) dy: i32,
    /// Index offset of the end node.
    pub(super) delta: isize,
    /// Planar length (m).
    pub(super) length: f64,
    /// Index offsets of the nodes whose closed cell square meets the segment, both ends included.
    pub(super) cells: Vec<isize>,
    /// Those without the two ends.
    pub(super) inner: Vec<isize>,
    /// Samples at most half a cell apart, both ends included.
    pub(super) samples: Vec<Sample>,
}

impl Move {
    fn new(grid: &Grid, dx: i32, dy: i32) -> Move {
        let nx = grid.nx as isize;
        let end = DVec2::new(dx as f64, dy as f64);
        let mut cells = Vec::new();
        let mut inner = Vec::new();
        for j in dy.min(0)..=dy.max(0) {
            for i in dx.min(0)..=dx.max(0) {
                let c = DVec2::new(i as f64, j as f64);
                if clip_segment_to_box(DVec2::ZERO, end, c - 0.5 - 1e-9, c + 0.5 + 1e-9).is_some() {
                    let d = j as isize * nx + i as isize;
                    cells.push(d);
                    if (i, j) != (0, 0) && (i, j) != (dx, dy) {
                        inner.push(d);
                    }
                }
            }
        }
        let n = (2.0 * end.length()).ceil() as usize;
        let samples = (0..=n)
            .map(|s| {
                let q = DVec2::new((dx * s as i32) as f64, (dy * s as i32) as f64) / n as f64;
                Sample::at(q, nx)
            })
            .collect();
        Move {
            dx,
            dy,
            delta: dy as isize * nx + dx as isize,
            length: end.length() * grid.cell,
            cells,
            inner,
            samples,
        }
    }

    /// Steepest sub-segment grade along the move from node `x`.
    pub(super) fn steepest(&self, land: &Land, x: usize) -> f64 {
        let sub = self.length / (self.samples.len() - 1) as f64;
        let mut prev = sample(land.height(), x, &self.samples[0]);
        let mut steepest: f64 = 0.0;
        for s in &self.samples[1..] {
            let h = sample(land.height(), x, s);
            steepest = steepest.max((h - prev).abs() / sub);
            prev = h;
        }
        steepest
    }
}

/// The move mask of one grid and radius, with the turn angles and the heuristic's gauge.
#[derive(Clone, Debug)]
pub(super) struct MoveTable {
    pub(super) moves: Vec<Move>,
    /// `rev[m]` is the move opposite `m`.
    pub(super) rev: Vec<usize>,
    /// The moves of length one cell or one diagonal.
    pub(super) unit: Vec<usize>,
    /// Turn angle (radians) from move `a` to move `b` at `a * moves + b`.
    pub(super) turn: Vec<f64>,
    /// Facets `c` of the mask's gauge in the first octant: `gauge(v) = max c·v` for `v.x ≥ v.y ≥ 0` (cells).
    facets: Vec<DVec2>,
}

fn gcd(a: i32, b: i32) -> i32 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// The mask's offsets, coprime within `radius`, by increasing angle.
fn mask_offsets(radius: u32) -> Vec<(i32, i32)> {
    let k = radius as i32;
    let mut offsets: Vec<(i32, i32)> = Vec::new();
    for dy in -k..=k {
        for dx in -k..=k {
            if (dx, dy) != (0, 0) && gcd(dx.abs(), dy.abs()) == 1 {
                offsets.push((dx, dy));
            }
        }
    }
    offsets.sort_by(|a, b| {
        (a.1 as f64)
            .atan2(a.0 as f64)
            .total_cmp(&(b.1 as f64).atan2(b.0 as f64))
    });
    offsets
}

/// The facets of the gauge: between two consecutive first-octant directions `w0`, `w1` (unit), the `c` with
/// `c·w0 = c·w1 = 1`.
fn gauge_facets(offsets: &[(i32, i32)]) -> Vec<DVec2> {
    // first-octant directions, by increasing angle, as unit vectors
    let mut octant: Vec<DVec2> = offsets
        .iter()
        .filter(|&&(dx, dy)| dx >= dy && dy >= 0)
        .map(|&(dx, dy)| DVec2::new(dx as f64, dy as f64).normalize())
        .collect();
    octant.sort_by(|a, b| a.y.atan2(a.x).total_cmp(&b.y.atan2(b.x)));
    octant
        .windows(2)
        .map(|w| {
            let det = w[0].x * w[1].y - w[0].y * w[1].x;
            DVec2::new((w[1].y - w[0].y) / det, (w[0].x - w[1].x) / det)
        })
        .collect()
}

impl MoveTable {
    pub(super) fn new(grid: &Grid, radius: u32) -> MoveTable {
        let offsets = mask_offsets(radius);
        let moves: Vec<Move> = offsets
            .iter()
            .map(|&(dx, dy)| Move::new(grid, dx, dy))
            .collect();
        let m = moves.len();
        let rev = (0..m)
            .map(|a| {
                (0..m)
                    .find(|&b| moves[b].dx == -moves[a].dx && moves[b].dy == -moves[a].dy)
                    .unwrap_or(a)
            })
            .collect();
        let unit = (0..m)
            .filter(|&a| moves[a].dx.abs() <= 1 && moves[a].dy.abs() <= 1)
            .collect();
        let mut turn = vec![0.0; m * m];
        for a in 0..m {
            for b in 0..m {
                let u = DVec2::new(moves[a].dx as f64, moves[a].dy as f64);
                let v = DVec2::new(moves[b].dx as f64, moves[b].dy as f64);
                turn[a * m + b] = crate::graph::angle_between(u, v);
            }
        }
        MoveTable {
            moves,
            rev,
            unit,
            turn,
            facets: gauge_facets(&offsets),
        }
    }

    /// Length (cells) of the shortest chain of mask moves, with real multiplicities, covering `v` (cells).
    pub(super) fn gauge(&self, v: DVec2) -> f64 {
        let (a, b) = (v.x.abs(), v.y.abs());
        let w = DVec2::new(a.max(b), a.min(b));
        self.facets.iter().map(|c| c.dot(w)).fold(w.x, f64::max)
    }

    /// The move from node `a` to node `b`, if they are one move apart.
    pub(super) fn move_between(&self, grid: &Grid, a: usize, b: usize) -> Option<usize> {
        let (ai, aj) = grid.ij(a);
        let (bi, bj) = grid.ij(b);
        let (dx, dy) = (bi as i64 - ai as i64, bj as i64 - aj as i64);
        self.moves
            .iter()
            .position(|m| m.dx as i64 == dx && m.dy as i64 == dy)
    }

    /// The node one move `m` from node `x` = `(i, j)`, when it is on the grid.
    pub(super) fn target(
        &self,
        grid: &Grid,
        x: usize,
        (i, j): (usize, usize),
        m: usize,
    ) -> Option<usize> {
        let mv = &self.moves[m];
        let (ti, tj) = (i as i64 + mv.dx as i64, j as i64 + mv.dy as i64);
        if ti < 0 || tj < 0 || ti >= grid.nx as i64 || tj >= grid.ny as i64 {
            return None;
        }
        Some((x as isize + mv.delta) as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::grid;
    use super::*;

    #[test]
    fn mask_sizes() {
        let g = grid(20, 20);
        for (k, n) in [(1, 8), (2, 16), (3, 32), (4, 48)] {
            let t = MoveTable::new(&g, k);
            assert_eq!(t.moves.len(), n, "radius {k}");
            for (a, &b) in t.rev.iter().enumerate() {
                assert_eq!(t.moves[a].dx, -t.moves[b].dx);
                assert_eq!(t.moves[a].dy, -t.moves[b].dy);
            }
        }
    }

    #[test]
    fn gauge_is_exact_on_mask_directions_and_below_on_others() {
        let t = MoveTable::new(&grid(20, 20), 3);
        for mv in &t.moves {
            let v = DVec2::new(mv.dx as f64, mv.dy as f64);
            assert!((t.gauge(v) - v.length()).abs() < 1e-12);
        }
        // (5, 1) is covered by (3, 1) + (2, 0): 3.162 + 2 = 5.162 cells at best, Euclid 5.099
        let g = t.gauge(DVec2::new(5.0, 1.0));
        assert!(g > 5.099 && g <= 5.1623, "{g}");
    }

    #[test]
    fn move_cells_are_symmetric() {
        let g = grid(20, 20);
        let t = MoveTable::new(&g, 3);
        let x = g.index(10, 10);
        for (a, mv) in t.moves.iter().enumerate() {
            let y = (x as isize + mv.delta) as usize;
            let mut fwd: Vec<isize> = mv.cells.iter().map(|&d| x as isize + d).collect();
            let mut back: Vec<isize> = t.moves[t.rev[a]]
                .cells
                .iter()
                .map(|&d| y as isize + d)
                .collect();
            fwd.sort_unstable();
            back.sort_unstable();
            assert_eq!(fwd, back, "move {} {}", mv.dx, mv.dy);
        }
        // a diagonal move touches the two corner cells too
        let diag = t.moves.iter().find(|m| m.dx == 1 && m.dy == 1).unwrap();
        assert_eq!(diag.inner.len(), 2);
    }
}

//! The open shape grammar rules for façade elements (3.4.1–3.4.2): position adaptation by a displacement cost
//! kernel over a lattice of the wall surface, explored best-first from a priority queue, and shape adaptation
//! over a priority list of shapes (Algorithm 3). A rule succeeds at the first valid configuration and fails once
//! its tests are spent; the caller then builds plain wall.

use super::geometry::outward;
use crate::search::MinHeap;
use glam::DVec2;

/// The terrain height under a point of the plane.
pub(crate) type Ground<'a> = dyn Fn(DVec2) -> f64 + Sync + 'a;

/// Lattice step of the position adaptation on the wall surface (m).
pub(super) const STEP: f64 = 0.1;
/// Openings stand this far in front of their wall (m).
pub(super) const OPENING_OFFSET: f64 = 0.03;
/// Height an opening keeps above the terrain line along its wall (m), so that no vertex is below the ground.
pub(super) const CLEARANCE: f64 = 0.1;
/// Spacing of the terrain samples kept per wall (m), at most.
const SAMPLE: f64 = 0.05;
/// Smallest free wall between two openings (m).
const GAP: f64 = 0.3;
/// Largest number of positions tried per shape before the rule fails (the "user-defined number of tests").
pub(super) const MAX_TESTS: usize = 400;

/// The displacement cost kernel `K(dx, dy)` for one lattice step: a vertical move costs ten horizontal ones and a
/// diagonal one a little more than a vertical one (Fig. 3.13). An element thus slides along its floor line
/// before it leaves it, as long as the terrain falls along the wall by more than one in ten.
pub(super) fn kernel(dx: i32, dy: i32) -> u32 {
    match (dx != 0, dy != 0) {
        (false, false) => 0,
        (true, false) => 1,
        (false, true) => 10,
        (true, true) => 11,
    }
}

const NEIGHBOURS: [(i32, i32); 8] = [
    (-1, 0),
    (1, 0),
    (0, 1),
    (0, -1),
    (-1, 1),
    (1, 1),
    (-1, -1),
    (1, -1),
];

/// A door or window shape: width and height, and the sill above the storey floor where it first goes (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Shape {
    pub name: &'static str,
    pub width: f64,
    pub height: f64,
    pub sill: f64,
}

/// An opening on a wall: along the wall `u0..u1`, above the storey floor `v0..v1` (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Rect {
    pub u0: f64,
    pub u1: f64,
    pub v0: f64,
    pub v1: f64,
}

impl Rect {
    /// The shape with its bottom centre at `at` (centre along the wall, sill above the floor).
    pub(super) fn of(shape: &Shape, at: DVec2) -> Rect {
        Rect {
            u0: at.x - shape.width * 0.5,
            u1: at.x + shape.width * 0.5,
            v0: at.y,
            v1: at.y + shape.height,
        }
    }

    fn near(&self, o: &Rect, gap: f64) -> bool {
        self.u0 < o.u1 + gap && o.u0 < self.u1 + gap && self.v0 < o.v1 + gap && o.v0 < self.v1 + gap
    }
}

/// One outer wall, from corner `a` along `dir` for `len`, with the terrain sampled along the line where its
/// openings stand.
pub(super) struct Wall {
    pub a: DVec2,
    pub dir: DVec2,
    pub normal: DVec2,
    pub len: f64,
    step: f64,
    samples: Vec<f64>,
}

impl Wall {
    /// The wall `a..b` of a counter-clockwise footprint; `None` when the terrain is not finite along it.
    pub(super) fn new(a: DVec2, b: DVec2, ground: &Ground) -> Option<Wall> {
        let len = (b - a).length();
        let n = ((len / SAMPLE).ceil() as usize).max(1);
        let mut wall = Wall {
            a,
            dir: (b - a) / len,
            normal: outward(b - a),
            len,
            step: len / n as f64,
            samples: Vec::with_capacity(n + 1),
        };
        for i in 0..=n {
            let g = ground(wall.at(i as f64 * wall.step));
            if !g.is_finite() {
                return None;
            }
            wall.samples.push(g);
        }
        Some(wall)
    }

    /// The point `u` along the wall, on the line of its openings.
    pub(super) fn at(&self, u: f64) -> DVec2 {
        self.a + self.dir * u + self.normal * OPENING_OFFSET
    }

    /// Lowest and highest sampled terrain strictly inside `u0..u1`.
    fn sampled(&self, u0: f64, u1: f64) -> (f64, f64) {
        let first = ((u0 / self.step).floor() + 1.0).max(0.0) as usize;
        let last = (((u1 / self.step).ceil() - 1.0).max(0.0) as usize).min(self.samples.len() - 1);
        let mut range = (f64::INFINITY, f64::NEG_INFINITY);
        for &g in self.samples.get(first..=last).unwrap_or(&[]) {
            range = (range.0.min(g), range.1.max(g));
        }
        range
    }
}

/// Where a rule looks for a valid position: one wall of one storey, the free band of it, and what is built there.
pub(super) struct Site<'a> {
    pub wall: &'a Wall,
    pub ground: &'a Ground<'a>,
    /// Height of the storey floor.
    pub floor: f64,
    /// Openings already on this wall and storey.
    pub placed: &'a [Rect],
    /// The opening stays within `u_lo..u_hi` along the wall and `v_lo..v_hi` above the floor.
    pub u_lo: f64,
    pub u_hi: f64,
    pub v_lo: f64,
    pub v_hi: f64,
    /// Whether the element may leave its floor line (windows) or only slide along it (doors).
    pub vertical: bool,
    /// Highest the bottom of the opening may stand above the terrain (a door one can still reach by steps).
    pub reach: Option<f64>,
}

/// A successful rule: which shape of the list, where it was first tried and where it went.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Placement {
    pub shape: usize,
    pub first: DVec2,
    pub at: DVec2,
}

impl Site<'_> {
    /// The external constraints: away from the other openings, above the terrain line with a clearance, and
    /// (for doors) not out of reach above it.
    pub(super) fn valid(&self, r: &Rect) -> bool {
        if self.placed.iter().any(|p| p.near(r, GAP)) {
            return false;
        }
        let z = self.floor + r.v0;
        let (lo, hi) = self.wall.sampled(r.u0, r.u1);
        if z < hi + CLEARANCE {
            return false;
        }
        let g0 = (self.ground)(self.wall.at(r.u0));
        let g1 = (self.ground)(self.wall.at(r.u1));
        // Written so that a NaN terrain fails the test.
        if !(z >= g0.max(g1) + CLEARANCE) {
            return false;
        }
        match self.reach {
            Some(reach) => z - lo.min(g0).min(g1) <= reach,
            None => true,
        }
    }

    /// Whether no position of the band can hold the shape clear of the terrain, so the search need not run.
    fn hopeless(&self, shape: &Shape) -> bool {
        let bottom = if self.vertical {
            self.v_hi - shape.height
        } else {
            shape.sill
        };
        // Every position of width above the sample spacing covers a sample, none lower than the lowest.
        let (lo, _) = self.wall.sampled(self.u_lo, self.u_hi);
        self.floor + bottom < lo + CLEARANCE
    }

    /// Position adaptation: from `first` (centre along the wall, sill), the lattice positions in order of the
    /// cost `c(p) + K(dx, dy)` of the cheapest path of kernel moves, until one is valid or `MAX_TESTS` are spent.
    pub(super) fn adapt_position(&self, shape: &Shape, first: DVec2) -> Option<DVec2> {
        let half = shape.width * 0.5;
        let iu_lo = ((self.u_lo + half - first.x) / STEP - 1e-9).ceil();
        let iu_hi = ((self.u_hi - half - first.x) / STEP + 1e-9).floor();
        let (iv_lo, iv_hi) = if self.vertical {
            (
                ((self.v_lo - first.y) / STEP - 1e-9).ceil(),
                ((self.v_hi - shape.height - first.y) / STEP + 1e-9).floor(),
            )
        } else if first.y >= self.v_lo - 1e-9 && first.y + shape.height <= self.v_hi + 1e-9 {
            (0.0, 0.0)
        } else {
            return None;
        };
        // No farther than the tests can reach: each lattice step away from the start costs one test at least.
        let reach = MAX_TESTS as f64;
        let (iu_lo, iu_hi) = (iu_lo.max(-reach), iu_hi.min(reach));
        let (iv_lo, iv_hi) = (iv_lo.max(-reach), iv_hi.min(reach));
        if !(iu_lo <= iu_hi && iv_lo <= iv_hi) {
            return None;
        }
        let (iu_lo, iu_hi, iv_lo, iv_hi) = (iu_lo as i32, iu_hi as i32, iv_lo as i32, iv_hi as i32);
        let nu = (iu_hi - iu_lo + 1) as usize;
        let nv = (iv_hi - iv_lo + 1) as usize;
        let index = |iu: i32, iv: i32| (iv - iv_lo) as usize * nu + (iu - iu_lo) as usize;
        let mut best = vec![u32::MAX; nu * nv];
        // equal costs pop in the order they were queued
        let mut queue = MinHeap::new();
        let start = (0.clamp(iu_lo, iu_hi), 0.clamp(iv_lo, iv_hi));
        best[index(start.0, start.1)] = 0;
        let mut order = 0u32;
        queue.push(0.0, (order, start.0, start.1));
        let mut tests = 0;
        while let Some(entry) = queue.pop() {
            let (_, iu, iv) = entry.item;
            // kernel costs are small integers: exact in an f64
            let cost = entry.cost as u32;
            if cost > best[index(iu, iv)] {
                continue;
            }
            let at = DVec2::new(first.x + iu as f64 * STEP, first.y + iv as f64 * STEP);
            if self.valid(&Rect::of(shape, at)) {
                return Some(at);
            }
            tests += 1;
            if tests >= MAX_TESTS {
                return None;
            }
            for (dx, dy) in NEIGHBOURS {
                let (u, v) = (iu + dx, iv + dy);
                if u < iu_lo || u > iu_hi || v < iv_lo || v > iv_hi {
                    continue;
                }
                let c = cost + kernel(dx, dy);
                let i = index(u, v);
                if c < best[i] {
                    best[i] = c;
                    order += 1;
                    queue.push(c as f64, (order, u, v));
                }
            }
        }
        None
    }

    /// Algorithm 3: for each shape of the priority list, position adaptation from the shape's place on the
    /// floor line at `centre`; the first success is kept, and `None` (plain wall) when every shape fails.
    pub(super) fn place(&self, shapes: &[Shape], centre: f64) -> Option<Placement> {
        shapes.iter().enumerate().find_map(|(i, s)| {
            let first = DVec2::new(centre, s.sill);
            if self.hopeless(s) {
                return None;
            }
            self.adapt_position(s, first).map(|at| Placement {
                shape: i,
                first,
                at,
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHAPES: [Shape; 3] = [
        Shape {
            name: "tall",
            width: 0.9,
            height: 1.3,
            sill: 0.9,
        },
        Shape {
            name: "square",
            width: 0.8,
            height: 0.8,
            sill: 1.4,
        },
        Shape {
            name: "small",
            width: 0.6,
            height: 0.6,
            sill: 1.6,
        },
    ];

    /// One window in the middle of a 4 m wall along x whose storey floor is at 0.5 m.
    fn place(ground: &Ground) -> Option<Placement> {
        let wall = Wall::new(DVec2::ZERO, DVec2::new(4.0, 0.0), ground)?;
        let site = Site {
            wall: &wall,
            ground,
            floor: 0.5,
            placed: &[],
            u_lo: 0.4,
            u_hi: 3.6,
            v_lo: 0.3,
            v_hi: 2.65,
            vertical: true,
            reach: None,
        };
        site.place(&SHAPES, 2.0)
    }

    #[test]
    fn a_mound_moves_the_window_along_its_floor_line() {
        // The mound is cleared by 1.1 m sideways (11 horizontal steps) or 0.2 m up (2 vertical ones, cost 20).
        let p = place(&|p: DVec2| if (p.x - 2.0).abs() < 0.6 { 1.5 } else { 0.0 }).unwrap();
        assert_eq!(p.shape, 0);
        assert_eq!(p.at.y, p.first.y);
        assert!(((p.at.x - p.first.x).abs() - 1.1).abs() < 1e-9, "{p:?}");
    }

    #[test]
    fn a_raised_ground_line_lifts_the_window() {
        // Level along the wall: sliding cannot help, two vertical steps do (sill 1.1 m over the needed 1.05 m).
        let p = place(&|_| 1.45).unwrap();
        assert_eq!((p.shape, p.at.x), (0, p.first.x));
        assert!((p.at.y - 1.1).abs() < 1e-9, "{p:?}");
    }

    #[test]
    fn a_nearly_buried_wall_takes_a_smaller_shape_and_a_buried_one_none() {
        // 1.8 m of terrain over the floor: the tall and square windows no longer fit under the lintel.
        let p = place(&|_| 2.3).unwrap();
        assert_eq!(p.shape, 2);
        assert!(p.at.y >= 1.9 - 1e-9 && p.at.y + SHAPES[2].height <= 2.65 + 1e-9);
        assert_eq!(place(&|_| 2.6), None);
        // A terrain that is not a number is never clear of the opening.
        assert_eq!(
            place(&|p: DVec2| if p.x > 1.0 { f64::NAN } else { 0.0 }),
            None
        );
    }

    #[test]
    fn the_kernel_prefers_horizontal_moves() {
        assert!(kernel(1, 0) < kernel(0, 1) && kernel(0, 1) < kernel(1, 1));
        assert_eq!(kernel(-1, 0), kernel(1, 0));
        assert_eq!(kernel(0, 0), 0);
    }
}

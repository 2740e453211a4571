//! What the arrangement tests share: elements, lattice references, growth options and the figures a user checks.

use std::collections::HashMap;

use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use worldpaint_core::{
    grow_arrangement, Arrangement, Element, GrowthOptions, ReferenceArrangement, Region,
    RotationMode,
};

pub fn element(position: DVec2, symbol: u32) -> Element {
    Element {
        position,
        symbol,
        rotation: 0.0,
        scale: 1.0,
    }
}

pub fn rect(min: (f64, f64), max: (f64, f64)) -> Region {
    Region::Rect {
        min: DVec2::new(min.0, min.1),
        max: DVec2::new(max.0, max.1),
    }
}

/// A jittered lattice of `side` × `side` elements, 1 m apart; `symbol` gives each (row, column) its symbol.
pub fn lattice(hexagonal: bool, side: usize, symbol: impl Fn(usize, usize) -> u32) -> Vec<Element> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut elements = Vec::new();
    for row in 0..side {
        for col in 0..side {
            let (x, y) = if hexagonal {
                (
                    col as f64 + 0.5 * (row % 2) as f64,
                    row as f64 * 3f64.sqrt() / 2.0,
                )
            } else {
                (col as f64, row as f64)
            };
            let jitter = DVec2::new(rng.random_range(-0.03..0.03), rng.random_range(-0.03..0.03));
            elements.push(element(DVec2::new(x, y) + jitter, symbol(row, col)));
        }
    }
    elements
}

pub fn hexagonal_reference() -> ReferenceArrangement {
    ReferenceArrangement::new(lattice(true, 7, |_, _| 0)).expect("a lattice is a valid reference")
}

pub fn options(rotation: RotationMode) -> GrowthOptions {
    GrowthOptions {
        rotation,
        seed: 11,
        relax_every: 50,
        ..GrowthOptions::default()
    }
}

/// The closest pair of points (brute force over a grid of cells of side `cell`).
/// `reference` grown over `region` from the origin, keeping its orientation.
pub fn grown_from_centre(reference: &ReferenceArrangement, region: &Region) -> Arrangement {
    grow_arrangement(reference, region, DVec2::ZERO, &options(RotationMode::None)).expect("grows")
}

pub fn closest_pair(points: &[DVec2], cell: f64) -> f64 {
    let key = |p: DVec2| ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, p) in points.iter().enumerate() {
        grid.entry(key(*p)).or_default().push(i);
    }
    let mut closest = f64::INFINITY;
    for (i, p) in points.iter().enumerate() {
        let (cx, cy) = key(*p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for &j in grid.get(&(cx + dx, cy + dy)).map_or(&[][..], |v| &v[..]) {
                    if j > i {
                        closest = closest.min(p.distance(points[j]));
                    }
                }
            }
        }
    }
    closest
}

pub fn positions(a: &Arrangement) -> Vec<DVec2> {
    a.elements.iter().map(|e| e.position).collect()
}

/// The share of `which` elements whose ring has as many neighbours as their reference element's.
pub fn ring_share(reference: &ReferenceArrangement, a: &Arrangement, which: &[usize]) -> f64 {
    let neighbours = a.neighbours();
    let same = which
        .iter()
        .filter(|&&i| neighbours[i].len() == reference.ring(a.sub_ids[i]).len())
        .count();
    same as f64 / which.len().max(1) as f64
}

/// Edge-direction histogram modulo π, 12 bins of 15° centred on multiples of 15°.
pub fn angle_histogram(edges: &[(usize, usize)], position: impl Fn(usize) -> DVec2) -> Vec<f64> {
    let bins = 12;
    let width = std::f64::consts::PI / bins as f64;
    let mut hist = vec![0.0; bins];
    for &(a, b) in edges {
        let d = position(b) - position(a);
        let angle = (d.y.atan2(d.x) + 0.5 * width).rem_euclid(std::f64::consts::PI);
        hist[((angle / width) as usize).min(bins - 1)] += 1.0;
    }
    let total: f64 = hist.iter().sum();
    hist.iter().map(|h| h / total.max(1.0)).collect()
}

pub fn total_variation(a: &[f64], b: &[f64]) -> f64 {
    0.5 * a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum::<f64>()
}

/// Each point's distance to its nearest other point.
pub fn nearest_distances(points: &[DVec2]) -> Vec<f64> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            points
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, q)| p.distance(*q))
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

/// The lattices a user places by hand as references.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatticeKind {
    Hexagonal,
    Square,
    /// Running bond: bricks twice as long as high, each row shifted by half a brick.
    RunningBond,
    /// A square lattice of two symbols alternating like a checkerboard's squares.
    Checkerboard,
}

impl LatticeKind {
    pub const ALL: [LatticeKind; 4] = [
        LatticeKind::Hexagonal,
        LatticeKind::Square,
        LatticeKind::RunningBond,
        LatticeKind::Checkerboard,
    ];

    pub fn name(self) -> &'static str {
        match self {
            LatticeKind::Hexagonal => "hexagonal",
            LatticeKind::Square => "square",
            LatticeKind::RunningBond => "running bond",
            LatticeKind::Checkerboard => "checkerboard",
        }
    }

    /// Elements per square metre of the exact lattice (its nearest neighbours 1 m apart).
    pub fn density(self) -> f64 {
        match self {
            LatticeKind::Hexagonal => 2.0 / 3f64.sqrt(),
            // a brick of w × h with w = √2, h = 1/√2 (its diagonal neighbours 1 m away)
            _ => 1.0,
        }
    }
}

/// A reference of about 50 elements of `lattice` (nearest neighbours 1 m apart) placed by hand: turned by `turn`
/// radians about its middle and each element moved by a normal offset of standard deviation `noise` m in x and y.
pub fn hand_placed(lattice: LatticeKind, turn: f64, noise: f64, seed: u64) -> Vec<Element> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (rows, cols) = match lattice {
        LatticeKind::RunningBond => (10, 5),
        _ => (7, 7),
    };
    let mut elements = Vec::new();
    for row in 0..rows {
        for col in 0..cols {
            let (r, c) = (row as f64, col as f64);
            let odd = (row % 2) as f64;
            let (position, symbol) = match lattice {
                LatticeKind::Hexagonal => (DVec2::new(c + 0.5 * odd, r * 3f64.sqrt() / 2.0), 0),
                LatticeKind::Square => (DVec2::new(c, r), 0),
                LatticeKind::Checkerboard => (DVec2::new(c, r), ((row + col) % 2) as u32),
                LatticeKind::RunningBond => {
                    let (w, h) = (2f64.sqrt(), 0.5f64.sqrt());
                    (DVec2::new((c + 0.5 * odd) * w, r * h), 0)
                }
            };
            elements.push(element(position, symbol));
        }
    }
    let middle = elements.iter().map(|e| e.position).sum::<DVec2>() / elements.len() as f64;
    let rotation = DVec2::from_angle(turn);
    for e in &mut elements {
        let jitter = DVec2::new(normal(&mut rng), normal(&mut rng)) * noise;
        e.position = rotation.rotate(e.position - middle) + jitter;
    }
    elements
}

/// A standard normal draw (Box–Muller).
pub fn normal(rng: &mut impl Rng) -> f64 {
    let u: f64 = rng.random_range(f64::EPSILON..1.0);
    let v: f64 = rng.random_range(0.0..std::f64::consts::TAU);
    (-2.0 * u.ln()).sqrt() * v.cos()
}

//! Generating processes for demo scenes, tests and benchmarks (all seeded, deterministic): the kinds of
//! arrangement the paper's examples are made of (Section 6, "Examples"; Figure 1's trees, rocks and grass) —
//! uniform (Poisson), clustered (Thomas), hard-core (dart throwing) — a multi-category scene on a slope, a
//! smooth demo terrain and rougher ones. Also the discrete Laplace equation's residual, recomputed independently of
//! the terrain-edit solvers that the tests check against it.

use crate::geom::{DVec2, Region};
use crate::scene::{Category, CategoryKind, Contour, Instance, Path, Scene};
use crate::sketch::SketchStroke;
use crate::spatial::{GridEntry, SpatialGrid};
use crate::terrain::Heightfield;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::f64::consts::TAU;

fn gaussian<R: Rng>(rng: &mut R) -> f64 {
    let u1: f64 = rng.random::<f64>().max(1e-300);
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
}

/// A Poisson-distributed count: exact (Knuth) below a mean of 50, normal approximation above.
pub(crate) fn poisson_count<R: Rng>(mean: f64, rng: &mut R) -> usize {
    if !(mean > 0.0) || !mean.is_finite() {
        return 0;
    }
    if mean < 50.0 {
        let l = (-mean).exp();
        let mut k = 0usize;
        let mut p = 1.0;
        loop {
            p *= rng.random::<f64>();
            if p <= l {
                return k;
            }
            k += 1;
        }
    }
    (mean + mean.sqrt() * gaussian(rng)).round().max(0.0) as usize
}

fn uniform_in_box<R: Rng>(lo: DVec2, hi: DVec2, rng: &mut R) -> DVec2 {
    DVec2::new(
        lo.x + rng.random::<f64>() * (hi.x - lo.x),
        lo.y + rng.random::<f64>() * (hi.y - lo.y),
    )
}

/// Poisson process of intensity `density` (per m²) in the region.
pub fn uniform_points(region: &Region, density: f64, seed: u64) -> Vec<DVec2> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (lo, hi) = region.bbox();
    let box_area = (hi.x - lo.x) * (hi.y - lo.y);
    let n = poisson_count(density * box_area, &mut rng);
    (0..n)
        .map(|_| uniform_in_box(lo, hi, &mut rng))
        .filter(|p| region.contains(*p))
        .collect()
}

/// Thomas cluster process: parents Poisson(`parent_density`), each with Poisson(`children_mean`) children at
/// isotropic Gaussian offsets of deviation `sigma`; parents are drawn in the region grown by 4σ, so clusters
/// crossing the border are not thinned out. Only the children inside the region are returned.
pub fn clustered_points(
    region: &Region,
    parent_density: f64,
    children_mean: f64,
    sigma: f64,
    seed: u64,
) -> Vec<DVec2> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (lo, hi) = region.bbox();
    let grow = DVec2::splat(4.0 * sigma.max(0.0));
    let (plo, phi) = (lo - grow, hi + grow);
    let n_parents = poisson_count(parent_density * (phi.x - plo.x) * (phi.y - plo.y), &mut rng);
    let mut out = Vec::new();
    for _ in 0..n_parents {
        let parent = uniform_in_box(plo, phi, &mut rng);
        let n = poisson_count(children_mean, &mut rng);
        for _ in 0..n {
            let p = parent + DVec2::new(gaussian(&mut rng), gaussian(&mut rng)) * sigma;
            if region.contains(p) {
                out.push(p);
            }
        }
    }
    out
}

/// Hard-core arrangement by random sequential adsorption (dart throwing): uniform candidates are kept when no
/// kept point is closer than `min_distance`, until `density × area` points or 50× that many attempts.
pub fn hard_core_points(region: &Region, density: f64, min_distance: f64, seed: u64) -> Vec<DVec2> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let want = (density * region.area()).round().max(0.0) as usize;
    let (lo, hi) = region.bbox();
    let mut grid = SpatialGrid::new(lo, hi, min_distance.max(1e-9));
    let mut out = Vec::with_capacity(want);
    for _ in 0..want.saturating_mul(50) {
        if out.len() >= want {
            break;
        }
        let p = uniform_in_box(lo, hi, &mut rng);
        if !region.contains(p) || grid.any_closer_than(p, min_distance, None) {
            continue;
        }
        grid.insert(GridEntry {
            position: p,
            tag: 0,
            id: out.len() as u32,
        });
        out.push(p);
    }
    out
}

/// Smooth hills: a sum of a few seeded sinusoidal waves, amplitude ~5% of the size. Deterministic.
pub fn demo_terrain(size: f64, cell: f64, seed: u64) -> Heightfield {
    let size = if size.is_finite() && size > 0.0 {
        size
    } else {
        100.0
    };
    let cell = if cell.is_finite() && cell > 0.0 {
        cell
    } else {
        size / 256.0
    };
    let n = ((size / cell).round() as usize + 1).clamp(2, 4096);
    let cell = size / (n - 1) as f64;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let waves: Vec<(DVec2, f64, f64)> = (0..6)
        .map(|k| {
            let angle = rng.random::<f64>() * TAU;
            let wavelength = size / (1.0 + k as f64 + rng.random::<f64>());
            let phase = rng.random::<f64>() * TAU;
            let amp = 0.05 * size / (1.0 + k as f64);
            (
                DVec2::new(angle.cos(), angle.sin()) * (TAU / wavelength),
                phase,
                amp,
            )
        })
        .collect();
    let heights = (0..n * n)
        .map(|idx| {
            let p = DVec2::new((idx % n) as f64, (idx / n) as f64) * cell;
            waves
                .iter()
                .map(|(k, ph, a)| a * (k.dot(p) + ph).sin())
                .sum::<f64>() as f32
        })
        .collect();
    // the grid is valid by construction (n ≥ 2, finite heights)
    match Heightfield::new(DVec2::ZERO, cell, n, n, heights) {
        Ok(h) => h,
        Err(_) => flat(n, cell),
    }
}

/// A terrain for villages, `size` metres square from the origin: a coast on the west (heights below 0 for
/// x < 0.12·size, the sea when the water level is 0), land rising gently eastwards, a hill 70 m high centred at
/// (0.6, 0.55)·size with slopes up to about 12°, and a few metres of rolling relief.
pub fn village_terrain(size: f64, cell: f64, seed: u64) -> Heightfield {
    let size = if size.is_finite() && size > 0.0 {
        size
    } else {
        1000.0
    };
    let relief = demo_terrain(size, cell, seed);
    let scale = size / 1000.0;
    let centre = DVec2::new(0.6, 0.55) * size;
    let heights = (0..relief.nx * relief.ny)
        .map(|k| {
            let p = DVec2::new((k % relief.nx) as f64, (k / relief.nx) as f64) * relief.cell;
            let coast = (p.x - 0.12 * size) * 0.04;
            let hill = 70.0
                * scale
                * (-(p - centre).length_squared() / (2.0 * (0.2 * size).powi(2))).exp();
            // the demo relief is 5 % of the size high: keep a tenth of it
            (coast + hill + 0.1 * relief.heights[k] as f64) as f32
        })
        .collect();
    Heightfield::new(relief.origin, relief.cell, relief.nx, relief.ny, heights)
        .unwrap_or_else(|_| flat(relief.nx, relief.cell))
}

/// [`village_terrain`] with fine relief added: seeded waves of wavelengths from `size / 16` down to 3 cells,
/// each as high as 0.5 % of its wavelength (a fractal spectrum), so a terrain edit has detail to keep.
pub fn rough_terrain(size: f64, cell: f64, seed: u64) -> Heightfield {
    let base = village_terrain(size, cell, seed);
    let size = base.cell * (base.nx - 1) as f64;
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed_f00d);
    let (longest, shortest) = (size / 16.0, 3.0 * base.cell);
    let count = 24;
    let waves: Vec<(DVec2, f64, f64)> = (0..count)
        .map(|k| {
            let t = k as f64 / (count - 1) as f64;
            let wavelength = longest * (shortest / longest).powf(t);
            let angle = rng.random::<f64>() * TAU;
            let phase = rng.random::<f64>() * TAU;
            (
                DVec2::new(angle.cos(), angle.sin()) * (TAU / wavelength),
                phase,
                0.005 * wavelength,
            )
        })
        .collect();
    let nx = base.nx;
    let heights: Vec<f32> = base
        .heights
        .par_iter()
        .enumerate()
        .map(|(idx, h)| {
            let p = DVec2::new((idx % nx) as f64, (idx / nx) as f64) * base.cell;
            let fine: f64 = waves
                .iter()
                .map(|(k, ph, a)| a * (k.dot(p) + ph).sin())
                .sum();
            (*h as f64 + fine) as f32
        })
        .collect();
    match Heightfield::new(base.origin, base.cell, base.nx, base.ny, heights) {
        Ok(h) => h,
        Err(_) => base,
    }
}

fn flat(n: usize, cell: f64) -> Heightfield {
    Heightfield {
        origin: DVec2::ZERO,
        cell,
        nx: n,
        ny: n,
        heights: vec![0.0; n * n],
        maps: Default::default(),
    }
}

/// Terrain of the slope scene: ridges along Y with slopes sweeping 0..45° across X (period `size / 4`).
fn slope_terrain(size: f64) -> Heightfield {
    let n = 257;
    let cell = size / (n - 1) as f64;
    let wavelength = size / 4.0;
    let k = TAU / wavelength;
    // max slope atan(amp k) = 45°
    let amp = 1.0 / k;
    let heights = (0..n * n)
        .map(|idx| (amp * (k * (idx % n) as f64 * cell).sin()) as f32)
        .collect();
    match Heightfield::new(DVec2::ZERO, cell, n, n, heights) {
        Ok(h) => h,
        Err(_) => flat(n, cell),
    }
}

/// Multi-category exemplar on a slope (square `size × size` from the origin): trees only on 20–35° slopes
/// (hard core 3 m), rocks anywhere (Poisson), grass clustered around the rocks (σ = 2 m, 12 per rock on
/// average) over a sparse uniform background. Categories in priority order: tree, rock, grass.
pub fn slope_scene(size: f64, seed: u64) -> Scene {
    let size = if size.is_finite() && size > 0.0 {
        size
    } else {
        200.0
    };
    let terrain = slope_terrain(size);
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(size),
    };
    let categories = vec![
        Category::distribution("tree", "vegetation", 0),
        Category::distribution("rock", "vegetation", 1),
        Category::distribution("grass", "vegetation", 2),
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5105_e5ce);
    let mut instances = Vec::new();
    let mut push = |p: DVec2, category: usize, rng: &mut ChaCha8Rng| {
        instances.push(Instance {
            position: p,
            rotation: rng.random::<f64>() * TAU,
            scale: 0.8 + 0.4 * rng.random::<f64>(),
            category,
            prototype: rng.random_range(0..3u32),
            locked: false,
            tint: 0.0,
        });
    };
    let (lo_slope, hi_slope) = (20f64.to_radians(), 35f64.to_radians());
    for p in hard_core_points(&region, 0.03, 3.0, seed.wrapping_add(1)) {
        let s = terrain.map_at("slope", p).unwrap_or(0.0);
        if s >= lo_slope && s <= hi_slope {
            push(p, 0, &mut rng);
        }
    }
    let rocks = uniform_points(&region, 0.002, seed.wrapping_add(2));
    for p in &rocks {
        push(*p, 1, &mut rng);
    }
    for r in &rocks {
        let n = poisson_count(12.0, &mut rng);
        for _ in 0..n {
            let p = *r + DVec2::new(gaussian(&mut rng), gaussian(&mut rng)) * 2.0;
            if region.contains(p) {
                push(p, 2, &mut rng);
            }
        }
    }
    for p in uniform_points(&region, 0.004, seed.wrapping_add(3)) {
        push(p, 2, &mut rng);
    }
    Scene {
        categories,
        instances,
        terrain: Some(terrain.into()),
        ..Default::default()
    }
}

/// Rocks per m² of [`river_rocks`] where its rock map is 1 (the thesis gives no value).
pub const RIVER_ROCK_DENSITY: f64 = 0.08;
/// Least distance between two rocks of [`river_rocks`] (m).
pub const RIVER_ROCK_SPACING: f64 = 1.5;
/// The category of [`river_rocks`].
pub const RIVER_ROCK_CATEGORY: &str = "River rock";
// The terrain map of `river_rocks` that says how dense the rocks are: the waterfall's rock map.
use crate::waterfall::ROCK_MAP;

/// Rocks on a riverbed whose named map "rocks" (thesis 4.4.3: "the rock map indicates the density of rocks to
/// generate") sets their density: a flat terrain 240 m by 120 m of 1 m cells from the origin, the map 0 on a
/// dry band `x < 40` and rising linearly from 0 to 1 over `x` from 40 to 240, so every value is seen; the
/// category [`RIVER_ROCK_CATEGORY`] holds a hard-core arrangement (no two rocks closer than
/// [`RIVER_ROCK_SPACING`]) of intensity [`RIVER_ROCK_DENSITY`] times the map, drawn by dart throwing strip by
/// strip (2 m wide, across the ramp) until each strip holds its share. No rock stands where the map is below
/// 0.05, so the lowest bin of a map histogram of 24 bins (values below 1/24) holds none and a color learned
/// from it keeps rocks off the map's zeros. Rotations are uniform, scales uniform in 0.6..1.4, one prototype.
pub fn river_rocks(seed: u64) -> Scene {
    let (width, depth, cell, dry) = (240.0, 120.0, 1.0, 40.0);
    let (nx, ny) = (241, 121);
    let ramp = |x: f64| ((x - dry) / (width - dry)).clamp(0.0, 1.0);
    let map: Vec<f32> = (0..nx * ny)
        .map(|k| ramp((k % nx) as f64 * cell) as f32)
        .collect();
    // the grid is valid by construction
    let mut terrain = Heightfield::new(DVec2::ZERO, cell, nx, ny, vec![0.0; nx * ny])
        .unwrap_or_else(|_| flat(nx, cell));
    terrain.maps.insert(ROCK_MAP.into(), map);
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x0020_c4e5);
    let (lo, hi) = (DVec2::ZERO, DVec2::new(width, depth));
    let mut grid = SpatialGrid::new(lo, hi, RIVER_ROCK_SPACING);
    let mut instances = Vec::new();
    let strip = 2.0;
    let mut x0 = dry;
    while x0 < width {
        let x1 = (x0 + strip).min(width);
        // the strip's share: the density integrated over it (the map is linear across it)
        let mean = RIVER_ROCK_DENSITY * 0.5 * (ramp(x0) + ramp(x1));
        let want = (mean * (x1 - x0) * depth).round() as usize;
        let mut placed = 0;
        for _ in 0..want.saturating_mul(200) {
            if placed >= want {
                break;
            }
            let x = x0 + rng.random::<f64>() * (x1 - x0);
            // within the strip the density follows the map too
            if ramp(x) < 0.05 || rng.random::<f64>() * ramp(x1) > ramp(x) {
                continue;
            }
            let p = DVec2::new(x, rng.random::<f64>() * depth);
            if grid.any_closer_than(p, RIVER_ROCK_SPACING, None) {
                continue;
            }
            grid.insert(GridEntry {
                position: p,
                tag: 0,
                id: instances.len() as u32,
            });
            instances.push(Instance {
                position: p,
                rotation: rng.random::<f64>() * TAU,
                scale: 0.6 + 0.8 * rng.random::<f64>(),
                category: 0,
                prototype: 0,
                locked: false,
                tint: 0.0,
            });
            placed += 1;
        }
        x0 = x1;
    }
    Scene {
        categories: vec![Category::distribution(RIVER_ROCK_CATEGORY, "water", 0)],
        instances,
        terrain: Some(terrain.into()),
        ..Default::default()
    }
}

/// Figure 1's undergrowth over the square `size × size` from the origin, as the benchmarks at scale paint it:
/// trees with a 3 m hard core (0.03 per m²), uniform rocks (0.03 per m²) and grass in 2 m clumps of ten (0.04 per
/// m²); 0.1 instances per m² in all. Categories in priority order: Tree, Rock, Grass.
pub fn undergrowth_scene(size: f64) -> Scene {
    let region = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(size),
    };
    let mut instances = Vec::new();
    let layers = [
        hard_core_points(&region, 0.03, 3.0, 1),
        uniform_points(&region, 0.03, 2),
        clustered_points(&region, 0.004, 10.0, 2.0, 3),
    ];
    for (category, points) in layers.into_iter().enumerate() {
        instances.extend(points.into_iter().map(|p| Instance::at(p, category)));
    }
    Scene {
        categories: vec![
            Category::distribution("Tree", "vegetation", 0),
            Category::distribution("Rock", "vegetation", 1),
            Category::distribution("Grass", "vegetation", 2),
        ],
        instances,
        ..Default::default()
    }
}

/// A scene of one distribution category from points.
pub fn scene_from_points(name: &str, points: &[DVec2]) -> Scene {
    Scene {
        categories: vec![Category::distribution(name, "vegetation", 0)],
        instances: points.iter().map(|p| Instance::at(*p, 0)).collect(),
        terrain: None,
        ..Default::default()
    }
}

/// A village on flat ground (square `size × size` from the origin): a road network grown from a jittered grid of
/// crossroads about 60 m apart (a random spanning tree of the grid plus some of its other streets, so there are
/// dead ends, bends, T junctions and crossings), houses along the roads at 8–15 m from them and at least 8 m
/// apart, and trees at least 20 m from any road. Categories in priority order: road (graph), house, tree.
pub fn village_scene(size: f64, seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x0011_a9e5);
    let spacing = 60.0;
    let n = ((size / spacing).round() as usize).max(2) + 1;
    let nodes: Vec<DVec2> = (0..n * n)
        .map(|k| {
            let (i, j) = ((k % n) as f64, (k / n) as f64);
            DVec2::new(i * spacing, j * spacing)
                + DVec2::new(gaussian(&mut rng), gaussian(&mut rng)) * 9.0
                - DVec2::splat(0.5 * spacing)
        })
        .collect();
    let roads = village_streets(n, &mut rng);
    // each street bends once on its way
    let paths: Vec<Path> = roads
        .iter()
        .map(|&(a, b)| {
            let (p, q) = (nodes[a], nodes[b]);
            let mid = 0.5 * (p + q) + (q - p).perp().normalize_or_zero() * gaussian(&mut rng) * 4.0;
            Path {
                category: 0,
                points: vec![p, mid, q],
                locked: false,
            }
        })
        .collect();
    let segments: Vec<(DVec2, DVec2)> = paths
        .iter()
        .flat_map(|p| {
            p.points
                .windows(2)
                .map(|w| (w[0], w[1]))
                .collect::<Vec<_>>()
        })
        .collect();
    let road_distance = |p: DVec2| {
        segments
            .iter()
            .map(|(a, b)| crate::geom::segment_distance(p, *a, *b))
            .fold(f64::INFINITY, f64::min)
    };
    let square = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(size),
    };
    let mut instances: Vec<Instance> = Vec::new();
    let houses = houses_along(&segments, &square, &road_distance, &mut rng);
    let mut push = |p: DVec2, category: usize, rng: &mut ChaCha8Rng| {
        instances.push(Instance {
            position: p,
            rotation: rng.random::<f64>() * TAU,
            scale: 0.9 + 0.2 * rng.random::<f64>(),
            category,
            prototype: 0,
            locked: false,
            tint: 0.0,
        });
    };
    for h in houses {
        push(h, 1, &mut rng);
    }
    for p in uniform_points(&square, 0.004, seed.wrapping_add(7)) {
        if road_distance(p) >= 20.0 {
            push(p, 2, &mut rng);
        }
    }
    let road = Category::new("road", "settlement", CategoryKind::Graph, 0);
    Scene {
        categories: vec![
            road,
            Category::distribution("house", "settlement", 1),
            Category::distribution("tree", "vegetation", 2),
        ],
        instances,
        paths,
        ..Default::default()
    }
}

/// The streets of the village's `n × n` grid of crossroads in random order: a spanning tree (union-find), then a
/// share of the others; each as a pair of crossroad indices.
fn village_streets(n: usize, rng: &mut ChaCha8Rng) -> Vec<(usize, usize)> {
    let at = |i: usize, j: usize| j * n + i;
    let mut streets: Vec<(usize, usize)> = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if i + 1 < n {
                streets.push((at(i, j), at(i + 1, j)));
            }
            if j + 1 < n {
                streets.push((at(i, j), at(i, j + 1)));
            }
        }
    }
    for k in (1..streets.len()).rev() {
        streets.swap(k, rng.random_range(0..=k));
    }
    let mut parent: Vec<usize> = (0..n * n).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    let mut roads: Vec<(usize, usize)> = Vec::new();
    for &(a, b) in &streets {
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        if ra != rb {
            parent[ra] = rb;
            roads.push((a, b));
        } else if rng.random::<f64>() < 0.35 {
            roads.push((a, b));
        }
    }
    roads
}

/// Houses along the road `segments` at 8–15 m from the roads (`road_distance`) and at least 8 m apart, in `square`.
fn houses_along(
    segments: &[(DVec2, DVec2)],
    square: &Region,
    road_distance: &dyn Fn(DVec2) -> f64,
    rng: &mut ChaCha8Rng,
) -> Vec<DVec2> {
    let mut houses: Vec<DVec2> = Vec::new();
    for &(a, b) in segments {
        let len = a.distance(b);
        let dir = (b - a) / len.max(1e-9);
        let mut s = rng.random::<f64>() * 12.0;
        while s < len {
            for side in [-1.0, 1.0] {
                let offset = 8.0 + 7.0 * rng.random::<f64>();
                let p = a + dir * s + dir.perp() * side * offset;
                let d = road_distance(p);
                if square.contains(p)
                    && (8.0..=15.0).contains(&d)
                    && houses.iter().all(|h| h.distance(p) >= 8.0)
                {
                    houses.push(p);
                }
            }
            s += 14.0 + 10.0 * rng.random::<f64>();
        }
    }
    houses
}

/// Islands in the sea (square `size × size` from the origin): wobbly contours of 25–45 m radius at least 40 m
/// apart, one with a lake; trees anywhere on the islands (not in the lake), boats within 12 m of a coast on the
/// water. Categories in priority order: island (polygon), tree, boat.
pub fn archipelago_scene(size: f64, seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x15_1a2d);
    let square = Region::Rect {
        min: DVec2::ZERO,
        max: DVec2::splat(size),
    };
    let blob = |c: DVec2, r: f64, rng: &mut ChaCha8Rng| -> Vec<DVec2> {
        let (a3, a5, p3, p5) = (
            0.15 * rng.random::<f64>(),
            0.08 * rng.random::<f64>(),
            TAU * rng.random::<f64>(),
            TAU * rng.random::<f64>(),
        );
        (0..72)
            .map(|k| {
                let a = TAU * k as f64 / 72.0;
                let rr = r * (1.0 + a3 * (3.0 * a + p3).sin() + a5 * (5.0 * a + p5).sin());
                c + DVec2::new(a.cos(), a.sin()) * rr
            })
            .collect()
    };
    let mut islands: Vec<(DVec2, f64)> = Vec::new();
    for _ in 0..400 {
        let r = 25.0 + 20.0 * rng.random::<f64>();
        let c = DVec2::new(rng.random::<f64>(), rng.random::<f64>()) * (size - 2.0 * r)
            + DVec2::splat(r);
        if islands.iter().all(|(d, s)| d.distance(c) >= r + s + 40.0) {
            islands.push((c, r));
        }
    }
    let mut contours: Vec<Contour> = islands
        .iter()
        .map(|&(c, r)| Contour {
            category: 0,
            points: blob(c, r, &mut rng),
            locked: false,
        })
        .collect();
    if let Some(&(c, r)) = islands.first() {
        contours.push(Contour {
            category: 0,
            points: blob(c, 0.3 * r, &mut rng),
            locked: false,
        });
    }
    let land = crate::contour::Polygons::new(
        &contours
            .iter()
            .map(|c| c.points.clone())
            .collect::<Vec<_>>(),
    );
    let mut instances = Vec::new();
    for p in hard_core_points(&square, 0.02, 3.0, seed.wrapping_add(1)) {
        if land.contains(p) {
            instances.push(Instance::at(p, 1));
        }
    }
    for p in hard_core_points(&square, 0.01, 6.0, seed.wrapping_add(2)) {
        if !land.contains(p) && land.distance(p, 100.0) <= 12.0 {
            instances.push(Instance::at(p, 2));
        }
    }
    let island = Category::new("island", "terrain", CategoryKind::Polygon, 0);
    Scene {
        categories: vec![
            island,
            Category::distribution("tree", "vegetation", 1),
            Category::distribution("boat", "water", 2),
        ],
        instances,
        contours,
        ..Default::default()
    }
}

/// A waterfall scene of `count` controllers on `terrain` (thesis ch. 4), seeded: `count / 5` rivers, each a
/// contact curve down the steepest slope from a random point with a flow of 1 to 6 units, a free-fall from its end (a drop of 1.2 % of the
/// terrain's size), a round pool receiving it and a contact curve leaving the pool downhill; the remaining
/// controllers are tributaries, straight contact curves drawn on the terrain that end on a control point of a
/// river's lower curve. Heights are the terrain's except below the falls, so the minimum-slope correction has
/// work to do.
pub fn waterfall_controllers(
    terrain: &Heightfield,
    count: usize,
    seed: u64,
) -> Vec<crate::waterfall::Controller> {
    use crate::waterfall::{subdivide::downhill, Controller, ControllerKind};
    use glam::DVec3;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (lo, hi) = terrain.bbox();
    let size = (hi - lo).min_element();
    let margin = 0.05 * size;
    let inside = |p: DVec2| p.cmpge(lo + margin).all() && p.cmple(hi - margin).all();
    let on_terrain = |p: DVec2| p.extend(terrain.height_at(p).unwrap_or(0.0));
    let step = 0.015 * size;
    let descend = |from: DVec2, n: usize| -> Vec<DVec2> {
        let mut pts = vec![from];
        let mut dir = DVec2::NEG_X;
        for _ in 0..n {
            let last = pts[pts.len() - 1];
            let g = downhill(terrain, last);
            if g.length() > 1e-6 {
                dir = g.normalize();
            }
            let next = last + dir * step;
            // stop at the edge and in valleys, where steepest descent would zigzag
            let descends = terrain.height_at(next).unwrap_or(f64::INFINITY)
                < terrain.height_at(last).unwrap_or(0.0) - 0.01 * step;
            if !inside(next) || !descends {
                break;
            }
            pts.push(next);
        }
        if pts.len() < 2 {
            pts.push(from + dir * step.min(margin * 0.5));
        }
        pts
    };
    let rivers = count / 5;
    let mut out: Vec<Controller> = Vec::with_capacity(count);
    let mut joins: Vec<DVec3> = Vec::new();
    for _ in 0..rivers {
        let start =
            lo + (hi - lo) * DVec2::new(rng.random_range(0.2..0.8), rng.random_range(0.2..0.8));
        let upper = descend(start, 12);
        let lip2 = upper[upper.len() - 1];
        let dir = (lip2 - upper[upper.len() - 2]).normalize_or(DVec2::X);
        let lip = on_terrain(lip2);
        let drop = 0.012 * size;
        let foot = (lip2 + dir * 0.003 * size).extend(lip.z - drop);
        let radius = 0.006 * size;
        let centre = foot.truncate() + dir * 0.002 * size;
        let pool: Vec<DVec3> = (0..12)
            .map(|k| {
                let a = TAU * k as f64 / 12.0;
                (centre + DVec2::new(a.cos(), a.sin()) * radius).extend(foot.z)
            })
            .collect();
        let outlet = centre + dir * radius;
        let lower_plan = descend(outlet, 12);
        let mut lower: Vec<DVec3> = lower_plan.iter().map(|p| on_terrain(*p)).collect();
        lower[0].z = foot.z;
        joins.extend(
            lower
                .iter()
                .skip(1)
                .take(lower.len().saturating_sub(2))
                .copied(),
        );
        out.push(
            Controller::new(
                ControllerKind::Contact,
                upper.iter().map(|p| on_terrain(*p)).collect(),
            )
            .with_strength(rng.random_range(1.0..6.0)),
        );
        out.push(Controller::new(ControllerKind::FreeFall, vec![lip, foot]));
        out.push(Controller::new(ControllerKind::Pool, pool));
        out.push(Controller::new(ControllerKind::Contact, lower));
    }
    while out.len() < count {
        let angle = rng.random::<f64>() * TAU;
        let reach = 0.08 * size;
        let end = match joins.len() {
            0 => on_terrain(lo + (hi - lo) * 0.5),
            n => joins[rng.random_range(0..n)],
        };
        let start = (end.truncate() + DVec2::new(angle.cos(), angle.sin()) * reach)
            .clamp(lo + margin, hi - margin);
        let mut pts: Vec<DVec3> = (0..8)
            .map(|k| on_terrain(start.lerp(end.truncate(), k as f64 / 8.0)))
            .collect();
        pts.push(end);
        out.push(Controller::new(ControllerKind::Contact, pts));
    }
    out
}

/// `count` random two-point strokes anywhere in the sketch's frame (seeded): the scribbles of a user trying the tool,
/// which the sketch must finish or refuse within its time limit.
pub fn random_strokes(count: usize, seed: u64) -> Vec<SketchStroke> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|_| SketchStroke {
            points: (0..2)
                .map(|_| DVec2::new(rng.random::<f64>(), rng.random::<f64>()))
                .collect(),
        })
        .collect()
}

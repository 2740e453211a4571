//! Decoration maps (thesis 4.4.3 "Procedural Decoration"): the integration mesh seen from above, rendered onto
//! the terrain's grid.
//!
//! * **Water map** — the mesh's footprint (1 under water, 0 elsewhere): "used to mask the procedural seeding of
//!   trees and plants", hence [`WaterMaps::is_water`].
//! * **Foam, rock and disturbance maps** — Table 4.1's values of each segment's type as grey levels; pools take
//!   the values of their inflows (see [`super::integration`]). "Some filtering is applied to these maps to reduce
//!   visible transitions between different types": here a normalized box filter of radius
//!   [`DecorationOptions::filter_radius`] inside the water (the mean over the water nodes of the window, so the
//!   values do not fade towards the banks).
//! * **Speed map** — the 2D surface speed. Contacts: `δ_x = δ_c (1 − ‖x − c‖/‖b − c‖)` with `c` and `b` the
//!   projections of `x` on the axis and on the shore, along the flow. Branches: inverse-distance interpolation of
//!   velocity constraints `δ_i` at points `p_i`, `δ_x = Σ ω_i δ_i`, `ω_i = ω̃_i / Σ ω̃_i`,
//!   `ω̃_i = Π_{j≠i} (1 − ‖x − p_i‖/‖p_j − p_i‖)`; the points are the axes of the arcs meeting at the branch,
//!   one branch radius (the widest half-width there) from the node, each factor clamped at 0 so that weights stay
//!   non-negative. Pools: the thesis runs "a fixed number of 2D fluid solver simulation steps" of Stam's stable
//!   fluids; here the viscous step is run to its steady state — the velocities of the inflowing and outflowing
//!   water and of the plunge points are diffused through the pool with the walls at rest (the Laplace solver of
//!   [`crate::terrain_edit`]), without advection.
//!
//! Rocks along the riverbeds ([`scatter_rocks`]): dart throwing over the water nodes, each node proposing on
//! average `rock_density · rocks(node) · cell²` darts at uniform positions in its cell, accepted unless another
//! rock lies within `rock_spacing` (a hard-core process whose intensity follows the rock map). Seeded; nodes are
//! visited in row-major order.

use super::integration::{Footprint, WaterMesh, WaterPart};
use super::network::NodeKind;
use super::{ControllerKind, WaterfallNetwork};
use crate::error::{Error, Result};
use crate::spatial::{GridEntry, SpatialGrid};
use crate::terrain::Heightfield;
use crate::terrain_edit::{diffuse, Constraints, DiffusionOptions};
use glam::{DVec2, DVec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// How the maps and rocks are made.
#[derive(Clone, Debug)]
pub struct DecorationOptions {
    /// Radius (m) of the filter smoothing foam, rocks and disturbance; `None`: two grid cells; 0: no filter.
    pub filter_radius: Option<f64>,
    /// Rocks per m² where the rock map is 1.
    pub rock_density: f64,
    /// Least distance between two rocks (m).
    pub rock_spacing: f64,
}

impl Default for DecorationOptions {
    fn default() -> Self {
        DecorationOptions {
            filter_radius: None,
            rock_density: 0.08,
            rock_spacing: 1.5,
        }
    }
}

impl DecorationOptions {
    pub fn validate(&self) -> Result<()> {
        if let Some(r) = self.filter_radius {
            if !(r.is_finite() && r >= 0.0) {
                return Err(Error::InvalidInput(format!(
                    "decoration filter_radius = {r} must be zero or positive"
                )));
            }
        }
        if !(self.rock_density.is_finite()
            && self.rock_density >= 0.0
            && self.rock_density <= 100.0)
        {
            return Err(Error::InvalidInput(format!(
                "decoration rock_density = {} must be between 0 and 100 per m²",
                self.rock_density
            )));
        }
        if !(self.rock_spacing.is_finite() && self.rock_spacing > 0.0) {
            return Err(Error::InvalidInput(format!(
                "decoration rock_spacing = {} must be positive",
                self.rock_spacing
            )));
        }
        Ok(())
    }
}

/// The decoration maps on the terrain's nodes, row-major.
#[derive(Clone, Debug)]
pub struct WaterMaps {
    pub nx: usize,
    pub ny: usize,
    pub origin: DVec2,
    pub cell: f64,
    /// 1 under the integration mesh, 0 elsewhere.
    pub water: Vec<f32>,
    pub foam: Vec<f32>,
    pub rocks: Vec<f32>,
    pub disturbance: Vec<f32>,
    /// Plan surface velocity.
    pub speed: Vec<DVec2>,
    /// Signed plan distance to the water's edge (positive in the water), clamped at minus the footprint's margin:
    /// its bilinear interpolation places the edge between nodes, also for ribbons narrower than a cell.
    pub inside: Vec<f32>,
}

impl WaterMaps {
    /// The node nearest to `p`, if `p` lies on the grid.
    pub fn node(&self, p: DVec2) -> Option<usize> {
        let f = ((p - self.origin) / self.cell).round();
        let inside = f.x >= 0.0 && f.y >= 0.0 && f.x < self.nx as f64 && f.y < self.ny as f64;
        (inside && p.is_finite()).then(|| f.y as usize * self.nx + f.x as usize)
    }

    /// Whether `p` lies in the water (the interpolated distance to the water's edge is positive): for keeping
    /// instances out of it.
    pub fn is_water(&self, p: DVec2) -> bool {
        if !p.is_finite() || self.nx < 2 || self.ny < 2 {
            return false;
        }
        let f = (p - self.origin) / self.cell;
        if f.x < 0.0 || f.y < 0.0 || f.x > (self.nx - 1) as f64 || f.y > (self.ny - 1) as f64 {
            return false;
        }
        let i = (f.x.floor() as usize).min(self.nx - 2);
        let j = (f.y.floor() as usize).min(self.ny - 2);
        let (tx, ty) = (f.x - i as f64, f.y - j as f64);
        let at = |i: usize, j: usize| self.inside[j * self.nx + i] as f64;
        let a = at(i, j) * (1.0 - tx) + at(i + 1, j) * tx;
        let b = at(i, j + 1) * (1.0 - tx) + at(i + 1, j + 1) * tx;
        a * (1.0 - ty) + b * ty > 0.0
    }

    /// The speed at the node nearest to `p` (zero off the grid).
    pub fn speed_at(&self, p: DVec2) -> DVec2 {
        self.node(p).map_or(DVec2::ZERO, |k| self.speed[k])
    }
}

/// The decoration maps of the water.
pub fn water_maps(
    net: &WaterfallNetwork,
    mesh: &WaterMesh,
    footprint: &Footprint,
    options: &DecorationOptions,
) -> Result<WaterMaps> {
    options.validate()?;
    let (nx, ny, cell) = (footprint.nx, footprint.ny, footprint.cell);
    let n = nx * ny;
    let mut water = vec![0.0f32; n];
    let mut values = [vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n]];
    let mut speed = vec![DVec2::ZERO; n];
    let far = -(footprint.margin.max(footprint.cell)) as f32;
    let inside: Vec<f32> = footprint
        .nodes
        .iter()
        .map(|f| f.map_or(far, |f| (f.inside as f32).max(far)))
        .collect();
    let pool_of = |c: usize| mesh.pools.iter().find(|p| p.controller == c);
    for (k, node) in footprint.nodes.iter().enumerate() {
        let Some(f) = node else {
            continue;
        };
        if f.inside <= 0.0 {
            continue;
        }
        water[k] = 1.0;
        let p = footprint.origin + DVec2::new((k % nx) as f64, (k / nx) as f64) * cell;
        let v = match f.part {
            WaterPart::Pool => {
                pool_of(f.element).map_or([0.0; 3], |pool| super::integration::pool_values(pool, p))
            }
            _ => super::integration::decoration_values(net.segments[f.element].kind_of_water),
        };
        for c in 0..3 {
            values[c][k] = v[c] as f32;
        }
        if f.part != WaterPart::Pool {
            let delta = net.segments[f.element].section.speed;
            let across = if f.part == WaterPart::Contact {
                (f.inside / f.half_width.max(1e-9)).clamp(0.0, 1.0)
            } else {
                1.0
            };
            speed[k] = f.along * delta * across;
        }
    }
    let radius = options.filter_radius.unwrap_or(2.0 * cell);
    let r = (radius / cell).round() as usize;
    let [foam, rocks, disturbance] = values.map(|v| filter(&v, &water, nx, ny, r));
    let mut maps = WaterMaps {
        nx,
        ny,
        origin: footprint.origin,
        cell,
        water,
        foam,
        rocks,
        disturbance,
        speed,
        inside,
    };
    branch_speeds(net, mesh, footprint, &mut maps);
    pool_speeds(net, mesh, footprint, &mut maps)?;
    Ok(maps)
}

/// Normalized box filter of radius `r` nodes over the water nodes (separable running sums).
fn filter(v: &[f32], w: &[f32], nx: usize, ny: usize, r: usize) -> Vec<f32> {
    if r == 0 {
        return v.to_vec();
    }
    let weighted: Vec<f64> = v.iter().zip(w).map(|(a, b)| (*a * *b) as f64).collect();
    let mass: Vec<f64> = w.iter().map(|b| *b as f64).collect();
    let blur = |src: &[f64]| -> Vec<f64> {
        // along x
        let mut tmp = vec![0.0; nx * ny];
        tmp.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
            let s = &src[j * nx..(j + 1) * nx];
            let mut acc = 0.0;
            for x in s.iter().take(r.min(nx)) {
                acc += x;
            }
            for i in 0..nx {
                if i + r < nx {
                    acc += s[i + r];
                }
                if i > r {
                    acc -= s[i - r - 1];
                }
                row[i] = acc;
            }
        });
        // along y, column by column in blocks of rows
        let mut out = vec![0.0; nx * ny];
        let cols: Vec<Vec<f64>> = (0..nx)
            .into_par_iter()
            .map(|i| {
                let mut col = vec![0.0; ny];
                let mut acc = 0.0;
                for j in 0..r.min(ny) {
                    acc += tmp[j * nx + i];
                }
                for j in 0..ny {
                    if j + r < ny {
                        acc += tmp[(j + r) * nx + i];
                    }
                    if j > r {
                        acc -= tmp[(j - r - 1) * nx + i];
                    }
                    col[j] = acc;
                }
                col
            })
            .collect();
        for (i, col) in cols.iter().enumerate() {
            for (j, x) in col.iter().enumerate() {
                out[j * nx + i] = *x;
            }
        }
        out
    };
    let (a, b) = (blur(&weighted), blur(&mass));
    (0..nx * ny)
        .map(|k| {
            if w[k] > 0.0 && b[k] > 1e-9 {
                (a[k] / b[k]).clamp(0.0, 1.0) as f32
            } else {
                0.0
            }
        })
        .collect()
}

/// The point at plan distance `r` from the start (or the end) of a path, and the unit direction there.
fn along_path(path: &[DVec3], r: f64, from_end: bool) -> Option<(DVec2, DVec2)> {
    let pts: Vec<DVec2> = if from_end {
        path.iter().rev().map(|p| p.truncate()).collect()
    } else {
        path.iter().map(|p| p.truncate()).collect()
    };
    let mut left = r;
    for w in pts.windows(2) {
        let l = w[0].distance(w[1]);
        if l <= 1e-12 {
            continue;
        }
        let dir = (w[1] - w[0]) / l;
        if left <= l {
            let flow = if from_end { -dir } else { dir };
            return Some((w[0] + dir * left, flow));
        }
        left -= l;
    }
    let n = pts.len();
    (n >= 2).then(|| {
        let dir = (pts[n - 1] - pts[n - 2]).normalize_or_zero();
        (pts[n - 1], if from_end { -dir } else { dir })
    })
}

/// The branch speeds: inverse-distance interpolation of the arcs' axis velocities around every branch node where
/// three or more contact arcs meet.
fn branch_speeds(
    net: &WaterfallNetwork,
    mesh: &WaterMesh,
    footprint: &Footprint,
    maps: &mut WaterMaps,
) {
    let graph = &net.graph;
    for node in &graph.nodes {
        if node.kind != NodeKind::Branch {
            continue;
        }
        let arcs: Vec<(usize, bool)> = node
            .arcs_in
            .iter()
            .map(|&a| (a, true))
            .chain(node.arcs_out.iter().map(|&a| (a, false)))
            .filter(|(a, _)| {
                graph.arcs[*a].kind == ControllerKind::Contact && !net.segment_ranges[*a].is_empty()
            })
            .collect();
        if arcs.len() < 3 {
            continue;
        }
        let seg_at = |a: usize, incoming: bool| {
            let r = &net.segment_ranges[a];
            &net.segments[if incoming { r.end - 1 } else { r.start }]
        };
        let radius = arcs
            .iter()
            .map(|&(a, inc)| {
                // the ribbon's half-width there: its row of vertices is (left bank, axis, right bank)
                let r = &net.segment_ranges[a];
                let s = if inc { r.end - 1 } else { r.start };
                mesh.part
                    .iter()
                    .zip(&mesh.element)
                    .position(|(p, e)| *p == WaterPart::Contact && *e == s)
                    .and_then(|v| Some(mesh.vertices.get(v)?.distance(*mesh.vertices.get(v + 1)?)))
                    .unwrap_or(0.5 * seg_at(a, inc).section.width)
            })
            .fold(footprint.cell, f64::max);
        let constraints: Vec<(DVec2, DVec2)> = arcs
            .iter()
            .filter_map(|&(a, inc)| {
                let (p, dir) = along_path(&net.paths[a], radius, inc)?;
                Some((p, dir * seg_at(a, inc).section.speed))
            })
            .collect();
        if constraints.len() < 3 {
            continue;
        }
        let c = node.position.truncate();
        let (lo, hi) = (c - radius, c + radius);
        let to_node = |v: f64, o: f64| ((v - o) / maps.cell).round();
        let (i0, i1) = (
            to_node(lo.x, maps.origin.x).max(0.0),
            to_node(hi.x, maps.origin.x),
        );
        let (j0, j1) = (
            to_node(lo.y, maps.origin.y).max(0.0),
            to_node(hi.y, maps.origin.y),
        );
        if i1 < 0.0 || j1 < 0.0 {
            continue;
        }
        let (i1, j1) = (
            (i1 as usize).min(maps.nx - 1),
            (j1 as usize).min(maps.ny - 1),
        );
        for j in j0 as usize..=j1 {
            for i in i0 as usize..=i1 {
                let k = j * maps.nx + i;
                let x = maps.origin + DVec2::new(i as f64, j as f64) * maps.cell;
                if maps.water[k] <= 0.5 || x.distance(c) > radius {
                    continue;
                }
                let weights: Vec<f64> = constraints
                    .iter()
                    .enumerate()
                    .map(|(i, (pi, _))| {
                        constraints
                            .iter()
                            .enumerate()
                            .filter(|(j, _)| *j != i)
                            .map(|(_, (pj, _))| {
                                let l = pj.distance(*pi).max(1e-9);
                                (1.0 - x.distance(*pi) / l).max(0.0)
                            })
                            .product()
                    })
                    .collect();
                let total: f64 = weights.iter().sum();
                if total > 1e-12 {
                    maps.speed[k] = weights
                        .iter()
                        .zip(&constraints)
                        .map(|(w, (_, d))| *d * (*w / total))
                        .sum();
                }
            }
        }
    }
}

/// A pool's solved speeds: the box's first node `(i0, j0)`, its size `(bx, by)` and the velocities in it.
type PoolSpeeds = (usize, usize, usize, usize, Vec<DVec2>);

/// The pool speeds: inflow, outflow and plunge velocities diffused through each pool with its walls at rest.
fn pool_speeds(
    net: &WaterfallNetwork,
    mesh: &WaterMesh,
    footprint: &Footprint,
    maps: &mut WaterMaps,
) -> Result<()> {
    let solved: Vec<Option<PoolSpeeds>> = mesh
        .pools
        .par_iter()
        .map(|pool| -> Result<_> {
            let mine = |k: usize| {
                footprint.nodes[k].is_some_and(|f| {
                    f.inside > 0.0 && f.part == WaterPart::Pool && f.element == pool.controller
                })
            };
            let (lo, hi) = pool.contour.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            let node_of = |v: f64, o: f64| ((v - o) / maps.cell).floor();
            let i0 = (node_of(lo.x, maps.origin.x) - 1.0).max(0.0) as usize;
            let j0 = (node_of(lo.y, maps.origin.y) - 1.0).max(0.0) as usize;
            let i1 = node_of(hi.x, maps.origin.x) + 2.0;
            let j1 = node_of(hi.y, maps.origin.y) + 2.0;
            if i1 < 0.0 || j1 < 0.0 {
                return Ok(None);
            }
            let (i1, j1) = (
                (i1 as usize).min(maps.nx - 1),
                (j1 as usize).min(maps.ny - 1),
            );
            if i1 <= i0 || j1 <= j0 {
                return Ok(None);
            }
            let (bx, by) = (i1 - i0 + 1, j1 - j0 + 1);
            let mut cx = Constraints::new(bx, by, maps.cell)?;
            let mut cy = Constraints::new(bx, by, maps.cell)?;
            // plunge points first: the velocity the falling water brings in
            let node = &net.graph.nodes[pool.node];
            for &a in &node.arcs_in {
                if net.graph.arcs[a].kind != ControllerKind::FreeFall {
                    continue;
                }
                let Some(foot) = net.paths[a].last() else {
                    continue;
                };
                let u = super::integration::fall_direction(net, a);
                let r = &net.segment_ranges[a];
                let v = u * net.segments[r.start].section.speed.min(speed_scale(net));
                let f = ((foot.truncate() - maps.origin) / maps.cell).round();
                if f.x >= i0 as f64 && f.y >= j0 as f64 && f.x <= i1 as f64 && f.y <= j1 as f64 {
                    let (i, j) = (f.x as usize - i0, f.y as usize - j0);
                    cx.set(i, j, v.x)?;
                    cy.set(i, j, v.y)?;
                }
            }
            for j in 0..by {
                for i in 0..bx {
                    let k = (j + j0) * maps.nx + i + i0;
                    if mine(k) {
                        continue;
                    }
                    let v = if maps.water[k] > 0.5 {
                        maps.speed[k]
                    } else {
                        DVec2::ZERO
                    };
                    if cx.get(i, j).is_none() {
                        cx.set(i, j, v.x)?;
                        cy.set(i, j, v.y)?;
                    }
                }
            }
            let o = DiffusionOptions {
                falloff: None,
                tolerance: 1e-4,
                max_cycles: 50,
            };
            let (dx, dy) = (diffuse(&cx, &o)?, diffuse(&cy, &o)?);
            let v = dx
                .displacement
                .iter()
                .zip(&dy.displacement)
                .map(|(x, y)| DVec2::new(*x, *y))
                .collect();
            Ok(Some((i0, j0, bx, by, v)))
        })
        .collect::<Result<_>>()?;
    for (pool, s) in mesh.pools.iter().zip(solved) {
        let Some((i0, j0, bx, by, v)) = s else {
            continue;
        };
        for j in 0..by {
            for i in 0..bx {
                let k = (j + j0) * maps.nx + i + i0;
                let f = footprint.nodes[k];
                if f.is_some_and(|f| {
                    f.inside > 0.0 && f.part == WaterPart::Pool && f.element == pool.controller
                }) {
                    maps.speed[k] = v[j * bx + i];
                }
            }
        }
    }
    Ok(())
}

/// The fastest contact speed of the network: a plunge brings water into its pool no faster.
fn speed_scale(net: &WaterfallNetwork) -> f64 {
    net.segments
        .iter()
        .filter(|s| s.kind == ControllerKind::Contact)
        .map(|s| s.section.speed)
        .fold(0.0, f64::max)
        .max(1e-3)
}

/// Rock positions in the water, their density following the rock map, at the height of `terrain` (the riverbed).
pub fn scatter_rocks(
    maps: &WaterMaps,
    terrain: &Heightfield,
    options: &DecorationOptions,
    seed: u64,
) -> Result<Vec<DVec3>> {
    options.validate()?;
    if terrain.nx != maps.nx || terrain.ny != maps.ny {
        return Err(Error::InvalidInput(format!(
            "water maps of {}x{} nodes do not fit a {}x{} terrain",
            maps.nx, maps.ny, terrain.nx, terrain.ny
        )));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (lo, hi) = terrain.bbox();
    let mut grid = SpatialGrid::new(lo, hi, options.rock_spacing);
    let mut out = Vec::new();
    let per_node = options.rock_density * maps.cell * maps.cell;
    for (k, r) in maps.rocks.iter().enumerate() {
        if *r <= 0.0 || maps.water[k] <= 0.5 {
            continue;
        }
        let expected = per_node * *r as f64;
        let mut darts = expected.floor() as usize;
        if rng.random::<f64>() < expected.fract() {
            darts += 1;
        }
        let centre =
            maps.origin + DVec2::new((k % maps.nx) as f64, (k / maps.nx) as f64) * maps.cell;
        for _ in 0..darts {
            // within the node's own cell, so the rock map there is what drew it
            let jitter = DVec2::new(rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5)
                * (0.999 * maps.cell);
            let p = (centre + jitter).clamp(lo, hi);
            if grid.any_closer_than(p, options.rock_spacing, None) {
                continue;
            }
            let Some(z) = terrain.height_at(p) else {
                continue;
            };
            grid.insert(GridEntry {
                position: p,
                tag: 0,
                id: out.len() as u32,
            });
            out.push(p.extend(z));
        }
    }
    Ok(out)
}

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
//! Rocks along the riverbeds ([`scatter_rocks`]) come from the engine's distribution synthesis
//! ([`crate::synthesis`]): a rock *color* is synthesized over the bounding rectangle of the water's rock map, on
//! the deformed terrain carrying the rock map as its map "rocks" (0 on dry nodes). The synthesis is the product
//! model of eq. (1) at any count ([`SynthesisOptions::product_model`]): the rocks' map confines them to a thin
//! part of the rectangle, where matching pair counts against the rectangle's whole area would spread them evenly
//! whatever the rock map says. Proposals fall uniformly in the rectangle, so there are as many more of them as
//! the rectangle is larger than the rock map's support (at most a hundred times). Where the map is
//! interpolated between a wet node and a dry one its support reaches beyond the water's edge; rocks there (not
//! in the water by [`WaterMaps::is_water`], or whose nearest node is dry) are left out.
//!
//! * **The built-in color** ([`river_rock_color`]) is an asset, `assets/waterfall/river_rocks.color.json`: the
//!   river-rock exemplar (`exemplar::river_rocks`, seed 1) learned on its map "rocks" (a test keeps the asset
//!   equal to that): rocks at least 1.5 m apart, as dense as 0.08 per m² times the map. Its map factor
//!   `ψ(m) = h(m) / q(m)` (see [`crate::synthesis`], "Maps") is 0 where `m` is below 1/24 — no rock on a dry
//!   node — and grows about as `m / m̄`, where `m̄ = 0.42` is the map's mean over the exemplar (where ψ
//!   averages to 1). The count is `λ_b ∫ ψ(m(x)) dx` over the water with `λ_b = 0.033` per m² the
//!   exemplar's mean density: `∫ 0.08 m dA`, the exemplar's intensity, up to its estimation noise. In the
//!   model `ψ` is a preference, and the hard core thins it again where rocks are densest (the exemplar's `ψ`
//!   is a density the hard core had already thinned): where the map is above 0.6 about a fifth fewer rocks
//!   stand than `0.08 m` per m², a few percent more where it is low; the count is kept.
//! * **A user's color** ([`DecorationOptions::rock_color`]) gives every one of its distribution categories
//!   its own rdf, density, rotations, scales and prototypes. A category that follows no map "rocks" is given
//!   the built-in color's `ψ`, so its placement follows the rock map and its count becomes
//!   `λ_user ∫ ψ(m) dA ≈ (λ_user / λ_b) ∫ 0.08 m dA`: the user's own density where the map is `m̄`, 2.4 times
//!   it where the map is 1. Any other map the color follows (slope, elevation) multiplies in.
//!
//! Neither color was learned on this terrain with this rock map, so the synthesis does not recalibrate their
//! preferences on it ([`SynthesisOptions::exemplar_on_terrain`] is off): ψ averages to 1 over the exemplar.
//!
//! The rocks are seeded from the scene's seed and do not depend on the thread count.

use super::integration::{PoolWater, WaterMesh, WaterPart, WaterfallFootprint};
use super::model::{ControllerKind, Segment, WaterfallNetwork};
use super::network::{HydraulicNode, HydraulicNodeKind};
use crate::error::{check, Error, Result};
use crate::geom::Region;
use crate::paint::synthesize;
use crate::palette::{Color, MapInteraction, MapSource};
use crate::scene::{CategoryKind, Scene};
use crate::synthesis::{SynthesisOptions, DEFAULT_ITERATIONS_PER_INSTANCE};
use crate::terrain::Heightfield;
use crate::terrain_edit::{diffuse, Constraints, DiffusionOptions};
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::sync::{Arc, OnceLock};

/// How the maps and rocks are made.
#[derive(Clone, Debug, Default)]
pub struct DecorationOptions {
    /// Radius (m) of the filter smoothing foam, rocks and disturbance; `None`: two grid cells; 0: no filter.
    pub filter_radius: Option<f64>,
    /// The color rocks are synthesized from (every distribution category of it); `None`: the built-in river
    /// rocks ([`river_rock_color`]). See the module documentation for the count.
    pub rock_color: Option<Color>,
}

impl DecorationOptions {
    /// Checks the filter radius, and that a rock color is valid and has a distribution category.
    pub fn validate(&self) -> Result<()> {
        if let Some(r) = self.filter_radius {
            check::non_negative("decoration filter_radius", r)?;
        }
        if let Some(c) = &self.rock_color {
            c.validate()?;
            if rock_categories(c).is_empty() {
                return Err(Error::invalid(
                    format!("rock color '{}'", c.name),
                    "has no distribution category to scatter as rocks",
                ));
            }
        }
        Ok(())
    }
}

/// The decoration maps on the terrain's nodes, row-major.
#[derive(Clone, Debug)]
pub struct WaterMaps {
    /// Nodes along X (the terrain's).
    pub nx: usize,
    /// Nodes along Y.
    pub ny: usize,
    /// World XY of node (0, 0).
    pub origin: DVec2,
    /// Spacing of the nodes (m).
    pub cell: f64,
    /// 1 under the integration mesh, 0 elsewhere.
    pub water: Vec<f32>,
    /// Table 4.1's foam of the water over each node, filtered; in [0, 1], 0 on dry nodes.
    pub foam: Vec<f32>,
    /// The rock map: Table 4.1's rocks, filtered; in [0, 1], 0 on dry nodes. Rocks are scattered by it.
    pub rocks: Vec<f32>,
    /// Table 4.1's disturbance, filtered; in [0, 1], 0 on dry nodes.
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
    pub(crate) fn speed_at(&self, p: DVec2) -> DVec2 {
        self.node(p).map_or(DVec2::ZERO, |k| self.speed[k])
    }
}

/// The decoration maps of the water.
pub(crate) fn water_maps(
    net: &WaterfallNetwork,
    mesh: &WaterMesh,
    footprint: &WaterfallFootprint,
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
    footprint: &WaterfallFootprint,
    maps: &mut WaterMaps,
) {
    for node in &net.graph.nodes {
        if node.kind != HydraulicNodeKind::Branch {
            continue;
        }
        let arcs = branch_arcs(net, node);
        if arcs.len() < 3 {
            continue;
        }
        let radius = branch_radius(net, mesh, &arcs, footprint.cell);
        let constraints: Vec<(DVec2, DVec2)> = arcs
            .iter()
            .filter_map(|&(a, inc)| {
                let (p, dir) = along_path(&net.paths[a], radius, inc)?;
                Some((p, dir * end_segment(net, a, inc).section.speed))
            })
            .collect();
        if constraints.len() < 3 {
            continue;
        }
        blend_around(maps, node.position.truncate(), radius, &constraints);
    }
}

/// The contact arcs (with segments) at a node: `(arc, whether it comes in)`, the incoming first.
fn branch_arcs(net: &WaterfallNetwork, node: &HydraulicNode) -> Vec<(usize, bool)> {
    let graph = &net.graph;
    node.arcs_in
        .iter()
        .map(|&a| (a, true))
        .chain(node.arcs_out.iter().map(|&a| (a, false)))
        .filter(|(a, _)| {
            graph.arcs[*a].kind == ControllerKind::Contact && !net.segment_ranges[*a].is_empty()
        })
        .collect()
}

/// The segment of arc `a` at the node: its last when the arc comes in, its first when it leaves.
fn end_segment(net: &WaterfallNetwork, a: usize, incoming: bool) -> &Segment {
    let r = &net.segment_ranges[a];
    &net.segments[if incoming { r.end - 1 } else { r.start }]
}

/// The radius of a branch: the widest half-width of the ribbons meeting there, at least a cell.
fn branch_radius(
    net: &WaterfallNetwork,
    mesh: &WaterMesh,
    arcs: &[(usize, bool)],
    cell: f64,
) -> f64 {
    arcs.iter()
        .map(|&(a, inc)| {
            // the ribbon's half-width there: its row of vertices is (left bank, axis, right bank)
            let r = &net.segment_ranges[a];
            let s = if inc { r.end - 1 } else { r.start };
            mesh.part
                .iter()
                .zip(&mesh.element)
                .position(|(p, e)| *p == WaterPart::Contact && *e == s)
                .and_then(|v| Some(mesh.vertices.get(v)?.distance(*mesh.vertices.get(v + 1)?)))
                .unwrap_or(0.5 * end_segment(net, a, inc).section.width)
        })
        .fold(cell, f64::max)
}

/// Sets the speed of the water nodes within `radius` of `c` to the blend of the `constraints` (point, velocity)
/// weighted by the product of their barycentric-like falloffs towards the others.
fn blend_around(maps: &mut WaterMaps, c: DVec2, radius: f64, constraints: &[(DVec2, DVec2)]) {
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
        return;
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
            let weights = blend_weights(x, constraints);
            let total: f64 = weights.iter().sum();
            if total > 1e-12 {
                maps.speed[k] = weights
                    .iter()
                    .zip(constraints)
                    .map(|(w, (_, d))| *d * (*w / total))
                    .sum();
            }
        }
    }
}

/// The weight of each constraint at `x`: the product over the other constraints of `1 − d(x, p_i) / d(p_j, p_i)`
/// (floored at 0).
fn blend_weights(x: DVec2, constraints: &[(DVec2, DVec2)]) -> Vec<f64> {
    constraints
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
        .collect()
}

/// A pool's solved speeds: the box's first node `(i0, j0)`, its size `(bx, by)` and the velocities in it.
type PoolSpeeds = (usize, usize, usize, usize, Vec<DVec2>);

/// The pool speeds: inflow, outflow and plunge velocities diffused through each pool with its walls at rest.
fn pool_speeds(
    net: &WaterfallNetwork,
    mesh: &WaterMesh,
    footprint: &WaterfallFootprint,
    maps: &mut WaterMaps,
) -> Result<()> {
    let solved: Vec<Option<PoolSpeeds>> = mesh
        .pools
        .par_iter()
        .map(|pool| pool_speed_field(net, footprint, maps, pool))
        .collect::<Result<_>>()?;
    for (pool, s) in mesh.pools.iter().zip(solved) {
        let Some((i0, j0, bx, by, v)) = s else {
            continue;
        };
        for j in 0..by {
            for i in 0..bx {
                let k = (j + j0) * maps.nx + i + i0;
                if in_pool(footprint, k, pool) {
                    maps.speed[k] = v[j * bx + i];
                }
            }
        }
    }
    Ok(())
}

/// Whether node `k` lies in the water of `pool`.
fn in_pool(footprint: &WaterfallFootprint, k: usize, pool: &PoolWater) -> bool {
    footprint.nodes[k].is_some_and(|f| {
        f.inside > 0.0 && f.part == WaterPart::Pool && f.element == pool.controller
    })
}

/// The nodes `(i0, j0, i1, j1)` of the maps around a pool: its contour's bounds and a node more (two past its
/// upper ends), within the maps; `None` when that box is empty.
fn pool_box(pool: &PoolWater, maps: &WaterMaps) -> Option<(usize, usize, usize, usize)> {
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
        return None;
    }
    let (i1, j1) = (
        (i1 as usize).min(maps.nx - 1),
        (j1 as usize).min(maps.ny - 1),
    );
    if i1 <= i0 || j1 <= j0 {
        return None;
    }
    Some((i0, j0, i1, j1))
}

/// A plan velocity fixed on some nodes: one constraint grid per component.
struct VelocityConstraints {
    x: Constraints,
    y: Constraints,
}

impl VelocityConstraints {
    fn new(nx: usize, ny: usize, cell: f64) -> Result<Self> {
        let x = Constraints::new(nx, ny, cell)?;
        let y = Constraints::new(nx, ny, cell)?;
        Ok(VelocityConstraints { x, y })
    }

    fn set(&mut self, i: usize, j: usize, v: DVec2) -> Result<()> {
        self.x.set(i, j, v.x)?;
        self.y.set(i, j, v.y)
    }

    fn is_set(&self, i: usize, j: usize) -> bool {
        self.x.get(i, j).is_some()
    }
}

/// The velocity field of one pool over its box: `(i0, j0, bx, by, velocities)`, `None` when the box is empty.
fn pool_speed_field(
    net: &WaterfallNetwork,
    footprint: &WaterfallFootprint,
    maps: &WaterMaps,
    pool: &PoolWater,
) -> Result<Option<PoolSpeeds>> {
    let Some((i0, j0, i1, j1)) = pool_box(pool, maps) else {
        return Ok(None);
    };
    let (bx, by) = (i1 - i0 + 1, j1 - j0 + 1);
    let mut fixed = VelocityConstraints::new(bx, by, maps.cell)?;
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
            fixed.set(f.x as usize - i0, f.y as usize - j0, v)?;
        }
    }
    // then every node of the box outside the pool: the water's speed there, or rest
    for j in 0..by {
        for i in 0..bx {
            let k = (j + j0) * maps.nx + i + i0;
            if in_pool(footprint, k, pool) {
                continue;
            }
            let v = if maps.water[k] > 0.5 {
                maps.speed[k]
            } else {
                DVec2::ZERO
            };
            if !fixed.is_set(i, j) {
                fixed.set(i, j, v)?;
            }
        }
    }
    let o = DiffusionOptions {
        falloff: None,
        tolerance: 1e-4,
        max_cycles: 50,
    };
    let (dx, dy) = (diffuse(&fixed.x, &o)?, diffuse(&fixed.y, &o)?);
    let v = dx
        .displacement
        .iter()
        .zip(&dy.displacement)
        .map(|(x, y)| DVec2::new(*x, *y))
        .collect();
    Ok(Some((i0, j0, bx, by, v)))
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

/// A rock on the riverbed, as the synthesis placed it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rock {
    /// On the (deformed) terrain.
    pub position: DVec3,
    /// About Z, radians.
    pub rotation: f64,
    /// Uniform scale of the rock's prototype model.
    pub scale: f64,
    /// Prototype index of the rock color's category.
    pub prototype: u32,
    /// Which of the rock color's distribution categories (index among the color's distribution categories, in its order).
    pub category: usize,
}

/// At most this many times the synthesis's usual proposals per rock (a bound on the work for a thin river
/// across a large rectangle).
const MAX_PROPOSAL_FACTOR: f64 = 100.0;

/// The terrain map that says how dense the river rocks are (thesis 4.4.3: "the rock map indicates the density of
/// rocks to generate").
pub const ROCK_MAP: &str = "rocks";

/// The built-in river-rock color as JSON (see the module documentation).
const RIVER_ROCK_COLOR: &str = include_str!("../../../../assets/waterfall/river_rocks.color.json");

/// The built-in river-rock color, read once per process.
pub fn river_rock_color() -> Result<&'static Color> {
    static COLOR: OnceLock<std::result::Result<Color, String>> = OnceLock::new();
    COLOR
        .get_or_init(|| Color::from_json(RIVER_ROCK_COLOR).map_err(|e| e.to_string()))
        .as_ref()
        .map_err(|e| Error::invalid("the built-in river-rock color", e.clone()))
}

/// The names of the color's distribution categories: what [`scatter_rocks`] synthesizes.
pub(super) fn rock_categories(color: &Color) -> Vec<String> {
    color
        .categories
        .iter()
        .filter(|c| c.category.kind == CategoryKind::Distribution)
        .map(|c| c.category.name.clone())
        .collect()
}

/// The color rocks are synthesized from: `color` with the built-in color's preference for the terrain map
/// "rocks" given to each of its distribution categories that follows no such map.
pub(super) fn following_the_rock_map(color: &Color) -> Result<Color> {
    let follows = |c: &Color, name: &str| {
        c.maps
            .iter()
            .any(|m| m.category == name && m.map == ROCK_MAP && m.source == MapSource::Terrain)
    };
    let names = rock_categories(color);
    if names.iter().all(|n| follows(color, n)) {
        return Ok(color.clone());
    }
    let builtin = river_rock_color()?;
    let preference = builtin
        .maps
        .iter()
        .find(|m| m.map == ROCK_MAP && m.source == MapSource::Terrain)
        .ok_or_else(|| Error::invalid("the built-in river-rock color", "follows no rock map"))?;
    let mut out = color.clone();
    for name in names {
        if !follows(color, &name) {
            out.maps.push(MapInteraction {
                category: name,
                ..preference.clone()
            });
        }
    }
    Ok(out)
}

/// Rocks along the riverbeds: the rock color (the user's, else the built-in river rocks) synthesized over the
/// bounding rectangle of the water's rock map, on `terrain` (the riverbed) carrying the rock map as its map
/// "rocks". Rocks the synthesis puts beyond the water's edge (the map is bilinear, so its support reaches into
/// the cells around the water) are left out. Seeded, and independent of the thread count.
pub(crate) fn scatter_rocks(
    maps: &WaterMaps,
    terrain: &Heightfield,
    options: &DecorationOptions,
    seed: u64,
) -> Result<Vec<Rock>> {
    options.validate()?;
    check::fits_terrain("water maps", (maps.nx, maps.ny), (terrain.nx, terrain.ny))?;
    let color = match &options.rock_color {
        Some(c) => following_the_rock_map(c)?,
        None => river_rock_color()?.clone(),
    };
    let on_rocks = |k: usize| maps.water[k] > 0.5 && maps.rocks[k] > 0.0;
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    let mut nodes = 0usize;
    for k in (0..maps.rocks.len()).filter(|k| on_rocks(*k)) {
        let p = maps.origin + DVec2::new((k % maps.nx) as f64, (k / maps.nx) as f64) * maps.cell;
        lo = lo.min(p);
        hi = hi.max(p);
        nodes += 1;
    }
    if nodes == 0 {
        return Ok(Vec::new());
    }
    // a cell around the nodes: the bilinear map is positive up to the next node
    let (tlo, thi) = terrain.bbox();
    let region = Region::Rect {
        min: (lo - DVec2::splat(maps.cell)).max(tlo),
        max: (hi + DVec2::splat(maps.cell)).min(thi),
    };
    let mut ground = terrain.clone();
    ground.add_map(ROCK_MAP, maps.rocks.clone())?;
    let scene = Scene {
        terrain: Some(Arc::new(ground)),
        ..Default::default()
    };
    // proposals land uniformly in the rectangle: more of them as the rocks' share of it is smaller
    let support = nodes as f64 * maps.cell * maps.cell;
    let sparse = (region.area() / support).clamp(1.0, MAX_PROPOSAL_FACTOR);
    let names = rock_categories(&color);
    let opts = SynthesisOptions {
        seed,
        influence_radius: Some(0.0),
        iterations_per_instance: DEFAULT_ITERATIONS_PER_INSTANCE * sparse,
        categories: Some(names.clone()),
        exemplar_on_terrain: false,
        product_model: true,
        ..Default::default()
    };
    let made = synthesize(&scene, &color, &region, &opts)?;
    let rocks = made
        .instances
        .iter()
        .filter(|i| maps.is_water(i.position) && maps.node(i.position).is_some_and(on_rocks))
        .filter_map(|i| {
            let z = terrain.height_at(i.position)?;
            let name = &made.categories.get(i.category)?.name;
            Some(Rock {
                position: i.position.extend(z),
                rotation: i.rotation,
                scale: i.scale,
                prototype: i.prototype,
                category: names.iter().position(|n| n == name)?,
            })
        })
        .collect();
    Ok(rocks)
}

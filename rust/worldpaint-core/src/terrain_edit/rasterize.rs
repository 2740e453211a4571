//! Writing constraints on the heightfield grid (thesis 4.4.2 "the terrain constraints d(x, y) are rasterized into
//! a 2D grid", 5.3.3 "δ = z − H(x, y)"): a 3D point or curve fixes the cells it passes through at the height
//! difference `z − H` there. Everywhere a cell already fixed keeps its value: the first constraint written wins.

use super::diffusion::Constraints;
use crate::error::{check, Error, Result};
use crate::geom::segment_distance;
use crate::terrain::Heightfield;
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::collections::BTreeMap;

fn check_grid(c: &Constraints, terrain: &Heightfield) -> Result<()> {
    if c.nx != terrain.nx || c.ny != terrain.ny || c.cell != terrain.cell {
        return Err(Error::invalid(
            format!("constraints on a {}x{} grid of {} m", c.nx, c.ny, c.cell),
            format!(
                "do not fit the {}x{} terrain of {} m cells",
                terrain.nx, terrain.ny, terrain.cell
            ),
        ));
    }
    Ok(())
}

fn check_points(points: &[DVec3], what: &str) -> Result<()> {
    if points.is_empty() {
        return Err(Error::invalid(format!("the {what}"), "has no point"));
    }
    if let Some(k) = points.iter().position(|p| !p.is_finite()) {
        return Err(Error::invalid(
            format!("the {what}"),
            format!("point {k} is not finite"),
        ));
    }
    Ok(())
}

/// The grid node nearest to `p`, if `p` is on the terrain.
fn nearest_node(terrain: &Heightfield, p: DVec2) -> Option<(usize, usize)> {
    if !terrain.contains(p) {
        return None;
    }
    let f = ((p - terrain.origin) / terrain.cell).round();
    let (i, j) = (f.x as usize, f.y as usize);
    (i < terrain.nx && j < terrain.ny).then_some((i, j))
}

/// Fixes the node nearest to `p` at `p.z − H(node)`; whether it was written (false off the terrain or when the
/// node was already fixed).
pub fn rasterize_point(c: &mut Constraints, terrain: &Heightfield, p: DVec3) -> Result<bool> {
    check_grid(c, terrain)?;
    check_points(&[p], "point constraint")?;
    match nearest_node(terrain, p.truncate()) {
        Some((i, j)) => c.set_if_free(i, j, p.z - terrain.heights[j * terrain.nx + i] as f64),
        None => Ok(false),
    }
}

/// Fixes every node the 3D polyline passes through: the curve is sampled at most half a cell apart (`z`
/// interpolated linearly), and each node takes `z − H(node)` from the sample nearest to it. Parts off the terrain
/// are skipped. Returns the number of nodes written.
pub fn rasterize_polyline(
    c: &mut Constraints,
    terrain: &Heightfield,
    points: &[DVec3],
) -> Result<usize> {
    polyline_with(c, terrain, points, |_, z| z)
}

/// [`rasterize_polyline`] with each node's height chosen by `height(node, z)` from the node's XY and the height `z` of
/// the curve's sample nearest to it: a curve whose nodes must keep a property of the curve rather than its height (a
/// sketched silhouette seen from a camera) sets them here.
pub(crate) fn polyline_with(
    c: &mut Constraints,
    terrain: &Heightfield,
    points: &[DVec3],
    height: impl Fn(DVec2, f64) -> f64,
) -> Result<usize> {
    polyline_nodes(c, terrain, points, height).map(|written| written.len())
}

/// [`polyline_with`], returning the nodes `(i, j)` it wrote.
pub(crate) fn polyline_nodes(
    c: &mut Constraints,
    terrain: &Heightfield,
    points: &[DVec3],
    height: impl Fn(DVec2, f64) -> f64,
) -> Result<Vec<(usize, usize)>> {
    check_grid(c, terrain)?;
    check_points(points, "curve")?;
    let mut best: BTreeMap<(usize, usize), (f64, f64)> = BTreeMap::new();
    let mut visit = |p: DVec3| {
        if let Some((i, j)) = nearest_node(terrain, p.truncate()) {
            let node = terrain.origin + DVec2::new(i as f64, j as f64) * terrain.cell;
            let d = node.distance(p.truncate());
            let e = best.entry((j, i)).or_insert((f64::INFINITY, 0.0));
            if d < e.0 {
                *e = (d, p.z);
            }
        }
    };
    visit(points[0]);
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let steps = ((a.truncate().distance(b.truncate()) / (0.5 * terrain.cell)).ceil() as usize)
            .clamp(1, 10_000_000);
        for s in 1..=steps {
            visit(a.lerp(b, s as f64 / steps as f64));
        }
    }
    let mut written = Vec::new();
    for ((j, i), (_, z)) in best {
        let node = terrain.origin + DVec2::new(i as f64, j as f64) * terrain.cell;
        if c.set_if_free(
            i,
            j,
            height(node, z) - terrain.heights[j * terrain.nx + i] as f64,
        )? {
            written.push((i, j));
        }
    }
    Ok(written)
}

/// A curve with gradient constraints: the curve itself (as [`rasterize_polyline`]), and beside it, one cell away on
/// each side, nodes fixed at the curve's height plus `left_slope` (resp. `right_slope`) times that distance — rise per
/// metre away from the curve, negative for falling ground (a ridge has both negative). Left is to the left when walking
/// along the curve. Returns the number of nodes written.
pub fn rasterize_gradient_polyline(
    c: &mut Constraints,
    terrain: &Heightfield,
    points: &[DVec3],
    left_slope: f64,
    right_slope: f64,
) -> Result<usize> {
    check::finite("the curve's left side slope", left_slope)?;
    check::finite("the curve's right side slope", right_slope)?;
    let mut written = rasterize_polyline(c, terrain, points)?;
    let offset = terrain.cell;
    for (side, slope) in [(1.0, left_slope), (-1.0, right_slope)] {
        for w in points.windows(2) {
            let dir = (w[1] - w[0]).truncate();
            let Some(t) = dir.try_normalize() else {
                continue;
            };
            let n = t.perp() * (side * offset);
            let shift = DVec3::new(n.x, n.y, slope * offset);
            written += rasterize_polyline(c, terrain, &[w[0] + shift, w[1] + shift])?;
        }
    }
    Ok(written)
}

/// A level corridor along a 3D polyline: every node within `half_width` of the curve (in plan) is fixed at the
/// height of the nearest point of the curve (so the ground is level across the corridor) minus `H(node)`. Returns
/// the number of nodes written.
pub fn rasterize_corridor(
    c: &mut Constraints,
    terrain: &Heightfield,
    points: &[DVec3],
    half_width: f64,
) -> Result<usize> {
    check_grid(c, terrain)?;
    let near = near_curve(terrain, points, half_width)?;
    let mut written = 0;
    for n in near {
        let (i, j) = (n.node % terrain.nx, n.node / terrain.nx);
        if c.set_if_free(i, j, n.z - terrain.heights[n.node] as f64)? {
            written += 1;
        }
    }
    Ok(written)
}

/// A node near a curve.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NearNode {
    /// Row-major node index.
    pub node: usize,
    /// Height of the curve at its point nearest to the node.
    pub z: f64,
}

/// The nodes within `radius` of a 3D polyline (in plan), row-major order, with the height of the nearest curve
/// point (the first segment wins a tie).
pub(crate) fn near_curve(
    terrain: &Heightfield,
    points: &[DVec3],
    radius: f64,
) -> Result<Vec<NearNode>> {
    check_points(points, "corridor")?;
    check::positive("corridor half-width", radius)?;
    let segments: Vec<(DVec3, DVec3)> = if points.len() == 1 {
        vec![(points[0], points[0])]
    } else {
        points.windows(2).map(|w| (w[0], w[1])).collect()
    };
    let (lo, hi) = points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p.truncate()), hi.max(p.truncate())),
    );
    let cell = terrain.cell;
    let to_cells = |v: f64, o: f64, n: usize| ((v - o) / cell).clamp(-1.0, n as f64);
    let j_lo = to_cells(lo.y - radius, terrain.origin.y, terrain.ny)
        .ceil()
        .max(0.0) as usize;
    let j_hi = to_cells(hi.y + radius, terrain.origin.y, terrain.ny).floor();
    if j_hi < 0.0 {
        return Ok(Vec::new());
    }
    let j_hi = (j_hi as usize).min(terrain.ny - 1);
    let nx = terrain.nx;
    let rows: Vec<Vec<NearNode>> = (j_lo..=j_hi)
        .into_par_iter()
        .map(|j| {
            let y = terrain.origin.y + j as f64 * cell;
            // per node of the row: (distance, curve height) of the nearest segment so far
            let mut best: BTreeMap<usize, (f64, f64)> = BTreeMap::new();
            for (a, b) in &segments {
                let (a2, b2) = (a.truncate(), b.truncate());
                if y < a2.y.min(b2.y) - radius || y > a2.y.max(b2.y) + radius {
                    continue;
                }
                let x0 = to_cells(a2.x.min(b2.x) - radius, terrain.origin.x, nx).ceil();
                let x1 = to_cells(a2.x.max(b2.x) + radius, terrain.origin.x, nx).floor();
                if x1 < 0.0 {
                    continue;
                }
                let (x0, x1) = (x0.max(0.0) as usize, (x1 as usize).min(nx - 1));
                let ab = b2 - a2;
                let len2 = ab.length_squared();
                for i in x0..=x1 {
                    let p = DVec2::new(terrain.origin.x + i as f64 * cell, y);
                    let d = segment_distance(p, a2, b2);
                    if d > radius {
                        continue;
                    }
                    let t = if len2 > 0.0 {
                        ((p - a2).dot(ab) / len2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let z = a.z + t * (b.z - a.z);
                    let e = best.entry(i).or_insert((f64::INFINITY, 0.0));
                    if d < e.0 {
                        *e = (d, z);
                    }
                }
            }
            best.into_iter()
                .map(|(i, (_, z))| NearNode {
                    node: j * nx + i,
                    z,
                })
                .collect()
        })
        .collect();
    Ok(rows.into_iter().flatten().collect())
}

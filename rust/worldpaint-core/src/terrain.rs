//! The terrain as a heightfield, and the *external* maps defined on it (Section 3, "Input data": "Maps, such as
//! of elevations or slopes, are assigned to the ground category and their type is called external, since they
//! define external constraints for scene objects"). The map-sampling histograms `h_m` of Section 4.1 read these
//! maps at instance positions by bilinear interpolation.
//!
//! A Blender terrain arrives as a triangle mesh: [`Heightfield::from_mesh`] uses the vertices directly when they
//! lie on a regular lattice (a subdivided grid), and otherwise rasterizes every triangle (planar interpolation
//! per scanline, rows split into bands processed in parallel; where triangles overlap the highest wins, which is
//! order-independent and so deterministic).

use crate::error::{check, Error, Result};
use crate::geom::{check_triangle_indices, Region};
use crate::limits;
use glam::DVec2;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Largest grid `from_mesh` builds on its own (nodes); larger explicit cells are refused beyond 4× this.
pub(crate) const MAX_AUTO_NODES: usize = 4_000_000;

/// A regular grid of terrain heights with named scalar maps ("elevation", "slope", ...) on the same nodes.
#[derive(Clone, Debug)]
pub struct Heightfield {
    /// World XY of sample (0, 0).
    pub origin: DVec2,
    /// Spacing of the samples along X and Y (m).
    pub cell: f64,
    /// Samples along X (at least 2).
    pub nx: usize,
    /// Samples along Y (at least 2).
    pub ny: usize,
    /// Heights (m), row-major, index = j * nx + i, sample (i, j) at origin + (i, j) * cell.
    pub heights: Vec<f32>,
    /// Named scalar maps on the same grid.
    pub maps: BTreeMap<String, Vec<f32>>,
}

impl Heightfield {
    /// A heightfield from its samples; fills the maps "elevation" (= height) and "slope" (radians, from central
    /// differences, one-sided at the border).
    pub fn new(origin: DVec2, cell: f64, nx: usize, ny: usize, heights: Vec<f32>) -> Result<Self> {
        check::positive("terrain cell size", cell)?;
        check::finite("terrain origin x", origin.x)?;
        check::finite("terrain origin y", origin.y)?;
        if nx < 2 || ny < 2 {
            return Err(Error::invalid(
                format!("terrain grid {nx}x{ny}"),
                "needs at least 2x2 samples",
            ));
        }
        limits::check(
            "the terrain grid",
            nx as f64 * ny as f64,
            limits::MAX_GRID_CELLS,
            "cells",
        )?;
        check::same_len("terrain heights", heights.len(), nx * ny)?;
        if let Some(k) = heights.iter().position(|h| !h.is_finite()) {
            return Err(Error::invalid(
                format!("terrain height {k}"),
                "is not finite",
            ));
        }
        let slope = slope_map(&heights, nx, ny, cell);
        let mut maps = BTreeMap::new();
        maps.insert("elevation".to_string(), heights.clone());
        maps.insert("slope".to_string(), slope);
        Ok(Heightfield {
            origin,
            cell,
            nx,
            ny,
            heights,
            maps,
        })
    }

    /// A heightfield from any triangle mesh (vertices world XYZ, triangles as vertex indices).
    ///
    /// Cell size when `cell` is `None`: the mean XY edge length of the triangles (so a triangle covers about one
    /// cell and no detail is lost or invented), enlarged when needed so the grid has at most
    /// 4 million nodes. A mesh whose vertices form a complete regular lattice (same spacing in X and Y)
    /// is used directly, without rasterizing, unless an explicit different `cell` is asked for.
    pub fn from_mesh(
        vertices: &[[f64; 3]],
        triangles: &[[u32; 3]],
        cell: Option<f64>,
    ) -> Result<Self> {
        if vertices.is_empty() {
            return Err(Error::invalid("the terrain mesh", "has no vertices"));
        }
        if triangles.is_empty() {
            return Err(Error::invalid("the terrain mesh", "has no triangles"));
        }
        if let Some(k) = vertices
            .iter()
            .position(|v| v.iter().any(|c| !c.is_finite()))
        {
            return Err(Error::invalid(
                format!("terrain mesh vertex {k}"),
                "is not finite",
            ));
        }
        check_triangle_indices("terrain mesh triangle", vertices.len(), triangles)?;
        if let Some(c) = cell {
            check::positive("terrain cell size", c)?;
        }
        let (lo, hi) = vertices.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), v| {
                let p = DVec2::new(v[0], v[1]);
                (lo.min(p), hi.max(p))
            },
        );
        let ext = hi - lo;
        if !(ext.x > 0.0 && ext.y > 0.0) {
            return Err(Error::invalid(
                "the terrain mesh",
                "has no extent in X or Y",
            ));
        }
        if let Some(hf) = lattice_heightfield(vertices, lo, cell)? {
            return Ok(hf);
        }
        let cell = match cell {
            Some(c) => c,
            None => {
                let mean_edge = mean_edge_length(vertices, triangles);
                let min_cell = (ext.x * ext.y / MAX_AUTO_NODES as f64).sqrt();
                if mean_edge.is_finite() && mean_edge > 0.0 {
                    mean_edge.max(min_cell)
                } else {
                    min_cell
                }
            }
        };
        let nx = (ext.x / cell).round() as usize + 1;
        let ny = (ext.y / cell).round() as usize + 1;
        limits::check(
            &format!("a terrain grid of {cell} m cells"),
            nx as f64 * ny as f64,
            4 * MAX_AUTO_NODES as u64,
            "cells",
        )?;
        let (mut nx, mut ny) = (nx.max(2), ny.max(2));
        // exact cell sizes so border nodes sit on the mesh's bounding box
        let (cx, cy) = (ext.x / (nx - 1) as f64, ext.y / (ny - 1) as f64);
        let mut cell = 0.5 * (cx + cy);
        if (cx - cy).abs() > 1e-3 * cell {
            // a grid's cells are square: where the mesh's sides do not divide into the same cells, the finer one
            // covers both and the last row or column reaches past the mesh (filled from its nearest covered node),
            // instead of a mean cell that would misplace the terrain's extent
            cell = cx.min(cy);
            nx = (ext.x / cell - 1e-9).ceil() as usize + 1;
            ny = (ext.y / cell - 1e-9).ceil() as usize + 1;
        }
        let heights = rasterize(vertices, triangles, lo, cell, cell, nx, ny);
        Heightfield::new(lo, cell, nx, ny, heights)
    }

    /// Upper corner of the grid.
    fn max_corner(&self) -> DVec2 {
        self.origin + DVec2::new((self.nx - 1) as f64, (self.ny - 1) as f64) * self.cell
    }

    /// The grid's extent, world XY (min, max): sample (0, 0) and sample (nx − 1, ny − 1).
    pub fn bbox(&self) -> (DVec2, DVec2) {
        (self.origin, self.max_corner())
    }

    /// The column and row ranges of the grid nodes lying in the box `[lo, hi]` (`None` when there are none).
    pub(crate) fn nodes_in(
        &self,
        lo: DVec2,
        hi: DVec2,
    ) -> Option<(
        std::ops::RangeInclusive<usize>,
        std::ops::RangeInclusive<usize>,
    )> {
        let first = ((lo - self.origin) / self.cell).ceil().max(DVec2::ZERO);
        let last = ((hi - self.origin) / self.cell).floor();
        if !(first.is_finite() && last.is_finite()) || last.x < 0.0 || last.y < 0.0 {
            return None;
        }
        let last = (
            (last.x as usize).min(self.nx - 1),
            (last.y as usize).min(self.ny - 1),
        );
        let first = (first.x as usize, first.y as usize);
        (first.0 <= last.0 && first.1 <= last.1).then_some((first.0..=last.0, first.1..=last.1))
    }

    /// The part of `region` on the terrain, where content can be painted: `region` itself when it lies on the
    /// terrain, `None` when no part does. Counting instances over the whole of a region that spills off the terrain
    /// would cram them onto the part that is on it.
    pub fn clip(&self, region: &Region) -> Option<Region> {
        let (tlo, thi) = self.bbox();
        let (lo, hi) = region.bbox();
        if lo.x >= tlo.x && lo.y >= tlo.y && hi.x <= thi.x && hi.y <= thi.y {
            return Some(region.clone());
        }
        let (lo, hi) = (lo.max(tlo), hi.min(thi));
        if !(hi.x > lo.x && hi.y > lo.y) {
            return None;
        }
        let on_terrain = Region::Rect { min: lo, max: hi };
        Some(match region {
            Region::Rect { .. } => on_terrain,
            _ => Region::Clipped {
                within: vec![region.clone(), on_terrain],
                without: Vec::new(),
            },
        })
    }

    /// Whether `p` lies within the grid's extent (its border included).
    pub fn contains(&self, p: DVec2) -> bool {
        let hi = self.max_corner();
        p.x >= self.origin.x && p.y >= self.origin.y && p.x <= hi.x && p.y <= hi.y
    }

    fn bilinear(&self, values: &[f32], p: DVec2) -> Option<f64> {
        if !self.contains(p) || values.len() != self.nx * self.ny {
            return None;
        }
        // f ≥ 0 inside the grid: truncation is the floor, without a call to it
        let f = (p - self.origin) / self.cell;
        let i = (f.x as usize).min(self.nx - 2);
        let j = (f.y as usize).min(self.ny - 2);
        let tx = (f.x - i as f64).clamp(0.0, 1.0);
        let ty = (f.y - j as f64).clamp(0.0, 1.0);
        let at = |i: usize, j: usize| values[j * self.nx + i] as f64;
        let a = at(i, j) * (1.0 - tx) + at(i + 1, j) * tx;
        let b = at(i, j + 1) * (1.0 - tx) + at(i + 1, j + 1) * tx;
        Some(a * (1.0 - ty) + b * ty)
    }

    /// Bilinear height; `None` outside the grid.
    pub fn height_at(&self, p: DVec2) -> Option<f64> {
        self.bilinear(&self.heights, p)
    }

    /// Bilinear value of a named map; `None` outside the grid or for an unknown map.
    pub fn map_at(&self, name: &str, p: DVec2) -> Option<f64> {
        self.maps.get(name).and_then(|m| self.bilinear(m, p))
    }

    /// Adds (or replaces) a named map on the grid's nodes.
    pub fn add_map(&mut self, name: &str, values: Vec<f32>) -> Result<()> {
        check::same_len(&format!("map '{name}'"), values.len(), self.nx * self.ny)?;
        if values.iter().any(|v| !v.is_finite()) {
            return Err(Error::invalid(
                format!("map '{name}'"),
                "has non-finite values",
            ));
        }
        self.maps.insert(name.to_string(), values);
        Ok(())
    }
}

/// Slope angle (radians) at every node from central differences (one-sided at the border).
fn slope_map(h: &[f32], nx: usize, ny: usize, cell: f64) -> Vec<f32> {
    let mut out = vec![0.0f32; nx * ny];
    out.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
        for (i, s) in row.iter_mut().enumerate() {
            let (i0, i1) = (i.saturating_sub(1), (i + 1).min(nx - 1));
            let (j0, j1) = (j.saturating_sub(1), (j + 1).min(ny - 1));
            let gx = (h[j * nx + i1] as f64 - h[j * nx + i0] as f64) / ((i1 - i0) as f64 * cell);
            let gy = (h[j1 * nx + i] as f64 - h[j0 * nx + i] as f64) / ((j1 - j0) as f64 * cell);
            *s = (gx * gx + gy * gy).sqrt().atan() as f32;
        }
    });
    out
}

/// Mean XY edge length over (at most 100k evenly picked) triangles.
fn mean_edge_length(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> f64 {
    let step = (triangles.len() / 100_000).max(1);
    let (mut sum, mut n) = (0.0, 0usize);
    for t in triangles.iter().step_by(step) {
        for k in 0..3 {
            let a = vertices[t[k] as usize];
            let b = vertices[t[(k + 1) % 3] as usize];
            sum += ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
            n += 1;
        }
    }
    sum / n.max(1) as f64
}

/// Sorted distinct values of `xs` (values closer than `tol` merged).
fn distinct(mut xs: Vec<f64>, tol: f64) -> Vec<f64> {
    xs.sort_by(f64::total_cmp);
    let mut out: Vec<f64> = Vec::new();
    for x in xs {
        match out.last() {
            Some(&l) if x - l <= tol => {}
            _ => out.push(x),
        }
    }
    out
}

/// The heightfield of a mesh whose vertices are exactly the nodes of a regular square lattice, if it is one.
fn lattice_heightfield(
    vertices: &[[f64; 3]],
    lo: DVec2,
    cell: Option<f64>,
) -> Result<Option<Heightfield>> {
    let n = vertices.len();
    if n < 4 {
        return Ok(None);
    }
    let scale = vertices
        .iter()
        .fold(0.0f64, |m, v| m.max(v[0].abs()).max(v[1].abs()))
        .max(1.0);
    let tol = 1e-9 * scale;
    // cheap necessary check first: distinct x times distinct y equals the vertex count
    let xs = distinct(vertices.iter().map(|v| v[0]).collect(), tol);
    let ys = distinct(vertices.iter().map(|v| v[1]).collect(), tol);
    let (nx, ny) = (xs.len(), ys.len());
    if nx < 2 || ny < 2 || nx.saturating_mul(ny) != n {
        return Ok(None);
    }
    let dx = (xs[nx - 1] - xs[0]) / (nx - 1) as f64;
    let dy = (ys[ny - 1] - ys[0]) / (ny - 1) as f64;
    let rel = 1e-6;
    if (dx - dy).abs() > rel * dx.max(dy) {
        return Ok(None);
    }
    if xs
        .windows(2)
        .any(|w| ((w[1] - w[0]) - dx).abs() > rel * dx * 10.0)
        || ys
            .windows(2)
            .any(|w| ((w[1] - w[0]) - dy).abs() > rel * dy * 10.0)
    {
        return Ok(None);
    }
    let spacing = 0.5 * (dx + dy);
    if let Some(c) = cell {
        if (c - spacing).abs() > 1e-6 * spacing {
            return Ok(None);
        }
    }
    let mut heights = vec![f32::NAN; n];
    for v in vertices {
        let i = ((v[0] - lo.x) / dx).round();
        let j = ((v[1] - lo.y) / dy).round();
        if i < 0.0 || j < 0.0 || i >= nx as f64 || j >= ny as f64 {
            return Ok(None);
        }
        let k = j as usize * nx + i as usize;
        if !heights[k].is_nan() {
            return Ok(None); // two vertices on one node: not a plain lattice
        }
        heights[k] = v[2] as f32;
    }
    Heightfield::new(lo, spacing, nx, ny, heights).map(Some)
}

/// Rasterizes triangles onto an nx×ny grid of nodes (spacing cx, cy from `lo`); nodes no triangle covers are
/// filled from the nearest covered node along their row, then along their column.
pub(crate) fn rasterize(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    lo: DVec2,
    cx: f64,
    cy: f64,
    nx: usize,
    ny: usize,
) -> Vec<f32> {
    const BAND: usize = 32;
    let n_bands = ny.div_ceil(BAND);
    // bucket triangles by the bands their Y range overlaps
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); n_bands];
    for (t, tri) in triangles.iter().enumerate() {
        let ys = tri.map(|i| vertices[i as usize][1]);
        let y0 = ys[0].min(ys[1]).min(ys[2]);
        let y1 = ys[0].max(ys[1]).max(ys[2]);
        let j0 = (((y0 - lo.y) / cy).ceil() - 1e-9).max(0.0) as usize;
        let j1 = (((y1 - lo.y) / cy).floor() + 1e-9).max(0.0) as usize;
        let j1 = j1.min(ny - 1);
        if j0 > j1 {
            continue;
        }
        for bucket in &mut buckets[(j0 / BAND)..=(j1 / BAND)] {
            bucket.push(t as u32);
        }
    }
    let mut heights = vec![f32::NEG_INFINITY; nx * ny];
    heights
        .par_chunks_mut(nx * BAND)
        .zip(buckets.par_iter())
        .enumerate()
        .for_each(|(b, (band, tris))| {
            let j_start = b * BAND;
            let rows = band.len() / nx;
            for &t in tris {
                let tri = triangles[t as usize];
                let p = tri.map(|i| vertices[i as usize]);
                // plane z = a x + b y + c through the three vertices
                let (x0, y0, z0) = (p[0][0], p[0][1], p[0][2]);
                let (ux, uy, uz) = (p[1][0] - x0, p[1][1] - y0, p[1][2] - z0);
                let (vx, vy, vz) = (p[2][0] - x0, p[2][1] - y0, p[2][2] - z0);
                let det = ux * vy - uy * vx;
                if det.abs() <= 1e-300 {
                    continue; // vertical or degenerate in XY
                }
                let a = (uz * vy - uy * vz) / det;
                let bb = (ux * vz - uz * vx) / det;
                let ymin = p[0][1].min(p[1][1]).min(p[2][1]);
                let ymax = p[0][1].max(p[1][1]).max(p[2][1]);
                let jlo = (((ymin - lo.y) / cy - 1e-9).ceil().max(0.0) as usize).max(j_start);
                let jhi =
                    (((ymax - lo.y) / cy + 1e-9).floor().max(0.0) as usize).min(j_start + rows - 1);
                let mut j = jlo;
                while j <= jhi {
                    let y = lo.y + j as f64 * cy;
                    // x-span of the triangle on this row
                    let (mut xl, mut xr) = (f64::INFINITY, f64::NEG_INFINITY);
                    for k in 0..3 {
                        let (a0, a1) = (p[k], p[(k + 1) % 3]);
                        let (ya, yb) = (a0[1], a1[1]);
                        let eps = 1e-9 * cy;
                        if (y < ya.min(yb) - eps) || (y > ya.max(yb) + eps) {
                            continue;
                        }
                        if (yb - ya).abs() <= 1e-300 {
                            xl = xl.min(a0[0]).min(a1[0]);
                            xr = xr.max(a0[0]).max(a1[0]);
                        } else {
                            let t = ((y - ya) / (yb - ya)).clamp(0.0, 1.0);
                            let x = a0[0] + t * (a1[0] - a0[0]);
                            xl = xl.min(x);
                            xr = xr.max(x);
                        }
                    }
                    if xl <= xr {
                        let ilo = ((xl - lo.x) / cx - 1e-9).ceil().max(0.0) as usize;
                        let ihi = (((xr - lo.x) / cx + 1e-9).floor() as i64).min(nx as i64 - 1);
                        let row = &mut band[(j - j_start) * nx..(j - j_start + 1) * nx];
                        let mut i = ilo as i64;
                        while i <= ihi {
                            let x = lo.x + i as f64 * cx;
                            let z = (z0 + a * (x - x0) + bb * (y - y0)) as f32;
                            let cell = &mut row[i as usize];
                            if z > *cell {
                                *cell = z;
                            }
                            i += 1;
                        }
                    }
                    j += 1;
                }
            }
        });
    fill_holes(&mut heights, nx, ny);
    heights
}

/// Fills uncovered nodes (−∞) from the nearest covered node in their row, then in their column; 0 if none.
fn fill_holes(h: &mut [f32], nx: usize, ny: usize) {
    if !h.contains(&f32::NEG_INFINITY) {
        return;
    }
    let fill_line = |get: &dyn Fn(usize) -> f32, len: usize| -> Option<Vec<f32>> {
        let covered: Vec<usize> = (0..len).filter(|&k| get(k) > f32::NEG_INFINITY).collect();
        if covered.is_empty() {
            return None;
        }
        let mut out = Vec::with_capacity(len);
        let mut c = 0usize;
        for k in 0..len {
            while c + 1 < covered.len() && covered[c + 1] <= k {
                c += 1;
            }
            let left = covered[c];
            let best = if c + 1 < covered.len() && covered[c + 1].abs_diff(k) < left.abs_diff(k) {
                covered[c + 1]
            } else {
                left
            };
            out.push(get(best));
        }
        Some(out)
    };
    for j in 0..ny {
        let row: Vec<f32> = h[j * nx..(j + 1) * nx].to_vec();
        if let Some(filled) = fill_line(&|i| row[i], nx) {
            h[j * nx..(j + 1) * nx].copy_from_slice(&filled);
        }
    }
    for i in 0..nx {
        let col: Vec<f32> = (0..ny).map(|j| h[j * nx + i]).collect();
        match fill_line(&|j| col[j], ny) {
            Some(filled) => {
                for j in 0..ny {
                    h[j * nx + i] = filled[j];
                }
            }
            None => {
                for j in 0..ny {
                    h[j * nx + i] = 0.0;
                }
            }
        }
    }
}

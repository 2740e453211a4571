//! The land a village grows on (thesis ch. 3, "Definitions"): the region of interest `Ω` as a regular grid over
//! the terrain, with the elevation `h(p)`, the water `w(p)` and the fortification walls sampled on its nodes. Roads
//! are searched, interests evaluated and parcels conquered on this grid (or on a finer one made with
//! [`LandGrid::refined`]).

use crate::error::{Error, Result};
use crate::geom::{segment_distance, Region};
use crate::terrain::Heightfield;
use glam::DVec2;
use rayon::prelude::*;

/// Largest number of nodes a village grid may have.
pub const MAX_LAND_NODES: usize = 16_000_000;

/// A regular grid of square cells; node (i, j) is at `origin + (i, j) * cell`, index `j * nx + i`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LandGrid {
    pub origin: DVec2,
    pub cell: f64,
    pub nx: usize,
    pub ny: usize,
}

impl LandGrid {
    /// The grid of nodes `cell` apart covering the box `min..max` (at least 2×2 nodes).
    pub fn covering(min: DVec2, max: DVec2, cell: f64) -> Result<LandGrid> {
        if !(cell.is_finite() && cell > 0.0) {
            return Err(Error::InvalidInput(format!(
                "village grid cell {cell} must be positive"
            )));
        }
        let size = max - min;
        if !(size.x.is_finite() && size.y.is_finite() && size.x > 0.0 && size.y > 0.0) {
            return Err(Error::BadRegion("the village region has no area".into()));
        }
        let nx = (size.x / cell).ceil() as usize + 1;
        let ny = (size.y / cell).ceil() as usize + 1;
        if nx.saturating_mul(ny) > MAX_LAND_NODES {
            return Err(Error::InvalidInput(format!(
                "a village grid of {nx}x{ny} nodes is too large; use a coarser cell than {cell} m"
            )));
        }
        Ok(LandGrid {
            origin: min,
            cell,
            nx: nx.max(2),
            ny: ny.max(2),
        })
    }

    /// The same box with cells `factor` times smaller.
    pub fn refined(&self, factor: usize) -> LandGrid {
        let f = factor.max(1);
        LandGrid {
            origin: self.origin,
            cell: self.cell / f as f64,
            nx: (self.nx - 1) * f + 1,
            ny: (self.ny - 1) * f + 1,
        }
    }

    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.nx + i
    }

    /// (i, j) of a node index.
    pub fn ij(&self, k: usize) -> (usize, usize) {
        (k % self.nx, k / self.nx)
    }

    /// World XY of node (i, j).
    pub fn point(&self, i: usize, j: usize) -> DVec2 {
        self.origin + DVec2::new(i as f64, j as f64) * self.cell
    }

    /// World XY of a node index.
    pub fn point_of(&self, k: usize) -> DVec2 {
        let (i, j) = self.ij(k);
        self.point(i, j)
    }

    /// The node nearest to `p`, if `p` lies within half a cell of the grid.
    pub fn nearest(&self, p: DVec2) -> Option<(usize, usize)> {
        let f = (p - self.origin) / self.cell;
        let (i, j) = (f.x.round(), f.y.round());
        if !(i >= 0.0 && j >= 0.0 && i < self.nx as f64 && j < self.ny as f64) {
            return None;
        }
        Some((i as usize, j as usize))
    }

    /// The node index nearest to `p`, clamped onto the grid.
    pub fn nearest_clamped(&self, p: DVec2) -> usize {
        let f = (p - self.origin) / self.cell;
        let i = f.x.round().clamp(0.0, (self.nx - 1) as f64) as usize;
        let j = f.y.round().clamp(0.0, (self.ny - 1) as f64) as usize;
        self.index(i, j)
    }

    /// Bilinear interpolation of node values at `p` (clamped onto the grid).
    pub fn bilinear(&self, values: &[f32], p: DVec2) -> f64 {
        let f = (p - self.origin) / self.cell;
        let fx = f.x.clamp(0.0, (self.nx - 1) as f64);
        let fy = f.y.clamp(0.0, (self.ny - 1) as f64);
        let i = (fx.floor() as usize).min(self.nx - 2);
        let j = (fy.floor() as usize).min(self.ny - 2);
        let (tx, ty) = (fx - i as f64, fy - j as f64);
        let at = |i: usize, j: usize| values[self.index(i, j)] as f64;
        let a = at(i, j) * (1.0 - tx) + at(i + 1, j) * tx;
        let b = at(i, j + 1) * (1.0 - tx) + at(i + 1, j + 1) * tx;
        a * (1.0 - ty) + b * ty
    }
}

/// What the village needs to know about the land, per node of its grid.
#[derive(Clone, Debug)]
pub struct Land {
    pub grid: LandGrid,
    /// Terrain elevation `h(p)`.
    pub height: Vec<f32>,
    /// Inside the region of interest `Ω`.
    pub inside: Vec<bool>,
    /// Under water (below the water level, or inside a lake or river).
    pub water: Vec<bool>,
    /// On a fortification wall (within half a cell of its line).
    pub wall: Vec<bool>,
    /// Inside a fortified enclosure.
    pub fortified: Vec<bool>,
}

/// The environment of a village, as the user gives it.
#[derive(Clone, Debug, Default)]
pub struct Environment {
    /// Water surface height: land below it is water.
    pub water_level: Option<f64>,
    /// Lakes and sea as closed contours.
    pub water_areas: Vec<Vec<DVec2>>,
    /// Rivers as open polylines, with their half-width (m).
    pub rivers: Vec<(Vec<DVec2>, f64)>,
    /// Fortification walls as closed contours.
    pub walls: Vec<Vec<DVec2>>,
}

impl Land {
    /// Samples the terrain and the environment on a grid of `cell` metres over the region's box.
    pub fn new(
        terrain: &Heightfield,
        region: &Region,
        environment: &Environment,
        cell: f64,
    ) -> Result<Land> {
        region.validate()?;
        let (rmin, rmax) = region.bbox();
        let (tmin, tmax) = terrain.bbox();
        let min = rmin.max(tmin);
        let max = rmax.min(tmax);
        if !(max.x > min.x && max.y > min.y) {
            return Err(Error::RegionOffTerrain(
                "the village region does not overlap the terrain".into(),
            ));
        }
        let grid = LandGrid::covering(min, max, cell)?;
        let water_polygons: Vec<Region> = environment
            .water_areas
            .iter()
            .filter(|c| c.len() >= 3)
            .map(|c| Region::Polygon { points: c.clone() })
            .collect();
        let wall_polygons: Vec<Region> = environment
            .walls
            .iter()
            .filter(|c| c.len() >= 3)
            .map(|c| Region::Polygon { points: c.clone() })
            .collect();
        let nodes: Vec<(f32, bool, bool, bool, bool)> = (0..grid.len())
            .into_par_iter()
            .map(|k| {
                let p = grid.point_of(k).min(tmax).max(tmin);
                let h = terrain.height_at(p).unwrap_or(0.0);
                let inside = region.contains(grid.point_of(k));
                let below = environment.water_level.is_some_and(|level| h < level);
                let in_lake = water_polygons.iter().any(|w| w.contains(p));
                let in_river = environment.rivers.iter().any(|(line, half_width)| {
                    line.windows(2)
                        .any(|s| segment_distance(p, s[0], s[1]) <= *half_width)
                });
                let on_wall = environment.walls.iter().any(|c| {
                    (0..c.len())
                        .any(|i| segment_distance(p, c[i], c[(i + 1) % c.len()]) <= 0.5 * cell)
                });
                let fortified = wall_polygons.iter().any(|w| w.contains(p));
                (
                    h as f32,
                    inside,
                    below || in_lake || in_river,
                    on_wall,
                    fortified,
                )
            })
            .collect();
        Ok(Land {
            grid,
            height: nodes.iter().map(|n| n.0).collect(),
            inside: nodes.iter().map(|n| n.1).collect(),
            water: nodes.iter().map(|n| n.2).collect(),
            wall: nodes.iter().map(|n| n.3).collect(),
            fortified: nodes.iter().map(|n| n.4).collect(),
        })
    }

    /// Terrain height at any point (bilinear on the grid).
    pub fn height_at(&self, p: DVec2) -> f64 {
        self.grid.bilinear(&self.height, p)
    }

    /// Slope (rise over run) at node `k`, from central differences.
    pub fn grade_at_node(&self, k: usize) -> f64 {
        self.gradient_at_node(k).length()
    }

    /// Height gradient at node `k`, from central differences (one-sided at the border).
    pub fn gradient_at_node(&self, k: usize) -> DVec2 {
        let g = &self.grid;
        let (i, j) = g.ij(k);
        let (i0, i1) = (i.saturating_sub(1), (i + 1).min(g.nx - 1));
        let (j0, j1) = (j.saturating_sub(1), (j + 1).min(g.ny - 1));
        let h = |i: usize, j: usize| self.height[g.index(i, j)] as f64;
        DVec2::new(
            (h(i1, j) - h(i0, j)) / ((i1 - i0).max(1) as f64 * g.cell),
            (h(i, j1) - h(i, j0)) / ((j1 - j0).max(1) as f64 * g.cell),
        )
    }

    /// Whether a building may stand at node `k` at all: inside `Ω`, on dry land, off the walls.
    pub fn buildable(&self, k: usize) -> bool {
        self.inside[k] && !self.water[k] && !self.wall[k]
    }
}

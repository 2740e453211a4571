//! The land a village grows on (thesis ch. 3, "Definitions"): the region of interest `Ω` as a regular grid over
//! the terrain, with the elevation `h(p)`, the water `w(p)` and the fortification walls sampled on its nodes. Roads
//! are searched and interests evaluated on this grid; parcels are conquered on a finer grid over the same box.

use crate::error::{check, Error, Result};
use crate::geom::{segment_distance, PreparedRegion, Region, RegionQueries};
use crate::grid::Grid;
use crate::terrain::Heightfield;
use glam::DVec2;
use rayon::prelude::*;

/// What the village needs to know about the land, per node of its grid: every map has one value per node.
#[derive(Clone, Debug)]
pub struct Land {
    /// The nodes, `cell` metres apart over the part of the region's box the terrain covers.
    grid: Grid,
    /// Terrain elevation `h(p)`.
    height: Vec<f32>,
    /// Inside the region of interest `Ω`.
    inside: Vec<bool>,
    /// Under water (below the water level, or inside a lake or river).
    water: Vec<bool>,
    /// On a fortification wall (within half a cell of its line).
    wall: Vec<bool>,
    /// Inside a fortified enclosure.
    fortified: Vec<bool>,
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

/// Where a village stands: the terrain, the region of interest `Ω` on it and its environment, read every `cell`
/// metres. Generating a village and reading its interests both start from one.
#[derive(Clone, Debug)]
pub struct Site<'a> {
    /// The terrain.
    pub terrain: &'a Heightfield,
    /// The region of interest `Ω`.
    pub region: Region,
    /// Water and fortification walls.
    pub environment: Environment,
    /// Grid cell (m) of the land: the skeleton's interests and roads are read on it.
    pub cell: f64,
}

impl Site<'_> {
    /// The land of this site, on a grid of its cell.
    pub fn land(&self) -> Result<Land> {
        check::positive("village grid cell", self.cell)?;
        Land::new(self.terrain, &self.region, &self.environment, self.cell)
    }
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
            return Err(Error::RegionOffTerrain {
                reason: "the village region does not overlap the terrain".to_string(),
            });
        }
        let grid = Grid::nodes_covering(min, max, cell)?;
        // contours of fewer than three points enclose nothing
        let polygons = |contours: &[Vec<DVec2>]| -> Vec<Region> {
            contours
                .iter()
                .filter(|c| c.len() >= 3)
                .map(|c| Region::Polygon { points: c.clone() })
                .collect()
        };
        let (water_polygons, wall_polygons) = (
            polygons(&environment.water_areas),
            polygons(&environment.walls),
        );
        // every node asks them: prepared once, a real place's lakes and rivers cost a box test at most nodes
        let (region, water_polygons, wall_polygons): (_, Vec<_>, Vec<_>) = (
            PreparedRegion::new(region),
            water_polygons.iter().map(PreparedRegion::new).collect(),
            wall_polygons.iter().map(PreparedRegion::new).collect(),
        );
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
        Land::from_maps(
            grid,
            nodes.iter().map(|n| n.0).collect(),
            [
                nodes.iter().map(|n| n.1).collect(),
                nodes.iter().map(|n| n.2).collect(),
                nodes.iter().map(|n| n.3).collect(),
                nodes.iter().map(|n| n.4).collect(),
            ],
        )
    }

    /// A land from maps of one value per node of `grid`, in its node order: the elevation, and the masks inside
    /// `Ω`, under water, on a wall and inside a fortified enclosure, in that order. The grid must have at least 2×2
    /// nodes and a positive cell.
    pub fn from_maps(grid: Grid, height: Vec<f32>, masks: [Vec<bool>; 4]) -> Result<Land> {
        let [inside, water, wall, fortified] = masks;
        if grid.nx < 2 || grid.ny < 2 {
            return Err(Error::invalid(
                format!("the land grid of {}x{} nodes", grid.nx, grid.ny),
                "needs at least 2x2 nodes",
            ));
        }
        check::positive("the land grid's cell", grid.cell)?;
        let n = grid.len();
        for (name, len) in [
            ("height", height.len()),
            ("inside", inside.len()),
            ("water", water.len()),
            ("wall", wall.len()),
            ("fortified", fortified.len()),
        ] {
            check::same_len(&format!("the land's {name} map"), len, n)?;
        }
        Ok(Land {
            grid,
            height,
            inside,
            water,
            wall,
            fortified,
        })
    }

    /// The grid whose nodes the maps sample.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// Terrain elevation `h(p)` at each node.
    pub fn height(&self) -> &[f32] {
        &self.height
    }

    /// Whether each node lies inside the region of interest `Ω`.
    pub fn inside(&self) -> &[bool] {
        &self.inside
    }

    /// Whether each node is under water (below the water level, or inside a lake or river).
    pub fn water(&self) -> &[bool] {
        &self.water
    }

    /// Whether each node is on a fortification wall (within half a cell of its line).
    pub fn wall(&self) -> &[bool] {
        &self.wall
    }

    /// Whether each node lies inside a fortified enclosure.
    pub fn fortified(&self) -> &[bool] {
        &self.fortified
    }

    /// [`Land::height`] to edit in place (the maps keep one value per node).
    pub fn height_mut(&mut self) -> &mut [f32] {
        &mut self.height
    }

    /// [`Land::inside`] to edit in place.
    pub fn inside_mut(&mut self) -> &mut [bool] {
        &mut self.inside
    }

    /// [`Land::water`] to edit in place.
    pub fn water_mut(&mut self) -> &mut [bool] {
        &mut self.water
    }

    /// [`Land::wall`] to edit in place.
    pub fn wall_mut(&mut self) -> &mut [bool] {
        &mut self.wall
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
    pub(crate) fn gradient_at_node(&self, k: usize) -> DVec2 {
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
